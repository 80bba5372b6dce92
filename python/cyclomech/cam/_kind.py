"""The ``cam`` mechanism kind of a machine file: a disc cam on the main shaft (one
turn per cycle) whose rises and returns are bound to cyclogram operations, each
bound by its criteria (seed 000: σ_max(t) ≤ [σ_H] and a(t) ≤ [a] turned into lower
bounds on the phase angle; the pressure angle, undercut and jump besides)."""

from __future__ import annotations

import contextlib
import functools
import math
import warnings
from collections import OrderedDict
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from .. import _toml
from .._arrays import instance, speeds_rpm
from .._errors import CyclomechWarning, InputError
from .._files import file_stem, folder_target
from .._keydoc import KeyTable
from .._kind import (
    Array,
    Bound,
    BoundLaw,
    BoundsResult,
    Context,
    ExactBounds,
    Proportional,
    Save,
    TableContext,
    efficiency_entry,
    per_distinct_speed,
)
from .._scene import Scene, cycle_angles
from ..cyclogram import Arc
from ._design import CAM_KEYS, CamDesign
from ._export import DxfUnavailableError, write_profile_csv, write_profile_dxf
from ._followers import OscillatingRoller
from ._free import checks, own_limit
from ._friction import CamFriction, CamFrictionForces, cam_friction, friction_from_table
from ._keys import KEY_DOCS
from ._loads import CRITERIA
from ._program import Cam
from ._size import CamLimits, cam_size
from ._synthesize import CamSynthesis, synthesis_from_table

__all__ = ["CamMechanism", "CamResult"]

#: How each criterion reads in labels and reasons.
WORDS = {
    "pressure_angle": "pressure angle",
    "undercut": "undercut",
    "jump": "jump",
    "contact_stress": "σ_H",
    "vibration": "vibration",
}


@dataclass(frozen=True)
class _Constant:
    """A bound law that does not depend on the speed (a pressure angle, undercut)."""

    value: float

    def __call__(self, rpm: Array) -> Array:
        return np.full(np.shape(rpm), self.value)


#: The Hertz stress laws' answers (:class:`_PerSpeed`), by everything the Rust call
#: reads and the speeds it is asked: the same inputs give the same floats, so an
#: answer is kept and given again (at most :data:`_MEMO_SIZE`, the oldest dropped).
#: A sensitivity ranking (:func:`cyclomech.machine.sensitivities`) asks the cam's
#: laws of every variant the search's speeds; a variant of a key that leaves the
#: cam as it is (an operation's, another mechanism's, the friction's, a damping
#: ratio) has a cam mechanism of its own but the same law, and where it does not
#: move the limit its search asks the same speeds: on the loom two calls in three
#: (1542 → 576) were such repeats.
_MEMO: OrderedDict[tuple[Any, ...], Array] = OrderedDict()
_MEMO_SIZE = 1024


@dataclass(frozen=True)
class _PerSpeed:
    """A bound law solved at each speed (the Hertz stress): one Rust call per call,
    or the answer of an earlier call with the same inputs (:data:`_MEMO`)."""

    design: CamDesign
    segment: int
    column: int

    @functools.cached_property
    def _key(self) -> tuple[Any, ...] | None:
        """Every input of the Rust call but the speeds, numbers by their bits (so that
        0.0 and -0.0 differ; a NaN matches itself); None (no memo) for a cam of a
        motion program, whose kernel is not kept here by value."""
        d = self.design
        c = d.cam
        if c.program is not None:
            return None
        kind, params = c.follower._kernel_args()
        loads = None if d.loads is None else d.loads._kernel_args(len(c.segments))
        numbers = [x for g in c.segments for x in (g.angle_deg, g.stroke)]
        numbers += params
        if loads is not None:
            numbers += [*loads[:3], *loads[3]]
        if d.contact is not None:
            numbers += d.contact._kernel_args()
        numbers += [math.nan if d.max_stress is None else d.max_stress]
        numbers += [d.max_pressure_angle_deg]
        words = tuple((g.kind, g.law) for g in c.segments)
        flags = (kind, c.closure, loads is None, d.contact is None, d.max_stress is None)
        bits = np.array(numbers, dtype=np.float64).tobytes()
        return (words, flags, bits, self.segment, self.column)

    def __call__(self, rpm: Array) -> Array:
        # Without the speed-free criteria's vibration.
        d = self.design

        def solve(speeds: Array) -> Array:
            key = None if self._key is None else (self._key, speeds.tobytes())
            kept = None if key is None else _MEMO.get(key)
            if kept is not None:
                # Another thread may have dropped it meanwhile: then it is not moved.
                with contextlib.suppress(KeyError):
                    _MEMO.move_to_end(key)  # type: ignore[arg-type]
                return kept
            m = d.cam.min_phase_angles(
                speeds,
                loads=d.loads,
                contact=d.contact,
                max_stress=d.max_stress,
                max_pressure_angle_deg=d.max_pressure_angle_deg,
                segments=[self.segment],
            )
            out = m.angle_deg[:, 0, self.column].copy()
            if key is not None:
                out.flags.writeable = False
                _MEMO[key] = out
                while len(_MEMO) > _MEMO_SIZE:
                    with contextlib.suppress(KeyError):
                        _MEMO.popitem(last=False)
            return out

        return per_distinct_speed(rpm, solve)


