"""pixgeo.regular_triangulation against the lower convex hull of the lifted
points (SciPy's Qhull), and pixgeo.power_diagram against the least power
by brute force."""

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
    labels, powers = pixgeo.dask.power_diagram(points, weights, (49, 61), bbox=(0, 0, 100, 80), chunks=(16, 25))
    np.testing.assert_array_equal(labels.compute(scheduler="sync"), whole.labels)
    np.testing.assert_array_equal(powers.compute(scheduler="sync"), whole.powers)
