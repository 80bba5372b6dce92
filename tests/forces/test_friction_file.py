"""Friction in a machine file (issue 34 item 5, the machine side): the
``[mechanism.<name>.friction]`` table of a linkage read into the same
:class:`~cyclomech.forces.Friction` one builds by hand (the forces equal
:func:`kinetostatics_with_friction` called directly), a slider-crank's guide
friction against the closed form μ·|N|·|v| from its positions, and bad input
named by file, table, key and value."""

from __future__ import annotations

import copy
import math
import warnings
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
F = cm.forces
RAD = 2 * math.pi / 60
CRANK, ROD, P = 0.1, 0.35, 500.0


def knife_data() -> dict[str, Any]:
    return copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLES / "knife_cutter.toml").data or {}))


def slider_data(friction: dict[str, Any] | None = None) -> dict[str, Any]:
    """The example machine with a slider-crank ``s`` (crank 0.1 m, rod 0.35 m,
    block C on a horizontal guide; massless) whose block is pushed back by P
    while it moves left (crank 10°–170°), and its ``friction`` table."""
    d = copy.deepcopy(dict(cm.Machine.example().data or {}))
    d["mechanism"]["s"] = {
        "kind": "linkage",
        "points": {"A": [0.0, 0.0], "B": [CRANK, 0.0], "C": [CRANK + ROD, 0.0]},
        "links": [["A", "B"], ["B", "C"]],
        "ground": ["A"],
        "driver": ["A", "B"],
        "sliders": {"C": {"ground": [1.0, 0.0]}},
        "load": [{"point": "C", "force_n": [[P, 0.0], [P, 0.0]], "angle_deg": [10.0, 170.0]}],
    }
    if friction is not None:
        d["mechanism"]["s"]["friction"] = friction
    return d


def build(d: dict[str, Any]) -> cm.Machine:
    return cm.Machine.from_dict(d, "dir/m.toml")


def refused(d: dict[str, Any]) -> str:
    with pytest.raises(cm.InputError) as e:
        build(d)
    return str(e.value)


# ------------------------------------------------------------ the same forces
def test_the_files_friction_is_kinetostatics_with_friction() -> None:
    """The knife's table (defaults for every joint, the crank's bearing O
    overridden) is the Friction one writes by hand, and its forces at 45 rpm are
    kinetostatics_with_friction's called directly on the same angles."""
    knife = cm.Machine.from_toml(EXAMPLES / "knife_cutter.toml").mechanisms["knife"]
    pin = F.PinFriction(0.015, 0.08)
    by_hand = F.Friction(
        pins={p: pin for p in "ADBCEF"} | {"O": F.PinFriction(0.03, 0.08)}, guides={}
    )
    assert knife.friction == by_hand
    angles = knife.linkage.drawn_angle + np.arange(3600) * (2 * math.pi / 3600)
    direct = F.kinetostatics_with_friction(
        knife.linkage, angles, by_hand, 45.0, **(knife.dynamics or {})
    )
    got = knife.friction_forces(45.0)
    assert got is not None
    np.testing.assert_allclose(got.torque, direct.torque, rtol=1e-12, atol=1e-9)
    order = [direct.elements.index(e) for e in got.elements]
    np.testing.assert_allclose(got.losses, direct.losses[..., order], rtol=1e-12, atol=1e-9)


def test_one_line_and_overrides() -> None:
    """One inline table sets every joint and guide; an override changes its keys
    only, the others from the defaults."""
    d = slider_data({"pin_radius_m": 0.01, "pin_mu": 0.1, "guide_mu": 0.15})
    d["mechanism"]["s"]["friction"]["pins"] = {"A": {"radius_m": 0.02}}
    d["mechanism"]["s"]["friction"]["guides"] = {"C": {"viscous_n_s_per_m": 2.0}}
    f = build(d).mechanisms["s"].friction
    assert f.pins == {
        "A": F.PinFriction(0.02, 0.1),
        "B": F.PinFriction(0.01, 0.1),
        "C": F.PinFriction(0.01, 0.1),
    }
    assert f.guides == {"C": F.GuideFriction(0.15, 2.0)}
    # Without defaults, only the joints named have friction.
    f = build(slider_data({"pins": {"B": {"radius_m": 0.01, "mu": 0.1}}})).mechanisms["s"].friction
    assert f.pins == {"B": F.PinFriction(0.01, 0.1)} and f.guides == {}


