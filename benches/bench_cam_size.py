"""Cam sizing: cyclomech's smallest base radius and its radius ↔ phase-angle
trade-off against numpy, the same rules.

The cam: a translating radial roller (r_r = 10 mm) on a cycloidal rise of 20 mm
over 120°, dwell 60°, return 120°, dwell 60°; a 2 kg follower on a 5 kN/m spring
with 100 N preload; steel on steel, 10 mm wide; limits 30° pressure angle and
σ_H ≤ 750 MPa. Up to ~1350 rpm the pressure angle binds, above it the Hertz
stress (``test_both_criteria_bind``).

**Sizing** (``cm.synthesis.cam_size``, one speed per call as its API takes, 20
speeds 200–1440 rpm, base radius searched over [r_r·1.001, 0.2 m]) against
:func:`numpy_size`, all speeds at once, and the same one speed per call. The
criteria in closed form (s, s′, s″ of the cycloidal law; the pitch curve's
pressure angle and curvature; the normal force from inertia, spring and preload
over cos φ; the Hertz line-contact stress, +∞ on an undercut profile); each
segment's worst value from 257 points, then 129 points over the two cells
around the sampled worst, then the parabola through the best of those and its
neighbours (the kernel's grid-and-Brent search done a simpler way to the same
accuracy, ~1e-12); the dwells in closed form at one point. Then the kernel's
rule: the same 64 radii geometrically spaced (the speed-free geometry once per
radius, the stress broadcast over (radius, speed, angle)), the smallest
admissible one, and the crossing below it by Illinois' regula falsi vectorised
over the speeds (a geometric bisection step where an end is +∞), to 1e-13
relative. The radii agree to 1e-9 relative (3e-11 measured) and the binding
criterion is the same (:func:`check_size`).

**Trade-off** (``cm.synthesis.cam_size_tradeoff``: ``Cam.min_phase_angles`` at
each of 60 base radii, 5 speeds, the rise and the return) against
:func:`numpy_tradeoff`: the same rule (from 360° down by factors of 0.7 to the
first violating angle, then the crossing) for the pressure-angle, undercut and
stress bounds, vectorised over (radius, segment) and (radius, speed, segment)
with the same closed forms and the same Illinois root; the jump bound in closed
form. They agree to 1e-10 relative (:func:`check_tradeoff`).

**numba** (:func:`numba_size`, :func:`numba_tradeoff`; checked equal to the same
tolerances, ``test_numba_agrees``): the same closed forms, grids and roots in
scalar loops, speeds or radii in ``prange`` — in the interleaved rounds of
:func:`test_print_ratios` only, with a timed run (compiling takes ~30 s the first
time; cached in ``benches/__pycache__``). It does not pay here: numpy's vectorised
transcendental functions and the geometry shared over speeds beat it.

Outputs are small (a row per speed; 60 × 5 × 2 × 4 angles), so the page state of
the output is not a question here; the peer's work arrays are allocated afresh
each call, as a user's would be.

Default test run (``--benchmark-disable`` in addopts): each row once on fewer
speeds and radii, without numba. For timings, the ratio tables and (``-s``) the
interleaved rounds' medians and ratios::

    python -m pytest benches/bench_cam_size.py --benchmark-enable -q -p no:cacheprovider -s
"""

from __future__ import annotations

import math
import os
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from _timing import interleaved, timed_run

Array = npt.NDArray[np.float64]
GROUP_SIZE = "synthesis: cam_size, smallest base radius, per speed"
GROUP_TRADE = "synthesis: cam_size_tradeoff, 60 radii, per radius"
RR, H = 0.010, 0.020
MASS, RATE, PRELOAD = 2.0, 5000.0, 100.0
WIDTH, E, NU, LIMIT = 0.01, 2.1e11, 0.3, 7.5e8
ALPHA = math.radians(30.0)
R_MIN, R_MAX = RR * 1.001, 0.2
SCAN = 64
# (kind sign, angle [deg]): +1 rise, 0 dwell, −1 return.
PROGRAM = ((1, 120.0), (0, 60.0), (-1, 120.0), (0, 60.0))
XC = np.linspace(0.0, 1.0, 257)  # coarse grid over a segment
XF = np.linspace(0.0, 1.0, 129)  # fine grid over two coarse cells
C_HERTZ = 2 * (1 - NU**2) / E
RPM_SIZE = np.linspace(200.0, 1440.0, 20)
RPM_TRADE = np.linspace(300.0, 1500.0, 5)
RADII_TRADE = np.geomspace(0.015, 0.15, 60)
LIMITS = cm.synthesis.CamLimits(30.0, LIMIT)
LOADS = cm.cam.FollowerLoads(MASS, RATE, PRELOAD)
CONTACT = cm.cam.Contact(WIDTH, E, NU, E, NU)


