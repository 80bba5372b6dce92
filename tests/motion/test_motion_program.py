"""Motion programs (VDI 2143 segments) against sympy, published values and integration.

* Moving-end laws: the construction s = s0 + V0·t + (V1 − V0)·β·H(t/β) + K·F(t/β)
  is derived here again in sympy (H = ∫F symbolically, K from the end position),
  for the cycloid and the harmonic; the program's s, v, a, j must equal sympy's
  to rounding.
* poly5 / poly7 / polynomial: the coefficients solved by sympy from the end
  conditions (a linear system written out here), against the program.
* Published characteristic values (VDI 2143, Norton's table 3-2).
* Joins: the continuity check fires exactly at the join that jumps, and at no
  other; the free-value rule joins segments smoothly.
* Property: for random programs, s(θ2) − s(θ1) equals the integral of v over a
  dense grid (and v of a, a of j): the derivatives are the position's.
"""

from __future__ import annotations

import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

S = cm.motion.Segment
P = cm.motion.Program
PI = math.pi


def _sympy_moving(F, s0, h, v0, v1, beta):
    """s(t) by the construction of the module docs, derived symbolically."""
    x, t = sp.symbols("x t", real=True)
    H = sp.integrate(F(x), (x, 0, x))
    K = h - v0 * beta - (v1 - v0) * beta * H.subs(x, 1)
    return t, s0 + v0 * t + (v1 - v0) * beta * H.subs(x, t / beta) + K * F(t / beta)


# Some of these ends make a segment run backwards on purpose (a short stroke
# for its end velocities): warned about, and not what is tested here.
BACKWARDS_OK = pytest.mark.filterwarnings("ignore:segment .* runs backwards")


@BACKWARDS_OK
@pytest.mark.parametrize(
    ("law", "F"),
    [
        ("cycloidal", lambda x: x - sp.sin(2 * sp.pi * x) / (2 * sp.pi)),
        ("harmonic", lambda x: (1 - sp.cos(sp.pi * x)) / 2),
    ],
)
@pytest.mark.parametrize(("v0", "v1"), [(0.0, 0.0), (0.03, 0.0), (0.0, 0.05), (0.04, -0.02)])
def test_moving_ends_against_sympy(law, F, v0, v1):
    beta_deg, s0, s1 = 100.0, 0.01, 0.07
    beta = math.radians(beta_deg)
    start = math.radians(40.0)
    first = s0  # the law's start position, reached by a poly5 from rest
    segs = [
        S("poly5", 40, start=(0.0, 0.0, 0.0), end=(first, v0, 0.0)),
        S(law, beta_deg, end=(s1, v1)),
        S("poly5", 360 - 40 - beta_deg, end=(0.0, 0.0, 0.0)),
    ]
    prog = P(segs, continuity="velocity")
    t, expr = _sympy_moving(F, first, s1 - first, v0, v1, beta)
    funcs = [sp.lambdify(t, sp.diff(expr, t, k), "numpy") for k in range(4)]
    u = np.linspace(0.0, beta * 0.999999, 37)
    m = prog.evaluate(start + u)
    for k, got in enumerate((m.s, m.v, m.a, m.j)):
        want = np.broadcast_to(funcs[k](u), u.shape)
        assert_allclose(got, want, rtol=1e-11, atol=1e-12 * (1 + np.abs(want).max()))
    # The ends met: velocity v0 and v1, and the law's own end acceleration
    # (zero for the cycloid).
    b = prog.boundaries[1]
    assert b[2][1] == pytest.approx(v0, abs=1e-14) and b[3][1] == pytest.approx(v1, abs=1e-14)
    if law == "cycloidal":
        assert abs(b[2][2]) < 1e-12 and abs(b[3][2]) < 1e-12


def _sympy_hermite(conds, beta):
    """The polynomial through (end, order, value) conditions, solved by sympy."""
    t = sp.symbols("t", real=True)
    n = len(conds)
    c = sp.symbols(f"c0:{n}")
    p = sum(c[k] * t**k for k in range(n))
    eqs = [
        sp.Eq(sp.diff(p, t, order).subs(t, 0 if end == 0 else beta), sp.nsimplify(value))
        for end, order, value in conds
    ]
    sol = sp.solve(eqs, c)
    return t, p.subs(sol)


