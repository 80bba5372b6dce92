"""``cyclomech cyclogram FILE.toml [--out DIR] [--speed RPM]``: the cyclogram's command.

Prints the schedule (every operation at its minimum), the LP optimum and the speed
limit, and writes a figure and a JSON summary to ``--out``. Exit status 3 when the
cyclogram has no feasible optimum (its files are written all the same).

>>> import argparse
>>> from cyclomech.cyclogram import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> sorted(commands.choices)
['cyclogram']
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from .._cli import EXIT_FAILS, EXIT_OK, has_matplotlib, out_folder, save, table
from .._errors import InfeasibleError
from .._files import write_text
from .._json import jsonable
from . import Arc, Cyclogram, Optimum, Schedule, SpeedLimit

__all__ = ["add_commands", "cyclogram_command"]


def add_commands(commands: Any) -> None:
    """Add the ``cyclogram`` command to the sub-parsers ``commands`` of ``cyclomech``.

    Parameters
    ----------
    commands : argparse._SubParsersAction
        The sub-parsers of the ``cyclomech`` parser (``add_subparsers()``).

    Examples
    --------
    >>> import argparse
    >>> from cyclomech.cyclogram import cli
    >>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
    >>> cli.add_commands(commands)
    >>> args = commands.choices["cyclogram"].parse_args(["g.toml", "--speed", "300"])
    >>> args.speed, args.run is cli.cyclogram_command
    (300.0, True)
    """
    p = commands.add_parser("cyclogram", help="schedule, optimise and plot a cyclogram file (TOML)")
    p.add_argument("file", help="cyclogram file, e.g. examples/stb_group1.toml")
    p.add_argument("--out", help="output folder (default: out/<file name>)")
    p.add_argument("--speed", type=float, help="main-shaft speed [rpm] for time-bound operations")
    p.add_argument("--no-plot", action="store_true", help="do not write the figure")
    p.set_defaults(run=cyclogram_command)


def _arc(a: Arc) -> str:
    return f"{a[0]}→{a[1]}"


def _print_schedule(cg: Cyclogram, s: Schedule) -> None:
    print(
        "\nSchedule, every operation at its minimum angle"
        + (f" (at {s.speed_rpm:g} rpm)" if s.speed_rpm is not None else "")
    )
    crit = set(s.critical)
    rows = [
        [
            op.mechanism or "",
            op.title,
            _arc(op.arc),
            f"{s.angles[op.arc]:.1f}",
            f"{s.earliest[op.src]:.1f}",
            f"{s.slack[op.arc]:.1f}",
            "*" if op.arc in crit else "",
        ]
        for op in cg.operations
    ]
    print(table(rows, ["mechanism", "operation", "arc", "angle°", "start°", "slack°", "critical"]))
    print(f"  duration {s.duration:.1f}° of the {s.cycle_deg:g}° cycle")


def _print_optimum(cg: Cyclogram, o: Optimum, s: Schedule) -> None:
    if o.limiting is not None:
        op = cg.operation(o.limiting)
        print(
            f"\nOptimum (LP, HiGHS): the limiting operation {op.title!r} gets {o.objective:.2f}° "
            f"of the {o.cycle_deg:g}° cycle, {o.stretch[o.limiting]:.2f}° more than its minimum "
            f"of {s.angles[o.limiting]:.2f}°"
        )
    else:
        print(f"\nOptimum (LP, HiGHS): shortest duration {o.objective:.2f}°")
    rows = [
        [
            op.mechanism or "",
            op.title,
            _arc(op.arc),
            f"{o.angles[op.arc]:.2f}",
            f"{o.times[op.src]:.2f}",
            f"{o.stretch[op.arc]:.2f}",
        ]
        for op in cg.operations
    ]
    print(table(rows, ["mechanism", "operation", "arc", "angle°", "start°", "stretch°"]))
    priced = [(k, v) for k, v in o.duals.items() if abs(v) > 1e-9]
    if priced:
        print(
            "  priced bounds and constraints"
            " (shadow price: change of the objective per unit of the bound)"
        )
        for k, v in priced:
            print(f"    {k:<40} {v:+.4g}")


def _print_speed(lim: SpeedLimit) -> None:
    if math.isinf(lim.rpm):
        print(
            "\nSpeed limit: none"
            " (no time-bound operation lies on a chain that must fit in the cycle)"
        )
        return
    print(
        f"\nSpeed limit: {lim.rpm:.2f} rpm (the operations' own angles and durations allow "
        f"{lim.network_rpm:.2f} rpm)"
    )
    if lim.cycle:
        print("  limiting chain: " + ", ".join(_arc(a) for a in lim.cycle))
    if lim.binding:
        print("  also binding: " + ", ".join(lim.binding))


def _summary(
    cg: Cyclogram, s: Schedule, o: Optimum | None, lim: SpeedLimit | None
) -> dict[str, Any]:
    out: dict[str, Any] = {
        "schema": "cyclomech.cyclogram/1",
        "name": cg.name,
        "cycle_deg": cg.cycle_deg,
        "speed_rpm": s.speed_rpm,
        "schedule": {
            "earliest_deg": s.earliest,
            "latest_deg": s.latest,
            "angles_deg": s.angles,
            "slack_deg": s.slack,
            "critical": list(s.critical),
            "duration_deg": s.duration,
        },
    }
    if o is not None:
        out["optimum"] = {
            "goal": o.goal,
            "limiting": o.limiting,
            "objective_deg": o.objective,
            "times_deg": o.times,
            "angles_deg": o.angles,
            "duals": o.duals,
            "binding": list(o.binding),
        }
    if lim is not None:
        out["speed_limit"] = {
            "rpm": lim.rpm,
            "network_rpm": lim.network_rpm,
            "chain": list(lim.cycle),
            "binding": list(lim.binding),
        }
    return jsonable(out)


def cyclogram_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech cyclogram`` with the parsed ``args``; return the exit status.

    Prints the schedule, the LP optimum and the speed limit, and writes
    ``cyclogram.json`` and (unless ``--no-plot``) ``cyclogram.png`` to the output
    folder.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of the ``cyclogram`` command (``file``, ``out``,
        ``speed`` [rpm], ``no_plot``).

    Returns
    -------
    int
        The exit status: 0, or 3 when the cyclogram has no feasible optimum (its
        files are written all the same).

    Raises
    ------
    InputError
        If the file cannot be read or describes no valid cyclogram.
    CycleError
        When the operations within one cycle form a cycle.

    Examples
    --------
    >>> import argparse, contextlib, io, pathlib, tempfile
    >>> from cyclomech.cyclogram import cli
    >>> parser = argparse.ArgumentParser(prog="cyclomech")
    >>> cli.add_commands(parser.add_subparsers())
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> args = parser.parse_args(
    ...     ["cyclogram", "examples/stb_group1.toml", "--out", str(out), "--no-plot"])
    >>> with contextlib.redirect_stdout(io.StringIO()) as printed:
    ...     status = cli.cyclogram_command(args)
    >>> status, sorted(p.name for p in out.iterdir())
    (0, ['cyclogram.json'])
    >>> printed.getvalue().splitlines()[0]
    'STB loom, group 1 (illustrative): 10 events, 11 operations, 1 constraints, cycle 360°'
    """
    cg = Cyclogram.from_toml(args.file)
    if args.speed is not None:
        cg.speed_rpm = args.speed
    print(
        f"{cg.name}: {len(cg.events)} events, {len(cg.operations)} operations, "
        f"{len(cg.constraints)} constraints, cycle {cg.cycle_deg:g}°"
    )
    s = cg.schedule()
    _print_schedule(cg, s)
    o: Optimum | None
    try:
        o = cg.optimize()
        _print_optimum(cg, o, s)
    except InfeasibleError as e:
        print(f"\nOptimum: none. {e}")
        o = None
    lim = None
    if any(op.min_duration_s > 0 for op in cg.operations):
        try:
            lim = cg.max_speed_rpm()
            _print_speed(lim)
        except InfeasibleError as e:
            print(f"\nSpeed limit: none, {e}")
    out = out_folder(args)
    write_text(
        out / "cyclogram.json", json.dumps(_summary(cg, s, o, lim), indent=2, ensure_ascii=False)
    )
    written = [out / "cyclogram.json"]
    if not args.no_plot and has_matplotlib("figure"):
        from .plot import plot_cyclogram_pair

        if o is None and s.duration > s.cycle_deg:
            # Wrapping a schedule longer than the cycle onto it draws overlaps
            # that mean nothing; say so instead.
            print(f"\n(no figure: the schedule takes {s.duration:g}°, more than the cycle)")
        else:
            save(plot_cyclogram_pair(o if o is not None else s), out / "cyclogram.png", written)
    print("\nWrote " + ", ".join(str(p) for p in written))
    if o is None:
        print("cyclomech: the cyclogram has no feasible optimum (see above)", file=sys.stderr)
        return EXIT_FAILS
    return EXIT_OK
