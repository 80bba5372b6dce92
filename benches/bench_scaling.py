"""How the hot loops scale with size: time per item and peak memory per item (issue 20).

Run it as a script; it prints a Markdown table for BENCHMARKS.md::

    python benches/bench_scaling.py              # every size, 1 and 2 threads (~3 min)
    python benches/bench_scaling.py --quick      # the two smallest sizes of each

Every (kernel, size, threads) runs in a fresh Python process. The table gives the
peak resident memory of the first call (``VmHWM``, reset through
``/proc/self/clear_refs`` once a 16-item call has paid the one-time costs and the
inputs are built) above the resident size before it, divided by the items: the
call's results and its working memory. Below about 1 MB a call's memory comes
from the allocator's free lists and hardly shows: read the large sizes. Times are the median
of 3 calls (5 below 0.1 s) after one warm-up call, divided by the items. A kernel
that scales well shows a flat time and memory per item across sizes.

Kernels and items:

- ``linkage``: a four-bar crank-rocker, ``Linkage.solve`` with positions, velocity
  and acceleration analogs of all 4 joints; item = one crank angle. 10³ … 10⁷.
- ``longest_path``: ``EventGraph`` build and one ``longest_path`` on a random DAG
  with E = 4V; item = one arc. V = 10³ … 10⁶.
- ``lp_floor``: the random accesses no longest path avoids, by numpy: a gather
  ``t[i]`` of E = 4V random indices from V times and a scatter ``out[i] = w`` of
  E values into V slots (at V = 10⁶: 4e6 indices into an 8 MB array); item = one
  arc. ``--kinds longest_path,lp_floor`` prints the ratio per size.
- ``duhamel``: ``cm.impact.duhamel`` of one oscillator under a piecewise-linear
  force; item = one time step. 10³ … 10⁶.
- ``sweep``: ``cm.sweep`` of the example loom over a speed axis; item = one point.
  10² … 10⁶.

pytest runs :func:`test_scaling_smoke`: the smallest sizes in this process, each
result checked against an independent reference, and the memory rule (a size
that cannot fit is an InputError before anything is allocated) for each kernel.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import cyclomech as cm
from bench_schedule import random_dag

SIZES = {
    "linkage": [10**3, 10**4, 10**5, 10**6, 10**7],
    "longest_path": [10**3, 10**4, 10**5, 10**6],
    "lp_floor": [10**3, 10**4, 10**5, 10**6],
    "duhamel": [10**3, 10**4, 10**5, 10**6],
    "sweep": [10**2, 10**3, 10**4, 10**5, 10**6],
}
ITEM = {
    "linkage": "angle",
    "longest_path": "arc",
    "lp_floor": "arc",
    "duhamel": "step",
    "sweep": "point",
}
#: Items per unit of size: the longest path's size is V, its items the E = 4V arcs.
PER_SIZE = {"linkage": 1, "longest_path": 4, "lp_floor": 4, "duhamel": 1, "sweep": 1}

# A four-bar crank-rocker (crank 0.05, coupler 0.2, rocker 0.15, frame 0.18 m).
_R, _L2, _L3, _D = 0.05, 0.2, 0.15, 0.18


def four_bar() -> cm.Linkage:
    """The crank-rocker drawn at φ = 90°, C above the line B-D."""
    b = np.array([0.0, _R])
    bd = math.hypot(_D, _R)
    x = (_L2**2 - _L3**2 + bd**2) / (2 * bd)
    h = math.sqrt(_L2**2 - x**2)
    e = np.array([_D, -_R]) / bd
    c = b + x * e + h * np.array([-e[1], e[0]])
    return cm.Linkage(
        {"A": (0.0, 0.0), "B": tuple(b), "C": tuple(c), "D": (_D, 0.0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def _linkage(n: int, threads: int) -> tuple[Callable[[], Any], Callable[[Any], None]]:
    lk = four_bar()
    phi = np.linspace(0.0, 2 * np.pi, n)

    def check(sol: Any) -> None:
        # The link lengths from the positions alone.
        xy = sol.xy
        bc = np.hypot(*(xy[:, 2] - xy[:, 1]).T)
        cd = np.hypot(*(xy[:, 2] - xy[:, 3]).T)
        assert np.abs(bc - _L2).max() < 1e-12 and np.abs(cd - _L3).max() < 1e-12
        assert sol.ok.all()

    return (lambda: lk.solve(phi, n_threads=threads)), check


def _longest_path(n: int, threads: int) -> tuple[Callable[[], Any], Callable[[Any], None]]:
    dag = random_dag(n, 4 * n, seed=20261126)

    def run() -> Any:
        g = cm.EventGraph(dag.n_events, dag.src, dag.dst)
        return g.longest_path(dag.weights, n_threads=threads)

    def check(t: Any) -> None:
        # Every arc's inequality holds, and each event with an incoming arc sits
        # on one of them exactly (the longest path's definition), by numpy alone.
        lhs = t[dag.src] + dag.weights
        assert np.all(t[dag.dst] >= lhs - 1e-9 * np.abs(lhs).max())
        best = np.full(dag.n_events, -np.inf)
        np.maximum.at(best, dag.dst, lhs)
        has_in = np.isfinite(best)
        np.testing.assert_allclose(t[has_in], best[has_in], rtol=1e-12)
        assert np.all(t[~has_in] == 0.0)

    return run, check


_OMEGA, _ZETA, _MASS = 2 * np.pi * 300.0, 0.05, 0.01


def _lp_floor(n: int, threads: int) -> tuple[Callable[[], Any], Callable[[Any], None]]:
    rng = np.random.default_rng(20261126)
    idx = rng.integers(0, n, 4 * n)
    t = rng.uniform(0.0, 360.0, n)
    w = rng.uniform(-10.0, 30.0, 4 * n)
    got = np.empty(4 * n)
    out = np.empty(n)

    def run() -> Any:
        np.take(t, idx, out=got)  # gather
        out[idx] = w  # scatter
        return got, out

    def check(r: Any) -> None:
        g, o = r
        assert np.array_equal(g, t[idx])
        last = np.full(n, -1)
        last[idx] = np.arange(idx.size)  # numpy keeps the last write
        hit = last >= 0
        assert np.array_equal(o[hit], w[last[hit]])

    return run, check


def _duhamel(n: int, threads: int) -> tuple[Callable[[], Any], Callable[[Any], None]]:
    del threads  # one case is one sequential recurrence
    t = np.linspace(0.0, 0.05, n)
    force = np.full(n, 10.0)  # a step of 10 N at t = 0, held

    def check(q: Any) -> None:
        # The closed-form step response of the damped oscillator.
        wd = _OMEGA * math.sqrt(1 - _ZETA**2)
        env = np.exp(-_ZETA * _OMEGA * t)
        exact = (
            10.0
            / (_MASS * _OMEGA**2)
            * (1 - env * (np.cos(wd * t) + _ZETA / math.sqrt(1 - _ZETA**2) * np.sin(wd * t)))
        )
        np.testing.assert_allclose(q, exact, atol=1e-12 * np.abs(exact).max())

    return (lambda: cm.impact.duhamel(t, force, omega_n=_OMEGA, zeta=_ZETA, mass=_MASS)), check


def _sweep(n: int, threads: int) -> tuple[Callable[[], Any], Callable[[Any], None]]:
    machine = cm.Machine.example()
    speeds = np.linspace(100.0, 700.0, n)

    def check(r: Any) -> None:
        assert r.n_points == n
        # The same points one by one, at three speeds, from the machine itself.
        for j in (0, n // 2, n - 1):
            one = cm.sweep(machine, {"speed_rpm": [float(speeds[j])]}, n_threads=1)
            for key in ("fits", "limiting_deg", "productivity_per_min"):
                np.testing.assert_array_equal(one.columns[key], r.columns[key][j : j + 1])

    return (lambda: cm.sweep(machine, {"speed_rpm": speeds}, n_threads=threads)), check


WORKLOADS = {
    "linkage": _linkage,
    "longest_path": _longest_path,
    "lp_floor": _lp_floor,
    "duhamel": _duhamel,
    "sweep": _sweep,
}


def _memory() -> dict[str, int]:
    """This process's resident size and its peak since the last reset [bytes]."""
    with open("/proc/self/status", encoding="ascii") as f:
        return {
            k: int(v.split()[0]) * 1024
            for k, v in (line.split(":", 1) for line in f)
            if k in ("VmRSS", "VmHWM")
        }


