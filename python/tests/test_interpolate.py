"""pixgeo.natural_neighbor against MetPy's natural-neighbour interpolation
(on MetPy's own test data), SciPy's griddata (linear and nearest) and exact
rational arithmetic; rasters against points; refusals."""

from fractions import Fraction

import numpy as np
import pytest
from scipy.interpolate import griddata

import pixgeo

# MetPy's test data for natural-neighbour interpolation
# (tests/interpolate/test_points.py).
METPY_X = np.array([8, 67, 79, 10, 52, 53, 98, 34, 15, 58], dtype=float)
METPY_Y = np.array([24, 87, 48, 94, 98, 66, 14, 24, 60, 16], dtype=float)
METPY_Z = np.array([0.064, 4.489, 6.241, 0.1, 2.704, 2.809, 9.604, 1.156, 0.225, 3.364])


def metpy_points():
    return np.stack([METPY_X, METPY_Y], axis=1)


def test_metpy_test_point():
    # MetPy's truth at (30, 30): 1.009 to three decimals.
    value = pixgeo.natural_neighbor(metpy_points(), METPY_Z, xi=[[30.0, 30.0]])
    assert value.shape == (1,)
    assert round(float(value[0]), 3) == 1.009


def test_agrees_with_metpy_on_its_test_data():
    metpy = pytest.importorskip("metpy.interpolate")
    # A grid off the Delaunay edges: MetPy divides by zero on them.
    xs = np.arange(0.1234, 100, 2.5)
    ys = np.arange(0.1357, 100, 2.5)
    grid = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)
    ours = pixgeo.natural_neighbor(metpy_points(), METPY_Z, xi=grid)
    theirs = metpy.natural_neighbor_to_points(metpy_points(), METPY_Z, grid)
    assert np.array_equal(np.isnan(ours), np.isnan(theirs))
    inside = ~np.isnan(ours)
    assert inside.sum() > 500
    np.testing.assert_allclose(ours[inside], theirs[inside], rtol=1e-12, atol=1e-12)


