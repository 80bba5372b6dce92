"""The whole machine: `_model` part of :mod:`cyclomech.machine` (its door)."""

from __future__ import annotations

import copy
import difflib
import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from .. import _toml
from .._arrays import count, real, threads_arg
from .._errors import CyclomechWarning, InfeasibleError, InputError
from .._units import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM
from ..cyclogram import Arc, Constraint, Cyclogram, Optimum, max_difference
from ..impact import StopImpact, max_impact_speeds, min_phase_angles, rebounds
from ..impact._study import _STOP_KEYS
from ..linkage import Linkage, LinkageSolution
from ..linkage._file import _LINKAGE_KEYS
from ..press import STATUS, GearLeverPress, PressCriteria
from ..transfer import TransferPath, design_transfer

__all__ = [
    "SCHEMA",
    "CamStop",
    "LinkageMechanism",
    "Machine",
    "Mechanism",
    "PressMechanism",
    "SpeedLimit",
    "SpeedSweep",
    "TransferMechanism",
    "check_parameter",
    "speed_limits",
    "speed_sweeps",
]

Array = npt.NDArray[np.float64]

#: Version of the layout of ``results.json`` and of sweep files.
SCHEMA = "cyclomech.machine/1"

#: Highest speed searched for a speed limit [rpm]; above it the machine is unlimited.
_SPEED_CAP_RPM = 1e6
#: Lowest speed searched [rpm]: a cyclogram that does not fit there fits at no speed
#: (its time-bound and rebound bounds only shrink as the speed falls).
_SPEED_FLOOR_RPM = 1e-6
_MACHINE_KEYS = {"name", "speed_rpm", "speed_points", "nominal_rpm", "angle_points"}
_KINDS = ("cam_stop", "linkage", "press", "transfer")
_CAM_KEYS = (_STOP_KEYS - {"name"}) | {"kind", "arc", "a_max", "phase_deg"}
_LINKAGE_EXTRA = {"kind", "max_acceleration"}
_PRESS_KEYS = {
    "kind",
    "R",
    "r",
    "d",
    "L",
    "phi0_deg",
    "offset",
    "k_Sp",
    "working_stroke",
    "max_V_np",
}
_TRANSFER_KEYS = {
    "kind",
    "R_t",
    "R_p",
    "gap",
    "pockets_t",
    "pockets_p",
    "x2",
    "max_jerk",
    "max_acceleration",
}


# --------------------------------------------------------------------- mechanisms
@dataclass(frozen=True)
class CamStop:
    """A cam-driven lever that hits a limit stop (seed 000), and the operation
    ``arc`` of the cyclogram that brings it there: at n rpm that operation's phase
    angle must keep the first rebound within ``a_max`` [m]. ``phase_deg`` are the
    phase angles [deg] drawn in the report's rebound curves."""

    #: The ``kind`` of its table in a machine file.
    kind: ClassVar[str] = "cam_stop"
    name: str
    stop: StopImpact
    arc: Arc
    a_max: float
    phase_deg: Array

    def min_phase_deg(self, rpm: npt.ArrayLike, *, n_threads: int | None = None) -> Array:
        """Exact smallest phase angle [deg] of the arc at each speed ``rpm``
        (:meth:`StopImpact.min_phase_angle`; NaN where even 360° is too short).

        >>> import cyclomech as cm
        >>> lifter = cm.Machine.example().mechanisms["lifter"]
        >>> round(float(lifter.min_phase_deg(280.0)), 4)
        28.0271
        """
        return np.asarray(
            self.stop.min_phase_angle(self.a_max, rpm, n_threads=n_threads), dtype=np.float64
        )

    def linear_min_phase_deg(
        self, rpm: npt.ArrayLike, *, points: int = 64, n_threads: int | None = None
    ) -> Array:
        """The seed's linearised form at each speed ``rpm`` [deg]: the rebound fitted
        by a line slope·t + intercept over 0.5…2 times the exact angle (as
        :meth:`StopImpact.constraint` with ``linear=True``), then t ≥ (a_max −
        intercept)/slope. One rebound call for all speeds.

        >>> import cyclomech as cm
        >>> lifter = cm.Machine.example().mechanisms["lifter"]
        >>> round(float(lifter.linear_min_phase_deg(280.0)), 2)     # exact: 28.03
        32.67
        """
        points = count("points", points, low=2, high=1_000_000)
        n = _speeds("rpm", rpm).reshape(np.shape(rpm) or (1,))
        exact = self.min_phase_deg(n, n_threads=n_threads)
        ok = np.isfinite(exact)
        out = np.full(n.shape, np.nan)
        if not ok.any():
            return out.reshape(np.shape(rpm))
        lo = 0.5 * exact[ok]
        hi = np.minimum(2.0 * exact[ok], 360.0)
        s = np.linspace(0.0, 1.0, points)
        t = lo[:, None] + (hi - lo)[:, None] * s[None, :]
        a = self.stop.rebound(n[ok][:, None], t, n_threads=n_threads)
        # Least squares per row, in closed form (np.polyfit row by row).
        tm, am = t.mean(axis=1, keepdims=True), a.mean(axis=1, keepdims=True)
        slope = ((t - tm) * (a - am)).sum(axis=1) / ((t - tm) ** 2).sum(axis=1)
        intercept = am[:, 0] - slope * tm[:, 0]
        out[ok] = (self.a_max - intercept) / slope
        return out.reshape(np.shape(rpm))

    def constraint(self, rpm: float) -> Constraint:
        """The exact cyclogram constraint at ``rpm``, named ``rebound[<name>]``.

        >>> import cyclomech as cm
        >>> cm.Machine.example().mechanisms["lifter"].constraint(280.0).describe()
        '1·t(3,7) >= 28.0271'
        """
        c = self.stop.constraint(self.arc, self.a_max, rpm)
        return Constraint(c.coeffs, c.sense, c.rhs, f"rebound[{self.name}]")


