"""Planar geometry by rendering: Voronoi diagrams as lower envelopes of cones.

pixgeo draws one cone per site with a depth test on a Vulkan device (Mesa's
lavapipe where there is no GPU), so every pixel gets its nearest site and the
distance to it. Arrays go in and come out in NumPy's conventions: points are
``(n, 2)`` float arrays, rasters ``(H, W)`` arrays; with a ``bbox`` they are
north-up (row 0 the largest y), as the command line writes them and GIS tools
read them, and their :class:`Frame` gives the affine ``transform``.

A device is made on first use and reused; calls from several threads are safe
(one at a time per device). Bad input raises ``ValueError`` with pixgeo's own
message; a file that cannot be read or written an ``OSError`` (such as
``FileNotFoundError``); no Vulkan driver or device ``NoDeviceError``, a failing
device ``DeviceError`` and a bug of pixgeo's ``InternalError``, all three
``RuntimeError`` subclasses.
"""

from __future__ import annotations

import functools
import operator
import sys
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import numpy as np

from . import _pixgeo

__version__ = _pixgeo.__version__

NoDeviceError = _pixgeo.NoDeviceError
DeviceError = _pixgeo.DeviceError
InternalError = _pixgeo.InternalError

NO_SITE = 2**32 - 1
"""The label of a pixel with no site (``labels`` are uint32)."""

__all__ = [
    "NO_SITE",
    "Lloyd",
    "lloyd",
    "natural_neighbor",
    "PowerDiagram",
    "power_diagram",
    "power_cells",
    "regular_triangulation",
    "EARTH_RADIUS",
    "NoDeviceError",
    "DeviceError",
    "InternalError",
    "Frame",
    "Diagram",
    "frame",
    "Triangulation",
    "Cells",
    "voronoi_cells",
    "Circle",
    "voronoi",
    "k_nearest",
    "furthest",
    "delaunay",
    "hausdorff",
    "diameter",
    "enclosing_circle",
    "largest_empty_circle",
    "AlphaHull",
    "Settle",
    "alpha_hull",
    "settle",
    "smallest_triangle",
    "largest_triangle",
    "smallest_quadrangle",
    "largest_quadrangle",
    "distance_transform_edt",
    "medial_axis",
]


@dataclass(frozen=True)
class Frame:
    """The picture and the world rectangle it shows.

    ``origin`` is the world point at the outer corner of pixel ``(0, 0)``
    (column 0, row 0). With ``y_axis == "up"`` (north-up, as maps and GIS
    tools hold rasters: the default with a ``bbox``) row 0 holds the largest
    y and pixel ``(i, j)`` is centred at ``origin + (i + 0.5, -(j + 0.5)) /
    scale``; with ``"down"`` row 0 holds the smallest y and the centre is at
    ``origin + (i + 0.5, j + 0.5) / scale``. ``crs`` is the coordinate
    system the caller named (``"EPSG:N"``), carried for the rasters' users.
    """

    width: int
    height: int
    origin: Tuple[float, float]
    scale: float
    y_axis: str = "down"
    crs: Optional[str] = None

    @property
    def res(self) -> float:
        """A pixel's side in world units."""
        return 1.0 / self.scale

    def _step(self) -> float:
        return -self.res if self.y_axis == "up" else self.res

    @property
    def transform(self) -> Tuple[float, float, float, float, float, float]:
        """The affine from (column, row) to world (x, y) of pixel corners, in
        rasterio's order ``(a, b, c, d, e, f)``: ``affine.Affine(*frame.transform)``
        or ``rasterio.open(..., transform=Affine(*frame.transform))``."""
        return (self.res, 0.0, self.origin[0], 0.0, self._step(), self.origin[1])

    @property
    def geotransform(self) -> Tuple[float, float, float, float, float, float]:
        """The same affine in GDAL's order ``(c, a, b, f, d, e)``, as
        ``SetGeoTransform`` takes it."""
        a, b, c, d, e, f = self.transform
        return (c, a, b, f, d, e)

    @property
    def bbox(self) -> Tuple[float, float, float, float]:
        """The world rectangle ``(xmin, ymin, xmax, ymax)`` the pixels cover."""
        x1 = self.origin[0] + self.width * self.res
        y1 = self.origin[1] + self.height * self._step()
        return (self.origin[0], min(self.origin[1], y1), x1, max(self.origin[1], y1))

    def pixel_centres(self) -> Tuple[np.ndarray, np.ndarray]:
        """World x (W,) of the columns' centres and y (H,) of the rows'."""
        x = self.origin[0] + (np.arange(self.width) + 0.5) * self.res
        y = self.origin[1] + (np.arange(self.height) + 0.5) * self._step()
        return x, y

    def to_xarray(self, **rasters):
        """Rasters of this frame's shape (``name=array``) as an
        ``xarray.Dataset`` placed as :meth:`Diagram.to_xarray` places its
        own: for :func:`natural_neighbor`'s values, say
        (``pixgeo.frame(shape, bbox=..., crs=...).to_xarray(heights=z)``).
        Float rasters take NaN as nodata."""
        for name, array in rasters.items():
            if np.shape(array)[:2] != (self.height, self.width):
                raise ValueError(f"{name} has shape {np.shape(array)}, not the frame's "
                                 f"({self.height}, {self.width})")
        return _georeferenced(self, {
            name: (a, np.nan if np.asarray(a).dtype.kind == "f" else None)
            for name, a in rasters.items()
        })


