"""A cam stop in a machine drawn over the cycle (:meth:`CamStopResult.scene`).

The lever turns about its axis A; the cam roller sits at a from A, the working
point W at the lever's end (a + b). Over the operation that brings it to the
stop (its ``arc``, timed by the optimum) W travels s = stroke·Z(u) along its arc,
u the fraction of the operation gone, until it meets the stop at
s = stroke − preload, which then holds it. The stop's model covers that approach
only: outside the operation the lever is not drawn (a lever driven by a cam of
the machine is drawn with that cam), the stop always is. To scale: W's travel is
small beside the lever.

>>> import numpy as np, cyclomech as cm
>>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
>>> s = stop_travel(r.mechanisms["lifter"], np.array([r.optimum.times["7"], 200.0]))
>>> round(float(s[0]) * 1e3, 4), bool(np.isnan(s[1]))      # held at the stop [mm]; outside
(9.15, True)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._scene import Array, Body, Scene, block

if TYPE_CHECKING:
    from ._kind import CamStopResult


def stop_travel(result: CamStopResult, cycle_deg: Array) -> Array:
    """The working point's travel s [m] at ``cycle_deg`` [deg] (NaN outside the
    operation), None-free: the optimum must exist."""
    o = result.ctx.optimum
    assert o is not None
    st = result.mech.stop
    arc = result.mech.arc
    start, span = float(o.times[arc[0]]), float(o.angles[arc])
    u = np.mod(np.asarray(cycle_deg, dtype=np.float64) - start, 360.0) / span
    inside = u <= 1.0
    s = st.stroke * np.asarray(st.law.z(np.clip(u, 0.0, 1.0)), dtype=np.float64)
    s = np.minimum(s, st.stroke - st.preload)  # the stop holds it
    return np.where(inside, s, np.nan)


def stop_scene(result: CamStopResult, cycle_deg: Array) -> Scene | None:
    """The lever and stop of ``result`` at ``cycle_deg`` [deg]; None without an optimum."""
    if result.ctx.optimum is None:
        return None
    st = result.mech.stop
    length = st.a + st.b
    s = stop_travel(result, cycle_deg)
    beta = s / length  # the lever's turn [rad]: W travels s along its arc
    n = beta.size
    turn = np.column_stack([np.cos(beta), np.sin(beta)])
    points = {"A": np.zeros((n, 2)), "roller": st.a * turn, "W": length * turn}
    at = (st.stroke - st.preload) / length  # the lever's turn at the stop
    size = 0.05 * length
    w = np.array([np.cos(at), np.sin(at)]) * length
    normal = np.array([-np.sin(at), np.cos(at)])
    centre = w + normal * 0.5 * size
    stop = Body(block(size, size), Scene.fixed((centre[0], centre[1], at), n))
    return Scene(
        result.mech.name,
        points,
        links=(("A", "roller", "W"),),
        ground=("A",),
        bodies={"stop": stop},
    )
