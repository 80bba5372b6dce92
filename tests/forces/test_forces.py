"""Kinetostatics of linkages (issue 19) against independent references: a dense
pin-node solve in numpy (tests/forces/forces_reference.py), the power balance from
positions by finite differences, Lagrange's equation for a four-bar derived with
sympy, the textbook slider-crank, static equilibrium of the whole mechanism, and
bad input."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.linkage import presets
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).parent))
from forces_reference import compact_kinetostatics, dense_kinetostatics

F = cm.forces
G = (0.0, -9.81)
RAD = 2 * math.pi / 60


def four_bar() -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (0.1, 0), "C": (0.3, 0.25), "D": (0.4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def slider_crank(r: float = 0.1, rod: float = 0.35) -> cm.Linkage:
    return cm.Linkage(
        {"O": (0, 0), "A": (r, 0), "C": (r + rod, 0)},
        [("O", "A"), ("A", "C")],
        ["O"],
        ("O", "A"),
        sliders={"C": ("ground", (1, 0))},
    )


def shaper() -> cm.Linkage:
    """An inverted slider-crank (RPR): a block at A on the crank slides on the rocker B–C."""
    a, b = np.array([0.1, 0.0]), np.array([0.0, -0.3])
    c = b + 0.6 * (a - b) / np.linalg.norm(a - b)
    return cm.Linkage(
        {"O": (0, 0), "A": tuple(a), "B": tuple(b), "C": tuple(c)},
        [("O", "A"), ("B", "C")],
        ["O", "B"],
        ("O", "A"),
        sliders={"A": ("link", ("B", "C"))},
    )


def cross_guides() -> cm.Linkage:
    """A PRP dyad: P, on no link, slides on a vertical guide of the frame and along
    the rod A–C of a slider-crank (two blocks pinned together at P)."""
    return cm.Linkage(
        {"O": (0, 0), "A": (0.1, 0.02), "C": (0.45, 0.0), "P": (0.3, 0.02 * 0.15 / 0.35)},
        [("O", "A"), ("A", "C")],
        ["O"],
        ("O", "A"),
        sliders={"C": ("ground", (1, 0)), "P": [("ground", (0, 1)), ("link", ("A", "C"))]},
    )


def loaded(lk: cm.Linkage, seed: int = 1) -> dict:
    """Masses, inertias and off-axis centres on every moving link, a point mass
    and a load table on the last point, gravity."""
    rng = np.random.default_rng(seed)
    t = lk.to_dict()
    ground = set(t["ground"])
    masses = {}
    for ln in t["links"]:
        if set(ln) <= ground:
            continue
        pts = np.array([t["points"][p] for p in ln])
        com = pts.mean(axis=0) + rng.uniform(-0.05, 0.05, 2)
        masses[tuple(ln)] = F.LinkMass(rng.uniform(1, 10), tuple(com), rng.uniform(0, 0.2))
    last = [p for p in lk.names if p not in ground][-1]  # a moving point
    table = F.PointLoad(last, [[0, -300.0], [100.0, -800.0], [0, -300.0]], angle_deg=[40, 120, 200])
    return {
        "masses": masses,
        "point_masses": {last: 2.5},
        "loads": [table],
        "gravity": G,
    }


def reference(lk: cm.Linkage, k: F.Kinetostatics, kw: dict) -> dict:
    sol = k.solution
    force = np.zeros(sol.xy.shape)
    for load in kw.get("loads", []):
        force[:, sol.index(load.point)] += load.at(sol.angles)
    masses = {j: (m.mass_kg, m.com_m, m.inertia_kg_m2) for j, m in kw.get("masses", {}).items()}
    return dense_kinetostatics(
        lk,
        sol.xy,
        sol.vel,
        sol.acc,
        masses=masses,
        point_masses=kw.get("point_masses"),
        force=force,
        gravity=kw.get("gravity") or (0.0, 0.0),
    )


ANGLES = np.radians(np.arange(0.0, 360.0, 2.5))


@pytest.mark.parametrize(
    "make", [four_bar, slider_crank, shaper, cross_guides, presets.burg_trimmer]
)
def test_matches_a_dense_pin_node_solve(make):
    lk = make()
    kw = loaded(lk)
    k = F.kinetostatics(lk, ANGLES, **kw)
    assert k.ok.all()
    ref = reference(lk, k, kw)
    scale = np.abs(ref["reactions"]).max(axis=(1, 2, 3))[:, None]
    np.testing.assert_allclose(k.torque_parts, ref["torque"], rtol=0, atol=1e-9 * scale.max())
    assert (
        np.abs(k.reaction_parts - ref["reactions"]).max(axis=(1, 2, 3)).max() < 1e-9 * scale.max()
    )
    np.testing.assert_allclose(k.guide_parts, ref["guides"], atol=1e-9 * scale.max())


@settings(max_examples=25, deadline=None)
@given(
    masses=st.lists(st.floats(0.0, 20.0), min_size=5, max_size=5),
    inertias=st.lists(st.floats(0.0, 1.0), min_size=5, max_size=5),
    gx=st.floats(-10, 10),
    gy=st.floats(-10, 10),
)
def test_class_iii_matches_the_dense_solve_for_any_masses(masses, inertias, gx, gy):
    lk = presets.burg_trimmer()
    links = [tuple(ln) for ln in lk.to_dict()["links"]]
    kw = {
        "masses": {
            ln: F.LinkMass(m, None, j) for ln, m, j in zip(links, masses, inertias, strict=True)
        },
        "gravity": (gx, gy),
    }
    k = F.kinetostatics(lk, ANGLES[::4], **kw)
    ref = reference(lk, k, kw)
    scale = 1.0 + np.abs(ref["reactions"]).max()
    assert np.abs(k.reaction_parts - ref["reactions"]).max() < 1e-9 * scale
    assert np.abs(k.torque_parts - ref["torque"]).max() < 1e-9 * scale


@settings(max_examples=20, deadline=None)
@given(
    kind=st.sampled_from(["four-bar", "slider-crank", "burg"]),
    masses=st.lists(st.floats(0.0, 20.0), min_size=5, max_size=5),
    inertias=st.lists(st.floats(0.0, 1.0), min_size=5, max_size=5),
    point_mass=st.floats(0.0, 5.0),
    scale=st.floats(0.5, 2.0),
    gy=st.floats(-10, 10),
)
def test_matches_the_compact_stacked_solve(kind, masses, inertias, point_mass, scale, gy):
    """The kernel (block order, specialised eliminations) against the smallest
    system a numpy user writes — 3 equations per link, one stacked
    ``numpy.linalg.solve`` — on the benchmark's three linkages, any masses."""
    lk = {"four-bar": four_bar, "slider-crank": lambda: slider_crank(0.1 * scale, 0.35)}.get(
        kind, presets.burg_trimmer
    )()
    t = lk.to_dict()
    ground = set(t["ground"])
    links = [tuple(ln) for ln in t["links"] if not set(ln) <= ground]
    mass = {ln: (m, None, j) for ln, m, j in zip(links, masses, inertias, strict=False)}
    pm = {p: point_mass for p in lk.names[-1:] if p not in ground}
    sol = lk.solve(ANGLES[::3])
    k = F.kinetostatics(
        lk,
        sol,
        masses={ln: F.LinkMass(*v) for ln, v in mass.items()},
        point_masses=pm,
        gravity=(0.0, gy),
    )
    ref = compact_kinetostatics(
        lk, sol.xy, sol.vel, sol.acc, masses=mass, point_masses=pm, gravity=(0.0, gy)
    )
    big = 1.0 + np.abs(ref["reactions"]).max()
    assert np.abs(k.reaction_parts - ref["reactions"]).max() < 1e-10 * big
    assert np.abs(k.torque_parts - ref["torque"]).max() < 1e-10 * big
    assert np.abs(k.guide_parts - ref["guides"]).max(initial=0.0) < 1e-10 * big


