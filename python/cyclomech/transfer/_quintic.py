"""The seed's quintic transition from a circle to a straight line
(:func:`quintic_transition`), its smooth member (:func:`smooth_transition`) and
the change to the machine frame (:func:`to_machine`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import broadcast as _broadcast
from .._arrays import finite_number, positive
from .._errors import InputError
from ._checks import _LENGTH_RANGE, Array, _finite_array, _radius, _scalar

__all__ = ["QuinticTransition", "quintic_transition", "smooth_transition", "to_machine"]


@dataclass(frozen=True)
class QuinticTransition:
    """The seed's quintic transition from a circle to a straight line.

    y(x) = a2·x² + a3·x³ + a4·x⁴ + a5·x⁵ on 0 ≤ x ≤ x2, in the frame of A (origin on
    the circle, x along its tangent in the direction of travel, y towards its
    centre): from the circle of radius ``R`` at A to the line y = k·x + b at
    B = (x2, k·x2 + b). Build it with :func:`quintic_transition` or
    :func:`smooth_transition`. Every method takes arrays of x [m] (any shape). Each
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    R : float
        The circle's radius [m].
    k : float
        The line's slope in A's frame.
    b : float
        The line's intercept in A's frame [m].
    x2 : float
        B's abscissa in A's frame [m] (> 0).
    coeffs : ndarray of float, shape (6,)
        The coefficients a0 … a5 (a0 = a1 = 0, a2 = 1/(2R)).

    Examples
    --------
    >>> import cyclomech as cm
    >>> q = cm.transfer.smooth_transition(0.15, 0.06)
    >>> q.R, q.k, round(q.b, 6)
    (0.15, 0.2, -0.0036)
    """

    R: float
    k: float
    b: float
    x2: float
    coeffs: Array  # (6,): a0 … a5

    def y(self, x: npt.ArrayLike) -> Any:
        """y(x) [m].

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            y(x) [m] at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> q = cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05)
        >>> bool(abs(q.y(0.05) - (0.1 * 0.05 - 0.002)) < 1e-15)
        True
        """
        return self._eval(x, "y")

    def dy(self, x: npt.ArrayLike) -> Any:
        """y'(x), the slope (dimensionless).

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            The slope y'(x) at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05).dy(0.05), 12)
        0.1
        """
        return self._eval(x, "dy")

    def ddy(self, x: npt.ArrayLike) -> Any:
        """y''(x) [1/m].

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            y''(x) [1/m] at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05).ddy(0.0), 12)
        5.0
        """
        return self._eval(x, "ddy")

    def dddy(self, x: npt.ArrayLike) -> Any:
        """y'''(x) [1/m²].

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            y'''(x) [1/m²] at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> q = cm.transfer.smooth_transition(0.2, 0.05)
        >>> bool(abs(q.dddy(0.0)) < 1e-9 and abs(q.dddy(0.05)) < 1e-9)
        True
        """
        return self._eval(x, "dddy")

    def curvature(self, x: npt.ArrayLike) -> Any:
        """κ = y''/(1 + y'²)^{3/2} [1/m]: 1/R at A, 0 at B.

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            The curvature κ [1/m] at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> q = cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05)
        >>> round(q.curvature(0.0), 12), bool(abs(q.curvature(0.05)) < 1e-12)
        (5.0, True)
        """
        return self._eval(x, "curvature")

    def curvature_rate(self, x: npt.ArrayLike) -> Any:
        """dκ/ds [1/m²], s the arc length.

        dκ/ds = (y'''·(1 + y'²) − 3·y'·y''²)/(1 + y'²)³. Times v³ it is the rate of
        the normal acceleration at constant speed v.

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            dκ/ds [1/m²] at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> q = cm.transfer.smooth_transition(0.2, 0.05)
        >>> bool(abs(q.curvature_rate(0.0)) < 1e-12), round(q.curvature_rate(0.025), 3)
        (True, -148.799)
        """
        return self._eval(x, "curvature_rate")

    def arc_length(self, x: npt.ArrayLike) -> Any:
        """s(x) = ∫₀ˣ √(1 + y'²) dx [m], the arc length from A.

        16-point Gauss–Legendre on sub-intervals of [0, x], one per 0.05 rad that the
        tangent turns over [0, max x] (exact to rounding against adaptive quadrature,
        steep quintics included).

        Parameters
        ----------
        x : float or array_like of float
            The abscissae x [m] in A's frame (any shape up to 3 dimensions).

        Returns
        -------
        float or ndarray of float
            The arc length s(x) [m] at each x: a float for a scalar ``x``, else an array of
            its shape.

        Raises
        ------
        InputError
            If an x is not finite.

        Examples
        --------
        >>> import cyclomech as cm
        >>> q = cm.transfer.quintic_transition(1e9, 0.0, 0.0, 0.05)   # nearly straight
        >>> round(q.arc_length(0.05), 12)
        0.05
        """
        return self._eval(x, "arc_length")

    @property
    def length(self) -> float:
        """Arc length from A to B [m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.transfer.quintic_transition(0.2, 0.1, -0.002, 0.05).length, 6)
        0.050109
        """
        return float(self.arc_length(self.x2))

    def _eval(self, x: npt.ArrayLike, what: str) -> Any:
        """``what`` at every x, one Rust call (the GIL released)."""
        xs = self._x(x)
        flat = np.ascontiguousarray(xs, dtype=np.float64).ravel()
        out = _core.transfer_quintic(self.coeffs, flat, what)
        return _scalar(out.reshape(xs.shape))

    def _x(self, x: npt.ArrayLike) -> Array:
        return _finite_array("x", x, "[m]")


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
    """The seed's quintic from a circle to a line, meeting both to the second derivative.

    From the circle of radius ``R`` (at the origin A, x along its tangent, centre at
    (0, R)) to the line y = k·x + b at x = ``x2``, meeting y = 0, y' = 0, y'' = 1/R
    at A and y = k·x2 + b, y' = k, y'' = 0 at B.

    Parameters
    ----------
    R : float
        The circle's radius [m] (> 0).
    k : float
        The line's slope in A's frame.
    b : float
        The line's intercept in A's frame [m].
    x2 : float
        B's abscissa in A's frame [m] (> 0: the 3×3 system of the conditions at B
        is singular at x2 = 0).

    Returns
    -------
    QuinticTransition
        The transition.

    Raises
    ------
    InputError
        For R ≤ 0, x2 ≤ 0, anything not finite, lengths outside [1e-60, 1e60] m, or a
        geometry whose coefficients overflow (scale it).

    Examples
    --------
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
    """The quintic transition whose curvature also starts and ends flat.

    y'' = (1 − 3s² + 2s³)/R with s = x/x2, so y''' = 0 at A and at B and the rate of
    the normal acceleration is continuous at both junctions too. It turns the
    tangent by atan(x2/(2R)) and meets the line y = k·x + b with k = x2/(2R),
    b = −3·x2²/(20R); its line lies farther from the centre than the circle, by the
    shift (R − b)/√(1 + k²) − R ≈ x2²/(40R).

    Parameters
    ----------
    R : float
        The circle's radius [m] (> 0).
    x2 : float
        The transition's length along A's tangent [m] (> 0).

    Returns
    -------
    QuinticTransition
        The transition.

    Raises
    ------
    InputError
        If ``R`` or ``x2`` is not finite and positive, or the geometry overflows.

    Examples
    --------
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
    """The seed's change of frame from a transition's local frame to the machine's.

    x = x'·cos α + y'·sin α − x0, y = −x'·sin α + y'·cos α − y0: a rotation by −α,
    then a shift by −(x0, y0). A rotation and a shift: lengths, angles and
    curvature are kept.

    Parameters
    ----------
    x_local : float or array_like of float
        The local abscissae x' [m]; broadcasts with ``y_local``.
    y_local : float or array_like of float
        The local ordinates y' [m].
    alpha : float
        The rotation angle α [rad].
    x0 : float
        The shift's x [m].
    y0 : float
        The shift's y [m].

    Returns
    -------
    ndarray of float, shape (..., 2)
        The points (x, y) in the machine frame [m].

    Raises
    ------
    InputError
        If a value is not finite or the local coordinates do not broadcast.

    Examples
    --------
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
