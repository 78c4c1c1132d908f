"""pixgeo.distance_transform_edt beside SciPy's distance_transform_edt and
OpenCV's distanceTransformWithLabels, in one run, each with the nearest zero
element (indices or labels): a random raster with 1 % zeros at each side.
Also reports whether pixgeo's distances equal SciPy's and OpenCV's largest
difference from them. A second table times the distances alone, pixgeo's
beside the `edt` package's (float32, parallel=2), with edt's largest
difference from pixgeo's, and with --memory each call's peak memory in a
fresh process.

    .venv/bin/python python/benchmarks/transform.py [--sides 1024,4096,16384] [--repeats 3] [--memory]

Prints a Markdown table; median of --repeats runs (one run at 16384²).
"""

import argparse
import gc
import statistics
import time

import numpy as np
from scipy import ndimage

import pixgeo
from peers import peak_mib

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
    ap.add_argument("--memory", action="store_true")
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
    memory = "| pixgeo peak (MiB) | edt peak (MiB) " if args.memory else ""
    print(f"\n| side | pixgeo distances (ms) | edt, 2 threads (ms) | edt / pixgeo {memory}"
          "| edt's largest difference |")
    print("|---|---|---|---|" + "---|" * (3 if args.memory else 1))
    for side in (int(s) for s in args.sides.split(",")):
        input = rng.random((side, side)) >= args.zeros
        repeats = 1 if side > 8192 else args.repeats
        t_pixgeo, t_edt = [], []
        for _ in range(repeats):
            t_pixgeo.append(timed(1, lambda: pixgeo.distance_transform_edt(input))[0])
            t_edt.append(timed(1, lambda: edt.edt(input, parallel=2))[0])
        t_pixgeo, t_edt = statistics.median(t_pixgeo), statistics.median(t_edt)
        d, e = pixgeo.distance_transform_edt(input), edt.edt(input, parallel=2)
        worst = float(np.max(np.abs(e.astype(np.float64) - d)))
        del d, e
        peaks = ""
        if args.memory:
            setup = (f"import edt\ninput = np.random.default_rng(1).random(({side}, {side})) "
                     f">= {args.zeros}\nsmall = input[:64, :64].copy()")
            warm = "pixgeo.distance_transform_edt(small); edt.edt(small, parallel=2)"
            mine = peak_mib(setup, warm, "d = pixgeo.distance_transform_edt(input)")
            theirs = peak_mib(setup, warm, "d = edt.edt(input, parallel=2)")
            peaks = f"| {mine:.0f} | {theirs:.0f} "
        print(f"| {side}² | {t_pixgeo:.0f} | {t_edt:.0f} | {t_edt / t_pixgeo:.2f}× {peaks}"
              f"| {worst:.2e} |", flush=True)


if __name__ == "__main__":
    main()
