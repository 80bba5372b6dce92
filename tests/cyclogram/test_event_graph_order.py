"""EventGraph's positional layout (issue 20): events renumbered by topological
position inside, arcs stored by position, built in linear time. Every public
result must be unchanged, so the earliest and latest times, the slack and the
critical arcs are checked against references that share nothing with the kernel
(networkx's topological sort with a dynamic program in Python, rustworkx's
longest path) on random DAGs with parallel arcs, isolated events and ties; and a
cycle is still refused with the same error."""

from __future__ import annotations

import pickle

import cyclomech as cm
import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

rx = pytest.importorskip("rustworkx")


@st.composite
def tied_dags(draw, max_events: int = 40):
    """(V, src, dst, w): arcs from a lower to a higher rank of a random permutation,
    some repeated (parallel arcs, equal or different weights), events of the
    upper ranks often isolated, small integer weights so that paths tie."""
    n = draw(st.integers(1, max_events))
    perm = np.array(draw(st.permutations(range(n))), dtype=np.int64)
    top = draw(st.integers(1, n))  # arcs only among the first `top` ranks
    pairs = draw(
        st.lists(st.tuples(st.integers(0, top - 1), st.integers(0, top - 1)), max_size=120)
    )
    pairs = [(min(a, b), max(a, b)) for a, b in pairs if a != b]
    copies = draw(st.lists(st.integers(1, 3), min_size=len(pairs), max_size=len(pairs)))
    lo = np.array([p[0] for p, c in zip(pairs, copies, strict=True) for _ in range(c)], np.int64)
    hi = np.array([p[1] for p, c in zip(pairs, copies, strict=True) for _ in range(c)], np.int64)
    w = np.array(draw(st.lists(st.integers(-3, 8), min_size=lo.size, max_size=lo.size)), float)
    return n, perm[lo], perm[hi], w


def reference_times(n, src, dst, w, horizon=None):
    """Earliest and latest times by a dynamic program over networkx's order."""
    g = nx.MultiDiGraph()
    g.add_nodes_from(range(n))
    g.add_edges_from((int(a), int(b), {"w": float(x)}) for a, b, x in zip(src, dst, w, strict=True))
    order = list(nx.topological_sort(g))
    early = {}
    for v in order:
        cands = [early[u] + d["w"] for u, _, d in g.in_edges(v, data=True)]
        early[v] = max(cands) if cands else 0.0
    e = np.array([early[v] for v in range(n)])
    h = max(0.0, e.max()) if horizon is None else horizon
    late = {}
    for v in reversed(order):
        late[v] = min([h] + [late[b] - d["w"] for _, b, d in g.out_edges(v, data=True)])
    return e, np.array([late[v] for v in range(n)]), h


@settings(max_examples=150, deadline=None)
@given(dag=tied_dags(), horizon=st.one_of(st.none(), st.integers(-5, 60)))
def test_times_slack_and_critical_arcs_match_an_independent_program(dag, horizon):
    n, src, dst, w = dag
    g = cm.EventGraph(n, src, dst)
    h = None if horizon is None else float(horizon)
    early, late, h_ref = reference_times(n, src, dst, w, h)
    # Integer weights: every sum is exact, so the times must be equal exactly.
    np.testing.assert_array_equal(g.longest_path(w), early)
    np.testing.assert_array_equal(cm.longest_path(n, src, dst, w), early)
    a = g.analyze(w, horizon=h)
    assert a.horizon == h_ref
    np.testing.assert_array_equal(a.earliest, early)
    np.testing.assert_array_equal(a.latest, late)
    np.testing.assert_array_equal(g.latest(w, h_ref), late)
    total = late[dst] - early[src] - w
    np.testing.assert_array_equal(a.total_slack, total)
    np.testing.assert_array_equal(a.free_slack, early[dst] - early[src] - w)
    # Ties: every arc of zero slack is critical, parallel copies included.
    np.testing.assert_array_equal(a.critical, total == 0.0)
    # The order reported is a topological order of the input's events.
    order = g.topological_order
    assert sorted(order.tolist()) == list(range(n))
    pos = np.empty(n, np.int64)
    pos[order] = np.arange(n)
    assert np.all(pos[src] < pos[dst])


@settings(max_examples=60, deadline=None)
@given(dag=tied_dags(), rows=st.integers(1, 20), threads=st.sampled_from([1, 2]))
def test_batch_rows_are_the_single_row_times_and_rustworkx_lengths(dag, rows, threads):
    n, src, dst, w = dag
    g = cm.EventGraph(n, src, dst)
    rng = np.random.default_rng(n + rows)
    # Positive weights: rustworkx's longest path is defined for those.
    W = rng.integers(1, 6, size=(rows, w.size)).astype(float)
    batch = g.longest_path(W, n_threads=threads)
    for r in range(rows):
        assert batch[r].tobytes() == g.longest_path(W[r]).tobytes()
    if w.size:
        rg = rx.PyDiGraph()
        rg.add_nodes_from(range(n))
        rg.add_edges_from(list(zip(src.tolist(), dst.tolist(), range(w.size), strict=True)))
        for r in range(rows):
            row = W[r].tolist()
            length = rx.dag_weighted_longest_path_length(rg, lambda _s, _t, e: row[e])  # noqa: B023
            assert batch[r].max() == length


@settings(max_examples=60, deadline=None)
@given(dag=tied_dags(max_events=20), cycle=st.lists(st.integers(0, 19), min_size=1, max_size=5))
def test_a_cycle_is_refused_naming_a_cycle(dag, cycle):
    n, src, dst, _ = dag
    cyc = [c % n for c in cycle]
    src = np.concatenate([src, cyc])
    dst = np.concatenate([dst, cyc[1:] + cyc[:1]])
    with pytest.raises(cm.CycleError, match="contain a cycle") as info:
        cm.EventGraph(n, src, dst)
    events = info.value.events
    arcs = set(zip(src.tolist(), dst.tolist(), strict=True))
    assert all((a, b) in arcs for a, b in zip(events, events[1:] + events[:1], strict=True))
    with pytest.raises(cm.CycleError) as again:
        cm.longest_path(n, src, dst, np.ones(src.size))
    assert again.value.events == events


def test_a_large_random_dag_matches_networkx_and_pickles():
    """V = 20 000, E = 80 000, arcs in random order with parallel copies."""
    rng = np.random.default_rng(20)
    n, m = 20_000, 80_000
    rank = rng.permutation(n)
    a, b = rng.integers(0, n, m), rng.integers(0, n, m)
    keep = a != b
    lo, hi = np.minimum(a, b)[keep], np.maximum(a, b)[keep]
    lo, hi = np.concatenate([lo, lo[:500]]), np.concatenate([hi, hi[:500]])
    src, dst = rank[lo], rank[hi]
    w = rng.integers(-5, 50, src.size).astype(float)
    g = cm.EventGraph(n, src, dst)
    early, late, _ = reference_times(n, src, dst, w)
    np.testing.assert_array_equal(g.longest_path(w), early)
    np.testing.assert_array_equal(g.analyze(w).latest, late)
    g2 = pickle.loads(pickle.dumps(g))
    np.testing.assert_array_equal(g2.topological_order, g.topological_order)
    assert g2.longest_path(w).tobytes() == g.longest_path(w).tobytes()
