"""pixgeo.regular_triangulation against the lower convex hull of the lifted
points (SciPy's Qhull), pixgeo.power_diagram against the least power by
brute force, and pixgeo.power_cells against the box cut by every radical
axis in shapely."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import pixgeo


def lower_hull(points, weights):
    """The regular triangulation by Qhull: the lower faces of the hull of
    (x, y, x² + y² - w), and the points on none of them."""
    lifted = np.column_stack([points, (points**2).sum(1) - weights])
    hull = ConvexHull(lifted)
    lower = hull.simplices[hull.equations[:, 2] < 0]
    triangles = {tuple(sorted(t)) for t in lower}
    hidden = set(range(len(points))) - set(np.unique(lower))
    return triangles, hidden


def test_regular_triangulation_is_qhulls_lower_hull():
    rng = np.random.default_rng(52)
    points = rng.uniform(0, 100, (400, 2))
    weights = rng.uniform(0, 80, 400)
    triangles, hidden = pixgeo.regular_triangulation(points, weights)
    want_triangles, want_hidden = lower_hull(points, weights)
    assert len(want_hidden) > 0
    assert {tuple(sorted(t)) for t in triangles} == want_triangles
    assert set(hidden.tolist()) == want_hidden
    a, b, c = (points[triangles[:, k]] for k in range(3))
    u, v = b - a, c - a
    assert np.all(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0)


def test_power_diagram_has_the_least_power_north_up():
    rng = np.random.default_rng(7)
    points = rng.uniform(0, 100, (60, 2))
    weights = rng.uniform(0, 150, 60)
    d = pixgeo.power_diagram(points, weights, (50, 50), bbox=(0, 0, 100, 100))
    x, y = d.frame.pixel_centres()
    xx, yy = np.meshgrid(x, y)
    centres = np.stack([xx.ravel(), yy.ravel()], 1)
    power = ((centres[:, None, :] - points[None]) ** 2).sum(-1) - weights[None]
    assert np.array_equal(d.labels.ravel(), power.argmin(1))
    np.testing.assert_allclose(d.powers.ravel(), power.min(1), rtol=1e-12, atol=1e-9)
    _, hidden = pixgeo.regular_triangulation(points, weights)
    np.testing.assert_array_equal(d.hidden, hidden)
    assert not np.isin(d.labels, d.hidden).any()


def test_refusals():
    with pytest.raises(ValueError, match="weights"):
        pixgeo.regular_triangulation(np.zeros((3, 2)) + [[0, 0], [1, 0], [0, 1]], [1.0, 2.0])
    with pytest.raises(ValueError, match="one line"):
        pixgeo.regular_triangulation([[0, 0], [1, 1], [2, 2]], [0.0, 0.0, 0.0])


def test_dask_blocks_tile_into_the_whole_diagram():
    import pixgeo.dask

    rng = np.random.default_rng(4)
    points = rng.uniform(0, 100, (50, 2))
    weights = rng.uniform(0, 100, 50)
    whole = pixgeo.power_diagram(points, weights, (49, 61), bbox=(0, 0, 100, 80))
    labels, powers, ties = pixgeo.dask.power_diagram(
        points, weights, (49, 61), bbox=(0, 0, 100, 80), chunks=(16, 25)
    )
    np.testing.assert_array_equal(labels.compute(scheduler="sync"), whole.labels)
    np.testing.assert_array_equal(powers.compute(scheduler="sync"), whole.powers)
    np.testing.assert_array_equal(ties.compute(scheduler="sync"), whole.ties)


def test_ties_count_the_sites_of_least_power():
    # A lattice of equal weights: pixel centres on the radical axes tie.
    points = np.array([[10.5 + 20 * i, 10.5 + 20 * j] for i in range(4) for j in range(4)])
    weights = np.full(16, 30.0)
    d = pixgeo.power_diagram(points, weights, (80, 80), bbox=(0, 0, 80, 80))
    x, y = d.frame.pixel_centres()
    xx, yy = np.meshgrid(x, y)
    centres = np.stack([xx.ravel(), yy.ravel()], 1)
    power = ((centres[:, None, :] - points[None]) ** 2).sum(-1) - weights[None]
    want = (power == power.min(1, keepdims=True)).sum(1)
    assert (want > 1).sum() > 100
    np.testing.assert_array_equal(d.ties.ravel(), want)


def test_power_cells_are_the_box_cut_by_every_radical_axis():
    shapely = pytest.importorskip("shapely")
    rng = np.random.default_rng(8)
    points = rng.uniform(-10, 110, (40, 2))
    weights = rng.uniform(0, 400, 40)
    box = (0.0, 0.0, 100.0, 100.0)
    cells = pixgeo.power_cells(points, weights, bbox=box)
    _, hidden = pixgeo.regular_triangulation(points, weights)
    np.testing.assert_array_equal(cells.hidden, hidden)
    assert len(hidden) > 0
    big = 1e4
    for i, cell in enumerate(cells.polygons):
        want = shapely.box(*box)
        for j in range(len(points)):
            if j == i:
                continue
            # power_i <= power_j: 2 p.(s_j - s_i) <= |s_j|² - w_j - |s_i|² + w_i
            n = points[j] - points[i]
            c = (points[j] @ points[j] - weights[j] - points[i] @ points[i] + weights[i]) / 2
            # A huge polygon of the half-plane n.p <= c.
            u = n / np.hypot(*n)
            foot = u * (c / np.hypot(*n))
            along = np.array([-u[1], u[0]])
            half = shapely.Polygon([foot + along * big, foot - along * big,
                                    foot - along * big - u * big, foot + along * big - u * big])
            want = want.intersection(half)
        if i in hidden:
            assert cell.is_empty
        else:
            assert cell.symmetric_difference(want).area < 1e-9, i
    assert abs(sum(c.area for c in cells.polygons) - 1e4) < 1e-8
    geo = cells.__geo_interface__["features"]
    assert geo[int(hidden[0])]["properties"]["hidden"] is True
    assert geo[0]["properties"]["weight"] == weights[0]
