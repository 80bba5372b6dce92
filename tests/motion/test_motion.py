"""Motion laws and the two-period slider law (seed 003), against closed forms.

* Every named law is written out here from its textbook definition: cycloidal,
  harmonic and the 3-4-5 / 4-5-6-7 polynomials in closed form; the modified sine
  and modified trapezoid integrated by hand from their acceleration pieces (sine
  ramps of 1/8, a plateau or a long sine through the middle), using the odd
  symmetry of Z'' about j = ½. The half law is built from the rise here by its
  definition Z_h(j) = 2·Z(j/2).
* Published peaks (Cv = max Z', Ca = max |Z''| of the rise) to their published
  digits.
* The two-period law is re-implemented here from the seed's definitions and the
  continuity condition (9), with f_A found by root-finding on the *definition*
  of each complex of data (not on the library's closed forms); every law the
  library synthesises is then measured numerically on a dense grid and must
  reproduce the data it was built from.
"""

from __future__ import annotations

import functools
import math
import pickle
import re

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.polynomial import Polynomial
from numpy.testing import assert_allclose, assert_array_equal
from scipy.optimize import brentq

PI = math.pi
NAMES = cm.motion.NAMES
FORMS = ("rise", "half")
FAST = settings(max_examples=50, deadline=None)

# ---------------------------------------------------------------------------
# Independent laws: (Z, Z', Z'') of the rise on [0, 1].


def _modified(kind: str):
    """(Z, Z', Z'') of a modified sine or trapezoid rise, integrated by hand.

    On [0, ½] the acceleration shape g is: sin(4πj) up to 1/8, then cos(4π/3·(j−1/8))
    (modified sine) or 1 up to 3/8 and cos(4π(j−3/8)) (modified trapezoid). G1 and
    G2 are its first and second integrals from 0; the peak Ca follows from
    Z(½) = ½, and the second half from Z(j) = 1 − Z(1 − j).
    """
    e1, e2 = 1 / (4 * PI), 1 / (32 * PI) - 1 / (16 * PI**2)  # G1, G2 at j = 1/8

    def shape(j):
        ramp = j <= 0.125
        g0r = np.sin(4 * PI * j)
        g1r = (1 - np.cos(4 * PI * j)) / (4 * PI)
        g2r = j / (4 * PI) - np.sin(4 * PI * j) / (16 * PI**2)
        t = j - 0.125
        if kind == "sine":
            w = 4 * PI / 3
            g0 = np.cos(w * t)
            g1 = e1 + np.sin(w * t) / w
            g2 = e2 + e1 * t + (1 - np.cos(w * t)) / w**2
            return np.where(ramp, g0r, g0), np.where(ramp, g1r, g1), np.where(ramp, g2r, g2)
        f1, f2 = e1 + 0.25, e2 + e1 / 4 + 1 / 32  # G1, G2 at j = 3/8
        u = j - 0.375
        flat = j <= 0.375
        g0 = np.select([ramp, flat], [g0r, np.ones_like(j)], np.cos(4 * PI * u))
        g1 = np.select([ramp, flat], [g1r, e1 + t], f1 + np.sin(4 * PI * u) / (4 * PI))
        g2 = np.select(
            [ramp, flat],
            [g2r, e2 + e1 * t + t * t / 2],
            f2 + f1 * u + (1 - np.cos(4 * PI * u)) / (16 * PI**2),
        )
        return g0, g1, g2

    ca = 1 / (2 * shape(np.array(0.5))[2])

    def f(j):
        j = np.asarray(j, dtype=float)
        low = j <= 0.5
        g0, g1, g2 = shape(np.where(low, j, 1 - j))
        return np.where(low, ca * g2, 1 - ca * g2), ca * g1, np.where(low, ca * g0, -ca * g0)

    return f


def _polynomial(c: list[float]):
    """(Z, Z', Z'') of the rise Z = Σ c_k j^k."""
    p = Polynomial(c)
    ps = (p, p.deriv(), p.deriv(2))
    return lambda j: tuple(q(np.asarray(j, dtype=float)) for q in ps)


#: Each law of the core (:data:`cyclomech.motion.NAMES`), written out here: its rise
#: j ↦ (Z, Z', Z''). A new law is its Rust arm plus its reference here and in
#: PUBLISHED; a law without one fails test_every_law_has_its_references.
RISES = {
    "cycloidal": lambda j: (
        j - np.sin(2 * PI * j) / (2 * PI),
        1 - np.cos(2 * PI * j),
        2 * PI * np.sin(2 * PI * j),
    ),
    "harmonic": lambda j: (
        (1 - np.cos(PI * j)) / 2,
        PI / 2 * np.sin(PI * j),
        PI**2 / 2 * np.cos(PI * j),
    ),
    "polynomial_345": _polynomial([0, 0, 0, 10, -15, 6]),
    "polynomial_4567": _polynomial([0, 0, 0, 0, 35, -84, 70, -20]),
    "modified_sine": _modified("sine"),
    "modified_trapezoid": _modified("trapezoid"),
}


def rise(name: str):
    """The named rise, written out here: j ↦ (Z, Z', Z'')."""
    return RISES[name]


def half(name: str):
    """The half law by its definition Z_h(j) = 2·Z(j/2): (Z_h, Z_h', Z_h'')."""
    f = rise(name)

    def h(j):
        z, dz, ddz = f(np.asarray(j, dtype=float) / 2)
        return 2 * z, dz, ddz / 2

    return h


def model(name: str, form: str):
    return rise(name) if form == "rise" else half(name)


DENSE = np.linspace(0.0, 1.0, 200_001)


