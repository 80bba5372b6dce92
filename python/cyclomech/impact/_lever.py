"""The lever of a stop (seed 000): its reduced stiffness free and propped at the
stop, natural frequency, contact time and the mean impact force."""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import broadcast, finite_number, positive, real_array
from .._errors import InputError
from ._checks import Array, _positive_array

__all__ = [
    "contact_time",
    "impact_force",
    "lever_stiffness",
    "natural_frequency",
    "propped_lever_stiffness",
]


def lever_stiffness(E: float, J_x: float, a: float, b: float) -> float:
    """Reduced stiffness [N/m] of the lever at its working end, free of the stop.

    The lever as a beam on two supports a [m] apart (its axis and the cam
    roller) with an overhang b [m] to the working point: c = 3·E·J_x/((a+b)·b²)
    (seed 000).

    Parameters
    ----------
    E : float
        Young's modulus of the lever's material [Pa].
    J_x : float
        The section's axial moment of inertia [m⁴].
    a : float
        Distance between the two supports (the lever's axis and the cam roller) [m].
    b : float
        The overhang from the roller support to the working point [m].

    Returns
    -------
    float
        The reduced stiffness c at the working end [N/m].

    Raises
    ------
    InputError
        If a value is not a finite positive number, or the values overflow or
        underflow (scale the units).

    Examples
    --------
    >>> import cyclomech as cm
    >>> round(cm.impact.lever_stiffness(2.1e11, 6.1e-11, 0.05, 0.1))
    25620
    """
    E = positive("E", E, "[Pa]")
    J = positive("J_x", J_x, "[m⁴]")
    a = positive("a", a, "[m]")
    b = positive("b", b, "[m]")
    with np.errstate(all="ignore"):
        c = 3.0 * np.float64(E) * J / ((a + b) * b * b)
    return _stiffness(c, E=E, J_x=J, a=a, b=b)


def _stiffness(c: Any, **given: float) -> float:
    """``c`` [N/m] if it is a finite, positive float, else :class:`InputError`:
    inputs of extreme magnitude overflow or underflow (scale the units)."""
    if not (np.isfinite(c) and c > 0.0):
        args = ", ".join(f"{k} = {v!r}" for k, v in given.items())
        raise InputError(
            f"the lever {args} gives a stiffness of {float(c)!r} N/m, not a finite positive "
            "number: the values overflow or underflow; scale the units"
        )
    return float(c)


def _moment(z: Array, xi: float, a: float) -> Array:
    """Bending moment at z of the two-support overhanging beam (supports at 0 and
    a) under a unit load at xi (the statically determinate base)."""
    if xi >= a:  # on the overhang: R_A = −(xi − a)/a
        return np.where(z <= a, -(xi - a) * z / a, np.where(z <= xi, -(xi - z), 0.0))
    return np.where(z <= xi, (a - xi) * z / a, np.where(z <= a, xi * (a - z) / a, 0.0))


def _flexibility(xi: float, xj: float, a: float, length: float, EJ: float) -> float:
    """∫ m_i·m_j dz / EJ over the beam, exact: Simpson's rule on each piece
    between the diagrams' breakpoints (the product is quadratic there)."""
    edges = np.unique(np.array([0.0, a, xi, xj, length]))
    lo, hi = edges[:-1], edges[1:]
    mid = 0.5 * (lo + hi)
    f = [_moment(z, xi, a) * _moment(z, xj, a) for z in (lo, mid, hi)]
    return float(np.sum((hi - lo) / 6.0 * (f[0] + 4.0 * f[1] + f[2]))) / EJ


def propped_lever_stiffness(
    E: float, J_x: float, a: float, b: float, at: float | None = None
) -> tuple[float, float]:
    """Stiffness [N/m] of the lever at a point of its overhang, free and propped.

    Free of the stop, and with its working end resting on the stop. In contact the
    stop adds a support at the end of the overhang (seed 000, fig. 6), so the
    reduced mass, now between two supports, vibrates faster. The beam is as in
    :func:`lever_stiffness`. Computed by the force method: the overhanging beam is
    the base, the stop's reaction the redundant; its flexibility
    f_mm − f_mc²/f_cc = s²(b − s)²(4ab + 4bs − s²)/(12b²(a + b)·E·J_x) (s = ``at``) is
    taken in that factored form, accurate to rounding up to the stop.

    Parameters
    ----------
    E : float
        Young's modulus of the lever's material [Pa].
    J_x : float
        The section's axial moment of inertia [m⁴].
    a : float
        Distance between the two supports (the lever's axis and the cam roller) [m].
    b : float
        The overhang from the roller support to the working end [m].
    at : float, optional
        Distance of the point from the roller support along the overhang [m],
        0 < at < b; default None (b/2).

    Returns
    -------
    free : float
        The stiffness at the point, free of the stop [N/m].
    propped : float
        The stiffness at the point with the working end resting on the stop [N/m].

    Raises
    ------
    InputError
        If a value is not a finite positive number, ``at`` does not lie inside the
        overhang, or the values overflow or underflow (scale the units).

    Examples
    --------
    >>> import cyclomech as cm
    >>> free, propped = cm.impact.propped_lever_stiffness(2.1e11, 6.1e-11, 0.05, 0.1)
    >>> round(free), round(propped / free, 2)
    (153720, 6.4)
    """
    E = positive("E", E, "[Pa]")
    J = positive("J_x", J_x, "[m⁴]")
    a = positive("a", a, "[m]")
    b = positive("b", b, "[m]")
    s = 0.5 * b if at is None else positive("at", at, "[m]")
    if s >= b:
        raise InputError(
            f"at = {at!r} m must lie inside the overhang, 0 < at < b = {b!r} m "
            "(at the stop itself the propped lever does not move)"
        )
    with np.errstate(all="ignore"):
        EJ, length = np.float64(E) * J, a + b
        x = a + s
        f_mm = np.float64(_flexibility(x, x, a, length, EJ))
        # The force method's f_mm − f_mc²/f_cc (c the stop at the end), factored:
        # s²(b − s)²(4ab + 4bs − s²)/(12b²(a + b)EJ). As written it cancelled as the
        # point neared the stop (3 % off at at = b(1 − 1e-7), overflow at 1e-8);
        # factored, each term is positive.
        d = np.float64(b) - s
        propped_f = s * s * d * d * (4.0 * a * b + 4.0 * b * s - s * s)
        propped_f = propped_f / (12.0 * b * b * (a + b) * EJ)
        free, propped = 1.0 / f_mm, 1.0 / propped_f
    given = {"E": E, "J_x": J, "a": a, "b": b, "at": s}
    return _stiffness(free, **given), _stiffness(propped, **given)


