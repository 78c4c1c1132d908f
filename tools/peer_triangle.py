#!/usr/bin/env python3
"""Times Shewchuk's Triangle (PyPI `triangle`) on point sets, as a Python user
would call it: triangle.triangulate({"vertices": points}).

Usage: peer_triangle.py REPEATS POINTS.npy [POINTS.npy ...]
Prints one JSON object {"<file>": [milliseconds (median of REPEATS), triangles]}."""

import json
import sys
import time

import numpy as np
import triangle


def main():
    repeats = int(sys.argv[1])
    out = {}
    for path in sys.argv[2:]:
        points = np.load(path)
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            mesh = triangle.triangulate({"vertices": points})
            times.append((time.perf_counter() - start) * 1e3)
        times.sort()
        out[path] = [times[len(times) // 2], int(len(mesh["triangles"]))]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
