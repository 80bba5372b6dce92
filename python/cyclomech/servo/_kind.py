"""The ``servo`` mechanism kind of a machine file: a servo axis whose master is the
machine's (virtual) main shaft, its rest-to-rest segments bound to cyclogram
operations by what the motor can do (issue 33, items 3 and 5).

**Bounds.** Each segment with ``arc = [from, to]`` (a rest-to-rest rise or return:
its shape scales with its angle) puts lower bounds on its operation: the motor's
peak torque and maximum speed (:meth:`ServoAxis.min_phase_angles`), exactly
proportional to the machine's speed (the torque is linear in (ω/β)² and the speed
in ω/β), so the cyclogram's speed limit treats them as the cam's jump bound; and,
when it is the axis's one bound segment with a dwell after it, the RMS torque
(``cyclomech._core.servo_rms_angles``: exact, the dwell taking up its change, solved
per speed). **Own speed limit.** The segments without an arc keep their shape and
angle (a constant velocity, moving ends, a dwell holding the load): the highest
speed at which the motor's peak torque and maximum speed hold on them, and its RMS
when no segment is bound (:func:`cyclomech._core.servo_speed_limit`, the bounds'
rule: every lower speed holds too). The reason names the motor. **Failures.** A
check that fails at the nominal speed on the optimised timing (the RMS with several
bound segments, the inertia ratio) warns and makes ``cyclomech run`` exit 3
(:meth:`ServoResult.failures`). A servo's torque does not load the main shaft: its
motor has its own drive.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from .. import _core, _keyrules, _toml
from .._arrays import count, finite_number, instance, instances, real_array
from .._errors import InputError
from .._keydoc import KeyTable
from .._kind import (
    Bound,
    BoundLaw,
    Context,
    ExactBounds,
    Phase,
    Proportional,
    TableContext,
    per_distinct_speed,
)
from .._units import RAD_PER_S_PER_RPM
from ..cam import UNITS, read_program, read_segments
from ..cyclogram import Arc
from ..motion import Program
from ._axis import DEFAULT_INERTIA_LIMIT, ServoAxis
from ._catalogue import load_catalogue
from ._keys import KEY_DOCS
from ._parts import Gearbox, LinearLoad, Motor, RotaryLoad

__all__ = ["ServoMechanism"]

#: How each bound's criterion reads in labels and reasons.
WORDS = {"peak_torque": "peak torque", "speed": "motor speed", "rms_torque": "RMS torque"}
#: The keys of a ``motor = {…}`` table.
MOTOR_KEYS = frozenset(
    {"rated_torque_nm", "peak_torque_nm", "rated_rpm", "max_rpm", "inertia_kg_m2", "name"}
)
_LINEAR = frozenset({"mass_kg", "lead_m", "force_n", "drive_efficiency", "advance_m"})
_ROTARY = frozenset({"inertia_kg_m2", "torque_nm", "advance_deg"})
#: Every key of a servo table.
SERVO_KEYS = frozenset(
    {"kind", "load", "segment", "motor", "catalogue", "gear_ratios", "continuity"}
    | {"gear_ratio", "gear_efficiency", "gear_inertia_kg_m2", "inertia_ratio_limit"}
    | {"table_points", "phase", "torque_reserve"}
    | _LINEAR
    | _ROTARY
)


def _number(table: Mapping[str, Any], key: str, at: str, default: float) -> float:
    return _toml.number(table, key, at, "") if key in table else default


@dataclass(frozen=True)
class ServoMechanism(ExactBounds):
    """A servo axis on the machine's master whose rest-to-rest segments bound operations.

    Built by :meth:`from_table`; each parameter is kept as the attribute of the
    same name. A bound is labelled ``<criterion>[<name> (<motor>) <kind>
    <from>→<to>]`` (criterion "peak torque" or "motor speed"), so the speed limit's
    reason names the motor when it binds.

    Parameters
    ----------
    name : str
        The mechanism's name.
    axis : ServoAxis
        The axis as the file lays it out (its motor None when only a catalogue is
        given).
    rows : tuple of dict
        The ``segment`` rows as read (the program is rebuilt from them at the
        optimum's angles).
    arcs : tuple of (tuple of (str, str)) or None
        Each segment's operation, or None.
    catalogue : tuple of Motor
        The motors to size from (empty without ``catalogue``).
    ratios : tuple of float
        The gear ratios the sizing tries.
    table_points : int
        Steps over the cycle of the cam table.
    family : str
        The ``segment`` rows' unit family, a key of :data:`cyclomech.cam.UNITS`
        (``"linear"`` for a linear load, ``"angular"`` for a rotary one).
    program_keys : dict
        ``continuity`` and ``advance`` as the file gives them (with ``family``,
        what :func:`cyclomech.cam.read_program` needs to rebuild the program).
    phase : Phase or None, optional
        Where the program's master angle 0 sits in the cycle when no segment is
        bound (``phase = {event, crank_deg}``: the program's angle at that event);
        default None (the first bound segment starts at its operation's start, or
        the program starts at cycle angle 0).
    torque_reserve : float, default 0.0
        The fraction of the motor's torques kept back, in [0, 1) (the motor and
        catalogue are already derated by it; kept for the report).

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.from_toml("examples/flow_wrapper.toml")
    >>> feed = m.mechanisms["film feed"]
    >>> feed.kind, [b.label for b in feed.bounds()][0]
    ('servo', 'peak torque[film feed (AC-060-127) rise 2→3]')
    """

    kind: ClassVar[str] = "servo"
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS
    keys: ClassVar[frozenset[str]] = SERVO_KEYS
    fixed_keys: ClassVar[frozenset[str]] = frozenset(
        {"kind", "load", "segment", "motor", "catalogue", "gear_ratios", "continuity"}
        | {"table_points", "phase"}
    )
    #: Sub-tables and lists whose numbers a sweep or a sensitivity may vary by a
    #: path (``segment.1.stroke_m``, ``phase.crank_deg``); not the catalogue's.
    varied_tables: ClassVar[frozenset[str]] = frozenset({"segment", "phase"})
    json_groups: ClassVar[tuple[str, ...]] = ("servo_axes",)
    name: str
    axis: ServoAxis
    rows: tuple[dict[str, Any], ...]
    arcs: tuple[Arc | None, ...]
    catalogue: tuple[Motor, ...]
    ratios: tuple[float, ...]
    table_points: int
    family: str
    program_keys: dict[str, Any] = field(default_factory=dict)
    phase: Phase | None = None
    torque_reserve: float = 0.0

    def __post_init__(self) -> None:
        # Built by from_table; checked here too, as a constructor's arguments.
        instance("name", self.name, str)
        instance("axis", self.axis, ServoAxis)
        rows = tuple(instances("rows", self.rows, dict))
        arcs = tuple(self.arcs) if isinstance(self.arcs, list | tuple) else None
        if arcs is None or len(arcs) != len(rows) or len(rows) != len(self.axis.program.segments):
            raise InputError(
                "rows and arcs must have one entry per segment of the axis's program; got "
                f"{self.rows!r:.60} and {self.arcs!r:.60}"
            )
        catalogue = tuple(instances("catalogue", self.catalogue, Motor))
        ratios = real_array("ratios", self.ratios, "(gear ratios)", low=0.0, strict=True)
        if ratios.ndim != 1 or ratios.size == 0:
            raise InputError(f"ratios must hold at least one gear ratio; got {self.ratios!r}")
        points = count("table_points", self.table_points, low=2, high=10**7)
        if not isinstance(self.family, str) or self.family not in UNITS:
            raise InputError(f"family = {self.family!r} must be one of {', '.join(UNITS)}")
        instance("program_keys", self.program_keys, dict)
        if self.phase is not None:
            instance("phase", self.phase, Phase)
        reserve = finite_number("torque_reserve", self.torque_reserve, "(fraction)")
        if not 0.0 <= reserve < 1.0:
            raise InputError(f"torque_reserve = {reserve!r} must be in [0, 1)")
        for key, value in (
            ("rows", rows),
            ("arcs", arcs),
            ("catalogue", catalogue),
            ("ratios", tuple(float(x) for x in ratios)),
            ("table_points", points),
            ("torque_reserve", reserve),
        ):
            object.__setattr__(self, key, value)

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> ServoMechanism:
        """Its ``[mechanism.<name>]`` table (the keys in the format reference).

        Parameters
        ----------
        name : str
            The mechanism's name.
        table : Mapping of str to Any
            Its table as read.
        ctx : TableContext
            The machine's cyclogram and file name.

        Returns
        -------
        ServoMechanism
            The axis.

        Raises
        ------
        InputError
            If a key is unknown or for the other kind of load, a value is invalid,
            neither ``motor`` nor ``catalogue`` is given, the motor is not in the
            catalogue, the cyclogram's ``cycle_deg`` is not 360, or an ``arc`` is not
            an operation, is bound twice or sits on a segment whose shape does not
            scale with its angle.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/flow_wrapper.toml")
        >>> m.mechanisms["jaw"].axis.load
        RotaryLoad(inertia_kg_m2=0.4, torque_nm=0.4)
        """
        instance("ctx", ctx, TableContext)
        at = ctx.where(name)
        _toml.check_keys(table, set(SERVO_KEYS), ctx.source, f"[mechanism.{name}]")
        _toml.require(table, ("load", "segment"), at)
        load_kind = table["load"]
        if load_kind not in ("linear", "rotary"):
            raise InputError(f"{at}: load = {load_kind!r} must be one of 'linear', 'rotary'")
        linear = load_kind == "linear"
        wrong = sorted(k for k in table if k in (_ROTARY if linear else _LINEAR))
        if wrong:
            mine = ", ".join(sorted(_LINEAR if linear else _ROTARY))
            raise InputError(
                f"{at}: {wrong[0]} is for a {'rotary' if linear else 'linear'} load; a "
                f"{load_kind} load takes {mine}"
            )
        if not math.isclose(ctx.cyclogram.cycle_deg, 360.0):
            raise InputError(
                f"{at}: a servo axis's master turns once per cycle, so the cyclogram's "
                f"cycle_deg must be 360; it is {ctx.cyclogram.cycle_deg!r}"
            )
        try:
            load = _load(table, at, linear)
            gearbox = Gearbox(
                _number(table, "gear_ratio", at, 1.0),
                _number(table, "gear_efficiency", at, 1.0),
                _number(table, "gear_inertia_kg_m2", at, 0.0),
            )
        except InputError as e:
            msg = _file_key(str(e))
            raise InputError(msg if msg.startswith(at) else f"{at}: {msg}") from None
        catalogue, motor = _motor(table, at, ctx.source)
        reserve, (catalogue, motor) = _reserved(table, at, catalogue, motor)
        ratios = _ratios(table, at, gearbox.ratio, bool(catalogue))
        limit = _number(table, "inertia_ratio_limit", at, DEFAULT_INERTIA_LIMIT)
        points = int(_number(table, "table_points", at, 3600))
        if table.get("table_points", 3600) != points or not 2 <= points <= 10**7:
            raise InputError(
                f"{at}: table_points = {table.get('table_points')!r} must be an integer in [2, 10⁷]"
            )
        units = UNITS["linear" if linear else "angular"]
        rows = table["segment"]
        keys = {"continuity": table.get("continuity", "velocity")}
        keys["advance"] = _number(table, "advance_m" if linear else "advance_deg", at, 0.0)
        try:
            program, arcs = _program(rows, units, keys)
            axis = ServoAxis(program, load, gearbox, motor, inertia_ratio_limit=limit)
        except InputError as e:
            raise InputError(f"{at}: {e}") from None
        _keyrules.check(table, (), at)
        _check_arcs(program, arcs, ctx, at)
        phase = None
        if "phase" in table:
            if any(a is not None for a in arcs):
                raise InputError(
                    f"{at}: phase is for an axis without bound segments; its segment "
                    "with an arc starts at its operation's start"
                )
            phase = Phase.from_table(table, ctx, name)
        return cls(
            name,
            axis,
            tuple(dict(r) for r in rows),
            arcs,
            catalogue,
            ratios,
            points,
            "linear" if linear else "angular",
            keys,
            phase,
            reserve,
        )

    # ------------------------------------------------------------- its program
    def program_at(self, angles: Mapping[Arc, float]) -> tuple[Program, str]:
        """The program with each bound segment at its operation's angle.

        As a cam's layout: the difference is taken from the next dwell
        (cyclically).

        Parameters
        ----------
        angles : Mapping of tuple of (str, str) to float
            The operations' angles [deg] (the optimum's), by arc.

        Returns
        -------
        program : Program
            The program laid out; the file's when that leaves no dwell or it is
            invalid.
        reason : str
            Why the file's program is returned ("" when laid out).

        Examples
        --------
        >>> import cyclomech as cm
        >>> feed = cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["film feed"]
        >>> p, why = feed.program_at({("2", "3"): 100.0})
        >>> [round(g.angle_deg, 6) for g in p.segments], why
        ([100.0, 20.0, 60.0, 60.0, 60.0, 60.0], '')
        """
        instance("angles", angles, Mapping)
        rows = [dict(r) for r in self.rows]
        n = len(rows)
        for k, arc in enumerate(self.arcs):
            if arc is None or arc not in angles:
                continue
            delta = float(angles[arc]) - float(rows[k]["angle_deg"])
            j = next((i % n for i in range(k + 1, k + n) if rows[i % n]["kind"] == "dwell"), None)
            if j is None or float(rows[j]["angle_deg"]) - delta <= 0.0:
                return self.axis.program, (
                    f"segment {k + 1} at {angles[arc]:.4g}° leaves no dwell to take up "
                    f"{delta:+.4g}°: shown with the file's angles"
                )
            rows[k]["angle_deg"] = float(angles[arc])
            rows[j]["angle_deg"] = float(rows[j]["angle_deg"]) - delta
        try:
            return _program(rows, UNITS[self.family], self.program_keys)[0], ""
        except InputError as e:
            return self.axis.program, f"the program at the optimum's angles is invalid ({e})"

    def phase_deg(self, times: Mapping[str, float], program: Program | None = None) -> float:
        """The cycle angle [deg] of the program's master angle 0 (the drive's offset).

        The first bound segment starts at its operation's start event; without
        one, ``phase`` places the program; without that, 0.

        Parameters
        ----------
        times : Mapping of str to float
            The optimum's event times [deg].
        program : Program, optional
            The program laid out (its segments' angles); default the file's.

        Returns
        -------
        float
            The angle [deg], in [0, 360).

        Examples
        --------
        >>> import cyclomech as cm
        >>> feed = cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["film feed"]
        >>> feed.phase_deg({"2": 82.5})
        82.5
        """
        instance("times", times, Mapping)
        program = self.axis.program if program is None else instance("program", program, Program)
        k = next((i for i, a in enumerate(self.arcs) if a is not None), None)
        arc = None if k is None else self.arcs[k]
        event = arc[0] if arc is not None else (self.phase.event if self.phase else None)
        if event is not None and event not in times:
            raise InputError(f"times has no event {event!r}: give the optimum's times")
        if arc is not None:
            at = float(times[arc[0]]) - sum(g.angle_deg for g in program.segments[:k])
        elif self.phase is not None:
            at = self.phase.shift_deg(times)
        else:
            at = 0.0
        return at % 360.0

    # ------------------------------------------------------------- its bounds
    def _bound_segments(self) -> tuple[int, ...]:
        return tuple(k for k, a in enumerate(self.arcs) if a is not None)

    def _where(self, k: int) -> str:
        arc = self.arcs[k]
        assert arc is not None
        motor = self.axis.motor
        who = "motor" if motor is None else (motor.name or "motor")
        return f"{self.name} ({who}) {self.rows[k]['kind']} {arc[0]}→{arc[1]}"

    def _rms_dwell(self) -> int | None:
        """The dwell that takes up the bound segment's change when the RMS is a
        bound (one bound segment, a dwell after it: module docs), else None."""
        segs = self._bound_segments()
        if self.axis.motor is None or len(segs) != 1:
            return None
        k, n = segs[0], len(self.rows)
        return next(
            (i % n for i in range(k + 1, k + n) if self.rows[i % n]["kind"] == "dwell"), None
        )

    def criteria(self) -> tuple[str, ...]:
        """The criteria of each bound segment, in the order of :meth:`bounds`.

        The motor's peak torque and maximum speed; and its RMS torque when the
        axis has one bound segment with a dwell after it (the RMS couples the
        cycle: exact for one segment whose change a dwell takes up).

        Returns
        -------
        tuple of str
            Of ``("peak_torque", "speed", "rms_torque")``; empty without a motor.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["film feed"].criteria()
        ('peak_torque', 'speed', 'rms_torque')
        """
        if self.axis.motor is None:
            return ()
        rms = ("rms_torque",) if self._rms_dwell() is not None else ()
        return (*_core.SERVO_BOUNDS, *rms)

    def bounds(self) -> tuple[Bound, ...]:
        """The bounds of each bound segment, one per criterion (:meth:`criteria`).

        None without a motor (a catalogue only: the axis is sized on the timing,
        it does not bound it).

        Returns
        -------
        tuple of Bound
            Labelled ``<criterion>[<name> (<motor>) <kind> <from>→<to>]``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> feed = cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["film feed"]
        >>> [b.label for b in feed.bounds()][1]
        'motor speed[film feed (AC-060-127) rise 2→3]'
        """
        out = []
        for k in self._bound_segments():
            arc = self.arcs[k]
            assert arc is not None
            for c in self.criteria():
                label = f"{WORDS[c]}[{self._where(k)}]"
                out.append(Bound(arc, label, label))
        return tuple(out)

    @functools.cached_property
    def _laws(self) -> tuple[BoundLaw, ...]:
        # The peak torque and speed are proportional to the speed (module docs):
        # their angle at 1 rpm is the law's slope; NaN (even the static torque
        # exceeds the peak) is an infinite bound, as a cam's. The RMS is solved
        # at each speed asked.
        segs = self._bound_segments()
        if self.axis.motor is None or not segs:
            return ()
        per = self.axis.min_phase_angles([1.0], segments=segs).angle_deg[0]
        out: list[BoundLaw] = []
        for j, k in enumerate(segs):
            out += [Proportional(math.inf if math.isnan(v) else float(v)) for v in per[j]]
            dwell = self._rms_dwell()
            if dwell is not None:
                out.append(_RmsLaw(self.axis, k, dwell))
        return tuple(out)

    def laws(self) -> list[BoundLaw]:
        """Each bound's smallest angle [deg] against speed [rpm].

        Proportional for the peak torque and speed (exact), solved per speed for
        the RMS torque.

        Returns
        -------
        list of BoundLaw
            One law per bound, in the order of :meth:`bounds`.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> feed = cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["film feed"]
        >>> [round(float(law(np.array([100.0]))[0]), 3) for law in feed.laws()]
        [51.327, 34.89, 46.011]
        """
        return list(self._laws)

    @functools.cached_property
    def _own_limit(self) -> tuple[float, str]:
        motor, ax = self.axis.motor, self.axis
        free = [k for k, a in enumerate(self.arcs) if a is None]
        if motor is None or not free:
            return math.inf, ""
        limits = _core.servo_speed_limit(
            ax.program.kernel,
            free,
            *ax._drive(motor, ax.gearbox),
            motor.peak_torque_nm,
            motor.max_rpm * RAD_PER_S_PER_RPM,
            motor.rated_torque_nm,
            len(free) == len(self.arcs),  # the RMS: over the whole cycle only
        )
        rpm = min(limits) / RAD_PER_S_PER_RPM
        if math.isinf(rpm):
            return rpm, ""
        who = f"motor {motor.name!r}" if motor.name else "the motor"
        where = ", ".join(f"{i + 1} ({self.axis.program.segments[i].law})" for i in free)
        c = int(np.argmin(limits))
        if rpm == 0.0:
            what = ("peak", motor.peak_torque_nm) if c == 0 else ("rated", motor.rated_torque_nm)
            why = (
                f"{who} cannot hold the load: its static torque exceeds the {what[0]} torque "
                f"{what[1]:g} N·m"
            )
        else:
            what_ = (
                f"its peak torque {motor.peak_torque_nm:g} N·m",
                f"its maximum speed {motor.max_rpm:g} rpm",
                f"its rated torque {motor.rated_torque_nm:g} N·m by the RMS over the cycle",
            )[c]
            why = f"{who} reaches {what_} on the segments no operation times: {where}"
        return rpm, why

    def speed_limit_rpm(self) -> float:
        """The highest speed [rpm] its segments without an operation allow (module docs).

        Returns
        -------
        float
            The speed [rpm]; inf without a motor or where nothing binds.

        Examples
        --------
        >>> import cyclomech as cm
        >>> jaw = cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["jaw"]
        >>> round(jaw.speed_limit_rpm(), 2)
        137.59
        """
        return self._own_limit[0]

    def limit_reason(self) -> str:
        """Why :meth:`speed_limit_rpm` is what it is: the motor and the check.

        Returns
        -------
        str
            "" where it has no limit.

        Examples
        --------
        >>> import cyclomech as cm
        >>> jaw = cm.Machine.from_toml("examples/flow_wrapper.toml").mechanisms["jaw"]
        >>> jaw.limit_reason()[:38]
        "motor 'AC-130-955' reaches its rated t"
        """
        return self._own_limit[1]

    def analyze(self, ctx: Context) -> Any:
        """Its results at the nominal speed: the duty, the sizing and the cam tables.

        The program is laid out at the optimum's angles. A
        :class:`cyclomech.CyclomechWarning` lists what fails at the nominal speed
        (:meth:`ServoResult.problems`).

        Parameters
        ----------
        ctx : Context
            What the machine computed before.

        Returns
        -------
        ServoResult
            Its results.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/flow_wrapper.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> r.mechanisms["film feed"].duty.status
        'ok'
        """
        from ._result import ServoResult

        instance("ctx", ctx, Context)
        return ServoResult.of(self, ctx)


def _file_key(text: str) -> str:
    """A part's message in the file's keys (a Gearbox says ``ratio``)."""
    for word, key in (
        ("ratio =", "gear_ratio ="),
        ("efficiency =", "gear_efficiency ="),
        ("inertia_kg_m2 =", "gear_inertia_kg_m2 ="),
    ):
        if text.startswith(word):
            return key + text[len(word) :]
    return text


def _load(table: Mapping[str, Any], at: str, linear: bool) -> LinearLoad | RotaryLoad:
    """The axis's load from its keys."""
    if linear:
        _toml.require(table, ("mass_kg", "lead_m"), at)
        try:
            return LinearLoad(
                _toml.number(table, "mass_kg", at, "[kg]"),
                _toml.number(table, "lead_m", at, "[m]"),
                _number(table, "force_n", at, 0.0),
                _number(table, "drive_efficiency", at, 1.0),
            )
        except InputError as e:
            text = str(e)
            if text.startswith("efficiency ="):
                text = "drive_" + text
            raise InputError(text) from None
    _toml.require(table, ("inertia_kg_m2",), at)
    return RotaryLoad(
        _toml.number(table, "inertia_kg_m2", at, "[kg·m²]"), _number(table, "torque_nm", at, 0.0)
    )


def _motor(
    table: Mapping[str, Any], at: str, source: str
) -> tuple[tuple[Motor, ...], Motor | None]:
    """The catalogue (empty without one) and the motor (None: sized only)."""
    catalogue: tuple[Motor, ...] = ()
    if "catalogue" in table:
        given = table["catalogue"]
        if not isinstance(given, str) or not given:
            raise InputError(f"{at}: catalogue = {given!r} must be a CSV file's path")
        path = Path(given)
        if not path.is_absolute() and Path(source).parent.is_dir():
            # Relative to the machine file's folder (the current one for "<dict>").
            path = Path(source).parent / path
        try:
            catalogue = load_catalogue(path)
        except InputError as e:
            raise InputError(f"{at}: catalogue: {e}") from None
    spec = table.get("motor")
    if spec is None:
        if not catalogue:
            raise InputError(
                f"{at}: give motor (a name of the catalogue, or a table of its data) or "
                "catalogue (to size the axis)"
            )
        return catalogue, None
    if isinstance(spec, str):
        if not catalogue:
            raise InputError(f"{at}: motor = {spec!r} names a motor: give the catalogue too")
        found = [m for m in catalogue if m.name == spec]
        if not found:
            names = ", ".join(m.name for m in catalogue)
            raise InputError(
                f"{at}: motor = {spec!r} is not in the catalogue {table['catalogue']!r}; "
                f"its motors: {names}"
            )
        return catalogue, found[0]
    if not isinstance(spec, Mapping):
        raise InputError(
            f"{at}: motor = {spec!r} must be a name of the catalogue or a table "
            "{rated_torque_nm = …, peak_torque_nm = …, max_rpm = …, inertia_kg_m2 = …}"
        )
    _toml.check_keys(spec, set(MOTOR_KEYS), None, f"{at} motor")
    try:
        return catalogue, Motor(**dict(spec))
    except (InputError, TypeError) as e:
        raise InputError(f"{at} motor: {e}") from None


def _reserved(
    table: Mapping[str, Any], at: str, catalogue: tuple[Motor, ...], motor: Motor | None
) -> tuple[float, tuple[tuple[Motor, ...], Motor | None]]:
    """The motors with ``torque_reserve`` of their peak and rated torque kept back:
    every bound, limit, check and sizing then uses (1 − reserve) of them."""
    reserve = _number(table, "torque_reserve", at, 0.0)
    if not 0.0 <= reserve < 1.0:
        raise InputError(
            f"{at}: torque_reserve = {table['torque_reserve']!r} must be in [0, 1): the "
            "fraction of the motor's torques kept back (0.2 for 20 %)"
        )
    if reserve == 0.0:
        return reserve, (catalogue, motor)

    def keep(m: Motor) -> Motor:
        return replace(
            m,
            rated_torque_nm=m.rated_torque_nm * (1.0 - reserve),
            peak_torque_nm=m.peak_torque_nm * (1.0 - reserve),
        )

    return reserve, (tuple(keep(m) for m in catalogue), None if motor is None else keep(motor))


def _ratios(table: Mapping[str, Any], at: str, ratio: float, sized: bool) -> tuple[float, ...]:
    """The ratios the sizing tries."""
    if "gear_ratios" not in table:
        return (ratio,)
    if not sized:
        raise InputError(f"{at}: gear_ratios is read only with catalogue (the sizing)")
    given = table["gear_ratios"]
    if (
        not isinstance(given, list)
        or not given
        or not all(isinstance(x, int | float) and not isinstance(x, bool) for x in given)
        or not all(math.isfinite(x) and x > 0 for x in given)
    ):
        raise InputError(
            f"{at}: gear_ratios = {given!r} must be a non-empty array of finite numbers > 0"
        )
    return tuple(float(x) for x in given)


def _check_arcs(program: Program, arcs: tuple[Arc | None, ...], ctx: TableContext, at: str) -> None:
    """Each arc an operation of the cyclogram, bound once, on a segment that scales."""
    known = [op.arc for op in ctx.cyclogram.operations]
    seen: set[Arc] = set()
    for i, arc in enumerate(arcs):
        if arc is None:
            continue
        _toml.operation(arc, "arc", f"{at} segment {i + 1}", known)
        if arc in seen:
            raise InputError(f"{at} segment {i + 1}: arc = {list(arc)!r} is bound twice")
        seen.add(arc)
        if not program.scalable[i]:
            raise InputError(
                f"{at} segment {i + 1}: arc = {list(arc)!r}, but its law "
                f"({program.segments[i].law}) has moving ends, a constant velocity or a "
                "point table: its shape changes with its angle, so it cannot take a "
                "phase angle from the cyclogram"
            )


def _program(
    rows: Any, units: Mapping[str, str], keys: Mapping[str, Any]
) -> tuple[Program, tuple[Arc | None, ...]]:
    """The axis's program from its rows (as a cam's: :func:`cyclomech.cam.read_program`)."""
    segs, arcs = read_segments(rows, units, True, loads=False)
    program = read_program(
        {"continuity": keys["continuity"]},
        rows,
        segs,
        units,
        always=True,
        advance=keys["advance"],
    )
    assert program is not None
    return program, arcs


@dataclass(frozen=True)
class _RmsLaw:
    """The RMS bound of an axis's one bound segment: one Rust call per call."""

    axis: ServoAxis
    segment: int
    dwell: int

    def __call__(self, rpm: Any) -> Any:
        # NaN (no angle will do) is an infinite bound.
        ax, motor = self.axis, self.axis.motor
        assert motor is not None

        def solve(speeds: Any) -> Any:
            rad = _core.servo_rms_angles(
                ax.program.kernel,
                self.segment,
                self.dwell,
                *ax._drive(motor, ax.gearbox),
                motor.rated_torque_nm,
                speeds * RAD_PER_S_PER_RPM,
            )
            return np.where(np.isnan(rad), np.inf, np.degrees(rad))

        return per_distinct_speed(rpm, solve)
