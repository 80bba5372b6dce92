"""A motion program evaluated over an angle grid against numpy closed forms.

``cyclomech.motion.Program.evaluate`` (s, v, a, j at 1e6 master angles, one Rust
call) against :func:`numpy_program`: the best a numpy user would write for the
same program — each segment's closed form (cycloidal rise, 3-4-5 return, dwells)
on its contiguous slice of the sorted grid (``searchsorted`` on the four
boundaries; no masks, no per-angle lookup). Both agree to 1e-12 (checked by
:func:`test_numpy_agrees`, outside the timing). Both allocate their outputs in
every call (``evaluate`` also keeps a copy of the angles, which numpy's returns
do not), and both sides run in the same memory-page state, two of them:

* ``reused``: glibc's heap keeps and reuses the freed outputs (the state a loop
  of calls reaches by itself: its mmap threshold rises to the 32 MB block);
* ``fresh``: ``malloc_trim(0)`` before each timed call hands the freed pages
  back to the kernel, so each call first-touches its outputs (page faults and
  the kernel's zeroing) and numpy its temporaries. Linux with glibc only;
  skipped elsewhere.

Floors in the same states: the four output rows written once
(``np.empty((4, N)).fill``), and that plus a copy of the angles (what
``evaluate`` must at least do: read θ, write 5 × N float64).

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings and the ratio table::

    python -m pytest benches/bench_motion_program.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from pathlib import Path

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import malloc_trim

Array = npt.NDArray[np.float64]
GROUP = "motion program: s, v, a, j at 1e6 angles"
N = 1_000_000
H = 0.05  # stroke [m]
B1, B2 = math.radians(120.0), math.radians(120.0)  # rise and return angles
D1 = math.radians(60.0)  # the dwell between them


@pytest.fixture(params=["reused", "fresh"])
def pages(request: pytest.FixtureRequest) -> Callable[[], object] | None:
    """The memory-page state of the outputs (module docs) for both sides: the
    setup to run before each timed call (none for reused pages)."""
    if request.param == "reused":
        return None
    trim = malloc_trim()
    if trim is None:
        pytest.skip("fresh pages need glibc's malloc_trim")
    return trim


def _timed(benchmark, pages: Callable[[], object] | None, fn, *args, rounds: int, **kwargs):
    """``fn(*args, **kwargs)`` timed over ``rounds`` calls, ``pages`` before each
    (untimed), after one untimed call (which lets glibc's heap settle on reusing
    the block); each call's result dropped inside the timing, as
    ``benchmark(fn)`` does, so that the next call can reuse its memory. Returns
    one more call's result."""

    def call() -> None:
        fn(*args, **kwargs)

    def setup() -> None:
        if pages is not None:
            pages()

    benchmark.pedantic(call, setup=setup, rounds=rounds, warmup_rounds=1)
    return fn(*args, **kwargs)


def program() -> cm.motion.Program:
    S = cm.motion.Segment
    return cm.motion.Program(
        [
            S("cycloidal", 120, end=H),
            S("dwell", 60),
            S("polynomial_345", 120, end=0.0),
            S("dwell", 60),
        ],
        continuity="acceleration",
    )


def grid() -> Array:
    return np.linspace(0.0, 2 * math.pi, N, endpoint=False)


def numpy_program(theta: Array) -> tuple[Array, Array, Array, Array]:
    """s, v, a, j of :func:`program` on a sorted grid in [0, 2π), by segment slices."""
    s, v, a, j = (np.zeros_like(theta) for _ in range(4))
    i1, i2, i3 = np.searchsorted(theta, [B1, B1 + D1, B1 + D1 + B2])
    # Cycloidal rise: s = H (x − sin 2πx / 2π), x = θ/β.
    x = theta[:i1] / B1
    w = 2 * math.pi * x
    sw, cw = np.sin(w), np.cos(w)
    s[:i1] = H * (x - sw / (2 * math.pi))
    v[:i1] = H / B1 * (1 - cw)
    a[:i1] = H / B1**2 * 2 * math.pi * sw
    j[:i1] = H / B1**3 * 4 * math.pi**2 * cw
    s[i1:i2] = H
    # 3-4-5 return: s = H (1 − (10x³ − 15x⁴ + 6x⁵)).
    x = (theta[i2:i3] - B1 - D1) / B2
    x2 = x * x
    s[i2:i3] = H * (1 - x2 * x * (10 - x * (15 - 6 * x)))
    v[i2:i3] = -H / B2 * 30 * x2 * (1 - x) ** 2
    a[i2:i3] = -H / B2**2 * 60 * x * (1 - x) * (1 - 2 * x)
    j[i2:i3] = -H / B2**3 * 60 * (1 - 6 * x + 6 * x2)
    return s, v, a, j


def test_numpy_agrees() -> None:
    theta = grid()[::97]
    m = program().evaluate(theta)
    for got, want in zip((m.s, m.v, m.a, m.j), numpy_program(theta), strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_program_cyclomech(benchmark, threads: int, pages) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"Program.evaluate, n_threads={threads}"
    p, theta = program(), grid()
    m = _timed(benchmark, pages, p.evaluate, theta, n_threads=threads, rounds=60)
    assert m.s.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
def test_program_numpy(benchmark, pages) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "closed forms on each segment's slice"
    s, *_ = _timed(benchmark, pages, numpy_program, grid(), rounds=20)
    assert s.shape == (N,)


def _rows() -> Array:
    out = np.empty((4, N))
    out.fill(0.5)
    return out


def _rows_and_angles(theta: Array) -> tuple[Array, Array]:
    return _rows(), theta.copy()


@pytest.mark.benchmark(group=GROUP)
def test_floor_rows(benchmark, pages) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "floor: np.empty((4, N)).fill"
    assert _timed(benchmark, pages, _rows, rounds=60).shape == (4, N)


@pytest.mark.benchmark(group=GROUP)
def test_floor_rows_and_angles(benchmark, pages) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "floor: the rows and theta.copy()"
    rows, copy = _timed(benchmark, pages, _rows_and_angles, grid(), rounds=60)
    assert rows.shape == (4, N) and copy.shape == (N,)
