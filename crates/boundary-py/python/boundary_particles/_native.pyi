# Types of the compiled module (crates/boundary-py/src/lib.rs), checked against it by
# `python -m mypy.stubtest boundary_particles._native` in the tests. Documented in the package
# (`boundary_particles/__init__.py`), which is the only caller.

from os import PathLike
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Detector",
    "FEATURES",
    "RADIUS_PER_SPACING",
    "Tracker",
    "__version__",
    "_points_address",
    "auto_radius_of",
    "bulk_spacing_of",
    "confusion",
    "methods",
    "read",
    "resample",
    "write",
]
__version__: str
FEATURES: Dict[int, str]
RADIUS_PER_SPACING: float

@final
class Detector:
    def __new__(
        cls,
        method: str = "exact",
        threads: Optional[int] = None,
        params: Optional[Mapping[str, Any]] = None,
    ) -> Detector: ...
    @property
    def method(self) -> str: ...
    @property
    def threads(self) -> Optional[int]: ...
    @property
    def certified(self) -> bool: ...
    def settings(self) -> List[Tuple[str, str]]: ...
    def label(self) -> str: ...
    def detect(
        self,
        points: Any,
        r: Optional[Union[float, str]] = None,
        margin: bool = False,
        radii: Any = None,
        walls: Any = None,
        wall_radii: Any = None,
        solids: Any = None,
        periodic: Any = None,
        phases: Any = None,
        dim: Optional[int] = None,
        *,
        h: Any = None,
        spacing: Any = None,
    ) -> Any: ...
    def _detect_timed(self, points: Any, r: float) -> Tuple[NDArray[np.bool_], float]: ...

@final
class Tracker:
    def __new__(
        cls,
        r: Optional[Union[float, str]] = None,
        method: str = "exact",
        threads: Optional[int] = None,
        *,
        h: Any = None,
        spacing: Any = None,
        walls: Any = None,
        wall_radii: Any = None,
        solids: Any = None,
        periodic: Any = None,
        **params: Any,
    ) -> Tracker: ...
    @property
    def recomputed(self) -> int: ...
    def update(
        self,
        points: Any = None,
        ids: Any = None,
        *,
        columns: Any = None,
        radii: Any = None,
        walls: Any = None,
        wall_radii: Any = None,
        phases: Any = None,
        dim: Optional[int] = None,
    ) -> Any: ...

def auto_radius_of(points: Any, dim: Optional[int] = None) -> float: ...
def bulk_spacing_of(points: Any, dim: Optional[int] = None) -> float: ...
def _points_address(points: Any) -> int: ...
def confusion(predicted: Any, truth: Any) -> Dict[str, Union[int, float]]: ...
def methods() -> List[Dict[str, Any]]: ...
def read(
    path: Union[str, PathLike[str]],
    dim: Optional[int] = None,
    format: Optional[str] = None,
    array: Optional[str] = None,
) -> Tuple[NDArray[np.float64], Dict[str, NDArray[Any]]]: ...
def write(
    path: Union[str, PathLike[str]],
    points: Any,
    boundary: Any = None,
    point_data: Optional[Mapping[str, Any]] = None,
    format: Optional[str] = None,
    dim: Optional[int] = None,
) -> None: ...
def resample(
    points: Any,
    r: Optional[Union[float, str]],
    detector: Detector,
    k: int = 4,
    alpha: float = 0.2,
    shift: float = 0.5,
    labels: Any = None,
    *,
    h: Any = None,
    spacing: Any = None,
) -> Tuple[NDArray[np.float64], NDArray[np.int8], NDArray[np.int64]]: ...
