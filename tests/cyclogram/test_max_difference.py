"""Tests of ``cyclomech.cyclogram.max_difference``: difference constraints by shortest paths.

Every expected value comes from scipy's LP solver (``scipy.optimize.linprog``, HiGHS)
applied to the linear program itself -- maximise ``x[t] - x[s]`` subject to
``x[dst[e]] - x[src[e]] <= w[e]``, ``x`` free -- or from numbers worked out by hand,
never from cyclomech. The only cyclomech-to-cyclomech comparisons are the ones the
API promises: a batch row equals the single call on that row, bit for bit, whatever
the thread count.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cyclogram import max_difference
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from scipy.optimize import linprog

NAN, INF = float("nan"), float("inf")

# ---------------------------------------------------------------------------
# Independent reference: the LP
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class System:
    """``n`` nodes, constraints ``x[dst[e]] - x[src[e]] <= w[e]``, objective ``x[t] - x[s]``."""

    n: int
    src: np.ndarray
    dst: np.ndarray
    w: np.ndarray
    s: int
    t: int

    @property
    def scale(self) -> float:
        """Magnitude of the largest sum of weights along a path."""
        return 1.0 + self.n * float(np.abs(self.w).max(initial=0.0))


def lp_optimum(n: int, src: np.ndarray, dst: np.ndarray, w: np.ndarray, s: int, t: int) -> float:
    """max x[t] - x[s] by linprog: nan if infeasible, inf if unbounded."""
    m = len(src)
    a_ub = b_ub = None
    if m:
        a_ub = np.zeros((m, n))
        a_ub[np.arange(m), dst] += 1.0
        a_ub[np.arange(m), src] -= 1.0  # a self-loop's row cancels to 0 <= w
        b_ub = np.asarray(w, dtype=np.float64)
    free = [(None, None)] * n
    # Feasibility first: with an objective, HiGHS may answer "infeasible or unbounded".
    feasible = linprog(np.zeros(n), A_ub=a_ub, b_ub=b_ub, bounds=free, method="highs")
    if feasible.status == 2:
        return NAN
    assert feasible.status == 0, feasible.message
    c = np.zeros(n)
    c[t] -= 1.0
    c[s] += 1.0  # minimise x[s] - x[t]
    res = linprog(c, A_ub=a_ub, b_ub=b_ub, bounds=free, method="highs")
    if res.status in (3, 4):  # the system is feasible, so this is unboundedness
        return INF
    assert res.status == 0, res.message
    return float(-res.fun)


def walk_marked(sys: System, on_path: np.ndarray) -> float:
    """Follow the marked arcs from ``s``: they must form one simple path to ``t`` and
    all be used. Returns the path's weight summed from ``s``."""
    left = [int(e) for e in np.flatnonzero(on_path)]
    v, total, seen = sys.s, 0.0, [sys.s]
    while True:
        nxt = [e for e in left if sys.src[e] == v]
        if not nxt:
            break
        assert len(nxt) == 1, f"marked arcs {nxt} all leave node {v}"
        e = nxt[0]
        left.remove(e)
        total += float(sys.w[e])
        v = int(sys.dst[e])
        assert v not in seen, f"the marked arcs revisit node {v}"
        seen.append(v)
    assert not left, f"marked arcs {left} are off the path from {sys.s}"
    assert v == sys.t, f"the marked path ends at {v}, not at the target {sys.t}"
    return total


def check_against_lp(sys: System, value: float, on_path: np.ndarray) -> None:
    want = lp_optimum(sys.n, sys.src, sys.dst, sys.w, sys.s, sys.t)
    assert on_path.shape == (len(sys.src),)
    assert on_path.dtype == np.bool_
    if math.isnan(want):
        assert math.isnan(value), f"{value} for an infeasible system"
        assert not on_path.any()
    elif want == INF:
        assert value == INF
        assert not on_path.any()
    else:
        assert abs(value - want) <= 1e-9 * sys.scale, (value, want)
        assert walk_marked(sys, on_path) == value  # summed the same way: exact
        if sys.s == sys.t:
            assert value == 0.0
            assert not on_path.any()


# ---------------------------------------------------------------------------
# Random systems
# ---------------------------------------------------------------------------

