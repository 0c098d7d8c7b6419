"""Boundary particles of meshfree particle sets (SPH, PBF, FLIP/APIC, MPS).

Particle *i* at *p_i* with resolution *r* is **interior** iff its sphere *S_i* of radius *r*
is covered by the closed balls of radius *r* of the other particles within *2r*; otherwise it
is **boundary** (Sandim, Paiva & Figueiredo, J. Comput. Phys. 2020). Coincident duplicates do
not cover each other.

Every method of the Rust library is available by name (see :func:`methods`); ``exact`` (the
default) gives the reference labels and is the fastest of the methods that never miss a
boundary particle. The others reproduce a paper or serve a comparison:

- ``dilts``: exact as well, by an independent proof (arc and cap covering);
- ``ia`` and ``ge``: the JCP 2020 interval-arithmetic and geometric-enclosure tests,
  certified (never a false negative);
- ``marrone``, ``muller``, ``divr``, ``asymmetry`` and ``randles``: the free-surface tests of
  SPH codes (renormalisation matrix, colour field, divergence of position, asymmetry of the
  neighbourhood, Randles-Doring eigenvalue);
- ``lnm``: the layered neighbourhood cells, a fast band a few ``r`` thick;
- ``hpr`` and ``svm``: the thesis' visibility method and learned classifier.

The resolution is the solver's smoothing length ``h`` (``r = h``, the paper's definition),
or ``spacing`` (the particle spacing, times one documented factor), or ``r`` itself:

>>> import numpy as np, boundary_particles as bp
>>> rng = np.random.default_rng(1)
>>> points = 0.005 * np.argwhere(np.ones((40, 40))) + rng.uniform(-5e-4, 5e-4, (1600, 2))
>>> labels = bp.detect(points, h=0.0075)    # h = 1.5 spacings; bool array, True = boundary
>>> scores = bp.confusion(bp.detect(points, h=0.0075, method="muller"), labels)
>>> sorted(scores)
['f1', 'fn', 'fp', 'fpr', 'm', 'precision', 'recall', 'tn', 'tp']

Conventions shared by every function:

- ``points`` is an ``(n, 2)`` or ``(n, 3)`` array-like of reals. A C-contiguous ``float64``
  array is read from its own buffer; ``float32``, Fortran-ordered arrays and lists are
  converted by NumPy first. The positions are then copied once into the engine's particle
  set, validated in the same pass. A 2D set has no z.
- A flat ``(n, 3)`` set (every particle with the same z, or y, or x) raises ``ValueError``
  naming ``dim=2``: read as 3D, every particle of it would be boundary. ``dim=2`` drops the
  constant axis; ``dim=3`` keeps the set 3D.
- The resolution is given once: ``h`` (the smoothing length, ``r = h``; the SPH-sum
  methods then use this ``h``), ``spacing`` (``r`` is the spacing times one factor), or ``r``
  (positive, finite, in the positions' unit), or ``r="auto"``, the fallback, which estimates
  it from the set (:func:`auto_radius`), as the command line's ``--smoothing-length``,
  ``--spacing``, ``--radius`` and ``--radius auto``.
- Detection releases the GIL and runs on all cores, or on ``threads`` worker threads. Ctrl-C
  stops the workers (each finishes the particle it is on) and raises ``KeyboardInterrupt``.
- Method parameters are keyword arguments, as ``--set KEY=VALUE`` on the command line
  (``detect(points, r, "ge", depth=4)``); ``True``/``False`` become ``true``/``false``.
- Errors raise ``ValueError`` (bad input, naming the particle or the argument) or ``OSError``
  (a file that cannot be opened or written), with the messages the ``boundary`` command
  prints.
"""

from __future__ import annotations

from os import PathLike
from typing import (
    Any,
    Dict,
    List,
    Literal,
    Mapping,
    Optional,
    Sequence,
    Tuple,
    TypedDict,
    Union,
    overload,
)

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _native

__all__ = [
    "FEATURES",
    "RADIUS_PER_SPACING",
    "Confusion",
    "Detector",
    "MethodInfo",
    "ParamInfo",
    "Tracker",
    "auto_radius",
    "bulk_spacing",
    "confusion",
    "detect",
    "methods",
    "read",
    "resample",
    "score",
    "write",
]

__version__: str = _native.__version__


def __dir__() -> List[str]:
    """The public API (``__all__`` and ``__version__``), not the names the module imports for
    its annotations (``typing``, NumPy)."""
    return sorted([*__all__, "__version__"])

#: Feature codes of :func:`resample` (thesis Eq. 2.5): -1 interior, 0 droplet, 1 ligament,
#: 2 sheet, 3 regular boundary particle.
FEATURES: Dict[int, str] = dict(_native.FEATURES)

#: The factor ``k`` of ``spacing=dp``: ``r = k * dp`` (1.45, between the smoothing lengths
#: SPH solvers use by default, 1.2 to 1.73 spacings); also what ``r="auto"`` applies to the
#: spacing it measures (:func:`bulk_spacing`).
RADIUS_PER_SPACING: float = _native.RADIUS_PER_SPACING

