"""Benchmarks of the whole machine: the speed sweep, its shortest-path call, cm.sweep.

The hot loop is one design at many speeds (:meth:`cyclomech.Machine.speed_sweep`): one
call per stop kernel (the exact smallest phase angle at every speed) and one
:func:`cyclomech.max_difference` call over all speeds. The peer is what a user would
write without it: per speed, the stop's exact constraint
(:meth:`cyclomech.impact.StopImpact.constraint`) added to a copy of the cyclogram and
:meth:`cyclomech.Cyclogram.optimize` (scipy HiGHS). The LP runs on a subset of the
speeds in the same run; the per-point ratio is printed at the end of a timed run.
The shortest-path call alone is timed against scipy's and networkx's Bellman–Ford,
one weight row at a time, on the loom's own network. Every peer is checked once
against cyclomech's values.

Sizes: the default run (``--benchmark-disable`` in addopts) calls every benchmark
once on 4 designs × 250 speeds; ``CYCLOMECH_BENCH_FULL=1`` times 40 designs × 2500
speeds (the 100 000-point sweep of BENCHMARKS.md), also on a 2-worker Dask
LocalCluster, whose start-up is timed on its own::

    python -m pytest benches/bench_machine.py --benchmark-enable -q
    CYCLOMECH_BENCH_FULL=1 python -m pytest benches/bench_machine.py --benchmark-enable -q
"""

from __future__ import annotations

import copy
import importlib
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from cyclomech.machine import SpeedSweep
from numpy.testing import assert_allclose

nx = pytest.importorskip("networkx")
csgraph = pytest.importorskip("scipy.sparse.csgraph")
sparse = pytest.importorskip("scipy.sparse")

FULL = os.environ.get("CYCLOMECH_BENCH_FULL", "") not in ("", "0")
full_only = pytest.mark.skipif(
    not FULL, reason="the 100 000-point sweep and the Dask cluster: CYCLOMECH_BENCH_FULL=1"
)

#: The loom as it was before its lifter cam (issue 18): the stop alone bounds it, so
#: these rows stay comparable with BENCHMARKS.md's; the loom with its cam spends
#: most of a sweep in the cam's stress bounds (see BENCHMARKS.md, "Cam bounds").
LOOM = (
    Path(__file__).resolve().parents[1] / "tests" / "machine" / "data" / "stb_loom_stop_only.toml"
)
#: Speeds [rpm] of the study: the loom's range, across its speed limit (421.4 rpm).
SPEED_RANGE_RPM = (200.0, 500.0)
N_SPEEDS = 2500 if FULL else 250
#: Preloads [m] of the lifter's stop: the designs of cm.sweep.
PRELOAD_RANGE_M = (1e-4, 5e-4)
N_PRELOADS = 40 if FULL else 4
#: The LP peer runs on every LP_STRIDE-th speed (100 speeds full, 10 by default).
LP_STRIDE = 25
#: Dask workers (processes, one thread each): the machine has 2 cores.
DASK_WORKERS = 2
#: Agreement of the LP and Bellman–Ford peers with cyclomech [deg]; the exact angles
#: differ by rounding only (HiGHS's tolerances are far looser than this in general,
#: but on this small LP the optimum is a vertex it hits exactly).
ATOL_DEG = 1e-9
#: Slow peers and the 100 000-point sweeps get few rounds, so the timed run stays short.
SLOW_ROUNDS = 3

GROUP_SPEED = f"speed_sweep: one design, {N_SPEEDS} speeds"
GROUP_LP = f"LP per point: {N_SPEEDS // LP_STRIDE} speeds (every {LP_STRIDE}th) of one design"
GROUP_PATH = f"max_difference: the loom's network (V=12, E=33), {N_SPEEDS} weight rows"
GROUP_SWEEP = f"cm.sweep: {N_PRELOADS} designs × {N_SPEEDS} speeds = {N_PRELOADS * N_SPEEDS}"
GROUP_CLUSTER = f"Dask LocalCluster start-up: {DASK_WORKERS} worker processes"

Array = npt.NDArray[np.float64]


def _label(benchmark, tool: str, what: str) -> None:
    """Name the tool and the call for the ratio table printed by conftest.py."""
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


# --- per-point ratios, printed after conftest's tables ------------------------------

#: Median seconds per point of each timed row, by key (filled only in a timed run).
_PER_POINT: dict[str, tuple[str, float]] = {}


