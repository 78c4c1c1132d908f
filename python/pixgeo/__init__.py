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

from . import _docs, _pixgeo
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


@_docs.fill
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

    With a ``bbox`` the rasters are north-up, as the command line and GIS
    tools hold them, and the frame's ``transform`` places them. Under a
    geographic ``crs`` the default metric is great circles: distances in
    metres on the sphere of :data:`EARTH_RADIUS`, found on the CPU where
    there is no GPU, else with the device as a filter, the same answer.

    Parameters
    ----------
    {sites}
    {placement}
    {metric}
    {mode}
    weights : array_like, shape (n,) or (n, 2), optional
        Multiplicative weights m, or rows ``(m, a)``: a site's distance is
        divided by m > 0, then a is added (thesis §3.8); ``distances`` are
        then the weighted ones.
    {device}
    window : tuple of int, optional
        ``(x0, y0, width, height)``: only those pixels of the picture (exact
        mode), equal to the whole diagram's there bit for bit, so windows
        computed apart tile into it (:func:`pixgeo.dask.voronoi`).
    method : {"auto", "cones", "grid"}, optional
        Exact Euclidean labels by cones drawn on a device or by a grid
        search on the CPU, both proven exact and equal bit for bit;
        ``"auto"`` takes the grid where there is no GPU, the cones on one.

    Returns
    -------
    Diagram
        ``labels`` (H, W) uint32, each pixel's nearest site (:data:`NO_SITE`
        where none), ``distances`` (H, W) float32, and the ``frame``.
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


@_docs.fill
def frame(
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
) -> Frame:
    """The frame :func:`voronoi` uses for these arguments, computed without
    drawing.

    Parameters
    ----------
    {placement}

    Returns
    -------
    Frame
        The picture's size, placement, ``transform`` and CRS.
    """
    place = _place(shape, bbox, res, y_axis, crs)
    return place.frame(_pixgeo.frame_of(place.width, place.height, place.bbox))


@_docs.fill
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
    """Every pixel's k nearest sites, nearest first.

    Parameters
    ----------
    {sites}
    shape : tuple of int, optional
        As for :func:`voronoi`.
    k : int, optional
        The levels, 1 to 256.
    bbox, res, y_axis, crs
        As for :func:`voronoi`.
    {planar_metric}
    {mode}
    {device}

    Returns
    -------
    Diagram
        ``labels`` and ``distances`` of shape ``(H, W, k)``;
        :data:`NO_SITE` (and inf) where fewer than k sites exist.
    """
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


