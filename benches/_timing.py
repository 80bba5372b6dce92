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


def malloc_trim() -> Callable[[], object] | None:
    """glibc's ``malloc_trim(0)`` (freed heap pages back to the kernel), or None
    off Linux/glibc."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        trim = ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError):
        return None
    return lambda: trim(0)


def page_states(
    tools: dict[str, Callable[[], Any]], rounds: int
) -> dict[str, dict[str, tuple[float, float]]]:
    """:func:`interleaved` medians of ``tools`` in both memory-page states (issue 37):
    ``reused`` (glibc's heap hands the freed outputs and temporaries back, their
    pages already mapped) and ``fresh`` (``malloc_trim(0)`` before each call of
    every tool, so each new array's pages are first touched in the call; arrays
    of 32 MB and more are mapped fresh by glibc in both states). A tool that
    writes into a caller's existing buffer (``out=``) keeps its pages in both."""
    trim = malloc_trim()
    out = {"reused": interleaved(tools, rounds)}
    if trim is not None:

        def fresh(run: Callable[[], Any]) -> Callable[[], None]:
            def call() -> None:
                trim()
                run()

            return call

        out["fresh"] = interleaved({k: fresh(f) for k, f in tools.items()}, rounds)
    return out


def print_states(
    title: str,
    states: dict[str, dict[str, tuple[float, float]]],
    per: float,
    unit: str,
    against: dict[str, str],
) -> None:
    """Print each state's medians (wall and CPU, divided by ``per`` into ``unit``)
    and, for each ``row: reference`` of ``against``, the ratio reference / row
    (wall and CPU) from the same run."""
    for state, t in states.items():
        print(f"\n{title}, {state} pages (medians of interleaved rounds)")
        for name, (w, c) in t.items():
            print(f"  {name:44s} wall {w / per:10.4g} {unit}  cpu {c / per:10.4g} {unit}")
        for row, ref in against.items():
            (wr, cr), (w, c) = t[ref], t[row]
            print(f"  {ref} / {row}: wall {wr / w:.3f}x  cpu {cr / c:.3f}x")
