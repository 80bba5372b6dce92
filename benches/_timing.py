"""What the benches that print interleaved rounds share (not a bench: pytest does not
collect it): whether the run is timed, the interleaved medians and the page states."""

from __future__ import annotations

import ctypes
import sys
import time
from collections.abc import Callable
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


def page_states() -> dict[str, Callable[[], object] | None]:
    """The page states a table is measured in: ``reused`` (nothing before a call:
    glibc's heap hands back the freed outputs and temporaries where it keeps them)
    and, on glibc, ``fresh`` (``malloc_trim(0)`` before each call, so every new
    array is first-touched)."""
    states: dict[str, Callable[[], object] | None] = {"reused": None}
    if sys.platform.startswith("linux"):
        try:
            trim = ctypes.CDLL(None).malloc_trim
        except (OSError, AttributeError):
            return states
        states["fresh"] = lambda: trim(0)
    return states


def in_state(f: Callable[[], Any], before: Callable[[], object] | None) -> Callable[[], None]:
    """``f`` with ``before`` (a page state's preparation, or None) run first."""

    def run() -> None:
        if before is not None:
            before()
        f()

    return run
