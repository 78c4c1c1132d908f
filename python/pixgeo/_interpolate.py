"""Scattered values onto rasters or points: natural-neighbour (Sibson)
interpolation, exact or rendered, and the linear and nearest-site
interpolants: :func:`pixgeo.natural_neighbor`."""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from . import _docs, _crs, _pixgeo, _place, _points, _unmasked, _warn_planar

METHODS = ("exact", "discrete", "linear", "nearest")


def _values(values, n: int, name: str = "values") -> np.ndarray:
    """``values`` as n finite float64s; ValueError otherwise."""
    v = np.asarray(_unmasked(values, name))
    if v.dtype.kind not in "fiu":
        raise ValueError(f"{name} must be real numbers, not dtype {v.dtype}")
    if v.shape != (n,):
        raise ValueError(f"{name} has shape {v.shape}: give one value per point, ({n},)")
    if not np.all(np.isfinite(v)):
        bad = int(np.argmin(np.isfinite(v)))
        raise ValueError(f"{name}[{bad}] is not finite: {name} are finite")
    return np.ascontiguousarray(v, dtype=np.float64)


@_docs.fill
def natural_neighbor(
    points,
    values,
    shape: Optional[Sequence[int]] = None,
    *,
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    xi=None,
    method: str = "exact",
    fill_value: float = np.nan,
    device: Optional[str] = None,
) -> np.ndarray:
    """``values`` at ``points`` interpolated at every pixel centre of the
    picture, or at the points ``xi``.

    Outside the points' convex hull the methods but ``"nearest"`` give
    ``fill_value``, as MetPy's ``natural_neighbor_to_grid`` and SciPy's
    ``griddata`` do.

    Parameters
    ----------
    {points}
    values : array_like, shape (n,)
        One finite value a point.
    {placement}
    xi : array_like or tuple of array_like, optional
        Any of SciPy ``griddata``'s forms: ``(m, 2)`` (or ``(..., 2)``)
        coordinates, or a tuple of coordinate arrays ``(gx, gy)``
        (``np.meshgrid``'s), instead of the picture.
    method : {"exact", "discrete", "linear", "nearest"}, optional
        ``"exact"``: Sibson's interpolant from the exact Delaunay
        triangulation, each value the double nearest the exact one;
        ``"discrete"``: the rendered discrete Sibson interpolant (rasters
        only); ``"linear"``: barycentric in the exact Delaunay triangle,
        correctly rounded; ``"nearest"``: the nearest point's value
        (rasters only).
    fill_value : float, optional
        Outside the convex hull (default NaN).
    {device}

    Returns
    -------
    ndarray of float64
        The picture's shape, rows as pixgeo's rasters; or shaped as ``xi``.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: use {', '.join(METHODS)}")
    _warn_planar(_crs(crs), "the natural neighbours' areas and the triangles are taken")
    p = _points(points, "points")
    v = _values(values, len(p))
    if xi is not None:
        if shape is not None or bbox is not None or res is not None:
            raise ValueError("give xi= (points) or a picture (shape=, bbox=, res=), not both")
        if method not in ("exact", "linear"):
            raise ValueError(f"the {method} method interpolates onto rasters; at points use exact or linear")
        q, answer_shape = _queries(xi)
        out = _pixgeo.interpolate_at(p, v, _points(q, "xi"), method, device).reshape(answer_shape)
    else:
        place = _place(shape, bbox, res, y_axis, crs)
        out = _pixgeo.interpolate(
            place.sites(p), v, place.width, place.height, place.bbox, method, device
        )
    if not np.isnan(fill_value):
        out[np.isnan(out)] = fill_value
    return out


def _queries(xi) -> tuple:
    """``xi`` in griddata's forms as (m, 2) points, and the answer's shape."""
    if isinstance(xi, tuple):
        if len(xi) != 2:
            raise ValueError(f"xi as a tuple holds the x and the y arrays, not {len(xi)} arrays")
        try:
            gx, gy = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in xi))
        except ValueError as e:
            raise ValueError(f"xi's x and y arrays do not match: {e}") from None
        return np.stack([gx, gy], axis=-1).reshape(-1, 2), gx.shape
    q = np.asarray(xi)
    if q.shape[-1:] != (2,):
        raise ValueError(f"xi must have shape (..., 2) or be a tuple (x, y), not shape {q.shape}")
    return q.reshape(-1, 2), q.shape[:-1]
