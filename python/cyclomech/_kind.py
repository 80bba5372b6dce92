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

from ._arrays import flag, instance, instances, positive, real_array, threads_arg
from ._errors import InputError
from ._keydoc import FIN, NO_UNIT, NUM, TEXT, KeyDoc, KeyTable
from .cyclogram import BoundLaw, Constraint, Proportional
from .cyclogram import proportional_law as proportional_law  # for the kinds and the machine

if TYPE_CHECKING:
    from .cyclogram import Cyclogram, Optimum, SpeedLimit

#: A float64 NumPy array (the arrays of speeds [rpm] and angles [deg] here).
Array = npt.NDArray[np.float64]
#: ``save(figure, file stem, caption)``: how a result hands the report a figure.
Save = Callable[[Any, str, str], None]

__all__ = [
    "Array",
    "BatchDesigns",
    "BatchSolution",
    "Bound",
    "BoundLaw",
    "BoundsResult",
    "Context",
    "ExactBounds",
    "Mechanism",
    "MechanismResult",
    "Phase",
    "PlainResult",
    "Proportional",
    "Save",
    "TableContext",
    "Unbounded",
    "efficiency_entry",
    "per_distinct_speed",
]


@dataclass(frozen=True)
class Bound:
    """A lower bound a mechanism puts on the angle of one cyclogram operation.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    arc : tuple of (str, str)
        The operation (its start and end events) whose angle is bounded.
    label : str
        The bound's name in the optimum's bounds and shadow prices
        (``"rebound[lifter]"``).
    name : str
        The bound's name in the speed sweep's ``min_phase_deg`` (the mechanism's
        name where it has one bound).

    Examples
    --------
    >>> from cyclomech.machine import Bound
    >>> Bound(("3", "7"), "rebound[lifter]", "lifter").label
    'rebound[lifter]'
    """

    arc: tuple[str, str]
    label: str
    name: str


@dataclass(frozen=True)
class TableContext:
    """What a kind's parser may use besides its own table.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    cyclogram : Cyclogram
        The machine's cyclogram (to check the arcs a table names).
    source : str
        The file's name, for messages.
    angle_points : int
        The machine's crank angles per turn.
    tables : Mapping of str to Any, optional
        The machine's ``[mechanism.*]`` tables as read, by name (a cam stop takes
        its law and stroke from its cam's table); default an empty dict.

    Examples
    --------
    >>> import cyclomech as cm
    >>> TableContext(cm.Cyclogram(), "loom.toml", 361).angle_points
    361
    """

    cyclogram: Cyclogram
    source: str
    angle_points: int
    tables: Mapping[str, Any] = field(default_factory=dict)

    def where(self, name: str) -> str:
        """The place a message names: ``<file>: [mechanism.<name>]``.

        Parameters
        ----------
        name : str
            The mechanism's name.

        Returns
        -------
        str
            ``<source>: [mechanism.<name>]``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> TableContext(cm.Cyclogram(), "loom.toml", 361).where("lifter")
        'loom.toml: [mechanism.lifter]'
        """
        return f"{self.source}: [mechanism.{name}]"


