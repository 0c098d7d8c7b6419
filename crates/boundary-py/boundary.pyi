"""Boundary particles of meshfree particle sets (SPH, PBF, FLIP/APIC, MPS).

Particle *i* at *p_i* with resolution *r* is **interior** iff its sphere *S_i* of radius *r* is
covered by the closed balls of radius *r* of the other particles within *2r*; otherwise it is
**boundary** (Sandim, Paiva & Figueiredo, "A fast and accurate method for boundary particle
detection", J. Comput. Phys. 2020). Coincident duplicates do not cover each other.

Every method of the Rust library is available by name (see :func:`methods`):

- ``exact``: restricted Voronoi cell per particle, the reference labels (JCP 2020 Sec. 2);
- ``dilts``: arc / cap covering (Dilts 2000; Haque & Dilts 2007), certified;
- ``ia``: interval-arithmetic quadtree / octree (JCP 2020 Sec. 3.1), never a false negative;
- ``ge``: geometric-enclosure slabs (JCP 2020 Sec. 3.2), never a false negative;
- ``marrone``: SPH renormalisation-matrix eigenvalue and scan cone (Marrone et al., JCP 2010);
- ``muller``: SPH colour-field gradient (Mueller et al., SCA 2003);
- ``hpr``: hidden point removal (Sandim 2020 thesis, ch. 2, Alg. 1);
- ``svm``: RBF support vector machine on SPH features (Sandim 2020 thesis, ch. 3).

Conventions shared by every function:

- ``points`` is any ``(n, 2)`` or ``(n, 3)`` array-like of reals. A C-contiguous ``float64``
  array is read in place (no intermediate copy); ``float32``, Fortran-ordered arrays and lists
  are converted by NumPy first. A 2D set has no z.
- Detection releases the GIL and runs on all cores (rayon), or on ``threads`` worker threads.
  Ctrl-C raises ``KeyboardInterrupt`` within 50 ms; the interrupted detection keeps running in
  the background until it ends (it cannot be cancelled midway), and its result is discarded.
- Method parameters are keyword arguments, exactly as ``--set KEY=VALUE`` on the command line
  (``detect(points, r, "ge", depth=4)``); ``True``/``False`` become ``true``/``false``.
- A radius per particle (adaptive resolution): ``radii`` is an ``(n,)`` array-like of radius
  factors ``s_i`` (converted like ``points``); particle *i* then has radius ``r_i = r * s_i``,
  and ``r`` defaults to 1 (the radii as given; the CLI's ``--radius-attribute`` with
  ``--radius-scale r``). Without ``radii``, ``r`` is required. Particle *i* is interior iff
  its sphere of radius ``r_i`` is covered by the balls of radius ``r_j`` of the others. A
  method without per-particle support raises ``ValueError`` saying so.
- A simulation's domain (:func:`detect`): ``walls`` are covering-only particles (a solver's
  fixed boundary particles: they cover, and get no label), ``solids`` closed solid
  half-spaces such as ``"y<0"`` (the solid ``{y <= 0}``: what lies in it counts as covered),
  ``periodic`` periodic axes such as ``"x:0:1"`` (images of every particle cover across the
  period), ``phases`` a phase number per particle (interface labels besides the free
  surface).
- A flat ``(n, 3)`` set (every particle with the same z, or y, or x; or all at one place) raises
  ``ValueError``: read as 3D, every particle of it would be boundary. The message names the
  2D slice to pass instead (``points[:, :2]`` when z is constant). Walls may be flat.
- Errors raise ``ValueError`` (bad shape, non-finite coordinate, a flat 3D set, ``r <= 0``, a
  bad radius, naming the particle, unknown method or parameter, malformed file) or ``OSError`` (a file
  that cannot be opened or written), with the message the ``boundary`` command prints.
"""

from os import PathLike
from typing import (
    Any,
    Dict,
    List,
    Literal,
    Optional,
    Sequence,
    Tuple,
    TypedDict,
    Union,
    overload,
)

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

#: Feature codes of :func:`resample` (thesis Eq. 2.5): -1 interior, 0 droplet, 1 ligament,
#: 2 sheet, 3 regular boundary particle.
FEATURES: Dict[int, str]

_Path = Union[str, "PathLike[str]"]
_Param = Union[str, int, float, bool]

class ParamInfo(TypedDict):
    name: str
    default: str
    description: str

class MethodInfo(TypedDict):
    name: str
    summary: str
    certified: bool
    params: List[ParamInfo]

class Score(TypedDict):
    TP: int
    TN: int
    FP: int
    FN: int
    Rec: float
    FPR: float
    M: float

_Labels = NDArray[np.bool_]
_Margin = Optional[NDArray[np.float64]]
_Texts = Union[str, Sequence[str]]

