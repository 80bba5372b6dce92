"""The keys of a cyclogram's tables in a machine file (``[cyclogram]``,
``[[operation]]``, ``[[constraint]]`` and a constraint's terms), for the
machine-file format reference (:attr:`Cyclogram.key_docs`; ``tests/test_keydocs.py``
holds them equal to the file reader's key sets).

>>> [t.name for t in KEY_DOCS]
['cyclogram', 'operation', 'constraint', 'constraint.terms']
"""

from __future__ import annotations

from .._keydoc import (
    ARR,
    INT,
    NO_UNIT,
    NONE,
    NUM,
    REQ,
    ROWS,
    TEXT,
    KeyTable,
)
from .._keydoc import KeyDoc as K

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: The cyclogram's tables' keys, in the page's order.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("cyclogram", "[cyclogram]", (
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
    ), intro=(
        "The head of the cyclogram: the operations and events of one machine cycle are "
        "timed against the main shaft."
    )),
    KeyTable("operation", "[[operation]]", (
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
    ), intro=(
        "One operation (an arc between two events) of the cyclogram, with the bounds on "
        "its phase angle."
    )),
    KeyTable("constraint", "[[constraint]]", (
        K("name", "The constraint's name in the optimum's results.", NO_UNIT, TEXT,
          "constraint <n> (n its position among the constraints)",
          "a string (a number is refused); unique; not cycle, and not starting with min[, max[ or "
          "duration[", False),
        K("terms", "The sum Σ coeff·t(from, to) over operations.", NO_UNIT, ROWS, REQ,
          "at least one {from, to, coeff} table, each arc once", False),
        K("sense", "The comparison of the sum with rhs.", NO_UNIT, TEXT, REQ,
          "one of <=, >=, ==", False),
        K("rhs", "The right-hand side.", "deg", NUM, REQ, "finite, magnitude ≤ 1e12", False),
    ), intro=(
        "A linear constraint over operations' phase angles for the cyclogram's LP; "
        "each term is ``{from = …, to = …, coeff = …}``."
    )),
    KeyTable("constraint.terms", "terms of a [[constraint]]", (
        K("from", "The first event of the term's operation.", NO_UNIT, TEXT, REQ,
          "an event name (a string); from → to must be an operation", None),
        K("to", "The second event of the term's operation.", NO_UNIT, TEXT, REQ,
          "an event name (a string); from → to must be an operation", None),
        K("coeff", "The coefficient of the operation's phase angle.", NO_UNIT, NUM, REQ,
          "finite, magnitude ≤ 1e12", None),
    ), intro=(
        "One term of a constraint's ``terms`` array."
    )),
)
# fmt: on
