"""The single case's chunked scan (issue 20): ``duhamel`` on a uniform grid of
≥ 1025 samples runs its recurrence as blocks in vector lanes, stitched by the
unforced transition. Checked against the sequential recurrence (the batch path,
which never scans), against scipy's ``lsim`` (the same first-order hold from the
matrix exponential), and against closed forms, including a lightly damped
million-step run."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
import scipy.signal
from hypothesis import given, settings
from hypothesis import strategies as st

#: Shortest grid the scan takes (8 blocks of 128 steps).
SCAN_MIN = 8 * 128 + 1


def sequential(t, f, omega_n, zeta, mass, q0=0.0, v0=0.0):
    """The sequential recurrence: ``duhamel_batch`` of one case never scans."""
    return cm.impact.duhamel_batch(t, f[None, :], omega_n, zeta, mass, q0, v0, n_threads=1)[0]


def state_err(q, ref_q, ref_v, omega):
    """max |q − ref_q| on the state's scale, max |q_ref| + max |v_ref|/ω."""
    scale = np.abs(ref_q).max() + np.abs(ref_v).max() / omega
    return float(np.abs(q - ref_q).max() / scale)


@settings(max_examples=40, deadline=None)
@given(
    zeta=st.one_of(st.just(0.0), st.just(1.0), st.floats(0.0, 0.3), st.floats(0.3, 3.0)),
    wh=st.floats(1e-4, 2.0),
    omega=st.floats(1.0, 1e4),
    extra=st.integers(0, 2000),
    shape=st.sampled_from(["step", "ramp", "noise", "pulse"]),
    q0=st.floats(-1.0, 1.0),
    v0=st.floats(-1.0, 1.0),
)
def test_the_scan_is_the_sequential_recurrence_up_to_rounding(
    zeta, wh, omega, extra, shape, q0, v0
) -> None:
    n = SCAN_MIN + extra
    t = np.linspace(0.0, (n - 1) * wh / omega, n)
    f = {
        "step": np.ones(n),
        "ramp": t * omega,
        "noise": np.random.default_rng(n).standard_normal(n),
        "pulse": np.clip(1.0 - t / t[n // 7], 0.0, None),
    }[shape]
    q, v = cm.impact.duhamel(
        t, f, omega_n=omega, zeta=zeta, mass=0.3, q0=q0 / omega, v0=v0, velocity=True
    )
    ref_q = sequential(t, f, omega, zeta, 0.3, q0 / omega, v0)
    # The batch returns q only: v from the scan itself sets the scale's v part
    # (a bound, the sequential v agrees with it to the same rounding).
    assert state_err(q, ref_q, v, omega) < 1e-12


def test_a_step_and_a_ramp_against_their_closed_forms() -> None:
    w, z, m = 2 * math.pi * 297.0, 0.05, 7.4e-3
    t = 2e-6 * np.arange(10_001)
    wd, s = w * math.sqrt(1 - z * z), z * w
    decay = np.exp(-s * t)
    # Unit step: q = (1 − e^{−σt}(cos ωd t + σ/ωd sin ωd t))/(mω²).
    step = (1 - decay * (np.cos(wd * t) + s / wd * np.sin(wd * t))) / (m * w * w)
    q = cm.impact.duhamel(t, np.ones_like(t), omega_n=w, zeta=z, mass=m)
    assert np.abs(q - step).max() < 1e-12 * np.abs(step).max()
    # Unit ramp F = t: q = (t − 2ζ/ω + e^{−σt}(2ζ/ω cos ωd t + (2ζ²−1)/ωd sin ωd t))/(mω²).
    ramp = (
        t - 2 * z / w + decay * (2 * z / w * np.cos(wd * t) + (2 * z * z - 1) / wd * np.sin(wd * t))
    ) / (m * w * w)
    q = cm.impact.duhamel(t, t, omega_n=w, zeta=z, mass=m)
    assert np.abs(q - ramp).max() < 1e-12 * np.abs(ramp).max()


def test_lsim_with_a_first_order_hold_agrees() -> None:
    # scipy's lsim (interp=True: the force linear between samples, from the
    # matrix exponential): an independent reference for the same recurrence.
    w, z, m = 2 * math.pi * 297.0, 0.05, 7.4e-3
    t = 2e-6 * np.arange(3001)
    f = 3.5 * np.clip(1 - t / t[325], 0.0, None)
    sys = scipy.signal.StateSpace([[0, 1], [-w * w, -2 * z * w]], [[0], [1 / m]], [[1, 0]], [[0]])
    _, ref, _ = scipy.signal.lsim(sys, f, t, interp=True)
    q = cm.impact.duhamel(t, f, omega_n=w, zeta=z, mass=m)
    assert np.abs(q - ref).max() < 1e-12 * np.abs(ref).max()


def test_a_lightly_damped_million_steps_stay_on_the_closed_form() -> None:
    # Free vibration, ζ = 1e-4, 1e6 steps (about 600 periods): the stitching
    # must not add error growth; the scan is as close to the closed form as
    # the sequential recurrence (closer: each block's chain is 8 times shorter).
    w, z = 2 * math.pi * 297.0, 1e-4
    t = 2e-6 * np.arange(1_000_001)
    s, wd = z * w, w * math.sqrt(1 - z * z)
    exact = np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    f = np.zeros_like(t)
    q = cm.impact.duhamel(t, f, omega_n=w, zeta=z, mass=1.0, q0=1.0)
    q_seq = sequential(t, f, w, z, 1.0, 1.0)
    err, err_seq = np.abs(q - exact).max(), np.abs(q_seq - exact).max()
    assert err < 2 * err_seq + 1e-13
    assert err < 1e-10


@pytest.mark.parametrize("n", [SCAN_MIN - 1, SCAN_MIN, SCAN_MIN + 7, 20_000])
def test_grid_lengths_around_the_scans_threshold(n) -> None:
    w, z, m = 300.0, 0.02, 1.0
    t = np.linspace(0.0, 1.0, n)
    f = np.sin(40 * t)
    q, v = cm.impact.duhamel(t, f, omega_n=w, zeta=z, mass=m, velocity=True)
    ref = sequential(t, f, w, z, m)
    assert state_err(q, ref, v, w) < 1e-12


def test_bad_values_on_a_scanned_grid_are_named_as_before() -> None:
    t = np.linspace(0.0, 1.0, 5000)
    f = np.ones_like(t)
    f[3210] = np.nan
    with pytest.raises(cm.CyclomechError, match=r"force\[3210\]") as e:
        cm.impact.duhamel(t, f, omega_n=300.0, zeta=0.02, mass=1.0)
    assert isinstance(e.value, ValueError)
    t2 = t.copy()
    t2[4000] = t2[3999] - 1e-3
    with pytest.raises(cm.CyclomechError, match=r"t\[4000\]"):
        cm.impact.duhamel(t2, np.ones_like(t), omega_n=300.0, zeta=0.02, mass=1.0)


def test_jumps_and_ragged_grids_still_take_the_sequential_path() -> None:
    # A repeated time (a force jump) or a ragged grid: not scanned, and the same
    # values as the batch's sequential recurrence, bit for bit.
    t = np.linspace(0.0, 1.0, 4000)
    t = np.insert(t, 1000, t[1000])
    f = np.where(np.arange(t.size) > 1000, 1.0, 0.0)
    q = cm.impact.duhamel(t, f, omega_n=300.0, zeta=0.02, mass=1.0)
    np.testing.assert_array_equal(q, sequential(t, f, 300.0, 0.02, 1.0))
    t = np.cumsum(np.random.default_rng(1).uniform(1e-4, 2e-4, 4000))
    f = np.ones_like(t)
    q = cm.impact.duhamel(t, f, omega_n=300.0, zeta=0.02, mass=1.0)
    np.testing.assert_array_equal(q, sequential(t, f, 300.0, 0.02, 1.0))


def test_non_float64_inputs_still_take_the_checked_path() -> None:
    # The wrapper's fast path takes contiguous float64 arrays and floats as they
    # are; lists, ints, strided views and other dtypes are converted as before.
    t = np.linspace(0.0, 1.0, 3001)
    f = np.ones_like(t)
    q = cm.impact.duhamel(t, f, omega_n=300.0, zeta=0.0, mass=1.0)
    np.testing.assert_array_equal(
        q, cm.impact.duhamel(t.tolist(), f.astype(np.float32), omega_n=300, zeta=0, mass=1)
    )
    np.testing.assert_array_equal(
        q, cm.impact.duhamel(np.repeat(t, 2)[::2], f, omega_n=300.0, zeta=0.0, mass=1.0)
    )
    with pytest.raises(cm.CyclomechError, match="zeta must be a real number"):
        cm.impact.duhamel(t, f, omega_n=300.0, zeta="0.1", mass=1.0)
    with pytest.raises(cm.CyclomechError, match="velocity must be True or False"):
        cm.impact.duhamel(t, f, omega_n=300.0, zeta=0.1, mass=1.0, velocity=1)
