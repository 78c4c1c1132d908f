"""pixgeo's natural-neighbour interpolation beside MetPy's, as one picture:
the same samples (examples/data/heights.csv) onto the same 200² grid of
pixel centres, pixgeo's exact method left, MetPy's natural_neighbor_to_points
middle, and their difference right (white where both agree to 1e-12, red
where they differ, grey where neither has a value). Prints the largest
difference and both times.

    .venv/bin/python python/benchmarks/beside_metpy.py [docs/natural_neighbor_metpy.png]
"""

import sys
import time
from pathlib import Path

import numpy as np
from metpy.interpolate import natural_neighbor_to_points
from PIL import Image

import pixgeo

STOPS = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], float)


def ramp(v, lo, hi):
    """pixgeo interpolate's colours: dark blue (low) to yellow (high), white
    where no value."""
    t = np.clip((v - lo) / (hi - lo), 0, 1) * (len(STOPS) - 1)
    k = np.minimum(np.floor(np.nan_to_num(t)).astype(int), len(STOPS) - 2)
    f = (np.nan_to_num(t) - k)[..., None]
    rgb = STOPS[k] + (STOPS[k + 1] - STOPS[k]) * f
    rgb[np.isnan(v)] = 255
    return rgb.round().astype(np.uint8)


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "natural_neighbor_metpy.png")
    data = np.loadtxt(Path(__file__).parents[2] / "examples/data/heights.csv", delimiter=",", skiprows=1)
    points, values = data[:, :2], data[:, 2]
    side, box = 200, (0.0, 0.0, 100.0, 100.0)
    x, y = pixgeo.frame((side, side), bbox=box).pixel_centres()
    grid = np.stack([c.ravel() for c in np.meshgrid(x, y)], 1)
    t = time.perf_counter()
    ours = pixgeo.natural_neighbor(points, values, xi=grid).reshape(side, side)
    ours_ms = (time.perf_counter() - t) * 1e3
    t = time.perf_counter()
    theirs = natural_neighbor_to_points(points, values, grid).reshape(side, side)
    theirs_ms = (time.perf_counter() - t) * 1e3
    both = ~(np.isnan(ours) | np.isnan(theirs))
    gap = np.abs(ours - theirs)
    lo, hi = np.nanmin(ours), np.nanmax(ours)
    differ = np.full((side, side, 3), 255, np.uint8)
    differ[~both] = 200
    differ[both & (gap > 1e-12)] = [220, 30, 30]
    differ[np.isnan(ours) != np.isnan(theirs)] = [220, 30, 30]
    gutter = np.full((side, 8, 3), 255, np.uint8)
    picture = np.concatenate([ramp(ours, lo, hi), gutter, ramp(theirs, lo, hi), gutter, differ], 1)
    Image.fromarray(picture).save(out)
    print(f"{out}: largest difference {gap[both].max():.1e}; values where only one has one: "
          f"{int(np.sum(np.isnan(ours) != np.isnan(theirs)))}; pixgeo {ours_ms:.0f} ms, "
          f"MetPy {theirs_ms:.0f} ms ({side}² points, {len(points)} samples)")


if __name__ == "__main__":
    main()
