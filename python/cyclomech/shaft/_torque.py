"""The main shaft's torque and its statistics: `_torque` part of
:mod:`cyclomech.shaft` (its door)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, float_array, speeds_rpm, threads_arg
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM

__all__ = ["STATS", "ShaftStats", "ShaftTorque"]

Array = npt.NDArray[np.float64]

#: The statistics of :meth:`ShaftTorque.stats`, as the kernel orders them.
STATS: tuple[str, ...] = tuple(_core.SHAFT_STATS)


@dataclass(frozen=True)
class ShaftStats:
    """The main shaft's torque statistics at each speed (arrays of the shape of ``rpm``).

    The energy fluctuation ΔE is the largest swing of ∫(T − T̄)dθ over the cycle; the
    flywheel inertia keeps the speed within δ = (ω_max − ω_min)/ω by the energy
    method, J = ΔE/(ω²δ), the rest of the machine's inertia neglected; the motor
    power is T̄·ω. Built by :meth:`ShaftTorque.stats`; each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    rpm : ndarray of float
        The shaft speeds [rpm].
    speed_fluctuation : float
        The coefficient of speed fluctuation δ = (ω_max − ω_min)/ω (> 0).
    mean_torque_nm : ndarray of float
        The mean torque T̄ over the cycle [N·m].
    peak_torque_nm : ndarray of float
        The largest torque over the cycle [N·m].
    lowest_torque_nm : ndarray of float
        The lowest torque over the cycle [N·m].
    rms_torque_nm : ndarray of float
        The RMS torque over the cycle [N·m].
    energy_fluctuation_j : ndarray of float
        The energy fluctuation ΔE [J].
    flywheel_kg_m2 : ndarray of float
        The flywheel inertia J = ΔE/(ω²δ) [kg·m²].
    power_w : ndarray of float
        The motor power T̄·ω [W].

    See Also
    --------
    ShaftTorque.stats : Builds it.

    Examples
    --------
    >>> import numpy as np
    >>> t = ShaftTorque.from_curves(np.zeros((1, 4)), np.full((1, 4), 2.0))
    >>> s = t.stats([60.0, 120.0], 0.05)
    >>> s.mean_torque_nm.tolist(), s.power_w.round(6).tolist()
    ([2.0, 2.0], [12.566371, 25.132741])
    """

    rpm: Array
    speed_fluctuation: float
    mean_torque_nm: Array
    peak_torque_nm: Array
    lowest_torque_nm: Array
    rms_torque_nm: Array
    energy_fluctuation_j: Array
    flywheel_kg_m2: Array
    power_w: Array


@dataclass(frozen=True)
class ShaftTorque:
    """The torque the main shaft must supply over one cycle [N·m].

    T(θ) = ω²·``per_omega2`` + ``static`` at ``theta_deg``, N points 360°·k/N,
    linear between them (periodic). Build it with :meth:`from_curves` (or
    :meth:`cyclomech.forces.Kinetostatics.shaft_torque`); each parameter is kept as
    the attribute of the same name.

    Parameters
    ----------
    theta_deg : ndarray of float, shape (N,)
        The shaft angles θ_k = 360°·k/N [deg].
    per_omega2 : ndarray of float, shape (N,)
        The part of the torque per ω² (inertia) [N·m·s²].
    static : ndarray of float, shape (N,)
        The part of the torque independent of the speed (loads, springs,
        gravity) [N·m].

    Examples
    --------
    >>> import numpy as np
    >>> t = ShaftTorque.from_curves(np.ones((1, 4)), np.zeros((1, 4)))
    >>> t.at(60.0).round(6).tolist()   # ω = 2π rad/s: 4π² N·m
    [39.478418, 39.478418, 39.478418, 39.478418]
    """

    theta_deg: Array
    per_omega2: Array
    static: Array

    @classmethod
    def from_curves(cls, per_omega2: Any, static: Any, phase_deg: Any = None) -> ShaftTorque:
        """The sum of M mechanisms' torque curves, each shifted by its phase.

        Mechanism i's torque at θ is its curve's at θ − φ_i, by periodic linear
        interpolation. One Rust call per part.

        Parameters
        ----------
        per_omega2 : array_like of float, shape (M, N) or (N,)
            Each mechanism's torque per ω² at the N angles 360°·k/N [N·m·s²].
        static : array_like of float, shape (M, N) or (N,)
            Each mechanism's speed-independent torque at the same angles [N·m].
        phase_deg : array_like of float, shape (M,), optional
            Each mechanism's phase φ_i in the cyclogram [deg]; default 0 for all.

        Returns
        -------
        ShaftTorque
            The summed torque on the shaft.

        Raises
        ------
        InputError
            If the two parts' shapes differ, a value is not finite, there are fewer
            than 3 samples over the turn, or ``phase_deg`` does not hold one phase
            per curve.

        Examples
        --------
        >>> import numpy as np
        >>> t = ShaftTorque.from_curves(np.zeros((1, 4)), np.array([[0.0, 1, 2, 3]]), [90.0])
        >>> t.static.tolist()
        [3.0, 0.0, 1.0, 2.0]
        """
        a = float_array("per_omega2", per_omega2, ndims=(1, 2))
        b = float_array("static", static, ndims=(1, 2))
        a, b = np.atleast_2d(a), np.atleast_2d(b)
        if a.shape != b.shape:
            raise InputError(
                f"per_omega2 {a.shape} and static {b.shape} must have the same shape (M, N)"
            )
        for name, v in (("per_omega2", a), ("static", b)):
            if not np.isfinite(v).all():
                i = np.unravel_index(int(np.argmax(~np.isfinite(v))), v.shape)
                raise InputError(f"{name}{list(i)} = {v[i]!r} must be finite [N·m·s² or N·m]")
        m, n = a.shape
        if n < 3:
            raise InputError(f"the curves need >= 3 samples over the turn; got {n}")
        phase = np.zeros(m) if phase_deg is None else float_array("phase_deg", phase_deg)
        if phase.shape != (m,):
            raise InputError(f"phase_deg must hold one phase per curve ({m}); got {phase.size}")
        rad = np.radians(phase)
        return cls(
            theta_deg=np.arange(n) * (360.0 / n),
            per_omega2=_core.shaft_sum(np.ascontiguousarray(a), rad),
            static=_core.shaft_sum(np.ascontiguousarray(b), rad),
        )

    def at(self, rpm: Any) -> Array:
        """The torque T(θ) at the shaft speed(s) ``rpm`` [N·m].

        Parameters
        ----------
        rpm : float or array_like of float, shape (S,)
            The shaft speed(s) [rpm], each in (0, 1e6].

        Returns
        -------
        ndarray of float, shape (N,) or (S, N)
            T(θ) at the N angles [N·m]: (N,) for a scalar speed, (S, N) for S speeds.

        Raises
        ------
        InputError
            If a speed is not positive and at most 1e6 rpm.

        Examples
        --------
        >>> import numpy as np
        >>> ShaftTorque.from_curves(np.zeros((1, 3)), np.full((1, 3), 2.0)).at(100.0).tolist()
        [2.0, 2.0, 2.0]
        """
        n = speeds_rpm("rpm", rpm)
        w2 = (n * RAD_PER_S_PER_RPM) ** 2
        out = w2[:, None] * self.per_omega2[None, :] + self.static[None, :]
        return out[0] if np.ndim(rpm) == 0 else out

    def stats(
        self, rpm: Any, speed_fluctuation: float, *, n_threads: int | None = None
    ) -> ShaftStats:
        """The shaft's statistics at each speed, for a coefficient of speed fluctuation.

        All speeds in one Rust call (rayon), exact for the piecewise-linear torque.

        Parameters
        ----------
        rpm : float or array_like of float
            The shaft speed(s) [rpm], each in (0, 1e6].
        speed_fluctuation : float
            The coefficient of speed fluctuation δ = (ω_max − ω_min)/ω (> 0), for the
            flywheel.
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        ShaftStats
            The mean, peak, lowest and RMS torque [N·m], energy fluctuation [J],
            flywheel inertia [kg·m²] and motor power [W], each of the shape of ``rpm``.

        Raises
        ------
        InputError
            If a speed is not in (0, 1e6] or ``speed_fluctuation`` is not > 0.

        Examples
        --------
        >>> import numpy as np
        >>> theta = np.radians(np.arange(0.0, 360.0, 0.5))
        >>> t = ShaftTorque.from_curves(np.zeros((1, 720)), (10 * np.cos(theta))[None])
        >>> s = t.stats([100.0, 200.0], 0.05)
        >>> s.energy_fluctuation_j.round(4).tolist()        # 2·10 J
        [19.9999, 19.9999]
        >>> (s.flywheel_kg_m2[0] / s.flywheel_kg_m2[1]).round(9)   # ∝ 1/ω²
        np.float64(4.0)
        """
        n = speeds_rpm("rpm", rpm)
        delta = finite_number("speed_fluctuation", speed_fluctuation, "(δ)", low=0.0)
        if delta <= 0.0 or math.isnan(delta):
            raise InputError(f"speed_fluctuation = {speed_fluctuation!r} must be > 0 (δ)")
        rows = _core.shaft_stats(
            np.ascontiguousarray(self.per_omega2, dtype=np.float64),
            np.ascontiguousarray(self.static, dtype=np.float64),
            n * RAD_PER_S_PER_RPM,
            delta,
            n_threads=threads_arg(n_threads),
        )
        shape = np.shape(rpm)

        def col(i: int) -> Array:
            return rows[:, i].reshape(shape)

        return ShaftStats(n.reshape(shape), delta, *(col(i) for i in range(len(STATS))))