def _georeferenced(frame: Frame, arrays: dict):
    """``arrays`` (name: (array, nodata)) as an ``xarray.Dataset`` on the
    pixel centres' x and y, with the CF grid mapping rioxarray reads: its CRS
    and GeoTransform."""
    try:
        import xarray
    except ImportError:
        raise ImportError(
            "to_xarray needs xarray (and rioxarray to read the CRS back): "
            "pip install 'pixgeo[xarray]'"
        ) from None
    x, y = frame.pixel_centres()
    mapping = {"GeoTransform": " ".join(repr(float(v)) for v in frame.geotransform)}
    if frame.crs is not None:
        try:
            import pyproj

            wkt = pyproj.CRS.from_user_input(frame.crs).to_wkt()
        except ImportError:
            wkt = frame.crs
        mapping.update(crs_wkt=wkt, spatial_ref=wkt)
    coords = {"x": x, "y": y, "spatial_ref": xarray.Variable((), 0, mapping)}
    data = {}
    for name, (array, nodata) in arrays.items():
        dims = ("y", "x", "k")[: array.ndim]
        attrs = {"grid_mapping": "spatial_ref"}
        if nodata is not None:
            attrs["_FillValue"] = nodata
        data[name] = xarray.DataArray(array, dims=dims, coords=coords, attrs=attrs)
    return xarray.Dataset(data)


@dataclass(frozen=True)
class Diagram:
    """A label raster, the distances to the labelled sites, and their frame.

    ``labels`` is uint32 ``(H, W)`` (``(H, W, k)`` for :func:`k_nearest`), with
    :data:`NO_SITE` where no site is; ``distances`` is float32 in world units.
    ``to_xarray()`` gives both georeferenced.
    """

    labels: np.ndarray
    distances: np.ndarray
    frame: Frame

    def to_xarray(self):
        """``labels`` and ``distances`` as an ``xarray.Dataset`` on the pixel
        centres' ``x`` and ``y``, with the frame's CRS and affine in a CF
        ``spatial_ref`` grid mapping, so that rioxarray reads them
        (``ds.labels.rio.crs``, ``ds.labels.rio.transform()``,
        ``ds.labels.rio.to_raster("labels.tif")``). Each carries its nodata,
        :data:`NO_SITE` and infinity: a GeoTIFF holds one type and one nodata,
        so write each raster to its own file. Dask arrays (from
        :func:`pixgeo.dask.voronoi`) stay lazy."""
        return _georeferenced(
            self.frame,
            {"labels": (self.labels, NO_SITE), "distances": (self.distances, np.float32(np.inf))},
        )


