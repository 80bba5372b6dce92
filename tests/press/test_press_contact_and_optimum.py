"""Issue 16, the press slice: where the working stroke starts (item 1), constrained
optimisation that is not local (item 4), an optimum on the edge of its grid (item 11).

The reference here is independent of the kernel: the slider height from the
geometry alone (complex numbers, its θ-derivative by hand), sampled densely over
the turn, its dead centres and crossings polished by scipy's brentq. The rule it
checks (documented in ``cm.press.PressCriteria``): the working stroke starts at
the *first contact*, coming down from TDC the first α where S = S_p; if the
slider then backs off above S_p and comes down again before BDC, the design
*re-contacts* (status 4), which sweeps and the optimiser treat as failing.
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

TAU = 2 * math.pi
OMEGA_40 = 40 * TAU / 60
RECONTACTS = cm.press.STATUS[4]


def _y(th, R, r, d, L, phi0, offset=0.0):
    """Slider height y and dy/dθ at carrier angles θ (the module's frame)."""
    i = R / r
    k = i - 1
    beta = -k * th + i * (phi0 - math.pi / 2)
    p = (R - r) * np.exp(1j * th) + d * np.exp(1j * beta)
    dp = 1j * (R - r) * np.exp(1j * th) - 1j * k * d * np.exp(1j * beta)
    u = p.real - offset
    w = np.sqrt(L * L - u * u)
    return p.imag - w, dp.imag + u * dp.real / w


def reference(R, r, d, L, phi0, k_Sp, omega, n=1 << 19):
    """First contact by dense sampling: α_c, V there, how far the slider backs off
    above S_p afterwards (``lift``), how close an earlier dip came to S_p
    (``dip_margin``) and the lowest Π' inside the working stroke."""
    th = np.linspace(0.0, TAU, n, endpoint=False)
    y = _y(th, R, r, d, L, phi0)[0]
    h = TAU / n

    def polish(j):
        f = lambda x: float(_y(x, R, r, d, L, phi0)[1])  # noqa: E731
        t = brentq(f, th[j] - h, th[j] + h, xtol=1e-15, rtol=1e-15)
        return t, float(_y(t, R, r, d, L, phi0)[0])

    tb, yb = polish(int(np.argmin(y)))
    tt, yt = polish(int(np.argmax(y)))
    s_n = yt - yb
    s_p = k_Sp * s_n
    a_t = (tb - tt) % TAU
    alpha = np.arange(n + 1) * h
    s = _y(tb - alpha, R, r, d, L, phi0)[0] - yb
    ds = np.gradient(s, h)
    before_tdc = alpha < a_t
    j = int(np.flatnonzero(before_tdc & (s <= s_p)).max())

    def s_at(a):
        return float(_y(tb - a, R, r, d, L, phi0)[0]) - yb

    if k_Sp >= 1.0:
        a_c = a_t  # the whole stroke: first contact at TDC
    else:
        a_c = brentq(lambda a: s_at(a) - s_p, alpha[j], alpha[j + 1], xtol=1e-15, rtol=1e-15)
    v = -float(_y(tb - a_c, R, r, d, L, phi0)[1]) * omega
    q = np.arange(1, n)
    peak = (s[q] >= s[q - 1]) & (s[q] >= s[q + 1])
    valley = (s[q] <= s[q - 1]) & (s[q] <= s[q + 1])
    inside = alpha[q] < a_c
    after = (alpha[q] > a_c) & before_tdc[q]
    lift = float(np.max(s[q][peak & inside], initial=-np.inf) - s_p)
    dip = float(np.min(s[q][valley & after], initial=np.inf) - s_p)
    # Two dead centres within 1e-9 of the stroke: which one is BDC (TDC) is the
    # library's tie rule, not this reference's.
    ext = np.sort(y[((y <= np.roll(y, 1)) & (y <= np.roll(y, -1)))])
    top = np.sort(y[((y >= np.roll(y, 1)) & (y >= np.roll(y, -1)))])
    tie = (len(ext) > 1 and ext[1] - ext[0] < 1e-9 * s_n) or (
        len(top) > 1 and top[-1] - top[-2] < 1e-9 * s_n
    )
    return {
        "tie": bool(tie),
        "S_n": s_n,
        "alpha_c": a_c,
        "V_np": v,
        "lift": lift,
        "dip_margin": dip,
        "min_ds": float(ds[alpha < a_c].min()),
        "max_ds": float(ds[alpha < a_c].max()),
        "first_nearest_bdc": float(alpha[int(np.argmax(s >= s_p))]),
    }


def ref_status(ref):
    """The documented rule on the reference, None where sampling cannot decide."""
    tol = 1e-7 * ref["S_n"]
    if ref["tie"] or abs(ref["lift"]) < tol or ref["dip_margin"] < tol:
        return None
    if ref["lift"] > 0:
        return 4
    if ref["min_ds"] < -1e-6 * ref["max_ds"]:
        return 2
    if ref["min_ds"] > 1e-9 * ref["max_ds"]:
        return 0
    return None


# ---------------------------------------------------------------------------
# Item 1: the working stroke starts at the first contact


def test_item1_press_line_example_meets_the_blank_at_its_first_crossing():
    """The issue's press (R 0.09, r 0.03, d 0.028, L 0.46, φ0 56°, k_Sp 0.1, 40 rpm)
    was reported at V_np = 3.25 mm/s with α_p = 76.0°; coming down from TDC its
    slider first reaches S_p at α ≈ 126.2° at ≈ 58 mm/s, dips below it and backs
    off above it: status re-contacts, with the first contact's numbers."""
    args = (0.09, 0.03, 0.028, 0.46, math.radians(56.0))
    ref = reference(*args, 0.1, OMEGA_40)
    # The reference sees what the issue describes.
    assert math.degrees(ref["alpha_c"]) == pytest.approx(126.2, abs=0.05)
    assert ref["V_np"] == pytest.approx(0.058, abs=0.001)
    assert ref["lift"] > 1e-5  # backs off 14 µm above S_p before coming down again
    assert math.degrees(ref["first_nearest_bdc"]) == pytest.approx(76.0, abs=0.05)
    c = cm.press.GearLeverPress(*args).criteria(k_Sp=0.1, omega=OMEGA_40)
    assert c.status == RECONTACTS and not c.ok
    assert c.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-9)
    assert c.V_np == pytest.approx(ref["V_np"], rel=1e-7)
    assert c.V_cp == pytest.approx(c.S_p * OMEGA_40 / ref["alpha_c"], rel=1e-9)


