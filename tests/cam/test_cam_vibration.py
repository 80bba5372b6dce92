"""The cam's follower dynamics (issue 18, item 6): the residual vibration of a
motion law, its bound τ*, and the periodic steady state of a whole cam — checked
against a closed form, scipy's ``solve_ivp`` and the definitions themselves.

The laws' accelerations z''(u) used by the references are written out here from
their textbook definitions (not read from cyclomech)."""

from __future__ import annotations

import itertools
import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

S = cm.cam.Segment
TAU = 2 * math.pi
PI2 = math.pi**2
#: Modified sine: peak acceleration Ca = 4π²/(4 + π) (textbook 5.528).
CA_MODSINE = 4 * PI2 / (4 + math.pi)
#: Modified trapezoid: Ca = 8π/(π + 2) (textbook 4.888).
CA_MODTRAP = 8 * math.pi / (math.pi + 2)


def _zpp(law: str, u: float) -> float:
    """z''(u) of the normalised rise, from the textbook forms."""
    if law == "cycloidal":
        return TAU * math.sin(TAU * u)
    if law == "harmonic":
        return PI2 / 2 * math.cos(math.pi * u)
    if law == "polynomial_345":
        return 60 * u - 180 * u**2 + 120 * u**3
    if law == "polynomial_4567":
        return 420 * u**2 - 1680 * u**3 + 2100 * u**4 - 840 * u**5
    if law == "modified_trapezoid":
        if u <= 1 / 8:
            return CA_MODTRAP * math.sin(4 * math.pi * u)
        if u <= 3 / 8:
            return CA_MODTRAP
        if u <= 5 / 8:
            return CA_MODTRAP * math.cos(4 * math.pi * (u - 3 / 8))
        if u <= 7 / 8:
            return -CA_MODTRAP
        return -CA_MODTRAP * math.cos(4 * math.pi * (u - 7 / 8))
    if law == "modified_sine":
        if u <= 1 / 8:
            return CA_MODSINE * math.sin(4 * math.pi * u)
        if u <= 7 / 8:
            return CA_MODSINE * math.cos(4 * math.pi * (u - 1 / 8) / 3)
        return -CA_MODSINE * math.cos(4 * math.pi * (u - 7 / 8))
    raise AssertionError(law)


_BREAKS = {
    "modified_sine": (0.0, 1 / 8, 7 / 8, 1.0),
    "modified_trapezoid": (0.0, 1 / 8, 3 / 8, 5 / 8, 7 / 8, 1.0),
}
LAWS = (
    "cycloidal",
    "harmonic",
    "polynomial_345",
    "polynomial_4567",
    "modified_sine",
    "modified_trapezoid",
)


def _amplitude(q: float, v: float, w: float, zeta: float) -> float:
    return math.hypot(q, (v + zeta * w * q) / (w * math.sqrt(1 - zeta**2)))


def _ivp_residual(law: str, tau: float, zeta: float) -> float:
    """R by integrating x'' + 2ζτx' + τ²x = −z''(u) from rest over [0, 1] with
    scipy (piece by piece across the law's breakpoints)."""
    y = np.zeros(2)
    knots = _BREAKS.get(law, (0.0, 1.0))
    for a, b in itertools.pairwise(knots):

        def f(u: float, s: np.ndarray, a: float = a, b: float = b) -> list[float]:
            uu = min(max(u, a), b)  # stay on this piece
            return [s[1], -2 * zeta * tau * s[1] - tau**2 * s[0] - _zpp(law, uu)]

        sol = solve_ivp(f, (a, b), y, method="DOP853", rtol=1e-10, atol=1e-14)
        y = sol.y[:, -1]
    return _amplitude(y[0], y[1], tau, zeta)


def _cycloidal_closed(tau: np.ndarray) -> np.ndarray:
    return 8 * PI2 * np.abs(np.sin(tau / 2)) / (tau * np.abs(4 * PI2 - tau**2))


# --- residual vibration of one segment -----------------------------------------