@overload
def detect(
    points: ArrayLike,
    r: Optional[float] = None,
    method: str = "exact",
    threads: Optional[int] = None,
    margin: Literal[False] = False,
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[_Texts] = None,
    periodic: Optional[_Texts] = None,
    phases: None = None,
    **params: _Param,
) -> _Labels: ...
@overload
def detect(
    points: ArrayLike,
    r: Optional[float] = None,
    method: str = "exact",
    threads: Optional[int] = None,
    *,
    margin: Literal[True],
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[_Texts] = None,
    periodic: Optional[_Texts] = None,
    phases: None = None,
    **params: _Param,
) -> Tuple[_Labels, _Margin]: ...
@overload
def detect(
    points: ArrayLike,
    r: Optional[float] = None,
    method: str = "exact",
    threads: Optional[int] = None,
    margin: Literal[False] = False,
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[_Texts] = None,
    periodic: Optional[_Texts] = None,
    *,
    phases: ArrayLike,
    **params: _Param,
) -> Tuple[_Labels, _Labels]: ...
@overload
def detect(
    points: ArrayLike,
    r: Optional[float] = None,
    method: str = "exact",
    threads: Optional[int] = None,
    *,
    margin: Literal[True],
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[_Texts] = None,
    periodic: Optional[_Texts] = None,
    phases: ArrayLike,
    **params: _Param,
) -> Tuple[_Labels, _Margin, _Labels]: ...
def detect(
    points: ArrayLike,
    r: Optional[float] = None,
    method: str = "exact",
    threads: Optional[int] = None,
    margin: bool = False,
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[_Texts] = None,
    periodic: Optional[_Texts] = None,
    phases: Optional[ArrayLike] = None,
    **params: _Param,
) -> Union[
    _Labels,
    Tuple[_Labels, _Margin],
    Tuple[_Labels, _Labels],
    Tuple[_Labels, _Margin, _Labels],
]:
    """Labels every particle: ``True`` on the boundary, ``False`` inside.

    Args:
        points: ``(n, 2)`` or ``(n, 3)`` positions.
        r: the particle resolution (positive, finite), in the positions' length unit;
            required without ``radii``. With ``radii``, the scale of every radius
            (``r_i = r * radii[i]``), default 1.
        method: a name from :func:`methods` (default ``exact``, the reference labels of
            Sandim et al., JCP 2020).
        threads: worker threads (default: all cores).
        margin: also return the method's per-particle margin (positive leans boundary,
            negative interior, near zero a near-tie; for ``exact`` the distance by which the
            particle's Voronoi cell reaches beyond ``r``), or ``None`` when the method has none.
        radii: optional ``(n,)`` radius factors, one per particle, each positive and finite
            (a C-contiguous float64 array is read in place; anything else is converted).
        walls: optional ``(m, d)`` covering-only particles of the points' dimension ``d``
            (converted to float64): they cover the points' spheres and get no label. The
            labels of ``points`` are those of the union ``points + walls`` restricted to
            ``points``.
        wall_radii: optional ``(m,)`` radius factors of the walls (``r * wall_radii[j]``);
            without them a wall has the factor 1 (radius ``r``). Only with ``walls``.
        solids: closed axis-aligned solid half-spaces: one string or a sequence of strings
            ``"AXIS<VALUE"`` / ``"AXIS>VALUE"`` (``"y<0"``: the solid ``{y <= 0}``, a floor).
            What lies in a solid counts as covered: a particle resting on a floor is boundary
            by its upper half, one whose sphere is inside the solid is interior. Only methods
            with a rule for solids accept them (``exact``); the others raise ``ValueError``
            saying so (use ``walls`` with them).
        periodic: periodic axes: one string or a sequence of strings ``"AXIS:MIN:MAX"``
            (``"x:0:1"``): the images of every particle (and wall) shifted by
            ``±(MAX - MIN)`` cover. Every particle must lie in ``[MIN, MAX]`` and the period
            must be at least the method's reach (``2r`` for most); an axis cannot be both
            periodic and bounded by a solid.
        phases: optional ``(n,)`` integer phase numbers (``0 .. 2**32 - 1``), one per
            particle. The labels stay those of the free surface (all phases cover); the
            interface labels are returned besides them (see Returns).
        **params: the method's parameters (``depth=4``, ``gamma=1.3``, ...).

    Returns:
        A ``bool`` array of length ``n``; with ``margin=True`` the pair ``(labels, margin)``.
        With ``phases``, the ``bool`` interface labels of length ``n`` come last:
        ``(labels, interface)``, or ``(labels, margin, interface)`` with ``margin=True``.
        ``interface[i]`` is ``True`` for a particle on an interface between phases: not on
        the free surface, but uncovered once only its own phase (its images, the walls and
        the solids) may cover.

    Raises:
        ValueError: bad shape, a non-finite coordinate, a flat ``(n, 3)`` set (the message
            names the 2D slice to pass, e.g. ``points[:, :2]``), ``r <= 0``, a radius that is not
            positive and finite (``radii: particle 3: radius must be positive and finite, got
            -1``), ``radii`` of the wrong length or not one-dimensional, a method without
            per-particle radii, an unknown method or parameter; a bad domain: ``walls`` not of
            shape ``(m, d)``, a malformed solid or periodic text (quoted in the message), a
            solid or periodic axis the points lack, a particle outside a periodic range, a
            period shorter than the reach, ``phases`` of the wrong length or not integers in
            range, a method that cannot honour solids.
        TypeError: ``r`` missing without ``radii``; ``solids`` or ``periodic`` not strings.
        KeyboardInterrupt: Ctrl-C during the detection.
    """

