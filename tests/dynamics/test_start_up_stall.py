"""Where a motor too weak to start the machine stalls: the start-up's report of the
stop (time and shaft angle, printed to 0.01°) against scipy's DOP853 with an event
at ω = 0 on the same equation, J·φ̈ = M(φ̇) − Q(φ), for a constant inertia, a
linear motor and a load Q = q₀·sin φ that the motor cannot carry over its hump."""

from __future__ import annotations

import math
import re

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.dynamics._shaft import _stop
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

N = 3600
PHI = np.arange(N) * 2.0 * np.pi / N


def _reference(j: float, m0: float, no_load_rpm: float, q0: float) -> tuple[float, float]:
    """(t [s], φ [deg]) where ω falls back to 0, by scipy."""
    w_nl = no_load_rpm * math.pi / 30.0

    def f(_t: float, y: np.ndarray) -> list[float]:
        return [y[1], (m0 * (1.0 - y[1] / w_nl) - q0 * math.sin(y[0])) / j]

    def stop(_t: float, y: np.ndarray) -> float:
        return y[1]

    stop.terminal, stop.direction = True, -1  # type: ignore[attr-defined]
    r = solve_ivp(
        f,
        (0.0, 100.0),
        [0.0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        events=stop,
        first_step=1e-6,
    )
    return float(r.t_events[0][0]), math.degrees(float(r.y_events[0][0][0]))


def _reported(j: float, m0: float, no_load_rpm: float, q0: float) -> tuple[float, float]:
    d = cm.dynamics.Reduced.from_curves(
        np.full(N, j), np.zeros(N), q0 * np.sin(PHI), nominal_rpm=0.5 * no_load_rpm
    )
    with pytest.raises(cm.SolverError, match="cannot start the machine") as e:
        cm.dynamics.start_up(d, cm.dynamics.LinearMotor(m0, no_load_rpm))
    t = re.search(r"at t = ([\d.e+-]+) s", str(e.value))
    phi = re.search(r"shaft angle ([\d.]+)°", str(e.value))
    assert t and phi, str(e.value)
    return float(t.group(1)), float(phi.group(1))


@pytest.mark.parametrize("q0", [15.0, 20.0, 30.0, 45.0])
def test_the_stall_is_where_scipy_puts_it(q0: float) -> None:
    t_ref, phi_ref = _reference(2.0, 10.0, 600.0, q0)
    t, phi = _reported(2.0, 10.0, 600.0, q0)
    assert phi == pytest.approx(phi_ref, abs=0.005 + 1e-4)  # printed to 0.01°
    assert t == pytest.approx(t_ref, rel=1e-3)  # printed to 4 digits


@settings(max_examples=6, deadline=None)
@given(
    j=st.floats(0.2, 20.0),
    ratio=st.floats(1.6, 6.0),  # the hump over the stall torque (it stalls from ~1.4)
)
def test_any_weak_motor_stalls_where_scipy_says(j: float, ratio: float) -> None:
    t_ref, phi_ref = _reference(j, 10.0, 900.0, 10.0 * ratio)
    t, phi = _reported(j, 10.0, 900.0, 10.0 * ratio)
    assert phi == pytest.approx(phi_ref, abs=0.005 + 1e-4)
    assert t == pytest.approx(t_ref, rel=1e-3)


def test_the_stop_is_the_peak_of_the_step_not_its_chord() -> None:
    # φ = t − t²/2 (ω = 1 − t) on a step from 0 to 1.5: the cubic Hermite
    # interpolant is exact; the stop is at t = 1, φ = 1/2 (a chord would give
    # φ = 0.375·2/3 = 0.25).
    t, phi = _stop(np.array([0.0, 1.5]), np.array([0.0, 0.375]), np.array([1.0, -0.5]))
    assert (t, phi) == pytest.approx((1.0, 0.5), abs=1e-15)
    # A step over a cubic: φ = sin-like cubic φ(t) = t − t³/3 (ω = 1 − t²),
    # stop at t = 1, φ = 2/3, from the ends t = 0.5 and 1.25.
    ts = np.array([0.5, 1.25])
    t, phi = _stop(ts, ts - ts**3 / 3.0, 1.0 - ts**2)
    assert (t, phi) == pytest.approx((1.0, 2.0 / 3.0), abs=1e-12)