def test_cycloidal_closed_form() -> None:
    """Undamped, from rest, x(u) = −(1/τ)∫₀ᵘ z''(s) sin(τ(u − s)) ds (Duhamel),
    so for u ≥ 1 (z'' = 0) x = −Im(e^{iτu} I)/τ with I = ∫₀¹ z''(s)e^{−iτs} ds:
    the residual amplitude is |I|/τ (per unit stroke; in time, |∫ s̈ e^{−iω_n t}
    dt|/ω_n). For the cycloidal rise z'' = 2π sin 2πs and
    ∫₀¹ sin(as)e^{−iτs} ds = a(1 − e^{−iτ})/(a² − τ²) when a = 2π (cos a = 1,
    sin a = 0), with |1 − e^{−iτ}| = 2|sin(τ/2)|: R = 8π²|sin(τ/2)|/(τ|4π² − τ²|),
    zero at τ = 2πk, k ≥ 2 (the rise lasts k natural periods)."""
    tau = np.linspace(1.0, 200.0, 4001)
    tau = tau[np.abs(tau - TAU) > 1e-3]  # the closed form's removable 0/0
    r = cm.cam.residual_vibration("cycloidal", tau)
    want = _cycloidal_closed(tau)
    envelope = 8 * PI2 / (tau * np.abs(4 * PI2 - tau**2))
    assert np.all(np.abs(r - want) <= 1e-6 * envelope)
    away = want > 1e-3 * envelope  # relative, away from the zeros
    np.testing.assert_allclose(r[away], want[away], rtol=1e-6)
    zeros = cm.cam.residual_vibration("cycloidal", TAU * np.arange(2, 11))
    assert np.all(zeros < 1e-6)
    # At τ = 2π the limit is 1/2 (sin(τ/2) ≈ (2π − τ)/2).
    assert cm.cam.residual_vibration("cycloidal", [TAU])[0] == pytest.approx(0.5, rel=1e-8)


@pytest.mark.parametrize("law", ["cycloidal", "modified_sine", "harmonic", "polynomial_345"])
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2])
def test_against_solve_ivp(law: str, zeta: float) -> None:
    taus = [0.7, 2.5, 7.0, 16.0, 40.0]
    r = cm.cam.residual_vibration(law, taus, zeta)
    want = [_ivp_residual(law, t, zeta) for t in taus]
    np.testing.assert_allclose(r, want, rtol=1e-7, atol=1e-10)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("zeta", [0.0, 0.01, 0.5, 0.95])
def test_every_law_against_solve_ivp(law: str, zeta: float) -> None:
    """The closed forms (issue 37) for every built-in law, ζ from 0 to near 1,
    τ from small to large, against scipy integrating the textbook z''."""
    taus = [0.05, 0.9, 1.1, 6.283185307179586, 13.0, 55.0, 120.0]
    r = cm.cam.residual_vibration(law, taus, zeta)
    want = [_ivp_residual(law, t, zeta) for t in taus]
    np.testing.assert_allclose(r, want, rtol=2e-7, atol=1e-10)


@settings(max_examples=30, deadline=None)
@given(
    law=st.sampled_from(LAWS),
    tau=st.floats(0.01, 60.0),
    zeta=st.floats(0.0, 0.95),
)
def test_closed_forms_property_against_solve_ivp(law: str, tau: float, zeta: float) -> None:
    r = float(cm.cam.residual_vibration(law, tau, zeta))
    want = _ivp_residual(law, tau, zeta)
    assert r == pytest.approx(want, rel=2e-7, abs=1e-10)


def _damped_cycloidal(tau: np.ndarray, zeta: float) -> np.ndarray:
    """Independent numpy closed form: G = 4π²(e^λ − 1)/(λ² + 4π²), R = |G|/ω_d
    (complex arithmetic, λ = −ζτ + iω_d)."""
    wd = tau * math.sqrt(1 - zeta**2)
    lam = -zeta * tau + 1j * wd
    return np.abs(4 * PI2 * np.expm1(lam) / (lam**2 + 4 * PI2)) / wd


