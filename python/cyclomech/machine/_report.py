"""The design report of a whole machine: ``report.html`` (self-contained, figures
embedded), ``results.json`` (machine-readable, with a schema version), CSV tables
and the figures as PNG files.

:func:`analyze` does the work (every mechanism over its crank-angle grid, every
stop's rebound against speed and phase angle, the cyclogram's optimum and speed
limit, the speed sweep) and returns a :class:`MachineResult`; :func:`write_report`
writes it. ``cyclomech run MACHINE.toml --out DIR`` does both.

This module gathers what the report shows (the results, ``results.json``'s
summary, the CSV tables, the figures) and writes the files; the HTML page that
lays them out is :mod:`cyclomech.machine._page`.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._arrays import flag, instance
from .._errors import CyclomechWarning, InfeasibleError
from .._files import file_stem, folder_target, whole, write_csv
from .._json import jsonable
from .._kind import Context
from .._progress import progress as progress_bar
from .._units import DEG_PER_S_PER_RPM
from ..cyclogram import Optimum
from ..dynamics import machine_dynamics, machine_shaking, machine_torsion
from ..shaft import main_shaft
from . import _page
from ._efficiency import machine_efficiency
from ._kinds import KINDS
from ._model import SCHEMA, Machine, SpeedSweep
from ._resize import resize_machine
from ._result import MachineResult
from ._sensitivity import drive_sensitivities
from ._sensitivity import sensitivities as sensitivity_table

__all__ = ["MachineResult", "analyze", "write_report"]


def analyze(
    machine: Machine, *, progress: bool | None = None, sensitivities: bool = False
) -> MachineResult:
    """Solve the machine once.

    Its speed limit, the optimised cyclogram at the nominal speed, the speed sweeps
    (exact and linearised bounds) and every mechanism's results.

    Parameters
    ----------
    machine : Machine
        The machine.
    progress : bool, optional
        A progress bar on stderr; default None (when stderr is a terminal).
    sensitivities : bool, default False
        Also the speed limit's sensitivity to every numeric key of the mechanisms'
        tables and the cyclogram's operations
        (:func:`~cyclomech.machine.sensitivities`: 2 variants per key, their limits
        in one call; seconds for a machine with many keys).

    Returns
    -------
    MachineResult
        Everything the report shows (speeds [rpm], angles [deg], SI otherwise).

    Examples
    --------
    >>> import cyclomech as cm
    >>> from cyclomech.machine import analyze
    >>> r = analyze(cm.Machine.example(), progress=False)
    >>> round(r.limit.rpm, 3), round(r.optimum.objective, 3)    # 6 · 421.37 rpm · 0.1 s
    (421.37, 252.822)
    """
    from ._model import Machine

    m = instance("machine", machine, Machine)
    # Mechanisms that size themselves at the optimised timing: to a fixed point first.
    m, resizing = resize_machine(m)
    steps = ["speed limit", "optimised cyclogram", "speed sweep", "mechanisms", "main shaft"]
    steps += ["sensitivities"] if flag("sensitivities", sensitivities) else []
    steps += _drive_steps(m, sensitivities)
    seconds: dict[str, float] = {}
    with progress_bar(len(steps), m.name, progress) as bar:

        def timed(name: str, fn: Callable[[], Any]) -> Any:
            bar.set_postfix_str(name)
            t = time.perf_counter()
            out = fn()
            seconds[name] = time.perf_counter() - t
            bar.update(1)
            return out

        limit = timed("speed limit", m.speed_limit)
        nominal = m.nominal_speed(limit)
        problem = ""

        def optimum() -> Optimum | None:
            nonlocal problem
            try:
                return m.optimize(nominal)
            except InfeasibleError as e:
                problem = str(e)
                return None

        opt = timed("optimised cyclogram", optimum)
        rpm = m.speed_grid()

        def sweeps() -> tuple[SpeedSweep, SpeedSweep]:
            return m.speed_sweep(rpm), m.speed_sweep(rpm, linear=True)

        sw, sw_lin = timed("speed sweep", sweeps)
        mins, mins_by = (None, []) if opt is None else _minimums(m, nominal)
        ctx = Context(
            limit=limit,
            nominal_rpm=nominal,
            rpm=rpm,
            optimum=opt,
            cyclogram=m.cyclogram,
            bounds=sw.min_phase_deg,
            linear_bounds=sw_lin.min_phase_deg,
            mechanisms=tuple(m.mechanisms),
        )
        results = timed(
            "mechanisms", lambda: {k: mech.analyze(ctx) for k, mech in m.mechanisms.items()}
        )
        flat = m.flatten_torque and opt is not None
        shaft = timed(
            "main shaft",
            lambda: main_shaft(
                results,
                nominal,
                rpm,
                m.speed_fluctuation,
                cyclogram=m.cyclogram_at(nominal) if flat else None,
                optimum=opt if flat else None,
            ),
        )
        sens = timed("sensitivities", lambda: sensitivity_table(m)) if sensitivities else None
        r = MachineResult(
            m, limit, nominal, opt, problem, sw, sw_lin, mins, mins_by, results, seconds, shaft
        )
        r.resizing = resizing
        r.sensitivities = sens
        _drive_and_frame(r, timed)
        _fold_error_limits(r)
        if sens is not None and DRIVE_KEYS in steps:
            r.sensitivities = timed(DRIVE_KEYS, lambda: drive_sensitivities(r, sens))
    _warn(r)
    return r


#: The progress bar's step that ranks the drive's elastic keys (:func:`drive_sensitivities`).
DRIVE_KEYS = "the drive's keys"


def _drive_steps(m: Machine, sensitivities: bool) -> list[str]:
    """The progress bar's steps after the main shaft: its real speed under the
    ``[drive]``, the elastic shaft's dynamic errors and, with the sensitivities,
    the drive's elastic keys ranked against them."""
    if m.drive is None:
        return []
    steps = ["main shaft's real speed"]
    if m.drive.elastic is not None:
        steps += ["elastic shaft's dynamic errors"] + ([DRIVE_KEYS] if sensitivities else [])
    return steps


