"""Tests of ``cyclomech impact FILE.toml [--out DIR] [--no-plot]``, the impact file
format (:class:`cyclomech.impact.ImpactStudy`) and the impact figures.

The tables are checked against the closed form of the pulse model: its rebound is
proportional to the impact speed v0 = ω·stroke·Z'(j*)/t, so a(n, t) = a(n0, t0)·
(n/n0)·(t0/t), and the smallest phase angle for a limit a_max is t0·a(n, t0)/a_max.
"""

from __future__ import annotations

import json
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from numpy.testing import assert_allclose

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

SMALL = """
[stop]
name = "small lifter"
stroke_m = 0.0094
preload_m = 0.00025
lever_length_m = 0.1
J_A_kg_m2 = 7.4e-5
a_m = 0.05
b_m = 0.1
E_pa = 2.1e11
J_x_m4 = 6.14e-11

[study]
rpm = [280, 420, 3]
phase_deg = [30, 50, 5]
a_max_m = 1e-4
arc = ["3", "7"]
"""


def _write(tmp_path: Path, text: str) -> Path:
    f = tmp_path / "lifter.toml"
    f.write_text(text, encoding="utf-8")
    return f


def test_tables_follow_the_pulse_models_scaling(tmp_path, capsys):
    f = _write(tmp_path, SMALL)
    code = main(["impact", str(f), "--out", str(tmp_path / "out"), "--no-plot"])
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    assert "small lifter" in out and "297" in out and "t(3,7) >=" in out
    reb = np.genfromtxt(tmp_path / "out" / "rebound.csv", delimiter=",", names=True)
    assert len(reb) == 15
    n, t, a = reb["rpm"], reb["phase_deg"], reb["rebound_mm"]
    ref = a[0] * (n / n[0]) * (t[0] / t)  # proportional to v0 ∝ n/t
    assert_allclose(a, ref, rtol=1e-9)
    v0 = reb["impact_speed_m_per_s"]
    assert_allclose(v0, v0[0] * (n / n[0]) * (t[0] / t), rtol=1e-10)  # CSV: 12 digits
    mins = np.genfromtxt(tmp_path / "out" / "min_phase.csv", delimiter=",", names=True)
    a30 = a[t == 30.0] * 1e-3  # m, per speed
    assert_allclose(mins[mins.dtype.names[1]], 30.0 * a30 / 1e-4, rtol=1e-8)
    data = json.loads((tmp_path / "out" / "impact.json").read_text())
    assert data["schema"] == "cyclomech.impact/1" and data["model"] == "pulse"
    assert abs(data["free_hz"] - 297) < 1 and data["contact_hz"] > data["free_hz"]
    assert data["linearized"]["slope_m_per_deg"] < 0
    assert data["constraint"]["text"].startswith("1·t(3,7) >= ")


def test_example_runs_with_figures(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    out_dir = tmp_path / "lifter"
    code = main(["impact", str(EXAMPLES / "stb_lifter.toml"), "--out", str(out_dir)])
    assert code == 0
    for name in ("rebound.csv", "min_phase.csv", "impact.json", "rebound_vs_speed.png"):
        assert (out_dir / name).stat().st_size > 0
    assert (out_dir / "response.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (("stroke_m = 0.0094", "strok_m = 0.0094"), ["[stop]", "unknown key 'strok_m'"]),
        (("stroke_m = 0.0094\n", ""), ["[stop]", "missing key 'stroke_m'"]),
        (("stroke_m = 0.0094", "stroke = 0.0094"), ["[stop]", "`stroke` is now `stroke_m`"]),
        (("restitution", "x"), []),  # absent key: not an edit, default used (checked below)
        (("J_A_kg_m2 = 7.4e-5", 'J_A_kg_m2 = "heavy"'), ["[stop]", "J_A_kg_m2", "a number"]),
        (("preload_m = 0.00025", "preload_m = 0.02"), ["[stop]", "preload_m", "than stroke_m"]),
        (("rpm = [280, 420, 3]", "rpm = [280, 420]"), ["[study]", "rpm", "[from, to, count]"]),
        (("phase_deg = [30, 50, 5]", "phase_deg = [30, 400, 5]"), ["[study]", "phase_deg"]),
        (("a_max_m = 1e-4", "a_max_m = -1e-4"), ["[study]", "a_max_m"]),
        (('arc = ["3", "7"]', 'arc = ["3"]'), ["[study]", "arc"]),
    ],
)
def test_bad_files_name_the_table_and_key(tmp_path, capsys, edit, words):
    text = SMALL.replace(*edit)
    f = _write(tmp_path, text)
    code = main(["impact", str(f), "--out", str(tmp_path / "out"), "--no-plot"])
    err = capsys.readouterr().err
    if not words:
        assert code == 0 and err == ""
        st = cm.impact.ImpactStudy.from_toml(f)
        assert st.stop.restitution == pytest.approx(5 / 9)
        return
    assert code == 2
    assert str(f) in err
    for w in words:
        assert w in err, (w, err)


def test_missing_file_and_table(tmp_path, capsys):
    assert main(["impact", str(tmp_path / "none.toml"), "--no-plot"]) == 2
    assert "no such file" in capsys.readouterr().err
    f = _write(tmp_path, SMALL.split("[study]")[0])
    assert main(["impact", str(f), "--no-plot"]) == 2
    assert "missing table [study]" in capsys.readouterr().err


def test_figures_hold_the_models_numbers():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from cyclomech.plot import plot_rebound_vs_speed, plot_response

    lifter = cm.impact.StopImpact.example()
    rpm = np.array([250.0, 300.0, 350.0, 400.0])
    fig = plot_rebound_vs_speed(lifter, rpm, phase_deg=[35, 45], a_max=1e-4)
    right = fig.axes[1]
    for ph in (35, 45):
        line = next(ln for ln in right.get_lines() if ln.get_gid() == f"rebound:{ph}")
        assert_allclose(line.get_ydata(), lifter.rebound(rpm, float(ph)) * 1e3, rtol=1e-12)
    limit = next(ln for ln in right.get_lines() if ln.get_gid() == "a_max")
    assert limit.get_ydata()[0] == pytest.approx(0.1)
    left = fig.axes[0]
    shown = [ln for ln in left.get_lines() if str(ln.get_gid()).startswith("response:")]
    assert len(shown) == 3
    plt.close(fig)
    t, q = lifter.response(300, 40.0)
    ax = plot_response(t, q, force=np.zeros_like(t), rebound=(float(t[q.argmax()]), q.max()))
    (line,) = [ln for ln in ax.get_lines() if ln.get_gid() == "q"]
    assert_allclose(line.get_ydata(), q * 1e3)
    dot = next(ln for ln in ax.get_lines() if ln.get_gid() == "rebound")
    assert dot.get_ydata()[0] == pytest.approx(float(lifter.rebound(300, 40.0)) * 1e3, rel=1e-6)
    plt.close(ax.figure)
    with pytest.raises(cm.InputError, match="shapes"):
        plot_response(t, q[:-1])
    with pytest.raises(cm.InputError, match="rpm"):
        plot_rebound_vs_speed(lifter, [300.0])