@BACKWARDS_OK
@pytest.mark.parametrize(
    ("law", "start", "end", "conds"),
    [
        (
            "poly5",
            (0.0, 0.2, -0.1),
            (0.3, 0.05, 0.4),
            [(0, 0, 0), (0, 1, 0.2), (0, 2, -0.1), (1, 0, 0.3), (1, 1, 0.05), (1, 2, 0.4)],
        ),
        (
            "poly7",
            (0.0, 0.2, -0.1, 0.0),
            (0.3, 0.05, 0.4, 1.5),
            [
                (0, 0, 0),
                (0, 1, 0.2),
                (0, 2, -0.1),
                (0, 3, 0),
                (1, 0, 0.3),
                (1, 1, 0.05),
                (1, 2, 0.4),
                (1, 3, 1.5),
            ],
        ),
        # The general polynomial: only what is given (degree 3 here).
        (
            "polynomial",
            (0.0, 0.2),
            (0.3, 0.05),
            [(0, 0, 0), (0, 1, 0.2), (1, 0, 0.3), (1, 1, 0.05)],
        ),
    ],
)
def test_polynomials_against_sympy(law, start, end, conds):
    beta_deg = 200.0
    beta = math.radians(beta_deg)
    prog = P([S(law, beta_deg, start=start, end=end), S("poly7", 160, end=(0.0, 0.2, -0.1, 0.0))])
    t, expr = _sympy_hermite(conds, sp.nsimplify(beta))
    u = np.linspace(0.0, beta * 0.999999, 29)
    m = prog.evaluate(u)
    for k, got in enumerate((m.s, m.v, m.a, m.j)):
        want = np.broadcast_to(sp.lambdify(t, sp.diff(expr, t, k), "numpy")(u), u.shape)
        assert_allclose(got, want, rtol=1e-10, atol=1e-12)
    b = prog.boundaries[0]
    for built, wanted in ((b[2], start), (b[3], end)):
        assert_allclose(built[: len(wanted)], wanted, atol=1e-12)


@pytest.mark.parametrize(
    ("law", "cv", "ca", "cj"),
    [
        # VDI 2143 and Norton, Cam Design and Manufacturing Handbook, table 3-2.
        ("modified_sine", 1.76, 5.53, 69.47),
        ("modified_trapezoid", 2.00, 4.89, 61.43),
        ("cycloidal", 2.0, 2 * PI, 4 * PI**2),
        ("polynomial_345", 1.875, 5.7735, 60.0),
        ("harmonic", PI / 2, PI**2 / 2, PI**3 / 2),
    ],
)
def test_published_characteristic_values(law, cv, ca, cj):
    prog = P([S(law, 90, end=0.02), S("dwell", 90), S(law, 180, end=0.0)], continuity="position")
    for c in prog.characteristics[0], prog.characteristics[2]:
        assert c.cv == pytest.approx(cv, abs=0.006)
        assert c.ca == pytest.approx(ca, abs=0.006)
        assert c.cj == pytest.approx(cj, rel=2e-3)
    assert prog.characteristics[0].stroke == pytest.approx(0.02)
    assert prog.characteristics[2].stroke == pytest.approx(-0.02)
    assert math.isnan(prog.characteristics[1].cv)  # a dwell has no stroke


def test_the_continuity_check_fires_exactly_at_the_jump():
    # Segment 2 starts with a velocity the previous one does not end with.
    segs = [
        S("cycloidal", 90, end=0.05),
        S("dwell", 60),
        S("constant_velocity", 30, start=(None, 0.02)),
        S("poly5", 180, end=(0.0, 0.0, 0.0)),
    ]
    with pytest.raises(cm.InputError) as e:
        P(segs, continuity="velocity")
    assert str(e.value) == (
        "segment 2 (dwell) → segment 3 (constant_velocity) at 150°: "
        "the velocity jumps from 0 to 0.02"
    )
    # Asked only to the position, the same program is accepted.
    prog = P(segs, continuity="position")
    m = prog.evaluate(np.radians([149.999999, 150.0]))
    assert m.v.tolist() == [0.0, 0.02]
    # A position jump is refused whatever is asked (the last segment back to
    # the first across the advance).
    with pytest.raises(cm.InputError, match=r"segment 2 \(poly5\) → segment 1 \(dwell\) at 360°"):
        P([S("dwell", 180, start=0.0), S("poly5", 180, end=0.1)], continuity="position")


