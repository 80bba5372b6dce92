"""Tests of the command line: ``cyclomech cyclogram FILE.toml [--out DIR]``.

The expected numbers for ``examples/stb_group1.toml`` are worked out by hand from
the file (angles in degrees, the main shaft at 300 rpm):

* schedule: weft insertion takes max(120, 6·300·0.1) = 180°; the longest chain to
  its start is 1→3→2→5→6→10.1 = 45 + 20 + 15 + 15 + 0 = 95°, so 275° in all;
* optimum: the rebound constraint makes t(3,7) >= 0.108 / 0.003 = 36°, the chain
  1→3→7→10.1 becomes 45 + 36 + 20 = 101°, and weft insertion gets 360 - 101 = 259°;
* speed limit: 101 + 6·n·0.1 = 360 gives n = 259 / 0.6 = 431.67 rpm; without the
  constraint the chain is 95° and n = 265 / 0.6 = 441.67 rpm.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path
from typing import Any

import pytest
from cyclomech.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "stb_group1.toml"

GROUP_DEG = 45.0 + 36.0 + 20.0  # 1→3→7→10.1 with t(3,7) raised to 36°
RPM = (360.0 - GROUP_DEG) / (6 * 0.1)  # 431.67
NETWORK_RPM = (360.0 - 95.0) / (6 * 0.1)  # 441.67


def run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def read_summary(folder: Path) -> dict[str, Any]:
    return json.loads((folder / "cyclogram.json").read_text(encoding="utf-8"))


def test_example_prints_and_writes_summary(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = run(["cyclogram", str(EXAMPLE), "--out", str(tmp_path), "--no-plot"], capsys)
    assert code == 0, err
    assert err == ""
    assert "10 events, 11 operations, 1 constraints" in out
    assert "duration 275.0° of the 360° cycle" in out
    assert "'weft insertion' gets 259.00°" in out
    assert f"{RPM:.2f}" == "431.67"
    assert "Speed limit: 431.67 rpm" in out
    assert f"{NETWORK_RPM:.2f} rpm" in out
    assert not (tmp_path / "cyclogram.png").exists()

    summary = read_summary(tmp_path)
    assert summary["schema"] == "cyclomech.cyclogram/1"
    assert summary["cycle_deg"] == 360.0 and summary["speed_rpm"] == 300.0
    assert summary["schedule"]["duration_deg"] == pytest.approx(275.0)
    assert summary["schedule"]["angles_deg"]["10.1→10.2"] == pytest.approx(180.0)
    opt = summary["optimum"]
    assert opt["goal"] == "max_limiting" and opt["limiting"] == "10.1→10.2"
    assert opt["objective_deg"] == pytest.approx(360.0 - GROUP_DEG, abs=1e-6)
    assert opt["angles_deg"]["3→7"] == pytest.approx(36.0, abs=1e-6)
    assert opt["duals"]["lifter rebound <= 0.1 mm"] == pytest.approx(1 / 0.003, rel=1e-6)
    lim = summary["speed_limit"]
    assert lim["rpm"] == pytest.approx(RPM, rel=1e-9)
    assert lim["network_rpm"] == pytest.approx(NETWORK_RPM, rel=1e-9)
    # The chain that fills the cycle at the limit, by hand: lift 45° + rebound-held
    # approach 36° + 20° + insertion 6·n·0.1 s = 360° (3→7 is held by the constraint).
    assert lim["chain"] == ["1→3", "3→7", "7→10.1", "10.1→10.2"]


def test_summary_binding_is_a_list(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["cyclogram", str(EXAMPLE), "--out", str(tmp_path), "--no-plot"], capsys)[0] == 0
    # The rebound constraint and the cycle price the speed limit (see the module
    # docstring). Formerly a bug: any two-item list of names was written as "a→b".
    assert read_summary(tmp_path)["speed_limit"]["binding"] == ["lifter rebound <= 0.1 mm", "cycle"]


def test_example_writes_a_figure(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("cyclomech.plot")
    code, out, err = run(["cyclogram", str(EXAMPLE), "--out", str(tmp_path)], capsys)
    assert code == 0, err
    png = tmp_path / "cyclogram.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert str(png) in out


def test_speed_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # At 100 rpm weft insertion takes max(120, 6·100·0.1 = 60) = 120°: 95 + 120 = 215°.
    argv = ["cyclogram", str(EXAMPLE), "--out", str(tmp_path), "--no-plot", "--speed", "100"]
    code, out, _ = run(argv, capsys)
    assert code == 0
    assert "(at 100 rpm)" in out and "duration 215.0°" in out
    assert read_summary(tmp_path)["speed_rpm"] == 100.0


def test_default_output_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    assert run(["cyclogram", str(EXAMPLE), "--no-plot"], capsys)[0] == 0
    assert read_summary(tmp_path / "out" / "stb_group1")["schema"] == "cyclomech.cyclogram/1"


def test_infeasible_optimum_is_reported_with_exit_code_3(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # 1 -> 2 -> 3 takes 100 + 100 = 200° of a 150° cycle.
    path = tmp_path / "tight.toml"
    path.write_text(
        "[cyclogram]\ncycle_deg = 150.0\n"
        '[[operation]]\nfrom = "1"\nto = "2"\nmin_angle_deg = 100.0\n'
        '[[operation]]\nfrom = "2"\nto = "3"\nmin_angle_deg = 100.0\n',
        encoding="utf-8",
    )
    code, out, err = run(["cyclogram", str(path), "--out", str(tmp_path)], capsys)
    # Reported, the schedule still written, but a script must see it failed: the
    # status every command gives a design that fails (a new user's script tested 3).
    assert code == 3 and "no feasible optimum" in err
    assert "Optimum: none" in out and "200° > 150°" in out
    # A 200° schedule wrapped onto a 150° axis would mislead: no figure, and why.
    assert not (tmp_path / "cyclogram.png").exists() and "no figure" in out
    summary = read_summary(tmp_path)
    assert "optimum" not in summary and "speed_limit" not in summary
    assert summary["schedule"]["duration_deg"] == 200.0


BAD_RUNS = {
    "missing-file": (["{dir}/nowhere.toml"], ["nowhere.toml", "no such file"]),
    "mistyped-key": (["{bad}"], ["bad.toml", "[[operation]] #1", "'min_angle'"]),
    "negative-speed": ([str(EXAMPLE), "--speed", "-5"], ["speed_rpm", "-5"]),
    "nan-speed": ([str(EXAMPLE), "--speed", "nan"], ["speed_rpm", "nan"]),
}


@pytest.mark.parametrize(("args", "fragments"), BAD_RUNS.values(), ids=BAD_RUNS.keys())
def test_errors_exit_2_with_a_message(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], fragments: list[str]
) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text('[[operation]]\nfrom = "a"\nto = "b"\nmin_angle = 5\n', encoding="utf-8")
    argv = [a.format(dir=tmp_path, bad=bad) for a in args]
    code, _, err = run(["cyclogram", *argv, "--out", str(tmp_path / "o"), "--no-plot"], capsys)
    assert code == 2
    assert err.startswith("cyclomech: error:")
    for fragment in fragments:
        assert fragment in err, (fragment, err)
    assert not (tmp_path / "o" / "cyclogram.json").exists()


def test_out_is_a_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "taken"
    out.write_text("", encoding="utf-8")
    code, _, err = run(["cyclogram", str(EXAMPLE), "--out", str(out), "--no-plot"], capsys)
    assert code == 2
    assert err.startswith("cyclomech: error:") and str(out) in err


def test_missing_matplotlib_skips_the_figure(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    code, out, err = run(["cyclogram", str(EXAMPLE), "--out", str(tmp_path)], capsys)
    assert code == 0, err
    assert "no figure" in out
    assert not (tmp_path / "cyclogram.png").exists()
    assert (tmp_path / "cyclogram.json").exists()


def test_usage_errors_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main([])
    assert stop.value.code == 2
    assert "usage: cyclomech" in capsys.readouterr().err


def console_script() -> str:
    """The installed ``cyclomech`` script (next to this interpreter, else on PATH)."""
    name = "cyclomech.exe" if sys.platform == "win32" else "cyclomech"
    here = Path(sysconfig.get_path("scripts")) / name
    found = str(here) if here.exists() else shutil.which("cyclomech")
    if found is None:
        pytest.skip("the cyclomech console script is not installed")
    return found


def test_console_script_entry_point(tmp_path: Path) -> None:
    proc = subprocess.run(
        [console_script(), "cyclogram", str(EXAMPLE), "--out", str(tmp_path), "--no-plot"],
        capture_output=True,
        text=True,
        encoding="utf-8",
        timeout=120,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert f"{RPM:.2f} rpm" in proc.stdout
    assert read_summary(tmp_path)["optimum"]["objective_deg"] == pytest.approx(259.0, abs=1e-6)
