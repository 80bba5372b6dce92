"""Servo sizing: every motor × gear ratio × machine speed in one call, against numpy.

``cyclomech.servo.size`` checks 100 motors × 50 ratios at 1000 machine speeds with
the program sampled at 3600 angles (the issue's target size) in one Rust call: per
speed, the motor torque of every candidate is T_m = (ã(θ) + J′·b̃(θ))/i with
J′ = (J_motor + J_gear)·i², so the RMS comes from three sums and the peak |T_m| from
the upper envelope of the 2N lines ±(ã + J′·b̃), built once per speed.

The peers use the same structure, as a numpy user would write it:

* :func:`numpy_dense`: ã, b̃ and the three sums broadcast over the speeds; the peak
  as max over θ of |ã + J′·b̃| broadcast over (candidates, θ), one speed at a time
  (chunked to keep the arrays in memory): timed on :data:`N_DENSE` speeds.
* :func:`numpy_hull`: the same, but the peak from the 2-D convex hull of the points
  ±(b̃_k, ã_k) (``scipy.spatial.ConvexHull``: the support function max_k (ã_k + J′b̃_k)
  is reached at a hull vertex), broadcast over the few vertices: every speed.

Both agree with cyclomech to 1e-9 (checked by :func:`test_peers_agree`, outside the
timing); the ratios compare the time per speed. Default test run
(``--benchmark-disable`` in addopts): each benchmark once. For timings::

    python -m pytest benches/bench_servo.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from scipy.spatial import ConvexHull

Array = npt.NDArray[np.float64]
GROUP = "servo sizing, 100 motors x 50 ratios, 3600 angles (per speed)"
N_MOTORS, N_RATIOS, N_SPEEDS, POINTS = 100, 50, 1000, 3600
N_DENSE = 3  # speeds the dense numpy peer is timed on
RPM_TO_RAD_S = 2 * math.pi / 60


class Cycloidal:
    """A cycloidal rise of 0.1 m over 100°, dwell 80°, return over 100°, dwell."""

    def evaluate(self, theta: Array) -> SimpleNamespace:
        h, b = 0.1, math.radians(100.0)
        t = np.asarray(theta)
        s, v, a = (np.zeros_like(t) for _ in range(3))
        for start, sign in ((0.0, 1.0), (math.radians(180.0), -1.0)):
            inside = (t >= start) & (t < start + b)
            x = (t[inside] - start) / b
            v[inside] = sign * h / b * (1 - np.cos(2 * np.pi * x))
            a[inside] = sign * 2 * np.pi * h / b**2 * np.sin(2 * np.pi * x)
        return SimpleNamespace(s=s, v=v, a=a, j=np.zeros_like(t))


def problem(
    n_speeds: int = N_SPEEDS,
) -> tuple[cm.servo.ServoAxis, list[cm.servo.Motor], Array, Array]:
    """The axis (a ball screw with a process force), motors, ratios and speeds."""
    load = cm.servo.LinearLoad(10.0, 0.1, force_n=100.0, efficiency=0.9)
    axis = cm.servo.ServoAxis(Cycloidal(), load, cm.servo.Gearbox(1.0, 0.95, 2e-5), points=POINTS)
    rated = np.geomspace(0.3, 30.0, N_MOTORS)
    motors = [
        cm.servo.Motor(t, 3 * t, 2000, 6000 - 30 * k, 8e-5 * t**1.3, name=f"M{k:03d}")
        for k, t in enumerate(rated)
    ]
    return axis, motors, np.geomspace(0.5, 20.0, N_RATIOS), np.linspace(20.0, 150.0, n_speeds)


def _parts(axis: cm.servo.ServoAxis, motors: list[cm.servo.Motor], rpm: Array) -> SimpleNamespace:
    """What the peers start from: the load shaft's φ′, φ″ and the parts' numbers."""
    k = 2 * math.pi / axis.load.lead_m  # type: ignore[union-attr]
    r = 1 / k
    return SimpleNamespace(
        vel=axis.v * k,
        acc=axis.a * k,
        j_load=axis.load.mass_kg * r * r,  # type: ignore[union-attr]
        t_ext=axis.load.force_n * r,  # type: ignore[union-attr]
        eta=axis.load.efficiency * axis.gearbox.efficiency,  # type: ignore[union-attr]
        jg=axis.gearbox.inertia_kg_m2,
        jm=np.array([m.inertia_kg_m2 for m in motors]),
        peak=np.array([m.peak_torque_nm for m in motors]),
        rated=np.array([m.rated_torque_nm for m in motors]),
        wmax=np.array([m.max_rpm for m in motors]) * RPM_TO_RAD_S,
        w=np.asarray(rpm) * RPM_TO_RAD_S,
        limit=axis.inertia_ratio_limit,
    )


def _load_side(p: SimpleNamespace) -> tuple[Array, Array]:
    """ã (S, N): the load torque with 1/η or η by the power's sign; b̃ = φ″·ω²."""
    w2 = p.w[:, None] ** 2
    t = p.j_load * p.acc[None, :] * w2 + p.t_ext
    a = np.where(t * p.vel[None, :] < 0, t * p.eta, t / p.eta)
    return a, p.acc[None, :] * w2


