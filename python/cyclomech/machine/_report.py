"""The design report of a whole machine: ``report.html`` (self-contained, figures
embedded), ``results.json`` (machine-readable, with a schema version), CSV tables
and the figures as PNG files.

:func:`analyze` does the work (every mechanism over its crank-angle grid, every
stop's rebound against speed and phase angle, the cyclogram's optimum and speed
limit, the speed sweep) and returns a :class:`MachineResult`; :func:`write_report`
writes it. ``cyclomech run MACHINE.toml --out DIR`` does both.
"""

from __future__ import annotations

import base64
import csv
import html
import json
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._arrays import flag, instance
from .._errors import CyclomechWarning, InfeasibleError
from .._files import folder_target, whole
from .._json import jsonable
from .._kind import Context, MechanismResult
from .._progress import progress as progress_bar
from .._units import DEG_PER_S_PER_RPM
from ..cyclogram import Optimum, SpeedLimit
from ..shaft import MainShaft, main_shaft
from ._kinds import KINDS
from ._model import SCHEMA, Machine, SpeedSweep

__all__ = ["MachineResult", "analyze", "write_report"]


@dataclass
class MachineResult:
    """Everything the report shows, computed once by :func:`analyze`.

    Speeds [rpm], angles [deg], SI otherwise: the report, ``results.json``, the
    CSVs and the CLI's summary only read it. Each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    machine : Machine
        The machine.
    limit : SpeedLimit
        The speed limit.
    nominal_rpm : float
        The speed of ``optimum`` [rpm].
    optimum : Optimum or None
        The LP optimum with the mechanisms' exact bounds (None if it does not fit
        there, and ``problem`` says why).
    problem : str
        Why there is no optimum ("" when there is).
    sweep : SpeedSweep
        The key figures against speed with the exact bounds.
    sweep_linear : SpeedSweep
        The same with the seed's linearised bounds.
    minimums : ndarray of float, optional
        Each operation's smallest angle at the nominal speed [deg]: its own
        minimum angle or duration, or a mechanism's bound on it, whichever is
        larger; default None.
    minimum_by : list of str, optional
        The name of what sets each of ``minimums`` (``min[op]``, ``duration[op]``
        or the bound's label, as in the optimum's ``binding``); default an empty
        list.
    mechanisms : dict of str to MechanismResult, optional
        Each mechanism's results (:meth:`~cyclomech.machine.Mechanism.analyze`);
        default an empty dict.
    seconds : dict of str to float, optional
        The time of each step [s]; default an empty dict.
    shaft : MainShaft, optional
        The main shaft's torque and statistics, when a mechanism loads it; default
        None.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
    >>> r.problem, r.minimums.round(3).tolist(), r.shaft is None
    ('', [45.0, 42.178, 20.0, 252.822], True)
    >>> r.minimum_by[1]      # the lifter's rebound bound exceeds (3, 7)'s own 20°
    'rebound[lifter]'
    """

    machine: Machine
    limit: SpeedLimit
    nominal_rpm: float
    optimum: Optimum | None
    problem: str
    sweep: SpeedSweep
    sweep_linear: SpeedSweep
    minimums: np.ndarray | None = None
    minimum_by: list[str] = field(default_factory=list)
    mechanisms: dict[str, MechanismResult] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)
    shaft: MainShaft | None = None

    @property
    def above_speed_limit(self) -> str:
        """Why the nominal speed is above a mechanism's own speed limit ("" if it is
        not). The cyclogram may still fit there (its optimum is then computed), but
        that mechanism does not work: :func:`analyze` warns, ``cyclomech run`` exits 3.
        (Above the cyclogram's own limit there is no optimum: see ``problem``.)

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.machine.analyze(cm.Machine.example(), progress=False).above_speed_limit
        ''
        """
        over = {k: v for k, v in self.limit.mechanisms_rpm.items() if self.nominal_rpm > v}
        if not over:
            return ""
        k = min(over, key=over.__getitem__)
        return (
            f"the nominal speed {self.nominal_rpm:g} rpm is above the speed limit of "
            f"mechanism {k!r}, {over[k]:.2f} rpm ({self.limit.mechanisms_reason.get(k, '')})"
        )


