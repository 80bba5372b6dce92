"""The cam's exact geometry against numpy and the ``mechanism`` package, on 1e6 cam angles.

Group 1: ``Cam.solve`` (s, s′, s″, s‴, pitch curve, profile, pressure angle, radii
of curvature, undercut; one Rust call) against :func:`numpy_solve`: the same closed
forms for a translating offset roller on a cycloidal rise–dwell–return–dwell
program, written with numpy over masks of the segments. Both agree to 1e-12 m
(checked by :func:`test_numpy_agrees`).

Group 2: the cam profile coordinates of the PyPI package ``mechanism`` (Gabe
Morris; ``pip install mechanism``) on the same program. Its cams are radial
(zero offset) and its "profile" is the polar curve (R + s(θ))·e^(−iθ): for R =
R_b + r_r that is the pitch curve of a radial roller follower, which
``Cam.solve`` gives (with every other output) for ``TranslatingRoller(R_b, r_r,
0)``; the coordinates agree to 1e-12 m (checked by
:func:`test_mechanism_agrees`, on mechanism's own angle grid). mechanism computes
at construction the displacement of all three of its laws (naive, harmonic,
cycloidal) over its grid, so its timed call is the construction plus
``cycloidal.get_profile``: what it takes to get the coordinates. The group skips,
with the reason printed, when mechanism is not installed.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings::

    python -m pytest benches/bench_cam.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import importlib.metadata
import math
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

Array = npt.NDArray[np.float64]
GROUP = "cam.solve, 1e6 angles (translating offset roller, cycloidal)"
GROUP_PROFILE = "cam profile coordinates, 1e6 angles (radial roller, cycloidal)"
N = 1_000_000
RB, RR, E, H = 0.05, 0.012, 0.006, 0.025
# (kind sign, start [deg], angle [deg]): +1 rise, 0 dwell, −1 return.
PROGRAM = ((1, 0.0, 120.0), (0, 120.0, 60.0), (-1, 180.0, 100.0), (0, 280.0, 80.0))


def make_cam(offset: float = E) -> cm.cam.Cam:
    kinds = {1: "rise", 0: "dwell", -1: "return"}
    segs = [cm.cam.Segment(kinds[k], ang, H if k else 0.0) for k, _, ang in PROGRAM]
    return cm.cam.Cam(segs, cm.cam.TranslatingRoller(RB, RR, offset))


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


def _mechanism() -> Any:
    """The ``mechanism`` package, or a skip whose reason the run prints (-rs)."""
    try:
        import mechanism
    except ImportError as e:  # pragma: no cover - depends on the environment
        pytest.skip(f"mechanism is not installed (pip install mechanism): {e}")
    return mechanism


def mechanism_profile(mech: Any) -> tuple[Any, Array, Array]:
    """mechanism's cam on PROGRAM (radial) and its profile at R = R_b + r_r: the
    pitch curve. Returns (cam, x, y)."""
    names = {1: "Rise", -1: "Fall"}
    motion = [(names[k], H, ang) if k else ("Dwell", ang) for k, _, ang in PROGRAM]
    cam = mech.Cam(motion=motion, degrees=True, h=2 * math.pi / N)
    x, y = cam.cycloidal.get_profile(RB + RR, cam.thetas_r)
    return cam, x, y


def mechanism_grid() -> Array:
    """mechanism's own angle grid for N points (np.arange with step 2π/N)."""
    return np.arange(0, 2 * np.pi, 2 * math.pi / N)


def test_mechanism_agrees() -> None:
    mech = _mechanism()
    cam, x, y = mechanism_profile(mech)
    np.testing.assert_array_equal(cam.thetas, mechanism_grid())
    k = make_cam(offset=0.0).solve(cam.thetas)
    # mechanism's frame: x along the follower at θ = 0, rotating by −θ; ours: the
    # follower along +y. The same curve: (x, y) = (pitch_y, −pitch_x).
    np.testing.assert_allclose(x, k.pitch[:, 1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(y, -k.pitch[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(cam.cycloidal.S, k.s, rtol=0, atol=1e-12)


@pytest.mark.benchmark(group=GROUP_PROFILE)
@pytest.mark.parametrize("threads", [1, 2])
def test_profile_cyclomech(benchmark, threads: int) -> None:
    _mechanism()
    theta = mechanism_grid()
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"Cam.solve (all outputs), n_threads={threads}"
    cam = make_cam(offset=0.0)
    k = benchmark(cam.solve, theta, n_threads=threads)
    assert k.pitch.shape == (theta.size, 2)


@pytest.mark.benchmark(group=GROUP_PROFILE)
def test_profile_mechanism(benchmark) -> None:
    mech = _mechanism()
    benchmark.extra_info["tool"] = "mechanism"
    version = importlib.metadata.version("mechanism")
    benchmark.extra_info["what"] = f"mechanism {version} Cam(...) + cycloidal.get_profile"
    _, x, _ = benchmark(mechanism_profile, mech)
    assert x.size == N
