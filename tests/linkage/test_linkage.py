"""Linkages (class II): positions and analogs against independent references.

* The four-bar's rocker angle against the textbook closed form of the Freudenstein
  equation (half-angle substitution; Norton, *Design of Machinery*, eq. 4.10),
  for both assembly modes, and the Freudenstein residual itself.
* Velocity and acceleration analogs against central finite differences of the
  positions.
* The angles where a non-Grashof linkage cannot be assembled, from the triangle
  inequality on |BD|, computed here.
"""

from __future__ import annotations

import itertools
import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

TAU = 2 * math.pi


def four_bar(r: float, l2: float, l3: float, d: float, up: bool = True) -> cm.Linkage:
    """Crank A–B (r), coupler B–C (l2), rocker C–D (l3), ground A = (0, 0), D = (d, 0),
    drawn at φ = 90° with C above (``up``) or below the line B–D."""
    b = (0.0, r)
    bd = math.hypot(d, r)
    x = (l2**2 - l3**2 + bd**2) / (2 * bd)
    h = math.sqrt(l2**2 - x**2)
    ex, ey = d / bd, -r / bd
    s = 1.0 if up else -1.0
    c = (b[0] + x * ex - s * h * ey, b[1] + x * ey + s * h * ex)
    return cm.Linkage(
        {"A": (0.0, 0.0), "B": b, "C": c, "D": (d, 0.0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def freudenstein_theta4(phi, r, l2, l3, d, mode):
    """Rocker angle θ4 (of D→C) by the half-angle closed form; mode ±1."""
    k1, k2 = d / r, d / l3
    k3 = (r**2 - l2**2 + l3**2 + d**2) / (2 * r * l3)
    a = np.cos(phi) - k1 - k2 * np.cos(phi) + k3
    b = -2 * np.sin(phi)
    c = k1 - (k2 + 1) * np.cos(phi) + k3
    return 2 * np.arctan2(-b + mode * np.sqrt(b * b - 4 * a * c), 2 * a)


CRANK_ROCKER = (1.0, 3.5, 3.0, 4.0)  # r, l2, l3, d: Grashof, crank shortest


@pytest.mark.parametrize("up", [True, False])
def test_crank_rocker_matches_the_freudenstein_closed_form(up: bool) -> None:
    r, l2, l3, d = CRANK_ROCKER
    lk = four_bar(r, l2, l3, d, up)
    phi = np.linspace(0, TAU, 3601)
    sol = lk.solve(phi)
    assert sol.ok.all() and not sol.singular.any()
    c = sol["C"]
    theta4 = np.arctan2(c[:, 1], c[:, 0] - d)
    # One of the two closed-form roots, the same one all the way round: the
    # drawn assembly mode is kept.
    roots = [freudenstein_theta4(phi, r, l2, l3, d, m) for m in (1, -1)]
    errs = [np.abs(np.angle(np.exp(1j * (theta4 - t)))).max() for t in roots]
    assert min(errs) < 1e-10
    # The Freudenstein equation itself holds.
    k1, k2 = d / r, d / l3
    k3 = (r**2 - l2**2 + l3**2 + d**2) / (2 * r * l3)
    residual = k1 * np.cos(theta4) - k2 * np.cos(phi) + k3 - np.cos(phi - theta4)
    assert np.abs(residual).max() < 1e-12
    # Link lengths hold.
    assert_allclose(np.linalg.norm(c - sol["B"], axis=1), l2, rtol=1e-13)
    assert_allclose(np.linalg.norm(c - sol["D"], axis=1), l3, rtol=1e-13)


def test_the_two_assembly_modes_are_the_two_roots() -> None:
    r, l2, l3, d = CRANK_ROCKER
    phi = np.linspace(0, TAU, 721)
    got = []
    for up in (True, False):
        c = four_bar(r, l2, l3, d, up).solve(phi)["C"]
        got.append(np.arctan2(c[:, 1], c[:, 0] - d))
    roots = [freudenstein_theta4(phi, r, l2, l3, d, m) for m in (1, -1)]
    wrap = lambda a, b: np.abs(np.angle(np.exp(1j * (a - b)))).max()  # noqa: E731
    assert (
        min(
            wrap(got[0], roots[0]) + wrap(got[1], roots[1]),
            wrap(got[0], roots[1]) + wrap(got[1], roots[0]),
        )
        < 1e-9
    )
    assert wrap(got[0], got[1]) > 0.1  # different branches


def test_analogs_match_finite_differences() -> None:
    r, l2, l3, d = CRANK_ROCKER
    lk = four_bar(r, l2, l3, d)
    phi = np.linspace(0.01, TAU, 200)
    h = 1e-5
    mid, lo, hi = lk.solve(phi), lk.solve(phi - h), lk.solve(phi + h)
    assert_allclose(mid.vel, (hi.xy - lo.xy) / (2 * h), atol=1e-8)
    assert_allclose(mid.acc, (hi.xy - 2 * mid.xy + lo.xy) / h**2, atol=2e-4)
    # Link angle analogs too.
    t, dt, ddt = mid.link_angle("C", "D")
    t_lo, _, _ = lo.link_angle("C", "D")
    t_hi, _, _ = hi.link_angle("C", "D")
    assert_allclose(dt, np.angle(np.exp(1j * (t_hi - t_lo))) / (2 * h), atol=1e-8)
    fd2 = (np.angle(np.exp(1j * (t_hi - t))) - np.angle(np.exp(1j * (t - t_lo)))) / h**2
    assert_allclose(ddt, fd2, atol=2e-4)


def test_non_grashof_flags_exactly_the_unassemblable_angles() -> None:
    r, l2, l3, d = 2.0, 2.0, 2.5, 3.0  # the crank cannot turn fully
    lk = four_bar(r, l2, l3, d)
    phi = np.linspace(0, TAU, 7201)
    sol = lk.solve(phi)
    bd = np.sqrt(r * r + d * d - 2 * r * d * np.cos(phi))
    feasible = (bd <= l2 + l3) & (bd >= abs(l2 - l3))
    margin = np.minimum(np.abs(bd - (l2 + l3)), np.abs(bd - abs(l2 - l3)))
    clear = margin > 1e-9  # leave the tangent angles themselves out
    assert (~feasible).any() and feasible.any()
    assert_array_equal(sol.ok[clear], feasible[clear])
    assert np.isnan(sol.xy[~sol.ok][:, 1:]).all()  # every point but the fixed A
    assert not np.isnan(sol.xy[sol.ok]).any()


def test_dead_centre_is_flagged_not_taken() -> None:
    # Change-point linkage r + l2 = l3 + d: at φ = 0 the coupler folds onto the rocker.
    lk = four_bar(1.0, 3.0, 2.0, 2.0)
    sol = lk.solve([0.0, 0.5])
    assert sol.ok.tolist() == [True, True]
    assert sol.singular.tolist() == [True, False]
    assert np.isnan(sol.vel[0, lk.names.index("C")]).all()
    assert np.isfinite(sol.vel[1]).all()


def test_coupler_point_of_a_ternary_link() -> None:
    pts = {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0), "E": (2.0, 3.5)}
    lk = cm.Linkage(pts, [("A", "B"), ("B", "C", "E"), ("C", "D")], ["A", "D"], ("A", "B"))
    assert lk.structure == [("driver", ("B",)), ("II", ("C",)), ("point", ("E",))]
    sol = lk.solve(np.linspace(0, TAU, 361))
    for a, b in (("B", "E"), ("C", "E"), ("B", "C")):
        want = math.dist(pts[a], pts[b])
        assert_allclose(np.linalg.norm(sol[a] - sol[b], axis=1), want, rtol=1e-12)
    # E stays on the side of B→C where it was drawn (a rigid body does not flip).
    bc, be = sol["C"] - sol["B"], sol["E"] - sol["B"]
    assert (bc[:, 0] * be[:, 1] - bc[:, 1] * be[:, 0] > 0).all()
    # The drawn pose is reproduced at the drawn crank angle.
    at = lk.solve([lk.drawn_angle])
    assert_allclose(at.xy[0], [pts[n] for n in lk.names], atol=1e-12)


def test_six_bar_with_two_dyads_in_series() -> None:
    # Watt II: a four-bar A-B-C-D drives a second dyad C-E-F from the rocker's
    # extension (ternary rocker C-D-G) to ground F.
    pts = {
        "A": (0, 0),
        "B": (1, 0),
        "C": (3.5, 2.5),
        "D": (4, 0),
        "G": (5.5, 1.0),
        "E": (7.0, 3.0),
        "F": (8.0, 0.0),
    }
    links = [("A", "B"), ("B", "C"), ("C", "D", "G"), ("G", "E"), ("E", "F")]
    lk = cm.Linkage(pts, links, ["A", "D", "F"], ("A", "B"))
    assert [s[0] for s in lk.structure] == ["driver", "II", "point", "II"]
    sol = lk.solve(np.linspace(0, TAU, 721))
    assert sol.ok.all()
    for ln in links:
        for a, b in itertools.pairwise(ln):
            want = math.dist(pts[a], pts[b])
            assert_allclose(np.linalg.norm(sol[a] - sol[b], axis=1), want, rtol=1e-12)


@given(
    r=st.floats(0.3, 1.0),
    l2=st.floats(2.0, 4.0),
    l3=st.floats(2.0, 4.0),
    d=st.floats(2.0, 4.0),
    up=st.booleans(),
)
def test_random_grashof_crank_rockers(r: float, l2: float, l3: float, d: float, up: bool) -> None:
    short, p, q, long_ = sorted([r, l2, l3, d])
    # A crank-rocker (the crank is the shortest link), clear of the change point.
    assume(r == short and short + long_ < p + q - 1e-2)
    lk = four_bar(r, l2, l3, d, up)
    phi = np.linspace(0, TAU, 181)
    h = 1e-5
    mid, lo, hi = lk.solve(phi), lk.solve(phi - h), lk.solve(phi + h)
    assert mid.ok.all()
    size = r + l2 + l3 + d
    for a, b, length in (("B", "C", l2), ("C", "D", l3)):
        closure = np.abs(np.linalg.norm(mid[a] - mid[b], axis=1) - length).max()
        assert closure <= 1e-12 * size
    # No branch jump: between neighbouring angles C moves no more than its
    # velocity analog allows.
    c = lk.names.index("C")
    step = np.linalg.norm(np.diff(mid.xy[:, c], axis=0), axis=1)
    speed = np.linalg.norm(mid.vel[:, c], axis=1)
    assert (step <= 1.5 * speed.max() * (phi[1] - phi[0]) + 1e-12).all()
    assert_allclose(mid.vel, (hi.xy - lo.xy) / (2 * h), atol=1e-6 * size)


def test_threads_give_identical_results() -> None:
    lk = four_bar(*CRANK_ROCKER)
    phi = np.linspace(0, 50 * TAU, 20_000)  # above the parallel threshold
    one, two = lk.solve(phi, n_threads=1), lk.solve(phi, n_threads=2)
    assert_array_equal(one.xy, two.xy)
    assert_array_equal(one.acc, two.acc)


def test_linkage_and_solution_pickle() -> None:
    lk = four_bar(*CRANK_ROCKER)
    back = pickle.loads(pickle.dumps(lk))
    assert back.structure == lk.structure
    sol = lk.solve([0.1, 0.2])
    assert_array_equal(pickle.loads(pickle.dumps(sol)).xy, sol.xy)
    assert_array_equal(back.solve([0.1, 0.2]).xy, sol.xy)


FOUR = {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)}
LINKS = [("A", "B"), ("B", "C"), ("C", "D")]
SLIDER_CRANK = {"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)}
SC_LINKS = [("A", "B"), ("B", "C")]
# Inverted slider-crank: block at the crank tip B slides on the rocker O–C.
INVERTED = {"A": (0, 0), "B": (0.1, 0), "O": (0, -0.25)}
INVERTED["C"] = (0.5 * 0.1 / math.hypot(0.1, 0.25), -0.25 + 0.5 * 0.25 / math.hypot(0.1, 0.25))
INV_LINKS = [("A", "B"), ("O", "C")]
BAD = {
    "under-constrained five-bar": (
        dict(
            points={**FOUR, "E": (5, 2)},
            links=[("A", "B"), ("B", "C"), ("C", "E"), ("E", "D")],
            ground=["A", "D"],
            driver=("A", "B"),
        ),
        ["under-constrained", "M = 3·4 links − 2·5 joints = 2"],
    ),
    "over-constrained truss": (
        dict(points=FOUR, links=[*LINKS, ("B", "D")], ground=["A", "D"], driver=("A", "B")),
        ["over-constrained", "M = 3·4 links − 2·6 joints = 0"],
    ),
    "pivot not ground": (
        dict(points=FOUR, links=LINKS, ground=["D"], driver=("A", "B")),
        ["pivot 'A' must be a ground joint"],
    ),
    "driver not a link": (
        dict(points=FOUR, links=LINKS, ground=["A", "D"], driver=("A", "C")),
        ["no link joins 'A' and 'C'"],
    ),
    "unknown point in a link": (
        dict(points=FOUR, links=[*LINKS[:2], ("C", "Z")], ground=["A", "D"], driver=("A", "B")),
        ["no point 'Z'"],
    ),
    "NaN coordinate": (
        dict(
            points={**FOUR, "C": (float("nan"), 2.5)},
            links=LINKS,
            ground=["A", "D"],
            driver=("A", "B"),
        ),
        ["points['C']", "finite"],
    ),
    "collinear drawn pose": (
        dict(points={**FOUR, "C": (2.5, 0.0)}, links=LINKS, ground=["A", "D"], driver=("A", "B")),
        ["'C' is drawn on the line through", "assembly mode"],
    ),
    "joint listed twice": (
        dict(points=FOUR, links=[*LINKS, ("B", "B")], ground=["A", "D"], driver=("A", "B")),
        ["lists a joint twice"],
    ),
    "one-joint link": (
        dict(points=FOUR, links=[*LINKS, ("B",)], ground=["A", "D"], driver=("A", "B")),
        ["at least two joints"],
    ),
    "slider over-constraining a four-bar": (
        dict(
            points=FOUR,
            links=LINKS,
            ground=["A", "D"],
            driver=("A", "B"),
            sliders={"C": ("ground", (1, 0))},
        ),
        ["over-constrained", "1 guides", "remove a link, a joint or a guide"],
    ),
    "slider on a ground joint": (
        dict(
            points=FOUR,
            links=LINKS,
            ground=["A", "D"],
            driver=("A", "B"),
            sliders={"D": ("ground", (1, 0))},
        ),
        ["sliders['D']", "ground joint"],
    ),
    "zero guide direction": (
        dict(
            points=SLIDER_CRANK,
            links=SC_LINKS,
            ground=["A"],
            driver=("A", "B"),
            sliders={"C": ("ground", (0, 0))},
        ),
        ["sliders['C']", "non-zero (dx, dy)"],
    ),
    "NaN guide direction": (
        dict(
            points=SLIDER_CRANK,
            links=SC_LINKS,
            ground=["A"],
            driver=("A", "B"),
            sliders={"C": ("ground", (float("nan"), 1))},
        ),
        ["sliders['C']", "finite"],
    ),
    "unknown guide kind": (
        dict(
            points=SLIDER_CRANK,
            links=SC_LINKS,
            ground=["A"],
            driver=("A", "B"),
            sliders={"C": ("rail", (1, 0))},
        ),
        ["('ground', (dx, dy)) or ('link', (b, c))"],
    ),
    "guide along a non-link": (
        dict(
            points=SLIDER_CRANK,
            links=SC_LINKS,
            ground=["A"],
            driver=("A", "B"),
            sliders={"C": ("link", ("A", "C"))},
        ),
        ["not two joints of one link"],
    ),
    "slider drawn off its link": (
        dict(
            points={**INVERTED, "B": (0.1, 0.05)},
            links=INV_LINKS,
            ground=["A", "O"],
            driver=("A", "B"),
            sliders={"B": ("link", ("O", "C"))},
        ),
        ["drawn off it"],
    ),
    "slider crank drawn at dead centre": (
        dict(
            points={"A": (0, 0), "B": (0.1, 0), "C": (0.1, 0.3)},
            links=SC_LINKS,
            ground=["A"],
            driver=("A", "B"),
            sliders={"C": ("ground", (1, 0))},
        ),
        ["perpendicular to its guide"],
    ),
    "length of a non-link pair": (
        dict(
            points=FOUR,
            links=LINKS,
            ground=["A", "D"],
            driver=("A", "B"),
            lengths={("A", "C"): 2.0},
        ),
        ["not joints of one link"],
    ),
    "negative length": (
        dict(
            points=FOUR,
            links=LINKS,
            ground=["A", "D"],
            driver=("A", "B"),
            lengths={("B", "C"): -2.0},
        ),
        ["positive length"],
    ),
}


@pytest.mark.parametrize(("kwargs", "words"), BAD.values(), ids=BAD.keys())
def test_bad_linkages_are_refused_clearly(kwargs: dict, words: list[str]) -> None:
    with pytest.raises(cm.InputError) as err:
        cm.Linkage(**kwargs)
    assert isinstance(err.value, ValueError)
    for w in words:
        assert w in str(err.value), (w, str(err.value))


@pytest.mark.parametrize("angles", [[float("nan")], [[0.0, 1.0]], ["a"]])
def test_bad_angles_are_refused(angles: object) -> None:
    with pytest.raises(cm.InputError, match="angles"):
        four_bar(*CRANK_ROCKER).solve(angles)


def test_lengths_override_the_drawn_distance() -> None:
    lk = cm.Linkage(FOUR, LINKS, ["A", "D"], ("A", "B"), lengths={("B", "C"): 3.0})
    sol = lk.solve(np.linspace(0, TAU, 91))
    assert_allclose(np.linalg.norm(sol["C"] - sol["B"], axis=1), 3.0, rtol=1e-13)


# ---------------------------------------------------------------------------
# Class III: a ternary link C-E-G held by B-C (B on the crank), E-F and G-H
# ---------------------------------------------------------------------------

TRIAD_POINTS = {
    "A": (0.0, 0.0),
    "B": (0.0, 0.2),
    "C": (1.5, 1.2),
    "E": (2.5, 0.8),
    "G": (2.0, 2.2),
    "F": (3.2, -0.6),
    "H": (3.1, 3.4),
}
TRIAD_LINKS = [("A", "B"), ("B", "C"), ("C", "E", "G"), ("E", "F"), ("G", "H")]
TRIAD_PAIRS = [("B", "C"), ("E", "F"), ("G", "H"), ("C", "E"), ("E", "G"), ("G", "C")]


def triad_linkage() -> cm.Linkage:
    return cm.Linkage(TRIAD_POINTS, TRIAD_LINKS, ["A", "F", "H"], ("A", "B"))


def scipy_continuation(angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Independent reference: scipy's least squares on the six closure equations,
    continued angle by angle from the drawn pose. Returns C, E, G (N, 3, 2) and
    the final cost at each angle (0 where the mechanism closes)."""
    from scipy.optimize import least_squares

    p = {k: np.array(v) for k, v in TRIAD_POINTS.items()}
    length = {ab: math.dist(TRIAD_POINTS[ab[0]], TRIAD_POINTS[ab[1]]) for ab in TRIAD_PAIRS}
    r = math.dist(TRIAD_POINTS["A"], TRIAD_POINTS["B"])

    def residual(x: np.ndarray, phi: float) -> list[float]:
        at = {"C": x[:2], "E": x[2:4], "G": x[4:], "F": p["F"], "H": p["H"]}
        at["B"] = r * np.array([math.cos(phi), math.sin(phi)])
        return [np.linalg.norm(at[a] - at[b]) - length[a, b] for a, b in TRIAD_PAIRS]

    x = np.r_[p["C"], p["E"], p["G"]]
    out, cost = [], []
    for phi in angles:
        fit = least_squares(residual, x, args=(phi,), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        x = fit.x
        out.append(x.reshape(3, 2))
        cost.append(fit.cost)
    return np.array(out), np.array(cost)


def test_class_iii_group_is_found() -> None:
    assert triad_linkage().structure == [("driver", ("B",)), ("III", ("C", "E", "G"))]


@pytest.mark.parametrize("end_deg", [110.0, 0.0])
def test_class_iii_matches_an_independent_root_finder(end_deg: float) -> None:
    lk = triad_linkage()
    # Walk from the drawn crank angle (90°) up to 110° or down to 0°.
    phi = np.radians(np.linspace(90.0, end_deg, 81))
    sol = lk.solve(phi)
    want, cost = scipy_continuation(phi)
    assert sol.ok.all() and (cost < 1e-24).all()
    got = np.stack([sol["C"], sol["E"], sol["G"]], axis=1)
    assert_allclose(got, want, atol=1e-9)
    for a, b in TRIAD_PAIRS:
        length = math.dist(TRIAD_POINTS[a], TRIAD_POINTS[b])
        assert np.abs(np.linalg.norm(sol[a] - sol[b], axis=1) - length).max() <= 1e-12


def test_class_iii_limit_position_agrees_with_the_root_finder() -> None:
    # Past about 111.1° the group cannot close (scipy's least cost turns positive):
    # cyclomech flags those angles, continuing from the drawn pose.
    phi = np.radians([110.5, 111.0, 111.5, 112.0, 150.0])
    sol = triad_linkage().solve(phi)
    _, cost = scipy_continuation(
        np.radians(np.r_[np.linspace(90.0, 110.5, 42), [111.0, 111.5, 112.0]])
    )
    assert cost[-3] < 1e-24 and cost[-2] > 1e-12 and cost[-1] > 1e-12
    assert sol.ok.tolist() == [True, True, False, False, False]


def test_class_iii_analogs_match_finite_differences() -> None:
    lk = triad_linkage()
    phi = np.radians(np.linspace(20.0, 100.0, 41))
    h = 1e-5
    mid, lo, hi = lk.solve(phi), lk.solve(phi - h), lk.solve(phi + h)
    assert mid.ok.all() and lo.ok.all() and hi.ok.all()
    assert_allclose(mid.vel, (hi.xy - lo.xy) / (2 * h), atol=1e-7)
    assert_allclose(mid.acc, (hi.xy - 2 * mid.xy + lo.xy) / h**2, atol=1e-3)


def test_class_iii_follows_the_drawn_pose_whatever_the_grid_order() -> None:
    lk = triad_linkage()
    at = lk.solve([lk.drawn_angle])
    assert_allclose(at.xy[0], [TRIAD_POINTS[n] for n in lk.names], atol=1e-12)
    phi = np.radians([100.0, 10.0, 55.0, 90.0, 30.0])  # unsorted, straddling 90°
    sol = lk.solve(phi)
    one_by_one = np.concatenate([lk.solve([p]).xy for p in phi])
    assert_allclose(sol.xy, one_by_one, atol=1e-12)


def test_a_link_drawn_with_zero_length_is_named() -> None:
    # Was "step 0 of the program is invalid: lengths must be finite and positive".
    with pytest.raises(cm.InputError, match=r"link AB has zero length: A and B are drawn"):
        cm.Linkage(
            points={"A": (0, 0), "B": (0, 0), "C": (3.5, 2.5), "D": (4, 0)},
            links=[("A", "B"), ("B", "C"), ("C", "D")],
            ground=["A", "D"],
            driver=("A", "B"),
        )
