"""The stop-impact kernels (seed 000) against independent references.

The references are written here from the textbook, not from the library:

* closed forms of the damped oscillator m·q̈ + 2ζω·m·q̇ + ω²·m·q = F0 + s·t for
  ζ = 0, 0 < ζ < 1, ζ = 1 and ζ > 1 (the homogeneous solution plus the ramp's
  particular solution (F0 + s·(t − 2ζ/ω))/(mω²)); a rectangular pulse as two steps;
* an O(N²) trapezoid quadrature of the Duhamel integral with the impulse response
  h(t) = e^{−ζωt}·sin(ω_d t)/(m·ω_d), Richardson-extrapolated, and scipy's lsim;
* shock spectra (Biggs, *Introduction to Structural Dynamics*, ch. 2; Harris'
  *Shock and Vibration Handbook*, transient response to pulses): undamped rectangular pulse
  DLF = 2 for t_d/T ≥ ½ and 2·sin(π·t_d/T) below; undamped decaying triangle
  DLF = 2 − 2·arctan(θ)/θ (θ = 2π·t_d/T, the peak inside the pulse where
  2·arctan θ ≤ θ) or the residual amplitude √((1 − cos θ)² + (θ − sin θ)²)/θ,
  derived below and checked against scipy's solve_ivp; the damped spectra against
  solve_ivp with event location;
* the unilateral stop against solve_ivp switching its right-hand side at x = 0,
  and against the undamped closed forms (contact time, exit speed, rebound height).
"""

from __future__ import annotations

import itertools
import math

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import impact
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy import signal
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

TAU = 2 * math.pi
FAST = settings(max_examples=40, deadline=None)
SLOW = settings(max_examples=15, deadline=None)
ZETAS = (0.0, 0.05, 0.5, 1.0, 2.0)


# ---------------------------------------------------------------------------
# Independent references


def free(t, w, z, x0, v0):
    """Free vibration x(t), ẋ(t) of ẍ + 2ζω·ẋ + ω²·x = 0 from x0, v0 (every regime)."""
    t = np.asarray(t, dtype=float)
    if z < 1.0:
        wd = w * math.sqrt(1.0 - z * z)
        e = np.exp(-z * w * t)
        c, s = np.cos(wd * t), np.sin(wd * t)
        b = (v0 + z * w * x0) / wd
        x = e * (x0 * c + b * s)
        v = e * (-z * w * (x0 * c + b * s) + wd * (b * c - x0 * s))
    elif z == 1.0:
        e = np.exp(-w * t)
        b = v0 + w * x0
        x = e * (x0 + b * t)
        v = e * (b - w * (x0 + b * t))
    else:
        r = math.sqrt(z * z - 1.0)
        r1, r2 = -w * (z - r), -w * (z + r)
        a1 = (v0 - r2 * x0) / (r1 - r2)
        a2 = (r1 * x0 - v0) / (r1 - r2)
        x = a1 * np.exp(r1 * t) + a2 * np.exp(r2 * t)
        v = a1 * r1 * np.exp(r1 * t) + a2 * r2 * np.exp(r2 * t)
    return x, v


def ramp(t, F0, s, w, z, m, q0=0.0, v0=0.0):
    """q(t), q̇(t) under F = F0 + s·t from q0, v0 at t = 0: the particular solution
    (F0 + s·(t − 2ζ/ω))/k plus free vibration."""
    t = np.asarray(t, dtype=float)
    k = m * w * w
    xh, vh = free(t, w, z, q0 - (F0 - 2 * z * s / w) / k, v0 - s / k)
    return (F0 + s * (t - 2 * z / w)) / k + xh, s / k + vh


def step(t, w, z, m):
    """Response to a unit step force applied at t = 0 (zero before)."""
    t = np.asarray(t, dtype=float)
    return np.where(t >= 0, ramp(np.maximum(t, 0.0), 1.0, 0.0, w, z, m)[0], 0.0)


def close(actual, expected, rel):
    """Agreement to ``rel`` relative to the largest |expected| (zero crossings)."""
    expected = np.asarray(expected, dtype=float)
    scale = float(np.abs(expected).max())
    assert_allclose(actual, expected, rtol=rel, atol=rel * scale)


def duhamel_quadrature(t_out, f, t_d, w, z, m, n):
    """q(t) = ∫₀^min(t, t_d) F(τ)·h(t − τ) dτ by the trapezoid rule on n intervals,
    all output times at once (an (n_out, n + 1) matrix: O(N²))."""
    wd = w * math.sqrt(1.0 - z * z)
    upper = np.minimum(t_out, t_d)
    u = np.linspace(0.0, 1.0, n + 1)
    tau = upper[:, None] * u[None, :]
    lag = t_out[:, None] - tau
    g = f(tau) * np.exp(-z * w * lag) * np.sin(wd * lag) / (m * wd)
    wts = np.full(n + 1, 1.0)
    wts[0] = wts[-1] = 0.5
    return upper / n * (g @ wts)


def ode_history(F, t_end, w, z, m, q0=0.0, v0=0.0, breaks=()):
    """solve_ivp (DOP853, rtol 1e-12) of the oscillator under F(t), restarted at the
    force's breakpoints; returns the segments' dense solutions and the local maxima
    and minima located as events of q̇ = 0."""

    def rhs(t, y):
        return [y[1], F(t) / m - 2 * z * w * y[1] - w * w * y[0]]

    def top(t, y):
        return y[1]

    def bottom(t, y):
        return y[1]

    top.direction, bottom.direction = -1, 1
    edges = [0.0, *sorted(breaks), t_end]
    y = np.array([q0, v0])
    segs, tops, bottoms = [], [], []
    for a, b in itertools.pairwise(edges):
        sol = solve_ivp(
            rhs,
            (a, b),
            y,
            method="DOP853",
            rtol=1e-12,
            atol=1e-14 * max(1.0, abs(F(a)) / (m * w * w)),
            dense_output=True,
            events=[top, bottom],
        )
        assert sol.success
        segs.append((a, b, sol.sol))
        tops += [(te, ye[0]) for te, ye in zip(sol.t_events[0], sol.y_events[0], strict=True)]
        bottoms += [(te, ye[0]) for te, ye in zip(sol.t_events[1], sol.y_events[1], strict=True)]
        y = sol.y[:, -1]
    return segs, np.array(tops).reshape(-1, 2), np.array(bottoms).reshape(-1, 2)


def dense_table(p, t_end, dt):
    """A dense history of a pulse table: its points (jumps kept as repeated
    times), points about dt apart in between, then the last force held to t_end."""
    ts, fs = [p.t[:1]], [p.f[:1]]
    for i in range(p.t.size - 1):
        a, b = p.t[i], p.t[i + 1]
        if b > a:
            inner = np.linspace(a, b, max(round((b - a) / dt), 1) + 1)[1:-1]
            ts.append(inner)
            fs.append(p.f[i] + (p.f[i + 1] - p.f[i]) * (inner - a) / (b - a))
        ts.append([b])
        fs.append([p.f[i + 1]])
    n = round((t_end - p.duration) / dt)
    tail = p.duration + dt * np.arange(1, n + 1)
    ts.append(tail)
    fs.append(np.full(n, p.f[-1]))
    return np.concatenate(ts), np.concatenate(fs)


