"""A cam design as a file describes it: `_design` part of :mod:`cyclomech.cam`.

One table (``[cam]`` of a cam file, or ``[mechanism.<name>]`` with
``kind = "cam"`` in a machine file) and its ``segment`` array of tables. Units are in
the key names: a translating or flat-faced follower's strokes, loads and rates are
in m and N (``stroke_m``, ``mass_kg``, ``spring_rate_n_per_m``, ``preload_n``,
``load_n``, ``max_vibration_m``); an oscillating follower's in degrees of arm
rotation and N·m (``stroke_deg``, ``inertia_kg_m2``, ``spring_rate_nm_per_rad``,
``preload_nm``, ``load_nm``, ``max_vibration_deg``).

**Motion programs.** A segment may take any law of
:data:`cyclomech.motion.SEGMENT_LAWS`, moving ends (``start_velocity_m_per_rad``,
``end_velocity_m_per_rad``: follower travel per radian of cam; an oscillating
follower's ``_deg_per_rad``) and a spline's point table (``points_m`` or
``points_deg``: rows [cam angle from the segment's start in degrees, displacement
from the cam's start]); ``kind`` still says which way the stroke goes. Such a cam
is built as a :class:`cyclomech.motion.Program` (joins continuous to the cam
table's ``continuity``, default velocity), and ``polydyne_rpm`` turns it into the
polydyne cam for that speed and the follower's ``mass_kg`` (``inertia_kg_m2``)
and natural frequency (stiffness = m·ω_n²).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import _keyrules, _toml
from .._arrays import flag, instances
from .._errors import InputError
from .._keyrules import Rule
from ._export import cutter_path
from ._followers import FlatFaced, OscillatingRoller, TranslatingRoller
from ._loads import Contact, FollowerLoads, MinPhaseAngles, default_pressure_angle_deg
from ._program import Cam
from ._rows import SEGMENT_KEYS, read_program, read_segments

__all__ = ["CAM_KEYS", "SEGMENT_KEYS", "CamDesign"]

_GEOMETRY = {
    "translating": ("base_radius_m", "roller_radius_m", "offset_m"),
    "flat": ("base_radius_m",),
    "oscillating": ("pivot_distance_m", "arm_length_m", "base_radius_m", "roller_radius_m"),
}
_TRANSLATING = {
    "velocity": "_m_per_rad",
    "points": "points_m",
    "mass": "mass_kg",
    "spring": "spring_rate_n_per_m",
    "preload": "preload_n",
    "stroke": "stroke_m",
    "load": "load_n",
    "vibration": "max_vibration_m",
}
_OSCILLATING = {
    "velocity": "_deg_per_rad",
    "points": "points_deg",
    "mass": "inertia_kg_m2",
    "spring": "spring_rate_nm_per_rad",
    "preload": "preload_nm",
    "stroke": "stroke_deg",
    "load": "load_nm",
    "vibration": "max_vibration_deg",
}
_ALL_GEOMETRY = frozenset(k for keys in _GEOMETRY.values() for k in keys)
_CONTACT = ("width_m", "follower_modulus_pa", "follower_poisson", "cam_modulus_pa", "cam_poisson")
#: The keys of a cam table (besides a machine's ``kind``; ``name`` and
#: ``rpm`` in a cam file).
CAM_KEYS = frozenset(
    {"follower", "closure", "segment", "max_stress_pa", "max_pressure_angle_deg"}
    | {"continuity", "polydyne_rpm"}
    | {k for keys in _GEOMETRY.values() for k in keys}
    | set(_TRANSLATING.values()) - {"stroke_m", "load_n", "_m_per_rad", "points_m"}
    | set(_OSCILLATING.values()) - {"stroke_deg", "load_nm", "_deg_per_rad", "points_deg"}
    | set(_CONTACT)
    | {"natural_frequency_hz", "damping_ratio"}
    | {"tool_radius_m"}
)
#: The plausibility rules of a cam table besides every key's by its unit suffix
#: (``cyclomech._keyrules.check``): a pressure-angle limit of a degree or two
#: admits almost no cam; 0.52 is far likelier 30° given in radians.
CAM_RULES = (
    Rule(
        "max_pressure_angle_deg",
        lambda v, t: v < 2.0,
        lambda v, t: (
            f"° admits almost no cam — did you give radians "
            f"(max_pressure_angle_deg = {math.degrees(v):.3g})?"
        ),
    ),
)


@dataclass(frozen=True)
class CamDesign:
    """A cam with what its bounds need: the cam, its loads, contact and limits.

    Built from a table by :meth:`from_table` (or a cam file by :meth:`from_toml`);
    each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    cam : Cam
        The cam.
    loads : FollowerLoads or None
        The follower's loads (None without a mass).
    contact : Contact or None
        The Hertz contact (None without a width).
    max_stress : float or None
        The largest Hertz stress [σ_H] [Pa] (None: not checked).
    max_pressure_angle_deg : float
        The largest pressure angle [α] [deg].
    vibration : tuple of (float, float, float) or None
        The follower's vibration data (natural frequency [Hz], damping ratio,
        amplitude limit [m or rad]), or None.
    arcs : tuple of (tuple of (str, str) or None)
        For each segment the cyclogram operation it is bound to (None where it is
        free).
    tool_radius : float or None, default None
        The radius [m] of the cutter the profile files give the centre path of
        (:func:`cyclomech.cam.cutter_path`), or None (none).

    Examples
    --------
    >>> import cyclomech as cm
    >>> d = cm.cam.CamDesign.from_table({"follower": "translating", "base_radius_m": 0.05,
    ...     "roller_radius_m": 0.01, "segment": [
    ...         {"kind": "rise", "angle_deg": 180, "stroke_m": 0.02},
    ...         {"kind": "return", "angle_deg": 180, "stroke_m": 0.02}]}, "[cam]")
    >>> d.max_pressure_angle_deg, d.loads is None
    (30.0, True)
    """

    cam: Cam
    loads: FollowerLoads | None
    contact: Contact | None
    max_stress: float | None
    max_pressure_angle_deg: float
    vibration: tuple[float, float, float] | None
    arcs: tuple[tuple[str, str] | None, ...]
    tool_radius: float | None = None

    @classmethod
    def from_table(
        cls,
        table: Mapping[str, Any],
        where: str,
        *,
        source: str | None = None,
        extra: frozenset[str] = frozenset(),
        arcs: bool = False,
        check: bool = True,
    ) -> CamDesign:
        """Parse a cam table (see the module's units for its keys).

        Parameters
        ----------
        table : Mapping of str to Any
            The cam table (``[cam]`` of a cam file, or a machine file's
            ``[mechanism.<name>]``), with its ``segment`` array of tables.
        where : str
            The table's name in errors ("file.toml: [cam]").
        source : str, optional
            The file, prefixed to ``where`` in errors; default None.
        extra : frozenset of str, default frozenset()
            Keys the caller reads itself (accepted, not read here).
        arcs : bool, default False
            Allow ``arc = [from, to]`` in segments (a machine file).
        check : bool, default True
            Warn of valid values a user may not have meant (a length in mm, an
            angle in radians); False where the table is read again and its own
            reading warns (a machine's cam stop reads its cam's table).

        Returns
        -------
        CamDesign
            The cam with its loads, contact and limits.

        Raises
        ------
        InputError
            If a key is unknown, missing, for the other kind of follower or read only
            beside a missing one, or a value is invalid (naming the file's key).

        Examples
        --------
        >>> CamDesign.from_table({"follower": "disc", "segment": []}, "[cam]")
        ... # doctest: +ELLIPSIS
        Traceback (most recent call last):
        cyclomech._errors.InputError: [cam]: follower = 'disc' must be one of 'translating', ...
        """
        extra = frozenset(instances("extra", extra, str))
        arcs = flag("arcs", arcs)
        check = flag("check", check)
        at = where if source is None else f"{source}: {where}"
        if isinstance(table, Mapping) and "friction" in table and "friction" not in extra:
            # Refused by name, not as an unknown key: whoever wrote it expects losses.
            # A machine file's cam mechanism reads it (cam/_kind.py), at its nominal speed.
            raise InputError(
                f"{at}: friction is not modelled for a cam file (no machine speed or "
                'efficiency to report); a machine file\'s cam mechanism (kind = "cam") '
                "takes a friction table; drop it here"
            )
        _toml.check_keys(table, CAM_KEYS | extra, source, where)
        _toml.require(table, ("follower", "segment"), at)
        kind = table["follower"]
        if not isinstance(kind, str) or kind not in _GEOMETRY:
            options = ", ".join(repr(k) for k in _GEOMETRY)
            raise InputError(f"{at}: follower = {kind!r} must be one of {options}")
        units = _OSCILLATING if kind == "oscillating" else _TRANSLATING
        wrong = set(_OSCILLATING.values() if kind != "oscillating" else _TRANSLATING.values())
        wrong -= {"_m_per_rad", "_deg_per_rad", "points_m", "points_deg"}
        stray = sorted(k for k in table if k in wrong)
        if stray:
            raise InputError(
                f"{at}: {stray[0]} is for the other kind of follower; a {kind} follower "
                f"takes {', '.join(v for v in units.values() if not v.startswith('_'))}"
            )
        unused = sorted(k for k in table if k in _ALL_GEOMETRY and k not in _GEOMETRY[kind])
        if unused:
            raise InputError(
                f"{at}: {unused[0]} is not used by a {kind} follower, which takes "
                f"{', '.join(_GEOMETRY[kind])}; remove it"
            )
        # A key read only beside another is refused without it: never ignored.
        needs = [
            (k, units["mass"], "the follower's loads") for k in (units["spring"], units["preload"])
        ]
        needs += [(k, "width_m", "the contact") for k in _CONTACT[1:]]
        rows = table["segment"] if isinstance(table["segment"], list) else []
        if any(isinstance(r, dict) and units["load"] in r for r in rows):
            needs.append((units["load"], units["mass"], "the follower's loads"))
        for key, need, what in needs:
            if need not in table and (key in table or key == units["load"]):
                where_ = f"a segment's {key}" if key == units["load"] else key
                raise InputError(
                    f"{at}: {where_} is read only with {need} ({what}); add {need} or remove it"
                )
        geometry = [k for k in _GEOMETRY[kind] if k != "offset_m"]
        _toml.require(table, geometry, at)
        g = {k: _toml.number(table, k, at, "[m]") for k in _GEOMETRY[kind] if k in table}
        closure = table.get("closure", "spring")
        try:
            follower: Any
            if kind == "translating":
                follower = TranslatingRoller(
                    g["base_radius_m"], g["roller_radius_m"], g.get("offset_m", 0.0)
                )
            elif kind == "flat":
                follower = FlatFaced(g["base_radius_m"])
            else:
                follower = OscillatingRoller(
                    g["pivot_distance_m"],
                    g["arm_length_m"],
                    g["base_radius_m"],
                    g["roller_radius_m"],
                )
            segments, bound = read_segments(table["segment"], units, arcs)
            program = read_program(table, table["segment"], segments, units)
            cam = Cam(segments if program is None else program, follower, closure)
        except InputError as e:
            raise _keyed(at, e, units) from None
        loads = _follower_loads(table, units, at)
        contact = None
        if "width_m" in table:
            c = {k: table[k] for k in _CONTACT if k in table}
            try:
                contact = Contact(
                    c["width_m"],
                    c.get("follower_modulus_pa", 2.1e11),
                    c.get("follower_poisson", 0.3),
                    c.get("cam_modulus_pa", 2.1e11),
                    c.get("cam_poisson", 0.3),
                )
            except InputError as e:
                raise _keyed(at, e, units) from None
        max_stress = _toml.optional_positive(table, "max_stress_pa", at, "[Pa]")
        if max_stress is not None and (loads is None or contact is None):
            raise InputError(
                f"{at}: max_stress_pa needs the follower's {units['mass']} and the contact's "
                "width_m (and the moduli, steel by default)"
            )
        alpha = default_pressure_angle_deg(follower)
        if "max_pressure_angle_deg" in table:
            alpha = _toml.number(table, "max_pressure_angle_deg", at, "[deg]")
            if not 0 < alpha < 90:
                raise InputError(f"{at}: max_pressure_angle_deg = {alpha!r} must be in (0, 90)")
        vibration = _vibration(table, at, units["vibration"], kind == "oscillating")
        if "polydyne_rpm" in table:
            cam = _polydyne(table, at, units, cam, loads, follower, closure)
        # Valid values a user may not have meant (a length in mm, an angle in
        # radians, a stress in MPa): the rules of every key by its unit suffix.
        if check:
            _keyrules.check(table, CAM_RULES, at)
            for i, row in enumerate(table["segment"]):
                _keyrules.check(row, (), f"{at} segment {i + 1}")
        _check_arcs(cam, bound, at)
        tool = _tool_radius(table, cam, at)
        return cls(cam, loads, contact, max_stress, alpha, vibration, bound, tool)

    @classmethod
    def from_toml(cls, path: str | Path) -> tuple[str, float | None, CamDesign]:
        """A cam file: its ``[cam]`` table, with an optional ``name`` and the speed ``rpm``.

        Parameters
        ----------
        path : str or Path
            The cam file (TOML).

        Returns
        -------
        name : str
            The cam's ``name`` (default: the file's stem).
        rpm : float or None
            The speed ``rpm`` of its loads [rpm] (None if not given).
        design : CamDesign
            The cam with its loads, contact and limits.

        Raises
        ------
        InputError
            If the file cannot be read or its ``[cam]`` table is missing or invalid.

        Examples
        --------
        >>> import cyclomech as cm
        >>> name, rpm, d = cm.cam.CamDesign.from_toml("examples/lifter_cam.toml")
        >>> name, rpm, len(d.cam.segments)
        ('loom lifter cam', 300.0, 4)
        """
        data, source = _toml.load(path)
        _toml.check_keys(data, {"cam"}, source, "the top level")
        _toml.require(data, ("cam",), source)
        table = data["cam"]
        if not isinstance(table, dict):
            raise InputError(f"{source}: [cam] must be a table")
        name = table.get("name", Path(str(path)).stem)
        if not isinstance(name, str):
            raise InputError(f"{source}: [cam]: name = {name!r} must be a string")
        rpm = _toml.optional_positive(table, "rpm", f"{source}: [cam]", "[rpm]")
        design = cls.from_table(table, "[cam]", source=source, extra=frozenset({"name", "rpm"}))
        return name, rpm, design

    def min_phase_angles(
        self, rpm: Any, *, segments: Any = None, n_threads: int | None = None
    ) -> MinPhaseAngles:
        """:meth:`Cam.min_phase_angles` with the design's loads, contact and limits.

        Parameters
        ----------
        rpm : float or array_like of float
            The cam speeds [rpm].
        segments : int or sequence of int, optional
            The indices of the rises and returns to bound; default None (all of them).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        MinPhaseAngles
            The smallest phase angles [deg], shape (speeds, segments, criteria).

        Raises
        ------
        InputError
            If a speed is not > 0 or an index of ``segments`` is not a rise or return.

        Examples
        --------
        >>> import cyclomech as cm
        >>> _, _, d = cm.cam.CamDesign.from_toml("examples/lifter_cam.toml")
        >>> d.min_phase_angles([300.0]).angle_deg.shape
        (1, 2, 5)
        """
        return self.cam.min_phase_angles(
            rpm,
            loads=self.loads,
            contact=self.contact,
            max_stress=self.max_stress,
            max_pressure_angle_deg=self.max_pressure_angle_deg,
            segments=segments,
            vibration=self.vibration,
            n_threads=n_threads,
        )


def _keyed(at: str, e: InputError, units: Mapping[str, str]) -> InputError:
    """``e`` from a constructor, located at ``at`` and naming the file's key (a
    constructor names its argument: ``roller_radius`` is ``roller_radius_m`` in a
    file)."""
    keys = {
        "base_radius": "base_radius_m",
        "roller_radius": "roller_radius_m",
        "offset": "offset_m",
        "pivot_distance": "pivot_distance_m",
        "arm_length": "arm_length_m",
        "width": "width_m",
        "follower_modulus": "follower_modulus_pa",
        "cam_modulus": "cam_modulus_pa",
        "mass": units["mass"],
        "spring_rate": units["spring"],
        "preload": units["preload"],
        "segment_loads": f"the segments' {units['load']}",
    }
    text = str(e)
    head = re.match(r"\w+", text)
    if head and head.group(0) in keys:
        text = keys[head.group(0)] + text[head.end() :]
    return InputError(f"{at}: {text}")


def _follower_loads(
    table: Mapping[str, Any], units: Mapping[str, str], at: str
) -> FollowerLoads | None:
    """The follower's mass, spring and segment loads, if the table gives its mass."""
    if units["mass"] not in table:
        return None
    try:
        return FollowerLoads(
            _toml.number(table, units["mass"], at, "[kg]"),
            table.get(units["spring"], 0.0),
            table.get(units["preload"], 0.0),
            tuple(
                _toml.number(row, units["load"], f"{at} segment {i + 1}", "")
                if units["load"] in row
                else 0.0
                for i, row in enumerate(table["segment"])
            ),
        )
    except InputError as e:
        raise _keyed(at, e, units) from None


