"""The rotor transfer: the `_model` part of :mod:`cyclomech.transfer` (its door)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import available_bytes, check_bytes, count, finite_number, float_array, positive
from .._errors import InfeasibleError, InputError

__all__ = [
    "PathAcceleration",
    "PathSample",
    "QuinticTransition",
    "TransferDesign",
    "TransferPath",
    "acceleration_jump",
    "acceleration_jump_at_speed",
    "design_transfer",
    "quintic_transition",
    "smooth_transition",
    "to_machine",
]

Array = npt.NDArray[np.float64]

# Gauss–Legendre nodes and weights on [0, 1]: 16 for an arc length from 0 to any
# x, 4 per interval for cumulative lengths along a sorted grid.
_GL16 = np.polynomial.legendre.leggauss(16)
_GL4 = np.polynomial.legendre.leggauss(4)
_NODES16, _WEIGHTS16 = (_GL16[0] + 1.0) / 2.0, _GL16[1] / 2.0
_NODES4, _WEIGHTS4 = (_GL4[0] + 1.0) / 2.0, _GL4[1] / 2.0

#: Pieces of a sampled path, in travel order.
#: Peak bytes a point of :meth:`TransferPath.sample` takes while it is built.
_SAMPLE_PEAK_BYTES = 112

PIECES = ("arc_t", "transition_t", "straight", "transition_p", "arc_p")


#: Lengths [m] the path's closed forms and scans hold in (fifth powers of x2 and
#: their reciprocals, and 1e-9 fractions, stay normal floats); outside, scale
#: the units.
_LENGTH_RANGE = (1e-60, 1e60)


def _radius(name: str, value: Any) -> float:
    r = finite_number(name, value, "m (a pitch radius must be positive)", low=0.0, strict=True)
    lo, hi = _LENGTH_RANGE
    if not lo <= r <= hi:
        raise InputError(f"{name} = {value!r} m must lie in [{lo:g}, {hi:g}] m (scale the units)")
    return r


def _finite_array(name: str, value: Any, unit: str) -> Array:
    a = float_array(name, value, ndims=(0, 1, 2, 3)).reshape(np.shape(value))
    if not np.isfinite(a).all():
        i = int(np.argmax(~np.isfinite(a.ravel())))
        raise InputError(f"{name} must be finite {unit}; entry {i} is {a.ravel()[i]!r}")
    return a


def _broadcast(**arrays: Array) -> list[Array]:
    """The arrays broadcast together, or :class:`InputError` naming them."""
    try:
        return list(np.broadcast_arrays(*arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {v.shape}" for k, v in arrays.items())
        raise InputError(f"{shapes}: these shapes do not broadcast together") from None


def _point(name: str, value: Any) -> Array:
    a = float_array(name, value, ndims=(1,))
    if a.shape != (2,) or not np.isfinite(a).all():
        raise InputError(f"{name} must be a finite point (x, y) [m]; got {value!r}")
    return a


# ---------------------------------------------------------------------------
# The jump


def acceleration_jump(R_t: Any, omega_t: Any, R_p: Any, omega_p: Any) -> Any:
    """ΔW = R_p·ω_p² + R_t·ω_t² [m/s²]: the jump of the workpiece's acceleration
    where the pitch circles touch (the two centripetal accelerations point at
    opposite centres). Radii [m] and angular speeds [rad/s] broadcast as arrays.

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
    """ΔW = V²/R_t + V²/R_p [m/s²]: :func:`acceleration_jump` for equal peripheral
    speeds V = R_t·ω_t = R_p·ω_p [m/s].

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


# ---------------------------------------------------------------------------
# The quintic


@dataclass(frozen=True)
class QuinticTransition:
    """y(x) = a2·x² + a3·x³ + a4·x⁴ + a5·x⁵ on 0 ≤ x ≤ x2, in the frame of A (origin
    on the circle, x along its tangent in the direction of travel, y towards its
    centre): from the circle of radius ``R`` [m] at A to the line y = k·x + b at
    B = (x2, k·x2 + b). Build it with :func:`quintic_transition` or
    :func:`smooth_transition`. Every method takes arrays of x [m] (any shape)."""

    R: float
    k: float
    b: float
    x2: float
    coeffs: Array  # (6,): a0 … a5

    def y(self, x: npt.ArrayLike) -> Any:
        """y(x) [m].

        >>> import cyclomech as cm
        >>> q = cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05)
        >>> bool(abs(q.y(0.05) - (0.1 * 0.05 - 0.002)) < 1e-15)
        True
        """
        return _scalar(self._poly(self._x(x), 0))

    def dy(self, x: npt.ArrayLike) -> Any:
        """y'(x), the slope.

        >>> import cyclomech as cm
        >>> round(cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05).dy(0.05), 12)
        0.1
        """
        return _scalar(self._poly(self._x(x), 1))

    def ddy(self, x: npt.ArrayLike) -> Any:
        """y''(x) [1/m].

        >>> import cyclomech as cm
        >>> round(cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05).ddy(0.0), 12)
        5.0
        """
        return _scalar(self._poly(self._x(x), 2))

    def dddy(self, x: npt.ArrayLike) -> Any:
        """y'''(x) [1/m²].

        >>> import cyclomech as cm
        >>> q = cm.transfer.smooth_transition(0.2, 0.05)
        >>> bool(abs(q.dddy(0.0)) < 1e-9 and abs(q.dddy(0.05)) < 1e-9)
        True
        """
        return _scalar(self._poly(self._x(x), 3))

    def curvature(self, x: npt.ArrayLike) -> Any:
        """κ = y''/(1 + y'²)^{3/2} [1/m]: 1/R at A, 0 at B.

        >>> import cyclomech as cm
        >>> q = cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05)
        >>> round(q.curvature(0.0), 12), bool(abs(q.curvature(0.05)) < 1e-12)
        (5.0, True)
        """
        x = self._x(x)
        return _scalar(_curvature(self._poly(x, 1), self._poly(x, 2), None)[0])

    def curvature_rate(self, x: npt.ArrayLike) -> Any:
        """dκ/ds [1/m²], s the arc length: (y'''·(1 + y'²) − 3·y'·y''²)/(1 + y'²)³.
        Times v³ it is the rate of the normal acceleration at constant speed v.

        >>> import cyclomech as cm
        >>> q = cm.transfer.smooth_transition(0.2, 0.05)
        >>> bool(abs(q.curvature_rate(0.0)) < 1e-12), round(q.curvature_rate(0.025), 3)
        (True, -148.799)
        """
        x = self._x(x)
        return _scalar(_curvature(*(self._poly(x, j) for j in (1, 2, 3)))[1])

    def arc_length(self, x: npt.ArrayLike) -> Any:
        """s(x) = ∫₀ˣ √(1 + y'²) dx [m]: 16-point Gauss–Legendre on sub-intervals
        of [0, x], one per 0.05 rad that the tangent turns over [0, max x] (exact to
        rounding against adaptive quadrature, steep quintics included).

        >>> import cyclomech as cm
        >>> q = cm.transfer.quintic_transition(1e9, 0.0, 0.0, 0.05)   # nearly straight
        >>> round(q.arc_length(0.05), 12)
        0.05
        """
        x = self._x(x)
        top = float(np.abs(x).max()) if x.size else 0.0
        m = self._pieces(top) if top > 0 else 1
        # Sub-interval j of [0, x]: x·(j + ξ)/m for the nodes ξ on [0, 1].
        frac = ((np.arange(m)[:, None] + _NODES16) / m).ravel()
        t = x[..., None] * frac
        f = np.sqrt(1.0 + self._poly(t, 1) ** 2)
        out = x * (f @ np.tile(_WEIGHTS16, m)) / m
        return _scalar(out)

    @property
    def length(self) -> float:
        """Arc length from A to B [m]."""
        return float(self.arc_length(self.x2))

    def _x(self, x: npt.ArrayLike) -> Array:
        return _finite_array("x", x, "[m]")

    def _poly(self, x: Array, order: int) -> Array:
        """The order-th derivative at an array x (unchecked: the callers check)."""
        return _horner(list(self.coeffs), x, order)

    def _pieces(self, upto: float) -> int:
        """Sub-intervals of [0, upto] for the arc-length quadrature: one per 0.05 rad
        of turning of the tangent (a steep or wiggly quintic brings the integrand's
        complex singularities close to the axis, and 16 nodes on the whole span lose
        digits: 1e-3 relative on a quintic turning by 4 rad)."""
        x = np.linspace(0.0, upto, 65)
        turn = float(np.abs(np.diff(np.arctan(self._poly(x, 1)))).sum())
        return int(min(max(1, math.ceil(turn / 0.05)), 512))


def _horner(c: list[Any], x: Array, order: int) -> Array:
    """The order-th derivative of Σ c[n]·xⁿ (n ≤ 5) at x; the c[n] are numbers or
    arrays broadcasting with x."""
    d = [c[n] * math.perm(n, order) for n in range(order, 6)]
    out = np.zeros(np.broadcast_shapes(np.shape(x), np.shape(d[-1]))) + d[-1]
    for a in reversed(d[:-1]):
        out = out * x + a
    return out


def _curvature(d1: Array, d2: Array, d3: Array | None) -> tuple[Array, Array | None]:
    """(κ, dκ/ds) of a graph from its first three derivatives (no rate without
    the third): κ = y''/(1 + y'²)^{3/2}, dκ/ds = (y⁽³⁾·(1 + y'²) − 3·y'·y''²)/(1 + y'²)³."""
    g = 1.0 + d1 * d1
    kappa = d2 / g**1.5
    rate = None if d3 is None else (d3 * g - 3.0 * d1 * d2 * d2) / g**3
    return kappa, rate


def _speeds(speed: Any) -> tuple[float, float]:
    """(V_t, V_p) [m/s] from a number V or a pair, checked."""
    v = _finite_array("speed", speed, "[m/s]")
    if v.ndim == 0:
        v = np.array([float(v), float(v)])
    if v.shape != (2,):
        raise InputError(
            f"speed must be a number V or a pair (V_t, V_p) [m/s]; got shape {v.shape}"
        )
    if (v <= 0).any():
        raise InputError(f"speed must be > 0 m/s; got {speed!r}")
    return float(v[0]), float(v[1])


def _scalar(a: Array) -> Any:
    return float(a) if a.ndim == 0 else a


def _coeffs(R: Any, k: Any, b: Any, x2: Any) -> tuple[Array, ...]:
    """a2 … a5 for arrays of (R, k, b, x2) (broadcast), from the conditions at B:
    with u = a3·x2³, v = a4·x2⁴, w = a5·x2⁵ the 3×3 system
    [1 1 1; 3 4 5; 6 12 20]·(u, v, w) = (r0, r1·x2, r2·x2²) (determinant 2) has
    the inverse rows (10, −4, 1/2), (−15, 7, −1), (6, −3, 1/2)."""
    a2 = 0.5 / R
    r0 = k * x2 + b - a2 * x2**2
    r1 = (k - 2.0 * a2 * x2) * x2
    r2 = -2.0 * a2 * x2**2
    u = 10.0 * r0 - 4.0 * r1 + 0.5 * r2
    v = -15.0 * r0 + 7.0 * r1 - r2
    w = 6.0 * r0 - 3.0 * r1 + 0.5 * r2
    return a2, u / x2**3, v / x2**4, w / x2**5


def quintic_transition(R: float, k: float, b: float, x2: float) -> QuinticTransition:
    """The seed's quintic from the circle of radius ``R`` [m] (at the origin A, x
    along its tangent, centre at (0, R)) to the line y = k·x + b (``k`` its slope,
    ``b`` [m] its intercept) at x = ``x2`` [m] > 0, meeting y = 0, y' = 0,
    y'' = 1/R at A and y = k·x2 + b, y' = k, y'' = 0 at B.

    Raises :class:`~cyclomech.InputError` for R ≤ 0, x2 ≤ 0 (the 3×3 system is
    singular at x2 = 0) or anything not finite.

    >>> import cyclomech as cm
    >>> q = cm.transfer.quintic_transition(R=0.15, k=0.2, b=-0.004, x2=0.06)
    >>> q.coeffs[:3].round(6).tolist()          # a0, a1, a2 = 1/(2R)
    [0.0, 0.0, 3.333333]
    >>> round(q.dy(0.06), 12), bool(abs(q.ddy(0.06)) < 1e-9)
    (0.2, True)
    """
    R = _radius("R", R)
    k = finite_number("k", k, "(the line's slope in A's frame)")
    b = finite_number("b", b, "m (the line's intercept in A's frame)")
    x2 = finite_number(
        "x2",
        x2,
        "m (B's abscissa in A's frame: the conditions at B are singular at 0)",
        low=0.0,
        strict=True,
    )
    lo, hi = _LENGTH_RANGE
    if not lo <= x2 <= hi:
        raise InputError(f"x2 = {x2!r} m must lie in [{lo:g}, {hi:g}] m (scale the units)")
    # In numpy floats, an overflow (x2**5) or an underflow to 0 (1/x2**3) is an
    # inf or a nan that the check below names, not a Python OverflowError or
    # ZeroDivisionError.
    with np.errstate(all="ignore"):
        a2, a3, a4, a5 = _coeffs(*(np.float64(v) for v in (R, k, b, x2)))
    coeffs = np.array([0.0, 0.0, a2, a3, a4, a5])
    if not np.isfinite(coeffs).all():
        raise InputError(
            f"the transition R = {R!r} m, k = {k!r}, b = {b!r} m, x2 = {x2!r} m overflows; "
            "scale the geometry"
        )
    return QuinticTransition(R=R, k=k, b=b, x2=x2, coeffs=coeffs)


def smooth_k_b(R: Any, x2: Any) -> tuple[Any, Any]:
    """(k, b) of :func:`smooth_transition`: k = x2/(2R), b = −3·x2²/(20R)."""
    return x2 / (2.0 * R), -3.0 * x2**2 / (20.0 * R)


def smooth_transition(R: float, x2: float) -> QuinticTransition:
    """The quintic transition of length ``x2`` [m] from a circle of radius ``R`` [m]
    whose curvature also starts and ends flat: y'' = (1 − 3s² + 2s³)/R with
    s = x/x2, so y''' = 0 at A and at B and the rate of the normal acceleration is
    continuous at both junctions too. It turns the tangent by atan(x2/(2R)) and
    meets the line y = k·x + b with k = x2/(2R), b = −3·x2²/(20R); its line lies
    farther from the centre than the circle, by the shift
    (R − b)/√(1 + k²) − R ≈ x2²/(40R).

    >>> import cyclomech as cm
    >>> q = cm.transfer.smooth_transition(0.15, 0.06)
    >>> q.coeffs[2:].round(4).tolist()   # a2 = 1/(2R), a3 = 0, a4 = −1/(4R·x2²), a5 = 1/(10R·x2³)
    [3.3333, -0.0, -462.963, 3086.4198]
    """
    R = _radius("R", R)
    x2 = positive("x2", x2, "m (the transition's length along A's tangent)")
    with np.errstate(all="ignore"):
        k, b = smooth_k_b(np.float64(R), np.float64(x2))
    if not (np.isfinite(k) and np.isfinite(b)):
        raise InputError(f"the transition R = {R!r} m, x2 = {x2!r} m overflows; scale the geometry")
    return quintic_transition(R, float(k), float(b), x2)


def to_machine(x_local: Any, y_local: Any, alpha: float, x0: float, y0: float) -> Array:
    """The seed's change of frame: x = x'·cos α + y'·sin α − x0,
    y = −x'·sin α + y'·cos α − y0 (a rotation by −α [rad], then a shift by
    −(x0, y0) [m]). Returns (..., 2) points. A rotation and a shift: lengths,
    angles and curvature are kept.

    >>> import cyclomech as cm, math
    >>> cm.transfer.to_machine(1.0, 0.0, math.pi / 2, -2.0, 0.0).round(12).tolist()
    [2.0, -1.0]
    """
    xl = _finite_array("x_local", x_local, "[m]")
    yl = _finite_array("y_local", y_local, "[m]")
    alpha = finite_number("alpha", alpha, "rad")
    x0 = finite_number("x0", x0, "m")
    y0 = finite_number("y0", y0, "m")
    xl, yl = _broadcast(x_local=xl, y_local=yl)
    c, s = math.cos(alpha), math.sin(alpha)
    return np.stack([xl * c + yl * s - x0, -xl * s + yl * c - y0], axis=-1)


# ---------------------------------------------------------------------------
# The composed path


@dataclass(frozen=True)
class PathSample:
    """A sampled :class:`TransferPath`, in travel order. ``points`` (n, 2) [m];
    ``s`` arc length from the start [m]; ``heading`` the tangent's angle [rad],
    unwrapped; ``curvature`` signed [1/m] (left turns positive); ``curvature_rate``
    dκ/ds [1/m²]; ``piece`` the index into :data:`PIECES` of each point."""

    points: Array
    s: Array
    heading: Array
    curvature: Array
    curvature_rate: Array
    piece: npt.NDArray[np.int8]


@dataclass(frozen=True)
class PathAcceleration:
    """The workpiece's motion along a sampled path for a speed law: ``s`` [m],
    ``time`` [s] from the start, ``speed`` [m/s], ``normal`` = v²·κ and
    ``tangential`` = v·dv/ds [m/s²], ``total`` = |a|, ``normal_rate`` = d(v²κ)/dt,
    ``tangential_rate`` [m/s³] and ``jerk`` = |da/dt| [m/s³] (the acceleration
    vector's rate, turning of the frame included)."""

    s: Array
    time: Array
    speed: Array
    normal: Array
    tangential: Array
    total: Array
    normal_rate: Array
    tangential_rate: Array
    jerk: Array
    piece: npt.NDArray[np.int8]

    @property
    def max_jerk(self) -> float:
        """Peak |da/dt| [m/s³]."""
        return float(self.jerk.max())

    @property
    def max_acceleration(self) -> float:
        """Peak |a| [m/s²]."""
        return float(self.total.max())


def _rot(v: Array, angle: Any) -> Array:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _left(v: Array) -> Array:
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


@dataclass(frozen=True)
class _Geometry:
    """The path's construction for arrays of transition lengths (broadcast), in the
    frame where the transport rotor turns counter-clockwise."""

    k: Array  # (…, 2): per side
    b: Array
    shift: Array  # line's distance from each centre minus the radius
    feasible: Array  # the shifted circles leave room for the line
    u: Array  # (…, 2): direction of travel on the straight
    ends: Array  # (…, 2 sides, 2): B_t and B_p
    t_a: Array  # (…, 2 sides, 2): local x axes at A (transport) and C (process)
    origin: Array  # (…, 2 sides, 2): A and C
    straight: Array  # length of the straight segment


def _geometry(r: Array, c_t: Array, c_p: Array, x2: Array) -> _Geometry:
    """Both transitions and the line for transition lengths ``x2`` (…, 2) [m] on
    the circles r = (R_t, R_p) with centres c_t, c_p (counter-clockwise transport)."""
    k, b = smooth_k_b(r, x2)
    dist = (r - b) / np.sqrt(1.0 + k * k)  # the line's distance from each centre
    d_vec = c_p - c_t
    d = float(np.hypot(*d_vec))
    e = d_vec / d
    span = dist.sum(axis=-1)
    feasible = span <= d
    psi = np.arcsin(np.minimum(span / d, 1.0))
    # Direction of travel on the line: from near the transport rotor towards the
    # process one, the transport centre on its left.
    u = _rot(np.broadcast_to(e, (*psi.shape, 2)), psi)
    theta = np.arctan(k)  # each transition's turn, from its start frame to the line
    t_a = np.stack([_rot(u, -theta[..., 0]), _rot(-u, -theta[..., 1])], axis=-2)
    centres = np.stack([c_t, c_p])
    origin = centres - r[..., None] * _left(t_a)
    y_end = k * x2 + b
    ends = origin + x2[..., None] * t_a + y_end[..., None] * _left(t_a)
    straight = np.einsum("...i,...i->...", ends[..., 1, :] - ends[..., 0, :], u)
    return _Geometry(
        k=k,
        b=b,
        shift=dist - r,
        feasible=feasible,
        u=u,
        ends=ends,
        t_a=t_a,
        origin=origin,
        straight=np.where(feasible, straight, -np.inf),
    )


class TransferPath:
    """The guide of a workpiece from a transport rotor to a process rotor: the
    transport pitch circle (a lead-in arc of ``lead_deg``), a smooth quintic
    transition (:func:`smooth_transition`, length ``x2_t`` along its tangent), the
    straight segment, the mirror transition onto the process pitch circle (length
    ``x2_p``) and a lead-out arc. The straight line is the internal common tangent
    of the two circles each widened by its transition's shift (≈ x2²/(40R)), so
    the curvature runs continuously +1/R_t → 0 → −1/R_p, its rate too.

    ``R_t``, ``R_p`` pitch radii [m]; ``centre_t``, ``centre_p`` the rotor centres
    (x, y) [m] in the machine frame, apart by more than R_t + R_p (the transitions
    leave each pitch circle outwards, so they need a gap). ``x2`` [m]: one length
    for both transitions, a pair (x2_t, x2_p), or None for the longest equal
    transitions the gap allows (the straight segment shrinks to a point: the
    guide is transition → transition, the seed's transfer with no common tangent
    segment). ``ccw``: the transport rotor turns counter-clockwise (the process
    rotor, meshing, clockwise); False mirrors the path.

    Attributes: ``k``, ``b`` and ``shift`` per side (transport, process); ``A`` and
    ``C`` where the path leaves the transport circle and joins the process one,
    ``B_t``, ``B_p`` the ends of the straight segment (machine frame, m);
    ``straight_length``; ``transitions`` (the two :class:`QuinticTransition`);
    ``frames`` the seed's (α, x0, y0) of each transition's frame, so that
    ``to_machine(x, q.y(x), *frames[i])`` places transition i (``q``) in the
    machine frame — with ``ccw=False`` the path is a mirror image and the seed's
    rotation cannot mirror, so there ``to_machine(x, -q.y(x), *frames[i])``;
    ``length`` of the whole path.

    >>> import cyclomech as cm
    >>> p = cm.transfer.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.05)
    >>> round(p.straight_length, 4), [round(s * 1e3, 3) for s in p.shift]   # m, mm
    (0.0361, [0.425, 0.252])
    >>> smp = p.sample(2001)
    >>> round(float(smp.curvature[0]), 6), round(float(smp.curvature[-1]), 6)
    (6.666667, -4.0)
    """

    def __init__(
        self,
        R_t: float,
        R_p: float,
        centre_t: Any,
        centre_p: Any,
        x2: Any = None,
        *,
        ccw: bool = True,
        lead_deg: float = 30.0,
    ) -> None:
        self.R_t = _radius("R_t", R_t)
        self.R_p = _radius("R_p", R_p)
        self.centre_t = _point("centre_t", centre_t)
        self.centre_p = _point("centre_p", centre_p)
        self.ccw = bool(ccw)
        self.lead_deg = finite_number(
            "lead_deg", lead_deg, "degrees of pitch circle before and after", low=0.0
        )
        if self.lead_deg > 180.0:
            raise InputError(f"lead_deg = {lead_deg!r} must be ≤ 180 degrees")
        d = float(np.hypot(*(self.centre_p - self.centre_t)))
        self.gap = d - self.R_t - self.R_p
        if self.gap <= 0.0:
            raise InputError(
                f"the pitch circles touch or overlap: centre distance {d:.6g} m ≤ "
                f"R_t + R_p = {self.R_t + self.R_p:.6g} m (gap {self.gap:.3g} m). The "
                "transitions leave each pitch circle outwards, so the centres must be "
                "farther apart than R_t + R_p"
            )
        r = np.array([self.R_t, self.R_p])
        if x2 is None:
            x2v = _longest(r, *self._canonical_centres(), ratio=np.ones(2))
        else:
            x2a = _finite_array("x2", x2, "[m]")
            if x2a.shape not in ((), (1,), (2,)):
                raise InputError(
                    f"x2 must be one length or a pair (x2_t, x2_p) [m]; got shape {x2a.shape}"
                )
            x2v = np.broadcast_to(x2a, (2,)).astype(np.float64)
            lo, hi = _LENGTH_RANGE
            if not ((x2v >= lo) & (x2v <= hi)).all():
                raise InputError(
                    f"x2 must be > 0 m, in [{lo:g}, {hi:g}] m (transition lengths); got {x2!r}"
                )
        self.x2_t, self.x2_p = float(x2v[0]), float(x2v[1])
        g = _geometry(r, *self._canonical_centres(), x2v)
        if not g.feasible or g.straight < -1e-12 * d:
            longest = _longest(r, *self._canonical_centres(), ratio=x2v / x2v.max())
            raise InfeasibleError(
                f"x2 = ({self.x2_t:.6g}, {self.x2_p:.6g}) m is too long for a gap of "
                f"{self.gap:.6g} m: the transitions overlap (straight segment "
                f"{float(g.straight):.3g} m). In these proportions the longest is "
                f"({longest[0]:.6g}, {longest[1]:.6g}) m; x2=None takes it"
            )
        self._g = g
        self.k = (float(g.k[0]), float(g.k[1]))
        self.b = (float(g.b[0]), float(g.b[1]))
        self.shift = (float(g.shift[0]), float(g.shift[1]))
        self.straight_length = max(float(g.straight), 0.0)
        self.transitions = (
            smooth_transition(self.R_t, self.x2_t),
            smooth_transition(self.R_p, self.x2_p),
        )
        t_a, origin = g.t_a * self._mirror, g.origin * self._mirror
        self.frames = tuple(
            (math.atan2(-t[1], t[0]), -float(o[0]), -float(o[1]))
            for t, o in zip(t_a, origin, strict=True)
        )
        self.A, self.C = origin
        self.B_t, self.B_p = g.ends * self._mirror
        lead = math.radians(self.lead_deg)
        self._lengths = np.array(
            [
                self.R_t * lead,
                self.transitions[0].length,
                self.straight_length,
                self.transitions[1].length,
                self.R_p * lead,
            ]
        )
        self.length = float(self._lengths.sum())

    # Frames: everything is built with a counter-clockwise transport rotor; a
    # clockwise one is its mirror image in the x axis (its own inverse).
    @property
    def _mirror(self) -> Array:
        return np.array([1.0, 1.0 if self.ccw else -1.0])

    def _canonical_centres(self) -> tuple[Array, Array]:
        return self.centre_t * self._mirror, self.centre_p * self._mirror

    @property
    def transfer_length(self) -> float:
        """Arc length from A (leaving the transport circle) to C [m]."""
        return float(self._lengths[1:4].sum())

    @property
    def start_of_transfer(self) -> float:
        """Arc length at A [m] (the lead-in arc's length)."""
        return float(self._lengths[0])

    def sample(self, n: int = 10_001) -> PathSample:
        """``n`` ≥ 10 points along the whole path (each piece sampled evenly in its
        own parameter, in proportion to its length; every piece gets ≥ 2), with arc
        length, heading, signed curvature and its rate. Vectorised: 1e6 points in
        well under a second.

        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> s = p.sample(10_001)
        >>> bool(abs(s.s[-1] - p.length) < 1e-12), bool(abs(s.curvature).max() <= 1 / 0.15)
        (True, True)
        """
        n = count("n", n, low=10, what="points along the path")
        # Sized before anything is allocated: the pieces and their concatenation
        # peak at ~104 bytes a point (49 kept); a size that cannot fit is an
        # InputError, not a MemoryError or the OOM killer.
        check_bytes(
            f"TransferPath.sample({n})",
            float(n) * _SAMPLE_PEAK_BYTES,
            f"sample fewer points (≤ {int(available_bytes() // _SAMPLE_PEAK_BYTES):,} fit)",
        )
        counts = _allocate(n, self._lengths)
        g = self._g
        lead = math.radians(self.lead_deg)
        parts = []
        # Headings are carried on from piece to piece (each the last one's end
        # angle), so they come out continuous without unwrapping.
        # Lead-in arc: counter-clockwise about the transport centre, ending at A.
        c_t, c_p = self._canonical_centres()
        phi_a = math.atan2(*(g.origin[0] - c_t)[::-1])
        u = np.linspace(0.0, 1.0, counts[0], endpoint=False)
        phi = phi_a - lead + lead * u
        parts.append(_arc_part(c_t, self.R_t, phi, 1.0, self.R_t * lead * u, 0))
        s0 = self._lengths[0]
        # Transport transition: x from 0 to x2_t in A's frame.
        q = self.transitions[0]
        x = np.linspace(0.0, q.x2, counts[1], endpoint=False)
        base = phi_a + 0.5 * math.pi  # the heading at A
        parts.append(_quintic_part(q, x, g.origin[0], g.t_a[0], base, s0, forward=True, piece=1))
        s0 += self._lengths[1]
        # Straight segment.
        u = np.linspace(0.0, 1.0, counts[2], endpoint=False)
        pts = g.ends[0] + (u * self.straight_length)[:, None] * g.u
        head = base + math.atan(g.k[0])
        zero = np.zeros_like(u)
        parts.append((pts, s0 + u * self.straight_length, zero + head, zero, zero, 2))
        s0 += self._lengths[2]
        # Process transition, travelled backwards in C's frame: x from x2_p to 0.
        q = self.transitions[1]
        x = np.linspace(q.x2, 0.0, counts[3], endpoint=False)
        # Its heading at B_p, atan(k_p) + base + π, is the straight's.
        base = head - math.atan(g.k[1]) - math.pi
        parts.append(_quintic_part(q, x, g.origin[1], g.t_a[1], base, s0, forward=False, piece=3))
        s0 += self._lengths[3]
        # Lead-out arc: clockwise about the process centre, from C (end included).
        phi_c = base + 1.5 * math.pi  # C's angle about the centre: heading at C + π/2
        u = np.linspace(0.0, 1.0, counts[4])
        phi = phi_c - lead * u
        parts.append(_arc_part(c_p, self.R_p, phi, -1.0, s0 + self.R_p * lead * u, 4))
        points = np.concatenate([p[0] for p in parts])
        s = np.concatenate([p[1] for p in parts])
        heading = np.concatenate([p[2] for p in parts])
        curv = np.concatenate([p[3] for p in parts])
        rate = np.concatenate([p[4] for p in parts])
        piece = np.concatenate([np.full(len(p[1]), p[5], dtype=np.int8) for p in parts])
        if not self.ccw:
            points = points * self._mirror
            heading, curv, rate = -heading, -curv, -rate
        return PathSample(points, s, heading, curv, rate, piece)

    def speed_law(self, speed: Any) -> Any:
        """The speed law ``speed`` as a function s ↦ (v, dv/ds, d²v/ds²) (see
        :meth:`acceleration`); v is V_t before A and V_p after C.

        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> v, dv, ddv = p.speed_law((0.15, 0.25))([0.0, p.length])
        >>> v.round(12).tolist(), dv.tolist()
        ([0.15, 0.25], [0.0, 0.0])
        """
        return _speed_law(speed, self.start_of_transfer, self.transfer_length)

    def acceleration(self, speed: Any, n: int = 20_001) -> PathAcceleration:
        """The workpiece's acceleration and jerk along the path sampled at ``n``
        points, for the speed law ``speed``: a number V [m/s] (constant, equal
        peripheral speeds), or a pair (V_t, V_p) [m/s] — the speed changes from V_t
        to V_p between A and C by a quintic smoothstep in arc length (its first two
        derivatives zero at both ends), as when rotors of different pitch turn at
        one workpiece rate. Normal acceleration v²κ, tangential v·dv/ds, and their
        rates d/dt = v·d/ds.

        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> a = p.acceleration(0.2)
        >>> round(float(a.normal[0]), 6), round(float(a.normal[-1]), 6)  # V²/R_t, −V²/R_p
        (0.266667, -0.16)
        """
        law = self.speed_law(speed)
        smp = self.sample(n)
        v, dv, ddv = law(smp.s)
        a_n, a_t, an_rate, at_rate, jerk = _kinematics(
            v, dv, ddv, smp.curvature, smp.curvature_rate
        )
        ds = np.diff(smp.s)
        vm = 0.5 * (v[1:] + v[:-1])
        time = np.concatenate([[0.0], np.cumsum(ds / vm)])
        return PathAcceleration(
            s=smp.s,
            time=time,
            speed=v,
            normal=a_n,
            tangential=a_t,
            total=np.hypot(a_n, a_t),
            normal_rate=an_rate,
            tangential_rate=at_rate,
            jerk=jerk,
            piece=smp.piece,
        )

    def max_jerk(self, speed: Any, n: int = 20_001) -> float:
        """Peak |da/dt| [m/s³] along the path for the speed law ``speed`` (see
        :meth:`acceleration`).

        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> round(p.max_jerk(0.2), 3)                    # m/s³
        1.584
        """
        return self.acceleration(speed, n).max_jerk

    def __repr__(self) -> str:
        return (
            f"TransferPath(R_t={self.R_t!r}, R_p={self.R_p!r}, centre_t={self.centre_t.tolist()}, "
            f"centre_p={self.centre_p.tolist()}, x2=({self.x2_t:.6g}, {self.x2_p:.6g}), "
            f"ccw={self.ccw})"
        )


def _allocate(n: int, lengths: Array) -> list[int]:
    """Points per piece: ≥ 2 each (an empty piece gets 2 at one place), the rest
    in proportion to length; the last piece takes the end point too."""
    free = n - 2 * len(lengths)
    share = free * lengths / lengths.sum()
    extra = np.floor(share).astype(int)
    rest = free - int(extra.sum())
    extra[np.argsort(share - extra)[::-1][:rest]] += 1
    return [2 + int(e) for e in extra]


def _arc_part(
    centre: Array, R: float, phi: Array, sign: float, s: Array, piece: int
) -> tuple[Any, ...]:
    pts = centre + R * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    head = phi + sign * 0.5 * math.pi
    return pts, s, head, np.full_like(phi, sign / R), np.zeros_like(phi), piece


def _quintic_part(
    q: QuinticTransition,
    x: Array,
    origin: Array,
    t_a: Array,
    base: float,
    s0: float,
    *,
    forward: bool,
    piece: int,
) -> tuple[Any, ...]:
    y, d1, d2, d3 = (q._poly(x, j) for j in range(4))
    pts = origin + x[:, None] * t_a + y[:, None] * _left(t_a)
    local = np.arctan(d1) + base  # base: the heading of the local x axis
    kappa, rate = _curvature(d1, d2, d3)
    s_local = _cumulative_arc(q, x)
    if forward:
        return pts, s0 + s_local, local, kappa, rate, piece
    # Travelled from B to C: the arc length runs backwards, the heading turns
    # round, the curvature changes sign and its rate (d/ds of −κ(S − s)) keeps it.
    return pts, s0 + (q.length - s_local), local + math.pi, -kappa, rate, piece


def _cumulative_arc(q: QuinticTransition, x: Array) -> Array:
    """s(x) at a monotone grid x: the length from 0 to x[0] plus 4-point
    Gauss–Legendre over each interval, where the tangent turns by at most
    0.005 rad an interval (then the rule is exact to rounding); on a coarser grid,
    each point's length from 0 by :meth:`QuinticTransition.arc_length`."""
    if x.size < 2 or 10 * q._pieces(float(np.abs(x).max())) > x.size:
        return np.asarray(q.arc_length(x), dtype=np.float64).reshape(x.shape)
    first = np.atleast_1d(q.arc_length(x[:1]))
    lo, hi = x[:-1], x[1:]
    h = hi - lo
    t = lo[:, None] + h[:, None] * _NODES4
    f = np.sqrt(1.0 + q._poly(t, 1) ** 2)
    steps = h * (f @ _WEIGHTS4)
    return np.concatenate([first, first[0] + np.cumsum(steps)])


def _speed_law(speed: Any, start: float, span: float) -> Any:
    """s ↦ (v, dv/ds, d²v/ds²) for a constant speed or a (V_t, V_p) pair."""
    v_t, v_p = _speeds(speed)

    def law(s: Any) -> tuple[Array, Array, Array]:
        s = np.asarray(s, dtype=np.float64)
        u = np.clip((s - start) / span, 0.0, 1.0)
        inside = (s > start) & (s < start + span)
        h = u**3 * (10.0 - 15.0 * u + 6.0 * u * u)
        dh = np.where(inside, 30.0 * u * u * (1.0 - u) ** 2 / span, 0.0)
        ddh = np.where(inside, 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / span**2, 0.0)
        dv = v_p - v_t
        return v_t + dv * h, dv * dh, dv * ddh

    return law


def _kinematics(v: Array, dv: Array, ddv: Array, kappa: Array, rate: Array) -> tuple[Array, ...]:
    """(a_n, a_t, da_n/dt, da_t/dt, |da/dt|) of a point moving at v(s) (dv, ddv its
    s-derivatives) along a curve of curvature κ(s) with rate dκ/ds; d/dt = v·d/ds."""
    a_n = v * v * kappa
    a_t = v * dv
    an_rate = v * (2.0 * v * dv * kappa + v * v * rate)
    at_rate = v * (dv * dv + v * ddv)
    # da/dt of a = a_t·T + a_n·N, with dT/dt = v·κ·N, dN/dt = −v·κ·T.
    jerk = np.hypot(at_rate - a_n * v * kappa, an_rate + a_t * v * kappa)
    return a_n, a_t, an_rate, at_rate, jerk


def _longest(r: Array, c_t: Array, c_p: Array, ratio: Array) -> Array:
    """The longest transitions in proportions ``ratio`` (x2 = λ·ratio) whose
    straight segment is not negative: the root in λ by bisection on a vectorised
    scan (the straight length falls as λ grows)."""
    d = float(np.hypot(*(c_p - c_t)))
    hi = 2.0 * math.sqrt(max(d, 1e-300) * r.max()) * 4.0
    lam = np.geomspace(1e-9 * d, hi, 257)
    g = _geometry(r, c_t, c_p, lam[:, None] * ratio)
    ok = np.flatnonzero(g.straight >= 0.0)
    if ok.size == 0:
        raise InfeasibleError("no transition fits between these rotors")
    lo, hi = lam[ok[-1]], lam[min(ok[-1] + 1, lam.size - 1)]
    for _ in range(8):
        grid = np.linspace(lo, hi, 65)
        g = _geometry(r, c_t, c_p, grid[:, None] * ratio)
        ok = np.flatnonzero(g.straight >= 0.0)
        lo, hi = grid[ok[-1]], grid[min(ok[-1] + 1, grid.size - 1)]
    return lo * ratio


# ---------------------------------------------------------------------------
# Design


@dataclass(frozen=True)
class TransferDesign:
    """:func:`design_transfer`'s result: the chosen ``path`` and its ``x2`` [m];
    ``candidates`` and ``peak_jerk`` of every candidate [m/s³]; on the chosen path
    ``max_acceleration`` [m/s²] and ``max_jerk`` [m/s³]; ``jump`` the acceleration
    jump without transitions [m/s²] (:func:`acceleration_jump`, infinite jerk);
    ``transfer_time`` from A to C [s]; ``at_limit`` whether the best is the longest
    transition the gap allows."""

    path: TransferPath
    x2: float
    candidates: Array
    peak_jerk: Array
    max_acceleration: float
    max_jerk: float
    jump: float
    transfer_time: float
    at_limit: bool


def design_transfer(
    R_t: float,
    R_p: float,
    gap: float,
    speed: Any,
    *,
    x2_min: float | None = None,
    n_candidates: int = 64,
    n_points: int = 801,
) -> TransferDesign:
    """The transition length x2 (the same on both sides) that minimises the peak
    jerk |da/dt| of the workpiece, for pitch radii ``R_t``, ``R_p`` [m] set ``gap``
    [m] apart (centre distance R_t + R_p + gap) and the speed law ``speed`` (V or
    (V_t, V_p) [m/s], see :meth:`TransferPath.acceleration`). Every candidate,
    from ``x2_min`` (default R_min/100) to the longest the gap allows, is evaluated
    in one vectorised pass over (candidates × ``n_points`` points on each
    transition and on the straight); the best is refined by scipy's bounded scalar
    minimiser.

    >>> import cyclomech as cm
    >>> d = cm.transfer.design_transfer(0.15, 0.25, 0.01, 0.157)
    >>> round(d.x2, 4), d.at_limit, round(d.max_jerk, 3), round(d.jump, 4)
    (0.0788, True, 0.484, 0.2629)
    """
    from scipy.optimize import minimize_scalar

    R_t, R_p = _radius("R_t", R_t), _radius("R_p", R_p)
    gap = positive("gap", gap, "m (between the pitch circles)")
    for name, value, lo in (("n_candidates", n_candidates, 2), ("n_points", n_points, 16)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < lo:
            raise InputError(f"{name} must be an integer ≥ {lo}; got {value!r}")
    r = np.array([R_t, R_p])
    c_t, c_p = np.zeros(2), np.array([R_t + R_p + gap, 0.0])
    top = float(_longest(r, c_t, c_p, np.ones(2))[0])
    low = min(R_t, R_p) / 100.0 if x2_min is None else positive("x2_min", x2_min, "m")
    if low >= top:
        raise InfeasibleError(
            f"x2_min = {low:.6g} m is not below the longest transition the gap of "
            f"{gap:.6g} m allows ({top:.6g} m)"
        )
    _speed_law(speed, 0.0, 1.0)  # checked before the scan
    cands = np.geomspace(low, top, n_candidates)
    peaks = _peak_jerk(r, c_t, c_p, cands, speed, n_points)
    i = int(np.argmin(peaks))
    lo, hi = cands[max(i - 1, 0)], cands[min(i + 1, cands.size - 1)]
    best = minimize_scalar(
        lambda x: float(_peak_jerk(r, c_t, c_p, np.array([x]), speed, n_points)[0]),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-6 * hi},
    )
    x2 = float(best.x) if best.fun <= peaks[i] else float(cands[i])
    path = TransferPath(R_t, R_p, c_t, c_p, x2=x2 if x2 < top else None)
    acc = path.acceleration(speed)
    v_t, v_p = _speeds(speed)
    jump = acceleration_jump(R_t, v_t / R_t, R_p, v_p / R_p)
    start = np.searchsorted(acc.s, path.start_of_transfer)
    end = np.searchsorted(acc.s, path.start_of_transfer + path.transfer_length)
    return TransferDesign(
        path=path,
        x2=path.x2_t,
        candidates=cands,
        peak_jerk=peaks,
        max_acceleration=acc.max_acceleration,
        max_jerk=acc.max_jerk,
        jump=float(jump),
        transfer_time=float(acc.time[min(end, acc.time.size - 1)] - acc.time[start]),
        at_limit=bool(x2 >= top * (1 - 1e-6)),
    )


def _peak_jerk(r: Array, c_t: Array, c_p: Array, x2: Array, speed: Any, m: int) -> Array:
    """Peak |da/dt| for each candidate length in ``x2`` (C,), on m points of each
    transition and of the straight, all candidates at once."""
    c = x2.size
    x2s = np.stack([x2, x2], axis=-1)
    g = _geometry(r, c_t, c_p, x2s)
    straight = np.maximum(g.straight, 0.0)
    u = np.linspace(0.0, 1.0, m)
    # Arc lengths of the transitions (C, 2), from the cumulative lengths below.
    lengths = np.empty((c, 2))
    pieces = []
    for side in range(2):
        R = r[side]
        a2, a3, a4, a5 = _coeffs(R, g.k[:, side], g.b[:, side], x2)
        a2 = np.full_like(x2, a2)
        xx = x2[:, None] * u  # (C, m)

        cs = [0.0, 0.0] + [a[:, None] for a in (a2, a3, a4, a5)]

        def d(order: int, x: Array, cs: list[Any] = cs) -> Array:
            return _horner(cs, x, order)

        d1, d2, d3 = d(1, xx), d(2, xx), d(3, xx)
        kappa, rate = _curvature(d1, d2, d3)
        # Cumulative arc length along the candidate's grid (trapezoid on a fine
        # grid is enough for locating the speed law).
        f = np.sqrt(1.0 + d1 * d1)
        s_loc = np.concatenate(
            [np.zeros((c, 1)), np.cumsum(0.5 * (f[:, 1:] + f[:, :-1]) * np.diff(xx), axis=1)],
            axis=1,
        )
        lengths[:, side] = s_loc[:, -1]
        pieces.append((kappa, rate, s_loc))
    span = lengths.sum(axis=1) + straight
    # s from A, each candidate's transfer its own span.
    law = _speed_law(speed, 0.0, span[:, None])

    def jerk(s: Array, kappa: Array, rate: Array) -> Array:
        return _kinematics(*law(s), kappa, rate)[4]

    k_t, r_t, s_t = pieces[0]
    out = jerk(s_t, k_t, r_t).max(axis=1)
    s_line = lengths[:, :1] + straight[:, None] * u
    zero = np.zeros_like(s_line)
    out = np.maximum(out, jerk(s_line, zero, zero).max(axis=1))
    k_p, r_p, s_p = pieces[1]
    # The process transition travelled backwards: s from its far end, κ negated.
    s_back = (span - lengths[:, 1])[:, None] + (lengths[:, 1][:, None] - s_p)
    out = np.maximum(out, jerk(s_back, -k_p, r_p).max(axis=1))
    # On the pitch circles: v²/R at the transfer's end speeds, no jerk but the
    # centripetal part of the turning frame is already counted at A and C.
    return np.where(g.feasible & (g.straight >= 0), out, np.inf)