def _fd(lk: cm.Linkage, phi: np.ndarray, h: float = 5e-3):
    """Positions and first/second derivatives of every point by five-point
    central differences of positions alone (no analogs; O(h⁴))."""
    x = {s: lk.solve(phi + s * h, analogs=False).xy for s in (-2, -1, 0, 1, 2)}
    d1 = (x[-2] - 8 * x[-1] + 8 * x[1] - x[2]) / (12 * h)
    d2 = (-x[-2] + 16 * x[-1] - 30 * x[0] + 16 * x[1] - x[2]) / (12 * h**2)
    return x[0], d1, d2


@pytest.mark.parametrize(
    "make", [four_bar, slider_crank, shaper, cross_guides, presets.burg_trimmer]
)
def test_power_balance_by_finite_differences(make):
    """M·ω equals the power of the loads and gravity plus the rate of change of
    kinetic energy: per part, M₂ = −Σ F·x' − Σ m g·c' and M₀ = Σ m c''·c' +
    Σ J θ''θ' (+ point masses), all from positions by finite differences."""
    lk = make()
    kw = loaded(lk, seed=7)
    phi = np.radians(np.arange(3.0, 360.0, 7.0))
    k = F.kinetostatics(lk, phi, **kw)
    x, x1, x2 = _fd(lk, phi)
    names = lk.names
    t = lk.to_dict()
    g = np.array(G)
    m0 = np.zeros(phi.size)
    m2 = np.zeros(phi.size)
    for joints, lm in kw["masses"].items():
        i0, i1 = names.index(joints[0]), names.index(joints[1])
        p0, p1 = np.array(t["points"][joints[0]]), np.array(t["points"][joints[1]])
        d = p1 - p0
        u = (np.array(lm.com_m) - p0) @ d / (d @ d)
        v = (np.array(lm.com_m) - p0) @ np.array([-d[1], d[0]]) / (d @ d)

        def com(a, i0=i0, i1=i1, u=u, v=v):
            dd = a[:, i1] - a[:, i0]
            return a[:, i0] + u * dd + v * np.stack([-dd[:, 1], dd[:, 0]], axis=1)

        c1, c2 = com(x1), com(x2)
        d0, d1, d2 = (xx[:, i1] - xx[:, i0] for xx in (x, x1, x2))
        n2 = (d0**2).sum(axis=1)
        w1 = (d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0]) / n2
        w2 = (d0[:, 0] * d2[:, 1] - d0[:, 1] * d2[:, 0]) / n2 - 2 * (d0 * d1).sum(axis=1) * w1 / n2
        m0 += lm.mass_kg * (c2 * c1).sum(axis=1) + lm.inertia_kg_m2 * w2 * w1
        m2 -= lm.mass_kg * (c1 @ g)
    for p, m in kw["point_masses"].items():
        i = names.index(p)
        m0 += m * (x2[:, i] * x1[:, i]).sum(axis=1)
        m2 -= m * (x1[:, i] @ g)
    for load in kw["loads"]:
        i = names.index(load.point)
        m2 -= (load.at(phi) * x1[:, i]).sum(axis=1)
    scale0, scale2 = np.abs(m0).max(), np.abs(m2).max()
    assert np.abs(k.torque_parts[0] - m0).max() < 1e-6 * scale0
    assert np.abs(k.torque_parts[2] - m2).max() < 1e-6 * scale2
    # And at a speed: the sum, with ε: J_eq(φ)·ε where J_eq = Σ m|c'|² + J θ'² …
    assert np.isfinite(k.torque(300.0, crank_acceleration=5.0)).all()


