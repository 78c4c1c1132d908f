"""How input enters pixgeo's functions: arrays checked once, the picture
placed by one rule (shape, bbox, resolution, y axis, CRS), metrics under a
geographic CRS."""

from __future__ import annotations

import operator
import sys
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from . import _pixgeo
from ._results import Circle, Frame


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


def _circle(t) -> Circle:
    x, y, r, sites = t
    return Circle((x, y), r, tuple(sites))


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
