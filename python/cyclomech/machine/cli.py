"""``cyclomech run`` and ``cyclomech sweep``: the whole machine's commands.

``cyclomech run FILE.toml [--out DIR]`` reads a machine file, analyses it over its
speed range and writes the report (HTML, results.json, CSVs, figures); exit status
3 when the machine works at no speed, its nominal speed does not fit or is above a
mechanism's limit, or a mechanism fails its own checks there (a servo's motor).
``cyclomech sweep FILE.toml --set MECH.KEY=FROM:TO:COUNT [--speed FROM:TO:COUNT]
[--dask …]`` computes the machine's key figures over a grid of its parameters and
speeds and writes them as a table (Parquet, or NumPy .npz without pyarrow); exit
status 3 when every design of the sweep is invalid.

>>> import argparse
>>> from cyclomech.machine import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> sorted(commands.choices)
['run', 'sweep']
>>> commands.choices["sweep"].parse_args(["loom.toml", "--set", "lifter.preload_m=1e-4:2e-4:3"]).set
['lifter.preload_m=1e-4:2e-4:3']
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

from .._cli import (
    EXIT_FAILS,
    EXIT_OK,
    has_matplotlib,
    out_folder,
    out_path,
    plural,
    quiet_interrupt,
)
from .._errors import InputError
from ._efficiency import efficiency_line, machine_efficiency

__all__ = ["add_commands", "design_range", "run_command", "sweep_command"]


def add_commands(commands: Any) -> None:
    """Add the ``run`` and ``sweep`` commands to the sub-parsers ``commands`` of
    ``cyclomech``. They read machine files (``machine_file``): the other commands
    send a machine file here."""
    m = commands.add_parser("run", help="the whole machine: a machine file (TOML) in, a report out")
    m.add_argument("file", help="machine file, e.g. examples/stb_loom.toml")
    m.add_argument("--out", help="output folder (default: out/<file name>)")
    m.add_argument("--no-plot", action="store_true", help="do not draw the figures")
    m.add_argument("--quiet", action="store_true", help="no progress bar")
    m.add_argument(
        "--no-sensitivities",
        action="store_true",
        help="skip which key buys speed (two speed limits per key of the file: most of "
        "a run's time where cams bound the speed); the report says it was skipped",
    )
    m.add_argument(
        "--animate",
        action="store_true",
        help="also write machine.gif: every mechanism moving over one cycle beside the "
        "cyclogram (needs matplotlib; some seconds)",
    )
    m.set_defaults(run=run_command, machine_file=True)
    w = commands.add_parser("sweep", help="a machine's key figures over parameters and speeds")
    w.add_argument("file", help="machine file, e.g. examples/stb_loom.toml")
    w.add_argument(
        "--set",
        action="append",
        metavar="MECH.KEY=FROM:TO:COUNT",
        help="a parameter of the file to sweep (repeat for a grid)",
    )
    w.add_argument("--speed", metavar="FROM:TO:COUNT", help="speeds [rpm] (default: the file's)")
    w.add_argument("--out", help="output folder (default: out/<file name>)")
    w.add_argument(
        "--dask",
        metavar="local[:N]|tcp://HOST:PORT",
        help="run the chunks on Dask: a LocalCluster of N processes, or a running scheduler",
    )
    w.add_argument("--threads", type=int, help="Rust threads in this process (default: all)")
    w.add_argument("--quiet", action="store_true", help="no progress bar")
    w.add_argument(
        "--shaft",
        action="store_true",
        help="add the main shaft's torque statistics (one full analysis per design)",
    )
    w.set_defaults(run=sweep_command, machine_file=True)


def _print_shaft_and_frame(r: Any) -> None:
    """The run's lines on the main shaft (its torque, its real speed under the drive,
    the flattening) and on the frame (the shaking force)."""
    if r.shaft is not None:
        s = r.shaft.at_nominal
        print(
            f"Main shaft at {r.nominal_rpm:g} rpm ({', '.join(r.shaft.parts)}): mean torque "
            f"{float(s.mean_torque_nm):.4g} N·m, peak {float(s.peak_torque_nm):.4g} N·m; motor "
            f"{float(s.power_w):.4g} W; flywheel {float(s.flywheel_kg_m2):.4g} kg·m² for "
            f"δ = {r.shaft.speed_fluctuation:g} (ΔE = {float(s.energy_fluctuation_j):.4g} J)"
        )
        eff = machine_efficiency(r)
        if eff is not None:
            print(efficiency_line(eff))
        if r.dynamics is not None:
            print(r.dynamics.line())
        if r.torsion is not None:
            print(r.torsion.line())
        fl = r.shaft.flattening
        if fl is not None:
            print(
                f"Flattening the main shaft's torque: peak |T| {fl.peak_before_nm:.4g} → "
                f"{fl.peak_after_nm:.4g} N·m" + (f" ({fl.note})" if fl.note else "")
            )
    if r.shaking is not None:
        st = r.shaking.stats()
        print(
            f"Shaking force on the frame at {r.nominal_rpm:g} rpm: peak "
            f"{st['peak_force_n']:.4g} N, RMS {st['rms_force_n']:.4g} N; moment peak "
            f"{st['peak_moment_nm']:.4g} N·m"
        )
        for k, why in r.shaking.shaking.notes.items():
            print(f"  assumed for {k}: {why}")
        for k, b in r.shaking.balances.items():
            weights = ", ".join(
                f"{c.link} {c.mass_radius_kg_m:.4g} kg·m at {c.angle_deg:.1f}°"
                + (" (at the bound max_mass_radius_kg_m)" if c.link in b.at_bound else "")
                for c in b.counterweights
            )
            before, after = b.before["rms_force_n"], b.after["rms_force_n"]
            # A force balanced to rounding is 0 (its digits would be the processor's).
            left = "0" if after <= 1e-9 * before else f"{after:.4g}"
            print(
                f"Balancing {k} ({b.objective}): {weights}; RMS shaking force "
                f"{before:.4g} → {left} N"
            )


def _print_resizing(r: Any) -> None:
    """What the mechanisms that size themselves chose at the optimised timing."""
    z = r.resizing
    if z is None:
        return
    end = f"a fixed point in {z.rounds} rounds" if z.converged else f"NO fixed point: {z.note}"
    print(f"Sized at the optimised timing ({end}):")
    for name, sizes in z.history[-1]["sizes"].items():
        dims = ", ".join(f"{k} = {v:.6g}" for k, v in sizes.items())
        res = r.mechanisms.get(name)
        sized = getattr(getattr(res, "mech", None), "sized", None)
        why = ""
        if sized is not None:
            why = f" ({sized.binding} binds)" if sized.binding else f" ({sized.status})"
            if getattr(res.mech, "sizing_status", "") == "at_upper_bound":
                why = f" (at its upper bound{'; ' + why[2:-1] if sized.binding else ''})"
        print(f"  {name}: {dims}{why}")


def _print_sensitivities(r: Any) -> None:
    """The three keys that buy the most speed per 1 %, in one line."""
    top = [s for s in r.sensitivities or () if s.status == "binds"][:3]
    if top:
        keys = ", ".join(f"{s.key} {s.rpm_per_percent:+.3g} rpm" for s in top)
        print(f"Speed limit per +1 % of a key: {keys} (all keys in the report)")


#: Frames of ``--animate``'s GIF over the cycle (4° apart).
GIF_FRAMES = 90


def _animate(r: Any, out: Path, quiet: bool) -> None:
    """``--animate``: write ``machine.gif`` into ``out``, or say on stderr why not."""
    from .plot import animate_machine

    if not has_matplotlib("--animate"):
        return
    if not quiet:
        print("drawing the animation …", file=sys.stderr, flush=True)
    try:
        gif = animate_machine(r, out / "machine.gif", frames=GIF_FRAMES)
    except InputError as e:
        print(f"cyclomech: no animation: {e}", file=sys.stderr)
        return
    print(f"Animation: {gif}")


def run_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech run`` with the parsed ``args``; return the exit status."""
    from . import Machine, analyze, write_report

    m = Machine.from_toml(args.file)
    kinds = ", ".join(f"{k} ({v.kind})" for k, v in m.mechanisms.items())
    print(
        f"{m.name}: {plural(len(m.mechanisms), 'mechanism')}{': ' + kinds if kinds else ''}; "
        f"{len(m.cyclogram.operations)} operations; speeds {m.speed_range_rpm[0]:g}–"
        f"{m.speed_range_rpm[1]:g} rpm"
    )
    out = out_folder(args)
    r = analyze(
        m, progress=None if not args.quiet else False, sensitivities=not args.no_sensitivities
    )
    lim = r.limit
    by = "the cyclogram" if lim.by == "cyclogram" else f"mechanism {lim.by!r}"
    if lim.rpm == 0:  # no speed is to blame: the reason names the chain
        print(f"The machine works at no speed: {lim.reason}")
    elif r.optimum is None:
        print(f"Speed limit: {lim.rpm:.2f} rpm, set by {by}: {lim.reason}")
        print(f"At {r.nominal_rpm:g} rpm the cyclogram does not fit: {r.problem}")
    else:
        print(f"Speed limit: {lim.rpm:.2f} rpm, set by {by}: {lim.reason}")
        op = m.cyclogram.operation(m.cyclogram.limiting)  # type: ignore[arg-type]
        o = r.optimum
        print(
            f"At {r.nominal_rpm:g} rpm the limiting operation {op.title!r} gets "
            f"{o.objective:.2f}° ({max(o.stretch[op.arc], 0.0):.2f}° more than its minimum)"
        )
        priced = [f"{k} ({v:+.3g})" for k, v in o.duals.items() if abs(v) > 1e-9]
        if priced:
            print("Binding, with shadow prices: " + ", ".join(priced))
    _print_sensitivities(r)
    _print_resizing(r)
    _print_shaft_and_frame(r)
    use_fig = not args.no_plot and has_matplotlib("figures")
    if use_fig and not args.quiet:
        print("drawing the figures …", file=sys.stderr, flush=True)  # a few seconds
    written = write_report(r, out, figures=use_fig)
    print(f"\nReport: {out / 'report.html'}  ({len(written)} files in {out})")
    if args.animate:
        _animate(r, out, args.quiet)
    if not r.fails:  # results.json's "fails": exit 3 exactly when it lists something
        return EXIT_OK
    if lim.rpm == 0:
        print(
            f"cyclomech: {args.file}: the machine works at no speed (exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    if r.optimum is None:
        # The file asked for a speed the cyclogram does not fit at: the report is
        # written, but the design fails there, and that must not look like success.
        print(
            f"cyclomech: {args.file}: the cyclogram does not fit at the nominal "
            f"{r.nominal_rpm:g} rpm (speed limit {lim.rpm:.2f} rpm; exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    if r.above_speed_limit:
        # The cyclogram fits, but a mechanism does not work that fast (analyze warned).
        print(
            f"cyclomech: {args.file}: {r.above_speed_limit} (exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    # The timing fits, but a mechanism fails its own checks there (a servo motor too
    # hot or too weak): the design does not work as it stands.
    for text in r.fails:
        print(f"cyclomech: {args.file}: {text}", file=sys.stderr)
    print(f"cyclomech: {args.file}: exit status {EXIT_FAILS}", file=sys.stderr)
    return EXIT_FAILS


def sweep_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech sweep`` with the parsed ``args``; return the exit status."""
    from .._arrays import speeds_rpm
    from . import Machine, check_parameter, dask_client, dask_workers, parse_range, sweep

    m = Machine.from_toml(args.file)
    workers = dask_workers(args.dask) if args.dask else 0
    grid: dict[str, Any] = {}
    for item in args.set or []:
        name, eq, text = item.partition("=")
        if not eq or not name:
            raise InputError(f"--set {item!r} must be <mechanism>.<key>=from:to:count")
        grid[name] = parse_range(text, f"--set {name}:")
    if args.threads is not None and not 1 <= args.threads <= 1024:
        raise InputError(f"--threads {args.threads} must be between 1 and 1024")
    if args.speed is not None:
        values = parse_range(args.speed, "--speed")
        if values.size > 1 and not (values[0] < values[-1]):
            raise InputError(
                f"--speed {args.speed} must go from a lower to a higher speed "
                "(FROM < TO, in rpm), as the file's speed_rpm does"
            )
        grid["speed_rpm"] = speeds_rpm("--speed", values)
    params = {k: v for k, v in grid.items() if k != "speed_rpm"}
    for k in params:  # a key the file cannot take fails before the work starts
        check_parameter(m, k)
    designs = math.prod(v.size for v in params.values())
    speeds = grid["speed_rpm"].size if "speed_rpm" in grid else m.speed_points
    print(
        f"{m.name}: sweeping {plural(designs, 'design')} × {plural(speeds, 'speed')} = "
        f"{plural(designs * speeds, 'point')}" + (f" on Dask ({args.dask})" if args.dask else ""),
        flush=True,
    )
    if workers:
        # Ctrl-C is ignored while the workers start (see _sweep._sigint_ignored).
        print(f"starting a Dask LocalCluster of {workers} worker processes …", flush=True)
    out = out_path(args)  # made when the first rows are written (none on a Ctrl-C)
    try:  # Parquet streams the rows as they come: any size in bounded memory
        import pyarrow.parquet  # noqa: F401

        target: Path | None = out / "sweep.parquet"
    except ImportError:
        target = None
    client = dask_client(args.dask) if args.dask else None
    try:
        with quiet_interrupt(client is not None):
            r = sweep(
                m,
                grid,
                client,
                progress=None if not args.quiet else False,
                n_threads=args.threads,
                out=target,
                shaft=args.shaft,
            )
    finally:
        if client is not None:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None and args.dask.startswith("local"):
                cluster.close()
    name = "sweep.npz" if target is None else "sweep.parquet"  # npz without pyarrow
    path = r.path if r.path is not None else r.write(out_folder(args) / name)
    summary = r.summary or {
        "points": r.n_points,
        "fits": int(r.columns["fits"].sum()),
        "invalid": r.n_invalid,
        "problem": next((str(p) for p in r.columns["problem"] if p), ""),
    }
    print(
        f"{plural(r.n_points, 'point')} ({plural(designs, 'design')} × "
        f"{plural(speeds, 'speed')}) in "
        f"{r.seconds:.2f} s"
        + (f" on Dask ({args.dask})" if args.dask else "")
        + f"; the cyclogram fits at {summary['fits']} of them"
    )
    bad = summary["invalid"] // speeds
    if bad:
        print(
            f"{plural(bad, 'design')} of {designs} {'is' if bad == 1 else 'are'} invalid "
            f"and counted as not fitting (the 'problem' column says why); the first: "
            f"{summary['problem']}"
        )
    line = design_range(path, r.columns, list(params)) if designs > 1 else ""
    if line:
        print(line)
    elif designs == 1 and design_range(path, r.columns, []):
        lim = design_range(path, r.columns, []).split("\n")[0].rpartition("–")[2]
        print(f"speed limit of the design: {lim}")
    print(f"Wrote {path}")
    if path.suffix == ".npz":
        print("(NumPy .npz: pyarrow is not installed; `pip install pyarrow` writes Parquet)")
    if bad == designs:
        print(
            f"cyclomech: {args.file}: every design of the sweep is invalid "
            f"(exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    if not summary["fits"]:
        print(
            f"cyclomech: {args.file}: the cyclogram fits at no point of the sweep "
            f"(its speed_limit_rpm and binding columns say where each design stops; "
            f"exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    return EXIT_OK


#: Speed limits of two designs within this (relative) of each other are a tie in
#: :func:`design_range`: ten times the speed search's default ``rtol`` (1e-10), so
#: designs its search cannot tell apart count as one limit.
TIE_RTOL = 1e-9


def _tie(a: Any, b: float) -> Any:
    """``a`` (a limit or an array of them) ties with ``b`` [rpm]: equal (∞ = ∞ too)
    or within :data:`TIE_RTOL` of it."""
    import numpy as np

    if not math.isfinite(b):
        return np.asarray(a) == b
    return np.abs(np.asarray(a) - b) <= TIE_RTOL * abs(b)


def design_range(path: Path, columns: dict[str, Any], params: list[str]) -> str:
    """One line naming the designs of a sweep with the highest and the lowest speed
    limit [rpm] and their parameters; empty when no design has one (all invalid).

    The rows are read from ``columns`` when the sweep kept them, else from the
    Parquet file at ``path`` in batches (a streamed sweep of any size; read twice:
    the limits, then the designs at the extremes). A design's speed limit is the
    same on each of its rows. Ties: the designs whose limit is within
    :data:`TIE_RTOL` (1e-9, relative) of the highest (or the lowest) share it; the
    line names the first of them in the sweep's order and says how many more there
    are. A design that fits up to the speed cap has an infinite limit (∞ ties only
    with ∞).

    Parameters
    ----------
    path : pathlib.Path
        The sweep's file (read only when ``columns`` is empty).
    columns : dict of str to numpy.ndarray
        The sweep's columns, or an empty dict for a streamed sweep.
    params : list of str
        The swept parameters, ``"mechanism.key"``.

    Returns
    -------
    str
        Three lines: the range of the designs' speed limits, then the design
        with the highest and the one with the lowest.

    Examples
    --------
    >>> import numpy as np
    >>> cols = {"lifter.preload_m": np.array([1e-4, 1e-4, 2e-4, 2e-4, 3e-4, 3e-4]),
    ...         "speed_limit_rpm": np.array([441.7, 441.7, 402.1, 402.1, 441.7, 441.7])}
    >>> print(design_range(Path("unused"), cols, ["lifter.preload_m"]))
    speed limit over the designs: 402.1–441.7 rpm
      highest 441.7 rpm at lifter.preload_m=0.0001 (and 1 more design at it)
      lowest  402.1 rpm at lifter.preload_m=0.0002
    """
    import numpy as np

    def batches(names: list[str]) -> Any:
        if columns:
            return [{k: np.asarray(columns[k]) for k in names}]
        import pyarrow.parquet as pq

        return (
            {k: b.column(k).to_numpy(zero_copy_only=False) for k in names}
            for b in pq.ParquetFile(path).iter_batches(columns=names, batch_size=1 << 16)
        )

    hi, lo = -math.inf, math.inf
    for b in batches(["speed_limit_rpm"]):
        lim = np.asarray(b["speed_limit_rpm"], dtype=np.float64)
        if not np.isnan(lim).all():
            hi, lo = max(hi, float(np.nanmax(lim))), min(lo, float(np.nanmin(lim)))
    if lo > hi:
        return ""
    # The designs at each extreme, in the sweep's order (a design has several rows).
    at: dict[float, list[Any]] = {hi: [], lo: []}
    for b in batches([*params, "speed_limit_rpm"]) if params else ():
        tie = {x: _tie(np.asarray(b["speed_limit_rpm"], dtype=np.float64), x) for x in at}
        for x, rows in tie.items():
            at[x].append(np.column_stack([np.asarray(b[k])[rows] for k in params]))

    def named(x: float) -> str:
        if not params:  # one design
            return ""
        rows = np.concatenate(at[x])
        where = ", ".join(f"{k}={v:g}" for k, v in zip(params, rows[0], strict=True))
        more = len(np.unique(rows, axis=0)) - 1  # distinct designs: a design has rows
        return where + (f" (and {plural(more, 'more design')} at it)" if more else "")

    return (
        f"speed limit over the designs: {lo:.4g}–{hi:.4g} rpm\n"
        f"  highest {hi:.4g} rpm at {named(hi)}\n"
        f"  lowest  {lo:.4g} rpm at {named(lo)}"
    )
