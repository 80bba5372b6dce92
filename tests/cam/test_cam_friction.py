"""Friction of a cam's follower (issue 34 item 5): Coulomb friction at an
oscillating follower's pivot or a translating follower's guide, and at the
roller's pin (:mod:`cyclomech.cam._friction`), against references written here:
the arm's Newton–Euler equations from ψ(θ) by finite differences and the contact
geometry; the cam shaft's torque as the moment of the contact force about the
cam's centre (a force balance, not the power balance the code uses); the power
balance over the cycle; the stem's closed form at one pressure angle; μ = 0
gives today's numbers; the loom's machine file; bad input by key."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cam._friction import CamFriction, cam_friction
from cyclomech.machine._efficiency import machine_efficiency

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
S = cm.cam.Segment
RPM = 300.0
W = RPM * 2.0 * math.pi / 60.0
A, L, RB, RR = 0.13, 0.1, 0.06, 0.012
INERTIA, SPRING, PRELOAD, DRAG = 0.03, 40.0, 20.0, 2.0


def oscillating_cam(closure: str = "spring") -> cm.cam.Cam:
    """An arm swung through 12° by cycloidal rise and return (smooth ψ″ for the
    finite differences) with dwells between."""
    segs = [
        S("rise", 100, math.radians(12.0), law="cycloidal"),
        S("dwell", 80),
        S("return", 100, math.radians(12.0), law="cycloidal"),
        S("dwell", 80),
    ]
    return cm.cam.Cam(segs, cm.cam.OscillatingRoller(A, L, RB, RR), closure)


ARM_LOADS = cm.cam.FollowerLoads(INERTIA, SPRING, PRELOAD, (DRAG, 0.0, 0.0, 0.0))


def grid(n: int = 720) -> np.ndarray:
    return np.arange(n) * (2.0 * math.pi / n)


def fixed(theta: np.ndarray, p: np.ndarray) -> np.ndarray:
    """A cam-frame point at cam angle θ in the fixed frame (the cam turns by +θ)."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([p[:, 0] * c - p[:, 1] * s, p[:, 0] * s + p[:, 1] * c], axis=1)


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