@dataclass(frozen=True)
class Triangulation:
    """Counter-clockwise triangles ``(m, 3)`` as indices into the points, and
    the repeated points ``(d, 2)`` as (dropped, kept) pairs. As GeoJSON-like
    features (``features()``, ``__geo_interface__``: geopandas'
    ``GeoDataFrame.from_features(t)``), each triangle is a Polygon with its
    ``vertices`` in its properties, as ``pixgeo delaunay --geojson`` writes it.

    As ``scipy.spatial.Delaunay``: ``neighbors``, ``convex_hull``,
    ``vertex_neighbor_vertices`` and ``find_simplex``, with SciPy's
    conventions."""

    simplices: np.ndarray
    duplicates: np.ndarray
    points: Optional[np.ndarray] = None

    def _edges(self) -> Tuple[np.ndarray, np.ndarray]:
        """Every directed edge (from, to) of the triangles, three a triangle
        (edge k from corner k to k + 1), and each one's reverse's index in
        that list, -1 on the hull."""
        s = np.asarray(self.simplices, dtype=np.int64).reshape(-1, 3)
        heads, tails = s.reshape(-1), np.roll(s, -1, axis=1).reshape(-1)
        if len(heads) == 0:
            return np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
        n = int(heads.max()) + 1
        key = heads * n + tails
        order = np.argsort(key)
        at = np.minimum(np.searchsorted(key[order], tails * n + heads), len(key) - 1)
        twin = np.where(key[order][at] == tails * n + heads, order[at], -1)
        return np.stack([heads, tails], axis=1), twin

    @functools.cached_property
    def neighbors(self) -> np.ndarray:
        """``(m, 3)``: ``neighbors[i, j]`` is the triangle across from corner
        j of triangle i, -1 where that edge is on the convex hull (SciPy's
        ``Delaunay.neighbors``)."""
        _, twin = self._edges()
        across = np.where(twin >= 0, twin // 3, -1).reshape(-1, 3)
        # Corner j faces the edge from corner j + 1 to j + 2.
        return np.roll(across, -1, axis=1).astype(np.intp)

    @functools.cached_property
    def convex_hull(self) -> np.ndarray:
        """``(h, 2)``: the edges of the convex hull as point index pairs, each
        counter-clockwise around the hull (SciPy's ``Delaunay.convex_hull``)."""
        edges, twin = self._edges()
        return edges[twin < 0].astype(np.intp)

    @functools.cached_property
    def vertex_neighbor_vertices(self) -> Tuple[np.ndarray, np.ndarray]:
        """``(indptr, indices)``: the points joined to point k by an edge are
        ``indices[indptr[k]:indptr[k + 1]]``, in increasing order (SciPy's
        ``Delaunay.vertex_neighbor_vertices``)."""
        edges, _ = self._edges()
        both = np.unique(np.concatenate([edges, edges[:, ::-1]]), axis=0)
        n = len(self.points) if self.points is not None else int(both.max(initial=-1)) + 1
        indptr = np.searchsorted(both[:, 0], np.arange(n + 1)).astype(np.intc)
        return indptr, both[:, 1].astype(np.intc)

    def find_simplex(self, xi) -> np.ndarray:
        """The triangle holding each point of ``xi`` (``(..., 2)``), by exact
        orientation tests: -1 outside the hull; a point on an edge or a
        corner gets the smallest index among the triangles holding it
        (SciPy's ``Delaunay.find_simplex``, without its tolerance)."""
        if self.points is None:
            raise ValueError("this triangulation has no points to find in")
        q = np.asarray(xi, dtype=np.float64)
        if q.shape[-1:] != (2,):
            raise ValueError(f"xi must have shape (..., 2), not {q.shape}")
        found = _pixgeo.find_simplex(
            self.points, np.ascontiguousarray(self.simplices, dtype=np.uint32),
            np.ascontiguousarray(q.reshape(-1, 2)),
        )
        return found.astype(np.intp).reshape(q.shape[:-1])

    def features(self) -> list:
        """The triangles as GeoJSON-like Feature mappings."""
        if self.points is None:
            raise ValueError("this triangulation has no points to place its triangles")
        return [
            {
                "type": "Feature",
                "geometry": {
                    "type": "Polygon",
                    "coordinates": [[tuple(map(float, self.points[v])) for v in (*t, t[0])]],
                },
                "properties": {"vertices": [int(v) for v in t]},
            }
            for t in self.simplices
        ]

    @property
    def __geo_interface__(self) -> dict:
        return {"type": "FeatureCollection", "features": self.features()}


@dataclass(frozen=True)
class Cells:
    """The exact Voronoi (or power) cells of points clipped to ``bbox``, in
    input order.

    ``polygons[i]`` is site i's cell: a ``shapely.Polygon`` when shapely is
    installed (empty where the cell misses the box), else a GeoJSON-like
    mapping (``{"type": "Polygon", "coordinates": []}`` there). Every corner
    is the double nearest the exact corner, so neighbouring cells share their
    corners bit for bit and the cells tile the box. A repeated site has the
    cell of the first equal to it: ``duplicates`` ``(d, 2)`` lists (repeat,
    first). ``__geo_interface__`` is a FeatureCollection with each feature's
    ``site`` (and ``same_as``) in its properties, as ``pixgeo voronoi
    --cells`` writes it. Power cells (:func:`power_cells`) carry the
    ``weights`` and the ``hidden`` sites (ascending), whose cells are empty;
    their features say ``weight`` and ``hidden``.

    The cells are a sequence of their polygons: ``len(cells)``,
    ``cells[i]``, ``for cell in cells``.
    """

    polygons: list
    duplicates: np.ndarray
    bbox: Tuple[float, float, float, float]
    crs: Optional[str] = None
    weights: Optional[np.ndarray] = None
    hidden: Optional[np.ndarray] = None

    def __len__(self) -> int:
        return len(self.polygons)

    def __getitem__(self, i):
        return self.polygons[i]

    def __iter__(self):
        return iter(self.polygons)

    @property
    def __geo_interface__(self) -> dict:
        same_as = {int(r): int(f) for r, f in self.duplicates}
        hidden = set() if self.hidden is None else set(self.hidden.tolist())
        features = []
        for i, cell in enumerate(self.polygons):
            geometry = cell if isinstance(cell, dict) else cell.__geo_interface__
            properties = {"site": i}
            if i in same_as:
                properties["same_as"] = same_as[i]
            if self.weights is not None:
                properties["weight"] = float(self.weights[i])
                properties["hidden"] = i in hidden
            features.append({"type": "Feature", "geometry": geometry, "properties": properties})
        return {"type": "FeatureCollection", "features": features}


@dataclass(frozen=True)
class Circle:
    """A circle's centre and radius, and the points on it."""

    centre: Tuple[float, float]
    radius: float
    sites: Tuple[int, ...]


def _unmasked(a, name: str):
    """``a``, refused where it is a masked array with masked values: asarray
    would read the values under the mask as if they were data. A masked
    array's module is loaded by whoever made it; NumPy loads it lazily, and
    loading it here would cost a first call more than the call itself."""
    ma = sys.modules.get("numpy.ma")
    if ma is None or not isinstance(a, ma.MaskedArray):
        return a
    if ma.is_masked(a):
        raise ValueError(
            f"{name}: a masked array with {ma.count_masked(a)} masked value(s); "
            "fill or compress it first (a.filled(...) or a.compressed())"
        )
    return ma.getdata(a)


def _count(v, name: str) -> int:
    """A whole number ``v`` (an int or a NumPy integer); 32.5 or True are refused."""
    if isinstance(v, (bool, np.bool_)):
        raise ValueError(f"{name} must be a whole number, not {v!r}")
    try:
        return operator.index(v)
    except TypeError:
        raise ValueError(f"{name} must be a whole number, not {v!r}") from None


def _points(a, name: str) -> np.ndarray:
    """An (n, 2) C-contiguous, aligned float64 copy-or-view of ``a``; ValueError otherwise."""
    a = _unmasked(a, name)
    try:
        p = np.asarray(a)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"{name}: not an array of points ({e})") from None
    if p.dtype.kind == "O" and p.ndim == 1:
        p = _shapely_points(p, name)
    if p.dtype.kind not in "fiu" or p.dtype.kind == "c":
        raise ValueError(f"{name}: points must be real numbers, not dtype {p.dtype}")
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"{name}: points must have shape (n, 2), not {p.shape}")
    # Aligned too: arrays unpickled from a buffer (as Dask sends them) may not be.
    return np.require(p, dtype=np.float64, requirements=["C_CONTIGUOUS", "ALIGNED"])


def _shapely_points(a: np.ndarray, name: str) -> np.ndarray:
    """The (n, 2) coordinates of a sequence of shapely Points (a GeoSeries of
    points, say); ValueError for anything else."""
    try:
        import shapely
    except ImportError:
        raise ValueError(f"{name}: an array of objects; give (n, 2) numbers") from None
    try:
        kinds = shapely.get_type_id(a)
    except TypeError:
        raise ValueError(f"{name}: an array of objects that are not shapely geometries; "
                         "give (n, 2) numbers or shapely Points") from None
    if len(a) and not (kinds == 0).all():
        raise ValueError(f"{name}: geometries other than Points; give (n, 2) numbers or Points")
    if shapely.is_empty(a).any():
        raise ValueError(f"{name}: an empty Point has no coordinates")
    return shapely.get_coordinates(a).reshape(-1, 2)


