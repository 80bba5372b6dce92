"""The machine moving: each frame at the main shaft's angle θ places every point
where the mechanism's solver puts it at θ, checked against what the file and the
optimum say independently of the scene code — a linkage's crank angle from its
``phase`` table, a cam's lift from its segments' strokes at the optimum's event
times and the roller touching the turned profile, a press's BDC (the slider's
lowest point over a dense turn) at its event, a servo axis's position at its
arc's events, a transfer's workpieces on the path at the time the speed law
gives (scipy's quad). The report's player carries the same numbers; the GIF and
one frame are drawn from them."""

from __future__ import annotations

import itertools
import json
import math
import re
import tomllib
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine import Body, Scene

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"


@pytest.fixture(scope="module")
def results():
    """Each example analysed once (the tests only read them)."""
    out = {}

    def get(name: str):
        if name not in out:
            m = cm.Machine.from_toml(EX / f"{name}.toml")
            out[name] = cm.machine.analyze(m, progress=False)
        return out[name]

    return get


def _toml(name: str) -> dict:
    return tomllib.loads((EX / f"{name}.toml").read_text(encoding="utf-8"))


def test_a_linkage_frame_is_the_linkage_solved_at_its_phase(results):
    r = results("knife_cutter")
    phase = _toml("knife_cutter")["mechanism"]["knife"]["phase"]
    theta = np.linspace(0.0, 360.0, 73)[:-1]
    s = r.mechanisms["knife"].scene(theta)
    # crank_deg at the event: the crank turns with the main shaft, once a cycle
    phi = np.radians(phase["crank_deg"] + theta - r.optimum.times[phase["event"]])
    lk = r.machine.mechanisms["knife"].linkage
    sol = lk.solve(phi, analogs=False)
    assert sol.ok.all()
    for p in lk.names:
        np.testing.assert_allclose(s.points[p], sol.xy[:, sol.index(p)], rtol=0, atol=1e-12)
    # every bar keeps its length over the cycle (a rigid drawing)
    for ln in s.links:
        for a, b in itertools.pairwise(ln):
            d = np.hypot(*(s.points[a] - s.points[b]).T)
            assert np.ptp(d) <= 1e-9 * d.max(), (a, b)
    assert s.ground == ("A", "D", "O") and s.traces == ("E",)


def _lift_translating(s: Scene, rb: float, rr: float) -> np.ndarray:
    """A radial translating roller's lift [m] from the scene: the roller centre's
    height above the base circle plus the roller."""
    xy = s.points["follower"]
    np.testing.assert_allclose(xy[:, 0], 0.0, atol=1e-12)  # on its axis
    return xy[:, 1] - (rb + rr)


def test_a_cam_frame_lifts_the_follower_by_its_law_at_the_optimum_events(results):
    r = results("flow_wrapper")
    t = r.optimum.times
    table = _toml("flow_wrapper")["mechanism"]["pusher"]
    rb, rr = table["base_radius_m"], table["roller_radius_m"]
    h = table["segment"][0]["stroke_m"]
    # rise 1→2 (modified sine), return 2→4 (cycloidal): both symmetric, h/2 mid-way
    at = np.array(
        [t["1"], 0.5 * (t["1"] + t["2"]), t["2"], 0.5 * (t["2"] + t["4"]), t["4"], t["4"] + 30.0]
    )
    s = r.mechanisms["pusher"].scene(at % 360.0)
    np.testing.assert_allclose(
        _lift_translating(s, rb, rr), [0.0, h / 2, h, h / 2, 0.0, 0.0], rtol=0, atol=1e-9
    )


@pytest.mark.parametrize(
    ("example", "name"),
    [("flow_wrapper", "pusher"), ("stb_loom", "lifter cam"), ("flow_wrapper", "folding arm")],
)
def test_the_roller_touches_the_turned_profile_at_every_frame(results, example, name):
    r = results(example)
    res = r.mechanisms[name]
    theta = np.arange(0.0, 360.0, 7.5)
    s = res.scene(theta)
    rr = res.cam.follower.roller_radius
    grid = np.linspace(0.0, 2.0 * math.pi, 14401)[:-1]  # 0.025° apart
    k = res.cam.solve(grid)
    flanks = [np.asarray(k.profile)]
    if k.profile_outer is not None:
        flanks.append(np.asarray(k.profile_outer))
    for i, th in enumerate(theta):
        a = s.bodies["cam"].pose[i, 2]  # the cam's angle at this frame
        c, si = math.cos(a), math.sin(a)
        centre = s.points["follower"][i]
        gap = min(
            float(np.min(np.hypot(*(f @ np.array([[c, si], [-si, c]]) - centre).T))) for f in flanks
        )
        assert gap == pytest.approx(rr, abs=2e-6), (th, gap, rr)