def test_item1_the_dip_goes_below_s_p_before_it_backs_off():
    """The slider's path in the example between first contact and the old α_p, from
    the kinematics (not the criteria): it goes about 1.55 mm below S_p, then back
    above it."""
    p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.028, L=0.46, phi0=math.radians(56.0))
    c = p.criteria(k_Sp=0.1, omega=OMEGA_40)
    a = np.linspace(math.radians(76.5), c.alpha_p, 200_001)
    s = p.solve(a).s
    assert c.S_p - s.min() == pytest.approx(1.55e-3, abs=0.01e-3)
    assert s.max() > c.S_p  # it backs off above the blank: the tool leaves it


designs = st.builds(
    lambda d, L, phi0, k: (0.09, 0.03, d, L, math.radians(phi0), k),
    st.one_of(st.floats(0.0, 0.04), st.floats(0.024, 0.032)),
    st.floats(0.25, 0.5),
    st.one_of(st.floats(0.0, 120.0), st.floats(50.0, 62.0)),
    st.sampled_from([0.05, 0.1, 0.2, 0.5, 1.0]),
)


@settings(max_examples=30, deadline=None)
@given(designs)
@example((0.09, 0.03, 0.028, 0.46, math.radians(56.0), 0.1))
@example((0.09, 0.03, 0.03, 0.25, math.radians(50.0), 0.5))  # a cusp: reverses between samples
@example((0.09, 0.03, 0.029, 0.25, math.radians(56.0), 0.1))
def test_item1_first_contact_against_dense_sampling(design):
    """α_p is the first contact coming down from TDC and the status follows the
    documented rule, for any design, against the dense reference."""
    *geo, k = design
    ref = reference(*geo, k, 1.0, n=1 << 17)
    want = ref_status(ref)
    assume(want is not None)
    c = cm.press.GearLeverPress(*geo).criteria(k_Sp=k, omega=1.0)
    assert cm.press.STATUS[want] == c.status, (ref, c)
    assert c.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-8)
    assert c.V_np == pytest.approx(ref["V_np"], rel=1e-6, abs=1e-12)


