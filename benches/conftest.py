"""Ratio tables for the benchmarks: each tool's median and how many times cyclomech's.

Printed only when benchmarks were timed (``--benchmark-enable``); the default run,
with ``--benchmark-disable`` in addopts, executes each benchmark once and prints
nothing extra. Benchmarks name their tool and call in ``benchmark.extra_info``
(``tool``, ``what``); every row whose tool is ``cyclomech`` is a reference.
"""

from __future__ import annotations

import os
import platform
from importlib import metadata
from typing import Any

import pytest

# scipy's and numpy's OpenBLAS keep worker threads spinning for a while after a
# BLAS call (scipy's least_squares in the class III peer row); on a 2-core machine
# they steal a core from whatever is timed next. No benchmark here uses BLAS
# threads, so they are turned off for all tools alike (before numpy is imported).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

REFERENCE_TOOL = "cyclomech"
VERSIONED = ("cyclomech", "numpy", "rustworkx", "networkx", "pytest-benchmark")


def _cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def _time(seconds: float) -> str:
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if seconds >= scale:
            return f"{seconds / scale:7.3g} {unit}"
    return f"{seconds / 1e-9:7.3g} ns"


def _ratio(r: float) -> str:
    return f"{r:.3g}x" if r < 100 else f"{r:.0f}x"


def _timed(config: pytest.Config) -> list[Any]:
    """The benchmarks that ran with timing, or [] (plugin absent or disabled)."""
    session = getattr(config, "_benchmarksession", None)
    if session is None or session.disabled:
        return []
    return [b for b in session.benchmarks if b and not b.has_error]


#: Parameters whose largest values only a timed run needs: (fixture, smallest value
#: left to ``-m exhaustive`` when benchmarks are off). bench_schedule's V = 1e6 rows
#: (a minute of the default run, most of it rustworkx and the graph's build) and its
#: V = 1e5 rows (5.6 CPU-s, 4.6 of them networkx's) check what V = 1e3 and 1e4 check
#: on the same code, and the solve and build groups run V = 1e5 with every tool but
#: networkx (every size switch of the kernels is at 2^20 arcs or more, V >= 2.6e5;
#: networkx's rows take V = 1e4 when benchmarks are off, bench_schedule's
#: ``nx_dag``); timed, they give the per-arc scaling.
SMOKE_TOO_LARGE = {"scaled": 100_000}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """With benchmarks off (the default run executes each benchmark once, as a test),
    the sizes of :data:`SMOKE_TOO_LARGE` are marked ``exhaustive``, which the default
    ``-m "not exhaustive"`` leaves out; ``--benchmark-enable`` runs them all. Before
    the ``-m`` selection (tryfirst)."""
    if not (config.getoption("benchmark_disable") and not config.getoption("benchmark_enable")):
        return
    for item in items:
        params = getattr(getattr(item, "callspec", None), "params", {})
        if any(params.get(k, 0) >= v for k, v in SMOKE_TOO_LARGE.items()):
            item.add_marker(pytest.mark.exhaustive)


@pytest.hookimpl(trylast=True)
def pytest_terminal_summary(terminalreporter, exitstatus, config: pytest.Config) -> None:
    benches = _timed(config)
    if not benches:
        return
    tr = terminalreporter
    tr.write_sep("=", "cyclomech ratios (median times)")
    threads = os.environ.get("CYCLOMECH_THREADS", "unset (all cores)")
    tr.write_line(f"machine: {_cpu_model()}, {_cores()} cores; CYCLOMECH_THREADS={threads}")
    tr.write_line(
        f"python {platform.python_version()}; " + ", ".join(f"{d} {_version(d)}" for d in VERSIONED)
    )
    groups: dict[str, list[Any]] = {}
    for b in benches:
        groups.setdefault(b.group or "(no group)", []).append(b)
    for group, rows in groups.items():
        tr.write_line("")
        tr.write_line(f"[{group}]")
        width = max(len(_name(b)) for b in rows)
        for b in rows:
            tr.write_line(
                f"  {_name(b):<{width}}  {_time(b.stats.median)}  ({b.stats.rounds} rounds)"
            )
        refs = [b for b in rows if _tool(b) == REFERENCE_TOOL]
        peers = [b for b in rows if _tool(b) != REFERENCE_TOOL]
        for peer in peers:
            for ref in refs:
                # Per work item where a benchmark says how many it did (a peer
                # timed on a subset): extra_info["items"].
                r = _per_item(peer) / _per_item(ref)
                tr.write_line(
                    f"    {_tool(peer)} / {REFERENCE_TOOL} = {_ratio(r):>6}"
                    f"   ({_what(peer)}  vs  {_what(ref)})"
                )


def _per_item(b: Any) -> float:
    return float(b.stats.median) / float(b.extra_info.get("items", 1))


def _tool(b: Any) -> str:
    return str(b.extra_info.get("tool", b.name))


def _what(b: Any) -> str:
    return str(b.extra_info.get("what", b.name))


def _name(b: Any) -> str:
    return f"{_tool(b)}: {_what(b)}"
