"""The keys of a ``kind = "press"`` table and of its sub-tables (the deformation
force, phase), for the machine-file format reference (:attr:`PressMechanism.key_docs`;
``tests/package/test_keydocs.py`` holds them equal to the parser's key sets and checks their
defaults and ranges).

>>> [t.name for t in KEY_DOCS]
['press', 'press.deformation_force', 'press.friction', 'phase']
"""

from __future__ import annotations

from .._keydoc import (
    ARR,
    FIN,
    NO_UNIT,
    NONNEG,
    NUM,
    POS,
    REQ,
    TAB,
    TEXT,
    KeyTable,
)
from .._keydoc import KeyDoc as K
from .._kind import Phase

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: A press's table and its sub-tables' keys, in the page's order; the phase
#: table, which a linkage shares, last.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("press", "kind = press", (
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
          NO_UNIT, TAB, "none (no force)", "a table {s_above_bdc_m, force_n}", False),
        K("slider_mass_kg", "The slider's mass.", "kg", NUM, "0", NONNEG, True),
        K("rod_mass_kg", "The (uniform) rod's mass.", "kg", NUM, "0", NONNEG, True),
        K("phase", "Where BDC sits in the cycle {event, crank_deg}: the carrier's angle past "
          "BDC.", NO_UNIT, TAB, "the carrier at BDC at cycle angle 0", "a phase table", False),
        K("friction", "The friction of its slider's guide and its rod's pins (a "
          "[….friction] table).", NO_UNIT, TAB, "none (frictionless)",
          "a friction table; needs deformation_force, slider_mass_kg or rod_mass_kg", False),
    )),
    KeyTable("press.deformation_force", "deformation_force of a press", (
        K("s_above_bdc_m", "The slider's heights above BDC.", "m", ARR, REQ,
          "at least 2 finite values, strictly increasing, within [0, S_p]", None),
        K("force_n", "The force at each height (linear between, zero outside).", "N", ARR, REQ,
          "finite, ≥ 0, as many as s_above_bdc_m", None),
    ), intro=(
        "The deformation-force diagram of a press: linear between its points, zero outside them."
    )),
    KeyTable("press.friction", "[mechanism.<name>.friction] of a press", (
        K("guide_mu", "The slider guide's Coulomb friction coefficient μ_g (a force "
          "μ_g·|H| against the sliding, H the guide's normal force).", NO_UNIT, NUM,
          "none (no friction in the guide)", "finite, ≥ 0; above 0.5 warns", None),
        K("pin_radius_m", "The radius r of the rod's two pins (a friction torque μ·r·|F| "
          "against the rod's turning on the planet and on the slider).", "m", NUM,
          "none (no friction in the pins)", "finite, ≥ 0; with pin_mu", None),
        K("pin_mu", "The rod's pins' Coulomb friction coefficient μ.", NO_UNIT, NUM,
          "none (no friction in the pins)",
          "finite, ≥ 0; with pin_radius_m; above 0.5 warns", None),
    ), intro=(
        "Coulomb friction of a press drive: at the slider's guide and the rod's "
        "two pins, solved with the slider's and the rod's Newton–Euler equations at the "
        "nominal speed. The efficiency and the torque friction adds reach the report and "
        "the main shaft as a linkage's do."
    )),
    Phase.key_docs,
)
# fmt: on
