"""The cyclogram's result types and the one rule for minimum angles against
speed; part of :mod:`cyclomech.cyclogram`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np
import numpy.typing as npt

from .._units import DEG_PER_S_PER_RPM

if TYPE_CHECKING:
    from ._model import Operation

Arc = tuple[str, str]
Sense = Literal["<=", ">=", "=="]


@dataclass(frozen=True)
class Constraint:
    """A linear constraint Σ coeffs[arc]·t(arc) (sense) rhs on phase angles [deg]."""

    coeffs: tuple[tuple[Arc, float], ...]
    sense: Sense
    rhs: float
    name: str

    def describe(self) -> str:
        """The constraint as text (angles in degrees).

        >>> from cyclomech import Constraint
        >>> Constraint(((("3", "7"), -0.003),), "<=", -0.108, "rebound").describe()
        '-0.003·t(3,7) <= -0.108'
        """
        terms = " + ".join(f"{c:g}·t({a[0]},{a[1]})" for a, c in self.coeffs)
        return f"{terms} {self.sense} {self.rhs:g}"


@dataclass(frozen=True)
class Schedule:
    """Every operation at its minimum angle: the earliest schedule (angles in degrees).

    ``slack[arc]`` is the total slack (how much the operation can grow without
    moving the end of the schedule), ``free_slack[arc]`` how much it can grow
    without moving any event; ``critical`` lists every operation with zero total
    slack. Operations crossing into the next cycle (height > 0) do not order
    events within the cycle; their ``slack`` is p(y) + cycle_deg·h − p(x) − angle,
    negative when the schedule violates them; ``violated`` lists those.
    """

    operations: tuple[Operation, ...]
    events: tuple[str, ...]
    earliest: dict[str, float]
    latest: dict[str, float]
    angles: dict[Arc, float]
    slack: dict[Arc, float]
    free_slack: dict[Arc, float]
    critical: tuple[Arc, ...]
    duration: float
    cycle_deg: float
    speed_rpm: float | None
    violated: tuple[Arc, ...] = ()
    name: str = "cyclogram"

    @property
    def times(self) -> dict[str, float]:
        """Occurrence angle of each event [deg] (the earliest times)."""
        return self.earliest


@dataclass(frozen=True)
class Optimum:
    """Result of :meth:`Cyclogram.optimize` (angles in degrees).

    ``duals[name]`` is the shadow price of each bound and constraint: the change of
    ``objective`` per unit increase of that bound's value (a minimum angle, a
    maximum angle, a constraint's right-hand side, the cycle angle). ``slack[name]``
    is how far each is from binding; ``binding`` names those with zero slack.
    Bounds are named ``min[op]`` and ``max[op]``; the cycle bound ``cycle``.
    ``stretch[arc]`` is how much an operation got beyond its minimum angle;
    ``critical`` lists the operations on the chains that set the objective: those
    whose minimum, or a constraint on them, has a non-zero shadow price, and every
    operation at its minimum on a chain tied with them.
    """

    operations: tuple[Operation, ...]
    events: tuple[str, ...]
    times: dict[str, float]
    angles: dict[Arc, float]
    objective: float
    goal: Literal["min_duration", "max_limiting"]
    limiting: Arc | None
    duration: float
    cycle_deg: float
    speed_rpm: float | None
    duals: dict[str, float]
    slack: dict[str, float]
    binding: tuple[str, ...]
    stretch: dict[Arc, float]
    critical: tuple[Arc, ...]
    name: str = "cyclogram"


@dataclass(frozen=True)
class SpeedLimit:
    """The highest main-shaft speed ``rpm`` [rpm] at which a cyclogram, or a whole
    machine, works; one type for both (:meth:`Cyclogram.max_speed_rpm`,
    :meth:`cyclomech.Machine.speed_limit`).

    ``binding`` names the bounds and constraints that price the limit (a tuple of
    names everywhere; a list in ``results.json``); ``reason`` says why in words.
    For a cyclogram: ``cycle`` lists the operations of the critical chain (whose
    angles fill ``cycle_deg`` at that speed; ``inf`` when no time-bound operation
    limits it); ``network_rpm`` is the bound from the operations' minimum angles and
    durations alone (Howard's maximum cycle ratio); when maximum angles or added
    constraints lower it, ``rpm < network_rpm``. For a machine: ``rpm`` is the least
    of ``cyclogram_rpm`` (its cyclogram with the mechanisms' bounds still fits) and
    each mechanism's own limit in ``mechanisms_rpm`` (``mechanisms_reason`` says
    why for each); ``by`` names what sets it (``"cyclogram"`` or a mechanism).

    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", min_duration_s=0.05)
    >>> cg.add_operation("b", "c", min_angle_deg=150)
    >>> lim = cg.max_speed_rpm()
    >>> round(lim.rpm, 6), lim.by, lim.cycle
    (700.0, 'cyclogram', (('a', 'b'), ('b', 'c')))
    """

    rpm: float
    cycle: tuple[Arc, ...] = ()
    cycle_deg: float = 360.0
    network_rpm: float = math.inf
    binding: tuple[str, ...] = ()
    reason: str = ""
    by: str = "cyclogram"
    cyclogram_rpm: float = math.nan  # (None given: rpm)
    mechanisms_rpm: dict[str, float] = field(default_factory=dict)
    mechanisms_reason: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if math.isnan(self.cyclogram_rpm):  # a cyclogram's own limit
            object.__setattr__(self, "cyclogram_rpm", self.rpm)


def minimum_angles(
    angle_deg: npt.NDArray[np.float64], secs: npt.NDArray[np.float64], rpm: npt.ArrayLike
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """Each operation's minimum angle [deg] at each speed: max(min_angle_deg,
    6·n·min_duration_s) for the operations with a duration (``secs`` > 0), the angle
    alone for the others; shape ``rpm.shape + angle_deg.shape``. Also whether the
    duration sets it. The one place this rule is written.

    >>> import numpy as np
    >>> from cyclomech.cyclogram import minimum_angles
    >>> mins, timed = minimum_angles(np.array([120.0, 30.0]), np.array([0.1, 0.0]), [100.0, 300.0])
    >>> mins.tolist(), timed.tolist()
    ([[120.0, 30.0], [180.0, 30.0]], [[False, False], [True, False]])
    """
    n = np.asarray(rpm, dtype=np.float64)[..., None]
    dur = np.where(secs > 0, DEG_PER_S_PER_RPM * n * secs, -np.inf)
    by_time = dur > angle_deg
    return np.where(by_time, dur, angle_deg), by_time
