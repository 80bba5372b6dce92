"""The cyclogram's constraints and result types (:class:`Constraint`,
:class:`Schedule`, :class:`Optimum`, :class:`SpeedLimit`); part of
:mod:`cyclomech.cyclogram`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from .._arrays import real
from .._errors import InputError
from .._notebook import figure_of, html_card, table_frame
from ._angles import Arc

if TYPE_CHECKING:
    from ._operation import Operation

#: How a :class:`Constraint`'s sum relates to its right-hand side.
Sense = Literal["<=", ">=", "=="]


@dataclass(frozen=True)
class Constraint:
    """A linear constraint Σ coeffs[arc]·t(arc) (sense) rhs on phase angles [deg].

    Each parameter is kept as the attribute of the same name. Built by
    :meth:`Cyclogram.add_constraint` (or, e.g.,
    :meth:`cyclomech.impact.StopImpact.constraint`), which checks it.

    Parameters
    ----------
    coeffs : tuple of ((str, str), float)
        The terms: each operation's arc ``(x, y)`` and its coefficient (the
        constraint's unit per degree).
    sense : {"<=", ">=", "=="}
        How the sum relates to ``rhs``.
    rhs : float
        The right-hand side, in the constraint's unit.
    name : str
        The constraint's name in results (``duals``, ``slack``, ``binding``).

    See Also
    --------
    Cyclogram.add_constraint : Adds one to a cyclogram.

    Examples
    --------
    >>> from cyclomech import Constraint
    >>> c = Constraint(((("3", "7"), -0.003),), "<=", -0.108, "rebound")
    >>> c.coeffs, c.sense, c.rhs
    (((('3', '7'), -0.003),), '<=', -0.108)
    """

    coeffs: tuple[tuple[Arc, float], ...]
    sense: Sense
    rhs: float
    name: str

    def __post_init__(self) -> None:
        # A string, a bool or None is not a number; NaN is a bound no angle meets (a
        # mechanism's at a speed it cannot reach), refused by add_constraint and
        # turned into an InfeasibleError by Machine.cyclogram_at.
        try:
            rhs = real(self.rhs)
        except (TypeError, ValueError):
            rhs = math.inf
        if math.isinf(rhs):
            raise InputError(f"rhs = {self.rhs!r} must be a number [deg] (NaN: no angle meets it)")
        object.__setattr__(self, "rhs", rhs)

    def describe(self) -> str:
        """The constraint as text (angles in degrees).

        Returns
        -------
        str
            ``"c·t(x,y) + … (sense) rhs"``, numbers in the shortest form (``:g``).

        Examples
        --------
        >>> from cyclomech import Constraint
        >>> Constraint(((("3", "7"), -0.003),), "<=", -0.108, "rebound").describe()
        '-0.003·t(3,7) <= -0.108'
        """
        terms = " + ".join(f"{c:g}·t({a[0]},{a[1]})" for a, c in self.coeffs)
        return f"{terms} {self.sense} {self.rhs:g}"


@dataclass(frozen=True)
class Schedule:
    """Every operation at its minimum angle: the earliest schedule (angles in degrees).

    Operations crossing into the next cycle (height h > 0) do not order events
    within the cycle; their ``slack`` is p(y) + cycle_deg·h − p(x) − angle,
    negative when the schedule violates them; ``violated`` lists those. Built by
    :meth:`Cyclogram.schedule`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    operations : tuple of Operation
        The cyclogram's operations, in the order added.
    events : tuple of str
        The event ids, in the order added.
    earliest : dict of str to float
        Each event's earliest occurrence angle p [deg].
    latest : dict of str to float
        Each event's latest occurrence angle [deg] that keeps the schedule's end
        (or the horizon of :meth:`Cyclogram.schedule`).
    angles : dict of (str, str) to float
        Each operation's angle in the schedule, its minimum [deg].
    slack : dict of (str, str) to float
        Each operation's total slack [deg]: how much it can grow without moving the
        end of the schedule.
    free_slack : dict of (str, str) to float
        How much each operation can grow without moving any event [deg].
    critical : tuple of (str, str)
        The operations with zero total slack.
    duration : float
        The span from the first to the last event [deg].
    cycle_deg : float
        The machine cycle [deg].
    speed_rpm : float or None
        The main-shaft speed [rpm] at which time-bound operations were converted,
        or None.
    violated : tuple of (str, str), default ()
        The operations into a later cycle that the schedule violates (negative
        slack).
    name : str, default "cyclogram"
        The cyclogram's title.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("1", "2", 40)
    >>> cg.add_operation("1", "3", 20)
    >>> s = cg.schedule()
    >>> s.earliest, s.latest["3"], s.slack[("1", "3")], s.critical
    ({'1': 0.0, '2': 40.0, '3': 20.0}, 40.0, 20.0, (('1', '2'),))
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
        """Occurrence angle of each event [deg] (the earliest times).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", 30)
        >>> cg.schedule().times
        {'a': 0.0, 'b': 30.0}
        """
        return self.earliest