def _shape(shape) -> Tuple[int, int]:
    try:
        h, w = (_count(s, "shape") for s in shape)
    except (TypeError, ValueError):
        raise ValueError(f"shape must be (height, width) in whole pixels, not {shape!r}") from None
    if h < 1 or w < 1 or h >= 2**32 or w >= 2**32:
        raise ValueError(f"shape {shape!r}: sides must be at least 1")
    return h, w


def _bbox(bbox) -> Optional[Tuple[float, float, float, float]]:
    if bbox is None:
        return None
    b = tuple(float(v) for v in bbox)
    if len(b) != 4:
        raise ValueError(f"bbox must be (xmin, ymin, xmax, ymax), not {bbox!r}")
    return b


def _frame(t) -> Frame:
    w, h, ox, oy, scale = t
    return Frame(w, h, (ox, oy), scale)


def _crs(crs) -> Optional[str]:
    """``"EPSG:N"`` from the number N, ``"EPSG:N"``, an OGC URN, a WKT or
    PROJ string that names or matches an EPSG code, a ``.prj`` file, or an
    object with ``to_epsg()`` (pyproj's and rasterio's CRS)."""
    if crs is None:
        return None
    if hasattr(crs, "to_epsg"):
        code = crs.to_epsg()
        if code is None:
            raise ValueError(f"crs {crs!r} has no EPSG code; pixgeo writes CRSs by EPSG code")
        crs = code
    text = f"EPSG:{crs}" if isinstance(crs, (int, np.integer)) else str(crs)
    return f"EPSG:{_pixgeo.epsg_code(text)}"


@dataclass(frozen=True)
class _Placement:
    """Where a picture lies, and how pixgeo computes it: north-up pictures in
    the world mirrored across the x axis (y to -y), whose frame puts the
    largest y in row 0, so that every raster comes out north-up as computed
    (distances are the same in the mirror)."""

    width: int
    height: int
    bbox: Optional[Tuple[float, float, float, float]]
    up: bool
    crs: Optional[str]

    def sites(self, points: np.ndarray) -> np.ndarray:
        """``points`` in the computing world."""
        if not self.up:
            return points
        mirrored = points.copy()
        mirrored[:, 1] *= -1.0
        return mirrored

    def point(self, x: float, y: float) -> Tuple[float, float]:
        """A point of the computing world in the user's."""
        return (x, -y) if self.up else (x, y)

    def frame(self, t) -> Frame:
        """The computing frame ``t`` as the user's."""
        w, h, ox, oy, scale = t
        origin = (ox, -oy) if self.up else (ox, oy)
        return Frame(w, h, origin, scale, "up" if self.up else "down", self.crs)


def _place(shape, bbox, res, y_axis, crs) -> _Placement:
    """The picture of ``shape`` (or of ``bbox`` in pixels of side ``res``),
    north-up unless ``y_axis == "down"`` (the default without a box)."""
    box = _bbox(bbox)
    if res is not None:
        if shape is not None:
            raise ValueError("give shape=(height, width) or res= (with a bbox), not both")
        if box is None:
            raise ValueError("res= sizes the pixels of a bbox: give bbox=(xmin, ymin, xmax, ymax)")
        res = float(res)
        if not (np.isfinite(res) and res > 0):
            raise ValueError(f"res must be a pixel side above 0, not {res!r}")
        sides = []
        for name, extent in (("height", box[3] - box[1]), ("width", box[2] - box[0])):
            n = extent / res
            if not (np.isfinite(n) and n >= 0.5 and abs(n - round(n)) <= 1e-9 * max(1.0, n)):
                raise ValueError(
                    f"the bbox's {name} {extent!r} is {n!r} pixels of side {res!r}: "
                    "give a bbox whose sides are whole numbers of pixels"
                )
            sides.append(int(round(n)))
        shape = tuple(sides)
    elif shape is None:
        raise ValueError("give shape=(height, width), or bbox= and res= (the pixels' side)")
    h, w = _shape(shape)
    if y_axis is None:
        y_axis = "up" if box is not None else "down"
    if y_axis not in ("up", "down"):
        raise ValueError(f"y_axis must be 'up' (row 0 the largest y) or 'down', not {y_axis!r}")
    up = y_axis == "up"
    if up:
        # Without a box, the pixel coordinates' own rectangle, flipped.
        x0, y0, x1, y1 = box if box is not None else (-0.5, -0.5, w - 0.5, h - 0.5)
        box = (x0, -y1, x1, -y0)
    return _Placement(w, h, box, up, _crs(crs))