@functools.cache
def peaks(name: str, form: str) -> tuple[float, float]:
    """(max Z', max |Z''|) of the independent law on a dense grid."""
    _, dz, ddz = model(name, form)(DENSE)
    return float(dz.max()), float(np.abs(ddz).max())


# ---------------------------------------------------------------------------
# Named laws


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("name", NAMES)
def test_every_law_lives_on_the_unit_square(name, form):
    """Z(0) = 0, Z(1) = 1, Z'(0) = 0; a rise stops at j = 1, a half law peaks there."""
    lw = cm.motion.law(name, form=form)
    assert (lw.name, lw.form) == (name, form)
    assert lw.z(0.0) == pytest.approx(0.0, abs=1e-14)
    assert lw.z(1.0) == pytest.approx(1.0, abs=1e-14)
    assert lw.dz(0.0) == pytest.approx(0.0, abs=1e-14)
    dz = lw.dz(DENSE)
    assert (dz >= -1e-14).all()  # never runs backwards
    assert (np.diff(lw.z(DENSE)) >= -1e-13).all()  # up to round-off
    if form == "rise":
        assert lw.dz(1.0) == pytest.approx(0.0, abs=1e-14)
        assert lw.dz(0.5) == pytest.approx(lw.dz_max, rel=1e-13)  # symmetric rise
    else:
        # The half law's speed peak is its end: dz(1) == dz_max and nothing above it.
        assert lw.dz(1.0) == pytest.approx(lw.dz_max, rel=1e-13)
        assert dz.max() <= lw.dz_max * (1 + 1e-13)
        # ... and Z'' vanishes there (the rise's Z'' is odd about j = ½).
        assert lw.ddz(1.0) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("name", NAMES)
def test_every_law_matches_its_definition_written_out_here(name, form):
    """Z, Z', Z'' and the peaks against the independent closed forms above."""
    lw = cm.motion.law(name, form=form)
    j = np.linspace(0.0, 1.0, 2001)
    z, dz, ddz = model(name, form)(j)
    assert_allclose(lw.z(j), z, atol=2e-15)
    assert_allclose(lw.dz(j), dz, atol=5e-15)
    assert_allclose(lw.ddz(j), ddz, atol=2e-14)
    cv, ca = peaks(name, form)
    assert lw.dz_max == pytest.approx(cv, rel=1e-12)
    assert lw.ddz_max == pytest.approx(ca, rel=1e-9)  # grid max of a smooth peak
    assert lw.ddz_max >= ca * (1 - 1e-15)  # the library's peak is exact, not sampled


# Published (Cv, tolerance, Ca, tolerance) of the rises, each tolerance half a unit
# of the last published digit (exact values where the peak is exact).
PUBLISHED = {
    "cycloidal": (2.0, 1e-12, 2 * PI, 1e-12),
    "harmonic": (PI / 2, 1e-12, PI**2 / 2, 1e-12),
    "polynomial_345": (1.875, 1e-12, 5.7735, 5e-5),
    "polynomial_4567": (2.1875, 1e-12, 7.5132, 5e-5),
    "modified_sine": (1.76, 5e-3, 5.528, 5e-4),
    "modified_trapezoid": (2.0, 1e-12, 4.888, 5e-4),
}


def test_every_law_has_its_references():
    """The law lists here come from the core; only the references are by hand."""
    assert set(RISES) == set(NAMES) == set(PUBLISHED)


@pytest.mark.parametrize("name", NAMES)
def test_published_peaks_of_the_rise(name):
    """Cv and Ca of each rise to the digits of the cam-design tables."""
    cv, cv_tol, ca, ca_tol = PUBLISHED[name]
    lw = cm.motion.law(name, form="rise")
    assert lw.dz_max == pytest.approx(cv, abs=cv_tol)
    assert lw.ddz_max == pytest.approx(ca, abs=ca_tol)
    # The half law keeps the speed peak and halves the acceleration peak.
    h = cm.motion.law(name)
    assert h.form == "half"
    assert h.dz_max == pytest.approx(lw.dz_max, rel=1e-13)
    assert h.ddz_max == pytest.approx(lw.ddz_max / 2, rel=1e-13)


def test_published_peaks_in_closed_form():
    """The exact peaks where they are known: 3-4-5 Ca = 10/√3, modified sine
    Cv = 4π/(4 + π) and Ca = 4π²/(4 + π), modified trapezoid Cv = 2 exactly,
    modified sine's published Cv = 1.76 and Ca = 5.53 to their digits."""
    assert cm.motion.law("polynomial_345", "rise").ddz_max == pytest.approx(10 / math.sqrt(3))
    ms = cm.motion.law("modified_sine", "rise")
    assert ms.dz_max == pytest.approx(4 * PI / (4 + PI), rel=1e-13)
    assert ms.ddz_max == pytest.approx(4 * PI**2 / (4 + PI), rel=1e-13)
    assert round(ms.dz_max, 2) == 1.76 and round(ms.ddz_max, 2) == 5.53
    mt = cm.motion.law("modified_trapezoid", "rise")
    assert mt.dz_max == pytest.approx(2.0, rel=1e-13)
    assert round(mt.ddz_max, 2) == 4.89


