"""Cam files with motion programs: moving ends, constant velocity, polydyne.

* The flying-knife example's cam matches the web's speed over its cut: s′ is the
  file's velocity there, and its profile is the program's (checked through the
  CLI's profile.csv against a Program built here from the same numbers).
* The polydyne example holds at its design speed and fails loudly (exit 3,
  naming the segment) off design, where the follower's residual vibration
  exceeds the file's limit.
* File mistakes name the segment and key.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from numpy.testing import assert_allclose

CamDesign = cm.cam.CamDesign
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_flying_knife_matches_the_web(tmp_path, capsys):
    _, _, d = CamDesign.from_toml(EXAMPLES / "flying_knife_cam.toml")
    assert d.cam.program is not None
    theta = np.radians(np.linspace(72.0, 128.0, 57))
    assert_allclose(d.cam.solve(theta).ds, 0.04, rtol=1e-13)
    M = cm.motion.Segment
    mine = cm.motion.Program(
        [
            M("cycloidal", 70, end=(0.025, 0.04)),
            M("constant_velocity", 60),
            M("modified_sine", 50, end=0.025 + 0.04 * math.pi / 3 + 0.018),
            M("dwell", 40),
            M("poly5", 140, end=0.0),
        ]
    )
    grid = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    assert_allclose(d.cam.solve(grid).s, mine.evaluate(grid).s, atol=1e-12)
    assert main(["cam", str(EXAMPLES / "flying_knife_cam.toml"), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "constant_velocity" in out and "the design holds every criterion" in out


def test_the_polydyne_example_holds_on_design_and_fails_off(tmp_path, capsys):
    path = str(EXAMPLES / "polydyne_cam.toml")
    assert main(["cam", path, "--out", str(tmp_path / "on"), "--no-plot"]) == 0
    results = json.loads((tmp_path / "on" / "results.json").read_text())
    residual = [e["residual"] for e in results["residual_vibration"]]
    assert max(residual) < 1e-10  # m: nil at the design speed (the limit is 2e-5)
    capsys.readouterr()
    assert main(["cam", path, "--out", str(tmp_path / "off"), "--no-plot", "--rpm", "1000"]) == 3
    out = capsys.readouterr().out
    assert "FAILS: segment 1 (poly7): residual vibration" in out


def _table(**extra: Any) -> dict[str, Any]:
    return {
        "follower": "translating",
        "base_radius_m": 0.05,
        "roller_radius_m": 0.01,
        "segment": [
            {"kind": "rise", "angle_deg": 90, "stroke_m": 0.02, "end_velocity_m_per_rad": 0.01},
            {"kind": "rise", "angle_deg": 90, "law": "constant_velocity"},
            {
                "kind": "return",
                "angle_deg": 180,
                "stroke_m": 0.02 + 0.01 * math.pi / 2,
                "law": "poly5",
            },
        ],
    } | extra


def test_a_file_program_reads():
    d = CamDesign.from_table(_table(), "[cam]")
    assert [g.law for g in d.cam.program.segments] == [
        "cycloidal",
        "constant_velocity",
        "poly5",
    ]
    assert d.cam.segments[1].stroke == pytest.approx(0.01 * math.pi / 2, rel=1e-15)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            lambda t: (
                t["segment"][1].update(law="constant_velocity")
                or t["segment"][0].pop("end_velocity_m_per_rad")
            ),
            r"segment 2: a constant_velocity segment needs stroke_m, start_velocity_m_per_rad",
        ),
        (
            lambda t: t["segment"][0].update(end_velocity_deg_per_rad=1.0),
            r"segment 1: unknown key .end_velocity_deg_per_rad.; valid keys are .*_m_per_rad",
        ),
        (lambda t: t.update(continuity="smooth"), r"continuity = 'smooth' must be one of"),
        (
            lambda t: t["segment"][0].update(law="polynomial_345"),
            r"segment 1 \(polynomial_345\): the law cannot meet its end velocity = 0.01",
        ),
        (
            lambda t: t.update(polydyne_rpm=600.0),
            r"polydyne_rpm needs the follower's mass_kg and natural_frequency_hz",
        ),
    ],
)
def test_file_mistakes_name_the_segment_and_key(change, message):
    t = _table()
    change(t)
    with pytest.raises(cm.InputError, match=message):
        CamDesign.from_table(t, "[cam]")


def test_an_arc_on_a_moving_segment_is_refused():
    t = _table()
    t["segment"][1]["arc"] = ["a", "b"]
    with pytest.raises(cm.InputError, match=r"segment 2: arc = \['a', 'b'\], but its law"):
        CamDesign.from_table(t, "[cam]", arcs=True)