def make_cam(rb: float = 0.05) -> cm.cam.Cam:
    kinds = {1: "rise", 0: "dwell", -1: "return"}
    segs = [cm.cam.Segment(kinds[k], ang, H if k else 0.0) for k, ang in PROGRAM]
    return cm.cam.Cam(segs, cm.cam.TranslatingRoller(rb, RR))


def rad_s(rpm: Any) -> Any:
    return np.asarray(rpm) * 2 * math.pi / 60


# ---------------------------------------------------------------- the peer
def law(sign: Any, beta: Any, x: Array) -> tuple[Array, Array, Array]:
    """s, s′, s″ [m, m/rad, m/rad²] of a cycloidal rise (sign +1) or return (−1)
    over the angle beta [rad] at the fractions x of the segment (broadcast)."""
    w = 2 * math.pi * x
    h = sign * H
    s = np.where(sign > 0, 0.0, H) + h * (x - np.sin(w) / (2 * math.pi))
    return s, h / beta * (1 - np.cos(w)), h / beta**2 * 2 * math.pi * np.sin(w)


def refined_max(f: Array) -> Array:
    """The largest value along the last axis, refined by the parabola through the
    sampled maximum and its two neighbours (at an end: the sample)."""
    i = np.argmax(f, axis=-1)[..., None]
    j = np.clip(i, 1, f.shape[-1] - 2)
    fm, f0, fp = (np.take_along_axis(f, j + k, -1)[..., 0] for k in (-1, 0, 1))
    top = np.take_along_axis(f, i, -1)[..., 0]
    curv = fm - 2 * f0 + fp
    inner = (i[..., 0] == j[..., 0]) & (curv < 0) & np.isfinite(curv)
    with np.errstate(invalid="ignore", divide="ignore"):
        vertex = f0 - (fm - fp) ** 2 / (8 * curv)
    return np.where(inner, np.maximum(vertex, top), top)


def peak(fn: Any) -> Array:
    """The worst value of fn over a segment: sampled on the coarse grid XC, then
    on the fine grid XF over the two cells around the sampled worst (each row
    its own), then the parabola through the finest worst and its neighbours.
    fn(x) broadcasts the segment fractions x (n,) or (..., n) against its rows."""
    v = fn(XC)
    i = np.argmax(v, axis=-1)
    a, b = XC[np.maximum(i - 1, 0)], XC[np.minimum(i + 1, XC.size - 1)]
    return refined_max(fn(a[..., None] + (b - a)[..., None] * XF))


def stress(q: Array, cos_phi: Array, kappa_p: Array) -> Array:
    """σ_H [Pa] of the roller on the profile (0 where the follower lifts off)."""
    n = q / cos_phi
    kappa = 1 / RR + kappa_p / (1 - RR * kappa_p)
    with np.errstate(invalid="ignore"):
        return np.sqrt(np.maximum(n, 0.0) * kappa / (math.pi * WIDTH * C_HERTZ))


def pitch(rb: Any, sign: Any, beta: Any, x: Array) -> tuple[Array, ...]:
    """s, s″, d = R_b + r_r + s, |T|, κ_p (+ convex) and φ's tangent parts of the
    radial translating roller's pitch curve (broadcast)."""
    s, ds, dds = law(sign, beta, x)
    d = rb + RR + s
    speed2 = d * d + ds * ds
    speed = np.sqrt(speed2)
    return s, ds, dds, d, speed, (d * (d - dds) + 2 * ds * ds) / (speed2 * speed)


