"""A servo segment's RMS bound over many machine speeds, against numpy.

The film feed of ``examples/flow_wrapper.toml`` has one segment bound to the
cyclogram (a modified-sine index) whose change of angle the next dwell takes up.
Its RMS bound (``laws()[2]`` of the machine kind, the law the machine's sweeps call
per speed) is, at each speed, the smallest angle β such that the motor's RMS
torque over the cycle holds at every longer angle the dwell can give
(``rust/core/src/servo/rms.rs``): the highest violation on a geometric grid of
2048 angles down from β_max, refined by bisection.

The energy over the cycle is β·S(ω²/β²) + hold + F(ω²), where S and F are sums of
squared motor torques over samples, each a line in x whose coefficients switch
once (the efficiency's side of the power flow): a piecewise quadratic in x. The
peer (:func:`numpy_rms`) uses that structure as a numpy user would: the breaks
sorted and the coefficients prefix-summed once, then the whole (speeds × grid)
energy table by ``searchsorted`` and the bisection vectorised over the speeds.
The samples are the program's own values (``Program.evaluate``) on a uniform grid
per segment; cyclomech samples each piece of the law, so the two agree to the
quadrature's error (:func:`test_numpy_agrees`: 1e-6 relative, outside the timing).

The outputs are a few kB: the memory-page state (fresh or reused) does not enter.
Default run (``--benchmark-disable`` in addopts): each benchmark once. Timings::

    python -m pytest benches/bench_servo_rms.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

Array = npt.NDArray[np.float64]
GROUP = "servo RMS bound, film feed of flow_wrapper.toml (per speed)"
EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "flow_wrapper.toml"
N_SPEEDS = 1000
GRID = 2048  # rms.rs's RMS_GRID
SAMPLES = 3072  # the peer's intervals per segment


def problem(n_speeds: int = N_SPEEDS) -> tuple[Any, Array]:
    """The film feed's machine kind and distinct speeds [rpm]."""
    feed = cm.Machine.from_toml(EXAMPLE).mechanisms["film feed"]
    return feed, np.linspace(40.0, 240.0, n_speeds)


def _samples(program: Any, start: float, angle: float, n: int) -> tuple[Array, Array, Array]:
    """θ [rad] at n uniform intervals over a segment (ends taken just inside),
    s′ and s″ there, and the trapezoid weights [rad]."""
    u = np.linspace(0.0, 1.0, n + 1)
    u[0], u[-1] = 1e-12, 1.0 - 1e-12
    ev = program.evaluate(start + u * angle)
    w = np.full(n + 1, angle / n)
    w[0] = w[-1] = 0.5 * angle / n
    return ev.v, ev.a, w


def peer_inputs(feed: Any) -> dict[str, Any]:
    """What the peer starts from: the drive's numbers at the load shaft and the
    samples of the bound segment (per unit of its angle) and of the fixed ones."""
    ax = feed.axis
    load, gear, motor = ax.load, ax.gearbox, ax.motor
    r = load.lead_m / (2 * math.pi)  # m per radian of the rollers
    segs = ax.program.segments
    angles = np.radians([s.angle_deg for s in segs])
    starts = np.concatenate([[0.0], np.cumsum(angles)[:-1]])
    bound, dwell = 0, 1  # the index and the dwell that takes up its change
    v, a, w = _samples(ax.program, starts[bound], angles[bound], SAMPLES)
    b0 = angles[bound]
    fixed = [_samples(ax.program, starts[k], angles[k], SAMPLES) for k in range(2, len(segs))]
    return {
        # The segment at angle β: φ″ = acc·x with x = ω²/β², acc = s″·β₀²/r
        # (its shape at angle β₀); of φ′ only the sign matters (the power's side).
        "seg": (a * b0 * b0 / r, v / r, w / b0),
        # The fixed segments: φ″ = s″/r per rad² (times x = ω²), φ′ = s′/r.
        "fixed": (
            np.concatenate([f[1] for f in fixed]) / r,
            np.concatenate([f[0] for f in fixed]) / r,
            np.concatenate([f[2] for f in fixed]),
        ),
        "j_load": load.mass_kg * r * r,
        "t_ext": load.force_n * r,
        "eta": load.efficiency * gear.efficiency,
        "ratio": gear.ratio,
        "j_drive": motor.inertia_kg_m2 + gear.inertia_kg_m2,
        "rated": motor.rated_torque_nm,
        "angle": b0,
        "dwell": angles[dwell],
    }


