"""Rotor transfer (seed 002, :mod:`cyclomech.transfer`) against independent references.

* The quintic's six end conditions evaluated with ``numpy.polynomial.Polynomial``
  and its ``.deriv()`` (not the module's Horner code), and its a3 … a5 against the
  3×3 system of the seed solved by ``numpy.linalg.solve``.
* The smooth transition against the closed form y'' = (1 − 3s² + 2s³)/R and its
  double integral by ``Polynomial.integ``.
* Curvature against the circle through three neighbouring points of the graph;
  its rate against finite differences over arc lengths from ``scipy.integrate.quad``;
  arc length against ``quad``.
* The change of frame against the seed's formula element by element with ``math``,
  and curvature of the transformed curve by finite differences.
* The composed path against plane geometry (circle radii, perpendicular tangents,
  the internal common tangent of the two widened circles in closed form, found with
  ``scipy.optimize.brentq`` when it shrinks to a point), against finite differences
  of its own sample (chords, headings), and against mirrored / rotated copies.
* Accelerations and jerk against a numerical motion: s(t) from ``solve_ivp``,
  r(s) from a quintic spline of the sampled points, and central differences in time.
* The jump against hand values; the design against the full path sampler.
"""

from __future__ import annotations

import functools
import math
import re

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import transfer as tr
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.polynomial import Polynomial
from numpy.testing import assert_allclose, assert_array_equal
from scipy.integrate import quad, solve_ivp
from scipy.interpolate import make_interp_spline
from scipy.optimize import brentq

FAST = settings(max_examples=60, deadline=None)
SLOW = settings(max_examples=20, deadline=None)

# The issue's geometry: rotors of 0.15 m and 0.25 m pitch radius, 10 mm apart.
R_T, R_P, GAP = 0.15, 0.25, 0.01
C_T, C_P = (0.0, 0.0), (R_T + R_P + GAP, 0.0)
V = 2 * math.pi * 0.15 / 6  # 60 workpieces/min at a pitch of 2π·0.15/6 m


@functools.cache
def path(x2: float | None = 0.05, ccw: bool = True) -> tr.TransferPath:
    return tr.TransferPath(R_T, R_P, C_T, C_P, x2=x2, ccw=ccw)


@functools.cache
def sample(n: int, x2: float | None = 0.05, ccw: bool = True) -> tr.PathSample:
    return path(x2, ccw).sample(n)


def poly(q: tr.QuinticTransition) -> Polynomial:
    return Polynomial(q.coeffs)


def quad_length(q: tr.QuinticTransition, lo: float, hi: float) -> float:
    """∫ √(1 + y'²) dx by adaptive quadrature on numpy's derivative."""
    d1 = poly(q).deriv()
    return quad(lambda x: math.sqrt(1.0 + d1(x) ** 2), lo, hi, epsabs=0.0, epsrel=1e-13)[0]


def smooth_k_b(R: float, x2: float) -> tuple[float, float]:
    """k and b of the smooth transition, from integrating y'' = (1 − 3s² + 2s³)/R
    by hand: y'(x2) = x2/(2R), y(x2) = 0.35·x2²/R, b = y(x2) − k·x2."""
    return x2 / (2 * R), 0.35 * x2**2 / R - x2**2 / (2 * R)


def straight_closed_form(R_t: float, R_p: float, d: float, x2_t: float, x2_p: float) -> float:
    """The straight segment's length by plane geometry. Each transition leaves its
    line at distance δ = (R − b)/√(1 + k²) from the centre, B lying e =
    (B − F)·u beyond the foot F of that perpendicular; the feet of the internal
    common tangent of circles δ_t, δ_p whose centres are d apart are
    √(d² − (δ_t + δ_p)²) apart."""
    delta, beyond = [], []
    for R, x2 in ((R_t, x2_t), (R_p, x2_p)):
        k, b = smooth_k_b(R, x2)
        g = math.hypot(1.0, k)
        delta.append((R - b) / g)
        # In A's frame: centre O = (0, R), line through P0 = (0, b) along u = (1, k)/g.
        beyond.append((x2 * (1 + k * k) - k * (R - b)) / g)
    span = sum(delta)
    if span > d:
        return -math.inf
    return math.sqrt(d * d - span * span) - sum(beyond)


def three_point_curvature(P: np.ndarray) -> np.ndarray:
    """Signed curvature of the circle through each three neighbouring points."""
    a, b = P[1:-1] - P[:-2], P[2:] - P[1:-1]
    c = P[2:] - P[:-2]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return 2 * cross / (np.hypot(*a.T) * np.hypot(*b.T) * np.hypot(*c.T))


def wrap(angle: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * np.asarray(angle)))


def unit(phi: float) -> np.ndarray:
    return np.array([math.cos(phi), math.sin(phi)])


def cross2(u: np.ndarray, v: np.ndarray) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


# ---------------------------------------------------------------------------
# 0. Errors are ValueErrors


def test_errors_are_value_errors():
    assert issubclass(cm.InputError, cm.CyclomechError)
    assert issubclass(cm.InfeasibleError, cm.CyclomechError)
    assert issubclass(cm.InputError, ValueError)
    assert issubclass(cm.InfeasibleError, ValueError)


# ---------------------------------------------------------------------------
# 1. quintic_transition: the seed's six conditions (reference: numpy.polynomial,
#    numpy.linalg.solve of the seed's 3×3 system)

radii = st.floats(0.01, 5.0)
slopes = st.floats(-2.0, 2.0)
intercepts = st.floats(-0.5, 0.5)
ends = st.floats(0.001, 2.0)


def _scales(R: float, k: float, b: float, x2: float) -> tuple[float, float, float]:
    """Tolerances for y, y', y'' at B: 1e-10 of the magnitude of the terms that
    cancel there (|k|·x2 + |b| + x2²/R for y, divided by x2 per derivative)."""
    M = 1.0 + abs(k) * x2 + abs(b) + x2 * x2 / R
    return 1e-10 * M, 1e-10 * M / x2, 1e-10 * M / x2**2


@FAST
@given(radii, slopes, intercepts, ends)
def test_quintic_six_conditions_with_numpy_polynomial(R, k, b, x2):
    q = tr.quintic_transition(R, k, b, x2)
    P = poly(q)
    d1, d2 = P.deriv(), P.deriv(2)
    ty, t1, t2 = _scales(R, k, b, x2)
    # At A: y = 0, y' = 0, y'' = 1/R.
    assert P(0.0) == 0.0
    assert d1(0.0) == 0.0
    assert d2(0.0) == pytest.approx(1.0 / R, rel=1e-12)
    # At B: y = k·x2 + b, y' = k, y'' = 0.
    assert abs(P(x2) - (k * x2 + b)) <= ty
    assert abs(d1(x2) - k) <= t1
    assert abs(d2(x2)) <= t2
    # The same through the module's methods.
    assert q.y(0.0) == 0.0 and q.dy(0.0) == 0.0
    assert q.ddy(0.0) == pytest.approx(1.0 / R, rel=1e-12)
    assert abs(q.y(x2) - (k * x2 + b)) <= ty
    assert abs(q.dy(x2) - k) <= t1
    assert abs(q.ddy(x2)) <= t2
    # And the methods agree with numpy's polynomial inside too (y''' included).
    x = np.linspace(0.0, x2, 17)
    assert_allclose(q.y(x), P(x), rtol=0, atol=ty)
    assert_allclose(q.dy(x), d1(x), rtol=0, atol=t1)
    assert_allclose(q.ddy(x), d2(x), rtol=0, atol=t2)
    assert_allclose(q.dddy(x), P.deriv(3)(x), rtol=0, atol=t2 / x2)
    assert (q.R, q.k, q.b, q.x2) == (R, k, b, x2)