def segment(rb: Array, omega: Array, sign: Array, beta: Array, crit: int) -> Array:
    """One criterion's worst ratio (0 pressure angle, 1 undercut, 2 stress) over a
    rise or return (sign ±1) of angle beta [rad] at base radius rb and speed omega
    [rad/s], each (m,)."""
    rb, omega, sign, beta = (np.asarray(x, float)[..., None] for x in (rb, omega, sign, beta))
    if crit == 0:

        def phi(x: Array) -> Array:
            s, ds, _ = law(sign, beta, x)
            return np.abs(np.arctan2(ds, rb + RR + s))

        return peak(phi) / ALPHA
    under = peak(lambda x: RR * pitch(rb, sign, beta, x)[5])
    if crit == 1:
        return under

    def sigma(x: Array) -> Array:
        s, _, dds, d, speed, kp = pitch(rb, sign, beta, x)
        return stress(MASS * dds * omega**2 + RATE * s + PRELOAD, d / speed, kp)

    return np.where(under < 1.0, peak(sigma) / LIMIT, np.inf)


def stress_scan(rb: Array, omega: Array) -> Array:
    """(radii, speeds) the stress's worst ratio over the whole cam, broadcast
    over (radius, speed, angle): on the coarse grid the geometry is computed once
    per radius and the normal force once per speed."""
    out = np.zeros((rb.size, omega.size))
    r3, w2 = rb[:, None, None], (omega**2)[None, :, None]
    beta = math.radians(120.0)
    for sign in (1.0, -1.0):
        under = peak(lambda x, sign=sign: RR * pitch(rb[:, None], sign, beta, x)[5])

        def sigma(x: Array, sign: float = sign) -> Array:
            s, _, dds, d, speed, kp = pitch(r3, sign, beta, x)
            return stress(MASS * dds * w2 + RATE * s + PRELOAD, d / speed, kp)

        out = np.maximum(out, np.where(under[:, None] < 1.0, peak(sigma) / LIMIT, np.inf))
    for s in (0.0, H):
        d = rb + RR + s
        sd = stress(np.asarray(RATE * s + PRELOAD), np.asarray(1.0), 1 / d) / LIMIT
        out = np.maximum(out, np.where(RR / d < 1.0, sd, np.inf)[:, None])
    return out


def whole_cam(rb: Array, omega: Array, crits: tuple[int, ...] = (0, 1, 2)) -> Array:
    """(3, m) each criterion's worst ratio over the whole cam at its own angles
    (those of ``crits``; 0 for the others): rise and return sampled, the dwells
    (s = 0 and H, φ = 0, κ_p = 1/(R_b + r_r + s)) in closed form."""
    out = np.zeros((3, rb.size))
    beta = np.full(rb.size, math.radians(120.0))
    for sign in (1.0, -1.0):
        for c in crits:
            out[c] = np.maximum(out[c], segment(rb, omega, np.full(rb.size, sign), beta, c))
    for s in (0.0, H):
        d = rb + RR + s
        out[1] = np.maximum(out[1], RR / d)
        sd = stress(np.asarray(RATE * s + PRELOAD), np.asarray(1.0), 1 / d) / LIMIT
        out[2] = np.maximum(out[2], np.where(RR / d < 1.0, sd, np.inf))
    return out


def illinois(f: Any, lo: Array, hi: Array, flo: Array, fhi: Array, geometric: bool) -> Array:
    """Roots of f on [lo, hi] (f(lo) > 0 ≥ f(hi) or the reverse) for every row
    at once: Illinois' regula falsi, a bisection step where an end is not finite
    (geometric: in log scale), each row stopped once its bracket or its step is
    below 1e-13 of the root; f(x, rows) evaluates the rows `rows` at x."""
    lo, hi, flo, fhi = (np.array(v, float) for v in (lo, hi, flo, fhi))
    x, last = hi.copy(), np.zeros(lo.shape, int)
    live = np.ones(lo.shape, bool)
    for _ in range(100):
        r = np.flatnonzero(live)
        if r.size == 0:
            break
        a, b, fa, fb = lo[r], hi[r], flo[r], fhi[r]
        bis = ~(np.isfinite(fa) & np.isfinite(fb))
        with np.errstate(invalid="ignore", divide="ignore"):
            xf = (a * fb - b * fa) / (fb - fa)
        mid = np.sqrt(a * b) if geometric else 0.5 * (a + b)
        xn = np.where(bis | ~np.isfinite(xf), mid, xf)
        fx = f(xn, r)
        left = np.sign(fx) == np.sign(fa)
        lo[r], flo[r] = np.where(left, xn, a), np.where(left, fx, fa)
        hi[r], fhi[r] = np.where(left, b, xn), np.where(left, fb, fx)
        # Illinois: the end kept twice in a row has its value halved.
        twice_hi = left & (last[r] == 1)
        twice_lo = ~left & (last[r] == -1)
        fhi[r[twice_hi]] *= 0.5
        flo[r[twice_lo]] *= 0.5
        last[r] = np.where(left, 1, -1)
        done = (fx == 0) | (np.abs(xn - x[r]) <= 1e-14 * xn) | (hi[r] - lo[r] <= 1e-13 * xn)
        x[r] = xn
        live[r[done]] = False
    return x


