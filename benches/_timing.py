"""What the benches that print interleaved rounds share (not a bench: pytest does not
collect it): whether the run is timed, and the interleaved medians."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pytest


def timed_run(config: pytest.Config) -> bool:
    """Whether this is a timed run (--benchmark-enable), as conftest reads it."""
    session = getattr(config, "_benchmarksession", None)
    return session is not None and not session.disabled


def interleaved(tools: dict[str, Any], rounds: int) -> dict[str, tuple[float, float]]:
    """Median wall time and median CPU time (the process's, all threads) [s] of
    each tool, the tools called in turn each round (so the machine's load drifts
    over all of them alike). On a loaded machine the one-thread rows' CPU time is
    the steadier measure of the work."""
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in tools}
    for _ in range(rounds):
        for name, run in tools.items():
            t0, c0 = time.perf_counter(), time.process_time()
            run()
            times[name].append((time.perf_counter() - t0, time.process_time() - c0))
    return {
        name: (float(np.median([w for w, _ in t])), float(np.median([c for _, c in t])))
        for name, t in times.items()
    }
