"""The cam's smallest phase angles against a scipy ``brentq`` loop.

``Cam.min_phase_angles``: the pressure angle, undercut and Hertz stress bounds (and
jump) of 10 rises and returns at 10 000 speeds in one Rust call, against what a
user writes without it: the same rule (scan β down from 360° in steps of 0.7, then
the crossing) with ``scipy.optimize.brentq`` per (segment, speed) on the worst
value over the segment sampled densely with numpy (2001 points), the translating
roller's closed forms written here. The speed-free criteria (pressure angle,
undercut) are searched once per segment by both, so the per-speed stress roots
are what is timed; the peer runs on a subset of speeds and its time per root is
extrapolated. Their bounds agree to 1e-4 relative (the dense sample's worst value
is at most 1e-5 under the exact one: checked outside the timing).

Default test run (``--benchmark-disable`` in addopts): each benchmark once, on
fewer speeds. For timings::

    CYCLOMECH_BENCH_FULL=1 python -m pytest benches/bench_cam_bounds.py \\
        --benchmark-enable -q -p no:cacheprovider -s
"""

from __future__ import annotations

import math
import os
import time

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from scipy.optimize import brentq

Array = npt.NDArray[np.float64]
GROUP = "cam.min_phase_angles: 10 segments x speeds, stress per speed"
FULL = os.environ.get("CYCLOMECH_BENCH_FULL") == "1"
N_SPEEDS = 10_000 if FULL else 500
PEER_SPEEDS = 20 if FULL else 4
RB, RR, H = 0.05, 0.012, 0.006
MASS, RATE, PRELOAD = 2.0, 5000.0, 100.0
WIDTH, E, NU, LIMIT = 0.01, 2.1e11, 0.3, 8e8
ALPHA = math.radians(30.0)
CONTACT = cm.cam.Contact(WIDTH, E, NU, E, NU)
LOADS = cm.cam.FollowerLoads(MASS, RATE, PRELOAD)
# 20 segments of 18°: rise, dwell, return, dwell, ... (10 bound segments).
KINDS = ["rise", "dwell", "return", "dwell"] * 5
X = np.linspace(0.0, 1.0, 2001)


def make_cam() -> cm.cam.Cam:
    segs = [cm.cam.Segment(k, 18.0, 0.0 if k == "dwell" else H) for k in KINDS]
    return cm.cam.Cam(segs, cm.cam.TranslatingRoller(RB, RR))


def speeds() -> Array:
    return np.linspace(100.0, 1500.0, N_SPEEDS)


@np.errstate(divide="ignore", invalid="ignore")
def numpy_worst(seg: int, beta: float, omega: float) -> tuple[float, float, float]:
    """(max |φ|/[α], max r_r/ρ_p on the convex side, max σ_H/[σ_H]) over segment
    ``seg`` at angle ``beta`` [rad] and speed ``omega`` [rad/s], numpy on 2001
    points: the translating roller's closed forms (cycloidal law)."""
    s0 = H if KINDS[seg] == "return" else 0.0
    h = H if KINDS[seg] == "rise" else -H
    w = 2 * math.pi * X
    s = s0 + h * (X - np.sin(w) / (2 * math.pi))
    ds = h / beta * (1 - np.cos(w))
    dds = h / beta**2 * 2 * math.pi * np.sin(w)
    d = RB + RR + s
    # Pitch point C = (0, d) in the fixed frame: T = C′ − JC = (d, s′), A = C″ − 2JC′ − C.
    tx, ty = d, ds
    ax, ay = 2 * ds, dds - d
    speed = np.hypot(tx, ty)
    kappa_p = -(tx * ay - ty * ax) / speed**3  # + convex
    phi = np.arctan2(ty, tx)
    q = MASS * dds * omega**2 + RATE * s + PRELOAD
    n = q / np.cos(phi)
    kappa = 1 / RR + kappa_p / (1 - RR * kappa_p)  # 1/r_r + 1/(ρ_p − r_r)
    c = 2 * (1 - NU**2) / E
    p = np.clip(n, 0, None) * kappa / (math.pi * WIDTH * c)
    # An undercut profile (κ < 0) carries no Hertz contact: a violation.
    sigma = np.sqrt(np.where(p >= 0, p, np.inf))
    undercut = float(np.max(RR * kappa_p))
    return (
        float(np.abs(phi).max() / ALPHA),
        undercut,
        # The rule: no Hertz contact on an undercut profile (violated).
        float(sigma.max() / LIMIT) if undercut < 1.0 else math.inf,
    )


