"""The non-dominated designs of a grid (:func:`pareto_mask`) and the optimiser
(:func:`optimize`): a grid search under limits, refined by zooming boxes."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, float_array
from .._errors import InfeasibleError, InputError
from ._drive import CRITERIA, SAMPLES, GearLeverPress, PressCriteria
from ._grid import PressGrid, design_grid

__all__ = ["OBJECTIVES", "PressOptimum", "optimize", "pareto_mask"]


#: The objectives of :func:`optimize`: name → how a design's value is scored (lower
#: is better).
OBJECTIVES = {
    "k_Vp": lambda v: v["k_Vp"],
    "k_Vmax": lambda v: np.abs(v["k_Vmax"] - 1.0),
    "k_J": lambda v: v["k_J"],
    "k_M": lambda v: v["k_M"],
}


@dataclass(frozen=True)
class PressOptimum:
    """The non-dominated designs of :func:`optimize`.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    designs : tuple of GearLeverPress
        The non-dominated designs.
    criteria : tuple of PressCriteria
        Their criteria.
    refined : tuple of bool
        Whether scipy moved each off the grid.
    scores : ndarray of float
        Their weighted score (lower is better; 1 per objective is the baseline's
        level), sorted.
    best : int
        The index of the lowest score (0, as the scores are sorted).
    baseline : PressCriteria
        The criteria of ``baseline_press``, which every objective is divided by.
    baseline_press : GearLeverPress
        The crank-slider (d = 0) of the same gears with the grid's median rod.
    grid : PressGrid
        The design grid it started from.
    objectives : tuple of str
        The objectives scored (names of :data:`OBJECTIVES`).
    edges : tuple of str, default ()
        One sentence each, where the best design lies on a bound of the grid (a
        swept axis's first or last value, to within half a grid step; not d = 0, nor
        φ0 on an axis spanning a whole period 2π/i, which wraps): a better design may
        lie beyond it, outside the grid. Empty when the best design is inside.

    See Also
    --------
    optimize : Builds it.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> opt = cm.press.optimize(R=0.09, r=0.03, d=np.linspace(0, 0.04, 9),
    ...                         L=[0.3, 0.4], phi0=np.radians(np.arange(0, 120, 10)),
    ...                         k_Sp=0.1, omega=4.0, refine=1)
    >>> opt.best, opt.baseline_press.d, opt.baseline_press.L, len(opt.edges)
    (0, 0.0, 0.35, 1)
    """

    designs: tuple[GearLeverPress, ...]
    criteria: tuple[PressCriteria, ...]
    refined: tuple[bool, ...]
    scores: npt.NDArray[np.float64]
    best: int
    baseline: PressCriteria
    baseline_press: GearLeverPress
    grid: PressGrid
    objectives: tuple[str, ...]
    edges: tuple[str, ...] = ()


def _objective_matrix(values: Mapping[str, Any], objectives: Sequence[str]) -> Any:
    return np.stack([np.asarray(OBJECTIVES[o](values), dtype=np.float64) for o in objectives], -1)


def pareto_mask(points: npt.ArrayLike) -> npt.NDArray[np.bool_]:
    """True for the rows of ``points`` that no other row dominates; lower is better.

    A row dominates another when every objective is lower or equal and one strictly
    lower. Equal rows are all kept. In Rust: rows in order of their sum, each
    compared with the front found so far.

    Parameters
    ----------
    points : array_like of float, shape (n, m)
        The objectives (m columns) of n designs.

    Returns
    -------
    ndarray of bool, shape (n,)
        True for the non-dominated rows.

    Raises
    ------
    InputError
        If ``points`` is not a 2-D array of numbers.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> cm.press.pareto_mask(np.array([[1, 2], [2, 1], [2, 2], [1, 2]])).tolist()
    [True, True, False, True]
    """
    p = float_array("points", points, ndims=(2,))
    return _core.pareto_mask(p)


def optimize(
    *,
    d: npt.ArrayLike,
    L: npt.ArrayLike,
    phi0: npt.ArrayLike,
    R: float,
    r: float,
    omega: float,
    offset: float = 0.0,
    k_Sp: float | None = None,
    working_stroke: float | None = None,
    limits: Mapping[str, float] | None = None,
    objectives: Sequence[str] = ("k_Vp", "k_Vmax", "k_J", "k_M"),
    weights: Sequence[float] | None = None,
    refine: int = 5,
    samples: int = SAMPLES,
    n_threads: int | None = None,
    progress: bool | None = None,
) -> PressOptimum:
    """The non-dominated designs over a grid of (d, L, φ0), then refined off it.

    Objectives (lower is better): ``k_Vp`` (→ 0), ``|k_Vmax − 1|``, ``k_J`` and
    ``k_M`` (the dimensionless peak acceleration and torque arm), or a subset.
    Designs that fail (see :data:`STATUS`: a rod that cannot reach, a slider that
    moves back up or re-contacts the blank) or break a limit are dropped. The score
    of a design is the weighted sum of its objectives, each divided by the baseline
    crank-slider's.

    The refinement (``refine`` > 0) is multi-start, with the limits inside it. A
    coarse grid is swept once more, finer (at most 100 000 designs, one Rust call),
    because the designs that meet a tight limit on V_np lie in a narrow band of φ0
    that a coarse grid steps over. From that grid start the ``refine`` best designs
    that meet the limits and the ``refine`` best working designs by score plus a
    penalty of 1000 per unit of relative excess over a limit, the starts spread
    (none within a grid step of another). Each start is refined by a zoom (boxes of
    9³ designs, ± one step around the best so far, a quarter the size each time, 8
    times; one Rust call each) and polished by scipy's Nelder–Mead on the penalised
    score, within the grid's bounds; of every design met, the best that meets the
    limits is kept. So a limit that no grid design meets can still be met by a
    design between the grid's points. The returned front is recomputed over the
    grid's front and the refined designs; ``PressOptimum.edges`` says when the
    best design lies on the grid's bound.

    Parameters
    ----------
    d : float or array_like of float
        The pin's eccentricity [m], fixed or an axis of the grid. All the parameters
        are keyword-only.
    L : float or array_like of float
        The rod's length [m], fixed or an axis.
    phi0 : float or array_like of float
        The guide gear's setting angle [rad], fixed or an axis.
    R : float
        The guide gear's pitch radius [m].
    r : float
        The planet gear's pitch radius [m].
    omega : float
        The crank speed ω [rad/s] (> 0).
    offset : float, default 0.0
        The slider's guide's offset from the centre [m].
    k_Sp : float, optional
        The working stroke as a fraction of the nominal stroke, in (0, 1]; give it
        or ``working_stroke``.
    working_stroke : float, optional
        The working stroke S_p [m] (> 0).
    limits : mapping of str to float, optional
        Upper bounds on any criterion of :data:`CRITERIA`, in its unit, e.g.
        ``{"V_np": 0.05}`` for a start of the working stroke at most 50 mm/s at
        ``omega``; default None (no limits).
    objectives : sequence of str, default ("k_Vp", "k_Vmax", "k_J", "k_M")
        The objectives, names of :data:`OBJECTIVES`.
    weights : sequence of float, optional
        One finite non-negative weight per objective; default None (all 1).
    refine : int, default 5
        The number of starts of each kind for the refinement (0: none).
    samples : int, default SAMPLES
        Carrier angles per turn (8 to 10⁶).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
    progress : bool, optional
        Show a progress bar for the grid; default None (when stderr is a terminal
        and the grid is large).

    Returns
    -------
    PressOptimum
        The non-dominated designs, their criteria and scores, the best, and the
        baseline.

    Raises
    ------
    InputError
        If an objective or a limit's criterion is unknown, the weights are not one
        finite non-negative number per objective, ``refine`` is negative, or a grid
        parameter is out of range (as :func:`design_grid`).
    InfeasibleError
        If no design works within the limits (with ``refine = 0``, or when none is
        found); it names the limits.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> opt = cm.press.optimize(R=0.09, r=0.03, d=np.linspace(0, 0.04, 9),
    ...                         L=[0.3, 0.4], phi0=np.radians(np.arange(0, 120, 10)),
    ...                         k_Sp=0.1, omega=4.0, refine=1)
    >>> c = opt.criteria[opt.best]
    >>> c.k_Vp < opt.baseline.k_Vp, len(opt.designs) >= 1
    (True, True)
    """
    objectives, wts, lim = _optimize_args(objectives, weights, limits, refine, R, r)
    # What every grid of this optimisation shares: gears, stroke, speed, sampling.
    common: dict[str, Any] = {
        "R": R,
        "r": r,
        "offset": offset,
        "k_Sp": k_Sp,
        "working_stroke": working_stroke,
        "omega": omega,
        "samples": samples,
        "n_threads": n_threads,
    }
    grid = design_grid(d=d, L=L, phi0=phi0, progress=progress, **common)
    flat, usable = _usable(grid, lim, refine)
    base_press, base = _baseline(L, common)
    score = _Score.against(base, objectives, wts, lim)
    designs, crits = _grid_front(grid, flat, usable, score)
    refined = [False] * len(designs)
    rf = _refinement(grid, score, common, refine)
    starts: list[int] = []
    if rf.names and refine:
        starts, more = _refine(rf, refine)
        for q, c in more:
            designs.append(q)
            crits.append(c)
            refined.append(True)
    if not designs:
        raise InfeasibleError(
            f"no design of the grid works within the limits {lim}, nor any refined from its "
            f"{len(starts)} designs nearest to them: widen or refine the grid, or relax the "
            "limits",
            tuple(lim),
        )
    return _optimum(designs, crits, refined, score, base, base_press, grid)


#: Weight of the limits' relative excess in the refinement's score (the score is
#: about 1 per objective): large enough that no gain in score pays for breaking a
#: limit.
_PENALTY = 1e3


#: Points per axis of each box of the refinement's zoom, and the number of boxes
#: (each a quarter the size of the one before: 8 boxes narrow one grid step
#: 65 536-fold).
_ZOOM = 9


_LEVELS = 8


#: Designs of the finer grid a coarse grid's refinement starts from.
_DENSE = 100_000


def _optimize_args(
    objectives: Any, weights: Any, limits: Any, refine: Any, R: Any, r: Any
) -> tuple[tuple[str, ...], npt.NDArray[np.float64], dict[str, float]]:
    """:func:`optimize`'s objectives, weights, limits, ``refine`` and gears checked,
    in the order it always checked them (so the first bad one is the one named):
    (objectives, one weight each, limits by criterion)."""
    if isinstance(objectives, str) or not isinstance(objectives, Sequence):
        raise InputError(
            f"objectives must be a sequence of names of OBJECTIVES; got {objectives!r}"
        )
    objectives = tuple(objectives)
    for o in objectives:
        if o not in OBJECTIVES:
            raise InputError(f"objective {o!r} is not known; choose from {', '.join(OBJECTIVES)}")
    if not objectives:
        raise InputError("objectives must name at least one objective")
    wts = np.ones(len(objectives)) if weights is None else float_array("weights", weights)
    if wts.shape != (len(objectives),) or not (np.isfinite(wts).all() and (wts >= 0).all()):
        raise InputError(
            f"weights must be {len(objectives)} finite non-negative numbers, one per objective"
        )
    lim: dict[str, float] = {}
    for name, v in dict(limits or {}).items():
        if name not in CRITERIA:
            raise InputError(f"limits: no criterion {name!r}; criteria are {', '.join(CRITERIA)}")
        lim[name] = finite_number(f"limits[{name!r}]", v, "")
    if isinstance(refine, bool) or not isinstance(refine, int) or refine < 0:
        raise InputError(f"refine must be a non-negative integer; got {refine!r}")
    for name, value in (("R", R), ("r", r)):
        if np.ndim(value) != 0:
            raise InputError(
                f"{name} must be a scalar for optimize; give a grid of it to cm.press.design_grid"
            )
    return objectives, wts, lim


def _usable(
    grid: PressGrid, lim: Mapping[str, float], refine: int
) -> tuple[dict[str, npt.NDArray[np.float64]], npt.NDArray[np.bool_]]:
    """The grid's criteria, flattened, and which of its designs work and meet the
    limits. Raises :class:`InfeasibleError` when none works at all, or none meets
    the limits and there is no refinement to look between the grid's points."""
    flat = {k: v.ravel() for k, v in grid.values.items()}
    ok = grid.ok.ravel()
    # How far each grid design breaks the limits (relative; 0: meets them all).
    excess = np.zeros(ok.size)
    for name, v in lim.items():
        excess += np.maximum(flat[name] - v, 0.0) / _limit_scale(v)
    usable = ok & (excess == 0.0)
    if not ok.any() or (not usable.any() and refine == 0):
        why = f" within the limits {lim}" if lim else ""
        raise InfeasibleError(
            f"no design of the grid works{why}: widen or refine the grid, or relax the limits",
            tuple(lim),
        )
    return flat, usable


