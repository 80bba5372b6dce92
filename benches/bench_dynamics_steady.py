"""The periodic steady state of many designs in one call against scipy per design.

``cyclomech.dynamics.steady_states`` (D = 256 flywheels on one reduced machine,
an induction motor through a gear; one Rust call, shooting on ω²(0) with Newton
and a fixed-step RK4 on the 3600 samples) against what a scipy user would
write per design: :func:`scipy_steady` — ``brentq`` on the periodicity
F(y0) = y(2π; y0) − y0 of the same energy-form ODE in φ, each F one
``solve_ivp`` (RK45, rtol 1e-10) with J, J′ and Q interpolated by ``np.interp``.
The two agree on the real δ to 1e-6 (:func:`test_scipy_agrees`, outside the
timing). The issue's target is ≥ 100× per design.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings and the ratio table::

    python -m pytest benches/bench_dynamics_steady.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math

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
def test_steady_scipy(benchmark) -> None:
    d = machine()
    benchmark.extra_info["tool"] = "scipy"
    benchmark.extra_info["what"] = "brentq + solve_ivp (RK45, rtol 1e-10), 1 design"
    delta = benchmark(scipy_steady, d, MOTOR, 5.0)
    assert 0 < delta < 1