@dataclass(frozen=True)
class Phase:
    """Where a mechanism driven by the main shaft sits in the cycle.

    At the cyclogram event ``event`` its own angle (a linkage's absolute crank
    angle, a press's carrier angle turned past BDC in the turning direction, −α) is
    ``crank_deg``; without an event, its angle is ``crank_deg`` at cycle angle 0.
    Read from ``phase = {event = "…", crank_deg = …}`` in a ``[mechanism.<name>]``
    table (:meth:`from_table`). The shift of its torque curve on the main shaft,
    :meth:`shift_deg`, is the cycle angle at which its own angle is ``origin_deg``
    (where its curve starts): ``times[event] − (crank_deg − origin_deg)``. Each
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    event : str, optional
        A cyclogram event; default None (cycle angle 0).
    crank_deg : float, default 0.0
        The mechanism's own angle at that event [deg].

    Examples
    --------
    >>> Phase("cut", 200.0).shift_deg({"cut": 90.0}, origin_deg=150.0)
    40.0
    """

    event: str | None = None
    crank_deg: float = 0.0

    #: The keys of a ``phase`` table.
    KEYS: ClassVar[frozenset[str]] = frozenset({"event", "crank_deg"})
    # Its keys' documentation for the machine-file format reference (a linkage's
    # and a press's ``key_docs`` end with it).
    # fmt: off
    key_docs: ClassVar[KeyTable] = KeyTable("phase", "phase of a linkage or press", (
        KeyDoc("event", "The cyclogram event at which the mechanism's angle is crank_deg.",
               NO_UNIT, TEXT, "none (crank_deg at cycle angle 0)",
               "one of the cyclogram's events (a string)", None),
        KeyDoc("crank_deg", "The mechanism's own angle at that event.", "deg", NUM, "0", FIN,
               None),
    ), intro=(
        "``phase = {event = …, crank_deg = …}`` in a linkage's or press's table places "
        "its torque on the main shaft; in a servo axis's, its program in the cycle."
    ))
    # fmt: on

    @classmethod
    def from_table(cls, table: Mapping[str, Any], ctx: TableContext, name: str) -> Phase:
        """The ``phase`` key of ``[mechanism.<name>]``.

        Parameters
        ----------
        table : Mapping of str to Any
            The mechanism's table.
        ctx : TableContext
            The machine's cyclogram and file name.
        name : str
            The mechanism's name.

        Returns
        -------
        Phase
            Its phase (``phase`` absent: the mechanism's angle is 0 at cycle angle 0).

        Raises
        ------
        InputError
            If ``phase`` is not a table, has an unknown key, or its event is not one of
            the cyclogram's.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Machine.from_toml("examples/knife_cutter.toml").cyclogram
        >>> ctx = TableContext(cg, "f", 361)
        >>> Phase.from_table({"phase": {"event": "clamped", "crank_deg": 30}}, ctx, "knife")
        Phase(event='clamped', crank_deg=30.0)
        """
        from . import _toml

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
        event = _toml.event(spec, "event", where) if "event" in spec else None
        if event is not None and event not in ctx.cyclogram.events:
            known = ", ".join(repr(e) for e in ctx.cyclogram.events)
            raise InputError(
                f"{where}: event = {event!r} is not an event of the cyclogram; its events are "
                f"{known}"
            )
        return cls(event, crank)

    def shift_deg(self, times: Mapping[str, float], origin_deg: float = 0.0) -> float:
        """The cycle angle [deg] at which the mechanism's angle is ``origin_deg``.

        Parameters
        ----------
        times : Mapping of str to float
            The optimum's event times [deg].
        origin_deg : float, default 0.0
            The mechanism's own angle where its torque curve starts [deg].

        Returns
        -------
        float
            ``times[event] − (crank_deg − origin_deg)`` [deg] (``times[event]`` 0
            without an event).

        Examples
        --------
        >>> Phase(crank_deg=30.0).shift_deg({})
        -30.0
        """
        at = 0.0 if self.event is None else float(times[self.event])
        return at - (self.crank_deg - origin_deg)


@dataclass(frozen=True)
class Context:
    """What the machine computed before its mechanisms' results, for :meth:`Mechanism.analyze`.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    limit : SpeedLimit
        The machine's speed limit.
    nominal_rpm : float
        The report's nominal speed [rpm].
    rpm : ndarray of float
        The speed grid [rpm].
    optimum : Optimum or None
        The cyclogram's optimum at the nominal speed (None if it does not fit).
    cyclogram : Cyclogram
        The machine's cyclogram.
    bounds : Mapping of str to ndarray, optional
        Each bound's smallest angle [deg] on the grid by the bound's name (the
        speed sweeps' ``min_phase_deg``), exact; default an empty dict.
    linear_bounds : Mapping of str to ndarray, optional
        The same, linearised; default an empty dict.
    mechanisms : tuple of str, optional
        The machine's mechanisms by name (what :meth:`own_limit_rpm` may be
        asked); default empty (any name).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> ctx = r.mechanisms["lifter"].ctx
    >>> ctx.nominal_rpm, ctx.bounds["lifter"].shape == ctx.rpm.shape
    (300.0, True)
    """

    limit: SpeedLimit
    nominal_rpm: float
    rpm: Array
    optimum: Optimum | None
    cyclogram: Cyclogram
    bounds: Mapping[str, Array] = field(default_factory=dict)
    linear_bounds: Mapping[str, Array] = field(default_factory=dict)
    mechanisms: tuple[str, ...] = ()

    def own_limit_rpm(self, name: str) -> float:
        """A mechanism's own speed limit [rpm] as the machine's speed limit holds it.

        One value, computed once.

        Parameters
        ----------
        name : str
            The mechanism's name.

        Returns
        -------
        float
            Its own speed limit [rpm] (inf where it has none).

        Raises
        ------
        TypeError
            If ``name`` is not a string.
        InputError
            If ``name`` is not one of ``mechanisms`` (when the context lists
            them): a misspelt name would otherwise read as "no limit".

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> round(r.mechanisms["knife"].ctx.own_limit_rpm("knife"), 2)
        76.83
        """
        instance("name", name, str)
        if self.mechanisms and name not in self.mechanisms:
            raise InputError(
                f"name = {name!r} is not a mechanism of the machine; its mechanisms are "
                f"{', '.join(repr(k) for k in self.mechanisms)}"
            )
        return self.limit.mechanisms_rpm.get(name, float("inf"))


