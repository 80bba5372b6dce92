"""A machine file's ``[drive]``: the main shaft's real speed in ``cyclomech run``
(issue 34 item 6, the drive's part).

The kernels are checked against independent references in this folder's other
files (a sympy Lagrangian through solve_ivp, closed forms); here: the file's keys and
their errors, what the machine's result, report, results.json and CLI carry, and
that a drive that fails is loud (exit 3). The real δ the report gives is checked
against an independent integration of the same reduced machine (scipy solve_ivp on
J(φ)·φ̈ + ½·J′·φ̇² = M − Q over many cycles from the machine's own curves).
"""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
import tomllib
import warnings
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parents[2]
KNIFE = ROOT / "examples" / "knife_cutter.toml"


def knife() -> dict[str, Any]:
    with open(KNIFE, "rb") as f:
        return tomllib.load(f)


def build(d: dict[str, Any]) -> cm.Machine:
    return cm.Machine.from_dict(d, "dir/knife.toml")


@pytest.fixture(scope="module")
def result() -> Any:
    return cm.machine.analyze(cm.Machine.from_toml(KNIFE), progress=False)


def test_the_drive_is_read() -> None:
    m = cm.Machine.from_toml(KNIFE)
    assert isinstance(m.drive, cm.dynamics.Drive)
    motor = m.drive.motor
    assert isinstance(motor, cm.dynamics.InductionMotor)
    assert (motor.rated_rpm, motor.synchronous_rpm, motor.breakdown_ratio) == (1430, 1500, 2.8)
    assert motor.rated_torque_nm == pytest.approx(3000.0 / (1430 * math.pi / 30), rel=1e-14)
    assert (motor.ratio, motor.efficiency, motor.rotor_kg_m2) == (32.0, 0.95, 0.0075)
    assert m.drive.flywheel_kg_m2 is None
    d = knife()
    del d["drive"]
    assert build(d).drive is None


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        ({"motor": "diesel"}, ["[drive]", "motor = 'diesel'", "induction, linear"]),
        ({"stall_torque_nm": 3.0}, ["[drive]", "stall_torque_nm", "not taken by motor"]),
        ({"flywheel_kg_m2": -1.0}, ["[drive]", "flywheel_kg_m2", "≥ 0"]),
        ({"gear_efficiency": 1.5}, ["[drive]", "gear_efficiency"]),
        ({"gear_ratio": 0.0}, ["[drive]", "gear_ratio"]),
        ({"rotor_inertia_kg_m2": -1.0}, ["[drive]", "rotor_inertia_kg_m2"]),
        ({"breakdown_ratio": 0.9}, ["[drive]", "breakdown_ratio", "> 1"]),
        ({"rated_rpm": 1600.0}, ["[drive]", "rated_rpm", "synchronous_rpm"]),
        ({"rated_torque_nm": 20.0}, ["[drive]", "exactly one of rated_power_w"]),
        ({"rated_rpm": "fast"}, ["[drive]", "rated_rpm", "number"]),
        ({"bogus": 1}, ["[drive]", "bogus"]),
    ],
)
def test_bad_drive_keys_are_named(edit: dict[str, Any], words: list[str]) -> None:
    d = knife()
    d["drive"].update(edit)
    with pytest.raises(cm.InputError) as e:
        build(d)
    for w in ["dir/knife.toml", *words]:
        assert w in str(e.value), (w, str(e.value))


def test_missing_and_malformed_drive() -> None:
    d = knife()
    del d["drive"]["rated_rpm"]
    with pytest.raises(cm.InputError, match=r"\[drive\].*missing rated_rpm"):
        build(d)
    d = knife()
    d["drive"] = [1, 2]
    with pytest.raises(cm.InputError, match=r"\[drive\]"):
        build(d)
    d = knife()
    d["drive"] = {"motor": "table", "speed_rpm": [0.0, 1500.0], "torque_nm": "flat"}
    with pytest.raises(cm.InputError, match="torque_nm"):
        build(d)
    with pytest.raises(cm.InputError, match="drive must be"):
        m = cm.Machine.from_toml(KNIFE)
        cm.Machine(m.name, m.cyclogram, m.mechanisms, speed_range_rpm=(20, 100), drive="induction")  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "table",
    [
        {"motor": "linear", "stall_torque_nm": 60.0, "no_load_rpm": 1500.0, "gear_ratio": 32},
        {"motor": "constant", "torque_nm": 16.0, "gear_ratio": 32, "flywheel_kg_m2": 2000.0},
        {
            "motor": "table",
            "speed_rpm": [0.0, 1400.0, 1500.0],
            "torque_nm": [60.0, 40.0, 0.0],
            "gear_ratio": 32,
        },
    ],
)
def test_every_motor_kind_is_read(table: dict[str, Any]) -> None:
    d = knife()
    d["drive"] = table
    motor = build(d).drive.motor  # type: ignore[union-attr]
    kind = {"linear": "LinearMotor", "constant": "ConstantTorque", "table": "TableMotor"}
    assert type(motor).__name__ == kind[table["motor"]]