@dataclass(frozen=True)
class CamMechanism(ExactBounds):
    """A disc cam on the main shaft whose rises and returns bound cyclogram operations.

    It holds its :class:`CamDesign` and, for each bound, the segment and criterion
    (``criteria``, in the order of :meth:`bounds`). A bound is labelled
    ``<criterion>[<name> <kind> <from>→<to>]`` in the optimum's shadow prices and the
    speed limit's reason. Built by :meth:`from_table`; each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    name : str
        The mechanism's name (the ``<name>`` of ``[mechanism.<name>]``).
    design : CamDesign
        The cam with its loads, contact and limits.
    criteria : tuple of tuple of (int, str)
        For each bound, in the order of :meth:`bounds`, the segment's index and
        the criterion (one of ``cyclomech.cam.CRITERIA``).
    friction : CamFriction, optional
        The follower's friction (the ``friction`` table, ``cyclomech/cam/_friction.py``),
        solved at the nominal speed; needs the follower's loads; None (default) without.
    synthesis : CamSynthesis, optional
        What the ``synthesize`` table asks (the base radius sized by the machine's run,
        :meth:`resize`); None (default) without: the file's base radius.
    sized : cyclomech.synthesis.CamSize, optional
        The last sizing (the radius chosen, the binding limit, the margins); None
        (default) before one.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
    >>> cam.kind, [b.label for b in cam.bounds()][:2]
    ('cam', ['pressure angle[lifter cam rise 1→3]', 'undercut[lifter cam rise 1→3]'])
    """

    # (ExactBounds: constraints and bound_laws from its bounds and laws; Unbounded's
    # defaults for what a cam does not add: sweep columns and
    # their values; its bounds are its own, below.)
    kind: ClassVar[str] = "cam"
    # Its tables' keys, its own first, for the machine-file format reference
    # (cyclomech._keydocs renders them; tests/package/test_keydocs.py holds them to the parser).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS
    keys: ClassVar[frozenset[str]] = frozenset(CAM_KEYS | {"kind", "friction", "synthesize"})
    fixed_keys: ClassVar[frozenset[str]] = frozenset(
        {"kind", "follower", "closure", "segment", "continuity", "friction", "synthesize"}
    )
    #: Sub-tables and lists whose numbers a sweep or a sensitivity may vary by a
    #: path (``segment.2.stroke_deg``, ``friction.pivot_mu``); not ``synthesize``,
    #: whose every variant would size the cam again.
    varied_tables: ClassVar[frozenset[str]] = frozenset({"segment", "friction"})
    json_groups: ClassVar[tuple[str, ...]] = ("cams",)
    name: str
    design: CamDesign
    criteria: tuple[tuple[int, str], ...]
    #: The follower's friction (the ``friction`` table), None without.
    friction: CamFriction | None = None
    #: What the ``synthesize`` table asks (the base radius sized), None without.
    synthesis: CamSynthesis | None = None
    #: The last sizing (a :class:`cyclomech.synthesis.CamSize`), None before one.
    sized: Any = None

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> CamMechanism:
        """Its ``[mechanism.<name>]`` table.

        A cam table (:class:`CamDesign`, units in the key names) whose segments may
        carry ``arc = [from, to]``, an operation of the cyclogram (one turn of the cam
        is one cycle).

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
        CamMechanism
            The cam with a bound per (bound segment, criterion that applies to it).

        Raises
        ------
        InputError
            If the cam table is invalid, the cyclogram's ``cycle_deg`` is not 360, or
            an ``arc`` is not an operation of the cyclogram or is bound twice.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/stb_loom.toml")
        >>> [c for c in m.mechanisms["lifter cam"].criteria if c[0] == 0]
        [(0, 'pressure_angle'), (0, 'undercut'), (0, 'contact_stress'), (0, 'vibration')]
        """
        instance("ctx", ctx, TableContext)  # a dict or a str: TypeError by name
        where = f"[mechanism.{name}]"
        at = ctx.where(name)
        _toml.must_be_table(table, ctx.source, where)
        synthesis = synthesis_from_table(table, at, str(table.get("follower", "")))
        if synthesis is not None:
            # The first round's cam: the largest radius asked (the loosest bounds);
            # the machine's run sizes it (resize) to a fixed point.
            table = {**table, "base_radius_m": synthesis.max_base_radius}
        extra = frozenset({"kind", "friction", "synthesize"})
        try:
            design = CamDesign.from_table(table, where, source=ctx.source, extra=extra, arcs=True)
        except InputError as e:
            if synthesis is None:
                raise
            raise InputError(
                f"{e} (synthesize: the first round's base radius is max_base_radius_m = "
                f"{synthesis.max_base_radius!r})"
            ) from None
        friction = friction_from_table(table, at, design.cam.follower)
        if friction is not None and design.loads is None:
            mass = (
                "inertia_kg_m2"
                if isinstance(design.cam.follower, OscillatingRoller)
                else ("mass_kg")
            )
            raise InputError(
                f"{at}: friction acts with the follower's forces, but the cam has no loads; "
                f"give the follower's {mass} (and its spring and loads), or drop the "
                "friction table"
            )
        if not math.isclose(ctx.cyclogram.cycle_deg, 360.0):
            raise InputError(
                f"{at}: a cam turns once per cycle, so the cyclogram's cycle_deg must be 360; "
                f"it is {ctx.cyclogram.cycle_deg!r}"
            )
        known = [op.arc for op in ctx.cyclogram.operations]
        seen: set[Arc] = set()
        for i, arc in enumerate(design.arcs):
            if arc is None:
                continue
            _toml.operation(arc, "arc", f"{at} segment {i + 1}", known)
            if arc in seen:
                raise InputError(f"{at} segment {i + 1}: arc = {list(arc)!r} is bound twice")
            seen.add(arc)
        return cls(name, design, _criteria(design), friction, synthesis)

    # ------------------------------------------------------------- its sizing
    @property
    def resizes(self) -> bool:
        """Whether the machine's run sizes this cam (it has a ``synthesize`` table).

        Returns
        -------
        bool
            True with a ``synthesize`` table.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"].resizes
        False
        """
        return self.synthesis is not None

    def resize(self, rpm: float, angles: Mapping[Arc, float]) -> CamMechanism | None:
        """The cam sized at the optimum's angles, or None where its size would not change.

        The machine's hook (``cyclomech/machine/_resize.py``): with a ``synthesize``
        table, the smallest base radius (and offset or pivot distance, if asked) that
        meets the cam's limits (``max_pressure_angle_deg``, undercut,
        ``max_stress_pa``) with its segments at ``angles``
        (:meth:`laid_out`) at ``rpm`` (:func:`cyclomech.synthesis.cam_size`). None
        without a ``synthesize`` table, or when every dimension is within 1e-9
        (relative) of this cam's: the fixed point.

        Parameters
        ----------
        rpm : float
            The machine's nominal speed [rpm].
        angles : Mapping of tuple of (str, str) to float
            The optimum's phase angles [deg], by arc.

        Returns
        -------
        CamMechanism or None
            The resized mechanism (its file's angles kept: the cyclogram sets them),
            or None.

        Raises
        ------
        InputError
            If no radius up to ``max_base_radius_m`` meets the limits (naming the one
            that fails and the best it reaches).

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/stb_loom.toml")
        >>> m.mechanisms["lifter cam"].resize(300.0, {}) is None   # no synthesize table
        True
        """
        rpm = float(speeds_rpm("rpm", rpm)[0]) if np.ndim(rpm) == 0 else math.nan
        if math.isnan(rpm):
            raise InputError("rpm must be one speed [rpm]")
        instance("angles", angles, Mapping)
        s = self.synthesis
        if s is None:
            return None
        d = self.design
        cam, _ = self.laid_out(angles)
        try:
            r = cam_size(
                cam,
                rpm,
                limits=CamLimits(d.max_pressure_angle_deg, d.max_stress),
                loads=d.loads,
                contact=d.contact,
                max_base_radius=s.max_base_radius,
                min_base_radius=s.min_base_radius,
                offset=s.offset,
                pivot_distance=s.pivot_distance,
            )
        except InputError as e:
            raise InputError(f"cam {self.name!r} (synthesize): {e}") from None
        new, old = r.cam.follower, d.cam.follower
        same = all(
            math.isclose(getattr(new, k), getattr(old, k), rel_tol=1e-9, abs_tol=1e-15)
            for k in ("base_radius", "offset", "pivot_distance")
            if hasattr(old, k)
        )
        if same and self.sized is not None:
            return None
        program = d.cam.segments if d.cam.program is None else d.cam.program
        design = replace(d, cam=Cam(program, new, d.cam.closure))
        return replace(self, design=design, sized=r)

    def resized_values(self) -> dict[str, float]:
        """The dimensions the last sizing chose [m], by the table's key names.

        Returns
        -------
        dict of str to float
            ``base_radius_m`` and the second dimension searched, if any; {} before a
            sizing.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"].resized_values()
        {}
        """
        r = self.sized
        if r is None:
            return {}
        return {f"{k}_m": float(getattr(r.cam.follower, k)) for k in r.searched}

    @property
    def sizing_status(self) -> str:
        """The last sizing's status: ``ok``, ``at_lower_bound``, ``infeasible`` (the
        sizing's own) or ``at_upper_bound``: an ``ok`` sizing whose base radius is
        ``max_base_radius_m`` within 1e-9 (relative, ``UPPER_TOL``): the bound, not a
        limit of the cam, set it, and the cyclogram stretched the phase angles to fit
        there; "" before a sizing.

        Returns
        -------
        str
            The status.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/lifter_cam_sized.toml"),
        ...                        progress=False)
        >>> r.mechanisms["lifter cam"].mech.sizing_status
        'ok'
        """
        r = self.sized
        if r is None:
            return ""
        radius = float(r.cam.follower.base_radius)
        if r.status == "ok" and radius >= r.max_base_radius * (1.0 - UPPER_TOL):
            return "at_upper_bound"
        return str(r.status)

    # ------------------------------------------------------------- its bounds
    def _arc(self, k: int) -> Arc:
        arc = self.design.arcs[k]
        assert arc is not None
        return arc

    def _where(self, k: int) -> str:
        a = self._arc(k)
        return f"{self.name} {self.design.cam.segments[k].kind} {a[0]}→{a[1]}"

    def bounds(self) -> tuple[Bound, ...]:
        """One bound per (bound segment, criterion that applies to it).

        Returns
        -------
        tuple of Bound
            The bounds, labelled ``<criterion>[<name> <kind> <from>→<to>]``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
        >>> cam.bounds()[2].arc, cam.bounds()[2].label
        (('1', '3'), 'σ_H[lifter cam rise 1→3]')
        """
        out = []
        for k, c in self.criteria:
            label = f"{WORDS[c]}[{self._where(k)}]"
            out.append(Bound(self._arc(k), label, label))
        return tuple(out)

    def laws(self) -> list[BoundLaw]:
        """Each bound's smallest angle [deg] against speed [rpm].

        Constant for the pressure angle and undercut, proportional for jump (exact),
        solved per speed for the stress, proportional for the residual vibration
        (exact).

        Returns
        -------
        list of BoundLaw
            One law per bound, in the order of :meth:`bounds`.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
        >>> [round(float(law(np.array([450.0]))[0]), 3) for law in cam.laws()][:4]
        [25.459, 27.058, 29.637, 30.978]
        """
        return list(self._laws)

    @functools.cached_property
    def _laws(self) -> tuple[BoundLaw, ...]:
        # Worked out once: variants of a sweep that share this cam share these law
        # objects, and the machine evaluates a shared law in one call.
        segs = sorted({k for k, _ in self.criteria})
        base = self.design.min_phase_angles([1.0], segments=segs).angle_deg[0]
        out: list[BoundLaw] = []
        for k, c in self.criteria:
            j, col = segs.index(k), CRITERIA.index(c)
            v = float(base[j, col])
            if c in ("jump", "vibration"):
                out.append(Proportional(math.inf if math.isnan(v) else v))
            elif c == "contact_stress":
                out.append(_PerSpeed(self.design, k, col))
            else:
                out.append(_Constant(v))
        return tuple(out)

    @functools.cached_property
    def _own_limit(self) -> tuple[float, str]:
        return own_limit(self.name, self.design)

    def speed_limit_rpm(self) -> float:
        """The highest speed [rpm] its rises and returns without an operation allow.

        The segments bound to operations limit the speed through the cyclogram's
        bounds. The others keep their file's angles, so each criterion that applies
        to them (as to a bound segment) sets the cam's own limit: the jump of a
        spring-closed follower and the residual vibration (exactly proportional to
        the speed: their angle at a reference speed scaled), σ_H (solved in the
        speed, taken as growing with it), and the pressure angle and undercut
        (geometry alone: 0 rpm, the machine works at no speed, where they fail).

        Returns
        -------
        float
            The speed [rpm]; inf where every rise and return is bound to an operation
            or nothing binds.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/stb_loom.toml")
        >>> m.mechanisms["lifter cam"].speed_limit_rpm()
        inf
        """
        return self._own_limit[0]

    def limit_reason(self) -> str:
        """Why :meth:`speed_limit_rpm` is what it is: the segment and the criterion.

        Returns
        -------
        str
            "" where it has no limit.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"].limit_reason()
        ''
        """
        return self._own_limit[1]

    # ------------------------------------------------------------- results
    def laid_out(self, angles: Mapping[Arc, float]) -> tuple[Cam, str]:
        """The cam with each bound segment at its operation's angle.

        The difference is taken from the next dwell (cyclically).

        Parameters
        ----------
        angles : Mapping of tuple of (str, str) to float
            The operations' angles [deg] (the optimum's), by arc.

        Returns
        -------
        cam : Cam
            The cam laid out; the file's cam when that leaves no dwell or the cam is
            invalid.
        reason : str
            Why the file's cam is returned ("" when laid out).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
        >>> c, why = cam.laid_out({("1", "3"): 60.0})
        >>> c.segments[0].angle_deg, c.segments[3].angle_deg, why
        (60.0, 190.0, '')
        """
        instance("angles", angles, Mapping)
        segs = list(self.design.cam.segments)
        n = len(segs)
        for k, arc in enumerate(self.design.arcs):
            if arc is None or arc not in angles:
                continue
            delta = float(angles[arc]) - segs[k].angle_deg
            j = next((i % n for i in range(k + 1, k + n) if segs[i % n].kind == "dwell"), None)
            if j is None or segs[j].angle_deg - delta <= 0.0:
                return self.design.cam, (
                    f"segment {k + 1} at {angles[arc]:.4g}° leaves no dwell to take up "
                    f"{delta:+.4g}°: shown with the file's angles"
                )
            segs[k] = replace(segs[k], angle_deg=float(angles[arc]))
            segs[j] = replace(segs[j], angle_deg=segs[j].angle_deg - delta)
        try:
            return Cam(segs, self.design.cam.follower, self.design.cam.closure), ""
        except InputError as e:
            return self.design.cam, f"the cam at the optimum's angles is invalid ({e})"

    def analyze(self, ctx: Context) -> CamResult:
        """Its results at the nominal speed and its bounds on the speed grid.

        The cam is laid out at the optimum's angles. A
        :class:`cyclomech.CyclomechWarning` lists what fails at the nominal speed
        (:meth:`CamResult.problems`).

        Parameters
        ----------
        ctx : Context
            What the machine computed before (nominal speed, optimum, bounds).

        Returns
        -------
        CamResult
            Its results.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> res = r.mechanisms["lifter cam"]
        >>> res.max_stress_pa < res.mech.design.max_stress
        True
        """
        instance("ctx", ctx, Context)
        n = ctx.nominal_rpm
        angles = {} if ctx.optimum is None else ctx.optimum.angles
        cam, note = self.laid_out(angles)
        d = self.design
        theta = np.radians(np.arange(3600) * 0.1)
        kin = cam.solve(theta)
        loads = None if d.loads is None else cam.loads(theta, n, d.loads, d.contact)
        stress = math.nan if loads is None or d.contact is None else np.nanmax(loads.contact_stress)
        undercut = loads is not None and np.isnan(loads.contact_stress[~loads.separated]).any()
        if undercut and d.contact is not None:
            # NaN where the follower touches the cam: an undercut profile, no Hertz
            # contact (NaN where it has left the cam only says there is no contact).
            stress = math.inf
        segs = sorted({k for k, _ in self.criteria})
        at = d.min_phase_angles([n], segments=segs) if segs else None
        fr = None
        if self.friction is not None and d.loads is not None:
            # On the 3600 angles of shaft_torque(), at the nominal speed.
            grid = np.arange(3600, dtype=np.float64) * (2.0 * math.pi / 3600)
            fr = cam_friction(cam, grid, n, d.loads, self.friction)
        result = CamResult(
            mech=self,
            ctx=ctx,
            cam=cam,
            layout_note=note,
            max_pressure_angle_deg=float(np.degrees(np.abs(kin.pressure_angle).max())),
            max_stress_pa=float(stress),
            jump_rpm=math.inf if d.loads is None else cam.jump_rpm(d.loads)[0],
            undercut_deg=cam.undercut_angles_deg(3600),
            at_nominal=at,
            friction=fr,
        )
        upper = _upper_note(self)
        if upper:
            msg = f"cam {self.name!r} (synthesize): {upper}"
            warnings.warn(msg, CyclomechWarning, stacklevel=2)
        problems = result.problems()
        if problems:
            warnings.warn(
                f"cam {self.name!r} at {n:g} rpm: " + "; ".join(problems),
                CyclomechWarning,
                stacklevel=2,
            )
        return result


