"""Servo axes: electronic cams whose master is the machine's (virtual)
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

>>> import cyclomech as cm
>>> S = cm.motion.Segment   # a 100 mm rise and return on a ball screw of 20 mm lead
>>> prog = cm.motion.Program([S("cycloidal", 120, end=0.1), S("dwell", 60),
...                           S("cycloidal", 120, end=0.0), S("dwell", 60)])
>>> ax = cm.servo.ServoAxis(prog, cm.servo.LinearLoad(mass_kg=8.0, lead_m=0.02, force_n=30.0),
...                         cm.servo.Gearbox(1.0, efficiency=0.9))
>>> best = cm.servo.size(ax, "examples/motors.csv", [1.0, 2.0, 3.0, 5.0], [60.0, 100.0])
>>> best.motor.name, best.gearbox.ratio
('AC-040-032', 2.0)
>>> d = ax.duty(100.0, motor=best.motor, gearbox=best.gearbox)
>>> d.status, d.binding
('ok', 'speed')
"""

from __future__ import annotations

from ._axis import CHECKS, Duty, ServoAxis
from ._catalogue import CATALOGUE_COLUMNS, load_catalogue
from ._kind import ServoMechanism
from ._parts import Gearbox, LinearLoad, Motor, RotaryLoad
from ._result import ServoResult
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
    "ServoMechanism",
    "ServoResult",
    "Sizing",
    "SizingRow",
    "load_catalogue",
    "size",
]