def test_the_real_speed_against_solve_ivp(result: Any) -> None:
    """The steady state the report gives equals many cycles of scipy's integration
    (LSODA/DOP853 on the same reduced machine, the flywheel sized by the report)."""
    dyn = result.dynamics
    s, red, motor = dyn.steady, dyn.reduced, dyn.drive.motor
    phi = np.radians(red.theta_deg)
    n = phi.size
    jc = dyn.flywheel_kg_m2 + motor.ratio**2 * motor.rotor_kg_m2

    def periodic(y: np.ndarray, x: float) -> float:
        # Linear interpolation on the 3600 samples: its error, ~1e-7 of J, is the
        # comparison's tolerance.
        return float(np.interp(x % (2 * math.pi), np.append(phi, 2 * math.pi), np.append(y, y[0])))

    eta, i = motor.efficiency, motor.ratio
    assert n == 3600

    def rhs(x: float, y: np.ndarray) -> list[float]:
        # In the shaft angle: dω/dφ = (M − Q − ½·J′·ω²)/(J·ω).
        w = y[0]
        j = periodic(red.inertia_kg_m2, x) + jc
        dj = periodic(red.d_inertia, x)
        q = periodic(red.load_torque_nm, x)
        m_motor = float(motor.torque_nm(w * i / (math.pi / 30)))
        # The gear: η on the side of the power flow (the motor drives: ×i·η).
        m_shaft = m_motor * i * (eta if m_motor >= 0 else 1 / eta)
        return [(m_shaft - q - 0.5 * dj * w * w) / (j * w)]

    # Three cycles from the steady state's own start stay on it (a periodic speed the
    # motor's slope makes attracting); the last one at every 60th of the cycle's angles.
    cycles = 3
    sol = solve_ivp(
        rhs,
        (0, cycles * 2 * math.pi),
        [s.omega[0]],
        method="DOP853",
        rtol=1e-11,
        atol=1e-12,
        dense_output=True,
    )
    w_ref = sol.sol((cycles - 1) * 2 * math.pi + phi[::60])[0]
    np.testing.assert_allclose(s.omega[::60], w_ref, rtol=2e-5)
    delta = (w_ref.max() - w_ref.min()) / (2 * math.pi / s.period_s)
    assert s.speed_fluctuation == pytest.approx(delta, rel=0.02)  # a 60-sample grid's max


def test_the_sized_flywheel_meets_the_target(result: Any) -> None:
    dyn = result.dynamics
    assert dyn.steady.speed_fluctuation == pytest.approx(0.05, rel=1e-6)
    assert dyn.sizing.flywheel_kg_m2 == dyn.flywheel_kg_m2
    # The energy method neglects the motor's slope and the knife's inertia: near,
    # not equal.
    e = dyn.sizing.energy_method_kg_m2
    assert e == pytest.approx(float(result.shaft.at_nominal.flywheel_kg_m2), rel=0.05)
    assert abs(dyn.sizing.difference) < 0.5
    assert dyn.failures() == [] and result.failures == []


def test_results_report_and_files(result: Any, tmp_path: Path) -> None:
    files = cm.machine.write_report(result, tmp_path, figures=True)
    names = {p.name for p in files}
    assert "main_shaft_speed.csv" in names and "main_shaft_speed.png" in names
    data = json.loads((tmp_path / "results.json").read_text())
    g = data["dynamics"]
    assert g["motor"] == "InductionMotor" and g["problem"] == ""
    assert g["speed_fluctuation"] == pytest.approx(0.05, rel=1e-6)
    assert len(g["speed_rpm"]) == 360
    page = (tmp_path / "report.html").read_text()
    assert "Under its motor" in page and "Main shaft under its motor" in page
    rows = np.loadtxt(tmp_path / "main_shaft_speed.csv", delimiter=",", skiprows=1)
    assert rows.shape == (3600, 4)
    rpm = rows[:, 1]
    mean = result.dynamics.steady.mean_rpm
    assert (rpm.max() - rpm.min()) / mean == pytest.approx(0.05, rel=1e-6)