def _record(benchmark, key: str, what: str, points: int) -> None:
    stats = getattr(benchmark, "stats", None)
    if stats is not None:  # None under --benchmark-disable
        _PER_POINT[key] = (what, stats.stats.median / points)


def _us(seconds: float) -> str:
    return f"{seconds * 1e6:.3g} µs" if seconds < 1e-3 else f"{seconds * 1e3:.3g} ms"


class _PerPointReport:
    """The LP peer ran on a subset of the points: its ratio is per point, not per call."""

    @pytest.hookimpl(trylast=True)
    def pytest_terminal_summary(self, terminalreporter) -> None:
        tr = terminalreporter
        pairs = [(f"design-old-{n}", f"design-batch-{n}") for n in (1, 2)]
        pairs.append(("stops-old", "stops-batch"))
        pairs.append(("limits-python", "limits-rust"))
        for old, new in pairs:
            if old in _PER_POINT and new in _PER_POINT:
                a, b = _PER_POINT[old][1], _PER_POINT[new][1]
                tr.write_line(
                    f"  per design: {_PER_POINT[old][0]} {_us(a)}; {_PER_POINT[new][0]} "
                    f"{_us(b)}: {a / b:.2f}x"
                )
        lp = _PER_POINT.get("lp")
        if lp is None:
            return
        tr.write_sep("=", "cyclomech machine: per point")
        tr.write_line(f"  peer: {lp[0]}: {_us(lp[1])} per point")
        for key, (what, t) in _PER_POINT.items():
            if key == "lp" or key.startswith(("design-", "stops-", "limits-")):
                continue
            n = N_PRELOADS * N_SPEEDS if key.startswith("sweep") else N_SPEEDS
            tr.write_line(
                f"  {what}: {_us(t)} per point; LP / this = {lp[1] / t:.0f}x"
                f"  (LP extrapolated to its {n} points: {lp[1] * n:.1f} s)"
            )


@pytest.fixture(scope="module", autouse=True)
def _per_point_report(request):
    pm = request.config.pluginmanager
    if not pm.has_plugin("cyclomech-bench-machine"):
        pm.register(_PerPointReport(), "cyclomech-bench-machine")


# --- the loom -----------------------------------------------------------------------


@pytest.fixture(scope="module")
def loom() -> cm.Machine:
    return cm.Machine.from_toml(LOOM)


@pytest.fixture(scope="module")
def speeds() -> Array:
    return np.linspace(*SPEED_RANGE_RPM, N_SPEEDS)


@pytest.fixture(scope="module")
def reference(loom: cm.Machine, speeds: Array) -> SpeedSweep:
    s = loom.speed_sweep(speeds)
    assert s.fits.any() and not s.fits.all()  # both sides of the speed limit
    return s


def grid() -> dict[str, Array]:
    return {
        "lifter.preload_m": np.linspace(*PRELOAD_RANGE_M, N_PRELOADS),
        "speed_rpm": np.linspace(*SPEED_RANGE_RPM, N_SPEEDS),
    }


# --- one design at every speed --------------------------------------------------------


@pytest.mark.benchmark(group=GROUP_SPEED)
@pytest.mark.parametrize("n_threads", [None, 1], ids=["all-cores", "1-thread"])
def test_speed_sweep_cyclomech(benchmark, loom, speeds, reference, n_threads) -> None:
    threads = "all cores" if n_threads is None else f"{n_threads} thread"
    what = f"Machine.speed_sweep({N_SPEEDS} speeds), {threads}"
    _label(benchmark, "cyclomech", what)
    s = benchmark(loom.speed_sweep, speeds, n_threads=n_threads)
    assert np.array_equal(s.limiting_deg, reference.limiting_deg, equal_nan=True)
    _record(benchmark, f"speed_sweep-{threads}", what, N_SPEEDS)


def lp_limiting_deg(machine: cm.Machine, rpm: Array) -> Array:
    """The peer: per speed, a copy of the cyclogram with each mechanism's exact
    constraints (a stop's rebound, a cam's criteria) and the LP (HiGHS); NaN where it
    does not fit. What a user writes without the machine's sweep."""
    out = np.full(rpm.size, np.nan)
    for i, n in enumerate(rpm.tolist()):
        cg = copy.deepcopy(machine.cyclogram)
        try:
            for mech in machine.mechanisms.values():
                for c in mech.constraints(n):
                    if not math.isfinite(c.rhs):
                        raise cm.InfeasibleError(f"{c.name} cannot be met at {n} rpm")
                    cg.add_constraint(c)
            out[i] = cg.optimize(speed_rpm=n).objective
        except cm.InfeasibleError:
            pass  # the rebound bound or the cyclogram does not fit at this speed
    return out