# ---------------------------------------------------------------------------
# 1. Closed forms: free vibration, steps and ramps, jumps


@pytest.mark.parametrize("zeta", ZETAS)
def test_free_vibration_on_a_coarse_grid(zeta):
    """No force, q0 and v0: exact to 1e-9 with 10 steps per period, every regime."""
    w, m = TAU * 7.0, 0.3
    t = np.linspace(0.0, 5 * TAU / w, 51)
    q, v = impact.duhamel(
        t, np.zeros_like(t), omega_n=w, zeta=zeta, mass=m, q0=2e-3, v0=-0.4, velocity=True
    )
    x, xd = free(t, w, zeta, 2e-3, -0.4)
    close(q, x, 1e-9)
    close(v, xd, 1e-9)
    assert q[0] == 2e-3 and v[0] == -0.4


@pytest.mark.parametrize("zeta", ZETAS)
@pytest.mark.parametrize(("F0", "s"), [(3.0, 0.0), (0.0, 50.0), (-1.5, 40.0)])
def test_step_and_ramp_on_a_coarse_grid(zeta, F0, s):
    """F = F0 + s·t from q0, v0: closed form to 1e-9 with 10 steps per period. A
    step that starts at full value at t[0] (no ramp from zero) is exact."""
    w, m = TAU * 5.0, 0.3
    T = TAU / w
    t = np.linspace(0.0, 4 * T, 41)
    q, v = impact.duhamel(
        t, F0 + s * t, omega_n=w, zeta=zeta, mass=m, q0=1e-3, v0=-0.2, velocity=True
    )
    x, xd = ramp(t, F0, s, w, zeta, m, 1e-3, -0.2)
    close(q, x, 1e-9)
    close(v, xd, 1e-9)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 1.0, 2.0])
def test_fine_grid_keeps_the_closed_form(zeta):
    """10⁴ steps per period (ω·h ≈ 6e-4): the step-to-step coefficients must not
    lose digits to cancellation."""
    w, m = TAU * 3.0, 1.7
    t = np.linspace(0.0, 2 * TAU / w, 20_001)
    q = impact.duhamel(t, 2.0 - 5.0 * t, omega_n=w, zeta=zeta, mass=m, v0=0.1)
    close(q, ramp(t, 2.0, -5.0, w, zeta, m, 0.0, 0.1)[0], 1e-9)


@FAST
@given(
    zeta=st.sampled_from(ZETAS),
    steps=st.lists(st.floats(0.001, 0.3), min_size=2, max_size=40),
    F0=st.floats(-5, 5),
    s=st.floats(-50, 50),
)
def test_nonuniform_grid_ramp(zeta, steps, F0, s):
    """A ramp on an arbitrary increasing grid (steps from 0.1 % to 30 % of a
    period): the closed form, to 1e-9."""
    w, m = TAU * 2.0, 0.8
    t = np.concatenate([[0.0], np.cumsum(steps) * (TAU / w)])
    q = impact.duhamel(t, F0 + s * t, omega_n=w, zeta=zeta, mass=m, q0=-1e-2, v0=0.3)
    x = ramp(t, F0, s, w, zeta, m, -1e-2, 0.3)[0]
    assert_allclose(q, x, rtol=1e-9, atol=1e-9 * (np.abs(x).max() + 1e-2))


@pytest.mark.parametrize("zeta", ZETAS)
def test_jump_at_time_zero(zeta):
    """A force at full value from t = 0 and the same force as a jump from 0 at a
    repeated t = 0 give the exact step response 1 − cos-like curve."""
    w, m, F = TAU * 4.0, 0.5, 2.5
    T = TAU / w
    t = np.linspace(0.0, 3 * T, 31)
    full = impact.duhamel(t, np.full_like(t, F), omega_n=w, zeta=zeta, mass=m)
    t2 = np.concatenate([[0.0], t])
    jump = impact.duhamel(
        t2, np.concatenate([[0.0], np.full_like(t, F)]), omega_n=w, zeta=zeta, mass=m
    )
    ref = F * step(t, w, zeta, m)
    close(full, ref, 1e-9)
    close(jump[1:], ref, 1e-9)
    assert jump[0] == 0.0 and jump[1] == 0.0


@pytest.mark.parametrize("zeta", ZETAS)
@pytest.mark.parametrize("td_over_T", [0.23, 0.5, 1.37])
def test_rectangular_pulse_is_two_steps(zeta, td_over_T):
    """A repeated time t_d with the force falling F → 0 there equals
    F·(g(t) − g(t − t_d)), g the closed-form step response: on a coarse grid."""
    w, m, F = TAU * 6.0, 0.2, 4.0
    T = TAU / w
    td = td_over_T * T
    before = np.linspace(0.0, td, 4)
    after = td + np.arange(0, 41) * (T / 10)
    t = np.concatenate([before, after])
    f = np.concatenate([np.full(4, F), np.zeros(41)])
    q = impact.duhamel(t, f, omega_n=w, zeta=zeta, mass=m)
    ref = F * (step(t, w, zeta, m) - step(t - td, w, zeta, m))
    close(q, ref, 1e-9)
    # The library's own rectangular Pulse table is the same thing.
    p = impact.Pulse.rectangular(F, td)
    q2 = impact.duhamel(
        np.concatenate([p.t, after[1:]]),
        np.concatenate([p.f, np.zeros(40)]),
        omega_n=w,
        zeta=zeta,
        mass=m,
    )
    close(q2[1:], ref[3:], 1e-9)


def test_one_sample_history_is_the_initial_state():
    q, v = impact.duhamel(
        [0.0], [3.0], omega_n=5.0, zeta=0.1, mass=1.0, q0=0.25, v0=-1.0, velocity=True
    )
    assert q.tolist() == [0.25] and v.tolist() == [-1.0]


# ---------------------------------------------------------------------------
# 2. Duhamel quadrature and lsim for a half-sine pulse


def test_half_sine_against_an_independent_quadrature():
    """The Duhamel integral by the trapezoid rule (n = 1000 and 2000 intervals):
    duhamel, fed the half sine at 20001 points, agrees with the raw quadrature to its
    own error estimate and with the Richardson-extrapolated one to 1e-8."""
    w, z, m, F = TAU * 3.0, 0.1, 2.0, 5.0
    T = TAU / w
    td = 0.6 * T
    t = np.concatenate([np.linspace(0.0, td, 20_001), np.linspace(td, td + 2 * T, 2001)[1:]])
    f = np.where(t <= td, F * np.sin(np.pi * np.minimum(t, td) / td), 0.0)
    q = impact.duhamel(t, f, omega_n=w, zeta=z, mass=m)
    idx = np.arange(0, t.size, 97)
    t_out = t[idx]

    def sine(tau):
        return F * np.sin(np.pi * tau / td)

    q1 = duhamel_quadrature(t_out, sine, td, w, z, m, 1000)
    q2 = duhamel_quadrature(t_out, sine, td, w, z, m, 2000)
    err = np.abs(q1 - q2).max() * 4 / 3  # the trapezoid error of q1
    assert err < 1e-5 * np.abs(q2).max()  # a meaningful quadrature
    assert np.abs(q[idx] - q1).max() <= 1.2 * err
    close(q[idx], (4 * q2 - q1) / 3, 1e-8)


