"""The followers: `_followers` part of :mod:`cyclomech.cam` (its door)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .._arrays import finite_number, positive
from .._errors import InputError

__all__ = ["FlatFaced", "Follower", "OscillatingRoller", "TranslatingRoller"]


def _roller(base_radius: Any, roller_radius: Any) -> tuple[float, float]:
    b = positive("base_radius", base_radius, "[m]")
    r = finite_number("roller_radius", roller_radius, "[m]", low=0.0)
    if r >= b:
        raise InputError(
            f"roller_radius = {r!r} [m] must be < base_radius = {b!r} [m] "
            "(a roller larger than the base circle)"
        )
    return b, r


@dataclass(frozen=True)
class TranslatingRoller:
    """A roller follower translating along +y, its line offset from the cam centre.

    ``roller_radius`` 0 is the knife edge. The pitch base circle is
    R_p = base_radius + roller_radius [m]. Each parameter is kept as the attribute of
    the same name (as a float).

    Parameters
    ----------
    base_radius : float
        The base circle's radius [m] (> 0).
    roller_radius : float
        The roller's radius [m], in [0, base_radius) (0: a knife edge).
    offset : float, default 0.0
        The follower's line offset along +x from the cam centre [m];
        |offset| < base_radius + roller_radius.

    Raises
    ------
    InputError
        If a radius is not finite, ``base_radius`` is not > 0, ``roller_radius`` is
        negative or not smaller than ``base_radius``, or |offset| ≥ R_p.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.cam.TranslatingRoller(0.05, 0.01, offset=0.005).pitch_base_radius
    0.060000000000000005
    >>> cm.cam.TranslatingRoller(0.01, 0.02)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: roller_radius = 0.02 [m] must be < base_radius = 0.01 [m] ...
    """

    base_radius: float
    roller_radius: float
    offset: float = 0.0

    def __post_init__(self) -> None:
        b, r = _roller(self.base_radius, self.roller_radius)
        e = finite_number("offset", self.offset, "[m]")
        if abs(e) >= b + r:
            raise InputError(
                f"offset = {e!r} [m] must satisfy |offset| < base_radius + roller_radius "
                f"= {b + r!r} [m]"
            )
        object.__setattr__(self, "base_radius", b)
        object.__setattr__(self, "roller_radius", r)
        object.__setattr__(self, "offset", e)

    @property
    def pitch_base_radius(self) -> float:
        """The pitch base circle's radius R_p = base_radius + roller_radius [m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.cam.TranslatingRoller(0.04, 0.0).pitch_base_radius
        0.04
        """
        return self.base_radius + self.roller_radius

    @property
    def title(self) -> str:
        """The follower in words, as reports and figures name it.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.cam.TranslatingRoller(0.04, 0.01).title, cm.cam.TranslatingRoller(0.04, 0.0).title
        ('translating roller', 'knife edge')
        """
        return "translating roller" if self.roller_radius > 0.0 else "knife edge"

    def _kernel_args(self) -> tuple[str, list[float]]:
        return "translating", [self.base_radius, self.roller_radius, self.offset]


@dataclass(frozen=True)
class FlatFaced:
    """A translating flat-faced follower along +y, the face perpendicular to its motion.

    Its pressure angle is 0; the contact point lies s′ [m] off the follower's axis;
    the profile's radius of curvature is R_b + s + s″ and the profile cusps
    (undercut) where it is < 0. The parameter is kept as the attribute of the same
    name (as a float).

    Parameters
    ----------
    base_radius : float
        The base circle's radius R_b [m] (> 0).

    Raises
    ------
    InputError
        If ``base_radius`` is not a finite number > 0.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.cam.FlatFaced(0.05).base_radius
    0.05
    """

    base_radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "base_radius", positive("base_radius", self.base_radius, "[m]"))

    @property
    def title(self) -> str:
        """The follower in words, as reports and figures name it.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.cam.FlatFaced(0.05).title
        'flat-faced'
        """
        return "flat-faced"

    def _kernel_args(self) -> tuple[str, list[float]]:
        return "flat", [self.base_radius]


@dataclass(frozen=True)
class OscillatingRoller:
    """A roller on an arm swinging about a pivot.

    The displacement of its segments is the arm's rotation [rad]. The initial arm
    angle ψ0 is where the roller centre lies on the pitch base circle
    R_p = base_radius + roller_radius: cos ψ0 = (a² + l² − R_p²)/(2al), which needs
    |a − l| < R_p < a + l. Each parameter is kept as the attribute of the same name
    (as a float).

    Parameters
    ----------
    pivot_distance : float
        The distance a from the cam centre to the arm's pivot [m] (> 0).
    arm_length : float
        The arm's length l, pivot to roller centre [m] (> 0).
    base_radius : float
        The base circle's radius [m] (> 0).
    roller_radius : float
        The roller's radius [m], in [0, base_radius).

    Raises
    ------
    InputError
        If a length is not finite and > 0, ``roller_radius`` is not in
        [0, base_radius), or the roller cannot reach the pitch base circle
        (not |a − l| < R_p < a + l).

    Examples
    --------
    >>> import cyclomech as cm
    >>> f = cm.cam.OscillatingRoller(0.1, 0.08, 0.04, 0.01)
    >>> round(f.initial_arm_angle_deg, 6)
    29.686295
    """

    pivot_distance: float
    arm_length: float
    base_radius: float
    roller_radius: float

    def __post_init__(self) -> None:
        a = positive("pivot_distance", self.pivot_distance, "[m]")
        arm = positive("arm_length", self.arm_length, "[m]")
        b, r = _roller(self.base_radius, self.roller_radius)
        rp = b + r
        if not abs(a - arm) < rp < a + arm:
            raise InputError(
                f"pivot_distance = {a!r} [m] and arm_length = {arm!r} [m]: the roller cannot "
                f"reach the pitch base circle R_p = {rp!r} [m] (needs |a − l| < R_p < a + l)"
            )
        for name, v in (("pivot_distance", a), ("arm_length", arm), ("base_radius", b)):
            object.__setattr__(self, name, v)
        object.__setattr__(self, "roller_radius", r)

    @property
    def pitch_base_radius(self) -> float:
        """The pitch base circle's radius R_p = base_radius + roller_radius [m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.cam.OscillatingRoller(0.1, 0.08, 0.04, 0.01).pitch_base_radius
        0.05
        """
        return self.base_radius + self.roller_radius

    @property
    def initial_arm_angle_deg(self) -> float:
        """The initial arm angle ψ0 [deg].

        The arm angle from the line pivot → cam centre at which the roller centre lies
        on the pitch base circle.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.cam.OscillatingRoller(0.1, 0.1, 0.04, 0.0).initial_arm_angle_deg, 6)
        23.073918
        """
        a, arm, rp = self.pivot_distance, self.arm_length, self.pitch_base_radius
        return math.degrees(math.acos((a * a + arm * arm - rp * rp) / (2 * a * arm)))

    @property
    def title(self) -> str:
        """The follower in words, as reports and figures name it.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.cam.OscillatingRoller(0.13, 0.1, 0.06, 0.012).title
        'oscillating roller'
        """
        return "oscillating roller"

    def _kernel_args(self) -> tuple[str, list[float]]:
        return "oscillating", [
            self.pivot_distance,
            self.arm_length,
            self.base_radius,
            self.roller_radius,
        ]


#: Any follower.
Follower = TranslatingRoller | FlatFaced | OscillatingRoller