@pytest.mark.benchmark(group=GROUP_LP)
def test_lp_cyclomech(benchmark, loom, speeds, reference) -> None:
    _label(benchmark, "cyclomech", f"Machine.speed_sweep({N_SPEEDS // LP_STRIDE} speeds)")
    s = benchmark(loom.speed_sweep, speeds[::LP_STRIDE])
    assert np.array_equal(s.limiting_deg, reference.limiting_deg[::LP_STRIDE], equal_nan=True)


@pytest.mark.benchmark(group=GROUP_LP, min_rounds=SLOW_ROUNDS)
def test_lp_peer(benchmark, loom, speeds, reference) -> None:
    what = "the mechanisms' constraints + Cyclogram.optimize per speed (HiGHS)"
    _label(benchmark, "scipy", what)
    sub = speeds[::LP_STRIDE]
    value = benchmark(lp_limiting_deg, loom, sub)
    want = reference.limiting_deg[::LP_STRIDE]
    assert np.isfinite(value).any() and np.isnan(value).any()
    assert np.array_equal(np.isnan(value), np.isnan(want))
    assert_allclose(value, want, rtol=0, atol=ATOL_DEG)
    _record(benchmark, "lp", what, sub.size)


# --- the shortest-path call alone -----------------------------------------------------


@dataclass(frozen=True)
class Network:
    """The loom's system of difference constraints at every speed: arc e bounds
    x[dst[e]] − x[src[e]] ≤ W[row, e] [deg], as Machine.speed_sweep builds it."""

    n_nodes: int
    src: npt.NDArray[np.int64]
    dst: npt.NDArray[np.int64]
    weights: Array  # (S, E)
    source: int
    target: int

    def cyclomech(self, n_threads: int | None = None) -> Array:
        value, _ = cm.max_difference(
            self.n_nodes,
            self.src,
            self.dst,
            self.weights,
            self.source,
            self.target,
            n_threads=n_threads,
        )
        return np.asarray(value)


@pytest.fixture(scope="module")
def network(loom: cm.Machine, speeds: Array) -> Network:
    # cyclogram.SpeedNetwork.solve's weights, from its own tables (on purpose:
    # this is the exact call speed_sweep makes).
    net = loom.speed_network
    mins, _ = net.minimums(speeds, list(loom.bound_angles(speeds).values()))
    w = np.broadcast_to(net.base, (speeds.size, net.base.size)).copy()
    w[:, net.min_edge] -= mins
    return Network(net.n, net.src, net.dst, w, net.source, net.target)


@pytest.fixture(scope="module")
def network_values(network: Network) -> Array:
    v = network.cyclomech()
    assert np.isfinite(v).any() and np.isnan(v).any()  # fits, and does not (a neg. cycle)
    return v