def _baseline(L: npt.ArrayLike, common: Mapping[str, Any]) -> tuple[GearLeverPress, PressCriteria]:
    """The design every objective is divided by, and its criteria: the crank-slider
    (d = 0) of the same gears with the grid's median rod, at the optimisation's
    stroke, speed and sampling."""
    # Score relative to one baseline: the crank-slider (d = 0) of the same gears
    # with the grid's median rod.
    base_press = GearLeverPress(
        R=float(common["R"]),
        r=float(common["r"]),
        d=0.0,
        L=float(np.median(np.atleast_1d(L))),
        phi0=0.0,
        offset=common["offset"],
    )
    base = base_press.criteria(
        k_Sp=common["k_Sp"],
        working_stroke=common["working_stroke"],
        omega=common["omega"],
        samples=common["samples"],
    )
    return base_press, base


@dataclass(frozen=True)
class _Score:
    """How :func:`optimize` scores designs: each objective divided by the baseline's
    (``norm``; 1 where the baseline's is 0), weighted and summed, and the limits'
    relative excess as a penalty. One object, so that the grid's front, the
    refinement and the returned scores use one and the same arithmetic."""

    objectives: tuple[str, ...]
    norm: npt.NDArray[np.float64]  # the baseline's objectives, in magnitude
    wts: npt.NDArray[np.float64]  # one weight per objective
    lim: dict[str, float]  # upper bounds by criterion

    @classmethod
    def against(
        cls,
        base: PressCriteria,
        objectives: tuple[str, ...],
        wts: npt.NDArray[np.float64],
        lim: dict[str, float],
    ) -> _Score:
        """The score relative to the baseline's criteria ``base``."""
        bvals = _objective_matrix(base.as_dict(), objectives)
        norm = np.where(np.abs(bvals) > 1e-12, np.abs(bvals), 1.0)
        return cls(objectives, norm, wts, lim)

    def objective(self, values: Mapping[str, Any]) -> Any:
        """The objectives of ``values`` (criteria by name, arrays or scalars), each
        divided by the baseline's: a last axis of one column per objective."""
        return _objective_matrix(values, self.objectives) / self.norm

    def penalised(
        self, values: Mapping[str, Any], status: Any, mu: float = _PENALTY
    ) -> tuple[Any, Any]:
        """(score, score + mu·the limits' excess); inf where a design fails."""
        sc = (_objective_matrix(values, self.objectives) / self.norm) @ self.wts
        over = np.zeros(np.shape(sc))
        for k_, v in self.lim.items():
            over = over + np.maximum(np.asarray(values[k_]) - v, 0.0) / _limit_scale(v)
        bad = np.asarray(status) != 0
        return np.where(bad | (over > 0), np.inf, sc), np.where(bad, np.inf, sc + mu * over)


