"""pixgeo from Python against scipy and brute force, on random and degenerate
inputs: duplicates, collinear points, lattices, sites outside the frame, bbox
frames."""

import os
import threading

import numpy as np
import pytest
from scipy.spatial import Delaunay, cKDTree
from scipy.spatial.distance import directed_hausdorff

import pixgeo


def lattice(step=7.0, n=6, offset=(3.0, 2.0)):
    g = np.stack(np.meshgrid(np.arange(n), np.arange(n)), -1).reshape(-1, 2)
    return g * step + np.asarray(offset)


def inputs():
    rng = np.random.default_rng(7)
    random = rng.uniform(0, 64, (40, 2))
    duplicates = np.concatenate([random[:10], random[:4]])
    collinear = np.stack([np.linspace(-5, 70, 9), np.linspace(3, 50, 9)], -1)
    outside = rng.uniform(-80, 150, (25, 2))
    return {
        "random": random,
        "duplicates": duplicates,
        "collinear": collinear,
        "lattice": lattice(),
        "outside": outside,
    }


def pixel_centres(frame):
    x, y = frame.pixel_centres()
    xx, yy = np.meshgrid(x, y)
    return np.stack([xx.ravel(), yy.ravel()], -1)


def brute_nearest(sites, query):
    d = np.linalg.norm(query[:, None, :] - sites[None, :, :], axis=-1)
    return d.min(axis=1), d


