"""The impact kernels (Duhamel integral, peak-only first rebound) against scipy, numpy,
sdof and eqsig, in one run.

The oscillator throughout: 297 Hz, ζ = 0.05 (varied where said), m = 7.4 g, from
rest, struck by the impact pulse F·(1 − t/τ) on [0, τ], τ = 0.65 ms, then zero (the
force jumps to F at t = 0). The grid: 10 000 steps of h = 2 µs (20 ms, six periods),
τ on the 325th sample. An error is max |q − q_ref| / max |q_ref| over the whole
history; for full histories q_ref is the closed form (:func:`closed_form`: step and
ramp responses, then free vibration; 2e-15 against mpmath), for peaks cyclomech's
first_rebound. Each row's error is appended to its label when timed, and every peer
is checked against cyclomech on the timed input in every run (benchmarks disabled
too).

Groups (each prints one ratio table; ``cyclomech`` rows are the references):

- one case: ``cm.impact.duhamel`` (5e-14; a chunked scan in vector lanes since
  issue 20, see BENCHMARKS.md) against ``scipy.signal.lsim`` (state space,
  its default ``interp=True``: the same exact first-order-hold recurrence, from the
  matrix exponential, stepped in a Python loop; 2e-13). So at equal step count lsim
  is as accurate, and the ratio is one at equal accuracy: neither pays for the jump
  at t = 0, as under a first-order hold the force is linear between samples from
  t[0] on, F at 0⁺ (lsim's zero-order hold, ``interp=False``, is off by 3e-3).
  Also ``scipy.signal.lfilter`` on the exact FOH recurrence as a 2nd-order IIR
  filter (:func:`foh_arma`; its first two outputs set by hand, as the filter's zero
  state would ramp the force up over the step before t = 0; 3e-11, the direct
  form's coefficients round with 2 − |a₁| ≈ (ωh)²), sdof's ``integrate`` (Newmark
  average acceleration in C: second order, 1e-5, its period (ωh)²/12 too long over
  six periods) and eqsig's ``nigam_and_jennings_response`` (cyclomech's recurrence
  in a Python loop over time steps, vectorised over periods; 1e-11, its gains
  cancel to O((ωh)²)).
- 1000 cases (amplitude 1…6 N, ζ 0.01…0.1) × 10 000 steps, full histories:
  ``duhamel_batch``, two threads and one (5e-13: at ζ ≈ 0.014 the recurrence's
  rounding builds up over the 10 000 steps), against batched FFT convolution with
  numpy (:func:`numpy_fft_batch`: ``np.fft.rfft`` of each case's exact FOH impulse
  response, in closed form, times that of the forces, 100 cases per chunk, the
  jump at t = 0 by the half hat; 6e-15, the pulse included. The plain rectangle
  rule, h·Σ f_k·g(t − t_k), is off by 3e-3, all but 4e-6 of it from weighing the
  jump's first sample as a full step), the lfilter loop over cases (1e-10: poles
  closer to 1 at small ζ) and sdof's integrate looped over cases (3e-5). eqsig
  vectorises over the periods of one record, not over records: 1000 cases are
  1000 of its Python loops (~80 s), timed only with ``CYCLOMECH_BENCH_FULL=1``.
  lsim is left out: 1000 cases as one block-diagonal system would step a
  2000-state matrix product. Also numpy's ``forces * 1.0``, not a solver: the
  memory traffic any tool returning the histories as a new array pays. And the
  same two without the fresh array (issue 20, "no fresh-page tax"):
  ``duhamel_batch(..., out=buf)`` into a reused buffer (bit for bit the fresh
  call's results) and its floor ``np.multiply(forces, 1.0, out=buf)``; a new
  80 MB array's pages are faulted in and zeroed by the OS on first touch.
- peak only, 1e6 cases (amplitude and ζ as above, the 3-point pulse F, F/2 at τ,
  then 0): ``first_rebound`` (O(breakpoints), exact) against
  :func:`numpy_first_max`, the exact FOH recurrence vectorised over the cases and
  stepped on the 2 µs grid until every case has turned (~560 steps), the turn
  refined with q̇ linear over its step (7e-10 in q, 2e-10 s in time).
- that first rebound for 1000 of the cases, one thread, against their full
  histories (``duhamel_batch`` on the 10 000-step grid with τ repeated for the
  jump; the search for the peak not timed): peak-only against full history per case.
- ``StopImpact.example().rebound`` over 1000 speeds × 100 phase angles (1e5
  impacts) in one call, against :func:`numpy_first_max` on the same impulses and
  pulse (grid τ/333; 2e-10).

Measured (AMD EPYC, 2 cores; medians; ratios to cyclomech on two threads / one):
one case 37 µs: lsim 1026x, lfilter 5.6x (63 of its 205 µs are lfilter itself, the
rest numpy setting up one case's coefficients), sdof 7.2x, eqsig 2233x. Batch 12 /
19 ms: numpy FFT 50x / 32x, lfilter 8.5x / 5.4x, sdof 22x / 14x; numpy's
``forces * 1.0`` (the memory floor: read the forces, write a new array of their
size) 12 ms. With a reused ``out=`` (issue 20, Intel Xeon, 2 cores; three runs,
load 2.3-2.5, one thread): 13.4 ms against 20.1 ms fresh (1.5x), numpy's
reused-buffer floor 11.9 ms and its fresh floor 17.6 ms. first_rebound 1e6 cases
in 0.48 / 0.93 s (2.1e6 / 1.1e6 cases/s): numpy 4.4x / 2.3x; per case 0.93 µs,
21x less than the full history's 19 µs. StopImpact 60 / 117 ms: numpy 4.7x / 2.4x.

Issue 37's row (:func:`batch_ratio_table`): the batch against its memory floors,
one thread, interleaved rounds, both page states::

    taskset -c 1 python benches/bench_impact.py

sdof and eqsig are optional (``pip install sdof eqsig``): their rows skip when not
installed. Default test run (``--benchmark-disable`` in addopts): each benchmark
once, with every check, about ten seconds; timed, about 25 s::

    python -m pytest benches/bench_impact.py --benchmark-enable -q -p no:cacheprovider
    CYCLOMECH_BENCH_FULL=1 python -m pytest benches/bench_impact.py --benchmark-enable -q
"""