@runtime_checkable
class MechanismResult(Protocol):
    """A mechanism's results, computed once by :meth:`Mechanism.analyze`.

    A protocol: each kind's result class satisfies it (``isinstance`` checks the
    methods); it is not instantiated itself.

    Parameters
    ----------
    *args, **kwargs
        None: a protocol takes no arguments (it cannot be instantiated).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> isinstance(r.mechanisms["lifter"], MechanismResult)
    True
    """

    def json(self) -> dict[str, dict[str, Any]]:
        """Its entries in ``results.json``.

        Returns
        -------
        dict of str to dict
            ``{group: entry}``, where the group is ``"mechanisms"`` (always) or one of
            its kind's ``json_groups``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> sorted(r.mechanisms["lifter"].json())
        ['mechanisms', 'stops']
        """
        ...

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """The header and rows of its section's table in the report.

        Returns
        -------
        header : list of str
            The column names.
        rows : list of list
            One row per quantity.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter"].table()[0]
        ['quantity', 'value']
        """
        ...

    def csv_columns(self) -> list[tuple[str, Array]]:
        """Columns it adds to ``speed_sweep.csv`` (on the sweep's speeds).

        Returns
        -------
        list of tuple of (str, ndarray)
            (column name with its unit, values on the sweep's speeds).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> [name for name, _ in r.mechanisms["lifter"].csv_columns()]
        ['min_phase_deg[lifter]', 'linear_min_phase_deg[lifter]']
        """
        ...

    def prices(self) -> dict[str, float]:
        """Shadow prices of its bounds per unit of its own limit.

        For ``results.json``'s ``optimum``.

        Returns
        -------
        dict of str to float
            label: value (empty where it has none).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> list(r.mechanisms["lifter"].prices())
        ['rebound[lifter]']
        """
        ...

    def figures(self, save: Save) -> None:
        """Draw its figures and hand each to ``save``.

        Parameters
        ----------
        save : callable
            ``save(figure, file stem, caption)``, called once per figure.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> stems = []
        >>> r.mechanisms["lifter"].figures(lambda fig, stem, caption: stems.append(stem))
        >>> stems
        ['lifter_rebound', 'lifter_law', 'lifter_min_phase']
        >>> plt.close("all")
        """
        ...


