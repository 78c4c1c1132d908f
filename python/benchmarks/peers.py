"""pixgeo against the tools Python users reach for today, in one run.

Labels: pixgeo.voronoi against scipy.ndimage.distance_transform_edt(
return_indices=True) plus a label lookup, and OpenCV's
distanceTransformWithLabels. Both peers work on sites snapped to pixel
centres; pixgeo on the exact sites. Each row also reports, at 1024², the share
of pixels whose label is a true nearest site (cKDTree on the pixel centres).

Hausdorff: pixgeo.hausdorff (its default method on the device) against
cKDTree queries both ways (2 workers) and SciPy's directed_hausdorff both
ways, on uniform sets and on a uniform set against a clustered one.

    .venv/bin/python python/benchmarks/peers.py [--tasks labels,hausdorff,lloyd,interpolate,power,cells,first]
        [--sides 1024,4096] [--n 1000,10000,100000] [--m 10000,100000]

Lloyd: pixgeo.lloyd against a Lloyd built on SciPy (cKDTree on the pixel
centres with 2 workers, np.bincount for the centroids), per iteration, at the
same resolution, uniform and with a density.

Interpolation: pixgeo.natural_neighbor (exact and linear) against SciPy's
griddata (linear, Qhull) onto the whole picture, and against MetPy's
natural_neighbor_to_points on a 64² subgrid of the pixel centres (MetPy
works point by point in Python; its time is scaled to the picture per pixel),
with the largest difference from MetPy on that subgrid.

Power diagrams: pixgeo.power_cells (exact cells clipped to the box) and
pixgeo.regular_triangulation (the exact dual: triangles and hidden sites)
against pyvoro2's power cells in the box (Voro++: each cell's polygon in
doubles), random weights up to 0.8 of a site's share of the box; the sites
pixgeo hides are compared with those pyvoro2 leaves empty (pyvoro2 also
empties cells that lie outside its box), and each cell's area with
pyvoro2's.

Vector cells: pixgeo.voronoi_cells (exact corners) against shapely's
voronoi_polygons clipped to the box (GEOS), both as shapely polygons, with
their area sums and whether each is a valid coverage.

First call: pixgeo.voronoi (2000 sites at 1024²) in fresh processes, the
first call against the best of five more in the same process, beside SciPy's
distance_transform_edt (indices too) on a 1024² raster with 2000 zeros; the
import is timed apart.

Prints Markdown tables; median of --repeats runs, the tools interleaved.
With --memory, each call's peak memory too: in a fresh process, after a
small call of the same kind, the peak resident set during the call less the
resident set before it.
"""

import argparse
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree

import pixgeo

try:
    import cv2
except ImportError:  # the peer is optional
    cv2 = None


def timed(repeats, f):
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return statistics.median(times) * 1e3, out


def peak_mib(setup, warm, call):
    """The peak memory of one call beyond what its process held before it,
    in MiB: a fresh Python process runs ``setup``, then ``warm`` (a small
    call of the same kind, which loads the libraries and drivers), then
    resets its peak resident set (Linux's clear_refs) and runs ``call``:
    the peak after it less the resident set before it."""
    code = "\n".join([
        "import sys",
        f"sys.path.insert(0, {os.path.dirname(os.path.abspath(__file__))!r})",
        "from peers import *",
        "def status(key):",
        "    line = next(l for l in open('/proc/self/status') if l.startswith(key))",
        "    return int(line.split()[1]) / 1024",
        setup,
        warm,
        "before = status('VmRSS')",
        "open('/proc/self/clear_refs', 'w').write('5')",
        call,
        "print(status('VmHWM') - before)",
    ])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.split()[-1])


FIRST_CALL = """
import time
t0 = time.perf_counter()
import numpy as np
import {module}
t1 = time.perf_counter()
{setup}
times = []
for _ in range(6):
    started = time.perf_counter()
    {call}
    times.append(time.perf_counter() - started)
print(1e3 * (t1 - t0), 1e3 * times[0], 1e3 * min(times[1:]))
"""


