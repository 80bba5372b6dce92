"""The main shaft's forward dynamics against an independent reference: a
slider-crank with a flywheel and an induction motor whose equation of motion is
derived here from its Lagrangian with sympy and integrated with scipy's
``solve_ivp`` (rtol 1e-11). cyclomech only sees the sampled J(φ), J′(φ) and
Q(φ)."""

import functools
import itertools
import math

import cyclomech as cm
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq
from scipy.signal import argrelmax

R, L, M_S, M_R, J_C, F0, Q0 = 0.08, 0.3, 6.0, 2.0, 0.02, 300.0, 25.0
N = 3600


@functools.cache
def _lagrangian():
    """(J(φ), J′(φ), Q(φ)) as numpy functions and the right-hand side φ̈(φ, ω, M)
    from the Lagrangian of the slider-crank (uniform rod, slider load F0 while it
    moves, a constant process torque Q0 on the crank). Derived when a test first
    asks (4 CPU-s of sympy), not when the file is collected: every xdist worker
    collects every file, and one runs it."""
    t = sp.symbols("t")
    phi = sp.Function("phi")(t)
    x = R * sp.cos(phi) + sp.sqrt(L**2 - R**2 * sp.sin(phi) ** 2)
    beta = sp.asin(R * sp.sin(phi) / L)
    gx, gy = (R * sp.cos(phi) + x) / 2, R * sp.sin(phi) / 2
    v2 = lambda e: sp.diff(e, t) ** 2  # noqa: E731
    kin = sp.Rational(1, 2) * (
        J_C * v2(phi) + M_S * v2(x) + M_R * (v2(gx) + v2(gy)) + M_R * L**2 / 12 * v2(beta)
    )
    # Generalised force of the loads on φ: the slider's F0·(−ẋ)·sign — take a smooth
    # load F0·(1 + cos φ)/2 pushing against +x, and the process torque Q0.
    p, w, a, m = sp.symbols("p w a m")
    load = Q0 + F0 * (1 + sp.cos(phi)) / 2 * sp.diff(x, phi)
    eq = sp.diff(sp.diff(kin, sp.diff(phi, t)), t) - sp.diff(kin, phi) - (m - load)
    sub = {sp.diff(phi, t, 2): a, sp.diff(phi, t): w}
    eq = eq.subs(sub).subs(phi, p)
    acc = sp.solve(eq, a)[0]
    jj = sp.simplify(2 * kin.subs(sp.diff(phi, t), 1).subs(phi, p))
    f = lambda e: sp.lambdify(p, e, "numpy")  # noqa: E731
    return f(jj), f(sp.diff(jj, p)), f(load.subs(phi, p)), sp.lambdify((p, w, m), acc, "numpy")


def J_OF(p):
    return _lagrangian()[0](p)


def DJ_OF(p):
    return _lagrangian()[1](p)


def Q_OF(p):
    return _lagrangian()[2](p)


def ACC(p, w, m):
    return _lagrangian()[3](p, w, m)


PHI = 2 * np.pi * np.arange(N) / N


def _machine():
    return cm.dynamics.Reduced.from_curves(
        J_OF(PHI) * np.ones(N), DJ_OF(PHI) * np.ones(N), Q_OF(PHI) * np.ones(N), nominal_rpm=100.0
    )


MOTOR = cm.dynamics.InductionMotor(
    1440.0, 1500.0, 2.3, rated_power_w=1500.0, ratio=15.0, efficiency=0.9, rotor_kg_m2=2e-3
)
FLYWHEEL = 1.5


def _shaft_torque(w):
    """The motor's torque on the shaft, written here from Kloss's formula."""
    ws = 1500 * math.pi / 30
    mn = 1500.0 / (1440 * math.pi / 30)
    sn = 60 / 1500
    sk = sn * (2.3 + math.sqrt(2.3**2 - 1))
    s = (ws - 15 * w) / ws
    mm = 2 * 2.3 * mn / (s / sk + sk / s)
    return 15 * (0.9 if mm >= 0 else 1 / 0.9) * mm


def _rhs_for(torque, extra):
    """The Lagrangian's φ̈ (for J without the constant inertias) with the constant
    inertia ``extra`` added: J_bare·φ̈_bare = rest ⇒ (J_bare + extra)·φ̈ = rest."""

    def rhs(_t, y):
        p, w = y
        j = J_OF(p)
        return [w, ACC(p, w, torque(w)) * j / (j + extra)]

    return rhs


_rhs = _rhs_for(_shaft_torque, FLYWHEEL + 15**2 * 2e-3)