@_docs.fill
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
    to it.

    Parameters
    ----------
    {sites}
    {placement}
    {planar_metric}
    {device}

    Returns
    -------
    Diagram
        ``labels`` (H, W), each pixel's farthest site (ties to the smaller
        index), ``distances`` (H, W) and the ``frame``.
    """
    place = _place(shape, bbox, res, y_axis, crs)
    metric = _planar(metric, place.crs, "furthest")
    labels, distances, frame = _pixgeo.furthest(
        place.sites(_points(sites, "sites")), place.width, place.height, place.bbox, metric, device
    )
    return Diagram(labels, distances, place.frame(frame))


@_docs.fill
def delaunay(points, *, device: Optional[str] = None) -> Triangulation:
    """The Delaunay triangulation, exact.

    By flooding (Cao, Edelsbrunner and Tan) on a device, by insertion on the
    CPU, the same triangles on every device. Co-circular points are decided
    by their order in ``points``, so the triangulation is unique; where no
    four points are co-circular it is ``scipy.spatial.Delaunay(points)``'s
    up to order.

    Parameters
    ----------
    {points}
    {device}

    Returns
    -------
    Triangulation
        Counter-clockwise ``simplices`` as indices into ``points``, each
        starting at its least index, sorted; the repeated points dropped
        (``duplicates``); SciPy's ``neighbors``, ``convex_hull``,
        ``vertex_neighbor_vertices`` and ``find_simplex``.
    """
    p = _points(points, "points")
    simplices, duplicates = _pixgeo.delaunay(p, device)
    return Triangulation(simplices.astype(np.intp), duplicates.astype(np.intp), p)


@_docs.fill
def voronoi_cells(
    points, *, bbox=None, crs=None, metric: Optional[str] = None, geojson: bool = False,
    device: Optional[str] = None,
) -> Cells:
    """The exact Euclidean Voronoi cells of ``points``, in input order.

    Every corner is the double nearest the exact corner, so neighbouring
    cells share corners bit for bit and the cells tile the box. Under a
    geographic ``crs`` cells on the sphere are not computed:
    ``metric='l2'`` asks for cells on the longitude-latitude plane (with a
    warning).

    Parameters
    ----------
    {points}
    bbox : tuple of float, optional
        ``(xmin, ymin, xmax, ymax)`` the cells are clipped to (default: the
        points' bounding box).
    crs : str, optional
        ``"EPSG:N"``, carried to the answer.
    metric : {"l2"}, optional
        ``"l2"`` under a geographic ``crs``: the plane, asked for.
    geojson : bool, optional
        GeoJSON-like mappings instead of shapely polygons.
    {device}

    Returns
    -------
    Cells
        A sequence of the cells (shapely polygons, or mappings without
        shapely or with ``geojson=True``; empty where a cell misses the
        box) and the repeated points.
    """
    crs = _crs(crs)
    _euclidean(metric, crs, "voronoi_cells")
    p = _points(points, "points")
    box = _cells_box(p, bbox)
    corners, duplicates = _pixgeo.voronoi_cells(p, box, device)
    return Cells(_polygons(corners, geojson), duplicates.astype(np.intp), box, crs)


@_docs.fill
def hausdorff(
    a, b, *, device: Optional[str] = None, method: Optional[str] = None
) -> Tuple[float, int, int]:
    """The Hausdorff distance between point sets ``a`` and ``b``, exact.

    Parameters
    ----------
    a, b : array_like, shape (n, 2) and (m, 2)
        Finite x, y coordinates.
    {device}
    method : {"pixels", "grid"}, optional
        What proposes the partners before the exact check: the Voronoi
        picture, or a bucket grid on the CPU (default: the faster on the
        device, the grid on lavapipe).

    Returns
    -------
    tuple of (float, int, int)
        ``(distance, index in a, index in b)`` of the pair that attains it.
    """
    d, ab, ba = _pixgeo.hausdorff(_points(a, "a"), _points(b, "b"), device, method)
    if ab[0] >= ba[0]:
        return (d, ab[1], ab[2])
    return (d, ba[2], ba[1])


@_docs.fill
def diameter(points, *, device: Optional[str] = None) -> Tuple[float, int, int]:
    """The largest distance between two of the points, exact.

    Parameters
    ----------
    {points}
    {device}

    Returns
    -------
    tuple of (float, int, int)
        ``(distance, i, j)``.
    """
    return tuple(_pixgeo.diameter(_points(points, "points"), device))


@_docs.fill
def enclosing_circle(points, *, device: Optional[str] = None) -> Circle:
    """The smallest circle holding every point, exact (Welzl's algorithm on
    the candidates the picture leaves).

    Parameters
    ----------
    {points}
    {device}

    Returns
    -------
    Circle
        Its ``centre`` and ``radius``, each the double nearest the exact
        one, and the ``sites`` on it.
    """
    return _circle(_pixgeo.enclosing_circle(_points(points, "points"), device))


@_docs.fill
def largest_empty_circle(
    points,
    *,
    segments=None,
    region: Optional[Sequence] = None,
    inside: bool = False,
    device: Optional[str] = None,
) -> Circle:
    """The largest circle holding none of the points and crossing none of
    the segments, its centre in a region.

    Parameters
    ----------
    {points}
    segments : array_like, shape (k, 4), optional
        Rows ``x0, y0, x1, y1``.
    region : sequence of array_like, optional
        Rings, each an (m, 2) array, even-odd (default: the sites'
        bounding box).
    inside : bool, optional
        The whole circle inside the region, not only its centre.
    {device}

    Returns
    -------
    Circle
        The radius is the double nearest the exact one; ``sites`` numbers
        the points, then the segments, then (with ``inside``) the region's
        edges.
    """
    rings = [] if region is None else [_points(r, "region ring") for r in region]
    bars = np.zeros((0, 4)) if segments is None else np.asarray(segments, dtype=np.float64)
    if bars.ndim != 2 or bars.shape[1] != 4:
        raise ValueError(f"segments must be (k, 4) rows x0, y0, x1, y1, not {bars.shape}")
    found = _pixgeo.largest_empty_circle(
        _points(points, "points"), np.ascontiguousarray(bars), rings, inside, device
    )
    return _circle(found)


@_docs.fill
def alpha_hull(
    points, alpha: float, *, side: int = 1024, method: str = "hull", device: Optional[str] = None
) -> AlphaHull:
    """The α-hull of the points (thesis ch. 6), on a picture fitted to where
    the hull can be.

    Parameters
    ----------
    {points}
    alpha : float
        0 the convex hull, > 0 the intersection of discs of radius 1/α
        holding every point, < 0 the complement of the empty discs of
        radius 1/|α|.
    side : int, optional
        Pixels along the picture's longer axis.
    method : {"hull", "pixels"}, optional
        For α > 0: circles through hull points, or intersections of discs
        counted on the device.
    {device}

    Returns
    -------
    AlphaHull
        The ``inside`` raster, its ``frame``, the ``boundary`` sites and the
        ``method`` that found it.
    """
    classes, frame, boundary, used = _pixgeo.alpha_hull_of(
        _points(points, "points"), float(alpha), _count(side, "side"), method, device
    )
    return AlphaHull(classes == 1, _frame(frame), tuple(boundary), used)


@_docs.fill
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
    (thesis §3.11.3), not counting pixels that ``own`` stores already hold.

    Parameters
    ----------
    sites : array_like, shape (n, 2)
        The rivals.
    shape : tuple of int, optional
        As for :func:`voronoi`.
    own : array_like, shape (m, 2), optional
        Stores whose pixels do not count.
    bbox, res, y_axis, crs
        As for :func:`voronoi`.
    metric : str, optional
        ``"l2"``, ``"l1"``, ``"linf"`` or ``"lp:P"``; planar only.
    refine_from : int, optional
        Under L2, an exact compass search from this many best pixels.
    {device}

    Returns
    -------
    Settle
        The ``area`` map (each pixel's market), its ``frame``, the
        ``best_area`` and, under L2, the ``refined`` position and area.
    """
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


@_docs.fill
def smallest_triangle(points) -> Tuple[np.ndarray, float]:
    """The smallest-area triangle with vertices among the points (rotational
    sweep, O(n² log n)).

    {extremal}
    """
    return _polygon(points, 3, False)


@_docs.fill
def largest_triangle(points) -> Tuple[np.ndarray, float]:
    """The largest-area triangle with vertices among the points.

    {extremal}
    """
    return _polygon(points, 3, True)


@_docs.fill
def smallest_quadrangle(points) -> Tuple[np.ndarray, float]:
    """The smallest quadrangle with vertices among the points: a diagonal with
    one vertex strictly on each side.

    {extremal}
    """
    return _polygon(points, 4, False)


@_docs.fill
def largest_quadrangle(points) -> Tuple[np.ndarray, float]:
    """The largest quadrangle with vertices among the points.

    {extremal}
    """
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
    """SciPy's ``scipy.ndimage.distance_transform_edt`` for 2-D arrays, exact.

    Where ``input`` has no zero at all, distances are infinite and indices
    -1 (SciPy's answer there is not a distance to any element).

    Parameters
    ----------
    input : array_like, shape (H, W)
        Each non-zero element gets its distance to the nearest zero one.
    sampling : float or tuple of float, optional
        One spacing, or one per axis (rows, columns).
    return_distances, return_indices : bool, optional
        Which arrays to return.
    distances : ndarray of float64, optional
        Filled in place, as in SciPy.
    indices : ndarray of int32, shape (2, H, W), optional
        Filled in place, as in SciPy.
    metric : str, optional
        Beyond SciPy: ``"l1"``, ``"linf"``, ``"lp:P"`` or ``"polygon:FILE"``
        (exact too; polygons and p < 1 take equal sampling).

    Returns
    -------
    ndarray or tuple of ndarray
        The distances (float64) and the nearest zero's indices in SciPy's
        layout (int32, ``(2, H, W)``), as asked and not given in place.
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
    ``skimage.morphology.medial_axis`` takes it.

    It is Hesselink and Roerdink's integer medial axis, computed from
    pixgeo's exact feature transform: a pixel is on it when it and a
    neighbour have nearest zero pixels more than ``prune`` apart seen under
    more than ``prune_angle`` degrees, and it is the one of the two nearer
    their bisector. Those pixels anchor a thinning that joins them along the
    shape's middle, so the axis is thin and keeps the topology: one
    connected axis per connected shape with a loop around each hole.

    Parameters
    ----------
    image : array_like, shape (H, W)
        The shape: its non-zero pixels.
    mask : array_like, shape (H, W), optional
        Only pixels non-zero in both count.
    return_distance : bool, optional
        Return the distance transform too.
    rng : optional
        Taken, as skimage takes it, with no effect: pixgeo's axis has no
        random part.
    prune : float, optional
        The least distance, in ``sampling``'s units, between two nearest
        zero pixels that makes an anchor.
    prune_angle : float, optional
        The least angle, in degrees, they are seen under.
    sampling, metric
        As for :func:`distance_transform_edt`.

    Returns
    -------
    ndarray of bool or tuple of ndarray
        The axis, and with ``return_distance`` the distance transform.
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