# Integers times a scale: zero-weight cycles are exactly (or up to round-off) zero and
# negative ones clearly negative, so the LP's feasibility tolerance and the kernel's
# never disagree. 0.1 and 360/7 make the sums inexact.
SCALES = [1.0, 0.25, 0.1, 360.0 / 7.0, 1000.0]


@st.composite
def systems(draw: st.DrawFn) -> System:
    """5-12 nodes, up to 3 arcs per node (self-loops and parallel arcs included),
    weights in [-10, 30] times a scale."""
    n = draw(st.integers(5, 12))
    node = st.integers(0, n - 1)
    arcs = draw(st.lists(st.tuples(node, node), max_size=3 * n))
    ints = draw(st.lists(st.integers(-10, 30), min_size=len(arcs), max_size=len(arcs)))
    scale = draw(st.sampled_from(SCALES))
    return System(
        n,
        np.array([a for a, _ in arcs], dtype=np.int64),
        np.array([b for _, b in arcs], dtype=np.int64),
        np.array(ints, dtype=np.float64) * scale,
        draw(node),
        draw(node),
    )


@settings(max_examples=200, deadline=None)
@given(sys=systems())
def test_matches_linprog(sys: System) -> None:
    value, on_path = max_difference(sys.n, sys.src, sys.dst, sys.w, sys.s, sys.t)
    assert type(value) is float
    check_against_lp(sys, value, on_path)


def shifted_rows(sys: System, rows: int) -> np.ndarray:
    """Row r lowers every weight by r - 2 units of the typical magnitude: later rows
    gain negative cycles, earlier ones lose them."""
    unit = max(1.0, float(np.abs(sys.w).max(initial=0.0))) / 4
    return sys.w[np.newaxis, :] - unit * (np.arange(rows)[:, np.newaxis] - 2.0)


def bits(a: Any) -> np.ndarray:
    return np.asarray(a, dtype=np.float64).view(np.uint64)


@settings(max_examples=60, deadline=None)
@given(sys=systems(), rows=st.integers(0, 12), n_threads=st.sampled_from([1, 2, None]))
def test_batch_rows_equal_single_calls(sys: System, rows: int, n_threads: int | None) -> None:
    w = shifted_rows(sys, rows)
    values, on_path = max_difference(sys.n, sys.src, sys.dst, w, sys.s, sys.t, n_threads=n_threads)
    assert values.shape == (rows,) and values.dtype == np.float64
    assert on_path.shape == (rows, len(sys.src)) and on_path.dtype == np.bool_
    singles = [max_difference(sys.n, sys.src, sys.dst, w[r], sys.s, sys.t) for r in range(rows)]
    assert_array_equal(bits(values), bits([v for v, _ in singles]))
    for r, (_, marks) in enumerate(singles):
        assert_array_equal(on_path[r], marks)


@settings(max_examples=25, deadline=None)
@given(sys=systems())
def test_batch_rows_match_linprog(sys: System) -> None:
    w = shifted_rows(sys, 6)
    values, on_path = max_difference(sys.n, sys.src, sys.dst, w, sys.s, sys.t)
    for r in range(6):
        row = System(sys.n, sys.src, sys.dst, w[r], sys.s, sys.t)
        check_against_lp(row, float(values[r]), on_path[r])


def big_batch(seed: int) -> tuple[System, np.ndarray]:
    """400 rows x 36 arcs on 12 nodes: past the threshold of the threaded path."""
    rng = np.random.default_rng(seed)
    n, m, rows = 12, 36, 400
    src, dst = rng.integers(0, n, size=(2, m))
    w = rng.integers(-10, 40, size=(rows, m)) * 0.5
    return System(n, src, dst, w[0], 0, 5), w


@pytest.mark.parametrize("seed", [0, 1])
def test_one_and_two_threads_agree_bit_for_bit(seed: int) -> None:
    sys, w = big_batch(seed)
    one = max_difference(sys.n, sys.src, sys.dst, w, sys.s, sys.t, n_threads=1)
    two = max_difference(sys.n, sys.src, sys.dst, w, sys.s, sys.t, n_threads=2)
    assert_array_equal(bits(one[0]), bits(two[0]))
    assert_array_equal(one[1], two[1])
    # The batch mixes optima and infeasible rows; spot-check both against the LP.
    assert np.isnan(one[0]).any() and np.isfinite(one[0]).any()
    for r in range(0, 400, 23):
        row = System(sys.n, sys.src, sys.dst, w[r], sys.s, sys.t)
        check_against_lp(row, float(one[0][r]), one[1][r])


