"""The loom example with its lifter cam (issue 18, item 7): the machine's optimum and
speed limit against an LP built here with scipy's linprog from the file (parsed by
tomllib) and the bounds the cam and stop APIs report, and the cam's place in the
report, results.json and a pickle (Dask ships machines)."""

from __future__ import annotations

import math
import pickle
import tomllib
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from scipy.optimize import linprog

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"


def data() -> dict:
    with LOOM.open("rb") as f:
        return tomllib.load(f)


def cam_design() -> cm.cam.CamDesign:
    table = data()["mechanism"]["lifter cam"]
    return cm.cam.CamDesign.from_table(
        table, "[lifter cam]", extra=frozenset({"kind", "friction"}), arcs=True
    )


def linprog_limiting(rpm: float) -> tuple[float, dict[tuple[str, str], float]]:
    """The weft insertion's largest angle at ``rpm`` by an LP over event angles
    p ≥ 0 written here: p(y) − p(x) ≥ each operation's minimum (its angle, or 6·n·its
    duration), ≤ its maximum, every p ≤ 360; plus the cam's bounds (the largest over
    its criteria, from `CamDesign.min_phase_angles`) and the stop's (from
    `CamStop.min_phase_deg`) on their arcs. NaN where it does not fit."""
    d = data()
    events = d["cyclogram"]["events"]
    ix = {e: i for i, e in enumerate(events)}
    mins: dict[tuple[str, str], float] = {}
    maxs: dict[tuple[str, str], float] = {}
    for op in d["operation"]:
        arc = (op["from"], op["to"])
        mins[arc] = max(op["min_angle_deg"], 6.0 * rpm * op.get("min_duration_s", 0.0))
        if "max_angle_deg" in op:
            maxs[arc] = op["max_angle_deg"]
    design = cam_design()
    m = design.min_phase_angles([rpm])
    for j, k in enumerate(m.segments):
        arc = design.arcs[k]
        if arc is not None:
            mins[arc] = max(mins[arc], float(np.max(m.angle_deg[0, j])))
    stop = cm.Machine.from_toml(LOOM).mechanisms["lifter"]
    mins[stop.arc] = max(mins[stop.arc], float(stop.min_phase_deg(rpm)))
    if any(not math.isfinite(v) for v in mins.values()):
        return math.nan, mins
    A, b = [], []
    for arc, v in mins.items():
        row = np.zeros(len(events))
        row[ix[arc[0]]], row[ix[arc[1]]] = 1.0, -1.0  # p(x) − p(y) ≤ −min
        A.append(row)
        b.append(-v)
    for arc, v in maxs.items():
        row = np.zeros(len(events))
        row[ix[arc[0]]], row[ix[arc[1]]] = -1.0, 1.0
        A.append(row)
        b.append(v)
    c = np.zeros(len(events))
    lim = d["cyclogram"]["limiting"]
    c[ix[lim[0]]], c[ix[lim[1]]] = 1.0, -1.0  # maximise p(10.2) − p(10.1)
    res = linprog(c, A_ub=np.array(A), b_ub=np.array(b), bounds=[(0.0, 360.0)] * len(events))
    return (-res.fun if res.status == 0 else math.nan), mins


@pytest.mark.parametrize("rpm", [200.0, 300.0, 380.0, 415.0, 420.3])
def test_loom_optimum_with_cam_bounds_equals_linprog(rpm):
    m = cm.Machine.from_toml(LOOM)
    ref, _ = linprog_limiting(rpm)
    got = m.optimize(rpm).objective
    assert got == pytest.approx(ref, abs=1e-7)


def test_above_the_limit_the_machine_and_linprog_both_refuse():
    assert math.isnan(linprog_limiting(430.0)[0])
    with pytest.raises(cm.InfeasibleError, match="σ_H"):
        cm.Machine.from_toml(LOOM).optimize(430.0)


