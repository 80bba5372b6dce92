"""The highest main-shaft speed at which a cyclogram fits in its cycle
(:meth:`Cyclogram.max_speed_rpm`) and the check that its minimum angles fit;
part of :mod:`cyclomech.cyclogram`."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from .. import _core
from .._errors import CycleError, InfeasibleError, SolverError
from ._layout import Layout, chain_after, closed_over_cycle
from ._lp import LP
from ._types import SpeedLimit


def check_fits(
    lay: Layout, mins: npt.NDArray[np.float64], cycle: float, speed: float | None
) -> None:
    """Raise if the minimum angles alone exceed the cycle, naming the chain."""
    src, dst, h = lay.src, lay.dst, lay.height
    V = len(lay.events)
    # Closed on itself over one cycle: a cycle of this graph longer than
    # cycle_deg per crossing is exactly a chain that does not fit.
    n, s2, d2, h2, pad = closed_over_cycle(src, dst, h, V)
    w2 = np.concatenate([mins, np.zeros(pad)])
    try:
        found = _core.max_cycle_ratio(n, s2, d2, w2, h2)
    except CycleError as e:
        raise lay.named_cycle(e) from None
    if found is None:
        return
    ratio, arcs = found
    if ratio <= cycle * (1 + 1e-12):
        return
    ops = [lay.ops[e] for e in chain_after(arcs, len(s2) - 1) if e < len(lay.ops)]
    at = "" if speed is None else f" at {speed:g} rpm"
    parts = " + ".join(f"{op.title} {mins[lay.arc_index[op.arc]]:g}°" for op in ops)
    crossings = round(float(h2[arcs].sum()))
    room = f"{cycle:g}°" if crossings == 1 else f"{crossings} × {cycle:g}°"
    raise InfeasibleError(
        f"cyclogram {lay.name!r}: the minimum angles{at} do not fit in the cycle: "
        f"{parts} = {ratio * crossings:g}° > {room}",
        [op.arc for op in ops],
    )


def max_speed(lay: Layout, cycle: float) -> SpeedLimit:
    """:meth:`Cyclogram.max_speed_rpm` of the cyclogram ``lay`` lays out, in a
    cycle of ``cycle`` degrees.

    >>> import cyclomech as cm
    >>> from cyclomech.cyclogram._layout import Layout
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", min_duration_s=0.05)
    >>> cg.add_operation("b", "c", min_angle_deg=150)
    >>> lay = Layout(cg.name, cg.events, cg.operations, cg.constraints)
    >>> round(max_speed(lay, 360.0).rpm, 6)          # 150° + 6·n·0.05 s = 360°
    700.0
    """
    src, dst, h = lay.src, lay.dst, lay.height
    V, E = len(lay.events), len(lay.ops)
    angle = np.array([op.min_angle_deg for op in lay.ops])
    secs = np.array([op.min_duration_s for op in lay.ops])
    # Each operation is two parallel arcs, one per lower bound: its angle at
    # rest and its duration (an angle of max(a, 6·n·s) at n rpm).
    n, s2, d2, h2, pad = closed_over_cycle(np.r_[src, src], np.r_[dst, dst], np.r_[h, h], V)
    a2 = np.concatenate([angle, np.zeros(E + pad)])
    t2 = np.concatenate([np.zeros(E), secs, np.zeros(pad)])
    try:
        status, rpm, _ratio, arcs = _core.max_speed(n, s2, d2, a2, t2, h2, cycle)
    except CycleError as e:
        raise lay.named_cycle(e) from None
    cyc = tuple(lay.ops[e % E].arc for e in chain_after(arcs, len(s2) - 1) if e < 2 * E)
    if status == "infeasible":
        check_fits(lay, angle, cycle, 0.0)  # raises with the chain named
        raise InfeasibleError(
            f"cyclogram {lay.name!r}: does not fit in {cycle:g}° at any speed", cyc
        )
    network = float(rpm)
    has_extra = lay.constraints or any(op.max_angle_deg is not None for op in lay.ops)
    if not has_extra:
        return SpeedLimit(network, cyc, cycle, network)
    lp = LP(lay, angle, cycle, None, speed_secs=secs)
    res = lp.solve()
    if res.status == 3:
        return SpeedLimit(math.inf, (), cycle, network)
    if res.status == 2:
        conflict = lp.irreducible_conflict()
        raise InfeasibleError(
            f"cyclogram {lay.name!r}: the bounds and constraints conflict even at standstill: "
            + "; ".join(lp.describe(r) for r in conflict),
            conflict,
        )
    if res.status != 0:
        raise SolverError(f"cyclogram {lay.name!r}: the LP solver stopped: {res.message}")
    best = float(res.x[-1])
    if best >= network * (1 - 1e-9):
        return SpeedLimit(network, cyc, cycle, network)
    # The rows with a non-zero shadow price are what limits the speed: the
    # operations among them form the limiting chain (ordered by event angle),
    # the rest are the maximum angles, constraints and cycle that bind.
    # Operations held at a bound by a priced constraint belong to the chain too.
    p = res.x[:V]
    chain_ops = lp.priced_ops(res)
    chain = sorted((lay.ops[e] for e in chain_ops), key=lambda op: p[lay.index[op.src]])
    others = lp.priced_others(res)
    return SpeedLimit(best, tuple(op.arc for op in chain), cycle, network, others)