@pytest.mark.parametrize("name", NAMES)
def test_half_law_is_the_first_half_of_the_rise(name):
    """Z_h(j) = 2 Z(j/2), Z_h' = Z'(j/2), Z_h'' = Z''(j/2)/2 against the library's rise."""
    r, h = cm.motion.law(name, form="rise"), cm.motion.law(name, form="half")
    j = np.linspace(0.0, 1.0, 1001)
    assert_allclose(h.z(j), 2 * r.z(j / 2), atol=2e-15)
    assert_allclose(h.dz(j), r.dz(j / 2), atol=2e-15)
    assert_allclose(h.ddz(j), r.ddz(j / 2) / 2, atol=1e-14)
    assert_allclose(h.dddz(j[1:-1]), r.dddz(j[1:-1] / 2) / 4, rtol=1e-12, atol=1e-12)


def test_half_laws_in_closed_form():
    """Cycloidal Z = j − sin(πj)/π (Z'max 2, Z''max π), harmonic Z = 1 − cos(πj/2)
    (π/2, π²/4), 3-4-5 Z = 2.5j³ − 1.875j⁴ + 0.375j⁵ (1.875, 5/√3), written out."""
    j = np.linspace(0.0, 1.0, 1001)
    cases = {
        "cycloidal": (
            j - np.sin(PI * j) / PI,
            1 - np.cos(PI * j),
            PI * np.sin(PI * j),
            2.0,
            PI,
        ),
        "harmonic": (
            1 - np.cos(PI * j / 2),
            PI / 2 * np.sin(PI * j / 2),
            PI**2 / 4 * np.cos(PI * j / 2),
            PI / 2,
            PI**2 / 4,
        ),
        "polynomial_345": (
            2.5 * j**3 - 1.875 * j**4 + 0.375 * j**5,
            7.5 * j**2 - 7.5 * j**3 + 1.875 * j**4,
            15 * j - 22.5 * j**2 + 7.5 * j**3,
            1.875,
            5 / math.sqrt(3),
        ),
    }
    for name, (z, dz, ddz, cv, ca) in cases.items():
        lw = cm.motion.law(name)  # the default form is the half law
        assert_allclose(lw.z(j), z, atol=2e-15, err_msg=name)
        assert_allclose(lw.dz(j), dz, atol=2e-15, err_msg=name)
        assert_allclose(lw.ddz(j), ddz, atol=1e-14, err_msg=name)
        assert lw.dz_max == pytest.approx(cv, rel=1e-13)
        assert lw.ddz_max == pytest.approx(ca, rel=1e-13)


def _away_from_breaks(lw: cm.motion.MotionLaw, j: float, gap: float) -> bool:
    return all(abs(j - b) > gap for b in lw.breaks)


@FAST
@given(
    name=st.sampled_from(NAMES),
    form=st.sampled_from(FORMS),
    j=st.floats(0.0, 1.0),
)
def test_derivatives_against_finite_differences(name, form, j):
    """Z', Z'', Z''' against central differences of Z, Z', Z'' (away from the breaks,
    where Z''' may jump)."""
    lw = cm.motion.law(name, form=form)
    h = 1e-5
    assume(_away_from_breaks(lw, j, 2 * h))
    x = np.array([j - h, j, j + h])
    for f, df in ((lw.z, lw.dz), (lw.dz, lw.ddz), (lw.ddz, lw.dddz)):
        lo, _, hi = f(x)
        assert df(j) == pytest.approx((hi - lo) / (2 * h), rel=1e-6, abs=1e-6)


def test_evaluation_keeps_shape_and_scalars():
    """Scalars give floats, arrays keep their shape (up to 3-D)."""
    lw = cm.motion.law("cycloidal")
    assert isinstance(lw.z(0.5), float)
    j = np.linspace(0, 1, 12).reshape(2, 3, 2)
    assert lw.dz(j).shape == (2, 3, 2)
    assert_allclose(lw.dz(j), 1 - np.cos(PI * j), atol=1e-15)


def test_law_refuses_unknown_names_and_forms():
    """An unknown name lists the known laws; an unknown form names the two forms."""
    with pytest.raises(cm.InputError, match="cycloidal") as e:
        cm.motion.law("cycloid")
    assert isinstance(e.value, ValueError) and "cycloid" in str(e.value)
    with pytest.raises(cm.InputError, match="form"):
        cm.motion.law("cycloidal", form="full")


# ---------------------------------------------------------------------------
# User polynomials


def test_polynomial_345_matches_the_named_law():
    """The 3-4-5 rise from its coefficients (and its half from 2·Z(j/2)) equals the
    named law."""
    j = np.linspace(0, 1, 501)
    for form, c in (("rise", [0, 0, 0, 10, -15, 6]), ("half", [0, 0, 0, 2.5, -1.875, 0.375])):
        p, named = cm.motion.polynomial(c, form=form), cm.motion.law("polynomial_345", form)
        for f in ("z", "dz", "ddz", "dddz"):
            assert_allclose(getattr(p, f)(j), getattr(named, f)(j), rtol=1e-12, atol=1e-12)
        assert p.dz_max == pytest.approx(named.dz_max, rel=1e-12)
        assert p.ddz_max == pytest.approx(named.ddz_max, rel=1e-12)
    rise = cm.motion.polynomial([0, 0, 0, 10, -15, 6])  # the default form is a rise
    assert rise.form == "rise" and rise.dz_max == pytest.approx(1.875)
    assert rise.ddz_max == pytest.approx(10 / math.sqrt(3), rel=1e-12)


def test_polynomial_half_law_z_squared():
    """Z = j² is a half law (Z'(0) = 0, Z' peaking at 1 = 2, Z'' = 2) but not a rise."""
    p = cm.motion.polynomial([0, 0, 1], form="half")
    assert p.dz_max == pytest.approx(2.0) and p.ddz_max == pytest.approx(2.0)
    assert_allclose(p.z([0.25, 0.5]), [0.0625, 0.25], atol=1e-15)
    with pytest.raises(cm.InputError, match=r"Z'\(1\)"):
        cm.motion.polynomial([0, 0, 1], form="rise")