def sibson_by_fractions(points, values, q):
    """Sibson's interpolant at q by its definition, in fractions: q's new
    Voronoi region clipped from a box, then the piece each point loses."""

    def clip(poly, a, b):
        f = lambda p: a[0] * p[0] + a[1] * p[1] - b  # noqa: E731
        out = []
        for k in range(len(poly)):
            p, r = poly[k], poly[(k + 1) % len(poly)]
            fp, fr = f(p), f(r)
            if fp <= 0:
                out.append(p)
            if (fp > 0 > fr) or (fp < 0 < fr):
                t = fp / (fp - fr)
                out.append((p[0] + (r[0] - p[0]) * t, p[1] + (r[1] - p[1]) * t))
        return out

    def nearer(poly, s, o):
        a = (2 * (o[0] - s[0]), 2 * (o[1] - s[1]))
        return clip(poly, a, o[0] ** 2 + o[1] ** 2 - s[0] ** 2 - s[1] ** 2)

    def area(poly):
        return abs(sum(p[0] * r[1] - p[1] * r[0] for p, r in zip(poly, poly[1:] + poly[:1])))

    pts = [(Fraction(x), Fraction(y)) for x, y in points]
    qf = (Fraction(q[0]), Fraction(q[1]))
    big = Fraction(10**6)
    region = [(qf[0] + dx * big, qf[1] + dy * big) for dx, dy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    for s in pts:
        region = nearer(region, qf, s)
    total = weighted = Fraction(0)
    for i, s in enumerate(pts):
        piece = region
        for j, o in enumerate(pts):
            if j != i and len(piece) >= 3:
                piece = nearer(piece, s, o)
        if len(piece) >= 3:
            a = area(piece)
            total += a
            weighted += a * Fraction(values[i])
    return weighted / total


def test_exact_is_the_rational_interpolant_correctly_rounded():
    rng = np.random.default_rng(5)
    points = rng.uniform(0, 10, (9, 2))
    values = rng.normal(0, 3, 9)
    centre = points.mean(axis=0)
    queries = centre + rng.uniform(-1, 1, (25, 2))
    got = pixgeo.natural_neighbor(points, values, xi=queries)
    for q, v in zip(queries, got):
        assert v == float(sibson_by_fractions(points, values, q))


def test_linear_and_nearest_agree_with_griddata():
    rng = np.random.default_rng(52)
    points = rng.uniform(0, 100, (300, 2))
    values = np.sin(points[:, 0] / 9) * np.cos(points[:, 1] / 13)
    frame = pixgeo.frame((64, 80), bbox=(0, 0, 100, 80))
    x, y = frame.pixel_centres()
    xx, yy = np.meshgrid(x, y)
    for method in ("linear", "nearest"):
        ours = pixgeo.natural_neighbor(points, values, (64, 80), bbox=(0, 0, 100, 80), method=method)
        theirs = griddata(points, values, (xx, yy), method=method)
        assert ours.shape == (64, 80)
        assert np.array_equal(np.isnan(ours), np.isnan(theirs)), method
        inside = ~np.isnan(ours)
        np.testing.assert_allclose(ours[inside], theirs[inside], rtol=0, atol=1e-12)


def test_raster_and_points_agree_and_rows_run_north_up():
    rng = np.random.default_rng(1)
    points = rng.uniform(0, 100, (60, 2))
    values = points[:, 1] * 2.0 + rng.normal(0, 0.1, 60)
    up = pixgeo.natural_neighbor(points, values, (50, 50), bbox=(0, 0, 100, 100))
    down = pixgeo.natural_neighbor(points, values, (50, 50), bbox=(0, 0, 100, 100), y_axis="down")
    np.testing.assert_array_equal(up, down[::-1])
    # Values grow with y: row 0 of a north-up raster is the top.
    column = up[:, 25][~np.isnan(up[:, 25])]
    assert column[0] > column[-1]
    x = y = np.arange(50) * 2.0 + 1.0
    grid = np.stack(np.meshgrid(x, y), -1).reshape(-1, 2)
    for method in ("exact", "linear"):
        raster = pixgeo.natural_neighbor(points, values, (50, 50), bbox=(0, 0, 100, 100), y_axis="down", method=method)
        at = pixgeo.natural_neighbor(points, values, xi=grid, method=method)
        np.testing.assert_array_equal(raster.reshape(-1), at)


def test_discrete_nears_exact_away_from_the_hull():
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(3)
    points = rng.uniform(0, 100, (100, 2))
    values = rng.uniform(0, 10, 100)
    box = dict(bbox=(0, 0, 100, 100), y_axis="down")
    exact = pixgeo.natural_neighbor(points, values, (400, 400), **box)
    discrete = pixgeo.natural_neighbor(points, values, (400, 400), method="discrete", **box)
    assert np.array_equal(np.isnan(exact), np.isnan(discrete))
    x, y = pixgeo.frame((400, 400), **box).pixel_centres()
    centres = np.stack([c.ravel() for c in np.meshgrid(x, y)], 1)
    hull = ConvexHull(points).equations
    depth = np.min(-(hull[:, :2] @ centres.T + hull[:, 2:3]), axis=0).reshape(400, 400)
    # Near the hull a pixel's stolen regions reach beyond any margin drawn;
    # 15 units in, measured: mean 0.008, largest 0.15, of a range of 10.
    error = np.abs(exact - discrete)[depth > 15]
    assert error.mean() < 0.02 and error.max() < 0.3


def test_refusals():
    p = metpy_points()
    with pytest.raises(ValueError, match="method"):
        pixgeo.natural_neighbor(p, METPY_Z, (10, 10), bbox=(0, 0, 100, 100), method="cubic")
    with pytest.raises(ValueError, match="one value per point"):
        pixgeo.natural_neighbor(p, METPY_Z[:-1], (10, 10), bbox=(0, 0, 100, 100))
    with pytest.raises(ValueError, match="finite"):
        pixgeo.natural_neighbor(p, np.where(METPY_Z > 9, np.inf, METPY_Z), (10, 10), bbox=(0, 0, 100, 100))
    with pytest.raises(ValueError, match="not both"):
        pixgeo.natural_neighbor(p, METPY_Z, (10, 10), xi=[[1.0, 2.0]])
    with pytest.raises(ValueError, match="rasters"):
        pixgeo.natural_neighbor(p, METPY_Z, xi=[[1.0, 2.0]], method="discrete")
    twice = np.vstack([p, p[:1]])
    with pytest.raises(ValueError, match="same point"):
        pixgeo.natural_neighbor(twice, np.append(METPY_Z, 5.0), xi=[[30.0, 30.0]])


@pytest.mark.parametrize("method", ["exact", "linear", "nearest"])
def test_dask_blocks_tile_into_the_whole_raster(method):
    import pixgeo.dask

    rng = np.random.default_rng(8)
    points = rng.uniform(0, 100, (70, 2))
    values = rng.normal(0, 5, 70)
    whole = pixgeo.natural_neighbor(points, values, (49, 61), bbox=(0, 0, 100, 80), method=method)
    blocks = pixgeo.dask.natural_neighbor(
        points, values, (49, 61), bbox=(0, 0, 100, 80), method=method, chunks=(16, 25)
    )
    assert blocks.chunks == ((16, 16, 16, 1), (25, 25, 11))
    np.testing.assert_array_equal(blocks.compute(scheduler="sync"), whole)
    with pytest.raises(ValueError, match="discrete"):
        pixgeo.dask.natural_neighbor(points, values, (49, 61), bbox=(0, 0, 100, 80), method="discrete")


def test_griddatas_forms_of_xi_and_fill_value():
    """``xi`` as griddata takes it, a tuple of meshgrid arrays or (..., 2)
    coordinates, answered in its shape, with ``fill_value`` outside the
    hull: SciPy's linear answer."""
    rng = np.random.default_rng(2)
    p = rng.random((50, 2)) * 10
    v = np.sin(p[:, 0]) + p[:, 1]
    gx, gy = np.meshgrid(np.linspace(-1, 11, 7), np.linspace(-1, 11, 5))
    ours = pixgeo.natural_neighbor(p, v, xi=(gx, gy), method="linear", fill_value=-9.0)
    theirs = griddata(p, v, (gx, gy), method="linear", fill_value=-9.0)
    assert ours.shape == (5, 7)
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12)
    assert (ours == -9.0).sum() == (theirs == -9.0).sum() > 0
    stacked = pixgeo.natural_neighbor(p, v, xi=np.stack([gx, gy], axis=-1))
    assert stacked.shape == (5, 7) and np.isnan(stacked).sum() == (theirs == -9.0).sum()
    with pytest.raises(AttributeError, match="natural_neighbor"):
        pixgeo.interpolate
