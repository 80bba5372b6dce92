"""The main job computes each result once (issue 17): the report, results.json,
the CSVs and the CLI summary read what :func:`analyze` computed."""

from __future__ import annotations

import json
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.machine import analyze, write_report

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_knife_linkage_is_solved_once_per_run(monkeypatch, tmp_path):
    # Five solves on main before issue 17 (parse, analyze, summary, figures, …).
    calls = []
    real = cm.Linkage.solve

    def counting(self, *args, **kwargs):
        calls.append(1)
        return real(self, *args, **kwargs)

    monkeypatch.setattr(cm.Linkage, "solve", counting)
    m = cm.Machine.from_toml(EXAMPLES / "knife_cutter.toml")
    assert len(calls) == 1  # the parser checks that it turns all the way round
    r = analyze(m, progress=False)
    write_report(r, tmp_path, figures=False)
    # … and once more for its forces, on their own grid (3600 angles, for the
    # main shaft), which the report, the CSVs and the shaft then all read; the
    # report's animation solves it at its own 120 frames, once.
    assert len(calls) == 3


def test_one_speed_limit_per_mechanism_in_results(tmp_path):
    # With a coarse grid and a low limit the knife's limit once came out twice,
    # from two grids (60.736 and 60.960 rpm): one value now, the speed limit's.
    m = cm.Machine.from_toml(EXAMPLES / "knife_cutter.toml").with_values(
        {"machine.angle_points": 13, "knife.max_acceleration_m_per_s2": 5.0}
    )
    r = analyze(m, progress=False)
    write_report(r, tmp_path, figures=False)
    res = json.loads((tmp_path / "results.json").read_text(encoding="utf-8"))
    limits = {
        res["speed_limit"]["mechanisms_rpm"]["knife"],
        res["mechanisms"]["knife"]["speed_limit_rpm"],
    }
    assert len(limits) == 1
    assert res["speed_limit"]["mechanisms_reason"]["knife"].startswith("the peak acceleration")


def test_the_stops_bound_is_searched_once_per_machine(monkeypatch):
    # The bound laws are worked out once and kept on the machine: the speed limit,
    # the sweep and fits() reuse them.
    from cyclomech.impact import CamStop

    calls = []
    real = CamStop.bound_laws.__func__

    def counting(cls, *args, **kwargs):
        calls.append(kwargs.get("linear", False))
        return real(cls, *args, **kwargs)

    monkeypatch.setattr(CamStop, "bound_laws", classmethod(counting))
    m = cm.Machine.from_toml(EXAMPLES / "stb_loom.toml")
    analyze(m, progress=False)
    m.fits([300.0])
    m.speed_limit()
    assert calls.count(False) == 1 and calls.count(True) == 1


def test_the_report_does_not_solve_again(monkeypatch, tmp_path):
    pytest.importorskip("matplotlib")
    r = analyze(cm.Machine.from_toml(EXAMPLES / "stb_loom.toml"), progress=False)

    def forbidden(*args, **kwargs):
        raise AssertionError("the report recomputed a result")

    for name in ("speed_limit", "speed_sweep", "optimize", "cyclogram_at"):
        monkeypatch.setattr(cm.Machine, name, forbidden)
    write_report(r, tmp_path, figures=True)
    assert (tmp_path / "report.html").is_file()