def _warn(r: MachineResult) -> None:
    """What the run must say loudly: a nominal speed above the speed limit, and a
    speed range where the machine works at no speed."""
    m, lim, sw = r.machine, r.limit, r.sweep
    if r.above_speed_limit:
        warnings.warn(f"{m.source}: {r.above_speed_limit}", CyclomechWarning, stacklevel=3)
    if lim.rpm > 0 and not np.any(sw.productivity_per_min > 0):
        lo, hi = m.speed_range_rpm
        warnings.warn(
            f"{m.source}: the machine works at none of the {sw.rpm.size} speeds of its speed "
            f"range {lo:g}–{hi:g} rpm (speed limit {lim.rpm:.2f} rpm): the speed sweep "
            "is empty",
            CyclomechWarning,
            stacklevel=3,
        )


def _drive_and_frame(r: MachineResult, timed: Callable[[str, Callable[[], Any]], Any]) -> None:
    """What the machine's motor and frame see, into ``r``: the main shaft's real speed
    under the file's ``[drive]`` and the shaking force with its ``[[balance]]`` rows,
    each step through ``timed`` (the progress bar's)."""
    m = r.machine
    r.shaking = machine_shaking(r, requests=m.balance)
    if m.drive is not None and r.shaft is not None:
        drive = m.drive
        r.dynamics = timed(
            "main shaft's real speed",
            lambda: machine_dynamics(r, drive, m.speed_fluctuation, r.limit.rpm),
        )
        if drive.elastic is not None:
            elastic, steady = drive.elastic, r.dynamics.steady
            r.torsion = timed(
                "elastic shaft's dynamic errors",
                lambda: machine_torsion(r, elastic, steady, drive.motor),
            )
    elif m.drive is not None and r.optimum is not None:
        # Without an optimum (the cyclogram does not fit at the nominal speed, a
        # failure said already) nothing is phased on the shaft: not a drive's fault.
        warnings.warn(
            f"{m.source}: [drive]: nothing loads the main shaft (no mechanism has masses or "
            "loads): no real speed and no flywheel to size",
            CyclomechWarning,
            stacklevel=3,
        )