def _damped_345(tau: np.ndarray, zeta: float) -> np.ndarray:
    """Independent numpy closed form of the 3-4-5 rise by parts (g = −z''):
    G = Σ_m (g⁽ᵐ⁾(0)·e^λ − g⁽ᵐ⁾(1))/λ^(m+1) with g(0) = g(1) = 0, g' = −60 at
    both ends, g'' = 360 and −360, and the third derivative −720 (used for
    |λ| ≥ 2, where the sum does not cancel)."""
    wd = tau * math.sqrt(1 - zeta**2)
    lam = -zeta * tau + 1j * wd
    e = np.exp(lam)
    g = -60 * (e - 1) / lam**2 + 360 * (e + 1) / lam**3 - 720 * (e - 1) / lam**4
    return np.abs(g) / wd


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.4, 0.99])
def test_against_independent_numpy_closed_forms(zeta: float) -> None:
    tau = np.geomspace(2.0, 1e4, 3001)
    tau = tau[np.abs(tau - TAU) > 1e-6]
    envelope = np.minimum(1 / math.sqrt(1 - zeta**2), 100 / tau**2)
    for law, ref in (("cycloidal", _damped_cycloidal), ("polynomial_345", _damped_345)):
        r = cm.cam.residual_vibration(law, tau, zeta)
        assert np.all(np.abs(r - ref(tau, zeta)) <= 1e-11 * envelope), law


def test_small_tau_limit_and_shape() -> None:
    # τ → 0: the follower stays put, x(1) → −1 and R → 1/√(1 − ζ²).
    for zeta in (0.0, 0.3):
        r = cm.cam.residual_vibration("polynomial_4567", [[1e-6]], zeta)
        assert r.shape == (1, 1)
        assert r[0, 0] == pytest.approx(1 / math.sqrt(1 - zeta**2), rel=1e-5)
    one = cm.cam.residual_vibration("harmonic", 3.0)
    assert one.shape == ()


def test_threads_agree() -> None:
    tau = np.linspace(0.5, 60, 301)
    a = cm.cam.residual_vibration("modified_trapezoid", tau, 0.1, n_threads=1)
    b = cm.cam.residual_vibration("modified_trapezoid", tau, 0.1, n_threads=2)
    np.testing.assert_array_equal(a, b)


# --- the bound τ* ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("law", "limit", "zeta"),
    [
        ("cycloidal", 0.05, 0.0),
        ("cycloidal", 0.003, 0.05),
        ("harmonic", 0.02, 0.0),
        ("modified_sine", 0.01, 0.2),
        ("polynomial_345", 0.3, 0.0),
        ("modified_trapezoid", 0.001, 0.05),
    ],
)
def test_min_tau_is_the_last_crossing(law: str, limit: float, zeta: float) -> None:
    t = cm.cam.min_vibration_tau(law, limit, zeta)
    assert t > 0
    r = cm.cam.residual_vibration(law, t, zeta)
    assert float(r) == pytest.approx(limit, rel=1e-9)
    # Below the limit on a dense grid well past τ* (20 lobes).
    dense = cm.cam.residual_vibration(law, t + np.linspace(1e-9, 40 * math.pi, 20001), zeta)
    assert dense.max() <= limit * (1 + 1e-9)
    # Violated just below.
    assert float(cm.cam.residual_vibration(law, t * (1 - 1e-6), zeta)) > limit


def test_min_tau_ignores_a_feasible_window_below() -> None:
    """The cycloidal rise has R = 0 at τ = 4π (two natural periods), but the lobe
    after it peaks above a 1 % limit: the bound is past that lobe, the window at
    4π is ignored (conservative)."""
    limit = 0.01
    t = cm.cam.min_vibration_tau("cycloidal", limit)
    assert t > 4 * math.pi
    assert float(cm.cam.residual_vibration("cycloidal", 4 * math.pi)) < limit
    between = cm.cam.residual_vibration("cycloidal", np.linspace(4 * math.pi, t, 2001))
    assert between.max() > limit
    np.testing.assert_allclose(t, 17.56594, rtol=1e-6)


def test_min_tau_without_a_bound() -> None:
    # R ≤ R(0+) = 1/√(1 − ζ²) for these laws: a limit above it binds nowhere.
    assert cm.cam.min_vibration_tau("cycloidal", 1.5) == 0.0
    assert cm.cam.min_vibration_tau("harmonic", 4.0, 0.1) == 0.0