def voronoi(
    sites,
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    metric: Optional[str] = None,
    mode: str = "exact",
    weights=None,
    device: Optional[str] = None,
    window: Optional[Sequence[int]] = None,
    method: str = "auto",
) -> Diagram:
    """The Voronoi diagram of ``sites`` as a label and distance raster.

    ``shape`` is ``(H, W)``. Without ``bbox`` world and pixel coordinates
    agree (pixel (i, j) centred at (i, j)); with ``bbox = (xmin, ymin, xmax,
    ymax)`` that rectangle fills the picture (pixels are square, so H must
    match its aspect ratio to within a pixel), or ``res`` gives the pixels'
    side instead of ``shape`` (``bbox=(0, 0, 1000, 800), res=10``: 80 x 100).
    With a bbox the rasters are north-up, as the command line and GIS tools
    hold them (row 0 the largest y); ``y_axis="down"`` puts the smallest y in
    row 0. ``crs`` (``"EPSG:N"``) is carried to the frame, whose
    ``transform`` places the rasters.

    ``metric="great-circle"`` measures distances on the Earth: x and y are
    longitude and latitude in degrees, and ``distances`` are metres along
    great circles of the sphere of the Earth's mean radius
    (:data:`EARTH_RADIUS`). It is the default under a geographic ``crs``
    (EPSG:4326, say); a planar metric there measures degrees and warns. Great
    circles are found on the CPU where there is no GPU (or with
    ``device="cpu"``), else with the device as a filter; both give the same
    answer. ``metric`` is ``l2``, ``l1``,
    ``linf`` or ``lp:P``; ``mode`` is ``exact`` (every pixel's nearest site,
    ties to the smaller index) or the thesis's triangle fans, ``fan`` (distance
    error within a pixel) or ``fan:T``. ``device``: ``auto``, ``lavapipe``,
    ``gpu``, an index or part of a name (default: ``PIXGEO_DEVICE``).

    ``weights`` is ``(n,)`` multiplicative weights m or ``(n, 2)`` rows
    ``(m, a)``: a site's distance is divided by m > 0, then a is added (thesis
    §3.8); ``distances`` are then the weighted ones.

    ``window = (x0, y0, width, height)`` computes only those pixels of the
    picture (exact mode): the arrays are ``(height, width)`` and equal the whole
    diagram's there bit for bit, so windows computed apart tile into it
    (:func:`pixgeo.dask.voronoi` does that on a cluster).

    ``method`` finds exact Euclidean labels by ``cones`` drawn on the device
    or by a ``grid`` search on the CPU, both proven exact and equal bit for
    bit; ``auto`` takes the grid where there is no GPU (without starting
    Vulkan) and the cones on a GPU.
    """
    place = _place(shape, bbox, res, y_axis, crs)
    metric = _metric_for(metric, place.crs)
    if metric == "great-circle":
        if weights is not None or window is not None or mode != "exact":
            raise ValueError(
                "great-circle diagrams take unweighted points, whole and exact: "
                "give metric='l2' for a planar diagram in degrees"
            )
        return _great_circle(_points(sites, "sites"), place, device)
    w, h, box = place.width, place.height, place.bbox
    points = place.sites(_points(sites, "sites"))
    if weights is None:
        labels, distances, frame = _pixgeo.voronoi(
            points, w, h, box, metric, mode, device, _window(window), method
        )
    else:
        if window is not None:
            raise ValueError("windows take unweighted points; give weights or a window")
        labels, distances, frame = _pixgeo.voronoi_weighted(
            points, _weights(weights, len(points)), w, h, box, metric, mode, device
        )
    return Diagram(labels, distances, place.frame(frame))


EARTH_RADIUS = _pixgeo.EARTH_RADIUS
"""The sphere of great-circle distances: the Earth's mean radius (IUGG R1), metres."""


def _metric_for(metric: Optional[str], crs: Optional[str]) -> str:
    """``metric``, or by default great circles under a geographic ``crs`` and
    ``l2`` otherwise; a planar metric under a geographic ``crs`` warns."""
    geographic = crs is not None and _pixgeo.is_geographic(int(crs[5:]))
    if metric is None:
        return "great-circle" if geographic else "l2"
    if geographic and metric != "great-circle":
        import warnings

        warnings.warn(
            f"{crs} is geographic: metric={metric!r} measures degrees on the longitude-latitude "
            "plane, not distances on the Earth (without metric=, pixgeo measures great circles "
            "in metres)",
            stacklevel=3,
        )
    return metric


def _planar(metric: Optional[str], crs: Optional[str], what: str) -> str:
    """The metric of a problem pixgeo solves on the plane alone: refused
    where great circles are asked for or are the default (a geographic
    ``crs``), and warned about where a planar one is asked for there."""
    metric = _metric_for(metric, crs)
    if metric == "great-circle":
        raise ValueError(
            f"{what} is computed on the plane, not on the Earth: give metric='l2' (or another "
            "planar metric) to measure degrees on the longitude-latitude plane"
        )
    return metric


def _euclidean(metric: Optional[str], crs: Optional[str], what: str) -> None:
    """Refuses a Euclidean-only problem under a geographic ``crs`` unless
    ``metric='l2'`` asks for the longitude-latitude plane (which warns)."""
    if _planar(metric, crs, what) != "l2":
        raise ValueError(f"{what} is Euclidean: metric='l2' or none")


def _warn_planar(crs: Optional[str], what: str) -> None:
    """Warns that ``what`` is taken on the longitude-latitude plane where
    ``crs`` is geographic."""
    if crs is not None and _pixgeo.is_geographic(int(crs[5:])):
        import warnings

        warnings.warn(f"{crs} is geographic: {what} on the longitude-latitude plane, "
                      "not on the Earth", stacklevel=3)


def _great_circle(sites: np.ndarray, place: "_Placement", device: Optional[str]) -> Diagram:
    """Every pixel's nearest site by great circle, and the distance in metres:
    on the CPU without a GPU (or for ``device="cpu"``), else on the device."""
    frame = place.frame(_pixgeo.frame_of(place.width, place.height, place.bbox))
    south, north = frame.bbox[1], frame.bbox[3]
    if south < -90 or north > 90:
        raise ValueError(
            f"the picture reaches latitudes {south} to {north}: great circles take y as a "
            "latitude in [-90, 90]; give a bbox within it"
        )
    x, y = frame.pixel_centres()
    labels, distances, *_ = _pixgeo.great_circle(
        sites, np.ascontiguousarray(x, dtype=np.float64), np.ascontiguousarray(y, dtype=np.float64), device
    )
    shape = (frame.height, frame.width)
    return Diagram(labels.reshape(shape), distances.astype(np.float32).reshape(shape), frame)