def _check_arcs(cam: Cam, bound: tuple[tuple[str, str] | None, ...], at: str) -> None:
    """A program's segment whose shape changes with its angle takes no arc."""
    if cam.program is None:
        return
    for i, arc in enumerate(bound):
        if arc is not None and not cam.program.scalable[i]:
            raise InputError(
                f"{at} segment {i + 1}: arc = {list(arc)!r}, but its law "
                f"({cam.segments[i].law}) has moving ends, a constant velocity or a "
                "point table (or the cam is polydyne): its shape changes with its "
                "angle, so it cannot take a phase angle from the cyclogram"
            )


def _polydyne(
    table: Mapping[str, Any],
    at: str,
    units: Mapping[str, str],
    cam: Cam,
    loads: FollowerLoads | None,
    follower: Any,
    closure: str,
) -> Cam:
    """The polydyne cam of ``cam``'s program at ``polydyne_rpm`` (module docs)."""
    from ._vibration import polydyne

    rpm = _toml.number(table, "polydyne_rpm", at, "[rpm]")
    if loads is None or "natural_frequency_hz" not in table or cam.program is None:
        raise InputError(
            f"{at}: polydyne_rpm needs the follower's {units['mass']} and "
            "natural_frequency_hz (the stiffness is m·(2π·f_n)²)"
        )
    wn = 2.0 * math.pi * _toml.number(table, "natural_frequency_hz", at, "[Hz]")
    motion = polydyne(
        cam.program,
        follower_mass=loads.mass,
        stiffness=loads.mass * wn * wn,
        rpm=rpm,
        continuity=table.get("continuity", "velocity"),
    )
    return Cam(motion, follower, closure)