def test_given_values_a_law_cannot_meet_are_errors():
    with pytest.raises(cm.InputError) as e:
        P([S("polynomial_345", 180, end=(0.1, 0.3)), S("poly5", 180, end=0.0)])
    assert "segment 1 (polynomial_345): the law cannot meet its end velocity = 0.3" in str(e.value)
    assert "use poly5 or poly7" in str(e.value)
    cannot = r"segment 1 \({}\): the law cannot meet its end {} = {}"
    with pytest.raises(cm.InputError, match=cannot.format("cycloidal", "acceleration", 1)):
        P([S("cycloidal", 180, end=(0.1, 0.0, 1.0)), S("poly5", 180, end=0.0)])
    with pytest.raises(cm.InputError, match=cannot.format("dwell", "position", 0.1)):
        P([S("dwell", 180, end=0.1), S("poly5", 180, end=0.0)])
    with pytest.raises(cm.InputError, match=r"segment 2 \(cycloidal\): its end position is"):
        P([S("dwell", 180), S("cycloidal", 180)])
    with pytest.raises(cm.InputError, match=r"sum to 350°, not 360°"):
        P([S("cycloidal", 180, end=0.1), S("cycloidal", 170, end=0.0)])
    with pytest.raises(cm.InputError, match=r"law must be one of"):
        S("bezier", 90, end=1.0)
    with pytest.raises(cm.InputError, match=r"start must be None, a position or a tuple"):
        S("poly5", 90, start=(0, 0, 0, 0, 0))
    with pytest.raises(cm.InputError, match=r"start\[1\]"):
        S("poly5", 90, start=(0, float("nan")))
    with pytest.raises(cm.InputError, match=r"continuity must be one of"):
        P([S("dwell", 360)], continuity="smooth")
    with pytest.raises(cm.InputError, match=r"points are for a spline"):
        P([S("cycloidal", 360, end=0.0, points=[(0, 0), (360, 0)])])


def test_an_advancing_axis_and_pickling():
    feed = 0.25  # m per cycle
    v = feed / (2 * PI)
    prog = P([S("constant_velocity", 360, start=(0.0, v))], continuity="jerk", advance=feed)
    m = prog.evaluate(np.array([-1.0, 0.5, 2 * PI + 0.5, 7 * PI]))
    assert_allclose(m.s, v * np.array([-1.0, 0.5, 2 * PI + 0.5, 7 * PI]), rtol=1e-14, atol=1e-16)
    assert_allclose(m.v, v)
    again = pickle.loads(pickle.dumps(prog))
    assert again.evaluate(1.0).s == prog.evaluate(1.0).s
    assert repr(again).startswith("Program([constant_velocity 360°]")


_LAWS = ("cycloidal", "modified_sine", "modified_trapezoid", "harmonic", "poly5", "poly7")


@BACKWARDS_OK
@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.sampled_from(_LAWS), min_size=1, max_size=5),
    st.lists(st.floats(10.0, 100.0), min_size=6, max_size=6),
    st.lists(st.floats(-0.1, 0.1), min_size=6, max_size=6),
    st.floats(-0.05, 0.05),
)
def test_derivatives_are_the_positions(laws, angles, ends, v):
    """s, v, a, j are each the integral of the next: trapezoids on a dense grid."""
    angles = np.array(angles[: len(laws) + 1])
    angles *= 360.0 / angles.sum()
    segs = [S("constant_velocity", angles[0], start=(0.0, v))]
    segs += [S(law, a, end=(e, None)) for law, a, e in zip(laws, angles[1:], ends, strict=False)]
    segs[-1] = S(segs[-1].law, segs[-1].angle_deg, end=(0.0, v))
    try:
        prog = P(segs, continuity="velocity")
    except cm.InputError as err:  # a law that cannot meet a join: named, not silent
        assert "jumps" in str(err) or "cannot meet" in str(err)
        return
    theta = np.linspace(0.0, 2 * PI, 400_001)
    m = prog.evaluate(theta)
    h = theta[1] - theta[0]
    for f, df in ((m.s, m.v), (m.v, m.a)):
        integral = np.concatenate(([0.0], np.cumsum((df[1:] + df[:-1]) * h / 2)))
        scale = np.abs(f).max() + np.abs(df).max()
        # (Trapezoids err by h·Δ/2 at a jump of the integrand: 1e-5 of the scale;
        # a subnormal scale, v = 5e-324 and all ends 0, rounds that to 0: a floor.)
        assert np.abs(f - f[0] - integral).max() <= 2e-5 * scale + 1e-300