def test_item1_a_reversal_between_two_samples_is_found():
    """d = r puts a cusp on the planet point's path: within the working stroke the
    slider stops and rises 8 nm (5.9e-8 of the stroke) over a stretch far narrower
    than a sample step. Dense sampling of the kinematics sees the rise; the criteria
    find it at every sample count from the local maximum of y' between samples
    (status 2, criteria kept)."""
    geo = (0.09, 0.03, 0.03, 0.25, math.radians(50.0))
    p = cm.press.GearLeverPress(*geo)
    c0 = p.criteria(k_Sp=0.5, omega=1.0)
    s = p.solve(np.linspace(0.0, c0.alpha_p, 2_000_001)).s
    rise = float(np.max(np.maximum.accumulate(s) - s))
    assert 1e-9 * c0.S_n < rise < 1e-7 * c0.S_n
    ref = reference(*geo, 0.5, 1.0, n=1 << 17)
    assert ref_status(ref) == 2
    for samples in (24, 90, 360, 2000):
        c = p.criteria(k_Sp=0.5, omega=1.0, samples=samples)
        assert c.status == cm.press.STATUS[2], samples
        assert not c.ok and c.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-8)
    # Moving d off the cusp by 1 mm: the slider only slows down, no reversal.
    ok = cm.press.GearLeverPress(0.09, 0.03, 0.029, 0.25, math.radians(50.0))
    ref = reference(0.09, 0.03, 0.029, 0.25, math.radians(50.0), 0.5, 1.0, n=1 << 17)
    assert ref_status(ref) == 0 and ok.criteria(k_Sp=0.5, omega=1.0).ok


def test_item1_first_contact_does_not_depend_on_the_sampling():
    """The example's first contact and status are the same from 24 to 2000 samples
    per turn, equal to the reference."""
    geo = (0.09, 0.03, 0.028, 0.46, math.radians(56.0))
    ref = reference(*geo, 0.1, 1.0)
    p = cm.press.GearLeverPress(*geo)
    for samples in (24, 37, 90, 181, 360, 720, 2000):
        c = p.criteria(k_Sp=0.1, omega=1.0, samples=samples)
        assert c.status == RECONTACTS, samples
        assert c.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-8), samples


def test_item1_a_dip_between_two_samples_is_found():
    """S_p 0.5 µm below the bottom of the example's dip: the dip never reaches the
    blank, the first contact is the later crossing and the design does not
    re-contact; 0.5 µm above it: the dip is the first contact (re-contacts). The
    stretch of the dip below S_p is then far narrower than a sample step, so only
    the refinement of the samples near S_p sees it."""
    geo = (0.09, 0.03, 0.028, 0.46, math.radians(56.0))
    p = cm.press.GearLeverPress(*geo)
    c = p.criteria(k_Sp=0.1, omega=1.0)
    a = np.linspace(c.alpha_p - 0.6, c.alpha_p + 0.01, 400_001)
    k = p.solve(a)
    # The dip's bottom: the last local minimum of S before first contact.
    q = np.flatnonzero((k.s[1:-1] <= k.s[:-2]) & (k.s[1:-1] <= k.s[2:])) + 1
    bottom, a_bottom = float(k.s[q[-1]]), float(a[q[-1]])
    for s_p, dips in ((bottom - 5e-7, False), (bottom + 5e-7, True)):
        ref = reference(*geo, s_p / c.S_n, 1.0)
        assert (ref["alpha_c"] > a_bottom) == dips
        for samples in (24, 360):
            got = p.criteria(working_stroke=s_p, omega=1.0, samples=samples)
            assert got.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-8), (samples, s_p)
            assert (got.status == RECONTACTS) == dips, (samples, s_p)


