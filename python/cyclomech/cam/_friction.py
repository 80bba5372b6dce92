"""Friction of a cam's follower (issue 34 item 5): `_friction` part of :mod:`cyclomech.cam`.

Coulomb friction at the follower's **pivot** (an oscillating follower: a pin of
radius r_p, a torque μ_p·r_p·|R| against the arm's turning, R the pivot's
reaction) or **guide** (a translating follower: a force μ_g·|F⊥| against its
sliding, F⊥ the contact force's component across the stem, one effective guide),
and at the **roller's pin** (a torque μ_r·r_pin·|F| against the roller's turning
relative to the arm or stem; the roller rolls on the cam without slip).

The model, per cam angle at one steady speed ω (the cam turns counter-clockwise,
as :meth:`Cam.solve`'s frames):

* The roller is massless: the pin's friction torque is balanced by a tangential
  force F_t at the contact, |F_t| = k·|F| with k = μ_r·r_pin/r_r, so the contact
  force's magnitude is |F| = |N|/√(1 − k²) (N its normal part).
* The arm's (stem's) balance along its coordinate, with Q the frictionless
  generalised force of :meth:`Cam.loads` (inertia, spring, preload, load),
  φ the pressure angle, s_m = sgn ṡ, s_r = sgn ω_rel, σ = sgn Q (the loaded
  flank), c = 1/√(1 − k²), l the arm length (1 for a stem):

  - oscillating: |N|·[l·(cos φ + k·c·s_r·sin φ) − σ·c·(r_r·k·s_r + μ_p·r_p·s_m)] = |Q|
  - translating: |N|·[cos φ + k·c·s_r·sin φ − σ·μ_g·|sin φ − k·c·s_r·cos φ|·s_m] = |Q|

  A closed form for each pose (every friction term goes with |N|); where the
  bracket is not positive no finite contact force moves the follower: the pose
  self-locks (NaN).
* The arm's file data are its moment of inertia about the pivot and couples
  (spring, preload, load), so its centre of mass is taken on the pivot: the pivot
  carries the contact force alone, |R| = |F|.
* The roller's spin: rolling at the contact gives its absolute angular velocity
  ω_r = ω·(1 − σ·|T|/r_r), |T| = |dP/dθ| the pitch point's speed per radian in
  the cam frame; relative to the arm ω_rel = ω_r + ψ̇ (the arm's angle is π − ψ),
  to a stem ω_rel = ω_r.
* The losses P_f = μ_p·r_p·|F|·|ψ̇| (or μ_g·|F⊥|·|ṡ|) + μ_r·r_pin·|F|·|ω_rel|, and
  the shaft's torque by the power balance T = Q·s′ + P_f/ω (the contact rolls:
  no loss there). Where the follower dwells (ṡ = 0) the pivot or guide costs
  nothing; the roller's pin still turns. Where a spring-closed follower has left
  the cam there is no contact and no friction.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _keyrules, _toml
from .._arrays import finite_number
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ._followers import FlatFaced, OscillatingRoller

if TYPE_CHECKING:
    from ._loads import FollowerLoads
    from ._program import Cam

Array = npt.NDArray[np.float64]

#: The keys of a cam's ``friction`` table.
CAM_FRICTION_KEYS = frozenset(
    {"pivot_radius_m", "pivot_mu", "guide_mu", "roller_pin_radius_m", "roller_pin_mu"}
)


@dataclass(frozen=True)
class CamFriction:
    """The Coulomb friction of a cam's follower (module docs for the model).

    Each parameter is kept as the attribute of the same name (as a float).

    Parameters
    ----------
    pivot_radius : float, default 0.0
        An oscillating follower's pivot pin radius r_p [m] (≥ 0).
    pivot_mu : float, default 0.0
        Its Coulomb coefficient μ_p (≥ 0).
    guide_mu : float, default 0.0
        A translating follower's guide's Coulomb coefficient μ_g (≥ 0).
    pin_radius : float, default 0.0
        The roller's pin radius r_pin [m] (≥ 0, below the roller's radius).
    pin_mu : float, default 0.0
        The roller pin's Coulomb coefficient μ_r (≥ 0).

    Raises
    ------
    InputError
        If a value is not a finite number ≥ 0.

    Examples
    --------
    >>> CamFriction(pivot_radius=0.01, pivot_mu=0.08).pin_mu
    0.0
    """

    pivot_radius: float = 0.0
    pivot_mu: float = 0.0
    guide_mu: float = 0.0
    pin_radius: float = 0.0
    pin_mu: float = 0.0

    def __post_init__(self) -> None:
        for name in ("pivot_radius", "pivot_mu", "guide_mu", "pin_radius", "pin_mu"):
            unit = "[m]" if name.endswith("radius") else ""
            v = finite_number(f"CamFriction: {name}", getattr(self, name), unit, low=0.0)
            object.__setattr__(self, name, v)


@dataclass(frozen=True)
class CamFrictionForces:
    """A cam's follower forces with friction at one steady speed.

    Built by :func:`cam_friction`; each parameter is kept as the attribute of the
    same name. N cam angles.

    Parameters
    ----------
    theta : ndarray of float, shape (N,)
        The cam angles [rad].
    rpm : float
        The cam speed [rpm].
    normal_force : ndarray of float, shape (N,)
        The contact's normal force N [N], signed as :class:`CamLoads`' (+ on the
        inner flank).
    contact_force : ndarray of float, shape (N,)
        |F| [N], with the roller pin's tangential part: the pivot's reaction.
    roller_spin : ndarray of float, shape (N,)
        The roller's angular velocity relative to the arm or stem [rad/s].
    torque : ndarray of float, shape (N,)
        The driving torque on the cam shaft with friction [N·m]; 0 where a
        spring-closed follower has left the cam (no contact, as the forces and
        losses there).
    torque_without : ndarray of float, shape (N,)
        Without friction (:meth:`Cam.loads`' shaft torque, but 0 where the follower
        has left the cam) [N·m].
    losses : ndarray of float, shape (N, 2)
        The power lost [W] at the pivot (or guide) and at the roller's pin.
    elements : tuple of str
        The names of ``losses``' columns.
    self_locking : ndarray of bool, shape (N,)
        Where no finite contact force moves the follower (the forces are NaN).

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> f = cam_friction(cam, [0.0], 60.0, cm.cam.FollowerLoads(1.0, preload=50.0),
    ...                  CamFriction(guide_mu=0.1))
    >>> f.elements, f.losses.tolist()      # at the rise's start ṡ = 0: no guide loss
    (('guide', 'roller pin'), [[0.0, 0.0]])
    """

    theta: Array
    rpm: float
    normal_force: Array
    contact_force: Array
    roller_spin: Array
    torque: Array
    torque_without: Array
    losses: Array
    elements: tuple[str, ...]
    self_locking: npt.NDArray[np.bool_]

    @property
    def friction_power(self) -> Array:
        """The power lost to friction at each angle [W] (NaN where self-locking).

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
        ...                  cm.cam.TranslatingRoller(0.05, 0.01))
        >>> f = cam_friction(cam, [0.5], 60.0, cm.cam.FollowerLoads(1.0, preload=50.0),
        ...                  CamFriction(guide_mu=0.1))
        >>> bool(f.friction_power[0] > 0)
        True
        """
        out: Array = self.losses.sum(axis=1)
        return out

    @property
    def input_power(self) -> Array:
        """The power the cam shaft puts in at each angle, T·ω [W].

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
        ...                  cm.cam.TranslatingRoller(0.05, 0.01))
        >>> f = cam_friction(cam, [0.0], 60.0, cm.cam.FollowerLoads(1.0, preload=50.0),
        ...                  CamFriction(guide_mu=0.1))
        >>> f.input_power.tolist()
        [0.0]
        """
        out: Array = self.torque * (self.rpm * RAD_PER_S_PER_RPM)
        return out


def cam_friction(
    cam: Cam, theta: Any, rpm: float, loads: FollowerLoads, friction: CamFriction
) -> CamFrictionForces:
    """The follower's forces, losses and the cam shaft's torque with friction.

    The closed form of the module docs at each cam angle, at the steady speed
    ``rpm``.

    Parameters
    ----------
    cam : Cam
        The cam (a translating or oscillating roller follower).
    theta : array_like of float
        The cam angles [rad] (1-D).
    rpm : float
        The cam speed [rpm] (> 0).
    loads : FollowerLoads
        The follower's mass, spring and loads.
    friction : CamFriction
        The friction coefficients and radii.

    Returns
    -------
    CamFrictionForces
        The forces, the losses [W] and the torque [N·m] at ``theta``.

    Raises
    ------
    InputError
        If the follower is flat-faced (its face's sliding is not modelled), a
        friction element does not fit the follower, or ``friction`` is not a
        :class:`CamFriction`.

    Examples
    --------
    >>> import cyclomech as cm, numpy as np
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> ld = cm.cam.FollowerLoads(1.0, 2000.0, 50.0)
    >>> f = cam_friction(cam, np.radians([90.0]), 60.0, ld, CamFriction(guide_mu=0.1))
    >>> bool(f.torque[0] > f.torque_without[0])      # friction costs torque on the rise
    True
    """
    if not isinstance(friction, CamFriction):
        raise InputError(f"friction must be a cyclomech.cam.CamFriction; got {friction!r}")
    fol: Any = cam.follower  # a roller follower (_check_fits refuses a flat one)
    _check_fits(fol, friction, "friction")
    th = np.asarray(theta, dtype=np.float64).reshape(-1)
    w = float(rpm) * RAD_PER_S_PER_RPM
    kin = cam.solve(th)
    ld = cam.loads(th, rpm, loads)
    q, ds, phi = ld.force, kin.ds, kin.pressure_angle
    osc = isinstance(fol, OscillatingRoller)
    r_r = fol.roller_radius
    # The roller centre C in the fixed frame (the pitch point turned back by θ),
    # its direction of motion v and T = C′ − J·C, the pitch point's velocity per
    # radian in the cam frame (Rust: cam/follower.rs).
    ct, st = np.cos(th), np.sin(th)
    px, py = kin.pitch[:, 0], kin.pitch[:, 1]
    cx, cy = px * ct - py * st, px * st + py * ct
    if osc:
        length = fol.arm_length
        vx, vy = cy / length, (fol.pivot_distance - cx) / length
    else:
        length = 1.0
        vx, vy = np.zeros_like(th), np.ones_like(th)
    tx, ty = length * ds * vx + cy, length * ds * vy - cx
    speed = np.hypot(tx, ty)
    sigma = np.where(q < 0.0, -1.0, 1.0)
    # Zero relative velocity (a dwell, to round-off) costs no friction: the sign
    # there is 0, the linkage's rule (forces/friction.rs).
    scale = 1.0 if osc else fol.base_radius + fol.roller_radius
    s_m = np.where(np.abs(ds) > 1e-12 * scale, np.sign(ds), 0.0)
    k = friction.pin_mu * friction.pin_radius / r_r if r_r > 0.0 else 0.0
    c = 1.0 / math.sqrt(1.0 - k * k)
    # ω_r = ω·(1 − σ|T|/r_r) (rolling, module docs); the arm's angle is π − ψ.
    spin_abs = w * (1.0 - sigma * speed / r_r) if r_r > 0.0 else np.zeros_like(th)
    spin = spin_abs + (w * ds if osc else 0.0)
    s_r = np.where(np.abs(spin) > 1e-12 * w, np.sign(spin), 0.0)
    cos, sin = np.cos(phi), np.sin(phi)
    if osc:
        h = np.full_like(th, c)
        mu_r = friction.pivot_mu * friction.pivot_radius
        denom = length * (cos + k * c * s_r * sin) - sigma * c * (r_r * k * s_r + mu_r * s_m)
    else:
        h = np.abs(sin - k * c * s_r * cos)
        mu_r = friction.guide_mu
        denom = cos + k * c * s_r * sin - sigma * mu_r * h * s_m
    locked = (denom <= 0.0) & (q != 0.0) & ~ld.separated
    with np.errstate(divide="ignore", invalid="ignore"):
        n_abs = np.where(locked, np.nan, np.abs(q) / np.where(denom > 0.0, denom, 1.0))
    n_abs = np.where(ld.separated, 0.0, n_abs)
    f_abs = c * n_abs
    # Pivot: μ_p·r_p·|F|·|ψ̇|; guide: μ_g·|F⊥|·|ṡ| with |F⊥| = h·|N|.
    joint = mu_r * h * n_abs * np.abs(w * ds)
    pin = friction.pin_mu * friction.pin_radius * f_abs * np.abs(spin)
    losses = np.stack([joint, pin], axis=1)
    # Off the cam (separated) nothing passes to the shaft: the torque is 0 there,
    # as the contact force and the losses are (Cam.loads' is the would-be Q·s').
    torque = np.where(ld.separated, 0.0, q * ds + (joint + pin) / w)
    return CamFrictionForces(
        theta=th,
        rpm=float(rpm),
        normal_force=sigma * n_abs,
        contact_force=f_abs,
        roller_spin=spin,
        torque=torque,
        torque_without=np.where(ld.separated, 0.0, ld.shaft_torque),
        losses=losses,
        elements=("pivot" if osc else "guide", "roller pin"),
        self_locking=locked,
    )


def _check_fits(fol: Any, f: CamFriction, at: str) -> None:
    """Refuse a friction element the follower does not have, by its key."""
    if isinstance(fol, FlatFaced):
        raise InputError(
            f"{at}: friction is not modelled for a flat-faced follower (its face slides on "
            "the cam and its stem bears on two bushings); a translating or oscillating "
            "roller follower takes a friction table"
        )
    osc = isinstance(fol, OscillatingRoller)
    if osc and f.guide_mu > 0.0:
        raise InputError(
            f"{at}: guide_mu = {f.guide_mu!r} is for a translating follower's guide; an "
            "oscillating follower takes pivot_radius_m and pivot_mu"
        )
    if not osc and (f.pivot_mu > 0.0 or f.pivot_radius > 0.0):
        raise InputError(
            f"{at}: pivot_radius_m and pivot_mu are for an oscillating follower's pivot; a "
            "translating follower takes guide_mu"
        )
    if f.pin_radius > 0.0 and not f.pin_radius < fol.roller_radius:
        raise InputError(
            f"{at}: roller_pin_radius_m = {f.pin_radius!r} must be below the roller's "
            f"radius roller_radius_m = {fol.roller_radius!r} (a knife edge has no roller)"
        )


def friction_from_table(table: Mapping[str, Any], at: str, follower: Any) -> CamFriction | None:
    """The :class:`CamFriction` of a cam table's ``friction`` table, None without one.

    ``pivot_radius_m`` [m] with ``pivot_mu`` (an oscillating follower),
    ``guide_mu`` (a translating one), ``roller_pin_radius_m`` [m] with
    ``roller_pin_mu``: each a finite number ≥ 0, a radius and its coefficient
    given together; a coefficient above 0.5 warns.

    Parameters
    ----------
    table : mapping of str to object
        The cam table.
    at : str
        The file and table, for the messages ("f.toml: [mechanism.cam]").
    follower : TranslatingRoller or OscillatingRoller or FlatFaced
        The follower (its kind says which keys fit).

    Returns
    -------
    CamFriction or None
        The friction; None without a ``friction`` table.

    Raises
    ------
    InputError
        If a key is unknown, a value is not a finite number ≥ 0, a radius comes
        without its coefficient (or the reverse), or a key does not fit the
        follower; the message names the key and the value.

    Warns
    -----
    CyclomechWarning
        For a friction coefficient above 0.5 (a percentage?).

    Examples
    --------
    >>> import cyclomech as cm
    >>> fol = cm.cam.OscillatingRoller(0.13, 0.1, 0.06, 0.012)
    >>> friction_from_table({"friction": {"pivot_radius_m": 0.01, "pivot_mu": 0.08}},
    ...                     "[cam]", fol).pivot_mu
    0.08
    """
    if "friction" not in table:
        return None
    where = f"{at.rstrip(']')}.friction]"
    spec = table["friction"]
    if not isinstance(spec, Mapping):
        raise InputError(f"{where}: friction = {spec!r} must be a table of friction keys")
    _toml.check_keys(spec, CAM_FRICTION_KEYS, None, where)
    v = {
        key: _keyrules.friction_number(spec, key, where, "[m]" if key.endswith("_m") else "")
        for key in sorted(spec)
    }
    for radius, mu in (("pivot_radius_m", "pivot_mu"), ("roller_pin_radius_m", "roller_pin_mu")):
        if (radius in spec) != (mu in spec):
            have, need = (radius, mu) if radius in spec else (mu, radius)
            raise InputError(f"{where}: {have} is given without {need}; give both or neither")
    _keyrules.check(spec, (), where)
    f = CamFriction(
        pivot_radius=v.get("pivot_radius_m", 0.0),
        pivot_mu=v.get("pivot_mu", 0.0),
        guide_mu=v.get("guide_mu", 0.0),
        pin_radius=v.get("roller_pin_radius_m", 0.0),
        pin_mu=v.get("roller_pin_mu", 0.0),
    )
    _check_fits(follower, f, where)
    return f
