"""A rotor transfer in a machine drawn over the cycle (:meth:`TransferResult.scene`).

Each rotor turns one pocket per cycle, so one workpiece enters the path per
cycle; a workpiece moves along the path by the speed law at the nominal speed
(V_t on the transport rotor, V_p on the process rotor, the quintic blend
between), so the time it takes from the path's start to arc length s, in cycles,
is (n/60)·∫ ds/v. The transfer has no operation in the cyclogram: workpiece 1
is at the path's start at θ = 0. The rotors are drawn by their pitch circles.

>>> import cyclomech as cm
>>> r = cm.machine.analyze(cm.Machine.from_toml("examples/rotor_line.toml"), progress=False)
>>> points, s, cycles = cycles_along(r.mechanisms["line"])
>>> bool(cycles[-1] > 1.0), points.shape
(True, (4001, 2))
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._scene import Array, Body, Scene, circle

if TYPE_CHECKING:
    from ._kind import TransferResult

#: Samples of the path for the time along it.
_SAMPLES = 4001


def cycles_along(result: TransferResult) -> tuple[Array, Array, Array]:
    """(the path's sampled points [m], their arc length [m], the time to reach each
    from the start [cycles] at the nominal speed)."""
    path = result.mech.path
    smp = path.sample(_SAMPLES)
    v, _, _ = path.speed_law(result.speeds)(smp.s)
    inv = 1.0 / np.asarray(v, dtype=np.float64)
    # trapezoids of 1/v over s: seconds, then cycles at n/60 cycles a second
    t = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(smp.s))])
    return np.asarray(smp.points), np.asarray(smp.s), t * result.ctx.nominal_rpm / 60.0


def transfer_scene(result: TransferResult, cycle_deg: Array) -> Scene:
    """The transfer of ``result`` at ``cycle_deg`` [deg]."""
    pts, _, cycles = cycles_along(result)
    path = result.mech.path
    u = np.asarray(cycle_deg, dtype=np.float64) / 360.0
    n, on = u.size, math.ceil(cycles[-1]) + 1
    points: dict[str, Array] = {}
    for j in range(on):
        t = u + j  # workpiece j + 1 entered j cycles before workpiece 1
        inside = (t >= 0.0) & (t <= cycles[-1])
        x = np.interp(t, cycles, pts[:, 0])
        y = np.interp(t, cycles, pts[:, 1])
        points[f"w{j + 1}"] = np.where(inside[:, None], np.column_stack([x, y]), np.nan)
    points["O_t"] = np.tile(path.centre_t, (n, 1))
    points["O_p"] = np.tile(path.centre_p, (n, 1))
    bodies = {
        "rotor t": Body(circle(path.R_t, 96), Scene.fixed((*path.centre_t, 0.0), n), fill=False),
        "rotor p": Body(circle(path.R_p, 96), Scene.fixed((*path.centre_p, 0.0), n), fill=False),
        "path": Body(pts[::20], Scene.fixed((0.0, 0.0, 0.0), n), closed=False, fill=False),
    }
    return Scene(result.mech.name, points, ground=("O_t", "O_p"), bodies=bodies)
