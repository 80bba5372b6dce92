"""The frame's shaking force and moment (:class:`Shaking`, :func:`shaking`) of one
linkage, from its kinetostatics, and of the whole machine, each mechanism at its
phase in the optimised cyclogram (issue 34, item 4).

**What is included.** The forces the mechanism puts on the frame are its ground
joints' reactions, its frame guides' normal forces and, as a moment, the reaction
−T of the driving torque on the motor's stator (the motor sits on the frame). By
the momentum balance of the moving parts they are

    F_frame = −Σ mᵢ a_Gᵢ + Σ mᵢ g + Σ F_loads,
    M_frame = −Σ (r_Gᵢ × mᵢ a_Gᵢ + Jᵢ αᵢ) + Σ r × (mᵢ g + F_loads) + Σ T_loads,

about the point ``about_m``. The **shaking** force and moment are the inertia
terms only, −Σ mᵢ a_Gᵢ and −dH/dt: gravity is excluded (the moving parts'
weight Σ mᵢ g is a constant load on the frame's feet that does not shake it), and
so are the working loads (a cutting or pressing force acts between the tool and
the work, which rests on the frame: it closes inside the machine). At crank speed
ω and acceleration ε they are ω²·(part 0) + ε·(part 1), from the kinetostatics'
parts; part 2, the static part (weight and loads as the bearings and guides carry
them), is kept beside them for :meth:`Shaking.frame_force`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, instance
from .._errors import InputError
from .._units import at_speed
from ..cam import Cam, FlatFaced, TranslatingRoller
from ..forces import Kinetostatics
from ..linkage import Linkage
from ..press import GearLeverPress

__all__ = ["Shaking", "shaking"]

Array = npt.NDArray[np.float64]


def _cross(a: Array, b: Array) -> Array:
    out: Array = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _point(name: str, about: Any) -> tuple[float, float]:
    if isinstance(about, str) or not hasattr(about, "__len__") or len(about) != 2:
        raise InputError(f"{name} = {about!r} must be a point (x, y) [m]")
    return (finite_number(name, about[0], "[m]"), finite_number(name, about[1], "[m]"))


def _frame_guides(k: Kinetostatics, linkage: Linkage | None) -> list[tuple[int, int, Array]]:
    """(guide index, point index, unit normal at each angle (N, 2)) of every
    guide that lies on the frame: a slider's guide given as a direction on the
    ground, or a line through two ground joints. Its normal force acts on the
    slider along the normal; the frame takes the opposite."""
    if not k.guides:
        return []
    if linkage is None:
        raise InputError(
            f"linkage: the kinetostatics has guides ({', '.join(k.guides)}); give the "
            "linkage it was solved for (linkage=...), whose guides' directions the "
            "normal forces refer to"
        )
    lk = instance("linkage", linkage, Linkage)
    names = list(k.solution.names)
    if list(lk.names) != names:
        raise InputError(
            f"linkage: its points {list(lk.names)} are not the kinetostatics' {names}; "
            "give the linkage it was solved for"
        )
    table = lk.to_dict()
    ground = set(table["ground"])
    idx = {p: i for i, p in enumerate(names)}
    xy = k.solution.xy
    out: list[tuple[int, int, Array]] = []
    g = 0
    for p, guides in (table.get("sliders") or {}).items():
        for spec in guides:
            ((kind, arg),) = spec.items()
            if kind == "ground":
                d = np.broadcast_to(np.array([float(arg[0]), float(arg[1])]), (xy.shape[0], 2))
            elif set(arg) <= ground:
                d = xy[:, idx[arg[1]]] - xy[:, idx[arg[0]]]
            else:
                g += 1
                continue  # a guide on a moving link: its force stays in the mechanism
            d = d / np.hypot(d[:, 0], d[:, 1])[:, None]
            out.append((g, idx[p], np.stack([-d[:, 1], d[:, 0]], axis=1)))
            g += 1
    if g != len(k.guides):
        raise InputError(
            f"linkage: it has {g} guides, the kinetostatics {len(k.guides)}; give the "
            "linkage it was solved for"
        )
    return out


@dataclass(frozen=True)
class Shaking:
    """The force and moment on the frame over the cycle, in parts (ω², ε, static).

    ``force(rpm)`` and ``moment(rpm)`` are the shaking force and moment (inertia
    only: ω²·part 0 + ε·part 1); ``frame_force`` and ``frame_moment`` add the
    static part (gravity and working loads, see :mod:`cyclomech.dynamics`). Built by
    :func:`shaking`; each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    angles_deg : ndarray of float, shape (N,)
        The crank angles of one mechanism, or the main shaft's cycle angles of a
        machine [deg].
    force_parts : ndarray of float, shape (3, N, 2)
        The force (x, y) on the frame: per ω² [N·s²], per ε [N·s²] and static [N].
    moment_parts : ndarray of float, shape (3, N)
        The moment on the frame about ``about_m``, counter-clockwise positive: per
        ω² [N·m·s²], per ε [N·m·s²] and static [N·m].
    about_m : tuple of (float, float)
        The point the moment is taken about (x, y) [m].
    parts : dict of str to Shaking, default {}
        A machine's: each contributing mechanism's, at its phase.
    skipped : dict of str to str, default {}
        A machine's: each mechanism left out, with the reason.
    notes : dict of str to str, default {}
        A machine's: what was assumed for a mechanism included (an oscillating
        follower's centre of mass at its pivot).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> k = cm.forces.kinetostatics(crank, np.radians([0.0, 90.0]), point_masses={"A": 2.0})
    >>> s = cm.dynamics.shaking(k)
    >>> s.force(60.0).round(4).tolist()     # m r ω², outwards along the crank
    [[23.6871, 0.0], [0.0, 23.6871]]
    """

    angles_deg: Array
    force_parts: Array
    moment_parts: Array
    about_m: tuple[float, float] = (0.0, 0.0)
    parts: dict[str, Shaking] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)
    notes: dict[str, str] = field(default_factory=dict)

    def __repr__(self) -> str:
        extra = f", {len(self.parts)} mechanisms" if self.parts else ""
        return f"Shaking({self.angles_deg.size} angles, about {self.about_m}{extra})"

    def force(self, rpm: Any, crank_acceleration: Any = 0.0) -> Array:
        """The shaking force −Σ mᵢ a_Gᵢ [N] at a crank speed and acceleration.

        Parameters
        ----------
        rpm : float
            The crank (main shaft) speed [rpm].
        crank_acceleration : float, default 0.0
            Its angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N, 2)
            The force (x, y) on the frame at each angle [N], inertia only.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
        >>> cm.dynamics.shaking(k).force(0.0, crank_acceleration=10.0).tolist()  # −m r ε ŷ
        [[0.0, -6.0]]
        """
        return at_speed(self.force_parts, rpm, crank_acceleration, static=False, rpm_low=0.0)

    def moment(self, rpm: Any, crank_acceleration: Any = 0.0) -> Array:
        """The shaking moment −dH/dt about ``about_m`` [N·m] at a speed and acceleration.

        It includes the reaction of the driving torque on the frame (the motor's
        stator), as the frame feels it.

        Parameters
        ----------
        rpm : float
            The crank (main shaft) speed [rpm].
        crank_acceleration : float, default 0.0
            Its angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N,)
            The moment on the frame at each angle [N·m], counter-clockwise positive.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
        >>> cm.dynamics.shaking(k).moment(0.0, crank_acceleration=10.0).round(9).tolist()  # −m r² ε
        [-1.8]
        """
        return at_speed(self.moment_parts, rpm, crank_acceleration, static=False, rpm_low=0.0)

    def frame_force(self, rpm: Any, crank_acceleration: Any = 0.0) -> Array:
        """The whole force on the frame [N]: the shaking force plus the static part.

        Parameters
        ----------
        rpm : float
            The crank (main shaft) speed [rpm].
        crank_acceleration : float, default 0.0
            Its angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N, 2)
            The force (x, y) the bearings and guides put on the frame [N]: with the
            moving parts' weight and the working loads.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0}, gravity=(0, -9.81))
        >>> cm.dynamics.shaking(k).frame_force(0.0).round(6).tolist()   # the weight m g
        [[0.0, -19.62]]
        """
        return self.force(rpm, crank_acceleration) + self.force_parts[2]

    def frame_moment(self, rpm: Any, crank_acceleration: Any = 0.0) -> Array:
        """The whole moment on the frame about ``about_m`` [N·m], static part included.

        Parameters
        ----------
        rpm : float
            The crank (main shaft) speed [rpm].
        crank_acceleration : float, default 0.0
            Its angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N,)
            The moment on the frame [N·m], counter-clockwise positive.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0}, gravity=(0, -9.81))
        >>> cm.dynamics.shaking(k).frame_moment(0.0).round(6).tolist()  # the weight's, r × m g
        [-5.886]
        """
        return self.moment(rpm, crank_acceleration) + self.moment_parts[2]

    def stats(self, rpm: Any) -> dict[str, float]:
        """Peak and RMS of the shaking force and moment over the cycle, at constant speed.

        The RMS is over the N angles (a uniform grid over the cycle gives the
        cycle's RMS).

        Parameters
        ----------
        rpm : float
            The crank (main shaft) speed [rpm].

        Returns
        -------
        dict of str to float
            ``peak_force_n``, ``rms_force_n`` (of |F|), ``peak_force_deg`` (the angle
            of the peak), ``peak_moment_nm`` and ``rms_moment_nm`` (of |M|).

        Raises
        ------
        InputError
            If ``rpm`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, np.radians([0.0, 180.0]), point_masses={"A": 2.0})
        >>> round(cm.dynamics.shaking(k).stats(60.0)["rms_force_n"], 4)
        23.6871
        """
        f = np.hypot(*self.force(rpm).T)
        m = np.abs(self.moment(rpm))
        i = int(np.argmax(f)) if f.size else 0
        return {
            "peak_force_n": float(f.max(initial=0.0)),
            "rms_force_n": float(np.sqrt(np.mean(f**2))) if f.size else 0.0,
            "peak_force_deg": float(self.angles_deg[i]) if f.size else math.nan,
            "peak_moment_nm": float(m.max(initial=0.0)),
            "rms_moment_nm": float(np.sqrt(np.mean(m**2))) if m.size else 0.0,
        }


def _of_kinetostatics(
    k: Kinetostatics, linkage: Linkage | None, about: tuple[float, float]
) -> Shaking:
    """The frame's force and moment in parts from the reactions of ``k``."""
    if not k.pairs:
        raise InputError(
            "mechanism: the joints' forces were not computed (kinetostatics(..., "
            "reactions=False)); solve with reactions=True"
        )
    guides = _frame_guides(k, linkage)
    names = list(k.solution.names)
    r = k.solution.xy - np.array(about)  # (N, P, 2)
    force = np.zeros((3, k.angles.size, 2))
    moment = np.zeros((3, k.angles.size))
    for i, (p, link) in enumerate(k.pairs):
        if link == "frame":
            f = k.reaction_parts[:, :, i]
            force += f
            moment += _cross(r[None, :, names.index(p)], f)
    for g, at, normal in guides:
        f = -k.guide_parts[:, :, g, None] * normal[None]
        force += f
        moment += _cross(r[None, :, at], f)
    moment -= k.torque_parts  # the motor's stator takes −T
    return Shaking(np.degrees(k.angles), force, moment, about)


def _phased(s: Shaking, phase_deg: float) -> Shaking:
    """``s`` moved to its phase in the cycle by the main shaft's own phasing
    (:meth:`cyclomech.shaft.ShaftTorque.from_curves`)."""
    from ..shaft import ShaftTorque

    def shift(a: Array, b: Array) -> tuple[Array, Array]:
        t = ShaftTorque.from_curves(a, b, [phase_deg])
        return t.per_omega2, t.static

    n = s.angles_deg.size
    f = np.empty_like(s.force_parts)
    m = np.empty_like(s.moment_parts)
    for c in range(2):
        f[0, :, c], f[2, :, c] = shift(s.force_parts[0, :, c], s.force_parts[2, :, c])
        f[1, :, c], _ = shift(s.force_parts[1, :, c], np.zeros(n))
    m[0], m[2] = shift(s.moment_parts[0], s.moment_parts[2])
    m[1], _ = shift(s.moment_parts[1], np.zeros(n))
    theta = np.arange(n, dtype=np.float64) * (360.0 / n)
    return Shaking(theta, f, m, s.about_m)


def _of_cam(cam: Cam, mass: float, about: tuple[float, float], n: int) -> Shaking:
    """A translating follower's shaking: −m s̈ along +y (the follower's axis as
    :mod:`cyclomech.cam` draws it, at x = its offset), on ``n`` cam angles from 0.
    The spring, the loads and the cam's contact force act between the follower,
    the cam and the frame: they close inside the machine (no static part)."""
    theta = np.arange(n, dtype=np.float64) * (2.0 * math.pi / n)
    kin = cam.solve(theta)
    e = cam.follower.offset if isinstance(cam.follower, TranslatingRoller) else 0.0
    force = np.zeros((3, n, 2))
    force[0, :, 1] = -mass * kin.dds
    force[1, :, 1] = -mass * kin.ds
    moment = (e - about[0]) * force[:, :, 1]  # the axis x = e: (r − Q) × F
    return Shaking(np.degrees(theta), force, moment, about)


def _of_oscillating(cam: Cam, inertia: float, about: tuple[float, float], n: int) -> Shaking:
    """An oscillating follower's shaking on ``n`` cam angles from 0: its arm is
    given by its moment of inertia J about the pivot alone, so its centre of mass
    is taken at the pivot (a lever balanced about its axis): no shaking force, and
    the moment −dH/dt of a lever turning about a fixed point, a couple (the same
    about every point). The arm's angle in the plane is π − ψ (the roller centre
    at (a − l·cos ψ, l·sin ψ), :mod:`cyclomech.cam`), ψ = ψ0 + s, so H = −J·ψ̇ and
    −dH/dt = J·s̈ = J·(ω²·s″ + ε·s′)."""
    theta = np.arange(n, dtype=np.float64) * (2.0 * math.pi / n)
    kin = cam.solve(theta)
    moment = np.zeros((3, n))
    moment[0] = inertia * kin.dds
    moment[1] = inertia * kin.ds
    return Shaking(np.degrees(theta), np.zeros((3, n, 2)), moment, about)


def _of_press(
    press: GearLeverPress, slider_mass: float, rod_mass: float, about: tuple[float, float], n: int
) -> Shaking:
    """The slider's and the (uniform) rod's shaking on ``n`` carrier angles ψ past
    BDC in the direction of rotation (α = −ψ), in the frame of the guide gear's
    centre. Their accelerations are differentiated in ψ from the drive's exact
    positions by a 5-point central stencil, h = 1e-3 rad: its truncation (~h⁴) is
    below its rounding, which 1/h² amplifies to ~4e-9 of the peak (measured
    against the press kernel's exact Π″, tested to 1e-8; a larger h trades it for
    truncation). The carrier's and planet's masses are not in the press's model."""
    psi = np.arange(n, dtype=np.float64) * (2.0 * math.pi / n)
    h = 1e-3
    steps = (-2, -1, 0, 1, 2)
    kin = [press.solve(np.mod(-(psi + k * h), 2.0 * math.pi)) for k in steps]
    slider = np.stack([k.slider for k in kin])  # (5, N, 2)
    pin = np.stack([k.pin for k in kin])
    centre = 0.5 * (slider + pin)
    d = slider - pin
    phi = np.unwrap(np.arctan2(d[..., 1], d[..., 0]), axis=0)

    def d1(x: Array) -> Array:
        out: Array = (x[0] - 8 * x[1] + 8 * x[3] - x[4]) / (12 * h)
        return out

    def d2(x: Array) -> Array:
        out: Array = (-x[0] + 16 * x[1] - 30 * x[2] + 16 * x[3] - x[4]) / (12 * h * h)
        return out

    jg = rod_mass * press.L**2 / 12.0
    q = np.array(about)
    force = np.zeros((3, n, 2))
    moment = np.zeros((3, n))
    # At shaft speed ω and acceleration ε a point's acceleration is ω² X_ψψ + ε X_ψ.
    for i, diff in ((0, d2), (1, d1)):
        a_s, a_g, alpha = diff(slider), diff(centre), diff(phi)
        f_s, f_g = -slider_mass * a_s, -rod_mass * a_g
        force[i] = f_s + f_g
        moment[i] = _cross(slider[2] - q, f_s) + _cross(centre[2] - q, f_g) - jg * alpha
    return Shaking(np.degrees(psi), force, moment, about)


def _of_machine(result: Any, about: tuple[float, float], offsets: Mapping[str, Any]) -> Shaking:
    """Each linkage's, translating cam follower's and loaded press's shaking at its
    phase (the phase its shaft torque takes, on the same samples), summed."""
    parts: dict[str, Shaking] = {}
    skipped: dict[str, str] = {}
    notes: dict[str, str] = {}
    for name in offsets:
        if name not in result.mechanisms:
            raise InputError(
                f"offsets_m: no mechanism {name!r}; the mechanisms are "
                f"{', '.join(result.mechanisms)}"
            )
    for name, res in result.mechanisms.items():
        k = getattr(res, "kinetostatics", None)
        get = getattr(res, "shaft_torque", None)
        curve = None if get is None else get()
        off = _point(f"offsets_m[{name!r}]", offsets.get(name, (0.0, 0.0)))
        # The mechanism's own coordinates sit at `off` in the machine's frame.
        own_about = (about[0] - off[0], about[1] - off[1])
        cam = getattr(res, "cam", None)
        if isinstance(k, Kinetostatics) and curve is not None:
            own = _of_kinetostatics(k, res.mech.linkage, own_about)
        elif isinstance(getattr(res.mech, "press", None), GearLeverPress) and curve is not None:
            m = res.mech
            own = _of_press(m.press, m.slider_mass, m.rod_mass, own_about, curve[0].size)
        elif isinstance(cam, Cam) and curve is not None:
            mass = float(res.mech.design.loads.mass)
            if isinstance(cam.follower, TranslatingRoller | FlatFaced):
                own = _of_cam(cam, mass, own_about, curve[0].size)
            elif mass > 0:
                own = _of_oscillating(cam, mass, own_about, curve[0].size)
                notes[name] = (
                    f"an oscillating follower given by its inertia about the pivot "
                    f"({mass:g} kg·m²): its centre of mass is taken at the pivot, so it "
                    "shakes the frame by a moment only (J·ψ̈, a couple), no force"
                )
            else:
                skipped[name] = (
                    "an oscillating follower without inertia_kg_m2: nothing of it moves with mass"
                )
                continue
        elif getattr(res.mech, "kind", "") == "cam_stop":
            skipped[name] = (
                "a cam stop: the impact of a lever on its stop, not the lever's motion "
                "over the cycle (the cam that drives it shakes the frame through its "
                "follower's mass or inertia)"
            )
            continue
        else:
            skipped[name] = (
                "no inertia forces at a phase in the cyclogram (a linkage with masses, a "
                "cam with its follower's loads or a loaded press is needed; servo axes "
                "are not included yet)"
            )
            continue
        parts[name] = _phased(own, float(curve[2]))
    if not parts:
        raise InputError(
            "mechanism: the machine has no linkage with masses, translating cam follower "
            "with loads nor loaded press at a phase in the cyclogram; "
            f"left out: {'; '.join(f'{k}: {v}' for k, v in skipped.items()) or 'none'}"
        )
    first = next(iter(parts.values()))
    force: Array = np.sum([p.force_parts for p in parts.values()], axis=0)
    moment: Array = np.sum([p.moment_parts for p in parts.values()], axis=0)
    return Shaking(
        first.angles_deg,
        force,
        moment,
        about,
        parts=parts,
        skipped=skipped,
        notes=notes,
    )


def shaking(
    mechanism: Any,
    *,
    linkage: Linkage | None = None,
    about_m: Any = (0.0, 0.0),
    offsets_m: Mapping[str, Any] | None = None,
) -> Shaking:
    """The shaking force and moment on the frame over the cycle.

    Of one linkage (its :class:`~cyclomech.forces.Kinetostatics`, or a machine's
    linkage result) or of a whole machine (a :class:`~cyclomech.machine.MachineResult`):
    each linkage with masses, each translating cam follower with loads and each
    loaded press (its slider and rod) at the phase its driving torque takes on the
    main shaft, summed (the rest listed in ``skipped`` with the reason: servo
    axes, a follower without mass). An oscillating follower, given by its arm's
    moment of inertia J about the pivot, is taken with its centre of mass at the
    pivot: it shakes the frame by the couple J·ψ̈ only (said in ``notes``). A
    linkage's force is taken from its ground joints' reactions and frame guides'
    normal forces, the moment adds the driving torque's reaction on the motor; see
    :mod:`cyclomech.dynamics` for what is included (gravity and the working loads
    only in the static part). A cam follower of mass m shakes the frame by −m s̈
    along +y, its axis as :mod:`cyclomech.cam` draws it (at x = its offset from the
    cam's centre, the origin of the cam's coordinates); a press's slider and uniform
    rod by their accelerations from the drive's positions (:meth:`GearLeverPress.solve
    <cyclomech.press.GearLeverPress.solve>`, in the frame of its guide gear's centre;
    the carrier's and planet's masses are not in its model).

    Parameters
    ----------
    mechanism : Kinetostatics, LinkageResult or MachineResult
        The forces of one linkage (with reactions), a machine's linkage result
        (``result.mechanisms[name]``) or the machine's result (each mechanism in
        its own coordinates, placed by ``offsets_m``).
    linkage : Linkage, optional
        The linkage a ``Kinetostatics`` was solved for: needed when it has guides
        (their directions); default None.
    about_m : tuple of (float, float), default (0.0, 0.0)
        The point the moment is taken about (x, y) [m], in the linkage's (the
        machine's) coordinates.
    offsets_m : mapping of str to tuple of (float, float), optional
        A machine's: where each mechanism's origin sits in the machine's frame
        [m]; default None (every mechanism drawn in one frame). The force does not
        depend on it, the moment does.

    Returns
    -------
    Shaking
        The force and moment in parts (ω², ε, static) at each angle.

    Raises
    ------
    InputError
        If the kinetostatics has no reactions, has guides and no (or another)
        ``linkage``, ``about_m`` is not a finite point, or a machine has no linkage
        with masses at a phase (or ``offsets_m`` names no mechanism of it).
    TypeError
        If ``mechanism`` is none of the above or ``linkage`` not a Linkage.

    Examples
    --------
    A slider-crank (crank 0.1 m, rod 0.35 m) with 3 kg on the slider shakes its frame
    along the guide by m r ω² (cos φ + (r/l) cos 2φ + …):

    >>> import numpy as np, cyclomech as cm
    >>> sc = cm.Linkage({"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
    ...                 [("A", "B"), ("B", "C")], ["A"], ("A", "B"),
    ...                 sliders={"C": ("ground", (1, 0))})
    >>> k = cm.forces.kinetostatics(sc, np.radians([0.0, 90.0]), point_masses={"C": 3.0})
    >>> s = cm.dynamics.shaking(k, linkage=sc)
    >>> (s.force(300.0) / (3.0 * 0.1 * (300 * np.pi / 30) ** 2)).round(4).tolist()
    [[1.2857, 0.0], [-0.2981, 0.0]]
    """
    if linkage is not None:
        instance("linkage", linkage, Linkage)
    about = _point("about_m", about_m)
    if isinstance(mechanism, Kinetostatics):
        if offsets_m is not None:
            raise InputError("offsets_m: only a machine's result has mechanisms to place")
        return _of_kinetostatics(mechanism, linkage, about)
    k = getattr(mechanism, "kinetostatics", None)
    mech = getattr(mechanism, "mech", None)
    if isinstance(k, Kinetostatics) and isinstance(getattr(mech, "linkage", None), Linkage):
        return _of_kinetostatics(k, mech.linkage, about)  # type: ignore[union-attr]
    if hasattr(mechanism, "mechanisms") and hasattr(mechanism, "optimum"):
        if offsets_m is not None and not isinstance(offsets_m, Mapping):
            raise InputError(f"offsets_m = {offsets_m!r} must map mechanisms to (x, y) [m]")
        return _of_machine(mechanism, about, offsets_m or {})
    if hasattr(mechanism, "mech"):
        raise InputError(
            f"mechanism: {type(mechanism).__name__} has no linkage forces (give the linkage "
            "masses or loads in the machine file)"
        )
    raise TypeError(
        "mechanism must be a Kinetostatics, a machine's linkage result or a MachineResult; "
        f"got {type(mechanism).__name__}"
    )
