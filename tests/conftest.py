"""Shared test settings: headless matplotlib, reproducible hypothesis runs in CI."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import HealthCheck, settings

# CI machines are slow and shared: no per-example deadline, and a fixed seed so a
# failure reproduces. Locally, hypothesis explores fresh examples each run.
settings.register_profile(
    "ci", derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")
