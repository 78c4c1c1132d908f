"""pixgeo's GIS outputs: GeoTIFFs and world files read back with rasterio
(the transform, the coordinate system and the values, against brute force in
the user's coordinates), and vector cells read with shapely, against its own
Voronoi polygons and brute force. The command line is the one `cargo test`
builds (or PIXGEO_CLI)."""

import os
import subprocess
from pathlib import Path

import json

import numpy as np
from scipy import ndimage
import pytest
import shapely
from shapely.geometry import MultiPoint, Point, box, shape

import rasterio
from rasterio.transform import Affine, from_origin

ROOT = Path(__file__).resolve().parents[2]
CLI = Path(os.environ.get("PIXGEO_CLI", ROOT / "target" / "debug" / "pixgeo"))

# A 1 km x 800 m box in UTM zone 33N, 4 m pixels.
BBOX = (500000.0, 4000000.0, 501000.0, 4000800.0)


def pixgeo(*args):
    assert CLI.exists(), f"build the command line first (cargo build): {CLI}"
    done = subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


@pytest.fixture()
def sites(tmp_path):
    rng = np.random.default_rng(5)
    xy = np.column_stack(
        [rng.uniform(BBOX[0], BBOX[2], 40), rng.uniform(BBOX[1], BBOX[3], 40)]
    )
    path = tmp_path / "sites.csv"
    np.savetxt(path, xy, delimiter=",", header="x,y", comments="", fmt="%.6f")
    return xy, path


def centres(transform, shape):
    """World coordinates of every pixel's centre, by the file's transform."""
    rows, cols = np.indices(shape)
    t = transform
    return t.c + t.a * (cols + 0.5) + t.b * (rows + 0.5), t.f + t.d * (cols + 0.5) + t.e * (rows + 0.5)


def check_nearest(labels, distances, transform, xy):
    x, y = centres(transform, labels.shape)
    d = np.hypot(x[..., None] - xy[:, 0], y[..., None] - xy[:, 1])
    best = d.min(axis=-1)
    mine = np.take_along_axis(d, labels[..., None].astype(np.int64), axis=-1)[..., 0]
    # Each pixel's label is a nearest site (to float32 rounding of ties).
    assert (mine - best <= 1e-3).all()
    np.testing.assert_allclose(distances, best, rtol=1e-5, atol=1e-3)


def test_north_up_geotiff(tmp_path, sites):
    xy, path = sites
    out = {k: tmp_path / f"{k}.tif" for k in ("labels", "distance", "ties")}
    pixgeo(
        "voronoi", "--sites", path, "--bbox", ",".join(map(str, BBOX)), "--size", 250,
        "--labels", out["labels"], "--distance", out["distance"], "--ties", out["ties"],
        "--crs", "EPSG:32633", "--world-file", tmp_path / "picture.pgw",
        "-o", tmp_path / "picture.png",
    )
    with rasterio.open(out["labels"]) as r:
        assert r.crs.to_epsg() == 32633
        assert r.transform == Affine(4.0, 0.0, BBOX[0], 0.0, -4.0, BBOX[3])
        assert (r.width, r.height, r.count, r.dtypes[0]) == (250, 200, 1, "uint32")
        labels = r.read(1)
        transform = r.transform
    with rasterio.open(out["distance"]) as r:
        assert r.dtypes[0] == "float32" and r.transform == transform
        distances = r.read(1)
    with rasterio.open(out["ties"]) as r:
        assert (r.read(1) >= 1).all()
    check_nearest(labels, distances, transform, xy)
    # The world file places the picture where the GeoTIFF lies.
    with rasterio.open(tmp_path / "picture.png") as r:
        assert r.transform == transform


def test_other_layouts(tmp_path, sites):
    xy, path = sites
    box = ",".join(map(str, BBOX))
    # Rows running north: a transformation with a positive y step.
    pixgeo("voronoi", "--sites", path, "--bbox", box, "--size", 100,
           "--labels", tmp_path / "down.tif", "--distance", tmp_path / "down-d.tif",
           "--y-axis", "down")
    with rasterio.open(tmp_path / "down.tif") as r:
        assert r.transform == Affine(10.0, 0.0, BBOX[0], 0.0, 10.0, BBOX[1])
        # No --crs: GDAL names a local system without an EPSG code.
        assert r.crs is None or r.crs.to_epsg() is None
        labels, transform = r.read(1), r.transform
    with rasterio.open(tmp_path / "down-d.tif") as r:
        check_nearest(labels, r.read(1), transform, xy)
    # A window lies where it lies in the whole picture, and so does its
    # world file.
    pixgeo("voronoi", "--sites", path, "--bbox", box, "--size", 100,
           "--labels", tmp_path / "window.tif", "--window", "10,20,30,40",
           "--world-file", tmp_path / "window.tfw")
    with rasterio.open(tmp_path / "window.tif") as r:
        assert r.transform == Affine(10.0, 0.0, BBOX[0] + 100, 0.0, -10.0, BBOX[3] - 200)
        assert r.shape == (40, 30)
    lines = [float(v) for v in (tmp_path / "window.tfw").read_text().split()]
    np.testing.assert_allclose(lines, [10, 0, 0, -10, BBOX[0] + 105, BBOX[3] - 205])
    # The second nearest sites: a band per level.
    pixgeo("voronoi", "--sites", path, "--bbox", box, "--size", 100,
           "--labels", tmp_path / "order.tif", "--degree", 2)
    with rasterio.open(tmp_path / "order.tif") as r:
        assert r.count == 2
        first, second = r.read(1), r.read(2)
        x, y = centres(r.transform, first.shape)
        d = np.hypot(x[..., None] - xy[:, 0], y[..., None] - xy[:, 1])
        ranked = np.sort(d, axis=-1)
        at = lambda l: np.take_along_axis(d, l[..., None].astype(np.int64), axis=-1)[..., 0]
        assert (at(first) - ranked[..., 0] <= 1e-3).all()
        assert (at(second) - ranked[..., 1] <= 1e-3).all()


