#!/usr/bin/env python3
"""Times the peer a Python user would pick for the Hausdorff distance:
scipy.spatial.distance.directed_hausdorff, both directions.

Usage: peer_hausdorff.py REPEATS A.npy B.npy [A.npy B.npy ...]
Prints one JSON object {"<A file>": [milliseconds (median), distance]}."""

import json
import sys
import time

import numpy as np
from scipy.spatial.distance import directed_hausdorff


def main():
    repeats = int(sys.argv[1])
    files = sys.argv[2:]
    out = {}
    for a_path, b_path in zip(files[::2], files[1::2]):
        a, b = np.load(a_path), np.load(b_path)
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            h = max(directed_hausdorff(a, b)[0], directed_hausdorff(b, a)[0])
            times.append((time.perf_counter() - start) * 1e3)
        times.sort()
        out[a_path] = [times[len(times) // 2], h]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
