"""Function generation (synthesis/_function.py): Freudenstein's three-point
synthesis against the closed form solved here with numpy, least squares against
numpy's lstsq, the structural error against the position solver sampled
densely, the slider-crank equivalent, the ambiguous cases (negative K's, branch
defects, a rocker asked to turn fully) and bad input."""

from __future__ import annotations

import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import synthesis as syn
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose


def _rocker_angle(a, b, c, d, phi_deg, sigma):
    """ψ [deg] of the four-bar at φ [deg] on branch σ, by hand (triangle BDC)."""
    phi = np.radians(phi_deg)
    bx, by = a * np.cos(phi) - d, a * np.sin(phi)
    f = np.hypot(bx, by)
    cos_g = (c * c + f * f - b * b) / (2 * c * f)
    gamma = np.arccos(np.where(np.abs(cos_g) <= 1, cos_g, np.nan))  # NaN: not assembled
    return np.degrees(np.arctan2(by, bx) + sigma * gamma)


def _freudenstein_by_hand(pairs_deg, d):
    """Norton's form K1 cos ψ − K2 cos φ + K3 = cos(φ − ψ), solved with numpy."""
    phi, psi = np.radians(np.asarray(pairs_deg, dtype=float)).T
    rows = np.column_stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)])
    k = np.linalg.lstsq(rows, np.cos(phi - psi), rcond=None)[0]
    a, c = d / k[0], d / k[1]
    b = math.sqrt(a * a + c * c + d * d - 2 * a * c * k[2])
    return k, a, b, c


def _linkage_outputs(cand, phi_deg):
    """ψ [deg] by the position solver of the candidate's Linkage."""
    lk = cand.linkage()
    th = np.radians([cand.crank_angle_deg(p) for p in np.atleast_1d(phi_deg)])
    sol = lk.solve(th)
    assert sol.ok.all()
    v = sol["C"] - sol["D"]
    return np.degrees(np.arctan2(v[:, 1], v[:, 0])) - (180.0 if cand.output_flipped else 0.0)


def _wrapped(x):
    return (np.asarray(x) + 180.0) % 360.0 - 180.0


PAIRS = [(10.0, 30.0), (45.0, 52.0), (80.0, 70.0)]


def test_three_points_match_the_closed_form_and_the_solver() -> None:
    (c,) = syn.function_generation(PAIRS, ground_m=0.25)
    k, a, b, r = _freudenstein_by_hand(PAIRS, 0.25)
    assert_allclose(c.k, k, rtol=1e-12)
    assert_allclose(
        [c.lengths["crank"], c.lengths["coupler"], c.lengths["rocker"], c.lengths["ground"]],
        [abs(a), b, abs(r), 0.25],
        rtol=1e-12,
    )
    assert c.crank_flipped == (a < 0) and c.output_flipped == (r < 0)
    # The built Linkage, analysed by the position solver, meets the points.
    psi = _linkage_outputs(c, [p for p, _ in PAIRS])
    assert_allclose(np.radians(_wrapped(psi - [q for _, q in PAIRS])), 0, atol=1e-9)
    assert c.structural_error < 1e-9  # only the precision points: no function given
    assert not c.branch_defect and c.clean
    assert pickle.loads(pickle.dumps(c)) == c


def test_least_squares_and_structural_error_against_dense_sampling() -> None:
    def f(phi):  # a known crank-rocker's output, bent a little: no four-bar is exact
        return _rocker_angle(1.0, 3.0, 3.5, 4.0, phi, 1) + 0.5 * np.sin(np.radians(4 * phi))

    (c,) = syn.function_generation(function=f, x_range_deg=(0, 90), n=7, ground_m=1.0)
    assert len(c.precision) == 7
    k, _, _, _ = _freudenstein_by_hand(c.precision, 1.0)
    assert_allclose(c.k, k, rtol=1e-10)
    # Structural error: the solver's output over a much denser grid.
    phi = np.linspace(0, 90, 7201)  # holds the 721-angle grid
    err = np.abs(_wrapped(_linkage_outputs(c, phi) - f(phi)))
    assert err.max() >= c.structural_error - 1e-9  # the reported grid is a subset
    assert err.max() - c.structural_error < 1e-3 * err.max() + 1e-9
    assert abs(phi[np.argmax(err)] - c.structural_error_at_deg) <= 90 / 720 + 1e-9
    # Least squares has a residual: the error is not zero but of the bend's size.
    assert 0.05 < c.structural_error < 1.0
    assert c.clean


