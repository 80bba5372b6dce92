"""The cam's exact geometry against numpy, on 1e6 cam angles.

``Cam.solve`` (s, s′, s″, s‴, pitch curve, profile, pressure angle, radii of
curvature, undercut; one Rust call) against :func:`numpy_solve`: the same closed
forms for a translating offset roller on a cycloidal rise–dwell–return–dwell
program, written with numpy over masks of the segments. Both agree to 1e-12 m
(checked by :func:`test_numpy_agrees`).

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings::

    python -m pytest benches/bench_cam.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

Array = npt.NDArray[np.float64]
GROUP = "cam.solve, 1e6 angles (translating offset roller, cycloidal)"
N = 1_000_000
RB, RR, E, H = 0.05, 0.012, 0.006, 0.025
# (kind sign, start [deg], angle [deg]): +1 rise, 0 dwell, −1 return.
PROGRAM = ((1, 0.0, 120.0), (0, 120.0, 60.0), (-1, 180.0, 100.0), (0, 280.0, 80.0))


def make_cam() -> cm.cam.Cam:
    kinds = {1: "rise", 0: "dwell", -1: "return"}
    segs = [cm.cam.Segment(kinds[k], ang, H if k else 0.0) for k, _, ang in PROGRAM]
    return cm.cam.Cam(segs, cm.cam.TranslatingRoller(RB, RR, E))


def numpy_solve(theta: Array) -> dict[str, Array]:
    """The translating roller's closed forms with numpy (cycloidal law)."""
    t = np.mod(theta, 2 * math.pi)
    s = np.zeros_like(t)
    ds = np.zeros_like(t)
    dds = np.zeros_like(t)
    level = 0.0
    for sign, start, ang in PROGRAM:
        b, a0 = math.radians(ang), math.radians(start)
        m = (t >= a0) & (t < a0 + b)
        if sign == 0:
            s[m] = level
            continue
        x = (t[m] - a0) / b
        w = 2 * math.pi * x
        h = sign * H
        s[m] = level + h * (x - np.sin(w) / (2 * math.pi))
        ds[m] = h / b * (1 - np.cos(w))
        dds[m] = h / b**2 * 2 * math.pi * np.sin(w)
        level += h
    d = math.sqrt((RB + RR) ** 2 - E**2) + s
    # Fixed frame: T = (d, s′ − e), A = (2s′ − e, s″ − d); cam frame: rotate by −θ.
    tx, ty = d, ds - E
    speed = np.hypot(tx, ty)
    k = tx * (dds - d) - ty * (2 * ds - E)
    rho = -(speed**3) / k
    nx, ny = -ty / speed, tx / speed
    c, sn = np.cos(t), np.sin(t)
    qx, qy = E - RR * nx, d - RR * ny
    return {
        "s": s,
        "pitch_x": E * c + d * sn,
        "pitch_y": -E * sn + d * c,
        "profile_x": qx * c + qy * sn,
        "profile_y": -qx * sn + qy * c,
        "pressure_angle": np.arctan2(ty, tx),
        "rho": rho,
        "undercut": (rho > 0) & (rho < RR),
    }


@pytest.fixture(scope="module")
def theta() -> Array:
    return np.linspace(0.0, 2 * math.pi, N, endpoint=False)


def test_numpy_agrees(theta: Array) -> None:
    k = make_cam().solve(theta[::97])
    ref = numpy_solve(theta[::97])
    np.testing.assert_allclose(k.s, ref["s"], atol=1e-12)
    np.testing.assert_allclose(k.pitch[:, 0], ref["pitch_x"], atol=1e-12)
    np.testing.assert_allclose(k.profile[:, 1], ref["profile_y"], atol=1e-12)
    np.testing.assert_allclose(k.pressure_angle, ref["pressure_angle"], atol=1e-12)
    np.testing.assert_allclose(k.pitch_radius_of_curvature, ref["rho"], rtol=1e-10)
    np.testing.assert_array_equal(k.undercut, ref["undercut"])


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_solve_cyclomech(benchmark, theta: Array, threads: int) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"Cam.solve (all outputs), n_threads={threads}"
    cam = make_cam()
    k = benchmark(cam.solve, theta, n_threads=threads)
    assert k.s.shape == (N,)


@pytest.mark.benchmark(group=GROUP)
def test_solve_numpy(benchmark, theta: Array) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "closed forms over segment masks"
    ref = benchmark(numpy_solve, theta)
    assert ref["s"].shape == (N,)
