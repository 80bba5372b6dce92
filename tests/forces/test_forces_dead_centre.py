"""When a linkage's forces are flagged near a dead centre (issue 31, item 2).

The flag reads the analogs: ``conditioning`` = max|x'| / (2 max|x''|) [rad], which
tends to the crank angle δ to a fold (x' ~ δ^-½, x'' ~ δ^-3/2, the torque ~ δ^-2).
The toggle of a non-Grashof four-bar is found here independently, by the cosine
law; the torque away from it is checked against the dense pin-node solve and
against the energy balance from closed-form positions; ordinary linkages over full
turns must not be flagged, at any size.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.linkage import presets
from cyclomech.linkage._kind import LinkageMechanism

sys.path.insert(0, str(Path(__file__).parent))
from forces_reference import dense_kinetostatics

F = cm.forces
G = (0.0, -9.81)
RPM = 120.0
# The non-Grashof four-bar: crank AB, coupler BC, rocker CD, ground AD [m].
CRANK, COUPLER, ROCKER, GROUND = 0.12, 0.16, 0.10, 0.3
# The documented multiple: where the flag turns on, the torque of a fold is under
# 50 times its largest 0.1 rad or more away (NEAR_DEAD_CENTRE's comment, the guide).
MULTIPLE = 50.0


def toggle_four_bar(scale: float = 1.0) -> cm.Linkage:
    """Drawn at crank angle 0, C above the line BD."""
    a, b, c, d = (scale * v for v in (CRANK, COUPLER, ROCKER, GROUND))
    bx, bd = a, d - a
    x = (b * b - c * c + bd * bd) / (2 * bd)
    h = math.sqrt(b * b - x * x)
    return cm.Linkage(
        {"A": (0, 0), "B": (bx, 0), "C": (bx + x, h), "D": (d, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def toggle_angle() -> float:
    """The crank angle [rad] where coupler and rocker line up (|BD| = BC + CD),
    by the cosine law in triangle ABD: the four-bar rocks between ±this."""
    a, b, c, d = CRANK, COUPLER, ROCKER, GROUND
    return math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d))


def dynamics(scale: float = 1.0) -> dict:
    """The issue's loads: a 2 kg coupler, J = 0.01 kg·m², gravity, 5 N·m on the
    rocker; at another scale s the masses go as s³ and J as s⁵."""
    return {
        "masses": {("B", "C"): F.LinkMass(2.0 * scale**3, inertia_kg_m2=0.01 * scale**5)},
        "gravity": G,
        "loads": [F.LinkTorque(("C", "D"), 5.0 * scale**4)],
    }


def regular_torque() -> float:
    """The largest |torque| over the crank's range 0.1 rad or more from its toggles."""
    edge = toggle_angle() - 0.1
    k = F.kinetostatics(toggle_four_bar(), np.linspace(-edge, edge, 2001), **dynamics())
    assert k.ok.all() and not k.near_dead_centre.any()
    return float(np.abs(k.torque(RPM)).max())


