"""Voronoi rasters larger than one machine, as Dask arrays.

Each block is a window of the diagram computed on a worker: the sites travel
once (one task of the graph that every block depends on) and pixgeo culls them
per window to the cones that reach it. Windows are bit for bit the whole
diagram's pixels, so the result equals :func:`pixgeo.voronoi` pixel for pixel
however it is chunked. Install with ``pip install ./python[dask]``.

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
    raise ImportError("pixgeo.dask needs Dask: pip install ./python[dask]") from e

from . import Diagram, _pixgeo, _place, _planar, _points

__all__ = ["voronoi"]


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
    try:
        rows, cols = (int(c) for c in chunks)
    except (TypeError, ValueError):
        raise ValueError(f"chunks must be (rows, columns), not {chunks!r}") from None
    if rows < 1 or cols < 1:
        raise ValueError(f"chunks {chunks!r}: blocks need at least one row and column")
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
