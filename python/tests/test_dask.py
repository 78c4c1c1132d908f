"""Windows and Dask blocks against the single-call diagram, pixel for pixel."""

import numpy as np
import pytest

import pixgeo

dask = pytest.importorskip("dask")
distributed = pytest.importorskip("distributed")
zarr = pytest.importorskip("zarr")
import pixgeo.dask  # noqa: E402


def sites():
    rng = np.random.default_rng(11)
    lattice = np.stack(np.meshgrid(np.arange(0, 90, 10.0), np.arange(0, 70, 10.0)), -1)
    return np.concatenate(
        [rng.uniform(-10, 100, (150, 2)), lattice.reshape(-1, 2), [[5.0, 5.0], [5.0, 5.0]]]
    )


@pytest.mark.parametrize("metric", ["l2", "l1"])
def test_random_windows_tile_into_the_whole(metric):
    s = sites()
    shape, bbox = (70, 90), (0, 0, 90, 70)
    whole = pixgeo.voronoi(s, shape, bbox=bbox, metric=metric)
    rng = np.random.default_rng(3)
    xs = np.unique(np.concatenate([[0, 90], rng.integers(1, 90, 3)]))
    ys = np.unique(np.concatenate([[0, 70], rng.integers(1, 70, 3)]))
    for y0, y1 in zip(ys[:-1], ys[1:]):
        for x0, x1 in zip(xs[:-1], xs[1:]):
            part = pixgeo.voronoi(
                s, shape, bbox=bbox, metric=metric, window=(x0, y0, x1 - x0, y1 - y0)
            )
            assert np.array_equal(part.labels, whole.labels[y0:y1, x0:x1])
            assert np.array_equal(
                part.distances.view(np.uint32), whole.distances[y0:y1, x0:x1].view(np.uint32)
            )


def test_bad_windows_and_modes_are_value_errors():
    with pytest.raises(ValueError, match="inside the 8x8 picture"):
        pixgeo.voronoi([[1, 1]], (8, 8), window=(4, 4, 5, 1))
    with pytest.raises(ValueError, match="exact mode"):
        pixgeo.voronoi([[1, 1]], (8, 8), mode="fan", window=(0, 0, 2, 2))
    with pytest.raises(ValueError, match="exact mode"):
        pixgeo.dask.voronoi([[1, 1]], (8, 8), mode="fan")
    with pytest.raises(ValueError, match="non-finite"):
        pixgeo.dask.voronoi([[1, np.nan]], (8, 8))
    with pytest.raises(ValueError, match="chunks"):
        pixgeo.dask.voronoi([[1, 1]], (8, 8), chunks=(0, 4))


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as c:
        yield c


def test_a_local_cluster_computes_the_same_diagram(client, tmp_path):
    s = sites()
    shape, bbox = (210, 270), (-5, -5, 85, 65)
    want = pixgeo.voronoi(s, shape, bbox=bbox)
    # Blocks whose edges cut through the regions, and a ragged last block.
    got = pixgeo.dask.voronoi(s, shape, bbox=bbox, chunks=(64, 100))
    assert got.labels.chunks == ((64, 64, 64, 18), (100, 100, 70))
    assert got.frame == want.frame
    # A bounded wait: a worker that died mid-task would leave the task pending.
    labels, distances = (f.result(timeout=300) for f in client.compute([got.labels, got.distances]))
    assert labels.dtype == np.uint32 and distances.dtype == np.float32
    assert np.array_equal(labels, want.labels)
    assert np.array_equal(distances.view(np.uint32), want.distances.view(np.uint32))
    assert len(client.scheduler_info()["workers"]) == 2
    # A Zarr round trip gives the same arrays.
    store = str(tmp_path / "labels.zarr")
    client.compute(got.labels.to_zarr(store, compute=False)).result(timeout=300)
    back = zarr.open_array(store, mode="r")
    assert back.shape == shape
    assert np.array_equal(back[:], want.labels)
