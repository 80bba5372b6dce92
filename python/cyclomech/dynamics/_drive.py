"""The machine's drive (``[drive]`` of a machine file) and the main shaft's real
speed it gives (:class:`MachineDynamics`, issue 34 item 6).

:meth:`Drive.from_table` reads the table (the motor's characteristic, its gear and
rotor, the flywheel); :func:`machine_dynamics` reduces an analysed machine to its
main shaft (:func:`~cyclomech.dynamics.reduced`), sizes the flywheel by simulation
for the machine's target δ (beside the energy method's), and solves the periodic
steady state with the file's flywheel (or the sized one). The machine's report,
``results.json`` and ``cyclomech run`` read the result; a motor that cannot drive
the machine, a real δ above the target with the file's flywheel, or a mean speed
above the machine's speed limit are its failures (``cyclomech run`` exits 3).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _toml
from .._arrays import finite_number, instance
from .._errors import InputError, SolverError
from .._units import RAD_PER_S_PER_RPM
from ._elastic import ElasticShaft
from ._motor import ConstantTorque, InductionMotor, LinearMotor, Motor, TableMotor
from ._reduced import Reduced, reduced
from ._shaft import FlywheelSizing, SteadyState, size_flywheel, start_up, steady_state

__all__ = ["DRIVE_KEYS", "Drive", "MachineDynamics", "machine_dynamics"]

#: The keys of each motor's characteristic in ``[drive]`` (besides the common ones).
_MOTOR_KEYS: dict[str, tuple[str, ...]] = {
    "induction": (
        "rated_rpm",
        "synchronous_rpm",
        "breakdown_ratio",
        "rated_power_w",
        "rated_torque_nm",
    ),
    "linear": ("stall_torque_nm", "no_load_rpm"),
    "constant": ("torque_nm",),
    "table": ("speed_rpm", "torque_nm"),
}
_COMMON = ("motor", "gear_ratio", "gear_efficiency", "rotor_inertia_kg_m2", "flywheel_kg_m2")

#: Every key ``[drive]`` takes.
DRIVE_KEYS: frozenset[str] = frozenset(_COMMON) | {k for v in _MOTOR_KEYS.values() for k in v}


@dataclass(frozen=True)
class Drive:
    """The main shaft's motor (with its gear and rotor) and flywheel.

    Parameters
    ----------
    motor : Motor
        The motor, its gear and rotor.
    flywheel_kg_m2 : float or None
        The flywheel [kg·m²] (≥ 0); None: sized by simulation for the machine's δ.
    elastic : ElasticShaft, optional
        The main shaft's and the working members' elasticity (``[drive.shaft]``,
        ``[drive.link.<mechanism>]``); None: a rigid machine.

    Raises
    ------
    InputError
        If ``flywheel_kg_m2`` is not None or a finite number ≥ 0.
    TypeError
        If ``motor`` is not a :class:`Motor`.

    Examples
    --------
    >>> d = Drive.from_table({"motor": "linear", "stall_torque_nm": 40.0,
    ...                       "no_load_rpm": 3000.0, "gear_ratio": 20.0}, "m.toml")
    >>> type(d.motor).__name__, d.motor.ratio, d.flywheel_kg_m2
    ('LinearMotor', 20.0, None)
    """

    motor: Motor
    flywheel_kg_m2: float | None = None
    elastic: ElasticShaft | None = None

    def __post_init__(self) -> None:
        instance("motor", self.motor, Motor)
        if self.elastic is not None:
            instance("elastic", self.elastic, ElasticShaft)
        if self.flywheel_kg_m2 is not None:
            fw = finite_number("flywheel_kg_m2", self.flywheel_kg_m2, "[kg·m²]", low=0.0)
            object.__setattr__(self, "flywheel_kg_m2", fw)

    @classmethod
    def from_table(cls, table: Any, source: str) -> Drive:
        """The drive of a machine file's ``[drive]`` table.

        Parameters
        ----------
        table : Mapping
            The table as read.
        source : str
            The file's name, for messages.

        Returns
        -------
        Drive

        Raises
        ------
        InputError
            Naming the file, ``[drive]`` and the key: an unknown key or motor, a key of
            another motor's characteristic, a missing or bad value.

        Examples
        --------
        >>> Drive.from_table({"motor": "constant", "torque_nm": 12.0,
        ...                   "flywheel_kg_m2": 3.0}, "m.toml").flywheel_kg_m2
        3.0
        """
        where = f"{source}: [drive]"
        _toml.must_be_table(table, source, "[drive]")
        elastic = None
        if "shaft" in table:
            elastic = ElasticShaft.from_tables(table["shaft"], table.get("link", {}), source)
        elif "link" in table:
            raise InputError(f"{where}: [drive.link.…] needs [drive.shaft] (the take-off points)")
        table = {k: v for k, v in table.items() if k not in ("shaft", "link")}
        _toml.check_keys(table, DRIVE_KEYS, source, "[drive]")
        kind = table.get("motor")
        if not isinstance(kind, str) or kind not in _MOTOR_KEYS:
            raise InputError(
                f"{where}: motor = {kind!r} must be one of {', '.join(_MOTOR_KEYS)} (the "
                "motor's torque against speed: Kloss's induction motor, a linear DC or servo "
                "characteristic, a constant torque, or a table)"
            )
        foreign = sorted(set(table) - set(_COMMON) - set(_MOTOR_KEYS[kind]))
        if foreign:
            raise InputError(
                f"{where}: {', '.join(foreign)} not taken by motor = {kind!r} (its keys: "
                f"{', '.join(_MOTOR_KEYS[kind])})"
            )
        gear = {
            "ratio": table.get("gear_ratio", 1.0),
            "efficiency": table.get("gear_efficiency", 1.0),
            "rotor_kg_m2": table.get("rotor_inertia_kg_m2", 0.0),
        }
        try:
            motor = _motor(kind, table, gear)
            flywheel = table.get("flywheel_kg_m2")
            if flywheel is not None:
                if not (_toml.is_number(flywheel) and math.isfinite(flywheel) and flywheel >= 0):
                    raise InputError(f"flywheel_kg_m2 = {flywheel!r} must be finite and ≥ 0")
                flywheel = float(flywheel)
        except InputError as e:
            raise InputError(f"{where}: {_file_names(str(e))}") from None
        return cls(motor, flywheel, elastic)


def _motor(kind: str, t: Mapping[str, Any], gear: dict[str, Any]) -> Motor:
    """The motor of one characteristic from the table's keys (the classes check the
    values and name the argument, which is the key's name)."""
    need = {
        "induction": ("rated_rpm", "synchronous_rpm", "breakdown_ratio"),
        "linear": ("stall_torque_nm", "no_load_rpm"),
        "constant": ("torque_nm",),
        "table": ("speed_rpm", "torque_nm"),
    }[kind]
    missing = [k for k in need if k not in t]
    if missing:
        raise InputError(f"missing {', '.join(missing)} (needed by motor = {kind!r})")
    for k, v in t.items():
        if k not in ("motor", "speed_rpm", "torque_nm") and not _toml.is_number(v):
            raise InputError(f"{k} = {v!r} must be a number")
    if kind == "induction":
        return InductionMotor(
            t["rated_rpm"],
            t["synchronous_rpm"],
            t["breakdown_ratio"],
            rated_power_w=t.get("rated_power_w"),
            rated_torque_nm=t.get("rated_torque_nm"),
            **gear,
        )
    if kind == "linear":
        return LinearMotor(t["stall_torque_nm"], t["no_load_rpm"], **gear)
    if kind == "constant":
        if not _toml.is_number(t["torque_nm"]):
            raise InputError(f"torque_nm = {t['torque_nm']!r} must be a number")
        return ConstantTorque(t["torque_nm"], **gear)
    for k in ("speed_rpm", "torque_nm"):
        if not (isinstance(t[k], list) and all(_toml.is_number(v) for v in t[k])):
            raise InputError(f"{k} = {t[k]!r} must be an array of numbers")
    return TableMotor(t["speed_rpm"], t["torque_nm"], **gear)