from __future__ import annotations

import math
import os
from importlib import metadata
from types import ModuleType
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
import scipy.fft
import scipy.signal
from _timing import page_states, print_states, timed_run
from numpy.testing import assert_array_equal

Array = npt.NDArray[np.float64]

FULL = os.environ.get("CYCLOMECH_BENCH_FULL", "") not in ("", "0")
full_only = pytest.mark.skipif(
    not FULL, reason="eqsig over 1000 cases takes ~80 s: CYCLOMECH_BENCH_FULL=1"
)

# --- the oscillator, the pulse and the grid -------------------------------------------

OMEGA = 2 * math.pi * 297.0  # [rad/s]
ZETA = 0.05
MASS = 7.4e-3  # [kg]
F_PEAK = 3.5  # [N], about the example lifter's mean impact force at 280 rpm
N_STEPS = 10_000
H = 2e-6  # [s]
T = H * np.arange(N_STEPS + 1)  # 20 ms
TAU = float(T[325])  # 0.65 ms, on the grid
N_CASES = 1000
N_PEAKS = 1_000_000


def _label(benchmark, tool: str, what: str) -> None:
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


def _report(benchmark, err: float, against: str = "exact") -> None:
    """Append the row's accuracy to its label (the ratio table prints it)."""
    benchmark.extra_info["what"] += f"; err {err:.1g} vs {against}"


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "?"


def rel_err(q: Array, ref: Array) -> float:
    """max |q − ref| / max |ref|."""
    return float(np.abs(q - ref).max() / np.abs(ref).max())


def decaying(t: Array, amp: Any) -> Array:
    """The pulse amp·(1 − t/τ) on [0, τ], zero after, sampled at ``t``; (B, N) for amp (B,)."""
    return np.multiply.outer(amp, np.clip(1.0 - t / TAU, 0.0, None))


def closed_form(t: Array, amp: Any, zeta: Any, omega: float = OMEGA, mass: float = MASS) -> Array:
    """The exact response from rest to :func:`decaying`, in closed form: F·(step − ramp/τ)
    up to τ (the step and ramp responses of m·q̈ + 2ζωm·q̇ + ω²m·q), free vibration
    from the state at τ after. amp, zeta scalars or (B,); returns (N,) or (B, N).
    (Against mpmath at 40 digits: 2e-15 of the peak.)"""
    scalar = np.ndim(amp) == 0 and np.ndim(zeta) == 0
    amp, zeta = np.atleast_1d(amp)[:, None], np.atleast_1d(zeta)[:, None]
    k, s = mass * omega**2, zeta * omega
    wd = omega * np.sqrt(1.0 - zeta**2)

    def during(x: Array) -> tuple[Array, Array]:
        e, c, sn = np.exp(-s * x), np.cos(wd * x), np.sin(wd * x)
        step = (1.0 - e * (c + s / wd * sn)) / k
        ramp = (x - 2 * zeta / omega + e * (2 * zeta / omega * c + (2 * zeta**2 - 1) / wd * sn)) / k
        dstep = omega**2 / wd * e * sn / k
        return amp * (step - ramp / TAU), amp * (dstep - step / TAU)

    n_in = int(np.searchsorted(t, TAU, side="right"))
    q = np.empty(np.broadcast_shapes(amp.shape, zeta.shape)[:1] + t.shape)
    q[:, :n_in] = during(t[:n_in])[0]
    q_tau, v_tau = during(np.array([TAU]))
    ez = np.exp((t[n_in:] - TAU) * (-s + 1j * wd))  # e^{−σu}·(cos + i·sin)(ω_d·u)
    q[:, n_in:] = q_tau * ez.real + (v_tau + s * q_tau) / wd * ez.imag
    return q[0] if scalar else q


# --- exact first-order-hold discretisation, for the numpy and scipy peers -------------


def foh_gains(omega: Any, zeta: Any, mass: float, h: float) -> tuple[Array, ...]:
    """Input gains (g0q, g0v, g1q, g1v) of the exact FOH step
    x_{k+1} = Φ·x_k + g0·f_k + g1·f_{k+1}, x = (q, q̇): g0 + g1 = Σ Aⁿb·hⁿ⁺¹/(n+1)!,
    g1 = Σ Aⁿb·hⁿ⁺¹/(n+2)!, A = [[0, 1], [−ω², −2ζω]], b = (0, 1/m); the series
    is summed to rounding (ωh ≪ 1 here; no cancellation, unlike the closed forms)."""
    omega, zeta = np.broadcast_arrays(np.asarray(omega, float), np.asarray(zeta, float))
    assert (omega * h < 0.1).all(), "the series is for small steps"
    aq, av = np.zeros(omega.shape), np.full(omega.shape, 1.0 / mass)  # Aⁿb
    sq, sv, g1q, g1v = (np.zeros(omega.shape) for _ in range(4))
    c1 = c2 = h  # hⁿ⁺¹/(n+1)!, hⁿ⁺¹/(n+2)!
    c2 /= 2
    for n in range(30):
        sq += c1 * aq
        sv += c1 * av
        g1q += c2 * aq
        g1v += c2 * av
        aq, av = av, -(omega**2) * aq - 2 * zeta * omega * av
        c1 *= h / (n + 2)
        c2 *= h / (n + 3)
        if c1 * np.abs(omega).max() ** (n + 1) < 1e-18 * h:
            break
    return sq - g1q, sv - g1v, g1q, g1v


