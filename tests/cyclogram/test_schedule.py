"""Tests of the scheduling kernels: longest paths, event graphs, cycle ratios.

Covers ``cm.longest_path``, ``cm.EventGraph`` (single and batch longest paths,
``latest``, ``analyze``) and ``cm.max_cycle_ratio``. Every expected value comes from
an independent reference written in this file -- forward and reverse passes over a
networkx topological order, brute-force enumeration of simple cycles with networkx,
or numbers worked out by hand -- never from cyclomech itself. The only
cyclomech-to-cyclomech comparisons are the ones the API promises: a batch row equals
the single solve of that row, whatever the thread settings.
"""

from __future__ import annotations

import math
import pickle
import subprocess
import sys
import textwrap
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any

import cyclomech as cm
import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

# ---------------------------------------------------------------------------
# Independent references
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Net:
    """An event network: ``n`` events, arcs ``src[e] -> dst[e]`` with weights ``w``."""

    n: int
    src: np.ndarray
    dst: np.ndarray
    w: np.ndarray

    @property
    def arcs(self) -> list[tuple[int, int]]:
        return list(zip(self.src.tolist(), self.dst.tolist(), strict=True))


def make_net(n: int, arcs: list[tuple[int, int]], weights: Any) -> Net:
    src = np.array([a for a, _ in arcs], dtype=np.int64)
    dst = np.array([b for _, b in arcs], dtype=np.int64)
    return Net(n, src, dst, np.asarray(weights, dtype=np.float64).reshape(len(arcs)))


def topo_order(net: Net) -> list[int]:
    g = nx.DiGraph()
    g.add_nodes_from(range(net.n))
    g.add_edges_from(net.arcs)
    return list(nx.topological_sort(g))


def ref_earliest(net: Net, weights: Any = None) -> np.ndarray:
    """Forward pass: 0 without incoming arcs, else max over them of p(x) + w.

    ``weights`` (E,) or (B, E), default ``net.w``; rows are evaluated together.
    """
    w = net.w if weights is None else np.asarray(weights, dtype=np.float64)
    rows = w if w.ndim == 2 else w[np.newaxis, :]
    t = np.zeros((rows.shape[0], net.n))
    incoming: dict[int, list[int]] = {v: [] for v in range(net.n)}
    for e, d in enumerate(net.dst.tolist()):
        incoming[d].append(e)
    for v in topo_order(net):
        arcs = incoming[v]
        if arcs:
            t[:, v] = np.max(t[:, net.src[arcs]] + rows[:, arcs], axis=1)
    return t if w.ndim == 2 else t[0]


def ref_tail(net: Net) -> np.ndarray:
    """Reverse pass: longest path from each event to any event (0 for the empty path)."""
    outgoing: dict[int, list[int]] = {v: [] for v in range(net.n)}
    for e, s in enumerate(net.src.tolist()):
        outgoing[s].append(e)
    tail = np.zeros(net.n)
    for v in reversed(topo_order(net)):
        tail[v] = max([0.0] + [net.w[e] + tail[net.dst[e]] for e in outgoing[v]])
    return tail


def brute_max_ratio(net: Net, heights: np.ndarray) -> float | None:
    """Max of sum(w)/sum(h) over all simple cycles (each arc subdivided by a node,
    so parallel arcs and self-loops are distinct cycles), or None without cycles."""
    g = nx.DiGraph()
    g.add_nodes_from(("v", v) for v in range(net.n))
    for e, (a, b) in enumerate(net.arcs):
        g.add_edge(("v", a), ("a", e))
        g.add_edge(("a", e), ("v", b))
    ratios = []
    for cycle in nx.simple_cycles(g):
        arcs = [k for kind, k in cycle if kind == "a"]
        ratios.append(net.w[arcs].sum() / heights[arcs].sum())
    return max(ratios, default=None)


def assert_is_cycle(events: tuple[int, ...], arcs: list[tuple[int, int]]) -> None:
    """``events`` are distinct and each is joined to the next (cyclically) by an arc."""
    assert len(events) >= 1
    assert len(set(events)) == len(events), events
    present = set(arcs)
    for a, b in zip(events, events[1:] + events[:1], strict=True):
        assert (a, b) in present, f"{a} -> {b} is not an arc of the input ({events})"


def close(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9)


# ---------------------------------------------------------------------------
# Random networks
# ---------------------------------------------------------------------------

FLOAT_WEIGHTS = st.floats(-50.0, 100.0, allow_nan=False, allow_infinity=False)
INT_WEIGHTS = st.integers(-5, 10).map(float)  # small integers: exact sums, many ties


