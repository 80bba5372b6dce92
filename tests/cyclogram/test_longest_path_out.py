"""EventGraph.longest_path(out=): a batch's earliest times written into the
caller's buffer (issue 20, no fresh-page tax), bit for bit those without it; a
buffer the kernel cannot fill is a clear error, through the library and _core."""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st


def dag(seed: int, v: int = 60, e: int = 240) -> tuple[cm.EventGraph, np.ndarray]:
    rng = np.random.default_rng(seed)
    a, b = rng.integers(0, v, e), rng.integers(0, v, e)
    src, dst = np.minimum(a, b), np.maximum(a, b)
    keep = src != dst
    return cm.EventGraph(v, src[keep], dst[keep]), rng


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), rows=st.integers(0, 40), threads=st.sampled_from([1, 2]))
def test_out_is_bit_for_bit_the_fresh_result(seed, rows, threads):
    g, rng = dag(seed)
    w = rng.normal(10.0, 30.0, (rows, g.n_arcs))
    fresh = g.longest_path(w, n_threads=threads)
    buf = np.full((rows, g.n_events), np.nan)
    got = g.longest_path(w, n_threads=threads, out=buf)
    assert got is buf
    assert fresh.tobytes() == buf.tobytes()
    # Reused: only the latest call's times remain.
    g.longest_path(w[::-1].copy(), n_threads=threads, out=buf)
    assert buf.tobytes() == g.longest_path(w[::-1].copy()).tobytes()


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda w, v: np.zeros((w.shape[0], v + 1)), "shape \\(5, 6\\)"),
        (lambda w, v: np.zeros((w.shape[0], v), dtype=np.float32), "float32"),
        (lambda w, v: np.zeros((v, w.shape[0])).T, "C-contiguous"),
        (lambda w, v: np.zeros((w.shape[0], v)).copy().view(np.ndarray), None),
        (lambda w, v: [[0.0] * v] * w.shape[0], "list"),
    ],
)
def test_a_bad_out_is_named(make, match):
    g = cm.EventGraph(6, [0, 1, 2, 3, 4], [1, 2, 3, 4, 5])
    w = np.ones((5, 5))
    out = make(w, 6)
    if match is None:  # a plain ndarray view is fine
        assert g.longest_path(w, out=out) is out
        return
    with pytest.raises(cm.CyclomechError, match=match) as e:
        g.longest_path(w, out=out)
    assert isinstance(e.value, ValueError) and "out must be" in str(e.value)


def test_read_only_overlapping_and_single_vector_outs_are_refused():
    g = cm.EventGraph(3, [0, 1], [1, 2])
    w = np.ones((4, 2))
    ro = np.zeros((4, 3))
    ro.flags.writeable = False
    with pytest.raises(cm.CyclomechError, match="read-only"):
        g.longest_path(w, out=ro)
    mem = np.ones(12)
    with pytest.raises(cm.CyclomechError, match="shares memory"):
        g.longest_path(mem[:8].reshape(4, 2), out=mem.reshape(4, 3))
    with pytest.raises(cm.CyclomechError, match="batch"):
        g.longest_path(np.ones(2), out=np.zeros((1, 3)))


def test_core_refuses_a_bad_out_with_an_input_error():
    g = cm.EventGraph(3, [0, 1], [1, 2])
    w = np.ones((2, 2))
    for bad in (np.zeros((2, 4)), np.zeros((2, 3), dtype=np.float32), "x"):
        with pytest.raises(cm.CyclomechError, match="out must be"):
            g._g.longest_path(w, out=bad)
