"""The keys of a ``kind = "cam"`` table and of its segments, for the machine-file
format reference (:attr:`CamMechanism.key_docs`; ``tests/package/test_keydocs.py`` holds
them equal to the parser's key sets and checks their defaults and ranges).

>>> [t.name for t in KEY_DOCS]
['cam', 'cam.synthesize', 'cam.friction', 'cam.segment']
"""

from __future__ import annotations

from .._keydoc import (
    ARR,
    FIN,
    LAWS,
    NO_UNIT,
    NONNEG,
    NUM,
    POS,
    REQ,
    ROWS,
    TAB,
    TEXT,
    KeyTable,
)
from .._keydoc import KeyDoc as K

# The rules of a key that only one kind of follower takes.
TR = "; refused with an oscillating follower"
OS = "; refused with a translating or flat follower"
STROKE = "finite, ≥ 0: 0 for a dwell, > 0 for a rise or return"

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: A cam's table and its segments' keys, in the page's order.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("cam", "kind = cam", (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "cam", False),
        K("follower", "The follower's kind.", NO_UNIT, TEXT, REQ,
          "one of translating, flat, oscillating", False),
        K("closure", "How the follower is kept on the cam: a spring, or a groove.", NO_UNIT,
          TEXT, "spring", "one of spring, groove; groove needs a roller (not flat) follower",
          False),
        K("segment", "The cam's program: rises, dwells and returns in turn.", NO_UNIT, ROWS,
          REQ, "at least one row; angles summing to 360; rises − returns = 0", False),
        K("base_radius_m", "The radius of the cam's base circle.", "m", NUM,
          "required unless a synthesize table sizes it (then refused)", POS, True),
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
        K("tool_radius_m", "The radius of the cutter that makes the profile: the "
          "profile files give its centre path (a roller's size: the pitch curve).", "m", NUM,
          "none (no cutter path)", "finite, > 0; a roller or flat-faced follower", True),
        K("max_stress_pa", "The allowed Hertz contact stress [σ_H].", "Pa", NUM,
          "none (σ_H not bounded)",
          "finite, > 0; needs mass_kg (inertia_kg_m2 when oscillating) and width_m", True),
        K("max_pressure_angle_deg", "The allowed pressure angle [α].", "deg", NUM,
          "45 for an oscillating follower, 30 otherwise", "finite, 0 < α < 90", True),
        K("continuity", "How smooth the motion program's joins must be (a cam built as a "
          "motion program).", NO_UNIT, TEXT, "velocity",
          "one of position, velocity, acceleration, jerk", False),
        K("polydyne_rpm", "Make the cam polydyne for this speed: the follower's output "
          "follows the program.", "rpm", NUM, "none (the cam follows the program)",
          "finite, > 0; needs mass_kg (inertia_kg_m2) and natural_frequency_hz", True),
        K("friction", "The follower's friction at its pivot or guide and its roller's pin "
          "(a [….friction] table).", NO_UNIT, TAB, "none (frictionless)",
          "a friction table; needs mass_kg (inertia_kg_m2 when oscillating); not for a flat "
          "follower", False),
        K("synthesize", "Size the cam instead of giving base_radius_m (a [….synthesize] "
          "table).", NO_UNIT, TAB, "none (base_radius_m as given)",
          "a synthesize table; refuses base_radius_m beside it", False),
    )),
    KeyTable("cam.synthesize", "[mechanism.<name>.synthesize] of a cam", (
        K("base_radius", "What to size: the smallest base radius that meets the cam's limits "
          "(max_pressure_angle_deg, undercut, max_stress_pa) at the optimised timing.",
          NO_UNIT, TEXT, REQ, "smallest", None),
        K("max_base_radius_m", "The largest base radius searched; the first round's cam. "
          "A cam sized to it (within 1e-9) has sizing status at_upper_bound: the bound, not "
          "a limit of the cam, set it and the phase angles were stretched to fit (a CLI "
          "warning; raise the bound to shorten them).",
          "m", NUM, REQ, "finite, > 0; above min_base_radius_m", None),
        K("min_base_radius_m", "The smallest base radius searched.", "m", NUM,
          "none (just above the roller's radius)", "finite, > 0; above the roller's radius",
          None),
        K("offset_m", "The range searched for a translating follower's offset (the one "
          "needing the smallest radius).", "m", ARR, "none (offset_m as given)",
          "[low, high], finite, low < high" + TR + " or flat", None),
        K("pivot_distance_m", "The range searched for an oscillating follower's pivot "
          "distance, its arm length held.", "m", ARR, "none (pivot_distance_m as given)",
          "[low, high], finite, low < high" + OS, None),
    ), intro=(
        "A cam sized by the machine's run: the smallest base radius that meets "
        "the pressure angle, undercut and Hertz stress at its phase angles in the optimised "
        "cyclogram and the nominal speed (cyclomech.synthesis.cam_size), iterated with the "
        "timing LP to a fixed point (at most 20 rounds; no fixed point fails the run). The "
        "first round's cam has max_base_radius_m. The report and results.json (cams, "
        "sizing; resizing) say what was chosen and which limit binds."
    )),
    KeyTable("cam.friction", "[mechanism.<name>.friction] of a cam", (
        K("pivot_radius_m", "The oscillating arm's pivot pin (journal) radius r_p (a friction "
          "torque μ_p·r_p·|R| against the arm's turning, R the pivot's reaction).", "m", NUM,
          "none (no friction at the pivot)", "finite, ≥ 0; with pivot_mu" + OS, None),
        K("pivot_mu", "The pivot's Coulomb friction coefficient μ_p.", NO_UNIT, NUM,
          "none (no friction at the pivot)",
          "finite, ≥ 0; with pivot_radius_m; above 0.5 warns" + OS, None),
        K("guide_mu", "The translating follower's guide's Coulomb friction coefficient μ_g "
          "(a force μ_g·|F⊥| against its sliding, F⊥ the contact force across the stem).",
          NO_UNIT, NUM, "none (no friction in the guide)",
          "finite, ≥ 0; above 0.5 warns" + TR, None),
        K("roller_pin_radius_m", "The roller's pin radius r_pin (a friction torque "
          "μ_r·r_pin·|F| against the roller's turning on its arm or stem).", "m", NUM,
          "none (no friction in the roller)",
          "finite, 0 ≤ roller_pin_radius_m < roller_radius_m; with roller_pin_mu", None),
        K("roller_pin_mu", "The roller pin's Coulomb friction coefficient μ_r (about 0.005 "
          "for a needle bearing, 0.05–0.1 for a plain one).", NO_UNIT, NUM,
          "none (no friction in the roller)",
          "finite, ≥ 0; with roller_pin_radius_m; above 0.5 warns", None),
    ), intro=(
        "Coulomb friction of a cam's follower, solved with the contact force "
        "at the nominal speed (a closed form per cam angle): at an oscillating arm's pivot "
        "(its centre of mass taken on the pivot, so the pivot carries the contact force) or "
        "a translating stem's guide (one effective guide), and at the roller's pin (the "
        "roller rolls on the cam). Where the follower dwells the pivot or guide costs "
        "nothing; the roller still turns. The efficiency and the torque friction adds reach "
        "the report and the main shaft as a linkage's do. A flat-faced follower refuses "
        "friction."
    )),
    KeyTable("cam.segment", "[[mechanism.<name>.segment]] of a cam", (
        K("kind", "The segment's kind.", NO_UNIT, TEXT, REQ, "one of rise, dwell, return",
          None),
        K("angle_deg", "The cam angle the segment takes.", "deg", NUM, REQ,
          "finite, > 0; the segments' angles sum to 360", None),
        K("stroke_m", "The follower's travel (translating and flat followers).", "m", NUM,
          "0", STROKE + TR, None),
        K("stroke_deg", "The arm's rotation (oscillating follower).", "deg", NUM, "0",
          STROKE + OS, None),
        K("law", "The motion law of a rise or return.", NO_UNIT, TEXT, "cycloidal",
          "a string; for a rise or return " + LAWS + ", or of cyclomech.motion.SEGMENT_LAWS "
          "(the cam is then a motion program)", None),
        K("start_velocity_m_per_rad", "The follower's velocity at the segment's start "
          "(a moving end; translating and flat).", "m/rad", NUM,
          "none (the previous segment's end; rest for the first)", FIN + TR, None),
        K("end_velocity_m_per_rad", "The follower's velocity at the segment's end.",
          "m/rad", NUM, "none (the next segment's start, else rest)", FIN + TR, None),
        K("start_velocity_deg_per_rad", "The arm's angular velocity at the segment's start "
          "(oscillating).", "deg/rad", NUM,
          "none (the previous segment's end; rest for the first)", FIN + OS, None),
        K("end_velocity_deg_per_rad", "The arm's angular velocity at the segment's end "
          "(oscillating).", "deg/rad", NUM, "none (the next segment's start, else rest)",
          FIN + OS, None),
        K("points_m", "A spline segment's table: rows [cam angle from its start in deg, "
          "displacement in m].", "deg, m", ARR, "none (law spline needs it)",
          "rows of 2 numbers, the first at 0, the last at angle_deg" + TR, None),
        K("points_deg", "A spline segment's table (oscillating): rows [cam angle from its "
          "start in deg, arm angle in deg].", "deg, deg", ARR, "none (law spline needs it)",
          "rows of 2 numbers, the first at 0, the last at angle_deg" + OS, None),
        K("degree", "A spline segment's degree.", NO_UNIT, NUM, "3", "3 (C2 cubic) or 5 "
          "(C4 quintic)", None),
        K("load_n", "The external force on the follower during the segment.", "N", NUM,
          "0", FIN + TR + "; needs mass_kg", None),
        K("load_nm", "The external torque on the arm during the segment.", "N·m", NUM,
          "0", FIN + OS + "; needs inertia_kg_m2", None),
        K("arc", "The cyclogram operation whose phase angle the segment takes.", NO_UNIT,
          ARR, "none (the segment bounds no operation)",
          "[from, to], two event names of an operation of the cyclogram, each bound once; "
          "not on a dwell", None),
    ), intro=(
        "One row of a cam's program; the stroke and load keys follow the follower "
        "(``_m`` and ``_n`` for translating and flat followers, ``_deg`` and ``_nm`` for "
        "an oscillating one; the other pair is refused)."
    )),
)
# fmt: on
