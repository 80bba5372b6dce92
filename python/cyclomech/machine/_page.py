"""The machine report's page: ``report.html``, self-contained (its figures
embedded), from what :func:`~cyclomech.machine.analyze` computed, the summary of
``results.json`` and the figures :func:`~cyclomech.machine.write_report` drew.
The `_page` part of :mod:`cyclomech.machine` (its door).

:func:`page` puts the sections together in reading order: the key figures, the
speed limits and what sets the optimum (:func:`_summary_section`), the optimised
cyclogram (:func:`_cyclogram_section`), each mechanism's table and figures, the
main shaft's, and the files written (:func:`_files_section`).
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path
from typing import Any

import numpy as np

from ._animation import animation_section
from ._efficiency import efficiency_table, machine_efficiency
from ._model import SCHEMA
from ._result import MachineResult

__all__ = ["page"]

#: A figure of the report: (section, caption, PNG file). The section is
#: ``"summary"``, ``"cyclogram"``, ``"shaft"`` or a mechanism's name.
Figure = tuple[str, str, Path]


def page(
    r: MachineResult,
    summary: dict[str, Any],
    figs: list[Figure],
    cycle_files: list[str],
) -> str:
    """The HTML of ``report.html``.

    Parameters
    ----------
    r : MachineResult
        What :func:`~cyclomech.machine.analyze` computed.
    summary : dict
        ``results.json``'s content (its ``optimum``, ``mechanisms``).
    figs : list of (str, str, Path)
        The figures drawn, by section, with their captions (none without
        matplotlib), embedded in their sections.
    cycle_files : list of str
        The CSV files over the cycle written besides the standard ones.

    Returns
    -------
    str
        The page.

    Examples
    --------
    >>> import cyclomech as cm
    >>> from cyclomech.machine._report import _summary
    >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
    >>> text = page(r, _summary(r), [], [])
    >>> text.count("<h2>"), "Speed limit: 421.37 rpm" in text
    (5, True)
    """
    m = r.machine
    e = html.escape
    parts = [
        f"<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{e(m.name)}: design report</title><style>{_CSS}</style></head><body>",
        f"<h1>{e(m.name)}</h1>",
        f"<p>Design report by cyclomech from <code>{e(m.source)}</code>: speed range "
        f"{m.speed_range_rpm[0]:g}–{m.speed_range_rpm[1]:g} rpm, cycle "
        f"{m.cyclogram.cycle_deg:g}°. "
        "Angles are degrees of main-shaft rotation, speeds in rpm, lengths in metres "
        "unless a column says otherwise.</p>",
        "<h2>Summary</h2>",
    ]
    parts += _summary_section(r, summary)
    parts += _images(figs, "summary")
    parts += _sensitivity_section(r)
    parts += _cyclogram_section(r)
    parts += _images(figs, "cyclogram")
    parts += animation_section(r)
    for k in m.mechanisms:
        info = summary["mechanisms"][k]
        parts.append(f"<h2>Mechanism “{e(k)}” ({e(info['kind'].replace('_', ' '))})</h2>")
        header, rows = r.mechanisms[k].table()
        parts.append(_table(header, rows))
        parts += _images(figs, k)
    if r.shaft is not None:
        parts.append("<h2>Main shaft</h2>")
        header, rows = r.shaft.table()
        parts.append(_table(header, rows))
        eff = machine_efficiency(r)
        if eff is not None:
            parts.append("<h3>Friction and efficiency</h3>")
            parts.append(
                f"<p>At {r.nominal_rpm:g} rpm; Coulomb friction at the nominal speed's "
                "velocities and reactions, its torque added to the main shaft's (so the "
                "flywheel and the motor below carry it).</p>"
            )
            header, rows = efficiency_table(eff)
            parts.append(_table(header, rows))
        if r.dynamics is not None:
            parts.append("<h3>Under its motor</h3>")
            header, rows = r.dynamics.table()
            parts.append(_table(header, rows))
        if r.torsion is not None:
            parts.append("<h3>Elastic shaft and links: the dynamic errors</h3>")
            header, rows = r.torsion.table()
            parts.append(_table(header, rows))
        parts += _images(figs, "shaft")
    if r.shaking is not None:
        parts.append("<h2>Frame: the shaking force</h2>")
        header, rows = r.shaking.table()
        parts.append(_table(header, rows))
        for k, b in r.shaking.balances.items():
            parts.append(f"<h3>{html.escape(k)} balanced ({html.escape(b.objective)})</h3>")
            header, rows = b.table()
            parts.append(_table(header, rows))
        parts += _images(figs, "frame")
    parts.append(_files_section(r, cycle_files))
    return "\n".join(parts)


def _sensitivity_section(r: MachineResult) -> list[str]:
    """Which key buys how many rpm: the ranked sensitivities, when computed."""
    if r.sensitivities is None:
        return [
            "<h3>Which key buys speed</h3>",
            "<p>Not computed for this report (<code>cyclomech run --no-sensitivities</code>, "
            "or <code>analyze(…, sensitivities=False)</code>).</p>",
        ]
    rows = [
        [s.key, s.value, s.rpm_per_percent, s.rpm_per_unit, s.status, s.note]
        for s in r.sensitivities
    ]
    header = ["key", "value", "rpm per +1 %", "rpm per unit", "status", "note"]
    base = r.sensitivities[0].limit_rpm if r.sensitivities else r.limit.rpm
    return [
        "<h3>Which key buys speed</h3>",
        f"<p>The speed limit ({base:.2f} rpm without the elastic "
        "shaft's dynamic errors) when one key of the file is raised by 1 %, the others "
        "as they are: central differences of ±0.1 % (every variant's limit in one call). "
        "Negative: lowering the key buys speed. A kink: another bound takes over at this "
        "value (the note gives both sides); does not bind: the key does not set the "
        "limit here. A key inside a sub-table or a list is named by its path, positions "
        "from 1 (<code>lengths.3.length</code>); a curve is scaled as a whole.</p>",
        _table(header, rows),
    ]


def _summary_section(r: MachineResult, summary: dict[str, Any]) -> list[str]:
    """The summary's parts: the key figures in a box, the speed limits' table and,
    with an optimum, what sets it."""
    parts = ["<div class='key'>" + "".join(_key_figures(r, summary)) + "</div>"]
    parts.append(_speed_limits(r))
    if r.optimum is not None:
        parts.append(_what_sets_the_optimum(r, summary))
    return parts


def _key_figures(r: MachineResult, summary: dict[str, Any]) -> list[str]:
    """The key figures, a paragraph each: the speed limit [rpm] and why, the
    limiting operation's angle [deg] and time [ms] at the nominal speed, the
    warnings, and the main shaft's motor power, peak torque [N·m] and flywheel
    [kg·m²]."""
    e = html.escape
    cg = r.machine.cyclogram
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
    for text in r.failures:
        key.append(f"<p class='warn'><b>Fails at {r.nominal_rpm:g} rpm</b>: {e(text)}.</p>")
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
    if r.dynamics is not None:
        key.append(f"<p>{e(r.dynamics.line())}.</p>")
    return key


def _speed_limits(r: MachineResult) -> str:
    """The table of speed limits [rpm]: the cyclogram's with the mechanisms' bounds
    and each mechanism's own, with the criterion of each."""
    lim = r.limit
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
    return "<h3>Speed limits</h3>" + _table(["what", "speed limit [rpm]", "criterion"], mech_rows)


