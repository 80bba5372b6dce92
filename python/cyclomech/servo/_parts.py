"""The parts of a servo axis: the motor, the gearbox and the load (rotary, or
linear through a screw, belt or rack): `_parts` part of :mod:`cyclomech.servo`
(its door)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .._arrays import finite_number, positive
from .._errors import InputError

__all__ = ["Gearbox", "LinearLoad", "Motor", "RotaryLoad"]


def _efficiency(name: str, value: Any) -> float:
    """An efficiency in (0, 1], or :class:`InputError` naming ``name``."""
    eta = finite_number(name, value, "(an efficiency, in (0, 1])")
    if not 0.0 < eta <= 1.0:
        raise InputError(f"{name} = {eta!r} must be in (0, 1] (an efficiency)")
    return eta


def _name(value: Any) -> str:
    if not isinstance(value, str):
        raise InputError(f"name must be a string; got {value!r}")
    return value


#: A Motor's speed or inertia not given (a dataclass default that no number is).
_MISSING: Any = type("Missing", (), {"__repr__": lambda self: "<not given>"})()


@dataclass(frozen=True)
class Motor:
    """A servo motor from a catalogue: its torques, speeds and rotor inertia.

    The rated torque is the continuous (thermal) torque, checked against the RMS
    torque over the cycle; the peak torque the largest the drive may command,
    checked against the peak ``|torque|``; the maximum speed against the peak
    ``|speed|``. The rated speed is kept for the reader (the corner of the
    torque-speed curve) and checked only against ``max_rpm``: the torque-speed
    curve itself is not modelled. Each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    rated_torque_nm : float
        Rated (continuous) torque [N·m], > 0.
    peak_torque_nm : float
        Peak torque [N·m], ≥ ``rated_torque_nm``.
    rated_rpm : float, optional
        Rated speed [rpm], > 0; default: not given (taken as ``max_rpm``).
    max_rpm : float
        Maximum speed [rpm], ≥ ``rated_rpm`` (required; a keyword when ``rated_rpm``
        is not given).
    inertia_kg_m2 : float
        Rotor inertia [kg·m²], > 0 (required).
    name : str, optional
        The catalogue's name of the motor; default "".

    Raises
    ------
    InputError
        If a value is not a finite positive number, ``max_rpm`` or ``inertia_kg_m2``
        is missing, the peak torque is below the rated one or the maximum speed below
        the rated one.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4, name="M130")
    >>> m.peak_torque_nm / m.rated_torque_nm
    3.0
    >>> cm.servo.Motor(rated_torque_nm=1.3, peak_torque_nm=3.9, max_rpm=6000,
    ...                inertia_kg_m2=1.4e-4).rated_rpm
    6000.0
    """

    rated_torque_nm: float
    peak_torque_nm: float
    # (_MISSING: not given; the dataclass needs defaults after the first optional one.)
    rated_rpm: float = _MISSING
    max_rpm: float = _MISSING
    inertia_kg_m2: float = _MISSING
    name: str = ""

    def __post_init__(self) -> None:
        for key in ("max_rpm", "inertia_kg_m2"):
            if getattr(self, key) is _MISSING:
                raise InputError(
                    f"{key} is required: a finite number (a Motor needs its maximum speed and "
                    "rotor inertia)"
                )
        rated = positive("rated_torque_nm", self.rated_torque_nm, "[N·m]")
        peak = positive("peak_torque_nm", self.peak_torque_nm, "[N·m]")
        max_rpm = positive("max_rpm", self.max_rpm, "[rpm]")
        given = self.rated_rpm
        rated_rpm = max_rpm if given is _MISSING else positive("rated_rpm", given, "[rpm]")
        inertia = positive("inertia_kg_m2", self.inertia_kg_m2, "[kg·m²]")
        if peak < rated:
            raise InputError(
                f"peak_torque_nm = {peak!r} must be >= rated_torque_nm = {rated!r} [N·m]"
            )
        if max_rpm < rated_rpm:
            raise InputError(f"max_rpm = {max_rpm!r} must be >= rated_rpm = {rated_rpm!r} [rpm]")
        for key, value in (
            ("rated_torque_nm", rated),
            ("peak_torque_nm", peak),
            ("rated_rpm", rated_rpm),
            ("max_rpm", max_rpm),
            ("inertia_kg_m2", inertia),
            ("name", _name(self.name)),
        ):
            object.__setattr__(self, key, value)


@dataclass(frozen=True)
class Gearbox:
    """A gearbox between the motor and the load shaft.

    Each parameter is kept as the attribute of the same name. The efficiency
    divides the torque where the motor drives the load and multiplies it where
    the load drives the motor (see :class:`ServoAxis`).

    Parameters
    ----------
    ratio : float
        i = motor speed / load-shaft speed, > 0 (1 for a direct drive).
    efficiency : float, optional
        η in (0, 1]; default 1.
    inertia_kg_m2 : float, optional
        The gearbox's inertia at its input (the motor side) [kg·m²], ≥ 0; default 0.

    Raises
    ------
    InputError
        If the ratio is not > 0, the efficiency not in (0, 1] or the inertia < 0.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.servo.Gearbox(5.0, efficiency=0.95).ratio
    5.0
    """

    ratio: float
    efficiency: float = 1.0
    inertia_kg_m2: float = 0.0

    def __post_init__(self) -> None:
        ratio = positive("ratio", self.ratio, "(gear ratio: motor speed / load speed)")
        eta = _efficiency("efficiency", self.efficiency)
        inertia = finite_number("inertia_kg_m2", self.inertia_kg_m2, "[kg·m²]", low=0.0)
        object.__setattr__(self, "ratio", ratio)
        object.__setattr__(self, "efficiency", eta)
        object.__setattr__(self, "inertia_kg_m2", inertia)


@dataclass(frozen=True)
class RotaryLoad:
    """A rotary load: the slave coordinate is the load shaft's angle [rad].

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    inertia_kg_m2 : float
        The load's inertia at the load shaft [kg·m²], ≥ 0.
    torque_nm : float, optional
        A constant load torque at the load shaft [N·m], signed: > 0 resists
        positive rotation (a process torque, an unbalanced weight's mean), < 0
        aids it; default 0.

    Raises
    ------
    InputError
        If the inertia is negative or a value is not a finite number.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.servo.RotaryLoad(0.02, torque_nm=1.5).torque_nm
    1.5
    """

    inertia_kg_m2: float
    torque_nm: float = 0.0

    def __post_init__(self) -> None:
        inertia = finite_number("inertia_kg_m2", self.inertia_kg_m2, "[kg·m²]", low=0.0)
        torque = finite_number("torque_nm", self.torque_nm, "[N·m]")
        object.__setattr__(self, "inertia_kg_m2", inertia)
        object.__setattr__(self, "torque_nm", torque)

    def _shaft(self) -> tuple[float, float, float, float]:
        """(k, J_L, T_ext, η): load-shaft angle per slave unit, the inertia and
        the torque at the load shaft, the efficiency between them (1)."""
        return 1.0, self.inertia_kg_m2, self.torque_nm, 1.0


@dataclass(frozen=True)
class LinearLoad:
    """A linear load driven through a ball screw (or a belt pulley, or a rack).

    The slave coordinate is the load's position x [m]. A screw of lead ``lead_m``
    turns its shaft by φ_L = 2π·x/lead; for a belt pulley or a rack and pinion of
    pitch radius r, lead = 2π·r. At the screw shaft: the reflected inertia
    m·(lead/2π)² and the torque (F + m·ẍ)·lead/(2π), divided by the screw's
    efficiency where the motor drives the load (the power (F + m·ẍ)·ẋ > 0, or the
    load at rest: a holding force) and multiplied by it where the load drives the
    screw. Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    mass_kg : float
        The moving mass [kg], ≥ 0.
    lead_m : float
        The screw's lead: travel per revolution of its shaft [m], > 0.
    force_n : float, optional
        A constant force on the load [N], signed: > 0 resists positive motion (a
        process force; the weight m·g of a vertical axis whose +x is up), < 0
        aids it; default 0. Friction that changes sign with the motion is not
        modelled.
    efficiency : float, optional
        The screw's (or belt's) efficiency in (0, 1]; default 1.

    Raises
    ------
    InputError
        If the mass is negative, the lead not > 0, the efficiency not in (0, 1].

    Examples
    --------
    >>> import cyclomech as cm
    >>> load = cm.servo.LinearLoad(mass_kg=20.0, lead_m=0.01, force_n=50.0)
    >>> round(load.mass_kg * (load.lead_m / 6.283185307179586) ** 2, 9)  # [kg·m²]
    5.0661e-05
    """

    mass_kg: float
    lead_m: float
    force_n: float = 0.0
    efficiency: float = 1.0

    def __post_init__(self) -> None:
        mass = finite_number("mass_kg", self.mass_kg, "[kg]", low=0.0)
        lead = positive("lead_m", self.lead_m, "[m per revolution]")
        force = finite_number("force_n", self.force_n, "[N]")
        eta = _efficiency("efficiency", self.efficiency)
        for key, value in (
            ("mass_kg", mass),
            ("lead_m", lead),
            ("force_n", force),
            ("efficiency", eta),
        ):
            object.__setattr__(self, key, value)

    def _shaft(self) -> tuple[float, float, float, float]:
        """(k, J_L, T_ext, η): the screw shaft's angle per metre 2π/lead, the
        reflected inertia m·(lead/2π)², the force's torque F·lead/2π, the screw's
        efficiency."""
        r = self.lead_m / (2.0 * math.pi)
        return 1.0 / r, self.mass_kg * r * r, self.force_n * r, self.efficiency