def test_item1_sweep_flags_recontacts_where_the_reference_does():
    """Over a grid around the example, the sweep's status is re-contacts exactly
    where the dense reference's slider backs off above S_p after first contact,
    and α_p is the first contact everywhere."""
    d = np.linspace(0.024, 0.034, 6)
    L = np.linspace(0.25, 0.5, 6)
    phi0 = np.radians(np.linspace(50.0, 62.0, 7))
    sw = cm.press.design_grid(R=0.09, r=0.03, d=d, L=L, phi0=phi0, k_Sp=0.1, omega=1.0)
    seen = {0: 0, 2: 0, 4: 0}
    for idx in np.ndindex(sw.shape):
        geo = (0.09, 0.03, d[idx[0]], L[idx[1]], phi0[idx[2]])
        ref = reference(*geo, 0.1, 1.0, n=1 << 16)
        want = ref_status(ref)
        if want is None:
            continue
        seen[want] += 1
        assert sw.status[idx] == want, (idx, ref)
        assert sw["alpha_p"][idx] == pytest.approx(ref["alpha_c"], abs=1e-7)
    assert seen[4] >= 10 and seen[0] >= 10  # both kinds are in the grid


def test_item1_optimiser_never_returns_a_recontacting_design():
    """The README's optimisation (4.19 rad/s, V_np ≤ 10 mm/s): every design returned
    meets the blank, by the reference, once, at its first contact and at most at
    the limit (the old kernel returned 4 of 10 that re-contact at 41–59 mm/s)."""
    opt = cm.press.optimize(
        R=0.09,
        r=0.03,
        d=np.linspace(0, 0.04, 41),
        L=np.linspace(0.25, 0.5, 26),
        phi0=np.radians(np.arange(0, 120, 2)),
        k_Sp=0.1,
        omega=4.19,
        limits={"V_np": 0.01},
    )
    assert (opt.grid.status == 4).sum() > 100  # the grid holds many that re-contact
    for p, c in zip(opt.designs, opt.criteria, strict=True):
        ref = reference(p.R, p.r, p.d, p.L, p.phi0, 0.1, 4.19)
        assert ref["lift"] < 0, p
        assert ref["V_np"] <= 0.01 * (1 + 1e-6), p
        assert c.ok and c.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-8)


# ---------------------------------------------------------------------------
# Item 4: constrained optimisation that is not local

W_README = 4.19
OBJ = ("k_Vp", "k_Vmax", "k_J", "k_M")


def _scorer(L_axis):
    """The optimiser's documented score (each objective over the crank-slider's of
    the grid's median rod, summed), written here from the criteria."""
    base = cm.press.GearLeverPress(
        R=0.09, r=0.03, d=0.0, L=float(np.median(L_axis)), phi0=0.0
    ).criteria(k_Sp=0.1, omega=W_README)
    norm = {k: abs(float(cm.press.OBJECTIVES[k](base.as_dict()))) for k in OBJ}

    def score(values):
        return sum(np.asarray(cm.press.OBJECTIVES[k](values)) / norm[k] for k in OBJ)

    return score


def _brute_force(score, centre, half, n, limit):
    """The best score that meets the limit on a dense grid (n per axis) of the box
    centre ± half (d, L, φ0), in the grid's bounds."""
    lo = np.maximum(np.subtract(centre, half), [0.0, 0.25, 0.0])
    hi = np.minimum(np.add(centre, half), [0.04, 0.5, math.radians(115)])
    sw = cm.press.design_grid(
        R=0.09,
        r=0.03,
        d=np.linspace(lo[0], hi[0], n[0]),
        L=np.linspace(lo[1], hi[1], n[1]),
        phi0=np.linspace(lo[2], hi[2], n[2]),
        k_Sp=0.1,
        omega=W_README,
    )
    sc = np.where(sw.ok & (sw["V_np"] <= limit), score(sw.values), np.inf)
    return float(sc.min())


def _differential_evolution(score, limit, seed):
    """scipy's differential evolution over the grid's box with the limit as a
    nonlinear constraint (failing designs: a large score and a broken limit)."""
    from scipy.optimize import NonlinearConstraint, differential_evolution

    cache = {}

    def crit(x):
        key = tuple(x)
        if key not in cache:
            p = cm.press.GearLeverPress(R=0.09, r=0.03, d=x[0], L=x[1], phi0=x[2])
            cache[key] = p.criteria(k_Sp=0.1, omega=W_README)
        return cache[key]

    def f(x):
        c = crit(x)
        return float(score(c.as_dict())) if c.ok else 1e3

    def g(x):
        c = crit(x)
        return c.V_np if c.ok else 1.0

    res = differential_evolution(
        f,
        [(0.0, 0.04), (0.25, 0.5), (0.0, math.radians(115))],
        constraints=NonlinearConstraint(g, -np.inf, limit),
        seed=seed,
        popsize=30,
        maxiter=400,
        polish=False,
        tol=1e-8,
    )
    return float(res.fun) if g(res.x) <= limit else math.inf, res.x