def transition(omega: Any, zeta: Any, h: float) -> tuple[Array, ...]:
    """Φ = exp(A·h): (Φ11, Φ12, Φ21, Φ22), underdamped."""
    s, wd = zeta * omega, omega * np.sqrt(1.0 - zeta**2)
    e, c, sn = np.exp(-s * h), np.cos(wd * h), np.sin(wd * h)
    return e * (c + s / wd * sn), e * sn / wd, -(omega**2) * e * sn / wd, e * (c - s / wd * sn)


def foh_arma(omega: Any, zeta: Any, mass: float, h: float) -> tuple[Array, ...]:
    """The FOH recurrence as an IIR filter q = (b/a)·f, b, a (B, 3): eliminating the
    velocity, a = (1, −tr Φ, det Φ), b = (g1q, g0q − Φ22·g1q + Φ12·g1v,
    Φ12·g0v − Φ22·g0q). It holds from the third sample on; the filter's zero state
    would be a force ramping up from 0 at t = −h, so :func:`lfilter_batch` sets q0,
    q1 itself (from g0q, g1q, returned too) and starts there."""
    g0q, g0v, g1q, g1v = foh_gains(omega, zeta, mass, h)
    p11, p12, p21, p22 = transition(omega, zeta, h)
    b = np.stack([g1q, g0q - p22 * g1q + p12 * g1v, p12 * g0v - p22 * g0q], axis=-1)
    a = np.stack([np.ones_like(p11), -(p11 + p22), p11 * p22 - p12 * p21], axis=-1)
    return np.atleast_2d(b), np.atleast_2d(a), np.atleast_1d(g0q), np.atleast_1d(g1q)


# --- peers: full histories ------------------------------------------------------------


def lsim_response(
    t: Array, force: Array, omega: float, zeta: float, mass: float, interp: bool = True
) -> Array:
    """scipy's lsim on the state-space oscillator, by default with its linear
    interpolation of the input (FOH); ``interp=False``: zero-order hold."""
    sys = scipy.signal.StateSpace(
        [[0.0, 1.0], [-(omega**2), -2 * zeta * omega]], [[0.0], [1.0 / mass]], [[1.0, 0.0]], [[0.0]]
    )
    return scipy.signal.lsim(sys, force, t, interp=interp)[1]


def lfilter_batch(t: Array, forces: Array, omega: Any, zeta: Any, mass: float) -> Array:
    """scipy.signal.lfilter per case (its coefficients differ with ζ), on the exact FOH
    recurrence; q0 = 0 and q1 from the gains, the filter state from them (lfiltic)."""
    forces = np.atleast_2d(forces)
    nb = forces.shape[0]
    h = float(t[1] - t[0])
    omega, zeta = np.broadcast_to(omega, (nb,)), np.broadcast_to(zeta, (nb,))
    b, a, g0q, g1q = foh_arma(omega, zeta, mass, h)
    out = np.empty_like(forces)
    for k in range(nb):
        f = forces[k]
        q1 = g0q[k] * f[0] + g1q[k] * f[1]
        zi = scipy.signal.lfiltic(b[k], a[k], [q1, 0.0], [f[1], f[0]])
        out[k, 0], out[k, 1] = 0.0, q1
        out[k, 2:] = scipy.signal.lfilter(b[k], a[k], f[2:], zi=zi)[0]
    return out


def numpy_fft_batch(
    t: Array, forces: Array, omega: Any, zeta: Any, mass: float, chunk: int = 100
) -> Array:
    """Full histories by FFT convolution with numpy, ``chunk`` cases at a time.

    Under a first-order hold the force is Σ f_k·hat_k(t), so q_n = Σ f_k·g[n − k]
    with g the response to a unit hat: g[0] = g1q (its rising half), then the free
    vibration from Φ·g1 + g0 in closed form. The first sample carries only the
    falling half (the force jumps at t[0]): f_0's share is taken with the kernel of
    that half, the free vibration from g0, instead of g. Kernels per case (ζ
    varies), the forces' and the kernels' rfft, product, irfft."""
    n, h = t.size, float(t[1] - t[0])
    nb = forces.shape[0]
    omega, zeta = np.broadcast_to(omega, (nb,)), np.broadcast_to(zeta, (nb,))
    size = scipy.fft.next_fast_len(2 * n - 1, real=True)
    u = h * np.arange(n - 1)
    out = np.empty_like(forces)
    for start in range(0, nb, chunk):
        sl = slice(start, start + chunk)
        w, z = omega[sl, None], zeta[sl, None]
        g0q, g0v, g1q, g1v = (g[:, None] for g in foh_gains(w[:, 0], z[:, 0], mass, h))
        p11, p12, p21, p22 = transition(w, z, h)
        xq, xv = p11 * g1q + p12 * g1v + g0q, p21 * g1q + p22 * g1v + g0v
        s, wd = z * w, w * np.sqrt(1.0 - z**2)
        ez = np.exp(u * (-s + 1j * wd))  # e^{−σu}(cos + i sin) of ω_d·u
        kern = np.empty((w.shape[0], n))
        kern[:, 0] = g1q[:, 0]
        kern[:, 1:] = xq * ez.real + (xv + s * xq) / wd * ez.imag
        half = g0q * ez.real + (g0v + s * g0q) / wd * ez.imag  # g0's kernel, from 1 on
        f = forces[sl]
        q = np.fft.irfft(np.fft.rfft(f, size) * np.fft.rfft(kern, size), size)[:, :n]
        q -= f[:, :1] * kern
        q[:, 1:] += f[:, :1] * half
        out[sl] = q
    return out


