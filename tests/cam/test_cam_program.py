"""Cams from motion programs (issue 33, item 2): any program, every cam result.

* A program of the named rest-to-rest laws gives the same cam as the classic
  segments (two different builds of the same laws: the motion program's pieces
  in master angle against the cam's named rises).
* A velocity–velocity program: the cam's s, s′, s″ equal the program's own
  evaluation, and the pressure angle and pitch curvature equal their closed
  forms computed here in numpy from those values.
* A rest-to-rest poly5 segment has the 3-4-5 law's minimum phase angles (a
  different law object, the same function); segments whose shape depends on
  their angle are refused by name.
"""

from __future__ import annotations

import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
from numpy.testing import assert_allclose

M = cm.motion.Segment
S = cm.cam.Segment
FOLLOWER = cm.cam.TranslatingRoller(0.05, 0.012, 0.004)


def _classic_and_program():
    classic = cm.cam.Cam(
        [
            S("rise", 100, 0.02, law="modified_sine"),
            S("dwell", 60),
            S("return", 120, 0.02, law="polynomial_345"),
            S("dwell", 80),
        ],
        FOLLOWER,
    )
    prog = cm.motion.Program(
        [
            M("modified_sine", 100, end=0.02),
            M("dwell", 60),
            M("polynomial_345", 120, end=0.0),
            M("dwell", 80),
        ]
    )
    return classic, cm.cam.Cam(prog, FOLLOWER)


def test_a_program_of_named_laws_is_the_classic_cam():
    classic, programmed = _classic_and_program()
    theta = np.linspace(0.0, 2 * math.pi, 7201)
    a, b = classic.solve(theta), programmed.solve(theta)
    for name in ("s", "ds", "dds", "ddds", "pitch", "profile", "pressure_angle"):
        x, y = getattr(a, name), getattr(b, name)
        assert_allclose(y, x, rtol=1e-12, atol=1e-14 * (1 + np.abs(x).max()), err_msg=name)
    assert [g.kind for g in programmed.segments] == ["rise", "dwell", "return", "dwell"]
    r1 = cm.cam.follower_response(classic, 300, 40.0, 0.1)
    r2 = cm.cam.follower_response(programmed, 300, 40.0, 0.1)
    assert_allclose(r2.error, r1.error, rtol=1e-9, atol=1e-15)


def _velocity_velocity():
    return cm.motion.Program(
        [
            M("cycloidal", 90, end=(0.01, 0.01)),
            M("constant_velocity", 90),
            M("modified_sine", 60, end=(0.032, 0.0)),
            M("poly5", 120, end=0.0),
        ]
    )


def test_a_velocity_velocity_cam_against_its_closed_forms():
    prog = _velocity_velocity()
    cam = cm.cam.Cam(prog, FOLLOWER)
    theta = np.linspace(0.0, 2 * math.pi, 3601)[:-1]
    k = cam.solve(theta)
    m = prog.evaluate(theta)
    for got, want in ((k.s, m.s), (k.ds, m.v), (k.dds, m.a), (k.ddds, m.j)):
        assert_allclose(got, want, rtol=1e-10, atol=1e-13 * (1 + np.abs(want).max()))
    # Translating roller: tan φ = (s′ − e)/(s + √(R_p² − e²)), R_p = R_b + R_r.
    rp, e = 0.05 + 0.012, 0.004
    d = m.s + math.sqrt(rp**2 - e**2)
    assert_allclose(k.pressure_angle, np.arctan((m.v - e) / d), rtol=1e-10, atol=1e-13)
    # The pitch curve: (e, d) turned by −θ, checked against the cam's; its
    # radius of curvature (x′² + y′²)^1.5 / (x′y″ − y′x″) from d′ = s′, d″ = s″.
    c, sn = np.cos(theta), np.sin(theta)
    x, y = e * c + d * sn, -e * sn + d * c
    assert_allclose(k.pitch[:, 0], x, atol=1e-14)
    assert_allclose(k.pitch[:, 1], y, atol=1e-14)
    dx = (m.v - e) * sn + d * c
    dy = (m.v - e) * c - d * sn
    ddx = (m.a - d) * sn + (2 * m.v - e) * c
    ddy = (m.a - d) * c - (2 * m.v - e) * sn
    rho = (dx**2 + dy**2) ** 1.5 / np.abs(dx * ddy - dy * ddx)
    assert_allclose(np.abs(k.pitch_radius_of_curvature), rho, rtol=1e-9)
    # The constant-velocity stretch: s′ = 0.01 throughout.
    mid = (theta > math.radians(95)) & (theta < math.radians(175))
    assert_allclose(k.ds[mid], 0.01, rtol=1e-13)