@dataclass(frozen=True)
class Optimum:
    """Result of :meth:`Cyclogram.optimize` (angles in degrees).

    Bounds are named ``min[op]`` and ``max[op]`` (``op`` the operation's title); the
    cycle bound ``cycle``; constraints by their names. Built by
    :meth:`Cyclogram.optimize`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    operations : tuple of Operation
        The cyclogram's operations, in the order added.
    events : tuple of str
        The event ids, in the order added.
    times : dict of str to float
        Each event's occurrence angle p at the optimum [deg].
    angles : dict of (str, str) to float
        Each operation's phase angle t(x, y) at the optimum [deg].
    objective : float
        The optimum [deg]: the duration p(N) − p(1), or the limiting operation's
        angle.
    goal : {"min_duration", "max_limiting"}
        What was optimised: the shortest duration, or the limiting operation's
        largest angle.
    limiting : (str, str) or None
        The limiting operation's arc when ``goal`` is ``"max_limiting"``.
    duration : float
        The span from the first to the last event [deg].
    cycle_deg : float
        The machine cycle [deg].
    speed_rpm : float or None
        The main-shaft speed [rpm] at which time-bound operations were converted,
        or None.
    duals : dict of str to float
        The shadow price of each bound and constraint: the change of ``objective``
        per unit increase of that bound's value (a minimum angle, a maximum angle, a
        constraint's right-hand side, the cycle angle). The cycle's (``"cycle"``)
        counts every place the cycle enters: the span F ≤ cycle, each operation with
        a height (its angle is p_y − p_x + cycle·height) and the limiting
        operation's own angle.
    slack : dict of str to float
        How far each bound and constraint is from binding in the schedule reported
        (``times``); ``"cycle"``'s is the span's (cycle − F).
    binding : tuple of str
        The bounds and constraints with zero slack there.
    stretch : dict of (str, str) to float
        How much each operation got beyond its minimum angle [deg].
    critical : tuple of (str, str)
        The operations on the chains that set the objective: those whose minimum,
        or a constraint on them, has a non-zero shadow price, and every operation
        at its minimum on a chain tied with them.
    name : str, default "cyclogram"
        The cyclogram's title.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", 30)
    >>> cg.add_operation("b", "c", 50)
    >>> opt = cg.optimize()                  # no limiting operation: the shortest span
    >>> opt.goal, opt.objective, opt.times, opt.slack["cycle"]
    ('min_duration', 80.0, {'a': 0.0, 'b': 30.0, 'c': 80.0}, 280.0)
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

    def table(self) -> tuple[list[str], list[list[object]]]:
        """Each operation at the optimum, in the order added: (header, rows).

        Columns: ``operation`` (its title), ``mechanism``, ``from``, ``to``,
        ``start_deg`` (its start event's angle), ``angle_deg``,
        ``beyond_minimum_deg`` (``stretch``), ``critical``.

        Returns
        -------
        header : list of str
            The columns' names.
        rows : list of list
            One row per operation.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", 30)
        >>> header, rows = cg.optimize().table()
        >>> header[4:6], rows[0][4:6]
        (['start_deg', 'angle_deg'], [0.0, 30.0])
        """
        header = ["operation", "mechanism", "from", "to", "start_deg", "angle_deg"]
        header += ["beyond_minimum_deg", "critical"]
        crit = set(self.critical)
        rows: list[list[object]] = [
            [
                op.title,
                op.mechanism or "",
                op.src,
                op.dst,
                self.times[op.src],
                self.angles[op.arc],
                self.stretch[op.arc],
                op.arc in crit,
            ]
            for op in self.operations
        ]
        return header, rows

    def to_pandas(self) -> Any:
        """:meth:`table` as a pandas DataFrame indexed by the operation's title
        (pandas needed).

        Returns
        -------
        pandas.DataFrame
            One row per operation.

        Raises
        ------
        ImportError
            If pandas is not installed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", 30)
        >>> cg.add_operation("b", "c", 50)
        >>> cg.optimize().to_pandas()["start_deg"].tolist()
        [0.0, 30.0]
        """
        return table_frame(*self.table(), index="operation")

    def _repr_html_(self) -> str:
        """The notebook's view: what was optimised and its value, the operations'
        table and the Gantt chart of the optimum."""
        rows: list[tuple[str, object]] = [
            (
                "goal",
                "the limiting operation's largest angle"
                if self.goal == "max_limiting"
                else "the shortest span",
            ),
            ("optimum [deg]", self.objective),
            ("span [deg]", self.duration),
            ("cycle [deg]", self.cycle_deg),
        ]
        if self.speed_rpm is not None:
            rows.append(("at [rpm]", self.speed_rpm))
        rows.append(("binding", ", ".join(self.binding) or "none"))
        return html_card(
            self.name,
            rows,
            figure_of(self),
            tables=[("Operations", *self.table())],
        )


@dataclass(frozen=True)
class SpeedLimit:
    """The highest main-shaft speed [rpm] at which a cyclogram, or a whole machine, works.

    One type for both (:meth:`Cyclogram.max_speed_rpm`,
    :meth:`~cyclomech.machine.Machine.speed_limit`). For a cyclogram, when maximum angles or
    added constraints lower the network bound, ``rpm < network_rpm``. For a
    machine, ``rpm`` is the least of ``cyclogram_rpm`` and each mechanism's own
    limit in ``mechanisms_rpm``. Each parameter is kept as the attribute of the
    same name.

    Parameters
    ----------
    rpm : float
        The speed limit [rpm] (``inf`` when no time-bound operation limits it).
    cycle : tuple of (str, str), default ()
        For a cyclogram: the operations of the critical chain, whose angles fill
        ``cycle_deg`` at that speed.
    cycle_deg : float, default 360.0
        The machine cycle [deg].
    network_rpm : float, default inf
        For a cyclogram: the bound from the operations' minimum angles and durations
        alone (Howard's maximum cycle ratio) [rpm].
    binding : tuple of str, default ()
        The bounds and constraints that price the limit (a tuple of names
        everywhere; a list in ``results.json``).
    reason : str, default ""
        Why, in words.
    by : str, default "cyclogram"
        What sets the limit: ``"cyclogram"`` or a mechanism's name.
    cyclogram_rpm : float, optional
        For a machine: the speed up to which its cyclogram, with the mechanisms'
        bounds, still fits [rpm]. Default (NaN): ``rpm``, a cyclogram's own limit.
    mechanisms_rpm : dict of str to float, optional
        For a machine: each mechanism's own limit [rpm]. Default empty.
    mechanisms_reason : dict of str to str, optional
        For a machine: why each mechanism's limit, in words. Default empty.

    Examples
    --------
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
