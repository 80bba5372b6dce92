"""The whole machine (cyclomech.machine, the report of ``cyclomech run``, cyclomech.machine.sweep)
checked against what does not go through the machine's fast path.

Every number here is compared with something computed another way: the cyclogram's
LP (:meth:`cyclomech.Cyclogram.optimize`) on a cyclogram built from the machine file
with tomllib, the stop's exact constraint from :class:`cyclomech.impact.StopImpact`,
the mechanisms' own modules, and closed forms derived below from the example files.
"""

from __future__ import annotations

import base64
import concurrent.futures as cf
import copy
import csv
import json
import math
import pickle
import re
import tomllib
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech._keyrules import RENAMED
from hypothesis import given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
LOOM, KNIFE, PRESS, ROTOR = (
    # The loom before its lifter cam (issue 18): the stop alone bounds its
    # cyclogram, which these tests check in closed form; test_machine_cams.py checks
    # the example with its cam against an LP built from the cam API's bounds.
    str(ROOT / "tests" / "machine" / "data" / "stb_loom_stop_only.toml"),
    "knife_cutter.toml",
    "extrusion_press_line.toml",
    "rotor_line.toml",
)
MACHINE_FILES = (LOOM, KNIFE, PRESS, ROTOR)
#: The one example run with figures (the others with --no-plot, to keep it fast).
PLOTTED = "stb_loom.toml"
RAD_PER_RPM = 2.0 * math.pi / 60.0
#: Degrees of main-shaft rotation per second at 1 rpm.
DEG_PER_S_PER_RPM = 6.0
#: Keys of a cam_stop table that are not StopImpact's.
CAM_ONLY = {"kind", "arc", "a_max_m", "phase_deg"}
#: A file key → the Python parameter it sets (the keys carry their units).
PARAM = {new: old for old, (new, _) in RENAMED.items()}


# --------------------------------------------------------------------- helpers
def load(path: str | Path) -> dict[str, Any]:
    """The machine file, parsed by tomllib (not by cyclomech)."""
    p = Path(path)
    if not p.is_absolute():
        p = EXAMPLES / p
    with p.open("rb") as f:
        return tomllib.load(f)


def cyclogram_of(data: dict[str, Any]) -> cm.Cyclogram:
    """The machine file's cyclogram tables as a cyclogram file of their own."""
    return cm.Cyclogram.from_dict(
        {k: data[k] for k in ("cyclogram", "operation", "constraint") if k in data}
    )


def stops_of(data: dict[str, Any]) -> list[tuple[str, cm.impact.StopImpact, tuple, float]]:
    """(name, StopImpact, arc, a_max) of every cam stop of the file."""
    out = []
    for name, spec in data.get("mechanism", {}).items():
        if spec["kind"] == "cam_stop":
            keys = {PARAM.get(k, k): v for k, v in spec.items() if k not in CAM_ONLY}
            out.append((name, cm.impact.StopImpact(**keys), tuple(spec["arc"]), spec["a_max_m"]))
    return out


def reference_optimum(data: dict[str, Any], rpm: float, *, linear: bool = False) -> cm.Optimum:
    """The LP optimum at ``rpm`` with every stop's constraint added by hand; raises
    InfeasibleError where it does not fit (or a stop cannot keep its limit)."""
    cg = cyclogram_of(data)
    for name, stop, arc, a_max in stops_of(data):
        c = stop.constraint(arc, a_max, rpm, linear=linear)
        cg.add_constraint(c, name=f"rebound[{name}]")
    return cg.optimize(speed_rpm=rpm)


def reference_limiting(data: dict[str, Any], rpm: float, *, linear: bool = False) -> float:
    """The limiting angle at ``rpm`` by the LP; NaN where it raises InfeasibleError."""
    try:
        return reference_optimum(data, rpm, linear=linear).objective
    except cm.InfeasibleError:
        return math.nan


