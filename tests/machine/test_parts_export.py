"""What a designer takes away from ``cyclomech run`` (issue 36, item 1): each cam's
profile at the optimised timing (the same file ``cyclomech cam`` writes for a cam
file with those phase angles, to the last digit), the timing table (each operation's
start, end and duration: results.json's numbers) and each linkage's drawing table
(pivots, joints and link lengths: the file's own drawing)."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import tomllib
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"
KNIFE = ROOT / "examples" / "knife_cutter.toml"


def _toml_value(v: object) -> str:
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return str(v)


def _cam_file(table: dict, angles: list[float], rpm: float, path: Path) -> Path:
    """A cam file of a machine's cam table with the segments' angles replaced, written
    here by hand (TOML's basic types only): the machine-only keys left out."""
    lines = ["[cam]", 'name = "lifter cam"', f"rpm = {rpm!r}"]
    for k, v in table.items():
        if k not in ("kind", "segment", "friction"):
            lines.append(f"{k} = {_toml_value(v)}")
    for seg, angle in zip(table["segment"], angles, strict=True):
        lines.append("[[cam.segment]]")
        for k, v in seg.items():
            if k != "arc":
                lines.append(f"{k} = {_toml_value(angle if k == 'angle_deg' else v)}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def loom_run(cli_run) -> Path:
    run = cli_run(LOOM, "--no-plot", "--quiet")
    assert run.code == 0
    return run.out


def test_the_cam_profile_is_cyclomech_cams_at_the_optimised_angles(loom_run, tmp_path):
    results = json.loads((loom_run / "results.json").read_text("utf-8"))
    table = tomllib.loads(LOOM.read_text("utf-8"))["mechanism"]["lifter cam"]
    # The optimised angles from results.json: each bound segment's operation's angle,
    # the dwell the rest of the turn (the layout's rule).
    op_angles = {tuple(k.split("→")): v for k, v in results["optimum"]["angles_deg"].items()}
    moving = [op_angles[tuple(s["arc"])] for s in table["segment"] if "arc" in s]
    angles = [*moving, 360.0 - sum(moving)]
    cam_file = _cam_file(table, angles, results["nominal_rpm"], tmp_path / "lifter.toml")
    out = tmp_path / "cam"
    assert main(["cam", str(cam_file), "--out", str(out), "--no-plot", "--no-dxf"]) == 0
    assert (out / "profile.csv").read_bytes() == (loom_run / "lifter_cam_profile.csv").read_bytes()


def test_the_dxf_holds_the_csvs_profile_in_millimetres(loom_run):
    ezdxf = pytest.importorskip("ezdxf")
    doc = ezdxf.readfile(loom_run / "lifter_cam_profile.dxf")
    (poly,) = doc.modelspace().query("LWPOLYLINE[layer=='PROFILE']")
    with (loom_run / "lifter_cam_profile.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    xy = np.array([[float(r["profile_x_m"]), float(r["profile_y_m"])] for r in rows]) * 1000.0
    np.testing.assert_allclose(np.array(poly.get_points("xy")), xy, rtol=0, atol=1e-9)


def test_the_timing_table_is_results_json(loom_run):
    results = json.loads((loom_run / "results.json").read_text("utf-8"))["optimum"]
    with (loom_run / "operations.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(results["angles_deg"])
    for row in rows:
        arc = f"{row['from']}→{row['to']}"
        angle, start = results["angles_deg"][arc], results["times_deg"][row["from"]]
        assert float(row["angle_deg"]) == angle and float(row["start_deg"]) == start
        assert float(row["end_deg"]) == start + angle
        # degrees at 6·n degrees per second
        assert math.isclose(float(row["duration_s"]), angle / (6.0 * results["speed_rpm"]))


def test_the_report_links_the_parts(loom_run):
    page = (loom_run / "report.html").read_text("utf-8")
    for name in ("lifter_cam_profile.csv", "lifter_cam_profile.dxf"):
        assert f'<a href="{name}">' in page and (loom_run / name).is_file()


def test_the_linkage_drawing_table_is_the_files_drawing(cli_run):
    run = cli_run(KNIFE, "--no-plot", "--quiet")
    assert run.code == 0
    table = tomllib.loads(KNIFE.read_text("utf-8"))["mechanism"]["knife"]
    pts = {k: tuple(v) for k, v in table["points"].items()}
    with (run.out / "knife_drawing.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    pivots = {r["name"]: (float(r["x_m"]), float(r["y_m"])) for r in rows if r["item"] == "pivot"}
    joints = {r["name"]: (float(r["x_m"]), float(r["y_m"])) for r in rows if r["item"] == "joint"}
    assert set(pivots) == set(table["ground"])
    assert {**pivots, **joints} == pts
    links = {r["name"]: float(r["length_m"]) for r in rows if r["item"] == "link"}
    for link in table["links"]:
        for i, a in enumerate(link):
            for b in link[i + 1 :]:
                (xa, ya), (xb, yb) = pts[a], pts[b]
                assert links[f"{a}-{b}"] == pytest.approx(math.hypot(xb - xa, yb - ya), rel=1e-15)
    assert '<a href="knife_drawing.csv">' in (run.out / "report.html").read_text("utf-8")


def test_a_cam_not_laid_out_at_the_optimum_writes_no_part(tmp_path):
    r = cm.machine.analyze(cm.Machine.from_toml(LOOM), progress=False)
    res = dataclasses.replace(r.mechanisms["lifter cam"], layout_note="no optimum")
    assert res.files(tmp_path) == [] and not any(tmp_path.iterdir())