def test_against_scipy_lsim():
    """scipy.signal.lsim (linear interpolation of the input, as duhamel) on a fine
    grid, with initial conditions, for a half sine then free vibration."""
    w, z, m = TAU * 11.0, 0.3, 0.05
    T = TAU / w
    td = 0.8 * T
    t = np.linspace(0.0, 4 * T, 8001)
    f = np.where(t <= td, 3.0 * np.sin(np.pi * np.minimum(t, td) / td), 0.0)
    sys = signal.StateSpace(
        [[0.0, 1.0], [-w * w, -2 * z * w]], [[0.0], [1.0 / m]], [[1.0, 0.0]], [[0.0]]
    )
    _, y, _ = signal.lsim(sys, f, t, X0=[1e-3, 0.05])
    q = impact.duhamel(t, f, omega_n=w, zeta=z, mass=m, q0=1e-3, v0=0.05)
    close(q, y, 1e-8)


# ---------------------------------------------------------------------------
# 3. Shock spectra


def rect_dlf(r):
    """Biggs: max DLF of an undamped rectangular pulse of duration r·T."""
    return 2.0 if r >= 0.5 else 2.0 * math.sin(math.pi * r)


def triangle_dlf(r):
    """Max DLF of an undamped decaying triangle of duration r·T, derived:
    inside the pulse q·k/F = 1 − cos φ + (sin φ − φ)/θ (φ = ωt, θ = ω·t_d) peaks
    where tan(φ/2) = θ, at 2 − 2·arctan(θ)/θ, if that lies inside the pulse;
    after it the residual amplitude is √((1 − cos θ)² + (θ − sin θ)²)/θ."""
    th = TAU * r
    resid = math.hypot(1 - math.cos(th), th - math.sin(th)) / th
    inside = 2 - 2 * math.atan(th) / th if 2 * math.atan(th) <= th else -math.inf
    return max(inside, resid), inside


# Biggs' response chart for the decaying triangle (zero rise time), t_d/T: max DLF,
# to chart-reading accuracy (±0.01).
BIGGS_TRIANGLE = {0.1: 0.31, 0.2: 0.60, 0.5: 1.20, 1.0: 1.55, 2.0: 1.76}


@pytest.mark.parametrize("r", [0.1, 0.2, 0.3, 0.45, 0.5, 0.75, 1.0, 2.0])
def test_rectangular_pulse_shock_spectrum_undamped(r):
    """Max over a dense history after the pulse (to the grid's resolution, the
    sampled max never above the exact one) and the first peak by first_rebound
    (exact: 2 at T/2 inside the pulse, 2·sin(πr) after it)."""
    w, m, F = TAU * 50.0, 0.01, 3.0
    T, k = TAU / w, m * w * w
    td = r * T
    p = impact.Pulse.rectangular(F, td)
    t, f = dense_table(p, td + 2 * T, T / 4000)
    q = impact.duhamel(t, f, omega_n=w, zeta=0.0, mass=m)
    dlf = q.max() / (F / k)
    assert rect_dlf(r) - 1e-6 <= dlf <= rect_dlf(r) + 1e-9
    rb = impact.first_rebound(p.t, p.f, w, 0.0, m)
    assert rb.q[0] / (F / k) == pytest.approx(rect_dlf(r), rel=1e-10)
    if r >= 0.5:  # at T/2 inside the pulse
        assert rb.time[0] == pytest.approx(T / 2, rel=1e-10)
    else:  # the residual vibration peaks where ωt − ωt_d/2 = π/2
        assert rb.time[0] == pytest.approx(T / 4 + td / 2, rel=1e-10)


def test_triangle_closed_form_against_solve_ivp_and_biggs():
    """The derived triangle DLF against a fine solve_ivp and the chart values."""
    w, m = TAU, 1.0
    for r, chart in BIGGS_TRIANGLE.items():
        td = r * TAU / w
        _, tops, _ = ode_history(
            lambda t, td=td: max(1.0 - t / td, 0.0) if t <= td else 0.0,
            td + 2.0,
            w,
            0.0,
            m,
            breaks=(td,),
        )
        dlf, _ = triangle_dlf(r)
        assert tops[:, 1].max() * (m * w * w) == pytest.approx(dlf, rel=1e-9)
        assert dlf == pytest.approx(chart, abs=0.01)


@pytest.mark.parametrize("r", sorted(BIGGS_TRIANGLE))
def test_decaying_triangle_shock_spectrum_undamped(r):
    """duhamel's dense max after the pulse and first_rebound's first peak against
    the closed-form DLF (the first peak is the max where the residual dominates,
    the in-pulse peak otherwise)."""
    w, m, F = TAU * 40.0, 0.02, 7.0
    T, k = TAU / w, m * w * w
    td = r * T
    p = impact.Pulse.decaying(F, td)
    t, f = dense_table(p, td + 2 * T, T / 4000)
    q = impact.duhamel(t, f, omega_n=w, zeta=0.0, mass=m)
    dlf, inside = triangle_dlf(r)
    assert dlf - 1e-6 <= q.max() / (F / k) <= dlf + 1e-9
    rb = impact.first_rebound(p.t, p.f, w, 0.0, m)
    first = inside if inside > -math.inf else dlf
    assert rb.q[0] / (F / k) == pytest.approx(first, rel=1e-10)
    if inside > -math.inf:  # inside the pulse at φ = 2·arctan θ
        assert rb.time[0] == pytest.approx(2 * math.atan(TAU * r) / w, rel=1e-10)


@pytest.mark.parametrize("zeta", [0.05, 0.1])
@pytest.mark.parametrize(("shape", "r"), [("rect", 0.2), ("rect", 0.8), ("tri", 0.2), ("tri", 1.0)])
def test_damped_shock_spectrum_against_solve_ivp(zeta, shape, r):
    """Damped rectangular and decaying-triangle pulses: the max from a dense
    duhamel history and the first peak (time and height) from first_rebound against
    solve_ivp's located maxima."""
    w, m, F = TAU * 30.0, 0.05, 2.0
    T, k = TAU / w, m * w * w
    td = r * T
    if shape == "rect":
        p = impact.Pulse.rectangular(F, td)

        def force(t):
            return F if t < td else 0.0
    else:
        p = impact.Pulse.decaying(F, td)

        def force(t):
            return F * (1 - t / td) if t < td else 0.0

    _, tops, _ = ode_history(force, td + 3 * T, w, zeta, m, breaks=(td,))
    t, f = dense_table(p, td + 3 * T, T / 4000)
    q = impact.duhamel(t, f, omega_n=w, zeta=zeta, mass=m)
    exact_max = tops[:, 1].max()
    assert exact_max - 1e-6 * F / k <= q.max() <= exact_max * (1 + 1e-9)
    rb = impact.first_rebound(p.t, p.f, w, zeta, m)
    assert rb.time[0] == pytest.approx(tops[0, 0], rel=1e-8)
    assert rb.q[0] == pytest.approx(tops[0, 1], rel=1e-9)


