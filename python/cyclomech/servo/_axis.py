"""A servo axis and its duty over the machine's cycle: `_axis` part of
:mod:`cyclomech.servo` (its door)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, float_array, positive, speeds_rpm, threads_arg
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ..cam import MinPhaseAngles
from ._parts import Gearbox, LinearLoad, Motor, RotaryLoad

__all__ = ["CHECKS", "Duty", "ServoAxis"]

Array = npt.NDArray[np.float64]

#: The checks of a motor and drive, in the order of every margin array: the peak
#: ``|torque|`` against the motor's peak torque, the RMS torque against its rated torque
#: (thermal), the peak ``|speed|`` against its maximum speed, the inertia ratio against
#: the axis's limit. A margin is 1 − used/available: ≥ 0 passes, < 0 fails.
CHECKS: tuple[str, ...] = tuple(_core.SERVO_CHECKS)

#: Samples of the program over the cycle unless the axis says otherwise.
DEFAULT_POINTS = 3600

#: The largest inertia ratio (load at the motor over the rotor's) unless the axis
#: says otherwise: the 10:1 rule of thumb of servo selection guides.
DEFAULT_INERTIA_LIMIT = 10.0


def _sample(program: Any, points: int) -> tuple[Array, Array, Array, Array, Array]:
    """θ (N,) and the program's s, v, a, j there, in one ``evaluate`` call."""
    evaluate = getattr(program, "evaluate", None)
    if not callable(evaluate):
        raise TypeError(
            "program must have a method evaluate(theta) (a cyclomech.motion.Program); "
            f"got {type(program).__name__}"
        )
    theta: Array = np.arange(points, dtype=np.float64) * (2.0 * math.pi / points)
    got = evaluate(theta)
    out: list[Array] = [theta]
    for key in ("s", "v", "a", "j"):
        if not hasattr(got, key):
            raise InputError(f"program.evaluate(theta) must return .s .v .a .j; it has no .{key}")
        values = float_array(f"program.evaluate(theta).{key}", getattr(got, key), ndims=None)
        if values.shape != theta.shape:
            raise InputError(
                f"program.evaluate(theta).{key} must have theta's shape {theta.shape}; "
                f"got {values.shape}"
            )
        bad = ~np.isfinite(values)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(
                f"program.evaluate(theta).{key}[{i}] = {float(values[i])!r} must be finite "
                f"(at θ = {math.degrees(theta[i]):g}°)"
            )
        out.append(values)
    return out[0], out[1], out[2], out[3], out[4]


@dataclass(frozen=True)
class Duty:
    """A motor's duty on a servo axis over the machine's cycle, and its checks.

    Built by :meth:`ServoAxis.duty`; each parameter is kept as the attribute of
    the same name. Statistics have the shape of ``rpm`` (scalars as 0-d arrays);
    margins have one more axis, the :data:`CHECKS`.

    Parameters
    ----------
    rpm : ndarray of float
        The machine's (master's) speeds [rpm].
    theta_deg : ndarray of float, shape (N,)
        The master angles of the samples [deg].
    motor_rpm : ndarray of float, shape (N,), or None
        The motor's speed over the cycle [rpm], for a scalar ``rpm`` (else None).
    torque_nm : ndarray of float, shape (N,), or None
        The motor's torque over the cycle [N·m], for a scalar ``rpm`` (else None).
    peak_torque_nm : ndarray of float
        The peak |motor torque| over the cycle [N·m].
    rms_torque_nm : ndarray of float
        The RMS motor torque over the whole cycle, dwells included [N·m].
    peak_speed_rpm : ndarray of float
        The peak |motor speed| [rpm].
    regen_energy_j : ndarray of float
        The energy the motor regenerates per cycle, ∫ max(0, −T_m·ω_m) dt [J].
    inertia_ratio : float
        (J_load/i² + J_gearbox)/J_motor: everything the motor drives, at its shaft,
        over its rotor's inertia.
    margins : ndarray of float, shape (..., 4)
        1 − used/available for each of :data:`CHECKS` at each speed.
    binding : str
        The check with the smallest margin over every speed.
    passes : bool
        Every check holds (margin ≥ 0) at every speed.
    status : str
        "ok", or "fails <check> (margin <m> at <n> rpm)" for the binding check.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> from types import SimpleNamespace
    >>> class Swing:  # a stand-in program: the load shaft swings ±0.5 rad
    ...     def evaluate(self, t):
    ...         c, s = np.cos(t), np.sin(t)
    ...         return SimpleNamespace(s=0.5 * s, v=0.5 * c, a=-0.5 * s, j=-0.5 * c)
    >>> ax = cm.servo.ServoAxis(Swing(), cm.servo.RotaryLoad(0.01), cm.servo.Gearbox(3.0),
    ...                         cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4))
    >>> d = ax.duty([60.0, 600.0])
    >>> d.passes, d.binding, d.status
    (False, 'rms_torque', 'fails rms_torque (margin -3.03 at 600 rpm)')
    """

    rpm: Array
    theta_deg: Array
    motor_rpm: Array | None
    torque_nm: Array | None
    peak_torque_nm: Array
    rms_torque_nm: Array
    peak_speed_rpm: Array
    regen_energy_j: Array
    inertia_ratio: float
    margins: Array
    binding: str
    passes: bool
    status: str