def test_four_bar_against_lagrange_with_sympy():
    """M = ½ ω² dI/dφ + dV/dφ + I ε for I(φ) = Σ m|c'|² + J θ'² and V = −Σ m g·c,
    with the four-bar's positions written in closed form and differentiated by
    sympy (no analogs of the solver)."""
    sp = pytest.importorskip("sympy")
    a, b, c, d = 0.1, 0.3, 0.27, 0.4
    phi = sp.symbols("phi")
    bx, by = a * sp.cos(phi), a * sp.sin(phi)
    ex, ey = d - bx, -by
    ll = sp.sqrt(ex**2 + ey**2)
    xx = (b**2 - c**2 + ll**2) / (2 * ll)
    hh = sp.sqrt(b**2 - xx**2)
    # The drawn assembly: C above the line B→D (the test's linkage draws it so).
    cx = bx + xx * ex / ll - hh * ey / ll
    cy = by + xx * ey / ll + hh * ex / ll
    pts = {"A": (0, 0), "B": (bx, by), "C": (cx, cy), "D": (d, 0)}
    phi0 = 0.4
    drawn = {
        k: tuple(float(sp.N(v.subs(phi, phi0))) if hasattr(v, "subs") else float(v) for v in xy)
        for k, xy in pts.items()
    }
    lk = cm.Linkage(drawn, [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
    spec = {("A", "B"): (2.0, 0.01), ("B", "C"): (3.0, 0.04), ("C", "D"): (2.5, 0.03)}
    masses = {}
    inertia, potential = 0, 0
    for (p, q), (m, jz) in spec.items():
        # the centre of mass 40 % along p→q and 0.02 m to its left, in the drawn pose
        p0, p1 = np.array(drawn[p]), np.array(drawn[q])
        dd = p1 - p0
        com = p0 + 0.4 * dd + 0.02 * np.array([-dd[1], dd[0]]) / np.linalg.norm(dd)
        masses[(p, q)] = F.LinkMass(m, tuple(com), jz)
        u, v = 0.4, 0.02 / np.linalg.norm(dd)
        (x0, y0), (x1, y1) = pts[p], pts[q]
        dx, dy = x1 - x0, y1 - y0
        gx, gy = x0 + u * dx - v * dy, y0 + u * dy + v * dx
        th = sp.atan2(dy, dx)
        inertia += m * (sp.diff(gx, phi) ** 2 + sp.diff(gy, phi) ** 2) + jz * sp.diff(th, phi) ** 2
        potential += -m * (G[0] * gx + G[1] * gy)
    m_omega2 = sp.lambdify(phi, sp.diff(inertia, phi) / 2, "numpy")
    m_eps = sp.lambdify(phi, inertia, "numpy")
    m_static = sp.lambdify(phi, sp.diff(potential, phi), "numpy")
    angles = np.radians(np.arange(0.0, 360.0, 5.0))
    k = F.kinetostatics(lk, angles, masses=masses, gravity=G)
    for part, ref in enumerate((m_omega2(angles), m_eps(angles), m_static(angles))):
        np.testing.assert_allclose(k.torque_parts[part], ref, rtol=1e-9, atol=1e-12)


def test_slider_crank_textbook_with_reciprocating_mass():
    """The engine's crank torque with a gas force F and a reciprocating mass m
    (massless crank and rod): T = (F − m a)·r·sin(φ + β)/cos β turns the crank
    (Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, the engine's
    force analysis; a = ω² x'' the piston's acceleration, exact, not the
    series); the driving torque is −T, the rod carries (F − m a)/cos β."""
    r, rod, m, f = 0.1, 0.35, 4.0, 1500.0
    lk = slider_crank(r, rod)
    phi = np.radians(np.arange(5.0, 360.0, 10.0))
    k = F.kinetostatics(lk, phi, point_masses={"C": m}, loads=[F.PointLoad("C", (-f, 0.0))])
    w = 600 * RAD
    s, c = np.sin(phi), np.cos(phi)
    q = np.sqrt(rod**2 - (r * s) ** 2)
    x2 = -r * c - r**2 * (c**2 - s**2) / q - (r**2 * s * c) ** 2 / q**3
    beta = np.arcsin(r * s / rod)
    push = f + m * w**2 * x2  # the force along −x on the rod from the piston: F − m a_x·(−1)
    torque = push * r * np.sin(phi + beta) / np.cos(beta)
    np.testing.assert_allclose(k.torque(600.0), -torque, rtol=1e-9, atol=1e-9)
    rod = k.reaction("C", "A-C", rpm=600.0)
    np.testing.assert_allclose(np.hypot(*rod.T), np.abs(push / np.cos(beta)), rtol=1e-9)


@pytest.mark.parametrize(
    "make", [four_bar, slider_crank, shaper, cross_guides, presets.burg_trimmer]
)
def test_static_equilibrium_of_the_whole_mechanism(make):
    """At rest the frame carries the weights and loads: the forces on the frame
    (bearings and frame guides) balance them, and so do the moments with the
    driving torque."""
    lk = make()
    kw = loaded(lk, seed=3)
    phi = np.radians(np.arange(0.0, 360.0, 15.0))
    k = F.kinetostatics(lk, phi, **kw)
    sol = k.solution
    g = np.array(G)
    react = k.reactions(0.0)
    on_frame = [i for i, (_, side) in enumerate(k.pairs) if side == "frame"]
    total = np.zeros((phi.size, 2))
    moment = k.torque(0.0).copy()
    for i in on_frame:
        p = sol.index(k.pairs[i][0])
        total -= react[:, i]
        moment -= sol.xy[:, p, 0] * react[:, i, 1] - sol.xy[:, p, 1] * react[:, i, 0]
    t = lk.to_dict()
    for joints, lm in kw["masses"].items():
        p0 = np.array(t["points"][joints[0]])
        dd = np.array(t["points"][joints[1]]) - p0
        u = (np.array(lm.com_m) - p0) @ dd / (dd @ dd)
        v = (np.array(lm.com_m) - p0) @ np.array([-dd[1], dd[0]]) / (dd @ dd)
        a, b = sol[joints[0]], sol[joints[1]]
        e = b - a
        cpos = a + u * e + v * np.stack([-e[:, 1], e[:, 0]], axis=1)
        total += lm.mass_kg * g
        moment += cpos[:, 0] * lm.mass_kg * g[1] - cpos[:, 1] * lm.mass_kg * g[0]
    for p, m in kw["point_masses"].items():
        total += m * g
        moment += sol[p][:, 0] * m * g[1] - sol[p][:, 1] * m * g[0]
    for load in kw["loads"]:
        fl = load.at(phi)
        total += fl
        moment += sol[load.point][:, 0] * fl[:, 1] - sol[load.point][:, 1] * fl[:, 0]
    # Frame guides push the pins along their normals (guides in the sliders' order).
    gf = k.guide_forces(0.0)
    order = [(p, *next(iter(gd.items()))) for p, gl in t.get("sliders", {}).items() for gd in gl]
    assert len(order) == len(k.guides)
    for j, (p, kind, arg) in enumerate(order):
        if kind == "ground":
            n = np.array([-arg[1], arg[0]]) / math.hypot(*arg)
            total += gf[:, j, None] * n
            moment += sol[p][:, 0] * gf[:, j] * n[1] - sol[p][:, 1] * gf[:, j] * n[0]
    scale = np.abs(react).max()
    assert np.abs(total).max() < 1e-9 * scale
    assert np.abs(moment).max() < 1e-9 * scale


def test_no_mass_no_load_no_force():
    k = F.kinetostatics(presets.burg_trimmer(), ANGLES)
    assert (k.torque(500.0) == 0).all() and (k.reactions(500.0) == 0).all()


def test_joint_loads_and_most_loaded_agree_with_the_reactions():
    lk = presets.burg_trimmer()
    k = F.kinetostatics(lk, ANGLES, **loaded(lk))
    loads = k.joint_loads(45.0)
    mag = np.hypot(*np.moveaxis(k.reactions(45.0), -1, 0))
    for p in lk.names:
        cols = [i for i, (q, _) in enumerate(k.pairs) if q == p]
        np.testing.assert_array_equal(loads[p], mag[:, cols].max(axis=1))
    joint, peak, at = k.most_loaded(45.0)
    assert peak == max(v.max() for v in loads.values())
    assert loads[joint].max() == peak and np.isclose(np.radians(at), ANGLES[loads[joint].argmax()])


def test_reactions_false_gives_the_same_torque():
    lk = presets.burg_trimmer()
    kw = loaded(lk)
    full = F.kinetostatics(lk, ANGLES, **kw)
    lean = F.kinetostatics(lk, ANGLES, reactions=False, **kw)
    np.testing.assert_array_equal(full.torque_parts, lean.torque_parts)
    assert lean.pairs == () and lean.reaction_parts.shape == (3, ANGLES.size, 0, 2)


def test_a_dead_centre_is_flagged_not_solved():
    """A slider-crank whose rod equals its crank folds at φ = 90° (C on O): the
    forces there are unbounded: NaN and singular, the other angles finite."""
    lk = slider_crank(0.1, 0.1)
    k = F.kinetostatics(lk, np.radians([30.0, 90.0]), point_masses={"C": 1.0})
    t = k.torque(100.0)
    assert np.isfinite(t[0]) and np.isnan(t[1])
    assert not k.ok[1]


def test_from_values_takes_the_kernels_output_and_refuses_a_nan_elsewhere():
    """Kinetostatics.from_values, public: the kernel's own values (NaN at a dead
    centre, where the analogs are not finite) are taken as kinetostatics takes
    them; a NaN at a finite angle, a conditioning of NaN there or a wrong width
    is an InputError naming the argument."""
    lk = slider_crank(0.1, 0.1)
    k = F.kinetostatics(lk, np.radians([30.0, 90.0]), point_masses={"C": 1.0})
    parts = [k.torque_parts[..., None], k.guide_parts, k.reaction_parts.reshape(3, 2, -1)]
    values = np.concatenate(parts, axis=2)
    cond = np.array([0.5, math.nan])
    again = F.Kinetostatics.from_values(k.solution, values, cond, pairs=k.pairs, guides=k.guides)
    np.testing.assert_array_equal(again.torque_parts, k.torque_parts)
    nan_at_30 = values.copy()
    nan_at_30[0, 0, 0] = math.nan
    for kw, match in (
        ({"values": nan_at_30}, r"values\[0, 0, 0\] = nan"),
        ({"conditioning": np.array([math.nan, math.nan])}, r"conditioning\[0\] = nan"),
        ({"values": values[:, :, :3]}, "values must be of shape"),
    ):
        args = {"values": values, "conditioning": cond, **kw}
        with pytest.raises(cm.InputError, match=match):
            F.Kinetostatics.from_values(k.solution, **args, pairs=k.pairs, guides=k.guides)


def test_load_table_is_zero_outside_and_wraps_by_whole_turns():
    p = F.PointLoad("E", [[0, 1.0], [0, 3.0]], angle_deg=[350.0, 370.0])
    got = p.at(np.radians([355.0, 5.0, 365.0 - 720.0, 20.0]))[:, 1]
    np.testing.assert_allclose(got, [1.5, 2.5, 2.5, 0.0])


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"masses": {("A", "Z"): F.LinkMass(1.0)}}, "no moving link has the joints A-Z"),
        ({"masses": {("A", "B"): 3.0}}, "must be a LinkMass"),
        ({"point_masses": {"Q": 1.0}}, "no point 'Q'"),
        ({"point_masses": {"B": -2.0}}, "≥ 0"),
        ({"loads": [F.PointLoad("Q", (1.0, 0.0))]}, "'Q', which is not a point"),
        ({"loads": [F.LinkTorque(("B", "Q"), 1.0)]}, "no moving link"),
        ({"loads": ["push"]}, "neither a PointLoad nor a LinkTorque"),
        ({"gravity": (0.0, -9.81, 0.0)}, "gravity"),
        ({"gravity": (0.0, math.nan)}, "gravity"),
    ],
)
def test_bad_input_is_a_clear_error(kw, match):
    with pytest.raises(cm.CyclomechError, match=match) as e:
        F.kinetostatics(four_bar(), ANGLES, **kw)
    assert isinstance(e.value, ValueError)


