"""Linkages synthesised from a machine file's ``[mechanism.<name>.synthesize]``
table by the classical methods: the record every such
synthesizer returns, and the readers of its keys that the four schemes share.

The schemes, each registered with :mod:`cyclomech.linkage` by its own module:

``function`` (``_function_file``)
    A four-bar function generator (:func:`~cyclomech.synthesis.function_generation`):
    the output rocker's angle ψ follows the crank angle φ through precision
    points.
``path`` (``_path_file``)
    A four-bar or slider-crank whose coupler point passes target points
    (:func:`~cyclomech.synthesis.path_generation`).
``motion`` (``_motion_file``)
    A four-bar whose coupler takes three poses
    (:func:`~cyclomech.synthesis.motion_generation`).
``dwell_sixbar`` (``_dwell_file``)
    A Stephenson III six-bar whose output rocker dwells
    (:func:`~cyclomech.synthesis.dwell_sixbar`).

A machine turns its linkages' cranks fully and counter-clockwise, once per cycle:
so every scheme keeps only the candidates whose crank turns fully, on one branch,
and (function, motion) which meet their precision points or poses in order as the
crank angle grows. If no candidate does, or none meets the table's own limits, the
file is refused with an :class:`~cyclomech.InputError` that says what the best one
missed: a machine file that reads runs a linkage that does what it asked.
"""

from __future__ import annotations

import csv
import math
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import _keyrules, _toml
from .._arrays import count, finite_number, real_array
from .._errors import CyclomechWarning, InputError
from ..linkage import Linkage

__all__ = [
    "LinkageSynthesis",
    "check_table",
    "fmt",
    "number",
    "points",
    "refused",
    "warn_array_slips",
    "whole",
]

#: A figure maker: (record, mechanism name) → [(figure, stem, caption)].
Figures = Callable[["LinkageSynthesis", str], list[tuple[Any, str, str]]]


@dataclass(frozen=True)
class LinkageSynthesis:
    """A linkage a ``synthesize`` table asked for, with its part of the report.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    scheme : str
        The table's ``scheme`` (``function``, ``path``, ``motion``, ``dwell_sixbar``).
    linkage : Linkage
        The chosen candidate's linkage, the one the machine analyses.
    candidate : object
        The chosen candidate (a :class:`~cyclomech.synthesis.FunctionCandidate`,
        :class:`~cyclomech.synthesis.PathCandidate`,
        :class:`~cyclomech.synthesis.MotionCandidate` or
        :class:`~cyclomech.synthesis.DwellCandidate`).
    report : tuple of (str, str)
        The report table's rows: what was asked, what was chosen and why, the
        dimensions and the margins.
    entry : dict
        Its ``synthesis`` entry in ``results.json`` (besides ``scheme``).
    dimensions : tuple of (str, float, str)
        The chosen dimensions (quantity, value, unit) for ``<name>_synthesis.csv``.
    draw : callable, optional
        Its figures: ``draw(record, name)`` → [(figure, stem, caption)].

    Examples
    --------
    >>> from cyclomech.synthesis._function_file import from_table
    >>> rec = from_table({"scheme": "function", "ground_m": 0.2,
    ...                   "precision_points_deg": [[30, 80], [60, 90], [90, 100]]}, "<doc>")
    >>> rec.scheme, rec.linkage.output
    ('function', 'C')
    """

    scheme: str
    linkage: Linkage
    candidate: Any
    report: tuple[tuple[str, str], ...]
    entry: dict[str, Any]
    dimensions: tuple[tuple[str, float, str], ...]
    draw: Figures | None = field(default=None, repr=False, compare=False)

    def rows(self) -> list[list[Any]]:
        """The report table's rows [quantity, value].

        Examples
        --------
        >>> from cyclomech.synthesis._function_file import from_table
        >>> rec = from_table({"scheme": "function", "ground_m": 0.2,
        ...                   "precision_points_deg": [[30, 80], [60, 90], [90, 100]]}, "<doc>")
        >>> rec.rows()[0]
        ['synthesised scheme', 'function (a four-bar function generator)']
        """
        return [[k, v] for k, v in self.report]

    def json(self) -> dict[str, Any]:
        """Its ``synthesis`` entry in ``results.json``.

        Examples
        --------
        >>> from cyclomech.synthesis._function_file import from_table
        >>> rec = from_table({"scheme": "function", "ground_m": 0.2,
        ...                   "precision_points_deg": [[30, 80], [60, 90], [90, 100]]}, "<doc>")
        >>> rec.json()["scheme"], sorted(rec.json()["lengths_m"])
        ('function', ['coupler', 'crank', 'ground', 'rocker'])
        """
        return {"scheme": self.scheme, **_plain(self.entry)}

    def figures(self, save: Any, name: str) -> None:
        """Its figures, each given to ``save(figure, stem, caption)``.

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import matplotlib.pyplot as plt
        >>> from cyclomech.synthesis._function_file import from_table
        >>> rec = from_table({"scheme": "function", "ground_m": 0.2,
        ...                   "precision_points_deg": [[30, 80], [60, 90], [90, 100]]}, "<doc>")
        >>> stems = []
        >>> rec.figures(lambda fig, stem, caption: (stems.append(stem), plt.close(fig)), "m")
        >>> stems
        ['m_synthesis']
        """
        if self.draw is None:
            return
        for fig, stem, caption in self.draw(self, name):
            save(fig, stem, caption)

    def files(self, folder: Path, name: str) -> list[Path]:
        """``<name>_synthesis.csv``: the chosen dimensions (quantity, value, unit).

        Examples
        --------
        >>> import tempfile
        >>> from cyclomech.synthesis._function_file import from_table
        >>> rec = from_table({"scheme": "function", "ground_m": 0.2,
        ...                   "precision_points_deg": [[30, 80], [60, 90], [90, 100]]}, "<doc>")
        >>> [p.name for p in rec.files(tempfile.mkdtemp(), "the arm")]
        ['the_arm_synthesis.csv']
        """
        path = Path(folder) / f"{'_'.join(name.split())}_synthesis.csv"
        with path.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["quantity", "value", "unit"])
            for q, v, unit in self.dimensions:
                w.writerow([q, repr(float(v)), unit])
        return [path]


