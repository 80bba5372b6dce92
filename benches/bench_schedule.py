"""Benchmarks of the longest-path scheduling kernel against rustworkx and networkx.

Every comparison is of equal work on the same random DAG: each benchmark checks once
that cyclomech's largest earliest event angle equals the peer's longest-path length.
Building a graph and solving on it are separate groups, because cyclomech analyses
the structure once (:class:`cyclomech.EventGraph`) and then only evaluates weights.

The default test run (``--benchmark-disable`` in addopts) calls each benchmark once as
a smoke test. For timings::

    python -m pytest benches/bench_schedule.py --benchmark-enable -q

``conftest.py`` then prints the median of every tool and its ratio to cyclomech.

The scaling rows (issue 20: per-arc time flat from V = 1e3 to 1e6) are one group per
size; for their time per arc::

    python -m pytest benches/bench_schedule.py -k scale --benchmark-enable -q \
        -p no:cacheprovider --benchmark-json=/tmp/scale.json
    python benches/bench_schedule.py /tmp/scale.json

Issue 37's row, the prepared solve against the random gather + scatter floor at
V = 1e5 and 1e6, one thread, both page states (:func:`floor_ratio_table`)::

    taskset -c 1 python benches/bench_schedule.py floor
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from _timing import page_states, print_states, timed_run
from numpy.testing import assert_allclose

rx = pytest.importorskip("rustworkx")
nx = pytest.importorskip("networkx")

#: Sizes: E = 4 V arcs.
ARCS_PER_EVENT = 4
LARGE_EVENTS = 100_000
BATCH_EVENTS = 1_000
#: Weight vectors of the batch benchmark (e.g. tolerance or speed variants).
BATCH_ROWS = 1_000
CYCLOGRAM_EVENTS = 30
CYCLOGRAM_ARCS = 90
#: Phase angles [deg]; positive, so that every tool agrees on the longest path.
MIN_ANGLE_DEG = 1.0
MAX_ANGLE_DEG = 100.0
#: Relative tolerance of the cross-checks: sums of the same angles, maybe in another order.
RTOL = 1e-12

#: Peers far slower than cyclomech get fewer rounds, so the timed run stays short.
SLOW_ROUNDS = 3

GROUP_SOLVE = f"solve: V={LARGE_EVENTS:.0e}, E={ARCS_PER_EVENT * LARGE_EVENTS:.0e}"
GROUP_BUILD = f"build: V={LARGE_EVENTS:.0e}, E={ARCS_PER_EVENT * LARGE_EVENTS:.0e}"
GROUP_BATCH = (
    f"batch: {BATCH_ROWS} weight vectors, V={BATCH_EVENTS:.0e}, "
    f"E={ARCS_PER_EVENT * BATCH_EVENTS:.0e}"
)
GROUP_CYCLOGRAM = f"cyclogram: V={CYCLOGRAM_EVENTS}, E={CYCLOGRAM_ARCS}"
#: Scaling rows: V events, E = 4 V arcs. networkx (~5 µs an arc) only up to this V.
SCALE_EVENTS = [1_000, 10_000, 100_000, 1_000_000]
SCALE_NETWORKX_MAX = 100_000


@dataclass(frozen=True)
class Dag:
    """A random DAG: arcs ``src[e] -> dst[e]`` with phase angles ``weights[e]`` [deg]."""

    n_events: int
    src: npt.NDArray[np.int64]
    dst: npt.NDArray[np.int64]
    weights: npt.NDArray[np.float64]

    @property
    def n_arcs(self) -> int:
        return int(self.src.size)

    def cyclomech_length(self) -> float:
        return float(
            cm.EventGraph(self.n_events, self.src, self.dst).longest_path(self.weights).max()
        )


def random_dag(n_events: int, n_arcs: int, seed: int) -> Dag:
    """``n_arcs`` distinct arcs, each from a lower to a higher rank of a random permutation.

    Arcs are distinct because ``networkx.DiGraph`` would merge parallel arcs and then
    solve a different problem from the other tools.
    """
    if n_arcs > n_events * (n_events - 1) // 2:
        raise ValueError(f"a DAG on {n_events} events has fewer than {n_arcs} distinct arcs")
    rng = np.random.default_rng(seed)
    event_of_rank = rng.permutation(n_events).astype(np.int64)
    lo = np.empty(0, dtype=np.int64)
    hi = np.empty(0, dtype=np.int64)
    while lo.size < n_arcs:
        a = rng.integers(0, n_events, size=2 * n_arcs + 16)
        b = rng.integers(0, n_events, size=a.size)
        keep = a != b
        lo = np.concatenate([lo, np.minimum(a, b)[keep]])
        hi = np.concatenate([hi, np.maximum(a, b)[keep]])
        # First occurrence of each (lo, hi) pair, in the order drawn.
        _, first = np.unique(lo * n_events + hi, return_index=True)
        first.sort()
        lo, hi = lo[first], hi[first]
    lo, hi = lo[:n_arcs], hi[:n_arcs]
    weights = rng.uniform(MIN_ANGLE_DEG, MAX_ANGLE_DEG, size=n_arcs)
    return Dag(n_events, event_of_rank[lo], event_of_rank[hi], weights)


def _label(benchmark, tool: str, what: str) -> None:
    """Name the tool and the call for the ratio table printed by conftest.py."""
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


def _edge_weight(_source: int, _target: int, weight: float) -> float:
    """rustworkx ``weight_fn`` for float payloads: called with (source, target, payload)."""
    return weight


def build_rustworkx(dag: Dag):
    """A PyDiGraph with every event and the angle as each arc's payload.

    Fastest of the ways tried at V=1e5: size hints plus ``extend_from_weighted_edge_list``
    fed by a ``zip`` of ``tolist()``s (49 ms) beat the same without hints (80 ms) and
    ``add_nodes_from(range(V))`` + ``add_edges_from(list(...))`` (93 ms).
    """
    g = rx.PyDiGraph(node_count_hint=dag.n_events, edge_count_hint=dag.n_arcs)
    g.add_nodes_from([None] * dag.n_events)  # events without arcs exist too
    g.extend_from_weighted_edge_list(
        zip(dag.src.tolist(), dag.dst.tolist(), dag.weights.tolist(), strict=True)
    )
    return g


def build_rustworkx_index(dag: Dag):
    """A PyDiGraph whose arc payloads are the arc indices (for a weight_fn that looks up)."""
    g = rx.PyDiGraph(node_count_hint=dag.n_events, edge_count_hint=dag.n_arcs)
    g.add_nodes_from([None] * dag.n_events)
    g.extend_from_weighted_edge_list(
        zip(dag.src.tolist(), dag.dst.tolist(), range(dag.n_arcs), strict=True)
    )
    return g


def build_networkx(dag: Dag):
    """A DiGraph with every event and the angle as each arc's ``weight`` attribute."""
    g = nx.DiGraph()
    g.add_nodes_from(range(dag.n_events))
    g.add_weighted_edges_from(
        zip(dag.src.tolist(), dag.dst.tolist(), dag.weights.tolist(), strict=True)
    )
    return g