@pytest.mark.parametrize(
    ("args", "kw"),
    [((-1.0,), {}), ((1.0,), {"inertia_kg_m2": -0.1}), (("2.0",), {}), ((math.nan,), {})],
)
def test_a_link_mass_is_checked_when_made(args, kw):
    """A negative, non-finite or non-numeric mass or inertia is refused by LinkMass
    itself, naming the attribute, not later by the linkage whose forces use it."""
    with pytest.raises(cm.InputError, match=r"mass_kg|inertia_kg_m2") as e:
        F.LinkMass(*args, **kw)
    assert isinstance(e.value, ValueError)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (("E", [[0, 1], [0, 2]], [10.0, 5.0]), "increase strictly"),
        (("E", [[0, 1], [0, 2]], [0.0, 400.0]), "at most one turn"),
        (("E", [[0, 1]], [0.0]), ">= 2 crank angles"),
        (("E", [0.0, math.inf]), "finite"),
        (("E", [1.0, 2.0, 3.0]), "2 finite number"),
    ],
)
def test_bad_load_tables(args, match):
    with pytest.raises(cm.CyclomechError, match=match):
        F.PointLoad(*args)


def test_file_keys_name_the_file_table_and_key():
    bad = [
        ({"mass": [{"link": ["A", "B"], "mass_kg": -1.0}]}, "mass #1: mass_kg = -1.0"),
        ({"mass": [{"link": "AB", "mass_kg": 1.0}]}, "link = 'AB'"),
        ({"mass": [{"link": ["A", "B"], "mass_kg": 1.0, "colour": 1}]}, "colour"),
        ({"point_mass_kg": {"C": -1.0}}, "point_mass_kg.C"),
        ({"load": [{"point": "C"}]}, "load #1: give point and force_n"),
        ({"load": [{"point": "C", "force_n": [1, 2], "angle_deg": [5, 1]}]}, "load #1"),
        ({"gravity_m_per_s2": [0, -9.81, 1]}, "gravity_m_per_s2"),
    ]
    for table, match in bad:
        with pytest.raises(cm.CyclomechError, match=match) as e:
            F.dynamics_from_table(table, "m.toml", "[mechanism.knife]")
        assert "m.toml" in str(e.value), str(e.value)


