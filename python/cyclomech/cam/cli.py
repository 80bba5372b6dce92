"""``cyclomech cam FILE.toml [--out DIR] [--rpm N] [--samples N] [--no-plot] [--no-dxf]``:
the cam's command.

Reads a cam file (:meth:`cyclomech.cam.CamDesign.from_toml`), prints a summary
(the follower, closure and segments; at the speed — the file's ``rpm`` or
``--rpm`` — the largest pressure angle and Hertz stress and where, the undercut
angles, the jump speed of a spring-closed follower, and each rise's and return's
smallest phase angle per criterion against its angle in the file) and writes
``profile.csv`` (m), ``profile.dxf`` (mm; unless ``--no-dxf`` or ezdxf is
missing), ``results.json``, ``min_phase.csv`` (the smallest phase angles per
criterion from 0.25× to 2× the speed, 41 speeds) and four figures.

Exit status 0 when the design holds every criterion at its angles and speed; 3
(the files written) when it fails one — a segment shorter than its smallest phase
angle, σ_H above [σ_H], the pressure angle above [α], an undercut profile, or a
follower that leaves the cam at the speed — with a line saying which; 2 for bad
input.

>>> import argparse
>>> from cyclomech.cam import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> commands.choices["cam"].parse_args(["lifter_cam.toml", "--rpm", "400"]).rpm
400.0
"""

from __future__ import annotations

import argparse
import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from .._arrays import count, positive
from .._cli import EXIT_FAILS, EXIT_OK, has_matplotlib, out_folder, save, table
from .._errors import CyclomechWarning, InputError
from .._files import savetxt, write_text
from .._json import jsonable
from ._design import CamDesign
from ._export import DxfUnavailableError, profile_table, write_profile_csv, write_profile_dxf
from ._followers import FlatFaced, OscillatingRoller, TranslatingRoller
from ._loads import MinPhaseAngles
from ._program import Cam
from ._vibration import follower_response

__all__ = ["SPEED_POINTS", "SPEED_RANGE", "add_commands", "cam_command"]

#: The speeds of min_phase.csv and its figure, as multiples of the cam's speed.
SPEED_RANGE = (0.25, 2.0)
#: How many speeds min_phase.csv holds.
SPEED_POINTS = 41
#: Relative tolerance of "a segment's angle is below its bound": a design exactly
#: at its bound holds (the bound is a root found to ~1e-12).
_BOUND_RTOL = 1e-9


def add_commands(commands: Any) -> None:
    """Add the ``cam`` command to the sub-parsers ``commands`` of ``cyclomech``.

    Parameters
    ----------
    commands : argparse._SubParsersAction
        The sub-parsers of the ``cyclomech`` argument parser.

    Examples
    --------
    >>> import argparse
    >>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
    >>> add_commands(commands)
    >>> sorted(commands.choices)
    ['cam']
    """
    c = commands.add_parser(
        "cam", help="a cam: profile (CSV, DXF), pressure angle, stress, smallest phase angles"
    )
    c.add_argument("file", help="cam file, e.g. examples/lifter_cam.toml")
    c.add_argument("--out", help="output folder (default: out/<file name>)")
    c.add_argument("--rpm", type=float, help="cam speed [rpm] (default: the file's rpm)")
    c.add_argument(
        "--samples",
        type=int,
        default=3600,
        help="cam angles over one turn in the profile files (default 3600)",
    )
    c.add_argument("--no-plot", action="store_true", help="do not write the figures")
    c.add_argument("--no-dxf", action="store_true", help="do not write profile.dxf")
    c.add_argument(
        "--tool-radius-mm",
        type=float,
        help="a cutter's radius [mm]: its centre path in profile.csv and profile.dxf "
        "(default: the file's tool_radius_m, else none)",
    )
    c.set_defaults(run=cam_command)


