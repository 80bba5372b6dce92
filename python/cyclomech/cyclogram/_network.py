"""A cyclogram solved at many speeds at once: the one place where a machine's
cyclogram is optimised against speed and its speed limit searched; part of
:mod:`cyclomech.cyclogram`."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import (
    SPEED_CAP_RPM,
    count,
    flag,
    float_array,
    instance,
    positive,
    real_array,
    speed_rtol,
)
from .._errors import InputError
from ._angles import Arc, minimum_angles
from ._bounds import proportional_law
from ._graph import max_difference
from ._layout import Layout
from ._lp import LP
from ._model import Cyclogram
from ._types import Constraint

__all__ = ["SPEED_FLOOR_RPM", "BoundsAt", "SpeedNetwork"]

Array = npt.NDArray[np.float64]
#: Lowest speed a speed-limit search tries [rpm]: a cyclogram that does not fit
#: there fits at no speed (its time bounds and speed-proportional bounds only shrink
#: as the speed falls).
SPEED_FLOOR_RPM = 1e-6
_Ints = npt.NDArray[np.int64]
#: The network as the proportional kernels take it (n, src, dst, base, source,
#: target, lim_shift, min_edge, angle, secs, bound_op).
_KernelArgs = tuple[int, _Ints, _Ints, Array, int, int, float, _Ints, Array, Array, _Ints]
#: The type of ``bounds_at(designs, rpm)``, the extra bounds of
#: :meth:`SpeedNetwork.fits` and :meth:`SpeedNetwork.speed_limits`: each extra
#: bound's smallest angle [deg] for the designs ``designs`` (int indices, (D',)) at
#: their speeds ``rpm`` [rpm] (D', M), one (D'·M,) array a bound in the row order
#: of ``rpm.reshape(-1)`` (NaN: no angle is enough).
BoundsAt = Callable[[npt.NDArray[np.int64], Array], list[Array]]


class SpeedNetwork:
    """A cyclogram's LP solved at many speeds (and designs) in one shortest-path call.

    The LP is a system of difference constraints over the event angles p, a zero
    node z and the span's end F: every operation's minimum (its angle, its
    duration, the extra ``bounds``) and maximum, every single-operation constraint,
    p ≥ 0, p ≤ F and F ≤ cycle. The limiting operation's optimal angle is the
    shortest path from its start to its end (plus the cycles it crosses).
    Constraints over several operations need the LP instead, one per speed.

    Parameters
    ----------
    cg : Cyclogram
        The cyclogram; it must name its limiting operation.
    bounds : sequence of (tuple of (str, str), str), default ()
        (arc, label) of each extra lower bound on an operation's angle that
        mechanisms impose (a stop's rebound bound, ``"rebound[lifter]"``); their
        values at each speed are given to :meth:`solve`.

    Raises
    ------
    InputError
        If the cyclogram has no limiting operation (``[cyclogram] limiting``).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> cg = cm.Cyclogram(limiting=("b", "c"))
    >>> cg.add_operation("a", "b", min_angle_deg=100, min_duration_s=0.05)
    >>> cg.add_operation("b", "c", min_angle_deg=60)
    >>> net = cm.cyclogram.SpeedNetwork(cg)
    >>> angle, fits, binding, _ = net.solve(np.array([300.0, 1300.0]), [])
    >>> angle.round(3).tolist(), fits.tolist(), binding.tolist()    # 360 − max(100, 6·n·0.05)
    ([260.0, nan], [True, False], ['min[a→b]; cycle', ''])
    """

    def __init__(self, cg: Cyclogram, bounds: Sequence[tuple[Arc, str]] = ()) -> None:
        instance("cg", cg, Cyclogram)
        if isinstance(bounds, str | bytes | Mapping) or not isinstance(bounds, Sequence):
            raise TypeError(f"bounds must be a sequence of (arc, label); got {bounds!r}")
        if cg.limiting is None:
            raise InputError(
                f"cyclogram {cg.name!r}: a machine needs its limiting operation "
                "([cyclogram] limiting = [from, to])"
            )
        self.cg = cg
        # The solvers' view of the cyclogram, from its public contents.
        self.lay = lay = Layout(cg.name, cg.events, cg.operations, cg.constraints)
        ev = lay.index
        V = len(ev)
        z, F = V, V + 1
        self.n = V + 2
        C = cg.cycle_deg
        labels = lay.labels
        src: list[int] = []
        dst: list[int] = []
        base: list[float] = []  # constant part of each edge's weight
        self.kind: list[str] = []  # "min", "max", "user", "cycle", ""
        self.label: list[str] = []
        self.op: list[int] = []

        def edge(s: int, d: int, w: float, kind: str, label: str, op: int) -> None:
            src.append(s)
            dst.append(d)
            base.append(w)
            self.kind.append(kind)
            self.label.append(label)
            self.op.append(op)

        ops = lay.ops
        self.min_edge = np.empty(len(ops), np.int64)
        for e, op in enumerate(ops):
            x, y = ev[op.src], ev[op.dst]
            self.min_edge[e] = len(src)
            edge(y, x, C * op.height, "min", labels[e], e)
            if op.max_angle_deg is not None:
                edge(x, y, op.max_angle_deg - C * op.height, "max", f"max[{labels[e]}]", e)
        self.general: list[Constraint] = []
        self.always_false: list[Constraint] = []
        for con in cg.constraints:
            coeff: dict[Arc, float] = {}
            for arc, c in con.coeffs:
                coeff[arc] = coeff.get(arc, 0.0) + c
            terms = [(a, c) for a, c in coeff.items() if c != 0.0]
            if len(terms) > 1:
                self.general.append(con)
                continue
            if not terms:
                holds = {"<=": con.rhs >= 0.0, ">=": con.rhs <= 0.0, "==": con.rhs == 0.0}
                if not holds[con.sense]:
                    self.always_false.append(con)
                continue
            (arc, c), bound = terms[0], con.rhs / terms[0][1]
            op = cg.operation(arc)
            e = lay.arc_index[op.arc]
            x, y = ev[op.src], ev[op.dst]
            upper = (con.sense == "<=") == (c > 0)
            senses = ("upper", "lower") if con.sense == "==" else ("upper" if upper else "lower",)
            for sense in senses:
                if sense == "upper":  # t ≤ bound
                    edge(x, y, bound - C * op.height, "user", con.name, e)
                else:  # t ≥ bound
                    edge(y, x, C * op.height - bound, "user", con.name, e)
        for v in range(V):  # p_v ≥ 0 (z − p_v ≤ 0) and p_v ≤ F
            edge(v, z, 0.0, "", "", -1)
            edge(F, v, 0.0, "", "", -1)
        edge(z, F, C, "cycle", "cycle", -1)
        self.src = np.array(src, np.int64)
        self.dst = np.array(dst, np.int64)
        self.base = np.array(base, np.float64)
        lim = cg.operation(cg.limiting)
        self.source, self.target = ev[lim.src], ev[lim.dst]
        self.lim_shift = C * lim.height
        self.angle = np.array([op.min_angle_deg for op in ops], np.float64)
        self.secs = np.array([op.min_duration_s for op in ops], np.float64)
        self.bound_op = [lay.arc_index[cg.operation(arc).arc] for arc, _ in bounds]
        self.bound_labels = [label for _, label in bounds]

    def minimums(self, rpm: Array, t_bound: Sequence[Array]) -> tuple[Array, npt.NDArray[np.int8]]:
        """Each operation's minimum angle at each speed and which lower bound sets it.

        Parameters
        ----------
        rpm : ndarray of float, shape (B,)
            The speeds [rpm].
        t_bound : sequence of ndarray of float, shape (B,)
            The extra bounds' angles [deg], one array a bound (in the order of
            ``bounds``); NaN: no angle is enough.

        Returns
        -------
        mins : ndarray of float, shape (B, E)
            Each operation's minimum angle [deg] at each speed.
        which : ndarray of int8, shape (B, E)
            The lower bound that sets it: 0 its angle, 1 its duration, 2 + k the
            extra bound k.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_angle_deg=100)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg, [(("a", "b"), "wear")])
        >>> mins, which = net.minimums(np.array([1.0, 2.0]), [np.array([90.0, 120.0])])
        >>> mins.tolist(), which.tolist()
        ([[100.0, 60.0], [120.0, 60.0]], [[0, 0], [2, 0]])
        """
        rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(1,))
        t_bound = self._bound_angles(t_bound, rpm.shape)
        mins, by_time = minimum_angles(self.angle, self.secs, rpm)
        which = by_time.astype(np.int8)
        for k, (e, t) in enumerate(zip(self.bound_op, t_bound, strict=True)):
            t = np.nan_to_num(t, nan=-np.inf)
            take = t > mins[:, e]
            mins[take, e], which[take, e] = t[take], 2 + k
        return mins, which

    def solve(
        self,
        rpm: Array,
        t_bound: Sequence[Array],
        n_threads: int | None = None,
        *,
        labels: bool = True,
    ) -> tuple[Array, npt.NDArray[np.bool_], npt.NDArray[np.object_], Array]:
        """The limiting operation's optimal angle at each speed, and what sets it.

        One shortest-path call for every speed (the LP per speed where constraints
        span several operations).

        Parameters
        ----------
        rpm : ndarray of float, shape (B,)
            The speeds [rpm].
        t_bound : sequence of ndarray of float, shape (B,)
            The extra bounds' angles [deg], one array a bound; NaN: no angle is
            enough.
        n_threads : int, optional
            Threads for the shortest paths (default: ``CYCLOMECH_THREADS`` or all
            cores).
        labels : bool, default True
            Name the bounds on the chain; False leaves ``binding`` empty (faster).

        Returns
        -------
        angle : ndarray of float, shape (B,)
            The limiting operation's optimal angle [deg] (NaN where it does not
            fit).
        fits : ndarray of bool, shape (B,)
            The fit flags.
        binding : ndarray of object, shape (B,) or (0,)
            The names of the bounds on the chain that sets it (joined by ``"; "``;
            an empty array with ``labels=False``).
        mins : ndarray of float, shape (B, E)
            The minimum angles [deg].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_angle_deg=100)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg, [(("a", "b"), "wear")])
        >>> angle, fits, binding, _ = net.solve(np.array([1.0, 2.0]), [np.array([90.0, 120.0])])
        >>> angle.tolist(), binding.tolist()
        ([260.0, 240.0], ['min[a→b]; cycle', 'wear; cycle'])
        """
        rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(1,))
        t_bound = self._bound_angles(t_bound, rpm.shape)
        labels = flag("labels", labels)
        w, bound_ok, mins, which = self._weights(rpm, t_bound)
        if self.always_false:
            bound_ok[:] = False
            w[:] = self.base
        extra: list[list[str]] = []
        if self.general:
            value, on_path, extra = self._lp(rpm, mins, bound_ok)
        else:
            got, on_path = max_difference(
                self.n, self.src, self.dst, w, self.source, self.target, n_threads=n_threads
            )
            value = np.asarray(got, dtype=np.float64)
        value = np.where(bound_ok & np.isfinite(value), value + self.lim_shift, np.nan)
        fits = np.isfinite(value)
        if not labels:
            return value, fits, np.empty(0, dtype=object), mins
        named = self._labels(on_path, which, fits)
        for i, names in enumerate(extra):
            if names and fits[i]:
                named[i] = "; ".join([named[i], *names] if named[i] else names)
        return value, fits, named, mins

    def _weights(
        self, rpm: Array, t_bound: Sequence[Array]
    ) -> tuple[Array, npt.NDArray[np.bool_], Array, Any]:
        """The arcs' weights at each speed (B, E), whether every extra bound has an
        angle there, and the minimum angles with what sets each (:meth:`minimums`)."""
        mins, which = self.minimums(rpm, t_bound)
        w = np.broadcast_to(self.base, (rpm.size, self.base.size)).copy()
        w[:, self.min_edge] -= mins
        bound_ok = np.ones(rpm.size, bool)
        for t in t_bound:
            bound_ok &= np.isfinite(t)
        # A bound no angle meets (+inf: a servo's RMS beyond what any angle
        # gives) means no fit at that speed: its row is not solved (value NaN
        # below), so give it finite weights.
        w[~bound_ok] = self.base
        return w, bound_ok, mins, which

    def minimums_fit(
        self, rpm: Array, t_bound: Sequence[Array], n_threads: int | None = None
    ) -> npt.NDArray[np.bool_]:
        """Whether the minimum angles alone fit in the cycle at each speed.

        The network without the maximum angles and the constraints: every
        operation's minimum (its angle, its duration, the extra ``bounds``) and the
        cycle, solved by the same shortest paths (and tolerance) as :meth:`solve`.
        Where :meth:`solve` finds no fit but this does, a maximum or a constraint
        conflicts with the minimums; where neither fits, the minimums fill the cycle.

        Parameters
        ----------
        rpm : ndarray of float, shape (B,)
            The speeds [rpm].
        t_bound : sequence of ndarray of float, shape (B,)
            The extra bounds' angles [deg], one array a bound; NaN: no angle is
            enough (no fit).
        n_threads : int, optional
            Threads for the shortest paths (default: ``CYCLOMECH_THREADS`` or all
            cores).

        Returns
        -------
        ndarray of bool, shape (B,)
            Whether the minimum angles fit at each speed.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_angle_deg=100, max_angle_deg=110)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg, [(("a", "b"), "wear")])
        >>> rpm, wear = np.array([1.0, 1.0]), [np.array([120.0, 320.0])]
        >>> net.solve(rpm, wear)[1].tolist(), net.minimums_fit(rpm, wear).tolist()
        ([False, False], [True, False])
        """
        rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(1,))
        t_bound = self._bound_angles(t_bound, rpm.shape)
        w, bound_ok, _, _ = self._weights(rpm, t_bound)
        keep = np.array([k not in ("max", "user") for k in self.kind], bool)
        got, _ = max_difference(
            self.n,
            self.src[keep],
            self.dst[keep],
            np.ascontiguousarray(w[:, keep]),
            self.source,
            self.target,
            n_threads=n_threads,
        )
        return bound_ok & ~np.isnan(np.asarray(got, dtype=np.float64))

    def fits(
        self, bounds_at: BoundsAt, rpm: Array, n_threads: int | None = None
    ) -> npt.NDArray[np.bool_]:
        """Whether each design fits at each of its speeds: one shortest-path call for all.

        Parameters
        ----------
        bounds_at : BoundsAt
            ``bounds_at(designs, rpm)``: the extra bounds' angles [deg] of the
            designs at their speeds (``BoundsAt``).
        rpm : ndarray of float, shape (D, M)
            The speeds of design d, ``rpm[d]`` [rpm].
        n_threads : int, optional
            Threads for the shortest paths (default: ``CYCLOMECH_THREADS`` or all
            cores).

        Returns
        -------
        ndarray of bool, shape (D, M)
            Whether design d fits at the speed ``rpm[d, j]``.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_duration_s=0.05)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg)
        >>> net.fits(lambda d, n: [], np.array([[900.0, 1100.0]])).tolist()   # 6·n·0.05 ≤ 300
        [[True, False]]
        """
        rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(2,))
        designs = np.arange(rpm.shape[0])
        t_bound = bounds_at(designs, rpm)
        return self.solve(rpm.reshape(-1), t_bound, n_threads, labels=False)[1].reshape(rpm.shape)

    def speed_limits(
        self,
        bounds_at: BoundsAt,
        designs: int,
        start: float,
        n_threads: int | None = None,
        rtol: float = 1e-10,
    ) -> Array:
        """The highest speed at which each design fits.

        Feasibility only shrinks as the speed grows, so each design's limit is
        bracketed by speeds 4× apart from ``start`` up to ``SPEED_CAP_RPM``
        (inf if it fits there; 0 if it does not fit at
        :data:`~cyclomech.cyclogram.SPEED_FLOOR_RPM`) and the bracket refined on
        grids of 64 speeds to ``rtol``; every step is one shortest-path call for all
        the designs still searching.

        Parameters
        ----------
        bounds_at : BoundsAt
            ``bounds_at(designs, rpm)``: the extra bounds' angles [deg] of the
            designs at their speeds (``BoundsAt``).
        designs : int
            The number of designs D (indices 0 … D-1 to ``bounds_at``).
        start : float
            The first speed tried above the floor [rpm].
        n_threads : int, optional
            Threads for the shortest paths (default: ``CYCLOMECH_THREADS`` or all
            cores).
        rtol : float, default 1e-10
            The relative width to which each bracket is refined.

        Returns
        -------
        ndarray of float, shape (D,)
            Each design's highest speed that fits [rpm] (inf: it fits at
            ``SPEED_CAP_RPM``; 0: it fits at no speed).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_duration_s=0.05)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg)
        >>> round(float(net.speed_limits(lambda d, n: [], 1, 100.0)[0]), 6)     # 6·n·0.05 = 300
        1000.0
        """
        designs = count("designs", designs, low=0)
        start = positive("start", start, "[rpm]")
        rtol = speed_rtol(rtol)

        def fit(idx: npt.NDArray[np.int64], rpm: Array) -> npt.NDArray[np.bool_]:
            t_bound = bounds_at(idx, rpm)
            flat = self.solve(rpm.reshape(-1), t_bound, n_threads, labels=False)[1]
            return flat.reshape(rpm.shape)

        D = designs
        out = np.full(D, np.nan)
        ok = fit(np.arange(D), np.full((D, 1), SPEED_FLOOR_RPM))[:, 0]
        out[~ok] = 0.0
        lo, hi = np.full(D, SPEED_FLOOR_RPM), np.full(D, start)
        act = np.flatnonzero(ok)
        while act.size:
            f = fit(act, hi[act, None])[:, 0]
            capped = f & (hi[act] >= SPEED_CAP_RPM)
            out[act[capped]] = math.inf
            act = act[f & ~capped]
            lo[act], hi[act] = hi[act], np.minimum(4.0 * hi[act], SPEED_CAP_RPM)
        act = np.flatnonzero(np.isnan(out))
        while act.size:
            done = hi[act] - lo[act] <= rtol * hi[act]
            out[act[done]] = lo[act[done]]
            act = act[~done]
            if not act.size:
                break
            grid = np.linspace(lo[act], hi[act], 66, axis=1)[:, 1:-1]
            fine = fit(act, grid)
            k = np.where(fine.all(axis=1), grid.shape[1], np.argmin(fine, axis=1))
            r = np.arange(act.size)
            lo[act] = np.where(k > 0, grid[r, np.maximum(k - 1, 0)], lo[act])
            hi[act] = np.where(
                k < grid.shape[1], grid[r, np.minimum(k, grid.shape[1] - 1)], hi[act]
            )
        return out

    def solve_proportional(
        self, per_rpm: Array, rpm: Array, n_threads: int | None = None
    ) -> tuple[Array, npt.NDArray[np.bool_], npt.NDArray[np.object_], Array]:
        """:meth:`solve` of every design at every speed, extra bounds proportional to speed.

        Row d·S + j is design d at ``rpm[j]``; bit for bit :meth:`solve` on the same
        rows, in one Rust call (the weights built per row, rayon over rows, the GIL
        released).

        Parameters
        ----------
        per_rpm : ndarray of float, shape (D, K)
            Design d's extra bounds' slopes [deg/rpm], as in
            :meth:`speed_limits_proportional`.
        rpm : ndarray of float, shape (S,)
            The speeds [rpm].
        n_threads : int, optional
            Threads (default: ``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        angle : ndarray of float, shape (D·S,)
            The limiting angles [deg] (NaN where it does not fit).
        fits : ndarray of bool, shape (D·S,)
            The fit flags.
        binding : ndarray of object, shape (D·S,)
            The chains' names (joined by ``"; "``).
        bound_mins : ndarray of float, shape (D·S, K)
            The minimum angle [deg] of each bound's operation.

        Raises
        ------
        InputError
            If ``per_rpm`` is not (D, K), K the number of extra bounds.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_angle_deg=100)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg, [(("a", "b"), "wear")])
        >>> rpm = np.array([100.0, 400.0])
        >>> angle, fits, binding, t = net.solve_proportional(np.array([[0.5]]), rpm)
        >>> angle.tolist(), binding.tolist(), t[:, 0].tolist()     # 360 − max(100, n·0.5)
        ([260.0, 160.0], ['min[a→b]; cycle', 'wear; cycle'], [100.0, 200.0])
        """
        rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True)
        per = self._slopes(per_rpm)
        speeds = np.ascontiguousarray(rpm, dtype=np.float64).reshape(-1)
        if self.general or self.always_false:
            rows = np.tile(speeds, per.shape[0])
            reps = speeds.size
            t_bound = [
                proportional_law(rows, np.repeat(per[:, k], reps)) for k in range(per.shape[1])
            ]
            value, fits, named, mins = self.solve(rows, t_bound, n_threads)
            return value, fits, named, mins[:, self.bound_op].reshape(rows.size, len(self.bound_op))
        value, code, bound_mins, starts = _core.solve_proportional(
            *self._kernel_args(), per, speeds, n_threads=n_threads
        )
        return value, np.isfinite(value), self._names(code, starts), bound_mins

    def _bound_angles(self, t_bound: Any, shape: tuple[int, ...]) -> list[Array]:
        """``t_bound`` as one float64 array of ``shape`` a bound (NaN: no angle will
        do), or :class:`InputError` naming the bad one."""
        if isinstance(t_bound, str | bytes | Mapping) or not isinstance(t_bound, Sequence):
            raise InputError(
                f"t_bound must be a sequence of {len(self.bound_op)} arrays of angles [deg]; "
                f"got {type(t_bound).__name__}"
            )
        if len(t_bound) != len(self.bound_op):
            raise InputError(
                f"t_bound must hold {len(self.bound_op)} arrays (one a bound); got {len(t_bound)}"
            )
        out = [float_array(f"t_bound[{k}]", t, ndims=None) for k, t in enumerate(t_bound)]
        for k, t in enumerate(out):
            if t.shape != shape:
                raise InputError(f"t_bound[{k}] must have the speeds' shape {shape}; got {t.shape}")
        return out

    def _slopes(self, per_rpm: Array) -> Array:
        """``per_rpm`` as a C-ordered (D, K) float64 array of slopes ≥ 0 [deg/rpm]
        (+inf allowed), K the bounds'."""
        per = float_array("per_rpm", per_rpm, ndims=None)
        if per.ndim != 2 or per.shape[1] != len(self.bound_op):
            raise InputError(
                f"per_rpm must be (designs, {len(self.bound_op)}) slopes [deg/rpm]; "
                f"got shape {per.shape}"
            )
        if not (per >= 0.0).all():  # +inf is a bound no speed meets; NaN is none
            i, k = (int(x) for x in np.argwhere(~(per >= 0.0))[0])
            raise InputError(f"per_rpm[{i}, {k}] = {per[i, k]!r} must be ≥ 0 [deg/rpm]")
        return per

    def _kernel_args(self) -> _KernelArgs:
        """The network's arrays for the proportional kernels."""
        return (
            self.n,
            self.src,
            self.dst,
            self.base,
            self.source,
            self.target,
            float(self.lim_shift),
            self.min_edge,
            self.angle,
            self.secs,
            np.asarray(self.bound_op, dtype=np.int64),
        )

    def speed_limits_proportional(
        self,
        per_rpm: Array,
        start: float,
        n_threads: int | None = None,
        rtol: float = 1e-10,
    ) -> Array:
        """:meth:`speed_limits` where every extra bound is proportional to the speed.

        Bound k of design d is ``max(n·per_rpm[d, k], 1e-9)`` degrees at n rpm (none
        over 360°; :class:`~cyclomech.cyclogram.Proportional`). The same search, bit
        for bit, in one Rust call for all the designs (rayon over designs, the GIL
        released); with constraints over several operations (the LP) the Python
        search itself.

        Parameters
        ----------
        per_rpm : ndarray of float, shape (D, K)
            The bounds' slopes [deg/rpm], design d's bound k in ``per_rpm[d, k]``.
        start : float
            The first speed tried above the floor [rpm].
        n_threads : int, optional
            Threads (default: ``CYCLOMECH_THREADS`` or all cores).
        rtol : float, default 1e-10
            The relative width to which each bracket is refined.

        Returns
        -------
        ndarray of float, shape (D,)
            Each design's highest speed that fits [rpm] (inf: it fits at
            ``SPEED_CAP_RPM``; 0: it fits at no speed).

        Raises
        ------
        InputError
            If ``per_rpm`` is not (D, K), K the number of extra bounds.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("b", "c"))
        >>> cg.add_operation("a", "b", min_angle_deg=100)
        >>> cg.add_operation("b", "c", min_angle_deg=60)
        >>> net = cm.cyclogram.SpeedNetwork(cg, [(("a", "b"), "rebound")])
        >>> lim = net.speed_limits_proportional(np.array([[0.5], [1.0]]), 100.0)
        >>> np.round(lim, 6).tolist()                  # n·0.5 = 300, n·1.0 = 300
        [600.0, 300.0]
        """
        start = positive("start", start, "[rpm]")
        rtol = speed_rtol(rtol)
        per = self._slopes(per_rpm)
        if self.general or self.always_false:

            def at(designs: npt.NDArray[np.int64], rpm: Array) -> list[Array]:
                rows = rpm.reshape(-1)
                m = rpm.shape[1]
                return [
                    proportional_law(rows, np.repeat(per[designs, k], m))
                    for k in range(per.shape[1])
                ]

            return self.speed_limits(at, per.shape[0], start, n_threads, rtol)
        return _core.speed_limits_proportional(
            *self._kernel_args(),
            per,
            float(start),
            SPEED_FLOOR_RPM,
            SPEED_CAP_RPM,
            float(rtol),
            n_threads=n_threads,
        )

    def _lp(
        self, rpm: Array, mins: Array, ok: npt.NDArray[np.bool_]
    ) -> tuple[Array, npt.NDArray[np.bool_], list[list[str]]]:
        """The LP at each speed, for constraints over several operations: the
        optimum; the edges of the bounds with a shadow price as the 'path'; and the
        priced constraints over several operations, which are no edge."""
        value = np.full(rpm.size, np.nan)
        on_path = np.zeros((rpm.size, self.src.size), bool)
        extra: list[list[str]] = [[] for _ in range(rpm.size)]
        cg = self.cg
        lim = cg.operation(cg.limiting)  # type: ignore[arg-type]
        edge = {}  # the LP's row names of the bounds that are edges here
        for k, (kind, lab) in enumerate(zip(self.kind, self.label, strict=True)):
            if kind == "min":
                edge[f"min[{lab}]"] = edge[f"duration[{lab}]"] = k
            elif kind:
                edge[lab] = k
        for i in np.flatnonzero(ok):
            lp = LP(self.lay, mins[i], cg.cycle_deg, lim.arc)
            res = lp.solve()
            if res.status != 0:
                continue
            value[i] = -float(res.fun)
            for r in lp.priced(res):
                name = lp.names[r]
                if name in edge:
                    on_path[i, edge[name]] = True
                else:
                    extra[i].append(name)
        return value, on_path, extra

    def _labels(
        self,
        on_path: npt.NDArray[np.bool_],
        which: npt.NDArray[np.int8],
        fits: npt.NDArray[np.bool_],
    ) -> npt.NDArray[np.object_]:
        """``; ``-joined names of the bounds on each row's chain (see
        :meth:`_names`)."""
        code = np.zeros(on_path.shape, np.int16)
        code[on_path] = 1
        mins = code[:, self.min_edge]
        code[:, self.min_edge] = np.where(mins > 0, 1 + which.astype(np.int16), 0)
        code[~fits] = 0
        return self._names(code)

    def _names(
        self, code: npt.NDArray[np.int16], new_run: npt.NDArray[np.bool_] | None = None
    ) -> npt.NDArray[np.object_]:
        """The names of the rows' codes (B, E) (0: off the chain; 1: on it; a
        minimum-angle arc: 1 + which bound sets it): the unique patterns are named
        once. Neighbouring speeds mostly share a pattern, so only the first row of
        each run of equal rows goes into the sort. ``new_run`` (B,): which rows
        differ from the previous one, when the kernel has found them."""
        if code.shape[0] == 0:
            return np.empty(0, dtype=object)
        code = np.ascontiguousarray(code, dtype=np.int16)
        # Each row as one opaque value (its bytes): compared and sorted as a whole,
        # far faster than numpy's unique over rows (axis=0).
        rows = code.view(np.dtype((np.void, 2 * code.shape[1]))).reshape(-1)
        if new_run is None:
            new_run = np.r_[True, rows[1:] != rows[:-1]]
        starts = np.flatnonzero(new_run)
        found = np.unique(rows[starts], return_index=True, return_inverse=True)
        _, first, of_run = cast(tuple[Any, Any, Any], found)  # (numpy's stubs miss this)
        patterns = code[starts[first]]
        inverse = np.repeat(of_run.reshape(-1), np.diff(np.r_[starts, len(code)]))
        names = []
        for row in patterns:
            parts = []
            for k in np.flatnonzero(row):
                kind, lab = self.kind[k], self.label[k]
                if kind == "min":
                    v = int(row[k]) - 1
                    parts.append(
                        f"min[{lab}]"
                        if v == 0
                        else f"duration[{lab}]"
                        if v == 1
                        else self.bound_labels[v - 2]
                    )
                elif kind:
                    parts.append(lab)
            names.append("; ".join(parts))
        out = np.array(names, dtype=object)[inverse.reshape(-1)]
        return out