def test_the_cam_stop_takes_its_law_and_stroke_from_the_cam():
    m = cm.Machine.from_toml(LOOM)
    stop, design = m.mechanisms["lifter"].stop, cam_design()
    k = design.arcs.index(("3", "7"))
    seg = design.cam.segments[k]
    assert stop.law.name == seg.law
    lever = data()["mechanism"]["lifter"]["lever_length_m"]
    assert stop.stroke == pytest.approx(seg.stroke * lever, rel=1e-15)
    assert stop.stroke == pytest.approx(0.0094, rel=1e-9)


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (('cam = "lifter cam"', 'cam = "lifter"'), "is not a cam of the machine"),
        (('cam = "lifter cam"', 'cam = "lifter cam"\nlaw = "cycloidal"'), "law comes from the cam"),
        (('arc = ["3", "7"]\n\n[[mech', 'arc = ["3", "8"]\n\n[[mech'), "has no segment bound"),
    ],
)
def test_bad_cam_stops_are_named(tmp_path, edit, needle):
    text = LOOM.read_text(encoding="utf-8")
    assert edit[0] in text
    text = text.replace(*edit, 1)
    p = tmp_path / "bad.toml"
    p.write_text(text, encoding="utf-8")
    with pytest.raises(cm.CyclomechError) as e:
        cm.Machine.from_toml(p)
    assert isinstance(e.value, ValueError)
    assert needle in str(e.value)


def test_loom_speed_limit_is_where_linprog_stops_fitting_and_names_the_cam():
    lim = cm.Machine.from_toml(LOOM).speed_limit()
    n = lim.rpm
    assert math.isfinite(linprog_limiting(n * (1 - 1e-6))[0])
    assert math.isnan(linprog_limiting(n * (1 + 1e-6))[0])
    # The cam's criteria bind at the limit, by their labels, in the reason.
    for label in ("vibration[lifter cam rise 1→3]", "σ_H[lifter cam return 7→10.1]"):
        assert label in lim.binding and label in lim.reason


def test_the_cam_bounds_are_its_criteria_and_grow_with_speed():
    cam = cm.Machine.from_toml(LOOM).mechanisms["lifter cam"]
    design = cam_design()
    n = np.linspace(200.0, 500.0, 31)
    m = design.min_phase_angles(n)
    for b, law, (k, c) in zip(cam.bounds(), cam.laws(), cam.criteria, strict=True):
        j = m.segments.index(k)
        np.testing.assert_allclose(law(n), m.angle_deg[:, j, cm.cam.CRITERIA.index(c)], rtol=1e-12)
        assert b.arc == design.arcs[k]
    # The stress grows with speed where it binds above the undercut (0 below:
    # there the undercut binds); the vibration bound in proportion to speed.
    for law, (_, c) in zip(cam.laws(), cam.criteria, strict=True):
        v = law(n)
        if c == "contact_stress":
            on = v > 0
            assert on[-1] and np.all(on[np.argmax(on) :]) and np.all(np.diff(v[on]) > 0)
        if c == "vibration":
            np.testing.assert_allclose(v, v[0] * n / n[0], rtol=1e-12)


def test_the_loom_report_has_the_cam(cli_run):
    run = cli_run(LOOM, "--no-plot", "--quiet")
    out = run.out
    assert run.code == 0
    import json

    r = json.loads((out / "results.json").read_text(encoding="utf-8"))
    cam = r["cams"]["lifter cam"]
    assert cam["closure"] == "groove"
    assert cam["max_stress_pa"] < cam["limit_stress_pa"]
    # At the optimum the bound segments take their operations' angles.
    angles = r["optimum"]["angles_deg"]
    assert cam["segment_angles_deg"][0] == pytest.approx(angles["1→3"], abs=1e-9)
    assert cam["segment_angles_deg"][2] == pytest.approx(angles["7→10.1"], abs=1e-9)
    assert sum(cam["segment_angles_deg"]) == pytest.approx(360.0, abs=1e-9)
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "lifter cam" in page and "largest Hertz stress" in page