def numpy_size(rpm: Array) -> tuple[Array, Array]:
    """(base radius [m], binding criterion index) per speed: the kernel's rule."""
    omega = rad_s(rpm)
    ns = omega.size
    radii = R_MIN * (R_MAX / R_MIN) ** (np.arange(SCAN) / (SCAN - 1))
    radii[-1] = R_MAX
    # The scan: the geometry once per radius, the stress per (radius, speed).
    geo = whole_cam(radii, np.zeros(SCAN), (0, 1))[:2].max(0)
    g = np.maximum(geo[:, None], stress_scan(radii, omega))
    ok = g <= 1.0 + 1e-9
    j = np.argmax(ok, axis=0)
    assert ok.any(axis=0).all() and (j > 0).all(), "infeasible or at the lower bound"
    cols = np.arange(ns)

    def f(x: Array, rows: Array) -> Array:
        return whole_cam(x, omega[rows]).max(0) - 1.0

    rb = illinois(f, radii[j - 1], radii[j], g[j - 1, cols] - 1, g[j, cols] - 1, True)
    return rb, np.argmax(whole_cam(rb, omega), axis=0)


def numpy_tradeoff(radii: Array, rpm: Array) -> Array:
    """(radii, speeds, 2 segments, 4 criteria) smallest phase angles [deg]:
    pressure angle, undercut, jump, stress; the kernel's rule, every (radius,
    speed, segment) at once."""
    omega = rad_s(rpm)
    nr, ns = radii.size, omega.size

    def bound(crit: int, rb: Array, om: Array, sign: Array) -> Array:
        """Scan down from 2π by 0.7 to the first violation, then the crossing."""

        def g(beta: Array, rows: Any = slice(None)) -> Array:
            return segment(rb[rows], om[rows], sign[rows], beta, crit) - 1.0

        hi = np.full(rb.size, 2 * math.pi)
        ghi = g(hi)
        holds = ghi <= 0.0
        lo, glo = hi.copy(), ghi.copy()
        live, found = holds.copy(), np.zeros(rb.size, bool)
        while live.any():
            r = np.flatnonzero(live)
            lo[r] = hi[r] * 0.7
            glo[r] = g(lo[r], r)
            viol = ~(glo[r] <= 0.0)
            found[r[viol]] = True
            step = r[~viol]
            hi[step], ghi[step] = lo[step], glo[step]
            live[:] = False
            live[step[lo[step] * 0.7 >= 2 * math.pi * 1e-6]] = True
        root = np.zeros(rb.size)
        i = np.flatnonzero(found)
        root[i] = illinois(lambda x, r: g(x, i[r]), lo[i], hi[i], glo[i], ghi[i], False)
        return np.where(holds, root, np.nan)

    out = np.zeros((nr, ns, 2, 4))
    signs = np.array([1.0, -1.0])
    # Speed-free criteria: once per (radius, segment).
    rb2, sg2 = np.repeat(radii, 2), np.tile(signs, nr)
    for c in (0, 1):
        out[:, :, :, c] = bound(c, rb2, np.zeros(2 * nr), sg2).reshape(nr, 1, 2)
    rb3 = np.repeat(radii, 2 * ns)
    om3 = np.tile(np.repeat(omega, 2), nr)
    sg3 = np.tile(signs, nr * ns)
    st = bound(2, rb3, om3, sg3).reshape(nr, ns, 2)
    out[..., 3] = np.where(st <= out[..., 1] * (1 + 1e-9), 0.0, st)
    # Jump: β_min = ω √(max −m s″(β = 1)/(k s + preload)), the same at every radius.
    for k, sign in enumerate(signs):

        def jump(x: Array, sign: float = sign) -> Array:
            s, _, dds = law(sign, 1.0, x)
            return np.maximum(-MASS * dds / (RATE * s + PRELOAD), 0.0)

        v = float(peak(jump))
        out[:, :, k, 2] = omega * math.sqrt(v)
    return np.degrees(out)


