"""The stops: `_model` part of :mod:`cyclomech.impact` (its door)."""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core, motion
from .._arrays import count, finite_number, float_array, positive, real, threads_arg
from .._errors import InfeasibleError, InputError
from .._units import RAD_PER_S_PER_RPM
from ..cyclogram import Constraint

__all__ = [
    "ContactHistory",
    "ImpactStudy",
    "Pulse",
    "Rebound",
    "StopImpact",
    "contact_response",
    "contact_sample",
    "contact_time",
    "critical_speeds",
    "duhamel",
    "duhamel_batch",
    "first_rebound",
    "impact_force",
    "lever_stiffness",
    "natural_frequency",
    "phase_angles",
    "propped_lever_stiffness",
    "rebounds",
]

Array = npt.NDArray[np.float64]


def _nonnegative(name: str, value: Any, unit: str) -> float:
    return finite_number(name, value, unit, low=0.0)


#: Relative tolerances a search can meet: rounding of the rebounds is ~1e-16, so
#: below 1e-15 a tolerance would be claimed but not met; 1 or more is no
#: tolerance at all (the bracket [0, v] already meets it).
_RTOL_RANGE = (1e-15, 0.5)


def _rtol(name: str, value: Any, scale: float = 1.0, unit: str = "(relative)") -> float:
    """A tolerance in [1e-15, 0.5]·``scale``, or :class:`InputError` with the range."""
    lo, hi = _RTOL_RANGE[0] * scale, _RTOL_RANGE[1] * scale
    v = finite_number(name, value, unit, low=0.0, strict=True)
    if not lo <= v <= hi:
        raise InputError(f"{name} = {value!r} must lie in [{lo:g}, {hi:g}] {unit}")
    return v


def _force(value: Any, name: str = "peak", unit: str = "[N]") -> float:
    return finite_number(name, value, unit)


def _positive_array(name: str, value: Any, unit: str) -> Array:
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be positive numbers {unit}; got {value!r}") from None
    bad = ~(np.isfinite(a) & (a > 0.0))
    if bad.any():
        if a.ndim:
            i = tuple(int(k) for k in np.unravel_index(int(np.argmax(bad)), a.shape))
            where, v = f"{name}{list(i)}", float(a[i])
        else:
            where, v = name, float(a)
        raise InputError(f"{where} = {v!r} must be finite and > 0 {unit}")
    return a


def lever_stiffness(E: float, J_x: float, a: float, b: float) -> float:
    """Reduced stiffness [N/m] of the lever at its working end, free of the stop.

    The lever as a beam on two supports a [m] apart (its axis and the cam
    roller) with an overhang b [m] to the working point: c = 3·E·J_x/((a+b)·b²),
    E [Pa], J_x [m⁴] the section's axial moment of inertia (seed 000).

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
    """Stiffness [N/m] of the lever at a point of its overhang, free and with its
    working end resting on the stop: ``(free, propped)``.

    In contact the stop adds a support at the end of the overhang (seed 000,
    fig. 6), so the reduced mass, now between two supports, vibrates faster. The
    point lies ``at`` [m] from the roller support along the overhang (default
    b/2); the beam is as in :func:`lever_stiffness`. Computed by the force
    method: the overhanging beam is the base, the stop's reaction the redundant.

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
        f_mc = np.float64(_flexibility(x, length, a, length, EJ))
        f_cc = np.float64(_flexibility(length, length, a, length, EJ))
        free, propped = 1.0 / f_mm, 1.0 / (f_mm - f_mc * f_mc / f_cc)
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
    """Natural frequency f = √(c/m)/(2π) [Hz] of stiffness c [N/m] and mass m [kg]
    (arrays broadcast).

    >>> import cyclomech as cm
    >>> round(float(cm.impact.natural_frequency(25620.0, 7.4e-3)), 1)
    296.1
    """
    c = _positive_array("stiffness", stiffness, "[N/m]")
    m = _positive_array("mass", mass, "[kg]")
    return np.sqrt(c / m) / (2.0 * np.pi)


def contact_time(stiffness: npt.ArrayLike, mass: npt.ArrayLike) -> Any:
    """Half the period of the contact vibration, τ = π·√(m/c) [s]: the seed's
    recommended duration of the impact (c [N/m] the in-contact stiffness).

    >>> import cyclomech as cm
    >>> round(float(cm.impact.contact_time(172e3, 7.4e-3)) * 1e3, 3)   # ms
    0.652
    """
    c = _positive_array("stiffness", stiffness, "[N/m]")
    m = _positive_array("mass", mass, "[kg]")
    return np.pi * np.sqrt(m / c)


_half_period = contact_time  # for StopImpact, whose argument shadows the name


def impact_force(
    J_A: float,
    omega0: npt.ArrayLike,
    restitution: float,
    lever_length: float,
    contact_time: npt.ArrayLike,
) -> Any:
    """Mean force [N] of the impact at the stop: F = J_A·ω0·(1 + k)/(l·τ).

    The impulse J_A·ω0·(1+k)/l [N·s] stops the lever (inertia J_A [kg·m²],
    angular velocity ω0 [rad/s] at contact, length l [m]) and throws it back with
    the restitution k ∈ [0, 1] (5/9 for steel), spread over the contact time τ
    [s] (see :func:`contact_time`). ω0 and τ broadcast.

    >>> import cyclomech as cm
    >>> round(float(cm.impact.impact_force(7.4e-5, 2.35, 5 / 9, 0.1, 6.52e-4)), 3)
    4.149
    """
    J = positive("J_A", J_A, "[kg·m²]")
    k = _restitution(restitution)
    length = positive("lever_length", lever_length, "[m]")
    w = np.asarray(omega0, dtype=np.float64)
    if not np.isfinite(w).all() or (w < 0).any():
        raise InputError(f"omega0 must be finite and ≥ 0 [rad/s]; got {omega0!r}")
    tau = _positive_array("contact_time", contact_time, "[s]")
    return J * w * (1.0 + k) / (length * tau)


def _restitution(value: Any) -> float:
    try:
        k = float(value)
    except (TypeError, ValueError):
        raise InputError(f"restitution must be a number in [0, 1]; got {value!r}") from None
    if not 0.0 <= k <= 1.0:
        raise InputError(
            f"restitution = {value!r} must lie in [0, 1] (0 plastic, 1 elastic; 5/9 for steel)"
        )
    return k