def analyze(machine: Machine, *, progress: bool | None = None) -> MachineResult:
    """Solve the machine once.

    Its speed limit, the optimised cyclogram at the nominal speed, the speed sweeps
    (exact and linearised bounds) and every mechanism's results.

    Parameters
    ----------
    machine : Machine
        The machine.
    progress : bool, optional
        A progress bar on stderr; default None (when stderr is a terminal).

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
    steps = ["speed limit", "optimised cyclogram", "speed sweep", "mechanisms"]
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
    r = MachineResult(
        m, limit, nominal, opt, problem, sw, sw_lin, mins, mins_by, results, seconds, shaft
    )
    if r.above_speed_limit:
        warnings.warn(f"{m.source}: {r.above_speed_limit}", CyclomechWarning, stacklevel=2)
    if limit.rpm > 0 and not np.any(sw.productivity_per_min > 0):
        lo, hi = m.speed_range_rpm
        warnings.warn(
            f"{m.source}: the machine works at none of the {rpm.size} speeds of its speed "
            f"range {lo:g}–{hi:g} rpm (speed limit {limit.rpm:.2f} rpm): the speed sweep "
            "is empty",
            CyclomechWarning,
            stacklevel=2,
        )
    return r


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


# --------------------------------------------------------------------- tables
def _f(v: Any, digits: int = 4) -> str:
    if v is None:
        return "—"
    if isinstance(v, float | np.floating):
        if not math.isfinite(v):
            return "—" if math.isnan(v) else ("∞" if v > 0 else "−∞")
        return f"{v:.{digits}g}"
    return str(v)


def _own(by: str) -> str:
    """A minimum's source as the report says it: its own angle or duration in
    words, a mechanism's bound by its label."""
    if by.startswith("min["):
        return "its minimum angle"
    if by.startswith("duration["):
        return "its minimum duration"
    return by


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
    o = r.optimum
    if o is not None:
        assert r.minimums is not None
        at = [op.arc for op in cg.operations].index(lim_op.arc)
        prices: dict[str, float] = {}
        for res in r.mechanisms.values():
            prices.update(res.prices())
        out["optimum"] = {
            "speed_rpm": r.nominal_rpm,
            "limiting_deg": o.objective,
            "limiting_min_deg": float(r.minimums[at]),
            "gained_deg": o.stretch[lim_op.arc],
            "limiting_s": o.objective / (DEG_PER_S_PER_RPM * r.nominal_rpm),
            "times_deg": o.times,
            "angles_deg": o.angles,
            "minimums_deg": {
                op.arc: float(v) for op, v in zip(cg.operations, r.minimums, strict=True)
            },
            "minimum_by": {op.arc: by for op, by in zip(cg.operations, r.minimum_by, strict=True)},
            "binding": list(o.binding),
            "shadow_prices": {kk: v for kk, v in o.duals.items() if abs(v) > 1e-9},
            "shadow_prices_per_mm_rebound": prices,
            "critical": list(o.critical),
        }
    else:
        out["optimum"] = None
        out["problem"] = r.problem
    out["above_speed_limit"] = r.above_speed_limit or None
    # Each mechanism's entries, by group: "mechanisms" and the groups its kind adds.
    groups: dict[str, dict[str, Any]] = {g: {} for c in KINDS.values() for g in c.json_groups}
    groups["mechanisms"] = {}
    for k, res in r.mechanisms.items():
        for g, entry in res.json().items():
            groups.setdefault(g, {})[k] = entry
    out.update(groups)
    if r.shaft is not None:
        out["shaft"] = r.shaft.json()
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


def _stem(name: str) -> str:
    """A mechanism's name as a file-name stem."""
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)


def _write_csv(path: Path, header: list[str], rows: list[list[Any]]) -> Path:
    with whole(path) as tmp, tmp.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(header)
        for row in rows:
            w.writerow([repr(float(v)) if isinstance(v, float | np.floating) else v for v in row])
    return path


# --------------------------------------------------------------------- figures
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
    if r.shaft is not None:
        save(
            r.shaft.figure(),
            "main_shaft",
            "shaft",
            "The torque the main shaft must supply over the cycle at the nominal speed: each "
            "mechanism's at its phase in the optimised cyclogram, stacked; dashed, the mean "
            "(what the motor supplies; the flywheel takes up the rest).",
        )
    return out


