"""A cam's rises and returns that no operation times (no ``arc``) set the cam's own
speed limit, and a check that fails at every speed makes the machine work at no
speed; a cam sized at its ``max_base_radius_m`` says so. Machine files are built in
``tmp_path`` from the examples, each against a closed form of its own."""

from __future__ import annotations

import json
import math
import re
import shutil
import warnings
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[2]
FLOW = ROOT / "examples" / "flow_wrapper.toml"
SIZED = ROOT / "examples" / "lifter_cam_sized.toml"


def _edit(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


def _flow(tmp_path: Path, *, nominal: float = 100.0, weak: bool, pa_limit: float = 40.0) -> Path:
    """flow_wrapper.toml with the pusher's spring weakened and its return unbound
    (``weak``), or the folding arm's return unbound with [α] = ``pa_limit``."""
    t = FLOW.read_text("utf-8")
    t = _edit(t, "nominal_rpm = 100.0", f"nominal_rpm = {nominal!r}")
    if weak:
        t = _edit(t, "spring_rate_n_per_m = 4000.0", "spring_rate_n_per_m = 200.0")
        t = _edit(t, "preload_n = 150.0", "preload_n = 5.0")
        t = _edit(t, 'law = "cycloidal"\narc = ["2", "4"]\n', 'law = "cycloidal"\n')
    else:
        t = _edit(t, "max_pressure_angle_deg = 40.0", f"max_pressure_angle_deg = {pa_limit!r}")
        t = _edit(t, 'law = "cycloidal"\narc = ["3", "4"]\n', 'law = "cycloidal"\n')
    shutil.copy(ROOT / "examples" / "motors.csv", tmp_path / "motors.csv")
    path = tmp_path / f"flow_{'jump' if weak else 'pa'}_{nominal:g}.toml"
    path.write_text(t, "utf-8")
    return path


def _run(path: Path, out: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    code = main(["run", str(path), "--out", str(out), "--no-plot", "--quiet"])
    cap = capsys.readouterr()
    return code, cap.out + cap.err


def _jump_rpm_closed_form() -> float:
    """The pusher's cycloidal return (h = 0.06 m over β = 100°, from the top) on a
    spring k = 200 N/m, F₀ = 5 N, m = 2.5 kg: the largest ω at which
    m·s″·ω² + k·s + F₀ ≥ 0 on a dense grid (s″ per rad² of cam), by brentq on ω."""
    h, beta, m, k, f0 = 0.06, math.radians(100.0), 2.5, 200.0, 5.0
    x = np.linspace(0.0, 1.0, 400_001)
    s = h * (1.0 - x + np.sin(2 * np.pi * x) / (2 * np.pi))
    s2 = -h * 2 * np.pi * np.sin(2 * np.pi * x) / beta**2
    w = brentq(lambda w: float(np.min(m * s2 * w * w + k * s + f0)), 1e-6, 100.0, xtol=1e-14)
    return w * 30.0 / math.pi


def test_unbound_return_sets_the_cams_own_limit_at_its_jump_speed(tmp_path: Path) -> None:
    """The return keeps its 100°, so its jump speed is the cam's own limit, and the
    machine's: the closed form, not the cyclogram's 107.48 rpm it used to report."""
    ref = _jump_rpm_closed_form()
    m = cm.Machine.from_toml(_flow(tmp_path, weak=True))
    pusher = m.mechanisms["pusher"]
    assert pusher.speed_limit_rpm() == pytest.approx(ref, rel=1e-7)
    assert pusher.limit_reason().startswith(
        f"cam 'pusher' segment 2 (return, 100°, no arc): the follower leaves the cam "
        f"above {ref:.2f} rpm"
    )
    lim = m.speed_limit()
    assert lim.by == "pusher" and lim.rpm == pytest.approx(ref, rel=1e-7)
    assert lim.cyclogram_rpm > ref  # the cyclogram alone would allow more
    assert m.mechanisms["folding arm"].speed_limit_rpm() == math.inf  # all bound


def test_run_above_the_jump_speed_exits_3_naming_the_cam(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    ref = _jump_rpm_closed_form()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cm.CyclomechWarning)
        code, text = _run(_flow(tmp_path, weak=True), tmp_path / "out", capsys)
    assert code == 3
    assert f"above the speed limit of mechanism 'pusher', {ref:.2f} rpm" in text
    doc = json.loads((tmp_path / "out" / "results.json").read_text("utf-8"))
    assert doc["speed_limit"]["by"] == "pusher"
    assert doc["speed_limit"]["rpm"] == pytest.approx(ref, rel=1e-7)
    assert "speed limit of mechanism 'pusher'" in doc["above_speed_limit"]
    # At the nominal the cam's own check fails too: the report's summary says it.
    assert "pusher: the follower jumps off the cam above" in (
        tmp_path / "out" / "report.html"
    ).read_text("utf-8")


def test_run_below_the_jump_speed_is_not_held_back(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """At 60 rpm (below the 68.19 rpm jump speed) nothing fails: the limit is no
    stricter than the closed form."""
    code, text = _run(_flow(tmp_path, nominal=60.0, weak=True), tmp_path / "out", capsys)
    assert code == 0, text
    assert "jumps" not in text


def _pressure_angle_closed_form(beta_deg: float) -> float:
    """The folding arm's cycloidal return (25° over ``beta_deg``) from the pivot's
    geometry (d = 0.12 m, l = 0.09 m, R_b + r = 0.062 m), the cam turning
    counter-clockwise: the largest angle [deg] between the pitch curve's normal and
    the roller centre's path (perpendicular to the arm), on a dense grid."""
    d, arm, r0 = 0.12, 0.09, 0.062
    big, beta = math.radians(25.0), math.radians(beta_deg)
    psi0 = math.acos((d * d + arm * arm - r0 * r0) / (2 * d * arm))
    x = np.linspace(0.0, 1.0, 200_001)
    phi = psi0 + big * (1.0 - x + np.sin(2 * np.pi * x) / (2 * np.pi))
    dpsi = -big / beta * (1.0 - np.cos(2 * np.pi * x))
    cx, cy = d - arm * np.cos(phi), arm * np.sin(phi)
    # The pitch curve's tangent in the ground frame: C′(θ) − J·C (J: +90°).
    tx, ty = arm * np.sin(phi) * dpsi + cy, arm * np.cos(phi) * dpsi - cx
    ux, uy = np.sin(phi), np.cos(phi)
    cos_a = np.abs(tx * uy - ty * ux) / np.hypot(tx, ty)
    return float(np.degrees(np.arccos(np.clip(cos_a, 0.0, 1.0))).max())


def test_pressure_angle_failing_at_every_speed_exits_3(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The folding arm's unbound 60° return reaches 44.5° > [α] = 30° whatever the
    speed: the machine works at no speed (exit 3), the reason names the segment,
    the angle it reaches and the angle it needs, both against the closed-form
    geometry."""
    path = _flow(tmp_path, weak=False, pa_limit=30.0)
    m = cm.Machine.from_toml(path)
    arm = m.mechanisms["folding arm"]
    assert arm.speed_limit_rpm() == 0.0
    why = arm.limit_reason()
    assert why.startswith("cam 'folding arm' segment 2 (return, 60°, no arc): the pressure angle")
    got = re.search(r"reaches ([0-9.]+)° > \[α\] = 30° at every speed \(it needs ([0-9.]+)°\)", why)
    assert got is not None, why
    assert float(got[1]) == pytest.approx(_pressure_angle_closed_form(60.0), abs=0.006)
    need = brentq(lambda b: _pressure_angle_closed_form(b) - 30.0, 61.0, 300.0, xtol=1e-6)
    assert float(got[2]) == pytest.approx(need, abs=0.06)  # printed to 4 digits
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cm.CyclomechWarning)
        code, text = _run(path, tmp_path / "out", capsys)
    assert code == 3
    assert "The machine works at no speed: cam 'folding arm' segment 2" in text
    doc = json.loads((tmp_path / "out" / "results.json").read_text("utf-8"))
    assert doc["speed_limit"]["rpm"] == 0.0 and doc["speed_limit"]["by"] == "folding arm"
    assert "pressure angle reaches" in doc["speed_limit"]["reason"]


def test_sized_at_the_upper_bound_says_so(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """lifter_cam_sized with max_base_radius_m = 35 mm: the radius is the bound (the
    example's own fixed point is 40.6 mm, above it), the status at_upper_bound."""
    t = _edit(SIZED.read_text("utf-8"), "max_base_radius_m = 0.09", "max_base_radius_m = 0.035")
    path = tmp_path / "upper.toml"
    path.write_text(t, "utf-8")
    free = cm.machine.analyze(cm.Machine.from_toml(SIZED), progress=False)
    assert free.mechanisms["lifter cam"].mech.sized.base_radius > 0.035  # the bound binds
    assert free.mechanisms["lifter cam"].mech.sizing_status == "ok"
    with warnings.catch_warnings():
        warnings.simplefilter("always", cm.CyclomechWarning)
        code, text = _run(path, tmp_path / "out", capsys)
    assert code == 0
    # The CLI's warning (on stderr).
    warned = "cyclomech: warning: cam 'lifter cam' (synthesize): at its upper bound "
    assert warned + "max_base_radius_m = 35 mm: the phase angles were stretched" in text
    assert "lifter cam: base_radius_m = 0.035 (at its upper bound; pressure_angle binds)" in text
    doc = json.loads((tmp_path / "out" / "results.json").read_text("utf-8"))
    sizing = doc["cams"]["lifter cam"]["sizing"]
    assert sizing["status"] == "at_upper_bound"
    assert sizing["base_radius_m"] == pytest.approx(0.035, rel=1e-9)
    assert "raise the bound to shorten them" in sizing["note"]
    assert "at its upper bound" in (tmp_path / "out" / "report.html").read_text("utf-8")


def test_unbound_segment_sets_the_limit_where_its_stress_reaches_the_allowed(
    tmp_path: Path,
) -> None:
    """The loom's lift (70°) without its arc: its σ_H bounds the speed by itself.
    Against dense sampling of the contact stress over the segment (the loads, not
    the phase-angle solver): just below the limit the largest σ_H is under [σ_H],
    just above it over."""
    loom = (ROOT / "examples" / "stb_loom.toml").read_text("utf-8")
    old = (
        "load_nm = 2.0                    # the microshuttle's drag, resisting the lift\n"
        'arc = ["1", "3"]'
    )
    path = tmp_path / "free_lift.toml"
    path.write_text(_edit(loom, old, "load_nm = 2.0"), "utf-8")
    cam = cm.Machine.from_toml(path).mechanisms["lifter cam"]
    rpm = cam.speed_limit_rpm()
    assert 0.0 < rpm < math.inf
    assert cam.limit_reason().startswith(
        f"cam 'lifter cam' segment 1 (rise, 70°, no arc): σ_H exceeds [σ_H] = 900 MPa "
        f"above {rpm:.2f} rpm"
    )
    d = cam.design
    theta = np.radians(np.linspace(0.0, 70.0, 20_001))
    peak = [
        float(np.nanmax(d.cam.loads(theta, n, d.loads, d.contact).contact_stress))
        for n in (rpm * (1 - 1e-5), rpm * (1 + 1e-5))
    ]
    assert peak[0] < d.max_stress < peak[1]
    # One crossing (the rule of stress_limit_rpm): σ_H at the lift's own 70° on 300
    # speeds from the reference speed to the search's cap is within [σ_H] exactly up
    # to the limit, though it is not monotone (it dips by ~3 % near 35 rpm first).
    from cyclomech.cam._free import REF_RPM, STRESS_CAP_RPM

    speeds = np.geomspace(REF_RPM, STRESS_CAP_RPM, 300)
    theta = theta[::5]
    top = np.array(
        [np.nanmax(d.cam.loads(theta, n, d.loads, d.contact).contact_stress) for n in speeds]
    )
    assert ((top <= d.max_stress) == (speeds < rpm)).all()
    assert top[np.argmin(np.abs(speeds - 35.0))] < 0.98 * top[0]