def test_geographic_crs_and_settle(tmp_path):
    # The settle point is computed on the plane: under a geographic system
    # only on request (--metric), with a warning.
    done = pixgeo("settle", "--random", 12, "--bbox", "10,45,12,46.5", "--size", 80,
                  "--area", tmp_path / "area.tif", "--crs", "EPSG:4326", "--metric", "l2",
                  "--world-file", tmp_path / "area.tfw")
    assert "warning: EPSG:4326 is geographic" in done.stderr
    refused = subprocess.run([str(CLI), "settle", "--random", "12", "--bbox", "10,45,12,46.5",
                              "--crs", "EPSG:4326"], capture_output=True, text=True)
    assert refused.returncode == 1 and "not on the Earth" in refused.stderr
    with rasterio.open(tmp_path / "area.tif") as r:
        assert r.crs.to_epsg() == 4326 and r.crs.is_geographic
        assert r.transform == Affine(0.025, 0.0, 10.0, 0.0, -0.025, 46.5)
        assert r.read(1).max() > 0
    lines = (tmp_path / "area.tfw").read_text().split()
    np.testing.assert_allclose(
        [float(v) for v in lines], [0.025, 0, 0, -0.025, 10.0125, 46.4875]
    )


def test_geotiffs_fit_for_gdal_as_they_are(tmp_path, sites, caplog):
    """Tiled, DEFLATE-compressed, nodata declared, the coordinate system's kind
    from EPSG's registry, and not a word from GDAL on reading them."""
    import logging

    xy, path = sites
    box = ",".join(map(str, BBOX))
    caplog.set_level(logging.DEBUG)
    pixgeo("voronoi", "--sites", path, "--bbox", box, "--size", 600,
           "--labels", tmp_path / "l.tif", "--distance", tmp_path / "d.tif",
           "--degree", 2, "--crs", "EPSG:32633")
    for name, dtype, nodata in (("l.tif", "uint32", 4294967295), ("d.tif", "float32", np.inf)):
        with rasterio.open(tmp_path / name) as r:
            profile = r.profile
            assert (profile["tiled"], profile["blockxsize"], profile["blockysize"]) == (True, 256, 256)
            assert profile["compress"] == "deflate" and r.count == 2
            assert r.dtypes[0] == dtype and r.nodata == nodata
            r.read()
    # Labels hold no "no site" here: every pixel keeps its value.
    with rasterio.open(tmp_path / "l.tif") as r:
        assert not r.read(1, masked=True).mask.any()
    # Geographic or projected as the registry says, not by the code's range.
    for code, geographic in ((6318, True), (4087, False), (4326, True)):
        pixgeo("voronoi", "--random", 10, "--bbox", "10,45,12,46.5", "--size", 40,
               "--labels", tmp_path / f"{code}.tif", "--crs", f"EPSG:{code}")
        with rasterio.open(tmp_path / f"{code}.tif") as r:
            assert r.crs.to_epsg() == code and r.crs.is_geographic == geographic
            r.read()
    warned = [rec for rec in caplog.records if rec.levelno >= logging.WARNING]
    assert not warned, [rec.getMessage() for rec in warned]
    refused = subprocess.run([str(CLI), "voronoi", "--random", "3", "--crs", "EPSG:4978"],
                             capture_output=True, text=True)
    assert refused.returncode != 0 and "geocentric" in refused.stderr


