"""Centroidal Voronoi tessellations by Lloyd's iterations (and stippling, with
a density): :func:`pixgeo.lloyd`."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from . import _docs, Frame, _pixgeo, _place, _points, _warn_planar


@dataclass(frozen=True)
class Lloyd:
    """Where Lloyd's iterations leave the sites (``points``, ``(n, 2)`` in
    input order), every pixel's nearest of them (``labels``), and per
    iteration the energy before its move (Σ density · squared distance to
    the nearest site) and the largest move; ``idle`` counts the sites whose
    region holds no weight (they stay put)."""

    points: np.ndarray
    labels: np.ndarray
    frame: Frame
    energy: np.ndarray
    largest_move: np.ndarray
    final_energy: float
    converged: bool
    idle: int


def _iterations(iterations) -> int:
    """``iterations`` checked: a whole number of 0 or more."""
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) or iterations < 0:
        raise ValueError(f"iterations is a whole number of 0 or more, not {iterations!r}")
    return int(iterations)


@_docs.fill
def lloyd(
    sites,
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    iterations: int = 50,
    tolerance: Optional[float] = None,
    density=None,
    device: Optional[str] = None,
) -> Lloyd:
    """Lloyd's iterations from ``sites`` on the picture.

    Each iteration takes the exact Voronoi diagram, sums every region's
    pixels (weighted by ``density``) and moves each site to its region's
    centroid, exact for the digital region (whole-number sums, rounded
    once). ``device="cpu"`` runs the CPU pixel algorithms, to the same
    answer.

    Parameters
    ----------
    sites : array_like, shape (n, 2)
        The starting sites.
    {placement}
    iterations : int, optional
        At most this many.
    tolerance : float, optional
        Stop once no site moves farther (world units; default a hundredth
        of a pixel).
    density : array_like, optional
        The picture's shape, finite and not negative, rows as the rasters'
        (uniform without one).
    {device}

    Returns
    -------
    Lloyd
        The moved ``points``, their ``labels``, the ``energy`` and
        ``largest_move`` of each iteration, and whether it ``converged``.
    """
    place = _place(shape, bbox, res, y_axis, crs)
    _warn_planar(place.crs, "Lloyd's centroids are taken")
    if place.crs is not None and _pixgeo.is_geographic(int(place.crs[5:])):
        warnings.warn(
            f"{place.crs} is geographic: Lloyd's centroids are taken on the longitude-latitude "
            "plane, in degrees",
            stacklevel=2,
        )
    iterations = _iterations(iterations)
    if density is not None:
        density = np.ascontiguousarray(density, dtype=np.float64)
    points, labels, frame, steps, final, converged, idle = _pixgeo.lloyd(
        place.sites(_points(sites, "sites")),
        place.width,
        place.height,
        place.bbox,
        iterations,
        None if tolerance is None else float(tolerance),
        density,
        device,
    )
    steps = np.asarray(steps, dtype=np.float64).reshape(-1, 2)
    return Lloyd(
        place.sites(points),
        labels,
        place.frame(frame),
        steps[:, 0].copy(),
        steps[:, 1].copy(),
        final,
        converged,
        idle,
    )
