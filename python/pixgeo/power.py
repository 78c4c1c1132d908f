"""Power (Laguerre) diagrams and regular triangulations:
:func:`pixgeo.power_diagram` and :func:`pixgeo.regular_triangulation`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import numpy as np

from . import Frame, _pixgeo, _place, _points
from .interpolate import _values


@dataclass(frozen=True)
class PowerDiagram:
    """Each pixel's site of least power ``|p - s|² - w`` (``labels``, ties to
    the lower index), that power (``powers``, the double nearest the exact
    one), and the sites whose cells are empty (``hidden``, ascending)."""

    labels: np.ndarray
    powers: np.ndarray
    hidden: np.ndarray
    frame: Frame


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
    """The power diagram of ``points`` (n, 2) with power ``weights`` (n,) on
    the picture, exact: on the CPU, by a walk over the regular
    triangulation."""
    place = _place(shape, bbox, res, y_axis, crs)
    p = _points(points, "points")
    labels, powers, hidden = _pixgeo.power_diagram(
        place.sites(p), _values(weights, len(p), "weights"), place.width, place.height, place.bbox
    )
    frame = place.frame(_pixgeo.frame_of(place.width, place.height, place.bbox))
    return PowerDiagram(labels, powers, np.asarray(hidden, dtype=np.uint32), frame)


def regular_triangulation(points, weights) -> Tuple[np.ndarray, np.ndarray]:
    """The regular (weighted Delaunay) triangulation of ``points`` with power
    ``weights``, exact: counter-clockwise triangles (m, 3) and the hidden
    points (ascending), whose power cells are empty."""
    p = _points(points, "points")
    triangles, hidden = _pixgeo.regular_triangulation(p, _values(weights, len(p), "weights"))
    return triangles, np.asarray(hidden, dtype=np.uint32)