# --- V = 1e5: solve on a prepared graph, one-shot, and build ----------------------


@pytest.fixture(scope="module")
def large() -> Dag:
    return random_dag(LARGE_EVENTS, ARCS_PER_EVENT * LARGE_EVENTS, seed=20261101)


@pytest.fixture(scope="module")
def large_rx(large: Dag):
    return build_rustworkx(large)


@pytest.fixture(scope="module")
def large_rx_length(large_rx) -> float:
    return float(rx.dag_weighted_longest_path_length(large_rx, _edge_weight))


#: V of networkx's solve and build rows when benchmarks are off: at V = 1e5 its graph
#: (built twice, ~2.5 CPU-s each) and its solve cost ~8 CPU-s of the default run, and
#: check nothing its V = 1e3 and 1e4 scaling rows do not (its code has no size
#: switch); timed, it runs the groups' V = 1e5 like every other tool.
SMOKE_NETWORKX_EVENTS = 10_000


@pytest.fixture(scope="module")
def nx_dag(request: pytest.FixtureRequest, large: Dag) -> Dag:
    """The DAG of networkx's solve and build rows: ``large`` when timed, else a
    V = :data:`SMOKE_NETWORKX_EVENTS` one."""
    if timed_run(request.config):
        return large
    n = SMOKE_NETWORKX_EVENTS
    return random_dag(n, ARCS_PER_EVENT * n, seed=20261101)


