"""The records of the machine-file format reference: one :class:`KeyDoc` per key,
one :class:`KeyTable` per table.

Each table's owner carries its records beside its parser: a mechanism kind in its
class attribute ``key_docs`` (its own table first, then its sub-tables), the
machine (``[machine]`` and the top level) and the cyclogram (``[cyclogram]``,
``[[operation]]``, ``[[constraint]]``) in theirs. :mod:`cyclomech._keydocs` only
gathers them (the kinds from the registry, in its order) and renders the page. This
module is low in the house so that every owner can import it.

Columns of a record: ``unit`` as the file takes it (the key names say ``_deg``,
``_rpm``, ``_m``; "—" for text, flags and counts); ``type``: number, integer, text,
bool, array, table or array of tables; ``default``: the value taken when the key is
absent, "required", "required unless …" or "none" (the feature it turns on is
off); ``valid``: the rule the parser checks; ``sweep``: whether
:func:`cyclomech.sweep` may vary it as a number (``<mechanism>.<key>``,
``machine.<key>``), None for the rows of a sub-table, whose numbers a sweep sets by
a path (``<mechanism>.lengths.3.length``) where the kind's ``varied_tables`` name
the parent key.

The short names below (:data:`NUM`, :data:`REQ`, :data:`POS`, …) keep the owners'
records one line of thought each.

>>> KeyTable("dwell", "kind = dwell", (KeyDoc("kind", "The mechanism's kind.", NO_UNIT,
...          TEXT, REQ, "dwell", False),)).keys[0].default
'required'
"""

from __future__ import annotations

from dataclasses import dataclass

from ._arrays import flag
from ._core import MOTION_LAWS

__all__ = [
    "ARR",
    "BOOL",
    "FIN",
    "INT",
    "LAWS",
    "NONE",
    "NONNEG",
    "NO_UNIT",
    "NUM",
    "POS",
    "REQ",
    "ROWS",
    "TAB",
    "TEXT",
    "KeyDoc",
    "KeyTable",
]


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

    def __post_init__(self) -> None:
        _texts(self, ("name", "meaning", "unit", "type", "default", "valid"))
        if self.sweep is not None:
            flag("KeyDoc.sweep", self.sweep)


@dataclass(frozen=True)
class KeyTable:
    """One table of a machine file, with its keys, as the format reference shows it.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The table's name in the reference: a kind's name for its
        ``[mechanism.<name>]`` table (``"cam"``), ``<kind>.<key>`` for a sub-table
        (``"cam.segment"``), or the owner's name (``"machine"``, ``"operation"``).
    title : str
        Its section title on the page (``"kind = cam"``).
    keys : tuple of KeyDoc
        Every key the table takes, in the page's order.
    intro : str, optional
        The paragraph under the title; default None: the first paragraph of the
        kind's class docstring (for a kind's own table).

    Examples
    --------
    >>> t = KeyTable("dwell", "kind = dwell", ())
    >>> t.title, t.intro
    ('kind = dwell', None)
    """

    name: str
    title: str
    keys: tuple[KeyDoc, ...]
    intro: str | None = None

    def __post_init__(self) -> None:
        _texts(self, ("name", "title") if self.intro is None else ("name", "title", "intro"))
        if not isinstance(self.keys, tuple) or not all(isinstance(k, KeyDoc) for k in self.keys):
            raise TypeError(f"KeyTable.keys must be a tuple of KeyDoc; got {self.keys!r:.80}")


def _texts(record: object, fields: tuple[str, ...]) -> None:
    """TypeError naming the first of ``fields`` of ``record`` that is not a string
    (the page prints them as they are)."""
    for field in fields:
        value = getattr(record, field)
        if not isinstance(value, str):
            kind = type(record).__name__
            raise TypeError(f"{kind}.{field} must be a string; got {value!r:.80}")


# The column values the owners' records share.
NUM, INT, TEXT, BOOL = "number", "integer", "text", "bool"
ARR, TAB, ROWS = "array", "table", "array of tables"
REQ, NONE, NO_UNIT = "required", "none", "—"
POS = "finite, > 0"
NONNEG = "finite, ≥ 0"
FIN = "any finite number"
#: The rule of a key that names a motion law: the core's laws
#: (:data:`cyclomech.motion.NAMES`), so a new law is listed with no edit here.
LAWS = "one of " + ", ".join(MOTION_LAWS)