def floats(values: list[Any]) -> np.ndarray:
    """A JSON array of numbers (null for NaN) as floats."""
    return np.array([math.nan if v is None else v for v in values], dtype=np.float64)


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal arrays, bit for bit for floats (NaN payloads and signed zeros too)."""
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind == "f":
        return a.tobytes() == b.tobytes()
    return bool(np.array_equal(a, b))


def widened(tmp_path: Path, name: str, hi: float) -> Path:
    """A copy of an example with the top of its speed range raised to ``hi`` [rpm]."""
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    lo = load(name)["machine"]["speed_rpm"][0]
    new, count = re.subn(
        r"^speed_rpm = \[[^\]]*\]", f"speed_rpm = [{lo!r}, {hi!r}]", text, flags=re.M
    )
    assert count == 1
    path = tmp_path / name
    path.write_text(new, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def run(cli_run):
    """``cyclomech run`` on a machine file, once per file and worker (``cli_run``,
    tests/conftest.py: other files read the same runs): the output folder."""

    def go(path: str | Path) -> Path:
        src = Path(path) if Path(path).is_absolute() else EXAMPLES / path
        plot = src.name == PLOTTED and src.parent == EXAMPLES
        done = cli_run(src, "--quiet") if plot else cli_run(src, "--no-plot", "--quiet")
        assert done.code == 0
        return done.out

    return go


def results(folder: Path) -> dict[str, Any]:
    return json.loads((folder / "results.json").read_text(encoding="utf-8"))


# --------------------------------------------------------------------- closed forms
def loom_slope() -> float:
    """t_min(n)/n [deg/rpm] of the loom's lifter. The pulse model's rebound is
    proportional to the impact speed v0 ∝ n/t, so rebound(n, t) = K·n/t and the
    smallest phase angle t_min(n) = K·n/a_max is exactly proportional to n."""
    data = load(LOOM)
    ((_, stop, _, a_max),) = stops_of(data)
    assert stop.model == "pulse"
    # The rebound is K·n/t: proportional to n, inversely to t.
    a = stop.rebound(np.array([[250.0], [500.0]]), np.array([30.0, 60.0]))
    np.testing.assert_allclose(a[1, 0] / a[0, 0], 2.0, rtol=1e-12)
    np.testing.assert_allclose(a[0, 0] / a[0, 1], 2.0, rtol=1e-12)
    K = float(stop.rebound(1.0, 1.0))  # [m] at 1 rpm and 1°
    slope = K / a_max
    # The exact bisection agrees at any speed.
    n = np.array([200.0, 300.0, 421.0, 500.0])
    np.testing.assert_allclose(stop.min_phase_angle(a_max, n), slope * n, rtol=1e-9)
    return slope


def closed_form_limiting(name: str, rpm: np.ndarray) -> np.ndarray:
    """The limiting operation's optimal angle [deg] at each speed (NaN: does not fit),
    worked out from the example files by hand.

    * loom: the weft insertion 10.1→10.2 gets 360° minus the longest chain into 10.1
      from the start: lift (45) + approach t(3,7) + to picking (20) = 65 + t_min(n),
      or lift (45) + open spring (20) + close (15) + release (15) + released (0) = 95,
      or carry (55) + hold (5) + release (15) + released (0) = 75; it needs at least
      max(120°, 6·n·0.1 s). The return 6→8 (40) ends before 360°.
    * knife: the pile move gets 360 − (clamp 40 + cut 110 + return 90 + clear 0) = 120
      (the unclamp chain 40 + 110 + 60 = 210 is shorter); it needs max(60, 6·n·0.35).
    * press: the feed die open→blank in crosses into the next cycle: blank in →
      contact (20) → bottom (103.3) → die open (90) → blank in (+360) leaves 146.7; it
      needs max(40, 6·n·0.2).
    * rotor: the process gets 360 − (40 + 30 + 50) = 240; it needs max(120, 6·n·0.15).
    """
    n = np.asarray(rpm, dtype=np.float64)
    free_deg, min_deg, min_s = CLOSED_FORMS[name]
    free = free_deg(n) if callable(free_deg) else np.full(n.shape, free_deg)
    need = np.maximum(min_deg, DEG_PER_S_PER_RPM * n * min_s)
    return np.where(free >= need, free, np.nan)


#: The reference numbers of :func:`closed_form_limiting`, worked out by hand from
#: each machine file: (the angle [deg] the chain leaves the limiting operation, a
#: number or a law of the speed [rpm]; its min_angle_deg; its min_duration_s). A
#: machine without its entry is a KeyError, not another machine's numbers.
CLOSED_FORMS: dict[str, tuple[Any, float, float]] = {
    LOOM: (lambda n: 360.0 - np.maximum(95.0, 65.0 + loom_slope() * n), 120.0, 0.1),
    KNIFE: (120.0, 60.0, 0.35),
    PRESS: (146.7, 40.0, 0.2),
    ROTOR: (240.0, 120.0, 0.15),
}


#: The cyclogram's speed limit [rpm] where the time-bound limiting operation's
#: duration meets what the chain of the closed forms above leaves it.
CHAIN_LIMIT = {KNIFE: 120.0 / (6 * 0.35), PRESS: 146.7 / (6 * 0.2), ROTOR: 240.0 / (6 * 0.15)}
#: The chain that fills the cycle at the limit, for max_speed_rpm's ``cycle``.
CHAIN_OPS = {
    KNIFE: {
        ("start", "clamped"),
        ("clamped", "cut"),
        ("cut", "knife up"),
        ("knife up", "unclamped"),
        ("unclamped", "pile set"),
    },
    PRESS: {
        ("blank in", "contact"),
        ("contact", "bottom"),
        ("bottom", "die open"),
        ("die open", "blank in"),
    },
    ROTOR: {
        ("arrive", "clamped"),
        ("clamped", "processed"),
        ("processed", "released"),
        ("released", "leave"),
    },
}


def loom_limit_rpm() -> float:
    """At the limit the lifter's chain fills the cycle with the weft insertion at its
    duration: 45 + t_min(n) + 20 + 6·n·0.1 = 360 with t_min(n) = slope·n."""
    c = loom_slope()
    n = (360.0 - 45.0 - 20.0) / (c + 6 * 0.1)
    # That chain, not the spring openers' (95°), is the longest there, and the
    # insertion's duration, not its 120°, is its minimum: the closed form holds.
    assert 65.0 + c * n > 95.0 and 6 * 0.1 * n > 120.0
    return n


# --------------------------------------------------------------------- 1. cyclomech run
def test_every_machine_example_is_covered():
    found = {p.name for p in EXAMPLES.glob("*.toml") if "machine" in load(p)}
    # The loom with its cam is covered by test_machine_cams.py; here its stop-only copy.
    # The flow wrapper (cams and servo axes) by tests/servo/test_servo_kind.py; the
    # synthesised knife drive by test_knife_synthesized.py, the sized cam by
    # test_cam_sized_machine.py, the synthesised transfer arm by
    # test_transfer_arm_synthesized.py.
    assert found == {Path(f).name for f in MACHINE_FILES} - {"stb_loom_stop_only.toml"} | {
        "stb_loom.toml",
        "flow_wrapper.toml",
        "knife_cutter_synthesized.toml",
        "lifter_cam_sized.toml",
        "transfer_arm_synthesized.toml",
    }


@pytest.mark.parametrize("name", MACHINE_FILES)
def test_run_writes_the_report_files(run, name):
    out = run(name)
    for f in ("report.html", "results.json", "speed_sweep.csv", "operations.csv"):
        assert (out / f).is_file()
    r = results(out)
    data = load(name)
    assert r["schema"] == "cyclomech.machine/1"
    assert r["name"] == data["machine"]["name"]
    assert r["nominal_rpm"] == data["machine"]["nominal_rpm"]
    assert r["speed_range_rpm"] == data["machine"]["speed_rpm"]
    lim = data["cyclogram"]["limiting"]
    assert r["limiting_operation"]["arc"] == f"{lim[0]}→{lim[1]}"
    sw = r["speed_sweep"]
    np.testing.assert_array_equal(
        floats(sw["speed_rpm"]),
        np.linspace(*data["machine"]["speed_rpm"], data["machine"]["speed_points"]),
    )
    assert (out / "figures").is_dir() == (name == PLOTTED)


def test_run_with_figures_embeds_them_in_the_report(run):
    out = run(PLOTTED)
    pngs = sorted((out / "figures").glob("*.png"))
    # The speed sweep, the cyclogram (Gantt and circular), the lifter's rebound,
    # cam law and smallest phase angle, and its cam's drawing, SVAJ, loads along the
    # cycle and smallest phase angles; the main shaft's torque, and under the file's
    # [drive] its real speed; the frame's shaking (the lifter cam's couple).
    assert {p.stem for p in pngs} == {
        "speed_sweep",
        "cyclogram",
        "cyclogram_circular",
        "lifter_rebound",
        "lifter_law",
        "lifter_min_phase",
        "lifter_cam_cam",
        "lifter_cam_svaj",
        "lifter_cam_along_cycle",
        "lifter_cam_min_phase",
        "main_shaft",
        "main_shaft_speed",
        "main_shaft_torsion",
        "shaking",
    }
    page = (out / "report.html").read_text(encoding="utf-8")
    for p in pngs:
        raw = p.read_bytes()
        assert raw.startswith(b"\x89PNG\r\n\x1a\n")
        assert f"data:image/png;base64,{base64.b64encode(raw).decode('ascii')}" in page
    assert page.count("data:image/png;base64,") == len(pngs)
    assert 'src="figures/' not in page  # self-contained


@pytest.mark.parametrize("name", MACHINE_FILES)
def test_run_optimum_is_the_lp_optimum(run, name):
    """The optimised cyclogram at the nominal speed against the LP of the file's own
    cyclogram with the stops' exact constraints added by hand."""
    r = results(run(name))
    data = load(name)
    rpm = data["machine"]["nominal_rpm"]
    ref = reference_optimum(data, rpm)
    o = r["optimum"]
    assert o["speed_rpm"] == rpm
    assert o["limiting_deg"] == pytest.approx(ref.objective, rel=1e-12, abs=1e-9)
    assert o["limiting_deg"] == pytest.approx(
        closed_form_limiting(name, np.array([rpm]))[0], abs=1e-7
    )
    lim = cyclogram_of(data).operation(tuple(data["cyclogram"]["limiting"]))
    minimum = max(lim.min_angle_deg, DEG_PER_S_PER_RPM * rpm * lim.min_duration_s)
    assert o["limiting_min_deg"] == pytest.approx(minimum, rel=1e-12)
    assert o["gained_deg"] == pytest.approx(ref.objective - minimum, abs=1e-9)
    assert o["limiting_s"] == pytest.approx(ref.objective / (6.0 * rpm), rel=1e-12)
    priced = {k: v for k, v in ref.duals.items() if abs(v) > 1e-9}
    assert set(o["shadow_prices"]) == set(priced)
    for k, v in priced.items():
        assert o["shadow_prices"][k] == pytest.approx(v, abs=1e-9)
    for (a, b), v in ref.angles.items():
        assert o["angles_deg"][f"{a}→{b}"] == pytest.approx(v, abs=1e-7)