@overload
class Tracker:
    """Labels the particles of successive time steps, each as `detect(points, r)` would,
    recomputing only the particles whose label may have changed since the previous step.

    r: the particle resolution (> 0); method: "exact" (the only method with a tracker);
    threads: worker threads (default: all cores); **params: the method's parameters (exact:
    tie must stay 0). Raises ValueError for another method, a tie, r <= 0 or bad points.
    """

    recomputed: int
    """How many particles the last update recomputed."""

    def __init__(
        self,
        r: float,
        method: str = "exact",
        threads: Optional[int] = None,
        **params: _Param,
    ) -> None: ...
    def update(self, points: ArrayLike) -> NDArray[np.bool_]:
        """The labels (True = boundary) of this step's positions, an (n, 2) or (n, 3)
        array-like: the same particles in the same order as before (another count starts
        over)."""
        ...

def score(
    points: ArrayLike,
    r: float,
    method: str,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: Optional[ArrayLike] = None,
    **params: _Param,
) -> Score: ...
@overload
def score(
    points: ArrayLike,
    r: float = 1.0,
    *,
    method: str,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: ArrayLike,
    **params: _Param,
) -> Score: ...
def score(
    points: ArrayLike,
    r: Optional[float] = None,
    method: Optional[str] = None,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: Optional[ArrayLike] = None,
    **params: _Param,
) -> Score:
    """Scores ``method`` against the truth: ``TP, TN, FP, FN, Rec, FPR, M``.

    Boundary is the positive class. ``Rec = TP/(TP+FN)``, ``FPR = FP/(FP+TN)``,
    ``M = Rec * (1 - FPR)`` (JCP 2020 Sec. 4).

    Args:
        method: required (by keyword when ``r`` is left to its default with ``radii``).
        truth: one boolean (or 0/1) per particle; default: the ``exact`` labels (with the
            same radii).
        r, radii, threads, **params: as :func:`detect`.
    """

def methods() -> List[MethodInfo]:
    """Every available method with its summary, whether it is certified, and its parameters
    with their defaults (the data of ``boundary methods --json``)."""

def read(
    path: _Path, dim: Optional[int] = None, format: Optional[str] = None
) -> Tuple[NDArray[np.float64], Dict[str, NDArray[Any]]]:
    """Reads a particle file: ``(points, attributes)``.

    Formats: CSV (header ``x,y[,z]``), whitespace XYZ, PLY, legacy VTK, VTK XML ``.vtu`` /
    ``.vtp``, Houdini BGEO (``.bgeo``, ``.bgeo.gz``), by extension or ``format``. ``points`` is
    ``(n, dim)`` float64; ``attributes`` maps every other per-particle attribute (a vector as
    ``name:0``, ``name:1``, ...) to an int64 or float64 array. ``dim=2`` drops the constant
    axis of a 3D file. Attributes the file has but that cannot be kept raise a ``UserWarning``.
    """

def write(
    path: _Path,
    points: ArrayLike,
    boundary: Optional[ArrayLike] = None,
    format: Optional[str] = None,
    **attributes: ArrayLike,
) -> None:
    """Writes ``points`` with an optional ``boundary`` column (0/1) and one column per
    keyword attribute (integers stay integers, anything else is written as reals), in the
    format of the extension or ``format``; VTK XML joins ``name:k`` into one vector array.
    Atomic: the file appears whole or not at all (a failed write leaves no file, and a file
    already at ``path`` stays as it was)."""

def resample(
    points: ArrayLike,
    r: float,
    method: str = "exact",
    k: int = 4,
    alpha: float = 0.2,
    shift: float = 0.5,
    labels: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    **params: _Param,
) -> Tuple[NDArray[np.float64], NDArray[np.int8], NDArray[np.int64]]:
    """Classifies the boundary particles by feature and resamples thin features (Sandim et
    al., Computers & Graphics 2019; thesis Sec. 2.6, Eq. 2.4-2.5).

    Boundary particles come from ``method`` (with ``**params``) or from ``labels``. A droplet
    (fewer than ``k`` neighbours) becomes 4 (2D) or 6 (3D) particles, a ligament 2 or 4, a
    sheet 2, all ``shift * r`` from it along its thin directions; a regular boundary particle
    moves ``shift * r`` outwards; interior particles are kept.

    Returns:
        ``(points, feature, source)``: the new set, each new particle's feature code
        (see :data:`FEATURES`) and the index of the input particle it comes from.
    """
