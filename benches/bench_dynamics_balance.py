"""Counterweight designs of a balanced linkage evaluated in one call, against numpy.

``cyclomech.dynamics.Balance.evaluate``: the RMS and peak shaking force, shaking
moment and driving torque of 10 000 counterweight designs (a crank's and a
rocker's, J = 2) of a four-bar over 3600 crank angles, one Rust call (designs in
parallel, the GIL released, only the statistics kept), against the best numpy a
user would write for the same linear form: the four channels of a chunk of
designs as one matrix product (the form's (4·N, 2J) matrix times the designs'
(2J, D) vectors, BLAS, plus the counterweights' lengths times their (4·N, J)
column), then the squares' means and the magnitudes' maxima along the angles; in
chunks of 256 designs (the whole (4, 3600, 10 000) block would be 1.2 GB). Both
agree to 1e-12 (:func:`test_numpy_agrees`, outside the timing).

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings and the ratio table::

    python -m pytest benches/bench_dynamics_balance.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from cyclomech.forces import LinkMass

Array = npt.NDArray[np.float64]
GROUP = "balance: 10 000 counterweight designs × 3600 angles"
D = 10_000
N = 3600
CHUNK = 256


def balanced() -> cm.dynamics.Balance:
    lk = cm.Linkage(
        {"O": (0.0, 0.0), "A": (0.1, 0.05), "B": (0.38, 0.22), "D": (0.4, 0.0)},
        [("O", "A"), ("A", "B"), ("D", "B")],
        ["O", "D"],
        ("O", "A"),
    )
    masses = {
        ("O", "A"): LinkMass(1.2, com_offset_m=(0.04, 0.01), inertia_kg_m2=0.002),
        ("A", "B"): LinkMass(2.5, com_offset_m=(0.15, -0.03), inertia_kg_m2=0.02),
        ("D", "B"): LinkMass(1.8, com_offset_m=(0.1, 0.02), inertia_kg_m2=0.008),
    }
    k = cm.forces.kinetostatics(
        lk, np.arange(N) * (2 * math.pi / N), masses=masses, gravity=(0.0, -9.81)
    )
    return cm.dynamics.balance(
        k, counterweights=[("O", "A"), ("D", "B")], rpm=300.0, gravity=(0.0, -9.81)
    )


def designs(d: int = D) -> Array:
    out: Array = np.random.default_rng(34).uniform(-0.5, 0.5, (d, 2, 2))
    return out


def numpy_stats(base: Array, lin: Array, nrm: Array, w: Array) -> Array:
    """(D, 6) statistics of designs ``w`` (D, J, 2) of the form (4, N), (4, J, N, 2),
    (4, J, N): chunks of designs, each one BLAS product per channel block."""
    c, j, n, _ = lin.shape
    a = np.ascontiguousarray(np.moveaxis(lin, 1, 2).reshape(c * n, 2 * j))
    q = np.ascontiguousarray(np.moveaxis(nrm, 1, 2).reshape(c * n, j))
    b = base.reshape(c * n, 1)
    out = np.empty((w.shape[0], 6))
    for s in range(0, w.shape[0], CHUNK):
        wc = w[s : s + CHUNK]
        v = a @ wc.reshape(-1, 2 * j).T + q @ np.hypot(wc[..., 0], wc[..., 1]).T + b
        v = v.reshape(c, n, -1)
        f2 = v[0] ** 2 + v[1] ** 2
        out[s : s + CHUNK, 0] = np.sqrt(f2.mean(axis=0))
        out[s : s + CHUNK, 1] = np.sqrt(f2.max(axis=0))
        for i, ch in ((2, 2), (4, 3)):
            out[s : s + CHUNK, i] = np.sqrt((v[ch] ** 2).mean(axis=0))
            out[s : s + CHUNK, i + 1] = np.abs(v[ch]).max(axis=0)
    return out


def test_numpy_agrees() -> None:
    b, w = balanced(), designs(300)
    got = b.evaluate(w)
    want = numpy_stats(b.form.base, b.form.lin, b.form.nrm, w)
    for i, key in enumerate(got):
        np.testing.assert_allclose(got[key], want[:, i], rtol=1e-12, atol=1e-12 * want[:, i].max())


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_balance_cyclomech(benchmark, threads: int) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"Balance.evaluate, n_threads={threads}"
    b, w = balanced(), designs()
    out = benchmark.pedantic(b.evaluate, (w,), {"n_threads": threads}, rounds=5, warmup_rounds=1)
    assert out["rms_force_n"].shape == (D,)


@pytest.mark.benchmark(group=GROUP)
def test_balance_numpy(benchmark) -> None:
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"BLAS product in chunks of {CHUNK} designs"
    b, w = balanced(), designs()
    f = b.form
    out = benchmark.pedantic(numpy_stats, (f.base, f.lin, f.nrm, w), rounds=3, warmup_rounds=1)
    assert out.shape == (D, 6)
