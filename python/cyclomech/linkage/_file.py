"""The linkage file format: the table of :meth:`Linkage.to_dict` and
:meth:`Linkage.from_dict` (TOML layout), its keys, and the ``[linkage]`` table of a
TOML file (:meth:`Linkage.from_toml`, :meth:`Linkage.to_toml`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .. import _toml
from .._errors import InputError
from .._files import file_target, write_text

if TYPE_CHECKING:
    from ._linkage import Linkage

_LINKAGE_KEYS = {"name", "points", "links", "ground", "driver", "output", "lengths", "sliders"}
#: The keys of a machine file's linkage table that describe its forces (masses,
#: loads, gravity), which :func:`cyclomech.forces.dynamics_from_table` reads. The
#: linkage's table format owns them, so the forces package imports the linkage
#: package and not the reverse (:data:`cyclomech.forces.DYNAMICS_KEYS` is this set).
#: ``friction`` (its joints' and guides', :func:`cyclomech.forces.friction_from_table`)
#: is one of them; the others are :func:`cyclomech.forces.dynamics_from_table`'s.
DYNAMICS_KEYS = frozenset({"mass", "point_mass_kg", "load", "gravity_m_per_s2", "friction"})
#: Keys of a machine file's linkage table that a plain linkage file does not take:
#: its forces (cyclomech.forces) and where its crank sits in the cycle.
_MACHINE_KEYS = DYNAMICS_KEYS | {"phase"}


def linkage_table(lk: Linkage) -> dict[str, Any]:
    """The table :meth:`Linkage.to_dict` returns.

    >>> import cyclomech as cm
    >>> from cyclomech.linkage._file import linkage_table
    >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
    >>> linkage_table(lk)["points"]
    {'A': [0.0, 0.0], 'B': [1.0, 0.0]}
    """
    out: dict[str, Any] = {}
    if lk.name is not None:
        out["name"] = lk.name
    out["points"] = {n: list(xy) for n, xy in lk._points.items()}
    out["links"] = [list(ln) for ln in lk._links]
    out["ground"] = sorted(lk._ground)
    out["driver"] = list(lk._driver)
    if lk.output is not None:
        out["output"] = lk.output
    if lk._lengths:
        out["lengths"] = [{"joints": list(k), "length": v} for k, v in lk._lengths.items()]
    if lk._sliders:
        out["sliders"] = {
            p: [{kind: list(arg)} for kind, arg in guides] for p, guides in lk._sliders.items()
        }
    return out


def drawing_table(lk: Linkage) -> tuple[list[str], list[list[Any]]]:
    """The table :meth:`Linkage.drawing_table` returns.

    >>> import cyclomech as cm
    >>> lk = cm.Linkage({"A": (0, 0), "B": (0, 1)}, [("A", "B")], ["A"], ("A", "B"))
    >>> for row in drawing_table(lk)[1]:
    ...     print(row)
    ['pivot', 'A', 0.0, 0.0, '', '']
    ['joint', 'B', 0.0, 1.0, '', 'crank A→B at 90°']
    ['link', 'A-B', '', '', 1.0, '']
    """
    a, b = lk._driver
    (xa, ya), (xb, yb) = lk._points[a], lk._points[b]
    crank = f"crank {a}→{b} at {math.degrees(math.atan2(yb - ya, xb - xa)) % 360.0:.6g}°"
    ground = [n for n in lk._points if n in lk._ground]
    moving = [n for n in lk._points if n not in lk._ground]
    rows: list[list[Any]] = [["pivot", n, *lk._points[n], "", ""] for n in ground]
    rows += [["joint", n, *lk._points[n], "", crank] for n in moving]
    for link in lk._links:
        for i, p in enumerate(link):
            for q in link[i + 1 :]:
                rows.append(["link", f"{p}-{q}", "", "", lk.length(p, q), ""])
    for pt, guides in lk._sliders.items():
        for kind, arg in guides:
            if kind == "ground":
                rows.append(["guide", pt, *map(float, arg), "", "a straight guide of the frame"])
            else:
                rows.append(["guide", pt, "", "", "", f"slides along link {arg[0]}-{arg[1]}"])
    return ["item", "name", "x_m", "y_m", "length_m", "note"], rows


def from_table(cls: type[Linkage], table: Mapping[str, Any], source: str, where: str) -> Linkage:
    """What :meth:`Linkage.from_dict` does: check ``table``'s keys, read its
    lengths and sliders and build a ``cls``; errors name ``source`` and ``where``."""
    _toml.must_be_table(table, source, where)
    machine_only = sorted(set(table) & _MACHINE_KEYS)
    if machine_only:
        raise InputError(
            f"{source}: {where}: {', '.join(machine_only)} describe(s) the linkage's forces in a "
            "machine: they belong in its [mechanism.<name>] table of a file for `cyclomech "
            "run`; in Python, cyclomech.forces.kinetostatics takes them"
        )
    _toml.check_keys(table, _LINKAGE_KEYS, source, where)
    for req in ("points", "links", "ground", "driver"):
        if req not in table:
            raise InputError(f"{source}: {where}: missing key {req!r}")
    try:
        lengths = {}
        items = table.get("lengths", [])
        if not isinstance(items, list):
            raise InputError(
                f"lengths = {items!r} must be an array of tables "
                "[{joints = [a, b], length = …}, …]"
            )
        for i, item in enumerate(items, 1):
            _toml.check_keys(item, {"joints", "length"}, None, f"lengths #{i}")
            joints = item.get("joints")
            if not (
                isinstance(joints, list)
                and len(joints) == 2
                and all(isinstance(j, str) for j in joints)
            ):
                raise InputError(
                    f"lengths #{i}: joints must be [a, b], two joint names; got {joints!r}"
                )
            lengths[(joints[0], joints[1])] = item.get("length")
        sliders: dict[str, Any] = {}
        guides_of = table.get("sliders", {})
        if not isinstance(guides_of, Mapping):
            raise InputError(
                f"sliders = {guides_of!r} must be a table: point = {{ground = [dx, dy]}} "
                "or {link = [b, c]}, or a list of two guides"
            )
        for p, spec in guides_of.items():
            specs = spec if isinstance(spec, list) else [spec]
            guides = []
            for g in specs:
                if not (isinstance(g, Mapping) and len(g) == 1 and set(g) <= {"ground", "link"}):
                    raise InputError(
                        f"sliders.{p} = {spec!r}: a guide is {{ground = [dx, dy]}} or "
                        "{link = [b, c]}, or a list of two guides"
                    )
                ((kind, arg),) = g.items()
                guides.append((kind, tuple(arg) if isinstance(arg, list) else arg))
            sliders[p] = guides
        driver = table["driver"]
        return cls(
            table["points"],
            table["links"],
            table["ground"],
            tuple(driver) if isinstance(driver, list) else driver,
            lengths=lengths or None,
            sliders=sliders or None,
            name=table.get("name"),
            output=table.get("output"),
        )
    except InputError as e:
        raise InputError(f"{source}: {where}: {e}") from None


def read_toml(cls: type[Linkage], path: str | Path) -> Linkage:
    """What :meth:`Linkage.from_toml` does: the ``[linkage]`` table of a TOML file."""
    data, source = _toml.load(path)
    _toml.check_keys(data, {"linkage"}, source, "top level")
    if "linkage" not in data:
        raise InputError(f"{source}: no [linkage] table")
    return cls.from_dict(data["linkage"], source)


def write_toml(lk: Linkage, path: str | Path | None) -> str:
    """What :meth:`Linkage.to_toml` does: the TOML text, written to ``path`` if given."""
    table = lk.to_dict()
    points = table.pop("points")
    lengths = table.pop("lengths", [])
    sliders = table.pop("sliders", {})
    lines = ["[linkage]"]
    lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in table.items()]
    lines += ["", "[linkage.points]"]
    lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in points.items()]
    for item in lengths:
        lines += ["", "[[linkage.lengths]]"]
        lines += [f"{k} = {_toml.value(v)}" for k, v in item.items()]
    if sliders:
        lines += ["", "[linkage.sliders]"]
        lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in sliders.items()]
    text = "\n".join(lines) + "\n"
    if path is not None:
        write_text(file_target("path", path), text)  # whole or not at all
    return text
