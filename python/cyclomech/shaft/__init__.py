"""The main shaft: the mechanisms' shaft torques over one
cycle, each shifted by its phase in the cyclogram and summed, and at each speed the
mean, peak, lowest and RMS torque, the energy fluctuation, the flywheel inertia for
a coefficient of speed fluctuation and the motor power.

A mechanism's torque on the shaft at a constant speed ω is T(θ) = ω²·a(θ) + b(θ)
[N·m]: inertia gives the ω² part, loads, springs and gravity the rest. Curves are
sampled at N points θ_k = 360°·k/N over one turn and linear between them
(periodic); a phase φ reads a curve at θ − φ. The statistics are exact for that
piecewise-linear torque; the flywheel is the energy method's J = ΔE/(ω²δ).

A machine's main shaft (:func:`main_shaft`, :class:`MainShaft`) sums its
mechanisms' torques at their phases in the optimised cyclogram; with
``[machine] flatten_torque`` they are first moved within the cyclogram's slack to
the lowest peak torque (:func:`flatten_phases`, :class:`Flattening`), over the
cyclogram's own LP feasible set (:meth:`cyclomech.Cyclogram.feasible_set`).

>>> import numpy as np
>>> import cyclomech as cm
>>> theta = np.radians(np.arange(360.0))
>>> t = cm.shaft.ShaftTorque.from_curves(np.zeros((1, 360)), 5 + 2 * np.sin(3 * theta)[None])
>>> s = t.stats(300.0, speed_fluctuation=0.02)
>>> round(float(s.mean_torque_nm), 9), round(float(s.energy_fluctuation_j), 4)
(5.0, 1.333)
"""

from __future__ import annotations

from ._assembly import MainShaft, main_shaft
from ._flatten import FLATTEN_STEP_DEG, Flattening, flatten_phases
from ._torque import STATS, ShaftStats, ShaftTorque

__all__ = [
    "FLATTEN_STEP_DEG",
    "STATS",
    "Flattening",
    "MainShaft",
    "ShaftStats",
    "ShaftTorque",
    "flatten_phases",
    "main_shaft",
]