def sdof_batch(sdof: ModuleType, t: Array, forces: Array, omega: float, zeta: Any, mass: float):
    """sdof's integrate per case: Newmark average acceleration in C."""
    forces = np.atleast_2d(forces)
    h = float(t[1] - t[0])
    zeta = np.broadcast_to(zeta, (forces.shape[0],))
    out = np.empty_like(forces)
    for k, f in enumerate(forces):
        out[k] = sdof.integrate(f, h, mass * omega**2, 2 * zeta[k] * omega * mass, mass)[0]
    return out


def eqsig_batch(eqsig_sdof: ModuleType, t: Array, forces: Array, omega: float, zeta: Any):
    """eqsig's Nigam-Jennings response per case. eqsig takes a ground acceleration
    and periods, with ω = 6.2831853/period (2π cut to 8 digits): the period passed is
    6.2831853/ω, so that its ω is ours; it returns −q for the acceleration +f/m, so f/m
    is passed for q."""
    forces = np.atleast_2d(forces)
    h = float(t[1] - t[0])
    zeta = np.broadcast_to(zeta, (forces.shape[0],))
    periods = np.array([6.2831853 / omega])
    out = np.empty_like(forces)
    for k, f in enumerate(forces):
        out[k] = eqsig_sdof.nigam_and_jennings_response(f / MASS, h, periods, float(zeta[k]))[0][0]
    return out


# --- peers: the first maximum ---------------------------------------------------------


def numpy_first_max(
    pulse_t: Array,
    pulse_f: Array,
    omega: float,
    zeta: Array,
    mass: float,
    v0: Any = 0.0,
    steps: int = 325,
    chunk: int = 65536,
    max_steps: int = 200_000,
) -> tuple[Array, Array]:
    """(time, q) of the first local maximum of each case, with numpy: the exact FOH
    recurrence vectorised over ``chunk`` cases and stepped in time from rest (q = 0,
    q̇ = ``v0``) until every case has turned; the turn, q̇ from > 0 to ≤ 0 within a
    step, refined with q̇ linear over the step. The pulse table (K,) with forces
    (B, K) (a repeated time is a jump) must have its breakpoints on a grid of step
    h = pulse_t[1]/``steps``; the force is held at its last value after it."""
    nb = pulse_f.shape[0]
    h = float(pulse_t[1]) / steps
    pieces = np.rint(np.diff(pulse_t) / h).astype(int)
    assert np.allclose(np.diff(pulse_t), pieces * h, rtol=0, atol=1e-9 * h), "off the grid"
    zeta = np.broadcast_to(zeta, (nb,))
    v0 = np.broadcast_to(np.asarray(v0, dtype=float), (nb,))
    out_t, out_q = np.full(nb, np.inf), np.zeros(nb)
    for start in range(0, nb, chunk):
        sl = slice(start, start + chunk)
        z, f = zeta[sl], pulse_f[sl]
        g0q, g0v, g1q, g1v = foh_gains(omega, z, mass, h)
        p11, p12, p21, p22 = transition(omega, z, h)
        # The force's share of step k_in of a piece from f_j with slope d per step:
        # g0·(f_j + d·k_in) + g1·(f_j + d·(k_in + 1)) = c + e·k_in.
        shares = []
        for j, n in enumerate(pieces):
            if n:
                d = (f[:, j + 1] - f[:, j]) / n
                shares.append(
                    (
                        n,
                        (g0q + g1q) * f[:, j] + g1q * d,
                        (g0q + g1q) * d,
                        (g0v + g1v) * f[:, j] + g1v * d,
                        (g0v + g1v) * d,
                    )
                )
        q, v = np.zeros(z.size), v0[sl].copy()
        tq, qq = out_t[sl], out_q[sl]
        todo = np.ones(z.size, dtype=bool)
        hold_q, hold_v = (g0q + g1q) * f[:, -1], (g0v + g1v) * f[:, -1]
        k, piece_start, queue = 0, 0, list(shares)
        while k < max_steps:
            if queue and k - piece_start == queue[0][0]:
                piece_start += queue.pop(0)[0]
            if queue:
                _, cq, eq, cv, ev = queue[0]
                k_in = k - piece_start
                qn = p11 * q + p12 * v + cq + eq * k_in
                vn = p21 * q + p22 * v + cv + ev * k_in
            else:
                qn = p11 * q + p12 * v + hold_q
                vn = p21 * q + p22 * v + hold_v
            turn = (v > 0) & (vn <= 0) & todo
            if turn.any():
                vt = v[turn]
                dt = vt / (vt - vn[turn]) * h
                tq[turn] = k * h + dt
                qq[turn] = q[turn] + 0.5 * vt * dt
                todo &= ~turn
            q, v = qn, vn
            k += 1
            if k % 32 == 0 and not todo.any():
                break
    return out_t, out_q


