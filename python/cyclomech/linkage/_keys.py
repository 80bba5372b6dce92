"""The keys of a ``kind = "linkage"`` table and of its sub-tables (lengths, slider
guides, masses, loads, phase), for the machine-file format reference
(:attr:`LinkageMechanism.key_docs`; ``tests/package/test_keydocs.py`` holds them equal to the
parsers' key sets and checks their defaults and ranges).

>>> [t.name for t in KEY_DOCS][:2]
['linkage', 'linkage.lengths']
"""

from __future__ import annotations

from .._keydoc import (
    ARR,
    BOOL,
    INT,
    NO_UNIT,
    NONE,
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
from .._kind import Phase

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: A linkage's table and its sub-tables' keys, in the page's order; the phase
#: table, which a press shares, last.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("linkage", "kind = linkage", (
        K("kind", "The mechanism's kind.", NO_UNIT, TEXT, REQ, "linkage", False),
        K("name", "The linkage's name.", NO_UNIT, TEXT, NONE, "a string", False),
        K("points", "The joints in the drawn pose {joint = [x, y]} (it picks the assembly "
          "mode).", "m", TAB, REQ,
          "non-empty names, two finite coordinates each; every point on a link or with "
          "two guides", False),
        K("links", "The rigid links, each an array of its joints (3 or more: a ternary link).",
          NO_UNIT, ARR, REQ,
          "at least one link of at least two distinct points; mobility 1", False),
        K("ground", "The joints fixed to the frame.", NO_UNIT, ARR, REQ,
          "at least one point name", False),
        K("driver", "The crank [pivot, tip], turning once per machine cycle.", NO_UNIT, ARR,
          REQ, "two points of one link: the pivot a ground joint, the tip not", False),
        K("output", "The point whose motion is reported.", NO_UNIT, TEXT,
          "the last point of points", "a point's name", True),
        K("lengths", "Link lengths that replace the drawn distances.", NO_UNIT, ROWS,
          "none (lengths from the drawn points)",
          "an array of {joints, length} tables", False),
        K("sliders", "Prismatic joints {point = guide, or [guide, guide]}.", NO_UNIT, TAB,
          "none (no sliders)",
          "each point a moving point with one guide or two, the point drawn on its guide",
          False),
        K("max_acceleration_m_per_s2", "The limit on the output point's peak acceleration.",
          "m/s²", NUM, "none (no speed limit)", POS, True),
        K("phase", "Where the crank sits in the cycle {event, crank_deg}.", NO_UNIT, TAB,
          "the crank at 0 at cycle angle 0",
          "a phase table; needs mass, point_mass_kg or load", False),
        K("mass", "The links' masses, one [[…mass]] row per link.", NO_UNIT, ROWS,
          "none (no link masses)", "an array of tables, each link once", False),
        K("point_mass_kg", "Masses concentrated at points {point = kg}.", "kg", TAB,
          "none (no point masses)", "finite, ≥ 0, each at a moving point", False),
        K("load", "External forces and torques, one [[…load]] row each.", NO_UNIT, ROWS,
          "none (no loads)", "an array of tables", False),
        K("gravity_m_per_s2", "The acceleration of gravity [gx, gy].", "m/s²", ARR,
          "none (no gravity)",
          "two finite numbers; needs mass or point_mass_kg", False),
        K("friction", "The friction of its joints and guides (a [….friction] table).", NO_UNIT,
          TAB, "none (frictionless)",
          "a friction table; needs mass, point_mass_kg or load", False),
        K("synthesize", "Requirements the linkage is synthesised from instead of its "
          "dimensions (a [….synthesize] table).", NO_UNIT, TAB,
          "none (the drawn dimensions)",
          "a synthesize table; then no points, links, ground, driver, output, lengths or "
          "sliders", False),
    )),
    KeyTable("linkage.lengths", "[[mechanism.<name>.lengths]] of a linkage", (
        K("joints", "The two joints the length joins.", NO_UNIT, ARR, REQ,
          "[a, b], two joints of one link", None),
        K("length", "The distance between them.", "m", NUM, REQ, POS, None),
    ), intro=(
        "One length of a linkage's ``lengths`` array."
    )),
    KeyTable("linkage.sliders", "a guide in sliders of a linkage", (
        K("ground", "A guide fixed to the frame, by its direction [dx, dy].", NO_UNIT, ARR,
          "none (give ground or link)", "two finite numbers, not both 0", None),
        K("link", "A guide along a link, through two of its joints [b, c].", NO_UNIT, ARR,
          "none (give ground or link)",
          "two joints of one link, the sliding point not on that link", None),
    ), intro=(
        "A guide of ``sliders``: a table with exactly one of these keys; a point takes "
        "one guide, or an array of two (a PRP dyad)."
    )),
    KeyTable("linkage.mass", "[[mechanism.<name>.mass]] of a linkage", (
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
    ), intro=(
        "One link's mass; give its centre of mass one way at most."
    )),
    KeyTable("linkage.load", "[[mechanism.<name>.load]] of a linkage", (
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
          "at least 2 finite angles, strictly increasing over at most 360 (all within "
          "±2π and spanning at most 2π warns: radians?)", None),
    ), intro=(
        "One external load: ``point`` with ``force_n``, or ``link`` with ``torque_nm``, "
        "optionally as a table over the crank angle ``angle_deg``."
    )),
    KeyTable("linkage.friction", "[mechanism.<name>.friction] of a linkage", (
        K("pin_radius_m", "Every joint's pin (journal) radius r (a friction torque μ·r·R, R "
          "the reaction).", "m", NUM,
          "none (no Coulomb friction in the pins)", "finite, ≥ 0; with pin_mu", None),
        K("pin_mu", "Every joint's Coulomb friction coefficient μ.", NO_UNIT, NUM,
          "none (no Coulomb friction in the pins)",
          "finite, ≥ 0; with pin_radius_m; above 0.5 warns", None),
        K("pin_viscous_nm_s_per_rad", "Every joint's viscous coefficient c (a torque "
          "c·ω_rel).", "N·m·s/rad", NUM, "0", NONNEG, None),
        K("guide_mu", "Every slider's guide's Coulomb friction coefficient μ (a force "
          "μ·N, N the normal force).", NO_UNIT, NUM, "none (no Coulomb friction in the guides)",
          "finite, ≥ 0; above 0.5 warns; needs a slider", None),
        K("guide_viscous_n_s_per_m", "Every slider's guide's viscous coefficient c (a force "
          "c·v_rel).", "N·s/m", NUM, "0", "finite, ≥ 0; needs a slider", None),
        K("pins", "Per-joint overrides {joint = {radius_m, mu, viscous_nm_s_per_rad}}.",
          NO_UNIT, TAB, "none (the defaults for every joint)",
          "joints of two members of the linkage; a key left out takes the default", None),
        K("guides", "Per-slider overrides {point = {mu, viscous_n_s_per_m}}.", NO_UNIT, TAB,
          "none (the defaults for every guide)",
          "sliders' points of the linkage; a key left out takes the default", None),
    ), intro=(
        "The friction of a linkage's joints and slider guides: Coulomb "
        "friction μ·r·R in each pin (R the joint's reaction) and μ·N on each guide (N the "
        "normal force), solved with the reactions, "
        "and a viscous term. The ``pin_*`` and ``guide_*`` keys apply to every joint of two "
        "members (two links, a link and the frame, a link and a slider's block) and every "
        "guide; ``pins`` and ``guides`` override them one by one. One line is the common "
        "case: ``friction = {pin_radius_m = 0.015, pin_mu = 0.08}``. Coulomb friction is "
        "taken at the nominal speed's velocities and reactions, and added to the torque the "
        "main shaft, its flywheel and its ``[drive]`` see. A cam and a press "
        "take their own friction tables (a cam's pivot or guide and roller pin, a press's "
        "slider guide and rod pins)."
    )),
    KeyTable("linkage.friction.pins", "a joint in pins of a linkage's friction", (
        K("radius_m", "The pin's (journal's) radius r.", "m", NUM, "pin_radius_m",
          "finite, ≥ 0; with mu", None),
        K("mu", "The Coulomb friction coefficient μ.", NO_UNIT, NUM, "pin_mu",
          "finite, ≥ 0; with radius_m; above 0.5 warns", None),
        K("viscous_nm_s_per_rad", "The viscous coefficient c (a torque c·ω_rel).",
          "N·m·s/rad", NUM, "pin_viscous_nm_s_per_rad", NONNEG, None),
    ), intro=(
        "One joint's friction in ``pins``, keyed by the joint's name; a key left out "
        "takes the table's ``pin_*`` default."
    )),
    KeyTable("linkage.friction.guides", "a slider in guides of a linkage's friction", (
        K("mu", "The guide's Coulomb friction coefficient μ.", NO_UNIT, NUM, "guide_mu",
          "finite, ≥ 0; above 0.5 warns", None),
        K("viscous_n_s_per_m", "The viscous coefficient c (a force c·v_rel).", "N·s/m", NUM,
          "guide_viscous_n_s_per_m", NONNEG, None),
    ), intro=(
        "One slider's guide friction in ``guides``, keyed by the sliding point; a key "
        "left out takes the table's ``guide_*`` default (a point with two guides: both)."
    )),
    KeyTable("linkage.synthesize", "[mechanism.<name>.synthesize] of a linkage", (
        K("scheme", "The scheme to synthesise: seed 001's knife drives br125 (p = 1, "
          "structure 1–3), br136 (p = 2, 1–2–3), brp4 (p = 3, 1–2–2–3) with the keys "
          "below; function, path, motion or dwell_sixbar with the keys of their own tables "
          "(below).", NO_UNIT, TEXT, REQ,
          "br125, br136, brp4, function, path, motion or dwell_sixbar", None),
        K("stroke_m", "The knife point E's stroke: max − min of its travel along −y.", "m",
          NUM, REQ, POS, None),
        K("cut_deg", "The crank angle of the working stroke, from the knife's top to its "
          "bottom (the return takes the rest).", "deg", NUM, REQ, "in (0, 360)", None),
        K("knife_m", "The knife holder's length BC; the frame is the scheme's scaled to it.",
          "m", NUM, "the scheme's preset", POS, None),
        K("envelope_m", "A frame box [x_min, y_min, x_max, y_max] every joint stays in over "
          "the turn.", "m", ARR, "none (no envelope)",
          "four finite numbers, x_min < x_max, y_min < y_max, holding the ground pivots",
          None),
        K("min_transmission_deg", "The least transmission angle at every dyad joint and the "
          "class III group's driven joint.", "deg", NUM, "30", "in [0, 90)", None),
        K("max_length_ratio", "The longest link over the shortest, at most.", NO_UNIT, NUM,
          "25", "finite, > 1", None),
        K("stroke_tol_m", "How close the stroke must come.", "m", NUM, "0.0005", POS, None),
        K("cut_tol_deg", "How close the cut's crank angle must come.", "deg", NUM, "0.5", POS,
          None),
        K("seed", "The optimiser's seed (a seed repeats its result).", NO_UNIT, INT, "1",
          "a whole number ≥ 0", None),
        K("popsize", "Candidates per design variable in each generation.", NO_UNIT, INT, "15",
          "a whole number ≥ 5", None),
        K("maxiter", "Generations of differential evolution at most.", NO_UNIT, INT, "120",
          "a whole number ≥ 1", None),
        K("compare", "Synthesise all three schemes and compare them in the report.", NO_UNIT,
          BOOL, "false", "true or false", None),
        K("compare_rpm", "The crank speed of the comparison's torque, loads and "
          "acceleration.", "rpm", NUM, "45", "finite, > 0; needs compare", None),
        K("compare_max_acceleration_m_per_s2", "The knife's allowed acceleration for the "
          "comparison's speed limit.", "m/s²", NUM, "8", "finite, > 0; needs compare", None),
        K("holder_kg", "The comparison's knife-holder mass.", "kg", NUM, "80",
          "finite, > 0; needs compare", None),
        K("link_kg_per_m", "The comparison's mass per length of every other moving link.",
          "kg/m", NUM, "10", "finite, > 0; needs compare", None),
        K("cut_force_n", "The comparison's cutting force on E, upwards over the cut.", "N",
          NUM, "0", "finite, ≥ 0; needs compare", None),
    ), intro=(
        "Requirements instead of dimensions: ``cyclomech run`` synthesises the "
        "linkage (``cyclomech.synthesis.knife_drive``: differential evolution over the "
        "scheme's link lengths, each generation solved in one batch call), reports what it "
        "chose and why, and analyses it as any other linkage; the masses, loads and phase "
        "of the table name the scheme's joints (A, B, C, D, E, F, O; br136 adds G, J; "
        "brp4 G, J, K, M, P). The knife's stroke is its travel along −y; its top and "
        "bottom are the crank angles of its highest and lowest positions."
    )),
    KeyTable("linkage.synthesize.function", "synthesize of a linkage: scheme = function", (
        K("scheme", "A four-bar function generator: its output rocker's angle ψ follows the "
          "crank angle φ (both from the ground line A → D).", NO_UNIT, TEXT, REQ, "function",
          None),
        K("precision_points_deg", "The precision points [[φ, ψ], …] the four-bar meets "
          "exactly (3) or by least squares (more).", "deg", ARR,
          "none (give one of precision_points_deg, function_deg, output_range_deg)",
          "at least 3 rows of 2 finite numbers, distinct φ", None),
        K("function_deg", "The wanted relation ψ(φ) as a table [[φ, ψ], …], interpolated "
          "linearly; precision points are placed on it.", "deg", ARR,
          "none (give one of precision_points_deg, function_deg, output_range_deg)",
          "at least 2 rows of 2 finite numbers, distinct φ", None),
        K("input_range_deg", "The input range [lo, hi] of φ (the structural error's range).",
          "deg", ARR, "the table's or the precision points' range",
          "two finite numbers, lo < hi; needed with output_range_deg", None),
        K("output_range_deg", "ψ at the input range's ends [ψ(lo), ψ(hi)]: ψ linear in φ.",
          "deg", ARR, "none (give one of precision_points_deg, function_deg, output_range_deg)",
          "two finite numbers; needs input_range_deg", None),
        K("points", "Precision points placed on the relation (3 exact, more least squares).",
          NO_UNIT, INT, "3", "a whole number ≥ 3; not with precision_points_deg", None),
        K("spacing", "How they are placed over the input range.", NO_UNIT, TEXT, "chebyshev",
          "chebyshev or uniform; not with precision_points_deg", None),
        K("ground_m", "The ground length A–D (the equation fixes only ratios).", "m", NUM, "1",
          POS, None),
        K("offsets_deg", "Origins of the scales to try [[Δφ, Δψ], …], one candidate each.",
          "deg", ARR, "[[0, 0]]", "rows of 2 finite numbers", None),
        K("min_transmission_deg", "The least transmission angle over the crank's turn.", "deg",
          NUM, "0", "in [0, 90)", None),
    ), intro=(
        "A four-bar function generator (``cyclomech.synthesis.function_generation``, "
        "Freudenstein's equation). A machine turns the crank fully: of the candidates, the "
        "first in function generation's ranking whose crank turns fully and meets every "
        "precision point on one branch is chosen, or the file is refused saying what each "
        "candidate missed. The linkage's points are A (crank pivot, the origin), B, C, D "
        "(output pivot on +x); its output C. Where the solution draws the crank flipped, the "
        "crank's angle is φ + 180° (the report says so)."
    )),
    KeyTable("linkage.synthesize.path", "synthesize of a linkage: scheme = path", (
        K("scheme", "A path generator: a coupler point P through target points.", NO_UNIT,
          TEXT, REQ, "path", None),
        K("targets_m", "The target points [[x, y], …].", "m", ARR, REQ,
          "at least 3 rows of 2 finite numbers (distinct without timing_deg)", None),
        K("timing_deg", "The crank angle at each target (only differences matter).", "deg",
          ARR, "none (P anywhere on its path)", "one finite number per target", None),
        K("mechanism", "The linkage searched.", NO_UNIT, TEXT, "four_bar",
          "four_bar or slider_crank", None),
        K("min_transmission_deg", "The least transmission angle over the turn.", "deg", NUM,
          "0", "in [0, 90)", None),
        K("max_length_ratio", "The longest link over the shortest, at most.", NO_UNIT, NUM,
          "none (no limit)", "finite, ≥ 1", None),
        K("pivot_box_m", "The box [x_min, x_max, y_min, y_max] the ground pivots stay in.",
          "m", ARR, "none (anywhere)", "four finite numbers, x_min ≤ x_max, y_min ≤ y_max",
          None),
        K("max_error_m", "The largest distance of a target from P allowed.", "m", NUM,
          "none (reported, not checked)", POS, None),
        K("seed", "The optimiser's seed (a seed repeats its result).", NO_UNIT, INT, "0",
          "a whole number ≥ 0", None),
        K("popsize", "Candidates per design variable in each generation.", NO_UNIT, INT, "15",
          "a whole number ≥ 5", None),
        K("maxiter", "Generations of differential evolution at most.", NO_UNIT, INT, "1000",
          "a whole number ≥ 1", None),
        K("polish", "Refine the best candidates by least squares after the search.", NO_UNIT,
          BOOL, "true", "true or false", None),
        K("bounds", "The search's ranges of the design variables {crank_m = [lo, hi], …} "
          "(a [….synthesize.bounds] table).", NO_UNIT, TAB,
          "ranges scaled to the targets' extent S (pivots ±3S, links up to 4S, crank 2S)",
          "a bounds table", None),
    ), intro=(
        "A four-bar or slider-crank whose coupler point P passes target points "
        "(``cyclomech.synthesis.path_generation``: differential evolution, each generation "
        "one parallel batch call, then least squares). Its crank must turn fully (a machine "
        "turns it once per cycle); the feasible candidate nearest the targets is chosen, and "
        "a file with none, or with the best error above max_error_m, is refused. Points A "
        "(crank pivot), B, C, D (four-bar) and P, the output."
    )),
    KeyTable("linkage.synthesize.path.bounds", "bounds of a path synthesis", (
        K("x0_m", "The crank pivot A's x.", "m", ARR, "targets' centre ± 3S", "[lo, hi], lo < hi",
          None),
        K("y0_m", "The crank pivot A's y.", "m", ARR, "targets' centre ± 3S", "[lo, hi], lo < hi",
          None),
        K("theta0_deg", "The ground line's (or slider guide's) direction.", "deg", ARR,
          "[-180, 180]", "[lo, hi], lo < hi", None),
        K("ground_m", "The ground link A–D (four-bar).", "m", ARR, "[0.1S, 4S]",
          "[lo, hi], lo < hi, hi > 0; four_bar only", None),
        K("offset_m", "The slider guide's offset from A (slider-crank).", "m", ARR,
          "[-2S, 2S]", "[lo, hi], lo < hi; slider_crank only", None),
        K("crank_m", "The crank A–B.", "m", ARR, "[0.05S, 2S]", "[lo, hi], lo < hi, hi > 0",
          None),
        K("coupler_m", "The coupler B–C.", "m", ARR, "[0.1S, 4S]", "[lo, hi], lo < hi, hi > 0",
          None),
        K("rocker_m", "The rocker D–C (four-bar).", "m", ARR, "[0.1S, 4S]",
          "[lo, hi], lo < hi, hi > 0; four_bar only", None),
        K("u_m", "The coupler point along B → C.", "m", ARR, "[-3S, 3S]", "[lo, hi], lo < hi",
          None),
        K("v_m", "The coupler point to the left of B → C.", "m", ARR, "[-3S, 3S]",
          "[lo, hi], lo < hi", None),
        K("phi1_deg", "The crank angle at the first target (with timing_deg).", "deg", ARR,
          "[-180, 180]", "[lo, hi], lo < hi; needs timing_deg", None),
    ), intro=(
        "The ranges differential evolution searches, overriding the defaults, which "
        "scale with the targets' extent S about their centre; a key left out keeps its "
        "default."
    )),
    KeyTable("linkage.synthesize.motion", "synthesize of a linkage: scheme = motion", (
        K("scheme", "A motion generator: a coupler that takes three poses.", NO_UNIT, TEXT,
          REQ, "motion", None),
        K("pose_points_m", "Where the coupler point P is at the three poses [[x, y], …].",
          "m", ARR, REQ, "3 rows of 2 finite numbers, the poses distinct", None),
        K("pose_angles_deg", "The angle of a coupler line through P at each pose.", "deg",
          ARR, REQ, "3 finite numbers", None),
        K("circle_points_m", "The moving pivots [[u, v], [u, v]] (the crank's, the rocker's) "
          "in the coupler frame (u along the pose angle from P, v to its left).", "m", ARR,
          "none (a grid of circle points is scanned)",
          "2 rows of 2 finite numbers; not with the grid's keys", None),
        K("grid_extent_m", "The scanned grid's half width around P.", "m", NUM,
          "the poses' largest distance from the first (at least 1 mm)", POS, None),
        K("grid_points", "Circle points per side of the grid (every pair is a candidate).",
          NO_UNIT, INT, "7", "a whole number from 2 to 15", None),
        K("min_transmission_deg", "The least transmission angle over the turn.", "deg", NUM,
          "0", "in [0, 90)", None),
        K("max_length_ratio", "The longest link over the shortest, at most.", NO_UNIT, NUM,
          "none (no limit)", "finite, ≥ 1", None),
    ), intro=(
        "A four-bar whose coupler takes three poses (``cyclomech.synthesis."
        "motion_generation``: circle and centre points). Of the candidates, those a machine "
        "can run — the crank turning fully and counter-clockwise through the poses in order, "
        "on one branch, within the limits — are kept, and the one with the largest worst "
        "transmission angle over the turn is chosen; a file with none is refused. Points A0, "
        "B0 (ground), A, B (moving pivots), P (the output; Q a helper where P is on AB)."
    )),
    KeyTable("linkage.synthesize.dwell_sixbar", "synthesize of a linkage: scheme = dwell_sixbar",
             (
        K("scheme", "A six-bar dwell linkage: the output rocker stands (nearly) still over "
          "part of the turn.", NO_UNIT, TEXT, REQ, "dwell_sixbar", None),
        K("dwell_deg", "The crank angle of the dwell.", "deg", NUM, REQ, "in (0, 360)", None),
        K("swing_deg", "The output rocker's swing over the rest of the turn.", "deg", NUM, REQ,
          "in (0, 180)", None),
        K("ground_m", "The four-bar's ground length A–D (every length scales with it).", "m",
          NUM, "1", POS, None),
        K("min_transmission_deg", "The least transmission angle in both loops.", "deg", NUM,
          "30", "in [0, 90]", None),
        K("max_length_ratio", "The six links' longest over shortest, at most.", NO_UNIT, NUM,
          "10", "finite, ≥ 1", None),
        K("max_residual_deg", "The output's motion over the dwell allowed, peak to peak.",
          "deg", NUM, "none (reported, not checked)", POS, None),
        K("seed", "The optimiser's seed (a seed repeats its result).", NO_UNIT, INT, "0",
          "a whole number ≥ 0", None),
        K("popsize", "Candidates per design variable in each generation.", NO_UNIT, INT, "20",
          "a whole number ≥ 1", None),
        K("maxiter", "Generations of differential evolution.", NO_UNIT, INT, "30",
          "a whole number ≥ 1", None),
    ), intro=(
        "A Stephenson III six-bar dwell linkage (``cyclomech.synthesis.dwell_sixbar``): a "
        "crank-rocker's coupler point P runs on a near-circular arc over the dwell and a "
        "dyad P–E of its radius holds the output joint E at the arc's centre. The feasible "
        "candidate (transmission angles, swing and length ratio held) whose output moves "
        "least over the dwell is chosen; a file with none, or above max_residual_deg, is "
        "refused. Points A (crank pivot, the origin), B, C, D (on +x), P, E (the output), F "
        "(the output's pivot); links A–B, B–C–P, D–C, P–E, F–E. The report gives the dwell's "
        "crank angles, for the phase."
    )),
    Phase.key_docs,
)
# fmt: on
