"""The ``press`` mechanism kind of a machine file: the planetary gear-lever press
drive whose crank turns once per machine cycle (seed 003)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np

from .. import _toml
from .._errors import InputError
from .._kind import Context, PlainResult, Save, TableContext, Unbounded
from .._units import RAD_PER_S_PER_RPM
from ._drive import STATUS, GearLeverPress, PressCriteria
from ._study import DRIVE_KEYS, drive_from_table

__all__ = ["PressMechanism"]


@dataclass(frozen=True)
class PressMechanism(Unbounded):
    """A gear-lever press drive whose crank turns once per machine cycle; the
    working stroke is ``k_Sp``·S_n or ``working_stroke`` [m]; ``max_V_np`` [m/s]
    optionally limits the slider's speed at the start of the working stroke.

    >>> import cyclomech as cm
    >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml").mechanisms["drive"]
    >>> m.kind, m.k_Sp
    ('press', 0.1)
    """

    kind: ClassVar[str] = "press"
    keys: ClassVar[frozenset[str]] = frozenset(
        DRIVE_KEYS | {"kind", "k_Sp", "working_stroke", "max_V_np"}
    )
    name: str
    press: GearLeverPress
    k_Sp: float | None = None
    working_stroke: float | None = None
    max_V_np: float | None = None

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> PressMechanism:
        """Its ``[mechanism.<name>]`` table: ``R``, ``r``, ``d``, ``L`` [m],
        ``phi0_deg`` [deg], optional ``offset`` [m]; one of ``k_Sp`` or
        ``working_stroke`` [m]; optional ``max_V_np`` [m/s]. The design must work.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> ctx = TableContext(m.cyclogram, "<doc>", 361)
        >>> PressMechanism.from_table("drive", m.data["mechanism"]["drive"], ctx).max_V_np
        0.005
        """
        where = ctx.where(name)
        _toml.check_keys(table, set(cls.keys), ctx.source, f"[mechanism.{name}]")
        if ("k_Sp" in table) == ("working_stroke" in table):
            raise InputError(
                f"{where}: give one of k_Sp (a fraction of the stroke) or working_stroke [m]"
            )
        press = drive_from_table(table, where)
        mech = cls(
            name,
            press,
            k_Sp=_toml.number(table, "k_Sp", where, "") if "k_Sp" in table else None,
            working_stroke=(
                _toml.number(table, "working_stroke", where, "[m]")
                if "working_stroke" in table
                else None
            ),
            max_V_np=_toml.optional_positive(table, "max_V_np", where, "[m/s]"),
        )
        c = mech.criteria(60.0)
        if not c.ok:
            raise InputError(f"{where}: {mech._failure(c)}")
        return mech

    def _failure(self, c: PressCriteria) -> str:
        """Why the design does not work (criteria ``c``), with the keys to change
        and their admissible values."""
        press = self.press
        if c.status == STATUS[1]:
            # The rod reaches the guide x = offset iff |x_pin − offset| < L all the
            # turn. The pin's path is the planet's, whatever L and offset: trace it
            # with a rod that always reaches (α counts from a BDC, which this design
            # lacks).
            tracer = replace(press, L=2.0 * (press.R + press.d) + 1.0, offset=0.0)
            x = tracer.solve(np.linspace(0.0, 2.0 * math.pi, 3601)).pin[:, 0]
            lo, hi = float(x.min()), float(x.max())
            reach = max(hi - press.offset, press.offset - lo)
            text = (
                f"the rod (L = {press.L:g} m) cannot reach the slider's guide x = offset = "
                f"{press.offset:g} m all the turn: the pin runs over x = {lo:.4g} … {hi:.4g} m, "
                f"so L must exceed {reach:.4g} m at this offset"
            )
            if hi - lo < 2.0 * press.L:
                text += (
                    f", or offset must lie in ({hi - press.L:.4g}, {lo + press.L:.4g}) m for this L"
                )
            return text
        if c.status == STATUS[3]:
            S_n = press.criteria(omega=1.0, k_Sp=1.0).S_n
            return (
                f"working_stroke = {self.working_stroke!r} m exceeds the nominal stroke "
                f"S_n = {S_n:.4g} m of this design; give working_stroke < {S_n:.4g} m or k_Sp "
                "in (0, 1]"
            )
        given = (
            f"k_Sp = {self.k_Sp!r}"
            if self.working_stroke is None
            else f"working_stroke = {self.working_stroke!r} m"
        )
        return (
            f"{c.status} ({given}): give a shorter working stroke, or change the design "
            "(d, L, phi0_deg)"
        )

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

    def analyze(self, ctx: Context) -> PressResult:
        """Its criteria at the nominal speed.

        >>> import cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/extrusion_press_line.toml")
        >>> r = cm.machine.analyze(m, progress=False).mechanisms["drive"]
        >>> round(r.criteria.S_n, 4)
        0.1276
        """
        return PressResult(self, ctx, self.criteria(ctx.nominal_rpm))


@dataclass(frozen=True)
class PressResult(PlainResult):
    """A press drive's working-stroke criteria at the machine's nominal speed."""

    mech: PressMechanism
    ctx: Context
    criteria: PressCriteria

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry."""
        return {
            "mechanisms": {
                "kind": "press",
                "criteria": self.criteria.as_dict(),
                "speed_limit_rpm": self.ctx.own_limit_rpm(self.mech.name),
            }
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        c = self.criteria
        return ["criterion", f"at {self.ctx.nominal_rpm:g} rpm"], [
            ["nominal stroke S_n [mm]", c.S_n * 1e3],
            ["working stroke S_p [mm]", c.S_p * 1e3],
            ["speed at the start of the working stroke V_np [mm/s]", c.V_np * 1e3],
            ["mean working speed V_cp [mm/s]", c.V_cp * 1e3],
            ["k_Vp = V_np/V_cp", c.k_Vp],
            ["k_Vmax = V_pmax/V_cp", c.k_Vmax],
            ["peak acceleration J_max [m/s²]", c.J_max],
            ["torque factor (max Π' in the working stroke) [mm]", c.torque * 1e3],
            ["speed limit [rpm]", self.ctx.own_limit_rpm(self.mech.name)],
        ]

    def figures(self, save: Save) -> None:
        """The drive at bottom dead centre and the slider's motion."""
        from .plot import plot_press

        k, mech = self.mech.name, self.mech
        res = plot_press(
            mech.press,
            0.0,
            show_motion=True,
            k_Sp=mech.k_Sp or self.criteria.k_Sp,
            title=f"{k}: gear-lever press",
        )
        fig = res[0].figure if isinstance(res, tuple) else res.figure
        save(
            fig,
            f"{k}_press",
            "The drive at bottom dead centre with the pin's hypotrochoid, and the "
            "slider's motion and transfer functions.",
        )