def test_a_solution_is_used_as_given_and_checked():
    lk = presets.burg_trimmer()
    kw = loaded(lk)
    sol = lk.solve(ANGLES)
    a = F.kinetostatics(lk, sol, **kw)
    b = F.kinetostatics(lk, ANGLES, **kw)
    np.testing.assert_array_equal(a.reaction_parts, b.reaction_parts)
    assert a.solution is sol
    with pytest.raises(cm.CyclomechError, match="every point of the linkage"):
        F.kinetostatics(lk, lk.solve(ANGLES, points=["E"]), **kw)
    with pytest.raises(cm.CyclomechError, match="without analogs"):
        F.kinetostatics(lk, lk.solve(ANGLES, analogs=False), **kw)


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        (
            'point = "E"  ',
            'point = "Z"  ',
            r"\[mechanism.knife\] load #1: point = 'Z' is not a point",
        ),
        ("mass_kg = 80.0", "mass_kg = -80.0", r"\[mechanism.knife\] mass #1: mass_kg = -80.0"),
        (
            'link = ["B", "C", "E"]',
            'link = ["B", "C", "Q"]',
            r"mass #1: link = \['B', 'C', 'Q'\]",
        ),
        ('event = "clamped"', 'event = "clampd"', r"phase: event = 'clampd' is not an event"),
        ("crank_deg = 140.0", "crank_deg = true", r"phase: crank_deg"),
        ("inertia_kg_m2 = 15.0", "inertia_kg_m2 = 15.0\ncolour = 1", r"mass #1.*colour"),
    ],
)
def test_a_machine_file_error_names_the_file_table_and_key(tmp_path, old, new, match):
    text = (Path(__file__).parents[2] / "examples" / "knife_cutter.toml").read_text("utf-8")
    assert old in text
    path = tmp_path / "cutter.toml"
    path.write_text(text.replace(old, new, 1), "utf-8")
    with pytest.raises(cm.CyclomechError, match=match) as e:
        cm.Machine.from_toml(path)
    assert str(e.value).startswith(str(path)), str(e.value)