@st.composite
def dags(draw: st.DrawFn, weights: st.SearchStrategy[float] = FLOAT_WEIGHTS) -> Net:
    """A random DAG: arcs go from a lower to a higher rank of a random permutation,
    with parallel arcs and E up to ~4V."""
    n = draw(st.integers(1, 30))
    rank = draw(st.permutations(range(n)))
    pairs = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=4 * n))
    arcs = [(rank[min(a, b)], rank[max(a, b)]) for a, b in pairs if a != b]
    if arcs:
        arcs += draw(st.lists(st.sampled_from(arcs), max_size=n))  # parallel arcs
    w = draw(st.lists(weights, min_size=len(arcs), max_size=len(arcs)))
    return make_net(n, arcs, w)


def random_dag(seed: int, n: int, m: int) -> Net:
    """A seeded random DAG with negative weights (numpy generator)."""
    rng = np.random.default_rng(seed)
    rank = rng.permutation(n)
    a, b = rng.integers(0, n, size=(2, m))
    keep = a != b
    lo, hi = np.minimum(a, b)[keep], np.maximum(a, b)[keep]
    return Net(n, rank[lo], rank[hi], rng.uniform(-60.0, 100.0, size=lo.size))


SMALL = random_dag(1, 30, 90)
PARALLEL = random_dag(2, 200, 800)  # 83 rows x ~800 arcs > 2**16: the threaded path
PARALLEL_ROWS = 83