def test_the_toggle_is_flagged_before_the_torque_exceeds_50_times_its_regular_size():
    """On main the flag (the force block's pivots, ~δ^½, under 1e-3) turned on only
    1e-6 rad from the toggle: at 1e-4 rad the torque was 2.6e7 N·m, unflagged."""
    star = toggle_angle()
    t_reg = regular_torque()
    # Dense in log δ from 0.3 rad to 1e-7 rad, and the issue's own distances.
    delta = np.concatenate([np.logspace(math.log10(0.3), -7, 241), 10.0 ** -np.arange(2.0, 8.0)])
    for side in (1.0, -1.0):  # the toggles at ±star (C above BD: two distinct folds)
        k = F.kinetostatics(toggle_four_bar(), side * (star - delta), **dynamics())
        torque = np.abs(k.torque(RPM))
        assert k.ok.all() and np.isfinite(torque).all()
        # The flag turns on before the torque passes MULTIPLE × its regular size ...
        big = torque > MULTIPLE * t_reg
        assert big.any() and k.near_dead_centre[big].all()
        # ... and stays on from 0.019 rad in (1e-2 … 1e-7 rad included), off from 0.0215.
        assert k.near_dead_centre[delta <= 0.019].all()
        assert not k.near_dead_centre[delta >= 0.0215].any()
        # The measure is the crank angle to the fold found by the cosine law.
        # (its error is O(δ): 0.35 % at 1e-3 rad)
        np.testing.assert_allclose(k.conditioning[delta <= 1e-3], delta[delta <= 1e-3], rtol=5e-3)
        near = delta <= 0.05
        np.testing.assert_allclose(k.conditioning[near], delta[near], rtol=0.1)
    # The numbers: 2.6e7 N·m at 1e-4 rad, now flagged.
    k = F.kinetostatics(toggle_four_bar(), [star - 1e-4], **dynamics())
    assert k.torque(RPM)[0] == pytest.approx(2.57e7, rel=0.01) and k.near_dead_centre[0]


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_the_rule_is_the_same_at_any_size(scale):
    """The flag reads a ratio of analogs: no unit of length, mass or speed (the
    parts of the torque are the same at every speed)."""
    star = toggle_angle()
    delta = np.array([0.1, 0.03, 0.0215, 0.0195, 1e-3, 1e-6])
    want = [False, False, False, True, True, True]
    k = F.kinetostatics(toggle_four_bar(scale), star - delta, **dynamics(scale))
    assert k.near_dead_centre.tolist() == want
    ref = F.kinetostatics(toggle_four_bar(), star - delta, **dynamics())
    np.testing.assert_allclose(k.conditioning, ref.conditioning, rtol=1e-6)
    # Masses ~ s³, J ~ s⁵: the inertia parts go as s⁵, gravity's and the load's as s⁴.
    np.testing.assert_allclose(k.torque_parts[:2], scale**5 * ref.torque_parts[:2], rtol=1e-6)
    np.testing.assert_allclose(k.torque_parts[2], scale**4 * ref.torque_parts[2], rtol=1e-6)


def test_exactly_at_the_toggle_the_forces_are_nan_not_ok():
    """On main the exact toggle gave ok True, singular False and a finite torque of
    1e30 N·m: the dyad's determinant there is the square root of round-off (~1e-8
    of its sides), above the solver's 1e-9 test."""
    star = toggle_angle()
    near = [star]
    for _ in range(3):  # and a few ulps either side (some do not assemble)
        near = [math.nextafter(near[0], 0.0), *near, math.nextafter(near[-1], 4.0)]
    for phi in (np.array(near), -np.array(near)):
        k = F.kinetostatics(toggle_four_bar(), phi, **dynamics())
        assert not k.ok.any()
        assert np.isnan(k.torque(RPM)).all() and np.isnan(k.reactions(RPM)).all()
        assert np.isnan(k.torque_parts).all() and np.isnan(k.reaction_parts).all()
        assert k.near_dead_centre[k.solution.ok].all()
        assert (k.singular == k.solution.ok).all()
    # The exact toggle assembles; 1e-9 rad short of it is still a finite, flagged pose.
    k = F.kinetostatics(toggle_four_bar(), [star, star - 1e-9], **dynamics())
    assert k.solution.ok.all() and k.singular.tolist() == [True, False]
    assert k.conditioning[0] == 0.0 and k.conditioning[1] == pytest.approx(1e-9, rel=1e-3)