COARSE = {
    "R": 0.09,
    "r": 0.03,
    "d": np.linspace(0.0, 0.04, 9),
    "L": np.linspace(0.25, 0.5, 6),
    "phi0": np.radians(np.arange(0, 120, 5)),
    "k_Sp": 0.1,
    "omega": W_README,
}


@pytest.mark.slow
def test_item4_constrained_optimum_is_not_local():
    """On a coarse grid (5° in φ0) with V_np ≤ 10 mm/s only 2 grid designs meet the
    limit, in a basin of score ~3.16-3.22; the feasible designs of score ~2.99 lie
    in a band of φ0 ~0.2° wide between grid points. The optimiser (refined from a
    finer sweep, several starts, the limit inside the refinement) finds a design at
    least as good as scipy's differential evolution with the limit as a constraint
    (seed 1) and as a dense brute-force grid around DE's best, and it meets the
    limit by the independent reference. The old optimiser returned 3.159. (Seed 0
    also ran, 5 CPU-s: it settles in the 3.16 basin, so the minimum over both seeds,
    the reference and the brute force's centre were seed 1's; measured 3.1586 vs
    2.9926.)"""
    limit = 0.01
    opt = cm.press.optimize(**COARSE, limits={"V_np": limit})
    grid = opt.grid
    assert (grid.ok & (grid["V_np"] <= limit)).sum() <= 3
    score = _scorer(COARSE["L"])
    de_best, x_best = _differential_evolution(score, limit, seed=1)
    brute = _brute_force(score, x_best, [0.0015, 0.02, math.radians(0.2)], (31, 21, 81), limit)
    ref = min(de_best, brute)
    assert ref < 3.05  # the references see the better basin
    best, c = opt.designs[0], opt.criteria[0]
    assert float(score(c.as_dict())) == pytest.approx(opt.scores[0], rel=1e-12)
    assert opt.scores[0] <= ref + 2e-3, (opt.scores[0], de_best, brute)
    r = reference(best.R, best.r, best.d, best.L, best.phi0, 0.1, W_README)
    assert r["V_np"] <= limit * (1 + 1e-9) and r["lift"] < 0


def test_item4_a_limit_no_grid_design_meets_is_reached_by_refinement():
    """V_np ≤ 5 mm/s on a grid of 3 rods: no grid design meets it (the old optimiser
    raised InfeasibleError), but designs between the grid's points do: the
    optimiser returns them, each meeting the limit by the reference."""
    kw = dict(COARSE, L=np.linspace(0.25, 0.5, 3))
    sw = cm.press.design_grid(**{k: v for k, v in kw.items()})
    assert not (sw.ok & (sw["V_np"] <= 0.005)).any()
    opt = cm.press.optimize(**kw, limits={"V_np": 0.005})
    assert all(opt.refined)
    for p, c in zip(opt.designs, opt.criteria, strict=True):
        r = reference(p.R, p.r, p.d, p.L, p.phi0, 0.1, W_README, n=1 << 17)
        assert c.ok and r["V_np"] <= 0.005 * (1 + 1e-9) and r["lift"] < 0
    # Without refinement nothing on the grid meets it: a loud error naming it.
    with pytest.raises(cm.InfeasibleError, match="V_np"):
        cm.press.optimize(**kw, limits={"V_np": 0.005}, refine=0)