# Running backwards: 3j² − 2j³ − 10·j²(1 − j)² has Z(1) = 1, Z'(0) = Z'(1) = 0, Z' < 0 near 0.
_BACKWARDS = (Polynomial([0, 0, 3, -2]) - 10 * Polynomial([0, 0, 1, -2, 1])).coef.tolist()


@pytest.mark.parametrize(
    ("coeffs", "form", "what"),
    [
        ([0, 0, 0, 10, -15, 6.1], "rise", r"Z\(1\)"),
        ([0, 0, 2, -0.9], "half", r"Z\(1\)"),
        ([1, 0, 0, 0], "rise", r"Z\(0\)"),
        ([0, 0.5, 0.5], "rise", r"Z'\(0\)"),
        ([0, 0.5, 0.5], "half", r"Z'\(0\)"),
        ([0, 0, 3, -2, 0], "half", "peak"),
        ([0, 0, 1], "rise", r"Z'\(1\)"),
        (_BACKWARDS, "rise", "backwards"),
        ([0, 0, -1, 2], "half", "backwards"),
        ([0, 0, 0, 10, -15, 6, math.nan], "rise", "coeffs"),
        ([0, 0, 0, 10, -15, math.inf], "rise", "coeffs"),
        ([0.0] * 30, "rise", "coeff"),
        ([[0, 0, 1]], "half", "coeffs"),
        ([0, 0, 1], "sideways", "form"),
    ],
)
def test_invalid_polynomials_are_refused(coeffs, form, what):
    """A polynomial that is not a law of its form raises InputError naming the defect."""
    assert np.polyval(_BACKWARDS[::-1], 1.0) == pytest.approx(1.0)  # the fixture is valid at 1
    with pytest.raises(cm.InputError, match=what) as e:
        cm.motion.polynomial(coeffs, form=form)
    assert isinstance(e.value, ValueError)


# ---------------------------------------------------------------------------
# The two-period law


def _law_model(name):
    """(Z, Z', Z'', Z'max, Z''max) of the half law, all independent of the library."""
    f = half(name)
    cv, ca = peaks(name, "half")
    return f, cv, ca


def two_period_model(p2, a2, name1, name2, f_a):
    """Π, Π', Π'' of the seed's two-period law for asymmetry f_A, from (9) written as
    continuity of the speed: (Π1/α1)·Z1'(1) = ((Π2 − Π1)/(α2 − α1))·Z2'(1)."""
    z1, v1, _ = _law_model(name1)
    z2, v2, _ = _law_model(name2)
    a1 = a2 / (1 + f_a)
    # Linear in Π1: Π1·(v1/α1 + v2/(α2 − α1)) = Π2·v2/(α2 − α1).
    p1 = p2 * v2 / (a2 - a1) / (v1 / a1 + v2 / (a2 - a1))

    def law(alpha):
        alpha = np.asarray(alpha, dtype=float)
        one = alpha <= a1
        j1 = np.clip(alpha / a1, 0, 1)
        j2 = np.clip((a2 - alpha) / (a2 - a1), 0, 1)
        (q1, dq1, ddq1), (q2, dq2, ddq2) = z1(j1), z2(j2)
        pos = np.where(one, p1 * q1, p2 - (p2 - p1) * q2)
        vel = np.where(one, p1 / a1 * dq1, (p2 - p1) / (a2 - a1) * dq2)
        acc = np.where(one, p1 / a1**2 * ddq1, -(p2 - p1) / (a2 - a1) ** 2 * ddq2)
        return pos, vel, acc

    return law, p1, a1


def measured(lw: cm.motion.TwoPeriodLaw, n: int = 40_001) -> dict[str, float]:
    """The data a synthesised law shows on a dense grid of its own outputs."""
    a1, a2 = lw.angle1, lw.angle
    g1 = np.linspace(0.0, a1, n)[:-1]  # period I, up to (not at) α1
    g2 = np.linspace(a1, a2, n)[1:]  # period II
    acc1 = np.abs(lw.acceleration(g1)).max()
    acc2 = np.abs(lw.acceleration(g2)).max()
    grid = np.sort(np.append(np.linspace(0.0, a2, 2 * n), a1))  # α1 itself included
    v = lw.velocity(grid)
    return {
        "accel_ratio": acc1 / acc2,
        "max_speed": float(v.max()),
        "argmax_speed": float(grid[np.argmax(v)]),
        "min_speed": float(v.min()),
    }


def _asym_for(p2, a2, n1, n2, key, value):
    """f_A for a complex of data, by root-finding on the definition of the datum."""
    if key == "asymmetry":
        return value

    def datum(f):
        _, p1, a1 = two_period_model(p2, a2, n1, n2, f)
        _, v1, c1 = _law_model(n1)
        c2 = _law_model(n2)[2]
        if key == "accel_ratio":
            return (p1 / a1**2 * c1) / ((p2 - p1) / (a2 - a1) ** 2 * c2) - value
        return p1 / a1 * v1 - value

    return brentq(datum, 1e-6, 1e6, xtol=1e-14, rtol=1e-14)


laws = st.sampled_from(NAMES)
strokes = st.floats(0.01, 0.5)
angles = st.floats(0.3, 2 * PI)


