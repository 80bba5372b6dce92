"""The frame's shaking force and moment (issue 34, item 4), each against a
reference computed here from the linkage's solved positions alone: the momentum
balance −Σ mᵢ a_Gᵢ and −dH/dt by finite differences, and the slider-crank's
closed form and its series."""

from __future__ import annotations

import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
import sympy as sp
from cyclomech.forces import LinkMass, PointLoad

W = 300.0 * math.pi / 30.0  # 300 rpm [rad/s]
ROOT = Path(__file__).resolve().parents[2]


def fourbar() -> cm.Linkage:
    return cm.Linkage(
        {"O": (0.0, 0.0), "A": (0.1, 0.05), "B": (0.38, 0.22), "D": (0.4, 0.0)},
        [("O", "A"), ("A", "B"), ("D", "B")],
        ["O", "D"],
        ("O", "A"),
    )


FOURBAR_MASSES = {
    ("O", "A"): LinkMass(1.2, com_offset_m=(0.04, 0.01), inertia_kg_m2=0.002),
    ("A", "B"): LinkMass(2.5, com_offset_m=(0.15, -0.03), inertia_kg_m2=0.02),
    ("D", "B"): LinkMass(1.8, com_offset_m=(0.1, 0.02), inertia_kg_m2=0.008),
}


def slider_crank(r: float = 0.1, rod: float = 0.35) -> cm.Linkage:
    return cm.Linkage(
        {"A": (0.0, 0.0), "B": (r, 0.0), "C": (r + rod, 0.0)},
        [("A", "B"), ("B", "C")],
        ["A"],
        ("A", "B"),
        sliders={"C": ("ground", (1.0, 0.0))},
    )


def _com(xy, lm: LinkMass, j0: int, j1: int):
    """A link's centre of mass (N, 2) from its joints' solved positions."""
    d = xy[:, j1] - xy[:, j0]
    u, v = lm.com_offset_m
    e = d / np.hypot(*d.T)[:, None]
    return xy[:, j0] + u * e + v * np.stack([-e[:, 1], e[:, 0]], 1)


def momentum_reference(lk, masses, point_masses, phi, h=1e-4, about=(0.0, 0.0)):
    """−Σ m a_G and −dH/dt per ω² at ``phi`` [rad], by central differences of the
    positions the linkage solves at φ ± h (nothing from the force kernel)."""
    names = list(lk.names)
    grid = np.concatenate([phi - h, phi, phi + h])
    xy = lk.solve(grid).xy.reshape(3, phi.size, len(names), 2)
    q = np.array(about)
    force = np.zeros((phi.size, 2))
    moment = np.zeros(phi.size)
    bodies = []
    for joints, lm in masses.items():
        j0, j1 = names.index(joints[0]), names.index(joints[1])
        g = np.stack([_com(x, lm, j0, j1) for x in xy])
        th = np.stack([np.unwrap(np.arctan2(*(x[:, j1] - x[:, j0]).T[::-1])) for x in xy])
        bodies.append((lm.mass_kg, lm.inertia_kg_m2, g, th))
    for p, m in point_masses.items():
        g = xy[:, :, names.index(p)]
        bodies.append((m, 0.0, g, np.zeros((3, phi.size))))
    for m, jz, g, th in bodies:
        a = (g[2] - 2 * g[1] + g[0]) / h**2
        alpha = (th[2] - 2 * th[1] + th[0]) / h**2
        force -= m * a
        r = g[1] - q
        moment -= m * (r[:, 0] * a[:, 1] - r[:, 1] * a[:, 0]) + jz * alpha
    return force, moment


