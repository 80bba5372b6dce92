"""The machine-file format reference: every key of every table a user writes.

Each table's owner carries its records (:class:`~cyclomech.machine.KeyTable` of
:class:`~cyclomech.machine.KeyDoc`) beside its parser: each mechanism kind in its
class attribute ``key_docs``, :class:`cyclomech.Machine` and
:class:`cyclomech.Cyclogram` in theirs. This module only gathers and renders them:
:func:`tables` lists the page's tables, the machine's and the cyclogram's first,
then each kind of the registry (:data:`cyclomech.machine.KINDS`) in its order, so a
registered kind is on the page with no edit here. ``tests/package/test_keydocs.py`` holds
the records' key sets equal to the parsers' own, so a key added to a parser without
a record fails the tests. :func:`render_table` and :func:`render_page` write
reStructuredText for the documentation site (``docs/_ext/keys_reference.py``).

>>> t = tables()["machine"]
>>> t.keys[0].name, t.keys[0].default
('name', "the file's name without its extension")
"""

from __future__ import annotations

import re
from pathlib import Path

from ._errors import InputError
from ._keydoc import KeyDoc, KeyTable

__all__ = ["KeyDoc", "KeyTable", "render_page", "render_table", "tables"]


def tables() -> dict[str, KeyTable]:
    """Every table of the page by name, in the page's order.

    The top level and ``[machine]`` (:attr:`cyclomech.Machine.key_docs`), the
    cyclogram's tables (:attr:`cyclomech.Cyclogram.key_docs`), then each kind of
    :data:`cyclomech.machine.KINDS` in the registry's order: its own table and its
    sub-tables (its ``key_docs``). A table several kinds share (``phase``, of a
    linkage and a press) is one object; it stands after the last kind that names
    it, where each of its users has been introduced.

    Returns
    -------
    dict of str to KeyTable
        The tables by name (``"machine"``, ``"cam.segment"``, …), in order.

    Raises
    ------
    InputError
        If a registered kind has no ``key_docs``, its first table is not named
        after its kind, or two different tables share a name: the page would
        otherwise leave out or mix up a table.

    Examples
    --------
    >>> list(tables())[:3]
    ['file', 'machine', 'drive']
    """
    from .cyclogram import Cyclogram
    from .machine import KINDS, Machine

    listed: list[KeyTable] = [*Machine.key_docs, *Cyclogram.key_docs]
    for kind, cls in KINDS.items():
        docs = getattr(cls, "key_docs", None)
        if not docs or not all(isinstance(t, KeyTable) for t in docs) or docs[0].name != kind:
            raise InputError(
                f"the kind {kind!r} ({cls.__qualname__}) documents no keys: give its class "
                f"key_docs, a tuple of KeyTable whose first is its own table, named {kind!r}"
            )
        listed += docs
    out: dict[str, KeyTable] = {}
    for t in listed:
        have = out.pop(t.name, None)
        if have is not None and have is not t:
            raise InputError(f"two different key tables are named {t.name!r}")
        out[t.name] = t  # a shared table moves to its last user
    return out


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
        A table's name, a key of :func:`tables` (``"machine"``, ``"cam.segment"``, …).

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
    for k in tables()[table].keys:
        cells = map(_text, (k.meaning, k.unit, k.type, k.default, k.valid))
        rows.append((f"``{k.name}``", *cells, _SWEEP[k.sweep]))
    lines = [".. list-table::", "   :header-rows: 1", "   :widths: 14 30 7 8 16 20 5", ""]
    for row in rows:
        lines.append(f"   * - {row[0]}")
        lines += [f"     - {cell}" for cell in row[1:]]
    return "\n".join(lines) + "\n"


def _intro(table: KeyTable) -> str:
    """A table's paragraph: its own, or for a kind's table the first paragraph of
    the kind's class docstring (cross-reference roles as literals)."""
    if table.intro is not None:
        return table.intro
    from .machine import KINDS

    doc = (KINDS[table.name].__doc__ or "").strip().split("\n\n")[0]
    return roles_as_literals(" ".join(doc.split()), last=True)


def render_page(title: str = "Machine-file format") -> str:
    """The reference page in rST.

    A section per table of :func:`tables`, its paragraph and its keys.

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
        "sets the file readers check, so a key listed here is one the reader takes. "
        "A value likely in the wrong unit warns: a ``_m`` length over 10 m, a ``_deg`` "
        "angle under 0.01°, a ``_pa`` stress under 1 MPa, and a ``_deg`` array (or the "
        "first column of its rows, the angle) of at least two distinct values, all within ±2π and "
        "spanning at most 2π — likelier radians, as an angle table (a load table, a "
        "spline's points, precision points, a phase grid) spans tens of degrees.",
        "",
    ]
    for name, table in tables().items():
        head = table.title
        out += [head, "-" * len(head), "", _intro(table), "", render_table(name)]
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
