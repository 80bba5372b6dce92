"""The ``cyclomech`` console script's entry point, outside the package.

``import cyclomech`` loads every domain and the Rust core (~0.6 s): a Ctrl-C in that
time would print the import's traceback, since :func:`cyclomech.cli.main` catches
KeyboardInterrupt only once it runs. This module imports nothing at the top but its
own :mod:`~_cyclomech_entry._interrupt` (the standard library only), so the console
script can catch it and exit like the rest of the command line: one line on stderr,
exit status 130.

A Ctrl-C that lands inside an extension module's initialisation does not arrive as a
KeyboardInterrupt: CPython raises ``ImportError("initialization failed")`` *from* it
(seen in CI with scipy's HiGHS module). The rule, in :func:`interrupted`: an error
whose chain of causes holds a KeyboardInterrupt is a Ctrl-C, and so is any error
while SIGINT arrived (:class:`~_cyclomech_entry._interrupt.CtrlC`, which also keeps a
Ctrl-C CPython swallows from being lost). The package's ``__init__`` (under ``python
-m``) and :func:`cyclomech.cli.main` use the same rule.
"""

from __future__ import annotations

from ._interrupt import CtrlC, report


def main() -> int:
    """Run the ``cyclomech`` command; 130 with one line on stderr if interrupted while
    the package loads (after, :func:`cyclomech.cli.main` handles it)."""
    watch = CtrlC()
    try:
        with watch:
            from cyclomech.cli import main as run
    except BaseException as error:  # only a Ctrl-C is handled (re-raised otherwise)
        if not watch.explains(error):
            raise
        return report()
    return run()