def test_most_loaded_ties_go_to_the_first_joint_and_angle():
    """A point mass on a crank at constant speed loads O and A equally at every
    angle: the rule picks O (first in pairs) at the first angle."""
    crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    k = F.kinetostatics(crank, np.radians([30.0, 210.0]), point_masses={"A": 2.0})
    loads = k.joint_loads(60.0)
    np.testing.assert_allclose(loads["O"], loads["A"], rtol=1e-14)
    assert k.most_loaded(60.0)[0] == "O" and k.most_loaded(60.0)[2] == pytest.approx(30.0)
    lk = slider_crank(0.1, 0.1)
    none = F.kinetostatics(lk, np.radians([90.0]), point_masses={"C": 1.0})
    joint, peak, at = none.most_loaded(60.0)
    assert joint == "" and math.isnan(peak) and math.isnan(at)


def test_engine_turning_moment_by_the_textbook_approximate_method():
    """The reciprocating engine's turning moment by the textbook's analytical
    method (R. S. Khurmi & J. K. Gupta, *Theory of Machines*, ch. 15 "Inertia
    Forces in Reciprocating Parts": piston acceleration ω²r(cos θ + cos 2θ/n),
    piston effort F_P = F_L − m a, turning moment F_P·r(sin θ + sin 2θ /
    (2√(n² − sin²θ))), n = l/r, θ from the inner dead centre), for a horizontal
    engine of stroke 0.5 m, rod 1 m, bore 0.75 m at 2.5 bar, 200 kg of
    reciprocating parts, 350 rpm. The method truncates the acceleration's series
    after the cos 2θ term, an error of order (r/l)³: the exact kinetostatics
    agrees within 1 % of the peak (0.44 % at θ = 45°: 13 070 vs 13 127 N·m)."""
    r, rod, m, rpm = 0.25, 1.0, 200.0, 350.0
    f_l = 2.5e5 * math.pi / 4 * 0.75**2
    lk = slider_crank(r, rod)  # θ = 0: the crank points at the piston (inner dead centre)
    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    k = F.kinetostatics(lk, theta, point_masses={"C": m}, loads=[F.PointLoad("C", (-f_l, 0.0))])
    w, n = rpm * RAD, rod / r
    a = w**2 * r * (np.cos(theta) + np.cos(2 * theta) / n)
    f_p = f_l - m * a
    s = np.sin(theta)
    turning = f_p * r * (s + np.sin(2 * theta) / (2 * np.sqrt(n**2 - s**2)))
    got = -k.torque(rpm)  # the driving torque balances the engine's turning moment
    assert np.abs(got - turning).max() < 0.01 * np.abs(turning).max()
    i = 9  # θ = 45°
    assert got[i] == pytest.approx(13069.70, abs=0.01)
    assert turning[i] == pytest.approx(13127.08, abs=0.01)


