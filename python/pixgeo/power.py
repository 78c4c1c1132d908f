"""Power (Laguerre) diagrams, their cells and regular triangulations:
:func:`pixgeo.power_diagram`, :func:`pixgeo.power_cells` and
:func:`pixgeo.regular_triangulation`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import numpy as np

from . import _docs, Cells, Frame, _cells_box, _crs, _euclidean, _pixgeo, _place, _points, _polygons, _warn_planar
from ._interpolate import _values


@dataclass(frozen=True)
class PowerDiagram:
    """Each pixel's site of least power ``|p - s|² - w`` (``labels``, ties to
    the lower index), that power (``powers``, the double nearest the exact
    one), how many sites share it (``ties``), and the sites whose cells are
    empty (``hidden``, ascending)."""

    labels: np.ndarray
    powers: np.ndarray
    ties: np.ndarray
    hidden: np.ndarray
    frame: Frame

    def to_xarray(self):
        """``labels``, ``powers`` and ``ties`` as an ``xarray.Dataset``,
        placed and georeferenced as :meth:`pixgeo.Diagram.to_xarray`."""
        return self.frame.to_xarray(labels=self.labels, powers=self.powers, ties=self.ties)


@_docs.fill
def power_diagram(
    points,
    weights,
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
) -> PowerDiagram:
    """The power diagram on the picture, exact: on the CPU, by a walk over
    the regular triangulation.

    Parameters
    ----------
    {points}
    weights : array_like, shape (n,)
        Power weights w: a pixel's power from a site s is ``|p - s|² - w``.
    {placement}

    Returns
    -------
    PowerDiagram
        Each pixel's site of least power, that power, how many sites share
        it, and the hidden sites.
    """
    place = _place(shape, bbox, res, y_axis, crs)
    _warn_planar(place.crs, "powers are measured")
    p = _points(points, "points")
    labels, powers, ties, hidden = _pixgeo.power_diagram(
        place.sites(p), _values(weights, len(p), "weights"), place.width, place.height, place.bbox
    )
    frame = place.frame(_pixgeo.frame_of(place.width, place.height, place.bbox))
    return PowerDiagram(labels, powers, ties, np.asarray(hidden, dtype=np.uint32), frame)


@_docs.fill
def power_cells(
    points, weights, *, bbox=None, crs=None, metric: Optional[str] = None, geojson: bool = False
) -> Cells:
    """The exact power cells of the points, in input order.

    Every corner is the double nearest the exact corner, so neighbouring
    cells share corners bit for bit and the cells tile the box; a hidden
    site's cell is empty. On the CPU, from the exact regular triangulation.

    Parameters
    ----------
    {points}
    weights : array_like, shape (n,)
        Power weights.
    bbox : tuple of float, optional
        ``(xmin, ymin, xmax, ymax)`` the cells are clipped to (default: the
        points' bounding box).
    crs : str, optional
        As for :func:`pixgeo.voronoi_cells`: under a geographic one,
        ``metric='l2'`` asks for the plane.
    metric : {"l2"}, optional
        The plane, asked for under a geographic ``crs``.
    geojson : bool, optional
        GeoJSON-like mappings instead of shapely polygons.

    Returns
    -------
    Cells
        The cells, with ``weights`` and the ``hidden`` sites.
    """
    crs = _crs(crs)
    _euclidean(metric, crs, "power_cells")
    p = _points(points, "points")
    v = _values(weights, len(p), "weights")
    box = _cells_box(p, bbox)
    corners, hidden = _pixgeo.power_cells(p, v, box)
    return Cells(
        _polygons(corners, geojson), np.empty((0, 2), dtype=np.intp), box, crs,
        weights=v, hidden=np.asarray(hidden, dtype=np.uint32),
    )


@_docs.fill
def regular_triangulation(points, weights) -> Tuple[np.ndarray, np.ndarray]:
    """The regular (weighted Delaunay) triangulation, exact.

    Parameters
    ----------
    {points}
    weights : array_like, shape (n,)
        Power weights.

    Returns
    -------
    tuple of ndarray
        Counter-clockwise triangles (m, 3), and the hidden points
        (ascending), whose power cells are empty.
    """
    p = _points(points, "points")
    triangles, hidden = _pixgeo.regular_triangulation(p, _values(weights, len(p), "weights"))
    return triangles, np.asarray(hidden, dtype=np.uint32)
