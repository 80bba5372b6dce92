"""Tests of ``cyclomech linkage FILE.toml [--out DIR] [--step-deg S]``.

The table and summary are checked against a direct ``Linkage.solve`` and, for the
crank-rocker example, against the rocker's extreme positions from the triangle
inequality (C is farthest from A when A, B, C are collinear: |AC| = |AB| + |BC|).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import EXIT_FAILS, main
from numpy.testing import assert_allclose

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_burg_trimmer_example_writes_table_and_summary(tmp_path, capsys):
    code = main(
        ["linkage", str(EXAMPLES / "burg_trimmer.toml"), "--out", str(tmp_path), "--no-plot"]
    )
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    assert "structure driver – III(B, C, E)" in out
    assert "assembled at 360 of 360, no dead centres, no branch changes" in out
    table = np.genfromtxt(tmp_path / "analogs.csv", delimiter=",", names=True)
    lk = cm.Linkage.from_toml(EXAMPLES / "burg_trimmer.toml")
    sol = lk.solve(np.radians(table["angle_deg"]))
    assert_allclose(table["E_x"], sol["E"][:, 0], rtol=1e-11, atol=1e-12)
    assert_allclose(table["E_ddy"], sol.acc[:, sol.index("E"), 1], rtol=1e-11, atol=1e-12)
    summary = json.loads((tmp_path / "linkage.json").read_text())
    assert summary["schema"] == "cyclomech.linkage/1"
    assert summary["structure"] == [["driver", ["F"]], ["III", ["B", "C", "E"]]]
    assert summary["output"] == "E" and summary["assembled"] == 360
    # The stroke is the largest chord of E's path; brute force over the table here.
    xy = np.c_[table["E_x"], table["E_y"]]
    chords = np.linalg.norm(xy[:, None] - xy[None], axis=2)
    assert summary["output_stroke_m"] == pytest.approx(chords.max(), rel=1e-12)


def test_crank_rocker_extremes_match_the_triangle_inequality(tmp_path, capsys):
    code = main(
        [
            "linkage",
            str(EXAMPLES / "crank_rocker.toml"),
            "--out",
            str(tmp_path),
            "--no-plot",
            "--step-deg",
            "0.25",
        ]
    )
    capsys.readouterr()
    assert code == 0
    lk = cm.Linkage.from_toml(EXAMPLES / "crank_rocker.toml")
    table = np.genfromtxt(tmp_path / "analogs.csv", delimiter=",", names=True)
    assert len(table) == 1440
    ac = np.hypot(table["C_x"], table["C_y"])
    ab, bc = lk.length("A", "B"), lk.length("B", "C")
    assert ac.max() == pytest.approx(ab + bc, abs=1e-6)  # grid within 0.25° of it
    assert ac.min() == pytest.approx(bc - ab, abs=1e-6)


def test_slider_file_runs_and_reports_unassemblable_angles(tmp_path, capsys):
    # Offset slider-crank whose rod reaches the guide only between 30° and 150°.
    path = tmp_path / "offset.toml"
    cm.Linkage(
        {"A": (0, 0), "B": (0, 0.1), "C": (math.sqrt(0.2**2 - 0.15**2), 0.25)},
        [("A", "B"), ("B", "C")],
        ["A"],
        ("A", "B"),
        sliders={"C": ("ground", (1, 0))},
    ).to_toml(path)
    code = main(["linkage", str(path), "--out", str(tmp_path / "o"), "--no-plot"])
    out, _ = capsys.readouterr()
    assert code == 0
    table = np.genfromtxt(tmp_path / "o" / "analogs.csv", delimiter=",", names=True)
    bad = table["ok"] == 0
    assert bad.any() and np.isnan(table["C_x"][bad]).all()
    assert f"assembled at {int((~bad).sum())} of {bad.size}," in out


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--step-deg", "0"], ["--step-deg 0", "[0.001, 90]"]),
        (["--step-deg", "nan"], ["--step-deg nan"]),
        # Issue 16 item 13: 1e-6° allocated 2.9 GB of angles before any check.
        (["--step-deg", "1e-6"], ["--step-deg 1e-06", "[0.001, 90]", "360,000 angles"]),
    ],
)
def test_bad_options_exit_2_with_a_message(tmp_path, capsys, args, words):
    code = main(
        ["linkage", str(EXAMPLES / "crank_rocker.toml"), "--out", str(tmp_path), "--no-plot", *args]
    )
    _, err = capsys.readouterr()
    assert code == 2
    for w in words:
        assert w in err


def test_bad_file_exits_2_naming_the_file(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text("[linkage]\npoints = {A = [0, 0]}\n")
    assert main(["linkage", str(path), "--out", str(tmp_path / "o")]) == 2
    _, err = capsys.readouterr()
    assert str(path) in err and "missing key 'links'" in err
    assert main(["linkage", str(tmp_path / "none.toml")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_a_linkage_that_never_assembles_exits_1(tmp_path, capsys):
    path = tmp_path / "never.toml"
    lk = cm.Linkage(
        {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
        lengths={("C", "D"): 10.0},
    )  # too long to meet the coupler anywhere
    lk.to_toml(path)
    assert main(["linkage", str(path), "--out", str(tmp_path / "o"), "--no-plot"]) == EXIT_FAILS
    assert "cannot be assembled at any angle" in capsys.readouterr().err


def test_figures_are_written_as_png(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    code = main(
        ["linkage", str(EXAMPLES / "burg_trimmer.toml"), "--out", str(tmp_path), "--step-deg", "5"]
    )
    out, _ = capsys.readouterr()
    assert code == 0
    for name in ("mechanism.png", "analogs_E.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert str(tmp_path / name) in out