@functools.lru_cache(maxsize=4096)
def _propped_ratio(a: float, b: float) -> float:
    """propped/free stiffness of :func:`propped_lever_stiffness` at the overhang's
    middle: E·J_x cancels, so it depends on the lever's geometry alone (remembered,
    as sweeps build a stop per design)."""
    free, propped = propped_lever_stiffness(1.0, 1.0, a, b)
    return propped / free


def natural_frequency(stiffness: npt.ArrayLike, mass: npt.ArrayLike) -> Any:
    """Natural frequency f = √(c/m)/(2π) [Hz] of a stiffness and a mass.

    Parameters
    ----------
    stiffness : float or array_like of float
        The stiffness c [N/m] (> 0); broadcasts with ``mass``.
    mass : float or array_like of float
        The mass m [kg] (> 0).

    Returns
    -------
    float or ndarray of float
        The natural frequency f [Hz], of the broadcast shape (a NumPy float for scalars).

    Raises
    ------
    InputError
        If a stiffness or a mass is not finite and positive.

    Examples
    --------
    >>> import cyclomech as cm
    >>> round(float(cm.impact.natural_frequency(25620.0, 7.4e-3)), 1)
    296.1
    """
    c, m = broadcast(
        stiffness=_positive_array("stiffness", stiffness, "[N/m]"),
        mass=_positive_array("mass", mass, "[kg]"),
    )
    return np.sqrt(c / m) / (2.0 * np.pi)


def contact_time(stiffness: npt.ArrayLike, mass: npt.ArrayLike) -> Any:
    """Half the period of the contact vibration, τ = π·√(m/c) [s].

    The seed's recommended duration of the impact.

    Parameters
    ----------
    stiffness : float or array_like of float
        The in-contact stiffness c [N/m] (> 0); broadcasts with ``mass``.
    mass : float or array_like of float
        The mass m [kg] (> 0).

    Returns
    -------
    float or ndarray of float
        The contact time τ [s], of the broadcast shape (a NumPy float for scalars).

    Raises
    ------
    InputError
        If a stiffness or a mass is not finite and positive.

    Examples
    --------
    >>> import cyclomech as cm
    >>> round(float(cm.impact.contact_time(172e3, 7.4e-3)) * 1e3, 3)   # ms
    0.652
    """
    c, m = broadcast(
        stiffness=_positive_array("stiffness", stiffness, "[N/m]"),
        mass=_positive_array("mass", mass, "[kg]"),
    )
    return np.pi * np.sqrt(m / c)


def impact_force(
    J_A: float,
    omega0: npt.ArrayLike,
    restitution: float,
    lever_length: float,
    contact_time: npt.ArrayLike,
) -> Any:
    """Mean force [N] of the impact at the stop: F = J_A·ω0·(1 + k)/(l·τ).

    The impulse J_A·ω0·(1+k)/l [N·s] stops the lever and throws it back with the
    restitution k, spread over the contact time τ (see :func:`contact_time`).

    Parameters
    ----------
    J_A : float
        The lever's moment of inertia about its axis [kg·m²].
    omega0 : float or array_like of float
        The lever's angular velocity at contact [rad/s] (≥ 0); broadcasts with
        ``contact_time``.
    restitution : float
        The coefficient of restitution k ∈ [0, 1] (0 plastic, 1 elastic; 5/9 for
        steel).
    lever_length : float
        The lever's length l [m].
    contact_time : float or array_like of float
        The contact time τ [s] (> 0).

    Returns
    -------
    float or ndarray of float
        The mean impact force F [N], of the broadcast shape (a NumPy float for scalars).

    Raises
    ------
    InputError
        If ``J_A``, ``lever_length`` or ``contact_time`` is not finite and positive,
        ``omega0`` is negative or not finite, or ``restitution`` lies outside [0, 1].

    Examples
    --------
    >>> import cyclomech as cm
    >>> round(float(cm.impact.impact_force(7.4e-5, 2.35, 5 / 9, 0.1, 6.52e-4)), 3)
    4.149
    """
    J = positive("J_A", J_A, "[kg·m²]")
    k = _restitution(restitution)
    length = positive("lever_length", lever_length, "[m]")
    w = real_array("omega0", omega0, "[rad/s]", low=0.0)
    tau = _positive_array("contact_time", contact_time, "[s]")
    return J * w * (1.0 + k) / (length * tau)


def _restitution(value: Any) -> float:
    k = finite_number("restitution", value, "(0 plastic, 1 elastic; 5/9 for steel)", low=0.0)
    if not k <= 1.0:
        raise InputError(
            f"restitution = {value!r} must lie in [0, 1] (0 plastic, 1 elastic; 5/9 for steel)"
        )
    return k
