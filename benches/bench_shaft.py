"""The main shaft's statistics at 10 000 speeds against numpy.

``ShaftTorque.stats``: mean, peak, lowest and RMS torque, energy fluctuation,
flywheel and power of T = ω²·a + b (3600 samples over the turn) at 10 000 speeds in
one Rust call, against the same quantities vectorised with numpy over a (speeds,
samples) array (the trapezoid cumulative energy; its extrema at the samples only,
so it is within 1e-5 under the interpolant's exact ΔE: checked outside the timing).

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings::

    python -m pytest benches/bench_shaft.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

Array = npt.NDArray[np.float64]
GROUP = "shaft.stats, 3600 samples x 10 000 speeds"
N, S = 3600, 10_000
RAD = 2 * math.pi / 60


def torque() -> cm.shaft.ShaftTorque:
    th = np.arange(N) * (2 * math.pi / N)
    a = 1e-3 * np.sin(2 * th) + 5e-4 * np.cos(5 * th)
    b = 8 + 5 * np.cos(th) + 2 * np.sin(3 * th)
    return cm.shaft.ShaftTorque.from_curves(a[None], b[None])


def speeds() -> Array:
    return np.linspace(50.0, 1500.0, S)


def numpy_stats(t: cm.shaft.ShaftTorque, rpm: Array, delta: float) -> dict[str, Array]:
    w = rpm * RAD
    tt = (w**2)[:, None] * t.per_omega2[None] + t.static[None]
    h = 2 * math.pi / N
    mean = tt.mean(axis=1)
    nxt = np.roll(tt, -1, axis=1)
    rms = np.sqrt((h * (tt * tt + tt * nxt + nxt * nxt) / 3).sum(axis=1) / (2 * math.pi))
    d = tt - mean[:, None]
    e = np.cumsum(0.5 * (d + np.roll(d, -1, axis=1)) * h, axis=1)
    de = np.maximum(e.max(axis=1), 0) - np.minimum(e.min(axis=1), 0)
    return {
        "mean": mean,
        "peak": tt.max(axis=1),
        "rms": rms,
        "de": de,
        "flywheel": de / (w**2 * delta),
        "power": mean * w,
    }


def test_numpy_agrees() -> None:
    t, n = torque(), speeds()[::97]
    s, ref = t.stats(n, 0.02), numpy_stats(t, n, 0.02)
    np.testing.assert_allclose(s.mean_torque_nm, ref["mean"], rtol=1e-12)
    np.testing.assert_allclose(s.peak_torque_nm, ref["peak"], rtol=1e-12)
    np.testing.assert_allclose(s.rms_torque_nm, ref["rms"], rtol=1e-10)
    # The kernel's ΔE also takes E's extrema inside a step (exact for the
    # piecewise-linear torque); numpy's, at the samples only, is a hair lower.
    np.testing.assert_allclose(s.energy_fluctuation_j, ref["de"], rtol=1e-5)
    assert np.all(s.energy_fluctuation_j >= ref["de"] * (1 - 1e-12))


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_stats_cyclomech(benchmark, threads: int | None) -> None:
    t, n = torque(), speeds()
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"ShaftTorque.stats, {where}"
    s = benchmark(t.stats, n, 0.02, n_threads=threads)
    assert s.mean_torque_nm.shape == (S,)


@pytest.mark.benchmark(group=GROUP)
def test_stats_numpy(benchmark) -> None:
    t, n = torque(), speeds()
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "vectorised over (speeds, samples)"
    ref = benchmark(numpy_stats, t, n, 0.02)
    assert ref["mean"].shape == (S,)
