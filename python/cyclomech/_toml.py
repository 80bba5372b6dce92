"""TOML reading and writing shared by every file format of cyclomech.

Errors name the file (``source``), the table and the key, as the brief asks.
"""

from __future__ import annotations

import codecs
import math
import re
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from collections.abc import Set as AbstractSet
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ._arrays import file_path
from ._errors import InputError
from ._keyrules import renamed

#: Deepest nesting of arrays and tables accepted [levels]: cyclomech's files need
#: five; far deeper ones would exhaust Python's recursion in the parser or later.
MAX_DEPTH = 64


def _depth_ok(data: Any) -> bool:
    """True if ``data`` nests at most :data:`MAX_DEPTH` levels (no recursion)."""
    stack = [(data, 0)]
    while stack:
        v, d = stack.pop()
        if d > MAX_DEPTH:
            return False
        if isinstance(v, Mapping):
            stack.extend((x, d + 1) for x in v.values())
        elif isinstance(v, list):
            stack.extend((x, d + 1) for x in v)
    return True


def load(path: str | Path) -> tuple[dict[str, Any], str]:
    """The parsed file and its name for messages, or :class:`InputError`. A UTF-8
    byte order mark (written by some Windows editors) is skipped; arrays and
    tables nested more than :data:`MAX_DEPTH` deep are refused."""
    p = file_path("path", path)
    deep = f"{p}: arrays or tables nested more than {MAX_DEPTH} levels deep"
    try:
        text = p.read_bytes().removeprefix(codecs.BOM_UTF8).decode("utf-8")
        data = tomllib.loads(text)
        if not _depth_ok(data):
            raise InputError(deep)
        return data, str(p)
    except RecursionError:
        raise InputError(deep) from None
    except FileNotFoundError:
        raise InputError(f"{p}: no such file") from None
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{p}: not valid TOML: {_decode_error(text, str(e))}") from None
    except UnicodeDecodeError as e:
        raise InputError(f"{p}: not valid TOML: the file is not UTF-8 text ({e})") from None
    except IsADirectoryError:
        raise InputError(f"{p}: is a directory, not a TOML file") from None
    except OSError as e:
        raise InputError(f"{p}: cannot be read: {e.strerror or e}") from None


#: A key of a TOML line: bare, "quoted" or 'literal' parts, dotted.
_KEY_PART = r"""(?:[A-Za-z0-9_-]+|"(?:[^"\\]|\\.)*"|'[^']*')"""
_QUOTED = re.compile(r""""(?:[^"\\]|\\.)*"|'[^']*'""")
_KEY = rf"{_KEY_PART}(?:[ \t]*\.[ \t]*{_KEY_PART})*"
_KEY_LINE = re.compile(rf"[ \t]*({_KEY})[ \t]*=")
_HEADER = re.compile(rf"[ \t]*(\[\[?)[ \t]*({_KEY})[ \t]*\]")
_AT = re.compile(r"\(at line (\d+), column (\d+)\)")


def _decode_error(text: str, message: str) -> str:
    """tomllib's ``message`` with the key it is about named, where it names none.

    tomllib says "Cannot overwrite a value (at line 3, column 6)" for a key given
    twice, and "Cannot declare ('t',) twice" for a table: the key (and its table)
    is read back from the line the position points to: "line 3: key 'x' of table
    [t] is given twice (each key once per table): Cannot overwrite a value (at line
    3, column 6)". Other messages are returned as they are.
    """
    at = _AT.search(message)
    dup = "Cannot overwrite a value" in message or "Cannot declare" in message
    lines = text.splitlines()
    if not (at and dup and 1 <= int(at.group(1)) <= len(lines)):
        return message
    n = int(at.group(1))
    line = lines[n - 1]
    header = _HEADER.match(line)
    if header:
        brackets = header.group(1)
        table = f"{brackets}{header.group(2)}{brackets.replace('[', ']')}"
        if "Cannot declare" in message:
            return f"line {n}: table {table} is declared twice (merge the two): {message}"
        return (
            f"line {n}: table {table} names a key that already holds a value "
            f"(rename one of them): {message}"
        )
    key = _KEY_LINE.match(line)
    if not key:
        return message
    table = "the top level"
    for above in reversed(lines[: n - 1]):
        if h := _HEADER.match(above):
            brackets = h.group(1)
            table = f"table {brackets}{h.group(2)}{brackets.replace('[', ']')}"
            break
    k = key.group(1)
    name = k if k[0] in "\"'" else repr(k)
    why = (
        "is given twice, or a part of it already holds a value"
        if "." in _QUOTED.sub("", k)
        else "is given twice (each key once per table)"
    )
    return f"line {n}: key {name} of {table} {why}: {message}"


