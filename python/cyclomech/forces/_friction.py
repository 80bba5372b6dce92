"""Friction in a linkage's joints and guides (issue 34 item 5): :class:`PinFriction`,
:class:`GuideFriction`, :class:`Friction`, and :func:`kinetostatics_with_friction`,
which solves it with the reactions at each steady crank speed
(:class:`FrictionForces`).

Coulomb friction is not linear in the loads (it goes with |R| and the sign of the
relative velocity), so its forces are per speed, not three parts summed. The
model, the rule at zero relative velocity and the self-locking test are those of
the Rust kernel (``rust/core/src/forces/friction.rs``).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, speeds_rpm, threads_arg
from .._errors import CyclomechWarning, InputError
from .._units import RAD_PER_S_PER_RPM
from ._model import LinkMass, LinkTorque, PointLoad, _build, _load_arrays, _solution
from ._result import _conditioning

if TYPE_CHECKING:
    from ..linkage import Linkage, LinkageSolution

__all__ = [
    "Friction",
    "FrictionForces",
    "GuideFriction",
    "PinFriction",
    "kinetostatics_with_friction",
]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class PinFriction:
    """Friction in one revolute joint: Coulomb μ on a pin of radius r, and viscous.

    The joint's two members each feel a torque μ·r·|R| (R the joint's reaction)
    opposing their relative angular velocity, plus ``viscous``·ω_rel. Each
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    radius_m : float
        The pin's (journal's) radius r [m] (≥ 0).
    mu : float
        The Coulomb friction coefficient μ (≥ 0, no unit).
    viscous : float, default 0.0
        The viscous coefficient c [N·m·s/rad] (≥ 0): a torque c·ω_rel.

    Raises
    ------
    InputError
        If a parameter is not a finite number ≥ 0.

    Examples
    --------
    >>> PinFriction(radius_m=0.01, mu=0.1).mu
    0.1
    """

    radius_m: float
    mu: float
    viscous: float = 0.0

    def __post_init__(self) -> None:
        for name, unit in (("radius_m", "[m]"), ("mu", ""), ("viscous", "[N·m·s/rad]")):
            v = finite_number(f"PinFriction: {name}", getattr(self, name), unit, low=0.0)
            object.__setattr__(self, name, v)


@dataclass(frozen=True)
class GuideFriction:
    """Friction of a slider's block on its guide: Coulomb μ, and viscous.

    A force μ·|N| (N the guide's normal force) along the guide on the block,
    opposing its sliding velocity relative to the guide, plus ``viscous``·v_rel.
    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    mu : float
        The Coulomb friction coefficient μ (≥ 0, no unit).
    viscous : float, default 0.0
        The viscous coefficient c [N·s/m] (≥ 0): a force c·v_rel.

    Raises
    ------
    InputError
        If a parameter is not a finite number ≥ 0.

    Examples
    --------
    >>> GuideFriction(mu=0.15).viscous
    0.0
    """

    mu: float
    viscous: float = 0.0

    def __post_init__(self) -> None:
        for name, unit in (("mu", ""), ("viscous", "[N·s/m]")):
            v = finite_number(f"GuideFriction: {name}", getattr(self, name), unit, low=0.0)
            object.__setattr__(self, name, v)


@dataclass(frozen=True)
class Friction:
    """The friction of a linkage: its joints' and its sliders' guides'.

    Joints and guides not named are frictionless. The names are checked against
    the linkage by :func:`kinetostatics_with_friction`. Each parameter is kept as
    the attribute of the same name (as a dict).

    Parameters
    ----------
    pins : mapping of str to PinFriction, optional
        Maps a joint's name to its :class:`PinFriction`. The joint must join two
        members: two links, a link and the frame, or a link and a slider's block
        (which turns with its guide).
    guides : mapping of str to GuideFriction, optional
        Maps a slider's point to the :class:`GuideFriction` of its guide(s).

    Raises
    ------
    InputError
        If ``pins`` or ``guides`` is not a mapping of names to
        :class:`PinFriction` / :class:`GuideFriction`.

    Examples
    --------
    >>> f = Friction(pins={"A": PinFriction(0.01, 0.1)}, guides={"C": GuideFriction(0.15)})
    >>> sorted(f.pins), sorted(f.guides)
    (['A'], ['C'])
    """

    pins: Mapping[str, PinFriction] = field(default_factory=dict)
    guides: Mapping[str, GuideFriction] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for what, cls in (("pins", PinFriction), ("guides", GuideFriction)):
            given = getattr(self, what)
            if not isinstance(given, Mapping):
                raise InputError(f"Friction: {what} = {given!r} must map names to {cls.__name__}")
            for k, v in given.items():
                if not isinstance(k, str) or not isinstance(v, cls):
                    raise InputError(
                        f"Friction: {what}[{k!r}] = {v!r} must be a {cls.__name__} keyed by "
                        "a point's name"
                    )
            object.__setattr__(self, what, dict(given))


@dataclass(frozen=True)
class FrictionForces:
    """A linkage's forces with friction, at each steady crank speed and crank angle.

    Built by :func:`kinetostatics_with_friction`; each parameter is kept as the
    attribute of the same name. S speeds, N angles, G guides, K joint forces, F
    friction elements (the joints with friction, then the guides with friction).

    Parameters
    ----------
    solution : LinkageSolution
        The solved linkage at the crank angles ``angles`` [rad] (N,).
    rpm : ndarray of float, shape (S,)
        The crank speeds [rpm].
    pairs : tuple of tuple of (str, str)
        The (point, link) of each joint force, as :class:`Kinetostatics`'s.
    guides : tuple of str
        The guides' names.
    elements : tuple of str
        The friction elements' names: a joint's point, a guide's name.
    torque : ndarray of float, shape (S, N)
        The driving torque on the crank with friction [N·m].
    guide_forces : ndarray of float, shape (S, N, G)
        The guides' normal forces [N].
    reactions : ndarray of float, shape (S, N, K, 2)
        The force [N] each joint exerts on each part it joins.
    losses : ndarray of float, shape (S, N, F)
        Each friction element's power loss [W] (≥ 0).
    status : ndarray of int, shape (S, N)
        The solves the fixed point took (≥ 1); 0 where not solved (not assembled
        or a dead centre); −1 where the pose is self-locking.
    conditioning : ndarray of float, shape (N,)
        As :class:`Kinetostatics`'s: the crank angle to a dead centre [rad].

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> f = cm.forces.kinetostatics_with_friction(
    ...     crank, [0.0], cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
    ...     rpm=60.0, loads=[cm.forces.PointLoad("A", (1000.0, 0.0))])
    >>> f.torque.round(9).tolist()        # μ·r·|R| at the bearing O
    [[2.0]]
    """

    solution: LinkageSolution
    rpm: Array
    pairs: tuple[tuple[str, str], ...]
    guides: tuple[str, ...]
    elements: tuple[str, ...]
    torque: Array
    guide_forces: Array
    reactions: Array
    losses: Array
    status: npt.NDArray[np.int64]
    conditioning: Array

    def __repr__(self) -> str:
        return (
            f"FrictionForces({self.rpm.size} speeds, {self.angles.size} crank angles, "
            f"{len(self.elements)} friction elements, "
            f"{int(self.self_locking.sum())} self-locking)"
        )

    @property
    def angles(self) -> Array:
        """The crank angles (N,) [rad].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics_with_friction(crank, [0.5], cm.forces.Friction(),
        ...                                       rpm=60.0).angles.tolist()
        [0.5]
        """
        return self.solution.angles

    @property
    def self_locking(self) -> npt.NDArray[np.bool_]:
        """True where the pose is self-locking at that speed (S, N).

        Friction there grows faster than the reactions that cause it: no finite
        driving torque moves the linkage (the forces are NaN).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics_with_friction(crank, [0.5], cm.forces.Friction(),
        ...                                       rpm=60.0).self_locking.tolist()
        [[False]]
        """
        out: npt.NDArray[np.bool_] = self.status == -1
        return out

    @property
    def ok(self) -> npt.NDArray[np.bool_]:
        """True where the forces are finite (S, N): solved, not self-locking.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics_with_friction(crank, [0.5], cm.forces.Friction(),
        ...                                       rpm=60.0).ok.tolist()
        [[True]]
        """
        out: npt.NDArray[np.bool_] = self.status > 0
        return out

    @property
    def friction_power(self) -> Array:
        """The total friction power loss (S, N) [W].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> f = cm.forces.kinetostatics_with_friction(
        ...     crank, [0.0], cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
        ...     rpm=60.0, loads=[cm.forces.PointLoad("A", (1000.0, 0.0))])
        >>> f.friction_power.round(6).tolist()    # 2 N·m at 2π rad/s
        [[12.566371]]
        """
        out: Array = self.losses.sum(axis=-1)
        return out

    @property
    def input_power(self) -> Array:
        """The power the motor supplies to the crank, T·ω (S, N) [W].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> f = cm.forces.kinetostatics_with_friction(
        ...     crank, [0.0], cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
        ...     rpm=60.0, loads=[cm.forces.PointLoad("A", (1000.0, 0.0))])
        >>> f.input_power.round(6).tolist()
        [[12.566371]]
        """
        out: Array = self.torque * (self.rpm * RAD_PER_S_PER_RPM)[:, None]
        return out

    @property
    def efficiency(self) -> Array:
        """The instantaneous efficiency 1 − P_friction / P_input (S, N).

        Where the motor delivers power (P_input > 0); NaN where it does not (the
        linkage drives the motor there, or stands still) or the forces are not
        finite. At steady speed it is (output power + dE/dt) / input power: the
        instantaneous share of the input not lost to friction.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> f = cm.forces.kinetostatics_with_friction(
        ...     crank, [np.pi / 2],
        ...     cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
        ...     rpm=60.0, loads=[cm.forces.PointLoad("A", (100.0, 0.0))])
        >>> f.efficiency.round(6).tolist()      # 30 / (30 + 0.2·0.01·100)
        [[0.993377]]
        """
        p_in = self.input_power
        with np.errstate(divide="ignore", invalid="ignore"):
            out: Array = np.where(p_in > 0.0, 1.0 - self.friction_power / p_in, np.nan)
        return out

    @property
    def mean_efficiency(self) -> Array:
        """The mean of :attr:`efficiency` over the angles where it is defined (S,).

        NaN at a speed where it is defined nowhere.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> f = cm.forces.kinetostatics_with_friction(
        ...     crank, [np.pi / 2],
        ...     cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
        ...     rpm=60.0, loads=[cm.forces.PointLoad("A", (100.0, 0.0))])
        >>> f.mean_efficiency.round(6).tolist()
        [0.993377]
        """
        e = self.efficiency
        n = np.isfinite(e).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            out: Array = np.where(n > 0, np.where(np.isfinite(e), e, 0.0).sum(axis=1) / n, np.nan)
        return out

    def cycle_efficiency(self) -> Array:
        """The efficiency over one turn: output work / input work, per speed (S,).

        Over a steady turn the energy stored returns to its start, so the output
        work is the input work less the friction work: 1 − W_friction / W_input.
        The angles must be N ≥ 3 uniform steps over one turn (equal times at a
        steady speed). NaN at a speed where a pose is not solved or self-locking,
        or where the input work is not positive (the linkage drives the motor).

        Returns
        -------
        ndarray of float, shape (S,)
            The cycle's efficiency at each speed.

        Raises
        ------
        InputError
            If the angles are not N ≥ 3 uniform steps over one turn.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> f = cm.forces.kinetostatics_with_friction(
        ...     crank, np.radians(np.arange(0.0, 360.0, 1.0)),
        ...     cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
        ...     rpm=60.0, loads=[cm.forces.LinkTorque(("O", "A"), -10.0)])
        >>> f.cycle_efficiency().round(9).tolist()   # 10 / (10 + μ r |R|): R = 0 here
        [1.0]
        """
        a = self.angles
        n = a.size
        step = 2.0 * math.pi / n if n else math.nan
        if n < 3 or not np.allclose(np.diff(a), step, rtol=0.0, atol=1e-9 * step):
            raise InputError(
                "cycle_efficiency needs the forces on N >= 3 uniform crank angles over one turn "
                "(a + 2πk/N, k = 0 … N−1); solve them on such a grid"
            )
        w_in = self.input_power.sum(axis=1)
        w_f = self.friction_power.sum(axis=1)
        good = self.ok.all(axis=1) & (w_in > 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            out: Array = np.where(good, 1.0 - w_f / w_in, np.nan)
        return out


def kinetostatics_with_friction(
    linkage: Linkage,
    angles: Any,
    friction: Friction,
    rpm: Any,
    *,
    masses: Mapping[Sequence[str], LinkMass] | None = None,
    point_masses: Mapping[str, float] | None = None,
    loads: Sequence[PointLoad | LinkTorque] = (),
    gravity: Sequence[float] | None = None,
    n_threads: int | None = None,
) -> FrictionForces:
    """Joint reactions, guide forces and driving torque with friction, per speed.

    As :func:`kinetostatics` with the friction of the joints and guides of
    ``friction``, at each steady crank speed of ``rpm`` (ε = 0). Coulomb
    friction goes with |R| and the sign of the relative velocity, so each angle
    and speed is solved to a fixed point: R⁽ᵏ⁺¹⁾ = solve(inertia + loads +
    friction(R⁽ᵏ⁾)) from the frictionless forces (the system's matrix is
    today's; the friction loads are extra right-hand sides), to 1e-12 relative,
    in Rust, angles in parallel, the GIL released. The matrix being the same,
    each angle is solved 1 + F times (the frictionless forces and each friction
    element's response to a unit load) and the fixed point runs on the F sizes.

    The model: a joint's two members each feel μ·r·|R| opposing their relative
    angular velocity (the frame's is 0; a slider's block turns with its guide),
    plus c·ω_rel; where the pin carries a load or a point mass the forces on its
    two members differ and |R| is the larger. A guide puts μ·|N| on the block
    along it, opposing the sliding velocity relative to the guide, plus c·v_rel.

    **Zero relative velocity** (a dwell, a reversal): kinetic friction with
    sign(0) = 0, so Coulomb friction is zero at an angle where the relative
    velocity analog is within 1e-12 of zero (rad/rad for a joint; for a guide,
    relative to the pose's largest point velocity analog). Caveat: the static
    friction there may be anything up to μ·|R|; the value at that single angle
    is a limit of neither side, and a linkage held at rest (or started) needs
    the static range, which this does not give.

    **Self-locking.** Where friction grows as fast as the reactions causing it,
    or faster (the fixed point's contraction factor, near μ·r over the links'
    lever arms, or μ·tan of a slider's pushing angle, is 1 or more), the
    rigid-body Coulomb model has no finite driving torque (the linkage jams) or
    no unique one (where friction would help the motion): the pose is reported
    self-locking, its forces NaN, ``status`` −1, ``self_locking`` True, and a
    :class:`~cyclomech.CyclomechWarning` says so. A pose within about 0.3 % of
    it (the iteration not converged in 10 000 steps) is reported the same way.

    Parameters
    ----------
    linkage : Linkage
        The linkage.
    angles : array_like of float, shape (N,), or LinkageSolution
        The absolute crank angles [rad], or a solution of ``linkage`` (as
        :func:`kinetostatics`'s).
    friction : Friction
        The joints' and guides' friction.
    rpm : float or array_like of float, shape (S,)
        The steady crank speeds [rpm], each > 0.
    masses, point_masses, loads, gravity
        As :func:`kinetostatics`'s.
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all
        cores).

    Returns
    -------
    FrictionForces
        The forces, the friction losses [W] and the efficiency at each speed and
        angle.

    Raises
    ------
    InputError
        If ``friction`` is not a :class:`Friction`, names a joint or slider the
        linkage does not have (the message lists those it has) or a joint of
        more than two members, ``rpm`` is not positive speeds, or for any of
        :func:`kinetostatics`'s reasons.
    TypeError
        If ``linkage`` is not a :class:`~cyclomech.Linkage`.

    Warns
    -----
    CyclomechWarning
        If a pose is self-locking at some speed.

    Examples
    --------
    A crank O–A of 0.3 m pushed against a force of 1000 N at its pin, with a
    bearing at O of 10 mm radius and μ = 0.2: the motor also pays μ·r·|R|:

    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> f = cm.forces.kinetostatics_with_friction(
    ...     crank, [np.pi / 2], cm.forces.Friction(pins={"O": cm.forces.PinFriction(0.01, 0.2)}),
    ...     rpm=[60.0, 120.0], loads=[cm.forces.PointLoad("A", (1000.0, 0.0))])
    >>> f.torque.round(9).tolist()       # F·r + μ·r_pin·F
    [[302.0], [302.0]]
    """
    if not isinstance(friction, Friction):
        raise InputError(
            f"friction = {friction!r} must be a cyclomech.forces.Friction(pins=..., guides=...)"
        )
    n_rpm = speeds_rpm("rpm", rpm)
    model, names, body_names, guide_names, links, moving = _build(
        linkage, masses, point_masses, loads, gravity
    )
    pins, guides, elements = _elements(friction, model, names, guide_names)
    sol = _solution(linkage, angles, n_threads)
    force, torque = _load_arrays(loads, sol.angles, names, links, moving)
    values, losses, status, cond = model.solve_friction(
        np.ascontiguousarray(sol.xy),
        np.ascontiguousarray(sol.vel),
        np.ascontiguousarray(sol.acc),
        force,
        torque,
        n_rpm * RAD_PER_S_PER_RPM,
        *pins,
        *guides,
        n_threads=threads_arg(n_threads),
    )
    pairs = tuple((names[p], "frame" if b < 0 else body_names[b]) for p, b in model.pairs())
    cond = _conditioning(sol, cond)
    values = np.moveaxis(values, 0, 1)  # (S, N, W)
    losses = np.moveaxis(losses, 0, 1)
    status = np.ascontiguousarray(status.T)
    dead = cond == 0.0
    if dead.any():
        values = np.where(dead[None, :, None], np.nan, values)
        losses = np.where(dead[None, :, None], np.nan, losses)
        status = np.where(dead[None, :], 0, status)
    g, k = len(guide_names), len(pairs)
    s_n, n = n_rpm.size, sol.angles.size
    out = FrictionForces(
        solution=sol,
        rpm=n_rpm,
        pairs=pairs,
        guides=tuple(guide_names),
        elements=tuple(elements),
        torque=values[:, :, 0],
        guide_forces=values[:, :, 1 : 1 + g],
        reactions=values[:, :, 1 + g :].reshape(s_n, n, k, 2),
        losses=losses,
        status=status,
        conditioning=cond,
    )
    _warn_self_locking(out)
    return out


def _joints(
    linkage: Linkage, dynamics: Mapping[str, Any]
) -> tuple[list[str], list[str], list[str]]:
    """The names a friction of ``linkage`` (with the forces' keywords ``dynamics``)
    may use: its joints where friction is modelled (two members: two links, a link
    and the frame, a link and a slider's block), its joints of more members, and
    its sliders' points, each in the linkage's order (the rule of :func:`_elements`)."""
    model, names, _b, guide_names, _l, _m = _build(
        linkage,
        dynamics.get("masses"),
        dynamics.get("point_masses"),
        dynamics.get("loads", ()),
        dynamics.get("gravity"),
    )
    joints = sorted({p for p, _ in model.pairs()})
    slider_of = [name.split(" ", 1)[0] for name in guide_names]
    modelled: list[str] = []
    other: list[str] = []
    for j in joints:
        sides = sum(1 for q, _ in model.pairs() if q == j)
        guides = slider_of.count(names[j])
        if (sides, guides) in ((2, 0), (1, 1)):
            modelled.append(names[j])
        elif sides + guides > 2:
            other.append(names[j])
        # else a point of one member only (a link's free end): no joint at all
    sliders = [p for p in names if p in slider_of]
    return modelled, other, sliders


def _elements(
    friction: Friction, model: Any, names: list[str], guide_names: list[str]
) -> tuple[tuple[Any, Any, Any], tuple[Any, Any, Any], list[str]]:
    """The kernel's friction arrays, each name checked against the linkage: the
    joints' (points, μ·r [m], viscous), the guides' (indices, μ, viscous), and
    the elements' names in the kernel's order (joints, then guides)."""
    idx = {p: i for i, p in enumerate(names)}
    joints = sorted({p for p, _ in model.pairs()})
    slider_of = [name.split(" ", 1)[0] for name in guide_names]
    sides = [sum(1 for q, _ in model.pairs() if q == j) for j in range(len(names))]
    pin_pts, pin_mu_r, pin_visc, elements = [], [], [], []
    for p, pf in friction.pins.items():
        if p not in idx or idx[p] not in joints:
            raise InputError(
                f"friction: pins[{p!r}]: no joint {p!r}; the joints are "
                f"{', '.join(names[j] for j in joints)}"
            )
        n_sides, n_guides = sides[idx[p]], slider_of.count(p)
        if (n_sides, n_guides) not in ((2, 0), (1, 1)):
            raise InputError(
                f"friction: pins[{p!r}]: joint {p!r} joins {n_sides} parts (the frame counts) "
                f"and {n_guides} guides; friction is modelled at a joint of two members (two "
                "links, a link and the frame, a link and a slider's block)"
            )
        pin_pts.append(idx[p])
        pin_mu_r.append(pf.mu * pf.radius_m)
        pin_visc.append(pf.viscous)
        elements.append(p)

    g_idx, g_mu, g_visc = [], [], []
    for p, gf in friction.guides.items():
        mine = [g for g, q in enumerate(slider_of) if q == p]
        if not mine:
            sliders = sorted(set(slider_of))
            raise InputError(
                f"friction: guides[{p!r}]: no slider at {p!r}; the sliders are "
                f"{', '.join(sliders) if sliders else 'none'}"
            )
        for g in mine:
            g_idx.append(g)
            g_mu.append(gf.mu)
            g_visc.append(gf.viscous)
            elements.append(guide_names[g])

    pins = (
        np.array(pin_pts, dtype=np.int64),
        np.array(pin_mu_r, dtype=np.float64),
        np.array(pin_visc, dtype=np.float64),
    )
    guides = (
        np.array(g_idx, dtype=np.int64),
        np.array(g_mu, dtype=np.float64),
        np.array(g_visc, dtype=np.float64),
    )
    return pins, guides, elements


def _warn_self_locking(out: FrictionForces) -> None:
    """A :class:`~cyclomech.CyclomechWarning` naming the self-locking poses, if any."""
    if out.self_locking.any():
        s, i = (int(x) for x in np.argwhere(out.self_locking)[0])
        bad = np.degrees(out.angles[out.self_locking.any(axis=0)])[:6]
        warnings.warn(
            f"the linkage is self-locking at crank angles {', '.join(f'{v:.1f}' for v in bad)} "
            f"degrees (first at {out.rpm[s]:g} rpm, {math.degrees(out.angles[i]):.1f}°): "
            "friction there grows as fast as the reactions that cause it, or faster, so the "
            "rigid-body Coulomb model gives no finite (or no unique) driving torque; its "
            "forces are NaN (FrictionForces.self_locking)",
            CyclomechWarning,
            stacklevel=3,
        )