def _fold_error_limits(r: MachineResult) -> None:
    """The dynamic errors' speed limits into the machine's: a working member whose
    error on the elastic shaft and link (``[drive.shaft]``) reaches its bound at a
    speed below the machine's limit lowers it, as a mechanism's own limit does
    (``by`` names it, ``mechanisms_rpm`` holds it as "<name> (dynamic error)"), and
    the speed sweep's productivity is 0 above it. The errors are computed with the
    mechanisms at their phases in the nominal optimum (their relative phases on the
    shaft; the twist of one take-off does not depend on its own phase)."""
    if r.torsion is None:
        return
    lim = r.limit
    rpm, by, reason = lim.rpm, lim.by, lim.reason
    extra, why = dict(lim.mechanisms_rpm), dict(lim.mechanisms_reason)
    for name, v in r.torsion.limits_rpm.items():
        if not math.isfinite(v):
            continue
        key = f"{name} (dynamic error)"
        extra[key] = v
        why[key] = r.torsion.limit_reason(name)
        if v < rpm:
            rpm, by, reason = v, key, why[key]
    if rpm == lim.rpm and extra == lim.mechanisms_rpm:
        return
    r.limit = dataclasses.replace(
        lim, rpm=rpm, by=by, reason=reason, mechanisms_rpm=extra, mechanisms_reason=why
    )
    for attr in ("sweep", "sweep_linear"):
        sw = getattr(r, attr)
        keep = sw.rpm <= rpm
        setattr(
            r,
            attr,
            dataclasses.replace(
                sw, productivity_per_min=np.where(keep, sw.productivity_per_min, 0.0)
            ),
        )


def _minimums(m: Machine, rpm: float) -> tuple[np.ndarray, list[str]]:
    """Each operation's smallest angle [deg] at ``rpm`` with the mechanisms' bounds,
    and what sets it; a tie keeps the operation's own minimum, then the first bound."""
    cg = m.cyclogram
    ops = cg.operations
    own = cg.min_angles(rpm)
    mins = own.copy()
    by = [
        f"min[{op.title}]" if v <= op.min_angle_deg else f"duration[{op.title}]"
        for op, v in zip(ops, own, strict=True)
    ]
    index = {op.arc: e for e, op in enumerate(ops)}
    angles = m.bound_angles([rpm])
    for b in m.bounds():
        e, v = index[cg.operation(b.arc).arc], float(angles[b.name][0])
        if v > mins[e]:
            mins[e], by[e] = v, b.label
    return mins, by


# --------------------------------------------------------------------- files
def _optimum(r: MachineResult) -> dict[str, Any] | None:
    """results.json's ``optimum``: the optimised cyclogram at the nominal speed, its
    limiting operation's angle and time, what binds and the shadow prices (None
    where the cyclogram does not fit there)."""
    o, cg = r.optimum, r.machine.cyclogram
    if o is None:
        return None
    assert r.minimums is not None
    lim_op = cg.operation(cg.limiting)  # type: ignore[arg-type]
    at = [op.arc for op in cg.operations].index(lim_op.arc)
    prices: dict[str, float] = {}
    for res in r.mechanisms.values():
        prices.update(res.prices())
    return {
        "speed_rpm": r.nominal_rpm,
        "limiting_deg": o.objective,
        "limiting_min_deg": float(r.minimums[at]),
        "gained_deg": o.stretch[lim_op.arc],
        "limiting_s": o.objective / (DEG_PER_S_PER_RPM * r.nominal_rpm),
        "times_deg": o.times,
        "angles_deg": o.angles,
        "minimums_deg": {op.arc: float(v) for op, v in zip(cg.operations, r.minimums, strict=True)},
        "minimum_by": {op.arc: by for op, by in zip(cg.operations, r.minimum_by, strict=True)},
        "binding": list(o.binding),
        "shadow_prices": {kk: v for kk, v in o.duals.items() if abs(v) > 1e-9},
        "shadow_prices_per_mm_rebound": prices,
        "critical": list(o.critical),
    }