def _grid_front(
    grid: PressGrid,
    flat: Mapping[str, npt.NDArray[np.float64]],
    usable: npt.NDArray[np.bool_],
    score: _Score,
) -> tuple[list[GearLeverPress], list[PressCriteria]]:
    """The grid stage: the non-dominated designs among the grid's usable ones (they
    work and meet the limits), best score first, and their criteria."""
    obj = score.objective(flat)
    cand = np.flatnonzero(usable)
    front = cand[pareto_mask(obj[cand])] if cand.size else cand
    weighted = obj @ score.wts
    ranked = front[np.argsort(weighted[front], kind="stable")]
    designs: list[GearLeverPress] = [grid.design(int(i)) for i in ranked]
    crits: list[PressCriteria] = [grid.at(int(i)) for i in ranked]
    return designs, crits


@dataclass(frozen=True)
class _Refinement:
    """What the refinement of :func:`optimize` works with: the score, the settings
    every grid shares (``common``), the axes refined (``names``, those of d, L, φ0
    that the grid sweeps over a range) with their bounds, the grid its starts come
    from (``dense``: the user's grid or a finer sweep of it, ``factor`` times denser)
    and that grid's steps, which size the zoom's first box."""

    score: _Score
    common: dict[str, Any]
    grid: PressGrid  # the user's grid
    dense: PressGrid  # the grid the starts are taken from
    factor: int  # how many times denser ``dense`` is on each refined axis
    names: list[str]
    bounds: list[tuple[float, float]]
    steps: npt.NDArray[np.float64]  # ``dense``'s step on each refined axis
    lo_b: npt.NDArray[np.float64]  # the bounds' lower ends
    hi_b: npt.NDArray[np.float64]  # and upper ends

    def evaluate(self, p: GearLeverPress) -> PressCriteria:
        """The criteria of one design at the optimisation's stroke, speed, sampling."""
        c = self.common
        return p.criteria(
            k_Sp=c["k_Sp"],
            working_stroke=c["working_stroke"],
            omega=c["omega"],
            samples=c["samples"],
        )


