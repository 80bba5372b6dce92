"""The impact file (:class:`ImpactStudy`): a lever with its stop and the speeds and
phase angles to study, and the keys of its ``[stop]`` table."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from .._arrays import positive, real_array
from .._errors import InputError
from ._checks import Array
from ._stop import StopImpact

__all__ = ["ImpactStudy"]


_STOP_KEYS = {
    "name",
    "law",
    "stroke",
    "preload",
    "lever_length",
    "J_A",
    "a",
    "b",
    "E",
    "J_x",
    "mass",
    "restitution",
    "zeta",
    "contact_stiffness",
    "pulse",
    "contact_time",
    "model",
}


_STRING_KEYS = {"name", "law", "pulse", "model"}


def _stop_from_table(table: Mapping[str, Any], where: str, skip: Iterable[str] = ()) -> StopImpact:
    """A :class:`StopImpact` from a file's table (its keys are checked by the
    caller; ``skip`` are the caller's own keys): the one reader of a stop, for
    ``cyclomech impact``'s [stop] and a machine's cam_stop mechanisms. Errors start
    with ``where``."""
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
        kwargs[k] = v
    for k in ("stroke", "preload", "lever_length", "J_A", "a", "b", "E", "J_x"):
        if k not in kwargs:
            raise InputError(f"{where}: missing key {k!r}")
    try:
        return StopImpact(**kwargs)
    except InputError as e:
        raise InputError(f"{where}: {e}") from None


@dataclass(frozen=True)
class ImpactStudy:
    """An impact file: a lever with its stop and the speeds and phase angles to study.

    Read with :meth:`from_toml`; each parameter is kept as the attribute of the
    same name. The file::

        [stop]
        name = "microshuttle lifter"   # optional
        law = "modified_sine"          # rise law of the cam (cyclomech.motion)
        stroke = 0.0094                # [m] travel of the working point
        preload = 0.00025              # [m]
        lever_length = 0.1             # [m]
        J_A = 7.4e-5                   # [kg m²]
        a = 0.05                       # [m] lever arms
        b = 0.1
        E = 2.1e11                     # [Pa]
        J_x = 6.14e-11                 # [m⁴]
        restitution = 0.5556           # optional (5/9), also: mass, zeta, pulse,
                                       # contact_stiffness, contact_time, model

        [study]
        rpm = [200, 450, 26]           # from, to, count
        phase_deg = [20, 60, 41]       # from, to, count [deg]
        a_max = 1e-4                   # [m] rebound limit
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
        _toml.check_keys(sd, {"rpm", "phase_deg", "a_max", "arc"}, src, "[study]")
        stop = _stop_from_table(sp, f"{src}: [stop]")

        at = f"{src}: [study]"
        rpm = _toml.span(sd, "rpm", at, within=(0.0, 1e6), unit="rpm")
        phase = _toml.span(sd, "phase_deg", at, within=(0.0, 360.0), unit="deg")
        if "a_max" not in sd:
            raise InputError(f"{src}: [study]: missing key 'a_max'")
        try:
            a_max = positive("a_max", sd["a_max"], "[m]")
        except InputError as e:
            raise InputError(f"{src}: [study]: {e}") from None
        arc = None
        if "arc" in sd:
            v = _toml.events(sd, "arc", at, arc=True)
            arc = (v[0], v[1])
        name = sp.get("name", "")
        if not isinstance(name, str):
            raise InputError(f"{src}: [stop]: name = {name!r} must be a string")
        return cls(stop, rpm, phase, a_max, arc, name)