def batch_weights(net: Net, rows: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(-60.0, 100.0, size=(rows, len(net.src)))


# ---------------------------------------------------------------------------
# Earliest times
# ---------------------------------------------------------------------------

DOC_NET = make_net(4, [(0, 1), (1, 3), (0, 2), (2, 3)], [30.0, 50.0, 100.0, -20.0])


def test_doc_example_by_hand() -> None:
    # 0 -30-> 1 -50-> 3 and 0 -100-> 2 -(-20)-> 3: event 3 at max(80, 80) = 80.
    got = cm.longest_path(DOC_NET.n, DOC_NET.src, DOC_NET.dst, DOC_NET.w)
    assert_array_equal(got, [0.0, 30.0, 100.0, 80.0])


@settings(max_examples=80, deadline=None)
@given(net=dags())
def test_earliest_matches_forward_pass(net: Net) -> None:
    want = ref_earliest(net)
    assert_allclose(cm.longest_path(net.n, net.src, net.dst, net.w), want, rtol=1e-12, atol=1e-9)
    g = cm.EventGraph(net.n, net.src, net.dst)
    assert_allclose(g.longest_path(net.w), want, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("seed", [10, 11, 12])
def test_earliest_matches_forward_pass_v1000(seed: int) -> None:
    net = random_dag(seed, 1000, 4000)
    got = cm.longest_path(net.n, net.src, net.dst, net.w)
    assert_allclose(got, ref_earliest(net), rtol=1e-12, atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(net=dags())
def test_event_graph_structure(net: Net) -> None:
    g = cm.EventGraph(net.n, net.src, net.dst)
    assert (g.n_events, g.n_arcs) == (net.n, len(net.src))
    assert_array_equal(g.src, net.src)
    assert_array_equal(g.dst, net.dst)
    order = g.topological_order.tolist()
    assert sorted(order) == list(range(net.n))
    position = {v: k for k, v in enumerate(order)}
    assert all(position[a] < position[b] for a, b in net.arcs)
    assert repr(g) == f"EventGraph(n_events={net.n}, n_arcs={len(net.src)})"


# ---------------------------------------------------------------------------
# Batches
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("n_threads", [1, 2])
@pytest.mark.parametrize(
    ("net", "rows"),
    [(SMALL, b) for b in (0, 1, 7, 8, 9, 17)] + [(PARALLEL, PARALLEL_ROWS)],
    ids=[f"small-B{b}" for b in (0, 1, 7, 8, 9, 17)] + [f"parallel-B{PARALLEL_ROWS}"],
)
def test_batch_rows_equal_single_solves(net: Net, rows: int, n_threads: int) -> None:
    g = cm.EventGraph(net.n, net.src, net.dst)
    w = batch_weights(net, rows)
    got = g.longest_path(w, n_threads=n_threads)
    assert got.shape == (rows, net.n)
    for r in range(rows):
        assert_array_equal(got[r], g.longest_path(w[r]))
    assert_allclose(got, ref_earliest(net, w).reshape(rows, net.n), rtol=1e-12, atol=1e-9)
    one_shot = cm.longest_path(net.n, net.src, net.dst, w, n_threads=n_threads)
    assert_array_equal(one_shot, got)


@settings(max_examples=40, deadline=None)
@given(net=dags(), rows=st.integers(0, 20), n_threads=st.sampled_from([1, 2]), seed=st.integers(0))
def test_batch_matches_forward_pass(net: Net, rows: int, n_threads: int, seed: int) -> None:
    w = batch_weights(net, rows, seed)
    got = cm.EventGraph(net.n, net.src, net.dst).longest_path(w, n_threads=n_threads)
    assert_allclose(got, ref_earliest(net, w).reshape(rows, net.n), rtol=1e-12, atol=1e-9)


# ---------------------------------------------------------------------------
# Latest times, slack and critical arcs
# ---------------------------------------------------------------------------


def check_analysis(net: Net, a: cm.GraphAnalysis, horizon: float) -> None:
    """Compare an analysis with the forward/reverse reference passes."""
    early = ref_earliest(net)
    late = horizon - ref_tail(net)  # every event, not only the sinks, capped at the horizon
    assert a.horizon == horizon
    assert_allclose(a.earliest, early, rtol=1e-12, atol=1e-9)
    assert_allclose(a.latest, late, rtol=1e-12, atol=1e-9)
    s, d = net.src, net.dst
    assert_allclose(a.total_slack, late[d] - early[s] - net.w, rtol=1e-12, atol=1e-9)
    assert_allclose(a.free_slack, early[d] - early[s] - net.w, rtol=1e-12, atol=1e-9)


@settings(max_examples=80, deadline=None)
@given(net=dags(weights=INT_WEIGHTS))
def test_critical_arcs_are_those_on_some_longest_path(net: Net) -> None:
    # Integer weights: sums are exact and ties (several longest paths) are common.
    a = cm.EventGraph(net.n, net.src, net.dst).analyze(net.w)
    early, tail = ref_earliest(net), ref_tail(net)
    longest = early.max()
    check_analysis(net, a, longest)
    on_longest = early[net.src] + net.w + tail[net.dst] == longest
    assert_array_equal(a.critical, on_longest)
    assert a.critical.dtype == np.bool_


@settings(max_examples=60, deadline=None)
@given(net=dags(), extra=st.floats(1.0, 500.0))
def test_latest_for_a_later_horizon(net: Net, extra: float) -> None:
    g = cm.EventGraph(net.n, net.src, net.dst)
    horizon = float(ref_earliest(net).max()) + extra
    a = g.analyze(net.w, horizon=horizon)
    check_analysis(net, a, horizon)
    assert not a.critical.any()  # every arc has at least `extra` of slack
    assert_allclose(g.latest(net.w, horizon), horizon - ref_tail(net), rtol=1e-12, atol=1e-9)


HAND_ANALYSES = {
    # Event 2 ends the schedule though it is no sink: 0 -> 2 alone is critical.
    "overlap": (DOC_NET, [0, 50, 100, 100], [False, False, True, False]),
    # Two longest paths 0-1-3 and 0-2-3 (30); 1 -> 2, 0 -> 3 and 3 -> 4 are not on one.
    "ties": (
        make_net(
            5, [(0, 1), (1, 3), (0, 2), (2, 3), (1, 2), (0, 3), (3, 4)], [10, 20, 20, 10, 5, 25, -5]
        ),
        [0, 10, 20, 30, 30],
        [True, True, True, True, False, False, False],
    ),
    # A negative last arc: event 2 (at 50) may still move up to the horizon 100.
    "negative tail": (make_net(3, [(0, 1), (1, 2)], [100, -50]), [0, 100, 100], [True, False]),
    # No arcs at all: every event at 0, horizon 0.
    "no arcs": (make_net(3, [], []), [0, 0, 0], []),
}


@pytest.mark.parametrize(("net", "latest", "critical"), HAND_ANALYSES.values(), ids=HAND_ANALYSES)
def test_analysis_by_hand(net: Net, latest: list[float], critical: list[bool]) -> None:
    a = cm.EventGraph(net.n, net.src, net.dst).analyze(net.w)
    assert_array_equal(a.latest, latest)
    assert_array_equal(a.critical, np.array(critical, dtype=bool))
    check_analysis(net, a, float(max(latest, default=0.0)))


def test_empty_graph_analysis() -> None:
    a = cm.EventGraph(0, [], []).analyze([])
    assert a.horizon == 0.0
    for f in ("earliest", "latest", "total_slack", "free_slack", "critical"):
        assert getattr(a, f).shape == (0,)
    assert cm.EventGraph(0, [], []).latest([], 5.0).shape == (0,)


# ---------------------------------------------------------------------------
# Maximum cycle ratio
# ---------------------------------------------------------------------------


@st.composite
def cyclic_nets(draw: st.DrawFn) -> tuple[Net, np.ndarray]:
    """Random graphs whose height-0 arcs go forward in index order (a DAG); backward
    arcs and self-loops get height 1 or 2, some forward arcs height 1."""
    n = draw(st.integers(1, 6))
    pairs = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=12))
    heights = [
        draw(st.sampled_from([0.0, 0.0, 1.0]) if a < b else st.sampled_from([1.0, 2.0]))
        for a, b in pairs
    ]
    w = draw(
        st.lists(st.one_of(FLOAT_WEIGHTS, INT_WEIGHTS), min_size=len(pairs), max_size=len(pairs))
    )
    return make_net(n, pairs, w), np.array(heights, dtype=np.float64)


@settings(max_examples=150, deadline=None)
@given(case=cyclic_nets())
def test_max_cycle_ratio_matches_enumeration(case: tuple[Net, np.ndarray]) -> None:
    net, h = case
    got = cm.max_cycle_ratio(net.n, net.src, net.dst, net.w, h)
    want = brute_max_ratio(net, h)
    if want is None:
        assert got is None
        return
    assert got is not None
    ratio, arcs = got
    assert close(ratio, want), (ratio, want)
    arcs = arcs.tolist()
    assert arcs, "a cycle needs at least one arc"
    for e, f in zip(arcs, arcs[1:] + arcs[:1], strict=True):
        assert net.dst[e] == net.src[f], f"arcs {arcs} are not a closed walk"
    assert close(net.w[arcs].sum() / h[arcs].sum(), ratio)


MAX_RATIO_BY_HAND = {
    "two-arc loop": ((2, [0, 1], [1, 0], [100.0, 200.0], [0.0, 1.0]), (300.0, [0, 1])),
    "self-loop": ((3, [0, 1], [1, 1], [5.0, 7.0], [0.0, 2.0]), (3.5, [1])),
    "dag": ((3, [0, 1], [1, 2], [5.0, 7.0], [0.0, 0.0]), None),
    "no events": ((0, [], [], [], []), None),
    "no arcs": ((4, [], [], [], []), None),
}


@pytest.mark.parametrize(("args", "want"), MAX_RATIO_BY_HAND.values(), ids=MAX_RATIO_BY_HAND)
def test_max_cycle_ratio_by_hand(
    args: tuple[Any, ...], want: tuple[float, list[int]] | None
) -> None:
    got = cm.max_cycle_ratio(*args)
    if want is None:
        assert got is None
    else:
        assert got is not None
        assert got[0] == want[0]
        assert got[1].tolist() == want[1]


# ---------------------------------------------------------------------------
# Bad input: CyclomechError (a ValueError) naming the field and the value
# ---------------------------------------------------------------------------

NAN, INF = float("nan"), float("inf")
S, D, W = [0, 1], [1, 2], [1.0, 2.0]  # a valid 3-event chain
G = cm.EventGraph(3, S, D)


def batch_with(
    position: tuple[int, int], value: float, shape: tuple[int, int] = (3, 7)
) -> np.ndarray:
    w = np.ones(shape)
    w[position] = value
    return w


CHAIN7 = cm.EventGraph(8, list(range(7)), list(range(1, 8)))

BAD_INPUTS: dict[str, tuple[Callable[[], Any], type[Exception], list[str]]] = {
    "cycle": (
        lambda: cm.longest_path(3, [0, 1, 2], [1, 2, 0], [1.0] * 3),
        cm.CycleError,
        ["cycle", "[0, 1, 2]"],
    ),
    "self-loop": (lambda: cm.EventGraph(3, [0, 1], [1, 1]), cm.CycleError, ["cycle", "[1]"]),
    "nan weight": (
        lambda: cm.longest_path(3, S, D, [1.0, NAN]),
        cm.InputError,
        ["weights[1] = NaN"],
    ),
    "inf weight": (lambda: G.longest_path([INF, 1.0]), cm.InputError, ["weights[0] = inf"]),
    "-inf weight": (lambda: G.analyze([1.0, -INF]), cm.InputError, ["weights[1] = -inf"]),
    "nan weight latest": (lambda: G.latest([NAN, 1.0], 9.0), cm.InputError, ["weights[0] = NaN"]),
    "inf in batch": (
        lambda: CHAIN7.longest_path(batch_with((2, 5), INF)),
        cm.InputError,
        ["weights[2, 5] = inf"],
    ),
    "nan in batch": (
        lambda: CHAIN7.longest_path(batch_with((0, 6), NAN)),
        cm.InputError,
        ["weights[0, 6] = NaN"],
    ),
    "index too large": (
        lambda: cm.longest_path(3, S, [1, 5], W),
        cm.InputError,
        ["dst[1] = 5", "n_events = 3"],
    ),
    "index 2**62": (lambda: cm.EventGraph(3, [0], [2**62]), cm.InputError, [f"dst[0] = {2**62}"]),
    "negative index": (lambda: cm.longest_path(3, [0, -1], D, W), cm.InputError, ["src[1] = -1"]),
    "length mismatch": (
        lambda: cm.EventGraph(3, [0, 1], [1]),
        cm.InputError,
        ["src and dst", "2 and 1"],
    ),
    "weights too short": (
        lambda: cm.longest_path(3, S, D, [1.0]),
        cm.InputError,
        ["weights", "2", "got 1"],
    ),
    "weights too long": (
        lambda: G.analyze([1.0, 2.0, 3.0]),
        cm.InputError,
        ["weights", "2", "got 3"],
    ),
    "batch rows too long": (
        lambda: G.longest_path(np.ones((4, 3))),
        cm.InputError,
        ["weights", "got 3"],
    ),
    "3-D weights": (
        lambda: G.longest_path(np.ones((2, 2, 2))),
        cm.InputError,
        ["weights", "(2, 2, 2)"],
    ),
    "scalar weights": (lambda: G.longest_path(1.0), cm.InputError, ["weights", "()"]),
    "2-D weights to analyze": (
        lambda: G.analyze(np.ones((1, 2))),
        cm.InputError,
        ["weights", "(1, 2)"],
    ),
    "2-D weights to latest": (
        lambda: G.latest(np.ones((1, 2)), 5.0),
        cm.InputError,
        ["weights", "(1, 2)"],
    ),
    "string weights": (lambda: G.longest_path(["a", "b"]), cm.InputError, ["weights", "<U1"]),
    "float src": (lambda: cm.EventGraph(3, [0.0, 1.0], D), cm.InputError, ["src", "float64"]),
    "string src": (
        lambda: cm.longest_path(3, ["a", "b"], D, W),
        cm.InputError,
        ["src", "<U1", "'a'"],
    ),
    "2-D dst": (lambda: cm.EventGraph(3, S, [D]), cm.InputError, ["dst", "(1, 2)"]),
    "n_events negative": (lambda: cm.longest_path(-1, S, D, W), cm.InputError, ["n_events", "-1"]),
    "n_events bool": (lambda: cm.EventGraph(True, [], []), cm.InputError, ["n_events", "True"]),
    "n_events float": (lambda: cm.EventGraph(3.0, S, D), cm.InputError, ["n_events", "3.0"]),
    "n_events 2**40": (
        lambda: cm.EventGraph(2**40, [], []),
        cm.InputError,
        ["n_events", str(2**40)],
    ),
    "n_events 2**63": (
        lambda: cm.longest_path(2**63, [], [], []),
        cm.InputError,
        ["n_events", str(2**63)],
    ),
    "n_threads 0": (
        lambda: G.longest_path(np.ones((2, 2)), n_threads=0),
        cm.InputError,
        ["n_threads", "0"],
    ),
    "n_threads -1": (
        lambda: cm.longest_path(3, S, D, [W], n_threads=-1),
        cm.InputError,
        ["n_threads", "-1"],
    ),
    "n_threads '2'": (
        lambda: G.longest_path([W], n_threads="2"),
        cm.InputError,
        ["n_threads", "'2'"],
    ),
    "n_threads 2.0": (
        lambda: G.longest_path([W], n_threads=2.0),
        cm.InputError,
        ["n_threads", "2.0"],
    ),
    "n_threads True": (
        lambda: G.longest_path([W], n_threads=True),
        cm.InputError,
        ["n_threads", "True"],
    ),
    "n_threads 5000": (
        lambda: G.longest_path([W], n_threads=5000),
        cm.InputError,
        ["n_threads", "5000"],
    ),
    "horizon nan": (lambda: G.latest(W, NAN), cm.InputError, ["horizon", "NaN"]),
    "horizon inf": (lambda: G.analyze(W, horizon=INF), cm.InputError, ["horizon", "inf"]),
    "horizon string": (lambda: G.analyze(W, horizon="x"), cm.InputError, ["horizon", "'x'"]),
    "heights negative": (
        lambda: cm.max_cycle_ratio(2, [0, 1], [1, 0], [1.0, 1.0], [0.0, -1.0]),
        cm.InputError,
        ["heights[1] = -1"],
    ),
    "heights nan": (
        lambda: cm.max_cycle_ratio(2, [0, 1], [1, 0], [1.0, 1.0], [0.0, NAN]),
        cm.InputError,
        ["heights[1] = NaN"],
    ),
    "heights too short": (
        lambda: cm.max_cycle_ratio(2, [0, 1], [1, 0], [1.0, 1.0], [1.0]),
        cm.InputError,
        ["heights", "got 1"],
    ),
    "ratio weights inf": (
        lambda: cm.max_cycle_ratio(2, [0, 1], [1, 0], [1.0, INF], [1.0, 1.0]),
        cm.InputError,
        ["weights[1] = inf"],
    ),
    "ratio index out of range": (
        lambda: cm.max_cycle_ratio(2, [0, 1], [1, 2], [1.0, 1.0], [1.0, 1.0]),
        cm.InputError,
        ["dst[1] = 2"],
    ),
    "zero-height cycle": (
        lambda: cm.max_cycle_ratio(3, [0, 1, 2], [1, 2, 0], [1.0] * 3, [0.0] * 3),
        cm.CycleError,
        ["height 0", "[0, 1, 2]"],
    ),
}


@pytest.mark.parametrize(("call", "cls", "fragments"), BAD_INPUTS.values(), ids=BAD_INPUTS)
def test_bad_input_is_a_named_error(
    call: Callable[[], Any], cls: type[Exception], fragments: list[str]
) -> None:
    with pytest.raises(cls) as info:
        call()
    assert isinstance(info.value, cm.CyclomechError)
    assert isinstance(info.value, ValueError)
    for fragment in fragments:
        assert fragment in str(info.value), f"{fragment!r} not in {str(info.value)!r}"


@settings(max_examples=100, deadline=None)
@given(
    n=st.integers(1, 8),
    pairs=st.lists(st.tuples(st.integers(0, 7), st.integers(0, 7)), max_size=16),
)
def test_cycle_error_names_a_cycle_of_the_input(n: int, pairs: list[tuple[int, int]]) -> None:
    arcs = [(a % n, b % n) for a, b in pairs]
    net = make_net(n, arcs, np.ones(len(arcs)))
    g = nx.DiGraph(arcs)
    if nx.is_directed_acyclic_graph(g):
        assert_allclose(cm.longest_path(n, net.src, net.dst, net.w), ref_earliest(net))
        return
    for build in (
        lambda: cm.EventGraph(n, net.src, net.dst),
        lambda: cm.longest_path(n, net.src, net.dst, net.w),
        lambda: cm.max_cycle_ratio(n, net.src, net.dst, net.w, np.zeros(len(arcs))),
    ):
        with pytest.raises(cm.CycleError) as info:
            build()
        assert_is_cycle(info.value.events, arcs)
        assert str(list(info.value.events)) in str(info.value)


def test_zero_height_cycle_names_height_zero_arcs() -> None:
    # 1 -> 2 -> 3 -> 1 at height 0 and a 0 <-> 1 loop that does cross a cycle.
    arcs = [(0, 1), (1, 0), (1, 2), (2, 3), (3, 1)]
    h = np.array([0.0, 1.0, 0.0, 0.0, 0.0])
    net = make_net(4, arcs, np.ones(5))
    with pytest.raises(cm.CycleError) as info:
        cm.max_cycle_ratio(net.n, net.src, net.dst, net.w, h)
    assert_is_cycle(info.value.events, [a for a, k in zip(arcs, h, strict=True) if k == 0])


@pytest.mark.parametrize("value", ["garbage", "0", "-1", "1.5", "100000", "2 threads"])
def test_bad_threads_env_is_named(monkeypatch: pytest.MonkeyPatch, value: str) -> None:
    monkeypatch.setenv("CYCLOMECH_THREADS", value)
    with pytest.raises(cm.InputError) as info:
        G.longest_path(np.ones((3, 2)))
    assert "CYCLOMECH_THREADS" in str(info.value)
    assert value in str(info.value)
    # Read at each batch call, not once at import; an explicit argument wins.
    assert_array_equal(G.longest_path([W], n_threads=1), [[0.0, 1.0, 3.0]])
    monkeypatch.setenv("CYCLOMECH_THREADS", "1")
    assert_array_equal(G.longest_path([W]), [[0.0, 1.0, 3.0]])


# ---------------------------------------------------------------------------
# Regressions: bugs found while writing this suite, fixed since
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("n_threads", [0, -1])
def test_bad_n_threads_rejected_for_single_solves(n_threads: int) -> None:
    with pytest.raises(cm.InputError, match="n_threads"):
        G.longest_path(W, n_threads=n_threads)


def test_huge_n_threads_is_an_input_error() -> None:
    with pytest.raises(cm.InputError, match="n_threads"):
        G.longest_path([W], n_threads=2**70)


def test_uint64_index_is_named_with_its_value() -> None:
    with pytest.raises(cm.InputError) as info:
        cm.EventGraph(3, np.array([0], np.uint64), np.array([2**63], np.uint64))
    assert f"dst[0] = {2**63}" in str(info.value)


def test_empty_batch_with_wrong_row_length_is_rejected() -> None:
    with pytest.raises(cm.InputError, match="weights"):
        G.longest_path(np.ones((0, 5)))


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses RLIMIT_AS")
def test_huge_accepted_n_events_does_not_abort_the_interpreter() -> None:
    # n_events = 10**9 passes validation (limit 2**32 - 2); the kernel then needs
    # several GB. With 2 GiB of address space the allocation must fail cleanly.
    code = textwrap.dedent(
        """
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
        import cyclomech as cm
        try:
            cm.longest_path(10**9, [], [], [])
        except cm.CyclomechError:
            pass
        print("survived")
        """
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and "survived" in run.stdout, run.stderr[:300]


# ---------------------------------------------------------------------------
# No panic crosses into Python
# ---------------------------------------------------------------------------

ERROR = cm.CyclomechError
EXTREME_INPUTS: dict[str, tuple[Callable[[], Any], Any]] = {
    "n_events 2**40": (lambda: cm.longest_path(2**40, [], [], []), ERROR),
    "n_events 2**32 - 1": (lambda: cm.EventGraph(2**32 - 1, [], []), ERROR),
    "n_events 2**63 - 1": (lambda: cm.longest_path(2**63 - 1, [], [], []), ERROR),
    "index 2**62": (lambda: cm.longest_path(3, [0], [2**62], [1.0]), ERROR),
    "index -2**63": (lambda: cm.longest_path(3, [-(2**63)], [1], [1.0]), ERROR),
    "ratio n_events 2**40": (lambda: cm.max_cycle_ratio(2**40, [], [], [], []), ERROR),
    "ratio index 2**62": (lambda: cm.max_cycle_ratio(2, [2**62], [0], [1.0], [1.0]), ERROR),
    "V=0 E=0": (lambda: cm.longest_path(0, [], [], []), np.zeros(0)),
    "V=0 batch": (
        lambda: cm.longest_path(0, [], [], np.zeros((4, 0)), n_threads=2),
        np.zeros((4, 0)),
    ),
    "V=0 B=0": (lambda: cm.EventGraph(0, [], []).longest_path(np.zeros((0, 0))), np.zeros((0, 0))),
    "E=0": (lambda: cm.longest_path(5, [], [], []), np.zeros(5)),
    "E=0 batch": (lambda: cm.longest_path(5, [], [], np.zeros((9, 0))), np.zeros((9, 5))),
    "E=0 B=0": (lambda: cm.longest_path(5, [], [], np.zeros((0, 0))), np.zeros((0, 5))),
    "latest V=0": (lambda: cm.EventGraph(0, [], []).latest([], 1.0), np.zeros(0)),
    "latest E=0": (lambda: cm.EventGraph(2, [], []).latest([], 7.0), np.full(2, 7.0)),
    # Finite but huge: 1e308 + 1e308 would be inf; magnitudes above 1e12 are refused.
    "huge weight": (lambda: cm.longest_path(2, [0], [1], [1e308]), ERROR),
    "huge weights summing to inf": (
        lambda: cm.longest_path(3, [0, 1], [1, 2], [1e308, 1e308]),
        ERROR,
    ),
    "largest accepted weights": (
        lambda: cm.longest_path(3, [0, 1], [1, 2], [1e12, 1e12]),
        np.array([0.0, 1e12, 2e12]),
    ),
    "denormal height": (
        lambda: cm.max_cycle_ratio(2, [0, 1], [1, 0], [1.0, 1.0], [0, 1e-320]),
        ERROR,
    ),
}


@pytest.mark.parametrize(("call", "expected"), EXTREME_INPUTS.values(), ids=EXTREME_INPUTS)
def test_extreme_input_is_an_error_or_a_right_answer(
    call: Callable[[], Any], expected: Any
) -> None:
    try:
        got = call()
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as e:  # pyo3's PanicException derives from BaseException
        assert isinstance(e, ERROR), f"{type(e).__module__}.{type(e).__name__}: {e}"
        assert expected is ERROR, f"unexpected error {e}"
        return
    assert expected is not ERROR, f"expected an error, got {got!r}"
    assert got.shape == expected.shape
    assert_array_equal(got, expected)


# ---------------------------------------------------------------------------
# Pickling
# ---------------------------------------------------------------------------


def test_event_graph_pickles() -> None:
    g = cm.EventGraph(SMALL.n, SMALL.src, SMALL.dst)
    h = pickle.loads(pickle.dumps(g))
    assert isinstance(h, cm.EventGraph)
    assert (h.n_events, h.n_arcs) == (SMALL.n, len(SMALL.src))
    assert_array_equal(h.src, SMALL.src)
    assert_array_equal(h.dst, SMALL.dst)
    assert_allclose(h.longest_path(SMALL.w), ref_earliest(SMALL), rtol=1e-12, atol=1e-9)


def test_graph_analysis_pickles() -> None:
    a = cm.EventGraph(DOC_NET.n, DOC_NET.src, DOC_NET.dst).analyze(DOC_NET.w)
    b = pickle.loads(pickle.dumps(a))
    assert type(b) is cm.GraphAnalysis
    for f in fields(cm.GraphAnalysis):
        assert_array_equal(getattr(b, f.name), getattr(a, f.name))
    assert_array_equal(b.latest, [0.0, 50.0, 100.0, 100.0])
    assert b.horizon == 100.0


EXCEPTIONS = [
    cm.CyclomechError("weights[1] = NaN"),
    cm.InputError("n_events = -1 is invalid"),
    cm.CycleError("cycle through events [1, 2]", events=[1, 2]),
    cm.InfeasibleError("too long", conflict=("press", "feed")),
    cm.SolverError("did not converge"),
    cm.InternalError("kernel state"),
]


@pytest.mark.parametrize("exc", EXCEPTIONS, ids=lambda e: type(e).__name__)
def test_exceptions_pickle(exc: Exception) -> None:
    back = pickle.loads(pickle.dumps(exc))
    assert type(back) is type(exc)
    assert str(back) == str(exc)
    assert isinstance(back, cm.CyclomechError)
    assert isinstance(back, ValueError)
    for attr in ("events", "conflict"):
        assert getattr(back, attr, None) == getattr(exc, attr, None)


def test_kernel_cycle_error_pickles_with_its_events() -> None:
    with pytest.raises(cm.CycleError) as info:
        cm.EventGraph(4, [0, 1, 2, 3], [1, 2, 3, 1])
    back = pickle.loads(pickle.dumps(info.value))
    assert back.events == info.value.events == (1, 2, 3)
    assert str(back) == str(info.value)


# ---------------------------------------------------------------------------
# Thread settings
# ---------------------------------------------------------------------------

THREAD_SETTINGS = [
    ("arg", 1),
    ("arg", 2),
    ("env", "1"),
    ("env", "2"),
    ("env", " 2 "),
    ("default", None),
]


@pytest.fixture(scope="module")
def parallel_case() -> tuple[np.ndarray, np.ndarray]:
    w = batch_weights(PARALLEL, PARALLEL_ROWS, seed=7)
    return w, ref_earliest(PARALLEL, w)


@pytest.mark.parametrize(
    ("how", "value"), THREAD_SETTINGS, ids=[f"{h}={v}" for h, v in THREAD_SETTINGS]
)
def test_thread_settings_give_identical_results(
    monkeypatch: pytest.MonkeyPatch,
    parallel_case: tuple[np.ndarray, np.ndarray],
    how: str,
    value: Any,
) -> None:
    w, want = parallel_case
    g = cm.EventGraph(PARALLEL.n, PARALLEL.src, PARALLEL.dst)
    monkeypatch.delenv("CYCLOMECH_THREADS", raising=False)
    serial = g.longest_path(w, n_threads=1)
    if how == "env":
        monkeypatch.setenv("CYCLOMECH_THREADS", value)
    got = g.longest_path(w, n_threads=value if how == "arg" else None)
    assert_array_equal(got, serial)
    assert_allclose(got, want, rtol=1e-12, atol=1e-9)


# ---------------------------------------------------------------------------
# Accepted input types
# ---------------------------------------------------------------------------

INDEX_TYPES: dict[str, Callable[[np.ndarray], Any]] = {
    "list": lambda a: a.tolist(),
    "tuple": lambda a: tuple(a.tolist()),
    "int32": lambda a: a.astype(np.int32),
    "int16": lambda a: a.astype(np.int16),
    "uint8": lambda a: a.astype(np.uint8),
    "uint32": lambda a: a.astype(np.uint32),
    "uint64": lambda a: a.astype(np.uint64),
    "strided": lambda a: np.repeat(a, 2)[::2],
}


@pytest.mark.parametrize("convert", INDEX_TYPES.values(), ids=INDEX_TYPES)
def test_index_types_are_accepted(convert: Callable[[np.ndarray], Any]) -> None:
    src, dst = convert(SMALL.src), convert(SMALL.dst)
    want = ref_earliest(SMALL)
    assert_allclose(cm.longest_path(SMALL.n, src, dst, SMALL.w), want, rtol=1e-12, atol=1e-9)
    g = cm.EventGraph(SMALL.n, src, dst)
    assert_array_equal(g.src, SMALL.src)
    assert_allclose(g.analyze(SMALL.w).earliest, want, rtol=1e-12, atol=1e-9)


WEIGHT_TYPES: dict[str, Callable[[np.ndarray], Any]] = {
    "float32": lambda w: w.astype(np.float32),
    "int64": lambda w: np.round(w).astype(np.int64),
    "int32": lambda w: np.round(w).astype(np.int32),
    "list of ints": lambda w: np.round(w).astype(int).tolist(),
    "tuple": lambda w: tuple(w.tolist()),
    "strided": lambda w: np.repeat(w, 2)[::2],
}


@pytest.mark.parametrize("convert", WEIGHT_TYPES.values(), ids=WEIGHT_TYPES)
def test_weight_types_are_accepted(convert: Callable[[np.ndarray], Any]) -> None:
    w = convert(SMALL.w)
    exact = np.asarray(w, dtype=np.float64)  # the values as the caller gave them
    want = ref_earliest(SMALL, exact)
    g = cm.EventGraph(SMALL.n, SMALL.src, SMALL.dst)
    assert_allclose(g.longest_path(w), want, rtol=1e-12, atol=1e-9)
    assert_allclose(g.analyze(w).earliest, want, rtol=1e-12, atol=1e-9)
    rows = np.asfortranarray(np.stack([exact, exact + 1.0, exact - 2.0]))
    assert_allclose(g.longest_path(rows), ref_earliest(SMALL, rows), rtol=1e-12, atol=1e-9)
    assert_allclose(
        g.longest_path(rows.astype(np.float32)),
        ref_earliest(SMALL, rows.astype(np.float32)),
        rtol=1e-12,
        atol=1e-9,
    )