def test_loom_shadow_prices_follow_the_lifter_chain(run):
    """At 300 rpm t_min = 30.03° > 30°, so the lifter's chain (lift, approach at its
    rebound bound, to picking) takes the angle from the weft insertion: −1 each, and
    +1 for the cycle."""
    o = results(run(LOOM))["optimum"]
    assert o["shadow_prices"] == pytest.approx(
        {
            "min[lift microshuttle]": -1.0,
            "rebound[lifter]": -1.0,
            "min[to picking position]": -1.0,
            "cycle": 1.0,
        },
        abs=1e-9,
    )
    assert o["angles_deg"]["3→7"] == pytest.approx(loom_slope() * 300.0, rel=1e-9)


def test_loom_speed_limit_in_closed_form(run):
    r = results(run(LOOM))
    n = loom_limit_rpm()
    lim = r["speed_limit"]
    assert lim["by"] == "cyclogram"
    assert lim["mechanisms_rpm"] == {}
    assert lim["rpm"] == pytest.approx(n, rel=1e-6)
    assert lim["cyclogram_rpm"] == pytest.approx(n, rel=1e-6)
    assert {
        "min[lift microshuttle]",
        "rebound[lifter]",
        "min[to picking position]",
        "cycle",
    } <= set(lim["binding"])
    # The LP agrees: it fits just below the limit, not just above.
    assert math.isfinite(reference_limiting(load(LOOM), n * (1 - 1e-6)))
    assert math.isnan(reference_limiting(load(LOOM), n * (1 + 1e-6)))


def test_loom_stop_angles_are_proportional_to_speed(run):
    r = results(run(LOOM))
    s = r["stops"]["lifter"]
    n = floats(s["speed_rpm"])
    np.testing.assert_allclose(floats(s["min_phase_deg"]), loom_slope() * n, rtol=1e-9)
    assert s["min_phase_deg_at_nominal"] == pytest.approx(loom_slope() * 300.0, rel=1e-9)
    # The seed's linearised form, as StopImpact.constraint(linear=True) gives it.
    data = load(LOOM)
    ((_, stop, arc, a_max),) = stops_of(data)
    lin = floats(s["linear_min_phase_deg"])
    for k in (0, 20, 60):
        c = stop.constraint(arc, a_max, float(n[k]), linear=True)
        ((_, slope),) = c.coeffs
        assert c.sense == "<="
        assert lin[k] == pytest.approx(c.rhs / slope, rel=1e-9)


def test_loom_max_rebound_in_closed_form():
    """With the arc at its smallest admissible angle max(20°, t_min(n)) the rebound is
    K·n/max(20, slope·n): a_max where the stop's bound is above 20° (from about 200
    rpm), less below; NaN where the cyclogram does not fit."""
    ((_, stop, _, a_max),) = stops_of(load(LOOM))
    K = float(stop.rebound(1.0, 1.0))
    n = np.array([80.0, 150.0, 199.0, 250.0, 300.0, 421.0, 450.0])
    want = K * n / np.maximum(20.0, loom_slope() * n)
    want[n > loom_limit_rpm()] = np.nan
    s = cm.Machine.from_toml(EXAMPLES / LOOM).speed_sweep(n)
    np.testing.assert_allclose(s.max_rebound_m, want, rtol=1e-9)
    assert s.max_rebound_m[0] < 0.5 * a_max
    np.testing.assert_allclose(s.min_phase_deg["lifter"], loom_slope() * n, rtol=1e-9)