def history_first_max(t: Array, q: Array) -> tuple[Array, Array]:
    """(time, q) of each history's first local maximum of samples, refined by the
    parabola through it and its neighbours."""
    d = np.diff(q, axis=1)
    i = np.argmax((d[:, :-1] > 0) & (d[:, 1:] <= 0), axis=1) + 1
    rows = np.arange(q.shape[0])
    qm, q0, qp = q[rows, i - 1], q[rows, i], q[rows, i + 1]
    h = t[i + 1] - t[i]
    x = 0.5 * (qm - qp) / (qm - 2 * q0 + qp)
    return t[i] + x * h, q0 - 0.25 * (qm - qp) * x


# --- group 1: one case ----------------------------------------------------------------

GROUP_ONE = "duhamel: one case, 10 000 steps (297 Hz, zeta 0.05, decaying pulse 0.65 ms)"


@pytest.fixture(scope="module")
def one_case() -> dict[str, Array]:
    """The force, cyclomech's response and the closed form."""
    f = decaying(T, F_PEAK)
    q = cm.impact.duhamel(T, f, omega_n=OMEGA, zeta=ZETA, mass=MASS)
    exact = closed_form(T, F_PEAK, ZETA)
    assert rel_err(q, exact) <= 1e-12
    return {"f": f, "q": q, "exact": exact}


def check_one(benchmark, q: Array, case: dict[str, Array], tol: float) -> None:
    """A peer against cyclomech (≤ ``tol``); its error against the closed form goes
    into its label."""
    assert rel_err(q, case["q"]) <= tol
    _report(benchmark, rel_err(q, case["exact"]))


@pytest.mark.benchmark(group=GROUP_ONE)
def test_one_cyclomech(benchmark, one_case) -> None:
    _label(benchmark, "cyclomech", "impact.duhamel (exact FOH, Rust)")
    q = benchmark(cm.impact.duhamel, T, one_case["f"], omega_n=OMEGA, zeta=ZETA, mass=MASS)
    check_one(benchmark, q, one_case, 0.0)


@pytest.mark.benchmark(group=GROUP_ONE)
def test_one_lsim(benchmark, one_case) -> None:
    _label(benchmark, "scipy", "signal.lsim, state space, interp=True (FOH, Python loop)")
    q = benchmark(lsim_response, T, one_case["f"], OMEGA, ZETA, MASS)
    check_one(benchmark, q, one_case, 1e-11)


@pytest.mark.benchmark(group=GROUP_ONE)
def test_one_lfilter(benchmark, one_case) -> None:
    _label(benchmark, "scipy", "signal.lfilter on the FOH recurrence (IIR, 2nd order)")
    q = benchmark(lfilter_batch, T, one_case["f"], OMEGA, ZETA, MASS)[0]
    check_one(benchmark, q, one_case, 1e-9)


def _sdof_bound() -> float:
    """Newmark average acceleration's error here: its period is (ωh)²/12 too long,
    so the phase lags by ω·t_end·(ωh)²/12 at the end (x1.5 for the damping's share)."""
    return 1.5 * OMEGA * T[-1] * (OMEGA * H) ** 2 / 12


@pytest.mark.benchmark(group=GROUP_ONE)
def test_one_sdof(benchmark, one_case) -> None:
    sdof = pytest.importorskip("sdof")
    _label(benchmark, "sdof", f"sdof {_version('sdof')} integrate (Newmark avg. accel., C)")
    q = benchmark(sdof_batch, sdof, T, one_case["f"], OMEGA, ZETA, MASS)[0]
    check_one(benchmark, q, one_case, _sdof_bound())


@pytest.mark.benchmark(group=GROUP_ONE)
def test_one_eqsig(benchmark, one_case) -> None:
    eqs = pytest.importorskip("eqsig.sdof")
    _label(benchmark, "eqsig", f"eqsig {_version('eqsig')} Nigam-Jennings (Python loop)")
    q = benchmark(eqsig_batch, eqs, T, one_case["f"], OMEGA, ZETA)[0]
    check_one(benchmark, q, one_case, 1e-9)


def test_one_zero_order_hold_misses() -> None:
    """The first-order hold is what makes the jump at t = 0 exact on this grid: lsim's
    zero-order hold, the force held over each step, is off by the shift of h/2."""
    q = lsim_response(T, decaying(T, F_PEAK), OMEGA, ZETA, MASS, interp=False)
    assert 1e-3 < rel_err(q, closed_form(T, F_PEAK, ZETA)) < 1e-2


# --- group 2: 1000 cases, full histories ----------------------------------------------

GROUP_BATCH = f"duhamel_batch: {N_CASES} cases x {N_STEPS} steps, full histories"


def _cases(n: int, seed: int) -> tuple[Array, Array]:
    """Amplitudes 1…6 N and ζ 0.01…0.1."""
    rng = np.random.default_rng(seed)
    return rng.uniform(1.0, 6.0, n), rng.uniform(0.01, 0.1, n)


@pytest.fixture(scope="module")
def batch() -> dict[str, Any]:
    amp, zeta = _cases(N_CASES, 1)
    forces = decaying(T, amp)
    q = cm.impact.duhamel_batch(T, forces, OMEGA, zeta, MASS)
    exact = closed_form(T, amp, zeta)
    assert rel_err(q, exact) <= 1e-12
    return {"zeta": zeta, "forces": forces, "q": q, "exact": exact}


