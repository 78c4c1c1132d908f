"""Voronoi rasters larger than one machine, as Dask arrays.

Each block is a window of the diagram computed on a worker: the sites travel
once (one task of the graph that every block depends on) and pixgeo culls them
per window to the cones that reach it. Windows are bit for bit the whole
diagram's pixels, so the result equals :func:`pixgeo.voronoi` pixel for pixel
however it is chunked. Install with ``pip install 'pixgeo[dask]'``.

The same code runs on any Dask cluster (``LocalCluster``, dask-jobqueue,
Kubernetes): each worker process makes its own device on first use, a GPU where
the worker has one (``PIXGEO_DEVICE=gpu`` in the worker's environment, one
worker per GPU), lavapipe otherwise (then one worker per core, with
``LP_NUM_THREADS=1``).
"""

from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np

try:
    import dask
    import dask.array as da
except ImportError as e:  # pragma: no cover - the extra is missing
    raise ImportError("pixgeo.dask needs Dask: pip install 'pixgeo[dask]'") from e

from fractions import Fraction

from . import Diagram, Lloyd, _pixgeo, _place, _planar, _points, _warn_planar
from ._interpolate import METHODS, _values
from .lloyd import _iterations

__all__ = ["voronoi", "lloyd", "natural_neighbor", "power_diagram"]


def _chunks(chunks) -> Tuple[int, int]:
    """``chunks`` checked: (rows, columns), each at least 1."""
    try:
        rows, cols = (int(c) for c in chunks)
    except (TypeError, ValueError):
        raise ValueError(f"chunks must be (rows, columns), not {chunks!r}") from None
    if rows < 1 or cols < 1:
        raise ValueError(f"chunks {chunks!r}: blocks need at least one row and column")
    return rows, cols


def _block(
    sites: np.ndarray,
    width: int,
    height: int,
    bbox,
    metric: str,
    mode: str,
    device: Optional[str],
    block_info=None,
) -> np.ndarray:
    """One window: labels in the low 32 bits, the distance's float32 bits in
    the high ones, so that both rasters come from one task."""
    (y0, y1), (x0, x1) = block_info[None]["array-location"]
    # The sites arrive unpickled from a buffer, perhaps unaligned.
    labels, distances, _ = _pixgeo.voronoi(
        _points(sites, "sites"), width, height, bbox, metric, mode, device, (x0, y0, x1 - x0, y1 - y0)
    )
    return labels.astype(np.uint64) | (distances.view(np.uint32).astype(np.uint64) << 32)


def voronoi(
    sites,
    shape: Optional[Sequence[int]] = None,
    *,
    chunks: Tuple[int, int] = (4096, 4096),
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    metric: Optional[str] = None,
    mode: str = "exact",
    device: Optional[str] = None,
) -> Diagram:
    """:func:`pixgeo.voronoi` as Dask arrays: ``labels`` (uint32) and
    ``distances`` (float32) of ``shape``, in blocks of ``chunks`` rows and
    columns, each computed as a window on a worker when the arrays are. Exact
    mode only (a window is the whole diagram's pixels bit for bit only there).

    ``result.labels.to_zarr(store)`` streams a raster larger than any one
    machine's memory; computing ``labels`` and ``distances`` together
    (``dask.compute``) draws each block once. ``bbox``, ``res``, ``y_axis``
    and ``crs`` place the rasters as :func:`pixgeo.voronoi` does: the frame's
    ``transform`` and ``crs`` georeference every block.
    """
    if mode != "exact":
        raise ValueError(
            "pixgeo.dask.voronoi takes exact mode: a fan's depths round by where its "
            "tile lies, so fan blocks would not match the whole diagram"
        )
    place = _place(shape, bbox, res, y_axis, crs)
    metric = _planar(metric, place.crs, "pixgeo.dask.voronoi")
    h, w, box = place.height, place.width, place.bbox
    points = place.sites(_points(sites, "sites"))
    frame = place.frame(_pixgeo.frame_of(w, h, box))
    # Check the sites and options once, here, on a one-pixel window.
    _pixgeo.voronoi(points, w, h, box, metric, mode, device, (0, 0, 1, 1))
    rows, cols = _chunks(chunks)
    shared = dask.delayed(points, pure=True)
    packed = da.map_blocks(
        _block,
        shared,
        w,
        h,
        box,
        metric,
        mode,
        device,
        chunks=da.core.normalize_chunks((rows, cols), (h, w)),
        dtype=np.uint64,
        meta=np.empty((0, 0), dtype=np.uint64),
    )
    labels = (packed & np.uint64(0xFFFFFFFF)).astype(np.uint32)
    distances = (packed >> np.uint64(32)).astype(np.uint32).view(np.float32)
    return Diagram(labels, distances, frame)


