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
    """The main shaft at each speed ``rpm`` [rpm] (arrays of its shape): the mean,
    peak, lowest and RMS torque [N·m], the energy fluctuation ΔE [J] (the largest
    swing of ∫(T − T̄)dθ over the cycle), the flywheel inertia [kg·m²] that keeps
    the speed within ``speed_fluctuation`` δ = (ω_max − ω_min)/ω by the energy
    method (J = ΔE/(ω²δ), the rest of the machine's inertia neglected) and the
    motor power T̄·ω [W]."""

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
    """The torque the main shaft must supply over one cycle, T(θ) = ω²·``per_omega2``
    + ``static`` [N·m] (``per_omega2`` in N·m·s²) at ``theta_deg``, N points
    360°·k/N, linear between them (periodic).

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
        """The sum of M mechanisms' curves (M, N) [N·m·s², N·m], each shifted by
        its phase ``phase_deg`` (M,) [deg] (0 by default): mechanism i's torque at
        θ is its curve's at θ − φ_i, by periodic linear interpolation. One Rust
        call per part.

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
        """T(θ) [N·m] at the speed ``rpm`` [rpm] ((N,); (S, N) for S speeds).

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
        """:class:`ShaftStats` at each speed ``rpm`` [rpm] for the coefficient of
        speed fluctuation ``speed_fluctuation`` δ (> 0): all speeds in one Rust
        call (rayon), exact for the piecewise-linear torque.

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