def _weights(weights, n: int) -> np.ndarray:
    wt = np.asarray(_unmasked(weights, "weights"), dtype=np.float64)
    if wt.shape == (n,):
        wt = np.stack([wt, np.zeros(n)], -1)
    if wt.shape != (n, 2):
        raise ValueError(f"weights must have shape ({n},) or ({n}, 2) for (m, a), not {wt.shape}")
    return np.require(wt, requirements=["C_CONTIGUOUS", "ALIGNED"])


def _window(window) -> Optional[Tuple[int, int, int, int]]:
    if window is None:
        return None
    try:
        v = tuple(_count(x, "window") for x in window)
    except (TypeError, ValueError):
        raise ValueError(f"window must be (x0, y0, width, height), not {window!r}") from None
    if len(v) != 4 or min(v) < 0 or max(v) >= 2**32:
        raise ValueError(f"window must be four pixel counts (x0, y0, width, height), not {window!r}")
    return v


def frame(
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
) -> Frame:
    """The frame :func:`voronoi` uses for these arguments, computed without
    drawing."""
    place = _place(shape, bbox, res, y_axis, crs)
    return place.frame(_pixgeo.frame_of(place.width, place.height, place.bbox))


def k_nearest(
    sites,
    shape: Optional[Sequence[int]] = None,
    k: int = 1,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    metric: Optional[str] = None,
    mode: str = "exact",
    device: Optional[str] = None,
) -> Diagram:
    """Every pixel's k nearest sites, nearest first: labels and distances of
    shape ``(H, W, k)``; :data:`NO_SITE` (and inf) where fewer than k sites
    exist. Arguments as for :func:`voronoi`."""
    place = _place(shape, bbox, res, y_axis, crs)
    metric = _planar(metric, place.crs, "k_nearest")
    k = _count(k, "k")
    if k < 1:
        raise ValueError(f"k must be at least 1, not {k!r}")
    labels, distances, frame = _pixgeo.k_nearest(
        place.sites(_points(sites, "sites")), place.width, place.height, k, place.bbox, metric,
        mode, device
    )
    return Diagram(labels, distances, place.frame(frame))


def furthest(
    sites,
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    metric: Optional[str] = None,
    device: Optional[str] = None,
) -> Diagram:
    """The furthest-site diagram: every pixel's farthest site and the distance
    to it. Arguments as for :func:`voronoi`."""
    place = _place(shape, bbox, res, y_axis, crs)
    metric = _planar(metric, place.crs, "furthest")
    labels, distances, frame = _pixgeo.furthest(
        place.sites(_points(sites, "sites")), place.width, place.height, place.bbox, metric, device
    )
    return Diagram(labels, distances, place.frame(frame))


def delaunay(points, *, device: Optional[str] = None) -> Triangulation:
    """The Delaunay triangulation by flooding (Cao, Edelsbrunner and Tan) on
    a device, by insertion on the CPU: counter-clockwise triangles as indices
    into ``points``, each starting at its least index, sorted; the same on
    every device. Co-circular points are decided by their order in
    ``points``, so the triangulation is unique; where no four points are
    co-circular it is ``scipy.spatial.Delaunay(points).simplices`` up to
    order. Repeated points are dropped and reported. ``features()`` gives the
    triangles as GeoJSON-like features."""
    p = _points(points, "points")
    simplices, duplicates = _pixgeo.delaunay(p, device)
    return Triangulation(simplices.astype(np.intp), duplicates.astype(np.intp), p)


def voronoi_cells(
    points, *, bbox=None, crs=None, metric: Optional[str] = None, geojson: bool = False,
    device: Optional[str] = None,
) -> Cells:
    """The exact Euclidean Voronoi cells of ``points`` clipped to ``bbox``
    (default: the points' bounding box), in input order: shapely polygons,
    or GeoJSON-like mappings without shapely or with ``geojson=True``. See
    :class:`Cells`; ``crs`` (``"EPSG:N"``) is carried to it. Under a
    geographic ``crs`` cells on the sphere are not computed: ``metric='l2'``
    asks for cells on the longitude-latitude plane (with a warning)."""
    crs = _crs(crs)
    _euclidean(metric, crs, "voronoi_cells")
    p = _points(points, "points")
    box = _cells_box(p, bbox)
    corners, duplicates = _pixgeo.voronoi_cells(p, box, device)
    return Cells(_polygons(corners, geojson), duplicates.astype(np.intp), box, crs)


def _cells_box(p: np.ndarray, bbox) -> Tuple[float, float, float, float]:
    """``bbox``, or by default the points' bounding box."""
    box = _bbox(bbox)
    if box is None:
        if len(p) == 0:
            raise ValueError("points: give at least one point")
        box = (*map(float, p.min(axis=0)), *map(float, p.max(axis=0)))
        if box[0] == box[2] or box[1] == box[3]:
            raise ValueError(
                f"the points' bounding box {box} is flat: give bbox=(xmin, ymin, xmax, ymax)"
            )
    return box


def _polygons(corners, geojson: bool) -> list:
    """Cells' corners as shapely polygons, or GeoJSON-like mappings without
    shapely or with ``geojson``."""
    shapely = None
    if not geojson:
        try:
            import shapely
        except ImportError:
            pass
    if shapely is None:
        # One conversion to lists for every corner, then each ring closed.
        flat = np.concatenate(corners).tolist() if len(corners) else []
        polygons, at = [], 0
        for c in corners:
            ring = flat[at:at + len(c)]
            at += len(c)
            polygons.append({"type": "Polygon", "coordinates": [ring + ring[:1]] if ring else []})
        return polygons
    # One vectorized call for every ring (each closed by shapely).
    full = [i for i, c in enumerate(corners) if len(c)]
    polygons = [shapely.Polygon()] * len(corners)
    if full:
        sizes = [len(corners[i]) for i in full]
        rings = shapely.linearrings(
            np.concatenate([corners[i] for i in full]), indices=np.repeat(np.arange(len(full)), sizes)
        )
        for i, polygon in zip(full, shapely.polygons(rings)):
            polygons[i] = polygon
    return polygons


