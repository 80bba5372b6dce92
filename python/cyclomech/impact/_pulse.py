"""Force pulses of an impact as piecewise-linear tables (:class:`Pulse`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from .._arrays import count, finite_number, float_array, positive
from .._errors import InputError
from ._checks import Array

__all__ = ["Pulse"]


def _force(value: Any, name: str = "peak", unit: str = "[N]") -> float:
    return finite_number(name, value, unit)


def _checked_table(t: Any, f: Any) -> tuple[Array, Array]:
    """``t`` and ``f`` as read-only float arrays, checked as :meth:`Pulse.table`
    documents, or :class:`InputError`."""
    try:  # float_array: strings and bools are not numbers, as np.array(float) had it
        ta = np.array(float_array("pulse t", t, ndims=None), ndmin=1)
        fa = np.array(float_array("pulse f", f, ndims=None), ndmin=1)
    except InputError:
        raise InputError(
            f"a pulse table needs t and f as arrays of numbers; got t = {t!r}, f = {f!r}"
        ) from None
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
    return ta, fa


@dataclass(frozen=True)
class Pulse:
    """A force pulse as a piecewise-linear table of force [N] over time [s].

    Zero after the last point unless the table says otherwise. Named shapes:
    :meth:`rectangular`, :meth:`decaying` (the seed's fig. 7 law),
    :meth:`triangular`, :meth:`half_sine`; any table by :meth:`table`. Every pulse
    is checked as :meth:`table` documents, the constructor's too. Each parameter is
    kept as the attribute of the same name (as a read-only float array).

    Parameters
    ----------
    t : ndarray of float, shape (N,)
        The times [s], non-decreasing from 0; a repeated time is a jump of the force
        there.
    f : ndarray of float, shape (N,)
        The force at each time [N].
    shape : str, default "table"
        The shape's name (``"rectangular"``, ``"decaying"``, ``"triangular"``,
        ``"half_sine"`` or ``"table"``).

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.impact.Pulse.rectangular(2.0, 1e-3)
    >>> p.t.tolist(), p.f.tolist(), round(p.impulse, 12)
    ([0.0, 0.001, 0.001], [2.0, 2.0, 0.0], 0.002)
    """

    t: Array
    f: Array
    shape: str = "table"

    def __post_init__(self) -> None:
        # Every pulse is checked, built by a named shape, by table or directly.
        ta, fa = _checked_table(self.t, self.f)
        object.__setattr__(self, "t", ta)
        object.__setattr__(self, "f", fa)

    @property
    def duration(self) -> float:
        """Time of the last point [s].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.impact.Pulse.triangular(1.0, 2e-3).duration
        0.002
        """
        return float(self.t[-1])

    @property
    def peak(self) -> float:
        """Largest |force| [N].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.impact.Pulse.decaying(3.0, 1e-3).peak
        3.0
        """
        return float(np.abs(self.f).max())

    @property
    def impulse(self) -> float:
        """∫ F dt [N·s] (exact for the linear pieces).

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.impact.Pulse.decaying(3.0, 1e-3).impulse, 12)
        0.0015
        """
        return float(np.sum(np.diff(self.t) * 0.5 * (self.f[1:] + self.f[:-1])))

    def scaled(self, factor: float) -> Pulse:
        """The same shape with every force times ``factor``.

        Parameters
        ----------
        factor : float
            The factor on the force (finite).

        Returns
        -------
        Pulse
            The scaled pulse, of the same times and shape name.

        Raises
        ------
        InputError
            If ``factor`` is not a finite number.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.impact.Pulse.rectangular(1.0, 1e-3).scaled(4.0).peak
        4.0
        """
        return Pulse.table(self.t, self.f * _force(factor, "factor", ""), self.shape)

    @classmethod
    def table(cls, t: npt.ArrayLike, f: npt.ArrayLike, shape: str = "table") -> Pulse:
        """A pulse from a user table.

        Parameters
        ----------
        t : array_like of float, shape (N,)
            The times [s], N ≥ 2, starting at 0 (the instant of impact) and never
            decreasing (repeat a time for a jump); the last > 0.
        f : array_like of float, shape (N,)
            The force at each time [N].
        shape : str, default "table"
            The shape's name, kept as ``shape``.

        Returns
        -------
        Pulse
            The pulse (its arrays read-only).

        Raises
        ------
        InputError
            If ``t`` and ``f`` are not 1-D arrays of one length with at least 2 finite
            points, ``t`` does not start at 0, decreases, or does not last.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.impact.Pulse.table([0, 1e-3, 2e-3], [0, 5, 0]).peak
        5.0
        """
        # Checked once, by __post_init__ (which takes any array-like).
        return cls(cast(Array, t), cast(Array, f), shape)

    @classmethod
    def rectangular(cls, peak: float, duration: float) -> Pulse:
        """Constant ``peak`` [N] for ``duration`` [s], then zero.

        Parameters
        ----------
        peak : float
            The force [N].
        duration : float
            The pulse's duration [s] (> 0).

        Returns
        -------
        Pulse
            The pulse, shape ``"rectangular"``.

        Raises
        ------
        InputError
            If ``peak`` is not finite or ``duration`` not positive.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.impact.Pulse.rectangular(1.0, 1e-3).f.tolist()
        [1.0, 1.0, 0.0]
        """
        p, d = _force(peak), positive("duration", duration, "[s]")
        return cls.table([0.0, d, d], [p, p, 0.0], "rectangular")

    @classmethod
    def decaying(cls, peak: float, duration: float, end: float = 0.0) -> Pulse:
        """The seed's impact law (fig. 7): a peak at the instant of impact, falling linearly.

        ``peak`` at the instant of impact, falling linearly to ``end``·peak at
        ``duration``, then zero (``end`` = 0: a decaying triangle; the seed's printed
        F·(1 − t/2τ) is ``end`` = ½).

        Parameters
        ----------
        peak : float
            The force at the instant of impact [N].
        duration : float
            The pulse's duration [s] (> 0).
        end : float, default 0.0
            The force at ``duration`` as a fraction of the peak, in [0, 1].

        Returns
        -------
        Pulse
            The pulse, shape ``"decaying"``.

        Raises
        ------
        InputError
            If ``peak`` is not finite, ``duration`` not positive or ``end`` outside [0, 1].

        Examples
        --------
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

        Parameters
        ----------
        peak : float
            The force at half the duration [N].
        duration : float
            The pulse's duration [s] (> 0).

        Returns
        -------
        Pulse
            The pulse, shape ``"triangular"``.

        Raises
        ------
        InputError
            If ``peak`` is not finite or ``duration`` not positive.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.impact.Pulse.triangular(1.0, 2e-3).t.tolist()
        [0.0, 0.001, 0.002]
        """
        p, d = _force(peak), positive("duration", duration, "[s]")
        return cls.table([0.0, 0.5 * d, d], [0.0, p, 0.0], "triangular")

    @classmethod
    def half_sine(cls, peak: float, duration: float, points: int = 257) -> Pulse:
        """``peak``·sin(πt/duration) over ``duration`` [s], sampled at ``points`` points.

        Linear between the points: the table's impulse falls short of the sine's by
        about (π²/12)/(points−1)² relative.

        Parameters
        ----------
        peak : float
            The sine's amplitude [N].
        duration : float
            The pulse's duration [s] (> 0).
        points : int, default 257
            The number of samples (3 to 10⁷).

        Returns
        -------
        Pulse
            The pulse, shape ``"half_sine"``.

        Raises
        ------
        InputError
            If ``peak`` is not finite, ``duration`` not positive or ``points`` out of
            range.

        Examples
        --------
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