@runtime_checkable
class Mechanism(Protocol):
    """A mechanism kind: what a kind of ``[mechanism.<name>]`` table provides.

    A protocol that each kind's class satisfies (``isinstance`` checks the
    methods); it is not instantiated itself. Class attributes: ``kind`` (the
    ``kind`` of its table), ``keys`` (every key its table takes, ``kind``
    included), ``fixed_keys`` (keys a sweep may not set: the ones that change the
    cyclogram's shape), ``json_groups`` (the top-level groups of ``results.json``
    it adds to, besides ``mechanisms``), ``sweep_columns`` (columns it adds to
    the machine's speed sweep; several mechanisms' values of one column combine by
    their maximum) and ``key_docs`` (its tables' keys for the machine-file format
    reference: a tuple of :class:`~cyclomech.machine.KeyTable`, its own table first,
    named after its kind, then its sub-tables; the reference lists every registered
    kind's, so a kind's documentation lives with the kind).

    Parameters
    ----------
    *args, **kwargs
        None: a protocol takes no arguments (it cannot be instantiated).

    Notes
    -----
    Optional hook, outside the protocol's ``isinstance`` check (a kind without it
    is a kind all the same): a classmethod ``batch_designs(mechanism, table,
    keys)`` offers the machine's sweeps a batch path for a mechanism of the kind
    whose table's ``keys`` (a collection of str) vary. ``mechanism`` is the
    machine's mechanism and ``table`` its table as read. It returns a batch of
    designs (the designs of that mechanism, built and
    solved many at once, bit for bit what one machine per design gives), or None
    where those keys need one machine per design. The sweep asks each swept
    mechanism's class for the hook and calls it; it knows no kind by name
    (``cam_stop`` has one: :meth:`cyclomech.impact.CamStop.batch_designs`).

    Optional class attribute: ``varied_tables`` (a frozenset of str), the sub-tables
    and lists of its table whose numbers a sweep and the sensitivities may vary by a
    path (``<mechanism>.lengths.3.length``, ``<mechanism>.points.B.1``; positions
    from 1); none without it.

    Optional hook too: a mechanism dimensioned from the machine's own timing has a
    ``resizes`` flag (True where its table asks for it) and a method ``resize(rpm,
    angles)``: given the nominal speed [rpm] and the optimum's phase angles [deg] by
    arc, the mechanism re-dimensioned for them (its bounds on the same operations),
    or None where its dimensions would not change; ``resized_values()`` names what
    it chose. ``cyclomech run`` iterates LP and resize to a fixed point before it
    analyses the machine (``cyclomech/machine/_resize.py``; ``cam`` has one:
    :meth:`cyclomech.cam.CamMechanism.resize`).

    Examples
    --------
    >>> import cyclomech as cm
    >>> stop = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter"]
    >>> isinstance(stop, Mechanism), stop.kind, stop.sweep_columns
    (True, 'cam_stop', ('max_rebound_m',))
    """

    kind: ClassVar[str]
    keys: ClassVar[frozenset[str]]
    fixed_keys: ClassVar[frozenset[str]]
    json_groups: ClassVar[tuple[str, ...]]
    sweep_columns: ClassVar[tuple[str, ...]]
    key_docs: ClassVar[tuple[KeyTable, ...]]

    @property
    def name(self) -> str:
        """Its name: the ``<name>`` of its table.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter"].name
        'lifter'
        """
        ...

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> Mechanism:
        """Parse and validate its table.

        Parameters
        ----------
        name : str
            The mechanism's name (the ``<name>`` of ``[mechanism.<name>]``).
        table : Mapping of str to Any
            Its table as read.
        ctx : TableContext
            The machine's cyclogram, file name, crank angles and tables.

        Returns
        -------
        Mechanism
            The mechanism.

        Raises
        ------
        InputError
            If the table is invalid; errors name ``ctx.where(name)``, the key and what
            is valid.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/stb_loom.toml")
        >>> ctx = TableContext(m.cyclogram, "stb_loom.toml", 361, m.data["mechanism"])
        >>> table = m.data["mechanism"]["lifter"]
        >>> cm.machine.KINDS["cam_stop"].from_table("lifter", table, ctx).name
        'lifter'
        """
        ...

    def speed_limit_rpm(self) -> float:
        """Its own speed limit [rpm].

        Returns
        -------
        float
            The limit [rpm] (inf without one).

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> round(m.mechanisms["knife"].speed_limit_rpm(), 2)
        76.83
        """
        ...

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`, in words.

        Returns
        -------
        str
            The reason ("" without a limit).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"].limit_reason()
        "the peak acceleration of point 'E' reaches max_acceleration = 8 m/s²"
        """
        ...

    def bounds(self) -> tuple[Bound, ...]:
        """The lower bounds it puts on cyclogram operations.

        Returns
        -------
        tuple of Bound
            Its bounds (empty without any).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter"].bounds()
        (Bound(arc=('3', '7'), label='rebound[lifter]', name='lifter'),)
        """
        ...

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[Constraint, ...]:
        """Its bounds at one speed as cyclogram constraints named by their labels.

        Parameters
        ----------
        rpm : float
            The speed [rpm].
        linear : bool, default False
            The seed's linearised forms, where it has them.

        Returns
        -------
        tuple of Constraint
            One constraint per bound.

        Examples
        --------
        >>> import cyclomech as cm
        >>> stop = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter"]
        >>> stop.constraints(300.0)[0].describe()
        '1·t(3,7) >= 30.0306'
        """
        ...

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[BoundLaw]]:
        """For each mechanism of this kind, for each of its bounds, its law against speed.

        The law gives the bound's smallest angle at any speed; cheap to evaluate, as a
        speed-limit search evaluates it many times. All mechanisms in one batched
        computation.

        Parameters
        ----------
        mechanisms : sequence of Mechanism
            Mechanisms all of this kind (e.g. the designs of a sweep).
        linear : bool, default False
            The seed's linearised form where the kind has one (else the exact law).
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        list of list of BoundLaw
            Per mechanism, per bound, the smallest angle [deg] as a function of the
            speeds [rpm].

        Examples
        --------
        >>> import numpy as np
        >>> import cyclomech as cm
        >>> stop = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter"]
        >>> (law,), = type(stop).bound_laws([stop])
        >>> law(np.array([300.0])).round(4).tolist()
        [30.0306]
        """
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
        """Its ``sweep_columns`` for each design of ``mechanisms`` at each speed.

        Parameters
        ----------
        mechanisms : sequence of Mechanism
            D designs, all of this kind.
        rpm : ndarray of float, shape (D, S)
            The speeds of each design [rpm].
        angle_deg : sequence of ndarray of float, each shape (D·S,)
            Each of its bounds' operation angle at the optimum [deg] (``angle_deg[k]``
            for bound k, in the row order of ``rpm.reshape(-1)``).
        fits : ndarray of bool, shape (D·S,)
            Where the machine fits.
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        dict of str to ndarray
            Each of its sweep columns, a (D·S,) array.

        Examples
        --------
        >>> import numpy as np
        >>> import cyclomech as cm
        >>> stop = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter"]
        >>> v = type(stop).sweep_values([stop], np.array([[300.0]]), [np.array([40.0])],
        ...                             np.array([True]))
        >>> list(v), v["max_rebound_m"].shape
        (['max_rebound_m'], (1,))
        """
        ...

    def analyze(self, ctx: Context) -> MechanismResult:
        """Its results, computed once.

        Parameters
        ----------
        ctx : Context
            What the machine computed before (speed limit, nominal speed, grid,
            optimum, bounds).

        Returns
        -------
        MechanismResult
            Its results, which the report, ``results.json``, the CSVs and the CLI only
            read.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> type(r.mechanisms["lifter"]).__name__
        'CamStopResult'
        """
        ...


class Unbounded:
    """Defaults for a kind that puts no bound on the cyclogram and adds nothing to the speed sweep.

    Mix it into the kind's class.

    Examples
    --------
    >>> Unbounded.bound_laws([object(), object()])
    [[], []]
    """

    fixed_keys: ClassVar[frozenset[str]] = frozenset({"kind"})
    json_groups: ClassVar[tuple[str, ...]] = ()
    sweep_columns: ClassVar[tuple[str, ...]] = ()

    def bounds(self) -> tuple[Bound, ...]:
        """No bound.

        Returns
        -------
        tuple
            ``()``.

        Examples
        --------
        >>> Unbounded().bounds()
        ()
        """
        return ()

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[Constraint, ...]:
        """No constraint.

        Parameters
        ----------
        rpm : float
            The speed [rpm] (unused).
        linear : bool, default False
            The linearised forms (unused).

        Returns
        -------
        tuple
            ``()``.

        Examples
        --------
        >>> Unbounded().constraints(300.0)
        ()
        """
        positive("rpm", rpm, "[rpm]")  # unused, but the same rule as every kind's
        flag("linear", linear)
        return ()

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[BoundLaw]]:
        """No law for any of ``mechanisms``.

        Parameters
        ----------
        mechanisms : sequence of Mechanism
            The mechanisms.
        linear : bool, default False
            The linearised forms (unused).
        n_threads : int, optional
            Threads (unused); default None.

        Returns
        -------
        list of list
            An empty list per mechanism.

        Examples
        --------
        >>> Unbounded.bound_laws([object()])
        [[]]
        """
        flag("linear", linear)
        threads_arg(n_threads)
        mechanisms = instances("mechanisms", mechanisms, object)
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
        """No sweep column.

        Parameters
        ----------
        mechanisms : sequence of Mechanism
            The D designs.
        rpm : ndarray of float, shape (D, S)
            The speeds [rpm] (unused).
        angle_deg : sequence of ndarray of float
            The bounds' operation angles [deg] (unused).
        fits : ndarray of bool
            Where the machine fits (unused).
        n_threads : int, optional
            Threads (unused); default None.

        Returns
        -------
        dict
            ``{}``.

        Examples
        --------
        >>> import numpy as np
        >>> Unbounded.sweep_values([], np.zeros((0, 1)), [], np.zeros(0, bool))
        {}
        """
        real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(2,))
        threads_arg(n_threads)
        return {}


class ExactBounds(Unbounded):
    """Defaults for a kind whose bounds are exact laws of the speed (a cam's, a servo axis's).

    Mix it in: the kind gives ``bounds()`` and ``laws()`` (one law per bound, in
    the same order); :meth:`constraints` and :meth:`bound_laws` follow from them,
    one way for every such kind. A law has no linearised form.

    Examples
    --------
    >>> ExactBounds().constraints(300.0), ExactBounds.bound_laws([])
    ((), [])
    """

    def laws(self) -> list[BoundLaw]:
        """Each bound's smallest angle [deg] against speed [rpm]: none by default.

        Returns
        -------
        list of BoundLaw
            One law per bound of ``bounds()``, in its order.

        Examples
        --------
        >>> ExactBounds().laws()
        []
        """
        return []

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[Constraint, ...]:
        """Its bounds at ``rpm`` as cyclogram constraints t(arc) ≥ bound.

        Parameters
        ----------
        rpm : float
            The speed [rpm].
        linear : bool, default False
            Unused (the laws are exact).

        Returns
        -------
        tuple of Constraint
            One constraint per bound, named by its label.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
        >>> cam.constraints(450.0)[2].describe()
        '1·t(1,3) >= 29.6374'
        """
        rpm = positive("rpm", rpm, "[rpm]")
        flag("linear", linear)  # exact laws have one form only
        n = np.array([float(rpm)])
        return tuple(
            Constraint(((b.arc, 1.0),), ">=", float(law(n)[0]), b.label)
            for b, law in zip(self.bounds(), self.laws(), strict=True)
        )

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[BoundLaw]]:
        """:meth:`laws` of each mechanism.

        Parameters
        ----------
        mechanisms : sequence of the kind's mechanisms
            The mechanisms (each of this class).
        linear : bool, default False
            No meaning: the laws are exact.
        n_threads : int, optional
            Unused; default None.

        Returns
        -------
        list of list of BoundLaw
            Per mechanism, its :meth:`laws`.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
        >>> len(type(cam).bound_laws([cam])[0]) == len(cam.bounds())
        True
        """
        flag("linear", linear)
        threads_arg(n_threads)
        mechanisms = instances("mechanisms", mechanisms, cls)
        return [m.laws() for m in mechanisms]


class PlainResult:
    """Defaults for a result without CSV columns or priced bounds (mix it in).

    Examples
    --------
    >>> PlainResult().csv_columns(), PlainResult().prices()
    ([], {})
    """

    def csv_columns(self) -> list[tuple[str, Array]]:
        """No CSV column.

        Returns
        -------
        list
            ``[]``.

        Examples
        --------
        >>> PlainResult().csv_columns()
        []
        """
        return []

    def prices(self) -> dict[str, float]:
        """No priced bound.

        Returns
        -------
        dict
            ``{}``.

        Examples
        --------
        >>> PlainResult().prices()
        {}
        """
        return {}


class BoundsResult:
    """Defaults for the result of a kind whose bounds stand in the speed sweep (mix it in).

    The result has ``mech`` (its mechanism, with ``bounds()``) and ``ctx`` (the
    :class:`Context`): each bound's smallest phase angle is a column of the sweep's
    CSV, and its price is the optimum's own (by label).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> isinstance(r.mechanisms["lifter cam"], BoundsResult)
    True
    """

    mech: Any
    ctx: Context

    def csv_columns(self) -> list[tuple[str, Array]]:
        """Each bound's smallest phase angle [deg] on the sweep's speeds.

        Returns
        -------
        list of tuple of (str, ndarray)
            (``min_phase_deg[<label>]``, values on the sweep's speeds [deg]).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter cam"].csv_columns()[0][0]
        'min_phase_deg[pressure angle[lifter cam rise 1→3]]'
        """
        return [(f"min_phase_deg[{b.label}]", self.ctx.bounds[b.name]) for b in self.mech.bounds()]

    def prices(self) -> dict[str, float]:
        """None beyond the optimum's own (its bounds are priced there by label).

        Returns
        -------
        dict
            ``{}``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter cam"].prices()
        {}
        """
        return {}


def per_distinct_speed(rpm: Any, solve: Callable[[Array], Array]) -> Array:
    """``solve`` at each distinct speed of ``rpm`` once, spread back to its shape.

    A bound law solved per speed (a cam's Hertz stress, a servo's RMS) is asked by
    the variants of a sweep that share a mechanism for the same speeds: one call on
    the distinct ones.

    Parameters
    ----------
    rpm : array_like of float
        The speeds [rpm], any shape.
    solve : callable
        ``solve(speeds)`` → values, for a sorted 1-d array of distinct speeds.

    Returns
    -------
    ndarray of float
        ``solve``'s values in ``rpm``'s shape.

    Examples
    --------
    >>> per_distinct_speed([[2.0, 1.0], [2.0, 2.0]], lambda n: 10 * n).tolist()
    [[20.0, 10.0], [20.0, 20.0]]
    """
    r = np.asarray(rpm, dtype=np.float64)
    speeds, where = np.unique(r.reshape(-1), return_inverse=True)
    return np.asarray(solve(speeds), dtype=np.float64)[where].reshape(r.shape)


class BatchSolution(Protocol):
    """A batch of designs of one mechanism, solved: what the sweep takes from it.

    Returned by :meth:`BatchDesigns.solve`. Its bounds are proportional to the
    speed (the smallest angle of bound k of design d is ``per_rpm[d, k]`` times
    the speed), which lets the sweep solve every design at every speed, and
    search every design's speed limit, in one shortest-path call.

    Parameters
    ----------
    *args, **kwargs
        None: a protocol takes no arguments (it cannot be instantiated).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> m = cm.Machine.example()
    >>> lifter = m.mechanisms["lifter"]
    >>> batch = type(lifter).batch_designs(lifter, m.data["mechanism"]["lifter"], ["a_max_m"])
    >>> solved = batch.solve(batch.designs({"a_max_m": np.array([1e-4, 2e-4])})[0], 1)
    >>> solved.per_rpm.shape
    (2, 1)
    """

    @property
    def per_rpm(self) -> Array:
        """Each design's bounds' smallest angles per rpm [deg/rpm].

        Returns
        -------
        ndarray of float, shape (D, K)
            Per design, per bound of the mechanism (in the order of its ``bounds()``).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.example()
        >>> lifter = m.mechanisms["lifter"]
        >>> batch = type(lifter).batch_designs(lifter, m.data["mechanism"]["lifter"], ["zeta"])
        >>> solved = batch.solve(batch.designs({"zeta": np.array([lifter.stop.zeta])})[0], 1)
        >>> (solved.per_rpm * 300).round(4).tolist()   # [deg] at 300 rpm: its bound law's
        [[30.0291]]
        """
        ...

    def sweep_values(
        self, rpm: Array, angle_deg: Sequence[Array], fits: npt.NDArray[np.bool_]
    ) -> dict[str, Array]:
        """Its kind's ``sweep_columns`` for each design at each speed.

        :meth:`Mechanism.sweep_values` of the designs, computed from the batch.

        Parameters
        ----------
        rpm : ndarray of float, shape (D, S)
            The speeds of each design [rpm].
        angle_deg : sequence of ndarray of float, each shape (D·S,)
            Each of its bounds' operation angle at the optimum [deg].
        fits : ndarray of bool, shape (D·S,)
            Where the machine fits.

        Returns
        -------
        dict of str to ndarray
            Each of its sweep columns, a (D·S,) array.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.example()
        >>> lifter = m.mechanisms["lifter"]
        >>> batch = type(lifter).batch_designs(lifter, m.data["mechanism"]["lifter"], ["zeta"])
        >>> solved = batch.solve(batch.designs({"zeta": np.array([0.05])})[0], 1)
        >>> list(solved.sweep_values(np.array([[300.0]]), [np.array([40.0])], np.array([True])))
        ['max_rebound_m']
        """
        ...


class BatchDesigns(Protocol):
    """The designs of one mechanism that a sweep varies, in one batch.

    What a kind's optional hook ``batch_designs`` returns (see the Notes of
    :class:`Mechanism`): it builds the designs from the swept values and solves
    them, each step for every design at once.

    Parameters
    ----------
    *args, **kwargs
        None: a protocol takes no arguments (it cannot be instantiated).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> m = cm.Machine.example()
    >>> lifter = m.mechanisms["lifter"]
    >>> batch = type(lifter).batch_designs(lifter, m.data["mechanism"]["lifter"], ["preload_m"])
    >>> batch.designs({"preload_m": np.array([1e-4, 2e-4])})[1].tolist()
    [True, True]
    """

    def designs(self, values: Mapping[str, Array]) -> tuple[Array, npt.NDArray[np.bool_]]:
        """The designs' table and which designs its checks pass.

        Parameters
        ----------
        values : Mapping of str to ndarray of float
            Each swept key of the mechanism's table → its D values, in the file's
            units.

        Returns
        -------
        designs : ndarray of float, shape (P, D)
            The kind's table of the designs (designs along the last axis: the sweep
            keeps the columns of the designs every swept mechanism passed).
        ok : ndarray of bool, shape (D,)
            The designs it takes; the others go to the per-design path, whose
            reader names what is wrong with them.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.example()
        >>> lifter = m.mechanisms["lifter"]
        >>> batch = type(lifter).batch_designs(lifter, m.data["mechanism"]["lifter"], ["zeta"])
        >>> batch.designs({"zeta": np.array([0.05, -1.0])})[1].tolist()
        [True, False]
        """
        ...

    def solve(self, designs: Array, n_threads: int | None) -> BatchSolution:
        """Solve the designs (columns of :meth:`designs`' table that passed).

        Parameters
        ----------
        designs : ndarray of float, shape (P, D)
            The designs.
        n_threads : int or None
            Threads for the Rust kernels (None: ``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        BatchSolution
            Their bounds' slopes and sweep columns.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.example()
        >>> lifter = m.mechanisms["lifter"]
        >>> batch = type(lifter).batch_designs(lifter, m.data["mechanism"]["lifter"], ["zeta"])
        >>> batch.solve(batch.designs({"zeta": np.array([0.05, 0.1])})[0], 1).per_rpm.shape
        (2, 1)
        """
        ...


def efficiency_entry(
    nominal_rpm: float,
    torque: Array,
    torque_without: Array,
    friction_power: Array,
    input_power: Array,
    losses: Array,
    elements: Sequence[str],
    locked_deg: Array,
    cycle_efficiency: float | None = None,
) -> dict[str, Any]:
    """A mechanism result's ``efficiency()`` (the keys
    :func:`cyclomech.machine._efficiency.machine_efficiency` reads), from its friction
    over one turn at the nominal speed; NaN (a self-locking pose) becomes None.

    Parameters
    ----------
    nominal_rpm : float
        The nominal speed [rpm].
    torque, torque_without : ndarray of float, shape (N,)
        The driving torque with and without friction [N·m].
    friction_power, input_power : ndarray of float, shape (N,)
        The power lost to friction and put in [W].
    losses : ndarray of float, shape (N, E)
        Each friction element's power [W].
    elements : sequence of str
        The elements' names (E).
    locked_deg : ndarray of float
        The angles where it self-locks [deg].
    cycle_efficiency : float, optional
        The efficiency over the turn; default 1 − mean friction power / mean input
        power (NaN where the input is not positive).

    Returns
    -------
    dict of str to Any
        ``nominal_rpm``, ``cycle_efficiency``, ``mean_friction_power_w``,
        ``mean_input_power_w``, ``mean_torque_nm``, ``peak_torque_nm``,
        ``peak_torque_nm_without``, ``friction_power_by_element_w`` and
        ``self_locking_crank_deg``.

    Examples
    --------
    >>> import numpy as np
    >>> e = efficiency_entry(60.0, np.full(4, 2.0), np.full(4, 1.8), np.full(4, 1.0),
    ...                      np.full(4, 10.0), np.ones((4, 1)), ["pin"], np.zeros(0))
    >>> round(e["cycle_efficiency"], 6), e["friction_power_by_element_w"]
    (0.9, {'pin': 1.0})
    """

    def finite(v: Any) -> float | None:
        x = float(v)
        return x if np.isfinite(x) else None

    p_f = float(np.mean(friction_power))
    p_in = float(np.mean(input_power))
    if cycle_efficiency is None:
        cycle_efficiency = 1.0 - p_f / p_in if p_in > 0.0 else float("nan")
    return {
        "nominal_rpm": nominal_rpm,
        "cycle_efficiency": finite(cycle_efficiency),
        "mean_friction_power_w": finite(p_f),
        "mean_input_power_w": finite(p_in),
        "mean_torque_nm": finite(np.mean(torque)),
        "peak_torque_nm": finite(np.max(torque)),
        "peak_torque_nm_without": float(np.max(torque_without)),
        "friction_power_by_element_w": {
            e: finite(np.mean(losses[:, i])) for i, e in enumerate(elements)
        },
        "self_locking_crank_deg": [float(v) for v in locked_deg],
    }
