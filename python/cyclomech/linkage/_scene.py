"""A linkage in a machine drawn over the cycle (:meth:`LinkageResult.scene`).

The crank's absolute angle at the main shaft's angle θ is the drawn angle plus
θ less the cycle angle where the crank is at its drawn angle (its ``phase``): the
crank turns once per cycle, counter-clockwise. Every point is where
:meth:`Linkage.solve` puts it at that angle.

>>> import numpy as np, cyclomech as cm
>>> lk = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"].linkage
>>> round(float(np.degrees(crank_angles(20.0, lk, np.array([50.0]))[0] - lk.drawn_angle)), 9)
30.0
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._scene import Array, Body, Scene, block

if TYPE_CHECKING:
    from ._kind import LinkageResult
    from ._linkage import Linkage


def crank_angles(shift_deg: float, linkage: Linkage, cycle_deg: Array) -> Array:
    """The crank's absolute angles [rad] at the cycle angles ``cycle_deg`` [deg]."""
    return linkage.drawn_angle + np.radians(np.asarray(cycle_deg, dtype=np.float64) - shift_deg)


def linkage_scene(result: LinkageResult, cycle_deg: Array) -> Scene | None:
    """The linkage of ``result`` at the cycle angles ``cycle_deg`` [deg]; None when its
    phase follows an event and there is no optimum."""
    at = result._shaft_phase()
    if at is None:
        return None
    lk = result.mech.linkage
    sol = lk.solve(crank_angles(at[0], lk, cycle_deg), analogs=False)
    xy = np.where(sol.ok[:, None, None], sol.xy, np.nan)
    points = {p: np.ascontiguousarray(xy[:, sol.index(p)]) for p in lk.names}
    moving = tuple(tuple(ln) for ln in lk._links if not set(ln) <= lk._ground)
    return Scene(
        result.mech.name,
        points,
        links=moving,
        ground=tuple(g for g in lk.names if g in lk._ground),
        bodies=_sliders(lk, points),
        traces=(result.mech.output,),
    )


def _size(linkage: Linkage, points: dict[str, Array]) -> float:
    """The blocks' size [m]: 4 % of the mechanism's extent over the cycle."""
    allp = np.concatenate(list(points.values()))
    allp = allp[np.isfinite(allp).all(axis=1)]
    if not allp.size:
        return 1.0
    return 0.04 * float(np.max(allp.max(axis=0) - allp.min(axis=0))) or 1.0


def _sliders(linkage: Linkage, points: dict[str, Array]) -> dict[str, Body]:
    """Each slider's block (on the point, along its guide) and each ground guide's line
    over the point's travel."""
    s = _size(linkage, points)
    out: dict[str, Body] = {}
    for p, guides in linkage._sliders.items():
        at = points[p]
        for k, (kind, arg) in enumerate(guides):
            if kind == "ground":
                u = np.asarray(arg, dtype=np.float64) / math.hypot(*arg)
                angle = np.full(at.shape[0], math.atan2(u[1], u[0]))
                origin = np.asarray(linkage._points[p], dtype=np.float64)
                t = (at - origin) @ u
                t = t[np.isfinite(t)]
                lo, hi = (float(t.min()), float(t.max())) if t.size else (0.0, 0.0)
                line = np.array([[lo - 2.0 * s, 0.0], [hi + 2.0 * s, 0.0]])
                pose = Scene.fixed((origin[0], origin[1], float(angle[0])), at.shape[0])
                out[f"guide {p}.{k + 1}"] = Body(line, pose, closed=False, fill=False)
            else:
                b, c = arg
                d = points[c] - points[b]
                angle = np.arctan2(d[:, 1], d[:, 0])
            pose = np.column_stack([at, angle])
            out[f"block {p}.{k + 1}"] = Body(block(2.6 * s, 1.5 * s), pose)
    return out
