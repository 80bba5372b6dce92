"""The highest main-shaft speed at which a cyclogram fits in its cycle
(:meth:`Cyclogram.max_speed_rpm`) and the check that its minimum angles fit;
part of :mod:`cyclomech.cyclogram`."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from .. import _core
from .._errors import CycleError, InfeasibleError, SolverError
from ._lp import _LP, _MIN, _USER, _chain_after, _closed_over_cycle
from ._types import SpeedLimit

if TYPE_CHECKING:
    from ._model import Cyclogram


def check_fits(
    cg: Cyclogram, mins: npt.NDArray[np.float64], cycle: float, speed: float | None
) -> None:
    """Raise if the minimum angles alone exceed the cycle, naming the chain."""
    src, dst, h = cg._arrays()
    V = len(cg._events)
    # Closed on itself over one cycle: a cycle of this graph longer than
    # cycle_deg per crossing is exactly a chain that does not fit.
    n, s2, d2, h2, pad = _closed_over_cycle(src, dst, h, V)
    w2 = np.concatenate([mins, np.zeros(pad)])
    try:
        found = _core.max_cycle_ratio(n, s2, d2, w2, h2)
    except CycleError as e:
        raise cg._named_cycle(e) from None
    if found is None:
        return
    ratio, arcs = found
    if ratio <= cycle * (1 + 1e-12):
        return
    ops = [cg._ops[e] for e in _chain_after(arcs, len(s2) - 1) if e < len(cg._ops)]
    at = "" if speed is None else f" at {speed:g} rpm"
    parts = " + ".join(f"{op.title} {mins[cg._arc_index[op.arc]]:g}°" for op in ops)
    crossings = round(float(h2[arcs].sum()))
    room = f"{cycle:g}°" if crossings == 1 else f"{crossings} × {cycle:g}°"
    raise InfeasibleError(
        f"cyclogram {cg.name!r}: the minimum angles{at} do not fit in the cycle: "
        f"{parts} = {ratio * crossings:g}° > {room}",
        [op.arc for op in ops],
    )


def max_speed(cg: Cyclogram, cycle: float) -> SpeedLimit:
    """:meth:`Cyclogram.max_speed_rpm` of ``cg`` in a cycle of ``cycle`` degrees.

    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", min_duration_s=0.05)
    >>> cg.add_operation("b", "c", min_angle_deg=150)
    >>> round(max_speed(cg, 360.0).rpm, 6)          # 150° + 6·n·0.05 s = 360°
    700.0
    """
    src, dst, h = cg._arrays()
    V, E = len(cg._events), len(cg._ops)
    angle = np.array([op.min_angle_deg for op in cg._ops])
    secs = np.array([op.min_duration_s for op in cg._ops])
    # Each operation is two parallel arcs, one per lower bound: its angle at
    # rest and its duration (an angle of max(a, 6·n·s) at n rpm).
    n, s2, d2, h2, pad = _closed_over_cycle(np.r_[src, src], np.r_[dst, dst], np.r_[h, h], V)
    a2 = np.concatenate([angle, np.zeros(E + pad)])
    t2 = np.concatenate([np.zeros(E), secs, np.zeros(pad)])
    try:
        status, rpm, _ratio, arcs = _core.max_speed(n, s2, d2, a2, t2, h2, cycle)
    except CycleError as e:
        raise cg._named_cycle(e) from None
    cyc = tuple(cg._ops[e % E].arc for e in _chain_after(arcs, len(s2) - 1) if e < 2 * E)
    if status == "infeasible":
        check_fits(cg, angle, cycle, 0.0)  # raises with the chain named
        raise InfeasibleError(
            f"cyclogram {cg.name!r}: does not fit in {cycle:g}° at any speed", cyc
        )
    network = float(rpm)
    has_extra = cg._constraints or any(op.max_angle_deg is not None for op in cg._ops)
    if not has_extra:
        return SpeedLimit(network, cyc, cycle, network)
    lp = _LP(cg, angle, cycle, None, speed_secs=secs)
    res = lp.solve()
    if res.status == 3:
        return SpeedLimit(math.inf, (), cycle, network)
    if res.status == 2:
        conflict = lp.irreducible_conflict()
        raise InfeasibleError(
            f"cyclogram {cg.name!r}: the bounds and constraints conflict even at standstill: "
            + "; ".join(lp.describe(r) for r in conflict),
            conflict,
        )
    if res.status != 0:
        raise SolverError(f"cyclogram {cg.name!r}: the LP solver stopped: {res.message}")
    best = float(res.x[-1])
    if best >= network * (1 - 1e-9):
        return SpeedLimit(network, cyc, cycle, network)
    # The rows with a non-zero shadow price are what limits the speed: the
    # operations among them form the limiting chain (ordered by event angle),
    # the rest are the maximum angles, constraints and cycle that bind.
    priced = lp.priced(res)
    p = res.x[:V]
    chain_ops = {int(lp.op[i]) for i in priced if lp.kind[i] == _MIN}
    # Operations held at a bound by a priced constraint belong to the chain too.
    for i in priced:
        if lp.kind[i] == _USER:
            con = next(c for c in cg._constraints if c.name == lp.names[i])
            chain_ops.update(cg._arc_index[a] for a, _ in con.coeffs)
    chain = sorted((cg._ops[e] for e in chain_ops), key=lambda op: p[cg._events[op.src]])
    others = tuple(lp.names[i] for i in priced if lp.kind[i] != _MIN)
    return SpeedLimit(best, tuple(op.arc for op in chain), cycle, network, others)