# ---------------------------------------------------------------------------
# By hand
# ---------------------------------------------------------------------------

# x1 - x0 <= 4, x2 - x1 <= -1, x2 - x0 <= 5: max x2 - x0 = 3 via 0 -> 1 -> 2.
S3, D3, W3 = [0, 1, 0], [1, 2, 2], [4.0, -1.0, 5.0]

BY_HAND: dict[str, tuple[tuple[Any, ...], float, list[bool]]] = {
    "shortest of two paths": ((3, S3, D3, W3, 0, 2), 3.0, [True, True, False]),
    "direct arc shorter": ((3, S3, D3, [4.0, 2.0, 5.0], 0, 2), 5.0, [False, False, True]),
    "source is target": ((3, S3, D3, W3, 1, 1), 0.0, [False] * 3),
    "unreachable target": ((3, S3, D3, W3, 2, 0), INF, [False] * 3),
    "no arcs, one node": ((1, [], [], [], 0, 0), 0.0, []),
    "no arcs, two nodes": ((2, [], [], [], 0, 1), INF, []),
    "negative cycle": ((3, [0, 1, 2], [1, 2, 0], [1.0, 1.0, -2.5], 0, 2), NAN, [False] * 3),
    # Nothing reachable from node 0 is on the negative cycle 2 <-> 3: still infeasible.
    "negative cycle elsewhere": (
        (4, [0, 2, 3], [1, 3, 2], [1.0, 2.0, -3.0], 0, 1),
        NAN,
        [False] * 3,
    ),
    "negative cycle elsewhere, source is target": (
        (4, [0, 2, 3], [1, 3, 2], [1.0, 2.0, -3.0], 1, 1),
        NAN,
        [False] * 3,
    ),
    "negative self-loop": ((2, [0, 1], [1, 1], [1.0, -0.5], 0, 1), NAN, [False] * 2),
    "zero cycle": ((4, [0, 2, 3], [1, 3, 2], [1.0, 2.0, -2.0], 0, 1), 1.0, [True, False, False]),
    "parallel arcs": (
        (2, [0, 0, 0], [1, 1, 1], [3.0, -2.0, -2.0], 0, 1),
        -2.0,
        [False, True, False],
    ),
}


@pytest.mark.parametrize(("args", "value", "marks"), BY_HAND.values(), ids=BY_HAND)
def test_by_hand(args: tuple[Any, ...], value: float, marks: list[bool]) -> None:
    got, on_path = max_difference(*args)
    assert type(got) is float
    assert_array_equal(got, value)  # nan == nan here
    assert_array_equal(on_path, np.array(marks, dtype=bool))
    n, src, dst, w, s, t = args
    assert_array_equal(lp_optimum(n, np.array(src, int), np.array(dst, int), w, s, t), value)


def test_tight_cycle_is_feasible() -> None:
    # A cyclogram cycle that closes exactly: 120 + 240 - 360 degrees, up to round-off.
    for slack in (-1e-13, 1e-13, 0.0):
        w = np.array([120.0, 240.0, -360.0 + slack])
        assert -2e-13 < w.sum() < 2e-13
        value, on_path = max_difference(3, [0, 1, 2], [1, 2, 0], w, 0, 2)
        assert value == 360.0
        assert on_path.tolist() == [True, True, False]
        value, on_path = max_difference(3, [0, 1, 2], [1, 2, 0], w, 2, 1)
        assert value == w[2] + w[0]
        assert on_path.tolist() == [True, False, True]
    # Decimal angles whose float sum is negative: still feasible.
    w = np.array([0.3, -0.1, -0.2])
    assert w[0] + w[1] + w[2] < 0.0
    assert max_difference(3, [0, 1, 2], [1, 2, 0], w, 0, 1)[0] == 0.3
    # A genuinely negative cycle, far beyond the tolerance, is not.
    w = np.array([120.0, 240.0, -360.0 - 1e-6])
    assert math.isnan(max_difference(3, [0, 1, 2], [1, 2, 0], w, 0, 2)[0])