# ------------------------------------------------------------ a closed form
def _closed_form(mu: float, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The slider-crank's guide friction loss and input power [W] at N crank
    angles, from its positions alone: the rod is a massless two-force member
    (frictionless pins) pushing the block with S along û (B→C); on the block,
    along the guide S·u_x + L − μ·|S·u_y|·sgn(v) = 0, across it N = −S·u_y (no
    masses: no inertia at any speed). Solved for S case by case (its sign), the
    loss μ·|N|·|v| and the input power the load's plus the loss. The velocity is
    the positions' central difference."""
    phi = np.arange(n) * (2 * math.pi / n)
    omega = 30.0 * RAD

    def x_c(p: np.ndarray) -> np.ndarray:
        return CRANK * np.cos(p) + np.sqrt(ROD**2 - (CRANK * np.sin(p)) ** 2)

    h = 1e-6
    v = (x_c(phi + h) - x_c(phi - h)) / (2 * h) * omega
    bx, by = CRANK * np.cos(phi), CRANK * np.sin(phi)
    u = np.stack([x_c(phi) - bx, -by], axis=1) / ROD
    deg = np.degrees(phi)
    load = np.where((deg >= 10.0) & (deg <= 170.0), P, 0.0)
    s = np.zeros(n)
    for sigma in (1.0, -1.0):
        trial = -load / (u[:, 0] - mu * sigma * np.abs(u[:, 1]) * np.sign(v))
        s = np.where(np.sign(trial) == sigma, trial, s)
    loss = mu * np.abs(s * u[:, 1]) * np.abs(v)
    p_in = load * np.abs(v) * (load > 0) + loss
    return phi, loss, p_in


def test_guide_friction_against_the_closed_form() -> None:
    """The file's slider-crank at 30 rpm: each angle's friction loss is μ·|N|·|v|
    and the efficiency over the turn ΣP·|v| / Σ(P·|v| + loss), both from the
    positions (to the central difference's 1e-7)."""
    mu = 0.2
    d = slider_data({"guide_mu": mu})
    d["machine"]["nominal_rpm"] = 30.0
    m = build(d)
    f = m.mechanisms["s"].friction_forces(30.0, 720)
    phi, loss, p_in = _closed_form(mu, 720)
    np.testing.assert_allclose(f.angles, phi, atol=1e-12)
    np.testing.assert_allclose(f.losses[0, :, 0], loss, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(f.input_power[0], p_in, rtol=1e-6, atol=1e-6)
    eta = 1.0 - loss.sum() / p_in.sum()
    assert 0.8 < eta < 0.99
    assert float(f.cycle_efficiency()[0]) == pytest.approx(eta, rel=1e-7)


# ------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    ("friction", "words"),
    [
        (
            {"pin_radius_m": 0.01, "pin_mu": -0.1},
            ["[mechanism.s.friction]", "pin_mu = -0.1", "≥ 0"],
        ),
        ({"guide_mu": "0.1"}, ["[mechanism.s.friction]", "guide_mu = '0.1'", "number"]),
        ({"pin_mu": 0.1}, ["pin_mu is given without pin_radius_m", "joint 'A'"]),
        ({"pins": {"Z": {"radius_m": 0.01, "mu": 0.1}}}, ["pins.Z", "not a joint", "A, B, C"]),
        ({"pins": {"B": {"mu": 0.1}}}, ["pins.B", "mu is given without radius_m"]),
        ({"pins": {"B": {"radius_m": 0.01, "mu": 0.1, "r": 1}}}, ["pins.B", "unknown key 'r'"]),
        ({"guides": {"B": {"mu": 0.1}}}, ["guides.B", "not a slider's point", "sliders are C"]),
        ({"pins": {"B": 0.1}}, ["pins = ", "table of tables"]),
        ({"pin_muu": 0.1}, ["[mechanism.s.friction]", "unknown key 'pin_muu'", "pin_mu"]),
        ({"guide_viscous_n_s_per_m": -1.0}, ["guide_viscous_n_s_per_m = -1.0", "≥ 0"]),
    ],
)
def test_bad_friction_is_named(friction: dict[str, Any], words: list[str]) -> None:
    msg = refused(slider_data(friction))
    assert msg.startswith("dir/m.toml: ")
    for w in words:
        assert w in msg, (w, msg)


def test_guide_keys_need_a_slider() -> None:
    d = knife_data()
    d["mechanism"]["knife"]["friction"]["guide_mu"] = 0.1
    assert "guide_mu is given but the linkage has no slider" in refused(d)


def test_friction_needs_forces() -> None:
    d = slider_data({"guide_mu": 0.1})
    del d["mechanism"]["s"]["load"]
    assert "[mechanism.s]: friction acts with the joints' forces" in refused(d)


def test_a_large_coefficient_warns_naming_the_slip() -> None:
    with pytest.warns(cm.CyclomechWarning, match=r"guide_mu = 8 is above 0.5.*guide_mu = 0.08"):
        build(slider_data({"guide_mu": 8.0}))


def test_a_pin_radius_in_millimetres_warns() -> None:
    with pytest.warns(cm.CyclomechWarning, match=r"pin_radius_m = 15.*millimetres"):
        build(slider_data({"pin_radius_m": 15.0, "pin_mu": 0.1}))


def test_a_press_refuses_a_linkages_per_joint_overrides() -> None:
    """A press takes its own friction table (tests/press/test_press_friction.py):
    a linkage's ``pins`` overrides are unknown there, the press's keys listed."""
    d = copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLES / "extrusion_press_line.toml").data or {}))
    d["mechanism"]["drive"]["friction"] = {"pins": {"A": {"radius_m": 0.01}}}
    msg = refused(d)
    assert "pins" in msg and "guide_mu" in msg and "pin_radius_m" in msg


