"""Stand-ins and references for the servo tests and the benchmark, independent of
the kernels under test.

* :class:`CycloidalProgram` and :class:`TrapezoidProgram`: motion programs in closed
  form (numpy), with the ``evaluate(theta) -> .s .v .a .j`` of
  ``cyclomech.motion.Program``, so the servo tests do not wait for it.
* :func:`brute_margins`: every candidate's motor torque sample by sample from the
  parts' own attributes (the screw's lead, the mass, the gearbox), in plain numpy,
  and its margins at every speed; :func:`brute_choice` applies the documented rules
  of ``cyclomech.servo.size`` by a plain Python loop.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]


class CycloidalProgram:
    """Cycloidal rise of ``h`` over ``rise_deg``, dwell ``top_deg``, cycloidal return
    over ``return_deg``, dwell for the rest of the turn (angles of the master)."""

    def __init__(self, h: float, rise_deg: float, top_deg: float, return_deg: float) -> None:
        self.h = h
        self.b1, self.d1, self.b2 = (math.radians(x) for x in (rise_deg, top_deg, return_deg))

    def evaluate(self, theta: Array) -> SimpleNamespace:
        t = np.asarray(theta, dtype=float)
        s, v, a, j = (np.zeros_like(t) for _ in range(4))
        h = self.h
        rise = t < self.b1
        x = t[rise] / self.b1
        s[rise] = h * (x - np.sin(2 * np.pi * x) / (2 * np.pi))
        v[rise] = h / self.b1 * (1 - np.cos(2 * np.pi * x))
        a[rise] = 2 * np.pi * h / self.b1**2 * np.sin(2 * np.pi * x)
        j[rise] = 4 * np.pi**2 * h / self.b1**3 * np.cos(2 * np.pi * x)
        top = (t >= self.b1) & (t < self.b1 + self.d1)
        s[top] = h
        back = (t >= self.b1 + self.d1) & (t < self.b1 + self.d1 + self.b2)
        x = (t[back] - self.b1 - self.d1) / self.b2
        s[back] = h * (1 - x + np.sin(2 * np.pi * x) / (2 * np.pi))
        v[back] = -h / self.b2 * (1 - np.cos(2 * np.pi * x))
        a[back] = -2 * np.pi * h / self.b2**2 * np.sin(2 * np.pi * x)
        j[back] = -4 * np.pi**2 * h / self.b2**3 * np.cos(2 * np.pi * x)
        return SimpleNamespace(s=s, v=v, a=a, j=j)


class TrapezoidProgram:
    """Accelerate at ``acc`` [per rad²] over [0°, a°), run at constant speed over
    [a°, a° + c°), decelerate at −``acc`` over the next a°, dwell for the rest: the
    trapezoidal velocity profile. Each phase is closed on the left; angles are
    rounded to 1e-9° first so that a phase boundary on the sample grid (72° with
    3600 samples) falls in the phase it starts."""

    def __init__(self, acc: float, accel_deg: float, const_deg: float) -> None:
        self.acc, self.ta, self.tc = acc, accel_deg, const_deg

    def evaluate(self, theta: Array) -> SimpleNamespace:
        deg = np.round(np.degrees(np.asarray(theta, dtype=float)), 9)
        ta, tc = self.ta, self.tc
        a = np.where(deg < ta, self.acc, 0.0)
        a = np.where((deg >= ta + tc) & (deg < 2 * ta + tc), -self.acc, a)
        rad = np.radians(deg)
        tar, tcr = math.radians(ta), math.radians(tc)
        vmax = self.acc * tar
        v = np.select(
            [deg < ta, deg < ta + tc, deg < 2 * ta + tc],
            [self.acc * rad, np.full_like(rad, vmax), vmax - self.acc * (rad - tar - tcr)],
            0.0,
        )
        s = np.cumsum(v) * (rad[1] - rad[0]) if rad.size > 1 else np.zeros_like(rad)
        return SimpleNamespace(s=s, v=v, a=a, j=np.zeros_like(a))


def _shaft(load: Any) -> tuple[float, float, float, float]:
    """(k, J_L, T_ext, η_screw) from the load's own attributes, by the hand formulas."""
    if hasattr(load, "lead_m"):
        r = load.lead_m / (2 * math.pi)
        return 1 / r, load.mass_kg * r**2, load.force_n * r, load.efficiency
    return 1.0, load.inertia_kg_m2, load.torque_nm, 1.0


def motor_torque(axis: Any, motor: Any, ratio: float, rpm: float) -> tuple[Array, Array]:
    """(T_m [N·m], ω_m [rad/s]) at the axis's samples for one motor, ratio and speed,
    the power's direction decided sample by sample."""
    k, j_load, t_ext, eta_s = _shaft(axis.load)
    eta = eta_s * axis.gearbox.efficiency
    w = rpm * 2 * math.pi / 60
    vel, acc = axis.v * k * w, axis.a * k * w * w  # φ̇_L, φ̈_L
    t_load = j_load * acc + t_ext
    drives = t_load * vel >= 0  # the motor drives or holds the load
    t_out = np.where(drives, t_load / (ratio * eta), t_load * eta / ratio)
    j_motor = motor.inertia_kg_m2 + axis.gearbox.inertia_kg_m2
    return j_motor * ratio * acc + t_out, ratio * vel


def brute_margins(axis: Any, motors: Any, ratios: Any, rpm: Any) -> Array:
    """(M, R, 4) smallest margin over the speeds of each check, candidate by candidate."""
    _, j_load, _, _ = _shaft(axis.load)
    out = np.empty((len(motors), len(ratios), 4))
    for m, motor in enumerate(motors):
        for r, i in enumerate(ratios):
            worst = np.full(3, np.inf)
            for n in np.atleast_1d(rpm):
                t, wm = motor_torque(axis, motor, i, float(n))
                used = [
                    np.abs(t).max() / motor.peak_torque_nm,
                    np.sqrt(np.mean(t**2)) / motor.rated_torque_nm,
                    np.abs(wm).max() * 60 / (2 * math.pi) / motor.max_rpm,
                ]
                worst = np.minimum(worst, 1 - np.array(used))
            inertia = (j_load / i**2 + axis.gearbox.inertia_kg_m2) / motor.inertia_kg_m2
            out[m, r, :3] = worst
            out[m, r, 3] = 1 - inertia / axis.inertia_ratio_limit
    return out


def brute_choice(motors: Any, ratios: Any, margins: Array) -> list[tuple[str, float]]:
    """(motor name, ratio) of every passing pair in the documented order: motors by
    rated torque, then rotor inertia, then name; one motor's ratios by the largest
    smallest margin, then the lower ratio."""
    by_motor = sorted(
        range(len(motors)),
        key=lambda m: (motors[m].rated_torque_nm, motors[m].inertia_kg_m2, motors[m].name),
    )
    out = []
    for m in by_motor:
        passing = [r for r in range(len(ratios)) if margins[m, r].min() >= 0]
        passing.sort(key=lambda r: (-margins[m, r].min(), ratios[r]))
        out += [(motors[m].name, float(ratios[r])) for r in passing]
    return out
