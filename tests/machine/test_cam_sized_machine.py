"""A machine whose cam asks to be sized ([mechanism.X.synthesize]): the fixed point of
timing and size, checked from outside the loop, and the file's bad input."""

from __future__ import annotations

import copy
import math
import tomllib
import warnings
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine import _resize, analyze
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[2]
FILE = ROOT / "examples" / "lifter_cam_sized.toml"
CAM = "lifter cam"


def data() -> dict:
    return tomllib.loads(FILE.read_text("utf-8"))


@pytest.fixture(scope="module")
def result():
    return analyze(cm.Machine.from_toml(FILE), progress=False)


def test_fixed_point_rerunning_the_lp_gives_the_same_timing(result) -> None:
    """The LP re-run with the final radius gives the same timing, and sizing at that
    timing gives the same radius: both hold."""
    z = result.resizing
    assert z.converged and 1 < z.rounds < _resize.MAX_ROUNDS and result.failures == []
    m = result.machine
    mech = m.mechanisms[CAM]
    rb = mech.design.cam.follower.base_radius
    assert rb == z.history[-1]["sizes"][CAM]["base_radius_m"]
    again = m.optimize(result.nominal_rpm)
    for arc, v in result.optimum.angles.items():
        assert again.angles[arc] == pytest.approx(v, abs=1e-9)
    assert mech.resize(result.nominal_rpm, again.angles) is None  # the size repeats
    cam, _ = mech.laid_out(again.angles)
    d = mech.design
    r = cm.synthesis.cam_size(
        cam,
        result.nominal_rpm,
        limits=cm.synthesis.CamLimits(d.max_pressure_angle_deg, d.max_stress),
        loads=d.loads,
        contact=d.contact,
        max_base_radius=0.09,
        min_base_radius=0.02,
    )
    assert r.base_radius == pytest.approx(rb, rel=1e-9)
    # The file's own first round started from the largest radius asked.
    assert cm.Machine.from_toml(FILE).mechanisms[CAM].design.cam.follower.base_radius == 0.09


def test_binding_limit_holds_with_equality_brentq(result) -> None:
    """At the optimum's timing, brentq on Cam.solve's pressure angle finds the radius
    the run chose; 0.1 % smaller violates the limit."""
    mech = result.machine.mechanisms[CAM]
    assert mech.sized.binding == "pressure_angle"
    cam = result.mechanisms[CAM].cam  # laid out at the optimum
    f = cam.follower
    theta = np.linspace(0.0, 2.0 * math.pi, 40001)

    def worst(rb: float) -> float:
        c = cm.cam.Cam(
            list(cam.segments),
            cm.cam.OscillatingRoller(f.pivot_distance, f.arm_length, rb, f.roller_radius),
            cam.closure,
        )
        return float(np.degrees(np.abs(c.solve(theta).pressure_angle)).max())

    rb = f.base_radius
    ref = brentq(lambda r: worst(r) - 45.0, 0.9 * rb, 1.1 * rb, xtol=1e-13)
    assert rb == pytest.approx(ref, rel=1e-6)  # the grid's max, not Brent's
    assert worst(rb * 0.999) > 45.0
    assert result.mechanisms[CAM].problems() == []


def test_results_json_and_report_say_what_was_chosen(result, tmp_path: Path) -> None:
    cm.machine.write_report(result, tmp_path, figures=False)
    import json

    d = json.loads((tmp_path / "results.json").read_text("utf-8"))
    s = d["cams"][CAM]["sizing"]
    assert s["binding"] == "pressure_angle" and s["status"] == "ok"
    assert s["margins"]["pressure_angle"] == pytest.approx(0.0, abs=1e-9)
    assert d["resizing"]["converged"] is True
    rows = dict(result.mechanisms[CAM].table()[1])
    assert "pressure angle binds" in rows["sized (synthesize)"]


