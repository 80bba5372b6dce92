"""``duhamel_batch(..., out=)``: a caller-owned output filled in place (issue 20,
"no fresh-page tax").

Rules tested here:
- the results are bit for bit those of a fresh output, whatever ``out`` held
  before (NaN, random bits): the kernel writes every entry and reads none, on
  the lockstep path (uniform grid, groups of 8 cases), the case-by-case path
  (random grid) and the parallel split (two threads, several tasks);
- ``out`` is returned (the same object), and a reused ``out`` holds the latest
  call's results only;
- an ``out`` of the wrong type, dtype, shape or layout, read-only, or sharing
  memory with any input (as given or as converted) is an ``InputError`` naming
  ``out``, what it is and what is expected — in the Python layer and, for
  callers of ``_core``, in the binding (numpy's borrow checker refuses overlap);
- if the call fails (a bad case), it raises and ``out`` may be partly written.
"""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core, impact
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

TAU = 2 * np.pi


def _batch(b, grid, seed=0):
    rng = np.random.default_rng(seed)
    if grid == "random":
        t = np.sort(np.concatenate([[0.0], rng.uniform(0, 0.05, 300)]))
    else:  # uniform, with a jump of the force at 0.01 s (a repeated time)
        t = np.sort(np.concatenate([np.linspace(0.0, 0.05, 300), [0.01]]))
    forces = rng.normal(size=(b, t.size)).cumsum(axis=1)
    omega = TAU * rng.uniform(20, 400, b)
    zeta = rng.choice([0.0, 0.03, 0.5, 1.0, 2.5], b)
    mass = rng.uniform(0.01, 2.0, b)
    q0 = rng.normal(scale=1e-3, size=b)
    v0 = rng.normal(scale=0.1, size=b)
    return t, forces, omega, zeta, mass, q0, v0


def _bits(a):
    return np.ascontiguousarray(a).view(np.uint64)


def _garbage(shape, kind, seed=1):
    if kind == "nan":
        return np.full(shape, np.nan)
    bits = np.random.default_rng(seed).integers(0, 2**64, size=shape, dtype=np.uint64)
    return bits.view(np.float64)  # any bit pattern: NaNs, infs, subnormals


@pytest.mark.parametrize("grid", ["random", "uniform"])
@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("kind", ["nan", "bits"])
def test_out_is_bit_identical_to_a_fresh_output(grid, threads, kind):
    # 203 cases: 25 lockstep groups and a remainder of 3, split over tasks.
    args = _batch(203, grid)
    fresh = impact.duhamel_batch(*args, n_threads=threads)
    out = _garbage(fresh.shape, kind)
    got = impact.duhamel_batch(*args, n_threads=threads, out=out)
    assert got is out
    np.testing.assert_array_equal(_bits(got), _bits(fresh))


def test_out_result_is_the_closed_form():
    # Independent of the kernel: a unit step force on an undamped oscillator
    # (k = m·ω² = 4) is q = (1 - cos ωt)/k; with ζ > 0 the exact damped step
    # response x = (1 - e^{-ζωt}(cos ω_d t + ζω/ω_d sin ω_d t))/k.
    t = np.linspace(0.0, 3.0, 3001)
    zeta = np.array([0.0, 0.1, 0.3, 0.0, 0.1, 0.3, 0.0, 0.1, 0.3])
    out = np.full((9, t.size), np.nan)
    q = cm.impact.duhamel_batch(t, np.ones((9, t.size)), 2.0, zeta, 1.0, out=out)
    wd = 2.0 * np.sqrt(1 - zeta[:, None] ** 2)
    decay = np.exp(-zeta[:, None] * 2.0 * t)
    exact = (1 - decay * (np.cos(wd * t) + zeta[:, None] * 2.0 / wd * np.sin(wd * t))) / 4
    assert_allclose(q, exact, rtol=0, atol=1e-13)  # 3000 steps of rounding on 0.25 m


def test_reused_out_holds_the_latest_call_only():
    t, forces, omega, zeta, mass, q0, v0 = _batch(20, "uniform")
    out = np.empty_like(forces)
    first = impact.duhamel_batch(t, forces, omega, zeta, mass, q0, v0, out=out).copy()
    second = impact.duhamel_batch(t, -2.0 * forces, omega, zeta, mass, out=out)
    assert second is out
    fresh = impact.duhamel_batch(t, -2.0 * forces, omega, zeta, mass)
    np.testing.assert_array_equal(_bits(out), _bits(fresh))
    assert not np.array_equal(first, out)


def test_out_with_no_cases_and_one_time():
    t = np.array([0.0])
    out = np.full((3, 1), np.nan)
    q = impact.duhamel_batch(t, np.ones((3, 1)), 5.0, 0.1, 1.0, [1.0, 2.0, 3.0], out=out)
    assert q is out
    np.testing.assert_array_equal(q[:, 0], [1.0, 2.0, 3.0])
    empty = np.empty((0, 4))
    q = impact.duhamel_batch(np.arange(4.0), np.empty((0, 4)), 5.0, 0.1, 1.0, out=empty)
    assert q is empty


def test_out_may_be_an_ndarray_subclass(tmp_path):
    # A memory map: histories larger than memory, written in place.
    t, forces, omega, zeta, mass, q0, v0 = _batch(10, "uniform")
    mm = np.lib.format.open_memmap(tmp_path / "q.npy", "w+", np.float64, forces.shape)
    impact.duhamel_batch(t, forces, omega, zeta, mass, q0, v0, out=mm)
    mm.flush()
    fresh = impact.duhamel_batch(t, forces, omega, zeta, mass, q0, v0)
    np.testing.assert_array_equal(_bits(np.load(tmp_path / "q.npy")), _bits(fresh))


