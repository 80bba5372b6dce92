"""A cam stop's arc that is no operation of the cyclogram is the arc's mistake
(new-user review): with ``cam = "..."`` it was reported as "the cam ... has no
segment bound to the stop's arc", which sent the user to the cam. The arc is now
checked against the cyclogram first, by the check the cam's segment arcs use too
(``cyclomech._toml.operation``); the cam's message is kept for an arc that is an
operation but not on the cam."""

from __future__ import annotations

import re
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech import _toml

LOOM = Path(__file__).resolve().parents[2] / "examples" / "stb_loom.toml"
STOP_ARC = 'arc = ["3", "7"]               #'  # the lifter's (a cam_stop with cam = "lifter cam")
NOT_AN_OPERATION = "is not an operation of the cyclogram"


def _read(tmp_path: Path, old: str, new: str) -> str:
    text = LOOM.read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    with pytest.raises(cm.InputError) as err:
        cm.Machine.from_toml(path)
    assert isinstance(err.value, ValueError)
    msg = str(err.value)
    assert msg.startswith(f"{path}: [mechanism."), msg
    return msg


def test_a_stop_arc_missing_from_the_cyclogram_names_the_arc_not_the_cam(tmp_path):
    msg = _read(tmp_path, STOP_ARC, 'arc = ["3", "8"]  #')
    assert "[mechanism.lifter]: arc = ['3', '8'] " + NOT_AN_OPERATION in msg
    assert "cam" not in msg.replace("[mechanism.lifter]", "")
    # The operations near it (from or to 3 or 8), then all of them.
    assert "from or to '3' or '8': ['1', '3'], ['3', '7'], ['3', '2'], ['6', '8'];" in msg
    assert "the operations are ['1', '3'], ['3', '7'], ['7', '10.1']," in msg


def test_a_stop_arc_the_wrong_way_round_says_so(tmp_path):
    msg = _read(tmp_path, STOP_ARC, 'arc = ["7", "3"]  #')
    assert NOT_AN_OPERATION in msg
    assert "the operation goes the other way: arc = ['3', '7']" in msg


def test_a_stop_arc_of_the_cyclogram_that_the_cam_does_not_drive_names_the_cam(tmp_path):
    # 3→2 is an operation (the spring opener's); the lifter cam has no segment on it.
    msg = _read(tmp_path, STOP_ARC, 'arc = ["3", "2"]  #')
    assert NOT_AN_OPERATION not in msg
    assert "the cam 'lifter cam' has no segment bound to the stop's arc ['3', '2']" in msg
    assert "bound to ['1', '3'], ['3', '7'], ['7', '10.1']" in msg


def test_a_cam_segment_arc_missing_from_the_cyclogram_gets_the_same_message(tmp_path):
    msg = _read(tmp_path, 'arc = ["1", "3"]', 'arc = ["1", "9"]')
    assert "[mechanism.lifter cam] segment 1: arc = ['1', '9'] " + NOT_AN_OPERATION in msg
    assert "from or to '1' or '9': ['1', '3'], ['1', '4'];" in msg


def test_the_check():
    ops = [("a", "b"), ("b", "c")]
    assert _toml.operation(["a", "b"], "arc", "w", ops) == ("a", "b")
    with pytest.raises(cm.InputError, match=re.escape("the operations are none")):
        _toml.operation(["a", "b"], "arc", "w", [])
    with pytest.raises(cm.InputError) as err:
        _toml.operation(["x", "y"], "arc", "f: [t]", ops)
    assert str(err.value) == (
        "f: [t]: arc = ['x', 'y'] is not an operation of the cyclogram (no [[operation]] "
        "has from = \"x\", to = \"y\"); the operations are ['a', 'b'], ['b', 'c']"
    )