@pytest.mark.benchmark(group=GROUP_BATCH)
@pytest.mark.parametrize("threads", [2, 1])
def test_batch_cyclomech(benchmark, batch, threads) -> None:
    _label(benchmark, "cyclomech", f"impact.duhamel_batch, n_threads={threads}")
    args = (T, batch["forces"], OMEGA, batch["zeta"], MASS)
    kwargs = {"n_threads": threads}
    q = benchmark.pedantic(cm.impact.duhamel_batch, args=args, kwargs=kwargs, rounds=5)
    check_one(benchmark, q, batch, 0.0)


@pytest.fixture(scope="module")
def out_buffer(batch) -> Array:
    """A caller's (B, N) output, its pages already faulted in (as after a first call)."""
    return np.full_like(batch["forces"], np.nan)


@pytest.mark.benchmark(group=GROUP_BATCH)
@pytest.mark.parametrize("threads", [2, 1])
def test_batch_cyclomech_out(benchmark, batch, out_buffer, threads) -> None:
    """The same batch written into a reused ``out=`` buffer: no fresh pages to
    fault in and zero; bit for bit the fresh call's results."""
    _label(benchmark, "cyclomech", f"impact.duhamel_batch(out=reused), n_threads={threads}")
    args = (T, batch["forces"], OMEGA, batch["zeta"], MASS)
    kwargs = {"n_threads": threads, "out": out_buffer}
    q = benchmark.pedantic(cm.impact.duhamel_batch, args=args, kwargs=kwargs, rounds=5)
    assert q is out_buffer
    assert_array_equal(q.view(np.uint64), batch["q"].view(np.uint64))
    check_one(benchmark, q, batch, 0.0)


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_numpy_fft(benchmark, batch) -> None:
    _label(benchmark, "numpy", "FFT convolution, exact FOH kernels, 100 cases per chunk")
    args = (T, batch["forces"], OMEGA, batch["zeta"], MASS)
    q = benchmark.pedantic(numpy_fft_batch, args=args, rounds=3)
    check_one(benchmark, q, batch, 1e-11)
    pulse = slice(0, 326)  # its jump at t = 0 included
    assert rel_err(q[:, pulse], batch["q"][:, pulse]) <= 1e-12


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_lfilter(benchmark, batch) -> None:
    _label(benchmark, "scipy", "signal.lfilter on the FOH recurrence, loop over cases")
    args = (T, batch["forces"], OMEGA, batch["zeta"], MASS)
    q = benchmark.pedantic(lfilter_batch, args=args, rounds=3)
    check_one(benchmark, q, batch, 1e-8)


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_sdof(benchmark, batch) -> None:
    sdof = pytest.importorskip("sdof")
    _label(benchmark, "sdof", f"sdof {_version('sdof')} integrate (Newmark), loop over cases")
    args = (sdof, T, batch["forces"], OMEGA, batch["zeta"], MASS)
    q = benchmark.pedantic(sdof_batch, args=args, rounds=3)
    check_one(benchmark, q, batch, _sdof_bound())


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_memory_floor(benchmark, batch) -> None:
    """Not a solver: the least any tool returning new (B, N) histories does, read
    the forces and write a fresh array of their size (its pages faulted in)."""
    _label(benchmark, "numpy", "forces * 1.0, memory floor (read B*N, write new B*N)")
    q = benchmark.pedantic(np.multiply, args=(batch["forces"], 1.0), rounds=5)
    assert_array_equal(q, batch["forces"])


@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_memory_floor_out(benchmark, batch) -> None:
    """The floor for the ``out=`` rows: read the forces, write an existing array
    of their size (no page faults), ``np.multiply(forces, 1.0, out=buf)``."""
    _label(benchmark, "numpy", "forces * 1.0 into a reused out=, floor without fresh pages")
    buf = np.full_like(batch["forces"], np.nan)
    kwargs = {"out": buf}
    q = benchmark.pedantic(np.multiply, args=(batch["forces"], 1.0), kwargs=kwargs, rounds=5)
    assert q is buf
    assert_array_equal(q, batch["forces"])


def batch_ratio_table(rounds: int = 9) -> None:
    """Issue 37's measurement of ``duhamel_batch`` (1000 cases × 10 000 steps)
    against its memory floors: one thread (run under ``taskset -c 1``),
    interleaved rounds, both page states (an 80 MB array is mapped fresh by glibc
    whatever the state: ``new`` rows first-touch their pages in every call, ``out=``
    rows never). Checked first: the batch against the closed form (1e-12) and its
    ``out=`` call bit for bit. Floors: ``np.copyto`` (read B·N, write B·N: glibc's
    memcpy, with non-temporal stores at this size), ``np.multiply(forces, 1.0)``
    (the same traffic through a ufunc loop's ordinary stores) and ``fill`` (write
    only)."""
    amp, zeta = _cases(N_CASES, 1)
    forces = decaying(T, amp)
    args = (T, forces, OMEGA, zeta, MASS)
    q = cm.impact.duhamel_batch(*args, n_threads=1)
    assert rel_err(q, closed_form(T, amp, zeta)) <= 1e-12
    buf, floor_buf = np.full_like(forces, np.nan), np.full_like(forces, np.nan)
    assert cm.impact.duhamel_batch(*args, n_threads=1, out=buf) is buf
    assert_array_equal(buf.view(np.uint64), q.view(np.uint64))
    tools = {
        "duhamel_batch, new array": lambda: cm.impact.duhamel_batch(*args, n_threads=1),
        "duhamel_batch, out=": lambda: cm.impact.duhamel_batch(*args, n_threads=1, out=buf),
        "floor np.copyto, new array": lambda: np.copyto(np.empty_like(forces), forces),
        "floor np.copyto, existing": lambda: np.copyto(floor_buf, forces),
        "floor np.multiply(f, 1.0), new array": lambda: np.multiply(forces, 1.0),
        "floor np.multiply(f, 1.0), existing": lambda: np.multiply(forces, 1.0, out=floor_buf),
        "floor fill (write only), new array": lambda: np.empty_like(forces).fill(1.0),
        "floor fill (write only), existing": lambda: floor_buf.fill(1.0),
    }
    new, out = "duhamel_batch, new array", "duhamel_batch, out="
    print_states(
        f"duhamel_batch {N_CASES} x {N_STEPS + 1}, one thread",
        page_states(tools, rounds),
        1e-3,
        "ms",
        {
            "floor np.copyto, new array": new,
            "floor np.copyto, existing": out,
            "floor np.multiply(f, 1.0), new array": new,
            "floor np.multiply(f, 1.0), existing": out,
            "floor fill (write only), new array": new,
            "floor fill (write only), existing": out,
        },
    )