def test_no_fixed_point_is_a_loud_failure(monkeypatch, tmp_path: Path, capsys) -> None:
    """One round allowed: the loop cannot confirm its fixed point; it warns, the run
    fails (exit status 3) and says why."""
    monkeypatch.setattr(_resize, "MAX_ROUNDS", 1)
    with pytest.warns(cm.CyclomechWarning, match="no fixed point after 1 rounds"):
        r = analyze(cm.Machine.from_toml(FILE), progress=False)
    assert not r.resizing.converged
    assert any("sizing: no fixed point" in t for t in r.failures)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the CLI reports it on stderr, checked below
        code = main(["run", str(FILE), "--out", str(tmp_path), "--no-plot", "--quiet"])
    assert code == 3
    out = capsys.readouterr()
    assert "NO fixed point" in out.out
    assert "sizing: no fixed point" in out.err


def _with(**synth) -> dict:
    d = copy.deepcopy(data())
    d["mechanism"][CAM]["synthesize"].update(synth)
    return d


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda d: d["mechanism"][CAM].update(base_radius_m=0.05), "drop base_radius_m"),
        (
            lambda d: d["mechanism"][CAM]["synthesize"].update(base_radius="largest"),
            r"must be one of \['smallest'\]",
        ),
        (lambda d: d["mechanism"][CAM]["synthesize"].update(offset_m=[0.0, 0.01]), "drop offset_m"),
        (
            lambda d: d["mechanism"][CAM]["synthesize"].update(max_base_radius_m=-0.1),
            "max_base_radius_m = -0.1 must be positive",
        ),
        (
            lambda d: d["mechanism"][CAM]["synthesize"].update(min_base_radius_m=0.1),
            "must be < max_base_radius_m",
        ),
        (
            lambda d: d["mechanism"][CAM]["synthesize"].update(pivot_distance_m=[0.2, 0.1]),
            "low < high",
        ),
        (lambda d: d["mechanism"][CAM]["synthesize"].update(bogus=1), "bogus"),
        (lambda d: d["mechanism"][CAM]["synthesize"].pop("max_base_radius_m"), "max_base_radius_m"),
    ],
)
def test_bad_synthesize_tables(change, match: str) -> None:
    d = copy.deepcopy(data())
    change(d)
    with pytest.raises(cm.InputError, match=match):
        cm.Machine.from_dict(d, "f.toml")


def test_unreachable_limits_name_the_requirement() -> None:
    """A stress limit the cam cannot meet even at its largest radius: the first
    round's LP does not fit; the run fails and the sizing says it was at the largest
    radius asked."""
    d = copy.deepcopy(data())
    d["mechanism"][CAM]["max_stress_pa"] = 1e8
    m = cm.Machine.from_dict(d, "f.toml")
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        r = analyze(m, progress=False)
    assert any("max_base_radius_m" in str(w.message) for w in seen)
    assert r.optimum is None and "σ_H[lifter cam" in r.problem
    assert not r.resizing.converged
    assert any("largest size" in t and "max_base_radius_m" in t for t in r.failures)


def test_a_pivot_search_in_the_file() -> None:
    """The pivot distance searched (the arm held): a radius no larger than with the
    pivot held, the chosen pivot inside the range, still a fixed point."""
    d = _with(pivot_distance_m=[0.11, 0.16])
    r = analyze(cm.Machine.from_dict(d, "f.toml"), progress=False)
    held = analyze(cm.Machine.from_toml(FILE), progress=False)
    f = r.machine.mechanisms[CAM].design.cam.follower
    assert r.resizing.converged
    assert 0.11 <= f.pivot_distance <= 0.16 and f.arm_length == 0.1
    held_rb = held.machine.mechanisms[CAM].design.cam.follower.base_radius
    assert f.base_radius <= held_rb * (1 + 1e-9)
    assert set(r.resizing.history[-1]["sizes"][CAM]) == {"base_radius_m", "pivot_distance_m"}


def test_a_radius_in_millimetres_is_warned_of() -> None:
    """max_base_radius_m = 90 (mm given as m) is not absorbed: the unit-suffix rule of
    every other table warns, naming the slip, before the geometry refuses it."""
    d = copy.deepcopy(data())
    d["mechanism"][CAM]["synthesize"]["max_base_radius_m"] = 90.0
    with (
        pytest.warns(cm.CyclomechWarning, match=r"max_base_radius_m = 90.0 m .*millimetres"),
        pytest.raises(cm.InputError, match="cannot reach"),
    ):
        cm.Machine.from_dict(d, "f.toml")
