"""A servo axis's results in a machine: `_result` part of :mod:`cyclomech.servo`
(its door). The duty at the nominal speed on the optimised timing, the sizing from
the catalogue, the cam tables written for a drive."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._arrays import instance
from .._errors import CyclomechWarning
from .._files import file_stem, folder_target, savetxt
from .._kind import Array, BoundsResult, Context, Save
from .._scene import Scene, cycle_angles
from ..cam import MinPhaseAngles
from ..motion import Program, write_cam_coefficients, write_cam_table
from ._axis import CHECKS, Duty, ServoAxis
from ._kind import WORDS, ServoMechanism
from ._parts import Gearbox, LinearLoad
from ._sizing import Sizing, size

__all__ = ["ServoResult"]

#: How far below 0 a margin may read and pass: the duty's 3600 samples against the
#: bounds' finer solvers (a bound met with equality reads within it).
MARGIN_TOL = 1e-4

#: How each check reads in the report.
CHECK_WORDS = {
    "peak_torque": "peak torque",
    "rms_torque": "RMS torque (thermal)",
    "speed": "peak speed",
    "inertia_ratio": "inertia ratio",
}


@dataclass(frozen=True)
class ServoResult(BoundsResult):
    """A servo axis's results at the nominal speed on the optimised timing.

    Built by :meth:`ServoMechanism.analyze` (:meth:`of`); each parameter is kept
    as the attribute of the same name.

    Parameters
    ----------
    mech : ServoMechanism
        The axis as the file gives it.
    ctx : Context
        What the machine computed before it.
    program : Program
        The program laid out at the optimum's angles.
    layout_note : str
        Why it is not laid out at the optimum, if not ("" when it is).
    axis : ServoAxis
        The axis on that program.
    duty : Duty or None
        The motor's duty at the nominal speed (None without a motor).
    sizing : Sizing or None
        The smallest motor of the catalogue and its best ratio at the nominal
        speed on that timing (None without a catalogue).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"), progress=False)
    >>> res = r.mechanisms["jaw"]
    >>> res.duty.binding, res.sizing.choice.motor
    ('inertia_ratio', 'AC-130-477')
    """

    mech: ServoMechanism
    ctx: Context
    program: Program
    layout_note: str
    axis: ServoAxis
    duty: Duty | None
    sizing: Sizing | None

    @classmethod
    def of(cls, mech: ServoMechanism, ctx: Context) -> ServoResult:
        """Its results (:meth:`ServoMechanism.analyze`), warning with its problems.

        Parameters
        ----------
        mech : ServoMechanism
            The axis.
        ctx : Context
            What the machine computed before.

        Returns
        -------
        ServoResult
            Its results.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> res = r.mechanisms["film feed"]
        >>> type(ServoResult.of(res.mech, res.ctx)).__name__
        'ServoResult'
        """
        instance("mech", mech, ServoMechanism)
        instance("ctx", ctx, Context)
        n = ctx.nominal_rpm
        angles = {} if ctx.optimum is None else ctx.optimum.angles
        program, note = mech.program_at(angles)
        a = mech.axis
        axis = ServoAxis(
            program, a.load, a.gearbox, a.motor, inertia_ratio_limit=a.inertia_ratio_limit
        )
        duty = None if a.motor is None else axis.duty(n)
        sizing = None
        if mech.catalogue:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                sizing = size(axis, mech.catalogue, list(mech.ratios), [n])
            for w in caught:
                if not issubclass(w.category, CyclomechWarning):
                    warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        result = cls(mech, ctx, program, note, axis, duty, sizing)
        problems = result.problems()
        if problems:
            warnings.warn(
                f"servo axis {mech.name!r} at {n:g} rpm: " + "; ".join(problems),
                CyclomechWarning,
                stacklevel=3,
            )
        return result

    def failures(self) -> list[str]:
        """What fails at the nominal speed and must not ship: ``cyclomech run`` exits 3.

        A check of the motor that fails on the optimised timing (its margin below
        −:data:`MARGIN_TOL`: the duty samples the cycle at 3600 angles, the bounds'
        solvers finer, so a bound met with equality reads within it), or a
        catalogue with no motor that passes.

        Returns
        -------
        list of str
            One sentence per failure ([] when nothing fails).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> r.mechanisms["film feed"].failures()
        []
        """
        out = []
        if self.duty is not None:
            margins = np.asarray(self.duty.margins).reshape(-1)
            for c, m in zip(CHECKS, margins, strict=True):
                if m < -MARGIN_TOL:
                    out.append(f"its motor fails the {CHECK_WORDS[c]} check (margin {m:.3g})")
        if self.sizing is not None and self.sizing.motor is None:
            row = self.sizing.choice
            out.append(
                f"no motor of the catalogue passes with any ratio; the nearest, {row.motor!r} "
                f"with ratio {row.ratio:g}, fails {row.binding}"
            )
        return out

    def problems(self) -> list[str]:
        """What fails or is not as asked at the nominal speed: :meth:`failures` and
        the layout (a bound segment the next dwell cannot take up).

        Returns
        -------
        list of str
            One sentence per problem ([] when nothing fails).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> r.mechanisms["film feed"].problems()
        []
        """
        return ([self.layout_note] if self.layout_note else []) + self.failures()

    def scene(self, cycle_deg: Array) -> Scene | None:
        """The axis's load at the main shaft's angles ``cycle_deg`` [deg], for the
        machine's animation: where the program laid out at the optimum puts it
        (master angle = cycle angle − :attr:`master_offset_deg`): a linear load's
        carriage at x = s on its rail, a rotary load's disc turned by s.

        Parameters
        ----------
        cycle_deg : ndarray of float
            The main shaft's angles [deg].

        Returns
        -------
        Scene or None
            Lengths in m; None without an optimum.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> m = cm.Machine.from_toml("examples/flow_wrapper.toml")
        >>> r = cm.machine.analyze(m, progress=False)
        >>> s = r.mechanisms["film feed"].scene(np.arange(0.0, 360.0, 30.0))
        >>> s.frames, sorted(s.bodies)
        (12, ['carriage', 'rail'])
        """
        from ._scene import servo_scene

        return servo_scene(self, cycle_angles(cycle_deg))

    @property
    def master_offset_deg(self) -> float:
        """The cycle angle [deg] of the program's master angle 0: the drive's offset.

        Returns
        -------
        float
            In [0, 360) (:meth:`ServoMechanism.phase_deg` on the optimum's times).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> r.mechanisms["film feed"].master_offset_deg == r.optimum.times["2"]
        True
        """
        times = {} if self.ctx.optimum is None else self.ctx.optimum.times
        if self.ctx.optimum is None:
            return 0.0
        return self.mech.phase_deg(times, self.program)

    def _margins(self) -> dict[str, float]:
        assert self.duty is not None
        return {
            c: float(v)
            for c, v in zip(CHECKS, np.asarray(self.duty.margins).reshape(-1), strict=True)
        }

    def json(self) -> dict[str, dict[str, Any]]:
        """Its ``mechanisms`` entry and its ``servo_axes`` entry of ``results.json``.

        Returns
        -------
        dict of str to dict
            ``{"mechanisms": …, "servo_axes": …}`` (torques in N·m, speeds in rpm,
            energy in J, angles in deg).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> r.mechanisms["film feed"].json()["servo_axes"]["motor"]
        'AC-060-127'
        """
        m, d, a = self.mech, self.duty, self.axis
        entry: dict[str, Any] = {
            "load": "linear" if isinstance(a.load, LinearLoad) else "rotary",
            "gear_ratio": a.gearbox.ratio,
            "motor": None if a.motor is None else a.motor.name,
            "loads_main_shaft": False,
            "segment_angles_deg": [g.angle_deg for g in self.program.segments],
            "master_offset_deg": self.master_offset_deg,
            "layout_note": self.layout_note,
            "own_limit_rpm": m.speed_limit_rpm(),
            "speed_rpm": self.ctx.rpm,
            "min_phase_deg": {b.label: self.ctx.bounds[b.name] for b in m.bounds()},
        }
        if d is not None:
            entry |= {
                "peak_torque_nm": float(d.peak_torque_nm),
                "rms_torque_nm": float(d.rms_torque_nm),
                "peak_speed_rpm": float(d.peak_speed_rpm),
                "regen_energy_j": float(d.regen_energy_j),
                "inertia_ratio": d.inertia_ratio,
                "margins": self._margins(),
                "binding": d.binding,
                "status": d.status,
            }
        if self.sizing is not None:
            s = self.sizing
            entry["sizing"] = {
                "status": s.status,
                "motor": s.choice.motor,
                "ratio": s.choice.ratio,
                "binding": s.choice.binding,
                "passes": s.choice.passes,
                "margins": _row_margins(s.choice),
                "runners_up": [
                    {"motor": r.motor, "ratio": r.ratio, "binding": r.binding}
                    | {"margins": _row_margins(r)}
                    for r in s.runners_up
                ],
            }
        arcs = [list(x) for x in m.arcs if x is not None]
        return {"mechanisms": {"kind": "servo", "arcs": arcs}, "servo_axes": entry}

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table: the drive, the timing, the checks with margins, the sizing.

        Returns
        -------
        header : list of str
            ``["quantity", "value"]``.
        rows : list of list
            One row per quantity.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> r.mechanisms["jaw"].table()[1][0]
        ['drive', 'its own motor: its torque does not load the main shaft']
        """
        a, d, n = self.axis, self.duty, self.ctx.nominal_rpm
        motor = a.motor
        rows: list[list[Any]] = [
            ["drive", "its own motor: its torque does not load the main shaft"],
            ["load, gearbox", f"{_load_text(a.load)}; {_gear_text(a.gearbox)}"],
            [
                "segments at the optimum [deg]",
                ", ".join(f"{g.law} {g.angle_deg:.4g}" for g in self.program.segments),
            ],
        ]
        if self.layout_note:
            rows.append(["layout", self.layout_note])
        rows.append(
            [
                "master offset [deg]",
                f"{self.master_offset_deg:.4g}: the program's (and cam table's) master angle 0 "
                "at this cycle angle",
            ]
        )
        if motor is not None and d is not None:
            margins = self._margins()
            limits = {
                "peak_torque": (float(d.peak_torque_nm), motor.peak_torque_nm, "N·m"),
                "rms_torque": (float(d.rms_torque_nm), motor.rated_torque_nm, "N·m"),
                "speed": (float(d.peak_speed_rpm), motor.max_rpm, "rpm"),
                "inertia_ratio": (d.inertia_ratio, a.inertia_ratio_limit, ""),
            }
            reserve = self.mech.torque_reserve
            kept = f" (torques with {100 * reserve:g} % kept in reserve)" if reserve else ""
            rows.append(["motor", (motor.name or str(motor)) + kept])
            for c in CHECKS:
                used, avail, unit = limits[c]
                u = f" [{unit}]" if unit else ""
                at = "" if c == "inertia_ratio" else f" at {n:g} rpm"  # (no speed in it)
                rows.append(
                    [
                        f"{CHECK_WORDS[c]}{at}{u} (limit, margin)",
                        f"{used:.4g} ({avail:.4g}, {margins[c]:+.3f})",
                    ]
                )
            rows.append(
                [f"regenerated energy per cycle at {n:g} rpm [J]", f"{float(d.regen_energy_j):.4g}"]
            )
            rows.append(["status", d.status])
        own = self.mech.speed_limit_rpm()
        if not math.isinf(own):
            rows.append(["own speed limit [rpm]", f"{own:.2f}: {self.mech.limit_reason()}"])
        for b, law in zip(self.mech.bounds(), self.mech.laws(), strict=True):
            angle = float(law(np.array([n]))[0])
            rows.append([f"smallest angle by {b.label} at {n:g} rpm [deg]", f"{angle:.4g}"])
        if self.sizing is not None:
            s = self.sizing
            rows.append(
                [
                    f"sizing at {n:g} rpm on this timing ({s.status})",
                    _row_text(s.choice),
                ]
            )
            for i, r in enumerate(s.runners_up, 1):
                rows.append([f"runner-up {i}", _row_text(r)])
        rows.append(
            [
                "files",
                "cam tables: master angle [deg] from the program's start (the master offset "
                "above), s "
                + ("[m]" if isinstance(a.load, LinearLoad) else "[rad of the load shaft]")
                + " and its derivatives per rad of master",
            ]
        )
        return ["quantity", "value"], rows

    def files(self, folder: Path) -> list[Path]:
        """Write its files for a drive into ``folder``.

        ``<name>_cam_table.csv`` (master angle → s, v, a, j at the axis's
        ``table_points``: :func:`cyclomech.motion.write_cam_table`),
        ``<name>_cam_coefficients.csv`` (each piece's closed form:
        :func:`cyclomech.motion.write_cam_coefficients`), both for the optimised
        timing in the program's own master angle (its 0 at the cycle angle
        :attr:`master_offset_deg`, the drive's master offset), and
        ``<name>_motor.csv`` (the motor's speed [rpm] and torque [N·m] over the cycle
        at the nominal speed, with a motor).

        Parameters
        ----------
        folder : str or Path
            The folder (created if missing).

        Returns
        -------
        list of Path
            The files written.

        Examples
        --------
        >>> import tempfile, pathlib, cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> [p.name for p in r.mechanisms["jaw"].files(pathlib.Path(tempfile.mkdtemp()))]
        ['jaw_cam_table.csv', 'jaw_cam_coefficients.csv', 'jaw_motor.csv']
        """
        folder = folder_target("folder", folder)
        folder.mkdir(parents=True, exist_ok=True)
        stem = file_stem(self.mech.name)
        out = [
            write_cam_table(
                self.program, folder / f"{stem}_cam_table.csv", points=self.mech.table_points
            ),
            write_cam_coefficients(self.program, folder / f"{stem}_cam_coefficients.csv"),
        ]
        d = self.duty
        if d is not None and d.motor_rpm is not None and d.torque_nm is not None:
            table = np.column_stack([np.round(d.theta_deg, 9), d.motor_rpm, d.torque_nm])
            out.append(
                savetxt(
                    folder / f"{stem}_motor.csv",
                    table,
                    delimiter=",",
                    header="master_deg,motor_rpm,torque_nm",
                    comments="",
                    fmt="%.17g",
                )
            )
        return [Path(p) for p in out]

    def figures(self, save: Save) -> None:
        """Draw its figures and hand each to ``save``.

        The motor's torque and speed over the cycle at the nominal speed (with a
        motor) and the bound segments' smallest phase angles against speed.

        Parameters
        ----------
        save : callable
            ``save(figure, file stem, caption)``, called once per figure.

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/flow_wrapper.toml"),
        ...                        progress=False)
        >>> stems = []
        >>> r.mechanisms["film feed"].figures(lambda fig, stem, caption: stems.append(stem))
        >>> stems
        ['film_feed_duty', 'film_feed_min_phase']
        >>> plt.close("all")
        """
        from ..cam.plot import plot_min_phase_angles
        from .plot import plot_duty

        m, n, stem = self.mech, self.ctx.nominal_rpm, file_stem(self.mech.name)
        if self.duty is not None:
            axes = plot_duty(self.duty, self.axis.motor, title=f"{m.name} at {n:g} rpm")
            save(
                axes[0].figure,
                f"{stem}_duty",
                f"The motor's torque and speed over one cycle at {n:g} rpm on the optimised "
                "timing, the motor's limits in red. A servo axis has its own motor: this "
                "torque does not load the main shaft.",
            )
        segs = tuple(k for k, a in enumerate(m.arcs) if a is not None)
        if segs and m.axis.motor is not None:
            mins = m.axis.min_phase_angles(self.ctx.rpm, segments=segs)
            if "rms_torque" in m.criteria():  # one bound segment: its RMS law too
                rms = m.laws()[2](self.ctx.rpm)
                mins = MinPhaseAngles(
                    rpm=mins.rpm,
                    segments=mins.segments,
                    criteria=m.criteria(),
                    angle_deg=np.concatenate(
                        [mins.angle_deg, np.where(np.isinf(rms), np.nan, rms)[:, None, None]],
                        axis=2,
                    ),
                )
            ax = plot_min_phase_angles(
                mins,
                labels=[m._where(k) for k in segs],
                nominal_deg=[self.program.segments[k].angle_deg for k in segs],
                title=f"{m.name}: smallest phase angles against speed",
            )
            ax.set_xlabel("machine speed  [rpm]")
            save(
                ax.figure,
                f"{stem}_min_phase",
                "Each bound segment's smallest phase angle against speed by the motor's "
                + ", ".join(WORDS[c] for c in m.criteria())
                + " (the bound bold; a gap where no angle will do); horizontal: its angle at "
                "the optimum.",
            )


def _load_text(load: Any) -> str:
    """A load in the report's words."""
    if isinstance(load, LinearLoad):
        return (
            f"linear {load.mass_kg:g} kg through {load.lead_m:.4g} m per turn, "
            f"{load.force_n:g} N, η {load.efficiency:g}"
        )
    return f"rotary {load.inertia_kg_m2:g} kg·m², {load.torque_nm:g} N·m"


def _gear_text(gear: Gearbox) -> str:
    """A gearbox in the report's words."""
    return f"ratio {gear.ratio:g}, η {gear.efficiency:g}, {gear.inertia_kg_m2:g} kg·m² at the motor"


def _row_margins(row: Any) -> dict[str, float]:
    """A sizing row's margins by check."""
    return {
        "peak_torque": row.peak_torque_margin,
        "rms_torque": row.rms_torque_margin,
        "speed": row.speed_margin,
        "inertia_ratio": row.inertia_ratio_margin,
    }


def _row_text(row: Any) -> str:
    """A sizing row in the report's words: motor, ratio, its margins."""
    m = ", ".join(f"{CHECK_WORDS[c]} {v:+.3f}" for c, v in _row_margins(row).items())
    return f"{row.motor}, ratio {row.ratio:g}: margins {m} (binding {row.binding})"