# ------------------------------------------- oscillating: the pivot's friction
def test_pivot_friction_power_from_the_arms_newton_euler_equations() -> None:
    """Only pivot friction: the test writes the arm's balance about its pivot
    from ψ(θ) (ψ̇, ψ̈ by central differences), the spring, preload and drag, and
    the contact normal's lever about the pivot from the profile and pitch points:
    N·lever = I·ψ̈ + k·ψ + M0 + M_L + μ·r·|N|·sgn ψ̇, the pivot reaction |R| = |N|
    (the arm's centre of mass on its pivot, the roller frictionless), the loss
    μ·r·|R|·|ψ̇|."""
    cam, mu, r = oscillating_cam(), 0.08, 0.01
    th = grid()
    f = cam_friction(cam, th, RPM, ARM_LOADS, CamFriction(pivot_radius=r, pivot_mu=mu))
    h = 1e-4
    psi = [cam.solve(th + d).s for d in (-h, 0.0, h)]
    dpsi = (psi[2] - psi[0]) / (2 * h) * W  # ψ̇ [rad/s]
    ddpsi = (psi[2] - 2 * psi[1] + psi[0]) / h**2 * W * W  # ψ̈ [rad/s²]
    load = np.where(np.degrees(th) < 100.0, DRAG, 0.0)
    q = INERTIA * ddpsi + SPRING * psi[1] + PRELOAD + load
    kin = cam.solve(th)
    c = fixed(th, kin.pitch)
    n = (c - fixed(th, kin.profile)) / RR  # the contact normal, outward
    # The lever of the normal about the pivot O = (a, 0), in the sense of ψ (the
    # arm's angle is π − ψ: a counter-clockwise moment is −ψ's).
    lever = -cross(c - np.array([A, 0.0]), n)
    # sgn ψ̇: 0 where the arm dwells (the differences there are round-off)
    moving = np.where(np.abs(dpsi) > 1e-6, np.sign(dpsi), 0.0)
    n_abs = np.abs(q) / (lever - np.sign(q) * mu * r * moving)
    ref = mu * r * n_abs * np.abs(dpsi)
    assert not f.self_locking.any()
    # (central differences: ~1e-5 of the loss where ψ̇ is small, at a rise's ends)
    np.testing.assert_allclose(f.losses[:, 0], ref, rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(f.contact_force, n_abs, rtol=1e-4)
    np.testing.assert_array_equal(f.losses[:, 1], 0.0)
    # Where the arm dwells the pivot costs nothing.
    dwell = (np.degrees(th) > 101) & (np.degrees(th) < 179)
    assert dwell.any() and (f.losses[dwell, 0] == 0.0).all()
    assert f.losses[:, 0].max() > 0.01  # and it is not trivially zero elsewhere


@pytest.mark.parametrize("closure", ["spring", "groove"])
@pytest.mark.parametrize(
    "friction",
    [
        CamFriction(pivot_radius=0.01, pivot_mu=0.08),
        CamFriction(pin_radius=0.004, pin_mu=0.05),
        CamFriction(pivot_radius=0.01, pivot_mu=0.15, pin_radius=0.004, pin_mu=0.05),
    ],
)
def test_shaft_torque_is_the_contact_forces_moment_and_balances_the_power(
    friction: CamFriction, closure: str
) -> None:
    """The code's torque comes from the power balance T = Q·s′ + P_f/ω; here it is
    the moment of the contact force (normal N along the profile's normal, the
    roller pin's tangential force k·|F| against the roller's spin) about the cam's
    centre, at every angle; and over the cycle the shaft's work is the follower's
    plus the friction's."""
    cam = oscillating_cam(closure)
    loads = (
        ARM_LOADS
        if closure == "spring"
        else cm.cam.FollowerLoads(INERTIA, 0.0, 0.0, (DRAG, 0, 0, 0))
    )
    th = grid(3600)
    f = cam_friction(cam, th, RPM, loads, friction)
    kin = cam.solve(th)
    c = fixed(th, kin.pitch)
    n = (c - fixed(th, kin.profile)) / RR
    sigma = np.where(f.normal_force < 0, -1.0, 1.0)
    point = c - (sigma * RR)[:, None] * n
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)
    k = friction.pin_mu * friction.pin_radius / RR
    ft = -sigma * k * f.contact_force * np.sign(f.roller_spin)
    force = f.normal_force[:, None] * n + ft[:, None] * t
    np.testing.assert_allclose(cross(point, force), f.torque, rtol=0, atol=1e-9)
    if closure == "groove":
        assert (f.normal_force < 0).any()  # both flanks are exercised
    # Power over the cycle: ∫T·ω = ∫Q·ψ̇ + ∫P_f, Q·ψ̇ integrating to the drag's work.
    q = cam.loads(th, RPM, loads).force
    useful = np.mean(q * kin.ds * W)
    np.testing.assert_allclose(
        np.mean(f.input_power), useful + np.mean(f.friction_power), rtol=1e-12
    )
    np.testing.assert_allclose(useful, DRAG * math.radians(12.0) * RPM / 60.0, rtol=1e-6)


def test_roller_spin_from_rolling_without_slip() -> None:
    """The roller's spin relative to the arm, from the rolling condition written
    here: the contact point's velocity on the cam (ω × P) equals the roller's
    (v_C + ω_r × (P − C)), v_C by central differences of the roller centre."""
    cam = oscillating_cam()
    th = grid()
    f = cam_friction(cam, th, RPM, ARM_LOADS, CamFriction(pin_radius=0.004, pin_mu=0.005))
    h = 1e-5
    cs = [fixed(th + d, cam.solve(th + d).pitch) for d in (-h, h)]
    vc = (cs[1] - cs[0]) / (2 * h) * W
    kin = cam.solve(th)
    c, p = fixed(th, kin.pitch), fixed(th, kin.profile)
    tang = np.stack([-(c - p)[:, 1], (c - p)[:, 0]], axis=1) / RR  # ẑ × n
    v_cam = W * np.stack([-p[:, 1], p[:, 0]], axis=1)  # ω ẑ × P
    # (v_C + ω_r ẑ×(P − C))·t = v_cam·t, ẑ×(P − C) = −RR·t
    omega_r = (np.sum(vc * tang, axis=1) - np.sum(v_cam * tang, axis=1)) / RR
    arm = -W * kin.ds  # the arm's counter-clockwise angular velocity
    np.testing.assert_allclose(f.roller_spin, omega_r - arm, rtol=1e-6, atol=1e-6)


