"""The keys of a ``kind = "servo"`` table, its motor and its segments, for the
machine-file format reference (:attr:`ServoMechanism.key_docs`;
``tests/package/test_keydocs.py`` holds them equal to the parser's key sets and
checks their defaults).

>>> [t.name for t in KEY_DOCS]
['servo', 'servo.motor', 'servo.segment']
"""

from __future__ import annotations

from .._keydoc import ARR, FIN, NO_UNIT, NUM, POS, REQ, ROWS, TEXT, KeyTable
from .._keydoc import KeyDoc as K

# The rules of a key that only one kind of load takes.
LIN = "; refused with a rotary load"
ROT = "; refused with a linear load"
EFF = "finite, 0 < η ≤ 1"

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: A servo axis's table, its motor and its segments' keys, in the page's order.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("servo", "kind = servo", (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "servo", False),
        K("load", "What the axis moves: a linear load through a screw, belt or rack, or a "
          "rotary one.", NO_UNIT, TEXT, REQ, "one of linear, rotary", False),
        K("mass_kg", "The moving mass of a linear load.", "kg", NUM,
          "required for a linear load", "finite, ≥ 0" + LIN, True),
        K("lead_m", "The load's travel per turn of the load shaft (a screw's lead; 2π·r of a "
          "belt pulley or pinion).", "m", NUM, "required for a linear load", POS + LIN, True),
        K("force_n", "The external force against the linear load's motion.", "N", NUM, "0",
          FIN + LIN, True),
        K("drive_efficiency", "The screw's, belt's or rack's efficiency.", NO_UNIT, NUM, "1",
          EFF + LIN, True),
        K("inertia_kg_m2", "The rotary load's inertia about its shaft.", "kg·m²", NUM,
          "required for a rotary load", "finite, ≥ 0" + ROT, True),
        K("torque_nm", "The external torque on the rotary load.", "N·m", NUM, "0",
          FIN + ROT, True),
        K("gear_ratio", "The gearbox's ratio, motor speed over load-shaft speed.", NO_UNIT,
          NUM, "1 (a direct drive)", POS, True),
        K("gear_efficiency", "The gearbox's efficiency.", NO_UNIT, NUM, "1", EFF, True),
        K("gear_inertia_kg_m2", "The gearbox's inertia at its input (motor) shaft.",
          "kg·m²", NUM, "0", "finite, ≥ 0", True),
        K("motor", "The motor: a name of the catalogue, or a table of its data.", NO_UNIT,
          "text or table", "none (with catalogue: sized only, no bound on the cyclogram)",
          "a name in catalogue, or a [mechanism.<name>.motor] table; motor or catalogue is "
          "required", False),
        K("catalogue", "A motor catalogue CSV to size the axis from (relative to the "
          "machine file).", NO_UNIT, TEXT, "none (no sizing)",
          "a CSV file with the columns of cyclomech.servo.CATALOGUE_COLUMNS", False),
        K("gear_ratios", "The gear ratios the sizing tries.", NO_UNIT, ARR,
          "[gear_ratio]", "a non-empty array of finite numbers > 0; needs catalogue", False),
        K("torque_reserve", "The fraction of each motor's peak and rated torque kept in "
          "reserve: bounds, limits, checks and sizing use the rest.", NO_UNIT, NUM,
          "0 (the motor's full torques)", "finite, 0 ≤ torque_reserve < 1", True),
        K("inertia_ratio_limit", "The largest inertia ratio (load and gearbox at the motor "
          "over the rotor's inertia) that passes.", NO_UNIT, NUM, "10", POS, True),
        K("advance_m", "The linear load's travel per cycle (a film or web fed on).", "m",
          NUM, "0 (the load comes back each cycle)", FIN + LIN, True),
        K("advance_deg", "The rotary load's turn per cycle (a rotary jaw or knife).", "deg",
          NUM, "0 (the load comes back each cycle)", FIN + ROT, True),
        K("continuity", "How smooth the program's joins must be.", NO_UNIT, TEXT,
          "velocity", "one of position, velocity, acceleration, jerk", False),
        K("phase", "Where the program's master angle 0 sits in the cycle {event, crank_deg}: "
          "the program's angle at that event.", NO_UNIT, "table",
          "the first bound segment at its operation's start, else cycle angle 0",
          "a phase table; refused when a segment has an arc", False),
        K("table_points", "Steps over the cycle of the cam table cyclomech run writes.",
          NO_UNIT, "integer", "3600", "an integer, 2 ≤ table_points ≤ 10⁷", False),
        K("segment", "The axis's motion program: segments in turn over the cycle.", NO_UNIT,
          ROWS, REQ, "at least one row; angles summing to 360; strokes summing to the "
          "advance", False),
    )),
    KeyTable("servo.motor", "motor = {…} of a servo axis", (
        K("rated_torque_nm", "The rated (continuous) torque.", "N·m", NUM, REQ, POS, None),
        K("peak_torque_nm", "The peak torque.", "N·m", NUM, REQ,
          "finite, ≥ rated_torque_nm", None),
        K("rated_rpm", "The rated speed (kept for the reader).", "rpm", NUM, "max_rpm",
          "finite, 0 < rated_rpm ≤ max_rpm", None),
        K("max_rpm", "The maximum speed.", "rpm", NUM, REQ, POS, None),
        K("inertia_kg_m2", "The rotor's inertia.", "kg·m²", NUM, REQ, POS, None),
        K("name", "The motor's name in the report.", NO_UNIT, TEXT, "none", "a string",
          None),
    ), intro=(
        "A motor given by its data instead of a catalogue's name: "
        "``motor = {rated_torque_nm = …, peak_torque_nm = …, max_rpm = …, "
        "inertia_kg_m2 = …}``."
    )),
    KeyTable("servo.segment", "[[mechanism.<name>.segment]] of a servo axis", (
        K("kind", "The segment's kind.", NO_UNIT, TEXT, REQ, "one of rise, dwell, return",
          None),
        K("angle_deg", "The master angle the segment takes.", "deg", NUM, REQ,
          "finite, > 0; the segments' angles sum to 360", None),
        K("stroke_m", "The linear load's travel.", "m", NUM, "0 (a constant_velocity "
          "segment: its velocity times its angle)", "finite, ≥ 0" + LIN, None),
        K("stroke_deg", "The rotary load's turn.", "deg", NUM, "0 (a constant_velocity "
          "segment: its velocity times its angle)", "finite, ≥ 0" + ROT, None),
        K("law", "The segment's motion law.", NO_UNIT, TEXT, "cycloidal",
          "one of cyclomech.motion.SEGMENT_LAWS", None),
        K("start_velocity_m_per_rad", "The linear load's velocity at the segment's start.",
          "m/rad", NUM, "none (the previous segment's end; rest for the first)",
          FIN + LIN, None),
        K("end_velocity_m_per_rad", "The linear load's velocity at the segment's end.",
          "m/rad", NUM, "none (the next segment's start, else rest)", FIN + LIN, None),
        K("start_velocity_deg_per_rad", "The rotary load's velocity at the segment's "
          "start.", "deg/rad", NUM, "none (the previous segment's end; rest for the first)",
          FIN + ROT, None),
        K("end_velocity_deg_per_rad", "The rotary load's velocity at the segment's end.",
          "deg/rad", NUM, "none (the next segment's start, else rest)", FIN + ROT, None),
        K("points_m", "A spline segment's table: rows [master angle from its start in deg, "
          "position in m].", "deg, m", ARR, "none (law spline needs it)",
          "rows of 2 numbers, the first at 0, the last at angle_deg" + LIN, None),
        K("points_deg", "A spline segment's table: rows [master angle from its start in "
          "deg, load angle in deg].", "deg, deg", ARR, "none (law spline needs it)",
          "rows of 2 numbers, the first at 0, the last at angle_deg" + ROT, None),
        K("degree", "A spline segment's degree.", NO_UNIT, NUM, "3",
          "3 (C2 cubic) or 5 (C4 quintic)", None),
        K("arc", "The cyclogram operation whose phase angle the segment takes.", NO_UNIT,
          ARR, "none (the segment bounds no operation)",
          "[from, to], two event names of an operation of the cyclogram, each bound once; "
          "only on a rest-to-rest rise or return", None),
    ), intro=(
        "One row of a servo axis's program, as a cam's (an electronic cam is a cam): "
        "the stroke, velocity and point keys follow the load (``_m`` for a linear load, "
        "``_deg`` for a rotary one; the other family is refused)."
    )),
)
# fmt: on
