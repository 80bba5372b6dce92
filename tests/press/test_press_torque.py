"""The press drive's crank torque (issue 19, item 2): M(α) from a deformation-force
diagram and the inertia of the slider and the rod, against references built here
independently of the kernel's transfer functions — the crank-slider's textbook
closed form, the power balance with velocities and the kinetic energy's rate
taken by finite differences of *positions*, the energy per stroke by scipy
quadrature — and its wiring into the machine's main shaft."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, simpson

ROOT = Path(__file__).resolve().parents[2]
LINE = ROOT / "examples" / "extrusion_press_line.toml"

#: The example's drive (seed 003 kind, i = 3, offset guide added to exercise it).
GEAR = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.029, L=0.25, phi0=math.radians(55.95))
CRANK = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)

#: 5-point central difference weights of the first derivative (error O(h⁴)).
D1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 12.0


def fd(f, alpha: np.ndarray, h: float) -> np.ndarray:
    """d f/dα by the 5-point stencil; ``f`` maps an α array to an (N, ...) array."""
    vals = [f(alpha + k * h) for k in (-2, -1, 0, 1, 2)]
    return sum(w * v for w, v in zip(D1, vals, strict=True)) / h


def positions(press: cm.press.GearLeverPress, alpha: np.ndarray) -> dict[str, np.ndarray]:
    """Positions only from the kernel: slider height S, pin and slider points."""
    k = press.solve(alpha)
    return {"s": k.s, "pin": k.pin, "slider": k.slider}


def kinetic_per_omega2(
    press: cm.press.GearLeverPress, alpha: np.ndarray, m_s: float, m_r: float, h: float
) -> np.ndarray:
    """T/ω² [kg·m²] at α, with every velocity by finite differences of positions:
    the slider as a point, the rod uniform (centre at mid-length, m·L²/12)."""
    ds = fd(lambda a: positions(press, a)["s"], alpha, h)
    g = fd(lambda a: 0.5 * (positions(press, a)["pin"] + positions(press, a)["slider"]), alpha, h)

    def angle(a):
        p = positions(press, a)
        return np.arctan2(p["pin"][:, 0] - p["slider"][:, 0], p["pin"][:, 1] - p["slider"][:, 1])

    dphi = fd(angle, alpha, h)
    return 0.5 * (m_s * ds**2 + m_r * np.sum(g**2, axis=1) + m_r * press.L**2 / 12 * dphi**2)


# --- the force part -------------------------------------------------------------------------


def test_crank_slider_force_torque_is_the_textbook_closed_form():
    """Crank-slider (d = 0), crank a = R − r, rod L, λ = a/L: S = a(1 − cos α) +
    L(1 − √(1 − λ² sin² α)) and M = F·a·sin α·(1 + λ cos α/√(1 − λ² sin² α))
    (e.g. Artobolevsky; Shigley & Uicker, *Theory of Machines*, slider-crank force
    analysis) on the working stroke, 0 off it."""
    a, L = 0.06, 0.3
    lam = a / L
    f = cm.press.DeformationForce([0.0, 0.005, 0.012], [3e5, 1e5, 0.0])
    alpha = np.radians(np.linspace(0.0, 359.9, 3600))
    t = CRANK.crank_torque(alpha, force=f, k_Sp=0.1)
    root = np.sqrt(1 - lam**2 * np.sin(alpha) ** 2)
    S = a * (1 - np.cos(alpha)) + L * (1 - root)
    dS = a * np.sin(alpha) * (1 + lam * np.cos(alpha) / root)
    on = alpha <= t.alpha_p
    ref = np.where(on, np.interp(S, f.s, f.force, left=0, right=0) * dS, 0.0)
    np.testing.assert_allclose(t.static, ref, rtol=1e-12, atol=1e-9)
    # α_p is where S = S_p = 0.012 m on the way down.
    assert S[np.searchsorted(alpha, t.alpha_p)] == pytest.approx(0.012, rel=2e-3)
    assert t.per_omega2 == pytest.approx(np.zeros_like(alpha))


@pytest.mark.parametrize("press", [GEAR, CRANK], ids=["gear-lever", "crank-slider"])
def test_force_torque_is_the_power_balance_with_finite_difference_speeds(press):
    """M_F·ω = −F·v with v = dS/dt = −ω·dS/dα, dS/dα by differences of positions."""
    S_p = press.criteria(omega=1.0, k_Sp=0.1).S_p
    heights = np.array([0.0, 0.001, 0.0105, 0.0115, 0.0127]) * S_p / 0.0128
    f = cm.press.DeformationForce(heights, [2e5, 2e5, 1.9e5, 1.5e5, 0])
    alpha = np.radians(np.linspace(0.5, 359.5, 719))
    t = press.crank_torque(alpha, force=f, k_Sp=0.1)
    h = 1e-3
    ds = fd(lambda a: positions(press, a)["s"], alpha, h)
    s = positions(press, alpha)["s"]
    omega = 4.0
    v = -omega * ds
    power = np.where(alpha <= t.alpha_p, -f.at(s) * v, 0.0)
    np.testing.assert_allclose(t.static * omega, power, rtol=1e-6, atol=1e-6 * np.abs(power).max())
    assert np.all(t.static[alpha > t.alpha_p] == 0.0)


@pytest.mark.parametrize("press", [GEAR, CRANK], ids=["gear-lever", "crank-slider"])
def test_constant_force_energy_per_stroke_closed_form(press):
    """A constant force F over the whole stroke [0, S_p]: ∫₀^{α_p} M dα = F·S_p."""
    S_p = press.criteria(omega=1.0, k_Sp=0.1).S_p
    F = 1.5e5
    f = cm.press.DeformationForce([0.0, S_p], [F, F])
    c = press.criteria(omega=1.0, k_Sp=0.1)
    alpha = np.linspace(0.0, c.alpha_p, 20001)
    t = press.crank_torque(alpha, force=f, k_Sp=0.1)
    assert simpson(t.static, x=alpha) == pytest.approx(F * S_p, rel=1e-9)
    assert t.energy_per_stroke_j == pytest.approx(F * S_p, rel=1e-14)
    # Over the whole turn: nothing outside the working stroke (nor on the way up).
    turn = np.linspace(0.0, 2 * math.pi, 20001)
    whole = press.crank_torque(turn, force=f, k_Sp=0.1)
    off = (turn > c.alpha_p) & (turn < 2 * math.pi)  # α = 2π is BDC again
    assert np.all(whole.static[off] == 0.0)
    # (Π'(0) is 0 to the BDC's rounding.)
    assert np.all(whole.static[turn <= c.alpha_p] >= -1e-12 * whole.static.max())


def test_energy_per_stroke_is_the_quadrature_of_the_interpolated_table():
    s = [0.0, 0.001, 0.004, 0.0105, 0.0115, 0.0127]
    F = [2.1e5, 2.0e5, 2.05e5, 1.9e5, 1.5e5, 0.0]
    f = cm.press.DeformationForce(s, F)
    ref, _ = quad(lambda x: np.interp(x, s, F), 0.0, s[-1], points=s[1:-1], epsabs=1e-10)
    assert f.energy_j == pytest.approx(ref, rel=1e-12)
    # … and the torque's integral over the working stroke's angles (the stroke is monotone).
    c = GEAR.criteria(omega=1.0, k_Sp=0.1)
    alpha = np.linspace(0.0, c.alpha_p, 400001)
    t = GEAR.crank_torque(alpha, force=f, k_Sp=0.1)
    assert t.energy_per_stroke_j == f.energy_j
    assert simpson(t.static, x=alpha) == pytest.approx(ref, rel=1e-7)


# --- the inertia part -----------------------------------------------------------------------


@pytest.mark.parametrize("press", [GEAR, CRANK], ids=["gear-lever", "crank-slider"])
@pytest.mark.parametrize(("m_s", "m_r"), [(60.0, 0.0), (0.0, 15.0), (60.0, 15.0)])
def test_inertia_torque_is_the_rate_of_the_kinetic_energy(press, m_s, m_r):
    """M·ω = dT/dt = −ω·dT/dα at constant ω; T from finite-difference velocities of
    positions, dT/dα by finite differences again."""
    alpha = np.radians(np.linspace(0.0, 359.0, 360))
    t = press.crank_torque(alpha, slider_mass=m_s, rod_mass=m_r, k_Sp=0.1)
    h = 2e-3
    dT = fd(lambda a: kinetic_per_omega2(press, a, m_s, m_r, h), alpha, h)
    ref = -dT
    np.testing.assert_allclose(t.per_omega2, ref, rtol=1e-5, atol=1e-6 * np.abs(ref).max())
    assert np.all(t.static == 0.0)
    # The kinetic energy is periodic: no net work over a turn.
    turn = np.linspace(0.0, 2 * math.pi, 20001)
    whole = press.crank_torque(turn, slider_mass=m_s, rod_mass=m_r, k_Sp=0.1)
    assert abs(simpson(whole.per_omega2, x=turn)) < 1e-9 * np.abs(whole.per_omega2).max()


def test_slider_inertia_at_the_dead_centres_and_the_sign():
    """At BDC and TDC Π' = 0: no inertia torque. Just before BDC (α small > 0) the
    slider slows down and gives its energy back: M < 0."""
    c = CRANK.criteria(omega=1.0, k_Sp=0.1)
    t = CRANK.crank_torque([0.0, math.pi, 0.2], slider_mass=50.0, k_Sp=0.1)
    assert t.per_omega2[:2] == pytest.approx([0.0, 0.0], abs=1e-15)
    assert t.per_omega2[2] < 0
    assert c.ok


@settings(max_examples=25, deadline=None)
@given(
    d=st.floats(0.0, 0.029),
    L=st.floats(0.2, 0.5),
    phi0=st.floats(0.0, 2 * math.pi / 3),
    offset=st.floats(-0.02, 0.02),
    m_s=st.floats(0.0, 100.0),
    m_r=st.floats(0.0, 30.0),
)
def test_inertia_power_balance_over_random_designs(d, L, phi0, offset, m_s, m_r):
    press = cm.press.GearLeverPress(R=0.09, r=0.03, d=d, L=L, phi0=phi0, offset=offset)
    c = press.criteria(omega=1.0, k_Sp=0.1)
    if math.isnan(c.S_p):
        return
    alpha = np.radians(np.linspace(3.0, 357.0, 37))
    t = press.crank_torque(alpha, slider_mass=m_s, rod_mass=m_r, k_Sp=0.1)
    h = 2e-3
    ref = -fd(lambda a: kinetic_per_omega2(press, a, m_s, m_r, h), alpha, h)
    scale = max(np.abs(ref).max(), 1e-12)
    np.testing.assert_allclose(t.per_omega2, ref, rtol=1e-4, atol=1e-5 * scale)


def test_torque_at_speed_and_peak():
    f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
    alpha = np.radians(np.arange(3600) / 10)
    t = CRANK.crank_torque(alpha, force=f, slider_mass=40.0, k_Sp=0.1)
    w = 6.0
    M = t.torque_nm(w)
    np.testing.assert_allclose(M, w * w * t.per_omega2 + t.static)
    assert t.peak_torque_nm(w) == M.max()
    # The force's peak is F times the torque arm (max Π' over the stroke): here at the
    # first contact α_p, which a grid must hold to see it (the peak is the grid's).
    c = CRANK.criteria(omega=w, k_Sp=0.1)
    assert t.static.max() < 1e5 * c.torque_arm
    fine = CRANK.crank_torque(np.append(alpha, c.alpha_p), force=f, k_Sp=0.1)
    assert fine.static.max() == pytest.approx(1e5 * c.torque_arm, rel=1e-9)


# --- bad input ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("s", "force", "match"),
    [
        ([0.0, 0.01, 0.01], [1.0, 2.0, 3.0], r"s must increase strictly.*s\[2\] = 0\.01"),
        ([0.0, 0.02, 0.01], [1.0, 2.0, 3.0], r"s\[2\] = 0\.01 does not exceed s\[1\]"),
        ([0.0, 0.01], [1.0, -2.0], r"force\[1\] = -2\.0 must be ≥ 0 \[N\]"),
        ([0.0, 0.01], [1.0, math.nan], r"force\[1\] = nan is not finite"),
        ([-0.001, 0.01], [1.0, 1.0], r"s\[0\] = -0\.001 must be ≥ 0"),
        ([0.0, 0.01], [1.0], r"same length"),
        ([0.01], [1.0], r"at least 2"),
        (["a", "b"], [1.0, 1.0], r"s must be an array of real numbers"),
    ],
)
def test_bad_force_tables(s, force, match):
    with pytest.raises(cm.CyclomechError, match=match) as e:
        cm.press.DeformationForce(s, force)
    assert isinstance(e.value, ValueError)


def test_force_table_above_the_working_stroke_names_the_range():
    S_p = CRANK.criteria(omega=1.0, k_Sp=0.1).S_p
    f = cm.press.DeformationForce([0.0, 0.013], [1.0, 1.0])
    with pytest.raises(cm.CyclomechError, match=r"s\[1\] = 0\.013 m .*\[0, 0\.012\] m"):
        CRANK.crank_torque([0.0], force=f, k_Sp=0.1)
    # Up to S_p itself (and its rounding) is inside.
    edge = cm.press.DeformationForce([0.0, S_p * (1 + 1e-12)], [1, 1])
    CRANK.crank_torque([0.0], force=edge, k_Sp=0.1)


@pytest.mark.parametrize("key", ["slider_mass", "rod_mass"])
def test_negative_or_bad_masses(key):
    with pytest.raises(cm.CyclomechError, match=rf"{key} = -1\.0 must be finite and ≥ 0 \[kg\]"):
        CRANK.crank_torque([0.0], k_Sp=0.1, **{key: -1.0})
    with pytest.raises(cm.CyclomechError, match=rf"{key} must be a number"):
        CRANK.crank_torque([0.0], k_Sp=0.1, **{key: "3"})


# --- the machine ----------------------------------------------------------------------------


def frictionless() -> str:
    """The press line's file without its friction table: these tests hold the
    frictionless closed form (tests/press/test_press_friction.py the friction)."""
    text = LINE.read_text(encoding="utf-8")
    start = text.index("friction = {")
    return text[:start] + text[text.index("\n", start) + 1 :]


def variant(tmp_path: Path, old: str, new: str) -> Path:
    text = frictionless()
    assert text.count(old) == 1, old
    p = tmp_path / "line.toml"
    p.write_text(text.replace(old, new), encoding="utf-8")
    return p


@pytest.fixture(scope="module")
def line(tmp_path_factory):
    p = tmp_path_factory.mktemp("line") / "line.toml"
    p.write_text(frictionless(), encoding="utf-8")
    m = cm.Machine.from_toml(p)
    return m, cm.machine.analyze(m, progress=False)


def test_press_line_main_shaft_is_the_press_torque_at_its_phase(line):
    """The shaft's torque at the cycle angle φ is the press's at ψ = φ − bottom
    (its BDC sits at the event "bottom"); the force acts over the α_p degrees of
    the cycle before "bottom", which the optimum gives the operation contact → bottom."""
    m, r = line
    mech = m.mechanisms["drive"]
    assert (mech.phase.event, mech.phase.crank_deg) == ("bottom", 0.0)
    o = r.optimum
    shaft = r.shaft
    assert list(shaft.parts) == ["drive"]
    w = r.nominal_rpm * 2 * math.pi / 60
    phi = shaft.torque.theta_deg
    psi = np.mod(phi - o.times["bottom"], 360.0)
    alpha = np.mod(-np.radians(psi), 2 * math.pi)
    ref = mech.press.crank_torque(
        alpha, force=mech.force, slider_mass=60.0, rod_mass=15.0, k_Sp=0.1
    ).torque_nm(w)
    np.testing.assert_allclose(shaft.torque.at(r.nominal_rpm), ref, rtol=1e-6, atol=1e-3)
    # The force's torque lies on the operation contact → bottom.
    c = mech.criteria(r.nominal_rpm)
    assert o.times["bottom"] - o.times["contact"] >= math.degrees(c.alpha_p) - 1e-9
    static = shaft.torque.static
    on = static > 0
    assert on.any()
    assert phi[on].min() >= o.times["contact"] - 0.1
    assert phi[on].max() <= o.times["bottom"] + 1e-9
    # Energy balance: the mean torque × 2π is the energy per stroke (inertia nets 0).
    assert 2 * math.pi * float(shaft.at_nominal.mean_torque_nm) == pytest.approx(
        mech.force.energy_j, rel=1e-3
    )


def test_press_line_report_and_results_json(tmp_path):
    out = tmp_path / "out"
    (tmp_path / "line.toml").write_text(frictionless(), encoding="utf-8")
    assert main(["run", str(tmp_path / "line.toml"), "--out", str(out)]) == 0
    res = json.loads((out / "results.json").read_text())
    shaft = res["shaft"]
    assert shaft["contributors"] == ["drive"]
    assert shaft["peak_torque_nm"] > 1000
    t = res["mechanisms"]["drive"]["crank_torque"]
    assert t["energy_per_stroke_j"] == pytest.approx(2200.0)
    assert t["peak_torque_nm"] == pytest.approx(shaft["peak_torque_nm"], rel=1e-9)
    assert res["mechanisms"]["drive"]["criteria"]["torque_arm"] == pytest.approx(0.00937, rel=1e-3)
    assert "torque" not in res["mechanisms"]["drive"]["criteria"]
    html = (out / "report.html").read_text()
    assert "energy per stroke" in html and "peak crank torque" in html
    assert (out / "figures" / "main_shaft.png").exists()
    assert (out / "figures" / "drive_crank_torque.png").exists()


def test_press_without_load_gives_no_shaft_torque(tmp_path):
    text = LINE.read_text(encoding="utf-8")
    start = text.index("# Its load on the main shaft.")
    end = text.index("[cyclogram]")
    p = tmp_path / "bare.toml"
    p.write_text(text[:start] + "\n" + text[end:], encoding="utf-8")
    m = cm.Machine.from_toml(p)
    r = cm.machine.analyze(m, progress=False)
    assert r.mechanisms["drive"].shaft_torque() is None
    assert r.mechanisms["drive"].json()["mechanisms"]["crank_torque"] is None
    assert r.shaft is None


def test_masses_alone_give_a_torque_that_averages_zero(tmp_path):
    text = frictionless()
    start = text.index("deformation_force = {")
    end = text.index("\n", start)
    p = tmp_path / "masses.toml"
    p.write_text(text[:start] + text[end + 1 :], encoding="utf-8")
    r = cm.machine.analyze(cm.Machine.from_toml(p), progress=False)
    s = r.shaft.at_nominal
    assert abs(float(s.mean_torque_nm)) < 1e-9 * float(s.peak_torque_nm)
    assert float(s.peak_torque_nm) > 0


def test_phase_moves_the_curve(tmp_path, line):
    _, r = line
    p = variant(
        tmp_path,
        'phase = { event = "bottom", crank_deg = 0.0 }',
        'phase = { event = "bottom", crank_deg = 30.0 }',
    )
    r2 = cm.machine.analyze(cm.Machine.from_toml(p), progress=False)
    a = r.mechanisms["drive"].shaft_torque()
    b = r2.mechanisms["drive"].shaft_torque()
    assert b[2] == pytest.approx(a[2] - 30.0)
    assert b[3] == "bottom"
    np.testing.assert_array_equal(a[1], b[1])


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        (
            "0.0110, 0.0120]",
            "0.0110, 0.0135]",
            r"line\.toml: \[mechanism\.drive\]: deformation_force\.s_above_bdc_m #5 = 0\.0135 m "
            r"lies above the working stroke.*\[0, 0\.0127606\] m",
        ),
        (
            "force_n = [200e3,",
            "force_n = [-200e3,",
            r"\[mechanism\.drive\]: deformation_force\.force_n #1 = -200000\.0 must be ≥ 0",
        ),
        (
            "0.0100, 0.0110",
            "0.0110, 0.0100",
            r"\[mechanism\.drive\]: deformation_force\.s_above_bdc_m must increase strictly",
        ),
        (
            "force_n = [200e3, 200e3, 190e3, 150e3, 0.0]",
            "force_n = [200e3, 200e3, 190e3, 150e3]",
            r"deformation_force\.s_above_bdc_m and deformation_force\.force_n must have the same",
        ),
        (
            "force_n = [",
            "force = [",
            r"line\.toml: \[mechanism\.drive\.deformation_force\].*force",
        ),
        (
            "slider_mass_kg = 60.0",
            "slider_mass_kg = -60.0",
            r"line\.toml: \[mechanism\.drive\]: slider_mass_kg = -60\.0 must be ≥ 0 \[kg\]",
        ),
        (
            "rod_mass_kg = 15.0",
            'rod_mass_kg = "15"',
            r"\[mechanism\.drive\]: rod_mass_kg = '15' must be a finite number \[kg\]",
        ),
        (
            'event = "bottom"',
            'event = "bottm"',
            r"\[mechanism\.drive\] phase: event = 'bottm' is not an event",
        ),
    ],
)
def test_bad_machine_keys_name_file_table_and_key(tmp_path, old, new, match):
    p = variant(tmp_path, old, new)
    with pytest.raises(cm.CyclomechError, match=match) as e:
        cm.Machine.from_toml(p)
    assert isinstance(e.value, ValueError)


def test_deformation_force_must_be_a_table(tmp_path):
    text = LINE.read_text(encoding="utf-8")
    start = text.index("deformation_force = {")
    end = text.index("\n", start)
    p = tmp_path / "line.toml"
    p.write_text(text[:start] + "deformation_force = [1.0, 2.0]" + text[end:], encoding="utf-8")
    with pytest.raises(cm.CyclomechError, match=r"force = \[1\.0, 2\.0\]: give a table"):
        cm.Machine.from_toml(p)


def test_plot_crank_torque_draws_the_parts():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from cyclomech.press._torque_plot import plot_crank_torque

    f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
    alpha = np.mod(-np.radians(np.arange(360.0)), 2 * math.pi)  # the kind's order
    t = CRANK.crank_torque(alpha, force=f, slider_mass=40.0, k_Sp=0.1)
    axes = plot_crank_torque(t, 5.0, force=f)
    lines = {ln.get_gid(): ln for ln in axes[1].get_lines()}
    x, y = lines["total"].get_xydata().T
    assert np.all(np.diff(x) > 0)
    np.testing.assert_allclose(y, t.torque_nm(5.0)[np.argsort(alpha)])
    np.testing.assert_allclose(lines["force"].get_ydata(), t.static[np.argsort(alpha)])
    force_line = next(ln for ln in axes[0].get_lines() if ln.get_gid() == "F(S)")
    np.testing.assert_allclose(force_line.get_ydata(), f.force * 1e-3)
    assert len(plot_crank_torque(t, 5.0)) == 1
    with pytest.raises(cm.CyclomechError, match="PressTorque"):
        plot_crank_torque("t", 5.0)
    plt.close("all")


def test_force_is_on_at_the_start_of_the_working_stroke():
    """At α = α_p the slider is at S_p only to rounding (criteria and kinematics compute
    it apart; here Π(α_p) − S_p is a few 1e-17 m, either sign): the diagram's force at S_p
    acts there, not the zero past the diagram's end. Reference: F times the speed Π' by
    central differences of the kernel's positions."""
    c = GEAR.criteria(omega=1.0, k_Sp=0.1)
    F = 1.5e5
    f = cm.press.DeformationForce([0.0, c.S_p], [F, F])
    t = GEAR.crank_torque([c.alpha_p], force=f, k_Sp=0.1)
    h = 1e-4
    s = positions(GEAR, np.array([c.alpha_p - h, c.alpha_p + h]))["s"]
    assert t.static[0] == pytest.approx(F * (s[1] - s[0]) / (2 * h), rel=1e-6)
    # Past the stroke's start the force is off.
    past = GEAR.crank_torque([c.alpha_p + 1e-6], force=f, k_Sp=0.1)
    assert past.static[0] == 0.0
