"""A linkage that cannot make its full turn is loud (issue 16, item 7):
``cyclomech linkage`` names the crank angles where it cannot be assembled
(checked against the closed-form reachability of the four-bar) and the length
that does not match the drawing."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from cyclomech.cli import EXIT_FAILS, main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

NON_GRASHOF = """\
[linkage]
name = "non-Grashof"
links = [["A", "B"], ["B", "C"], ["C", "D"]]
ground = ["A", "D"]
driver = ["A", "B"]
output = "C"

[linkage.points]
A = [0.0, 0.0]
B = [0.0, 0.25]
C = [0.25, 0.3]
D = [0.4, 0.0]
"""


def _reachable_deg(a: float, b: float, c: float, d: float, deg: np.ndarray) -> np.ndarray:
    """Closed form: the four-bar A(0,0)-B-C-D(d,0) with crank a, coupler b,
    rocker c assembles at crank angle φ iff |b − c| ≤ |BD| ≤ b + c."""
    phi = np.radians(deg)
    bd = np.hypot(d - a * np.cos(phi), a * np.sin(phi))
    return (bd <= b + c) & (bd >= abs(b - c))


def test_item7_a_linkage_that_cannot_turn_is_loud(tmp_path, capsys):
    """`cyclomech linkage` took a non-Grashof crank-rocker with exit 0 and "dead
    centres at 0". Now a warning names the unreachable crank-angle ranges (checked
    against the closed-form reachability of the four-bar on the same grid), the
    output's figures say they are over the reachable angles only, the JSON says
    full_turn false, and --require-full-turn exits with EXIT_FAILS."""
    path = tmp_path / "ng.toml"
    path.write_text(NON_GRASHOF, encoding="utf-8")
    code = main(["linkage", str(path), "--out", str(tmp_path / "o"), "--no-plot"])
    io = capsys.readouterr()
    assert code == 0
    deg = 90.0 + np.arange(360.0)
    b = math.dist((0.0, 0.25), (0.25, 0.3))
    c = math.dist((0.25, 0.3), (0.4, 0.0))
    ok = _reachable_deg(0.25, b, c, 0.4, deg)
    bad = deg[~ok]
    assert bad.size and np.all(np.diff(bad) == 1.0)  # one range on this grid
    assert f"cannot be assembled at crank angles {bad[0]:g}…{bad[-1]:g}°" in io.err
    assert "warning" in io.err and "reachable angles only" in io.err
    assert f"assembled at {int(ok.sum())} of 360" in io.out
    assert "no dead centres" in io.out and "dead centres at 0" not in io.out
    summary = json.loads((tmp_path / "o" / "linkage.json").read_text("utf-8"))
    assert summary["full_turn"] is False
    assert summary["unreachable_deg"] == [[bad[0], bad[-1]]]
    assert summary["output_over"] == "the reachable angles only"
    args = ["linkage", str(path), "--out", str(tmp_path / "o"), "--no-plot"]
    assert main([*args, "--require-full-turn"]) == EXIT_FAILS
    # A Grashof crank-rocker makes its turn: no warning, exit 0 either way.
    crank = str(EXAMPLES / "crank_rocker.toml")
    capsys.readouterr()
    assert main(["linkage", crank, "--out", str(tmp_path / "c"), "--require-full-turn"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_item7_a_length_that_does_not_match_the_drawing_is_named(tmp_path, capsys):
    """A lengths override (BC 0.15 m where the drawing has 0.3606 m) made the
    crank-rocker assemble at 253 of 360 angles with exit 0 and no word why."""
    text = (EXAMPLES / "crank_rocker.toml").read_text("utf-8")
    path = tmp_path / "over.toml"
    path.write_text(text + '\n[[linkage.lengths]]\njoints = ["B", "C"]\nlength = 0.15\n')
    main(["linkage", str(path), "--out", str(tmp_path / "o"), "--no-plot"])
    err = capsys.readouterr().err
    assert "cannot make a full turn" in err
    assert "BC drawn 0.360555 m, given 0.15 m" in err
