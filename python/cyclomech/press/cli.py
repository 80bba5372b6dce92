"""``cyclomech press FILE.toml [--out DIR] [--step-deg S]``: the press's command.

Kinematics, criteria and design sweep of a gear-lever press file: prints the
criteria of the design beside the crank-slider's, writes the kinematics and
criteria tables (CSV), the sweep and its Pareto front when the file has a
``[sweep]``, a JSON summary and figures. The files are SI with the unit in each
column's name and angles in degrees (``alpha_p_deg``, ``S_n_m``, ``V_np_m_per_s``;
the ratios k_* have none); a status is its text. Exit status 3 when the design does not
work (its files are written all the same).

>>> import argparse
>>> from cyclomech.press import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> commands.choices["press"].parse_args(["press.toml", "--no-plot"]).no_plot
True
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
from pathlib import Path
from typing import Any

from .._cli import EXIT_FAILS, EXIT_OK, check_step, has_matplotlib, out_folder, save, table
from .._files import savetxt, whole, write_text
from .._json import jsonable

__all__ = ["add_commands", "press_command"]


#: The files' names of the criteria and design values, SI with the unit in the name
#: and angles in degrees, as the machine report's files: name → (column, factor
#: from the value in SI/radians). Dimensionless ratios (k_*) keep their names.
FILE_COLUMNS: dict[str, tuple[str, float]] = {
    "S_n": ("S_n_m", 1.0),
    "S_p": ("S_p_m", 1.0),
    "alpha_p": ("alpha_p_deg", 180.0 / math.pi),
    "V_np": ("V_np_m_per_s", 1.0),
    "V_cp": ("V_cp_m_per_s", 1.0),
    "V_pmax": ("V_pmax_m_per_s", 1.0),
    "J_max": ("J_max_m_per_s2", 1.0),
    "torque_arm": ("torque_arm_m", 1.0),
    "theta_bdc": ("theta_bdc_deg", 180.0 / math.pi),
    "omega": ("omega_rad_per_s", 1.0),
    "R": ("R_m", 1.0),
    "r": ("r_m", 1.0),
    "d": ("d_m", 1.0),
    "L": ("L_m", 1.0),
    "phi0": ("phi0_deg", 180.0 / math.pi),
    "offset": ("offset_m", 1.0),
}


def file_values(values: dict[str, Any]) -> dict[str, Any]:
    """``values`` (criteria or a design, SI and radians) under the files' names and
    units (:data:`FILE_COLUMNS`); other keys (ratios, ``status``) as they are.

    >>> file_values({"alpha_p": math.pi / 2, "k_Vp": 0.12, "d": 0.029})
    {'alpha_p_deg': 90.0, 'k_Vp': 0.12, 'd_m': 0.029}
    """
    out: dict[str, Any] = {}
    for k, v in values.items():
        name, f = FILE_COLUMNS.get(k, (k, 1.0))
        out[name] = v * f if f != 1.0 else v
    return out


def _columns(names: Any) -> list[str]:
    """The files' column names of criteria or design values ``names``."""
    return [FILE_COLUMNS.get(k, (k, 1.0))[0] for k in names]


def add_commands(commands: Any) -> None:
    """Add the ``press`` command to the sub-parsers ``commands`` of ``cyclomech``."""
    r = commands.add_parser(
        "press", help="kinematics, criteria and design sweep of a press file (TOML)"
    )
    r.add_argument("file", help="press file, e.g. examples/extrusion_press.toml")
    r.add_argument("--out", help="output folder (default: out/<file name>)")
    r.add_argument("--step-deg", type=float, default=1.0, help="crank-angle step [°] (default 1)")
    r.add_argument("--no-plot", action="store_true", help="do not write the figures")
    r.set_defaults(run=press_command)


