"""Linkage.solve(out=) and linkage.solve_geometries(out=): results written into
the caller's arrays (issue 20, no fresh-page tax), bit for bit a fresh solve's; a
bad out is an InputError naming the array; and a solve of some points computes
the same bits and flags as the full solve (only what is asked)."""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

FIELDS = ("xy", "vel", "acc", "ok", "singular", "branch_change")


def crank_rocker() -> cm.Linkage:
    """A crank-rocker with a coupler point E and a slider F on a ground guide."""
    return cm.Linkage(
        {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0), "E": (2.0, 2.6), "F": (3.7, 1.55)},
        [("A", "B"), ("B", "C", "E"), ("C", "D"), ("C", "F")],
        ["A", "D"],
        ("A", "B"),
        sliders={"F": ("ground", (1.0, 0.3))},
    )


def same(a, b) -> bool:
    """Bit for bit (NaN payloads included), or both None."""
    if a is None or b is None:
        return a is None and b is None
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def assert_same_solution(got: cm.LinkageSolution, want: cm.LinkageSolution) -> None:
    for f in FIELDS:
        assert same(getattr(got, f), getattr(want, f)), f


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(0, 5000),
    start=st.floats(-20.0, 20.0),
    points=st.sampled_from([None, ["C"], ["E", "A"], ["F", "C", "B"]]),
    analogs=st.booleans(),
    threads=st.sampled_from([1, 2]),
    as_mapping=st.booleans(),
)
def test_out_is_bit_for_bit_a_fresh_solve(n, start, points, analogs, threads, as_mapping):
    lk = crank_rocker()
    phi = start + np.linspace(0.0, 7.0, n)
    fresh = lk.solve(phi, threads, points=points, analogs=analogs)
    # Poisoned buffers: every element must be written.
    shape = fresh.xy.shape
    bufs = {
        "xy": np.full(shape, 7.0),
        "vel": np.full(shape, -3.0) if analogs else None,
        "acc": np.full(shape, 1e300) if analogs else None,
        "ok": np.ones(n, bool) if n % 2 else np.zeros(n, bool),
        "singular": np.ones(n, bool),
        "branch_change": np.ones(n, bool),
    }
    out = bufs if as_mapping else cm.LinkageSolution(phi, fresh.names, *bufs.values())
    got = lk.solve(phi, threads, points=points, analogs=analogs, out=out)
    assert_same_solution(got, fresh)
    for f in FIELDS:
        assert getattr(got, f) is bufs[f]
    # Reused for other angles: only the latest call's results remain.
    again = lk.solve(phi[::-1].copy(), threads, points=points, analogs=analogs, out=got)
    assert again.xy is bufs["xy"]
    assert_same_solution(again, lk.solve(phi[::-1].copy(), points=points, analogs=analogs))


def test_a_mapping_may_leave_the_flags_out():
    lk = crank_rocker()
    phi = np.linspace(0, 6, 100)
    xy = np.empty((100, 1, 2))
    got = lk.solve(phi, points=["E"], analogs=False, out={"xy": xy})
    assert got.xy is xy and got.vel is None
    assert_same_solution(got, lk.solve(phi, points=["E"], analogs=False))


def test_a_huge_drawing_is_rescaled_in_place():
    # Drawn at 2^60 m: the kernel works in scaled units and the positions and
    # analogs are multiplied back, in the out arrays themselves.
    s = 2.0**60
    pts = {"A": (0, 0), "B": (s, 0), "C": (3.5 * s, 2.5 * s), "D": (4 * s, 0)}
    lk = cm.Linkage(pts, [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
    phi = np.linspace(0, 6, 50)
    fresh = lk.solve(phi)
    first = lk.solve(phi[::-1].copy())
    got = lk.solve(phi, out=first)
    assert got.xy is first.xy
    assert_same_solution(got, fresh)
    assert np.nanmax(np.abs(got.xy)) > s


@settings(max_examples=15, deadline=None)
@given(k=st.integers(0, 6), n=st.integers(0, 300), analogs=st.booleans())
def test_a_sweep_into_out_is_bit_for_bit(k, n, analogs):
    lk = crank_rocker()
    rng = np.random.default_rng(k * 1000 + n)
    lengths = lk.dimension_values * rng.uniform(0.9, 1.1, (k, len(lk.dimensions)))
    phi = np.linspace(0, 6.3, n)
    fresh = cm.linkage.solve_geometries(lk, phi, lengths, points=["E", "F"], analogs=analogs)
    first = cm.linkage.solve_geometries(lk, phi, lengths[::-1], points=["E", "F"], analogs=analogs)
    got = cm.linkage.solve_geometries(
        lk, phi, lengths, points=["E", "F"], analogs=analogs, out=first
    )
    assert got.xy is first.xy
    assert_same_solution(got, fresh)


def _solution(n=10, m=4, analogs=True):
    lk = crank_rocker()
    return lk, np.linspace(0, 1, n), lk.solve(np.zeros(n), points=list("ABCD")[:m], analogs=analogs)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda d: d.update(xy=np.zeros((10, 3, 2))), r"shape \(10, 4, 2\).*out\.xy"),
        (lambda d: d.update(vel=np.zeros((10, 4, 2), np.float32)), r"out\.vel.*float32"),
        (lambda d: d.update(acc=np.zeros((10, 2, 4)).transpose(0, 2, 1)), "out.acc"),
        (lambda d: d.update(vel=None), "out.vel is missing"),
        (lambda d: d.update(ok=np.zeros(10, np.int8)), r"out\.ok.*int8"),
        (lambda d: d.update(singular=np.zeros(11, bool)), r"out\.singular.*shape \(11,\)"),
        (lambda d: d.update(branch_change=[False] * 10), r"out\.branch_change.*list"),
        (lambda d: d.update(acc=d["vel"]), "out.vel and out.acc share memory"),
        (lambda d: d.update(extra=np.zeros(3)), "unknown array 'extra'"),
    ],
)
def test_a_bad_out_is_an_input_error_naming_the_array(change, match):
    lk, phi, sol = _solution()
    d = {f: getattr(sol, f) for f in FIELDS}
    change(d)
    with pytest.raises(cm.CyclomechError, match=match) as e:
        lk.solve(phi, points=list("ABCD"), out=d)
    assert isinstance(e.value, ValueError)