@pytest.mark.parametrize("name", list(inputs()))
@pytest.mark.parametrize("bbox", [None, (-10.0, -20.0, 90.0, 60.0)])
def test_voronoi_labels_the_nearest_site(name, bbox):
    sites = inputs()[name]
    shape = (48, 60)
    d = pixgeo.voronoi(sites, shape, bbox=bbox)
    assert d.labels.shape == shape and d.labels.dtype == np.uint32
    assert d.distances.shape == shape and d.distances.dtype == np.float32
    query = pixel_centres(d.frame)
    best, all_d = brute_nearest(sites, query)
    labels = d.labels.ravel()
    # The labelled site is a nearest one (ties to any of them), and the
    # distance is the exact one in float32.
    chosen = all_d[np.arange(len(query)), labels]
    np.testing.assert_allclose(chosen, best, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(d.distances.ravel(), best, rtol=1e-6, atol=1e-5)
    # cKDTree agrees wherever the nearest site is unique.
    dist, idx = cKDTree(sites).query(query, k=2)
    unique = dist[:, 1] - dist[:, 0] > 1e-9
    assert np.array_equal(labels[unique], idx[unique, 0])


@pytest.mark.parametrize("name", list(inputs()))
def test_cones_and_the_grid_give_the_same_diagram(name):
    sites = inputs()[name]
    shape, bbox = (48, 60), (-10.0, -20.0, 90.0, 60.0)
    drawn = pixgeo.voronoi(sites, shape, bbox=bbox, method="cones")
    searched = pixgeo.voronoi(sites, shape, bbox=bbox, method="grid")
    default = pixgeo.voronoi(sites, shape, bbox=bbox)
    for d in (searched, default):
        assert np.array_equal(d.labels, drawn.labels)
        assert np.array_equal(d.distances.view(np.uint32), drawn.distances.view(np.uint32))
    with pytest.raises(ValueError, match="Voronoi method"):
        pixgeo.voronoi(sites, shape, method="splat")
    with pytest.raises(ValueError, match="Euclidean"):
        pixgeo.voronoi(sites, shape, metric="l1", method="grid")


def test_frame_places_pixels_in_the_bbox():
    d = pixgeo.voronoi([[0.0, 0.0], [10.0, 5.0]], (50, 100), bbox=(0, 0, 10, 5), crs=32633)
    f = d.frame
    assert (f.width, f.height, f.y_axis, f.crs) == (100, 50, "up", "EPSG:32633")
    x, y = f.pixel_centres()
    assert x[0] == pytest.approx(0.05) and x[-1] == pytest.approx(9.95)
    # North-up, as the command line: row 0 is the largest y, so site 1
    # (10, 5) owns the top-right pixel and site 0 the bottom-left.
    assert y[0] == pytest.approx(4.95) and y[-1] == pytest.approx(0.05)
    assert d.labels[0, -1] == 1 and d.labels[-1, 0] == 0
    assert f.origin == (0.0, 5.0) and f.bbox == (0.0, 0.0, 10.0, 5.0)
    assert f.transform == pytest.approx((0.1, 0.0, 0.0, 0.0, -0.1, 5.0))
    assert f.geotransform == pytest.approx((0.0, 0.1, 0.0, 5.0, 0.0, -0.1))
    # The command line's rasters, row for row.
    down = pixgeo.voronoi([[0.0, 0.0], [10.0, 5.0]], (50, 100), bbox=(0, 0, 10, 5), y_axis="down")
    assert down.frame.y_axis == "down" and down.frame.origin == (0.0, 0.0)
    np.testing.assert_array_equal(down.labels[::-1], d.labels)
    np.testing.assert_array_equal(down.distances[::-1], d.distances)
    # 10 m pixels of a 1 km x 800 m box: 80 rows of 100.
    r = pixgeo.frame(bbox=(500000, 4000000, 501000, 4000800), res=10)
    assert (r.height, r.width, r.res) == (80, 100, pytest.approx(10.0))
    for bad, says in (
        (dict(bbox=(0, 0, 1005, 800), res=10), "whole numbers of pixels"),
        (dict(res=10), "give bbox"),
        (dict(shape=(8, 8), bbox=(0, 0, 8, 8), res=1), "not both"),
        (dict(), "give shape"),
        (dict(shape=(8, 8), y_axis="north"), "y_axis"),
        (dict(shape=(8, 8), crs="WGS84"), "EPSG:N"),
    ):
        with pytest.raises(ValueError, match=says):
            pixgeo.frame(**bad)


def test_rasters_are_north_up_with_a_bbox_as_the_command_line_writes_them(tmp_path):
    """The same sites and box through Python and the command line give the
    same labels, row for row, and the same placement."""
    import json
    import subprocess
    from pathlib import Path

    cli = Path(__file__).resolve().parents[2] / "target" / "debug" / "pixgeo"
    if not cli.exists():
        pytest.skip("build the command line first (cargo build)")
    sites = inputs()["random"]
    np.savetxt(tmp_path / "s.csv", sites, delimiter=",", header="x,y", comments="")
    box = (-10.0, -20.0, 90.0, 60.0)
    done = subprocess.run(
        [str(cli), "voronoi", "--sites", str(tmp_path / "s.csv"), "--bbox", ",".join(map(str, box)),
         "--size", "100x80", "--labels", str(tmp_path / "l.npy"), "--json"],
        capture_output=True, text=True, check=True)
    frame = json.loads(done.stdout)["frame"]
    d = pixgeo.voronoi(sites, (80, 100), bbox=box)
    np.testing.assert_array_equal(np.load(tmp_path / "l.npy"), d.labels)
    assert tuple(frame["origin"]) == d.frame.origin and frame["y_axis"] == d.frame.y_axis
    # Unplaced, Python and the command line both keep pixel coordinates.
    assert pixgeo.frame((4, 4)).y_axis == "down"


def test_other_metrics_and_fans():
    sites = inputs()["random"]
    query = None
    for metric, order in [("l1", 1), ("linf", np.inf), ("lp:3", 3)]:
        d = pixgeo.voronoi(sites, (32, 40), metric=metric)
        query = pixel_centres(d.frame)
        dist = np.linalg.norm(query[:, None, :] - sites[None], ord=order, axis=-1)
        chosen = dist[np.arange(len(query)), d.labels.ravel()]
        np.testing.assert_allclose(chosen, dist.min(axis=1), rtol=1e-9, atol=1e-9)
    fan = pixgeo.voronoi(sites, (32, 40), mode="fan")
    best, _ = brute_nearest(sites, query)
    # Fans of the thesis: within a pixel of the true distance.
    assert np.all(np.abs(fan.distances.ravel() - best) <= 1.0 + 1e-4)


def test_k_nearest_and_furthest():
    sites = inputs()["random"][:12]
    d = pixgeo.k_nearest(sites, (24, 30), 3)
    assert d.labels.shape == (24, 30, 3)
    query = pixel_centres(d.frame)
    dist, _ = cKDTree(sites).query(query, k=3)
    np.testing.assert_allclose(d.distances.reshape(-1, 3), dist, rtol=1e-5, atol=1e-4)
    many = pixgeo.k_nearest(sites[:2], (8, 8), 3)
    assert np.all(many.labels[..., 2] == pixgeo.NO_SITE)
    assert np.all(np.isinf(many.distances[..., 2]))
    f = pixgeo.furthest(sites, (24, 30))
    all_d = np.linalg.norm(query[:, None] - sites[None], axis=-1)
    chosen = all_d[np.arange(len(query)), f.labels.ravel()]
    np.testing.assert_allclose(chosen, all_d.max(axis=1), rtol=1e-12)


def triangles(simplices):
    return {tuple(sorted(t)) for t in np.asarray(simplices).tolist()}


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_delaunay_matches_scipy(seed):
    points = np.random.default_rng(seed).uniform(-1e3, 1e3, (300, 2))
    ours = pixgeo.delaunay(points)
    assert triangles(ours.simplices) == triangles(Delaunay(points).simplices)
    # Counter-clockwise.
    a, b, c = (points[ours.simplices[:, k]] for k in range(3))
    cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
    assert np.all(cross > 0)


def test_delaunay_reports_repeated_points():
    points = np.array([[0, 0], [4, 0], [0, 3], [4, 0], [5, 5], [1, 4]], dtype=float)
    t = pixgeo.delaunay(points)
    assert t.duplicates.tolist() == [[3, 1]]
    kept = np.array([0, 1, 2, 4, 5])
    assert triangles(t.simplices) == triangles(kept[Delaunay(points[kept]).simplices])


@pytest.mark.parametrize("name", ["random", "duplicates", "lattice", "outside"])
def test_hausdorff_and_diameter_are_exact(name):
    a = inputs()[name]
    b = np.random.default_rng(3).uniform(0, 64, (30, 2))
    want = max(directed_hausdorff(a, b)[0], directed_hausdorff(b, a)[0])
    answers = [pixgeo.hausdorff(a, b, method=m) for m in (None, "pixels", "grid")]
    assert answers[0] == answers[1] == answers[2]
    d, i, j = answers[0]
    assert d == pytest.approx(want, rel=1e-12)
    assert np.linalg.norm(a[i] - b[j]) == pytest.approx(want, rel=1e-12)
    with pytest.raises(ValueError, match="method must be"):
        pixgeo.hausdorff(a, b, method="kd")
    dist = np.linalg.norm(a[:, None] - a[None], axis=-1)
    d, i, j = pixgeo.diameter(a)
    assert d == pytest.approx(dist.max(), rel=1e-12)
    assert dist[i, j] == pytest.approx(d, rel=1e-12)


def test_largest_empty_circle_among_segments_inside_a_region():
    """Python at parity with `pixgeo empty --inside`: the same exact circle,
    at the origin and moved by 1e15."""
    for far in (0.0, 1e15):
        square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], dtype=float) + far
        c = pixgeo.largest_empty_circle(
            np.array([[3, 4], [7, 1]], dtype=float) + far,
            segments=np.array([[2, 8, 6, 9]], dtype=float) + far,
            region=[square],
            inside=True,
        )
        assert c.radius == 3.630264097376426 and c.sites == (0, 2, 4)
    with pytest.raises(ValueError, match="segments must be"):
        pixgeo.largest_empty_circle(square, segments=[1, 2, 3, 4])


