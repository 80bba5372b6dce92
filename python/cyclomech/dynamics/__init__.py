"""Machine dynamics: the main shaft's real speed under its motor, its
torsion and the working members' dynamic errors, the frame's shaking force and
moment, and balancing.

**The main shaft.**

**The reduced machine** (:func:`reduced`, :class:`Reduced`). A cyclic machine on
one main shaft has one degree of freedom, the shaft angle φ. Its mechanisms'
kinetic energy is ½·J(φ)·φ̇², J(φ) the reduced moment of inertia
(Σ m·|v_G/ω|² + J_G·(ω_link/ω)² over the moving parts; a cam follower's
m·s′(φ)²), each mechanism's J read at its phase in the optimised cyclogram as the
main shaft reads its torque (:func:`cyclomech.shaft.main_shaft`). The
kinetostatics' torque at constant speed, ω²·a(φ) + b(φ), holds the rest:
a = ½·J′ exactly (the inertial forces of positional constraints) and b = Q(φ),
the reduced load torque (loads, springs, gravity). The flywheel and the motor's
rotor (i²·J_rotor through a gear of ratio i) add constants.

**The equation of motion** (Lagrange, with the motor torque M on the shaft):

    J(φ)·φ̈ + ½·J′(φ)·φ̇² = M(φ̇) − Q(φ)

Motors (:class:`ConstantTorque`, :class:`LinearMotor`, :class:`InductionMotor`
by Kloss's formula, :class:`TableMotor`) with a gear ratio and efficiency.

**The periodic steady state** (:func:`steady_state`, many designs at once:
:func:`steady_states`): with y = ω² the equation is d(½·J·y)/dφ = M(√y) − Q,
solved over the cycle by a fixed-step RK4 on the samples (step 2·360°/N; error
O(h⁴)) and shot on y(0) by Newton with the sensitivity equation to a tolerance
the user sets. It gives ω(φ), t(φ), the real coefficient of speed fluctuation
δ = (ω_max − ω_min)/ω_mean (ω_mean = 2π/T, the time mean), the motor's peak and
RMS torque (the current proxy). No periodic speed (the motor too weak, a stall,
an unbalanced constant torque) is an error, or a warning and a status in a batch.

**The start-up** (:func:`start_up`): from rest in time by Dormand–Prince 5(4)
until the speed stays near the steady state for a whole turn. **The flywheel
sized by simulation** (:func:`size_flywheel`): the flywheel whose simulated δ
meets a target, beside the energy method's ΔE/(ω²δ) and their difference.

The kernels are Rust (``rust/core/src/dynamics``), the GIL released and designs
in parallel.

>>> import numpy as np
>>> import cyclomech as cm
>>> phi = np.radians(np.arange(0.0, 360.0, 0.1))
>>> d = cm.dynamics.Reduced.from_curves(0.2 + 0.05 * np.cos(2 * phi), -0.1 * np.sin(2 * phi),
...                                     20 + 15 * np.sin(phi), nominal_rpm=100.0)
>>> motor = cm.dynamics.InductionMotor(1440.0, 1500.0, 2.5, rated_power_w=400.0, ratio=15.0)
>>> s = cm.dynamics.steady_state(d, motor, flywheel_kg_m2=5.0)
>>> round(s.mean_rpm, 2), round(s.speed_fluctuation, 4)
(98.03, 0.0297)

**Torsion and dynamic errors**: the main shaft as torsional springs
between the motor's end and the mechanisms' take-off points, each node a
mechanism's J(φ) and Q(φ) on its hub, and each working member on an elastic link
(:class:`ShaftNode`, :class:`WorkingMember`): :func:`torsion` gives the periodic
steady state under a motor or at a constant speed (the twists, the segments'
torques, each member's dynamic error: where it is minus where the rigid machine
puts it), :func:`torsion_sweep` many constant speeds in one parallel call. A
machine file's ``[drive.shaft]`` and ``[drive.link.<mechanism>]`` give them to
``cyclomech run`` (:func:`machine_torsion`, :class:`MachineTorsion`), where a bound
on a member's error lowers the machine's speed limit.

>>> import numpy as np, cyclomech as cm
>>> phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
>>> member = cm.dynamics.WorkingMember(0.01 * np.sin(phi), 0.01 * np.cos(phi),
...                                    -0.01 * np.sin(phi), frequency_hz=50.0)
>>> node = cm.dynamics.ShaftNode("crank", np.zeros(360), np.zeros(360),
...                              np.full(360, 20.0), 0.02, 2e4, 2.0, member)
>>> round(cm.dynamics.torsion([node], rpm=300.0).peak_error["crank"] * 1e3, 4)  # (ω/ω_n)²·10 mm
0.1016

**Shaking force and moment, and balancing**: the force and moment a
linkage, and the whole machine with its mechanisms phased by the cyclogram, puts on the
frame over the cycle (:func:`shaking`, :class:`Shaking`), and counterweights on
the links pivoted to the frame that minimise it (:func:`balance`,
:class:`Balance`, :class:`Counterweight`).

**Shaking.** The shaking force is the inertia force the moving parts put on the
frame, −Σ mᵢ·a_Gᵢ, and the shaking moment −dH/dt about a point (the driving
torque's reaction on the motor included); both are ω²·(part 0) + ε·(part 1) at
crank speed ω and acceleration ε, taken from the kinetostatics' frame reactions
(ground joints and frame guides). Gravity and the working loads are not part of
them: they form the static part, which :meth:`Shaking.frame_force` adds (what
the frame's bearings and guides carry).

**Balancing.** A counterweight on a link pivoted to the frame is the vector
(m r cos α, m r sin α) [kg·m] in the link's frame, a point mass at a radius r:
the shaking force is linear in these vectors, so the least RMS force is one
least-squares solve; the peak force and SAM's RMS force + weight × RMS torque go
through scipy's optimisers over the Rust batch of designs.

Units: SI (N, N·m, kg, m); speeds in rpm where named so; angles of results in
degrees.

>>> import numpy as np, cyclomech as cm
>>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
>>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 10.0)),
...                             point_masses={"A": 2.0})
>>> round(cm.dynamics.shaking(k).stats(600.0)["rms_force_n"], 3)   # m r ω²
789.568
>>> round(cm.dynamics.balance(k, counterweights=[("O", "A")], rpm=600.0).after["peak_force_n"], 9)
0.0

The plots are in ``cyclomech.dynamics.plot`` (in :mod:`cyclomech.plot`).
"""

