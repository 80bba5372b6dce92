"""The ``cyclomech`` console script's entry point, outside the package.

``import cyclomech`` loads every domain and the Rust core (~0.6 s): a Ctrl-C in that
time would print the import's traceback, since :func:`cyclomech.cli.main` catches
KeyboardInterrupt only once it runs. This module imports nothing at the top but
:mod:`sys`, so the console script can catch it and exit like the rest of the command
line: one line on stderr, exit status 130.
"""

from __future__ import annotations

import sys

#: The exit status of an interrupted command (128 + SIGINT), as cyclomech._cli's.
EXIT_INTERRUPTED = 130


def main() -> int:
    """Run the ``cyclomech`` command; 130 with one line on stderr if interrupted while
    the package loads (after, :func:`cyclomech.cli.main` handles it)."""
    try:
        from cyclomech.cli import main as run
    except KeyboardInterrupt:
        print("cyclomech: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    return run()
