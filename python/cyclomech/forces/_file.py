"""The machine file's keys for a linkage's forces: ``mass`` (links),
``point_mass_kg``, ``load`` and ``gravity_m_per_s2`` in a ``[mechanism.<name>]``
table (units in the key names)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from .. import _toml
from .._arrays import instance
from .._errors import InputError
from ..linkage import DYNAMICS_KEYS as LINKAGE_DYNAMICS_KEYS
from ._model import LinkMass, LinkTorque, PointLoad

if TYPE_CHECKING:
    from ..linkage import Linkage

__all__ = ["DYNAMICS_KEYS", "dynamics_from_table"]

#: The keys of a linkage's table that describe its forces: the linkage's table
#: format owns them (:data:`cyclomech.linkage.DYNAMICS_KEYS`, the same set).
DYNAMICS_KEYS = LINKAGE_DYNAMICS_KEYS

_MASS_KEYS = {"link", "mass_kg", "com_m", "com_point", "com_offset_m", "inertia_kg_m2"}
_LOAD_KEYS = {"point", "force_n", "link", "torque_nm", "angle_deg"}


def _rows(table: Mapping[str, Any], key: str, where: str) -> list[Mapping[str, Any]]:
    rows = table.get(key, [])
    if not isinstance(rows, list) or not all(isinstance(r, Mapping) for r in rows):
        raise InputError(f"{where}: {key} must be an array of tables ([[...{key}]]); got {rows!r}")
    return rows


def dynamics_from_table(
    table: Mapping[str, Any], source: str, where: str, linkage: Linkage | None = None
) -> dict[str, Any] | None:
    """The keywords of :func:`~cyclomech.forces.kinetostatics` from a linkage's table.

    ``[[<table>.mass]]``: ``link`` (its joints), ``mass_kg``, optional centre of
    mass — one of ``com_m`` = [x, y] in the drawn pose, ``com_point`` = a joint of
    the link, ``com_offset_m`` = [u, v] in the link's frame (origin its first
    joint, u towards its second); default the centroid of its joints — and
    ``inertia_kg_m2`` about it (default 0). ``point_mass_kg`` = {point = kg}.
    ``[[<table>.load]]``: ``point`` and ``force_n`` = [fx, fy], or ``link`` and
    ``torque_nm``; with ``angle_deg`` (crank angles) the force is a table, one
    row per angle, zero outside it. ``gravity_m_per_s2`` = [gx, gy].

    Parameters
    ----------
    table : mapping of str to object
        The linkage's table of the machine file (units in the key names: [kg],
        [m], [kg·m²], [N], [N·m], [deg], [m/s²]).
    source : str
        The file's name, for the error messages.
    where : str
        The table's name (e.g. ``"[mechanism.press]"``), for the error messages.
    linkage : Linkage, optional
        The linkage: with it, the points and links named are checked against it
        here, the message naming the key; default None.

    Returns
    -------
    dict of str to object or None
        The keywords ``masses``, ``point_masses``, ``loads``, ``gravity``, or None
        when the table has none of :data:`DYNAMICS_KEYS`.

    Raises
    ------
    InputError
        If a key is unknown or malformed, or (with ``linkage``) names a point or
        link it does not have; the message names ``source``, the table and the key.
    TypeError
        If ``table`` is not a mapping or ``linkage`` is not a
        :class:`~cyclomech.Linkage`.

    Examples
    --------
    >>> d = dynamics_from_table({"point_mass_kg": {"C": 2.0},
    ...                          "load": [{"point": "C", "force_n": [-100.0, 0.0]}]}, "f", "[m]")
    >>> d["point_masses"], d["loads"][0].force_n.tolist()
    ({'C': 2.0}, [-100.0, 0.0])
    """
    if not DYNAMICS_KEYS & set(instance("table", table, Mapping)):
        return None
    if linkage is not None:
        from ..linkage import Linkage  # here: the linkage package imports this one

        instance("linkage", linkage, Linkage)
    masses: dict[tuple[str, ...], LinkMass] = {}
    for i, row in enumerate(_rows(table, "mass", where)):
        at = f"{source}: {where} mass[{i}]"
        _toml.check_keys(row, _MASS_KEYS, source, f"{where} mass[{i}]")
        _toml.require(row, ("link", "mass_kg"), at)
        link = row["link"]
        if not isinstance(link, list) or not all(isinstance(p, str) for p in link):
            raise InputError(f'{at}: link = {link!r} must be the link\'s joints, e.g. ["B", "C"]')
        pair = {}
        for key in ("com_m", "com_offset_m"):
            v = row.get(key)
            if v is not None and not (
                isinstance(v, list) and len(v) == 2 and all(_toml.is_number(x) for x in v)
            ):
                raise InputError(f"{at}: {key} = {v!r} must be two numbers [m]")
            pair[key] = None if v is None else (float(v[0]), float(v[1]))
        point = row.get("com_point")
        if point is not None and not isinstance(point, str):
            raise InputError(f"{at}: com_point = {point!r} must be one of the link's joints")
        given = [k for k in ("com_m", "com_point", "com_offset_m") if k in row]
        if len(given) > 1:
            raise InputError(f"{at}: give the centre of mass one way, not {' and '.join(given)}")
        m = _toml.number(row, "mass_kg", at, "[kg]")
        jz = _toml.number(row, "inertia_kg_m2", at, "[kg·m²]") if "inertia_kg_m2" in row else 0.0
        for name, v, unit in (("mass_kg", m, "kg"), ("inertia_kg_m2", jz, "kg·m²")):
            if v < 0:
                raise InputError(f"{at}: {name} = {v!r} must be >= 0 [{unit}]")
        twin = next((j for j, k in enumerate(masses) if set(k) == set(link)), None)
        if twin is not None:
            raise InputError(
                f"{at}: link = {link!r} has a mass already in mass[{twin}]; give each link once"
            )
        masses[tuple(link)] = LinkMass(
            m, pair["com_m"], jz, com_point=point, com_offset_m=pair["com_offset_m"]
        )
    pm = table.get("point_mass_kg", {})
    if not isinstance(pm, Mapping):
        raise InputError(f"{source}: {where}: point_mass_kg must be a table {{point = kg}}")
    point_masses: dict[str, float] = {}
    for p, v in pm.items():
        m = _toml.number(pm, p, f"{source}: {where} point_mass_kg", "[kg]")
        if m < 0:
            raise InputError(f"{source}: {where}: point_mass_kg.{p} = {v!r} must be >= 0 [kg]")
        point_masses[p] = m
    loads: list[PointLoad | LinkTorque] = []
    for i, row in enumerate(_rows(table, "load", where)):
        at = f"{source}: {where} load[{i}]"
        _toml.check_keys(row, _LOAD_KEYS, source, f"{where} load[{i}]")
        try:
            if "point" in row and "force_n" in row and not {"link", "torque_nm"} & set(row):
                loads.append(PointLoad(row["point"], row["force_n"], row.get("angle_deg")))
            elif "link" in row and "torque_nm" in row and not {"point", "force_n"} & set(row):
                loads.append(LinkTorque(row["link"], row["torque_nm"], row.get("angle_deg")))
            else:
                raise InputError(
                    "give point and force_n [N] (a force), or link and torque_nm [N·m] (a "
                    "torque), optionally with angle_deg (a table over the crank angle)"
                )
        except InputError as e:
            raise InputError(f"{at}: {e}") from None
    gravity = None
    if "gravity_m_per_s2" in table:
        g = table["gravity_m_per_s2"]
        if not (isinstance(g, list) and len(g) == 2 and all(_toml.is_number(v) for v in g)):
            raise InputError(f"{source}: {where}: gravity_m_per_s2 = {g!r} must be [gx, gy] [m/s²]")
        gravity = (float(g[0]), float(g[1]))
    if gravity is not None and not masses and not point_masses:
        raise InputError(
            f"{source}: {where}: gravity_m_per_s2 is given but no link or point has a mass; "
            "give [[…mass]] rows or point_mass_kg (or drop gravity_m_per_s2)"
        )
    if linkage is not None:
        _check_names(linkage, source, where, masses, point_masses, loads)
    return {"masses": masses, "point_masses": point_masses, "loads": loads, "gravity": gravity}


def _check_names(
    linkage: Linkage,
    source: str,
    where: str,
    masses: Mapping[tuple[str, ...], Any],
    point_masses: Mapping[str, float],
    loads: list[PointLoad | LinkTorque],
) -> None:
    t = linkage.to_dict()
    ground = set(t["ground"])
    moving = [set(ln) for ln in t["links"] if not set(ln) <= ground]
    names = ", ".join(linkage.names)
    links = ", ".join(
        "[" + ", ".join(map(repr, ln)) + "]" for ln in t["links"] if not set(ln) <= ground
    )

    def link_ok(joints: tuple[str, ...], at: str) -> None:
        if set(joints) not in moving:
            raise InputError(
                f"{source}: {at}: link = {list(joints)!r} is not a moving link of the linkage; "
                f"its moving links are {links}"
            )

    for i, joints in enumerate(masses):
        link_ok(joints, f"{where} mass[{i}]")
    for p in point_masses:
        if p not in linkage.names:
            raise InputError(
                f"{source}: {where}: point_mass_kg.{p}: {p!r} is not a point; the points are "
                f"{names}"
            )
        if p in ground:
            raise InputError(
                f"{source}: {where}: point_mass_kg.{p}: {p!r} is a ground joint, which does "
                "not move; put the mass on a moving point"
            )
    for i, load in enumerate(loads):
        if isinstance(load, PointLoad) and load.point not in linkage.names:
            raise InputError(
                f"{source}: {where} load[{i}]: point = {load.point!r} is not a point; the points "
                f"are {names}"
            )
        if isinstance(load, PointLoad) and load.point in ground:
            raise InputError(
                f"{source}: {where} load[{i}]: point = {load.point!r} is a ground joint: a force "
                "there goes straight into the frame and loads no link; put it on a moving point"
            )
        if isinstance(load, LinkTorque):
            link_ok(load.link, f"{where} load[{i}]")
