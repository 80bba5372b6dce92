"""Many stops at once: their rebounds (:func:`rebounds`), their largest admissible
impact speeds (:func:`max_impact_speeds`) and the smallest phase angles that follow
(:func:`min_phase_angles`); `_stops` part of :mod:`cyclomech.impact` (its door)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import float_array, instances, positive, threads_arg, tolerance
from .._errors import InputError
from .._kind import proportional_law
from ._checks import Array, _positive_array
from ._contact import _restitution_damping
from ._response import first_rebound

if TYPE_CHECKING:
    from ._stop import StopImpact

__all__ = ["max_impact_speeds", "min_phase_angles", "rebounds"]


#: Relative tolerances a search can meet: rounding of the rebounds is ~1e-16, so
#: below 1e-15 a tolerance would be claimed but not met; 1 or more is no
#: tolerance at all (the bracket [0, v] already meets it).
_RTOL_RANGE = (1e-15, 0.5)


def _rtol(name: str, value: Any, scale: float = 1.0, unit: str = "(relative)") -> float:
    """A tolerance in [1e-15, 0.5]·``scale``, or :class:`InputError` with the range."""
    return tolerance(name, value, _RTOL_RANGE[0] * scale, _RTOL_RANGE[1] * scale, unit)


def _stops(value: Any) -> list[StopImpact]:
    """``stops`` as a list of StopImpact, or a TypeError naming the bad one."""
    from ._stop import StopImpact  # at call time: _stop imports this module

    return instances("stops", value, StopImpact)


_PULSES = ("decaying", "rectangular", "triangular", "half_sine")


def rebounds(
    stops: Sequence[StopImpact], v0: npt.ArrayLike, *, n_threads: int | None = None
) -> Array:
    """First rebound [m] of each stop hit at given impact speeds.

    The rebound depends on the speed and phase angle only through the impact speed.
    The pulse model is linear in it (the lever starts at q = 0 and the pulse's
    impulse is ∝ the speed), so a pulse-model stop's rebound is g·v0, g its rebound
    at 1 m/s: one exact solve per stop (stops with the same pulse table in one Rust
    call), whatever the number of speeds. A contact-model stop is solved at every
    speed (one call per stop).

    Parameters
    ----------
    stops : sequence of StopImpact
        The S stops.
    v0 : array_like of float, shape (S, W)
        The impact speeds of stop i in row i [m/s] (magnitudes: finite, ≥ 0).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    ndarray of float, shape (S, W)
        The first rebound of stop i at speed ``v0[i, j]`` [m].

    Raises
    ------
    InputError
        If ``v0`` is not 2-D with one row per stop or holds a speed that is not
        finite and ≥ 0.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> a, b = cm.impact.StopImpact.example(), cm.impact.StopImpact.example(zeta=0.2)
    >>> r = cm.impact.rebounds([a, b], [[0.2, 0.3], [0.2, 0.3]])
    >>> r.shape, bool(r[1, 0] < r[0, 0]), bool(np.isclose(r[0, 1] / r[0, 0], 1.5))
    ((2, 2), True, True)
    """
    stops = _stops(stops)
    v = float_array("v0", v0, ndims=(2,))
    bad = ~(np.isfinite(v) & (v >= 0.0))
    if bad.any():
        i, j = (int(x) for x in np.argwhere(bad)[0])
        raise InputError(
            f"v0[{i}, {j}] = {float(v[i, j])!r} must be a finite impact speed ≥ 0 [m/s] "
            "(its magnitude)"
        )
    if v.shape[0] != len(stops):
        raise InputError(f"v0 must have one row per stop ({len(stops)}); got shape {v.shape}")
    threads = threads_arg(n_threads)
    out = np.empty_like(v)
    groups: dict[tuple[str, float], list[int]] = {}
    for i, s in enumerate(stops):
        if s.model == "contact":
            out[i] = _core.contact_rebound_batch(
                s.mass,
                s.stiffness,
                s.contact_stiffness - s.stiffness,
                s.preload,
                s.zeta,
                _restitution_damping(s.restitution),
                np.ascontiguousarray(-v[i]),
                n_threads=threads,
            )
        else:
            groups.setdefault((s.pulse, s.contact_time), []).append(i)
    for rows in groups.values():
        out[rows] = _rebound_per_speed([stops[i] for i in rows], threads)[:, None] * v[rows]
    return out


def _rebound_per_speed(stops: Sequence[StopImpact], threads: int | None) -> Array:
    """g [m per m/s] of pulse-model stops sharing one pulse table: the first
    rebound after an impact at 1 m/s, one Rust call for all (``batch_figures``
    takes the same g from ``_core.stop_design_batch``, bit for bit)."""
    pulse = stops[0]._shape()
    case = {
        k: np.array([getattr(s, k) for s in stops], dtype=np.float64)
        for k in ("omega_free", "zeta", "mass", "restitution")
    }
    impulse = case["mass"] * (1.0 + case["restitution"]) * 1.0  # J_A·ω0·(1+k)/l at 1 m/s
    return first_rebound(
        pulse.t,
        np.multiply.outer(impulse, pulse.f),
        case["omega_free"],
        case["zeta"],
        case["mass"],
        0.0,
        -np.ones(len(stops)),
        maximum=True,
        n_threads=threads,
    ).q


#: Relative margin below the largest admissible impact speed (see max_impact_speeds).
_SPEED_MARGIN = 1e-13


def max_impact_speeds(
    stops: Sequence[StopImpact],
    a_max: npt.ArrayLike,
    *,
    rtol: float = 1e-12,
    n_threads: int | None = None,
) -> Array:
    """The largest impact speed v* [m/s] of each stop whose first rebound is at most its ``a_max``.

    inf if every speed up to 1e9 m/s is admissible; 0 if none is. The speed
    returned is admissible with a margin of 1e-13 (relative), so that angles worked
    out from it are too: the rebounds' rounding is ~1e-16, the angles' tolerance
    1e-9°. The pulse model's rebound is g·v0 (linear), so v* = a_max/g from one
    evaluation per stop. The contact model's grows with v0, but not in proportion,
    so its v* is bracketed on a grid of 64 speeds from 1e-9 to 1e9 m/s and the
    bracket narrowed on grids of 64, about 8 steps. Each step evaluates all the
    stops in one :func:`rebounds` call; results are remembered per stop and
    parameters.

    Parameters
    ----------
    stops : sequence of StopImpact
        The S stops.
    a_max : float or array_like of float, shape (S,)
        The largest admissible rebound of each stop [m] (> 0; a scalar for all).
    rtol : float, default 1e-12
        The relative tolerance on v*, in [1e-15, 0.5] (the rebounds' rounding is
        ~1e-16, and a wider tolerance is none). Keyword-only.
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    ndarray of float, shape (S,)
        The largest admissible impact speed v* of each stop [m/s].

    Raises
    ------
    InputError
        If an ``a_max`` is not finite and positive or ``rtol`` lies outside its range.

    Examples
    --------
    >>> import cyclomech as cm
    >>> stops = [cm.impact.StopImpact.example(), cm.impact.StopImpact.example(zeta=0.2)]
    >>> v = cm.impact.max_impact_speeds(stops, 0.1e-3)
    >>> [round(float(x), 4) for x in v]
    [0.2909, 0.3657]
    """
    stops = _stops(stops)
    n = len(stops)
    a = float_array("a_max", a_max, ndims=(0, 1))
    if a.size not in (1, n):
        raise InputError(f"a_max must be one limit or one a stop ({n}); got {a.size}")
    a = np.broadcast_to(a, (n,)).copy()
    for i, ai in enumerate(a):
        positive(f"a_max[{i}]" if n > 1 else "a_max", ai, "[m]")
    r = _rtol("rtol", rtol)
    out = np.empty(n)
    keys = [s._max_speed_key(ai, r) for s, ai in zip(stops, a, strict=True)]
    todo = []
    for i, (s, key) in enumerate(zip(stops, keys, strict=True)):
        memo = s.__dict__.get("_max_speed_memo", {})
        if key in memo:
            out[i] = memo[key]
        else:
            todo.append(i)
    if not todo:
        return out
    v = np.full(n, np.nan)
    # The pulse model is linear in v0 (the lever starts at v0, the pulse's impulse
    # is ∝ v0): rebound = g·v0, so v* = a_max/g (less the margin), stepped down by
    # ulps until admissible should rounding still put it over.
    lin = [i for i in todo if stops[i].model == "pulse"]
    if lin:
        g = rebounds([stops[i] for i in lin], np.ones((len(lin), 1)), n_threads=n_threads)[:, 0]
        al = a[lin]
        with np.errstate(divide="ignore"):
            vl = np.where(g > 0.0, al / g * (1.0 - _SPEED_MARGIN), np.inf)
        for _ in range(8):
            over = np.flatnonzero(np.isfinite(vl) & (g * vl > al))
            if not over.size:
                break
            vl[over] = np.nextafter(vl[over], 0.0) * (1.0 - 2.0 * np.finfo(float).eps)
        v[lin] = vl
    idx = np.array([i for i in todo if stops[i].model != "pulse"], dtype=np.intp)
    lo, hi = np.zeros(idx.size), np.full(idx.size, np.inf)
    grid = np.tile(np.logspace(-9.0, 9.0, 64), (idx.size, 1))
    active = np.arange(idx.size)
    for _ in range(64):
        if not active.size:
            break
        heights = rebounds([stops[i] for i in idx[active]], grid[active], n_threads=n_threads)
        fine = heights <= a[idx[active], None]
        k = np.where(fine.all(axis=1), 64, np.argmin(fine, axis=1))
        lo[active] = np.where(k > 0, grid[active, np.maximum(k - 1, 0)], lo[active])
        hi[active] = np.where(k < 64, grid[active, np.minimum(k, 63)], hi[active])
        h = hi[active]
        done = ~np.isfinite(h) | (h - lo[active] <= r * h)
        active = active[~done]
        grid[active] = np.linspace(lo[active], hi[active], 66, axis=1)[:, 1:-1]
    v[idx] = np.where(np.isfinite(hi), lo * (1.0 - _SPEED_MARGIN), np.inf)
    for i in todo:
        memo = stops[i].__dict__.setdefault("_max_speed_memo", {})
        if len(memo) >= 64:
            memo.clear()
        memo[keys[i]] = out[i] = v[i]
    return out


def min_phase_angles(rpm: npt.ArrayLike, per_rpm: npt.ArrayLike) -> Array:
    """Smallest phase angles [deg] n·``per_rpm`` at speeds n.

    At least 1e-9°, NaN where over 360° (no phase angle of one turn will do).

    Parameters
    ----------
    rpm : float or array_like of float
        The speeds n [rpm] (finite, > 0); broadcasts with ``per_rpm``.
    per_rpm : float or array_like of float
        The phase angle per rpm [deg/rpm] (≥ 0; +inf: no speed will do), e.g. from
        :meth:`StopImpact.phase_per_rpm`.

    Returns
    -------
    ndarray of float
        The smallest phase angles [deg], of the broadcast shape.

    Raises
    ------
    InputError
        If a speed is not finite and positive or a ``per_rpm`` is NaN or negative.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.impact.min_phase_angles([100.0, 200.0, 400.0], 0.1).tolist()
    [10.0, 20.0, 40.0]
    >>> cm.impact.min_phase_angles(100.0, float("inf")).tolist()   # no phase angle will do
    nan
    """
    # float_array checks the dtype; np.asarray keeps a scalar 0-d.
    n = _positive_array("rpm", np.asarray(float_array("rpm", rpm, ndims=(0, 1, 2))), "[rpm]")
    n = n.reshape(np.shape(rpm))
    k = float_array("per_rpm", per_rpm, ndims=(0, 1, 2)).reshape(np.shape(per_rpm))
    bad = ~(k >= 0.0)  # NaN too
    if bad.any():
        v = k.reshape(-1)[int(np.argmax(bad.reshape(-1)))]
        raise InputError(f"per_rpm = {float(v)!r} must be ≥ 0 [deg/rpm] (inf: no speed)")
    return proportional_law(n, k)