def _refinement(grid: PressGrid, score: _Score, common: dict[str, Any], refine: int) -> _Refinement:
    """The :class:`_Refinement` of ``grid``: its refined axes and their bounds, and
    (when there is a refinement) the finer sweep the starts come from."""
    # Refine along the swept axes that span a range.
    names: list[str] = [
        n_ for n_ in ("d", "L", "phi0") if n_ in grid.axes and np.ptp(grid.axes[n_]) > 0
    ]
    bounds = [(float(grid.axes[n_].min()), float(grid.axes[n_].max())) for n_ in names]
    # Where the refinement starts: a coarse grid is swept again first, finer
    # (each refined axis `factor` times denser, at most _DENSE designs, one Rust
    # call), so that a narrow feasible region between the grid's points has
    # designs in it.
    dense, factor = grid, 1
    if names and refine:
        factor = int((_DENSE / grid.status.size) ** (1 / len(names)) + 1e-9)
        if factor >= 2:
            kw: dict[str, Any] = {}
            for n_ in ("d", "L", "phi0"):
                if n_ in names:
                    ax = grid.axes[n_]
                    kw[n_] = np.linspace(ax.min(), ax.max(), (len(ax) - 1) * factor + 1)
                else:
                    kw[n_] = grid.axes[n_] if n_ in grid.axes else grid.fixed[n_]
            dense = design_grid(progress=False, **common, **kw)
        else:
            factor = 1
    steps = np.array([np.ptp(dense.axes[n_]) / max(len(dense.axes[n_]) - 1, 1) for n_ in names])
    lo_b = np.array([b_[0] for b_ in bounds])
    hi_b = np.array([b_[1] for b_ in bounds])
    return _Refinement(score, common, grid, dense, factor, names, bounds, steps, lo_b, hi_b)


