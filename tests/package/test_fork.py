"""Kernels in a child made by ``fork`` after the parent ran a parallel kernel.

``fork`` copies the parent's thread pools but not their threads; before the pools
remembered the process that built them, the child's first parallel call waited
forever (issue 31, item 6). ``multiprocessing``'s default start method on Linux
is ``fork``, and joblib and some Dask set-ups fork too.
"""

from __future__ import annotations

import multiprocessing as mp
import os

import numpy as np
import pytest
from cyclomech.impact import duhamel_batch
from cyclomech.motion import law

pytestmark = pytest.mark.skipif(
    "fork" not in mp.get_all_start_methods(), reason="this platform cannot fork"
)

#: Seconds a child's call may take before it counts as hung (the calls take ms).
_HUNG_S = 60.0


def _duhamel(threads: int) -> float:
    t = np.linspace(0.0, 0.1, 2000)
    forces = np.ones((64, t.size))
    return float(duhamel_batch(t, forces, 300.0, 0.05, 1.0, n_threads=threads).sum())


def _law(threads: int) -> float:
    x = np.linspace(0.0, 1.0, 300_000)
    return float(law("cycloidal").z(x, n_threads=threads).sum())


@pytest.mark.parametrize("kernel", [_duhamel, _law])
@pytest.mark.parametrize("threads", [1, 2])
def test_fork_pool_after_a_parallel_call(kernel, threads) -> None:
    # The parent builds its pool first: that pool is what the children inherit.
    reference = kernel(threads)
    ctx = mp.get_context("fork")
    with ctx.Pool(2) as workers:
        results = workers.map_async(kernel, [threads] * 4).get(timeout=_HUNG_S)
    # The children's answers are the parent's, bit for bit.
    assert results == [reference] * 4
    # And the parent's own pool still works after forking.
    assert kernel(threads) == reference


def test_fork_in_a_child_of_a_child() -> None:
    """A grandchild forked from a child that built its own fresh pool."""
    reference = _duhamel(2)
    ctx = mp.get_context("fork")
    with ctx.Pool(1) as workers:
        got = workers.apply_async(_fork_again).get(timeout=_HUNG_S)
    assert got == [reference] * 2


def _fork_again() -> list[float]:
    """In a pool worker: build this process's own pool, then fork twice more
    (``os.fork``: a pool worker is daemonic and may not start a ``Pool``) and
    return what each grandchild computed."""
    _duhamel(2)
    out = []
    for _ in range(2):
        r, w = os.pipe()
        pid = os.fork()
        if pid == 0:  # the grandchild: answer through the pipe, then leave at once
            os.close(r)
            os.write(w, repr(_duhamel(2)).encode())
            os._exit(0)
        os.close(w)
        with os.fdopen(r, "rb") as f:
            out.append(float(f.read()))
        os.waitpid(pid, 0)
    return out