def _summary(r: MachineResult) -> dict[str, Any]:
    m = r.machine
    cg = m.cyclogram
    lim_op = cg.operation(cg.limiting)  # type: ignore[arg-type]
    out: dict[str, Any] = {
        "schema": SCHEMA,
        "name": m.name,
        "source": m.source,
        "speed_range_rpm": list(m.speed_range_rpm),
        "nominal_rpm": r.nominal_rpm,
        "speed_limit": {
            "rpm": r.limit.rpm,
            "by": r.limit.by,
            "cyclogram_rpm": r.limit.cyclogram_rpm,
            "mechanisms_rpm": r.limit.mechanisms_rpm,
            "binding": list(r.limit.binding),
            "reason": r.limit.reason,
            "mechanisms_reason": r.limit.mechanisms_reason,
        },
        "limiting_operation": {"name": lim_op.title, "arc": lim_op.arc},
    }
    out["optimum"] = _optimum(r)
    if r.optimum is None:
        out["problem"] = r.problem
    out["above_speed_limit"] = r.above_speed_limit or None
    out["fails"] = r.fails  # everything that makes `cyclomech run` exit 3; [] if it works
    out.update(_asked_for(r))
    # Each mechanism's entries, by group: "mechanisms" and the groups its kind adds.
    groups: dict[str, dict[str, Any]] = {g: {} for c in KINDS.values() for g in c.json_groups}
    groups["mechanisms"] = {}
    for k, res in r.mechanisms.items():
        for g, entry in res.json().items():
            groups.setdefault(g, {})[k] = entry
    out.update(groups)
    if r.shaft is not None:
        out["shaft"] = r.shaft.json()
    if r.dynamics is not None:
        out["dynamics"] = r.dynamics.json()
    eff = machine_efficiency(r)
    if eff is not None:  # only with friction: the other machines' files stay as they were
        out["efficiency"] = {k: v for k, v in eff.items() if k != "mechanisms"}
    if r.shaking is not None:
        out["shaking"] = r.shaking.json()
    if r.torsion is not None:
        out["torsion"] = r.torsion.json()
    sw = r.sweep
    out["speed_sweep"] = {
        "speed_rpm": sw.rpm,
        "fits": sw.fits,
        "limiting_deg": sw.limiting_deg,
        "limiting_deg_linear": r.sweep_linear.limiting_deg,
        "limiting_s": sw.limiting_s,
        "productivity_per_min": sw.productivity_per_min,
        **{c: v for c, v in sw.columns.items()},
        "binding": list(sw.binding),
    }
    out["seconds"] = r.seconds
    return jsonable(out)


# --------------------------------------------------------------------- figures
def _asked_for(r: MachineResult) -> dict[str, Any]:
    """``results.json``'s entries of what the file or the caller asked for: how
    mechanisms sized themselves (``resizing``) and the speed limit's sensitivities."""
    out: dict[str, Any] = {}
    if r.resizing is not None:
        out["resizing"] = r.resizing.json()
    if r.sensitivities is not None:
        out["sensitivities"] = [x.json() for x in r.sensitivities]
    return out


