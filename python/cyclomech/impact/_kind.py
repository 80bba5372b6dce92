"""The ``cam_stop`` mechanism kind of a machine file: a cam-driven lever that hits
its limit stop, and the cyclogram operation that brings it there (seed 000)."""

from __future__ import annotations

import functools
import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from .. import _keyrules, _toml
from .._arrays import flag, float_array, instance, instances, positive, real_array, threads_arg
from .._errors import InputError
from .._keydoc import KeyTable
from .._keyrules import Rule
from .._kind import Array, Bound, BoundLaw, Context, Proportional, Save, TableContext
from .._scene import Scene, cycle_angles
from ..cyclogram import Arc, Constraint
from ._batch import StopBatch, stop_batch
from ._keys import KEY_DOCS
from ._stop import StopImpact, max_impact_speeds, rebounds
from ._study import _STOP_KEYS, A_MAX_RULES, STOP_PARAMS, STOP_RULES, _stop_from_table

__all__ = ["CamStop"]

#: Relative bracket of the stops' largest impact speeds: min_phase_angle's default
#: 1e-9° over at most 360°.
_STOP_RTOL = 1e-9 / 360.0


@dataclass(frozen=True)
class CamStop:
    """A cam-driven lever that hits a limit stop (seed 000), and the operation that brings it there.

    At n rpm the phase angle of the cyclogram's operation ``arc`` must keep the
    first rebound within ``a_max``. The ``cam_stop`` kind of a machine file, read
    by :meth:`from_table` (its keys say their units: ``a_max_m``, ``stroke_m``,
    ``preload_m``, …); each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The mechanism's name in the machine file.
    stop : StopImpact
        The lever with its stop.
    arc : tuple of (str, str)
        The cyclogram operation (from, to) that brings the lever to the stop.
    a_max : float
        The rebound limit [m].
    phase_deg : ndarray of float
        The phase angles [deg] drawn in the report's rebound curves.

    Attributes
    ----------
    kind : str
        ``"cam_stop"``, the ``kind`` key of its table.
    keys : frozenset of str
        The keys its table takes: a stop's (``stroke_m``, ``preload_m``, …, each
        setting the :class:`StopImpact` parameter of ``params``) plus ``kind``,
        ``arc``, ``a_max_m``, ``phase_deg`` and ``cam``.
    params : dict of str to str
        Each key that sets a :class:`StopImpact` parameter or ``a_max``, and that
        parameter's name (``"preload_m": "preload"``).
    rules : tuple of Rule
        Its plausibility rules (a value implausible for its unit warns): a
        rebound limit not below the stroke is an error, a damping ratio ζ ≥ 1 a
        warning.
    fixed_keys : frozenset of str
        The keys a sweep may not vary (``kind``, ``arc``, ``cam``).
    json_groups : tuple of str
        The groups of the machine's JSON results it adds to (``"stops"``).
    sweep_columns : tuple of str
        The columns it adds to a speed sweep (``"max_rebound_m"``).

    Examples
    --------
    >>> import cyclomech as cm
    >>> lifter = cm.Machine.example().mechanisms["lifter"]
    >>> lifter.kind, lifter.arc, lifter.a_max
    ('cam_stop', ('3', '7'), 0.0001)
    """

    kind: ClassVar[str] = "cam_stop"
    # Its tables' keys, its own first, for the machine-file format reference
    # (cyclomech._keydocs renders them; tests/package/test_keydocs.py holds them to the parser).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS
    keys: ClassVar[frozenset[str]] = frozenset(
        (_STOP_KEYS - {"name"}) | {"kind", "arc", "a_max_m", "phase_deg", "cam"}
    )
    params: ClassVar[dict[str, str]] = {
        **{k: p for k, p in STOP_PARAMS.items() if k not in ("name", "law", "pulse", "model")},
        "a_max_m": "a_max",
    }
    rules: ClassVar[tuple[Rule, ...]] = (*STOP_RULES, *A_MAX_RULES)
    fixed_keys: ClassVar[frozenset[str]] = frozenset({"kind", "arc", "cam"})

    @classmethod
    def sweep_refuses(cls, table: Mapping[str, Any]) -> dict[str, str]:
        """Keys this table takes in general but a sweep may not set here, with why.

        A stop that names its cam takes ``law`` and ``stroke_m`` from it.

        Parameters
        ----------
        table : mapping of str to Any
            The mechanism's table as read from the file.

        Returns
        -------
        dict of str to str
            Each refused key and the reason (empty if the table names no cam).

        Examples
        --------
        >>> CamStop.sweep_refuses({"cam": "lifter cam"})["stroke_m"]
        "it comes from the cam 'lifter cam'"
        >>> CamStop.sweep_refuses({"stroke_m": 0.009})
        {}
        """
        _toml.must_be_table(table, None, "table")
        if "cam" not in table:
            return {}
        return {k: f"it comes from the cam {table['cam']!r}" for k in ("law", "stroke_m")}

    @classmethod
    def batch_designs(
        cls, mechanism: CamStop, table: Mapping[str, Any], keys: Collection[str]
    ) -> StopBatch | None:
        """The kind's batch path for sweeps (the optional hook of
        :class:`~cyclomech.machine.Mechanism`): the designs of ``mechanism`` that vary
        ``keys`` in one Rust call per chunk, or None when the sweep must build one
        machine per design (a contact-model or half-sine stop, a key that is not a
        number of the stop, the stroke or lever of a stop that names its cam).

        Parameters
        ----------
        mechanism : CamStop
            The machine's stop.
        table : Mapping of str to Any
            Its table as read.
        keys : collection of str
            The keys of its table the sweep varies.

        Returns
        -------
        StopBatch or None
            The batch (its ``designs`` and ``solve``: every design's stop in one
            Rust call), or None.

        Raises
        ------
        InputError
            If ``keys`` is not a collection of str.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.example()
        >>> table = m.data["mechanism"]["lifter"]
        >>> CamStop.batch_designs(m.mechanisms["lifter"], table, ["preload_m"]) is not None
        True
        >>> CamStop.batch_designs(m.mechanisms["lifter"], table, ["phase_deg"]) is None
        True
        >>> CamStop.batch_designs(m.mechanisms["lifter"], table, "preload_m")
        Traceback (most recent call last):
        cyclomech._errors.InputError: keys must be a collection of its table's keys; got 'preload_m'
        """
        m = instance("mechanism", mechanism, cls)
        table = instance("table", table, Mapping)
        if isinstance(keys, str) or not isinstance(keys, Collection):
            raise InputError(f"keys must be a collection of its table's keys; got {keys!r}")
        if not all(isinstance(k, str) for k in keys):
            raise InputError(f"keys must be its table's keys (str); got {keys!r}")
        return stop_batch(m.stop, m.a_max, cls.params, table, keys)

    json_groups: ClassVar[tuple[str, ...]] = ("stops",)
    sweep_columns: ClassVar[tuple[str, ...]] = ("max_rebound_m",)
    name: str
    stop: StopImpact
    arc: Arc
    a_max: float
    phase_deg: Array

    def __post_init__(self) -> None:
        # Built directly too, not only from a file: the same rule for its numbers.
        instance("stop", self.stop, StopImpact)
        object.__setattr__(self, "a_max", positive("a_max", self.a_max, "[m]"))
        phase = real_array("phase_deg", self.phase_deg, "[deg]", low=0.0, strict=True)
        object.__setattr__(self, "phase_deg", phase)

    # ------------------------------------------------------------- the file
    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> CamStop:
        """A cam stop from its ``[mechanism.<name>]`` table.

        The table holds the keys of a stop (``params``: those of
        :class:`~cyclomech.impact.StopImpact` with their units, ``stroke_m``,
        ``preload_m``, …) plus ``arc`` (the operation's two events), ``a_max_m`` [m]
        and optionally ``phase_deg = [from, to, count]`` [deg]; or, with ``cam =
        "<name>"``, the law and stroke from that cam's rise on the arc (a ``kind =
        "cam"`` mechanism of the machine; an oscillating follower's rotation times
        ``lever_length_m``). The values are then checked against ``rules``.

        Parameters
        ----------
        name : str
            The mechanism's name.
        table : mapping of str to Any
            Its table as read from the file.
        ctx : TableContext
            The machine's cyclogram (the arc must be one of its operations), the file's
            name for messages and the machine's other tables.

        Returns
        -------
        CamStop
            The mechanism.

        Raises
        ------
        InputError
            If a key is missing or unknown, a value is malformed or out of range, the
            arc is not an operation of the cyclogram, the named cam has no rise on
            the arc (or ``law`` or ``stroke_m`` is given besides it), a key has its old
            name (``a_max`` for ``a_max_m``), or the rebound limit is not below the
            stroke.

        Warns
        -----
        CyclomechWarning
            If a value is unusual (ζ ≥ 1; see ``rules``).

        Examples
        --------
        >>> import cyclomech as cm
        >>> spec = cm.Machine.example().data["mechanism"]["lifter"]
        >>> ctx = TableContext(cm.Machine.example().cyclogram, "<doc>", 361)
        >>> CamStop.from_table("lifter", spec, ctx).phase_deg.tolist()
        [20.0, 30.0, 40.0, 50.0, 60.0]
        """
        instance("ctx", ctx, TableContext)  # a dict or a str: TypeError by name
        where = ctx.where(name)
        _toml.check_keys(table, set(cls.keys), ctx.source, f"[mechanism.{name}]")
        _toml.require(table, ("arc", "a_max_m"), where)
        # The arc is checked against the cyclogram before the cam: an arc that is no
        # operation at all is the arc's mistake, not the cam's.
        known = [op.arc for op in ctx.cyclogram.operations]
        arc = _toml.operation(_toml.events(table, "arc", where, arc=True), "arc", where, known)
        if "cam" in table:
            table = {**table, **_from_cam(table, arc, where, ctx)}
        stop = _stop_from_table(
            table, where, skip=("kind", "arc", "a_max_m", "phase_deg", "cam"), rules=None
        )
        a_max = _toml.number(table, "a_max_m", where, "[m]")
        if a_max <= 0:
            raise InputError(f"{where}: a_max_m = {a_max!r} must be a positive rebound limit [m]")
        _keyrules.check(table, cls.rules, where)
        shown = {"phase_deg": table.get("phase_deg", [20.0, 60.0, 5])}
        grid = _toml.span(shown, "phase_deg", where, within=(0.0, 360.0), most=50, unit="deg")
        if grid[0] > grid[-1]:
            raise InputError(
                f"{where}: phase_deg = {shown['phase_deg']!r} must go up: [from, to, count] "
                "with from ≤ to (the phase angles [deg] of the report's rebound curves)"
            )
        return cls(name, stop, arc, a_max, grid)

    # ------------------------------------------------------------- its bound
    def min_phase_deg(self, rpm: npt.ArrayLike, *, n_threads: int | None = None) -> Array:
        """Exact smallest phase angle [deg] of the arc at each speed.

        :meth:`StopImpact.min_phase_angle`; NaN where even 360° is too short.

        Parameters
        ----------
        rpm : float or array_like of float
            The main shaft's speeds [rpm] (> 0).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        ndarray of float
            The smallest phase angle at each speed [deg] (0-d for a scalar speed).

        Examples
        --------
        >>> import cyclomech as cm
        >>> lifter = cm.Machine.example().mechanisms["lifter"]
        >>> round(float(lifter.min_phase_deg(280.0)), 4)
        28.0271
        """
        return np.asarray(
            self.stop.min_phase_angle(self.a_max, rpm, n_threads=n_threads), dtype=np.float64
        )

    def linear_min_phase_deg(
        self, rpm: npt.ArrayLike, *, points: int = 64, n_threads: int | None = None
    ) -> Array:
        """The seed's linearised smallest phase angle [deg] at each speed.

        :meth:`StopImpact.linear_min_phase_angle`.

        Parameters
        ----------
        rpm : float or array_like of float
            The main shaft's speeds [rpm] (> 0).
        points : int, default 64
            The number of phase angles each line is fitted to.
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        ndarray of float
            The linearised smallest phase angle at each speed [deg] (0-d for a scalar
            speed).

        Examples
        --------
        >>> import cyclomech as cm
        >>> lifter = cm.Machine.example().mechanisms["lifter"]
        >>> round(float(lifter.linear_min_phase_deg(280.0)), 2)     # exact: 28.03
        32.67
        """
        return np.asarray(
            self.stop.linear_min_phase_angle(self.a_max, rpm, points=points, n_threads=n_threads),
            dtype=np.float64,
        )

    def constraint(self, rpm: float, *, linear: bool = False) -> Constraint:
        """The cyclogram constraint at a speed, named ``rebound[<name>]``.

        Exact, or the seed's linearised form with ``linear=True``
        (:meth:`StopImpact.constraint`).

        Parameters
        ----------
        rpm : float
            The main shaft's speed [rpm].
        linear : bool, default False
            The seed's linearised form instead of the exact one.

        Returns
        -------
        Constraint
            The constraint on the arc's phase angle [deg].

        Raises
        ------
        InfeasibleError
            If the rebound stays above ``a_max`` for every phase angle up to 360°.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().mechanisms["lifter"].constraint(280.0).describe()
        '1·t(3,7) >= 28.0271'
        """
        c = self.stop.constraint(self.arc, self.a_max, rpm, linear=linear)
        return Constraint(c.coeffs, c.sense, c.rhs, self.bounds()[0].label)

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[Constraint, ...]:
        """Its bound at a speed as cyclogram constraints (:meth:`constraint`).

        Parameters
        ----------
        rpm : float
            The main shaft's speed [rpm].
        linear : bool, default False
            The seed's linearised form instead of the exact one.

        Returns
        -------
        tuple of Constraint
            The one constraint, named ``rebound[<name>]``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> [c.name for c in cm.Machine.example().mechanisms["lifter"].constraints(280.0)]
        ['rebound[lifter]']
        """
        return (self.constraint(rpm, linear=linear),)

    def bounds(self) -> tuple[Bound, ...]:
        """Its one bound: the rebound bound on its arc.

        Returns
        -------
        tuple of Bound
            The bound, labelled ``rebound[<name>]``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().mechanisms["lifter"].bounds()
        (Bound(arc=('3', '7'), label='rebound[lifter]', name='lifter'),)
        """
        return (Bound(self.arc, f"rebound[{self.name}]", self.name),)

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[BoundLaw]]:
        """Each stop's smallest phase angle [deg] at any speed, as a function of the speed.

        t_min = n·slope, the slopes of all the stops from one search for their largest
        impact speeds (the rebound depends on the impact speed alone, which grows as
        n/t); or the seed's linearised form, one fit per call.

        Parameters
        ----------
        mechanisms : sequence of CamStop
            The stops.
        linear : bool, default False
            The seed's linearised form instead of the exact one.
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        list of list of callable
            Per stop, its one bound law: speeds [rpm] (array) to the smallest phase
            angle [deg].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> lifter = cm.Machine.example().mechanisms["lifter"]
        >>> [[law]] = CamStop.bound_laws([lifter])
        >>> np.round(law(np.array([280.0, 300.0])), 4).tolist()
        [28.0271, 30.0291]
        """
        mechanisms = instances("mechanisms", mechanisms, cls)
        threads = threads_arg(n_threads)
        if flag("linear", linear):
            return [
                [functools.partial(m.linear_min_phase_deg, n_threads=threads)] for m in mechanisms
            ]
        if not mechanisms:
            return []
        v = max_impact_speeds(
            [m.stop for m in mechanisms],
            [m.a_max for m in mechanisms],
            rtol=_STOP_RTOL,
            n_threads=threads,
        )
        slopes = [m.stop.phase_per_rpm(x) for m, x in zip(mechanisms, v, strict=True)]
        return [[Proportional(k)] for k in slopes]

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
        """The speed sweep's ``max_rebound_m`` column: each stop's first rebound [m] at the optimum.

        The first rebound with its arc at the optimum's angle (its minimum there), one
        rebound call per pulse table; NaN where the machine does not fit.

        Parameters
        ----------
        mechanisms : sequence of CamStop
            The same stop in D designs.
        rpm : ndarray of float, shape (D, S)
            The speeds of each design [rpm].
        angle_deg : sequence of ndarray of float, shape (D·S,)
            The optimum's angle of the stop's arc at each design and speed [deg] (one
            array per bound; a stop has one).
        fits : ndarray of bool, shape (D·S,)
            Whether the machine fits at each design and speed.
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        dict of str to ndarray of float
            ``{"max_rebound_m": ...}``, the first rebound at each design and speed [m],
            shape (D·S,).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> lifter = cm.Machine.example().mechanisms["lifter"]
        >>> n = np.array([[300.0]])
        >>> t = [lifter.min_phase_deg(n.reshape(-1))]
        >>> a = CamStop.sweep_values([lifter], n, t, np.array([True]))["max_rebound_m"]
        >>> bool(abs(a[0] - lifter.a_max) < 1e-9)
        True
        """
        mechanisms = instances("mechanisms", mechanisms, cls)
        rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(2,))
        D, S = rpm.shape
        rows = rpm.reshape(-1)
        stops = [m.stop for m in mechanisms]
        # Impact speeds at the operation's angle t: the angle per rpm at 1 m/s is
        # phase_per_rpm(1), so v0 = n·that/t; 1 m/s where the machine does not fit
        # (dropped).
        per = np.repeat([s.phase_per_rpm(1.0) for s in stops], S)
        if isinstance(angle_deg, str | Mapping) or not isinstance(angle_deg, Sequence):
            raise TypeError(
                f"angle_deg must be a sequence of arrays (one a bound); got {angle_deg!r}"
            )
        if not len(angle_deg):
            raise InputError("angle_deg must hold the bounds' operation angles [deg]; got none")
        t = float_array("angle_deg[0]", angle_deg[0], ndims=None)
        v0 = np.where(fits, rows * per / np.where(fits, t, 1.0), 1.0)
        a = rebounds(stops, v0.reshape(D, S), n_threads=n_threads).reshape(-1)
        return {"max_rebound_m": np.where(fits, a, np.nan)}

    # ------------------------------------------------------------- its limit
    def speed_limit_rpm(self) -> float:
        """A stop limits the speed through the cyclogram only: inf here.

        Returns
        -------
        float
            ``inf`` [rpm].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().mechanisms["lifter"].speed_limit_rpm()
        inf
        """
        return math.inf

    def limit_reason(self) -> str:
        """Why it limits the speed: "" (see :meth:`speed_limit_rpm`).

        Returns
        -------
        str
            The empty string.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().mechanisms["lifter"].limit_reason()
        ''
        """
        return ""

    # ------------------------------------------------------------- results
    def analyze(self, ctx: Context) -> CamStopResult:
        """Its results at the machine's nominal speed and on the speed grid.

        Parameters
        ----------
        ctx : Context
            What the machine computed before: the nominal speed, the speed grid, the
            optimum and each bound's smallest angles.

        Returns
        -------
        CamStopResult
            Its largest admissible impact speed [m/s], its smallest phase angle [deg] at
            the nominal speed (exact and linearised) and on the speed grid, and its
            bound's shadow price per mm of ``a_max``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
        >>> round(r.nominal_rpm, 2), round(r.mechanisms["lifter"].min_phase_at_nominal, 4)
        (421.37, 42.1779)
        """
        instance("ctx", ctx, Context)
        bound = self.bounds()[0]
        label = bound.label
        n = ctx.nominal_rpm
        price = 0.0 if ctx.optimum is None else ctx.optimum.duals.get(label, 0.0)
        per_mm: dict[str, float] = {}
        if abs(price) > 1e-9:
            # Its LP price per degree of the bound, times dt_min/da_max by a central
            # difference (±0.1 % of a_max), per mm.
            h = 1e-3 * self.a_max
            up, down = (float(self.stop.min_phase_angle(self.a_max + d, n)) for d in (h, -h))
            per_mm[label] = price * (up - down) / (2.0 * h) * 1e-3
        return CamStopResult(
            mech=self,
            ctx=ctx,
            max_impact_speed=self.stop.max_impact_speed(self.a_max),
            min_phase_at_nominal=float(self.min_phase_deg(n)),
            linear_at_nominal=float(self.linear_min_phase_deg(n)),
            exact=ctx.bounds[bound.name],
            linear=ctx.linear_bounds[bound.name],
            per_mm=per_mm,
        )