@settings(max_examples=6, deadline=None)
@given(limit=st.floats(0.004, 0.05), nl=st.integers(2, 6))
def test_item4_refined_designs_meet_the_limits_and_beat_the_grid(limit, nl):
    """For any limit on V_np: every design returned meets it (criteria and the
    reference), the designs are mutually non-dominated, and the best score is no
    worse than the best grid design that meets the limit."""
    kw = dict(COARSE, L=np.linspace(0.25, 0.5, nl))
    try:
        opt = cm.press.optimize(**kw, limits={"V_np": limit}, refine=2)
    except cm.InfeasibleError:
        assume(False)
    grid = opt.grid
    score = _scorer(kw["L"])
    usable = grid.ok & (grid["V_np"] <= limit)
    if usable.any():
        assert opt.scores[0] <= float(score(grid.values)[usable].min()) + 1e-12
    objs = np.array([[_objectives_of(c)[k] for k in OBJ] for c in opt.criteria])
    for i, (p, c) in enumerate(zip(opt.designs, opt.criteria, strict=True)):
        assert c.ok and c.V_np <= limit
        r = reference(p.R, p.r, p.d, p.L, p.phi0, 0.1, W_README, n=1 << 16)
        assert r["V_np"] <= limit * (1 + 1e-6) and r["lift"] < 0
        others = np.delete(objs, i, axis=0)
        assert not ((others <= objs[i]).all(1) & (others < objs[i]).any(1)).any()


def _objectives_of(c):
    return {k: float(cm.press.OBJECTIVES[k](c.as_dict())) for k in OBJ}


# ---------------------------------------------------------------------------
# Item 11: an optimum on the edge of its grid is said


README_GRID = {
    "R": 0.09,
    "r": 0.03,
    "d": np.linspace(0, 0.04, 41),
    "L": np.linspace(0.25, 0.5, 26),
    "phi0": np.radians(np.arange(0, 120, 2)),
    "k_Sp": 0.1,
    "omega": W_README,
}


def test_item11_optimum_on_the_edge_of_its_grid_is_said():
    """The README's optimisation: the best design has L within half a step of the
    grid's lowest rod 250 mm, and the result says so (the old result said nothing).
    With rods down to 150 mm the best design is inside its grid: no warning. φ0
    spans a whole period (0-118° in 2° steps, i = 3): never an edge."""
    opt = cm.press.optimize(**README_GRID, limits={"V_np": 0.01})
    best = opt.designs[0]
    assert abs(best.L - 0.25) <= 0.005
    assert len(opt.edges) == 1 and opt.edges[0].startswith("L = ")
    assert "lower bound 250 mm" in opt.edges[0]
    wider = cm.press.optimize(
        **dict(README_GRID, L=np.linspace(0.15, 0.5, 36)), limits={"V_np": 0.01}
    )
    axis = wider.grid.axes["L"]
    assert axis[0] + 0.005 < wider.designs[0].L < axis[-1] - 0.005
    assert wider.edges == ()


def test_item11_edges_rule_on_each_axis():
    """The rule on small grids: a swept axis's first or last value, within half a
    step, is an edge (both bounds, every axis); d = 0 and a φ0 axis spanning a whole
    period are not; a single-valued axis is not swept."""
    from cyclomech.press._optimize import _edges

    sw = cm.press.design_grid(
        R=0.09,
        r=0.03,
        d=[0.0, 0.01, 0.02],
        L=[0.3, 0.35, 0.4],
        phi0=np.radians([10.0, 15.0, 20.0]),
        k_Sp=0.1,
        omega=1.0,
    )
    p = cm.press.GearLeverPress
    at = lambda d, L, phi: p(R=0.09, r=0.03, d=d, L=L, phi0=math.radians(phi))  # noqa: E731
    assert _edges(sw, at(0.01, 0.35, 15.0), ratio=3) == ()
    assert _edges(sw, at(0.0051, 0.3251, 12.51), ratio=3) == ()  # just over half a step
    e = _edges(sw, at(0.0, 0.3, 10.0), ratio=3)
    assert [x.split(" ")[0] for x in e] == ["L", "phi0"]  # not d = 0
    assert all("lower bound" in x for x in e)
    e = _edges(sw, at(0.0151, 0.3751, 17.51), ratio=3)
    assert [x.split(" ")[0] for x in e] == ["d", "L", "phi0"]
    assert all("upper bound" in x for x in e)
    full = cm.press.design_grid(
        R=0.09,
        r=0.03,
        d=0.02,
        L=[0.3, 0.35, 0.4],
        phi0=np.radians(np.arange(0, 120, 10)),
        k_Sp=0.1,
        omega=1.0,
    )
    assert _edges(full, at(0.02, 0.35, 0.0), ratio=3) == ()