def test_four_bar_shaking_force_and_moment_are_the_momentum_balance():
    lk = fourbar()
    phi = np.radians(np.arange(0.0, 360.0, 15.0))
    k = cm.forces.kinetostatics(
        lk,
        phi,
        masses=FOURBAR_MASSES,
        gravity=(0.0, -9.81),
        loads=[PointLoad("B", (-40.0, 25.0)), cm.forces.LinkTorque(("D", "B"), 3.0)],
    )
    s = cm.dynamics.shaking(k, about_m=(0.2, -0.1))
    ref_f, ref_m = momentum_reference(lk, FOURBAR_MASSES, {}, phi, about=(0.2, -0.1))
    scale = np.abs(ref_f).max()
    np.testing.assert_allclose(s.force_parts[0], ref_f, atol=1e-5 * scale)
    np.testing.assert_allclose(s.moment_parts[0], ref_m, atol=1e-5 * np.abs(ref_m).max())
    np.testing.assert_allclose(s.force(300.0), W**2 * s.force_parts[0])
    # Gravity and the working loads stay out of the shaking force: the static part
    # is the weight plus the load on B, constant (the link torque gives no force).
    weight = sum(lm.mass_kg for lm in FOURBAR_MASSES.values()) * np.array([0.0, -9.81])
    np.testing.assert_allclose(
        s.force_parts[2], np.broadcast_to(weight + np.array([-40.0, 25.0]), (24, 2)), atol=1e-9
    )


def test_the_epsilon_part_is_minus_the_momentum_rate_of_the_velocity_analogs():
    lk = slider_crank()
    phi = np.radians(np.arange(5.0, 360.0, 20.0))
    k = cm.forces.kinetostatics(
        lk,
        phi,
        masses={("B", "C"): LinkMass(2.0, com_offset_m=(0.1, 0.0))},
        point_masses={"C": 3.0, "B": 0.5},
    )
    s = cm.dynamics.shaking(k, linkage=lk)
    names = list(lk.names)
    h = 1e-6
    xy = lk.solve(np.concatenate([phi - h, phi + h])).xy.reshape(2, phi.size, 3, 2)
    v = (xy[1] - xy[0]) / (2 * h)
    gv = 2.0 * (v[:, 1] + 0.1 / 0.35 * (v[:, 2] - v[:, 1])) + 3.0 * v[:, 2] + 0.5 * v[:, 1]
    np.testing.assert_allclose(s.force_parts[1], -gv, atol=1e-6 * np.abs(gv).max())
    assert names == ["A", "B", "C"]


def test_slider_crank_shaking_force_is_the_closed_form_and_its_series():
    r, rod, mc, mb = 0.1, 0.35, 3.0, 0.8
    lk = slider_crank(r, rod)
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    k = cm.forces.kinetostatics(lk, phi, point_masses={"C": mc, "B": mb})
    f = cm.dynamics.shaking(k, linkage=lk).force(300.0)
    # The exact slider position, differentiated symbolically.
    p = sp.symbols("p")
    x = r * sp.cos(p) + sp.sqrt(rod**2 - r**2 * sp.sin(p) ** 2)
    xpp = sp.lambdify(p, sp.diff(x, p, 2), "numpy")(phi)
    fx = -(W**2) * (mc * xpp - mb * r * np.cos(phi))
    fy = W**2 * mb * r * np.sin(phi)
    np.testing.assert_allclose(f[:, 0], fx, atol=1e-9 * np.abs(fx).max())
    np.testing.assert_allclose(f[:, 1], fy, atol=1e-9 * np.abs(fx).max())
    # The primary and secondary approximation, and the series to λ⁵.
    lam = r / rod
    approx = (mb + mc) * r * W**2 * np.cos(phi) + mc * r * W**2 * lam * np.cos(2 * phi)
    assert np.abs(f[:, 0] - approx).max() < 0.02 * np.abs(fx).max()  # O(λ³) = 2.3 %
    a2 = lam + lam**3 / 4 + 15 * lam**5 / 128
    a4 = lam**3 / 4 + 3 * lam**5 / 16
    a6 = 9 * lam**5 / 128
    series = mc * r * W**2 * (
        np.cos(phi) + a2 * np.cos(2 * phi) - a4 * np.cos(4 * phi) + a6 * np.cos(6 * phi)
    ) + mb * r * W**2 * np.cos(phi)
    assert np.abs(f[:, 0] - series).max() < 3 * lam**7 * mc * r * W**2


def _harmonic(v, phi, order):
    """The amplitude of cos(order φ) and sin(order φ) in v over a uniform turn."""
    return 2 * np.mean(v * np.cos(order * phi)), 2 * np.mean(v * np.sin(order * phi))