def test_circles():
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]], dtype=float)
    c = pixgeo.enclosing_circle(square)
    assert c.centre == pytest.approx((1.0, 1.0)) and c.radius == pytest.approx(2**0.5)
    e = pixgeo.largest_empty_circle(square)
    # Centred at an edge midpoint of the box, touching two corners and the middle.
    assert e.radius == pytest.approx(1.0)
    region = [np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=float)]
    assert pixgeo.largest_empty_circle(square, region=region).radius == pytest.approx(1.0)


def brute_triangle(p, largest):
    n = len(p)
    best = None
    for i in range(n):
        for j in range(i + 1, n):
            d = p[j] - p[i]
            for k in range(j + 1, n):
                e = p[k] - p[i]
                area = abs(d[0] * e[1] - d[1] * e[0]) / 2
                if best is None or (area > best if largest else area < best):
                    best = area
    return best


@pytest.mark.parametrize("name", ["random", "lattice", "collinear", "duplicates"])
def test_extremal_triangles(name):
    p = inputs()[name][:20]
    for largest, f in [(False, pixgeo.smallest_triangle), (True, pixgeo.largest_triangle)]:
        v, area = f(p)
        assert len(set(v.tolist())) == 3
        assert area == pytest.approx(brute_triangle(p, largest), abs=1e-12)


