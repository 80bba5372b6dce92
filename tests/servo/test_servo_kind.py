"""The ``servo`` machine kind (issue 33, items 3 and 5): a servo axis on the
machine's master, its bounds on the cyclogram, its own speed limit, its results
and the cam tables ``cyclomech run`` writes.

Independent references: the bounds at their angle are checked against a dense
duty (the motor's peak torque and speed met with equality there, by
:meth:`ServoAxis.duty` on 20 000 samples, not the bound's solver); the
proportional laws against the per-speed solve; the own speed limit against the
duty just below and above it; the cam table against the program's closed form;
the sizing against :func:`cyclomech.servo.size` on the laid-out axis.
"""

from __future__ import annotations

import copy
import csv
import json
import math
import warnings
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "flow_wrapper.toml"


@pytest.fixture(scope="module")
def machine() -> cm.Machine:
    return cm.Machine.from_toml(EXAMPLE)


@pytest.fixture(scope="module")
def result(machine: cm.Machine) -> Any:
    return cm.machine.analyze(machine, progress=False)


def data(machine: cm.Machine) -> dict[str, Any]:
    d = copy.deepcopy(dict(machine.data or {}))
    for table in d["mechanism"].values():
        if "catalogue" in table:
            table["catalogue"] = str(EXAMPLE.parent / table["catalogue"])
    return d


def build(d: dict[str, Any]) -> cm.Machine:
    return cm.Machine.from_dict(d, "flow.toml")


def refused(d: dict[str, Any]) -> str:
    with pytest.raises(cm.CyclomechError) as e:
        build(d)
    assert isinstance(e.value, ValueError)
    return str(e.value)


def dense(program: cm.motion.Program, mech: Any) -> cm.servo.ServoAxis:
    a = mech.axis
    return cm.servo.ServoAxis(
        program, a.load, a.gearbox, a.motor, points=20_000, inertia_ratio_limit=10.0
    )


# ---------------------------------------------------------------- bounds
def test_bounds_are_met_with_equality_at_their_angle(machine: cm.Machine) -> None:
    feed = machine.mechanisms["film feed"]
    motor = feed.axis.motor
    for rpm in (60.0, 140.0):
        torque, speed, _ = (c.rhs for c in feed.constraints(rpm))
        # Alone on its angle the index segment sets the peaks (the rest of the
        # program is slower): at the torque bound's angle the peak torque is the
        # motor's, at the speed bound's angle the peak speed.
        at_torque, _ = feed.program_at({("2", "3"): torque})
        d = dense(at_torque, feed).duty(rpm)
        assert float(d.peak_torque_nm) == pytest.approx(motor.peak_torque_nm, rel=2e-4)
        at_speed, _ = feed.program_at({("2", "3"): speed})
        d = dense(at_speed, feed).duty(rpm)
        assert float(d.peak_speed_rpm) == pytest.approx(motor.max_rpm, rel=1e-5)
        # Longer passes, shorter fails.
        longer, _ = feed.program_at({("2", "3"): torque * 1.01})
        assert float(dense(longer, feed).duty(rpm).peak_torque_nm) < motor.peak_torque_nm
        shorter, _ = feed.program_at({("2", "3"): torque * 0.99})
        assert float(dense(shorter, feed).duty(rpm).peak_torque_nm) > motor.peak_torque_nm


def test_laws_are_the_per_speed_solve(machine: cm.Machine) -> None:
    feed = machine.mechanisms["film feed"]
    rpm = np.array([40.0, 77.7, 160.0])
    per = feed.axis.min_phase_angles(rpm, segments=[0]).angle_deg[:, 0, :]
    laws = feed.laws()
    for c in range(2):
        np.testing.assert_allclose(laws[c](rpm), per[:, c], rtol=1e-12)
    # proportional: 160 rpm needs 4 times the angle of 40 rpm
    assert laws[0](rpm)[2] == pytest.approx(4.0 * laws[0](rpm)[0], rel=1e-12)


