"""The lever with its stop (:class:`StopImpact`): its first rebound against speed and
phase angle, its largest admissible impact speed and the minimum phase angles that
follow, and the cyclogram constraint (many stops at once: ``_stops``)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import broadcast, count, finite_number, flag, float_array, positive, real_array
from .._errors import InfeasibleError, InputError
from .._numtext import number_text
from .._units import RAD_PER_S_PER_RPM
from ..cyclogram import Constraint
from ..motion import law as motion_law
from ._checks import Array, _nonnegative, _positive_array
from ._contact import _restitution_damping, contact_sample
from ._lever import _propped_ratio, _restitution, contact_time, impact_force, lever_stiffness
from ._pulse import Pulse, _pulse_at
from ._response import duhamel
from ._stops import _PULSES, _rtol, max_impact_speeds, min_phase_angles, rebounds

__all__ = ["StopImpact"]

_half_period = contact_time  # for StopImpact, whose argument shadows the name


class StopImpact:
    """A cam-driven lever that strikes its limit stop (seed 000).

    The cam moves the lever's working point through ``stroke`` by the rise ``law``
    (full-rise form) over the phase angle t of the operation; the stop sits
    ``preload`` short of the end of the stroke, so the lever meets it where
    Z(j*) = 1 − preload/stroke, with the working point's speed
    v0 = ω_shaft·stroke·Z'(j*)/t (ω0 = v0/l), which grows with the speed n and
    shrinks as t grows.

    The lever's free stiffness is c = 3EJ_x/((a+b)b²) (:func:`lever_stiffness`).
    In contact the stop props the lever: ``contact_stiffness`` defaults to c times
    the stiffening that a prop at the end of the overhang gives its middle
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

    Parameters
    ----------
    law : str, default "modified_sine"
        The cam's rise law, a name of :mod:`cyclomech.motion` (full-rise form).
        All the parameters are keyword-only.
    stroke : float
        The travel of the working point [m].
    preload : float
        How far short of the end of the stroke the stop sits [m] (0 ≤ preload <
        stroke).
    lever_length : float
        The lever's length l [m].
    J_A : float
        The lever's moment of inertia about its axis [kg·m²].
    a : float
        The arm between the lever's axis and the cam roller [m].
    b : float
        The overhang from the roller to the working point [m].
    E : float
        Young's modulus of the lever [Pa].
    J_x : float
        The section's axial moment of inertia [m⁴].
    mass : float, optional
        The mass reduced to the working point [kg]; default None (J_A/l²).
    restitution : float, default 5/9
        The coefficient of restitution k ∈ [0, 1] (5/9 for steel).
    zeta : float, default 0.05
        The damping ratio of the free vibration (≥ 0; ζ ≥ 1, a critically or
        over-damped lever, is valid too: the response is exact for every ζ, and the
        first rebound is then the first extremum of q, as for ζ < 1).
    contact_stiffness : float, optional
        The stiffness in contact [N/m], above the free stiffness; default None (the
        propped lever's, see above).
    pulse : {"decaying", "rectangular", "triangular", "half_sine"}, default "decaying"
        The impact pulse's shape (pulse model).
    contact_time : float, optional
        The pulse's duration [s]; default None (half the period of the contact
        vibration, :func:`contact_time`).
    model : {"pulse", "contact"}, default "pulse"
        The model of the first rebound.

    Attributes
    ----------
    law : MotionLaw
        The rise law (full-rise form).
    stiffness : float
        The free stiffness c of the lever at its working end [N/m].
    contact_stiffness : float
        The stiffness in contact [N/m] (given or the default).
    mass : float
        The reduced mass [kg] (given or J_A/l²).
    contact_time : float
        The pulse's duration [s] (given or the default).
    j_contact : float
        Where the lever meets the stop, j* with Z(j*) = 1 − preload/stroke
        (dimensionless).
    dz_contact : float
        Z'(j*), the law's dimensionless speed there.

    Raises
    ------
    InputError
        If a value is missing, not finite or out of range: ``preload`` not below
        ``stroke``, ``contact_stiffness`` not above the free stiffness, an unknown
        law, ``pulse`` or ``model``.

    Examples
    --------
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
                f"preload = {preload!r} m must be smaller than stroke = "
                f"{number_text(self.stroke, self.preload)} m "
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

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.impact.StopImpact.example().omega_free / (2 * 3.141592653589793))
        297
        """
        return math.sqrt(self.stiffness / self.mass)

    @property
    def omega_contact(self) -> float:
        """Natural angular frequency in contact, √(c_contact/m) [rad/s].

        Examples
        --------
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
        """Speed v0 [m/s] of the working point as it meets the stop.

        Parameters
        ----------
        rpm : float or array_like of float
            The main shaft's speed [rpm] (> 0); broadcasts with ``phase_deg``.
        phase_deg : float or array_like of float
            The phase angle of the operation [deg], in (0, 360].

        Returns
        -------
        float or ndarray of float
            The impact speed v0 [m/s], of the broadcast shape.

        Raises
        ------
        InputError
            If a speed is not finite and positive or a phase angle lies outside (0, 360].

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(float(cm.impact.StopImpact.example().impact_speed(280, 40.0)), 4)
        0.2038
        """
        n, t = broadcast(rpm=_positive_array("rpm", rpm, "[rpm]"), phase_deg=_phase(phase_deg))
        return n * RAD_PER_S_PER_RPM * self.stroke * self.dz_contact / np.radians(t)

    def impact_force(self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike) -> Any:
        """Mean impact force F = J_A·ω0·(1+k)/(l·τ) [N] (the seed's F_уд).

        Parameters
        ----------
        rpm : float or array_like of float
            The main shaft's speed [rpm] (> 0); broadcasts with ``phase_deg``.
        phase_deg : float or array_like of float
            The phase angle of the operation [deg], in (0, 360].

        Returns
        -------
        float or ndarray of float
            The mean impact force [N], of the broadcast shape.

        Raises
        ------
        InputError
            If a speed is not finite and positive or a phase angle lies outside (0, 360].

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(float(cm.impact.StopImpact.example().impact_force(280, 40.0)), 2)
        3.53
        """
        w0 = self.impact_speed(rpm, phase_deg) / self.lever_length
        return impact_force(self.J_A, w0, self.restitution, self.lever_length, self.contact_time)

    def rebound(
        self, rpm: npt.ArrayLike, phase_deg: npt.ArrayLike, *, n_threads: int | None = None
    ) -> Any:
        """First-rebound amplitude [m] at given speeds and phase angles.

        One Rust call for all of them.

        Parameters
        ----------
        rpm : float or array_like of float
            The main shaft's speeds [rpm] (> 0); broadcasts with ``phase_deg``.
        phase_deg : float or array_like of float
            The phase angles of the operation [deg], in (0, 360].
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        ndarray of float
            The first rebound [m], of the broadcast shape.

        Raises
        ------
        InputError
            If a speed is not finite and positive or a phase angle lies outside (0, 360].

        Examples
        --------
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
        """The motion after the impact at one speed and phase angle.

        q is the displacement of the working point away from the stop, t runs from the
        instant of contact, with the pulse's breakpoints on the grid (pulse model: exact
        Duhamel response; contact model: the exact event-driven motion).

        Parameters
        ----------
        rpm : float
            The main shaft's speed [rpm].
        phase_deg : float
            The phase angle of the operation [deg].
        duration : float, optional
            The time to cover [s]; default None (6 free periods).
        points : int, default 2001
            The number of samples (the pulse's breakpoints are added).

        Returns
        -------
        t : ndarray of float
            The times from the instant of contact [s].
        q : ndarray of float
            The displacement away from the stop at each time [m].

        Raises
        ------
        InputError
            If the speed, the phase angle, ``duration`` or ``points`` is out of range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> t, q = cm.impact.StopImpact.example().response(280, 40.0)
        >>> round(float(q.max()) * 1e3, 3)                   # mm: the first rebound
        0.07
        """
        rpm = positive("rpm", rpm, "[rpm]")
        phase_deg = finite_number("phase_deg", phase_deg, "[deg]")
        v0 = float(self.impact_speed(rpm, phase_deg))
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
        """The largest impact speed v* [m/s] whose first rebound is at most ``a_max``.

        inf if every speed up to 1e9 m/s is admissible; 0 if none is
        (:func:`max_impact_speeds` for one stop).

        Parameters
        ----------
        a_max : float
            The largest admissible rebound [m] (> 0).
        rtol : float, default 1e-12
            The relative tolerance on v*, in [1e-15, 0.5].
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float
            The largest admissible impact speed v* [m/s].

        Raises
        ------
        InputError
            If ``a_max`` is not finite and positive or ``rtol`` lies outside its range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> v = lifter.max_impact_speed(0.1e-3)        # the impact speed at t_min, any rpm
        >>> t = lifter.min_phase_angle(0.1e-3, 280)
        >>> round(v, 6), round(float(lifter.impact_speed(280, t)), 6)
        (0.290929, 0.290929)
        """
        return float(max_impact_speeds([self], a_max, rtol=rtol, n_threads=n_threads)[0])

    def phase_per_rpm(self, v_star: float) -> float:
        """The phase angle per rpm [deg/rpm] at which the impact speed is ``v_star``.

        t = n·(360/60)·stroke·Z'/v* (degrees of a turn of 2π·n/60 rad/s); 0 for
        v* = inf, inf for v* = 0.

        Parameters
        ----------
        v_star : float
            The impact speed v* [m/s] (≥ 0, may be inf).

        Returns
        -------
        float
            The phase angle per rpm [deg/rpm].

        Examples
        --------
        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> round(280 * lifter.phase_per_rpm(lifter.max_impact_speed(0.1e-3)), 6)
        28.027142
        """
        # A v* so small (a subnormal rebound limit) that the slope passes the float
        # range is a bound no speed meets: inf, as for v* = 0.
        with np.errstate(divide="ignore", over="ignore"):
            per_rpm = np.degrees(RAD_PER_S_PER_RPM * self.stroke * self.dz_contact)
            return float(
                per_rpm
                / np.float64(
                    finite_number("v_star", v_star, "[m/s] (inf: no bound)", low=0.0, inf=True)
                )
            )

    def min_phase_angle(
        self,
        a_max: float,
        rpm: npt.ArrayLike,
        *,
        tol_deg: float = 1e-9,
        n_threads: int | None = None,
    ) -> Any:
        """Smallest phase angle [deg] whose first rebound is at most ``a_max``, at each speed.

        The rebound depends on the speed n and the phase angle t only through the
        impact speed v0 = (2π·n/60)·stroke·Z'/t (:meth:`impact_speed`) and grows with
        it, so t_min = (2π·n/60)·stroke·Z'/v* at every speed, with v* the largest
        admissible impact speed (:meth:`max_impact_speed`): one search for all speeds.
        At least 1e-9°; NaN where even 360° is too short.

        Parameters
        ----------
        a_max : float
            The largest admissible rebound [m] (> 0).
        rpm : float or array_like of float
            The main shaft's speeds [rpm] (> 0).
        tol_deg : float, default 1e-9
            The tolerance on the angle [deg], in [3.6e-13, 180] (360° times the range of
            :func:`max_impact_speeds`' ``rtol``).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float or ndarray of float
            The smallest phase angle at each speed [deg] (a float for a scalar speed).

        Raises
        ------
        InputError
            If ``a_max`` or a speed is not finite and positive or ``tol_deg`` lies
            outside its range.

        Examples
        --------
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
        """Least-squares line slope·t + intercept through the first rebound over phase angles.

        The seed's form a(3,7) = −0.003·t + 0.208 (mm, deg).

        Parameters
        ----------
        phase_deg_range : tuple of (float, float)
            The phase angles (low, high) [deg], low < high, in (0, 360].
        rpm : float
            The main shaft's speed [rpm].
        points : int, default 64
            The number of phase angles the line is fitted to (≥ 2).

        Returns
        -------
        slope : float
            The line's slope [m/deg].
        intercept : float
            The line's intercept [m].

        Raises
        ------
        InputError
            If the range is not (low, high) with low < high inside (0, 360] or
            ``points`` is out of range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> s, c = cm.impact.StopImpact.example().linearize((30, 45), 420)
        >>> round(s * 1e3, 4), round(c * 1e3, 3)                   # mm/deg, mm
        (-0.0031, 0.229)
        """
        pair = real_array("phase_deg_range", phase_deg_range, "[deg]", ndims=(1,))
        if pair.shape != (2,):
            raise InputError(
                f"phase_deg_range = {phase_deg_range!r} must be (low, high) with low < high"
            )
        lo, hi = (float(_phase(v)) for v in pair)
        if not hi > lo:
            raise InputError(
                f"phase_deg_range = {phase_deg_range!r} must be (low, high) with low < high"
            )
        points = count("points", points, low=2, high=10**7)
        slope, intercept = self._lines(
            np.array([positive("rpm", rpm, "[rpm]")]), np.array([lo]), np.array([hi]), points
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
        """The seed's linearised smallest phase angle [deg] at each speed.

        The rebound fitted by a line slope·t + intercept over 0.5…2 times the exact
        angle (capped at 360°; as :meth:`constraint` with ``linear=True``), then
        t = (a_max − intercept)/slope; NaN where the exact angle is. One rebound call
        for all speeds.

        Parameters
        ----------
        a_max : float
            The largest admissible rebound [m] (> 0).
        rpm : float or array_like of float
            The main shaft's speeds [rpm] (> 0).
        points : int, default 64
            The number of phase angles each line is fitted to (2 to 10⁶).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float or ndarray of float
            The linearised smallest phase angle at each speed [deg] (a float for a
            scalar speed).

        Raises
        ------
        InputError
            If ``a_max`` or a speed is not finite and positive or ``points`` is out of
            range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lifter = cm.impact.StopImpact.example()
        >>> round(float(lifter.linear_min_phase_angle(1e-4, 280.0)), 2)     # exact: 28.03
        32.67
        """
        points = count("points", points, low=2, high=1_000_000)
        n = _positive_array("rpm", rpm, "[rpm]")
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
        """The cyclogram constraint rebound(t(arc)) ≤ ``a_max`` at a speed.

        Exact, t(arc) ≥ :meth:`min_phase_angle` (default), or the seed's linearised
        slope·t + intercept ≤ a_max over 0.5…2 times that angle (``linear=True``). Pass
        it to :meth:`cyclomech.Cyclogram.add_constraint`.

        Parameters
        ----------
        arc : tuple of (str, str)
            The operation's two event names (from, to), e.g. ``("3", "7")``.
        a_max : float
            The largest admissible rebound [m] (> 0).
        rpm : float
            The main shaft's speed [rpm].
        linear : bool, default False
            The seed's linearised constraint instead of the exact one.

        Returns
        -------
        Constraint
            The constraint on the phase angle t(arc) [deg], named ``"rebound<from>-<to>"``.

        Raises
        ------
        InputError
            If ``arc`` is not two event names, or ``a_max`` or ``rpm`` is out of range.
        InfeasibleError
            If the rebound stays above ``a_max`` for every phase angle up to 360°.

        Examples
        --------
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
        rpm = positive("rpm", rpm, "[rpm]")
        linear = flag("linear", linear)
        t_min = float(self.min_phase_angle(a_max, rpm))
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
        """An illustrative microshuttle lifter in the spirit of the STB loom's (seed 000).

        Not measured data. A steel lever 100 mm long (arms 50 and 100 mm, a section of
        6.14e-11 m⁴, about 8 × 4.5 mm), 7.4 g reduced to its working point, free at
        297 Hz and 752 Hz in contact, a modified-sine rise of 9.4 mm with 0.25 mm
        preload. Its first rebound at a 40° phase angle is 0.070, 0.080, 0.093,
        0.105 mm at 280, 320, 370, 420 rpm (the seed: 0.07, 0.078, 0.092, 0.105 mm),
        and its linearisation over 30–45° at 420 rpm is −0.0031·t + 0.229 mm (the seed:
        −0.003·t + 0.208).

        Parameters
        ----------
        **overrides
            Constructor arguments that replace the example's (see :class:`StopImpact`).

        Returns
        -------
        StopImpact
            The lifter.

        Examples
        --------
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
    t = float_array("phase_deg", value, ndims=None).reshape(np.shape(value))
    bad = ~(np.isfinite(t) & (t > 0.0) & (t <= 360.0))
    if bad.any():
        v = t.reshape(-1)[int(np.argmax(bad.reshape(-1)))]
        raise InputError(f"phase_deg = {float(v)!r} must lie in (0, 360] degrees")
    return t
