"""One base in every message: the n-th table, segment or entry of a file is counted
from 1, as a designer counts the tables in the file (``[[operation]] #1``, ``load #1``,
``segment 1``); messages once mixed ``load[0]``, ``segment 0`` and ``[[operation]] #1``.

The reference is the construction: each case breaks a known table of an example
(the first, or the second) and expects its 1-based count in the message, from the
Python readers and from the Rust core's errors (a motion program's join) alike.
A Python subscript of an argument the caller passed (``theta[5]``) is Python's own
notation and keeps Python's index.
"""

from __future__ import annotations

from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _edited(tmp_path: Path, name: str, old: str, new: str, nth: int = 1) -> Path:
    """The example ``name`` with the ``nth`` occurrence of ``old`` replaced by ``new``."""
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    at = -1
    for _ in range(nth):
        at = text.index(old, at + 1)
    f = tmp_path / name
    f.write_text(text[:at] + new + text[at + len(old) :], encoding="utf-8")
    return f


@pytest.mark.parametrize(
    ("command", "name", "old", "new", "nth", "expected"),
    [
        # the first [[cam.segment]] is segment 1
        ("cam", "lifter_cam.toml", 'law = "modified_sine"', 'law = "nope"', 1,
         "[cam]: segment 1 (rise): unknown law 'nope'"),
        # the Python reader's: the second [[cam.segment]] is segment 2
        ("cam", "lifter_cam.toml", 'kind = "dwell"', 'kind = "dwell"\nspeed = 1', 1,
         "segment 2: unknown key 'speed'"),
        ("run", "knife_cutter.toml", 'point = "E" ', 'point = "Q" ', 1,
         "load #1: point = 'Q' is not a point"),
        ("cyclogram", "stb_group1.toml", "[[operation]]\n", "[[operation]]\nbogus = 1\n", 2,
         "[[operation]] #2: unknown key 'bogus'"),
        ("linkage", "crank_rocker.toml", 'ground = ["A", "D"]', 'ground = ["A", 4]', 1,
         "ground #2 = 4 must be a joint name"),
        ("run", "knife_cutter.toml", "[[balance]]\n", "[[balance]]\nbogus = 1\n", 1,
         "[[balance]] #1: unknown key 'bogus'"),
    ],
)  # fmt: skip
def test_a_files_tables_are_counted_from_1(
    command, name, old, new, nth, expected, tmp_path, capsys
):
    f = _edited(tmp_path, name, old, new, nth)
    assert main([command, str(f), "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert expected in err, err


def test_the_motion_programs_join_counts_segments_from_1():
    # Rust's MotionError::Join: the jump from the first segment to the second.
    S = cm.motion.Segment
    segments = [S("harmonic", 90, end=0.1), S("dwell", 90), S("harmonic", 180, end=0.0)]
    with pytest.raises(cm.InputError, match=r"segment 1 \(harmonic\) → segment 2 \(dwell\)"):
        cm.motion.Program(segments, continuity="acceleration")
