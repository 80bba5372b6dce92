"""The polydyne cam (issue 33, item 2) against an integration of its follower.

The follower model of :mod:`cyclomech.cam` (undamped): ÿ = ω_n²·(s(ωt) − y).
At the design speed, solve_ivp (DOP853, rtol 1e-11) of that equation driven by
the polydyne cam's s, started on the program, must stay on the program y(ωt);
at another speed it must not. The library's own steady state
(:func:`cyclomech.cam.follower_response`, a different solver: the exact Duhamel
recurrence) must agree at the design speed.
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from scipy.integrate import solve_ivp

M = cm.motion.Segment
MASS, K, RPM = 0.5, 2.0e5, 600.0
WN = math.sqrt(K / MASS)


def _program():
    return cm.motion.Program(
        [
            M("poly7", 120, end=0.02),
            M("dwell", 60),
            M("poly7", 120, end=0.0),
            M("dwell", 60),
        ],
        continuity="jerk",
    )


def _output(cam_motion, rpm, cycles=2):
    """y(t) over ``cycles`` turns from the program's state at t = 0."""
    w = rpm * 2 * math.pi / 60
    y0 = _program().evaluate(0.0)

    def rhs(t, q):
        s = cam_motion.evaluate(w * t).s
        return [q[1], WN**2 * (float(s) - q[0])]

    t_end = cycles * 2 * math.pi / w
    t = np.linspace(0.0, t_end, 2001)
    sol = solve_ivp(
        rhs,
        (0.0, t_end),
        [float(y0.s), float(y0.v) * w],
        method="DOP853",
        t_eval=t,
        rtol=1e-11,
        atol=1e-14,
        max_step=1e-4,
    )
    assert sol.success
    return t, sol.y[0], _program().evaluate(w * t).s


def test_the_follower_follows_the_program_at_the_design_speed():
    cam_motion = cm.cam.polydyne(_program(), follower_mass=MASS, stiffness=K, rpm=RPM)
    assert cam_motion.shift == pytest.approx(MASS * (RPM * math.pi / 30) ** 2 / K, rel=1e-15)
    _, y, want = _output(cam_motion, RPM)
    assert np.abs(y - want).max() < 1e-8 * 0.02
    # The plain cam (s = y) at the same speed leaves the program by far more.
    _, y_plain, _ = _output(_program(), RPM)
    assert np.abs(y_plain - want).max() > 1e3 * np.abs(y - want).max()


def test_off_design_the_output_departs():
    cam_motion = cm.cam.polydyne(_program(), follower_mass=MASS, stiffness=K, rpm=RPM)
    _, y, want = _output(cam_motion, 1.3 * RPM)
    assert np.abs(y - want).max() > 1e-5


def test_the_library_steady_state_agrees_at_the_design_speed():
    cam_motion = cm.cam.polydyne(_program(), follower_mass=MASS, stiffness=K, rpm=RPM)
    cam = cm.cam.Cam(cam_motion, cm.cam.TranslatingRoller(0.06, 0.01))
    theta = np.linspace(0.0, 2 * math.pi, 721)
    r = cm.cam.follower_response(cam, RPM, WN / (2 * math.pi), 0.0, theta=theta)
    y = cam.solve(theta).s + r.error  # the member: the cam's s plus the dynamic error
    assert np.abs(y - _program().evaluate(theta).s).max() < 1e-7 * 0.02
    # Off design, the residual vibration after each segment is no longer nil.
    off = cm.cam.follower_response(cam, 1.3 * RPM, WN / (2 * math.pi), 0.0)
    at = cm.cam.follower_response(cam, RPM, WN / (2 * math.pi), 0.0)
    assert off.residual.max() > 1e3 * max(at.residual.max(), 1e-12)


def test_a_program_with_a_jerk_jump_is_refused_by_name():
    prog = cm.motion.Program([M("cycloidal", 180, end=0.02), M("cycloidal", 180, end=0.0)])
    with pytest.raises(cm.InputError) as e:
        cm.cam.polydyne(prog, follower_mass=MASS, stiffness=K, rpm=RPM)
    assert str(e.value).startswith(
        "the polydyne cam motion at 600.0 rpm: segment 1 (cycloidal) → segment 2 (cycloidal) "
        "at 180°: the velocity jumps"
    )
    with pytest.raises(cm.InputError, match="stiffness"):
        cm.cam.polydyne(_program(), follower_mass=MASS, stiffness=0.0, rpm=RPM)
