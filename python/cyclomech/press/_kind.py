"""The ``press`` mechanism kind of a machine file: the planetary gear-lever press
drive whose crank turns once per machine cycle (seed 003)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from .. import _keyrules, _toml
from .._arrays import finite_number, instance, positive
from .._errors import InputError
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
from .._numtext import number_text
from .._scene import Scene, cycle_angles
from .._units import RAD_PER_S_PER_RPM
from ._drive import STATUS, GearLeverPress, PressCriteria
from ._friction import PressFriction, PressFrictionForces, friction_from_table, press_friction
from ._keys import KEY_DOCS
from ._study import DRIVE_KEYS, drive_from_table
from ._torque import DeformationForce, PressTorque, check_table

__all__ = ["PressMechanism"]

#: Carrier angles per turn of the press's torque curve on the main shaft.
SHAFT_SAMPLES = 3600

#: The keys of a ``deformation_force`` table.
FORCE_KEYS = ("s_above_bdc_m", "force_n")


@dataclass(frozen=True)
class PressMechanism(Unbounded):
    """A gear-lever press drive whose crank turns once per machine cycle (seed 003).

    Its load on the main shaft (:meth:`GearLeverPress.crank_torque`): the
    deformation-force diagram ``force``, the slider's mass and a uniform rod's mass;
    ``phase`` places it in the cycle. The press's own angle for
    ``Phase`` is the carrier's angle turned since BDC, in its
    direction of rotation (ψ = −α mod 360°): ``phase = {event = "bottom", crank_deg
    = 0}`` puts BDC at the event ``bottom``, and the working stroke then takes the
    α_p degrees of the cycle before it. The ``press`` kind of a machine file, read
    by :meth:`from_table`; each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The mechanism's name in the machine file.
    press : GearLeverPress
        The drive's design.
    k_Sp : float, optional
        The working stroke as a fraction of the nominal stroke S_n; default None.
    working_stroke : float, optional
        The working stroke S_p [m]; default None (one of the two is given).
    max_V_np : float, optional
        The limit on the slider's speed at the start of the working stroke [m/s];
        default None (no limit).
    force : DeformationForce, optional
        The deformation-force diagram; default None.
    slider_mass : float, default 0.0
        The slider's mass [kg].
    rod_mass : float, default 0.0
        A uniform rod's mass [kg].
    phase : Phase, optional
        Where it sits in the cycle; default ``Phase()`` (its angle 0 at cycle angle
        0).
    friction : PressFriction, optional
        The friction of its slider's guide and its rod's pins (the ``friction``
        table, ``cyclomech/press/_friction.py``), solved at the nominal speed;
        needs a load; None (default) without.

    Attributes
    ----------
    kind : str
        ``"press"``, the ``kind`` key of its table.
    keys : frozenset of str
        The keys its table takes (their names say their units: ``R_m``,
        ``working_stroke_m``, ``max_V_np_m_per_s``, …).
    rules : tuple of Rule
        Its plausibility rules (a value implausible for its unit warns).

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml").mechanisms["drive"]
    >>> m.kind, m.k_Sp
    ('press', 0.1)
    >>> m.phase, m.slider_mass, m.rod_mass
    (Phase(event='bottom', crank_deg=0.0), 60.0, 15.0)
    """

    kind: ClassVar[str] = "press"
    # Its tables' keys, its own first, for the machine-file format reference
    # (cyclomech._keydocs renders them; tests/package/test_keydocs.py holds them to the parser).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS
    keys: ClassVar[frozenset[str]] = frozenset(
        DRIVE_KEYS
        | {
            "kind",
            "k_Sp",
            "working_stroke_m",
            "max_V_np_m_per_s",
            "deformation_force",
            "slider_mass_kg",
            "rod_mass_kg",
            "phase",
            "friction",
        }
    )
    # A sweep sets numbers: the tables are set in the file (their numbers by a
    # path: varied_tables).
    fixed_keys: ClassVar[frozenset[str]] = frozenset(
        {"kind", "friction", "deformation_force", "phase"}
    )
    #: Sub-tables whose numbers a sweep or a sensitivity may vary by a path
    #: (``friction.guide_mu``, ``deformation_force.force_n``).
    varied_tables: ClassVar[frozenset[str]] = frozenset({"deformation_force", "phase", "friction"})
    #: Its plausibility rules (besides every ``_m`` key's): a press slider meets
    #: the workpiece at mm/s to a few m/s; a limit over 10 m/s is likelier mm/s.
    rules: ClassVar[tuple[Rule, ...]] = (
        Rule(
            "max_V_np_m_per_s",
            lambda v, t: v > 10.0,
            lambda v, t: (
                f"m/s is over 10 m/s — did you give mm/s (max_V_np_m_per_s = {v / 1000:g})?"
            ),
        ),
    )
    name: str
    press: GearLeverPress
    k_Sp: float | None = None
    working_stroke: float | None = None
    max_V_np: float | None = None
    force: DeformationForce | None = None
    slider_mass: float = 0.0
    rod_mass: float = 0.0
    phase: Phase = field(default_factory=Phase)
    friction: PressFriction | None = None

    def __post_init__(self) -> None:
        # Built directly too, not only from a file: the same rule for its numbers.
        instance("press", self.press, GearLeverPress)
        if self.k_Sp is not None:
            k_Sp = positive("k_Sp", self.k_Sp, "(a fraction of the stroke, in (0, 1])")
            if k_Sp > 1.0:
                raise InputError(f"k_Sp = {k_Sp!r} must lie in (0, 1] (a fraction of the stroke)")
            object.__setattr__(self, "k_Sp", k_Sp)
        for k, unit in (("working_stroke", "[m]"), ("max_V_np", "[m/s]")):
            if getattr(self, k) is not None:
                object.__setattr__(self, k, positive(k, getattr(self, k), unit))
        for k in ("slider_mass", "rod_mass"):
            object.__setattr__(self, k, finite_number(k, getattr(self, k), "[kg]", low=0.0))

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> PressMechanism:
        """A press from its ``[mechanism.<name>]`` table; the design must work.

        The table holds ``R_m``, ``r_m``, ``d_m``, ``L_m`` [m], ``phi0_deg`` [deg],
        optional ``offset_m`` [m]; one of ``k_Sp`` or ``working_stroke_m`` [m];
        optional ``max_V_np_m_per_s`` [m/s]. The values are then checked against
        ``rules``.

        Its load on the main shaft, all optional: ``deformation_force =
        {s_above_bdc_m = [...], force_n = [...]}``, the force diagram (heights of the
        slider above BDC [m], strictly increasing, inside the working stroke [0, S_p];
        forces [N] ≥ 0; linear between the points, zero outside them);
        ``slider_mass_kg`` and ``rod_mass_kg`` (a uniform rod) [kg] ≥ 0; ``phase =
        {event = "...", crank_deg = ...}``, the carrier's angle past BDC [deg] at that
        cyclogram event (see the class's docs).

        Parameters
        ----------
        name : str
            The mechanism's name.
        table : mapping of str to Any
            Its table as read from the file.
        ctx : TableContext
            The machine's cyclogram (for the phase's event) and the file's name for
            messages.

        Returns
        -------
        PressMechanism
            The mechanism.

        Raises
        ------
        InputError
            If a key is missing or unknown, a value is malformed or out of range, the
            design does not work (the message says which keys to change and to what),
            or the force diagram leaves the working stroke.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> ctx = TableContext(m.cyclogram, "<doc>", 361)
        >>> PressMechanism.from_table("drive", m.data["mechanism"]["drive"], ctx).max_V_np
        0.005
        """
        instance("ctx", ctx, TableContext)  # a dict or a str: TypeError by name
        where = ctx.where(name)
        _toml.check_keys(table, set(cls.keys), ctx.source, f"[mechanism.{name}]")
        if ("k_Sp" in table) == ("working_stroke_m" in table):
            raise InputError(
                f"{where}: give one of k_Sp (a fraction of the stroke) or working_stroke_m [m]"
            )
        press = drive_from_table(table, where, check=False)
        mech = cls(
            name,
            press,
            k_Sp=_toml.number(table, "k_Sp", where, "") if "k_Sp" in table else None,
            working_stroke=_toml.optional_positive(table, "working_stroke_m", where, "[m]"),
            max_V_np=_toml.optional_positive(table, "max_V_np_m_per_s", where, "[m/s]"),
            force=_force(table, name, ctx),
            slider_mass=_mass(table, "slider_mass_kg", where),
            rod_mass=_mass(table, "rod_mass_kg", where),
            phase=Phase.from_table(table, ctx, name),
            friction=friction_from_table(table, where),
        )
        if mech.friction is not None and not mech.loaded:
            raise InputError(
                f"{where}: friction acts with the slider's and the rod's forces, but the press "
                "has no load; give deformation_force, slider_mass_kg or rod_mass_kg, or drop "
                "the friction table"
            )
        _keyrules.check(table, cls.rules, where)
        try:
            c = mech.criteria(60.0)
        except InputError as e:
            named = _keyrules.file_names(str(e), {"working_stroke_m": "working_stroke"})
            raise InputError(f"{where}: {named}") from None
        if not c.ok:
            raise InputError(f"{where}: {mech._failure(c)}")
        if mech.force is not None:
            try:
                mech.force.check_stroke(c.S_p, "deformation_force.s_above_bdc_m", counted=True)
            except InputError as e:
                raise InputError(f"{where}: {e}") from None
        return mech

    @property
    def loaded(self) -> bool:
        """True when it has a force diagram or a mass: a torque on the main shaft.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/extrusion_press_line.toml").mechanisms["drive"].loaded
        True
        """
        return self.force is not None or self.slider_mass > 0 or self.rod_mass > 0

    def crank_torque(self) -> PressTorque | None:
        """Its crank torque on ``SHAFT_SAMPLES`` (3600) carrier angles past BDC.

        :meth:`GearLeverPress.crank_torque` at ψ = 0, 0.1°, … past BDC in the direction
        of rotation (α = −ψ mod 2π).

        Returns
        -------
        PressTorque or None
            The crank torque [N·m] (ω² part and force part); None when it has no load.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml").mechanisms["drive"]
        >>> t = m.crank_torque()
        >>> t.alpha.shape, round(t.energy_per_stroke_j)
        ((3600,), 2200)
        """
        if not self.loaded:
            return None
        psi = 2.0 * math.pi * np.arange(SHAFT_SAMPLES) / SHAFT_SAMPLES
        return self.press.crank_torque(
            np.mod(-psi, 2.0 * math.pi),
            force=self.force,
            slider_mass=self.slider_mass,
            rod_mass=self.rod_mass,
            k_Sp=self.k_Sp,
            working_stroke=self.working_stroke,
        )

    def _failure(self, c: PressCriteria) -> str:
        """Why the design does not work (criteria ``c``), with the keys to change
        and their admissible values."""
        press = self.press
        if c.status == STATUS[1]:
            # The rod reaches the guide x = offset iff |x_pin − offset| < L all the
            # turn. The pin's path is the planet's, whatever L and offset: trace it
            # with a rod that always reaches (α counts from a BDC, which this design
            # lacks).
            tracer = replace(press, L=2.0 * (press.R + press.d) + 1.0, offset=0.0)
            x = tracer.solve(np.linspace(0.0, 2.0 * math.pi, 3601)).pin[:, 0]
            lo, hi = float(x.min()), float(x.max())
            reach = max(hi - press.offset, press.offset - lo)
            text = (
                f"the rod (L_m = {press.L!r}) cannot reach the slider's guide x = offset_m = "
                f"{press.offset!r} m all the turn: the pin runs over x = {number_text(lo)} … "
                f"{number_text(hi)} m, so L_m must exceed {number_text(reach, press.L)} at "
                "this offset"
            )
            if hi - lo < 2.0 * press.L:
                bounds = (number_text(v, press.offset) for v in (hi - press.L, lo + press.L))
                text += ", or offset_m must lie in ({}, {}) for this L_m".format(*bounds)
            return text
        if c.status == STATUS[3]:
            S_n = press.criteria(omega=1.0, k_Sp=1.0).S_n
            sn = number_text(S_n, self.working_stroke or 0.0)
            return (
                f"working_stroke_m = {self.working_stroke!r} exceeds the nominal stroke "
                f"S_n = {sn} m of this design; give working_stroke_m < {sn} or k_Sp in (0, 1]"
            )
        given = (
            f"k_Sp = {self.k_Sp!r}"
            if self.working_stroke is None
            else f"working_stroke_m = {self.working_stroke!r}"
        )
        return (
            f"{c.status} ({given}): give a shorter working stroke, or change the design "
            "(d_m, L_m, phi0_deg)"
        )

    def criteria(self, rpm: float) -> PressCriteria:
        """The working-stroke criteria at a machine speed (:meth:`GearLeverPress.criteria`).

        Parameters
        ----------
        rpm : float
            The machine speed, the crank's [rpm].

        Returns
        -------
        PressCriteria
            The criteria at ω = 2π·rpm/60.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> round(m.mechanisms["drive"].criteria(40.0).S_n, 4)
        0.1276
        """
        return self.press.criteria(
            omega=positive("rpm", rpm, "[rpm]") * RAD_PER_S_PER_RPM,
            k_Sp=self.k_Sp,
            working_stroke=self.working_stroke,
        )

    def speed_limit_rpm(self) -> float:
        """Speed [rpm] at which V_np reaches ``max_V_np`` (V_np grows as n).

        Returns
        -------
        float
            The speed limit [rpm]; inf without a limit.

        Raises
        ------
        InputError
            If the design does not work.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> round(m.mechanisms["drive"].speed_limit_rpm(), 1)
        54.8
        """
        if self.max_V_np is None:
            return math.inf
        c = self.criteria(1.0)
        if not c.ok:
            raise InputError(
                f"mechanism {self.name!r}: the press design does not work ({c.status})"
            )
        return self.max_V_np / c.V_np if c.V_np > 0 else math.inf

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`: the criterion and its limit.

        Returns
        -------
        str
            The reason, "" without a limit.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> m.mechanisms["drive"].limit_reason()
        'V_np (the slider speed where the working stroke starts) reaches max_V_np = 5 mm/s'
        """
        if self.max_V_np is None:
            return ""
        return (
            "V_np (the slider speed where the working stroke starts) reaches "
            f"max_V_np = {1e3 * self.max_V_np:g} mm/s"
        )

    def analyze(self, ctx: Context) -> PressResult:
        """Its criteria and crank torque at the nominal speed.

        Parameters
        ----------
        ctx : Context
            What the machine computed before: the nominal speed among it.

        Returns
        -------
        PressResult
            The working-stroke criteria at the nominal speed and the crank torque (None
            without a force diagram or masses).

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> r = cm.machine.analyze(m, progress=False).mechanisms["drive"]
        >>> round(r.criteria.S_n, 4)
        0.1276
        """
        instance("ctx", ctx, Context)
        t = self.crank_torque()
        f = None
        if self.friction is not None and t is not None:
            f = press_friction(
                self.press,
                t.alpha,
                ctx.nominal_rpm * RAD_PER_S_PER_RPM,
                self.friction,
                force=self.force,
                slider_mass=self.slider_mass,
                rod_mass=self.rod_mass,
                k_Sp=self.k_Sp,
                working_stroke=self.working_stroke,
            )
        return PressResult(self, ctx, self.criteria(ctx.nominal_rpm), t, f)


