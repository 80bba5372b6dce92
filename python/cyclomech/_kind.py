"""The contract between the machine and its mechanism kinds.

A mechanism kind (``cam_stop``, ``linkage``, ``press``, ``transfer``, …) is a class
in its domain's package that satisfies :class:`Mechanism`: it parses and validates
its ``[mechanism.<name>]`` table, gives its own speed limit with the reason, the
lower bounds it puts on cyclogram operations, and computes its results once
(:meth:`Mechanism.analyze`) into a :class:`MechanismResult` that the report,
``results.json``, the CSVs and the CLI only read. The machine holds a registry
``{kind: class}`` (:data:`cyclomech.machine.KINDS`) and no per-kind code.

Units: SI; speeds in rpm and angles in degrees where the names say so.

>>> from cyclomech._kind import Bound
>>> Bound(("3", "7"), "rebound[lifter]", "lifter").label
'rebound[lifter]'
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, runtime_checkable

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from .cyclogram import Constraint, Cyclogram, Optimum, SpeedLimit

Array = npt.NDArray[np.float64]
#: The smallest angle [deg] of a bound at each speed [rpm] (same shape; NaN where
#: even the whole cycle is too short).
BoundLaw = Callable[[Array], Array]
#: ``save(figure, file stem, caption)``: how a result hands the report a figure.
Save = Callable[[Any, str, str], None]

__all__ = [
    "Array",
    "Bound",
    "BoundLaw",
    "Context",
    "Mechanism",
    "MechanismResult",
    "Phase",
    "PlainResult",
    "Proportional",
    "Save",
    "TableContext",
    "Unbounded",
]


@dataclass(frozen=True)
class Bound:
    """A lower bound a mechanism puts on the angle of the cyclogram operation
    ``arc``, named ``label`` in the optimum's bounds and shadow prices
    (``"rebound[lifter]"``) and ``name`` in the speed sweep's
    ``min_phase_deg`` (the mechanism's name where it has one bound)."""

    arc: tuple[str, str]
    label: str
    name: str


@dataclass(frozen=True)
class Proportional:
    """A bound law that grows in proportion to the speed: the smallest angle is
    n·``per_rpm`` [deg] at n rpm (at least 1e-9°; NaN over 360°, where no phase
    angle of one turn will do), as a stop's rebound bound (its impact speed grows
    as n/t). The machine evaluates many of them in one vectorised step.

    >>> import numpy as np
    >>> Proportional(0.1)(np.array([100.0, 4000.0])).tolist()
    [10.0, nan]
    """

    per_rpm: float

    def __call__(self, rpm: Array) -> Array:
        return self.evaluate(rpm, self.per_rpm)

    @staticmethod
    def evaluate(rpm: npt.ArrayLike, per_rpm: npt.ArrayLike) -> Array:
        """n·per_rpm [deg] at least 1e-9, NaN over 360 (broadcast; no checks).

        >>> Proportional.evaluate([100.0, 200.0], [0.1, 2.0]).tolist()
        [10.0, nan]
        """
        t = np.maximum(np.multiply(rpm, per_rpm), 1e-9)
        return np.where(t <= 360.0, t, np.nan)


@dataclass(frozen=True)
class TableContext:
    """What a kind's parser may use besides its own table: the machine's
    cyclogram (to check the arcs it names), the file's name for messages, the
    machine's crank angles per turn and the machine's ``[mechanism.*]`` tables as
    read (``tables``: a cam stop takes its law and stroke from its cam's table)."""

    cyclogram: Cyclogram
    source: str
    angle_points: int
    tables: Mapping[str, Any] = field(default_factory=dict)

    def where(self, name: str) -> str:
        """The place a message names: ``<file>: [mechanism.<name>]``.

        >>> import cyclomech as cm
        >>> TableContext(cm.Cyclogram(), "loom.toml", 361).where("lifter")
        'loom.toml: [mechanism.lifter]'
        """
        return f"{self.source}: [mechanism.{name}]"


@dataclass(frozen=True)
class Phase:
    """Where a mechanism driven by the main shaft sits in the cycle: at the
    cyclogram event ``event`` its own angle (a linkage's absolute crank angle, a
    press's carrier angle turned past BDC in the turning direction, −α) is
    ``crank_deg``; without an event, its angle is
    ``crank_deg`` at cycle angle 0. Read from ``phase = {event = "…", crank_deg =
    …}`` in a ``[mechanism.<name>]`` table (:meth:`from_table`).

    The shift of its torque curve on the main shaft, :meth:`shift_deg`, is the
    cycle angle at which its own angle is ``origin_deg`` (where its curve starts):
    ``times[event] − (crank_deg − origin_deg)``.

    >>> Phase("cut", 200.0).shift_deg({"cut": 90.0}, origin_deg=150.0)
    40.0
    """

    event: str | None = None
    crank_deg: float = 0.0

    #: The keys of a ``phase`` table.
    KEYS: ClassVar[frozenset[str]] = frozenset({"event", "crank_deg"})

    @classmethod
    def from_table(cls, table: Mapping[str, Any], ctx: TableContext, name: str) -> Phase:
        """The ``phase`` key of ``[mechanism.<name>]`` (absent: the mechanism's
        angle is 0 at cycle angle 0); the event must be one of the cyclogram's.

        >>> import cyclomech as cm
        >>> cg = cm.Machine.from_toml("examples/knife_cutter.toml").cyclogram
        >>> ctx = TableContext(cg, "f", 361)
        >>> Phase.from_table({"phase": {"event": "clamped", "crank_deg": 30}}, ctx, "knife")
        Phase(event='clamped', crank_deg=30.0)
        """
        from . import _toml
        from ._errors import InputError

        where = f"{ctx.where(name)} phase"
        spec = table.get("phase")
        if spec is None:
            return cls()
        if not isinstance(spec, Mapping):
            raise InputError(
                f'{where} = {spec!r}: give a table {{event = "<event>", crank_deg = <angle>}}'
            )
        _toml.check_keys(spec, set(cls.KEYS), ctx.source, f"[mechanism.{name}.phase]")
        crank = _toml.number(spec, "crank_deg", where, "[deg]") if "crank_deg" in spec else 0.0
        event = spec.get("event")
        if event is not None and event not in ctx.cyclogram.events:
            known = ", ".join(repr(e) for e in ctx.cyclogram.events)
            raise InputError(
                f"{where}: event = {event!r} is not an event of the cyclogram; its events are "
                f"{known}"
            )
        return cls(event, crank)

    def shift_deg(self, times: Mapping[str, float], origin_deg: float = 0.0) -> float:
        """The cycle angle [deg] at which the mechanism's angle is ``origin_deg``,
        given the optimum's event ``times`` [deg]."""
        at = 0.0 if self.event is None else float(times[self.event])
        return at - (self.crank_deg - origin_deg)


@dataclass(frozen=True)
class Context:
    """What the machine computed before its mechanisms' results, for
    :meth:`Mechanism.analyze`: the speed limit, the report's nominal speed [rpm]
    and the speed grid [rpm], the optimum there (None if it does not fit), the
    cyclogram, and ``bounds`` / ``linear_bounds``: each bound's smallest angle
    [deg] on the grid by the bound's name (the speed sweeps' ``min_phase_deg``),
    exact and linearised."""

    limit: SpeedLimit
    nominal_rpm: float
    rpm: Array
    optimum: Optimum | None
    cyclogram: Cyclogram
    bounds: Mapping[str, Array] = field(default_factory=dict)
    linear_bounds: Mapping[str, Array] = field(default_factory=dict)

    def own_limit_rpm(self, name: str) -> float:
        """The mechanism's own speed limit [rpm] as the machine's speed limit holds
        it (inf where it has none): one value, computed once.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> round(r.mechanisms["knife"].ctx.own_limit_rpm("knife"), 2)
        76.83
        """
        return self.limit.mechanisms_rpm.get(name, float("inf"))


@runtime_checkable
class MechanismResult(Protocol):
    """A mechanism's results, computed once by :meth:`Mechanism.analyze`."""

    def json(self) -> dict[str, dict[str, Any]]:
        """Its entries in ``results.json``: ``{group: entry}``, where the group is
        ``"mechanisms"`` (always) or one of its kind's :attr:`Mechanism.json_groups`."""
        ...

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """The header and rows of its section's table in the report."""
        ...

    def csv_columns(self) -> list[tuple[str, Array]]:
        """Columns it adds to ``speed_sweep.csv`` (on the sweep's speeds)."""
        ...

    def prices(self) -> dict[str, float]:
        """Shadow prices of its bounds per unit of its own limit (label: value),
        for ``results.json``'s ``optimum`` (empty where it has none)."""
        ...

    def figures(self, save: Save) -> None:
        """Draw its figures and hand each to ``save``."""
        ...


@runtime_checkable
class Mechanism(Protocol):
    """A mechanism kind (see the module's docstring). Class attributes: ``kind``
    (the ``kind`` of its table), ``keys`` (every key its table takes, ``kind``
    included), ``fixed_keys`` (keys a sweep may not set: the ones that change the
    cyclogram's shape), ``json_groups`` (the top-level groups of ``results.json`` it
    adds to, besides ``mechanisms``) and ``sweep_columns`` (columns it adds to the
    machine's speed sweep; several mechanisms' values of one column combine by their
    maximum)."""

    kind: ClassVar[str]
    keys: ClassVar[frozenset[str]]
    fixed_keys: ClassVar[frozenset[str]]
    json_groups: ClassVar[tuple[str, ...]]
    sweep_columns: ClassVar[tuple[str, ...]]

    @property
    def name(self) -> str:
        """Its name: the ``<name>`` of its table."""
        ...

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> Mechanism:
        """Parse and validate its table; errors name ``ctx.where(name)``, the key
        and what is valid."""
        ...

    def speed_limit_rpm(self) -> float:
        """Its own speed limit [rpm] (inf without one)."""
        ...

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`, in words ("" without a limit)."""
        ...

    def bounds(self) -> tuple[Bound, ...]:
        """The lower bounds it puts on cyclogram operations."""
        ...

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[Constraint, ...]:
        """Its bounds at ``rpm`` [rpm] as cyclogram constraints named by their
        labels (the seed's linearised forms with ``linear``, where it has them)."""
        ...

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[BoundLaw]]:
        """For each of ``mechanisms`` (all of this kind, e.g. the designs of a
        sweep: one batched computation), for each of its bounds, the law that
        gives its smallest angle at any speed; cheap to evaluate, as a speed-limit
        search evaluates it many times. ``linear``: the seed's linearised form where
        the kind has one (else the exact law)."""
        ...

    @classmethod
    def sweep_values(
        cls,
        mechanisms: Sequence[Any],
        rpm: Array,
        angle_deg: Sequence[Array],
        fits: npt.NDArray[np.bool_],
        *,
        n_threads: int | None = None,
    ) -> dict[str, Array]:
        """Its :attr:`sweep_columns` for design d of ``mechanisms`` at the speeds
        ``rpm`` (D, S), given each of its bounds' operation angle at the optimum
        (``angle_deg[k]``, (D·S,), row order of ``rpm.reshape(-1)``) and where the
        machine fits; (D·S,) arrays."""
        ...

    def analyze(self, ctx: Context) -> MechanismResult:
        """Its results, computed once."""
        ...


class Unbounded:
    """Defaults for a kind that puts no bound on the cyclogram and adds nothing to
    the speed sweep (mix it into the kind's class).

    >>> Unbounded.bound_laws([object(), object()])
    [[], []]
    """

    fixed_keys: ClassVar[frozenset[str]] = frozenset({"kind"})
    json_groups: ClassVar[tuple[str, ...]] = ()
    sweep_columns: ClassVar[tuple[str, ...]] = ()

    def bounds(self) -> tuple[Bound, ...]:
        """None.

        >>> Unbounded().bounds()
        ()
        """
        return ()

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[Constraint, ...]:
        """None.

        >>> Unbounded().constraints(300.0)
        ()
        """
        return ()

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[BoundLaw]]:
        """No law for any of ``mechanisms``.

        >>> Unbounded.bound_laws([object()])
        [[]]
        """
        return [[] for _ in mechanisms]

    @classmethod
    def sweep_values(
        cls,
        mechanisms: Sequence[Any],
        rpm: Array,
        angle_deg: Sequence[Array],
        fits: npt.NDArray[np.bool_],
        *,
        n_threads: int | None = None,
    ) -> dict[str, Array]:
        """Nothing.

        >>> import numpy as np
        >>> Unbounded.sweep_values([], np.zeros((0, 1)), [], np.zeros(0, bool))
        {}
        """
        return {}


class PlainResult:
    """Defaults for a result without CSV columns or priced bounds (mix it in)."""

    def csv_columns(self) -> list[tuple[str, Array]]:
        """None.

        >>> PlainResult().csv_columns()
        []
        """
        return []

    def prices(self) -> dict[str, float]:
        """None.

        >>> PlainResult().prices()
        {}
        """
        return {}
