"""pixgeo.distance_transform_edt against scipy.ndimage: distances equal, bit
for bit, and indices that point at a zero element at that distance; L1 and
L∞ against distance_transform_cdt."""

import numpy as np
import pytest
from scipy import ndimage

import pixgeo


def masks():
    rng = np.random.default_rng(11)
    out = {}
    for h, w in [(1, 1), (1, 17), (23, 1), (40, 57)]:
        for density in (0.02, 0.5, 0.97):
            m = rng.random((h, w)) < density
            # SciPy's answer without a zero is no distance (see below).
            m[h // 2, w // 2] &= not m.all()
            out[f"{h}x{w} {density}"] = m
        single = np.ones((h, w), bool)
        single[rng.integers(h), rng.integers(w)] = False
        out[f"{h}x{w} single"] = single
        out[f"{h}x{w} full"] = np.zeros((h, w), bool)
    lattice = np.ones((48, 48), bool)
    lattice[2::5, 1::4] = False
    out["lattice"] = lattice
    return out


def check_indices(input, d, i, sampling=(1.0, 1.0)):
    rows, cols = np.indices(input.shape)
    assert (input[i[0], i[1]] == 0).all()
    dy = (rows - i[0]) * sampling[0]
    dx = (cols - i[1]) * sampling[1]
    np.testing.assert_array_equal(np.sqrt(dy * dy + dx * dx), d)


@pytest.mark.parametrize("name", list(masks()))
@pytest.mark.parametrize("sampling", [None, (1.0, 1.0), (2.0, 0.5), 0.3, (1e-3, 7.0)])
def test_edt_equals_scipy(name, sampling):
    input = masks()[name].astype(np.uint8)
    expected = ndimage.distance_transform_edt(input, sampling=sampling)
    d, i = pixgeo.distance_transform_edt(input, sampling=sampling, return_indices=True)
    assert d.dtype == np.float64 and i.dtype == np.int32 and i.shape == (2,) + input.shape
    np.testing.assert_array_equal(d, expected)
    s = (1.0, 1.0) if sampling is None else np.broadcast_to(sampling, (2,))
    check_indices(input, d, i, s)


def test_outputs_in_place_and_one_at_a_time():
    input = masks()["40x57 0.5"]
    d = np.empty(input.shape)
    i = np.empty((2,) + input.shape, np.int32)
    assert pixgeo.distance_transform_edt(input, distances=d, return_indices=True, indices=i) is None
    np.testing.assert_array_equal(d, ndimage.distance_transform_edt(input))
    only = pixgeo.distance_transform_edt(input, return_distances=False, return_indices=True)
    np.testing.assert_array_equal(only, i)
    with pytest.raises(RuntimeError):
        pixgeo.distance_transform_edt(input, return_distances=False)
    with pytest.raises(ValueError):
        pixgeo.distance_transform_edt(np.ones((2, 2, 2)))
    with pytest.raises(ValueError):
        pixgeo.distance_transform_edt(input, sampling=(1.0, -1.0))


def test_no_zero_gives_infinite_distances():
    d, i = pixgeo.distance_transform_edt(np.ones((3, 4)), return_indices=True)
    assert np.isinf(d).all() and (i == -1).all()


@pytest.mark.parametrize("name", list(masks()))
@pytest.mark.parametrize("metric,scipy_metric", [("l1", "taxicab"), ("linf", "chessboard")])
def test_l1_and_linf_equal_cdt(name, metric, scipy_metric):
    input = masks()[name]
    expected = ndimage.distance_transform_cdt(input, metric=scipy_metric)
    d = pixgeo.distance_transform_edt(input, metric=metric)
    np.testing.assert_array_equal(d, expected)
