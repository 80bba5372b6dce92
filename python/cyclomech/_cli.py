"""Helpers that several commands of ``cyclomech`` share (private).

Each domain's ``cli.py`` defines its command; what they have in common lives here
once: the exit statuses, the text table, counted words, the ``--step-deg`` check,
the output folder (checked before any work, made when the results are written),
the matplotlib check and figure saving (matplotlib imported only when figures are
written), and quiet Ctrl-C while a Dask sweep runs.

>>> print(table([["cam", "rise", "12.5"]], ["mechanism", "operation", "angle°"]))
  mechanism  operation  angle°
  ---------  ---------  ------
  cam        rise         12.5
>>> plural(1, "design"), plural(3, "speed")
('1 design', '3 speeds')
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import math
import signal
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from _cyclomech_entry._interrupt import EXIT_INTERRUPTED

from ._errors import InputError
from ._files import folder_problem, whole

__all__ = [
    "EXIT_BROKEN_PIPE",
    "EXIT_FAILS",
    "EXIT_INPUT",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "MIN_STEP_DEG",
    "check_step",
    "has_matplotlib",
    "out_folder",
    "out_path",
    "plural",
    "quiet_interrupt",
    "save",
    "table",
]

#: Exit status of a job that is done and whose design works.
EXIT_OK = 0
#: Exit status for bad input: the message names the file, the table and the key.
EXIT_INPUT = 2
#: Exit status of a job that ran and wrote its files, but whose design fails (a
#: machine that works at no speed, a cyclogram with no feasible optimum, a press
#: design that does not work): every command's.
EXIT_FAILS = 3
#: Exit status when an output file could not be written (a full disk, no
#: permission, a quota): the message names the file and the system's reason; the
#: file is not left half-written (:func:`cyclomech._files.whole`).
EXIT_WRITE = 4
#: Exit status when whoever read the output stopped reading (``| head``).
EXIT_BROKEN_PIPE = 141
#: Finest crank-angle step of the linkage and press commands [deg]: 360 000 angles a
#: turn, whose table (CSV) is already hundreds of MB; 1e-6° would allocate gigabytes.
MIN_STEP_DEG = 1e-3


def table(rows: list[list[str]], header: list[str]) -> str:
    """``rows`` under ``header`` in aligned columns, indented by two spaces: the
    first two columns flush left (names), the others flush right (numbers)."""
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]
    fmt = "  ".join(f"{{:<{w}}}" if i < 2 else f"{{:>{w}}}" for i, w in enumerate(widths))
    lines = [fmt.format(*header), fmt.format(*("-" * w for w in widths))]
    lines += [fmt.format(*r) for r in rows]
    return "\n".join("  " + ln for ln in lines)


def plural(count: int, word: str) -> str:
    """``count`` and ``word``, plural where it is not 1: 1 design, 2 designs."""
    return f"{count} {word}{'' if count == 1 else 's'}"


def check_step(step: float) -> None:
    """``--step-deg`` of the linkage and press commands, in [MIN_STEP_DEG, 90]°."""
    if not (math.isfinite(step) and MIN_STEP_DEG <= step <= 90):
        raise InputError(
            f"--step-deg {step:g}: give a step in [{MIN_STEP_DEG:g}, 90] degrees "
            f"(at most {round(360 / MIN_STEP_DEG):,} angles a turn)"
        )


def out_path(args: argparse.Namespace) -> Path:
    """The output folder of a command, checked before any work: it, or the nearest
    of its parents that exists, must be a writable folder."""
    out = Path(args.out) if args.out else Path("out") / Path(args.file).stem
    why = folder_problem(out)
    if why:
        raise InputError(f"--out {out}: {why}; give a folder for the results")
    return out


def out_folder(args: argparse.Namespace) -> Path:
    """The output folder of a command (:func:`out_path`), made if it is missing."""
    out = out_path(args)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(
            f"--out {out}: cannot create the output folder: {e.strerror or e}"
        ) from None
    return out


def has_matplotlib(what: str = "figures") -> bool:
    """Select the Agg backend, or say why no figures are written."""
    try:
        import matplotlib
    except ImportError:
        print(f"\n(no {what}: matplotlib is not installed; pip install cyclomech[plot])")
        return False
    matplotlib.use("Agg")
    return True


def save(fig: Any, path: Path, written: list[Path]) -> None:
    """Write ``fig`` to ``path``, close it, and note the file."""
    import matplotlib.pyplot as plt

    with whole(path) as tmp:  # a Ctrl-C leaves no half-written figure
        fig.savefig(tmp, dpi=130, bbox_inches="tight")
    plt.close(fig)
    written.append(path)


@contextlib.contextmanager
def quiet_interrupt(active: bool) -> Iterator[None]:
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