def _refine(
    rf: _Refinement, refine: int
) -> tuple[list[int], list[tuple[GearLeverPress, PressCriteria]]]:
    """The refinement stage: from each start (``refine`` of each kind, see
    :func:`_starts`) a zoom (:func:`_zoom`) then a polish (:func:`_polish`); of
    each, the best design met that meets the limits, kept when it is new. Returns
    the starts (their indices in ``rf.dense``) and the designs kept with their
    criteria."""
    d_feas, d_pen = rf.score.penalised(rf.dense.values, rf.dense.status)
    d_feas, d_pen = d_feas.ravel(), d_pen.ravel()
    d_usable = np.flatnonzero(np.isfinite(d_feas))
    d_ranked = d_usable[np.argsort(d_feas[d_usable], kind="stable")]
    starts = _starts(rf.dense, d_ranked, d_pen, refine, reach=rf.factor)
    found: list[tuple[float, npt.NDArray[np.float64], PressCriteria]] = []
    kept: list[tuple[GearLeverPress, PressCriteria]] = []
    for start in starts:
        p0 = rf.dense.design(int(start))
        best: list[Any] = [math.inf, None, None]
        x0 = _zoom(rf, p0, best)
        _polish(rf, p0, x0, best)
        if best[1] is None:
            continue
        # On the user's grid, keep a move only when it is a real improvement
        # on a start that met the limits, not rounding (off it, every design
        # is new).
        s0 = float(d_feas[start])
        if rf.dense is rf.grid and math.isfinite(s0) and best[0] >= s0 - 1e-6 * max(abs(s0), 1.0):
            continue
        # Starts that converge to one design keep it once.
        span = np.array([hi - lo for lo, hi in rf.bounds]) + 1e-300
        if any(np.all(np.abs(best[1] - x) <= 1e-6 * span) for _, x, _ in found):
            continue
        q = replace(p0, **dict(zip(rf.names, best[1].tolist(), strict=True)))
        c = best[2] if best[2] is not None else rf.evaluate(q)
        found.append((best[0], best[1], c))
        kept.append((q, c))
    return starts, kept