# ---------------------------------------------------------------------------
# 4. The batch kernel


def _cases(b, seed=1):
    rng = np.random.default_rng(seed)
    t = np.sort(np.concatenate([[0.0], rng.uniform(0, 0.05, 300)]))
    forces = rng.normal(size=(b, t.size)).cumsum(axis=1)
    omega = TAU * rng.uniform(20, 400, b)
    zeta = rng.choice([0.0, 0.03, 0.5, 1.0, 2.5], b)
    mass = rng.uniform(0.01, 2.0, b)
    q0 = rng.normal(scale=1e-3, size=b)
    v0 = rng.normal(scale=0.1, size=b)
    return t, forces, omega, zeta, mass, q0, v0


@pytest.mark.parametrize("grid", ["random", "linspace"])
def test_batch_equals_single_rows_bit_for_bit(grid):
    # A sorted random grid goes case by case; a linspace grid (a jump at 0.01 s
    # inserted) in lockstep groups of cases, 19 = two groups and a remainder.
    t, forces, omega, zeta, mass, q0, v0 = _cases(9 if grid == "random" else 19)
    if grid == "linspace":
        t = np.sort(np.concatenate([np.linspace(0.0, 0.05, 300), [0.01]]))
    qb = impact.duhamel_batch(t, forces, omega, zeta, mass, q0, v0)
    assert qb.shape == forces.shape
    for i in range(forces.shape[0]):
        qi = impact.duhamel(
            t, forces[i], omega_n=omega[i], zeta=zeta[i], mass=mass[i], q0=q0[i], v0=v0[i]
        )
        assert_array_equal(qb[i], qi)


def test_batch_broadcasts_scalars_and_threads_agree():
    t, forces, omega, zeta, mass, q0, v0 = _cases(64, seed=2)
    b = forces.shape[0]
    scal = impact.duhamel_batch(t, forces, 300.0, 0.05, 0.2, 1e-3, -0.1)
    full = impact.duhamel_batch(
        t,
        forces,
        np.full(b, 300.0),
        np.full(b, 0.05),
        np.full(b, 0.2),
        np.full(b, 1e-3),
        np.full(b, -0.1),
    )
    assert_array_equal(scal, full)
    one = impact.duhamel_batch(t, forces, omega, zeta, mass, q0, v0, n_threads=1)
    two = impact.duhamel_batch(t, forces, omega, zeta, mass, q0, v0, n_threads=2)
    assert_array_equal(one, two)
    r1 = impact.first_rebound(t, forces, omega, zeta, mass, q0, v0, n_threads=1)
    r2 = impact.first_rebound(t, forces, omega, zeta, mass, q0, v0, n_threads=2)
    assert_array_equal(r1.time, r2.time)
    assert_array_equal(r1.q, r2.q)
    # and first_rebound's batch rows are its single cases
    for i in (0, 17, 63):
        ri = impact.first_rebound(t, forces[i], omega[i], zeta[i], mass[i], q0[i], v0[i])
        assert_array_equal(ri.q, r1.q[i : i + 1])
        assert_array_equal(ri.time, r1.time[i : i + 1])


# ---------------------------------------------------------------------------
# 5. first_rebound against dense histories


def first_turn(t, q, maximum):
    """Index of the first local extremum (maximum only if asked) of a dense history."""
    d = np.diff(q)
    turn = (
        np.flatnonzero((d[:-1] > 0) & (d[1:] <= 0))
        if maximum
        else np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))
    )
    return int(turn[0]) + 1


@FAST
@given(
    zeta=st.floats(0.0, 0.6),
    v0=st.floats(-1.0, -0.05),
    peak=st.floats(0.5, 20.0),
    r=st.floats(0.05, 1.5),
    shape=st.sampled_from(["decaying", "rectangular", "triangular", "half_sine"]),
)
def test_first_rebound_against_dense_history(zeta, v0, peak, r, shape):
    """A link arriving with v0 < 0, pressed by a positive pulse: the first turn is
    a minimum, the first maximum comes after it. Both from first_rebound against a
    dense duhamel history, to its sampling resolution."""
    w, m = TAU * 300.0, 0.0074
    T = TAU / w
    p = getattr(impact.Pulse, shape)(peak, r * T)
    dt = T / 4000
    t, f = dense_table(p, p.duration + 3 * T, dt)
    q = impact.duhamel(t, f, omega_n=w, zeta=zeta, mass=m, v0=v0)
    res = impact.first_rebound(p.t, p.f, w, zeta, m, 0.0, v0)
    res_max = impact.first_rebound(p.t, p.f, w, zeta, m, 0.0, v0, maximum=True)
    amp = np.abs(q).max()
    keep = np.diff(t, prepend=-1.0) > 0  # one sample per time for the turns
    t, q = t[keep], q[keep]
    for r_, mx in ((res, False), (res_max, True)):
        i = first_turn(t, q, mx)
        assert abs(r_.time[0] - t[i]) <= 1.01 * dt
        assert abs(r_.q[0] - q[i]) <= 1e-5 * amp
        assert np.isfinite(r_.time[0])
    assert res.q[0] < 0 < res_max.q[0]
    assert res.time[0] < res_max.time[0]
    # exact extrema: never beaten by the samples
    assert res.q[0] <= q[t <= res_max.time[0]].min() + 1e-12 * amp
    assert (
        res_max.q[0] >= q[(t >= res.time[0]) & (t <= res_max.time[0] + T / 4)].max() - 1e-12 * amp
    )


@pytest.mark.parametrize("zeta", [1.0, 2.0, 5.0])
def test_first_rebound_never_turns_under_constant_force(zeta):
    """Critically and over-damped creep from rest to F/k under a held force: no
    extremum, time = inf, q = the static deflection; the dense history is monotone."""
    w, m, F = 40.0, 0.5, 3.0
    t = np.array([0.0, 0.01])
    r = impact.first_rebound(t, [F, F], w, zeta, m)
    assert r.time[0] == math.inf
    assert r.q[0] == pytest.approx(F / (m * w * w), rel=1e-14)
    rm = impact.first_rebound(t, [F, F], w, zeta, m, maximum=True)
    assert rm.time[0] == math.inf and rm.q[0] == pytest.approx(F / (m * w * w), rel=1e-14)
    tt = np.linspace(0, 2.0, 4001)
    q = impact.duhamel(tt, np.full_like(tt, F), omega_n=w, zeta=zeta, mass=m)
    static = F / (m * w * w)
    assert (np.diff(q) >= -1e-14 * static).all()
    close(q, F * step(tt, w, zeta, m), 1e-9)
    assert (q <= static * (1 + 1e-12)).all()


def test_first_rebound_free_vibration_closed_form():
    """No force: the first extremum of e^{−ζωt}·(v0/ω_d)·sin ω_d t is at
    tan(ω_d t) = ω_d/(ζω)."""
    w, z, m, v0 = 100.0, 0.2, 1.0, 2.0
    wd = w * math.sqrt(1 - z * z)
    t_pk = math.atan2(wd, z * w) / wd
    r = impact.first_rebound([0.0], [0.0], w, z, m, v0=v0)
    assert r.time[0] == pytest.approx(t_pk, rel=1e-12)
    assert r.q[0] == pytest.approx(
        math.exp(-z * w * t_pk) * v0 / wd * math.sin(wd * t_pk), rel=1e-12
    )


