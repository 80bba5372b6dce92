"""A gear-lever press in a machine drawn over the cycle (:meth:`PressResult.scene`).

The carrier turns counter-clockwise once per cycle: at the main shaft's angle θ it
has turned ψ = θ less the cycle angle of BDC (its ``phase``) past BDC, so the
press's angle from BDC against the motion is α = −ψ; every joint is where
:meth:`GearLeverPress.solve` puts it at α.

>>> import numpy as np
>>> np.degrees(press_alpha(10.0, np.array([10.0, 100.0]))).round(9).tolist()
[0.0, 270.0]
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._scene import Array, Body, Scene, block, circle

if TYPE_CHECKING:
    from ._kind import PressResult


def press_alpha(bdc_deg: float, cycle_deg: Array) -> Array:
    """The press's angles α [rad] (from BDC against the motion) at ``cycle_deg`` [deg]."""
    psi = np.radians(np.asarray(cycle_deg, dtype=np.float64) - bdc_deg)
    return np.mod(-psi, 2.0 * math.pi)


def press_scene(result: PressResult, cycle_deg: Array) -> Scene | None:
    """The press of ``result`` at ``cycle_deg`` [deg]; None when its phase follows an
    event and there is no optimum."""
    phase, o = result.mech.phase, result.ctx.optimum
    if phase.event is not None and o is None:
        return None
    bdc = phase.shift_deg({} if o is None else o.times, 0.0)
    p = result.mech.press
    k = p.solve(press_alpha(bdc, cycle_deg))
    n = k.alpha.size
    ok = k.ok[:, None]
    points = {
        "O": np.zeros((n, 2)),
        "C": np.asarray(k.centre, dtype=np.float64),
        "P": np.asarray(k.pin, dtype=np.float64),
        "B": np.where(ok, k.slider, np.nan),
    }
    span = max(p.R + p.r, float(np.nanmax(np.abs(k.slider[:, 1]))) if k.ok.any() else p.R)
    s = 0.05 * span
    arm = points["P"] - points["C"]
    ys = k.slider[k.ok, 1]
    lo, hi = (float(ys.min()), float(ys.max())) if ys.size else (0.0, 0.0)
    bodies = {
        "guide gear": Body(circle(p.R, 96), Scene.fixed((0.0, 0.0, 0.0), n), fill=False),
        "planet": Body(
            circle(p.r, 48), np.column_stack([points["C"], np.arctan2(arm[:, 1], arm[:, 0])])
        ),
        "slider guide": Body(
            np.array([[0.0, lo - 2.0 * s], [0.0, hi + 2.0 * s]]),
            Scene.fixed((p.offset, 0.0, 0.0), n),
            closed=False,
            fill=False,
        ),
        "slider": Body(block(1.5 * s, 2.6 * s), np.column_stack([points["B"], np.zeros(n)])),
    }
    return Scene(
        result.mech.name,
        points,
        links=(("O", "C"), ("C", "P"), ("P", "B")),
        ground=("O",),
        bodies=bodies,
        traces=("P",),
    )
