"""A servo segment's smallest phase angle (the cyclogram's bound), at the limit.

* Closed form: a cycloidal rise of a pure inertia (η = 1, no load torque) needs
  the peak torque (J·i + J_L/i)·H·C_a·ω²/β², C_a = 2π, so β_min =
  √((J·i + J_L/i)·H·2π·ω²/T_peak); its peak speed i·H·C_v·ω/β, C_v = 2, meets
  the motor's maximum at β = 2·i·H·ω/ω_max.
* At the limit, by the axis's own duty on a dense grid (another kernel): with
  the segment at its bound angle the peak torque equals the motor's peak, with a
  load torque and an efficiency (both sides of the power flow) too.
* A static torque beyond the peak gives NaN (no angle will do); a segment whose
  shape changes with its angle is refused by name.
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest

S = cm.motion.Segment
MOTOR = cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4)


def _program(rise_deg: float, stroke: float = 1.0) -> cm.motion.Program:
    return cm.motion.Program(
        [
            S("cycloidal", rise_deg, end=stroke),
            S("dwell", 180 - rise_deg),
            S("cycloidal", 120, end=0.0),
            S("dwell", 60),
        ]
    )


def test_closed_forms_of_the_cycloid():
    jl, i, h, rpm = 0.02, 2.0, 1.0, 60.0
    ax = cm.servo.ServoAxis(_program(90), cm.servo.RotaryLoad(jl), cm.servo.Gearbox(i), MOTOR)
    m = ax.min_phase_angles([rpm, 2 * rpm])
    w = np.array([rpm, 2 * rpm]) * math.pi / 30
    torque = np.sqrt((MOTOR.inertia_kg_m2 * i + jl / i) * h * 2 * math.pi * w**2 / 3.9)
    speed = 2 * i * h * w / (6000 * math.pi / 30)
    np.testing.assert_allclose(m.angle_deg[:, 0, 0], np.degrees(torque), rtol=1e-6)
    np.testing.assert_allclose(m.angle_deg[:, 0, 1], np.degrees(speed), rtol=1e-12)
    assert m.segments == (0, 2)


@pytest.mark.parametrize(
    "load",
    [
        cm.servo.RotaryLoad(0.02, torque_nm=0.4),
        cm.servo.LinearLoad(mass_kg=30.0, lead_m=0.01, force_n=150.0, efficiency=0.85),
    ],
)
def test_at_its_bound_the_peak_torque_is_the_motors(load):
    stroke = 1.0 if isinstance(load, cm.servo.RotaryLoad) else 0.05
    gear = cm.servo.Gearbox(2.0, efficiency=0.9)
    ax = cm.servo.ServoAxis(_program(90, stroke), load, gear, MOTOR)
    beta = float(ax.min_phase_angles(60.0, segments=[0]).angle_deg[0, 0, 0])
    assert 5.0 < beta < 170.0
    at = cm.servo.ServoAxis(_program(beta, stroke), load, gear, MOTOR, points=720_000)
    # The rise alone: the return (120°) is gentler, the dwells hold less.
    d = at.duty(60.0)
    rise = d.theta_deg < beta
    assert np.abs(d.torque_nm[rise]).max() == pytest.approx(3.9, rel=1e-5)
    longer = cm.servo.ServoAxis(_program(beta * 1.01, stroke), load, gear, MOTOR, points=72_000)
    d = longer.duty(60.0)
    assert np.abs(d.torque_nm[d.theta_deg < beta * 1.01]).max() < 3.9


def test_no_angle_and_refusals():
    heavy = cm.servo.ServoAxis(
        _program(90), cm.servo.RotaryLoad(0.02, torque_nm=9.0), cm.servo.Gearbox(2.0), MOTOR
    )
    assert np.isnan(heavy.min_phase_angles(60.0).angle_deg[0, 0, 0])  # 9/2 > 3.9 N·m static
    moving = cm.motion.Program([S("cycloidal", 90, end=(1.0, 0.5)), S("poly5", 270, end=0.0)])
    ax = cm.servo.ServoAxis(moving, cm.servo.RotaryLoad(0.02), cm.servo.Gearbox(2.0), MOTOR)
    assert ax.min_phase_angles(60.0).segments == ()
    with pytest.raises(cm.InputError, match=r"segment 1 \(cycloidal\): its shape changes"):
        ax.min_phase_angles(60.0, segments=[0])


def test_the_design_contract_spelling():
    """DESIGN.md's ``Motor(rated_torque_nm=…, peak_torque_nm=…, max_rpm=…,
    inertia_kg_m2=…)`` and ``ax.cam_table(points=…)``."""
    m = cm.servo.Motor(rated_torque_nm=1.3, peak_torque_nm=3.9, max_rpm=6000, inertia_kg_m2=1e-4)
    assert m.rated_rpm == 6000.0
    with pytest.raises(cm.InputError, match="inertia_kg_m2 is required"):
        cm.servo.Motor(rated_torque_nm=1.3, peak_torque_nm=3.9, max_rpm=6000)
    ax = cm.servo.ServoAxis(_program(90), cm.servo.RotaryLoad(0.02), cm.servo.Gearbox(2.0), m)
    t = ax.cam_table(points=8)
    want = _program(90).evaluate(np.linspace(0.0, 2 * math.pi, 9))
    np.testing.assert_array_equal(t.s, want.s)
    np.testing.assert_array_equal(t.a, want.a)
    assert t.theta[-1] == 2 * math.pi
