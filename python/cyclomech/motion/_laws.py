"""The motion laws: `_laws` part of :mod:`cyclomech.motion` (its door)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import float_array, instance, out_array, positive, real_array, threads_arg
from .._errors import InputError

__all__ = ["NAMES", "MotionLaw", "TwoPeriodLaw", "law", "polynomial", "two_period"]

#: Names of the built-in laws.
NAMES = tuple(_core.MOTION_LAWS)
_FORMS = ("half", "rise")


class MotionLaw:
    """A dimensionless law Z(j) on the unit square.

    Build it with :func:`law` or :func:`polynomial`. ``z``, ``dz``, ``ddz``, ``dddz``
    evaluate Z and its derivatives at j in [0, 1] (arrays in, float64 arrays out);
    ``dz_max`` = max Z' and ``ddz_max`` = max |Z''| are its dimensionless speed and
    acceleration peaks. Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The law's name, one of :data:`NAMES`, or ``"polynomial"`` with ``coeffs``.
    form : {"half", "rise"}
        The half law (Z' peaking at j = 1) or the full rise (zero speed at both ends).
    coeffs : tuple of float, optional
        The polynomial's coefficients c0, c1, … of Z(j) = Σ c_k j^k; default None
        (a named law).

    Raises
    ------
    InputError
        If ``form`` is neither ``"half"`` nor ``"rise"``.

    See Also
    --------
    law, polynomial : The constructors to use.

    Examples
    --------
    >>> import cyclomech as cm
    >>> lw = cm.motion.law("cycloidal", form="rise")
    >>> round(lw.dz_max, 12), round(lw.ddz_max, 12)
    (2.0, 6.28318530718)
    """

    __slots__ = ("_kernel", "coeffs", "form", "name")

    def __init__(self, name: str, form: str, coeffs: tuple[float, ...] | None = None) -> None:
        # The form is checked here too: any other string was the half law, silently.
        form = _form(form)
        instance("name", name, str)
        self.name = name
        self.form = form
        self.coeffs = coeffs
        rise = form == "rise"
        if coeffs is None:
            self._kernel = _core.MotionLaw.named(name, rise)
        else:
            c = real_array("coeffs", coeffs, "(polynomial coefficients)", ndims=(1,))
            self._kernel = _core.MotionLaw.polynomial(c, rise)

    @property
    def dz_max(self) -> float:
        """Peak of Z' (the dimensionless speed peak: max speed / mean speed), dimensionless.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.motion.law("cycloidal").dz_max, 12)
        2.0
        """
        return float(self._kernel.dz_max)

    @property
    def ddz_max(self) -> float:
        """Peak of |Z''| (the dimensionless acceleration peak), dimensionless.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.motion.law("polynomial_345", form="rise").ddz_max, 4)
        5.7735
        """
        return float(self._kernel.ddz_max)

    @property
    def breaks(self) -> tuple[float, ...]:
        """Ends of the law's pieces on [0, 1] (where Z''' may jump), dimensionless j.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.motion.law("modified_trapezoid", form="rise").breaks
        (0.0, 0.125, 0.375, 0.625, 0.875, 1.0)
        """
        return tuple(self._kernel.breaks)

    def _eval(self, j: npt.ArrayLike, order: int, n_threads: int | None) -> Any:
        scalar = np.ndim(j) == 0
        a = float_array("j", j, ndims=(0, 1, 2, 3))
        out = self._kernel.eval(a.ravel(), order, n_threads=threads_arg(n_threads))
        return float(out[0]) if scalar else out.reshape(a.shape)

    def z(self, j: npt.ArrayLike, *, n_threads: int | None = None) -> Any:
        """Z(j), dimensionless, for j in [0, 1].

        Parameters
        ----------
        j : float or array_like of float
            The dimensionless position(s) j in [0, 1] (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float or ndarray of float
            Z(j), dimensionless: a float for a scalar ``j``, else an array of its shape.

        Raises
        ------
        InputError
            If ``j`` is not an array of numbers of at most 3 dimensions or ``n_threads``
            is not None or a positive integer.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.motion.law("harmonic", form="rise").z([0.0, 0.5, 1.0]).round(12).tolist()
        [0.0, 0.5, 1.0]
        """
        return self._eval(j, 0, n_threads)

    def dz(self, j: npt.ArrayLike, *, n_threads: int | None = None) -> Any:
        """Z'(j) = dZ/dj, dimensionless.

        Parameters
        ----------
        j : float or array_like of float
            The dimensionless position(s) j in [0, 1] (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float or ndarray of float
            Z'(j), dimensionless: a float for a scalar ``j``, else an array of its shape.

        Raises
        ------
        InputError
            If ``j`` is not an array of numbers of at most 3 dimensions or ``n_threads``
            is not None or a positive integer.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.motion.law("cycloidal").dz(1.0), 12)
        2.0
        """
        return self._eval(j, 1, n_threads)

    def ddz(self, j: npt.ArrayLike, *, n_threads: int | None = None) -> Any:
        """Z''(j) = d²Z/dj², dimensionless.

        Parameters
        ----------
        j : float or array_like of float
            The dimensionless position(s) j in [0, 1] (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float or ndarray of float
            Z''(j), dimensionless: a float for a scalar ``j``, else an array of its shape.

        Raises
        ------
        InputError
            If ``j`` is not an array of numbers of at most 3 dimensions or ``n_threads``
            is not None or a positive integer.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.motion.law("cycloidal").ddz(0.5), 12)   # π·sin(π/2)
        3.14159265359
        """
        return self._eval(j, 2, n_threads)

    def dddz(self, j: npt.ArrayLike, *, n_threads: int | None = None) -> Any:
        """Z'''(j) = d³Z/dj³, dimensionless (one-sided at the breaks, where it may jump).

        Parameters
        ----------
        j : float or array_like of float
            The dimensionless position(s) j in [0, 1] (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float or ndarray of float
            Z'''(j), dimensionless: a float for a scalar ``j``, else an array of its shape.

        Raises
        ------
        InputError
            If ``j`` is not an array of numbers of at most 3 dimensions or ``n_threads``
            is not None or a positive integer.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.motion.law("polynomial_345", form="rise").dddz(0.0), 12)
        60.0
        """
        return self._eval(j, 3, n_threads)

    def __reduce__(self) -> tuple[Any, ...]:
        return (MotionLaw, (self.name, self.form, self.coeffs))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MotionLaw):
            return NotImplemented
        return (self.name, self.form, self.coeffs) == (other.name, other.form, other.coeffs)

    def __hash__(self) -> int:
        return hash((self.name, self.form, self.coeffs))

    def __repr__(self) -> str:
        if self.coeffs is not None:
            return f"cyclomech.motion.polynomial({list(self.coeffs)!r}, form={self.form!r})"
        return f"cyclomech.motion.law({self.name!r}, form={self.form!r})"


def _form(form: Any) -> str:
    if form not in _FORMS:
        raise InputError(f"form = {form!r} must be 'half' (the default) or 'rise'")
    return str(form)


def law(name: str | MotionLaw, form: str = "half") -> MotionLaw:
    """A named law: its half law (default) or its full rise (``form="rise"``).

    The modified laws are built from their acceleration pieces (sine ramps of 1/8
    with a constant plateau, or a long sine through the middle) and integrated
    exactly.

    Parameters
    ----------
    name : str or MotionLaw
        The law's name: ``cycloidal``, ``harmonic``, ``polynomial_345``,
        ``polynomial_4567``, ``modified_sine``, ``modified_trapezoid`` (see
        :data:`NAMES`). A :class:`MotionLaw` passes through unchanged (its own form
        is kept).
    form : {"half", "rise"}, default "half"
        The half law Z_h(j) = 2·Z(j/2) or the full rise Z(j).

    Returns
    -------
    MotionLaw
        The law.

    Raises
    ------
    InputError
        If the name is not known or ``form`` is neither ``"half"`` nor ``"rise"``.

    Examples
    --------
    >>> import cyclomech as cm
    >>> h = cm.motion.law("cycloidal")                  # Z = j − sin(πj)/π
    >>> round(h.z(0.5), 12), round(h.dz_max, 12), round(h.ddz_max, 12)
    (0.181690113816, 2.0, 3.14159265359)
    """
    if isinstance(name, MotionLaw):
        return name
    f = _form(form)
    if not isinstance(name, str) or name not in NAMES:
        raise InputError(f"law name {name!r} is not known; known laws: {', '.join(NAMES)}")
    return MotionLaw(name, f)


def polynomial(coeffs: npt.ArrayLike, form: str = "rise") -> MotionLaw:
    """A user law Z(j) = Σ c_k j^k from its coefficients c0, c1, … (degree ≤ 24).

    Checked to within 1e-9: Z(0) = 0, Z(1) = 1, Z'(0) = 0 and Z' ≥ 0 on [0, 1];
    as a rise also Z'(1) = 0, as a half law (``form="half"``) Z' largest at j = 1.
    Z' ≥ 0 and the peaks ``dz_max``, ``ddz_max`` are found on 256 samples, each
    of the highest sampled local extrema then refined (a dip of Z' narrower than
    a sample gap is seen, and the higher of two near-tied peaks taken); two
    extrema within one gap of 1/256 on a rising or falling stretch are not.

    Parameters
    ----------
    coeffs : array_like of float, shape (K,)
        The coefficients c0, c1, … of the powers of j, dimensionless (K ≤ 25).
    form : {"rise", "half"}, default "rise"
        Whether the polynomial is a full rise or a half law.

    Returns
    -------
    MotionLaw
        The law, named ``"polynomial"``.

    Raises
    ------
    InputError
        If ``form`` is neither ``"half"`` nor ``"rise"``, or the coefficients fail
        the checks above.

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.motion.polynomial([0, 0, 0, 10, -15, 6])     # the 3-4-5 rise
    >>> round(p.dz_max, 6), round(p.ddz_max, 6)
    (1.875, 5.773503)
    """
    f = _form(form)
    c = float_array("coeffs", coeffs)
    return MotionLaw("polynomial", f, tuple(float(v) for v in c))


def _half(name: str, value: Any) -> MotionLaw:
    lw = law(value) if isinstance(value, str) else value
    if not isinstance(lw, MotionLaw):
        raise InputError(
            f"{name} must be a law name ({', '.join(NAMES)}) or a cyclomech.motion.MotionLaw; "
            f"got {value!r}"
        )
    if lw.form != "half":
        raise InputError(
            f"{name} = {lw!r} is a rise; the two-period law joins half laws "
            f"(Z' = 0 at j = 0, peaking at j = 1): use form='half'"
        )
    return lw


@dataclass(frozen=True, eq=False)
class TwoPeriodLaw:
    """The two-period slider law Π(α) of seed 003.

    Period I, 0 ≤ α ≤ α1 (``angle1``): Π = Π1·Z1(α/α1), from BDC up to the speed
    peak; period II, α1 ≤ α ≤ α2 (``angle``): Π = Π2 − (Π2 − Π1)·Z2((α2 − α)/(α2 − α1)),
    up to the full stroke Π2 (``stroke``) [m]. Π' is continuous at α1 (condition 9
    of the seed) and peaks there at ``max_speed`` [m/rad]. ``asymmetry`` is
    f_A = (α2 − α1)/α1 and ``accel_ratio`` I = Π''1max/Π''2max, whichever complex
    of input data built the law. Build it with :func:`two_period`; built directly,
    Π' must be continuous at α1 to 1e-9 (relative), else it is refused. Each
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    law1 : MotionLaw
        The half law Z1 of period I.
    law2 : MotionLaw
        The half law Z2 of period II.
    stroke : float
        The full stroke Π2 [m].
    angle : float
        The crank angle α2 of the full stroke [rad].
    stroke1 : float
        The stroke Π1 at the end of period I [m].
    angle1 : float
        The crank angle α1 at the end of period I, the speed peak [rad].

    See Also
    --------
    two_period : Builds it from one of the seed's complexes of data.

    Examples
    --------
    >>> import cyclomech as cm
    >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "cycloidal", asymmetry=1.0)
    >>> round(lw.angle1, 12), round(lw.stroke1, 12)
    (1.5, 0.05)
    """

    law1: MotionLaw
    law2: MotionLaw
    stroke: float
    angle: float
    stroke1: float
    angle1: float

    def __post_init__(self) -> None:
        # Built directly too, not only by two_period: the same rule for its numbers
        # (a NaN stroke would reach the kernel and give NaN positions).
        instance("law1", self.law1, MotionLaw)
        instance("law2", self.law2, MotionLaw)
        _half("law1", self.law1)
        _half("law2", self.law2)
        p2 = positive("stroke", self.stroke, "[m]")
        a2 = positive("angle", self.angle, "[rad]")
        p1 = positive("stroke1", self.stroke1, "[m]")
        a1 = positive("angle1", self.angle1, "[rad]")
        if a2 > 2 * math.pi * (1 + 1e-12):
            raise InputError(f"angle = {self.angle!r} [rad] must not exceed one crank turn, 2π")
        if not (p1 < p2 and a1 < a2):
            raise InputError(
                f"stroke1 = {p1!r} m and angle1 = {a1!r} rad must lie below stroke = {p2!r} m "
                f"and angle = {a2!r} rad"
            )
        # Π' continuous at α1 (the seed's condition 9): Π1·Z1'(1)/α1 = (Π2 − Π1)·Z2'(1)/
        # (α2 − α1). two_period meets it to rounding; numbers typed in may not, and a
        # jump in Π' is an impact the law's name hides.
        v1, v2 = self.law1.dz_max, self.law2.dz_max
        before, after = p1 * v1 / a1, (p2 - p1) * v2 / (a2 - a1)
        if abs(before - after) > 1e-9 * max(before, after):
            fit = p2 * v2 * a1 / (v1 * (a2 - a1) + v2 * a1)
            raise InputError(
                f"stroke1 = {p1!r} m: Π' would jump at angle1 from {before:.6g} to "
                f"{after:.6g} m/rad (continuity, the seed's condition 9: "
                f"Π1·Z1'max/α1 = (Π2 − Π1)·Z2'max/(α2 − α1)); with these laws and angles "
                f"stroke1 = {fit:.12g} m, or build the law with two_period"
            )
        for k, v in (("stroke", p2), ("angle", a2), ("stroke1", p1), ("angle1", a1)):
            object.__setattr__(self, k, v)

    @property
    def _kernel(self) -> Any:
        k = self.__dict__.get("_k")
        if k is None:
            k = _core.TwoPeriodKernel(
                self.law1._kernel,
                self.law2._kernel,
                self.stroke1,
                self.angle1,
                self.stroke,
                self.angle,
            )
            object.__setattr__(self, "_k", k)
        return k

    @property
    def asymmetry(self) -> float:
        """The asymmetry f_A = (α2 − α1)/α1, dimensionless.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "cycloidal", asymmetry=2.0)
        >>> round(lw.asymmetry, 12)
        2.0
        """
        return (self.angle - self.angle1) / self.angle1

    @property
    def accel_ratio(self) -> float:
        """I = Π''1max/Π''2max, the ratio of the periods' acceleration peaks, dimensionless.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "cycloidal", accel_ratio=0.5)
        >>> round(lw.accel_ratio, 12)
        0.5
        """
        a1 = self.stroke1 / self.angle1**2 * self.law1.ddz_max
        a2 = (self.stroke - self.stroke1) / (self.angle - self.angle1) ** 2 * self.law2.ddz_max
        return a1 / a2

    @property
    def max_speed(self) -> float:
        """Π'max = (Π1/α1)·Z'1max [m/rad], reached at α1.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", max_speed=0.062)
        >>> round(lw.max_speed, 12)
        0.062
        """
        return self.stroke1 / self.angle1 * self.law1.dz_max

    def _eval(
        self, alpha: npt.ArrayLike, order: int, n_threads: int | None, out: Any = None
    ) -> Any:
        scalar = np.ndim(alpha) == 0
        a = float_array("alpha", alpha, ndims=(0, 1, 2, 3))
        threads = threads_arg(n_threads)
        if out is not None:
            if scalar:
                raise InputError("out is for arrays of angles; got a single angle")
            out_array(out, a.shape, [a], "the law at each angle [m, m/rad or m/rad²]")
            self._kernel.eval(a.reshape(-1), order, n_threads=threads, out=out.reshape(-1))
            return out
        res = self._kernel.eval(a.ravel(), order, n_threads=threads)
        return float(res[0]) if scalar else res.reshape(a.shape)

    def position(
        self, alpha: npt.ArrayLike, *, n_threads: int | None = None, out: Any = None
    ) -> Any:
        """Π(α) [m] for α in [0, α2] [rad], counted from BDC against the motion.

        Parameters
        ----------
        alpha : float or array_like of float
            The crank angle(s) α in [0, α2] [rad], counted from BDC against the motion
            (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
        out : ndarray of float64, optional
            A writeable C-contiguous array of ``alpha``'s shape, filled in place and
            returned (a caller that evaluates again reuses its pages; a fresh array's
            are faulted in and zeroed by the OS on first touch); default None (a new
            array).

        Returns
        -------
        float or ndarray of float
            Π(α) [m]: a float for a scalar ``alpha``, else an array of its shape
            (``out`` when given).

        Raises
        ------
        InputError
            If ``alpha`` is not an array of numbers of at most 3 dimensions, ``out`` is
            given with a single angle or does not fit, or ``n_threads`` is not None or a
            positive integer.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", asymmetry=1.5)
        >>> lw.position([0.0, lw.angle]).round(12).tolist()
        [0.0, 0.1]
        >>> buf = np.empty(2)
        >>> lw.position(np.array([0.0, lw.angle]), out=buf) is buf
        True
        """
        return self._eval(alpha, 0, n_threads, out)

    def velocity(
        self, alpha: npt.ArrayLike, *, n_threads: int | None = None, out: Any = None
    ) -> Any:
        """Π'(α) = dΠ/dα [m/rad]; times ω [rad/s] it is the slider speed.

        Parameters
        ----------
        alpha : float or array_like of float
            The crank angle(s) α in [0, α2] [rad], counted from BDC against the motion
            (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
        out : ndarray of float64, optional
            A writeable C-contiguous array of ``alpha``'s shape, filled in place and
            returned (a caller that evaluates again reuses its pages; a fresh array's
            are faulted in and zeroed by the OS on first touch); default None (a new
            array).

        Returns
        -------
        float or ndarray of float
            Π'(α) [m/rad]: a float for a scalar ``alpha``, else an array of its shape
            (``out`` when given).

        Raises
        ------
        InputError
            If ``alpha`` is not an array of numbers of at most 3 dimensions, ``out`` is
            given with a single angle or does not fit, or ``n_threads`` is not None or a
            positive integer.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "modified_sine", asymmetry=1.5)
        >>> bool(abs(lw.velocity(lw.angle1) - lw.max_speed) < 1e-14)
        True
        """
        return self._eval(alpha, 1, n_threads, out)

    def acceleration(
        self, alpha: npt.ArrayLike, *, n_threads: int | None = None, out: Any = None
    ) -> Any:
        """Π''(α) = d²Π/dα² [m/rad²]; times ω² it is the slider acceleration.

        Parameters
        ----------
        alpha : float or array_like of float
            The crank angle(s) α in [0, α2] [rad], counted from BDC against the motion
            (up to 3 dimensions).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
        out : ndarray of float64, optional
            A writeable C-contiguous array of ``alpha``'s shape, filled in place and
            returned (a caller that evaluates again reuses its pages; a fresh array's
            are faulted in and zeroed by the OS on first touch); default None (a new
            array).

        Returns
        -------
        float or ndarray of float
            Π''(α) [m/rad²]: a float for a scalar ``alpha``, else an array of its shape
            (``out`` when given).

        Raises
        ------
        InputError
            If ``alpha`` is not an array of numbers of at most 3 dimensions, ``out`` is
            given with a single angle or does not fit, or ``n_threads`` is not None or a
            positive integer.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lw = cm.motion.two_period(0.1, 3.0, "cycloidal", "cycloidal", asymmetry=1.0)
        >>> abs(lw.acceleration(0.0)) < 1e-15      # a half law starts at zero accel.
        True
        """
        return self._eval(alpha, 2, n_threads, out)

    def __reduce__(self) -> tuple[Any, ...]:
        # The cached Rust kernel is rebuilt on demand, not pickled.
        return (
            TwoPeriodLaw,
            (self.law1, self.law2, self.stroke, self.angle, self.stroke1, self.angle1),
        )

    def __repr__(self) -> str:
        return (
            f"TwoPeriodLaw(law1={self.law1.name!r}, law2={self.law2.name!r}, "
            f"stroke={self.stroke!r}, angle={self.angle!r}, stroke1={self.stroke1!r}, "
            f"angle1={self.angle1!r})"
        )


def two_period(
    stroke: float,
    angle: float,
    law1: str | MotionLaw,
    law2: str | MotionLaw,
    *,
    asymmetry: float | None = None,
    accel_ratio: float | None = None,
    max_speed: float | None = None,
) -> TwoPeriodLaw:
    """The seed's two-period slider law from one of its three complexes of data.

    Give exactly one of ``asymmetry`` (complex 1), ``accel_ratio`` (complex 2) and
    ``max_speed`` (complex 3). With n1 = Z'1max/Z'2max, n2 = Z''1max/Z''2max,
    α1 = α2/(1 + f_A) and, from continuity of Π' at α1 (the seed's condition 9),
    Π1 = Π2/(1 + n1·f_A). The printed (13) Π1 = Π2/(1 + f_A) is the n1 = 1 case.

    Parameters
    ----------
    stroke : float
        The full stroke Π2 [m] (> 0).
    angle : float
        The crank angle α2 the stroke takes [rad] (0 < α2 ≤ 2π).
    law1 : str or MotionLaw
        The half law of period I (0 ≤ α ≤ α1, ending at the speed peak), by name
        or as :class:`MotionLaw`.
    law2 : str or MotionLaw
        The half law of period II (α1 ≤ α ≤ α2), by name or as :class:`MotionLaw`.
    asymmetry : float, optional
        f_A = (α2 − α1)/α1 > 0 (complex 1), dimensionless.
    accel_ratio : float, optional
        I = Π''1max/Π''2max > 0 (complex 2), dimensionless, giving f_A = I·n1/n2.
    max_speed : float, optional
        Π'max [m/rad] (complex 3), which must lie strictly between Z'1max and
        Z'2max times the mean speed Π2/α2 (and the laws' speed peaks must differ).

    Returns
    -------
    TwoPeriodLaw
        The law.

    Raises
    ------
    InputError
        If ``stroke`` or ``angle`` is not positive or ``angle`` exceeds 2π, a law
        is not known or is a rise, not exactly one of the three data is given, a
        datum is out of its range, or the data give no 0 < Π1 < Π2 and
        0 < α1 < α2.

    Examples
    --------
    >>> import cyclomech as cm, math
    >>> lw = cm.motion.two_period(0.2, math.pi, "cycloidal", "modified_sine", asymmetry=2.0)
    >>> round(lw.angle1, 6), round(lw.stroke1, 6)
    (1.047198, 0.061102)
    """
    p2 = positive("stroke", stroke, "[m]")
    a2 = positive("angle", angle, "[rad]")
    if a2 > 2 * math.pi * (1 + 1e-12):
        raise InputError(f"angle = {angle!r} [rad] must not exceed one crank turn, 2π")
    l1, l2 = _half("law1", law1), _half("law2", law2)
    given = {
        k: v
        for k, v in (
            ("asymmetry", asymmetry),
            ("accel_ratio", accel_ratio),
            ("max_speed", max_speed),
        )
        if v is not None
    }
    if len(given) != 1:
        raise InputError(
            "give exactly one of asymmetry (f_A), accel_ratio (I) and max_speed (Π'max); "
            f"got {', '.join(given) or 'none'}"
        )
    v1, v2 = l1.dz_max, l2.dz_max
    n1, n2 = v1 / v2, l1.ddz_max / l2.ddz_max
    if asymmetry is not None:
        f = positive(
            "asymmetry", asymmetry, "(f_A = (α2 − α1)/α1; f_A ≤ 0 would put α1 at or past α2)"
        )
    elif accel_ratio is not None:
        f = positive("accel_ratio", accel_ratio, "(I = Π''1max/Π''2max)") * n1 / n2
    else:
        pm = positive("max_speed", max_speed, "[m/rad]")
        mean = p2 / a2
        lo, hi = sorted((v1, v2))
        if hi - lo <= 1e-12 * hi:
            raise InputError(
                f"max_speed cannot be chosen when both laws have the same speed peak "
                f"Z'max = {v1:.6g}: it is then fixed at Z'max·Π2/α2 = {v1 * mean:.6g} m/rad; "
                "give asymmetry or accel_ratio instead"
            )
        p = pm / mean
        if not lo < p < hi:
            raise InputError(
                f"max_speed = {pm!r} m/rad is outside the admissible range "
                f"({lo * mean:.6g}, {hi * mean:.6g}) m/rad: with law1 {l1.name!r} "
                f"(Z'max = {v1:.6g}) and law2 {l2.name!r} (Z'max = {v2:.6g}) the speed peak "
                f"lies strictly between {lo:.6g} and {hi:.6g} times the mean speed "
                f"Π2/α2 = {mean:.6g} m/rad"
            )
        f = v2 * (v1 - p) / (v1 * (p - v2))
    a1 = a2 / (1 + f)
    p1 = p2 / (1 + n1 * f)
    if not (0 < p1 < p2 and 0 < a1 < a2):
        raise InputError(
            f"these data give Π1 = {p1:.6g} m and α1 = {a1:.6g} rad; a law needs "
            f"0 < Π1 < Π2 = {p2:.6g} m and 0 < α1 < α2 = {a2:.6g} rad"
        )
    return TwoPeriodLaw(l1, l2, p2, a2, p1, a1)