def test_read_only_overlapping_and_mismatched_outs_are_refused():
    lk, phi, sol = _solution()
    ro = sol.xy.copy()
    ro.flags.writeable = False
    d = {f: getattr(sol, f) for f in FIELDS}
    with pytest.raises(cm.CyclomechError, match="read-only"):
        lk.solve(phi, points=list("ABCD"), out={**d, "xy": ro})
    # An out that is a view of the angles themselves.
    mem = np.zeros(10 * 4 * 2)
    angles = mem[:10]
    with pytest.raises(cm.CyclomechError, match="shares memory with an input"):
        lk.solve(angles, points=list("ABCD"), out={**d, "xy": mem.reshape(10, 4, 2)})
    # A solution with analogs for a solve without, and the reverse.
    with pytest.raises(cm.CyclomechError, match="analogs=False"):
        lk.solve(phi, points=list("ABCD"), analogs=False, out=sol)
    _, _, bare = _solution(analogs=False)
    with pytest.raises(cm.CyclomechError, match=r"out\.vel is missing"):
        lk.solve(phi, points=list("ABCD"), out=bare)
    with pytest.raises(cm.CyclomechError, match="LinkageSolution"):
        lk.solve(phi, out=(sol.xy, sol.vel))
    # A previous solution of other angles' count.
    with pytest.raises(cm.CyclomechError, match=r"shape \(11, 4, 2\)"):
        lk.solve(np.zeros(11), points=list("ABCD"), out=sol)


def test_the_core_refuses_a_bad_out_with_an_input_error():
    lk, phi, sol = _solution()
    sel = np.arange(4, dtype=np.int64)
    arrays = [getattr(sol, f) for f in FIELDS]
    bad = [np.zeros((10, 3, 2)), *arrays[1:]]
    with pytest.raises(cm.CyclomechError, match="out must be C-contiguous arrays"):
        lk._program.solve(phi, sel, out=tuple(bad))
    # Two outputs that are one array: numpy will not lend it twice.
    twice = [arrays[0], arrays[0], *arrays[2:]]
    with pytest.raises(cm.CyclomechError, match="cannot be written in place"):
        lk._program.solve(phi, sel, out=tuple(twice))


@settings(max_examples=25, deadline=None)
@given(
    points=st.lists(st.sampled_from(list("ABCDEF")), min_size=1, max_size=4, unique=True),
    analogs=st.booleans(),
    threads=st.sampled_from([1, 2]),
)
def test_a_subset_is_the_full_solves_columns_and_flags(points, analogs, threads):
    # F's guide is out of reach over part of the turn: those angles fail for
    # every subset (the flags are the mechanism's), even when F is not asked for.
    lk = crank_rocker()
    phi = np.linspace(-1.0, 9.0, 4099)
    full = lk.solve(phi, threads)
    part = lk.solve(phi, threads, points=points, analogs=analogs)
    assert not full.ok.all() and full.ok.any()
    cols = [full.index(p) for p in points]
    assert same(part.ok, full.ok) and same(part.singular, full.singular)
    assert same(part.xy, full.xy[:, cols].copy())
    if analogs:
        assert same(part.vel, full.vel[:, cols].copy())
        assert same(part.acc, full.acc[:, cols].copy())


def test_new_solution_arrays_are_disjoint_and_a_solve_into_them_is_bit_for_bit():
    """A solve's new arrays are carved from one block (issue 37 row 6): each is its
    own memory, and solving into them again (``out=``) gives the same bits."""
    lk = crank_rocker()
    phi = np.linspace(-1.0, 9.0, 60_001)
    for analogs in (True, False):
        sol = lk.solve(phi, 1, analogs=analogs)
        given = {f: getattr(sol, f) for f in FIELDS if getattr(sol, f) is not None}
        arrays = list(given.values())
        assert len(arrays) == (6 if analogs else 4)
        for i, a in enumerate(arrays):
            assert a.flags.c_contiguous and a.flags.writeable
            assert not any(np.shares_memory(a, b) for b in arrays[i + 1 :])
        want = {f: a.copy() for f, a in given.items()}
        again = lk.solve(phi, 2, analogs=analogs, out=sol)
        for f, w in want.items():
            assert getattr(again, f) is given[f]
            assert same(getattr(again, f), w), f
