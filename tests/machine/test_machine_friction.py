"""A machine's friction and efficiency (issue 34 item 5): the knife cutter's
friction table loads its main shaft by exactly the friction's mean power (the
shaft's mean torque, the reduced load torque of [drive]), the power balance
over the turn (input = output + friction, the output from the knife's
positions and the pile's force), the efficiency in results.json, the report and
the run line, and a self-locking linkage failing with exit 3, naming it and
its crank angles."""

from __future__ import annotations

import copy
import json
import math
import warnings
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine import analyze, write_report

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
KNIFE = EXAMPLES / "knife_cutter.toml"
RAD = 2 * math.pi / 60

#: A slider-crank ram whose block meets P = 500 N while it moves left, its guide
#: with μ = 5: μ·tan(rod angle) ≥ 1 over part of the turn, where it self-locks.
RAM = """
[mechanism.ram]
kind = "linkage"
links = [["A", "B"], ["B", "C"]]
ground = ["A"]
driver = ["A", "B"]
points = {A = [0.0, 0.0], B = [0.1, 0.0], C = [0.45, 0.0]}
sliders = {C = {ground = [1.0, 0.0]}}
load = [{point = "C", force_n = [[500.0, 0.0], [500.0, 0.0]], angle_deg = [10.0, 170.0]}]
friction = {guide_mu = 5.0}
"""


def with_ram(ram: str) -> str:
    """The knife cutter's file with ``ram`` added, on its elastic main shaft too."""
    text = KNIFE.read_text("utf-8")
    for key, two in (
        ("take_off", '["knife", "ram"]'),
        ("stiffness_nm_per_rad", "[1.6e6, 1.6e6]"),
        ("hub_inertia_kg_m2", "[2.0, 0.5]"),
    ):
        line = next(x for x in text.splitlines() if x.startswith(key + " "))
        text = text.replace(line, f"{key} = {two}")
    return text + ram


def knife(friction: bool = True) -> cm.Machine:
    d = copy.deepcopy(dict(cm.Machine.from_toml(KNIFE).data or {}))
    if not friction:
        del d["mechanism"]["knife"]["friction"]
    return cm.Machine.from_dict(d, str(KNIFE))


@pytest.fixture(scope="module")
def results() -> tuple[Any, Any]:
    return analyze(knife(), progress=False), analyze(knife(False), progress=False)


def test_the_shaft_carries_exactly_the_friction_power(results: tuple[Any, Any]) -> None:
    """At steady speed (T_f − T_0)·ω is the friction power at every angle (same
    motion, same loads), so the main shaft's mean torque and the reduced load
    torque Q(φ) that [drive] integrates rise by the mean friction power / ω."""
    with_f, without = results
    w = 45.0 * RAD
    lost = with_f.mechanisms["knife"].efficiency()["mean_friction_power_w"]
    assert lost > 50.0
    rise = float(with_f.shaft.at_nominal.mean_torque_nm - without.shaft.at_nominal.mean_torque_nm)
    assert rise * w == pytest.approx(lost, rel=1e-9)
    p_rise = float(with_f.shaft.at_nominal.power_w - without.shaft.at_nominal.power_w)
    assert p_rise == pytest.approx(lost, rel=1e-9)
    q_f = cm.dynamics.reduced(with_f).load_torque_nm
    q_0 = cm.dynamics.reduced(without).load_torque_nm
    assert float(np.mean(q_f - q_0)) * w == pytest.approx(lost, rel=1e-9)
    # The frictionless mechanism's own numbers stay as they were.
    a, b = with_f.mechanisms["knife"].json(), without.mechanisms["knife"].json()
    assert a["mechanisms"] == b["mechanisms"] and "friction" not in b
    # [drive] sees the load: its steady state needs more motor torque and flywheel.
    assert with_f.dynamics.steady.rms_motor_torque_nm > without.dynamics.steady.rms_motor_torque_nm
    assert with_f.shaft.at_nominal.flywheel_kg_m2 > without.shaft.at_nominal.flywheel_kg_m2