def test_quadrangles():
    p = lattice(1.0, 4, (0.0, 0.0))
    v, area = pixgeo.smallest_quadrangle(p)
    assert area == pytest.approx(1.0) and len(v) == 4
    v, area = pixgeo.largest_quadrangle(p)
    assert area == pytest.approx(9.0)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: pixgeo.voronoi([[0, 0], [1, np.nan]], (8, 8)), "non-finite"),
        (lambda: pixgeo.voronoi(np.zeros((0, 2)), (8, 8)), "empty"),
        (lambda: pixgeo.voronoi(np.zeros((3, 3)), (8, 8)), "shape (n, 2)"),
        (lambda: pixgeo.voronoi([["a", "b"]], (8, 8)), "real numbers"),
        (lambda: pixgeo.voronoi([[0, 0]], (8,)), "(height, width)"),
        (lambda: pixgeo.voronoi([[0, 0]], (0, 8)), "at least 1"),
        (lambda: pixgeo.voronoi([[0, 0]], (8, 8), metric="l7x"), "metric"),
        (lambda: pixgeo.voronoi([[0, 0]], (8, 8), mode="fast"), "unknown mode"),
        (lambda: pixgeo.voronoi([[0, 0]], (8, 8), bbox=(1, 1, 0, 0)), "XMIN < XMAX"),
        (lambda: pixgeo.k_nearest([[0, 0]], (8, 8), 0), "k must be"),
        (lambda: pixgeo.delaunay([[0, 0], [1, 1]]), "three"),
        (lambda: pixgeo.smallest_triangle([[0, 0], [1, 1]]), "three sites"),
        (lambda: pixgeo.hausdorff([[0, 0]], [[np.inf, 0]]), "non-finite"),
    ],
)
def test_bad_input_raises_value_error(call, message):
    with pytest.raises(ValueError, match=None) as e:
        call()
    assert message in str(e.value), str(e.value)


@pytest.mark.parametrize(
    "call, reason",
    [
        (lambda: pixgeo.voronoi([[0, 0], [1, 1], [1, np.nan]], (8, 8)), {"kind": "not_finite", "index": 2}),
        (lambda: pixgeo.smallest_triangle([[0, 0], [1, 1]]), {"kind": "too_few", "needed": 3, "given": 2}),
        (lambda: pixgeo.delaunay([[0, 0], [1, 1], [2, 2]]), {"kind": "degenerate"}),
        (lambda: pixgeo.voronoi([[0, 0]], (8, 8), bbox=(1, 1, 0, 0)), {"kind": "malformed"}),
    ],
)
def test_bad_input_says_why_by_kind(call, reason):
    """pixgeo's refusals carry `reason`, as the command line's JSON does."""
    with pytest.raises(ValueError) as e:
        call()
    assert e.value.reason == reason, str(e.value)


def test_an_unknown_device_is_a_no_device_error():
    with pytest.raises(pixgeo.NoDeviceError, match="no-such-device-anywhere"):
        pixgeo.voronoi([[0, 0]], (8, 8), device="no-such-device-anywhere")
    assert issubclass(pixgeo.NoDeviceError, RuntimeError)
    assert issubclass(pixgeo.DeviceError, RuntimeError)
    assert issubclass(pixgeo.InternalError, RuntimeError)


def test_calls_from_several_threads_agree():
    sites = inputs()["random"]
    want = pixgeo.voronoi(sites, (40, 40)).labels
    results = [None] * 4

    def work(k):
        results[k] = pixgeo.voronoi(sites, (40, 40)).labels

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        assert np.array_equal(r, want)