def _vibration(
    table: Mapping[str, Any], at: str, key: str, angular: bool
) -> tuple[float, float, float] | None:
    keys = ("natural_frequency_hz", key)
    given = [k for k in keys if k in table]
    if not given:
        if "damping_ratio" in table:
            raise InputError(f"{at}: damping_ratio needs natural_frequency_hz and {key}")
        return None
    if len(given) == 1:
        missing = next(k for k in keys if k not in table)
        raise InputError(f"{at}: {given[0]} needs {missing} too (the follower's vibration)")
    f = _toml.optional_positive(table, "natural_frequency_hz", at, "[Hz]")
    a = _toml.optional_positive(table, key, at, "[deg]" if angular else "[m]")
    zeta = _toml.number(table, "damping_ratio", at, "") if "damping_ratio" in table else 0.0
    if not 0.0 <= zeta < 1.0:
        # The residual vibration (cam._vibration) is the amplitude of a damped free
        # oscillation, R = √(q² + ((q' + ζτq)/(τ√(1 − ζ²)))²): it exists for ζ < 1 only.
        raise InputError(
            f"{at}: damping_ratio = {zeta!r} must be in [0, 1) (an under-damped follower: "
            "the residual vibration's amplitude is that of a damped free oscillation)"
        )
    assert f is not None and a is not None
    return f, zeta, math.radians(a) if angular else a


def _tool_radius(table: Mapping[str, Any], cam: Cam, at: str) -> float | None:
    """The table's ``tool_radius_m`` [m] (None without), checked against the cam: a
    knife edge has no cutter path, and the table is where to say so."""
    tool = _toml.optional_positive(table, "tool_radius_m", at, "[m]")
    if tool is not None:
        try:
            cutter_path(cam, tool, 3)
        except InputError as e:
            raise InputError(f"{at}: {e}") from None
    return tool
