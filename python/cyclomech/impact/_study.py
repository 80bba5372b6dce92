"""The impact file (:class:`ImpactStudy`): a lever with its stop and the speeds and
phase angles to study, and the keys of its ``[stop]`` table."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from .. import _keyrules, _toml
from .._arrays import positive, real_array
from .._errors import InputError
from .._keyrules import Rule
from ._checks import Array
from ._stop import StopImpact

__all__ = ["ImpactStudy"]


#: The keys of a stop's table (an impact file's ``[stop]``, a machine's ``cam_stop``
#: mechanism) → the :class:`StopImpact` parameter each sets. A key with a unit says
#: it in its name (the old names, ``stroke`` and the like, are refused naming these:
#: :data:`cyclomech._keyrules.RENAMED`).
STOP_PARAMS: dict[str, str] = {
    "name": "name",
    "law": "law",
    "stroke_m": "stroke",
    "preload_m": "preload",
    "lever_length_m": "lever_length",
    "J_A_kg_m2": "J_A",
    "a_m": "a",
    "b_m": "b",
    "E_pa": "E",
    "J_x_m4": "J_x",
    "mass_kg": "mass",
    "restitution": "restitution",
    "zeta": "zeta",
    "contact_stiffness_n_per_m": "contact_stiffness",
    "pulse": "pulse",
    "contact_time_s": "contact_time",
    "model": "model",
}
_STOP_KEYS = set(STOP_PARAMS)
#: The keys a stop's table must give (a cam stop that names its cam takes the
#: stroke from it).
STOP_REQUIRED = (
    "stroke_m",
    "preload_m",
    "lever_length_m",
    "J_A_kg_m2",
    "a_m",
    "b_m",
    "E_pa",
    "J_x_m4",
)

#: The plausibility rules of a stop's table (``cyclomech._keyrules.check``): a
#: damping ratio of 1 or more is valid (overdamped) but far likelier a percentage.
STOP_RULES = (
    Rule(
        "zeta",
        lambda v, t: v >= 1.0,
        lambda v, t: (
            "is overdamped (ζ ≥ 1: the lever would creep back without vibrating) — did you "
            f"mean {v / 100:g}? zeta is a ratio, not a percentage"
        ),
    ),
)
#: The rule of a rebound limit: a first rebound as large as the whole stroke cannot
#: be meant; it is likelier a limit in millimetres.
A_MAX_RULES = (
    Rule(
        "a_max_m",
        lambda v, t: _toml.is_number(t.get("stroke_m")) and v >= t["stroke_m"],
        lambda v, t: (
            f"is not below the stroke (stroke_m = {t['stroke_m']:g} m): a rebound limit of "
            f"the whole stroke or more cannot be meant — did you give millimetres "
            f"(a_max_m = {v / 1000:g})?"
        ),
        error=True,
    ),
)


_STRING_KEYS = {"name", "law", "pulse", "model"}


def _stop_from_table(
    table: Mapping[str, Any],
    where: str,
    skip: Iterable[str] = (),
    rules: Iterable[Rule] | None = STOP_RULES,
) -> StopImpact:
    """A :class:`StopImpact` from a file's table (its keys are checked by the
    caller; ``skip`` are the caller's own keys): the one reader of a stop, for
    ``cyclomech impact``'s [stop] and a machine's cam_stop mechanisms. Errors start
    with ``where`` and name the file's keys; the values are then checked against
    ``rules`` (:data:`STOP_RULES`: a warning for a damping ratio given in percent),
    unless ``rules`` is None: a cam stop checks its whole table itself, with its
    rebound limit, once (checking here too printed each unit warning twice)."""
    skip = {"name", *skip}
    kwargs: dict[str, Any] = {}
    for k, v in table.items():
        if k in skip:
            continue
        if k in _STRING_KEYS:
            if not isinstance(v, str):
                raise InputError(f"{where}: {k} = {v!r} must be a string")
        elif isinstance(v, bool) or not isinstance(v, int | float):
            raise InputError(f"{where}: {k} = {v!r} must be a number")
        kwargs[STOP_PARAMS[k]] = v
    _toml.require(table, STOP_REQUIRED, where)
    try:
        stop = StopImpact(**kwargs)
    except InputError as e:
        raise InputError(f"{where}: {_keyrules.file_names(str(e), STOP_PARAMS)}") from None
    if rules is not None:
        _keyrules.check(table, rules, where)
    return stop


@dataclass(frozen=True)
class ImpactStudy:
    """An impact file: a lever with its stop and the speeds and phase angles to study.

    Read with :meth:`from_toml`; each parameter is kept as the attribute of the
    same name. The file::

        [stop]
        name = "microshuttle lifter"   # optional
        law = "modified_sine"          # rise law of the cam (cyclomech.motion)
        stroke_m = 0.0094              # travel of the working point
        preload_m = 0.00025
        lever_length_m = 0.1
        J_A_kg_m2 = 7.4e-5             # lever inertia about its axis
        a_m = 0.05                     # lever arms
        b_m = 0.1
        E_pa = 2.1e11
        J_x_m4 = 6.14e-11
        restitution = 0.5556           # optional (5/9), also: mass_kg, zeta, pulse,
                                       # contact_stiffness_n_per_m, contact_time_s, model

        [study]
        rpm = [200, 450, 26]           # from, to, count
        phase_deg = [20, 60, 41]       # from, to, count [deg]
        a_max_m = 1e-4                 # rebound limit
        arc = ["3", "7"]               # optional: the cyclogram operation

    Parameters
    ----------
    stop : StopImpact
        The lever with its stop (the file's ``[stop]`` table).
    rpm : ndarray of float
        The machine speeds to study [rpm].
    phase_deg : ndarray of float
        The phase angles to study [deg].
    a_max : float
        The rebound limit [m].
    arc : tuple of (str, str), optional
        The cyclogram operation (two event names); default None.
    name : str, default ""
        The stop's name.

    Examples
    --------
    >>> import cyclomech as cm
    >>> st = cm.impact.ImpactStudy.from_toml("examples/stb_lifter.toml")
    >>> st.arc, st.name
    (('3', '7'), 'STB microshuttle lifter (illustrative)')
    """

    stop: StopImpact
    rpm: Array
    phase_deg: Array
    a_max: float
    arc: tuple[str, str] | None = None
    name: str = ""

    def __post_init__(self) -> None:
        # One rule for every public number (issue 31): a string, a bool, NaN or
        # ±inf is refused here too, not only by the file reader.
        if not isinstance(self.stop, StopImpact):
            raise TypeError(f"stop must be a StopImpact; got {type(self.stop).__name__}")
        rpm = real_array("rpm", self.rpm, "[rpm]", low=0.0, strict=True)
        phase = real_array("phase_deg", self.phase_deg, "[deg]", low=0.0, strict=True)
        object.__setattr__(self, "rpm", rpm)
        object.__setattr__(self, "phase_deg", phase)
        object.__setattr__(self, "a_max", positive("a_max", self.a_max, "[m]"))

    @classmethod
    def from_toml(cls, path: Any) -> ImpactStudy:
        """Read an impact file; errors name the file, the table and the key.

        Parameters
        ----------
        path : str or path-like
            The impact file (TOML).

        Returns
        -------
        ImpactStudy
            The stop and the study's speeds, phase angles and rebound limit.

        Raises
        ------
        InputError
            If the file cannot be read, a table or a key is missing or unknown, or a
            value is malformed or out of range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> st = cm.impact.ImpactStudy.from_toml("examples/stb_lifter.toml")
        >>> st.rpm.size, st.phase_deg.size, st.a_max
        (26, 41, 0.0001)
        """
        from .. import _toml

        data, src = _toml.load(path)
        _toml.check_keys(data, {"stop", "study"}, src, "the file")
        for t in ("stop", "study"):
            if t not in data:
                raise InputError(f"{src}: missing table [{t}]")
        sp, sd = data["stop"], data["study"]
        _toml.check_keys(sp, _STOP_KEYS, src, "[stop]")
        _toml.check_keys(sd, {"rpm", "phase_deg", "a_max_m", "arc"}, src, "[study]")
        stop = _stop_from_table(sp, f"{src}: [stop]")

        at = f"{src}: [study]"
        rpm = _toml.span(sd, "rpm", at, within=(0.0, 1e6), unit="rpm")
        phase = _toml.span(sd, "phase_deg", at, within=(0.0, 360.0), unit="deg")
        if "a_max_m" not in sd:
            raise InputError(f"{src}: [study]: missing key 'a_max_m'")
        try:
            a_max = positive("a_max_m", sd["a_max_m"], "[m]")
        except InputError as e:
            raise InputError(f"{src}: [study]: {e}") from None
        _keyrules.check({"a_max_m": a_max, "stroke_m": stop.stroke}, A_MAX_RULES, at)
        arc = None
        if "arc" in sd:
            v = _toml.events(sd, "arc", at, arc=True)
            arc = (v[0], v[1])
        name = sp.get("name", "")
        if not isinstance(name, str):
            raise InputError(f"{src}: [stop]: name = {name!r} must be a string")
        return cls(stop, rpm, phase, a_max, arc, name)