def _figures(r: MachineResult, folder: Path) -> list[tuple[str, str, Path]]:
    """(section, caption, path) of every figure, written as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    from ..cyclogram.plot import plot_cyclogram
    from .plot import plot_speed_sweep

    folder.mkdir(parents=True, exist_ok=True)
    out: list[tuple[str, str, Path]] = []
    m = r.machine

    def save(fig: Any, name: str, section: str, caption: str) -> None:
        p = folder / f"{name}.png"
        with whole(p) as tmp:
            fig.savefig(tmp, dpi=110, bbox_inches="tight")
        plt.close(fig)
        out.append((section, caption, p))

    save(
        plot_speed_sweep(
            r.sweep,
            linear=r.sweep_linear if m.bounds() else None,
            limit_rpm=r.limit.rpm,
            limit_by=r.limit.by,
            title=f"{m.name}: against speed",
        ),
        "speed_sweep",
        "summary",
        "The limiting operation's optimal angle and the time it gets against speed"
        + (
            ", and each stop's smallest phase angle (exact solid, the seed's linearised form "
            "dashed)"
            if m.bounds()
            else ""
        )
        + "; the curves end at the speed limit (dashed red line), shaded above it.",
    )
    if r.optimum is not None:
        # Two figures, each legible at the page's width (side by side they were
        # shrunk to half size).
        at = f"at {r.nominal_rpm:g} rpm"
        assert r.minimums is not None
        ops = m.cyclogram.operations
        floors = {op.arc: float(v) for op, v in zip(ops, r.minimums, strict=True)}
        ax = plot_cyclogram(
            r.optimum, kind="gantt", title=f"optimised cyclogram {at}", minimums=floors
        )
        save(
            ax.figure,
            "cyclogram",
            "cyclogram",
            "The optimised cyclogram, one row per mechanism over the main-shaft turn. The "
            "critical operations (red outline) form the chain that leaves the limiting "
            "operation (orange) its angle; the hatched parts are what each operation got "
            "beyond its minimum (its own, or the bound in force, as in the operations table).",
        )
        _, polar = plt.subplots(
            figsize=(9.0, 7.2), layout="constrained", subplot_kw={"projection": "polar"}
        )
        engine = polar.figure.get_layout_engine()
        assert isinstance(engine, ConstrainedLayoutEngine)
        engine.set(w_pad=0.25, h_pad=0.1)
        plot_cyclogram(
            r.optimum,
            polar,
            kind="circular",
            title=f"circular cyclogram {at}",
            minimums=floors,
        )
        save(
            polar.figure,
            "cyclogram_circular",
            "cyclogram",
            "The same as a circular diagram: 0° at the top, the turn clockwise, one ring per "
            "mechanism from the centre out.",
        )
    for k, res in r.mechanisms.items():
        res.figures(lambda fig, name, caption, k=k: save(fig, name, k, caption))  # type: ignore[misc]
    _shaft_figures(r, save)
    return out


def _shaft_figures(r: MachineResult, save: Callable[[Any, str, str, str], None]) -> None:
    """The main shaft's figures, handed to ``save``: its torque at the nominal speed
    and, under the file's drive, its real speed and the motor's torque; and the
    frame's shaking force and moment."""
    if r.shaking is not None:
        save(
            r.shaking.figure(),
            "shaking",
            "frame",
            "The force the machine's moving parts put on the frame over the cycle at the "
            "nominal speed (inertia only: −Σ m·a_G, each mechanism at its phase in the "
            "optimised cyclogram): left, the tip of the force vector (its hodograph); "
            "right, the moment.",
        )
        for k, fig in r.shaking.balance_figures():
            save(
                fig,
                f"balance_{file_stem(k)}",
                "frame",
                f"The shaking force of {k} before (grey) and after the counterweights of "
                "its [[balance]] row, at the nominal speed.",
            )
    if r.shaft is not None:
        save(
            r.shaft.figure(),
            "main_shaft",
            "shaft",
            "The torque the main shaft must supply over the cycle at the nominal speed: each "
            "mechanism's at its phase in the optimised cyclogram, stacked; dashed, the mean "
            "(what the motor supplies; the flywheel takes up the rest).",
        )
    fig = None if r.dynamics is None else r.dynamics.figure()
    if fig is not None:
        save(
            fig,
            "main_shaft_speed",
            "shaft",
            "The main shaft's real speed over the cycle under its motor, and the motor's "
            "torque: the machine's equation of motion with its reduced inertia (the "
            "mechanisms' masses at their phases, the flywheel, the rotor through the gear) "
            "in its periodic steady state.",
        )
    fig = None if r.torsion is None else r.torsion.figure()
    if fig is not None:
        save(
            fig,
            "main_shaft_torsion",
            "shaft",
            "The working members' dynamic errors (where each is minus where the rigid "
            "machine puts it at the same motor angle) and the main shaft's twist at each "
            "take-off over the cycle, under the motor at its steady state: the shaft as "
            "torsional springs between the take-off points, each working member on its "
            "elastic link ([drive.shaft], [drive.link.…]).",
        )


