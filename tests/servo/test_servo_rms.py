"""RMS torque of a trapezoidal move against a hand-worked example."""

from __future__ import annotations

import math

import cyclomech as cm
import pytest
from numpy.testing import assert_allclose
from servo_reference import TrapezoidProgram


@pytest.mark.parametrize(
    ("eta", "torques"),
    [(1.0, (0.4, 0.1, -0.2, 0.1)), (0.9, (0.1 + 1.5 / 4.5, 0.5 / 4.5, -0.19, 0.5 / 4.5))],
)
def test_rms_torque_of_a_trapezoidal_move(eta: float, torques: tuple[float, ...]) -> None:
    """The formula T_rms = √(Σ T_i²·t_i / t_cycle) over the phases of a move, as
    servo sizing notes give it for accelerate–constant–decelerate–dwell (e.g.
    Trinamic's QBL5704 manual §5.2, "RMS torque requirement"; numberfactory.com's
    "Torque Root Mean Square"), worked by hand here.

    The machine runs at 60 rpm: one cycle is 1 s and 1° of master is 1/360 s. The
    load shaft accelerates for 0.2 s (72°) to 10 rad/s (α_L = 50 rad/s²), runs
    0.2 s, decelerates 0.2 s and dwells 0.4 s (144°). Load J_L = 0.02 kg·m² with a
    constant load torque T_f = 0.5 N·m (present at rest too, as a weight's); a
    gearbox i = 5 of efficiency η; motor J_m = 4e-4 kg·m² (no gearbox inertia).

    At the motor, α_m = i·α_L = 250 rad/s².

    η = 1: J = J_m + J_L/i² = 4e-4 + 8e-4 = 1.2e-3 kg·m², load torque T_f/i = 0.1:
    T_acc = 1.2e-3·250 + 0.1 = 0.4; T_run = 0.1; T_dec = −0.3 + 0.1 = −0.2;
    T_dwell = 0.1 N·m. T_rms = √((0.4²·0.2 + 0.1²·0.2 + 0.2²·0.2 + 0.1²·0.4)/1)
    = √0.046 = 0.21448 N·m; peak 0.4 N·m.

    η = 0.9: the load side T_L = J_L·α_L + T_f = 1.5 N·m while accelerating (the
    motor drives: T_L/(i·η) = 1.5/4.5) and 0.5 N·m running and at rest (0.5/4.5);
    decelerating T_L = −1 + 0.5 = −0.5 N·m with the load still moving forward, so
    the load drives: T_L·η/i = −0.09, plus the rotor's −4e-4·250 = −0.1:
    T_dec = −0.19 N·m; T_acc = 0.1 + 1/3 = 0.4333 N·m.
    """
    rpm = 60.0
    w = rpm * 2 * math.pi / 60
    program = TrapezoidProgram(acc=50.0 / w**2, accel_deg=72.0, const_deg=72.0)
    ax = cm.servo.ServoAxis(
        program,
        cm.servo.RotaryLoad(0.02, torque_nm=0.5),
        cm.servo.Gearbox(5.0, efficiency=eta),
        cm.servo.Motor(0.32, 0.96, 3000, 6000, 4e-4),
    )
    d = ax.duty(rpm)
    times = (0.2, 0.2, 0.2, 0.4)
    rms = math.sqrt(sum(t * t * s for t, s in zip(torques, times, strict=True)) / 1.0)
    if eta == 1.0:
        assert_allclose(rms, math.sqrt(0.046), rtol=1e-12)  # the hand value above
    assert_allclose(float(d.rms_torque_nm), rms, rtol=1e-9)
    assert_allclose(float(d.peak_torque_nm), max(abs(t) for t in torques), rtol=1e-9)
    # The peak motor speed: 5 · 10 rad/s = 477.46 rpm.
    assert_allclose(float(d.peak_speed_rpm), 50.0 * 60 / (2 * math.pi), rtol=1e-9)
    # Margins, 1 − used/available: RMS against the rated 0.32 N·m.
    assert_allclose(d.margins[1], 1 - rms / 0.32, rtol=1e-9)
