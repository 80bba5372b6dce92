"""Numbers printed for people have 6 significant digits (cyclomech._numtext); the
files for programs keep every digit."""

from __future__ import annotations

import json
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech._numtext import number_text
from cyclomech.cli import main

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"
# The lifter stop's stroke comes from its cam: 0.009399999999599031 m, not 0.0094.
STROKE = cm.Machine.from_toml(LOOM).mechanisms["lifter"].stop.stroke


def _loom(tmp_path: Path, preload: str) -> Path:
    text = LOOM.read_text().replace("preload_m = 0.00025 ", f"preload_m = {preload} ", 1)
    assert text != LOOM.read_text()
    path = tmp_path / "loom.toml"
    path.write_text(text)
    return path


def test_the_stroke_is_a_computed_value_with_many_digits():
    assert repr(STROKE) != f"{STROKE:.6g}"  # else the tests below test nothing


def test_a_computed_stroke_prints_with_six_digits(tmp_path, capsys):
    path = _loom(tmp_path, "0.5")
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"preload_m = 0.5 m must be smaller than stroke_m = {STROKE:.6g} m" in err
    assert repr(STROKE) not in err


def test_a_stroke_that_would_read_equal_to_the_preload_prints_in_full(tmp_path, capsys):
    # 6 digits would say "preload_m = 0.0094 m must be smaller than stroke_m = 0.0094 m".
    path = _loom(tmp_path, "0.0094")
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"preload_m = 0.0094 m must be smaller than stroke_m = {STROKE!r} m" in err


@pytest.mark.parametrize(
    ("value", "compared", "text"),
    [
        (0.009399999999599031, (), "0.0094"),
        (0.009399999999599031, (0.0094,), "0.009399999999599031"),
        (0.0094, (0.0094,), "0.0094"),  # equal values print short
        (2.0 / 3.0, (1.0,), "0.666667"),
        (-1234567.0, (), "-1.23457e+06"),
    ],
)
def test_number_text(value, compared, text):
    assert number_text(value, *compared) == text


def test_the_results_file_keeps_every_digit(cli_run):
    run = cli_run(LOOM, "--no-plot", "--quiet")
    out = run.out
    assert run.code == 0
    results = json.loads((out / "results.json").read_text())
    strokes = []

    def find(node):
        if isinstance(node, dict):
            strokes.extend(v for k, v in node.items() if k == "stroke_m")
            for v in node.values():
                find(v)
        elif isinstance(node, list):
            for v in node:
                find(v)

    find(results)
    assert STROKE in strokes  # the exact float, read back from the JSON text
