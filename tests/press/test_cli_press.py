"""Tests of ``cyclomech press FILE.toml [--out DIR] [--step-deg S] [--no-plot]``.

The tables are checked against direct calls and, for the crank-slider column,
against the closed form of the crank-slider press (S_n = 2a, J_max = ω²a(1 + a/L)).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from numpy.testing import assert_allclose

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

SMALL = """
[press]
name = "small"
R_m = 0.09
r_m = 0.03
d_m = 0.029
L_m = 0.25
phi0_deg = 55.95

[working]
k_Sp = 0.1
rpm = 40.0
"""


def _write(tmp_path: Path, text: str) -> Path:
    f = tmp_path / "press.toml"
    f.write_text(text, encoding="utf-8")
    return f


def test_design_tables_match_direct_calls(tmp_path, capsys):
    f = _write(tmp_path, SMALL)
    code = main(["press", str(f), "--out", str(tmp_path / "out"), "--no-plot", "--step-deg", "2"])
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    assert "i = 3" in out and "k_Vp" in out
    st = cm.press.PressStudy.from_toml(f)
    w = 2 * math.pi * 40 / 60
    kin = np.genfromtxt(tmp_path / "out" / "kinematics.csv", delimiter=",", names=True)
    assert len(kin) == 181 and kin["alpha_deg"][-1] == 360
    k = st.press.solve(np.radians(kin["alpha_deg"]))
    assert_allclose(kin["S_m"], k.s, rtol=1e-11, atol=1e-14)
    assert_allclose(kin["V_m_per_s"], k.ds * w, rtol=1e-11, atol=1e-14)
    assert_allclose(kin["J_m_per_s2"], k.dds * w * w, rtol=1e-11, atol=1e-14)
    crit = np.genfromtxt(tmp_path / "out" / "criteria.csv", delimiter=",", names=True, dtype=None)
    design, base = crit[0], crit[1]
    c = st.press.criteria(k_Sp=0.1, omega=w)
    assert_allclose(design["k_Vp"], c.k_Vp, rtol=1e-10)
    # The baseline column is the crank-slider of the same gears and rod.
    a, L = 0.06, 0.25
    assert_allclose(base["S_n_m"], 2 * a, rtol=1e-12)
    assert_allclose(base["J_max_m_per_s2"], w * w * a * (1 + a / L), rtol=1e-10)
    # Angles in degrees, as the screen shows them, with the unit in the name.
    assert_allclose(design["alpha_p_deg"], math.degrees(c.alpha_p), rtol=1e-11)
    assert_allclose(design["theta_bdc_deg"], math.degrees(c.theta_bdc), rtol=1e-11)
    summary = json.loads((tmp_path / "out" / "press.json").read_text())
    assert summary["schema"] == "cyclomech.press/2"
    assert summary["design"]["d_m"] == 0.029 and "optimum" not in summary
    assert summary["criteria"]["alpha_p_deg"] == pytest.approx(math.degrees(c.alpha_p))
    # The slow start of the working stroke that the drive is for.
    assert c.k_Vp < 0.15 < 1.9 < summary["crank_slider"]["k_Vp"]


def test_example_with_sweep_writes_front_and_figures(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    text = (EXAMPLES / "extrusion_press.toml").read_text(encoding="utf-8")
    # A smaller grid than the example's, to keep the test quick.
    # (so a looser limit: the coarse grid misses the narrow band of slow starts).
    text = (
        text.replace("[0.0, 0.04, 41]", "[0.0, 0.04, 11]")
        .replace("[0.2, 0.5, 31]", "[0.2, 0.5, 6]")
        .replace("V_np = 0.01 ", "V_np = 0.05 ")
    )
    f = _write(tmp_path, text)
    code = main(["press", str(f), "--out", str(tmp_path / "o")])
    out, _ = capsys.readouterr()
    assert code == 0
    assert "non-dominated designs within the limits" in out
    for name in ("sweep.csv", "pareto.csv", "press.png", "criteria.png", "press.json"):
        assert (tmp_path / "o" / name).stat().st_size > 0
    with (tmp_path / "o" / "sweep.csv").open(newline="", encoding="utf-8") as fh:
        sweep = list(csv.DictReader(fh))
    assert len(sweep) == 11 * 6 * 60
    # Units in the names, φ0 in degrees as the file gives it, the status as text.
    assert {"d_m", "L_m", "phi0_deg", "alpha_p_deg", "V_np_m_per_s", "status"} <= set(sweep[0])
    phi0 = sorted({float(r["phi0_deg"]) for r in sweep})
    assert phi0[0] == 0.0 and phi0[-1] == pytest.approx(118.0)
    assert {r["status"] for r in sweep} <= set(cm.press.STATUS.values())
    front = np.genfromtxt(tmp_path / "o" / "pareto.csv", delimiter=",", names=True, ndmin=1)
    # Every design of the front meets the limit V_np <= 50 mm/s.
    assert (front["V_np_m_per_s"] <= 0.05 + 1e-15).all()
    summary = json.loads((tmp_path / "o" / "press.json").read_text())
    assert summary["optimum"]["non_dominated"] == len(front)
    assert summary["optimum"]["designs_swept"] == 11 * 6 * 60


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("R_m = 0.09", "R_m = 0.1"), "R/r"),
        (("d_m = 0.029", "d_m = -0.01"), "[press]: d_m = -0.01"),
        (("rpm = 40.0", "rpm = 0"), "[working]: rpm = 0"),
        (("k_Sp = 0.1", "k_Sp = 1.5"), "k_Sp = 1.5"),
        (("k_Sp = 0.1", "working_stroke_m = 0.01\nk_Sp = 0.1"), "exactly one of k_Sp"),
        (("phi0_deg = 55.95", "phi0 = 55.95"), "unknown key 'phi0'"),
        (("L_m = 0.25", 'L_m = "long"'), "L_m = 'long' must be a finite number"),
        (("L_m = 0.25", "L = 0.25"), "[press]: `L` is now `L_m` (metres)"),
        (("[working]", "[work]"), "unknown key 'work'"),
    ],
)
def test_bad_files_exit_2_naming_file_table_and_key(tmp_path, capsys, change, message):
    f = _write(tmp_path, SMALL.replace(*change))
    code = main(["press", str(f), "--out", str(tmp_path / "o"), "--no-plot"])
    err = capsys.readouterr().err
    assert code == 2
    assert str(f) in err and message in err, err


def test_bad_sweep_spec_and_limits(tmp_path, capsys):
    f = _write(tmp_path, SMALL + "[sweep]\nd_m = [0.0, 0.04]\n")
    assert main(["press", str(f), "--no-plot", "--out", str(tmp_path / "o")]) == 2
    assert "[sweep]: d_m = [0.0, 0.04] must be [from, to, count]" in capsys.readouterr().err
    f = _write(tmp_path, SMALL + "[limits]\nV_start = 0.01\n")
    assert main(["press", str(f), "--no-plot", "--out", str(tmp_path / "o")]) == 2
    assert "[limits]: unknown key 'V_start'" in capsys.readouterr().err


def test_limits_no_design_meets_exit_2(tmp_path, capsys):
    f = _write(tmp_path, SMALL + "[sweep]\nd_m = [0.0, 0.01, 3]\n[limits]\nV_np = 0.001\n")
    assert main(["press", str(f), "--no-plot", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "no design of the grid works within the limits {'V_np': 0.001}" in err


def test_a_design_that_cannot_be_assembled_exits_3(tmp_path, capsys):
    # The rod is shorter than the pin's sideways reach: it cannot reach the guide.
    f = _write(tmp_path, SMALL.replace("L_m = 0.25", "L_m = 0.05"))
    code = main(["press", str(f), "--no-plot", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 3  # a design that fails, as every command's
    assert "the rod cannot reach the guide" in err
