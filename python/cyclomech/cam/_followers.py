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
    """A roller follower translating along +y, its line offset ``offset`` [m]
    along +x from the cam centre; ``roller_radius`` 0 is the knife edge. Radii
    [m]: the pitch base circle is R_p = base_radius + roller_radius.

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
        """R_p = base_radius + roller_radius [m].

        >>> import cyclomech as cm
        >>> cm.cam.TranslatingRoller(0.04, 0.0).pitch_base_radius
        0.04
        """
        return self.base_radius + self.roller_radius

    def _kernel_args(self) -> tuple[str, list[float]]:
        return "translating", [self.base_radius, self.roller_radius, self.offset]


@dataclass(frozen=True)
class FlatFaced:
    """A translating flat-faced follower along +y, the face perpendicular to its
    motion; ``base_radius`` [m]. Its pressure angle is 0; the contact point lies
    s′ [m] off the follower's axis; the profile's radius of curvature is
    R_b + s + s″ and the profile cusps (undercut) where it is < 0.

    >>> import cyclomech as cm
    >>> cm.cam.FlatFaced(0.05).base_radius
    0.05
    """

    base_radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "base_radius", positive("base_radius", self.base_radius, "[m]"))

    def _kernel_args(self) -> tuple[str, list[float]]:
        return "flat", [self.base_radius]


@dataclass(frozen=True)
class OscillatingRoller:
    """A roller on an arm of ``arm_length`` l [m] swinging about a pivot at
    ``pivot_distance`` a [m] from the cam centre; radii [m]. The displacement of
    its segments is the arm's rotation [rad]. The initial arm angle ψ0 is where
    the roller centre lies on the pitch base circle R_p = base_radius +
    roller_radius: cos ψ0 = (a² + l² − R_p²)/(2al), which needs
    |a − l| < R_p < a + l.

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
        """R_p = base_radius + roller_radius [m].

        >>> import cyclomech as cm
        >>> cm.cam.OscillatingRoller(0.1, 0.08, 0.04, 0.01).pitch_base_radius
        0.05
        """
        return self.base_radius + self.roller_radius

    @property
    def initial_arm_angle_deg(self) -> float:
        """ψ0 [deg]: the arm angle from the line pivot → cam centre at which the
        roller centre lies on the pitch base circle.

        >>> import cyclomech as cm
        >>> round(cm.cam.OscillatingRoller(0.1, 0.1, 0.04, 0.0).initial_arm_angle_deg, 6)
        23.073918
        """
        a, arm, rp = self.pivot_distance, self.arm_length, self.pitch_base_radius
        return math.degrees(math.acos((a * a + arm * arm - rp * rp) / (2 * a * arm)))

    def _kernel_args(self) -> tuple[str, list[float]]:
        return "oscillating", [
            self.pivot_distance,
            self.arm_length,
            self.base_radius,
            self.roller_radius,
        ]


#: Any follower.
Follower = TranslatingRoller | FlatFaced | OscillatingRoller