def test_cloud_optimised_geotiffs(tmp_path, sites, caplog):
    """--cog: GDAL reads the layout as COG, with overviews down to one tile
    that hold the nearest samples (as GDAL's NEAREST takes them), for labels,
    distances and a proximity raster read from a GeoTIFF; not a warning."""
    import logging

    xy, path = sites
    caplog.set_level(logging.DEBUG)
    box = ",".join(map(str, BBOX))
    pixgeo("voronoi", "--sites", path, "--bbox", box, "--size", 1100, "--crs", "EPSG:32633",
           "--labels", tmp_path / "l.tif", "--distance", tmp_path / "d.tif", "--cog")
    cover = np.zeros((300, 600), np.uint8)
    cover[::37, ::53] = 1
    with rasterio.open(tmp_path / "m.tif", "w", driver="GTiff", width=600, height=300, count=1,
                       dtype="uint8", crs="EPSG:32633",
                       transform=Affine(10.0, 0.0, 500000.0, 0.0, -10.0, 4001000.0)) as w:
        w.write(cover, 1)
    pixgeo("transform", "--mask", tmp_path / "m.tif", "--distance", tmp_path / "p.tif", "--cog")
    for name, levels in (("l.tif", [2, 4, 8]), ("d.tif", [2, 4, 8]), ("p.tif", [2, 4])):
        with rasterio.open(tmp_path / name) as r:
            assert r.tags(ns="IMAGE_STRUCTURE")["LAYOUT"] == "COG", name
            assert r.overviews(1) == levels and r.crs.to_epsg() == 32633, name
            full = r.read(1)
            for factor in levels:
                shape = (-(-r.height // factor), -(-r.width // factor))
                overview = r.read(1, out_shape=shape)
                rows = np.minimum(np.arange(shape[0]) * factor + factor // 2, r.height - 1)
                columns = np.minimum(np.arange(shape[1]) * factor + factor // 2, r.width - 1)
                assert np.array_equal(overview, full[np.ix_(rows, columns)]), (name, factor)
    warned = [rec for rec in caplog.records if rec.levelno >= logging.WARNING]
    assert not warned, [rec.getMessage() for rec in warned]


def test_crs_from_wkt_proj_and_prj_files(tmp_path):
    """--crs and Python's crs take what names or matches an EPSG code: WKT
    as GDAL and PROJ write it, ESRI's .prj, PROJ strings; a local grid is
    refused by name."""
    from rasterio.crs import CRS

    import pixgeo as pixgeo_module

    utm = CRS.from_epsg(32633)
    prj = tmp_path / "zone.prj"
    prj.write_text(utm.to_wkt(version="WKT1_ESRI"))
    for given in (utm.to_wkt(), utm.to_wkt(version="WKT2_2019"), str(prj),
                  "+proj=utm +zone=33 +datum=WGS84 +units=m +no_defs",
                  "urn:ogc:def:crs:EPSG::32633"):
        tif = tmp_path / "l.tif"
        done = pixgeo("voronoi", "--random", 10, "--bbox", "500000,4000000,501000,4000800",
                      "--size", 40, "--labels", tif, "--crs", given, "--json")
        assert json.loads(done.stdout)["frame"]["crs"] == "EPSG:32633", given
        with rasterio.open(tif) as r:
            assert r.crs.to_epsg() == 32633, given
        assert pixgeo_module.frame((10, 10), bbox=(0, 0, 1, 1), crs=given).crs == "EPSG:32633"
    assert pixgeo_module.frame((10, 10), bbox=(0, 0, 1, 1), crs=utm).crs == "EPSG:32633"
    local = 'LOCAL_CS["site grid",UNIT["metre",1]]'
    refused = subprocess.run([str(CLI), "voronoi", "--random", "3", "--crs", local],
                             capture_output=True, text=True)
    assert refused.returncode != 0 and "names no EPSG code" in refused.stderr
    with pytest.raises(ValueError, match="no EPSG code"):
        pixgeo_module.frame((10, 10), bbox=(0, 0, 1, 1), crs=local)


def read_cells(path):
    collection = json.loads(path.read_text())
    assert collection["type"] == "FeatureCollection"
    return collection["features"]


@pytest.mark.parametrize("case", ["random", "lattice", "co-circular", "outside", "repeated"])
def test_exact_cells_beside_shapely(tmp_path, case):
    rng = np.random.default_rng(8)
    frame = box(*BBOX)
    if case == "random":
        xy = np.column_stack([rng.uniform(BBOX[0], BBOX[2], 60), rng.uniform(BBOX[1], BBOX[3], 60)])
    elif case == "lattice":
        gx, gy = np.meshgrid(np.arange(50, 1000, 100), np.arange(50, 800, 100))
        xy = np.column_stack([gx.ravel() + BBOX[0], gy.ravel() + BBOX[1]])
    elif case == "co-circular":
        a = np.arange(16) * np.pi / 8
        xy = np.column_stack([500 + 300 * np.cos(a), 400 + 300 * np.sin(a)]) + BBOX[:2]
        xy = np.vstack([xy, [BBOX[0] + 500, BBOX[1] + 400]])
    elif case == "outside":
        xy = np.array([[-300, 400], [200, 300], [700, 500], [1500, 1500], [500, -10]]) + BBOX[:2]
    else:
        xy = np.column_stack([rng.uniform(BBOX[0], BBOX[2], 20), rng.uniform(BBOX[1], BBOX[3], 20)])
        xy = np.vstack([xy, xy[:5]])
    path = tmp_path / "sites.csv"
    np.savetxt(path, xy, delimiter=",", header="x,y", comments="", fmt="%.6f")
    xy = np.loadtxt(path, delimiter=",", skiprows=1)
    out = tmp_path / "cells.geojson"
    pixgeo("voronoi", "--sites", path, "--bbox", ",".join(map(str, BBOX)), "--size", 100,
           "--cells", out, "-o", tmp_path / "cells.svg")
    features = read_cells(out)
    assert [f["properties"]["site"] for f in features] == list(range(len(xy)))
    first = {}
    for i, p in enumerate(map(tuple, xy)):
        first.setdefault(p, i)
    cells = {}
    for f in features:
        i = f["properties"]["site"]
        assert f["properties"]["accuracy"] == "exact"
        if f["geometry"] is None:
            assert not frame.contains(Point(xy[i]))
            continue
        cell = shape(f["geometry"])
        assert cell.is_valid and cell.geom_type == "Polygon"
        assert shapely.is_ccw(cell.exterior)
        np.testing.assert_allclose(f["properties"]["area"], cell.area, rtol=1e-9)
        if first[tuple(xy[i])] != i:
            assert f["properties"]["same_as"] == first[tuple(xy[i])]
            continue
        cells[i] = cell
        if frame.contains(Point(xy[i])):
            assert cell.buffer(1e-6).contains(Point(xy[i]))
        # Random points of the cell are nearest to its site.
        lo = np.array(cell.bounds[:2])
        hi = np.array(cell.bounds[2:])
        q = rng.uniform(lo, hi, (200, 2))
        q = q[shapely.contains_xy(cell, q[:, 0], q[:, 1])]
        d = np.hypot(q[:, None, 0] - xy[:, 0], q[:, None, 1] - xy[:, 1])
        assert (d[:, i] <= d.min(axis=1) + 1e-6).all()
    np.testing.assert_allclose(sum(c.area for c in cells.values()), frame.area, rtol=1e-9)
    # Neighbours share their corners bit for bit, and the cells end at the box.
    assert shapely.coverage_is_valid(list(cells.values()))
    assert shapely.union_all(list(cells.values())).bounds == tuple(BBOX)
    # shapely's (GEOS's) Voronoi polygons of the same points, clipped: each
    # site's cell has the same area.
    theirs = shapely.voronoi_polygons(MultiPoint(xy), extend_to=frame)
    for poly in theirs.geoms:
        part = poly.intersection(frame)
        if part.is_empty:
            continue
        owners = [i for i in cells if poly.contains(Point(xy[i]))]
        if len(owners) == 1:
            np.testing.assert_allclose(cells[owners[0]].area, part.area, rtol=1e-6)
    svg = (tmp_path / "cells.svg").read_text()
    assert svg.startswith("<svg") and svg.count("<path") == len(cells)


def test_cells_where_four_sites_meet_form_a_coverage(tmp_path):
    """Four sites of a lattice of spacing 1/9 share one Voronoi vertex, and
    the box is a tenth beyond the unit square: each corner comes out once,
    shared, and the cells are clipped to the box as given."""
    path = tmp_path / "four.csv"
    path.write_text("x,y\n0.4444444444444444,0\n0.4444444444444444,0.1111111111111111\n"
                    "0.5555555555555556,0\n0.5555555555555556,0.1111111111111111\n")
    out = tmp_path / "cells.geojson"
    pixgeo("voronoi", "--sites", path, "--bbox=-0.1,-0.1,1.1,1.1", "--size", 60, "--cells", out)
    cells = [shape(f["geometry"]) for f in read_cells(out)]
    assert all(c.is_valid and len(c.exterior.coords) == 5 for c in cells)
    assert shapely.coverage_is_valid(cells)
    assert shapely.union_all(cells).bounds == (-0.1, -0.1, 1.1, 1.1)
    centre = set.intersection(*(set(c.exterior.coords) for c in cells))
    assert centre == {(0.5, 0.05555555555555555)}
    # 30 random points: a valid coverage too.
    rng = np.random.default_rng(30)
    np.savetxt(path, rng.uniform(0, 1, (30, 2)), delimiter=",", header="x,y", comments="")
    pixgeo("voronoi", "--sites", path, "--bbox", "0,0,1,1", "--size", 64, "--cells", out)
    cells = [shape(f["geometry"]) for f in read_cells(out)]
    assert shapely.coverage_is_valid(cells)
    np.testing.assert_allclose(sum(c.area for c in cells), 1.0, rtol=1e-12)


def test_traced_cells_and_triangles(tmp_path, sites):
    xy, path = sites
    box_text = ",".join(map(str, BBOX))
    out = tmp_path / "l1.geojson"
    pixgeo("voronoi", "--sites", path, "--bbox", box_text, "--size", 250, "--metric", "l1",
           "--cells", out, "--labels", tmp_path / "l1.npy", "--y-axis", "up")
    labels = np.load(tmp_path / "l1.npy")
    features = read_cells(out)
    frame = box(*BBOX)
    total = 0.0
    for f in features:
        assert f["properties"]["accuracy"] == "raster: within half a pixel"
        cell = shape(f["geometry"])
        assert cell.is_valid
        total += cell.area
        # The traced cell is the label's pixels: 4 m squares.
        assert abs(cell.area - 16.0 * (labels == f["properties"]["site"]).sum()) < 1e-6
    np.testing.assert_allclose(total, frame.area)
    # The Delaunay triangles as GeoJSON: they tile the points' hull.
    tri = tmp_path / "mesh.geojson"
    pixgeo("delaunay", "--sites", path, "--geojson", tri)
    triangles = read_cells(tri)
    hull = MultiPoint(xy).convex_hull
    area = sum(shape(t["geometry"]).area for t in triangles)
    np.testing.assert_allclose(area, hull.area, rtol=1e-9)
    assert all(len(t["properties"]["vertices"]) == 3 for t in triangles)


def test_alpha_hull_raster_in_a_box_and_fitted(tmp_path, sites):
    """The α-hull raster is placed like every raster: in the user's box with
    --bbox, north-up, or in the picture the command fits to the sites; the
    convex hull (α = 0) is the pixels whose centres shapely puts inside."""
    xy, path = sites
    hull = MultiPoint([tuple(p) for p in xy]).convex_hull
    for extra in (["--bbox", ",".join(map(str, BBOX)), "--size", 250], ["--size", 200]):
        tif = tmp_path / "hull.tif"
        done = pixgeo("alpha", "--sites", path, "--alpha", 0, "--hull", tif,
                      "--crs", "EPSG:32633", "--world-file", tmp_path / "hull.tfw",
                      "--json", *extra)
        frame = json.loads(done.stdout)["frame"]
        with rasterio.open(tif) as r:
            assert r.crs.to_epsg() == 32633
            inside, transform = r.read(1), r.transform
        if "--bbox" in extra:
            assert transform == Affine(4.0, 0.0, BBOX[0], 0.0, -4.0, BBOX[3])
        assert inside.shape == (frame["height"], frame["width"])
        assert frame["crs"] == "EPSG:32633"
        x, y = centres(transform, inside.shape)
        pts = shapely.points(x, y)
        truth = shapely.contains(hull, pts)
        # Pixel centres within a thousandth of a pixel of an edge may go
        # either way in float32.
        near = shapely.distance(hull.boundary, pts) < 1e-3 * abs(transform.a)
        assert ((inside == 1) == truth)[~near].all()
        assert inside[~near].sum() > 0
        lines = [float(v) for v in (tmp_path / "hull.tfw").read_text().split()]
        np.testing.assert_allclose(lines[:4], [transform.a, 0, 0, transform.e])


def test_transform_writes_geotiffs_placed_by_the_box(tmp_path):
    """`transform` writes its rasters as GeoTIFFs where --bbox puts the mask,
    with the distances SciPy computes and the same values as its .npy files."""
    from scipy import ndimage

    rng = np.random.default_rng(3)
    mask = rng.random((40, 50)) < 0.02
    mask[0, 0] = True
    np.save(tmp_path / "mask.npy", mask)
    box = "500000,4000000,500100,4000080"  # 2 m pixels
    names = ("distance", "indices", "components", "medial-axis")
    for ext in ("tif", "npy"):
        outputs = [a for n in names for a in (f"--{n}", tmp_path / f"{n}.{ext}")]
        done = pixgeo("transform", "--mask", tmp_path / "mask.npy", "--bbox", box,
                      "--crs", "EPSG:32633", "--world-file", tmp_path / "t.tfw",
                      "--json", *outputs)
    placed = json.loads(done.stdout)["result"]["georeference"]
    assert placed == {"bbox": [500000, 4000000, 500100, 4000080], "y_axis": "up",
                      "crs": "EPSG:32633"}
    truth = ndimage.distance_transform_edt(~mask)
    with rasterio.open(tmp_path / "distance.tif") as r:
        assert r.transform == Affine(2.0, 0.0, 500000.0, 0.0, -2.0, 4000080.0)
        assert r.crs.to_epsg() == 32633
        np.testing.assert_array_equal(r.read(1), truth)
    with rasterio.open(tmp_path / "indices.tif") as r:
        rows, columns = r.read(1), r.read(2)
    np.testing.assert_array_equal(np.stack([rows, columns]), np.load(tmp_path / "indices.npy"))
    r_, c_ = np.indices(mask.shape)
    assert mask[rows, columns].all()
    np.testing.assert_array_equal(np.hypot(rows - r_, columns - c_), truth)
    for name in ("components", "medial-axis"):
        with rasterio.open(tmp_path / f"{name}.tif") as r:
            np.testing.assert_array_equal(r.read(1), np.load(tmp_path / f"{name}.npy"))
    lines = [float(v) for v in (tmp_path / "t.tfw").read_text().split()]
    np.testing.assert_allclose(lines, [2, 0, 0, -2, 500001, 4000079])
    # Rows running north: row 0 is the box's south edge.
    pixgeo("transform", "--mask", tmp_path / "mask.npy", "--bbox", box, "--y-axis", "down",
           "--distance", tmp_path / "down.tif")
    with rasterio.open(tmp_path / "down.tif") as r:
        assert r.transform == Affine(2.0, 0.0, 500000.0, 0.0, 2.0, 4000000.0)


def test_transform_as_a_proximity_tool(tmp_path):
    """`transform` reads a GeoTIFF mask as GDAL writes it (LZW, tiled), picks
    the features by value, and writes distances in the georeferencing's units
    with a cut-off, placed where the mask lies: SciPy's distances bit for bit."""
    from scipy import ndimage

    rng = np.random.default_rng(1)
    cover = rng.integers(0, 20, (300, 400)).astype(np.uint8)
    cover[rng.random(cover.shape) < 0.995] = 0
    placed = Affine(10.0, 0.0, 500000.0, 0.0, -10.0, 4001000.0)
    with rasterio.open(tmp_path / "cover.tif", "w", driver="GTiff", width=400, height=300,
                       count=1, dtype="uint8", crs="EPSG:32633", transform=placed,
                       compress="lzw", tiled=True) as w:
        w.write(cover, 1)
    done = pixgeo("transform", "--mask", tmp_path / "cover.tif", "--values", "11,12",
                  "--distance-units", "geo", "--max-distance", 500,
                  "--distance", tmp_path / "d.tif", "--indices", tmp_path / "i.tif",
                  "--components", tmp_path / "c.tif", "--json")
    assert json.loads(done.stdout)["result"]["georeference"] == {
        "bbox": [500000, 3998000, 504000, 4001000], "y_axis": "up", "crs": "EPSG:32633"}
    features = np.isin(cover, [11, 12])
    truth, (rows, columns) = ndimage.distance_transform_edt(
        ~features, sampling=(10, 10), return_indices=True)
    far = truth > 500
    truth[far] = np.inf
    with rasterio.open(tmp_path / "d.tif") as r:
        assert r.transform == placed and r.crs.to_epsg() == 32633 and r.nodata == np.inf
        np.testing.assert_array_equal(r.read(1), truth)
    with rasterio.open(tmp_path / "i.tif") as r:
        assert r.nodata == -1
        got_rows, got_columns = r.read(1), r.read(2)
    assert (got_rows[far] == -1).all() and (got_columns[far] == -1).all()
    # Ties may pick another feature at the same distance.
    near = ~far
    r_, c_ = np.indices(cover.shape)
    np.testing.assert_allclose(np.hypot(got_rows - r_, got_columns - c_)[near] * 10,
                               truth[near], rtol=1e-15)
    with rasterio.open(tmp_path / "c.tif") as r:
        assert (r.read(1)[far] == 4294967295).all() and r.nodata == 4294967295
    # In pixels by default; --values reads every value given.
    pixgeo("transform", "--mask", tmp_path / "cover.tif", "--distance", tmp_path / "p.tif")
    with rasterio.open(tmp_path / "p.tif") as r:
        np.testing.assert_array_equal(r.read(1), ndimage.distance_transform_edt(cover == 0))
    for args, says in (
        (["--bbox", "0,0,1,1"], "its own georeferencing"),
        (["--crs", "EPSG:4326"], "EPSG:32633, not the EPSG:4326"),
        (["--distance-units", "geo", "--sampling", "2"], "give one"),
        (["--max-distance", "-1"], "0 or more"),
        (["--values", "nan"], "NaN equals no pixel value"),
    ):
        refused = subprocess.run([str(CLI), "transform", "--mask", str(tmp_path / "cover.tif"),
                                  "--distance", str(tmp_path / "x.tif"), *args],
                                 capture_output=True, text=True)
        assert refused.returncode == 1 and says in refused.stderr, (args, refused.stderr)
        assert not (tmp_path / "x.tif").exists()


def test_python_cells_are_the_command_lines_in_input_order(tmp_path):
    """`pixgeo.voronoi_cells` gives the exact cells without the command line:
    the same corners, bit for bit, as `voronoi --cells`, in input order, as
    shapely polygons or GeoJSON-like mappings, tiling the box."""
    import pixgeo

    rng = np.random.default_rng(8)
    xy = rng.uniform(0, 100, (60, 2))
    xy[9] = xy[4]  # a repeat shares the first one's cell
    square = (0.0, 0.0, 100.0, 100.0)
    cells = pixgeo.voronoi_cells(xy, bbox=square, crs="EPSG:32633")
    assert len(cells.polygons) == 60 and cells.crs == "EPSG:32633"
    assert cells.duplicates.tolist() == [[9, 4]]
    distinct = [c for i, c in enumerate(cells.polygons) if i != 9]
    assert sum(c.area for c in distinct) == pytest.approx(100 * 100, rel=1e-12)
    assert shapely.union_all(distinct).equals(box(*square))
    for i, cell in enumerate(cells.polygons):
        assert cell.covers(Point(xy[i]))
    np.savetxt(tmp_path / "s.csv", xy, delimiter=",", header="x,y", comments="", fmt="%.17g")
    from_cli = cli_cells(tmp_path, square)
    for i, feature in enumerate(from_cli):
        assert feature["properties"]["site"] == i
        ours = np.asarray(cells.polygons[i].exterior.coords)
        theirs = np.asarray(feature["geometry"]["coordinates"][0])
        np.testing.assert_array_equal(ours, theirs)
    assert len(cells) == 60 and cells[3] is cells.polygons[3]
    assert list(cells) == cells.polygons
    mappings = pixgeo.voronoi_cells(xy, bbox=square, geojson=True)
    assert shape(mappings.polygons[0]).equals(cells.polygons[0])
    features = mappings.__geo_interface__["features"]
    assert features[9]["properties"] == {"site": 9, "same_as": 4}
    # The triangulation as features: each triangle a Polygon of its vertices.
    t = pixgeo.delaunay(xy)
    for f, simplex in zip(t.features(), t.simplices):
        assert f["properties"]["vertices"] == list(simplex)
        assert shape(f["geometry"]).area == pytest.approx(
            shapely.Polygon(xy[simplex]).area, rel=1e-12)
    with pytest.raises(ValueError, match="flat"):
        pixgeo.voronoi_cells([[0, 0], [1, 0]])


def cli_cells(tmp_path, b):
    pixgeo("voronoi", "--sites", tmp_path / "s.csv", "--bbox", ",".join(map(str, b)),
           "--size", 100, "--y-axis", "down", "--cells", tmp_path / "c.geojson")
    return read_cells(tmp_path / "c.geojson")


def test_geojson_round_trips_features_properties_and_crs(tmp_path):
    """Cells carry their site's input feature (index and properties, pixgeo's
    own keys over them), in the input's crs; a --crs that contradicts it is
    refused; `delaunay --geojson --crs` names its system."""
    collection = {
        "type": "FeatureCollection",
        "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}},
        "features": [
            {"type": "Feature", "properties": {"name": "north", "site": "theirs"},
             "geometry": {"type": "Point", "coordinates": [500200, 4000600]}},
            {"type": "Feature", "properties": {"name": "pair", "staff": 3},
             "geometry": {"type": "MultiPoint", "coordinates": [[500700, 4000300], [500800, 4000700]]}},
            {"type": "Feature", "properties": None,
             "geometry": {"type": "Point", "coordinates": [500400, 4000100]}},
        ],
    }
    sites = tmp_path / "shops.geojson"
    sites.write_text(json.dumps(collection))
    box = ",".join(map(str, BBOX))
    done = pixgeo("voronoi", "--sites", sites, "--bbox", box, "--size", 100,
                  "--cells", tmp_path / "cells.geojson", "--labels", tmp_path / "l.tif", "--json")
    assert json.loads(done.stdout)["frame"]["crs"] == "EPSG:32633"
    with rasterio.open(tmp_path / "l.tif") as r:
        assert r.crs.to_epsg() == 32633
    written = json.loads((tmp_path / "cells.geojson").read_text())
    assert written["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::32633"
    props = [f["properties"] for f in written["features"]]
    assert [p["feature"] for p in props] == [0, 1, 1, 2]
    assert [p["site"] for p in props] == [0, 1, 2, 3]
    assert props[0]["name"] == "north" and props[2]["staff"] == 3 and "name" not in props[3]
    # Traced cells (another metric) carry them too.
    pixgeo("voronoi", "--sites", sites, "--bbox", box, "--size", 100, "--metric", "l1",
           "--cells", tmp_path / "l1.geojson")
    traced = json.loads((tmp_path / "l1.geojson").read_text())["features"]
    assert {f["properties"]["site"]: f["properties"]["feature"] for f in traced} == {0: 0, 1: 1, 2: 1, 3: 2}
    refused = subprocess.run([str(CLI), "voronoi", "--sites", str(sites), "--bbox", box,
                              "--crs", "EPSG:4326"], capture_output=True, text=True)
    assert refused.returncode == 1 and "not the EPSG:4326 of --crs" in refused.stderr
    pixgeo("delaunay", "--sites", sites, "--geojson", tmp_path / "t.geojson", "--crs", "EPSG:32633")
    triangles = json.loads((tmp_path / "t.geojson").read_text())
    assert triangles["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::32633"
    assert len(triangles["features"]) == 2


def test_results_as_georeferenced_xarray(tmp_path):
    """`to_xarray()` gives DataArrays on the pixel centres whose CRS and affine
    rioxarray reads; Dask results stay lazy and are placed the same way."""
    import pixgeo
    import pixgeo.dask  # noqa: F401
    import rioxarray  # noqa: F401  (the .rio accessor)

    rng = np.random.default_rng(4)
    xy = np.column_stack([rng.uniform(BBOX[0], BBOX[2], 30), rng.uniform(BBOX[1], BBOX[3], 30)])
    d = pixgeo.voronoi(xy, bbox=BBOX, res=8, crs="EPSG:32633")
    ds = d.to_xarray()
    labels = ds.labels
    assert labels.dims == ("y", "x") and labels.shape == (100, 125)
    assert labels.rio.crs.to_epsg() == 32633
    assert labels.rio.transform() == Affine(*d.frame.transform)
    assert labels.rio.nodata == pixgeo.NO_SITE
    x, y = d.frame.pixel_centres()
    np.testing.assert_array_equal(labels.x, x)
    np.testing.assert_array_equal(labels.y, y)
    labels.rio.to_raster(tmp_path / "labels.tif")
    with rasterio.open(tmp_path / "labels.tif") as r:
        assert r.crs.to_epsg() == 32633 and r.transform == Affine(*d.frame.transform)
        np.testing.assert_array_equal(r.read(1), d.labels)
    lazy = pixgeo.dask.voronoi(xy, bbox=BBOX, res=8, crs="EPSG:32633", chunks=(64, 64)).to_xarray()
    assert lazy.labels.chunks is not None
    assert lazy.labels.rio.crs.to_epsg() == 32633
    assert lazy.labels.rio.transform() == labels.rio.transform()
    np.testing.assert_array_equal(lazy.labels.values, d.labels)
    s = pixgeo.settle(xy, bbox=BBOX, res=8, crs="EPSG:32633").to_xarray()
    assert s.area.rio.crs.to_epsg() == 32633
    # Distances carry their nodata; every raster result reaches xarray.
    assert ds.distances.rio.nodata == np.inf
    ds.distances.rio.to_raster(tmp_path / "distances.tif")
    with rasterio.open(tmp_path / "distances.tif") as r:
        assert r.nodata == np.inf and np.array_equal(r.read(1), d.distances)
    power = pixgeo.power_diagram(xy, np.zeros(30), bbox=BBOX, res=8, crs="EPSG:32633").to_xarray()
    assert power.powers.rio.crs.to_epsg() == 32633 and power.labels.shape == (100, 125)
    z = pixgeo.natural_neighbor(xy, xy[:, 0], bbox=BBOX, res=8, crs="EPSG:32633")
    grid = pixgeo.frame(bbox=BBOX, res=8, crs="EPSG:32633").to_xarray(z=z)
    assert grid.z.rio.transform() == labels.rio.transform() and np.isnan(grid.z.rio.nodata)
    grid.z.rio.to_raster(tmp_path / "z.tif")
    with rasterio.open(tmp_path / "z.tif") as r:
        np.testing.assert_array_equal(r.read(1), z)
    with pytest.raises(ValueError, match="not the frame's"):
        d.frame.to_xarray(z=z[1:])


def test_great_circle_labels_and_distances_match_pyproj(tmp_path):
    """Under a geographic CRS, `voronoi` measures great circles on the
    Earth's mean sphere in metres: every label a nearest site and every
    distance that of pyproj's Geod on the same sphere, by brute force;
    across the antimeridian and up to a pole too. Degrees on the plane only
    on request, with a warning."""
    from pyproj import Geod

    sphere = Geod(a=6371008.8, b=6371008.8)
    rng = np.random.default_rng(3)
    for box, xy in (
        ((-30.0, 30.0, 40.0, 70.0), np.column_stack([rng.uniform(-30, 40, 25), rng.uniform(30, 70, 25)])),
        # Sites beyond the antimeridian and near the pole.
        ((160.0, 60.0, 200.0, 90.0), np.array([[170.0, 65.0], [-175.0, 70.0], [10.0, 89.5], [185.0, 80.0]])),
    ):
        np.savetxt(tmp_path / "s.csv", xy, delimiter=",", header="x,y", comments="", fmt="%.17g")
        done = pixgeo("voronoi", "--sites", tmp_path / "s.csv", "--bbox", ",".join(map(str, box)),
                      "--size", 120, "--crs", "EPSG:4326", "--labels", tmp_path / "l.tif",
                      "--distance", tmp_path / "d.tif", "--json")
        result = json.loads(done.stdout)["result"]
        assert result["metric"] == "great-circle" and result["sphere_radius_m"] == 6371008.8
        with rasterio.open(tmp_path / "l.tif") as r:
            labels, t = r.read(1), r.transform
            assert r.crs.to_epsg() == 4326
        with rasterio.open(tmp_path / "d.tif") as r:
            distances = r.read(1)
        lon, lat = centres(t, labels.shape)
        n = lon.size
        every = np.stack([sphere.inv(lon.ravel(), lat.ravel(), np.full(n, s[0]), np.full(n, s[1]))[2]
                          for s in xy], -1)
        best = every.min(axis=-1)
        mine = every[np.arange(n), labels.ravel().astype(np.int64)]
        assert np.all(mine - best <= 1e-6 + 1e-12 * best), np.max(mine - best)
        np.testing.assert_allclose(distances.ravel(), best, rtol=1.2e-7, atol=1e-6)
        # The device as a filter and the CPU's k-d tree: one answer, bit for bit.
        for device in ("cpu", "lavapipe"):
            done = pixgeo("voronoi", "--sites", tmp_path / "s.csv", "--bbox", ",".join(map(str, box)),
                          "--size", 120, "--crs", "EPSG:4326", "--labels", tmp_path / f"l-{device}.npy",
                          "--distance", tmp_path / f"d-{device}.npy", "--device", device, "--json")
            on = json.loads(done.stdout)
            assert on["device"].startswith("cpu" if device == "cpu" else "llvmpipe"), on["device"]
            np.testing.assert_array_equal(np.load(tmp_path / f"l-{device}.npy"), labels)
            np.testing.assert_array_equal(np.load(tmp_path / f"d-{device}.npy"), distances)
    planar = subprocess.run([str(CLI), "voronoi", "--sites", str(tmp_path / "s.csv"), "--bbox",
                             "160,60,200,90", "--crs", "EPSG:4326", "--metric", "l2",
                             "--labels", str(tmp_path / "p.tif")], capture_output=True, text=True)
    assert planar.returncode == 0 and "warning: EPSG:4326 is geographic" in planar.stderr
    refused = subprocess.run([str(CLI), "voronoi", "--sites", str(tmp_path / "s.csv"), "--bbox",
                              "160,60,200,90", "--crs", "EPSG:4326", "--ties", str(tmp_path / "t.npy")],
                             capture_output=True, text=True)
    assert refused.returncode == 1 and "not computed on the Earth" in refused.stderr


def test_python_great_circles_are_the_command_lines(tmp_path):
    """`pixgeo.voronoi` under a geographic crs: great circles by default, the
    command line's labels row for row, distances pyproj's on the sphere."""
    import warnings

    import pixgeo
    from pyproj import Geod

    rng = np.random.default_rng(9)
    xy = np.column_stack([rng.uniform(-20, 30, 15), rng.uniform(35, 65, 15)])
    box = (-20.0, 35.0, 30.0, 65.0)
    d = pixgeo.voronoi(xy, bbox=box, res=0.5, crs="EPSG:4326")
    assert d.labels.shape == (60, 100) and d.frame.crs == "EPSG:4326"
    np.savetxt(tmp_path / "s.csv", xy, delimiter=",", header="x,y", comments="", fmt="%.17g")
    done = subprocess.run([str(CLI), "voronoi", "--sites", str(tmp_path / "s.csv"), "--bbox",
                           ",".join(map(str, box)), "--size", "100", "--crs", "EPSG:4326",
                           "--labels", str(tmp_path / "l.npy")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    np.testing.assert_array_equal(np.load(tmp_path / "l.npy"), d.labels)
    lon, lat = np.meshgrid(*d.frame.pixel_centres())
    sphere = Geod(a=pixgeo.EARTH_RADIUS, b=pixgeo.EARTH_RADIUS)
    n = lon.size
    every = np.stack([sphere.inv(lon.ravel(), lat.ravel(), np.full(n, s[0]), np.full(n, s[1]))[2]
                      for s in xy], -1)
    np.testing.assert_allclose(d.distances.ravel(), every.min(axis=-1), rtol=1.2e-7, atol=1e-6)
    for device in ("cpu", "lavapipe"):
        on = pixgeo.voronoi(xy, bbox=box, res=0.5, crs="EPSG:4326", device=device)
        np.testing.assert_array_equal(on.labels, d.labels)
        np.testing.assert_array_equal(on.distances, d.distances)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pixgeo.voronoi(xy, bbox=box, res=0.5, crs="EPSG:4326", metric="l2")
    assert any("geographic" in str(w.message) for w in caught)
    with pytest.raises(ValueError, match="great-circle"):
        pixgeo.voronoi(xy, bbox=box, res=0.5, crs="EPSG:4326", mode="fan")
    # The problems solved on the plane alone say so under a geographic crs.
    for call in (lambda: pixgeo.k_nearest(xy, bbox=box, res=0.5, k=2, crs="EPSG:4326"),
                 lambda: pixgeo.settle(xy, bbox=box, res=0.5, crs="EPSG:4326")):
        with pytest.raises(ValueError, match="on the plane, not on the Earth"):
            call()
    with pytest.raises(ValueError, match=r"latitude in \[-90, 90\]"):
        pixgeo.voronoi(xy, bbox=(0, 0, 10, 100), res=1, crs="EPSG:4326")
    refused = subprocess.run([str(CLI), "voronoi", "--random", "5", "--bbox", "0,0,10,100",
                              "--crs", "EPSG:4326"], capture_output=True, text=True)
    assert refused.returncode == 1 and "latitude in [-90, 90]" in refused.stderr


GDAL_LAYOUTS = [
    (compress, predictor, dtype, tiled)
    for compress in ("none", "lzw", "deflate", "packbits")
    for predictor in (None, 2)
    for dtype in ("uint8", "int16", "uint16", "float32")
    for tiled in (True, False)
    if not (predictor and compress in ("none", "packbits"))
]


@pytest.mark.parametrize("compress,predictor,dtype,tiled", GDAL_LAYOUTS)
def test_geotiffs_as_gdal_writes_them_are_read_bit_for_bit(tmp_path, compress, predictor, dtype,
                                                          tiled):
    """A mask GDAL writes in each of its compressions (none, LZW, DEFLATE,
    PackBits, with and without the horizontal predictor), sample types and
    layouts (one 256-pixel tile over 232 rows, as the issue's crashing file;
    strips) is read value for value: the transform of value 1 equals SciPy's."""
    values = np.random.default_rng(5).integers(0, 4, (232, 256)).astype(dtype)
    layout = {"tiled": True, "blockxsize": 256, "blockysize": 256} if tiled else {}
    if predictor:
        layout["predictor"] = predictor
    path = tmp_path / "mask.tif"
    with rasterio.open(path, "w", driver="GTiff", width=256, height=232, count=1, dtype=dtype,
                       compress=compress, transform=from_origin(0, 232, 1, 1),
                       **layout) as out:
        out.write(values, 1)
    done = subprocess.run([str(CLI), "transform", "--mask", str(path), "--values", "1",
                           "--distance", str(tmp_path / "d.npy"), "-q"], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    want = ndimage.distance_transform_edt(values != 1)
    np.testing.assert_array_equal(np.load(tmp_path / "d.npy"), want)


def test_shapely_points_and_geoseries_are_points():
    """Sites given as an array of shapely Points (as a GeoSeries of points
    converts) are their coordinates; other geometries are refused with what
    to give."""
    import pixgeo

    xy = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 3.0], [5.0, 5.0]])
    want = pixgeo.delaunay(xy).simplices
    points = np.array([Point(p) for p in xy], dtype=object)
    assert np.array_equal(pixgeo.delaunay(points).simplices, want)
    with pytest.raises(ValueError, match="other than Points"):
        pixgeo.delaunay(np.array([box(0, 0, 1, 1)] * 3, dtype=object))


def test_one_geographic_rule(tmp_path):
    """Under EPSG:4326 nothing is planar in degrees unasked: cells on the
    sphere are refused with the reason (and given on the plane for
    metric='l2', with a warning); planar interpolation, Lloyd and power
    diagrams warn; the command line's geographic distance transform is
    refused."""
    import pixgeo

    xy = np.array([[10.0, 50.0], [11.0, 51.0], [12.0, 50.0], [11.0, 49.0]])
    for cells in (lambda **kw: pixgeo.voronoi_cells(xy, crs="EPSG:4326", **kw),
                  lambda **kw: pixgeo.power_cells(xy, np.zeros(4), crs="EPSG:4326", **kw)):
        with pytest.raises(ValueError, match="on the plane, not on the Earth"):
            cells()
        with pytest.warns(UserWarning, match="EPSG:4326 is geographic"):
            assert len(cells(metric="l2")) == 4
    box = dict(bbox=(9, 48, 13, 52), crs="EPSG:4326")
    for call in (lambda: pixgeo.natural_neighbor(xy, np.arange(4.0), (8, 8), **box),
                 lambda: pixgeo.lloyd(xy, (8, 8), iterations=1, **box),
                 lambda: pixgeo.power_diagram(xy, np.zeros(4), (8, 8), **box)):
        with pytest.warns(UserWarning, match="EPSG:4326 is geographic"):
            call()
    mask = tmp_path / "m.tif"
    with rasterio.open(mask, "w", driver="GTiff", width=8, height=8, count=1, dtype="uint8",
                       crs="EPSG:4326", transform=from_origin(10, 51, 0.5, 0.5)) as out:
        out.write(np.eye(8, dtype=np.uint8), 1)
    done = subprocess.run([str(CLI), "transform", "--mask", str(mask), "--distance-units", "geo",
                           "--distance", str(tmp_path / "d.tif")], capture_output=True, text=True)
    assert done.returncode == 1 and "not distances on the Earth" in done.stderr, done.stderr
    assert not (tmp_path / "d.tif").exists()


DELAUNATOR = Path(__file__).parent / "data" / "delaunator"


@pytest.mark.parametrize("name, scale, offset, bbox", [
    # The box in which cell 30's rounded ring crossed itself at (110, 170).
    ("robustness1", 1.0, 0.0, (4.5, 24.5, 190.5, 205.5)),
    ("robustness1", 2.0 ** -996, 0.0, None),
    ("robustness1", 2.0 ** 966, 0.0, None),
    ("robustness1", 1.0, 1e9, None),
    # At 1e15 the doubles are an eighth apart: thin cells flip when rounded.
    ("ukraine", 0.1, 1e15, None),
])
def test_rounded_cells_stay_valid_on_robustness_sets(tmp_path, name, scale, offset, bbox):
    """Every corner is the double nearest its exact corner, and where those
    would cross a ring over itself the crowded corners become one, shared:
    each cell is a valid counter-clockwise polygon and the cells a coverage,
    as shapely reads them (powers of two scaled back exactly)."""
    xy = np.array(json.loads((DELAUNATOR / f"{name}.json").read_text())) * scale + offset
    if bbox is None:
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        pad = 0.5 * (hi - lo).max()
        bbox = (lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad)
    path = tmp_path / "sites.csv"
    np.savetxt(path, xy, delimiter=",", fmt="%.17g")
    out = tmp_path / "cells.geojson"
    pixgeo("voronoi", "--sites", path, "--bbox=" + ",".join("%.17g" % v for v in bbox),
           "--size", 64, "--cells", out)
    _, first = np.unique(xy, axis=0, return_index=True)
    distinct = set(first.tolist())
    back = 1.0 / scale if offset == 0.0 else 1.0
    cells = [shapely.transform(shape(f["geometry"]), lambda c: c * back)
             for f in read_cells(out)
             if f["geometry"] is not None and f["properties"]["site"] in distinct]
    assert len(cells) > 0.9 * len(distinct)
    invalid = [i for i, c in enumerate(cells) if not c.is_valid or not shapely.is_ccw(c.exterior)]
    assert invalid == []
    assert shapely.coverage_is_valid(cells)