#: A sized cam is at its upper bound (status ``at_upper_bound``) when its base radius
#: is within this (relative) of ``max_base_radius_m``: the tolerance at which
#: :meth:`CamMechanism.resize` takes a sizing as its fixed point (the sizing's own
#: root is refined to 1e-13 relative, so a radius pressed against the bound reads
#: within it, and one 1e-9 below has room the sizing did not need).
UPPER_TOL = 1e-9


def _upper_note(m: CamMechanism) -> str:
    """What a cam sized at its upper bound means, in words ("" if it is not)."""
    r = m.sized
    if m.sizing_status != "at_upper_bound":
        return ""
    return (
        f"at its upper bound max_base_radius_m = {r.max_base_radius * 1e3:.4g} mm: the "
        "phase angles were stretched to fit; raise the bound to shorten them"
    )


def _sizing_json(m: CamMechanism) -> dict[str, Any]:
    """The ``sizing`` entry of a sized cam's ``cams`` entry: what was chosen and why."""
    r = m.sized
    return {
        **m.resized_values(),
        "searched": list(r.searched),
        "at_rpm": r.rpm,
        "status": m.sizing_status,
        "binding": r.binding,
        "ratios": r.ratios,
        "margins": r.margins,
        "min_base_radius_m": r.min_base_radius,
        "max_base_radius_m": r.max_base_radius,
        # Only where it says something: what the bound did.
        **({"note": note} if (note := _upper_note(m)) else {}),
    }


