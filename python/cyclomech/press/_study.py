"""The press file (:class:`PressStudy`): one design, its working stroke and speed,
and optionally a design grid with limits for :func:`optimize`."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _keyrules, _toml
from .._arrays import finite_number, instance, positive, speeds_rpm
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ._drive import CRITERIA, GearLeverPress, _stroke

__all__ = ["PressStudy"]


#: The keys of a press drive's design in a file ([press] here, [mechanism.<name>]
#: of kind press in a machine file) → the :class:`GearLeverPress` parameter each
#: sets (``phi0_deg`` in degrees sets ``phi0`` in radians). The names carry their
#: units; the old ones (``R``, ``L``, …) are refused naming these
#: (:data:`cyclomech._keyrules.RENAMED`).
DRIVE_PARAMS: dict[str, str] = {
    "R_m": "R",
    "r_m": "r",
    "d_m": "d",
    "L_m": "L",
    "phi0_deg": "phi0",
    "offset_m": "offset",
}
DRIVE_KEYS = frozenset(DRIVE_PARAMS)


def drive_from_table(table: Mapping[str, Any], where: str, *, check: bool = True) -> GearLeverPress:
    """The design of a table's ``R_m``, ``r_m``, ``d_m``, ``L_m`` [m], ``phi0_deg``
    [deg] and optional ``offset_m`` [m]: the one reader of a press drive, for
    ``cyclomech press`` files and machines' press mechanisms. Errors start with
    ``where`` and name the file's keys; the values are then checked by
    ``cyclomech._keyrules.check`` (a length over 10 m warns), unless ``check`` is
    False: a machine's press mechanism checks its whole table itself, once.

    >>> d = drive_from_table({"R_m": 0.09, "r_m": 0.03, "d_m": 0.02, "L_m": 0.3,
    ...                       "phi0_deg": 15}, "x")
    >>> round(d.phi0, 6), d.offset
    (0.261799, 0.0)
    """
    _toml.require(table, ("R_m", "r_m", "d_m", "L_m", "phi0_deg"), where)
    geo = {
        DRIVE_PARAMS[k]: _toml.number(table, k, where, "[m]") for k in ("R_m", "r_m", "d_m", "L_m")
    }
    phi0 = math.radians(_toml.number(table, "phi0_deg", where, "[deg]"))
    offset = _toml.number(table, "offset_m", where, "[m]") if "offset_m" in table else 0.0
    try:
        press = GearLeverPress(phi0=phi0, offset=offset, **geo)
    except InputError as e:
        raise InputError(f"{where}: {_keyrules.file_names(str(e), DRIVE_PARAMS)}") from None
    if check:
        _keyrules.check({k: table[k] for k in DRIVE_KEYS if k in table}, (), where)
    return press


@dataclass(frozen=True)
class PressStudy:
    """A press file: one design, its working stroke and speed, and optionally a design grid.

    The grid with limits is for :func:`optimize`. Read with :meth:`from_toml`; each
    parameter is kept as the attribute of the same name. The file::

        [press]
        name = "extrusion press"     # optional
        R_m = 0.09                   # guide gear pitch radius
        r_m = 0.03                   # planet pitch radius (R_m/r_m whole)
        d_m = 0.025                  # pin eccentricity
        L_m = 0.30                   # rod
        phi0_deg = 17.0              # guide gear setting angle
        offset_m = 0.0               # optional, guide offset

        [working]
        k_Sp = 0.1                   # or working_stroke_m = 0.012
        rpm = 40.0                   # crank speed [rpm]

        [sweep]                      # optional: a grid of (d, L, φ0), [from, to, count]
        d_m = [0.0, 0.04, 41]
        L_m = [0.25, 0.5, 26]
        phi0_deg = [0.0, 118.0, 60]

        [limits]                     # optional upper bounds on criteria (SI units)
        V_np = 0.05

    Parameters
    ----------
    press : GearLeverPress
        The design.
    rpm : float
        The crank speed [rpm].
    k_Sp : float, optional
        The working stroke as a fraction of the nominal stroke; default None.
    working_stroke : float, optional
        The working stroke S_p [m]; default None (one of the two is given).
    grid : dict of str to ndarray of float, optional
        The grid's ``d``, ``L`` [m] and ``phi0`` [rad] values (an axis not swept
        holds the design's value); default None (no ``[sweep]``).
    limits : dict of str to float, optional
        Upper bounds on criteria of :data:`CRITERIA`, in SI units; default empty.
    name : str, default ""
        The press's name.

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.0)
    >>> st = cm.press.PressStudy(p, rpm=60.0, k_Sp=0.1)
    >>> st.working_stroke, st.grid, st.limits
    (None, None, {})
    """

    press: GearLeverPress
    rpm: float
    k_Sp: float | None = None
    working_stroke: float | None = None
    grid: dict[str, npt.NDArray[np.float64]] | None = None
    limits: dict[str, float] = field(default_factory=dict)
    name: str = ""

    def __post_init__(self) -> None:
        # One rule for every public number (issue 31): rpm = NaN would give ω = NaN
        # and rpm = -40 a backwards crank, silently.
        instance("press", self.press, GearLeverPress)
        rpm = float(speeds_rpm("rpm", finite_number("rpm", self.rpm, "[rpm]"))[0])
        object.__setattr__(self, "rpm", rpm)
        if self.k_Sp is not None:
            object.__setattr__(self, "k_Sp", positive("k_Sp", self.k_Sp, "(a fraction)"))
        if self.working_stroke is not None:
            ws = positive("working_stroke", self.working_stroke, "[m]")
            object.__setattr__(self, "working_stroke", ws)

    @property
    def omega(self) -> float:
        """Crank speed [rad/s].

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.0)
        >>> round(cm.press.PressStudy(p, rpm=60.0, k_Sp=0.1).omega, 6)
        6.283185
        """
        return self.rpm * RAD_PER_S_PER_RPM

    @classmethod
    def from_toml(cls, path: str | Any) -> PressStudy:
        """Read a press file; errors name the file, the table and the key.

        Parameters
        ----------
        path : str or path-like
            The press file (TOML).

        Returns
        -------
        PressStudy
            The design, its working stroke and speed, and the grid and limits if given.

        Raises
        ------
        InputError
            If the file cannot be read, a table or a key is missing or unknown (a
            machine's crank-torque keys in ``[press]`` among them), or a value is
            malformed or out of range.

        Examples
        --------
        >>> import cyclomech as cm, pathlib, tempfile
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "p.toml"
        >>> _ = f.write_text('[press]\\nR_m = 0.09\\nr_m = 0.03\\nd_m = 0.02\\nL_m = 0.3\\n'
        ...                  'phi0_deg = 15\\n[working]\\nk_Sp = 0.1\\nrpm = 40\\n')
        >>> st = cm.press.PressStudy.from_toml(f)
        >>> round(st.press.phi0, 6), st.grid is None
        (0.261799, True)
        """

        data, src = _toml.load(path)
        _toml.check_keys(data, {"press", "working", "sweep", "limits"}, src, "the file")
        for t in ("press", "working"):
            if t not in data:
                raise InputError(f"{src}: missing table [{t}]")
        pt, wt = data["press"], data["working"]
        _toml.must_be_table(pt, src, "[press]")
        machine_only = sorted(
            set(pt) & {"deformation_force", "slider_mass_kg", "rod_mass_kg", "phase"}
        )
        if machine_only:
            raise InputError(
                f"{src}: [press]: {', '.join(machine_only)} give(s) the crank torque in a "
                'machine: they belong in its [mechanism.<name>] (kind = "press") table of a '
                "file for `cyclomech run`; in Python, GearLeverPress.crank_torque takes them"
            )
        _toml.check_keys(pt, DRIVE_KEYS | {"name"}, src, "[press]")
        _toml.check_keys(wt, {"k_Sp", "working_stroke_m", "rpm"}, src, "[working]")

        def num(table: Mapping[str, Any], where: str, key: str, default: Any = None) -> float:
            if key not in table:
                if default is not None:
                    return float(default)
                raise InputError(f"{src}: {where}: missing key {key!r}")
            v = table[key]
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                raise InputError(f"{src}: {where}: {key} = {v!r} must be a finite number")
            return float(v)

        press = drive_from_table(pt, f"{src}: [press]")
        rpm = num(wt, "[working]", "rpm")
        if rpm <= 0:
            raise InputError(f"{src}: [working]: rpm = {rpm!r} must be > 0")
        k = num(wt, "[working]", "k_Sp") if "k_Sp" in wt else None
        s = num(wt, "[working]", "working_stroke_m") if "working_stroke_m" in wt else None
        try:
            _stroke(k, s)
        except InputError as e:
            named = _keyrules.file_names(str(e), {"working_stroke_m": "working_stroke"})
            raise InputError(f"{src}: [working]: {named}") from None
        grid = None
        if "sweep" in data:
            st = data["sweep"]
            _toml.check_keys(st, {"d_m", "L_m", "phi0_deg"}, src, "[sweep]")
            grid = {}
            axes = (("d_m", "d", 1.0), ("L_m", "L", 1.0), ("phi0_deg", "phi0", None))
            for key, name, scale in axes:
                if key not in st:
                    grid[name] = np.array([getattr(press, name)])
                    continue
                vals = _toml.span(st, key, f"{src}: [sweep]")
                grid[name] = vals if scale else np.radians(vals)
        limits: dict[str, float] = {}
        if "limits" in data:
            _toml.check_keys(data["limits"], set(CRITERIA), src, "[limits]")
            limits = {k_: num(data["limits"], "[limits]", k_) for k_ in data["limits"]}
        name = pt.get("name", "")
        if not isinstance(name, str):
            raise InputError(f"{src}: [press]: name = {name!r} must be a string")
        return cls(press, rpm, k, s, grid, limits, name)