def first_calls(repeats):
    """Per tool, the medians over ``repeats`` fresh processes of the import,
    the first call and the best warm call, in ms."""
    tools = {
        "pixgeo.voronoi": dict(
            module="pixgeo",
            setup="sites = np.random.default_rng(1).uniform(0, 1024, (2000, 2))",
            call="pixgeo.voronoi(sites, (1024, 1024))",
        ),
        "scipy distance_transform_edt": dict(
            module="scipy.ndimage",
            setup="img = np.ones((1024, 1024)); "
            "img.flat[np.random.default_rng(1).choice(1 << 20, 2000, replace=False)] = 0",
            call="scipy.ndimage.distance_transform_edt(img, return_indices=True)",
        ),
    }
    rows = {name: [] for name in tools}
    for _ in range(repeats):
        for name, parts in tools.items():
            out = subprocess.run([sys.executable, "-c", FIRST_CALL.format(**parts)],
                                 capture_output=True, text=True, check=True)
            rows[name].append([float(v) for v in out.stdout.split()])
    print("| tool | import (ms) | first call (ms) | warm call (ms) | first / warm |")
    print("|---|---|---|---|---|")
    for name, runs in rows.items():
        imp, first, warm = (statistics.median(r[k] for r in runs) for k in range(3))
        print(f"| {name} | {imp:.0f} | {first:.1f} | {warm:.1f} | {first / warm:.2f}× |")


def seed_image(sites, side):
    """Site k + 1 at its pixel (the last of several sites in one pixel wins)."""
    ij = np.clip(np.floor(sites / 1000.0 * side).astype(int), 0, side - 1)
    img = np.zeros((side, side), dtype=np.int64)
    img[ij[:, 1], ij[:, 0]] = np.arange(1, len(sites) + 1)
    return img


def scipy_labels(sites, side):
    seeds = seed_image(sites, side)
    _, (iy, ix) = ndimage.distance_transform_edt(seeds == 0, return_indices=True)
    return seeds[iy, ix] - 1


def opencv_labels(sites, side):
    seeds = seed_image(sites, side)
    mask = np.where(seeds == 0, 255, 0).astype(np.uint8)
    _, lab = cv2.distanceTransformWithLabels(
        mask, cv2.DIST_L2, cv2.DIST_MASK_PRECISE, labelType=cv2.DIST_LABEL_PIXEL
    )
    # OpenCV numbers the zero pixels in scan order; map its labels to sites.
    ys, xs = np.nonzero(seeds)
    order = np.zeros(len(ys) + 1, dtype=np.int64)
    order[1:] = seeds[ys, xs]
    return order[lab] - 1


def nearest_share(labels, sites, frame):
    x, y = frame.pixel_centres()
    xx, yy = np.meshgrid(x, y)
    q = np.stack([xx.ravel(), yy.ravel()], -1)
    best, _ = cKDTree(sites).query(q)
    mine = np.linalg.norm(q - sites[labels.ravel()], axis=1)
    return float(np.mean(mine <= best + 1e-9))