def _sizing_text(m: CamMechanism) -> str:
    """A sized cam's report row: the dimensions chosen and the limit that binds."""
    r = m.sized
    dims = ", ".join(f"{k} = {v * 1e3:.4g} mm" for k, v in m.resized_values().items())
    why = (
        f"the smallest radius searched ({r.min_base_radius * 1e3:.4g} mm) already holds"
        if r.status == "at_lower_bound"
        else f"{WORDS.get(r.binding, r.binding)} binds"
    )
    upper = _upper_note(m)
    if upper:
        why = f"{upper} ({why} there)"
    margins = ", ".join(f"{WORDS.get(k, k)} {v:.3g}" for k, v in r.margins.items())
    return f"{dims} at {r.rpm:g} rpm: {why} (margins {margins})"


def _criteria(design: CamDesign) -> tuple[tuple[int, str], ...]:
    """The (segment, criterion) pairs that bound a cam's operations."""
    return tuple(
        (k, c) for k, arc in enumerate(design.arcs) if arc is not None for c in checks(design, k)
    )


#: The relative tolerance of a cam's checks at the nominal speed
#: (:meth:`CamResult.failures`): a bound met with equality reads within it.
CHECK_TOL = 1e-6


@dataclass(frozen=True)
class CamResult(BoundsResult):
    """A cam's results.

    Built by :meth:`CamMechanism.analyze`; each parameter is kept as the attribute
    of the same name.

    Parameters
    ----------
    mech : CamMechanism
        The cam mechanism.
    ctx : Context
        What the machine computed before it.
    cam : Cam
        The cam laid out at the optimum.
    layout_note : str
        Why it is not laid out at the optimum, if not ("" when it is).
    max_pressure_angle_deg : float
        The largest pressure angle at the nominal speed [deg].
    max_stress_pa : float
        The largest Hertz stress at the nominal speed [Pa] (inf where undercut,
        NaN without contact data).
    jump_rpm : float
        The jump speed [rpm] (inf for a groove or without loads).
    undercut_deg : list of tuple of (float, float)
        The undercut runs of cam angles [deg].
    at_nominal : MinPhaseAngles or None
        Its bound segments' smallest phase angles at the nominal speed (None
        without a bound segment).
    friction : CamFrictionForces or None
        Its follower's forces with friction at the nominal speed on the 3600 cam
        angles of :meth:`shaft_torque`; None (default) without a ``friction`` table.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> res = r.mechanisms["lifter cam"]
    >>> round(res.max_pressure_angle_deg, 3), res.jump_rpm, res.undercut_deg
    (45.0, inf, [])
    """

    mech: CamMechanism
    ctx: Context
    cam: Cam
    layout_note: str
    max_pressure_angle_deg: float
    max_stress_pa: float
    jump_rpm: float
    undercut_deg: list[tuple[float, float]]
    at_nominal: Any
    friction: CamFrictionForces | None = None

    def problems(self) -> list[str]:
        """What fails or is not as asked at the nominal speed on the cam as laid out:
        the layout (a bound segment the next dwell cannot take up) and the checks
        that fail (:meth:`failures` but friction's).

        The bound segments hold their criteria by construction; the free ones, the
        dwells and the layout may not. The machine warns with them.

        Returns
        -------
        list of str
            One sentence per problem ([] when nothing fails).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter cam"].problems()
        []
        """
        return ([self.layout_note] if self.layout_note else []) + self._failing()

    def _failing(self) -> list[str]:
        """The cam's checks that fail at the nominal speed, beyond 1e-6 (``CHECK_TOL``)."""
        d, out, tol = self.mech.design, [], 1.0 + CHECK_TOL
        if self.max_pressure_angle_deg > d.max_pressure_angle_deg * tol:
            out.append(
                f"the pressure angle reaches {self.max_pressure_angle_deg:.4g}° "
                f"> [α] = {d.max_pressure_angle_deg:g}°"
            )
        if d.max_stress is not None and not self.max_stress_pa <= d.max_stress * tol:
            out.append(
                f"σ_H reaches {self.max_stress_pa / 1e6:.4g} MPa "
                f"> [σ_H] = {d.max_stress / 1e6:g} MPa"
                + (" (an undercut profile)" if math.isinf(self.max_stress_pa) else "")
            )
        if self.undercut_deg:
            runs = ", ".join(f"{a:g}–{b:g}°" for a, b in self.undercut_deg)
            out.append(f"the profile is undercut at {runs}")
        if self.jump_rpm * tol < self.ctx.nominal_rpm:
            out.append(f"the follower jumps off the cam above {self.jump_rpm:.4g} rpm")
        return out

    def failures(self) -> list[str]:
        """What fails at the nominal speed and must not ship: ``cyclomech run`` exits 3.

        A check of the cam as laid out at the optimum that fails (the pressure
        angle above [α], σ_H above [σ_H], an undercut profile, the follower leaving
        the cam below the nominal speed: beyond 1e-6 relative (``CHECK_TOL``), since
        the bounds are solved finer than the 3600 angles checked here), and cam
        angles where friction self-locks the follower (no finite contact force
        moves it), as a linkage's; empty otherwise.

        Returns
        -------
        list of str
            One line per failure (empty when nothing fails).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter cam"].failures()
        []
        """
        out = self._failing()
        f = self.friction
        if f is None or not f.self_locking.any():
            return out
        deg = np.degrees(f.theta[f.self_locking])
        return [
            *out,
            f"friction self-locks the follower of {self.mech.name!r} at cam angles "
            f"{deg.min():.1f}–{deg.max():.1f}° ({int(f.self_locking.sum())} of "
            f"{f.theta.size} angles): no finite contact force moves it there; lower the "
            "friction coefficients or the pivot's radius, or the pressure angle",
        ]

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry and its ``cams`` entry of ``results.json``.

        Returns
        -------
        dict of str to dict
            ``{"mechanisms": …, "cams": …}`` (angles in deg, stresses in Pa, speeds in
            rpm).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter cam"].json()["mechanisms"]
        {'kind': 'cam', 'arcs': [['1', '3'], ['3', '7'], ['7', '10.1']]}
        """
        m, d = self.mech, self.mech.design
        bounds = {b.label: self.ctx.bounds[b.name] for b in m.bounds()}
        eff = self.efficiency()
        return {
            **({} if eff is None else {"friction": eff}),
            "mechanisms": {"kind": "cam", "arcs": [list(a) for a in d.arcs if a is not None]},
            "cams": {
                "follower": type(d.cam.follower).__name__,
                "closure": d.cam.closure,
                "segment_angles_deg": [g.angle_deg for g in self.cam.segments],
                "layout_note": self.layout_note,
                "max_pressure_angle_deg": self.max_pressure_angle_deg,
                "limit_pressure_angle_deg": d.max_pressure_angle_deg,
                "max_stress_pa": self.max_stress_pa,
                "limit_stress_pa": d.max_stress,
                "jump_rpm": self.jump_rpm,
                "undercut_deg": self.undercut_deg,
                "speed_rpm": self.ctx.rpm,
                "min_phase_deg": bounds,
                **({} if m.sized is None else {"sizing": _sizing_json(m)}),
            },
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table.

        Returns
        -------
        header : list of str
            ``["quantity", "value"]``.
        rows : list of list
            The follower, segments at the optimum, largest pressure angle and Hertz
            stress (with their limits), jump speed, undercut and the bound segments'
            smallest angles.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.mechanisms["lifter cam"].table()[1][0]
        ['follower, closure', 'oscillating roller, groove']
        """
        m, d, n = self.mech, self.mech.design, self.ctx.nominal_rpm
        rows: list[list[Any]] = [
            ["follower, closure", f"{d.cam.follower.title}, {d.cam.closure}"],
            [
                "segments at the optimum [deg]",
                ", ".join(f"{g.kind} {g.angle_deg:.4g}" for g in self.cam.segments),
            ],
        ]
        if self.layout_note:
            rows.append(["layout", self.layout_note])
        if m.sized is not None:
            rows.append(["sized (synthesize)", _sizing_text(m)])
        rows += [
            [
                f"largest pressure angle at {n:g} rpm [deg] (limit)",
                f"{self.max_pressure_angle_deg:.4g} ({d.max_pressure_angle_deg:g})",
            ],
            [
                f"largest Hertz stress at {n:g} rpm [MPa] (limit)",
                f"{self.max_stress_pa / 1e6:.4g}"
                + ("" if d.max_stress is None else f" ({d.max_stress / 1e6:g})"),
            ],
            ["jump speed [rpm]", "none (groove)" if d.cam.closure == "groove" else self.jump_rpm],
            ["undercut", ", ".join(f"{a:g}–{b:g}°" for a, b in self.undercut_deg) or "none"],
        ]
        if self.at_nominal is not None:
            for j, k in enumerate(self.at_nominal.segments):
                row = self.at_nominal.angle_deg[0, j]
                text = ", ".join(
                    f"{WORDS[c]} " + ("none" if row[i] == 0 else f"{row[i]:.4g}")
                    for i, c in enumerate(CRITERIA)
                    if (k, c) in m.criteria
                )
                rows.append([f"smallest angle of {m._where(k)} at {n:g} rpm [deg]", text])
        return ["quantity", "value"], rows

    def shaft_torque(self) -> tuple[Array, Array, float, str] | None:
        """Its torque on the main shaft, for the machine's main shaft.

        Returns
        -------
        tuple of (ndarray, ndarray, float, str) or None
            (ω² part [N·m·s²], static part [N·m], on 3600 cam angles; its phase [deg]:
            the first bound segment starts at its operation's start in the optimum;
            that operation's start event, which the phase follows); None without the
            follower's loads or an optimum.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> per_omega2, static, phase_deg, event = r.mechanisms["lifter cam"].shaft_torque()
        >>> per_omega2.shape, phase_deg, event
        ((3600,), 0.0, '1')
        """
        d, at = self.mech.design, self._shaft_phase()
        if d.loads is None or at is None:
            return None
        t = self.cam.shaft_torque(d.loads, samples=3600)
        return t.per_omega2, t.static + self.friction_torque(), at[0], at[1]

    def friction_torque(self) -> Array:
        """The torque friction adds on the cam shaft at the nominal speed [N·m]: the
        driving torque with friction less the one without, on the 3600 cam angles of
        :meth:`shaft_torque` (zeros without friction or where a pose self-locks).

        As a linkage's: Coulomb friction goes with the contact force, which changes
        with the speed, so :meth:`shaft_torque` carries the nominal speed's friction
        torque in its static part at every speed.

        Returns
        -------
        ndarray of float, shape (3600,)
            The added torque [N·m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"),
        ...                        progress=False).mechanisms["lifter cam"]
        >>> t = r.friction_torque()
        >>> t.shape, bool(t.mean() > 0)
        ((3600,), True)
        """
        f = self.friction
        if f is None or f.self_locking.any():
            return np.zeros(3600)
        out: Array = f.torque - f.torque_without
        return out

    def efficiency(self) -> dict[str, Any] | None:
        """Its friction over one turn at the nominal speed, None without friction.

        The keys of a linkage's (``LinkageResult.efficiency()``):
        ``cycle_efficiency`` = 1 − mean friction power / mean input power (None where
        a pose self-locks or the shaft puts no work in), ``mean_friction_power_w``,
        ``mean_input_power_w`` (with friction) [W], ``mean_torque_nm``,
        ``peak_torque_nm`` with friction and ``peak_torque_nm_without`` [N·m],
        ``friction_power_by_element_w`` (the pivot or guide, the roller's pin) and
        ``self_locking_crank_deg`` (the cam angles where it self-locks [deg]).

        Returns
        -------
        dict of str to Any or None
            The keys above; None without friction.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"),
        ...                        progress=False).mechanisms["lifter cam"]
        >>> e = r.efficiency()
        >>> 0.0 < e["cycle_efficiency"] < 1.0, e["mean_friction_power_w"] > 0
        (True, True)
        """
        f = self.friction
        if f is None:
            return None

        return efficiency_entry(
            self.ctx.nominal_rpm,
            f.torque,
            f.torque_without,
            f.friction_power,
            f.input_power,
            f.losses,
            f.elements,
            np.degrees(f.theta[f.self_locking]),
        )

    def shaft_inertia(self) -> tuple[Array, float, str] | None:
        """Its reduced moment of inertia about the cam shaft, for the machine's
        main shaft (:func:`cyclomech.dynamics.reduced`).

        The follower's kinetic energy is ½·m·ṡ² = ½·(m·s′(θ)²)·ω², so
        J(θ) = m·s′² (the follower's mass, or its moment of inertia for an
        oscillating one, as :meth:`shaft_torque` takes it), and ½·dJ/dθ = m·s′·s″
        is the ω² part of the torque.

        Returns
        -------
        tuple of (ndarray, float, str) or None
            (J [kg·m²] on the 3600 cam angles of :meth:`shaft_torque`, its phase
            [deg], the event); None where :meth:`shaft_torque` is None.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> j, phase_deg, event = r.mechanisms["lifter cam"].shaft_inertia()
        >>> j.shape, bool(j.min() >= 0), phase_deg, event
        ((3600,), True, 0.0, '1')
        """
        d, at = self.mech.design, self._shaft_phase()
        if d.loads is None or at is None:
            return None
        theta = np.arange(3600, dtype=np.float64) * (2.0 * math.pi / 3600)
        ds = self.cam.solve(theta).ds
        return d.loads.mass * ds * ds, at[0], at[1]

    def working_member(self) -> tuple[Array, Array, Array, str] | None:
        """Its working member, the follower, for the main shaft's torsion
        (:func:`cyclomech.dynamics.torsion`): (s, s′, s″ as (1, N) rows on the 3600 cam
        angles of :meth:`shaft_inertia`, the unit: "m", or "rad" for an oscillating
        follower); None where :meth:`shaft_inertia` is None.

        Returns
        -------
        tuple of (ndarray, ndarray, ndarray, str) or None
            As above.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> s, ds, dds, unit = r.mechanisms["lifter cam"].working_member()
        >>> s.shape, unit
        ((1, 3600), 'rad')
        """
        if self.shaft_inertia() is None:
            return None
        theta = np.arange(3600, dtype=np.float64) * (2.0 * math.pi / 3600)
        k = self.cam.solve(theta)
        unit = "rad" if isinstance(self.mech.design.cam.follower, OscillatingRoller) else "m"
        return k.s[None], k.ds[None], k.dds[None], unit

    def scene(self, cycle_deg: Array) -> Scene | None:
        """The cam and its follower at the main shaft's angles ``cycle_deg`` [deg],
        for the machine's animation: the profile turned to the cam's angle there
        (from its phase in the optimum) and the follower where :meth:`Cam.solve`
        puts it.

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
        >>> s = r.mechanisms["lifter cam"].scene(np.arange(0.0, 360.0, 30.0))
        >>> s.frames, sorted(s.bodies)
        (12, ['cam', 'groove', 'roller'])
        """
        from ._scene import cam_scene

        return cam_scene(self, cycle_angles(cycle_deg))

    def _shaft_phase(self) -> tuple[float, str] | None:
        """(its phase [deg]: the first bound segment starts at its operation's start
        in the optimum; that operation's start event); None without an optimum."""
        d, o = self.mech.design, self.ctx.optimum
        if o is None:
            return None
        k = next(i for i, a in enumerate(d.arcs) if a is not None)
        arc = d.arcs[k]
        assert arc is not None
        start = sum(g.angle_deg for g in self.cam.segments[:k])
        return float(o.times[arc[0]]) - start, arc[0]

    def files(self, folder: Path) -> list[Path]:
        """Write the cam's profile at the optimised timing into ``folder``: the part
        to make.

        ``<name>_profile.csv`` (:func:`cyclomech.cam.write_profile_csv`: 3600 cam
        angles, lengths in m) and, with ezdxf installed, ``<name>_profile.dxf``
        (:func:`cyclomech.cam.write_profile_dxf`, mm), with the centre path of a
        cutter of the table's ``tool_radius_m`` when it gives one — the same files
        ``cyclomech cam`` writes for a cam file with these phase angles. Nothing when the cam
        is not laid out at the optimum (``layout_note`` says why; the report shows
        it): a profile at another timing is not the part to make.

        Parameters
        ----------
        folder : str or Path
            The folder (created if missing).

        Returns
        -------
        list of Path
            The files written.

        Examples
        --------
        >>> import tempfile, pathlib, cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> [p.name for p in r.mechanisms["lifter cam"].files(pathlib.Path(tempfile.mkdtemp()))]
        ['lifter_cam_profile.csv', 'lifter_cam_profile.dxf']
        """
        folder = folder_target("folder", folder)
        if self.layout_note:
            return []
        folder.mkdir(parents=True, exist_ok=True)
        stem = file_stem(self.mech.name)
        tool = self.mech.design.tool_radius
        out = [write_profile_csv(self.cam, folder / f"{stem}_profile.csv", tool_radius=tool)]
        # The DXF is the dxf extra's: without ezdxf the CSV holds the same geometry.
        with contextlib.suppress(DxfUnavailableError):
            out.append(
                write_profile_dxf(self.cam, folder / f"{stem}_profile.dxf", tool_radius=tool)
            )
        return out

    def figures(self, save: Save) -> None:
        """Draw its figures and hand each to ``save``.

        The cam, its SVAJ diagram, the stress and pressure angle along the cycle and
        its smallest phase angles against speed.

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
        >>> r.mechanisms["lifter cam"].figures(lambda fig, stem, caption: stems.append(stem))
        >>> stems
        ['lifter_cam_cam', 'lifter_cam_svaj', 'lifter_cam_along_cycle', 'lifter_cam_min_phase']
        >>> plt.close("all")
        """
        from .plot import plot_along_cycle, plot_cam, plot_min_phase_angles, plot_svaj

        m, d, k, n = self.mech, self.mech.design, self.mech.name, self.ctx.nominal_rpm
        stem = file_stem(k)
        stress = d.loads is not None and d.contact is not None
        ax = plot_cam(
            self.cam,
            color_by="contact_stress" if stress else "pressure_angle",
            loads=d.loads,
            contact=d.contact,
            rpm=n if stress else None,
            title=f"{k} at the optimum, {n:g} rpm",
        )
        save(
            ax.figure,
            f"{stem}_cam",
            "The cam laid out at the optimum's angles (each bound rise or return at its "
            "operation's angle), in its own frame: the profile coloured by "
            + ("the Hertz stress on the loaded flank" if stress else "the pressure angle")
            + ", the pitch curve dashed, the roller at a few cam angles."
            + (f" {self.layout_note}." if self.layout_note else ""),
        )
        axes = plot_svaj(self.cam, rpm=n, title=f"{k}: displacement and its derivatives")
        save(
            axes[0].figure,
            f"{stem}_svaj",
            f"Displacement, velocity, acceleration and jerk of the follower at {n:g} rpm "
            "over one turn of the cam (exact derivatives of the laws).",
        )
        if d.loads is not None:
            axes = plot_along_cycle(
                self.cam,
                n,
                d.loads,
                d.contact,
                max_stress=d.max_stress,
                max_pressure_angle_deg=d.max_pressure_angle_deg,
                title=f"{k} along the cycle at {n:g} rpm",
            )
            save(
                axes[0].figure,
                f"{stem}_along_cycle",
                "The pressure angle, the normal force, the Hertz stress and the shaft "
                f"torque over one turn at {n:g} rpm, limits dashed.",
            )
        segs = sorted({j for j, _ in m.criteria})
        if segs:
            mins = d.min_phase_angles(self.ctx.rpm, segments=segs)
            labels = [m._where(j) for j in segs]
            nominal = [self.cam.segments[j].angle_deg for j in segs]
            ax = plot_min_phase_angles(
                mins,
                labels=labels,
                nominal_deg=nominal,
                title=f"{k}: smallest phase angles against speed",
            )
            save(
                ax.figure,
                f"{stem}_min_phase",
                "Each bound rise or return's smallest phase angle against speed per "
                "criterion (the bound, the largest, bold); horizontal: its angle at the "
                "optimum.",
            )
