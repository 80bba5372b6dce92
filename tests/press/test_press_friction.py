"""Friction of a press drive (issue 34 item 5): Coulomb friction at the slider's
guide and the rod's two pins (:mod:`cyclomech.press._friction`), against
references written here: the massless rod's closed form with guide friction, the
slider's and the rod's Newton–Euler equations with kinematics by finite
differences of the positions, the crank torque from the planet's pin force (a
force balance, not the power balance the code uses), the power balance over the
cycle, μ = 0 gives today's torque; the press line's machine file; bad input."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.machine._efficiency import machine_efficiency
from cyclomech.press._friction import PressFriction, press_friction

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
W = 40.0 * math.pi / 30.0


def line() -> Any:
    return cm.Machine.from_toml(EXAMPLES / "extrusion_press_line.toml").mechanisms["drive"]


def solve(fr: PressFriction, alpha: np.ndarray, masses: bool = True) -> Any:
    m = line()
    return press_friction(
        m.press,
        alpha,
        W,
        fr,
        force=m.force,
        slider_mass=m.slider_mass if masses else 0.0,
        rod_mass=m.rod_mass if masses else 0.0,
        k_Sp=m.k_Sp,
    )


def grid(n: int = 720) -> np.ndarray:
    return np.arange(n) * (2.0 * math.pi / n)


def test_guide_friction_on_a_massless_rod_against_the_closed_form() -> None:
    """A massless rod is a strut along its axis: on the working stroke the slider
    comes down, the guide's friction μ·|H| pushes it up, so the rod's force
    is F_b/(cos φ − μ·|sin φ|), H its part across the guide, the loss μ·|H|·|v|;
    φ the rod's angle to the guide from the pin's and the slider's positions."""
    mu = 0.12
    a = grid()
    f = solve(PressFriction(guide_mu=mu), a, masses=False)
    m = line()
    k = m.press.solve(a)
    e = k.pin - k.slider
    sin, cos = e[:, 0] / m.press.L, e[:, 1] / m.press.L
    on = np.mod(a, 2 * math.pi) <= m.press.crank_torque(a, force=m.force, k_Sp=m.k_Sp).alpha_p
    fb = np.where(on, m.force.at(k.s), 0.0)
    v = -W * k.ds
    assert (v[fb > 0] < 1e-12).all()  # the working stroke comes down (BDC: v = 0)
    down = v < -1e-9
    rod = fb / (cos - mu * np.abs(sin) * down)
    np.testing.assert_allclose(np.abs(f.guide_force), rod * np.abs(sin), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(np.hypot(*f.slider_force.T), rod, rtol=1e-12, atol=1e-9)
    loss = mu * rod * np.abs(sin) * np.abs(v)
    np.testing.assert_allclose(f.losses[:, 0], loss, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(f.torque, f.torque_without + loss / W, rtol=1e-12, atol=1e-9)
    assert loss.max() > 100.0  # not trivially zero


FRICTIONS = [
    PressFriction(guide_mu=0.1),
    PressFriction(pin_radius=0.02, pin_mu=0.08),
    PressFriction(guide_mu=0.1, pin_radius=0.03, pin_mu=0.15),
]


@pytest.mark.parametrize("fr", FRICTIONS)
def test_forces_satisfy_newton_euler_with_finite_difference_kinematics(fr: PressFriction) -> None:
    """The code's forces, put into the slider's and the rod's equations written
    here with accelerations by second differences of the positions over α."""
    m = line()
    a = grid()
    f = solve(fr, a)
    h = 1e-4
    ks = [m.press.solve(a + d) for d in (-h, 0.0, h)]
    k = ks[1]

    def d1(x: list[np.ndarray]) -> np.ndarray:
        return -W * (x[2] - x[0]) / (2 * h)  # d/dt = −ω d/dα

    def d2(x: list[np.ndarray]) -> np.ndarray:
        return W * W * (x[2] - 2 * x[1] + x[0]) / h**2

    g = [0.5 * (q.pin + q.slider) for q in ks]
    gam = [np.unwrap(np.arctan2((q.pin - q.slider)[:, 1], (q.pin - q.slider)[:, 0])) for q in ks]
    beta = [np.arctan2(*(q.pin - q.centre)[:, ::-1].T) for q in ks]
    a_g, gdd, gd = d2(g), d2(gam), d1(gam)
    planet = -W * np.angle(np.exp(1j * (beta[2] - beta[0]))) / (2 * h)
    a_s = d2([q.slider[:, 1] for q in ks])
    v_s = d1([q.slider[:, 1] for q in ks])
    on = np.mod(a, 2 * math.pi) <= m.press.crank_torque(a, force=m.force, k_Sp=m.k_Sp).alpha_p
    fb = np.where(on, m.force.at(k.s), 0.0)
    fs, fp = f.slider_force, f.pin_force
    scale = np.abs(fp).max()
    # The slider: vertical, with the guide's friction against its velocity.
    moving = np.where(np.abs(v_s) > 1e-7, np.sign(v_s), 0.0)  # BDC and TDC: v = 0
    res = fs[:, 1] + fb - fr.guide_mu * np.abs(fs[:, 0]) * moving - m.slider_mass * a_s
    assert np.abs(res).max() < 1e-5 * scale
    # The rod: forces, and moments about G with the pins' friction torques.
    np.testing.assert_allclose(fp - fs, m.rod_mass * a_g, rtol=0, atol=1e-5 * scale)
    mr = fr.pin_mu * fr.pin_radius
    e = k.pin - k.slider
    torques = -mr * np.hypot(*fp.T) * np.sign(gd - planet) - mr * np.hypot(*fs.T) * np.sign(gd)
    moment = 0.5 * (e[:, 0] * fp[:, 1] - e[:, 1] * fp[:, 0]) + 0.5 * (
        e[:, 0] * fs[:, 1] - e[:, 1] * fs[:, 0]
    )
    i_g = m.rod_mass * m.press.L**2 / 12
    assert np.abs(moment + torques - i_g * gdd).max() < 1e-5 * scale * m.press.L
    np.testing.assert_allclose(planet, f.planet_spin, rtol=1e-6)


@pytest.mark.parametrize("fr", FRICTIONS)
def test_crank_torque_from_the_planets_pin_force(fr: PressFriction) -> None:
    """The carrier and the planet keep their kinetic energy and the gears are
    lossless, so the crank's power is what the planet gives the rod: M·ω =
    F_P·v_P + M_P·ω_planet (M_P the pin's friction torque on the rod), v_P by
    central differences of the pin's position."""
    m = line()
    a = grid()
    f = solve(fr, a)
    h = 1e-5
    v_p = -W * (m.press.solve(a + h).pin - m.press.solve(a - h).pin) / (2 * h)
    fp = f.pin_force
    mp = -fr.pin_mu * fr.pin_radius * np.hypot(*fp.T) * np.sign(f.rod_spin - f.planet_spin)
    m_ref = (np.sum(fp * v_p, axis=1) + mp * f.planet_spin) / W
    np.testing.assert_allclose(f.torque, m_ref, rtol=0, atol=1e-6 * np.abs(f.torque).max())
    # Over the turn: the crank's work is the blank's plus the friction's.
    e = m.force.energy_j * W / (2 * math.pi)
    np.testing.assert_allclose(np.mean(f.input_power), e + np.mean(f.friction_power), rtol=1e-3)


def test_zero_friction_gives_todays_torque() -> None:
    a = grid(3600)
    f = solve(PressFriction(), a)
    m = line()
    t = m.press.crank_torque(
        a, force=m.force, slider_mass=m.slider_mass, rod_mass=m.rod_mass, k_Sp=m.k_Sp
    )
    np.testing.assert_array_equal(f.torque, t.torque_nm(W))
    np.testing.assert_array_equal(f.losses, 0.0)


# ------------------------------------------------------------------ the machine
def data() -> dict[str, Any]:
    return copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLES / "extrusion_press_line.toml").data))


