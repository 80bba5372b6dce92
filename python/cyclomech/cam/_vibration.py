"""Follower dynamics: the dynamic error of a cam's motion law (`_vibration` part
of :mod:`cyclomech.cam`).

**Model.** The follower is a mass–spring–damper driven through its cam: the cam
imposes s(t) on one end of the follower's elastic link, and the working member y
obeys ÿ + 2ζω_n(ẏ − ṡ) + ω_n²(y − s) = 0, so that the dynamic error x = y − s
obeys

    ẍ + 2ζω_n ẋ + ω_n² x = −s̈(t),

ω_n [rad/s] the natural frequency (``2π·natural_frequency_hz``), ζ the damping
ratio in [0, 1), x in the stroke's unit (m, or rad for an oscillating follower).

**One segment.** A rise or return of stroke h over a cam angle β [rad] at cam
speed ω [rad/s] lasts T = β/ω; in dimensionless time u = t/T,
x'' + 2ζτx' + τ²x = −h·z''(u) with τ = ω_n·T (the segment's duration in radians
of the natural vibration) and z the law's normalised rise. Started from rest
(the classic "dynamic error of the motion law"), the free vibration after the
segment has the amplitude A = h·R(τ, ζ), R depending on the law, τ and ζ only:
R = √(q² + ((q' + ζτq)/(τ√(1 − ζ²)))²) from the end state (q, q'). R → 1/√(1 − ζ²)
as τ → 0; for the cycloidal rise (ζ = 0) R = 8π²|sin(τ/2)|/(τ|4π² − τ²|), zero
when the rise lasts a whole number k ≥ 2 of natural periods.

For the built-in laws R is a closed form (issue 37): with λ = −ζτ + iω_d,
ω_d = τ√(1 − ζ²), R = |G|/ω_d where G = −∫₀¹ e^{λ(1−s)} z''(s) ds, integrated
exactly piece by piece (each law's pieces are polynomials and sines); for the
cycloidal rise R = 4π²|e^{λ} − 1|/(ω_d|λ² + 4π²|), evaluated without
cancellation (also through the resonance τ = 2π) and in SIMD lanes, the
harmonic rise likewise; the other four laws' pieces summed with per-law
constants in SIMD lanes too (the exact scalar pieces at small τ and near a sine
piece's resonance). Tested within 1e-11
of R's envelope up to τ = 10⁴ against independent closed forms (numpy, per law).
A motion program's own segment law (the ``program`` path of the bound below)
keeps the exact piecewise-linear Duhamel kernel of the stops
(:func:`cyclomech.impact.duhamel`'s recurrence) with −z'' sampled at 1024
intervals per unit and on the bisected grid, combined by Richardson
extrapolation: ~1e-9 relative over τ ≤ 200.

**The bound.** :func:`min_vibration_tau` returns τ*, the smallest τ such that
R(τ') ≤ the limit for EVERY τ' ≥ τ*. R has lobes and zeros, so a feasible
window below a violating lobe is ignored (conservative: a speed change would
move τ out of it). A segment's cam angle must then satisfy
β ≥ τ*·ω/ω_n, i.e. β_min [deg] = 6·τ*·rpm/ω_n [rad/s], proportional to speed.

**A whole cam.** :func:`follower_response` gives the periodic steady state at a
constant speed: x and ẋ at cam angles, and the residual amplitude after each
segment (the free-vibration amplitude of the state at its end).

**Polydyne.** :func:`polydyne` inverts the model: for the working member to
follow a program y(θ) exactly at one speed ω, the cam must impose
s = y + ÿ/ω_n² = y + (ω/ω_n)²·y″ (undamped model; y″ per rad² of cam), with
ω_n² = k/m. The program must be continuous to its jerk for s to be continuous to
its velocity. At other speeds the output departs from the program: the follower's
response to the polydyne cam (:func:`follower_response`) shows by how much.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import check_bytes, finite_number, float_array, positive, threads_arg
from .._errors import InputError
from ..motion import NAMES, Program
from ._program import Cam

__all__ = [
    "FollowerResponse",
    "follower_response",
    "min_vibration_tau",
    "polydyne",
    "residual_vibration",
]

#: Cam angles of the default response grid (every half degree, 0 and 360° both).
_DEFAULT_SAMPLES = 721


def _law(law: Any) -> str:
    if not isinstance(law, str) or law not in NAMES:
        raise InputError(f"law must be one of {NAMES}; got {law!r}")
    return law


def _zeta(value: Any) -> float:
    z = finite_number("damping_ratio", value, "(dimensionless)", low=0.0)
    if z >= 1.0:
        raise InputError(f"damping_ratio = {value!r} must be in [0, 1) (an under-damped follower)")
    return z


def residual_vibration(
    law: str, tau: Any, damping_ratio: float = 0.0, *, n_threads: int | None = None
) -> npt.NDArray[np.float64]:
    """Residual vibration amplitude per unit stroke R(τ, ζ) after one rise or return.

    The rise or return of ``law`` starts from rest; amplitude [m or rad] =
    stroke · R. One Rust call (each law's closed form, see the module docs), in
    parallel over τ for large batches, GIL released.

    Parameters
    ----------
    law : str
        The motion law's name (one of ``cyclomech.motion.NAMES``).
    tau : array_like of float, any shape
        Each τ = ω_n·T [rad] (T the segment's duration [s], ω_n the natural
        frequency [rad/s]), finite and > 0.
    damping_ratio : float, default 0.0
        The damping ratio ζ, in [0, 1).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    ndarray of float, shape of ``tau``
        R(τ, ζ) for each τ (dimensionless, the amplitude per unit stroke).

    Raises
    ------
    InputError
        If ``law`` is not a known law, ``damping_ratio`` is not in [0, 1), or a τ is
        not finite and > 0.

    Examples
    --------
    >>> import numpy as np
    >>> import cyclomech as cm
    >>> r = cm.cam.residual_vibration("cycloidal", [4 * np.pi, 10.0])
    >>> bool(r[0] < 1e-9), round(float(r[1]), 6)  # zero at two natural periods
    (True, 0.125102)
    """
    _law(law)
    z = _zeta(damping_ratio)
    # Sized before the copy: the input as float64, its checks' masks and the output.
    n = float(np.prod(np.shape(tau), dtype=np.float64))
    check_bytes(f"residual_vibration of {n:.0f} values", 26.0 * n, "pass fewer values of tau")
    t = float_array("tau", tau, ndims=tuple(range(33)))
    try:
        # The kernel checks every τ itself (its pass costs less than numpy's
        # masks, which would cost more than the closed forms): the masks only
        # name the bad entry by its index in ``tau``'s shape.
        out = _core.cam_residual_ratio(law, t.reshape(-1), z, n_threads=threads_arg(n_threads))
    except InputError:
        bad = ~(np.isfinite(t) & (t > 0.0))
        if bad.any():
            i = np.unravel_index(int(np.argmax(bad)), t.shape)
            where = ", ".join(str(int(k)) for k in i)
            raise InputError(
                f"tau[{where}] = {float(t[i])!r} must be finite and > 0 [rad]"
            ) from None
        raise
    return out.reshape(np.shape(tau))


def min_vibration_tau(law: str, amplitude_ratio: float, damping_ratio: float = 0.0) -> float:
    """The smallest τ = ω_n·T beyond which the residual vibration stays within a limit.

    τ* [rad] is the smallest τ such that the residual amplitude per unit stroke
    R(τ', ζ) ≤ ``amplitude_ratio`` for every τ' ≥ τ* (the bound rule: a feasible
    window below a violating lobe is ignored); 0 if R never exceeds it. Exact:
    R(τ*) equals the limit to ~1e-12 (a bracketed root after a scan of step 2π/64
    that refines every lobe near the limit). A segment of cam angle β at ``rpm``
    then needs β ≥ τ*·ω/ω_n.

    Parameters
    ----------
    law : str
        The motion law's name (one of ``cyclomech.motion.NAMES``).
    amplitude_ratio : float
        The largest residual amplitude per unit stroke, [a]/h (> 0).
    damping_ratio : float, default 0.0
        The damping ratio ζ, in [0, 1).

    Returns
    -------
    float
        τ* [rad] (0.0 if R never exceeds ``amplitude_ratio``).

    Raises
    ------
    InputError
        If ``law`` is not a known law, ``amplitude_ratio`` is not > 0 or
        ``damping_ratio`` is not in [0, 1).

    Examples
    --------
    >>> import math
    >>> import cyclomech as cm
    >>> t = cm.cam.min_vibration_tau("cycloidal", 0.01)  # [a] = 1 % of the stroke
    >>> round(t, 6)
    17.56594
    >>> wn = 2 * math.pi * 100.0                  # a 100 Hz follower
    >>> round(t * 600 * 6 / wn, 3)                # beta_min [deg] at 600 rpm
    100.645
    >>> cm.cam.min_vibration_tau("cycloidal", 2.0)
    0.0
    """
    _law(law)
    z = _zeta(damping_ratio)
    limit = positive("amplitude_ratio", amplitude_ratio, "(amplitude per unit stroke)")
    return float(_core.cam_min_tau(law, limit, z))


@dataclass(frozen=True)
class FollowerResponse:
    """The periodic steady-state dynamic error of a cam's follower at one speed.

    Built by :func:`follower_response`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    theta : ndarray of float
        The cam angles asked for [rad] (any shape).
    error : ndarray of float, shape of ``theta``
        The dynamic error x = y − s there [m, or rad for an oscillating follower].
    rate : ndarray of float, shape of ``theta``
        Its rate ẋ there [m/s, or rad/s].
    residual : ndarray of float, shape (segments,)
        One per segment: the amplitude of the free vibration of the state at the
        segment's end (the residual vibration after a rise or return when a dwell
        follows) [m or rad].

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> r = cm.cam.follower_response(cam, 600, 50.0, 0.05, theta=[0.0, 1.0])
    >>> r.error.shape, r.residual.shape
    ((2,), (2,))
    """

    theta: npt.NDArray[np.float64]
    error: npt.NDArray[np.float64]
    rate: npt.NDArray[np.float64]
    residual: npt.NDArray[np.float64]


def follower_response(
    cam: Cam,
    rpm: float,
    natural_frequency_hz: float,
    damping_ratio: float = 0.0,
    theta: Any = None,
) -> FollowerResponse:
    """The periodic steady state of ``cam``'s follower at one speed.

    The dynamic error and its rate at cam angles ``theta``, and the residual
    amplitude after each segment. s̈ is sampled on every segment, propagated exactly
    over one turn and the periodic condition solved in closed form.

    Parameters
    ----------
    cam : Cam
        The cam.
    rpm : float
        The cam speed [rpm] (> 0).
    natural_frequency_hz : float
        The follower's natural frequency [Hz] (> 0).
    damping_ratio : float, default 0.0
        The damping ratio ζ, in [0, 1).
    theta : array_like of float, optional
        The cam angles [rad] (any shape): values in [0, 2π] as given, 2π the end of
        the turn, others modulo 2π; default None (721 angles from 0 to 2π).

    Returns
    -------
    FollowerResponse
        The dynamic error [m or rad] and its rate at ``theta``, and the residual
        amplitude after each segment.

    Raises
    ------
    InputError
        If ``cam`` is not a :class:`Cam`, ``rpm`` or ``natural_frequency_hz`` is
        not > 0, ``damping_ratio`` is not in [0, 1); or, for an undamped follower at
        resonance (a turn lasting a whole number of natural periods), which has no
        steady state, naming the speed.

    Examples
    --------
    >>> import numpy as np
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("dwell", 180), S("rise", 90, 0.01), S("return", 90, 0.01)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> r = cm.cam.follower_response(cam, 300, 40.0, 0.1)
    >>> bool(abs(r.error[0] - r.error[-1]) < 1e-12)  # periodic
    True
    >>> round(float(r.residual[1] * 1e6), 3)          # after the rise [µm]
    186.154
    """
    if not isinstance(cam, Cam):
        raise InputError(f"cam must be a cyclomech.cam.Cam; got {cam!r}")
    speed = positive("rpm", rpm, "[rpm]")
    fn = positive("natural_frequency_hz", natural_frequency_hz, "[Hz]")
    z = _zeta(damping_ratio)
    if theta is None:
        theta = np.linspace(0.0, 2.0 * math.pi, _DEFAULT_SAMPLES)
    t = float_array("theta", theta, ndims=tuple(range(33)))
    shape = np.shape(theta)
    segs = cam.segments
    x, v, residual = _core.cam_follower_response(
        [g.kind for g in segs],
        [math.radians(g.angle_deg) for g in segs],
        [g.stroke for g in segs],
        [g.law for g in segs],
        speed * _core.RAD_PER_S_PER_RPM,
        2.0 * math.pi * fn,
        z,
        t.reshape(-1),
        None if cam.program is None else cam.program.kernel,
    )
    return FollowerResponse(
        theta=t.reshape(shape).copy(),
        error=x.reshape(shape),
        rate=v.reshape(shape),
        residual=residual,
    )


def polydyne(
    program: Program,
    follower_mass: float,
    stiffness: float,
    rpm: float,
    *,
    continuity: str = "velocity",
) -> Program:
    """The polydyne cam motion: the cam displacement whose follower output follows ``program``.

    For a follower of mass m on an elastic link of stiffness k (ω_n² = k/m, the
    model of the module docs, undamped), the cam displacement
    s(θ) = y(θ) + (m·ω²/k)·y″(θ) makes the working member follow y exactly at
    ``rpm`` (ω = 2π·rpm/60). Closed form per piece: s stays a polynomial plus a sine.

    Parameters
    ----------
    program : cyclomech.motion.Program
        The motion the working member must follow, y(θ) [m or rad], continuous to
        its jerk (so that s is continuous to its velocity).
    follower_mass : float
        m [kg] (for an oscillating arm: its inertia [kg·m²]).
    stiffness : float
        k [N/m] (oscillating: [N·m/rad]) of the link between cam and member.
    rpm : float
        The design speed [rpm].
    continuity : {"position", "velocity", "acceleration", "jerk"}, default "velocity"
        The order to which the cam motion's joins must be continuous.

    Returns
    -------
    cyclomech.motion.Program
        The cam motion, its ``shift`` = m·ω²/k [rad²]; a :class:`Cam` takes it.

    Raises
    ------
    InputError
        If ``program`` is not a plain motion program, a number is not > 0, or the
        cam motion jumps at a join (the program's own continuity is too low: named).

    Examples
    --------
    >>> import cyclomech as cm
    >>> M = cm.motion.Segment
    >>> y = cm.motion.Program([M("poly7", 120, end=0.02), M("dwell", 60),
    ...                        M("poly7", 120, end=0.0), M("dwell", 60)], continuity="jerk")
    >>> s = cm.cam.polydyne(y, follower_mass=0.5, stiffness=2e5, rpm=600)
    >>> round(s.shift, 9)  # m ω² / k [rad²]
    0.009869604
    >>> cam = cm.cam.Cam(s, cm.cam.TranslatingRoller(0.06, 0.01))
    """
    if not isinstance(program, Program):
        raise InputError(f"program must be a cyclomech.motion.Program; got {program!r}")
    m = positive("follower_mass", follower_mass, "[kg or kg·m²]")
    k = positive("stiffness", stiffness, "[N/m or N·m/rad]")
    w = positive("rpm", rpm, "[rpm]") * _core.RAD_PER_S_PER_RPM
    try:
        return program.plus_second_derivative(m * w * w / k, continuity)
    except InputError as e:
        raise InputError(
            f"the polydyne cam motion at {rpm!r} rpm: {e}; its program must be continuous "
            "two derivatives higher than the cam motion (e.g. poly7 or polynomial_4567 "
            "segments for a cam continuous to its velocity)"
        ) from None