def test_a_press_frame_is_at_bdc_at_its_event(results):
    r = results("extrusion_press_line")
    res = r.mechanisms["drive"]
    press = r.machine.mechanisms["drive"].press
    bottom = r.optimum.times["bottom"]  # phase = {event = "bottom", crank_deg = 0}
    s = res.scene(np.array([bottom - 5.0, bottom, bottom + 5.0]) % 360.0)
    dense = press.solve(np.linspace(0.0, 2.0 * math.pi, 72001))
    lowest = float(np.nanmin(dense.slider[:, 1]))
    y = s.points["B"][:, 1]
    assert y[1] == pytest.approx(lowest, abs=1e-9)
    assert y[0] > y[1] and y[2] > y[1]
    # the rod and the carrier keep their lengths
    np.testing.assert_allclose(np.hypot(*(s.points["P"] - s.points["B"]).T), press.L, rtol=1e-12)
    np.testing.assert_allclose(np.hypot(*s.points["C"].T), press.R - press.r, rtol=1e-12)


def test_a_servo_frame_is_the_program_at_its_arc_events(results):
    r = results("flow_wrapper")
    t = r.optimum.times
    seg = _toml("flow_wrapper")["mechanism"]["film feed"]["segment"]
    index = seg[0]["stroke_m"]
    dwell = seg[1]["angle_deg"]
    at = np.array([t["2"], t["3"], t["3"] + 0.5 * dwell, t["2"] + 359.999]) % 360.0
    s = r.mechanisms["film feed"].scene(at)
    x = s.points["load"][:, 0]
    # from rest at "2", the index's stroke at "3", held through the dwell, and the
    # whole advance (one bag) at the end of the cycle
    np.testing.assert_allclose(x[:3], [0.0, index, index], rtol=0, atol=1e-12)
    assert x[3] == pytest.approx(0.25, abs=1e-6)
    # a rotary axis: the pointer turns by the program's angle, its disc with it
    jaw = r.mechanisms["jaw"].scene(at)
    ang = np.arctan2(jaw.points["tip"][:, 1], jaw.points["tip"][:, 0])
    np.testing.assert_allclose(np.cos(ang - jaw.bodies["disc"].pose[:, 2]), 1.0, atol=1e-12)


def test_transfer_workpieces_ride_the_path_at_the_time_the_speed_law_gives(results):
    from scipy.integrate import quad

    r = results("rotor_line")
    res = r.mechanisms["line"]
    path = res.mech.path
    theta = np.array([0.0, 45.0, 130.0, 275.0])
    s = res.scene(theta)
    dense = path.sample(200_001)
    law = path.speed_law(res.speeds)
    n = r.nominal_rpm
    seen = 0
    for name, xy in s.points.items():
        if not name.startswith("w"):
            continue
        j = int(name[1:]) - 1
        for i in np.flatnonzero(np.isfinite(xy[:, 0])):
            d = np.hypot(*(dense.points - xy[i]).T)
            k = int(np.argmin(d))
            assert d[k] < 1e-5  # on the path
            cycles, _ = quad(lambda u: 1.0 / float(law(u)[0]), 0.0, dense.s[k], limit=200)
            assert cycles * n / 60.0 == pytest.approx(theta[i] / 360.0 + j, abs=2e-5)
            seen += 1
    assert seen >= len(theta)


def test_the_report_plays_the_same_frames(results, tmp_path):
    r = results("knife_cutter")
    cm.machine.write_report(r, tmp_path, figures=False)
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "<h2>The machine moving</h2>" in page and "cm-play" in page
    assert "http" not in re.search(r"<script>(.*?)</script>", page, re.S).group(1)
    raw = re.search(r"id='cm-anim-data'>(.*?)</script>", page, re.S).group(1)
    data = json.loads(raw)
    theta, scenes = r.scenes()
    assert data["theta"] == pytest.approx(theta.tolist()) and len(theta) == 120
    (knife,) = data["scenes"]
    e = np.array(knife["points"]["E"], dtype=float).reshape(-1, 2)
    np.testing.assert_allclose(e, 1e3 * scenes["knife"].points["E"], atol=6e-5)  # mm, 4 places
    assert [op["row"] for op in data["timeline"]["ops"]] and data["timeline"]["cycle"] == 360.0


