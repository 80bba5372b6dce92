"""Friction in joints and guides (issue 34 item 5) against independent references:
a block driven up an inclined guide (the closed form with the rod's angle), a
journal under a known load (μ·r·|R|), the power balance over a turn (input =
output + friction + dE/dt, the energy from positions by finite differences), a
four-bar's efficiency at one pose from its own equations solved by
scipy.optimize.root, μ = 0 equal to today's kinetostatics, self-locking
reported, and bad input."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from scipy.optimize import root

F = cm.forces
G = 9.81
RAD = 2 * math.pi / 60


def crank() -> cm.Linkage:
    return cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))


def four_bar() -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (0.1, 0), "C": (0.3, 0.25), "D": (0.4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def shaper() -> cm.Linkage:
    """An inverted slider-crank: a block at A on the crank slides on the rocker B–C."""
    a, b = np.array([0.1, 0.0]), np.array([0.0, -0.3])
    c = b + 0.6 * (a - b) / np.linalg.norm(a - b)
    return cm.Linkage(
        {"O": (0, 0), "A": tuple(a), "B": tuple(b), "C": tuple(c)},
        [("O", "A"), ("B", "C")],
        ["O", "B"],
        ("O", "A"),
        sliders={"A": ("link", ("B", "C"))},
    )


ALPHA, R, ROD, E = math.radians(30.0), 0.1, 0.4, -0.02


def incline() -> tuple[cm.Linkage, float]:
    """A slider-crank whose block C climbs a guide inclined at ALPHA, offset E
    from the crank's pivot; drawn at the crank angle where the rod lies along
    the guide (returned)."""
    t = np.array([math.cos(ALPHA), math.sin(ALPHA)])
    phi = ALPHA + math.asin(E / R)
    b = R * np.array([math.cos(phi), math.sin(phi)])
    c = b + ROD * t
    link = cm.Linkage(
        {"O": (0, 0), "B": tuple(b), "C": tuple(c)},
        [("O", "B"), ("B", "C")],
        ["O"],
        ("O", "B"),
        sliders={"C": ("ground", tuple(t))},
    )
    return link, phi


def test_block_up_an_incline_closed_form() -> None:
    """The rod (massless, frictionless pins: a two-force member) pushes the block
    with P along û; along the guide P(û·t̂) + m g_t − μ|N| sgn(v) = m a_t, across
    it N = −P(û·n̂) − m g_n: solved for P case by case (the sign of N), then the
    torque by the power through the rod, T = P (û·x'_C)."""
    link, phi_star = incline()
    m, mu, rpm = 5.0, 0.2, 30.0
    angles = np.concatenate([[phi_star], np.linspace(0.0, 2 * np.pi, 73)[:-1]])
    f = F.kinetostatics_with_friction(
        link,
        angles,
        F.Friction(guides={"C": F.GuideFriction(mu=mu)}),
        rpm,
        point_masses={"C": m},
        gravity=(0.0, -G),
    )
    sol = f.solution
    w = rpm * RAD
    t = np.array([math.cos(ALPHA), math.sin(ALPHA)])
    n = np.array([-t[1], t[0]])
    g = np.array([0.0, -G])
    checked = 0
    for i in range(angles.size):
        xb, xc = sol.xy[i, 1], sol.xy[i, 2]
        u = (xc - xb) / np.linalg.norm(xc - xb)
        v_t = float(sol.vel[i, 2] @ t)
        if abs(v_t) < 1e-6:
            continue
        a_t = w * w * float(sol.acc[i, 2] @ t)
        s = math.copysign(1.0, v_t)
        ut, un, gt, gn = float(u @ t), float(u @ n), float(g @ t), float(g @ n)
        found = []
        for sn in (1.0, -1.0):  # N = sn·|N|: P ut + m gt − μ s sn N = m a_t
            # N = −P un − m gn  ⇒  P (ut + μ s sn un) = m a_t − m gt − μ s sn m gn
            p = (m * a_t - m * gt - mu * s * sn * m * gn) / (ut + mu * s * sn * un)
            big_n = -p * un - m * gn
            if big_n * sn >= 0:
                found.append((p, big_n))
        assert len(found) >= 1
        p, big_n = found[0]
        torque = p * float(u @ sol.vel[i, 2])
        assert f.guide_forces[0, i, 0] == pytest.approx(big_n, rel=1e-9, abs=1e-9)
        assert f.torque[0, i] == pytest.approx(torque, rel=1e-9, abs=1e-9)
        assert f.losses[0, i, 0] == pytest.approx(mu * abs(big_n) * abs(v_t) * w, rel=1e-9)
        checked += 1
    assert checked > 60
    # The textbook pose: the rod along the guide pushes the climbing block with
    # P = m g (sin α + μ cos α) + m a_t.
    assert sol.vel[0, 2] @ t > 0
    a_t = w * w * float(sol.acc[0, 2] @ t)
    p = m * G * (math.sin(ALPHA) + mu * math.cos(ALPHA)) + m * a_t
    xb, xc = sol.xy[0, 1], sol.xy[0, 2]
    assert np.allclose((xc - xb) / ROD, t, atol=1e-12)
    assert f.torque[0, 0] == pytest.approx(p * float(t @ sol.vel[0, 2]), rel=1e-10)
    assert f.guide_forces[0, 0, 0] == pytest.approx(m * G * math.cos(ALPHA), rel=1e-10)


def test_journal_with_a_known_load() -> None:
    """A crank with a force F and a mass m at its pin, friction μ·r and viscous c
    at its bearing O: |R| = |F + m g + m ω² A| and T = −(A × (F + m g)) + μ r |R|
    + c ω, at two speeds in one call."""
    r_pin, mu, c, m = 0.012, 0.15, 0.02, 2.0
    force = np.array([300.0, -200.0])
    rpm = np.array([60.0, 600.0])
    angles = np.linspace(0.0, 2 * np.pi, 37)[:-1]
    f = F.kinetostatics_with_friction(
        crank(),
        angles,
        F.Friction(pins={"O": F.PinFriction(radius_m=r_pin, mu=mu, viscous=c)}),
        rpm,
        point_masses={"A": m},
        loads=[F.PointLoad("A", force)],
        gravity=(0.0, -G),
    )
    a = 0.3 * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    ext = force + m * np.array([0.0, -G])
    for s, n in enumerate(rpm):
        w = n * RAD
        load = ext + m * w * w * a
        big_r = np.hypot(load[:, 0], load[:, 1])
        torque = -(a[:, 0] * ext[1] - a[:, 1] * ext[0]) + mu * r_pin * big_r + c * w
        assert np.allclose(f.torque[s], torque, rtol=1e-10, atol=1e-9)
        assert np.allclose(f.losses[s, :, 0], (mu * r_pin * big_r + c * w) * w, rtol=1e-10)
        assert np.allclose(np.hypot(*f.reactions[s, :, 0].T), big_r, rtol=1e-10)
    assert f.elements == ("O",)
    assert (f.status >= 1).all()


def _masses() -> dict[tuple[str, str], F.LinkMass]:
    return {
        ("O", "A"): F.LinkMass(1.5, inertia_kg_m2=0.004),
        ("B", "C"): F.LinkMass(3.0, inertia_kg_m2=0.09),
    }


@pytest.mark.parametrize("viscous", [0.0, 0.05])
def test_power_balance_over_a_turn(viscous: float) -> None:
    """Input power T ω = output power (the load's) + friction power + dE/dt, the
    energy (kinetic and potential) from the positions, dE/dt by central
    differences on a fine uniform grid; for an inverted slider-crank with
    friction in its three pins (the block's turning on the crank pin included)
    and its guide on the rocker."""
    link = shaper()
    n = 7200
    angles = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    rpm = 90.0
    w = rpm * RAD
    # A cutting stroke: −40 N·m on the rocker over the crank's first half turn,
    # where the rocker turns forward (zero outside the table).
    load = F.LinkTorque(("B", "C"), [-40.0, -40.0], angle_deg=[0.0, 180.0])
    fr = F.Friction(
        pins={p: F.PinFriction(0.01, 0.12, viscous) for p in ("O", "A", "B")},
        guides={"A": F.GuideFriction(0.18, viscous)},
    )
    f = F.kinetostatics_with_friction(
        link,
        angles,
        fr,
        rpm,
        masses=_masses(),
        point_masses={"A": 0.5},
        loads=[load],
        gravity=(0.0, -G),
    )
    assert f.ok.all()
    sol = link.solve(angles)
    xy = sol.xy
    idx = {p: i for i, p in enumerate(sol.names)}

    def theta(p: str, q: str) -> np.ndarray:
        d = xy[:, idx[q]] - xy[:, idx[p]]
        return np.unwrap(np.arctan2(d[:, 1], d[:, 0]))

    h = 2 * np.pi / n

    def ddphi(x: np.ndarray) -> np.ndarray:  # periodic central difference in the crank angle
        return (np.roll(x, -1, axis=0) - np.roll(x, 1, axis=0)) / (2 * h)

    th_rocker = theta("B", "C")
    # Unwrapped angles are periodic up to whole turns: difference them as such.
    d_crank = np.full(n, 1.0)
    d_rocker = ddphi(np.exp(1j * th_rocker)) / (1j * np.exp(1j * th_rocker))
    d_rocker = d_rocker.real
    energy = np.zeros(n)
    m = _masses()
    for (p, q), om in (((("O", "A"), d_crank)), ((("B", "C"), d_rocker))):
        lm = m[(p, q)]
        com = 0.5 * (xy[:, idx[p]] + xy[:, idx[q]])
        v = ddphi(com) * w
        energy += 0.5 * lm.mass_kg * (v**2).sum(axis=1) + 0.5 * lm.inertia_kg_m2 * (om * w) ** 2
        energy += lm.mass_kg * G * com[:, 1]
    va = ddphi(xy[:, idx["A"]]) * w
    energy += 0.5 * 0.5 * (va**2).sum(axis=1) + 0.5 * G * xy[:, idx["A"], 1]
    de_dt = ddphi(energy) * w
    cutting = np.degrees(angles) <= 180.0
    p_out = np.where(cutting, 40.0 * d_rocker * w, 0.0)  # the load takes 40·θ̇
    p_in = f.input_power[0]
    resid = p_in - (p_out + f.friction_power[0] + de_dt)
    assert np.abs(resid).max() < 1e-4 * np.abs(p_in).max()
    assert (f.friction_power > 0).mean() > 0.9
    # Over the turn the stored energy returns: the cycle's efficiency is the
    # output work over the input work.
    eff = f.cycle_efficiency()[0]
    assert eff == pytest.approx(p_out.sum() / p_in.sum(), rel=1e-4)
    assert 0.0 < eff < 1.0


def test_zero_friction_is_todays_kinetostatics() -> None:
    link = shaper()
    angles = np.linspace(0.0, 2 * np.pi, 91)
    kw = {"masses": _masses(), "point_masses": {"A": 0.5}, "gravity": (0.0, -G)}
    kw["loads"] = [F.LinkTorque(("B", "C"), -40.0)]
    k = F.kinetostatics(link, angles, **kw)
    fr = F.Friction(
        pins={p: F.PinFriction(0.01, 0.0) for p in ("O", "A", "B")},
        guides={"A": F.GuideFriction(0.0)},
    )
    rpm = [30.0, 300.0]
    for friction in (fr, F.Friction()):
        f = F.kinetostatics_with_friction(link, angles, friction, rpm, **kw)
        for s, n in enumerate(rpm):
            assert np.array_equal(f.torque[s], k.torque(n))
            assert np.array_equal(f.guide_forces[s], k.guide_forces(n))
            assert np.array_equal(f.reactions[s], k.reactions(n))
        assert (f.losses == 0.0).all()
        assert (f.status == 1).all()


def _four_bar_kinematics(phi: float) -> tuple[np.ndarray, ...]:
    """The four-bar's pose and its links' angular velocity analogs at ``phi``,
    from its loop equations (not the linkage solver): the branch drawn."""
    a0, d0 = np.array([0.0, 0.0]), np.array([0.4, 0.0])
    l2, l3, l4 = 0.1, math.hypot(0.2, 0.25), math.hypot(0.1, 0.25)
    b = a0 + l2 * np.array([math.cos(phi), math.sin(phi)])
    dist = np.linalg.norm(d0 - b)
    x = (l3**2 - l4**2 + dist**2) / (2 * dist)
    hh = math.sqrt(l3**2 - x**2)
    e = (d0 - b) / dist
    c = b + x * e + hh * np.array([-e[1], e[0]])
    # Velocities: ω3 (C−B)⊥ − ω4 (C−D)⊥ = −ω2 (B−A)⊥ with ω2 = 1.
    perp = lambda v: np.array([-v[1], v[0]])  # noqa: E731
    mat = np.column_stack([perp(c - b), -perp(c - d0)])
    w3, w4 = np.linalg.solve(mat, -perp(b - a0))
    return a0, b, c, d0, np.array([1.0, w3, w4])


def test_four_bar_efficiency_at_one_pose() -> None:
    """A massless four-bar driving a load torque M on its rocker with friction μ·r
    at all four pins: with one force F through the links (F_A = F_B = F_C =
    −F_D), its three moment equations (crank about A, coupler about B, rocker
    about D) in F and T, solved by scipy's root (MINPACK's hybrid Newton);
    efficiency = −M ω4 / (T ω2)."""
    phi, mu_r, big_m = math.radians(50.0), 0.15 * 0.01, -25.0
    a0, b, c, d0, om = _four_bar_kinematics(phi)
    rel = {"A": om[0], "B": om[0] - om[1], "C": om[1] - om[2], "D": om[2]}

    def tau(joint: str, fmag: float) -> float:  # friction torque on the first member
        return -mu_r * fmag * np.sign(rel[joint])

    def eqs(z: np.ndarray) -> list[float]:
        fx, fy, t = z
        fv = np.array([fx, fy])  # the coupler's force on the rocker at C
        fm = math.hypot(fx, fy)
        cr = lambda r, v: r[0] * v[1] - r[1] * v[0]  # noqa: E731
        # crank A–B: the frame at A and the coupler at B (−F on the crank).
        crank_m = cr(b - a0, -fv) + t + tau("A", fm) + tau("B", fm)
        # coupler B–C: +F from the crank at B, −F from the rocker at C; about B.
        coupler_m = cr(c - b, -fv) - tau("B", fm) + tau("C", fm)
        # rocker D–C: +F at C; about D.
        rocker_m = cr(c - d0, fv) + big_m - tau("C", fm) + tau("D", fm)
        return [crank_m, coupler_m, rocker_m]

    z = root(eqs, [1.0, 1.0, 1.0], method="hybr", tol=1e-14).x
    assert np.allclose(eqs(z), 0.0, atol=1e-10)
    eff_ref = -big_m * om[2] / (z[2] * om[0])
    fr = F.Friction(pins={p: F.PinFriction(0.01, 0.15) for p in "ABCD"})
    f = F.kinetostatics_with_friction(
        four_bar(), [phi], fr, 60.0, loads=[F.LinkTorque(("C", "D"), big_m)]
    )
    assert f.torque[0, 0] == pytest.approx(z[2], rel=1e-9)
    assert f.efficiency[0, 0] == pytest.approx(eff_ref, rel=1e-9)
    assert 0.5 < eff_ref < 1.0
    k = F.kinetostatics(four_bar(), [phi], loads=[F.LinkTorque(("C", "D"), big_m)])
    assert f.torque[0, 0] > k.torque(60.0)[0] > 0


def test_self_locking_is_reported() -> None:
    """A block pushed along a level guide by a rod at angle β against a load: the
    rod's force P needs P(cos β − μ|sin β|) = load, no finite P where μ|tan β| ≥ 1
    (β up to 30° here; μ = 3 locks beyond 18.4°)."""
    link = cm.Linkage(
        {"O": (0, 0), "A": (0.1, 0), "C": (0.3, 0)},
        [("O", "A"), ("A", "C")],
        ["O"],
        ("O", "A"),
        sliders={"C": ("ground", (1, 0))},
    )
    angles = np.linspace(0.0, 2 * np.pi, 73)[:-1]
    mu = 3.0
    with pytest.warns(cm.CyclomechWarning, match="self-locking"):
        f = F.kinetostatics_with_friction(
            link,
            angles,
            F.Friction(guides={"C": F.GuideFriction(mu)}),
            60.0,
            loads=[F.PointLoad("C", (-500.0, 0.0))],
        )
    xy = f.solution.xy
    d = xy[:, 2] - xy[:, 1]
    tan_b = np.abs(d[:, 1] / d[:, 0])
    v = f.solution.vel[:, 2, 0]
    locked = f.self_locking[0]
    clear = (mu * tan_b < 0.9) | (np.abs(v) < 1e-9)
    assert locked[(mu * tan_b > 1.1) & (np.abs(v) > 1e-9)].all()
    assert not locked[clear].any()
    assert np.isnan(f.torque[0, locked]).all() and np.isfinite(f.torque[0, ~locked]).all()
    assert (f.status[0, locked] == -1).all()
    assert "self-locking" in repr(f)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: F.PinFriction(radius_m=-0.01, mu=0.1), "radius_m"),
        (lambda: F.PinFriction(radius_m=0.01, mu=-0.1), "mu"),
        (lambda: F.PinFriction(radius_m=0.01, mu=0.1, viscous=-1.0), "viscous"),
        (lambda: F.PinFriction(radius_m=0.01, mu=math.nan), "mu"),
        (lambda: F.GuideFriction(mu=-0.2), "mu"),
        (lambda: F.GuideFriction(mu=0.2, viscous=-3.0), "viscous"),
        (lambda: F.GuideFriction(mu="0.2"), "mu"),
        (lambda: F.Friction(pins={"A": F.GuideFriction(0.1)}), "PinFriction"),
        (lambda: F.Friction(guides=[("C", F.GuideFriction(0.1))]), "guides"),
    ],
)
def test_bad_friction_values(make, match: str) -> None:
    with pytest.raises(cm.InputError, match=match):
        make()


