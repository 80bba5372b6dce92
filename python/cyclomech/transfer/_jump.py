"""The jump of the workpiece's acceleration where two pitch circles touch, without
a transition (:func:`acceleration_jump`, :func:`acceleration_jump_at_speed`)."""

from __future__ import annotations

from typing import Any

from .._arrays import broadcast as _broadcast
from .._errors import InputError
from ._checks import _finite_array, _scalar

__all__ = ["acceleration_jump", "acceleration_jump_at_speed"]


def acceleration_jump(R_t: Any, omega_t: Any, R_p: Any, omega_p: Any) -> Any:
    """ΔW = R_p·ω_p² + R_t·ω_t² [m/s²]: the workpiece's acceleration jump at the contact.

    The jump of the workpiece's acceleration where the pitch circles touch: the two
    centripetal accelerations point at opposite centres, so they add.

    Parameters
    ----------
    R_t : float or array_like of float
        The pitch radius of the first rotor [m] (> 0). All four broadcast.
    omega_t : float or array_like of float
        Its angular speed [rad/s].
    R_p : float or array_like of float
        The pitch radius of the second rotor [m] (> 0).
    omega_p : float or array_like of float
        Its angular speed [rad/s].

    Returns
    -------
    float or ndarray of float
        The acceleration jump ΔW [m/s²]: a float for scalars, else an array of the
        broadcast shape.

    Raises
    ------
    InputError
        If a value is not finite, a radius is not positive, or the shapes do not
        broadcast.

    Examples
    --------
    >>> import cyclomech as cm
    >>> round(cm.transfer.acceleration_jump(0.15, 2.0, 0.25, 1.2), 6)   # 0.36 + 0.6
    0.96
    """
    r_t = _finite_array("R_t", R_t, "[m]")
    r_p = _finite_array("R_p", R_p, "[m]")
    w_t = _finite_array("omega_t", omega_t, "[rad/s]")
    w_p = _finite_array("omega_p", omega_p, "[rad/s]")
    for name, r in (("R_t", r_t), ("R_p", r_p)):
        if (r <= 0).any():
            raise InputError(f"{name} must be > 0 m (a pitch radius); got {r.min()!r}")
    r_t, w_t, r_p, w_p = _broadcast(R_t=r_t, omega_t=w_t, R_p=r_p, omega_p=w_p)
    return _scalar(r_p * w_p**2 + r_t * w_t**2)


def acceleration_jump_at_speed(speed: Any, R_t: Any, R_p: Any) -> Any:
    """ΔW = V²/R_t + V²/R_p [m/s²]: :func:`acceleration_jump` at equal peripheral speeds.

    The peripheral speeds V = R_t·ω_t = R_p·ω_p.

    Parameters
    ----------
    speed : float or array_like of float
        The peripheral speed V [m/s]; its sign (the direction of travel) does not
        change the jump, V²·(1/R_t + 1/R_p). All three broadcast.
    R_t : float or array_like of float
        The pitch radius of the first rotor [m] (> 0).
    R_p : float or array_like of float
        The pitch radius of the second rotor [m] (> 0).

    Returns
    -------
    float or ndarray of float
        The acceleration jump ΔW [m/s²]: a float for scalars, else an array of the
        broadcast shape.

    Raises
    ------
    InputError
        If a value is not finite, a radius is not positive, or the shapes do not
        broadcast.

    Examples
    --------
    >>> import cyclomech as cm
    >>> round(cm.transfer.acceleration_jump_at_speed(0.3, 0.15, 0.25), 6)   # 0.6 + 0.36
    0.96
    """
    v = _finite_array("speed", speed, "[m/s]")
    r_t = _finite_array("R_t", R_t, "[m]")
    r_p = _finite_array("R_p", R_p, "[m]")
    if (r_t <= 0).any() or (r_p <= 0).any():
        raise InputError(f"R_t and R_p must be > 0 m; got {r_t.min()!r}, {r_p.min()!r}")
    v, r_t, r_p = _broadcast(speed=v, R_t=r_t, R_p=r_p)
    return _scalar(v**2 / r_t + v**2 / r_p)