def test_the_three_ways_to_place_a_centre_of_mass_agree():
    """com_m (drawn pose), com_point (a joint) and com_offset_m (the link's frame)
    describe one centre the same way; two at once is an error."""
    lk = presets.burg_trimmer()
    t = lk.to_dict()
    e, b, c = (np.array(t["points"][p]) for p in ("E", "B", "C"))
    d = c - b
    u_hat = d / np.linalg.norm(d)
    off = e - b
    local = (float(off @ u_hat), float(off @ np.array([-u_hat[1], u_hat[0]])))
    ways = [
        F.LinkMass(40.0, tuple(e), 2.0),
        F.LinkMass(40.0, inertia_kg_m2=2.0, com_point="E"),
        F.LinkMass(40.0, inertia_kg_m2=2.0, com_offset_m=local),
    ]
    got = [
        F.kinetostatics(lk, ANGLES, masses={("B", "C", "E"): w}, gravity=G).torque(50.0)
        for w in ways
    ]
    np.testing.assert_allclose(got[1], got[0], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(got[2], got[0], rtol=1e-9, atol=1e-9)
    with pytest.raises(cm.CyclomechError, match="one way"):
        F.kinetostatics(
            lk, ANGLES, masses={("B", "C", "E"): F.LinkMass(1.0, (0, 0), com_point="E")}
        )
    with pytest.raises(cm.CyclomechError, match="not one of its joints"):
        F.kinetostatics(lk, ANGLES, masses={("B", "C", "E"): F.LinkMass(1.0, com_point="F")})
    with pytest.raises(cm.CyclomechError, match="one way"):
        F.dynamics_from_table(
            {"mass": [{"link": ["B", "C"], "mass_kg": 1.0, "com_m": [0, 0], "com_point": "B"}]},
            "f.toml",
            "[mechanism.k]",
        )


def test_near_a_dead_centre_is_flagged_and_a_machine_refuses_it(tmp_path):
    """An offset slider-crank whose rod nearly stands perpendicular to the guide at
    crank 90° (the circle of A reaches 25 µm past the guide): the force solve there
    is nearly singular. The rule: conditioning < NEAR_DEAD_CENTRE flags the angle
    (``near_dead_centre``), shaft_torque() warns, a machine refuses the mechanism
    (exit 2) rather than report a 1 MW motor. (With the circle just touching the
    guide, crank 90° is a change point: tests/linkage/test_change_points.py.)"""
    lk = cm.Linkage(
        {"O": (0, 0), "A": (0.1, 0), "C": (0.1 + math.sqrt(0.03 + 1e-5), -0.1)},
        [("O", "A"), ("A", "C")],
        ["O"],
        ("O", "A"),
        sliders={"C": ("ground", (1, 0))},
    )
    phi = np.radians(np.arange(0.0, 360.0, 0.1))
    k = F.kinetostatics(lk, phi, point_masses={"C": 20.0}, gravity=G)
    flagged = np.degrees(phi[k.near_dead_centre])
    assert flagged.size and np.all(np.abs(flagged - 90.0) < 1.5)
    assert k.conditioning[~k.near_dead_centre].min() >= F.NEAR_DEAD_CENTRE
    with pytest.warns(cm.CyclomechWarning, match="near a dead centre"):
        k.shaft_torque()
    # A well-built linkage stays far from the threshold (conditioning ≥ 0.1).
    assert F.kinetostatics(presets.burg_trimmer(), ANGLES).conditioning.min() > 0.1


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"masses": {("A", "B"): F.LinkMass(1.0), ("B", "A"): F.LinkMass(2.0)}}, "twice"),
        ({"point_masses": {"A": 1.0}}, "ground joint"),
        ({"loads": [F.PointLoad("D", (1.0, 0.0))]}, "ground joint"),
        ({"loads": F.PointLoad("C", (1.0, 0.0))}, "must be a list"),
        ({"masses": {("A", "B"): F.LinkMass(1.0, com_m=0.05)}}, "com_m"),
        ({"masses": {("A", "B"): F.LinkMass(1.0, com_m=(0, 0, 1))}}, "com_m"),
    ],
)
def test_more_bad_input(kw, match):
    with pytest.raises(cm.CyclomechError, match=match):
        F.kinetostatics(four_bar(), ANGLES, **kw)