def press_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech press`` with the parsed ``args``; return the exit status."""
    import numpy as np

    from . import CRITERIA, STATUS, PressStudy, optimize

    st = PressStudy.from_toml(args.file)
    p, w = st.press, st.omega
    step = args.step_deg
    check_step(step)
    stroke: dict[str, Any] = {"k_Sp": st.k_Sp, "working_stroke": st.working_stroke}
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
        "torque_arm": ("mm", 1e3),
        "theta_bdc": ("°", 180 / math.pi),
    }
    rows = []
    for k in CRITERIA:
        u, f = units.get(k, ("", 1.0))
        a, b = getattr(c, k) * f, getattr(base, k) * f
        rows.append([k + (f" [{u}]" if u else ""), f"{a:.6g}", f"{b:.6g}"])
    print(table(rows, ["criterion", "design", f"crank-slider (d = 0, L = {p.L * 1e3:g} mm)"]))
    out = out_folder(args)
    n = round(360.0 / step)
    alpha = np.radians(np.arange(n + 1) * step)
    kin = p.solve(alpha)
    kinematics = np.column_stack(
        [np.degrees(alpha), kin.s, kin.ds, kin.dds, kin.ds * w, kin.dds * w * w]
    )
    savetxt(
        out / "kinematics.csv",
        kinematics,
        delimiter=",",
        comments="",
        fmt="%.12g",
        header="alpha_deg,S_m,dS_m_per_rad,d2S_m_per_rad2,V_m_per_s,J_m_per_s2",
    )
    factor = [FILE_COLUMNS.get(k_, (k_, 1.0))[1] for k_ in CRITERIA]
    with whole(out / "criteria.csv") as tmp, tmp.open("w", encoding="utf-8", newline="") as fh:
        wr = csv.writer(fh)  # a status text may hold a comma: quoted
        wr.writerow(["design", *_columns(CRITERIA), "status"])
        for label, cc in (("design", c), ("crank_slider", base)):
            vals = (getattr(cc, k_) * f for k_, f in zip(CRITERIA, factor, strict=True))
            wr.writerow([label, *(f"{v:.12g}" for v in vals), cc.status])
    summary: dict[str, Any] = {
        "schema": "cyclomech.press/2",
        "name": name,
        "design": file_values(p.to_dict()),
        "rpm": st.rpm,
        "omega_rad_per_s": w,
        "criteria": file_values(c.as_dict()),
        "crank_slider": file_values(base.as_dict()),
        "crank_slider_design": file_values(p.baseline().to_dict()),
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
            f"k_J {cb.k_J:.4g}, k_M {cb.k_M:.4g} (the optimiser's crank-slider, "
            f"L = {opt.baseline_press.L * 1e3:.4g} mm: k_Vp {opt.baseline.k_Vp:.4g}, "
            f"k_Vmax {opt.baseline.k_Vmax:.4g}, k_J {opt.baseline.k_J:.4g}, "
            f"k_M {opt.baseline.k_M:.4g})"
        )
        for edge in opt.edges:
            print(f"warning: the best design is on the edge of the grid: {edge}; widen [sweep]")
        grid_cols = opt.grid.table()
        codes = grid_cols.pop("status")
        cols = file_values(grid_cols)
        status = [STATUS[int(v)] for v in codes]
        with whole(out / "sweep.csv") as tmp, tmp.open("w", encoding="utf-8", newline="") as fh:
            wr = csv.writer(fh)  # the status texts hold commas: quoted
            wr.writerow([*cols, "status"])
            body = np.column_stack([np.asarray(v, dtype=np.float64) for v in cols.values()])
            wr.writerows(
                [*(f"{v:.10g}" for v in row), stat] for row, stat in zip(body, status, strict=True)
            )
        with whole(out / "pareto.csv") as tmp, tmp.open("w", encoding="utf-8") as fh:
            fh.write("d_m,L_m,phi0_deg,refined,score," + ",".join(_columns(CRITERIA)) + "\n")
            for q, cq, rf, sc in zip(
                opt.designs, opt.criteria, opt.refined, opt.scores, strict=True
            ):
                fh.write(f"{q.d:.10g},{q.L:.10g},{math.degrees(q.phi0):.10g},{int(rf)},{sc:.10g},")
                vals = (getattr(cq, k_) * f for k_, f in zip(CRITERIA, factor, strict=True))
                fh.write(",".join(f"{v:.10g}" for v in vals) + "\n")
        summary["optimum"] = {
            "designs_swept": n_designs,
            "non_dominated": len(opt.designs),
            "objectives": list(opt.objectives),
            "limits": st.limits,
            "best": file_values(best.to_dict()),
            "best_criteria": file_values(cb.as_dict()),
            "best_on_grid_edge": list(opt.edges),
            "baseline": file_values(opt.baseline_press.to_dict()),
            "baseline_criteria": file_values(opt.baseline.as_dict()),
        }
        written += [out / "sweep.csv", out / "pareto.csv"]
    write_text(out / "press.json", json.dumps(jsonable(summary), indent=2, ensure_ascii=False))
    written.append(out / "press.json")
    if not args.no_plot:
        written += _figures(st, c, opt, out)
    print("\nWrote " + ", ".join(str(q) for q in written))
    return EXIT_OK if c.ok else EXIT_FAILS


def _figures(st: Any, c: Any, opt: Any, out: Path) -> list[Path]:
    written: list[Path] = []
    if not has_matplotlib():
        return written
    from .plot import plot_press, plot_press_criteria

    if c.ok:
        axes = plot_press(st.press, c.alpha_p, show_motion=True, k_Sp=c.k_Sp)
        save(_first(axes).figure, out / "press.png", written)
    if opt is not None:
        axes = plot_press_criteria(opt.grid, optimum=opt)
        save(_first(axes).figure, out / "criteria.png", written)
    return written


def _first(axes: Any) -> Any:
    """The first of the axes a press plot drew (one, or a pair)."""
    return axes[0] if isinstance(axes, tuple) else axes