def test_the_steady_state_is_the_lagrangian_one_and_one_more_cycle_returns_to_it():
    d = _machine()
    s = cm.dynamics.steady_state(d, MOTOR, flywheel_kg_m2=FLYWHEEL, tol=1e-13)
    assert s.residual <= 1e-13
    w0 = s.omega[0]
    sol = solve_ivp(
        _rhs,
        (0, s.period_s * 1.0000001),
        [0.0, w0],
        rtol=1e-11,
        atol=1e-12,
        dense_output=True,
        method="DOP853",
    )
    p, w = sol.sol(s.time_s)
    assert np.max(np.abs(p - PHI)) < 1e-8
    assert np.max(np.abs(w - s.omega)) / np.mean(s.omega) < 1e-8
    # One more cycle from the steady state returns to it (solve_ivp's own period).
    p_end, w_end = sol.sol(s.period_s)
    assert abs(p_end - 2 * np.pi) < 1e-8
    assert abs(w_end - w0) / w0 < 1e-8
    # The real δ and mean speed, from solve_ivp's solution.
    ww = sol.sol(np.linspace(0, s.period_s, 20001))[1]
    mean = 2 * np.pi / s.period_s
    assert abs((ww.max() - ww.min()) / mean - s.speed_fluctuation) < 1e-6


def test_the_start_up_is_the_lagrangian_one():
    d = _machine()
    s = cm.dynamics.start_up(d, MOTOR, flywheel_kg_m2=FLYWHEEL, rtol=1e-11, settle=1e-3)
    assert math.isfinite(s.settle_time_s) and s.settle_time_s > 0
    sol = solve_ivp(
        _rhs,
        (0, s.time_s[-1]),
        [0.0, 0.0],
        rtol=1e-11,
        atol=1e-12,
        dense_output=True,
        method="DOP853",
    )
    p, w = sol.sol(s.time_s)
    scale = s.steady.mean_rpm * math.pi / 30
    assert np.max(np.abs(w - s.omega)) / scale < 1e-8
    assert np.max(np.abs(p - s.phi_rad)) < 1e-7
    # It ends near the steady state, as it says.
    end = np.interp(s.phi_rad[-1] % (2 * np.pi), PHI, s.steady.omega, period=2 * np.pi)
    assert abs(s.omega[-1] - end) <= 1e-3 * scale
    # Its settle time: the last time solve_ivp's speed leaves the band around the
    # steady state (sampled densely, then the crossing by brentq on its dense
    # output). It was the end of the step the crossing fell in (off by up to a
    # step: 1.160-1.190 s for the loom as rtol went 1e-8-1e-11); now the crossing.
    tt = np.linspace(0, s.time_s[-1], 400_001)
    pp, ww = sol.sol(tt)
    ss = np.interp(pp % (2 * np.pi), PHI, s.steady.omega, period=2 * np.pi)
    i = np.flatnonzero(np.abs(ww - ss) > 1e-3 * scale).max()

    def excess(t: float) -> float:
        p_, w_ = sol.sol(t)
        return abs(w_ - np.interp(p_ % (2 * np.pi), PHI, s.steady.omega, period=2 * np.pi)) - (
            1e-3 * scale
        )

    last = brentq(excess, tt[i], tt[i + 1], xtol=1e-14)
    step = np.max(np.diff(s.time_s))
    assert abs(last - s.settle_time_s) <= 1e-6 * s.settle_time_s, (last, s.settle_time_s)
    assert step > 1e4 * abs(last - s.settle_time_s)  # within a step: was up to one step off


@pytest.mark.parametrize("settle", [0.1, 1e-3])
@pytest.mark.parametrize("rtol", [1e-7, 1e-10])
def test_the_settle_time_is_the_crossing_not_a_step_end(settle: float, rtol: float) -> None:
    """A linear motor (stall torque M, no-load speed ω0) on a constant inertia J
    with no load: ω = ω0·(1 − e^(−t/τ)), τ = J·ω0/M, so the speed enters the band
    settle·ω0 for good at τ·ln(1/settle), whatever the integrator's steps (before,
    the end of the step it fell in: 43.3 s for 43.40). The speed's own error, up to
    about rtol·ω0, moves the crossing by τ·rtol/settle (measured ≤ 50 of those)."""
    d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.zeros(8), nominal_rpm=100.0)
    s = cm.dynamics.start_up(d, cm.dynamics.LinearMotor(10.0, 600.0), settle=settle, rtol=rtol)
    tau = 1.0 * (600.0 * math.pi / 30) / 10.0
    want = tau * math.log(1 / settle)
    assert abs(s.settle_time_s - want) <= 100 * tau * rtol / settle, (s.settle_time_s, want)
    assert np.max(np.diff(s.time_s)) > 1e3 * abs(s.settle_time_s - want)  # steps are coarse


