"""``cyclomech linkage FILE.toml [--out DIR] [--step-deg S]``: the linkage's command.

Solves a linkage over a full crank turn and writes the analog table (CSV), a JSON
summary and figures (the mechanism with the traced path of its output point, the
output point's analogs). Exit status 3 when the linkage can be assembled at no
angle, or cannot make a full turn under ``--require-full-turn``.

>>> import argparse
>>> from cyclomech.linkage import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> commands.choices["linkage"].parse_args(["crank.toml", "--step-deg", "2"]).step_deg
2.0
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

from .._cli import EXIT_FAILS, EXIT_OK, check_step, has_matplotlib, out_folder, plural, save
from .._files import savetxt, write_text
from . import Linkage, LinkageSolution

__all__ = ["add_commands", "linkage_command"]


def add_commands(commands: Any) -> None:
    """Add the ``linkage`` command to the sub-parsers ``commands`` of ``cyclomech``.

    Parameters
    ----------
    commands : argparse._SubParsersAction
        The sub-parsers of the ``cyclomech`` parser (``add_subparsers()``).

    Examples
    --------
    >>> import argparse
    >>> from cyclomech.linkage import cli
    >>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
    >>> cli.add_commands(commands)
    >>> args = commands.choices["linkage"].parse_args(["crank.toml", "--no-plot"])
    >>> args.step_deg, args.no_plot, args.run is cli.linkage_command
    (1.0, True, True)
    """
    q = commands.add_parser("linkage", help="solve a linkage file (TOML) over a crank turn")
    q.add_argument("file", help="linkage file, e.g. examples/burg_trimmer.toml")
    q.add_argument("--out", help="output folder (default: out/<file name>)")
    q.add_argument("--step-deg", type=float, default=1.0, help="crank-angle step [°] (default 1)")
    q.add_argument("--no-plot", action="store_true", help="do not write the figures")
    q.add_argument(
        "--require-full-turn",
        action="store_true",
        help=f"exit with status {EXIT_FAILS} if the linkage cannot make a full crank turn",
    )
    q.set_defaults(run=linkage_command)


def _analog_table(sol: LinkageSolution) -> tuple[list[str], Any]:
    """Columns and rows of the analog table: one row per crank angle."""
    import numpy as np

    cols = ["angle_deg", "ok", "singular", "branch_change"]
    parts = [np.degrees(sol.angles)[:, None], sol.ok[:, None], sol.singular[:, None]]
    parts.append(sol.branch_change[:, None])
    assert sol.vel is not None and sol.acc is not None
    for k, name in enumerate(sol.names):
        cols += [f"{name}_{q}" for q in ("x", "y", "dx", "dy", "ddx", "ddy")]
        parts += [sol.xy[:, k], sol.vel[:, k], sol.acc[:, k]]
    return cols, np.hstack([np.asarray(p, dtype=np.float64) for p in parts])


def _turn_range(a: float, b: float) -> str:
    """A range of crank angles [deg] walked from the drawn angle (up to 360° past
    it), shown within one turn: 343…377° reads 343…17° (through 0°).

    >>> _turn_range(38.0, 322.0), _turn_range(343.0, 377.0)
    ('38…322°', '343…17° (through 0°)')
    """
    lo, hi = a % 360.0, b % 360.0
    return f"{lo:.6g}…{hi:.6g}°" + (" (through 0°)" if hi < lo else "")


def _runs(bad: Any, deg: Any, step: float) -> list[tuple[float, float]]:
    """The ranges [from, to] of crank angle [deg] where ``bad`` holds, on a grid of
    one turn: runs of neighbours, a run that wraps past the last angle joined to
    the first."""
    import numpy as np

    idx = np.flatnonzero(bad)
    if not idx.size:
        return []
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.r_[idx[0], idx[breaks + 1]]
    ends = np.r_[idx[breaks], idx[-1]]
    runs = [[int(a), int(b)] for a, b in zip(starts, ends, strict=True)]
    n = len(bad)
    if len(runs) > 1 and runs[0][0] == 0 and runs[-1][1] == n - 1:
        runs[0][0] = runs.pop()[0] - n  # wraps: one range through the start
    return [(float(deg[0] + a * step), float(deg[0] + b * step)) for a, b in runs]


def _summary(lk: Linkage, sol: LinkageSolution, point: str, step: float) -> dict[str, Any]:
    import numpy as np

    k = sol.index(point)
    assert sol.vel is not None and sol.acc is not None
    xy = sol.xy[sol.ok, k]
    out: dict[str, Any] = {
        "schema": "cyclomech.linkage/1",
        "name": lk.name,
        "structure": [[kind, list(joints)] for kind, joints in lk.structure],
        "dimensions": [
            {"joints": list(pair), "length_m": float(v)}
            for pair, v in zip(lk.dimensions, lk.dimension_values, strict=True)
        ],
        "angles": len(sol.angles),
        "assembled": int(sol.ok.sum()),
        "singular": int(sol.singular.sum()),
        "branch_changes": [float(a) for a in np.degrees(sol.angles[sol.branch_change])],
        # Where a class II group's two assemblies meet (Linkage.change_points)
        "change_points": [
            {"joint": j, "angle_deg": math.degrees(a) % 360.0, "followed": f}
            for j, a, f in lk.change_points
        ],
        "full_turn": bool(sol.ok.all()),
        "unreachable_deg": [
            list(r) for r in _runs(~sol.ok, np.degrees(sol.angles), step) if not sol.ok.all()
        ],
        "output": point,
    }
    if len(xy):
        out["output_range_m"] = {
            "x": [float(xy[:, 0].min()), float(xy[:, 0].max())],
            "y": [float(xy[:, 1].min()), float(xy[:, 1].max())],
        }
        out["output_stroke_m"] = sol.stroke(point)
        # Over the angles where the linkage is assembled: the whole turn, or not.
        out["output_over"] = "the whole turn" if sol.ok.all() else "the reachable angles only"
        speed = np.hypot(*sol.vel[sol.ok, k].T)
        accel = np.hypot(*sol.acc[sol.ok, k].T)
        out["max_velocity_analog_m_per_rad"] = float(np.nanmax(speed))
        out["max_acceleration_analog_m_per_rad2"] = float(np.nanmax(accel))
    return out


def _print_change_points(found: list[dict[str, Any]], file: str) -> None:
    """Say where the linkage passes change points (uncertainty positions) and how the
    solve took them: followed (a guide is needed), or held (its velocity jumps).

    >>> _print_change_points([{"joint": "C", "angle_deg": 180.0, "followed": True},
    ...                       {"joint": "C", "angle_deg": 0.0, "followed": True}],
    ...                      "pg.toml")  # doctest: +NORMALIZE_WHITESPACE
    Change points (a group's two assemblies meet): joint 'C' at 180.00°, joint 'C' at
    0.00°; followed smoothly, as a guide (a second coupler out of phase) makes the
    mechanism do
    """
    if not found:
        return
    where = ", ".join(f"joint {c['joint']!r} at {c['angle_deg']:.2f}°" for c in found)
    print(
        f"Change points (a group's two assemblies meet): {where}; followed smoothly, as a "
        "guide (a second coupler out of phase) makes the mechanism do"
        if all(c["followed"] for c in found)
        else f"Change points (a group's two assemblies meet): {where}"
    )
    held = sorted({c["joint"] for c in found if not c["followed"]})
    if held:
        print(
            f"cyclomech: warning: {file}: joint {held[0]!r} passes an odd number of change "
            "points a crank turn, so its smooth motion repeats only every two turns; it is "
            "held on its drawn side and its velocity jumps there (a four-bar with "
            "s + l = p + q has one); a machine refuses it",
            file=sys.stderr,
        )


def linkage_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech linkage`` with the parsed ``args``; return the exit status.

    Prints a summary and writes ``analogs.csv``, ``linkage.json`` and (unless
    ``--no-plot``) the figures to the output folder.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of the ``linkage`` command (``file``, ``out``,
        ``step_deg`` [deg], ``no_plot``, ``require_full_turn``).

    Returns
    -------
    int
        The exit status: 0, or 3 when the linkage can be assembled at no angle, or
        cannot make a full turn under ``--require-full-turn``.

    Raises
    ------
    InputError
        If the file cannot be read or describes no valid linkage, or the step is
        not a valid angle.

    Examples
    --------
    >>> import argparse, contextlib, io, pathlib, tempfile
    >>> from cyclomech.linkage import cli
    >>> parser = argparse.ArgumentParser(prog="cyclomech")
    >>> cli.add_commands(parser.add_subparsers())
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> args = parser.parse_args(
    ...     ["linkage", "examples/crank_rocker.toml", "--out", str(out), "--no-plot"])
    >>> with contextlib.redirect_stdout(io.StringIO()) as printed:
    ...     status = cli.linkage_command(args)
    >>> status, printed.getvalue().splitlines()[0], sorted(p.name for p in out.iterdir())
    (0, 'crank-rocker: 4 points, structure driver – II(C)', ['analogs.csv', 'linkage.json'])
    """
    import numpy as np

    lk = Linkage.from_toml(args.file)
    step = args.step_deg
    check_step(step)
    n = round(360.0 / step)
    angles = lk.drawn_angle + np.radians(np.arange(n) * step)
    sol = lk.solve(angles)
    point = lk.output or lk.names[-1]
    summary = _summary(lk, sol, point, step)
    structure = " – ".join(
        kind if kind == "driver" else f"{kind}({', '.join(j)})" for kind, j in lk.structure
    )
    print(f"{lk.name or Path(args.file).stem}: {len(lk.names)} points, structure {structure}")

    def at(count: int, what: str) -> str:
        return f"no {what}" if count == 0 else f"{what} at {plural(count, 'angle')}"

    print(
        f"Solved {n} crank angles from the drawn {math.degrees(lk.drawn_angle):.2f}° in steps "
        f"of {step:g}°: assembled at {summary['assembled']} of {n}, "
        f"{at(summary['singular'], 'dead centres')}, "
        f"{at(len(summary['branch_changes']), 'branch changes')}."
    )
    _print_change_points(summary["change_points"], args.file)
    full = bool(sol.ok.all())
    if not full and sol.ok.any():
        ranges = ", ".join(_turn_range(a, b) for a, b in summary["unreachable_deg"])
        why = lk.mismatched_lengths()
        print(
            f"cyclomech: warning: {args.file}: the linkage cannot make a full turn: it cannot "
            f"be assembled at crank angles {ranges}; the output's range, stroke and peaks "
            "below are over the reachable angles only"
            + (f" (the lengths given differ from the drawing: {'; '.join(why)})" if why else ""),
            file=sys.stderr,
        )
    if "output_range_m" in summary:
        r = summary["output_range_m"]
        print(
            f"Output point {point}: x {r['x'][0]:.6g}…{r['x'][1]:.6g} m, "
            f"y {r['y'][0]:.6g}…{r['y'][1]:.6g} m"
            + (
                f", stroke {summary['output_stroke_m']:.6g} m"
                if "output_stroke_m" in summary
                else ""
            )
            + f"; |d xy/dφ| ≤ {summary['max_velocity_analog_m_per_rad']:.6g} m/rad, "
            f"|d² xy/dφ²| ≤ {summary['max_acceleration_analog_m_per_rad2']:.6g} m/rad²"
            + ("" if full else f" (over {summary['output_over']})")
        )
    out = out_folder(args)
    cols, table = _analog_table(sol)
    savetxt(
        out / "analogs.csv", table, delimiter=",", header=",".join(cols), comments="", fmt="%.12g"
    )
    write_text(out / "linkage.json", json.dumps(summary, indent=2, ensure_ascii=False))
    written = [out / "analogs.csv", out / "linkage.json"]
    if not args.no_plot:
        written += _figures(lk, sol, point, out)
    print("\nWrote " + ", ".join(str(p) for p in written))
    if not sol.ok.any():
        print("cyclomech: the linkage cannot be assembled at any angle", file=sys.stderr)
        return EXIT_FAILS
    if not full and args.require_full_turn:
        print(
            f"cyclomech: {args.file}: the linkage cannot make a full turn (exit status "
            f"{EXIT_FAILS}, --require-full-turn)",
            file=sys.stderr,
        )
        return EXIT_FAILS
    return EXIT_OK


def _figures(lk: Linkage, sol: LinkageSolution, point: str, out: Path) -> list[Path]:
    written: list[Path] = []
    if not has_matplotlib():
        return written
    from .plot import plot_analogs, plot_linkage

    if sol.ok.any():
        first = int(sol.ok.argmax())
        ax = plot_linkage(lk, sol, first, trace=[point])
        save(ax.figure, out / "mechanism.png", written)
    save(plot_analogs(sol, point), out / f"analogs_{point}.png", written)
    return written