def test_a_weak_motor_fails_loudly(tmp_path: Path) -> None:
    text = KNIFE.read_text()
    assert "rated_power_w = 3000.0" in text
    path = tmp_path / "weak.toml"
    path.write_text(text.replace("rated_power_w = 3000.0", "rated_power_w = 300.0"))
    r = cm.machine.analyze(cm.Machine.from_toml(path), progress=False)
    assert r.dynamics.steady is None and "cannot drive" in r.dynamics.problem
    assert any(f.startswith("drive:") for f in r.failures)
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "cyclomech",
            "run",
            str(path),
            "--out",
            str(tmp_path / "o"),
            "--no-plot",
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert run.returncode == 3, run.stdout + run.stderr
    assert "cannot drive" in run.stdout + run.stderr


def test_a_small_given_flywheel_fails_loudly() -> None:
    d = knife()
    d["drive"]["flywheel_kg_m2"] = 100.0
    r = cm.machine.analyze(build(d), progress=False)
    s = r.dynamics.steady
    assert s.speed_fluctuation > 0.05
    (text,) = r.failures
    assert "exceeds [machine] speed_fluctuation = 0.05" in text and "flywheel_kg_m2 = 100" in text


def test_a_drive_without_masses_warns() -> None:
    m = cm.Machine.example()
    d = copy.deepcopy(dict(m.data))
    d["drive"] = {"motor": "constant", "torque_nm": 1.0}
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = cm.machine.analyze(cm.Machine.from_dict(d, "ex.toml"), progress=False)
    assert r.dynamics is None
    assert any("[drive]: nothing loads the main shaft" in str(x.message) for x in w)


def test_the_loaded_start_is_reported(result: Any) -> None:
    """The report's start-up note: the knife's 3 kW motor cannot start it under load
    (its speed falls back through 0): scipy's integration from rest in time on the
    same reduced machine finds the same fall-back time and angle."""
    dyn = result.dynamics
    assert dyn.start.startswith("the motor cannot start the machine")
    t_said = float(dyn.start.split("at t = ")[1].split(" s")[0])
    red, motor = dyn.reduced, dyn.drive.motor
    phi = np.append(np.radians(red.theta_deg), 2 * math.pi)
    jc = dyn.flywheel_kg_m2 + motor.ratio**2 * motor.rotor_kg_m2
    i, eta = motor.ratio, motor.efficiency

    def at(y: np.ndarray, x: float) -> float:
        return float(np.interp(x % (2 * math.pi), phi, np.append(y, y[0])))

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        x, w = y
        m = float(motor.torque_nm(w * i * 30 / math.pi))
        m_shaft = m * i * (eta if m >= 0 else 1 / eta)
        j = at(red.inertia_kg_m2, x) + jc
        return [w, (m_shaft - at(red.load_torque_nm, x) - 0.5 * at(red.d_inertia, x) * w * w) / j]

    def stops(t: float, y: np.ndarray) -> float:
        return y[1] if t > 0.05 else 1.0

    stops.terminal = True  # type: ignore[attr-defined]
    stops.direction = -1  # type: ignore[attr-defined]
    sol = solve_ivp(rhs, (0, 60), [0.0, 0.0], events=stops, rtol=1e-9, atol=1e-12)
    assert sol.t_events[0].size == 1
    assert sol.t_events[0][0] == pytest.approx(t_said, rel=2e-3)
    # 72.6° with the knife's friction on the shaft (74.6° without).
    assert math.degrees(sol.y_events[0][0][0]) == pytest.approx(72.6, abs=0.2)


def test_a_strong_motor_starts_the_knife() -> None:
    d = knife()
    d["drive"] = {
        "motor": "linear",
        "stall_torque_nm": 200.0,
        "no_load_rpm": 1500.0,
        "gear_ratio": 32.0,
        "flywheel_kg_m2": 1500.0,
    }
    r = cm.machine.analyze(build(d), progress=False)
    assert r.dynamics.start.startswith("within 1 % of the steady speed after")
    assert "start-up from rest under load" in dict(r.dynamics.table()[1])