def _square_sum(p: dict[str, Any], acc: Array, moving: Array, w: Array) -> tuple[Array, Array]:
    """Σ w·T_m(x)² as a piecewise quadratic: the breaks (B,) and (3, B+1) coefficients."""
    slope, t = p["j_load"] * acc, p["t_ext"]

    def square(sign: Array) -> Array:
        k = np.where(sign * moving < 0, p["eta"] / p["ratio"], 1 / (p["ratio"] * p["eta"]))
        q = k * t
        pp = p["j_drive"] * p["ratio"] * acc + k * slope
        return np.stack([w * pp * pp, 2 * w * pp * q, w * q * q])

    with np.errstate(divide="ignore", invalid="ignore"):
        cross = -t / slope
    has = (cross > 0) & np.isfinite(cross)
    below = square(np.where(has, t, slope + t))
    step = square(slope) - below
    order = np.argsort(cross[has])
    base = below.sum(axis=1)
    coef = np.concatenate([base[:, None], base[:, None] + np.cumsum(step[:, has][:, order], 1)], 1)
    return cross[has][order], coef


def _at(sq: tuple[Array, Array], x: Array) -> Array:
    c = sq[1][:, np.searchsorted(sq[0], x, side="right")]
    out: Array = (c[0] * x + c[1]) * x + c[2]
    return out


def numpy_rms(p: dict[str, Any], rpm: Array) -> Array:
    """The RMS bound [deg] at each speed (inf where no angle will do)."""
    w2 = (np.asarray(rpm) * math.pi / 30) ** 2
    seg, fixed = _square_sum(p, *p["seg"]), _square_sum(p, *p["fixed"])
    hold = p["t_ext"] / (p["ratio"] * p["eta"])
    top, budget = p["angle"] + p["dwell"], p["rated"] ** 2 * 2 * math.pi
    f = _at(fixed, w2)[:, None]

    def fails(beta: Array) -> Array:
        e = beta * _at(seg, w2[:, None] / beta**2) + (top - beta) * hold**2 + f
        return e > budget

    grid = top * (1e-9 ** (1 / GRID)) ** np.arange(GRID + 1)
    bad = fails(np.broadcast_to(grid, (w2.size, GRID + 1)))
    first = np.where(bad[:, 1:].any(1), bad[:, 1:].argmax(1) + 1, 0)
    lo, hi = grid[first][:, None], grid[np.maximum(first - 1, 0)][:, None]
    while np.any(hi - lo > 1e-13 * hi):
        mid = 0.5 * (lo + hi)
        f_mid = fails(mid)
        lo, hi = np.where(f_mid, mid, lo), np.where(f_mid, hi, mid)
    out = np.degrees(hi[:, 0])
    out[first == 0] = 0.0
    out[bad[:, 0]] = np.inf
    return out


def test_numpy_agrees() -> None:
    feed, rpm = problem(200)
    got = feed.laws()[2](rpm)
    want = numpy_rms(peer_inputs(feed), rpm)
    assert np.isfinite(got).sum() > 100 and np.isinf(got).sum() > 10  # both regimes
    np.testing.assert_array_equal(np.isinf(got), np.isinf(want))
    ok = np.isfinite(got)
    np.testing.assert_allclose(got[ok], want[ok], rtol=1e-6)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_rms_cyclomech(benchmark, monkeypatch, threads: int) -> None:  # type: ignore[no-untyped-def]
    feed, rpm = problem()
    law = feed.laws()[2]
    monkeypatch.setenv("CYCLOMECH_THREADS", str(threads))
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"laws()[2](rpm), {N_SPEEDS} speeds, {threads} thr"
    benchmark.extra_info["items"] = N_SPEEDS
    r = benchmark(law, rpm)
    assert r.shape == rpm.shape


@pytest.mark.benchmark(group=GROUP)
def test_rms_numpy(benchmark) -> None:  # type: ignore[no-untyped-def]
    feed, rpm = problem()
    p = peer_inputs(feed)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "piecewise quadratic, (speeds x grid) table, vector bisection"
    benchmark.extra_info["items"] = N_SPEEDS
    r = benchmark(numpy_rms, p, rpm)
    assert r.shape == rpm.shape