def test_chebyshev_points_and_spacing() -> None:
    want = 45 - 45 * np.cos((2 * np.arange(1, 4) - 1) * np.pi / 6)
    assert_allclose(syn.chebyshev_points(0, 90, 3), want, rtol=1e-15)

    def f(p):
        return 80 + 20 * ((p - 30) / 60) ** 2

    (c,) = syn.function_generation(function=f, x_range_deg=(30, 90))
    assert_allclose([p for p, _ in c.precision], syn.chebyshev_points(30, 90, 3), rtol=1e-15)
    (u,) = syn.function_generation(function=f, x_range_deg=(30, 90), spacing="uniform")
    assert [p for p, _ in u.precision] == [30.0, 60.0, 90.0]
    # Chebyshev spacing gives the smaller largest error here (its purpose).
    assert c.structural_error < u.structural_error


def test_negative_k_flips_the_crank_and_still_meets_the_points() -> None:
    # Points of a four-bar whose crank sits at φ + 180°: Freudenstein's a < 0.
    phi = np.array([10.0, 40.0, 75.0])
    psi = _rocker_angle(1.0, 3.0, 3.5, 4.0, phi + 180.0, -1)
    (c,) = syn.function_generation(list(zip(phi, psi, strict=True)), ground_m=4.0)
    assert c.crank_flipped and c.k[0] < 0
    assert_allclose([c.lengths["crank"], c.lengths["coupler"], c.lengths["rocker"]], [1, 3, 3.5])
    assert_allclose(np.radians(_wrapped(_linkage_outputs(c, phi) - psi)), 0, atol=1e-9)
    assert_allclose(c.crank_angle_deg(10.0), 190.0)


def test_branch_defect_is_reported_and_ranked_last() -> None:
    # Two points on one assembly, one on the other, of the same four-bar: the
    # equation cannot tell, the branch check must.
    a, b, c_, d = 1.0, 3.0, 3.5, 4.0
    phi = [20.0, 60.0, 100.0]
    psi = [_rocker_angle(a, b, c_, d, 20, 1), _rocker_angle(a, b, c_, d, 60, 1)]
    psi.append(_rocker_angle(a, b, c_, d, 100, -1))
    (cand,) = syn.function_generation(list(zip(phi, psi, strict=True)), ground_m=d)
    assert_allclose(
        [cand.lengths["crank"], cand.lengths["coupler"], cand.lengths["rocker"]], [a, b, c_]
    )
    assert cand.branches == (1, 1, -1) and cand.branch_defect and not cand.clean
    assert not cand.margins.branch_ok


def test_a_rocker_asked_for_a_full_turn_is_flagged() -> None:
    # A non-Grashof triple-rocker's points, with a full-turn input range.
    phi = [-40.0, 0.0, 40.0]
    pairs = [(p, float(_rocker_angle(3, 3, 3, 4, p, 1))) for p in phi]
    (c,) = syn.function_generation(pairs, x_range_deg=(0, 360), ground_m=4)
    assert c.margins.grashof == "triple-rocker" and not c.margins.crank_turns
    assert not c.margins.branch_ok and not c.clean
    # Over its own range it is clean.
    (ok,) = syn.function_generation(pairs, ground_m=4)
    assert ok.clean


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(-40, 40), st.floats(-40, 40)), min_size=2, max_size=6))
def test_candidates_are_ranked_clean_first_then_by_error(offsets) -> None:
    def f(p):
        return 30 + 0.5 * p + 10 * math.sin(math.radians(2 * p))

    try:
        cands = syn.function_generation(
            function=f, x_range_deg=(0, 120), n=4, offsets=offsets, n_grid=181
        )
    except cm.InputError:
        return  # no offset gave a real four-bar: refused, not answered
    keys = [(not c.clean, c.structural_error) for c in cands]
    assert keys == sorted(keys)
    for c in cands:
        if c.clean:  # no clean candidate violates its margins
            assert c.margins.branch_ok and not c.branch_defect
            assert 0 < c.margins.worst_transmission_deg <= 90


