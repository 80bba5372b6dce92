"""Tests of ``cyclomech transfer FILE.toml``, the rotor transfer's command.

References independent of the command: the peripheral speeds V = 2π·R·n/(60·z) and
the jump without transitions ΔW = V_t²/R_t + V_p²/R_p in closed form; the normal
acceleration on the two arcs V²/R; the points of the arcs on the pitch circles;
the peak jerk's n³ law between two runs; and the machine command (``cyclomech
run``) on the machine file that holds the same transfer, a peer for the speed
limit.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cyclomech.cli import main
from numpy.testing import assert_allclose

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "rotor_transfer.toml"
R_T, R_P, GAP, Z_T, Z_P = 0.15, 0.25, 0.01, 8, 12


def _results(out: Path) -> dict:
    return json.loads((out / "results.json").read_text(encoding="utf-8"))


def test_the_real_command_writes_its_files_and_closed_form_numbers(tmp_path):
    out = tmp_path / "out"
    # The interpreter's own cyclomech (installed, or editable), not the source tree:
    # a wheel's test has no compiled core in python/.
    run = subprocess.run(
        [sys.executable, "-m", "cyclomech", "transfer", str(EXAMPLE), "--out", str(out)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    assert "peak jerk" in run.stdout and "speed limit" in run.stdout
    names = {"path.csv", "results.json"}
    try:
        import matplotlib  # noqa: F401

        names.add("transfer.png")
    except ImportError:
        pass
    assert names <= {p.name for p in out.iterdir()}
    r = _results(out)
    n = r["rpm"]
    v_t = 2 * math.pi * R_T * n / (60 * Z_T)
    v_p = 2 * math.pi * R_P * n / (60 * Z_P)
    assert_allclose(r["speeds_m_per_s"], [v_t, v_p], rtol=1e-12)
    assert_allclose(r["jump_m_per_s2"], v_t**2 / R_T + v_p**2 / R_P, rtol=1e-12)
    assert r["works"] is True
    path = np.genfromtxt(out / "path.csv", delimiter=",", names=True)
    # On the arcs the workpiece turns with the rotors: a_n = V²/R, on the circles.
    assert_allclose(path["normal_acceleration_m_per_s2"][0], v_t**2 / R_T, rtol=1e-9)
    assert_allclose(path["normal_acceleration_m_per_s2"][-1], -(v_p**2) / R_P, rtol=1e-9)
    first = np.hypot(path["x_m"][0], path["y_m"][0])
    last = np.hypot(path["x_m"][-1] - (R_T + R_P + GAP), path["y_m"][-1])
    assert_allclose([first, last], [R_T, R_P], rtol=1e-9)


def test_jerk_grows_as_the_cube_of_speed_and_the_limit_is_the_machines(tmp_path):
    codes = {}
    for rpm in (60, 150):
        codes[rpm] = main(
            [
                *("transfer", str(EXAMPLE), "--out", str(tmp_path / str(rpm))),
                *("--rpm", str(rpm), "--no-plot", "--samples", "2001"),
            ]
        )
    assert codes == {60: 0, 150: 0}
    a, b = _results(tmp_path / "60"), _results(tmp_path / "150")
    assert_allclose(b["max_jerk_m_per_s3"] / a["max_jerk_m_per_s3"], 2.5**3, rtol=1e-9)
    assert_allclose(b["max_acceleration_m_per_s2"] / a["max_acceleration_m_per_s2"], 2.5**2)
    # The peer: the machine file rotor_line.toml holds the same transfer.
    m = tmp_path / "machine"
    assert main(["run", str(ROOT / "examples" / "rotor_line.toml"), "--out", str(m)]) in (0, 3)
    machine = json.loads((m / "results.json").read_text(encoding="utf-8"))
    line = machine["mechanisms"]["line"]
    assert_allclose(a["speed_limit_rpm"], line["speed_limit_rpm"], rtol=1e-12)
    assert_allclose(a["x2_m"], line["x2_m"], rtol=1e-12)
    # At its speed limit the jerk is the file's limit, by the n³ law from 60 rpm.
    limit = a["speed_limit_rpm"]
    assert_allclose(a["max_jerk_m_per_s3"] * (limit / 60) ** 3, 10.0, rtol=1e-9)


def test_above_the_speed_limit_the_files_are_written_and_the_status_is_3(tmp_path, capsys):
    out = tmp_path / "fast"
    code = main(["transfer", str(EXAMPLE), "--out", str(out), "--rpm", "300", "--no-plot"])
    text = capsys.readouterr().out
    assert code == 3
    assert "FAILS: 300 rpm is above the speed limit" in text and "max_jerk" in text
    assert _results(out)["works"] is False and (out / "path.csv").exists()


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (("gap_m = 0.01", "gap_m = -0.01"), "[transfer]: gap_m = -0.01 must be positive"),
        (("pockets_t = 8", "pockets_t = 0"), "[transfer]: pockets_t = 0 must be a whole"),
        (("rpm = 120.0", "rpm_x = 120.0"), "[transfer]: unknown key 'rpm_x'"),
        (("R_t_m = 0.15", "# R_t_m"), "[transfer]: missing"),
    ],
)
def test_bad_input_names_the_file_the_table_and_the_key(tmp_path, capsys, edit, message):
    f = tmp_path / "t.toml"
    f.write_text(EXAMPLE.read_text(encoding="utf-8").replace(*edit), encoding="utf-8")
    assert main(["transfer", str(f), "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert str(f) in err and message in err


def test_each_file_names_its_command(tmp_path, capsys):
    line = ROOT / "examples" / "rotor_line.toml"
    assert main(["transfer", str(line), "--out", str(tmp_path / "a")]) == 2
    assert f"run it with `cyclomech run {line}`" in capsys.readouterr().err
    assert main(["run", str(EXAMPLE), "--out", str(tmp_path / "b")]) == 2
    assert f"run it with `cyclomech transfer {EXAMPLE}`" in capsys.readouterr().err
