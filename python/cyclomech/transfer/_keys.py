"""The keys of a ``kind = "transfer"`` table, for the machine-file format reference
(:attr:`TransferMechanism.key_docs`; ``tests/test_keydocs.py`` holds them equal to
the parser's key set and checks their defaults and ranges).

>>> [t.name for t in KEY_DOCS]
['transfer']
"""

from __future__ import annotations

from .._keydoc import (
    INT,
    NO_UNIT,
    NUM,
    POS,
    REQ,
    TEXT,
    KeyTable,
)
from .._keydoc import KeyDoc as K

# The records are a table each: one key per record, aligned for reading.
# fmt: off
#: A rotor transfer's table's keys.
KEY_DOCS: tuple[KeyTable, ...] = (
    KeyTable("transfer", "kind = transfer", (
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
    )),
)
# fmt: on
