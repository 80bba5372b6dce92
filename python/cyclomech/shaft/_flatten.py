"""The main shaft's flattening: its parts moved within the cyclogram's slack to
the lowest peak torque (:func:`flatten_phases`, ``[machine] flatten_torque``);
part of :mod:`cyclomech.shaft` (issue 19). Its LPs are solved over the cyclogram's
own feasible set (:meth:`cyclomech.Cyclogram.feasible_set`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, instance
from .._units import RAD_PER_S_PER_RPM
from ..cyclogram import Cyclogram, Optimum

__all__ = ["FLATTEN_STEP_DEG", "Flattening", "flatten_phases"]

Array = npt.NDArray[np.float64]


# --------------------------------------------------------------------- flattening
#: The grid step of the sampled min–max over relative phases [deg].
FLATTEN_STEP_DEG = 0.5
#: Candidates of one local refinement around the best grid point (± one step).
_REFINE = 201
#: Coordinate-descent sweeps at most (three or more groups).
_SWEEPS = 25
#: How far the shifted times may miss a cyclogram row before they are refused [deg].
_FEASIBLE_TOL_DEG = 1e-6

Curve = tuple[Array, Array, float, str | None]


@dataclass(frozen=True)
class Flattening:
    """The main shaft's parts moved within the cyclogram's slack to the lowest peak torque.

    The peak torque magnitude max|T| at the nominal speed is lowest
    (:func:`flatten_phases`). Each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    times : dict of str to float
        Every event's cycle angle after the move [deg] (the optimum's where
        nothing moves).
    shifts_deg : dict of str to float
        How far each contributing mechanism's curve moved along the cycle [deg]
        (its anchor event's move).
    groups : tuple of tuple of str
        The contributors that move as one (they share an event).
    peak_before_nm : float
        max|T| at the nominal speed at the optimum [N·m].
    peak_after_nm : float
        max|T| at the nominal speed after the move [N·m] (never higher), exact for
        the parts' piecewise-linear curves (the main shaft's statistics read the
        sum on its own grid of angles, which may pass between a moved part's
        samples: their peak is at most this one, and as close as the curves are
        fine).
    method : str
        How the min–max was searched.
    step_deg : float
        Its grid step [deg].
    note : str, default ""
        Why nothing moved, if nothing did.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> cg = cm.Cyclogram(limiting=("a", "b"))
    >>> cg.add_operation("a", "b", 10.0, mechanism="cam")
    >>> f = flatten_phases({"cam": (np.zeros(4), np.ones(4), 0.0, "a")}, cg, cg.optimize(), 60)
    >>> f.moved, f.peak_before_nm, f.peak_after_nm, f.note
    (False, 1.0, 1.0, 'one group of contributors: only a common shift, which leaves the peak')
    """

    times: dict[str, float]
    shifts_deg: dict[str, float]
    groups: tuple[tuple[str, ...], ...]
    peak_before_nm: float
    peak_after_nm: float
    method: str
    step_deg: float
    note: str = ""

    @property
    def moved(self) -> bool:
        """Whether any contributor moved.

        Examples
        --------
        >>> Flattening({}, {"cam": 0.0, "press": 12.5}, (("cam",), ("press",)), 9.0, 7.0,
        ...            "grid", 0.5).moved
        True
        """
        return any(v != 0.0 for v in self.shifts_deg.values())

    def json(self) -> dict[str, Any]:
        """Its ``results.json`` entry (angles in degrees).

        Returns
        -------
        dict of str to Any
            The peaks before and after [N·m], the shifts, groups and event times [deg],
            the method, its step [deg] and the note.

        Examples
        --------
        >>> f = Flattening({"a": 0.0}, {"cam": 0.0}, (("cam",),), 1.0, 1.0, "none", 0.5, "alone")
        >>> f.json()["shifts_deg"], f.json()["note"]
        ({'cam': 0.0}, 'alone')
        """
        return {
            "peak_abs_torque_nm_before": self.peak_before_nm,
            "peak_abs_torque_nm_after": self.peak_after_nm,
            "shifts_deg": dict(self.shifts_deg),
            "groups": [list(g) for g in self.groups],
            "times_deg": dict(self.times),
            "method": self.method,
            "step_deg": self.step_deg,
            "note": self.note,
        }

    def rows(self) -> list[list[Any]]:
        """Its rows of the main shaft's report table.

        Returns
        -------
        list of list
            The peaks before and after [N·m], each contributor's phase shift [deg] and
            how it was searched.

        Examples
        --------
        >>> f = Flattening({"a": 0.0}, {"cam": 0.0}, (("cam",),), 1.0, 1.0, "none", 0.5, "alone")
        >>> f.rows()[-1]
        ['flattening', 'none; 0.5° grid refined to 0.005°; alone']
        """
        out: list[list[Any]] = [
            ["peak |torque| before flattening [N·m]", self.peak_before_nm],
            ["peak |torque| after flattening [N·m]", self.peak_after_nm],
        ]
        out += [[f"phase shift of {k} [deg]", v] for k, v in self.shifts_deg.items()]
        how = f"{self.method}; {self.step_deg:g}° grid refined to {self.step_deg / 100:g}°"
        out.append(["flattening", f"{how}; {self.note}" if self.note else how])
        return out


class _Feasible:
    """The cyclogram's LP feasible set at one speed over x = (p_0 … p_{V−1}, F),
    :meth:`cyclomech.Cyclogram.feasible_set` (the rows of its optimize:
    every operation's minimum angle at that speed — so the mechanisms' bounds added
    by :meth:`~cyclomech.Machine.cyclogram_at` too — and maximum, the added
    constraints, the span p_v ≤ F ≤ cycle, p ≥ 0); plus
    the optimum's objective kept (the limiting angle ≥ its optimum, or the span ≤
    the optimum's duration) and each rigid group's events at their spacing in the
    optimum. Dense: cyclograms have tens of events."""

    def __init__(self, cg: Cyclogram, opt: Optimum, rpm: float, groups: list[list[str]]) -> None:
        ev = {e: i for i, e in enumerate(cg.events)}
        V = len(ev)
        self.V, self.n = V, V + 1
        C = cg.cycle_deg
        self.set = cg.feasible_set(rpm)
        # The first objective kept: the shifts only use the slack. To round-off,
        # as the optimum's own (tidied) times reach it.
        t = np.array([opt.times[e] for e in cg.events])
        self.t0 = t
        tol = 1e-9
        keep = np.zeros((1, self.n))
        if opt.limiting is not None:
            o = cg.operation(opt.limiting)
            keep[0, ev[o.src]], keep[0, ev[o.dst]] = 1.0, -1.0
            got = t[ev[o.dst]] - t[ev[o.src]] + C * o.height
            self.set.add_ub(keep, np.array([C * o.height - min(opt.objective, got) + tol]))
        else:
            keep[0, V] = 1.0
            self.set.add_ub(keep, np.array([max(opt.objective, float(t.max() - t.min())) + tol]))
        # Each rigid group: its events at their spacing in the optimum.
        for g in groups:
            r = ev[g[0]]
            for e in g[1:]:
                row = np.zeros((1, self.n))
                row[0, ev[e]], row[0, r] = 1.0, -1.0
                self.set.add_eq(row, np.array([t[ev[e]] - t[r]]))
        self.ref = [ev[g[0]] for g in groups]

    def violation(self, x: Array) -> float:
        """The largest amount [deg] by which the point x misses a row."""
        return self.set.violation(x)

    def _fix(self, s: Array, held: Any, base: int) -> tuple[Array, Array]:
        """Rows holding the groups ``held`` at their shifts ``s`` relative to group ``base``."""
        keep = [h for h in held if h != base]
        rows = np.zeros((len(keep), self.n))
        rhs = np.zeros(len(keep))
        rb = self.ref[base]
        for i, h in enumerate(keep):
            rh = self.ref[h]
            rows[i, rh], rows[i, rb] = 1.0, -1.0
            rhs[i] = self.t0[rh] - self.t0[rb] + s[h] - s[base]
        return rows, rhs

    def _solve(self, c: Array, rows: Array, rhs: Array) -> Any:
        return self.set.minimize(c, eq=(rows, rhs))

    def interval(
        self, g: int, s: Array, held: Any = None, *, current: bool = True
    ) -> tuple[float, float] | None:
        """The exact range of group ``g``'s shift with the groups ``held`` (default:
        all others) at their shifts in ``s``, the rest free (two LPs: the
        projection of a convex set on a line); ``current``: ``s[g]`` is feasible,
        kept inside the range against round-off. None if there is no such shift."""
        base = 1 if g == 0 else 0
        if held is None:
            held = [h for h in range(len(self.ref)) if h not in (g, base)]
        rows, rhs = self._fix(s, held, base)
        rg, rb = self.ref[g], self.ref[base]
        c = np.zeros(self.n)
        c[rg], c[rb] = 1.0, -1.0
        off = self.t0[rg] - self.t0[rb] - s[base]
        lo, hi = self._solve(c, rows, rhs), self._solve(-c, rows, rhs)
        if not current:
            if lo.status != 0 or hi.status != 0:
                return None
            return lo.fun - off, -hi.fun - off
        a = lo.fun - off if lo.status == 0 else s[g]
        z = -hi.fun - off if hi.status == 0 else s[g]
        return min(a, s[g]), max(z, s[g])

    def place(self, s: Array) -> Array | None:
        """Event angles with the groups at the relative shifts ``s``: the least
        total |shift| of the groups' anchors from the optimum (an LP), then the
        earliest events at that (a second LP, as the optimum's own tidying)."""
        G, n = len(self.ref), self.n
        rows, rhs = self._fix(s, range(1, G), 0)
        # Variables (x, u): u_g ≥ |p_{r_g} − t_{r_g}|.
        U = np.zeros((2 * G, n + G))
        bu = np.zeros(2 * G)
        for g, r in enumerate(self.ref):
            U[2 * g, r], U[2 * g, n + g], bu[2 * g] = 1.0, -1.0, self.t0[r]
            U[2 * g + 1, r], U[2 * g + 1, n + g], bu[2 * g + 1] = -1.0, -1.0, -self.t0[r]
        c = np.r_[np.zeros(n), np.ones(G)]
        first = self.set.minimize(c, ub=(U, bu), eq=(rows, rhs))
        if first.status != 0:
            return None
        pin = c[None]
        second = self.set.minimize(
            np.r_[np.ones(self.V), np.zeros(1 + G)],
            ub=(np.vstack([U, pin]), np.r_[bu, first.fun * (1 + 1e-9) + 1e-9]),
            eq=(rows, rhs),
        )
        x = second.x if second.status == 0 else first.x
        return np.asarray(x[:n], dtype=np.float64)


def _peaks(T: Array, phase: Array, shifts: Array) -> Array:
    """max_θ |Σ_i T_i(θ − φ_i − s_i)| [N·m] for each row of ``shifts`` (M, K)
    [deg], exactly, for the curves T (K, N) linear between their samples
    360°·k/N (periodic): the maximum of a piecewise-linear function is at a
    breakpoint, so the sum is read at every part's samples, the others
    interpolated there. So a common shift of all parts leaves it as it is (a
    reading on one fixed grid would not: it would see the sum between the
    breakpoints of a part moved off the grid). The candidates in chunks (numpy),
    no loop over angles; K(K − 1) interpolated reads of (M, N)."""
    K, N = T.shape
    M = len(shifts)
    out = np.empty(M)
    h = 360.0 / N
    k = np.arange(N)
    # Two turns and one sample of each curve and of its steps: index k + j0 < 2N.
    T2 = np.concatenate([T, T, T[:, :1]], axis=1)
    D2 = np.diff(T2, axis=1)
    step = max(1, 1_000_000 // N)
    for a in range(0, M, step):
        s = phase[None, :] + shifts[a : a + step]
        best = np.zeros(len(s))
        for i in range(K):  # the sum at part i's breakpoints θ = φ_i + s_i + k·h
            total = np.repeat(T[i][None], len(s), axis=0)
            for j in range(K):
                if j == i:
                    continue
                # T_j at θ − φ_j − s_j = k·h + (φ_i + s_i − φ_j − s_j): index k + u.
                u = np.mod((s[:, i] - s[:, j]) / h, N)
                j0 = np.minimum(np.floor(u), N - 1)
                f = (u - j0)[:, None]
                idx = k[None, :] + j0.astype(np.int64)[:, None]
                total += np.take(T2[j], idx) + f * np.take(D2[j], idx)
            best = np.maximum(best, np.abs(total).max(axis=1))
        out[a : a + step] = best
    return out


def _rigid_groups(
    curves: Mapping[str, Curve], cg: Cyclogram, extra: Mapping[str, Any]
) -> tuple[list[list[str]], list[int]]:
    """The contributors' rigid event sets, merged where they share an event:
    (the events of each group, its anchor first; each contributor's group)."""
    names = list(curves)
    own: list[set[str]] = []
    for k in names:
        s = {str(curves[k][3])}
        s |= {e for o in cg.operations if o.mechanism == k for e in o.arc}
        s |= {e for e in extra.get(k, ()) if e in cg.events}
        own.append(s)
    parent = list(range(len(names)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i in range(len(names)):
        for j in range(i):
            if own[i] & own[j]:
                parent[root(i)] = root(j)
    roots = sorted({root(i) for i in range(len(names))})
    of = [roots.index(root(i)) for i in range(len(names))]
    groups = []
    for g, r in enumerate(roots):
        first = str(curves[names[r]][3])
        evs = set().union(*(own[i] for i in range(len(names)) if of[i] == g)) - {first}
        groups.append([first, *sorted(evs, key=cg.events.index)])
    return groups, of


#: Divisors of a turn the coarse grid of three groups steps by [deg].
_COARSE_STEPS = (0.5, 1, 2, 2.5, 3, 4, 5, 6, 7.5, 8, 9, 10, 12, 15, 18, 20, 24, 30, 36, 45, 60, 90)
#: Points per axis of the coarse grid of three groups, at most.
_COARSE_POINTS = 72
#: Points of one line search, at most (a cycle of 10⁴ turns would otherwise ask for 10⁸).
_LINE_POINTS = 20_000


def _grid(lo: float, hi: float, step: float, *extra: float) -> Array:
    """The multiples of ``step`` in [lo, hi] (the optimum's phase on the grid),
    the ends and ``extra``; ``step`` grows if that would be over 20 000 points."""
    step = max(step, (hi - lo) / _LINE_POINTS)
    k = np.arange(math.ceil(lo / step), math.floor(hi / step) + 1) * step
    return np.unique(np.r_[lo, k, hi, extra])


def _plane(
    lp: _Feasible, evaluate: Any, step: float, tol: float, current: float
) -> tuple[Array, float, float]:
    """Three groups: the peak on a grid of both relative phases (group 0 held)
    over their exact admissible region — the range of group 1's shift (two LPs,
    group 2 free), and on each of its grid values the range of group 2's (two
    LPs each) — at most 72 points a side on a step that divides the turn, the
    optimum among them, ranked on the curves read every grid step. Returns the
    best shifts, their exact peak and the step; the optimum's when nothing beats
    it (coordinate descent then polishes)."""
    zero = np.zeros(3)
    got = lp.interval(1, zero, held=[])
    assert got is not None
    lo1, hi1 = got

    def coarse(width: float) -> float:
        raw = max(step, width / _COARSE_POINTS)
        return next((c for c in _COARSE_STEPS if c >= raw), raw)

    c = coarse(hi1 - lo1)
    cand = [zero[None]]
    for v in _grid(lo1, hi1, c, 0.0):
        row = lp.interval(2, np.array([0.0, v, 0.0]), held=[1], current=False)
        if row is None:
            continue
        d2 = _grid(row[0], row[1], max(c, coarse(row[1] - row[0])))
        cand.append(np.c_[np.zeros(len(d2)), np.full(len(d2), v), d2])
    S = np.vstack(cand)
    pk, mv = evaluate(S, exact=False)
    best = S[_best(pk, mv, tol)]
    exact = float(evaluate(best[None])[0][0])
    if exact < current - tol:
        return best.copy(), exact, c
    return zero, current, c


def _best(peaks: Array, moves: Array, tol: float) -> int:
    """The candidate of least peak; within ``tol`` of it, the least total move
    (then the first)."""
    near = peaks <= peaks.min() + tol
    return int(np.flatnonzero(near)[np.argmin(moves[near])])


def flatten_phases(
    curves: Mapping[str, Curve],
    cyclogram: Cyclogram,
    optimum: Optimum,
    nominal_rpm: float,
    *,
    rigid: Mapping[str, Any] | None = None,
    step_deg: float = FLATTEN_STEP_DEG,
) -> Flattening:
    """Move the main shaft's parts within the cyclogram's slack to the lowest peak torque.

    The peak torque magnitude max|T(θ)| [N·m] at ``nominal_rpm`` is made lowest,
    keeping the optimum's first objective (a second objective after it).

    Rules:

    * A contributor moves rigidly: its anchor event, the events of the operations
      whose ``mechanism`` is it and the events in ``rigid[name]`` (the arcs it is
      laid out on) keep their spacing, so its curve stays exact. Contributors that
      share an event move as one group.
    * The admissible moves are the LP's feasible set at the nominal speed (every
      operation's minimum angle there, the mechanisms' bounds, maximum angles,
      constraints, the cycle) with the limiting operation's angle at least its
      optimum (without one: the span at most the optimum's duration). Events of
      no contributor move as the LP lets them.
    * Only the groups' relative phases change the peak; the search runs over them
      (G − 1 dimensions for G groups), each move along one group's exact admissible
      segment (two LPs, with the other groups held): a sampled min–max on the
      multiples of ``step_deg`` [deg] (0.5° by default) over the whole segment
      (ranked on the curves read every ``step_deg`` where they are finer), then,
      exactly, a grid of step ``step_deg``/100 within one step of the best, the
      current phase always a candidate. With two groups that is the whole admissible set. With
      three, first a coarse grid of both relative phases over their exact
      admissible region (the range of one, and on each of its grid values the
      range of the other, by LPs; at most 72 points a side on a step that divides
      the turn), then coordinate descent from its best point. With four or more,
      coordinate descent over the groups from the optimum until a sweep improves
      nothing (a local method: it never raises the peak, it may stop short of the
      global min–max). One group (or none): nothing to move.
    * Peaks within 1e-9 of the scale Σ max|T_i| are ties: the smaller total move
      Σ|s_g − median(s)| wins, so the optimum stands unless a move strictly lowers
      the peak. The event angles of the chosen phases are then placed by an LP with
      the least Σ|shift| of the groups' anchors, events earliest after that.
    * Any LP failure, or shifted times that miss a cyclogram row by more than
      1e-6°, leave the optimum unchanged (``note`` says why).

    Parameters
    ----------
    curves : Mapping of str to tuple
        Each contributor's ``shaft_torque()``: (ω² part [N·m·s²], static part
        [N·m] on its own angle; phase [deg]; anchor event).
    cyclogram : ~cyclomech.Cyclogram
        The cyclogram at the nominal speed with the mechanisms' bounds
        (:meth:`~cyclomech.Machine.cyclogram_at`).
    optimum : ~cyclomech.Optimum
        Its optimum there.
    nominal_rpm : float
        The nominal speed [rpm].
    rigid : Mapping of str to sequence of str, optional
        For each contributor, the events of the arcs it is laid out on, which move
        with it; default None (none).
    step_deg : float, default 0.5
        The grid step of the sampled min–max [deg] (> 0, :data:`FLATTEN_STEP_DEG`).

    Returns
    -------
    Flattening
        The moved event times and shifts [deg], the peaks before and after [N·m],
        the method and the note.

    Raises
    ------
    InputError
        If ``step_deg`` is not > 0 or ``nominal_rpm`` is negative.
    TypeError
        If ``curves`` is not a mapping, ``cyclogram`` not a :class:`~cyclomech.Cyclogram` or
        ``optimum`` not an :class:`~cyclomech.Optimum`.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> cg = cm.Cyclogram(limiting=("L0", "L1"))
    >>> for x, y, m in (("L0", "L1", None), ("a0", "a1", "A"), ("b0", "b1", "B")):
    ...     cg.add_operation(x, y, 10.0, mechanism=m)
    >>> th = np.radians(np.arange(360.0))
    >>> wave = (np.zeros(360), 5.0 + 2.0 * np.cos(th))
    >>> f = flatten_phases({"A": (*wave, 0.0, "a0"), "B": (*wave, 0.0, "b0")},
    ...                    cg, cg.optimize(), 100.0)
    >>> round(f.peak_before_nm, 6), round(f.peak_after_nm, 6)
    (14.0, 10.0)
    >>> abs(f.shifts_deg["B"] - f.shifts_deg["A"])
    180.0
    """
    step = finite_number("step_deg", step_deg, "[deg]", low=0.0, strict=True)
    rpm = finite_number("nominal_rpm", nominal_rpm, "[rpm]", low=0.0)
    # Objects of the wrong type fail here, by name (not deep inside the search).
    instance("curves", curves, Mapping)
    instance("cyclogram", cyclogram, Cyclogram)
    instance("optimum", optimum, Optimum)
    if not curves:  # no contributor: nothing to move, and no torque to peak
        return _unmoved(optimum, [], (), 0.0, step, "no contributors: nothing to move")
    names = list(curves)
    w2 = (rpm * RAD_PER_S_PER_RPM) ** 2
    T = np.array([w2 * np.asarray(c[0]) + np.asarray(c[1]) for c in curves.values()])
    phase = np.array([float(c[2]) for c in curves.values()])
    fixed = [k for k, c in curves.items() if c[3] is None]
    if fixed:
        # A part whose phase follows no event sits at a fixed cycle angle: the
        # others' moves would not be relative. Nothing moves; the note says why.
        note = (
            f"{', '.join(fixed)}: its phase follows no cyclogram event (phase = {{event = "
            "…}} in its table), so the parts cannot be moved relative to each other"
        )
        return _unmoved(optimum, names, (tuple(names),), _peak_of(curves, phase, w2), step, note)
    groups, of = _rigid_groups(curves, cyclogram, rigid or {})
    G = len(groups)
    before = _peak_of(curves, phase, w2)
    tied = tuple(tuple(k for k, g in zip(names, of, strict=True) if g == j) for j in range(G))

    def unchanged(note: str, method: str = "none") -> Flattening:
        return _unmoved(optimum, names, tied, before, step, note, method)

    if G < 2:
        return unchanged("one group of contributors: only a common shift, which leaves the peak")
    lp = _Feasible(cyclogram, optimum, rpm, groups)
    x0 = np.r_[lp.t0, lp.t0.max()]
    if lp.violation(x0) > _FEASIBLE_TOL_DEG:
        return unchanged("the optimum misses the rebuilt LP's rows; left as it is")
    scale = float(np.abs(T).max(axis=1).sum())
    tol = 1e-9 * scale
    of_arr = np.array(of)

    # The grids rank candidates on the curves read every grid step (when finer);
    # the refinement and every acceptance read them exactly.
    n_grid = math.ceil(360.0 / step)
    if T.shape[1] > n_grid:
        own = np.arange(T.shape[1]) * 360.0 / T.shape[1]
        at = np.arange(n_grid) * 360.0 / n_grid
        T_grid = np.array([np.interp(at, own, t, period=360.0) for t in T])
    else:
        T_grid = T

    def evaluate(S: Array, exact: bool = True) -> tuple[Array, Array]:
        moves = np.abs(S - np.median(S, axis=1, keepdims=True)).sum(axis=1)
        return _peaks(T if exact else T_grid, phase, S[:, of_arr]), moves

    s = np.zeros(G)
    current = float(evaluate(s[None])[0][0])
    method = (
        "sampled min–max over the whole admissible range of the relative phase"
        if G == 2
        else "coordinate descent from the optimum (local), sampled"
    )
    if G == 3:
        s, current, coarse = _plane(lp, evaluate, step, tol, current)
        method = (
            f"grid of both relative phases over their admissible region ({coarse:g}°), "
            "then coordinate descent, sampled"
        )
    for _ in range(_SWEEPS):
        moved = False
        for g in [1] if G == 2 else range(G):
            got = lp.interval(g, s)
            assert got is not None
            lo, hi = got
            grid = _grid(lo, hi, step, s[g])
            S = np.repeat(s[None], len(grid), axis=0)
            S[:, g] = grid
            pk, mv = evaluate(S, exact=False)
            i = _best(pk, mv, tol)
            fine = np.linspace(max(lo, grid[i] - step), min(hi, grid[i] + step), _REFINE)
            S = np.repeat(s[None], len(fine) + 2, axis=0)
            S[:, g] = np.r_[s[g], grid[i], fine]
            pk, mv = evaluate(S)
            i = _best(pk, mv, tol)
            if pk[i] < current - tol:
                s, current, moved = S[i].copy(), float(pk[i]), True
        if not moved or G == 2:
            break
    if not (s != 0.0).any():
        return unchanged("no move within the slack lowers the peak", method)
    x = lp.place(s)
    if x is None:
        return unchanged("the LP could not place the events at the chosen phases", method)
    if lp.violation(x) > _FEASIBLE_TOL_DEG:
        return unchanged("the placed events miss a cyclogram row; left as they were", method)
    times = dict(zip(cyclogram.events, x[: lp.V].tolist(), strict=True))
    anchor = {k: str(c[3]) for k, c in curves.items()}  # every part has one (see above)
    shifts = {k: times[anchor[k]] - optimum.times[anchor[k]] for k in curves}
    after = _peak_of(curves, phase + np.array(list(shifts.values())), w2)
    if after > before:  # (round-off: the placed shifts hold the chosen ones to ~1e-9°)
        return unchanged("no move within the slack lowers the peak", method)
    return Flattening(
        times=times,
        shifts_deg=shifts,
        groups=tied,
        peak_before_nm=before,
        peak_after_nm=after,
        method=method,
        step_deg=step,
    )


def _unmoved(
    optimum: Optimum,
    names: list[str],
    groups: tuple[tuple[str, ...], ...],
    peak: float,
    step: float,
    note: str,
    method: str = "none",
) -> Flattening:
    """The optimum left as it is: no part of ``names`` moved, the peak ``peak``
    [N·m] unchanged; ``note`` says why."""
    return Flattening(
        times=dict(optimum.times),
        shifts_deg={k: 0.0 for k in names},
        groups=groups,
        peak_before_nm=peak,
        peak_after_nm=peak,
        method=method,
        step_deg=step,
        note=note,
    )


def _peak_of(curves: Mapping[str, Curve], phase: Array, w2: float) -> float:
    """max|T| [N·m] of the phased sum at ω² = ``w2`` (exact, :func:`_peaks`)."""
    T = np.array([w2 * np.asarray(c[0]) + np.asarray(c[1]) for c in curves.values()])
    return float(_peaks(T, phase, np.zeros((1, len(T))))[0])
