"""The cutter's centre path (issue 36, item 1): a tool of radius r_t cutting the cam
is tangent to the profile, so every centre lies at r_t from the profile and no
closer (checked against a dense polyline of the profile, not the normal the code
uses); a tool of the roller's size runs on the pitch curve; a concave stretch tighter
than the tool is warned of; the CLI and the machine file carry it to the files."""

from __future__ import annotations

import csv
import tomllib
import warnings
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main

S = cm.cam.Segment
ROOT = Path(__file__).resolve().parents[2]


def _distance_to_curve(points: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """Each point's distance to the closed polyline ``curve`` (segments, exactly)."""
    a, b = curve, np.roll(curve, -1, axis=0)
    ab = b - a
    out = np.empty(len(points))
    for i, p in enumerate(points):
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
        out[i] = np.min(np.hypot(*(a + t[:, None] * ab - p).T))
    return out


def _dense(cam: cm.cam.Cam, which: str = "profile") -> np.ndarray:
    k = cam.solve(np.radians(np.arange(40000) * (360 / 40000)))
    return getattr(k, which)


@pytest.mark.parametrize(
    "follower",
    [
        cm.cam.TranslatingRoller(0.05, 0.012, 0.005),
        cm.cam.OscillatingRoller(0.13, 0.1, 0.06, 0.012),
        cm.cam.FlatFaced(0.05),
    ],
    ids=["translating", "oscillating", "flat"],
)
def test_the_cutter_is_tangent_to_the_profile(follower):
    stroke = 0.2 if isinstance(follower, cm.cam.OscillatingRoller) else 0.015
    cam = cm.cam.Cam([S("rise", 150, stroke), S("dwell", 60), S("return", 150, stroke)], follower)
    r_t = 0.004
    c = cm.cam.cutter_path(cam, r_t, 360)
    d = _distance_to_curve(c, _dense(cam))
    np.testing.assert_allclose(d, r_t, rtol=0, atol=2e-7)  # the dense chords' sag


def test_a_groove_is_cut_on_both_flanks():
    cam = cm.cam.Cam(
        [S("rise", 180, 0.015), S("return", 180, 0.015)],
        cm.cam.TranslatingRoller(0.05, 0.012),
        closure="groove",
    )
    t = cm.cam.profile_table(cam, 1000, 0.005)  # fine enough for the chordal error
    inner = np.column_stack([t["cutter_x_m"], t["cutter_y_m"]])[::3]
    outer = np.column_stack([t["outer_cutter_x_m"], t["outer_cutter_y_m"]])[::3]
    np.testing.assert_allclose(_distance_to_curve(inner, _dense(cam)), 0.005, atol=2e-7)
    np.testing.assert_allclose(
        _distance_to_curve(outer, _dense(cam, "profile_outer")), 0.005, atol=2e-7
    )


def test_a_groove_refuses_a_cutter_wider_than_itself():
    """A groove 2·r_r wide is cut from inside on both flanks: a cutter of radius above
    r_r would overcut the opposite flank by 2·(r_t − r_r) (10 mm here), so it is
    refused by name, in the call and in a cam table's key; r_t = r_r cuts both
    flanks on the pitch curve, at r_r from each (against the dense flanks)."""
    segs = [S("rise", 180, 0.02), S("return", 180, 0.02)]
    cam = cm.cam.Cam(segs, cm.cam.TranslatingRoller(0.05, 0.01), closure="groove")
    for call in (
        lambda: cm.cam.cutter_path(cam, 0.015),
        lambda: cm.cam.profile_table(cam, 720, tool_radius=0.015),
    ):
        with pytest.raises(cm.InputError, match=r"tool_radius = 0\.015.*roller radius 0\.01"):
            call()
    table = {
        "follower": "translating", "base_radius_m": 0.05, "roller_radius_m": 0.01,
        "closure": "groove", "tool_radius_m": 0.015,
        "segment": [{"kind": "rise", "angle_deg": 180, "stroke_m": 0.02},
                    {"kind": "return", "angle_deg": 180, "stroke_m": 0.02}],
    }  # fmt: skip
    with pytest.raises(cm.InputError, match=r"\[cam\].*tool_radius = 0\.015"):
        cm.cam.CamDesign.from_table(table, "[cam]")
    t = cm.cam.profile_table(cam, 1000, tool_radius=0.01)
    for cutter, flank in (("cutter", "profile"), ("outer_cutter", "profile_outer")):
        c = np.column_stack([t[f"{cutter}_x_m"], t[f"{cutter}_y_m"]])[::13]
        np.testing.assert_allclose(_distance_to_curve(c, _dense(cam, flank)), 0.01, atol=2e-7)


def test_a_cutter_of_the_rollers_size_runs_on_the_pitch_curve():
    cam = cm.cam.Cam(
        [S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.TranslatingRoller(0.05, 0.01)
    )
    k = cam.solve(np.radians(np.arange(720) / 2))
    np.testing.assert_allclose(cm.cam.cutter_path(cam, 0.01, 720), k.pitch, rtol=0, atol=1e-15)


def test_a_tool_larger_than_a_concave_stretch_is_warned_of():
    # A fast rise on a small base circle: the profile is concave where the rise ends.
    cam = cm.cam.Cam(
        [S("rise", 60, 0.03), S("dwell", 120), S("return", 60, 0.03), S("dwell", 120)],
        cm.cam.TranslatingRoller(0.04, 0.005),
    )
    t = cm.cam.profile_table(cam, 3600)
    rho = t["profile_curvature_radius_m"]
    tightest = float(np.min(-rho[rho < 0]))
    with pytest.warns(cm.CyclomechWarning, match="gouges the profile"):
        cm.cam.profile_table(cam, 3600, tightest * 1.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cm.cam.profile_table(cam, 3600, tightest * 0.5)


def test_bad_tools_are_refused():
    cam = cm.cam.Cam(
        [S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.TranslatingRoller(0.05, 0.01)
    )
    for bad in (0.0, -0.01, float("nan")):
        with pytest.raises(cm.InputError, match="tool_radius"):
            cm.cam.cutter_path(cam, bad)
    knife = cm.cam.Cam(
        [S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.TranslatingRoller(0.05, 0.0)
    )
    with pytest.raises(cm.InputError, match="knife-edge"):
        cm.cam.cutter_path(knife, 0.005)


def test_the_cam_command_writes_the_cutter_path(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    out = tmp_path / "o"
    args = ["cam", str(ROOT / "examples" / "lifter_cam.toml"), "--out", str(out), "--no-plot"]
    assert main([*args, "--tool-radius-mm", "12"]) == 0
    with (out / "profile.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    # 12 mm is the file's roller: the cutter runs on the pitch curve.
    for r in rows[::100]:
        assert float(r["cutter_x_m"]) == pytest.approx(float(r["pitch_x_m"]), abs=1e-12)
    doc = ezdxf.readfile(out / "profile.dxf")
    assert len(doc.modelspace().query("LWPOLYLINE[layer=='CUTTER']")) == 1
    assert len(doc.modelspace().query("LWPOLYLINE[layer=='CUTTER_OUTER']")) == 1  # a groove


def test_a_machine_files_tool_radius_reaches_the_parts(tmp_path):
    text = (ROOT / "examples" / "stb_loom.toml").read_text("utf-8")
    text = text.replace('kind = "cam"\n', 'kind = "cam"\ntool_radius_m = 0.008\n', 1)
    path = tmp_path / "loom.toml"
    path.write_text(text, encoding="utf-8")
    assert tomllib.loads(text)["mechanism"]["lifter cam"]["tool_radius_m"] == 0.008
    # The report's writer, as `cyclomech run` calls it (the run's sensitivities,
    # 12 of its 14 CPU-s, write no part; test_parts_export runs the command).
    out = tmp_path / "o"
    m = cm.Machine.from_toml(path)
    cm.machine.write_report(cm.machine.analyze(m, progress=False), out, figures=False)
    with (out / "lifter_cam_profile.csv").open(newline="", encoding="utf-8") as f:
        header = next(csv.reader(f))
    assert {"cutter_x_m", "cutter_y_m", "outer_cutter_x_m", "outer_cutter_y_m"} <= set(header)


def test_a_knife_edge_with_a_tool_radius_is_refused_by_key():
    table = {
        "follower": "translating", "base_radius_m": 0.05, "roller_radius_m": 0.0,
        "tool_radius_m": 0.005,
        "segment": [{"kind": "rise", "angle_deg": 180, "stroke_m": 0.02},
                    {"kind": "return", "angle_deg": 180, "stroke_m": 0.02}],
    }  # fmt: skip
    with pytest.raises(cm.InputError, match=r"\[cam\].*knife-edge"):
        cm.cam.CamDesign.from_table(table, "[cam]")