def hausdorff(
    a, b, *, device: Optional[str] = None, method: Optional[str] = None
) -> Tuple[float, int, int]:
    """The Hausdorff distance between point sets ``a`` and ``b``, exact, and
    the pair that attains it: ``(distance, index in a, index in b)``.
    ``method`` is what proposes the partners before the exact check:
    ``"pixels"`` (the Voronoi picture), ``"grid"`` (a bucket grid on the CPU),
    or None, the faster on the device (the grid on lavapipe)."""
    d, ab, ba = _pixgeo.hausdorff(_points(a, "a"), _points(b, "b"), device, method)
    if ab[0] >= ba[0]:
        return (d, ab[1], ab[2])
    return (d, ba[2], ba[1])


def diameter(points, *, device: Optional[str] = None) -> Tuple[float, int, int]:
    """The largest distance between two of the points, exact: ``(distance, i, j)``."""
    return tuple(_pixgeo.diameter(_points(points, "points"), device))


def _circle(t) -> Circle:
    x, y, r, sites = t
    return Circle((x, y), r, tuple(sites))


def enclosing_circle(points, *, device: Optional[str] = None) -> Circle:
    """The smallest circle holding every point (exact, by Welzl's algorithm on
    the candidates the picture leaves)."""
    return _circle(_pixgeo.enclosing_circle(_points(points, "points"), device))


def largest_empty_circle(
    points,
    *,
    segments=None,
    region: Optional[Sequence] = None,
    inside: bool = False,
    device: Optional[str] = None,
) -> Circle:
    """The largest circle holding none of the points and crossing none of
    the ``segments`` ((k, 4) rows x0, y0, x1, y1), its centre inside
    ``region`` (a sequence of rings, each an (m, 2) array, even-odd; default:
    the sites' bounding box); with ``inside`` the whole circle inside it. The
    radius is the double nearest the exact one. ``sites`` numbers the points,
    then the segments, then (with ``inside``) the region's edges."""
    rings = [] if region is None else [_points(r, "region ring") for r in region]
    bars = np.zeros((0, 4)) if segments is None else np.asarray(segments, dtype=np.float64)
    if bars.ndim != 2 or bars.shape[1] != 4:
        raise ValueError(f"segments must be (k, 4) rows x0, y0, x1, y1, not {bars.shape}")
    found = _pixgeo.largest_empty_circle(
        _points(points, "points"), np.ascontiguousarray(bars), rings, inside, device
    )
    return _circle(found)


@dataclass(frozen=True)
class AlphaHull:
    """An α-hull's pixels (True inside), the picture fitted to it, the sites on
    its boundary counter-clockwise (hull method and α = 0), and the method."""

    inside: np.ndarray
    frame: Frame
    boundary: Tuple[int, ...]
    method: str


def alpha_hull(
    points, alpha: float, *, side: int = 1024, method: str = "hull", device: Optional[str] = None
) -> AlphaHull:
    """The α-hull of the points (thesis ch. 6): α = 0 the convex hull, α > 0 the
    intersection of discs of radius 1/α holding every point, α < 0 the
    complement of the empty discs of radius 1/|α|. The picture is fitted to
    where the hull can be, ``side`` pixels along its longer axis; ``method``
    (α > 0) is ``hull`` (circles through hull points) or ``pixels``."""
    classes, frame, boundary, used = _pixgeo.alpha_hull_of(
        _points(points, "points"), float(alpha), _count(side, "side"), method, device
    )
    return AlphaHull(classes == 1, _frame(frame), tuple(boundary), used)


@dataclass(frozen=True)
class Settle:
    """The potential-area map (pixels a new site at each pixel would win), its
    largest value, and the exact settle point ``(x, y, area)`` in world units
    (L2 only; ``None`` otherwise)."""

    area: np.ndarray
    frame: Frame
    best_area: int
    refined: Optional[Tuple[float, float, float]]

    def to_xarray(self):
        """``area`` georeferenced as :meth:`Diagram.to_xarray` does."""
        return _georeferenced(self.frame, {"area": (self.area, None)})


def settle(
    sites,
    shape: Optional[Sequence[int]] = None,
    *,
    own=None,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    metric: Optional[str] = None,
    refine_from: int = 8,
    device: Optional[str] = None,
) -> Settle:
    """Where a new store wins the largest market among rival ``sites``
    (thesis §3.11.3), not counting pixels that ``own`` stores already hold:
    the map on the picture, then under L2 an exact compass search from the
    ``refine_from`` best pixels."""
    place = _place(shape, bbox, res, y_axis, crs)
    metric = _planar(metric, place.crs, "settle")
    own = np.zeros((0, 2)) if own is None else own
    area, frame, best, refined = _pixgeo.settle(
        place.sites(_points(sites, "sites")),
        place.sites(_points(own, "own")),
        place.width,
        place.height,
        place.bbox,
        metric,
        _count(refine_from, "refine_from"),
        device,
    )
    if refined is not None:
        refined = (*place.point(refined[0], refined[1]), refined[2])
    return Settle(area, place.frame(frame), best, refined)


def _polygon(points, corners: int, largest: bool) -> Tuple[np.ndarray, float]:
    vertices, area = _pixgeo.extremal_polygon(_points(points, "points"), corners, largest)
    return vertices.astype(np.intp), area


def smallest_triangle(points) -> Tuple[np.ndarray, float]:
    """The smallest-area triangle with vertices among the points: its vertex
    indices counter-clockwise and its area, exact (rotational sweep,
    O(n² log n))."""
    return _polygon(points, 3, False)