def test_min_tau_lobe_just_above_limit() -> None:
    """A limit a hair under a lobe's top: the lobe must be found (refined), not
    missed by the scan's samples."""
    law, zeta = "cycloidal", 0.0
    tau = np.linspace(18.0, 26.0, 80001)
    r = cm.cam.residual_vibration(law, tau, zeta)
    i = int(np.argmax(r))  # the lobe between 4π and 6π
    top = float(r[i])
    limit = top * (1 - 1e-7)
    t = cm.cam.min_vibration_tau(law, limit, zeta)
    assert t > tau[i]
    assert float(cm.cam.residual_vibration(law, t, zeta)) == pytest.approx(limit, rel=1e-9)
    # And just above the top, that lobe no longer binds.
    assert cm.cam.min_vibration_tau(law, top * (1 + 1e-6), zeta) < tau[i]


@settings(max_examples=25, deadline=None)
@given(
    law=st.sampled_from(["cycloidal", "harmonic", "polynomial_345", "modified_sine"]),
    a=st.floats(1e-3, 1.2),
    b=st.floats(1e-3, 1.2),
    zeta=st.sampled_from([0.0, 0.05, 0.3]),
)
def test_min_tau_non_increasing_in_the_limit(law: str, a: float, b: float, zeta: float) -> None:
    lo, hi = sorted((a, b))
    t_lo = cm.cam.min_vibration_tau(law, lo, zeta)
    t_hi = cm.cam.min_vibration_tau(law, hi, zeta)
    assert t_hi <= t_lo * (1 + 1e-12)


# --- the periodic steady state of a whole cam ---------------------------------------


def _cam(program: list[cm.cam.Segment]) -> cm.cam.Cam:
    return cm.cam.Cam(program, cm.cam.TranslatingRoller(0.05, 0.01))


def test_steady_state_is_periodic() -> None:
    cam = _cam([S("rise", 100, 0.02, "harmonic"), S("dwell", 80), S("return", 180, 0.02)])
    r = cm.cam.follower_response(cam, 450, 35.0, 0.02, theta=[0.0, TAU, 2.0])
    scale = np.abs(cm.cam.follower_response(cam, 450, 35.0, 0.02).error).max()
    assert abs(r.error[0] - r.error[1]) < 1e-9 * scale
    wn = TAU * 35.0
    assert abs(r.rate[0] - r.rate[1]) < 1e-9 * wn * scale
    # A turn by scipy from the returned start comes back to it.
    omega = 450 * TAU / 60

    def sdd(theta: float) -> float:
        return float(cam.solve(theta).dds) * omega**2

    def f(t: float, y: np.ndarray) -> list[float]:
        return [y[1], -2 * 0.02 * wn * y[1] - wn**2 * y[0] - sdd(omega * t)]

    y = np.array([r.error[0], r.rate[0]])
    edges = np.radians([0, 100, 180, 360]) / omega
    for a, b in itertools.pairwise(edges):
        y = solve_ivp(f, (a, b), y, method="DOP853", rtol=1e-10, atol=1e-15).y[:, -1]
    np.testing.assert_allclose(y[0], r.error[0], rtol=0, atol=1e-7 * scale)


def test_steady_state_against_solve_ivp_settled() -> None:
    """From rest, scipy runs turn after turn until the start-up has died out
    (ζ = 0.1: e^{−ζω_n·12 turns} ≈ 1e-17), then its last turn is the steady state."""
    rpm, fn, zeta = 120.0, 10.0, 0.1
    program = [S("rise", 90, 0.01), S("dwell", 30), S("return", 120, 0.01, "polynomial_345"),
               S("dwell", 120)]  # fmt: skip
    cam = _cam(program)
    omega, wn = rpm * TAU / 60, TAU * fn
    bounds = np.radians([0, 90, 120, 240, 360])
    strokes = [0.01, 0.0, -0.01, 0.0]
    laws = ["cycloidal", None, "polynomial_345", None]

    def sdd(theta: float) -> float:
        k = min(int(np.searchsorted(bounds, theta, side="right")) - 1, 3)
        if laws[k] is None:
            return 0.0
        beta = bounds[k + 1] - bounds[k]
        u = min(max((theta - bounds[k]) / beta, 0.0), 1.0)
        return strokes[k] * _zpp(laws[k], u) / beta**2 * omega**2

    y = np.zeros(2)
    theta_out = np.radians([0.0, 45.0, 90.0, 100.0, 200.0, 300.0])
    turns = 12
    for turn in range(turns):
        for k in range(4):
            a, b = bounds[k], bounds[k + 1]

            def f(
                t: float, s: np.ndarray, a: float = a, b: float = b, turn: int = turn
            ) -> list[float]:
                th = min(max(omega * t - turn * TAU, a), b)
                return [s[1], -2 * zeta * wn * s[1] - wn**2 * s[0] - sdd(th)]

            t0, t1 = (turn * TAU + a) / omega, (turn * TAU + b) / omega
            want_at = [(turn * TAU + th) / omega for th in theta_out if a <= th < b]
            sol = solve_ivp(f, (t0, t1), y, method="DOP853", rtol=1e-11, atol=1e-16,
                            dense_output=True)  # fmt: skip
            if turn == turns - 1:
                for tt in want_at:
                    f_x = sol.sol(tt)
                    th = omega * tt - turn * TAU
                    got = cm.cam.follower_response(cam, rpm, fn, zeta, theta=[th])
                    scale = 1e-7 * 0.01
                    assert got.error[0] == pytest.approx(f_x[0], abs=scale)
                    assert got.rate[0] == pytest.approx(f_x[1], abs=scale * wn)
            y = sol.y[:, -1]