def _zoom(rf: _Refinement, p0: GearLeverPress, best: list[Any]) -> npt.NDArray[np.float64]:
    """A box of _ZOOM points per axis, ± one grid step around the start, swept
    in one Rust call; its best design (by penalised score) the centre of the
    next box, a quarter the size, _LEVELS times. Every design of every box
    counts: the best one that meets the limits is kept in ``best``. A box
    search, not a descent: a feasible sliver thinner than the grid's step, or
    bordered by designs that fail, is found as long as a box point lands in it,
    and the penalty leads the boxes towards it otherwise."""
    names, penalised = rf.names, rf.score.penalised
    x = np.array([float(getattr(p0, n_)) for n_ in names])
    c0 = rf.evaluate(p0)
    half = rf.steps.copy()
    for level in range(_LEVELS):
        mu = _PENALTY ** ((level + 1) / _LEVELS)
        x_pen = penalised(c0.as_dict(), 0 if c0.ok else 1, mu)[1]
        axes = [
            np.linspace(max(lo, c - h), min(hi, c + h), _ZOOM)
            for lo, hi, c, h in zip(rf.lo_b, rf.hi_b, x, half, strict=True)
        ]
        kw = {n_: getattr(p0, n_) for n_ in ("d", "L", "phi0")}
        kw.update(zip(names, axes, strict=True))
        box = design_grid(progress=False, **rf.common, **kw)  # p0 shares R, r, offset
        feas, pen = penalised(box.values, box.status, mu)
        i = int(np.argmin(feas))
        if feas.flat[i] < best[0]:
            q = box.design(i)
            best[:] = [float(feas.flat[i]), np.array([getattr(q, n_) for n_ in names]), None]
        j = int(np.argmin(pen))
        if pen.flat[j] < x_pen:
            q = box.design(j)
            c0 = box.at(j)
            x = np.array([float(getattr(q, n_)) for n_ in names])
        half = half / (_ZOOM - 1) * 2
    return x


def _polish(
    rf: _Refinement, p0: GearLeverPress, x0: npt.NDArray[np.float64], best: list[Any]
) -> None:
    """scipy's Nelder–Mead from the zoom's end ``x0`` on the penalised score, within
    the grid's bounds (at most 200 evaluations); every design it meets that meets
    the limits and beats ``best`` replaces it (score, x, criteria)."""
    from scipy.optimize import minimize

    names, lo_b, hi_b = rf.names, rf.lo_b, rf.hi_b

    def f(x: npt.NDArray[np.float64]) -> float:
        # The limits inside the refinement: an exact penalty on their
        # excess, so that a start that breaks them moves towards them
        # and one that meets them is not walled in; the best design met
        # that meets them is kept whatever the simplex ends on.
        x = np.clip(x, lo_b, hi_b)
        try:
            c = rf.evaluate(replace(p0, **dict(zip(names, x.tolist(), strict=True))))
        except InputError:
            return math.inf
        feas, pen = rf.score.penalised(c.as_dict(), 0 if c.ok else 1)
        if feas < best[0]:
            best[:] = [float(feas), x.copy(), c]
        return float(pen)

    # Nelder–Mead polishes the boxes' best, its first simplex a last box
    # step on each axis.
    h = rf.steps * (2 / (_ZOOM - 1)) ** _LEVELS
    simplex = np.vstack(
        [x0]
        + [
            x0
            + np.where(np.arange(len(names)) == j, hj, 0.0)
            * (1.0 if x0[j] + hj <= hi_b[j] else -1.0)
            for j, hj in enumerate(h)
        ]
    )
    minimize(
        f,
        x0,
        method="Nelder-Mead",
        bounds=rf.bounds,
        options={
            "xatol": 1e-9,
            "fatol": 1e-10,
            "maxfev": 200,
            "initial_simplex": simplex,
        },
    )


