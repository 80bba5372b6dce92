"""The residual vibration of a motion law, R(τ, ζ), against a scipy loop.

``cyclomech.cam.residual_vibration`` over 1e5 values of τ in one Rust call
(exact Duhamel kernel, 1024 + 2048 steps per τ and Richardson extrapolation)
against :func:`scipy_residual`: ``solve_ivp`` (DOP853, rtol 1e-10) of
x'' + 2ζτx' + τ²x = −z''(u) over [0, 1] from rest, one τ at a time, on a subset
of :data:`N_SCIPY` values. Both agree to 1e-7 (checked by
:func:`test_scipy_agrees`). The ratio compares the time per τ.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings (and the per-τ ratio printed at the end)::

    python benches/bench_cam_vibration.py
    python -m pytest benches/bench_cam_vibration.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
import time

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from scipy.integrate import solve_ivp

Array = npt.NDArray[np.float64]
GROUP = "cam residual vibration R(tau), cycloidal, zeta = 0.05"
N = 100_000
N_SCIPY = 20
ZETA = 0.05
LAW = "cycloidal"


def taus(n: int) -> Array:
    return np.linspace(0.5, 100.0, n)


def scipy_residual(tau: Array, zeta: float = ZETA) -> Array:
    """R(τ) per τ by solve_ivp on the cycloidal rise (z'' = 2π sin 2πu)."""
    out = np.empty_like(tau)
    for i, t in enumerate(tau):

        def f(u: float, y: Array, t: float = t) -> list[float]:
            return [
                y[1],
                -2 * zeta * t * y[1] - t * t * y[0] - 2 * math.pi * math.sin(2 * math.pi * u),
            ]

        q, v = solve_ivp(f, (0.0, 1.0), [0.0, 0.0], method="DOP853", rtol=1e-10, atol=1e-14).y[
            :, -1
        ]
        out[i] = math.hypot(q, (v + zeta * t * q) / (t * math.sqrt(1 - zeta * zeta)))
    return out


def test_scipy_agrees() -> None:
    t = taus(N_SCIPY)
    np.testing.assert_allclose(
        cm.cam.residual_vibration(LAW, t, ZETA), scipy_residual(t), rtol=1e-7
    )


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_residual_cyclomech(benchmark, threads: int) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"residual_vibration, {N} tau, n_threads={threads}"
    benchmark.extra_info["items"] = N
    t = taus(N)
    r = benchmark(cm.cam.residual_vibration, LAW, t, ZETA, n_threads=threads)
    assert r.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
def test_residual_scipy(benchmark) -> None:
    benchmark.extra_info["tool"] = "scipy"
    benchmark.extra_info["what"] = f"solve_ivp loop, {N_SCIPY} tau (ratio per tau)"
    benchmark.extra_info["items"] = N_SCIPY
    r = benchmark(scipy_residual, taus(N_SCIPY))
    assert r.shape == (N_SCIPY,)


def _best(f, repeat: int = 3) -> float:  # type: ignore[no-untyped-def]
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    """Time per τ of each and their ratio."""
    big, small = taus(N), taus(N_SCIPY)
    sp = _best(lambda: scipy_residual(small)) / N_SCIPY
    print(f"scipy solve_ivp loop: {sp * 1e3:.3f} ms per tau ({N_SCIPY} tau)")
    for threads in (1, 2):
        cy = _best(lambda th=threads: cm.cam.residual_vibration(LAW, big, ZETA, n_threads=th)) / N
        print(
            f"cyclomech, n_threads={threads}: {cy * 1e6:.2f} us per tau ({N} tau in one call); "
            f"{sp / cy:.0f}x scipy"
        )


if __name__ == "__main__":
    main()