# ------------------------------------------------ translating: the guide's friction
@pytest.mark.parametrize("at_deg", [40.0, 220.0])  # on the rise, and on the return
def test_guide_friction_against_the_stems_closed_form(at_deg: float) -> None:
    """Only guide friction, one effective guide: the stem's balance at a pose of
    pressure angle φ is N·cos φ = Q + μ·N·|sin φ|·sgn ṡ (the side force N·sin φ),
    so N = Q/(cos φ ∓ μ|sin φ|), the loss μ·N·|sin φ|·|ṡ| and T = (Q·ṡ + loss)/ω;
    Q = m·s″·ω² + k·s + F0 written here."""
    segs = [S("rise", 150, 0.03, law="cycloidal"), S("return", 210, 0.03, law="cycloidal")]
    cam = cm.cam.Cam(segs, cm.cam.TranslatingRoller(0.03, 0.01))
    m, k, f0, mu = 1.2, 3000.0, 60.0, 0.12
    th = np.radians([at_deg])
    f = cam_friction(cam, th, RPM, cm.cam.FollowerLoads(m, k, f0), CamFriction(guide_mu=mu))
    kin = cam.solve(th)
    phi, ds = float(kin.pressure_angle[0]), float(kin.ds[0])
    q = m * float(kin.dds[0]) * W * W + k * float(kin.s[0]) + f0
    assert abs(phi) > math.radians(10) and q > 0
    n = q / (math.cos(phi) - mu * abs(math.sin(phi)) * math.copysign(1.0, ds))
    loss = mu * n * abs(math.sin(phi)) * abs(ds * W)
    assert f.normal_force[0] == pytest.approx(n, rel=1e-9)
    assert f.losses[0, 0] == pytest.approx(loss, rel=1e-9)
    assert f.torque[0] == pytest.approx((q * ds * W + loss) / W, rel=1e-9)


def test_a_guide_that_self_locks_is_nan_and_named() -> None:
    """μ·tan φ ≥ 1 on the rise: no finite contact force lifts the stem."""
    cam = cm.cam.Cam(
        [S("rise", 90, 0.03), S("return", 270, 0.03)], cm.cam.TranslatingRoller(0.03, 0.01)
    )
    th = grid()
    f = cam_friction(
        cam, th, RPM, cm.cam.FollowerLoads(1.0, 1000.0, 30.0), CamFriction(guide_mu=3.0)
    )
    phi = cam.solve(th).pressure_angle
    # (where a spring-closed follower has left the cam there is no contact)
    touching = ~cam.loads(th, RPM, cm.cam.FollowerLoads(1.0, 1000.0, 30.0)).separated
    expect = (3.0 * np.abs(np.tan(phi)) >= 1.0) & (cam.solve(th).ds > 0) & touching
    assert expect.any()
    np.testing.assert_array_equal(f.self_locking, expect)
    assert np.isnan(f.torque[f.self_locking]).all()


def test_off_the_cam_nothing_passes_to_the_shaft() -> None:
    """Above the jump speed a spring-closed follower leaves the cam: there the
    contact force, the losses and both torques are 0 (the torque was still Q·s′,
    up to 0.6 N·m, beside a contact force of 0); Cam.loads keeps the would-be Q·s′
    (its documented rule, as for the pull in normal_force); on the cam the torque
    is the power balance (Q·s′ + losses/ω) as before."""
    cam = oscillating_cam()
    loads = cm.cam.FollowerLoads(INERTIA, SPRING, 2.0, (DRAG, 0.0, 0.0, 0.0))
    rpm = 1.3 * cam.jump_rpm(loads)[0]
    th = grid()
    f = cam_friction(cam, th, rpm, loads, CamFriction(pivot_mu=0.1, pin_mu=0.1))
    ld = cam.loads(th, rpm, loads)
    off = ld.separated
    assert off.any() and not off.all()
    for name in ("contact_force", "torque", "torque_without"):
        np.testing.assert_array_equal(getattr(f, name)[off], 0.0, err_msg=name)
    np.testing.assert_array_equal(f.losses[off], 0.0)
    ds = cam.solve(th).ds
    np.testing.assert_allclose(ld.shaft_torque, ld.force * ds, rtol=1e-12, atol=1e-12)
    assert np.abs(ld.shaft_torque[off]).max() > 0.0
    w = rpm * 2.0 * math.pi / 60.0
    on = f.torque[~off] - (ld.force * ds + f.losses.sum(axis=1) / w)[~off]
    np.testing.assert_allclose(on, 0.0, atol=1e-12 * np.abs(f.torque).max())