def _file_names(message: str) -> str:
    """A class's message in the file's key names (``ratio`` is ``gear_ratio`` …)."""
    for arg, key in (
        ("rotor_kg_m2", "rotor_inertia_kg_m2"),
        ("efficiency", "gear_efficiency"),
        ("ratio", "gear_ratio"),
    ):
        if message.startswith(arg + " "):
            return key + message[len(arg) :]
    return message


@dataclass(frozen=True)
class MachineDynamics:
    """The main shaft's real speed under the machine's drive, at its optimised timing.

    Built by :func:`machine_dynamics`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    drive : Drive
        The drive.
    reduced : Reduced
        The machine reduced to its main shaft.
    target_speed_fluctuation : float
        The machine's δ (``[machine] speed_fluctuation``).
    speed_limit_rpm : float
        The machine's speed limit [rpm].
    steady : SteadyState or None
        The steady state with the drive's flywheel (or the sized one); None when
        there is none (``problem`` says why).
    sizing : FlywheelSizing or None
        The flywheel for the target δ by simulation, beside the energy method's;
        None when the motor cannot drive the machine.
    problem : str
        Why there is no steady state ("" when there is).
    start : str
        The start-up from rest under load with the steady state's flywheel
        (:func:`~cyclomech.dynamics.start_up`, until within 1 % of the steady
        speed for a turn): its settle time, or why the motor cannot start the
        machine loaded (a note, not a failure: machines often start unloaded); ""
        without a steady state.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> d = r.dynamics
    >>> round(d.steady.mean_rpm, 2), round(d.steady.speed_fluctuation, 4), d.failures()
    (45.1, 0.05, [])
    """

    drive: Drive
    reduced: Reduced
    target_speed_fluctuation: float
    speed_limit_rpm: float
    steady: SteadyState | None
    sizing: FlywheelSizing | None
    problem: str = ""
    start: str = ""

    @property
    def flywheel_kg_m2(self) -> float:
        """The flywheel the steady state has [kg·m²]: the file's, else the sized one
        (NaN when neither exists).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> round(r.dynamics.flywheel_kg_m2, 1)     # sized: the file gives none
        1748.6
        """
        if self.drive.flywheel_kg_m2 is not None:
            return self.drive.flywheel_kg_m2
        return math.nan if self.sizing is None else float(self.sizing.flywheel_kg_m2)

    def line(self) -> str:
        """Its one-line summary, for the CLI and the report's key figures.

        Returns
        -------
        str

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.dynamics.line()[:40]
        'Main shaft under its motor (InductionMot'
        """
        head = f"Main shaft under its motor ({type(self.drive.motor).__name__})"
        s, f = self.steady, self.sizing
        if s is None:
            return f"{head}: {self.problem}"
        given = "given" if self.drive.flywheel_kg_m2 is not None else "sized by simulation"
        text = (
            f"{head}: mean {s.mean_rpm:.2f} rpm, real δ {s.speed_fluctuation:.4g} with a "
            f"{self.flywheel_kg_m2:.4g} kg·m² flywheel ({given}); motor torque peak "
            f"{s.peak_motor_torque_nm:.4g} N·m, RMS {s.rms_motor_torque_nm:.4g} N·m"
        )
        if f is not None:
            text += (
                f"; for δ = {self.target_speed_fluctuation:g} the flywheel is "
                f"{f.flywheel_kg_m2:.4g} kg·m² by simulation, {f.energy_method_kg_m2:.4g} by "
                f"the energy method at the simulated mean speed ({100 * f.difference:+.1f} %)"
            )
        if self.start.startswith("the motor cannot start"):
            text += "; it cannot start the machine from rest under load (see the report)"
        return text

    def failures(self) -> list[str]:
        """What must not ship: no steady state, a real δ above the target with the
        file's flywheel, a mean speed above the speed limit.

        Returns
        -------
        list of str
            One line each; empty when nothing fails.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.dynamics.failures()
        []
        """
        s = self.steady
        if s is None:
            return [f"drive: {self.problem}"]
        out = []
        target = self.target_speed_fluctuation
        if self.drive.flywheel_kg_m2 is not None and s.speed_fluctuation > target:
            need = (
                ""
                if self.sizing is None
                else (
                    f"; the flywheel for δ = {target:g} is {self.sizing.flywheel_kg_m2:.4g} kg·m²"
                )
            )
            out.append(
                f"drive: the real coefficient of speed fluctuation {s.speed_fluctuation:.4g} "
                f"exceeds [machine] speed_fluctuation = {target:g} with flywheel_kg_m2 = "
                f"{self.drive.flywheel_kg_m2:g}{need}"
            )
        top = float(np.max(s.omega)) / RAD_PER_S_PER_RPM
        if top > self.speed_limit_rpm:
            out.append(
                f"drive: the motor turns the main shaft at up to {top:.2f} rpm (mean "
                f"{s.mean_rpm:.2f} rpm), above the machine's speed limit "
                f"{self.speed_limit_rpm:.2f} rpm: a larger gear ratio or a slower motor"
            )
        return out

    def json(self) -> dict[str, Any]:
        """Its ``results.json`` group ``dynamics`` (SI, speeds in rpm).

        Returns
        -------
        dict of str to Any
            The motor, the flywheels, the real δ, the mean speed, the motor's peak and
            RMS torque, the speed over the cycle (every 10th angle), and ``problem``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> g = r.dynamics.json()
        >>> g["motor"], round(g["speed_fluctuation"], 4)
        ('InductionMotor', 0.05)
        """
        s, f = self.steady, self.sizing
        out: dict[str, Any] = {
            "motor": type(self.drive.motor).__name__,
            "gear_ratio": self.drive.motor.ratio,
            "flywheel_kg_m2": self.flywheel_kg_m2,
            "flywheel_given": self.drive.flywheel_kg_m2 is not None,
            "target_speed_fluctuation": self.target_speed_fluctuation,
            "mechanisms_with_inertia": list(self.reduced.parts),
            "mechanisms_without_inertia": list(self.reduced.without_inertia),
            "problem": self.problem,
        }
        if f is not None:
            out |= {
                "flywheel_simulated_kg_m2": float(f.flywheel_kg_m2),
                "flywheel_energy_method_kg_m2": float(f.energy_method_kg_m2),
                "flywheel_difference": float(f.difference),
            }
        if s is not None:
            out |= {
                "mean_rpm": s.mean_rpm,
                "speed_fluctuation": s.speed_fluctuation,
                "period_s": s.period_s,
                "peak_motor_torque_nm": s.peak_motor_torque_nm,
                "rms_motor_torque_nm": s.rms_motor_torque_nm,
                "theta_deg": s.theta_deg[::10],
                "speed_rpm": s.omega[::10] / RAD_PER_S_PER_RPM,
                "motor_torque_nm": s.motor_torque_nm[::10],
                "start_up": self.start,
            }
        return out

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table.

        Returns
        -------
        header : list of str
            ``["quantity", "value"]``.
        rows : list of list
            The motor, the flywheels, the real δ and the motor's torques.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.dynamics.table()[1][0]
        ['motor', 'InductionMotor through a gear of ratio 32']
        """
        m, s, f = self.drive.motor, self.steady, self.sizing
        target = self.target_speed_fluctuation
        rows: list[list[Any]] = [
            ["motor", f"{type(m).__name__} through a gear of ratio {m.ratio:g}"],
            ["mechanisms in the reduced inertia", ", ".join(self.reduced.parts) or "none"],
        ]
        if self.reduced.without_inertia:
            rows.append(
                ["loading the shaft without inertia", ", ".join(self.reduced.without_inertia)]
            )
        if f is not None:
            rows += [
                [f"flywheel for δ = {target:g}, simulated [kg·m²]", float(f.flywheel_kg_m2)],
                [
                    f"flywheel for δ = {target:g}, energy method [kg·m²]",
                    float(f.energy_method_kg_m2),
                ],
                ["simulated − energy method, relative", float(f.difference)],
            ]
        if s is None:
            return ["quantity", "value"], [*rows, ["steady state", self.problem]]
        given = "file's" if self.drive.flywheel_kg_m2 is not None else "sized"
        return ["quantity", "value"], [
            *rows,
            [f"flywheel in the steady state ({given}) [kg·m²]", self.flywheel_kg_m2],
            ["mean speed [rpm]", s.mean_rpm],
            ["real coefficient of speed fluctuation δ", s.speed_fluctuation],
            [
                "speed over the cycle, lowest / highest [rpm]",
                f"{float(s.omega.min()) / RAD_PER_S_PER_RPM:.4g} / "
                f"{float(s.omega.max()) / RAD_PER_S_PER_RPM:.4g}",
            ],
            [
                "motor torque, peak / lowest / RMS [N·m]",
                f"{s.peak_motor_torque_nm:.4g} / {s.lowest_motor_torque_nm:.4g} / "
                f"{s.rms_motor_torque_nm:.4g}",
            ],
            ["start-up from rest under load", self.start],
        ]

    def figure(self) -> Any:
        """The shaft's speed and the motor's torque over the cycle.

        Returns
        -------
        matplotlib.figure.Figure or None
            None when there is no steady state.

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> type(r.dynamics.figure()).__name__
        'Figure'
        """
        s = self.steady
        if s is None:
            return None
        from .._plotting import pyplot

        fig, (ax, tq) = pyplot().subplots(
            2, 1, sharex=True, figsize=(8.0, 4.6), layout="constrained"
        )
        rpm = s.omega / RAD_PER_S_PER_RPM
        ax.plot(s.theta_deg, rpm, lw=1.4, color="C0", label="main shaft")
        ax.axhline(s.mean_rpm, color="C0", lw=0.8, ls="--", label=f"mean {s.mean_rpm:.4g} rpm")
        ax.set_ylabel("speed  [rpm]")
        ax.set_title(
            f"main shaft under its motor: δ = {s.speed_fluctuation:.3g} with a "
            f"{self.flywheel_kg_m2:.4g} kg·m² flywheel"
        )
        ax.legend(fontsize=8, loc="upper right")
        tq.plot(s.theta_deg, s.motor_torque_nm, lw=1.2, color="C3")
        tq.set_ylabel("motor torque  [N·m]")
        tq.set_xlabel("main-shaft angle  [deg]")
        for a in (ax, tq):
            a.grid(True, lw=0.4, alpha=0.5)
        return fig

    def csv(self) -> tuple[list[str], list[list[float]]] | None:
        """``main_shaft_speed.csv``: the speed and motor torque over the cycle.

        Returns
        -------
        tuple of (list of str, list of list of float) or None
            The header and the rows; None without a steady state.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.dynamics.csv()[0]
        ['theta_deg', 'speed_rpm', 'time_s', 'motor_torque_nm']
        """
        s = self.steady
        if s is None:
            return None
        cols = (s.theta_deg, s.omega / RAD_PER_S_PER_RPM, s.time_s, s.motor_torque_nm)
        head = ["theta_deg", "speed_rpm", "time_s", "motor_torque_nm"]
        return head, [list(map(float, row)) for row in zip(*cols, strict=True)]


def machine_dynamics(
    result: Any, drive: Drive, speed_fluctuation: float, speed_limit_rpm: float
) -> MachineDynamics:
    """The main shaft's real speed under ``drive`` for an analysed machine.

    The flywheel for ``speed_fluctuation`` by simulation (beside the energy
    method's); the steady state with the drive's flywheel, or with that one. A
    motor that cannot drive the machine is a ``problem``, not an exception: the
    report shows it and ``cyclomech run`` fails on it.

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result, with its main shaft.
    drive : Drive
        The drive.
    speed_fluctuation : float
        The target δ, in (0, 1).
    speed_limit_rpm : float
        The machine's speed limit [rpm].

    Returns
    -------
    MachineDynamics

    Raises
    ------
    InputError
        If nothing loads the main shaft (:func:`~cyclomech.dynamics.reduced`), or
        ``speed_fluctuation`` or ``speed_limit_rpm`` is out of its range.
    TypeError
        If ``drive`` is not a :class:`Drive`.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> d = machine_dynamics(r, r.machine.drive, 0.05, r.limit.rpm)
    >>> round(float(d.sizing.flywheel_kg_m2), 1), round(float(d.sizing.energy_method_kg_m2), 1)
    (1748.6, 1881.2)
    """
    instance("drive", drive, Drive)
    delta = finite_number("speed_fluctuation", speed_fluctuation, "(δ)", low=0.0)
    if not 0.0 < delta < 1.0:
        raise InputError(f"speed_fluctuation = {delta!r} must be the target δ, 0 < δ < 1")
    limit = float(speed_limit_rpm) if _toml.is_number(speed_limit_rpm) else math.nan
    if not (limit >= 0.0 and math.isfinite(limit)):
        raise InputError(f"speed_limit_rpm = {speed_limit_rpm!r} must be a finite speed ≥ 0 [rpm]")
    d = reduced(result)
    steady, sizing, problem = None, None, ""
    try:
        sizing = size_flywheel(d, drive.motor, delta)
    except SolverError as e:
        problem = f"the motor cannot drive the machine: {e}"
    if drive.flywheel_kg_m2 is not None:
        try:
            steady = steady_state(d, drive.motor, flywheel_kg_m2=drive.flywheel_kg_m2)
            problem = ""
        except SolverError as e:
            problem = f"the motor cannot drive the machine: {e}"
    elif sizing is not None:
        steady = sizing.steady
    start = "" if steady is None else _start(d, drive.motor, steady.flywheel_kg_m2)
    return MachineDynamics(drive, d, delta, limit, steady, sizing, problem, start)


def _start(d: Reduced, motor: Motor, flywheel: float) -> str:
    """The start-up from rest under load, in words."""
    try:
        s = start_up(d, motor, flywheel_kg_m2=flywheel, settle=0.01)
    except SolverError as e:
        return str(e)
    if math.isnan(s.settle_time_s):
        return "not within 1 % of the steady speed by the integration's time limit"
    return f"within 1 % of the steady speed after {s.settle_time_s:.3g} s"
