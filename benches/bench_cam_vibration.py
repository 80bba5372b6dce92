"""The residual vibration of a motion law, R(τ, ζ), against numpy's closed form.

``cyclomech.cam.residual_vibration`` over 1e5 values of τ in one Rust call (the
cycloidal rise's closed form in SIMD lanes; every built-in law has one, issue 37)
against the peers a numpy user would write for the cycloidal rise:

- :func:`numpy_residual`, the best of them: the closed form
  R = 4π²·√[((1 − e)² + 4e·sin²(ω_d/2)) / |λ² + 4π²|²] / ω_d (e = e^{−ζτ},
  λ = −ζτ + iω_d) in real arithmetic, in place (no temporaries beyond three
  arrays); measured 2–3× faster than the same formula written with complex
  numbers (``np.expm1`` of a complex array) or with fresh temporaries, which is
  why it is the peer;
- :func:`scipy_residual`, ``solve_ivp`` (DOP853, rtol 1e-10) of
  x'' + 2ζτx' + τ²x = −z''(u) from rest, one τ at a time, on a subset of
  :data:`N_SCIPY` values (the general solver a user without the closed form
  would reach for; a second, much slower peer).

All agree (checked before timing: numpy to 1e-12 relative, scipy to 1e-7).

The output is 0.8 MB (1e5 float64): fresh pages cost little next to the
arithmetic, and neither side writes into a reused buffer.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings (one thread, interleaved rounds, medians and the ratios of one run)::

    taskset -c 1 python benches/bench_cam_vibration.py
    python -m pytest benches/bench_cam_vibration.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).parent))
from _timing import interleaved

Array = npt.NDArray[np.float64]
GROUP = "cam residual vibration R(tau), cycloidal, zeta = 0.05"
N = 100_000
N_SCIPY = 20
ZETA = 0.05
LAW = "cycloidal"
FOUR_PI2 = 4 * math.pi**2


def taus(n: int) -> Array:
    return np.linspace(0.5, 100.0, n)


def numpy_residual(tau: Array, zeta: float = ZETA) -> Array:
    """R(τ) of the cycloidal rise, vectorised numpy, in place (see the module docs)."""
    c = math.sqrt(1 - zeta * zeta)
    wd = tau * c
    e = np.exp(tau * -zeta)
    num = np.sin(wd * 0.5)
    num *= num
    num *= 4 * e
    np.subtract(1.0, e, out=e)
    e *= e
    num += e
    # |λ² + 4π²|² = (ζ²τ² − ω_d² + 4π²)² + (2ζτω_d)² = (τ²(ζ² − c²) + 4π²)² + 4ζ²c²τ⁴.
    t2 = tau * tau
    re = t2 * (zeta * zeta - c * c)
    re += FOUR_PI2
    re *= re
    t2 *= t2
    t2 *= 4 * zeta * zeta * c * c
    re += t2
    num /= re
    np.sqrt(num, out=num)
    num /= wd
    num *= FOUR_PI2
    return num


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


def test_peers_agree() -> None:
    t = taus(N_SCIPY)
    np.testing.assert_allclose(
        cm.cam.residual_vibration(LAW, t, ZETA), scipy_residual(t), rtol=1e-7
    )
    big = taus(N)
    np.testing.assert_allclose(
        cm.cam.residual_vibration(LAW, big, ZETA, n_threads=1), numpy_residual(big), rtol=1e-12
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
def test_residual_numpy(benchmark) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"closed form in place, {N} tau"
    benchmark.extra_info["items"] = N
    r = benchmark(numpy_residual, taus(N))
    assert r.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
def test_residual_scipy(benchmark) -> None:
    benchmark.extra_info["tool"] = "scipy"
    benchmark.extra_info["what"] = f"solve_ivp loop, {N_SCIPY} tau (ratio per tau)"
    benchmark.extra_info["items"] = N_SCIPY
    r = benchmark(scipy_residual, taus(N_SCIPY))
    assert r.shape == (N_SCIPY,)


def main() -> None:
    """Time per τ of each (one thread, interleaved rounds) and the ratios."""
    test_peers_agree()
    big, small = taus(N), taus(N_SCIPY)
    med = interleaved(
        {
            "cyclomech": lambda: cm.cam.residual_vibration(LAW, big, ZETA, n_threads=1),
            "numpy": lambda: numpy_residual(big),
        },
        rounds=31,
    )
    sp = interleaved({"scipy": lambda: scipy_residual(small)}, rounds=3)["scipy"][0] / N_SCIPY
    cy, npy = med["cyclomech"][0] / N, med["numpy"][0] / N
    cyc, npc = med["cyclomech"][1] / N, med["numpy"][1] / N
    print(f"cyclomech, 1 thread: {cy * 1e9:.1f} ns per tau wall, {cyc * 1e9:.1f} CPU ({N} tau)")
    print(
        f"numpy closed form:   {npy * 1e9:.1f} ns per tau wall, {npc * 1e9:.1f} CPU "
        f"-> cyclomech {npy / cy:.2f}x wall, {npc / cyc:.2f}x CPU"
    )
    print(f"scipy solve_ivp:     {sp * 1e6:.0f} us per tau -> cyclomech {sp / cy:.0f}x")
    for law in cm.motion.NAMES:
        t = interleaved(
            {law: lambda law=law: cm.cam.residual_vibration(law, big, ZETA, n_threads=1)}, 7
        )
        wall, cpu = (v / N * 1e9 for v in t[law])
        print(f"  {law:20s} {wall:7.1f} ns per tau wall, {cpu:7.1f} CPU")


if __name__ == "__main__":
    main()