# ---------------------------------------------------------------------------
# 6. The unilateral stop


def contact_ode(m, kf, ks, d, zf, zc, v0, t_end, contacts=3):
    """The stop by solve_ivp: free for x > 0 under −k_f(x + δ) − c_f·ẋ, in contact
    for x < 0 with −k_s·x − c_c·ẋ instead of the free damping, c = 2ζ√(k·m) with
    the regime's stiffness (k_f, k_f + k_s); x = 0 located as a terminal event."""
    cf = 2 * zf * math.sqrt(kf * m)
    cc = 2 * zc * math.sqrt((kf + ks) * m)

    def rhs(contact):
        def f(t, y):
            x, v = y
            if contact:
                return [v, (-kf * (x + d) - ks * x - cc * v) / m]
            return [v, (-kf * (x + d) - cf * v) / m]

        return f

    def cross(t, y):
        return y[0]

    def turn(t, y):
        return y[1]

    cross.terminal = True
    out = {k: [] for k in ("start", "end", "pen", "pen_t", "height", "height_t")}
    segs = []
    t0, y, contact = 0.0, np.array([0.0, v0]), True
    out["start"].append(0.0)
    while len(out["start"]) <= contacts:
        cross.direction = 1 if contact else -1
        turn.direction = 1 if contact else -1
        sol = solve_ivp(
            rhs(contact),
            (t0, t_end),
            y,
            method="DOP853",
            rtol=1e-12,
            atol=1e-18,
            events=[cross, turn],
            dense_output=True,
        )
        segs.append((t0, sol.t[-1], sol.sol))
        if len(sol.t_events[1]):
            key = "pen" if contact else "height"
            out[key].append(sol.y_events[1][0][0])
            out[key + "_t"].append(sol.t_events[1][0])
        if sol.status != 1:
            break
        t0 = sol.t_events[0][0]
        y = np.array([0.0, sol.y_events[0][0][1]])
        out["end" if contact else "start"].append(t0)
        contact = not contact
    return {k: np.array(v) for k, v in out.items()}, segs


CONTACT_CASES = [
    # mass, k_free, k_stop, preload, zeta_free, zeta_contact, v0
    (1.0, 1.0, 99.0, 0.3, 0.05, 0.1, -1.0),
    (1.0, 4.0, 60.0, 0.0, 0.0, 0.2, -0.5),
    (0.0074, 25788.0, 139255.0, 2.5e-5, 0.05, 0.184, -0.8),
    (2.0, 10.0, 500.0, 0.05, 0.3, 0.0, -2.0),
]


@pytest.mark.parametrize("case", CONTACT_CASES)
def test_contact_events_against_solve_ivp(case):
    """Contact start and end times, deepest points and rebound heights of the first
    contacts against solve_ivp with event location, to 1e-6 (relative)."""
    m, kf, ks, d, zf, zc, v0 = case
    T = TAU * math.sqrt(m / kf)
    ref, _ = contact_ode(m, kf, ks, d, zf, zc, v0, 8 * T)
    h = impact.contact_response(
        mass=m, k_free=kf, k_stop=ks, preload=d, zeta_free=zf, zeta_contact=zc, v0=v0, t_end=8 * T
    )
    n_end = min(len(ref["end"]), 3)
    assert n_end >= 1
    tol = dict(rel=1e-6, abs=1e-12 * T)
    assert h.contact_start[: len(ref["start"])] == pytest.approx(ref["start"][:4], **tol)
    assert h.contact_end[:n_end] == pytest.approx(ref["end"][:n_end], **tol)
    n_h = min(len(ref["height"]), 3)
    scale = abs(v0) * math.sqrt(m / kf)
    assert h.rebound_height[:n_h] == pytest.approx(ref["height"][:n_h], rel=1e-6, abs=1e-9 * scale)
    assert h.rebound_time[:n_h] == pytest.approx(ref["height_t"][:n_h], **tol)
    n_p = min(len(ref["pen"]), 3)
    assert h.penetration[:n_p] == pytest.approx(ref["pen"][:n_p], rel=1e-6)
    assert h.penetration_time[:n_p] == pytest.approx(ref["pen_t"][:n_p], **tol)
    assert h.impact_velocity[0] == v0
    assert_allclose(
        h.contact_duration, h.contact_end - h.contact_start[: h.contact_end.size], rtol=1e-12
    )


@pytest.mark.parametrize("case", CONTACT_CASES)
def test_contact_sample_against_solve_ivp(case):
    """x(t), ẋ(t) on a grid over the first contacts and flights, against the ODE."""
    m, kf, ks, d, zf, zc, v0 = case
    T = TAU * math.sqrt(m / kf)
    _, segs = contact_ode(m, kf, ks, d, zf, zc, v0, 3 * T)
    t = np.linspace(0.0, segs[-1][1], 1501)
    x_ref = np.empty_like(t)
    v_ref = np.empty_like(t)
    for a, b, sol in segs:
        sel = (t >= a) & (t <= b)
        x_ref[sel], v_ref[sel] = sol(t[sel])
    x, v = impact.contact_sample(
        t, mass=m, k_free=kf, k_stop=ks, preload=d, zeta_free=zf, zeta_contact=zc, v0=v0
    )
    close(x, x_ref, 1e-6)
    close(v, v_ref, 1e-6)


@FAST
@given(
    m=st.floats(0.01, 5.0),
    kf=st.floats(1.0, 1e4),
    ratio=st.floats(1.0, 200.0),
    d_rel=st.floats(0.0, 2.0),
    v0=st.floats(0.01, 5.0),
)
def test_undamped_contact_closed_forms(m, kf, ratio, d_rel, v0):
    """Undamped: the link leaves the stop at the speed it came (energy), after
    (2π − 2φ)/ω_c with tan φ = v0/(ω_c·|x_e|), x_e = −k_f·δ/(k_f + k_s) the
    in-contact equilibrium; then rises to −δ + √(δ² + (v0/ω_f)²)."""
    ks = ratio * kf
    wf, wc = math.sqrt(kf / m), math.sqrt((kf + ks) / m)
    d = d_rel * v0 / wf
    e = kf * d / (kf + ks)
    h = impact.contact_response(mass=m, k_free=kf, k_stop=ks, preload=d, v0=-v0, max_rebounds=1)
    phi = math.atan2(v0 / wc, e)
    assert h.contact_start[0] == 0.0
    assert h.contact_duration[0] == pytest.approx((TAU - 2 * phi) / wc, rel=1e-9)
    assert h.exit_velocity[0] == pytest.approx(v0, rel=1e-9)
    assert h.penetration[0] == pytest.approx(-e - math.hypot(e, v0 / wc), rel=1e-9)
    assert h.rebound_height[0] == pytest.approx(-d + math.hypot(d, v0 / wf), rel=1e-8)


# ---------------------------------------------------------------------------
# 7. Refusals


