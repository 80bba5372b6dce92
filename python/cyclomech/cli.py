"""Command line of cyclomech.

``cyclomech cyclogram FILE.toml [--out DIR]`` prints the schedule (every operation
at its minimum), the LP optimum and the speed limit, and writes a figure and a JSON
summary to ``--out``.

``cyclomech linkage FILE.toml [--out DIR] [--step-deg S]`` solves a linkage over a
full crank turn and writes the analog table (CSV), a JSON summary and figures (the
mechanism with the traced path of its output point, the output point's analogs).

Exit status: 0 when the job is done and the design works; 2 for bad input (the
message names the file, the table and the key); 3 when the job is done (its files
written) but the design fails: a machine whose cyclogram fits at no speed, a
linkage that cannot make a full turn under ``--require-full-turn``, a sweep whose
every design is invalid; 130 when
interrupted.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import math
import os
import signal
import sys
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from ._errors import CyclomechError, InfeasibleError, InputError
from ._json import jsonable
from .cyclogram import Arc, Cyclogram, Optimum, Schedule, SpeedLimit
from .linkage import Linkage, LinkageSolution

__all__ = ["main"]

#: Exit status of a job that ran and wrote its files, but whose design fails.
EXIT_FAILS = 3
#: Finest crank-angle step of the linkage and press commands [deg]: 360 000 angles a
#: turn, whose table (CSV) is already hundreds of MB; 1e-6° would allocate gigabytes.
MIN_STEP_DEG = 1e-3


def _arc(a: Arc) -> str:
    return f"{a[0]}→{a[1]}"


def _table(rows: list[list[str]], header: list[str]) -> str:
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]
    fmt = "  ".join(f"{{:<{w}}}" if i < 2 else f"{{:>{w}}}" for i, w in enumerate(widths))
    lines = [fmt.format(*header), fmt.format(*("-" * w for w in widths))]
    lines += [fmt.format(*r) for r in rows]
    return "\n".join("  " + ln for ln in lines)


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
    print(_table(rows, ["mechanism", "operation", "arc", "angle°", "start°", "slack°", "critical"]))
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
    print(_table(rows, ["mechanism", "operation", "arc", "angle°", "start°", "stretch°"]))
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
    return jsonable(out)  # type: ignore[no-any-return]


def _has_matplotlib(what: str = "figures") -> bool:
    """Select the Agg backend, or say why no figures are written."""
    try:
        import matplotlib
    except ImportError:
        print(f"\n(no {what}: matplotlib is not installed; pip install cyclomech[plot])")
        return False
    matplotlib.use("Agg")
    return True


def _save(fig: Any, path: Path, written: list[Path]) -> None:
    """Write ``fig`` to ``path``, close it, and note the file."""
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=130, bbox_inches="tight")
    plt.close(fig)
    written.append(path)


def _cyclogram_command(args: argparse.Namespace) -> int:
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
    out = _out_folder(args)
    (out / "cyclogram.json").write_text(
        json.dumps(_summary(cg, s, o, lim), indent=2, ensure_ascii=False), encoding="utf-8"
    )
    written = [out / "cyclogram.json"]
    if not args.no_plot and _has_matplotlib("figure"):
        from .plot import plot_cyclogram_pair

        if o is None and s.duration > s.cycle_deg:
            # Wrapping a schedule longer than the cycle onto it draws overlaps
            # that mean nothing; say so instead.
            print(f"\n(no figure: the schedule takes {s.duration:g}°, more than the cycle)")
        else:
            _save(plot_cyclogram_pair(o if o is not None else s), out / "cyclogram.png", written)
    print("\nWrote " + ", ".join(str(p) for p in written))
    if o is None:
        print("cyclomech: the cyclogram has no feasible optimum (see above)", file=sys.stderr)
        return 1
    return 0


def _n(count: int, word: str) -> str:
    """``count`` and ``word``, plural where it is not 1: 1 design, 2 designs."""
    return f"{count} {word}{'' if count == 1 else 's'}"


def _out_path(args: argparse.Namespace) -> Path:
    """The output folder of a command, checked before any work: it, or the nearest
    of its parents that exists, must be a writable folder."""
    out = Path(args.out) if args.out else Path("out") / Path(args.file).stem
    near = next((q for q in (out, *out.parents) if q.exists()), Path("."))
    if not near.is_dir():
        what = "is a file" if near == out else f"cannot be made: {near} is a file"
        raise InputError(f"--out {out}: {what}, not a folder; give a folder for the results")
    if not os.access(near, os.W_OK | os.X_OK):
        raise InputError(f"--out {out}: the folder {near} is not writable")
    return out


def _out_folder(args: argparse.Namespace) -> Path:
    out = _out_path(args)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(
            f"--out {out}: cannot create the output folder: {e.strerror or e}"
        ) from None
    return out


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


def _stroke(xy: Any) -> float:
    """The largest distance between two points of a path [m] (its diameter), over
    the vertices of its convex hull; a straight path's extent along its line."""
    import numpy as np
    from scipy.spatial import ConvexHull, QhullError

    try:
        pts = xy[ConvexHull(xy).vertices]
    except (QhullError, ValueError):  # on one line (a slider), or too few points
        centred = xy - xy.mean(axis=0)
        axis = np.linalg.svd(centred, full_matrices=False)[2][0]
        along = centred @ axis
        return float(along.max() - along.min())
    d = pts[:, None, :] - pts[None, :, :]
    return float(np.sqrt((d**2).sum(axis=2)).max())


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


