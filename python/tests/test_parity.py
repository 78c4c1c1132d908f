"""The Python package answers as the command line does, bit for bit, with and
without a device: the nearest and furthest sites and the Delaunay triangles
of the parity generator's kinds of input (uniform, clustered, a lattice whose
pixels tie, the lattice nudged by one ulp, repeats, a line), each moved by
1e9 and 1e15 and scaled by 1e-300, 1e300 and 0.1 with its picture."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import pixgeo

ROOT = Path(__file__).resolve().parents[2]
CLI = Path(os.environ.get("PIXGEO_CLI", ROOT / "target" / "debug" / "pixgeo"))
W, H = 28, 20


def kinds():
    rng = np.random.default_rng(67)
    uniform = lambda n: rng.uniform(-0.5, [W - 0.5, H - 0.5], (n, 2))
    lattice = np.array([[i * 4 + 1.0, j * 4 + 2.0] for j in range(H // 4) for i in range(W // 4)])
    nudged = lattice.copy()
    nudged[::3, 0] = np.nextafter(nudged[::3, 0], np.inf)
    nudged[::3, 1] = np.nextafter(nudged[::3, 1], -np.inf)
    repeats = uniform(10)
    repeats = np.vstack([repeats, repeats[2:6], repeats[:1]])
    centres = uniform(4)
    clustered = centres[np.arange(24) % 4] + rng.uniform(-4, 4, (24, 2))
    line = np.array([[1.5 + 2.5 * i, 1.0 + 1.75 * i] for i in range(9)])
    return {"uniform": uniform(30), "clustered": clustered, "lattice": lattice,
            "lattice ±1 ulp": nudged, "repeats": repeats, "line": line}


CASES = [
    (f"{kind}{moved}", sites * scale + offset,
     (-0.5 * scale + offset, -0.5 * scale + offset,
      (W - 0.5) * scale + offset, (H - 0.5) * scale + offset))
    for kind, sites in kinds().items()
    for moved, scale, offset in [("", 1.0, 0.0), (" + 1e9", 1.0, 1e9), (" + 1e15", 1.0, 1e15),
                                 (" × 1e-300", 1e-300, 0.0), (" × 1e300", 1e300, 0.0),
                                 (" × 0.1", 0.1, 0.0)]
]


def cli(*args):
    done = subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.mark.parametrize("device", ["cpu", "lavapipe"])
def test_python_answers_as_the_command_line_on_every_route(tmp_path, device):
    sites, labels, distances = tmp_path / "s.npy", tmp_path / "l.npy", tmp_path / "d.npy"
    for name, xy, bbox in CASES:
        np.save(sites, xy)
        for extra, call in (([], pixgeo.voronoi), (["--furthest"], pixgeo.furthest)):
            ours = call(xy, (H, W), bbox=bbox, y_axis="down", device=device)
            cli("voronoi", "--sites", sites, "--bbox", ",".join(map(repr, bbox)),
                "--size", f"{W}x{H}", "--y-axis", "down", "--device", device,
                "--labels", labels, "--distance", distances, *extra)
            assert np.array_equal(ours.labels, np.load(labels)), (name, extra)
            assert np.array_equal(ours.distances.view(np.uint32),
                                  np.load(distances).view(np.uint32)), (name, extra)
        try:
            ours = pixgeo.delaunay(xy, device=device).simplices.tolist()
        except ValueError as e:
            ours = str(e)
        done = subprocess.run([str(CLI), "delaunay", "--sites", str(sites), "--device", device,
                               "--json"], capture_output=True, text=True)
        theirs = (json.loads(done.stdout)["result"]["triangles"] if done.returncode == 0
                  else done.stderr)
        if isinstance(ours, str):
            assert ours in theirs, name
        else:
            assert ours == theirs, name
