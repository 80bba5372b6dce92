"""Follower loads, Hertz stress and the smallest phase angles: `_loads` part of
:mod:`cyclomech.cam` (its door).

The cam must supply the generalised force Q = m s″ω² + k s + F0 + F_L along the
follower's coordinate (N, or N·m about an oscillating arm's pivot): inertia, the
spring (rate k, preload F0 at s = 0) and the segment's external load F_L, the last
three acting toward the cam. The normal force is N = Q/(l cos φ) (l = 1, or the
arm length), the shaft torque T = Q s′ (power balance; friction neglected), and the
Hertz line-contact stress σ_H = √(|N| κ/(π b c)) with κ = 1/r_r + 1/ρ the relative
curvature on the loaded flank and c = Σ(1 − ν²)/E (Johnson, *Contact Mechanics*,
eq. 4.45).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number, float_array, positive, real, speeds_rpm, threads_arg
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ._followers import OscillatingRoller

if TYPE_CHECKING:
    from ._program import Cam

__all__ = [
    "CRITERIA",
    "CamLoads",
    "Contact",
    "FollowerLoads",
    "MinPhaseAngles",
    "default_pressure_angle_deg",
]

Array = npt.NDArray[np.float64]

#: The criteria of :meth:`Cam.min_phase_angles`, in the order of its last axis:
#: the kernel's four, then the follower's residual vibration.
CRITERIA: tuple[str, ...] = (*_core.CAM_CRITERIA, "vibration")


@dataclass(frozen=True)
class FollowerLoads:
    """The follower's loads: its mass, spring and one external load per segment.

    Gravity, if it matters, is a load or part of the preload. Each parameter is kept
    as the attribute of the same name (as floats; ``segment_loads`` as a tuple).

    Parameters
    ----------
    mass : float
        The follower's mass [kg] (≥ 0); an oscillating follower: the arm's moment
        of inertia about its pivot [kg·m²].
    spring_rate : float, default 0.0
        The spring's rate [N/m, or N·m/rad] (≥ 0).
    preload : float, default 0.0
        The spring's force at s = 0 [N, or N·m].
    segment_loads : sequence of float, optional
        One external load per segment [N, or N·m], acting toward the cam as the
        spring does; default None (none).

    Raises
    ------
    InputError
        If ``mass`` or ``spring_rate`` is negative or a value is not finite.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.cam.FollowerLoads(mass=0.8, spring_rate=2000.0, preload=40.0).mass
    0.8
    >>> cm.cam.FollowerLoads(mass=-1.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: mass = -1.0 must be finite and ≥ 0 [kg, or kg·m² ...]
    """

    mass: float
    spring_rate: float = 0.0
    preload: float = 0.0
    segment_loads: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        m = finite_number("mass", self.mass, "[kg, or kg·m² for an oscillating arm]", low=0.0)
        k = finite_number("spring_rate", self.spring_rate, "[N/m, or N·m/rad]", low=0.0)
        f0 = finite_number("preload", self.preload, "[N, or N·m]")
        object.__setattr__(self, "mass", m)
        object.__setattr__(self, "spring_rate", k)
        object.__setattr__(self, "preload", f0)
        if self.segment_loads is not None:
            v = float_array("segment_loads", self.segment_loads)
            if not np.isfinite(v).all():
                raise InputError(f"segment_loads must be finite [N, or N·m]; got {v.tolist()}")
            object.__setattr__(self, "segment_loads", tuple(float(x) for x in v))

    def _kernel_args(self, n_segments: int) -> tuple[float, float, float, list[float]]:
        loads = self.segment_loads
        if loads is None:
            loads = (0.0,) * n_segments
        if len(loads) != n_segments:
            raise InputError(
                f"segment_loads holds {len(loads)} values; the cam has {n_segments} segments"
            )
        return self.mass, self.spring_rate, self.preload, list(loads)


@dataclass(frozen=True)
class Contact:
    """Hertz line contact of the follower (roller, or flat face) on the cam.

    The defaults are steel (210 GPa, 0.3). Each parameter is kept as the attribute
    of the same name (as a float).

    Parameters
    ----------
    width : float
        The contact's width along the cam's axis [m] (> 0).
    follower_modulus : float, default 2.1e11
        The follower's Young's modulus [Pa] (> 0).
    follower_poisson : float, default 0.3
        The follower's Poisson's ratio, in (−1, 0.5).
    cam_modulus : float, default 2.1e11
        The cam's Young's modulus [Pa] (> 0).
    cam_poisson : float, default 0.3
        The cam's Poisson's ratio, in (−1, 0.5).

    Raises
    ------
    InputError
        If ``width`` or a modulus is not > 0, or a Poisson's ratio is not in
        (−1, 0.5).

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.cam.Contact(width=0.012).cam_modulus
    210000000000.0
    >>> cm.cam.Contact(width=0.01, cam_poisson=0.5)
    Traceback (most recent call last):
    cyclomech._errors.InputError: cam_poisson must be a number in (-1, 0.5); got 0.5
    """

    width: float
    follower_modulus: float = 2.1e11
    follower_poisson: float = 0.3
    cam_modulus: float = 2.1e11
    cam_poisson: float = 0.3

    def __post_init__(self) -> None:
        object.__setattr__(self, "width", positive("width", self.width, "[m]"))
        for name in ("follower_modulus", "cam_modulus"):
            object.__setattr__(self, name, positive(name, getattr(self, name), "[Pa]"))
        for name in ("follower_poisson", "cam_poisson"):
            v = getattr(self, name)
            ok = isinstance(v, int | float) and not isinstance(v, bool) and -1.0 < v < 0.5
            if not ok:
                raise InputError(f"{name} must be a number in (-1, 0.5); got {v!r}")
            object.__setattr__(self, name, float(v))

    def _kernel_args(self) -> tuple[float, float, float, float, float]:
        return (
            self.width,
            self.follower_modulus,
            self.follower_poisson,
            self.cam_modulus,
            self.cam_poisson,
        )


@dataclass(frozen=True)
class CamLoads:
    """Loads along the cycle at one speed (arrays of ``theta``'s shape).

    Built by :meth:`Cam.loads`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    theta : ndarray of float
        The cam angles [rad].
    rpm : float
        The cam speed [rpm].
    force : ndarray of float
        The generalised force Q along the follower's coordinate [N, or N·m].
    normal_force : ndarray of float
        The normal force N [N], signed: + on the inner flank, − on a groove's outer
        flank or, with a spring, the pull the follower would need (separation).
    contact_stress : ndarray of float
        The Hertz stress σ_H [Pa]: NaN without a :class:`Contact`, where the
        profile is undercut, and where the follower has left the cam (``separated``:
        no contact, so no stress to compare with [σ_H]).
    shaft_torque : ndarray of float
        The torque the cam shaft must supply [N·m], Q·s′. Where the follower has
        left the cam (``separated``), the torque it would need were it held on, as
        ``normal_force`` there is the pull it would need; none passes while it is
        off (the friction forces, ``cam_friction``, report 0 there).
    separated : ndarray of bool
        Spring closure: where the follower leaves the cam.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> l = cam.loads([0.0, 1.0], 100.0, cm.cam.FollowerLoads(1.0, preload=5.0))
    >>> l.force.round(3).tolist(), l.separated.tolist()
    ([5.0, 5.635], [False, False])
    """

    theta: Array
    rpm: float
    force: Array
    normal_force: Array
    contact_stress: Array
    shaft_torque: Array
    separated: npt.NDArray[np.bool_]


@dataclass(frozen=True)
class MinPhaseAngles:
    """The smallest phase angle of each bound segment for each criterion.

    NaN: no angle up to a whole turn will do; 0: the criterion does not bound the
    segment. The rule (documented in the kernel): the bound is the smallest angle β
    such that the criterion holds on all of [β, 360°]; a feasible window below a
    violation is ignored. Built by :meth:`Cam.min_phase_angles`; each parameter is
    kept as the attribute of the same name.

    Parameters
    ----------
    rpm : ndarray of float, shape (speeds,)
        The cam speeds [rpm].
    segments : tuple of int
        The indices of the bound segments (rises and returns).
    criteria : tuple of str
        The criteria, ``cyclomech.cam.CRITERIA``.
    angle_deg : ndarray of float, shape (speeds, segments, criteria)
        The smallest phase angles [deg].

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
    >>> m = cam.min_phase_angles([300.0])
    >>> str(m.binding[0, 0]), round(float(m.bound_deg[0, 0]), 4)
    ('pressure_angle', 57.1837)
    """

    rpm: Array
    segments: tuple[int, ...]
    criteria: tuple[str, ...]
    angle_deg: Array

    @property
    def bound_deg(self) -> Array:
        """The bound of each segment, the largest over the criteria [deg], shape (speeds, segments).

        NaN if any criterion's angle is NaN.

        Examples
        --------
        >>> import numpy as np
        >>> MinPhaseAngles(np.ones(1), (0,), ("a", "b"), np.array([[[10.0, 20.0]]])).bound_deg
        array([[20.]])
        """
        return np.max(self.angle_deg, axis=-1)

    @property
    def binding(self) -> npt.NDArray[np.str_]:
        """The criterion that sets each bound, shape (speeds, segments).

        "" where none does; the NaN one where no angle will do.

        Examples
        --------
        >>> import numpy as np
        >>> MinPhaseAngles(np.ones(1), (0,), ("a", "b"), np.array([[[10.0, 20.0]]])).binding
        array([['b']], dtype='<U1')
        """
        a = self.angle_deg
        nan = np.isnan(a)
        idx = np.where(nan.any(axis=-1), np.argmax(nan, axis=-1), np.argmax(np.nan_to_num(a), -1))
        names = np.array(self.criteria)[idx]
        return np.where((np.nan_to_num(a, nan=1.0) > 0).any(axis=-1), names, "")


def default_pressure_angle_deg(follower: Any) -> float:
    """The largest pressure angle [α] by default [deg].

    Parameters
    ----------
    follower : TranslatingRoller or FlatFaced or OscillatingRoller
        The follower.

    Returns
    -------
    float
        45.0 for an oscillating follower, 30.0 for a translating one [deg].

    Examples
    --------
    >>> import cyclomech as cm
    >>> default_pressure_angle_deg(cm.cam.OscillatingRoller(0.1, 0.08, 0.04, 0.01))
    45.0
    """
    return 45.0 if isinstance(follower, OscillatingRoller) else 30.0


def solve_loads(
    cam: Cam,
    theta: Any,
    rpm: Any,
    follower_loads: Any,
    contact: Any = None,
    *,
    n_threads: int | None = None,
) -> CamLoads:
    """:meth:`Cam.loads` (see there).

    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> float(solve_loads(cam, 0.0, 100.0, cm.cam.FollowerLoads(1.0, preload=5.0)).force)
    5.0
    """
    if not isinstance(follower_loads, FollowerLoads):
        raise InputError(f"loads must be a cyclomech.cam.FollowerLoads; got {follower_loads!r}")
    if contact is not None and not isinstance(contact, Contact):
        raise InputError(f"contact must be None or a cyclomech.cam.Contact; got {contact!r}")
    n = float(speeds_rpm("rpm", rpm)[0]) if np.ndim(rpm) == 0 else None
    if n is None:
        raise InputError(f"rpm must be one speed [rpm]; got {rpm!r}")
    t = float_array("theta", theta, ndims=tuple(range(33)))
    shape = np.shape(theta)
    rows = cam._kernel.loads(
        t.reshape(-1),
        n * RAD_PER_S_PER_RPM,
        follower_loads._kernel_args(len(cam.segments)),
        None if contact is None else contact._kernel_args(),
        n_threads=threads_arg(n_threads),
    )

    def col(i: int) -> Array:
        return rows[:, i].reshape(shape)

    return CamLoads(
        theta=t.reshape(shape).copy(),
        rpm=n,
        force=col(0),
        normal_force=col(1),
        contact_stress=col(2),
        shaft_torque=col(3),
        separated=col(4) != 0.0,
    )


def solve_jump(cam: Cam, follower_loads: Any) -> tuple[float, float]:
    """:meth:`Cam.jump_rpm` (see there).

    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> round(solve_jump(cam, cm.cam.FollowerLoads(1.0, preload=5.0))[0], 3)
    267.619
    """
    if not isinstance(follower_loads, FollowerLoads):
        raise InputError(f"loads must be a cyclomech.cam.FollowerLoads; got {follower_loads!r}")
    w, theta = cam._kernel.jump_speed(follower_loads._kernel_args(len(cam.segments)))
    return w / RAD_PER_S_PER_RPM, math.degrees(theta)


def solve_min_angles(
    cam: Cam,
    rpm: Any,
    *,
    follower_loads: Any = None,
    contact: Any = None,
    max_stress: Any = None,
    max_pressure_angle_deg: Any = None,
    segments: Any = None,
    vibration: Any = None,
    n_threads: int | None = None,
) -> MinPhaseAngles:
    """:meth:`Cam.min_phase_angles` (see there).

    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> solve_min_angles(cam, 100.0).criteria[0]
    'pressure_angle'
    """
    n = speeds_rpm("rpm", rpm)
    if follower_loads is not None and not isinstance(follower_loads, FollowerLoads):
        raise InputError(
            f"loads must be None or a cyclomech.cam.FollowerLoads; got {follower_loads!r}"
        )
    if contact is not None and not isinstance(contact, Contact):
        raise InputError(f"contact must be None or a cyclomech.cam.Contact; got {contact!r}")
    if max_stress is not None:
        max_stress = positive("max_stress", max_stress, "[Pa]")
        if follower_loads is None or contact is None:
            raise InputError("max_stress needs the follower's loads and a Contact")
    alpha = pressure_limit_deg(cam, max_pressure_angle_deg)
    idx = bound_segments(cam, segments)
    out = cam._kernel.min_angles(
        list(idx),
        n * RAD_PER_S_PER_RPM,
        math.radians(alpha),
        None if follower_loads is None else follower_loads._kernel_args(len(cam.segments)),
        None if contact is None else contact._kernel_args(),
        max_stress,
        n_threads=threads_arg(n_threads),
    )
    vib = np.zeros((n.size, len(idx), 1))
    if vibration is not None:
        vib[:, :, 0] = _vibration_deg(cam, idx, n, vibration)
    angles = np.concatenate([np.degrees(out), vib], axis=-1)
    return MinPhaseAngles(rpm=n, segments=idx, criteria=CRITERIA, angle_deg=angles)


def pressure_limit_deg(cam: Cam, max_pressure_angle_deg: Any) -> float:
    """The pressure-angle limit [deg]: the given one, checked to lie in (0, 90), or
    the follower's default (:func:`default_pressure_angle_deg`).

    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> pressure_limit_deg(cam, None), pressure_limit_deg(cam, 20)
    (30.0, 20.0)
    """
    if max_pressure_angle_deg is None:
        return default_pressure_angle_deg(cam.follower)
    alpha = finite_number("max_pressure_angle_deg", max_pressure_angle_deg, "[deg]")
    if not 0.0 < alpha < 90.0:
        raise InputError(f"max_pressure_angle_deg must be in (0, 90) [deg]; got {alpha!r}")
    return alpha


def bound_segments(cam: Cam, segments: Any) -> tuple[int, ...]:
    """The indices of the rises and returns to bound: ``segments`` checked, or (None)
    every rest-to-rest one.

    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> bound_segments(cam, None)
    (0, 1)
    """
    moving = tuple(i for i, g in enumerate(cam.segments) if g.kind != "dwell")
    # A program's segment whose shape changes with its angle (moving ends, a
    # constant velocity, a spline) has no minimum angle of its own.
    scalable = (True,) * len(cam.segments) if cam.program is None else cam.program.scalable
    if segments is None:
        idx = tuple(i for i in moving if scalable[i])
    else:
        # count: a float, bool or string index is refused, not truncated or read
        idx = tuple(
            count("segments", i, low=0, what="the index of a rise or return")
            for i in np.atleast_1d(np.asarray(segments)).reshape(-1)
        )
        for i in idx:
            if i not in moving:
                raise InputError(
                    f"segments: {i} is not the index of a rise or return; those are {list(moving)}"
                )
            if not scalable[i]:
                raise InputError(
                    f"segments: {i} ({cam.segments[i].law}) has moving ends, a constant "
                    "velocity or a point table: its shape changes with its angle, so it has "
                    "no minimum phase angle; bound rest-to-rest segments only"
                )
    return idx


def _vibration_deg(cam: Cam, idx: tuple[int, ...], rpm: Array, vibration: Any) -> Array:
    """(speeds, segments) [deg]: β_min = τ*·ω/ω_n of each segment for the residual
    vibration (τ* from :func:`min_vibration_tau` on [a]/h); NaN over 360°.

    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.04))
    >>> _vibration_deg(cam, (0,), np.array([600.0]), (100.0, 0.0, 1e-4)).round(3).tolist()
    [[100.645]]
    """
    from ._vibration import min_vibration_tau

    try:
        f, zeta, a = (real(v) for v in vibration)  # a string is not a number
    except (TypeError, ValueError):
        raise InputError(
            "vibration must be (natural frequency [Hz], damping ratio, amplitude limit "
            f"[m or rad]); got {vibration!r}"
        ) from None
    positive("natural frequency", f, "[Hz]")
    positive("amplitude limit", a, "[m or rad]")
    wn = 2.0 * math.pi * f
    if cam.program is None:
        tau = np.array(
            [min_vibration_tau(cam.segments[k].law, a / cam.segments[k].stroke, zeta) for k in idx]
        )
    else:  # the program's own law of each segment on the unit square
        kernel = cam.program.kernel
        tau = np.array(
            [_core.cam_min_tau("", a / cam.segments[k].stroke, zeta, kernel, k) for k in idx]
        )
    beta = np.degrees(np.outer(rpm * RAD_PER_S_PER_RPM, tau / wn))
    return np.where(beta <= 360.0, beta, np.nan)