def test_a_cam_refuses_a_linkages_friction_keys() -> None:
    """A cam takes its own friction table (tests/cam/test_cam_friction.py): a
    linkage's pin keys are unknown there, the cam's keys listed."""
    d = copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLES / "stb_loom.toml").data or {}))
    d["mechanism"]["lifter cam"]["friction"] = {"pin_radius_m": 0.01, "pin_mu": 0.1}
    msg = refused(d)
    assert "pin_mu" in msg and "roller_pin_mu" in msg and "pivot_mu" in msg


def test_no_warning_for_plausible_values() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build(slider_data({"pin_radius_m": 0.02, "pin_mu": 0.5, "guide_mu": 0.1}))


def six_bar(friction: dict[str, Any]) -> dict[str, Any]:
    """The example machine with a four-bar A-B-C-D whose coupler's joint C also
    carries a rod C-E to a block E on a horizontal guide: three members at C."""
    d = copy.deepcopy(dict(cm.Machine.example().data or {}))
    d["mechanism"]["six"] = {
        "kind": "linkage",
        "points": {
            "A": [0.0, 0.0],
            "B": [0.1, 0.0],
            "C": [0.3, 0.25],
            "D": [0.4, 0.0],
            "E": [0.7, 0.1],
        },
        "links": [["A", "B"], ["B", "C"], ["C", "D"], ["C", "E"]],
        "ground": ["A", "D"],
        "driver": ["A", "B"],
        "sliders": {"E": {"ground": [1.0, 0.0]}},
        "load": [{"point": "E", "force_n": [-100.0, 0.0]}],
        "friction": friction,
    }
    return d


def test_a_joint_of_three_members() -> None:
    """The defaults leave C frictionless with a warning naming it; naming C is an
    error saying why and listing the joints that take friction."""
    with pytest.warns(cm.CyclomechWarning, match=r"leave joint\(s\) C frictionless"):
        f = build(six_bar({"pin_radius_m": 0.01, "pin_mu": 0.1})).mechanisms["six"].friction
    assert sorted(f.pins) == ["A", "B", "D", "E"]
    msg = refused(six_bar({"pins": {"C": {"radius_m": 0.01, "mu": 0.1}}}))
    assert "pins.C: friction is not modelled at joint 'C', which joins more than two" in msg
    assert "A, B, D, E" in msg


def test_an_overrides_radius_in_millimetres_warns() -> None:
    with pytest.warns(cm.CyclomechWarning, match=r"pins.B: radius_m = 20.*millimetres"):
        build(slider_data({"pins": {"B": {"radius_m": 20.0, "mu": 0.1}}}))