@settings(max_examples=30, deadline=None)
@given(
    a=st.floats(0.5, 2),
    b=st.floats(1, 4),
    c=st.floats(1, 4),
    phi0=st.floats(0, 300),
    s1=st.floats(10, 60),
    s2=st.floats(10, 60),
    sigma=st.sampled_from([1, -1]),
)
def test_any_three_points_of_a_four_bar_are_met_by_the_solver(a, b, c, phi0, s1, s2, sigma):
    d = 3.0
    phi = np.array([phi0, phi0 + s1, phi0 + s1 + s2])
    psi = _rocker_angle(a, b, c, d, phi, sigma)
    assume(np.isfinite(psi).all())
    try:
        (cand,) = syn.function_generation(list(zip(phi, psi, strict=True)), ground_m=d)
    except cm.InputError as e:
        assert "singular" in str(e) or "same equation" in str(e)
        return
    assert_allclose(
        [cand.lengths["crank"], cand.lengths["coupler"], cand.lengths["rocker"]],
        [a, b, c],
        rtol=1e-6,
    )
    if cand.margins.branch_ok:
        assert_allclose(np.radians(_wrapped(_linkage_outputs(cand, phi) - psi)), 0, atol=1e-9)


def test_slider_crank_equivalent() -> None:
    r, ln, e = 0.08, 0.3, 0.03
    phi = np.array([20.0, 110.0, 200.0])
    th = np.radians(phi)
    s = r * np.cos(th) + np.sqrt(ln**2 - (e - r * np.sin(th)) ** 2)
    (c,) = syn.function_generation(list(zip(phi, s, strict=True)), mechanism="slider-crank")
    # The linear equation K1·s·cos φ + K2·sin φ − K3 = s², solved by hand.
    rows = np.column_stack([s * np.cos(th), np.sin(th), -np.ones(3)])
    k = np.linalg.solve(rows, s**2)
    assert_allclose(c.k, k, rtol=1e-12)
    assert_allclose([c.lengths["crank"], c.lengths["rod"], c.lengths["offset"]], [r, ln, e])
    sol = c.linkage().solve(np.radians([c.crank_angle_deg(p) for p in phi]))
    assert_allclose(sol["C"][:, 0], s, atol=1e-9)
    assert c.margins.grashof == "crank-slider" and c.clean
    # With the function: the structural error over the range on a grid.
    (g,) = syn.function_generation(
        function=lambda p: float(np.interp(p, phi, s)),
        x_range_deg=(20, 200),
        mechanism="slider-crank",
    )
    assert g.structural_error > 0 and math.isfinite(g.structural_error)


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"pairs_deg": [(0, 0), (10, 5)]}, "needs at least 3"),
        (
            {"pairs_deg": [(0, 0), (10, 5), (360, 7)]},
            "pairs_deg[0] and pairs_deg[2] are coincident",
        ),
        ({"pairs_deg": [(20, 40), (-20, -40), (50, 60)]}, "precision points 0 and 1 give the same"),
        ({"pairs_deg": [(10, 10), (30, 30), (50, 50)]}, "singular"),
        ({"pairs_deg": PAIRS, "mechanism": "six-bar"}, "mechanism must be one of"),
        ({"pairs_deg": PAIRS, "mechanism": "slider-crank", "ground_m": 1}, "ground_m scales"),
        ({"pairs_deg": PAIRS, "ground_m": -1}, "ground_m"),
        ({"function": lambda p: p}, "x_range_deg = (lo, hi)"),
        ({}, "give the precision points"),
        ({"function": math.sqrt, "x_range_deg": (-10, 10)}, "function"),
        ({"function": lambda p: p * p, "x_range_deg": (0, 90), "n": 2}, "n must be"),
        ({"function": lambda p: p * p, "x_range_deg": (0, 90), "spacing": "even"}, "spacing"),
        ({"pairs_deg": [(0, 0, 1)]}, "pairs_deg must be"),
    ],
)
def test_bad_input_says_what_and_which(kwargs, needle) -> None:
    with pytest.raises(cm.InputError) as info:
        syn.function_generation(**kwargs)
    assert needle in str(info.value)
