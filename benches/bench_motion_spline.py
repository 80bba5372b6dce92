"""A spline segment through a point table against scipy's CubicSpline, build and evaluate.

A program of one cubic spline segment over the whole cycle through 1e4 points of
a smooth table over one period (periodic ends: a table over the whole cycle runs
into the next), then s, v, a, j at 1e6 sorted master angles, against
``scipy.interpolate.CubicSpline`` (the same function: ``bc_type="periodic"``, knots
at the points) built on the same table and evaluated with its derivatives
(``cs(x, k)`` for k = 0…3). Both agree (``test_scipy_agrees``, outside the timing:
s to 1e-12 of its scale, j to 1e-7); both allocate their outputs in every call.

    python -m pytest benches/bench_motion_spline.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

GROUP = "spline segment: 1e4 points, s/v/a/j at 1e6 angles"
POINTS = 10_000
N = 1_000_000


def table() -> tuple[np.ndarray, np.ndarray]:
    deg = np.linspace(0.0, 360.0, POINTS)
    y = 0.02 * (1 - np.cos(np.radians(deg))) + 0.003 * np.sin(3 * np.radians(deg))
    y[-1] = y[0]  # one period: the spline over the whole cycle is periodic
    return deg, y


def program() -> cm.motion.Program:
    deg, y = table()
    seg = cm.motion.Segment("spline", 360, points=np.column_stack([deg, y]))
    return cm.motion.Program([seg], continuity="position")


def grid() -> np.ndarray:
    return np.linspace(0.0, 2 * math.pi, N, endpoint=False)


def ours(theta: np.ndarray) -> cm.motion.MotionValues:
    return program().evaluate(theta)


def scipy_spline(theta: np.ndarray) -> list[np.ndarray]:
    deg, y = table()
    cs = CubicSpline(np.radians(deg), y, bc_type="periodic")
    return [cs(theta, k) for k in range(4)]


def test_scipy_agrees() -> None:
    """Two solvers of a 1e4-point spline: s and v agree to rounding, the higher
    derivatives to the rounding the table's 1e4 knots amplify: the k-th derivative by
    about (n/2π)^k·ε of its scale, 1e-6 for the jerk (the periodic system's and
    scipy's solves round differently)."""
    theta = grid()[::101]
    m = ours(theta)
    tol = (1e-12, 1e-11, 1e-8, 1e-5)
    for got, want, t in zip((m.s, m.v, m.a, m.j), scipy_spline(theta), tol, strict=True):
        np.testing.assert_allclose(got, want, rtol=0, atol=t * np.abs(want).max())


@pytest.mark.benchmark(group=GROUP)
def test_spline_cyclomech(benchmark) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = "Program(spline segment) + evaluate"
    m = benchmark(ours, grid())
    assert m.s.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
def test_spline_scipy(benchmark) -> None:
    benchmark.extra_info["tool"] = "scipy"
    benchmark.extra_info["what"] = "CubicSpline + cs(x, k), k = 0…3"
    s, *_ = benchmark(scipy_spline, grid())
    assert s.shape == (N,)
