"""Sizing a servo axis from a motor catalogue: `_sizing` part of
:mod:`cyclomech.servo` (its door)."""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, real_array, speeds_rpm, threads_arg
from .._errors import CyclomechWarning, InputError
from .._units import RAD_PER_S_PER_RPM
from ._axis import CHECKS, ServoAxis
from ._catalogue import load_catalogue
from ._parts import Gearbox, Motor

__all__ = ["Sizing", "SizingRow", "size"]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class SizingRow:
    """One motor on one gear ratio: its smallest margin of each check over the speeds.

    Each parameter is kept as the attribute of the same name; a margin is
    1 − used/available (≥ 0 passes), the smallest over the machine's speeds.

    Parameters
    ----------
    motor : str
        The motor's name.
    ratio : float
        The gear ratio (motor speed / load speed).
    peak_torque_margin : float
        Of the peak ``|torque|`` against the motor's peak torque.
    rms_torque_margin : float
        Of the RMS torque against the motor's rated torque (thermal).
    speed_margin : float
        Of the peak ``|speed|`` against the motor's maximum speed.
    inertia_ratio_margin : float
        Of the inertia ratio against the axis's limit.
    binding : str
        The check with the smallest margin (a name of :data:`CHECKS`).
    passes : bool
        Every margin ≥ 0.

    Examples
    --------
    >>> import cyclomech as cm
    >>> row = cm.servo.SizingRow("M1", 5.0, 0.4, 0.1, 0.6, 0.8, "rms_torque", True)
    >>> row.binding, row.passes
    ('rms_torque', True)
    """

    motor: str
    ratio: float
    peak_torque_margin: float
    rms_torque_margin: float
    speed_margin: float
    inertia_ratio_margin: float
    binding: str
    passes: bool


@dataclass(frozen=True)
class Sizing:
    """The smallest motor of a catalogue and its best gear ratio for a servo axis.

    Built by :func:`size`; each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    status : str
        "ok", or "no motor passes" (then ``choice`` is the nearest candidate, the
        pair with the largest smallest margin, and a :class:`~cyclomech.CyclomechWarning`
        was issued naming its binding check).
    motor : Motor or None
        The chosen motor (None if no motor passes).
    gearbox : Gearbox or None
        The axis's gearbox with the chosen ratio (None if no motor passes).
    choice : SizingRow
        The chosen pair's margins, or the nearest candidate's if none passes.
    runners_up : tuple of SizingRow
        The pairs ranked next: passing pairs (fewer than asked if fewer pass) or,
        if none passes, the next nearest.
    rpm : ndarray of float
        The machine's speeds checked [rpm].
    ratios : ndarray of float, shape (R,)
        The gear ratios tried.
    motors : tuple of Motor
        The catalogue, shape (M,).
    margins : ndarray of float, shape (M, R, 4)
        Every candidate's smallest margin of each of :data:`CHECKS` over the speeds.
    worst_rpm : ndarray of float, shape (M, R, 4)
        The speed at which each of those margins is smallest [rpm] (the first such
        speed; the inertia ratio's, the same at every speed, is the first speed).

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.motion.Segment
    >>> prog = cm.motion.Program([S("cycloidal", 120, end=0.1), S("dwell", 60),
    ...                           S("cycloidal", 120, end=0.0), S("dwell", 60)])
    >>> ax = cm.servo.ServoAxis(prog, cm.servo.LinearLoad(mass_kg=8.0, lead_m=0.02))
    >>> result = cm.servo.size(ax, "examples/motors.csv", [1.0, 2.0, 3.0], 100.0)
    >>> result.margins.shape, result.status
    ((16, 3, 4), 'ok')
    """

    status: str
    motor: Motor | None
    gearbox: Gearbox | None
    choice: SizingRow
    runners_up: tuple[SizingRow, ...]
    rpm: Array
    ratios: Array
    motors: tuple[Motor, ...]
    margins: Array
    worst_rpm: Array


def _motors(catalogue: Any) -> tuple[Motor, ...]:
    if isinstance(catalogue, str | os.PathLike):
        return load_catalogue(catalogue)
    if isinstance(catalogue, bytes | dict) or not hasattr(catalogue, "__len__"):
        raise TypeError(
            "catalogue must be a path to a motor CSV or a sequence of Motor; "
            f"got {type(catalogue).__name__}"
        )
    motors = tuple(catalogue)
    for i, m in enumerate(motors):
        if not isinstance(m, Motor):
            raise TypeError(f"catalogue[{i}] must be a Motor; got {type(m).__name__}")
    if not motors:
        raise InputError("catalogue must hold at least one motor; got none")
    names = [m.name for m in motors]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"catalogue: motor name {twice[0]!r} is given twice; names must differ")
    return motors


def _row(motor: Motor, ratio: float, margins: Array) -> SizingRow:
    c = int(np.argmin(margins))
    peak, rms, speed, inertia = (float(v) for v in margins)
    passes = bool(margins.min() >= 0.0)
    return SizingRow(motor.name, float(ratio), peak, rms, speed, inertia, CHECKS[c], passes)


def _ranked(motors: tuple[Motor, ...], ratios: Array, margins: Array) -> list[tuple[int, int]]:
    """Every (motor, ratio) pair, best first: passing pairs by the motor's rank
    (lowest rated torque, then lowest rotor inertia, then name) and, for one motor,
    by the largest smallest margin (then the lower ratio); then failing pairs by
    the largest smallest margin (the nearest first)."""
    rank = sorted(
        range(len(motors)),
        key=lambda m: (motors[m].rated_torque_nm, motors[m].inertia_kg_m2, motors[m].name),
    )
    place = {m: p for p, m in enumerate(rank)}
    least = margins.min(axis=2)
    pairs = [(m, r) for m in range(len(motors)) for r in range(len(ratios))]

    def key(pair: tuple[int, int]) -> tuple[Any, ...]:
        m, r = pair
        if least[m, r] >= 0.0:
            return (0, place[m], -least[m, r], ratios[r])
        return (1, -least[m, r], place[m], ratios[r])

    return sorted(pairs, key=key)


