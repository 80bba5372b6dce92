"""Motor catalogues from CSV files: `_catalogue` part of :mod:`cyclomech.servo`
(its door)."""

from __future__ import annotations

import csv
import os
from pathlib import Path
from typing import Any

from .._arrays import real
from .._errors import InputError
from ._parts import Motor

__all__ = ["CATALOGUE_COLUMNS", "load_catalogue"]

#: The columns a motor catalogue must have (any order; other columns are ignored):
#: the motor's name, rated and peak torque [N·m], rated and maximum speed [rpm] and
#: rotor inertia [kg·m²].
CATALOGUE_COLUMNS: tuple[str, ...] = (
    "name",
    "rated_torque_nm",
    "peak_torque_nm",
    "rated_rpm",
    "max_rpm",
    "inertia_kg_m2",
)


def _lines(path: Path) -> list[tuple[int, str]]:
    """(line number, text) of the file's lines that are neither blank nor
    comments (``#`` first)."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: cannot read the motor catalogue: {e}") from None
    return [
        (n, line)
        for n, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]


def _motor(path: Path, n: int, row: dict[str, str]) -> Motor:
    """The motor of line ``n``, or :class:`InputError` naming the file, the line,
    the column and the value."""
    values: dict[str, Any] = {"name": row["name"].strip()}
    for column in CATALOGUE_COLUMNS[1:]:
        text = (row.get(column) or "").strip()
        try:
            values[column] = real(float(text))
        except ValueError:
            raise InputError(
                f"{path}: line {n}: column {column} = {text!r} is not a number"
            ) from None
    if not values["name"]:
        raise InputError(f"{path}: line {n}: column name is empty; each motor needs a name")
    try:
        return Motor(**values)
    except InputError as e:
        raise InputError(f"{path}: line {n} (motor {values['name']!r}): {e}") from None


def load_catalogue(path: str | os.PathLike[str]) -> tuple[Motor, ...]:
    """The motors of a catalogue CSV file, in the file's order.

    A header line names the columns (:data:`CATALOGUE_COLUMNS`, any order; other
    columns, a vendor's part number or a price say, are ignored); blank lines and
    lines starting with ``#`` are skipped, so the file can say where its numbers
    come from.

    Parameters
    ----------
    path : str or path-like
        The CSV file.

    Returns
    -------
    tuple of Motor
        One per data line.

    Raises
    ------
    InputError
        If the file cannot be read, lacks a column, has a value that is not a
        number, a motor whose values are out of range, a name given twice or no
        motor at all: each naming the file, the line, the column and the value.

    Examples
    --------
    >>> import cyclomech as cm
    >>> motors = cm.servo.load_catalogue("examples/motors.csv")
    >>> motors[0].name, motors[0].rated_torque_nm
    ('AC-040-032', 0.32)
    """
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"path must be a str or a path; got {type(path).__name__}")
    path = Path(path)
    lines = _lines(path)
    if not lines:
        raise InputError(f"{path}: the motor catalogue has no header and no motor")
    reader = csv.DictReader([line for _, line in lines], skipinitialspace=True)
    header = [h.strip() for h in reader.fieldnames or []]
    reader.fieldnames = header
    missing = [c for c in CATALOGUE_COLUMNS if c not in header]
    if missing:
        raise InputError(
            f"{path}: line {lines[0][0]}: the header lacks column {', '.join(missing)}; a motor "
            f"catalogue needs {', '.join(CATALOGUE_COLUMNS)} (got {', '.join(header)})"
        )
    motors: list[Motor] = []
    seen: dict[str, int] = {}
    for (n, _), row in zip(lines[1:], reader, strict=False):
        motor = _motor(path, n, row)
        if motor.name in seen:
            raise InputError(
                f"{path}: line {n}: column name = {motor.name!r} is given twice (first on "
                f"line {seen[motor.name]}); each motor needs its own name"
            )
        seen[motor.name] = n
        motors.append(motor)
    if not motors:
        raise InputError(f"{path}: the motor catalogue has a header but no motor")
    return tuple(motors)
