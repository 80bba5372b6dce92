"""The keys of a ``kind = "cam_stop"`` table, for the machine-file format reference
(:attr:`CamStop.key_docs`; ``tests/package/test_keydocs.py`` holds them equal to the
parser's key set and checks their defaults and ranges).

>>> [t.name for t in KEY_DOCS]
['cam_stop']
"""

from __future__ import annotations

from .._keydoc import (
    ARR,
    LAWS,
    NO_UNIT,
    NONNEG,
    NUM,
    POS,
    REQ,
    TEXT,
    KeyTable,
)
from .._keydoc import KeyDoc as K

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: A cam stop's table's keys.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("cam_stop", "kind = cam_stop", (
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
          False),
    )),
)
# fmt: on
