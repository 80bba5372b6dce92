"""The machine's elastic main shaft and links (``[drive.shaft]`` and
``[drive.link.<mechanism>]`` of a machine file) and the dynamic errors they give
(:class:`MachineTorsion`, issue 34 item 3): `_elastic` part of
:mod:`cyclomech.dynamics` (its door).

:meth:`ElasticShaft.from_tables` reads the tables; :func:`machine_torsion` puts
each mechanism's reduced inertia and load torque (phased by the optimised
cyclogram, as :func:`~cyclomech.dynamics.reduced` does) and its working member on
its take-off node, solves the chain under the drive's motor with the steady
state's flywheel at the nominal speed (:func:`~cyclomech.dynamics.torsion`), and
sweeps the machine's speed range with the head at constant speed
(:func:`~cyclomech.dynamics.torsion_sweep`) for the speed at which each bounded
member's dynamic error reaches its bound.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _keyrules, _toml
from .._arrays import finite_number, instance, positive
from .._errors import InputError, SolverError
from .._units import RAD_PER_S_PER_RPM
from ..shaft import ShaftTorque
from ._motor import Motor
from ._shaft import SteadyState
from ._torsion import ShaftNode, Torsion, TorsionSweep, WorkingMember, torsion, torsion_sweep

__all__ = ["ElasticShaft", "LinkSpec", "MachineTorsion", "error_limits", "machine_torsion"]

Array = npt.NDArray[np.float64]


#: The periodicity a machine's run asks of the chain (relative to each variable's
#: range): the peak errors it reports keep 5 digits at it, a quarter fewer cycles
#: than :func:`torsion`'s default 1e-9.
_TOL = 1e-7
#: The cycles a machine's run gives the chain to settle: a real shaft's and link's
#: damping take the start's transient away in a few (ζ·ω·T ≫ 1); a chain that has not
#: settled in these is reported so (a failure), in seconds rather than minutes.
_MAX_CYCLES = 300

#: The plausibility rule of a damping ratio in ``[drive.shaft]`` and
#: ``[drive.link.…]``: 1 or more is valid (overdamped) but far likelier a percentage.
DAMPING_RULES = (
    _keyrules.Rule(
        "damping_ratio",
        lambda v, t: v >= 1.0,
        lambda v, t: (
            f"is overdamped (ζ ≥ 1) — did you mean {v / 100:g}? damping_ratio is a ratio, "
            "not a percentage"
        ),
    ),
)

#: The keys of ``[drive.shaft]`` and of each ``[drive.link.<mechanism>]``.
SHAFT_KEYS = frozenset({"take_off", "stiffness_nm_per_rad", "hub_inertia_kg_m2", "damping_ratio"})
LINK_KEYS = frozenset({"frequency_hz", "damping_ratio", "max_error_m", "max_error_deg"})


@dataclass(frozen=True)
class LinkSpec:
    """A working member's elastic link: natural frequency [Hz] (inf: rigid), damping
    ratio, and the largest dynamic error allowed (in metres, or degrees for a member
    that turns; None: no bound). Each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    frequency_hz : float, default inf
        > 0.
    damping_ratio : float, default 0.05
        ≥ 0.
    max_error_m, max_error_deg : float, optional
        > 0; at most one.

    Examples
    --------
    >>> LinkSpec(frequency_hz=60.0, max_error_m=5e-4).max_error_m
    0.0005
    """

    frequency_hz: float = math.inf
    damping_ratio: float = 0.05
    max_error_m: float | None = None
    max_error_deg: float | None = None

    def __post_init__(self) -> None:
        f = self.frequency_hz
        if not (_toml.is_number(f) and f > 0):  # a number > 0, inf allowed (a rigid link)
            raise InputError(
                f"LinkSpec: frequency_hz = {f!r} must be a number > 0 [Hz] (inf: rigid)"
            )
        object.__setattr__(self, "frequency_hz", float(f))
        z = finite_number("LinkSpec: damping_ratio", self.damping_ratio, "", low=0.0)
        object.__setattr__(self, "damping_ratio", z)
        for k, unit in (("max_error_m", "[m]"), ("max_error_deg", "[deg]")):
            v = getattr(self, k)
            if v is not None:
                object.__setattr__(self, k, positive(f"LinkSpec: {k}", v, unit))
        if self.max_error_m is not None and self.max_error_deg is not None:
            raise InputError("LinkSpec: give max_error_m or max_error_deg, not both")


@dataclass(frozen=True)
class ElasticShaft:
    """The main shaft's elasticity: its take-off points in order from the motor's
    end, each segment's stiffness [N·m/rad], each hub's inertia [kg·m²], one damping
    ratio for the segments (d_k = 2ζ·√(c_k·J̄_k), J̄_k the node's mean inertia), and
    the working members' links by mechanism. Each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    take_off : tuple of str
        Every mechanism on the main shaft, in order from the motor's end.
    stiffness_nm_per_rad, hub_inertia_kg_m2 : tuple of float
        One per take-off point (> 0).
    damping_ratio : float, default 0.02
        ≥ 0 (steel shafts: 0.01–0.05).
    links : dict of str to LinkSpec
        The elastic links (mechanisms not named have rigid ones).

    Examples
    --------
    >>> e = ElasticShaft.from_tables({"take_off": ["knife"], "stiffness_nm_per_rad": [2e4],
    ...                               "hub_inertia_kg_m2": [0.5]}, {}, "m.toml")
    >>> e.take_off, e.damping_ratio
    (('knife',), 0.02)
    """

    take_off: tuple[str, ...]
    stiffness_nm_per_rad: tuple[float, ...]
    hub_inertia_kg_m2: tuple[float, ...]
    damping_ratio: float = 0.02
    links: dict[str, LinkSpec] = field(default_factory=dict)

    def __post_init__(self) -> None:
        names = self.take_off
        if not (
            isinstance(names, (tuple, list))
            and names
            and all(isinstance(x, str) for x in names)
            and len(set(names)) == len(names)
        ):
            raise InputError(
                f"ElasticShaft: take_off = {names!r} must be distinct mechanism names, at least one"
            )
        object.__setattr__(self, "take_off", tuple(names))
        for k, unit in (("stiffness_nm_per_rad", "[N·m/rad]"), ("hub_inertia_kg_m2", "[kg·m²]")):
            v = getattr(self, k)
            if not (isinstance(v, (tuple, list)) and len(v) == len(names)):
                raise InputError(
                    f"ElasticShaft: {k} = {v!r} must hold {len(names)} numbers, one per "
                    "take_off point"
                )
            vals = tuple(positive(f"ElasticShaft: {k}[{i}]", x, unit) for i, x in enumerate(v))
            object.__setattr__(self, k, vals)
        z = finite_number("ElasticShaft: damping_ratio", self.damping_ratio, "", low=0.0)
        object.__setattr__(self, "damping_ratio", z)
        if not isinstance(self.links, Mapping) or not all(
            isinstance(k, str) and isinstance(v, LinkSpec) for k, v in self.links.items()
        ):
            raise InputError(f"ElasticShaft: links = {self.links!r} must map names to LinkSpec")
        object.__setattr__(self, "links", dict(self.links))

    @classmethod
    def from_tables(cls, shaft: Any, links: Any, source: str) -> ElasticShaft:
        """The elastic shaft of ``[drive.shaft]`` and the ``[drive.link.<name>]`` tables.

        Parameters
        ----------
        shaft : Mapping
            ``[drive.shaft]`` as read.
        links : Mapping
            ``[drive.link]`` as read: a table per mechanism.
        source : str
            The file's name, for messages.

        Returns
        -------
        ElasticShaft

        Raises
        ------
        InputError
            Naming the file, the table and the key: an unknown key, a missing one,
            arrays of other lengths than ``take_off``, a value out of range.

        Examples
        --------
        >>> try:
        ...     ElasticShaft.from_tables({"take_off": ["a"], "stiffness_nm_per_rad": [-1.0],
        ...                               "hub_inertia_kg_m2": [0.1]}, {}, "m.toml")
        ... except InputError as e:
        ...     print(e)
        m.toml: [drive.shaft]: stiffness_nm_per_rad #1 = -1.0 must be a finite number > 0 [N·m/rad]
        """
        where = f"{source}: [drive.shaft]"
        _toml.must_be_table(shaft, source, "[drive.shaft]")
        _toml.check_keys(shaft, SHAFT_KEYS, source, "[drive.shaft]")
        for k in ("take_off", "stiffness_nm_per_rad", "hub_inertia_kg_m2"):
            if k not in shaft:
                raise InputError(f"{where}: {k} is missing (one per take-off point)")
        names = shaft["take_off"]
        if not (isinstance(names, list) and names and all(isinstance(x, str) for x in names)):
            raise InputError(
                f"{where}: take_off = {names!r} must be a non-empty array of mechanism names, "
                "in order from the motor's end"
            )
        if len(set(names)) != len(names):
            raise InputError(f"{where}: take_off = {names!r} names a mechanism twice")
        arrays = {}
        for k, unit in (("stiffness_nm_per_rad", "[N·m/rad]"), ("hub_inertia_kg_m2", "[kg·m²]")):
            v = shaft[k]
            if not (isinstance(v, list) and len(v) == len(names)):
                raise InputError(
                    f"{where}: {k} = {v!r} must be an array of {len(names)} numbers, one per "
                    "take_off point"
                )
            for i, x in enumerate(v):
                if not (_toml.is_number(x) and math.isfinite(x) and x > 0):
                    raise InputError(
                        f"{where}: {k} #{i + 1} = {x!r} must be a finite number > 0 {unit}"
                    )
            arrays[k] = tuple(float(x) for x in v)
        zeta = shaft.get("damping_ratio", 0.02)
        if not (_toml.is_number(zeta) and math.isfinite(zeta) and zeta >= 0):
            raise InputError(f"{where}: damping_ratio = {zeta!r} must be a finite number ≥ 0")
        _keyrules.check(shaft, DAMPING_RULES, where)
        _toml.must_be_table(links, source, "[drive.link]")
        specs = {name: _link(name, t, source) for name, t in links.items()}
        for name in specs:
            if name not in names:
                raise InputError(
                    f"{source}: [drive.link.{name}]: {name!r} is not a take_off point of "
                    f"[drive.shaft] ({', '.join(names)})"
                )
        return cls(
            tuple(names),
            arrays["stiffness_nm_per_rad"],
            arrays["hub_inertia_kg_m2"],
            float(zeta),
            specs,
        )


def _link(name: str, t: Any, source: str) -> LinkSpec:
    """One ``[drive.link.<name>]`` table, checked."""
    where = f"{source}: [drive.link.{name}]"
    _toml.must_be_table(t, source, f"[drive.link.{name}]")
    _toml.check_keys(t, LINK_KEYS, source, f"[drive.link.{name}]")
    for k, v in t.items():
        if not (_toml.is_number(v) and (v > 0 or (k == "damping_ratio" and v == 0))):
            raise InputError(
                f"{where}: {k} = {v!r} must be a number > 0"
                + (" (or 0)" if k == "damping_ratio" else "")
            )
        if k != "frequency_hz" and not math.isfinite(v):
            raise InputError(f"{where}: {k} = {v!r} must be finite")
    if "max_error_m" in t and "max_error_deg" in t:
        raise InputError(f"{where}: give max_error_m or max_error_deg, not both")
    _keyrules.check(t, DAMPING_RULES, where)
    return LinkSpec(
        float(t.get("frequency_hz", math.inf)),
        float(t.get("damping_ratio", 0.05)),
        None if "max_error_m" not in t else float(t["max_error_m"]),
        None if "max_error_deg" not in t else float(t["max_error_deg"]),
    )


def _shown(value: float, unit: str, digits: int = 4) -> str:
    """A dynamic error [m or rad] as the report writes it: in mm or degrees.

    Parameters
    ----------
    value : float
        The error [m] or [rad]; not finite: "—".
    unit : str
        "m" or "rad".
    digits : int, default 4
        Significant digits.

    Returns
    -------
    str
        The text.

    Examples
    --------
    >>> _shown(2.143e-4, "m"), _shown(0.00117, "rad", 3)
    ('0.2143 mm', '0.067°')
    """
    if not math.isfinite(value):
        return "—"
    if unit == "m":
        return f"{value * 1e3:.{digits}g} mm"
    return f"{math.degrees(value):.{digits}g}°"


def _phased(rows: Array, phase_deg: float) -> Array:
    """Each row of a mechanism's own-grid curve at the main shaft's angles (the same
    Rust shift as the torque's)."""
    z = np.zeros((1, rows.shape[1]))
    return np.vstack([ShaftTorque.from_curves(r[None], z, [phase_deg]).per_omega2 for r in rows])


def _bound(spec: LinkSpec, unit: str, name: str, source: str) -> float | None:
    """The member's bound in its own unit, or an error for a unit it has not."""
    if spec.max_error_m is not None:
        if unit != "m":
            raise InputError(
                f"{source}: [drive.link.{name}]: max_error_m bounds a member that travels; "
                f"{name!r}'s turns: give max_error_deg"
            )
        return spec.max_error_m
    if spec.max_error_deg is not None:
        if unit != "rad":
            raise InputError(
                f"{source}: [drive.link.{name}]: max_error_deg bounds a member that turns; "
                f"{name!r}'s travels: give max_error_m"
            )
        return math.radians(spec.max_error_deg)
    return None


def _check_travel(bound: float | None, pos: Array, unit: str, name: str, source: str) -> None:
    """Refuse a bound as large as the member's whole travel (the extent of its
    positions over the cycle): it cannot bind, so it cannot be meant — likelier a
    bound in millimetres given as metres."""
    if bound is None:
        return
    travel = float(np.hypot.reduce(np.ptp(pos, axis=1)))
    if bound < travel:
        return
    key, scale, u = (
        ("max_error_m", 1.0, "m") if unit == "m" else ("max_error_deg", 180 / math.pi, "°")
    )
    hint = f" — did you give millimetres ({key} = {bound / 1000:g})?" if unit == "m" else ""
    raise InputError(
        f"{source}: [drive.link.{name}]: {key} = {bound * scale:g} {u} is as large as "
        f"{name!r}'s whole travel over the cycle ({travel * scale:.4g} {u}): such a bound "
        f"cannot bind, so it cannot be meant{hint}"
    )


def _nodes(result: Any, elastic: ElasticShaft, source: str) -> list[ShaftNode]:
    """The chain's nodes of an analysed machine."""
    shaft = result.shaft
    on = list(shaft.parts)
    missing = [k for k in on if k not in elastic.take_off]
    extra = [k for k in elastic.take_off if k not in on]
    if missing or extra:
        raise InputError(
            f"{source}: [drive.shaft]: take_off = {list(elastic.take_off)} must list every "
            f"mechanism on the main shaft ({', '.join(on)}) and no other"
            + (f"; missing {', '.join(missing)}" if missing else "")
            + (f"; not on the shaft: {', '.join(extra)}" if extra else "")
        )
    nodes = []
    for k, name in enumerate(elastic.take_off):
        mech = result.mechanisms[name]
        part = shaft.parts[name]
        phase = shaft.phases_deg[name]
        got = mech.shaft_inertia()
        j = np.zeros(part.static.size) if got is None else _phased(got[0][None], phase)[0]
        hub, c = elastic.hub_inertia_kg_m2[k], elastic.stiffness_nm_per_rad[k]
        damping = 2.0 * elastic.damping_ratio * math.sqrt(c * (hub + float(j.mean())))
        member = None
        wm = getattr(mech, "working_member", None)
        w = None if wm is None else wm()
        if w is not None:
            spec = elastic.links.get(name, LinkSpec())
            pos, d1, d2 = (_phased(a, phase) for a in w[:3])
            bound = _bound(spec, w[3], name, source)
            _check_travel(bound, pos, w[3], name, source)
            member = WorkingMember(pos, d1, d2, w[3], spec.frequency_hz, spec.damping_ratio, bound)
        elif name in elastic.links:
            raise InputError(
                f"{source}: [drive.link.{name}]: {name!r} has no working member to put on a link"
            )
        nodes.append(
            ShaftNode(name, j, 2.0 * part.per_omega2, part.static, hub, c, damping, member)
        )
    return nodes


@dataclass(frozen=True)
class MachineTorsion:
    """The dynamic errors of an analysed machine on its elastic shaft and links.

    Built by :func:`machine_torsion`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    nodes : tuple of ShaftNode
        The chain.
    nominal : Torsion or None
        The steady state under the drive's motor with the steady state's flywheel
        (None when the motor has no steady state or the chain none: ``problem``).
    sweep : TorsionSweep
        The peak errors and twists at the machine's speeds, the head at constant
        speed.
    limits_rpm : dict of str to float
        Each bounded member's speed at which its error first reaches its bound:
        the sweep's first crossing (:meth:`TorsionSweep.limit_rpm`) put to a root
        (Brent's method, 1e-9 relative; inf: not in the speed range).
    nominal_rpm : float
        The machine's nominal speed [rpm].
    problem : str
        Why there is no ``nominal`` ("" when there is).
    event_lags_deg : dict of str to dict of str to float
        For each take-off point, how late its mechanism's events happen under the
        motor [deg]: the node's twist at each event's angle in the optimum, for the
        events of the operations it performs (``mechanism`` of an operation) and
        the operations whose bounds it sets, and the event its ``phase`` follows.
        Empty without a steady state.
    working_rpm : float, default inf
        The machine's speed limit before its dynamic errors lower it [rpm]: a sweep
        speed above it is outside the speeds the machine can run at, so a chain that
        does not settle there is no failure (its errors stay NaN in the sweep).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> r.torsion.failures()
    []
    """

    nodes: tuple[ShaftNode, ...]
    nominal: Torsion | None
    sweep: TorsionSweep
    limits_rpm: dict[str, float]
    nominal_rpm: float
    problem: str = ""
    event_lags_deg: dict[str, dict[str, float]] = field(default_factory=dict)
    working_rpm: float = math.inf

    def bounds(self) -> dict[str, float]:
        """Each bounded member's largest dynamic error allowed [its unit].

        Returns
        -------
        dict of str to float
            The bound by mechanism [m or rad].

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.torsion.bounds()
        {'knife': 0.001}
        """
        return {
            x.name: x.member.max_error
            for x in self.nodes
            if x.member is not None and x.member.max_error is not None
        }

    def nominal_units(self) -> dict[str, str]:
        """Each working member's unit ("m" or "rad"), by mechanism.

        Returns
        -------
        dict of str to str
            The unit by mechanism.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.torsion.nominal_units()
        {'knife': 'm'}
        """
        return {x.name: x.member.unit for x in self.nodes if x.member is not None}

    def limit_reason(self, name: str) -> str:
        """Why member ``name``'s error limits the speed, in words (the machine's
        speed limit names it so).

        Parameters
        ----------
        name : str
            A take-off point whose member has a bound.

        Returns
        -------
        str
            The reason.

        Raises
        ------
        InputError
            If ``name`` has no bounded member.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.torsion.limit_reason("knife")
        'its dynamic error on the elastic shaft and link reaches max_error = 1 mm ([drive.link])'
        """
        instance("name", name, str)
        bounds = self.bounds()
        if name not in bounds:
            raise InputError(
                f"limit_reason: {name!r} has no bounded member; those with one: {list(bounds)}"
            )
        b = _shown(bounds[name], self.nominal_units()[name])
        return (
            f"its dynamic error on the elastic shaft and link reaches max_error = {b} "
            "([drive.link])"
        )

    def failures(self) -> list[str]:
        """What fails: a chain with no steady state (under the motor, or at a speed of
        the sweep), a member's error at the nominal
        speed under the motor above its bound, or above it at every speed of the
        range. (An error-limited speed below the nominal speed lowers the machine's
        speed limit, whose check says so:
        :attr:`cyclomech.machine.MachineResult.above_speed_limit`.)

        Returns
        -------
        list of str
            One line per failure (empty when nothing fails).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.torsion.failures()
        []
        """
        out = []
        if self.problem:
            out.append(f"the elastic main shaft: {self.problem}")
        bad = self.sweep.rpm[~self.sweep.settled & (self.sweep.rpm <= self.working_rpm)]
        if bad.size:
            out.append(
                f"the elastic main shaft did not settle at {bad.size} of the "
                f"{self.sweep.rpm.size} speeds of the sweep ({bad.min():g}–{bad.max():g} rpm): "
                "its errors there are unknown (NaN); give the shaft or the links some damping"
            )
        units = self.nominal_units()
        for name, bound in self.bounds().items():

            def show(v: float, unit: str = units[name]) -> str:
                return _shown(v, unit)

            if self.nominal is not None and self.nominal.peak_error[name] > bound:
                out.append(
                    f"{name}: its dynamic error under the motor reaches "
                    f"{show(self.nominal.peak_error[name])} > max_error {show(bound)}: a "
                    "stiffer shaft or link, or a lower speed"
                )
            lim = self.limits_rpm.get(name, math.inf)
            if lim <= self.sweep.rpm[0]:
                out.append(
                    f"{name}: its dynamic error exceeds max_error {show(bound)} at every speed "
                    f"of the speed range (from {self.sweep.rpm[0]:g} rpm)"
                )
        return out

    def line(self) -> str:
        """One line for the CLI: each member's peak dynamic error under the motor and
        the speed at which it reaches its bound.

        Returns
        -------
        str
            The line.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.torsion.line()[:30]
        'Elastic shaft: dynamic error o'
        """
        if self.nominal is None:
            return f"Elastic shaft: no steady state ({self.problem})"
        parts = []
        for x in self.nodes:
            m = x.member
            if m is None:
                continue
            txt = f"{x.name} {_shown(self.nominal.peak_error[x.name], m.unit, 3)}"
            lim = self.limits_rpm.get(x.name)
            if lim is not None:
                txt += (
                    " (bound reached "
                    + ("above the speed range" if math.isinf(lim) else f"at {lim:.2f} rpm")
                    + ")"
                )
            parts.append(txt)
        return (
            "Elastic shaft: dynamic error of " + "; ".join(parts)
            if parts
            else "Elastic shaft: no working member"
        )

    def json(self) -> dict[str, Any]:
        """The ``torsion`` group of ``results.json``.

        Returns
        -------
        dict
            The nominal speed, the mean speed under the motor, the problem, the
            sweep's range and one entry per take-off point (JSON types).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> sorted(r.torsion.json()["nodes"][0])[:3]
        ['damping_nm_s_per_rad', 'error_limited_rpm', 'event_lag_deg']
        """
        t = self.nominal
        rows = []
        for k, x in enumerate(self.nodes):
            m = x.member
            rows.append(
                {
                    "mechanism": x.name,
                    "stiffness_nm_per_rad": x.stiffness_nm_per_rad,
                    "hub_inertia_kg_m2": x.hub_inertia_kg_m2,
                    "damping_nm_s_per_rad": x.damping_nm_s_per_rad,
                    "max_twist_deg": None
                    if t is None
                    else float(np.degrees(np.abs(t.twist_rad[k]).max())),
                    "member_unit": None if m is None else m.unit,
                    "link_frequency_hz": None
                    if m is None or math.isinf(m.frequency_hz)
                    else m.frequency_hz,
                    "peak_error": None if t is None or m is None else t.peak_error[x.name],
                    "max_error": None if m is None else m.max_error,
                    "error_limited_rpm": None
                    if x.name not in self.limits_rpm or math.isinf(self.limits_rpm[x.name])
                    else self.limits_rpm[x.name],
                    "event_lag_deg": self.event_lags_deg.get(x.name, {}),
                }
            )
        return {
            "nominal_rpm": self.nominal_rpm,
            "mean_rpm": None if t is None else t.mean_rpm,
            "problem": self.problem,
            "sweep_rpm": [
                float(self.sweep.rpm[0]),
                float(self.sweep.rpm[-1]),
                int(self.sweep.rpm.size),
            ],
            "nodes": rows,
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """The report's table: one row per take-off point.

        Returns
        -------
        tuple of (list of str, list of list)
            The header and the rows.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.torsion.table()[0][:3]
        ['take-off', 'stiffness [N·m/rad]', 'largest twist [deg]']
        """
        head = [
            "take-off",
            "stiffness [N·m/rad]",
            "largest twist [deg]",
            "link [Hz]",
            "peak dynamic error",
            "bound",
            "error reaches the bound at [rpm]",
            "latest event [deg]",
        ]
        rows = []
        for k, x in enumerate(self.nodes):
            m, t = x.member, self.nominal

            def show(v: float | None, m: WorkingMember | None = m) -> str:
                return "—" if v is None or m is None else _shown(v, m.unit)

            lim = self.limits_rpm.get(x.name)
            rows.append(
                [
                    x.name,
                    f"{x.stiffness_nm_per_rad:.4g}",
                    "—" if t is None else f"{np.degrees(np.abs(t.twist_rad[k]).max()):.4g}",
                    "rigid" if m is None or math.isinf(m.frequency_hz) else f"{m.frequency_hz:g}",
                    show(None if t is None or m is None else t.peak_error[x.name]),
                    show(None if m is None else m.max_error),
                    "—"
                    if lim is None
                    else ("above the range" if math.isinf(lim) else f"{lim:.2f}"),
                    _latest(self.event_lags_deg.get(x.name, {})),
                ]
            )
        return head, rows

    def figure(self) -> Any:
        """The dynamic errors and twists over the cycle at the nominal speed under the
        motor (None without a steady state).

        Returns
        -------
        matplotlib.figure.Figure or None
            ``plot_torsion``'s figure (:mod:`cyclomech.plot`).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> fig = r.torsion.figure()
        >>> len(fig.axes)
        2
        """
        from .plot import plot_torsion

        return None if self.nominal is None else plot_torsion(self.nominal)


def machine_torsion(result: Any, elastic: ElasticShaft, steady: Any, motor: Any) -> MachineTorsion:
    """The dynamic errors of an analysed machine on its elastic shaft and links.

    At the nominal speed under ``motor`` with the head's inertia of ``steady`` (the
    rigid steady state: its flywheel and rotor, and its speed at the first angle as
    the start); and over the machine's speed range (its ``speed_grid``) with the head
    at constant speed, each mechanism at its phase in the nominal optimum (the
    phases move with the speed: the sweep takes the nominal's), for the speed at
    which each bounded member's error first reaches its bound.

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result, with its main shaft.
    elastic : ElasticShaft
        The shaft and the links.
    steady : SteadyState or None
        The rigid machine's steady state under ``motor`` (None: no nominal run).
    motor : Motor
        The drive's motor.

    Returns
    -------
    MachineTorsion

    Raises
    ------
    InputError
        If ``take_off`` does not list the mechanisms on the main shaft, or a bound
        has the wrong unit for its member.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> t = machine_torsion(r, r.machine.drive.elastic, r.dynamics.steady, r.machine.drive.motor)
    >>> t.nominal.names
    ('knife',)
    """
    _check_result(result, elastic)
    instance("motor", motor, Motor)
    if steady is not None:
        instance("steady", steady, SteadyState)
    source = result.machine.source
    nodes = _nodes(result, elastic, source)
    nominal, problem = None, ""
    if steady is None:
        problem = "the motor has no steady state"
    else:
        try:
            nominal = torsion(
                nodes,
                motor=motor,
                head_inertia_kg_m2=steady.constant_inertia_kg_m2,
                start_rpm=float(steady.omega[0]) / RAD_PER_S_PER_RPM,
                tol=_TOL,
                max_cycles=_MAX_CYCLES,
            )
        except SolverError as e:
            problem = str(e)
    sweep, limits = _error_limits(result, nodes)
    lags = {} if nominal is None else _event_lags(result, nominal)
    top = float(getattr(getattr(result, "limit", None), "rpm", math.inf))
    return MachineTorsion(
        tuple(nodes), nominal, sweep, limits, float(result.nominal_rpm), problem, lags, top
    )


def _error_limits(
    result: Any, nodes: list[ShaftNode], below: float = math.inf
) -> tuple[TorsionSweep, dict[str, float]]:
    """The chain's sweep over the machine's speed range with the head at constant
    speed, and each bounded member's speed at which its error first reaches its
    bound (inf: not in the range).

    With ``below`` [rpm], the sweep stops at its first speed ≥ ``below``: a limit
    under ``below`` is the same (the first crossing depends on the speeds up to
    it alone), one above is inf. For a caller that takes min(``below``, limit)
    (the sensitivities' variants) the answers are those of the whole sweep."""
    full = np.asarray(result.machine.speed_grid(), dtype=np.float64)
    # 41 speeds at most: the first crossing is found on them, then put to a root
    grid = np.linspace(full[0], full[-1], min(full.size, 41))
    grid = grid[: int(np.searchsorted(grid, below, side="left")) + 1]
    sweep = torsion_sweep(nodes, grid, tol=_TOL, max_cycles=_MAX_CYCLES)
    limits = {
        x.name: _error_limit(nodes, sweep, x.name, x.member.max_error)
        for x in nodes
        if x.member is not None and x.member.max_error is not None
    }
    return sweep, limits


#: The dynamic-error speed limit's root, relative (Brent's method between the two
#: sweep speeds that bracket the first crossing).
LIMIT_RTOL = 1e-9


def _error_limit(nodes: list[ShaftNode], sweep: TorsionSweep, name: str, bound: float) -> float:
    """The speed [rpm] at which member ``name``'s peak error first reaches ``bound``:
    the sweep's first crossing (:meth:`TorsionSweep.limit_rpm`: the first from
    below, from the lowest speed up), put to a root of (peak error − bound) between
    the two sweep speeds that bracket it, each evaluation one constant-speed solve
    of the chain (a speed where it does not settle counts as exceeding, as in the
    sweep). The sweep's straight line between them was off by 0.1 % of the speed
    on the knife cutter with a 0.2 mm bound. Where the crossing is the sweep's
    first speed, or one where the chain did not settle, that speed stays."""
    from scipy.optimize import brentq

    i = sweep.first_over(name, bound)
    if i is None or i == 0 or not sweep.settled[i]:
        return sweep.limit_rpm(name, bound)
    k = sweep.names.index(name)

    lo, hi = float(sweep.rpm[i - 1]), float(sweep.rpm[i])
    e_lo, e_hi = float(sweep.peak_error[i - 1, k] - bound), float(sweep.peak_error[i, k] - bound)
    if not e_lo < 0.0 < e_hi:  # at the bound at lo already
        return lo

    def excess(rpm: float) -> float:
        if rpm in (lo, hi):  # the sweep solved the bracket's ends already
            return e_lo if rpm == lo else e_hi
        s = torsion_sweep(nodes, [rpm], tol=_TOL, max_cycles=_MAX_CYCLES, n_threads=1)
        # an unsettled chain exceeds (a finite value keeps Brent's bracket sound)
        return float(s.peak_error[0, k] - bound) if s.settled[0] else bound

    return float(brentq(excess, lo, hi, rtol=LIMIT_RTOL))


def error_limits(
    result: Any, elastic: ElasticShaft, *, below_rpm: float = math.inf
) -> dict[str, float]:
    """Each bounded member's dynamic-error speed limit [rpm] of an analysed machine on
    another elastic shaft and links: what :func:`machine_torsion` gives as
    ``limits_rpm``, without its nominal run under the motor (the sensitivities of
    the limit to the drive's keys vary ``elastic`` alone).

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result, with its main shaft.
    elastic : ElasticShaft
        The shaft and the links.
    below_rpm : float, default inf
        Only limits below this speed [rpm] are sought: the sweep stops at its
        first speed ≥ ``below_rpm`` (a first crossing depends on the speeds up to
        it alone), and a limit above is inf. min(``below_rpm``, limit) is that of
        the whole sweep, in fewer solves of the chain (the sensitivities take
        it with the machine's limit).

    Returns
    -------
    dict of str to float
        The limit by mechanism [rpm] (inf: its error stays within its bound over
        the speed range, or, with ``below_rpm``, does not reach it below that).

    Raises
    ------
    InputError
        As :func:`machine_torsion`.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> error_limits(r, r.machine.drive.elastic) == r.torsion.limits_rpm
    True
    >>> tight = r.machine.with_values({"drive.link.knife.max_error_m": 2e-4}).drive.elastic
    >>> round(error_limits(r, tight)["knife"], 2), error_limits(r, tight, below_rpm=30.0)
    (37.45, {'knife': inf})
    """
    _check_result(result, elastic)
    below = finite_number(
        "below_rpm", below_rpm, "[rpm] (inf: the whole range)", low=0.0, strict=True, inf=True
    )
    nodes = _nodes(result, elastic, result.machine.source)
    return _error_limits(result, nodes, below)[1]


def _check_result(result: Any, elastic: Any) -> None:
    """Refuse what is not an analysed machine with a main shaft, or not an
    :class:`ElasticShaft`."""
    if not all(hasattr(result, k) for k in ("machine", "shaft", "mechanisms", "optimum")):
        raise InputError(
            f"result must be a machine's result (cyclomech.machine.analyze); got "
            f"{type(result).__name__}"
        )
    instance("elastic", elastic, ElasticShaft)
    if result.shaft is None:
        raise InputError("result: nothing loads the main shaft: no chain to put on it")


def _event_lags(result: Any, t: Torsion) -> dict[str, dict[str, float]]:
    """Each node's twist [deg] at the optimum's angle of each event of its own: the
    operations whose ``mechanism`` it is or whose bounds it sets, and the event its
    phase follows."""
    opt = result.optimum
    if opt is None:
        return {}
    cg = result.machine.cyclogram
    out = {}
    for name in t.names:
        mech = result.machine.mechanisms[name]
        own = [e for o in cg.operations if o.mechanism == name for e in o.arc]
        own += [e for b in mech.bounds() for e in b.arc]  # the operations it bounds
        phase = getattr(getattr(mech, "phase", None), "event", None)
        if phase is not None:
            own.append(phase)
        events = [e for e in cg.events if e in set(own) and e in opt.times]
        at = t.lag_deg(name, [opt.times[e] for e in events]) if events else np.zeros(0)
        out[name] = {e: float(v) for e, v in zip(events, at, strict=True)}
    return out


def _latest(lags: Mapping[str, float]) -> str:
    """The report's cell: the event its node's twist delays most."""
    if not lags:
        return "—"
    e = max(lags, key=lambda k: abs(lags[k]))
    return f"{e}: {lags[e]:+.4g}"
