"""What counts as a Ctrl-C: the one rule of the console script, ``python -m
cyclomech`` and :func:`cyclomech.cli.main`. Here, outside the package, so that the
entry point can use it before ``import cyclomech`` (which takes ~0.6 s) has run."""

from __future__ import annotations

import _thread
import os
import signal
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any


def interrupted(error: BaseException) -> bool:
    """Whether ``error`` is a Ctrl-C: a KeyboardInterrupt, or an error raised while
    one was propagating (its ``__cause__`` / ``__context__`` chain holds one).

    >>> interrupted(KeyboardInterrupt())
    True
    >>> try:
    ...     try:
    ...         raise KeyboardInterrupt
    ...     except KeyboardInterrupt as e:
    ...         raise ImportError("initialization failed") from e
    ... except ImportError as e:
    ...     interrupted(e)
    True
    >>> interrupted(ImportError("No module named 'scipy'"))
    False
    """
    seen: set[int] = set()
    link: BaseException | None = error
    while link is not None and id(link) not in seen:
        if isinstance(link, KeyboardInterrupt):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False


class _Resend:
    """A swallowed Ctrl-C, sent again once: by a short-lived thread 10 ms after the
    hook saw it, or, if the block ends first, raised at its end (the lock makes it
    exactly one of the two)."""

    def __init__(self) -> None:
        self.lock = _thread.allocate_lock()
        self.pending = self.sent = self.ended = False

    def seen(self) -> None:
        if not self.pending:
            self.pending = True
            _thread.start_new_thread(self._send, ())  # does not wait for the thread

    def _send(self) -> None:
        time.sleep(0.01)  # the hook that started this thread has returned by then
        with self.lock:
            if self.ended:
                return
            self.sent = True
            self.pending = False  # a new one swallowed later is sent again
        os.kill(os.getpid(), signal.SIGINT)

    def end(self) -> bool:
        """Whether the block's end must raise it (seen, and not sent)."""
        with self.lock:
            self.ended = True
            return self.pending


@contextmanager
def swallowed_interrupts_raised() -> Iterator[None]:
    """Within the block, a Ctrl-C that CPython could not raise is raised again.

    A KeyboardInterrupt raised inside a weakref callback or a ``__del__`` (an
    import's module lock has one) cannot propagate: CPython prints "Exception ignored
    in ..." with a traceback and carries on, so the Ctrl-C would be lost and the
    command would run on. Inside this block such an interrupt prints nothing and is
    sent again, as the signal a Ctrl-C sends, from a short-lived thread 10 ms later:
    the main thread then raises it out of the callback. (Not from the hook itself:
    Python would raise it at once, inside the hook, to be swallowed again.) If the
    block ends before that, it raises KeyboardInterrupt at its end instead. Other
    unraisable errors go to the hook that was in place.

    >>> import time
    >>> class Dropped:
    ...     def __del__(self):
    ...         raise KeyboardInterrupt
    >>> try:
    ...     with swallowed_interrupts_raised():
    ...         dropped = Dropped()
    ...         del dropped  # its __del__ runs here
    ...         time.sleep(5)  # interrupted 10 ms in
    ...         print("never")
    ... except KeyboardInterrupt:
    ...     print("raised")
    raised
    """
    before = sys.unraisablehook
    resend = _Resend()

    def hook(unraisable: Any) -> None:
        if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
            resend.seen()
        else:
            before(unraisable)

    sys.unraisablehook = hook
    try:
        yield
    finally:
        sys.unraisablehook = before
        ended_first = resend.end()
    if ended_first:
        raise KeyboardInterrupt