def _window_sums(sites, width, height, frame, bbox, window, q, device):
    """One block's share of Lloyd's sums: per site Σq, Σq(2i + 1) and
    Σq(2j + 1) over the block's pixels nearest to it, as Python integers,
    and the block's energy Σq · squared distance, as a double."""
    x0, y0, w, h = window
    # The sites arrive unpickled from a buffer, perhaps unaligned.
    sites = _points(sites, "sites")
    labels, _, _ = _pixgeo.voronoi(sites, width, height, bbox, "l2", "exact", device, window)
    labels = labels.ravel().astype(np.int64)
    jj, ii = (a.ravel() for a in np.mgrid[y0 : y0 + h, x0 : x0 + w])
    q = np.ones(w * h, dtype=np.int64) if q is None else np.asarray(q, dtype=np.int64).ravel()
    _, _, ox, oy, scale = frame
    px, py = ox + (ii + 0.5) / scale, oy + (jj + 0.5) / scale
    energy = float(np.sum(q * ((px - sites[labels, 0]) ** 2 + (py - sites[labels, 1]) ** 2)))
    order = np.argsort(labels, kind="stable")
    keys = labels[order]
    starts = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    q = q[order]
    sums = [np.add.reduceat(v, starts) for v in (q, q * (2 * ii[order] + 1), q * (2 * jj[order] + 1))]
    return {int(k): tuple(int(s[n]) for s in sums) for n, k in enumerate(keys[starts])}, energy


def lloyd(
    sites,
    shape: Optional[Sequence[int]] = None,
    *,
    chunks: Tuple[int, int] = (4096, 4096),
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    iterations: int = 50,
    tolerance: Optional[float] = None,
    density=None,
    device: Optional[str] = None,
) -> Lloyd:
    """:func:`pixgeo.lloyd` on a picture larger than one machine: each
    iteration draws every block of ``chunks`` as a window on a worker (the
    whole diagram's pixels, bit for bit) with its share of the region sums,
    and the sums meet on the client as whole numbers, so the sites are the
    same doubles as :func:`pixgeo.lloyd`'s. ``density`` (a NumPy or Dask
    array of the picture's shape) takes whole numbers from 0 to 65535 here,
    which keep a block's sums exact in 64 bits (blocks too large for that
    are refused). ``labels`` is a Dask array of
    the final sites' diagram; the energies are summed block by block, so they
    may differ from :func:`pixgeo.lloyd`'s in the last bits."""
    place = _place(shape, bbox, res, y_axis, crs)
    _warn_planar(place.crs, "Lloyd's centroids are taken")
    h, w, box = place.height, place.width, place.bbox
    points = place.sites(_points(sites, "sites"))
    frame = _pixgeo.frame_of(w, h, box)
    iterations = _iterations(iterations)
    rows, cols = _chunks(chunks)
    if 65535 * 2 * max(w, h) * min(rows, h) * min(cols, w) >= 1 << 63:
        raise ValueError(f"chunks {chunks!r}: blocks this large could overflow the sums; use smaller ones")
    if density is not None:
        density = da.asarray(density)
        if density.shape != (h, w):
            raise ValueError(f"density has shape {density.shape}, the picture {(h, w)}")
        low, high, whole = dask.compute(density.min(), density.max(),
                                        da.all(density == da.floor(density)))
        if not (whole and 0 <= low and 0 < high <= 65535):
            raise ValueError(
                "pixgeo.dask.lloyd takes densities of whole numbers from 0 to 65535, not all "
                "zero; pixgeo.lloyd takes any"
            )
    _, _, ox, oy, scale = frame
    tolerance = 0.01 / scale if tolerance is None else float(tolerance)
    if not tolerance >= 0:
        raise ValueError(f"the tolerance is a distance of 0 or more, not {tolerance}")
    windows = [(x0, y0, min(cols, w - x0), min(rows, h - y0))
               for y0 in range(0, h, rows) for x0 in range(0, w, cols)]

    def sums(at):
        """Every site's sums and the energy, the blocks computed by Dask."""
        shared = dask.delayed(at, pure=True)
        parts = [dask.delayed(_window_sums)(
            shared, w, h, frame, box, (x0, y0, ww, hh),
            None if density is None else density[y0 : y0 + hh, x0 : x0 + ww], device)
            for x0, y0, ww, hh in windows]
        totals, energy = {}, 0.0
        for part, e in dask.compute(*parts):
            energy += e
            for site, s in part.items():
                t = totals.get(site, (0, 0, 0))
                totals[site] = (t[0] + s[0], t[1] + s[1], t[2] + s[2])
        return totals, energy

    current = points.copy()
    energies, moves, converged = [], [], False
    for _ in range(iterations):
        totals, energy = sums(current)
        moved = current.copy()
        for site, (weight, sx, sy) in totals.items():
            if weight:
                unit = 2 * weight * Fraction(scale)
                moved[site] = (float(Fraction(ox) + sx / unit), float(Fraction(oy) + sy / unit))
        energies.append(energy)
        step = moved - current
        # As pixgeo.lloyd measures a move: the root of the sum of squares.
        moves.append(float(np.max(np.sqrt(step[:, 0] * step[:, 0] + step[:, 1] * step[:, 1]))))
        current = moved
        if moves[-1] <= tolerance:
            converged = True
            break
    totals, final_energy = sums(current)
    idle = len(current) - sum(1 for t in totals.values() if t[0] > 0)
    final = voronoi(place.sites(current), shape, chunks=chunks, bbox=bbox, res=res,
                    y_axis=y_axis, crs=crs, device=device)
    return Lloyd(place.sites(current), final.labels, final.frame, np.array(energies),
                 np.array(moves), final_energy, converged, idle)