def must_be_table(table: Any, source: str | None, where: str) -> None:
    """``table`` must be a table (a Mapping), else :class:`InputError` naming
    ``source`` and ``where``: checked before a reader looks at its keys (a list
    there once ended in ``TypeError: unhashable type``).

    >>> must_be_table({"a": 1}, "f.toml", "[press]")
    >>> must_be_table([1], "f.toml", "[press]")
    Traceback (most recent call last):
    cyclomech._errors.InputError: f.toml: [press] must be a table; got [1]
    """
    if not isinstance(table, Mapping):
        at = where if source is None else f"{source}: {where}"
        raise InputError(f"{at} must be a table; got {table!r}")


def check_keys(table: Any, allowed: AbstractSet[str], source: str | None, where: str) -> None:
    """``table`` must be a table whose keys are all in ``allowed``; messages start
    with ``source`` (None: the caller adds the file's name). A key renamed to say
    its unit (:data:`cyclomech._keyrules.RENAMED`) is an error naming its new name."""
    must_be_table(table, source, where)
    at = where if source is None else f"{source}: {where}"
    for k in table:
        if k not in allowed and (new := renamed(k, allowed)):
            raise InputError(f"{at}: {new}")
        if k not in allowed:
            raise InputError(
                f"{at}: unknown key {k!r}; valid keys are {', '.join(sorted(allowed))}"
            )


def renamed_hint(key: str, allowed: AbstractSet[str]) -> str:
    """`` (`a_max` is now `a_max_m` (metres): …)`` where ``key`` is the old name of
    an allowed key (:data:`cyclomech._keyrules.RENAMED`), else ``""``: for a
    message that names an unknown key in its own words (a sweep's parameter)."""
    new = renamed(key, allowed)
    return f" ({new})" if new else ""


