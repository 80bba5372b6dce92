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
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._errors import InfeasibleError
from .._json import jsonable
from .._units import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM
from ..cyclogram import Optimum
from ..linkage import LinkageSolution
from ._model import (
    SCHEMA,
    CamStop,
    LinkageMechanism,
    Machine,
    PressMechanism,
    SpeedLimit,
    SpeedSweep,
    TransferMechanism,
)

__all__ = ["MachineResult", "analyze", "write_report"]


@dataclass
class MachineResult:
    """Everything the report shows (speeds [rpm], angles [deg], SI otherwise).

    ``limit``: the speed limit; ``nominal_rpm``: the speed of ``optimum`` (the LP
    optimum with the stops' exact constraints; None if it does not fit there);
    ``sweep`` / ``sweep_linear``: the key figures against speed with the exact and
    the seed's linearised stop constraints; ``linkages``: each linkage's solution
    over a crank turn; ``press``: each press's criteria at the nominal speed;
    ``transfer``: each transfer's (peak |a| [m/s²], peak jerk [m/s³]) at the
    nominal speed; ``stops``: each stop's exact and linearised smallest phase
    angle on the sweep's speeds.
    """

    machine: Machine
    limit: SpeedLimit
    nominal_rpm: float
    optimum: Optimum | None
    problem: str
    sweep: SpeedSweep
    sweep_linear: SpeedSweep
    linkages: dict[str, LinkageSolution] = field(default_factory=dict)
    press: dict[str, Any] = field(default_factory=dict)
    transfer: dict[str, tuple[float, float]] = field(default_factory=dict)
    stops: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)


class _Steps:
    """A progress bar over the steps of a run, on stderr."""

    def __init__(self, steps: list[str], enabled: bool) -> None:
        self.steps, self.enabled, self.k = steps, enabled, 0
        self.t0 = time.perf_counter()

    def run(self, fn: Callable[[], Any]) -> Any:
        name = self.steps[self.k]
        if self.enabled:
            bar = "#" * int(30 * self.k / len(self.steps))
            sys.stderr.write(
                f"\r[{bar:<30}] {self.k + 1}/{len(self.steps)} {name:<32} "
                f"{time.perf_counter() - self.t0:5.1f} s"
            )
            sys.stderr.flush()
        out = fn()
        self.k += 1
        if self.enabled and self.k == len(self.steps):
            sys.stderr.write(
                f"\r[{'#' * 30}] {self.k}/{len(self.steps)} {'done':<32} "
                f"{time.perf_counter() - self.t0:5.1f} s\n"
            )
        return out


def analyze(machine: Machine, *, progress: bool | None = None) -> MachineResult:
    """Solve every mechanism, every stop, the cyclogram and the speed sweep.

    >>> import cyclomech as cm
    >>> from cyclomech.machine import analyze
    >>> r = analyze(cm.Machine.example(), progress=False)
    >>> round(r.limit.rpm, 3), round(r.optimum.objective, 3)    # 6 · 421.37 rpm · 0.1 s
    (421.37, 252.822)
    """
    steps = _Steps(
        ["mechanisms", "stops", "speed limit", "optimised cyclogram", "speed sweep"],
        sys.stderr.isatty() if progress is None else bool(progress),
    )
    seconds: dict[str, float] = {}

    def timed(name: str, fn: Callable[[], Any]) -> Any:
        t = time.perf_counter()
        out = steps.run(fn)
        seconds[name] = time.perf_counter() - t
        return out

    m = machine

    def mechanisms() -> tuple[dict[str, Any], ...]:
        lk: dict[str, LinkageSolution] = {}
        for k, mech in m.mechanisms.items():
            if isinstance(mech, LinkageMechanism):
                lk[k] = mech.solve()
        return (lk,)

    (linkages,) = timed("mechanisms", mechanisms)
    rpm = m.speed_grid()

    def stops() -> dict[str, tuple[np.ndarray, np.ndarray]]:
        return {s.name: (s.min_phase_deg(rpm), s.linear_min_phase_deg(rpm)) for s in m.stops}

    stop_angles = timed("stops", stops)
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

    def sweeps() -> tuple[SpeedSweep, SpeedSweep]:
        return m.speed_sweep(rpm), m.speed_sweep(rpm, linear=True)

    sw, sw_lin = timed("speed sweep", sweeps)
    press = {
        k: mech.criteria(nominal)
        for k, mech in m.mechanisms.items()
        if isinstance(mech, PressMechanism)
    }
    transfer = {
        k: mech.peaks(nominal)
        for k, mech in m.mechanisms.items()
        if isinstance(mech, TransferMechanism)
    }
    return MachineResult(
        m, limit, nominal, opt, problem, sw, sw_lin, linkages, press, transfer, stop_angles, seconds
    )