def test_a_machine_with_a_cam_pickles():
    m = cm.Machine.from_toml(LOOM)
    again = pickle.loads(pickle.dumps(m))
    assert again.speed_limit().rpm == pytest.approx(m.speed_limit().rpm, rel=1e-12)


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (('arc = ["1", "3"]', 'arc = ["1", "9"]'), "is not an operation of the cyclogram"),
        (('law = "modified_sine"\nload_nm', 'law = "sine"\nload_nm'), "unknown law"),
        (("cam_poisson", "cam_poisson = 0.5\nx"), None),
        (("width_m = 0.008", "width_m = -0.008"), "width"),
        (
            (
                'stroke_deg = 12.0\nlaw = "modified_sine"\nload_nm',
                'stroke_m = 0.01\nlaw = "modified_sine"\nload_nm',
            ),
            "stroke_m",
        ),
        (("angle_deg = 180.0", "angle_deg = 170.0"), "not 360°"),
    ],
)
def test_bad_cam_tables_are_named(tmp_path, edit, needle):
    text = LOOM.read_text(encoding="utf-8")
    old, new = edit
    if old == "cam_poisson":  # an unknown key in the cam's table
        text = text.replace(
            "max_pressure_angle_deg = 45.0", "max_pressure_angle_deg = 45.0\npoisson_cam = 0.3"
        )
        needle = "poisson_cam"
    else:
        assert old in text
        text = text.replace(old, new, 1)
    p = tmp_path / "bad.toml"
    p.write_text(text, encoding="utf-8")
    with pytest.raises(cm.CyclomechError, match=None) as e:
        cm.Machine.from_toml(p)
    assert isinstance(e.value, ValueError)
    assert needle in str(e.value)
    assert "lifter cam" in str(e.value)


def test_the_main_shaft_carries_the_cams_torque_at_its_phase():
    """The loom's main shaft (issue 19): the lifter cam's torque at its phase in the
    optimum. Its mean is the work of the rise's load per turn, F·h/(2π) (h the arm
    rotation: the inertia and the groove do no work over a turn); at each cycle
    angle θ the torque is the cam's own (Cam.loads) at cam angle θ − phase, where
    the phase puts the lift's start at its operation's start. Without its friction
    table (friction's torque is tested in tests/cam/test_cam_friction.py)."""
    d = data()
    del d["mechanism"]["lifter cam"]["friction"]
    m = cm.Machine.from_dict(d, str(LOOM))
    r = cm.machine.analyze(m, progress=False)
    sh = r.shaft
    assert list(sh.parts) == ["lifter cam"]
    load = data()["mechanism"]["lifter cam"]["segment"][0]["load_nm"]
    h = math.radians(data()["mechanism"]["lifter cam"]["segment"][0]["stroke_deg"])
    # (the samples' mean: 3600 over the turn, ~270 on the lift)
    assert float(sh.at_nominal.mean_torque_nm) == pytest.approx(load * h / (2 * math.pi), rel=1e-5)
    res = r.mechanisms["lifter cam"]
    cam, design = res.cam, res.mech.design
    start = r.optimum.times["1"]
    theta = np.radians(sh.torque.theta_deg)
    ref = cam.loads(theta - math.radians(start), r.nominal_rpm, design.loads).shaft_torque
    np.testing.assert_allclose(
        sh.torque.at(r.nominal_rpm), ref, rtol=1e-6, atol=1e-6 * np.abs(ref).max()
    )
    # The flywheel by the energy method, and the motor's power, at every sweep speed.
    o = sh.over_speed
    w = o.rpm * 2 * math.pi / 60
    np.testing.assert_allclose(o.flywheel_kg_m2, o.energy_fluctuation_j / (w**2 * 0.05), rtol=1e-12)
    np.testing.assert_allclose(o.power_w, o.mean_torque_nm * w, rtol=1e-12)


