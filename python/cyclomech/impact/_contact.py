"""The stop as a unilateral contact, solved exactly event by event
(:func:`contact_response`, :func:`contact_sample`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number, float_array, positive
from ._checks import Array, _nonnegative

__all__ = ["ContactHistory", "contact_response", "contact_sample"]


@dataclass(frozen=True)
class ContactHistory:
    """The motion of a link on a unilateral stop (see :func:`contact_response`).

    Built by :func:`contact_response`; each parameter is kept as the attribute of
    the same name. The per-contact arrays have one entry per contact, the
    per-flight arrays one per free flight after a contact.

    Parameters
    ----------
    contact_start : ndarray of float
        Per contact: the time it starts [s].
    contact_end : ndarray of float
        Per contact: the time it ends [s].
    impact_velocity : ndarray of float
        Per contact: the velocity at the start [m/s].
    exit_velocity : ndarray of float
        Per contact: the velocity at the end [m/s].
    contact_duration : ndarray of float
        Per contact: its duration [s].
    penetration : ndarray of float
        Per contact: the deepest point [m] (x < 0).
    penetration_time : ndarray of float
        Per contact: the time of the deepest point [s].
    rebound_height : ndarray of float
        Per free flight after a contact: its top [m].
    rebound_time : ndarray of float
        Per free flight after a contact: the time of its top [s].
    n_events : int
        The number of events (crossings of x = 0) located.
    end : str
        Why the history stops: ``"rest_in_contact"``, ``"rest_free"``, ``"t_end"``,
        ``"max_rebounds"`` or ``"max_events"`` (chattering capped).
    t_stop : float
        The time where the history stops [s].
    x_stop : float
        The position there [m].
    v_stop : float
        The velocity there [m/s].

    See Also
    --------
    contact_response : Builds it.

    Examples
    --------
    >>> import cyclomech as cm
    >>> h = cm.impact.contact_response(mass=1.0, k_free=1.0, k_stop=99.0, v0=-1.0, max_rebounds=1)
    >>> h.end, h.contact_start.tolist(), h.x_stop
    ('max_rebounds', [0.0], 1.0)
    """

    contact_start: Array
    contact_end: Array
    impact_velocity: Array
    exit_velocity: Array
    contact_duration: Array
    penetration: Array
    penetration_time: Array
    rebound_height: Array
    rebound_time: Array
    n_events: int
    end: str
    t_stop: float
    x_stop: float
    v_stop: float


def _contact_args(
    mass: float, k_free: float, k_stop: float, preload: float, zeta_free: float, zeta_contact: float
) -> tuple[float, float, float, float, float, float]:
    return (
        positive("mass", mass, "[kg]"),
        positive("k_free", k_free, "[N/m]"),
        positive("k_stop", k_stop, "[N/m]"),
        _nonnegative("preload", preload, "[m]"),
        _nonnegative("zeta_free", zeta_free, "(damping ratio)"),
        _nonnegative("zeta_contact", zeta_contact, "(damping ratio)"),
    )


def contact_response(
    *,
    mass: float,
    k_free: float,
    k_stop: float,
    preload: float = 0.0,
    zeta_free: float = 0.0,
    zeta_contact: float = 0.0,
    x0: float = 0.0,
    v0: float,
    t_end: float = math.inf,
    max_rebounds: int = 1000,
) -> ContactHistory:
    """The link on its stop as a unilateral contact, solved exactly event by event.

    The link moves along x with the stop at x = 0: free for x > 0 under the spring
    −k_free·(x + preload) (its equilibrium ``preload`` inside the stop, so at rest it
    presses on it with k_free·preload [N]), in contact for x < 0 with the stop's
    spring −k_stop·x added. Each regime is an oscillator solved in closed form,
    damped by its own ratio (``zeta_free``, ``zeta_contact``); every crossing of
    x = 0 is located on the closed form (bracketed between its extrema, Newton with
    bisection), so the contact times and the rebounds come out of the model instead
    of an assumed τ.

    Parameters
    ----------
    mass : float
        The link's mass [kg] (> 0). Keyword-only, as are all the parameters.
    k_free : float
        The stiffness of the free regime's spring [N/m] (> 0).
    k_stop : float
        The stop's stiffness, added in contact [N/m] (> 0).
    preload : float, default 0.0
        The free spring's equilibrium inside the stop [m] (≥ 0).
    zeta_free : float, default 0.0
        The damping ratio of the free regime (≥ 0).
    zeta_contact : float, default 0.0
        The damping ratio in contact (≥ 0).
    x0 : float, default 0.0
        The starting position [m].
    v0 : float
        The starting velocity [m/s] (v0 < 0: arriving at the stop).
    t_end : float, default inf
        The time to stop at [s] (> 0, or inf).
    max_rebounds : int, default 1000
        The number of rebounds to stop after.

    Returns
    -------
    ContactHistory
        The contacts, the rebounds, and why and where the history stops.

    Raises
    ------
    InputError
        If a stiffness or the mass is not finite and positive, ``preload`` or a
        damping ratio is negative, ``x0`` or ``v0`` is not finite, ``t_end`` is not
        positive or ``max_rebounds`` is not a count.

    Examples
    --------
    >>> import math, cyclomech as cm
    >>> h = cm.impact.contact_response(mass=1.0, k_free=1.0, k_stop=99.0, v0=-1.0, max_rebounds=1)
    >>> round(float(h.contact_duration[0]) / (math.pi / 10), 12)   # half period at √(100/1)
    1.0
    >>> round(float(h.rebound_height[0]), 12)                     # undamped: v0·√(m/k_free)
    1.0
    """
    args = _contact_args(mass, k_free, k_stop, preload, zeta_free, zeta_contact)
    end = t_end if t_end == math.inf else positive("t_end", t_end, "[s] (or inf)")
    d = _core.contact_response(
        *args,
        finite_number("x0", x0, "[m]"),
        finite_number("v0", v0, "[m/s]"),
        t_end=end,
        max_rebounds=count("max_rebounds", max_rebounds),
    )
    return ContactHistory(**d)


def contact_sample(
    times: npt.ArrayLike,
    *,
    mass: float,
    k_free: float,
    k_stop: float,
    preload: float = 0.0,
    zeta_free: float = 0.0,
    zeta_contact: float = 0.0,
    x0: float = 0.0,
    v0: float,
) -> tuple[Array, Array]:
    """x(t) [m] and ẋ(t) [m/s] of :func:`contact_response`'s motion at given times.

    By the same piecewise closed form.

    Parameters
    ----------
    times : array_like of float, shape (N,)
        The times [s] (non-decreasing, ≥ 0).
    mass : float
        The link's mass [kg] (> 0). Keyword-only, as are the parameters below.
    k_free : float
        The stiffness of the free regime's spring [N/m] (> 0).
    k_stop : float
        The stop's stiffness, added in contact [N/m] (> 0).
    preload : float, default 0.0
        The free spring's equilibrium inside the stop [m] (≥ 0).
    zeta_free : float, default 0.0
        The damping ratio of the free regime (≥ 0).
    zeta_contact : float, default 0.0
        The damping ratio in contact (≥ 0).
    x0 : float, default 0.0
        The starting position [m].
    v0 : float
        The starting velocity [m/s] (v0 < 0: arriving at the stop).

    Returns
    -------
    x : ndarray of float, shape (N,)
        The position at each time [m].
    v : ndarray of float, shape (N,)
        The velocity ẋ at each time [m/s].

    Raises
    ------
    InputError
        If an argument is out of range (as :func:`contact_response`) or ``times``
        is not a 1-D array of non-decreasing times ≥ 0.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> x, v = cm.impact.contact_sample([0.0, np.pi / 20], mass=1.0, k_free=1.0, k_stop=99.0,
    ...                                 v0=-1.0)
    >>> round(float(x[1]), 12)                          # deepest at a quarter contact period
    -0.1
    """
    args = _contact_args(mass, k_free, k_stop, preload, zeta_free, zeta_contact)
    ts = float_array("times", times, ndims=(1,))
    return _core.contact_sample(
        *args, finite_number("x0", x0, "[m]"), finite_number("v0", v0, "[m/s]"), ts
    )


def _restitution_damping(k: float) -> float:
    """Damping ratio of a linear contact whose rebound speed is k times the
    impact speed: k = exp(−ζπ/√(1 − ζ²)) ⇒ ζ = −ln k/√(π² + ln² k) (1 for k = 0)."""
    if k <= 0.0:
        return 1.0
    lk = math.log(k)
    return -lk / math.sqrt(math.pi**2 + lk * lk)
