"""README's "Motion programs and servo axes in Python": its code block runs as it
is (from the repository's root, in a temporary folder for the file it writes), and
the values its comments state hold."""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def _block() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    head = text.index("## Motion programs and servo axes in Python")
    return re.search(r"```python\n(.*?)```", text[head:], re.DOTALL).group(1)


def test_the_block_runs_and_says_true(tmp_path, monkeypatch):
    code = _block().replace('"examples/motors.csv"', repr(str(ROOT / "examples" / "motors.csv")))
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    exec(compile(code, "README.md", "exec"), ns)
    assert ns["m"].v.tolist() == pytest.approx([0.04], rel=1e-13)
    assert round(ns["prog"].characteristics[2].cv, 2) == 1.94
    assert os.path.exists(tmp_path / "knife_table.csv")
    assert ns["best"].status == "ok"
    assert (ns["best"].motor.name, ns["best"].gearbox.ratio) == ("AC-040-032", 1.5)
    assert np.isfinite(ns["best"].motor.rated_torque_nm)