# --------------------------------------------------------------------- HTML
_CSS = """
body { font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto;
       padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; }
table { border-collapse: collapse; margin: .6em 0 1.2em; font-size: .92em; }
th, td { border: 1px solid #ccc; padding: .25em .6em; text-align: left; }
td.n { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #f2f2f2; } .key { font-size: 1.1em; background: #f6f9ff;
       border: 1px solid #c9d7ef; padding: .8em 1em; border-radius: 6px; }
figure { margin: 1em 0 2em; } figure img { max-width: 100%; }
figcaption, .note { color: #555; font-size: .9em; } .warn { color: #b00; }
"""


def _table(header: list[str], rows: list[list[Any]]) -> str:
    th = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = []
    for row in rows:
        cells = []
        for v in row:
            num = isinstance(v, int | float | np.floating) and not isinstance(v, bool)
            cls = ' class="n"' if num else ""
            cells.append(f"<td{cls}>{html.escape(_f(v, 5))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><tr>{th}</tr>{''.join(body)}</table>"


def _img(path: Path, caption: str) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (
        f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{data}">'
        f"<figcaption>{html.escape(caption)}</figcaption></figure>"
    )


def _html(
    r: MachineResult,
    summary: dict[str, Any],
    figs: list[tuple[str, str, Path]],
    cycle_files: list[str],
) -> str:
    m = r.machine
    cg = m.cyclogram
    e = html.escape
    parts = [
        f"<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{e(m.name)}: design report</title><style>{_CSS}</style></head><body>",
        f"<h1>{e(m.name)}</h1>",
        f"<p>Design report by cyclomech from <code>{e(m.source)}</code>: speed range "
        f"{m.speed_range_rpm[0]:g}–{m.speed_range_rpm[1]:g} rpm, cycle {cg.cycle_deg:g}°. "
        "Angles are degrees of main-shaft rotation, speeds in rpm, lengths in metres "
        "unless a column says otherwise.</p>",
        "<h2>Summary</h2>",
    ]
    lim = r.limit
    lim_op = cg.operation(cg.limiting)  # type: ignore[arg-type]
    by = "the cyclogram" if lim.by == "cyclogram" else f"mechanism {lim.by!r}"
    if lim.rpm > 0:
        key = [f"<p><b>Speed limit: {_f(lim.rpm, 5)} rpm</b>, set by {e(by)}: {e(lim.reason)}.</p>"]
    else:
        key = [f"<p class='warn'><b>The machine works at no speed</b>: {e(lim.reason)}.</p>"]
    o = summary.get("optimum")
    if o is not None:
        key.append(
            f"<p><b>Limiting operation “{e(lim_op.title)}” ({e(lim_op.src)}→{e(lim_op.dst)})</b> "
            f"at {r.nominal_rpm:g} rpm gets <b>{o['limiting_deg']:.2f}°</b> "
            f"({1e3 * o['limiting_s']:.1f} ms) of the {cg.cycle_deg:g}° cycle: "
            f"<b>{o['gained_deg']:.2f}° more</b> than its minimum of "
            f"{o['limiting_min_deg']:.2f}°.</p>"
        )
    if r.above_speed_limit:
        key.append(f"<p class='warn'><b>Above the speed limit</b>: {e(r.above_speed_limit)}.</p>")
    if o is None and lim.rpm > 0:  # at no speed, said above: no speed is to blame
        key.append(
            f"<p class='warn'>At {r.nominal_rpm:g} rpm the cyclogram does not fit: "
            f"{e(r.problem)}</p>"
        )
    if r.shaft is not None:
        sh = r.shaft.at_nominal
        key.append(
            f"<p><b>Main shaft</b> at {r.nominal_rpm:g} rpm: motor "
            f"<b>{_power(float(sh.power_w))}</b> (mean torque "
            f"{float(sh.mean_torque_nm):.4g} N·m), peak torque "
            f"<b>{float(sh.peak_torque_nm):.4g} N·m</b>, flywheel "
            f"<b>{float(sh.flywheel_kg_m2):.4g} kg·m²</b> on the main shaft for δ = "
            f"{r.shaft.speed_fluctuation:g} (ΔE = {float(sh.energy_fluctuation_j):.4g} J).</p>"
        )
    parts.append("<div class='key'>" + "".join(key) + "</div>")
    cg_why = (
        lim.reason
        if lim.by == "cyclogram"
        else "the cyclogram fills the cycle"
        if math.isfinite(lim.cyclogram_rpm)
        else ""
    )
    mech_rows = [["cyclogram (with the mechanisms' bounds)", lim.cyclogram_rpm, cg_why]]
    mech_rows += [
        [f"mechanism {k}", v, lim.mechanisms_reason.get(k, "")]
        for k, v in lim.mechanisms_rpm.items()
    ]
    parts.append(
        "<h3>Speed limits</h3>" + _table(["what", "speed limit [rpm]", "criterion"], mech_rows)
    )
    if r.optimum is not None:
        o_ = r.optimum
        priced = [(k, float(v)) for k, v in o_.duals.items() if abs(v) > 1e-9]
        per_mm = summary["optimum"]["shadow_prices_per_mm_rebound"]
        # The price per unit of a mechanism's own limit, where a kind gives one (a
        # stop's, per mm of its rebound limit): a column only if some bound has it.
        header = ["bound or constraint", "shadow price [deg/deg]"]
        rows = [[k, v] for k, v in priced]
        extra = ""
        if per_mm:
            header.append("per mm of rebound limit [deg/mm]")
            rows = [[k, v, per_mm.get(k, "")] for k, v in priced]
            extra = " For a stop's rebound bound also per millimetre added to its rebound limit."
        free = [k for k in o_.binding if k not in dict(priced)]
        parts.append(
            "<h3>What sets the optimum at the nominal speed</h3>"
            "<p>The bounds and constraints with a shadow price: the change of the limiting "
            "operation's angle per degree added to the bound (negative: raising that "
            f"minimum takes angle from the limiting operation).{extra}</p>"
            + _table(header, rows)
            + (
                f"<p>Also binding, at zero price (the optimum is degenerate there): "
                f"{e(', '.join(free))}.</p>"
                if free
                else ""
            )
        )
    for sec, cap, p in figs:
        if sec == "summary":
            parts.append(_img(p, cap))
    # The cyclogram
    parts.append("<h2>Optimised cyclogram</h2>")
    if r.optimum is None:
        parts.append(
            f"<p class='warn'>No optimised cyclogram: at {r.nominal_rpm:g} rpm it does not "
            f"fit. {e(r.problem)}</p>"
        )
    else:
        o_ = r.optimum
        crit = set(o_.critical)
        mins = r.minimums
        assert mins is not None
        rows = [
            [
                op.mechanism or "",
                op.title,
                f"{op.src}→{op.dst}",
                float(mn),
                _own(by),
                o_.angles[op.arc],
                o_.times[op.src],
                _noise_free(o_.angles[op.arc] - float(mn), 360.0),
                "yes" if op.arc in crit else "",
            ]
            for op, mn, by in zip(cg.operations, mins, r.minimum_by, strict=True)
        ]
        parts.append(
            _table(
                [
                    "mechanism",
                    "operation",
                    "arc",
                    "minimum [deg]",
                    "minimum set by",
                    "angle [deg]",
                    "start [deg]",
                    "beyond minimum [deg]",
                    "critical",
                ],
                rows,
            )
        )
        parts.append(
            "<p class='note'>Minimum: the operation's own minimum angle or duration, or "
            "the largest bound a mechanism puts on it at this speed; beyond minimum: "
            "what the optimum gave it on top of that.</p>"
        )
    for sec, cap, p in figs:
        if sec == "cyclogram":
            parts.append(_img(p, cap))
    # Mechanisms
    for k in m.mechanisms:
        info = summary["mechanisms"][k]
        parts.append(f"<h2>Mechanism “{e(k)}” ({e(info['kind'].replace('_', ' '))})</h2>")
        header, rows = r.mechanisms[k].table()
        parts.append(_table(header, rows))
        for sec, cap, p in figs:
            if sec == k:
                parts.append(_img(p, cap))
    if r.shaft is not None:
        parts.append("<h2>Main shaft</h2>")
        header, rows = r.shaft.table()
        parts.append(_table(header, rows))
        for sec, cap, p in figs:
            if sec == "shaft":
                parts.append(_img(p, cap))
    cycle = [f"<code>{name}</code>" for name in cycle_files]
    over = f"; over the cycle at {r.nominal_rpm:g} rpm: {', '.join(cycle)}" if cycle else ""
    parts.append(
        "<h2>Files</h2><p><code>results.json</code> (schema "
        f"<code>{SCHEMA}</code>), <code>speed_sweep.csv</code>, <code>operations.csv</code>, "
        f"<code>figures/*.png</code>{over}.</p></body></html>"
    )
    return "\n".join(parts)


def write_report(result: MachineResult, out: str | Path, *, figures: bool = True) -> list[Path]:
    """Write the machine's report, results and tables to the folder ``out``.

    ``report.html``, ``results.json``, ``speed_sweep.csv``, ``operations.csv``,
    ``main_shaft.csv`` (the torque over the cycle at the nominal speed, total and
    each mechanism's, when a mechanism loads the shaft), ``<mechanism>_forces.csv``
    (a linkage's driving torque, guide forces and joint forces over its crank turn,
    when it has masses or loads) and ``figures/*.png`` (figures need matplotlib).

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
    written = []
    sw = result.sweep
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
        result.sweep_linear.limiting_deg,
        sw.limiting_s,
        sw.productivity_per_min,
        *sw.columns.values(),
    ]
    for res in result.mechanisms.values():
        for name, column in res.csv_columns():
            header.append(name)
            cols.append(column)
    header.append("binding")
    cols.append(sw.binding)
    rows = [list(r) for r in zip(*cols, strict=True)]
    written.append(_write_csv(folder / "speed_sweep.csv", header, rows))
    op_rows: list[list[Any]] = []
    if result.optimum is not None:
        o, mins = result.optimum, result.minimums
        assert mins is not None
        ops = result.machine.cyclogram.operations
        for op, mn, by in zip(ops, mins, result.minimum_by, strict=True):
            op_rows.append(
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
                ]
            )
    written.append(
        _write_csv(
            folder / "operations.csv",
            [
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
            ],
            op_rows,
        )
    )
    cycle_files: list[str] = []  # over the cycle, for the report's Files section
    if result.shaft is not None:
        cycle_files.append("main_shaft.csv")
        sh, n = result.shaft, result.nominal_rpm
        head = ["cycle_deg", "torque_nm", *(f"torque_nm[{k}]" for k in sh.parts)]
        theta = np.round(sh.torque.theta_deg, 9)  # 0.1 steps, not 0.30000000000000004
        columns = [theta, sh.torque.at(n), *(p.at(n) for p in sh.parts.values())]
        rows = [list(r) for r in zip(*columns, strict=True)]
        written.append(_write_csv(folder / "main_shaft.csv", head, rows))
    for k, res in result.mechanisms.items():
        over = getattr(res, "cycle_csv", lambda: None)()
        if over is not None:
            head, columns = over
            rows = [list(r) for r in zip(*columns, strict=True)]
            cycle_files.append(f"{_stem(k)}_forces.csv")
            written.append(_write_csv(folder / cycle_files[-1], head, rows))
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
        (folder / "report.html", _html(result, summary, figs, cycle_files)),
    ]:
        with whole(p) as tmp:
            tmp.write_text(text, encoding="utf-8")
        written.append(p)
    written += [f[2] for f in figs]
    return written


def _power(watts: float) -> str:
    """A power for the report, in W below a kilowatt and kW above (the CLI's unit
    below a kilowatt too).

    >>> _power(2.0944), _power(2202.4)
    ('2.094 W', '2.202 kW')
    """
    return f"{watts:.4g} W" if abs(watts) < 1e3 else f"{watts / 1e3:.4g} kW"


def _noise_free(value: float, scale: float) -> float:
    """``value``, or 0.0 when it is rounding noise (below 1e-12 of ``scale``): an LP's
    7.1e-15° of slack is no gain.

    >>> _noise_free(7.1054e-15, 360.0), _noise_free(7.06, 360.0)
    (0.0, 7.06)
    """
    return 0.0 if abs(value) < 1e-12 * scale else value
