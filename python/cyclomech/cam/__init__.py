"""Disc cams: the cam program and the exact kinematics and geometry of its follower.

A :class:`Cam` is a sequence of :class:`Segment` s (rise, dwell, return) over one
turn of the cam, each with a law of :mod:`cyclomech.motion` (its full rise form),
and a follower: :class:`TranslatingRoller` (a knife edge is roller radius 0),
:class:`FlatFaced` or :class:`OscillatingRoller`. :meth:`Cam.solve` gives, at any
cam angles, the follower displacement and its first three derivatives per radian
of cam, the pitch curve, the profile (both flanks of a groove), the pressure
angle, the signed radii of curvature and the undercut flags — all in closed form
(the laws' exact derivatives and the chain rule; no finite differences), in one
Rust call.

Conventions: SI units, angles in radians inside and ``_deg`` at the edges. The cam
turns counter-clockwise at positive ω; cam angle θ is measured from the start of
the first segment. Results are in the cam frame, fixed to the cam, whose +y axis
points at the follower at θ = 0. A translating follower moves along +y, its offset
``e`` along +x. An oscillating follower's pivot lies at (a, 0) in the fixed frame;
its arm angle ψ is measured from the line pivot → cam centre, the roller centre
at (a − l·cos ψ, l·sin ψ), ψ = ψ0 + s (s [rad] grows on a rise, moving the roller
away from the cam centre). Radii of curvature are + where the curve is convex (as
the base circle), − where concave, ``inf`` where straight.

>>> import cyclomech as cm
>>> cam = cm.cam.Cam(
...     [cm.cam.Segment("rise", 120, 0.02), cm.cam.Segment("dwell", 60),
...      cm.cam.Segment("return", 120, 0.02), cm.cam.Segment("dwell", 60)],
...     cm.cam.TranslatingRoller(base_radius=0.05, roller_radius=0.01))
>>> k = cam.solve([0.0, 1.0])
>>> k.s.shape, k.pitch.shape
((2,), (2, 2))
"""

from __future__ import annotations

from ._design import CAM_KEYS, SEGMENT_KEYS, CamDesign
from ._export import (
    DxfUnavailableError,
    cutter_path,
    profile_table,
    write_profile_csv,
    write_profile_dxf,
)
from ._followers import FlatFaced, Follower, OscillatingRoller, TranslatingRoller
from ._kind import CamMechanism, CamResult
from ._loads import CRITERIA, CamLoads, Contact, FollowerLoads, MinPhaseAngles
from ._program import KINDS, Cam, CamKinematics, Segment
from ._rows import UNITS, read_program, read_segments

# Not in __all__: the cam sizing's door is cyclomech.synthesis (issue 35); it lives
# here, beside the criteria it evaluates, so that a cam table can ask to be sized.
from ._size import CAM_SIZE_CRITERIA as CAM_SIZE_CRITERIA
from ._size import CamLimits as CamLimits
from ._size import CamSize as CamSize
from ._size import CamSizeTradeoff as CamSizeTradeoff
from ._size import cam_size as cam_size
from ._size import cam_size_tradeoff as cam_size_tradeoff
from ._vibration import (
    FollowerResponse,
    follower_response,
    min_vibration_tau,
    polydyne,
    residual_vibration,
)

__all__ = [
    "CAM_KEYS",
    "CRITERIA",
    "KINDS",
    "SEGMENT_KEYS",
    "UNITS",
    "Cam",
    "CamDesign",
    "CamKinematics",
    "CamLoads",
    "CamMechanism",
    "CamResult",
    "Contact",
    "DxfUnavailableError",
    "FlatFaced",
    "Follower",
    "FollowerLoads",
    "FollowerResponse",
    "MinPhaseAngles",
    "OscillatingRoller",
    "Segment",
    "TranslatingRoller",
    "cutter_path",
    "follower_response",
    "min_vibration_tau",
    "polydyne",
    "profile_table",
    "read_program",
    "read_segments",
    "residual_vibration",
    "write_profile_csv",
    "write_profile_dxf",
]
