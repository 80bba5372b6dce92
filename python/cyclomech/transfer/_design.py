"""The transition length that minimises the peak jerk (:func:`design_transfer`),
every candidate evaluated in one Rust call (``cyclomech_core::transfer::peak_jerk``:
the geometry, the quintics, trapezoid arc lengths, the speed law and the jerk on
m points of each piece, candidates in parallel)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from .._arrays import check_bytes, positive, threads_arg
from .._errors import InfeasibleError, InputError
from ._checks import Array, _radius, _speeds
from ._jump import acceleration_jump
from ._path import TransferPath, _longest

__all__ = ["TransferDesign", "design_transfer"]


@dataclass(frozen=True)
class TransferDesign:
    """:func:`design_transfer`'s result: the transition length that minimises the peak jerk.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    path : TransferPath
        The chosen path.
    x2 : float
        Its transition length [m].
    candidates : ndarray of float
        The transition lengths evaluated [m].
    peak_jerk : ndarray of float
        The peak jerk of every candidate [m/s³].
    max_acceleration : float
        The largest acceleration on the chosen path [m/s²].
    max_jerk : float
        The largest jerk on the chosen path [m/s³].
    jump : float
        The acceleration jump without transitions [m/s²] (:func:`acceleration_jump`;
        infinite jerk).
    transfer_time : float
        The time from A to C [s].
    at_limit : bool
        Whether the best is the longest transition the gap allows.

    See Also
    --------
    design_transfer : Builds it.

    Examples
    --------
    >>> import cyclomech as cm
    >>> d = cm.transfer.design_transfer(0.15, 0.25, 0.01, 0.157)
    >>> d.candidates.size, round(d.transfer_time, 4), round(d.max_acceleration, 4)
    (64, 1.0168, 0.1643)
    """

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
    n_threads: int | None = None,
) -> TransferDesign:
    """The transition length x2 that minimises the workpiece's peak jerk |da/dt| [m/s³].

    The same x2 on both sides. Every candidate, from ``x2_min`` to the longest the
    gap allows, is evaluated in one Rust call (the GIL released, candidates in
    parallel on ``n_threads`` threads) over ``n_points`` points on each transition
    and on the straight; the best is refined by scipy's bounded scalar minimiser,
    each of its evaluations one Rust call too.

    Parameters
    ----------
    R_t : float
        The pitch radius of the first rotor [m] (> 0).
    R_p : float
        The pitch radius of the second rotor [m] (> 0).
    gap : float
        The gap between the pitch circles [m] (> 0): the centre distance is
        R_t + R_p + gap.
    speed : float or tuple of (float, float)
        The speed law: V or (V_t, V_p) [m/s], see :meth:`TransferPath.acceleration`.
    x2_min : float, optional
        The shortest candidate [m]; default None (R_min/100). Keyword-only, as are
        the parameters below.
    n_candidates : int, default 64
        The number of candidates (≥ 2), geometrically spaced.
    n_points : int, default 801
        The points on each transition and on the straight (≥ 16).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    TransferDesign
        The chosen path and its x2, every candidate's peak jerk, the chosen path's
        peaks, the jump without transitions and the transfer time.

    Raises
    ------
    InputError
        If a radius, the gap, the speed or a count is malformed or out of range.
    InfeasibleError
        If ``x2_min`` is not below the longest transition the gap allows.

    Examples
    --------
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
    threads = threads_arg(n_threads)
    # Sized before anything is allocated: each candidate in flight holds 15 work
    # arrays of n_points doubles (one a thread), the scan 3 of n_candidates.
    busy = min(threads or os.cpu_count() or 1, int(n_candidates))
    check_bytes(
        f"design_transfer(n_candidates={n_candidates}, n_points={n_points})",
        busy * 15.0 * 8.0 * float(n_points) + 3 * 8.0 * float(n_candidates),
        "lower n_points (801 by default) or n_candidates (64 by default)",
    )
    r = np.array([R_t, R_p])
    c_t, c_p = np.zeros(2), np.array([R_t + R_p + gap, 0.0])
    top = float(_longest(r, c_t, c_p, np.ones(2))[0])
    low = min(R_t, R_p) / 100.0 if x2_min is None else positive("x2_min", x2_min, "m")
    if low >= top:
        raise InfeasibleError(
            f"x2_min = {low:.6g} m is not below the longest transition the gap of "
            f"{gap:.6g} m allows ({top:.6g} m)"
        )
    speeds = _speeds(speed)  # checked before the scan
    d = float(c_p[0])

    def scan(x2: Array) -> Array:
        return _core.transfer_peak_jerk((R_t, R_p), d, x2, speeds, n_points, n_threads=threads)

    cands = np.geomspace(low, top, n_candidates)
    peaks = scan(cands)
    i = int(np.argmin(peaks))
    lo, hi = cands[max(i - 1, 0)], cands[min(i + 1, cands.size - 1)]
    best = minimize_scalar(
        lambda x: float(scan(np.array([x]))[0]),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-6 * hi},
    )
    x2 = float(best.x) if best.fun <= peaks[i] else float(cands[i])
    path = TransferPath(R_t, R_p, c_t, c_p, x2=x2 if x2 < top else None)
    acc = path.acceleration(speed, n_threads=threads)
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