def _closed_form(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """B and C of the four-bar by the cosine law (C above BD), shape (N, 2) each."""
    b_ = np.stack([CRANK * np.cos(phi), CRANK * np.sin(phi)], axis=1)
    bd = np.array([GROUND, 0.0]) - b_
    dist = np.hypot(bd[:, 0], bd[:, 1])
    e = bd / dist[:, None]
    x = (COUPLER**2 - ROCKER**2 + dist**2) / (2 * dist)
    h = np.sqrt(COUPLER**2 - x**2)
    c_ = b_ + x[:, None] * e + h[:, None] * np.stack([-e[:, 1], e[:, 0]], axis=1)
    return b_, c_


def test_away_from_the_toggle_the_torque_matches_two_references():
    """Where it is finite the torque is unchanged: it matches the dense pin-node
    solve (numpy's LU on the whole system) and the energy balance
    M = ½ω² dI/dφ + I ε + dV/dφ − 5 θ'_rocker, with I(φ) = m|c'|² + J θ'² of the
    coupler and V its potential, from closed-form positions by finite differences."""
    star = toggle_angle()
    near = star - np.array([0.02, 0.01, 1e-3])
    phi = np.concatenate([np.linspace(-star + 0.05, star - 0.05, 41), near])
    kw = dynamics()
    k = F.kinetostatics(toggle_four_bar(), phi, **kw)
    sol = k.solution
    dense = dense_kinetostatics(
        toggle_four_bar(),
        sol.xy,
        sol.vel,
        sol.acc,
        masses={("B", "C"): (2.0, None, 0.01)},
        force=np.zeros(sol.xy.shape),
        gravity=G,
    )
    torque = {"static": k.torque_parts[2], "speed": k.torque_parts[0], "acc": k.torque_parts[1]}
    np.testing.assert_allclose(torque["speed"], dense["torque"][0], rtol=1e-9)
    np.testing.assert_allclose(torque["acc"], dense["torque"][1], rtol=1e-9)
    # dense has no link torques: the 5 N·m on the rocker adds −5·θ'_rocker.
    c_, c1 = sol["C"], sol.vel[:, sol.index("C")]
    rocker_w = (c_[:, 0] - GROUND) * c1[:, 1] - c_[:, 1] * c1[:, 0]
    rocker_w /= ROCKER**2
    np.testing.assert_allclose(torque["static"], dense["torque"][2] - 5.0 * rocker_w, rtol=1e-9)

    # Energy, at the regular angles (finite differences lose the last ones).
    reg = phi[:41]
    hstep = 1e-4

    def energy(p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """I(φ), V(φ) and the rocker's angle at the angles p, by 5-point differences."""
        pos = {s: _closed_form(p + s * hstep) for s in (-2, -1, 0, 1, 2)}

        def d1(f):
            return (f(pos[-2]) - 8 * f(pos[-1]) + 8 * f(pos[1]) - f(pos[2])) / (12 * hstep)

        com = lambda bc: 0.5 * (bc[0] + bc[1])  # noqa: E731  centroid of B and C
        ang = lambda bc: np.arctan2(*(bc[1] - bc[0]).T[::-1])  # noqa: E731  (no wrap here)
        rock = lambda bc: np.arctan2(bc[1][:, 1], bc[1][:, 0] - GROUND)  # noqa: E731
        c1, w = d1(com), d1(ang)
        inertia = 2.0 * (c1**2).sum(axis=1) + 0.01 * w**2
        return inertia, d1(lambda bc: 2.0 * 9.81 * com(bc)[:, 1]), d1(rock)

    i0, dv, rock1 = energy(reg)
    di = (energy(reg + hstep)[0] - energy(reg - hstep)[0]) / (2 * hstep)
    scale = np.abs(torque["speed"][:41]).max()
    np.testing.assert_allclose(torque["speed"][:41], 0.5 * di, atol=1e-5 * scale)
    np.testing.assert_allclose(torque["acc"][:41], i0, rtol=1e-6)
    np.testing.assert_allclose(torque["static"][:41], dv - 5.0 * rock1, rtol=1e-6, atol=1e-8)


def _grashof_crank_rockers(n: int) -> list[tuple[cm.Linkage, float]]:
    """Seeded Grashof crank-rockers (the crank shortest), with their smallest
    transmission angle [deg]; those below 5° are left out (near a change point)."""
    rng = np.random.default_rng(31)
    out = []
    while len(out) < n:
        b, c, d = rng.uniform(1.05, 6.0, 3)
        if 1.0 + max(b, c, d) > sum(sorted([b, c, d])[:2]):
            continue
        cos_g = [(b * b + c * c - (d - s) ** 2) / (2 * b * c) for s in (1.0, -1.0)]
        gmin = min(min(math.degrees(math.acos(v)), 180 - math.degrees(math.acos(v))) for v in cos_g)
        if gmin < 5.0:
            continue
        bd = d - 1.0
        x = (b * b - c * c + bd * bd) / (2 * bd)
        lk = cm.Linkage(
            {"A": (0, 0), "B": (1.0, 0), "C": (1.0 + x, math.sqrt(b * b - x * x)), "D": (d, 0)},
            [("A", "B"), ("B", "C"), ("C", "D")],
            ["A", "D"],
            ("A", "B"),
        )
        out.append((lk, gmin))
    return out


def _slider_crank(r: float, rod: float, offset: float) -> cm.Linkage:
    return cm.Linkage(
        {"O": (0, 0), "A": (r, 0), "C": (r + math.sqrt(rod**2 - offset**2), offset)},
        [("O", "A"), ("A", "C")],
        ["O"],
        ("O", "A"),
        sliders={"C": ("ground", (1, 0))},
    )


TURN = np.radians(np.arange(0.0, 360.0, 0.5))


def test_ordinary_linkages_over_full_turns_are_not_flagged():
    """No false alarms: Grashof crank-rockers down to a 5° transmission angle,
    slider-cranks (offset or not, rods down to 1.05 cranks: 0.16 rad), the presets."""
    for lk, gmin in _grashof_crank_rockers(150):
        k = F.kinetostatics(lk, TURN, masses={("B", "C"): F.LinkMass(1.0)})
        assert k.ok.all() and not k.near_dead_centre.any(), gmin
        assert k.conditioning.min() > 0.04, gmin
    for r, rod, off in [(0.1, 0.35, 0.0), (0.1, 0.105, 0.0), (0.1, 0.3, 0.05), (0.1, 1.0, 0.0)]:
        k = F.kinetostatics(_slider_crank(r, rod, off), TURN, point_masses={"C": 1.0})
        assert k.ok.all() and not k.near_dead_centre.any()
        if off == 0.0:  # at TDC the crank pin's |x'| = r, the slider's |x''| = r(1 + r/l)
            assert k.conditioning[0] == pytest.approx(1 / (2 * (1 + r / rod)), rel=1e-9)
        assert k.conditioning.min() > 0.15
    for make in (presets.burg_trimmer, presets.br125, presets.br136, presets.brp4):
        lk = make()
        k = F.kinetostatics(lk, lk.drawn_angle + TURN)
        assert k.ok.all() and k.conditioning.min() > 0.29, make.__name__


@pytest.mark.parametrize("scale", [2e-4, 1.0, 1e4])
def test_a_machine_takes_a_good_linkage_of_any_size_and_refuses_a_toggle(scale):
    """On main the pivots' measure depended on the links' size: the example
    crank-rocker drawn 2e-4 or 1e4 times as large was refused as near a dead
    centre. An offset slider-crank whose rod nearly stands across its guide at 90°
    is refused at every size, naming the angle and how near it is; with the rod
    exactly across it (a change point, once a turn) it is refused on construction."""
    t = cm.Linkage.from_toml(Path(__file__).parents[2] / "examples" / "crank_rocker.toml")
    d = t.to_dict()
    good = cm.Linkage(
        {p: (scale * x, scale * y) for p, (x, y) in d["points"].items()},
        d["links"],
        d["ground"],
        d["driver"],
    )
    dyn = {"masses": {("B", "C"): F.LinkMass(scale**3)}, "gravity": G}
    mech = LinkageMechanism("good", good, "C", None, 361, dyn)
    k = mech.kinetostatics(720)
    assert k is not None and k.ok.all() and k.conditioning.min() > 0.1
    r = 0.1 * scale

    def slider_crank(reach: float) -> cm.Linkage:
        return cm.Linkage(
            {"O": (0, 0), "A": (r, 0), "C": (r + math.sqrt(reach) * r, -r)},
            [("O", "A"), ("A", "C")],
            ["O"],
            ("O", "A"),
            sliders={"C": ("ground", (1, 0))},
        )

    with pytest.raises(cm.InputError, match=r"'bad'.*joint 'C' at 90\.00°.*odd number"):
        LinkageMechanism("bad", slider_crank(3.0), "C", None, 361, {"point_masses": {"C": 1.0}})
    bad = slider_crank(3.001)
    mech = LinkageMechanism("bad", bad, "C", None, 361, {"point_masses": {"C": scale**3}})
    said = r"'bad'.* angles 89\.30, .* degrees \(its analogs put the crank 0\.0079 rad from one, "
    said += r"under 0\.02 rad\)"
    with pytest.raises(cm.InputError, match=said):
        mech.kinetostatics(3600)
