"""The cyclogram: `_model` part of :mod:`cyclomech.cyclogram` (its door)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
from scipy import sparse
from scipy.optimize import linprog
from scipy.sparse.csgraph import breadth_first_order

from .. import _core, _toml
from .._arrays import real
from .._errors import CycleError, InfeasibleError, InputError, SolverError
from .._units import DEG_PER_S_PER_RPM

__all__ = [
    "Arc",
    "Constraint",
    "Cyclogram",
    "Operation",
    "Optimum",
    "Schedule",
    "SpeedLimit",
]

Arc = tuple[str, str]
Sense = Literal["<=", ">=", "=="]

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

    Angles in degrees of main-shaft rotation; ``min_duration_s`` in seconds;
    ``height`` is the number of machine cycles the operation crosses (1 for an
    operation that ends in the next cycle).
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
        where = f"operation {self.name or f'{src}→{dst}'!r}"
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
            ("name", None if self.name is None else str(self.name)),
            ("mechanism", None if self.mechanism is None else str(self.mechanism)),
        ):
            object.__setattr__(self, key, value)

    @property
    def arc(self) -> Arc:
        """The arc ``(src, dst)``."""
        return (self.src, self.dst)

    @property
    def title(self) -> str:
        """The name, or ``"src→dst"``."""
        return self.name or f"{self.src}→{self.dst}"

    def min_angle_at(self, speed_rpm: float | None) -> float:
        """Minimum angle [deg] at a speed [rpm]: max(min_angle_deg, 6·n·min_duration_s).

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
        return max(self.min_angle_deg, DEG_PER_S_PER_RPM * speed_rpm * self.min_duration_s)


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
    """Result of :meth:`Cyclogram.max_speed_rpm`.

    ``rpm`` is the highest main-shaft speed at which the cyclogram fits in
    ``cycle_deg`` (``inf`` when no time-bound operation limits it). ``cycle`` lists
    the operations of the critical cycle (the chain whose angles fill the cycle at
    that speed). ``network_rpm`` is the bound from the operations' minimum angles
    and durations alone (Howard's maximum cycle ratio); when maximum angles or
    added constraints lower it, ``rpm < network_rpm``, ``cycle`` lists the
    operations held at their minimum and ``binding`` names the constraints, maximum
    angles and the cycle bound that price the limit (non-zero shadow price).
    """

    rpm: float
    cycle: tuple[Arc, ...]
    cycle_deg: float
    network_rpm: float
    binding: tuple[str, ...] = field(default=())


_OP_KEYS = {
    "from",
    "to",
    "min_angle_deg",
    "max_angle_deg",
    "min_duration_s",
    "height",
    "name",
    "mechanism",
}
_CG_KEYS = {"name", "cycle_deg", "limiting", "speed_rpm", "events"}
_CON_KEYS = {"name", "terms", "sense", "rhs"}
_TERM_KEYS = {"from", "to", "coeff"}


