"""Command line of cyclomech: ``cyclomech <command> FILE.toml [options]``.

Each domain owns its command in its ``cli.py``, which adds the command's
sub-parser and runs it: ``cyclogram`` (:mod:`cyclomech.cyclogram.cli`),
``linkage`` (:mod:`cyclomech.linkage.cli`), ``press`` (:mod:`cyclomech.press.cli`),
``impact`` (:mod:`cyclomech.impact.cli`), ``cam`` (:mod:`cyclomech.cam.cli`),
``transfer`` (:mod:`cyclomech.transfer.cli`), ``run`` and ``sweep``
(:mod:`cyclomech.machine.cli`). This module builds the top-level parser from the
list :data:`COMMANDS`, checks ``--out`` before any work, and turns errors into one
line and an exit status; the helpers the commands share are in ``_cli``.

Exit status: 0 when the job is done and the design works; 2 for bad input (the
message names the file, the table and the key); 3 when the job is done (its files
written) but the design fails: a machine whose cyclogram fits at no speed, a
linkage that cannot make a full turn under ``--require-full-turn``, a sweep whose
every design is invalid; 1 when a cyclogram has no feasible optimum or a press
design does not work; 130 when interrupted.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from collections.abc import Sequence
from typing import TextIO

from _cyclomech_entry._interrupt import CtrlC, report

from . import _core
from ._arrays import MAX_THREADS
from ._cli import (
    EXIT_BROKEN_PIPE,
    EXIT_FAILS,
    EXIT_INPUT,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_WRITE,
    out_path,
)
from ._errors import CyclomechError, InputError
from .cam import cli as cam_cli
from .cyclogram import cli as cyclogram_cli
from .impact import cli as impact_cli
from .linkage import cli as linkage_cli
from .machine import cli as machine_cli
from .press import cli as press_cli
from .transfer import cli as transfer_cli

#: The environment variable of the Rust kernels' default thread count.
THREADS_ENV = _core.THREADS_ENV

__all__ = [
    "EXIT_BROKEN_PIPE",
    "EXIT_FAILS",
    "EXIT_INPUT",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "main",
]

#: The domains with commands, in the order of ``cyclomech --help``: each module's
#: ``add_commands(subparsers)`` adds its commands, each sub-parser with its ``run``
#: function as a default. A new domain adds one line here.
COMMANDS = (
    cyclogram_cli,
    linkage_cli,
    press_cli,
    impact_cli,
    cam_cli,
    transfer_cli,
    machine_cli,
)


def _not_a_machine_file(args: argparse.Namespace) -> None:
    """A machine file given to a one-domain command: say which command reads it
    (as `run` does for the other files)."""
    if getattr(args, "machine_file", False):
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


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """``warnings.showwarning`` for the command: ``cyclomech: warning: <message>``."""
    print(f"cyclomech: warning: {message}", file=sys.stderr if file is None else file)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``cyclomech`` command."""
    threads_env = os.environ.get(THREADS_ENV)  # --threads sets it for the command only
    watch = CtrlC()
    try:  # from its first line: building the parser takes a while too
        with watch:
            return _main(argv)
    except BaseException as error:  # a Ctrl-C, or an error it caused (its rule)
        if not watch.explains(error):
            raise
        return report()
    finally:
        if threads_env is None:
            os.environ.pop(THREADS_ENV, None)
        else:
            os.environ[THREADS_ENV] = threads_env


def _threads_env(threads: int | None) -> str:
    """Why ``CYCLOMECH_THREADS`` is unusable ("" if it is fine), by the Rust core's
    rule. ``--threads N`` (validated by its command) sets it for the command, so that
    every kernel takes N."""
    if threads is not None and 1 <= threads <= MAX_THREADS:
        os.environ[THREADS_ENV] = str(threads)
    try:
        _core.threads()
    except InputError as e:
        return str(e)
    return ""


def _main(argv: Sequence[str] | None) -> int:
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="cyclomech",
        description="Design of cyclic machines.",
        epilog="Exit statuses: 0 the job is done and the design works; 2 bad input; 3 the "
        "job is done and its files written but the design fails; 4 an output file could "
        "not be written (a full disk); 130 interrupted.",
    )
    parser.add_argument("--version", action="version", version=f"cyclomech {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for domain in COMMANDS:
        domain.add_commands(sub)
    args = parser.parse_args(argv)
    bad = _threads_env(getattr(args, "threads", None))
    if bad:  # the environment's, not the file's: said before the file is read
        print(f"cyclomech: error: {bad}", file=sys.stderr)
        return EXIT_INPUT
    # A warning for the user (a near-miss name, an angle a linkage cannot reach) is one
    # line on stderr, like an error, not Python's warning with a source line.
    try:
        with warnings.catch_warnings():  # restores showwarning for an in-process caller
            warnings.showwarning = _one_line_warning
            out_path(args)  # a bad --out fails now, not after the work
            _not_a_machine_file(args)
            return int(args.run(args))
    except CyclomechError as e:
        # Errors from the file already name it; name it for the others too.
        msg = str(e) if args.file in str(e) else f"{args.file}: {e}"
        print(f"cyclomech: error: {msg}", file=sys.stderr)
        return EXIT_INPUT
    except BrokenPipeError:
        # Whoever read the output stopped (`| head`): no traceback, and none at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except OSError as e:
        # A file the command writes could not be written (ENOSPC, EACCES, EDQUOT):
        # one line naming it and why. The files are written whole or not at all, so
        # nothing half-written is left (the input file's errors are InputErrors).
        print(f"cyclomech: error: {_write_failure(e)}", file=sys.stderr)
        return EXIT_WRITE


def _write_failure(e: OSError) -> str:
    """One line for an output file that could not be written: the file (when the
    system names it) and the system's reason."""
    reason = e.strerror or str(e)
    where = f"cannot write {e.filename}" if e.filename else "cannot write an output file"
    return f"{where}: {reason} (no half-written file is left)"


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
