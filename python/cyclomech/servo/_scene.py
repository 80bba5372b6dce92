"""A servo axis in a machine drawn over the cycle (:meth:`ServoResult.scene`).

At the main shaft's angle θ the program's master angle is θ less the drive's
offset (:attr:`ServoResult.master_offset_deg`); the load is where the program's
position puts it there: a linear load's carriage at x = s [m] on its rail, a
rotary load's disc turned by s [rad] (drawn with a radius of 0.1 m: a rotary
load has no length of its own). A program with an advance (a feed) draws the
position within the cycle, from 0 to the advance.

>>> import numpy as np
>>> np.degrees(master_angles(350.0, np.array([0.0, 10.0]))).round(9).tolist()
[10.0, 20.0]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._scene import Array, Body, Scene, block, circle
from ._parts import LinearLoad

if TYPE_CHECKING:
    from ._result import ServoResult

#: The drawn radius of a rotary load [m].
ROTARY_RADIUS = 0.1


def master_angles(offset_deg: float, cycle_deg: Array) -> Array:
    """The program's master angles [rad] in [0, 2π) at ``cycle_deg`` [deg]."""
    return np.radians(np.mod(np.asarray(cycle_deg, dtype=np.float64) - offset_deg, 360.0))


def servo_scene(result: ServoResult, cycle_deg: Array) -> Scene | None:
    """The axis of ``result`` at ``cycle_deg`` [deg]; None without an optimum."""
    if result.ctx.optimum is None:
        return None
    s = np.asarray(
        result.program.evaluate(master_angles(result.master_offset_deg, cycle_deg)).s,
        dtype=np.float64,
    )
    n = s.size
    name = result.mech.name
    if isinstance(result.axis.load, LinearLoad):
        lo, hi = float(s.min()), float(s.max())
        size = 0.08 * max(hi - lo, 1e-3)
        rail = np.array([[lo - 1.5 * size, 0.0], [hi + 1.5 * size, 0.0]])
        bodies = {
            "rail": Body(rail, Scene.fixed((0.0, -0.5 * size, 0.0), n), closed=False, fill=False),
            "carriage": Body(block(2.0 * size, size), np.column_stack([s, np.zeros((n, 2))])),
        }
        return Scene(name, {"load": np.column_stack([s, np.zeros(n)])}, bodies=bodies)
    r = ROTARY_RADIUS
    tip = np.column_stack([r * np.cos(s), r * np.sin(s)])
    disc = Body(circle(r), np.column_stack([np.zeros((n, 2)), s]))
    return Scene(
        name,
        {"O": np.zeros((n, 2)), "tip": tip},
        links=(("O", "tip"),),
        ground=("O",),
        bodies={"disc": disc},
    )