@pytest.mark.parametrize("name", [KNIFE, PRESS, ROTOR])
def test_cyclogram_speed_limit_where_the_chain_fills_the_cycle(run, name):
    lim = results(run(name))["speed_limit"]
    n = CHAIN_LIMIT[name]
    assert lim["cyclogram_rpm"] == pytest.approx(n, rel=1e-9)
    ref = cyclogram_of(load(name)).max_speed_rpm()
    assert ref.rpm == pytest.approx(n, rel=1e-12)
    assert set(ref.cycle) == CHAIN_OPS[name]


def test_knife_speed_limit_from_the_linkage_analogs(run):
    """The knife E at constant crank speed ω: |a| = ω²·|d² xy/dφ²|, so the 8 m/s²
    limit is reached at ω = √(8/max|d² xy/dφ²|)."""
    r = results(run(KNIFE))
    data = load(KNIFE)
    spec = data["mechanism"]["knife"]
    lk = cm.Linkage.from_dict(
        {
            k: v
            for k, v in spec.items()
            if k not in {"kind", "max_acceleration_m_per_s2", "phase", *cm.forces.DYNAMICS_KEYS}
        }
    )
    points = data["machine"].get("angle_points", 361)
    sol = lk.solve(lk.drawn_angle + np.linspace(0.0, 2.0 * math.pi, points))
    assert sol.ok.all()
    k = sol.index(spec["output"])
    acc = float(np.max(np.hypot(*sol.acc[:, k].T)))
    vel = float(np.max(np.hypot(*sol.vel[:, k].T)))
    # The analogs against finite differences of the positions on a fine grid.
    fine = lk.solve(lk.drawn_angle + np.linspace(0.0, 2.0 * math.pi, 7201))
    h = 2.0 * math.pi / 7200
    xy = fine.xy[:, k]
    dd = (xy[2:] - 2.0 * xy[1:-1] + xy[:-2]) / h**2
    np.testing.assert_allclose(dd, fine.acc[1:-1, k], rtol=0, atol=1e-5 * acc)
    limit = math.sqrt(spec["max_acceleration_m_per_s2"] / acc) / RAD_PER_RPM
    m = r["mechanisms"]["knife"]
    assert m["max_acceleration_analog_m_per_rad2"] == pytest.approx(acc, rel=1e-12)
    assert m["max_velocity_analog_m_per_rad"] == pytest.approx(vel, rel=1e-12)
    assert m["speed_limit_rpm"] == pytest.approx(limit, rel=1e-12)
    w = r["nominal_rpm"] * RAD_PER_RPM
    assert m["max_acceleration_m_s2"] == pytest.approx(acc * w * w, rel=1e-12)
    # At the limit speed the peak acceleration is the limit.
    assert acc * (limit * RAD_PER_RPM) ** 2 == pytest.approx(
        spec["max_acceleration_m_per_s2"], rel=1e-12
    )
    lim = r["speed_limit"]
    assert lim["mechanisms_rpm"] == {"knife": pytest.approx(limit, rel=1e-12)}
    assert limit > CHAIN_LIMIT[KNIFE]
    assert lim["by"] == "cyclogram"
    assert lim["rpm"] == pytest.approx(CHAIN_LIMIT[KNIFE], rel=1e-9)


def test_press_speed_limit_from_the_start_of_the_working_stroke(run):
    """V_np grows as n: the 5 mm/s limit is max_V_np/V_np(1 rpm)."""
    r = results(run(PRESS))
    spec = load(PRESS)["mechanism"]["drive"]
    press = cm.press.GearLeverPress(
        R=spec["R_m"],
        r=spec["r_m"],
        d=spec["d_m"],
        L=spec["L_m"],
        phi0=math.radians(spec["phi0_deg"]),
    )
    nominal = r["nominal_rpm"]
    c1 = press.criteria(omega=nominal * RAD_PER_RPM, k_Sp=spec["k_Sp"])
    c2 = press.criteria(omega=2 * nominal * RAD_PER_RPM, k_Sp=spec["k_Sp"])
    assert c1.ok and c2.ok
    assert c2.V_np / c1.V_np == pytest.approx(2.0, rel=1e-9)
    limit = spec["max_V_np_m_per_s"] * nominal / c1.V_np
    crit = r["mechanisms"]["drive"]["criteria"]
    assert crit["V_np"] == pytest.approx(c1.V_np, rel=1e-12)
    assert crit["S_n"] == pytest.approx(c1.S_n, rel=1e-12)
    assert r["mechanisms"]["drive"]["speed_limit_rpm"] == pytest.approx(limit, rel=1e-9)
    lim = r["speed_limit"]
    assert limit < CHAIN_LIMIT[PRESS]
    assert lim["by"] == "drive"
    assert lim["rpm"] == pytest.approx(limit, rel=1e-9)
    assert lim["mechanisms_rpm"] == {"drive": pytest.approx(limit, rel=1e-9)}