def _plain(v: Any) -> Any:
    """``v`` for JSON: non-finite numbers as None (JSON has no NaN), tuples as lists."""
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_plain(x) for x in v]
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def check_table(
    table: Mapping[str, Any], keys: frozenset[str], required: tuple[str, ...], where: str
) -> None:
    """The table's keys: all known (a key without its unit suffix named with it),
    the required ones there."""
    for k in table:
        if k not in keys:
            near = [k + s for s in ("_m", "_deg") if k + s in keys]
            if near:
                raise InputError(
                    f"{where}: unknown key {k!r}: the key says its unit, {near[0]!r}; "
                    f"valid keys are {', '.join(sorted(keys))}"
                )
    _toml.check_keys(table, set(keys), None, where)
    _toml.require(table, required, where)


def number(
    table: Mapping[str, Any],
    key: str,
    default: float | None,
    unit: str,
    *,
    low: float | None = None,
    strict: bool = False,
    below: float | None = None,
) -> float | None:
    """``table[key]`` as a finite number (``default`` when absent), ≥ ``low`` (>
    with ``strict``) and < ``below``."""
    if key not in table:
        return default
    v = finite_number(key, table[key], unit, low=low, strict=strict)
    if below is not None and v >= below:
        raise InputError(f"{key} = {v!r} must be below {below:g} {unit}")
    return v


def whole(table: Mapping[str, Any], key: str, default: int, low: int, what: str) -> int:
    """``table[key]`` as a whole number ≥ ``low`` (``default`` when absent)."""
    return count(key, table.get(key, default), low=low, what=what)


def points(
    table: Mapping[str, Any], key: str, width: int, unit: str, *, rows: int = 1
) -> tuple[tuple[float, ...], ...]:
    """``table[key]`` as rows of ``width`` finite numbers, at least ``rows`` of them,
    as a tuple of tuples (hashable: it keys the synthesis's cache)."""
    a = real_array(key, table[key], unit, ndims=(2,))
    if a.shape[1] != width or len(a) < rows:
        raise InputError(
            f"{key} must be at least {rows} rows of {width} numbers {unit}; got shape {a.shape}"
        )
    return tuple(tuple(float(x) for x in r) for r in a)


def warn_array_slips(table: Mapping[str, Any], where: str) -> None:
    """The unit-suffix rules of every table (:func:`cyclomech._keyrules.check`) on
    the numbers, and on the arrays of ``_m`` keys by their largest entry: a length
    in millimetres given as metres warns, naming the key."""
    _keyrules.check(table, (), where)
    for k, v in table.items():
        if not k.endswith("_m") or not isinstance(v, list):
            continue
        a = np.abs(np.asarray(v, dtype=float))
        if a.size and float(a.max()) > _keyrules.LONGEST_M:
            warnings.warn(
                f"{where}: {k} holds {float(a.max()):g} m, over {_keyrules.LONGEST_M:g} m — "
                f"did you mean millimetres (divide {k} by 1000)?",
                CyclomechWarning,
                stacklevel=4,
            )


def fmt(v: float, digits: int = 4) -> str:
    """A number for a report row; "—" for NaN."""
    return "—" if not math.isfinite(v) else f"{v:.{digits}g}"


def refused(where: str, e: Exception) -> InputError:
    """The error naming the table, from an error of the synthesis."""
    return InputError(f"{where}: {e}")