@st.composite
def complexes(draw):
    """(stroke, angle, law1, law2, keyword, value) for one of the three complexes."""
    p2, a2 = draw(strokes), draw(angles)
    n1, n2 = draw(laws), draw(laws)
    key = draw(st.sampled_from(["asymmetry", "accel_ratio", "max_speed"]))
    if key == "asymmetry":
        value = draw(st.floats(0.1, 10.0))
    elif key == "accel_ratio":
        value = draw(st.floats(0.05, 20.0))
    else:
        v1, v2 = peaks(n1, "half")[0], peaks(n2, "half")[0]
        assume(abs(v1 - v2) > 1e-3)
        lo, hi = sorted((v1, v2))
        t = draw(st.floats(0.02, 0.98))
        value = (lo + t * (hi - lo)) * p2 / a2
    return p2, a2, n1, n2, key, value


@FAST
@given(data=complexes())
def test_two_period_reproduces_its_data(data):
    """Each complex: the synthesised law shows α1 = α2/(1 + f_A), the acceleration
    ratio I and the speed peak asked for, measured on a dense grid of its outputs."""
    p2, a2, n1, n2, key, value = data
    lw = cm.motion.two_period(p2, a2, n1, n2, **{key: value})
    assert (lw.stroke, lw.angle, lw.law1.name, lw.law2.name) == (p2, a2, n1, n2)
    assert 0 < lw.stroke1 < p2 and 0 < lw.angle1 < a2
    m = measured(lw)
    if key == "asymmetry":
        assert lw.angle1 == pytest.approx(a2 / (1 + value), rel=1e-13)
        assert (a2 - lw.angle1) / lw.angle1 == pytest.approx(value, rel=1e-12)
    elif key == "accel_ratio":
        assert m["accel_ratio"] == pytest.approx(value, rel=1e-6)
        assert lw.accel_ratio == pytest.approx(value, rel=1e-12)
    else:
        assert m["max_speed"] == pytest.approx(value, rel=1e-12)
        assert lw.velocity(lw.angle1) == pytest.approx(value, rel=1e-12)
        assert lw.max_speed == pytest.approx(value, rel=1e-12)
    # Whatever the complex, the law's own report of the others is what it shows.
    assert m["max_speed"] == pytest.approx(lw.max_speed, rel=1e-12)
    assert m["argmax_speed"] == pytest.approx(lw.angle1, abs=a2 * 1e-4)  # the peak is at α1
    assert m["accel_ratio"] == pytest.approx(lw.accel_ratio, rel=1e-6)
    assert m["min_speed"] >= -1e-15 * lw.max_speed  # Π' ≥ 0: the slider never backs up


@FAST
@given(data=complexes())
def test_two_period_matches_the_independent_model(data):
    """Π, Π', Π'' against the model above, with f_A found from the datum's definition."""
    p2, a2, n1, n2, key, value = data
    lw = cm.motion.two_period(p2, a2, n1, n2, **{key: value})
    f_a = _asym_for(p2, a2, n1, n2, key, value)
    law, p1, a1 = two_period_model(p2, a2, n1, n2, f_a)
    assert lw.angle1 == pytest.approx(a1, rel=1e-9)
    assert lw.stroke1 == pytest.approx(p1, rel=1e-9)
    alpha = np.linspace(0.0, a2, 1001)
    alpha = alpha[np.abs(alpha - lw.angle1) > 1e-6 * a2]  # each side of α1 on its own
    pos, vel, acc = law(alpha)
    scale = p2 / a2
    assert_allclose(lw.position(alpha), pos, rtol=1e-8, atol=1e-9 * p2)
    assert_allclose(lw.velocity(alpha), vel, rtol=1e-8, atol=1e-9 * scale)
    assert_allclose(lw.acceleration(alpha), acc, rtol=1e-8, atol=1e-8 * scale / a2)


@FAST
@given(data=complexes())
def test_two_period_ends_and_continuity(data):
    """Π(0) = 0, Π(α2) = Π2, Π(α1) = Π1; Π and Π' continuous at α1 (condition 9)."""
    p2, a2, n1, n2, key, value = data
    lw = cm.motion.two_period(p2, a2, n1, n2, **{key: value})
    a1, p1 = lw.angle1, lw.stroke1
    assert lw.position(0.0) == pytest.approx(0.0, abs=1e-15 * p2)
    assert lw.position(a2) == pytest.approx(p2, rel=1e-14)
    assert lw.position(a1) == pytest.approx(p1, rel=1e-13)
    assert lw.velocity(0.0) == pytest.approx(0.0, abs=1e-14 * p2 / a2)
    eps = 1e-9 * a1
    lo, hi = lw.position([a1 - eps, a1 + eps])
    assert hi - lo == pytest.approx(0.0, abs=1e-8 * p2)
    vlo, v1, vhi = lw.velocity([a1 - eps, a1, a1 + eps])
    assert vlo == pytest.approx(v1, rel=1e-7) and vhi == pytest.approx(v1, rel=1e-7)
    # The seed's (9) with each period's own scale: both sides reach the speed peak.
    left = p1 / a1 * lw.law1.dz_max
    right = (p2 - p1) / (a2 - a1) * lw.law2.dz_max
    assert left == pytest.approx(right, rel=1e-12)


