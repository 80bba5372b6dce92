"""Shared test settings: headless matplotlib, reproducible hypothesis runs in CI,
and the repository's root as the working directory of every test."""

import os
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

import pytest
from hypothesis import HealthCheck, settings

# CI machines are slow and shared: no per-example deadline, and a fixed seed so a
# failure reproduces. Locally, hypothesis explores fresh examples each run.
settings.register_profile(
    "ci", derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

ROOT = Path(__file__).resolve().parents[1]


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config: pytest.Config) -> None:
    """``-n N`` sends whole files to the workers (``--dist loadfile``) unless a
    ``--dist`` is given: many files build a module-scoped fixture (the docstring
    examples' recorded calls, the full-disk reference outputs, a synthesised drive,
    the million-event graphs) that ``--dist load`` builds again on every worker
    that gets one of the file's tests. Set here, not in pyproject's addopts:
    pytest-benchmark turns timing off whenever ``--dist`` is set, also without
    ``-n``. Runs before xdist's own hook, which makes ``-n`` mean ``--dist load``."""
    if getattr(config.option, "numprocesses", None) and config.option.dist == "no":
        config.option.dist = "loadfile"


@pytest.fixture(autouse=True)
def _in_the_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    """Docstring examples and tests name files as a user at the repository's root
    does (``examples/stb_loom.toml``), also when pytest runs elsewhere: against an
    installed wheel, tools/test_wheel.sh runs it from an empty directory so that
    ``python/`` cannot be imported, and the package is imported before this runs."""
    monkeypatch.chdir(ROOT)