@FAST
@given(radii, slopes, intercepts, ends)
def test_quintic_coefficients_solve_the_seed_system(R, k, b, x2):
    q = tr.quintic_transition(R, k, b, x2)
    a2 = 1.0 / (2 * R)
    # Rows: y(x2), y'(x2), y''(x2) in the unknowns a3, a4, a5.
    A = np.array(
        [
            [x2**3, x2**4, x2**5],
            [3 * x2**2, 4 * x2**3, 5 * x2**4],
            [6 * x2, 12 * x2**2, 20 * x2**3],
        ]
    )
    rhs = np.array([k * x2 + b - a2 * x2**2, k - 2 * a2 * x2, -2 * a2])
    a345 = np.linalg.solve(A, rhs)
    assert_array_equal(q.coeffs[:2], [0.0, 0.0])
    assert q.coeffs[2] == pytest.approx(a2, rel=1e-15)
    # Compare the terms a_i·x2^i, on the scale of the y values they add up to.
    ty = _scales(R, k, b, x2)[0]
    powers = x2 ** np.arange(3, 6)
    assert_allclose(q.coeffs[3:] * powers, a345 * powers, rtol=0, atol=ty)


def test_quintic_methods_keep_the_shape_of_x():
    q = tr.quintic_transition(0.2, 0.1, -0.002, 0.05)
    x = np.linspace(0.0, 0.05, 12).reshape(3, 4)
    for f in (q.y, q.dy, q.ddy, q.dddy, q.curvature, q.curvature_rate, q.arc_length):
        out = f(x)
        assert out.shape == (3, 4)
        assert isinstance(f(0.02), float)
        # Element by element, scalars give the same numbers.
        assert_allclose(out.ravel(), [f(float(v)) for v in x.ravel()], rtol=1e-15, atol=0)


# ---------------------------------------------------------------------------
# 2. smooth_transition (reference: the closed form y'' = (1 − 3s² + 2s³)/R and its
#    double integral by Polynomial.integ)


@FAST
@given(radii, st.floats(0.001, 2.0))
def test_smooth_transition_against_closed_form(R, x2):
    q = tr.smooth_transition(R, x2)
    # y''(x) = (1 − 3s² + 2s³)/R, s = x/x2, as a polynomial in x; integrated twice
    # from y(0) = y'(0) = 0.
    ddy = Polynomial([1.0, 0.0, -3.0 / x2**2, 2.0 / x2**3]) / R
    dy, y = ddy.integ(), ddy.integ(2)
    x = np.linspace(0.0, x2, 101)
    s = x / x2
    assert_allclose(q.ddy(x), (1 - 3 * s**2 + 2 * s**3) / R, rtol=0, atol=1e-12 / R)
    assert_allclose(q.dy(x), dy(x), rtol=0, atol=1e-12 * x2 / R)
    assert_allclose(q.y(x), y(x), rtol=0, atol=1e-12 * x2**2 / R)
    # y''' = 0 at both ends (the curvature starts and ends flat).
    assert abs(q.dddy(0.0)) <= 1e-12 / (R * x2)
    assert abs(q.dddy(x2)) <= 1e-10 / (R * x2)
    # Its line: k = x2/(2R), b = −3·x2²/(20R); and it meets it.
    assert q.k == pytest.approx(x2 / (2 * R), rel=1e-14)
    assert q.b == pytest.approx(-3 * x2**2 / (20 * R), rel=1e-14)
    assert q.k == pytest.approx(dy(x2), rel=1e-12)
    assert q.b == pytest.approx(y(x2) - dy(x2) * x2, rel=1e-10)


def test_smooth_transition_coefficients_by_hand():
    # y = (x²/2 − x⁴/(4·x2²) + x⁵/(10·x2³))/R: a3 = 0.
    R, x2 = 0.15, 0.06
    q = tr.smooth_transition(R, x2)
    want = [0, 0, 1 / (2 * R), 0, -1 / (4 * R * x2**2), 1 / (10 * R * x2**3)]
    assert_allclose(q.coeffs, want, rtol=1e-13, atol=1e-9)


# ---------------------------------------------------------------------------
# 3. Curvature, its rate, arc length (references: circles through three points of
#    the graph; finite differences over quad arc lengths; quad)

# Transitions as a guide uses them: turning by up to ~half a radian.
moderate = st.tuples(
    st.floats(0.05, 5.0),  # R
    st.floats(0.02, 0.5),  # x2/R
    st.floats(-0.5, 0.5),  # k·R/x2
    st.floats(-0.2, 0.2),  # b·R/x2²
)


def _moderate(t: tuple[float, float, float, float]) -> tr.QuinticTransition:
    R, f, g, h = t
    x2 = f * R
    return tr.quintic_transition(R, g * x2 / R, h * x2**2 / R, x2)


@FAST
@given(moderate)
def test_curvature_against_circles_through_graph_points(t):
    q = _moderate(t)
    x = np.linspace(0.0, q.x2, 4001)
    pts = np.stack([x, poly(q)(x)], axis=-1)
    ref = three_point_curvature(pts)  # O(h²) in the spacing
    scale = np.abs(ref).max()
    assert_allclose(q.curvature(x[1:-1]), ref, rtol=0, atol=1e-6 * scale)
    # The ends: 1/R where it leaves the circle, 0 on the line.
    assert q.curvature(0.0) == pytest.approx(1 / q.R, rel=1e-14)
    assert abs(q.curvature(q.x2)) <= 1e-10 * scale


@FAST
@given(moderate)
def test_curvature_rate_against_finite_differences_in_arc_length(t):
    q = _moderate(t)
    P = poly(q)
    d1, d2 = P.deriv(), P.deriv(2)

    def kappa(x):
        return d2(x) / (1 + d1(x) ** 2) ** 1.5

    h = 1e-5 * q.x2  # truncation O(h²), rounding O(ε/h): both ≲ 1e-9 of the scale
    x = np.linspace(h, q.x2 - h, 9)
    fd = [(kappa(v + h) - kappa(v - h)) / quad_length(q, v - h, v + h) for v in x]
    scale = 1.0 / (q.R * q.x2)  # the rate's size, curvature 1/R over length x2
    assert_allclose(q.curvature_rate(x), fd, rtol=0, atol=1e-6 * scale)


@FAST
@given(moderate, st.floats(0.0, 1.0))
def test_arc_length_against_quad(t, frac):
    q = _moderate(t)
    x = frac * q.x2
    ref = quad_length(q, 0.0, x) if x > 0 else 0.0
    assert q.arc_length(x) == pytest.approx(ref, rel=1e-12, abs=1e-300)
    assert q.length == pytest.approx(quad_length(q, 0.0, q.x2), rel=1e-12)
    # A chord is never longer than its arc.
    assert q.length >= math.hypot(q.x2, q.y(q.x2))


@FAST
@given(st.floats(0.01, 5.0), st.floats(0.001, 1.0))
def test_smooth_transition_length_against_quad(R, f):
    # The guide's transitions (k = x2/(2R) ≤ 1 here).
    q = tr.smooth_transition(R, 2 * R * f)
    assert q.length == pytest.approx(quad_length(q, 0.0, q.x2), rel=1e-12)


