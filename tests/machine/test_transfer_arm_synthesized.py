"""The cartoner's transfer arm whose six-bar is synthesised from its dwell
(``examples/transfer_arm_synthesized.toml``, issue 35 item 8): the linkage the
machine analyses dwells and swings as asked, solved by its own solver on a dense
grid; the grip of the optimised cycle falls inside the dwell; the pinned results
agree with those recomputations."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.machine import analyze, write_report

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "transfer_arm_synthesized.toml"
PINNED = ROOT / "tests" / "package" / "pinned" / "transfer_arm_synthesized" / "results.json"


@pytest.fixture(scope="module")
def machine() -> cm.Machine:
    return cm.Machine.from_toml(EXAMPLE)


def _rocker(lk: cm.Linkage, crank_deg: np.ndarray) -> np.ndarray:
    sol = lk.solve(np.radians(crank_deg), points=["E", "F"])
    d = sol["E"] - sol["F"]
    return np.degrees(np.unwrap(np.arctan2(d[:, 1], d[:, 0])))


def test_the_arm_dwells_and_swings_as_asked(machine: cm.Machine) -> None:
    arm = machine.mechanisms["arm"]
    rec = arm.synthesis
    assert rec.scheme == "dwell_sixbar" and arm.linkage is rec.linkage and arm.output == "E"
    c = rec.candidate
    lo, hi = c.dwell_range_deg
    assert hi - lo == pytest.approx(100.0, abs=1e-12)
    still = _rocker(arm.linkage, np.linspace(lo, hi, 10001))
    assert np.ptp(still) <= 0.25  # max_residual_deg
    assert np.ptp(still) == pytest.approx(c.residual_deg, abs=1e-6)
    turn = _rocker(arm.linkage, np.arange(0.0, 360.0, 0.005))
    assert np.ptp(turn) == pytest.approx(35.0, abs=1e-5)
    # Both loops' transmission angles at least 35° over a dense turn (the four-bar's
    # between B → C and D → C, the dyad's between E → P and E → F).
    sol = arm.linkage.solve(np.radians(np.arange(0.0, 360.0, 0.05)))

    def mu(p: str, a: str, b: str) -> np.ndarray:
        u, v = sol[a] - sol[p], sol[b] - sol[p]
        t = np.degrees(np.arccos(np.sum(u * v, 1) / np.hypot(*u.T) / np.hypot(*v.T)))
        return np.minimum(t, 180.0 - t)

    assert mu("C", "B", "D").min() >= 35.0 - 1e-6 and mu("E", "P", "F").min() >= 35.0 - 1e-6


def test_the_grip_falls_inside_the_dwell(machine: cm.Machine) -> None:
    """The phase puts the crank at 110.5° at the event "grip": at the optimised
    timing, the crank's angles at "grip" and "gripped" lie in the dwell."""
    r = analyze(machine, progress=False)
    times = r.optimum.times
    c = machine.mechanisms["arm"].synthesis.candidate
    lo, hi = c.dwell_range_deg
    start = 110.5
    end = start + (times["gripped"] - times["grip"]) % 360.0
    assert lo <= start and end <= hi
    assert r.failures == []


def test_the_pinned_results_agree_with_a_recomputation(machine: cm.Machine) -> None:
    """The pinned synthesis and speed limit, recomputed here: the residual and swing
    by a dense solve; the speed limit from E's peak acceleration by central
    differences of its positions, n = √(a_max / max|d²E/dφ²|)·60/2π."""
    pin = json.loads(PINNED.read_text("utf-8"))["mechanisms"]["arm"]
    syn = pin["synthesis"]
    lk = machine.mechanisms["arm"].linkage
    lo = syn["dwell_start_deg"]
    assert np.ptp(_rocker(lk, np.linspace(lo, lo + 100.0, 10001))) == pytest.approx(
        syn["residual_deg"], abs=1e-6
    )
    assert syn["swing_deg"] == pytest.approx(35.0, abs=1e-6)
    # E's positions on a fine grid, differentiated twice by central differences (not
    # the solver's analogs).
    h = math.radians(0.01)
    xy = lk.solve(np.arange(0.0, 2.0 * math.pi, h), points=["E"], analogs=False)["E"]
    acc = float(np.max(np.hypot(*((np.roll(xy, -1, 0) - 2 * xy + np.roll(xy, 1, 0)) / h**2).T)))
    limit = math.sqrt(25.0 / acc) * 60.0 / (2.0 * math.pi)
    assert pin["speed_limit_rpm"] == pytest.approx(limit, rel=1e-3)


def test_the_report_has_the_synthesis(machine: cm.Machine, tmp_path: Path) -> None:
    r = analyze(machine, progress=False)
    rows = dict((row[0], row[1]) for row in r.mechanisms["arm"].table()[1])
    assert rows["synthesised scheme"].startswith("dwell_sixbar")
    assert "feasible one whose output moves least" in rows["synthesis: what it chose and why"]
    assert rows["synthesis: the dwell [crank deg]"].startswith("100.5 to 200.5")
    names = {p.name for p in write_report(r, tmp_path, figures=True)}
    assert {"arm_synthesis.csv", "arm_synthesis.png"} <= names
