"""The four-bar and slider-crank checks (synthesis/_fourbar.py): margins against
dense sampling of the solver's own poses, the drawn linkages against the
closed-form loop, bad input."""

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


def _sampled_mu_deg(lk: cm.Linkage, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """Transmission angle BCD [deg] of a four-bar by the position solver, densely."""
    th = np.linspace(math.radians(lo), math.radians(hi), 4001)
    sol = lk.solve(th)
    u, v = sol["B"] - sol["C"], sol["D"] - sol["C"]
    cos = np.sum(u * v, axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1, 1))), sol.ok


def test_crank_rocker_margins_match_the_solver_sampled() -> None:
    m = syn.four_bar_margins(1, 3, 3.5, 4)
    mu, ok = _sampled_mu_deg(syn.four_bar_linkage(1, 3, 3.5, 4), 0, 360)
    assert ok.all()
    assert m.grashof == "crank-rocker" and m.crank_turns and m.branch_ok
    assert_allclose(
        [m.transmission_min_deg, m.transmission_max_deg], [mu.min(), mu.max()], atol=1e-9
    )
    assert m.length_ratio == 4.0
    # Closed forms by hand: BD = 3 at θ = 0 and BD = 5 at θ = π.
    assert_allclose(m.transmission_min_deg, math.degrees(math.acos(12.25 / 21)), rtol=1e-14)
    assert pickle.loads(pickle.dumps(m)) == m


@settings(max_examples=40, deadline=None)
@given(
    a=st.floats(0.3, 3),
    b=st.floats(0.3, 3),
    c=st.floats(0.3, 3),
    d=st.floats(0.3, 3),
    lo=st.floats(-180, 180),
    span=st.floats(1, 360),
)
def test_margins_bound_the_solver_over_any_range(a, b, c, d, lo, span) -> None:
    m = syn.four_bar_margins(a, b, c, d, range_deg=(lo, lo + span))
    try:
        lk = syn.four_bar_linkage(a, b, c, d, crank_deg=lo)
    except cm.InputError:
        # It cannot be drawn at the range's start: broken or folded there.
        assert not m.branch_ok or m.worst_transmission_deg < 1e-6
        return
    if not m.branch_ok:
        return
    mu, ok = _sampled_mu_deg(lk, lo, lo + span)
    assume(ok.all())  # a solver walk that stops early is the solver's business
    assert mu.min() >= m.transmission_min_deg - 1e-7
    assert mu.max() <= m.transmission_max_deg + 1e-7
    # Sampling at 4001 angles comes close to the closed form's extremes.
    assert mu.min() - m.transmission_min_deg < 0.05 * (1 + a * d / (b * c))
    assert m.transmission_max_deg - mu.max() < 0.05 * (1 + a * d / (b * c))


def test_grashof_kinds_and_which_link_turns() -> None:
    kinds = {
        (1, 3, 3.5, 4): ("crank-rocker", True),
        (3, 3.5, 4, 1): ("double-crank", True),
        (3, 1, 3.5, 4): ("double-rocker", False),
        (3, 3.5, 1, 4): ("rocker-crank", False),
        (2, 4, 2, 4): ("change point", True),
        (3, 3, 3, 4): ("triple-rocker", False),
    }
    for lengths, (kind, turns) in kinds.items():
        m = syn.four_bar_margins(*lengths)
        assert (m.grashof, m.crank_turns) == (kind, turns), lengths
    # A triple-rocker cannot turn a full turn: it breaks, so no transmission angle.
    m = syn.four_bar_margins(3, 3, 3, 4)
    assert not m.branch_ok and math.isnan(m.worst_transmission_deg)