T5 = np.linspace(0.0, 1.0, 5)
Z5 = np.zeros(5)
OSC = dict(omega_n=10.0, zeta=0.1, mass=1.0)
CONTACT = dict(mass=1.0, k_free=1.0, k_stop=99.0, v0=-1.0)


@pytest.mark.parametrize(
    ("call", "pattern"),
    [
        (
            lambda: impact.duhamel([0, 1, 0.5], [0, 0, 0], **OSC),
            r"t.*non-decreasing.*t\[2\] = 0\.5",
        ),
        (lambda: impact.duhamel([0, 2, 1, 3], Z5[:4], **OSC), r"t\[2\] = 1"),
        (lambda: impact.duhamel([0, np.nan, 1], [0, 0, 0], **OSC), r"t\[1\].*finite.*NaN"),
        (lambda: impact.duhamel([0, 1, np.inf], [0, 0, 0], **OSC), r"t\[2\].*finite.*inf"),
        (lambda: impact.duhamel(T5, [0, 0, np.nan, 0, 0], **OSC), r"force\[2\].*finite.*NaN"),
        (lambda: impact.duhamel(T5, [0, -np.inf, 0, 0, 0], **OSC), r"force\[1\].*finite.*inf"),
        (lambda: impact.duhamel(T5, Z5[:4], **OSC), r"force.*5"),
        (lambda: impact.duhamel(T5, Z5, omega_n=1.0, zeta=0.0, mass=0.0), r"mass.*> 0.*0"),
        (lambda: impact.duhamel(T5, Z5, omega_n=1.0, zeta=0.0, mass=-2.0), r"mass.*-2"),
        (lambda: impact.duhamel(T5, Z5, omega_n=0.0, zeta=0.0, mass=1.0), r"omega_n.*> 0.*0"),
        (lambda: impact.duhamel(T5, Z5, omega_n=-3.0, zeta=0.0, mass=1.0), r"omega_n.*-3"),
        (lambda: impact.duhamel(T5, Z5, omega_n=1.0, zeta=-0.1, mass=1.0), r"zeta.*-0\.1"),
        (lambda: impact.duhamel(T5, Z5, omega_n=1.0, zeta=np.nan, mass=1.0), r"zeta.*NaN"),
        (lambda: impact.duhamel_batch(T5, np.zeros((2, 4)), 1.0, 0.0, 1.0), r"forces.*5.*4"),
        (lambda: impact.duhamel_batch(T5, Z5, 1.0, 0.0, 1.0), r"forces.*2-D"),
        (
            lambda: impact.duhamel_batch(T5, np.zeros((2, 5)), [1.0, 2.0, 3.0], 0.0, 1.0),
            r"omega_n.*\(2\).*3",
        ),
        (lambda: impact.duhamel_batch(T5, np.zeros((2, 5)), 1.0, 0.0, [1.0, 1.0, 1.0]), r"mass.*3"),
        (
            lambda: impact.duhamel_batch(T5, np.zeros((2, 5)), 1.0, [0.0, -1.0], 1.0),
            r"case 1.*zeta.*-1",
        ),
        (
            lambda: impact.duhamel_batch(T5[::-1], np.zeros((2, 5)), 1.0, 0.0, 1.0),
            r"non-decreasing",
        ),
        (lambda: impact.first_rebound(T5[::-1], Z5, 1.0, 0.0, 1.0), r"non-decreasing"),
        (lambda: impact.first_rebound(T5, Z5, 1.0, 0.0, 0.0), r"mass"),
        (lambda: impact.first_rebound(T5, np.zeros((3, 4)), 1.0, 0.0, 1.0), r"forces.*5"),
        (lambda: impact.StopImpact.example(restitution=1.5), r"restitution = 1\.5.*\[0, 1\]"),
        (lambda: impact.StopImpact.example(restitution=-0.1), r"restitution = -0\.1"),
        (lambda: impact.StopImpact.example(preload=9.4e-3), r"preload = 0\.0094.*stroke"),
        (lambda: impact.StopImpact.example(preload=0.02), r"preload = 0\.02.*stroke"),
        (lambda: impact.StopImpact.example(pulse="square"), r"pulse = 'square'"),
        (lambda: impact.StopImpact.example(model="fem"), r"model = 'fem'"),
        (lambda: impact.StopImpact.example().rebound(280, 0.0), r"phase_deg = 0\.0.*\(0, 360\]"),
        (lambda: impact.StopImpact.example().rebound(280, -10), r"phase_deg = -10"),
        (lambda: impact.StopImpact.example().rebound(280, [40, 361]), r"phase_deg = 361"),
        (lambda: impact.StopImpact.example().rebound(280, np.nan), r"phase_deg = nan"),
        (lambda: impact.StopImpact.example().linearize((0, 40), 280), r"phase_deg = 0"),
        (lambda: impact.StopImpact.example().rebound(0, 40), r"rpm.*0"),
        (lambda: impact.contact_response(**{**CONTACT, "k_free": 0.0}), r"k_free = 0\.0"),
        (lambda: impact.contact_response(**{**CONTACT, "k_stop": -5.0}), r"k_stop = -5\.0"),
        (lambda: impact.contact_response(**{**CONTACT, "mass": 0.0}), r"mass = 0\.0"),
        (lambda: impact.contact_sample([0.0, 1.0], **{**CONTACT, "k_stop": 0.0}), r"k_stop = 0\.0"),
        (
            lambda: impact.contact_response(**{**CONTACT, "zeta_contact": -0.2}),
            r"zeta_contact = -0\.2",
        ),
    ],
)
def test_refusals_name_the_field_and_value(call, pattern):
    with pytest.raises(cm.InputError, match=pattern) as info:
        call()
    assert isinstance(info.value, ValueError)


# ---------------------------------------------------------------------------
# 8. StopImpact


def pulse_model_rebound(lifter, rpm, phase):
    """The seed's pulse model from the closed forms: the free oscillator starts at
    the stop with −v0 under a decaying triangle of impulse m·(1 + k)·v0 over τ;
    the rebound is its first maximum (located by brentq on q̇ = 0)."""
    v0 = float(lifter.impact_speed(rpm, phase))
    m, w, z, tau = lifter.mass, lifter.omega_free, lifter.zeta, lifter.contact_time
    F0 = 2 * m * (1 + lifter.restitution) * v0 / tau

    def state(t):
        if t <= tau:
            q, v = ramp(t, F0, -F0 / tau, w, z, m, 0.0, -v0)
            return float(q), float(v)
        qe, ve = ramp(tau, F0, -F0 / tau, w, z, m, 0.0, -v0)
        q, v = free(t - tau, w, z, float(qe), float(ve))
        return float(q), float(v)

    T = TAU / w
    grid = np.linspace(0.0, 2 * T, 20001)
    v = np.array([state(t)[1] for t in grid])
    q = np.array([state(t)[0] for t in grid])
    i = int(np.flatnonzero((v[:-1] > 0) & (v[1:] <= 0) & (q[1:] > 0))[0])
    t_pk = brentq(lambda s: state(s)[1], grid[i], grid[i + 1], xtol=1e-16, rtol=1e-15)
    return state(t_pk)[0]