def test_rms_bound_is_met_with_equality_at_its_angle(machine: cm.Machine) -> None:
    feed = machine.mechanisms["film feed"]
    motor = feed.axis.motor
    assert feed.criteria() == ("peak_torque", "speed", "rms_torque")
    for rpm in (120.0, 160.0):
        rms = feed.constraints(rpm)[2].rhs
        at, why = feed.program_at({("2", "3"): rms})
        assert why == ""
        # The RMS over the whole cycle (the dwell after the index took up the
        # change) is the rated torque: a dense duty, not the bound's trapezoids.
        d = dense(at, feed).duty(rpm)
        assert float(d.rms_torque_nm) == pytest.approx(motor.rated_torque_nm, rel=2e-4)
        longer, _ = feed.program_at({("2", "3"): rms * 1.01})
        assert float(dense(longer, feed).duty(rpm).rms_torque_nm) < motor.rated_torque_nm
        shorter, _ = feed.program_at({("2", "3"): rms * 0.99})
        assert float(dense(shorter, feed).duty(rpm).rms_torque_nm) > motor.rated_torque_nm
    # Not proportional to the speed (the fixed segments' share grows too), but
    # rising with it.
    law = feed.laws()[2]
    a = law(np.array([80.0, 120.0, 160.0]))
    assert np.all(np.diff(a) > 0) and a[2] != pytest.approx(2.0 * a[0], rel=1e-3)


def test_no_rms_bound_with_two_bound_segments(machine: cm.Machine) -> None:
    # The RMS couples the cycle: exact for one bound segment only; with two it is
    # the duty's check on the optimised timing.
    d = data(machine)
    d["mechanism"]["film feed"]["segment"] = [
        {"kind": "rise", "angle_deg": 60.0, "stroke_m": 0.1, "arc": ["2", "3"]},
        {"kind": "dwell", "angle_deg": 120.0},
        {"kind": "rise", "angle_deg": 60.0, "stroke_m": 0.15, "arc": ["1", "2"]},
        {"kind": "dwell", "angle_deg": 120.0},
    ]
    feed = build(d).mechanisms["film feed"]
    assert feed.criteria() == ("peak_torque", "speed")
    assert len(feed.bounds()) == 4


def test_speed_limit_names_the_motor(result: Any) -> None:
    lim = result.limit
    assert lim.by == "jaw" and "'AC-130-955'" in lim.reason and "RMS" in lim.reason
    feed = result.mechanisms["film feed"].mech
    n = result.nominal_rpm
    assert result.optimum.angles[("2", "3")] == pytest.approx(
        max(c.rhs for c in feed.constraints(n)), rel=1e-9
    )
    assert "peak torque[film feed (AC-060-127) rise 2→3]" in result.optimum.duals


def test_own_speed_limit_is_where_the_duty_reaches_the_rated_torque(
    machine: cm.Machine,
) -> None:
    jaw = machine.mechanisms["jaw"]
    limit = jaw.speed_limit_rpm()
    assert 100.0 < limit < 1000.0
    assert "AC-130-955" in jaw.limit_reason() and "RMS" in jaw.limit_reason()
    ax = dense(jaw.axis.program, jaw)
    rated = jaw.axis.motor.rated_torque_nm
    assert float(ax.duty(limit).rms_torque_nm) == pytest.approx(rated, rel=2e-4)
    assert float(ax.duty(0.99 * limit).rms_torque_nm) < rated
    assert float(ax.duty(1.01 * limit).rms_torque_nm) > rated


def test_own_speed_limit_by_the_peak_torque(machine: cm.Machine) -> None:
    # A motor with torque to spare thermally: the peak torque binds.
    d = data(machine)
    d["mechanism"]["jaw"]["motor"] = {
        "rated_torque_nm": 30.0,
        "peak_torque_nm": 30.0,
        "max_rpm": 3000.0,
        "inertia_kg_m2": 0.0165,
        "name": "cool",
    }
    jaw = build(d).mechanisms["jaw"]
    limit = jaw.speed_limit_rpm()
    assert "peak torque 30 N·m" in jaw.limit_reason()
    ax = dense(jaw.axis.program, jaw)
    assert float(ax.duty(limit).peak_torque_nm) == pytest.approx(30.0, rel=2e-4)
    assert float(ax.duty(0.99 * limit).peak_torque_nm) < 30.0
    assert float(ax.duty(1.01 * limit).peak_torque_nm) > 30.0


def test_own_limit_is_a_closed_form_for_a_constant_velocity(machine: cm.Machine) -> None:
    # A rotary load turning at a constant velocity all cycle: no acceleration, so
    # the torque never grows; the limit is the motor's speed: ω_max/(i·|φ′|).
    d = data(machine)
    jaw = d["mechanism"]["jaw"]
    jaw["segment"] = [
        {
            "kind": "rise",
            "angle_deg": 360.0,
            "law": "constant_velocity",
            "start_velocity_deg_per_rad": 180.0 / math.pi,  # one turn per cycle
        }
    ]
    jaw.pop("phase")
    m = build(d).mechanisms["jaw"]
    motor, ratio = m.axis.motor, m.axis.gearbox.ratio
    assert m.speed_limit_rpm() == pytest.approx(motor.max_rpm / ratio, rel=1e-12)
    assert "maximum speed" in m.limit_reason()