@dataclass(frozen=True)
class Pulse:
    """A force pulse as a piecewise-linear table: force ``f`` [N] at times ``t``
    [s] (non-decreasing from 0; a repeated time is a jump of the force there),
    zero after the last point unless the table says otherwise.

    Named shapes: :meth:`rectangular`, :meth:`decaying` (the seed's fig. 7 law),
    :meth:`triangular`, :meth:`half_sine`; any table by :meth:`table`.

    >>> import cyclomech as cm
    >>> p = cm.impact.Pulse.rectangular(2.0, 1e-3)
    >>> p.t.tolist(), p.f.tolist(), round(p.impulse, 12)
    ([0.0, 0.001, 0.001], [2.0, 2.0, 0.0], 0.002)
    """

    t: Array
    f: Array
    shape: str = "table"

    @property
    def duration(self) -> float:
        """Time of the last point [s].

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.triangular(1.0, 2e-3).duration
        0.002
        """
        return float(self.t[-1])

    @property
    def peak(self) -> float:
        """Largest |force| [N].

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.decaying(3.0, 1e-3).peak
        3.0
        """
        return float(np.abs(self.f).max())

    @property
    def impulse(self) -> float:
        """∫ F dt [N·s] (exact for the linear pieces).

        >>> import cyclomech as cm
        >>> round(cm.impact.Pulse.decaying(3.0, 1e-3).impulse, 12)
        0.0015
        """
        return float(np.sum(np.diff(self.t) * 0.5 * (self.f[1:] + self.f[:-1])))

    def scaled(self, factor: float) -> Pulse:
        """The same shape with every force times ``factor``.

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.rectangular(1.0, 1e-3).scaled(4.0).peak
        4.0
        """
        return Pulse.table(self.t, self.f * _force(factor, "factor", ""), self.shape)

    @classmethod
    def table(cls, t: npt.ArrayLike, f: npt.ArrayLike, shape: str = "table") -> Pulse:
        """A pulse from a user table; ``t`` [s] starts at 0 and never decreases.

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.table([0, 1e-3, 2e-3], [0, 5, 0]).peak
        5.0
        """
        ta = np.array(t, dtype=np.float64, ndmin=1)
        fa = np.array(f, dtype=np.float64, ndmin=1)
        if ta.ndim != 1 or fa.shape != ta.shape:
            raise InputError(
                f"a pulse table needs t and f as 1-D arrays of one length; "
                f"got shapes {ta.shape} and {fa.shape}"
            )
        if ta.size < 2:
            raise InputError(f"a pulse table needs at least 2 points; got {ta.size}")
        for name, a in (("t", ta), ("f", fa)):
            bad = ~np.isfinite(a)
            if bad.any():
                i = int(np.argmax(bad))
                raise InputError(f"pulse {name}[{i}] = {float(a[i])!r} must be finite")
        if ta[0] != 0.0:
            raise InputError(f"pulse t[0] = {float(ta[0])!r} must be 0 (the instant of impact)")
        down = np.diff(ta) < 0
        if down.any():
            i = int(np.argmax(down)) + 1
            raise InputError(
                f"pulse t must not decrease: t[{i}] = {float(ta[i])!r} < "
                f"t[{i - 1}] = {float(ta[i - 1])!r} "
                "(repeat a time for a jump)"
            )
        if ta[-1] <= 0.0:
            raise InputError("a pulse must last: its last time must be > 0 s")
        ta.flags.writeable = False
        fa.flags.writeable = False
        return cls(ta, fa, shape)

    @classmethod
    def rectangular(cls, peak: float, duration: float) -> Pulse:
        """Constant ``peak`` [N] for ``duration`` [s], then zero.

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.rectangular(1.0, 1e-3).f.tolist()
        [1.0, 1.0, 0.0]
        """
        p, d = _force(peak), positive("duration", duration, "[s]")
        return cls.table([0.0, d, d], [p, p, 0.0], "rectangular")

    @classmethod
    def decaying(cls, peak: float, duration: float, end: float = 0.0) -> Pulse:
        """The seed's impact law (fig. 7): ``peak`` [N] at the instant of impact,
        falling linearly to ``end``·peak at ``duration`` [s], then zero (``end`` =
        0: a decaying triangle; the seed's printed F·(1 − t/2τ) is ``end`` = ½).

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.decaying(2.0, 1e-3, end=0.5).f.tolist()
        [2.0, 1.0, 0.0]
        """
        p, d = _force(peak), positive("duration", duration, "[s]")
        end = _force(end, "end", "(a fraction of the peak)")
        if not 0.0 <= end <= 1.0:
            raise InputError(f"end = {end!r} must lie in [0, 1] (a fraction of the peak)")
        if end == 0.0:
            return cls.table([0.0, d], [p, 0.0], "decaying")
        return cls.table([0.0, d, d], [p, end * p, 0.0], "decaying")

    @classmethod
    def triangular(cls, peak: float, duration: float) -> Pulse:
        """Rising linearly to ``peak`` [N] at half the ``duration`` [s], back to zero.

        >>> import cyclomech as cm
        >>> cm.impact.Pulse.triangular(1.0, 2e-3).t.tolist()
        [0.0, 0.001, 0.002]
        """
        p, d = _force(peak), positive("duration", duration, "[s]")
        return cls.table([0.0, 0.5 * d, d], [0.0, p, 0.0], "triangular")

    @classmethod
    def half_sine(cls, peak: float, duration: float, points: int = 257) -> Pulse:
        """``peak``·sin(πt/duration) over ``duration`` [s], sampled at ``points``
        points (linear between them: the table's impulse falls short of the
        sine's by about (π²/12)/(points−1)² relative).

        >>> import cyclomech as cm
        >>> p = cm.impact.Pulse.half_sine(1.0, 1e-3)
        >>> round(p.impulse / (2e-3 / 3.141592653589793), 5)
        0.99999
        """
        p, d = _force(peak), positive("duration", duration, "[s]")
        t = np.linspace(0.0, d, count("points", points, low=3, high=10**7))
        f = p * np.sin(np.pi * t / d)
        f[-1] = 0.0
        return cls.table(t, f, "half_sine")


# --- kernels ------------------------------------------------------------------------


def _grid(name: str, value: Any) -> Array:
    a = float_array(name, value, ndims=(1,))
    if a.size < 1:
        raise InputError(f"{name} must hold at least one time [s]")
    return a


def _cases(b: int, **fields: Any) -> list[Array]:
    """Each per-case field as a contiguous (b,) array (scalars broadcast)."""
    out = []
    for name, value in fields.items():
        a = float_array(name, value, ndims=(0, 1))
        if a.size == 1:
            a = np.full(b, float(a.reshape(-1)[0]))
        elif a.size != b:
            raise InputError(
                f"{name} must be a scalar or hold one value per case ({b}); got {a.size}"
            )
        out.append(np.ascontiguousarray(a))
    return out


