"""Path generation: a coupler point through target points.

The optimiser is scipy's differential evolution with ``vectorized=True``: each
generation's whole population is one call of the Rust batch evaluator
(``cyclomech._core.path_evaluate``), which scores candidate four-bars or
slider-cranks in parallel with the constraints in the same pass. The rules the
evaluator follows (the candidate's columns, the untimed error as a distance to
the sampled and refined coupler curve, the working range, the penalty that
ranks every violated candidate after every feasible one) are those of
``rust/core/src/synthesis/path.rs``; :func:`path_generation` documents them for
users.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number, flag, float_array, real_array, threads_arg
from .._errors import InfeasibleError, InputError
from ..linkage import Linkage
from ._fourbar import (
    Margins,
    four_bar_linkage,
    four_bar_margins,
    slider_crank_linkage,
    slider_crank_margins,
)

__all__ = ["PathCandidate", "path_evaluate", "path_generation"]

_COLUMNS, _PARAMS, _PENALTY = _core.path_columns()
_KINDS = ("four_bar", "slider_crank")
#: The design variables of the optimiser, in the kernel's columns (r4 is not
#: one for a slider-crank; mode is one, its sign taken).
_LENGTHS = ("r1", "r2", "r3", "r4", "u", "v", "x0", "y0")
#: The curve's resolution while searching and for the reported errors.
_SEARCH = (90, 24)  # (samples, refine)
_REPORT = (1440, 60)


@dataclass(frozen=True)
class PathCandidate:
    """One synthesised linkage, its error and its margins.

    Built by :func:`path_generation`; each field is kept as the attribute of the
    same name.

    Parameters
    ----------
    kind : str
        ``"four_bar"`` or ``"slider_crank"``.
    params : dict of str to float
        The dimensions in the frame of the targets: ``x0, y0`` the crank pivot
        A [m], ``theta0`` the direction of the ground link A→D (four-bar) or of
        the slider's guide [rad], ``r1`` the ground link |AD| (four-bar) or the
        guide's offset from A (slider-crank, signed, a quarter turn left of the
        guide's direction) [m], ``r2`` the crank, ``r3`` the coupler, ``r4`` the
        rocker (four-bar only) [m], ``u, v`` the coupler point in the coupler's
        frame (origin B, x along B→C) [m], ``mode`` ±1 the assembly mode (the σ of
        :func:`four_bar_linkage`: +1 puts C on the left of the ray D → B; for a
        slider-crank, the slider ahead of the crank pin along the guide), and with
        timing ``phi1`` the absolute crank angle at the first target [rad].
    rms : float
        RMS distance of the targets from the coupler point (timing) or from the
        coupler curve (no timing) [m].
    max : float
        The largest of those distances [m].
    angles : ndarray of float, shape (N,)
        The absolute crank angle [rad] at which the coupler point is nearest each
        target (with timing: the prescribed ones).
    points : ndarray of float, shape (N, 2)
        The coupler point at ``angles`` [m], by the batch evaluator.
    margins : Margins
        The shared margins of :func:`four_bar_margins` or
        :func:`slider_crank_margins` over the working range: Grashof type,
        whether the crank turns, the transmission angle's extremes [deg] (four-bar:
        between coupler and rocker; slider-crank: between coupler and the guide's
        normal), ``branch_ok`` (one branch, no fold, over the whole range) and the
        link-length ratio.
    full_turn : bool
        The working range was the crank's whole turn.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.synthesis import path_generation
    >>> c = path_generation([(1, 2), (2.5, 3), (3.5, 2), (2, 0.5)], seed=1, maxiter=60)[0]
    >>> c.rms < 1e-3, c.margins.grashof, c.margins.branch_ok
    (True, 'crank-rocker', True)
    >>> sol = c.linkage().solve(c.angles)
    >>> bool(np.allclose(sol["P"], c.points, atol=1e-9))
    True
    """

    kind: str
    params: dict[str, float]
    rms: float
    max: float
    angles: npt.NDArray[np.float64]
    points: npt.NDArray[np.float64]
    margins: Margins
    full_turn: bool
    _row: npt.NDArray[np.float64] = field(repr=False, compare=False)

    def linkage(self) -> Linkage:
        """This candidate as a :class:`cyclomech.Linkage`, drawn at the first
        target's crank angle by :func:`four_bar_linkage` or
        :func:`slider_crank_linkage`.

        Points A (crank pivot), B (crank tip), C (coupler–rocker joint, or the
        slider), D (rocker pivot, four-bar only) and P (the coupler point, the
        linkage's ``output``); the driver is (A, B), solved at absolute crank
        angles.

        Returns
        -------
        Linkage
            Its solve at ``angles`` places P at ``points``.

        Examples
        --------
        >>> from cyclomech.synthesis import path_generation
        >>> c = path_generation([(1, 2), (2.5, 3), (3.5, 2), (2, 0.5)], seed=1, maxiter=60)[0]
        >>> c.linkage().names
        ('A', 'B', 'C', 'D', 'P')
        """
        return _linkage(self.kind, self._row, float(self.angles[0]))


def _linkage(kind: str, row: npt.NDArray[np.float64], phi: float) -> Linkage:
    x0, y0, th, r1, r2, r3, r4, u, v, mode = (float(x) for x in row[:10])
    draw: dict[str, Any] = {
        "crank_deg": math.degrees(phi - th),
        "mode": 1 if mode >= 0 else -1,
        "coupler_point": (u, v),
        "origin": (x0, y0),
        "ground_deg": math.degrees(th),
    }
    if kind == "four_bar":
        return four_bar_linkage(r2, r3, r4, r1, name="path generation four-bar", **draw)
    return slider_crank_linkage(r2, r3, r1, name="path generation slider-crank", **draw)


def _margins(kind: str, row: npt.NDArray[np.float64], span: tuple[float, float] | None) -> Margins:
    """The shared margins over the working range: absolute crank angles
    ``span`` [rad] (None: the whole turn), measured from the ground line."""
    th, r1, r2, r3, r4 = (float(x) for x in row[2:7])
    rng = None if span is None else (math.degrees(span[0] - th), math.degrees(span[1] - th))
    if kind == "four_bar":
        return four_bar_margins(r2, r3, r4, r1, range_deg=rng)
    return slider_crank_margins(r2, r3, r1, range_deg=rng)


def _kind(kind: Any) -> str:
    if kind not in _KINDS:
        raise InputError(f"kind = {kind!r} is not one path generation knows; use one of {_KINDS}")
    return str(kind)


def _targets(points: Any, timed: bool) -> npt.NDArray[np.float64]:
    pts = real_array("points", points, "[m]", ndims=(2,))
    if pts.shape[1:] != (2,):
        raise InputError(f"points must be (x, y) pairs, shape (N, 2); got shape {pts.shape}")
    if len(pts) < 3:
        raise InputError(
            f"path generation needs at least 3 target points (two lie on any curve "
            f"through them); got {len(pts)}"
        )
    if not timed:
        # The same point twice adds nothing without timing: a slip, said so.
        for i in range(len(pts)):
            same = np.flatnonzero(np.all(pts[i + 1 :] == pts[i], axis=1))
            if same.size:
                j = i + 1 + int(same[0])
                raise InputError(
                    f"points[{i}] and points[{j}] are the same point {tuple(pts[i].tolist())}; "
                    "without timing each target must be distinct"
                )
    return np.ascontiguousarray(pts)


def _timing(timing: Any, n: int) -> npt.NDArray[np.float64] | None:
    if timing is None:
        return None
    t = real_array("timing", timing, "[deg]", ndims=(1,))
    if len(t) != n:
        raise InputError(f"timing must give one crank angle per point: {n} points, {len(t)} angles")
    return np.ascontiguousarray(np.radians(t - t[0]))


def _constraints(
    min_transmission_deg: Any, max_ratio: Any, pivot_box: Any, full_turn: Any
) -> dict[str, Any]:
    mu = finite_number("min_transmission_deg", min_transmission_deg, "[deg]", low=0.0)
    if mu >= 90.0:
        raise InputError(
            f"min_transmission_deg = {mu!r} must be below 90 [deg] (the transmission "
            "angle cannot stay above 90° and below 180° − 90° at once)"
        )
    ratio = finite_number("max_ratio", max_ratio, "(longest/shortest link)", low=1.0, inf=True)
    box = None
    if pivot_box is not None:
        b = real_array("pivot_box", pivot_box, "[m]", ndims=(1,))
        if b.shape != (4,) or b[0] > b[1] or b[2] > b[3]:
            raise InputError(
                f"pivot_box must be (xmin, xmax, ymin, ymax) [m] with xmin ≤ xmax and "
                f"ymin ≤ ymax; got {b.tolist()}"
            )
        box = [float(x) for x in b]
    return {
        "min_transmission": math.radians(mu),
        "max_ratio": ratio,
        "pivot_box": box,
        "full_turn": flag("full_turn", full_turn),
    }


def path_evaluate(
    params: npt.ArrayLike,
    points: npt.ArrayLike,
    timing: npt.ArrayLike | None = None,
    *,
    kind: str = "four_bar",
    full_turn: bool = True,
    min_transmission_deg: float = 0.0,
    max_ratio: float = math.inf,
    pivot_box: npt.ArrayLike | None = None,
    samples: int = 90,
    refine: int = 24,
    angles: bool = False,
    n_threads: int | None = None,
) -> dict[str, npt.NDArray[np.float64]]:
    """Score candidate linkages against target points, in one parallel call.

    The batch evaluator :func:`path_generation` optimises with, for users who
    sweep candidates of their own (millions per call are fine).

    Parameters
    ----------
    params : array_like of float, shape (K, 10), or (K, 11) with timing
        One candidate per row, columns ``x0, y0, theta0, r1, r2, r3, r4, u, v,
        mode`` (and ``phi1``) as in :class:`PathCandidate`'s ``params``, angles
        in radians, lengths in metres; ``mode`` ≥ 0 is +1, < 0 is −1.
    points : array_like of float, shape (N, 2)
        The targets [m].
    timing : array_like of float, shape (N,), optional
        The crank angle at each target [deg] (only differences matter: target i
        is reached at ``phi1 + timing[i] − timing[0]``).
    kind : {"four_bar", "slider_crank"}
        The mechanism the rows describe.
    full_turn, min_transmission_deg, max_ratio, pivot_box
        The constraints, as in :func:`path_generation`.
    samples : int, default 90
        Curve samples over the turn without timing.
    refine : int, default 24
        Golden-section steps refining each target's nearest sample.
    angles : bool, default False
        Also return each target's crank angle [rad], shape (K, N).
    n_threads : int, optional
        Threads (default: ``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    dict of str to ndarray
        ``cost`` (the RMS error of a feasible row; ≥ 1e100 for a violated one,
        +inf for a row with a non-finite value or a length ≤ 0), ``rms`` and
        ``max`` [m], ``violation`` (0 when feasible), ``mu_min`` and ``mu_max``
        (the transmission angle's range over the working range [rad]), each
        shape (K,); and ``angles`` (K, N) when asked.

    Raises
    ------
    InputError
        For rows of the wrong width, non-finite targets or timing, a timing of
        the wrong length or a bad constraint.

    Examples
    --------
    >>> import numpy as np
    >>> from cyclomech.synthesis import path_evaluate
    >>> row = [0, 0, 0, 4, 1, 3.5, 2.5, 1.2, 0.7, 1]   # a crank-rocker
    >>> r = path_evaluate([row], [(1, 2), (3, 3.5), (0.5, -1)])
    >>> r["cost"].shape, bool(r["violation"][0] == 0)
    ((1,), True)
    """
    k = _kind(kind)
    pts = real_array("points", points, "[m]", ndims=(2,))
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) == 0:
        raise InputError(f"points must be (x, y) pairs, shape (N, 2); got shape {pts.shape}")
    tm = _timing(timing, len(pts))
    rows = float_array("params", params, ndims=(2,))
    width = len(_PARAMS) + (tm is not None)
    if rows.shape[1] != width:
        raise InputError(
            f"params must have {width} columns ({', '.join(_PARAMS)}"
            f"{', phi1' if tm is not None else ''}); got shape {rows.shape}"
        )
    res, ang = _core.path_evaluate(
        k,
        rows,
        np.ascontiguousarray(pts),
        tm,
        samples=count("samples", samples, low=3),
        refine=count("refine", refine, low=0, high=200),
        angles=flag("angles", angles),
        n_threads=threads_arg(n_threads),
        **_constraints(min_transmission_deg, max_ratio, pivot_box, full_turn),
    )
    out = {name: np.ascontiguousarray(res[:, i]) for i, name in enumerate(_COLUMNS)}
    if ang is not None:
        out["angles"] = ang
    return out


def _bounds(
    kind: str, pts: npt.NDArray[np.float64], timed: bool, bounds: Mapping[str, Any] | None
) -> tuple[list[str], npt.NDArray[np.float64]]:
    """The optimiser's variables and their [lo, hi] (angles in rad)."""
    centre = pts.mean(axis=0)
    size = float(np.ptp(pts, axis=0).max())
    if not size > 0:
        raise InputError("the points all coincide; path generation needs targets apart")
    s = size
    default: dict[str, tuple[float, float]] = {
        "x0": (centre[0] - 3 * s, centre[0] + 3 * s),
        "y0": (centre[1] - 3 * s, centre[1] + 3 * s),
        "theta0": (-180.0, 180.0),
        "r1": (0.1 * s, 4 * s) if kind == "four_bar" else (-2 * s, 2 * s),
        "r2": (0.05 * s, 2 * s),
        "r3": (0.1 * s, 4 * s),
        "r4": (0.1 * s, 4 * s),
        "u": (-3 * s, 3 * s),
        "v": (-3 * s, 3 * s),
        "mode": (-1.0, 1.0),
    }
    if timed:
        default["phi1"] = (-180.0, 180.0)
    names = [n for n in default if not (kind == "slider_crank" and n == "r4")]
    given = dict(bounds or {})
    if not isinstance(bounds, Mapping | None):
        raise InputError(f"bounds must be a mapping of variable to (lo, hi); got {bounds!r}")
    unknown = sorted(set(given) - set(names) - {"mode"})
    if unknown:
        raise InputError(
            f"bounds has unknown variables {unknown}; the variables are {', '.join(names[:-1])}"
        )
    out = []
    for n in names:
        lo, hi = default[n]
        if n in given and n != "mode":
            b = real_array(
                f"bounds[{n!r}]", given[n], "[deg]" if "th" in n or "phi" in n else "[m]"
            )
            if b.shape != (2,) or not b[0] < b[1]:
                raise InputError(
                    f"bounds[{n!r}] = {b.tolist()} must be (lo, hi) with lo < hi; an empty or "
                    "single-valued range leaves the optimiser nothing to search"
                )
            lo, hi = float(b[0]), float(b[1])
        if n in ("r2", "r3", "r4") or (n == "r1" and kind == "four_bar"):
            if hi <= 0:
                raise InputError(f"bounds[{n!r}] = ({lo:g}, {hi:g}) must reach above 0 [m]")
            lo = max(lo, 1e-9 * s)
        if n in ("theta0", "phi1"):
            lo, hi = math.radians(lo), math.radians(hi)
        out.append((lo, hi))
    return names, np.array(out)


def path_generation(
    points: npt.ArrayLike,
    timing: npt.ArrayLike | None = None,
    *,
    kind: str = "four_bar",
    bounds: Mapping[str, Any] | None = None,
    full_turn: bool = True,
    min_transmission_deg: float = 0.0,
    max_ratio: float = math.inf,
    pivot_box: npt.ArrayLike | None = None,
    seed: int | None = None,
    popsize: int = 15,
    maxiter: int = 1000,
    tol: float = 1e-10,
    polish: bool = True,
    keep: int = 5,
    n_threads: int | None = None,
) -> list[PathCandidate]:
    """Synthesise a four-bar or slider-crank whose coupler point passes targets.

    Differential evolution (scipy, ``vectorized=True``: a generation is one
    parallel call of the Rust batch evaluator) over the dimensions, then, with
    ``polish``, least squares (scipy's ``least_squares``) on the targets'
    residuals from the best candidates.

    **Error.** With ``timing`` the crank angle at each target is prescribed up
    to one free offset (target i at ``phi1 + timing[i] − timing[0]``, the crank
    turning counter-clockwise as the angle grows), and the error of a target is
    its distance from the coupler point there. Without timing it is its distance
    from the coupler curve over the crank's whole turn: the curve is sampled at
    M crank angles, and the sample nearest each target refined by golden-section
    steps over the intervals beside it (M = 90 while searching, 1440 with 60
    steps for the reported errors; the distance found is a distance to a point
    of the curve, never below the true one). ``rms`` is the RMS of the targets'
    errors, ``max`` the largest.

    **Constraints** (checked in closed form over the working range, the whole
    turn without timing or with ``full_turn``, else the crank angles the targets
    span): the dyad closes strictly everywhere on it (no fold, so no branch
    change: the crank turns fully when the range is the whole turn, a Grashof
    crank for a four-bar); the transmission angle stays in
    [``min_transmission_deg``, 180° − ``min_transmission_deg``]; longest over
    shortest link at most ``max_ratio``; the ground pivots inside
    ``pivot_box``. A violated candidate ranks after every feasible one (its cost
    is 1e100·(1 + its relative violation)); only feasible ones are returned.

    Parameters
    ----------
    points : array_like of float, shape (N, 2)
        The targets [m], N ≥ 3 (distinct without timing).
    timing : array_like of float, shape (N,), optional
        Crank angles at the targets [deg] (only their differences matter).
    kind : {"four_bar", "slider_crank"}
        The mechanism.
    bounds : mapping of str to (float, float), optional
        Search ranges overriding the defaults (which scale with the targets'
        extent S about their centre: pivots ±3S, links up to 4S, crank up to
        2S), for ``x0, y0, r1, r2, r3, r4, u, v`` [m] and ``theta0, phi1`` [deg]
        (see :class:`PathCandidate`).
    full_turn : bool, default True
        The crank must turn fully (always so without timing).
    min_transmission_deg : float, default 0
        Smallest transmission angle allowed [deg].
    max_ratio : float, default inf
        Largest ratio of longest to shortest link (four-bar: the four; slider-crank:
        crank and coupler).
    pivot_box : (xmin, xmax, ymin, ymax), optional
        The region [m] the ground pivots (A, and D for a four-bar) must lie in.
    seed : int, optional
        Seed of the optimiser (the result is reproducible with one).
    popsize : int, default 15
        Population size per variable (scipy's ``popsize``).
    maxiter : int, default 1000
        Generations at most.
    tol : float, default 1e-10
        scipy's relative convergence tolerance.
    polish : bool, default True
        Refine the best candidates by least squares.
    keep : int, default 5
        How many distinct candidates to return at most.
    n_threads : int, optional
        Threads of the evaluator (default: ``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of PathCandidate
        Feasible candidates, best (lowest ``rms``) first.

    Raises
    ------
    InputError
        Fewer than 3 points, a non-finite value, coincident points without
        timing, a timing of the wrong length, an empty or unknown bound, a bad
        constraint.
    InfeasibleError
        When no candidate found meets the constraints (naming the ones the best
        candidate missed).

    Examples
    --------
    >>> import numpy as np
    >>> from cyclomech.synthesis import path_generation
    >>> pts = [(1, 2), (2.5, 3), (3.5, 2), (2, 0.5)]
    >>> best = path_generation(pts, seed=2, maxiter=60, min_transmission_deg=30)[0]
    >>> best.rms < 1e-3, best.margins.worst_transmission_deg >= 30
    (True, True)
    """
    k = _kind(kind)
    pts = _targets(points, timing is not None)
    tau = _timing(timing, len(pts))
    names, box = _bounds(k, pts, tau is not None, bounds)
    cons = _constraints(min_transmission_deg, max_ratio, pivot_box, full_turn)
    keep = count("keep", keep, low=1)
    prob = _Problem(k, pts, tau, names, box, cons, threads_arg(n_threads))
    found = prob.search(
        count("popsize", popsize, low=5),
        count("maxiter", maxiter, low=1),
        finite_number("tol", tol, "(relative)", low=0.0),
        None if seed is None else count("seed", seed, low=0, what="seed"),
        4 * keep,
    )
    if flag("polish", polish):
        found += [prob.polish(x0) for x0 in found[:keep]]
    return prob.ranked(found, keep)


@dataclass
class _Problem:
    """One path-generation problem: the targets, the optimiser's variables and
    their bounds, the constraints; its steps as methods."""

    kind: str
    pts: npt.NDArray[np.float64]
    tau: npt.NDArray[np.float64] | None
    names: list[str]
    box: npt.NDArray[np.float64]
    cons: dict[str, Any]
    threads: int | None

    def rows(self, x: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Optimiser vectors (D, S) → kernel rows (S, width)."""
        width = len(_PARAMS) + (self.tau is not None)
        slot = [[*_PARAMS, "phi1"].index(n) for n in self.names]
        r = np.ones((x.shape[1], width))  # r4 = 1 for a slider-crank: unused
        r[:, slot] = x.T
        return r

    def evaluate(
        self, x: npt.NDArray[np.float64], accuracy: tuple[int, int], angles: bool = False
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64] | None]:
        """The kernel's columns (and angles) of optimiser vectors (D, S)."""
        return _core.path_evaluate(
            self.kind,
            self.rows(x),
            self.pts,
            self.tau,
            # One candidate (the polish's calls): no pool to wake for it.
            n_threads=self.threads if x.shape[1] > 1 else 1,
            angles=angles,
            samples=accuracy[0],
            refine=accuracy[1],
            **self.cons,
        )

    def cost(self, x: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        return np.ascontiguousarray(self.evaluate(x, _SEARCH)[0][:, 0])

    def search(
        self, popsize: int, maxiter: int, tol: float, seed: Any, n: int
    ) -> list[npt.NDArray[np.float64]]:
        """Differential evolution, a generation a kernel call: the ``n`` best of
        the final population."""
        from scipy.optimize import differential_evolution

        de = differential_evolution(
            lambda x: self.cost(np.reshape(x, (len(self.names), -1))),
            self.box,
            popsize=popsize,
            maxiter=maxiter,
            tol=tol,
            rng=seed,
            polish=False,
            vectorized=True,
            updating="deferred",
            # Measured on targets from known linkages (timed and untimed): these
            # reach the exact linkage far more often than scipy's defaults
            # (best1bin, 0.7), which settle on a neighbouring local minimum.
            strategy="randtobest1bin",
            recombination=0.9,
        )
        order = np.argsort(de.population_energies)
        return [de.population[i] for i in order[:n]]

    def polish(self, x0: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Least squares on the targets' residual vectors (smooth in the
        dimensions, so it converges fast where DE only creeps) from ``x0``, the
        assembly mode held. A step into a violated region gets a residual that
        dominates; :meth:`ranked` keeps only feasible results anyway."""
        from scipy.optimize import least_squares

        lo, hi = self.box[:, 0], self.box[:, 1]
        im = self.names.index("mode")
        free = np.array([n != "mode" for n in self.names])
        big = 1e3 * float(np.ptp(self.pts, axis=0).max())
        x0 = x0.copy()
        x0[im] = 1.0 if x0[im] >= 0 else -1.0
        if self.cost(x0[:, None])[0] >= _PENALTY:
            return x0

        def residual(z: npt.NDArray[np.float64]) -> Any:
            x = x0.copy()
            x[free] = z
            res, ang = self.evaluate(x[:, None], _SEARCH, angles=True)
            assert ang is not None  # asked for
            # A target the curve does not reach (no sample assembles) has no
            # angle: its residual is the dominating one below.
            row = np.ascontiguousarray(self.rows(x[:, None])[0, :10])
            at = _core.path_points(self.kind, row, np.nan_to_num(ang[0]))
            r = np.append((at - self.pts).ravel(), big * res[0, 3])
            return np.where(np.isfinite(r), r, big)

        fit = least_squares(
            residual,
            np.clip(x0[free], lo[free], hi[free]),
            bounds=(lo[free], hi[free]),
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
            max_nfev=200 * len(x0),
        )
        y = x0.copy()
        y[free] = fit.x
        return y

    def ranked(self, found: list[npt.NDArray[np.float64]], keep: int) -> list[PathCandidate]:
        """The feasible ones of ``found`` at the reporting accuracy, best first,
        distinct (not the same linkage polished twice: within 1e-4 of the
        targets' extent), at most ``keep``."""
        x = np.array(found).T
        res, ang = self.evaluate(x, _REPORT, angles=True)
        final: dict[str, Any] = {name: res[:, i] for i, name in enumerate(_COLUMNS)}
        final["angles"] = ang
        cand_rows = self.rows(x)
        ok = np.flatnonzero(final["violation"] == 0)
        if ok.size == 0:
            raise InfeasibleError(_missed(final, self.cons), conflict=_conflict(self.cons))
        ok = ok[np.argsort(final["rms"][ok], kind="stable")]
        out: list[PathCandidate] = []
        span = float(np.ptp(self.pts, axis=0).max())
        for j in ok:
            row = cand_rows[j]
            if any(np.allclose(row, c._row, rtol=1e-4, atol=1e-4 * span) for c in out):
                continue
            out.append(_candidate(self.kind, row, final, int(j), self.tau, self.cons["full_turn"]))
            if len(out) == keep:
                break
        return out


def _candidate(
    kind: str,
    row: npt.NDArray[np.float64],
    final: dict[str, Any],
    i: int,
    tau: npt.NDArray[np.float64] | None,
    full: bool,
) -> PathCandidate:
    row = row.copy()
    row[9] = 1.0 if row[9] >= 0 else -1.0
    names = list(_PARAMS) + (["phi1"] if tau is not None else [])
    params = {n: float(v) for n, v in zip(names, row, strict=True)}
    if kind == "slider_crank":
        del params["r4"]
    angles = np.ascontiguousarray(final["angles"][i])
    whole = full or tau is None
    span = (
        None if whole or tau is None else (float(row[10] + tau.min()), float(row[10] + tau.max()))
    )
    return PathCandidate(
        kind=kind,
        params=params,
        rms=float(final["rms"][i]),
        max=float(final["max"][i]),
        angles=angles,
        points=_core.path_points(kind, np.ascontiguousarray(row[:10]), angles),
        margins=_margins(kind, row, span),
        full_turn=whole,
        _row=row,
    )


def _conflict(cons: dict[str, Any]) -> list[str]:
    out = ["assembly over the working range"]
    if cons["min_transmission"] > 0:
        out.append("min_transmission_deg")
    if math.isfinite(cons["max_ratio"]):
        out.append("max_ratio")
    if cons["pivot_box"] is not None:
        out.append("pivot_box")
    return out


def _missed(final: dict[str, Any], cons: dict[str, Any]) -> str:
    """Which constraints the least violated candidate misses, in words."""
    i = int(np.argmin(final["violation"]))
    mu = math.degrees(min(final["mu_min"][i], math.pi - final["mu_max"][i]))
    parts = []
    need = math.degrees(cons["min_transmission"])
    if mu <= 0 or (need > 0 and mu < need):
        parts.append(
            f"its smallest transmission angle is {mu:.3g}° (min_transmission_deg = {need:g})"
            if need > 0
            else "it does not assemble over the whole working range"
        )
    return (
        "no candidate met the constraints ("
        + ", ".join(_conflict(cons))
        + "); the least violated one misses by "
        + f"{float(final['violation'][i]):.3g} (relative)"
        + (f": {'; '.join(parts)}" if parts else "")
        + "; relax the constraints or widen the bounds"
    )