@pytest.mark.parametrize(
    ("R", "k", "b", "x2"),
    [
        (0.01458974766322017, -0.31926186122747824, 0.13143610613229006, 1.2199291720917016),
        (1.0, 10.0, -3 * 20.0**2 / 20, 20.0),  # smooth_transition(1, 20)
    ],
)
def test_arc_length_of_steep_quintics_against_quad(R, k, b, x2):
    q = tr.quintic_transition(R, k, b, x2)
    assert q.length == pytest.approx(quad_length(q, 0.0, x2), rel=1e-12)


# ---------------------------------------------------------------------------
# 4. to_machine (reference: the seed's formula with math; finite differences)


@FAST
@given(
    st.lists(st.floats(-5, 5), min_size=1, max_size=6),
    st.floats(-7.0, 7.0),
    st.floats(-3, 3),
    st.floats(-3, 3),
)
def test_to_machine_is_the_seed_transform(xs, alpha, x0, y0):
    ys = [0.3 * v - 1.0 for v in xs]
    out = tr.to_machine(xs, ys, alpha, x0, y0)
    assert out.shape == (len(xs), 2)
    ca, sa = math.cos(alpha), math.sin(alpha)
    for (mx, my), xl, yl in zip(out, xs, ys, strict=True):
        assert abs(mx - (xl * ca + yl * sa - x0)) <= 1e-13
        assert abs(my - (-xl * sa + yl * ca - y0)) <= 1e-13
    # Lengths are kept: every pairwise distance.
    P = np.stack([xs, ys], axis=-1)
    dl = np.hypot(*(P[:, None] - P[None]).transpose(2, 0, 1))
    dm = np.hypot(*(out[:, None] - out[None]).transpose(2, 0, 1))
    assert_allclose(dm, dl, rtol=0, atol=1e-12)


def test_to_machine_docstring_case_and_scalars():
    assert_allclose(tr.to_machine(1.0, 0.0, math.pi / 2, -2.0, 0.0), [2.0, -1.0], atol=1e-15)
    # A rotation by −α: the local x axis goes to (cos α, −sin α).
    a = 0.7
    assert_allclose(tr.to_machine(1.0, 0.0, a, 0, 0), [math.cos(a), -math.sin(a)], atol=1e-15)
    assert_allclose(tr.to_machine(0.0, 1.0, a, 0, 0), [math.sin(a), math.cos(a)], atol=1e-15)
    # Broadcasting a grid of x against one y.
    assert tr.to_machine(np.zeros((2, 3)), 1.0, a, 0, 0).shape == (2, 3, 2)


@pytest.mark.parametrize(("alpha", "x0", "y0"), [(0.0, 0.0, 0.0), (2.1, -0.3, 0.5), (-4.0, 1, 1)])
def test_to_machine_keeps_curvature_with_its_sign(alpha, x0, y0):
    q = tr.quintic_transition(0.15, 0.2, -0.004, 0.06)
    t = np.linspace(0.0, q.x2, 2001)
    h = t[1] - t[0]
    X, Y = tr.to_machine(t, q.y(t), alpha, x0, y0).T
    # κ = (X'Y'' − Y'X'')/(X'² + Y'²)^{3/2}, central differences in t = x'.
    dX, dY = (X[2:] - X[:-2]) / (2 * h), (Y[2:] - Y[:-2]) / (2 * h)
    ddX, ddY = (X[2:] - 2 * X[1:-1] + X[:-2]) / h**2, (Y[2:] - 2 * Y[1:-1] + Y[:-2]) / h**2
    kappa = (dX * ddY - dY * ddX) / (dX**2 + dY**2) ** 1.5
    assert_allclose(kappa, q.curvature(t[1:-1]), rtol=0, atol=1e-5 / q.R)
    # Arc length kept: the polyline's length equals the quintic's.
    assert np.hypot(np.diff(X), np.diff(Y)).sum() == pytest.approx(q.length, rel=1e-8)


@pytest.mark.parametrize(
    "ccw",
    [
        True,
        False,
    ],
)
def test_frames_place_the_transitions_on_the_path(ccw):
    p, smp = path(0.05, ccw), sample(2001, 0.05, ccw)
    for side, piece, end in ((0, 1, p.B_t), (1, 3, p.B_p)):
        q = p.transitions[side]
        on_path = smp.points[smp.piece == piece]
        # The transport transition is sampled from x = 0, the process one from x2.
        x = np.linspace(0.0, q.x2, on_path.shape[0], endpoint=False)
        if side == 1:
            x = q.x2 - x
        # A rotation cannot mirror: on the mirrored path (ccw=False) the seed's
        # frame has y' pointing away from the centre, so the quintic enters as −y.
        sign = 1.0 if ccw else -1.0
        placed = tr.to_machine(x, sign * q.y(x), *p.frames[side])
        assert_allclose(placed, on_path, rtol=0, atol=1e-12)
        end_placed = tr.to_machine(q.x2, sign * q.y(q.x2), *p.frames[side])
        assert_allclose(end_placed, end, atol=1e-12)


# ---------------------------------------------------------------------------
# 5. TransferPath (references: plane geometry, the closed-form internal tangent,
#    finite differences of the sample, mirrored and moved copies)


def _ends_and_tangents(p: tr.TransferPath, smp: tr.PathSample, tol: float) -> None:
    ct, cp = p.centre_t, p.centre_p
    turn = 1.0 if p.ccw else -1.0  # transport sense; the process rotor turns the other way
    assert abs(np.hypot(*(p.A - ct)) - p.R_t) <= tol
    assert abs(np.hypot(*(p.C - cp)) - p.R_p) <= tol
    assert abs(np.hypot(*(smp.points[0] - ct)) - p.R_t) <= tol
    assert abs(np.hypot(*(smp.points[-1] - cp)) - p.R_p) <= tol
    for piece, point, centre, R, sense in ((1, p.A, ct, p.R_t, turn), (4, p.C, cp, p.R_p, -turn)):
        i = int(np.flatnonzero(smp.piece == piece)[0])
        assert_allclose(smp.points[i], point, rtol=0, atol=tol)
        radial = (point - centre) / R
        tangent = unit(smp.heading[i])
        # Perpendicular to the radius, and in the rotor's sense of rotation.
        assert abs(tangent @ radial) <= 1e-12
        assert cross2(radial, tangent) == pytest.approx(sense, abs=1e-12)
    # The whole lead-in lies on the transport circle, the lead-out on the process one.
    assert_allclose(np.hypot(*(smp.points[smp.piece == 0] - ct).T), p.R_t, rtol=0, atol=tol)
    assert_allclose(np.hypot(*(smp.points[smp.piece == 4] - cp).T), p.R_p, rtol=0, atol=tol)


@pytest.mark.parametrize("ccw", [True, False])
@pytest.mark.parametrize("x2", [0.05, None, 0.002])
def test_path_ends_lie_on_both_pitch_circles_with_their_tangents(ccw, x2):
    p = path(x2, ccw)
    _ends_and_tangents(p, p.sample(2001), 1e-12)


