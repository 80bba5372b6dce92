"""Which key buys how many rpm (issue 36, item 2): the speed limit's sensitivity to
each numeric key of the mechanisms' tables, from one batched call, checked against
re-runs of the machine with the key changed (each its own ``speed_limit()``, not the
batch), and the rules for a key that does not bind, a kink and a key that cannot
vary."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.machine._sensitivity import EXACT, FLAT, STEP, _rate
from hypothesis import assume, given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]


def _limit(m: cm.Machine, key: str, factor: float) -> float:
    parts = key.split(".")
    if parts[0] == "operation":  # operation.<k>.<key>, k from 1
        value = m.data["operation"][int(parts[1]) - 1][parts[2]]
    else:
        value = m.data["mechanism"][parts[0]][parts[1]]
    return m.with_values({key: value * factor}).speed_limit().rpm


@pytest.fixture(scope="module")
def example() -> tuple[cm.Machine, list[cm.machine.Sensitivity]]:
    m = cm.Machine.example()
    return m, cm.machine.sensitivities(m)


def test_each_binding_key_is_its_central_difference_rerun(example):
    m, table = example
    binds = [s for s in table if s.status == "binds"]
    assert len(binds) >= 3
    for s in binds:
        up, down = _limit(m, s.key, 1 + STEP), _limit(m, s.key, 1 - STEP)
        want = (up - down) / (2 * STEP * s.value)
        assert s.rpm_per_unit == pytest.approx(want, rel=1e-2), s.key


def test_a_one_percent_raise_buys_what_the_table_says(example):
    m, table = example
    base = m.speed_limit().rpm
    for s in [s for s in table if s.status == "binds"][:3]:
        gained = _limit(m, s.key, 1.01) - base
        assert gained == pytest.approx(s.rpm_per_percent, rel=0.05), s.key


def test_the_ranking_puts_the_largest_effect_first(example):
    _, table = example
    binds = [abs(s.rpm_per_percent) for s in table if s.status == "binds"]
    assert binds == sorted(binds, reverse=True)
    order = ["binds", "kink", "does not bind", "cannot vary", "not varied"]
    ranks = [order.index(s.status) for s in table]
    assert ranks == sorted(ranks)


def test_a_key_that_does_not_bind_is_zero_and_says_so():
    m = cm.Machine.from_toml(ROOT / "examples" / "flow_wrapper.toml")
    table = {s.key: s for s in cm.machine.sensitivities(m)}
    s = table["pusher.base_radius_m"]
    assert (s.status, s.rpm_per_percent, s.rpm_per_unit) == ("does not bind", 0.0, 0.0)
    assert _limit(m, "pusher.base_radius_m", 1.01) == pytest.approx(m.speed_limit().rpm, rel=1e-9)


def test_a_kink_gives_both_sides_and_no_slope():
    # The press's phase angle φ0 sits at the top of its speed limit: both ways lower it.
    m = cm.Machine.from_toml(ROOT / "examples" / "extrusion_press_line.toml")
    s = {s.key: s for s in cm.machine.sensitivities(m)}["drive.phi0_deg"]
    assert s.status == "kink" and math.isnan(s.rpm_per_percent)
    base = m.speed_limit().rpm
    up, down = _limit(m, "drive.phi0_deg", 1 + STEP), _limit(m, "drive.phi0_deg", 1 - STEP)
    assert f"{up - base:+.4g} rpm" in s.note and f"{down - base:+.4g} rpm" in s.note
    assert up < base and down < base


def test_a_key_that_cannot_vary_says_why():
    m = cm.Machine.from_toml(ROOT / "examples" / "extrusion_press_line.toml")
    s = {s.key: s for s in cm.machine.sensitivities(m)}["drive.R_m"]
    assert s.status == "cannot vary" and math.isnan(s.rpm_per_percent)
    assert "R" in s.note and "extrusion_press_line.toml" in s.note


@given(
    a=st.floats(10, 1000),
    b=st.floats(-50, 50).filter(lambda x: abs(x) > 1e-3),
    v=st.floats(1e-3, 1e3),
)
def test_a_straight_line_gives_its_slope(a, b, v):
    # L(k) = a + b·k: the central difference is exact, the +1 % figure b·0.01·v.
    base = a + b * v
    s = _rate("m.k", v, base, a + b * v * (1 + STEP), a + b * v * (1 - STEP))
    if abs(b * v) * STEP <= 0.5 * FLAT * max(abs(base), 1.0):
        assert s.status == "does not bind"  # a change within the search's tolerance
        return
    assume(abs(b * v) * STEP > 2.0 * FLAT * max(abs(base), 1.0))  # not at the threshold
    assert s.status == "binds"
    assert s.rpm_per_unit == pytest.approx(b, rel=1e-6, abs=1e-9)
    assert s.rpm_per_percent == pytest.approx(b * 0.01 * v, rel=1e-6, abs=1e-9)


def test_run_reports_them_in_results_json_and_the_page(cli_run):
    run = cli_run(ROOT / "examples" / "stb_loom.toml", "--no-plot", "--quiet")
    out = run.out
    assert run.code == 0
    printed = run.stdout
    # the weft insertion's time sets the loom's limit first, then the lever's overhang
    assert "Speed limit per +1 % of a key: operation.11.min_duration_s" in printed
    assert ", lifter.b_m" in printed
    results = json.loads((out / "results.json").read_text("utf-8"))
    entries = {e["key"]: e for e in results["sensitivities"]}
    assert entries["lifter.b_m"]["status"] == "binds"
    assert all(
        e["rpm_per_percent"] is None or math.isfinite(e["rpm_per_percent"])
        for e in entries.values()
    )
    page = (out / "report.html").read_text("utf-8")
    assert "Which key buys speed" in page and "lifter.b_m" in page


def test_run_without_sensitivities_says_so_and_keeps_every_other_figure(cli_run):
    """``--no-sensitivities`` leaves out the table and nothing else: the limit, the
    optimum and the results file's other entries are the full run's, the printed
    line on the keys is gone, and the page says why its section is empty."""
    loom = ROOT / "examples" / "stb_loom.toml"
    full = cli_run(loom, "--no-plot", "--quiet")
    bare = cli_run(loom, "--no-plot", "--quiet", "--no-sensitivities")
    assert bare.code == full.code == 0
    assert "Speed limit per +1 % of a key" not in bare.stdout
    # every printed line but the keys' (and the folder's name in the last) alike
    lines = [x for x in full.stdout.splitlines() if "per +1 %" not in x]
    assert [x.replace(str(full.out), "OUT") for x in lines] == [
        x.replace(str(bare.out), "OUT") for x in bare.stdout.splitlines()
    ]
    a = json.loads((full.out / "results.json").read_text("utf-8"))
    b = json.loads((bare.out / "results.json").read_text("utf-8"))
    assert "sensitivities" in a and "sensitivities" not in b
    a.pop("sensitivities")
    assert {k: v for k, v in a.items() if k != "seconds"} == {
        k: v for k, v in b.items() if k != "seconds"
    }
    assert "sensitivities" in a["seconds"] and "sensitivities" not in b["seconds"]
    page = (bare.out / "report.html").read_text("utf-8")
    assert "Which key buys speed" in page and "--no-sensitivities" in page
    assert "lifter.b_m" not in page.split("Which key buys speed")[1].split("<h3>")[0]


def test_operation_keys_match_the_critical_chains_closed_form():
    """The knife cutter's limit is its cyclogram's: the chain clamp → cut → knife
    return → move the pile fills the turn, Σ a_k + 6·n·t = 360° (t the pile's
    min_duration_s), so n = (360 − Σ a_k)/(6 t): a +1 % raise of an angle a_k buys
    −0.01·a_k/(6 t) rpm and of t, −0.01·n rpm. The table takes these from the LP's
    shadow prices at the limit (exact, its note says so); its central differences
    (each a re-parse of the file with the operation's key changed) agree."""
    m = cm.Machine.from_toml(ROOT / "examples" / "knife_cutter.toml")
    table = {s.key: s for s in cm.machine.sensitivities(m)}
    ops = m.data["operation"]
    t = ops[5]["min_duration_s"]
    chain = {1: ops[0], 2: ops[1], 3: ops[2]}
    n = (360.0 - sum(op["min_angle_deg"] for op in chain.values())) / (6.0 * t)
    assert table["operation.6.min_duration_s"].limit_rpm == pytest.approx(n, rel=1e-9)
    assert table["operation.6.min_duration_s"].rpm_per_percent == pytest.approx(-0.01 * n, rel=1e-8)
    for k, op in chain.items():
        s = table[f"operation.{k}.min_angle_deg"]
        assert s.status == "binds" and op["name"] in s.note and EXACT in s.note
        assert s.rpm_per_percent == pytest.approx(-0.01 * op["min_angle_deg"] / (6 * t), rel=1e-8)
        fd = (_limit(m, s.key, 1 + STEP) - _limit(m, s.key, 1 - STEP)) / (2 * STEP * s.value)
        assert s.rpm_per_unit == pytest.approx(fd, rel=1e-5)
    assert table["operation.4.min_angle_deg"].status == "does not bind"  # off the chain


def test_an_operation_key_path_is_checked():
    m = cm.Machine.from_toml(ROOT / "examples" / "knife_cutter.toml")
    assert m.with_values({"operation.6.min_duration_s": 0.3}).speed_limit().rpm > 60.0
    with pytest.raises(
        cm.CyclomechError,
        match=r"operation '9' must be the number of an \[\[operation\]\] of the file, 1 to 6",
    ):
        m.with_values({"operation.9.min_angle_deg": 1.0})
    with pytest.raises(cm.CyclomechError, match="has no key 'name' a sweep can set"):
        cm.machine.check_parameter(m, "operation.2.name")
    cm.machine.check_parameter(m, "operation.2.min_angle_deg")


@settings(max_examples=8, deadline=None)
@given(
    a=st.tuples(st.floats(10.0, 60.0), st.floats(60.0, 120.0), st.floats(65.0, 110.0)),
    t=st.floats(0.1, 0.6),
)
def test_exact_rates_hold_on_any_chain(a, t):
    """The knife cutter's chain with other angles and another duration (the knife's
    return above the unclamp's 60°, so the chain stays critical): the exact rates
    are the closed form's."""
    m = cm.Machine.from_toml(ROOT / "examples" / "knife_cutter.toml")
    values = {f"operation.{k + 1}.min_angle_deg": v for k, v in enumerate(a)}
    m = m.with_values({**values, "operation.6.min_duration_s": t})
    n = (360.0 - sum(a)) / (6.0 * t)
    lim = m.speed_limit()
    assume(lim.by == "cyclogram" and lim.rpm == pytest.approx(n, rel=1e-9))
    table = {s.key: s for s in cm.machine.sensitivities(m)}
    for k in range(len(a)):
        s = table[f"operation.{k + 1}.min_angle_deg"]
        if EXACT in s.note:
            assert s.rpm_per_unit == pytest.approx(-1.0 / (6.0 * t), rel=1e-8)
    s = table["operation.6.min_duration_s"]
    assert EXACT in s.note and s.rpm_per_unit == pytest.approx(-n / t, rel=1e-8)