def test_a_crank_counterweight_only_moves_the_primary_force_between_x_and_y():
    r, rod, mc = 0.1, 0.35, 3.0
    lk = slider_crank(r, rod)
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    k = cm.forces.kinetostatics(lk, phi, point_masses={"C": mc})
    b = cm.dynamics.balance(k, counterweights=[("A", "B")], rpm=300.0, linkage=lk)
    one = mc * r * W**2
    seconds = []
    for frac in (0.0, 0.5, 1.0):
        w = np.array([[[-frac * mc * r, 0.0]]])
        f = b.form.base[:2] + np.einsum("cjnb,jb->cn", b.form.lin[:2], w[0])
        cx, _ = _harmonic(f[0], phi, 1)
        _, sy = _harmonic(f[1], phi, 1)
        # x keeps (1 − frac) of the primary, y gains frac of it: never less in total.
        assert cx == pytest.approx((1 - frac) * one, rel=1e-9)
        assert sy == pytest.approx(-frac * one, rel=1e-9)
        # The secondary is untouched: the series' A₂ (to λ⁵; λ⁷ is 1.6e-4 of it).
        c2, _ = _harmonic(f[0], phi, 2)
        secondary = one * (r / rod + (r / rod) ** 3 / 4 + 15 * (r / rod) ** 5 / 128)
        assert c2 == pytest.approx(secondary, rel=1e-4)
        seconds.append(c2)
    assert np.ptp(seconds) < 1e-9 * one
    # The least RMS splits it evenly: half the reciprocating mass at the crank radius.
    (c,) = b.counterweights
    assert c.mass_kg == pytest.approx(mc / 2, rel=1e-9)
    assert c.angle_deg == pytest.approx(180.0, abs=1e-9)


def test_the_example_machine_shakes_as_its_linkage_at_its_phase():
    m = cm.Machine.from_toml(ROOT / "examples" / "knife_cutter.toml")
    r = cm.machine.analyze(m, progress=False)
    s = cm.dynamics.shaking(r)
    (name,) = s.parts
    res = r.mechanisms[name]
    own = cm.dynamics.shaking(res)
    shift = res.shaft_torque()[2]
    n = own.angles_deg.size
    steps = shift / (360.0 / n)
    assert steps == pytest.approx(round(steps), abs=1e-9)  # whole steps here: no interpolation
    moved = np.roll(own.force_parts, round(steps), axis=1)
    np.testing.assert_allclose(s.force_parts, moved, atol=1e-9 * np.abs(moved).max())
    assert s.stats(300.0)["rms_force_n"] == pytest.approx(own.stats(300.0)["rms_force_n"], rel=1e-9)