def _what_sets_the_optimum(r: MachineResult, summary: dict[str, Any]) -> str:
    """The bounds and constraints with a shadow price at the nominal speed
    [deg/deg], per mm of a stop's rebound limit where a kind gives it [deg/mm],
    and those binding at zero price."""
    o_ = r.optimum
    assert o_ is not None
    priced = [(k, float(v)) for k, v in o_.duals.items() if abs(v) > 1e-9]
    per_mm = summary["optimum"]["shadow_prices_per_mm_rebound"]
    # The price per unit of a mechanism's own limit, where a kind gives one (a
    # stop's, per mm of its rebound limit): a column only if some bound has it.
    header = ["bound or constraint", "shadow price [deg/deg]"]
    rows: list[list[Any]] = [[k, v] for k, v in priced]
    extra = ""
    if per_mm:
        header.append("per mm of rebound limit [deg/mm]")
        rows = [[k, v, per_mm.get(k, "")] for k, v in priced]
        extra = " For a stop's rebound bound also per millimetre added to its rebound limit."
    free = [k for k in o_.binding if k not in dict(priced)]
    return (
        "<h3>What sets the optimum at the nominal speed</h3>"
        "<p>The bounds and constraints with a shadow price: the change of the limiting "
        "operation's angle per degree added to the bound (negative: raising that "
        f"minimum takes angle from the limiting operation).{extra}</p>"
        + _table(header, rows)
        + (
            f"<p>Also binding, at zero price (the optimum is degenerate there): "
            f"{html.escape(', '.join(free))}.</p>"
            if free
            else ""
        )
    )


def _cyclogram_section(r: MachineResult) -> list[str]:
    """The optimised cyclogram's heading and table: each operation's minimum
    [deg] and what sets it, its angle and start [deg], what it got beyond its
    minimum [deg] and whether it is critical; a warning where it does not fit."""
    parts = ["<h2>Optimised cyclogram</h2>"]
    if r.optimum is None:
        parts.append(
            f"<p class='warn'>No optimised cyclogram: at {r.nominal_rpm:g} rpm it does not "
            f"fit. {html.escape(r.problem)}</p>"
        )
        return parts
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
        for op, mn, by in zip(r.machine.cyclogram.operations, mins, r.minimum_by, strict=True)
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
    return parts


def _files_section(r: MachineResult, cycle_files: list[str]) -> str:
    """The files written, the page's last section (and the document's end)."""
    cycle = [f'<a href="{name}"><code>{name}</code></a>' for name in cycle_files]
    over = (
        f"; at the optimised timing and {r.nominal_rpm:g} rpm (tables over the cycle, "
        f"the parts to make): {', '.join(cycle)}"
        if cycle
        else ""
    )
    return (
        "<h2>Files</h2><p><code>results.json</code> (schema "
        f"<code>{SCHEMA}</code>), <code>speed_sweep.csv</code>, <code>operations.csv</code>, "
        f"<code>figures/*.png</code>{over}.</p></body></html>"
    )


def _images(figs: list[Figure], section: str) -> list[str]:
    """The figures of one section, embedded, in the order they were drawn."""
    return [_img(p, cap) for sec, cap, p in figs if sec == section]


# --------------------------------------------------------------------- pieces
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
.cm-ctrl { margin: .5em 0; } .cm-ctrl input { width: 60%; vertical-align: middle; }
.cm-scenes { display: flex; flex-wrap: wrap; gap: .5em; }
.cm-fig { margin: 0; } .cm-fig canvas { border: 1px solid #ddd; background: #fff; }
#cm-timeline { width: 100%; border: 1px solid #ddd; margin-top: .5em; }
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