def test_the_main_shaft_in_the_report_and_only_where_a_mechanism_gives_torque(cli_run):
    import json

    run = cli_run(LOOM, "--no-plot", "--quiet")
    out = run.out
    assert run.code == 0
    r = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert r["shaft"]["contributors"] == ["lifter cam"] and r["shaft"]["speed_fluctuation"] == 0.05
    assert "Main shaft" in (out / "report.html").read_text(encoding="utf-8")
    rotor = ROOT / "examples" / "rotor_line.toml"
    assert cm.machine.analyze(cm.Machine.from_toml(rotor), progress=False).shaft is None


@pytest.mark.parametrize("value", [0.0, 1.0, -0.1, "0.05"])
def test_a_bad_speed_fluctuation_is_named(tmp_path, value):
    text = LOOM.read_text(encoding="utf-8").replace(
        "nominal_rpm = 300.0",
        f"nominal_rpm = 300.0\nspeed_fluctuation = {value!r}".replace("'", '"'),
    )
    p = tmp_path / "bad.toml"
    p.write_text(text, encoding="utf-8")
    with pytest.raises(cm.CyclomechError, match="speed_fluctuation"):
        cm.Machine.from_toml(p)


def test_a_free_segment_that_fails_at_the_nominal_speed_is_loud(tmp_path):
    """The bound segments hold their criteria by construction; a free one need
    not: the loom's lift made free and squeezed into 10° fails its pressure angle
    at 300 rpm, and the machine warns, naming the cam and the criterion."""
    text = LOOM.read_text(encoding="utf-8")
    old = "angle_deg = 70.0                 # the file's angle; the cyclogram's optimum sets it"
    assert old in text
    text = text.replace(old, "angle_deg = 10.0", 1)
    text = text.replace(
        "load_nm = 2.0                    # the microshuttle's drag, resisting the lift\n"
        'arc = ["1", "3"]',
        "load_nm = 2.0",
        1,
    )
    text = text.replace("angle_deg = 180.0", "angle_deg = 240.0", 1)
    p = tmp_path / "free.toml"
    p.write_text(text, encoding="utf-8")
    m = cm.Machine.from_toml(p)
    assert m.mechanisms["lifter cam"].design.arcs[0] is None
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", cm.CyclomechWarning)
        r = cm.machine.analyze(m, progress=False)
    said = [str(w.message) for w in caught]
    assert any("cam 'lifter cam' at 300 rpm: the pressure angle" in w for w in said), said
    # Geometry alone fails it: the cam's own limit is 0 (the machine works at no
    # speed), and at the nominal the check is a failure (exit 3), not a warning only.
    assert any("speed limit of mechanism 'lifter cam', 0.00 rpm" in w for w in said), said
    assert r.limit.rpm == 0.0 and r.limit.by == "lifter cam"
    assert "segment 1 (rise, 10°, no arc): the pressure angle" in r.limit.reason
    assert r.mechanisms["lifter cam"].problems()
    assert any(f.startswith("lifter cam: the pressure angle reaches") for f in r.failures)
    # The loom as it is: nothing to say.

    with warnings.catch_warnings():
        warnings.simplefilter("error", cm.CyclomechWarning)
        cm.machine.analyze(cm.Machine.from_toml(LOOM), progress=False)


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ('point = "E"  ', 'point = "A"  ', "ground joint"),
        (
            '[[mechanism.knife.mass]]\nlink = ["A", "B"]',
            '[[mechanism.knife.mass]]\nlink = ["C", "E", "B"]',
            "has a mass already",
        ),
    ],
)
def test_knife_file_mistakes_that_would_be_silent(tmp_path, old, new, match):
    text = (ROOT / "examples" / "knife_cutter.toml").read_text("utf-8")
    assert old in text
    path = tmp_path / "k.toml"
    path.write_text(text.replace(old, new, 1), "utf-8")
    with pytest.raises(cm.CyclomechError, match=match):
        cm.Machine.from_toml(path)