# ------------------------------------------------------------- the numba peer
try:
    import numba
except ImportError:  # pragma: no cover - depends on the environment
    numba = None

if numba is not None:
    _jit = numba.njit(cache=True, error_model="numpy")
    _pjit = numba.njit(parallel=True, cache=True, error_model="numpy")
    _prange = numba.prange
else:  # the functions below are then never called
    _jit = _pjit = lambda f: f
    _prange = range
TAU = 2 * math.pi
NC, NF = XC.size, XF.size


@_jit
def nb_value(crit, rb, omega, sign, beta, x):  # type: ignore[no-untyped-def]
    """One criterion's value at the fraction x of a rise (+1) or return (−1):
    0 pressure ratio, 1 undercut ratio, 2 stress ratio, 3 jump (β = 1)."""
    w = TAU * x
    h = sign * H
    s = (0.0 if sign > 0 else H) + h * (x - math.sin(w) / TAU)
    ds = h / beta * (1 - math.cos(w))
    dds = h / beta**2 * TAU * math.sin(w)
    if crit == 3:
        return max(-MASS * dds / (RATE * s + PRELOAD), 0.0)
    d = rb + RR + s
    if crit == 0:
        return abs(math.atan2(ds, d)) / ALPHA
    speed2 = d * d + ds * ds
    speed = math.sqrt(speed2)
    kp = (d * (d - dds) + 2 * ds * ds) / (speed2 * speed)
    if crit == 1:
        return RR * kp
    n = (MASS * dds * omega**2 + RATE * s + PRELOAD) / (d / speed)
    kappa = 1 / RR + kp / (1 - RR * kp)
    return math.sqrt(max(n, 0.0) * kappa / (math.pi * WIDTH * C_HERTZ)) / LIMIT


@_jit
def nb_peak(crit, rb, omega, sign, beta):  # type: ignore[no-untyped-def]
    """:func:`peak` of one criterion over a segment, scalar."""
    best, i = -np.inf, 0
    for k in range(NC):
        v = nb_value(crit, rb, omega, sign, beta, k / (NC - 1))
        if v > best:
            best, i = v, k
    a = max(i - 1, 0) / (NC - 1)
    b = min(i + 1, NC - 1) / (NC - 1)
    vals = np.empty(NF)
    j = 0
    for k in range(NF):
        vals[k] = nb_value(crit, rb, omega, sign, beta, a + (b - a) * (k / (NF - 1)))
        if vals[k] > vals[j]:
            j = k
    top = vals[j]
    if 0 < j < NF - 1:
        fm, f0, fp = vals[j - 1], vals[j], vals[j + 1]
        curv = fm - 2 * f0 + fp
        if curv < 0:
            top = max(f0 - (fm - fp) ** 2 / (8 * curv), top)
    return top


@_jit
def nb_ratio(crit, rb, omega, sign, beta):  # type: ignore[no-untyped-def]
    """A segment's worst ratio; the stress's +∞ on an undercut profile."""
    if crit == 2 and not nb_peak(1, rb, 0.0, sign, beta) < 1.0:
        return np.inf
    return nb_peak(crit, rb, omega, sign, beta)


@_jit
def nb_stress_cam(rb, omega):  # type: ignore[no-untyped-def]
    """The stress's worst ratio over the whole cam (rise, return, both dwells)."""
    g = max(
        nb_ratio(2, rb, omega, 1.0, TAU / 3),
        nb_ratio(2, rb, omega, -1.0, TAU / 3),
    )
    for s in (0.0, H):
        d = rb + RR + s
        if RR / d >= 1.0:
            return np.inf
        kappa = 1 / RR + 1 / (d - RR)
        g = max(g, math.sqrt((RATE * s + PRELOAD) * kappa / (math.pi * WIDTH * C_HERTZ)) / LIMIT)
    return g


@_jit
def nb_geometry_cam(rb):  # type: ignore[no-untyped-def]
    """max(pressure ratio, undercut ratio) over the whole cam (speed-free)."""
    g = RR / (rb + RR)  # the base circle's dwell: the larger undercut ratio
    for sign in (1.0, -1.0):
        g = max(g, nb_peak(0, rb, 0.0, sign, TAU / 3), nb_peak(1, rb, 0.0, sign, TAU / 3))
    return g