Path = Union[str, "PathLike[str]"]
Param = Union[str, int, float, bool]
Radius = Union[float, Literal["auto"]]
Labels = NDArray[np.bool_]
Margin = Optional[NDArray[np.float64]]
Texts = Union[str, Sequence[str]]


class ParamInfo(TypedDict):
    """One parameter of a method: its name, default and description."""

    name: str
    default: str
    description: str


class MethodInfo(TypedDict):
    """One method: its name, a summary naming its paper, whether it is certified, and its
    parameters."""

    name: str
    summary: str
    certified: bool
    params: List[ParamInfo]


class Confusion(TypedDict):
    """Confusion counts and rates, boundary the positive class; the keys of
    ``boundary score --json`` and of the C API."""

    tp: int
    tn: int
    fp: int
    fn: int
    recall: float
    fpr: float
    m: float
    precision: float
    f1: float


class Detector:
    """A method with its parameters and thread count, checked once and reused.

    Parameters
    ----------
    method : str, default "exact"
        A name from :func:`methods`. ``exact`` gives the reference labels of the definition.
    threads : int, optional
        Worker threads of each detection (default: all cores).
    **params : str, int, float or bool
        The method's parameters, as ``--set KEY=VALUE`` on the command line (``depth=4``,
        ``gamma=1.3``, ...).

    Raises
    ------
    ValueError
        An unknown method, an unknown parameter or a value out of its range (the message
        names it and its accepted values), ``threads=0``.

    Examples
    --------
    >>> import numpy as np, boundary_particles as bp
    >>> ge = bp.Detector("ge", depth=4)
    >>> ge
    Detector('ge', depth=4)
    >>> ge.detect(np.random.default_rng(0).random((500, 3)), r=0.1).shape
    (500,)
    """

    def __init__(
        self, method: str = "exact", *, threads: Optional[int] = None, **params: Param
    ) -> None:
        self._native = _native.Detector(method, threads, params)
        self._params = dict(params)

    @property
    def method(self) -> str:
        """The method's name."""
        return self._native.method

    @property
    def threads(self) -> Optional[int]:
        """The worker threads of each detection (``None``: all cores)."""
        return self._native.threads

    @property
    def params(self) -> Dict[str, Param]:
        """The parameters given."""
        return dict(self._params)

    @property
    def certified(self) -> bool:
        """Whether the method never labels a boundary particle interior."""
        return self._native.certified

    def settings(self) -> Dict[str, str]:
        """Every parameter of the method with its value in this detector (defaults
        included)."""
        return dict(self._native.settings())

    def __repr__(self) -> str:
        args = [repr(self.method)]
        if self.threads is not None:
            args.append(f"threads={self.threads!r}")
        args += [f"{key}={value!r}" for key, value in self._params.items()]
        return f"Detector({', '.join(args)})"

    def __str__(self) -> str:
        return self._native.label()

    @overload
    def detect(
        self,
        points: ArrayLike,
        r: Optional[Radius] = None,
        *,
        h: Optional[float] = None,
        spacing: Optional[float] = None,
        margin: Literal[False] = False,
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        solids: Optional[Texts] = None,
        periodic: Optional[Texts] = None,
        phases: None = None,
        dim: Optional[int] = None,
    ) -> Labels: ...
    @overload
    def detect(
        self,
        points: ArrayLike,
        r: Optional[Radius] = None,
        *,
        h: Optional[float] = None,
        spacing: Optional[float] = None,
        margin: Literal[True],
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        solids: Optional[Texts] = None,
        periodic: Optional[Texts] = None,
        phases: None = None,
        dim: Optional[int] = None,
    ) -> Tuple[Labels, Margin]: ...
    @overload
    def detect(
        self,
        points: ArrayLike,
        r: Optional[Radius] = None,
        *,
        h: Optional[float] = None,
        spacing: Optional[float] = None,
        margin: Literal[False] = False,
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        solids: Optional[Texts] = None,
        periodic: Optional[Texts] = None,
        phases: ArrayLike,
        dim: Optional[int] = None,
    ) -> Tuple[Labels, Labels]: ...
    @overload
    def detect(
        self,
        points: ArrayLike,
        r: Optional[Radius] = None,
        *,
        h: Optional[float] = None,
        spacing: Optional[float] = None,
        margin: Literal[True],
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        solids: Optional[Texts] = None,
        periodic: Optional[Texts] = None,
        phases: ArrayLike,
        dim: Optional[int] = None,
    ) -> Tuple[Labels, Margin, Labels]: ...
    def detect(
        self,
        points: ArrayLike,
        r: Optional[Radius] = None,
        *,
        h: Optional[float] = None,
        spacing: Optional[float] = None,
        margin: bool = False,
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        solids: Optional[Texts] = None,
        periodic: Optional[Texts] = None,
        phases: Optional[ArrayLike] = None,
        dim: Optional[int] = None,
    ) -> Union[
        Labels,
        Tuple[Labels, Margin],
        Tuple[Labels, Labels],
        Tuple[Labels, Margin, Labels],
    ]:
        """Labels every particle: ``True`` on the boundary, ``False`` inside.

        Parameters
        ----------
        points : array_like, shape (n, 2) or (n, 3)
            The positions.
        r : float or "auto"
            The particle resolution (positive, finite), or ``"auto"`` to estimate it
            (:func:`auto_radius`). Give the resolution once, as ``r``, ``h`` or ``spacing``;
            one of them is required without ``radii``; with ``radii`` it is the scale of
            every radius (``r_i = r * radii[i]``), default 1.
        h : float, optional
            The solver's smoothing length (positive, finite): ``r = h``, the paper's
            definition (``--smoothing-length``). The SPH-sum methods (``marrone``,
            ``muller``, ``divr``, ``asymmetry``, ``randles``) then use this ``h`` as their
            smoothing length, so their ``h_over_r`` must stay 1.
        spacing : float, optional
            The solver's particle spacing ``dp`` (positive, finite):
            ``r = RADIUS_PER_SPACING * dp`` (:data:`RADIUS_PER_SPACING`, ``--spacing``).
        margin : bool, default False
            Also return the method's per-particle margin (positive leans boundary, negative
            interior, near zero a near-tie; for ``exact`` the distance by which the particle's
            Voronoi cell reaches beyond ``r``), or ``None`` when the method has none.
        radii : array_like, shape (n,), optional
            A radius factor per particle, each positive and finite: particle *i* has radius
            ``r * radii[i]`` and is interior iff its sphere is covered by the balls of the
            others. A method without per-particle radii raises ``ValueError`` saying so.
        walls : array_like, shape (m, d), optional
            Covering-only particles (a solver's fixed boundary particles): they cover the
            points' spheres and get no label. May be flat.
        wall_radii : array_like, shape (m,), optional
            Radius factors of the walls (default 1 each). Only with ``walls``.
        solids : str or sequence of str, optional
            Closed axis-aligned solid half-spaces ``"AXIS<VALUE"`` / ``"AXIS>VALUE"``
            (``"y<0"``: the solid ``{y <= 0}``, a floor). What lies in a solid counts as
            covered. Methods without a rule for solids raise ``ValueError`` (use ``walls``).
        periodic : str or sequence of str, optional
            Periodic axes ``"AXIS:MIN:MAX"`` (``"x:0:1"``): the images of every particle and
            wall shifted by ``±(MAX - MIN)`` cover. Every particle must lie in
            ``[MIN, MAX]`` and the period must be at least the method's reach.
        phases : array_like of int, shape (n,), optional
            A phase number per particle (``0 .. 2**32 - 1``). The labels stay those of the
            free surface; the interface labels are returned besides them.
        dim : {2, 3}, optional
            ``2`` drops the one constant axis of an ``(n, 3)`` array (z first, then y, then
            x); ``3`` keeps a flat ``(n, 3)`` set 3D (every particle of it is then boundary).
            Default: the array's own dimension, refusing a flat ``(n, 3)`` set.

        Returns
        -------
        labels : ndarray of bool, shape (n,)
            ``True`` for a boundary particle.
        margin : ndarray of float64, shape (n,), or None
            Only with ``margin=True``.
        interface : ndarray of bool, shape (n,)
            Only with ``phases``: ``True`` for a particle on an interface between phases (not
            on the free surface, but uncovered once only its own phase may cover).

        Warns
        -----
        UserWarning
            When ``r`` (given as ``r``, ``h`` or ``spacing``) is outside ``[0.75, 4]`` times
            the particle spacing measured in the bulk (:func:`bulk_spacing`): almost every
            particle would be boundary, or gaps and thin features would close. The message
            gives the numbers; the detection runs all the same.

        Raises
        ------
        ValueError
            Bad shape, a non-finite coordinate (naming the particle), a flat ``(n, 3)`` set
            (naming ``dim=2``), ``r <= 0``, more than one of ``r``, ``h`` and ``spacing``,
            ``h`` with an ``h_over_r`` other than 1, a bad radius, a bad domain, a method that
            cannot honour the input.
        TypeError
            None of ``r``, ``h`` and ``spacing`` without ``radii``; ``solids`` or
            ``periodic`` not strings.
        KeyboardInterrupt
            Ctrl-C during the detection; the workers have stopped when it is raised.
        """
        out: Any = self._native.detect(
            points,
            r,
            margin,
            radii,
            walls,
            wall_radii,
            solids,
            periodic,
            phases,
            dim,
            h=h,
            spacing=spacing,
        )
        return out  # type: ignore[no-any-return]