@SLOW
@given(
    st.floats(0.02, 1.0),
    st.floats(0.02, 1.0),
    st.floats(1e-3, 0.5),
    st.floats(-math.pi, math.pi),
    st.floats(0.05, 1.0),
    st.floats(0.05, 1.0),
    st.booleans(),
)
def test_path_ends_on_random_geometry(R_t, R_p, gap, angle, f_t, f_p, ccw):
    d = R_t + R_p + gap
    c_t = np.array([0.3, -0.2])
    c_p = c_t + d * unit(angle)
    longest = tr.TransferPath(R_t, R_p, c_t, c_p, ccw=ccw)
    assert abs(longest.straight_length) <= 1e-9 * d
    # Shorter transitions, one fraction each; a pair shorter on both sides fits.
    x2 = (f_t * longest.x2_t, f_p * longest.x2_p)
    p = tr.TransferPath(R_t, R_p, c_t, c_p, x2=x2, ccw=ccw)
    _ends_and_tangents(p, p.sample(500), 1e-12 * (1 + d))
    assert p.straight_length == pytest.approx(
        straight_closed_form(R_t, R_p, d, *x2), rel=1e-9, abs=1e-12 * d
    )


def test_curvature_is_continuous_and_its_jumps_scale_like_one_over_n():
    coarse, fine = sample(50_001), sample(200_001)
    jump_c, jump_f = np.abs(np.diff(coarse.curvature)), np.abs(np.diff(fine.curvature))
    # The largest jump between neighbours falls like 1/n (κ is C¹).
    assert 3.5 <= jump_c.max() / jump_f.max() <= 4.5
    assert jump_f.max() < 1e-4 / R_T
    # At the four junctions (A, B_t, B_p, C) too: no step, and at least as fast.
    jc = np.flatnonzero(np.diff(coarse.piece))
    jf = np.flatnonzero(np.diff(fine.piece))
    assert_array_equal(coarse.piece[jc + 1], [1, 2, 3, 4])
    assert_array_equal(fine.piece[jf + 1], [1, 2, 3, 4])
    assert np.all(jump_f[jf] <= jump_c[jc] / 3 + 1e-12)
    assert np.all(jump_f[jf] <= jump_f.max())
    # The pieces' curvatures: +1/R_t on the lead-in, 0 on the straight, −1/R_p after C.
    for smp in (coarse, fine):
        assert_allclose(smp.curvature[smp.piece == 0], 1 / R_T, rtol=1e-15)
        assert_array_equal(smp.curvature[smp.piece == 2], 0.0)
        assert_allclose(smp.curvature[smp.piece == 4], -1 / R_P, rtol=1e-15)
        assert_array_equal(smp.curvature_rate[np.isin(smp.piece, (0, 2, 4))], 0.0)


def test_sample_is_consistent_with_itself():
    p, smp = path(), sample(20_001)
    ds = np.diff(smp.s)
    chord = np.diff(smp.points, axis=0)
    length = np.hypot(*chord.T)
    kmax = 1 / R_T
    # Chord against arc: arc − chord ≤ κ²·h³/24 (plus rounding), never negative.
    assert np.all(ds > 0)
    assert np.all(ds - length <= kmax**2 * ds**3 / 24 * 1.01 + 1e-15)
    assert np.all(ds - length >= -1e-15)
    # The chord's direction is the mean of the headings at its ends, to O(h²).
    mean_heading = 0.5 * (smp.heading[1:] + smp.heading[:-1])
    assert np.abs(wrap(np.arctan2(chord[:, 1], chord[:, 0]) - mean_heading)).max() < 1e-7
    # κ = dθ/ds and dκ/ds by finite differences, to O(h²).
    k_mid = 0.5 * (smp.curvature[1:] + smp.curvature[:-1])
    assert_allclose(np.diff(smp.heading) / ds, k_mid, rtol=0, atol=3e-7 * kmax)
    r_mid = 0.5 * (smp.curvature_rate[1:] + smp.curvature_rate[:-1])
    assert_allclose(np.diff(smp.curvature) / ds, r_mid, rtol=0, atol=1e-6 * kmax**2)
    # The arc length at the start of each piece, from closed forms and quad.
    lead = math.radians(p.lead_deg)
    L_t = quad_length(p.transitions[0], 0.0, p.x2_t)
    L_p = quad_length(p.transitions[1], 0.0, p.x2_p)
    straight = straight_closed_form(R_T, R_P, C_P[0], 0.05, 0.05)
    starts = np.cumsum([0.0, R_T * lead, L_t, straight, L_p])
    first = [int(np.flatnonzero(smp.piece == i)[0]) for i in range(5)]
    assert_allclose(smp.s[first], starts, rtol=1e-12)
    total = starts[-1] + R_P * lead
    assert smp.s[0] == 0.0
    assert smp.s[-1] == pytest.approx(total, rel=1e-12)
    assert p.length == pytest.approx(total, rel=1e-12)
    assert p.start_of_transfer == pytest.approx(R_T * lead, rel=1e-15)
    assert p.transfer_length == pytest.approx(L_t + straight + L_p, rel=1e-12)


@pytest.mark.parametrize(
    ("R", "gap"),
    [
        (0.15, 0.01),
        (0.01, 1.0),  # steep transitions (k ≈ 6)
    ],
)
def test_sample_s_at_junctions_against_quad(R, gap):
    p = tr.TransferPath(R, R, (0, 0), (2 * R + gap, 0))
    smp = p.sample(20_001)
    lead = math.radians(p.lead_deg)
    L = quad_length(p.transitions[0], 0.0, p.x2_t)
    first = [int(np.flatnonzero(smp.piece == i)[0]) for i in (2, 4)]
    assert_allclose(smp.s[first], [R * lead + L, R * lead + 2 * L], rtol=1e-12)


@pytest.mark.parametrize("ccw", [True, False])
def test_straight_segment_is_the_common_tangent_of_the_widened_circles(ccw):
    p, smp = path(0.05, ccw), sample(2001, 0.05, ccw)
    ct, cp = p.centre_t, p.centre_p
    # B_t, B_p begin the straight and the process transition.
    assert_allclose(smp.points[smp.piece == 2][0], p.B_t, atol=1e-15)
    assert_allclose(smp.points[smp.piece == 3][0], p.B_p, atol=1e-15)
    u = (p.B_p - p.B_t) / np.hypot(*(p.B_p - p.B_t))
    # Every straight sample lies on the line B_t B_p, heading along it.
    line = smp.points[smp.piece == 2]
    assert_allclose([cross2(u, P - p.B_t) for P in line], 0.0, atol=1e-15)
    heading = smp.heading[smp.piece == 2]
    assert_allclose(wrap(heading - math.atan2(u[1], u[0])), 0.0, atol=1e-12)
    assert np.hypot(*(p.B_p - p.B_t)) == pytest.approx(p.straight_length, rel=1e-12)
    assert p.straight_length == pytest.approx(
        straight_closed_form(R_T, R_P, C_P[0], 0.05, 0.05), rel=1e-12
    )
    # Its distance from each centre is R + shift; the centres on opposite sides
    # (the transport centre on the left when it turns counter-clockwise).
    side_t, side_p = cross2(u, ct - p.B_t), cross2(u, cp - p.B_t)
    assert abs(side_t) == pytest.approx(R_T + p.shift[0], rel=1e-13)
    assert abs(side_p) == pytest.approx(R_P + p.shift[1], rel=1e-13)
    assert np.sign(side_t) == (1 if ccw else -1) == -np.sign(side_p)
    # The shift: the line's distance (R − b)/√(1 + k²) from the centre in A's frame,
    # with k, b from the integrated closed form; ≈ x2²/(40R).
    for R, shift, k, b in zip((R_T, R_P), p.shift, p.k, p.b, strict=True):
        k_ref, b_ref = smooth_k_b(R, 0.05)
        assert (k, b) == pytest.approx((k_ref, b_ref), rel=1e-13)
        assert R + shift == pytest.approx((R - b_ref) / math.hypot(1, k_ref), rel=1e-14)
        assert shift == pytest.approx(0.05**2 / (40 * R), rel=0.05)


