"""The machine's main shaft: each mechanism's shaft torque at its phase in the
optimised cyclogram, summed; part of :mod:`cyclomech.machine` (issue 19)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..shaft import ShaftStats, ShaftTorque

__all__ = ["MainShaft", "main_shaft"]


@dataclass(frozen=True)
class MainShaft:
    """The main shaft at the optimum: ``torque`` (the sum) and ``parts`` (each
    contributing mechanism's, at its phase), the statistics at the nominal speed
    (``at_nominal``) and at the sweep's speeds (``over_speed``) for the coefficient
    of speed fluctuation ``speed_fluctuation``."""

    torque: ShaftTorque
    parts: dict[str, ShaftTorque]
    speed_fluctuation: float
    nominal_rpm: float
    at_nominal: ShaftStats
    over_speed: ShaftStats

    def json(self) -> dict[str, Any]:
        """Its ``results.json`` entry (SI, angles in degrees)."""
        n, s = self.nominal_rpm, self.at_nominal
        o = self.over_speed
        return {
            "contributors": list(self.parts),
            "speed_fluctuation": self.speed_fluctuation,
            "nominal_rpm": n,
            "mean_torque_nm": float(s.mean_torque_nm),
            "peak_torque_nm": float(s.peak_torque_nm),
            "lowest_torque_nm": float(s.lowest_torque_nm),
            "rms_torque_nm": float(s.rms_torque_nm),
            "energy_fluctuation_j": float(s.energy_fluctuation_j),
            "flywheel_kg_m2": float(s.flywheel_kg_m2),
            "power_w": float(s.power_w),
            "theta_deg": self.torque.theta_deg[::10],
            "torque_nm_at_nominal": self.torque.at(n)[::10],
            "speed_rpm": o.rpm,
            "peak_torque_nm_over_speed": o.peak_torque_nm,
            "flywheel_kg_m2_over_speed": o.flywheel_kg_m2,
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table."""
        s, n = self.at_nominal, self.nominal_rpm
        return ["quantity", "value"], [
            ["contributing mechanisms", ", ".join(self.parts)],
            [f"mean torque at {n:g} rpm [N·m]", float(s.mean_torque_nm)],
            [
                "peak / lowest torque [N·m]",
                f"{float(s.peak_torque_nm):.4g} / {float(s.lowest_torque_nm):.4g}",
            ],
            ["RMS torque [N·m]", float(s.rms_torque_nm)],
            ["energy fluctuation ΔE over the cycle [J]", float(s.energy_fluctuation_j)],
            [
                f"flywheel for δ = {self.speed_fluctuation:g} [kg·m²] (J = ΔE/(ω²δ))",
                float(s.flywheel_kg_m2),
            ],
            ["motor power (mean torque × ω) [W]", float(s.power_w)],
        ]

    def figure(self) -> Any:
        """The torque over the cycle at the nominal speed, each contribution stacked."""
        from .._plotting import pyplot

        plt = pyplot()
        fig, ax = plt.subplots(figsize=(8.0, 3.6), layout="constrained")
        th, n = self.torque.theta_deg, self.nominal_rpm
        base = np.zeros_like(th)
        for i, (k, t) in enumerate(self.parts.items()):
            v = t.at(n)
            ax.fill_between(th, base, base + v, alpha=0.35, color=f"C{i}", lw=0, label=k)
            base = base + v
        ax.plot(th, self.torque.at(n), color="k", lw=1.4, label="main shaft")
        ax.axhline(
            float(self.at_nominal.mean_torque_nm),
            color="0.4",
            ls="--",
            lw=1,
            label="mean (the motor's)",
        )
        ax.set_xlim(0, 360)
        ax.set_xlabel("main-shaft angle  [deg]")
        ax.set_ylabel("torque  [N·m]")
        ax.set_title(f"main shaft torque at {n:g} rpm")
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.legend(fontsize=8, loc="upper right")
        return fig


def main_shaft(
    results: Mapping[str, Any], nominal_rpm: float, rpm: Any, speed_fluctuation: float
) -> MainShaft | None:
    """The main shaft from the mechanisms' results that give a shaft torque
    (``shaft_torque()`` → (ω² part [N·m·s²], static part [N·m], on a common grid
    of the mechanism's own angle from 0 to 360°; phase [deg], the cycle angle
    where that angle is 0; the cyclogram event the phase follows); None when none
    does.

    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> list(r.shaft.parts), round(float(r.shaft.at_nominal.mean_torque_nm), 4)
    (['lifter cam'], 0.0667)
    """
    curves = {}
    for k, res in results.items():
        get = getattr(res, "shaft_torque", None)
        c = None if get is None else get()
        if c is not None:
            curves[k] = c
    if not curves:
        return None
    parts = {
        k: ShaftTorque.from_curves(a[None], b[None], [phase])
        for k, (a, b, phase, _event) in curves.items()
    }
    # The sum of the phased parts (the shift is linear: no second interpolation).
    first = next(iter(parts.values()))
    total = ShaftTorque(
        first.theta_deg,
        np.sum([p.per_omega2 for p in parts.values()], axis=0),
        np.sum([p.static for p in parts.values()], axis=0),
    )
    return MainShaft(
        torque=total,
        parts=parts,
        speed_fluctuation=speed_fluctuation,
        nominal_rpm=nominal_rpm,
        at_nominal=total.stats(nominal_rpm, speed_fluctuation),
        over_speed=total.stats(rpm, speed_fluctuation),
    )