@FAST
@given(data=complexes(), u=st.floats(0.0, 1.0))
def test_two_period_derivatives_against_finite_differences(data, u):
    """Π' and Π'' against central differences of Π and Π' (away from α1, the ends
    and the laws' breaks)."""
    p2, a2, n1, n2, key, value = data
    lw = cm.motion.two_period(p2, a2, n1, n2, **{key: value})
    a1 = lw.angle1
    alpha = u * a2
    h = 1e-6 * a2
    js = [b * a1 for b in lw.law1.breaks] + [a2 - b * (a2 - a1) for b in lw.law2.breaks]
    assume(all(abs(alpha - b) > 1e-3 * a2 for b in js))
    x = np.array([alpha - h, alpha + h])
    p_lo, p_hi = lw.position(x)
    v_lo, v_hi = lw.velocity(x)
    scale = p2 / a2
    assert lw.velocity(alpha) == pytest.approx((p_hi - p_lo) / (2 * h), rel=1e-6, abs=1e-8 * scale)
    assert lw.acceleration(alpha) == pytest.approx(
        (v_hi - v_lo) / (2 * h), rel=1e-5, abs=1e-6 * scale / a2
    )


def test_mixed_laws_follow_continuity_not_the_printed_13():
    """Cycloidal + modified sine: the printed (13) Π1 = Π2/(1 + f_A) would break the
    continuity of Π'; the library's Π1 = Π2/(1 + n1·f_A) keeps it."""
    p2, a2, f_a = 0.2, PI, 2.0
    lw = cm.motion.two_period(p2, a2, "cycloidal", "modified_sine", asymmetry=f_a)
    a1 = a2 / (1 + f_a)
    v1, v2 = 2.0, 4 * PI / (4 + PI)  # the half laws' speed peaks, in closed form
    printed = p2 / (1 + f_a)
    assert lw.angle1 == pytest.approx(a1, rel=1e-14)
    assert lw.stroke1 == pytest.approx(p2 / (1 + v1 / v2 * f_a), rel=1e-13)
    assert abs(lw.stroke1 - printed) > 0.05 * printed
    # (9) holds for the library's Π1, fails for the printed one.
    assert lw.stroke1 / a1 * v1 == pytest.approx((p2 - lw.stroke1) / (a2 - a1) * v2, rel=1e-12)
    assert abs(printed / a1 * v1 - (p2 - printed) / (a2 - a1) * v2) > 1e-3
    lo, hi = lw.velocity([a1 * (1 - 1e-10), a1 * (1 + 1e-10)])
    assert lo == pytest.approx(hi, rel=1e-8)
    # With the same law in both periods (n1 = 1) the printed (13) is right.
    same = cm.motion.two_period(p2, a2, "cycloidal", "cycloidal", asymmetry=f_a)
    assert same.stroke1 == pytest.approx(printed, rel=1e-14)


def test_two_period_with_a_user_half_law():
    """A user half law Z = j² (Z'max = 2, Z''max = 2) in period I with a harmonic
    period II: Π = Π1·(α/α1)² in period I, and the law reproduces I."""
    z2 = cm.motion.polynomial([0, 0, 1], form="half")
    p2, a2 = 0.1, 3.0
    lw = cm.motion.two_period(p2, a2, z2, "harmonic", accel_ratio=1.3)
    # f_A = I·n1/n2 with n1 = 2/(π/2), n2 = 2/(π²/4).
    f_a = 1.3 * (2 / (PI / 2)) / (2 / (PI**2 / 4))
    a1 = a2 / (1 + f_a)
    assert lw.angle1 == pytest.approx(a1, rel=1e-12)
    assert measured(lw)["accel_ratio"] == pytest.approx(1.3, rel=1e-6)
    alpha = np.linspace(0, a1, 101)
    assert_allclose(lw.position(alpha), lw.stroke1 * (alpha / a1) ** 2, rtol=1e-12, atol=1e-16)
    assert lw.stroke1 / a1 * 2 == pytest.approx((p2 - lw.stroke1) / (a2 - a1) * PI / 2, rel=1e-12)


def test_mixed_laws_accel_ratio_uses_n1_over_n2():
    """Complex 2 with mixed laws: f_A = I·n1/n2, and the measured ratio is I."""
    lw = cm.motion.two_period(0.1, 3.0, "modified_sine", "polynomial_345", accel_ratio=0.7)
    n1 = (4 * PI / (4 + PI)) / 1.875
    n2 = (2 * PI**2 / (4 + PI)) / (5 / math.sqrt(3))
    assert lw.asymmetry == pytest.approx(0.7 * n1 / n2, rel=1e-12)
    assert measured(lw)["accel_ratio"] == pytest.approx(0.7, rel=1e-6)


def _bounds(msg: str) -> tuple[float, float]:
    m = re.search(r"admissible range \(([^,]+), ([^)]+)\)", msg)
    assert m, msg
    return float(m.group(1)), float(m.group(2))


@pytest.mark.parametrize(
    ("law1", "law2"), [("cycloidal", "modified_sine"), ("modified_sine", "cycloidal")]
)
@pytest.mark.parametrize("factor", [1.70, 4 * PI / (4 + PI) * (1 - 1e-9), 2.0 * (1 + 1e-9), 2.05])
def test_max_speed_outside_the_admissible_range_is_refused(law1, law2, factor):
    """Cycloidal with modified sine: Π'max must lie strictly in (4π/(4 + π), 2)·Π2/α2
    = (1.7596, 2)·Π2/α2; the message gives that range."""
    p2, a2 = 0.1, 3.0
    mean = p2 / a2
    lo, hi = 4 * PI / (4 + PI) * mean, 2 * mean
    with pytest.raises(cm.InputError, match="max_speed") as e:
        cm.motion.two_period(p2, a2, law1, law2, max_speed=factor * mean)
    assert isinstance(e.value, ValueError)
    got = _bounds(str(e.value))
    assert got == pytest.approx((lo, hi), rel=1e-5)
    # Just inside the range works.
    for v in (lo * (1 + 1e-6), hi * (1 - 1e-6)):
        lw = cm.motion.two_period(p2, a2, law1, law2, max_speed=v)
        assert lw.max_speed == pytest.approx(v, rel=1e-12)