def _margins(p: SimpleNamespace, ratios: Array, a: Array, b: Array, peak: Array) -> Array:
    """(M, R, 4) smallest margins over the speeds, from ã, b̃ and peak (S, M, R) of
    max_θ |ã + J′b̃|."""
    jp = (p.jm[:, None] + p.jg) * ratios[None, :] ** 2  # (M, R)
    n = a.shape[1]
    saa, sab, sbb = (a * a).sum(1), (a * b).sum(1), (b * b).sum(1)
    q = saa[:, None, None] + jp * (2 * sab[:, None, None] + jp * sbb[:, None, None])
    rms = np.sqrt(np.maximum(q, 0) / n) / ratios
    speed = ratios * p.w[:, None, None] * np.abs(p.vel).max()
    out = np.empty((*jp.shape, 4))
    out[..., 0] = (1 - peak / ratios / p.peak[:, None]).min(0)
    out[..., 1] = (1 - rms / p.rated[:, None]).min(0)
    out[..., 2] = (1 - speed / p.wmax[:, None]).min(0)
    out[..., 3] = 1 - (p.j_load / ratios**2 + p.jg) / p.jm[:, None] / p.limit
    return out


def numpy_dense(p: SimpleNamespace, ratios: Array) -> Array:
    """The peak by broadcasting over (candidates, θ), a speed at a time."""
    a, b = _load_side(p)
    jp = ((p.jm[:, None] + p.jg) * ratios[None, :] ** 2).ravel()
    peak = np.empty((len(p.w), *jp.shape))
    chunk = 500  # candidates at a time: (500, 3600) floats = 14 MB
    for s in range(len(p.w)):
        for c in range(0, jp.size, chunk):
            block = a[s] + jp[c : c + chunk, None] * b[s]
            peak[s, c : c + chunk] = np.abs(block).max(axis=1)
    return _margins(p, ratios, a, b, peak.reshape(len(p.w), len(p.jm), len(ratios)))


def numpy_hull(p: SimpleNamespace, ratios: Array) -> Array:
    """The peak from the convex hull's vertices of the points ±(b̃_k, ã_k)."""
    a, b = _load_side(p)
    jp = ((p.jm[:, None] + p.jg) * ratios[None, :] ** 2).ravel()
    peak = np.empty((len(p.w), *jp.shape))
    for s in range(len(p.w)):
        pts = np.concatenate([np.c_[b[s], a[s]], -np.c_[b[s], a[s]]])
        v = pts[ConvexHull(pts).vertices]
        peak[s] = (v[:, 1][None, :] + jp[:, None] * v[:, 0][None, :]).max(axis=1)
    return _margins(p, ratios, a, b, peak.reshape(len(p.w), len(p.jm), len(ratios)))


def test_peers_agree() -> None:
    axis, motors, ratios, rpm = problem(n_speeds=7)
    got = cm.servo.size(axis, motors, ratios, rpm).margins
    p = _parts(axis, motors, rpm)
    np.testing.assert_allclose(numpy_dense(p, ratios), got, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(numpy_hull(p, ratios), got, rtol=1e-9, atol=1e-9)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_size_cyclomech(benchmark, threads: int) -> None:  # type: ignore[no-untyped-def]
    axis, motors, ratios, rpm = problem()
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = (
        f"servo.size, {N_MOTORS} x {N_RATIOS} x {N_SPEEDS} speeds, n_threads={threads}"
    )
    benchmark.extra_info["items"] = N_SPEEDS
    r = benchmark(cm.servo.size, axis, motors, ratios, rpm, n_threads=threads)
    assert r.margins.shape == (N_MOTORS, N_RATIOS, 4)


@pytest.mark.benchmark(group=GROUP)
def test_size_numpy_dense(benchmark) -> None:  # type: ignore[no-untyped-def]
    axis, motors, ratios, rpm = problem(N_DENSE)
    p = _parts(axis, motors, rpm)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"broadcast over (candidates, angles), {N_DENSE} speeds"
    benchmark.extra_info["items"] = N_DENSE
    r = benchmark(numpy_dense, p, ratios)
    assert r.shape == (N_MOTORS, N_RATIOS, 4)


@pytest.mark.benchmark(group=GROUP)
def test_size_numpy_hull(benchmark) -> None:  # type: ignore[no-untyped-def]
    axis, motors, ratios, rpm = problem()
    p = _parts(axis, motors, rpm)
    benchmark.extra_info["tool"] = "numpy+scipy"
    benchmark.extra_info["what"] = f"ConvexHull per speed, {N_SPEEDS} speeds"
    benchmark.extra_info["items"] = N_SPEEDS
    r = benchmark(numpy_hull, p, ratios)
    assert r.shape == (N_MOTORS, N_RATIOS, 4)
