"""The transition length that minimises the peak jerk (:func:`design_transfer`),
every candidate evaluated in one vectorised pass."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._arrays import positive
from .._errors import InfeasibleError, InputError
from ._checks import Array, _radius, _speeds
from ._jump import acceleration_jump
from ._path import TransferPath, _geometry, _kinematics, _longest, _speed_law
from ._quintic import _coeffs, _curvature, _horner

__all__ = ["TransferDesign", "design_transfer"]


@dataclass(frozen=True)
class TransferDesign:
    """:func:`design_transfer`'s result: the chosen ``path`` and its ``x2`` [m];
    ``candidates`` and ``peak_jerk`` of every candidate [m/s³]; on the chosen path
    ``max_acceleration`` [m/s²] and ``max_jerk`` [m/s³]; ``jump`` the acceleration
    jump without transitions [m/s²] (:func:`acceleration_jump`, infinite jerk);
    ``transfer_time`` from A to C [s]; ``at_limit`` whether the best is the longest
    transition the gap allows."""

    path: TransferPath
    x2: float
    candidates: Array
    peak_jerk: Array
    max_acceleration: float
    max_jerk: float
    jump: float
    transfer_time: float
    at_limit: bool


def design_transfer(
    R_t: float,
    R_p: float,
    gap: float,
    speed: Any,
    *,
    x2_min: float | None = None,
    n_candidates: int = 64,
    n_points: int = 801,
) -> TransferDesign:
    """The transition length x2 (the same on both sides) that minimises the peak
    jerk |da/dt| of the workpiece, for pitch radii ``R_t``, ``R_p`` [m] set ``gap``
    [m] apart (centre distance R_t + R_p + gap) and the speed law ``speed`` (V or
    (V_t, V_p) [m/s], see :meth:`TransferPath.acceleration`). Every candidate,
    from ``x2_min`` (default R_min/100) to the longest the gap allows, is evaluated
    in one vectorised pass over (candidates × ``n_points`` points on each
    transition and on the straight); the best is refined by scipy's bounded scalar
    minimiser.

    >>> import cyclomech as cm
    >>> d = cm.transfer.design_transfer(0.15, 0.25, 0.01, 0.157)
    >>> round(d.x2, 4), d.at_limit, round(d.max_jerk, 3), round(d.jump, 4)
    (0.0788, True, 0.484, 0.2629)
    """
    from scipy.optimize import minimize_scalar

    R_t, R_p = _radius("R_t", R_t), _radius("R_p", R_p)
    gap = positive("gap", gap, "m (between the pitch circles)")
    for name, value, lo in (("n_candidates", n_candidates, 2), ("n_points", n_points, 16)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < lo:
            raise InputError(f"{name} must be an integer ≥ {lo}; got {value!r}")
    r = np.array([R_t, R_p])
    c_t, c_p = np.zeros(2), np.array([R_t + R_p + gap, 0.0])
    top = float(_longest(r, c_t, c_p, np.ones(2))[0])
    low = min(R_t, R_p) / 100.0 if x2_min is None else positive("x2_min", x2_min, "m")
    if low >= top:
        raise InfeasibleError(
            f"x2_min = {low:.6g} m is not below the longest transition the gap of "
            f"{gap:.6g} m allows ({top:.6g} m)"
        )
    _speed_law(speed, 0.0, 1.0)  # checked before the scan
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
    path = TransferPath(R_t, R_p, c_t, c_p, x2=x2 if x2 < top else None)
    acc = path.acceleration(speed)
    v_t, v_p = _speeds(speed)
    jump = acceleration_jump(R_t, v_t / R_t, R_p, v_p / R_p)
    start = int(np.searchsorted(acc.s, path.start_of_transfer))
    end = int(np.searchsorted(acc.s, path.start_of_transfer + path.transfer_length))
    return TransferDesign(
        path=path,
        x2=path.x2_t,
        candidates=cands,
        peak_jerk=peaks,
        max_acceleration=acc.max_acceleration,
        max_jerk=acc.max_jerk,
        jump=float(jump),
        transfer_time=float(acc.time[min(end, acc.time.size - 1)] - acc.time[start]),
        at_limit=bool(x2 >= top * (1 - 1e-6)),
    )


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
