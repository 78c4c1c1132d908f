"""pixgeo.lloyd against a Lloyd built on SciPy (cKDTree on the pixel
centres, np.bincount for the centroids) at the same resolution, with and
without a density, north-up under a bbox, on the device and the CPU."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

import pixgeo


def scipy_lloyd(sites, frame, density, iterations):
    x, y = frame.pixel_centres()
    xx, yy = np.meshgrid(x, y)
    centres = np.stack([xx.ravel(), yy.ravel()], -1)
    w = density.ravel()
    sites = sites.copy()
    for _ in range(iterations):
        _, nearest = cKDTree(sites).query(centres)
        weight = np.bincount(nearest, weights=w, minlength=len(sites))
        for axis in (0, 1):
            total = np.bincount(nearest, weights=w * centres[:, axis], minlength=len(sites))
            moved = weight > 0
            sites[moved, axis] = total[moved] / weight[moved]
    return sites


@pytest.mark.parametrize("weighted", [False, True])
def test_lloyd_agrees_with_a_scipy_lloyd(weighted):
    rng = np.random.default_rng(52)
    h, w = 96, 128
    box = (0.0, 0.0, 16.0, 12.0)
    sites = np.column_stack([rng.uniform(0, 16, 50), rng.uniform(0, 12, 50)])
    jj, ii = np.mgrid[0:h, 0:w]
    density = (1.0 + np.sin(ii / 11.0) * np.cos(jj / 17.0)).round(3) if weighted else np.ones((h, w))
    got = pixgeo.lloyd(sites, (h, w), bbox=box, iterations=8, tolerance=0.0,
                       density=density if weighted else None)
    assert got.labels.shape == (h, w) and got.points.shape == (50, 2)
    assert got.frame.y_axis == "up"
    want = scipy_lloyd(sites, got.frame, density, 8)
    np.testing.assert_allclose(got.points, want, rtol=0, atol=1e-9)
    assert len(got.energy) == 8
    assert np.all(np.diff(got.energy) <= 1e-12 * got.energy[:-1])
    assert got.final_energy <= got.energy[-1] * (1 + 1e-12)
    on_cpu = pixgeo.lloyd(sites, (h, w), bbox=box, iterations=8, tolerance=0.0,
                          density=density if weighted else None, device="cpu")
    np.testing.assert_array_equal(on_cpu.points, got.points)
    np.testing.assert_array_equal(on_cpu.labels, got.labels)


def test_lloyd_stops_at_its_tolerance_and_refuses_bad_densities():
    rng = np.random.default_rng(3)
    sites = rng.uniform(0, 64, (20, 2))
    got = pixgeo.lloyd(sites, (64, 64), iterations=500, tolerance=0.05)
    assert got.converged and got.largest_move[-1] <= 0.05 and len(got.energy) < 500
    with pytest.raises(ValueError, match="not negative"):
        pixgeo.lloyd(sites, (64, 64), density=-np.ones((64, 64)))
    with pytest.raises(ValueError, match="shape"):
        pixgeo.lloyd(sites, (64, 64), density=np.ones((10, 10)))
    with pytest.raises(ValueError, match="iterations"):
        pixgeo.lloyd(sites, (64, 64), iterations=-1)


@pytest.mark.parametrize("weighted", [False, True])
def test_dask_lloyd_is_lloyd_block_by_block(weighted):
    """pixgeo.dask.lloyd sums the regions window by window: the same sites
    as pixgeo.lloyd, bit for bit, however the picture is chunked."""
    import dask
    import dask.array as da

    import pixgeo.dask

    rng = np.random.default_rng(8)
    h, w = 90, 120
    box = (0.0, 0.0, 12.0, 9.0)
    sites = np.column_stack([rng.uniform(0, 12, 40), rng.uniform(0, 9, 40)])
    jj, ii = np.mgrid[0:h, 0:w]
    density = (100 + 90 * np.sin(ii / 13.0) * np.cos(jj / 7.0)).round() if weighted else None
    whole = pixgeo.lloyd(sites, (h, w), bbox=box, iterations=6, tolerance=0.0, density=density)
    lazy = None if density is None else da.from_array(density, chunks=(45, 60))
    with dask.config.set(scheduler="synchronous"):
        blocks = pixgeo.dask.lloyd(sites, (h, w), bbox=box, chunks=(32, 50), iterations=6,
                                   tolerance=0.0, density=lazy)
        labels = blocks.labels.compute()
    np.testing.assert_array_equal(blocks.points, whole.points)
    np.testing.assert_array_equal(blocks.largest_move, whole.largest_move)
    np.testing.assert_allclose(blocks.energy, whole.energy, rtol=1e-12)
    np.testing.assert_array_equal(labels, whole.labels)
    assert blocks.idle == whole.idle and blocks.converged == whole.converged
    if weighted:
        with pytest.raises(ValueError, match="whole numbers"):
            pixgeo.dask.lloyd(sites, (h, w), bbox=box, density=density + 0.5)