def _force(table: Mapping[str, Any], name: str, ctx: TableContext) -> DeformationForce | None:
    """The ``deformation_force`` table of ``[mechanism.<name>]``, or None."""
    spec = table.get("deformation_force")
    if spec is None:
        return None
    where = ctx.where(name)
    if not isinstance(spec, Mapping):
        raise InputError(
            f"{where} deformation_force = {spec!r}: give a table {{s_above_bdc_m = [...], "
            "force_n = [...]} (heights above BDC [m], forces [N])"
        )
    _toml.check_keys(spec, set(FORCE_KEYS), ctx.source, f"[mechanism.{name}.deformation_force]")
    _toml.require(spec, FORCE_KEYS, f"{where} deformation_force")
    try:
        s, f = check_table(
            spec["s_above_bdc_m"],
            spec["force_n"],
            "deformation_force.s_above_bdc_m",
            "deformation_force.force_n",
            counted=True,
        )
    except InputError as e:
        raise InputError(f"{where}: {e}") from None
    return DeformationForce(s, f)


def _mass(table: Mapping[str, Any], key: str, where: str) -> float:
    """The mass ``table[key]`` [kg] ≥ 0 (0 where absent)."""
    if key not in table:
        return 0.0
    v = _toml.number(table, key, where, "[kg]")
    if v < 0:
        raise InputError(f"{where}: {key} = {v!r} must be ≥ 0 [kg]")
    return v


