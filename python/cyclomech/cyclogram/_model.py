"""The cyclogram: `_model` part of :mod:`cyclomech.cyclogram` (its door)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from .. import _core, _toml
from .._errors import CycleError, InfeasibleError, InputError, SolverError
from .._keydoc import KeyTable
from . import _file
from ._angles import Arc, minimum_angles
from ._feasible import FeasibleSet
from ._keys import KEY_DOCS
from ._layout import Layout
from ._lp import LP
from ._operation import MAX_ANGLE_DEG, Operation, _cycle, _event_id, _finite
from ._speed import check_fits, max_speed
from ._types import Constraint, Optimum, Schedule, SpeedLimit

__all__ = [
    "Arc",
    "Constraint",
    "Cyclogram",
    "Operation",
    "Optimum",
    "Schedule",
    "SpeedLimit",
    "minimum_angles",
]


class Cyclogram:
    """The network cyclogram of a machine or of one group of its mechanisms.

    Parameters
    ----------
    name : str, default "cyclogram"
        A title for reports.
    cycle_deg : float, default 360.0
        The machine cycle [deg], 360 for one main-shaft turn.
    limiting : (str, str) or str, optional
        The limiting operation (an arc or an operation name), whose angle
        :meth:`optimize` maximises by default.
    speed_rpm : float, optional
        Main-shaft speed [rpm] at which operations with a minimum duration in
        seconds are converted to degrees, unless a method is given another.

    Raises
    ------
    InputError
        If ``cycle_deg`` is not a positive finite angle, ``speed_rpm`` is negative
        or not finite, or ``limiting`` is neither a name nor an arc of two event
        names.

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

    # Its tables' keys, for the machine-file format reference (cyclomech._keydocs).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS

    def __init__(
        self,
        name: str = "cyclogram",
        *,
        cycle_deg: float = 360.0,
        limiting: Arc | str | None = None,
        speed_rpm: float | None = None,
    ) -> None:
        if not isinstance(name, str):
            raise InputError(f"name must be the cyclogram's name (a string); got {name!r}")
        self.name = name
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
        # The solvers' view (numbered events, per-operation arrays), built once per
        # change, so no method loops over operations in Python.
        self._lay: Layout | None = None

    @property
    def speed_rpm(self) -> float | None:
        """Main-shaft speed [rpm] for time-bound operations, or None.

        Settable; a negative or non-finite speed raises :class:`~cyclomech.InputError`.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram(speed_rpm=300)
        >>> cg.speed_rpm = 450
        >>> cg.speed_rpm
        450.0
        """
        return self._speed_rpm

    @speed_rpm.setter
    def speed_rpm(self, value: float | None) -> None:
        self._speed_rpm = None if value is None else _finite(value, "speed_rpm", lower=0.0)

    # ----------------------------------------------------------------- building
    def add_event(self, event: str) -> str:
        """Add an event (idempotent) and return its id.

        Events of operations are added by :meth:`add_operation` anyway; this fixes
        their order for reports.

        Parameters
        ----------
        event : str
            The event id (an integer is taken as its text).

        Returns
        -------
        str
            The event's id.

        Raises
        ------
        InputError
            If ``event`` is not a non-empty string (or an integer).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_event("10.1")
        '10.1'
        >>> cg.events
        ('10.1',)
        """
        e = _event_id(event, "event")
        if e not in self._events:
            self._events[e] = len(self._events)
            self._lay = None
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

        Its events are added too, if new.

        Parameters
        ----------
        x : str
            The event at which the operation starts.
        y : str
            The event at which it ends.
        min_angle_deg : float, default 0.0
            The lower bound of its phase angle [deg], ≥ 0.
        max_angle_deg : float, optional
            The upper bound of its phase angle [deg]; None (default) for none.
        name : str, optional
            A name for reports, :meth:`operation` and ``limiting``.
        mechanism : str, optional
            The mechanism that performs it.
        min_duration_s : float, default 0.0
            Makes it time-bound [s]: 6·n·s degrees at n rpm.
        height : int, default 0
            1 for an operation that ends in the next machine cycle.

        Raises
        ------
        InputError
            If the operation is malformed (see :class:`Operation`) or an operation
            x → y already exists.

        See Also
        --------
        Operation : The operation added, and the checks of its fields.

        Examples
        --------
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
        self._lay = None

    def add_constraint(
        self,
        coeffs: Mapping[tuple[str, str], float] | Constraint,
        sense: str | None = None,
        rhs: float | None = None,
        name: str | None = None,
    ) -> None:
        """Add Σ coeffs[(x, y)]·t(x, y) (sense) rhs, with sense ``"<="``, ``">="`` or ``"=="``.

        Angles in degrees. The operations named in ``coeffs`` must exist.

        Parameters
        ----------
        coeffs : mapping of (str, str) to float, or Constraint
            Each operation's arc ``(x, y)`` and its coefficient; or a whole
            :class:`Constraint` (e.g. from
            :meth:`cyclomech.impact.StopImpact.constraint`), passed alone.
        sense : {"<=", ">=", "=="}, optional
            How the sum relates to ``rhs``; needed unless ``coeffs`` is a
            :class:`Constraint`.
        rhs : float, optional
            The right-hand side; needed unless ``coeffs`` is a :class:`Constraint`.
        name : str, optional
            The constraint's name in results; default ``"constraint k"`` (k its
            number), or the :class:`Constraint`'s own.

        Raises
        ------
        InputError
            If a part is missing, or given beside a :class:`Constraint`; the name is
            taken or reserved (``cycle``, ``min[…]``, ``max[…]``, ``duration[…]``);
            the sense is unknown; a key is not an arc of an existing operation; or a
            number is not finite.

        Examples
        --------
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
            con = coeffs
            coeffs, sense, rhs = dict(con.coeffs), con.sense, con.rhs
            name = con.name if name is None else name
        if sense is None or rhs is None:
            raise InputError("add_constraint needs coeffs, sense and rhs (or one Constraint)")
        if name is not None and not isinstance(name, str):
            raise InputError(f"a constraint's name must be a string; got {name!r}")
        name = name if name is not None else f"constraint {len(self._constraints) + 1}"
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
        self._lay = None

    # ------------------------------------------------------------------ access
    @property
    def events(self) -> tuple[str, ...]:
        """Event ids in the order they were added.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("b", "c", 30)
        >>> cg.add_operation("a", "b", 20)
        >>> cg.events
        ('b', 'c', 'a')
        """
        return tuple(self._events)

    @property
    def operations(self) -> tuple[Operation, ...]:
        """The operations in the order they were added.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", 30, name="feed")
        >>> cg.add_operation("b", "c", 40)
        >>> [op.title for op in cg.operations]
        ['feed', 'b→c']
        """
        return tuple(self._ops)

    @property
    def constraints(self) -> tuple[Constraint, ...]:
        """The added linear constraints, in the order added.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", 30)
        >>> cg.add_constraint({("a", "b"): 1.0}, "<=", 90.0, name="short feed")
        >>> [c.name for c in cg.constraints]
        ['short feed']
        """
        return tuple(self._constraints)

    @property
    def limiting(self) -> Arc | None:
        """The limiting operation's arc, if one was set (None otherwise).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram(limiting="feed")
        >>> cg.add_operation("a", "b", 30, name="feed")
        >>> cg.limiting
        ('a', 'b')
        """
        return (
            None
            if self._limiting_spec is None
            else self._resolve_op(self._limiting_spec, "limiting")
        )

    def operation(self, key: Arc | str) -> Operation:
        """The operation with this arc ``(x, y)`` or this name.

        Parameters
        ----------
        key : (str, str) or str
            The operation's arc or its name.

        Returns
        -------
        Operation
            The operation.

        Raises
        ------
        InputError
            If no operation has that arc or name, or several share the name.

        Examples
        --------
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

    def _layout(self) -> Layout:
        """The cyclogram as the solvers read it, rebuilt after a change (a new
        name too: their messages name the cyclogram)."""
        if self._lay is None or self._lay.name != self.name:
            self._lay = Layout(self.name, self.events, self._ops, self._constraints)
        return self._lay

    def feasible_rows(
        self, speed_rpm: float | None = None
    ) -> tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
    ]:
        """The rows of :meth:`optimize`'s LP at ``speed_rpm``, dense.

        Over x = (event angles p [deg] in the order of :attr:`events`, the span F),
        with x ≥ 0: every operation's minimum and maximum angle, the added
        constraints, p_v ≤ F and F ≤ the cycle. For a second objective within the
        feasible set (the main shaft's flattening).

        Parameters
        ----------
        speed_rpm : float, optional
            The main-shaft speed [rpm] for time-bound operations; default the
            cyclogram's.

        Returns
        -------
        a_ub : ndarray of float, shape (R, V + 1)
            The inequality rows A_ub (A_ub·x ≤ b_ub); V events.
        b_ub : ndarray of float, shape (R,)
            Their right-hand sides [deg].
        a_eq : ndarray of float, shape (Q, V + 1)
            The equality rows A_eq (A_eq·x = b_eq).
        b_eq : ndarray of float, shape (Q,)
            Their right-hand sides [deg].

        Raises
        ------
        InputError
            If there are no operations, or a time-bound operation has no speed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", min_angle_deg=30)
        >>> a_ub, b_ub, a_eq, b_eq = cg.feasible_rows()
        >>> a_ub[0].tolist(), float(b_ub[0]), a_eq.shape   # p_a − p_b ≤ −30
        ([1.0, -1.0, 0.0], -30.0, (0, 3))
        """
        self._require_ops()
        return LP(self._layout(), self.min_angles(speed_rpm), self.cycle_deg, None).dense_rows()

    def feasible_set(self, speed_rpm: float | None = None) -> FeasibleSet:
        """The feasible set of :meth:`optimize`'s LP at ``speed_rpm``, to optimise
        a second objective within it (the main shaft's flattening).

        Its rows are :meth:`feasible_rows`; rows may be added to it, and it
        minimises a linear objective over x = (event angles p [deg] in the order
        of :attr:`events`, the span F) ≥ 0.

        Parameters
        ----------
        speed_rpm : float, optional
            The main-shaft speed [rpm] for time-bound operations; default the
            cyclogram's.

        Returns
        -------
        FeasibleSet
            The set, its rows and its solve.

        Raises
        ------
        InputError
            If there are no operations, or a time-bound operation has no speed.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", min_angle_deg=30)
        >>> res = cg.feasible_set().minimize(np.array([0.0, 1.0, 0.0]))   # p_b earliest
        >>> res.status, round(float(res.x[1]), 9)
        (0, 30.0)
        """
        return FeasibleSet(*self.feasible_rows(speed_rpm))

    def min_angles(self, speed_rpm: float | None = None) -> npt.NDArray[np.float64]:
        """Minimum angle of each operation [deg] at ``speed_rpm`` (default: the cyclogram's).

        max(min_angle_deg, 6·n·min_duration_s) for each operation, in the order added.

        Parameters
        ----------
        speed_rpm : float, optional
            The main-shaft speed n [rpm]; default the cyclogram's.

        Returns
        -------
        ndarray of float, shape (E,)
            The minimum angles [deg], one per operation.

        Raises
        ------
        InputError
            If a time-bound operation has no speed, or its angle at that speed is
            beyond any machine cycle.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Cyclogram()
        >>> cg.add_operation("a", "b", min_angle_deg=30)
        >>> cg.add_operation("b", "c", min_angle_deg=10, min_duration_s=0.02)
        >>> cg.min_angles(speed_rpm=500).tolist()   # 6 · 500 rpm · 0.02 s = 60°
        [30.0, 60.0]
        """
        n = self._speed(speed_rpm)
        lay = self._layout()
        angle, secs = lay.angle, lay.secs
        timed = secs > 0
        if not timed.any():
            return angle.copy()
        if n is None:
            self._ops[int(np.argmax(timed))].min_angle_at(None)  # raises, naming the operation
        assert n is not None
        out, _ = minimum_angles(angle, secs, n)
        bad = ~(np.abs(out) <= MAX_ANGLE_DEG)
        if bad.any():
            op = self._ops[int(np.argmax(bad))]
            raise InputError(
                f"operation {op.title!r}: at speed_rpm = {n:g} its minimum duration of "
                f"{op.min_duration_s:g} s is {out[bad][0]:g}°, beyond any machine cycle "
                f"(at most {MAX_ANGLE_DEG:g}°); give a realistic speed"
            )
        return out

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

        Parameters
        ----------
        speed_rpm : float, optional
            The main-shaft speed [rpm] for time-bound operations; default the
            cyclogram's.
        horizon_deg : float, optional
            The angle [deg] by which every event must occur for the latest times
            (default: the schedule's own end, so the critical operations are those
            on the longest chains).

        Returns
        -------
        Schedule
            Earliest and latest event angles, slacks and critical operations.

        Raises
        ------
        CycleError
            When the operations within one cycle form a cycle.
        InputError
            If the cyclogram has no operations, or a time-bound operation has no
            speed.

        Examples
        --------
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
        lay = self._layout()
        src, dst, h = lay.src, lay.dst, lay.height
        inner = h == 0
        try:
            g = _core.EventGraph(len(self._events), src[inner], dst[inner])
        except CycleError as e:
            raise lay.named_cycle(e) from None
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

    def _check_order(self) -> None:
        """:class:`CycleError` if the operations within one machine cycle (height
        0) form a cycle: no schedule can order their events."""
        if not self._ops:
            return
        lay = self._layout()
        inner = lay.height == 0
        try:
            _core.EventGraph(len(lay.events), lay.src[inner], lay.dst[inner])
        except CycleError as e:
            raise lay.named_cycle(e) from None

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
        cycle.

        Parameters
        ----------
        cycle_deg : float, optional
            The machine cycle [deg]; default the cyclogram's.
        limiting : (str, str) or str, optional
            The operation (arc or name) whose angle to maximise; default the
            cyclogram's own, if any.
        speed_rpm : float, optional
            The main-shaft speed [rpm] that converts time-bound operations to
            degrees; default the cyclogram's.

        Returns
        -------
        Optimum
            The event and phase angles at the optimum [deg], the objective, and
            every bound's and constraint's shadow price and slack.

        Raises
        ------
        InfeasibleError
            If the bounds cannot all hold, naming the chain of operations whose
            minimum angles exceed the cycle, or the smallest set of bounds and
            constraints that conflict.
        SolverError
            If the LP solver stops without an answer.
        CycleError
            When the operations within one cycle form a cycle.
        InputError
            If there are no operations, or an argument is out of its range.

        Examples
        --------
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
        lay = self._layout()
        check_fits(lay, mins, cycle, n)
        lp = LP(lay, mins, cycle, lim)
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

    # ---------------------------------------------------------------- speed
    def max_speed_rpm(self, cycle_deg: float | None = None) -> SpeedLimit:
        """The highest main-shaft speed [rpm] at which the cyclogram fits in its cycle.

        Operations with ``min_duration_s`` take 6·n·s degrees at n rpm, so they grow
        with speed. The network bound is the maximum cycle ratio of the operations
        closed over one cycle, found by Howard's policy iteration with Newton steps
        in speed (Rust). When maximum angles or added constraints exist, an LP over
        the event angles and the speed itself gives the exact limit.

        Parameters
        ----------
        cycle_deg : float, optional
            The machine cycle [deg]; default the cyclogram's.

        Returns
        -------
        SpeedLimit
            The limit [rpm] (``inf`` when no time-bound operation limits it), the
            critical chain in ``cycle``, the network bound in ``network_rpm`` and
            the bounds that price it in ``binding``.

        Raises
        ------
        InfeasibleError
            If the cyclogram does not fit in the cycle at any speed (the chain
            named), or its bounds and constraints conflict even at standstill.
        SolverError
            If the LP solver stops without an answer.
        CycleError
            When the operations within one cycle form a cycle.

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
        return max_speed(self._layout(), cycle)

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

        Parameters
        ----------
        path : str or pathlib.Path
            The TOML file.

        Returns
        -------
        Cyclogram
            The cyclogram the file describes.

        Raises
        ------
        InputError
            If the file cannot be read or parsed, or an entry is malformed (naming
            the file, the table and the key).

        See Also
        --------
        from_dict : The same from the parsed tables.
        to_toml : The inverse.

        Examples
        --------
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

        Parameters
        ----------
        data : mapping of str to object
            The tables: ``cyclogram``, ``operation`` and ``constraint``.
        source : str, default "<dict>"
            Where the data came from, for error messages.

        Returns
        -------
        Cyclogram
            The cyclogram the tables describe.

        Raises
        ------
        InputError
            If an entry is malformed (naming the source, the table and the key).

        Examples
        --------
        >>> import cyclomech as cm
        >>> data = {"cyclogram": {"cycle_deg": 360.0},
        ...         "operation": [{"from": "a", "to": "b", "min_angle_deg": 30.0}]}
        >>> cm.Cyclogram.from_dict(data).operations[0].min_angle_deg
        30.0
        """
        cg = _file.read(cls, data, source)
        try:
            cg._check_order()
        except CycleError as e:
            raise CycleError(f"{source}: [[operation]]: {e}", e.events) from None
        return cg

    def to_toml(self, path: str | Path | None = None) -> str:
        """The cyclogram as TOML text, written to ``path`` if given.

        Reads back with :meth:`from_toml` to an equal cyclogram.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            A file to write the text to; None (default) to write nothing.

        Returns
        -------
        str
            The TOML text.

        Examples
        --------
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
        return _file.write(self, path)

    def __repr__(self) -> str:
        return (
            f"Cyclogram({self.name!r}, events={len(self._events)}, operations={len(self._ops)}, "
            f"constraints={len(self._constraints)}, cycle_deg={self.cycle_deg:g})"
        )