@_jit
def nb_illinois(kind, crit, rb, omega, sign, a, b, fa, fb, geometric):  # type: ignore[no-untyped-def]
    """The root of g − 1 on [a, b] (:func:`illinois`, scalar); kind 0: the whole
    cam's g(R_b) at speed omega, kind 1: a segment's ratio g(β) at rb."""
    x, last = b, 0
    for _ in range(100):
        if math.isfinite(fa) and math.isfinite(fb) and fb != fa:
            xn = (a * fb - b * fa) / (fb - fa)
        else:
            xn = math.sqrt(a * b) if geometric else 0.5 * (a + b)
        if kind == 0:
            fx = max(nb_geometry_cam(xn), nb_stress_cam(xn, omega)) - 1.0
        else:
            fx = nb_ratio(crit, rb, omega, sign, xn) - 1.0
        if np.sign(fx) == np.sign(fa):
            a, fa = xn, fx
            if last == 1:
                fb *= 0.5
            last = 1
        else:
            b, fb = xn, fx
            if last == -1:
                fa *= 0.5
            last = -1
        done = fx == 0 or abs(xn - x) <= 1e-14 * xn or b - a <= 1e-13 * xn
        x = xn
        if done:
            break
    return x


@_pjit
def numba_size(rpm):  # type: ignore[no-untyped-def]
    """:func:`numpy_size` in numba: the speed-free geometry once per scanned
    radius, then each speed (``prange``) its stress scan and root."""
    omega = rpm * TAU / 60
    radii = R_MIN * (R_MAX / R_MIN) ** (np.arange(SCAN) / (SCAN - 1))
    radii[-1] = R_MAX
    geo = np.empty(SCAN)
    for i in _prange(SCAN):
        geo[i] = nb_geometry_cam(radii[i])
    out = np.empty(rpm.size)
    for k in _prange(rpm.size):
        g = np.empty(SCAN)
        for i in range(SCAN):
            g[i] = max(geo[i], nb_stress_cam(radii[i], omega[k]))
        j = 0
        while j < SCAN and not g[j] <= 1.0 + 1e-9:
            j += 1
        out[k] = nb_illinois(
            0, 0, 0.0, omega[k], 0.0, radii[j - 1], radii[j], g[j - 1] - 1, g[j] - 1, True
        )
    return out


@_jit
def nb_bound(crit, rb, omega, sign):  # type: ignore[no-untyped-def]
    """Scan down from 2π by 0.7 to the first violation, then the crossing."""
    hi = TAU
    ghi = nb_ratio(crit, rb, omega, sign, hi) - 1.0
    if not ghi <= 0.0:
        return np.nan
    while hi * 0.7 >= TAU * 1e-6:
        lo = hi * 0.7
        glo = nb_ratio(crit, rb, omega, sign, lo) - 1.0
        if not glo <= 0.0:
            return nb_illinois(1, crit, rb, omega, sign, lo, hi, glo, ghi, False)
        hi, ghi = lo, glo
    return 0.0


@_pjit
def numba_tradeoff(radii, rpm):  # type: ignore[no-untyped-def]
    """:func:`numpy_tradeoff` in numba, radii in ``prange``."""
    omega = rpm * TAU / 60
    out = np.zeros((radii.size, rpm.size, 2, 4))
    jump = np.empty(2)
    for k in range(2):
        jump[k] = math.sqrt(nb_peak(3, 0.0, 0.0, 1.0 - 2.0 * k, 1.0))
    for i in _prange(radii.size):
        for k in range(2):
            sign = 1.0 - 2.0 * k
            p = nb_bound(0, radii[i], 0.0, sign)
            u = nb_bound(1, radii[i], 0.0, sign)
            for m in range(rpm.size):
                st = nb_bound(2, radii[i], omega[m], sign)
                out[i, m, k, 0] = p
                out[i, m, k, 1] = u
                out[i, m, k, 2] = omega[m] * jump[k]
                out[i, m, k, 3] = 0.0 if st <= u * (1 + 1e-9) else st
    return out * (180.0 / math.pi)


# ---------------------------------------------------------------- cyclomech
def cyclomech_size(rpm: Array, threads: int | None) -> list[cm.synthesis.CamSize]:
    cam = make_cam()
    return [
        cm.synthesis.cam_size(
            cam,
            float(n),
            limits=LIMITS,
            loads=LOADS,
            contact=CONTACT,
            max_base_radius=R_MAX,
            n_threads=threads,
        )
        for n in rpm
    ]


