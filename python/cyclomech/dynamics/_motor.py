"""Motors for the main shaft's dynamics: `_motor` part of :mod:`cyclomech.dynamics`
(its door).

A motor's characteristic is its torque M [N·m] against its own speed [rpm]; a
gear of ratio i (motor speed / shaft speed) and efficiency η puts i·η·M on the
main shaft while the motor drives (i·M/η while it brakes), and its rotor (with
the gears on its side) adds i²·J_rotor to the shaft's inertia.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, float_array, positive
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM

__all__ = ["ConstantTorque", "InductionMotor", "LinearMotor", "Motor", "TableMotor"]

Array = npt.NDArray[np.float64]


def _drive(ratio: Any, efficiency: Any, rotor: Any) -> tuple[float, float, float]:
    """The gear ratio, efficiency and rotor inertia, checked."""
    i = positive("ratio", ratio, "(motor speed / shaft speed)")
    eta = finite_number("efficiency", efficiency, "(of the gear)", low=0.0, strict=True)
    if eta > 1.0:
        raise InputError(f"efficiency = {eta!r} must lie in (0, 1] (of the gear)")
    j = finite_number("rotor_kg_m2", rotor, "[kg·m²]", low=0.0)
    return i, eta, j


@dataclass(frozen=True)
class Motor:
    """What every motor has: the gear to the main shaft and the rotor's inertia.

    Use one of :class:`ConstantTorque`, :class:`LinearMotor`,
    :class:`InductionMotor` or :class:`TableMotor`.

    Parameters
    ----------
    ratio : float
        The gear ratio i = motor speed / main-shaft speed (> 0).
    efficiency : float
        The gear's efficiency η in (0, 1].
    rotor_kg_m2 : float
        The rotor's (and the motor-side gears') moment of inertia [kg·m²] (≥ 0);
        the shaft sees i²·J_rotor.

    Examples
    --------
    >>> m = LinearMotor(10.0, 3000.0, ratio=10.0, rotor_kg_m2=1e-3)
    >>> m.shaft_inertia_kg_m2
    0.1
    >>> Motor(2.0, 0.9, 1e-3).shaft_inertia_kg_m2   # the gear alone: no characteristic
    0.004
    """

    ratio: float
    efficiency: float
    rotor_kg_m2: float

    def __post_init__(self) -> None:
        # Only a Motor made directly runs this (each characteristic sets its fields
        # itself, through the same checks).
        i, eta, j = _drive(self.ratio, self.efficiency, self.rotor_kg_m2)
        for k, v in (("ratio", i), ("efficiency", eta), ("rotor_kg_m2", j)):
            object.__setattr__(self, k, v)

    #: The kernel's code of the characteristic.
    _KIND = -1

    @property
    def shaft_inertia_kg_m2(self) -> float:
        """The rotor's inertia seen by the main shaft, i²·J_rotor [kg·m²].

        Examples
        --------
        >>> ConstantTorque(1.0, ratio=2.0, rotor_kg_m2=0.5).shaft_inertia_kg_m2
        2.0
        """
        return self.ratio**2 * self.rotor_kg_m2

    def _params(self) -> tuple[list[float], Array, Array]:
        """(3 kernel parameters, table speeds [rad/s], table torques [N·m])."""
        raise InputError(
            "motor: a bare Motor (gear and rotor only) has no torque characteristic; use "
            "ConstantTorque, LinearMotor, InductionMotor or TableMotor"
        )

    def torque_nm(self, motor_rpm: Any) -> Array:
        """The characteristic: the motor's torque at its own speeds [N·m].

        Parameters
        ----------
        motor_rpm : float or array_like of float
            The motor's speed(s) [rpm].

        Returns
        -------
        ndarray of float
            The torque at each speed [N·m], of the shape of ``motor_rpm``.

        Examples
        --------
        >>> LinearMotor(10.0, 3000.0).torque_nm([0.0, 1500.0]).tolist()
        [10.0, 5.0]
        """
        n = float_array("motor_rpm", motor_rpm, ndims=(0, 1))
        if not np.isfinite(n).all():
            raise InputError("motor_rpm must be finite [rpm]")
        return self._torque(n * RAD_PER_S_PER_RPM).reshape(np.shape(motor_rpm))

    def _torque(self, w: Array) -> Array:
        raise InputError(
            "motor: a bare Motor (gear and rotor only) has no torque characteristic; use "
            "ConstantTorque, LinearMotor, InductionMotor or TableMotor"
        )


@dataclass(frozen=True, init=False)
class ConstantTorque(Motor):
    """A motor giving the same torque at every speed.

    Its steady states form a family (any speed is periodic once the torque
    balances the mean load, none otherwise): :func:`cyclomech.dynamics.steady_state`
    takes the one through the reduced machine's speed at φ = 0.

    Parameters
    ----------
    torque_nm : float
        The motor's torque [N·m].
    ratio, efficiency, rotor_kg_m2 : float
        The gear and rotor (:class:`Motor`); default 1, 1, 0.

    Raises
    ------
    InputError
        Naming the argument, if one is not a finite number in its range.

    Examples
    --------
    >>> ConstantTorque(4.0, ratio=2.0).torque_nm([0.0, 1e4]).tolist()
    [4.0, 4.0]
    """

    torque: float

    _KIND = 0

    def __init__(
        self,
        torque_nm: float,
        *,
        ratio: float = 1.0,
        efficiency: float = 1.0,
        rotor_kg_m2: float = 0.0,
    ) -> None:
        i, eta, j = _drive(ratio, efficiency, rotor_kg_m2)
        object.__setattr__(self, "torque", finite_number("torque_nm", torque_nm, "[N·m]"))
        object.__setattr__(self, "ratio", i)
        object.__setattr__(self, "efficiency", eta)
        object.__setattr__(self, "rotor_kg_m2", j)

    def _params(self) -> tuple[list[float], Array, Array]:
        return [self.torque, 0.0, 0.0], np.zeros(0), np.zeros(0)

    def _torque(self, w: Array) -> Array:
        return np.full_like(w, self.torque)


@dataclass(frozen=True, init=False)
class LinearMotor(Motor):
    """A DC or servo motor: a torque falling linearly from stall to no load.

    M = M_stall·(1 − n/n_0).

    Parameters
    ----------
    stall_torque_nm : float
        The torque at rest [N·m] (> 0).
    no_load_rpm : float
        The speed at which the torque is 0 [rpm] (> 0).
    ratio, efficiency, rotor_kg_m2 : float
        The gear and rotor (:class:`Motor`); default 1, 1, 0.

    Raises
    ------
    InputError
        Naming the argument, if one is not a finite number in its range.

    Examples
    --------
    >>> LinearMotor(10.0, 3000.0).torque_nm(3000.0).tolist()
    0.0
    """

    stall_torque_nm: float
    no_load_rpm: float

    _KIND = 1

    def __init__(
        self,
        stall_torque_nm: float,
        no_load_rpm: float,
        *,
        ratio: float = 1.0,
        efficiency: float = 1.0,
        rotor_kg_m2: float = 0.0,
    ) -> None:
        i, eta, j = _drive(ratio, efficiency, rotor_kg_m2)
        object.__setattr__(
            self, "stall_torque_nm", positive("stall_torque_nm", stall_torque_nm, "[N·m]")
        )
        object.__setattr__(self, "no_load_rpm", positive("no_load_rpm", no_load_rpm, "[rpm]"))
        object.__setattr__(self, "ratio", i)
        object.__setattr__(self, "efficiency", eta)
        object.__setattr__(self, "rotor_kg_m2", j)

    def _params(self) -> tuple[list[float], Array, Array]:
        w0 = self.no_load_rpm * RAD_PER_S_PER_RPM
        return [self.stall_torque_nm, w0, 0.0], np.zeros(0), np.zeros(0)

    def _torque(self, w: Array) -> Array:
        out: Array = self.stall_torque_nm * (1.0 - w / (self.no_load_rpm * RAD_PER_S_PER_RPM))
        return out


@dataclass(frozen=True, init=False)
class InductionMotor(Motor):
    """A three-phase induction motor by Kloss's formula.

    M = 2·M_k/(s/s_k + s_k/s), slip s = (n_sync − n)/n_sync, breakdown torque
    M_k = λ·M_n, and the critical slip from the rated point,
    s_k = s_n·(λ + √(λ² − 1)) (so that M(s_n) = M_n). The rated torque is
    ``rated_torque_nm`` or P_n/ω_n from ``rated_power_w``.

    Parameters
    ----------
    rated_rpm : float
        The rated speed n_n [rpm] (0 < n_n < n_sync).
    synchronous_rpm : float
        The synchronous speed n_sync [rpm].
    breakdown_ratio : float
        λ = M_k/M_n (> 1: the breakdown torque exceeds the rated torque).
    rated_power_w : float, optional
        The rated power P_n [W]; give it or ``rated_torque_nm``.
    rated_torque_nm : float, optional
        The rated torque M_n [N·m].
    ratio, efficiency, rotor_kg_m2 : float
        The gear and rotor (:class:`Motor`); default 1, 1, 0.

    Raises
    ------
    InputError
        Naming the argument: a value out of its range, λ ≤ 1 (a breakdown torque
        not above the rated torque), a rated speed not below the synchronous one,
        or neither or both of the rated power and torque.

    Examples
    --------
    >>> m = InductionMotor(1440.0, 1500.0, 2.5, rated_torque_nm=10.0)
    >>> round(float(m.torque_nm(1440.0)), 12), round(m.critical_slip, 6)
    (10.0, 0.191652)
    """

    rated_rpm: float
    synchronous_rpm: float
    breakdown_ratio: float
    rated_torque_nm: float

    _KIND = 2

    def __init__(
        self,
        rated_rpm: float,
        synchronous_rpm: float,
        breakdown_ratio: float,
        *,
        rated_power_w: float | None = None,
        rated_torque_nm: float | None = None,
        ratio: float = 1.0,
        efficiency: float = 1.0,
        rotor_kg_m2: float = 0.0,
    ) -> None:
        i, eta, j = _drive(ratio, efficiency, rotor_kg_m2)
        n_s = positive("synchronous_rpm", synchronous_rpm, "[rpm]")
        n_n = positive("rated_rpm", rated_rpm, "[rpm]")
        if n_n >= n_s:
            raise InputError(
                f"rated_rpm = {n_n!r} must be below synchronous_rpm = {n_s!r} (an induction "
                "motor runs with some slip at its rated torque)"
            )
        lam = positive("breakdown_ratio", breakdown_ratio, "(M_k/M_n)")
        if lam <= 1.0:
            raise InputError(
                f"breakdown_ratio = {lam!r} must be > 1: the breakdown torque M_k = λ·M_n must "
                "exceed the rated torque"
            )
        if (rated_power_w is None) == (rated_torque_nm is None):
            raise InputError(
                "give exactly one of rated_power_w [W] and rated_torque_nm [N·m]; got "
                f"rated_power_w = {rated_power_w!r}, rated_torque_nm = {rated_torque_nm!r}"
            )
        if rated_torque_nm is not None:
            m_n = positive("rated_torque_nm", rated_torque_nm, "[N·m]")
        else:
            m_n = positive("rated_power_w", rated_power_w, "[W]") / (n_n * RAD_PER_S_PER_RPM)
        for k, v in (
            ("rated_rpm", n_n),
            ("synchronous_rpm", n_s),
            ("breakdown_ratio", lam),
            ("rated_torque_nm", m_n),
            ("ratio", i),
            ("efficiency", eta),
            ("rotor_kg_m2", j),
        ):
            object.__setattr__(self, k, v)

    @property
    def critical_slip(self) -> float:
        """The slip of the breakdown torque, s_k = s_n·(λ + √(λ² − 1)).

        Examples
        --------
        >>> round(InductionMotor(1450.0, 1500.0, 2.0, rated_torque_nm=1.0).critical_slip, 6)
        0.124402
        """
        s_n = (self.synchronous_rpm - self.rated_rpm) / self.synchronous_rpm
        lam = self.breakdown_ratio
        return s_n * (lam + math.sqrt(lam * lam - 1.0))

    def _params(self) -> tuple[list[float], Array, Array]:
        m_k = self.breakdown_ratio * self.rated_torque_nm
        w_s = self.synchronous_rpm * RAD_PER_S_PER_RPM
        return [m_k, w_s, self.critical_slip], np.zeros(0), np.zeros(0)

    def _torque(self, w: Array) -> Array:
        w_s = self.synchronous_rpm * RAD_PER_S_PER_RPM
        s, sk = (w_s - w) / w_s, self.critical_slip
        out: Array = 2.0 * self.breakdown_ratio * self.rated_torque_nm * s * sk / (s * s + sk * sk)
        return out


@dataclass(frozen=True, init=False)
class TableMotor(Motor):
    """A motor given by a table of torque against speed.

    Linear between the points and extended by the end segments (so a table
    ending at 0 torque keeps falling beyond it).

    Parameters
    ----------
    speed_rpm : array_like of float, shape (K,)
        The motor speeds [rpm], K ≥ 2, strictly increasing.
    torque_nm : array_like of float, shape (K,)
        The torque at each speed [N·m].
    ratio, efficiency, rotor_kg_m2 : float
        The gear and rotor (:class:`Motor`); default 1, 1, 0.

    Raises
    ------
    InputError
        Naming the argument, if the table is not two finite arrays of one length
        ≥ 2 with increasing speeds.

    Examples
    --------
    >>> m = TableMotor([0.0, 1000.0, 1500.0], [20.0, 15.0, 0.0])
    >>> m.torque_nm([500.0, 1600.0]).round(9).tolist()
    [17.5, -3.0]
    """

    speed_rpm: Array
    torque: Array

    _KIND = 3

    def __init__(
        self,
        speed_rpm: Any,
        torque_nm: Any,
        *,
        ratio: float = 1.0,
        efficiency: float = 1.0,
        rotor_kg_m2: float = 0.0,
    ) -> None:
        i, eta, j = _drive(ratio, efficiency, rotor_kg_m2)
        n = float_array("speed_rpm", speed_rpm)
        t = float_array("torque_nm", torque_nm)
        if n.size < 2 or n.size != t.size:
            raise InputError(
                f"speed_rpm and torque_nm must have the same length, at least 2 points; got "
                f"{n.size} and {t.size}"
            )
        for k, v in (("speed_rpm", n), ("torque_nm", t)):
            if not np.isfinite(v).all():
                raise InputError(f"{k} must be finite; got {v.tolist()!r}")
        if (np.diff(n) <= 0).any():
            raise InputError(f"speed_rpm must increase strictly [rpm]; got {n.tolist()!r}")
        fields: tuple[tuple[str, Any], ...] = (
            ("speed_rpm", n),
            ("torque", t),
            ("ratio", i),
            ("efficiency", eta),
            ("rotor_kg_m2", j),
        )
        for k, v in fields:
            object.__setattr__(self, k, v)

    def _params(self) -> tuple[list[float], Array, Array]:
        return [0.0, 0.0, 0.0], self.speed_rpm * RAD_PER_S_PER_RPM, self.torque

    def _torque(self, w: Array) -> Array:
        x = self.speed_rpm * RAD_PER_S_PER_RPM
        j = np.clip(np.searchsorted(x, w, side="right") - 1, 0, x.size - 2)
        slope = (self.torque[j + 1] - self.torque[j]) / (x[j + 1] - x[j])
        out: Array = self.torque[j] + slope * (w - x[j])
        return out


def pack(motors: list[Motor]) -> dict[str, Any]:
    """The kernel's motor arrays for ``motors`` (see ``rust/bindings/src/dynamics_shaft.rs``)."""
    kinds, params, ratio, eff, off, ts, tt = [], [], [], [], [0], [], []
    for m in motors:
        p, s, t = m._params()
        kinds.append(m._KIND)
        params.append(p)
        ratio.append(m.ratio)
        eff.append(m.efficiency)
        ts.append(s)
        tt.append(t)
        off.append(off[-1] + s.size)
    return {
        "kinds": np.asarray(kinds, dtype=np.int64),
        "params": np.ascontiguousarray(np.asarray(params, dtype=np.float64).reshape(-1, 3)),
        "ratio": np.asarray(ratio, dtype=np.float64),
        "efficiency": np.asarray(eff, dtype=np.float64),
        "table_offsets": np.asarray(off, dtype=np.int64),
        "table_speed": np.ascontiguousarray(np.concatenate(ts) if ts else np.zeros(0)),
        "table_torque": np.ascontiguousarray(np.concatenate(tt) if tt else np.zeros(0)),
    }
