"""The periodic steady state of many designs in one call against scipy per design.

``cyclomech.dynamics.steady_states`` (D = 256 flywheels on one reduced machine,
an induction motor through a gear; one Rust call, shooting on ω²(0) with Newton
and a fixed-step RK4 on the 3600 samples) against what a scipy user would
write per design: :func:`scipy_steady` — ``brentq`` on the periodicity
F(y0) = y(2π; y0) − y0 of the same energy-form ODE in φ, each F one
``solve_ivp`` (RK45, rtol 1e-10) with J, J′ and Q interpolated by ``np.interp``.
The two agree on the real δ to 1e-5 (:func:`test_scipy_agrees`, outside the
timing). The issue's target is ≥ 100× per design. A third row, when numba is
installed (the ``[bench]`` extras): :func:`numba_kernel`, cyclomech's own method
(RK4 on the samples, Newton with the sensitivity equation) written in numba, the
designs one after the other — what a user who knew the method would write; it
agrees with cyclomech on δ to 1e-5, its extrema at the nodes only (:func:`test_numba_agrees`).

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings and the ratio table::

    python -m pytest benches/bench_dynamics_steady.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

Array = npt.NDArray[np.float64]
GROUP = "dynamics: periodic steady state per design"
N = 3600
D = 256
PHI = 2 * np.pi * np.arange(N) / N


def machine() -> cm.dynamics.Reduced:
    """A slider-crank-like reduced machine: J with its 2nd harmonic, a load peak."""
    j = 0.2 + 0.05 * np.cos(2 * PHI)
    dj = -0.1 * np.sin(2 * PHI)
    q = 20 + 15 * np.sin(PHI) + 5 * np.sin(3 * PHI)
    return cm.dynamics.Reduced.from_curves(j, dj, q, nominal_rpm=100.0)


MOTOR = cm.dynamics.InductionMotor(1440.0, 1500.0, 2.5, rated_power_w=400.0, ratio=15.0)


def flywheels() -> Array:
    return np.geomspace(0.5, 50.0, D)


def scipy_steady(d: cm.dynamics.Reduced, motor: cm.dynamics.InductionMotor, fw: float) -> float:
    """The real δ of one design by scipy: brentq on the periodicity of y = ω²."""
    j, dj, q = d.inertia_kg_m2 + fw, d.d_inertia, d.load_torque_nm
    ws = motor.synchronous_rpm * math.pi / 30
    mk, sk, i = motor.breakdown_ratio * motor.rated_torque_nm, motor.critical_slip, motor.ratio
    grid = np.append(PHI, 2 * np.pi)

    def at(v: Array, p: float) -> float:
        return float(np.interp(p, grid, np.append(v, v[0])))

    def rhs(p: float, y: Array) -> list[float]:
        w = math.sqrt(y[0])
        s = (ws - i * w) / ws
        m = i * 2 * mk * s * sk / (s * s + sk * sk)
        return [(2 * (m - at(q, p)) - at(dj, p) * y[0]) / at(j, p)]

    def cycle(y0: float) -> Array:
        return solve_ivp(
            rhs, (0, 2 * np.pi), [y0], rtol=1e-10, atol=1e-10, max_step=0.05, t_eval=grid
        )

    def f(y0: float) -> float:
        return float(cycle(y0).y[0, -1] - y0)

    w_no_load = ws / i
    y0 = brentq(f, (0.5 * w_no_load) ** 2, (0.999 * w_no_load) ** 2, xtol=1e-12, rtol=1e-12)
    w = np.sqrt(cycle(y0).y[0])
    t = np.trapezoid(1 / w, grid)
    return float((w.max() - w.min()) / (2 * np.pi / t))


def numba_kernel() -> Any:
    """The steady states' δ of many flywheels, compiled by numba (None without it)."""
    try:
        import numba
    except ImportError:
        return None

    @numba.njit(cache=False)
    def deltas(j, dj, q, fws, mk, ws, sk, i, w_guess):
        n = j.size
        h = 2.0 * 2.0 * np.pi / n
        out = np.empty(fws.size)
        ys = np.empty(n // 2 + 1)
        ts = np.empty(n // 2 + 1)
        for d in range(fws.size):
            y0 = w_guess * w_guess
            for _ in range(60):
                y, t, z = y0, 0.0, 1.0
                for s in range(n // 2):
                    ys[s], ts[s] = y, t
                    ks = np.empty((4, 3))
                    for stage in range(4):
                        k = 2 * s + (0 if stage == 0 else (1 if stage < 3 else 2))
                        k %= n
                        c = 0.0 if stage == 0 else (0.5 * h if stage < 3 else h)
                        yy = y + c * (ks[stage - 1, 0] if stage else 0.0)
                        zz = z + c * (ks[stage - 1, 2] if stage else 0.0)
                        w = np.sqrt(yy)
                        sl = (ws - i * w) / ws
                        den = sl * sl + sk * sk
                        m = i * 2 * mk * sl * sk / den
                        dm = -i * i * 2 * mk * sk * (sk * sk - sl * sl) / (den * den) / ws
                        jj = j[k] + fws[d]
                        ks[stage, 0] = (2 * (m - q[k]) - dj[k] * yy) / jj
                        ks[stage, 1] = 1 / w
                        ks[stage, 2] = (dm / w - dj[k]) / jj * zz
                    y += h / 6 * (ks[0, 0] + 2 * ks[1, 0] + 2 * ks[2, 0] + ks[3, 0])
                    t += h / 6 * (ks[0, 1] + 2 * ks[1, 1] + 2 * ks[2, 1] + ks[3, 1])
                    z += h / 6 * (ks[0, 2] + 2 * ks[1, 2] + 2 * ks[2, 2] + ks[3, 2])
                ys[n // 2], ts[n // 2] = y, t
                f = y - y0
                if abs(f) <= 1e-10 * y0:
                    break
                y0 = min(max(y0 - f / (z - 1), 0.25 * y0), 4 * y0)
            w = np.sqrt(ys)
            out[d] = (w.max() - w.min()) / (2 * np.pi / ts[n // 2])
        return out

    return deltas


def _numba_args(d: cm.dynamics.Reduced, fw: Array) -> tuple[Any, ...]:
    m = MOTOR
    ws = m.synchronous_rpm * math.pi / 30
    mk = m.breakdown_ratio * m.rated_torque_nm
    return (
        d.inertia_kg_m2,
        d.d_inertia,
        d.load_torque_nm,
        fw,
        mk,
        ws,
        m.critical_slip,
        m.ratio,
        0.97 * ws / m.ratio,
    )


def test_numba_agrees() -> None:
    kernel = numba_kernel()
    if kernel is None:
        pytest.skip("numba is not installed (the [bench] extras)")
    d, fw = machine(), flywheels()[::17]
    # cyclomech's δ takes the odd samples too (cubic Hermite); numba's the nodes only.
    ref = cm.dynamics.steady_states(d, MOTOR, fw, tol=1e-12).column("delta")
    np.testing.assert_allclose(kernel(*_numba_args(d, fw)), ref, rtol=1e-5)


def test_scipy_agrees() -> None:
    d = machine()
    b = cm.dynamics.steady_states(d, MOTOR, flywheels()[::85])
    for fw, delta in zip(flywheels()[::85], b.column("delta"), strict=True):
        assert scipy_steady(d, MOTOR, float(fw)) == pytest.approx(delta, rel=1e-5)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_steady_cyclomech(benchmark, threads: int | None) -> None:
    d, fw = machine(), flywheels()
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"steady_states, {D} designs in one call, {where} (per design)"
    benchmark.extra_info["items"] = D  # the ratio table compares per design
    b = benchmark(cm.dynamics.steady_states, d, MOTOR, fw, n_threads=threads)
    assert b.ok.all()


@pytest.mark.benchmark(group=GROUP)
def test_steady_numba(benchmark) -> None:
    kernel = numba_kernel()
    if kernel is None:
        pytest.skip("numba is not installed (the [bench] extras)")
    d, fw = machine(), flywheels()
    args = _numba_args(d, fw)
    kernel(*args)  # compile outside the timing
    benchmark.extra_info["tool"] = "numba"
    benchmark.extra_info["what"] = f"the same method, njit, {D} designs in a loop (per design)"
    benchmark.extra_info["items"] = D
    out = benchmark(kernel, *args)
    assert np.isfinite(out).all()


@pytest.mark.benchmark(group=GROUP)
def test_steady_scipy(benchmark) -> None:
    d = machine()
    benchmark.extra_info["tool"] = "scipy"
    benchmark.extra_info["what"] = "brentq + solve_ivp (RK45, rtol 1e-10), 1 design"
    delta = benchmark(scipy_steady, d, MOTOR, 5.0)
    assert 0 < delta < 1