@pytest.mark.parametrize(("rpm", "phase"), [(177, 40.0), (280, 40.0), (420, 30.0), (420, 90.0)])
def test_pulse_model_rebound_against_closed_form(rpm, phase):
    lifter = impact.StopImpact.example()
    assert float(lifter.rebound(rpm, phase)) == pytest.approx(
        pulse_model_rebound(lifter, rpm, phase), rel=1e-9
    )


def test_example_lifter_rebound_of_the_seeds_order():
    """0.02–0.2 mm at 280–420 rpm and 40° (seed: 0.07 … 0.105 mm), growing with n."""
    lifter = impact.StopImpact.example()
    n = np.array([280.0, 320.0, 370.0, 420.0])
    a = lifter.rebound(n, 40.0)
    assert ((a > 0.02e-3) & (a < 0.2e-3)).all()
    assert (np.diff(a) > 0).all()
    assert_allclose(a * 1e3, [0.07, 0.078, 0.092, 0.105], rtol=0.05)  # the seed's values


@FAST
@given(
    rpm=st.floats(50.0, 1500.0),
    phase=st.floats(1.0, 300.0),
    up=st.floats(1.001, 1.2),
    model=st.sampled_from(["pulse", "contact"]),
)
def test_rebound_monotone_in_speed_and_phase(rpm, phase, up, model):
    """Faster shaft ⇒ larger rebound; longer phase angle ⇒ smaller (strictly for
    the pulse model, non-strictly where the contact model's rebound is zero)."""
    lifter = impact.StopImpact.example(model=model)
    a = float(lifter.rebound(rpm, phase))
    faster = float(lifter.rebound(rpm * up, phase))
    longer = float(lifter.rebound(rpm, phase * up))
    if model == "pulse":
        assert faster > a > longer > 0
    else:
        assert faster >= a >= longer >= 0
        if a > 0:
            assert faster > a
        if longer > 0:
            assert a > longer


@FAST
@given(rpm=st.floats(50.0, 1500.0), phase=st.floats(1.0, 360.0), c=st.floats(0.1, 10.0))
def test_pulse_rebound_is_proportional_to_speed(rpm, phase, c):
    """The pulse model is linear in v0 ∝ n/t: a(c·n, t) = c·a(n, t) and
    a(n, t)·t constant."""
    lifter = impact.StopImpact.example()
    a = float(lifter.rebound(rpm, phase))
    assert float(lifter.rebound(rpm * c, phase)) == pytest.approx(c * a, rel=1e-10)
    ratio = a / float(lifter.impact_speed(rpm, phase))
    assert float(lifter.rebound(rpm, 40.0)) / float(
        lifter.impact_speed(rpm, 40.0)
    ) == pytest.approx(ratio, rel=1e-10)


@FAST
@given(
    v0=st.floats(1e-6, 1e3),
    zeta=st.floats(0.0, 0.9),
    tau=st.floats(1e-5, 5e-3),
    pulse=st.sampled_from(["decaying", "rectangular", "triangular", "half_sine"]),
)
def test_pulse_rebound_scaled_from_one_meter_per_second_is_the_solve_at_v0(v0, zeta, tau, pulse):
    """rebounds takes a pulse-model stop's rebound as g·v0 (g: its rebound at 1 m/s,
    the model being linear in v0). Independent: the first maximum solved at v0
    itself, the pulse's impulse m·(1 + k)·v0, from q = 0, q̇ = −v0. The two differ
    by rounding only, but a short pulse (ω·τ ≈ 0.02 at τ = 1e-5 s) loses ~(ω·τ)⁻²
    ulps in the step coefficients' cancellation: up to 5.6e-12 relative over this
    range (measured on 3000 random cases), hence 1e-10."""
    s = impact.StopImpact.example(zeta=zeta, contact_time=tau, pulse=pulse)
    got = float(impact.rebounds([s], [[v0]])[0, 0])
    p = s._shape()
    impulse = s.mass * (1.0 + s.restitution) * v0
    want = impact.first_rebound(
        p.t, impulse * p.f, s.omega_free, s.zeta, s.mass, 0.0, -v0, maximum=True
    ).q
    assert got == pytest.approx(float(np.ravel(want)[0]), rel=1e-10, abs=0.0)


@FAST
@given(rpm=st.floats(100.0, 1000.0), a_max_mm=st.floats(0.02, 0.5))
def test_min_phase_angle_is_consistent_with_rebound(rpm, a_max_mm):
    """rebound(t_min) ≈ a_max, above it just below t_min, below it just above; as
    the pulse model is ∝ 1/t, t_min = 40°·a(n, 40°)/a_max exactly."""
    lifter = impact.StopImpact.example()
    a_max = a_max_mm * 1e-3
    t_min = float(lifter.min_phase_angle(a_max, rpm))
    expected = 40.0 * float(lifter.rebound(rpm, 40.0)) / a_max
    if expected > 360.0:
        assert math.isnan(t_min)
        assert float(lifter.rebound(rpm, 360.0)) > a_max
        return
    assert t_min == pytest.approx(expected, rel=1e-9)
    assert float(lifter.rebound(rpm, t_min)) == pytest.approx(a_max, rel=1e-9)
    assert float(lifter.rebound(rpm, t_min)) <= a_max
    assert float(lifter.rebound(rpm, t_min * (1 - 1e-6))) > a_max


@FAST
@given(rpm=st.floats(600.0, 5000.0), a_max_mm=st.floats(0.002, 0.2))
def test_min_phase_angle_of_the_contact_model_is_consistent_with_rebound(rpm, a_max_mm):
    """The contact model's rebound is not proportional to the impact speed (the
    preload holds the lever up to a speed), so t_min comes from the search alone:
    rebound(t_min) ≤ a_max, and above it 1e-9 relative below t_min."""
    lifter = impact.StopImpact.example(model="contact")
    a_max = a_max_mm * 1e-3
    t_min = float(lifter.min_phase_angle(a_max, rpm))
    if math.isnan(t_min):
        assert float(lifter.rebound(rpm, 360.0)) > a_max
        return
    assert float(lifter.rebound(rpm, t_min)) <= a_max
    if t_min > 1e-9:
        assert float(lifter.rebound(rpm, t_min * (1 - 1e-9))) > a_max


@pytest.mark.parametrize("a_max", [1e-9, 1e-6, 1e-4, 1e-2])
def test_max_impact_speed_of_the_pulse_model_is_a_max_over_the_rebound_per_speed(a_max):
    """The pulse model is linear in the impact speed v0 (the lever starts at v0 and
    the pulse's impulse is ∝ v0), so v* = a_max·v0/rebound(v0) for any v0."""
    lifter = impact.StopImpact.example()
    v0 = float(lifter.impact_speed(300.0, 40.0))
    g = float(lifter.rebound(300.0, 40.0)) / v0
    assert lifter.max_impact_speed(a_max) == pytest.approx(a_max / g, rel=1e-11)