def test_transfer_speed_limit_from_jerk_and_acceleration(run):
    """Each rotor turns one pocket per cycle, V = ω·R/pockets; on a fixed path the
    peak acceleration grows as n² and the peak jerk as n³."""
    r = results(run(ROTOR))
    spec = load(ROTOR)["mechanism"]["line"]
    R_t, R_p, gap = spec["R_t_m"], spec["R_p_m"], spec["gap_m"]
    nominal = r["nominal_rpm"]

    def speeds(rpm: float) -> tuple[float, float]:
        w = rpm * RAD_PER_RPM
        return (w * R_t / spec["pockets_t"], w * R_p / spec["pockets_p"])

    x2 = cm.transfer.design_transfer(R_t, R_p, gap, speeds(nominal)).x2
    path = cm.transfer.TransferPath(R_t, R_p, (0.0, 0.0), (R_t + R_p + gap, 0.0), x2)
    a1 = path.acceleration(speeds(nominal))
    a2 = path.acceleration(speeds(2 * nominal))
    assert a2.max_acceleration / a1.max_acceleration == pytest.approx(4.0, rel=1e-9)
    assert a2.max_jerk / a1.max_jerk == pytest.approx(8.0, rel=1e-9)
    by_jerk = nominal * (spec["max_jerk_m_per_s3"] / a1.max_jerk) ** (1 / 3)
    by_acc = nominal * math.sqrt(spec["max_acceleration_m_per_s2"] / a1.max_acceleration)
    limit = min(by_jerk, by_acc)
    m = r["mechanisms"]["line"]
    assert m["x2_m"] == pytest.approx([x2, x2], rel=1e-12)
    assert m["speeds_m_s"] == pytest.approx(list(speeds(nominal)), rel=1e-12)
    assert m["max_acceleration_m_s2"] == pytest.approx(a1.max_acceleration, rel=1e-12)
    assert m["max_jerk_m_s3"] == pytest.approx(a1.max_jerk, rel=1e-12)
    assert m["speed_limit_rpm"] == pytest.approx(limit, rel=1e-9)
    lim = r["speed_limit"]
    assert limit < CHAIN_LIMIT[ROTOR]
    assert lim["by"] == "line"
    assert lim["rpm"] == pytest.approx(limit, rel=1e-9)


def _sweep_indices(fits: list[bool]) -> list[int]:
    """A handful of rows: both ends, a few between, and the last row that fits and the
    first that does not."""
    n = len(fits)
    idx = {0, n - 1, *np.linspace(0, n - 1, 6).round().astype(int).tolist()}
    if any(fits) and not all(fits):
        first_bad = fits.index(False)
        idx |= {first_bad, max(first_bad - 1, 0)}
    return sorted(idx)


@pytest.mark.parametrize(
    ("name", "wider"),
    [(LOOM, None), (KNIFE, None), (PRESS, 220.0), (ROTOR, 320.0)],
)
def test_speed_sweep_against_the_lp(run, tmp_path, name, wider):
    """limiting_deg at a handful of the sweep's speeds against the LP with the exact
    stop constraint there, and fits False exactly where the LP raises InfeasibleError;
    the press and the rotor line fit over their whole range, so they also run with a
    range beyond their cyclogram's limit."""
    data = load(name)
    folders = [run(name)] + ([run(widened(tmp_path, name, wider))] if wider else [])
    infeasible_seen = 0
    for out in folders:
        sw = results(out)["speed_sweep"]
        rpm = floats(sw["speed_rpm"])
        lim = floats(sw["limiting_deg"])
        fits = sw["fits"]
        # Every row in closed form.
        np.testing.assert_allclose(lim, closed_form_limiting(name, rpm), rtol=0, atol=1e-7)
        np.testing.assert_array_equal(np.array(fits), np.isfinite(lim))
        # Productivity where the machine works: the cyclogram fits and no mechanism is
        # above its own speed limit (the press's, the transfer's jerk).
        own = min(results(out)["speed_limit"]["mechanisms_rpm"].values(), default=np.inf)
        works = np.array(fits) & (rpm <= own)
        np.testing.assert_array_equal(floats(sw["productivity_per_min"]), np.where(works, rpm, 0.0))
        np.testing.assert_allclose(floats(sw["limiting_s"]), lim / (6.0 * rpm), rtol=1e-12)
        for k in _sweep_indices(fits):
            ref = reference_limiting(data, float(rpm[k]))
            if math.isnan(ref):
                infeasible_seen += 1
                assert fits[k] is False and sw["limiting_deg"][k] is None
                assert sw["binding"][k] == ""
            else:
                assert fits[k] is True
                assert abs(lim[k] - ref) <= 1e-7
                assert sw["binding"][k]
            if stops_of(data):
                ref_lin = reference_limiting(data, float(rpm[k]), linear=True)
                got = floats(sw["limiting_deg_linear"])[k]
                assert np.isnan(got) == np.isnan(ref_lin)
                if not np.isnan(ref_lin):
                    assert abs(got - ref_lin) <= 1e-7
    assert infeasible_seen >= 1


