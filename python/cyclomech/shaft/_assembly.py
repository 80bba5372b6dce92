"""The machine's main shaft: each mechanism's shaft torque at its phase in the
optimised cyclogram, summed, and its flywheel (:class:`MainShaft`,
:func:`main_shaft`); part of :mod:`cyclomech.shaft` (issue 19)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._arrays import instance
from ..cyclogram import Cyclogram, Optimum
from ._flatten import Flattening, flatten_phases
from ._torque import ShaftStats, ShaftTorque

__all__ = ["MainShaft", "main_shaft"]


@dataclass(frozen=True)
class MainShaft:
    """The main shaft at the optimum: the summed torque, its parts and statistics.

    The statistics at the sweep's speeds use the same curves and phases, those of
    the nominal speed's optimum, at each speed — the ω² part scales, the layout does
    not follow each speed's own optimum. With ``[machine] flatten_torque``,
    ``flattening`` says how the parts were moved within the cyclogram's slack, and
    ``torque``, ``parts`` and the statistics are at the moved phases (the rest of the
    report stays at the optimum). Built by :func:`main_shaft`; each parameter is kept
    as the attribute of the same name.

    Parameters
    ----------
    torque : ShaftTorque
        The sum of the parts [N·m].
    parts : dict of str to ShaftTorque
        Each contributing mechanism's torque, at its phase [N·m].
    speed_fluctuation : float
        The coefficient of speed fluctuation δ of the statistics.
    nominal_rpm : float
        The nominal speed [rpm].
    at_nominal : ShaftStats
        The statistics at the nominal speed.
    over_speed : ShaftStats
        The statistics at the sweep's speeds.
    flattening : Flattening, optional
        How the parts were moved (``[machine] flatten_torque``); default None.
    phases_deg : dict of str to float, optional
        The phase [deg] each part was read at (its ``shaft_torque()`` phase, plus
        the flattening's shift): the cycle angle where the mechanism's own angle
        is 0; other curves of the mechanism (its reduced inertia,
        :func:`cyclomech.dynamics.reduced`) are phased by it; default empty.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> list(r.shaft.parts), r.shaft.nominal_rpm, r.shaft.flattening is None
    (['lifter cam'], 300.0, True)
    """

    torque: ShaftTorque
    parts: dict[str, ShaftTorque]
    speed_fluctuation: float
    nominal_rpm: float
    at_nominal: ShaftStats
    over_speed: ShaftStats
    flattening: Flattening | None = None
    phases_deg: dict[str, float] = field(default_factory=dict)

    def json(self) -> dict[str, Any]:
        """Its ``results.json`` entry (SI, angles in degrees).

        Returns
        -------
        dict of str to Any
            The contributors, the statistics at the nominal speed, the torque over the
            cycle (every 10th angle) and the peak torque and flywheel over speed;
            ``flattening`` only with ``[machine] flatten_torque``.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> entry = r.shaft.json()
        >>> entry["contributors"], "flattening" in entry
        (['lifter cam'], False)
        """
        n, s = self.nominal_rpm, self.at_nominal
        o = self.over_speed
        flat = {} if self.flattening is None else {"flattening": self.flattening.json()}
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
            **flat,
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table.

        Returns
        -------
        header : list of str
            ``["quantity", "value"]``.
        rows : list of list
            The contributors, mean, peak, lowest and RMS torque [N·m], energy
            fluctuation [J], flywheel [kg·m²] and motor power [W] (and the flattening's
            rows).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.shaft.table()[1][0]
        ['contributing mechanisms', 'lifter cam']
        """
        s, n = self.at_nominal, self.nominal_rpm
        flat = [] if self.flattening is None else self.flattening.rows()
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
            *flat,
        ]

    def figure(self) -> Any:
        """The torque over the cycle at the nominal speed, each contribution stacked.

        Returns
        -------
        matplotlib.figure.Figure
            A new figure: torque [N·m] against the main-shaft angle [deg].

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
        >>> r.shaft.figure().axes[0].get_ylabel()
        'torque  [N·m]'
        """
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
    results: Mapping[str, Any],
    nominal_rpm: float,
    rpm: Any,
    speed_fluctuation: float,
    *,
    cyclogram: Cyclogram | None = None,
    optimum: Optimum | None = None,
) -> MainShaft | None:
    """The main shaft from the mechanisms' results that give a shaft torque.

    With ``cyclogram`` and its ``optimum``, the parts are first moved within its
    slack to the lowest peak torque (:func:`flatten_phases`;
    ``[machine] flatten_torque = true``): each result's laid-out arcs are
    ``shaft_arcs()`` where it has one, else the ``arcs`` of its ``mechanisms`` json
    entry (the cam's).

    Parameters
    ----------
    results : Mapping of str to MechanismResult
        The mechanisms' results; those with ``shaft_torque()`` → (ω² part
        [N·m·s²], static part [N·m], on a common grid of the mechanism's own angle
        from 0 to 360°; phase [deg], the cycle angle where that angle is 0; the
        cyclogram event the phase follows) contribute.
    nominal_rpm : float
        The nominal speed [rpm].
    rpm : array_like of float
        The sweep's speeds [rpm].
    speed_fluctuation : float
        The coefficient of speed fluctuation δ, for the flywheel.
    cyclogram : Cyclogram, optional
        The cyclogram at the nominal speed, with the mechanisms' bounds; default
        None (no flattening).
    optimum : Optimum, optional
        Its optimum; default None (no flattening).

    Returns
    -------
    MainShaft or None
        The main shaft; None when no result gives a shaft torque.

    Raises
    ------
    TypeError
        If ``results`` is not a mapping.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/stb_loom.toml"), progress=False)
    >>> list(r.shaft.parts), round(float(r.shaft.at_nominal.mean_torque_nm), 4)  # drag + friction
    (['lifter cam'], 0.1659)
    """
    instance("results", results, Mapping)  # a wrong object fails here, by name
    curves = {}
    for k, res in results.items():
        get = getattr(res, "shaft_torque", None)
        c = None if get is None else get()
        if c is not None:
            curves[k] = c
    if not curves:
        return None
    flat = None
    if cyclogram is not None and optimum is not None:
        laid = {k: _laid_out(results[k]) for k in curves}
        flat = flatten_phases(curves, cyclogram, optimum, nominal_rpm, rigid=laid)
        curves = {
            k: (a, b, phase + flat.shifts_deg[k], ev) for k, (a, b, phase, ev) in curves.items()
        }
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
        flattening=flat,
        phases_deg={k: float(phase) for k, (_a, _b, phase, _event) in curves.items()},
    )


def _laid_out(result: Any) -> list[str]:
    """The events of the arcs a mechanism's curve is laid out on (it must move
    rigidly with them): ``shaft_arcs()`` if its result has one, else the ``arcs``
    its ``mechanisms`` json entry lists (the cam's segments); none otherwise."""
    get = getattr(result, "shaft_arcs", None)
    if get is not None:
        arcs = get()
    else:
        entry = result.json().get("mechanisms", {}) if hasattr(result, "json") else {}
        arcs = entry.get("arcs", []) if isinstance(entry, Mapping) else []
    return [str(e) for arc in arcs or [] for e in arc]
