"""The main shaft's forward dynamics: `_shaft` part of :mod:`cyclomech.dynamics`
(its door). The kernels are in ``rust/core/src/dynamics/shaft.rs`` (the method
and its error are described there and in the door's docstring)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import (
    count,
    finite_number,
    instance,
    instances,
    positive,
    threads_arg,
    tolerance,
)
from .._errors import CyclomechWarning, InputError, SolverError
from .._units import RAD_PER_S_PER_RPM
from ._motor import ConstantTorque, InductionMotor, LinearMotor, Motor, TableMotor, pack
from ._reduced import Reduced

__all__ = [
    "STEADY_COLUMNS",
    "FlywheelSizing",
    "StartUp",
    "SteadyBatch",
    "SteadyState",
    "size_flywheel",
    "start_up",
    "steady_state",
    "steady_states",
]

Array = npt.NDArray[np.float64]

#: The columns of :func:`steady_states`, as the kernel orders them.
STEADY_COLUMNS: tuple[str, ...] = tuple(_core.DYNAMICS_STEADY_COLUMNS)
_STATUS: tuple[str, ...] = tuple(_core.DYNAMICS_STEADY_STATUS)


#: The largest net work over a periodic cycle, relative to the work of the load and
#: the motor: a steady state must balance them (the kinetic energy returns). The
#: discretisation's own error is ~1e-7 of it, ~1e-4 where a gear's efficiency kinks
#: the motor's torque.
WORK_BALANCE = 1e-3


def _check_work(d: Reduced, motor: Motor, motor_torque: Array) -> None:
    """Refuse a "periodic" speed whose cycle does not balance the motor's work and the
    load's: a flywheel so large that the speed hardly changes over a cycle passes the
    periodicity test while the machine still speeds up or slows down (a constant
    torque that is not the mean load)."""
    m = np.asarray(motor_torque, dtype=float)
    g = np.where(m >= 0, motor.ratio * motor.efficiency, motor.ratio / motor.efficiency)
    shaft = g * m
    q = d.load_torque_nm
    net = float(np.mean(shaft - q))
    scale = float(np.mean(np.abs(q)) + np.mean(np.abs(shaft)))
    if scale > 0 and abs(net) > WORK_BALANCE * scale:
        raise SolverError(
            f"no periodic steady state: over a cycle the motor's torque on the shaft "
            f"{'exceeds' if net > 0 else 'falls short of'} the load's by {abs(net):.4g} N·m "
            f"on average ({abs(net) / scale:.2g} of their scale): the machine "
            f"{'speeds up' if net > 0 else 'slows down'} cycle after cycle (a constant "
            "torque must equal the mean load torque)"
        )


def _motor_against_load(d: Reduced, motor: Motor) -> str:
    """The motor's largest torque on the shaft against the load's mean and peak
    torque at the nominal speed, and what to change: the reason a motor cannot
    drive the machine, in numbers."""
    if isinstance(motor, InductionMotor):
        what, most = "breakdown torque M_k", motor.breakdown_ratio * motor.rated_torque_nm
    elif isinstance(motor, LinearMotor):
        what, most = "stall torque", motor.stall_torque_nm
    elif isinstance(motor, ConstantTorque):
        what, most = "torque", motor.torque
    elif isinstance(motor, TableMotor):
        what, most = "largest torque of its table", float(np.max(motor.torque))
    else:  # pragma: no cover - every motor is one of the four
        return ""
    shaft = most * motor.ratio * motor.efficiency
    st = d.torque().stats(d.nominal_rpm, 0.5)
    mean, peak = float(st.mean_torque_nm), float(st.peak_torque_nm)
    verdict = (
        "below the load's mean: it cannot keep the machine turning at any flywheel"
        if shaft < mean
        else "above the load's mean, yet no flywheel kept a periodic speed (the motor "
        "slows past its largest torque within the cycle)"
    )
    return (
        f"the motor's {what} {most:.4g} N·m is {shaft:.4g} N·m on the main shaft "
        f"(× gear ratio {motor.ratio:g} × efficiency {motor.efficiency:g}), {verdict}; the "
        f"load at {d.nominal_rpm:g} rpm is {mean:.4g} N·m mean, {peak:.4g} N·m peak: choose "
        "a larger motor or a larger gear ratio"
    )


def _flywheel(value: Any) -> float:
    return finite_number("flywheel_kg_m2", value, "[kg·m²]", low=0.0)


def _curves(d: Reduced) -> dict[str, Any]:
    instance("d", d, Reduced)
    return {
        "j": np.ascontiguousarray(d.inertia_kg_m2, dtype=np.float64),
        "dj": np.ascontiguousarray(d.d_inertia, dtype=np.float64),
        "q": np.ascontiguousarray(d.load_torque_nm, dtype=np.float64),
    }


def _constant(d: Reduced, motor: Motor, flywheel: float) -> float:
    """The constant inertia on the shaft [kg·m²]: the flywheel and the rotor; an
    InputError naming ``flywheel_kg_m2`` when the machine has no inertia at all."""
    extra = flywheel + motor.shaft_inertia_kg_m2
    if not (d.inertia_kg_m2 + extra > 0).all():
        raise InputError(
            f"flywheel_kg_m2 = {flywheel!r}: the machine has no inertia at some angle (no masses "
            "there, no flywheel, no rotor): give a flywheel_kg_m2 > 0 or the motor's rotor_kg_m2"
        )
    return extra


@dataclass(frozen=True)
class SteadyState:
    """The periodic steady state of the main shaft under a motor.

    Built by :func:`steady_state`; each parameter is kept as the attribute of the
    same name.

    Parameters
    ----------
    theta_deg : ndarray of float, shape (N,)
        The cycle angles φ [deg].
    omega : ndarray of float, shape (N,)
        The shaft speed ω(φ) [rad/s].
    time_s : ndarray of float, shape (N,)
        The time from φ = 0 [s].
    motor_torque_nm : ndarray of float, shape (N,)
        The motor's torque on its own shaft [N·m].
    period_s : float
        The cycle's duration T [s].
    mean_rpm : float
        The time-mean speed 60/T [rpm].
    speed_fluctuation : float
        The real δ = (ω_max − ω_min)/ω_mean, ω_mean = 2π/T.
    peak_motor_torque_nm, lowest_motor_torque_nm : float
        The motor's largest and lowest torque over the cycle [N·m].
    rms_motor_torque_nm : float
        The motor's RMS torque over time [N·m]: the current proxy (a DC motor's
        current, and a motor's heating, follow it).
    flywheel_kg_m2 : float
        The flywheel [kg·m²].
    constant_inertia_kg_m2 : float
        The flywheel plus the rotor reduced to the shaft [kg·m²].
    iterations : int
        Newton's shots.
    residual : float
        |ω²(2π) − ω²(0)|/ω²(0) of the last shot.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.radians(np.arange(0.0, 360.0, 0.1))
    >>> d = cm.dynamics.Reduced.from_curves(np.zeros(3600), np.zeros(3600),
    ...                                     5 + 3 * np.sin(phi), nominal_rpm=95.0)
    >>> s = cm.dynamics.steady_state(d, cm.dynamics.LinearMotor(10.0, 200.0),
    ...                              flywheel_kg_m2=2.0)
    >>> round(s.mean_rpm, 3), round(s.speed_fluctuation, 4)
    (99.991, 0.0274)
    """

    theta_deg: Array
    omega: Array
    time_s: Array
    motor_torque_nm: Array
    period_s: float
    mean_rpm: float
    speed_fluctuation: float
    peak_motor_torque_nm: float
    lowest_motor_torque_nm: float
    rms_motor_torque_nm: float
    flywheel_kg_m2: float
    constant_inertia_kg_m2: float
    iterations: int
    residual: float


def steady_state(
    d: Reduced,
    motor: Motor,
    *,
    flywheel_kg_m2: float = 0.0,
    tol: float = 1e-10,
    max_iter: int = 60,
) -> SteadyState:
    """The periodic steady state ω(φ) of the reduced machine under ``motor``.

    J(φ)·φ̈ + ½·J′(φ)·φ̇² = M(φ̇) − Q(φ), J with the flywheel and the rotor: in φ
    with y = ω², shooting on y(0) with Newton (sensitivity equation) until
    |y(2π) − y(0)| ≤ ``tol``·y(0); a fixed-step RK4 of step 2·(360°/N) on the
    samples themselves, the odd samples by cubic Hermite (error O(h⁴): at
    N = 3600, ~1e-10 relative for smooth curves; where a gear with η < 1 switches
    between driving and braking the torque has a kink, and the error grows to
    ~1e-5). A constant-torque motor runs through the nominal speed at φ = 0.

    Parameters
    ----------
    d : Reduced
        The reduced machine (:func:`reduced`).
    motor : Motor
        The motor and its gear.
    flywheel_kg_m2 : float, default 0.0
        The flywheel on the main shaft [kg·m²] (≥ 0).
    tol : float, default 1e-10
        Newton's tolerance on the periodicity of ω², in [1e-14, 0.1].
    max_iter : int, default 60
        Newton's shots at most.

    Returns
    -------
    SteadyState
        ω(φ), t(φ), the motor torque, the real δ, the mean speed, the motor's peak
        and RMS torque and the convergence.

    Raises
    ------
    InputError
        Naming the argument: a bad value, or a machine without inertia and no
        flywheel or rotor.
    SolverError
        If there is no periodic speed: the motor's torque is below the mean load at
        every speed, the machine stalls within the cycle, a constant torque that
        does not balance the load, or the shooting did not converge.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> d = cm.dynamics.Reduced.from_curves(np.full(8, 1.0), np.zeros(8), np.full(8, 4.0),
    ...                                     nominal_rpm=100.0)
    >>> s = cm.dynamics.steady_state(d, cm.dynamics.LinearMotor(10.0, 1000.0))
    >>> round(s.mean_rpm, 6)        # 10·(1 − n/1000) = 4
    600.0
    """
    c = _curves(d)
    instance("motor", motor, Motor)
    fw = _flywheel(flywheel_kg_m2)
    extra = _constant(d, motor, fw)
    tol = tolerance("tol", tol, 1e-14, 0.1)
    iters = count("max_iter", max_iter, low=1, high=10_000)
    row, w, t, m = _core.dynamics_steady(
        c["j"],
        c["dj"],
        c["q"],
        extra,
        **pack([motor]),
        tol=tol,
        max_iter=iters,
        omega_start=d.nominal_rpm * RAD_PER_S_PER_RPM,
    )
    status = int(row[0])
    if status != 0:
        advice = (
            _motor_against_load(d, motor)
            if status == 1
            else "a stronger motor, another gear ratio or a bigger flywheel may help"
        )
        raise SolverError(
            f"no periodic steady state: {_STATUS[status]} (after {int(row[1])} shots, residual "
            f"{row[2]:.3g}); {advice}"
        )
    col = dict(zip(STEADY_COLUMNS, row.tolist(), strict=True))
    _check_work(d, motor, m)
    return SteadyState(
        theta_deg=d.theta_deg,
        omega=w,
        time_s=t,
        motor_torque_nm=m,
        period_s=col["period"],
        mean_rpm=col["omega_mean"] / RAD_PER_S_PER_RPM,
        speed_fluctuation=col["delta"],
        peak_motor_torque_nm=col["peak_motor_torque"],
        lowest_motor_torque_nm=col["lowest_motor_torque"],
        rms_motor_torque_nm=col["rms_motor_torque"],
        flywheel_kg_m2=fw,
        constant_inertia_kg_m2=extra,
        iterations=int(col["iterations"]),
        residual=col["residual"],
    )


@dataclass(frozen=True)
class SteadyBatch:
    """The steady states of many designs (:func:`steady_states`).

    Parameters
    ----------
    values : ndarray of float, shape (D, 12)
        One row per design, columns :data:`STEADY_COLUMNS` (speeds [rad/s],
        period [s], torques [N·m]); NaN where not periodic.
    status : tuple of str
        Each design's outcome: ``"periodic"`` or why there is no steady state.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.full(8, 4.0),
    ...                                     nominal_rpm=100.0)
    >>> b = cm.dynamics.steady_states(d, cm.dynamics.LinearMotor(10.0, 1000.0), [0.0, 1.0])
    >>> b.column("omega_mean").round(6).tolist(), b.ok.tolist()
    ([62.831853, 62.831853], [True, True])
    """

    values: Array
    status: tuple[str, ...]

    @property
    def ok(self) -> npt.NDArray[np.bool_]:
        """True where the design has a periodic steady state.

        Examples
        --------
        >>> SteadyBatch(np.array([[0.0] * 12, [2.0] + [np.nan] * 11]), ("periodic", "stall")).ok
        array([ True, False])
        """
        return np.asarray(self.values[:, 0] == 0)

    def column(self, name: str) -> Array:
        """One column of :data:`STEADY_COLUMNS` over the designs.

        Parameters
        ----------
        name : str
            The column's name.

        Returns
        -------
        ndarray of float, shape (D,)
            Its values.

        Raises
        ------
        InputError
            If ``name`` is not a column.

        Examples
        --------
        >>> SteadyBatch(np.zeros((1, 12)), ("periodic",)).column("delta").tolist()
        [0.0]
        """
        if name not in STEADY_COLUMNS:
            raise InputError(f"name = {name!r} must be one of {', '.join(STEADY_COLUMNS)}")
        return np.asarray(self.values[:, STEADY_COLUMNS.index(name)])


def steady_states(
    d: Reduced,
    motors: Motor | list[Motor],
    flywheel_kg_m2: Any,
    *,
    tol: float = 1e-10,
    max_iter: int = 60,
    n_threads: int | None = None,
) -> SteadyBatch:
    """The steady states of many designs in one Rust call (rayon, GIL released).

    Design k has the flywheel ``flywheel_kg_m2[k]`` and the motor ``motors[k]`` (or
    one motor for all); the method is :func:`steady_state`'s.

    Parameters
    ----------
    d : Reduced
        The reduced machine.
    motors : Motor or list of Motor
        One motor for all designs, or one per design.
    flywheel_kg_m2 : float or array_like of float, shape (D,)
        The flywheels [kg·m²] (≥ 0).
    tol : float, default 1e-10
        Newton's tolerance, in [1e-14, 0.1].
    max_iter : int, default 60
        Newton's shots at most.
    n_threads : int, optional
        Threads; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    SteadyBatch
        A row per design.

    Raises
    ------
    InputError
        Naming the argument.

    Warns
    -----
    CyclomechWarning
        If some designs have no periodic steady state (their rows are NaN).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.full(8, 4.0),
    ...                                     nominal_rpm=100.0)
    >>> m = [cm.dynamics.LinearMotor(10.0, 1000.0), cm.dynamics.LinearMotor(20.0, 1000.0)]
    >>> (cm.dynamics.steady_states(d, m, 0.0).column("omega_mean") * 30 / np.pi).round(6).tolist()
    [600.0, 800.0]
    """
    c = _curves(d)
    fw = np.atleast_1d(np.asarray(flywheel_kg_m2, dtype=object))
    if isinstance(motors, Motor):
        ms = [motors] * max(fw.size, 1)
    else:
        ms = instances("motors", motors, Motor)
    if fw.size == 1:
        fw = np.repeat(fw, len(ms))
    if fw.ndim != 1 or fw.size != len(ms):
        raise InputError(
            f"flywheel_kg_m2 must hold one value or one per motor ({len(ms)}); got {fw.size}"
        )
    extra = np.array(
        [_constant(d, m, _flywheel(f)) for f, m in zip(fw.tolist(), ms, strict=True)],
        dtype=np.float64,
    )
    tol = tolerance("tol", tol, 1e-14, 0.1)
    iters = count("max_iter", max_iter, low=1, high=10_000)
    rows = _core.dynamics_steady_batch(
        c["j"],
        c["dj"],
        c["q"],
        extra,
        **pack(ms),
        tol=tol,
        max_iter=iters,
        omega_start=d.nominal_rpm * RAD_PER_S_PER_RPM,
        n_threads=threads_arg(n_threads),
    )
    status = tuple(_STATUS[int(s)] for s in rows[:, 0])
    bad = int(np.sum(rows[:, 0] != 0))
    if bad:
        warnings.warn(
            f"{bad} of {len(ms)} designs have no periodic steady state (their rows are NaN; "
            "SteadyBatch.status says why)",
            CyclomechWarning,
            stacklevel=2,
        )
    return SteadyBatch(rows, status)


@dataclass(frozen=True)
class StartUp:
    """The start-up from rest (:func:`start_up`); each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    time_s : ndarray of float, shape (K,)
        The times of the integrator's accepted steps [s].
    phi_rad : ndarray of float, shape (K,)
        The shaft angle [rad] (from 0, not wrapped).
    omega : ndarray of float, shape (K,)
        The shaft speed [rad/s].
    motor_torque_nm : ndarray of float, shape (K,)
        The motor's torque [N·m].
    settle_time_s : float
        When the speed entered the band ``settle``·ω̄ around the steady state for
        good [s] (it then stayed there for a whole turn; ω̄ = 2π/T, the steady
        state's time-mean speed ``steady.mean_rpm``); NaN if it did not. The
        crossing itself, on each step's continuous extension of order 4
        (Dormand–Prince's dense output), not the end of the step it falls in; an
        excursion out of the band is seen where it spans an eighth of a step. Where
        the speed's deviation only just touches the band's edge, a slight change
        of the machine moves this time by the spacing of the touches (the rule:
        the last crossing).
    steady : SteadyState
        The steady state it settles on.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.zeros(8),
    ...                                     nominal_rpm=100.0)
    >>> s = cm.dynamics.start_up(d, cm.dynamics.LinearMotor(10.0, 600.0))
    >>> round(s.settle_time_s, 2)       # τ = J ω0/M_stall = 6.28 s; ln(1000)·τ = 43.40
    43.4
    """

    time_s: Array
    phi_rad: Array
    omega: Array
    motor_torque_nm: Array
    settle_time_s: float
    steady: SteadyState


def start_up(
    d: Reduced,
    motor: Motor,
    *,
    flywheel_kg_m2: float = 0.0,
    rtol: float = 1e-9,
    settle: float = 1e-3,
    t_max_s: float = 600.0,
    max_steps: int = 2_000_000,
) -> StartUp:
    """The start-up from rest (φ = 0, ω = 0) to the steady state, in time.

    Dormand–Prince 5(4) with error control (``rtol``; the speed's absolute
    tolerance ``rtol``·ω̄), J, J′ and Q between samples by periodic cubic Hermite
    interpolation (O(h⁴)); it stops once the speed has stayed within
    ``settle``·ω̄ of the steady state (:func:`steady_state`) for a whole turn.

    Parameters
    ----------
    d : Reduced
        The reduced machine.
    motor : Motor
        The motor and its gear.
    flywheel_kg_m2 : float, default 0.0
        The flywheel [kg·m²].
    rtol : float, default 1e-9
        The integrator's relative tolerance, in [1e-14, 0.1].
    settle : float, default 1e-3
        The band around the steady state, relative to its time-mean speed 2π/T
        (``SteadyState.mean_rpm``), in (0, 0.5].
    t_max_s : float, default 600.0
        Stop at this time at the latest [s].
    max_steps : int, default 2 000 000
        Stop after this many steps at the latest.

    Returns
    -------
    StartUp
        t, φ, ω and the motor torque at each step, and the settle time.

    Raises
    ------
    InputError
        Naming the argument.
    SolverError
        If the motor cannot start the machine (its speed falls back through 0:
        the message says when and where) or there is no steady state to settle on.

    Warns
    -----
    CyclomechWarning
        If it has not settled by ``t_max_s`` or ``max_steps``.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> d = cm.dynamics.Reduced.from_curves(np.ones(8), np.zeros(8), np.zeros(8),
    ...                                     nominal_rpm=100.0)
    >>> s = cm.dynamics.start_up(d, cm.dynamics.LinearMotor(10.0, 600.0))
    >>> round(float(s.omega[-1] * 30 / np.pi), 1)
    599.5
    """
    ss = steady_state(d, motor, flywheel_kg_m2=flywheel_kg_m2)
    c = _curves(d)
    rt = tolerance("rtol", rtol, 1e-14, 0.1)
    band = tolerance("settle", settle, 1e-12, 0.5)
    tm = positive("t_max_s", t_max_s, "[s]")
    steps = count("max_steps", max_steps, low=1, high=10**9)
    status, when, t, phi, w, m = _core.dynamics_start_up(
        c["j"],
        c["dj"],
        c["q"],
        ss.constant_inertia_kg_m2,
        **pack([motor]),
        steady=ss.omega,
        rtol=rt,
        settle=band,
        t_max=tm,
        max_steps=steps,
    )
    if status == 2:
        t_stop, phi_stop = _stop(t[-2:], phi[-2:], w[-2:])
        raise SolverError(
            f"the motor cannot start the machine: its speed falls back through 0 at "
            f"t = {t_stop:.4g} s, shaft angle {math.degrees(phi_stop):.2f}° (the "
            "load's torque there exceeds what the motor gives before the machine has gathered "
            "speed); a stronger motor, another gear ratio or an unloaded start may help"
        )
    if status == 1:
        warnings.warn(
            f"the start-up has not settled within {settle:g} of the steady speed by "
            f"t = {float(t[-1]):.4g} s (t_max_s = {tm:g}, max_steps = {steps})",
            CyclomechWarning,
            stacklevel=2,
        )
    return StartUp(t, phi, w, m, float(when), ss)


def _stop(t: Array, phi: Array, w: Array) -> tuple[float, float]:
    """Where the speed falls back through 0 inside the last step, from its two ends
    (t [s], φ [rad], ω [rad/s], ω₀ > 0 ≥ ω₁): the peak of φ's cubic Hermite
    interpolant on the step (φ and φ′ = ω at both ends; O(h⁴), as the integrator's
    own dense output), whose derivative, a quadratic, is 0 there. Linear
    interpolation of φ would miss it by O(h²), since φ peaks where ω = 0.

    Returns
    -------
    tuple of float
        (t, φ) at the stop [s, rad].

    >>> # φ = t − t²/2 (ω = 1 − t) sampled at t = 0 and 1.5: the stop is t = 1, φ = ½.
    >>> _stop(np.array([0.0, 1.5]), np.array([0.0, 0.375]), np.array([1.0, -0.5]))
    (1.0, 0.5)
    """
    t0, t1, p0, p1, w0, w1 = (float(x) for x in (t[0], t[1], phi[0], phi[1], w[0], w[1]))
    h = t1 - t0
    # φ(s) = h00 p0 + h10 h w0 + h01 p1 + h11 h w1, s ∈ [0, 1]; φ′(s)/h = a s² + b s + c.
    d = (p1 - p0) / h
    a, b, c = 3.0 * (w0 + w1) - 6.0 * d, 6.0 * d - 4.0 * w0 - 2.0 * w1, w0
    roots = np.roots([a, b, c]) if abs(a) > 1e-300 else np.array([-c / b])
    real = [float(r.real) for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12]
    inside = [r for r in real if 0.0 <= r <= 1.0]
    s = min(inside) if inside else (w0 / (w0 - w1) if w0 > 0 > w1 else 1.0)
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return t0 + s * h, h00 * p0 + h10 * h * w0 + h01 * p1 + h11 * h * w1


@dataclass(frozen=True)
class FlywheelSizing:
    """The flywheel for a coefficient of speed fluctuation, by simulation and by
    the energy method (:func:`size_flywheel`); each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    speed_fluctuation : float
        The target δ.
    flywheel_kg_m2 : float
        The flywheel whose simulated steady state has δ = target [kg·m²]; 0 when
        the machine without one already stays within the target (the motor's
        slope and the mechanisms' inertia steady the speed).
    energy_method_kg_m2 : float
        The energy method's J = ΔE/(ω²δ) at the simulated mean speed [kg·m²]
        (:class:`cyclomech.shaft.ShaftStats`: constant speed, the mechanisms'
        inertia and the motor's characteristic neglected).
    difference : float
        (simulated − energy method)/energy method.
    steady : SteadyState
        The steady state with the simulated flywheel.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.radians(np.arange(0.0, 360.0, 0.1))
    >>> d = cm.dynamics.Reduced.from_curves(np.zeros(3600), np.zeros(3600),
    ...                                     5 + 3 * np.sin(phi), nominal_rpm=100.0)
    >>> f = cm.dynamics.size_flywheel(d, cm.dynamics.InductionMotor(
    ...     1440, 1500, 2.5, rated_torque_nm=1.0, ratio=15), 0.01)
    >>> round(f.steady.speed_fluctuation, 8)
    0.01
    """

    speed_fluctuation: float
    flywheel_kg_m2: float
    energy_method_kg_m2: float
    difference: float
    steady: SteadyState


def size_flywheel(
    d: Reduced,
    motor: Motor,
    speed_fluctuation: float,
    *,
    rtol: float = 1e-9,
    n_threads: int | None = None,
) -> FlywheelSizing:
    """The flywheel J_F whose simulated steady state has the real δ = target.

    δ falls as J_F grows: bracketed (doubling from the energy method's value),
    then narrowed 16 flywheels at a time, each round one batch of steady states
    (:func:`steady_states`), to ``rtol`` relative in J_F. Beside it, the energy
    method's J = ΔE/(ω²δ) at the simulated mean speed and the relative difference.

    Parameters
    ----------
    d : Reduced
        The reduced machine.
    motor : Motor
        The motor and its gear.
    speed_fluctuation : float
        The target δ = (ω_max − ω_min)/ω_mean, in (0, 1).
    rtol : float, default 1e-9
        The relative tolerance on J_F, in [1e-12, 0.1].
    n_threads : int, optional
        Threads; default None.

    Returns
    -------
    FlywheelSizing
        Both flywheels, their difference and the steady state.

    Raises
    ------
    InputError
        Naming the argument.
    SolverError
        If no flywheel reaches the target (the motor cannot drive the machine, or
        δ stays above the target at any flywheel).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.radians(np.arange(0.0, 360.0, 0.1))
    >>> d = cm.dynamics.Reduced.from_curves(np.zeros(3600), np.zeros(3600),
    ...                                     5 + 3 * np.sin(phi), nominal_rpm=100.0)
    >>> f = cm.dynamics.size_flywheel(d, cm.dynamics.LinearMotor(10.0, 200.0), 0.02)
    >>> round(f.steady.speed_fluctuation, 6)
    0.02
    """
    instance("d", d, Reduced)
    instance("motor", motor, Motor)
    target = tolerance("speed_fluctuation", speed_fluctuation, 1e-9, 0.999, "(δ)")
    rt = tolerance("rtol", rtol, 1e-12, 0.1)

    def deltas(js: Array) -> Array:
        # A flywheel leaving the machine without inertia somewhere has no δ.
        some = float(np.min(d.inertia_kg_m2)) + js + motor.shaft_inertia_kg_m2 > 0
        out = np.full(js.shape, np.inf)
        if some.any():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", CyclomechWarning)
                b = steady_states(d, motor, js[some], n_threads=n_threads)
            out[some] = np.where(b.ok, b.column("delta"), np.inf)
        return out

    # The energy method's flywheel at the nominal speed: a first scale.
    stats = d.torque().stats(d.nominal_rpm, target)
    scale = float(stats.flywheel_kg_m2)
    if not (scale > 0 and math.isfinite(scale)):
        scale = max(float(np.mean(d.inertia_kg_m2)), 1e-6)
    if deltas(np.array([0.0]))[0] <= target:
        # The motor's slope and the mechanisms' own inertia hold δ alone.
        ss = steady_state(d, motor)
        energy = float(d.torque().stats(ss.mean_rpm, target).flywheel_kg_m2)
        return FlywheelSizing(target, 0.0, energy, -1.0, ss)
    hi = scale
    # Up to 2^30 times the energy method's flywheel: beyond it a "δ" met is a speed
    # that drifts too slowly to see in one cycle, not a steady state.
    for _ in range(30):
        if deltas(np.array([hi]))[0] <= target:
            break
        hi *= 2.0
    else:
        raise SolverError(
            f"no flywheel up to {hi:.3g} kg·m² brings δ down to {target:g}: "
            f"{_motor_against_load(d, motor)}"
        )
    lo = 0.0
    while (hi - lo) > rt * hi:
        js = np.linspace(lo, hi, 18)[1:-1]
        dl = deltas(js)
        above = np.flatnonzero(dl > target)
        below = np.flatnonzero(dl <= target)
        if above.size:
            lo = float(js[above.max()])
        if below.size:
            hi = float(js[below.min()])
    # The crossing by a last secant between the bracket's ends (δ is smooth in J_F).
    d_lo, d_hi = deltas(np.array([lo, hi]))
    j = hi
    if math.isfinite(d_lo) and d_lo != d_hi:
        j = lo + (d_lo - target) * (hi - lo) / (d_lo - d_hi)
    ss = steady_state(d, motor, flywheel_kg_m2=j)
    energy = float(d.torque().stats(ss.mean_rpm, target).flywheel_kg_m2)
    return FlywheelSizing(target, j, energy, (j - energy) / energy, ss)
