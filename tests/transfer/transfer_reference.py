"""Today's numpy code path of :mod:`cyclomech.transfer` (before its kernels moved
to Rust, issue 20), kept as the REFERENCE the Rust kernels are tested against
(tests/transfer/test_transfer_kernels.py) and timed against (benches/bench_transfer.py).
Copied from python/cyclomech/transfer/_quintic.py, _path.py and _design.py at
commit 12fc966, unchanged but for names: functions of a
:class:`~cyclomech.transfer.QuinticTransition` ``q`` (its ``coeffs``) and of a
:class:`~cyclomech.transfer.TransferPath` ``path`` (its ``_g``, ``_lengths``,
``transitions``) instead of methods."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt
from cyclomech.transfer import PathAcceleration, PathSample, TransferPath, acceleration_jump
from cyclomech.transfer._checks import _speeds
from cyclomech.transfer._path import _geometry

Array = npt.NDArray[np.float64]

_GL16 = np.polynomial.legendre.leggauss(16)
_GL4 = np.polynomial.legendre.leggauss(4)
_NODES16, _WEIGHTS16 = (_GL16[0] + 1.0) / 2.0, _GL16[1] / 2.0
_NODES4, _WEIGHTS4 = (_GL4[0] + 1.0) / 2.0, _GL4[1] / 2.0


def poly(q: Any, x: Array, order: int) -> Array:
    """The order-th derivative of q at an array x (QuinticTransition._poly)."""
    return _horner(list(q.coeffs), np.asarray(x, dtype=np.float64), order)


def pieces(q: Any, upto: float) -> int:
    """QuinticTransition._pieces."""
    x = np.linspace(0.0, upto, 65)
    turn = float(np.abs(np.diff(np.arctan(poly(q, x, 1)))).sum())
    return int(min(max(1, math.ceil(turn / 0.05)), 512))


def arc_length(q: Any, x: Any) -> Array:
    """QuinticTransition.arc_length (16-point Gauss-Legendre on pieces)."""
    x = np.asarray(x, dtype=np.float64)
    top = float(np.abs(x).max()) if x.size else 0.0
    m = pieces(q, top) if top > 0 else 1
    frac = ((np.arange(m)[:, None] + _NODES16) / m).ravel()
    t = x[..., None] * frac
    f = np.sqrt(1.0 + poly(q, t, 1) ** 2)
    return x * (f @ np.tile(_WEIGHTS16, m)) / m


def curvature(q: Any, x: Any) -> tuple[Array, Array]:
    """(κ, dκ/ds) of q at x (QuinticTransition.curvature, curvature_rate)."""
    d1, d2, d3 = (poly(q, x, j) for j in (1, 2, 3))
    return _curvature(d1, d2, d3)


def _horner(c: list[Any], x: Array, order: int) -> Array:
    """The order-th derivative of Σ c[n]·xⁿ (n ≤ 5) at x; the c[n] are numbers or
    arrays broadcasting with x."""
    d = [c[n] * math.perm(n, order) for n in range(order, 6)]
    out = np.zeros(np.broadcast_shapes(np.shape(x), np.shape(d[-1]))) + d[-1]
    for a in reversed(d[:-1]):
        out = out * x + a
    return out


def _curvature(d1: Array, d2: Array, d3: Array) -> tuple[Array, Array]:
    """(κ, dκ/ds) of a graph from its first three derivatives."""
    g = 1.0 + d1 * d1
    kappa = d2 / g**1.5
    rate = (d3 * g - 3.0 * d1 * d2 * d2) / g**3
    return kappa, rate


def _coeffs(R: Any, k: Any, b: Any, x2: Any) -> tuple[Array, ...]:
    """a2 … a5 for arrays of (R, k, b, x2) (broadcast), from the conditions at B:
    with u = a3·x2³, v = a4·x2⁴, w = a5·x2⁵ the 3×3 system
    [1 1 1; 3 4 5; 6 12 20]·(u, v, w) = (r0, r1·x2, r2·x2²) (determinant 2) has
    the inverse rows (10, −4, 1/2), (−15, 7, −1), (6, −3, 1/2)."""
    a2 = 0.5 / R
    r0 = k * x2 + b - a2 * x2**2
    r1 = (k - 2.0 * a2 * x2) * x2
    r2 = -2.0 * a2 * x2**2
    u = 10.0 * r0 - 4.0 * r1 + 0.5 * r2
    v = -15.0 * r0 + 7.0 * r1 - r2
    w = 6.0 * r0 - 3.0 * r1 + 0.5 * r2
    return a2, u / x2**3, v / x2**4, w / x2**5


def _rot(v: Array, angle: Any) -> Array:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _left(v: Array) -> Array:
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def _allocate(n: int, lengths: Array) -> list[int]:
    """Points per piece: ≥ 2 each (an empty piece gets 2 at one place), the rest
    in proportion to length; the last piece takes the end point too."""
    free = n - 2 * len(lengths)
    share = free * lengths / lengths.sum()
    extra = np.floor(share).astype(int)
    rest = free - int(extra.sum())
    extra[np.argsort(share - extra)[::-1][:rest]] += 1
    return [2 + int(e) for e in extra]


def _arc_part(
    centre: Array, R: float, phi: Array, sign: float, s: Array, piece: int
) -> tuple[Any, ...]:
    pts = centre + R * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    head = phi + sign * 0.5 * math.pi
    return pts, s, head, np.full_like(phi, sign / R), np.zeros_like(phi), piece


def _quintic_part(
    q: Any,
    x: Array,
    origin: Array,
    t_a: Array,
    base: float,
    s0: float,
    *,
    forward: bool,
    piece: int,
) -> tuple[Any, ...]:
    y, d1, d2, d3 = (poly(q, x, j) for j in range(4))
    pts = origin + x[:, None] * t_a + y[:, None] * _left(t_a)
    local = np.arctan(d1) + base  # base: the heading of the local x axis
    kappa, rate = _curvature(d1, d2, d3)
    s_local = _cumulative_arc(q, x)
    if forward:
        return pts, s0 + s_local, local, kappa, rate, piece
    # Travelled from B to C: the arc length runs backwards, the heading turns
    # round, the curvature changes sign and its rate (d/ds of −κ(S − s)) keeps it.
    return pts, s0 + (float(arc_length(q, q.x2)) - s_local), local + math.pi, -kappa, rate, piece


def _cumulative_arc(q: Any, x: Array) -> Array:
    """s(x) at a monotone grid x: the length from 0 to x[0] plus 4-point
    Gauss–Legendre over each interval, where the tangent turns by at most
    0.005 rad an interval (then the rule is exact to rounding); on a coarser grid,
    each point's length from 0 by :meth:`QuinticTransition.arc_length`."""
    if x.size < 2 or 10 * pieces(q, float(np.abs(x).max())) > x.size:
        return np.asarray(arc_length(q, x), dtype=np.float64).reshape(x.shape)
    first = np.atleast_1d(arc_length(q, x[:1]))
    lo, hi = x[:-1], x[1:]
    h = hi - lo
    t = lo[:, None] + h[:, None] * _NODES4
    f = np.sqrt(1.0 + poly(q, t, 1) ** 2)
    steps = h * (f @ _WEIGHTS4)
    return np.concatenate([first, first[0] + np.cumsum(steps)])