def _interpolated_block(points, values, width, height, bbox, method, device, block_info=None):
    """One window of the interpolated raster."""
    (y0, y1), (x0, x1) = block_info[None]["array-location"]
    # The arrays arrive unpickled from a buffer, perhaps unaligned.
    return _pixgeo.interpolate(
        _points(points, "points"), np.require(values, requirements=["C_CONTIGUOUS", "ALIGNED"]),
        width, height, bbox, method, device, (x0, y0, x1 - x0, y1 - y0),
    )


def natural_neighbor(
    points,
    values,
    shape: Optional[Sequence[int]] = None,
    *,
    chunks: Tuple[int, int] = (4096, 4096),
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
    method: str = "exact",
    device: Optional[str] = None,
):
    """:func:`pixgeo.natural_neighbor` onto a raster as a Dask array of
    ``shape``, in blocks of ``chunks`` rows and columns, each interpolated
    as a window on a worker (which triangulates the points itself): the same
    values bit for bit however it is chunked. The exact, linear and nearest
    methods (the discrete one's values depend on the pixels drawn around
    them)."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: use {', '.join(METHODS)}")
    if method == "discrete":
        raise ValueError(
            "pixgeo.dask.natural_neighbor takes the exact, linear and nearest methods: a "
            "discrete value depends on the pixels drawn around it, so blocks would not tile"
        )
    place = _place(shape, bbox, res, y_axis, crs)
    _warn_planar(place.crs, "the natural neighbours' areas and the triangles are taken")
    h, w, box = place.height, place.width, place.bbox
    p = place.sites(_points(points, "points"))
    v = _values(values, len(p))
    # Check the points and values once, here, on a one-pixel window.
    _pixgeo.interpolate(p, v, w, h, box, method, device, (0, 0, 1, 1))
    rows, cols = _chunks(chunks)
    return da.map_blocks(
        _interpolated_block,
        dask.delayed(p, pure=True),
        dask.delayed(v, pure=True),
        w,
        h,
        box,
        method,
        device,
        chunks=da.core.normalize_chunks((rows, cols), (h, w)),
        dtype=np.float64,
        meta=np.empty((0, 0), dtype=np.float64),
    )


def _power_block(points, weights, width, height, bbox, which, block_info=None):
    """One window of a power diagram's labels (``which == 0``), powers (1)
    or ties (2)."""
    (y0, y1), (x0, x1) = block_info[None]["array-location"]
    # The arrays arrive unpickled from a buffer, perhaps unaligned.
    return _pixgeo.power_diagram(
        _points(points, "points"), np.require(weights, requirements=["C_CONTIGUOUS", "ALIGNED"]),
        width, height, bbox, (x0, y0, x1 - x0, y1 - y0),
    )[which]


def power_diagram(
    points,
    weights,
    shape: Optional[Sequence[int]] = None,
    *,
    chunks: Tuple[int, int] = (4096, 4096),
    bbox=None,
    res: Optional[float] = None,
    y_axis: Optional[str] = None,
    crs=None,
):
    """:func:`pixgeo.power_diagram` as Dask arrays ``(labels, powers, ties)`` of
    ``shape``, in blocks of ``chunks``, each a window computed on a worker
    (which builds the regular triangulation itself): the same values bit for
    bit however it is chunked."""
    place = _place(shape, bbox, res, y_axis, crs)
    _warn_planar(place.crs, "powers are measured")
    h, w, box = place.height, place.width, place.bbox
    p = place.sites(_points(points, "points"))
    v = _values(weights, len(p), "weights")
    # Check the points and weights once, here, on a one-pixel window.
    _pixgeo.power_diagram(p, v, w, h, box, (0, 0, 1, 1))
    rows, cols = _chunks(chunks)
    shared = (dask.delayed(p, pure=True), dask.delayed(v, pure=True))
    blocks = da.core.normalize_chunks((rows, cols), (h, w))
    return tuple(
        da.map_blocks(_power_block, *shared, w, h, box, which, chunks=blocks, dtype=dtype,
                      meta=np.empty((0, 0), dtype=dtype))
        for which, dtype in ((0, np.uint32), (1, np.float64), (2, np.uint32))
    )