def cyclomech_tradeoff(radii: Array, rpm: Array, threads: int | None) -> Array:
    t = cm.synthesis.cam_size_tradeoff(
        make_cam(), rpm, radii, limits=LIMITS, loads=LOADS, contact=CONTACT, n_threads=threads
    )
    return t.angle_deg


def test_both_criteria_bind() -> None:
    got = {r.binding for r in cyclomech_size(RPM_SIZE[[0, -1]], None)}
    assert got == {"pressure_angle", "contact_stress"}


@pytest.fixture(scope="module")
def numpy_checked() -> None:
    """The numpy peers checked against cyclomech before any row that times them."""
    check_size()
    check_tradeoff()


def test_peers_agree(numpy_checked: None) -> None:
    """:func:`check_size` and :func:`check_tradeoff`, through the fixture."""


def check_size() -> None:
    """Radii to 1e-9 relative and the same binding criterion, on 7 speeds (the
    last bound by the stress)."""
    rpm = RPM_SIZE[::3]
    ours = cyclomech_size(rpm, None)
    rb, binding = numpy_size(rpm)
    np.testing.assert_allclose([r.base_radius for r in ours], rb, rtol=1e-9)
    names = ("pressure_angle", "undercut", "contact_stress")
    assert [r.binding for r in ours] == [names[b] for b in binding]


def check_tradeoff() -> None:
    """Every angle to 1e-10 relative, on 10 radii × 5 speeds × 2 segments."""
    radii = RADII_TRADE[::6]
    ours = cyclomech_tradeoff(radii, RPM_TRADE, None)
    ref = numpy_tradeoff(radii, RPM_TRADE)
    np.testing.assert_allclose(ours, ref, rtol=1e-10, atol=1e-12)


def _speeds(benchmark: Any) -> Array:
    return RPM_SIZE[::5] if benchmark.disabled else RPM_SIZE


@pytest.mark.benchmark(group=GROUP_SIZE)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_size_cyclomech(benchmark, threads: int | None) -> None:
    rpm = _speeds(benchmark)
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"cam_size, one call per speed, {rpm.size} speeds, {where}"
    benchmark.extra_info["items"] = rpm.size
    out = benchmark.pedantic(cyclomech_size, (rpm, threads), rounds=3, iterations=1)
    assert len(out) == rpm.size


@pytest.mark.benchmark(group=GROUP_SIZE)
def test_size_numpy(benchmark, numpy_checked: None) -> None:
    rpm = _speeds(benchmark)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"all {rpm.size} speeds at once: scan, vectorised Illinois root"
    benchmark.extra_info["items"] = rpm.size
    rb, _ = benchmark.pedantic(numpy_size, (rpm,), rounds=3, iterations=1)
    assert rb.shape == rpm.shape


def _radii(benchmark: Any) -> Array:
    return RADII_TRADE[::10] if benchmark.disabled else RADII_TRADE


@pytest.mark.benchmark(group=GROUP_TRADE)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_tradeoff_cyclomech(benchmark, threads: int | None) -> None:
    radii = _radii(benchmark)
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = (
        f"cam_size_tradeoff, {radii.size} radii x {RPM_TRADE.size} speeds, {where}"
    )
    benchmark.extra_info["items"] = radii.size
    out = benchmark.pedantic(
        cyclomech_tradeoff, (radii, RPM_TRADE, threads), rounds=3, iterations=1
    )
    assert out.shape == (radii.size, RPM_TRADE.size, 2, 4)


@pytest.mark.benchmark(group=GROUP_TRADE)
def test_tradeoff_numpy(benchmark, numpy_checked: None) -> None:
    radii = _radii(benchmark)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "vectorised over (radius, speed, segment): scan, Illinois root"
    benchmark.extra_info["items"] = radii.size
    out = benchmark.pedantic(numpy_tradeoff, (radii, RPM_TRADE), rounds=3, iterations=1)
    assert out.shape == (radii.size, RPM_TRADE.size, 2, 4)


