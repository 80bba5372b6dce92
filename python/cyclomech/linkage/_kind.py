"""The ``linkage`` mechanism kind of a machine file: a planar linkage whose crank
turns once per machine cycle (seed 001)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from .. import _keyrules, _toml, forces
from .._arrays import count, instance, positive
from .._errors import CyclomechWarning, InputError
from .._files import file_stem, write_csv
from .._keydoc import KeyTable
from .._keyrules import Rule
from .._kind import (
    Array,
    Context,
    Phase,
    PlainResult,
    Save,
    TableContext,
    Unbounded,
    efficiency_entry,
)
from .._scene import Scene, cycle_angles
from .._units import RAD_PER_S_PER_RPM
from ._file import _LINKAGE_KEYS, DYNAMICS_KEYS
from ._keys import KEY_DOCS
from ._linkage import Linkage
from ._solution import LinkageSolution
from ._synthesize import synthesize

__all__ = ["LinkageMechanism"]


@dataclass(frozen=True)
class LinkageMechanism(Unbounded):
    """A planar linkage driven by the main shaft (one crank turn per machine cycle).

    The ``linkage`` mechanism kind of a machine file, usually built by
    :meth:`from_table`; each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The mechanism's name in the machine file.
    linkage : Linkage
        The linkage.
    output : str
        The point whose motion is reported (and limited).
    max_acceleration : float, optional
        A limit on the output point's acceleration [m/s²]; None (default) for none.
    points : int, default 361
        Crank angles per turn (the machine's ``angle_points``): the grid of
        :meth:`solve`, :meth:`peaks` and :meth:`speed_limit_rpm` unless given
        another.
    dynamics : dict of str to object, optional
        The keywords of :func:`cyclomech.forces.kinetostatics` (masses, loads,
        gravity) when the table gives any; None (default) without.
    phase : Phase, optional
        Where the crank sits in the cycle: its absolute angle [deg] at a cyclogram
        event (default ``Phase()``: angle 0° at cycle angle 0).
    friction : Friction, optional
        The friction of its joints and guides (:class:`cyclomech.forces.Friction`,
        the ``friction`` table), solved at the nominal speed
        (:meth:`friction_forces`); needs ``dynamics``; None (default) without.
    synthesis : object, optional
        The record of a ``synthesize`` table (the linkage synthesised from
        requirements, with its report rows, figures and files; see
        ``cyclomech.linkage.SYNTHESIZERS``); None (default) for drawn dimensions.

    Examples
    --------
    >>> import cyclomech as cm
    >>> knife = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"]
    >>> knife.kind, knife.output
    ('linkage', 'E')
    """

    kind: ClassVar[str] = "linkage"
    # Its tables' keys, its own first, for the machine-file format reference
    # (cyclomech._keydocs renders them; tests/package/test_keydocs.py holds them to the parser).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS
    keys: ClassVar[frozenset[str]] = frozenset(
        _LINKAGE_KEYS | DYNAMICS_KEYS | {"kind", "max_acceleration_m_per_s2", "phase", "synthesize"}
    )
    #: Its plausibility rules besides the suffix rules of every key: none of its own
    #: (its lengths are the drawn points', whose table the linkage file reads).
    rules: ClassVar[tuple[Rule, ...]] = ()
    # A sweep sets numbers: the structure and the tables are set in the file (their
    # numbers by a path: varied_tables).
    fixed_keys: ClassVar[frozenset[str]] = frozenset(
        {"kind", "name", "points", "links", "ground", "driver", "lengths", "sliders"}
        | {"phase", "mass", "point_mass_kg", "load", "gravity_m_per_s2", "friction"}
        | {"synthesize"}
    )
    #: Sub-tables and lists whose numbers a sweep or a sensitivity may vary by a
    #: path (``lengths.3.length``, ``points.B.1``); not ``synthesize``, whose every
    #: variant would run the synthesis again.
    varied_tables: ClassVar[frozenset[str]] = frozenset(
        {"points", "lengths", "phase", "mass", "point_mass_kg", "load", "gravity_m_per_s2"}
        | {"friction"}
    )
    name: str
    linkage: Linkage
    output: str
    max_acceleration: float | None = None
    #: Crank angles per turn (the machine's ``angle_points``): the grid of
    #: :meth:`solve`, :meth:`peaks` and :meth:`speed_limit_rpm` unless given another.
    points: int = 361
    #: The keywords of :func:`cyclomech.forces.kinetostatics` (masses, loads,
    #: gravity) when the table gives any, and where the crank sits in the cycle.
    dynamics: dict[str, Any] | None = None
    phase: Phase = field(default_factory=Phase)
    #: The friction of its joints and guides (the ``friction`` table), None without.
    friction: forces.Friction | None = None
    #: The record of its ``synthesize`` table (the linkage synthesised from
    #: requirements, with its report rows and figures), None for given dimensions.
    synthesis: Any = field(default=None, compare=False)
    _solved: dict[int, tuple[LinkageSolution, tuple[float, float]]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )
    _forces: dict[int, forces.Kinetostatics] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )
    _friction: dict[tuple[int, float], forces.FrictionForces] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        # Built directly too, not only from a file: the same rule for its numbers.
        instance("linkage", self.linkage, Linkage)
        instance("output", self.output, str)
        object.__setattr__(self, "points", count("points", self.points, low=2, what="angles"))
        if self.max_acceleration is not None:
            a = positive("max_acceleration", self.max_acceleration, "[m/s²]")
            object.__setattr__(self, "max_acceleration", a)
        self._check_change_points()
        if self.friction is not None:
            instance("friction", self.friction, forces.Friction)
            if self.dynamics is None:
                raise InputError(
                    "friction: the linkage has no masses or loads (dynamics): no forces for "
                    "its friction to act with; give masses or loads, or drop the friction"
                )

    def _check_change_points(self) -> None:
        """A change point the motion cannot follow within one turn is an error; one it
        follows is a warning (a real mechanism needs a guide to pass it)."""
        found = self.linkage.change_points
        if not found:
            return
        where = ", ".join(f"joint {j!r} at {math.degrees(a) % 360.0:.2f}°" for j, a, _ in found)
        held = [j for j, _, followed in found if not followed]
        if held:
            raise InputError(
                f"mechanism {self.name!r}: the linkage has change points (uncertainty "
                f"positions, where a group's two assemblies meet): {where}; joint "
                f"{held[0]!r} passes an odd number a crank turn, so its smooth motion "
                "repeats only every two turns (held to one turn, its velocity jumps "
                "there); change its dimensions (a four-bar with s + l = p + q has one)"
            )
        warnings.warn(
            f"mechanism {self.name!r}: the linkage passes change points (uncertainty "
            f"positions, where a group's two assemblies meet), crank angles: {where}; "
            "cyclomech follows the smooth motion through them, which the mechanism "
            "does only with a guide (such as a second coupler out of phase)",
            CyclomechWarning,
            stacklevel=2,
        )

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> LinkageMechanism:
        """The mechanism of its ``[mechanism.<name>]`` table.

        The table of :meth:`~cyclomech.linkage.Linkage.from_dict` plus an optional
        ``max_acceleration_m_per_s2`` [m/s²], the forces' keys (masses, loads, gravity) and
        ``phase``; the linkage must assemble over the whole turn.

        Parameters
        ----------
        name : str
            The mechanism's name (``<name>``).
        table : mapping of str to object
            The table as read from the machine file.
        ctx : TableContext
            The machine's cyclogram, the file's name for messages and its crank
            angles per turn.

        Returns
        -------
        LinkageMechanism
            The mechanism, checked.

        Raises
        ------
        InputError
            If a key is unknown or a value malformed, ``phase`` is given without
            masses or loads, the forces name unknown links or points, or the
            linkage does not assemble over the whole turn (naming the file, the
            table and the key).

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> ctx = TableContext(m.cyclogram, "<doc>", 73)
        >>> LinkageMechanism.from_table("knife", m.data["mechanism"]["knife"], ctx).points
        73
        """
        instance("ctx", ctx, TableContext)  # a dict or a str: TypeError by name
        where = f"[mechanism.{name}]"
        _toml.check_keys(table, set(cls.keys), ctx.source, where)
        extra = {"kind", "max_acceleration_m_per_s2", "phase", "synthesize", *DYNAMICS_KEYS}
        own = {k: v for k, v in table.items() if k not in extra}
        record = None
        if "synthesize" in table:
            # Requirements instead of dimensions: the synthesis domain's synthesizer
            # (registered at import) gives the linkage; drawn dimensions would clash.
            clash = sorted(k for k in own if k != "name")
            if clash:
                raise InputError(
                    f"{ctx.where(name)}: synthesize gives the linkage from requirements, so "
                    f"{', '.join(clash)} cannot be given too; drop them, or drop synthesize"
                )
            record = synthesize(table["synthesize"], f"{ctx.where(name)}.synthesize")
            lk = record.linkage
        else:
            lk = Linkage.from_dict(own, ctx.source, where)
        limit = _toml.optional_positive(
            table, "max_acceleration_m_per_s2", ctx.where(name), "[m/s²]"
        )
        _keyrules.check(table, cls.rules, ctx.where(name))
        dynamics = forces.dynamics_from_table(table, ctx.source, where, lk)
        phase = Phase.from_table(table, ctx, name)
        if "phase" in table and dynamics is None:
            raise InputError(
                f"{ctx.where(name)}: phase places the linkage's torque on the main shaft, but "
                "it has no masses or loads ([[…mass]], point_mass_kg, [[…load]]): nothing to place"
            )
        if "friction" in table and dynamics is None:
            raise InputError(
                f"{ctx.where(name)}: friction acts with the joints' forces, but the linkage "
                "has no masses or loads ([[…mass]], point_mass_kg, [[…load]]): give them, or "
                "drop the friction table"
            )
        if dynamics is not None:
            try:  # names of links and points, checked against the linkage now
                forces.check_dynamics(lk, **dynamics)
            except InputError as e:
                raise InputError(f"{ctx.where(name)}: {e}") from None
        friction = (
            None
            if dynamics is None
            else forces.friction_from_table(table, ctx.source, where, lk, dynamics)
        )
        out = lk.output or lk.names[-1]
        mech = cls(name, lk, out, limit, ctx.angle_points, dynamics, phase, friction, record)
        mech.peaks()  # must assemble over the whole turn
        return mech

    def kinetostatics(self, samples: int = 3600) -> forces.Kinetostatics | None:
        """The forces over one crank turn from the drawn angle; computed once per grid.

        Parameters
        ----------
        samples : int, default 3600
            The number of uniform crank angles (the last one short of a full turn).

        Returns
        -------
        Kinetostatics or None
            The forces over the turn (:class:`cyclomech.forces.Kinetostatics`), or
            None without masses or loads.

        Raises
        ------
        InputError
            If a group is at or near a dead centre at some crank angle, where its
            forces grow without bound.

        Examples
        --------
        >>> import cyclomech as cm
        >>> knife = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"]
        >>> k = knife.kinetostatics(360)
        >>> k.torque_parts.shape, k.pairs[0]
        ((3, 360), ('A', 'frame'))
        """
        samples = count("samples", samples, low=2, what="angles")
        if self.dynamics is None:
            return None
        if samples not in self._forces:
            angles = self.linkage.drawn_angle + np.arange(samples) * (2.0 * math.pi / samples)
            k = forces.kinetostatics(self.linkage, angles, **self.dynamics)
            if not k.ok.all() or k.near_dead_centre.any():
                flagged = ~k.ok | k.near_dead_centre
                bad = np.degrees(angles[flagged])[:6]
                # The closest the analogs put the crank to a dead centre (0 at one);
                # angles where it does not assemble have none.
                near = k.conditioning[flagged & k.solution.ok]
                why = (
                    f"its analogs put the crank {float(near.min()):.2g} rad from one, under "
                    f"{forces.NEAR_DEAD_CENTRE:g} rad"
                    if near.size
                    else "it does not assemble there"
                )
                raise InputError(
                    f"mechanism {self.name!r}: a group is at or near a dead centre at crank "
                    f"angles {', '.join(f'{v:.2f}' for v in bad)} degrees ({why}): its forces "
                    "grow without bound there, so its crank cannot drive it through; change "
                    "its dimensions"
                )
            self._forces[samples] = k
        return self._forces[samples]

    def friction_forces(self, rpm: float, samples: int = 3600) -> forces.FrictionForces | None:
        """Its forces with friction at the steady crank speed ``rpm``, on the grid of
        :meth:`kinetostatics`; computed once per speed and grid.

        Parameters
        ----------
        rpm : float
            The crank speed [rpm] (> 0).
        samples : int, default 3600
            The number of uniform crank angles from the drawn one.

        Returns
        -------
        FrictionForces or None
            :func:`cyclomech.forces.kinetostatics_with_friction` over the turn; None
            without a ``friction`` table.

        Warns
        -----
        CyclomechWarning
            If a pose is self-locking (its forces are NaN).

        Examples
        --------
        >>> import cyclomech as cm
        >>> knife = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"]
        >>> f = knife.friction_forces(45.0, 360)
        >>> f.torque.shape, 0.8 < float(f.cycle_efficiency()[0]) < 1.0
        ((1, 360), True)
        """
        n = positive("rpm", rpm, "[rpm]")
        k = self.kinetostatics(samples)
        if self.friction is None or k is None:
            return None
        key = (k.angles.size, n)
        if key not in self._friction:
            assert self.dynamics is not None
            self._friction[key] = forces.kinetostatics_with_friction(
                self.linkage, k.solution, self.friction, n, **self.dynamics
            )
        return self._friction[key]

    def solve(self, points: int | None = None) -> LinkageSolution:
        """The mechanism over one crank turn from its drawn angle; solved once per grid.

        Parameters
        ----------
        points : int, optional
            The number of crank angles (default :attr:`points`; the last one
            repeats the first).

        Returns
        -------
        LinkageSolution
            Every point's positions [m] and analogs over the turn.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> bool(m.mechanisms["knife"].solve(73).ok.all())
        True
        """
        n = self.points if points is None else count("points", points, low=2, what="angles")
        if n in self._solved:
            return self._solved[n][0]
        angles = self.linkage.drawn_angle + np.linspace(0.0, 2.0 * math.pi, n)
        return self.linkage.solve(angles)

    def peaks(self, points: int | None = None) -> tuple[float, float]:
        """Largest |d xy/dφ| [m/rad] and |d² xy/dφ²| [m/rad²] of the output point over the turn.

        At constant crank speed ω its speed and acceleration peak at ω and ω² times
        these. Computed once per grid.

        Parameters
        ----------
        points : int, optional
            The number of crank angles (default :attr:`points`).

        Returns
        -------
        velocity : float
            The largest velocity analog |d xy/dφ| [m/rad].
        acceleration : float
            The largest acceleration analog |d² xy/dφ²| [m/rad²].

        Raises
        ------
        InputError
            If the linkage cannot be assembled at some crank angle (naming them).

        Examples
        --------
        >>> import cyclomech as cm
        >>> v, a = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"].peaks()
        >>> v > 0 and a > 0
        True
        """
        n = self.points if points is None else count("points", points, low=2, what="angles")
        if n in self._solved:
            return self._solved[n][1]
        sol = self.solve(n)
        if not sol.ok.all():
            bad = np.degrees(sol.angles[~sol.ok])
            raise InputError(
                f"mechanism {self.name!r}: the linkage cannot be assembled at crank angles "
                f"{', '.join(f'{v:.1f}' for v in bad[:6])}{' …' if bad.size > 6 else ''} "
                "degrees; it must turn through a whole revolution in a machine"
            )
        assert sol.vel is not None and sol.acc is not None
        k = sol.index(self.output)
        peaks = (
            float(np.nanmax(np.hypot(*sol.vel[:, k].T))),
            float(np.nanmax(np.hypot(*sol.acc[:, k].T))),
        )
        self._solved[n] = (sol, peaks)
        return peaks

    def speed_limit_rpm(self, points: int | None = None) -> float:
        """Speed [rpm] at which the output point's peak acceleration reaches ``max_acceleration``.

        The peak acceleration is ω² · max|d² xy/dφ²| over the turn.

        Parameters
        ----------
        points : int, optional
            The number of crank angles (default :attr:`points`).

        Returns
        -------
        float
            The speed limit [rpm]; inf without a ``max_acceleration``.

        Raises
        ------
        InputError
            If the linkage cannot be assembled at some crank angle.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"]
        >>> round(m.speed_limit_rpm()) > 0
        True
        """
        if self.max_acceleration is None:
            return math.inf
        _, acc = self.peaks(points)
        return math.sqrt(self.max_acceleration / acc) / RAD_PER_S_PER_RPM

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`: the criterion and its limit.

        Returns
        -------
        str
            The reason in words; empty without a ``max_acceleration``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"].limit_reason()
        "the peak acceleration of point 'E' reaches max_acceleration = 8 m/s²"
        """
        if self.max_acceleration is None:
            return ""
        return (
            f"the peak acceleration of point {self.output!r} reaches max_acceleration = "
            f"{self.max_acceleration:g} m/s²"
        )

    def analyze(self, ctx: Context) -> LinkageResult:
        """Its solution over the turn and its peaks at the nominal speed.

        Parameters
        ----------
        ctx : Context
            What the machine computed before its mechanisms' results (the nominal
            speed [rpm], the optimum, the speed limit).

        Returns
        -------
        LinkageResult
            The solution over the turn, the output point's largest analogs [m/rad,
            m/rad²] and, with masses or loads, the forces.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> r = cm.machine.analyze(m, progress=False).mechanisms["knife"]
        >>> r.solution.xy.shape[0] == m.angle_points
        True
        """
        instance("ctx", ctx, Context)
        vmax, amax = self.peaks()
        k = self.kinetostatics()
        f = None if k is None else self.friction_forces(ctx.nominal_rpm)
        return LinkageResult(self, ctx, self.solve(), vmax, amax, k, f)


def _runs(f: forces.FrictionForces) -> str:
    """The crank angles [deg] where ``f`` self-locks, as runs of neighbouring
    angles ("43.3–70.1, 110.0"), at most six runs."""
    locked = f.self_locking[0]
    deg = np.degrees(f.angles)
    idx = np.flatnonzero(locked)
    # A run breaks where the next locked angle is not the next sample.
    cuts = np.flatnonzero(np.diff(idx) > 1) + 1
    runs = [
        f"{deg[r[0]]:.1f}" if r.size == 1 else f"{deg[r[0]]:.1f}–{deg[r[-1]]:.1f}"
        for r in np.split(idx, cuts)
    ]
    return ", ".join(runs[:6]) + (f" and {len(runs) - 6} more runs" if len(runs) > 6 else "")


@dataclass(frozen=True)
class LinkageResult(PlainResult):
    """A linkage's solution over one crank turn and the output point's largest
    velocity and acceleration analogs [m/rad, m/rad²]."""

    mech: LinkageMechanism
    ctx: Context
    solution: LinkageSolution
    max_velocity_analog: float
    max_acceleration_analog: float
    #: Its forces over the turn (3600 angles from the drawn one), None without
    #: masses or loads.
    kinetostatics: forces.Kinetostatics | None = None
    #: Its forces with friction at the nominal speed on the same angles, None
    #: without a ``friction`` table.
    friction: forces.FrictionForces | None = None

    def shaft_torque(self) -> tuple[Array, Array, float, str | None] | None:
        """Its driving torque for the machine's main shaft: (ω² part [N·m·s²],
        static part [N·m] on 3600 crank angles from the drawn one; the cycle angle
        [deg] where the crank is at its drawn angle, from its ``phase``; the event
        the phase follows, None for a crank fixed at cycle angle 0); None without
        masses or loads, or when the phase follows an event and there is no
        optimum.

        With friction, the static part carries the torque friction adds at the
        nominal speed (the torque with friction less the one without), so the
        main shaft, its flywheel and its drive see the losses. Coulomb friction
        is not linear in ω² (it goes with |R|), so this is the nominal speed's
        friction at every speed the shaft's statistics are read at; a pose that
        self-locks (a failure, :meth:`failures`) leaves the torque frictionless.
        """
        k, at = self.kinetostatics, self._shaft_phase()
        if k is None or at is None:
            return None
        t = k.shaft_torque()
        return t.per_omega2, t.static + self.friction_torque(), at[0], at[1]

    def friction_torque(self) -> Array:
        """The torque friction adds on the crank at the nominal speed [N·m]: the
        driving torque with friction less the one without, on the angles of
        :attr:`kinetostatics` (zeros without friction or where a pose
        self-locks).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False).mechanisms["knife"]
        >>> t = r.friction_torque()
        >>> t.shape, bool(t.mean() > 0)
        ((3600,), True)
        """
        k, f = self.kinetostatics, self.friction
        if k is None:
            return np.zeros(0)
        if f is None or not f.ok.all():
            return np.zeros(k.angles.size)
        out: Array = f.torque[0] - k.torque(self.ctx.nominal_rpm)
        return out

    def failures(self) -> list[str]:
        """What fails at the nominal speed: poses where friction self-locks the
        linkage (no finite driving torque), by crank angle; empty otherwise.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False).mechanisms["knife"]
        >>> r.failures()
        []
        """
        f = self.friction
        if f is None or not f.self_locking.any():
            return []
        return [
            f"friction self-locks the linkage at crank angles {_runs(f)} degrees: no "
            "finite driving "
            "torque moves it there; lower the friction coefficients or pin radii, or change "
            "the dimensions (the pressure angles)"
        ]

    def efficiency(self) -> dict[str, Any] | None:
        """Its friction over one turn at the nominal speed, None without friction:
        ``cycle_efficiency`` (output work / input work; None where a pose
        self-locks or the motor puts no work in), ``mean_friction_power_w``,
        ``mean_input_power_w`` (with friction), ``peak_torque_nm`` and
        ``mean_torque_nm`` with friction and ``peak_torque_nm_without`` (the
        frictionless peak) [N·m], and ``self_locking_crank_deg``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False).mechanisms["knife"]
        >>> e = r.efficiency()
        >>> 0.8 < e["cycle_efficiency"] < 1.0, e["mean_friction_power_w"] > 0
        (True, True)
        """
        f, k = self.friction, self.kinetostatics
        if f is None or k is None:
            return None
        n = self.ctx.nominal_rpm
        return efficiency_entry(
            n,
            f.torque[0],
            k.torque(n),
            f.friction_power[0],
            f.input_power[0],
            f.losses[0],
            f.elements,
            np.degrees(f.angles[f.self_locking[0]]),
            float(f.cycle_efficiency()[0]),
        )

    def shaft_inertia(self) -> tuple[Array, float, str | None] | None:
        """Its reduced moment of inertia about the crank, for the machine's main
        shaft (:func:`cyclomech.dynamics.reduced`): (J(φ) [kg·m²] on the grid,
        phase and event of :meth:`shaft_torque`); None where that is None.

        J is the kinetostatics' crank-acceleration part (the torque per unit ε at
        rest is Σ m·|v_G/ω|² + J_G·(ω_link/ω)², the kinetic energy's ½·J·ω²), so
        ½·dJ/dφ is its ω² part.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False).mechanisms["knife"]
        >>> j, phase, event = r.shaft_inertia()
        >>> j.shape, bool(j.min() > 0)
        ((3600,), True)
        """
        k, at = self.kinetostatics, self._shaft_phase()
        if k is None or at is None:
            return None
        k.shaft_torque()  # the same checks: a uniform grid, finite everywhere
        return np.array(k.torque_parts[1]), at[0], at[1]

    def working_member(self) -> tuple[Array, Array, Array, str] | None:
        """Its working member, the output point, for the main shaft's torsion
        (:func:`cyclomech.dynamics.torsion`): (x and y, their first and second
        derivatives in the crank angle as (2, N) rows on the grid of
        :meth:`shaft_inertia`, the unit "m"); None where that is None.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False).mechanisms["knife"]
        >>> xy, d1, d2, unit = r.working_member()
        >>> xy.shape, unit
        ((2, 3600), 'm')
        """
        k = self.kinetostatics
        if k is None or self.shaft_inertia() is None:
            return None
        sol = k.solution
        i = sol.index(self.mech.output)
        assert sol.vel is not None and sol.acc is not None  # the forces solve with analogs
        rows = [np.ascontiguousarray(a[:, i, :].T) for a in (sol.xy, sol.vel, sol.acc)]
        return rows[0], rows[1], rows[2], "m"

    def scene(self, cycle_deg: Array) -> Scene | None:
        """The linkage at the main shaft's angles ``cycle_deg`` [deg], for the
        machine's animation: every point where :meth:`Linkage.solve` puts it at the
        crank angle its ``phase`` gives (NaN where it cannot be assembled), its
        moving links, its fixed pivots, its sliders' blocks and guides, and the
        output point's path.

        Parameters
        ----------
        cycle_deg : ndarray of float
            The main shaft's angles [deg].

        Returns
        -------
        Scene or None
            Lengths in m; None when its phase follows an event and there is no
            optimum.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False).mechanisms["knife"]
        >>> s = r.scene(np.arange(0.0, 360.0, 30.0))
        >>> s.frames, s.traces
        (12, ('E',))
        """
        from ._scene import linkage_scene

        return linkage_scene(self, cycle_angles(cycle_deg))

    def _shaft_phase(self) -> tuple[float, str | None] | None:
        """(the cycle angle [deg] where the crank is at its drawn angle, the event
        its ``phase`` follows); None when it follows an event and there is no
        optimum."""
        phase, o = self.mech.phase, self.ctx.optimum
        if phase.event is not None and o is None:
            return None
        origin = math.degrees(self.mech.linkage.drawn_angle)
        return phase.shift_deg({} if o is None else o.times, origin), phase.event

    def cycle_csv(self) -> tuple[list[str], list[Array]] | None:
        """Its forces over the turn at the nominal speed for ``<name>_forces.csv``:
        the crank angle [deg], the driving torque [N·m], each guide's force and
        each joint's force on each part (x, y) [N]; None without forces."""
        k = self.kinetostatics
        return None if k is None else k.table(self.ctx.nominal_rpm)

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry, and with friction its ``friction`` entry
        (:meth:`efficiency`)."""
        w = RAD_PER_S_PER_RPM * self.ctx.nominal_rpm
        eff = self.efficiency()
        return {
            **({} if eff is None else {"friction": eff}),
            "mechanisms": {
                "kind": "linkage",
                "output": self.mech.output,
                "max_velocity_analog_m_per_rad": self.max_velocity_analog,
                "max_acceleration_analog_m_per_rad2": self.max_acceleration_analog,
                "max_velocity_m_s": self.max_velocity_analog * w,
                "max_acceleration_m_s2": self.max_acceleration_analog * w * w,
                "speed_limit_rpm": self.ctx.own_limit_rpm(self.mech.name),
                **self._forces_json(),
                **(
                    {} if self.mech.synthesis is None else {"synthesis": self.mech.synthesis.json()}
                ),
            },
        }

    def files(self, folder: Path) -> list[Path]:
        """Its own files: ``<name>_drawing.csv``, the linkage's drawing table (its
        pivots, joints, link lengths and guides: :meth:`Linkage.drawing_table`),
        and those of its ``synthesize`` record."""
        lk, stem = self.mech.linkage, file_stem(self.mech.name)
        header, rows = lk.drawing_table()
        path = write_csv(folder / f"{stem}_drawing.csv", header, rows)
        rec = self.mech.synthesis
        return [path, *([] if rec is None else rec.files(folder, self.mech.name))]

    def _forces_json(self) -> dict[str, Any]:
        k = self.kinetostatics
        if k is None:
            return {}
        n = self.ctx.nominal_rpm
        t = k.torque(n)
        joint, peak, at = k.most_loaded(n)
        loads = k.joint_loads(n)
        return {
            "peak_torque_nm": float(np.max(t)),
            "lowest_torque_nm": float(np.min(t)),
            "mean_torque_nm": float(np.mean(t)),
            "most_loaded_joint": joint,
            "most_loaded_joint_peak_n": peak,
            "most_loaded_joint_at_crank_deg": at,
            "joint_peak_loads_n": {p: float(np.max(v)) for p, v in loads.items()},
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        info, n = self.json()["mechanisms"], self.ctx.nominal_rpm
        return ["quantity", "value"], [
            ["output point", self.mech.output],
            ["max |d xy/dφ| [m/rad]", info["max_velocity_analog_m_per_rad"]],
            ["max |d² xy/dφ²| [m/rad²]", info["max_acceleration_analog_m_per_rad2"]],
            [f"max speed at {n:g} rpm [m/s]", info["max_velocity_m_s"]],
            [f"max acceleration at {n:g} rpm [m/s²]", info["max_acceleration_m_s2"]],
            ["speed limit [rpm]", info["speed_limit_rpm"]],
            *(
                [
                    [
                        f"driving torque at {n:g} rpm: peak / lowest [N·m]",
                        f"{info['peak_torque_nm']:.4g} / {info['lowest_torque_nm']:.4g}",
                    ],
                    [
                        f"most loaded joint at {n:g} rpm",
                        f"{info['most_loaded_joint']}: {info['most_loaded_joint_peak_n']:,.0f} N "
                        f"at crank {info['most_loaded_joint_at_crank_deg']:.1f}°",
                    ],
                ]
                if "peak_torque_nm" in info
                else []
            ),
            *self._friction_rows(),
            *([] if self.mech.synthesis is None else self.mech.synthesis.rows()),
        ]

    def _friction_rows(self) -> list[list[Any]]:
        """Its report table's rows on friction (none without)."""
        e, n = self.efficiency(), self.ctx.nominal_rpm
        if e is None:
            return []
        eta = e["cycle_efficiency"]
        rows: list[list[Any]] = [
            [
                f"efficiency over the turn at {n:g} rpm (work out / work in)",
                "—" if eta is None else f"{eta:.4f}",
            ],
            [f"mean power lost to friction at {n:g} rpm [W]", e["mean_friction_power_w"]],
            [
                f"driving torque with friction at {n:g} rpm: peak / mean [N·m]",
                f"{e['peak_torque_nm']:.4g} / {e['mean_torque_nm']:.4g}"
                if e["peak_torque_nm"] is not None
                else "— (self-locking)",
            ],
        ]
        if e["self_locking_crank_deg"]:
            rows.append(
                [
                    "self-locking at crank [deg]",
                    ", ".join(f"{v:.1f}" for v in e["self_locking_crank_deg"][:6]),
                ]
            )
        return rows

    def figures(self, save: Save) -> None:
        """The mechanism with its output's path, and the output's analogs."""
        from .plot import plot_analogs, plot_linkage

        k, mech, sol = self.mech.name, self.mech, self.solution
        if mech.synthesis is not None:
            mech.synthesis.figures(save, k)
        ax = plot_linkage(mech.linkage, sol, 0, trace=[mech.output], title=f"{k}: mechanism")
        save(
            ax.figure,
            f"{k}_mechanism",
            f"The mechanism at its drawn angle, with the path of {mech.output}.",
        )
        save(
            plot_analogs(sol, mech.output, title=f"{k}: analogs of {mech.output}"),
            f"{k}_analogs",
            f"Position, velocity and acceleration analogs of {mech.output} over the turn.",
        )
        if self.kinetostatics is not None:
            from ..forces.plot import plot_forces

            n = self.ctx.nominal_rpm
            save(
                plot_forces(self.kinetostatics, n, title=f"{k}: driving torque and joint loads"),
                f"{k}_forces",
                f"The torque the crank of {k} needs and each joint's load over the crank "
                f"angle at {n:g} rpm (masses, loads and gravity of the machine file).",
            )
