"""A servo axis's motor torque and speed against independent references: the power
balance of motor, gearbox and load over a cycle, and the closed forms of a rotary
inertia and a vertical linear axis driven by cycloidal moves."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from numpy.testing import assert_allclose
from servo_reference import CycloidalProgram, motor_torque

RISE, TOP, BACK = 120.0, 60.0, 90.0  # [deg] of master; the rest of the turn dwells


def _axis(
    load: object, gearbox: cm.servo.Gearbox, h: float = 1.5, points: int = 3600
) -> cm.servo.ServoAxis:
    motor = cm.servo.Motor(3.18, 9.55, 3000, 5000, 1.6e-4, name="m")
    program = CycloidalProgram(h, RISE, TOP, BACK)
    return cm.servo.ServoAxis(program, load, gearbox, motor, points=points)


def _energy(d: cm.servo.Duty, rpm: float) -> tuple[float, float]:
    """(∫T_m·ω_m dt, ∫|T_m·ω_m| dt) [J] over the cycle from the duty's curves."""
    assert d.torque_nm is not None and d.motor_rpm is not None
    p = d.torque_nm * d.motor_rpm * (2 * math.pi / 60)  # [W]
    dt = 60.0 / rpm / p.size  # [s] per sample
    return float(p.sum() * dt), float(np.abs(p).sum() * dt)


def test_kinetic_energy_returns_without_losses() -> None:
    """η = 1, no external load: the motor's work over a cycle is 0 (what it puts in
    the inertias it takes back), to the quadrature's accuracy."""
    ax = _axis(cm.servo.RotaryLoad(0.05), cm.servo.Gearbox(4.0, inertia_kg_m2=2e-5))
    d = ax.duty(200.0)
    net, gross = _energy(d, 200.0)
    assert gross > 1.0
    assert abs(net) < 1e-9 * gross


@pytest.mark.parametrize(("points", "rtol"), [(3600, 1e-5), (36000, 1e-7)])
def test_losses_of_an_inertia_by_its_kinetic_energy(points: int, rtol: float) -> None:
    """η < 1, pure inertia: accelerating the load costs E_k/η and decelerating it
    returns E_k·η (E_k = ½·J_L·φ̇_max², φ̇_max = 2h/β·ω for a cycloid); the motor's
    and gearbox's own inertia give back all they take. So the motor's net work per
    cycle is (E_rise + E_return)(1/η − η), and the energy it regenerates is each
    move's deceleration: ½(J_m + J_g)·ω_m,max² + E_k·η per move. The sums over the
    samples switch factor where the power changes sign, between samples: an O(h²)
    quadrature error, 100 times smaller with 10 times the samples."""
    rpm, h, j_load, eta, i = 150.0, 1.5, 0.05, 0.8, 4.0
    gear = cm.servo.Gearbox(i, efficiency=eta, inertia_kg_m2=2e-5)
    ax = _axis(cm.servo.RotaryLoad(j_load), gear, h, points)
    d = ax.duty(rpm)
    w = rpm * 2 * math.pi / 60
    ek = [0.5 * j_load * (2 * h / math.radians(b) * w) ** 2 for b in (RISE, BACK)]
    net, _ = _energy(d, rpm)
    assert_allclose(net, sum(ek) * (1 / eta - eta), rtol=rtol)
    j_drive = 1.6e-4 + 2e-5
    regen = sum(
        0.5 * j_drive * (i * 2 * h / math.radians(b) * w) ** 2 + e * eta
        for b, e in zip((RISE, BACK), ek, strict=True)
    )
    assert_allclose(float(d.regen_energy_j), regen, rtol=rtol)