def test_power_balance_over_the_turn(results: tuple[Any, Any]) -> None:
    """Mean input power with friction = the power into the pile + the friction
    power (the stored energy returns over a steady turn): the pile's force on the
    knife E interpolated from the file's table, E's velocity from the positions
    by central differences."""
    with_f, _ = results
    res = with_f.mechanisms["knife"]
    f = res.friction
    lk = res.mech.linkage
    n = f.angles.size
    h = 1e-6
    e = lk.names.index("E")
    up, down = lk.solve(f.angles + h), lk.solve(f.angles - h)
    v = (up.xy[:, e] - down.xy[:, e]) / (2 * h) * (45.0 * RAD)
    deg = np.mod(np.degrees(f.angles), 360.0)
    table = [140.0, 150.0, 200.0, 240.0, 250.0]
    fy = np.interp(deg, table, [0.0, 30000.0, 25000.0, 15000.0, 0.0], left=0.0, right=0.0)
    p_out = -(fy * v[:, 1])  # the knife works against the pile's push
    p_in, p_f = f.input_power[0], f.friction_power[0]
    assert p_out.mean() > 1000.0 and n == 3600
    assert p_in.mean() == pytest.approx(p_out.mean() + p_f.mean(), rel=1e-6)
    eta = res.efficiency()["cycle_efficiency"]
    assert eta == pytest.approx(p_out.mean() / p_in.mean(), rel=1e-6)


def test_efficiency_in_results_report_and_run_line(cli_run) -> None:
    run = cli_run(KNIFE, "--no-plot", "--quiet")
    assert run.code == 0
    out, folder = run.stdout, run.out
    line = next(t for t in out.splitlines() if t.startswith("Friction at 45 rpm"))
    assert "knife efficiency 0.95" in line and "machine efficiency 0.95" in line
    data = json.loads((folder / "results.json").read_text("utf-8"))
    k, m = data["friction"]["knife"], data["efficiency"]
    assert m["machine_efficiency"] == pytest.approx(k["cycle_efficiency"], rel=1e-12)
    assert m["mean_friction_power_w"] == pytest.approx(k["mean_friction_power_w"], rel=1e-12)
    assert k["peak_torque_nm"] > k["peak_torque_nm_without"]
    assert sum(k["friction_power_by_element_w"].values()) == pytest.approx(
        k["mean_friction_power_w"], rel=1e-9
    )
    page = (folder / "report.html").read_text("utf-8")
    assert "<h3>Friction and efficiency</h3>" in page and "efficiency over the turn" in page


def test_no_friction_no_efficiency_group(tmp_path: Path) -> None:
    r = analyze(knife(False), progress=False)
    write_report(r, tmp_path, figures=False)
    data = json.loads((tmp_path / "results.json").read_text("utf-8"))
    assert "efficiency" not in data and "friction" not in data


def test_self_locking_fails_naming_the_mechanism_and_angles(tmp_path: Path, capsys) -> None:
    f = tmp_path / "k.toml"
    f.write_text(with_ram(RAM), encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cm.CyclomechWarning)  # μ = 5; self-locking
        status = main(["run", str(f), "--out", str(tmp_path / "out"), "--no-plot", "--quiet"])
    assert status == 3
    err = capsys.readouterr().err
    assert "ram: friction self-locks the linkage at crank angles 43.3–136.7 degrees" in err
    data = json.loads((tmp_path / "out" / "results.json").read_text("utf-8"))
    ram = data["friction"]["ram"]
    assert ram["cycle_efficiency"] is None and len(ram["self_locking_crank_deg"]) > 100
    assert data["efficiency"]["machine_efficiency"] is None


def test_the_machines_efficiency_over_two_mechanisms(tmp_path: Path) -> None:
    """The knife and a ram with μ = 0.2 on its guide: the main shaft's mean power
    is the sum of the two mechanisms' mean input powers (phasing moves a curve,
    not its mean), and the machine's efficiency is 1 − (P_f,knife + P_f,ram)/ΣP_in."""
    f = tmp_path / "k.toml"
    f.write_text(with_ram(RAM.replace("5.0", "0.2")), encoding="utf-8")
    r = analyze(cm.Machine.from_toml(f), progress=False)
    k, ram = (r.mechanisms[n].efficiency() for n in ("knife", "ram"))
    p_in = k["mean_input_power_w"] + ram["mean_input_power_w"]
    assert float(r.shaft.at_nominal.power_w) == pytest.approx(p_in, rel=1e-9)
    e = cm.machine._efficiency.machine_efficiency(r)
    lost = k["mean_friction_power_w"] + ram["mean_friction_power_w"]
    assert e["mean_friction_power_w"] == pytest.approx(lost, rel=1e-12)
    assert e["machine_efficiency"] == pytest.approx(1.0 - lost / p_in, rel=1e-9)
    low, high = sorted((k["cycle_efficiency"], ram["cycle_efficiency"]))
    assert low < e["machine_efficiency"] < high