def test_tight_cycle_in_a_batch() -> None:
    w = np.array([[120.0, 240.0, -360.0 - 1e-13], [120.0, 240.0, -360.0 - 1e-3]])
    values, on_path = max_difference(3, [0, 1, 2], [1, 2, 0], w, 0, 2, n_threads=2)
    assert values[0] == 360.0 and math.isnan(values[1])
    assert on_path.tolist() == [[True, True, False], [False, False, False]]


def test_cyclogram_lp() -> None:
    # Events at angles x: 1 starts >= 30 deg after 0, 2 >= 50 after 1, 2 within 100 of 0,
    # and the cycle closes: 0 of the next cycle (x0 + 360) >= 200 after 2.
    # Latest event 2 relative to event 0: min(100, 360 - 200) = 100.
    src = [1, 2, 0, 0]  # x[b] - x[a] >= d  is  x[a] - x[b] <= -d: arc b -> a
    dst = [0, 1, 2, 2]
    w = [-30.0, -50.0, 100.0, 160.0]
    value, on_path = max_difference(3, src, dst, w, 0, 2)
    assert value == 100.0
    assert on_path.tolist() == [False, False, True, False]
    # Earliest event 2: max x0 - x2 = -(30 + 50).
    assert max_difference(3, src, dst, w, 2, 0)[0] == -80.0


# ---------------------------------------------------------------------------
# Shapes, types and sizes
# ---------------------------------------------------------------------------


def test_result_types() -> None:
    value, on_path = max_difference(3, S3, D3, W3, 0, 2)
    assert type(value) is float and on_path.shape == (3,) and on_path.dtype == np.bool_
    values, on_path = max_difference(3, S3, D3, [W3], 0, 2)
    assert values.shape == (1,) and values.dtype == np.float64
    assert on_path.shape == (1, 3) and on_path.dtype == np.bool_
    values, on_path = max_difference(3, S3, D3, np.zeros((0, 3)), 0, 2)
    assert values.shape == (0,) and on_path.shape == (0, 3)
    values, on_path = max_difference(2, [], [], np.zeros((4, 0)), 0, 1, n_threads=2)
    assert_array_equal(values, [INF] * 4)
    assert on_path.shape == (4, 0)


INPUT_TYPES: dict[str, tuple[Any, Any, Any, Any, Any]] = {
    "lists": (S3, D3, W3, 0, 2),
    "int32 indices": (np.int32(S3), np.array(D3, np.uint8), W3, np.int64(0), np.int32(2)),
    "int weights": (S3, D3, [4, -1, 5], 0, 2),
    "float32 weights": (S3, D3, np.float32(W3), 0, 2),
    "strided": (np.repeat(S3, 2)[::2], np.repeat(D3, 2)[::2], np.repeat(W3, 2)[::2], 0, 2),
    "fortran batch": (S3, D3, np.asfortranarray([W3, W3]), 0, 2),
}


@pytest.mark.parametrize("args", INPUT_TYPES.values(), ids=INPUT_TYPES)
def test_input_types_are_accepted(args: tuple[Any, ...]) -> None:
    value, on_path = max_difference(3, *args)
    assert_array_equal(value, 3.0 if np.ndim(args[2]) == 1 else [3.0, 3.0])
    assert_array_equal(on_path[..., 0], True)


# ---------------------------------------------------------------------------
# Bad input: cyclomech.InputError (a ValueError) naming the field and the value
# ---------------------------------------------------------------------------


def batch_with(position: tuple[int, int], value: float, rows: int = 3) -> np.ndarray:
    w = np.ones((rows, 3))
    w[position] = value
    return w


def call(n: Any = 3, src: Any = S3, dst: Any = D3, w: Any = W3, s: Any = 0, t: Any = 2, **kw: Any):
    return lambda: max_difference(n, src, dst, w, s, t, **kw)


