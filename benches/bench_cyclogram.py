"""Cyclogram-level benchmarks: the LP and the speed limit next to what a user would
otherwise run.

* ``Cyclogram.optimize`` on 1e4 events (E ≈ 4e4 operations), next to the Rust
  longest path of the same network (the issue asks for the two times side by side)
  and to a bare ``scipy.optimize.linprog`` of the same minimum-span LP, assembled
  directly as sparse matrices (what a user without cyclomech would write; it has no
  names, no duals by bound, no tie-break pass and no infeasibility explanation).
* ``Cyclogram.max_speed_rpm`` on the STB example, next to the obvious alternative:
  bisection on speed with a positive-cycle test (networkx Bellman–Ford) per step.

Every benchmark checks its answer against the peer's once, so equal work is timed.
"""

from __future__ import annotations

from pathlib import Path

import cyclomech as cm
import networkx as nx
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy import sparse
from scipy.optimize import linprog

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "stb_group1.toml"
GROUP_LP = "Cyclogram.optimize, V=1e4, E~4e4"
GROUP_SPEED = "max_speed_rpm, STB group 1"
N_EVENTS = 10_000


def _label(benchmark, tool: str, what: str) -> None:
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


class Network:
    """A random DAG as arrays and as a Cyclogram (event ids are the indices as text)."""

    def __init__(self, n: int, seed: int) -> None:
        rng = np.random.default_rng(seed)
        rank = rng.permutation(n)
        a, b = rng.integers(0, n, 4 * n), rng.integers(0, n, 4 * n)
        keep = a != b
        lo, hi = np.minimum(a, b)[keep], np.maximum(a, b)[keep]
        pairs = np.unique(np.stack([rank[lo], rank[hi]], axis=1), axis=0)
        self.n = n
        self.src, self.dst = pairs[:, 0].copy(), pairs[:, 1].copy()
        self.w = rng.uniform(1.0, 10.0, len(pairs))
        self.cyclogram = cm.Cyclogram("bench", cycle_deg=1e9)
        for x, y, w in zip(self.src.tolist(), self.dst.tolist(), self.w.tolist(), strict=True):
            self.cyclogram.add_operation(str(x), str(y), min_angle_deg=w)
        # Cyclogram events are numbered in order of first appearance.
        self.order = np.array([int(e) for e in self.cyclogram.events])


@pytest.fixture(scope="module")
def network() -> Network:
    return Network(N_EVENTS, seed=20261121)


def scipy_min_span(net: Network) -> float:
    """The minimum-span LP with plain scipy: min F s.t. p_x - p_y <= -w, p_v - F <= 0."""
    n, m = net.n, len(net.w)
    rows = np.r_[np.arange(m), np.arange(m), m + np.arange(n), m + np.arange(n)]
    cols = np.r_[net.src, net.dst, np.arange(n), np.full(n, n)]
    vals = np.r_[np.ones(m), -np.ones(m), np.ones(n), -np.ones(n)]
    A = sparse.csr_array((vals, (rows, cols)), shape=(m + n, n + 1))
    b = np.r_[-net.w, np.zeros(n)]
    c = np.zeros(n + 1)
    c[n] = 1.0
    res = linprog(c, A_ub=A, b_ub=b, bounds=(0, None), method="highs")
    assert res.status == 0
    return float(res.fun)


@pytest.mark.benchmark(group=GROUP_LP)
def test_lp_longest_path(benchmark, network: Network) -> None:
    _label(benchmark, "cyclomech", "EventGraph.longest_path(w) (the same network)")
    g = cm.EventGraph(network.n, network.src, network.dst)
    t = benchmark(g.longest_path, network.w)
    assert_allclose(t.max(), scipy_min_span(network), rtol=1e-9)