def test_steady_residual_after_a_long_dwell_is_the_segment_residual() -> None:
    """A long damped dwell before the rise leaves it starting from (nearly) rest:
    its residual in steady state is h·R(τ) with τ = ω_n·β/ω."""
    h, rpm, fn, zeta = 0.015, 20.0, 40.0, 0.15
    cam = _cam([S("dwell", 240), S("rise", 50, h, "modified_sine"), S("dwell", 20),
                S("return", 50, h, "modified_sine")])  # fmt: skip
    resp = cm.cam.follower_response(cam, rpm, fn, zeta, theta=[0.0])
    omega = rpm * TAU / 60
    tau = TAU * fn * math.radians(50) / omega
    want = h * float(cm.cam.residual_vibration("modified_sine", tau, zeta))
    # What is left of the previous return after the dwell: e^{−ζω_n·T_dwell}.
    left = math.exp(-zeta * TAU * fn * math.radians(240) / omega)
    assert left < 1e-10
    assert resp.residual[1] == pytest.approx(want, rel=1e-7)


def test_response_shapes_and_default_grid() -> None:
    cam = _cam([S("rise", 180, 0.01), S("return", 180, 0.01)])
    r = cm.cam.follower_response(cam, 300, 23.0)
    assert r.theta.shape == r.error.shape == r.rate.shape == (721,)
    assert r.theta[-1] == TAU
    assert r.residual.shape == (2,)
    grid = np.linspace(-1.0, 8.0, 12).reshape(3, 4)
    r2 = cm.cam.follower_response(cam, 300, 23.0, theta=grid)
    assert r2.error.shape == (3, 4)
    r3 = cm.cam.follower_response(cam, 300, 23.0, theta=np.mod(grid, TAU))
    np.testing.assert_allclose(r2.error, r3.error, rtol=0, atol=1e-15)
    back = pickle.loads(pickle.dumps(r2))
    np.testing.assert_array_equal(back.error, r2.error)


