"""The residual vibration of a motion law, R(τ, ζ), against numpy's closed forms.

``cyclomech.cam.residual_vibration`` over 1e5 values of τ in one Rust call (every
built-in law's closed form in SIMD lanes: the cycloidal rise's own real form,
the other five the pieces' sum with per-law constants, issue 37 row 1) against
the peers a numpy user would write:

- for each law, its closed form derived by hand from the textbook z''
  (``tests/cam/residual_peers.py``, shared with the tests that check it against
  scipy): real arithmetic on float64 arrays, vectorised over τ, in place where
  it saves a temporary, one ``exp`` and one ``cos``/``sin`` pair per τ (the
  modified laws' powers of e^{λ/8} by products, cheaper than more
  transcendental calls). For the cycloidal rise this real, in-place form
  measured 2–3× faster than the same formula with complex arrays (``np.expm1``
  of a complex array) or with fresh temporaries, which is why the peers are
  written so;
- :func:`scipy_residual`, ``solve_ivp`` (DOP853, rtol 1e-10) of
  x'' + 2ζτx' + τ²x = −z''(u) from rest for the cycloidal rise, one τ at a
  time, on a subset of :data:`N_SCIPY` values (the general solver a user
  without the closed form would reach for; a second, much slower peer).

All agree (checked before timing: each numpy peer to 1e-10 relative where the
peer is well conditioned — τ ≥ 2 for 3-4-5 and τ ≥ 4 for 4-5-6-7, whose sums
cancel below — and within 1e-11 of R's envelope everywhere there; scipy to 1e-7).

The output is 0.8 MB (1e5 float64), and each numpy peer's temporaries as much:
both sides allocate alike, and the run is printed in both page states
(``_timing.page_states``: ``reused``, the heap handing freed pages back, and
``fresh``, ``malloc_trim(0)`` before every call so that each call's new arrays
are first touched in it).

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
sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "cam"))
import residual_peers as peers
from _timing import interleaved, page_states

Array = npt.NDArray[np.float64]
GROUP = "cam residual vibration R(tau), zeta = 0.05"
N = 100_000
N_SCIPY = 20
ZETA = 0.05
LAW = "cycloidal"
LAWS = tuple(peers.PEERS)


def taus(n: int) -> Array:
    return np.linspace(0.5, 100.0, n)


def numpy_residual(tau: Array, zeta: float = ZETA) -> Array:
    """R(τ) of the cycloidal rise, vectorised numpy, in place (``residual_peers``)."""
    return peers.cycloidal(tau, zeta)


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


def check_peers(big: Array) -> None:
    """Every numpy peer against cyclomech (module docs), before any timing."""
    for law in LAWS:
        got = cm.cam.residual_vibration(law, big, ZETA, n_threads=1)
        want = peers.PEERS[law](big, ZETA)
        ok = big >= peers.TAU_FROM.get(law, 0.0)
        np.testing.assert_allclose(got[ok], want[ok], rtol=1e-10, err_msg=law)


def test_peers_agree() -> None:
    t = taus(N_SCIPY)
    np.testing.assert_allclose(
        cm.cam.residual_vibration(LAW, t, ZETA), scipy_residual(t), rtol=1e-7
    )
    check_peers(taus(N))


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("threads", [1, 2])
def test_residual_cyclomech(benchmark, law: str, threads: int) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"residual_vibration {law}, {N} tau, n_threads={threads}"
    benchmark.extra_info["items"] = N
    t = taus(N)
    r = benchmark(cm.cam.residual_vibration, law, t, ZETA, n_threads=threads)
    assert r.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("law", LAWS)
def test_residual_numpy(benchmark, law: str) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"{law} closed form in place, {N} tau"
    benchmark.extra_info["items"] = N
    r = benchmark(peers.PEERS[law], taus(N), ZETA)
    assert r.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
def test_residual_scipy(benchmark) -> None:
    benchmark.extra_info["tool"] = "scipy"
    benchmark.extra_info["what"] = f"solve_ivp loop, {N_SCIPY} tau (ratio per tau)"
    benchmark.extra_info["items"] = N_SCIPY
    r = benchmark(scipy_residual, taus(N_SCIPY))
    assert r.shape == (N_SCIPY,)


def main() -> None:
    """Time per τ of each law on both sides (one thread; one interleaved run over
    all twelve tools in each page state) and the ratios."""
    big, small = taus(N), taus(N_SCIPY)
    test_peers_agree()
    tools = {}
    for law in LAWS:
        tools[f"cyclomech {law}"] = lambda law=law: cm.cam.residual_vibration(
            law, big, ZETA, n_threads=1
        )
        tools[f"numpy {law}"] = lambda law=law: peers.PEERS[law](big, ZETA)
    states = page_states(tools, rounds=31)
    sp = interleaved({"scipy": lambda: scipy_residual(small)}, rounds=3)["scipy"][0] / N_SCIPY
    for state, med in states.items():
        print(
            f"\nR(tau, zeta = {ZETA}), {N} tau in [0.5, 100], one thread, ns per tau,"
            f" {state} pages (31 rounds)"
        )
        print(
            f"{'law':20s} {'cyclomech':>10s} {'numpy':>8s} {'ratio':>7s} |"
            f" {'cpu: cm':>8s} {'numpy':>8s} {'ratio':>7s}"
        )
        for law in LAWS:
            (cw, cc), (nw, nc) = med[f"cyclomech {law}"], med[f"numpy {law}"]
            print(
                f"{law:20s} {cw / N * 1e9:10.1f} {nw / N * 1e9:8.1f} {nw / cw:6.2f}x |"
                f" {cc / N * 1e9:8.1f} {nc / N * 1e9:8.1f} {nc / cc:6.2f}x"
            )
    cy = states["reused"][f"cyclomech {LAW}"][0] / N
    print(f"scipy solve_ivp (cycloidal): {sp * 1e6:.0f} us per tau -> cyclomech {sp / cy:.0f}x")


if __name__ == "__main__":
    main()
