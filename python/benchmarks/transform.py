"""pixgeo.distance_transform_edt beside SciPy's distance_transform_edt and
OpenCV's distanceTransformWithLabels, in one run, each with the nearest zero
element (indices or labels): a random raster with 1 % zeros at each side.
Also reports whether pixgeo's distances equal SciPy's and OpenCV's largest
difference from them. A second table times the distances alone, pixgeo's
beside the `edt` package's (float32, parallel=2), with edt's largest
difference from pixgeo's.

    .venv/bin/python python/benchmarks/transform.py [--sides 1024,4096,16384] [--repeats 3]

Prints a Markdown table; median of --repeats runs (one run at 16384²).
"""

import argparse
import gc
import statistics
import time

import numpy as np
from scipy import ndimage

import pixgeo

try:
    import cv2
except ImportError:  # the peer is optional
    cv2 = None

try:
    import edt
except ImportError:  # the peer is optional (tools/setup --bench)
    edt = None


def timed(repeats, f):
    times, out = [], None
    for _ in range(repeats):
        out = None
        gc.collect()
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return statistics.median(times) * 1e3, out


def opencv(input):
    src = np.where(input != 0, 255, 0).astype(np.uint8)
    return cv2.distanceTransformWithLabels(
        src, cv2.DIST_L2, cv2.DIST_MASK_PRECISE, labelType=cv2.DIST_LABEL_PIXEL
    )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sides", default="1024,4096,16384")
    ap.add_argument("--zeros", type=float, default=0.01)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    print("| side | pixgeo (ms) | SciPy (ms) | OpenCV (ms) | SciPy / pixgeo | OpenCV / pixgeo "
          "| distances equal SciPy's | OpenCV's largest difference |")
    print("|---|---|---|---|---|---|---|---|")
    for side in (int(s) for s in args.sides.split(",")):
        input = rng.random((side, side)) >= args.zeros
        repeats = 1 if side > 8192 else args.repeats
        t_pixgeo, (d, _) = timed(
            repeats, lambda: pixgeo.distance_transform_edt(input, return_indices=True)
        )
        t_scipy, (expected, _) = timed(
            repeats, lambda: ndimage.distance_transform_edt(input, return_indices=True)
        )
        equal = "yes" if np.array_equal(d, expected) else "NO"
        del expected
        if cv2 is not None:
            t_cv, (cv_d, _) = timed(repeats, lambda: opencv(input))
            cv_cells = f"{t_cv:.0f} | " 
            ratio = f"{t_cv / t_pixgeo:.2f}×"
            worst = f"{np.max(np.abs(cv_d - d)):.2e}"
            del cv_d
        else:
            cv_cells, ratio, worst = "– | ", "–", "–"
        print(f"| {side}² | {t_pixgeo:.0f} | {t_scipy:.0f} | {cv_cells}"
              f"{t_scipy / t_pixgeo:.2f}× | {ratio} | {equal} | {worst} |", flush=True)
        del d
    if edt is None:
        return
    print("\n| side | pixgeo distances (ms) | edt, 2 threads (ms) | edt / pixgeo | edt's largest difference |")
    print("|---|---|---|---|---|")
    for side in (int(s) for s in args.sides.split(",")):
        input = rng.random((side, side)) >= args.zeros
        repeats = 1 if side > 8192 else args.repeats
        t_pixgeo, d = timed(repeats, lambda: pixgeo.distance_transform_edt(input))
        t_edt, e = timed(repeats, lambda: edt.edt(input, parallel=2))
        worst = float(np.max(np.abs(e.astype(np.float64) - d)))
        print(f"| {side}² | {t_pixgeo:.0f} | {t_edt:.0f} | {t_edt / t_pixgeo:.2f}× | {worst:.2e} |",
              flush=True)
        del d, e


if __name__ == "__main__":
    main()