class Cyclogram:
    """The network cyclogram of a machine or of one group of its mechanisms.

    Parameters
    ----------
    name : a title for reports.
    cycle_deg : the machine cycle [deg], 360 for one main-shaft turn.
    limiting : the limiting operation (an arc or an operation name), whose angle
        :meth:`optimize` maximises by default.
    speed_rpm : main-shaft speed [rpm] at which operations with a minimum duration
        in seconds are converted to degrees, unless a method is given another.

    Examples
    --------
    The seed's linearised rebound constraint a(3,7) = -0.003·t(3,7) + 0.208 ≤ 0.1 mm
    forces t(3,7) ≥ 36°:

    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("1", "3", min_angle_deg=40, mechanism="lifter")
    >>> cg.add_operation("3", "7", min_angle_deg=20, mechanism="lifter")
    >>> cg.add_constraint({("3", "7"): -0.003}, "<=", 0.1 - 0.208, name="rebound")
    >>> opt = cg.optimize()
    >>> round(opt.angles[("3", "7")], 6), round(opt.objective, 6), opt.binding
    (36.0, 76.0, ('min[1→3]', 'rebound'))
    """

    def __init__(
        self,
        name: str = "cyclogram",
        *,
        cycle_deg: float = 360.0,
        limiting: Arc | str | None = None,
        speed_rpm: float | None = None,
    ) -> None:
        self.name = str(name)
        self.cycle_deg = _cycle(cycle_deg)
        self.speed_rpm = speed_rpm
        self._events: dict[str, int] = {}
        self._ops: list[Operation] = []
        self._arc_index: dict[Arc, int] = {}
        self._constraints: list[Constraint] = []
        if limiting is not None and not (
            isinstance(limiting, str)
            or (
                isinstance(limiting, tuple | list)
                and len(limiting) == 2
                and all(isinstance(v, str) for v in limiting)
            )
        ):
            raise InputError(
                f"limiting = {limiting!r} must be an operation's name or its arc (x, y) of "
                "two event names"
            )
        self._limiting_spec = limiting
        # Per-operation columns, appended as operations are added and turned into
        # arrays once per change, so no method loops over operations in Python.
        self._columns: dict[str, list[float]] = {
            k: [] for k in ("src", "dst", "height", "angle", "secs")
        }
        self._column_arrays: dict[str, npt.NDArray[Any]] = {}

    @property
    def speed_rpm(self) -> float | None:
        """Main-shaft speed [rpm] for time-bound operations, or None."""
        return self._speed_rpm

    @speed_rpm.setter
    def speed_rpm(self, value: float | None) -> None:
        self._speed_rpm = None if value is None else _finite(value, "speed_rpm", lower=0.0)

    # ----------------------------------------------------------------- building
    def add_event(self, event: str) -> str:
        """Add an event (idempotent) and return its id; events of operations are
        added by :meth:`add_operation` anyway, this fixes their order for reports.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_event("10.1")
        '10.1'
        >>> cg.events
        ('10.1',)
        """
        e = _event_id(event, "event")
        self._events.setdefault(e, len(self._events))
        return e

    def add_operation(
        self,
        x: str,
        y: str,
        min_angle_deg: float = 0.0,
        max_angle_deg: float | None = None,
        name: str | None = None,
        mechanism: str | None = None,
        *,
        min_duration_s: float = 0.0,
        height: int = 0,
    ) -> None:
        """Add the operation x → y.

        ``min_angle_deg`` / ``max_angle_deg`` bound its phase angle [deg];
        ``min_duration_s`` [s] makes it time-bound (6·n·s degrees at n rpm);
        ``height = 1`` for an operation that ends in the next machine cycle.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("1", "3", 45, 90, name="lift", mechanism="lifter")
        >>> op = cg.operation("lift")
        >>> op.arc, op.min_angle_deg, op.max_angle_deg, op.mechanism
        (('1', '3'), 45.0, 90.0, 'lifter')
        """
        op = Operation(x, y, min_angle_deg, max_angle_deg, min_duration_s, height, name, mechanism)
        if op.arc in self._arc_index:
            raise InputError(
                f"operation {op.title!r}: an operation {op.src}→{op.dst} already exists; "
                "state all its bounds in one operation"
            )
        self.add_event(op.src)
        self.add_event(op.dst)
        self._arc_index[op.arc] = len(self._ops)
        self._ops.append(op)
        for key, value in (
            ("src", self._events[op.src]),
            ("dst", self._events[op.dst]),
            ("height", float(op.height)),
            ("angle", op.min_angle_deg),
            ("secs", op.min_duration_s),
        ):
            self._columns[key].append(value)
        self._column_arrays.clear()

    def add_constraint(
        self,
        coeffs: Mapping[tuple[str, str], float] | Constraint,
        sense: str | None = None,
        rhs: float | None = None,
        name: str | None = None,
    ) -> None:
        """Add Σ coeffs[(x, y)]·t(x, y) (sense) rhs, with sense ``"<="``, ``">="`` or ``"=="``.

        Angles in degrees. The operations named in ``coeffs`` must exist. A
        :class:`Constraint` (e.g. from :meth:`cyclomech.impact.StopImpact.constraint`)
        may be passed alone.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("3", "7", 20)
        >>> cg.add_constraint({("3", "7"): -0.003}, "<=", 0.1 - 0.208, name="rebound")
        >>> cg.constraints[0].describe()
        '-0.003·t(3,7) <= -0.108'
        """
        if isinstance(coeffs, Constraint):
            if sense is not None or rhs is not None:
                raise InputError("pass a Constraint alone, or coeffs, sense and rhs; not both")
            coeffs, sense, rhs, name = (
                dict(coeffs.coeffs),
                coeffs.sense,
                coeffs.rhs,
                coeffs.name if name is None else name,
            )
        if sense is None or rhs is None:
            raise InputError("add_constraint needs coeffs, sense and rhs (or one Constraint)")
        name = str(name) if name is not None else f"constraint {len(self._constraints) + 1}"
        if any(c.name == name for c in self._constraints):
            raise InputError(
                f"constraint {name!r} already exists; give each constraint its own name"
            )
        if name == "cycle" or name.startswith(("min[", "max[", "duration[")):
            raise InputError(
                f"constraint name {name!r} is reserved for the bounds in results "
                "('cycle', 'min[…]', 'max[…]', 'duration[…]'); choose another name"
            )
        if sense not in ("<=", ">=", "=="):
            raise InputError(
                f"constraint {name!r}: sense must be '<=', '>=' or '=='; got {sense!r}"
            )
        if not isinstance(coeffs, Mapping) or not coeffs:
            raise InputError(
                f"constraint {name!r}: coeffs must map arcs (x, y) to coefficients; got {coeffs!r}"
            )
        terms = []
        for arc, c in coeffs.items():
            if not (isinstance(arc, tuple) and len(arc) == 2):
                raise InputError(f"constraint {name!r}: keys must be arcs (x, y); got {arc!r}")
            a = (_event_id(arc[0], "arc"), _event_id(arc[1], "arc"))
            if a not in self._arc_index:
                known = ", ".join(f"{s}→{d}" for s, d in self._arc_index) or "none"
                raise InputError(
                    f"constraint {name!r}: there is no operation {a[0]}→{a[1]}; "
                    f"add it first (known: {known})"
                )
            terms.append(
                (a, _finite(c, f"constraint {name!r}: the coefficient (coeff) of {a[0]}→{a[1]}"))
            )
        self._constraints.append(
            Constraint(tuple(terms), sense, _finite(rhs, f"constraint {name!r}: rhs"), name)  # type: ignore[arg-type]
        )

    # ------------------------------------------------------------------ access
    @property
    def events(self) -> tuple[str, ...]:
        """Event ids in the order they were added."""
        return tuple(self._events)

    @property
    def operations(self) -> tuple[Operation, ...]:
        """The operations in the order they were added."""
        return tuple(self._ops)

    @property
    def constraints(self) -> tuple[Constraint, ...]:
        """The added linear constraints."""
        return tuple(self._constraints)

    @property
    def limiting(self) -> Arc | None:
        """The limiting operation's arc, if one was set."""
        return (
            None
            if self._limiting_spec is None
            else self._resolve_op(self._limiting_spec, "limiting")
        )

    def operation(self, key: Arc | str) -> Operation:
        """The operation with this arc ``(x, y)`` or this name.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", 30, name="feed")
        >>> cg.operation(("a", "b")) is cg.operation("feed")
        True
        """
        return self._ops[self._arc_index[self._resolve_op(key, "operation")]]

    def _resolve_op(self, key: Arc | str | list[str], what: str) -> Arc:
        names = (
            ", ".join(f"{o.src}→{o.dst}" + (f" ({o.name!r})" if o.name else "") for o in self._ops)
            or "none"
        )
        if isinstance(key, tuple | list) and len(key) == 2:
            arc = (_event_id(key[0], what), _event_id(key[1], what))
            if arc in self._arc_index:
                return arc
            raise InputError(
                f"{what} = {key!r}: there is no operation {arc[0]}→{arc[1]}; "
                f"the operations are {names}"
            )
        if isinstance(key, str):
            hits = [op.arc for op in self._ops if op.name == key]
            if len(hits) == 1:
                return hits[0]
            if len(hits) > 1:
                raise InputError(
                    f"{what} = {key!r}: several operations have that name; give the arc (x, y)"
                )
        raise InputError(
            f"{what} = {key!r} is neither an arc (x, y) nor an operation name (known: {names})"
        )

    def _speed(self, speed_rpm: float | None) -> float | None:
        if speed_rpm is None:
            return self.speed_rpm
        return _finite(speed_rpm, "speed_rpm", lower=0.0)

    def _column(self, key: str) -> npt.NDArray[Any]:
        if key not in self._column_arrays:
            dtype = np.int64 if key in ("src", "dst") else np.float64
            self._column_arrays[key] = np.array(self._columns[key], dtype=dtype)
        return self._column_arrays[key]

    def _arrays(
        self,
    ) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.float64]]:
        return self._column("src"), self._column("dst"), self._column("height")

    def min_angles(self, speed_rpm: float | None = None) -> npt.NDArray[np.float64]:
        """Minimum angle of each operation [deg] at ``speed_rpm`` (default: the cyclogram's).

        max(min_angle_deg, 6·n·min_duration_s) for each operation, in the order added.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", min_angle_deg=30)
        >>> cg.add_operation("b", "c", min_angle_deg=10, min_duration_s=0.02)
        >>> cg.min_angles(speed_rpm=500).tolist()   # 6 · 500 rpm · 0.02 s = 60°
        [30.0, 60.0]
        """
        n = self._speed(speed_rpm)
        angle, secs = self._column("angle"), self._column("secs")
        timed = secs > 0
        if not timed.any():
            return angle.copy()
        if n is None:
            self._ops[int(np.argmax(timed))].min_angle_at(None)  # raises, naming the operation
        assert n is not None
        out = np.maximum(angle, np.where(timed, DEG_PER_S_PER_RPM * n * secs, -np.inf))
        bad = ~(np.abs(out) <= MAX_ANGLE_DEG)
        if bad.any():
            op = self._ops[int(np.argmax(bad))]
            raise InputError(
                f"operation {op.title!r}: at speed_rpm = {n:g} its minimum duration of "
                f"{op.min_duration_s:g} s is {out[bad][0]:g}°, beyond any machine cycle "
                f"(at most {MAX_ANGLE_DEG:g}°); give a realistic speed"
            )
        return out

    def _bound_labels(self) -> list[str]:
        """The label of each operation's bounds in results (``min[label]``, ``max[label]``):
        its title, with the arc added where several operations share a title."""
        titles = [op.title for op in self._ops]
        seen: dict[str, int] = {}
        for t in titles:
            seen[t] = seen.get(t, 0) + 1
        return [
            t if seen[t] == 1 else f"{t} ({op.src}→{op.dst})"
            for t, op in zip(titles, self._ops, strict=True)
        ]

    def _require_ops(self) -> None:
        if not self._ops:
            raise InputError(
                f"cyclogram {self.name!r} has no operations; add some with add_operation"
            )

    # ---------------------------------------------------------------- schedule
    def schedule(
        self, speed_rpm: float | None = None, horizon_deg: float | None = None
    ) -> Schedule:
        """The earliest schedule with every operation at its minimum angle.

        ``horizon_deg`` [deg] is the angle by which every event must occur for the
        latest times (default: the schedule's own end, so the critical operations
        are those on the longest chains). Raises :class:`CycleError` when the
        operations within one cycle form a cycle.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("1", "2", 40)
        >>> cg.add_operation("2", "4", 30)
        >>> cg.add_operation("1", "3", 20)
        >>> cg.add_operation("3", "4", 30)
        >>> s = cg.schedule()
        >>> s.duration, s.critical, s.slack[("1", "3")]
        (70.0, (('1', '2'), ('2', '4')), 20.0)
        """
        self._require_ops()
        n = self._speed(speed_rpm)
        w = self.min_angles(n)
        src, dst, h = self._arrays()
        inner = h == 0
        try:
            g = _core.EventGraph(len(self._events), src[inner], dst[inner])
        except CycleError as e:
            raise self._named_cycle(e) from None
        horizon = None if horizon_deg is None else _finite(horizon_deg, "horizon_deg")
        a = g.analyze(np.ascontiguousarray(w[inner]), horizon)
        names = self.events
        t = a["earliest"]
        # Arcs of height 0 get their slack from the kernel; operations that end in a
        # later cycle are checked against the schedule: p(y) + C·h − p(x) − angle.
        total = np.empty(len(w))
        free = np.empty(len(w))
        crit = np.zeros(len(w), bool)
        total[inner], free[inner], crit[inner] = a["total_slack"], a["free_slack"], a["critical"]
        outer = ~inner
        across = t[dst[outer]] + self.cycle_deg * h[outer] - t[src[outer]] - w[outer]
        total[outer] = free[outer] = across
        crit[outer] = np.abs(across) <= a["tolerance"]
        bad = outer.copy()
        bad[outer] = across < -a["tolerance"]
        arcs = list(self._arc_index)  # in operation order
        return Schedule(
            operations=self.operations,
            events=names,
            earliest=dict(zip(names, t.tolist(), strict=True)),
            latest=dict(zip(names, a["latest"].tolist(), strict=True)),
            angles=dict(zip(arcs, w.tolist(), strict=True)),
            slack=dict(zip(arcs, total.tolist(), strict=True)),
            free_slack=dict(zip(arcs, free.tolist(), strict=True)),
            critical=tuple(arcs[e] for e in np.flatnonzero(crit)),
            duration=float(t.max() - t.min()) if t.size else 0.0,
            cycle_deg=self.cycle_deg,
            speed_rpm=n,
            violated=tuple(arcs[e] for e in np.flatnonzero(bad)),
            name=self.name,
        )

    def _named_cycle(self, e: CycleError) -> CycleError:
        names = self.events
        ev = [names[i] for i in e.events]
        chain = " → ".join([*ev, ev[0]])
        return CycleError(
            f"cyclogram {self.name!r}: the operations {chain} form a cycle within one machine "
            "cycle; an operation that ends in the next cycle needs height=1",
            ev,
        )

    # ---------------------------------------------------------------- optimize
    def optimize(
        self,
        cycle_deg: float | None = None,
        limiting: Arc | str | None = None,
        speed_rpm: float | None = None,
    ) -> Optimum:
        """Optimise the phase angles by linear programming (HiGHS), seed eq. (1).

        Without a limiting operation: minimise the duration p(N) − p(1) (the span
        from the first to the last event), subject to every operation's bounds, the
        added constraints and the span fitting in the cycle. With ``limiting`` (or
        the cyclogram's own): maximise that operation's angle instead, inside the
        cycle. ``cycle_deg`` defaults to the cyclogram's; ``speed_rpm`` converts
        time-bound operations to degrees.

        Raises :class:`InfeasibleError` naming the chain of operations whose minimum
        angles exceed the cycle, or the smallest set of bounds and constraints that
        conflict.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram(limiting=("10.1", "10.2"))
        >>> cg.add_operation("1", "10.1", 100, name="group")
        >>> cg.add_operation("10.1", "10.2", 150, name="weft insertion")
        >>> opt = cg.optimize()                  # the insertion gets what the group leaves
        >>> opt.objective, opt.duals["min[group]"], opt.duals["cycle"]
        (260.0, -1.0, 1.0)
        """
        self._require_ops()
        cycle = self.cycle_deg if cycle_deg is None else _cycle(cycle_deg)
        lim_spec = self._limiting_spec if limiting is None else limiting
        lim = None if lim_spec is None else self._resolve_op(lim_spec, "limiting")
        n = self._speed(speed_rpm)
        mins = self.min_angles(n)
        self._check_fits(mins, cycle, n)
        lp = _LP(self, mins, cycle, lim)
        res = lp.solve()
        if res.status == 2:
            conflict = lp.irreducible_conflict()
            detail = "; ".join(lp.describe(r) for r in conflict)
            raise InfeasibleError(
                f"cyclogram {self.name!r}: the bounds and constraints cannot all hold; "
                "these conflict "
                f"(dropping any one of them removes the conflict): {detail}",
                conflict,
            )
        if res.status != 0:
            raise SolverError(f"cyclogram {self.name!r}: the LP solver stopped: {res.message}")
        return lp.result(res, lp.earliest_at_optimum(res), n)

    def _check_fits(self, mins: npt.NDArray[np.float64], cycle: float, speed: float | None) -> None:
        """Raise if the minimum angles alone exceed the cycle, naming the chain."""
        src, dst, h = self._arrays()
        V = len(self._events)
        # Closed on itself over one cycle: a cycle of this graph longer than
        # cycle_deg per crossing is exactly a chain that does not fit.
        n, s2, d2, h2, pad = _closed_over_cycle(src, dst, h, V)
        w2 = np.concatenate([mins, np.zeros(pad)])
        try:
            found = _core.max_cycle_ratio(n, s2, d2, w2, h2)
        except CycleError as e:
            raise self._named_cycle(e) from None
        if found is None:
            return
        ratio, arcs = found
        if ratio <= cycle * (1 + 1e-12):
            return
        ops = [self._ops[e] for e in _chain_after(arcs, len(s2) - 1) if e < len(self._ops)]
        at = "" if speed is None else f" at {speed:g} rpm"
        parts = " + ".join(f"{op.title} {mins[self._arc_index[op.arc]]:g}°" for op in ops)
        crossings = round(float(h2[arcs].sum()))
        room = f"{cycle:g}°" if crossings == 1 else f"{crossings} × {cycle:g}°"
        raise InfeasibleError(
            f"cyclogram {self.name!r}: the minimum angles{at} do not fit in the cycle: "
            f"{parts} = {ratio * crossings:g}° > {room}",
            [op.arc for op in ops],
        )

    # ---------------------------------------------------------------- speed
    def max_speed_rpm(self, cycle_deg: float | None = None) -> SpeedLimit:
        """The highest main-shaft speed [rpm] at which the cyclogram fits in its cycle.

        Operations with ``min_duration_s`` take 6·n·s degrees at n rpm, so they grow
        with speed. The network bound is the maximum cycle ratio of the operations
        closed over one cycle, found by Howard's policy iteration with Newton steps
        in speed (Rust). When maximum angles or added constraints exist, an LP over
        the event angles and the speed itself gives the exact limit.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("10.1", "10.2", min_duration_s=0.05, name="weft insertion")
        >>> cg.add_operation("10.2", "g", min_angle_deg=150, name="group 1")
        >>> lim = cg.max_speed_rpm()          # 150° + 6·n·0.05 s = 360°
        >>> round(lim.rpm, 6), lim.cycle
        (700.0, (('10.1', '10.2'), ('10.2', 'g')))
        """
        self._require_ops()
        cycle = self.cycle_deg if cycle_deg is None else _cycle(cycle_deg)
        src, dst, h = self._arrays()
        V, E = len(self._events), len(self._ops)
        angle = np.array([op.min_angle_deg for op in self._ops])
        secs = np.array([op.min_duration_s for op in self._ops])
        # Each operation is two parallel arcs, one per lower bound: its angle at
        # rest and its duration (an angle of max(a, 6·n·s) at n rpm).
        n, s2, d2, h2, pad = _closed_over_cycle(np.r_[src, src], np.r_[dst, dst], np.r_[h, h], V)
        a2 = np.concatenate([angle, np.zeros(E + pad)])
        t2 = np.concatenate([np.zeros(E), secs, np.zeros(pad)])
        try:
            status, rpm, _ratio, arcs = _core.max_speed(n, s2, d2, a2, t2, h2, cycle)
        except CycleError as e:
            raise self._named_cycle(e) from None
        cyc = tuple(self._ops[e % E].arc for e in _chain_after(arcs, len(s2) - 1) if e < 2 * E)
        if status == "infeasible":
            self._check_fits(angle, cycle, 0.0)  # raises with the chain named
            raise InfeasibleError(
                f"cyclogram {self.name!r}: does not fit in {cycle:g}° at any speed", cyc
            )
        network = float(rpm)
        has_extra = self._constraints or any(op.max_angle_deg is not None for op in self._ops)
        if not has_extra:
            return SpeedLimit(network, cyc, cycle, network)
        lp = _LP(self, angle, cycle, None, speed_secs=secs)
        res = lp.solve()
        if res.status == 3:
            return SpeedLimit(math.inf, (), cycle, network)
        if res.status == 2:
            conflict = lp.irreducible_conflict()
            raise InfeasibleError(
                f"cyclogram {self.name!r}: the bounds and constraints conflict even at standstill: "
                + "; ".join(lp.describe(r) for r in conflict),
                conflict,
            )
        if res.status != 0:
            raise SolverError(f"cyclogram {self.name!r}: the LP solver stopped: {res.message}")
        best = float(res.x[-1])
        if best >= network * (1 - 1e-9):
            return SpeedLimit(network, cyc, cycle, network)
        # The rows with a non-zero shadow price are what limits the speed: the
        # operations among them form the limiting chain (ordered by event angle),
        # the rest are the maximum angles, constraints and cycle that bind.
        priced = lp.priced(res)
        p = res.x[:V]
        chain_ops = {int(lp.op[i]) for i in priced if lp.kind[i] == _MIN}
        # Operations held at a bound by a priced constraint belong to the chain too.
        for i in priced:
            if lp.kind[i] == _USER:
                con = next(c for c in self._constraints if c.name == lp.names[i])
                chain_ops.update(self._arc_index[a] for a, _ in con.coeffs)
        chain = sorted((self._ops[e] for e in chain_ops), key=lambda op: p[self._events[op.src]])
        others = tuple(lp.names[i] for i in priced if lp.kind[i] != _MIN)
        return SpeedLimit(best, tuple(op.arc for op in chain), cycle, network, others)

    # ---------------------------------------------------------------- TOML
    @classmethod
    def from_toml(cls, path: str | Path) -> Cyclogram:
        """Read a cyclogram from a TOML file (see ``examples/stb_group1.toml``).

        Layout: a ``[cyclogram]`` table (``name``, ``cycle_deg``, ``limiting``,
        ``speed_rpm``, ``events``), ``[[operation]]`` tables (``from``, ``to``,
        ``min_angle_deg``, ``max_angle_deg``, ``min_duration_s``, ``height``,
        ``name``, ``mechanism``) and ``[[constraint]]`` tables (``name``,
        ``terms = [{from, to, coeff}, …]``, ``sense``, ``rhs``). Every error names
        the file, the table and the key.

        >>> import pathlib, tempfile, cyclomech as cm
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "g.toml"
        >>> _ = path.write_text('[[operation]]\\nfrom = "a"\\nto = "b"\\nmin_angle_deg = 30.0\\n')
        >>> cm.Cyclogram.from_toml(path).schedule().duration
        30.0
        """
        data, source = _toml.load(path)
        return cls.from_dict(data, source=source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], source: str = "<dict>") -> Cyclogram:
        """Build a cyclogram from the parsed TOML layout of :meth:`from_toml`.

        >>> import cyclomech as cm
        >>> data = {"cyclogram": {"cycle_deg": 360.0},
        ...         "operation": [{"from": "a", "to": "b", "min_angle_deg": 30.0}]}
        >>> cm.Cyclogram.from_dict(data).operations[0].min_angle_deg
        30.0
        """
        _toml.check_keys(data, {"cyclogram", "operation", "constraint"}, source, "top level")
        head = data.get("cyclogram", {})
        _toml.check_keys(head, _CG_KEYS, source, "[cyclogram]")
        try:
            lim = head.get("limiting")
            cg = cls(
                head.get("name", Path(source).stem),
                cycle_deg=head.get("cycle_deg", 360.0),
                limiting=tuple(lim) if isinstance(lim, list) else lim,
                speed_rpm=head.get("speed_rpm"),
            )
            events = head.get("events", [])
            if not isinstance(events, list):
                raise InputError(f"events must be an array of event ids; got {events!r}")
            for ev in events:
                cg.add_event(ev)
        except InputError as e:
            raise InputError(f"{source}: [cyclogram]: {e}") from None
        declared = set(cg.events) if "events" in head else None
        ops = data.get("operation", [])
        if not isinstance(ops, list):
            raise InputError(f"{source}: 'operation' must be an array of tables ([[operation]])")
        for i, op in enumerate(ops, 1):
            where = f"{source}: [[operation]] #{i}"
            _toml.check_keys(op, _OP_KEYS, source, f"[[operation]] #{i}")
            for req in ("from", "to"):
                if req not in op:
                    raise InputError(
                        f"{where}: missing key {req!r} (the event the operation goes {req})"
                    )
            try:
                src, dst = _event_id(op["from"], "from"), _event_id(op["to"], "to")
                for key, ev in (("from", src), ("to", dst)):
                    if declared is not None and ev not in declared:
                        raise InputError(
                            f"{key} = {ev!r} is not one of the events listed in [cyclogram] "
                            f"events ({', '.join(repr(e) for e in cg.events)}); a typo, or "
                            "add it to that list"
                        )
                cg.add_operation(
                    src,
                    dst,
                    min_angle_deg=op.get("min_angle_deg", 0.0),
                    max_angle_deg=op.get("max_angle_deg"),
                    name=op.get("name"),
                    mechanism=op.get("mechanism"),
                    min_duration_s=op.get("min_duration_s", 0.0),
                    height=op.get("height", 0),
                )
            except InputError as e:
                raise InputError(f"{where}: {e}") from None
        cons = data.get("constraint", [])
        if not isinstance(cons, list):
            raise InputError(f"{source}: 'constraint' must be an array of tables ([[constraint]])")
        for i, con in enumerate(cons, 1):
            where = f"{source}: [[constraint]] #{i}"
            _toml.check_keys(con, _CON_KEYS, source, f"[[constraint]] #{i}")
            for req in ("terms", "sense", "rhs"):
                if req not in con:
                    raise InputError(f"{where}: missing key {req!r}")
            coeffs: dict[Arc, float] = {}
            if not isinstance(con["terms"], list):
                raise InputError(f"{where}: terms must be a list of {{from, to, coeff}} tables")
            for j, t in enumerate(con["terms"], 1):
                if not isinstance(t, Mapping):
                    raise InputError(
                        f"{where}: terms #{j} must be a table {{from, to, coeff}}; got {t!r}"
                    )
                _toml.check_keys(t, _TERM_KEYS, source, f"[[constraint]] #{i} terms #{j}")
                missing = _TERM_KEYS - set(t)
                if missing:
                    raise InputError(f"{where}: terms #{j} is missing {sorted(missing)}")
                try:
                    arc = (_event_id(t["from"], "from"), _event_id(t["to"], "to"))
                except InputError as e:
                    raise InputError(f"{where}: terms #{j}: {e}") from None
                if arc in coeffs:
                    raise InputError(
                        f"{where}: terms #{j} repeats the arc {arc[0]}→{arc[1]}; "
                        "list each arc once with its total coefficient"
                    )
                coeffs[arc] = t["coeff"]
            try:
                cg.add_constraint(coeffs, con["sense"], con["rhs"], name=con.get("name"))
            except InputError as e:
                raise InputError(f"{where}: {e}") from None
        if cg._limiting_spec is not None:
            try:
                _ = cg.limiting
            except InputError as e:
                raise InputError(f"{source}: [cyclogram]: {e}") from None
        try:
            cg._check_order()
        except CycleError as e:
            raise CycleError(f"{source}: [[operation]]: {e}", e.events) from None
        return cg

    def _check_order(self) -> None:
        """:class:`CycleError` if the operations within one machine cycle (height
        0) form a cycle: no schedule can order their events."""
        if not self._ops:
            return
        src, dst, h = self._arrays()
        inner = h == 0
        try:
            _core.EventGraph(len(self._events), src[inner], dst[inner])
        except CycleError as e:
            raise self._named_cycle(e) from None

    def to_toml(self, path: str | Path | None = None) -> str:
        """The cyclogram as TOML text, written to ``path`` if given.

        Reads back with :meth:`from_toml` to an equal cyclogram.

        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram("press")
        >>> cg.add_operation("a", "b", 30, name="feed")
        >>> print(cg.to_toml())
        [cyclogram]
        name = "press"
        cycle_deg = 360.0
        events = ["a", "b"]
        <BLANKLINE>
        [[operation]]
        from = "a"
        to = "b"
        min_angle_deg = 30.0
        name = "feed"
        <BLANKLINE>
        """
        q = _toml.value
        lines = ["[cyclogram]", f"name = {q(self.name)}", f"cycle_deg = {q(self.cycle_deg)}"]
        if self.limiting is not None:
            lines.append(f"limiting = {q(list(self.limiting))}")
        if self.speed_rpm is not None:
            lines.append(f"speed_rpm = {q(self.speed_rpm)}")
        lines.append(f"events = {q(list(self.events))}")
        for op in self._ops:
            lines += [
                "",
                "[[operation]]",
                f"from = {q(op.src)}",
                f"to = {q(op.dst)}",
                f"min_angle_deg = {q(op.min_angle_deg)}",
            ]
            if op.max_angle_deg is not None:
                lines.append(f"max_angle_deg = {q(op.max_angle_deg)}")
            if op.min_duration_s:
                lines.append(f"min_duration_s = {q(op.min_duration_s)}")
            if op.height:
                lines.append(f"height = {op.height}")
            if op.name is not None:
                lines.append(f"name = {q(op.name)}")
            if op.mechanism is not None:
                lines.append(f"mechanism = {q(op.mechanism)}")
        for con in self._constraints:
            terms = ", ".join(
                f"{{ from = {q(a[0])}, to = {q(a[1])}, coeff = {q(c)} }}" for a, c in con.coeffs
            )
            lines += [
                "",
                "[[constraint]]",
                f"name = {q(con.name)}",
                f"terms = [{terms}]",
                f"sense = {q(con.sense)}",
                f"rhs = {q(con.rhs)}",
            ]
        text = "\n".join(lines) + "\n"
        if path is not None:
            Path(path).write_text(text, encoding="utf-8")
        return text

    def __repr__(self) -> str:
        return (
            f"Cyclogram({self.name!r}, events={len(self._events)}, operations={len(self._ops)}, "
            f"constraints={len(self._constraints)}, cycle_deg={self.cycle_deg:g})"
        )


