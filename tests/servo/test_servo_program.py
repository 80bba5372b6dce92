"""The real motion program drops in: cyclomech.motion.Program gives a servo axis the
same duty and sizing as the tests' closed-form stand-in, and a program with moving
ends (a rotating knife's constant-velocity cut) is sized as any other."""

from __future__ import annotations

import math
from pathlib import Path

import cyclomech as cm
import numpy as np
from numpy.testing import assert_allclose
from servo_reference import CycloidalProgram, motor_torque

CATALOGUE = Path(__file__).resolve().parents[2] / "examples" / "motors.csv"
S = cm.motion.Segment


def test_a_program_and_the_stand_in_give_the_same_duty() -> None:
    program = cm.motion.Program(
        [S("cycloidal", 120, end=1.5), S("dwell", 60), S("cycloidal", 90, end=0.0), S("dwell", 90)],
        continuity="acceleration",
    )
    parts = (
        cm.servo.RotaryLoad(0.05, torque_nm=1.0),
        cm.servo.Gearbox(4.0, 0.9, 2e-5),
        cm.servo.Motor(3.18, 9.55, 3000, 5000, 1.6e-4),
    )
    real = cm.servo.ServoAxis(program, *parts)
    stand_in = cm.servo.ServoAxis(CycloidalProgram(1.5, 120, 60, 90), *parts)
    a, b = real.duty([60.0, 200.0]), stand_in.duty([60.0, 200.0])
    assert_allclose(a.margins, b.margins, rtol=1e-12, atol=1e-12)
    assert_allclose(a.regen_energy_j, b.regen_energy_j, rtol=1e-12)
    s1 = cm.servo.size(real, CATALOGUE, [2.0, 4.0, 8.0], [40.0, 80.0])
    s2 = cm.servo.size(stand_in, CATALOGUE, [2.0, 4.0, 8.0], [40.0, 80.0])
    assert s1.status == "ok" and (s1.choice.motor, s1.choice.ratio) == (
        s2.choice.motor,
        s2.choice.ratio,
    )
    assert_allclose(s1.margins, s2.margins, rtol=1e-12, atol=1e-12)


def test_a_rotating_knife_with_a_matched_cut() -> None:
    """A knife drum that turns once per cycle (advance 2π), at constant speed over
    the 60° cut and catching up in between (velocity–velocity segments): its motor
    never stops, turns at i·v·n while cutting, and its torque is the
    sample-by-sample reference's."""
    v_cut = 0.8  # rad of drum per rad of master while cutting
    rest = 2 * math.pi - v_cut * math.radians(60)
    program = cm.motion.Program(
        [
            S("constant_velocity", 60, start=(0.0, v_cut)),
            S("poly5", 300, end=(v_cut * math.radians(60) + rest, v_cut, 0.0)),
        ],
        advance=2 * math.pi,
    )
    ax = cm.servo.ServoAxis(
        program,
        cm.servo.RotaryLoad(0.08, torque_nm=0.5),
        cm.servo.Gearbox(3.0, 0.95),
        cm.servo.Motor(3.18, 9.55, 3000, 5000, 1.6e-4),
    )
    d = ax.duty(120.0)
    assert ax.motor is not None and d.motor_rpm is not None and d.torque_nm is not None
    t, wm = motor_torque(ax, ax.motor, 3.0, 120.0)
    assert_allclose(d.torque_nm, t, rtol=1e-12, atol=1e-12)
    assert_allclose(d.motor_rpm, wm * 60 / (2 * math.pi), rtol=1e-12)
    assert d.motor_rpm.min() > 0  # the drum never stops
    cut = np.degrees(ax.theta) < 60
    assert_allclose(d.motor_rpm[cut], 3.0 * v_cut * 120.0, rtol=1e-12)