@pytest.mark.parametrize("shape_of_weights", ["m", "m,a"])
def test_weighted_voronoi_matches_the_weighted_distance(shape_of_weights):
    rng = np.random.default_rng(5)
    sites = rng.uniform(0, 40, (12, 2))
    m = rng.uniform(0.5, 2.0, 12)
    a = rng.uniform(0, 5, 12) if shape_of_weights == "m,a" else np.zeros(12)
    weights = m if shape_of_weights == "m" else np.stack([m, a], -1)
    d = pixgeo.voronoi(sites, (40, 40), weights=weights)
    q = pixel_centres(d.frame)
    dist = np.linalg.norm(q[:, None] - sites[None], axis=-1) / m + a
    best = dist.min(axis=1)
    chosen = dist[np.arange(len(q)), d.labels.ravel()]
    np.testing.assert_allclose(chosen, best, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(d.distances.ravel(), best, rtol=1e-5, atol=1e-4)
    with pytest.raises(ValueError, match="weights must have shape"):
        pixgeo.voronoi(sites, (8, 8), weights=np.ones(3))
    with pytest.raises(ValueError, match="windows take unweighted"):
        pixgeo.voronoi(sites, (8, 8), weights=m, window=(0, 0, 2, 2))


def test_convex_hull_as_alpha_zero():
    from scipy.spatial import ConvexHull

    p = np.random.default_rng(8).uniform(0, 100, (40, 2))
    h = pixgeo.alpha_hull(p, 0.0, side=128)
    hull = ConvexHull(p)
    assert set(h.boundary) == set(hull.vertices.tolist())
    q = pixel_centres(h.frame)
    # Signed distance to the hull: the largest facet offset (negative inside).
    signed = (q @ hull.equations[:, :2].T + hull.equations[:, 2]).max(axis=1)
    clear = np.abs(signed) > 1.0 / h.frame.scale
    assert clear.mean() > 0.9
    assert np.array_equal(h.inside.ravel()[clear], signed[clear] < 0)


def test_settle_counts_the_pixels_a_new_site_wins():
    rivals = np.random.default_rng(4).uniform(0, 24, (5, 2)) + 0.123
    s = pixgeo.settle(rivals, (24, 24))
    q = pixel_centres(s.frame)
    nearest_rival = np.linalg.norm(q[:, None] - rivals[None], axis=-1).min(axis=1)
    to_new = np.linalg.norm(q[:, None] - q[None], axis=-1)
    want = (to_new < nearest_rival[None, :]).sum(axis=1)
    assert np.array_equal(s.area.ravel(), want)
    assert s.best_area == want.max()
    x, y, area = s.refined
    assert 0 <= x <= 24 and 0 <= y <= 24 and area > 0


def test_unaligned_arrays_are_read():
    # A float64 view one byte into a buffer, as unpickled buffers can be.
    raw = np.zeros(8 * 20 + 1, dtype=np.uint8)
    sites = raw[1:].view(np.float64).reshape(10, 2)
    sites[:] = np.random.default_rng(2).uniform(0, 16, (10, 2))
    assert not sites.flags.aligned
    d = pixgeo.voronoi(sites, (16, 16))
    assert np.array_equal(d.labels, pixgeo.voronoi(sites.copy(), (16, 16)).labels)


def test_ambiguous_input_is_refused_not_guessed():
    sites = np.array([[1.0, 2.0], [5.0, 5.0], [9.0, 1.0]])
    masked = np.ma.masked_array(sites, mask=[[False, False], [True, True], [False, False]])
    with pytest.raises(ValueError, match="masked"):
        pixgeo.voronoi(masked, (16, 16))
    # With nothing masked, the values are the data.
    clear = np.ma.masked_array(sites, mask=False)
    assert (pixgeo.voronoi(clear, (16, 16)).labels == pixgeo.voronoi(sites, (16, 16)).labels).all()
    with pytest.raises(ValueError, match="whole pixels"):
        pixgeo.voronoi(sites, (32.5, 32))
    with pytest.raises(ValueError, match="whole number"):
        pixgeo.k_nearest(sites, (16, 16), 1.5)
    image = np.ma.masked_array(np.ones((8, 8)), mask=np.eye(8, dtype=bool))
    with pytest.raises(ValueError, match="masked"):
        pixgeo.distance_transform_edt(image)


def test_without_a_vulkan_driver_the_cpu_algorithms_give_the_devices_answers(tmp_path):
    # A process whose Vulkan loader finds no driver: every call with a CPU
    # algorithm answers there, bit for bit as on the device here.
    import subprocess
    import sys

    rng = np.random.default_rng(3)
    lattice = np.array([[x, y] for x in range(5) for y in range(5)], float)
    points = np.vstack([rng.uniform(0, 4, (40, 2)), lattice])
    values = points[:, 0] * 2 - points[:, 1]
    np.save(tmp_path / "points.npy", points)
    np.save(tmp_path / "values.npy", values)
    script = """
import sys, warnings
import numpy as np, pixgeo
warnings.simplefilter("always")
d = sys.argv[1]
points = np.load(d + "/points.npy")
values = np.load(d + "/values.npy")
np.save(d + "/simplices.npy", pixgeo.delaunay(points).simplices)
cells = pixgeo.voronoi_cells(points, bbox=(-1, -1, 5, 5), geojson=True)
np.save(d + "/cells.npy", np.concatenate([np.asarray(c["coordinates"][0]).ravel() for c in cells.polygons if c]))
np.save(d + "/natural.npy", pixgeo.natural_neighbor(points, values, (20, 20), bbox=(0, 0, 4, 4)))
np.save(d + "/hausdorff.npy", np.array(pixgeo.hausdorff(points[:30], points[30:])))
np.save(d + "/labels.npy", pixgeo.voronoi(points, (20, 20), bbox=(0, 0, 4, 4)).labels)
c = pixgeo.enclosing_circle(points)
np.save(d + "/furthest.npy", pixgeo.furthest(points, (20, 20), bbox=(0, 0, 4, 4)).labels)
np.save(d + "/circle.npy", np.array([*c.centre, c.radius, *c.sites]))
np.save(d + "/settle.npy", pixgeo.settle(points[:20], (20, 20), bbox=(0, 0, 4, 4)).area)
np.save(d + "/levels.npy", pixgeo.k_nearest(points, (20, 20), 3, bbox=(0, 0, 4, 4)).labels)
weights = 1 + (np.arange(len(points)) % 3) / 4
np.save(d + "/weighted.npy", pixgeo.voronoi(points, (20, 20), bbox=(0, 0, 4, 4), weights=weights).labels)
# The discrete method is drawn where a device starts: here, with a warning.
pixgeo.natural_neighbor(points, values, (20, 20), bbox=(0, 0, 4, 4), method="discrete")
"""
    env = dict(os.environ, VK_DRIVER_FILES=str(tmp_path / "none.json"))
    env.pop("PIXGEO_DEVICE", None)
    done = subprocess.run(
        [sys.executable, "-c", script, str(tmp_path)], env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    # Where a device was wanted, the fallback warns.
    assert "RuntimeWarning" in done.stderr and "computing on the CPU" in done.stderr
    cells = pixgeo.voronoi_cells(points, bbox=(-1, -1, 5, 5), geojson=True, device="lavapipe")
    here = {
        "simplices": pixgeo.delaunay(points, device="lavapipe").simplices,
        "cells": np.concatenate(
            [np.asarray(c["coordinates"][0]).ravel() for c in cells.polygons if c]
        ),
        "natural": pixgeo.natural_neighbor(
            points, values, (20, 20), bbox=(0, 0, 4, 4), device="lavapipe"
        ),
        "hausdorff": np.array(pixgeo.hausdorff(points[:30], points[30:], device="lavapipe")),
        "labels": pixgeo.voronoi(points, (20, 20), bbox=(0, 0, 4, 4), device="lavapipe").labels,
    }
    far = pixgeo.furthest(points, (20, 20), bbox=(0, 0, 4, 4), device="lavapipe")
    here["furthest"] = far.labels
    c = pixgeo.enclosing_circle(points, device="lavapipe")
    here["circle"] = np.array([*c.centre, c.radius, *c.sites])
    here["settle"] = pixgeo.settle(points[:20], (20, 20), bbox=(0, 0, 4, 4), device="lavapipe").area
    levels = pixgeo.k_nearest(points, (20, 20), 3, bbox=(0, 0, 4, 4), device="lavapipe")
    here["levels"] = levels.labels
    weights = 1 + (np.arange(len(points)) % 3) / 4
    weighted = pixgeo.voronoi(points, (20, 20), bbox=(0, 0, 4, 4), weights=weights, device="lavapipe")
    here["weighted"] = weighted.labels
    for name, want in here.items():
        got = np.load(tmp_path / f"{name}.npy")
        assert got.dtype == want.dtype and np.array_equal(got, want, equal_nan=True), name


def test_a_box_of_part_pixels_is_placed_as_the_command_line_places_it(tmp_path):
    # 7 rows over a box 7.4 high: row 0 is the box's top edge's, here and in
    # the command line, north-up.
    sites = np.array([[1.0, 0.3], [8.0, 7.2], [4.5, 3.9], [2.0, 6.9]])
    csv = tmp_path / "sites.csv"
    csv.write_text("x,y\n" + "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in sites))
    out = tmp_path / "labels.npy"
    args = ["pixgeo", "voronoi", "--sites", str(csv), "--size", "10x7", "--bbox", "0,0,10,7.4"]
    assert pixgeo._pixgeo.cli(args + ["--labels", str(out), "-q"]) == 0
    d = pixgeo.voronoi(sites, (7, 10), bbox=(0, 0, 10, 7.4))
    assert np.array_equal(np.load(out), d.labels)
    assert d.frame.origin == (0.0, 7.4)


def test_triangulation_answers_as_scipys_delaunay():
    """On 10⁴ random points, ``neighbors``, ``convex_hull``,
    ``vertex_neighbor_vertices`` and ``find_simplex`` equal
    ``scipy.spatial.Delaunay``'s, up to the order of the simplices."""
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(4)
    p = rng.random((10_000, 2))
    ours, theirs = pixgeo.delaunay(p), Delaunay(p)
    name = lambda simplices, i: tuple(sorted(simplices[i])) if i >= 0 else None
    index = {name(theirs.simplices, i): i for i in range(len(theirs.simplices))}
    assert set(index) == {name(ours.simplices, i) for i in range(len(ours.simplices))}
    for i, corners in enumerate(ours.simplices):
        j = index[name(ours.simplices, i)]
        for c, v in enumerate(corners):
            k = list(theirs.simplices[j]).index(v)
            assert name(ours.simplices, ours.neighbors[i, c]) == name(
                theirs.simplices, theirs.neighbors[j, k])
    edges = lambda e: {tuple(sorted(x)) for x in e}
    assert edges(ours.convex_hull) == edges(theirs.convex_hull)
    (a, b), (sa, sb) = ours.vertex_neighbor_vertices, theirs.vertex_neighbor_vertices
    for k in range(len(p)):
        assert list(b[a[k]:a[k + 1]]) == sorted(sb[sa[k]:sa[k + 1]])
    q = rng.random((20_000, 2)) * 1.2 - 0.1
    for f, g in zip(ours.find_simplex(q), theirs.find_simplex(q)):
        assert name(ours.simplices, f) == name(theirs.simplices, g)
    assert ours.find_simplex(q[:6].reshape(2, 3, 2)).shape == (2, 3)


def test_find_simplex_is_exact_on_edges_and_corners():
    """A point on a shared edge or corner goes to the smallest triangle
    holding it; one a ulp outside the hull to none."""
    p = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0]])
    t = pixgeo.delaunay(p)
    cross = lambda u, v: u[0] * v[1] - u[1] * v[0]
    holding = lambda q: [i for i, s in enumerate(t.simplices)
                         if all(cross(p[s[(k + 1) % 3]] - p[s[k]], q - p[s[k]]) >= 0
                                for k in range(3))]
    for q in ([1.0, 1.0], [0.5, 0.5], [1.0, 0.0], [0.0, 0.0]):
        assert t.find_simplex([q])[0] == min(holding(np.array(q))), q
    assert t.find_simplex([[1.0, np.nextafter(0.0, -1.0)]])[0] == -1
    with pytest.raises(ValueError, match="counter-clockwise"):
        pixgeo.Triangulation(t.simplices[:, ::-1], t.duplicates, p).find_simplex([[1.0, 0.5]])
