"""The machine-file format reference: every key of every table a user writes.

One :class:`KeyDoc` per key, grouped by table in :data:`TABLES` (its titles in
:data:`TITLES`, a sentence on each in :data:`INTROS`, the page's order in
:data:`ORDER`). Each record states what the parsers enforce (``from_table`` of
each kind, the readers of :mod:`cyclomech._toml`, the cyclogram's file format);
``tests/package/test_keydocs.py`` holds the key sets equal to the parsers' own, so a key
added to a parser without a record here fails the tests. :func:`render_table`
and :func:`render_page` write reStructuredText for the documentation site
(``docs/_ext/keys_reference.py``).

Columns: ``unit`` as the file takes it (the key names say ``_deg``, ``_rpm``,
``_m``; "—" for text, flags and counts); ``type``: number, integer, text, bool,
array, table or array of tables; ``default``: the value taken when the key is
absent, "required", "required unless …" or "none" (the feature it turns on is
off); ``valid``: the rule the parser checks; ``sweep``: whether
:func:`cyclomech.sweep` may vary it (``<mechanism>.<key>``, ``machine.<key>``),
None for the rows of a sub-table, which a sweep sets only through their parent key.

>>> TABLES["machine"][0].name, TABLES["machine"][0].default
('name', "the file's name without its extension")
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

__all__ = ["INTROS", "ORDER", "TABLES", "TITLES", "KeyDoc", "render_page", "render_table"]


@dataclass(frozen=True)
class KeyDoc:
    """One key of a machine-file table.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The key.
    meaning : str
        What it means (one sentence).
    unit : str
        Its unit as the file takes it ("—" for text, flags and counts).
    type : str
        number, integer, text, bool, array, table or array of tables.
    default : str
        The value taken when the key is absent, "required", "required unless …"
        or "none" (the feature it turns on is off).
    valid : str
        The rule its parser enforces.
    sweep : bool or None
        Whether a sweep may set it (None for a sub-table's rows).

    Examples
    --------
    >>> KeyDoc("gap", "Distance between the pitch circles.", "m", "number", "required",
    ...        "finite, > 0", True).unit
    'm'
    """

    name: str
    meaning: str
    unit: str
    type: str
    default: str
    valid: str
    sweep: bool | None


K = KeyDoc
NUM, INT, TEXT, BOOL = "number", "integer", "text", "bool"
ARR, TAB, ROWS = "array", "table", "array of tables"
REQ, NONE, NO_UNIT = "required", "none", "—"
POS = "finite, > 0"
NONNEG = "finite, ≥ 0"
FIN = "any finite number"
TR = "; refused with an oscillating follower"
OS = "; refused with a translating or flat follower"
STROKE = "finite, ≥ 0: 0 for a dwell, > 0 for a rise or return"
LAWS = (
    "one of cycloidal, harmonic, polynomial_345, polynomial_4567, modified_sine, modified_trapezoid"
)

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: Every key of every table a user writes, by table (``"machine"``, ``"cam.segment"``,
#: …): one :class:`KeyDoc` per key, in the order of the page.
TABLES: dict[str, tuple[KeyDoc, ...]] = {
    "file": (
        K("machine", "The machine: its name, speed range and grids.", NO_UNIT, TAB, REQ,
          "a table", False),
        K("mechanism", "The mechanisms, one [mechanism.<name>] table each with its kind.",
          NO_UNIT, TAB, "none (no mechanisms)",
          "a table of tables, each with kind = one of the kinds below", False),
        K("cyclogram", "The cyclogram's head: its name, cycle and limiting operation.",
          NO_UNIT, TAB, REQ, "a table", False),
        K("operation", "The cyclogram's operations, one [[operation]] row each.", NO_UNIT,
          ROWS, REQ, "an array of tables", False),
        K("constraint", "Linear constraints on the operations' phase angles.", NO_UNIT, ROWS,
          "none (no constraints)", "an array of tables", False),
    ),
    "machine": (
        K("name", "The machine's name in the report.", NO_UNIT, TEXT,
          "the file's name without its extension", "a string", False),
        K("speed_rpm", "The range of main-shaft speeds studied.", "rpm", ARR, REQ,
          "[from, to], two finite numbers, 0 < from < to ≤ 1e6", False),
        K("speed_points", "Speeds in the speed sweep over speed_rpm.", NO_UNIT, INT, "61",
          "a whole number from 2 to 1000000", True),
        K("nominal_rpm", "The speed of the report's optimised cyclogram.", "rpm", NUM,
          "none (the top of speed_rpm, capped at the speed limit)",
          "0 < nominal_rpm ≤ 1e6", True),
        K("angle_points", "Crank angles per turn of the mechanisms' grids.", NO_UNIT, INT,
          "361", "a whole number from 9 to 1000000", True),
        K("speed_fluctuation", "The main shaft's coefficient of speed fluctuation δ.",
          NO_UNIT, NUM, "0.05", "0 < δ < 1", True),
        K("flatten_torque", "Move mechanisms within the cyclogram's slack to lower the "
          "main shaft's peak torque.", NO_UNIT, BOOL, "false", "true or false", True),
        K("unmodelled", "The mechanisms the operations name that the file does not model "
          "(a clamp, a back gauge: Gantt rows only). Every operation's mechanism is a "
          "[mechanism.<name>] table or listed here; anything else is an error (a typo "
          "would silently drop a mechanism's bounds).", NO_UNIT, ARR, "[] (none)",
          "a list of names, each named by an operation's mechanism and none a "
          "[mechanism.<name>] table", False),
    ),
    "cyclogram": (
        K("name", "The cyclogram's name in the report.", NO_UNIT, TEXT,
          "the file's name without its extension", "a string (a number is refused)", False),
        K("cycle_deg", "The angle of one machine cycle.", "deg", NUM, "360",
          "finite, 0 < cycle_deg ≤ 1e12; 360 in a machine with a cam", False),
        K("limiting", "The operation that gets what the others leave of the cycle.", NO_UNIT,
          "text or array", REQ,
          "an operation's name (of one operation) or its arc [from, to] of two event names",
          False),
        K("speed_rpm", "The speed of time-bound operations (cyclogram files only).", "rpm",
          NUM, "set by the machine",
          "refused in a machine file: give [machine] speed_rpm and nominal_rpm", False),
        K("events", "The events in the order reports show them.", NO_UNIT, ARR,
          "the events in the order the operations name them",
          "event names (strings, in quotes: a number is refused), none blank; when given, "
          "every operation's from and to must be listed", False),
    ),
    "operation": (
        K("from", "The event the operation starts at.", NO_UNIT, TEXT, REQ,
          "an event name (a string, in quotes: from = 1 is refused), not blank, other than to",
          False),
        K("to", "The event the operation ends at.", NO_UNIT, TEXT, REQ,
          "an event name (a string), not blank, other than from; each arc from → to once",
          False),
        K("min_angle_deg", "The smallest phase angle of the operation.", "deg", NUM, "0",
          "finite, 0 ≤ min_angle_deg ≤ 1e12", False),
        K("max_angle_deg", "The largest phase angle of the operation.", "deg", NUM,
          "none (no upper bound)", "finite, min_angle_deg ≤ max_angle_deg ≤ 1e12", False),
        K("min_duration_s", "The shortest time the operation takes (6·n·s degrees at n rpm).",
          "s", NUM, "0", "0, or from 1e-12 to 1e12", False),
        K("height", "Machine cycles the operation crosses (1: it ends in the next cycle).",
          NO_UNIT, INT, "0", "a whole number ≥ 0", False),
        K("name", "The operation's name in reports and in limiting.", NO_UNIT, TEXT,
          "none (shown as from→to)", "a string (a number is refused)", False),
        K("mechanism", "The mechanism that performs it (a Gantt row of the report).",
          NO_UNIT, TEXT, NONE,
          "a [mechanism.<name>] table's name, or a name listed in [machine] unmodelled; "
          "anything else is an error naming the nearest mechanism", False),
    ),
    "constraint": (
        K("name", "The constraint's name in the optimum's results.", NO_UNIT, TEXT,
          "constraint <n> (n its position among the constraints)",
          "a string (a number is refused); unique; not cycle, and not starting with min[, max[ or "
          "duration[", False),
        K("terms", "The sum Σ coeff·t(from, to) over operations.", NO_UNIT, ROWS, REQ,
          "at least one {from, to, coeff} table, each arc once", False),
        K("sense", "The comparison of the sum with rhs.", NO_UNIT, TEXT, REQ,
          "one of <=, >=, ==", False),
        K("rhs", "The right-hand side.", "deg", NUM, REQ, "finite, magnitude ≤ 1e12", False),
    ),
    "constraint.terms": (
        K("from", "The first event of the term's operation.", NO_UNIT, TEXT, REQ,
          "an event name (a string); from → to must be an operation", None),
        K("to", "The second event of the term's operation.", NO_UNIT, TEXT, REQ,
          "an event name (a string); from → to must be an operation", None),
        K("coeff", "The coefficient of the operation's phase angle.", NO_UNIT, NUM, REQ,
          "finite, magnitude ≤ 1e12", None),
    ),
    "phase": (
        K("event", "The cyclogram event at which the mechanism's angle is crank_deg.",
          NO_UNIT, TEXT, "none (crank_deg at cycle angle 0)",
          "one of the cyclogram's events (a string)", None),
        K("crank_deg", "The mechanism's own angle at that event.", "deg", NUM, "0", FIN, None),
    ),
    "cam": (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "cam", False),
        K("follower", "The follower's kind.", NO_UNIT, TEXT, REQ,
          "one of translating, flat, oscillating", False),
        K("closure", "How the follower is kept on the cam: a spring, or a groove.", NO_UNIT,
          TEXT, "spring", "one of spring, groove; groove needs a roller (not flat) follower",
          False),
        K("segment", "The cam's program: rises, dwells and returns in turn.", NO_UNIT, ROWS,
          REQ, "at least one row; angles summing to 360; rises − returns = 0", False),
        K("base_radius_m", "The radius of the cam's base circle.", "m", NUM, REQ, POS, True),
        K("roller_radius_m", "The roller's radius (0: a knife edge).", "m", NUM,
          "required for translating and oscillating followers (a flat one refuses it)",
          "finite, 0 ≤ roller_radius_m < base_radius_m", True),
        K("offset_m", "The translating follower's offset from the cam centre.", "m", NUM,
          "0 (translating only; other followers refuse it)",
          "finite, magnitude < base_radius_m + roller_radius_m", True),
        K("pivot_distance_m", "The distance from the cam centre to the arm's pivot.", "m",
          NUM, "required for an oscillating follower (others refuse it)",
          "finite, > 0; abs(pivot_distance_m − arm_length_m) < base_radius_m + "
          "roller_radius_m < pivot_distance_m + arm_length_m", True),
        K("arm_length_m", "The oscillating arm's length, pivot to roller centre.", "m", NUM,
          "required for an oscillating follower (others refuse it)",
          "finite, > 0; as pivot_distance_m", True),
        K("mass_kg", "The follower's mass at the cam (translating and flat followers).", "kg",
          NUM, "none (no loads: no σ_H, jump or vibration from loads)",
          "finite, ≥ 0; refused with an oscillating follower", True),
        K("spring_rate_n_per_m", "The closing spring's rate (translating and flat).", "N/m",
          NUM, "0", NONNEG + TR + "; needs mass_kg", True),
        K("preload_n", "The closing spring's force at the base circle (translating, flat).",
          "N", NUM, "0", FIN + TR + "; needs mass_kg", True),
        K("inertia_kg_m2", "The oscillating arm's inertia about its pivot.", "kg·m²", NUM,
          "none (no loads)", NONNEG + OS, True),
        K("spring_rate_nm_per_rad", "The closing spring's torsional rate (oscillating).",
          "N·m/rad", NUM, "0", NONNEG + OS + "; needs inertia_kg_m2", True),
        K("preload_nm", "The closing spring's torque at the base circle (oscillating).",
          "N·m", NUM, "0", FIN + OS + "; needs inertia_kg_m2", True),
        K("max_vibration_m", "The follower's vibration amplitude limit (translating, flat).",
          "m", NUM, "none (no vibration bound)",
          "finite, > 0; needs natural_frequency_hz" + TR, True),
        K("max_vibration_deg", "The arm's vibration amplitude limit (oscillating).", "deg",
          NUM, "none (no vibration bound)", "finite, > 0; needs natural_frequency_hz" + OS, True),
        K("natural_frequency_hz", "The follower's natural frequency.", "Hz", NUM,
          "none (no vibration bound)",
          "finite, > 0; needs max_vibration_m (max_vibration_deg when oscillating)", True),
        K("damping_ratio", "The follower's damping ratio ζ.", NO_UNIT, NUM, "0",
          "0 ≤ ζ < 1; needs natural_frequency_hz and the vibration limit", True),
        K("width_m", "The contact's width along the cam's axis.", "m", NUM,
          "none (no contact stress)", POS, True),
        K("follower_modulus_pa", "The follower's Young's modulus.", "Pa", NUM,
          "2.1e11", POS + "; needs width_m", True),
        K("follower_poisson", "The follower's Poisson's ratio.", NO_UNIT, NUM,
          "0.3", "a number, −1 < ν < 0.5" + "; needs width_m", True),
        K("cam_modulus_pa", "The cam's Young's modulus.", "Pa", NUM,
          "2.1e11", POS + "; needs width_m", True),
        K("cam_poisson", "The cam's Poisson's ratio.", NO_UNIT, NUM,
          "0.3", "a number, −1 < ν < 0.5" + "; needs width_m", True),
        K("max_stress_pa", "The allowed Hertz contact stress [σ_H].", "Pa", NUM,
          "none (σ_H not bounded)",
          "finite, > 0; needs mass_kg (inertia_kg_m2 when oscillating) and width_m", True),
        K("max_pressure_angle_deg", "The allowed pressure angle [α].", "deg", NUM,
          "45 for an oscillating follower, 30 otherwise", "finite, 0 < α < 90", True),
    ),
    "cam.segment": (
        K("kind", "The segment's kind.", NO_UNIT, TEXT, REQ, "one of rise, dwell, return",
          None),
        K("angle_deg", "The cam angle the segment takes.", "deg", NUM, REQ,
          "finite, > 0; the segments' angles sum to 360", None),
        K("stroke_m", "The follower's travel (translating and flat followers).", "m", NUM,
          "0", STROKE + TR, None),
        K("stroke_deg", "The arm's rotation (oscillating follower).", "deg", NUM, "0",
          STROKE + OS, None),
        K("law", "The motion law of a rise or return.", NO_UNIT, TEXT, "cycloidal",
          "a string; for a rise or return " + LAWS, None),
        K("load_n", "The external force on the follower during the segment.", "N", NUM,
          "0", FIN + TR + "; needs mass_kg", None),
        K("load_nm", "The external torque on the arm during the segment.", "N·m", NUM,
          "0", FIN + OS + "; needs inertia_kg_m2", None),
        K("arc", "The cyclogram operation whose phase angle the segment takes.", NO_UNIT,
          ARR, "none (the segment bounds no operation)",
          "[from, to], two event names of an operation of the cyclogram, each bound once; "
          "not on a dwell", None),
    ),
    "cam_stop": (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "cam_stop", False),
        K("arc", "The cyclogram operation that brings the lever to its stop.", NO_UNIT, ARR,
          REQ, "[from, to], two event names of an operation of the cyclogram", False),
        K("a_max_m", "The largest first rebound allowed.", "m", NUM, REQ,
          "finite, > 0, below the stroke (stroke_m, or the cam's)", True),
        K("cam", "The cam mechanism whose rise on arc drives the lever.", NO_UNIT, TEXT,
          "none (give law and stroke_m)",
          "the name of a kind = cam mechanism with a rise segment on arc; then law and "
          "stroke_m are refused", False),
        K("law", "The cam's rise law.", NO_UNIT, TEXT, "modified_sine (from the cam with cam)",
          LAWS + "; refused with cam (a sweep too)", True),
        K("stroke_m", "The working point's travel.", "m", NUM, "required unless cam is given",
          "finite, > 0; refused with cam (a sweep too)", True),
        K("preload_m", "How far short of the end of the stroke the stop sits.", "m", NUM, REQ,
          "finite, 0 ≤ preload_m < stroke_m", True),
        K("lever_length_m", "The lever's length l.", "m", NUM, REQ, POS, True),
        K("J_A_kg_m2", "The lever's inertia about its axis.", "kg·m²", NUM, REQ, POS, True),
        K("a_m", "The lever's arm a.", "m", NUM, REQ, POS, True),
        K("b_m", "The lever's arm b.", "m", NUM, REQ, POS, True),
        K("E_pa", "The lever's Young's modulus.", "Pa", NUM, REQ, POS, True),
        K("J_x_m4", "The lever section's second moment of area.", "m⁴", NUM, REQ, POS, True),
        K("mass_kg", "The reduced mass at the working point.", "kg", NUM,
          "J_A_kg_m2 / lever_length_m²", POS, True),
        K("restitution", "The coefficient of restitution k.", NO_UNIT, NUM, "5/9",
          "0 ≤ k ≤ 1", True),
        K("zeta", "The damping ratio of the lever's free vibration (any ζ ≥ 0; ζ ≥ 1 "
          "is overdamped and warns: a percentage?).", NO_UNIT, NUM, "0.05", NONNEG, True),
        K("contact_stiffness_n_per_m", "The lever's stiffness while propped by the stop.", "N/m",
          NUM, "the free stiffness 3·E·J_x/((a + b)·b²) times the prop's stiffening",
          "finite, > the free stiffness 3·E·J_x/((a + b)·b²)", True),
        K("pulse", "The impact pulse's shape (pulse model).", NO_UNIT, TEXT, "decaying",
          "one of decaying, rectangular, triangular, half_sine", True),
        K("contact_time_s", "The impact pulse's duration (pulse model).", "s", NUM,
          "half the period of the contact vibration", POS, True),
        K("model", "The model of the first rebound.", NO_UNIT, TEXT, "pulse",
          "one of pulse, contact", True),
        K("phase_deg", "The phase angles of the report's rebound curves.", "deg", ARR,
          "[20, 60, 5]",
          "[from, to, count]: from and to finite in (0, 360], count a whole number 1 to 50",
          True),
    ),
    "linkage": (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "linkage", False),
        K("name", "The linkage's name.", NO_UNIT, TEXT, NONE, "a string", False),
        K("points", "The joints in the drawn pose {joint = [x, y]} (it picks the assembly "
          "mode).", "m", TAB, REQ,
          "non-empty names, two finite coordinates each; every point on a link or with "
          "two guides", True),
        K("links", "The rigid links, each an array of its joints (3 or more: a ternary link).",
          NO_UNIT, ARR, REQ,
          "at least one link of at least two distinct points; mobility 1", True),
        K("ground", "The joints fixed to the frame.", NO_UNIT, ARR, REQ,
          "at least one point name", True),
        K("driver", "The crank [pivot, tip], turning once per machine cycle.", NO_UNIT, ARR,
          REQ, "two points of one link: the pivot a ground joint, the tip not", True),
        K("output", "The point whose motion is reported.", NO_UNIT, TEXT,
          "the last point of points", "a point's name", True),
        K("lengths", "Link lengths that replace the drawn distances.", NO_UNIT, ROWS,
          "none (lengths from the drawn points)",
          "an array of {joints, length} tables", True),
        K("sliders", "Prismatic joints {point = guide, or [guide, guide]}.", NO_UNIT, TAB,
          "none (no sliders)",
          "each point a moving point with one guide or two, the point drawn on its guide",
          True),
        K("max_acceleration_m_per_s2", "The limit on the output point's peak acceleration.",
          "m/s²", NUM, "none (no speed limit)", POS, True),
        K("phase", "Where the crank sits in the cycle {event, crank_deg}.", NO_UNIT, TAB,
          "the crank at 0 at cycle angle 0",
          "a phase table; needs mass, point_mass_kg or load", True),
        K("mass", "The links' masses, one [[…mass]] row per link.", NO_UNIT, ROWS,
          "none (no link masses)", "an array of tables, each link once", True),
        K("point_mass_kg", "Masses concentrated at points {point = kg}.", "kg", TAB,
          "none (no point masses)", "finite, ≥ 0, each at a moving point", True),
        K("load", "External forces and torques, one [[…load]] row each.", NO_UNIT, ROWS,
          "none (no loads)", "an array of tables", True),
        K("gravity_m_per_s2", "The acceleration of gravity [gx, gy].", "m/s²", ARR,
          "none (no gravity)",
          "two finite numbers; needs mass or point_mass_kg", True),
    ),
    "linkage.lengths": (
        K("joints", "The two joints the length joins.", NO_UNIT, ARR, REQ,
          "[a, b], two joints of one link", None),
        K("length", "The distance between them.", "m", NUM, REQ, POS, None),
    ),
    "linkage.sliders": (
        K("ground", "A guide fixed to the frame, by its direction [dx, dy].", NO_UNIT, ARR,
          "none (give ground or link)", "two finite numbers, not both 0", None),
        K("link", "A guide along a link, through two of its joints [b, c].", NO_UNIT, ARR,
          "none (give ground or link)",
          "two joints of one link, the sliding point not on that link", None),
    ),
    "linkage.mass": (
        K("link", "The link, by its joints.", NO_UNIT, ARR, REQ,
          "joint names of a moving link of the linkage", None),
        K("mass_kg", "The link's mass.", "kg", NUM, REQ, NONNEG, None),
        K("com_m", "The centre of mass in the drawn pose [x, y].", "m", ARR,
          "the centroid of the link's joints",
          "two numbers; at most one of com_m, com_point, com_offset_m", None),
        K("com_point", "The centre of mass at one of the link's joints.", NO_UNIT, TEXT,
          "the centroid of the link's joints", "a joint of the link", None),
        K("com_offset_m", "The centre of mass [u, v] in the link's frame (origin its first "
          "joint, u towards its second).", "m", ARR, "the centroid of the link's joints",
          "two numbers", None),
        K("inertia_kg_m2", "The link's inertia about its centre of mass.", "kg·m²", NUM, "0",
          NONNEG, None),
    ),
    "linkage.load": (
        K("point", "The point a force acts on (with force_n).", NO_UNIT, TEXT,
          "none (give point and force_n, or link and torque_nm)",
          "a moving point of the linkage", None),
        K("force_n", "The force [fx, fy], or one [fx, fy] row per angle_deg.", "N", ARR,
          "none (with point: required)", "finite numbers", None),
        K("link", "The link a torque acts on (with torque_nm).", NO_UNIT, ARR,
          "none (give point and force_n, or link and torque_nm)",
          "joint names of a moving link", None),
        K("torque_nm", "The torque, or one value per angle_deg.", "N·m", "number or array",
          "none (with link: required)", "finite numbers", None),
        K("angle_deg", "Crank angles of a load table (zero outside it).", "deg", ARR,
          "none (a constant load)",
          "at least 2 finite angles, strictly increasing over at most 360", None),
    ),
    "press": (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "press", False),
        K("R_m", "The guide gear's pitch radius.", "m", NUM, REQ,
          "finite, R_m > r_m, R_m/r_m a whole number from 2 to 64", True),
        K("r_m", "The planet's pitch radius.", "m", NUM, REQ, POS, True),
        K("d_m", "The pin's eccentricity on the planet (0: a crank-slider).", "m", NUM, REQ,
          NONNEG, True),
        K("L_m", "The rod's length.", "m", NUM, REQ,
          "finite, > 0; the rod must reach the slider's guide all the turn", True),
        K("phi0_deg", "The guide gear's setting angle.", "deg", NUM, REQ, FIN, True),
        K("offset_m", "The slider guide's offset from the centre.", "m", NUM, "0", FIN, True),
        K("k_Sp", "The working stroke as a fraction of the nominal stroke S_n.", NO_UNIT,
          NUM, "required unless working_stroke_m (give exactly one)",
          "0 < k_Sp ≤ 1; the criteria must hold", True),
        K("working_stroke_m", "The working stroke S_p.", "m", NUM,
          "required unless k_Sp (give exactly one)",
          "finite, > 0, not above the nominal stroke S_n; the criteria must hold", True),
        K("max_V_np_m_per_s", "The limit on the slider's speed at the start of the working "
          "stroke.", "m/s", NUM, "none (no speed limit)", POS, True),
        K("deformation_force", "The deformation-force diagram over the working stroke.",
          NO_UNIT, TAB, "none (no force)", "a table {s_above_bdc_m, force_n}", True),
        K("slider_mass_kg", "The slider's mass.", "kg", NUM, "0", NONNEG, True),
        K("rod_mass_kg", "The (uniform) rod's mass.", "kg", NUM, "0", NONNEG, True),
        K("phase", "Where BDC sits in the cycle {event, crank_deg}: the carrier's angle past "
          "BDC.", NO_UNIT, TAB, "the carrier at BDC at cycle angle 0", "a phase table", True),
    ),
    "press.deformation_force": (
        K("s_above_bdc_m", "The slider's heights above BDC.", "m", ARR, REQ,
          "at least 2 finite values, strictly increasing, within [0, S_p]", None),
        K("force_n", "The force at each height (linear between, zero outside).", "N", ARR, REQ,
          "finite, ≥ 0, as many as s_above_bdc_m", None),
    ),
    "transfer": (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "transfer", False),
        K("R_t_m", "The transfer rotor's pitch radius.", "m", NUM, REQ,
          "finite, > 0, within [1e-60, 1e60]", True),
        K("R_p_m", "The process rotor's pitch radius.", "m", NUM, REQ,
          "finite, > 0, within [1e-60, 1e60]", True),
        K("gap_m", "The distance between the two pitch circles.", "m", NUM, REQ, POS, True),
        K("pockets_t", "The transfer rotor's pockets (one passes per cycle).", NO_UNIT, INT,
          REQ, "a whole number from 1 to 10000", True),
        K("pockets_p", "The process rotor's pockets (one passes per cycle).", NO_UNIT, INT,
          REQ, "a whole number from 1 to 10000", True),
        K("x2_m", "The length of each quintic transition.", "m", NUM,
          "the length of least jerk",
          "finite, within [1e-60, 1e60]; the two transitions must fit in the gap", True),
        K("max_jerk_m_per_s3", "The limit on the workpiece's peak jerk.", "m/s³", NUM,
          "none (no limit)", POS, True),
        K("max_acceleration_m_per_s2", "The limit on the workpiece's peak acceleration.",
          "m/s²", NUM, "none (no limit)", POS, True),
    ),
}
# fmt: on

#: Each table's section title on the page.
TITLES: dict[str, str] = {
    "file": "The top level",
    "machine": "[machine]",
    "cyclogram": "[cyclogram]",
    "operation": "[[operation]]",
    "constraint": "[[constraint]]",
    "constraint.terms": "terms of a [[constraint]]",
    "phase": "phase of a linkage or press",
    "cam": "kind = cam",
    "cam.segment": "[[mechanism.<name>.segment]] of a cam",
    "cam_stop": "kind = cam_stop",
    "linkage": "kind = linkage",
    "linkage.lengths": "[[mechanism.<name>.lengths]] of a linkage",
    "linkage.sliders": "a guide in sliders of a linkage",
    "linkage.mass": "[[mechanism.<name>.mass]] of a linkage",
    "linkage.load": "[[mechanism.<name>.load]] of a linkage",
    "press": "kind = press",
    "press.deformation_force": "deformation_force of a press",
    "transfer": "kind = transfer",
}

#: A paragraph on each table that is not a mechanism kind (a kind's own comes
#: from its class's docstring).
INTROS: dict[str, str] = {
    "file": "A machine file is TOML; these are its top-level tables.",
    "machine": "The machine as a whole: its name, the speed range studied and the grids.",
    "cyclogram": (
        "The head of the cyclogram: the operations and events of one machine cycle are "
        "timed against the main shaft."
    ),
    "operation": (
        "One operation (an arc between two events) of the cyclogram, with the bounds on "
        "its phase angle."
    ),
    "constraint": (
        "A linear constraint over operations' phase angles for the cyclogram's LP; "
        "each term is ``{from = …, to = …, coeff = …}``."
    ),
    "constraint.terms": "One term of a constraint's ``terms`` array.",
    "phase": (
        "``phase = {event = …, crank_deg = …}`` in a linkage's or press's table places "
        "its torque on the main shaft."
    ),
    "cam.segment": (
        "One row of a cam's program; the stroke and load keys follow the follower "
        "(``_m`` and ``_n`` for translating and flat followers, ``_deg`` and ``_nm`` for "
        "an oscillating one; the other pair is refused)."
    ),
    "linkage.lengths": "One length of a linkage's ``lengths`` array.",
    "linkage.sliders": (
        "A guide of ``sliders``: a table with exactly one of these keys; a point takes "
        "one guide, or an array of two (a PRP dyad)."
    ),
    "linkage.mass": "One link's mass; give its centre of mass one way at most.",
    "linkage.load": (
        "One external load: ``point`` with ``force_n``, or ``link`` with ``torque_nm``, "
        "optionally as a table over the crank angle ``angle_deg``."
    ),
    "press.deformation_force": (
        "The deformation-force diagram of a press: linear between its points, zero outside them."
    ),
}

#: The page's order: the file, the cyclogram, then each kind and its sub-tables.
ORDER: tuple[str, ...] = (
    "file",
    "machine",
    "cyclogram",
    "operation",
    "constraint",
    "constraint.terms",
    "cam",
    "cam.segment",
    "cam_stop",
    "linkage",
    "linkage.lengths",
    "linkage.sliders",
    "linkage.mass",
    "linkage.load",
    "press",
    "press.deformation_force",
    "phase",
    "transfer",
)

_HEADER = ("Key", "Meaning", "Unit", "Type", "Default", "Valid values", "Sweep")
_SWEEP = {True: "yes", False: "no", None: "—"}
_ROLE = re.compile(r":[\w:]+:`(~?)([^`<]*?)\s*(?:<([^>]*)>)?`")


def doc_comment(package: str, name: str) -> list[str]:
    """The ``#:`` comment above ``name``'s assignment in the modules of
    ``package`` (its own files, read as text: importing ``__main__`` would run the
    CLI), where Sphinx's autodoc reads a constant's documentation.

    Parameters
    ----------
    package : str
        A package's dotted name, e.g. ``"cyclomech.press"``.
    name : str
        The constant's name.

    Returns
    -------
    list of str
        The comment's lines without ``#:``; empty if there is none.

    Examples
    --------
    >>> doc_comment("cyclomech.press", "CRITERIA")
    ["Names of the criteria, in the kernel's column order."]
    """
    import importlib

    folder = Path(importlib.import_module(package).__file__ or "").parent
    pattern = re.compile(rf"((?:^#:.*\n)+)^{re.escape(name)}\b[^\n=]*=", re.MULTILINE)
    for path in sorted(folder.glob("*.py")):
        match = pattern.search(path.read_text(encoding="utf-8"))
        if match:
            return [ln[2:].strip() for ln in match.group(1).splitlines()]
    return []


def roles_as_literals(text: str, *, last: bool = False) -> str:
    """``text`` with its Sphinx cross-reference roles as inline literals, for text
    shown where the references would not resolve (a copied summary, a page built
    from docstrings).

    A role with a title keeps the title; ``~target`` keeps the target's last part,
    as Sphinx shows it; a plain target stays whole, or its last part too with
    ``last=True``.

    Parameters
    ----------
    text : str
        reStructuredText.
    last : bool, default False
        Show every target by its last dotted part.

    Returns
    -------
    str
        The text, each role replaced by ````text````.

    Examples
    --------
    >>> roles_as_literals(":class:`~cyclomech.Cam` and :meth:`Cam.solve`")
    '``Cam`` and ``Cam.solve``'
    >>> roles_as_literals(":func:`the sweep <cyclomech.sweep>`", last=True)
    '``the sweep``'
    """

    def literal(m: re.Match[str]) -> str:
        tilde, shown, target = m.groups()
        if not target and (tilde or last):
            shown = shown.rsplit(".", 1)[-1]
        return f"``{shown}``"

    return _ROLE.sub(literal, text)


def _text(s: str) -> str:
    """Plain text for rST: the characters that start inline markup escaped."""
    return re.sub(r"([\\*`|_])", r"\\\1", s)


def render_table(table: str) -> str:
    """The keys of one table as an rST ``list-table``.

    Parameters
    ----------
    table : str
        A key of :data:`TABLES` (``"machine"``, ``"cam.segment"``, …).

    Returns
    -------
    str
        The ``list-table`` directive: key, meaning, unit, type, default, valid
        values and sweep, one row per key.

    Examples
    --------
    >>> print(render_table("phase").splitlines()[0])
    .. list-table::
    """
    rows: list[tuple[str, ...]] = [_HEADER]
    for k in TABLES[table]:
        cells = map(_text, (k.meaning, k.unit, k.type, k.default, k.valid))
        rows.append((f"``{k.name}``", *cells, _SWEEP[k.sweep]))
    lines = [".. list-table::", "   :header-rows: 1", "   :widths: 14 30 7 8 16 20 5", ""]
    for row in rows:
        lines.append(f"   * - {row[0]}")
        lines += [f"     - {cell}" for cell in row[1:]]
    return "\n".join(lines) + "\n"


def _intro(table: str) -> str:
    """A kind's first docstring paragraph (cross-reference roles as literals), or
    the table's entry in :data:`INTROS`."""
    if table in INTROS:
        return INTROS[table]
    from .machine import KINDS

    doc = (KINDS[table].__doc__ or "").strip().split("\n\n")[0]
    return roles_as_literals(" ".join(doc.split()), last=True)


def render_page(title: str = "Machine-file format") -> str:
    """The reference page in rST.

    A section per table of :data:`ORDER`, its paragraph and its keys.

    Parameters
    ----------
    title : str, default "Machine-file format"
        The page's title.

    Returns
    -------
    str
        The page's reStructuredText.

    Examples
    --------
    >>> page = render_page()
    >>> page.splitlines()[0], "kind = transfer" in page
    ('Machine-file format', True)
    """
    out = [
        title,
        "=" * len(title),
        "",
        "Every key of every table of a machine file (``cyclomech run <file>.toml``; "
        "``examples/stb_loom.toml`` is a complete one, walked through in the user "
        "guide's whole-machine page). Units are SI as the file takes them, angles in "
        "degrees and speeds in rpm where the key's name says so. *Sweep* says whether "
        "``cyclomech sweep --set`` (``cyclomech.sweep``) may vary the key, as "
        "``<mechanism>.<key>`` or ``machine.<key>``; — marks a sub-table's rows, set "
        "only through their parent key. The tables are generated from the same key "
        "sets the file readers check, so a key listed here is one the reader takes.",
        "",
    ]
    for table in ORDER:
        head = TITLES[table]
        out += [head, "-" * len(head), "", _intro(table), "", render_table(table)]
    out += _renamed_section()
    return "\n".join(out)


def _renamed_section() -> list[str]:
    """The page's last section: every key renamed to say its unit, old → new
    (:data:`cyclomech._keyrules.RENAMED`), which the readers refuse by the old name."""
    from ._keyrules import RENAMED

    head = "Renamed keys"
    lines = [
        head,
        "-" * len(head),
        "",
        "Keys with a unit say it in their names. A file that still uses an old name is "
        "refused with a message naming the new one; the value stays as it was.",
        "",
        ".. list-table::",
        "   :header-rows: 1",
        "",
        "   * - Old name",
        "     - New name",
        "     - Unit",
    ]
    for old, (new, unit) in RENAMED.items():
        lines += [f"   * - ``{old}``", f"     - ``{new}``", f"     - {_text(unit)}"]
    return [*lines, ""]
