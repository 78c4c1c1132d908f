#!/usr/bin/env python3
"""Times the peer a Python user would pick for a digital Voronoi label map:
scipy.ndimage.distance_transform_edt(return_indices=True) on a grid with the
sites marked, then a lookup of the site id at the nearest marked pixel.

Usage: peer_edt.py SIZE REPEATS SITES.npy [SITES.npy ...]
Prints one JSON object {"<file>": milliseconds (median of REPEATS)}.
Sites are rounded to pixel centres: the EDT only knows the grid."""

import json
import sys
import time

import numpy as np
from scipy import ndimage


def label_map(sites, size):
    ids = np.full((size, size), -1, dtype=np.int64)
    ij = np.clip(np.rint(sites).astype(np.int64), 0, size - 1)
    # Later sites overwrite earlier ones in the same pixel, like the lowest cone.
    ids[ij[:, 1], ij[:, 0]] = np.arange(len(sites))
    start = time.perf_counter()
    rows, cols = ndimage.distance_transform_edt(
        ids < 0, return_distances=False, return_indices=True
    )
    labels = ids[rows, cols]
    return labels, (time.perf_counter() - start) * 1e3


def main():
    size, repeats = int(sys.argv[1]), int(sys.argv[2])
    out = {}
    for path in sys.argv[3:]:
        sites = np.load(path)
        times = sorted(label_map(sites, size)[1] for _ in range(repeats))
        out[path] = times[len(times) // 2]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