def test_zero_friction_gives_todays_numbers() -> None:
    cam = oscillating_cam("groove")
    th = grid(3600)
    f = cam_friction(cam, th, RPM, ARM_LOADS, CamFriction())
    ld = cam.loads(th, RPM, ARM_LOADS)
    # Cam.solve's fast kernel (FMA, issue 37 row 4) and the loads' kernel
    # round apart by an ulp or so of the torque's scale: no longer bit for bit.
    scale = np.max(np.abs(ld.shaft_torque))
    np.testing.assert_allclose(f.torque, ld.shaft_torque, rtol=0, atol=1e-12 * scale)
    np.testing.assert_array_equal(f.losses, 0.0)
    np.testing.assert_allclose(f.normal_force, ld.normal_force, rtol=1e-12, atol=1e-12)


# ------------------------------------------------------------------ the machine
def loom_data() -> dict[str, Any]:
    return copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLES / "stb_loom.toml").data or {}))


def analyze(d: dict[str, Any]) -> Any:
    return cm.machine.analyze(cm.Machine.from_dict(d, "dir/m.toml"), progress=False)


@pytest.fixture(scope="module")
def loom() -> tuple[Any, Any]:
    d = loom_data()
    assert "friction" in d["mechanism"]["lifter cam"]
    bare = copy.deepcopy(d)
    del bare["mechanism"]["lifter cam"]["friction"]
    return analyze(d), analyze(bare)


def test_the_looms_efficiency_and_shaft_torque(loom: tuple[Any, Any]) -> None:
    """The cam's efficiency() has the linkage's keys; the machine's efficiency
    picks it up; the shaft's static torque is the frictionless one plus the
    friction torque, whose mean is the mean friction power over ω."""
    r, bare = loom
    res, res0 = r.mechanisms["lifter cam"], bare.mechanisms["lifter cam"]
    e = res.efficiency()
    assert set(e) == {
        "nominal_rpm",
        "cycle_efficiency",
        "mean_friction_power_w",
        "mean_input_power_w",
        "mean_torque_nm",
        "peak_torque_nm",
        "peak_torque_nm_without",
        "friction_power_by_element_w",
        "self_locking_crank_deg",
    }
    assert res0.efficiency() is None
    w = r.nominal_rpm * 2 * math.pi / 60
    assert 0.0 < e["cycle_efficiency"] < 1.0
    assert set(e["friction_power_by_element_w"]) == {"pivot", "roller pin"}
    p2, s2, ph, ev = res.shaft_torque()
    p0, s0, ph0, ev0 = res0.shaft_torque()
    np.testing.assert_array_equal(p2, p0)
    assert (ph, ev) == (ph0, ev0)
    np.testing.assert_allclose(s2 - s0, res.friction_torque(), rtol=0, atol=1e-12)
    assert np.mean(s2 - s0) == pytest.approx(e["mean_friction_power_w"] / w, rel=1e-12)
    m = machine_efficiency(r)
    assert m is not None and list(m["mechanisms"]) == ["lifter cam"]
    assert m["mean_friction_power_w"] == pytest.approx(e["mean_friction_power_w"], rel=1e-12)
    assert machine_efficiency(bare) is None
    assert res.json()["friction"] == e


def test_zero_coefficients_leave_the_loom_as_it_was(loom: tuple[Any, Any]) -> None:
    d = loom_data()
    d["mechanism"]["lifter cam"]["friction"] = {"pivot_radius_m": 0.01, "pivot_mu": 0.0}
    r, (_, bare) = analyze(d), loom
    a, b = r.mechanisms["lifter cam"].shaft_torque(), bare.mechanisms["lifter cam"].shaft_torque()
    # Within round-off (Cam.solve's fast kernel and the loads' round apart by an
    # ulp or so of the torque's scale: test_zero_friction_gives_todays_numbers).
    scale = np.max(np.abs(b[1]))
    np.testing.assert_allclose(a[1], b[1], rtol=0, atol=1e-12 * scale)
    for key in ("mean_torque_nm", "peak_torque_nm", "rms_torque_nm", "power_w"):
        want = getattr(bare.shaft.at_nominal, key)
        assert getattr(r.shaft.at_nominal, key) == pytest.approx(want, rel=1e-12, abs=1e-12 * scale)


