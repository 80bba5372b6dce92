"""``cyclomech transfer FILE.toml [--out DIR] [--rpm N] [--samples N] [--no-plot]``:
the rotor transfer's command.

Reads a transfer file — one ``[transfer]`` table with the keys of a machine file's
``kind = "transfer"`` mechanism (``R_t_m``, ``R_p_m``, ``gap_m``, ``pockets_t``,
``pockets_p``, optionally ``x2_m``, ``max_jerk_m_per_s3``,
``max_acceleration_m_per_s2``) plus ``name`` and the speed ``rpm`` — and prints the
transition lengths (the length of least jerk unless ``x2_m`` is given), at the speed
(the file's ``rpm`` or ``--rpm``) the peripheral speeds, the acceleration jump
without transitions, the workpiece's peak acceleration and jerk, and the speed
limit the file's limits set. Writes ``path.csv`` (the path and the workpiece's
motion along it), ``results.json`` and the figure ``transfer.png``.

Exit status 0 when the speed is within the speed limit; 3 (the files written) when
a limit is exceeded at the speed, with a line saying which; 2 for bad input.

>>> import argparse
>>> from cyclomech.transfer import cli
>>> commands = argparse.ArgumentParser(prog="cyclomech").add_subparsers()
>>> cli.add_commands(commands)
>>> commands.choices["transfer"].parse_args(["line.toml", "--rpm", "90"]).rpm
90.0
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from .. import _toml
from .._arrays import count, speeds_rpm
from .._cli import EXIT_FAILS, EXIT_OK, has_matplotlib, out_folder, save, table
from .._errors import InputError
from .._files import savetxt, write_text
from .._json import jsonable
from ._jump import acceleration_jump
from ._kind import TransferMechanism
from ._path import PathAcceleration, PathSample

__all__ = ["FILE_KEYS", "add_commands", "read_transfer_file", "transfer_command"]

#: The keys of a transfer file's ``[transfer]`` table: a machine file's transfer
#: mechanism's (but ``kind``), its name and the speed [rpm].
FILE_KEYS = frozenset((TransferMechanism.keys - {"kind"}) | {"name", "rpm"})
#: The columns of ``path.csv`` (SI units, as their names say).
PATH_COLUMNS = (
    "s_m",
    "x_m",
    "y_m",
    "curvature_per_m",
    "piece",
    "time_s",
    "speed_m_per_s",
    "normal_acceleration_m_per_s2",
    "tangential_acceleration_m_per_s2",
    "acceleration_m_per_s2",
    "jerk_m_per_s3",
)


def add_commands(commands: Any) -> None:
    """Add the ``transfer`` command to the sub-parsers ``commands`` of ``cyclomech``.

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
    ['transfer']
    """
    t = commands.add_parser(
        "transfer",
        help="a rotor transfer: transition of least jerk, peak acceleration and jerk, "
        "speed limit (TOML)",
    )
    t.add_argument("file", help="transfer file, e.g. examples/rotor_transfer.toml")
    t.add_argument("--out", help="output folder (default: out/<file name>)")
    t.add_argument("--rpm", type=float, help="machine speed [rpm] (default: the file's rpm)")
    t.add_argument(
        "--samples",
        type=int,
        default=4001,
        help="points along the path in path.csv (default 4001)",
    )
    t.add_argument("--no-plot", action="store_true", help="do not write the figure")
    t.set_defaults(run=transfer_command)


def read_transfer_file(path: str | Path) -> tuple[TransferMechanism, float, str]:
    """The transfer, its speed [rpm] and its file's name for messages.

    Parameters
    ----------
    path : str or Path
        A transfer file: one ``[transfer]`` table (:data:`FILE_KEYS`).

    Returns
    -------
    mechanism : TransferMechanism
        The transfer (named by the file's ``name``, else the file's stem).
    rpm : float
        The file's ``rpm`` [rpm].
    source : str
        The file's name for messages.

    Raises
    ------
    InputError
        If the file is not a transfer file, a key is missing or unknown, or a value
        is malformed or out of range (each message names the file and the key).

    Examples
    --------
    >>> m, rpm, _ = read_transfer_file("examples/rotor_transfer.toml")
    >>> m.pockets_t, m.pockets_p, rpm
    (8, 12, 120.0)
    """
    data, source = _toml.load(path)
    if "machine" in data:
        raise InputError(
            f"{source}: this is a machine file ([machine]); run it with `cyclomech run {path}`"
        )
    _toml.check_keys(data, {"transfer"}, source, "top level")
    if "transfer" not in data:
        raise InputError(f"{source}: missing table [transfer] (the rotors and the speed)")
    t = data["transfer"]
    _toml.check_keys(t, FILE_KEYS, source, "[transfer]")
    where = f"{source}: [transfer]"
    _toml.require(t, ("rpm",), where)
    rpm = _toml.number(t, "rpm", where, "[rpm]")
    if not (math.isfinite(rpm) and rpm > 0):
        raise InputError(f"{where}: rpm = {rpm!r} must be a finite speed > 0 [rpm]")
    name = t.get("name", Path(source).stem)
    if not isinstance(name, str):
        raise InputError(f"{where}: name = {name!r} must be a string")
    table_ = {k: v for k, v in t.items() if k not in ("name", "rpm")}
    return TransferMechanism._from_checked(name, table_, where), rpm, source


def transfer_command(args: argparse.Namespace) -> int:
    """Run ``cyclomech transfer`` with the parsed ``args``.

    Prints the summary and writes the files to ``args.out`` (see the module's
    docstring).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``file``, ``out``, ``rpm`` [rpm], ``samples``,
        ``no_plot``).

    Returns
    -------
    int
        The exit status: 0 when the speed is within the speed limit, 3 when a limit
        is exceeded at it (the files written).

    Raises
    ------
    InputError
        If the file or an option is invalid.

    Examples
    --------
    >>> import argparse, tempfile
    >>> out = tempfile.mkdtemp()
    >>> a = argparse.Namespace(file="examples/rotor_transfer.toml", out=out, rpm=None,
    ...                        samples=401, no_plot=True)
    >>> transfer_command(a)  # doctest: +ELLIPSIS
    rotor transfer ...
    0
    """
    m, rpm, _ = read_transfer_file(args.file)
    if args.rpm is not None:
        rpm = float(speeds_rpm("--rpm", args.rpm)[0])
    n = count("--samples", args.samples, low=10, high=1_000_000)
    p = m.path
    v_t, v_p = m.speeds(rpm)
    jump = float(acceleration_jump(p.R_t, v_t / p.R_t, p.R_p, v_p / p.R_p))
    # The peaks on the fine sample the speed limit is found on; the CSV's on --samples.
    peak_acc, peak_jerk = m.peaks(rpm)
    acc = p.acceleration((v_t, v_p), n)
    smp = p.sample(n)
    limit = m.speed_limit_rpm()
    works = rpm <= limit * (1 + 1e-12)
    print(
        f"{m.name}: rotor transfer, R_t = {p.R_t * 1e3:g} mm ({m.pockets_t} pockets), "
        f"R_p = {p.R_p * 1e3:g} mm ({m.pockets_p} pockets), gap {p.gap * 1e3:g} mm"
    )
    rows = [
        ["transitions x2 [mm]", "", f"{p.x2_t * 1e3:.4g}, {p.x2_p * 1e3:.4g}"],
        ["peripheral speeds [m/s]", "V_t, V_p", f"{v_t:.4g}, {v_p:.4g}"],
        ["jump without transitions [m/s²]", "ΔW", f"{jump:.4g}"],
        ["peak acceleration [m/s²]", "|a|", f"{peak_acc:.4g}"],
        ["peak jerk [m/s³]", "|da/dt|", f"{peak_jerk:.4g}"],
        [
            "speed limit [rpm]",
            "",
            f"{limit:.4g}" if math.isfinite(limit) else "none (no limit given)",
        ],
    ]
    print(f"  at {rpm:g} rpm:")
    print(table(rows, ["quantity", "symbol", "value"]))
    out = out_folder(args)
    _write_path(out / "path.csv", smp, acc)
    written = [out / "path.csv"]
    summary = {
        "schema": "cyclomech.transfer/1",
        "name": m.name,
        "rpm": rpm,
        "R_t_m": p.R_t,
        "R_p_m": p.R_p,
        "gap_m": p.gap,
        "pockets": [m.pockets_t, m.pockets_p],
        "x2_m": [p.x2_t, p.x2_p],
        "speeds_m_per_s": [v_t, v_p],
        "jump_m_per_s2": jump,
        "max_acceleration_m_per_s2": peak_acc,
        "max_jerk_m_per_s3": peak_jerk,
        "speed_limit_rpm": limit if math.isfinite(limit) else None,
        "limit_reason": m.limit_reason(),
        "works": works,
    }
    write_text(out / "results.json", json.dumps(jsonable(summary), indent=2) + "\n")
    written.append(out / "results.json")
    if not args.no_plot and has_matplotlib("figure"):
        from .plot import plot_transfer

        fig = plot_transfer(p, speed=(v_t, v_p), title=f"{m.name}: transfer at {rpm:g} rpm")
        save(fig, out / "transfer.png", written)
    print("\nwrote " + ", ".join(str(w) for w in written))
    if not works:
        print(f"\nFAILS: {rpm:g} rpm is above the speed limit {limit:.4g} rpm: {m.limit_reason()}")
        return EXIT_FAILS
    return EXIT_OK


def _write_path(path: Path, smp: PathSample, acc: PathAcceleration) -> None:
    """``path.csv``: the sampled path and the workpiece's motion along it
    (:data:`PATH_COLUMNS`)."""
    savetxt(
        path,
        np.column_stack(
            [
                smp.s,
                smp.points[:, 0],
                smp.points[:, 1],
                smp.curvature,
                smp.piece,
                acc.time,
                acc.speed,
                acc.normal,
                acc.tangential,
                acc.total,
                acc.jerk,
            ]
        ),
        delimiter=",",
        comments="",
        fmt="%.12g",
        header=",".join(PATH_COLUMNS),
    )