def test_without_reactions_the_joint_queries_say_so():
    k = F.kinetostatics(four_bar(), ANGLES, reactions=False, point_masses={"C": 1.0})
    for call in (
        lambda: k.reaction("A", rpm=10),
        lambda: k.most_loaded(10),
        lambda: k.joint_loads(10),
    ):
        with pytest.raises(cm.CyclomechError, match="reactions=False"):
            call()
    assert "near a dead centre" in repr(k) and len(repr(k)) < 200


def test_standalone_files_say_where_the_force_keys_belong(tmp_path):
    lk = tmp_path / "lk.toml"
    text = (Path(__file__).parents[2] / "examples" / "burg_trimmer.toml").read_text("utf-8")
    lk.write_text(text.replace("[linkage]\n", "[linkage]\npoint_mass_kg = {E = 1.0}\n", 1), "utf-8")
    with pytest.raises(cm.CyclomechError, match=r"belong in its \[mechanism\.<name>\]"):
        cm.Linkage.from_toml(lk)
    press = tmp_path / "p.toml"
    text = (Path(__file__).parents[2] / "examples" / "extrusion_press.toml").read_text("utf-8")
    press.write_text(text.replace("[press]\n", "[press]\nslider_mass_kg = 60.0\n", 1), "utf-8")
    with pytest.raises(cm.CyclomechError, match=r"GearLeverPress\.crank_torque"):
        cm.press.PressStudy.from_toml(press)