def test_a_cycloidal_inertia_by_the_hand_formula() -> None:
    """A rotary inertia on a cycloidal rise and return, η = 1: T_m = J·i·φ_L″·ω² with
    J = J_m + J_g + J_L/i², φ_L″ peaking at 2πh/β² and sin² averaging ½ over each
    move: peak |T_m| = J·i·ω²·2πh/β_min², RMS² = Σ_moves (J·i·ω²·2πh/β²)²·½·β/2π;
    peak motor speed i·ω·2h/β_min."""
    rpm, h, j_load, i, jg = 90.0, 1.5, 0.05, 4.0, 2e-5
    ax = _axis(cm.servo.RotaryLoad(j_load), cm.servo.Gearbox(i, inertia_kg_m2=jg), h)
    d = ax.duty(rpm)
    w = rpm * 2 * math.pi / 60
    j = 1.6e-4 + jg + j_load / i**2
    amp = [j * i * w**2 * 2 * math.pi * h / math.radians(b) ** 2 for b in (RISE, BACK)]
    assert_allclose(float(d.peak_torque_nm), max(amp), rtol=1e-6)
    rms = math.sqrt(
        sum(
            a * a * 0.5 * math.radians(b) / (2 * math.pi)
            for a, b in zip(amp, (RISE, BACK), strict=True)
        )
    )
    assert_allclose(float(d.rms_torque_nm), rms, rtol=1e-9)
    peak_rpm = i * 2 * h / math.radians(min(RISE, BACK)) * rpm
    assert_allclose(float(d.peak_speed_rpm), peak_rpm, rtol=1e-6)
    assert_allclose(d.inertia_ratio, (j_load / i**2 + jg) / 1.6e-4)


def test_a_vertical_axis_lifts_motoring_and_lowers_regenerating() -> None:
    """A vertical linear axis (weight F = m·g resisting the rise) slow enough that
    m·|ẍ| < F: the rise is all motoring, the return all regenerating. Over the
    cycle the load's work is 0 and the motor's is F·h·(1/η − η) (η of screw and
    gearbox): the losses. In the dwells the motor holds F·lead/2π/(i·η): the
    motoring side, the documented rule at rest."""
    m, lead, h, rpm, i = 30.0, 0.02, 0.1, 20.0, 3.0
    f = m * 9.81
    load = cm.servo.LinearLoad(m, lead, force_n=f, efficiency=0.9)
    gear = cm.servo.Gearbox(i, efficiency=0.95)
    ax = _axis(load, gear, h)
    d = ax.duty(rpm)
    eta = 0.9 * 0.95
    w = rpm * 2 * math.pi / 60
    assert m * 2 * math.pi * h / math.radians(BACK) ** 2 * w**2 < f  # the premise
    net, _ = _energy(d, rpm)
    assert_allclose(net, f * h * (1 / eta - eta), rtol=1e-6)
    assert d.torque_nm is not None
    dwell = np.degrees(ax.theta) > RISE + TOP + BACK + 1
    assert_allclose(d.torque_nm[dwell], f * lead / (2 * math.pi) / (i * eta), rtol=1e-12)


@pytest.mark.parametrize("rpm", [30.0, 240.0])
def test_the_curves_match_the_sample_by_sample_reference(rpm: float) -> None:
    """The kernel's torque and speed at every sample against numpy from the parts'
    own attributes (tests/servo/servo_reference.py), a linear load with a force
    both resisting and, at speed, overcome by inertia."""
    load = cm.servo.LinearLoad(12.0, 0.01, force_n=40.0, efficiency=0.85)
    ax = _axis(load, cm.servo.Gearbox(2.5, efficiency=0.9, inertia_kg_m2=1e-5), 0.08)
    assert ax.motor is not None
    d = ax.duty(rpm)
    t, wm = motor_torque(ax, ax.motor, 2.5, rpm)
    assert d.torque_nm is not None and d.motor_rpm is not None
    assert_allclose(d.torque_nm, t, rtol=1e-12, atol=1e-12)
    assert_allclose(d.motor_rpm, wm * 60 / (2 * math.pi), rtol=1e-12, atol=1e-9)
    assert_allclose(float(d.peak_torque_nm), np.abs(t).max(), rtol=1e-12)


def test_many_speeds_give_the_statistics_of_each() -> None:
    ax = _axis(cm.servo.RotaryLoad(0.05, torque_nm=2.0), cm.servo.Gearbox(4.0, 0.9))
    many = ax.duty([60.0, 300.0])
    assert many.torque_nm is None and many.margins.shape == (2, 4)
    for k, rpm in enumerate([60.0, 300.0]):
        one = ax.duty(rpm)
        assert_allclose(many.rms_torque_nm[k], one.rms_torque_nm, rtol=1e-12)
        assert_allclose(many.margins[k], one.margins, rtol=1e-12)


def test_a_failing_check_is_reported_not_raised() -> None:
    ax = _axis(cm.servo.RotaryLoad(0.5), cm.servo.Gearbox(2.0))
    d = ax.duty(400.0)
    assert not d.passes
    assert d.status.startswith(f"fails {d.binding} (margin -")
    assert d.binding == cm.servo.CHECKS[int(np.argmin(d.margins))]
