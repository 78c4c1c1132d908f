"""The package's metadata says what its tests need: every module the tests
import is the standard library's, pixgeo's, or a distribution in the `test`
extra."""

import ast
import re
import sys
from pathlib import Path

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

import pytest

HERE = Path(__file__).resolve().parent
# Modules whose distribution has another name.
DISTRIBUTION = {"skimage": "scikit-image", "dask": "dask"}


@pytest.mark.skipif(tomllib is None, reason="tomllib is Python 3.11's")
def test_the_test_extra_holds_what_the_tests_import():
    project = tomllib.loads((HERE.parent / "pyproject.toml").read_text())["project"]
    extra = {re.split(r"[\[<>=]", d)[0] for d in project["optional-dependencies"]["test"]}
    imported = set()
    for path in HERE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                imported |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                imported.add(node.module.split(".")[0])
            elif (isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "importorskip"
                  and isinstance(node.args[0], ast.Constant)):
                imported.add(node.args[0].value.split(".")[0])
    needed = {DISTRIBUTION.get(m, m) for m in imported
              if m not in sys.stdlib_module_names and m not in ("pixgeo", "numpy", "tomllib")}
    assert needed <= extra, needed - extra


def test_the_package_installs_the_command_line(tmp_path):
    """`pip install` puts the `pixgeo` command beside Python: the command line
    itself, compiled into the package, answering and refusing as the binary."""
    import json
    import shutil
    import subprocess
    import sysconfig

    import pixgeo

    script = Path(sysconfig.get_path("scripts")) / "pixgeo"
    assert script.exists() or shutil.which("pixgeo"), "no pixgeo console script"
    command = [str(script)] if script.exists() else ["pixgeo"]
    done = subprocess.run([*command, "--version"], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == f"pixgeo {pixgeo.__version__}"
    labels = tmp_path / "l.npy"
    done = subprocess.run(
        [sys.executable, "-m", "pixgeo", "voronoi", "--random", "5", "--size", "16",
         "--labels", str(labels), "--json"],
        capture_output=True, text=True, check=True)
    assert json.loads(done.stdout)["command"] == "voronoi"
    import numpy as np
    assert np.load(labels).shape == (16, 16)
    refused = subprocess.run([*command, "voronoi", "--sites", str(tmp_path / "none.csv")],
                             capture_output=True, text=True)
    assert refused.returncode == 1 and refused.stderr.startswith("Error:")


def test_the_wheel_carries_its_licenses():
    """The installed distribution states its SPDX licence and holds both
    licence texts."""
    from importlib import metadata

    meta = metadata.metadata("pixgeo")
    assert meta["License-Expression"] == "MIT OR Apache-2.0"
    assert sorted(meta.get_all("License-File")) == ["LICENSE-APACHE", "LICENSE-MIT"]
    texts = [f for f in metadata.files("pixgeo") if f.name.startswith("LICENSE-")]
    assert {f.name for f in texts} == {"LICENSE-APACHE", "LICENSE-MIT"}
    assert all("Copyright" in f.read_text() or "Apache" in f.read_text() for f in texts)


def test_the_namespace_shows_what_pixgeo_offers():
    """``dir(pixgeo)`` (what completion offers) lists the public names, not
    the modules pixgeo imports for itself; every one of them is there."""
    import pixgeo

    shown = dir(pixgeo)
    assert not {"np", "sys", "Optional", "dataclass", "functools"} & set(shown)
    assert {"voronoi", "delaunay", "natural_neighbor", "__version__"} <= set(shown)
    assert all(hasattr(pixgeo, name) for name in pixgeo.__all__)


def test_every_function_documents_its_parameters_in_numpydoc_sections():
    import inspect

    import pixgeo
    from pixgeo import _docs

    functions = [getattr(pixgeo, name) for name in pixgeo.__all__]
    functions = [f for f in functions if inspect.isfunction(f)]
    assert len(functions) > 20
    for f in functions:
        doc = inspect.getdoc(f)
        assert "\nParameters\n----------\n" in doc, f.__name__
        assert "\nReturns\n-------\n" in doc, f.__name__
        assert not any("{%s}" % part in doc for part in _docs.PARTS), f.__name__
        section = doc.split("\nParameters\n----------\n")[1].split("\nReturns\n")[0]
        # Each parameter names a line of its own: "name : type" or a list
        # of names sharing one.
        named = set()
        for line in section.split("\n"):
            if line and not line.startswith(" "):
                named.update(n.strip() for n in line.split(" : ")[0].split(","))
        missing = set(inspect.signature(f).parameters) - named
        assert not missing, f"{f.__name__}: {sorted(missing)}"
