"""The parameters many of pixgeo's functions share, written once and filled
into their numpydoc sections where a line holds ``{name}``."""

from __future__ import annotations

PARTS = {
    "placement": """\
shape : tuple of int, optional
    ``(H, W)``: the picture's rows and columns. Without ``bbox``, world and
    pixel coordinates agree (pixel (i, j) centred at (i, j)).
bbox : tuple of float, optional
    ``(xmin, ymin, xmax, ymax)``, the rectangle the picture fills (pixels
    are square, so ``H`` must match its aspect ratio to within a pixel).
    With a bbox the rasters are north-up: row 0 holds the largest y.
res : float, optional
    The pixels' side, instead of ``shape``: ``bbox=(0, 0, 1000, 800),
    res=10`` is 80 x 100 pixels.
y_axis : {"up", "down"}, optional
    ``"down"`` puts the smallest y in row 0.
crs : str, optional
    ``"EPSG:N"`` (or anything pyproj reads), carried to the frame; a
    geographic one makes x and y longitude and latitude.""",
    "device": """\
device : str, optional
    ``"auto"``, ``"cpu"``, ``"lavapipe"``, ``"gpu"``, an index or part of a
    name (default: ``PIXGEO_DEVICE``, else ``"auto"``). Every device gives
    the same answer; ``"auto"`` falls back to the CPU, with a
    ``RuntimeWarning``, where no Vulkan device starts.""",
    "metric": """\
metric : str, optional
    ``"l2"`` (the default on the plane), ``"l1"``, ``"linf"``, ``"lp:P"`` or
    ``"polygon:FILE"``; ``"great-circle"`` (the default under a geographic
    ``crs``) measures metres along great circles of the Earth.""",
    "planar_metric": """\
metric : str, optional
    ``"l2"`` (the default), ``"l1"``, ``"linf"``, ``"lp:P"`` or
    ``"polygon:FILE"``. Under a geographic ``crs`` a metric must be asked
    for: it measures degrees (great circles are :func:`voronoi`'s).""",
    "mode": """\
mode : str, optional
    ``"exact"`` (every pixel's nearest site, ties to the smaller index), or
    the thesis's triangle fans: ``"fan"`` (distance error within a pixel)
    or ``"fan:T"`` with T triangles a cone.""",
    "points": """\
points : array_like, shape (n, 2)
    Finite x, y coordinates; a GeoSeries or an array of shapely points is
    taken too.""",
    "sites": """\
sites : array_like, shape (n, 2)
    Finite x, y coordinates.""",
    "extremal": """\
Parameters
----------
{points}

Returns
-------
tuple of (ndarray, float)
    The vertex indices counter-clockwise, and the area, exact.""",
}


def _expand(line: str) -> list:
    """``line``, or the shared text it names at its indentation, its own
    names expanded in turn."""
    name = line.strip()
    if not (name.startswith("{") and name.endswith("}") and name[1:-1] in PARTS):
        return [line]
    indent = line[: len(line) - len(line.lstrip())]
    return [l for part in PARTS[name[1:-1]].split("\n") for l in _expand(indent + part)]


def fill(function):
    """``function`` with each line ``{name}`` of its docstring replaced by
    the shared text, at that line's indentation."""
    lines = function.__doc__.split("\n")
    function.__doc__ = "\n".join(l for line in lines for l in _expand(line))
    return function