@settings(max_examples=40, deadline=None)
@given(
    b=st.integers(0, 40),
    n=st.integers(1, 60),
    threads=st.sampled_from([1, 2]),
    seed=st.integers(0, 2**32 - 1),
)
def test_out_property_any_size_any_previous_content(b, n, threads, seed):
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0.0, 0.02, n))
    if rng.random() < 0.5:
        t = np.linspace(0.0, 0.02, n)  # the lockstep path
    forces = rng.normal(size=(b, n))
    cases = (
        TAU * rng.uniform(10, 500, b),
        rng.choice([0.0, 0.02, 1.0, 3.0], b),
        rng.uniform(0.1, 2.0, b),
        rng.normal(scale=1e-3, size=b),
        rng.normal(scale=1e-2, size=b),
    )
    fresh = impact.duhamel_batch(t, forces, *cases, n_threads=threads)
    out = _garbage((b, n), "bits", seed)
    got = impact.duhamel_batch(t, forces, *cases, n_threads=threads, out=out)
    assert got is out
    np.testing.assert_array_equal(_bits(got), _bits(fresh))


T5 = np.linspace(0.0, 1.0, 5)
F5 = np.ones((2, 5))


def _readonly():
    a = np.empty((2, 5))
    a.flags.writeable = False
    return a


@pytest.mark.parametrize(
    ("out", "match"),
    [
        (
            np.empty((2, 4)),
            r"out must be .*float64.*shape \(2, 5\).*got a float64 array of shape \(2, 4\)",
        ),
        (np.empty(10), r"out .*shape \(2, 5\).*got a float64 array of shape \(10,\)"),
        (np.empty((2, 5), np.float32), r"out .*float64.*got a float32 array of shape \(2, 5\)"),
        (np.empty((2, 5), np.int64), r"out .*float64.*got a int64 array"),
        (np.empty((2, 5), ">f8"), r"out .*float64.*got a >f8 array"),
        (np.empty((5, 2)).T, r"out .*C-contiguous.*not C-contiguous \(strides \(8, 16\)\)"),
        (np.empty((2, 10))[:, ::2], r"out .*C-contiguous.*not C-contiguous"),
        (_readonly(), r"out .*writeable.*read-only"),
        ([[0.0] * 5] * 2, r"out must be .*numpy array.*got list"),
        (3.0, r"out .*got float"),
    ],
)
def test_bad_out_is_an_input_error_naming_it(out, match):
    with pytest.raises(cm.InputError, match=match) as e:
        impact.duhamel_batch(T5, F5, 1.0, 0.0, 1.0, out=out)
    assert isinstance(e.value, ValueError)
    assert isinstance(e.value, cm.CyclomechError)


def test_out_sharing_memory_with_an_input_is_refused():
    buf = np.zeros((4, 5))
    cases = [
        # out is forces itself, or overlaps it
        dict(forces=buf[:2], out=buf[:2]),
        dict(forces=buf[1:3], out=buf[:2]),
        # out holds t, or a per-case array (contiguous, then strided: copied
        # before the call, refused all the same)
        dict(t=buf[3], out=buf[2:4]),
        dict(omega_n=buf[2, :2], out=buf[2:4]),
        dict(zeta=buf[:, 0][:2], out=buf[:2]),
    ]
    for kw in cases:
        args = dict(t=T5, forces=F5, omega_n=1.0, zeta=0.0, mass=1.0)
        args.update(kw)
        out = args.pop("out")
        before = out.copy()
        with pytest.raises(cm.InputError, match=r"out .*shares memory with an input"):
            impact.duhamel_batch(**args, out=out)
        np.testing.assert_array_equal(out, before)  # not written
    # Neighbours in one buffer that do not overlap are fine.
    big = np.zeros((4, 5))
    big[2:] = 1.0
    q = impact.duhamel_batch(T5, big[2:], 1.0, 0.0, 1.0, out=big[:2])
    assert q.base is big
    np.testing.assert_array_equal(q, impact.duhamel_batch(T5, F5, 1.0, 0.0, 1.0))


def test_core_refuses_a_bad_out_too():
    # Callers of _core skip the Python checks: the binding's own, never a panic.
    z, one = np.zeros(2), np.ones(2)
    f = np.ones((2, 5))

    def call(out, forces=f):
        return _core.duhamel_batch(T5, forces, one, z, one, z, z, out=out)

    bad = [
        (f, r"out .*overlaps no input.*already borrowed"),
        (_readonly(), r"out .*not writeable"),
        (np.empty((2, 4)), r"out .*\(2, 5\).*C-contiguous float64 array of shape \(2, 4\)"),
        (np.empty((5, 2)).T, r"out .*non-contiguous float64 array of shape \(2, 5\)"),
        (np.empty((2, 5), np.float32), r"out .*ndarray with dtype float32 and shape \(2, 5\)"),
        ("q", r"out .*str with dtype none"),
    ]
    for out, match in bad:
        with pytest.raises(cm.InputError, match=match):
            call(out)
    buf = np.zeros((3, 5))
    with pytest.raises(cm.InputError, match=r"out .*already borrowed"):
        call(buf[:2], forces=buf[1:])
    good = np.full((2, 5), np.nan)
    assert call(good) is good
    np.testing.assert_array_equal(good, call(None))


def test_a_failing_call_with_out_raises():
    f = np.ones((2, 5))
    f[1, 3] = np.nan
    out = np.zeros((2, 5))
    with pytest.raises(cm.InputError, match=r"case 1: force\[3\] must be finite"):
        impact.duhamel_batch(T5, f, 1.0, 0.0, 1.0, out=out)
