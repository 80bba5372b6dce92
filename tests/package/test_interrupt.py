"""Ctrl-C during one long Rust call: the call stops at its next chunk and raises
KeyboardInterrupt, and no partial output ever comes back.

The rules (``cyclomech_core::cancel`` and ``rust/bindings/src/interrupt.rs``):
- a kernel called from the main thread, with SIGINT on the interpreter's default
  handler, is cut short and raises KeyboardInterrupt;
- a SIGINT handler set with ``signal.signal`` after import replaces the hook: the
  call runs to the end and its output is whole (the handler runs after);
- a call from another thread is not cut short; if an armed main-thread call's
  signal reached its tasks, it raises KeyboardInterrupt instead of returning.

Each case runs in a fresh interpreter (the hook is per process). The only timing
checked is that an interrupted call ends far sooner than it would have: the full
call takes seconds (the 4-5-6-7 rise at 1 ≤ τ ≤ 4, below its SIMD lanes' τ_min:
the exact scalar pieces, the slowest path of the laws' closed forms, ~100 ns a
value), the test allows 20 s after the signal. That each kind of
parallel loop polls the flag is checked in Rust (``rust/core/tests/cancel.rs``).
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")

PRELUDE = """
import os, signal, sys, threading, time, traceback
import numpy as np
import cyclomech as cm

CALL = "_core.cam_residual_ratio"  # the kernel's call, as its line reads

def kill_soon(delay):
    threading.Timer(delay, lambda: os.kill(os.getpid(), signal.SIGINT)).start()

def kill_in_kernel(delay):
    # SIGINT `delay` s after the main thread entered the kernel (its innermost frame
    # is the line calling _core, as in_kernel reads it). Not a fixed time from now:
    # on a loaded machine the checks before the call took longer than the timer.
    main = threading.main_thread().ident
    def watch():
        while True:
            frame = sys._current_frames().get(main)
            if frame is not None and CALL in (traceback.extract_stack(frame)[-1].line or ""):
                break
            time.sleep(0.005)
        time.sleep(delay)
        KILLED.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)
    threading.Thread(target=watch, daemon=True).start()

KILLED = []  # when kill_in_kernel sent its signal

def vibration(n, threads):
    # Below the lanes' tau_min (4.03): the scalar pieces, ~100 ns a value.
    tau = np.linspace(1.0, 4.0, n)
    return cm.cam.residual_vibration("polynomial_4567", tau, 0.1, n_threads=threads)

def in_kernel(e):
    # Raised by the kernel's call, not by Python code before it (the checks of 2e7
    # values take a while): the innermost frame is the line calling _core.
    return CALL in traceback.extract_tb(e.__traceback__)[-1].line
"""


def _child(body: str) -> str:
    code = PRELUDE + textwrap.dedent(body)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


@pytest.mark.slow
@pytest.mark.parametrize("threads", [1, 2])
def test_a_long_call_is_cut_short_and_raises_keyboard_interrupt(threads):
    # 2e7 values at ~100 ns each: ~2 s on one thread if it ran to the end; the
    # signal comes 0.2 s after the kernel started (checked: where the exception came from).
    out = _child(f"""
        ref = vibration(3000, {threads})
        kill_in_kernel(0.2)
        t0 = time.perf_counter()
        try:
            vibration(20_000_000, {threads})
            print("finished")
        except KeyboardInterrupt as e:
            # seconds from the signal to the interrupt (the kernel's chunks are short)
            print("interrupted" if in_kernel(e) else "early", time.perf_counter() - KILLED[0])
        # The next call is whole and the same as before.
        print("same", np.array_equal(vibration(3000, {threads}), ref))
    """)
    words = out.split()
    assert words[0] == "interrupted", out
    assert float(words[1]) < 20.0, out
    assert words[2:] == ["same", "True"], out


@pytest.mark.slow
def test_a_handler_of_the_users_own_keeps_the_call_whole():
    out = _child("""
        ref = vibration(5_000_000, 1)
        seen = []
        signal.signal(signal.SIGINT, lambda s, f: seen.append(s))
        kill_soon(0.1)
        got = vibration(5_000_000, 1)
        print(np.array_equal(got, ref), seen == [signal.SIGINT])
    """)
    assert out.split() == ["True", "True"], out


@pytest.mark.slow
def test_a_call_from_another_thread_runs_to_the_end():
    out = _child("""
        ref = vibration(5_000_000, 1)
        box = {}
        worker = threading.Thread(target=lambda: box.update(r=vibration(5_000_000, 1)))
        worker.start()
        kill_soon(0.1)
        try:
            worker.join()
            time.sleep(5)  # the signal lands while the main thread waits in Python
        except KeyboardInterrupt:
            print("main interrupted")
        worker.join()
        print(np.array_equal(box["r"], ref))
    """)
    assert out.split() == ["main", "interrupted", "True"], out


@pytest.mark.slow
def test_a_call_beside_an_interrupted_one_is_whole_or_raises():
    # The flag is shared: a worker's call running while the main thread's call is
    # cut may stop early too. It must then raise, never return a partial output.
    # (On a pool of its own, so that its chunks run while the main call winds down.)
    out = _child("""
        ref = vibration(1_000_000, 2)
        box = {}
        def work():
            try:
                box["r"] = vibration(1_000_000, 2)
            except KeyboardInterrupt as e:
                box["e"] = str(e)
        worker = threading.Thread(target=work)
        worker.start()
        kill_in_kernel(0.2)
        try:
            vibration(20_000_000, 1)
        except KeyboardInterrupt as e:
            print("main interrupted" if in_kernel(e) else "main early")
        worker.join()
        if "r" in box:
            print("whole", np.array_equal(box["r"], ref))
        else:
            print("raised", "cut short by Ctrl-C" in box["e"])
    """)
    words = out.split()
    assert words[:2] == ["main", "interrupted"], out
    assert words[2:] in (["whole", "True"], ["raised", "True"]), out