# --- bad input -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: cm.cam.residual_vibration("cycloidal", 1.0, -0.1), "damping_ratio"),
        (lambda: cm.cam.residual_vibration("cycloidal", 1.0, 1.0), "damping_ratio"),
        (lambda: cm.cam.residual_vibration("cycloidal", 1.0, math.nan), "damping_ratio"),
        (lambda: cm.cam.residual_vibration("nope", 1.0), "law"),
        (lambda: cm.cam.residual_vibration("harmonic", [1.0, 0.0]), r"tau\[1\]"),
        (lambda: cm.cam.residual_vibration("harmonic", [[1.0, math.nan]]), r"tau\[0, 1\]"),
        (lambda: cm.cam.residual_vibration("harmonic", ["a"]), "tau"),
        (lambda: cm.cam.min_vibration_tau("cycloidal", 0.0), "amplitude_ratio"),
        (lambda: cm.cam.min_vibration_tau("cycloidal", -1.0), "amplitude_ratio"),
        (lambda: cm.cam.min_vibration_tau("cycloidal", math.nan), "amplitude_ratio"),
        (lambda: cm.cam.min_vibration_tau("cycloidal", 0.1, 1.5), "damping_ratio"),
        (lambda: cm.cam.min_vibration_tau("x", 0.1), "law"),
    ],
)
def test_bad_input(call, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(cm.InputError, match=match) as e:
        call()
    assert isinstance(e.value, ValueError)


def test_bad_response_input() -> None:
    cam = _cam([S("rise", 180, 0.01), S("return", 180, 0.01)])
    for kwargs, match in [
        ({"rpm": 0.0}, "rpm"),
        ({"rpm": math.nan}, "rpm"),
        ({"natural_frequency_hz": -2.0}, "natural_frequency_hz"),
        ({"damping_ratio": 1.0}, "damping_ratio"),
        ({"theta": [0.0, math.nan]}, r"theta\[1\]"),
    ]:
        args = {"rpm": 300.0, "natural_frequency_hz": 20.0} | kwargs
        with pytest.raises(cm.InputError, match=match):
            cm.cam.follower_response(cam, **args)
    with pytest.raises(cm.InputError, match="cam must be"):
        cm.cam.follower_response("cam", 300.0, 20.0)  # type: ignore[arg-type]


def test_resonance_is_a_clear_error() -> None:
    # 300 rpm = 5 turns/s; 20 Hz: a turn lasts exactly 4 natural periods.
    cam = _cam([S("rise", 180, 0.01, "harmonic"), S("return", 180, 0.01, "harmonic")])
    with pytest.raises(cm.InputError, match=r"speed = 300.*resonance"):
        cm.cam.follower_response(cam, 300.0, 20.0)
    # Damped, or off resonance, it has a steady state.
    assert np.isfinite(cm.cam.follower_response(cam, 300.0, 20.0, 0.01).error).all()
    assert np.isfinite(cm.cam.follower_response(cam, 301.0, 20.0).error).all()


def test_kernel_errors_without_the_python_checks() -> None:
    """The Rust entry points refuse bad input themselves (no panic)."""
    tau = np.array([1.0, -2.0])
    with pytest.raises(cm.InputError, match="case 1: tau"):
        _core.cam_residual_ratio("cycloidal", tau, 0.0)
    with pytest.raises(cm.InputError, match=r"case 0: tau must be finite and within"):
        cm.cam.residual_vibration("cycloidal", 1e-200)
    with pytest.raises(cm.InputError, match="unknown motion law"):
        _core.cam_residual_ratio("nope", np.ones(1), 0.0)
    with pytest.raises(cm.InputError, match="zeta"):
        _core.cam_min_tau("cycloidal", 0.1, 1.0)
    with pytest.raises(cm.InputError, match="ratio_limit"):
        _core.cam_min_tau("cycloidal", -0.1, 0.0)
    with pytest.raises(cm.InputError, match="ratio_limit"):
        _core.cam_min_tau("cycloidal", 1e-14, 0.0)
    th = np.zeros(1)
    with pytest.raises(cm.InputError, match="one entry per segment"):
        _core.cam_follower_response(["rise"], [1.0, 2.0], [0.1], ["cycloidal"], 1, 1, 0, th)
    with pytest.raises(cm.InputError, match="rise, dwell or return"):
        _core.cam_follower_response(["lift"], [TAU], [0.0], ["cycloidal"], 1.0, 1.0, 0.0, th)
    with pytest.raises(cm.InputError, match="not 360"):
        _core.cam_follower_response(["dwell"], [1.0], [0.0], ["cycloidal"], 1.0, 1.0, 0.0, th)
    with pytest.raises(cm.InputError, match="omega_n"):
        _core.cam_follower_response(["dwell"], [TAU], [0.0], ["x"], 1.0, 0.0, 0.0, th)


def test_residual_vibration_refuses_a_size_that_cannot_fit() -> None:
    # 1e9 broadcast values ran to 9.8 GB and ~70 minutes without a word.
    with pytest.raises(cm.InputError, match=r"residual_vibration of 1000000000000 values needs"):
        cm.cam.residual_vibration("cycloidal", np.broadcast_to(1.0, (10**12,)))
    with pytest.raises(cm.InputError, match=r"tau\[1\] = nan must be finite"):
        cm.cam.residual_vibration("cycloidal", [1.0, np.nan])
