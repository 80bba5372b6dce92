"""``cm.impact.duhamel`` on uniform grids of at least 1025 samples (the chunked
scan: a lane pass from rest, then each block's start state's free motion added;
issue 20) against closed forms and scipy, around the scan's threshold, with and
without the velocity, and on grids that only look uniform.

The reference is independent of the kernel: the exact response to a force
linear in time (particular solution plus the free motion that meets the start
state), evaluated in numpy, and scipy's ``lsim`` (matrix exponential).
"""

from __future__ import annotations

import cyclomech as cm
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from scipy import signal


def linear_force_response(t, F0, s, w, z, m, q0, v0):
    """Exact (q, q̇) of m q̈ + 2ζω m q̇ + mω² q = F0 + s·(t − t[0]) from
    (q0, v0) at t[0], ζ < 1: particular solution a + b·τ plus the damped free
    motion that meets the start state."""
    tau = t - t[0]
    b = s / (m * w * w)
    a = F0 / (m * w * w) - 2 * z * s / (m * w**3)
    x0, y0 = q0 - a, v0 - b
    sig, wd = z * w, w * np.sqrt((1 - z) * (1 + z))
    e, c, sn = np.exp(-sig * tau), np.cos(wd * tau), np.sin(wd * tau)
    q = a + b * tau + e * (x0 * c + (y0 + sig * x0) / wd * sn)
    v = b + e * (y0 * c - (w * w * x0 + sig * y0) / wd * sn)
    return q, v


def scaled_error(q, v, q_ref, v_ref, w):
    """Errors of q and v/ω on the state's scale max |q| + max |q̇|/ω."""
    scale = np.abs(q_ref).max() + np.abs(v_ref).max() / w or 1.0  # all zero: exact
    return np.abs(q - q_ref).max() / scale, np.abs(v - v_ref).max() / (w * scale)


@settings(max_examples=40, deadline=None)
@given(
    log_w=st.floats(0.0, 4.0),
    zeta=st.floats(0.0, 0.9),
    wh=st.floats(1e-3, 0.5),
    n=st.one_of(st.integers(1000, 1050), st.integers(1050, 12000)),
    t0=st.floats(-2.0, 2.0),
    F0=st.floats(-5.0, 5.0),
    s=st.floats(-5.0, 5.0),
    q0=st.floats(-1.0, 1.0),
    v0=st.floats(-1.0, 1.0),
)
def test_scan_matches_the_closed_form_around_the_threshold(log_w, zeta, wh, n, t0, F0, s, q0, v0):
    w, m = 10.0**log_w, 0.3
    h = wh / w
    t = t0 + h * np.arange(n)
    f = F0 + s * w * (t - t[0])
    q0, v0 = q0 / (m * w * w), v0 / (m * w)
    q, v = cm.impact.duhamel(t, f, omega_n=w, zeta=zeta, mass=m, q0=q0, v0=v0, velocity=True)
    q_ref, v_ref = linear_force_response(t, F0, s * w, w, zeta, m, q0, v0)
    eq, ev = scaled_error(q, v, q_ref, v_ref, w)
    # The closed form's own cos(ω_d τ) rounds with ω_d τ ≤ 0.5·12000.
    assert eq < 1e-11 and ev < 1e-11, (eq, ev)
    # Without the velocity, q bit for bit.
    assert_array_equal(cm.impact.duhamel(t, f, omega_n=w, zeta=zeta, mass=m, q0=q0, v0=v0), q)


def test_scan_against_scipy_lsim_on_a_rough_force():
    # A random force on the benchmark's oscillator and grid (10 001 samples, a
    # scan), from a moving start: lsim's exact first-order-hold recurrence.
    w, z, m = 2 * np.pi * 297, 0.05, 7.4e-3
    t = np.linspace(0.0, 0.02, 10_001)
    f = np.random.default_rng(7).normal(size=t.size)
    q0, v0 = 1e-6, 3e-3
    q, v = cm.impact.duhamel(t, f, omega_n=w, zeta=z, mass=m, q0=q0, v0=v0, velocity=True)
    sys = signal.StateSpace([[0, 1], [-w * w, -2 * z * w]], [[0], [1 / m]], np.eye(2), [[0], [0]])
    _, _, x = signal.lsim(sys, f, t, X0=[q0, v0])
    eq, ev = scaled_error(q, v, x[:, 0], x[:, 1], w)
    assert eq < 1e-11 and ev < 1e-11, (eq, ev)


def test_grids_that_drift_within_their_steps():
    # Steps within 2⁻²⁷ of the first (the scan runs) whose offsets drift past
    # the free-motion shift's first-order bound (its blocks run twice), and
    # beyond 2⁻²⁷ (the sequential loop): both on the closed form of the same t.
    w, z, m = 1000.0, 0.02, 0.5
    k = np.arange(4000)
    for jitter in (2.0**-29, 2.0**-45, 2.0**-26):
        steps = 1e-4 * (1 + jitter * np.sign(np.sin(0.7 * k)))
        t = 0.25 + np.concatenate([[0.0], np.cumsum(steps)])
        f = 2.0 + 300.0 * (t - t[0])
        q, v = cm.impact.duhamel(t, f, omega_n=w, zeta=z, mass=m, q0=1e-3, v0=0.2, velocity=True)
        q_ref, v_ref = linear_force_response(t, 2.0, 300.0, w, z, m, 1e-3, 0.2)
        eq, ev = scaled_error(q, v, q_ref, v_ref, w)
        assert eq < 1e-12 and ev < 1e-12, (jitter, eq, ev)


def test_every_sample_is_written():
    # The one-case output is not zeroed before the kernel runs: every sample
    # must be the kernel's, on the scan (with its leftover steps) and off it.
    w, z, m = 300.0, 0.1, 1.0
    for n in (1, 2, 1024, 1025, 1031, 4099):
        t = np.linspace(0.0, 0.1, n)
        f = np.ones(n)
        for _ in range(3):
            q, v = cm.impact.duhamel(t, f, omega_n=w, zeta=z, mass=m, velocity=True)
            q_ref, v_ref = linear_force_response(t, 1.0, 0.0, w, z, m, 0.0, 0.0)
            assert np.isfinite(q).all() and np.isfinite(v).all()
            assert np.abs(q - q_ref).max() <= 1e-12 / (m * w * w), n
            assert np.abs(v - v_ref).max() <= 1e-12 / (m * w), n