@dataclass(frozen=True)
class CamStopResult:
    """A cam stop's results: its largest admissible impact speed [m/s], its
    smallest phase angle [deg] at the nominal speed (exact and linearised), on the
    speed grid (``exact``, ``linear``), and its bound's shadow price per mm of
    ``a_max`` (``per_mm``)."""

    mech: CamStop
    ctx: Context
    max_impact_speed: float
    min_phase_at_nominal: float
    linear_at_nominal: float
    exact: Array
    linear: Array
    per_mm: dict[str, float]

    def scene(self, cycle_deg: Array) -> Scene | None:
        """The lever and its stop at the main shaft's angles ``cycle_deg`` [deg], for
        the machine's animation: over its operation (timed by the optimum) the
        working point travels stroke·Z(u) until the stop holds it at
        stroke − preload; outside it the lever is not drawn (the stop's model
        covers the approach only), the stop always is.

        Parameters
        ----------
        cycle_deg : ndarray of float
            The main shaft's angles [deg].

        Returns
        -------
        Scene or None
            Lengths in m; None without an optimum.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> s = r.mechanisms["lifter"].scene(np.arange(0.0, 360.0, 30.0))
        >>> s.frames, s.links, sorted(s.bodies)
        (12, (('A', 'roller', 'W'),), ['stop'])
        """
        from ._scene import stop_scene

        return stop_scene(self, cycle_angles(cycle_deg))

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry and its ``stops`` entry."""
        s, st = self.mech, self.mech.stop
        return {
            "mechanisms": {"kind": "cam_stop", "arc": s.arc},
            "stops": {
                "arc": s.arc,
                "model": st.model,
                "law": st.law.name,
                "stroke_m": st.stroke,
                "preload_m": st.preload,
                "critical_speed_m_s": self.max_impact_speed,
                "linear_min_phase_deg_at_nominal": self.linear_at_nominal,
                "a_max_m": s.a_max,
                "omega_free_rad_s": st.omega_free,
                "omega_contact_rad_s": st.omega_contact,
                "min_phase_deg_at_nominal": self.min_phase_at_nominal,
                "speed_rpm": self.ctx.rpm,
                "min_phase_deg": self.exact,
                "linear_min_phase_deg": self.linear,
            },
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        s, st, n = self.mech, self.mech.stop, self.ctx.nominal_rpm
        model = (
            "pulse (the seed's: the free lever and the impact pulse)"
            if st.model == "pulse"
            else "contact (the stop as a unilateral spring, event by event)"
        )
        return ["quantity", "value"], [
            ["operation it constrains", f"{s.arc[0]}→{s.arc[1]}"],
            ["rebound model", model],
            ["cam law (rise)", st.law.name.replace("_", " ")],
            ["stroke [mm]", st.stroke * 1e3],
            ["preload (stop before the end of the stroke) [mm]", st.preload * 1e3],
            ["rebound limit [mm]", s.a_max * 1e3],
            ["free natural frequency [Hz]", st.omega_free / (2 * math.pi)],
            ["natural frequency in contact [Hz]", st.omega_contact / (2 * math.pi)],
            ["largest admissible impact speed [m/s]", self.max_impact_speed],
            [f"smallest phase angle at {n:g} rpm [deg]", self.min_phase_at_nominal],
            [f"the seed's linearised form at {n:g} rpm [deg]", self.linear_at_nominal],
        ]

    def csv_columns(self) -> list[tuple[str, Array]]:
        """Its smallest phase angles on the sweep's speeds, exact and linearised."""
        k = self.mech.name
        return [(f"min_phase_deg[{k}]", self.exact), (f"linear_min_phase_deg[{k}]", self.linear)]

    def prices(self) -> dict[str, float]:
        """Its bound's shadow price per mm of ``a_max`` [deg/mm] (where priced)."""
        return self.per_mm

    def figures(self, save: Save) -> None:
        """The rebound against speed, the cam law and the smallest phase angle."""
        from ..motion.plot import plot_law
        from .plot import plot_min_phase, plot_rebound_vs_speed

        k, mech, n = self.mech.name, self.mech, self.ctx.rpm
        save(
            plot_rebound_vs_speed(
                mech.stop,
                n,
                phase_deg=mech.phase_deg,
                a_max=mech.a_max,
                title=f"{k}: rebound at the stop",
            ),
            f"{k}_rebound",
            "Left: the lever's motion after it strikes the stop"
            + (
                " (pulse model: the stop acts only through the impact pulse, so q < 0, "
                "into the stop, is the model's free vibration, not the lever's)"
                if mech.stop.model == "pulse"
                else " (contact model: q < 0 is the stop's deflection under the lever)"
            )
            + "; right: the first rebound against speed for several phase angles, with "
            "the limit dashed.",
        )
        axes = plot_law(
            mech.stop.law, title=f"{k}: cam law ({mech.stop.law.name.replace('_', ' ')}, rise)"
        )
        for a in axes:
            a.axvline(mech.stop.j_contact, color="0.4", ls=":", lw=1.0)
        axes[0].annotate(
            "meets the stop",
            (mech.stop.j_contact, 0.5),
            xytext=(-6, 0),
            textcoords="offset points",
            ha="right",
            fontsize=8,
            color="0.3",
        )
        save(
            axes[0].figure,
            f"{k}_law",
            f"The cam's motion law over the arc {mech.arc[0]}→{mech.arc[1]}: Z, Z' and Z'' "
            f"(dimensionless) against the fraction j of the phase angle; the lever meets "
            f"the stop at j = {mech.stop.j_contact:.3f} (dotted), Z' = "
            f"{mech.stop.dz_contact:.3f} there sets the impact speed.",
        )
        ax = plot_min_phase(
            n,
            self.exact,
            self.linear,
            minimum_deg=self.ctx.cyclogram.operation(mech.arc).min_angle_deg,
            title=f"{k}: smallest phase angle of {mech.arc[0]}→{mech.arc[1]}",
        )
        save(
            ax.figure,
            f"{k}_min_phase",
            "The smallest phase angle of the operation that keeps the rebound within its "
            "limit: exact and the seed's linearised form.",
        )