def write_report(result: MachineResult, out: str | Path, *, figures: bool = True) -> list[Path]:
    """Write the machine's report, results and tables to the folder ``out``.

    ``report.html``, ``results.json``, ``speed_sweep.csv``, ``operations.csv``,
    ``main_shaft.csv`` (the torque over the cycle at the nominal speed, total and
    each mechanism's, when a mechanism loads the shaft), ``main_shaft_speed.csv``
    (its real speed and the motor's torque over the cycle, with a ``[drive]``),
    ``<mechanism>_forces.csv``
    (a linkage's driving torque, guide forces and joint forces over its crank turn,
    when it has masses or loads), a mechanism's own files (a servo axis's cam
    tables and motor curve: ``<axis>_cam_table.csv``, ``<axis>_cam_coefficients.csv``,
    ``<axis>_motor.csv``) and ``figures/*.png`` (figures need matplotlib).

    Parameters
    ----------
    result : MachineResult
        What :func:`analyze` computed.
    out : str or Path
        The folder (created if missing).
    figures : bool, default True
        Draw the figures (PNG files, embedded in the report).

    Returns
    -------
    list of Path
        The paths written.

    Raises
    ------
    InputError
        If ``out`` is empty (``""`` would fill the current folder), not a path, or
        a file; if ``result`` is not a :class:`MachineResult`.
    OSError
        If a file cannot be written (a full disk, no permission), naming it; each
        file is written whole or not at all, and ``report.html`` and
        ``results.json`` last.

    Examples
    --------
    >>> import pathlib, tempfile, cyclomech as cm
    >>> from cyclomech.machine import analyze, write_report
    >>> r = analyze(cm.Machine.example(), progress=False)
    >>> sorted(p.name for p in write_report(r, tempfile.mkdtemp(), figures=False))
    ['operations.csv', 'report.html', 'results.json', 'speed_sweep.csv']
    """
    instance("result", result, MachineResult)
    figures = flag("figures", figures)
    folder = folder_target("out", out)  # "" would fill the current folder: refused
    folder.mkdir(parents=True, exist_ok=True)
    # results.json and report.html are written last, and an earlier run's removed
    # first: a run interrupted on the way leaves neither, not a folder that looks done.
    for name in ("report.html", "results.json"):
        (folder / name).unlink(missing_ok=True)
    summary = _summary(result)
    written: list[Path] = []
    cycle_files: list[str] = []  # over the cycle, for the report's Files section
    for name, (header, rows) in tables(result).items():
        if name not in ("speed_sweep.csv", "operations.csv"):
            cycle_files.append(name)
        written.append(write_csv(folder / name, header, rows))
    for res in result.mechanisms.values():
        # A kind's own files (a servo axis's cam tables), by an optional hook.
        own = getattr(res, "files", None)
        for p in own(folder) if own is not None else ():
            cycle_files.append(p.name)
            written.append(p)
    figs: list[tuple[str, str, Path]] = []
    if figures:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            figs = []
        else:
            figs = _figures(result, folder / "figures")
    for p, text in [
        (folder / "results.json", json.dumps(summary, indent=2, ensure_ascii=False)),
        (folder / "report.html", _page.page(result, summary, figs, cycle_files)),
    ]:
        with whole(p) as tmp:
            tmp.write_text(text, encoding="utf-8")
        written.append(p)
    written += [f[2] for f in figs]
    return written


def tables(r: MachineResult) -> dict[str, tuple[list[str], list[list[Any]]]]:
    """Every CSV table of the report, by file name → (header, rows): the speed
    sweep, the operations at the optimum and the tables over the cycle
    (:func:`write_report` writes them; :meth:`MachineResult.to_pandas` gives each
    as a DataFrame).

    >>> import cyclomech as cm
    >>> list(tables(cm.machine.analyze(cm.Machine.example(), progress=False)))
    ['speed_sweep.csv', 'operations.csv']
    """
    out = {"speed_sweep.csv": _sweep_table(r), "operations.csv": _operations_table(r)}
    for name, header, rows in _cycle_tables(r):
        out[name] = (header, rows)
    return out


