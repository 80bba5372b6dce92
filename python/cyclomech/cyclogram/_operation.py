"""One operation of the cyclogram (:class:`Operation`) and the checks of event ids
and angles the cyclogram shares; part of :mod:`cyclomech.cyclogram`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._arrays import real
from .._errors import InputError
from ._angles import Arc, minimum_angles

__all__ = ["Operation"]


#: Largest angle magnitude accepted anywhere [deg]: far beyond any machine cycle,
#: and small enough that sums over millions of operations cannot overflow.
MAX_ANGLE_DEG = 1e12


def _event_id(value: Any, field_name: str) -> str:
    if isinstance(value, bool) or not isinstance(value, str | int):
        raise InputError(f"{field_name} must be an event id (a string); got {value!r}")
    text = str(value)
    if not text.strip():
        raise InputError(f"{field_name} must be a non-empty event id; got {value!r}")
    return text


def _label(value: Any, field_name: str) -> str | None:
    """A name (an operation's ``name`` or ``mechanism``): None or a string. A
    number is refused: ``mechanism = 1.0`` in a file is a slip (a value
    typed into the wrong key), and read as the text "1.0" it named nothing."""
    if value is None:
        return None
    if not isinstance(value, str):
        raise InputError(f"{field_name} must be a name (a string); got {value!r}")
    return value


def _finite(
    value: Any, field_name: str, *, lower: float | None = None, limit: float | None = None
) -> float:
    try:
        x = real(value)
    except (TypeError, ValueError):
        raise InputError(f"{field_name} must be a real number; got {value!r}") from None
    if not math.isfinite(x):
        raise InputError(f"{field_name} must be finite; got {value!r}")
    if lower is not None and x < lower:
        raise InputError(f"{field_name} must be >= {lower:g}; got {value!r}")
    limit = MAX_ANGLE_DEG if limit is None else limit
    if abs(x) > limit:
        raise InputError(
            f"{field_name} = {value!r} is out of range: at most {limit:g} in magnitude"
        )
    return x


def _cycle(value: Any, field_name: str = "cycle_deg") -> float:
    x = _finite(value, field_name)
    if x <= 0:
        raise InputError(
            f"{field_name} must be a positive angle in degrees (360 for one turn); got {value!r}"
        )
    return x


@dataclass(frozen=True)
class Operation:
    """One operation (arc) of the cyclogram.

    Angles in degrees of main-shaft rotation. Usually built by
    :meth:`Cyclogram.add_operation`; every field is checked and normalised on
    construction, and each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    src : str
        The event x at which the operation starts.
    dst : str
        The event y at which it ends (another event than ``src``).
    min_angle_deg : float, default 0.0
        The smallest phase angle t(x, y) [deg], ≥ 0: the crank angle the operation
        takes.
    max_angle_deg : float, optional
        The largest phase angle [deg], ≥ ``min_angle_deg``; None (default) for no
        maximum.
    min_duration_s : float, default 0.0
        The shortest duration [s]: 0, or at least 1e-12 s; it takes 6·n·s degrees
        at n rpm.
    height : int, default 0
        The number of machine cycles the operation crosses (1 for an operation that
        ends in the next cycle), a whole number ≥ 0.
    name : str, optional
        A name for reports and for :meth:`Cyclogram.operation`.
    mechanism : str, optional
        The mechanism that performs it (a row of the cyclogram's plots).

    Raises
    ------
    InputError
        If the two events are the same, an angle or duration is not finite or out
        of its range, or ``height`` is not a whole number ≥ 0.

    Examples
    --------
    >>> from cyclomech import Operation
    >>> op = Operation("a", "b", min_angle_deg=30, name="feed")
    >>> op.arc, op.min_angle_deg, op.max_angle_deg, op.height
    (('a', 'b'), 30.0, None, 0)
    """

    src: str
    dst: str
    min_angle_deg: float = 0.0
    max_angle_deg: float | None = None
    min_duration_s: float = 0.0
    height: int = 0
    name: str | None = None
    mechanism: str | None = None

    def __post_init__(self) -> None:
        """Validate and normalise every field: an operation joins two different
        events; its phase angle is the crank angle it takes, so ``min_angle_deg``
        ≥ 0 (a negative one cannot be honoured: every event of a cycle lies in
        [0, cycle], so the optimum would silently give the operation 0°); its
        duration is 0 or at least 1e-12 s; ``height`` is a whole number ≥ 0."""
        src, dst = _event_id(self.src, "x"), _event_id(self.dst, "y")
        name = _label(self.name, f"operation {src}→{dst}: name")
        where = f"operation {name or f'{src}→{dst}'!r}"
        mechanism = _label(self.mechanism, f"{where}: mechanism")
        if src == dst:
            raise InputError(
                f"{where}: an operation must join two different events; got {src!r} twice"
            )
        lo = _finite(self.min_angle_deg, f"{where}: min_angle_deg")
        if lo < 0:
            raise InputError(
                f"{where}: min_angle_deg = {self.min_angle_deg!r} must be ≥ 0 [deg]: an "
                "operation's phase angle is the crank angle it takes (to let one event come "
                "before another, order the events differently or add a [[constraint]])"
            )
        hi = self.max_angle_deg
        if hi is not None:
            hi = _finite(hi, f"{where}: max_angle_deg")
            if hi < lo:
                raise InputError(f"{where}: max_angle_deg = {hi:g} is below min_angle_deg = {lo:g}")
        secs = _finite(self.min_duration_s, f"{where}: min_duration_s", lower=0.0)
        if 0.0 < secs < 1e-12:
            raise InputError(f"{where}: min_duration_s = {secs!r} s: 0, or at least 1e-12 s")
        h = self.height
        if isinstance(h, bool) or not isinstance(h, int | np.integer) or h < 0:
            raise InputError(
                f"{where}: height must be a non-negative integer (cycles crossed); got {h!r}"
            )
        for key, value in (
            ("src", src),
            ("dst", dst),
            ("min_angle_deg", lo),
            ("max_angle_deg", hi),
            ("min_duration_s", secs),
            ("height", int(h)),
            ("name", name),
            ("mechanism", mechanism),
        ):
            object.__setattr__(self, key, value)

    @property
    def arc(self) -> Arc:
        """The arc ``(src, dst)``: the operation's key in results.

        Examples
        --------
        >>> from cyclomech import Operation
        >>> Operation("a", "b").arc
        ('a', 'b')
        """
        return (self.src, self.dst)

    @property
    def title(self) -> str:
        """The name, or ``"src→dst"`` for an operation without one.

        Examples
        --------
        >>> from cyclomech import Operation
        >>> Operation("a", "b", name="feed").title, Operation("a", "b").title
        ('feed', 'a→b')
        """
        return self.name or f"{self.src}→{self.dst}"

    def min_angle_at(self, speed_rpm: float | None) -> float:
        """Minimum angle [deg] at a speed [rpm]: max(min_angle_deg, 6·n·min_duration_s).

        Parameters
        ----------
        speed_rpm : float or None
            The main-shaft speed n [rpm], ≥ 0; None for an operation without a
            duration.

        Returns
        -------
        float
            The minimum phase angle [deg].

        Raises
        ------
        InputError
            If ``speed_rpm`` is negative or not finite, or is None for an operation
            with a minimum duration.

        Examples
        --------
        >>> from cyclomech import Operation
        >>> Operation("a", "b", min_angle_deg=120, min_duration_s=0.1).min_angle_at(300)
        180.0
        """
        if speed_rpm is not None:
            speed_rpm = _finite(speed_rpm, "speed_rpm", lower=0.0, limit=math.inf)
        if self.min_duration_s == 0.0:
            return self.min_angle_deg
        if speed_rpm is None:
            raise InputError(
                f"operation {self.title!r} has a minimum duration of {self.min_duration_s:g} s; "
                "pass speed_rpm to convert it to degrees"
            )
        mins, _ = minimum_angles(
            np.array([self.min_angle_deg]), np.array([self.min_duration_s]), speed_rpm
        )
        return float(mins[0])
