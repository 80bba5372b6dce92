"""Forces in planar linkages: kinetostatics.

At every crank angle, the reaction at every joint, the normal force of every
guide and the driving torque on the crank, for links with mass, centre of mass
and moment of inertia, lumped point masses (a slider block, a knife), external
forces on points and torques on links (constant or tables over the crank angle:
a cutting force over the cut) and gravity.

The positions and the velocity and acceleration analogs x', x'' come from the
linkage solver (:meth:`cyclomech.Linkage.solve`). At crank speed ω and angular
acceleration ε the accelerations are a = ω² x'' + ε x', so every force is
ω²·(part 0) + ε·(part 1) + (part 2): one linear solve per angle with three
right-hand sides gives the forces at every speed. Each moving link obeys
Newton–Euler (ΣF = m a_c, ΣM_c = J α), each joint the balance of its pin; the
system's pattern is the same at every angle, so its block-triangular order (the
Assur groups, from the last placed to the crank) is found once and each block
solved by LU in Rust, angles in parallel. A dead centre (a singular block) is
flagged, not solved, and so is an angle near one: where the analogs put the crank
within ``NEAR_DEAD_CENTRE`` (0.02 rad) of it (``Kinetostatics.near_dead_centre``,
scale-free; the torque there grows as the inverse square of that angle).
Sliders: the block pinned at the point slides on its guide without friction and
has no mass beyond the point's, so the guide's force is normal to it, through
the point. Friction in the joints and guides (Coulomb and viscous) is solved
per steady speed by :func:`kinetostatics_with_friction` (:class:`Friction`,
:class:`PinFriction`, :class:`GuideFriction`, :class:`FrictionForces`).

Units: SI (N, N·m, kg, m, rad); crank speeds in rpm where named so.

>>> import numpy as np, cyclomech as cm
>>> sc = cm.Linkage({"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
...                 [("A", "B"), ("B", "C")], ["A"], ("A", "B"),
...                 sliders={"C": ("ground", (1, 0))})
>>> k = cm.forces.kinetostatics(sc, np.radians([90.0]),
...                             loads=[cm.forces.PointLoad("C", (-1000.0, 0.0))])
>>> round(float(k.torque(rpm=0.0)[0]), 6)    # −F·r: the force drives the crank here
-100.0

A machine file's linkage gives its masses, loads and friction in its own table
(:func:`dynamics_from_table`, :func:`friction_from_table`).
"""

from __future__ import annotations

from ._file import DYNAMICS_KEYS, FRICTION_KEYS, dynamics_from_table, friction_from_table
from ._friction import (
    Friction,
    FrictionForces,
    GuideFriction,
    PinFriction,
    kinetostatics_with_friction,
)
from ._model import LinkMass, LinkTorque, PointLoad, check_dynamics, kinetostatics
from ._result import NEAR_DEAD_CENTRE, Kinetostatics

__all__ = [
    "DYNAMICS_KEYS",
    "FRICTION_KEYS",
    "NEAR_DEAD_CENTRE",
    "Friction",
    "FrictionForces",
    "GuideFriction",
    "Kinetostatics",
    "LinkMass",
    "LinkTorque",
    "PinFriction",
    "PointLoad",
    "check_dynamics",
    "dynamics_from_table",
    "friction_from_table",
    "kinetostatics",
    "kinetostatics_with_friction",
]