def test_longest_transitions_close_the_straight_and_longer_ones_are_refused():
    p = path(None)
    d = C_P[0]
    assert p.x2_t == p.x2_p
    assert p.straight_length <= 1e-12
    assert np.hypot(*(p.B_p - p.B_t)) <= 1e-10
    # The closed-form straight length vanishes at the same x2 (brentq on it).
    root = brentq(lambda x: straight_closed_form(R_T, R_P, d, x, x), 1e-3, 0.1, xtol=1e-15)
    assert p.x2_t == pytest.approx(root, rel=1e-10)
    # The curvature goes +1/R_t → 0 → −1/R_p with no straight between.
    smp = sample(20_001, None)
    assert np.abs(np.diff(smp.curvature)).max() < 2e-3 / R_T
    longer = 1.001 * root
    with pytest.raises(cm.InfeasibleError, match=re.escape(f"longest is ({root:.6g}, {root:.6g})")):
        tr.TransferPath(R_T, R_P, C_T, C_P, x2=longer)
    # Unequal lengths: refused naming the longest in the same proportions.
    lam = brentq(lambda x: straight_closed_form(R_T, R_P, d, x, 0.05 * x), 1e-3, 0.2, xtol=1e-15)
    with pytest.raises(
        cm.InfeasibleError, match=r"x2 = \(0\.2, 0\.01\) m is too long.*" + re.escape(f"({lam:.6g}")
    ):
        tr.TransferPath(R_T, R_P, C_T, C_P, x2=(0.2, 0.01))
    # Just inside the limit is accepted.
    inside = tr.TransferPath(R_T, R_P, C_T, C_P, x2=0.999 * root)
    assert inside.straight_length == pytest.approx(
        straight_closed_form(R_T, R_P, d, 0.999 * root, 0.999 * root), rel=1e-9
    )


@pytest.mark.parametrize("x2", [0.05, None])
def test_clockwise_path_is_the_mirror_image(x2):
    a, b = sample(4001, x2, True), sample(4001, x2, False)
    flip = np.array([1.0, -1.0])
    assert_allclose(b.points, a.points * flip, rtol=0, atol=1e-15)
    assert_allclose(b.s, a.s, rtol=1e-15)
    assert_allclose(b.curvature, -a.curvature, rtol=1e-15)
    assert_allclose(b.curvature_rate, -a.curvature_rate, rtol=1e-15)
    assert_allclose(wrap(b.heading + a.heading), 0.0, atol=1e-12)
    assert_array_equal(b.piece, a.piece)
    pa, pb = path(x2, True), path(x2, False)
    for name in ("A", "B_t", "B_p", "C"):
        assert_allclose(getattr(pb, name), getattr(pa, name) * flip, atol=1e-15)
    assert pb.length == pytest.approx(pa.length, rel=1e-15)


@SLOW
@given(
    st.floats(-math.pi, math.pi),
    st.floats(-5.0, 5.0),
    st.floats(-5.0, 5.0),
    st.booleans(),
)
def test_moving_both_centres_moves_the_whole_path(theta, tx, ty, ccw):
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[c, -s], [s, c]])
    shift = np.array([tx, ty])
    ref = sample(2001, 0.05, ccw)
    moved = tr.TransferPath(
        R_T, R_P, rot @ C_T + shift, rot @ np.array(C_P) + shift, x2=0.05, ccw=ccw
    ).sample(2001)
    tol = 1e-12 * (1 + abs(tx) + abs(ty))
    assert_allclose(moved.points, ref.points @ rot.T + shift, rtol=0, atol=tol)
    assert_allclose(moved.s, ref.s, rtol=0, atol=1e-13)
    assert_allclose(moved.curvature, ref.curvature, rtol=1e-12, atol=1e-9)
    assert_allclose(moved.curvature_rate, ref.curvature_rate, rtol=1e-10, atol=1e-8)
    assert_allclose(wrap(moved.heading - ref.heading - theta), 0.0, atol=1e-11)
    assert_array_equal(moved.piece, ref.piece)


def test_a_million_points_in_one_vectorised_pass():
    p = path()
    smp = p.sample(1_000_000)
    for a in (smp.s, smp.heading, smp.curvature, smp.curvature_rate, smp.piece):
        assert a.shape == (1_000_000,)
    assert smp.points.shape == (1_000_000, 2)
    assert np.all(np.diff(smp.s) > 0)
    assert smp.s[-1] == pytest.approx(p.length, rel=1e-13)
    assert np.all(np.diff(smp.piece) >= 0)
    assert np.isfinite(smp.points).all()
    # numpy integers are integers too.
    assert p.sample(np.int64(10)).points.shape == (10, 2)


@pytest.mark.parametrize("lead_deg", [0.0, 30.0, 180.0])
def test_lead_arcs_sweep_the_requested_angle(lead_deg):
    p = tr.TransferPath(R_T, R_P, C_T, C_P, x2=0.05, lead_deg=lead_deg)
    smp = p.sample(2001)
    lead = math.radians(lead_deg)

    def angle(P, centre):
        return math.atan2(P[1] - centre[1], P[0] - centre[0])

    # From the first sample to A on the transport circle, from C to the last
    # sample on the process circle (|wrap| is π for a half turn either way).
    swept_t = abs(wrap(angle(p.A, C_T) - angle(smp.points[0], C_T)))
    swept_p = abs(wrap(angle(smp.points[-1], C_P) - angle(p.C, C_P)))
    assert swept_t == pytest.approx(lead, abs=1e-12)
    assert swept_p == pytest.approx(lead, abs=1e-12)
    assert p.length == pytest.approx((R_T + R_P) * lead + p.transfer_length, rel=1e-14)
    _ends_and_tangents(p, smp, 1e-12)


# ---------------------------------------------------------------------------
# 6. Acceleration and jerk along the path (references: closed forms of uniform
#    circular motion; a numerical motion r(t) differentiated in time)


