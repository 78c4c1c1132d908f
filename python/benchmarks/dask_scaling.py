"""pixgeo.dask.voronoi on a LocalCluster of 1 and then 2 worker processes (one
thread each), in one run: the time to compute every block of a SIDE² label
raster (summed, so nothing large comes back), and each worker's peak resident
memory. With --zarr PATH it then writes the labels to a Zarr store instead.

    .venv/bin/python python/benchmarks/dask_scaling.py [--side 16384] [--n 10000] \
        [--chunk 4096] [--workers 1,2] [--zarr /tmp/labels.zarr]
"""

import argparse
import resource
import time

import numpy as np
from distributed import Client, LocalCluster

import pixgeo.dask


def peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--side", type=int, default=16384)
    ap.add_argument("--n", type=int, default=10000)
    ap.add_argument("--chunk", type=int, default=4096)
    ap.add_argument("--workers", default="1,2")
    ap.add_argument("--zarr")
    args = ap.parse_args()
    sites = np.random.default_rng(1).uniform(0, 1000, (args.n, 2))
    shape = (args.side, args.side)
    print("| workers | side | n | chunk | seconds | speed-up | peak RSS per worker (MB) |")
    print("|---|---|---|---|---|---|---|")
    first = None
    for workers in (int(w) for w in args.workers.split(",")):
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster, Client(cluster) as client:
            client.run(lambda: pixgeo.voronoi(sites[:10], (8, 8)))  # make each device
            d = pixgeo.dask.voronoi(
                sites, shape, chunks=(args.chunk, args.chunk), bbox=(0, 0, 1000, 1000)
            )
            t = time.perf_counter()
            if args.zarr:
                d.labels.to_zarr(args.zarr, overwrite=True)
            else:
                d.labels.sum(dtype=np.uint64).compute()
            seconds = time.perf_counter() - t
            first = first or seconds
            peaks = sorted(client.run(peak_rss_mb).values())
            print(
                f"| {workers} | {args.side}² | {args.n} | {args.chunk}² | {seconds:.1f} "
                f"| {first / seconds:.2f}× | {', '.join(f'{p:.0f}' for p in peaks)} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
