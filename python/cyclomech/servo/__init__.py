"""Servo axes (issue 33): electronic cams whose master is the machine's (virtual)
main shaft, the motor torque and speed they need through a gearbox, the checks of a
motor, and the sizing of motor and gear ratio from a catalogue.

A :class:`ServoAxis` takes a motion program (any object with ``evaluate(theta)``
returning ``.s .v .a .j`` per radian of master, as :class:`cyclomech.motion.Program`
does), a load (:class:`RotaryLoad`, or :class:`LinearLoad` through a screw, belt or
rack), a :class:`Gearbox` and a :class:`Motor`. At a machine speed n [rpm] the master
turns at ω = 2π·n/60: :meth:`ServoAxis.duty` gives the motor's torque and speed over
the cycle, the peak and RMS torque (dwells included), the peak speed, the inertia
ratio, the regenerated energy and the margin of each check (:data:`CHECKS`: peak
torque, RMS torque against the rated torque, speed, inertia ratio), each
1 − used/available. :func:`size` checks every motor of a catalogue
(:func:`load_catalogue`) on every gear ratio at every speed in one Rust call and
picks the smallest motor that passes and its best ratio, with the runners-up.

A servo's torque does not load the main shaft: its motor has its own drive.

>>> import numpy as np
>>> import cyclomech as cm
>>> from types import SimpleNamespace
>>> class Swing:  # a stand-in program: the load shaft swings ±0.5 rad
...     def evaluate(self, t):
...         c, s = np.cos(t), np.sin(t)
...         return SimpleNamespace(s=0.5 * s, v=0.5 * c, a=-0.5 * s, j=-0.5 * c)
>>> ax = cm.servo.ServoAxis(Swing(), cm.servo.RotaryLoad(0.05), points=360)
>>> cm.servo.size(ax, "examples/motors.csv", [3.0, 5.0, 10.0], 120.0).motor.name
'AC-080-239'
"""

from __future__ import annotations

from ._axis import CHECKS, Duty, ServoAxis
from ._catalogue import CATALOGUE_COLUMNS, load_catalogue
from ._parts import Gearbox, LinearLoad, Motor, RotaryLoad
from ._sizing import Sizing, SizingRow, size

__all__ = [
    "CATALOGUE_COLUMNS",
    "CHECKS",
    "Duty",
    "Gearbox",
    "LinearLoad",
    "Motor",
    "RotaryLoad",
    "ServoAxis",
    "Sizing",
    "SizingRow",
    "load_catalogue",
    "size",
]