def _report(title: str, med: dict[str, tuple[float, float]], items: int, unit: str) -> None:
    print(f"\n{title}:")
    for name, (t, cpu) in med.items():
        print(
            f"  {name:<38} {t * 1e3:9.2f} ms   {t / items * 1e3:8.3f} ms per {unit}"
            f"   CPU {cpu * 1e3:9.2f} ms"
        )
    for peer in [n for n in med if not n.startswith("cyclomech")]:
        for ref in [n for n in med if n.startswith("cyclomech")]:
            wall, cpu = med[peer][0] / med[ref][0], med[peer][1] / med[ref][1]
            print(f"  {peer} / {ref} = {wall:.2f}x  (CPU time: {cpu:.2f}x)")


def _on(threads: int, run: Any) -> Any:
    """run() on numba's `threads` threads (0: all)."""

    def call() -> None:
        every = numba.config.NUMBA_NUM_THREADS
        numba.set_num_threads(threads or every)
        try:
            run()
        finally:
            numba.set_num_threads(every)

    return call


@pytest.fixture(scope="module")
def numba_peer(request: pytest.FixtureRequest) -> None:
    """The numba peer compiled and checked against cyclomech (skips without numba;
    in the default run unless CYCLOMECH_BENCH_NUMBA=1: compiling takes ~30 s)."""
    if numba is None:
        pytest.skip("numba is not installed (pip install numba)")
    if not timed_run(request.config) and os.environ.get("CYCLOMECH_BENCH_NUMBA") != "1":
        pytest.skip("the numba peer compiles for ~30 s: runs with --benchmark-enable")
    rpm = RPM_SIZE[::3]
    ours = [r.base_radius for r in cyclomech_size(rpm, None)]
    np.testing.assert_allclose(numba_size(rpm), ours, rtol=1e-9)
    radii = RADII_TRADE[::6]
    ref = cyclomech_tradeoff(radii, RPM_TRADE, None)
    np.testing.assert_allclose(numba_tradeoff(radii, RPM_TRADE), ref, rtol=1e-10, atol=1e-12)


def test_numba_agrees(numba_peer: None) -> None:
    """The fixture's check (radii to 1e-9, angles to 1e-10), as a test."""


def test_print_ratios(request: pytest.FixtureRequest) -> None:
    """Interleaved rounds in one process, medians and ratios (print with -s). The
    numba rows need numba and a timed run (or CYCLOMECH_BENCH_NUMBA=1)."""
    timed = timed_run(request.config)
    rounds = 7 if timed else 1
    rpm = RPM_SIZE if timed else RPM_SIZE[::5]
    request.getfixturevalue("numpy_checked")
    jit = numba is not None and (timed or os.environ.get("CYCLOMECH_BENCH_NUMBA") == "1")
    if jit:
        request.getfixturevalue("numba_peer")  # compiled and checked
    tools: dict[str, Any] = {
        "cyclomech cam_size, 1 thread": lambda: cyclomech_size(rpm, 1),
        "cyclomech cam_size, all cores": lambda: cyclomech_size(rpm, None),
        "numpy, all speeds at once": lambda: numpy_size(rpm),
        "numpy, one speed per call": lambda: [numpy_size(rpm[i : i + 1]) for i in range(rpm.size)],
    }
    if jit:
        tools["numba, all speeds at once, 1 thread"] = _on(1, lambda: numba_size(rpm))
        tools["numba, all speeds at once, all cores"] = _on(0, lambda: numba_size(rpm))
    med = interleaved(tools, rounds)
    _report(f"cam_size, {rpm.size} speeds, {rounds} interleaved rounds", med, rpm.size, "speed")
    radii = RADII_TRADE if timed else RADII_TRADE[::10]
    tools = {
        "cyclomech tradeoff, 1 thread": lambda: cyclomech_tradeoff(radii, RPM_TRADE, 1),
        "cyclomech tradeoff, all cores": lambda: cyclomech_tradeoff(radii, RPM_TRADE, None),
        "numpy": lambda: numpy_tradeoff(radii, RPM_TRADE),
    }
    if jit:
        tools["numba, 1 thread"] = _on(1, lambda: numba_tradeoff(radii, RPM_TRADE))
        tools["numba, all cores"] = _on(0, lambda: numba_tradeoff(radii, RPM_TRADE))
    med2 = interleaved(tools, rounds)
    _report(
        f"cam_size_tradeoff, {radii.size} radii x {RPM_TRADE.size} speeds, {rounds} rounds",
        med2,
        radii.size,
        "radius",
    )
    assert all(t > 0 for t, _ in [*med.values(), *med2.values()])