def test_the_simulated_flywheel_tends_to_the_energy_methods_as_delta_falls():
    d = _machine()
    # A soft DC motor: it barely steadies the speed itself.
    motor = cm.dynamics.LinearMotor(20.0, 3000.0, ratio=15.0)
    errs = []
    for delta in (0.1, 0.01, 0.001):
        f = cm.dynamics.size_flywheel(d, motor, delta)
        assert f.steady.speed_fluctuation == pytest.approx(delta, rel=1e-7)
        assert f.difference == pytest.approx(
            (f.flywheel_kg_m2 - f.energy_method_kg_m2) / f.energy_method_kg_m2, rel=1e-12
        )
        errs.append(abs(f.flywheel_kg_m2 / f.energy_method_kg_m2 - 1))
        if delta == 0.1:
            # At δ = 0.1 the two differ by half (the motor's slope and the mechanism's
            # own inertia steady the speed too); solve_ivp checks the simulated one.
            rhs = _rhs_for(lambda w: 300.0 * (1 - 15 * w / (100 * np.pi)), f.flywheel_kg_m2)
            sol = solve_ivp(
                rhs,
                (0, f.steady.period_s),
                [0.0, f.steady.omega[0]],
                rtol=1e-11,
                atol=1e-12,
                dense_output=True,
                method="DOP853",
            )
            ww = sol.sol(np.linspace(0, f.steady.period_s, 40001))[1]
            real = (ww.max() - ww.min()) / (2 * np.pi / f.steady.period_s)
            assert real == pytest.approx(0.1, rel=1e-6)
            assert f.difference == pytest.approx(-0.5, abs=0.1)
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 0.01


def test_a_stiff_motor_needs_no_flywheel_and_says_so():
    # The induction motor through a 15:1 gear holds δ < 0.01 alone: no flywheel.
    f = cm.dynamics.size_flywheel(_machine(), MOTOR, 0.05)
    assert f.flywheel_kg_m2 == 0.0
    assert f.steady.speed_fluctuation < 0.05
    assert f.difference == -1.0


def test_the_steady_states_error_falls_as_the_fourth_power_of_the_step():
    # RK4 on the samples with step 2·360°/N, the odd samples by cubic Hermite:
    # halving the step divides the error by ~16 (against solve_ivp at rtol 1e-12).
    errs = []
    for n in (900, 1800, 3600):
        p = 2 * np.pi * np.arange(n) / n
        d = cm.dynamics.Reduced.from_curves(
            J_OF(p) * np.ones(n), DJ_OF(p) * np.ones(n), Q_OF(p) * np.ones(n), nominal_rpm=100.0
        )
        s = cm.dynamics.steady_state(d, MOTOR, flywheel_kg_m2=FLYWHEEL, tol=1e-13)
        sol = solve_ivp(
            _rhs,
            (0, s.period_s * 1.0000001),
            [0.0, s.omega[0]],
            rtol=1e-12,
            atol=1e-13,
            dense_output=True,
            method="DOP853",
        )
        errs.append(np.max(np.abs(sol.sol(s.time_s)[1] - s.omega)) / np.mean(s.omega))
    assert errs[0] / errs[1] > 12 and errs[1] / errs[2] > 12
    assert errs[2] < 1e-10


def _rippled_start_up():
    """A machine whose start-up approaches its steady state in ripples: J = 1 +
    0.3·sin φ (J′ = 0.3·cos φ), no load, a linear motor (stall 100 N·m, no load
    600 rpm). The term ½J′ω² (≈ 18·ω̄ δω) dwarfs the motor's slope (1.6 N·m·s), so
    |ω − ω_ss(φ)| peaks once a turn and the peaks decay by ≈ 0.85 a turn; the
    steady speed itself fluctuates by δ = 0.32. Returns the machine, the motor and
    the right-hand side, written here from J φ̈ = M(ω) − ½J′ω²."""
    n, a, m0, n0 = 3600, 0.3, 100.0, 600.0
    phi = 2 * np.pi * np.arange(n) / n
    d = cm.dynamics.Reduced.from_curves(
        1 + a * np.sin(phi), a * np.cos(phi), np.zeros(n), nominal_rpm=100.0
    )
    w0 = n0 * math.pi / 30

    def rhs(_t, y):
        p, w = y
        return [w, (m0 * (1 - w / w0) - 0.5 * a * math.cos(p) * w * w) / (1 + a * math.sin(p))]

    return d, cm.dynamics.LinearMotor(m0, n0), rhs


