"""Results against speed and the functions over many machines at once: `_many`
part of :mod:`cyclomech.machine` (its door). :class:`SpeedSweep` is a machine's key
figures against speed; :func:`speed_sweeps` and :func:`speed_limits` solve machines
that share a cyclogram's network in one call per step."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

import numpy as np
import numpy.typing as npt

from .._arrays import SPEED_CAP_RPM, flag, instances, speeds_rpm, threads_arg
from .._errors import InfeasibleError
from .._kind import Array, BoundLaw, Mechanism, Proportional, proportional_law
from .._units import DEG_PER_S_PER_RPM
from ..cyclogram import (
    SPEED_FLOOR_RPM,
    BoundsAt,
    SpeedLimit,
)
from ._kinds import KINDS

if TYPE_CHECKING:
    from ._model import Machine

__all__ = ["SpeedSweep", "speed_limits", "speed_sweeps"]


def _machines(value: Sequence[Machine]) -> list[Machine]:
    """``machines`` as a list of Machine, or a TypeError naming the bad one."""
    from ._model import Machine

    return instances("machines", value, Machine)


# --------------------------------------------------------------------- results
@dataclass(frozen=True)
class SpeedSweep:
    """The machine's key figures at each speed ``rpm`` (arrays of that shape).

    With ``linear=True`` (:meth:`Machine.speed_sweep`), the bounds are the seed's
    linearised forms. Built by :meth:`Machine.speed_sweep` and
    :func:`speed_sweeps`; each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    rpm : ndarray of float, shape (S,)
        The speeds [rpm].
    fits : ndarray of bool, shape (S,)
        The cyclogram fits in the cycle with every mechanism's bound.
    limiting_deg : ndarray of float, shape (S,)
        The limiting operation's optimal angle [deg] (NaN where it does not fit).
    limiting_s : ndarray of float, shape (S,)
        The time it gets [s].
    productivity_per_min : ndarray of float, shape (S,)
        Machine cycles per minute where the machine works, else 0 [1/min]: the
        cyclogram fits and the speed is within every mechanism's own speed limit
        (``fits`` is the cyclogram's alone).
    binding : ndarray of object, shape (S,)
        The bounds and constraints on the chain that sets the optimum
        (joined by ``"; "``).
    min_phase_deg : dict of str to ndarray
        Each bound's smallest angle [deg], by the bound's name (a stop's is its
        mechanism's name).
    columns : dict of str to ndarray, optional
        What the mechanism kinds add
        (the kinds' ``sweep_columns``; ``max_rebound_m``, the
        largest first rebound of the stops [m] with each stop's arc at its angle in
        the optimum, NaN without stops); default an empty dict.

    Examples
    --------
    >>> import cyclomech as cm
    >>> s = cm.Machine.example().speed_sweep([300.0, 900.0])
    >>> s.productivity_per_min.tolist()
    [300.0, 0.0]
    >>> {k: v.round(2).tolist() for k, v in s.min_phase_deg.items()}
    {'lifter': [30.03, 90.09]}
    """

    rpm: Array
    fits: npt.NDArray[np.bool_]
    limiting_deg: Array
    limiting_s: Array
    productivity_per_min: Array
    binding: npt.NDArray[np.object_]
    min_phase_deg: dict[str, Array]
    columns: dict[str, Array] = field(default_factory=dict)

    @property
    def max_rebound_m(self) -> Array:
        """The stops' column ``max_rebound_m`` [m] (NaN without stops).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.Machine.example().speed_sweep([300.0, 900.0]).max_rebound_m
        >>> (r * 1e6).round(6).tolist()   # [µm]: the bound a_max = 100 µm binds at 300 rpm
        [100.0, nan]
        """
        return self.columns["max_rebound_m"]


def _own_limits(machine: Machine, cache: dict[int, float] | None = None) -> dict[str, float]:
    """Each mechanism's own speed limit [rpm] (a transfer's jerk, say; inf without),
    by name; with ``cache``, worked out once per mechanism object (a sweep's variants
    share theirs, and one can take a millisecond). Above the lowest the machine does
    not work even where its cyclogram fits: its productivity there is 0.

    Examples
    --------
    >>> import cyclomech as cm
    >>> _own_limits(cm.Machine.example())   # a stop has no speed limit of its own
    {'lifter': inf}
    """
    cache = {} if cache is None else cache
    for x in machine.mechanisms.values():
        if id(x) not in cache:
            cache[id(x)] = float(x.speed_limit_rpm())
    return {k: cache[id(x)] for k, x in machine.mechanisms.items()}


# --------------------------------------------------------------------- many machines
def _bounded(mechanisms: Mapping[str, Mechanism]) -> list[Mechanism]:
    """The mechanisms that bound cyclogram operations, in order."""
    return [m for m in mechanisms.values() if m.bounds()]


def _networks(machines: Sequence[Machine]) -> dict[int, list[int]]:
    """Indices of the machines that share each cyclogram network (the variants of
    one file made by :meth:`Machine.with_values`), in order."""
    groups: dict[int, list[int]] = {}
    for i, m in enumerate(machines):
        groups.setdefault(id(m.speed_network), []).append(i)
    return groups


def _laws(machines: Sequence[Machine], linear: bool, n_threads: int | None) -> list[list[BoundLaw]]:
    """Each machine's bound laws, (D, K): the machines share a network, so their
    bounded mechanisms match one to one; each kind works out the laws of all the
    designs' mechanisms in one batch (one search for all the stops)."""
    if not machines:
        return []
    out: list[list[BoundLaw]] = [[] for _ in machines]
    for j, first in enumerate(machines[0].bounded_mechanisms):
        same = [m.bounded_mechanisms[j] for m in machines]
        for d, laws in enumerate(type(first).bound_laws(same, linear=linear, n_threads=n_threads)):
            out[d].extend(laws)
    return out


def _group_laws(
    machines: Sequence[Machine], linear: bool, n_threads: int | None
) -> list[list[BoundLaw]]:
    """The bound laws of machines that share a network: one machine's are kept on
    it (worked out once per machine); many are worked out in one batch."""
    if len(machines) == 1:
        return [machines[0].bound_laws(linear=linear, n_threads=n_threads)]
    return _laws(machines, linear, n_threads)


def _bounds_at(laws: Sequence[Sequence[BoundLaw]]) -> BoundsAt:
    """``bounds_at(designs, rpm)`` over the laws (D, K) of
    :meth:`SpeedNetwork.speed_limits`: bound k of design ``designs[i]`` at the
    speeds ``rpm[i]``; the speed-proportional laws of all the designs in one
    vectorised step."""
    K = len(laws[0]) if laws else 0
    prop = [all(isinstance(row[k], Proportional) for row in laws) for k in range(K)]
    slopes = [
        np.array([cast(Proportional, row[k]).per_rpm if prop[k] else 0.0 for row in laws])
        for k in range(K)
    ]

    def at(designs: npt.NDArray[np.int64], rpm: Array) -> list[Array]:
        m = rpm.shape[1]
        rows = rpm.reshape(-1)
        out = []
        for k in range(K):
            if prop[k]:
                out.append(proportional_law(rows, np.repeat(slopes[k][designs], m)))
            else:
                # Designs that share a law (a mechanism the variants did not change)
                # are one call over all their speeds.
                vals = np.empty(rows.size)
                groups: dict[int, list[int]] = {}
                for i, d in enumerate(designs):
                    groups.setdefault(id(laws[d][k]), []).append(i)
                for idx in groups.values():
                    law = laws[designs[idx[0]]][k]
                    got = np.asarray(law(rpm[idx].reshape(-1)), dtype=np.float64)
                    for j, i in enumerate(idx):
                        vals[i * m : (i + 1) * m] = got[j * m : (j + 1) * m]
                out.append(vals)
        return out

    return at


def speed_sweeps(
    machines: Sequence[Machine],
    rpm: npt.ArrayLike,
    *,
    linear: bool = False,
    n_threads: int | None = None,
) -> list[SpeedSweep]:
    """:meth:`Machine.speed_sweep` of many machines at the same speeds.

    Variants of one file (:meth:`Machine.with_values`) share their cyclogram: their
    bounds are worked out together and every design at every speed goes into one
    shortest-path call; each kind's sweep columns are one call for all the designs.

    Parameters
    ----------
    machines : sequence of Machine
        The machines.
    rpm : array_like of float
        The speeds [rpm].
    linear : bool, default False
        The bounds in the seed's linearised forms.
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of SpeedSweep
        One per machine, in order.

    Raises
    ------
    InputError
        If a speed is not in (0, 1e6].

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> a, b = cm.machine.speed_sweeps([m, m.with_values({"lifter.a_max_m": 2e-4})], [300.0])
    >>> round(float(a.limiting_deg[0]), 3), round(float(b.limiting_deg[0]), 3)
    (264.971, 275.0)
    """
    machines = _machines(machines)
    n = speeds_rpm("rpm", rpm)
    linear = flag("linear", linear)
    threads = threads_arg(n_threads)
    out: list[SpeedSweep | None] = [None] * len(machines)
    S = n.size
    columns = sorted({c for cls in KINDS.values() for c in cls.sweep_columns})
    cache: dict[int, float] = {}  # the mechanisms' own limits (_own_limits)
    for idx in _networks(machines).values():
        ms = [machines[i] for i in idx]
        net, D = ms[0].speed_network, len(ms)
        laws = _group_laws(ms, linear, threads)
        grid = np.tile(n, (D, 1))
        t_bound = _bounds_at(laws)(np.arange(D), grid)
        rows = grid.reshape(-1)
        value, fits, binding, mins = net.solve(rows, t_bound, threads)
        extra = {c: np.full(rows.shape, np.nan) for c in columns}
        k = 0
        for j, first in enumerate(ms[0].bounded_mechanisms):
            nb = len(first.bounds())
            angles = [mins[:, net.bound_op[k + i]] for i in range(nb)]
            same = [m.bounded_mechanisms[j] for m in ms]
            got = type(first).sweep_values(same, grid, angles, fits, n_threads=threads)
            for c, v in got.items():
                extra[c] = np.fmax(extra.get(c, np.full(rows.shape, np.nan)), v)
            k += nb
        names = [b.name for b in ms[0].bounds()]
        lowest = [min(_own_limits(m, cache).values(), default=math.inf) for m in ms]
        for j, i in enumerate(idx):
            r = slice(j * S, (j + 1) * S)
            out[i] = SpeedSweep(
                rpm=n,
                fits=fits[r],
                limiting_deg=value[r],
                limiting_s=value[r] / (DEG_PER_S_PER_RPM * n),
                productivity_per_min=np.where(fits[r] & (n <= lowest[j]), n, 0.0),
                binding=binding[r],
                min_phase_deg={name: t[r] for name, t in zip(names, t_bound, strict=True)},
                columns={c: v[r] for c, v in extra.items()},
            )
    return out  # type: ignore[return-value]


def speed_limits(machines: Sequence[Machine], *, n_threads: int | None = None) -> list[SpeedLimit]:
    """:meth:`Machine.speed_limit` of many machines.

    The cyclogram limits of the variants of one file are searched together (one
    shortest-path call per step for all of them); a mechanism shared by variants is
    evaluated once.

    Parameters
    ----------
    machines : sequence of Machine
        The machines.
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of SpeedLimit
        One per machine, in order: the limit [rpm], what sets it and why.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> both = cm.machine.speed_limits([m, m.with_values({"lifter.a_max_m": 2e-4})])
    >>> [round(x.rpm, 2) for x in both]
    [421.37, 453.81]
    """
    machines = _machines(machines)
    threads = threads_arg(n_threads)
    out: list[SpeedLimit | None] = [None] * len(machines)
    cache: dict[int, float] = {}  # the mechanisms' own limits (_own_limits)
    for idx in _networks(machines).values():
        ms = [machines[i] for i in idx]
        net = ms[0].speed_network
        laws = _group_laws(ms, False, threads)
        at = _bounds_at(laws)
        cg = net.speed_limits(at, len(ms), ms[0].search_start_rpm, threads, 1e-10)
        ok = np.flatnonzero((cg > 0.0) & np.isfinite(cg))
        binding = np.full(len(ms), "", dtype=object)
        fills = np.ones(len(ms), bool)
        if ok.size:
            binding[ok] = net.solve(cg[ok], at(ok, cg[ok, None]), threads)[2]
            # What stops the fit just above the limit: the minimums filling the
            # cycle, or (they still fit) a minimum rising into a maximum/constraint.
            above = cg[ok] * (1.0 + _ABOVE)
            fills[ok] = ~net.minimums_fit(above, at(ok, above[:, None]), threads)
        for j, (i, m) in enumerate(zip(idx, ms, strict=True)):
            mech = {k: v for k, v in _own_limits(m, cache).items() if math.isfinite(v)}
            why = {k: m.mechanisms[k].limit_reason() for k in mech}
            by, rpm = "cyclogram", float(cg[j])
            for k, v in mech.items():
                if v < rpm:
                    by, rpm = k, v
            chain = tuple(b for b in str(binding[j]).split("; ") if b)
            if by != "cyclogram":
                reason = why[by]
            elif fills[j]:
                reason = _cyclogram_reason(m, rpm, chain)
            else:
                reason, chain = _conflict_reason(m, rpm, chain)
            out[i] = SpeedLimit(
                rpm,
                binding=chain,
                reason=reason,
                by=by,
                cyclogram_rpm=float(cg[j]),
                mechanisms_rpm=mech,
                mechanisms_reason=why,
            )
    return out  # type: ignore[return-value]


#: How far above a cyclogram speed limit (relative) :func:`speed_limits` looks for
#: what stops the fit: far above the search's 1e-10 and its tolerance, so a bound
#: that rises into a maximum is over it by far more than the LP's tolerance.
_ABOVE = 1e-6


def _conflict_reason(m: Machine, rpm: float, chain: tuple[str, ...]) -> tuple[str, tuple[str, ...]]:
    """Why the cyclogram limits machine ``m`` at ``rpm`` when its minimum angles
    still fit just above it, and the bounds that set it: those the LP names as
    conflicting there (a speed-dependent minimum rising into a maximum angle or a
    constraint). ``chain`` (the bounds at the limit) if the LP names none."""
    for step in (_ABOVE, 1e-4, 1e-2):
        try:
            m.cyclogram_at(rpm * (1.0 + step)).optimize()
        except InfeasibleError as e:
            names = tuple(str(c) for c in e.conflict)
            if names:
                pair = " against ".join(names) if len(names) == 2 else ", ".join(names)
                return (
                    f"{pair}: a speed-dependent minimum rises to meet a fixed maximum "
                    "or constraint (above this speed no angle satisfies them all; the "
                    "cyclogram does not fill the cycle)",
                    names,
                )
    return "the cyclogram's bounds stop fitting just above this speed", chain


def _cyclogram_reason(m: Machine, rpm: float, chain: tuple[str, ...]) -> str:
    """Why the cyclogram limits machine ``m`` at ``rpm``, in words."""
    if math.isinf(rpm):
        return f"nothing limits the speed up to {SPEED_CAP_RPM:g} rpm"
    if rpm > 0:
        bounded = f"; bounded by {', '.join(chain)}" if chain else ""
        return "the cyclogram fills the cycle" + bounded
    # Fits at no speed: the operations' durations and the bounds vanish as the
    # speed falls, so what is left is the minimum angles and the constraints.
    try:
        m.cyclogram.max_speed_rpm()
    except InfeasibleError as e:
        text = str(e).replace(" at 0 rpm", "")
        return (
            "the minimum angles alone do not fit in the cycle at any speed (they do not "
            f"depend on the speed): {text}"
        )
    try:
        m.cyclogram_at(SPEED_FLOOR_RPM).optimize()
    except InfeasibleError as e:
        return f"the cyclogram's bounds and constraints conflict at any speed: {e}"
    return f"the cyclogram does not fit even at {SPEED_FLOOR_RPM:g} rpm"