def duhamel(
    t: npt.ArrayLike,
    force: npt.ArrayLike,
    *,
    omega_n: float,
    zeta: float,
    mass: float,
    q0: float = 0.0,
    v0: float = 0.0,
    velocity: bool = False,
) -> Any:
    """Exact response q(t) [m] of m·q̈ + 2ζω·m·q̇ + ω²·m·q = F(t) to a force F [N]
    linear between the samples of ``t`` [s] (first-order hold; the Duhamel
    integral in closed form from step to step, Nigam–Jennings), from q(t[0]) =
    ``q0`` [m], q̇(t[0]) = ``v0`` [m/s]; ``omega_n`` [rad/s] > 0, ``zeta`` ≥ 0
    (over- and critically damped exactly too), ``mass`` [kg] > 0.

    ``t`` never decreases; a repeated time is a jump of the force there, so a
    force that starts at full value at t[0] (an impact) is exact, and so is a
    rectangular pulse. ``velocity=True`` returns ``(q, q̇)``.

    >>> import numpy as np, cyclomech as cm
    >>> t = np.linspace(0.0, 1.0, 11)                    # a step force, undamped
    >>> q = cm.impact.duhamel(t, np.ones(11), omega_n=2.0, zeta=0.0, mass=1.0)
    >>> bool(np.allclose(q, (1 - np.cos(2 * t)) / 4, rtol=0, atol=1e-15))
    True
    """
    ta, fa = _grid("t", t), _grid("force", force)
    # Real numbers only (a string, bytes, a bool or a complex is refused, not
    # read as a number); the kernel checks their ranges and names them.
    return _core.duhamel(
        ta,
        fa,
        _real("omega_n", omega_n, "[rad/s]"),
        _real("zeta", zeta, "(damping ratio)"),
        _real("mass", mass, "[kg]"),
        _real("q0", q0, "[m]"),
        _real("v0", v0, "[m/s]"),
        with_velocity=_flag("velocity", velocity),
    )