class ServoAxis:
    """A servo axis: an electronic cam whose master is the machine's main shaft.

    The master turns at the constant speed ω = 2π·n/60 (n the machine's speed in
    rpm); the program gives the slave x(θ) over one cycle θ ∈ [0, 2π) [m for a
    linear load, rad for a rotary one] and its derivatives per radian of master,
    so ẋ = x′·ω and ẍ = x″·ω² (time is uniform in θ: an RMS over the cycle is an
    RMS over the uniform samples, dwells included). The program is sampled once,
    at ``points`` uniform angles, by one ``program.evaluate(theta)`` call.

    At the load shaft (angle φ_L; a linear load's screw shaft, φ_L = 2π·x/lead)
    the torque is T_L = J_L·φ̈_L + T_ext. Through the screw and the gearbox
    (efficiency η = η_screw·η_gear, ratio i = motor speed / load-shaft speed) it
    reaches the motor as T_out = T_L/(i·η) where the motor drives the load
    (T_L·φ̇_L > 0) and T_L·η/i where the load drives the motor (regeneration).
    Where the load stands (φ̇_L = 0, a dwell) a holding torque is taken on the
    motoring side, T_L/(i·η): the larger, the conservative choice for a check.
    The motor's torque is T_m = (J_motor + J_gear)·φ̈_m + T_out with φ_m = i·φ_L.

    Parameters
    ----------
    program : object with ``evaluate(theta)``
        The slave's motion: ``evaluate`` takes master angles [rad] (a float64
        array) and returns an object with ``.s .v .a .j``, arrays of theta's
        shape: position and its 1st to 3rd derivatives per radian of master (a
        :class:`cyclomech.motion.Program` does).
    load : RotaryLoad or LinearLoad
        What the axis moves.
    gearbox : Gearbox, optional
        Between motor and load shaft; default a direct drive, ``Gearbox(1.0)``.
    motor : Motor, optional
        The motor, needed by :meth:`duty` (not by :func:`size`, which tries a
        catalogue); default None.
    points : int, optional
        Samples of the program over the cycle, ≥ 16; default 3600.
    inertia_ratio_limit : float, optional
        The largest inertia ratio (J_load/i² + J_gear)/J_motor that passes, > 0;
        default 10 (the common 10:1 rule of servo selection guides; 1–5 for a
        stiff, fast axis).

    Attributes
    ----------
    theta : ndarray of float, shape (N,)
        The master angles of the samples, 2π·k/N [rad].
    s, v, a, j : ndarray of float, shape (N,)
        The program there: position [m or rad] and its derivatives per radian of
        master (one ``evaluate`` call, at construction).
    program, load, gearbox, motor, points, inertia_ratio_limit
        The arguments, as given (``gearbox`` made a direct drive if None).

    Raises
    ------
    InputError
        If the program's arrays are not finite or of theta's shape, or a number
        is out of its range.
    TypeError
        If ``program`` has no ``evaluate`` method or a part is of the wrong type.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> from types import SimpleNamespace
    >>> class Swing:  # a stand-in program: the load shaft swings ±0.5 rad
    ...     def evaluate(self, t):
    ...         c, s = np.cos(t), np.sin(t)
    ...         return SimpleNamespace(s=0.5 * s, v=0.5 * c, a=-0.5 * s, j=-0.5 * c)
    >>> ax = cm.servo.ServoAxis(Swing(), cm.servo.RotaryLoad(0.01), cm.servo.Gearbox(3.0),
    ...                         cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4), points=360)
    >>> round(float(ax.duty(60.0).peak_speed_rpm), 6)   # 3 · 0.5 · 60 rpm
    90.0
    """

    def __init__(
        self,
        program: Any,
        load: RotaryLoad | LinearLoad,
        gearbox: Gearbox | None = None,
        motor: Motor | None = None,
        *,
        points: int = DEFAULT_POINTS,
        inertia_ratio_limit: float = DEFAULT_INERTIA_LIMIT,
    ) -> None:
        if not isinstance(load, RotaryLoad | LinearLoad):
            raise TypeError(f"load must be a RotaryLoad or LinearLoad; got {type(load).__name__}")
        gearbox = Gearbox(1.0) if gearbox is None else gearbox
        if not isinstance(gearbox, Gearbox):
            raise TypeError(f"gearbox must be a Gearbox; got {type(gearbox).__name__}")
        if motor is not None and not isinstance(motor, Motor):
            raise TypeError(f"motor must be a Motor; got {type(motor).__name__}")
        self.points = count("points", points, low=16, high=10**7, what="samples over the cycle")
        self.inertia_ratio_limit = positive("inertia_ratio_limit", inertia_ratio_limit, "(J/J)")
        self.program, self.load, self.gearbox, self.motor = program, load, gearbox, motor
        self.theta, self.s, self.v, self.a, self.j = _sample(program, self.points)
        k, j_load, t_ext, eta = load._shaft()
        # The load shaft's φ_L′, φ_L″ [rad/rad, rad/rad²]; J_L [kg·m²], T_ext [N·m]
        # and the screw's efficiency (1 for a rotary load). A velocity within
        # rounding of 0 (1e-12 of the largest: a dwell's join) is a load at rest,
        # held on the motoring side, not a sign for the efficiency to flip on.
        vel = self.v * k
        vel[np.abs(vel) <= 1e-12 * np.abs(vel).max(initial=0.0)] = 0.0
        self._vel, self._acc = vel, self.a * k
        self._load = (j_load, t_ext, eta)

    def _drive(
        self, motor: Motor, gearbox: Gearbox
    ) -> tuple[float, float, float, float, float, float]:
        """The drive arguments of the program kernels (bounds, limits) in order: the
        load shaft's radians per program unit, J_L, T_ext, η_screw·η_gear, the ratio
        and J_motor + J_gear."""
        k, j_load, t_ext, eta = self.load._shaft()
        return (
            k,
            j_load,
            t_ext,
            eta * gearbox.efficiency,
            gearbox.ratio,
            motor.inertia_kg_m2 + gearbox.inertia_kg_m2,
        )

    def _kernel_load(self, gearbox: Gearbox) -> tuple[Array, Array, float, float, float]:
        """The load arguments of the kernels through ``gearbox``: φ_L′, φ_L″, J_L,
        T_ext and the whole drive's efficiency η_screw·η_gear."""
        j_load, t_ext, eta = self._load
        return self._vel, self._acc, j_load, t_ext, eta * gearbox.efficiency

    def inertia_ratio(self, motor: Motor | None = None, gearbox: Gearbox | None = None) -> float:
        """The inertia ratio (J_load/i² + J_gear)/J_motor.

        Everything the motor drives, brought to its shaft, over the rotor's
        inertia: the load's reflected through the gearbox (and the screw) plus
        the gearbox's own. Without a gearbox inertia it is the load-to-motor
        inertia ratio λ = J_L/(i²·J_motor) of servo sizing guides (Kollmorgen's,
        Yaskawa's), whose rule of thumb keeps it ≤ 10:1 (the default limit).

        Parameters
        ----------
        motor : Motor, optional
            Default the axis's motor.
        gearbox : Gearbox, optional
            Default the axis's gearbox.

        Returns
        -------
        float
            The ratio (dimensionless).

        Raises
        ------
        InputError
            If no motor is given and the axis has none.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> from types import SimpleNamespace
        >>> class Swing:
        ...     def evaluate(self, t):
        ...         return SimpleNamespace(s=np.sin(t), v=np.cos(t), a=-np.sin(t), j=-np.cos(t))
        >>> ax = cm.servo.ServoAxis(Swing(), cm.servo.RotaryLoad(0.009), cm.servo.Gearbox(3.0))
        >>> round(ax.inertia_ratio(cm.servo.Motor(1, 3, 3000, 6000, 1e-4)), 9)  # 0.009/9/1e-4
        10.0
        """
        motor = self._motor(motor)
        gearbox = self.gearbox if gearbox is None else gearbox
        if not isinstance(gearbox, Gearbox):
            raise TypeError(f"gearbox must be a Gearbox; got {type(gearbox).__name__}")
        i = gearbox.ratio
        return (self._load[0] / (i * i) + gearbox.inertia_kg_m2) / motor.inertia_kg_m2

    def _motor(self, motor: Motor | None) -> Motor:
        motor = self.motor if motor is None else motor
        if motor is None:
            raise InputError("motor: the axis has no motor; give ServoAxis(motor=...) or motor=")
        if not isinstance(motor, Motor):
            raise TypeError(f"motor must be a Motor; got {type(motor).__name__}")
        return motor

    def duty(
        self,
        rpm: Any,
        *,
        motor: Motor | None = None,
        gearbox: Gearbox | None = None,
        n_threads: int | None = None,
    ) -> Duty:
        """The motor's torque and speed over the cycle and its checks, at each speed.

        All speeds in one Rust call. The margins are 1 − used/available for each
        of :data:`CHECKS`; a failing check is reported in ``passes``, ``binding``
        and ``status``, not raised (sizing needs failing candidates too).

        Parameters
        ----------
        rpm : float or array_like of float
            The machine's speed(s) [rpm], each in (0, 1e6].
        motor : Motor, optional
            Instead of the axis's motor; default None (the axis's).
        gearbox : Gearbox, optional
            Instead of the axis's gearbox; default None (the axis's).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        Duty
            The curves (for a scalar ``rpm``), the statistics, margins and status.

        Raises
        ------
        InputError
            If a speed is out of range or the axis has no motor and none is given.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> from types import SimpleNamespace
        >>> class Swing:  # the load shaft swings ±0.5 rad
        ...     def evaluate(self, t):
        ...         c, s = np.cos(t), np.sin(t)
        ...         return SimpleNamespace(s=0.5 * s, v=0.5 * c, a=-0.5 * s, j=-0.5 * c)
        >>> ax = cm.servo.ServoAxis(Swing(), cm.servo.RotaryLoad(0.01), cm.servo.Gearbox(3.0),
        ...                         cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4))
        >>> d = ax.duty(60.0)   # ω = 2π rad/s: T = (1.4e-4·3 + 0.01/3)·0.5·4π² sin θ
        >>> round(float(d.peak_torque_nm), 6), d.status
        (0.074088, 'ok')
        """
        motor = self._motor(motor)
        gearbox = self.gearbox if gearbox is None else gearbox
        if not isinstance(gearbox, Gearbox):
            raise TypeError(f"gearbox must be a Gearbox; got {type(gearbox).__name__}")
        n = speeds_rpm("rpm", rpm)
        shape = np.shape(rpm)
        scalar = shape == ()
        stats, curves = _core.servo_duty(
            *self._kernel_load(gearbox),
            gearbox.ratio,
            motor.inertia_kg_m2 + gearbox.inertia_kg_m2,
            n * RAD_PER_S_PER_RPM,
            curves=scalar,
            n_threads=threads_arg(n_threads),
        )
        peak, rms, speed, regen = (stats[:, c].reshape(shape) for c in range(4))
        speed = speed / RAD_PER_S_PER_RPM
        ratio = self.inertia_ratio(motor, gearbox)
        margins = np.stack(
            [
                1.0 - peak / motor.peak_torque_nm,
                1.0 - rms / motor.rated_torque_nm,
                1.0 - speed / motor.max_rpm,
                np.full(shape, 1.0 - ratio / self.inertia_ratio_limit),
            ],
            axis=-1,
        )
        return Duty(
            rpm=n.reshape(shape),
            theta_deg=np.degrees(self.theta),
            motor_rpm=gearbox.ratio * self._vel * float(n[0]) if scalar else None,
            torque_nm=curves[0] if scalar else None,
            peak_torque_nm=peak,
            rms_torque_nm=rms,
            peak_speed_rpm=speed,
            regen_energy_j=regen,
            inertia_ratio=ratio,
            margins=margins,
            **_verdict(margins, n),
        )

    def cam_table(self, points: int = 3600) -> Any:
        """The axis's electronic cam table: master angle → slave s, v, a, j.

        At ``points`` steps over the cycle, both ends included (the last row is the
        next cycle's start); one ``evaluate`` call of the program. To write it for a
        drive: :func:`cyclomech.motion.write_cam_table` (or its closed form,
        :func:`cyclomech.motion.write_cam_coefficients`).

        Parameters
        ----------
        points : int, default 3600
            Steps over the cycle, at least 2.

        Returns
        -------
        cyclomech.motion.MotionValues
            ``theta`` [rad of master] from 0 to 2π, ``s`` [m or rad] and ``v``, ``a``,
            ``j`` per rad^k of master.

        Raises
        ------
        InputError
            If ``points`` is not an integer ≥ 2.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> prog = cm.motion.Program([S("cycloidal", 180, end=0.1), S("cycloidal", 180, end=0.0)])
        >>> ax = cm.servo.ServoAxis(prog, cm.servo.LinearLoad(mass_kg=5.0, lead_m=0.02))
        >>> t = ax.cam_table(points=4)
        >>> t.s.round(6).tolist()
        [0.0, 0.05, 0.1, 0.05, 0.0]
        """
        n = count("points", points, low=2)
        return self.program.evaluate(np.linspace(0.0, 2.0 * math.pi, n + 1))

    def min_phase_angles(
        self,
        rpm: Any,
        *,
        motor: Motor | None = None,
        gearbox: Gearbox | None = None,
        segments: Any = None,
    ) -> MinPhaseAngles:
        """Each moving segment's smallest phase angle the motor and gearbox can do.

        For a segment whose shape scales with its angle (rest to rest: a named law
        or a polynomial), the smallest angle β such that at every β′ ≥ β the motor's
        peak torque holds over the segment (``"peak_torque"``; NaN when even the
        static torque exceeds it) and its peak speed stays within its maximum speed
        (``"speed"``: β = i·H·max|Z′|·ω/ω_max, H the stroke at the load shaft), at
        each machine speed: the cyclogram's bound on the segment's operation, as a
        cam's. The RMS torque couples the whole cycle: :meth:`duty` checks it on the
        timing. One Rust call; the segment's law is sampled on 1024 intervals per
        piece (the peak's error is below 1e-5 relative).

        Parameters
        ----------
        rpm : float or array_like of float
            The machine's speed(s) [rpm].
        motor : Motor, optional
            Instead of the axis's motor; default None (the axis's).
        gearbox : Gearbox, optional
            Instead of the axis's gearbox; default None (the axis's).
        segments : sequence of int, optional
            The segments to bound; default None (every one that moves and scales).

        Returns
        -------
        cyclomech.cam.MinPhaseAngles
            ``angle_deg`` of shape (speeds, segments, 2), criteria
            ``("peak_torque", "speed")``; ``bound_deg`` and ``binding`` per segment.

        Raises
        ------
        InputError
            If the program is not a :class:`cyclomech.motion.Program`, a segment asked
            for does not scale with its angle (named), or a speed is not > 0.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> prog = cm.motion.Program([S("cycloidal", 90, end=1.0), S("dwell", 90),
        ...                           S("cycloidal", 90, end=0.0), S("dwell", 90)])
        >>> ax = cm.servo.ServoAxis(prog, cm.servo.RotaryLoad(0.02), cm.servo.Gearbox(2.0),
        ...                         cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4))
        >>> m = ax.min_phase_angles(60.0)
        >>> m.segments, m.criteria
        ((0, 2), ('peak_torque', 'speed'))
        >>> round(float(m.bound_deg[0, 0]), 3), str(m.binding[0, 0])
        (46.329, 'peak_torque')
        """
        from ..motion import Program

        if not isinstance(self.program, Program):
            raise InputError(
                "min_phase_angles needs the axis's program to be a cyclomech.motion.Program"
            )
        motor = self._motor(motor)
        gearbox = self.gearbox if gearbox is None else gearbox
        if not isinstance(gearbox, Gearbox):
            raise TypeError(f"gearbox must be a Gearbox; got {type(gearbox).__name__}")
        n = speeds_rpm("rpm", rpm)
        moving = [
            i
            for i, (g, (_, _, s0, s1)) in enumerate(
                zip(self.program.segments, self.program.boundaries, strict=True)
            )
            if g.law != "dwell" and s1[0] != s0[0]
        ]
        if segments is None:
            idx = tuple(i for i in moving if self.program.scalable[i])
        else:
            idx = tuple(int(i) for i in np.atleast_1d(np.asarray(segments)).reshape(-1))
        out = _core.servo_min_angles(
            self.program.kernel,
            list(idx),
            *self._drive(motor, gearbox),
            motor.peak_torque_nm,
            motor.max_rpm * RAD_PER_S_PER_RPM,
            n * RAD_PER_S_PER_RPM,
        )
        return MinPhaseAngles(
            rpm=n, segments=idx, criteria=tuple(_core.SERVO_BOUNDS), angle_deg=np.degrees(out)
        )


def _verdict(margins: Array, rpm: Array) -> dict[str, Any]:
    """binding, passes and status of margins (..., 4) at speeds ``rpm`` (flat)."""
    flat = margins.reshape(-1, len(CHECKS))
    s, c = np.unravel_index(int(np.argmin(flat)), flat.shape)
    worst = float(flat[s, c])
    passes = bool(worst >= 0.0)
    status = "ok" if passes else f"fails {CHECKS[c]} (margin {worst:.3g} at {rpm[s]:g} rpm)"
    return {"binding": CHECKS[c], "passes": passes, "status": status}