BAD_INPUTS: dict[str, tuple[Callable[[], Any], list[str]]] = {
    "n_nodes 0": (call(n=0, src=[], dst=[], w=[], s=0, t=0), ["n_nodes = 0", "between 1"]),
    "n_nodes negative": (call(n=-2), ["n_nodes = -2"]),
    "n_nodes float": (call(n=3.0), ["n_nodes", "3.0"]),
    "n_nodes bool": (call(n=True), ["n_nodes", "True"]),
    "n_nodes 2**40": (call(n=2**40), ["n_nodes = 1099511627776"]),
    "n_nodes 2**70": (call(n=2**70), ["n_nodes", str(2**70)]),
    "src out of range": (call(src=[0, 7, 0]), ["src[1] = 7", "n_nodes = 3"]),
    "dst negative": (call(dst=[-1, 2, 2]), ["dst[0] = -1", "not a node index"]),
    "dst 2**62": (call(dst=[1, 2, 2**62]), [f"dst[2] = {2**62}"]),
    "source out of range": (call(s=3), ["source = 3", "0 to 2", "n_nodes = 3"]),
    "target negative": (call(t=-1), ["target = -1", "not a node index"]),
    "source float": (call(s=1.5), ["source", "1.5"]),
    "target string": (call(t="2"), ["target", "'2'"]),
    "target 2**70": (call(t=2**70), ["target", str(2**70)]),
    "nan weight": (call(w=[4.0, NAN, 5.0]), ["weights[1] = NaN"]),
    "inf weight": (call(w=[INF, 1.0, 1.0]), ["weights[0] = inf"]),
    "huge weight": (call(w=[1e300, 1.0, 1.0]), ["weights[0] = 1e300", "1e12"]),
    "inf in batch": (call(w=batch_with((2, 1), INF)), ["weights[2, 1] = inf"]),
    "nan in batch": (call(w=batch_with((1, 2), NAN)), ["weights[1, 2] = NaN"]),
    "-inf in a batch of one row": (call(w=batch_with((0, 0), -INF, 1)), ["weights[0, 0] = -inf"]),
    "src and dst lengths": (call(dst=[1, 2]), ["src and dst", "3 and 2"]),
    "weights too short": (call(w=[1.0, 2.0]), ["weights", "3 entries", "got 2"]),
    "weights too long": (call(w=[1.0] * 4), ["weights", "3 entries", "got 4"]),
    "batch rows too long": (call(w=np.ones((2, 4))), ["weights", "got 4"]),
    "empty batch, wrong rows": (call(w=np.ones((0, 5))), ["weights", "got 5"]),
    "3-D weights": (call(w=np.ones((2, 3, 1))), ["weights", "(2, 3, 1)"]),
    "scalar weights": (call(w=1.0), ["weights", "()"]),
    "string weights": (call(w=["a", "b", "c"]), ["weights", "<U1"]),
    "float src": (call(src=[0.0, 1.0, 0.0]), ["src", "float64"]),
    "2-D dst": (call(dst=[D3]), ["dst", "(1, 3)"]),
    "n_threads 0": (call(w=[W3], n_threads=0), ["n_threads", "0"]),
    "n_threads 0, one row": (call(n_threads=0), ["n_threads", "0"]),
    "n_threads 5000": (call(w=[W3], n_threads=5000), ["n_threads", "5000"]),
    "n_threads float": (call(w=[W3], n_threads=2.0), ["n_threads", "2.0"]),
}


@pytest.mark.parametrize(("bad", "fragments"), BAD_INPUTS.values(), ids=BAD_INPUTS)
def test_bad_input_is_a_named_error(bad: Callable[[], Any], fragments: list[str]) -> None:
    with pytest.raises(cm.InputError) as info:
        bad()
    assert isinstance(info.value, ValueError)
    for fragment in fragments:
        assert fragment in str(info.value), f"{fragment!r} not in {str(info.value)!r}"


def test_bad_threads_env_is_named(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CYCLOMECH_THREADS", "many")
    with pytest.raises(cm.InputError, match="CYCLOMECH_THREADS"):
        max_difference(3, S3, D3, [W3, W3], 0, 2)
    assert_array_equal(max_difference(3, S3, D3, [W3, W3], 0, 2, n_threads=1)[0], [3.0, 3.0])
