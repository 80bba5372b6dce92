"""A machine file's cam that asks to be sized: `_synthesize` part of :mod:`cyclomech.cam`.

``[mechanism.<name>.synthesize]`` replaces the cam table's ``base_radius_m`` (issue 35,
items 7 and 8): ``base_radius = "smallest"`` sizes the base radius by
:func:`cyclomech.synthesis.cam_size` at the machine's optimised timing, the cam's
limits (``max_pressure_angle_deg``, ``max_stress_pa``) its requirements; optionally
the offset (translating roller) or pivot distance (oscillating roller, its arm
length held) is searched over a range. The machine's run iterates to a fixed
point (:meth:`CamMechanism.resize`, ``cyclomech/machine/_resize.py``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .. import _keyrules, _toml
from .._errors import InputError

__all__ = ["SYNTHESIZE_KEYS", "CamSynthesis", "synthesis_from_table"]

#: The keys of a cam's ``synthesize`` table.
SYNTHESIZE_KEYS = frozenset(
    {"base_radius", "max_base_radius_m", "min_base_radius_m", "offset_m", "pivot_distance_m"}
)

#: What ``base_radius`` may ask for.
_MODES = ("smallest",)


@dataclass(frozen=True)
class CamSynthesis:
    """What a cam's ``synthesize`` table asks: the radii searched and the second dimension.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    max_base_radius : float
        The largest base radius searched [m]; the machine's first round uses it.
    min_base_radius : float or None
        The smallest base radius searched [m]; None: just above the roller.
    offset : tuple of (float, float) or None
        A translating roller's offset range searched [m]; None: held.
    pivot_distance : tuple of (float, float) or None
        An oscillating roller's pivot-distance range searched [m]; None: held.

    Examples
    --------
    >>> CamSynthesis(0.1, None, None, None).max_base_radius
    0.1
    """

    max_base_radius: float
    min_base_radius: float | None
    offset: tuple[float, float] | None
    pivot_distance: tuple[float, float] | None


def _range(spec: Mapping[str, Any], key: str, where: str) -> tuple[float, float] | None:
    if key not in spec:
        return None
    v = spec[key]
    if not (
        isinstance(v, list)
        and len(v) == 2
        and all(_toml.is_number(x) and math.isfinite(x) for x in v)
        and v[0] < v[1]
    ):
        raise InputError(f"{where}: {key} = {v!r} must be [low, high] in m, finite, low < high")
    return float(v[0]), float(v[1])


def synthesis_from_table(table: Mapping[str, Any], at: str, follower: str) -> CamSynthesis | None:
    """The :class:`CamSynthesis` of a cam table's ``synthesize`` table, None without one.

    Parameters
    ----------
    table : mapping of str to object
        The cam table.
    at : str
        The file and table, for the messages ("f.toml: [mechanism.cam]").
    follower : str
        The table's ``follower`` (which second dimension fits).

    Returns
    -------
    CamSynthesis or None
        What is asked; None without a ``synthesize`` table.

    Raises
    ------
    InputError
        If the table also gives ``base_radius_m`` (drop one), a key is unknown,
        ``base_radius`` is not "smallest", a radius is not > 0 (the largest above the
        smallest), a range is malformed or does not fit the follower.

    Examples
    --------
    >>> t = {"synthesize": {"base_radius": "smallest", "max_base_radius_m": 0.1}}
    >>> synthesis_from_table(t, "[cam]", "oscillating").max_base_radius
    0.1
    >>> synthesis_from_table({**t, "base_radius_m": 0.05}, "[cam]", "oscillating")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: [cam]: base_radius_m = 0.05 and a synthesize table ...
    """
    if "synthesize" not in table:
        return None
    where = f"{at.rstrip(']')}.synthesize]"
    spec = table["synthesize"]
    if not isinstance(spec, Mapping):
        raise InputError(f"{where}: synthesize = {spec!r} must be a table")
    if "base_radius_m" in table:
        raise InputError(
            f"{at}: base_radius_m = {table['base_radius_m']!r} and a synthesize table both "
            "set the base radius: drop base_radius_m to have it sized, or drop the synthesize "
            "table to keep it"
        )
    _toml.check_keys(spec, SYNTHESIZE_KEYS, None, where)
    _toml.require(spec, ("base_radius", "max_base_radius_m"), where)
    if spec["base_radius"] not in _MODES:
        raise InputError(
            f"{where}: base_radius = {spec['base_radius']!r} must be one of {list(_MODES)}"
        )
    hi = _toml.optional_positive(spec, "max_base_radius_m", where, "[m]")
    lo = _toml.optional_positive(spec, "min_base_radius_m", where, "[m]")
    assert hi is not None  # required above
    if lo is not None and not lo < hi:
        raise InputError(
            f"{where}: min_base_radius_m = {lo!r} must be < max_base_radius_m = {hi!r} [m]"
        )
    _keyrules.check(spec, (), where)  # a radius in mm given as m, …
    offset = _range(spec, "offset_m", where)
    pivot = _range(spec, "pivot_distance_m", where)
    if offset is not None and follower != "translating":
        raise InputError(
            f"{where}: offset_m searches a translating follower's offset; "
            f"this follower is {follower}: drop offset_m"
        )
    if pivot is not None and follower != "oscillating":
        raise InputError(
            f"{where}: pivot_distance_m searches an oscillating follower's "
            f"pivot; this follower is {follower}: drop pivot_distance_m"
        )
    return CamSynthesis(hi, lo, offset, pivot)
