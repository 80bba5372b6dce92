"""A cam table's ``segment`` rows as segments and a motion program: `_rows` part
of :mod:`cyclomech.cam` (its door). A servo axis's table
(:mod:`cyclomech.servo`) takes the same rows: an electronic cam is a cam.

Units are in the key names (the cam module's docs): a translating follower's (a
linear servo axis's) in m, an oscillating one's (a rotary axis's) in degrees.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from .. import _toml
from .._arrays import finite_number, flag, instance, instances
from .._errors import InputError
from ..motion import CONTINUITY, NAMES, SEGMENT_LAWS, Program
from ..motion import Segment as MotionSegment
from ._program import Segment

__all__ = ["SEGMENT_KEYS", "UNITS", "read_program", "read_segments"]

#: The keys of one ``segment`` table (``arc`` only in a machine file).
SEGMENT_KEYS = frozenset(
    {"kind", "angle_deg", "stroke_m", "stroke_deg", "law", "load_n", "load_nm"}
    | {f"{end}_velocity{u}" for end in ("start", "end") for u in ("_m_per_rad", "_deg_per_rad")}
    | {"points_m", "points_deg", "degree"}
)
#: The keys of a segment's stroke, load, point table and velocities by unit
#: family: a translating (linear) follower's, an oscillating (rotary) one's.
UNITS: dict[str, dict[str, str]] = {
    "linear": {
        "stroke": "stroke_m",
        "load": "load_n",
        "points": "points_m",
        "velocity": "_m_per_rad",
    },
    "angular": {
        "stroke": "stroke_deg",
        "load": "load_nm",
        "points": "points_deg",
        "velocity": "_deg_per_rad",
    },
}


def read_segments(
    rows: Any, units: Mapping[str, str], arcs: bool, *, loads: bool = True
) -> tuple[list[Segment], tuple[tuple[str, str] | None, ...]]:
    """The ``segment`` rows of a cam (or servo) table as segments, with their arcs.

    Errors name the segment (``segment 2: …``); the caller prefixes its table.

    Parameters
    ----------
    rows : list of dict
        The ``[[…segment]]`` rows as read.
    units : Mapping of str to str
        The stroke, load, points and velocity keys of the follower: one of
        :data:`UNITS`' values.
    arcs : bool
        Allow ``arc = [from, to]`` (a machine file).
    loads : bool, default True
        Allow the load keys (``load_n``/``load_nm``; a servo axis takes its load
        for the whole axis).

    Returns
    -------
    segments : list of Segment
        One per row (kind, angle, stroke [m or rad], law).
    arcs : tuple of (tuple of (str, str)) or None
        Each row's operation, or None.

    Raises
    ------
    InputError
        If ``rows`` is not a non-empty array of tables, a row has an unknown or
        missing key or an invalid value, or a dwell takes an arc.

    Examples
    --------
    >>> segs, arcs = read_segments([{"kind": "rise", "angle_deg": 90, "stroke_m": 0.01,
    ...                              "arc": ["a", "b"]}, {"kind": "return", "angle_deg": 270,
    ...                              "stroke_m": 0.01}], UNITS["linear"], True)
    >>> [g.kind for g in segs], arcs
    (['rise', 'return'], (('a', 'b'), None))
    """
    _units(units)
    arcs, loads = flag("arcs", arcs), flag("loads", loads)
    if not isinstance(rows, list) or not rows or not all(isinstance(r, dict) for r in rows):
        raise InputError("segment must be an array of tables [[...segment]] with at least one")
    allowed = set(SEGMENT_KEYS) | ({"arc"} if arcs else set())
    if not loads:
        allowed -= {"load_n", "load_nm"}
    stroke_key, load_key = units["stroke"], units["load"]
    other = {"stroke_m", "stroke_deg", "load_n", "load_nm"} - {stroke_key, load_key}
    # The other follower's velocity and point keys.
    mine = {units["points"], *(f"{e}_velocity{units['velocity']}" for e in ("start", "end"))}
    other |= {"points_m", "points_deg"} - mine
    other |= {k for k in SEGMENT_KEYS if "_velocity_" in k} - mine
    segs, bound = [], []
    for i, row in enumerate(rows):
        where = f"segment {i + 1}"
        _toml.check_keys(row, allowed - other, None, where)
        _toml.require(row, ("kind", "angle_deg"), where)
        stroke = _toml.number(row, stroke_key, where, "") if stroke_key in row else 0.0
        if stroke_key == "stroke_deg":
            stroke = math.radians(stroke)
        law = row.get("law", "cycloidal")
        segs.append(
            Segment(row["kind"], _toml.number(row, "angle_deg", where, "[deg]"), stroke, law)
        )
        arc = _toml.events(row, "arc", where, arc=True) if "arc" in row else None
        if arc is not None and row["kind"] == "dwell":
            raise InputError(f"{where}: a dwell has no phase-angle bound; arc = {arc!r}")
        bound.append(None if arc is None else (arc[0], arc[1]))
    return segs, tuple(bound)


def read_program(
    table: Mapping[str, Any],
    rows: list[Any],
    segs: list[Segment],
    units: Mapping[str, str],
    *,
    always: bool = False,
    advance: float = 0.0,
) -> Program | None:
    """The motion program of a cam's (or servo axis's) segments.

    Built when the table or a segment asks for one (a law outside
    ``cyclomech.motion.NAMES``, a moving end, a point table, ``continuity``; the
    cam module's docs) or ``always``; else None (a cam's classic segments). Each
    segment ends where the strokes so far take it (rises up, returns down); a
    ``constant_velocity`` segment without a stroke takes its velocity times its
    angle.

    Parameters
    ----------
    table : Mapping of str to Any
        The table the rows belong to (its ``continuity``, ``polydyne_rpm``).
    rows : list of dict
        The ``segment`` rows as read.
    segs : list of Segment
        Those rows as :func:`read_segments` gives them.
    units : Mapping of str to str
        The follower's keys: one of :data:`UNITS`' values.
    always : bool, default False
        Build the program even for classic segments (a servo axis).
    advance : float, default 0.0
        The slave's travel per cycle in the file's unit (m, or deg when
        ``units`` is angular): a film fed on, a rotary jaw turning on. The last
        segment's end is snapped to it within 1e-9 of the largest stroke and the
        program's last-to-first join is checked across it.

    Returns
    -------
    Program or None
        The program (positions in m, or rad when angular), or None.

    Raises
    ------
    InputError
        If a law is unknown, an end condition cannot be met, a join jumps or the
        ``continuity`` is not one of :data:`cyclomech.motion.CONTINUITY`.

    Examples
    --------
    >>> rows = [{"kind": "rise", "angle_deg": 180, "stroke_m": 0.1},
    ...         {"kind": "rise", "angle_deg": 180, "stroke_m": 0.1}]
    >>> segs, _ = read_segments(rows, UNITS["linear"], False)
    >>> p = read_program({}, rows, segs, UNITS["linear"], always=True, advance=0.2)
    >>> p.advance, [round(g.angle_deg) for g in p.segments]
    (0.2, [180, 180])
    """
    instance("table", table, Mapping)
    rows = instances("rows", rows, dict)
    segs = instances("segs", segs, Segment)
    if len(rows) != len(segs):
        raise InputError(f"rows and segs must match one to one; got {len(rows)} and {len(segs)}")
    _units(units)
    always = flag("always", always)
    advance = finite_number("advance", advance, "[m or deg]")
    angular = units["stroke"] == "stroke_deg"
    vel = [f"{e}_velocity{units['velocity']}" for e in ("start", "end")]
    keys = {*vel, units["points"], "degree"}
    if (
        not always
        and all(g.law in NAMES for g in segs)
        and not any(k in row for row in rows for k in keys)
        and not {"continuity", "polydyne_rpm"} & set(table)
    ):
        return None
    continuity = table.get("continuity", "velocity")
    if continuity not in CONTINUITY:
        raise InputError(f"continuity = {continuity!r} must be one of {', '.join(CONTINUITY)}")
    scale = math.radians(1.0) if angular else 1.0  # the file's stroke unit to the program's
    end = advance * scale
    out, s, prev_v1 = [], 0.0, None
    for i, (row, g) in enumerate(zip(rows, segs, strict=True)):
        where = f"segment {i + 1}"
        v0, v1 = (_toml.number(row, k, where, "") * scale if k in row else None for k in vel)
        stroke = g.stroke
        if g.law == "constant_velocity" and units["stroke"] not in row:
            # Its stroke is its velocity times its angle, exactly; its velocity
            # given, or the previous segment's given end velocity.
            v = next((x for x in (v0, v1, prev_v1) if x is not None), None)
            if v is None:
                raise InputError(
                    f"{where}: a constant_velocity segment needs {units['stroke']}, "
                    f"{vel[0]} or {vel[1]}, or the previous segment's {vel[1]}"
                )
            stroke = abs(v) * math.radians(g.angle_deg)
        prev_v1 = v1
        s += {"rise": stroke, "return": -stroke}.get(g.kind, 0.0)
        if i == len(rows) - 1 and abs(s - end) <= 1e-9 * max(g.stroke for g in segs):
            s = end  # back to the start (or on by the advance), to the strokes' rounding
        elif i == len(rows) - 1 and always:
            # (A cam's program says where its last segment jumps; an axis that
            # moves on says it in its own keys.)
            unit = units["stroke"].removeprefix("stroke_")
            raise InputError(
                f"the strokes sum to {s / scale:.10g} {unit} (rises − returns) but "
                f"advance_{unit} = {advance:g}: the program must end where the next cycle "
                f"starts, one advance on"
            )
        points = _points(row, units["points"], scale, where)
        law = "dwell" if g.kind == "dwell" else g.law
        if law not in SEGMENT_LAWS:
            raise InputError(
                f"{where} ({g.kind}): unknown law {law!r}; known laws: {', '.join(SEGMENT_LAWS)}"
            )
        try:
            out.append(
                MotionSegment(
                    law,
                    g.angle_deg,
                    start=(None, v0),
                    end=(s, v1),
                    points=points,
                    degree=row.get("degree", 3),
                    operation=g.operation,
                )
            )
        except InputError as e:
            raise InputError(f"{where}: {e}") from None
    return Program(out, continuity=continuity, advance=end)


def _units(units: Any) -> None:
    """``units`` must hold one of :data:`UNITS`' families (a cam's adds its own keys)."""
    if not isinstance(units, Mapping) or not any(
        all(units.get(k) == v for k, v in u.items()) for u in UNITS.values()
    ):
        raise InputError(f"units must be one of cyclomech.cam.UNITS' values; got {units!r:.80}")


def _points(row: Mapping[str, Any], key: str, scale: float, where: str) -> Any:
    """A segment's point table ``key`` in the program's units, or None."""
    if key not in row:
        return None
    table = row[key]
    if not isinstance(table, list) or not all(isinstance(p, list) and len(p) == 2 for p in table):
        raise InputError(f"{where}: {key} must be rows [angle_deg, s]; got {table!r}")
    return [(p[0], p[1] * scale) for p in table]
