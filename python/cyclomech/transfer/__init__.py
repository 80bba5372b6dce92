"""Transfer of workpieces between the rotors of a rotor machine (seed 002).

A workpiece carried on the pitch circle of a transport rotor (radius R_t, angular
speed ω_t) passes to a process rotor (R_p, ω_p). Where the two pitch circles
touch, its acceleration jumps from R_t·ω_t² to R_p·ω_p² in the opposite direction
(:func:`acceleration_jump`): an impact. The seed's remedy is a guide whose
curvature is continuous: circle → quintic transition → straight segment → quintic
transition → circle.

* :func:`quintic_transition` — the seed's quintic in the frame of the point A where
  it leaves the circle (origin at A, x along the tangent, y towards the centre):
  y = 0, y' = 0, y'' = 1/R at A; y = k·x2 + b, y' = k, y'' = 0 at B on the line
  y = k·x + b. a0 = a1 = 0, a2 = 1/(2R); a3, a4, a5 from the three conditions at B,
  solved in closed form.
* :func:`smooth_transition` — the member of that family whose curvature also
  *starts and ends flat* (y''' = 0 at A and B, so the jerk does not jump at either
  junction either): y'' = (1 − 3s² + 2s³)/R, s = x/x2; it fixes k = x2/(2R) and
  b = −3·x2²/(20R), so one length x2 describes it.
* :class:`TransferPath` — the whole guide in the machine frame (the seed's
  rotation and translation, :func:`to_machine`), two smooth transitions joined by
  the straight segment they leave between the rotors; :meth:`TransferPath.sample`,
  :meth:`TransferPath.acceleration` along it for a workpiece speed law, and
  :meth:`TransferPath.max_jerk`.
* :func:`design_transfer` — the transition length that minimises the peak jerk
  for given rotors, gap and speeds, every candidate evaluated in one Rust call
  (candidates in parallel), with the peak acceleration and jerk next to the jump
  without transitions.

Conventions: SI units (m, s, rad); the transport rotor turns counter-clockwise
unless ``ccw=False`` (then the process rotor turns clockwise, as meshing rotors
do, and the path is the mirror image). Signed curvature is positive where the
path turns left: +1/R_t on the transport circle, −1/R_p on the process circle.

A transfer alone from a file: ``cyclomech transfer FILE.toml`` (a ``[transfer]``
table: a machine file's ``kind = "transfer"`` keys, its ``name`` and ``rpm``).

The numeric work — the quintic's values, curvature and arc length, the composed
path's sample, the kinematics along it and the design's candidate scan — is
compiled code, one call each with the GIL released; the path's sample, kinematics
and scan take
``n_threads`` (default: every core, or ``CYCLOMECH_THREADS``) and give the same
result on any thread count.
"""

from __future__ import annotations

from ._design import TransferDesign, design_transfer
from ._jump import acceleration_jump, acceleration_jump_at_speed
from ._kind import TransferMechanism
from ._path import PathAcceleration, PathSample, TransferPath
from ._quintic import QuinticTransition, quintic_transition, smooth_transition, to_machine

__all__ = [
    "PathAcceleration",
    "PathSample",
    "QuinticTransition",
    "TransferDesign",
    "TransferMechanism",
    "TransferPath",
    "acceleration_jump",
    "acceleration_jump_at_speed",
    "design_transfer",
    "quintic_transition",
    "smooth_transition",
    "to_machine",
]
