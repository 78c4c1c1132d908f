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


@pytest.mark.parametrize(
    "arguments",
    [
        {"return_distances": False, "return_indices": True, "distances": "d"},
        {"return_distances": True, "return_indices": False, "indices": "i"},
        {"return_distances": False, "return_indices": False, "distances": "d", "indices": "i"},
    ],
)
def test_outputs_given_with_their_flag_off_are_refused_as_scipy_refuses(arguments):
    input = masks()["40x57 0.5"]
    arrays = {"d": np.zeros(input.shape), "i": np.zeros((2,) + input.shape, np.int32)}
    arguments = {k: arrays.get(v, v) if isinstance(v, str) else v for k, v in arguments.items()}
    with pytest.raises(RuntimeError) as ours:
        pixgeo.distance_transform_edt(input, **arguments)
    with pytest.raises(RuntimeError) as scipys:
        ndimage.distance_transform_edt(input, **arguments)
    assert str(ours.value) == str(scipys.value)
    assert not arrays["d"].any() and not arrays["i"].any()
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


def shapes():
    h, w = 120, 160
    y, x = np.mgrid[:h, :w]
    blobs = ndimage.gaussian_filter(np.random.default_rng(1).random((h, w)), 6)
    return {
        "disk": (y - 60) ** 2 + (x - 80) ** 2 < 50**2,
        "bar": (y > 20) & (y < 60) & (x > 10) & (x < 150),
        "ellipse": ((y - 60) / 40) ** 2 + ((x - 80) / 70) ** 2 < 1,
        "ring": ((y - 60) ** 2 + (x - 80) ** 2 < 55**2) & ((y - 60) ** 2 + (x - 80) ** 2 > 20**2),
        "L": ((y > 10) & (y < 40) & (x > 10) & (x < 140)) | ((y > 10) & (y < 110) & (x > 10) & (x < 45)),
        "blobs": blobs > np.median(blobs),
    }


@pytest.mark.parametrize("name", list(shapes()))
def test_medial_axis_beside_skimage(name):
    """skimage thins the shape in the order of the distances and keeps it
    connected; pixgeo's integer medial axis keeps the pixels between features
    far apart and seen under a wide angle, from the exact feature transform.
    So skimage's axis lies along pixgeo's: 85% or more of its pixels within
    1.5 pixels of pixgeo's, the rest on the spurs that keep it connected and
    branches into blunt corners, which pixgeo prunes. pixgeo's may keep a few
    lone pixels where a digital curve's lattice points tie, and more axis
    where skimage's thinning has stopped, in the middle of a disk (skimage
    keeps 2 pixels there) and along an ellipse's blunt ends."""
    from skimage.morphology import medial_axis

    image = shapes()[name]
    ours, d = pixgeo.medial_axis(image, return_distance=True)
    theirs = medial_axis(image, rng=0)
    assert ours.dtype == bool and ours.shape == image.shape
    assert not ours[~image].any()
    np.testing.assert_array_equal(d, ndimage.distance_transform_edt(image))
    near_ours = ndimage.distance_transform_edt(~ours)[theirs] <= 1.5
    near_theirs = ndimage.distance_transform_edt(~theirs)[ours] <= 1.5
    assert near_ours.mean() >= 0.85, near_ours.mean()
    if name == "disk":
        assert ours[60, 80] and ours.sum() <= 20
    else:
        assert near_theirs.mean() >= 0.8, near_theirs.mean()
    if name == "bar":
        # 39 free rows: the axis is the middle one, away from the corners.
        np.testing.assert_array_equal(ours[:, 60:100], theirs[:, 60:100])
        assert ours[40, 60:100].all() and ours[:, 60:100].sum() == 40


def test_medial_axis_keeps_topology_on_skimages_shapes():
    """scikit-image's own medial-axis test shapes and thin ones: pixgeo's axis
    is connected wherever the shape is, keeps the loop around a hole, lies on
    skimage's, and lacks only the tips that skimage grows into square
    corners (pruning takes them)."""
    from skimage.morphology import medial_axis

    def loops(a):
        return ndimage.label(~np.pad(a, 1))[1] - 1

    line = np.zeros((9, 9), bool)
    line[:, 2:5] = True
    rectangle = np.zeros((9, 15), bool)
    rectangle[1:-1, 1:-1] = True
    holed = rectangle.copy()
    holed[4, 4:-4] = False
    thin = {
        "3-pixel bar": np.pad(np.ones((3, 9), bool), 2),
        "1x3 strip": np.pad(np.ones((1, 3), bool), 2),
        "5x3 square": np.pad(np.ones((3, 5), bool), 2),
    }
    np.testing.assert_array_equal(pixgeo.medial_axis(line), medial_axis(line))
    for image in [rectangle, holed, *thin.values()]:
        ours, theirs = pixgeo.medial_axis(image), medial_axis(image)
        assert ours.any() and not (ours & ~theirs).any()
        assert ndimage.label(ours, np.ones((3, 3)))[1] == 1
        assert loops(ours) == loops(image)
    for image in (rectangle, holed):
        assert (medial_axis(image) & ~pixgeo.medial_axis(image)).sum() <= 8
    # skimage's narrow image, one row tall: the image's edge is no feature for
    # pixgeo, so the axis is the bisector of the two zeros, the middle pixel.
    narrow = np.array([[0, 1, 1, 1, 0]], bool)
    np.testing.assert_array_equal(pixgeo.medial_axis(narrow), [[0, 0, 1, 0, 0]])


def test_medial_axis_options():
    image = shapes()["L"]
    bar = image & (np.mgrid[:120, :160][0] < 40)
    # A mask counts only the pixels non-zero in it too.
    np.testing.assert_array_equal(
        pixgeo.medial_axis(image, mask=bar), pixgeo.medial_axis(bar)
    )
    # Sampling stretches the rows: the bar's axis stays in its middle row.
    stretched = pixgeo.medial_axis(bar, sampling=(3.0, 1.0))
    assert stretched[25, 60:90].all() and stretched[:, 60:90].sum() == 30
    # Less pruning keeps more.
    loose = pixgeo.medial_axis(image, prune=1.0, prune_angle=0.0)
    assert loose.sum() > pixgeo.medial_axis(image).sum()
    assert (loose | ~pixgeo.medial_axis(image)).all()
    for bad in ({"prune": -1.0}, {"prune_angle": 200.0}):
        with pytest.raises(ValueError, match="pruning"):
            pixgeo.medial_axis(image, **bad)
    with pytest.raises(ValueError):
        pixgeo.medial_axis(image, mask=np.ones((2, 2)))
    # skimage's keyword arguments all work: rng changes nothing here.
    np.testing.assert_array_equal(
        pixgeo.medial_axis(image, rng=np.random.default_rng(7)), pixgeo.medial_axis(image)
    )