def test_four_bar_linkage_draws_the_loop_on_either_branch() -> None:
    for mode in (1, -1):
        lk = syn.four_bar_linkage(
            1,
            3,
            3.5,
            4,
            crank_deg=30,
            mode=mode,
            origin=(1, 2),
            ground_deg=20,
            coupler_point=(1.0, 0.5),
        )
        assert lk.output == "P"
        th = np.radians(20 + np.linspace(30, 390, 73))
        sol = lk.solve(th)
        assert sol.ok.all()
        assert_allclose(np.linalg.norm(sol["B"] - sol["A"], axis=1), 1, atol=1e-12)
        assert_allclose(np.linalg.norm(sol["C"] - sol["B"], axis=1), 3, atol=1e-12)
        assert_allclose(np.linalg.norm(sol["C"] - sol["D"], axis=1), 3.5, atol=1e-12)
        assert_allclose(np.linalg.norm(sol["P"] - sol["B"], axis=1), math.hypot(1, 0.5), atol=1e-12)
        # The branch: C stays on the side `mode` of the ray D → B.
        u, v = sol["B"] - sol["D"], sol["C"] - sol["D"]
        assert (np.sign(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) == mode).all()


def test_slider_crank_linkage_and_margins() -> None:
    r, ln, e = 0.1, 0.35, 0.04
    lk = syn.slider_crank_linkage(r, ln, e, crank_deg=10)
    th = np.radians(np.linspace(0, 360, 721))
    sol = lk.solve(th)
    assert sol.ok.all()
    want = r * np.cos(th) + np.sqrt(ln**2 - (e - r * np.sin(th)) ** 2)
    assert_allclose(sol["C"][:, 0], want, atol=1e-12)
    assert_allclose(sol["C"][:, 1], e, atol=1e-12)
    m = syn.slider_crank_margins(r, ln, e)
    cos_mu = (r * np.sin(th) - e) / ln
    mu = np.degrees(np.arccos(cos_mu))
    assert m.grashof == "crank-slider" and m.branch_ok
    assert m.transmission_min_deg <= mu.min() + 1e-12
    assert_allclose(
        [m.transmission_min_deg, m.transmission_max_deg], [mu.min(), mu.max()], atol=1e-9
    )
    assert syn.slider_crank_margins(0.1, 0.12, 0.05).grashof == "rocker-slider"


@pytest.mark.parametrize(
    ("call", "needle"),
    [
        (lambda: syn.four_bar_margins(0, 1, 1, 1), "crank = 0.0 must be finite and > 0"),
        (lambda: syn.four_bar_margins(1, 1, 1, 1, range_deg=(10, 0)), "range_deg[1]"),
        (lambda: syn.four_bar_margins(1, 1, 1, 1, range_deg=5), "range_deg must be (lo, hi)"),
        (lambda: syn.four_bar_linkage(1, 3, 3.5, 4, mode=0), "mode must be +1 or -1"),
        (lambda: syn.four_bar_linkage(3, 3, 3, 4, crank_deg=180), "cannot be assembled"),
        (lambda: syn.slider_crank_linkage(0.1, 0.05, 0.0, crank_deg=90), "cannot be assembled"),
        (lambda: syn.slider_crank_margins(0.1, 0.3, math.nan), "offset"),
        (lambda: syn.four_bar_linkage(1, 3, 3.5, 4, coupler_point=(1,)), "coupler_point"),
    ],
)
def test_bad_input_names_the_argument(call, needle) -> None:
    with pytest.raises(cm.InputError) as info:
        call()
    assert needle in str(info.value)


def test_a_coupler_point_on_the_coupler_line_gets_a_helper_point() -> None:
    # P on the line BC: the solver needs a third point of the coupler to know
    # which side of BC P is on; Q fixes it and P follows B → C exactly.
    lk = syn.four_bar_linkage(1, 3, 3.5, 4, crank_deg=40, coupler_point=(1.5, 0.0))
    assert "Q" in lk.names and lk.output == "P"
    sol = lk.solve(np.radians(np.linspace(40, 400, 91)))
    assert sol.ok.all()
    assert_allclose(sol["P"], sol["B"] + 0.5 * (sol["C"] - sol["B"]), atol=1e-12)