@dataclass(frozen=True)
class LinkageMechanism:
    """A planar linkage driven by the main shaft (one crank turn per machine
    cycle); ``output`` is the point whose motion is reported, and
    ``max_acceleration`` [m/s²] an optional limit on its acceleration."""

    #: The ``kind`` of its table in a machine file.
    kind: ClassVar[str] = "linkage"
    name: str
    linkage: Linkage
    output: str
    max_acceleration: float | None = None
    #: Crank angles per turn (the machine's ``angle_points``): the grid of
    #: :meth:`solve`, :meth:`peaks` and :meth:`speed_limit_rpm` unless given another.
    points: int = 361
    _peaks: dict[int, tuple[float, float]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    def solve(self, points: int | None = None) -> LinkageSolution:
        """The mechanism over one crank turn from its drawn angle, ``points``
        angles (default :attr:`points`; the last one repeats the first).

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> bool(m.mechanisms["knife"].solve(73).ok.all())
        True
        """
        n = self.points if points is None else points
        angles = self.linkage.drawn_angle + np.linspace(0.0, 2.0 * math.pi, n)
        return self.linkage.solve(angles)

    def peaks(self, points: int | None = None) -> tuple[float, float]:
        """Largest |d xy/dφ| [m/rad] and |d² xy/dφ²| [m/rad²] of the output point
        over the turn (``points`` angles, default :attr:`points`; computed once per
        grid): at constant crank speed ω its speed and acceleration peak at ω and
        ω² times these.

        >>> import cyclomech as cm
        >>> v, a = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"].peaks()
        >>> v > 0 and a > 0
        True
        """
        n = self.points if points is None else points
        if n in self._peaks:
            return self._peaks[n]
        sol = self.solve(n)
        if not sol.ok.all():
            bad = np.degrees(sol.angles[~sol.ok])
            raise InputError(
                f"mechanism {self.name!r}: the linkage cannot be assembled at crank angles "
                f"{', '.join(f'{v:.1f}' for v in bad[:6])}{' …' if bad.size > 6 else ''} "
                "degrees; it must turn through a whole revolution in a machine"
            )
        assert sol.vel is not None and sol.acc is not None
        k = sol.index(self.output)
        self._peaks[n] = (
            float(np.nanmax(np.hypot(*sol.vel[:, k].T))),
            float(np.nanmax(np.hypot(*sol.acc[:, k].T))),
        )
        return self._peaks[n]

    def speed_limit_rpm(self, points: int | None = None) -> float:
        """Speed [rpm] at which the output point's peak acceleration over
        ``points`` crank angles (default :attr:`points`) reaches
        ``max_acceleration`` (inf without a limit): ω² · max|d² xy/dφ²|.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"]
        >>> round(m.speed_limit_rpm()) > 0
        True
        """
        if self.max_acceleration is None:
            return math.inf
        _, acc = self.peaks(points)
        return math.sqrt(self.max_acceleration / acc) / RAD_PER_S_PER_RPM

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`: the criterion and its limit.

        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"].limit_reason()
        "the peak acceleration of point 'E' reaches max_acceleration = 8 m/s²"
        """
        if self.max_acceleration is None:
            return ""
        return (
            f"the peak acceleration of point {self.output!r} reaches max_acceleration = "
            f"{self.max_acceleration:g} m/s²"
        )


@dataclass(frozen=True)
class PressMechanism:
    """A gear-lever press drive whose crank turns once per machine cycle; the
    working stroke is ``k_Sp``·S_n or ``working_stroke`` [m]; ``max_V_np`` [m/s]
    optionally limits the slider's speed at the start of the working stroke."""

    #: The ``kind`` of its table in a machine file.
    kind: ClassVar[str] = "press"
    name: str
    press: GearLeverPress
    k_Sp: float | None = None
    working_stroke: float | None = None
    max_V_np: float | None = None

    def criteria(self, rpm: float) -> PressCriteria:
        """The working-stroke criteria at ``rpm`` (:meth:`GearLeverPress.criteria`).

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> round(m.mechanisms["drive"].criteria(40.0).S_n, 4)
        0.1276
        """
        return self.press.criteria(
            omega=float(rpm) * RAD_PER_S_PER_RPM, k_Sp=self.k_Sp, working_stroke=self.working_stroke
        )

    def speed_limit_rpm(self) -> float:
        """Speed [rpm] at which V_np reaches ``max_V_np`` (V_np grows as n; inf
        without a limit).

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> round(m.mechanisms["drive"].speed_limit_rpm(), 1)
        54.8
        """
        if self.max_V_np is None:
            return math.inf
        c = self.criteria(1.0)
        if not c.ok:
            raise InputError(
                f"mechanism {self.name!r}: the press design does not work ({c.status})"
            )
        return self.max_V_np / c.V_np if c.V_np > 0 else math.inf

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`: the criterion and its limit.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> m.mechanisms["drive"].limit_reason()
        'V_np (the slider speed where the working stroke starts) reaches max_V_np = 5 mm/s'
        """
        if self.max_V_np is None:
            return ""
        return (
            "V_np (the slider speed where the working stroke starts) reaches "
            f"max_V_np = {1e3 * self.max_V_np:g} mm/s"
        )


@dataclass(frozen=True)
class TransferMechanism:
    """A transfer between a transfer rotor (pitch radius R_t, ``pockets_t``
    pockets) and a process rotor (R_p, ``pockets_p``): each turns one pocket per
    machine cycle, so at n rpm the peripheral speeds are V = 2π·R·n/(60·pockets)
    [m/s]. Optional limits on the workpiece's peak jerk [m/s³] and acceleration
    [m/s²]."""

    #: The ``kind`` of its table in a machine file.
    kind: ClassVar[str] = "transfer"
    name: str
    path: TransferPath
    pockets_t: int
    pockets_p: int
    max_jerk: float | None = None
    max_acceleration: float | None = None

    def speeds(self, rpm: float) -> tuple[float, float]:
        """Peripheral speeds (V_t, V_p) [m/s] at ``rpm``.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml").mechanisms["line"]
        >>> [round(v, 4) for v in m.speeds(60.0)]
        [0.1178, 0.1309]
        """
        w = float(_speeds("rpm", rpm)[0]) * RAD_PER_S_PER_RPM
        return (w * self.path.R_t / self.pockets_t, w * self.path.R_p / self.pockets_p)

    def peaks(self, rpm: float) -> tuple[float, float]:
        """Peak |a| [m/s²] and |da/dt| [m/s³] of the workpiece at ``rpm``; they
        grow as n² and n³ (the path is fixed, the speed law scales with n).

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml").mechanisms["line"]
        >>> a1, j1 = m.peaks(60.0); a2, j2 = m.peaks(120.0)
        >>> round(a2 / a1, 6), round(j2 / j1, 6)
        (4.0, 8.0)
        """
        acc = self.path.acceleration(self.speeds(rpm))
        return acc.max_acceleration, acc.max_jerk

    def _limits_rpm(self) -> tuple[float, float]:
        """The speeds [rpm] at which the peak jerk and the peak acceleration reach
        their limits (inf without one): jerk grows as n³, acceleration as n²."""
        a1, j1 = self.peaks(1.0)
        by_jerk = math.inf if self.max_jerk is None else (self.max_jerk / j1) ** (1.0 / 3.0)
        by_acc = (
            math.inf if self.max_acceleration is None else math.sqrt(self.max_acceleration / a1)
        )
        return by_jerk, by_acc

    def speed_limit_rpm(self) -> float:
        """Speed [rpm] at which the first of the limits is reached (inf without).

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml").mechanisms["line"]
        >>> a, j = m.peaks(m.speed_limit_rpm())
        >>> round(j, 6) <= m.max_jerk and round(a, 6) <= m.max_acceleration
        True
        """
        if self.max_jerk is None and self.max_acceleration is None:
            return math.inf
        return min(self._limits_rpm())

    def limit_reason(self) -> str:
        """What sets :meth:`speed_limit_rpm`: the first limit reached (jerk where
        both are reached at the same speed).

        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/rotor_line.toml").mechanisms["line"].limit_reason()
        "the workpiece's peak jerk reaches max_jerk = 10 m/s³"
        """
        if self.max_jerk is None and self.max_acceleration is None:
            return ""
        by_jerk, by_acc = self._limits_rpm()
        if by_jerk <= by_acc:
            return f"the workpiece's peak jerk reaches max_jerk = {self.max_jerk:g} m/s³"
        return (
            "the workpiece's peak acceleration reaches max_acceleration = "
            f"{self.max_acceleration:g} m/s²"
        )


Mechanism = CamStop | LinkageMechanism | PressMechanism | TransferMechanism


# --------------------------------------------------------------------- results
@dataclass(frozen=True)
class SpeedSweep:
    """The machine's key figures at each speed ``rpm`` [rpm] (arrays of that shape).

    ``fits``: the cyclogram fits in the cycle with every stop's rebound within its
    limit; ``limiting_deg``: the limiting operation's optimal angle [deg] (NaN
    where it does not fit); ``limiting_s``: the time it gets [s]; ``productivity``:
    machine cycles per minute where it fits, else 0; ``max_rebound_m``: the largest
    first rebound of the stops [m] with each stop's arc at its smallest admissible
    angle (NaN without stops); ``binding``: the bounds and constraints on the
    chain that sets the optimum (``; ``-joined); ``min_phase_deg[stop]``: each
    stop's exact smallest phase angle [deg]; with ``linear=True``,
    ``limiting_deg`` uses the seed's linearised rebound constraints instead.
    """

    rpm: Array
    fits: npt.NDArray[np.bool_]
    limiting_deg: Array
    limiting_s: Array
    productivity: Array
    max_rebound_m: Array
    binding: npt.NDArray[np.object_]
    min_phase_deg: dict[str, Array]


@dataclass(frozen=True)
class SpeedLimit:
    """The highest speed [rpm] at which the machine works: ``rpm`` is the least of
    ``cyclogram_rpm`` (the cyclogram with the stops' constraints still fits) and
    each mechanism's own limit in ``mechanisms_rpm``; ``by`` names what sets it
    (``"cyclogram"`` or a mechanism); ``reason`` says why, in words: the
    mechanism's criterion and its limit (``mechanisms_reason`` for each), the
    cyclogram's chain, or that the minimum angles fit at no speed (``rpm`` 0);
    ``binding`` the bounds and constraints on the chain at the cyclogram's limit
    (a tuple, as :attr:`cyclomech.cyclogram.SpeedLimit.binding`)."""

    rpm: float
    by: str
    cyclogram_rpm: float
    mechanisms_rpm: dict[str, float]
    binding: tuple[str, ...] = ()
    reason: str = ""
    mechanisms_reason: dict[str, str] = field(default_factory=dict)


# --------------------------------------------------------------------- network
class _Network:
    """The cyclogram's LP as a system of difference constraints over the event
    angles p, a zero node z and the span's end F: every operation's minimum (its
    angle, its duration, a stop's rebound bound) and maximum, every single-operation
    constraint, p ≥ 0, p ≤ F and F ≤ cycle. The limiting angle's optimum is the
    shortest path from the limiting operation's start to its end (plus the cycles
    it crosses). ``general`` lists the constraints over several operations, which
    need the LP instead."""

    def __init__(self, cg: Cyclogram, stops: Sequence[CamStop]) -> None:
        if cg.limiting is None:
            raise InputError(
                f"cyclogram {cg.name!r}: a machine needs its limiting operation "
                "([cyclogram] limiting = [from, to])"
            )
        self.cg = cg
        ev = cg._events
        V = len(ev)
        z, F = V, V + 1
        self.n = V + 2
        C = cg.cycle_deg
        labels = cg._bound_labels()
        src: list[int] = []
        dst: list[int] = []
        base: list[float] = []  # constant part of each edge's weight
        self.kind: list[str] = []  # "min", "max", "user", "cycle", ""
        self.label: list[str] = []
        self.op: list[int] = []
        ops = cg._ops
        self.min_edge = np.empty(len(ops), np.int64)
        for e, op in enumerate(ops):
            x, y = ev[op.src], ev[op.dst]
            self.min_edge[e] = len(src)
            src.append(y), dst.append(x), base.append(C * op.height)
            self.kind.append("min"), self.label.append(labels[e]), self.op.append(e)
            if op.max_angle_deg is not None:
                src.append(x), dst.append(y), base.append(op.max_angle_deg - C * op.height)
                self.kind.append("max"), self.label.append(f"max[{labels[e]}]"), self.op.append(e)
        self.general: list[Constraint] = []
        self.always_false: list[Constraint] = []
        for con in cg.constraints:
            coeff: dict[Arc, float] = {}
            for arc, c in con.coeffs:
                coeff[arc] = coeff.get(arc, 0.0) + c
            terms = [(a, c) for a, c in coeff.items() if c != 0.0]
            if len(terms) > 1:
                self.general.append(con)
                continue
            if not terms:
                holds = {"<=": con.rhs >= 0.0, ">=": con.rhs <= 0.0, "==": con.rhs == 0.0}
                if not holds[con.sense]:
                    self.always_false.append(con)
                continue
            (arc, c), bound = terms[0], con.rhs / terms[0][1]
            op = cg.operation(arc)
            e = cg._arc_index[op.arc]
            x, y = ev[op.src], ev[op.dst]
            upper = (con.sense == "<=") == (c > 0)
            senses = ("upper", "lower") if con.sense == "==" else ("upper" if upper else "lower",)
            for s in senses:
                if s == "upper":  # t ≤ bound
                    src.append(x), dst.append(y), base.append(bound - C * op.height)
                else:  # t ≥ bound
                    src.append(y), dst.append(x), base.append(C * op.height - bound)
                self.kind.append("user"), self.label.append(con.name), self.op.append(e)
        for v in range(V):  # p_v ≥ 0 (z − p_v ≤ 0) and p_v ≤ F
            src += [v, F]
            dst += [z, v]
            base += [0.0, 0.0]
            self.kind += ["", ""]
            self.label += ["", ""]
            self.op += [-1, -1]
        src.append(z), dst.append(F), base.append(C)
        self.kind.append("cycle"), self.label.append("cycle"), self.op.append(-1)
        self.src = np.array(src, np.int64)
        self.dst = np.array(dst, np.int64)
        self.base = np.array(base, np.float64)
        lim = cg.operation(cg.limiting)
        self.source, self.target = ev[lim.src], ev[lim.dst]
        self.lim_shift = C * lim.height
        self.angle = np.array([op.min_angle_deg for op in ops], np.float64)
        self.secs = np.array([op.min_duration_s for op in ops], np.float64)
        self.stop_op = [cg._arc_index[cg.operation(s.arc).arc] for s in stops]
        self.stop_names = [s.name for s in stops]

    def minimums(self, rpm: Array, t_stop: Sequence[Array]) -> tuple[Array, npt.NDArray[np.int8]]:
        """Each operation's minimum angle at each speed (B, E) and which lower bound
        sets it (0: its angle, 1: its duration, 2 + k: stop k)."""
        mins = np.broadcast_to(self.angle, (rpm.size, self.angle.size)).copy()
        which = np.zeros(mins.shape, np.int8)
        dur = DEG_PER_S_PER_RPM * rpm[:, None] * self.secs[None, :]
        take = dur > mins
        mins[take], which[take] = dur[take], 1
        for k, (e, t) in enumerate(zip(self.stop_op, t_stop, strict=True)):
            t = np.nan_to_num(t, nan=-np.inf)
            take = t > mins[:, e]
            mins[take, e], which[take, e] = t[take], 2 + k
        return mins, which

    def solve(
        self, rpm: Array, t_stop: Sequence[Array], n_threads: int | None, *, labels: bool = True
    ) -> tuple[Array, npt.NDArray[np.bool_], npt.NDArray[np.object_], Array]:
        """The limiting angle [deg] (NaN: does not fit), the fit flags, the binding
        labels (empty with ``labels=False``) and the minimum angles (B, E) at each
        speed."""
        mins, which = self.minimums(rpm, t_stop)
        w = np.broadcast_to(self.base, (rpm.size, self.base.size)).copy()
        w[:, self.min_edge] -= mins
        stop_ok = np.ones(rpm.size, bool)
        for t in t_stop:
            stop_ok &= np.isfinite(t)
        if self.always_false:
            stop_ok[:] = False
        extra: list[list[str]] = []
        if self.general:
            value, on_path, extra = self._lp(rpm, mins, stop_ok)
        else:
            value, on_path = max_difference(
                self.n, self.src, self.dst, w, self.source, self.target, n_threads=n_threads
            )
        value = np.where(stop_ok & np.isfinite(value), value + self.lim_shift, np.nan)
        fits = np.isfinite(value)
        if not labels:
            return value, fits, np.empty(0, dtype=object), mins
        named = self._labels(on_path, which, fits)
        for i, names in enumerate(extra):
            if names and fits[i]:
                named[i] = "; ".join([named[i], *names] if named[i] else names)
        return value, fits, named, mins

    def _lp(
        self, rpm: Array, mins: Array, ok: npt.NDArray[np.bool_]
    ) -> tuple[Array, npt.NDArray[np.bool_], list[list[str]]]:
        """The LP at each speed, for constraints over several operations: the
        optimum; the edges of the bounds with a shadow price as the 'path'; and the
        priced constraints over several operations, which are no edge."""
        from ..cyclogram._model import _LP

        value = np.full(rpm.size, np.nan)
        on_path = np.zeros((rpm.size, self.src.size), bool)
        extra: list[list[str]] = [[] for _ in range(rpm.size)]
        cg = self.cg
        lim = cg.operation(cg.limiting)  # type: ignore[arg-type]
        edge = {}  # the LP's row names of the bounds that are edges here
        for k, (kind, lab) in enumerate(zip(self.kind, self.label, strict=True)):
            if kind == "min":
                edge[f"min[{lab}]"] = edge[f"duration[{lab}]"] = k
            elif kind:
                edge[lab] = k
        for i in np.flatnonzero(ok):
            lp = _LP(cg, mins[i], cg.cycle_deg, lim.arc)
            res = lp.solve()
            if res.status != 0:
                continue
            value[i] = -float(res.fun)
            for r in lp.priced(res):
                name = lp.names[r]
                if name in edge:
                    on_path[i, edge[name]] = True
                else:
                    extra[i].append(name)
        return value, on_path, extra

    def _labels(
        self,
        on_path: npt.NDArray[np.bool_],
        which: npt.NDArray[np.int8],
        fits: npt.NDArray[np.bool_],
    ) -> npt.NDArray[np.object_]:
        """``; ``-joined names of the bounds on each row's chain: the unique
        patterns are named once. Neighbouring speeds mostly share a pattern, so
        only the first row of each run of equal rows goes into the sort."""
        code = np.zeros(on_path.shape, np.int16)
        code[on_path] = 1
        mins = code[:, self.min_edge]
        code[:, self.min_edge] = np.where(mins > 0, 1 + which.astype(np.int16), 0)
        code[~fits] = 0
        starts = np.flatnonzero(np.r_[True, (code[1:] != code[:-1]).any(axis=1)])
        patterns, of_run = np.unique(code[starts], axis=0, return_inverse=True)
        inverse = np.repeat(of_run.reshape(-1), np.diff(np.r_[starts, code.shape[0]]))
        names = []
        for row in patterns:
            parts = []
            for k in np.flatnonzero(row):
                kind, lab = self.kind[k], self.label[k]
                if kind == "min":
                    v = int(row[k]) - 1
                    parts.append(
                        f"min[{lab}]"
                        if v == 0
                        else f"duration[{lab}]"
                        if v == 1
                        else f"rebound[{self.stop_names[v - 2]}]"
                    )
                elif kind:
                    parts.append(lab)
            names.append("; ".join(parts))
        out = np.array(names, dtype=object)[inverse.reshape(-1)]
        return out


# --------------------------------------------------------------------- the machine
class Machine:
    """A machine: its mechanisms and its cyclogram, over a speed range.

    Read one with :meth:`from_toml` (the layout is in the module's docstring);
    :meth:`speed_sweep` gives the key figures at many speeds in one pass,
    :meth:`speed_limit` the highest speed at which it works, :meth:`optimize` the
    LP optimum of its cyclogram with the stops' constraints at one speed.

    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> sorted(m.mechanisms), m.speed_range_rpm
    (['lifter'], (200.0, 500.0))
    """

    def __init__(
        self,
        name: str,
        cyclogram: Cyclogram,
        mechanisms: Mapping[str, Mechanism],
        *,
        speed_range_rpm: tuple[float, float],
        speed_points: int = 61,
        nominal_rpm: float | None = None,
        angle_points: int = 361,
        source: str = "<machine>",
        data: Mapping[str, Any] | None = None,
    ) -> None:
        if not isinstance(cyclogram, Cyclogram):
            raise InputError(f"cyclogram must be a cyclomech.Cyclogram; got {cyclogram!r}")
        rng = _speeds("speed_range_rpm", speed_range_rpm)
        if rng.size != 2 or not rng[0] < rng[1]:
            raise InputError(
                f"speed_range_rpm = {speed_range_rpm!r} must be (from, to) in rpm with "
                f"0 < from < to ≤ {_SPEED_CAP_RPM:g}"
            )
        if nominal_rpm is not None:
            nominal_rpm = float(_speeds("nominal_rpm", nominal_rpm)[0])
        self.name = str(name)
        self.cyclogram = cyclogram
        self.mechanisms = dict(mechanisms)
        self.speed_range_rpm = (float(rng[0]), float(rng[1]))
        self.speed_points = count("speed_points", speed_points, low=2, high=1_000_000)
        self.nominal_rpm = nominal_rpm
        self.angle_points = count("angle_points", angle_points, low=9, high=1_000_000)
        self.source = source
        self.data = data
        self.stops = [m for m in self.mechanisms.values() if isinstance(m, CamStop)]
        self._network = _Network(cyclogram, self.stops)

    def __repr__(self) -> str:
        kinds = ", ".join(f"{k}: {type(v).__name__}" for k, v in self.mechanisms.items())
        return f"Machine({self.name!r}, {{{kinds}}}, speed {self.speed_range_rpm} rpm)"

    # ----------------------------------------------------------------- reading
    @classmethod
    def from_toml(cls, path: str | Path) -> Machine:
        """Read a machine file; every error names the file, the table and the key.

        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").name
        'STB loom, group 1 (illustrative)'
        """
        data, source = _toml.load(path)
        return cls.from_dict(data, source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], source: str = "<dict>") -> Machine:
        """A machine from the parsed layout of :meth:`from_toml` (``source`` names
        it in messages).

        >>> import cyclomech as cm
        >>> m = cm.Machine.example()
        >>> cm.Machine.from_dict(m.data).speed_points
        61
        """
        if isinstance(data, Mapping) and "machine" not in data:
            other = _other_command(data)
            if other:
                raise InputError(
                    f"{source}: a machine file needs a [machine] table; this looks like "
                    f"{other[0]}: run it with `cyclomech {other[1]}`"
                )
        _toml.check_keys(
            data,
            {"machine", "mechanism", "cyclogram", "operation", "constraint"},
            source,
            "top level",
        )
        if "machine" not in data:
            raise InputError(f"{source}: missing table [machine] (its name and speed_rpm)")
        head = data["machine"]
        _toml.check_keys(head, _MACHINE_KEYS, source, "[machine]")
        name = head.get("name", Path(source).stem)
        if not isinstance(name, str):
            raise InputError(f"{source}: [machine]: name = {name!r} must be a string")
        rng = head.get("speed_rpm")
        if not (
            isinstance(rng, list)
            and len(rng) == 2
            and all(_is_number(v) and math.isfinite(v) for v in rng)
            and 0 < rng[0] < rng[1] <= _SPEED_CAP_RPM
        ):
            raise InputError(
                f"{source}: [machine]: speed_rpm = {rng!r} must be [from, to] in rpm with "
                f"0 < from < to ≤ {_SPEED_CAP_RPM:g}"
            )
        speed_points = _int_key(head, "speed_points", 61, 2, source, "[machine]")
        angle_points = _int_key(head, "angle_points", 361, 9, source, "[machine]")
        nominal = head.get("nominal_rpm")
        if nominal is not None and not (_is_number(nominal) and 0 < nominal <= _SPEED_CAP_RPM):
            raise InputError(
                f"{source}: [machine]: nominal_rpm = {nominal!r} must be a speed in rpm, "
                f"0 < nominal_rpm ≤ {_SPEED_CAP_RPM:g}"
            )
        if "cyclogram" not in data or "operation" not in data:
            raise InputError(
                f"{source}: a machine needs its cyclogram: a [cyclogram] table and "
                "[[operation]] tables (see cyclomech.Cyclogram.from_toml)"
            )
        if isinstance(data["cyclogram"], Mapping) and "speed_rpm" in data["cyclogram"]:
            raise InputError(
                f"{source}: [cyclogram]: speed_rpm is set by the machine; give the speed "
                "range in [machine] speed_rpm and the report's speed in [machine] nominal_rpm"
            )
        if isinstance(data["cyclogram"], Mapping) and "limiting" not in data["cyclogram"]:
            raise InputError(
                f"{source}: [cyclogram]: missing key 'limiting': the operation that gets what "
                'the others leave of the cycle, e.g. limiting = ["10.1", "10.2"]'
            )
        cg = Cyclogram.from_dict(
            {k: data[k] for k in ("cyclogram", "operation", "constraint") if k in data}, source
        )
        mechs: dict[str, Mechanism] = {}
        table = data.get("mechanism", {})
        if not isinstance(table, Mapping):
            raise InputError(f"{source}: [mechanism] must be a table of [mechanism.<name>] tables")
        for key, spec in table.items():
            mechs[key] = _mechanism(key, spec, cg, source, angle_points)
        _near_misses(cg, mechs, source)
        return cls(
            name,
            cg,
            mechs,
            speed_range_rpm=(float(rng[0]), float(rng[1])),
            speed_points=speed_points,
            nominal_rpm=None if nominal is None else float(nominal),
            angle_points=angle_points,
            source=source,
            data=copy.deepcopy(dict(data)),
        )

    @classmethod
    def example(cls) -> Machine:
        """A small machine for examples: the STB lifter's stop on the arc (3, 7)
        of a four-operation group with a time-bound weft insertion.

        >>> import cyclomech as cm
        >>> len(cm.Machine.example().cyclogram.operations)
        4
        """
        lifter = {
            "kind": "cam_stop",
            "law": "modified_sine",
            "stroke": 9.4e-3,
            "preload": 0.25e-3,
            "lever_length": 0.1,
            "J_A": 7.4e-5,
            "a": 0.05,
            "b": 0.1,
            "E": 2.1e11,
            "J_x": 6.14e-11,
            "restitution": 5.0 / 9.0,
            "zeta": 0.05,
            "arc": ["3", "7"],
            "a_max": 1e-4,
        }
        ops = [
            {"from": "1", "to": "3", "min_angle_deg": 45.0, "mechanism": "lifter"},
            {"from": "3", "to": "7", "min_angle_deg": 20.0, "mechanism": "lifter"},
            {"from": "7", "to": "10.1", "min_angle_deg": 20.0, "mechanism": "lifter"},
            {
                "from": "10.1",
                "to": "10.2",
                "min_angle_deg": 120.0,
                "min_duration_s": 0.1,
                "name": "weft insertion",
            },
        ]
        return cls.from_dict(
            {
                "machine": {"name": "example", "speed_rpm": [200.0, 500.0]},
                "mechanism": {"lifter": lifter},
                "cyclogram": {"name": "example", "limiting": ["10.1", "10.2"]},
                "operation": ops,
            },
            "<example>",
        )

    def with_values(self, values: Mapping[str, Any]) -> Machine:
        """A copy with mechanism keys replaced: ``{"lifter.preload": 2e-4}``
        (``<mechanism>.<key>``) or machine keys (``machine.<key>``); the result is
        validated like a file.

        >>> import cyclomech as cm
        >>> m = cm.Machine.example().with_values({"lifter.preload": 3e-4})
        >>> m.mechanisms["lifter"].stop.preload
        0.0003
        """
        if self.data is None:
            raise InputError("with_values needs a machine read from a file or a dict")
        # A copy of the tables that change; the others are shared with this machine.
        data = dict(self.data)
        data["mechanism"] = dict(data.get("mechanism", {}))
        touched: set[str] = set()
        for path, value in values.items():
            head = path.split(".", 1)[0]
            if head not in touched:
                if head == "machine":
                    data["machine"] = copy.deepcopy(data.get("machine", {}))
                elif head in data["mechanism"]:
                    data["mechanism"][head] = copy.deepcopy(data["mechanism"][head])
            table, key = _split_key(path, data)
            table[key] = value.item() if isinstance(value, np.generic) else value
            touched.add(head)
        if "machine" in touched:
            return Machine.from_dict(data, self.source)
        # Only the named mechanisms' tables changed: validate and build those (as
        # from_dict would), and share the cyclogram and its network with this one.
        mechs = dict(self.mechanisms)
        for name in touched:
            spec = data["mechanism"][name]
            mechs[name] = _mechanism(name, spec, self.cyclogram, self.source, self.angle_points)
        stops = [m for m in mechs.values() if isinstance(m, CamStop)]
        if [(m.name, m.arc) for m in stops] != [(m.name, m.arc) for m in self.stops]:
            return Machine.from_dict(data, self.source)  # the stops bound other operations
        other = copy.copy(self)
        other.mechanisms, other.data, other.stops = mechs, data, stops
        return other

    # ----------------------------------------------------------------- results
    def speed_grid(self) -> Array:
        """The report's speeds [rpm]: ``speed_points`` over ``speed_rpm``.

        >>> import cyclomech as cm
        >>> cm.Machine.example().speed_grid()[[0, -1]].tolist()
        [200.0, 500.0]
        """
        return np.linspace(*self.speed_range_rpm, self.speed_points)

    def stop_angles(
        self, rpm: Array, *, linear: bool = False, n_threads: int | None = None
    ) -> list[Array]:
        """Each stop's smallest phase angle [deg] at each speed: exact, or the
        seed's linearised form with ``linear=True``.

        >>> import numpy as np, cyclomech as cm
        >>> [np.round(t, 2).tolist() for t in cm.Machine.example().stop_angles(np.array([300.0]))]
        [[30.03]]
        """
        rpm = _speeds("rpm", rpm)
        if linear:
            return [s.linear_min_phase_deg(rpm, n_threads=n_threads) for s in self.stops]
        slopes = _stop_slopes([self], threads_arg(n_threads))[0]
        return [min_phase_angles(rpm, k) for k in slopes]

    def speed_sweep(
        self,
        rpm: npt.ArrayLike | None = None,
        *,
        linear: bool = False,
        n_threads: int | None = None,
    ) -> SpeedSweep:
        """The key figures at each speed ``rpm`` (default :meth:`speed_grid`): one
        search per stop for all speeds and one shortest-path call for all speeds
        (:func:`speed_sweeps` for one machine).

        >>> import cyclomech as cm
        >>> s = cm.Machine.example().speed_sweep([300.0, 900.0])
        >>> s.fits.tolist(), round(float(s.limiting_deg[0]), 3)
        ([True, False], 264.971)
        """
        n = self.speed_grid() if rpm is None else _speeds("rpm", rpm)
        return speed_sweeps([self], n, linear=linear, n_threads=n_threads)[0]

    def fits(self, rpm: npt.ArrayLike, *, n_threads: int | None = None) -> npt.NDArray[np.bool_]:
        """Whether the cyclogram with the stops' constraints fits at each speed.

        >>> import cyclomech as cm
        >>> cm.Machine.example().fits([300.0, 900.0]).tolist()
        [True, False]
        """
        n = _speeds("rpm", rpm)
        threads = threads_arg(n_threads)
        return _fits(self._network, _stop_slopes([self], threads), n[None, :], threads)[0]

    def cyclogram_speed_limit(self, *, n_threads: int | None = None, rtol: float = 1e-10) -> float:
        """The highest speed [rpm] at which the cyclogram with the stops'
        constraints fits (inf if it fits up to 1e6 rpm; 0 if it fits at no
        speed from 1e-6 rpm up), to ``rtol`` (:func:`speed_limits`' search).

        >>> import cyclomech as cm
        >>> round(cm.Machine.example().cyclogram_speed_limit(), 3)
        421.37
        """
        rtol = _rtol(rtol)
        threads = threads_arg(n_threads)
        slopes = _stop_slopes([self], threads)
        return float(
            _cyclogram_limits(self._network, slopes, self._search_start(), threads, rtol)[0]
        )

    def speed_limit(self, *, n_threads: int | None = None) -> SpeedLimit:
        """The machine's speed limit: the cyclogram's and every mechanism's
        (:func:`speed_limits` for one machine).

        >>> import cyclomech as cm
        >>> lim = cm.Machine.example().speed_limit()
        >>> round(lim.rpm, 3), lim.by
        (421.37, 'cyclogram')
        """
        return speed_limits([self], n_threads=n_threads)[0]

    def _search_start(self) -> float:
        """The first speed [rpm] the speed-limit search tries."""
        return max(self.speed_range_rpm[1], 1.0)

    def nominal_speed(self, limit: SpeedLimit | None = None) -> float:
        """The speed [rpm] of the report's optimised cyclogram: ``nominal_rpm``, or
        the top of the speed range capped at the speed limit.

        >>> import cyclomech as cm
        >>> round(cm.Machine.example().nominal_speed(), 3)
        421.37
        """
        if self.nominal_rpm is not None:
            return self.nominal_rpm
        lim = self.speed_limit() if limit is None else limit
        return min(self.speed_range_rpm[1], lim.rpm) if lim.rpm > 0 else self.speed_range_rpm[0]

    def cyclogram_at(self, rpm: float, *, linear: bool = False) -> Cyclogram:
        """A copy of the cyclogram at ``rpm`` with each stop's constraint added
        (exact, or the seed's linearised form with ``linear=True``).

        >>> import cyclomech as cm
        >>> cg = cm.Machine.example().cyclogram_at(300.0)
        >>> [c.name for c in cg.constraints]
        ['rebound[lifter]']
        """
        cg = copy.deepcopy(self.cyclogram)
        cg.speed_rpm = float(rpm)
        for s in self.stops:
            if linear:
                c = s.stop.constraint(s.arc, s.a_max, rpm, linear=True)
                cg.add_constraint(dict(c.coeffs), c.sense, c.rhs, name=f"rebound[{s.name}]")
            else:
                c = s.constraint(rpm)
                cg.add_constraint(dict(c.coeffs), c.sense, c.rhs, name=c.name)
        return cg

    def optimize(self, rpm: float) -> Optimum:
        """The LP optimum (HiGHS) of the cyclogram with the stops' exact
        constraints at ``rpm``: angles, shadow prices, binding bounds.

        >>> import cyclomech as cm
        >>> round(cm.Machine.example().optimize(300.0).objective, 3)
        264.971
        """
        try:
            return self.cyclogram_at(rpm).optimize()
        except InfeasibleError as e:
            raise InfeasibleError(
                f"machine {self.name!r} at {rpm:g} rpm: {e}", e.conflict
            ) from None


# --------------------------------------------------------------------- many machines
#: Relative bracket of the stops' critical speeds: min_phase_angle's default 1e-9°
#: over at most 360°.
_STOP_RTOL = 1e-9 / 360.0


def _networks(machines: Sequence[Machine]) -> dict[int, list[int]]:
    """Indices of the machines that share each cyclogram network (the variants of
    one file made by :meth:`Machine.with_values`), in order."""
    groups: dict[int, list[int]] = {}
    for i, m in enumerate(machines):
        groups.setdefault(id(m._network), []).append(i)
    return groups


def _stop_slopes(machines: Sequence[Machine], n_threads: int | None) -> Array:
    """Each machine's stops' smallest phase angle per rpm [deg/rpm], (D, K): t_min
    = n·slope (:meth:`StopImpact.min_phase_angle`); one search for every stop."""
    stops = [s for m in machines for s in m.stops]
    k = len(machines[0].stops) if machines else 0
    if not stops:
        return np.zeros((len(machines), k))
    v = max_impact_speeds(
        [s.stop for s in stops], [s.a_max for s in stops], rtol=_STOP_RTOL, n_threads=n_threads
    )
    slopes = [s.stop.phase_per_rpm(x) for s, x in zip(stops, v, strict=True)]
    return np.array(slopes, dtype=np.float64).reshape(len(machines), k)


def _stop_bounds(slopes: Array, rpm: Array) -> list[Array]:
    """Each stop's smallest phase angle [deg] for machine d (stop slopes
    ``slopes[d]``, (D, K)) at its speeds ``rpm[d]`` (D, M): one (D·M,) array a stop,
    in the row order of ``rpm.reshape(-1)``."""
    m = rpm.shape[1]
    rows = rpm.reshape(-1)
    return [min_phase_angles(rows, np.repeat(slopes[:, k], m)) for k in range(slopes.shape[1])]


def _fits(net: _Network, slopes: Array, rpm: Array, n_threads: int | None) -> npt.NDArray[np.bool_]:
    """Whether machine d (stop slopes ``slopes[d]``) fits at the speeds ``rpm[d]``,
    (D, M): one shortest-path call for all."""
    t_stop = _stop_bounds(slopes, rpm)
    return net.solve(rpm.reshape(-1), t_stop, n_threads, labels=False)[1].reshape(rpm.shape)


def _cyclogram_limits(
    net: _Network, slopes: Array, start: float, n_threads: int | None, rtol: float
) -> Array:
    """The cyclogram speed limit [rpm] of each machine (stop slopes (D, K)), (D,):
    feasibility only shrinks as the speed grows, so each is bracketed by speeds 4×
    apart from ``start`` up to the cap (inf if it fits there; 0 if it does not fit
    at the floor) and the bracket refined on grids of 64 speeds to ``rtol``;
    every step is one shortest-path call for all machines still searching."""
    D = slopes.shape[0]
    out = np.full(D, np.nan)
    ok = _fits(net, slopes, np.full((D, 1), _SPEED_FLOOR_RPM), n_threads)[:, 0]
    out[~ok] = 0.0
    lo, hi = np.full(D, _SPEED_FLOOR_RPM), np.full(D, start)
    act = np.flatnonzero(ok)
    while act.size:
        f = _fits(net, slopes[act], hi[act, None], n_threads)[:, 0]
        capped = f & (hi[act] >= _SPEED_CAP_RPM)
        out[act[capped]] = math.inf
        act = act[f & ~capped]
        lo[act], hi[act] = hi[act], np.minimum(4.0 * hi[act], _SPEED_CAP_RPM)
    act = np.flatnonzero(np.isnan(out))
    while act.size:
        done = hi[act] - lo[act] <= rtol * hi[act]
        out[act[done]] = lo[act[done]]
        act = act[~done]
        if not act.size:
            break
        grid = np.linspace(lo[act], hi[act], 66, axis=1)[:, 1:-1]
        fine = _fits(net, slopes[act], grid, n_threads)
        k = np.where(fine.all(axis=1), grid.shape[1], np.argmin(fine, axis=1))
        r = np.arange(act.size)
        lo[act] = np.where(k > 0, grid[r, np.maximum(k - 1, 0)], lo[act])
        hi[act] = np.where(k < grid.shape[1], grid[r, np.minimum(k, grid.shape[1] - 1)], hi[act])
    return out


def speed_sweeps(
    machines: Sequence[Machine],
    rpm: npt.ArrayLike,
    *,
    linear: bool = False,
    n_threads: int | None = None,
) -> list[SpeedSweep]:
    """:meth:`Machine.speed_sweep` of many machines at the same speeds ``rpm``
    [rpm]. Variants of one file (:meth:`Machine.with_values`) share their
    cyclogram: their stops are searched together and every design at every speed
    goes into one shortest-path call; each stop's rebounds at the optimum are one
    call per pulse table.

    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> a, b = cm.machine.speed_sweeps([m, m.with_values({"lifter.a_max": 2e-4})], [300.0])
    >>> round(float(a.limiting_deg[0]), 3), round(float(b.limiting_deg[0]), 3)
    (264.971, 275.0)
    """
    n = _speeds("rpm", rpm)
    threads = threads_arg(n_threads)
    out: list[SpeedSweep | None] = [None] * len(machines)
    S = n.size
    for idx in _networks(machines).values():
        ms = [machines[i] for i in idx]
        net, D = ms[0]._network, len(ms)
        rows = np.tile(n, D)
        if linear:
            each = [m.stop_angles(n, linear=True, n_threads=threads) for m in ms]
            t_stop = [np.concatenate([t[k] for t in each]) for k in range(len(net.stop_op))]
        else:
            slopes = _stop_slopes(ms, threads)
            t_stop = _stop_bounds(slopes, rows.reshape(D, S))
        value, fits, binding, mins = net.solve(rows, t_stop, threads)
        rebound = np.full(rows.shape, np.nan)
        for k, e in enumerate(net.stop_op):
            stops = [m.stops[k].stop for m in ms]
            # Impact speeds at the operation's optimum angle t (its minimum): the
            # angle per rpm at 1 m/s is phase_per_rpm(1), so v0 = n·that/t; 1 m/s
            # where the machine does not fit (dropped).
            per = np.repeat([s.phase_per_rpm(1.0) for s in stops], S)
            v0 = np.where(fits, rows * per / np.where(fits, mins[:, e], 1.0), 1.0)
            a = rebounds(stops, v0.reshape(D, S), n_threads=threads).reshape(-1)
            rebound = np.fmax(rebound, np.where(fits, a, np.nan))
        names = [st.name for st in ms[0].stops]
        for j, i in enumerate(idx):
            r = slice(j * S, (j + 1) * S)
            out[i] = SpeedSweep(
                rpm=n,
                fits=fits[r],
                limiting_deg=value[r],
                limiting_s=value[r] / (DEG_PER_S_PER_RPM * n),
                productivity=np.where(fits[r], n, 0.0),
                max_rebound_m=rebound[r],
                binding=binding[r],
                min_phase_deg={name: t[r] for name, t in zip(names, t_stop, strict=True)},
            )
    return out  # type: ignore[return-value]


def speed_limits(machines: Sequence[Machine], *, n_threads: int | None = None) -> list[SpeedLimit]:
    """:meth:`Machine.speed_limit` of many machines: the cyclogram limits of the
    variants of one file are searched together (one shortest-path call per step
    for all of them); a mechanism shared by variants is evaluated once.

    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> both = cm.machine.speed_limits([m, m.with_values({"lifter.a_max": 2e-4})])
    >>> [round(x.rpm, 2) for x in both]
    [421.37, 453.81]
    """
    threads = threads_arg(n_threads)
    out: list[SpeedLimit | None] = [None] * len(machines)
    own: dict[int, float] = {}  # a mechanism's own limit, by object
    for idx in _networks(machines).values():
        ms = [machines[i] for i in idx]
        net = ms[0]._network
        slopes = _stop_slopes(ms, threads)
        cg = _cyclogram_limits(net, slopes, ms[0]._search_start(), threads, 1e-10)
        at = np.flatnonzero((cg > 0.0) & np.isfinite(cg))
        binding = np.full(len(ms), "", dtype=object)
        if at.size:
            t_stop = _stop_bounds(slopes[at], cg[at, None])
            binding[at] = net.solve(cg[at], t_stop, threads)[2]
        for j, (i, m) in enumerate(zip(idx, ms, strict=True)):
            mech, why = {}, {}
            for k, x in m.mechanisms.items():
                if isinstance(x, CamStop):
                    continue
                if id(x) not in own:
                    own[id(x)] = float(x.speed_limit_rpm())
                if math.isfinite(own[id(x)]):
                    mech[k] = own[id(x)]
                    why[k] = x.limit_reason()
            by, rpm = "cyclogram", float(cg[j])
            for k, v in mech.items():
                if v < rpm:
                    by, rpm = k, v
            chain = tuple(b for b in str(binding[j]).split("; ") if b)
            reason = why[by] if by != "cyclogram" else _cyclogram_reason(m, rpm, chain)
            out[i] = SpeedLimit(rpm, by, float(cg[j]), mech, chain, reason, why)
    return out  # type: ignore[return-value]


def _cyclogram_reason(m: Machine, rpm: float, chain: tuple[str, ...]) -> str:
    """Why the cyclogram limits machine ``m`` at ``rpm``, in words."""
    if math.isinf(rpm):
        return f"nothing limits the speed up to {_SPEED_CAP_RPM:g} rpm"
    if rpm > 0:
        bounded = f"; bounded by {', '.join(chain)}" if chain else ""
        return "the cyclogram fills the cycle" + bounded
    # Fits at no speed: the operations' durations and the stops' bounds vanish as the
    # speed falls, so what is left is the minimum angles and the constraints.
    try:
        m.cyclogram.max_speed_rpm()
    except InfeasibleError as e:
        text = str(e).replace(" at 0 rpm", "")
        return (
            "the minimum angles alone do not fit in the cycle at any speed (they do not "
            f"depend on the speed): {text}"
        )
    try:
        m.cyclogram_at(_SPEED_FLOOR_RPM).optimize()
    except InfeasibleError as e:
        return f"the cyclogram's bounds and constraints conflict at any speed: {e}"
    return f"the cyclogram does not fit even at {_SPEED_FLOOR_RPM:g} rpm"


# --------------------------------------------------------------------- parsing
def _near_misses(cg: Cyclogram, mechs: Mapping[str, Mechanism], source: str) -> None:
    """Warn when an operation's ``mechanism`` is not one of the machine's but nearly
    is (``"liftr"`` for ``"lifter"``: difflib ratio ≥ 0.75): probably a typo that
    would draw a Gantt row of its own. A name far from every mechanism is a
    mechanism the file does not model (a clamp, a back gauge), and stays quiet."""
    seen: set[str] = set()
    for op in cg.operations:
        name = op.mechanism
        if name is None or name in mechs or name in seen:
            continue
        seen.add(name)
        near = difflib.get_close_matches(name, list(mechs), n=1, cutoff=0.75)
        if near:
            warnings.warn(
                f"{source}: operation {op.title!r}: mechanism = {name!r} is not a mechanism "
                f"of the machine; did you mean {near[0]!r}? (it gets a Gantt row of its own)",
                CyclomechWarning,
                stacklevel=4,
            )


def _other_command(data: Mapping[str, Any]) -> tuple[str, str] | None:
    """What another command's file looks like, and that command: by its tables."""
    if "stop" in data:
        return "an impact file ([stop])", "impact"
    if "linkage" in data:
        return "a linkage file ([linkage])", "linkage"
    if "press" in data:
        return "a press file ([press])", "press"
    if "mechanism" not in data and ("cyclogram" in data or "operation" in data):
        return "a cyclogram file ([cyclogram], [[operation]])", "cyclogram"
    return None


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _int_key(
    table: Mapping[str, Any], key: str, default: int, low: int, source: str, where: str
) -> int:
    v = table.get(key, default)
    if isinstance(v, bool) or not isinstance(v, int) or not low <= v <= 1_000_000:
        raise InputError(
            f"{source}: {where}: {key} = {v!r} must be a whole number from {low} to 1000000"
        )
    return v


def _rtol(value: Any) -> float:
    """A relative tolerance of a speed search: finite, in [1e-14, 0.5] (below, the
    64-speed refinement cannot shrink its bracket in float64; at 1 and above it
    would stop at once, at the search's floor)."""
    try:
        v = real(value)
    except (TypeError, ValueError):
        v = math.nan
    if not 1e-14 <= v <= 0.5:
        raise InputError(f"rtol = {value!r} must be a relative tolerance in [1e-14, 0.5]")
    return v


def _speeds(name: str, value: npt.ArrayLike) -> Array:
    try:
        n = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be speeds in rpm; got {value!r}") from None
    bad = ~(np.isfinite(n) & (n > 0) & (n <= _SPEED_CAP_RPM))
    if n.size == 0 or bad.any():
        got = f"{float(n[np.argmax(bad)]):g}" if n.size else "no speeds"
        raise InputError(
            f"{name} must hold positive speeds in rpm, each in (0, {_SPEED_CAP_RPM:g}]; got {got}"
        )
    return n


def _split_key(path: str, data: dict[str, Any]) -> tuple[dict[str, Any], str]:
    """The table and key a sweep parameter ``<mechanism>.<key>`` or
    ``machine.<key>`` names in the parsed file."""
    parts = path.split(".")
    mechs = data.get("mechanism", {})
    if len(parts) == 2 and parts[0] == "machine":
        table = data.setdefault("machine", {})
    elif len(parts) == 2 and parts[0] in mechs:
        table = mechs[parts[0]]
    else:
        raise InputError(
            f"parameter {path!r} must be <mechanism>.<key> or machine.<key>; the mechanisms "
            f"are {', '.join(sorted(mechs)) or '(none)'}"
        )
    return table, parts[1]


_KIND_KEYS: dict[str, set[str]] = {
    "cam_stop": set(_CAM_KEYS),
    "linkage": _LINKAGE_KEYS | _LINKAGE_EXTRA,
    "press": _PRESS_KEYS,
    "transfer": _TRANSFER_KEYS,
}


def check_parameter(machine: Machine, path: str) -> None:
    """Raise :class:`InputError` unless ``path`` (``<mechanism>.<key>`` or
    ``machine.<key>``) names a key its table can take: what a sweep checks before
    it starts, whatever the values (a value that makes a design invalid is that
    design's problem, not the sweep's).

    >>> import cyclomech as cm
    >>> from cyclomech.machine import check_parameter
    >>> check_parameter(cm.Machine.example(), "lifter.preload")
    >>> check_parameter(cm.Machine.example(), "lifter.preloud")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: <example>: parameter 'lifter.preloud': [mechanism.lifter] has ...
    """
    if machine.data is None:
        raise InputError("a sweep needs a machine read from a file or a dict")
    _, key = _split_key(path, dict(machine.data))  # a copy: it may add a [machine] table
    head = path.split(".", 1)[0]
    if head == "machine":
        allowed, where = _MACHINE_KEYS - {"name", "speed_rpm"}, "[machine]"
    else:
        allowed, where = _KIND_KEYS[machine.mechanisms[head].kind], f"[mechanism.{head}]"
        allowed = allowed - {"kind", "arc", "name"}
    if key not in allowed:
        raise InputError(
            f"{machine.source}: parameter {path!r}: {where} has no key {key!r} a sweep can "
            "set; valid keys are "
            f"{', '.join(sorted(allowed))}"
        )


def _number(spec: Mapping[str, Any], key: str, where: str, unit: str) -> float:
    v = spec[key]
    if not _is_number(v) or not math.isfinite(v):
        raise InputError(f"{where}: {key} = {v!r} must be a finite number {unit}")
    return float(v)


def _optional(spec: Mapping[str, Any], key: str, where: str, unit: str) -> float | None:
    if key not in spec:
        return None
    v = _number(spec, key, where, unit)
    if v <= 0:
        raise InputError(f"{where}: {key} = {v!r} must be positive {unit}")
    return v


def _require(spec: Mapping[str, Any], keys: Sequence[str], where: str) -> None:
    for k in keys:
        if k not in spec:
            raise InputError(f"{where}: missing key {k!r}")


def _mechanism(key: str, spec: Any, cg: Cyclogram, source: str, points: int) -> Mechanism:
    where = f"{source}: [mechanism.{key}]"
    if not isinstance(spec, Mapping):
        raise InputError(f"{where} must be a table; got {spec!r}")
    kind = spec.get("kind")
    if kind not in _KINDS:
        raise InputError(f"{where}: kind = {kind!r} must be one of {', '.join(_KINDS)}")
    build: dict[str, Callable[..., Mechanism]] = {
        "cam_stop": _cam_stop,
        "linkage": _linkage,
        "press": _press,
        "transfer": _transfer,
    }
    try:
        return build[kind](key, spec, cg, source, where, points)
    except (InputError, InfeasibleError) as e:
        # A mechanism that cannot work (a transition too long for its gap, say) is a
        # mistake in the file: an InputError naming the file and the table.
        msg = str(e)
        raise InputError(msg if msg.startswith(source) else f"{where}: {msg}") from None


def _cam_stop(
    key: str, spec: Mapping[str, Any], cg: Cyclogram, source: str, where: str, points: int
) -> CamStop:
    _toml.check_keys(spec, _CAM_KEYS, source, f"[mechanism.{key}]")
    _require(spec, ("stroke", "preload", "lever_length", "J_A", "a", "b", "E", "J_x"), where)
    _require(spec, ("arc", "a_max"), where)
    kwargs: dict[str, Any] = {}
    for k, v in spec.items():
        if k in ("kind", "arc", "a_max", "phase_deg"):
            continue
        if k in ("law", "pulse", "model"):
            if not isinstance(v, str):
                raise InputError(f"{where}: {k} = {v!r} must be a string")
        elif not _is_number(v):
            raise InputError(f"{where}: {k} = {v!r} must be a number")
        kwargs[k] = v
    stop = StopImpact(**kwargs)
    arc = spec["arc"]
    if not (isinstance(arc, list) and len(arc) == 2 and all(isinstance(x, str) for x in arc)):
        raise InputError(f"{where}: arc = {arc!r} must be two event names [from, to]")
    known = [op.arc for op in cg.operations]
    if (arc[0], arc[1]) not in known:
        listing = ", ".join(f"[{a!r}, {b!r}]" for a, b in known)
        raise InputError(
            f"{where}: arc = {arc!r} is not an operation of the cyclogram; the operations "
            f"are {listing}"
        )
    a_max = _number(spec, "a_max", where, "[m]")
    if a_max <= 0:
        raise InputError(f"{where}: a_max = {a_max!r} must be a positive rebound limit [m]")
    phase = spec.get("phase_deg", [20.0, 60.0, 5])
    if not (
        isinstance(phase, list)
        and len(phase) == 3
        and all(_is_number(v) for v in phase)
        and isinstance(phase[2], int)
        and 1 <= phase[2] <= 50
        and all(0 < v <= 360 for v in phase[:2])
    ):
        raise InputError(
            f"{where}: phase_deg = {phase!r} must be [from, to, count] with from and to in "
            "(0, 360] degrees and a whole count from 1 to 50"
        )
    return CamStop(
        key, stop, (arc[0], arc[1]), a_max, np.linspace(float(phase[0]), float(phase[1]), phase[2])
    )


def _linkage(
    key: str, spec: Mapping[str, Any], cg: Cyclogram, source: str, where: str, points: int
) -> LinkageMechanism:
    _toml.check_keys(spec, _LINKAGE_KEYS | _LINKAGE_EXTRA, source, f"[mechanism.{key}]")
    table = {k: v for k, v in spec.items() if k not in _LINKAGE_EXTRA}
    lk = Linkage.from_dict(table, source, f"[mechanism.{key}]")
    limit = _optional(spec, "max_acceleration", where, "[m/s²]")
    mech = LinkageMechanism(key, lk, lk.output or lk.names[-1], limit, points)
    mech.peaks()  # must assemble over the whole turn
    return mech


def _press(
    key: str, spec: Mapping[str, Any], cg: Cyclogram, source: str, where: str, points: int
) -> PressMechanism:
    _toml.check_keys(spec, _PRESS_KEYS, source, f"[mechanism.{key}]")
    _require(spec, ("R", "r", "d", "L", "phi0_deg"), where)
    if ("k_Sp" in spec) == ("working_stroke" in spec):
        raise InputError(
            f"{where}: give one of k_Sp (a fraction of the stroke) or working_stroke [m]"
        )
    geo = {k: _number(spec, k, where, "[m]") for k in ("R", "r", "d", "L")}
    phi0 = math.radians(_number(spec, "phi0_deg", where, "[deg]"))
    offset = _number(spec, "offset", where, "[m]") if "offset" in spec else 0.0
    press = GearLeverPress(phi0=phi0, offset=offset, **geo)
    mech = PressMechanism(
        key,
        press,
        k_Sp=_number(spec, "k_Sp", where, "") if "k_Sp" in spec else None,
        working_stroke=(
            _number(spec, "working_stroke", where, "[m]") if "working_stroke" in spec else None
        ),
        max_V_np=_optional(spec, "max_V_np", where, "[m/s]"),
    )
    c = mech.criteria(60.0)
    if not c.ok:
        raise InputError(f"{where}: {_press_failure(press, c, mech)}")
    return mech


def _press_failure(press: GearLeverPress, c: PressCriteria, mech: PressMechanism) -> str:
    """Why the press design ``c`` does not work, with the keys to change and their
    admissible values."""
    if c.status == STATUS[1]:
        # The rod reaches the guide x = offset iff |x_pin − offset| < L all the turn.
        # The pin's path is the planet's, whatever L and offset: trace it with a rod
        # that always reaches (α counts from a BDC, which this design lacks).
        tracer = replace(press, L=2.0 * (press.R + press.d) + 1.0, offset=0.0)
        x = tracer.solve(np.linspace(0.0, 2.0 * math.pi, 3601)).pin[:, 0]
        lo, hi = float(x.min()), float(x.max())
        reach = max(hi - press.offset, press.offset - lo)
        text = (
            f"the rod (L = {press.L:g} m) cannot reach the slider's guide x = offset = "
            f"{press.offset:g} m all the turn: the pin runs over x = {lo:.4g} … {hi:.4g} m, so "
            f"L must exceed {reach:.4g} m at this offset"
        )
        if hi - lo < 2.0 * press.L:
            text += f", or offset must lie in ({hi - press.L:.4g}, {lo + press.L:.4g}) m for this L"
        return text
    if c.status == STATUS[3]:
        S_n = press.criteria(omega=1.0, k_Sp=1.0).S_n
        return (
            f"working_stroke = {mech.working_stroke!r} m exceeds the nominal stroke "
            f"S_n = {S_n:.4g} m of this design; give working_stroke < {S_n:.4g} m or k_Sp in (0, 1]"
        )
    given = (
        f"k_Sp = {mech.k_Sp!r}"
        if mech.working_stroke is None
        else f"working_stroke = {mech.working_stroke!r} m"
    )
    return (
        f"{c.status} ({given}): give a shorter working stroke, or change the design "
        "(d, L, phi0_deg)"
    )


def _transfer(
    key: str, spec: Mapping[str, Any], cg: Cyclogram, source: str, where: str, points: int
) -> TransferMechanism:
    _toml.check_keys(spec, _TRANSFER_KEYS, source, f"[mechanism.{key}]")
    _require(spec, ("R_t", "R_p", "gap", "pockets_t", "pockets_p"), where)
    R_t, R_p = _number(spec, "R_t", where, "[m]"), _number(spec, "R_p", where, "[m]")
    gap = _number(spec, "gap", where, "[m]")
    pockets = []
    for k in ("pockets_t", "pockets_p"):
        v = spec[k]
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= 10_000:
            raise InputError(f"{where}: {k} = {v!r} must be a whole number of pockets ≥ 1")
        pockets.append(v)
    if gap <= 0:
        raise InputError(f"{where}: gap = {gap!r} must be positive [m] (pitch circles apart)")
    x2 = _number(spec, "x2", where, "[m]") if "x2" in spec else None
    if x2 is None:
        w = RAD_PER_S_PER_RPM
        x2 = design_transfer(R_t, R_p, gap, (w * R_t / pockets[0], w * R_p / pockets[1])).x2
    path = TransferPath(R_t, R_p, (0.0, 0.0), (R_t + R_p + gap, 0.0), x2)
    return TransferMechanism(
        key,
        path,
        pockets[0],
        pockets[1],
        _optional(spec, "max_jerk", where, "[m/s³]"),
        _optional(spec, "max_acceleration", where, "[m/s²]"),
    )