def test_the_hodograph_draws_the_force_vector_tip(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from cyclomech.dynamics.plot import plot_shaking

    lk = slider_crank()
    phi = np.radians(np.arange(0.0, 360.0, 2.0))
    k = cm.forces.kinetostatics(lk, phi, point_masses={"C": 3.0, "B": 1.0})
    b = cm.dynamics.balance(k, counterweights=[("A", "B")], rpm=300.0, linkage=lk)
    fig = plot_shaking(b, 300.0)
    polar = fig.axes[0]
    (after,) = [ln for ln in polar.lines if ln.get_gid() == "force"]
    (before,) = [ln for ln in polar.lines if ln.get_gid() == "force before"]
    for line, s in ((after, b.shaking_after), (before, b.shaking_before)):
        ang, mag = line.get_data()
        f = s.force(300.0)
        # The closed curve's points are the force's tips (x, y) = mag (cos, sin).
        np.testing.assert_allclose(mag[:-1] * np.cos(ang[:-1]), f[:, 0], atol=1e-9 * mag.max())
        np.testing.assert_allclose(mag[:-1] * np.sin(ang[:-1]), f[:, 1], atol=1e-9 * mag.max())
    fig.savefig(tmp_path / "shaking.png")
    assert (tmp_path / "shaking.png").stat().st_size > 10_000
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_a_translating_cam_follower_shakes_the_machine_by_its_inertia_along_its_axis():
    m = cm.Machine.from_toml(ROOT / "examples" / "flow_wrapper.toml")
    r = cm.machine.analyze(m, progress=False)
    s = cm.dynamics.shaking(r, about_m=(0.01, 0.0))
    cams = [
        k for k, res in r.mechanisms.items() if isinstance(getattr(res, "cam", None), cm.cam.Cam)
    ]
    translating = [
        k for k in cams if isinstance(r.mechanisms[k].cam.follower, cm.cam.TranslatingRoller)
    ]
    assert translating and set(translating) <= set(s.parts)
    assert set(cams) - set(translating) <= set(s.skipped)
    for k in translating:
        res = r.mechanisms[k]
        mass = res.mech.design.loads.mass
        e = res.cam.follower.offset
        phase = res.shaft_torque()[2]
        # −m s″ by central differences of the displacement at the cam angle θ − phase.
        theta = np.radians(s.angles_deg[::37] - phase)
        h = 1e-4
        sv = [res.cam.solve(theta + d).s for d in (-h, 0.0, h)]
        ref = -mass * (sv[2] - 2 * sv[1] + sv[0]) / h**2
        got = s.parts[k].force_parts[0, ::37]
        scale = np.abs(ref).max()
        np.testing.assert_allclose(got[:, 1], ref, atol=2e-4 * scale)
        assert np.abs(got[:, 0]).max() == 0.0
        np.testing.assert_allclose(
            s.parts[k].moment_parts[0, ::37], (e - 0.01) * ref, atol=2e-4 * scale
        )


def _press_line(tmp_path, slider_kg: float, rod_kg: float):
    text = (ROOT / "examples" / "extrusion_press_line.toml").read_text(encoding="utf-8")
    text = text.replace("slider_mass_kg = 60.0", f"slider_mass_kg = {slider_kg}")
    text = text.replace("rod_mass_kg = 15.0", f"rod_mass_kg = {rod_kg}")
    path = tmp_path / "press_line.toml"
    path.write_text(text, encoding="utf-8")
    r = cm.machine.analyze(cm.Machine.from_toml(path), progress=False)
    return r, r.mechanisms["drive"]


@pytest.mark.parametrize(("slider_kg", "rod_kg"), [(60.0, 0.0), (0.0, 15.0)])
def test_a_press_shakes_as_its_crank_torque_says_by_the_power_balance(tmp_path, slider_kg, rod_kg):
    # The press's own crank torque (its kernel's exact Π′, Π″ and the rod's terms)
    # is the power of the inertia forces: per ω², T = −F·X_ψ − (−J φ_ψψ)·φ_ψ over the
    # carrier angle ψ, X the slider or the rod's centre G. The velocities here by
    # np.gradient on the drive's positions; −J φ_ψψ from the shaking moment about G.
    r, res = _press_line(tmp_path, slider_kg, rod_kg)
    part = cm.dynamics.shaking(r).parts["drive"]
    phase = res.shaft_torque()[2]
    n = part.angles_deg.size
    steps = round(phase / (360.0 / n))
    assert phase == pytest.approx(steps * 360.0 / n, abs=1e-9)  # whole steps: no interpolation
    force = np.roll(part.force_parts[0], -steps, axis=0)
    moment = np.roll(part.moment_parts[0], -steps, axis=0)
    psi = np.radians(np.arange(n) * (360.0 / n))
    kin = res.mech.press.solve(np.mod(-psi, 2 * np.pi))
    g = 0.5 * (kin.slider + kin.pin)
    d = kin.slider - kin.pin
    phi = np.arctan2(d[:, 1], d[:, 0])  # the rod swings: no wrap over the turn

    def grad(x):
        wrapped = np.concatenate([x[-2:], x, x[:2]])
        return np.gradient(wrapped, psi[1], axis=0, edge_order=2)[2:-2]

    if rod_kg == 0.0:
        got = -np.einsum("ni,ni->n", force, grad(kin.slider))
        # The slider's inertia force per ω² against the press kernel's exact Π″:
        # the stencil's rounding (1/h², h = 1e-3) leaves ~4e-9 of the peak.
        exact = slider_kg * np.abs(kin.dds)
        np.testing.assert_allclose(np.hypot(*force.T), exact, rtol=0, atol=1e-8 * exact.max())
    else:
        about_g = moment - (g[:, 0] * force[:, 1] - g[:, 1] * force[:, 0])  # −J φ_ψψ
        got = -np.einsum("ni,ni->n", force, grad(g)) - about_g * grad(phi)
    want = res.shaft_torque()[0]
    np.testing.assert_allclose(got, want, atol=1e-5 * np.abs(want).max())
