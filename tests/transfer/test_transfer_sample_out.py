"""TransferPath.sample(out=) and the sample's new arrays (issue 37 row 5): written
into a previous sample's arrays, the sample equals the numpy code it replaced
(``transfer_reference.sample``, 1e-12 of each array's scale) and, bit for bit, a
sample into new arrays; every element is written (poisoned buffers); a bad ``out``
is an error naming the array; new arrays are disjoint views of one block."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from cyclomech import InputError
from cyclomech import transfer as tr
from cyclomech._arrays import one_block
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

sys.path.insert(0, str(Path(__file__).parent))
import transfer_reference as ref

FIELDS = ("points", "s", "heading", "curvature", "curvature_rate", "piece")


def _poisoned(n: int) -> tr.PathSample:
    """A sample-shaped PathSample full of values no sample holds."""
    return tr.PathSample(
        np.full((n, 2), np.nan),
        np.full(n, -1e300),
        np.full(n, np.inf),
        np.full(n, 7.0),
        np.full(n, np.nan),
        np.full(n, -5, dtype=np.int8),
    )


def _arrays(smp: tr.PathSample) -> list[np.ndarray]:
    return [getattr(smp, f) for f in FIELDS]


def _close(got: np.ndarray, want: np.ndarray, what: str) -> None:
    scale = max(float(np.max(np.abs(want))), 1e-300)
    err = float(np.max(np.abs(got - want)))
    assert err <= 1e-12 * scale, f"{what}: error {err:.3g} on scale {scale:.3g}"


@settings(max_examples=25, deadline=None)
@given(
    r_t=st.floats(0.02, 1.0),
    r_p=st.floats(0.02, 1.0),
    gap=st.floats(1e-3, 0.2),
    angle=st.floats(-math.pi, math.pi),
    ccw=st.booleans(),
    n=st.integers(10, 20_000),
    threads=st.sampled_from([1, 2]),
)
def test_sample_into_out_equals_the_numpy_code_and_a_new_sample(
    r_t, r_p, gap, angle, ccw, n, threads
):
    d = r_t + r_p + gap
    p = tr.TransferPath(r_t, r_p, (0.0, 0.0), (d * math.cos(angle), d * math.sin(angle)), ccw=ccw)
    out = _poisoned(n)
    got = p.sample(n, n_threads=threads, out=out)
    new = p.sample(n, n_threads=threads)
    want = ref.sample(p, n)
    for f in FIELDS:
        assert getattr(got, f) is getattr(out, f), f
        assert getattr(got, f).tobytes() == getattr(new, f).tobytes(), f
    assert_array_equal(got.piece, want.piece)
    for f in FIELDS[:-1]:
        _close(getattr(got, f), getattr(want, f), f)


def test_sample_into_a_previous_sample_of_another_path():
    a = tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.04)
    b = tr.TransferPath(0.1, 0.3, (0.0, 0.0), (0.0, 0.42), ccw=False)
    prev = a.sample(50_001)
    again = b.sample(50_001, out=prev)
    new = b.sample(50_001)
    for f in FIELDS:
        assert_array_equal(getattr(again, f), getattr(new, f), err_msg=f)


def test_a_bad_out_is_an_error_naming_the_array():
    p = tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.04)
    good = p.sample(100)
    with pytest.raises(TypeError, match="out must be a PathSample"):
        p.sample(100, out={"s": good.s})
    with pytest.raises(InputError, match=r"out\.points.*shape \(101, 2\)"):
        p.sample(101, out=good)
    frozen = np.array(good.s)
    frozen.flags.writeable = False
    with pytest.raises(InputError, match=r"out\.s.*read-only"):
        p.sample(100, out=tr.PathSample(good.points, frozen, *_arrays(_poisoned(100))[2:]))
    shared = _poisoned(100)
    with pytest.raises(InputError, match=r"out\.heading shares memory with out\.s"):
        p.sample(100, out=tr.PathSample(shared.points, shared.s, shared.s, *_arrays(shared)[3:]))
    with pytest.raises(InputError, match=r"out\.piece.*int8"):
        p.sample(100, out=tr.PathSample(*_arrays(good)[:5], np.zeros(100, np.int64)))
    strided = np.zeros((100, 4))[:, ::2]
    with pytest.raises(InputError, match=r"out\.points.*not C-contiguous"):
        p.sample(100, out=tr.PathSample(strided, *_arrays(_poisoned(100))[1:]))


def test_new_sample_arrays_are_disjoint_views_of_one_aligned_block():
    p = tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.04)
    smp = p.sample(300_001)
    arrays = _arrays(smp)
    for i, a in enumerate(arrays):
        assert a.flags.c_contiguous and a.flags.writeable
        assert a.ctypes.data % 64 == 0
        assert not any(np.shares_memory(a, b) for b in arrays[i + 1 :])
    # Over 4 MiB: the block starts on a huge page.
    assert smp.points.ctypes.data % (1 << 21) == 0


@settings(max_examples=40, deadline=None)
@given(
    parts=st.lists(
        st.tuples(
            st.lists(st.integers(0, 40), min_size=0, max_size=3),
            st.sampled_from([np.float64, np.int8, np.bool_, np.int64]),
        ),
        min_size=1,
        max_size=6,
    )
)
def test_one_block_gives_disjoint_aligned_arrays_of_the_parts(parts):
    arrays = one_block(*[(tuple(shape), dt) for shape, dt in parts], what="parts", hint="")
    assert len(arrays) == len(parts)
    for (shape, dt), a in zip(parts, arrays, strict=True):
        assert a.shape == tuple(shape) and a.dtype == np.dtype(dt)
        assert a.flags.c_contiguous and a.flags.writeable
        if a.size:
            assert a.ctypes.data % 64 == 0
    # Disjoint: writing each array its index leaves every other intact.
    for i, a in enumerate(arrays):
        a[...] = i + 1
    for i, a in enumerate(arrays):
        assert (a == (i + 1 if a.dtype != np.bool_ else True)).all()


def test_one_block_refuses_a_size_that_cannot_fit_before_allocating(monkeypatch):
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", str(10**6))
    with pytest.raises(InputError, match=r"the parts needs .* GB, more than .*; fewer"):
        one_block(((10**6,), np.float64), what="the parts", hint="fewer")
    with pytest.raises(InputError, match=r"TransferPath\.sample\(200000\)"):
        tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0)).sample(200_000)
    # An element count that overflows int64 is refused, not wrapped.
    monkeypatch.delenv("CYCLOMECH_MAX_BYTES")
    with pytest.raises(InputError, match="more than"):
        one_block(((2**40, 2**40), np.float64), what="the parts", hint="fewer")