def test_item11_cli_warns_when_the_best_design_is_on_the_edge(tmp_path, capsys):
    """`cyclomech press` prints the edge and writes it to press.json."""
    import json

    from cyclomech.cli import main

    text = """
[press]
R_m = 0.09
r_m = 0.03
d_m = 0.029
L_m = 0.25
phi0_deg = 55.95
[working]
k_Sp = 0.1
rpm = 40.0
[sweep]
d_m = [0.0, 0.04, 41]
L_m = [0.25, 0.5, 26]
phi0_deg = [0.0, 118.0, 60]
[limits]
V_np = 0.01
"""
    f = tmp_path / "p.toml"
    f.write_text(text, encoding="utf-8")
    code = main(["press", str(f), "--out", str(tmp_path / "o"), "--no-plot"])
    out, _ = capsys.readouterr()
    assert code == 0
    assert "warning: the best design is on the edge of the grid: L = " in out
    summary = json.loads((tmp_path / "o" / "press.json").read_text())
    edges = summary["optimum"]["best_on_grid_edge"]
    assert len(edges) == 1 and "lower bound 250 mm" in edges[0]


# ---------------------------------------------------------------------------
# Item 1, the rule's ambiguous cases (documented in cm.press.PressCriteria)


def test_item1_a_rise_above_s_p_within_1e9_of_the_stroke_is_a_touch():
    """The example's slider, after first contact, rises back to a local maximum H of
    S (14 µm above its S_p) before coming down again. With S_p set just below H it
    leaves the blank by δ: re-contacts when δ > 1e-9·S_n, a touch (it only moves
    back up: status 2) below that; S_p just above H: it never leaves (status 2).
    H from the reference (dense samples, brentq on y')."""
    geo = (0.09, 0.03, 0.028, 0.46, math.radians(56.0))
    p = cm.press.GearLeverPress(*geo)
    c = p.criteria(k_Sp=0.1, omega=1.0)
    ref = reference(*geo, 0.1, 1.0)
    height = c.S_p + ref["lift"]  # the local maximum after first contact (sampled)
    # Polish it: the root of y' next to the sampled peak.
    a = np.linspace(math.radians(76.5), c.alpha_p - 0.01, 100_001)
    s = p.solve(a).s
    j = int(np.argmax(s))
    tb = c.theta_bdc
    t = brentq(lambda x: float(_y(tb - x, *geo)[1]), a[j - 1], a[j + 1], xtol=1e-15, rtol=1e-15)
    height = max(height, float(p.solve(np.array([t])).s[0]))
    s_n = c.S_n
    cases = ((1e-7, RECONTACTS), (-1e-7, cm.press.STATUS[2]), (1e-11, cm.press.STATUS[2]))
    for delta, want in cases:
        got = p.criteria(working_stroke=height - delta * s_n, omega=1.0)
        assert got.status == want, (delta, got.status)


def test_item1_a_dip_on_the_way_up_is_not_a_contact():
    """S_p is watched from TDC down to BDC: this slider (d 37.7 mm, L 300 mm, φ0
    61.46°) rises above S_p after BDC, dips below it and rises again to TDC (by the
    reference, over the up-stroke), yet comes down from TDC to BDC cleanly: ok, its
    first contact the reference's."""
    geo = (0.09, 0.03, 0.037747, 0.299825, math.radians(61.46084))
    th = np.linspace(0.0, TAU, 1 << 18, endpoint=False)
    y = _y(th, *geo)[0]
    jb, jt = int(np.argmin(y)), int(np.argmax(y))
    s = y - y[jb]
    s_p = 0.1 * s[jt]
    up = s[(jb + np.arange((jt - jb) % th.size + 1)) % th.size]  # BDC → TDC in time
    first_above = int(np.argmax(up > s_p))
    assert (up[first_above:] < s_p - 1e-4).any()  # a dip 0.1 mm below S_p on the way up
    ref = reference(*geo, 0.1, 1.0)
    assert ref_status(ref) == 0
    c = cm.press.GearLeverPress(*geo).criteria(k_Sp=0.1, omega=1.0)
    assert c.ok and c.alpha_p == pytest.approx(ref["alpha_c"], abs=1e-8)