def test_a_load_the_motor_cannot_hold_limits_to_zero(machine: cm.Machine) -> None:
    d = data(machine)
    d["mechanism"]["jaw"]["torque_nm"] = 1000.0
    m = build(d)
    assert m.mechanisms["jaw"].speed_limit_rpm() == 0.0
    assert "cannot hold the load" in m.mechanisms["jaw"].limit_reason()
    assert m.speed_limit().rpm == 0.0


# ---------------------------------------------------------------- results
def test_results_at_the_optimum(result: Any) -> None:
    feed = result.mechanisms["film feed"]
    o = result.optimum
    assert feed.program.segments[0].angle_deg == pytest.approx(o.angles[("2", "3")])
    assert sum(g.angle_deg for g in feed.program.segments) == pytest.approx(360.0)
    assert feed.master_offset_deg == pytest.approx(o.times["2"])
    jaw = result.mechanisms["jaw"]
    # phase = {event = "2", crank_deg = -180}: the jaw's 0 is 180° after event 2
    assert jaw.master_offset_deg == pytest.approx((o.times["2"] + 180.0) % 360.0)
    # The sizing is cyclomech.servo.size on the laid-out axis at the nominal speed.
    want = cm.servo.size(jaw.axis, jaw.mech.catalogue, list(jaw.mech.ratios), [100.0])
    assert (jaw.sizing.choice.motor, jaw.sizing.choice.ratio) == (
        want.choice.motor,
        want.choice.ratio,
    )
    entry = feed.json()["servo_axes"]
    assert entry["loads_main_shaft"] is False
    assert entry["motor"] == "AC-060-127"
    # The index is as short as the motor's peak torque allows: margin 0, to the
    # duty's 3600 samples (the peak falls between two).
    assert 0.0 <= entry["margins"]["peak_torque"] < 1e-4
    assert "main_shaft" not in str(result.shaft.parts) and set(result.shaft.parts) == {"pusher"}


