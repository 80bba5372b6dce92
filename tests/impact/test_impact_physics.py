"""The physics layer of the stop impact (seed 000), against independent references.

* The lever's stiffness, free and propped at the stop, against an Euler–Bernoulli
  finite-element model written here with numpy (2-node Hermite elements, which are
  exact for point loads at nodes), and against the textbook overhang deflection
  P·s²·(a + s)/(3EJ).
* natural_frequency, contact_time and impact_force against their formulas evaluated
  element by element with ``math``, and against the seed's magnitudes (297 Hz free,
  768 Hz in contact, F = 4.137 … 6.2 N at 280 … 420 rpm).
* Pulse shapes against their closed-form impulses; the half-sine against the exact
  trapezoid sum of a sine, (π/n)·cot(π/2n) for n intervals.
"""

from __future__ import annotations

import itertools
import math
import re

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import impact
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

FAST = settings(max_examples=60, deadline=None)

lengths = st.floats(0.01, 1.0)
moduli = st.floats(1e9, 3e11)
inertias = st.floats(1e-12, 1e-8)
fractions = st.floats(0.02, 0.98)


# ---------------------------------------------------------------------------
# The independent model: an Euler–Bernoulli beam by finite elements


def _gauss(A: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Gaussian elimination with partial pivoting, in the arrays' own dtype
    (np.linalg.solve would drop long double to float64)."""
    A, r = A.copy(), r.copy()
    m = r.size
    for c in range(m):
        p = c + int(np.argmax(np.abs(A[c:, c])))
        A[[c, p]], r[[c, p]] = A[[p, c]], r[[p, c]]
        f = A[c + 1 :, c] / A[c, c]
        A[c + 1 :, c:] -= f[:, None] * A[c, c:]
        r[c + 1 :] -= f * r[c]
    u = np.zeros_like(r)
    for i in reversed(range(m)):
        u[i] = (r[i] - A[i, i + 1 :] @ u[i + 1 :]) / A[i, i]
    return u


def fem_deflection(
    EI: float,
    stations: list[float],
    supports: list[float],
    load_at: float,
    per_segment: int = 3,
) -> float:
    """Transverse deflection at ``load_at`` under a unit load there, for a beam
    over ``stations`` (its ends and every support and load point) with zero
    transverse displacement at ``supports``; rotations are free everywhere.

    Hermite elements are exact here, but a short element between long ones
    (a point close to the stop) makes the stiffness matrix ill-conditioned:
    in float64 the solve loses up to ~4e-9 relative, so it runs in long double
    (checked against exact rational arithmetic to ~1e-11 with 3 elements per
    segment)."""
    ld = np.longdouble
    key = sorted(set(stations))
    x = [ld(key[0])]
    for lo, hi in itertools.pairwise(key):
        x.extend(ld(lo) + (ld(hi) - ld(lo)) * j / per_segment for j in range(1, per_segment + 1))
    x = np.array(x, dtype=ld)
    n = x.size
    K = np.zeros((2 * n, 2 * n), dtype=ld)
    for e in range(n - 1):
        L = x[e + 1] - x[e]
        k = (ld(EI) / L**3) * np.array(
            [
                [12.0, 6 * L, -12.0, 6 * L],
                [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                [-12.0, -6 * L, 12.0, -6 * L],
                [6 * L, 2 * L * L, -6 * L, 4 * L * L],
            ],
            dtype=ld,
        )
        dofs = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        K[np.ix_(dofs, dofs)] += k

    def node(pos: float) -> int:
        i = int(np.argmin(np.abs(x - ld(pos))))
        assert abs(float(x[i]) - pos) <= 1e-12 * max(1.0, abs(pos))
        return i

    fixed = {2 * node(s) for s in supports}
    free = np.array([d for d in range(2 * n) if d not in fixed])
    load = np.zeros(2 * n, dtype=ld)
    load[2 * node(load_at)] = 1.0
    u = np.zeros(2 * n, dtype=ld)
    u[free] = _gauss(K[np.ix_(free, free)], load[free])
    return float(u[2 * node(load_at)])


def names(message: str, field: str) -> bool:
    """Does the message open with ``field`` (``name`` or ``name[i]``)? The index
    may be printed as a numpy scalar, ``name[np.int64(i)]``; see the report."""
    m = re.fullmatch(r"(\w+)\[(\d+)\]", field)
    if m is None:
        return message.startswith(field)
    return re.match(rf"{m[1]}\[(np\.int64\()?{m[2]}\)?\]", message) is not None


def fem_free_tip(E: float, J: float, a: float, b: float) -> float:
    return 1.0 / fem_deflection(E * J, [0.0, a, a + b], [0.0, a], a + b)


def fem_at(E: float, J: float, a: float, b: float, s: float, propped: bool) -> float:
    supports = [0.0, a, a + b] if propped else [0.0, a]
    return 1.0 / fem_deflection(E * J, [0.0, a, a + s, a + b], supports, a + s)


def test_fem_reference_reproduces_textbook_cases():
    # The reference itself: simply supported mid-span PL³/48EI, and the
    # overhang's P·s²·(a + s)/(3EI), a cantilever's PL³/3EI as a → 0.
    EI, L = 7.0, 0.8
    mid = fem_deflection(EI, [0.0, L / 2, L], [0.0, L], L / 2)
    assert mid == pytest.approx(L**3 / (48 * EI), rel=1e-12)
    eps = 1e-4
    tip = fem_deflection(EI, [0.0, eps, eps + L], [0.0, eps], eps + L)
    assert tip == pytest.approx((L**2 * (eps + L)) / (3 * EI), rel=1e-12)
    assert tip == pytest.approx(L**3 / (3 * EI), rel=1e-3)


# ---------------------------------------------------------------------------
# lever_stiffness


@FAST
@given(moduli, inertias, lengths, lengths)
def test_lever_stiffness_against_fem(E, J, a, b):
    c = impact.lever_stiffness(E, J, a, b)
    assert c == pytest.approx(fem_free_tip(E, J, a, b), rel=1e-9)
    assert c == pytest.approx(3 * E * J / ((a + b) * b * b), rel=1e-14)


def test_lever_stiffness_seed_magnitude_and_scaling():
    c = impact.lever_stiffness(2.1e11, 6.1e-11, 0.05, 0.1)
    assert c == pytest.approx(25620.0, rel=1e-12)
    # Linear in E·J; doubling both arms divides by 8.
    assert impact.lever_stiffness(4.2e11, 6.1e-11, 0.05, 0.1) == pytest.approx(2 * c, rel=1e-14)
    assert impact.lever_stiffness(2.1e11, 6.1e-11, 0.1, 0.2) == pytest.approx(c / 8, rel=1e-14)


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("E", {"E": 0.0}),
        ("E", {"E": -2.1e11}),
        ("J_x", {"J_x": math.nan}),
        ("a", {"a": math.inf}),
        ("b", {"b": -0.1}),
        ("b", {"b": "long"}),
    ],
)
def test_lever_stiffness_refusals_name_the_field(field, kwargs):
    args = {"E": 2.1e11, "J_x": 6.1e-11, "a": 0.05, "b": 0.1} | kwargs
    with pytest.raises(cm.InputError) as err:
        impact.lever_stiffness(**args)
    assert isinstance(err.value, ValueError)
    assert str(err.value).startswith(field)


# ---------------------------------------------------------------------------
# propped_lever_stiffness


@FAST
@given(moduli, inertias, lengths, lengths, fractions)
def test_propped_stiffness_against_fem(E, J, a, b, frac):
    s = frac * b
    free, propped = impact.propped_lever_stiffness(E, J, a, b, at=s)
    assert free == pytest.approx(fem_at(E, J, a, b, s, propped=False), rel=1e-9)
    assert propped == pytest.approx(fem_at(E, J, a, b, s, propped=True), rel=1e-9)
    # The overhang's textbook deflection P·s²·(a + s)/(3EJ) at distance s.
    assert free == pytest.approx(3 * E * J / (s * s * (a + s)), rel=1e-9)
    assert propped > free


def test_propped_stiffness_default_is_mid_overhang():
    E, J, a, b = 2.1e11, 6.1e-11, 0.05, 0.1
    default = impact.propped_lever_stiffness(E, J, a, b)
    explicit = impact.propped_lever_stiffness(E, J, a, b, at=b / 2)
    assert default == explicit
    free, propped = default
    assert free == pytest.approx(3 * E * J / ((b / 2) ** 2 * (a + b / 2)), rel=1e-12)
    assert propped == pytest.approx(fem_at(E, J, a, b, b / 2, propped=True), rel=1e-9)


@pytest.mark.parametrize("gap", [1e-3, 1e-5, 1e-7, 1e-9, 1e-12])
def test_propped_stiffness_next_to_the_stop_against_50_digits(gap):
    """A point a fraction ``gap`` of the overhang from the stop: the force method's
    f_mm − f_mc²/f_cc from the overhang's textbook deflections (P at u, seen at
    v ≤ u: (u·a·v/3 + v²(3u − v)/6)/EJ) in 50-digit arithmetic, unfactored. As
    written in floats it cancelled: 2e-6 off at 1e-5, 3 % at 1e-7, an overflow
    error at 1e-8."""
    mpmath = pytest.importorskip("mpmath")
    E, J, a, b = 2.1e11, 6.1e-11, 0.05, 0.1
    at = b * (1 - gap)
    with mpmath.workdps(50):
        A, B, S, EJ = (mpmath.mpf(v) for v in (a, b, at, E * J))

        def f(v, u):
            return (u * A * v / 3 + v * v * (3 * u - v) / 6) / EJ

        want = 1 / (f(S, S) - f(S, B) ** 2 / f(B, B))
    _, propped = impact.propped_lever_stiffness(E, J, a, b, at=at)
    assert propped == pytest.approx(float(want), rel=1e-12)


def test_propped_stiffness_near_the_ends_of_the_overhang():
    # Next to the roller support both stiffnesses grow without bound; next to
    # the stop the propped one does while the free one tends to the tip's.
    E, J, a, b = 2.1e11, 6.1e-11, 0.05, 0.1
    tip = impact.lever_stiffness(E, J, a, b)
    free, propped = impact.propped_lever_stiffness(E, J, a, b, at=b * (1 - 1e-4))
    assert free == pytest.approx(tip, rel=1e-3)
    assert propped > 1e3 * free
    free0, propped0 = impact.propped_lever_stiffness(E, J, a, b, at=b * 1e-4)
    assert free0 > 1e6 * tip
    assert propped0 > free0


@pytest.mark.parametrize("at", [0.1, 0.2, 0.0, -0.01, math.nan, math.inf])
def test_propped_stiffness_refuses_points_outside_the_overhang(at):
    with pytest.raises(cm.InputError) as err:
        impact.propped_lever_stiffness(2.1e11, 6.1e-11, 0.05, 0.1, at=at)
    assert isinstance(err.value, ValueError)
    assert str(err.value).startswith("at ")


# ---------------------------------------------------------------------------
# natural_frequency and contact_time


def test_natural_frequency_broadcasts_against_math():
    c = np.array([[1.0e3], [2.562e4], [1.72e5]])
    m = np.array([1e-3, 7.4e-3, 0.5, 2.0])
    f = impact.natural_frequency(c, m)
    assert f.shape == (3, 4)
    ref = [[math.sqrt(ci / mj) / (2 * math.pi) for mj in m] for ci in c[:, 0]]
    assert_allclose(f, ref, rtol=1e-14)
    assert float(impact.natural_frequency(4 * math.pi**2, 1.0)) == pytest.approx(1.0, rel=1e-15)


def test_seed_frequencies_and_contact_time():
    # A reduced mass chosen so the free lever rings at the paper's 297 Hz ...
    c_free = impact.lever_stiffness(2.1e11, 6.1e-11, 0.05, 0.1)
    m = c_free / (2 * math.pi * 297.0) ** 2
    assert m == pytest.approx(7.36e-3, rel=2e-3)  # the seed's few grams
    assert float(impact.natural_frequency(c_free, m)) == pytest.approx(297.0, rel=1e-12)
    # ... and the in-contact stiffness that makes it 768 Hz.
    c_contact = c_free * (768.0 / 297.0) ** 2
    assert float(impact.natural_frequency(c_contact, m)) == pytest.approx(768.0, rel=1e-12)
    # Contact time is half the period: τ = 1/(2f).
    tau = float(impact.contact_time(c_contact, m))
    assert tau == pytest.approx(1.0 / (2 * 768.0), rel=1e-12)
    assert tau == pytest.approx(0.651e-3, rel=1e-3)


def test_contact_time_broadcasts_against_math():
    c = np.array([2.562e4, 1.72e5])
    m = np.array([[1e-3], [7.4e-3], [0.1]])
    tau = impact.contact_time(c, m)
    assert tau.shape == (3, 2)
    ref = [[math.pi * math.sqrt(mi / cj) for cj in c] for mi in m[:, 0]]
    assert_allclose(tau, ref, rtol=1e-14)
    assert_allclose(tau * 2 * impact.natural_frequency(c, m), 1.0, rtol=1e-14)


@pytest.mark.parametrize("func", [impact.natural_frequency, impact.contact_time])
@pytest.mark.parametrize(
    ("field", "c", "m"),
    [
        ("mass", 1e4, 0.0),
        ("mass", 1e4, -1e-3),
        ("mass", 1e4, math.nan),
        ("mass", 1e4, math.inf),
        ("mass[1]", 1e4, [1e-3, -1e-3]),
        ("stiffness", 0.0, 1e-3),
        ("stiffness", -1e4, 1e-3),
        ("stiffness", math.nan, 1e-3),
        ("stiffness", math.inf, 1e-3),
        ("stiffness[2]", [1e4, 2e4, math.nan], 1e-3),
    ],
)
def test_frequency_and_contact_time_refusals_name_the_field(func, field, c, m):
    with pytest.raises(cm.InputError) as err:
        func(c, m)
    assert isinstance(err.value, ValueError)
    assert names(str(err.value), field)


# ---------------------------------------------------------------------------
# impact_force


def test_impact_force_formula_and_broadcasting():
    J, k, length = 7.4e-5, 5 / 9, 0.1
    w = np.array([0.0, 1.0, 2.35, 4.0])
    tau = np.array([[6.52e-4], [1e-3]])
    F = impact.impact_force(J, w, k, length, tau)
    assert F.shape == (2, 4)
    ref = [[J * wi * (1 + k) / (length * ti) for wi in w] for ti in tau[:, 0]]
    assert_allclose(F, ref, rtol=1e-14)
    assert float(impact.impact_force(J, 2.35, k, length, 6.52e-4)) == pytest.approx(4.149, abs=5e-4)
    # Plastic impact halves the elastic one's force.
    elastic = impact.impact_force(J, w, 1.0, length, 1e-3)
    plastic = impact.impact_force(J, w, 0.0, length, 1e-3)
    assert_allclose(plastic * 2, elastic, rtol=1e-15)


def test_impact_force_is_proportional_to_speed_as_in_the_seed():
    # The lever's speed at contact scales with the main shaft's, so F ∝ n.
    J, k, length, tau = 7.4e-5, 5 / 9, 0.1, 6.52e-4
    w280 = 4.137 * length * tau / (J * (1 + k))  # ω0 giving the seed's 4.137 N
    rpm = np.array([280.0, 320.0, 370.0, 420.0])
    F = impact.impact_force(J, w280 * rpm / 280.0, k, length, tau)
    assert F[0] == pytest.approx(4.137, rel=1e-12)
    assert_allclose(F / F[0], rpm / 280.0, rtol=1e-14)
    assert F[-1] == pytest.approx(6.2, rel=2e-3)
    assert abs((6.2 / 4.137) / (420.0 / 280.0) - 1.0) < 2e-3


@pytest.mark.parametrize("k", [-0.01, 1.01, math.nan, math.inf, "steel"])
def test_impact_force_refuses_restitution_outside_unit_interval(k):
    with pytest.raises(cm.InputError) as err:
        impact.impact_force(7.4e-5, 2.35, k, 0.1, 6.52e-4)
    assert isinstance(err.value, ValueError)
    assert str(err.value).startswith("restitution")


@pytest.mark.parametrize("w", [-1.0, [1.0, -0.5], math.nan, [0.0, math.inf]])
def test_impact_force_refuses_negative_or_nonfinite_speed(w):
    with pytest.raises(cm.InputError, match="omega0"):
        impact.impact_force(7.4e-5, w, 5 / 9, 0.1, 6.52e-4)


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("J_A", {"J_A": 0.0}),
        ("lever_length", {"lever_length": -0.1}),
        ("contact_time", {"contact_time": 0.0}),
        ("contact_time[1]", {"contact_time": [1e-3, math.nan]}),
    ],
)
def test_impact_force_other_refusals_name_the_field(field, kwargs):
    args = {
        "J_A": 7.4e-5,
        "omega0": 2.35,
        "restitution": 5 / 9,
        "lever_length": 0.1,
        "contact_time": 6.52e-4,
    } | kwargs
    with pytest.raises(cm.InputError) as err:
        impact.impact_force(**args)
    assert names(str(err.value), field)


# ---------------------------------------------------------------------------
# Pulse

peaks = st.floats(1e-3, 1e3)
durations = st.floats(1e-6, 1e-1)


@FAST
@given(peaks, durations)
def test_named_pulse_impulses_against_closed_forms(F, d):
    rect = impact.Pulse.rectangular(F, d)
    assert rect.impulse == pytest.approx(F * d, rel=1e-12)
    assert (rect.peak, rect.duration, rect.shape) == (F, d, "rectangular")

    tri = impact.Pulse.triangular(F, d)
    assert tri.impulse == pytest.approx(F * d / 2, rel=1e-12)
    assert (tri.peak, tri.duration, tri.shape) == (F, d, "triangular")
    assert tri.f[0] == 0.0 == tri.f[-1]

    for end in (0.0, 0.25, 0.5, 1.0):
        dec = impact.Pulse.decaying(F, d, end=end)
        # Linear fall from F at t = 0 to end·F at t = d.
        assert dec.impulse == pytest.approx(F * d * (1 + end) / 2, rel=1e-12)
        assert (dec.peak, dec.duration, dec.shape) == (F, d, "decaying")
        assert dec.f[0] == F
        assert dec.f[-1] == 0.0  # zero after the pulse

    # The seed's printed F·(1 − t/2τ) over τ: integral 3Fτ/4.
    assert impact.Pulse.decaying(F, d, end=0.5).impulse == pytest.approx(0.75 * F * d, rel=1e-12)
    # end = 1 is the rectangle.
    assert impact.Pulse.decaying(F, d, end=1.0).impulse == pytest.approx(rect.impulse, rel=1e-12)


@pytest.mark.parametrize("points", [3, 5, 17, 257, 1001])
def test_half_sine_impulse_is_the_trapezoid_sum_of_the_sine(points):
    F, d = 3.0, 2e-3
    p = impact.Pulse.half_sine(F, d, points=points)
    assert p.t.size == points
    assert p.duration == d
    assert p.shape == "half_sine"
    assert p.f[0] == 0.0 == p.f[-1]
    n = points - 1
    # Σ sin(kπ/n), k = 1 … n − 1, is cot(π/2n): the table's exact integral.
    exact = F * (d / n) / math.tan(math.pi / (2 * n))
    assert p.impulse == pytest.approx(exact, rel=1e-12)
    # Against the sine's 2Fd/π: the deficit is 1 − x·cot x, x = π/2n, which is
    # the docstring's (π²/12)/n² to leading order (the next term is + x⁴/45).
    x = math.pi / (2 * n)
    deficit = 1 - p.impulse / (2 * F * d / math.pi)
    bound = (math.pi**2 / 12) / n**2
    assert deficit > 0
    assert deficit == pytest.approx(bound, rel=x * x / 10)
    # Peak: the sample nearest the middle (exactly sin(π/2) for odd points).
    assert p.peak == pytest.approx(F, rel=bound)
    if points % 2:
        assert p.peak == pytest.approx(F, rel=1e-15)


def test_half_sine_default_257_points_within_about_1e5():
    p = impact.Pulse.half_sine(1.0, 1e-3)
    assert p.t.size == 257
    assert p.impulse == pytest.approx(2e-3 / math.pi, rel=1.3e-5)


@pytest.mark.parametrize("points", [2, 0, 3.0, True, "9"])
def test_half_sine_refuses_bad_point_counts(points):
    with pytest.raises(cm.InputError, match="points"):
        impact.Pulse.half_sine(1.0, 1e-3, points=points)


def test_pulse_table_accepts_jumps_and_is_read_only():
    p = impact.Pulse.table([0, 1e-3, 1e-3, 2e-3], [1.0, 1.0, -2.0, 0.0])
    assert p.shape == "table"
    assert p.peak == 2.0
    assert p.duration == 2e-3
    assert p.impulse == pytest.approx(1e-3 - 1e-3, abs=1e-18)
    with pytest.raises(ValueError):
        p.t[0] = 1.0
    with pytest.raises(ValueError):
        p.f[0] = 1.0


@pytest.mark.parametrize(
    ("t", "f", "needle"),
    [
        ([0.0, 2e-3, 1e-3], [1.0, 1.0, 0.0], "t[2]"),
        ([0.0, 1e-3, 3e-3, 2e-3, 4e-3], [0.0] * 5, "t[3]"),
        ([1e-3, 2e-3], [1.0, 0.0], "t[0]"),
        ([-1e-3, 2e-3], [1.0, 0.0], "t[0]"),
        ([0.0, math.nan], [1.0, 0.0], "t[1]"),
        ([0.0, math.inf], [1.0, 0.0], "t[1]"),
        ([0.0, 1e-3], [math.nan, 0.0], "f[0]"),
        ([0.0, 1e-3, 2e-3], [1.0, -math.inf, 0.0], "f[1]"),
        ([0.0, 1e-3, 2e-3], [1.0, 0.0], "shapes"),
        ([[0.0, 1e-3]], [[1.0, 0.0]], "1-D"),
        ([0.0], [1.0], "at least 2"),
        (0.0, 1.0, "at least 2"),
        ([0.0, 0.0], [1.0, 0.0], "last time"),
    ],
)
def test_pulse_table_refusals(t, f, needle):
    with pytest.raises(cm.InputError) as err:
        impact.Pulse.table(t, f)
    assert isinstance(err.value, ValueError)
    assert needle in str(err.value)


def test_pulse_table_decreasing_message_names_both_times():
    with pytest.raises(cm.InputError) as err:
        impact.Pulse.table([0.0, 2e-3, 1e-3], [1.0, 1.0, 0.0])
    msg = str(err.value)
    # The values may print as numpy scalars, np.float64(0.001); see the report.
    assert re.search(r"t\[2\] = (np\.float64\()?0\.001\b", msg)
    assert re.search(r"t\[1\] = (np\.float64\()?0\.002\b", msg)


@pytest.mark.parametrize(
    ("maker", "field"),
    [
        (lambda: impact.Pulse.rectangular(1.0, 0.0), "duration"),
        (lambda: impact.Pulse.triangular(1.0, -1e-3), "duration"),
        (lambda: impact.Pulse.half_sine(math.nan, 1e-3), "peak"),
        (lambda: impact.Pulse.decaying(math.inf, 1e-3), "peak"),
        (lambda: impact.Pulse.decaying(1.0, 1e-3, end=1.5), "end"),
        (lambda: impact.Pulse.decaying(1.0, 1e-3, end=-0.1), "end"),
        (lambda: impact.Pulse.decaying(1.0, 1e-3, end=math.nan), "end"),
    ],
)
def test_named_pulse_refusals(maker, field):
    with pytest.raises(cm.InputError) as err:
        maker()
    assert str(err.value).startswith(field)


@FAST
@given(peaks, durations, st.floats(-10.0, 10.0))
def test_scaled_multiplies_forces_only(F, d, factor):
    for p in (
        impact.Pulse.rectangular(F, d),
        impact.Pulse.decaying(F, d, end=0.5),
        impact.Pulse.triangular(F, d),
        impact.Pulse.half_sine(F, d, points=33),
    ):
        q = p.scaled(factor)
        assert_array_equal(q.t, p.t)
        assert_allclose(q.f, p.f * factor, rtol=1e-15)
        assert q.shape == p.shape
        assert q.duration == p.duration
        assert q.peak == pytest.approx(abs(factor) * p.peak, rel=1e-15)
        assert q.impulse == pytest.approx(factor * p.impulse, rel=1e-12, abs=1e-300)
    # The original is untouched.
    r = impact.Pulse.rectangular(F, d)
    r.scaled(factor)
    assert_array_equal(r.f, [F, F, 0.0])