def _from_cam(table: Mapping[str, Any], arc: Arc, where: str, ctx: TableContext) -> dict[str, Any]:
    """``law`` and ``stroke_m`` of a cam stop that names its cam (``cam = "<name>"``, a
    ``kind = "cam"`` mechanism of the machine): the law of the cam's rise bound to
    the stop's arc, and its stroke at the working point [m] (an oscillating
    follower's rotation times ``lever_length_m``). One description of the motion,
    not two: giving ``law`` or ``stroke_m`` as well is an error."""
    from ..cam import CamDesign, OscillatingRoller

    name = table["cam"]
    twice = sorted(k for k in ("law", "stroke_m") if k in table)
    if twice:
        raise InputError(
            f"{where}: {twice[0]} comes from the cam {name!r}; give either cam or law and stroke"
        )
    other = ctx.tables.get(name) if isinstance(name, str) else None
    if not isinstance(other, Mapping) or other.get("kind") != "cam":
        cams = sorted(
            k for k, v in ctx.tables.items() if isinstance(v, Mapping) and v.get("kind") == "cam"
        )
        raise InputError(
            f"{where}: cam = {name!r} is not a cam of the machine; its cams are {cams}"
        )
    # The cam is a mechanism of the machine and warns of its own values (a length
    # in mm, an angle in radians) when it is read as one: not again here.
    design = CamDesign.from_table(
        other,
        f"[mechanism.{name}]",
        source=ctx.source,
        extra=frozenset({"kind", "friction"}),
        arcs=True,
        check=False,
    )
    if arc not in design.arcs:
        bound = ", ".join(repr(list(a)) for a in design.arcs if a is not None) or "none"
        raise InputError(
            f"{where}: the cam {name!r} has no segment bound to the stop's arc {list(arc)!r} "
            f"(an operation of the cyclogram; the cam's segments are bound to {bound}); give "
            f"the cam's rise on it arc = {list(arc)!r} in [mechanism.{name}]"
        )
    seg = design.cam.segments[design.arcs.index(arc)]
    if seg.kind != "rise":
        raise InputError(
            f"{where}: the cam {name!r}'s segment on {list(arc)!r} is a {seg.kind}; a stop is "
            "met at the end of a rise"
        )
    stroke = seg.stroke
    if isinstance(design.cam.follower, OscillatingRoller):
        if "lever_length_m" not in table:
            raise InputError(f"{where}: missing key 'lever_length_m'")
        lever = _toml.number(table, "lever_length_m", where, "[m]")
        if not lever > 0:
            # Checked here, before it scales the cam's stroke: else the error would
            # name the derived stroke, not the key the user wrote.
            raise InputError(f"{where}: lever_length_m = {lever!r} must be finite and > 0 [m]")
        stroke *= lever
    return {"law": seg.law, "stroke_m": stroke}
