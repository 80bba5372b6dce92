"""A cam's rises and returns that no operation times (no ``arc``): they keep their
file's angles, so their criteria set the cam's own speed limit
(:meth:`cyclomech.cam._kind.CamMechanism.speed_limit_rpm`)."""

from __future__ import annotations

import math

import numpy as np

from ._design import CamDesign
from ._followers import FlatFaced
from ._loads import CRITERIA
from ._program import Cam

__all__ = ["checks", "own_limit"]


def checks(design: CamDesign, k: int) -> list[str]:
    """The criteria that apply to segment ``k`` of a cam (whether or not it is bound)."""
    cam = design.cam
    flat = isinstance(cam.follower, FlatFaced)
    knife = not isinstance(cam.follower, FlatFaced) and cam.follower.roller_radius == 0.0
    out = []
    if not flat:
        out.append("pressure_angle")
    if not knife:
        out.append("undercut")
    if cam.closure == "spring" and design.loads is not None and design.loads.mass > 0:
        out.append("jump")
    if design.max_stress is not None:
        out.append("contact_stress")
    if design.vibration is not None:
        out.append("vibration")
    return out


#: The reference speed [rpm] of the criteria proportional to the speed (jump,
#: vibration) on a segment no operation times (:meth:`CamMechanism.speed_limit_rpm`).
REF_RPM = 1e-3

#: The highest speed [rpm] searched for a σ_H limit of a segment no operation times.
STRESS_CAP_RPM = 1e6


def stress_limit_rpm(design: CamDesign, k: int, beta: float, at_ref: float) -> float:
    """The speed [rpm] above which segment ``k`` at ``beta`` [deg] fails [σ_H]: 0 where
    it fails at the reference speed (``at_ref`` its smallest angle there), inf where it
    holds up to :data:`STRESS_CAP_RPM`; else the root of (its smallest angle − beta)
    in the speed (Brent's, 1e-9 relative), bracketed on a geometric grid of speeds
    solved in one call.

    One crossing, not several: at each cam angle the contact force is affine in ω²
    (the inertia force ∝ ω², the spring, the preload and the loads not), so its
    largest value over the segment, and with it the largest σ_H, is convex in ω².
    The speeds where σ_H ≤ [σ_H] are then one interval; it holds the reference
    speed, so the first grid speed past it brackets its only upper end. σ_H need
    not grow with the speed: on the loom's lift it falls from 101 to 98 MPa up to
    ~35 rpm (the inertia unloading the spring's peak at the end of the rise), then
    rises."""
    from scipy.optimize import brentq  # here: scipy.optimize is ~0.3 s to import

    col = CRITERIA.index("contact_stress")
    if math.isnan(at_ref) or at_ref > beta:
        return 0.0
    grid = np.geomspace(REF_RPM, STRESS_CAP_RPM, 91)
    need = design.min_phase_angles(grid, segments=[k]).angle_deg[:, 0, col]
    over = np.flatnonzero(~(need <= beta))
    if over.size == 0:
        return math.inf
    i = int(over[0])
    lo, hi = float(grid[i - 1]), float(grid[i])

    def gap(rpm: float) -> float:
        v = float(design.min_phase_angles([rpm], segments=[k]).angle_deg[0, 0, col])
        return 360.0 if math.isnan(v) else v - beta

    return float(brentq(gap, lo, hi, rtol=1e-9))


def segment_pressure_angle_deg(cam: Cam, k: int) -> float:
    """The largest pressure angle [deg] on segment ``k`` of ``cam`` (2001 angles)."""
    start = sum(g.angle_deg for g in cam.segments[:k])
    theta = np.radians(start + np.linspace(0.0, cam.segments[k].angle_deg, 2001))
    return float(np.degrees(np.abs(cam.solve(theta).pressure_angle).max()))


def own_limit(name: str, d: CamDesign) -> tuple[float, str]:
    """The own speed limit [rpm] of a cam named ``name`` and why: its rises and
    returns no operation times (:meth:`CamMechanism.speed_limit_rpm`).

    Parameters
    ----------
    name : str
        The cam's name, for the reason.
    d : CamDesign
        The cam with its loads, contact, limits and arcs.

    Returns
    -------
    rpm : float
        The limit [rpm]: inf where every rise and return has an arc or nothing
        binds, 0 where a check fails at every speed.
    reason : str
        The segment and the criterion ("" with no limit).

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.from_toml("examples/stb_loom.toml")
    >>> own_limit("lifter cam", m.mechanisms["lifter cam"].design)   # every segment bound
    (inf, '')
    """
    # The rises and returns no operation times keep their file's angles (the
    # layout takes the optimum's differences from the dwells), so their
    # speed-dependent criteria bound the speed by themselves: the mechanism's own
    # limit, as a servo axis's untimed segments bound it.
    segs = d.cam.segments
    free = [
        k
        for k, a in enumerate(d.arcs)
        if a is None and segs[k].kind in ("rise", "return") and checks(d, k)
    ]
    if not free:
        return math.inf, ""
    # Jump and vibration are exactly proportional to the speed: at a small
    # reference speed the angle is their ratio (and fits where 1 rpm may not).
    at = d.min_phase_angles([REF_RPM], segments=free).angle_deg[0]
    best, why = math.inf, ""
    for j, k in enumerate(free):
        beta = segs[k].angle_deg
        for c in checks(d, k):
            v = float(at[j, CRITERIA.index(c)])
            if c in ("jump", "vibration"):
                rpm = 0.0 if math.isnan(v) else (math.inf if v <= 0.0 else beta * REF_RPM / v)
            elif c == "contact_stress":
                rpm = stress_limit_rpm(d, k, beta, v)
            else:
                rpm = 0.0 if math.isnan(v) or v > beta * (1.0 + 1e-9) else math.inf
            if rpm < best:
                best, why = rpm, _reason(name, d, k, c, rpm, v)
    return best, why


def _reason(name: str, d: CamDesign, k: int, c: str, rpm: float, need: float) -> str:
    """Why segment ``k`` (no operation times it) limits the speed to ``rpm`` by
    criterion ``c`` (``need``: its smallest angle at the reference speed [deg])."""
    g = d.cam.segments[k]
    at = f"cam {name!r} segment {k + 1} ({g.kind}, {g.angle_deg:g}°, no arc)"
    fix = "; give it an arc (an operation) or a longer angle"
    if c == "jump":
        return f"{at}: the follower leaves the cam above {rpm:.2f} rpm{fix}, or a stronger spring"
    if c == "vibration":
        return f"{at}: the residual vibration exceeds its limit above {rpm:.2f} rpm{fix}"
    if c == "contact_stress":
        assert d.max_stress is not None
        if rpm == 0.0:
            return f"{at}: σ_H exceeds [σ_H] = {d.max_stress / 1e6:g} MPa at every speed{fix}"
        return f"{at}: σ_H exceeds [σ_H] = {d.max_stress / 1e6:g} MPa above {rpm:.2f} rpm{fix}"
    more = "no angle up to a whole turn will do" if math.isnan(need) else f"it needs {need:.4g}°"
    if c == "pressure_angle":
        top = segment_pressure_angle_deg(d.cam, k)
        return (
            f"{at}: the pressure angle reaches {top:.4g}° > [α] = "
            f"{d.max_pressure_angle_deg:g}° at every speed ({more}){fix}"
        )
    return f"{at}: the profile is undercut at every speed ({more}){fix}"