@pytest.fixture(scope="module")
def large_nx(nx_dag: Dag):
    return build_networkx(nx_dag)


@pytest.mark.benchmark(group=GROUP_SOLVE)
def test_solve_cyclomech(benchmark, large: Dag, large_rx_length: float) -> None:
    _label(benchmark, "cyclomech", "EventGraph.longest_path(w)")
    graph = cm.EventGraph(large.n_events, large.src, large.dst)
    t = benchmark(graph.longest_path, large.weights)
    assert_allclose(t.max(), large_rx_length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_SOLVE)
def test_solve_cyclomech_one_shot(benchmark, large: Dag, large_rx_length: float) -> None:
    _label(benchmark, "cyclomech", "longest_path(V, src, dst, w), one-shot")
    t = benchmark(cm.longest_path, large.n_events, large.src, large.dst, large.weights)
    assert_allclose(t.max(), large_rx_length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_SOLVE)
def test_solve_rustworkx(benchmark, large: Dag, large_rx) -> None:
    _label(benchmark, "rustworkx", "dag_weighted_longest_path_length(G, weight_fn)")
    length = benchmark(rx.dag_weighted_longest_path_length, large_rx, _edge_weight)
    assert_allclose(large.cyclomech_length(), length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_SOLVE, min_rounds=SLOW_ROUNDS)
def test_solve_networkx(benchmark, nx_dag: Dag, large_nx) -> None:
    _label(benchmark, "networkx", "dag_longest_path_length(G, weight='weight')")
    length = benchmark(nx.dag_longest_path_length, large_nx, weight="weight")
    assert_allclose(nx_dag.cyclomech_length(), length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_BUILD)
def test_build_cyclomech(benchmark, large: Dag, large_rx_length: float) -> None:
    _label(benchmark, "cyclomech", "EventGraph(V, src, dst)")
    graph = benchmark(cm.EventGraph, large.n_events, large.src, large.dst)
    assert_allclose(graph.longest_path(large.weights).max(), large_rx_length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_BUILD)
def test_build_rustworkx(benchmark, large: Dag) -> None:
    _label(benchmark, "rustworkx", "PyDiGraph from the arrays")
    graph = benchmark(build_rustworkx, large)
    length = rx.dag_weighted_longest_path_length(graph, _edge_weight)
    assert_allclose(large.cyclomech_length(), length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_BUILD, min_rounds=SLOW_ROUNDS)
def test_build_networkx(benchmark, nx_dag: Dag) -> None:
    _label(benchmark, "networkx", "DiGraph from the arrays")
    graph = benchmark(build_networkx, nx_dag)
    length = nx.dag_longest_path_length(graph, weight="weight")
    assert_allclose(nx_dag.cyclomech_length(), length, rtol=RTOL)


# --- 1000 weight vectors on one DAG with V = 1e3 ----------------------------------


@dataclass(frozen=True)
class Batch:
    dag: Dag
    weights: npt.NDArray[np.float64]  # (BATCH_ROWS, E) [deg]

    def cyclomech_lengths(self) -> npt.NDArray[np.float64]:
        graph = cm.EventGraph(self.dag.n_events, self.dag.src, self.dag.dst)
        return graph.longest_path(self.weights).max(axis=1)


@pytest.fixture(scope="module")
def batch() -> Batch:
    dag = random_dag(BATCH_EVENTS, ARCS_PER_EVENT * BATCH_EVENTS, seed=20261102)
    rng = np.random.default_rng(20261103)
    weights = rng.uniform(MIN_ANGLE_DEG, MAX_ANGLE_DEG, size=(BATCH_ROWS, dag.n_arcs))
    return Batch(dag, weights)