def test_a_segment_that_runs_backwards_is_warned_about():
    # From rest to 0.04 per rad over 70° (1.22 rad) with a stroke of 0.018 m: a
    # cycloid carrying the change of velocity would go back first (below 0).
    with pytest.warns(cm.CyclomechWarning, match=r"segment 1 \(cycloidal\) runs backwards"):
        prog = P([S("cycloidal", 70, end=(0.018, 0.04)), S("poly5", 290, end=0.0)])
    assert prog.evaluate(np.radians(10.0)).s < 0.0
    # With the stroke of the velocity change alone (0.04 × 1.22 / 2) it does not.
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        P([S("cycloidal", 70, end=(0.0245, 0.04)), S("poly5", 290, end=0.0)])


def test_the_last_segment_ends_as_the_first_starts():
    """A free end of the last segment takes what the first fixes at its start."""
    v, feed = 0.05, 0.3
    prog = P(
        [S("constant_velocity", 120, start=(0.0, v)), S("cycloidal", 240, end=feed)],
        advance=feed,
        continuity="acceleration",
    )
    assert prog.boundaries[1][3][1] == pytest.approx(v, abs=1e-15)


def test_evaluate_keeps_its_own_copy_of_the_angles():
    """``MotionValues.theta`` is the kernel's copy of the angles (written as they
    are read), not the caller's array: the same values and shape, untouched by a
    later change to the input, and s, v, a, j the rows of the plain kernel call.
    At sizes on one thread and on two (several chunks), and for int input."""
    prog = P([S("cycloidal", 200, end=0.02), S("poly5", 160, end=(0.0, 0.0, 0.0))])
    for theta in (
        np.linspace(-7.0, 20.0, 30_011).reshape(30_011),
        np.linspace(0.0, 2 * PI, 24).reshape(2, 3, 4),
        np.arange(-3, 9),
        np.float64(1.25),
    ):
        want = np.asarray(theta, dtype=float).copy()
        rows = prog.kernel.eval(want.reshape(-1), n_threads=1)
        for threads in (1, 2):
            given_ = np.array(theta, copy=True)
            m = prog.evaluate(given_, n_threads=threads)
            assert m.theta.shape == want.shape and not np.shares_memory(m.theta, given_)
            assert np.array_equal(m.theta, want)
            if given_.ndim:
                given_[...] = 99  # the caller's array changes, the result does not
            assert np.array_equal(m.theta, want)
            for k, got in enumerate((m.s, m.v, m.a, m.j)):
                assert got.shape == want.shape
                assert np.array_equal(got.reshape(-1), rows[k])


def test_a_grid_over_many_cycles_is_each_angle_alone():
    """A sorted grid over several cycles either side (the SIMD runs on cycles
    other than the first, s lifted by the advance) gives, bit for bit, what each
    angle gives alone (a 0-d call: the pointwise path); the advance itself is
    checked against the closed form by ``test_an_advancing_axis_and_pickling``."""
    feed = 0.25
    prog = P(
        [
            S("cycloidal", 150, start=(0.0, 0.0), end=(0.2, 0.0)),
            S("dwell", 30),
            S("poly5", 180, end=(feed, 0.0, 0.0)),
        ],
        continuity="acceleration",
        advance=feed,
    )
    theta = np.concatenate(
        [np.linspace(-4 * PI - 0.3, 9 * PI, 40_009), 2 * PI * np.arange(-2, 5) + 1e-15]
    )
    for threads in (1, 2):
        m = prog.evaluate(theta, n_threads=threads)
        alone = [prog.evaluate(x) for x in theta[::37]]
        for name in "svaj":
            want = np.array([getattr(e, name) for e in alone])
            got = getattr(m, name)[::37]
            assert np.array_equal(got, want), name
    assert m.s.max() > 4 * feed  # several cycles up
