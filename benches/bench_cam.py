"""The cam's exact geometry against numpy and the ``mechanism`` package, on 1e6 cam angles.

Group 1: ``Cam.solve`` (s, s′, s″, s‴, pitch curve, profile, pressure angle, radii
of curvature, undercut; one Rust call) against :func:`numpy_solve`: the same closed
forms for a translating offset roller on a cycloidal rise–dwell–return–dwell
program, written with numpy on each segment's slice of the sorted grid (the best
closed form a numpy user writes: no masks, each sine once). Both agree to 1e-12
m (checked by :func:`test_numpy_agrees`).

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

Ratio table (:func:`test_ratio_table`, timed runs only): interleaved rounds of
``Cam.solve`` (new arrays, and ``out=`` a previous result), the numpy peer and
the floors of writing the (N, 14) block once, with reused and with fresh pages.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings and the table (``-s`` prints it)::

    python -m pytest benches/bench_cam.py --benchmark-enable -q -p no:cacheprovider -s
"""

from __future__ import annotations

import importlib.metadata
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import page_states, timed_run

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
    """The translating roller's closed forms with numpy (cycloidal law), the best
    a numpy user writes for a sorted grid: each segment's closed form on its
    contiguous slice (``searchsorted`` on the boundaries; no masks, no gathers),
    each sine and cosine taken once. Any order of angles: an unsorted grid is
    sorted first and the results put back (not timed here: the grid is sorted)."""
    t = np.mod(theta, 2 * math.pi)
    if t.size > 1 and not (t[1:] >= t[:-1]).all():
        order = np.argsort(t)
        out = numpy_solve(t[order])
        back = np.empty_like(order)
        back[order] = np.arange(order.size)
        return {k: v[back] for k, v in out.items()}
    s = np.empty_like(t)
    ds = np.zeros_like(t)
    dds = np.zeros_like(t)
    level = 0.0
    bounds = np.searchsorted(t, [math.radians(a) for _, a, _ in PROGRAM[1:]])
    edges = [0, *bounds.tolist(), t.size]
    for (sign, start, ang), i0, i1 in zip(PROGRAM, edges[:-1], edges[1:], strict=True):
        b, a0 = math.radians(ang), math.radians(start)
        if sign == 0:
            s[i0:i1] = level
            continue
        x = (t[i0:i1] - a0) / b
        w = 2 * math.pi * x
        sw, cw = np.sin(w), np.cos(w)
        h = sign * H
        s[i0:i1] = level + h * (x - sw / (2 * math.pi))
        ds[i0:i1] = h / b * (1 - cw)
        dds[i0:i1] = h / b**2 * 2 * math.pi * sw
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


@pytest.mark.parametrize("step", [97, -89])
def test_numpy_agrees(theta: Array, step: int) -> None:
    k = make_cam().solve(theta[::step])
    ref = numpy_solve(theta[::step])
    np.testing.assert_allclose(k.s, ref["s"], atol=1e-12)
    np.testing.assert_allclose(k.pitch[:, 0], ref["pitch_x"], atol=1e-12)
    np.testing.assert_allclose(k.profile[:, 1], ref["profile_y"], atol=1e-12)
    np.testing.assert_allclose(k.pressure_angle, ref["pressure_angle"], atol=1e-12)
    np.testing.assert_allclose(k.pitch_radius_of_curvature, ref["rho"], rtol=1e-10)
    np.testing.assert_array_equal(k.undercut, ref["undercut"])


def test_ratio_table(request: pytest.FixtureRequest, theta: Array) -> None:
    """Interleaved rounds (medians, wall and CPU), both page states for every
    row: ``reused`` (glibc's heap reuses the freed outputs and temporaries),
    ``fresh`` (``malloc_trim(0)`` before each call: every new array is
    first-touched). ``out=`` keeps its block, so its pages are never fresh.
    Floors: a (N, 14) float64 block written once, new (``np.empty`` + ``fill``)
    and existing (``fill``)."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    cam = make_cam()
    prev = {1: cam.solve(theta), 2: cam.solve(theta)}
    block = np.empty((N, 14))
    tools: dict[str, Callable[[], Any]] = {
        "cyclomech 1 thread": lambda: cam.solve(theta, n_threads=1),
        "cyclomech 1 thread, out=": lambda: cam.solve(theta, n_threads=1, out=prev[1]),
        "cyclomech 2 threads": lambda: cam.solve(theta, n_threads=2),
        "cyclomech 2 threads, out=": lambda: cam.solve(theta, n_threads=2, out=prev[2]),
        "numpy": lambda: numpy_solve(theta),
        "floor: new (N, 14) written": lambda: np.empty((N, 14)).fill(1.0),
        "floor: existing (N, 14) written": lambda: block.fill(1.0),
    }
    for state, t in page_states(tools, 7).items():
        wall, cpu = t["numpy"]
        print(f"\nCam.solve, {N} angles, {state} pages, 7 interleaved rounds (medians)")
        for name, (w, c) in t.items():
            print(
                f"  {name:32s} wall {w * 1e3:6.1f} ms  cpu {c * 1e3:6.1f} ms  "
                f"numpy/this wall {wall / w:5.2f}x  cpu {cpu / c:5.2f}x"
            )


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