@pytest.fixture(scope="module")
def press_line() -> tuple[Any, Any]:
    d = data()
    assert "friction" in d["mechanism"]["drive"]
    bare = copy.deepcopy(d)
    del bare["mechanism"]["drive"]["friction"]
    run = [cm.machine.analyze(cm.Machine.from_dict(x, "m.toml"), progress=False) for x in (d, bare)]
    return run[0], run[1]


def test_the_press_lines_efficiency_and_shaft_torque(press_line: tuple[Any, Any]) -> None:
    r, bare = press_line
    res, res0 = r.mechanisms["drive"], bare.mechanisms["drive"]
    e = res.efficiency()
    linkage = cm.machine.analyze(
        cm.Machine.from_toml(EXAMPLES / "knife_cutter.toml"), progress=False
    ).mechanisms["knife"]
    assert set(e) == set(linkage.efficiency())
    assert set(e["friction_power_by_element_w"]) == {"guide", "slider pin", "planet pin"}
    assert 0.5 < e["cycle_efficiency"] < 1.0 and res0.efficiency() is None
    p2, s2, ph, ev = res.shaft_torque()
    p0, s0, ph0, ev0 = res0.shaft_torque()
    np.testing.assert_array_equal(p2, p0)
    assert (ph, ev) == (ph0, ev0)
    w = r.nominal_rpm * 2 * math.pi / 60
    assert np.mean(s2 - s0) == pytest.approx(e["mean_friction_power_w"] / w, rel=1e-12)
    mach = machine_efficiency(r)
    assert mach is not None and list(mach["mechanisms"]) == ["drive"]
    assert mach["machine_efficiency"] == pytest.approx(e["cycle_efficiency"], rel=1e-9)
    assert res.json()["friction"] == e and res.failures() == []


# ------------------------------------------------------------------- bad input
def refused(friction: Any, drop: tuple[str, ...] = ()) -> str:
    d = data()
    d["mechanism"]["drive"]["friction"] = friction
    for k in drop:
        d["mechanism"]["drive"].pop(k)
    with pytest.raises(cm.InputError) as e:
        cm.Machine.from_dict(d, "dir/m.toml")
    return str(e.value)


def test_bad_friction_tables_are_named() -> None:
    msg = refused({"guide_mu": -0.1})
    assert "dir/m.toml" in msg and "drive.friction]" in msg and "guide_mu" in msg
    assert "-0.1" in msg
    assert "pin_mu is given without pin_radius_m" in refused({"pin_mu": 0.1})
    msg = refused({"pins": {}})
    assert "pins" in msg and "pin_radius_m" in msg and "guide_mu" in msg
    msg = refused({"guide_mu": 0.1}, ("deformation_force", "slider_mass_kg", "rod_mass_kg"))
    assert "friction acts with the slider's and the rod's forces" in msg


def test_a_large_coefficient_warns() -> None:
    d = data()
    d["mechanism"]["drive"]["friction"] = {"guide_mu": 8.0}
    with pytest.warns(cm.CyclomechWarning, match=r"guide_mu = 8 is above 0.5.*guide_mu = 0.08"):
        cm.Machine.from_dict(d, "dir/m.toml")