def test_batch_ratio_table(request: pytest.FixtureRequest) -> None:
    """The issue-37 table in timed runs (``taskset -c 1 python benches/bench_impact.py``)."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    batch_ratio_table(5)


@full_only
@pytest.mark.benchmark(group=GROUP_BATCH)
def test_batch_eqsig(benchmark, batch) -> None:
    eqs = pytest.importorskip("eqsig.sdof")
    _label(benchmark, "eqsig", f"eqsig {_version('eqsig')} Nigam-Jennings, loop over cases")
    args = (eqs, T, batch["forces"], OMEGA, batch["zeta"])
    q = benchmark.pedantic(eqsig_batch, args=args, rounds=1)
    check_one(benchmark, q, batch, 1e-9)


def test_rectangle_rule_misses_the_jump() -> None:
    """What the FFT peer's exact kernels buy: the plain rectangle rule,
    q_n = h·Σ f_k·g(t_n − t_k) with g the impulse response, weighs the jump's first
    sample as a full step of F and is off by 3e-3 here, about ωh; weighing it by
    h/2 instead leaves 4e-6."""
    amp, zeta = _cases(10, 1)
    forces = decaying(T, amp)
    s, wd = zeta[:, None] * OMEGA, OMEGA * np.sqrt(1 - zeta[:, None] ** 2)
    g = H * np.exp(-s * T) * np.sin(wd * T) / (MASS * wd)
    size = scipy.fft.next_fast_len(2 * T.size - 1, real=True)
    q = np.fft.irfft(np.fft.rfft(forces, size) * np.fft.rfft(g, size), size)[:, : T.size]
    exact = cm.impact.duhamel_batch(T, forces, OMEGA, zeta, MASS)
    assert 0.3 * OMEGA * H < rel_err(q, exact) < OMEGA * H
    assert rel_err(q - 0.5 * forces[:, :1] * g, exact) < 1e-5


# --- group 3: peak only, 1e6 cases ----------------------------------------------------

GROUP_PEAK = f"first_rebound: {N_PEAKS:.0e} cases, 3-point pulse (F, F/2 at tau, 0)"
PULSE_T = np.array([0.0, TAU, TAU])
PULSE_SHAPE = np.array([1.0, 0.5, 0.0])


#: Cases of the peak group when benchmarks are off: numpy's recurrence over 1e6 cases
#: costs ~5 CPU-s of the default run and checks nothing 1e5 cases (two of its chunks,
#: both thread counts of the kernel) do not; timed, the group runs :data:`N_PEAKS`.
SMOKE_PEAKS = 100_000


@pytest.fixture(scope="module")
def peaks(request: pytest.FixtureRequest) -> dict[str, Any]:
    amp, zeta = _cases(N_PEAKS if timed_run(request.config) else SMOKE_PEAKS, 2)
    forces = np.multiply.outer(amp, PULSE_SHAPE)
    r = cm.impact.first_rebound(PULSE_T, forces, OMEGA, zeta, MASS)
    assert np.isfinite(r.time).all() and (r.q > 0).all()
    return {"zeta": zeta, "forces": forces, "ref": r}


def check_first_max(time: Array, q: Array, ref: cm.impact.Rebound, h: float) -> float:
    """The peer's first maxima against cyclomech's; returns the relative error in q."""
    err = rel_err(q, ref.q)
    assert err <= 1e-8
    assert np.abs(time - ref.time).max() <= 1e-3 * h
    return err


@pytest.mark.benchmark(group=GROUP_PEAK)
@pytest.mark.parametrize("threads", [2, 1])
def test_peak_cyclomech(benchmark, peaks, threads) -> None:
    _label(benchmark, "cyclomech", f"impact.first_rebound (peak only), n_threads={threads}")
    args = (PULSE_T, peaks["forces"], OMEGA, peaks["zeta"], MASS)
    r = benchmark.pedantic(
        cm.impact.first_rebound, args=args, kwargs={"n_threads": threads}, rounds=5
    )
    assert np.array_equal(r.q, peaks["ref"].q)


@pytest.mark.benchmark(group=GROUP_PEAK)
def test_peak_numpy(benchmark, peaks) -> None:
    _label(benchmark, "numpy", "FOH recurrence over cases, stepped on the 2 us grid")
    args = (PULSE_T, peaks["forces"], OMEGA, peaks["zeta"], MASS)
    time, q = benchmark.pedantic(numpy_first_max, args=args, rounds=1)
    _report(benchmark, check_first_max(time, q, peaks["ref"], H), "cyclomech")


# --- group 3b: peak only against full history, per case -------------------------------

GROUP_PER_CASE = f"first rebound of {N_CASES} cases, one thread: peak only vs full history"


@pytest.fixture(scope="module")
def per_case(peaks) -> dict[str, Any]:
    """The first 1000 cases of ``peaks``, also as full histories on the 10 000-step
    grid (τ repeated: the jump from F/2 to 0)."""
    t = np.insert(T, 326, TAU)
    zeta, forces = peaks["zeta"][:N_CASES], peaks["forces"][:N_CASES]
    hist = np.zeros((N_CASES, t.size))
    hist[:, :326] = np.multiply.outer(forces[:, 0], 1.0 - 0.5 * T[:326] / TAU)
    ref = cm.impact.first_rebound(PULSE_T, forces, OMEGA, zeta, MASS)
    q = cm.impact.duhamel_batch(t, hist, OMEGA, zeta, MASS)
    check_first_max(*history_first_max(T, np.delete(q, 326, axis=1)), ref, H)  # τ once
    return {"t": t, "hist": hist, "zeta": zeta, "forces": forces, "ref": ref}


@pytest.mark.benchmark(group=GROUP_PER_CASE)
def test_per_case_peak(benchmark, per_case) -> None:
    _label(benchmark, "cyclomech", "impact.first_rebound (peak only)")
    args = (PULSE_T, per_case["forces"], OMEGA, per_case["zeta"], MASS)
    r = benchmark(cm.impact.first_rebound, *args, n_threads=1)
    assert np.array_equal(r.q, per_case["ref"].q)


@pytest.mark.benchmark(group=GROUP_PER_CASE)
def test_per_case_history(benchmark, per_case) -> None:
    _label(
        benchmark,
        "cyclomech full history",
        f"impact.duhamel_batch on {N_STEPS} steps (the peak search not timed)",
    )
    args = (per_case["t"], per_case["hist"], OMEGA, per_case["zeta"], MASS)
    benchmark.pedantic(cm.impact.duhamel_batch, args=args, kwargs={"n_threads": 1}, rounds=5)


# --- group 4: StopImpact.rebound over speeds x phase angles ---------------------------

N_RPM, N_PHASE = 1000, 100
GROUP_STOP = f"StopImpact.example().rebound: {N_RPM} speeds x {N_PHASE} phase angles"


@pytest.fixture(scope="module")
def stop() -> dict[str, Any]:
    lifter = cm.impact.StopImpact.example()
    rpm = np.linspace(200.0, 500.0, N_RPM)[:, None]
    phase = np.linspace(20.0, 60.0, N_PHASE)
    a = lifter.rebound(rpm, phase)
    assert a.shape == (N_RPM, N_PHASE) and (a > 0).all()
    doc = lifter.rebound([280, 320, 370, 420], 40.0)  # the example's documented rebounds
    assert np.allclose(doc * 1e3, [0.070, 0.080, 0.093, 0.105], rtol=0, atol=5e-4)
    return {"lifter": lifter, "rpm": rpm, "phase": phase, "a": a}


def numpy_rebound(lifter: cm.impact.StopImpact, rpm: Array, phase: Array) -> Array:
    """The same model in numpy: the oscillator leaves the stop with −v0 and takes the
    decaying pulse of impulse m·(1 + k)·v0; the rebound is its first maximum
    (:func:`numpy_first_max`, on the grid τ/333 ≈ 2 µs)."""
    assert lifter.pulse == "decaying" and lifter.model == "pulse"
    v0 = np.asarray(lifter.impact_speed(rpm, phase), dtype=float)
    tau = lifter.contact_time
    impulse = lifter.mass * (1.0 + lifter.restitution) * v0.ravel()
    forces = np.multiply.outer(impulse, [2.0 / tau, 0.0])  # unit impulse: 2/τ falling to 0
    zeta = np.full(v0.size, lifter.zeta)
    _, q = numpy_first_max(
        np.array([0.0, tau]), forces, lifter.omega_free, zeta, lifter.mass, -v0.ravel(), 333
    )
    return q.reshape(v0.shape)


@pytest.mark.benchmark(group=GROUP_STOP)
@pytest.mark.parametrize("threads", [2, 1])
def test_stop_cyclomech(benchmark, stop, threads) -> None:
    _label(benchmark, "cyclomech", f"StopImpact.rebound, one call, n_threads={threads}")
    a = benchmark(stop["lifter"].rebound, stop["rpm"], stop["phase"], n_threads=threads)
    assert np.array_equal(a, stop["a"])


@pytest.mark.benchmark(group=GROUP_STOP)
def test_stop_numpy(benchmark, stop) -> None:
    _label(benchmark, "numpy", "FOH recurrence over cases, stepped on a 2 us grid")
    args = (stop["lifter"], stop["rpm"], stop["phase"])
    a = benchmark.pedantic(numpy_rebound, args=args, rounds=3)
    err = rel_err(a, stop["a"])
    _report(benchmark, err, "cyclomech")
    assert err <= 1e-8


if __name__ == "__main__":
    import sys

    batch_ratio_table(int(sys.argv[1]) if len(sys.argv) > 1 else 9)
