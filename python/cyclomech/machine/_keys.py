"""The keys of a machine file's top level and of its ``[machine]`` table, for the
machine-file format reference (:attr:`Machine.key_docs`; ``tests/package/test_keydocs.py``
holds them equal to the reader's key sets and checks their defaults and ranges).

>>> [t.name for t in KEY_DOCS]
['file', 'machine']
"""

from __future__ import annotations

from .._keydoc import (
    ARR,
    BOOL,
    INT,
    NO_UNIT,
    NUM,
    REQ,
    ROWS,
    TAB,
    TEXT,
    KeyTable,
)
from .._keydoc import KeyDoc as K

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: The top level's and ``[machine]``'s keys, in the page's order.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("file", "The top level", (
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
        K("drive", "The main shaft's motor, gear and flywheel, for its real speed.", NO_UNIT,
          TAB, "none (the main shaft at constant speed)", "a table", False),
        K("balance", "Linkages to balance by counterweights, one [[balance]] row each.",
          NO_UNIT, ROWS, "none (no balancing)", "an array of tables", False),
    ), intro=(
        "A machine file is TOML; these are its top-level tables."
    )),
    KeyTable("machine", "[machine]", (
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
    ), intro=(
        "The machine as a whole: its name, the speed range studied and the grids."
    )),
)
# fmt: on