@pytest.mark.parametrize(
    ("law1", "law2"), [("harmonic", "harmonic"), ("cycloidal", "modified_trapezoid")]
)
def test_max_speed_with_equal_speed_peaks_is_refused(law1, law2):
    """Equal speed peaks (the same law, or cycloidal and modified trapezoid, both 2)
    fix Π'max at Z'max·Π2/α2: the message says so."""
    with pytest.raises(cm.InputError, match="same speed peak") as e:
        cm.motion.two_period(0.1, 3.0, law1, law2, max_speed=0.06)
    v = cm.motion.law(law1).dz_max
    assert f"{v * 0.1 / 3.0:.6g}" in str(e.value)


@pytest.mark.parametrize(
    ("kwargs", "what"),
    [
        ({"asymmetry": 0.0}, "asymmetry.*> 0"),
        ({"asymmetry": -1.0}, "asymmetry.*> 0"),
        ({"asymmetry": math.nan}, "asymmetry"),
        ({"asymmetry": math.inf}, "asymmetry"),
        ({"accel_ratio": 0.0}, "accel_ratio.*> 0"),
        ({"accel_ratio": -2.0}, "accel_ratio.*> 0"),
        ({"accel_ratio": math.nan}, "accel_ratio"),
        ({"max_speed": -0.06}, "max_speed"),
        ({"max_speed": math.inf}, "max_speed"),
        ({"max_speed": math.nan}, "max_speed"),
        ({}, "exactly one"),
        ({"asymmetry": 1.0, "accel_ratio": 1.0}, "exactly one"),
        ({"asymmetry": 1.0, "max_speed": 0.06}, "exactly one"),
    ],
)
def test_bad_data_are_refused(kwargs, what):
    """Non-positive or non-finite data, and not exactly one complex, raise InputError."""
    with pytest.raises(cm.InputError, match=what) as e:
        cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", **kwargs)
    assert isinstance(e.value, ValueError)


@pytest.mark.parametrize(
    ("args", "what"),
    [
        ((math.nan, 3.0, "cycloidal", "cycloidal"), "stroke"),
        ((-0.1, 3.0, "cycloidal", "cycloidal"), "stroke"),
        ((0.1, math.inf, "cycloidal", "cycloidal"), "angle"),
        ((0.1, 0.0, "cycloidal", "cycloidal"), "angle"),
        ((0.1, 2 * PI + 0.01, "cycloidal", "cycloidal"), "2π"),
        ((0.1, 3.0, cm.motion.law("cycloidal", form="rise"), "cycloidal"), "law1.*rise"),
        ((0.1, 3.0, "cycloidal", cm.motion.law("harmonic", form="rise")), "law2.*rise"),
        ((0.1, 3.0, "cycloid", "cycloidal"), "not known"),
        ((0.1, 3.0, 3, "cycloidal"), "law1"),
    ],
)
def test_bad_strokes_angles_and_laws_are_refused(args, what):
    """Stroke and angle must be finite and positive, the angle at most a turn, the
    laws known half laws."""
    with pytest.raises(cm.InputError, match=what):
        cm.motion.two_period(*args, asymmetry=1.0)


def test_full_turn_is_admissible():
    """α2 = 2π is one whole turn: accepted."""
    lw = cm.motion.two_period(0.1, 2 * PI, "cycloidal", "cycloidal", asymmetry=1.0)
    assert lw.position(2 * PI) == pytest.approx(0.1, rel=1e-14)


@pytest.mark.parametrize("alpha", [-1e-3, 3.001, [0.0, 1.0, 3.5], [0.0, math.nan], math.inf])
def test_position_refuses_angles_outside_the_law(alpha):
    """α outside [0, α2] (or not finite) raises InputError naming alpha."""
    lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", asymmetry=1.5)
    for f in (lw.position, lw.velocity, lw.acceleration):
        with pytest.raises(cm.InputError, match="alpha"):
            f(alpha)


def test_two_period_is_vectorised():
    """Arrays keep their shape; a scalar gives a float equal to the array entry."""
    lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", asymmetry=1.5)
    a = np.linspace(0, 3.0, 24).reshape(4, 6)
    out = lw.position(a)
    assert out.shape == (4, 6)
    assert isinstance(lw.position(1.0), float)
    assert lw.position(a[1, 2]) == out[1, 2]
    assert_array_equal(lw.velocity(a.ravel()), lw.velocity(a).ravel())


# ---------------------------------------------------------------------------
# Pickling


def test_motion_law_pickles():
    """Named and user laws survive a pickle round trip with the same values."""
    j = np.linspace(0, 1, 101)
    for lw in (
        cm.motion.law("modified_sine"),
        cm.motion.law("polynomial_4567", form="rise"),
        cm.motion.polynomial([0, 0, 1], form="half"),
    ):
        lw.z(0.5)
        back = pickle.loads(pickle.dumps(lw))
        assert back == lw and hash(back) == hash(lw)
        for f in ("z", "dz", "ddz", "dddz"):
            assert_array_equal(getattr(back, f)(j), getattr(lw, f)(j))
        assert (back.dz_max, back.ddz_max, back.breaks) == (lw.dz_max, lw.ddz_max, lw.breaks)


def _same_two_period(a: cm.motion.TwoPeriodLaw, b: cm.motion.TwoPeriodLaw) -> None:
    alpha = np.linspace(0, a.angle, 301)
    assert (b.law1, b.law2, b.stroke, b.angle, b.stroke1, b.angle1) == (
        a.law1,
        a.law2,
        a.stroke,
        a.angle,
        a.stroke1,
        a.angle1,
    )
    for f in ("position", "velocity", "acceleration"):
        assert_array_equal(getattr(b, f)(alpha), getattr(a, f)(alpha))


