"""Longest path at scale (issue 20): from 2^20 arcs ``EventGraph`` groups the arcs
in radix passes and keeps the weights' partition from its build. Around that
threshold (one arc below, at it, one above; V not a multiple of the partition's
blocks) the times are checked against numpy alone — each event's time is 0
without incoming arcs, else the largest ``t[src] + w`` over them, exactly — and
against the one-shot kernel (another algorithm), bit for bit."""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest

THRESHOLD = 1 << 20


def big_dag(n: int, m: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """m arcs from a lower to a higher rank of a random permutation of n events
    (parallel arcs allowed), integer-and-half weights with ties, signed zeros."""
    rng = np.random.default_rng(seed)
    rank = rng.permutation(n)
    a, b = rng.integers(0, n, m), rng.integers(0, n - 1, m)
    b = np.where(b >= a, b + 1, b)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    w = rng.integers(-6, 20, m) * 0.5
    w[::97] = -0.0
    return rank[lo], rank[hi], w


def assert_is_the_longest_path(n, src, dst, w, t) -> None:
    cand = t[src] + w
    best = np.full(n, -np.inf)
    np.maximum.at(best, dst, cand)
    has_in = np.isfinite(best)
    np.testing.assert_array_equal(t[has_in], best[has_in])
    assert np.all(t[~has_in] == 0.0)


@pytest.mark.parametrize("m", [THRESHOLD - 1, THRESHOLD, THRESHOLD + 1])
def test_times_around_the_radix_threshold(m: int) -> None:
    n = 250_007  # not a multiple of any power of two
    src, dst, w = big_dag(n, m, seed=m)
    g = cm.EventGraph(n, src, dst)
    t = g.longest_path(w)
    assert_is_the_longest_path(n, src, dst, w, t)
    assert t.tobytes() == cm.longest_path(n, src, dst, w).tobytes()
    # A second solve (the partition reused) and a copy of the graph agree.
    assert g.longest_path(w).tobytes() == t.tobytes()
    w2 = w[::-1].copy()
    assert_is_the_longest_path(n, src, dst, w2, g.longest_path(w2))
    # Latest times: every event at or before the horizon, each arc kept, and
    # each event with outgoing arcs tight on one of them (or on the horizon).
    a = g.analyze(w)
    late = a.latest
    assert np.all(late[dst] - w >= late[src])
    bound = np.full(n, a.horizon)
    np.minimum.at(bound, src, late[dst] - w)
    np.testing.assert_array_equal(late, bound)
    np.testing.assert_array_equal(a.earliest, t)
