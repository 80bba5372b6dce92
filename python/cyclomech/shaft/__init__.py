"""The main shaft (issue 19, first slice): the mechanisms' shaft torques over one
cycle, each shifted by its phase in the cyclogram and summed, and at each speed the
mean, peak, lowest and RMS torque, the energy fluctuation, the flywheel inertia for
a coefficient of speed fluctuation and the motor power.

A mechanism's torque on the shaft at a constant speed ω is T(θ) = ω²·a(θ) + b(θ)
[N·m]: inertia gives the ω² part, loads, springs and gravity the rest. Curves are
sampled at N points θ_k = 360°·k/N over one turn and linear between them
(periodic); a phase φ reads a curve at θ − φ. The statistics are exact for that
piecewise-linear torque; the flywheel is the energy method's J = ΔE/(ω²δ).

>>> import numpy as np
>>> import cyclomech as cm
>>> theta = np.radians(np.arange(360.0))
>>> t = cm.shaft.ShaftTorque.from_curves(np.zeros((1, 360)), 5 + 2 * np.sin(3 * theta)[None])
>>> s = t.stats(300.0, speed_fluctuation=0.02)
>>> round(float(s.mean_torque_nm), 9), round(float(s.energy_fluctuation_j), 4)
(5.0, 1.333)
"""

from __future__ import annotations

from ._torque import STATS, ShaftStats, ShaftTorque

__all__ = ["STATS", "ShaftStats", "ShaftTorque"]
