"""A cam's ``damping_ratio`` (the follower's vibration): 0 ≤ ζ < 1. The residual
vibration is the amplitude of a damped free oscillation (a √(1 − ζ²) in it): there
is none for ζ ≥ 1, so ζ ≥ 1 is refused, naming the file, the table, the key, the
value and the valid range.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.cli import main

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"
LIFTER_CAM = ROOT / "examples" / "lifter_cam.toml"


def _edit(tmp_path: Path, src: Path, old: str, new: str) -> Path:
    text = src.read_text()
    assert old in text
    path = tmp_path / src.name
    # The last occurrence: the loom's [drive.link."lifter cam"] also has a
    # damping_ratio = 0.05, before the cam's own table.
    head, _, tail = text.rpartition(old)
    path.write_text(head + new + tail)
    return path


@pytest.mark.parametrize("command", ["cam", "run"])
def test_a_cam_damping_ratio_just_below_one_is_taken(tmp_path, capsys, command):
    src = LIFTER_CAM if command == "cam" else LOOM
    path = _edit(tmp_path, src, "damping_ratio = 0.05", "damping_ratio = 0.999999")
    quiet = ["--no-dxf"] if command == "cam" else ["--quiet", "--no-sensitivities"]
    with warnings.catch_warnings():  # it may work at no speed of the range: a warning
        warnings.simplefilter("always", cm.CyclomechWarning)
        status = main([command, str(path), "--out", str(tmp_path / "o"), "--no-plot", *quiet])
    # The design may fail at this damping (status 3), but the file is valid (not 2).
    assert status in (0, 3)
    assert "error:" not in capsys.readouterr().err


@pytest.mark.parametrize("value", ["1.0", "2.5"])
@pytest.mark.parametrize(
    ("command", "table"), [("cam", "[cam]"), ("run", "[mechanism.lifter cam]")]
)
def test_a_cam_damping_ratio_of_one_and_above_is_refused(tmp_path, capsys, command, table, value):
    src = LIFTER_CAM if command == "cam" else LOOM
    path = _edit(tmp_path, src, "damping_ratio = 0.05", f"damping_ratio = {value}")
    quiet = ["--no-dxf"] if command == "cam" else ["--quiet"]
    status = main([command, str(path), "--out", str(tmp_path / "o"), "--no-plot", *quiet])
    assert status == 2
    err = capsys.readouterr().err
    assert src.name in err and table in err
    assert f"damping_ratio = {value} must be in [0, 1)" in err
    with pytest.raises(cm.CyclomechError, match=r"damping_ratio = .* must be in \[0, 1\)"):
        cm.Machine.from_toml(path) if command == "run" else cm.cam.CamDesign.from_toml(path)
