"""The main shaft (issue 19, first slice) against independent references: closed
forms of a sinusoidal ripple, numpy's periodic interpolation and dense quadrature of
the piecewise-linear torque, the flywheel checked by integrating the shaft's own
equation of motion with scipy, and the cam's torque against its loads."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

RAD = 2 * math.pi / 60


def _grid(n: int) -> np.ndarray:
    return np.arange(n) * (2 * math.pi / n)


def test_a_sinusoidal_ripple_in_closed_form() -> None:
    """T = ω²·A cos θ + T0 + B sin 3θ: mean T0, RMS √(T0² + (ω²A)²/2 + B²/2), and
    ΔE the swing of ∫(T − T0) = ω²A sin θ − (B/3) cos 3θ, found by dense sampling."""
    n, a, t0, b = 36_000, 0.01, 4.0, 3.0
    th = _grid(n)
    t = cm.shaft.ShaftTorque.from_curves((a * np.cos(th))[None], (t0 + b * np.sin(3 * th))[None])
    rpm = np.array([100.0, 300.0])
    s = t.stats(rpm, 0.02)
    w2 = (rpm * RAD) ** 2
    np.testing.assert_allclose(s.mean_torque_nm, t0, rtol=1e-12)
    np.testing.assert_allclose(
        s.rms_torque_nm, np.sqrt(t0**2 + (w2 * a) ** 2 / 2 + b**2 / 2), rtol=1e-7
    )
    fine = np.linspace(0, 2 * math.pi, 2_000_001)
    for i, w in enumerate(w2):
        e = w * a * np.sin(fine) - b / 3 * np.cos(3 * fine)
        assert s.energy_fluctuation_j[i] == pytest.approx(e.max() - e.min(), rel=1e-7, abs=1e-7)
        tt = w * a * np.cos(fine) + t0 + b * np.sin(3 * fine)
        assert s.peak_torque_nm[i] == pytest.approx(tt.max(), abs=1e-6)
        assert s.lowest_torque_nm[i] == pytest.approx(tt.min(), abs=1e-6)
    np.testing.assert_allclose(s.flywheel_kg_m2, s.energy_fluctuation_j / (w2 * 0.02), rtol=1e-14)
    np.testing.assert_allclose(s.power_w, t0 * rpm * RAD, rtol=1e-12)


@given(
    st.integers(1, 4),
    st.integers(5, 60),
    st.lists(st.floats(-720, 720), min_size=4, max_size=4),
    st.integers(0, 2**31),
)
@settings(max_examples=40, deadline=None)
def test_the_shifted_sum_is_numpys_periodic_interpolation(m, n, phases, seed) -> None:
    rng = np.random.default_rng(seed)
    curves = rng.normal(size=(m, n))
    phase = np.array(phases[:m])
    got = cm.shaft.ShaftTorque.from_curves(np.zeros((m, n)), curves, phase).static
    th = np.arange(n) * (360.0 / n)
    want = sum(
        np.interp((th - p) % 360.0, np.r_[th, 360.0], np.r_[c, c[0]])
        for c, p in zip(curves, phase, strict=True)
    )
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-12)


@given(st.integers(0, 2**31), st.integers(3, 40), st.floats(10.0, 2000.0))
@settings(max_examples=40, deadline=None)
def test_statistics_against_dense_quadrature_of_the_interpolant(seed, n, rpm) -> None:
    """Mean, RMS and ΔE of the piecewise-linear torque by 200 points a step."""
    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=n) * 1e-3, rng.normal(size=n)
    s = cm.shaft.ShaftTorque.from_curves(a[None], b[None]).stats(rpm, 0.01)
    t = (rpm * RAD) ** 2 * a + b
    fine = np.linspace(0, n, n * 200 + 1)
    tt = np.interp(fine, np.arange(n + 1), np.r_[t, t[0]])
    h = 2 * math.pi / n / 200
    mean = np.trapezoid(tt, dx=h) / (2 * math.pi)
    assert float(s.mean_torque_nm) == pytest.approx(mean, rel=1e-9, abs=1e-12)
    rms = math.sqrt(np.trapezoid(tt**2, dx=h) / (2 * math.pi))
    assert float(s.rms_torque_nm) == pytest.approx(rms, rel=1e-4)
    e = np.concatenate([[0.0], np.cumsum(0.5 * (tt[1:] + tt[:-1] - 2 * mean) * h)])
    de = e.max() - e.min()
    assert float(s.energy_fluctuation_j) >= de * (1 - 1e-9)
    assert float(s.energy_fluctuation_j) == pytest.approx(de, rel=1e-4, abs=1e-9)


def test_the_flywheel_holds_the_speed_fluctuation() -> None:
    """The energy method against the shaft's own motion: a flywheel J driven by a
    constant motor torque T̄ against the mechanisms' torque T(θ) (J ω̇ = T̄ − T,
    θ̇ = ω), integrated over several cycles by scipy: (ω_max − ω_min)/ω_mean ≈ δ
    (to second order in δ: within 2 % at δ = 0.01)."""
    n, rpm, delta = 3600, 300.0, 0.01
    th = _grid(n)
    torque = cm.shaft.ShaftTorque.from_curves(
        (2e-3 * np.sin(2 * th))[None], (10 + 6 * np.cos(th) + 3 * np.sin(4 * th))[None]
    )
    s = torque.stats(rpm, delta)
    jf, tm = float(s.flywheel_kg_m2), float(s.mean_torque_nm)
    w0 = rpm * RAD

    def t_of(theta: float, w: float) -> float:
        k = (theta % (2 * math.pi)) / (2 * math.pi) * n
        i = int(k) % n
        f = k - int(k)
        a = torque.per_omega2[i] * (1 - f) + torque.per_omega2[(i + 1) % n] * f
        b = torque.static[i] * (1 - f) + torque.static[(i + 1) % n] * f
        return w * w * a + b

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [y[1], (tm - t_of(y[0], y[1])) / jf]

    # Start where E = 0 (θ = 0) at the speed that makes the cycle periodic: search
    # by a few cycles' settling with the motor torque held at T̄.
    sol = solve_ivp(
        rhs,
        (0, 6 * 2 * math.pi / w0),
        [0.0, w0],
        rtol=1e-10,
        atol=1e-12,
        max_step=2 * math.pi / w0 / 2000,
    )
    w = sol.y[1][sol.t > 3 * 2 * math.pi / w0]
    fluct = (w.max() - w.min()) / w.mean()
    assert fluct == pytest.approx(delta, rel=0.02)


def test_the_cams_torque_is_its_loads_torque_and_does_no_work() -> None:
    S = cm.cam.Segment
    cam = cm.cam.Cam(
        [
            S("rise", 120, 0.02),
            S("dwell", 60),
            S("return", 120, 0.02, "modified_sine"),
            S("dwell", 60),
        ],
        cm.cam.TranslatingRoller(0.05, 0.01, offset=0.004),
    )
    loads = cm.cam.FollowerLoads(1.5, 3000.0, 40.0)
    t = cam.shaft_torque(loads, samples=7200)
    theta = np.radians(t.theta_deg)
    for rpm in (100.0, 450.0):
        ref = cam.loads(theta, rpm, loads).shaft_torque
        np.testing.assert_allclose(t.at(rpm), ref, rtol=1e-12, atol=1e-12)
    # Inertia and a spring are conservative: no work over a turn, no mean torque.
    s = t.stats([100.0, 450.0], 0.02)
    assert np.all(np.abs(s.mean_torque_nm) < 1e-9 * s.rms_torque_nm)
    # A load resisting the rise only: mean torque = F·h/(2π) (its work per turn).
    with_load = cm.cam.FollowerLoads(1.5, 3000.0, 40.0, (25.0, 0.0, 0.0, 0.0))
    s = cam.shaft_torque(with_load, samples=7200).stats(300.0, 0.02)
    assert float(s.mean_torque_nm) == pytest.approx(25.0 * 0.02 / (2 * math.pi), rel=1e-6)


@pytest.mark.parametrize(
    ("call", "needle"),
    [
        (lambda: cm.shaft.ShaftTorque.from_curves(np.zeros((1, 4)), np.zeros((1, 5))), "shape"),
        (lambda: cm.shaft.ShaftTorque.from_curves(np.zeros((1, 2)), np.zeros((1, 2))), ">= 3"),
        (
            lambda: cm.shaft.ShaftTorque.from_curves(np.zeros((2, 4)), np.zeros((2, 4)), [0.0]),
            "phase_deg",
        ),
        (lambda: cm.shaft.ShaftTorque.from_curves([[0, 0, math.nan]], [[0, 0, 0]]), "per_omega2"),
        (
            lambda: cm.shaft.ShaftTorque.from_curves([[0, 0, 0]], [[0, 0, 0]]).stats(100, 0.0),
            "speed_fluctuation",
        ),
        (lambda: cm.shaft.ShaftTorque.from_curves([[0, 0, 0]], [[0, 0, 0]]).stats(-5, 0.1), "rpm"),
    ],
)
def test_bad_input_is_named(call, needle) -> None:
    with pytest.raises(cm.CyclomechError) as e:
        call()
    assert isinstance(e.value, ValueError) and needle in str(e.value)


def _numpy_exact_stats(a: np.ndarray, b: np.ndarray, rpm: np.ndarray, delta: float) -> list:
    """The statistics as the sampled kernel defines them, vectorised over (speeds,
    samples) in numpy: T = ω²a + b, its samples' mean, peak and lowest, the RMS of
    the piecewise-linear torque, and ΔE over the samples of E = ∫(T − T̄) AND E's
    extrema inside each step where T − T̄ changes sign."""
    n = a.size
    h = 2 * math.pi / n
    w = rpm * RAD
    t = (w**2)[:, None] * a[None] + b[None]
    t1 = np.roll(t, -1, axis=1)
    mean = t.mean(axis=1)
    rms = np.sqrt((h * (t * t + t * t1 + t1 * t1) / 3).sum(axis=1) / (2 * math.pi))
    d0, d1 = t - mean[:, None], t1 - mean[:, None]
    e = np.concatenate([np.zeros((len(w), 1)), np.cumsum(0.5 * (d0 + d1) * h, axis=1)], axis=1)
    cross = ((d0 < 0) != (d1 < 0)) & (d0 != d1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ex = e[:, :-1] + 0.5 * d0 * (d0 / (d0 - d1)) * h
    hi = np.maximum(e.max(axis=1), np.where(cross, ex, -np.inf).max(axis=1))
    lo = np.minimum(e.min(axis=1), np.where(cross, ex, np.inf).min(axis=1))
    de = hi - lo
    return [mean, t.max(axis=1), t.min(axis=1), rms, de, de / (w**2 * delta), mean * w]


@given(
    st.integers(0, 2**31),
    st.integers(3, 50),
    st.lists(st.floats(1.0, 5000.0), min_size=1, max_size=30),
    st.booleans(),
)
@settings(max_examples=60, deadline=None)
def test_statistics_equal_the_sampled_definition(seed, n, rpm, ties) -> None:
    """Every column of the envelope kernel (issue 37) against the sampled kernel's
    definition in numpy, on random torques (with ties in a and b when `ties`), at
    one or many speeds, repeated and unsorted. Tolerances, relative to the scale
    S = max|ω²a| + max|b| at each speed: 1e-12 for the mean, peak and lowest,
    1e-7 for the RMS (its square is a quadratic in ω² here, a sum there), 2e-9
    of S for ΔE [J] (and the flywheel with it)."""
    rng = np.random.default_rng(seed)
    if ties:
        a = rng.integers(-2, 3, size=n) * 1e-3
        b = rng.integers(-2, 3, size=n).astype(float)
    else:
        a, b = rng.normal(size=n) * 1e-3, rng.normal(size=n)
    speeds = np.array(rpm + rpm[:1])
    s = cm.shaft.ShaftTorque.from_curves(a[None], b[None]).stats(speeds, 0.03)
    want = _numpy_exact_stats(a, b, speeds, 0.03)
    w2 = (speeds * RAD) ** 2
    scale = w2 * np.abs(a).max() + np.abs(b).max() + 1e-300
    got = [
        s.mean_torque_nm,
        s.peak_torque_nm,
        s.lowest_torque_nm,
        s.rms_torque_nm,
        s.energy_fluctuation_j,
        s.flywheel_kg_m2 * w2 * 0.03,
        s.power_w / (speeds * RAD),
    ]
    want[5] = want[5] * w2 * 0.03
    want[6] = want[6] / (speeds * RAD)
    for g, wv, tol in zip(got, want, [1e-12, 1e-12, 1e-12, 1e-7, 2e-9, 2e-9, 1e-12], strict=True):
        assert np.all(np.abs(g - wv) <= tol * scale), (g, wv)
