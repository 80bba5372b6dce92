"""A cam in a machine drawn over the cycle (:meth:`CamResult.scene`).

The cam turns counter-clockwise once per cycle; at the main shaft's angle θ its
own angle is θ less its phase (the cycle angle where its first bound segment's
operation starts less the segments before it). The profile is drawn in the cam's
frame and turned by that angle; the follower's roller centre (or face point) is
where :meth:`Cam.solve` puts the pitch point, turned into the fixed frame.

>>> import numpy as np
>>> np.degrees(cam_angles(30.0, np.array([30.0, 120.0]))).tolist()
[0.0, 90.0]
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._scene import Array, Body, Scene, circle, rotate
from ._followers import FlatFaced, OscillatingRoller
from ._program import Cam

if TYPE_CHECKING:
    from ._kind import CamResult

#: Cam angles the drawn profile is solved at (0.5° apart).
_PROFILE_POINTS = 720


def cam_angles(phase_deg: float, cycle_deg: Array) -> Array:
    """The cam's angles [rad] at the cycle angles ``cycle_deg`` [deg]."""
    return np.radians(np.asarray(cycle_deg, dtype=np.float64) - phase_deg)


def cam_scene(result: CamResult, cycle_deg: Array) -> Scene | None:
    """The cam of ``result`` at the cycle angles ``cycle_deg`` [deg]; None without
    an optimum."""
    at = result._shaft_phase()
    if at is None:
        return None
    return scene_of(result.mech.name, result.cam, cam_angles(at[0], cycle_deg))


def scene_of(name: str, cam: Cam, angles: Array) -> Scene:
    """``cam`` turned to ``angles`` [rad] with its follower: the scene named ``name``."""
    grid = np.linspace(0.0, 2.0 * math.pi, _PROFILE_POINTS, endpoint=False)
    shape = cam.solve(grid)
    k = cam.solve(angles)
    n = angles.size
    pitch = rotate(np.asarray(k.pitch, dtype=np.float64).reshape(-1, 2), angles)
    f = cam.follower
    r_max = float(np.max(np.hypot(*np.asarray(shape.pitch).reshape(-1, 2).T)))
    bodies = {"cam": Body(np.asarray(shape.profile, dtype=np.float64), _turning(angles))}
    if shape.profile_outer is not None:
        outer = np.asarray(shape.profile_outer, dtype=np.float64)
        bodies["groove"] = Body(outer, _turning(angles), fill=False)
    points = {"O": np.zeros((n, 2)), "follower": pitch}
    links: list[tuple[str, ...]] = []
    ground = ["O"]
    rr = float(getattr(f, "roller_radius", 0.0))
    if isinstance(f, OscillatingRoller):
        points["pivot"] = np.tile([f.pivot_distance, 0.0], (n, 1))
        links.append(("pivot", "follower"))
        ground.append("pivot")
    elif isinstance(f, FlatFaced):
        face = np.array([[-0.35 * r_max, 0.0], [0.35 * r_max, 0.0]])
        bodies["face"] = Body(face, np.column_stack([pitch, np.zeros(n)]), closed=False)
        points["stem"] = pitch + np.array([0.0, 0.25 * r_max])
        links.append(("follower", "stem"))
    else:
        points["stem"] = pitch + np.array([0.0, rr + 0.25 * r_max])
        links.append(("follower", "stem"))
    if rr > 0.0:
        bodies["roller"] = Body(circle(rr), np.column_stack([pitch, np.zeros(n)]))
    return Scene(name, points, links=tuple(links), ground=tuple(ground), bodies=bodies, traces=())


def _turning(angles: Array) -> Array:
    """The cam's pose at each angle: at the origin, turned by it."""
    return np.column_stack([np.zeros((angles.size, 2)), angles])