def peer_root(g) -> float:  # type: ignore[no-untyped-def]
    """The rule with brentq: scan down from 2π by 0.7 to the first violation."""
    hi = 2 * math.pi
    if not g(hi) <= 1.0:
        return math.nan
    while hi * 0.7 >= 2 * math.pi * 1e-6:
        lo = hi * 0.7
        if not g(lo) <= 1.0:
            return brentq(lambda b: g(b) - 1.0, lo, hi, xtol=1e-15, rtol=1e-13)
        hi = lo
    return 0.0


def peer(rpm: Array) -> Array:
    """(speeds, 10, 3) bounds [deg]: pressure angle, undercut, stress."""
    out = np.zeros((rpm.size, 10, 3))
    bound = [i for i, k in enumerate(KINDS) if k != "dwell"]
    for j, seg in enumerate(bound):
        p = peer_root(lambda b, seg=seg: numpy_worst(seg, b, 0.0)[0])
        u = peer_root(lambda b, seg=seg: numpy_worst(seg, b, 0.0)[1])
        out[:, j, 0], out[:, j, 1] = p, u
        for i, n in enumerate(rpm):
            w = n * 2 * math.pi / 60
            st = peer_root(lambda b, seg=seg, w=w: numpy_worst(seg, b, w)[2])
            # Where it holds right above the undercut bound, the undercut binds: 0.
            out[i, j, 2] = 0.0 if st <= u * (1 + 1e-9) else st
    return np.degrees(out)


def cyclomech_bounds(rpm: Array, threads: int | None) -> Array:
    m = make_cam().min_phase_angles(
        rpm, loads=LOADS, contact=CONTACT, max_stress=LIMIT, n_threads=threads
    )
    return m.angle_deg[:, :, [0, 1, 3]]


def test_the_peer_agrees() -> None:
    n = speeds()[:: max(1, N_SPEEDS // PEER_SPEEDS)][:PEER_SPEEDS]
    ours, ref = cyclomech_bounds(n, None), peer(n)
    np.testing.assert_allclose(ours, ref, rtol=1e-4)
    assert np.all(ours >= ref * (1 - 1e-12))  # the exact worst value is the larger


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_min_phase_angles_cyclomech(benchmark, threads: int | None) -> None:
    n = speeds()
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else f"{threads} thread"
    benchmark.extra_info["what"] = f"10 segments x {n.size} speeds, one call, {where}"
    benchmark.extra_info["items"] = 10 * n.size
    out = benchmark(cyclomech_bounds, n, threads)
    assert out.shape == (n.size, 10, 3)


@pytest.mark.benchmark(group=GROUP)
def test_min_phase_angles_scipy(benchmark) -> None:
    n = speeds()[:PEER_SPEEDS]
    benchmark.extra_info["tool"] = "scipy brentq loop"
    benchmark.extra_info["what"] = f"10 segments x {n.size} speeds (ratio per root)"
    benchmark.extra_info["items"] = 10 * n.size
    out = benchmark(peer, n)
    assert out.shape == (n.size, 10, 3)


def test_print_ratio() -> None:
    """One run, same process: time per stress root, and the ratio."""
    n = speeds()
    t = time.perf_counter()
    cyclomech_bounds(n, 1)
    ours1 = (time.perf_counter() - t) / (n.size * 10)
    t = time.perf_counter()
    cyclomech_bounds(n, None)
    ours = (time.perf_counter() - t) / (n.size * 10)
    sub = n[:PEER_SPEEDS]
    t = time.perf_counter()
    peer(sub)
    theirs = (time.perf_counter() - t) / (sub.size * 10)
    print(
        f"\nper (segment, speed): cyclomech {ours1 * 1e6:.1f} µs (1 thread), "
        f"{ours * 1e6:.1f} µs (all cores); scipy brentq loop {theirs * 1e6:.0f} µs; "
        f"ratio {theirs / ours1:.0f}x (1 thread), {theirs / ours:.0f}x (all cores)"
    )
    assert ours > 0 and theirs > 0