def largest_triangle(points) -> Tuple[np.ndarray, float]:
    """The largest-area triangle with vertices among the points, exact."""
    return _polygon(points, 3, True)


def smallest_quadrangle(points) -> Tuple[np.ndarray, float]:
    """The smallest quadrangle with vertices among the points: a diagonal with
    one vertex strictly on each side; indices counter-clockwise, area."""
    return _polygon(points, 4, False)


def largest_quadrangle(points) -> Tuple[np.ndarray, float]:
    """The largest quadrangle with vertices among the points, exact."""
    return _polygon(points, 4, True)


def distance_transform_edt(
    input,
    sampling=None,
    return_distances: bool = True,
    return_indices: bool = False,
    distances=None,
    indices=None,
    *,
    metric: str = "l2",
):
    """SciPy's ``scipy.ndimage.distance_transform_edt`` for 2-D arrays: each
    non-zero element's distance to the nearest zero element, exact, with
    ``sampling`` (one spacing, or one per axis) and the nearest zero's indices
    in SciPy's layout, int32 ``(2, H, W)``. ``distances`` (float64) and
    ``indices`` (int32) may be given to be filled in place, as in SciPy.

    ``metric`` goes beyond SciPy: ``"l1"``, ``"linf"``, ``"lp:P"`` or
    ``"polygon:FILE"`` (exact too; polygons and p < 1 take equal sampling).

    Where ``input`` has no zero at all, distances are infinite and indices -1
    (SciPy's answer there is not a distance to any element).
    """
    a = _raster(input)
    # SciPy's argument rules, and its messages.
    problems = []
    if not (return_distances or return_indices):
        problems.append("at least one of return_distances/return_indices must be True")
    if distances is not None and not return_distances:
        problems.append("return_distances must be True if distances is supplied")
    if indices is not None and not return_indices:
        problems.append("return_indices must be True if indices is supplied")
    if problems:
        raise RuntimeError(", ".join(problems))
    features = np.ascontiguousarray(a == 0)
    d, i = _pixgeo.distance_transform(
        features, _spacing(sampling), metric, indices=bool(return_indices)
    )
    out = []
    if return_distances:
        if distances is None:
            out.append(d)
        else:
            if distances.shape != a.shape or distances.dtype != np.float64:
                raise RuntimeError("distances array has wrong shape or type")
            distances[...] = d
    if return_indices:
        if indices is None:
            out.append(i)
        else:
            if indices.shape != (2,) + a.shape or indices.dtype != np.int32:
                raise RuntimeError("indices array has wrong shape or type")
            indices[...] = i
    if len(out) == 2:
        return tuple(out)
    if len(out) == 1:
        return out[0]
    return None


def _raster(image) -> np.ndarray:
    a = np.asarray(_unmasked(image, "the raster"))
    if a.ndim != 2:
        raise ValueError(f"pixgeo transforms 2-D arrays, not {a.ndim}-D ones")
    return a


def _spacing(sampling) -> Tuple[float, float]:
    if sampling is None:
        return (1.0, 1.0)
    s = np.broadcast_to(np.asarray(sampling, dtype=np.float64), (2,))
    return (float(s[0]), float(s[1]))


def medial_axis(
    image,
    mask=None,
    return_distance: bool = False,
    *,
    rng=None,
    prune: float = 4.0,
    prune_angle: float = 45.0,
    sampling=None,
    metric: str = "l2",
):
    """The medial axis of ``image``'s non-zero pixels, as
    ``skimage.morphology.medial_axis`` takes it: a boolean array, and with
    ``return_distance`` the distance transform (each pixel's distance to the
    nearest zero pixel). Where ``mask`` is given, only the pixels that are
    non-zero in both count.

    It is Hesselink and Roerdink's integer medial axis, computed from pixgeo's
    exact feature transform: a pixel is on it when it and a neighbour have
    nearest zero pixels more than ``prune`` apart (in ``sampling``'s units)
    seen under more than ``prune_angle`` degrees, and it is the one of the two
    nearer their bisector. Those pixels anchor a thinning of the shape that
    joins them along its middle, so the axis is thin and keeps the topology:
    one connected axis per connected shape with a loop around each hole, thin
    shapes included (anchored by their farthest-apart pairs). ``metric`` and
    ``sampling`` are those of :func:`distance_transform_edt`. ``rng`` is
    taken, as skimage takes it, and has no effect: skimage draws on it to
    break ties in its thinning's order, and pixgeo's axis has no random part.
    """
    del rng  # deterministic: see above
    a = _raster(image) != 0
    if mask is not None:
        m = np.asarray(_unmasked(mask, "mask"))
        if m.shape != a.shape:
            raise ValueError(f"mask has shape {m.shape}, the image {a.shape}")
        a &= m != 0
    axis, d = _pixgeo.medial_axis(
        np.ascontiguousarray(~a), _spacing(sampling), metric, float(prune), float(prune_angle)
    )
    if return_distance:
        return axis, d
    return axis


def __dir__() -> list:
    # What a user completes on: the public names, not the helpers' imports.
    return sorted({*__all__, "__version__"})


def __getattr__(name: str):
    # A user of the command line's `pixgeo interpolate` reaches for it here.
    if name == "interpolate":
        raise AttributeError(
            "pixgeo has no interpolate: the command line's `pixgeo interpolate` is "
            "pixgeo.natural_neighbor(points, values, shape, method='exact' | 'discrete' | "
            "'linear' | 'nearest')"
        )
    raise AttributeError(f"module 'pixgeo' has no attribute {name!r}")


from .lloyd import Lloyd, lloyd  # noqa: E402  (it builds on the helpers above)
from ._interpolate import natural_neighbor  # noqa: E402
from .power import PowerDiagram, power_cells, power_diagram, regular_triangulation  # noqa: E402
