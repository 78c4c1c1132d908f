"""The native layer under :mod:`pixgeo`; call the functions of :mod:`pixgeo` instead."""

from typing import List, Optional, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

class NoDeviceError(RuntimeError): ...
class DeviceError(RuntimeError): ...
class InternalError(RuntimeError): ...

_Frame = Tuple[int, int, float, float, float]
_Pair = Tuple[float, int, int]
_Circle = Tuple[float, float, float, List[int]]
_Points = npt.NDArray[np.float64]
_BBox = Optional[Tuple[float, float, float, float]]

def frame_of(width: int, height: int, bbox: _BBox) -> _Frame: ...
def distance_transform(
    features: npt.NDArray[np.bool_], sampling: Tuple[float, float], metric_name: str
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32]]: ...
def medial_axis(
    features: npt.NDArray[np.bool_], sampling: Tuple[float, float], metric_name: str,
    length: float, angle: float,
) -> Tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64]]: ...
def voronoi(
    sites: _Points, width: int, height: int, bbox: _BBox, metric_name: str, mode: str,
    device: Optional[str], window: Optional[Tuple[int, int, int, int]] = None,
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.float32], _Frame]: ...
def k_nearest(
    sites: _Points, width: int, height: int, k: int, bbox: _BBox, metric_name: str,
    mode: str, device: Optional[str],
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.float32], _Frame]: ...
def furthest(
    sites: _Points, width: int, height: int, bbox: _BBox, metric_name: str,
    device: Optional[str],
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.float32], _Frame]: ...
def delaunay(
    points: _Points, device: Optional[str]
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint32]]: ...
def find_simplex(
    points: _Points, simplices: npt.NDArray[np.uint32], xi: _Points
) -> npt.NDArray[np.int64]: ...
def cli(args: List[str]) -> int: ...
def is_geographic(code: int) -> bool: ...
def great_circle(
    sites: _Points, places: _Points
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.float64], int]: ...
EARTH_RADIUS: float
def voronoi_cells(
    points: _Points, bbox: Tuple[float, float, float, float], device: Optional[str]
) -> Tuple[List[npt.NDArray[np.float64]], npt.NDArray[np.uint32]]: ...
def hausdorff(a: _Points, b: _Points, device: Optional[str]) -> Tuple[float, _Pair, _Pair]: ...
def diameter(p: _Points, device: Optional[str]) -> _Pair: ...
def enclosing_circle(p: _Points, device: Optional[str]) -> _Circle: ...
def largest_empty_circle(
    p: _Points, region: List[_Points], device: Optional[str]
) -> _Circle: ...
def extremal_polygon(
    p: _Points, corners: int, largest: bool
) -> Tuple[npt.NDArray[np.uint32], float]: ...
def voronoi_weighted(
    sites: _Points, weights: _Points, width: int, height: int, bbox: _BBox, metric_name: str,
    mode: str, device: Optional[str],
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.float32], _Frame]: ...
def alpha_hull_of(
    p: _Points, alpha: float, side: int, method: str, device: Optional[str]
) -> Tuple[npt.NDArray[np.uint8], _Frame, List[int], str]: ...
def lloyd(
    sites: _Points, width: int, height: int, bbox: _BBox, iterations: int,
    tolerance: Optional[float], density: Optional[npt.NDArray[np.float64]], device: Optional[str],
) -> Tuple[
    npt.NDArray[np.float64], npt.NDArray[np.uint32], _Frame, List[Tuple[float, float]], float, bool, int
]: ...
def interpolate(
    sites: _Points, values: npt.NDArray[np.float64], width: int, height: int, bbox: _BBox,
    method: str, device: Optional[str], window: Optional[Tuple[int, int, int, int]] = None,
) -> npt.NDArray[np.float64]: ...
def interpolate_at(
    sites: _Points, values: npt.NDArray[np.float64], at: _Points, method: str, device: Optional[str],
) -> npt.NDArray[np.float64]: ...
def power_diagram(
    sites: _Points, weights: npt.NDArray[np.float64], width: int, height: int, bbox: _BBox,
    window: Optional[Tuple[int, int, int, int]] = None,
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.float64], List[int]]: ...
def regular_triangulation(
    sites: _Points, weights: npt.NDArray[np.float64],
) -> Tuple[npt.NDArray[np.uint32], List[int]]: ...
def settle(
    rivals: _Points, own: _Points, width: int, height: int, bbox: _BBox, metric_name: str,
    refine_from: int, device: Optional[str],
) -> Tuple[npt.NDArray[np.uint32], _Frame, int, Optional[Tuple[float, float, float]]]: ...