def _follower_text(cam: Cam) -> str:
    f = cam.follower

    def mm(v: float) -> str:
        return f"{v * 1e3:g} mm"

    if isinstance(f, OscillatingRoller):
        return (
            f"oscillating roller follower (pivot at {mm(f.pivot_distance)}, "
            f"arm {mm(f.arm_length)}, base radius {mm(f.base_radius)}, "
            f"roller {mm(f.roller_radius)}, "
            f"ψ0 = {f.initial_arm_angle_deg:.4g}°)"
        )
    if isinstance(f, FlatFaced):
        return f"flat-faced follower (base radius {mm(f.base_radius)})"
    assert isinstance(f, TranslatingRoller)
    what = "knife-edge" if f.roller_radius == 0.0 else "translating roller"
    roller = "" if f.roller_radius == 0.0 else f", roller {mm(f.roller_radius)}"
    return f"{what} follower (base radius {mm(f.base_radius)}{roller}, offset {mm(f.offset)})"


def _where(values: np.ndarray, deg: np.ndarray) -> tuple[float, float]:
    """The largest finite value and its cam angle [deg] (NaN, NaN if none)."""
    ok = np.isfinite(values)
    if not ok.any():
        return math.nan, math.nan
    i = int(np.argmax(np.where(ok, values, -np.inf)))
    return float(values[i]), float(deg[i])


