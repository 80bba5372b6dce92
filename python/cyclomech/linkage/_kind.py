"""The ``linkage`` mechanism kind of a machine file: a planar linkage whose crank
turns once per machine cycle (seed 001)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .. import _toml
from .._errors import InputError
from .._kind import Context, PlainResult, Save, TableContext, Unbounded
from .._units import RAD_PER_S_PER_RPM
from ._file import _LINKAGE_KEYS
from ._linkage import Linkage
from ._solution import LinkageSolution

__all__ = ["LinkageMechanism"]


@dataclass(frozen=True)
class LinkageMechanism(Unbounded):
    """A planar linkage driven by the main shaft (one crank turn per machine
    cycle); ``output`` is the point whose motion is reported, and
    ``max_acceleration`` [m/s²] an optional limit on its acceleration.

    >>> import cyclomech as cm
    >>> knife = cm.Machine.from_toml("examples/knife_cutter.toml").mechanisms["knife"]
    >>> knife.kind, knife.output
    ('linkage', 'E')
    """

    kind: ClassVar[str] = "linkage"
    keys: ClassVar[frozenset[str]] = frozenset(_LINKAGE_KEYS | {"kind", "max_acceleration"})
    fixed_keys: ClassVar[frozenset[str]] = frozenset({"kind", "name"})
    name: str
    linkage: Linkage
    output: str
    max_acceleration: float | None = None
    #: Crank angles per turn (the machine's ``angle_points``): the grid of
    #: :meth:`solve`, :meth:`peaks` and :meth:`speed_limit_rpm` unless given another.
    points: int = 361
    _solved: dict[int, tuple[LinkageSolution, tuple[float, float]]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> LinkageMechanism:
        """Its ``[mechanism.<name>]`` table: the table of
        :meth:`cyclomech.Linkage.from_dict` plus an optional ``max_acceleration``
        [m/s²]; it must assemble over the whole turn.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> ctx = TableContext(m.cyclogram, "<doc>", 73)
        >>> LinkageMechanism.from_table("knife", m.data["mechanism"]["knife"], ctx).points
        73
        """
        where = f"[mechanism.{name}]"
        _toml.check_keys(table, set(cls.keys), ctx.source, where)
        own = {k: v for k, v in table.items() if k not in ("kind", "max_acceleration")}
        lk = Linkage.from_dict(own, ctx.source, where)
        limit = _toml.optional_positive(table, "max_acceleration", ctx.where(name), "[m/s²]")
        mech = cls(name, lk, lk.output or lk.names[-1], limit, ctx.angle_points)
        mech.peaks()  # must assemble over the whole turn
        return mech

    def solve(self, points: int | None = None) -> LinkageSolution:
        """The mechanism over one crank turn from its drawn angle, ``points``
        angles (default :attr:`points`; the last one repeats the first); solved
        once per grid.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> bool(m.mechanisms["knife"].solve(73).ok.all())
        True
        """
        n = self.points if points is None else points
        if n in self._solved:
            return self._solved[n][0]
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
        if n in self._solved:
            return self._solved[n][1]
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
        peaks = (
            float(np.nanmax(np.hypot(*sol.vel[:, k].T))),
            float(np.nanmax(np.hypot(*sol.acc[:, k].T))),
        )
        self._solved[n] = (sol, peaks)
        return peaks

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

    def analyze(self, ctx: Context) -> LinkageResult:
        """Its solution over the turn and its peaks at the nominal speed.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
        >>> r = cm.machine.analyze(m, progress=False).mechanisms["knife"]
        >>> r.solution.xy.shape[0] == m.angle_points
        True
        """
        vmax, amax = self.peaks()
        return LinkageResult(self, ctx, self.solve(), vmax, amax)


@dataclass(frozen=True)
class LinkageResult(PlainResult):
    """A linkage's solution over one crank turn and the output point's largest
    velocity and acceleration analogs [m/rad, m/rad²]."""

    mech: LinkageMechanism
    ctx: Context
    solution: LinkageSolution
    max_velocity_analog: float
    max_acceleration_analog: float

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry."""
        w = RAD_PER_S_PER_RPM * self.ctx.nominal_rpm
        return {
            "mechanisms": {
                "kind": "linkage",
                "output": self.mech.output,
                "max_velocity_analog_m_per_rad": self.max_velocity_analog,
                "max_acceleration_analog_m_per_rad2": self.max_acceleration_analog,
                "max_velocity_m_s": self.max_velocity_analog * w,
                "max_acceleration_m_s2": self.max_acceleration_analog * w * w,
                "speed_limit_rpm": self.ctx.own_limit_rpm(self.mech.name),
            }
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        info, n = self.json()["mechanisms"], self.ctx.nominal_rpm
        return ["quantity", "value"], [
            ["output point", self.mech.output],
            ["max |d xy/dφ| [m/rad]", info["max_velocity_analog_m_per_rad"]],
            ["max |d² xy/dφ²| [m/rad²]", info["max_acceleration_analog_m_per_rad2"]],
            [f"max speed at {n:g} rpm [m/s]", info["max_velocity_m_s"]],
            [f"max acceleration at {n:g} rpm [m/s²]", info["max_acceleration_m_s2"]],
            ["speed limit [rpm]", info["speed_limit_rpm"]],
        ]

    def figures(self, save: Save) -> None:
        """The mechanism with its output's path, and the output's analogs."""
        from .plot import plot_analogs, plot_linkage

        k, mech, sol = self.mech.name, self.mech, self.solution
        ax = plot_linkage(mech.linkage, sol, 0, trace=[mech.output], title=f"{k}: mechanism")
        save(
            ax.figure,
            f"{k}_mechanism",
            f"The mechanism at its drawn angle, with the path of {mech.output}.",
        )
        save(
            plot_analogs(sol, mech.output, title=f"{k}: analogs of {mech.output}"),
            f"{k}_analogs",
            f"Position, velocity and acceleration analogs of {mech.output} over the turn.",
        )
