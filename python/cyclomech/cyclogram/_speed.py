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

#: :data:`DIFFERENCE_RTOL` of the Rust difference-constraint solver
#: (``rust/core/src/cyclogram/difference.rs``), which the speed-limit search
#: (:class:`~cyclomech.cyclogram.SpeedNetwork`) uses to decide what fits.
DIFFERENCE_RTOL = 1e-12


def fit_slack(lay: Layout, mins: npt.NDArray[np.float64], cycle: float) -> float:
    """How far [deg] a chain of minimum angles may exceed the cycle and still fit.

    One rule for :func:`check_fits` and the speed-limit search: the search's
    shortest paths (:class:`~cyclomech.cyclogram.SpeedNetwork`, V + 2 nodes) call
    a cycle feasible unless its weights sum below ``-(V + 2)·eps``, with
    ``eps = DIFFERENCE_RTOL·(1 + max|w|)·(V + 2)``; this is that bound with
    ``max|w|`` bounded by the cycle times (1 + the largest height), the largest
    minimum, maximum and single-bound constraint (plus ``1e-12·cycle`` for the
    round-off of the cycle ratio). So a speed the search reports as fitting is
    one at which the minimum angles pass :func:`check_fits`.

    >>> import cyclomech as cm
    >>> from cyclomech.cyclogram._layout import Layout
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", 100)
    >>> lay = Layout(cg.name, cg.events, cg.operations, cg.constraints)
    >>> fit_slack(lay, lay.angle, 360.0) < 1e-8
    True
    """
    n_nodes = len(lay.events) + 2
    his = [abs(op.max_angle_deg) for op in lay.ops if op.max_angle_deg is not None]
    rhs = [
        abs(c.rhs) / min(abs(k) for _, k in c.coeffs if k)
        for c in lay.constraints
        if any(k for _, k in c.coeffs)
    ]
    scale = max(
        cycle * (1.0 + float(np.max(lay.height, initial=0.0))),
        float(np.max(np.abs(mins), initial=0.0)),
        max(his, default=0.0),
        max(rhs, default=0.0),
    )
    return DIFFERENCE_RTOL * (1.0 + scale) * n_nodes**2 + 1e-12 * cycle


def check_fits(
    lay: Layout, mins: npt.NDArray[np.float64], cycle: float, speed: float | None
) -> None:
    """Raise if the minimum angles alone exceed the cycle by more than
    :func:`fit_slack` (the speed-limit search's tolerance), naming the chain."""
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
    crossings = max(round(float(h2[arcs].sum())), 1)
    if (ratio - cycle) * crossings <= fit_slack(lay, mins, cycle):
        return
    ops = [lay.ops[e] for e in chain_after(arcs, len(s2) - 1) if e < len(lay.ops)]
    at = "" if speed is None else f" at {speed:g} rpm"
    parts = " + ".join(f"{op.title} {mins[lay.arc_index[op.arc]]:g}°" for op in ops)
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
