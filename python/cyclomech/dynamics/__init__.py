"""Machine dynamics (issue 34): the main shaft's real speed under its motor.

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
"""

from __future__ import annotations

from ._drive import Drive, MachineDynamics, machine_dynamics
from ._keys import KEY_DOCS as DRIVE_KEY_DOCS
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

__all__ = [
    "DRIVE_KEY_DOCS",
    "STEADY_COLUMNS",
    "ConstantTorque",
    "Drive",
    "FlywheelSizing",
    "InductionMotor",
    "LinearMotor",
    "MachineDynamics",
    "Motor",
    "Reduced",
    "StartUp",
    "SteadyBatch",
    "SteadyState",
    "TableMotor",
    "machine_dynamics",
    "reduced",
    "size_flywheel",
    "start_up",
    "steady_state",
    "steady_states",
]