# ------------------------------------------------------------------- bad input
def refused(friction: Any, **cam: Any) -> str:
    d = loom_data()
    d["mechanism"]["lifter cam"]["friction"] = friction
    d["mechanism"]["lifter cam"].update(cam)
    with pytest.raises(cm.InputError) as e:
        cm.Machine.from_dict(d, "dir/m.toml")
    return str(e.value)


def test_bad_friction_tables_are_named() -> None:
    at = 'dir/m.toml: [mechanism."lifter cam".friction]'
    msg = refused({"pivot_radius_m": 0.01, "pivot_mu": -0.1})
    assert "pivot_mu" in msg and "-0.1" in msg and "friction" in msg
    msg = refused({"guide_mu": 0.1})
    assert "guide_mu = 0.1 is for a translating follower" in msg and "pivot_mu" in msg
    msg = refused({"pivot_mu": 0.1})
    assert "pivot_mu is given without pivot_radius_m" in msg
    msg = refused({"pin_mu": 0.1})
    assert "pin_mu" in msg and "roller_pin_mu" in msg  # unknown, the valid keys listed
    msg = refused({"roller_pin_radius_m": 0.02, "roller_pin_mu": 0.01})
    assert "roller_pin_radius_m = 0.02 must be below" in msg and "roller_radius_m" in msg
    assert at.split(": ")[0] in refused({"pivot_radius_m": "x", "pivot_mu": 0.1})


def test_friction_needs_the_followers_loads() -> None:
    d = loom_data()
    t = d["mechanism"]["lifter cam"]
    for key in ("inertia_kg_m2", "max_stress_pa"):
        t.pop(key)
    for row in t["segment"]:
        row.pop("load_nm", None)
    with pytest.raises(
        cm.InputError, match=r"friction acts with the follower's forces.*inertia_kg_m2"
    ):
        cm.Machine.from_dict(d, "dir/m.toml")


def test_a_large_coefficient_warns() -> None:
    d = loom_data()
    d["mechanism"]["lifter cam"]["friction"] = {"pivot_radius_m": 0.01, "pivot_mu": 8.0}
    with pytest.warns(cm.CyclomechWarning, match=r"pivot_mu = 8 is above 0.5.*pivot_mu = 0.08"):
        cm.Machine.from_dict(d, "dir/m.toml")


def test_a_flat_follower_and_a_cam_file_refuse_friction() -> None:
    flat = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    with pytest.raises(cm.InputError, match="flat-faced follower"):
        cam_friction(flat, [0.0], RPM, cm.cam.FollowerLoads(1.0), CamFriction(guide_mu=0.1))
    table = {
        "follower": "oscillating",
        "pivot_distance_m": A,
        "arm_length_m": L,
        "base_radius_m": RB,
        "roller_radius_m": RR,
        "friction": {"pivot_radius_m": 0.01, "pivot_mu": 0.08},
        "segment": [
            {"kind": "rise", "angle_deg": 180, "stroke_deg": 10},
            {"kind": "return", "angle_deg": 180, "stroke_deg": 10},
        ],
    }
    with pytest.raises(cm.InputError, match=r"\[cam\]: friction is not modelled for a cam file"):
        cm.cam.CamDesign.from_table(table, "[cam]")


def test_a_self_locking_follower_is_a_failure_of_the_machine() -> None:
    """A pivot friction that no contact force overcomes (μ·r_p larger than the
    normal's lever over part of the turn) fails the run, naming the cam, as a
    linkage's self-locking does; the shaft's torque stays frictionless."""
    d = loom_data()
    d["mechanism"]["lifter cam"]["friction"] = {"pivot_radius_m": 0.5, "pivot_mu": 0.5}
    r = analyze(d)
    res = r.mechanisms["lifter cam"]
    assert res.friction.self_locking.any()
    assert any("friction self-locks the follower of 'lifter cam'" in t for t in r.failures)
    np.testing.assert_array_equal(res.friction_torque(), 0.0)
    e = res.efficiency()
    assert e["cycle_efficiency"] is None and e["self_locking_crank_deg"]