def test_a_failing_check_warns_and_exits_3(
    machine: cm.Machine, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # A heavier rotor: the inertia ratio fails at any speed, on any timing.
    d = data(machine)
    d["mechanism"]["jaw"]["inertia_kg_m2"] = 0.5
    with pytest.warns(cm.CyclomechWarning, match=r"servo axis 'jaw'.*inertia ratio"):
        r = cm.machine.analyze(build(d), progress=False)
    assert r.failures == ["jaw: its motor fails the inertia ratio check (margin -0.212)"]
    text = EXAMPLE.read_text().replace("inertia_kg_m2 = 0.4 ", "inertia_kg_m2 = 0.5 ")
    (tmp_path / "m.toml").write_text(text)
    (tmp_path / "motors.csv").write_text((EXAMPLE.parent / "motors.csv").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        code = main(["run", str(tmp_path / "m.toml"), "--out", str(tmp_path / "o"), "--no-plot"])
    assert code == 3
    err = capsys.readouterr().err
    assert "jaw: its motor fails the inertia ratio check" in err
    assert "Fails at 100 rpm" in (tmp_path / "o" / "report.html").read_text()
    results = json.loads((tmp_path / "o" / "results.json").read_text())
    assert results["fails"] == r.fails == [f"at 100 rpm {r.failures[0]}"]


def test_run_writes_cam_tables(cli_run) -> None:
    run = cli_run(EXAMPLE, "--no-plot", "--quiet")
    out = run.out
    assert run.code == 0
    summary = json.loads((out / "results.json").read_text())
    assert summary["servo_axes"]["jaw"]["motor"] == "AC-130-955"
    m = cm.Machine.from_toml(EXAMPLE)
    r = cm.machine.analyze(m, progress=False)
    program = r.mechanisms["film feed"].program
    with open(out / "film_feed_cam_table.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == list(cm.motion.TABLE_COLUMNS)
    table = np.array(rows[1:], dtype=float)
    assert table.shape == (3601, 5)
    # The table's positions are the program's closed form (and the film ends one
    # bag on: the advance).
    values = program.evaluate(np.radians(table[:, 0]))
    np.testing.assert_allclose(table[:, 1], values.s, rtol=0, atol=1e-15)
    assert table[-1, 1] == pytest.approx(0.25, abs=1e-12)
    assert (out / "jaw_cam_coefficients.csv").is_file()
    motor = np.loadtxt(out / "jaw_motor.csv", delimiter=",", skiprows=1)
    assert motor.shape[1] == 3
    page = (out / "report.html").read_text()
    assert 'href="jaw_cam_table.csv"' in page


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (lambda t: t.update(load="spinning"), "load = 'spinning' must be one of"),
        (lambda t: t.update(inertia_kg_m2=0.1), "inertia_kg_m2 is for a rotary load"),
        (lambda t: t.update(gear_ratio=0.0), "gear_ratio"),
        (lambda t: t.update(gear_ratio=-2.0), "gear_ratio"),
        (lambda t: t.update(drive_efficiency=1.5), "drive_efficiency"),
        (lambda t: t.update(motor="NO-SUCH"), "'NO-SUCH' is not in the catalogue"),
        (lambda t: (t.pop("motor"), t.pop("catalogue")), "give motor"),
        (lambda t: t.update(gear_ratios=[]), "gear_ratios"),
        (lambda t: t.update(table_points=2.5), "table_points"),
        (lambda t: t.update(phase={"event": "1"}), "phase is for an axis without bound"),
        (lambda t: t["segment"][2].update(arc=["1", "2"]), "cannot take a phase angle"),
        (lambda t: t["segment"][0].update(arc=["1", "4"]), "arc"),
        (lambda t: t["segment"][0].update(load_n=3.0), "load_n"),
        (lambda t: t.update(advance_m=0.3), "the strokes sum to 0.25 m"),
        (lambda t: t["segment"][0].update(law="bouncy"), "bouncy"),
        (lambda t: t.update(motor={"rated_torque_nm": 1.0, "peak_torque_nm": 3.0}), "max_rpm"),
    ],
)
def test_bad_input_is_named(machine: cm.Machine, edit: Any, needle: str) -> None:
    d = data(machine)
    edit(d["mechanism"]["film feed"])
    message = refused(d)
    assert "[mechanism.film feed]" in message and needle in message, message


def test_catalogue_missing_a_column(machine: cm.Machine, tmp_path: Path) -> None:
    bad = tmp_path / "motors.csv"
    bad.write_text("name,rated_torque_nm,peak_torque_nm,max_rpm\nA,1,3,3000\n")
    d = data(machine)
    d["mechanism"]["film feed"]["catalogue"] = str(bad)
    assert "inertia_kg_m2" in refused(d)


def test_catalogue_relative_to_the_file(tmp_path: Path) -> None:
    text = EXAMPLE.read_text()
    (tmp_path / "m.toml").write_text(text)
    with pytest.raises(cm.CyclomechError, match=r"motors\.csv"):
        cm.Machine.from_toml(tmp_path / "m.toml")
    (tmp_path / "motors.csv").write_text((EXAMPLE.parent / "motors.csv").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cm.Machine.from_toml(tmp_path / "m.toml").mechanisms["jaw"].catalogue


def test_torque_reserve_is_the_motor_derated(machine: cm.Machine) -> None:
    """A 20 % reserve is the same axis with a motor of 80 % of its torques: the same
    bounds (an independent build from an inline motor table)."""
    d = data(machine)
    d["mechanism"]["film feed"]["torque_reserve"] = 0.2
    kept = build(d).mechanisms["film feed"]
    m = machine.mechanisms["film feed"].axis.motor
    d = data(machine)
    d["mechanism"]["film feed"]["motor"] = {
        "rated_torque_nm": 0.8 * m.rated_torque_nm,
        "peak_torque_nm": 0.8 * m.peak_torque_nm,
        "rated_rpm": m.rated_rpm,
        "max_rpm": m.max_rpm,
        "inertia_kg_m2": m.inertia_kg_m2,
        "name": m.name,
    }
    derated = build(d).mechanisms["film feed"]
    rpm = np.array([60.0, 120.0])
    for a, b in zip(kept.laws(), derated.laws(), strict=True):
        np.testing.assert_allclose(a(rpm), b(rpm), rtol=1e-12)
    assert kept.torque_reserve == 0.2
    assert all(
        k.peak_torque_nm == pytest.approx(0.8 * c.peak_torque_nm)
        for k, c in zip(kept.catalogue, machine.mechanisms["film feed"].catalogue, strict=True)
    )
    # More reserve, a longer index at the same speed.
    assert kept.laws()[0](rpm)[0] > machine.mechanisms["film feed"].laws()[0](rpm)[0]
    d = data(machine)
    d["mechanism"]["film feed"]["torque_reserve"] = 1.0
    assert "torque_reserve = 1.0 must be in [0, 1)" in refused(d)
