"""The package type-checks: mypy, with the configuration in pyproject.toml's
[tool.mypy] (files = python/cyclomech), reports no error."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_mypy_passes() -> None:
    pytest.importorskip("mypy", reason="mypy is in the [test] extras")
    run = subprocess.run(
        [sys.executable, "-m", "mypy"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    out = run.stdout + run.stderr
    assert run.returncode == 0, out
    assert "Success" in out, out