def _optimum(
    designs: list[GearLeverPress],
    crits: list[PressCriteria],
    refined: list[bool],
    score: _Score,
    base: PressCriteria,
    base_press: GearLeverPress,
    grid: PressGrid,
) -> PressOptimum:
    """The report of the optimum: the front recomputed over the grid's front and the
    refined designs, sorted by score (the best first), with the baseline, the grid
    and where the best design lies on the grid's bound."""
    allobj = np.array([score.objective(c.as_dict()) for c in crits])
    keep = pareto_mask(allobj)
    sel = np.flatnonzero(keep)
    scores = allobj[sel] @ score.wts
    order = sel[np.argsort(scores, kind="stable")]
    out_designs = tuple(designs[i] for i in order)
    return PressOptimum(
        designs=out_designs,
        criteria=tuple(crits[i] for i in order),
        refined=tuple(refined[i] for i in order),
        scores=np.sort(scores),
        best=0,
        baseline=base,
        baseline_press=base_press,
        grid=grid,
        objectives=score.objectives,
        edges=_edges(grid, out_designs[0], ratio=base_press.ratio),
    )


def _limit_scale(v: float) -> float:
    """The unit a limit's excess is measured in: the limit itself (1 if it is 0)."""
    return abs(v) if v != 0 else 1.0


def _starts(
    grid: PressGrid,
    ranked: npt.NDArray[np.intp],
    penalised: npt.NDArray[np.float64],
    refine: int,
    reach: int = 1,
) -> list[int]:
    """The refinement's starts: the ``refine`` best grid designs that meet the
    limits (``ranked``), then the ``refine`` best working grid designs by penalised
    score (a limit broken counts against it), each at least ``reach`` + 1 steps
    away on some axis from every start taken before, so that the starts spread
    over the grid's basins instead of one."""
    taken: list[npt.NDArray[np.intp]] = []

    def far(i: int) -> bool:
        at = np.array(np.unravel_index(i, grid.shape))
        return all(np.any(np.abs(at - t) > reach) for t in taken)

    out: list[int] = []
    for pool in (ranked, np.argsort(penalised, kind="stable")):
        n = 0
        for i in pool:
            if n == refine or not np.isfinite(penalised[i]):
                break
            if far(int(i)):
                taken.append(np.array(np.unravel_index(int(i), grid.shape)))
                out.append(int(i))
                n += 1
    return out


def _edges(grid: PressGrid, p: GearLeverPress, *, ratio: int) -> tuple[str, ...]:
    """Where design ``p`` lies on a bound of the grid: a swept axis's lowest or
    highest value, to within half a grid step (the grid cannot tell a better design
    beyond it). Not an edge: d = 0 (no lower eccentricity exists) and φ0 on an
    axis that spans a whole period 2π/i (designs repeat: the axis wraps)."""
    out = []
    units = {"d": ("mm", 1e3), "L": ("mm", 1e3), "phi0": ("°", 180 / math.pi)}
    for name in ("d", "L", "phi0"):
        if name not in grid.axes or len(grid.axes[name]) < 2:
            continue
        ax = grid.axes[name]
        lo, hi = float(ax.min()), float(ax.max())
        half = 0.5 * (hi - lo) / (len(ax) - 1)
        if name == "phi0" and hi - lo + 2 * half >= 2 * math.pi / ratio * (1 - 1e-9):
            continue
        v = float(getattr(p, name))
        u, f = units[name]
        for bound, side in ((lo, "lower"), (hi, "upper")):
            if abs(v - bound) < half and not (name == "d" and side == "lower" and bound <= 0):
                out.append(
                    f"{name} = {v * f:.4g} {u} is at the {side} bound {bound * f:.4g} {u} of the "
                    f"grid: a better design may lie beyond it"
                )
    return tuple(out)
