"""The reduced machine, closed forms, properties and bad input of the main shaft's
dynamics. J′ = 2a: for a machine of one degree of freedom the kinetostatics' ω²
part is ½·dJ/dφ exactly, so each kind's J (its kinetic energy) differentiated
numerically here must match twice its ω² part (computed by the kinetostatics,
independently)."""

import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech._errors import InputError, SolverError
from hypothesis import given, settings
from hypothesis import strategies as st

#: The examples, found from this file (the wheel's tests run from an empty folder).
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

N = 3600
PHI = 2 * np.pi * np.arange(N) / N


def _derivative(j):
    """dJ/dφ by fourth-order central differences on the periodic grid."""
    h = 2 * np.pi / j.size
    r = lambda k: np.roll(j, -k)  # noqa: E731
    return (-r(2) + 8 * r(1) - 8 * r(-1) + r(-2)) / (12 * h)


@pytest.fixture(scope="module")
def machines():
    return {
        k: cm.machine.analyze(cm.Machine.from_toml(EXAMPLES / f"{k}.toml"), progress=False)
        for k in ("knife_cutter", "stb_loom", "extrusion_press_line")
    }


@pytest.mark.parametrize(
    ("example", "mechanism", "rtol"),
    [
        ("knife_cutter", "knife", 1e-6),
        ("stb_loom", "lifter cam", 1e-3),
        ("extrusion_press_line", "drive", 1e-6),
    ],
)
def test_each_kinds_inertia_differentiates_to_twice_its_omega2_part(
    machines, example, mechanism, rtol
):
    res = machines[example].mechanisms[mechanism]
    j, phase, event = res.shaft_inertia()
    a, _b, phase_t, event_t = res.shaft_torque()
    assert (phase, event) == (phase_t, event_t)
    assert j.shape == a.shape == (N,) and j.min() >= 0
    err = np.abs(_derivative(j) - 2 * a)
    # The cam's s″ jumps at its segments' joins: there the finite difference is
    # first order; everywhere else it agrees as the others do.
    assert np.median(err) <= 1e-6 * np.max(np.abs(2 * a))
    assert np.max(err) <= rtol * np.max(np.abs(2 * a)) * (1 if rtol < 1e-4 else 50)


@pytest.mark.parametrize("example", ["knife_cutter", "stb_loom", "extrusion_press_line"])
def test_the_phased_machines_inertia_differentiates_to_its_d_inertia(machines, example):
    r = machines[example]
    d = cm.dynamics.reduced(r)
    assert d.parts == tuple(r.shaft.parts) and d.without_inertia == ()
    np.testing.assert_array_equal(d.load_torque_nm, r.shaft.torque.static)
    err = np.abs(_derivative(d.inertia_kg_m2) - d.d_inertia)
    assert np.median(err) <= 1e-5 * np.max(np.abs(d.d_inertia))
    # The linkage's inertia: positive everywhere (Σ m v² + J ω²).
    assert d.inertia_kg_m2.min() >= 0


def test_the_linkages_inertia_is_its_kinetic_energy_from_positions():
    # A crank with a point mass m at radius r: J = m r² at every angle.
    crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    k = cm.forces.kinetostatics(crank, PHI, point_masses={"A": 2.0})
    np.testing.assert_allclose(k.torque_parts[1], 2.0 * 0.09, rtol=1e-12)


def test_constant_inertia_constant_torque_and_a_sinusoidal_load_in_closed_form():
    # ½J(ω² − ω0²) = ∫(M − Q) = A (cos φ − 1) with Q = M + A sin φ.
    jv, m, amp, rpm = 2.0, 5.0, 3.0, 120.0
    d = cm.dynamics.Reduced.from_curves(
        np.zeros(N), np.zeros(N), m + amp * np.sin(PHI), nominal_rpm=rpm
    )
    s = cm.dynamics.steady_state(d, cm.dynamics.ConstantTorque(m), flywheel_kg_m2=jv)
    w0 = rpm * math.pi / 30
    exact = np.sqrt(w0**2 + 2 * amp * (np.cos(PHI) - 1) / jv)
    np.testing.assert_allclose(s.omega, exact, rtol=1e-11)
    # The period: ∫dφ/ω by dense quadrature of the closed form.
    fine = np.linspace(0, 2 * np.pi, 400_001)
    t = np.trapezoid(1 / np.sqrt(w0**2 + 2 * amp * (np.cos(fine) - 1) / jv), fine)
    assert s.period_s == pytest.approx(t, rel=1e-9)
    # An unbalanced constant torque has no periodic speed: an error, not a number.
    with pytest.raises(SolverError, match="constant torque"):
        cm.dynamics.steady_state(d, cm.dynamics.ConstantTorque(m * 1.01), flywheel_kg_m2=jv)


