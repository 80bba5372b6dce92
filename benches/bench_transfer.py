"""Rotor transfer (issues 6 and 20): sampling the composed path and scanning
transition lengths, the Rust kernels against what a user would write with numpy
and scipy, in one run, on one thread and on two.

- ``TransferPath.sample(1e6)`` — points, arc length, heading, signed curvature and
  its rate along the whole guide (arc → quintic → straight → quintic → arc) of the
  README's example (0.15 and 0.25 m rotors, gap 10 mm, x2 = 40 mm): one Rust
  call. Peers: the numpy code it replaced (``tests/transfer/transfer_reference.py``, the
  same outputs, vectorised numpy with Gauss–Legendre arc lengths), and
  :func:`scipy_sample`, which samples only the two transitions with
  ``numpy.polynomial.Polynomial`` and its derivatives, arc length by
  ``scipy.integrate.cumulative_trapezoid`` and curvature from the closed form
  (less work: no arcs, no straight, no headings). Error: the arc length at the
  end of the second transition against ``scipy.integrate.quad``.
- ``design_transfer`` — 64 candidate lengths × 801 points per piece in one Rust
  call, then scipy's bounded minimiser (one Rust call per step) — against the
  numpy code it replaced (the same scan vectorised over candidates, the same
  minimiser) and against a Python loop of that numpy code's ``TransferPath`` and
  ``max_jerk`` per candidate (the straightforward way).

- ``test_ratio_table`` (issue 37): the sample on one thread against the scipy peer
  in both page states (fresh pages: ``malloc_trim(0)`` before each call), new arrays
  and ``out=previous``, and the floors of writing the sample's arrays once (new and
  existing). The scipy peer is the one a numpy/scipy user writes for the curve
  (polynomial derivatives, trapezoid arc length, closed-form curvature); the numpy
  code it replaced is slower still (the groups above).

Measured (AMD EPYC, 2 cores; medians): see BENCHMARKS.md. Run::

    python -m pytest benches/bench_transfer.py --benchmark-enable -q -p no:cacheprovider
    taskset -c 1 python -m pytest benches/bench_transfer.py -k ratio_table \
        --benchmark-enable -q -p no:cacheprovider -s
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
import scipy.integrate
from numpy.polynomial import Polynomial

sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "transfer"))
import transfer_reference as ref
from _timing import page_states, timed_run
from cyclomech._arrays import one_block

Array = npt.NDArray[np.float64]

R_T, R_P, GAP, X2, V = 0.15, 0.25, 0.01, 0.04, 0.15708
N = 1_000_000
GROUP_SAMPLE = f"TransferPath.sample: {N:.0e} points"
GROUP_DESIGN = "design_transfer: 64 candidate lengths"
ROUNDS = 9


def _label(benchmark, tool: str, what: str) -> None:
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


@pytest.fixture(scope="module")
def path() -> cm.transfer.TransferPath:
    return cm.transfer.TransferPath(R_T, R_P, (0.0, 0.0), (R_T + R_P + GAP, 0.0), x2=X2)


def quad_length(q: cm.transfer.QuinticTransition) -> float:
    d1 = Polynomial(q.coeffs).deriv()
    return scipy.integrate.quad(lambda x: np.sqrt(1 + d1(x) ** 2), 0.0, q.x2, epsabs=1e-15)[0]


def scipy_sample(path: cm.transfer.TransferPath, n: int) -> tuple[Array, ...]:
    """Both transitions on n/2 points each: machine-frame points, cumulative arc
    length (trapezoid), curvature and its rate from the polynomial's derivatives."""
    out = []
    s0 = 0.0
    for q, (alpha, x0, y0) in zip(path.transitions, path.frames, strict=True):
        p = Polynomial(q.coeffs)
        d1, d2, d3 = p.deriv(1), p.deriv(2), p.deriv(3)
        x = np.linspace(0.0, q.x2, n // 2)
        y, y1, y2, y3 = p(x), d1(x), d2(x), d3(x)
        c, s = np.cos(alpha), np.sin(alpha)
        pts = np.stack([x * c + y * s - x0, -x * s + y * c - y0], axis=-1)
        g = 1 + y1 * y1
        arc = s0 + scipy.integrate.cumulative_trapezoid(np.sqrt(g), x, initial=0.0)
        kappa = y2 / g**1.5
        rate = (y3 * g - 3 * y1 * y2 * y2) / g**3
        s0 = arc[-1]
        out.append((pts, arc, kappa, rate))
    return tuple(np.concatenate(parts) for parts in zip(*out, strict=True))


@pytest.mark.parametrize("threads", [1, 2])
def test_sample_cyclomech(benchmark, path, threads) -> None:
    benchmark.group = GROUP_SAMPLE
    _label(benchmark, "cyclomech", f"TransferPath.sample (whole path, Rust), n_threads={threads}")
    smp = benchmark(path.sample, N, n_threads=threads)
    assert smp.points.shape == (N, 2)
    ends = [np.flatnonzero(smp.piece == i)[-1] for i in (1, 3)]
    # The second transition ends at C: its arc length from A is the two
    # transitions' quad lengths and the straight.
    want = sum(quad_length(q) for q in path.transitions) + path.straight_length
    got = smp.s[ends[1] + 1] - path.start_of_transfer
    err = abs(got - want) / want
    benchmark.extra_info["what"] += f"; err {err:.0e} vs quad"
    assert err < 1e-12


def test_sample_numpy(benchmark, path) -> None:
    benchmark.group = GROUP_SAMPLE
    _label(benchmark, "numpy", "the numpy code it replaced (whole path, same outputs)")
    smp = benchmark.pedantic(ref.sample, args=(path, N), rounds=5)
    ours = path.sample(N)
    assert np.allclose(smp.s, ours.s, rtol=0, atol=1e-12 * ours.s[-1])


def test_sample_scipy(benchmark, path) -> None:
    benchmark.group = GROUP_SAMPLE
    _label(benchmark, "scipy", "Polynomial + cumulative_trapezoid, the two transitions only")
    pts, arc, kappa, _rate = benchmark(scipy_sample, path, N)
    want = sum(quad_length(q) for q in path.transitions)
    err = abs(arc[-1] - want) / want
    benchmark.extra_info["what"] += f"; err {err:.0e} vs quad"
    assert err < 1e-9
    assert kappa[0] == pytest.approx(1 / R_T, rel=1e-12)
    assert pts.shape == (N, 2)


def _sample_block(n: int) -> list[Any]:
    """Arrays of a sample's shapes and types (the floor's output)."""
    return one_block(
        ((n, 2), np.float64), *[((n,), np.float64)] * 4, ((n,), np.int8), what="floor", hint=""
    )


def test_ratio_table(request: pytest.FixtureRequest, path) -> None:
    """``TransferPath.sample(1e6)``, one thread, interleaved rounds (medians, wall
    and CPU), both page states (``_timing.page_states``): new arrays and
    ``out=previous``, the scipy peer, and the floors — the sample's arrays new
    (one block, as ``sample`` allocates them) and existing, written once
    (``fill``). The peer and ours are checked to agree first."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    prev = path.sample(N, n_threads=1)
    pts, arc, kappa, _rate = scipy_sample(path, N)
    assert pts.shape == (N, 2)
    # The peer's transitions against ours on the same abscissas: the curvature
    # at A and the transitions' total length (quad) agree.
    assert kappa[0] == pytest.approx(prev.curvature[prev.piece == 1][0], rel=1e-12)
    want = sum(quad_length(q) for q in path.transitions)
    assert abs(arc[-1] - want) < 1e-9 * want
    assert path.sample(N, n_threads=1, out=prev).s is prev.s
    existing = _sample_block(N)
    tools: dict[str, Callable[[], Any]] = {
        "cyclomech 1 thread": lambda: path.sample(N, n_threads=1),
        "cyclomech 1 thread, out=": lambda: path.sample(N, n_threads=1, out=prev),
        "scipy (two transitions)": lambda: scipy_sample(path, N),
        "floor: new arrays written once": lambda: [a.fill(1) for a in _sample_block(N)],
        "floor: existing arrays written": lambda: [a.fill(1) for a in existing],
    }
    for state, t in page_states(tools, ROUNDS).items():
        print(
            f"\nTransferPath.sample({N:.0e}), {state} pages, {ROUNDS} interleaved rounds (medians)"
        )
        peer = t["scipy (two transitions)"]
        for name, (w, c) in t.items():
            print(
                f"  {name:32s} wall {w * 1e3:6.2f} ms  cpu {c * 1e3:6.2f} ms  "
                f"scipy/this {peer[0] / w:5.2f}x (cpu {peer[1] / c:5.2f}x)"
            )


def loop_design(speed: float, cands: Array) -> Array:
    return np.array(
        [
            ref.max_jerk(
                cm.transfer.TransferPath(R_T, R_P, (0.0, 0.0), (R_T + R_P + GAP, 0.0), x2=float(x)),
                speed,
                n=2401,
            )
            for x in cands
        ]
    )


@pytest.mark.parametrize("threads", [1, 2])
def test_design_cyclomech(benchmark, threads) -> None:
    benchmark.group = GROUP_DESIGN
    _label(
        benchmark, "cyclomech", f"design_transfer (Rust scan, then bounded), n_threads={threads}"
    )
    d = benchmark(cm.transfer.design_transfer, R_T, R_P, GAP, V, n_threads=threads)
    assert d.at_limit
    # The scan agrees with the full sampler on a few candidates.
    check = loop_design(V, d.candidates[::16])
    assert np.allclose(d.peak_jerk[::16], check, rtol=2e-2)


def test_design_numpy(benchmark) -> None:
    benchmark.group = GROUP_DESIGN
    _label(benchmark, "numpy", "the numpy code it replaced (candidates vectorised, then bounded)")
    want = benchmark.pedantic(ref.design_transfer, args=(R_T, R_P, GAP, V), rounds=5)
    d = cm.transfer.design_transfer(R_T, R_P, GAP, V)
    assert np.allclose(d.peak_jerk, want["peak_jerk"], rtol=1e-12)


def test_design_loop(benchmark) -> None:
    benchmark.group = GROUP_DESIGN
    _label(benchmark, "numpy", "a TransferPath and the numpy max_jerk per candidate (Python loop)")
    d = cm.transfer.design_transfer(R_T, R_P, GAP, V)
    cands = d.candidates[:-1]  # the last is the geometric limit (x2=None case)
    peaks = benchmark.pedantic(loop_design, args=(V, cands), rounds=5)
    assert np.allclose(peaks, d.peak_jerk[:-1], rtol=2e-2)