def test_min_phase_angles_of_program_segments():
    rest = cm.motion.Program([M("poly5", 120, end=0.02), M("dwell", 90), M("poly5", 150, end=0)])
    named = cm.cam.Cam(
        [S("rise", 120, 0.02, law="polynomial_345"), S("dwell", 90), S("return", 150, 0.02)],
        FOLLOWER,
    )
    a = cm.cam.Cam(rest, FOLLOWER).min_phase_angles(300, vibration=(60.0, 0.05, 1e-5))
    b = named.min_phase_angles(300, vibration=(60.0, 0.05, 1e-5))
    assert a.segments == (0, 2)
    assert_allclose(a.angle_deg[:, 0], b.angle_deg[:, 0], rtol=1e-9)
    cam = cm.cam.Cam(_velocity_velocity(), FOLLOWER)
    # Only the rest-to-rest poly5 gets a bound by default; asking for a
    # moving-ends one is refused by name.
    assert cam.min_phase_angles(300).segments == (3,)
    with pytest.raises(cm.InputError, match=r"segments: 0 \(cycloidal\) has moving ends"):
        cam.min_phase_angles(300, segments=[0])


def test_program_cams_refuse_what_a_cam_cannot_be():
    with pytest.raises(cm.InputError, match=r"advance = 0.1 \[m or rad\] must be 0"):
        cm.cam.Cam(
            cm.motion.Program(
                [M("constant_velocity", 360, start=(0, 0.1 / (2 * math.pi)))], advance=0.1
            ),
            FOLLOWER,
        )
    with pytest.raises(cm.InputError, match=r"must start at s = 0"):
        cm.cam.Cam(
            cm.motion.Program([M("poly5", 180, start=0.01, end=0.02), M("poly5", 180, end=0.01)]),
            FOLLOWER,
        )
    with pytest.raises(cm.InputError, match=r"segment 1 \(poly5\) moves but ends where it starts"):
        cm.cam.Cam(
            cm.motion.Program([M("poly5", 180, end=(0.0, 0.01)), M("poly5", 180, end=0.0)]),
            FOLLOWER,
        )


def test_a_program_cam_pickles():
    cam = cm.cam.Cam(_velocity_velocity(), FOLLOWER)
    again = pickle.loads(pickle.dumps(cam))
    assert again.program is not None
    assert float(again.solve(1.0).s) == float(cam.solve(1.0).s)


def test_the_design_contract_spelling():
    """``cm.cam.Cam(program=prog, follower=…)`` as DESIGN.md writes it, and its misuses."""
    prog = _velocity_velocity()
    a = cm.cam.Cam(program=prog, follower=FOLLOWER)
    b = cm.cam.Cam(prog, FOLLOWER)
    assert float(a.solve(2.0).s) == float(b.solve(2.0).s)
    with pytest.raises(cm.InputError, match="not both"):
        cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], FOLLOWER, program=prog)
    with pytest.raises(cm.InputError, match="needs its segments"):
        cm.cam.Cam(program=prog)
    with pytest.raises(cm.InputError, match=r"program must be a cyclomech\.motion\.Program"):
        cm.cam.Cam(program="cycloidal", follower=FOLLOWER)