# --------------------------------------------------------------------- tables
def _f(v: Any, digits: int = 4) -> str:
    if v is None:
        return "—"
    if isinstance(v, float | np.floating):
        if not math.isfinite(v):
            return "—" if math.isnan(v) else ("∞" if v > 0 else "−∞")
        return f"{v:.{digits}g}"
    return str(v)


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
        mins = m.cyclogram_at(r.nominal_rpm).min_angles(r.nominal_rpm)
        at = [op.arc for op in cg.operations].index(lim_op.arc)
        out["optimum"] = {
            "speed_rpm": r.nominal_rpm,
            "limiting_deg": o.objective,
            "limiting_min_deg": float(mins[at]),
            "gained_deg": o.stretch[lim_op.arc],
            "limiting_s": o.objective / (DEG_PER_S_PER_RPM * r.nominal_rpm),
            "times_deg": o.times,
            "angles_deg": o.angles,
            "binding": list(o.binding),
            "shadow_prices": {kk: v for kk, v in o.duals.items() if abs(v) > 1e-9},
            "shadow_prices_per_mm_rebound": _rebound_prices(r),
            "critical": list(o.critical),
        }
    else:
        out["optimum"] = None
        out["problem"] = r.problem
    stops = {}
    for s in m.stops:
        exact, linear = r.stops[s.name]
        stops[s.name] = {
            "arc": s.arc,
            "model": s.stop.model,
            "law": s.stop.law.name,
            "stroke_m": s.stop.stroke,
            "preload_m": s.stop.preload,
            "critical_speed_m_s": s.stop.max_impact_speed(s.a_max),
            "linear_min_phase_deg_at_nominal": float(s.linear_min_phase_deg(r.nominal_rpm)),
            "a_max_m": s.a_max,
            "omega_free_rad_s": s.stop.omega_free,
            "omega_contact_rad_s": s.stop.omega_contact,
            "min_phase_deg_at_nominal": float(s.min_phase_deg(r.nominal_rpm)),
            "speed_rpm": m.speed_grid(),
            "min_phase_deg": exact,
            "linear_min_phase_deg": linear,
        }
    out["stops"] = stops
    mech: dict[str, Any] = {}

    def own_limit(k: str) -> float:
        # The one value speed_limit computed (infinite where the mechanism has no limit).
        return r.limit.mechanisms_rpm.get(k, math.inf)

    for k, v in m.mechanisms.items():
        if isinstance(v, LinkageMechanism):
            vmax, amax = v.peaks()
            w = RAD_PER_S_PER_RPM * r.nominal_rpm
            mech[k] = {
                "kind": "linkage",
                "output": v.output,
                "max_velocity_analog_m_per_rad": vmax,
                "max_acceleration_analog_m_per_rad2": amax,
                "max_velocity_m_s": vmax * w,
                "max_acceleration_m_s2": amax * w * w,
                "speed_limit_rpm": own_limit(k),
            }
        elif isinstance(v, PressMechanism):
            mech[k] = {
                "kind": "press",
                "criteria": r.press[k].as_dict(),
                "speed_limit_rpm": own_limit(k),
            }
        elif isinstance(v, TransferMechanism):
            a, j = r.transfer[k]
            mech[k] = {
                "kind": "transfer",
                "x2_m": [v.path.x2_t, v.path.x2_p],
                "speeds_m_s": list(v.speeds(r.nominal_rpm)),
                "max_acceleration_m_s2": a,
                "max_jerk_m_s3": j,
                "speed_limit_rpm": own_limit(k),
            }
        else:
            mech[k] = {"kind": "cam_stop", "arc": v.arc}
    out["mechanisms"] = mech
    sw = r.sweep
    out["speed_sweep"] = {
        "speed_rpm": sw.rpm,
        "fits": sw.fits,
        "limiting_deg": sw.limiting_deg,
        "limiting_deg_linear": r.sweep_linear.limiting_deg,
        "limiting_s": sw.limiting_s,
        "productivity_per_min": sw.productivity,
        "max_rebound_m": sw.max_rebound_m,
        "binding": list(sw.binding),
    }
    out["seconds"] = r.seconds
    return jsonable(out)  # type: ignore[no-any-return]