def _sweep_table(r: MachineResult) -> tuple[list[str], list[list[Any]]]:
    """``speed_sweep.csv``: the key figures at each speed [rpm] (the limiting
    operation's angle [deg], exact and linearised, its time [s], the productivity
    [1/min]), the kinds' sweep columns, each mechanism's CSV columns and what
    binds.

    >>> import cyclomech as cm
    >>> header, rows = _sweep_table(cm.machine.analyze(cm.Machine.example(), progress=False))
    >>> header[:3], len(rows)
    (['speed_rpm', 'fits', 'limiting_deg'], 61)
    """
    sw = r.sweep
    header = [
        "speed_rpm",
        "fits",
        "limiting_deg",
        "limiting_deg_linear",
        "limiting_s",
        "productivity_per_min",
        *sw.columns,
    ]
    cols: list[Any] = [
        sw.rpm,
        sw.fits,
        sw.limiting_deg,
        r.sweep_linear.limiting_deg,
        sw.limiting_s,
        sw.productivity_per_min,
        *sw.columns.values(),
    ]
    for res in r.mechanisms.values():
        for name, column in res.csv_columns():
            header.append(name)
            cols.append(column)
    header.append("binding")
    cols.append(sw.binding)
    return header, [list(row) for row in zip(*cols, strict=True)]


def _operations_table(r: MachineResult) -> tuple[list[str], list[list[Any]]]:
    """``operations.csv``, the timing table: each operation of the optimum at the
    nominal speed, its minimum [deg] and what sets it, its angle and start [deg],
    what it got beyond its minimum [deg], whether it is critical, its end [deg]
    (start + angle: past the cycle where it ends in the next one) and its
    duration at the nominal speed [s] (no rows without an optimum).

    >>> import cyclomech as cm
    >>> header, rows = _operations_table(cm.machine.analyze(cm.Machine.example(), progress=False))
    >>> header[4], [round(row[4], 3) for row in rows]
    ('minimum_deg', [45.0, 42.178, 20.0, 252.822])
    """
    header = [
        "mechanism",
        "operation",
        "from",
        "to",
        "minimum_deg",
        "minimum_by",
        "angle_deg",
        "start_deg",
        "beyond_minimum_deg",
        "critical",
        "end_deg",
        "duration_s",
    ]
    rows: list[list[Any]] = []
    if r.optimum is not None:
        o, mins = r.optimum, r.minimums
        assert mins is not None
        for op, mn, by in zip(r.machine.cyclogram.operations, mins, r.minimum_by, strict=True):
            rows.append(
                [
                    op.mechanism or "",
                    op.title,
                    op.src,
                    op.dst,
                    float(mn),
                    by,
                    o.angles[op.arc],
                    o.times[op.src],
                    o.angles[op.arc] - float(mn),
                    op.arc in set(o.critical),
                    o.times[op.src] + o.angles[op.arc],
                    o.angles[op.arc] / (DEG_PER_S_PER_RPM * r.nominal_rpm),
                ]
            )
    return header, rows


def _cycle_tables(r: MachineResult) -> list[tuple[str, list[str], list[list[Any]]]]:
    """(file name, header, rows) of each table over the cycle at the nominal
    speed: ``main_shaft.csv`` (the shaft's torque [N·m], total and each
    mechanism's, at each angle [deg]) when a mechanism loads the shaft,
    ``main_shaft_speed.csv`` (its real speed [rpm], time [s] and the motor's torque
    [N·m]) under a ``[drive]``, and each
    mechanism's own (``<mechanism>_forces.csv``: a linkage's forces).

    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"), progress=False)
    >>> [name for name, _, _ in _cycle_tables(r)]
    ['main_shaft.csv', 'main_shaft_speed.csv', 'knife_forces.csv']
    """
    out: list[tuple[str, list[str], list[list[Any]]]] = []
    if r.shaft is not None:
        sh, n = r.shaft, r.nominal_rpm
        head = ["cycle_deg", "torque_nm", *(f"torque_nm[{k}]" for k in sh.parts)]
        theta = np.round(sh.torque.theta_deg, 9)  # 0.1 steps, not 0.30000000000000004
        columns = [theta, sh.torque.at(n), *(p.at(n) for p in sh.parts.values())]
        out.append(("main_shaft.csv", head, [list(row) for row in zip(*columns, strict=True)]))
    speed = None if r.dynamics is None else r.dynamics.csv()
    if speed is not None:
        out.append(("main_shaft_speed.csv", *speed))
    for k, res in r.mechanisms.items():
        over = getattr(res, "cycle_csv", lambda: None)()
        if over is not None:
            head, columns = over
            rows = [list(row) for row in zip(*columns, strict=True)]
            out.append((f"{file_stem(k)}_forces.csv", head, rows))
    return out