def test_a_rippled_start_up_settles_at_the_last_crossing_and_a_bare_touch_is_the_rule():
    """The ambiguous case of the settle time's rule (the last crossing into the
    band settle·ω̄, ω̄ = 2π/T the steady state's time mean): where the deviation's
    peaks decay through the band, the settle time is the crossing on the falling
    side of the last peak above it. Reference: ``solve_ivp`` (DOP853, rtol 1e-11)
    with its dense output, the steady state by a periodic cubic spline of its
    samples, each crossing by ``brentq``.

    - A band between two peaks: the crossing after the higher, to 1e-8.
    - A band a fraction δ below a peak (a bare touch): while the excursion above
      the band spans an eighth of the step it falls in, that crossing (to 1e-6);
      narrower, either it or the crossing after the peak before — one turn earlier,
      never anything else — and, the integrator's steps being the same whatever the
      band, once missed it stays missed as δ shrinks.
    - A band just above a peak: the crossing after the peak before.
    Before, the band was relative to the angle mean of ω (1.2 % wide here) and
    the deviation read on a cubic Hermite interpolant of each step (1e-7 of ω̄ off
    between the steps' ends): the band between two peaks gave 4e-4 off, and a
    touch 1e-5 below a peak was read as the crossing a turn earlier."""
    d, motor, rhs = _rippled_start_up()
    s = cm.dynamics.start_up(d, motor, settle=1e-2, rtol=1e-10)
    t_end = s.time_s[-1]
    sol = solve_ivp(
        rhs, (0, t_end), [0.0, 0.0], rtol=1e-11, atol=1e-12, dense_output=True, method="DOP853"
    )
    scale = s.steady.mean_rpm * math.pi / 30
    knots = 2 * np.pi * np.arange(s.steady.omega.size + 1) / s.steady.omega.size
    wss = CubicSpline(knots, np.append(s.steady.omega, s.steady.omega[0]), bc_type="periodic")

    def dev(t):
        p, w = sol.sol(t)
        return np.abs(w - wss(p % (2 * np.pi))) / scale

    tt = np.linspace(0.5 * t_end, t_end, 100_001)
    dv = dev(tt)
    peaks = [(tt[i], dv[i]) for i in argrelmax(dv)[0]]
    assert len(peaks) >= 6
    assert all(b[1] < 0.9 * a[1] for a, b in itertools.pairwise(peaks))  # decaying ripples
    (t_prev, _), (t_k, h_k), (t_next, h_next) = peaks[-5:-2]

    def crossing(t_peak: float, band: float, t_after: float) -> float:
        g = np.linspace(t_peak, t_after, 20_001)
        j = np.flatnonzero(dev(g) < band)[0]
        return brentq(lambda t: dev(t) - band, g[j - 1], g[j], xtol=1e-14)

    def width(band: float) -> float:
        g = np.linspace(t_prev, t_next, 200_001)
        above = g[dev(g) > band]
        return float(np.ptp(above[above > 0.5 * (t_prev + t_k)]))

    def settle(band: float) -> tuple[float, float]:
        r = cm.dynamics.start_up(d, motor, settle=band, rtol=1e-10)
        i = np.searchsorted(r.time_s, t_k)
        return r.settle_time_s, r.time_s[i] - r.time_s[i - 1]

    band = math.sqrt(h_k * h_next)
    got, _ = settle(band)
    assert abs(got - crossing(t_k, band, t_next)) <= 1e-8 * got
    missed = False
    for delta in [1e-2, 1e-4, 1e-6, 1e-7, 1e-8, 1e-10]:
        band = h_k * (1 - delta)
        got, step = settle(band)
        on_k, on_prev = crossing(t_k, band, t_next), crossing(t_prev, band, t_k)
        if abs(got - on_prev) <= 1e-8 * got:
            assert width(band) < step / 8, (delta, width(band), step)
            missed = True
        else:
            assert not missed, delta  # once missed, missed for every smaller δ
            assert abs(got - on_k) <= 1e-6 * got, (delta, got, on_k)
    assert missed  # both sides of the rule are met (here from δ = 1e-8 on)
    band = h_k * (1 + 1e-6)
    got, _ = settle(band)
    assert abs(got - crossing(t_prev, band, t_k)) <= 1e-8 * got
