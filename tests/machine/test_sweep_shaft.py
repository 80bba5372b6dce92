"""The main shaft's columns of a sweep (issue 20): at every point, the statistics
of the design's main-shaft torque, the ``cyclomech run`` report's own numbers at
the same speeds; NaN without a mechanism that loads the shaft."""

from __future__ import annotations

import json
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine import analyze
from cyclomech.machine._sweep_shaft import SHAFT_COLUMNS

ROOT = Path(__file__).parents[2]
LOOM_CAM = ROOT / "examples" / "stb_loom.toml"
LOOM = Path(__file__).parent / "data" / "stb_loom_stop_only.toml"


@pytest.fixture(scope="module")
def loom() -> cm.Machine:
    return cm.Machine.from_toml(LOOM_CAM)


def test_the_columns_are_the_run_reports(loom, cli_run) -> None:
    run = cli_run(LOOM_CAM, "--no-plot", "--quiet")
    assert run.code == 0
    shaft = json.loads((run.out / "results.json").read_text())["shaft"]
    rpm = np.array(shaft["speed_rpm"])
    r = cm.sweep(loom, {"speed_rpm": rpm}, progress=False, shaft=True)
    assert np.array_equal(r.columns["shaft_peak_torque_nm"], shaft["peak_torque_nm_over_speed"])
    assert np.array_equal(r.columns["shaft_flywheel_kg_m2"], shaft["flywheel_kg_m2_over_speed"])
    # At the nominal speed, the report's table: mean, RMS, power too.
    at = cm.sweep(loom, {"speed_rpm": [shaft["nominal_rpm"]]}, progress=False, shaft=True)
    at = at.columns
    for col, key in SHAFT_COLUMNS.items():
        assert at[col][0] == shaft[key], col
    # Independent: the motor's power is the mean torque times ω.
    w = rpm * 2 * np.pi / 60
    np.testing.assert_allclose(r.columns["shaft_power_w"], r.columns["shaft_mean_torque_nm"] * w)


def test_each_design_is_its_own_analysis(loom) -> None:
    g = {"lifter.preload_m": [2e-4, 3e-4, 2e-2], "speed_rpm": [250.0, 350.0]}
    r = cm.sweep(loom, g, progress=False, shaft=True)
    for d, p in enumerate(g["lifter.preload_m"][:2]):
        m = loom.with_values({"lifter.preload_m": p})
        st = analyze(m, progress=False).shaft.torque.stats(g["speed_rpm"], m.speed_fluctuation)
        for col, key in SHAFT_COLUMNS.items():
            assert np.array_equal(r.columns[col][2 * d : 2 * d + 2], getattr(st, key)), col
    peak = r.columns["shaft_peak_torque_nm"]
    assert np.isfinite(peak[:4]).all() and peak[1] > peak[0]  # ∝ ω² mostly
    assert np.isnan(peak[4:]).all() and r.n_invalid == 2  # preload beyond the stroke


def test_asked_for_only_and_nan_without_a_shaft(loom, tmp_path) -> None:
    g = {"speed_rpm": [300.0, 400.0]}
    assert not set(SHAFT_COLUMNS) & set(cm.sweep(loom, g, progress=False).columns)
    r = cm.sweep(cm.Machine.from_toml(LOOM), g, progress=False, shaft=True)
    for col in SHAFT_COLUMNS:
        assert np.isnan(r.columns[col]).all()
    back = cm.SweepResult.read(r.write(tmp_path / "s.npz"))
    assert back.parameters == () and set(SHAFT_COLUMNS) <= set(back.columns)
    with pytest.raises(cm.InputError, match="shaft must be True or False"):
        cm.sweep(loom, g, shaft="yes")  # type: ignore[arg-type]
    # cyclomech sweep --shaft streams them too.
    out = tmp_path / "cli"
    argv = ["sweep", str(LOOM_CAM), "--speed", "300", "--shaft", "--quiet", "--out", str(out)]
    assert main(argv) == 0
    got = cm.SweepResult.read(out / "sweep.parquet").columns
    assert np.isfinite(got["shaft_peak_torque_nm"]).all()