def _speed_law(speed: Any, start: float, span: float) -> Any:
    """s ↦ (v, dv/ds, d²v/ds²) for a constant speed or a (V_t, V_p) pair."""
    v_t, v_p = _speeds(speed)

    def law(s: Any) -> tuple[Array, Array, Array]:
        s = np.asarray(s, dtype=np.float64)
        u = np.clip((s - start) / span, 0.0, 1.0)
        inside = (s > start) & (s < start + span)
        h = u**3 * (10.0 - 15.0 * u + 6.0 * u * u)
        dh = np.where(inside, 30.0 * u * u * (1.0 - u) ** 2 / span, 0.0)
        ddh = np.where(inside, 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / span**2, 0.0)
        dv = v_p - v_t
        return v_t + dv * h, dv * dh, dv * ddh

    return law


def _kinematics(v: Array, dv: Array, ddv: Array, kappa: Array, rate: Array) -> tuple[Array, ...]:
    """(a_n, a_t, da_n/dt, da_t/dt, |da/dt|) of a point moving at v(s) (dv, ddv its
    s-derivatives) along a curve of curvature κ(s) with rate dκ/ds; d/dt = v·d/ds."""
    a_n = v * v * kappa
    a_t = v * dv
    an_rate = v * (2.0 * v * dv * kappa + v * v * rate)
    at_rate = v * (dv * dv + v * ddv)
    # da/dt of a = a_t·T + a_n·N, with dT/dt = v·κ·N, dN/dt = −v·κ·T.
    jerk = np.hypot(at_rate - a_n * v * kappa, an_rate + a_t * v * kappa)
    return a_n, a_t, an_rate, at_rate, jerk