def _linkage_summary(lk: Linkage, sol: LinkageSolution, point: str, step: float) -> dict[str, Any]:
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
        out["output_stroke_m"] = _stroke(xy)
        # Over the angles where the linkage is assembled: the whole turn, or not.
        out["output_over"] = "the whole turn" if sol.ok.all() else "the reachable angles only"
        speed = np.hypot(*sol.vel[sol.ok, k].T)
        accel = np.hypot(*sol.acc[sol.ok, k].T)
        out["max_velocity_analog_m_per_rad"] = float(np.nanmax(speed))
        out["max_acceleration_analog_m_per_rad2"] = float(np.nanmax(accel))
    return out


def _check_step(step: float) -> None:
    """``--step-deg`` of the linkage and press commands, in [MIN_STEP_DEG, 90]°."""
    if not (math.isfinite(step) and MIN_STEP_DEG <= step <= 90):
        raise InputError(
            f"--step-deg {step:g}: give a step in [{MIN_STEP_DEG:g}, 90] degrees "
            f"(at most {round(360 / MIN_STEP_DEG):,} angles a turn)"
        )


def _not_a_machine_file(args: argparse.Namespace) -> None:
    """A machine file given to a one-domain command: say which command reads it
    (as `run` does for the other files)."""
    if args.command in ("run", "sweep"):
        return
    from . import _toml

    try:
        data, source = _toml.load(args.file)
    except InputError:
        return  # the command itself says what is wrong with the file
    if isinstance(data, dict) and "machine" in data:
        raise InputError(
            f"{source}: this is a machine file ([machine]); run it with "
            f"`cyclomech run {args.file}` (or sweep it with `cyclomech sweep`)"
        )


def _linkage_command(args: argparse.Namespace) -> int:
    import numpy as np

    lk = Linkage.from_toml(args.file)
    step = args.step_deg
    _check_step(step)
    n = round(360.0 / step)
    angles = lk.drawn_angle + np.radians(np.arange(n) * step)
    sol = lk.solve(angles)
    point = lk.output or lk.names[-1]
    summary = _linkage_summary(lk, sol, point, step)
    structure = " – ".join(
        kind if kind == "driver" else f"{kind}({', '.join(j)})" for kind, j in lk.structure
    )
    print(f"{lk.name or Path(args.file).stem}: {len(lk.names)} points, structure {structure}")

    def at(count: int, what: str) -> str:
        return f"no {what}" if count == 0 else f"{what} at {_n(count, 'angle')}"

    print(
        f"Solved {n} crank angles from the drawn {math.degrees(lk.drawn_angle):.2f}° in steps "
        f"of {step:g}°: assembled at {summary['assembled']} of {n}, "
        f"{at(summary['singular'], 'dead centres')}, "
        f"{at(len(summary['branch_changes']), 'branch changes')}."
    )
    full = bool(sol.ok.all())
    if not full and sol.ok.any():
        ranges = ", ".join(f"{a:.6g}…{b:.6g}°" for a, b in summary["unreachable_deg"])
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
    out = _out_folder(args)
    cols, table = _analog_table(sol)
    np.savetxt(
        out / "analogs.csv", table, delimiter=",", header=",".join(cols), comments="", fmt="%.12g"
    )
    (out / "linkage.json").write_text(
        json.dumps(summary, indent=2, ensure_ascii=False), encoding="utf-8"
    )
    written = [out / "analogs.csv", out / "linkage.json"]
    if not args.no_plot:
        written += _linkage_figures(lk, sol, point, out)
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
    return 0