def test_a_kloss_motor_gives_its_rated_torque_at_its_rated_speed():
    m = cm.dynamics.InductionMotor(1440.0, 1500.0, 2.5, rated_power_w=1500.0)
    mn = 1500.0 / (1440 * math.pi / 30)
    assert float(m.torque_nm(1440.0)) == pytest.approx(mn, rel=1e-12)
    # Its peak, λ·M_n, at the critical slip.
    n = np.linspace(0, 1500, 150_001)
    assert m.torque_nm(n).max() == pytest.approx(2.5 * mn, rel=1e-8)
    # The steady state of a constant load: where the characteristic meets the load.
    d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.full(8, mn), nominal_rpm=1.0)
    assert cm.dynamics.steady_state(d, m).mean_rpm == pytest.approx(1440.0, rel=1e-9)


def _shaft_torque(motor, w):
    m = motor.torque_nm(w * motor.ratio * 30 / math.pi)
    g = np.where(m >= 0, motor.ratio * motor.efficiency, motor.ratio / motor.efficiency)
    return g * m


@settings(max_examples=40)
@given(
    j0=st.floats(0.05, 5.0),
    j1=st.floats(0.0, 0.9),
    q0=st.floats(1.0, 50.0),
    q1=st.floats(0.0, 2.0),
    k=st.integers(1, 4),
    induction=st.booleans(),
    ratio=st.floats(1.0, 20.0),
    eff=st.floats(0.5, 1.0),
)
def test_properties_of_the_steady_state(j0, j1, q0, q1, k, induction, ratio, eff):
    jj = j0 * (1 + j1 * np.cos(k * PHI))
    dj = -j0 * j1 * k * np.sin(k * PHI)
    q = q0 * (1 + q1 * np.sin(PHI + 0.3))
    d = cm.dynamics.Reduced.from_curves(jj, dj, q, nominal_rpm=100.0)
    top = 2 * q0 * (1 + q1) / ratio / eff
    motor = (
        cm.dynamics.InductionMotor(
            1450.0, 1500.0, 2.5, rated_torque_nm=top, ratio=ratio, efficiency=eff
        )
        if induction
        else cm.dynamics.LinearMotor(3 * top, 3000.0, ratio=ratio, efficiency=eff)
    )
    try:
        s = cm.dynamics.steady_state(d, motor, flywheel_kg_m2=0.1, tol=1e-12)
    except SolverError:
        return  # said so: no quiet number
    w = s.omega
    # Periodic and positive; the energy balances over the cycle: ∮(M − Q)dφ = 0
    # (the motor's torque on the shaft written here from its characteristic).
    assert w.min() > 0 and s.residual <= 1e-12
    net = _shaft_torque(motor, w) - q
    scale = np.mean(np.abs(q))
    # RK4's O(h⁴) holds for a smooth torque; a gear with η < 1 kinks it where the
    # motor turns from driving to braking (i·η·M against i·M/η): first order there.
    mt = motor.torque_nm(w * motor.ratio * 30 / math.pi)
    kink = eff < 1 and mt.min() < 0 < mt.max()
    # Both errors (RK4's on the samples and this check's own trapezoid) grow with how
    # fast J varies against itself: k lobes, J_max/J_min = (1 + j1)/(1 − j1). The
    # tolerances hold for gentle variation (rough = 1) and widen as its square.
    rough = max(1.0, (k * (1 + j1) / (1 - j1) / 4) ** 2)
    assert abs(np.mean(net)) <= (1e-4 if kink else 1e-7) * rough * scale
    # And pointwise: ½(J + J_F)ω² − ½(J + J_F)ω0² = ∫(M − Q), trapezoid on the grid.
    e = 0.5 * (jj + 0.1) * w**2
    work = np.concatenate([[0.0], np.cumsum(0.5 * (net[1:] + net[:-1]))]) * (2 * np.pi / N)
    assert np.max(np.abs(e - e[0] - work)) <= 1e-5 * rough * (scale * 2 * np.pi + e.max())
    # The batch gives the same steady state.
    b = cm.dynamics.steady_states(d, [motor], [0.1], tol=1e-12)
    assert b.column("delta")[0] == pytest.approx(s.speed_fluctuation, rel=1e-12, abs=1e-15)