def size(
    axis: ServoAxis,
    catalogue: Any,
    ratios: Any,
    rpm: Any,
    *,
    runners_up: int = 5,
    n_threads: int | None = None,
) -> Sizing:
    """The smallest motor of a catalogue and the best gear ratio for a servo axis.

    Every motor × ratio × speed is checked (the :data:`CHECKS` of
    :meth:`ServoAxis.duty`, with the axis's load, gearbox efficiency and inertia
    and inertia-ratio limit) in one Rust call. The rules: the **smallest motor**
    is the one of lowest rated torque (then lowest rotor inertia, then name) that
    passes every check at every speed with some ratio; its **best ratio** is the
    passing one with the largest smallest margin (over the checks and speeds;
    the lower ratio on a tie). The runners-up are the pairs ranked next by the
    same rules (the chosen motor's other passing ratios first). If no pair
    passes, the result says so in ``status``, ``choice`` is the nearest pair (the
    largest smallest margin) and a :class:`~cyclomech.CyclomechWarning` names its binding
    check: never an empty answer.

    Parameters
    ----------
    axis : ServoAxis
        The axis (its motor, if any, is not used).
    catalogue : str, path-like or sequence of Motor
        A motor catalogue CSV (:func:`load_catalogue`) or the motors.
    ratios : float or array_like of float
        The gear ratios to try (motor speed / load speed), each > 0.
    rpm : float or array_like of float
        The machine's speed(s) [rpm]: a motor must pass at every one.
    runners_up : int, optional
        How many runners-up to list, ≥ 0; default 5.
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    Sizing
        The choice, its margins, the runners-up and every candidate's margins.

    Raises
    ------
    InputError
        If the catalogue cannot be read, a ratio is not > 0 or a speed is out of range.
    TypeError
        If ``axis`` is not a ServoAxis or ``catalogue`` not a path or motors.

    Warns
    -----
    CyclomechWarning
        If no motor passes every check with any ratio at every speed.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.motion.Segment   # a 100 mm rise and return on a ball screw, 20 mm lead
    >>> prog = cm.motion.Program([S("cycloidal", 120, end=0.1), S("dwell", 60),
    ...                           S("cycloidal", 120, end=0.0), S("dwell", 60)])
    >>> ax = cm.servo.ServoAxis(prog, cm.servo.LinearLoad(mass_kg=8.0, lead_m=0.02, force_n=30.0),
    ...                         cm.servo.Gearbox(1.0, efficiency=0.9))
    >>> best = cm.servo.size(ax, "examples/motors.csv", [1.0, 2.0, 3.0, 5.0], [60.0, 100.0])
    >>> best.motor.name, best.gearbox.ratio, best.choice.binding
    ('AC-040-032', 2.0, 'speed')
    >>> [(row.motor, row.ratio) for row in best.runners_up[:2]]
    [('AC-060-064', 1.0), ('AC-060-064', 2.0)]
    """
    if not isinstance(axis, ServoAxis):
        raise TypeError(f"axis must be a ServoAxis; got {type(axis).__name__}")
    motors = _motors(catalogue)
    ratio = real_array("ratios", ratios, "(gear ratios)", low=0.0, strict=True).reshape(-1)
    if ratio.size == 0:
        raise InputError("ratios must hold at least one gear ratio; got none")
    n = speeds_rpm("rpm", rpm)
    keep = count("runners_up", runners_up, low=0)
    gear = axis.gearbox
    margins, worst = _core.servo_size(
        *axis._kernel_load(gear),
        ratio,
        gear.inertia_kg_m2,
        np.array([m.inertia_kg_m2 for m in motors]),
        np.array([m.peak_torque_nm for m in motors]),
        np.array([m.rated_torque_nm for m in motors]),
        np.array([m.max_rpm for m in motors]) * RAD_PER_S_PER_RPM,
        n * RAD_PER_S_PER_RPM,
        axis.inertia_ratio_limit,
        n_threads=threads_arg(n_threads),
    )
    order = _ranked(motors, ratio, margins)
    rows = [_row(motors[m], ratio[r], margins[m, r]) for m, r in order[: keep + 1]]
    first = rows[0]
    if first.passes:  # the runners-up of a choice pass too; failing pairs only when none does
        rows = [row for row in rows if row.passes]
    chosen = motors[order[0][0]]
    if not first.passes:
        c = CHECKS.index(first.binding)
        at = n[worst[order[0]][c]]
        warnings.warn(
            f"no motor of the catalogue passes every check at every speed with any ratio; "
            f"the nearest, {chosen.name!r} with ratio {first.ratio:g}, fails {first.binding} "
            f"(margin {margins[order[0]][c]:.3g} at {at:g} rpm)",
            CyclomechWarning,
            stacklevel=2,
        )
    return Sizing(
        status="ok" if first.passes else "no motor passes",
        motor=chosen if first.passes else None,
        gearbox=Gearbox(first.ratio, gear.efficiency, gear.inertia_kg_m2) if first.passes else None,
        choice=first,
        runners_up=tuple(rows[1:]),
        rpm=n,
        ratios=ratio,
        motors=motors,
        margins=margins,
        worst_rpm=n[worst],
    )
