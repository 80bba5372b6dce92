"""The machine file's keys for a linkage's forces: ``mass`` (links),
``point_mass_kg``, ``load`` and ``gravity_m_per_s2`` in a ``[mechanism.<name>]``
table (units in the key names)."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from .. import _keyrules, _toml
from .._arrays import instance
from .._errors import CyclomechWarning, InputError
from ..linkage import DYNAMICS_KEYS as LINKAGE_DYNAMICS_KEYS
from ._friction import Friction, GuideFriction, PinFriction, _joints
from ._model import LinkMass, LinkTorque, PointLoad

if TYPE_CHECKING:
    from ..linkage import Linkage

__all__ = ["DYNAMICS_KEYS", "FRICTION_KEYS", "dynamics_from_table", "friction_from_table"]

#: The keys of a linkage's table that describe its forces: the linkage's table
#: format owns them (:data:`cyclomech.linkage.DYNAMICS_KEYS`, the same set).
DYNAMICS_KEYS = LINKAGE_DYNAMICS_KEYS
#: Those :func:`dynamics_from_table` reads (friction is :func:`friction_from_table`'s).
_FORCE_KEYS = DYNAMICS_KEYS - {"friction"}

#: The keys of a linkage's ``[mechanism.<name>.friction]`` table: the defaults of
#: every joint and every guide, and per joint / per slider overrides.
FRICTION_KEYS = frozenset(
    {
        "pin_radius_m",
        "pin_mu",
        "pin_viscous_nm_s_per_rad",
        "guide_mu",
        "guide_viscous_n_s_per_m",
        "pins",
        "guides",
    }
)
#: The keys of one joint's table in ``pins`` and of one slider's in ``guides``.
_PIN_KEYS = frozenset({"radius_m", "mu", "viscous_nm_s_per_rad"})
_GUIDE_KEYS = frozenset({"mu", "viscous_n_s_per_m"})

_MASS_KEYS = {"link", "mass_kg", "com_m", "com_point", "com_offset_m", "inertia_kg_m2"}
_LOAD_KEYS = {"point", "force_n", "link", "torque_nm", "angle_deg"}


def _rows(table: Mapping[str, Any], key: str, where: str) -> list[Mapping[str, Any]]:
    rows = table.get(key, [])
    if not isinstance(rows, list) or not all(isinstance(r, Mapping) for r in rows):
        raise InputError(f"{where}: {key} must be an array of tables ([[...{key}]]); got {rows!r}")
    return rows


def _load(row: Mapping[str, Any], source: str, where: str) -> PointLoad | LinkTorque:
    """One ``[[…load]]`` row (``where``: its table and number) as a load; its
    ``_deg`` angle table warns if it looks like radians (:mod:`cyclomech._keyrules`)."""
    at = f"{source}: {where}"
    _toml.check_keys(row, _LOAD_KEYS, source, where)
    load: PointLoad | LinkTorque
    try:
        if "point" in row and "force_n" in row and not {"link", "torque_nm"} & set(row):
            load = PointLoad(row["point"], row["force_n"], row.get("angle_deg"))
        elif "link" in row and "torque_nm" in row and not {"point", "force_n"} & set(row):
            load = LinkTorque(row["link"], row["torque_nm"], row.get("angle_deg"))
        else:
            raise InputError(
                "give point and force_n [N] (a force), or link and torque_nm [N·m] (a "
                "torque), optionally with angle_deg (a table over the crank angle)"
            )
    except InputError as e:
        raise InputError(f"{at}: {e}") from None
    _keyrules.check(row, (), at)  # after the row's own errors
    return load


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
        when the table has none of :data:`DYNAMICS_KEYS` but ``friction`` (which
        :func:`friction_from_table` reads).

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
    if not _FORCE_KEYS & set(instance("table", table, Mapping)):
        return None
    if linkage is not None:
        from ..linkage import Linkage  # here: the linkage package imports this one

        instance("linkage", linkage, Linkage)
    masses: dict[tuple[str, ...], LinkMass] = {}
    for i, row in enumerate(_rows(table, "mass", where)):
        at = f"{source}: {where} mass #{i + 1}"
        _toml.check_keys(row, _MASS_KEYS, source, f"{where} mass #{i + 1}")
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
        loads.append(_load(row, source, f"{where} load #{i + 1}"))
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
        link_ok(joints, f"{where} mass #{i + 1}")
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
                f"{source}: {where} load #{i + 1}: point = {load.point!r} is not a point; the "
                f"points are {names}"
            )
        if isinstance(load, PointLoad) and load.point in ground:
            raise InputError(
                f"{source}: {where} load #{i + 1}: point = {load.point!r} is a ground joint: a "
                "force there goes straight into the frame and loads no link; put it on a moving "
                "point"
            )
        if isinstance(load, LinkTorque):
            link_ok(load.link, f"{where} load #{i + 1}")


def _names_table(spec: Mapping[str, Any], key: str, at: str) -> Mapping[str, Any]:
    """The sub-table ``spec[key]`` ({name = {…}}), each value a table."""
    t = spec.get(key, {})
    if not isinstance(t, Mapping) or not all(isinstance(v, Mapping) for v in t.values()):
        one = "{radius_m = 0.02, mu = 0.05}" if key == "pins" else "{mu = 0.15}"
        raise InputError(
            f"{at}: {key} = {t!r} must be a table of tables {{name = {one}}}, one per "
            f"{'joint' if key == 'pins' else 'slider'}"
        )
    return t


def friction_from_table(
    table: Mapping[str, Any], source: str, where: str, linkage: Linkage, dynamics: Mapping[str, Any]
) -> Friction | None:
    """The :class:`~cyclomech.forces.Friction` of a linkage's ``friction`` table.

    ``[<table>.friction]``: defaults for every joint — ``pin_radius_m`` [m] and
    ``pin_mu`` (given together), ``pin_viscous_nm_s_per_rad`` [N·m·s/rad] — and
    for every slider's guide — ``guide_mu``, ``guide_viscous_n_s_per_m`` [N·s/m] —
    and overrides ``pins`` = {joint = {radius_m, mu, viscous_nm_s_per_rad}} and
    ``guides`` = {slider's point = {mu, viscous_n_s_per_m}}, a key an override
    lacks taken from the defaults. The defaults apply to every joint where
    friction is modelled (two members: two links, a link and the frame, a link
    and a slider's block); a joint of more members is left frictionless with a
    warning naming it. One line covers the common case:
    ``friction = {pin_radius_m = 0.015, pin_mu = 0.08}``.

    Parameters
    ----------
    table : mapping of str to object
        The linkage's table of the machine file.
    source : str
        The file's name, for the messages.
    where : str
        The table's name (e.g. ``"[mechanism.knife]"``), for the messages.
    linkage : Linkage
        The linkage: the joints and sliders named are checked against it.
    dynamics : mapping of str to object
        Its forces' keywords (:func:`dynamics_from_table`'s).

    Returns
    -------
    Friction or None
        The friction of its joints and guides; None without a ``friction`` table.

    Raises
    ------
    InputError
        If a key is unknown, a value is not a finite number ≥ 0, ``pin_mu`` comes
        without ``pin_radius_m`` (or the reverse) for some joint, a joint or slider
        named is not one of the linkage's (the message lists those it has) or its
        friction is not modelled; the message names ``source``, the table, the key
        and the value.

    Warns
    -----
    CyclomechWarning
        For a friction coefficient above 0.5 (a percentage?), and for joints of
        more than two members the defaults cannot reach.

    Examples
    --------
    >>> import cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> f = friction_from_table({"friction": {"pin_radius_m": 0.01, "pin_mu": 0.1}}, "f.toml",
    ...                         "[mechanism.crank]", crank, {})
    >>> f.pins["O"]
    PinFriction(radius_m=0.01, mu=0.1, viscous=0.0)
    """
    for name, value, kind in (
        ("table", table, Mapping),
        ("source", source, str),
        ("where", where, str),
        ("dynamics", dynamics, Mapping),
    ):
        if not isinstance(value, kind):
            raise InputError(
                f"friction_from_table: {name} = {value!r} must be a "
                f"{'mapping' if kind is Mapping else 'string'}"
            )
    if "friction" not in table:
        return None
    at = f"{source}: {where.rstrip(']')}.friction]"
    spec = table["friction"]
    _toml.check_keys(spec, FRICTION_KEYS, None, at)
    _keyrules.check(spec, (), at)
    modelled, other, sliders = _joints(linkage, dynamics)
    default = {
        k: _keyrules.friction_number(spec, f"pin_{k}", at, unit)
        for k, unit in (("radius_m", "[m]"), ("mu", ""), ("viscous_nm_s_per_rad", "[N·m·s/rad]"))
        if f"pin_{k}" in spec
    }
    g_default = {
        k: _keyrules.friction_number(spec, f"guide_{k}", at, unit)
        for k, unit in (("mu", ""), ("viscous_n_s_per_m", "[N·s/m]"))
        if f"guide_{k}" in spec
    }
    pins = _pins(spec, at, modelled, other, default)
    guides = _guides(spec, at, sliders, g_default)
    return Friction(pins=pins, guides=guides)


def _pins(
    spec: Mapping[str, Any],
    at: str,
    modelled: list[str],
    other: list[str],
    default: Mapping[str, float],
) -> dict[str, PinFriction]:
    """The joints' friction of a friction table ``spec``: the defaults for every
    joint of ``modelled`` (when given), each override of ``pins`` on top."""
    own = _names_table(spec, "pins", at)
    for p in own:
        if p in other:
            raise InputError(
                f"{at}: pins.{p}: friction is not modelled at joint {p!r}, which joins more "
                "than two members; it is modelled at a joint of two (two links, a link and "
                f"the frame, a link and a slider's block): {', '.join(modelled)}"
            )
        if p not in modelled:
            raise InputError(
                f"{at}: pins.{p}: {p!r} is not a joint of the linkage; its joints are "
                f"{', '.join(modelled + other)}"
            )
    pins: dict[str, PinFriction] = {}
    for p in modelled if default else list(own):
        row = own.get(p, {})
        here = f"{at} pins.{p}" if p in own else at
        _toml.check_keys(row, _PIN_KEYS, None, f"{at} pins.{p}")
        _keyrules.check(row, (), f"{at} pins.{p}")
        got = dict(default)
        for k, unit in (("radius_m", "[m]"), ("mu", ""), ("viscous_nm_s_per_rad", "[N·m·s/rad]")):
            if k in row:
                got[k] = _keyrules.friction_number(row, k, f"{at} pins.{p}", unit)
        if ("radius_m" in got) != ("mu" in got):
            have, lack = ("radius_m", "mu") if "radius_m" in got else ("mu", "radius_m")
            pre = "pin_" if p not in own else ""
            raise InputError(
                f"{here}: {pre}{have} is given without {pre}{lack} for joint {p!r}: Coulomb "
                f"friction in a pin takes both (the torque μ·r·|R|); give {pre}{lack} "
                "(≥ 0, μ ≈ 0.05–0.1 and r = the pin's radius in m)"
            )
        pins[p] = PinFriction(
            got.get("radius_m", 0.0), got.get("mu", 0.0), got.get("viscous_nm_s_per_rad", 0.0)
        )
    if other and default:
        warnings.warn(
            f"{at}: the pin defaults leave joint(s) {', '.join(other)} frictionless: each "
            "joins more than two members, where friction is not modelled",
            CyclomechWarning,
            stacklevel=3,
        )
    return pins


def _guides(
    spec: Mapping[str, Any], at: str, sliders: list[str], g_default: Mapping[str, float]
) -> dict[str, GuideFriction]:
    """The guides' friction of a friction table ``spec``: the defaults for every
    slider of ``sliders`` (when given), each override of ``guides`` on top."""
    g_own = _names_table(spec, "guides", at)
    for p in g_own:
        if p not in sliders:
            raise InputError(
                f"{at}: guides.{p}: {p!r} is not a slider's point; the sliders are "
                f"{', '.join(sliders) if sliders else 'none (the linkage has no slider)'}"
            )
    if g_default and not sliders:
        raise InputError(
            f"{at}: {', '.join(f'guide_{k}' for k in g_default)} is given but the linkage "
            "has no slider; drop it, or give sliders"
        )
    guides: dict[str, GuideFriction] = {}
    for p in sliders if g_default else list(g_own):
        row = g_own.get(p, {})
        _toml.check_keys(row, _GUIDE_KEYS, None, f"{at} guides.{p}")
        got = dict(g_default)
        for k, unit in (("mu", ""), ("viscous_n_s_per_m", "[N·s/m]")):
            if k in row:
                got[k] = _keyrules.friction_number(row, k, f"{at} guides.{p}", unit)
        guides[p] = GuideFriction(got.get("mu", 0.0), got.get("viscous_n_s_per_m", 0.0))
    return guides
