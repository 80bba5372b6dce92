"""The lever with its stop (:class:`StopImpact`): its first rebound against speed and
phase angle, the rebounds of many stops at once (:func:`rebounds`), their largest
admissible impact speeds and the minimum phase angles that follow, and the
cyclogram constraint."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number, float_array, positive, threads_arg
from .._errors import InfeasibleError, InputError
from .._kind import Proportional
from .._units import RAD_PER_S_PER_RPM
from ..cyclogram import Constraint
from ..motion import law as motion_law
from ._checks import Array, _nonnegative, _positive_array
from ._contact import _restitution_damping, contact_sample
from ._lever import _propped_ratio, _restitution, contact_time, impact_force, lever_stiffness
from ._pulse import Pulse, _pulse_at
from ._response import duhamel, first_rebound

__all__ = ["StopImpact", "max_impact_speeds", "min_phase_angles", "rebounds"]


#: Relative tolerances a search can meet: rounding of the rebounds is ~1e-16, so
#: below 1e-15 a tolerance would be claimed but not met; 1 or more is no
#: tolerance at all (the bracket [0, v] already meets it).
_RTOL_RANGE = (1e-15, 0.5)


def _rtol(name: str, value: Any, scale: float = 1.0, unit: str = "(relative)") -> float:
    """A tolerance in [1e-15, 0.5]·``scale``, or :class:`InputError` with the range."""
    lo, hi = _RTOL_RANGE[0] * scale, _RTOL_RANGE[1] * scale
    v = finite_number(name, value, unit, low=0.0, strict=True)
    if not lo <= v <= hi:
        raise InputError(f"{name} = {value!r} must lie in [{lo:g}, {hi:g}] {unit}")
    return v


_half_period = contact_time  # for StopImpact, whose argument shadows the name


_PULSES = ("decaying", "rectangular", "triangular", "half_sine")


def rebounds(
    stops: Sequence[StopImpact], v0: npt.ArrayLike, *, n_threads: int | None = None
) -> Array:
    """First rebound [m] of stop i hit at the speeds ``v0[i]`` [m/s], shape (S, W):
    the rebound depends on the speed and phase angle only through the impact
    speed. Pulse-model stops with the same pulse table go into one Rust call
    (per-case frequency, damping and mass); a contact-model stop takes one call.

    >>> import numpy as np, cyclomech as cm
    >>> a, b = cm.impact.StopImpact.example(), cm.impact.StopImpact.example(zeta=0.2)
    >>> r = cm.impact.rebounds([a, b], [[0.2, 0.3], [0.2, 0.3]])
    >>> r.shape, bool(r[1, 0] < r[0, 0]), bool(np.isclose(r[0, 1] / r[0, 0], 1.5))
    ((2, 2), True, True)
    """
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
        pulse = stops[rows[0]]._shape()
        w = v.shape[1]
        case = {
            k: np.repeat([getattr(stops[i], k) for i in rows], w)
            for k in ("omega_free", "zeta", "mass", "restitution")
        }
        speed = v[rows].reshape(-1)
        impulse = case["mass"] * (1.0 + case["restitution"]) * speed  # J_A·ω0·(1+k)/l
        out[rows] = first_rebound(
            pulse.t,
            np.multiply.outer(impulse, pulse.f),
            case["omega_free"],
            case["zeta"],
            case["mass"],
            0.0,
            -speed,
            maximum=True,
            n_threads=threads,
        ).q.reshape(len(rows), w)
    return out


#: Relative margin below the largest admissible impact speed (see max_impact_speeds).
_SPEED_MARGIN = 1e-13


def max_impact_speeds(
    stops: Sequence[StopImpact],
    a_max: npt.ArrayLike,
    *,
    rtol: float = 1e-12,
    n_threads: int | None = None,
) -> Array:
    """The largest impact speed v* [m/s] of each stop whose first rebound is at most
    its ``a_max`` [m] (inf if every speed up to 1e9 m/s is; 0 if none is), to
    ``rtol`` relative (in [1e-15, 0.5]: the rebounds' rounding is ~1e-16, and a
    wider tolerance is none), shape (S,). The speed returned is admissible with a margin
    of 1e-13 (relative), so that angles worked out from it are too: the rebounds'
    rounding is ~1e-16, the angles' tolerance 1e-9°. The pulse
    model's rebound is g·v0 (linear), so v* = a_max/g from one evaluation per
    stop. The contact model's grows with v0, but not in proportion, so its v* is
    bracketed on a grid of 64 speeds from 1e-9 to 1e9 m/s and the bracket
    narrowed on grids of 64, about 8 steps. Each step evaluates all the stops in
    one :func:`rebounds` call; results are remembered per stop and parameters.

    >>> import cyclomech as cm
    >>> stops = [cm.impact.StopImpact.example(), cm.impact.StopImpact.example(zeta=0.2)]
    >>> v = cm.impact.max_impact_speeds(stops, 0.1e-3)
    >>> [round(float(x), 4) for x in v]
    [0.2909, 0.3657]
    """
    n = len(stops)
    a = np.broadcast_to(float_array("a_max", a_max, ndims=(0, 1)), (n,)).copy()
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
        with np.errstate(divide="ignore"):
            vl = np.where(g > 0.0, a[lin] / g * (1.0 - _SPEED_MARGIN), np.inf)
        for _ in range(8):
            fin = np.flatnonzero(np.isfinite(vl))
            if not fin.size:
                break
            at = rebounds([stops[lin[j]] for j in fin], vl[fin, None], n_threads=n_threads)
            over = fin[at[:, 0] > a[np.array(lin)[fin]]]
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
    """Smallest phase angles [deg] n·``per_rpm`` at speeds ``rpm`` [rpm] (finite,
    > 0; broadcast) with ``per_rpm`` [deg/rpm] finite and ≥ 0, at least 1e-9°, NaN
    where over 360° (no phase angle of one turn will do).

    >>> import cyclomech as cm
    >>> cm.impact.min_phase_angles([100.0, 200.0, 400.0], 0.1).tolist()
    [10.0, 20.0, 40.0]
    """
    # float_array checks the dtype; np.asarray keeps a scalar 0-d.
    n = _positive_array("rpm", np.asarray(float_array("rpm", rpm, ndims=(0, 1, 2))), "[rpm]")
    n = n.reshape(np.shape(rpm))
    k = float_array("per_rpm", per_rpm, ndims=(0, 1, 2)).reshape(np.shape(per_rpm))
    bad = ~(np.isfinite(k) & (k >= 0.0))
    if bad.any():
        v = k.reshape(-1)[int(np.argmax(bad.reshape(-1)))]
        raise InputError(f"per_rpm = {float(v)!r} must be finite and ≥ 0 [deg/rpm]")
    return Proportional.evaluate(n, k)


class StopImpact:
    """A cam-driven lever that strikes its limit stop (seed 000).

    The cam moves the lever's working point through ``stroke`` [m] by the rise
    ``law`` (a name of :mod:`cyclomech.motion`, full-rise form) over the phase
    angle t of the operation; the stop sits ``preload`` [m] short of the end of
    the stroke, so the lever meets it where Z(j*) = 1 − preload/stroke, with the
    working point's speed v0 = ω_shaft·stroke·Z'(j*)/t (ω0 = v0/l), which grows
    with the speed n and shrinks as t grows.

    The lever: length ``lever_length`` l [m], inertia ``J_A`` [kg·m²] about its
    axis, arms ``a``, ``b`` [m], ``E`` [Pa] and ``J_x`` [m⁴] (its free stiffness
    c = 3EJ_x/((a+b)b²), :func:`lever_stiffness`), reduced ``mass`` at the
    working point (default J_A/l² [kg]); ``restitution`` k (5/9 for steel);
    damping ratio ``zeta`` of the free vibration. In contact the stop props the
    lever: ``contact_stiffness`` [N/m] defaults to c times the stiffening that a
    prop at the end of the overhang gives its middle
    (:func:`propped_lever_stiffness`).

    Two models of the first rebound:

    * ``model="pulse"`` (the seed's): the oscillator (free stiffness) starts at
      the stop with −v0 (towards it) and receives the impact pulse (``pulse``
      shape, duration ``contact_time``, default half the period of the contact
      vibration), whose impulse J_A·ω0·(1+k)/l turns the speed round to k·v0;
      the rebound is the first maximum of the displacement away from the stop,
      by the exact peak-only kernel. It is proportional to v0.
    * ``model="contact"``: the stop as a unilateral contact (stiffness switching
      at the stop, the free spring's equilibrium ``preload`` inside it, the
      contact damped so that a single impact has restitution k), solved exactly
      event by event; the rebound is the highest point of the first free flight.

    >>> import cyclomech as cm
    >>> lifter = cm.impact.StopImpact.example()
    >>> a = lifter.rebound([280, 420], 40.0)          # m, at a 40° phase angle
    >>> [round(float(v) * 1e3, 3) for v in a]         # mm
    [0.07, 0.105]
    """

    def __init__(
        self,
        *,
        law: str = "modified_sine",
        stroke: float,
        preload: float,
        lever_length: float,
        J_A: float,
        a: float,
        b: float,
        E: float,
        J_x: float,
        mass: float | None = None,
        restitution: float = 5.0 / 9.0,
        zeta: float = 0.05,
        contact_stiffness: float | None = None,
        pulse: str = "decaying",
        contact_time: float | None = None,
        model: str = "pulse",
    ) -> None:
        self.law = motion_law(law, form="rise")
        self.stroke = positive("stroke", stroke, "[m]")
        self.preload = _nonnegative("preload", preload, "[m]")
        if self.preload >= self.stroke:
            raise InputError(
                f"preload = {preload!r} m must be smaller than stroke = {stroke!r} m "
                "(the lever meets the stop before the end of its stroke)"
            )
        self.lever_length = positive("lever_length", lever_length, "[m]")
        self.J_A = positive("J_A", J_A, "[kg·m²]")
        self.a, self.b = positive("a", a, "[m]"), positive("b", b, "[m]")
        self.E, self.J_x = positive("E", E, "[Pa]"), positive("J_x", J_x, "[m⁴]")
        self.mass = (
            self.J_A / self.lever_length**2 if mass is None else positive("mass", mass, "[kg]")
        )
        self.restitution = _restitution(restitution)
        self.zeta = _nonnegative("zeta", zeta, "(damping ratio)")
        self.stiffness = lever_stiffness(self.E, self.J_x, self.a, self.b)
        if contact_stiffness is None:
            self.contact_stiffness = self.stiffness * _propped_ratio(self.a, self.b)
        else:
            self.contact_stiffness = positive("contact_stiffness", contact_stiffness, "[N/m]")
            if self.contact_stiffness <= self.stiffness:
                raise InputError(
                    f"contact_stiffness = {contact_stiffness!r} N/m must exceed the free "
                    f"stiffness {self.stiffness:.6g} N/m (the stop adds a support)"
                )
        if pulse not in _PULSES:
            raise InputError(f"pulse = {pulse!r} is not a shape; choose one of {_PULSES}")
        self.pulse = pulse
        self.contact_time = (
            float(_half_period(self.contact_stiffness, self.mass))
            if contact_time is None
            else positive("contact_time", contact_time, "[s]")
        )
        if model not in ("pulse", "contact"):
            raise InputError(f"model = {model!r} must be 'pulse' or 'contact'")
        self.model = model
        # Where the lever meets the stop: Z(j*) = 1 − preload/stroke (Z rises), on
        # grids of 64 values, each a vectorised law call, down to adjacent doubles.
        target = 1.0 - self.preload / self.stroke
        lo, hi = 0.0, 1.0
        for _ in range(16):
            grid = np.linspace(lo, hi, 66)[1:-1]
            below = self.law.z(grid) < target
            k = int(np.argmin(below)) if not below.all() else grid.size
            lo = float(grid[k - 1]) if k > 0 else lo
            hi = float(grid[k]) if k < grid.size else hi
            if hi - lo <= 2.0 * np.spacing(hi):
                break
        self.j_contact = 0.5 * (lo + hi)
        self.dz_contact = float(self.law.dz(self.j_contact))

    @property
    def omega_free(self) -> float:
        """Natural angular frequency of the free lever, √(c/m) [rad/s].

        >>> import cyclomech as cm
        >>> round(cm.impact.StopImpact.example().omega_free / (2 * 3.141592653589793))
        297
        """
        return math.sqrt(self.stiffness / self.mass)

    @property
    def omega_contact(self) -> float:
        """Natural angular frequency in contact, √(c_contact/m) [rad/s].

        >>> import cyclomech as cm
        >>> round(cm.impact.StopImpact.example().omega_contact / (2 * 3.141592653589793))
        752
        """
        return math.sqrt(self.contact_stiffness / self.mass)

    def _shape(self) -> Pulse:
        """The pulse of unit impulse [N·s]."""
        tau = self.contact_time
        make = {
            "decaying": lambda: Pulse.decaying(1.0, tau),
            "rectangular": lambda: Pulse.rectangular(1.0, tau),
            "triangular": lambda: Pulse.triangular(1.0, tau),
            "half_sine": lambda: Pulse.half_sine(1.0, tau),
        }[self.pulse]()
        return make.scaled(1.0 / make.impulse)

    def impact_speed(self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike) -> Any:
        """Speed v0 [m/s] of the working point as it meets the stop, at main-shaft
        speed ``rpm`` and phase angle ``phase_deg`` [deg] (broadcast).

        >>> import cyclomech as cm
        >>> round(float(cm.impact.StopImpact.example().impact_speed(280, 40.0)), 4)
        0.2038
        """
        n = _positive_array("rpm", rpm, "[rpm]")
        t = _phase(phase_deg)
        return n * RAD_PER_S_PER_RPM * self.stroke * self.dz_contact / np.radians(t)

    def impact_force(self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike) -> Any:
        """Mean impact force F = J_A·ω0·(1+k)/(l·τ) [N] (the seed's F_уд).

        >>> import cyclomech as cm
        >>> round(float(cm.impact.StopImpact.example().impact_force(280, 40.0)), 2)
        3.53
        """
        w0 = self.impact_speed(rpm, phase_deg) / self.lever_length
        return impact_force(self.J_A, w0, self.restitution, self.lever_length, self.contact_time)

    def rebound(
        self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike, *, n_threads: int | None = None
    ) -> Any:
        """First-rebound amplitude [m] at speeds ``rpm`` and phase angles
        ``phase_deg`` [deg] (arrays broadcast; one Rust call for all of them).

        >>> import numpy as np, cyclomech as cm
        >>> a = cm.impact.StopImpact.example().rebound(np.array([[280], [420]]), [40, 60])
        >>> a.shape, bool(a[1, 0] > a[0, 0] > a[0, 1])
        ((2, 2), True)
        """
        v0 = np.asarray(self.impact_speed(rpm, phase_deg), dtype=np.float64)
        return rebounds([self], v0.reshape(1, -1), n_threads=n_threads).reshape(v0.shape)

    def response(
        self, rpm: float, phase_deg: float, *, duration: float | None = None, points: int = 2001
    ) -> tuple[Array, Array]:
        """The motion after the impact at one speed and phase angle: ``(t [s], q
        [m])``, q the displacement of the working point away from the stop, t from
        the instant of contact over ``duration`` (default 6 free periods), with
        the pulse's breakpoints on the grid (pulse model: exact Duhamel response;
        contact model: the exact event-driven motion).

        >>> import cyclomech as cm
        >>> t, q = cm.impact.StopImpact.example().response(280, 40.0)
        >>> round(float(q.max()) * 1e3, 3)                   # mm: the first rebound
        0.07
        """
        v0 = float(self.impact_speed(float(rpm), float(phase_deg)))
        span = 12.0 * math.pi / self.omega_free if duration is None else float(duration)
        span = positive("duration", span, "[s]")
        points = count("points", points, low=2, high=10**8)
        if self.model == "contact":
            t = np.linspace(0.0, span, points)
            x, _v = contact_sample(
                t,
                mass=self.mass,
                k_free=self.stiffness,
                k_stop=self.contact_stiffness - self.stiffness,
                preload=self.preload,
                zeta_free=self.zeta,
                zeta_contact=_restitution_damping(self.restitution),
                v0=-v0,
            )
            return t, x
        shape = self._shape()
        pulse_t = shape.t[shape.t < span]
        t = np.union1d(np.linspace(0.0, span, points), pulse_t)
        # Repeated breakpoints (jumps) stay repeated: the force there is two-valued.
        jumps = shape.t[1:][np.diff(shape.t) == 0.0]
        t = np.sort(np.concatenate([t, jumps[jumps < span]]))
        f = self.mass * (1.0 + self.restitution) * v0 * _pulse_at(shape, t)
        q = duhamel(t, f, omega_n=self.omega_free, zeta=self.zeta, mass=self.mass, q0=0.0, v0=-v0)
        return t, q

    def _max_speed_key(self, a_max: float, rtol: float) -> tuple[Any, ...]:
        """What v* depends on: a_max, rtol and the parameters of the rebound."""
        key = (a_max, rtol, self.model, self.pulse, self.contact_time, self.mass)
        return (
            *key,
            self.stiffness,
            self.contact_stiffness,
            self.preload,
            self.zeta,
            self.restitution,
        )

    def max_impact_speed(
        self, a_max: float, *, rtol: float = 1e-12, n_threads: int | None = None
    ) -> float:
        """The largest impact speed v* [m/s] whose first rebound is at most ``a_max``
        [m] (inf if every speed up to 1e9 m/s is; 0 if none is), to ``rtol``
        relative (:func:`max_impact_speeds` for one stop).

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> v = lifter.max_impact_speed(0.1e-3)        # the impact speed at t_min, any rpm
        >>> t = lifter.min_phase_angle(0.1e-3, 280)
        >>> round(v, 6), round(float(lifter.impact_speed(280, t)), 6)
        (0.290929, 0.290929)
        """
        return float(max_impact_speeds([self], a_max, rtol=rtol, n_threads=n_threads)[0])

    def phase_per_rpm(self, v_star: float) -> float:
        """The phase angle per rpm [deg/rpm] at which the impact speed is ``v_star``
        [m/s]: t = n·(360/60)·stroke·Z'/v* (degrees of a turn of 2π·n/60 rad/s);
        0 for v* = inf, inf for v* = 0.

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> round(280 * lifter.phase_per_rpm(lifter.max_impact_speed(0.1e-3)), 6)
        28.027142
        """
        with np.errstate(divide="ignore"):
            per_rpm = np.degrees(RAD_PER_S_PER_RPM * self.stroke * self.dz_contact)
            return float(per_rpm / np.float64(v_star))

    def min_phase_angle(
        self,
        a_max: float,
        rpm: npt.ArrayLike,
        *,
        tol_deg: float = 1e-9,
        n_threads: int | None = None,
    ) -> Any:
        """Smallest phase angle [deg] whose first rebound is at most ``a_max`` [m],
        at each speed ``rpm``, to ``tol_deg`` (in [3.6e-13, 180]°: 360° times the
        range of :func:`max_impact_speeds`' ``rtol``); NaN where even 360° is too short.

        The rebound depends on the speed n and the phase angle t only through the
        impact speed v0 = (2π·n/60)·stroke·Z'/t (:meth:`impact_speed`) and grows
        with it, so t_min = (2π·n/60)·stroke·Z'/v* at every speed, with v* the
        largest admissible impact speed (:meth:`max_impact_speed`): one search for
        all speeds. At least 1e-9°.

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> t = lifter.min_phase_angle(0.1e-3, 280)
        >>> round(float(t), 6), round(float(lifter.rebound(280, t)) * 1e3, 9)
        (28.027142, 0.1)
        """
        n = np.asarray(_positive_array("rpm", rpm, "[rpm]"), dtype=np.float64)
        tol = _rtol("tol_deg", tol_deg, 360.0, "[deg]")
        # t ≤ 360° and |Δt| ≤ t·Δv/v*: a relative bracket of tol/360 is enough.
        v = self.max_impact_speed(a_max, rtol=tol / 360.0, n_threads=n_threads)
        return min_phase_angles(n, self.phase_per_rpm(v))[()]  # a float for a scalar speed

    def linearize(
        self, phase_deg_range: tuple[float, float], rpm: float, points: int = 64
    ) -> tuple[float, float]:
        """Least-squares line a(t) ≈ slope·t + intercept over ``phase_deg_range``
        [deg] at ``rpm``: ``(slope [m/deg], intercept [m])``, the seed's form
        a(3,7) = −0.003·t + 0.208 (mm, deg).

        >>> import cyclomech as cm
        >>> s, c = cm.impact.StopImpact.example().linearize((30, 45), 420)
        >>> round(s * 1e3, 4), round(c * 1e3, 3)                   # mm/deg, mm
        (-0.0031, 0.229)
        """
        lo, hi = (_phase(v) for v in phase_deg_range)
        if not hi > lo:
            raise InputError(
                f"phase_deg_range = {phase_deg_range!r} must be (low, high) with low < high"
            )
        points = count("points", points, low=2, high=10**7)
        slope, intercept = self._lines(
            np.array([float(rpm)]), np.array([lo]), np.array([hi]), points
        )
        return float(slope[0]), float(intercept[0])

    def _lines(self, rpm: Array, lo: Array, hi: Array, points: int) -> tuple[Array, Array]:
        """The seed's linearisation, the one place it is computed: per speed
        ``rpm[i]``, the least-squares line through the first rebound at ``points``
        phase angles from ``lo[i]`` to ``hi[i]`` [deg] (one rebound call for all;
        the normal equations in closed form)."""
        t = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, points)[None, :]
        a = self.rebound(rpm[:, None], t)
        tm, am = t.mean(axis=1, keepdims=True), a.mean(axis=1, keepdims=True)
        slope = ((t - tm) * (a - am)).sum(axis=1) / ((t - tm) ** 2).sum(axis=1)
        return slope, am[:, 0] - slope * tm[:, 0]

    def linear_min_phase_angle(
        self, a_max: float, rpm: npt.ArrayLike, *, points: int = 64, n_threads: int | None = None
    ) -> Any:
        """The seed's linearised smallest phase angle [deg] at each speed ``rpm``:
        the rebound fitted by a line slope·t + intercept over 0.5…2 times the exact
        angle (capped at 360°; as :meth:`constraint` with ``linear=True``), then
        t = (a_max − intercept)/slope; NaN where the exact angle is. One rebound
        call for all speeds.

        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> round(float(lifter.linear_min_phase_angle(1e-4, 280.0)), 2)     # exact: 28.03
        32.67
        """
        points = count("points", points, low=2, high=1_000_000)
        n = np.asarray(rpm, dtype=np.float64)
        flat = n.reshape(-1)
        exact = np.asarray(self.min_phase_angle(a_max, flat, n_threads=n_threads)).reshape(-1)
        ok = np.isfinite(exact)
        out = np.full(flat.shape, np.nan)
        if ok.any():
            lo, hi = 0.5 * exact[ok], np.minimum(2.0 * exact[ok], 360.0)
            slope, intercept = self._lines(flat[ok], lo, hi, points)
            out[ok] = (float(a_max) - intercept) / slope
        return out.reshape(n.shape) if n.ndim else float(out[0])

    def constraint(
        self, arc: tuple[str, str], a_max: float, rpm: float, *, linear: bool = False
    ) -> Constraint:
        """The cyclogram constraint rebound(t(arc)) ≤ ``a_max`` [m] at ``rpm``:
        exact, t(arc) ≥ :meth:`min_phase_angle` (default), or the seed's
        linearised slope·t + intercept ≤ a_max over 0.5…2 times that angle
        (``linear=True``). Pass it to :meth:`cyclomech.Cyclogram.add_constraint`.

        >>> import cyclomech as cm
        >>> c = cm.impact.StopImpact.example().constraint(("3", "7"), 0.1e-3, 280)
        >>> c.describe()
        '1·t(3,7) >= 28.0271'
        """
        if not (
            isinstance(arc, tuple | list)
            and len(arc) == 2
            and all(isinstance(e, str) and e for e in arc)
        ):
            raise InputError(
                f'arc = {arc!r} must be an operation\'s two event names (from, to), e.g. ("3", "7")'
            )
        arc = (arc[0], arc[1])
        t_min = float(self.min_phase_angle(a_max, float(rpm)))
        if not math.isfinite(t_min):
            raise InfeasibleError(
                f"rebound stays above a_max = {a_max!r} m at {rpm!r} rpm for every phase "
                "angle up to 360°",
                [f"{arc[0]}→{arc[1]}"],
            )
        name = f"rebound{arc[0]}-{arc[1]}"
        if not linear:
            return Constraint(((arc, 1.0),), ">=", t_min, name)
        slope, intercept = self.linearize((0.5 * t_min, min(2.0 * t_min, 360.0)), float(rpm))
        return Constraint(((arc, slope),), "<=", float(a_max) - intercept, name)

    @classmethod
    def example(cls, **overrides: Any) -> StopImpact:
        """An illustrative microshuttle lifter in the spirit of the STB loom's
        (seed 000): not measured data. A steel lever 100 mm long (arms 50 and 100
        mm, a section of 6.14e-11 m⁴, about 8 × 4.5 mm), 7.4 g reduced to its
        working point, free at 297 Hz and 752 Hz in contact, a modified-sine rise of
        9.4 mm with 0.25 mm preload. Its first rebound at a 40° phase angle is 0.070,
        0.080, 0.093, 0.105 mm at 280, 320, 370, 420 rpm (the seed: 0.07, 0.078,
        0.092, 0.105 mm), and its linearisation over 30–45° at 420 rpm is
        −0.0031·t + 0.229 mm (the seed: −0.003·t + 0.208).

        >>> import cyclomech as cm
        >>> cm.impact.StopImpact.example().preload
        0.00025
        """
        data: dict[str, Any] = dict(
            law="modified_sine",
            stroke=9.4e-3,
            preload=0.25e-3,
            lever_length=0.1,
            J_A=7.4e-5,
            a=0.05,
            b=0.1,
            E=2.1e11,
            J_x=6.14e-11,
            restitution=5.0 / 9.0,
            zeta=0.05,
        )
        data.update(overrides)
        return cls(**data)

    def __repr__(self) -> str:
        return (
            f"StopImpact(law={self.law.name!r}, stroke={self.stroke!r}, preload={self.preload!r}, "
            f"f_free={self.omega_free / (2 * math.pi):.4g} Hz, "
            f"f_contact={self.omega_contact / (2 * math.pi):.4g} Hz, model={self.model!r})"
        )


def _phase(value: Any) -> Any:
    try:
        t = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"phase_deg must be angles in degrees; got {value!r}") from None
    bad = ~(np.isfinite(t) & (t > 0.0) & (t <= 360.0))
    if bad.any():
        v = t.reshape(-1)[int(np.argmax(bad.reshape(-1)))]
        raise InputError(f"phase_deg = {float(v)!r} must lie in (0, 360] degrees")
    return t