def _reset_peak() -> None:
    """Reset the peak resident size to the current one (Linux ≥ 4.0)."""
    with open("/proc/self/clear_refs", "w", encoding="ascii") as f:
        f.write("5")


def measure(kind: str, n: int, threads: int) -> dict[str, Any]:
    """Time and peak memory of one kernel at one size, in this process."""
    # A tiny call first pays the one-time costs (code paged in, the thread pool,
    # caches), so that the peak above ``base`` is what this size needs.
    WORKLOADS[kind](16, threads)[0]()
    run, _ = WORKLOADS[kind](n, threads)
    _reset_peak()
    base = _memory()["VmRSS"]
    t0 = time.perf_counter()
    run()  # warm-up; also the peak-memory call
    first = time.perf_counter() - t0
    peak = _memory()["VmHWM"]
    times = []
    for _ in range(5 if first < 0.1 else 3):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    med = statistics.median(times)
    items = n * PER_SIZE[kind]
    return {
        "kind": kind,
        "n": n,
        "threads": threads,
        "seconds": med,
        "ns_per_item": med / items * 1e9,
        "peak_bytes_per_item": max(peak - base, 0) / items,
    }


def _one_process(kind: str, n: int, threads: int) -> dict[str, Any]:
    cmd = [sys.executable, __file__, "--one", kind, str(n), str(threads)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{out.stderr}")
    return dict(json.loads(out.stdout.strip().splitlines()[-1]))


def table(rows: list[dict[str, Any]]) -> str:
    """The Markdown table of :func:`main`."""
    lines = [
        "| kernel | item | size (angles, V, steps, points) | 1 thread: ns/item "
        "| 2 threads: ns/item | peak memory/item |",
        "|---|---|---|---|---|---|",
    ]
    by = {(r["kind"], r["n"], r["threads"]): r for r in rows}
    for kind, sizes in SIZES.items():
        for n in sizes:
            one, two = by.get((kind, n, 1)), by.get((kind, n, 2))
            if one is None:
                continue
            mem = one["peak_bytes_per_item"]
            lines.append(
                f"| {kind} | {ITEM[kind]} | {n:.0e} | {one['ns_per_item']:.3g} | "
                f"{two['ns_per_item']:.3g} | {mem:.3g} B |"
                if two
                else f"| {kind} | {ITEM[kind]} | {n:.0e} | {one['ns_per_item']:.3g} | — | "
                f"{mem:.3g} B |"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="the two smallest sizes only")
    p.add_argument("--one", nargs=3, metavar=("KIND", "N", "THREADS"), help=argparse.SUPPRESS)
    p.add_argument("--kinds", default=",".join(SIZES), help="comma-separated kernels")
    args = p.parse_args(argv)
    if args.one:
        kind, n, threads = args.one[0], int(args.one[1]), int(args.one[2])
        print(json.dumps(measure(kind, n, threads)))
        return 0
    rows = []
    for kind in args.kinds.split(","):
        for n in SIZES[kind][: 2 if args.quick else None]:
            for threads in (1, 2):
                r = _one_process(kind, n, threads)
                print(
                    f"{kind:13s} {n:9.0e} {threads} thr  {r['seconds'] * 1e3:9.2f} ms  "
                    f"{r['ns_per_item']:9.3g} ns/{ITEM[kind]}  "
                    f"{r['peak_bytes_per_item']:9.3g} B/{ITEM[kind]}",
                    file=sys.stderr,
                    flush=True,
                )
                rows.append(r)
    print(table(rows))
    floor = {(r["n"], r["threads"]): r["ns_per_item"] for r in rows if r["kind"] == "lp_floor"}
    ratios = []
    for r in rows:
        f = floor.get((r["n"], r["threads"]))
        if r["kind"] == "longest_path" and f:
            x = r["ns_per_item"]
            ratios.append(f"| {r['n']:.0e} | {r['threads']} | {x:.3g} | {f:.3g} | {x / f:.3g}× |")
    if ratios:
        print(
            "\n| V | threads | longest path ns/arc | floor ns/arc | ratio |\n|---|---|---|---|---|"
        )
        print("\n".join(ratios))
    return 0


# ---------------------------------------------------------------------------
# Smoke test (the default pytest run): small sizes, checked, and the memory rule.


@pytest.mark.parametrize("kind", list(SIZES))
def test_scaling_smoke(kind: str) -> None:
    """The smallest size of each kernel against its independent reference, and the
    measurement's own bookkeeping."""
    n = SIZES[kind][0]
    run, check = WORKLOADS[kind](n, 1)
    check(run())
    m = measure(kind, n, 1)
    assert m["n"] == n and m["seconds"] > 0 and m["peak_bytes_per_item"] >= 0


@pytest.mark.parametrize(
    ("kind", "n"),
    [("linkage", 10**5), ("sweep", 10**5)],
)
def test_a_size_that_cannot_fit_is_refused_before_allocating(
    monkeypatch: pytest.MonkeyPatch, kind: str, n: int
) -> None:
    """With the memory limit below a size's results, the call raises InputError
    before the process grows (the results of 1e5 angles are 19 MB; of 1e5 sweep
    points, several MB). Longest path and one Duhamel case return less than they
    are given, so their inputs' copies carry the rule (tests/package/test_size_limits.py)."""
    run, _ = WORKLOADS[kind](n, 1)
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", "1e5")
    _reset_peak()
    before = _memory()["VmRSS"]
    with pytest.raises(cm.InputError, match=r"needs .* GB, more than the 0\.0001 GB"):
        run()
    assert _memory()["VmHWM"] - before < 1_000_000  # bytes: nothing result-sized


if __name__ == "__main__":
    raise SystemExit(main())
