"""The parts of a linkage's drawing checked one by one: points, links, ground,
driver, given lengths and sliders."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from .._arrays import real
from .._errors import InputError

Point = tuple[float, float]


def _joint(value: Any, where: str, points: Mapping[str, Any]) -> str:
    """``value`` as the name of one of ``points``, or :class:`InputError` naming
    ``where``: a name is a string (a list, a number or a table is not one; a
    file's ``ground = [["A", "D"]]`` once ended in ``TypeError: unhashable``).

    >>> from cyclomech.linkage._drawing import _joint
    >>> _joint("A", "ground #1", {"A": 0})
    'A'
    >>> _joint(["A"], "ground", {"A": 0})
    Traceback (most recent call last):
    cyclomech._errors.InputError: ground = ['A'] must be a joint name (a string); the points are A
    """
    if not isinstance(value, str):
        raise InputError(
            f"{where} = {value!r} must be a joint name (a string); the points are "
            f"{', '.join(points)}"
        )
    if value not in points:
        raise InputError(f"{where}: no point {value!r}; known points are {', '.join(points)}")
    return value


def _sliders(
    sliders: Any, points: Mapping[str, Any], ground: set[str], links: list[tuple[str, ...]]
) -> dict[str, list[tuple[str, tuple[Any, ...]]]]:
    """{point: [(kind, arg), …]} with every guide checked."""
    if sliders is None:
        return {}
    if not isinstance(sliders, Mapping):
        raise InputError(f"sliders must map points to guides; got {sliders!r}")
    out: dict[str, list[tuple[str, tuple[Any, ...]]]] = {}
    for p, spec in sliders.items():
        where = f"sliders[{p!r}]"
        _joint(p, where, points)
        if p in ground:
            raise InputError(f"{where}: {p!r} is a ground joint; a fixed point cannot slide")
        specs = (
            [spec] if isinstance(spec, tuple | list) and spec and isinstance(spec[0], str) else spec
        )
        if not isinstance(specs, list | tuple) or not 1 <= len(specs) <= 2:
            raise InputError(
                f"{where} = {spec!r}: give a guide, ('ground', (dx, dy)) or ('link', (b, c)), "
                "or a list of two guides"
            )
        guides: list[tuple[str, tuple[Any, ...]]] = []
        for g in specs:
            if not (isinstance(g, tuple | list) and len(g) == 2 and g[0] in ("ground", "link")):
                raise InputError(
                    f"{where}: guide {g!r} must be ('ground', (dx, dy)) or ('link', (b, c))"
                )
            kind, arg = g
            if kind == "ground":
                try:
                    dx, dy = (float(v) for v in arg)
                except (TypeError, ValueError):
                    raise InputError(
                        f"{where}: the direction {arg!r} of a ground guide must be (dx, dy)"
                    ) from None
                if not (math.isfinite(dx) and math.isfinite(dy)) or dx == dy == 0.0:
                    raise InputError(
                        f"{where}: the direction {arg!r} must be a finite, non-zero (dx, dy)"
                    )
                guides.append(("ground", (dx, dy)))
            else:
                if not (isinstance(arg, tuple | list) and len(arg) == 2):
                    raise InputError(f"{where}: a link guide is ('link', (b, c)); got {g!r}")
                b = _joint(arg[0], f"{where}: the guide's first joint", points)
                c = _joint(arg[1], f"{where}: the guide's second joint", points)
                if not any(b in ln and c in ln for ln in links) or b == c:
                    raise InputError(
                        f"{where}: ({b!r}, {c!r}) are not two joints of one link; the guide "
                        "runs along a link, through two of its joints"
                    )
                if any(p in ln and b in ln and c in ln for ln in links):
                    raise InputError(
                        f"{where}: {p!r} is a joint of the link {b}–{c} it would slide on"
                    )
                guides.append(("link", (b, c)))
        out[p] = guides
    return out


def _points(points: Any) -> dict[str, tuple[float, float]]:
    """{name: (x, y) [m]} with every name a non-empty string and every coordinate
    a finite real number.

    >>> from cyclomech.linkage._drawing import _points
    >>> _points({"A": (0, 0), "B": (1, 0.5)})
    {'A': (0.0, 0.0), 'B': (1.0, 0.5)}
    """
    if not isinstance(points, Mapping) or not points:
        raise InputError(f"points must map joint names to (x, y) [m]; got {points!r}")
    out = {}
    for name, xy in points.items():
        if not isinstance(name, str) or not name:
            raise InputError(f"points: joint names must be non-empty strings; got {name!r}")
        try:
            x, y = (real(v) for v in xy)
        except (TypeError, ValueError):
            raise InputError(f"points[{name!r}] must be (x, y) in metres; got {xy!r}") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(f"points[{name!r}] = {xy!r} must be finite coordinates [m]")
        out[name] = (x, y)
    return out


def _links(links: Any, points: Mapping[str, Any]) -> list[tuple[str, ...]]:
    """The links as tuples of known joint names, each of two joints or more.

    >>> from cyclomech.linkage._drawing import _links
    >>> _links([["A", "B"], ["B", "C", "E"]], {"A": 0, "B": 0, "C": 0, "E": 0})
    [('A', 'B'), ('B', 'C', 'E')]
    """
    if isinstance(links, str) or not isinstance(links, Iterable):
        raise InputError(
            f"links = {links!r} must be an array of links, each an array of joint names, "
            'e.g. [["A", "B"], ["B", "C", "E"]]'
        )
    out = []
    for k, ln in enumerate(links):
        if isinstance(ln, str) or not isinstance(ln, Sequence) or len(ln) < 2:
            raise InputError(f"links #{k + 1} = {ln!r} must list at least two joints")
        joints = tuple(
            _joint(p, f"links #{k + 1}, joint #{i + 1}", points) for i, p in enumerate(ln)
        )
        if len(set(joints)) != len(joints):
            raise InputError(f"links #{k + 1} = {ln!r} lists a joint twice")
        out.append(joints)
    if not out:
        raise InputError("links must list at least the crank")
    return out


def _ground(ground: Any, points: Mapping[str, Any]) -> set[str]:
    if isinstance(ground, str) or not isinstance(ground, Iterable):
        raise InputError(
            f"ground = {ground!r} must be an array of joint names, e.g. [{ground!r}]"
            if isinstance(ground, str)
            else f"ground = {ground!r} must be an array of joint names"
        )
    g = {_joint(p, f"ground #{i + 1}", points) for i, p in enumerate(ground)}
    if not g:
        raise InputError("ground must list at least the crank's pivot")
    return g


def _driver(
    driver: Any, points: Mapping[str, Any], ground: set[str], links: list[tuple[str, ...]]
) -> tuple[str, str]:
    if not (isinstance(driver, tuple | list) and len(driver) == 2):
        raise InputError(f"driver must be (pivot, tip); got {driver!r}")
    pivot = _joint(driver[0], f"driver = {driver!r}: the pivot", points)
    tip = _joint(driver[1], f"driver = {driver!r}: the tip", points)
    if pivot not in ground:
        raise InputError(f"driver = {driver!r}: the crank's pivot {pivot!r} must be a ground joint")
    if tip in ground:
        raise InputError(f"driver = {driver!r}: the crank's tip {tip!r} cannot be a ground joint")
    if not any(pivot in ln and tip in ln for ln in links):
        cranks = sorted(
            {(g, t) for ln in links for g in ln if g in ground for t in ln if t not in ground}
        )
        listing = ", ".join(f"[{g!r}, {t!r}]" for g, t in cranks) or "none"
        raise InputError(
            f"driver = {driver!r}: no link joins {pivot!r} and {tip!r}; a driver is a ground "
            f"joint and a moving joint of one link: {listing}"
        )
    return (pivot, tip)


def _lengths(lengths: Any, links: list[tuple[str, ...]]) -> dict[tuple[str, str], float]:
    out: dict[tuple[str, str], float] = {}
    if lengths is not None and not isinstance(lengths, Mapping):
        raise InputError(f"lengths must map joint pairs (a, b) to lengths [m]; got {lengths!r}")
    joints = {p: None for ln in links for p in ln}
    for pair, value in (lengths or {}).items():
        if not (isinstance(pair, tuple) and len(pair) == 2):
            raise InputError(f"lengths: a key must be a pair of joints (a, b); got {pair!r}")
        a = _joint(pair[0], f"lengths[{pair!r}]", joints)
        b = _joint(pair[1], f"lengths[{pair!r}]", joints)
        if not any(a in ln and b in ln for ln in links):
            raise InputError(f"lengths[{(a, b)!r}]: {a!r} and {b!r} are not joints of one link")
        try:
            v = real(value)
        except (TypeError, ValueError):
            raise InputError(f"lengths[{(a, b)!r}] = {value!r} must be a length [m]") from None
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"lengths[{(a, b)!r}] = {value!r} must be a positive length [m]")
        out[(a, b)] = v
    return out
