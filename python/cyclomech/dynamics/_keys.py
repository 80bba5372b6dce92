"""The keys of a machine file's ``[drive]`` table (the main shaft's motor, gear and
flywheel) and ``[[balance]]`` rows (counterweights to find), for the machine-file
format reference (:attr:`cyclomech.Machine.key_docs`; ``tests/package/test_keydocs.py``
holds them equal to the reader's key sets and checks their defaults and ranges).

>>> [t.name for t in DRIVE_KEY_DOCS]
['drive', 'drive.shaft', 'drive.link', 'balance']
"""

from __future__ import annotations

from .._keydoc import ARR, NO_UNIT, NUM, POS, REQ, TEXT, KeyTable
from .._keydoc import KeyDoc as K

# The rule of a key only one kind of motor takes.
IND = "; induction motors only"
LIN = "; linear motors only"
CON = "; constant-torque motors only"
TAB_ = "; table motors only"

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: The machine file's ``[drive]`` and ``[[balance]]`` tables' keys, in the format
#: reference's order (the machine's key documentation ends with them).
DRIVE_KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("drive", "[drive]", (
        K("motor", "The motor's characteristic: torque against speed.", NO_UNIT, TEXT, REQ,
          "one of induction, linear, constant, table", False),
        K("rated_rpm", "The induction motor's rated speed.", "rpm", NUM,
          "required for an induction motor", "0 < rated_rpm < synchronous_rpm" + IND, False),
        K("synchronous_rpm", "The induction motor's synchronous speed (60·f/pole pairs).",
          "rpm", NUM, "required for an induction motor", POS + IND, False),
        K("breakdown_ratio", "The breakdown torque over the rated torque, λ = M_k/M_n (Kloss's "
          "formula).", NO_UNIT, NUM, "required for an induction motor", "finite, > 1" + IND,
          False),
        K("rated_power_w", "The induction motor's rated power (its rated torque is P/ω).",
          "W", NUM, "none: give this or rated_torque_nm", POS + IND, False),
        K("rated_torque_nm", "The induction motor's rated torque.", "N·m", NUM,
          "none: give this or rated_power_w", POS + IND, False),
        K("stall_torque_nm", "The linear (DC, servo) motor's torque at rest.", "N·m", NUM,
          "required for a linear motor", POS + LIN, False),
        K("no_load_rpm", "The linear motor's speed at zero torque.", "rpm", NUM,
          "required for a linear motor", POS + LIN, False),
        K("torque_nm", "The constant motor's torque, or the table motor's torque at each of "
          "speed_rpm.", "N·m", "number or array", "required for a constant or table motor",
          "finite" + CON + "; for a table, one finite number per speed" + TAB_, False),
        K("speed_rpm", "The table motor's speeds.", "rpm", ARR, "required for a table motor",
          "two or more finite numbers, strictly increasing" + TAB_, False),
        K("gear_ratio", "The gear between motor and main shaft: motor speed over shaft "
          "speed.", NO_UNIT, NUM, "1 (a direct drive)", POS, False),
        K("gear_efficiency", "The gear's efficiency.", NO_UNIT, NUM, "1",
          "finite, 0 < η ≤ 1", False),
        K("rotor_inertia_kg_m2", "The rotor's (and the motor-side gears') inertia; the "
          "shaft sees gear_ratio² times it.", "kg·m²", NUM, "0", "finite, ≥ 0", False),
        K("flywheel_kg_m2", "The flywheel on the main shaft.", "kg·m²", NUM,
          "none: sized by simulation for [machine] speed_fluctuation", "finite, ≥ 0", False),
    ), intro=(
        "The main shaft's motor, gear and flywheel: with it the report gives the shaft's "
        "real speed over the cycle (the machine's equation of motion with its reduced "
        "inertia, not the constant speed of the kinetostatics), the real coefficient of "
        "speed fluctuation and the flywheel sized by simulation beside the energy "
        "method's. Optional; without it the main shaft turns at constant speed."
    )),
    KeyTable("drive.shaft", "[drive.shaft]", (
        K("take_off", "Every mechanism on the main shaft, in order from the motor's end.",
          NO_UNIT, ARR, REQ, "the names of the mechanisms that load the main shaft, each once",
          None),
        K("stiffness_nm_per_rad", "Each shaft segment's torsional stiffness, the one before "
          "each take-off point (G·I_p/L for a plain shaft).", "N·m/rad", ARR, REQ,
          "one finite number > 0 per take_off point", None),
        K("hub_inertia_kg_m2", "The constant inertia at each take-off point: the crank, cam "
          "disc, gear and shaft section there.", "kg·m²", ARR, REQ,
          "one finite number > 0 per take_off point", None),
        K("damping_ratio", "The segments' damping ratio (each segment's damping "
          "2ζ·√(c·J̄), J̄ its node's mean inertia).", NO_UNIT, NUM, "0.02", "finite, ≥ 0",
          None),
    ), intro=(
        "The main shaft as torsional springs between the motor's end (the flywheel, "
        "rotor and gears) and the mechanisms' take-off points: with it the report gives "
        "each node's twist and each working member's dynamic error over the cycle under "
        "the motor, and the speed at which an error reaches its bound. Needs [drive]; "
        "optional."
    )),
    KeyTable("drive.link", "[drive.link.<mechanism>]", (
        K("frequency_hz", "The natural frequency of the working member on its link or "
          "transmission (the member as one mass on it).", "Hz", NUM, "inf (a rigid link)",
          "> 0", None),
        K("damping_ratio", "The link's damping ratio.", NO_UNIT, NUM, "0.05", "finite, ≥ 0",
          None),
        K("max_error_m", "The largest dynamic error allowed of a member that travels "
          "(a slider, a follower, a point: its distance from the rigid machine's).", "m", NUM,
          "none", "finite, > 0; not with max_error_deg", None),
        K("max_error_deg", "The largest dynamic error allowed of a member that turns (an "
          "oscillating follower).", "deg", NUM, "none", "finite, > 0; not with max_error_m",
          None),
    ), intro=(
        "A working member's elastic link, one table per mechanism of [drive.shaft]'s "
        "take_off (a mechanism without one has a rigid link): its dynamic error is the "
        "shaft's lag and the link's vibration together. Optional."
    )),
    KeyTable("balance", "[[balance]]", (
        K("mechanism", "The linkage (or press) to balance.", NO_UNIT, TEXT, REQ,
          "a linkage of the machine with masses, or a press with its masses and load", False),
        K("links", "The links to counterweight, each by two of its joints (a press's "
          'carrier: ["O", "planet"]).', NO_UNIT, ARR,
          REQ, "a non-empty array of [joint, joint] pairs, each link pivoted to the frame",
          False),
        K("objective", "What the counterweights minimise: the shaking force's RMS or peak, "
          "or the RMS force plus torque_weight times the driving torque's RMS.", NO_UNIT,
          TEXT, "rms_force", "one of rms_force, peak_force, rms_force+torque", False),
        K("torque_weight", "The RMS driving torque's weight in rms_force+torque.", "1/m",
          NUM, "1", "finite, ≥ 0; only with objective = rms_force+torque", False),
        K("max_mass_radius_kg_m", "The largest m·r of each counterweight of the row: the "
          "optimum under it, a counterweight it stops flagged as at the bound.", "kg·m", NUM,
          "none (no bound)", POS, False),
    ), intro=(
        "Counterweights to find for a linkage, one row each: the report gives their "
        "mass·radius and angle on each link and the shaking force before and after, at "
        "the nominal speed. Optional."
    )),
)
# fmt: on
