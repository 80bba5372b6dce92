"""``cyclomech impact FILE.toml [--out DIR]``: the stops' command.

The rebound at a stop against speed and phase angle: prints the stop's
frequencies and contact time, the rebound, impact force and minimum phase angle at
a few speeds and the linearised rebound, and writes the grid (CSV), the minimum
phase angles (CSV), a JSON summary and figures.

>>> import argparse
>>> from cyclomech.impact import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> commands.choices["impact"].parse_args(["stop.toml", "--out", "here"]).out
'here'
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

from .._cli import EXIT_OK, has_matplotlib, out_folder, save, table
from .._files import savetxt, write_text

__all__ = ["add_commands", "impact_command"]


def add_commands(commands: Any) -> None:
    """Add the ``impact`` command to the sub-parsers ``commands`` of ``cyclomech``."""
    i = commands.add_parser("impact", help="rebound at a stop against speed and phase angle (TOML)")
    i.add_argument("file", help="impact file, e.g. examples/stb_lifter.toml")
    i.add_argument("--out", help="output folder (default: out/<file name>)")
    i.add_argument("--no-plot", action="store_true", help="do not write the figures")
    i.set_defaults(run=impact_command)


def impact_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech impact`` with the parsed ``args``; return the exit status."""
    import numpy as np

    from . import ImpactStudy

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
        table(
            rows,
            ["rpm", f"rebound at {mid:g}° [mm]", "impact force [N]", "min phase angle [°]"],
        )
    )
    print(
        f"  linearised at {top:g} rpm over {lo:g}–{hi:g}°: "
        f"a = {slope * 1e3:.4g}·t + {intercept * 1e3:.4g} mm (the seed: −0.003·t + 0.208)"
    )
    out = out_folder(args)
    grid_rpm, grid_phase = np.meshgrid(rpm, phase, indexing="ij")
    savetxt(
        out / "rebound.csv",
        np.column_stack(
            [grid_rpm.ravel(), grid_phase.ravel(), v0.ravel(), force.ravel(), a.ravel() * 1e3]
        ),
        delimiter=",",
        comments="",
        fmt="%.12g",
        header="rpm,phase_deg,impact_speed_m_per_s,impact_force_N,rebound_mm",
    )
    savetxt(
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
    write_text(out / "impact.json", json.dumps(summary, indent=2) + "\n")
    written.append(out / "impact.json")
    if not args.no_plot and has_matplotlib():
        from .plot import plot_rebound_vs_speed, plot_response

        fig = plot_rebound_vs_speed(m, rpm, phase_deg=[lo, mid, hi], a_max=st.a_max, title=name)
        save(fig, out / "rebound_vs_speed.png", written)
        t, q = m.response(top, float(mid))
        k = int(np.argmax(q))
        ax = plot_response(
            t, q, rebound=(float(t[k]), float(q[k])), title=f"{name}: {top:g} rpm, {mid:g}°"
        )
        save(ax.figure, out / "response.png", written)
    print("\nwrote " + ", ".join(str(w) for w in written))
    return EXIT_OK