def test_bad_names_and_speeds() -> None:
    link, _ = incline()
    with pytest.raises(cm.InputError, match=r"no joint 'X'; the joints are O, B, C"):
        F.kinetostatics_with_friction(
            link, [0.0], F.Friction(pins={"X": F.PinFriction(0.01, 0.1)}), 60.0
        )
    with pytest.raises(cm.InputError, match=r"no slider at 'B'; the sliders are C"):
        F.kinetostatics_with_friction(
            link, [0.0], F.Friction(guides={"B": F.GuideFriction(0.1)}), 60.0
        )
    with pytest.raises(cm.InputError, match="rpm must hold positive speeds"):
        F.kinetostatics_with_friction(link, [0.0], F.Friction(), [60.0, -1.0])
    with pytest.raises(cm.InputError, match=r"must be a cyclomech\.forces\.Friction"):
        F.kinetostatics_with_friction(link, [0.0], {"pins": {}}, 60.0)
    cross = cm.Linkage(
        {"A": (0, 0), "B": (0.1, 0), "C": (0.3, 0.2), "D": (0.4, 0), "E": (0.3, 0.4)},
        [("A", "B"), ("B", "C"), ("C", "D"), ("C", "E")],
        ["A", "D"],
        ("A", "B"),
        sliders={"E": ("ground", (0, 1))},
    )
    with pytest.raises(cm.InputError, match="joins 3 parts"):
        F.kinetostatics_with_friction(
            cross, [0.3], F.Friction(pins={"C": F.PinFriction(0.01, 0.1)}), 60.0
        )
