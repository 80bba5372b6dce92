"""The main shaft's statistics at 10 000 speeds against numpy.

``ShaftTorque.stats``: mean, peak, lowest and RMS torque, energy fluctuation,
flywheel and power of T = ω²·a + b (3600 samples over the turn) at 10 000 speeds
in one Rust call (since issue 37: functions of u = ω² over sums, convex hulls and
the steps' crossing intervals computed once, O(N log N + S log S)), against
:func:`numpy_stats`, the best numpy a user would write with the same structure:

- mean = u·ā + b̄ and RMS² = mean² + u²·Qaa + u·Qab + Qbb from three step sums
  (no (speeds, samples) array at all);
- peak, lowest and the energy E_k = u·Ea_k + Eb_k (the trapezoid cumulative
  integral of each part, once) as matrix products ``np.outer(u, a) + b`` in
  blocks of :data:`BLOCK` speeds into one reused buffer (in cache, no fresh
  pages), max and min along the samples.

It takes E's extrema at the samples only (the cyclomech kernel also takes those
inside a step, exact for the piecewise-linear torque): ΔE within 1e-5 of the
kernel's and never above (checked outside the timing); every other column to
1e-12 (RMS 1e-10).

The output is (10 000, 7) float64, 0.56 MB, and numpy's work arrays are reused,
so both sides run in the same page state; there is no large output to measure
fresh against reused.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings (one thread, interleaved rounds, medians and the ratio of one run)::

    taskset -c 1 python benches/bench_shaft.py
    python -m pytest benches/bench_shaft.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from _timing import interleaved

Array = npt.NDArray[np.float64]
GROUP = "shaft.stats, 3600 samples x 10 000 speeds"
N, S = 3600, 10_000
RAD = 2 * math.pi / 60
#: Speeds per block of numpy's (speeds, samples) products (1.8 MB: in cache).
BLOCK = 64


def torque() -> cm.shaft.ShaftTorque:
    th = np.arange(N) * (2 * math.pi / N)
    a = 1e-3 * np.sin(2 * th) + 5e-4 * np.cos(5 * th)
    b = 8 + 5 * np.cos(th) + 2 * np.sin(3 * th)
    return cm.shaft.ShaftTorque.from_curves(a[None], b[None])


def speeds() -> Array:
    return np.linspace(50.0, 1500.0, S)


def numpy_stats(t: cm.shaft.ShaftTorque, rpm: Array, delta: float) -> dict[str, Array]:
    """The statistics with T = ω²·a + b (see the module docs)."""
    a, b = t.per_omega2, t.static
    n = a.size
    h = 2 * math.pi / n
    w = rpm * RAD
    u = w * w
    mean = u * a.mean() + b.mean()
    da, db = a - a.mean(), b - b.mean()
    da1, db1 = np.roll(da, -1), np.roll(db, -1)
    qaa = (da * da + da * da1 + da1 * da1).sum() / (3 * n)
    qab = (2 * da * db + da * db1 + da1 * db + 2 * da1 * db1).sum() / (3 * n)
    qbb = (db * db + db * db1 + db1 * db1).sum() / (3 * n)
    rms = np.sqrt(mean * mean + (u * qaa + qab) * u + qbb)
    ea = np.concatenate([[0.0], np.cumsum(0.5 * (da + da1) * h)])
    eb = np.concatenate([[0.0], np.cumsum(0.5 * (db + db1) * h)])
    peak, low, de = np.empty_like(u), np.empty_like(u), np.empty_like(u)
    buf_t = np.empty((BLOCK, n))
    buf_e = np.empty((BLOCK, n + 1))
    for i in range(0, u.size, BLOCK):
        ub = u[i : i + BLOCK]
        m = ub.size
        tt, ee = buf_t[:m], buf_e[:m]
        np.multiply.outer(ub, a, out=tt)
        tt += b
        tt.max(axis=1, out=peak[i : i + m])
        tt.min(axis=1, out=low[i : i + m])
        np.multiply.outer(ub, ea, out=ee)
        ee += eb
        de[i : i + m] = ee.max(axis=1) - ee.min(axis=1)
    return {
        "mean": mean,
        "peak": peak,
        "low": low,
        "rms": rms,
        "de": de,
        "flywheel": de / (u * delta),
        "power": mean * w,
    }


def test_numpy_agrees() -> None:
    t, n = torque(), speeds()[::97]
    s, ref = t.stats(n, 0.02), numpy_stats(t, n, 0.02)
    np.testing.assert_allclose(s.mean_torque_nm, ref["mean"], rtol=1e-12)
    np.testing.assert_allclose(s.peak_torque_nm, ref["peak"], rtol=1e-12)
    np.testing.assert_allclose(s.lowest_torque_nm, ref["low"], rtol=1e-12)
    np.testing.assert_allclose(s.rms_torque_nm, ref["rms"], rtol=1e-10)
    np.testing.assert_allclose(s.power_w, ref["power"], rtol=1e-12)
    # The kernel's ΔE also takes E's extrema inside a step (exact for the
    # piecewise-linear torque); numpy's, at the samples only, is a hair lower.
    np.testing.assert_allclose(s.energy_fluctuation_j, ref["de"], rtol=1e-5)
    assert np.all(s.energy_fluctuation_j >= ref["de"] * (1 - 1e-12))
    np.testing.assert_allclose(s.flywheel_kg_m2, ref["flywheel"], rtol=1e-5)


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
    benchmark.extra_info["what"] = f"T = w^2 a + b, outer products in blocks of {BLOCK} speeds"
    ref = benchmark(numpy_stats, t, n, 0.02)
    assert ref["mean"].shape == (S,)


def main() -> None:
    """Medians of interleaved rounds, one thread, and the ratio."""
    test_numpy_agrees()
    t, n = torque(), speeds()
    med = interleaved(
        {
            "cyclomech": lambda: t.stats(n, 0.02, n_threads=1),
            "numpy": lambda: numpy_stats(t, n, 0.02),
        },
        rounds=21,
    )
    (cy, cyc), (npy, npc) = med["cyclomech"], med["numpy"]
    print(f"cyclomech, 1 thread: {cy * 1e3:.3f} ms wall, {cyc * 1e3:.3f} CPU ({S} x {N})")
    print(
        f"numpy (T = w^2 a + b, blocks of {BLOCK}): {npy * 1e3:.2f} ms wall, "
        f"{npc * 1e3:.2f} CPU -> cyclomech {npy / cy:.0f}x wall, {npc / cyc:.0f}x CPU"
    )


if __name__ == "__main__":
    main()