def _mixed_stops() -> list[impact.StopImpact]:
    """Stops in three pulse tables (two shapes, two contact times) and the contact
    model, in an interleaved order."""
    ex = impact.StopImpact.example
    return [
        ex(),
        ex(model="contact"),
        ex(zeta=0.2),
        ex(pulse="half_sine"),
        ex(contact_time=1e-3),
        ex(preload=1e-4, model="contact"),
        ex(preload=1e-4),
        ex(pulse="half_sine", zeta=0.01),
    ]


def test_rebounds_of_many_stops_are_each_stops_rebound():
    """One call over stops of different pulse tables and models gives, bit for
    bit, what each stop's own rebound gives."""
    stops = _mixed_stops()
    v0 = np.linspace(0.05, 0.5, 24).reshape(len(stops), 3)
    got = impact.rebounds(stops, v0)
    for s, v, g in zip(stops, v0, got, strict=True):
        t = 40.0
        rpm = v * np.radians(t) / (2 * np.pi / 60 * s.stroke * s.dz_contact)
        np.testing.assert_allclose(g, s.rebound(rpm, t), rtol=1e-13)
        assert np.array_equal(g, impact.rebounds([s], v[None, :])[0])


def test_max_impact_speeds_together_are_each_alone():
    """The search over many stops at once (each step one call for all) gives each
    stop's own largest admissible impact speed bit for bit, and each is admissible."""
    stops = _mixed_stops()
    a_max = np.array([1e-4, 2e-5, 1e-4, 5e-5, 1e-4, 3e-5, 2e-4, 1e-4])
    together = impact.max_impact_speeds(stops, a_max)
    fresh = _mixed_stops()  # no remembered results
    alone = [float(impact.max_impact_speeds([s], a)[0]) for s, a in zip(fresh, a_max, strict=True)]
    assert together.tolist() == alone
    at = impact.rebounds(stops, together[:, None])[:, 0]
    assert (at <= a_max).all()
    above = impact.rebounds(stops, together[:, None] * (1 + 1e-9))[:, 0]
    assert (above > a_max).all()


def test_min_phase_angle_nan_where_impossible_and_arrays():
    lifter = impact.StopImpact.example()
    t = lifter.min_phase_angle(0.1e-3, [280.0, 420.0, 1e5])
    assert t.shape == (3,)
    assert math.isnan(t[2]) and float(lifter.rebound(1e5, 360.0)) > 0.1e-3
    assert t[0] < t[1]
    assert math.isnan(float(lifter.min_phase_angle(1e-9, 280.0)))
    with pytest.raises(cm.InfeasibleError):
        lifter.constraint(("3", "7"), 1e-9, 280.0)


def _cyclogram():
    cg = cm.Cyclogram()
    cg.add_operation("1", "3", min_angle_deg=40, mechanism="lifter")
    cg.add_operation("3", "7", min_angle_deg=20, mechanism="lifter")
    cg.add_operation("7", "9", min_angle_deg=30, mechanism="lifter")
    return cg


@pytest.mark.parametrize("rpm", [280.0, 420.0])
def test_constraint_binds_in_the_cyclogram(rpm):
    """The exact constraint t(3,7) ≥ t_min, accepted by add_constraint, lifts the
    operation from its 20° minimum to the rebound bound at the optimum."""
    lifter = impact.StopImpact.example()
    c = lifter.constraint(("3", "7"), 0.1e-3, rpm)
    assert isinstance(c, cm.Constraint)
    t_min = float(lifter.min_phase_angle(0.1e-3, rpm))
    assert t_min > 20.0
    cg = _cyclogram()
    cg.add_constraint(c)
    opt = cg.optimize()
    assert opt.angles[("3", "7")] == pytest.approx(t_min, abs=1e-7)
    assert opt.objective == pytest.approx(70.0 + t_min, abs=1e-7)
    assert c.name in opt.binding
    assert float(lifter.rebound(rpm, opt.angles[("3", "7")])) == pytest.approx(0.1e-3, rel=1e-6)


def test_linear_constraint_binds_at_the_linearised_bound():
    """The seed's form slope·t + intercept ≤ a_max: the optimum sits where the line
    meets a_max; the rebound there is within 20 % of a_max (a line fitted over
    0.5…2 times the exact bound to the convex a ∝ 1/t errs on the safe side)."""
    lifter = impact.StopImpact.example()
    rpm, a_max = 420.0, 0.1e-3
    c = lifter.constraint(("3", "7"), a_max, rpm, linear=True)
    ((arc, slope),) = c.coeffs
    assert arc == ("3", "7") and slope < 0 and c.sense == "<="
    cg = _cyclogram()
    cg.add_constraint(c)
    t = cg.optimize().angles[("3", "7")]
    assert slope * t == pytest.approx(c.rhs, rel=1e-9)
    assert 0.8 * a_max < float(lifter.rebound(rpm, t)) <= a_max


def test_linearize_slope_and_the_seed():
    """Negative slope; over 30–45° at 420 rpm the seed's −0.003·t + 0.208 (mm, deg)
    in order; the line within 5 % of the rebound inside its range."""
    lifter = impact.StopImpact.example()
    slope, intercept = lifter.linearize((30.0, 45.0), 420.0)
    assert slope < 0
    assert slope * 1e3 == pytest.approx(-0.003, rel=0.2)
    assert intercept * 1e3 == pytest.approx(0.208, rel=0.2)
    t = np.linspace(30.0, 45.0, 31)
    assert_allclose(slope * t + intercept, lifter.rebound(420.0, t), rtol=0.05)
    # convex a ∝ 1/t: the chord-like fit lies below at the ends and above inside
    a = lifter.rebound(420.0, np.array([30.0, 37.5, 45.0]))
    line = slope * np.array([30.0, 37.5, 45.0]) + intercept
    assert line[0] < a[0] and line[1] > a[1] and line[2] < a[2]


def test_contact_model_grows_with_speed():
    """model='contact' solves the stop as a unilateral contact: its rebound grows
    with speed where the link leaves the stop."""
    contact = impact.StopImpact.example(model="contact")
    a = contact.rebound(np.array([280.0, 320.0, 370.0, 420.0]), 10.0)
    assert (a > 0).all() and (np.diff(a) > 0).all()


def test_contact_model_holds_the_preloaded_lever_as_the_readme_says():
    """The README's comparison: with the 0.25 mm preload the contact model keeps
    the example lifter on its stop at 280–420 rpm (40°), where the pulse model
    gives 0.07–0.105 mm; it rebounds only at much higher speed, and earlier with
    less preload. (In contact the link oscillates about x_c = −k_f·δ/k_c; the
    damped swing must carry it back past x = 0, which takes a large enough v0.)"""
    lifter = impact.StopImpact.example(model="contact")
    n = np.array([280.0, 320.0, 370.0, 420.0])
    assert (lifter.rebound(n, 40.0) == 0.0).all()
    assert (impact.StopImpact.example().rebound(n, 40.0) > 0.06e-3).all()
    high = lifter.rebound(np.array([800.0, 1500.0]), 40.0)
    assert 0.005e-3 < high[0] < high[1] < 0.2e-3
    # Less preload, earlier rebounds.
    soft = impact.StopImpact.example(model="contact", preload=0.05e-3).rebound(420.0, 40.0)
    assert soft > 0.0