from __future__ import annotations

from ._balance import OBJECTIVES, Balance, Counterweight, balance
from ._drive import Drive, MachineDynamics, machine_dynamics
from ._elastic import ElasticShaft, LinkSpec, MachineTorsion, error_limits, machine_torsion
from ._frame import BalanceRequest, MachineShaking, machine_balances, machine_shaking
from ._keys import DRIVE_KEY_DOCS
from ._motor import ConstantTorque, InductionMotor, LinearMotor, Motor, TableMotor
from ._reduced import Reduced, reduced
from ._shaft import (
    STEADY_COLUMNS,
    FlywheelSizing,
    StartUp,
    SteadyBatch,
    SteadyState,
    size_flywheel,
    start_up,
    steady_state,
    steady_states,
)
from ._shaking import Shaking, shaking
from ._torsion import ShaftNode, Torsion, TorsionSweep, WorkingMember, torsion, torsion_sweep

__all__ = [
    "DRIVE_KEY_DOCS",
    "OBJECTIVES",
    "STEADY_COLUMNS",
    "Balance",
    "BalanceRequest",
    "ConstantTorque",
    "Counterweight",
    "Drive",
    "ElasticShaft",
    "FlywheelSizing",
    "InductionMotor",
    "LinearMotor",
    "LinkSpec",
    "MachineDynamics",
    "MachineShaking",
    "MachineTorsion",
    "Motor",
    "Reduced",
    "ShaftNode",
    "Shaking",
    "StartUp",
    "SteadyBatch",
    "SteadyState",
    "TableMotor",
    "Torsion",
    "TorsionSweep",
    "WorkingMember",
    "balance",
    "error_limits",
    "machine_balances",
    "machine_dynamics",
    "machine_shaking",
    "machine_torsion",
    "reduced",
    "shaking",
    "size_flywheel",
    "start_up",
    "steady_state",
    "steady_states",
    "torsion",
    "torsion_sweep",
]
