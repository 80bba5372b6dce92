"""The cyclogram's file format (TOML): reading and writing; part of
:mod:`cyclomech.cyclogram` (:meth:`Cyclogram.from_toml`, :meth:`Cyclogram.to_toml`)."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

from .. import _toml
from .._arrays import instance
from .._errors import InputError
from .._files import file_target, write_text

if TYPE_CHECKING:
    from collections.abc import Callable

    from ._angles import Arc
    from ._operation import Operation
    from ._types import Constraint

_OP_KEYS = {
    "from",
    "to",
    "min_angle_deg",
    "max_angle_deg",
    "min_duration_s",
    "height",
    "name",
    "mechanism",
}
_CG_KEYS = {"name", "cycle_deg", "limiting", "speed_rpm", "events"}
_CON_KEYS = {"name", "terms", "sense", "rhs"}
_TERM_KEYS = {"from", "to", "coeff"}


class Model(Protocol):
    """The cyclogram as its file reads and writes it: its public face alone (the
    file knows no more of :class:`~cyclomech.cyclogram.Cyclogram`)."""

    name: str
    cycle_deg: float

    @property
    def speed_rpm(self) -> float | None: ...
    @property
    def events(self) -> tuple[str, ...]: ...
    @property
    def operations(self) -> tuple[Operation, ...]: ...
    @property
    def constraints(self) -> tuple[Constraint, ...]: ...
    @property
    def limiting(self) -> Arc | None: ...
    def add_event(self, event: str) -> str: ...
    def add_operation(self, *args: Any, **kwargs: Any) -> None: ...
    def add_constraint(self, *args: Any, **kwargs: Any) -> None: ...


_M = TypeVar("_M", bound=Model)


def read(cls: Callable[..., _M], data: Mapping[str, Any], source: str) -> _M:
    """The cyclogram of the parsed layout ``data`` (:meth:`Cyclogram.from_dict`),
    made by ``cls``; the order of its events is checked by the cyclogram itself."""
    instance("source", source, (str, os.PathLike))  # the name its messages give
    _toml.check_keys(data, {"cyclogram", "operation", "constraint"}, source, "top level")
    head = data.get("cyclogram", {})
    _toml.check_keys(head, _CG_KEYS, source, "[cyclogram]")
    at = f"{source}: [cyclogram]"
    lim = head.get("limiting")
    if isinstance(lim, list):  # else a name, or refused by the constructor
        lim = tuple(_toml.events(head, "limiting", at, arc=True))
    events = _toml.events(head, "events", at) if "events" in head else []
    try:
        cg = cls(
            head.get("name", Path(source).stem),
            cycle_deg=head.get("cycle_deg", 360.0),
            limiting=lim,
            speed_rpm=head.get("speed_rpm"),
        )
        for ev in events:
            cg.add_event(ev)
    except InputError as e:
        raise InputError(f"{at}: {e}") from None
    declared = set(cg.events) if "events" in head else None
    ops = data.get("operation", [])
    if not isinstance(ops, list):
        raise InputError(f"{source}: 'operation' must be an array of tables ([[operation]])")
    for i, op in enumerate(ops, 1):
        where = f"{source}: [[operation]] #{i}"
        _toml.check_keys(op, _OP_KEYS, source, f"[[operation]] #{i}")
        for req in ("from", "to"):
            if req not in op:
                raise InputError(
                    f"{where}: missing key {req!r} (the event the operation goes {req})"
                )
        src, dst = _toml.event(op, "from", where), _toml.event(op, "to", where)
        try:
            for key, ev in (("from", src), ("to", dst)):
                if declared is not None and ev not in declared:
                    raise InputError(
                        f"{key} = {ev!r} is not one of the events listed in [cyclogram] "
                        f"events ({', '.join(repr(e) for e in cg.events)}); a typo, or "
                        "add it to that list"
                    )
            cg.add_operation(
                src,
                dst,
                min_angle_deg=op.get("min_angle_deg", 0.0),
                max_angle_deg=op.get("max_angle_deg"),
                name=op.get("name"),
                mechanism=op.get("mechanism"),
                min_duration_s=op.get("min_duration_s", 0.0),
                height=op.get("height", 0),
            )
        except InputError as e:
            raise InputError(f"{where}: {e}") from None
    cons = data.get("constraint", [])
    if not isinstance(cons, list):
        raise InputError(f"{source}: 'constraint' must be an array of tables ([[constraint]])")
    for i, con in enumerate(cons, 1):
        where = f"{source}: [[constraint]] #{i}"
        _toml.check_keys(con, _CON_KEYS, source, f"[[constraint]] #{i}")
        for req in ("terms", "sense", "rhs"):
            if req not in con:
                raise InputError(f"{where}: missing key {req!r}")
        coeffs: dict[Arc, float] = {}
        if not isinstance(con["terms"], list):
            raise InputError(f"{where}: terms must be a list of {{from, to, coeff}} tables")
        for j, t in enumerate(con["terms"], 1):
            if not isinstance(t, Mapping):
                raise InputError(
                    f"{where}: terms #{j} must be a table {{from, to, coeff}}; got {t!r}"
                )
            _toml.check_keys(t, _TERM_KEYS, source, f"[[constraint]] #{i} terms #{j}")
            missing = _TERM_KEYS - set(t)
            if missing:
                raise InputError(f"{where}: terms #{j} is missing {sorted(missing)}")
            term = f"{where}: terms #{j}"
            arc = (_toml.event(t, "from", term), _toml.event(t, "to", term))
            if arc in coeffs:
                raise InputError(
                    f"{where}: terms #{j} repeats the arc {arc[0]}→{arc[1]}; "
                    "list each arc once with its total coefficient"
                )
            coeffs[arc] = t["coeff"]
        try:
            cg.add_constraint(coeffs, con["sense"], con["rhs"], name=con.get("name"))
        except InputError as e:
            raise InputError(f"{where}: {e}") from None
    try:
        _ = cg.limiting  # None when not given; a name or arc that exists
    except InputError as e:
        raise InputError(f"{source}: [cyclogram]: {e}") from None
    return cg


def write(cg: Model, path: str | Path | None) -> str:
    """The cyclogram as TOML text, written to ``path`` if given
    (:meth:`Cyclogram.to_toml`)."""
    q = _toml.value
    lines = ["[cyclogram]", f"name = {q(cg.name)}", f"cycle_deg = {q(cg.cycle_deg)}"]
    if cg.limiting is not None:
        lines.append(f"limiting = {q(list(cg.limiting))}")
    if cg.speed_rpm is not None:
        lines.append(f"speed_rpm = {q(cg.speed_rpm)}")
    lines.append(f"events = {q(list(cg.events))}")
    for op in cg.operations:
        lines += [
            "",
            "[[operation]]",
            f"from = {q(op.src)}",
            f"to = {q(op.dst)}",
            f"min_angle_deg = {q(op.min_angle_deg)}",
        ]
        if op.max_angle_deg is not None:
            lines.append(f"max_angle_deg = {q(op.max_angle_deg)}")
        if op.min_duration_s:
            lines.append(f"min_duration_s = {q(op.min_duration_s)}")
        if op.height:
            lines.append(f"height = {op.height}")
        if op.name is not None:
            lines.append(f"name = {q(op.name)}")
        if op.mechanism is not None:
            lines.append(f"mechanism = {q(op.mechanism)}")
    for con in cg.constraints:
        terms = ", ".join(
            f"{{ from = {q(a[0])}, to = {q(a[1])}, coeff = {q(c)} }}" for a, c in con.coeffs
        )
        lines += [
            "",
            "[[constraint]]",
            f"name = {q(con.name)}",
            f"terms = [{terms}]",
            f"sense = {q(con.sense)}",
            f"rhs = {q(con.rhs)}",
        ]
    text = "\n".join(lines) + "\n"
    if path is not None:
        write_text(file_target("path", path), text)  # whole or not at all
    return text