# Kinds of named LP rows.
_MIN, _MAX, _USER, _CYCLE = 0, 1, 2, 3


class _LP:
    """The cyclogram LP over event angles p (and the finish F, and the speed n).

    Variables: p_0 … p_{V-1} ≥ 0, F (the span's end; the start is 0), and with
    ``speed_secs`` the speed n ≥ 0 [rpm]. Every bound and constraint is a named row
    of one sparse matrix, with its kind, its operation and the sign that turned it
    into the solver's form, so a subset is a row mask (for the deletion filter) and
    every dual maps back to its name. The span rows p_v − F ≤ 0 are structure, not
    bounds: always present, never reported.
    """

    def __init__(
        self,
        cg: Cyclogram,
        mins: npt.NDArray[np.float64],
        cycle: float,
        limiting: Arc | None,
        speed_secs: npt.NDArray[np.float64] | None = None,
    ) -> None:
        self.cg, self.cycle, self.limiting, self.mins = cg, cycle, limiting, mins
        V = len(cg._events)
        self.V = self.F = V
        self.n_var = V + 1 + (speed_secs is not None)
        xi, yi, h = cg._arrays()
        self.xi, self.yi, self.ch = xi, yi, cycle * h
        E = len(xi)
        label = cg._bound_labels()
        ops = np.arange(E)
        max_ops = np.array([e for e, op in enumerate(cg._ops) if op.max_angle_deg is not None], int)
        maxs = np.array([cg._ops[e].max_angle_deg for e in max_ops], dtype=np.float64)
        dur_ops = np.flatnonzero(speed_secs > 0) if speed_secs is not None else np.zeros(0, int)
        rows: list[npt.NDArray[np.int64]] = []
        cols: list[npt.NDArray[np.int64]] = []
        vals: list[npt.NDArray[np.float64]] = []
        n_rows = 0

        def block(c: list[npt.NDArray[np.int64]], v: list[npt.NDArray[np.float64] | float]) -> None:
            # One row per entry of c[0]; the k-th column list gives each row's k-th entry.
            nonlocal n_rows
            k = len(c[0])
            r = n_rows + np.arange(k)
            for ck, vk in zip(c, v, strict=True):
                rows.append(r)
                cols.append(np.asarray(ck, dtype=np.int64))
                vals.append(np.broadcast_to(np.asarray(vk, dtype=np.float64), (k,)))
            n_rows += k

        # angle = p_y − p_x + C·h ≥ min   ⇔   p_x − p_y ≤ C·h − min
        block([xi, yi], [1.0, -1.0])
        rhs = [self.ch - mins]
        kind = [np.full(E, _MIN)]
        opi = [ops]
        sign = [np.full(E, -1.0)]
        names = [f"min[{lab}]" for lab in label]
        if len(dur_ops):
            assert speed_secs is not None
            n_col = np.full(len(dur_ops), self.n_var - 1)
            block(
                [xi[dur_ops], yi[dur_ops], n_col],
                [1.0, -1.0, DEG_PER_S_PER_RPM * speed_secs[dur_ops]],
            )
            rhs.append(self.ch[dur_ops])
            kind.append(np.full(len(dur_ops), _MIN))
            opi.append(dur_ops)
            sign.append(np.full(len(dur_ops), -1.0))
            names += [f"duration[{label[e]}]" for e in dur_ops]
        # angle ≤ max   ⇔   p_y − p_x ≤ max − C·h
        if len(max_ops):
            block([yi[max_ops], xi[max_ops]], [1.0, -1.0])
            rhs.append(maxs - self.ch[max_ops])
            kind.append(np.full(len(max_ops), _MAX))
            opi.append(max_ops)
            sign.append(np.ones(len(max_ops)))
            names += [f"max[{label[e]}]" for e in max_ops]
        eq = [np.zeros(n_rows, bool)]
        idx = cg._events
        for con in cg._constraints:
            acc: dict[int, float] = {}
            shift = 0.0
            for arc, coeff in con.coeffs:
                op = cg._ops[cg._arc_index[arc]]
                acc[idx[op.dst]] = acc.get(idx[op.dst], 0.0) + coeff
                acc[idx[op.src]] = acc.get(idx[op.src], 0.0) - coeff
                shift += coeff * cycle * op.height
            sg = -1.0 if con.sense == ">=" else 1.0  # ">=" is negated into "<="
            rows.append(np.full(len(acc), n_rows))
            cols.append(np.fromiter(acc, np.int64, len(acc)))
            vals.append(sg * np.fromiter(acc.values(), np.float64, len(acc)))
            n_rows += 1
            rhs.append(np.array([sg * (con.rhs - shift)]))
            kind.append(np.array([_USER]))
            opi.append(np.array([-1]))
            sign.append(np.array([sg]))
            eq.append(np.array([con.sense == "=="]))
            names.append(con.name)
        # The span fits in the cycle: F ≤ cycle.
        rows.append(np.array([n_rows]))
        cols.append(np.array([self.F]))
        vals.append(np.array([1.0]))
        n_rows += 1
        rhs.append(np.array([cycle]))
        kind.append(np.array([_CYCLE]))
        opi.append(np.array([-1]))
        sign.append(np.array([1.0]))
        eq.append(np.array([False]))
        names.append("cycle")

        self.A = sparse.csr_array(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(n_rows, self.n_var),
        )
        self.b = np.concatenate(rhs).astype(np.float64)
        self.kind = np.concatenate(kind)
        self.op = np.concatenate(opi).astype(np.int64)
        self.sign = np.concatenate(sign)
        self.eq = np.concatenate(eq)
        self.names = names
        self.n_rows = n_rows
        self.max_of = dict(zip(max_ops.tolist(), maxs.tolist(), strict=True))
        self.speed_secs = speed_secs
        ar = np.arange(V)
        self._span = sparse.csr_array(
            (np.r_[np.ones(V), -np.ones(V)], (np.r_[ar, ar], np.r_[ar, np.full(V, self.F)])),
            shape=(V, self.n_var),
        )
        c = np.zeros(self.n_var)
        if speed_secs is not None:
            c[-1] = -1.0  # maximise n
            self.sigma = -1.0
        elif limiting is None:
            c[self.F] = 1.0  # minimise the span
            self.sigma = 1.0
        else:
            op = cg._ops[cg._arc_index[limiting]]
            c[idx[op.src]] += 1.0  # maximise p_y − p_x  ⇔  minimise p_x − p_y
            c[idx[op.dst]] -= 1.0
            self.sigma = -1.0
        self.c = c

    def solve(
        self,
        keep: npt.NDArray[np.bool_] | None = None,
        c: npt.NDArray[np.float64] | None = None,
        extra: tuple[Any, float] | None = None,
    ) -> Any:
        """Solve with the named rows in ``keep`` (default all), objective ``c``
        (default the LP's own) and an optional extra row ``(row, rhs)``.

        On success the result carries ``dual_all`` and ``resid_all``: the marginal
        and the residual of every named row (NaN for rows left out).
        """
        sel = np.arange(self.n_rows) if keep is None else np.flatnonzero(keep)
        ub, eq = sel[~self.eq[sel]], sel[self.eq[sel]]
        blocks = [self.A[ub], self._span]
        b_ub = [self.b[ub], np.zeros(self.V)]
        if extra is not None:
            blocks.append(extra[0])
            b_ub.append(np.array([extra[1]]))
        res = linprog(
            self.c if c is None else c,
            A_ub=sparse.vstack(blocks).tocsr(),
            b_ub=np.concatenate(b_ub),
            A_eq=self.A[eq] if len(eq) else None,
            b_eq=self.b[eq] if len(eq) else None,
            bounds=[(0, None)] * self.n_var,
            method="highs",
        )
        if res.status == 0:
            dual = np.full(self.n_rows, np.nan)
            resid = np.full(self.n_rows, np.nan)
            dual[ub] = res.ineqlin.marginals[: len(ub)]
            resid[ub] = res.ineqlin.residual[: len(ub)]
            if len(eq):
                dual[eq] = res.eqlin.marginals
                resid[eq] = 0.0
            res.dual_all, res.resid_all = dual, resid
        return res

    def tight(self, res: Any) -> npt.NDArray[np.int64]:
        """Named rows that hold with equality."""
        scale = 1.0 + float(np.abs(res.x).max(initial=0.0))
        return np.flatnonzero(np.abs(res.resid_all) <= 1e-9 * scale)

    def priced(self, res: Any) -> npt.NDArray[np.int64]:
        """Named rows with a non-zero shadow price."""
        return np.flatnonzero(np.abs(np.nan_to_num(res.dual_all)) > 1e-9)

    def irreducible_conflict(self) -> list[str]:
        """Rows that are infeasible together and feasible without any one of them.

        First an elastic LP (every named row may be violated by a slack ≥ 0; minimise
        the total slack): the rows with a non-zero dual there form an infeasible
        subsystem (a Farkas certificate), usually a handful of rows. The deletion
        filter then drops each of those in turn and keeps it only if the rest turn
        feasible: one small LP per candidate instead of one per row.
        """
        keep = self._elastic_support()
        if keep is None or self.solve(keep).status != 2:
            keep = np.ones(self.n_rows, bool)  # fall back to every row
        for i in np.flatnonzero(keep):
            keep[i] = False
            if self.solve(keep).status != 2:
                keep[i] = True  # needed for the conflict
        return [self.names[i] for i in np.flatnonzero(keep)]

    def _elastic_support(self) -> npt.NDArray[np.bool_] | None:
        """Rows with a non-zero dual in the elastic LP, or None if it fails."""
        R, nv = self.n_rows, self.n_var
        # Equalities become two inequalities sharing one slack.
        A = sparse.vstack([self.A, -self.A[self.eq]]).tocsr()
        b = np.r_[self.b, -self.b[self.eq]]
        owner = np.r_[np.arange(R), np.flatnonzero(self.eq)]
        slack = sparse.csr_array(
            (-np.ones(len(owner)), (np.arange(len(owner)), owner)), shape=(len(owner), R)
        )
        A_ub = sparse.vstack(
            [sparse.hstack([A, slack]), sparse.hstack([self._span, sparse.csr_array((self.V, R))])]
        ).tocsr()
        res = linprog(
            np.r_[np.zeros(nv), np.ones(R)],
            A_ub=A_ub,
            b_ub=np.r_[b, np.zeros(self.V)],
            bounds=[(0, None)] * (nv + R),
            method="highs",
        )
        if res.status != 0:
            return None
        dual = np.zeros(R)
        np.add.at(dual, owner, np.abs(res.ineqlin.marginals[: len(owner)]))
        support = dual > 1e-9
        return support if support.any() else None

    def describe(self, name: str) -> str:
        """``name: the bound as text`` (row names are unique)."""
        i = self.names.index(name)
        kind = self.kind[i]
        if kind in (_MIN, _MAX):
            op = self.cg._ops[self.op[i]]
            t = f"t({op.src},{op.dst})"
            if kind == _MAX:
                return f"{name}: {t} <= {self.max_of[int(self.op[i])]:g}°"
            if name.startswith("duration["):
                assert self.speed_secs is not None
                return f"{name}: {t} >= 6·n·{self.speed_secs[self.op[i]]:g} s"
            return f"{name}: {t} >= {self.mins[self.op[i]]:g}°"
        if kind == _USER:
            con = next(c for c in self.cg._constraints if c.name == name)
            return f"{name}: {con.describe()}"
        return f"{name}: span p(N) - p(1) <= {self.cycle:g}°"

    def earliest_at_optimum(self, res: Any) -> npt.NDArray[np.float64]:
        """Event angles of the optimum that puts every event as early as it can be.

        The LP optimum is degenerate: operations off the critical chains may take
        any angle that fits. A second LP keeps the objective at its optimum and
        minimises Σ p(v), so each such operation stays at its minimum where it can,
        as in the earliest schedule. Pinned at the optimum itself: HiGHS's own
        feasibility tolerance absorbs round-off, and if it did not, the first LP's
        answer stands. Shadow prices still come from the first LP.
        """
        pin = sparse.csr_array(self.c.reshape(1, -1))
        c = np.r_[np.ones(self.V), np.zeros(self.n_var - self.V)]
        tidy = self.solve(c=c, extra=(pin, float(res.fun)))
        return tidy.x if tidy.status == 0 else res.x

    def _critical_ops(self, res: Any) -> npt.NDArray[np.bool_]:
        """Operations on the chains that set the objective.

        Every operation whose minimum, or a constraint on it, has a shadow price; and,
        because a degenerate LP prices only one of several tied chains, every
        operation at its minimum on a chain of such operations between two events of
        the priced ones (lengthening it would move a priced event just the same).
        """
        E, V = len(self.xi), self.V
        priced = np.zeros(E, bool)
        rows = self.priced(res)
        priced[self.op[rows[self.kind[rows] == _MIN]]] = True
        # Operations held by a priced constraint (the seed's rebound bound) too.
        for i in rows[self.kind[rows] == _USER]:
            con = next(c for c in self.cg._constraints if c.name == self.names[i])
            priced[[self.cg._arc_index[a] for a, _ in con.coeffs]] = True
        if not priced.any():
            return priced
        # The first E rows are the minimum-angle rows, in operation order.
        tight = np.abs(res.resid_all[:E]) <= 1e-9 * (1.0 + float(np.abs(res.x).max()))
        ends = np.unique(np.r_[self.xi[priced], self.yi[priced]])
        reach = []
        for a, b in ((self.xi, self.yi), (self.yi, self.xi)):  # forwards, then backwards
            # Arcs at their minimum, plus a virtual root V joined to every priced event.
            g = sparse.csr_array(
                (
                    np.ones(int(tight.sum()) + len(ends)),
                    (np.r_[a[tight], np.full(len(ends), V)], np.r_[b[tight], ends]),
                ),
                shape=(V + 1, V + 1),
            )
            seen = np.zeros(V + 1, bool)
            seen[breadth_first_order(g, V, directed=True, return_predecessors=False)] = True
            reach.append(seen)
        return priced | (tight & reach[0][self.xi] & reach[1][self.yi])

    def result(self, res: Any, x: npt.NDArray[np.float64], speed: float | None) -> Optimum:
        """The :class:`Optimum` with duals from ``res`` and event angles from ``x``."""
        cg = self.cg
        p = x[: self.V] - x[: self.V].min()
        arcs = list(cg._arc_index)  # in operation order
        ang = p[self.yi] - p[self.xi] + self.ch
        duals = self.sigma * self.sign * res.dual_all + 0.0  # + 0.0: no -0.0 in reports
        critical = self._critical_ops(res)
        # The objective is the first LP's optimum, not re-derived from the tidied angles.
        goal: Literal["min_duration", "max_limiting"]
        if self.limiting is None:
            objective, goal = float(res.fun), "min_duration"
        else:
            height = cg.operation(self.limiting).height
            objective, goal = -float(res.fun) + self.cycle * height, "max_limiting"
        return Optimum(
            operations=cg.operations,
            events=cg.events,
            times=dict(zip(cg.events, p.tolist(), strict=True)),
            angles=dict(zip(arcs, ang.tolist(), strict=True)),
            objective=objective,
            goal=goal,
            limiting=self.limiting,
            duration=float(p.max() - p.min()),
            cycle_deg=self.cycle,
            speed_rpm=speed,
            duals=dict(zip(self.names, duals.tolist(), strict=True)),
            slack=dict(zip(self.names, res.resid_all.tolist(), strict=True)),
            binding=tuple(self.names[i] for i in self.tight(res)),
            stretch=dict(zip(arcs, (ang - self.mins).tolist(), strict=True)),
            critical=tuple(arcs[e] for e in np.flatnonzero(critical)),
            name=cg.name,
        )


def _closed_over_cycle(
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    heights: npt.NDArray[np.float64],
    n_events: int,
) -> tuple[int, npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.float64], int]:
    """The arcs closed over one machine cycle, for the cycle-ratio kernels.

    A virtual start S before and finish F after every event, and F → S crossing
    into the next cycle. Returns (number of events, src, dst, heights, number of
    virtual arcs appended, all of weight 0); the closure F → S is the last arc.
    """
    S, F = n_events, n_events + 1
    ev = np.arange(n_events, dtype=np.int64)
    s2 = np.concatenate([src, np.full(n_events, S), ev, [F]])
    d2 = np.concatenate([dst, ev, np.full(n_events, F), [S]])
    h2 = np.concatenate([heights, np.zeros(2 * n_events), [1.0]])
    return n_events + 2, s2, d2, h2, 2 * n_events + 1


def _chain_after(arcs: npt.NDArray[np.int64], closure: int) -> list[int]:
    """Rotate a cycle's arcs to start right after the closure arc F → S, so that
    the operations read as a chain from the first event to the last."""
    a = [int(e) for e in arcs]
    if closure in a:
        k = a.index(closure)
        a = a[k + 1 :] + a[: k + 1]
    return a