def string(text: str) -> str:
    """A TOML basic string: quotes, backslashes and every control character
    (U+0000-U+001F and U+007F, which TOML forbids raw) escaped."""
    out = []
    for ch in text:
        if ch in ('"', "\\"):
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def value(v: Any) -> str:
    """A TOML value: strings, floats (round-tripping repr), ints, arrays, inline tables."""
    if isinstance(v, str):
        return string(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + " }"
    return str(v)


def key(k: str) -> str:
    """A TOML key: bare when it may be, quoted otherwise."""
    bare = k and all(c.isascii() and (c.isalnum() or c in "-_") for c in k)
    return k if bare else string(k)


# --------------------------------------------------------------------- field readers
# One reader per kind of field, for every table of every file format: each names
# the place (``where``: the file and the table), the key, the value and what is valid.


def is_number(v: Any) -> bool:
    """A TOML number (int or float; a boolean is not one)."""
    return isinstance(v, int | float) and not isinstance(v, bool)


def number(table: Mapping[str, Any], key: str, where: str, unit: str) -> float:
    """The finite number ``table[key]``."""
    v = table[key]
    if not is_number(v) or not math.isfinite(v):
        raise InputError(f"{where}: {key} = {v!r} must be a finite number {unit}".rstrip())
    return float(v)


def optional_positive(table: Mapping[str, Any], key: str, where: str, unit: str) -> float | None:
    """The positive number ``table[key]``, or None where the key is absent."""
    if key not in table:
        return None
    v = number(table, key, where, unit)
    if v <= 0:
        raise InputError(f"{where}: {key} = {v!r} must be positive {unit}".rstrip())
    return v


def event(table: Mapping[str, Any], key: str, where: str) -> str:
    """The event name ``table[key]``: a string, not blank. A number is refused, not
    read as its text (``from = 1`` could name "1" or "1.0"): event names are strings
    in every file, as :func:`events` reads them in arrays."""
    return _event_name(table[key], key, where, None, "")


def events(table: Mapping[str, Any], key: str, where: str, *, arc: bool = False) -> list[str]:
    """The event names of the array ``table[key]`` (as :func:`event`); with ``arc``
    exactly two, an operation's ``[from, to]``."""
    v = table[key]
    what = "[from, to], two event names" if arc else "an array of event names"
    if not isinstance(v, list) or (arc and len(v) != 2):
        raise InputError(f"{where}: {key} = {v!r} must be {what} (strings)")
    names = [_event_name(x, key, where, v, what) for x in v]
    if not arc:
        seen: dict[str, int] = {}
        for i, n in enumerate(names):
            if n in seen:
                raise InputError(
                    f"{where}: {key} = {v!r} names the event {n!r} twice (entries #{seen[n] + 1} "
                    f"and #{i + 1}); each event once"
                )
            seen[n] = i
    return names


def _event_name(v: Any, key: str, where: str, array: list[Any] | None, what: str) -> str:
    if isinstance(v, str) and v.strip():
        return v
    shown = f"{key} = {v!r}" if array is None else f"{key} = {array!r} must be {what}: {v!r}"
    fix = ""
    if is_number(v):
        quoted = str(v) if array is None else [str(x) if is_number(x) else x for x in array]
        names = "that is the name" if array is None else "those are the names"
        fix = f"; write {key} = {value(quoted)} if {names}"
    raise InputError(
        f"{where}: {shown} must be an event name, a string that is not blank "
        f"(event names are strings{fix})"
    )


def operation(
    arc: Sequence[str], key: str, where: str, operations: Sequence[tuple[str, str]]
) -> tuple[str, str]:
    """``arc`` (read by :func:`events`) as a tuple if it is one of ``operations``
    (the cyclogram's arcs); else the error names it, the operations that share an
    event with it (or the one that goes the other way) and all of them."""
    a, b = arc[0], arc[1]
    if (a, b) in operations:
        return a, b

    def listing(arcs: Iterable[tuple[str, str]]) -> str:
        return ", ".join(f"[{x!r}, {y!r}]" for x, y in arcs)

    if (b, a) in operations:
        hint = f"; the operation goes the other way: {key} = {[b, a]!r}"
    else:
        near = [o for o in operations if {a, b} & set(o)]
        hint = f"; the operations from or to {a!r} or {b!r}: {listing(near)}" if near else ""
    raise InputError(
        f"{where}: {key} = {[a, b]!r} is not an operation of the cyclogram (no [[operation]] "
        f"has from = {value(a)}, to = {value(b)}){hint}; the operations are "
        f"{listing(operations) or 'none'}"
    )


def require(table: Mapping[str, Any], keys: Iterable[str], where: str) -> None:
    """Every key of ``keys`` is in ``table``."""
    for k in keys:
        if k not in table:
            raise InputError(f"{where}: missing key {k!r}")


def whole(
    table: Mapping[str, Any], key: str, default: int, low: int, where: str, high: int = 1_000_000
) -> int:
    """The whole number ``table[key]`` (``default`` if absent) in [low, high]."""
    v = table.get(key, default)
    if isinstance(v, bool) or not isinstance(v, int) or not low <= v <= high:
        raise InputError(f"{where}: {key} = {v!r} must be a whole number from {low} to {high}")
    return v


def span(
    table: Mapping[str, Any],
    key: str,
    where: str,
    *,
    within: tuple[float, float] | None = None,
    most: int = 1_000_000,
    unit: str = "",
) -> npt.NDArray[np.float64]:
    """The values of ``key = [from, to, count]``: ``count`` evenly spaced values
    from ``from`` to ``to`` (``numpy.linspace``; both finite, in the half-open
    interval ``within`` = (low, high] where given), ``count`` a whole number from 1
    to ``most``.

    >>> span({"rpm": [100, 300, 3]}, "rpm", "f.toml: [study]", within=(0, 1e6)).tolist()
    [100.0, 200.0, 300.0]
    >>> span({"rpm": [0, 300, 3]}, "rpm", "f.toml: [study]", within=(0, 1e6), unit="rpm")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: f.toml: [study]: rpm = [0, 300, 3] must be [from, to, count] ...
    """
    if key not in table:
        raise InputError(f"{where}: missing key {key!r}")
    v = table[key]
    lo, hi = within if within is not None else (-math.inf, math.inf)
    ok = (
        isinstance(v, list)
        and len(v) == 3
        and all(is_number(x) for x in v)
        and isinstance(v[2], int)
        and 1 <= v[2] <= most
        and all(math.isfinite(x) and lo < x <= hi for x in v[:2])
    )
    if not ok:
        bounds = ""
        if within is not None:
            bounds = f" with from and to in ({lo:g}, {hi:g}]" + (f" {unit}" if unit else "")
        raise InputError(
            f"{where}: {key} = {v!r} must be [from, to, count]{bounds} and a whole count "
            f"from 1 to {most}"
        )
    return np.linspace(float(v[0]), float(v[1]), int(v[2]))