def _linkage_figures(lk: Linkage, sol: LinkageSolution, point: str, out: Path) -> list[Path]:
    written: list[Path] = []
    if not _has_matplotlib():
        return written
    from .plot import plot_analogs, plot_linkage

    if sol.ok.any():
        first = int(sol.ok.argmax())
        ax = plot_linkage(lk, sol, first, trace=[point])
        _save(ax.figure, out / "mechanism.png", written)
    _save(plot_analogs(sol, point), out / f"analogs_{point}.png", written)
    return written


def _press_command(args: argparse.Namespace) -> int:
    import numpy as np

    from .press import CRITERIA, PressStudy, optimize

    st = PressStudy.from_toml(args.file)
    p, w = st.press, st.omega
    step = args.step_deg
    _check_step(step)
    stroke = {"k_Sp": st.k_Sp, "working_stroke": st.working_stroke}
    c = p.criteria(omega=w, **stroke)
    base = p.baseline().criteria(omega=w, **stroke)
    name = st.name or Path(args.file).stem
    print(
        f"{name}: gear-lever press R = {p.R * 1e3:g} mm, r = {p.r * 1e3:g} mm (i = {p.ratio}), "
        f"d = {p.d * 1e3:g} mm, L = {p.L * 1e3:g} mm, φ0 = {math.degrees(p.phi0):g}°, "
        f"offset {p.offset * 1e3:g} mm; {st.rpm:g} rpm"
    )
    if not c.ok:
        print(f"cyclomech: the design does not work: {c.status}", file=sys.stderr)
    units = {
        "S_n": ("mm", 1e3),
        "S_p": ("mm", 1e3),
        "alpha_p": ("°", 180 / math.pi),
        "V_np": ("mm/s", 1e3),
        "V_cp": ("mm/s", 1e3),
        "V_pmax": ("mm/s", 1e3),
        "J_max": ("m/s²", 1.0),
        "torque": ("mm", 1e3),
        "theta_bdc": ("°", 180 / math.pi),
    }
    rows = []
    for k in CRITERIA:
        u, f = units.get(k, ("", 1.0))
        a, b = getattr(c, k) * f, getattr(base, k) * f
        rows.append([k + (f" [{u}]" if u else ""), f"{a:.6g}", f"{b:.6g}"])
    print(_table(rows, ["criterion", "design", "crank-slider (d = 0)"]))
    out = _out_folder(args)
    n = round(360.0 / step)
    alpha = np.radians(np.arange(n + 1) * step)
    k = p.solve(alpha)
    table = np.column_stack([np.degrees(alpha), k.s, k.ds, k.dds, k.ds * w, k.dds * w * w])
    np.savetxt(
        out / "kinematics.csv",
        table,
        delimiter=",",
        comments="",
        fmt="%.12g",
        header="alpha_deg,S_m,dS_m_per_rad,d2S_m_per_rad2,V_m_per_s,J_m_per_s2",
    )
    with (out / "criteria.csv").open("w", encoding="utf-8") as fh:
        fh.write("design," + ",".join(CRITERIA) + ",status\n")
        for label, cc in (("design", c), ("crank_slider", base)):
            fh.write(label + "," + ",".join(f"{getattr(cc, k_):.12g}" for k_ in CRITERIA))
            fh.write(f",{cc.status}\n")
    summary: dict[str, Any] = {
        "schema": "cyclomech.press/1",
        "name": name,
        "design": p.to_dict(),
        "rpm": st.rpm,
        "omega_rad_per_s": w,
        "criteria": c.as_dict(),
        "crank_slider": base.as_dict(),
    }
    written = [out / "kinematics.csv", out / "criteria.csv"]
    opt = None
    if st.grid is not None:
        g = st.grid
        n_designs = len(g["d"]) * len(g["L"]) * len(g["phi0"])
        print(f"\nSweeping {n_designs} designs (d × L × φ0) and refining the best …")
        opt = optimize(
            R=p.R,
            r=p.r,
            d=g["d"],
            L=g["L"],
            phi0=g["phi0"],
            offset=p.offset,
            omega=w,
            limits=st.limits,
            progress=None,
            **stroke,
        )
        best, cb = opt.designs[opt.best], opt.criteria[opt.best]
        print(
            f"{len(opt.designs)} non-dominated designs"
            + (f" within the limits {st.limits}" if st.limits else "")
            + f"; the best by score: d = {best.d * 1e3:.4g} mm, L = {best.L * 1e3:.4g} mm, "
            f"φ0 = {math.degrees(best.phi0):.4g}°: k_Vp {cb.k_Vp:.4g}, k_Vmax {cb.k_Vmax:.4g}, "
            f"k_J {cb.k_J:.4g}, k_M {cb.k_M:.4g} (crank-slider: k_Vp {opt.baseline.k_Vp:.4g}, "
            f"k_Vmax {opt.baseline.k_Vmax:.4g}, k_J {opt.baseline.k_J:.4g}, "
            f"k_M {opt.baseline.k_M:.4g})"
        )
        for edge in opt.edges:
            print(f"warning: the best design is on the edge of the grid: {edge}; widen [sweep]")
        cols = opt.grid.table()
        names = list(cols)
        np.savetxt(
            out / "sweep.csv",
            np.column_stack([cols[k_] for k_ in names]),
            delimiter=",",
            header=",".join(names),
            comments="",
            fmt="%.10g",
        )
        with (out / "pareto.csv").open("w", encoding="utf-8") as fh:
            fh.write("d,L,phi0_deg,refined,score," + ",".join(CRITERIA) + "\n")
            for q, cq, rf, sc in zip(
                opt.designs, opt.criteria, opt.refined, opt.scores, strict=True
            ):
                fh.write(f"{q.d:.10g},{q.L:.10g},{math.degrees(q.phi0):.10g},{int(rf)},{sc:.10g},")
                fh.write(",".join(f"{getattr(cq, k_):.10g}" for k_ in CRITERIA) + "\n")
        summary["optimum"] = {
            "designs_swept": n_designs,
            "non_dominated": len(opt.designs),
            "objectives": list(opt.objectives),
            "limits": st.limits,
            "best": best.to_dict(),
            "best_criteria": cb.as_dict(),
            "best_on_grid_edge": list(opt.edges),
            "baseline": opt.baseline_press.to_dict(),
            "baseline_criteria": opt.baseline.as_dict(),
        }
        written += [out / "sweep.csv", out / "pareto.csv"]
    (out / "press.json").write_text(
        json.dumps(jsonable(summary), indent=2, ensure_ascii=False), encoding="utf-8"
    )
    written.append(out / "press.json")
    if not args.no_plot:
        written += _press_figures(st, c, opt, out)
    print("\nWrote " + ", ".join(str(q) for q in written))
    return 0 if c.ok else 1