def test_bad_input_names_the_argument():
    with pytest.raises(InputError, match="breakdown_ratio"):
        cm.dynamics.InductionMotor(1440.0, 1500.0, 0.8, rated_torque_nm=10.0)
    with pytest.raises(InputError, match="rated_rpm"):
        cm.dynamics.InductionMotor(1500.0, 1500.0, 2.0, rated_torque_nm=10.0)
    with pytest.raises(InputError, match="rated_power_w"):
        cm.dynamics.InductionMotor(1440.0, 1500.0, 2.0)
    with pytest.raises(InputError, match="efficiency"):
        cm.dynamics.LinearMotor(1.0, 100.0, efficiency=1.2)
    with pytest.raises(InputError, match="rotor_kg_m2"):
        cm.dynamics.LinearMotor(1.0, 100.0, rotor_kg_m2=-1.0)
    with pytest.raises(InputError, match="speed_rpm"):
        cm.dynamics.TableMotor([0.0, 0.0], [1.0, 0.0])
    d = cm.dynamics.Reduced.from_curves(np.zeros(8), np.zeros(8), np.ones(8), nominal_rpm=60.0)
    m = cm.dynamics.LinearMotor(5.0, 100.0)
    with pytest.raises(InputError, match="flywheel_kg_m2"):
        cm.dynamics.steady_state(d, m, flywheel_kg_m2=-1.0)
    # A machine without masses and no flywheel: no inertia at all.
    with pytest.raises(InputError, match="flywheel_kg_m2"):
        cm.dynamics.steady_state(d, m)
    with pytest.raises(InputError, match="inertia_kg_m2"):
        cm.dynamics.Reduced.from_curves(-np.ones(8), np.zeros(8), np.ones(8), nominal_rpm=60.0)
    with pytest.raises(InputError, match="tol"):
        cm.dynamics.steady_state(d, m, flywheel_kg_m2=1.0, tol=0.0)
    # A machine with nothing on its main shaft: no reduced machine, no flywheel.
    r = cm.machine.analyze(cm.Machine.from_toml(EXAMPLES / "stb_loom.toml"), progress=False)
    import dataclasses

    with pytest.raises(InputError, match="result"):
        cm.dynamics.reduced(dataclasses.replace(r, shaft=None))
    with pytest.raises(InputError, match="result"):
        cm.dynamics.reduced(object())


def test_a_motor_too_weak_or_stalling_is_said_loudly():
    d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.full(8, 50.0), nominal_rpm=60.0)
    weak = cm.dynamics.LinearMotor(10.0, 100.0)
    with pytest.raises(SolverError, match="below the mean load"):
        cm.dynamics.steady_state(d, weak)
    with pytest.warns(cm.CyclomechWarning, match="1 of 2 designs"):
        b = cm.dynamics.steady_states(d, [weak, cm.dynamics.LinearMotor(100.0, 100.0)], 0.0)
    assert b.ok.tolist() == [False, True] and math.isnan(b.column("omega_mean")[0])
    # A load peak the motor cannot carry the shaft through at its speed: a stall.
    q = np.where(np.arange(N) < 100, 2000.0, 0.0)
    d = cm.dynamics.Reduced.from_curves(np.full(N, 1e-3), np.zeros(N), q, nominal_rpm=60.0)
    with pytest.raises(SolverError):
        cm.dynamics.steady_state(d, cm.dynamics.LinearMotor(100.0, 100.0))


