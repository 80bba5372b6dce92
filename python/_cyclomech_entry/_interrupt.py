"""What counts as a Ctrl-C: the one rule of the console script, ``python -m
cyclomech`` and :func:`cyclomech.cli.main`. Here, outside the package, so that the
entry point can use it before ``import cyclomech`` (which takes ~0.6 s) has run."""

from __future__ import annotations

import _thread
import contextlib
import os
import signal
import sys
import time
from typing import Any

#: The exit status of an interrupted command (128 + SIGINT): the entry point's, the
#: package's under ``python -m`` and every command's (``cyclomech._cli`` takes it).
EXIT_INTERRUPTED = 130


def report() -> int:
    """Say that the command was interrupted (one line on stderr) and give its exit
    status, :data:`EXIT_INTERRUPTED`.

    >>> import contextlib, io, sys
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     status = report()
    >>> status, err.getvalue()
    (130, 'cyclomech: interrupted\\n')
    """
    print("cyclomech: interrupted", file=sys.stderr, flush=True)
    return EXIT_INTERRUPTED


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


class CtrlC:
    """Watch a block for Ctrl-C: whether SIGINT arrived, and no Ctrl-C lost.

    Two ways a Ctrl-C escapes the KeyboardInterrupt rule of :func:`interrupted`:

    * CPython cannot raise a KeyboardInterrupt inside a weakref callback or a
      ``__del__`` (an import's module lock has one): it prints "Exception ignored
      in ..." with a traceback and carries on, so the Ctrl-C would be lost and the
      command would run on. Inside the block such an interrupt prints nothing and
      is sent again, as the signal a Ctrl-C sends, from a short-lived thread 10 ms
      later, and the main thread raises it out of the callback. (Not from the hook
      itself: Python would raise it at once, inside the hook, to be swallowed
      again.) If the block ends before that, it raises KeyboardInterrupt as it ends.
    * A Cython module's initialisation turns an interrupt into an ImportError of its
      own ("numpy.core.multiarray failed to import"), with no chain to it. So the
      block also notes whether SIGINT arrived at all (:func:`signal.set_wakeup_fd`,
      which leaves the handlers alone: the Rust core hooks its kernels' Ctrl-C to the
      interpreter's default handler when it loads) and :meth:`explains` counts any
      error of a block that received SIGINT as the Ctrl-C's.

    Other unraisable errors go to the hook that was in place. Outside the main
    thread (where signals are never handled) only the first applies.

    >>> import time
    >>> class Dropped:
    ...     def __del__(self):
    ...         raise KeyboardInterrupt
    >>> watch = CtrlC()
    >>> try:
    ...     with watch:
    ...         dropped = Dropped()
    ...         del dropped  # its __del__ runs here
    ...         time.sleep(5)  # interrupted 10 ms in
    ...         print("never")
    ... except KeyboardInterrupt as e:
    ...     print("raised", watch.received, watch.explains(e))
    raised True True
    """

    def __init__(self) -> None:
        self.received = False
        self._lock = _thread.allocate_lock()
        self._pending = self._ended = False
        self._hook: Any = None
        self._fds: tuple[int, int] | None = None
        self._wakeup = -1

    def explains(self, error: BaseException) -> bool:
        """Whether ``error`` is the Ctrl-C's: SIGINT arrived during the block, or
        ``error`` is an interrupt by :func:`interrupted`'s rule."""
        return self.received or interrupted(error)

    def __enter__(self) -> CtrlC:
        self._hook = sys.unraisablehook
        sys.unraisablehook = self._unraisable
        r, w = os.pipe()
        os.set_blocking(r, False)
        os.set_blocking(w, False)
        try:
            self._wakeup = signal.set_wakeup_fd(w, warn_on_full_buffer=False)
            self._fds = (r, w)
        except ValueError:  # not the main thread: signals are not handled here
            os.close(r)
            os.close(w)
        return self

    def __exit__(self, *exc: object) -> None:
        sys.unraisablehook = self._hook
        if self._fds is not None:
            signal.set_wakeup_fd(self._wakeup)
            r, w = self._fds
            try:
                arrived = os.read(r, 4096)  # one byte a signal: its number
            except BlockingIOError:  # no signal at all
                arrived = b""
            self.received = self.received or bytes([signal.SIGINT]) in arrived
            if arrived and self._wakeup >= 0:  # an outer watch (or asyncio) hears it too
                with contextlib.suppress(OSError):
                    os.write(self._wakeup, arrived)
            os.close(r)
            os.close(w)
        with self._lock:
            self._ended = True
            ends_first = self._pending
        if ends_first and exc[0] is None:
            self.received = True
            raise KeyboardInterrupt

    def _unraisable(self, unraisable: Any) -> None:
        if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
            if not self._pending:
                self._pending = True
                _thread.start_new_thread(self._send, ())  # does not wait for the thread
        else:
            self._hook(unraisable)

    def _send(self) -> None:
        time.sleep(0.01)  # the hook that started this thread has returned by then
        with self._lock:
            if self._ended:
                return
            self._pending = False  # one swallowed later is sent again
        os.kill(os.getpid(), signal.SIGINT)