def _press_figures(st: Any, c: Any, opt: Any, out: Path) -> list[Path]:
    written: list[Path] = []
    if not _has_matplotlib():
        return written
    from .plot import plot_press, plot_press_criteria

    if c.ok:
        axes = plot_press(st.press, c.alpha_p, show_motion=True, k_Sp=c.k_Sp)
        _save(axes[0].figure, out / "press.png", written)
    if opt is not None:
        axes = plot_press_criteria(opt.grid, optimum=opt)
        _save(axes[0].figure, out / "criteria.png", written)
    return written


def _impact_command(args: argparse.Namespace) -> int:
    import numpy as np

    from .impact import ImpactStudy

    st = ImpactStudy.from_toml(args.file)
    m, name = st.stop, st.name or Path(args.file).stem
    two_pi = 2 * math.pi
    print(
        f"{name}: {m.law.name} rise of {m.stroke * 1e3:g} mm, preload {m.preload * 1e3:g} mm, "
        f"{m.model} model"
    )
    print(
        f"  free {m.omega_free / two_pi:.4g} Hz, in contact {m.omega_contact / two_pi:.4g} Hz, "
        f"contact time {m.contact_time * 1e3:.4g} ms, meets the stop at j = {m.j_contact:.4f} "
        f"of the rise"
    )
    rpm, phase = st.rpm, st.phase_deg
    a = m.rebound(rpm[:, None], phase[None, :])  # one call over the grid
    v0 = m.impact_speed(rpm[:, None], phase[None, :])
    force = m.impact_force(rpm[:, None], phase[None, :])
    t_min = np.atleast_1d(m.min_phase_angle(st.a_max, rpm))
    top = float(rpm.max())
    lo, hi = float(phase.min()), float(phase.max())
    slope, intercept = m.linearize((lo, hi), top)
    shown = sorted({0, len(rpm) // 2, len(rpm) - 1})
    rows = [
        [
            f"{rpm[i]:g}",
            f"{a[i, len(phase) // 2] * 1e3:.4g}",
            f"{force[i, len(phase) // 2]:.4g}",
            f"{t_min[i]:.4g}" if math.isfinite(t_min[i]) else "none ≤ 360",
        ]
        for i in shown
    ]
    mid = phase[len(phase) // 2]
    print(
        _table(
            rows,
            ["rpm", f"rebound at {mid:g}° [mm]", "impact force [N]", "min phase angle [°]"],
        )
    )
    print(
        f"  linearised at {top:g} rpm over {lo:g}–{hi:g}°: "
        f"a = {slope * 1e3:.4g}·t + {intercept * 1e3:.4g} mm (the seed: −0.003·t + 0.208)"
    )
    out = _out_folder(args)
    grid_rpm, grid_phase = np.meshgrid(rpm, phase, indexing="ij")
    np.savetxt(
        out / "rebound.csv",
        np.column_stack(
            [grid_rpm.ravel(), grid_phase.ravel(), v0.ravel(), force.ravel(), a.ravel() * 1e3]
        ),
        delimiter=",",
        comments="",
        fmt="%.12g",
        header="rpm,phase_deg,impact_speed_m_per_s,impact_force_N,rebound_mm",
    )
    np.savetxt(
        out / "min_phase.csv",
        np.column_stack([rpm, t_min]),
        delimiter=",",
        comments="",
        fmt="%.12g",
        header=f"rpm,min_phase_deg_for_rebound_le_{st.a_max * 1e3:g}_mm",
    )
    written = [out / "rebound.csv", out / "min_phase.csv"]
    summary = {
        "schema": "cyclomech.impact/1",
        "name": name,
        "model": m.model,
        "free_hz": m.omega_free / two_pi,
        "contact_hz": m.omega_contact / two_pi,
        "contact_time_s": m.contact_time,
        "j_contact": m.j_contact,
        "a_max_m": st.a_max,
        "rpm": rpm.tolist(),
        "min_phase_deg": [v if math.isfinite(v) else None for v in t_min.tolist()],
        "linearized": {"rpm": top, "slope_m_per_deg": slope, "intercept_m": intercept},
    }
    if st.arc is not None and math.isfinite(t_min[-1]):
        c = m.constraint(st.arc, st.a_max, top)
        summary["constraint"] = {"at_rpm": top, "text": c.describe()}
        print(f"  cyclogram constraint at {top:g} rpm: {c.describe()}")
    (out / "impact.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    written.append(out / "impact.json")
    if not args.no_plot and _has_matplotlib():
        from .plot import plot_rebound_vs_speed, plot_response

        fig = plot_rebound_vs_speed(m, rpm, phase_deg=[lo, mid, hi], a_max=st.a_max, title=name)
        _save(fig, out / "rebound_vs_speed.png", written)
        t, q = m.response(top, float(mid))
        k = int(np.argmax(q))
        ax = plot_response(
            t, q, rebound=(float(t[k]), float(q[k])), title=f"{name}: {top:g} rpm, {mid:g}°"
        )
        _save(ax.figure, out / "response.png", written)
    print("\nwrote " + ", ".join(str(w) for w in written))
    return 0


def _run_command(args: argparse.Namespace) -> int:
    from .machine import Machine, analyze, write_report

    m = Machine.from_toml(args.file)
    kinds = ", ".join(f"{k} ({v.kind})" for k, v in m.mechanisms.items())
    print(
        f"{m.name}: {_n(len(m.mechanisms), 'mechanism')}{': ' + kinds if kinds else ''}; "
        f"{len(m.cyclogram.operations)} operations; speeds {m.speed_range_rpm[0]:g}–"
        f"{m.speed_range_rpm[1]:g} rpm"
    )
    out = _out_folder(args)
    r = analyze(m, progress=None if not args.quiet else False)
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
            f"{o.objective:.2f}° ({o.stretch[op.arc]:.2f}° more than its minimum)"
        )
        priced = [f"{k} ({v:+.3g})" for k, v in o.duals.items() if abs(v) > 1e-9]
        if priced:
            print("Binding, with shadow prices: " + ", ".join(priced))
    use_fig = not args.no_plot and _has_matplotlib("figures")
    if use_fig and not args.quiet:
        print("drawing the figures …", file=sys.stderr, flush=True)  # a few seconds
    written = write_report(r, out, figures=use_fig)
    print(f"\nReport: {out / 'report.html'}  ({len(written)} files in {out})")
    if lim.rpm == 0:
        print(
            f"cyclomech: {args.file}: the machine works at no speed (exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    return 0


@contextlib.contextmanager
def _quiet_interrupt(active: bool) -> Iterator[None]:
    """While a Dask sweep runs, Ctrl-C first silences Dask's, tornado's and
    asyncio's loggers (the cancelled tasks they would report are what the user
    asked for), then interrupts as usual: one line, status 130."""
    if not active or threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame: Any) -> None:
        for name in ("distributed", "tornado", "asyncio"):
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGINT, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def _sweep_command(args: argparse.Namespace) -> int:
    import numpy as np

    from ._arrays import speeds_rpm as _speeds
    from .machine import Machine, check_parameter, dask_client, dask_workers, parse_range, sweep

    m = Machine.from_toml(args.file)
    workers = dask_workers(args.dask) if args.dask else 0
    grid: dict[str, Any] = {}
    for item in args.set or []:
        name, eq, text = item.partition("=")
        if not eq or not name:
            raise InputError(f"--set {item!r} must be <mechanism>.<key>=from:to:count")
        grid[name] = parse_range(text, f"--set {name}:")
    if args.speed is not None:
        grid["speed_rpm"] = _speeds("--speed", parse_range(args.speed, "--speed"))
    params = {k: v for k, v in grid.items() if k != "speed_rpm"}
    for k in params:  # a key the file cannot take fails before the work starts
        check_parameter(m, k)
    designs = math.prod(v.size for v in params.values())
    speeds = grid["speed_rpm"].size if "speed_rpm" in grid else m.speed_points
    print(
        f"{m.name}: sweeping {_n(designs, 'design')} × {_n(speeds, 'speed')} = "
        f"{_n(designs * speeds, 'point')}" + (f" on Dask ({args.dask})" if args.dask else ""),
        flush=True,
    )
    if workers:
        # Ctrl-C is ignored while the workers start (see scale._sigint_ignored).
        print(f"starting a Dask LocalCluster of {workers} worker processes …", flush=True)
    client = dask_client(args.dask) if args.dask else None
    try:
        with _quiet_interrupt(client is not None):
            r = sweep(
                m, grid, client, progress=None if not args.quiet else False, n_threads=args.threads
            )
    finally:
        if client is not None:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None and args.dask.startswith("local"):
                cluster.close()
    out = _out_folder(args)
    path = r.write(out / "sweep.parquet")
    fits = r.columns["fits"]
    n_speeds = int(np.unique(r.columns["speed_rpm"]).size)
    print(
        f"{_n(r.n_points, 'point')} ({_n(r.n_points // n_speeds, 'design')} × "
        f"{_n(n_speeds, 'speed')}) in "
        f"{r.seconds:.2f} s"
        + (f" on Dask ({args.dask})" if args.dask else "")
        + f"; the cyclogram fits at {int(fits.sum())} of them"
    )
    problem = r.columns["problem"]
    bad = problem[::n_speeds] != ""
    if bad.any():
        first = str(problem[::n_speeds][bad][0])
        print(
            f"{_n(int(bad.sum()), 'design')} of {bad.size} are invalid and counted as not "
            f"fitting (the 'problem' column says why); the first: {first}"
        )
    print(f"Wrote {path}")
    if path.suffix == ".npz":
        print("(NumPy .npz: pyarrow is not installed; `pip install pyarrow` writes Parquet)")
    if bad.all():
        print(
            f"cyclomech: {args.file}: every design of the sweep is invalid "
            f"(exit status {EXIT_FAILS})",
            file=sys.stderr,
        )
        return EXIT_FAILS
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``cyclomech`` command."""
    parser = argparse.ArgumentParser(prog="cyclomech", description="Design of cyclic machines.")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("cyclogram", help="schedule, optimise and plot a cyclogram file (TOML)")
    p.add_argument("file", help="cyclogram file, e.g. examples/stb_group1.toml")
    p.add_argument("--out", help="output folder (default: out/<file name>)")
    p.add_argument("--speed", type=float, help="main-shaft speed [rpm] for time-bound operations")
    p.add_argument("--no-plot", action="store_true", help="do not write the figure")
    p.set_defaults(run=_cyclogram_command)
    q = sub.add_parser("linkage", help="solve a linkage file (TOML) over a crank turn")
    q.add_argument("file", help="linkage file, e.g. examples/burg_trimmer.toml")
    q.add_argument("--out", help="output folder (default: out/<file name>)")
    q.add_argument("--step-deg", type=float, default=1.0, help="crank-angle step [°] (default 1)")
    q.add_argument("--no-plot", action="store_true", help="do not write the figures")
    q.add_argument(
        "--require-full-turn",
        action="store_true",
        help=f"exit with status {EXIT_FAILS} if the linkage cannot make a full crank turn",
    )
    q.set_defaults(run=_linkage_command)
    r = sub.add_parser("press", help="kinematics, criteria and design sweep of a press file (TOML)")
    r.add_argument("file", help="press file, e.g. examples/extrusion_press.toml")
    r.add_argument("--out", help="output folder (default: out/<file name>)")
    r.add_argument("--step-deg", type=float, default=1.0, help="crank-angle step [°] (default 1)")
    r.add_argument("--no-plot", action="store_true", help="do not write the figures")
    r.set_defaults(run=_press_command)
    i = sub.add_parser("impact", help="rebound at a stop against speed and phase angle (TOML)")
    i.add_argument("file", help="impact file, e.g. examples/stb_lifter.toml")
    i.add_argument("--out", help="output folder (default: out/<file name>)")
    i.add_argument("--no-plot", action="store_true", help="do not write the figures")
    i.set_defaults(run=_impact_command)
    m = sub.add_parser("run", help="the whole machine: a machine file (TOML) in, a report out")
    m.add_argument("file", help="machine file, e.g. examples/stb_loom.toml")
    m.add_argument("--out", help="output folder (default: out/<file name>)")
    m.add_argument("--no-plot", action="store_true", help="do not draw the figures")
    m.add_argument("--quiet", action="store_true", help="no progress bar")
    m.set_defaults(run=_run_command)
    w = sub.add_parser("sweep", help="a machine's key figures over parameters and speeds")
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
    w.set_defaults(run=_sweep_command)
    args = parser.parse_args(argv)
    try:
        _out_path(args)  # a bad --out fails now, not after the work
        _not_a_machine_file(args)
        return int(args.run(args))
    except CyclomechError as e:
        # Errors from the file already name it; name it for the others too.
        msg = str(e) if args.file in str(e) else f"{args.file}: {e}"
        print(f"cyclomech: error: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("cyclomech: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # Whoever read the output stopped (`| head`): no traceback, and none at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