@dataclass(frozen=True)
class PressResult(PlainResult):
    """A press drive's working-stroke criteria at the machine's nominal speed and
    its crank torque (None without a force diagram or masses)."""

    mech: PressMechanism
    ctx: Context
    criteria: PressCriteria
    torque: PressTorque | None = None
    #: Its forces with friction at the nominal speed on the angles of ``torque``,
    #: None without a ``friction`` table.
    friction: PressFrictionForces | None = None

    @property
    def omega(self) -> float:
        """The nominal crank speed [rad/s]."""
        return self.ctx.nominal_rpm * RAD_PER_S_PER_RPM

    def shaft_torque(self) -> tuple[np.ndarray, np.ndarray, float, str | None] | None:
        """Its torque on the main shaft: (ω² part [N·m·s²], static part [N·m]) on
        3600 carrier angles ψ from BDC in the direction of rotation over [0, 360°);
        the cycle angle [deg] where BDC sits in the optimum (its ``phase``); the
        event the phase follows (None without one). None without a load or an optimum.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> a, b, phase, event = r.mechanisms["drive"].shaft_torque()
        >>> a.shape, event, phase == r.optimum.times["bottom"]
        ((3600,), 'bottom', True)
        """
        t, o = self.torque, self.ctx.optimum
        if t is None or o is None:
            return None
        phase = self.mech.phase
        static = t.static + self.friction_torque()
        return t.per_omega2, static, phase.shift_deg(o.times, 0.0), phase.event

    def scene(self, cycle_deg: Array) -> Scene | None:
        """The press at the main shaft's angles ``cycle_deg`` [deg], for the
        machine's animation: the carrier turned past BDC by its ``phase``, every
        joint (O, the planet's centre C, the pin P, the slider B) where
        :meth:`GearLeverPress.solve` puts it, the gears, the slider and its guide.

        Parameters
        ----------
        cycle_deg : ndarray of float
            The main shaft's angles [deg].

        Returns
        -------
        Scene or None
            Lengths in m; None when its phase follows an event and there is no optimum.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> s = r.mechanisms["drive"].scene(np.arange(0.0, 360.0, 30.0))
        >>> s.frames, s.links
        (12, (('O', 'C'), ('C', 'P'), ('P', 'B')))
        """
        from ._scene import press_scene

        return press_scene(self, cycle_angles(cycle_deg))

    def friction_torque(self) -> np.ndarray:
        """The torque friction adds on the crank at the nominal speed [N·m]: the
        driving torque with friction less the one without, on the angles of
        :attr:`torque` (zeros without friction or where a pose self-locks).

        As a linkage's: Coulomb friction goes with the forces, which change with
        the speed, so :meth:`shaft_torque` carries the nominal speed's friction
        torque in its static part at every speed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> t = cm.machine.analyze(m, progress=False).mechanisms["drive"].friction_torque()
        >>> t.shape, bool(t.mean() > 0)
        ((3600,), True)
        """
        t, f = self.torque, self.friction
        if t is None:
            return np.zeros(0)
        if f is None or f.self_locking.any():
            return np.zeros(t.alpha.size)
        out: np.ndarray = f.torque - f.torque_without
        return out

    def failures(self) -> list[str]:
        """What fails at the nominal speed: crank angles where friction self-locks
        the drive (no finite driving torque); empty otherwise.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> cm.machine.analyze(m, progress=False).mechanisms["drive"].failures()
        []
        """
        f = self.friction
        if f is None or not f.self_locking.any():
            return []
        deg = np.degrees(np.mod(-f.alpha[f.self_locking], 2.0 * math.pi))
        return [
            f"friction self-locks the press drive at {int(f.self_locking.sum())} crank angles "
            f"({deg.min():.1f}–{deg.max():.1f}° past BDC): no finite driving torque moves it "
            "there; lower the friction coefficients or the pins' radius"
        ]

    def efficiency(self) -> dict[str, Any] | None:
        """Its friction over one turn at the nominal speed, None without friction.

        The keys of a linkage's (:meth:`cyclomech.linkage.LinkageResult.efficiency`):
        ``cycle_efficiency`` = 1 − mean friction power / mean input power (None where
        a pose self-locks or the crank puts no work in), ``mean_friction_power_w``,
        ``mean_input_power_w`` (with friction) [W], ``mean_torque_nm``,
        ``peak_torque_nm`` with friction and ``peak_torque_nm_without`` [N·m],
        ``friction_power_by_element_w`` (the guide, the slider's pin, the planet's
        pin) and ``self_locking_crank_deg`` (the carrier's angles past BDC [deg]).

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> e = cm.machine.analyze(m, progress=False).mechanisms["drive"].efficiency()
        >>> 0.5 < e["cycle_efficiency"] < 1.0, e["mean_friction_power_w"] > 0
        (True, True)
        """
        f = self.friction
        if f is None:
            return None

        locked = np.degrees(np.mod(-f.alpha[f.self_locking], 2.0 * math.pi))
        return efficiency_entry(
            self.ctx.nominal_rpm,
            f.torque,
            f.torque_without,
            f.friction_power,
            f.input_power,
            f.losses,
            f.elements,
            locked,
        )

    def shaft_inertia(self) -> tuple[np.ndarray, float, str | None] | None:
        """Its reduced moment of inertia about the crank, for the machine's main
        shaft (:func:`cyclomech.dynamics.reduced`): (J [kg·m²] of the slider and the
        rod on the 3600 angles ψ of :meth:`shaft_torque`, its phase [deg], the
        event); None where :meth:`shaft_torque` is None. ½·dJ/dψ is the ω² part of
        the torque.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> j, phase, event = r.mechanisms["drive"].shaft_inertia()
        >>> j.shape, event
        ((3600,), 'bottom')
        """
        from ._torque import crank_inertia

        t, o = self.torque, self.ctx.optimum
        if t is None or o is None:
            return None
        m = self.mech
        j = crank_inertia(m.press, t.alpha, slider_mass=m.slider_mass, rod_mass=m.rod_mass)
        return j, m.phase.shift_deg(o.times, 0.0), m.phase.event

    def working_member(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, str] | None:
        """Its working member, the slider, for the main shaft's torsion
        (:func:`cyclomech.dynamics.torsion`): (its height, and its first and second
        derivatives in ψ, as (1, N) rows on the angles ψ of :meth:`shaft_inertia`,
        the unit "m"); None where that is None. (α = −ψ: dS/dψ = −dS/dα.)

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> s, ds, dds, unit = r.mechanisms["drive"].working_member()
        >>> s.shape, unit
        ((1, 3600), 'm')
        """
        t = self.torque
        if t is None or self.shaft_inertia() is None:
            return None
        k = self.mech.press.solve(t.alpha)
        return k.slider[:, 1][None].copy(), -k.ds[None], k.dds[None].copy(), "m"

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry, and with friction its ``friction`` entry
        (:meth:`efficiency`)."""
        t, m = self.torque, self.mech
        eff = self.efficiency()
        return {
            **({} if eff is None else {"friction": eff}),
            "mechanisms": {
                "kind": "press",
                "criteria": self.criteria.as_dict(),
                "speed_limit_rpm": self.ctx.own_limit_rpm(m.name),
                "crank_torque": None
                if t is None
                else {
                    "nominal_rpm": self.ctx.nominal_rpm,
                    "peak_torque_nm": t.peak_torque_nm(self.omega),
                    "lowest_torque_nm": float(np.min(t.torque_nm(self.omega))),
                    "peak_force_torque_nm": float(np.max(t.static)),
                    "energy_per_stroke_j": t.energy_per_stroke_j,
                    "peak_force_n": None if m.force is None else float(m.force.force.max()),
                    "slider_mass_kg": m.slider_mass,
                    "rod_mass_kg": m.rod_mass,
                },
            },
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        c = self.criteria
        return ["criterion", f"at {self.ctx.nominal_rpm:g} rpm"], [
            ["nominal stroke S_n [mm]", c.S_n * 1e3],
            ["working stroke S_p [mm]", c.S_p * 1e3],
            ["speed at the start of the working stroke V_np [mm/s]", c.V_np * 1e3],
            ["mean working speed V_cp [mm/s]", c.V_cp * 1e3],
            ["k_Vp = V_np/V_cp", c.k_Vp],
            ["k_Vmax = V_pmax/V_cp", c.k_Vmax],
            ["peak acceleration J_max [m/s²]", c.J_max],
            ["torque arm (max Π' in the working stroke) [mm]", c.torque_arm * 1e3],
            ["speed limit [rpm]", self.ctx.own_limit_rpm(self.mech.name)],
            *self._torque_rows(),
        ]

    def _torque_rows(self) -> list[list[Any]]:
        """The crank torque's rows of the report table (none without a load)."""
        t, m = self.torque, self.mech
        if t is None:
            return []
        M = t.torque_nm(self.omega)
        rows: list[list[Any]] = []
        if m.force is not None:
            rows += [
                ["peak deformation force [kN]", float(m.force.force.max()) * 1e-3],
                ["energy per stroke ∫F dS [J]", t.energy_per_stroke_j],
                ["peak torque of the force alone F·Π' [N·m]", float(np.max(t.static))],
            ]
        rows += [
            ["slider / rod mass [kg]", f"{m.slider_mass:g} / {m.rod_mass:g}"],
            ["peak crank torque (force + inertia) [N·m]", float(np.max(M))],
            ["lowest crank torque [N·m]", float(np.min(M))],
        ]
        return rows

    def figures(self, save: Save) -> None:
        """The drive at bottom dead centre and the slider's motion."""
        from .plot import plot_press

        k, mech = self.mech.name, self.mech
        res = plot_press(
            mech.press,
            0.0,
            show_motion=True,
            k_Sp=mech.k_Sp or self.criteria.k_Sp,
            title=f"{k}: gear-lever press",
        )
        fig = res[0].figure if isinstance(res, tuple) else res.figure
        save(
            fig,
            f"{k}_press",
            "The drive at bottom dead centre with the pin's hypotrochoid, and the "
            "slider's motion and transfer functions.",
        )
        if self.torque is not None:
            from ._torque_plot import plot_crank_torque

            axes = plot_crank_torque(self.torque, self.omega, force=mech.force)
            save(
                axes[0].figure,
                f"{k}_crank_torque",
                (
                    "The deformation-force diagram over the working stroke and "
                    if mech.force is not None
                    else ""
                )
                + f"the crank torque over the turn at {self.ctx.nominal_rpm:g} rpm: the "
                "force's part F·Π' on the working stroke, the slider's and the rod's "
                "inertia, and their sum (the press's own angle α, from BDC against the "
                "motion; on the main shaft it runs the other way).",
            )