@overload
def detect(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: str = "exact",
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    threads: Optional[int] = None,
    margin: Literal[False] = False,
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[Texts] = None,
    periodic: Optional[Texts] = None,
    phases: None = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Labels: ...
@overload
def detect(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: str = "exact",
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    threads: Optional[int] = None,
    margin: Literal[True],
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[Texts] = None,
    periodic: Optional[Texts] = None,
    phases: None = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Tuple[Labels, Margin]: ...
@overload
def detect(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: str = "exact",
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    threads: Optional[int] = None,
    margin: Literal[False] = False,
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[Texts] = None,
    periodic: Optional[Texts] = None,
    phases: ArrayLike,
    dim: Optional[int] = None,
    **params: Param,
) -> Tuple[Labels, Labels]: ...
@overload
def detect(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: str = "exact",
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    threads: Optional[int] = None,
    margin: Literal[True],
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[Texts] = None,
    periodic: Optional[Texts] = None,
    phases: ArrayLike,
    dim: Optional[int] = None,
    **params: Param,
) -> Tuple[Labels, Margin, Labels]: ...
def detect(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: str = "exact",
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    threads: Optional[int] = None,
    margin: bool = False,
    radii: Optional[ArrayLike] = None,
    walls: Optional[ArrayLike] = None,
    wall_radii: Optional[ArrayLike] = None,
    solids: Optional[Texts] = None,
    periodic: Optional[Texts] = None,
    phases: Optional[ArrayLike] = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Union[
    Labels,
    Tuple[Labels, Margin],
    Tuple[Labels, Labels],
    Tuple[Labels, Margin, Labels],
]:
    """Labels every particle: ``True`` on the boundary, ``False`` inside.

    ``Detector(method, threads=threads, **params).detect(points, r, ...)`` in one call; build
    a :class:`Detector` once to reuse it.

    Parameters
    ----------
    points : array_like, shape (n, 2) or (n, 3)
        The positions.
    r : float or "auto"
        The particle resolution, or ``"auto"``; see :meth:`Detector.detect`.
    method : str, default "exact"
        A name from :func:`methods`; ``exact`` gives the reference labels.
    h : float, optional
        The smoothing length, ``r = h`` (instead of ``r``); see :meth:`Detector.detect`.
    spacing : float, optional
        The particle spacing, ``r = RADIUS_PER_SPACING * spacing`` (instead of ``r``).
    threads : int, optional
        Worker threads (default: all cores).
    margin, radii, walls, wall_radii, solids, periodic, phases, dim
        As :meth:`Detector.detect`.
    **params : str, int, float or bool
        The method's parameters (``depth=4``, ``gamma=1.3``, ...).

    Returns
    -------
    labels : ndarray of bool, shape (n,)
        ``True`` for a boundary particle; with ``margin=True`` and/or ``phases``, a tuple
        ``(labels[, margin][, interface])`` as :meth:`Detector.detect`.

    Warns
    -----
    UserWarning
        An ``r`` implausible for the particles' spacing; see :meth:`Detector.detect`.

    Raises
    ------
    ValueError
        Bad input or an unknown method or parameter; see :meth:`Detector.detect`.
    KeyboardInterrupt
        Ctrl-C during the detection; the workers have stopped when it is raised.
    """
    detector = Detector(method, threads=threads, **params)
    out: Any = detector._native.detect(
        points,
        r,
        margin,
        radii,
        walls,
        wall_radii,
        solids,
        periodic,
        phases,
        dim,
        h=h,
        spacing=spacing,
    )
    return out  # type: ignore[no-any-return]


class Tracker:
    """Labels the successive time steps of one particle set, each exactly as
    ``detect(points, r, ...)`` would in the same domain, recomputing only the particles whose
    label may have changed.

    Between two solver steps a particle moves by a small fraction of the spacing; a particle
    far enough inside (or outside) the covering keeps its label, and the tracker proves it
    from the previous step's cells instead of recomputing them. The labels are those of a full
    ``exact`` detection, bit for bit, at every step.

    The domain is that of :meth:`Detector.detect`. Walls given here are fixed: after the
    first update they cost nothing per step. Walls that move are passed to each
    :meth:`update` instead (``walls=``): walls equal to the last ones cost one comparison, and
    moved walls keep the saving (their movement counts like the particles'). Solids, periodic
    axes, phases and per-particle radii are honoured by a full detection at every step: the
    labels of :func:`detect`, without the saving.

    Parameters
    ----------
    r : float or "auto", optional
        The resolution (positive, finite), the same at every step; ``"auto"`` measures it on
        the first update's particles (:func:`auto_radius`) and keeps it. Give it once, as
        ``r``, ``h`` or ``spacing``. With ``radii`` at the updates, it is their scale
        (default 1).
    method : str, default "exact"
        Only ``exact`` has a tracker.
    h : float, optional
        The smoothing length: ``r = h``.
    spacing : float, optional
        The particle spacing: ``r = RADIUS_PER_SPACING * spacing``.
    threads : int, optional
        Worker threads of the updates (default: all cores), started once. An update of fewer
        than 16,384 particles runs on the calling thread and hands only its large parts (a
        first update, a step that recomputes 128 particles or more) to them: waking sleeping
        workers costs about as much as such an update.
    walls : array_like, shape (m, d), optional
        Fixed covering-only particles (a solver's wall particles), as in :func:`detect`.
        ``(m, 3)`` walls beside ``(n, 3)`` points updated with ``dim=2`` lie in the points'
        plane, which is dropped from both.
    wall_radii : array_like, shape (m,), optional
        Radius factors of the walls (default 1 each).
    solids, periodic : str or sequence of str, optional
        Solid half-spaces (``"y<0"``) and periodic axes (``"x:0:1"``), as in :func:`detect`.
    **params : str, int, float or bool
        The method's parameters; ``exact``'s ``tie`` must stay 0 (the exact labels).

    Warns
    -----
    UserWarning
        At the first :meth:`update`, when ``r`` is implausible for the particles' spacing
        (as :meth:`Detector.detect`).

    Raises
    ------
    ValueError
        Another method, ``tie`` other than 0, ``r`` not positive and finite, more than one of
        ``r``, ``h`` and ``spacing``, ``threads=0``, bad walls, solids or periodic axes.

    Examples
    --------
    >>> import numpy as np, boundary_particles as bp
    >>> points = np.random.default_rng(2).random((3000, 3))
    >>> tracker = bp.Tracker(r=0.06)
    >>> first = tracker.update(points)
    >>> moved = points + 1e-4
    >>> bool((tracker.update(moved) == bp.detect(moved, r=0.06)).all())
    True
    >>> tracker.recomputed < len(points)
    True

    A tank: the walls are set once, the water moves.

    >>> k = np.arange(400)
    >>> water = np.column_stack([k % 20, k // 20 + 1.0]) * 0.05
    >>> floor = np.column_stack([np.arange(-5.0, 25.0) * 0.05, np.zeros(30)])
    >>> tracker = bp.Tracker(h=0.06, walls=floor)
    >>> labels = tracker.update(water)
    >>> bool((labels == bp.detect(water, h=0.06, walls=floor)).all())
    True
    """

    def __init__(
        self,
        r: Optional[Radius] = None,
        method: str = "exact",
        *,
        h: Optional[float] = None,
        spacing: Optional[float] = None,
        threads: Optional[int] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        solids: Optional[Texts] = None,
        periodic: Optional[Texts] = None,
        **params: Param,
    ) -> None:
        self._native = _native.Tracker(
            r,
            method,
            threads,
            h=h,
            spacing=spacing,
            walls=walls,
            wall_radii=wall_radii,
            solids=solids,
            periodic=periodic,
            **params,
        )

    def __repr__(self) -> str:
        return repr(self._native)

    @property
    def recomputed(self) -> int:
        """How many particles the last :meth:`update` recomputed (all of them at the first
        step, after a change of the particle count without ``ids``, on a step that fell
        back to a full detection, and with solids, periodic axes, phases or radii)."""
        return self._native.recomputed

    @overload
    def update(
        self,
        points: Optional[ArrayLike] = None,
        ids: Optional[ArrayLike] = None,
        *,
        columns: Optional[Sequence[ArrayLike]] = None,
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        phases: None = None,
        dim: Optional[int] = None,
    ) -> Labels: ...
    @overload
    def update(
        self,
        points: Optional[ArrayLike] = None,
        ids: Optional[ArrayLike] = None,
        *,
        columns: Optional[Sequence[ArrayLike]] = None,
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        phases: ArrayLike,
        dim: Optional[int] = None,
    ) -> Tuple[Labels, Labels]: ...
    def update(
        self,
        points: Optional[ArrayLike] = None,
        ids: Optional[ArrayLike] = None,
        *,
        columns: Optional[Sequence[ArrayLike]] = None,
        radii: Optional[ArrayLike] = None,
        walls: Optional[ArrayLike] = None,
        wall_radii: Optional[ArrayLike] = None,
        phases: Optional[ArrayLike] = None,
        dim: Optional[int] = None,
    ) -> Union[Labels, Tuple[Labels, Labels]]:
        """The labels of this step's positions.

        Parameters
        ----------
        points : array_like, shape (n, 2) or (n, 3)
            Without ``ids``: the same particles in the same order as at the previous step;
            another count starts over with a full detection. Or give ``columns``.
        columns : sequence of array_like, ``(x, y)`` or ``(x, y, z)``, each shape (n,)
            The positions as one array per coordinate, as a solver that stores its particles
            as a structure of arrays has them (PySPH's ``fluid.x, fluid.y``): read in place
            when contiguous ``float64``, without building an ``(n, d)`` array first.
        ids : array_like of int, shape (n,), optional
            A stable id per particle (whole numbers >= 0, unique) that follows the particle
            when the solver reorders, e.g. the solver's global particle id: particles are
            matched to the previous step's by id, so they may come (inflow), go (outflow) and
            change order without the tracker starting over. A solver without such ids (PySPH
            run serially leaves ``gid`` at 4294967295 for every particle) passes none: the
            particles are then matched by their place in ``points``, which is right while the
            solver keeps their order (a new count starts over). A solver that reorders without
            ids gets the right labels all the same, with less saving.
        radii : array_like, shape (n,), optional
            A radius factor per particle (``r_i = r * radii[i]``), as in :func:`detect`.
        walls : array_like, shape (m, d), optional
            The walls at this step, replacing the tracker's (for walls that move; fixed
            walls are given once to :class:`Tracker`). Walls equal to the last ones change
            nothing; another count starts over.
        wall_radii : array_like, shape (m,), optional
            Radius factors of ``walls``.
        phases : array_like of int, shape (n,), optional
            A phase number per particle: the interface labels are returned too.
        dim : {2, 3}, optional
            As :func:`detect`: ``2`` drops the constant axis of a flat ``(n, 3)`` array (and
            of ``(m, 3)`` walls in the same plane).

        Returns
        -------
        labels : numpy.ndarray of bool, shape (n,)
            True on the boundary; with ``phases``, ``(labels, interface)``.

        Raises
        ------
        ValueError
            Positions that are not finite reals (naming the particle), a flat ``(n, 3)``
            array without ``dim=2``, ``columns`` of different lengths or not one-dimensional;
            ``ids`` of another length than ``points``, negative, not integers or repeated
            (naming the particles, and saying what to pass instead); bad walls, radii or
            phases.
        TypeError
            Both ``points`` and ``columns``, or neither.
        KeyboardInterrupt
            On Ctrl-C, after the workers have stopped (an update of 16,384 particles or more;
            a smaller one sees it when it returns); the next update starts over.

        Examples
        --------
        Outflow: the particles past x = 0.9 leave, the others keep their ids.

        >>> import numpy as np, boundary_particles as bp
        >>> points = np.random.default_rng(3).random((3000, 3))
        >>> ids = np.arange(3000)
        >>> tracker = bp.Tracker(r=0.06)
        >>> _ = tracker.update(points, ids=ids)
        >>> stay = points[:, 0] < 0.9
        >>> labels = tracker.update(points[stay], ids=ids[stay])
        >>> bool((labels == bp.detect(points[stay], r=0.06)).all())
        True
        >>> tracker.recomputed < int(stay.sum())
        True

        A solver's own coordinate arrays, as they are:

        >>> x, y, z = (np.ascontiguousarray(c) for c in points[stay].T)
        >>> bool((tracker.update(columns=(x, y, z), ids=ids[stay]) == labels).all())
        True
        """
        out: Any = self._native.update(
            points,
            ids,
            columns=columns,
            radii=radii,
            walls=walls,
            wall_radii=wall_radii,
            phases=phases,
            dim=dim,
        )
        return out  # type: ignore[no-any-return]


def auto_radius(points: ArrayLike, dim: Optional[int] = None) -> float:
    """The resolution ``r="auto"`` uses: :data:`RADIUS_PER_SPACING` times the particle spacing
    measured in the bulk of the set (:func:`bulk_spacing`), as ``boundary detect --radius
    auto``.

    It is an estimate, the fallback: give the solver's smoothing length (``h=``) or spacing
    (``spacing=``) when they are known.

    Parameters
    ----------
    points : array_like, shape (n, 2) or (n, 3)
        The positions.
    dim : {2, 3}, optional
        As :meth:`Detector.detect`.

    Returns
    -------
    float
        The estimated resolution, ``RADIUS_PER_SPACING * bulk_spacing(points)``.

    Raises
    ------
    ValueError
        Fewer than two distinct positions, or bad points.

    Examples
    --------
    >>> import numpy as np, boundary_particles as bp
    >>> points = 0.02 * np.argwhere(np.ones((30, 30)))     # a lattice of spacing 0.02
    >>> r = bp.auto_radius(points)
    >>> r == bp.RADIUS_PER_SPACING * bp.bulk_spacing(points)
    True
    """
    return _native.auto_radius_of(points, dim)


def bulk_spacing(points: ArrayLike, dim: Optional[int] = None) -> float:
    """The particle spacing ``dp`` as a solver defines it: the side of the volume (area in 2D)
    per particle in the bulk of the set, ``dp = (V / N) ** (1 / d)``.

    It counts particles per volume, so jitter, disorder or a compression along one direction
    at constant volume do not shrink it (the nearest-neighbour distance does); particles near
    a free surface or in spray do not count as the bulk. It is a statistic, within a few per
    cent of the lattice spacing on jittered, sheared or compressed lattices; a set with no
    bulk (a sheet or a filament one or two particles thick) reads larger. ``spacing=dp``
    gives ``r = RADIUS_PER_SPACING * dp``.

    Parameters
    ----------
    points : array_like, shape (n, 2) or (n, 3)
        The positions.
    dim : {2, 3}, optional
        As :meth:`Detector.detect`.

    Returns
    -------
    float
        The measured spacing.

    Raises
    ------
    ValueError
        Fewer than two distinct positions, or bad points.

    Examples
    --------
    >>> import numpy as np, boundary_particles as bp
    >>> points = 0.02 * np.argwhere(np.ones((30, 30)))
    >>> abs(bp.bulk_spacing(points) / 0.02 - 1) < 0.05
    True
    """
    return _native.bulk_spacing_of(points, dim)


def confusion(predicted: ArrayLike, truth: ArrayLike) -> Confusion:
    """Scores labels one already has against the truth; boundary is the positive class.

    Parameters
    ----------
    predicted, truth : array_like of bool or 0/1, shape (n,)
        One label per particle, ``True`` (or 1) for boundary.

    Returns
    -------
    Confusion
        ``tp, tn, fp, fn`` (counts), ``recall = tp / (tp + fn)``, ``fpr = fp / (fp + tn)``,
        ``m = recall * (1 - fpr)`` (J. Comput. Phys. 2020, Sec. 4), ``precision`` and ``f1``:
        the keys of ``boundary score --json``. A rate whose denominator is zero is 0.

    Raises
    ------
    ValueError
        Lengths that differ, a label other than 0/1, an array that is not one-dimensional.
    """
    return _native.confusion(predicted, truth)  # type: ignore[return-value]


@overload
def score(
    points: ArrayLike,
    r: Radius,
    method: str,
    *,
    h: None = None,
    spacing: None = None,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: Optional[ArrayLike] = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Confusion: ...
@overload
def score(
    points: ArrayLike,
    r: Optional[Radius] = None,
    *,
    method: str,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: ArrayLike,
    dim: Optional[int] = None,
    **params: Param,
) -> Confusion: ...
@overload
def score(
    points: ArrayLike,
    r: None = None,
    *,
    method: str,
    h: float,
    spacing: None = None,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: Optional[ArrayLike] = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Confusion: ...
@overload
def score(
    points: ArrayLike,
    r: None = None,
    *,
    method: str,
    h: None = None,
    spacing: float,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: Optional[ArrayLike] = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Confusion: ...
def score(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: Optional[str] = None,
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    truth: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    radii: Optional[ArrayLike] = None,
    dim: Optional[int] = None,
    **params: Param,
) -> Confusion:
    """Runs ``method`` and scores its labels against the truth (``boundary score``).

    ``confusion(detect(points, r, method, ...), truth)``, the truth defaulting to the
    ``exact`` labels of the same points, ``r`` and radii.

    Parameters
    ----------
    points, r, h, spacing, radii, dim
        As :meth:`Detector.detect` (the resolution once, as ``r``, ``h`` or ``spacing``).
    method : str
        Required (by keyword when ``r`` is not given).
    truth : array_like of bool or 0/1, shape (n,), optional
        The reference labels; default: those of ``exact``.
    threads : int, optional
        Worker threads (default: all cores).
    **params : str, int, float or bool
        The method's parameters.

    Returns
    -------
    Confusion
        As :func:`confusion`.
    """
    if method is None:
        raise TypeError("score() missing required argument 'method'")
    predicted = Detector(method, threads=threads, **params).detect(
        points, r, h=h, spacing=spacing, radii=radii, dim=dim
    )
    if truth is None:
        truth = Detector("exact", threads=threads).detect(
            points, r, h=h, spacing=spacing, radii=radii, dim=dim
        )
    return confusion(predicted, truth)


def methods() -> List[MethodInfo]:
    """Every available method.

    Returns
    -------
    list of MethodInfo
        Per method: ``name``, ``summary`` (with its paper), ``certified`` (never a false
        negative) and ``params`` (``name``, ``default``, ``description`` each): the data of
        ``boundary methods --json``.
    """
    return _native.methods()  # type: ignore[return-value]


def read(
    path: Path,
    dim: Optional[int] = None,
    format: Optional[str] = None,
    array: Optional[str] = None,
) -> Tuple[NDArray[np.float64], Dict[str, NDArray[Any]]]:
    """Reads a particle file.

    Parameters
    ----------
    path : str or path-like
        CSV (header ``x,y[,z]``), whitespace XYZ, PLY, legacy VTK, VTK XML ``.vtu`` /
        ``.vtp``, Houdini BGEO (``.bgeo``, ``.bgeo.gz``), PySPH's ``.hdf5`` and ``.npz``.
    dim : {2, 3}, optional
        ``2`` drops the one constant axis of a 3D file; ``3`` asks for 3D.
    format : str, optional
        The format when the extension does not say it (``csv``, ``xyz``, ``ply``, ``vtk``,
        ``vtu``, ``vtp``, ``bgeo``, ``hdf5``, ``npz``).
    array : str, optional
        The particle array of a PySPH file to read (``"fluid"``, ``"boundary"``, ...); by
        default its ``fluid`` array, or its only one. Other formats hold no named arrays:
        naming one is a ``ValueError``.

    Returns
    -------
    points : ndarray of float64, shape (n, dim)
    point_data : dict of str to ndarray
        Every other per-particle attribute, as meshio gives it: a scalar as an ``(n,)``
        array, a vector of ``k`` components as an ``(n, k)`` array; ``int64`` or ``float64``.

    Warns
    -----
    UserWarning
        For each attribute of the file that cannot be kept (named, with the reason).

    Raises
    ------
    FileNotFoundError, OSError
        The file cannot be opened.
    ValueError
        Malformed content (naming the line or element); a file of no particle (an empty
        file, a CSV header without rows); a header with ``x``, ``y`` and a column that looks
        like a misspelt ``z`` (``x,y,zz``): rename the column, or pass ``dim=2`` to read the
        file as 2D from ``x``, ``y`` on purpose.
    """
    return _native.read(path, dim, format, array)


def write(
    path: Path,
    points: ArrayLike,
    *,
    boundary: Optional[ArrayLike] = None,
    point_data: Optional[Mapping[str, ArrayLike]] = None,
    format: Optional[str] = None,
    dim: Optional[int] = None,
) -> None:
    """Writes a particle file; atomic (the file appears whole or not at all, and a file
    already at ``path`` stays as it was when the write fails).

    Parameters
    ----------
    path : str or path-like
        The format is that of the extension, or ``format``.
    points : array_like, shape (n, 2) or (n, 3)
        The positions.
    boundary : array_like of bool or 0/1, shape (n,), optional
        Written as the integer column ``boundary``.
    point_data : mapping of str to array_like, optional
        Per-particle attributes, as meshio takes them: an ``(n,)`` array is one column, an
        ``(n, k)`` array a vector attribute. VTK XML and BGEO write a vector as one attribute
        of ``k`` components; CSV, XYZ and legacy VTK as the columns ``name:0`` ..
        ``name:k-1``; PLY, whose property names are identifiers, as the properties
        ``name_0`` .. ``name_k-1`` (``velocity`` becomes ``velocity_0``, ``velocity_1``,
        ..., and any other character not allowed there becomes ``_``). Integer arrays stay
        integers, anything else is written as reals. Any name is allowed that is a valid
        column name and not a position (``x``, ...).
    format : str, optional
        As :func:`read`.
    dim : {2, 3}, optional
        As :meth:`Detector.detect`.

    Raises
    ------
    OSError
        The file cannot be written.
    ValueError
        Bad points, a column of the wrong length or shape, a bad or repeated name.
    """
    _native.write(path, points, boundary, point_data, format, dim)


def resample(
    points: ArrayLike,
    r: Optional[Radius] = None,
    method: str = "exact",
    *,
    h: Optional[float] = None,
    spacing: Optional[float] = None,
    k: int = 4,
    alpha: float = 0.2,
    shift: float = 0.5,
    labels: Optional[ArrayLike] = None,
    threads: Optional[int] = None,
    **params: Param,
) -> Tuple[NDArray[np.float64], NDArray[np.int8], NDArray[np.int64]]:
    """Classifies the boundary particles by feature and resamples thin features (Sandim et
    al., Computers & Graphics 2019; thesis Sec. 2.6, Eq. 2.4-2.5).

    A droplet (fewer than ``k`` neighbours) becomes 4 (2D) or 6 (3D) particles, a ligament 2
    or 4, a sheet 2, all ``shift * r`` from it along its thin directions; a regular boundary
    particle moves ``shift * r`` outwards; interior particles are kept.

    Parameters
    ----------
    points : array_like, shape (n, 2) or (n, 3)
        The positions.
    r : float or "auto"
        The particle resolution; or give ``h`` or ``spacing`` instead, as
        :meth:`Detector.detect`.
    method : str, default "exact"
        The method giving the boundary particles (with ``**params``), unless ``labels``.
    h : float, optional
        The smoothing length, ``r = h``.
    spacing : float, optional
        The particle spacing, ``r = RADIUS_PER_SPACING * spacing``.
    k : int, default 4
        *K* of Eq. 2.5.
    alpha : float, default 0.2
        *alpha* of Eq. 2.5.
    shift : float, default 0.5
        The shift in units of ``r``.
    labels : array_like of bool or 0/1, shape (n,), optional
        The boundary labels to use instead of running ``method``.
    threads : int, optional
        Worker threads (default: all cores).
    **params : str, int, float or bool
        The method's parameters.

    Returns
    -------
    points : ndarray of float64, shape (m, dim)
        The new set.
    feature : ndarray of int8, shape (m,)
        Each new particle's feature code (:data:`FEATURES`).
    source : ndarray of int64, shape (m,)
        The index of the input particle each new particle comes from.
    """
    detector = Detector(method, threads=threads, **params)
    return _native.resample(
        points, r, detector._native, k, alpha, shift, labels, h=h, spacing=spacing
    )