def _rebound_prices(r: MachineResult) -> dict[str, float]:
    """Shadow price of each stop's rebound bound per mm of its rebound limit a_max
    [deg/mm]: the LP's price per degree of the bound t ≥ t_min times dt_min/da_max
    (central difference, ±0.1 % of a_max)."""
    o, out = r.optimum, {}
    if o is None:
        return out
    for s in r.machine.stops:
        name = f"rebound[{s.name}]"
        price = o.duals.get(name, 0.0)
        if abs(price) <= 1e-9:
            continue
        h = 1e-3 * s.a_max
        up, down = (float(s.stop.min_phase_angle(s.a_max + d, r.nominal_rpm)) for d in (h, -h))
        out[name] = price * (up - down) / (2.0 * h) * 1e-3
    return out


def _write_csv(path: Path, header: list[str], rows: list[list[Any]]) -> Path:
    with path.open("w", newline="", encoding="utf-8") as f:
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

    from ..plot import (
        plot_analogs,
        plot_cyclogram,
        plot_law,
        plot_linkage,
        plot_min_phase,
        plot_press,
        plot_rebound_vs_speed,
        plot_speed_sweep,
        plot_transfer,
    )

    folder.mkdir(parents=True, exist_ok=True)
    out: list[tuple[str, str, Path]] = []
    m = r.machine

    def save(fig: Any, name: str, section: str, caption: str) -> None:
        p = folder / f"{name}.png"
        fig.savefig(p, dpi=110, bbox_inches="tight")
        plt.close(fig)
        out.append((section, caption, p))

    save(
        plot_speed_sweep(
            r.sweep,
            linear=r.sweep_linear if m.stops else None,
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
            if m.stops
            else ""
        )
        + "; the curves end at the speed limit (dashed red line), shaded above it.",
    )
    if r.optimum is not None:
        # Two figures, each legible at the page's width (side by side they were
        # shrunk to half size).
        at = f"at {r.nominal_rpm:g} rpm"
        ax = plot_cyclogram(r.optimum, kind="gantt", title=f"optimised cyclogram {at}")
        save(
            ax.figure,
            "cyclogram",
            "cyclogram",
            "The optimised cyclogram, one row per mechanism over the main-shaft turn. The "
            "critical operations (red outline) form the chain that leaves the limiting "
            "operation (orange) its angle; the hatched parts are what each operation got "
            "beyond its minimum.",
        )
        _, polar = plt.subplots(
            figsize=(9.0, 7.2), layout="constrained", subplot_kw={"projection": "polar"}
        )
        polar.figure.get_layout_engine().set(w_pad=0.25, h_pad=0.1)
        plot_cyclogram(r.optimum, polar, kind="circular", title=f"circular cyclogram {at}")
        save(
            polar.figure,
            "cyclogram_circular",
            "cyclogram",
            "The same as a circular diagram: 0° at the top, the turn clockwise, one ring per "
            "mechanism from the centre out.",
        )
    for k, mech in m.mechanisms.items():
        if isinstance(mech, CamStop):
            n = m.speed_grid()
            save(
                plot_rebound_vs_speed(
                    mech.stop,
                    n,
                    phase_deg=mech.phase_deg,
                    a_max=mech.a_max,
                    title=f"{k}: rebound at the stop",
                ),
                f"{k}_rebound",
                k,
                "Left: the lever's motion after it strikes the stop"
                + (
                    " (pulse model: the stop acts only through the impact pulse, so q < 0, "
                    "into the stop, is the model's free vibration, not the lever's)"
                    if mech.stop.model == "pulse"
                    else " (contact model: q < 0 is the stop's deflection under the lever)"
                )
                + "; right: the first rebound against speed for several phase angles, with "
                "the limit dashed.",
            )
            axes = plot_law(
                mech.stop.law, title=f"{k}: cam law ({mech.stop.law.name.replace('_', ' ')}, rise)"
            )
            for a in axes:
                a.axvline(mech.stop.j_contact, color="0.4", ls=":", lw=1.0)
            axes[0].annotate(
                "meets the stop",
                (mech.stop.j_contact, 0.5),
                xytext=(-6, 0),
                textcoords="offset points",
                ha="right",
                fontsize=8,
                color="0.3",
            )
            save(
                axes[0].figure,
                f"{k}_law",
                k,
                f"The cam's motion law over the arc {mech.arc[0]}→{mech.arc[1]}: Z, Z' and Z'' "
                f"(dimensionless) against the fraction j of the phase angle; the lever meets "
                f"the stop at j = {mech.stop.j_contact:.3f} (dotted), Z' = "
                f"{mech.stop.dz_contact:.3f} there sets the impact speed.",
            )
            exact, linear = r.stops[k]
            ax = plot_min_phase(
                n,
                exact,
                linear,
                minimum_deg=m.cyclogram.operation(mech.arc).min_angle_deg,
                title=f"{k}: smallest phase angle of {mech.arc[0]}→{mech.arc[1]}",
            )
            save(
                ax.figure,
                f"{k}_min_phase",
                k,
                "The smallest phase angle of the operation that keeps the rebound within its "
                "limit: exact and the seed's linearised form.",
            )
        elif isinstance(mech, LinkageMechanism):
            sol = r.linkages[k]
            ax = plot_linkage(mech.linkage, sol, 0, trace=[mech.output], title=f"{k}: mechanism")
            save(
                ax.figure,
                f"{k}_mechanism",
                k,
                f"The mechanism at its drawn angle, with the path of {mech.output}.",
            )
            save(
                plot_analogs(sol, mech.output, title=f"{k}: analogs of {mech.output}"),
                f"{k}_analogs",
                k,
                f"Position, velocity and acceleration analogs of {mech.output} over the turn.",
            )
        elif isinstance(mech, PressMechanism):
            c = r.press[k]
            res = plot_press(
                mech.press,
                0.0,
                show_motion=True,
                k_Sp=mech.k_Sp or c.k_Sp,
                title=f"{k}: gear-lever press",
            )
            fig = res[0].figure if isinstance(res, tuple) else res.figure
            save(
                fig,
                f"{k}_press",
                k,
                "The drive at bottom dead centre with the pin's hypotrochoid, and the "
                "slider's motion and transfer functions.",
            )
        elif isinstance(mech, TransferMechanism):
            save(
                plot_transfer(
                    mech.path,
                    speed=mech.speeds(r.nominal_rpm),
                    title=f"{k}: transfer at {r.nominal_rpm:g} rpm",
                ),
                f"{k}_transfer",
                k,
                "The workpiece's path between the rotors, its curvature, acceleration and "
                "jerk at the nominal speed.",
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
figcaption { color: #555; font-size: .9em; } .warn { color: #b00; }
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


def _html(r: MachineResult, summary: dict[str, Any], figs: list[tuple[str, str, Path]]) -> str:
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
    elif lim.rpm > 0:  # at no speed, said above: no speed is to blame
        key.append(
            f"<p class='warn'>At {r.nominal_rpm:g} rpm the cyclogram does not fit: "
            f"{e(r.problem)}</p>"
        )
    parts.append("<div class='key'>" + "".join(key) + "</div>")
    cg_why = (
        lim.reason
        if lim.by == "cyclogram"
        else "the cyclogram fills the cycle"
        if math.isfinite(lim.cyclogram_rpm)
        else ""
    )
    mech_rows = [["cyclogram (with the stops' constraints)", lim.cyclogram_rpm, cg_why]]
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
        rows = [[k, v, per_mm.get(k, "")] for k, v in priced]
        free = [k for k in o_.binding if k not in dict(priced)]
        parts.append(
            "<h3>What sets the optimum at the nominal speed</h3>"
            "<p>The bounds and constraints with a shadow price: the change of the limiting "
            "operation's angle per degree added to the bound (negative: raising that "
            "minimum takes angle from the limiting operation). For a stop's rebound bound "
            "also per millimetre added to its rebound limit.</p>"
            + _table(
                [
                    "bound or constraint",
                    "shadow price [deg/deg]",
                    "per mm of rebound limit [deg/mm]",
                ],
                rows,
            )
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
        mins = m.cyclogram_at(r.nominal_rpm).min_angles(r.nominal_rpm)
        rows = [
            [
                op.mechanism or "",
                op.title,
                f"{op.src}→{op.dst}",
                float(mn),
                o_.angles[op.arc],
                o_.times[op.src],
                o_.stretch[op.arc],
                "yes" if op.arc in crit else "",
            ]
            for op, mn in zip(cg.operations, mins, strict=True)
        ]
        parts.append(
            _table(
                [
                    "mechanism",
                    "operation",
                    "arc",
                    "minimum [deg]",
                    "angle [deg]",
                    "start [deg]",
                    "gained [deg]",
                    "critical",
                ],
                rows,
            )
        )
    for sec, cap, p in figs:
        if sec == "cyclogram":
            parts.append(_img(p, cap))
    # Mechanisms
    for k, mech in m.mechanisms.items():
        info = summary["mechanisms"][k]
        parts.append(f"<h2>Mechanism “{e(k)}” ({e(info['kind'].replace('_', ' '))})</h2>")
        if isinstance(mech, CamStop):
            s = summary["stops"][k]
            st = mech.stop
            model = (
                "pulse (the seed's: the free lever and the impact pulse)"
                if st.model == "pulse"
                else "contact (the stop as a unilateral spring, event by event)"
            )
            parts.append(
                _table(
                    ["quantity", "value"],
                    [
                        ["operation it constrains", f"{mech.arc[0]}→{mech.arc[1]}"],
                        ["rebound model", model],
                        ["cam law (rise)", st.law.name.replace("_", " ")],
                        ["stroke [mm]", st.stroke * 1e3],
                        ["preload (stop before the end of the stroke) [mm]", st.preload * 1e3],
                        ["rebound limit [mm]", mech.a_max * 1e3],
                        ["free natural frequency [Hz]", st.omega_free / (2 * math.pi)],
                        ["natural frequency in contact [Hz]", st.omega_contact / (2 * math.pi)],
                        ["largest admissible impact speed [m/s]", s["critical_speed_m_s"]],
                        [
                            f"smallest phase angle at {r.nominal_rpm:g} rpm [deg]",
                            s["min_phase_deg_at_nominal"],
                        ],
                        [
                            f"the seed's linearised form at {r.nominal_rpm:g} rpm [deg]",
                            s["linear_min_phase_deg_at_nominal"],
                        ],
                    ],
                )
            )
        elif isinstance(mech, LinkageMechanism):
            parts.append(
                _table(
                    ["quantity", "value"],
                    [
                        ["output point", mech.output],
                        ["max |d xy/dφ| [m/rad]", info["max_velocity_analog_m_per_rad"]],
                        ["max |d² xy/dφ²| [m/rad²]", info["max_acceleration_analog_m_per_rad2"]],
                        [f"max speed at {r.nominal_rpm:g} rpm [m/s]", info["max_velocity_m_s"]],
                        [
                            f"max acceleration at {r.nominal_rpm:g} rpm [m/s²]",
                            info["max_acceleration_m_s2"],
                        ],
                        ["speed limit [rpm]", info["speed_limit_rpm"]],
                    ],
                )
            )
        elif isinstance(mech, PressMechanism):
            c = r.press[k]
            parts.append(
                _table(
                    ["criterion", f"at {r.nominal_rpm:g} rpm"],
                    [
                        ["nominal stroke S_n [mm]", c.S_n * 1e3],
                        ["working stroke S_p [mm]", c.S_p * 1e3],
                        ["speed at the start of the working stroke V_np [mm/s]", c.V_np * 1e3],
                        ["mean working speed V_cp [mm/s]", c.V_cp * 1e3],
                        ["k_Vp = V_np/V_cp", c.k_Vp],
                        ["k_Vmax = V_pmax/V_cp", c.k_Vmax],
                        ["peak acceleration J_max [m/s²]", c.J_max],
                        ["torque factor (max Π' in the working stroke) [mm]", c.torque * 1e3],
                        ["speed limit [rpm]", info["speed_limit_rpm"]],
                    ],
                )
            )
        elif isinstance(mech, TransferMechanism):
            parts.append(
                _table(
                    ["quantity", "value"],
                    [
                        [
                            "transition lengths x2 [mm]",
                            ", ".join(f"{1e3 * x:.4g}" for x in info["x2_m"]),
                        ],
                        [
                            f"peripheral speeds at {r.nominal_rpm:g} rpm [m/s]",
                            ", ".join(f"{v:.4g}" for v in info["speeds_m_s"]),
                        ],
                        ["peak acceleration [m/s²]", info["max_acceleration_m_s2"]],
                        ["peak jerk [m/s³]", info["max_jerk_m_s3"]],
                        ["speed limit [rpm]", info["speed_limit_rpm"]],
                    ],
                )
            )
        for sec, cap, p in figs:
            if sec == k:
                parts.append(_img(p, cap))
    parts.append(
        "<h2>Files</h2><p><code>results.json</code> (schema "
        f"<code>{SCHEMA}</code>), <code>speed_sweep.csv</code>, <code>operations.csv</code>, "
        "<code>figures/*.png</code>.</p></body></html>"
    )
    return "\n".join(parts)


def write_report(result: MachineResult, out: str | Path, *, figures: bool = True) -> list[Path]:
    """Write ``report.html``, ``results.json``, ``speed_sweep.csv``,
    ``operations.csv`` and ``figures/*.png`` to the folder ``out``; returns the
    paths written (figures need matplotlib).

    >>> import pathlib, tempfile, cyclomech as cm
    >>> from cyclomech.machine import analyze, write_report
    >>> r = analyze(cm.Machine.example(), progress=False)
    >>> sorted(p.name for p in write_report(r, tempfile.mkdtemp(), figures=False))
    ['operations.csv', 'report.html', 'results.json', 'speed_sweep.csv']
    """
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    summary = _summary(result)
    written = []
    p = folder / "results.json"
    p.write_text(json.dumps(summary, indent=2, ensure_ascii=False), encoding="utf-8")
    written.append(p)
    sw, m = result.sweep, result.machine
    header = [
        "speed_rpm",
        "fits",
        "limiting_deg",
        "limiting_deg_linear",
        "limiting_s",
        "productivity_per_min",
        "max_rebound_m",
    ]
    cols: list[Any] = [
        sw.rpm,
        sw.fits,
        sw.limiting_deg,
        result.sweep_linear.limiting_deg,
        sw.limiting_s,
        sw.productivity,
        sw.max_rebound_m,
    ]
    for s in m.stops:
        header += [f"min_phase_deg[{s.name}]", f"linear_min_phase_deg[{s.name}]"]
        cols += list(result.stops[s.name])
    header.append("binding")
    cols.append(sw.binding)
    rows = [list(r) for r in zip(*cols, strict=True)]
    written.append(_write_csv(folder / "speed_sweep.csv", header, rows))
    op_rows: list[list[Any]] = []
    if result.optimum is not None:
        o = result.optimum
        for op in m.cyclogram.operations:
            op_rows.append(
                [
                    op.mechanism or "",
                    op.title,
                    op.src,
                    op.dst,
                    o.angles[op.arc],
                    o.times[op.src],
                    o.stretch[op.arc],
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
                "angle_deg",
                "start_deg",
                "gained_deg",
                "critical",
            ],
            op_rows,
        )
    )
    figs: list[tuple[str, str, Path]] = []
    if figures:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            figs = []
        else:
            figs = _figures(result, folder / "figures")
    p = folder / "report.html"
    p.write_text(_html(result, summary, figs), encoding="utf-8")
    written.append(p)
    written += [f[2] for f in figs]
    return written