def test_a_constant_torque_that_does_not_balance_the_load_fails() -> None:
    """A constant torque other than the mean load's has no periodic speed: the
    machine speeds up or slows down cycle after cycle. Sizing a flywheel for it
    must not return a flywheel so large the drift hides within one cycle (it
    returned 6e10 kg·m² and δ 1e-9, exit 0): the run fails, naming the imbalance."""
    r0 = cm.machine.analyze(cm.Machine.from_toml(KNIFE), progress=False)
    mean_load = float(np.mean(r0.dynamics.reduced.load_torque_nm))
    for factor in (1.03, 0.97):
        d = knife()
        d["drive"] = {
            "motor": "constant",
            "torque_nm": factor * mean_load / (32 * 0.95),
            "gear_ratio": 32.0,
            "gear_efficiency": 0.95,
        }
        r = cm.machine.analyze(build(d), progress=False)
        assert r.dynamics.steady is None
        word = "exceeds" if factor > 1 else "falls short of"
        assert word in r.dynamics.problem, r.dynamics.problem
        assert any(f.startswith("drive:") for f in r.failures)


def test_the_speed_limit_advice_points_the_right_way() -> None:
    d = knife()
    d["drive"]["gear_ratio"] = 20.0  # 1430/20 = 71.5 rpm, above the 57.14 rpm limit
    r = cm.machine.analyze(build(d), progress=False)
    (text,) = [f for f in r.failures if "speed limit" in f]
    assert "a larger gear ratio" in text


def test_a_bare_motor_is_refused_by_name() -> None:
    """Motor (the gear and rotor every characteristic has) can be made on its own
    since it checks its fields; asked for a torque it is an InputError naming the
    characteristics, not a NotImplementedError from inside."""
    m = cm.dynamics.Motor(2.0, 0.9, 1e-3)
    with pytest.raises(cm.InputError, match="LinearMotor"):
        m.torque_nm(100.0)
    d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.ones(8), nominal_rpm=1.0)
    with pytest.raises(cm.InputError, match="no torque characteristic"):
        cm.dynamics.steady_state(d, m)


@pytest.mark.parametrize("flywheel", [None, 2000.0])
def test_a_weak_motor_names_its_torque_against_the_load(flywheel: float | None) -> None:
    # Sized (no flywheel in the file) or given, a motor too weak for the load says by
    # how much: its breakdown torque through the gear against the load's mean and peak
    # on the main shaft, and what to change (the trial's message named neither).
    d = knife()
    d["drive"]["rated_power_w"] = 500.0
    if flywheel is not None:
        d["drive"]["flywheel_kg_m2"] = flywheel
    r = cm.machine.analyze(build(d), progress=False)
    assert r.dynamics.steady is None
    text = r.dynamics.problem
    m_k = 2.8 * 500.0 / (1430.0 * math.pi / 30.0)  # λ·P/ω_n, by hand
    st = r.shaft.torque.stats(45.0, 0.05)  # the kinetostatics' shaft torque
    mean, peak = float(st.mean_torque_nm), float(st.peak_torque_nm)
    assert 32 * 0.95 * m_k < mean  # the case: below the mean load
    for words in (
        f"breakdown torque M_k {m_k:.4g} N·m",
        f"{32 * 0.95 * m_k:.4g} N·m on the main shaft",
        f"{mean:.4g} N·m mean, {peak:.4g} N·m peak",
        "a larger motor or a larger gear ratio",
    ):
        assert words in text, text


def test_a_nominal_speed_above_the_limit_is_not_blamed_on_the_drive() -> None:
    # The cyclogram does not fit at 70 rpm (limit 57.14): no optimum, no shaft torque,
    # so no real speed. That failure is said once; the drive was warned about as if
    # nothing loaded the main shaft (a warning, an error under filterwarnings).
    d = knife()
    d["machine"]["nominal_rpm"] = 70.0
    r = cm.machine.analyze(build(d), progress=False)
    assert r.optimum is None and r.dynamics is None
    assert r.problem  # the cyclogram's own failure, said by the report and the CLI