@pytest.mark.benchmark(group=GROUP_BATCH)
@pytest.mark.parametrize("n_threads", [None, 1], ids=["all-cores", "1-thread"])
def test_batch_cyclomech(benchmark, batch: Batch, n_threads: int | None) -> None:
    threads = "all cores" if n_threads is None else f"{n_threads} thread"
    _label(benchmark, "cyclomech", f"EventGraph.longest_path(W), {threads}")
    graph = cm.EventGraph(batch.dag.n_events, batch.dag.src, batch.dag.dst)
    t = benchmark(graph.longest_path, batch.weights, n_threads=n_threads)
    assert t.shape == (BATCH_ROWS, batch.dag.n_events)
    rows = [0, BATCH_ROWS // 2, BATCH_ROWS - 1]
    lengths = _rustworkx_loop(build_rustworkx_index(batch.dag), batch.weights[rows])
    assert_allclose(t[rows].max(axis=1), lengths, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_cyclomech_reused_out(benchmark, batch: Batch) -> None:
    """The same batch on one thread into a reused buffer (issue 20: no fresh pages)."""
    _label(benchmark, "cyclomech", "EventGraph.longest_path(W, out=reused), 1 thread")
    graph = cm.EventGraph(batch.dag.n_events, batch.dag.src, batch.dag.dst)
    buf = np.empty((BATCH_ROWS, batch.dag.n_events))
    t = benchmark(graph.longest_path, batch.weights, n_threads=1, out=buf)
    assert t is buf
    assert buf.tobytes() == graph.longest_path(batch.weights, n_threads=1).tobytes()


# The fastest rustworkx loop we found. The Python weight_fn call per arc (~0.1 µs, 4e3
# per vector) is most of its time. Tried and dropped (median of 3, 1000 vectors, quiet
# machine; this loop 0.43 s): the same with the row in a nonlocal instead of a closure
# (0.43 s, no gain), rebuilding the graph for every vector (0.55 s), float payloads
# overwritten with update_edge_by_index before each solve (0.63 s), and W.tolist() of
# the whole matrix up front (0.71 s: 4e6 float objects alive at once).


def _rustworkx_loop(graph, weights: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Longest-path length per row; ``graph`` from :func:`build_rustworkx_index`."""
    out = np.empty(weights.shape[0])
    solve = rx.dag_weighted_longest_path_length
    for i in range(weights.shape[0]):
        row = weights[i].tolist()
        out[i] = solve(graph, lambda s, t, e: row[e])  # noqa: B023 (called before row changes)
    return out


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_rustworkx(benchmark, batch: Batch) -> None:
    _label(benchmark, "rustworkx", "loop of solves: payload = arc index, weight_fn reads the row")
    graph = build_rustworkx_index(batch.dag)
    lengths = benchmark(_rustworkx_loop, graph, batch.weights)
    assert_allclose(batch.cyclomech_lengths(), lengths, rtol=RTOL)


# --- a cyclogram-sized network: 30 events --------------------------------------------


@pytest.fixture(scope="module")
def cyclogram() -> Dag:
    return random_dag(CYCLOGRAM_EVENTS, CYCLOGRAM_ARCS, seed=20261104)


@pytest.mark.benchmark(group=GROUP_CYCLOGRAM)
def test_cyclogram_cyclomech_one_shot(benchmark, cyclogram: Dag) -> None:
    _label(benchmark, "cyclomech", "longest_path(V, src, dst, w), one-shot")
    dag = cyclogram
    t = benchmark(cm.longest_path, dag.n_events, dag.src, dag.dst, dag.weights)
    length = rx.dag_weighted_longest_path_length(build_rustworkx(dag), _edge_weight)
    assert_allclose(t.max(), length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_CYCLOGRAM)
def test_cyclogram_cyclomech(benchmark, cyclogram: Dag) -> None:
    _label(benchmark, "cyclomech", "EventGraph.longest_path(w)")
    dag = cyclogram
    graph = cm.EventGraph(dag.n_events, dag.src, dag.dst)
    t = benchmark(graph.longest_path, dag.weights)
    length = rx.dag_weighted_longest_path_length(build_rustworkx(dag), _edge_weight)
    assert_allclose(t.max(), length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_CYCLOGRAM)
def test_cyclogram_rustworkx(benchmark, cyclogram: Dag) -> None:
    _label(benchmark, "rustworkx", "dag_weighted_longest_path_length(G, weight_fn)")
    graph = build_rustworkx(cyclogram)
    length = benchmark(rx.dag_weighted_longest_path_length, graph, _edge_weight)
    assert_allclose(cyclogram.cyclomech_length(), length, rtol=RTOL)


@pytest.mark.benchmark(group=GROUP_CYCLOGRAM)
def test_cyclogram_networkx(benchmark, cyclogram: Dag) -> None:
    _label(benchmark, "networkx", "dag_longest_path_length(G, weight='weight')")
    graph = build_networkx(cyclogram)
    length = benchmark(nx.dag_longest_path_length, graph, weight="weight")
    assert_allclose(cyclogram.cyclomech_length(), length, rtol=RTOL)


# --- scaling: V = 1e3 … 1e6, build and solve, time per arc (issue 20) ----------------


def _scale_group(what: str, n_events: int) -> str:
    return f"scale {what}: V={n_events:.0e}, E={ARCS_PER_EVENT * n_events:.0e}"


@pytest.fixture(scope="module", params=SCALE_EVENTS, ids=lambda v: f"V{v:.0e}")
def scaled(request) -> Dag:
    n = request.param
    return random_dag(n, ARCS_PER_EVENT * n, seed=20261120 + n)


def _scale_label(benchmark, dag: Dag, tool: str, what: str) -> None:
    _label(benchmark, tool, what)
    # Build and solve apart, so that the ratios compare like with like.
    benchmark.group = _scale_group(what.split(":")[0], dag.n_events)
    benchmark.extra_info["arcs"] = dag.n_arcs


def _slow(dag: Dag) -> dict[str, int]:
    """Few rounds for the peers at the largest sizes (seconds a call)."""
    return {"rounds": SLOW_ROUNDS, "iterations": 1} if dag.n_events >= 100_000 else {}


def test_scale_build_cyclomech(benchmark, scaled: Dag) -> None:
    _scale_label(benchmark, scaled, "cyclomech", "build: EventGraph(V, src, dst)")
    graph = benchmark(cm.EventGraph, scaled.n_events, scaled.src, scaled.dst)
    assert graph.n_arcs == scaled.n_arcs


def test_scale_solve_cyclomech(benchmark, scaled: Dag) -> None:
    _scale_label(benchmark, scaled, "cyclomech", "solve: EventGraph.longest_path(w)")
    graph = cm.EventGraph(scaled.n_events, scaled.src, scaled.dst)
    graph.longest_path(scaled.weights)  # a large graph's weight permutation is built once
    t = benchmark(graph.longest_path, scaled.weights)
    length = rx.dag_weighted_longest_path_length(build_rustworkx(scaled), _edge_weight)
    assert_allclose(t.max(), length, rtol=RTOL)


def test_scale_build_rustworkx(benchmark, scaled: Dag) -> None:
    _scale_label(benchmark, scaled, "rustworkx", "build: PyDiGraph from the arrays")
    if _slow(scaled):
        graph = benchmark.pedantic(build_rustworkx, args=(scaled,), **_slow(scaled))
    else:
        graph = benchmark(build_rustworkx, scaled)
    assert graph.num_edges() == scaled.n_arcs


def test_scale_solve_rustworkx(benchmark, scaled: Dag) -> None:
    _scale_label(benchmark, scaled, "rustworkx", "solve: dag_weighted_longest_path_length")
    graph = build_rustworkx(scaled)
    args = (graph, _edge_weight)
    if _slow(scaled):
        length = benchmark.pedantic(rx.dag_weighted_longest_path_length, args=args, **_slow(scaled))
    else:
        length = benchmark(rx.dag_weighted_longest_path_length, *args)
    assert_allclose(scaled.cyclomech_length(), length, rtol=RTOL)


def test_scale_solve_networkx(benchmark, scaled: Dag) -> None:
    if scaled.n_events > SCALE_NETWORKX_MAX:
        pytest.skip(f"networkx takes minutes above V = {SCALE_NETWORKX_MAX:.0e}")
    _scale_label(benchmark, scaled, "networkx", "solve: dag_longest_path_length")
    graph = build_networkx(scaled)
    length = benchmark.pedantic(
        nx.dag_longest_path_length,
        args=(graph,),
        kwargs={"weight": "weight"},
        rounds=SLOW_ROUNDS,
        iterations=1,
    )
    assert_allclose(scaled.cyclomech_length(), length, rtol=RTOL)


def check_earliest(dag: Dag, t: npt.NDArray[np.float64]) -> None:
    """Earliest times by their definition, with numpy alone: every arc's inequality
    holds, and an event with incoming arcs sits exactly on the largest
    t[src] + w of them (0 without)."""
    lhs = t[dag.src] + dag.weights
    best = np.full(dag.n_events, -np.inf)
    np.maximum.at(best, dag.dst, lhs)
    has_in = np.isfinite(best)
    assert np.array_equal(t[has_in], best[has_in])
    assert np.all(t[~has_in] == 0.0)


def floor_ratio_table(sizes: tuple[int, ...] = (10**5, 10**6), rounds: int = 15) -> None:
    """Issue 37's measurement of the prepared solve, ``EventGraph.longest_path(w)``
    with E = 4V, against the random-access floor every longest path pays (as
    ``bench_scaling.py``'s ``lp_floor``): numpy's gather ``t[i]`` of E random
    indices from V times and scatter ``out[i] = w`` of E values into V slots. One
    thread (run under ``taskset -c 1``), interleaved rounds, both page states; the
    solve returns a new array and works in scratch of its own (``out=`` is for
    batches), so its peer is the floor into new arrays; the floor into existing
    ones is printed too. Checked first against the definition
    (:func:`check_earliest`)."""
    for v in sizes:
        dag = random_dag(v, 4 * v, seed=20261126)
        g = cm.EventGraph(dag.n_events, dag.src, dag.dst)
        w = dag.weights
        check_earliest(dag, g.longest_path(w, n_threads=1))
        rng = np.random.default_rng(20261126)
        idx = rng.integers(0, v, 4 * v)
        times = rng.uniform(0.0, 360.0, v)
        fw = rng.uniform(MIN_ANGLE_DEG, MAX_ANGLE_DEG, 4 * v)
        got, slots = np.empty(4 * v), np.empty(v)

        def floor_new(idx=idx, times=times, fw=fw, v=v) -> None:
            np.take(times, idx)
            np.empty(v)[idx] = fw

        def floor_existing(idx=idx, times=times, fw=fw, got=got, slots=slots) -> None:
            np.take(times, idx, out=got)
            slots[idx] = fw

        tools = {
            "longest_path(w), new array": lambda g=g, w=w: g.longest_path(w, n_threads=1),
            "floor gather + scatter, new arrays": floor_new,
            "floor gather + scatter, existing": floor_existing,
        }
        print_states(
            f"prepared longest path, V = {v:.0e}, E = {4 * v:.0e}, one thread",
            page_states(tools, rounds),
            4 * v * 1e-9,
            "ns/arc",
            {
                "floor gather + scatter, new arrays": "longest_path(w), new array",
                "floor gather + scatter, existing": "longest_path(w), new array",
            },
        )


def test_floor_ratio_table(request: pytest.FixtureRequest) -> None:
    """The issue-37 table in timed runs (``taskset -c 1 python
    benches/bench_schedule.py floor``)."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    floor_ratio_table((10**5,), 7)


def per_arc_table(path: str) -> str:
    """The scaling rows of a ``--benchmark-json`` file as ns per arc (median)."""
    with open(path, encoding="utf-8") as f:
        benches = json.load(f)["benchmarks"]
    rows: dict[str, dict[int, float]] = {}
    for b in benches:
        info = b.get("extra_info", {})
        if "arcs" not in info:
            continue
        what = f"{info['tool']}: {info['what']}"
        rows.setdefault(what, {})[info["arcs"]] = b["stats"]["median"] / info["arcs"] * 1e9
    sizes = sorted({e for r in rows.values() for e in r})
    lines = ["| ns per arc | " + " | ".join(f"E = {e:.0e}" for e in sizes) + " |"]
    lines.append("|---" * (len(sizes) + 1) + "|")
    for what, r in rows.items():
        cells = [f"{r[e]:.3g}" if e in r else "—" for e in sizes]
        lines.append(f"| {what} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    if sys.argv[1:2] == ["floor"]:
        floor_ratio_table()
    else:
        print(per_arc_table(sys.argv[1]))
