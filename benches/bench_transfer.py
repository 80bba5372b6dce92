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

Measured (AMD EPYC, 2 cores; medians): see BENCHMARKS.md. Run::

    python -m pytest benches/bench_transfer.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
import scipy.integrate
from numpy.polynomial import Polynomial

sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "transfer"))
import transfer_reference as ref

Array = npt.NDArray[np.float64]

R_T, R_P, GAP, X2, V = 0.15, 0.25, 0.01, 0.04, 0.15708
N = 1_000_000
GROUP_SAMPLE = f"TransferPath.sample: {N:.0e} points"
GROUP_DESIGN = "design_transfer: 64 candidate lengths"


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
