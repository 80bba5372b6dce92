"""``Cam.solve(out=previous)`` (issue 37): the arrays of a previous result are
overwritten and returned, bit for bit a fresh solve (each follower kind and
closure, any shape of angles), the fresh solve itself checked against the closed
forms of a translating roller written with numpy; a wrong ``out`` is an
``InputError`` that says what would do."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

S = cm.cam.Segment
RB, RR, E, H = 0.05, 0.012, 0.006, 0.025

FOLLOWERS = {
    "translating": lambda: cm.cam.TranslatingRoller(RB, RR, E),
    "flat": lambda: cm.cam.FlatFaced(RB),
    "oscillating": lambda: cm.cam.OscillatingRoller(0.1, 0.1, 0.04, 0.0),
}


def cam(follower: str = "translating", closure: str = "spring") -> cm.cam.Cam:
    h = 0.2 if follower == "oscillating" else H
    segs = [S("rise", 120, h), S("dwell", 60), S("return", 100, h), S("dwell", 80)]
    return cm.cam.Cam(segs, FOLLOWERS[follower](), closure=closure)


FIELDS = [
    "theta",
    "s",
    "ds",
    "dds",
    "ddds",
    "pitch",
    "profile",
    "profile_outer",
    "pressure_angle",
    "pitch_radius_of_curvature",
    "profile_radius_of_curvature",
    "undercut",
]


@settings(max_examples=15, deadline=None)
@given(
    follower=st.sampled_from(list(FOLLOWERS)),
    closure=st.sampled_from(["spring", "groove"]),
    shape=st.sampled_from([(50,), (5, 10), (2, 5, 5)]),
    seed=st.integers(0, 2**31),
)
def test_into_a_previous_result_is_a_fresh_solve(follower, closure, shape, seed):
    if closure == "groove" and follower == "flat":
        closure = "spring"
    c = cam(follower, closure)
    rng = np.random.default_rng(seed)
    first = c.solve(rng.uniform(-10, 10, shape))
    theta = rng.uniform(-10, 10, shape)
    fresh = c.solve(theta)
    again = c.solve(theta, out=first, n_threads=1)
    for f in FIELDS:
        a, b = getattr(again, f), getattr(fresh, f)
        if b is None:
            assert a is None
            continue
        np.testing.assert_array_equal(a, b, err_msg=f)
        assert np.shares_memory(a, getattr(first, f)), f


def test_fresh_solve_matches_the_closed_forms():
    """The translating roller's s, pitch curve and pressure angle by numpy."""
    theta = np.linspace(0.0, 2 * math.pi, 997, endpoint=False)
    k = cam().solve(theta, out=cam().solve(np.zeros(997)))
    t = np.mod(theta, 2 * math.pi)
    b1, b3, a3 = math.radians(120), math.radians(100), math.radians(180)
    x1 = np.clip(t / b1, 0, 1)
    x3 = np.clip((t - a3) / b3, 0, 1)
    s = H * (x1 - np.sin(2 * math.pi * x1) / (2 * math.pi)) - H * (
        x3 - np.sin(2 * math.pi * x3) / (2 * math.pi)
    )
    ds = np.where(t < b1, H / b1 * (1 - np.cos(2 * math.pi * x1)), 0.0) - np.where(
        (t >= a3) & (t < a3 + b3), H / b3 * (1 - np.cos(2 * math.pi * x3)), 0.0
    )
    d = math.sqrt((RB + RR) ** 2 - E**2) + s
    np.testing.assert_allclose(k.s, s, atol=1e-12)
    np.testing.assert_allclose(k.pitch[:, 0], E * np.cos(t) + d * np.sin(t), atol=1e-12)
    np.testing.assert_allclose(k.pressure_angle, np.arctan2(ds - E, d), atol=1e-12)


def test_a_wrong_out_is_an_input_error():
    c = cam()
    first = c.solve(np.zeros(10))
    with pytest.raises(cm.InputError, match=r"out must be a CamKinematics.*for 11 angles"):
        c.solve(np.zeros(11), out=first)
    with pytest.raises(cm.InputError, match="out must be a CamKinematics"):
        c.solve(np.zeros(10), out=np.zeros((10, 14)))
    with pytest.raises(cm.InputError, match="same closure"):
        cam(closure="groove").solve(np.zeros(10), out=first)


@pytest.mark.parametrize("index", [0, 13, 4099, 8191])
def test_a_non_finite_angle_anywhere_is_named(index):
    """The finite check runs per lane group inside the kernel's pass: the angle
    planted at ``index`` (first of a group, inside one, across a chunk) is the
    one the error names, with ``out=`` as without."""
    c = cam()
    theta = np.linspace(0.0, 2 * math.pi, 8195)
    theta[index] = np.nan
    first = c.solve(np.zeros(theta.size))
    for out in (None, first):
        with pytest.raises(cm.InputError, match=rf"theta.*\b{index}\b"):
            c.solve(theta, out=out, n_threads=1)


def test_the_kernel_copies_the_angles_where_asked():
    """``theta_copy=`` of the kernel (what ``out=`` uses for ``out.theta``): the
    angles themselves, for a length that is not a whole number of lane groups;
    a wrong array is an InputError naming it."""
    c = cam()
    theta = np.random.default_rng(3).uniform(-10, 10, 1003)
    copy = np.full(theta.size, np.nan)
    rows = c._kernel.solve(theta, n_threads=1, theta_copy=copy)
    np.testing.assert_array_equal(copy, theta)
    np.testing.assert_array_equal(rows, c._kernel.solve(theta, n_threads=2))
    with pytest.raises(cm.InputError, match="theta_copy"):
        c._kernel.solve(theta, theta_copy=np.zeros(theta.size + 1))