@pytest.mark.benchmark(group=GROUP_LP)
def test_lp_cyclogram_optimize(benchmark, network: Network) -> None:
    _label(benchmark, "cyclomech LP", "Cyclogram.optimize() (HiGHS, duals, tie-break pass)")
    opt = benchmark.pedantic(network.cyclogram.optimize, rounds=3, iterations=1)
    assert_allclose(opt.objective, scipy_min_span(network), rtol=1e-9)


@pytest.mark.benchmark(group=GROUP_LP)
def test_lp_cyclogram_schedule(benchmark, network: Network) -> None:
    _label(benchmark, "cyclomech schedule", "Cyclogram.schedule() (dicts by event and arc)")
    s = benchmark(network.cyclogram.schedule)
    assert_allclose(s.duration, scipy_min_span(network), rtol=1e-9)


@pytest.mark.benchmark(group=GROUP_LP)
def test_lp_scipy(benchmark, network: Network) -> None:
    _label(benchmark, "scipy", "linprog(highs) of the same LP, matrices prebuilt by hand")
    span = benchmark.pedantic(scipy_min_span, args=(network,), rounds=3, iterations=1)
    g = cm.EventGraph(network.n, network.src, network.dst)
    assert_allclose(span, g.longest_path(network.w).max(), rtol=1e-9)


# --- speed limit ------------------------------------------------------------------


def bisection_speed(cg: cm.Cyclogram, tol: float = 1e-9) -> float:
    """Highest rpm at which no positive cycle exists, by bisection with networkx.

    Weights of the feasibility graph at n rpm: max(min angle, 6·n·s) − cycle·height
    per operation, closed by S → every event (0), every event → F (0), F → S (−cycle).
    Ignores added constraints (the STB example's rebound is handled by cyclomech's
    LP; here it is removed so both compute the same network bound).
    """
    ops, cycle = cg.operations, cg.cycle_deg

    def feasible(n: float) -> bool:
        g = nx.DiGraph()
        for op in ops:
            w = max(op.min_angle_deg, 6.0 * n * op.min_duration_s) - cycle * op.height
            g.add_edge(op.src, op.dst, weight=-w)
        for e in cg.events:
            g.add_edge("__S", e, weight=0.0)
            g.add_edge(e, "__F", weight=0.0)
        g.add_edge("__F", "__S", weight=cycle)
        return not nx.negative_edge_cycle(g, weight="weight")

    lo, hi = 0.0, 1.0
    while feasible(hi):
        lo, hi = hi, 2 * hi
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if feasible(mid) else (lo, mid)
    return lo


@pytest.fixture(scope="module")
def stb_network_only() -> cm.Cyclogram:
    """The STB example without its added constraint and maximum angle: the pure
    network bound, which cyclomech computes by Howard's algorithm alone."""
    full = cm.Cyclogram.from_toml(EXAMPLE)
    cg = cm.Cyclogram(full.name, cycle_deg=full.cycle_deg)
    for op in full.operations:
        cg.add_operation(
            op.src,
            op.dst,
            op.min_angle_deg,
            None,
            op.name,
            op.mechanism,
            min_duration_s=op.min_duration_s,
            height=op.height,
        )
    return cg


@pytest.mark.benchmark(group=GROUP_SPEED)
def test_speed_cyclomech(benchmark, stb_network_only: cm.Cyclogram) -> None:
    _label(benchmark, "cyclomech", "Cyclogram.max_speed_rpm() (Howard + Newton, Rust)")
    cg = stb_network_only
    lim = benchmark(cg.max_speed_rpm)
    assert_allclose(lim.network_rpm, bisection_speed(cg), rtol=1e-7)


@pytest.mark.benchmark(group=GROUP_SPEED)
def test_speed_networkx_bisection(benchmark, stb_network_only: cm.Cyclogram) -> None:
    _label(benchmark, "networkx", "bisection on rpm, negative_edge_cycle per step (rtol 1e-9)")
    rpm = benchmark.pedantic(bisection_speed, args=(stb_network_only,), rounds=3, iterations=1)
    assert_allclose(rpm, stb_network_only.max_speed_rpm().network_rpm, rtol=1e-7)