def hausdorff_rows(args):
    from scipy.spatial.distance import directed_hausdorff

    rng = np.random.default_rng(2)
    pixgeo.hausdorff(rng.random((100, 2)), rng.random((100, 2)))
    print(
        "| m | sets | pixgeo (ms) | cKDTree ×2 (ms) | scipy directed_hausdorff ×2 (ms) "
        "| cKDTree / pixgeo | scipy / pixgeo | peers' distance | peak MiB: pixgeo / cKDTree / scipy |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for m in (int(s) for s in args.m.split(",")):
        a = rng.random((m, 2))
        sets = {
            "uniform": rng.random((m, 2)),
            "clustered": np.vstack([rng.normal(0.3, 0.01, (m // 2, 2)),
                                    rng.normal(0.7, 0.05, (m - m // 2, 2))]),
        }
        for name, b in sets.items():
            ours, h = timed(args.repeats, lambda: pixgeo.hausdorff(a, b))
            tree, d = timed(args.repeats, lambda: max(
                cKDTree(b).query(a, workers=2)[0].max(), cKDTree(a).query(b, workers=2)[0].max()))
            scipy, e = timed(args.repeats, lambda: max(
                directed_hausdorff(a, b)[0], directed_hausdorff(b, a)[0]))
            memory = "–"
            if args.memory:
                memory = " / ".join(f"{peak_mib(*hausdorff_calls(m, name, tool)):.1f}"
                                    for tool in ("pixgeo", "cKDTree", "scipy"))
            print(f"| {m} | {name} | {ours:.1f} | {tree:.1f} | {scipy:.1f} | {tree / ours:.2f}× "
                  f"| {scipy / ours:.2f}× | {agreement(h[0], d, e)} | {memory} |",
                  flush=True)


def agreement(exact, *peers):
    """How far the peers' distances lie from pixgeo's, which is the exact
    distance correctly rounded: "equal", or the most ulps apart."""
    ulps = max(abs(float(p) - exact) / np.spacing(exact) for p in peers)
    return "equal" if ulps == 0 else f"{ulps:.0f} ulp off"


HAUSDORFF_CALLS = {
    "pixgeo": "pixgeo.hausdorff({a}, {b})",
    "cKDTree": "max(cKDTree({b}).query({a}, workers=2)[0].max(), "
               "cKDTree({a}).query({b}, workers=2)[0].max())",
    "scipy": "max(directed_hausdorff({a}, {b})[0], directed_hausdorff({b}, {a})[0])",
}


def hausdorff_calls(m, name, tool):
    """peak_mib's setup, warm-up and call for one tool's Hausdorff distance
    between m uniform points and m points of set `name`."""
    setup = "\n".join([
        "from scipy.spatial.distance import directed_hausdorff",
        "rng = np.random.default_rng(2)",
        f"a = rng.random(({m}, 2))",
        f"b = rng.random(({m}, 2)) if {name!r} == 'uniform' else np.vstack(["
        f"rng.normal(0.3, 0.01, ({m} // 2, 2)), rng.normal(0.7, 0.05, ({m} - {m} // 2, 2))])",
    ])
    call = HAUSDORFF_CALLS[tool]
    return setup, call.format(a="a[:100]", b="b[:100]"), call.format(a="a", b="b")


def scipy_lloyd_step(sites, centres, weights):
    """One Lloyd iteration on the pixel centres: cKDTree (2 workers) for the
    nearest site, np.bincount for the weighted centroids."""
    _, nearest = cKDTree(sites).query(centres, workers=2)
    total = np.bincount(nearest, weights=weights, minlength=len(sites))
    moved = sites.copy()
    for axis in (0, 1):
        s = np.bincount(nearest, weights=weights * centres[:, axis], minlength=len(sites))
        moved[total > 0, axis] = s[total > 0] / total[total > 0]
    return moved


def lloyd_rows(args):
    """Per iteration, at the same resolution: pixgeo.lloyd against a SciPy
    Lloyd, uniform and weighted by a smooth density."""
    rng = np.random.default_rng(5)
    steps = 5
    print("| side | n | density | pixgeo (ms/iteration) | SciPy cKDTree Lloyd (ms/iteration) "
          "| SciPy / pixgeo | largest difference of the sites |")
    print("|---|---|---|---|---|---|---|")
    for side in (int(s) for s in args.sides.split(",")):
        box = (0.0, 0.0, 1000.0, 1000.0)
        frame = pixgeo.frame((side, side), bbox=box)
        x, y = frame.pixel_centres()
        xx, yy = np.meshgrid(x, y)
        centres = np.stack([xx.ravel(), yy.ravel()], -1)
        jj, ii = np.mgrid[0:side, 0:side]
        smooth = (1.0 + np.sin(ii / (side / 7.0)) * np.cos(jj / (side / 5.0))).round(3)
        pixgeo.lloyd(rng.uniform(0, 1000, (100, 2)), (side, side), bbox=box, iterations=1)
        for n in (int(s) for s in args.n.split(",")):
            sites = rng.uniform(0, 1000, (n, 2))
            for name, density in (("uniform", None), ("smooth", smooth)):
                weights = np.ones(side * side) if density is None else density.ravel()
                ours, got = timed(args.repeats, lambda: pixgeo.lloyd(
                    sites, (side, side), bbox=box, iterations=steps, tolerance=0.0, density=density))

                def scipy_run():
                    s = sites
                    for _ in range(steps):
                        s = scipy_lloyd_step(s, centres, weights)
                    return s

                theirs, want = timed(args.repeats, scipy_run)
                gap = float(np.abs(got.points - want).max())
                print(f"| {side}² | {n} | {name} | {ours / steps:.1f} | {theirs / steps:.1f} "
                      f"| {theirs / ours:.2f}× | {gap:.1e} |", flush=True)


def interpolation_rows(args):
    """Onto side² pixels: pixgeo's exact Sibson and linear interpolants
    against griddata (linear) and MetPy's natural neighbours."""
    from scipy.interpolate import griddata

    try:
        from metpy.interpolate import natural_neighbor_to_points
    except ImportError:  # the peer is optional
        natural_neighbor_to_points = None
    rng = np.random.default_rng(9)
    print("| side | n | pixgeo exact (ms) | pixgeo linear (ms) | griddata linear (ms) "
          "| griddata / pixgeo linear | MetPy, scaled to the picture (ms) | MetPy / pixgeo exact "
          "| largest difference from MetPy |")
    print("|---|---|---|---|---|---|---|---|---|")
    for side in (int(s) for s in args.sides.split(",")):
        box = (0.0, 0.0, 1000.0, 1000.0)
        x, y = pixgeo.frame((side, side), bbox=box).pixel_centres()
        xx, yy = np.meshgrid(x, y)
        sub = np.stack([c[:: side // 64, :: side // 64].ravel() for c in (xx, yy)], 1)
        for n in (int(s) for s in args.n.split(",")):
            points = rng.uniform(0, 1000, (n, 2))
            values = np.sin(points[:, 0] / 97) * np.cos(points[:, 1] / 131) * 10
            run = lambda method: pixgeo.natural_neighbor(  # noqa: E731
                points, values, (side, side), bbox=box, method=method)
            exact, _ = timed(args.repeats, lambda: run("exact"))
            linear, _ = timed(args.repeats, lambda: run("linear"))
            theirs, _ = timed(args.repeats, lambda: griddata(points, values, (xx, yy), method="linear"))
            metpy = gap = float("nan")
            if natural_neighbor_to_points is not None:
                took, want = timed(1, lambda: natural_neighbor_to_points(points, values, sub))
                metpy = took * side * side / len(sub)
                got = pixgeo.natural_neighbor(points, values, xi=sub)
                both = ~(np.isnan(got) | np.isnan(want))
                gap = float(np.abs(got[both] - want[both]).max())
            print(f"| {side}² | {n} | {exact:.0f} | {linear:.0f} | {theirs:.0f} | {theirs / linear:.2f}× "
                  f"| {metpy:.0f} | {metpy / exact:.0f}× | {gap:.1e} |", flush=True)


def power_rows(args):
    """pixgeo's power cells (and regular triangulation) against pyvoro2's."""
    from pyvoro2 import planar

    rng = np.random.default_rng(3)
    print("| n | pixgeo power cells (ms) | pyvoro2 power cells (ms) | pyvoro2 / pixgeo "
          "| pixgeo regular triangulation (ms) | hidden (pixgeo) | empty (pyvoro2) "
          "| pixgeo's hidden all empty in pyvoro2 | largest cell area difference "
          "| peak MiB: pixgeo / pyvoro2 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    box = planar.Box(((0.0, 1000.0), (0.0, 1000.0)))
    for n in (int(s) for s in args.n.split(",")):
        points = rng.uniform(0, 1000, (n, 2))
        weights = rng.uniform(0, 0.8 * 1000**2 / n, n)
        ours, cells = timed(args.repeats, lambda: pixgeo.power_cells(
            points, weights, bbox=(0, 0, 1000, 1000), geojson=True))
        regular, (_, hidden) = timed(args.repeats, lambda: pixgeo.regular_triangulation(points, weights))
        theirs, theirs_cells = timed(args.repeats, lambda: planar.compute(
            points, domain=box, mode="power", weights=weights, include_empty=True,
            output="cells", return_edges=False))
        empty = {c["id"] for c in theirs_cells if len(c.get("vertices", [])) == 0}
        area = np.zeros(n)
        for c in theirs_cells:
            area[c["id"]] = c.get("area", 0.0)
        gap = max(abs(shoelace(cell) - area[i]) for i, cell in enumerate(cells.polygons))
        setup = (f"rng = np.random.default_rng({n}); p = rng.uniform(0, 1000, ({n}, 2)); "
                 f"w = rng.uniform(0, {0.8 * 1000**2 / n}, {n}); from pyvoro2 import planar; "
                 "box = planar.Box(((0.0, 1000.0), (0.0, 1000.0)))")
        calls = [
            ("pixgeo.power_cells(p[:10], w[:10], bbox=(0, 0, 1000, 1000), geojson=True)",
             "pixgeo.power_cells(p, w, bbox=(0, 0, 1000, 1000), geojson=True)"),
            ("planar.compute(p[:10], domain=box, mode='power', weights=w[:10], "
             "include_empty=True, output='cells', return_edges=False)",
             "planar.compute(p, domain=box, mode='power', weights=w, include_empty=True, "
             "output='cells', return_edges=False)"),
        ]
        peaks = [peak_mib(setup, warm, call) for warm, call in calls] if args.memory else []
        memory = " / ".join(f"{m:.0f}" for m in peaks) or "–"
        print(f"| {n} | {ours:.0f} | {theirs:.0f} | {theirs / ours:.2f}× | {regular:.0f} | {len(hidden)} "
              f"| {len(empty)} | {set(hidden.tolist()) <= empty} | {gap:.1e} | {memory} |", flush=True)


def shoelace(polygon):
    """The area of a GeoJSON-like polygon's outer ring."""
    if not polygon["coordinates"]:
        return 0.0
    ring = np.asarray(polygon["coordinates"][0])
    x, y = ring[:, 0] - ring[0, 0], ring[:, 1] - ring[0, 1]
    return 0.5 * abs(float((x[:-1] * y[1:] - x[1:] * y[:-1]).sum()))


def shapely_cells(points):
    """shapely's Voronoi polygons of the points, each clipped to the box."""
    import shapely

    box = shapely.box(0, 0, 1000, 1000)
    cells = shapely.voronoi_polygons(shapely.MultiPoint(points), extend_to=box)
    return shapely.intersection(shapely.get_parts(cells), box)


def cells_rows(args):
    """pixgeo's exact Voronoi cells against shapely's (GEOS), both clipped
    to the box as shapely polygons."""
    import shapely

    rng = np.random.default_rng(11)
    pixgeo.voronoi_cells(rng.uniform(0, 1000, (10, 2)), bbox=(0, 0, 1000, 1000))
    print("| n | pixgeo (ms) | shapely (ms) | shapely / pixgeo | area sum − 10⁶: pixgeo / shapely "
          "| a valid coverage: pixgeo / shapely | peak MiB: pixgeo / shapely |")
    print("|---|---|---|---|---|---|---|")
    for n in (int(s) for s in args.n.split(",")):
        points = rng.uniform(0, 1000, (n, 2))
        ours, cells = timed(args.repeats, lambda: pixgeo.voronoi_cells(points, bbox=(0, 0, 1000, 1000)))
        theirs, polygons = timed(args.repeats, lambda: shapely_cells(points))
        areas = [float(shapely.area(cells.polygons).sum()) - 1e6, float(shapely.area(polygons).sum()) - 1e6]
        valid = [bool(shapely.coverage_is_valid(np.asarray(cells.polygons))),
                 bool(shapely.coverage_is_valid(polygons))]
        memory = "–"
        if args.memory:
            setup = f"p = np.random.default_rng({n}).uniform(0, 1000, ({n}, 2))"
            memory = " / ".join(f"{peak_mib(setup, w, c):.0f}" for w, c in [
                ("pixgeo.voronoi_cells(p[:10], bbox=(0, 0, 1000, 1000))",
                 "pixgeo.voronoi_cells(p, bbox=(0, 0, 1000, 1000))"),
                ("shapely_cells(p[:10])", "shapely_cells(p)"),
            ])
        print(f"| {n} | {ours:.0f} | {theirs:.0f} | {theirs / ours:.2f}× | {areas[0]:.1e} / {areas[1]:.1e} "
              f"| {'yes' if valid[0] else 'no'} / {'yes' if valid[1] else 'no'} | {memory} |", flush=True)


def threads_line():
    """Which device and how many threads each tool uses in this run."""
    import os

    cores = os.cpu_count()
    opencv = f"OpenCV {cv2.getNumThreads()} threads" if cv2 is not None else "OpenCV absent"
    print(f"pixgeo: device {os.environ.get('PIXGEO_DEVICE', 'auto')} (lavapipe without a GPU, "
          f"LP_NUM_THREADS={os.environ.get('LP_NUM_THREADS', 'one per core')}; exact labels by "
          f"the grid on the CPU there, without Vulkan), CPU steps on {cores} threads; cKDTree 2 workers; SciPy's ndimage, griddata, directed_hausdorff and "
          f"MetPy 1 thread; {opencv}; {cores} cores.\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tasks", default="labels,hausdorff")
    ap.add_argument("--sides", default="1024,4096")
    ap.add_argument("--n", default="1000,10000,100000")
    ap.add_argument("--m", default="10000,100000")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--memory", action="store_true",
                    help="also measure each call's peak memory, in a fresh process")
    args = ap.parse_args()
    threads_line()
    if "hausdorff" in args.tasks:
        hausdorff_rows(args)
    if "lloyd" in args.tasks:
        lloyd_rows(args)
    if "interpolate" in args.tasks:
        interpolation_rows(args)
    if "power" in args.tasks:
        power_rows(args)
    if "cells" in args.tasks:
        cells_rows(args)
    if "first" in args.tasks:
        first_calls(max(args.repeats, 3))
    if "labels" not in args.tasks:
        return
    rng = np.random.default_rng(1)
    pixgeo.voronoi(rng.uniform(0, 1000, (100, 2)), (64, 64), bbox=(0, 0, 1000, 1000))
    print(
        "| side | n | pixgeo (ms) | scipy EDT + lookup (ms) | OpenCV (ms) | scipy / pixgeo "
        "| OpenCV / pixgeo | nearest: pixgeo / scipy / OpenCV | peak MiB: pixgeo / scipy / OpenCV |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for side in (int(s) for s in args.sides.split(",")):
        for n in (int(s) for s in args.n.split(",")):
            sites = rng.uniform(0, 1000, (n, 2))
            ours, d = timed(
                args.repeats,
                lambda: pixgeo.voronoi(sites, (side, side), bbox=(0, 0, 1000, 1000), y_axis="down"),
            )
            theirs, s_labels = timed(args.repeats, lambda: scipy_labels(sites, side))
            if cv2 is not None:
                cv, c_labels = timed(args.repeats, lambda: opencv_labels(sites, side))
            else:
                cv, c_labels = float("nan"), None
            share = "–"
            if side <= 1024:
                shares = [nearest_share(d.labels.astype(np.int64), sites, d.frame)]
                shares.append(nearest_share(s_labels, sites, d.frame))
                if c_labels is not None:
                    shares.append(nearest_share(c_labels, sites, d.frame))
                share = " / ".join(f"{100 * s:.2f} %" for s in shares)
            memory = "–"
            if args.memory:
                setup = f"sites = np.random.default_rng({n}).uniform(0, 1000, ({n}, 2))"
                calls = [
                    ("pixgeo.voronoi(sites[:100], (64, 64), bbox=(0, 0, 1000, 1000))",
                     f"pixgeo.voronoi(sites, ({side}, {side}), bbox=(0, 0, 1000, 1000))"),
                    ("scipy_labels(sites[:100], 64)", f"scipy_labels(sites, {side})"),
                    ("opencv_labels(sites[:100], 64)", f"opencv_labels(sites, {side})"),
                ][: 3 if cv2 is not None else 2]
                memory = " / ".join(f"{peak_mib(setup, w, c):.0f}" for w, c in calls)
            print(
                f"| {side}² | {n} | {ours:.1f} | {theirs:.1f} | {cv:.1f} | {theirs / ours:.2f}× "
                f"| {cv / ours:.2f}× | {share} | {memory} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
