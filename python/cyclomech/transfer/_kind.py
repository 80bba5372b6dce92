"""The ``transfer`` mechanism kind of a machine file: a transfer of workpieces
between two rotors, each turning one pocket per machine cycle (seed 002)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from .. import _keyrules, _toml
from .._arrays import count, instance, positive, speeds_rpm
from .._errors import InfeasibleError, InputError
from .._keydoc import KeyTable
from .._keyrules import Rule
from .._kind import Array, Context, PlainResult, Save, TableContext, Unbounded
from .._scene import Scene, cycle_angles
from .._units import RAD_PER_S_PER_RPM
from ._design import design_transfer
from ._keys import KEY_DOCS
from ._path import TransferPath

__all__ = ["TransferMechanism"]

#: The keys of a transfer's table that set a parameter of its path, by that
#: parameter's name in :class:`TransferPath` (for messages).
_PARAMS = {"R_t_m": "R_t", "R_p_m": "R_p", "gap_m": "gap", "x2_m": "x2"}


@dataclass(frozen=True)
class TransferMechanism(Unbounded):
    """A transfer of workpieces between a transfer rotor and a process rotor (seed 002).

    Each rotor turns one pocket per machine cycle, so at n rpm the peripheral speeds
    are V = 2π·R·n/(60·pockets) [m/s]. Optional limits on the workpiece's peak jerk
    and acceleration set its speed limit. The ``transfer`` kind of a machine file,
    read by :meth:`from_table`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    name : str
        The mechanism's name in the machine file.
    path : TransferPath
        The workpiece's path (pitch radii R_t, R_p [m] and transitions).
    pockets_t : int
        The transfer rotor's pockets.
    pockets_p : int
        The process rotor's pockets.
    max_jerk : float, optional
        The limit on the workpiece's peak jerk [m/s³]; default None (no limit).
    max_acceleration : float, optional
        The limit on its peak acceleration [m/s²]; default None (no limit).

    Attributes
    ----------
    kind : str
        ``"transfer"``, the ``kind`` key of its table.
    keys : frozenset of str
        The keys its table takes (their names say their units: ``R_t_m``,
        ``gap_m``, ``max_jerk_m_per_s3``, …).
    rules : tuple of Rule
        Its own plausibility rules (a value implausible for its unit warns).

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.from_toml("examples/rotor_line.toml").mechanisms["line"]
    >>> m.kind, m.pockets_t, m.pockets_p
    ('transfer', 8, 12)
    """

    kind: ClassVar[str] = "transfer"
    # Its tables' keys, its own first, for the machine-file format reference
    # (cyclomech._keydocs renders them; tests/package/test_keydocs.py holds them to the parser).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS
    keys: ClassVar[frozenset[str]] = frozenset(
        {
            "kind",
            "R_t_m",
            "R_p_m",
            "gap_m",
            "pockets_t",
            "pockets_p",
            "x2_m",
            "max_jerk_m_per_s3",
            "max_acceleration_m_per_s2",
        }
    )
    #: Its plausibility rules besides every ``_m`` key's (a length over 10 m warns):
    #: none of its own.
    rules: ClassVar[tuple[Rule, ...]] = ()
    name: str
    path: TransferPath
    pockets_t: int
    pockets_p: int
    max_jerk: float | None = None
    max_acceleration: float | None = None

    def __post_init__(self) -> None:
        # Built directly too, not only from a file: the same rule for its numbers.
        instance("path", self.path, TransferPath)
        for k in ("pockets_t", "pockets_p"):
            object.__setattr__(self, k, count(k, getattr(self, k), high=10_000, what="pockets"))
        for k, unit in (("max_jerk", "[m/s³]"), ("max_acceleration", "[m/s²]")):
            if getattr(self, k) is not None:
                object.__setattr__(self, k, positive(k, getattr(self, k), unit))

    @classmethod
    def from_table(
        cls, name: str, table: Mapping[str, Any], ctx: TableContext
    ) -> TransferMechanism:
        """A transfer from its ``[mechanism.<name>]`` table.

        The table holds ``R_t_m``, ``R_p_m``, ``gap_m`` [m], ``pockets_t``,
        ``pockets_p``; optionally ``x2_m`` [m] (default: the length of least jerk,
        :func:`cyclomech.transfer.design_transfer`), ``max_jerk_m_per_s3`` [m/s³]
        and ``max_acceleration_m_per_s2`` [m/s²]. The values are then checked for
        plausibility (a value implausible for its unit warns).

        Parameters
        ----------
        name : str
            The mechanism's name.
        table : mapping of str to Any
            Its table as read from the file.
        ctx : TableContext
            The machine's cyclogram and the file's name for messages.

        Returns
        -------
        TransferMechanism
            The mechanism.

        Raises
        ------
        InputError
            If a key is missing or unknown, or a value is malformed or out of range
            (pockets a whole number from 1 to 10 000, the gap positive).
        InfeasibleError
            If the given ``x2_m`` is too long for the gap.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml")
        >>> ctx = TableContext(m.cyclogram, "<doc>", 361)
        >>> TransferMechanism.from_table("line", m.data["mechanism"]["line"], ctx).max_jerk
        10.0
        """
        instance("ctx", ctx, TableContext)  # a dict or a str: TypeError by name
        _toml.check_keys(table, set(cls.keys), ctx.source, f"[mechanism.{name}]")
        return cls._from_checked(name, table, ctx.where(name))

    @classmethod
    def _from_checked(cls, name: str, table: Mapping[str, Any], where: str) -> TransferMechanism:
        """The mechanism from a table whose key names are checked; messages start
        with ``where`` (a machine file's ``[mechanism.<name>]`` or a transfer
        file's ``[transfer]``)."""
        _toml.require(table, ("R_t_m", "R_p_m", "gap_m", "pockets_t", "pockets_p"), where)
        R_t, R_p = (
            _toml.number(table, "R_t_m", where, "[m]"),
            _toml.number(table, "R_p_m", where, "[m]"),
        )
        gap = _toml.number(table, "gap_m", where, "[m]")
        pockets = []
        for k in ("pockets_t", "pockets_p"):
            v = table[k]
            if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= 10_000:
                raise InputError(f"{where}: {k} = {v!r} must be a whole number of pockets ≥ 1")
            pockets.append(v)
        if gap <= 0:
            raise InputError(f"{where}: gap_m = {gap!r} must be positive [m] (pitch circles apart)")
        _keyrules.check(table, cls.rules, where)
        x2 = _toml.number(table, "x2_m", where, "[m]") if "x2_m" in table else None
        try:
            if x2 is None:
                w = RAD_PER_S_PER_RPM
                speeds = (w * R_t / pockets[0], w * R_p / pockets[1])
                x2 = design_transfer(R_t, R_p, gap, speeds).x2
            path = TransferPath(R_t, R_p, (0.0, 0.0), (R_t + R_p + gap, 0.0), x2)
        except (InputError, InfeasibleError) as e:
            # The path names its parameters (R_p, x2); the message names the file's keys.
            text = str(e).replace("x2=None takes it", "without x2_m it is taken")
            named = f"{where}: {_keyrules.file_names(text, _PARAMS)}"
            if isinstance(e, InfeasibleError):
                raise InfeasibleError(named, e.conflict) from None
            raise InputError(named) from None
        return cls(
            name,
            path,
            pockets[0],
            pockets[1],
            _toml.optional_positive(table, "max_jerk_m_per_s3", where, "[m/s³]"),
            _toml.optional_positive(table, "max_acceleration_m_per_s2", where, "[m/s²]"),
        )

    def speeds(self, rpm: float) -> tuple[float, float]:
        """Peripheral speeds (V_t, V_p) [m/s] at a machine speed.

        Parameters
        ----------
        rpm : float
            The machine speed [rpm] (> 0).

        Returns
        -------
        V_t : float
            The transfer rotor's peripheral speed [m/s].
        V_p : float
            The process rotor's peripheral speed [m/s].

        Raises
        ------
        InputError
            If ``rpm`` is not a finite positive speed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml").mechanisms["line"]
        >>> [round(v, 4) for v in m.speeds(60.0)]
        [0.1178, 0.1309]
        """
        w = float(speeds_rpm("rpm", rpm)[0]) * RAD_PER_S_PER_RPM
        return (w * self.path.R_t / self.pockets_t, w * self.path.R_p / self.pockets_p)

    def peaks(self, rpm: float) -> tuple[float, float]:
        """Peak |a| [m/s²] and |da/dt| [m/s³] of the workpiece at a machine speed.

        They grow as n² and n³ (the path is fixed, the speed law scales with n).

        Parameters
        ----------
        rpm : float
            The machine speed [rpm] (> 0).

        Returns
        -------
        max_acceleration : float
            The peak acceleration [m/s²].
        max_jerk : float
            The peak jerk [m/s³].

        Raises
        ------
        InputError
            If ``rpm`` is not a finite positive speed.

        Examples
        --------
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

        Returns
        -------
        float
            The speed limit [rpm]: jerk grows as n³, acceleration as n².

        Examples
        --------
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
        """What sets :meth:`speed_limit_rpm`: the first limit reached.

        Jerk where both are reached at the same speed.

        Returns
        -------
        str
            The reason, "" without limits.

        Examples
        --------
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

    def analyze(self, ctx: Context) -> TransferResult:
        """Its speeds and peaks at the nominal speed.

        Parameters
        ----------
        ctx : Context
            What the machine computed before: the nominal speed among it.

        Returns
        -------
        TransferResult
            The peripheral speeds [m/s] and the workpiece's peak acceleration [m/s²]
            and jerk [m/s³] at the nominal speed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml")
        >>> r = cm.machine.analyze(m, progress=False).mechanisms["line"]
        >>> r.max_jerk <= m.mechanisms["line"].max_jerk * (1 + 1e-9)
        True
        """
        instance("ctx", ctx, Context)
        a, j = self.peaks(ctx.nominal_rpm)
        return TransferResult(self, ctx, self.speeds(ctx.nominal_rpm), a, j)


@dataclass(frozen=True)
class TransferResult(PlainResult):
    """A transfer's peripheral speeds [m/s] and the workpiece's peak acceleration
    [m/s²] and jerk [m/s³] at the machine's nominal speed."""

    mech: TransferMechanism
    ctx: Context
    speeds: tuple[float, float]
    max_acceleration: float
    max_jerk: float

    def scene(self, cycle_deg: Array) -> Scene | None:
        """The transfer at the main shaft's angles ``cycle_deg`` [deg], for the
        machine's animation: both pitch circles, the path, and one workpiece per
        cycle moving along it by the speed law at the nominal speed (workpiece 1 at
        the path's start at cycle angle 0: the transfer has no operation in the
        cyclogram).

        Parameters
        ----------
        cycle_deg : ndarray of float
            The main shaft's angles [deg].

        Returns
        -------
        Scene or None
            Lengths in m; never None.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/rotor_line.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> s = r.mechanisms["line"].scene(np.arange(0.0, 360.0, 30.0))
        >>> s.frames, s.ground
        (12, ('O_t', 'O_p'))
        """
        from ._scene import transfer_scene

        return transfer_scene(self, cycle_angles(cycle_deg))

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry."""
        p = self.mech.path
        return {
            "mechanisms": {
                "kind": "transfer",
                "x2_m": [p.x2_t, p.x2_p],
                "speeds_m_s": list(self.speeds),
                "max_acceleration_m_s2": self.max_acceleration,
                "max_jerk_m_s3": self.max_jerk,
                "speed_limit_rpm": self.ctx.own_limit_rpm(self.mech.name),
            }
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        info, n = self.json()["mechanisms"], self.ctx.nominal_rpm
        return ["quantity", "value"], [
            ["transition lengths x2 [mm]", ", ".join(f"{1e3 * x:.4g}" for x in info["x2_m"])],
            [
                f"peripheral speeds at {n:g} rpm [m/s]",
                ", ".join(f"{v:.4g}" for v in info["speeds_m_s"]),
            ],
            ["peak acceleration [m/s²]", info["max_acceleration_m_s2"]],
            ["peak jerk [m/s³]", info["max_jerk_m_s3"]],
            ["speed limit [rpm]", info["speed_limit_rpm"]],
        ]

    def figures(self, save: Save) -> None:
        """The workpiece's path, curvature, acceleration and jerk."""
        from .plot import plot_transfer

        k, n = self.mech.name, self.ctx.nominal_rpm
        save(
            plot_transfer(self.mech.path, speed=self.speeds, title=f"{k}: transfer at {n:g} rpm"),
            f"{k}_transfer",
            "The workpiece's path between the rotors, its curvature, acceleration and "
            "jerk at the nominal speed.",
        )
