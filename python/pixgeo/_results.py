"""What pixgeo's functions return: frames, diagrams, triangulations, cells,
circles, hulls and settle maps."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from . import _pixgeo

NO_SITE = 2**32 - 1
"""The label of a pixel with no site (``labels`` are uint32)."""


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


@dataclass(frozen=True)
class AlphaHull:
    """An α-hull's pixels (True inside), the picture fitted to it, the sites on
    its boundary counter-clockwise (hull method and α = 0), and the method."""

    inside: np.ndarray
    frame: Frame
    boundary: Tuple[int, ...]
    method: str


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