def _longest(r: Array, c_t: Array, c_p: Array, ratio: Array) -> Array:
    """The longest transitions in proportions ``ratio`` (x2 = λ·ratio) whose
    straight segment is not negative: the root in λ by bisection on a vectorised
    scan (the straight length falls as λ grows)."""
    d = float(np.hypot(*(c_p - c_t)))
    hi = 2.0 * math.sqrt(max(d, 1e-300) * r.max()) * 4.0
    lam = np.geomspace(1e-9 * d, hi, 257)
    g = _geometry(r, c_t, c_p, lam[:, None] * ratio)
    ok = np.flatnonzero(g.straight >= 0.0)
    if ok.size == 0:
        raise ValueError("no transition fits between these rotors")
    lo, hi = lam[ok[-1]], lam[min(ok[-1] + 1, lam.size - 1)]
    for _ in range(8):
        grid = np.linspace(lo, hi, 65)
        g = _geometry(r, c_t, c_p, grid[:, None] * ratio)
        ok = np.flatnonzero(g.straight >= 0.0)
        lo, hi = grid[ok[-1]], grid[min(ok[-1] + 1, grid.size - 1)]
    return lo * ratio


def _peak_jerk(r: Array, c_t: Array, c_p: Array, x2: Array, speed: Any, m: int) -> Array:
    """Peak |da/dt| for each candidate length in ``x2`` (C,), on m points of each
    transition and of the straight, all candidates at once."""
    c = x2.size
    x2s = np.stack([x2, x2], axis=-1)
    g = _geometry(r, c_t, c_p, x2s)
    straight = np.maximum(g.straight, 0.0)
    u = np.linspace(0.0, 1.0, m)
    # Arc lengths of the transitions (C, 2), from the cumulative lengths below.
    lengths = np.empty((c, 2))
    pieces = []
    for side in range(2):
        R = r[side]
        a2, a3, a4, a5 = _coeffs(R, g.k[:, side], g.b[:, side], x2)
        a2 = np.full_like(x2, a2)
        xx = x2[:, None] * u  # (C, m)

        cs = [0.0, 0.0] + [a[:, None] for a in (a2, a3, a4, a5)]

        def d(order: int, x: Array, cs: list[Any] = cs) -> Array:
            return _horner(cs, x, order)

        d1, d2, d3 = d(1, xx), d(2, xx), d(3, xx)
        kappa, rate = _curvature(d1, d2, d3)
        # Cumulative arc length along the candidate's grid (trapezoid on a fine
        # grid is enough for locating the speed law).
        f = np.sqrt(1.0 + d1 * d1)
        s_loc = np.concatenate(
            [np.zeros((c, 1)), np.cumsum(0.5 * (f[:, 1:] + f[:, :-1]) * np.diff(xx), axis=1)],
            axis=1,
        )
        lengths[:, side] = s_loc[:, -1]
        pieces.append((kappa, rate, s_loc))
    span = lengths.sum(axis=1) + straight
    # s from A, each candidate's transfer its own span.
    law = _speed_law(speed, 0.0, span[:, None])

    def jerk(s: Array, kappa: Array, rate: Array) -> Array:
        v, dv, ddv = law(s)
        return _kinematics(v, dv, ddv, kappa, rate)[4]

    k_t, r_t, s_t = pieces[0]
    out = jerk(s_t, k_t, r_t).max(axis=1)
    s_line = lengths[:, :1] + straight[:, None] * u
    zero = np.zeros_like(s_line)
    out = np.maximum(out, jerk(s_line, zero, zero).max(axis=1))
    k_p, r_p, s_p = pieces[1]
    # The process transition travelled backwards: s from its far end, κ negated.
    s_back = (span - lengths[:, 1])[:, None] + (lengths[:, 1][:, None] - s_p)
    out = np.maximum(out, jerk(s_back, -k_p, r_p).max(axis=1))
    # On the pitch circles: v²/R at the transfer's end speeds, no jerk but the
    # centripetal part of the turning frame is already counted at A and C.
    return np.where(g.feasible & (g.straight >= 0), out, np.inf)