def _real(name: str, value: Any, unit: str) -> float:
    """``value`` as a float if it is a real number (NaN and inf included: the
    kernels name those), else :class:`InputError`."""
    try:
        return real(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a real number {unit}; got {value!r}") from None


def _flag(name: str, value: Any) -> bool:
    """A bool (or numpy bool), or :class:`InputError`: 0, "no" or None are not flags."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise InputError(f"{name} must be True or False; got {value!r}")


def duhamel_batch(
    t: npt.ArrayLike,
    forces: npt.ArrayLike,
    omega_n: npt.ArrayLike,
    zeta: npt.ArrayLike,
    mass: npt.ArrayLike,
    q0: npt.ArrayLike = 0.0,
    v0: npt.ArrayLike = 0.0,
    *,
    n_threads: int | None = None,
) -> Any:
    """:func:`duhamel` for B cases on one time grid ``t`` (N,): ``forces`` (B, N)
    [N], per-case ``omega_n``, ``zeta``, ``mass``, ``q0``, ``v0`` (scalars or
    (B,)); returns q (B, N) [m], computed in parallel in Rust.

    >>> import numpy as np, cyclomech as cm
    >>> t = np.linspace(0.0, 0.01, 101)
    >>> q = cm.impact.duhamel_batch(t, np.ones((3, 101)), 2 * np.pi * 297, [0.0, 0.05, 1.0], 0.01)
    >>> q.shape
    (3, 101)
    """
    ta = _grid("t", t)
    fa = float_array("forces", forces, ndims=(2,))
    b = fa.shape[0]
    cases = _cases(b, omega_n=omega_n, zeta=zeta, mass=mass, q0=q0, v0=v0)
    return _core.duhamel_batch(ta, fa, *cases, n_threads=threads_arg(n_threads))


@dataclass(frozen=True)
class Rebound:
    """First rebounds of a batch: ``time`` [s] (+inf where q never turns) and
    ``q`` [m], each (B,)."""

    time: Array
    q: Array


def first_rebound(
    t: npt.ArrayLike,
    forces: npt.ArrayLike,
    omega_n: npt.ArrayLike,
    zeta: npt.ArrayLike,
    mass: npt.ArrayLike,
    q0: npt.ArrayLike = 0.0,
    v0: npt.ArrayLike = 0.0,
    *,
    maximum: bool = False,
    n_threads: int | None = None,
) -> Rebound:
    """The first turn of q(t) after t[0] for each case, without histories: the
    first extremum (``maximum=True``: the first local maximum), found exactly by
    stepping from breakpoint to breakpoint of the pulse table and solving for
    q̇ = 0 in closed form between them — O(breakpoints), not O(time steps).

    Arguments as :func:`duhamel_batch` (``forces`` may be 1-D for one case); the
    force is held at its last value after the table. Where q never turns,
    ``time`` is inf and ``q`` the static deflection of the last force.

    >>> import numpy as np, cyclomech as cm
    >>> w = 2 * np.pi * 297
    >>> r = cm.impact.first_rebound([0.0], [0.0], w, 0.0, 1.0, v0=1.0)  # free vibration
    >>> bool(np.isclose(r.q[0], 1 / w, rtol=1e-14)), bool(np.isclose(r.time[0], np.pi / 2 / w))
    (True, True)
    """
    ta = _grid("t", t)
    fa = float_array("forces", forces, ndims=(1, 2))
    if fa.ndim == 1:
        fa = fa.reshape(1, -1)
    b = fa.shape[0]
    cases = _cases(b, omega_n=omega_n, zeta=zeta, mass=mass, q0=q0, v0=v0)
    time, q = _core.first_rebound_batch(
        ta, fa, *cases, maximum=_flag("maximum", maximum), n_threads=threads_arg(n_threads)
    )
    return Rebound(time, q)


# --- the stop as a contact ----------------------------------------------------------


@dataclass(frozen=True)
class ContactHistory:
    """The motion of a link on a unilateral stop (see :func:`contact_response`).

    Per contact: ``contact_start``, ``contact_end`` [s], ``impact_velocity``,
    ``exit_velocity`` [m/s], ``contact_duration`` [s], the deepest point
    ``penetration`` [m] (x < 0) at ``penetration_time`` [s]; per free flight
    after a contact: its top ``rebound_height`` [m] at ``rebound_time`` [s].
    ``end`` says why the history stops: ``"rest_in_contact"``, ``"rest_free"``,
    ``"t_end"``, ``"max_rebounds"`` or ``"max_events"`` (chattering capped);
    ``t_stop``, ``x_stop``, ``v_stop`` the state there.
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
) -> tuple[float, ...]:
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

    The link (``mass`` [kg]) moves along x with the stop at x = 0: free for x > 0
    under the spring −k_free·(x + preload) (its equilibrium ``preload`` [m]
    inside the stop, so at rest it presses on it with k_free·preload [N]), in
    contact for x < 0 with the stop's spring −k_stop·x added. Each regime is an
    oscillator solved in closed form, damped by its own ratio (``zeta_free``,
    ``zeta_contact``); every crossing of x = 0 is located on the closed form
    (bracketed between its extrema, Newton with bisection), so the contact
    times and the rebounds come out of the model instead of an assumed τ.
    Starts at ``x0`` [m] with ``v0`` [m/s] (v0 < 0: arriving at the stop).

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
    """x(t) [m] and ẋ(t) [m/s] of :func:`contact_response`'s motion at ``times``
    [s] (non-decreasing, ≥ 0), by the same piecewise closed form.

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


# --- the lever and its stop ---------------------------------------------------------

_PULSES = ("decaying", "rectangular", "triangular", "half_sine")


def _restitution_damping(k: float) -> float:
    """Damping ratio of a linear contact whose rebound speed is k times the
    impact speed: k = exp(−ζπ/√(1 − ζ²)) ⇒ ζ = −ln k/√(π² + ln² k) (1 for k = 0)."""
    if k <= 0.0:
        return 1.0
    lk = math.log(k)
    return -lk / math.sqrt(math.pi**2 + lk * lk)


def rebounds(
    stops: Sequence[StopImpact], v0: npt.ArrayLike, *, n_threads: int | None = None
) -> Array:
    """First rebound [m] of stop i hit at the speeds ``v0[i]`` [m/s], shape (S, W):
    the rebound depends on the speed and phase angle only through the impact
    speed. Pulse-model stops with the same pulse table go into one Rust call
    (per-case frequency, damping and mass); a contact-model stop takes one call.

    >>> import numpy as np, cyclomech as cm
    >>> a, b = cm.impact.StopImpact.example(), cm.impact.StopImpact.example(zeta=0.2)
    >>> r = cm.impact.rebounds([a, b], [[0.2, 0.3], [0.2, 0.3]])
    >>> r.shape, bool(r[1, 0] < r[0, 0]), bool(np.isclose(r[0, 1] / r[0, 0], 1.5))
    ((2, 2), True, True)
    """
    v = float_array("v0", v0, ndims=(2,))
    bad = ~(np.isfinite(v) & (v >= 0.0))
    if bad.any():
        i, j = (int(x) for x in np.argwhere(bad)[0])
        raise InputError(
            f"v0[{i}, {j}] = {float(v[i, j])!r} must be a finite impact speed ≥ 0 [m/s] "
            "(its magnitude)"
        )
    if v.shape[0] != len(stops):
        raise InputError(f"v0 must have one row per stop ({len(stops)}); got shape {v.shape}")
    threads = threads_arg(n_threads)
    out = np.empty_like(v)
    groups: dict[tuple[str, float], list[int]] = {}
    for i, s in enumerate(stops):
        if s.model == "contact":
            out[i] = _core.contact_rebound_batch(
                s.mass,
                s.stiffness,
                s.contact_stiffness - s.stiffness,
                s.preload,
                s.zeta,
                _restitution_damping(s.restitution),
                np.ascontiguousarray(-v[i]),
                n_threads=threads,
            )
        else:
            groups.setdefault((s.pulse, s.contact_time), []).append(i)
    for rows in groups.values():
        pulse = stops[rows[0]]._shape()
        w = v.shape[1]
        case = {
            k: np.repeat([getattr(stops[i], k) for i in rows], w)
            for k in ("omega_free", "zeta", "mass", "restitution")
        }
        speed = v[rows].reshape(-1)
        impulse = case["mass"] * (1.0 + case["restitution"]) * speed  # J_A·ω0·(1+k)/l
        out[rows] = first_rebound(
            pulse.t,
            np.multiply.outer(impulse, pulse.f),
            case["omega_free"],
            case["zeta"],
            case["mass"],
            0.0,
            -speed,
            maximum=True,
            n_threads=threads,
        ).q.reshape(len(rows), w)
    return out


#: Relative margin below the largest admissible impact speed (see critical_speeds).
_SPEED_MARGIN = 1e-13


def critical_speeds(
    stops: Sequence[StopImpact],
    a_max: npt.ArrayLike,
    *,
    rtol: float = 1e-12,
    n_threads: int | None = None,
) -> Array:
    """The largest impact speed v* [m/s] of each stop whose first rebound is at most
    its ``a_max`` [m] (inf if every speed up to 1e9 m/s is; 0 if none is), to
    ``rtol`` relative (in [1e-15, 0.5]: the rebounds' rounding is ~1e-16, and a
    wider tolerance is none), shape (S,). The speed returned is admissible with a margin
    of 1e-13 (relative), so that angles worked out from it are too: the rebounds'
    rounding is ~1e-16, the angles' tolerance 1e-9°. The pulse
    model's rebound is g·v0 (linear), so v* = a_max/g from one evaluation per
    stop. The contact model's grows with v0, but not in proportion, so its v* is
    bracketed on a grid of 64 speeds from 1e-9 to 1e9 m/s and the bracket
    narrowed on grids of 64, about 8 steps. Each step evaluates all the stops in
    one :func:`rebounds` call; results are remembered per stop and parameters.

    >>> import cyclomech as cm
    >>> stops = [cm.impact.StopImpact.example(), cm.impact.StopImpact.example(zeta=0.2)]
    >>> v = cm.impact.critical_speeds(stops, 0.1e-3)
    >>> [round(float(x), 4) for x in v]
    [0.2909, 0.3657]
    """
    n = len(stops)
    a = np.broadcast_to(float_array("a_max", a_max, ndims=(0, 1)), (n,)).copy()
    for i, ai in enumerate(a):
        positive(f"a_max[{i}]" if n > 1 else "a_max", ai, "[m]")
    r = _rtol("rtol", rtol)
    out = np.empty(n)
    keys = [s._critical_key(ai, r) for s, ai in zip(stops, a, strict=True)]
    todo = []
    for i, (s, key) in enumerate(zip(stops, keys, strict=True)):
        memo = s.__dict__.get("_critical_memo", {})
        if key in memo:
            out[i] = memo[key]
        else:
            todo.append(i)
    if not todo:
        return out
    v = np.full(n, np.nan)
    # The pulse model is linear in v0 (the lever starts at v0, the pulse's impulse
    # is ∝ v0): rebound = g·v0, so v* = a_max/g (less the margin), stepped down by
    # ulps until admissible should rounding still put it over.
    lin = [i for i in todo if stops[i].model == "pulse"]
    if lin:
        g = rebounds([stops[i] for i in lin], np.ones((len(lin), 1)), n_threads=n_threads)[:, 0]
        with np.errstate(divide="ignore"):
            vl = np.where(g > 0.0, a[lin] / g * (1.0 - _SPEED_MARGIN), np.inf)
        for _ in range(8):
            fin = np.flatnonzero(np.isfinite(vl))
            if not fin.size:
                break
            at = rebounds([stops[lin[j]] for j in fin], vl[fin, None], n_threads=n_threads)
            over = fin[at[:, 0] > a[np.array(lin)[fin]]]
            if not over.size:
                break
            vl[over] = np.nextafter(vl[over], 0.0) * (1.0 - 2.0 * np.finfo(float).eps)
        v[lin] = vl
    idx = np.array([i for i in todo if stops[i].model != "pulse"], dtype=np.intp)
    lo, hi = np.zeros(idx.size), np.full(idx.size, np.inf)
    grid = np.tile(np.logspace(-9.0, 9.0, 64), (idx.size, 1))
    active = np.arange(idx.size)
    for _ in range(64):
        if not active.size:
            break
        fine = rebounds([stops[i] for i in idx[active]], grid[active], n_threads=n_threads)
        fine = fine <= a[idx[active], None]
        k = np.where(fine.all(axis=1), 64, np.argmin(fine, axis=1))
        lo[active] = np.where(k > 0, grid[active, np.maximum(k - 1, 0)], lo[active])
        hi[active] = np.where(k < 64, grid[active, np.minimum(k, 63)], hi[active])
        h = hi[active]
        done = ~np.isfinite(h) | (h - lo[active] <= r * h)
        active = active[~done]
        grid[active] = np.linspace(lo[active], hi[active], 66, axis=1)[:, 1:-1]
    v[idx] = np.where(np.isfinite(hi), lo * (1.0 - _SPEED_MARGIN), np.inf)
    for i in todo:
        memo = stops[i].__dict__.setdefault("_critical_memo", {})
        if len(memo) >= 64:
            memo.clear()
        memo[keys[i]] = out[i] = v[i]
    return out


def phase_angles(rpm: npt.ArrayLike, per_rpm: npt.ArrayLike) -> Array:
    """Smallest phase angles [deg] n·``per_rpm`` at speeds ``rpm`` [rpm] (finite,
    > 0; broadcast) with ``per_rpm`` [deg/rpm] finite and ≥ 0, at least 1e-9°, NaN
    where over 360° (no phase angle of one turn will do).

    >>> import cyclomech as cm
    >>> cm.impact.phase_angles([100.0, 200.0, 400.0], 0.1).tolist()
    [10.0, 20.0, 40.0]
    """
    # float_array checks the dtype; np.asarray keeps a scalar 0-d.
    n = _positive_array("rpm", np.asarray(float_array("rpm", rpm, ndims=(0, 1, 2))), "[rpm]")
    n = n.reshape(np.shape(rpm))
    k = float_array("per_rpm", per_rpm, ndims=(0, 1, 2)).reshape(np.shape(per_rpm))
    bad = ~(np.isfinite(k) & (k >= 0.0))
    if bad.any():
        v = k.reshape(-1)[int(np.argmax(bad.reshape(-1)))]
        raise InputError(f"per_rpm = {float(v)!r} must be finite and ≥ 0 [deg/rpm]")
    t = np.maximum(np.multiply(n, k), 1e-9)
    return np.where(t <= 360.0, t, np.nan)


class StopImpact:
    """A cam-driven lever that strikes its limit stop (seed 000).

    The cam moves the lever's working point through ``stroke`` [m] by the rise
    ``law`` (a name of :mod:`cyclomech.motion`, full-rise form) over the phase
    angle t of the operation; the stop sits ``preload`` [m] short of the end of
    the stroke, so the lever meets it where Z(j*) = 1 − preload/stroke, with the
    working point's speed v0 = ω_shaft·stroke·Z'(j*)/t (ω0 = v0/l), which grows
    with the speed n and shrinks as t grows.

    The lever: length ``lever_length`` l [m], inertia ``J_A`` [kg·m²] about its
    axis, arms ``a``, ``b`` [m], ``E`` [Pa] and ``J_x`` [m⁴] (its free stiffness
    c = 3EJ_x/((a+b)b²), :func:`lever_stiffness`), reduced ``mass`` at the
    working point (default J_A/l² [kg]); ``restitution`` k (5/9 for steel);
    damping ratio ``zeta`` of the free vibration. In contact the stop props the
    lever: ``contact_stiffness`` [N/m] defaults to c times the stiffening that a
    prop at the end of the overhang gives its middle
    (:func:`propped_lever_stiffness`).

    Two models of the first rebound:

    * ``model="pulse"`` (the seed's): the oscillator (free stiffness) starts at
      the stop with −v0 (towards it) and receives the impact pulse (``pulse``
      shape, duration ``contact_time``, default half the period of the contact
      vibration), whose impulse J_A·ω0·(1+k)/l turns the speed round to k·v0;
      the rebound is the first maximum of the displacement away from the stop,
      by the exact peak-only kernel. It is proportional to v0.
    * ``model="contact"``: the stop as a unilateral contact (stiffness switching
      at the stop, the free spring's equilibrium ``preload`` inside it, the
      contact damped so that a single impact has restitution k), solved exactly
      event by event; the rebound is the highest point of the first free flight.

    >>> import cyclomech as cm
    >>> lifter = cm.impact.StopImpact.example()
    >>> a = lifter.rebound([280, 420], 40.0)          # m, at a 40° phase angle
    >>> [round(float(v) * 1e3, 3) for v in a]         # mm
    [0.07, 0.105]
    """

    def __init__(
        self,
        *,
        law: str = "modified_sine",
        stroke: float,
        preload: float,
        lever_length: float,
        J_A: float,
        a: float,
        b: float,
        E: float,
        J_x: float,
        mass: float | None = None,
        restitution: float = 5.0 / 9.0,
        zeta: float = 0.05,
        contact_stiffness: float | None = None,
        pulse: str = "decaying",
        contact_time: float | None = None,
        model: str = "pulse",
    ) -> None:
        self.law = motion.law(law, form="rise")
        self.stroke = positive("stroke", stroke, "[m]")
        self.preload = _nonnegative("preload", preload, "[m]")
        if self.preload >= self.stroke:
            raise InputError(
                f"preload = {preload!r} m must be smaller than stroke = {stroke!r} m "
                "(the lever meets the stop before the end of its stroke)"
            )
        self.lever_length = positive("lever_length", lever_length, "[m]")
        self.J_A = positive("J_A", J_A, "[kg·m²]")
        self.a, self.b = positive("a", a, "[m]"), positive("b", b, "[m]")
        self.E, self.J_x = positive("E", E, "[Pa]"), positive("J_x", J_x, "[m⁴]")
        self.mass = (
            self.J_A / self.lever_length**2 if mass is None else positive("mass", mass, "[kg]")
        )
        self.restitution = _restitution(restitution)
        self.zeta = _nonnegative("zeta", zeta, "(damping ratio)")
        self.stiffness = lever_stiffness(self.E, self.J_x, self.a, self.b)
        if contact_stiffness is None:
            self.contact_stiffness = self.stiffness * _propped_ratio(self.a, self.b)
        else:
            self.contact_stiffness = positive("contact_stiffness", contact_stiffness, "[N/m]")
            if self.contact_stiffness <= self.stiffness:
                raise InputError(
                    f"contact_stiffness = {contact_stiffness!r} N/m must exceed the free "
                    f"stiffness {self.stiffness:.6g} N/m (the stop adds a support)"
                )
        if pulse not in _PULSES:
            raise InputError(f"pulse = {pulse!r} is not a shape; choose one of {_PULSES}")
        self.pulse = pulse
        self.contact_time = (
            float(_half_period(self.contact_stiffness, self.mass))
            if contact_time is None
            else positive("contact_time", contact_time, "[s]")
        )
        if model not in ("pulse", "contact"):
            raise InputError(f"model = {model!r} must be 'pulse' or 'contact'")
        self.model = model
        # Where the lever meets the stop: Z(j*) = 1 − preload/stroke (Z rises), on
        # grids of 64 values, each a vectorised law call, down to adjacent doubles.
        target = 1.0 - self.preload / self.stroke
        lo, hi = 0.0, 1.0
        for _ in range(16):
            grid = np.linspace(lo, hi, 66)[1:-1]
            below = self.law.z(grid) < target
            k = int(np.argmin(below)) if not below.all() else grid.size
            lo = float(grid[k - 1]) if k > 0 else lo
            hi = float(grid[k]) if k < grid.size else hi
            if hi - lo <= 2.0 * np.spacing(hi):
                break
        self.j_contact = 0.5 * (lo + hi)
        self.dz_contact = float(self.law.dz(self.j_contact))

    @property
    def omega_free(self) -> float:
        """Natural angular frequency of the free lever, √(c/m) [rad/s].

        >>> import cyclomech as cm
        >>> round(cm.impact.StopImpact.example().omega_free / (2 * 3.141592653589793))
        297
        """
        return math.sqrt(self.stiffness / self.mass)

    @property
    def omega_contact(self) -> float:
        """Natural angular frequency in contact, √(c_contact/m) [rad/s].

        >>> import cyclomech as cm
        >>> round(cm.impact.StopImpact.example().omega_contact / (2 * 3.141592653589793))
        752
        """
        return math.sqrt(self.contact_stiffness / self.mass)

    def _shape(self) -> Pulse:
        """The pulse of unit impulse [N·s]."""
        tau = self.contact_time
        make = {
            "decaying": lambda: Pulse.decaying(1.0, tau),
            "rectangular": lambda: Pulse.rectangular(1.0, tau),
            "triangular": lambda: Pulse.triangular(1.0, tau),
            "half_sine": lambda: Pulse.half_sine(1.0, tau),
        }[self.pulse]()
        return make.scaled(1.0 / make.impulse)

    def impact_speed(self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike) -> Any:
        """Speed v0 [m/s] of the working point as it meets the stop, at main-shaft
        speed ``rpm`` and phase angle ``phase_deg`` [deg] (broadcast).

        >>> import cyclomech as cm
        >>> round(float(cm.impact.StopImpact.example().impact_speed(280, 40.0)), 4)
        0.2038
        """
        n = _positive_array("rpm", rpm, "[rpm]")
        t = _phase(phase_deg)
        return n * RAD_PER_S_PER_RPM * self.stroke * self.dz_contact / np.radians(t)

    def impact_force(self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike) -> Any:
        """Mean impact force F = J_A·ω0·(1+k)/(l·τ) [N] (the seed's F_уд).

        >>> import cyclomech as cm
        >>> round(float(cm.impact.StopImpact.example().impact_force(280, 40.0)), 2)
        3.53
        """
        w0 = self.impact_speed(rpm, phase_deg) / self.lever_length
        return impact_force(self.J_A, w0, self.restitution, self.lever_length, self.contact_time)

    def rebound(
        self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike, *, n_threads: int | None = None
    ) -> Any:
        """First-rebound amplitude [m] at speeds ``rpm`` and phase angles
        ``phase_deg`` [deg] (arrays broadcast; one Rust call for all of them).

        >>> import numpy as np, cyclomech as cm
        >>> a = cm.impact.StopImpact.example().rebound(np.array([[280], [420]]), [40, 60])
        >>> a.shape, bool(a[1, 0] > a[0, 0] > a[0, 1])
        ((2, 2), True)
        """
        v0 = np.asarray(self.impact_speed(rpm, phase_deg), dtype=np.float64)
        return rebounds([self], v0.reshape(1, -1), n_threads=n_threads).reshape(v0.shape)

    def response(
        self, rpm: float, phase_deg: float, *, duration: float | None = None, points: int = 2001
    ) -> tuple[Array, Array]:
        """The motion after the impact at one speed and phase angle: ``(t [s], q
        [m])``, q the displacement of the working point away from the stop, t from
        the instant of contact over ``duration`` (default 6 free periods), with
        the pulse's breakpoints on the grid (pulse model: exact Duhamel response;
        contact model: the exact event-driven motion).

        >>> import cyclomech as cm
        >>> t, q = cm.impact.StopImpact.example().response(280, 40.0)
        >>> round(float(q.max()) * 1e3, 3)                   # mm: the first rebound
        0.07
        """
        v0 = float(self.impact_speed(float(rpm), float(phase_deg)))
        span = 12.0 * math.pi / self.omega_free if duration is None else float(duration)
        span = positive("duration", span, "[s]")
        points = count("points", points, low=2, high=10**8)
        if self.model == "contact":
            t = np.linspace(0.0, span, points)
            x, _v = contact_sample(
                t,
                mass=self.mass,
                k_free=self.stiffness,
                k_stop=self.contact_stiffness - self.stiffness,
                preload=self.preload,
                zeta_free=self.zeta,
                zeta_contact=_restitution_damping(self.restitution),
                v0=-v0,
            )
            return t, x
        shape = self._shape()
        pulse_t = shape.t[shape.t < span]
        t = np.union1d(np.linspace(0.0, span, points), pulse_t)
        # Repeated breakpoints (jumps) stay repeated: the force there is two-valued.
        jumps = shape.t[1:][np.diff(shape.t) == 0.0]
        t = np.sort(np.concatenate([t, jumps[jumps < span]]))
        f = self.mass * (1.0 + self.restitution) * v0 * _pulse_at(shape, t)
        q = duhamel(t, f, omega_n=self.omega_free, zeta=self.zeta, mass=self.mass, q0=0.0, v0=-v0)
        return t, q

    def _critical_key(self, a_max: float, rtol: float) -> tuple[Any, ...]:
        """What v* depends on: a_max, rtol and the parameters of the rebound."""
        key = (a_max, rtol, self.model, self.pulse, self.contact_time, self.mass)
        return (
            *key,
            self.stiffness,
            self.contact_stiffness,
            self.preload,
            self.zeta,
            self.restitution,
        )

    def critical_speed(
        self, a_max: float, *, rtol: float = 1e-12, n_threads: int | None = None
    ) -> float:
        """The largest impact speed v* [m/s] whose first rebound is at most ``a_max``
        [m] (inf if every speed up to 1e9 m/s is; 0 if none is), to ``rtol``
        relative (:func:`critical_speeds` for one stop).

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> v = lifter.critical_speed(0.1e-3)        # the impact speed at t_min, any rpm
        >>> t = lifter.min_phase_angle(0.1e-3, 280)
        >>> round(v, 6), round(float(lifter.impact_speed(280, t)), 6)
        (0.290929, 0.290929)
        """
        return float(critical_speeds([self], a_max, rtol=rtol, n_threads=n_threads)[0])

    def phase_per_rpm(self, v_star: float) -> float:
        """The phase angle per rpm [deg/rpm] at which the impact speed is ``v_star``
        [m/s]: t = n·(360/60)·stroke·Z'/v* (degrees of a turn of 2π·n/60 rad/s);
        0 for v* = inf, inf for v* = 0.

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> round(280 * lifter.phase_per_rpm(lifter.critical_speed(0.1e-3)), 6)
        28.027142
        """
        with np.errstate(divide="ignore"):
            per_rpm = np.degrees(RAD_PER_S_PER_RPM * self.stroke * self.dz_contact)
            return float(per_rpm / np.float64(v_star))

    def min_phase_angle(
        self,
        a_max: float,
        rpm: npt.ArrayLike,
        *,
        tol_deg: float = 1e-9,
        n_threads: int | None = None,
    ) -> Any:
        """Smallest phase angle [deg] whose first rebound is at most ``a_max`` [m],
        at each speed ``rpm``, to ``tol_deg`` (in [3.6e-13, 180]°: 360° times the
        range of :func:`critical_speeds`' ``rtol``); NaN where even 360° is too short.

        The rebound depends on the speed n and the phase angle t only through the
        impact speed v0 = (2π·n/60)·stroke·Z'/t (:meth:`impact_speed`) and grows
        with it, so t_min = (2π·n/60)·stroke·Z'/v* at every speed, with v* the
        largest admissible impact speed (:meth:`critical_speed`): one search for
        all speeds. At least 1e-9°.

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> t = lifter.min_phase_angle(0.1e-3, 280)
        >>> round(float(t), 6), round(float(lifter.rebound(280, t)) * 1e3, 9)
        (28.027142, 0.1)
        """
        n = np.asarray(_positive_array("rpm", rpm, "[rpm]"), dtype=np.float64)
        tol = _rtol("tol_deg", tol_deg, 360.0, "[deg]")
        # t ≤ 360° and |Δt| ≤ t·Δv/v*: a relative bracket of tol/360 is enough.
        v = self.critical_speed(a_max, rtol=tol / 360.0, n_threads=n_threads)
        return phase_angles(n, self.phase_per_rpm(v))[()]  # a float for a scalar speed

    def linearize(
        self, phase_deg_range: tuple[float, float], rpm: float, points: int = 64
    ) -> tuple[float, float]:
        """Least-squares line a(t) ≈ slope·t + intercept over ``phase_deg_range``
        [deg] at ``rpm``: ``(slope [m/deg], intercept [m])``, the seed's form
        a(3,7) = −0.003·t + 0.208 (mm, deg).

        >>> import cyclomech as cm
        >>> s, c = cm.impact.StopImpact.example().linearize((30, 45), 420)
        >>> round(s * 1e3, 4), round(c * 1e3, 3)                   # mm/deg, mm
        (-0.0031, 0.229)
        """
        lo, hi = (_phase(v) for v in phase_deg_range)
        if not hi > lo:
            raise InputError(
                f"phase_deg_range = {phase_deg_range!r} must be (low, high) with low < high"
            )
        t = np.linspace(float(lo), float(hi), count("points", points, low=2, high=10**7))
        slope, intercept = np.polyfit(t, self.rebound(float(rpm), t), 1)
        return float(slope), float(intercept)

    def constraint(
        self, arc: tuple[str, str], a_max: float, rpm: float, *, linear: bool = False
    ) -> Constraint:
        """The cyclogram constraint rebound(t(arc)) ≤ ``a_max`` [m] at ``rpm``:
        exact, t(arc) ≥ :meth:`min_phase_angle` (default), or the seed's
        linearised slope·t + intercept ≤ a_max over 0.5…2 times that angle
        (``linear=True``). Pass it to :meth:`cyclomech.Cyclogram.add_constraint`.

        >>> import cyclomech as cm
        >>> c = cm.impact.StopImpact.example().constraint(("3", "7"), 0.1e-3, 280)
        >>> c.describe()
        '1·t(3,7) >= 28.0271'
        """
        if not (
            isinstance(arc, tuple | list)
            and len(arc) == 2
            and all(isinstance(e, str) and e for e in arc)
        ):
            raise InputError(
                f'arc = {arc!r} must be an operation\'s two event names (from, to), e.g. ("3", "7")'
            )
        arc = (arc[0], arc[1])
        t_min = float(self.min_phase_angle(a_max, float(rpm)))
        if not math.isfinite(t_min):
            raise InfeasibleError(
                f"rebound stays above a_max = {a_max!r} m at {rpm!r} rpm for every phase "
                "angle up to 360°",
                [f"{arc[0]}→{arc[1]}"],
            )
        name = f"rebound{arc[0]}-{arc[1]}"
        if not linear:
            return Constraint(((arc, 1.0),), ">=", t_min, name)
        slope, intercept = self.linearize((0.5 * t_min, min(2.0 * t_min, 360.0)), float(rpm))
        return Constraint(((arc, slope),), "<=", float(a_max) - intercept, name)

    @classmethod
    def example(cls, **overrides: Any) -> StopImpact:
        """An illustrative microshuttle lifter in the spirit of the STB loom's
        (seed 000): not measured data. A steel lever 100 mm long (arms 50 and 100
        mm, a section of 6.14e-11 m⁴, about 8 × 4.5 mm), 7.4 g reduced to its
        working point, free at 297 Hz and 752 Hz in contact, a modified-sine rise of
        9.4 mm with 0.25 mm preload. Its first rebound at a 40° phase angle is 0.070,
        0.080, 0.093, 0.105 mm at 280, 320, 370, 420 rpm (the seed: 0.07, 0.078,
        0.092, 0.105 mm), and its linearisation over 30–45° at 420 rpm is
        −0.0031·t + 0.229 mm (the seed: −0.003·t + 0.208).

        >>> import cyclomech as cm
        >>> cm.impact.StopImpact.example().preload
        0.00025
        """
        data: dict[str, Any] = dict(
            law="modified_sine",
            stroke=9.4e-3,
            preload=0.25e-3,
            lever_length=0.1,
            J_A=7.4e-5,
            a=0.05,
            b=0.1,
            E=2.1e11,
            J_x=6.14e-11,
            restitution=5.0 / 9.0,
            zeta=0.05,
        )
        data.update(overrides)
        return cls(**data)

    def __repr__(self) -> str:
        return (
            f"StopImpact(law={self.law.name!r}, stroke={self.stroke!r}, preload={self.preload!r}, "
            f"f_free={self.omega_free / (2 * math.pi):.4g} Hz, "
            f"f_contact={self.omega_contact / (2 * math.pi):.4g} Hz, model={self.model!r})"
        )


def _pulse_at(pulse: Pulse, t: Array) -> Array:
    """The pulse's force at the sorted times ``t`` (zero after its table), the
    right-hand value at a repeated time for its first copy, so that a jump at a
    repeated breakpoint is kept."""
    f = np.interp(t, pulse.t, pulse.f, right=0.0)
    # np.interp takes the last of repeated xp: at a jump, the first copy of t
    # gets the value before it.
    for k in np.flatnonzero(np.diff(pulse.t) == 0.0):
        at = np.flatnonzero(t == pulse.t[k])
        if at.size >= 2:
            f[at[0]] = pulse.f[k]
            f[at[1:]] = pulse.f[k + 1]
    return f


def _phase(value: Any) -> Any:
    try:
        t = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"phase_deg must be angles in degrees; got {value!r}") from None
    bad = ~(np.isfinite(t) & (t > 0.0) & (t <= 360.0))
    if bad.any():
        v = t.reshape(-1)[int(np.argmax(bad.reshape(-1)))]
        raise InputError(f"phase_deg = {float(v)!r} must lie in (0, 360] degrees")
    return t


_STOP_KEYS = {
    "name",
    "law",
    "stroke",
    "preload",
    "lever_length",
    "J_A",
    "a",
    "b",
    "E",
    "J_x",
    "mass",
    "restitution",
    "zeta",
    "contact_stiffness",
    "pulse",
    "contact_time",
    "model",
}
_STRING_KEYS = {"name", "law", "pulse", "model"}


@dataclass(frozen=True)
class ImpactStudy:
    """An impact file: a lever with its stop and the speeds and phase angles to
    study (read with :meth:`from_toml`).

    The file::

        [stop]
        name = "microshuttle lifter"   # optional
        law = "modified_sine"          # rise law of the cam (cyclomech.motion)
        stroke = 0.0094                # [m] travel of the working point
        preload = 0.00025              # [m]
        lever_length = 0.1             # [m]
        J_A = 7.4e-5                   # [kg m²]
        a = 0.05                       # [m] lever arms
        b = 0.1
        E = 2.1e11                     # [Pa]
        J_x = 6.14e-11                 # [m⁴]
        restitution = 0.5556           # optional (5/9), also: mass, zeta, pulse,
                                       # contact_stiffness, contact_time, model

        [study]
        rpm = [200, 450, 26]           # from, to, count
        phase_deg = [20, 60, 41]       # from, to, count [deg]
        a_max = 1e-4                   # [m] rebound limit
        arc = ["3", "7"]               # optional: the cyclogram operation
    """

    stop: StopImpact
    rpm: Array
    phase_deg: Array
    a_max: float
    arc: tuple[str, str] | None = None
    name: str = ""

    @classmethod
    def from_toml(cls, path: Any) -> ImpactStudy:
        """Read an impact file; errors name the file, the table and the key.

        >>> import cyclomech as cm
        >>> st = cm.impact.ImpactStudy.from_toml("examples/stb_lifter.toml")
        >>> st.rpm.size, st.phase_deg.size, st.a_max
        (26, 41, 0.0001)
        """
        from .. import _toml

        data, src = _toml.load(path)
        _toml.check_keys(data, {"stop", "study"}, src, "the file")
        for t in ("stop", "study"):
            if t not in data:
                raise InputError(f"{src}: missing table [{t}]")
        sp, sd = data["stop"], data["study"]
        _toml.check_keys(sp, _STOP_KEYS, src, "[stop]")
        _toml.check_keys(sd, {"rpm", "phase_deg", "a_max", "arc"}, src, "[study]")
        kwargs: dict[str, Any] = {}
        for k, v in sp.items():
            if k == "name":
                continue
            if k in _STRING_KEYS:
                if not isinstance(v, str):
                    raise InputError(f"{src}: [stop]: {k} = {v!r} must be a string")
            elif isinstance(v, bool) or not isinstance(v, int | float):
                raise InputError(f"{src}: [stop]: {k} = {v!r} must be a number")
            kwargs[k] = v
        for k in ("stroke", "preload", "lever_length", "J_A", "a", "b", "E", "J_x"):
            if k not in kwargs:
                raise InputError(f"{src}: [stop]: missing key {k!r}")
        try:
            stop = StopImpact(**kwargs)
        except InputError as e:
            raise InputError(f"{src}: [stop]: {e}") from None

        def span(key: str, lo: float, hi: float) -> Array:
            if key not in sd:
                raise InputError(f"{src}: [study]: missing key {key!r}")
            v = sd[key]
            ok = (
                isinstance(v, list)
                and len(v) == 3
                and all(isinstance(x, int | float) and not isinstance(x, bool) for x in v)
                and isinstance(v[2], int)
                and v[2] >= 1
                and all(math.isfinite(x) and lo < x <= hi for x in v[:2])
            )
            if not ok:
                raise InputError(
                    f"{src}: [study]: {key} = {v!r} must be [from, to, count], from and to "
                    f"in ({lo:g}, {hi:g}] and a whole count ≥ 1"
                )
            return np.linspace(float(v[0]), float(v[1]), int(v[2]))

        rpm = span("rpm", 0.0, 1e6)
        phase = span("phase_deg", 0.0, 360.0)
        if "a_max" not in sd:
            raise InputError(f"{src}: [study]: missing key 'a_max'")
        try:
            a_max = positive("a_max", sd["a_max"], "[m]")
        except InputError as e:
            raise InputError(f"{src}: [study]: {e}") from None
        arc = None
        if "arc" in sd:
            v = sd["arc"]
            if not (isinstance(v, list) and len(v) == 2 and all(isinstance(x, str) for x in v)):
                raise InputError(f"{src}: [study]: arc = {v!r} must be two event names")
            arc = (v[0], v[1])
        name = sp.get("name", "")
        if not isinstance(name, str):
            raise InputError(f"{src}: [stop]: name = {name!r} must be a string")
        return cls(stop, rpm, phase, a_max, arc, name)