def test_a_machine_without_an_optimum_says_why_nothing_moves(tmp_path):
    text = (EX / "stb_loom.toml").read_text(encoding="utf-8")
    fast = tmp_path / "fast.toml"
    fast.write_text(text.replace("nominal_rpm = 300.0", "nominal_rpm = 450.0"), encoding="utf-8")
    r = cm.machine.analyze(cm.Machine.from_toml(fast), progress=False)
    assert r.optimum is None
    assert r.scenes(4)[1] == {}
    cm.machine.write_report(r, tmp_path / "out", figures=False)
    page = (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    assert "the mechanisms have no timing to move by" in page and "cm-anim-data" not in page
    from cyclomech.machine.plot import animate_machine

    with pytest.raises(cm.CyclomechError, match="does not fit at the nominal speed"):
        animate_machine(r, tmp_path / "m.gif")


def test_one_frame_draws_the_scene_at_its_angle(results):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from cyclomech.machine.plot import plot_machine_frame

    r = results("knife_cutter")
    fig = plot_machine_frame(r, 123.0)
    try:
        (cursor,) = [a for ax in fig.axes for a in ax.lines if a.get_gid() == "cursor"]
        assert list(cursor.get_xdata()) == [123.0, 123.0]
        assert cursor.axes.get_title() == "main shaft at θ = 123.0°"
        ax = next(a for a in fig.axes if a.get_title() == "knife")
        joints = ax.lines[-1].get_xydata()
        s = r.mechanisms["knife"].scene(np.array([123.0]))
        want = 1e3 * np.array([s.points[p][0] for p in s.points])
        np.testing.assert_allclose(joints, want, rtol=1e-12)
    finally:
        plt.close(fig)
    with pytest.raises(cm.CyclomechError, match=r"cycle_deg = 360.0 must be in \[0, 360\)"):
        plot_machine_frame(r, 360.0)


def test_the_gif_has_a_frame_per_angle_and_refuses_bad_arguments(results, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from cyclomech.machine.plot import animate_machine
    from PIL import Image

    r = results("extrusion_press_line")
    gif = animate_machine(r, tmp_path / "press.gif", frames=5, dpi=30)
    with Image.open(gif) as im:
        assert im.n_frames == 5
        first = np.asarray(im.convert("RGB"))
        im.seek(2)
        assert not np.array_equal(first, np.asarray(im.convert("RGB")))  # it moves
    for kw, msg in [
        ({"path": tmp_path / "m.png"}, "must end in .gif"),
        ({"frames": 1}, "frames must be an integer ≥ 2"),
        ({"fps": 0.0}, "fps"),
        ({"dpi": -1.0}, "dpi"),
    ]:
        args = {"path": tmp_path / "m.gif", **kw}
        with pytest.raises(cm.CyclomechError, match=msg):
            animate_machine(r, args.pop("path"), **args)


def test_run_animate_writes_the_gif(tmp_path, capsys, monkeypatch):
    import cyclomech.machine.cli as machine_cli

    monkeypatch.setattr(machine_cli, "GIF_FRAMES", 6)  # the CLI's 90 take seconds
    out = tmp_path / "out"
    argv = ["run", str(EX / "rotor_line.toml"), "--out", str(out), "--quiet", "--no-plot"]
    assert main([*argv, "--animate"]) == 0
    assert f"Animation: {out / 'machine.gif'}" in capsys.readouterr().out
    from PIL import Image

    with Image.open(out / "machine.gif") as im:
        assert im.n_frames == 6


def test_a_scene_refuses_inconsistent_data():
    two = np.zeros((2, 2))
    with pytest.raises(cm.CyclomechError, match=r"unknown points \['B'\]"):
        Scene("x", {"A": two}, links=(("A", "B"),))
    with pytest.raises(cm.CyclomechError, match="disagree on the frames"):
        Scene("x", {"A": two}, bodies={"b": Body(two, np.zeros((3, 3)))})
    with pytest.raises(cm.CyclomechError, match="frames"):
        results_free = cm.machine.analyze(cm.Machine.example(), progress=False)
        results_free.scenes(1)


def test_a_stop_frame_drives_the_lever_by_its_law_until_the_stop_holds_it(results):
    r = results("stb_loom")
    o = r.optimum
    mech = r.machine.mechanisms["lifter"]
    st, (a, b) = mech.stop, mech.arc
    start, span = o.times[a], o.angles[(a, b)]
    u = np.linspace(0.0, 1.0, 41)
    theta = np.concatenate([start + span * u, [start + span + 5.0, start - 5.0]]) % 360.0
    s = r.mechanisms["lifter"].scene(theta)
    w = s.points["W"]
    length = np.hypot(*w[0])
    travel = length * np.arctan2(w[:, 1], w[:, 0])  # W's arc from the rest position
    z = cm.motion.law(st.law.name, form="rise").z(u)  # the law, from the motion module
    want = np.minimum(st.stroke * z, st.stroke - st.preload)
    np.testing.assert_allclose(travel[:41], want, rtol=0, atol=1e-12)
    assert travel[40] == pytest.approx(st.stroke - st.preload)  # held at the stop
    assert np.isnan(w[41:]).all()  # outside its operation: not drawn
    # the stop sits where the working point meets it, in every frame
    stop = s.bodies["stop"].at(0)
    assert float(np.min(np.hypot(*(stop - w[40]).T))) < 0.05 * length