def test_two_period_law_pickles_before_use():
    """A fresh TwoPeriodLaw survives a pickle round trip with the same values."""
    lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", max_speed=0.062)
    _same_two_period(lw, pickle.loads(pickle.dumps(lw)))


def test_two_period_law_pickles_after_use():
    """A TwoPeriodLaw that has been evaluated still pickles (a law is a value)."""
    lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", max_speed=0.062)
    lw.position(1.0)
    _same_two_period(lw, pickle.loads(pickle.dumps(lw)))


def _rise_from_velocity(dz: Polynomial) -> list[float]:
    """Z's coefficients for Z' ∝ ``dz``, scaled so that Z(1) = 1."""
    z = dz.integ()
    return (z / z(1.0)).coef.tolist()


def test_a_dip_of_z_prime_below_zero_between_the_samples_is_refused():
    """Z' = x²(1 − x)²((x − a)² − ε²) runs backwards on (a − ε, a + ε), a dip 3e-3
    wide centred between two of the 256 samples the check takes (a = 100.5/256).
    Before, only the best sample was refined and this law was accepted (its Z' down
    to −8.1e-5 by dense sampling here); now every sampled local extreme is."""
    a, eps = 100.5 / 256, 1.5e-3
    x = Polynomial([0.0, 1.0])
    dz = x**2 * (1 - x) ** 2 * ((x - a) ** 2 - eps**2)
    coeffs = _rise_from_velocity(dz)
    dense = Polynomial(coeffs).deriv()(np.linspace(0.0, 1.0, 2_000_001)).min()
    assert dense < -8e-5  # the law does run backwards, by dense sampling
    with pytest.raises(cm.CyclomechError, match="runs backwards"):
        cm.motion.polynomial(coeffs)


def test_two_near_tied_peaks_of_z_prime_give_the_higher():
    """Z' = x²(1 − x)²((x − m)² + κ)(1 + e(x − m)) has two peaks, one at a sample
    and one between samples, whose heights cross as e moves through e0 (found by
    brentq). ``dz_max`` is the higher, to 1e-12, against scipy's bounded search on
    each side of m. Before, only the best sample was refined: 1e-4 low."""
    from scipy.optimize import minimize_scalar

    m, kappa = 0.5 + 0.37 / 256, 0.004
    x = Polynomial([0.0, 1.0])

    def law(e: float) -> list[float]:
        return _rise_from_velocity(x**2 * (1 - x) ** 2 * ((x - m) ** 2 + kappa) * (1 + e * (x - m)))

    def peaks(coeffs: list[float]) -> list[float]:
        d1 = Polynomial(coeffs).deriv()
        return [
            -minimize_scalar(
                lambda t: -d1(t), bounds=side, method="bounded", options={"xatol": 1e-14}
            ).fun
            for side in ((0.0, m), (m, 1.0))
        ]

    e0 = brentq(lambda e: (lambda p: p[0] - p[1])(peaks(law(e))), -0.2, 0.2, xtol=1e-16)
    for de in np.linspace(-3e-4, 3e-4, 13):
        coeffs = law(e0 + de)
        want = max(peaks(coeffs))
        assert cm.motion.polynomial(coeffs).dz_max == pytest.approx(want, rel=1e-12), de


def test_a_two_period_law_built_directly_must_join_its_speeds():
    """TwoPeriodLaw built from numbers (not by two_period) is refused where Π' jumps
    at α1 (0.300 → 0.047 m/rad was accepted: an impact under a smooth law's name), or
    where a law is a rise; two_period's own numbers and the stroke1 the message
    proposes both give a law whose Π' is continuous (dense one-sided differences of
    its positions, against the kinks of the refused one)."""
    half, rise = cm.motion.law("cycloidal"), cm.motion.law("cycloidal", form="rise")
    built = cm.motion.two_period(0.2, math.pi, "cycloidal", "harmonic", asymmetry=1.4)
    again = cm.motion.TwoPeriodLaw(
        built.law1, built.law2, built.stroke, built.angle, built.stroke1, built.angle1
    )
    assert again.max_speed == built.max_speed
    with pytest.raises(cm.InputError, match=r"stroke1 = 0\.15 m: Π' would jump.*0\.3 to"):
        cm.motion.TwoPeriodLaw(half, half, 0.2, math.pi, 0.15, 1.0)
    with pytest.raises(cm.InputError, match=r"law2 .* is a rise"):
        cm.motion.TwoPeriodLaw(half, rise, 0.2, math.pi, 0.1, 1.0)
    try:
        cm.motion.TwoPeriodLaw(half, half, 0.2, math.pi, 0.15, 1.0)
    except cm.InputError as e:
        fit = float(re.search(r"stroke1 = ([0-9.e-]+) m, or", str(e)).group(1))
    lw = cm.motion.TwoPeriodLaw(half, half, 0.2, math.pi, fit, 1.0)
    eps = 1e-6
    p = lw.position(np.array([1.0 - 2 * eps, 1.0 - eps, 1.0, 1.0 + eps, 1.0 + 2 * eps]))
    left = (3 * p[2] - 4 * p[1] + p[0]) / (2 * eps)
    right = (-3 * p[2] + 4 * p[3] - p[4]) / (2 * eps)
    assert left == pytest.approx(right, rel=1e-6)
    assert left == pytest.approx(fit * half.dz_max / 1.0, rel=1e-6)