def test_a_kind_without_an_inertia_is_named_and_only_its_static_torque_counts(machines):
    import dataclasses

    r = machines["knife_cutter"]

    class NoInertia:
        """A mechanism's result that loads the shaft but has no shaft_inertia()."""

        def __init__(self, res):
            self.shaft_torque = res.shaft_torque

    mechs = {k: NoInertia(v) for k, v in r.mechanisms.items()}
    d = cm.dynamics.reduced(dataclasses.replace(r, mechanisms=mechs))
    assert d.parts == () and d.without_inertia == ("knife",)
    assert not d.inertia_kg_m2.any() and not d.d_inertia.any()
    np.testing.assert_array_equal(d.load_torque_nm, r.shaft.torque.static)


def test_a_table_motor_is_the_characteristic_it_tabulates():
    jj = 0.3 * (1 + 0.4 * np.cos(2 * PHI))
    d = cm.dynamics.Reduced.from_curves(
        jj, -0.24 * np.sin(2 * PHI), 8 + 6 * np.sin(PHI), nominal_rpm=100.0
    )
    lin = cm.dynamics.LinearMotor(2.0, 3000.0, ratio=12.0, efficiency=0.95)
    tab = cm.dynamics.TableMotor([0.0, 3000.0], [2.0, 0.0], ratio=12.0, efficiency=0.95)
    a = cm.dynamics.steady_state(d, lin, flywheel_kg_m2=0.5, tol=1e-13)
    b = cm.dynamics.steady_state(d, tab, flywheel_kg_m2=0.5, tol=1e-13)
    np.testing.assert_allclose(b.omega, a.omega, rtol=1e-12)
    # A dense table of Kloss's curve: the induction motor's steady state.
    ind = cm.dynamics.InductionMotor(1440.0, 1500.0, 2.5, rated_torque_nm=0.8, ratio=12.0)
    n = np.linspace(0.0, 1600.0, 160_001)
    dense = cm.dynamics.TableMotor(n, ind.torque_nm(n), ratio=12.0)
    a = cm.dynamics.steady_state(d, ind, flywheel_kg_m2=0.5)
    b = cm.dynamics.steady_state(d, dense, flywheel_kg_m2=0.5)
    np.testing.assert_allclose(b.omega, a.omega, rtol=1e-7)
    # One batch of mixed motors (tables among them) gives each single call's state.
    motors = [lin, tab, ind, dense]
    batch = cm.dynamics.steady_states(d, motors, [0.5, 1.0, 2.0, 0.5])
    for m, fw, delta in zip(motors, [0.5, 1.0, 2.0, 0.5], batch.column("delta"), strict=True):
        s = cm.dynamics.steady_state(d, m, flywheel_kg_m2=fw)
        assert delta == pytest.approx(s.speed_fluctuation, rel=1e-9)


def test_a_flattened_machines_inertia_follows_the_moved_phases(tmp_path):
    # The two-cam machine of the flattening's tests (tests/shaft/test_shaft_phasing.py):
    # J read without the flattening's shifts would not differentiate to the d_inertia
    # of the moved torques.
    import importlib.util
    from pathlib import Path

    here = Path(__file__).resolve().parents[1]
    spec = importlib.util.spec_from_file_location(
        "shaft_phasing", here / "shaft" / "test_shaft_phasing.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    path = tmp_path / "two_cams.toml"
    path.write_text(mod.machine_text(), encoding="utf-8")
    r = cm.machine.analyze(cm.Machine.from_toml(path), progress=False)
    assert r.shaft.flattening is not None and r.shaft.flattening.moved
    d = cm.dynamics.reduced(r)
    assert d.parts == ("cam A", "cam B")
    err = np.abs(_derivative(d.inertia_kg_m2) - d.d_inertia)
    assert np.median(err) <= 1e-5 * np.max(np.abs(d.d_inertia))
    # Each cam's J read at its own shaft_torque() phase plus its shift, by np.interp.
    total = np.zeros(N)
    for k in d.parts:
        j, phase, _ = r.mechanisms[k].shaft_inertia()
        at = phase + r.shaft.flattening.shifts_deg[k]
        total += np.interp((np.degrees(PHI) - at) % 360, np.arange(N) * 0.1, j, period=360)
    np.testing.assert_allclose(d.inertia_kg_m2, total, atol=1e-12 * total.max())