def cam_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech cam`` with the parsed ``args``.

    Prints the summary and writes the files to ``args.out`` (see the module's
    docstring).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``file``, ``out``, ``rpm`` [rpm], ``samples``,
        ``no_plot``, ``no_dxf``).

    Returns
    -------
    int
        The exit status: 0 when the design holds every criterion at its angles and
        speed, 3 when it fails one (the files written).

    Raises
    ------
    InputError
        For bad input (the CLI exits with status 2): an invalid cam file, no speed
        (neither the file's ``rpm`` nor ``--rpm``), or ``--samples`` < 3.

    Examples
    --------
    >>> import argparse, contextlib, io, pathlib, tempfile
    >>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
    >>> add_commands(commands)
    >>> out = tempfile.mkdtemp()
    >>> args = commands.choices["cam"].parse_args(
    ...     ["examples/lifter_cam.toml", "--out", out, "--no-plot", "--no-dxf"])
    >>> with contextlib.redirect_stdout(io.StringIO()):
    ...     status = cam_command(args)
    >>> status, sorted(p.name for p in pathlib.Path(out).iterdir())
    (0, ['min_phase.csv', 'profile.csv', 'results.json'])
    """
    name, file_rpm, d = CamDesign.from_toml(args.file)
    cam = d.cam
    if args.rpm is not None:
        rpm = positive("--rpm", args.rpm, "[rpm]")
    elif file_rpm is not None:
        rpm = file_rpm
    else:
        raise InputError(
            f"{args.file}: [cam]: no speed: give rpm = <cam speed in rpm> in [cam], or --rpm N"
        )
    samples = count("--samples", args.samples, low=3, what="cam angles over one turn")
    tool = _tool_radius(args, d)
    angular = isinstance(cam.follower, OscillatingRoller)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        prof = profile_table(cam, samples, tool)
    notes = [str(w.message) for w in caught]

    print(f"{name}: {_follower_text(cam)}, {cam.closure} closure")
    load_key = "load [N·m]" if angular else "load [N]"
    seg_loads = d.loads.segment_loads if d.loads is not None else None
    rows = [
        [
            str(i),
            g.kind,
            f"{g.angle_deg:g}",
            (f"{math.degrees(g.stroke):.6g}°" if angular else f"{g.stroke * 1e3:.6g} mm")
            if g.kind != "dwell"
            else "",
            g.law if g.kind != "dwell" else "",
            f"{seg_loads[i]:g}" if seg_loads is not None and seg_loads[i] else "",
        ]
        for i, g in enumerate(cam.segments)
    ]
    print(table(rows, ["segment", "kind", "angle [°]", "stroke", "law", load_key]))

    deg = prof["theta_deg"]
    fails: list[str] = []
    results: dict[str, Any] = {
        "schema": "cyclomech.cam/1",
        "name": name,
        "rpm": rpm,
        "follower": type(cam.follower).__name__,
        "closure": cam.closure,
        "segments": [
            {"kind": g.kind, "angle_deg": g.angle_deg}
            | (
                {}
                if g.kind == "dwell"
                else {
                    "stroke_deg" if angular else "stroke_m": (
                        math.degrees(g.stroke) if angular else g.stroke
                    ),
                    "law": g.law,
                }
            )
            for g in cam.segments
        ],
    }
    print(f"\nat {rpm:g} rpm ({'--rpm' if args.rpm is not None else 'the file'}):")
    phi, phi_at = _where(np.abs(prof["pressure_angle_deg"]), deg)
    alpha = d.max_pressure_angle_deg
    ok = phi <= alpha
    print(
        f"  max |pressure angle| {phi:.4g}° at θ = {phi_at:.4g}° ([α] = {alpha:g}°)"
        + ("" if ok else "  FAILS")
    )
    if not ok:
        fails.append(
            f"the pressure angle reaches {phi:.4g}° at θ = {phi_at:.4g}° > [α] = {alpha:g}°"
        )
    results["pressure_angle"] = {"max_deg": phi, "at_deg": phi_at, "limit_deg": alpha}

    if d.loads is not None:
        ld = cam.loads(np.radians(deg), rpm, d.loads, d.contact)
        if d.contact is not None:
            sigma, sigma_at = _where(ld.contact_stress, deg)
            limit = d.max_stress
            bad = limit is not None and sigma > limit
            lim = "" if limit is None else f" ([σ_H] = {limit / 1e6:g} MPa)"
            print(
                f"  max σ_H {sigma / 1e6:.4g} MPa at θ = {sigma_at:.4g}°{lim}"
                + ("  FAILS" if bad else "")
            )
            if bad:
                assert limit is not None
                fails.append(
                    f"σ_H reaches {sigma / 1e6:.4g} MPa at θ = {sigma_at:.4g}° "
                    f"> [σ_H] = {limit / 1e6:g} MPa"
                )
            results["contact_stress"] = {"max_pa": sigma, "at_deg": sigma_at, "limit_pa": limit}
        else:
            print("  σ_H: not computed (no width_m: the contact is not described)")
        if cam.closure == "spring":
            jump, jump_at = cam.jump_rpm(d.loads)
            leaves = bool(ld.separated.any()) or jump <= rpm
            text = (
                "none (the follower has no inertia)"
                if math.isinf(jump)
                else f"the follower leaves the cam from {jump:.5g} rpm (at θ = {jump_at:.4g}°)"
            )
            print(f"  jump: {text}" + ("  FAILS" if leaves else ""))
            if leaves:
                fails.append(f"the follower leaves the cam at {rpm:g} rpm (from {jump:.5g} rpm)")
            results["jump"] = {"rpm": jump, "at_deg": jump_at}
        else:
            print("  jump: none (groove closure)")
    else:
        mass = "inertia_kg_m2" if angular else "mass_kg"
        print(f"  loads, σ_H and jump: not computed (no {mass} in the file)")

    runs = cam.undercut_angles_deg(len(deg))
    if runs:
        text = ", ".join(f"{a:.4g}–{b:.4g}°" for a, b in runs)
        print(f"  undercut at θ = {text}  FAILS")
        fails.append(f"the profile is undercut at θ = {text}")
    else:
        print("  undercut: none")
    results["undercut_deg"] = [list(r) for r in runs]

    lo, hi = SPEED_RANGE
    speeds = np.linspace(lo * rpm, hi * rpm, SPEED_POINTS)
    both = d.min_phase_angles(np.concatenate([[rpm], speeds]))  # one Rust call
    here = both.angle_deg[0]
    sweep = MinPhaseAngles(speeds, both.segments, both.criteria, both.angle_deg[1:])
    fails += _print_phase_checks(d, both, here, rpm, results)

    out = out_folder(args)
    written = _write_profiles(cam, out, samples, tool, dxf=not args.no_dxf)
    _write_min_phase_csv(out / "min_phase.csv", cam, sweep)
    written.append(out / "min_phase.csv")
    for note in notes:
        print(f"\nnote: {note}")
    results["fails"] = fails
    write_text(
        out / "results.json", json.dumps(jsonable(results), indent=2, ensure_ascii=False) + "\n"
    )
    written.append(out / "results.json")
    if not args.no_plot and has_matplotlib():
        _figures(name, rpm, d, sweep, out, written)
    print("\nwrote " + ", ".join(str(w) for w in written))
    if fails:
        print()
        for f in fails:
            print(f"FAILS: {f}")
        return EXIT_FAILS
    print("\nthe design holds every criterion at its angles and speed")
    return EXIT_OK


def _angle_text(v: float) -> str:
    """A smallest phase angle [deg] in the table: 0 plainly (the criterion does
    not bound the segment), NaN as "none ≤ 360" (no angle will do)."""
    if not math.isfinite(v):
        return "none ≤ 360"
    return "0" if v == 0.0 else f"{v:.4f}"


def _print_min_phase(
    cam: Cam, m: MinPhaseAngles, here: np.ndarray, rpm: float, results: dict[str, Any]
) -> list[str]:
    """The table of the smallest phase angles at ``rpm`` ((segments, criteria)
    ``here``); returns the failures."""
    fails = []
    rows, entries = [], []
    bound = np.max(here, axis=-1)
    binding = m.binding[0]
    for i, seg in enumerate(m.segments):
        g = cam.segments[seg]
        b = float(bound[i])
        short = not math.isfinite(b) or g.angle_deg < b * (1.0 - _BOUND_RTOL)
        why = str(binding[i]) or "none"
        rows.append(
            [
                str(seg + 1),
                g.kind,
                *(_angle_text(v) for v in here[i]),
                _angle_text(b),
                why,
                f"{g.angle_deg:g}",
                "FAILS" if short else "ok",
            ]
        )
        entries.append(
            {
                "segment": seg + 1,
                "kind": g.kind,
                "angle_deg": g.angle_deg,
                "min_deg": dict(zip(m.criteria, here[i].tolist(), strict=True)),
                "bound_deg": b,
                "binding": why,
                "ok": not short,
            }
        )
        if short:
            what = why.replace("_", " ")
            if math.isfinite(b):
                fails.append(
                    f"segment {seg + 1} ({g.kind}): {g.angle_deg:g}° < {b:.4g}°, the smallest "
                    f"phase angle for {what} at {rpm:g} rpm"
                )
            else:
                fails.append(
                    f"segment {seg + 1} ({g.kind}): {g.angle_deg:g}°, but no phase angle up to a "
                    f"whole turn meets {what} at {rpm:g} rpm"
                )
    results["min_phase"] = entries
    if not rows:
        print(
            "\n  no smallest phase angles: no rise or return whose shape scales with its "
            "angle (a rest-to-rest one)"
        )
        return fails
    print(f"\n  smallest phase angles at {rpm:g} rpm [deg] (0: the criterion does not bound it)")
    crit = [c.replace("_", " ") for c in m.criteria]
    print(table(rows, ["segment", "kind", *crit, "bound", "binding", "in file", "verdict"]))
    return fails


def _print_phase_checks(
    d: CamDesign, m: MinPhaseAngles, here: np.ndarray, rpm: float, results: dict[str, Any]
) -> list[str]:
    """The smallest phase angles, then the residual vibration of the segments they
    do not bound; returns the failures of both."""
    return _print_min_phase(d.cam, m, here, rpm, results) + _print_residual(d, m, rpm, results)


def _print_residual(
    d: CamDesign, m: MinPhaseAngles, rpm: float, results: dict[str, Any]
) -> list[str]:
    """With a vibration limit: the follower's residual vibration after each moving
    segment that has no smallest phase angle (a program segment whose shape changes
    with its angle, a polydyne cam), from the periodic steady state at ``rpm``
    (segments with one are checked by their bound); returns the failures."""
    cam = d.cam
    if d.vibration is None:
        return []
    f_n, zeta, limit = d.vibration
    rest = [i for i, g in enumerate(cam.segments) if g.kind != "dwell" and i not in m.segments]
    if not rest:
        return []
    r = follower_response(cam, rpm, f_n, zeta)
    angular = isinstance(cam.follower, OscillatingRoller)
    unit, scale = ("°", 180 / math.pi) if angular else (" µm", 1e6)
    print(f"\n  residual vibration at {rpm:g} rpm (segments without a smallest phase angle)")
    rows, fails, entries = [], [], []
    for i in rest:
        a = float(r.residual[i])
        bad = a > limit
        rows.append(
            [
                str(i + 1),
                cam.segments[i].law,
                f"{a * scale:.4g}{unit}",
                f"{limit * scale:.4g}{unit}",
                "FAILS" if bad else "ok",
            ]
        )
        entries.append({"segment": i + 1, "residual": a, "limit": limit, "ok": not bad})
        if bad:
            fails.append(
                f"segment {i + 1} ({cam.segments[i].law}): residual vibration "
                f"{a * scale:.4g}{unit} > {limit * scale:.4g}{unit} at {rpm:g} rpm"
            )
    print(table(rows, ["segment", "law", "residual", "limit", "verdict"]))
    results["residual_vibration"] = entries
    return fails


def _write_min_phase_csv(path: Path, cam: Cam, m: MinPhaseAngles) -> None:
    """rpm, then per segment each criterion's smallest phase angle and the bound [deg]
    (nan: no angle up to a whole turn will do)."""
    cols, head = [np.asarray(m.rpm, dtype=np.float64)], ["rpm"]
    bound = m.bound_deg
    for i, seg in enumerate(m.segments):
        tag = f"seg{seg + 1}_{cam.segments[seg].kind}"
        for j, c in enumerate(m.criteria):
            cols.append(m.angle_deg[:, i, j])
            head.append(f"{tag}_{c}_deg")
        cols.append(bound[:, i])
        head.append(f"{tag}_bound_deg")
    savetxt(
        path, np.column_stack(cols), delimiter=",", comments="", fmt="%.12g", header=",".join(head)
    )


def _figures(
    name: str, rpm: float, d: CamDesign, sweep: MinPhaseAngles, out: Path, written: list[Path]
) -> None:
    from .plot import plot_along_cycle, plot_cam, plot_min_phase_angles, plot_svaj

    cam = d.cam
    ax = plot_cam(cam, title=f"{name}: the cam, coloured by |pressure angle|")
    save(ax.figure, out / "cam.png", written)
    axes = plot_svaj(cam, rpm=rpm, title=f"{name}: follower motion at {rpm:g} rpm")
    save(axes[0].figure, out / "svaj.png", written)
    if d.loads is not None:
        axes = plot_along_cycle(
            cam,
            rpm,
            d.loads,
            d.contact,
            max_stress=d.max_stress,
            max_pressure_angle_deg=d.max_pressure_angle_deg,
            title=f"{name}: along the cycle at {rpm:g} rpm",
        )
        save(axes[0].figure, out / "along_cycle.png", written)
    labels = [f"segment {i + 1} ({cam.segments[i].kind})" for i in sweep.segments]
    nominal = [cam.segments[i].angle_deg for i in sweep.segments]
    ax = plot_min_phase_angles(
        sweep, labels=labels, nominal_deg=nominal, title=f"{name}: smallest phase angles"
    )
    ax.axvline(rpm, color="0.4", lw=0.8, ls="--", gid="rpm")
    ax.annotate(
        f"{rpm:g} rpm",
        (rpm, 0.0),
        xycoords=("data", "axes fraction"),
        xytext=(3, 3),
        textcoords="offset points",
        fontsize=8,
        color="0.3",
    )
    save(ax.figure, out / "min_phase.png", written)


def _tool_radius(args: argparse.Namespace, d: CamDesign) -> float | None:
    """The cutter's radius [m]: ``--tool-radius-mm``, else the file's ``tool_radius_m``."""
    if getattr(args, "tool_radius_mm", None) is None:
        return d.tool_radius
    return positive("--tool-radius-mm", args.tool_radius_mm, "[mm]") / 1000.0


def _write_profiles(
    cam: Cam, out: Path, samples: int, tool: float | None, *, dxf: bool
) -> list[Path]:
    """``profile.csv`` and (``dxf``, with ezdxf) ``profile.dxf``: the parts to make."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CyclomechWarning)  # the chordal error: noted once
        written = [write_profile_csv(cam, out / "profile.csv", samples, tool)]
        if dxf:
            try:
                written.append(write_profile_dxf(cam, out / "profile.dxf", samples, tool))
            except DxfUnavailableError:
                print("\n(no profile.dxf: ezdxf is not installed; pip install 'cyclomech[dxf]')")
    return written