def numerical_motion(p: tr.TransferPath, speed, dt: float):
    """s(t) by solve_ivp of ds/dt = v(s), r(s) by a quintic spline through the
    sampled points, and |a|, |da/dt| by central differences of r(t_i)."""
    smp = p.sample(20_001)
    r_of_s = make_interp_spline(smp.s, smp.points, k=5)
    law = p.speed_law(speed)
    sol = solve_ivp(
        lambda t, y: law(y)[0],
        (0.0, 100.0),
        [0.0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-16,
        dense_output=True,
        events=lambda t, y: y[0] - p.length,
    )
    t_end = sol.t_events[0][0]
    t = np.arange(0.0, t_end, dt)
    s = sol.sol(t)[0]
    r = r_of_s(s)
    acc = (r[2:] - 2 * r[1:-1] + r[:-2]) / dt**2
    jerk = (r[4:] - 2 * r[3:-1] + 2 * r[1:-3] - r[:-4]) / (2 * dt**3)
    junctions = smp.s[np.flatnonzero(np.diff(smp.piece)) + 1]
    return t_end, s, np.hypot(*acc.T), np.hypot(*jerk.T), junctions


def test_constant_speed_closed_forms():
    p, smp = path(), sample(20_001)
    a = p.acceleration(V)
    assert_array_equal(a.s, smp.s)
    assert_array_equal(a.piece, smp.piece)
    assert_allclose(a.normal, V**2 * smp.curvature, rtol=1e-15)
    assert_array_equal(a.tangential, 0.0)
    assert_allclose(a.total, V**2 * np.abs(smp.curvature), rtol=1e-15)
    assert_allclose(a.time, smp.s / V, rtol=1e-12, atol=1e-15)
    assert_allclose(a.speed, V)
    # Uniform circular motion: |a| = V²/R, the vector turning at V/R, |da/dt| = V³/R².
    assert_allclose(a.jerk[a.piece == 0], V**3 / R_T**2, rtol=1e-13)
    assert_allclose(a.jerk[a.piece == 4], V**3 / R_P**2, rtol=1e-13)
    # On the straight nothing changes.
    assert_array_equal(a.jerk[a.piece == 2], 0.0)
    assert a.max_acceleration == pytest.approx(V**2 / R_T, rel=1e-14)
    assert a.max_jerk == pytest.approx(a.jerk.max(), rel=0)
    assert p.max_jerk(V) == a.max_jerk


@pytest.mark.parametrize("speed", [V, (0.15, 0.25)])
def test_acceleration_and_jerk_against_a_numerical_motion(speed):
    p = path()
    dt = 1e-3
    t_end, s, acc, jerk, junctions = numerical_motion(p, speed, dt)
    a = p.acceleration(speed, n=20_001)
    # The travel time, ∫ds/v, against the module's.
    assert a.time[-1] == pytest.approx(t_end, rel=1e-8)
    v_max = max(np.atleast_1d(speed))
    # Central differences straddling a junction see a jump in r'''' (O(dt) there).
    s_a, s_j = s[1:-1], s[2:-2]
    far_a = np.min(np.abs(s_a[:, None] - junctions), axis=1) > 2 * v_max * dt
    far_j = np.min(np.abs(s_j[:, None] - junctions), axis=1) > 3 * v_max * dt
    total = np.interp(s_a, a.s, a.total)
    jerk_ref = np.interp(s_j, a.s, a.jerk)
    assert_allclose(acc[far_a], total[far_a], rtol=0, atol=1e-4 * a.total.max())
    assert_allclose(jerk[far_j], jerk_ref[far_j], rtol=0, atol=1e-3 * a.jerk.max())
    # The check covers the transitions, where the jerk peaks.
    assert far_j.sum() > 0.9 * far_j.size
    assert np.max(jerk[far_j]) == pytest.approx(a.max_jerk, rel=1e-3)


def test_speed_law_for_a_speed_pair():
    p = path()
    V_t, V_p = 0.15, 0.25
    law = p.speed_law((V_t, V_p))
    A, C = p.start_of_transfer, p.start_of_transfer + p.transfer_length
    s = np.linspace(0.0, p.length, 200_001)
    v, dv, ddv = law(s)
    assert_array_equal(v[s <= A], V_t)
    assert_allclose(v[s >= C], V_p, rtol=1e-15)
    assert_array_equal(dv[(s <= A) | (s >= C)], 0.0)
    assert np.all(np.diff(v) >= 0) and np.all((v >= V_t) & (v <= V_p * (1 + 1e-15)))
    # dv/ds and d²v/ds² against central differences: v is C² across A and C.
    h = s[1] - s[0]
    assert_allclose((v[2:] - v[:-2]) / (2 * h), dv[1:-1], rtol=0, atol=1e-6 * np.abs(dv).max())
    assert_allclose((dv[2:] - dv[:-2]) / (2 * h), ddv[1:-1], rtol=0, atol=1e-4 * np.abs(ddv).max())
    assert np.abs(np.diff(dv)).max() < 1e-4 * np.abs(dv).max()
    # Between A and C it is the quintic fixed by v, v', v'' at both ends.
    inside = (s > A) & (s < C)
    fit = Polynomial.fit(s[inside], v[inside], 5)
    assert np.abs(fit(s[inside]) - v[inside]).max() < 1e-13
    for at, want in ((A, V_t), (C, V_p)):
        assert fit(at) == pytest.approx(want, rel=1e-10)
        assert abs(fit.deriv()(at)) < 1e-8 * (V_p - V_t) / (C - A)
        assert abs(fit.deriv(2)(at)) < 1e-6 * (V_p - V_t) / (C - A) ** 2
    # The time along the path: ∫ds/v by quad.
    a = p.acceleration((V_t, V_p))
    ref = quad(lambda x: 1.0 / law(x)[0], 0.0, p.length, points=[A, C], epsrel=1e-12)[0]
    assert a.time[-1] == pytest.approx(ref, rel=1e-8)
    # A pair of equal speeds is the constant speed.
    assert_allclose(p.acceleration((V, V)).jerk, p.acceleration(V).jerk, rtol=1e-14)


# ---------------------------------------------------------------------------
# 7. The jump (references: hand values, math element by element)


def test_acceleration_jump_hand_values():
    assert tr.acceleration_jump(0.15, 2.0, 0.25, 1.2) == pytest.approx(0.96, rel=1e-15)
    assert tr.acceleration_jump(0.1, 10.0, 0.2, 5.0) == pytest.approx(15.0, rel=1e-15)
    assert tr.acceleration_jump(0.1, -10.0, 0.2, 0.0) == pytest.approx(10.0, rel=1e-15)
    assert isinstance(tr.acceleration_jump(0.1, 1.0, 0.2, 1.0), float)
    assert tr.acceleration_jump_at_speed(0.3, 0.15, 0.25) == pytest.approx(0.96, rel=1e-15)
    assert tr.acceleration_jump_at_speed(1.0, 0.5, 0.25) == pytest.approx(6.0, rel=1e-15)


def test_acceleration_jump_broadcasts():
    R_t = np.array([0.1, 0.15, 0.2])
    w_p = np.array([[1.0], [2.5]])
    out = tr.acceleration_jump(R_t, 3.0, 0.25, w_p)
    assert out.shape == (2, 3)
    for i, j in np.ndindex(2, 3):
        assert out[i, j] == pytest.approx(0.25 * w_p[i, 0] ** 2 + R_t[j] * 9.0, rel=1e-15)
    speeds = np.array([0.1, 0.2, 0.4])
    at = tr.acceleration_jump_at_speed(speeds, 0.15, 0.25)
    assert_allclose(at, [v * v / 0.15 + v * v / 0.25 for v in speeds], rtol=1e-15)


@FAST
@given(st.floats(1e-3, 10.0), st.floats(1e-3, 5.0), st.floats(1e-3, 5.0))
def test_jump_at_speed_is_the_jump_with_omega_v_over_r(v, R_t, R_p):
    at = tr.acceleration_jump_at_speed(v, R_t, R_p)
    assert at == pytest.approx(v * v / R_t + v * v / R_p, rel=1e-14)
    assert at == pytest.approx(tr.acceleration_jump(R_t, v / R_t, R_p, v / R_p), rel=1e-14)


# ---------------------------------------------------------------------------
# 8. design_transfer (references: the full path sampler at 200 001 points; the
#    mean value theorem; the issue's worked example by hand)


@pytest.mark.parametrize("speed", [V, (0.12, 0.2)])
def test_design_peak_jerk_against_the_path_sampler(speed):
    d = tr.design_transfer(R_T, R_P, GAP, speed)
    assert d.candidates.shape == d.peak_jerk.shape == (64,)
    assert np.all(np.diff(d.candidates) > 0)
    for i in (0, 20, 45, 63):
        full = tr.TransferPath(R_T, R_P, C_T, C_P, x2=float(d.candidates[i]))
        assert d.peak_jerk[i] == pytest.approx(full.max_jerk(speed, n=200_001), rel=1e-2)
    # Longer transitions lower the jerk here: the longest wins, at the limit.
    assert np.all(np.diff(d.peak_jerk) < 0)
    assert int(np.argmin(d.peak_jerk)) == 63
    assert d.at_limit
    assert d.x2 == pytest.approx(d.candidates[-1], rel=1e-9)
    assert d.x2 == pytest.approx(path(None).x2_t, rel=1e-12)
    assert d.path.straight_length <= 1e-12
    assert d.max_jerk == pytest.approx(d.peak_jerk.min(), rel=1e-2)
    assert math.isfinite(d.max_jerk)
    # The jump without transitions.
    v_t, v_p = (speed, speed) if np.ndim(speed) == 0 else speed
    assert d.jump == tr.acceleration_jump(R_T, v_t / R_T, R_P, v_p / R_P)
    # From A to C the acceleration vector changes by |a_C − a_A| in transfer_time:
    # some jerk ≥ that / time (mean value theorem); a step would need infinite jerk,
    # the transitions spread the change over a good part of the transfer.
    p = d.path
    a_A = v_t**2 / R_T * (np.array(C_T) - p.A) / R_T
    a_C = v_p**2 / R_P * (np.array(C_P) - p.C) / R_P
    change = np.hypot(*(a_C - a_A))
    assert 0.9 * d.jump < change <= d.jump
    assert change / d.transfer_time <= d.max_jerk < 5 * change / d.transfer_time


def test_design_worked_example_of_the_issue():
    # Rotors of 0.15 m (6 pockets) and 0.25 m (10 pockets), equal pitch
    # 2π·0.15/6 = 2π·0.25/10 m, 60 workpieces/min: V = 0.15708 m/s, gap 10 mm.
    assert 2 * math.pi * 0.25 / 10 == pytest.approx(V, rel=1e-15)
    assert abs(V - 0.15708) < 5e-6
    d = tr.design_transfer(0.15, 0.25, 0.010, V)
    # ΔW = V²/0.15 + V²/0.25 = 0.164493 + 0.098696 ≈ 0.263 m/s².
    assert d.jump == pytest.approx(0.263189, abs=1e-6)
    assert d.jump == pytest.approx(V**2 / 0.15 + V**2 / 0.25, rel=1e-14)
    omega_t, omega_p = 2 * math.pi / 6, 2 * math.pi / 10  # one pocket a second
    assert d.jump == pytest.approx(tr.acceleration_jump(0.15, omega_t, 0.25, omega_p), rel=1e-14)
    # With transitions the peak is the transport rotor's own V²/R_t.
    assert d.max_acceleration == pytest.approx(V**2 / 0.15, rel=1e-12)
    # The time from A to C: its length (quad and the closed-form straight) over V,
    # to within one sampling step of the path.
    p = d.path
    L = (
        quad_length(p.transitions[0], 0.0, p.x2_t)
        + straight_closed_form(0.15, 0.25, 0.41, p.x2_t, p.x2_p)
        + quad_length(p.transitions[1], 0.0, p.x2_p)
    )
    assert d.transfer_time == pytest.approx(L / V, abs=2 * p.length / 20_000 / V)
    # At least the jerk of uniform circular motion on the lead-in, V³/R_t².
    assert d.max_jerk >= V**3 / 0.15**2 * (1 - 1e-12)


# ---------------------------------------------------------------------------
# 9. Bad input: the right error class, naming the field and the value

NAN, INF = math.nan, math.inf


def _path(**kw):
    return tr.TransferPath(**({"R_t": R_T, "R_p": R_P, "centre_t": C_T, "centre_p": C_P} | kw))


REFUSALS = [
    # quintic_transition / smooth_transition
    (lambda: tr.quintic_transition(0.0, 0.1, 0.0, 0.1), cm.InputError, r"^R = 0\.0 "),
    (lambda: tr.quintic_transition(-1.0, 0.1, 0.0, 0.1), cm.InputError, r"^R = -1\.0 "),
    (lambda: tr.quintic_transition(NAN, 0.1, 0.0, 0.1), cm.InputError, r"^R = nan "),
    (lambda: tr.quintic_transition(INF, 0.1, 0.0, 0.1), cm.InputError, r"^R = inf "),
    (lambda: tr.quintic_transition(1.0, 0.1, 0.0, 0.0), cm.InputError, r"^x2 = 0\.0 "),
    (lambda: tr.quintic_transition(1.0, 0.1, 0.0, -0.2), cm.InputError, r"^x2 = -0\.2 "),
    (lambda: tr.quintic_transition(1.0, 0.1, 0.0, NAN), cm.InputError, r"^x2 = nan "),
    (lambda: tr.quintic_transition(1.0, INF, 0.0, 0.1), cm.InputError, r"^k = inf "),
    (lambda: tr.quintic_transition(1.0, NAN, 0.0, 0.1), cm.InputError, r"^k = nan "),
    (lambda: tr.quintic_transition(1.0, 0.1, -INF, 0.1), cm.InputError, r"^b = -inf "),
    (lambda: tr.quintic_transition(1.0, 0.1, NAN, 0.1), cm.InputError, r"^b = nan "),
    (lambda: tr.quintic_transition(1.0, "steep", 0.0, 0.1), cm.InputError, r"^k .*'steep'"),
    (lambda: tr.smooth_transition(0.0, 0.1), cm.InputError, r"^R = 0\.0 "),
    (lambda: tr.smooth_transition(1.0, -0.1), cm.InputError, r"^x2 = -0\.1 "),
    (lambda: tr.quintic_transition(1, 0, 0, 1).y([NAN]), cm.InputError, r"^x .*nan"),
    (lambda: tr.quintic_transition(1, 0, 0, 1).curvature(INF), cm.InputError, r"^x .*inf"),
    # to_machine
    (lambda: tr.to_machine(1.0, 0.0, NAN, 0, 0), cm.InputError, r"^alpha = nan"),
    (lambda: tr.to_machine([0.0, INF], 0.0, 0, 0, 0), cm.InputError, r"^x_local .*inf"),
    (lambda: tr.to_machine(0.0, NAN, 0, 0, 0), cm.InputError, r"^y_local .*nan"),
    (lambda: tr.to_machine(0.0, 0.0, 0, INF, 0), cm.InputError, r"^x0 = inf"),
    # TransferPath
    (lambda: _path(R_t=0.0), cm.InputError, r"^R_t = 0\.0 "),
    (lambda: _path(R_p=NAN), cm.InputError, r"^R_p = nan "),
    (lambda: _path(centre_p=(0.40, 0.0)), cm.InputError, r"touch or overlap.*gap 0 m"),
    (lambda: _path(centre_p=(0.30, 0.0)), cm.InputError, r"overlap.*gap -0\.1 m"),
    (lambda: _path(centre_t=(0.0, 0.0, 0.0)), cm.InputError, r"^centre_t .*\(0\.0, 0\.0, 0\.0\)"),
    (lambda: _path(centre_t=(0.0,)), cm.InputError, r"^centre_t .*\(0\.0,\)"),
    (lambda: _path(centre_p=(NAN, 0.0)), cm.InputError, r"^centre_p .*nan"),
    (lambda: _path(x2=-0.01), cm.InputError, r"^x2 must be > 0 .*-0\.01"),
    (lambda: _path(x2=(0.05, -0.01)), cm.InputError, r"^x2 must be > 0 .*-0\.01"),
    (lambda: _path(x2=NAN), cm.InputError, r"^x2 .*nan"),
    (lambda: _path(x2=0.2), cm.InfeasibleError, r"^x2 = \(0\.2, 0\.2\) m is too long"),
    (lambda: _path(lead_deg=-1.0), cm.InputError, r"^lead_deg = -1\.0 "),
    (lambda: _path(lead_deg=181.0), cm.InputError, r"^lead_deg = 181\.0 .*180"),
    (lambda: _path(lead_deg=NAN), cm.InputError, r"^lead_deg = nan "),
    # sample / acceleration
    (lambda: path().sample(9), cm.InputError, r"^n must be an integer ≥ 10.*got 9$"),
    (lambda: path().sample(100.0), cm.InputError, r"^n must be an integer.*got 100\.0$"),
    (lambda: path().sample(True), cm.InputError, r"^n must be an integer.*got True$"),
    (lambda: path().acceleration(0.0), cm.InputError, r"^speed must be > 0 m/s; got 0\.0"),
    (lambda: path().acceleration(-0.1), cm.InputError, r"^speed must be > 0.*-0\.1"),
    (lambda: path().acceleration((0.1, 0.0)), cm.InputError, r"^speed must be > 0.*0\.0"),
    (lambda: path().acceleration(NAN), cm.InputError, r"^speed must be finite.*nan"),
    (lambda: path().acceleration((1, 2, 3)), cm.InputError, r"^speed .*shape \(3,\)"),
    (lambda: path().acceleration(0.1, n=5), cm.InputError, r"^n must be an integer.*5"),
    (lambda: path().max_jerk(INF), cm.InputError, r"^speed must be finite.*inf"),
    # design_transfer
    (lambda: tr.design_transfer(0.15, 0.25, 0.0, 0.1), cm.InputError, r"^gap = 0\.0 "),
    (lambda: tr.design_transfer(0.15, 0.25, -0.01, 0.1), cm.InputError, r"^gap = -0\.01 "),
    (lambda: tr.design_transfer(0.15, 0.25, NAN, 0.1), cm.InputError, r"^gap = nan "),
    (lambda: tr.design_transfer(0.0, 0.25, 0.01, 0.1), cm.InputError, r"^R_t = 0\.0 "),
    (
        lambda: tr.design_transfer(0.15, 0.25, 0.01, 0.1, n_candidates=1),
        cm.InputError,
        r"^n_candidates .*got 1$",
    ),
    (
        lambda: tr.design_transfer(0.15, 0.25, 0.01, 0.1, n_candidates=True),
        cm.InputError,
        r"^n_candidates .*got True$",
    ),
    (
        lambda: tr.design_transfer(0.15, 0.25, 0.01, 0.1, x2_min=1.0),
        cm.InfeasibleError,
        r"^x2_min = 1 m is not below the longest .*\(0\.0787534 m\)",
    ),
    (
        lambda: tr.design_transfer(0.15, 0.25, 0.01, 0.1, x2_min=0.0),
        cm.InputError,
        r"^x2_min = 0\.0 ",
    ),
    (lambda: tr.design_transfer(0.15, 0.25, 0.01, 0.0), cm.InputError, r"^speed must be > 0"),
    (lambda: tr.design_transfer(0.15, 0.25, 0.01, (1, 2, 3)), cm.InputError, r"^speed .*\(3,\)"),
    # acceleration_jump / acceleration_jump_at_speed
    (lambda: tr.acceleration_jump(0.0, 1.0, 0.2, 1.0), cm.InputError, r"^R_t must be > 0.*0\.0"),
    (lambda: tr.acceleration_jump(0.1, 1.0, -0.2, 1.0), cm.InputError, r"^R_p .*-0\.2"),
    (
        lambda: tr.acceleration_jump(0.1, 1.0, [0.2, -0.1], 1.0),
        cm.InputError,
        r"^R_p .*-0\.1",
    ),
    (lambda: tr.acceleration_jump(NAN, 1.0, 0.2, 1.0), cm.InputError, r"^R_t .*nan"),
    (lambda: tr.acceleration_jump(0.1, NAN, 0.2, 1.0), cm.InputError, r"^omega_t .*nan"),
    (lambda: tr.acceleration_jump(0.1, 1.0, 0.2, INF), cm.InputError, r"^omega_p .*inf"),
    (lambda: tr.acceleration_jump_at_speed(1.0, 0.0, 0.2), cm.InputError, r"^R_t .*0\.0"),
    (lambda: tr.acceleration_jump_at_speed(1.0, 0.2, -0.5), cm.InputError, r"R_p.*-0\.5"),
    (lambda: tr.acceleration_jump_at_speed(1.0, NAN, 0.2), cm.InputError, r"^R_t .*nan"),
    (lambda: tr.acceleration_jump_at_speed(NAN, 0.1, 0.2), cm.InputError, r"^speed .*nan"),
]


@pytest.mark.parametrize(("call", "error", "pattern"), REFUSALS, ids=[c[2] for c in REFUSALS])
def test_bad_input_is_refused_naming_the_field(call, error, pattern):
    with pytest.raises(error, match=pattern) as err:
        call()
    assert isinstance(err.value, cm.CyclomechError)
    assert isinstance(err.value, ValueError)


def test_too_long_x2_names_the_longest():
    longest = path(None).x2_t
    with pytest.raises(cm.InfeasibleError, match=re.escape(f"({longest:.6g}, {longest:.6g}) m")):
        _path(x2=1.5 * longest)


# Refusals that are easy to miss.


def test_x2_of_three_values_is_refused_naming_x2():
    with pytest.raises(cm.InputError, match=r"^x2 "):
        _path(x2=(0.01, 0.02, 0.03))


@pytest.mark.parametrize("n_points", [1, 2.5])
def test_design_refuses_bad_n_points(n_points):
    with pytest.raises(cm.InputError, match=r"^n_points "):
        tr.design_transfer(0.15, 0.25, 0.01, 0.1, n_points=n_points)


@pytest.mark.parametrize("method", ["y", "dy", "ddy", "dddy"])
def test_quintic_methods_refuse_nan_arrays(method):
    q = tr.quintic_transition(1.0, 0.0, 0.0, 1.0)
    with pytest.raises(cm.InputError, match=r"^x .*nan"):
        getattr(q, method)(np.array([0.5, NAN]))


@pytest.mark.parametrize(
    "call",
    [
        lambda: tr.acceleration_jump([0.1, 0.2], [1.0, 2.0, 3.0], 0.2, 1.0),
        lambda: tr.to_machine([0.0, 1.0], [0.0, 1.0, 2.0], 0.0, 0.0, 0.0),
    ],
    ids=["acceleration_jump", "to_machine"],
)
def test_non_broadcasting_arrays_are_refused(call):
    with pytest.raises(cm.InputError, match=r"R_t|omega_t|x_local|y_local"):
        call()


@pytest.mark.parametrize(
    "kw", [{"n_points": 10**12}, {"n_candidates": 10**12}], ids=["points", "candidates"]
)
def test_design_transfer_refuses_a_size_that_cannot_fit(kw) -> None:
    """A new user's n_points=10**9 filled 24 GB and was OOM-killed: the size is
    checked before anything is allocated, as TransferPath.sample's is."""
    with pytest.raises(cm.InputError, match=r"design_transfer\(.*needs .* GB.*lower n_points"):
        cm.transfer.design_transfer(0.15, 0.25, gap=0.01, speed=0.15708, **kw)