@pytest.mark.parametrize("name", MACHINE_FILES)
def test_csv_files_agree_with_results_json(run, name):
    out = run(name)
    r = results(out)
    sw = r["speed_sweep"]
    with (out / "speed_sweep.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    stops = list(r["stops"])
    header = [
        "speed_rpm",
        "fits",
        "limiting_deg",
        "limiting_deg_linear",
        "limiting_s",
        "productivity_per_min",
        "max_rebound_m",
    ]
    for s in stops:
        header += [f"min_phase_deg[{s}]", f"linear_min_phase_deg[{s}]"]
    assert list(rows[0]) == [*header, "binding"]
    assert len(rows) == len(sw["speed_rpm"])

    def column(key: str) -> np.ndarray:
        return np.array([float(row[key]) for row in rows])

    for key, js in [
        ("speed_rpm", sw["speed_rpm"]),
        ("limiting_deg", sw["limiting_deg"]),
        ("limiting_deg_linear", sw["limiting_deg_linear"]),
        ("limiting_s", sw["limiting_s"]),
        ("productivity_per_min", sw["productivity_per_min"]),
        ("max_rebound_m", sw["max_rebound_m"]),
        *[(f"min_phase_deg[{s}]", r["stops"][s]["min_phase_deg"]) for s in stops],
        *[(f"linear_min_phase_deg[{s}]", r["stops"][s]["linear_min_phase_deg"]) for s in stops],
    ]:
        np.testing.assert_array_equal(column(key), floats(js), err_msg=key)
    assert [row["fits"] for row in rows] == [str(v) for v in sw["fits"]]
    assert [row["binding"] for row in rows] == sw["binding"]
    if not stops:
        assert np.isnan(column("max_rebound_m")).all()

    with (out / "operations.csv").open(newline="", encoding="utf-8") as f:
        ops = list(csv.DictReader(f))
    o = r["optimum"]
    data = load(name)
    assert [(row["from"], row["to"]) for row in ops] == [
        (str(op["from"]), str(op["to"])) for op in data["operation"]
    ]
    for row, op in zip(ops, data["operation"], strict=True):
        arc = f"{row['from']}→{row['to']}"
        assert row["operation"] == op.get("name", arc)
        assert row["mechanism"] == op.get("mechanism", "")
        assert float(row["angle_deg"]) == o["angles_deg"][arc]
        assert float(row["start_deg"]) == o["times_deg"][row["from"]]
        assert row["critical"] == str(arc in o["critical"])
        own = max(
            op.get("min_angle_deg", 0.0),
            DEG_PER_S_PER_RPM * r["nominal_rpm"] * op.get("min_duration_s", 0.0),
        )
        minimum, by = float(row["minimum_deg"]), row["minimum_by"]
        assert minimum == o["minimums_deg"][arc] and by == o["minimum_by"][arc]
        if by.startswith(("min[", "duration[")):  # the operation's own minimum sets it
            assert by.endswith(f"[{row['operation']}]")
            assert minimum == pytest.approx(own, abs=1e-9)
        else:  # a mechanism's bound, above the operation's own minimum
            assert minimum > own
        # The optimum honours it, and where it sits on it, that bound is binding.
        beyond = float(row["beyond_minimum_deg"])
        assert beyond == pytest.approx(o["angles_deg"][arc] - minimum, abs=1e-12)
        assert beyond >= -1e-9
        if abs(beyond) <= 1e-9:
            assert by in o["binding"], (arc, by)


# --------------------------------------------------------------------- 2. properties
COEFFS = (-4.0, -2.0, -1.0, -0.5, 0.5, 1.0, 2.0, 4.0)


def _deg(lo: int, hi: int) -> st.SearchStrategy[float]:
    """Angles on a 0.001° grid: sums of them never fall a hair's breadth (below the
    solvers' tolerances) short of or beyond the cycle."""
    return st.integers(lo * 1000, hi * 1000).map(lambda k: k / 1000)


@st.composite
def machine_dicts(draw: Any, *, extras: bool = True) -> dict[str, Any]:
    """A small random machine without mechanisms: 4–8 events, operations forward in
    the event order (or backward into the next cycle, height 1), some time-bound,
    some with a maximum, single-operation constraints, rarely one over two operations,
    and a limiting operation."""
    n_ev = draw(st.integers(4, 8))
    pairs = [(i, j) for i in range(n_ev) for j in range(n_ev) if i != j]
    arcs = draw(st.lists(st.sampled_from(pairs), min_size=3, max_size=10, unique=True))
    ops = []
    for i, j in arcs:
        op: dict[str, Any] = {"from": f"e{i}", "to": f"e{j}", "min_angle_deg": draw(_deg(0, 120))}
        if j < i:
            op["height"] = 1
        if draw(st.booleans()):
            op["min_duration_s"] = draw(st.integers(1, 300)) / 1000
        if extras and draw(st.integers(0, 3)) == 0:
            op["max_angle_deg"] = op["min_angle_deg"] + draw(_deg(0, 150))
        ops.append(op)
    lim = draw(st.integers(0, len(ops) - 1))
    cons = []
    if extras:
        for k in range(draw(st.integers(0, 3))):
            e = draw(st.integers(0, len(ops) - 1))
            c = draw(st.sampled_from(COEFFS))
            bound = draw(_deg(0, 200))
            cons.append(
                {
                    "name": f"c{k}",
                    "terms": [{"from": ops[e]["from"], "to": ops[e]["to"], "coeff": c}],
                    "sense": draw(st.sampled_from(["<=", ">=", "<=", ">=", "=="])),
                    "rhs": c * bound,
                }
            )
        if len(ops) >= 2 and draw(st.integers(0, 4)) == 0:  # the LP path
            e1, e2 = draw(
                st.lists(st.integers(0, len(ops) - 1), min_size=2, max_size=2, unique=True)
            )
            cons.append(
                {
                    "name": "two",
                    "terms": [
                        {
                            "from": ops[e]["from"],
                            "to": ops[e]["to"],
                            "coeff": draw(st.sampled_from(COEFFS)),
                        }
                        for e in (e1, e2)
                    ],
                    "sense": draw(st.sampled_from(["<=", ">="])),
                    "rhs": draw(_deg(-200, 200)),
                }
            )
    data: dict[str, Any] = {
        "machine": {"name": "random", "speed_rpm": [1.0, 3000.0]},
        "cyclogram": {"name": "random", "limiting": [ops[lim]["from"], ops[lim]["to"]]},
        "operation": ops,
    }
    if cons:
        data["constraint"] = cons
    return data


SPEEDS = st.lists(st.integers(10, 30_000), min_size=1, max_size=8, unique=True).map(
    lambda v: np.array(sorted(v), dtype=np.float64) / 10.0
)


@settings(max_examples=40, deadline=None)
@given(data=machine_dicts(), rpm=SPEEDS)
def test_speed_sweep_is_the_lp_optimum_at_every_speed(data, rpm):
    m = cm.Machine.from_dict(copy.deepcopy(data))
    sw = m.speed_sweep(rpm)
    cg = cyclogram_of(data)
    for k, n in enumerate(rpm):
        try:
            ref = cg.optimize(speed_rpm=float(n)).objective
        except cm.InfeasibleError:
            assert math.isnan(sw.limiting_deg[k]), (n, sw.limiting_deg[k])
            assert not sw.fits[k]
        else:
            assert sw.fits[k], (n, ref)
            assert abs(sw.limiting_deg[k] - ref) <= 1e-7 * (1 + abs(ref)), (n, ref)
    np.testing.assert_array_equal(sw.fits, np.isfinite(sw.limiting_deg))
    np.testing.assert_array_equal(sw.productivity_per_min, np.where(sw.fits, rpm, 0.0))
    assert np.isnan(sw.max_rebound_m).all() and sw.min_phase_deg == {}


@settings(max_examples=40, deadline=None)
@given(data=machine_dicts(extras=False))
def test_cyclogram_speed_limit_is_max_speed(data):
    m = cm.Machine.from_dict(copy.deepcopy(data))
    try:
        ref = cyclogram_of(data).max_speed_rpm().rpm
    except cm.InfeasibleError:
        ref = 0.0  # fits at no speed
    got = m.cyclogram_speed_limit()
    if ref == 0.0 or math.isinf(ref):
        assert got == ref
        return
    assert got == pytest.approx(ref, rel=1e-8)
    assert m.speed_sweep([ref * (1 - 1e-7), ref * (1 + 1e-7)]).fits.tolist() == [True, False]


def test_cyclogram_speed_limit_below_the_cap_is_finite():
    # t(a,b) ≥ 10° and 6·n·s for b→c: the limit is 350/(6·s) = 600 000 rpm < 1e6 rpm.
    s = 350.0 / (6.0 * 600_000.0)
    data = {
        "machine": {"name": "fast", "speed_rpm": [100.0, 500.0]},
        "cyclogram": {"name": "fast", "limiting": ["a", "b"]},
        "operation": [
            {"from": "a", "to": "b", "min_angle_deg": 10.0},
            {"from": "b", "to": "c", "min_duration_s": s},
        ],
    }
    m = cm.Machine.from_dict(data)
    ref = cyclogram_of(data).max_speed_rpm().rpm
    assert ref == pytest.approx(600_000.0, rel=1e-12)
    assert m.fits([610_000.0]).tolist() == [False]
    assert m.cyclogram_speed_limit() == pytest.approx(ref, rel=1e-8)


# --------------------------------------------------------------------- 3. sweeps
PRELOADS = [2.0e-4, 2.5e-4, 3.0e-4]
SWEEP_SPEEDS = [250.0, 350.0, 420.0, 450.0]


@pytest.fixture(scope="module")
def loom_sweep():
    m = cm.Machine.from_toml(EXAMPLES / LOOM)
    return m, cm.sweep(m, {"lifter.preload_m": PRELOADS, "speed_rpm": SWEEP_SPEEDS}, progress=False)


def test_sweep_rows_are_the_speed_sweep_of_each_design(loom_sweep):
    m, r = loom_sweep
    S = len(SWEEP_SPEEDS)
    assert r.n_points == len(PRELOADS) * S
    assert r.parameters == ("lifter.preload_m",)
    cols = r.columns
    for d, p in enumerate(PRELOADS):
        rows = slice(d * S, (d + 1) * S)
        design = m.with_values({"lifter.preload_m": p})
        assert design.mechanisms["lifter"].stop.preload == p
        s = design.speed_sweep(SWEEP_SPEEDS)
        lim = design.speed_limit()
        assert same_bits(cols["lifter.preload_m"][rows], np.full(S, p))
        assert same_bits(cols["speed_rpm"][rows], s.rpm)
        for key in ("fits", "limiting_deg", "limiting_s", "productivity_per_min", "max_rebound_m"):
            assert same_bits(cols[key][rows], getattr(s, key)), key
        assert cols["binding"][rows].tolist() == s.binding.tolist()
        assert same_bits(cols["speed_limit_rpm"][rows], np.full(S, lim.rpm))
        assert cols["speed_limit_by"][rows].tolist() == [lim.by] * S
    # A stiffer preload is a different design: the sweep is not one design repeated.
    assert len(set(cols["speed_limit_rpm"].tolist())) == len(PRELOADS)


def test_sweep_columns_and_their_order():
    m = cm.Machine.from_toml(EXAMPLES / LOOM)
    a_max = [1e-4, 2e-4]
    speeds = [300.0, 400.0, 500.0]
    r = cm.sweep(
        m,
        {"lifter.preload_m": PRELOADS[:2], "lifter.a_max_m": a_max, "speed_rpm": speeds},
        progress=False,
    )
    assert list(r.columns) == [
        "lifter.preload_m",
        "lifter.a_max_m",
        "speed_rpm",
        "fits",
        "limiting_deg",
        "limiting_s",
        "productivity_per_min",
        "max_rebound_m",
        "speed_limit_rpm",
        "speed_limit_by",
        "binding",
        "problem",
    ]
    assert r.parameters == ("lifter.preload_m", "lifter.a_max_m")
    # The first parameter slowest, the speed fastest.
    assert r.columns["lifter.preload_m"].tolist() == [p for p in PRELOADS[:2] for _ in range(6)]
    assert r.columns["lifter.a_max_m"].tolist() == [
        a for _ in range(2) for a in a_max for _ in range(3)
    ]
    assert r.columns["speed_rpm"].tolist() == speeds * 4
    assert all(v.ndim == 1 and v.size == 12 for v in r.columns.values())
    # Row 5: preload 2e-4, a_max 2e-4, 500 rpm.
    s = m.with_values({"lifter.preload_m": PRELOADS[0], "lifter.a_max_m": 2e-4}).speed_sweep(
        [500.0]
    )
    assert same_bits(r.columns["limiting_deg"][5:6], s.limiting_deg)


def test_sweep_on_an_executor_is_bit_for_bit_the_same(loom_sweep):
    """Chunks on an executor (one Rust thread each) give the in-process result."""
    m, r = loom_sweep
    with cf.ThreadPoolExecutor(2) as ex:
        r2 = cm.sweep(
            m,
            {"lifter.preload_m": PRELOADS, "speed_rpm": SWEEP_SPEEDS},
            ex,
            chunk=1,
            progress=False,
        )
    assert list(r2.columns) == list(r.columns)
    for k, v in r.columns.items():
        if v.dtype == object:
            assert r2.columns[k].tolist() == v.tolist(), k
        else:
            assert same_bits(r2.columns[k], v), k


@pytest.mark.parametrize("suffix", [".parquet", ".npz"])
def test_sweep_files_read_back_equal(loom_sweep, tmp_path, suffix):
    _, r = loom_sweep
    path = r.write(tmp_path / f"sweep{suffix}")
    assert path.suffix == suffix and path.is_file()
    back = cm.SweepResult.read(path)
    assert back.parameters == r.parameters
    assert list(back.columns) == list(r.columns)
    for k, v in r.columns.items():
        got = back.columns[k]
        if v.dtype == object:
            assert got.dtype == object and got.tolist() == v.tolist(), k
        else:
            assert same_bits(got, v), k


def test_rebound_price_per_mm_is_the_optimum_s_slope_in_a_max(run):
    """The report's price of the lifter's rebound bound per mm of its rebound limit
    against the LP re-solved with a_max ± 10 nm (a central difference of the
    optimum, not of t_min). A shadow price holds for small changes only: here a
    parallel chain (open gripper spring …, at zero price) takes over once t(3,7)
    has fallen by 0.031°, i.e. for a_max up by 0.1 µm."""
    r = results(run(PLOTTED))
    price = r["optimum"]["shadow_prices_per_mm_rebound"]["rebound[lifter]"]
    m = cm.Machine.from_toml(EXAMPLES / PLOTTED)
    n = r["nominal_rpm"]
    a = m.mechanisms["lifter"].a_max
    up, down = (
        m.with_values({"lifter.a_max_m": a + d}).optimize(n).objective for d in (1e-8, -1e-8)
    )
    assert price == pytest.approx((up - down) / 2e-5, rel=1e-3)  # deg per mm
    assert price > 0  # more allowed rebound leaves the weft insertion more angle


def test_a_speed_range_above_the_limit_is_reported_as_such(tmp_path):
    """A loom whose speed range lies wholly above its speed limit: the report says
    the machine works at no speed of the range, and draws the figure anyway. By
    analyze and write_report, what ``cyclomech run`` calls (without the speed
    limit's sensitivities, a third of the time here, which draw nothing): the
    command's one warning line and exit 0 for such a range are
    tests/machine/test_cli_machine.py::test_version_and_one_line_warnings's."""
    path = tmp_path / "fast.toml"
    text = (EXAMPLES / PLOTTED).read_text(encoding="utf-8")
    path.write_text(text.replace("speed_rpm = [200.0, 500.0]", "speed_rpm = [600.0, 900.0]"))
    out = tmp_path / "out"
    with pytest.warns(cm.CyclomechWarning, match="works at none of the 61 speeds"):
        analysis = cm.machine.analyze(cm.Machine.from_toml(path), progress=False)
    cm.machine.write_report(analysis, out, figures=True)
    r = results(out)
    assert r["speed_limit"]["rpm"] == pytest.approx(420.32, abs=0.01)
    assert not any(r["speed_sweep"]["fits"])
    assert (out / "figures" / "speed_sweep.png").is_file()
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "420.32 rpm</b>, set by the cyclogram" in page


def test_many_machines_together_are_each_alone():
    """speed_sweeps / speed_limits of variants (one network, stops searched
    together, one shortest-path call) equal each machine's own, bit for bit; a
    machine of another file in the same call too."""
    loom = cm.Machine.from_toml(EXAMPLES / "stb_loom.toml")
    others = [
        loom.with_values({"lifter.preload_m": p, "lifter.a_max_m": a})
        for p, a in ((1e-4, 1e-4), (3e-4, 5e-5), (5e-4, 2e-4))
    ]
    rotor = cm.Machine.from_toml(EXAMPLES / ROTOR)
    ms = [loom, *others, rotor, loom.with_values({"lifter.model": "contact"})]
    rpm = np.linspace(150.0, 600.0, 37)
    sweeps = cm.machine.speed_sweeps(ms, rpm)
    limits = cm.machine.speed_limits(ms)
    for m, s, lim in zip(ms, sweeps, limits, strict=True):
        one = m.speed_sweep(rpm)
        for k in ("fits", "limiting_deg", "limiting_s", "productivity_per_min", "max_rebound_m"):
            assert np.array_equal(getattr(s, k), getattr(one, k), equal_nan=k != "fits"), k
        assert s.binding.tolist() == one.binding.tolist()
        assert lim == m.speed_limit()


def test_sweep_over_a_whole_number_key():
    m = cm.Machine.from_toml(EXAMPLES / ROTOR)
    r = cm.sweep(m, {"line.pockets_t": [6, 8], "speed_rpm": [100.0]}, progress=False)
    want = [m.with_values({"line.pockets_t": p}).speed_limit().rpm for p in (6, 8)]
    assert r.columns["speed_limit_rpm"].tolist() == want


# --------------------------------------------------------------------- 4. pickling
@pytest.mark.parametrize("name", MACHINE_FILES)
def test_machine_and_speed_sweep_pickle(name):
    m = cm.Machine.from_toml(EXAMPLES / name)
    back = pickle.loads(pickle.dumps(m))
    assert isinstance(back, cm.Machine)
    assert back.name == m.name and back.data == m.data
    assert list(back.mechanisms) == list(m.mechanisms)
    rpm = m.speed_grid()[::10]
    s, s2 = m.speed_sweep(rpm), back.speed_sweep(rpm)
    for key in (
        "rpm",
        "fits",
        "limiting_deg",
        "limiting_s",
        "productivity_per_min",
        "max_rebound_m",
    ):
        assert same_bits(getattr(s2, key), getattr(s, key)), key
    s3 = pickle.loads(pickle.dumps(s))
    assert type(s3) is type(s)
    for key in (
        "rpm",
        "fits",
        "limiting_deg",
        "limiting_s",
        "productivity_per_min",
        "max_rebound_m",
    ):
        assert same_bits(getattr(s3, key), getattr(s, key)), key
    assert s3.binding.tolist() == s.binding.tolist()
    assert list(s3.min_phase_deg) == list(s.min_phase_deg)
    for k, v in s.min_phase_deg.items():
        assert same_bits(s3.min_phase_deg[k], v)
    assert back.speed_limit() == m.speed_limit()


def test_sweep_result_pickles(loom_sweep):
    _, r = loom_sweep
    back = pickle.loads(pickle.dumps(r))
    assert type(back) is cm.SweepResult
    assert back.parameters == r.parameters and back.seconds == r.seconds
    assert list(back.columns) == list(r.columns)
    for k, v in r.columns.items():
        if v.dtype == object:
            assert back.columns[k].tolist() == v.tolist()
        else:
            assert same_bits(back.columns[k], v), k
