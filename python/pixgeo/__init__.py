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

from typing import Optional, Sequence, Tuple

import numpy as np

from . import _pixgeo
from ._input import (  # noqa: F401  (lloyd, power and the others import them from here)
    _cells_box,
    _circle,
    _count,
    _crs,
    _euclidean,
    _frame,
    _metric_for,
    _place,
    _Placement,
    _planar,
    _points,
    _polygons,
    _raster,
    _spacing,
    _unmasked,
    _warn_planar,
    _weights,
    _window,
)
from ._results import NO_SITE, AlphaHull, Cells, Circle, Diagram, Frame, Settle, Triangulation

# The answers are pixgeo's: their reprs, help and pickles name it.
for _answer in (AlphaHull, Cells, Circle, Diagram, Frame, Settle, Triangulation):
    _answer.__module__ = __name__
del _answer

__version__ = _pixgeo.__version__

NoDeviceError = _pixgeo.NoDeviceError
DeviceError = _pixgeo.DeviceError
InternalError = _pixgeo.InternalError


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
