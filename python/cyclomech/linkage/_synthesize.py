"""The hook by which a linkage table gives requirements instead of dimensions
(``[mechanism.<name>.synthesize]``).

The synthesis domain imports this one, not the reverse (no import circles): it
registers a synthesizer per ``scheme`` here when it is imported (``import
cyclomech`` imports it), and the linkage table's parser calls it through
:func:`synthesize`. A synthesizer takes the ``synthesize`` table and the place
to name in messages and returns a record with the synthesised ``linkage`` and
the report's hooks (``Synthesized``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Protocol

from .._errors import InputError
from ._linkage import Linkage

__all__ = ["SYNTHESIZERS", "Synthesized", "register_synthesizer", "synthesize"]


class Synthesized(Protocol):
    """What a synthesizer returns: the linkage and its part of the report."""

    @property
    def linkage(self) -> Linkage:
        """The synthesised linkage."""
        ...

    def rows(self) -> list[list[Any]]:
        """Rows [quantity, value] for the mechanism's report table."""
        ...

    def json(self) -> dict[str, Any]:
        """Its entry under the mechanism in ``results.json``."""
        ...

    def figures(self, save: Any, name: str) -> None:
        """Its figures, each through ``save(fig, stem, caption)``."""
        ...

    def files(self, folder: Path, name: str) -> list[Path]:
        """Its own files written into ``folder``."""
        ...


#: scheme name → synthesizer(table, where) → ``Synthesized``.
SYNTHESIZERS: dict[str, Callable[[Mapping[str, Any], str], Synthesized]] = {}


def register_synthesizer(scheme: str, fn: Callable[[Mapping[str, Any], str], Synthesized]) -> None:
    """Register ``fn`` as the synthesizer of ``synthesize`` tables whose ``scheme``
    is ``scheme``.

    Parameters
    ----------
    scheme : str
        The ``scheme`` value it answers.
    fn : callable
        ``fn(table, where)`` → a ``Synthesized`` record.

    Raises
    ------
    InputError
        If ``scheme`` is not a string or ``fn`` is not callable.

    Examples
    --------
    >>> import cyclomech as cm
    >>> knife = cm.linkage.SYNTHESIZERS["br125"]     # cyclomech.synthesis registered it
    >>> cm.linkage.register_synthesizer("br125", knife)
    >>> cm.linkage.SYNTHESIZERS["br125"] is knife
    True
    """
    if not isinstance(scheme, str) or not callable(fn):
        raise InputError(f"register_synthesizer: ({scheme!r}, {fn!r}) is not (name, callable)")
    SYNTHESIZERS[scheme] = fn


def synthesize(table: Any, where: str) -> Synthesized:
    """The record of a ``synthesize`` table by its ``scheme``'s synthesizer.

    Parameters
    ----------
    table : mapping
        The ``synthesize`` table as read.
    where : str
        The place to name in messages (``<file>: [mechanism.<name>.synthesize]``).

    Returns
    -------
    Synthesized
        The synthesizer's record.

    Raises
    ------
    InputError
        If ``table`` is not a table or its ``scheme`` has no synthesizer.
    """
    if not isinstance(table, Mapping):
        raise InputError(f"{where}: synthesize must be a table; got {table!r}")
    scheme = table.get("scheme")
    if not isinstance(scheme, str) or scheme not in SYNTHESIZERS:
        raise InputError(
            f"{where}: scheme = {scheme!r} has no synthesizer; the schemes are "
            f"{', '.join(sorted(SYNTHESIZERS)) or 'none (import cyclomech.synthesis)'}"
        )
    return SYNTHESIZERS[scheme](table, where)
