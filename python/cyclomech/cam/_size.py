"""Cams sized against the cyclogram: `_size` part of :mod:`cyclomech.cam`, whose door
to users is :mod:`cyclomech.synthesis` (``cyclomech.synthesis.cam_size``).

The smallest base radius (and, if asked, a translating roller's offset or an
oscillating roller's pivot distance) that meets the cam's pressure-angle, undercut
and Hertz-stress limits at its own phase angles and a speed, and the trade-off
between the base radius and the smallest phase angles. The
kernel is ``rust/core/src/synthesis/cam_size.rs``: the cam module's own criteria
(:meth:`cyclomech.cam.Cam.solve`'s pressure angle and curvature,
:meth:`cyclomech.cam.Cam.loads`'s stress), speeds and radii in parallel.

**What is searched, what is held.** The base radius always, over
[``min_base_radius``, ``max_base_radius``]; with ``offset=(lo, hi)`` a translating
roller's offset too, with ``pivot_distance=(lo, hi)`` an oscillating roller's pivot
distance (its arm length held: scaling pivot, arm and radius together would leave
every angle unchanged). The roller, the program, the loads and the contact are held.

**The rule.** g(R_b), the largest of the criteria's ratios (worst value over the
whole cam, dwells included, to its limit; ≤ 1 admissible, to 1 + 1e-9 so that a
cam laid out at its own bounds' angles is not read as violating them), is scanned on 64 radii
geometrically spaced over the range; the answer is the smallest scanned admissible
radius refined downward to the crossing by Brent's root (1e-13 relative): the
smallest radius where all hold, to within a scan cell (a feasible window narrower
than a cell is not seen). ``gap_above`` says a larger scanned radius violates again
(the stress of a non-monotone cam). Already admissible at ``min_base_radius``: the
answer is that bound, status ``"at_lower_bound"``, no criterion binding. No scanned
radius admissible: :class:`cyclomech.InputError` naming the criterion that fails and
the best ratio it reaches. The second dimension: 33 values over its range, the
least radius taken (ties to the smaller magnitude), refined by Brent's minimiser.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, float_array, positive, speeds_rpm, threads_arg
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ._followers import FlatFaced, OscillatingRoller
from ._followers import TranslatingRoller as _Translating
from ._loads import CRITERIA, Contact, FollowerLoads, bound_segments, pressure_limit_deg
from ._program import Cam

__all__ = [
    "CAM_SIZE_CRITERIA",
    "CamLimits",
    "CamSize",
    "CamSizeTradeoff",
    "cam_size",
    "cam_size_tradeoff",
]

Array = npt.NDArray[np.float64]

#: The criteria a sizing holds, in the order of :attr:`CamSize.ratios`; "geometry"
#: binds where the follower cannot be built at the radius.
CAM_SIZE_CRITERIA: tuple[str, ...] = _core.CAM_SIZE_CRITERIA

#: Scanned radii when ``min_base_radius`` is not given: R_max·1e-3, or just above
#: the roller (a base circle must hold the roller).
_ROLLER_CLEARANCE = 1.001


@dataclass(frozen=True)
class CamLimits:
    """The limits a cam is sized against.

    The undercut needs no number: the profile's radius of curvature must stay
    larger than the roller's (r_r/ρ_p ≤ 1 on both flanks of a groove).

    Parameters
    ----------
    max_pressure_angle_deg : float, optional
        The largest pressure angle [deg], in (0, 90); default None (30° translating,
        45° oscillating, as :meth:`cyclomech.cam.Cam.min_phase_angles`).
    max_stress : float, optional
        The largest Hertz stress σ_H [Pa] (needs ``loads`` and ``contact`` in
        :func:`cam_size`); default None (not a criterion).

    Raises
    ------
    InputError
        If a limit is not a finite number > 0 (the angle also < 90).

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.synthesis.CamLimits(25.0, 6e8).max_stress
    600000000.0
    >>> cm.synthesis.CamLimits(max_stress=-1.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: max_stress = -1.0 must be finite and > 0 [Pa]
    """

    max_pressure_angle_deg: float | None = None
    max_stress: float | None = None

    def __post_init__(self) -> None:
        a = self.max_pressure_angle_deg
        if a is not None:
            a = finite_number("max_pressure_angle_deg", a, "[deg]", low=0.0, strict=True)
            if a >= 90.0:
                raise InputError(f"max_pressure_angle_deg must be in (0, 90) [deg]; got {a!r}")
            object.__setattr__(self, "max_pressure_angle_deg", a)
        if self.max_stress is not None:
            object.__setattr__(self, "max_stress", positive("max_stress", self.max_stress, "[Pa]"))


@dataclass(frozen=True)
class CamSize:
    """A sized cam: the radius (and offset or pivot distance) chosen and why.

    Built by :func:`cam_size`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    cam : cyclomech.cam.Cam
        The cam with the chosen dimensions.
    rpm : float
        The cam speed [rpm] it was sized at.
    base_radius : float
        The chosen base radius [m].
    searched : tuple of str
        What was searched: ``("base_radius",)``, plus ``"offset"`` or
        ``"pivot_distance"``; everything else of the cam was held.
    status : str
        ``"ok"`` (a limit binds) or ``"at_lower_bound"`` (already admissible at
        ``min_base_radius``: the optimum is the search's bound).
    binding : str
        The criterion of ``CAM_SIZE_CRITERIA`` that binds (ratio 1), "" at the
        lower bound.
    ratios : dict of str to float
        Each criterion's worst value over the cam to its limit at the answer (≤ 1;
        0 where it is not a criterion).
    gap_above : bool
        A larger scanned radius violates a limit again (the admissible radii are a
        window, not an interval up to ``max_base_radius``).
    min_base_radius, max_base_radius : float
        The radii searched [m].

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
    >>> r = cm.synthesis.cam_size(cam, 300.0, max_base_radius=0.2)
    >>> r.binding, round(r.margins["pressure_angle"], 12)
    ('pressure_angle', 0.0)
    """

    cam: Cam
    rpm: float
    base_radius: float
    searched: tuple[str, ...]
    status: str
    binding: str
    ratios: dict[str, float]
    gap_above: bool
    min_base_radius: float
    max_base_radius: float

    @property
    def margins(self) -> dict[str, float]:
        """Each criterion's margin at the answer, 1 − ratio (0 on the binding one).

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
        ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
        >>> r = cm.synthesis.cam_size(cam, 300.0, max_base_radius=0.2)
        >>> {k: round(v, 4) for k, v in r.margins.items()}
        {'pressure_angle': 0.0, 'undercut': 0.5883, 'contact_stress': 1.0}
        """
        return {k: 1.0 - v for k, v in self.ratios.items()}


@dataclass(frozen=True)
class CamSizeTradeoff:
    """The smallest phase angles of a cam's rises and returns against its base radius.

    Built by :func:`cam_size_tradeoff`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    base_radius : ndarray of float, shape (radii,)
        The base radii [m].
    rpm : ndarray of float, shape (speeds,)
        The cam speeds [rpm].
    segments : tuple of int
        The indices of the bound segments.
    criteria : tuple of str
        The kernel's criteria (``cyclomech.cam.CRITERIA`` without "vibration", which
        does not depend on the radius).
    angle_deg : ndarray of float, shape (radii, speeds, segments, criteria)
        The smallest phase angles [deg] (NaN: none up to 360°, or the follower
        cannot be built at that radius; 0: no bound).

    Examples
    --------
    >>> import numpy as np
    >>> t = CamSizeTradeoff(np.ones(1), np.ones(1), (0,), ("a", "b"), np.ones((1, 1, 1, 2)))
    >>> t.bound_deg.shape
    (1, 1, 1)
    """

    base_radius: Array
    rpm: Array
    segments: tuple[int, ...]
    criteria: tuple[str, ...]
    angle_deg: Array

    @property
    def bound_deg(self) -> Array:
        """The bound of each segment, the largest over the criteria [deg], shape
        (radii, speeds, segments); NaN if any criterion's is.

        Examples
        --------
        >>> import numpy as np
        >>> a = np.array([[[[10.0, 20.0]]]])
        >>> CamSizeTradeoff(np.ones(1), np.ones(1), (0,), ("a", "b"), a).bound_deg.tolist()
        [[[20.0]]]
        """
        return np.max(self.angle_deg, axis=-1)


def _check_cam(cam: Any) -> Cam:
    if not isinstance(cam, Cam):
        raise InputError(f"cam must be a cyclomech.cam.Cam; got {cam!r}")
    return cam


def _kernel_loads(cam: Cam, loads: Any, contact: Any, limits: CamLimits) -> tuple[Any, Any]:
    if loads is not None and not isinstance(loads, FollowerLoads):
        raise InputError(f"loads must be None or a cyclomech.cam.FollowerLoads; got {loads!r}")
    if contact is not None and not isinstance(contact, Contact):
        raise InputError(f"contact must be None or a cyclomech.cam.Contact; got {contact!r}")
    if limits.max_stress is not None and (loads is None or contact is None):
        raise InputError(
            f"limits.max_stress = {limits.max_stress!r} [Pa] needs the follower's loads= "
            "(a cyclomech.cam.FollowerLoads) and contact= (a cyclomech.cam.Contact)"
        )
    return (
        None if loads is None else loads._kernel_args(len(cam.segments)),
        None if contact is None else contact._kernel_args(),
    )


def _range(name: str, value: Any) -> tuple[float, float]:
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a (low, high) range [m]; got {value!r}") from None
    a = finite_number(f"{name}[0]", lo, "[m]")
    b = finite_number(f"{name}[1]", hi, "[m]")
    if not b > a:
        raise InputError(f"{name} = ({a!r}, {b!r}) [m] must have low < high")
    return a, b


def _resized(cam: Cam, rb: float, second: str | None, p: float) -> Cam:
    kw: dict[str, float] = {"base_radius": rb}
    if second is not None:
        kw[second] = p
    follower = dataclasses.replace(cam.follower, **kw)  # type: ignore[arg-type]
    program = cam.segments if cam.program is None else cam.program
    return Cam(program, follower, cam.closure)


def _radius_range(cam: Cam, min_base_radius: Any, max_base_radius: Any) -> tuple[float, float]:
    """The base radii searched [m]: (R_min, R_max), checked."""
    hi = positive("max_base_radius", max_base_radius, "[m]")
    f = cam.follower
    roller = 0.0 if isinstance(f, FlatFaced) else f.roller_radius
    if min_base_radius is None:
        lo = roller * _ROLLER_CLEARANCE if roller > 0.0 else hi * 1e-3
    else:
        lo = positive("min_base_radius", min_base_radius, "[m]")
        if lo <= roller:
            raise InputError(
                f"min_base_radius = {lo!r} [m] must be > the roller's radius {roller!r} [m]"
            )
    if not hi > lo:
        raise InputError(f"max_base_radius = {hi!r} [m] must be > min_base_radius = {lo!r} [m]")
    return lo, hi


def _second(
    cam: Cam, offset: Any, pivot_distance: Any
) -> tuple[str | None, tuple[float, float] | None]:
    """The second dimension searched, if any: its name and range [m]."""
    f = cam.follower
    if offset is not None:
        if not isinstance(f, _Translating):
            raise InputError(
                f"offset= searches a TranslatingRoller's offset; this cam's follower is "
                f"{type(f).__name__}: drop offset="
            )
        return "offset", _range("offset", offset)
    if pivot_distance is not None:
        if not isinstance(f, OscillatingRoller):
            raise InputError(
                f"pivot_distance= searches an OscillatingRoller's pivot distance; this cam's "
                f"follower is {type(f).__name__}: drop pivot_distance="
            )
        return "pivot_distance", _range("pivot_distance", pivot_distance)
    return None, None


def _infeasible(
    binding: str, ratios: dict[str, float], rb: float, lo: float, hi: float, rpm: float
) -> InputError:
    """The error of a sizing no radius up to R_max meets: which requirement, how close."""
    what = (
        "the follower cannot be built at any radius searched"
        if binding == "geometry"
        else f"{binding} reaches at best {ratios[binding]:.4g}× its limit"
    )
    return InputError(
        f"no base radius in [{lo:g}, {hi:g}] m meets the limits at {rpm:g} rpm: "
        f"{what} (at base radius {rb:g} m); raise max_base_radius or relax the "
        f"{binding} limit"
    )


def cam_size(
    cam: Cam,
    rpm: Any,
    *,
    limits: CamLimits | None = None,
    loads: FollowerLoads | None = None,
    contact: Contact | None = None,
    max_base_radius: Any,
    min_base_radius: Any = None,
    offset: Any = None,
    pivot_distance: Any = None,
    n_threads: int | None = None,
) -> CamSize:
    """The smallest base radius that meets the cam's limits at its phase angles and speed.

    The pressure angle ≤ ``limits.max_pressure_angle_deg``, no undercut (the
    profile's radius of curvature larger than the roller's, both flanks of a
    groove; a flat face's −s″/(R_b + s) ≤ 1) and, with ``limits.max_stress``, the
    Hertz stress ≤ it, over the whole cam at ``rpm``: see the module's rule (scan,
    then Brent's root; the smallest radius where all hold; an optimum at
    ``min_base_radius`` reported as such).

    Parameters
    ----------
    cam : cyclomech.cam.Cam
        The cam: its program (phase angles, strokes, laws), follower and closure;
        its base radius is replaced, everything else held.
    rpm : float
        The cam speed [rpm] (the stress's inertia loads).
    limits : CamLimits, optional
        The limits; default None (``CamLimits()``: the default pressure angle only).
    loads : cyclomech.cam.FollowerLoads, optional
        The follower's mass, spring and loads (for the stress); default None.
    contact : cyclomech.cam.Contact, optional
        The Hertz contact (for the stress); default None.
    max_base_radius : float
        The largest base radius searched [m]; no admissible radius up to it is an
        :class:`cyclomech.InputError`.
    min_base_radius : float, optional
        The smallest base radius searched [m]; default None (the roller's radius
        ×1.001, or ``max_base_radius``·1e-3 for a flat face or a knife edge).
    offset : tuple of (float, float), optional
        A translating roller's offset range [m] to search for the least radius;
        default None (the cam's offset held).
    pivot_distance : tuple of (float, float), optional
        An oscillating roller's pivot-distance range [m] to search (its arm length
        held); default None (held).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    CamSize
        The sized cam, the binding limit and every criterion's margin.

    Raises
    ------
    InputError
        If an argument is malformed (the message names it), ``max_stress`` lacks
        ``loads`` or ``contact``, ``offset`` is asked of a follower without one (or
        ``pivot_distance``), or no radius up to ``max_base_radius`` meets the limits:
        the message names the criterion that fails, the least ratio it reaches and
        at which radius.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
    >>> r = cm.synthesis.cam_size(cam, 300.0, limits=cm.synthesis.CamLimits(30.0),
    ...                           max_base_radius=0.2)
    >>> round(r.base_radius, 6), r.binding, r.status
    (0.01429, 'pressure_angle', 'ok')
    """
    c = _check_cam(cam)
    n = speeds_rpm("rpm", rpm)
    if n.size != 1 or np.ndim(rpm) != 0:
        raise InputError(f"rpm must be one speed [rpm]; got {rpm!r}")
    if limits is None:
        limits = CamLimits()
    if not isinstance(limits, CamLimits):
        raise InputError(f"limits must be a cyclomech.synthesis.CamLimits; got {limits!r}")
    alpha = pressure_limit_deg(c, limits.max_pressure_angle_deg)
    kl, kc = _kernel_loads(c, loads, contact, limits)
    lo, hi = _radius_range(c, min_base_radius, max_base_radius)
    second, span = _second(c, offset, pivot_distance)
    row = _core.cam_size(
        c._kernel,
        n * RAD_PER_S_PER_RPM,
        math.radians(alpha),
        lo,
        hi,
        kl,
        kc,
        limits.max_stress,
        span,
        n_threads=threads_arg(n_threads),
    )[0]
    names = CAM_SIZE_CRITERIA[:3]
    ratios = {k: float(v) for k, v in zip(names, row[4:7], strict=True)}
    status = _core.CAM_SIZE_STATUS[int(row[2])]
    binding = "" if row[3] < 0 else CAM_SIZE_CRITERIA[int(row[3])]
    rb = float(row[0])
    if status == "infeasible":
        raise _infeasible(binding, ratios, rb, lo, hi, float(n[0]))
    p = float(row[1])
    sized = _resized(c, rb, second, p)
    return CamSize(
        cam=sized,
        rpm=float(n[0]),
        base_radius=rb,
        searched=("base_radius",) if second is None else ("base_radius", second),
        status=status,
        binding=binding,
        ratios=ratios,
        gap_above=bool(row[7]),
        min_base_radius=lo,
        max_base_radius=hi,
    )


def cam_size_tradeoff(
    cam: Cam,
    rpm: Any,
    base_radius: Any,
    *,
    limits: CamLimits | None = None,
    loads: FollowerLoads | None = None,
    contact: Contact | None = None,
    segments: Any = None,
    n_threads: int | None = None,
) -> CamSizeTradeoff:
    """The smallest phase angle of each rise and return against the base radius.

    For each base radius (the cam's other dimensions held), the cam's own
    :meth:`cyclomech.cam.Cam.min_phase_angles` (pressure angle, undercut, jump,
    stress; the same rule) at each speed: one Rust call, radii in parallel. In a
    machine the cam's size sets its bounds in the timing LP and the LP its phase
    angles: this is the curve between them.

    Parameters
    ----------
    cam : cyclomech.cam.Cam
        The cam.
    rpm : float or array_like of float
        The cam speeds [rpm].
    base_radius : array_like of float
        The base radii [m] (> 0); one where the follower cannot be built gives NaN.
    limits : CamLimits, optional
        The limits; default None (the default pressure angle only).
    loads : cyclomech.cam.FollowerLoads, optional
        The follower's loads (jump; the stress); default None.
    contact : cyclomech.cam.Contact, optional
        The Hertz contact (the stress); default None.
    segments : int or sequence of int, optional
        The rises and returns to bound; default None (every rest-to-rest one).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    CamSizeTradeoff
        The angles [deg], shape (radii, speeds, segments, criteria).

    Raises
    ------
    InputError
        As :meth:`cyclomech.cam.Cam.min_phase_angles`, or if a radius is not > 0.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
    >>> t = cm.synthesis.cam_size_tradeoff(cam, 300.0, [0.03, 0.05, 0.08])
    >>> np.round(t.bound_deg[:, 0, 0], 2).tolist()
    [80.71, 57.18, 39.86]
    """
    c = _check_cam(cam)
    n = speeds_rpm("rpm", rpm)
    if limits is None:
        limits = CamLimits()
    if not isinstance(limits, CamLimits):
        raise InputError(f"limits must be a cyclomech.synthesis.CamLimits; got {limits!r}")
    alpha = pressure_limit_deg(c, limits.max_pressure_angle_deg)
    kl, kc = _kernel_loads(c, loads, contact, limits)
    radii = float_array("base_radius", base_radius, ndims=(0, 1)).reshape(-1)
    bad = ~(np.isfinite(radii) & (radii > 0))
    if radii.size == 0 or bad.any():
        got = float(radii[np.argmax(bad)]) if radii.size else "none"
        raise InputError(f"base_radius must hold radii [m], each finite and > 0; got {got}")
    idx = bound_segments(c, segments)
    out = _core.cam_size_tradeoff(
        c._kernel,
        np.ascontiguousarray(radii),
        list(idx),
        n * RAD_PER_S_PER_RPM,
        math.radians(alpha),
        kl,
        kc,
        limits.max_stress,
        n_threads=threads_arg(n_threads),
    )
    return CamSizeTradeoff(
        base_radius=radii.copy(),
        rpm=n,
        segments=idx,
        criteria=tuple(k for k in CRITERIA if k != "vibration"),
        angle_deg=np.degrees(out),
    )