class ScipyLoop:
    """scipy's Bellman–Ford per row on one CSR structure whose data is overwritten."""

    def __init__(self, net: Network) -> None:
        key = net.src * net.n_nodes + net.dst
        order = np.argsort(key, kind="stable")
        uniq, self.first = np.unique(key[order], return_index=True)
        self.order = order
        # csr_matrix would *add* parallel arcs; the constraint is their minimum.
        ones = np.ones(uniq.size)
        self.graph = sparse.csr_array(
            (ones, (uniq // net.n_nodes, uniq % net.n_nodes)), shape=(net.n_nodes,) * 2
        )
        self.graph.sort_indices()  # data in (row, col) order, as uniq
        self.net = net

    def __call__(self) -> Array:
        net, g = self.net, self.graph
        out = np.full(net.weights.shape[0], np.nan)
        for i, row in enumerate(net.weights):
            g.data[:] = np.minimum.reduceat(row[self.order], self.first)
            try:
                out[i] = csgraph.bellman_ford(g, directed=True, indices=net.source)[net.target]
            except csgraph.NegativeCycleError:
                continue  # infeasible: NaN, as max_difference
        return out


def networkx_loop(net: Network) -> Array:
    """networkx's Bellman–Ford per row; the arc index is the payload, the weight a lookup."""
    g = nx.DiGraph()
    g.add_nodes_from(range(net.n_nodes))
    for e, (u, v) in enumerate(zip(net.src.tolist(), net.dst.tolist(), strict=True)):
        if g.has_edge(u, v):  # parallel arcs: keep the tighter bound's index
            raise AssertionError("the loom's network has no parallel arcs")
        g.add_edge(u, v, i=e)
    out = np.full(net.weights.shape[0], np.nan)
    for r, w in enumerate(net.weights):
        row = w.tolist()
        try:
            out[r] = nx.bellman_ford_path_length(
                g,
                net.source,
                net.target,
                weight=lambda u, v, d: row[d["i"]],  # noqa: B023 (used before row changes)
            )
        except nx.NetworkXUnbounded:
            continue  # a negative cycle: infeasible, NaN as max_difference
    return out


@pytest.mark.benchmark(group=GROUP_PATH)
@pytest.mark.parametrize("n_threads", [None, 1], ids=["all-cores", "1-thread"])
def test_path_cyclomech(benchmark, network, network_values, n_threads) -> None:
    threads = "all cores" if n_threads is None else f"{n_threads} thread"
    _label(benchmark, "cyclomech", f"max_difference(W), {threads}")
    v = benchmark(network.cyclomech, n_threads)
    assert np.array_equal(v, network_values, equal_nan=True)


@pytest.mark.benchmark(group=GROUP_PATH)
def test_path_scipy(benchmark, network, network_values) -> None:
    _label(benchmark, "scipy", "csgraph.bellman_ford per row (CSR data overwritten)")
    v = benchmark(ScipyLoop(network))
    assert np.array_equal(np.isnan(v), np.isnan(network_values))
    assert_allclose(v, network_values, rtol=0, atol=ATOL_DEG)


@pytest.mark.benchmark(group=GROUP_PATH, min_rounds=SLOW_ROUNDS)
def test_path_networkx(benchmark, network, network_values) -> None:
    _label(benchmark, "networkx", "bellman_ford_path_length per row (weight=callable)")
    v = benchmark(networkx_loop, network)
    assert np.array_equal(np.isnan(v), np.isnan(network_values))
    assert_allclose(v, network_values, rtol=0, atol=ATOL_DEG)


# --- cm.sweep: designs × speeds, in-process and on Dask ---------------------------------


@pytest.fixture(scope="module")
def sweep_reference(loom: cm.Machine) -> cm.SweepResult:
    return cm.sweep(loom, grid(), n_threads=1, progress=False)


def _same_sweep(r: cm.SweepResult, want: cm.SweepResult) -> None:
    assert list(r.columns) == list(want.columns)
    for k, v in want.columns.items():
        if v.dtype == object:
            assert (r.columns[k] == v).all(), k
        else:
            assert np.array_equal(r.columns[k], v, equal_nan=v.dtype.kind == "f"), k


@pytest.mark.benchmark(group=GROUP_SWEEP)
@pytest.mark.parametrize("n_threads", [1, 2], ids=["1-thread", "2-threads"])
def test_sweep_in_process(benchmark, loom, sweep_reference, n_threads) -> None:
    what = f"cm.sweep(machine, grid, n_threads={n_threads})"
    _label(benchmark, "cyclomech", what)
    kw = {"n_threads": n_threads, "progress": False}
    r = benchmark.pedantic(cm.sweep, (loom, grid()), kw, rounds=SLOW_ROUNDS if FULL else 1)
    assert r.n_points == N_PRELOADS * N_SPEEDS
    _same_sweep(r, sweep_reference)
    _record(benchmark, f"sweep-{n_threads}", what, r.n_points)


#: The other shape of 100 000 points: many designs, few speeds (each design one
#: StopImpact, its largest admissible impact speed searched with the others).
N_DESIGNS_WIDE = 1000 if FULL else 20
N_SPEEDS_WIDE = 100 if FULL else 10
GROUP_WIDE = (
    f"cm.sweep: {N_DESIGNS_WIDE} designs × {N_SPEEDS_WIDE} speeds = "
    f"{N_DESIGNS_WIDE * N_SPEEDS_WIDE}"
)


def wide_grid() -> dict[str, Array]:
    return {
        "lifter.preload_m": np.linspace(*PRELOAD_RANGE_M, N_DESIGNS_WIDE),
        "speed_rpm": np.linspace(*SPEED_RANGE_RPM, N_SPEEDS_WIDE),
    }


@pytest.mark.benchmark(group=GROUP_WIDE)
@pytest.mark.parametrize("n_threads", [1, 2], ids=["1-thread", "2-threads"])
def test_wide_sweep_in_process(benchmark, loom, n_threads) -> None:
    what = f"cm.sweep(machine, {N_DESIGNS_WIDE} designs × {N_SPEEDS_WIDE} speeds), {n_threads}"
    _label(benchmark, "cyclomech", what)
    kw = {"n_threads": n_threads, "progress": False}
    r = benchmark.pedantic(cm.sweep, (loom, wide_grid()), kw, rounds=SLOW_ROUNDS if FULL else 1)
    assert r.n_points == N_DESIGNS_WIDE * N_SPEEDS_WIDE
    # Every row is its design's own speed sweep (spot checks: first, middle, last).
    for d in (0, N_DESIGNS_WIDE // 2, N_DESIGNS_WIDE - 1):
        m = loom.with_values({"lifter.preload_m": wide_grid()["lifter.preload_m"][d]})
        rows = slice(d * N_SPEEDS_WIDE, (d + 1) * N_SPEEDS_WIDE)
        want = m.speed_sweep(wide_grid()["speed_rpm"]).limiting_deg
        assert np.array_equal(r.columns["limiting_deg"][rows], want, equal_nan=True)


# --- issue 20: many stop designs in one Rust call ------------------------------------

#: The design axis of issue 20: 10^4 preloads × 100 speeds (full), 200 × 10 (smoke).
N_DESIGNS_BATCH = 10_000 if FULL else 200
N_SPEEDS_BATCH = 100 if FULL else 10
#: The bit-for-bit reference: the per-design path on every BATCH_STRIDE-th design.
BATCH_STRIDE = 10
#: The timed per-design path takes every PER_DESIGN_STRIDE-th design: all of them
#: in a full run (~6 s, one round), so that both paths build the same 10^6-point
#: result (on this VM a fresh array of 4 MB or more may stall in the kernel's
#: attempt at a huge page, see BENCHMARKS.md; a 10× smaller result never does, and
#: would leave the stall on the batch alone).
PER_DESIGN_STRIDE = 1 if FULL else BATCH_STRIDE
#: Rounds of the batch sweep (the median is the figure).
DESIGN_ROUNDS = 3 if FULL else 1
GROUP_BATCH = (
    f"cm.sweep, design axis: {N_DESIGNS_BATCH} preloads × {N_SPEEDS_BATCH} speeds "
    f"(per-design path on every {PER_DESIGN_STRIDE}th design)"
)


def batch_grid(stride: int = 1) -> dict[str, Array]:
    return {
        "lifter.preload_m": np.linspace(*PRELOAD_RANGE_M, N_DESIGNS_BATCH)[::stride],
        "speed_rpm": np.linspace(*SPEED_RANGE_RPM, N_SPEEDS_BATCH),
    }


@pytest.fixture(scope="module")
def batch_reference(loom: cm.Machine) -> cm.SweepResult:
    """The per-design path on the subset: what the batch must give, bit for bit."""
    return cm.sweep(loom, batch_grid(BATCH_STRIDE), progress=False, n_threads=1, batch=False)


def _subset(r: cm.SweepResult, stride: int) -> cm.SweepResult:
    rows = np.arange(r.n_points).reshape(-1, N_SPEEDS_BATCH)[::stride].reshape(-1)
    return cm.SweepResult({k: v[rows] for k, v in r.columns.items()}, r.parameters)


@pytest.mark.benchmark(group=GROUP_BATCH)
@pytest.mark.parametrize("n_threads", [1, 2], ids=["1-thread", "2-threads"])
def test_design_axis_batch(benchmark, loom, batch_reference, n_threads) -> None:
    what = f"cm.sweep(batch=True), {n_threads} thread(s)"
    _label(benchmark, "cyclomech", what)
    kw = {"n_threads": n_threads, "progress": False}
    r = benchmark.pedantic(cm.sweep, (loom, batch_grid()), kw, rounds=DESIGN_ROUNDS)
    _same_sweep(_subset(r, BATCH_STRIDE), batch_reference)
    _record(benchmark, f"design-batch-{n_threads}", what, N_DESIGNS_BATCH)


@pytest.mark.benchmark(group=GROUP_BATCH)
@pytest.mark.parametrize("n_threads", [1, 2], ids=["1-thread", "2-threads"])
def test_design_axis_per_design(benchmark, loom, batch_reference, n_threads) -> None:
    n = N_DESIGNS_BATCH // PER_DESIGN_STRIDE
    what = f"cm.sweep(batch=False) on {n} designs, {n_threads}"
    _label(benchmark, "cyclomech (per design)", what)
    kw = {"n_threads": n_threads, "progress": False, "batch": False}
    r = benchmark.pedantic(cm.sweep, (loom, batch_grid(PER_DESIGN_STRIDE)), kw, rounds=1)
    _same_sweep(_subset(r, BATCH_STRIDE // PER_DESIGN_STRIDE), batch_reference)
    _record(benchmark, f"design-old-{n_threads}", what, n)


def _stop_designs_batch(loom: cm.Machine, preloads: Array) -> Array:
    """What the batch replaced: every design's stop built and solved (v*, the phase
    angle per rpm, the smallest phase angle at every speed) in one Rust call."""
    from cyclomech import _core
    from cyclomech.machine._batch import batch_designs, plan

    pl = plan(loom, ["lifter.preload_m"])
    assert pl is not None
    tables, ok = batch_designs(loom, pl, {"lifter.preload_m": preloads})
    assert ok.all()
    law = loom.mechanisms["lifter"].stop.law  # type: ignore[attr-defined]
    speeds = np.linspace(*SPEED_RANGE_RPM, N_SPEEDS_BATCH)
    return _core.stop_design_batch(law.name, True, None, 0, tables["lifter"], speeds)[4]


def _stop_designs_per_design(loom: cm.Machine, preloads: Array) -> Array:
    """The same per design, as the per-design path does it: a machine with the
    design's values (its StopImpact), then all the stops' laws in one search."""
    ms = [loom.with_values({"lifter.preload_m": float(p)}) for p in preloads]
    laws = cm.machine._model._laws(ms, False, None)
    return np.array([law[0].per_rpm for law in laws])


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_stop_designs_kernel(benchmark, loom) -> None:
    _label(benchmark, "cyclomech", f"{N_DESIGNS_BATCH} stop designs built and solved, 1 call")
    pre = np.linspace(*PRELOAD_RANGE_M, N_DESIGNS_BATCH)
    k = benchmark(_stop_designs_batch, loom, pre)
    want = _stop_designs_per_design(loom, pre[::BATCH_STRIDE])
    assert np.array_equal(k[::BATCH_STRIDE], want)
    _record(benchmark, "stops-batch", "stop designs, batch", N_DESIGNS_BATCH)


@pytest.mark.benchmark(group=GROUP_BATCH, min_rounds=SLOW_ROUNDS)
def test_stop_designs_per_design(benchmark, loom) -> None:
    n = N_DESIGNS_BATCH // BATCH_STRIDE
    _label(benchmark, "cyclomech (per design)", f"{n} machines with_values + their stop laws")
    pre = np.linspace(*PRELOAD_RANGE_M, N_DESIGNS_BATCH)[::BATCH_STRIDE]
    benchmark(_stop_designs_per_design, loom, pre)
    _record(benchmark, "stops-old", "stop designs, per design", n)


def _design_slopes(loom: cm.Machine) -> Array:
    """The 10^4 designs' rebound bounds [deg/rpm] (D, 1), as the batch has them."""
    pre = np.linspace(*PRELOAD_RANGE_M, N_DESIGNS_BATCH)
    law = loom.mechanisms["lifter"].stop.law  # type: ignore[attr-defined]
    from cyclomech import _core
    from cyclomech.machine._batch import batch_designs, plan

    pl = plan(loom, ["lifter.preload_m"])
    assert pl is not None
    tables, _ = batch_designs(loom, pl, {"lifter.preload_m": pre})
    per = _core.stop_design_batch(law.name, True, None, 0, tables["lifter"], np.empty(0))[4]
    return np.ascontiguousarray(per[:, None])


def _python_limits(loom: cm.Machine, per: Array) -> Array:
    """The Python search (SpeedNetwork.speed_limits, the per-design path's)."""
    from cyclomech._kind import Proportional

    def at(designs, rpm):
        m = rpm.shape[1]
        return [Proportional.evaluate(rpm.reshape(-1), np.repeat(per[designs, 0], m))]

    return loom.speed_network.speed_limits(at, per.shape[0], loom.search_start_rpm, 1, 1e-10)


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_speed_limits_rust(benchmark, loom) -> None:
    _label(benchmark, "cyclomech", f"{N_DESIGNS_BATCH} designs' speed limits, 1 Rust call")
    per = _design_slopes(loom)
    net, start = loom.speed_network, loom.search_start_rpm
    got = benchmark(net.speed_limits_proportional, per, start, 1)
    want = _python_limits(loom, per[::BATCH_STRIDE])
    assert np.array_equal(got[::BATCH_STRIDE], want)
    _record(benchmark, "limits-rust", "speed limits, Rust search", N_DESIGNS_BATCH)


@pytest.mark.benchmark(group=GROUP_BATCH, min_rounds=SLOW_ROUNDS)
def test_speed_limits_python(benchmark, loom) -> None:
    n = N_DESIGNS_BATCH // BATCH_STRIDE
    _label(benchmark, "cyclomech (Python search)", f"{n} designs' speed limits, Python search")
    per = _design_slopes(loom)[::BATCH_STRIDE]
    benchmark(_python_limits, loom, per)
    _record(benchmark, "limits-python", "speed limits, Python search", n)


def _start_cluster() -> tuple[Any, Any]:
    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(
        n_workers=DASK_WORKERS,
        processes=True,
        threads_per_worker=1,
        dashboard_address=":0",  # None still binds port 8787 (see tests/machine/test_dask.py)
    )
    client = Client(cluster)
    client.run(importlib.import_module, "cyclomech")  # what the first task would pay
    return cluster, client


def _close_cluster(cluster: Any, client: Any) -> None:
    client.close()
    cluster.close()


@full_only
@pytest.mark.benchmark(group=GROUP_CLUSTER)
def test_cluster_start(benchmark) -> None:
    pytest.importorskip("dask.distributed")
    _label(benchmark, "dask", "LocalCluster + Client + import cyclomech in the workers")
    started: list[tuple[Any, Any]] = []

    def start() -> None:
        started.append(_start_cluster())

    def close() -> None:
        _close_cluster(*started.pop())

    try:
        benchmark.pedantic(start, teardown=close, rounds=SLOW_ROUNDS)
    finally:
        while started:  # --benchmark-disable runs no teardown
            _close_cluster(*started.pop())


@pytest.fixture(scope="module")
def dask_client():
    pytest.importorskip("dask.distributed")
    cluster, client = _start_cluster()
    yield client
    _close_cluster(cluster, client)


@full_only
@pytest.mark.benchmark(group=GROUP_SWEEP)
def test_sweep_dask(benchmark, loom, sweep_reference, dask_client) -> None:
    what = f"cm.sweep(machine, grid, client), LocalCluster of {DASK_WORKERS}×1 thread"
    _label(benchmark, "cyclomech", what)
    r = benchmark.pedantic(
        cm.sweep, (loom, grid(), dask_client), {"progress": False}, rounds=SLOW_ROUNDS
    )
    assert r.n_points == N_PRELOADS * N_SPEEDS
    _same_sweep(r, sweep_reference)
    _record(benchmark, "sweep-dask", what, r.n_points)


# --- the speed limit of a machine with thousands of operations (issue 16 item 20) ------

#: Operations of the chain (a chain given in order, with one time-bound operation at its
#: end): 4000 took 108 s before the depth-first arc order, 20 000 fifteen minutes.
N_CHAIN = 4000 if FULL else 1000
GROUP_CHAIN = f"speed limit: a chain of {N_CHAIN} operations"
#: Its exact limit: the chain's 100° plus 10° at rest, 6·n·0.05 s at n rpm: 360° at
#: n = 260 / 0.3 rpm.
CHAIN_LIMIT_RPM = 260.0 / (6.0 * 0.05)


@pytest.fixture(scope="module")
def chain() -> cm.Machine:
    ops: list[dict[str, Any]] = [
        {"from": str(i), "to": str(i + 1), "min_angle_deg": 100.0 / N_CHAIN} for i in range(N_CHAIN)
    ]
    ops.append({"from": str(N_CHAIN), "to": "end", "min_angle_deg": 10.0, "min_duration_s": 0.05})
    return cm.Machine.from_dict(
        {
            "machine": {"name": "chain", "speed_rpm": [100.0, 200.0]},
            "cyclogram": {"name": "chain", "limiting": [str(N_CHAIN), "end"]},
            "operation": ops,
        }
    )


def chain_lp(m: cm.Machine) -> float:
    """The peer a user writes: one LP (scipy HiGHS) over the event angles p, the
    span's end F and the speed n: max n with p_v − p_u ≥ a and p_v − p_u ≥ 6·n·s
    per operation (its angle and its duration), 0 ≤ p ≤ F ≤ 360."""
    from scipy.optimize import linprog

    cg = m.cyclogram
    ev = {e: k for k, e in enumerate(cg.events)}
    V = len(ev)
    ops = cg.operations
    E = len(ops)
    # Row e: p_u − p_v ≤ −a_e; row E + e: p_u − p_v + 6·s_e·n ≤ 0.
    rows = np.r_[np.repeat(np.arange(E), 2), E + np.repeat(np.arange(E), 3)]
    uv = [[ev[o.src], ev[o.dst]] for o in ops]
    cols = np.r_[np.reshape(uv, -1), np.c_[uv, np.full(E, V + 1)].reshape(-1)]
    secs = [6.0 * o.min_duration_s for o in ops]
    vals = np.r_[np.tile([1.0, -1.0], E), np.c_[np.ones(E), -np.ones(E), secs].reshape(-1)]
    span_rows = 2 * E + np.repeat(np.arange(V), 2)
    span_cols = np.c_[np.arange(V), np.full(V, V)].reshape(-1)
    span_vals = np.tile([1.0, -1.0], V)
    a = sparse.csr_matrix(
        (np.r_[vals, span_vals], (np.r_[rows, span_rows], np.r_[cols, span_cols])),
        shape=(2 * E + V, V + 2),
    )
    b = np.r_[[-o.min_angle_deg for o in ops], np.zeros(E + V)]
    c = np.zeros(V + 2)
    c[-1] = -1.0
    bounds = [(0.0, None)] * V + [(0.0, cg.cycle_deg), (0.0, None)]
    res = linprog(c, A_ub=a, b_ub=b, bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return float(res.x[-1])


@pytest.mark.benchmark(group=GROUP_CHAIN, min_rounds=SLOW_ROUNDS)
def test_chain_speed_limit_cyclomech(benchmark, chain) -> None:
    _label(benchmark, "cyclomech", "Machine.speed_limit() (max_difference search)")
    lim = benchmark(chain.speed_limit)
    # max_difference's documented tolerance: 1e-12·(1 + max|w|)·nodes per relaxation.
    assert lim.rpm == pytest.approx(CHAIN_LIMIT_RPM, rel=1e-7)


@pytest.mark.benchmark(group=GROUP_CHAIN, min_rounds=SLOW_ROUNDS)
def test_chain_speed_limit_howard(benchmark, chain) -> None:
    _label(benchmark, "cyclomech (Howard)", "Cyclogram.max_speed_rpm() (max cycle ratio)")
    lim = benchmark(chain.cyclogram.max_speed_rpm)
    assert lim.rpm == pytest.approx(CHAIN_LIMIT_RPM, rel=1e-9)


@pytest.mark.benchmark(group=GROUP_CHAIN, min_rounds=SLOW_ROUNDS)
def test_chain_speed_limit_lp(benchmark, chain) -> None:
    _label(benchmark, "scipy", "one LP (HiGHS) over event angles and the speed")
    rpm = benchmark(chain_lp, chain)
    assert rpm == pytest.approx(CHAIN_LIMIT_RPM, rel=1e-7)


# --- peak memory of a sweep by its size (issue 20): run in a fresh process each --------


def peak_rss(points: int, out: str | None, designs: int = 1) -> tuple[float, float]:
    """Sweep the loom over ``designs`` preloads × ``points // designs`` speeds,
    streamed to ``out`` (a .parquet path) or held in memory: (seconds, peak RSS [MB]
    of this process, its own start included)."""
    import resource
    import time

    m = cm.Machine.from_toml(LOOM)
    grid = {
        "lifter.preload_m": np.linspace(*PRELOAD_RANGE_M, designs),
        "speed_rpm": np.linspace(*SPEED_RANGE_RPM, points // designs),
    }
    t = time.perf_counter()
    r = cm.sweep(m, grid, progress=False, n_threads=1, out=out)
    seconds = time.perf_counter() - t
    assert r.n_points == points
    return seconds, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


if __name__ == "__main__":
    # python benches/bench_machine.py POINTS [DESIGNS] [OUT.parquet]
    import sys

    n = int(float(sys.argv[1]))
    d = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    target = sys.argv[3] if len(sys.argv) > 3 else None
    s, mb = peak_rss(n, target, d)
    print(
        f"{n:.0e} points ({d} designs), {'streamed' if target else 'in memory'}: "
        f"{s:.2f} s, peak RSS {mb:.0f} MB"
    )