def sample(path: TransferPath, n: int) -> PathSample:
    """TransferPath.sample(n), today's numpy code."""
    counts = _allocate(n, path._lengths)
    g = path._g
    lead = math.radians(path.lead_deg)
    parts = []
    c_t, c_p = path._canonical_centres()
    phi_a = math.atan2(*(g.origin[0] - c_t)[::-1])
    u = np.linspace(0.0, 1.0, counts[0], endpoint=False)
    phi = phi_a - lead + lead * u
    parts.append(_arc_part(c_t, path.R_t, phi, 1.0, path.R_t * lead * u, 0))
    s0 = path._lengths[0]
    q = path.transitions[0]
    x = np.linspace(0.0, q.x2, counts[1], endpoint=False)
    base = phi_a + 0.5 * math.pi
    parts.append(_quintic_part(q, x, g.origin[0], g.t_a[0], base, s0, forward=True, piece=1))
    s0 += path._lengths[1]
    u = np.linspace(0.0, 1.0, counts[2], endpoint=False)
    pts = g.ends[0] + (u * path.straight_length)[:, None] * g.u
    head = base + math.atan(g.k[0])
    zero = np.zeros_like(u)
    parts.append((pts, s0 + u * path.straight_length, zero + head, zero, zero, 2))
    s0 += path._lengths[2]
    q = path.transitions[1]
    x = np.linspace(q.x2, 0.0, counts[3], endpoint=False)
    base = head - math.atan(g.k[1]) - math.pi
    parts.append(_quintic_part(q, x, g.origin[1], g.t_a[1], base, s0, forward=False, piece=3))
    s0 += path._lengths[3]
    phi_c = base + 1.5 * math.pi
    u = np.linspace(0.0, 1.0, counts[4])
    phi = phi_c - lead * u
    parts.append(_arc_part(c_p, path.R_p, phi, -1.0, s0 + path.R_p * lead * u, 4))
    points = np.concatenate([p[0] for p in parts])
    s = np.concatenate([p[1] for p in parts])
    heading = np.concatenate([p[2] for p in parts])
    curv = np.concatenate([p[3] for p in parts])
    rate = np.concatenate([p[4] for p in parts])
    piece = np.concatenate([np.full(len(p[1]), p[5], dtype=np.int8) for p in parts])
    if not path.ccw:
        points = points * path._mirror
        heading, curv, rate = -heading, -curv, -rate
    return PathSample(points, s, heading, curv, rate, piece)


def acceleration(path: TransferPath, speed: Any, n: int = 20_001) -> PathAcceleration:
    """TransferPath.acceleration(speed, n), today's numpy code."""
    law = _speed_law(speed, path.start_of_transfer, path.transfer_length)
    smp = sample(path, n)
    v, dv, ddv = law(smp.s)
    a_n, a_t, an_rate, at_rate, jerk = _kinematics(v, dv, ddv, smp.curvature, smp.curvature_rate)
    ds = np.diff(smp.s)
    vm = 0.5 * (v[1:] + v[:-1])
    time = np.concatenate([[0.0], np.cumsum(ds / vm)])
    return PathAcceleration(
        s=smp.s,
        time=time,
        speed=v,
        normal=a_n,
        tangential=a_t,
        total=np.hypot(a_n, a_t),
        normal_rate=an_rate,
        tangential_rate=at_rate,
        jerk=jerk,
        piece=smp.piece,
    )


def max_jerk(path: TransferPath, speed: Any, n: int = 20_001) -> float:
    """TransferPath.max_jerk, today's numpy code."""
    return float(acceleration(path, speed, n).jerk.max())


def design_transfer(
    R_t: float,
    R_p: float,
    gap: float,
    speed: Any,
    *,
    x2_min: float | None = None,
    n_candidates: int = 64,
    n_points: int = 801,
) -> dict[str, Any]:
    """design_transfer, today's numpy code (inputs assumed valid); a dict of the
    TransferDesign's fields."""
    from scipy.optimize import minimize_scalar

    r = np.array([R_t, R_p])
    c_t, c_p = np.zeros(2), np.array([R_t + R_p + gap, 0.0])
    top = float(_longest(r, c_t, c_p, np.ones(2))[0])
    low = min(R_t, R_p) / 100.0 if x2_min is None else x2_min
    cands = np.geomspace(low, top, n_candidates)
    peaks = _peak_jerk(r, c_t, c_p, cands, speed, n_points)
    i = int(np.argmin(peaks))
    lo, hi = cands[max(i - 1, 0)], cands[min(i + 1, cands.size - 1)]
    best = minimize_scalar(
        lambda x: float(_peak_jerk(r, c_t, c_p, np.array([x]), speed, n_points)[0]),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-6 * hi},
    )
    x2 = float(best.x) if best.fun <= peaks[i] else float(cands[i])
    path = TransferPath(R_t, R_p, c_t, c_p, x2=x2 if x2 < top else top)
    acc = acceleration(path, speed)
    v_t, v_p = _speeds(speed)
    jump = acceleration_jump(R_t, v_t / R_t, R_p, v_p / R_p)
    start = int(np.searchsorted(acc.s, path.start_of_transfer))
    end = int(np.searchsorted(acc.s, path.start_of_transfer + path.transfer_length))
    return {
        "x2": path.x2_t,
        "top": top,
        "candidates": cands,
        "peak_jerk": peaks,
        "max_acceleration": acc.max_acceleration,
        "max_jerk": acc.max_jerk,
        "jump": float(jump),
        "transfer_time": float(acc.time[min(end, acc.time.size - 1)] - acc.time[start]),
        "at_limit": bool(x2 >= top * (1 - 1e-6)),
    }
