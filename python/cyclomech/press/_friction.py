"""Friction of a press drive's rod and slider (issue 34 item 5): `_friction` part
of :mod:`cyclomech.press`.

Coulomb friction at the slider's **guide** (a force μ_g·|H| against the slider's
sliding, H the guide's normal force: the rod's force across the guide) and at the
rod's **two pins** (a torque μ·r·|F| against the rod's turning relative to the
planet at the top pin and to the slider at the bottom one, F the pin's force).

The model, per crank angle at one steady speed ω (the conventions of
:mod:`cyclomech.press._torque`: α from BDC against the motion, ẋ = −ω·x_α,
ẍ = ω²·x_αα): the slider (mass m_s, on its guide) and the uniform rod (mass
m_r, length L, centre of mass G mid-way, I_G = m_r·L²/12) by Newton–Euler,
gravity left out as the frictionless torque leaves it out:

* slider: Y + F_b + f_g = m_s·a_s (vertical), X + H = 0 (across the guide), with
  (X, Y) the rod's force on the slider, F_b the blank's force (up, on the working
  stroke), f_g = −μ_g·|H|·sgn v_s;
* rod: F_P − (X, Y) = m_r·a_G; about G: e × (X, Y) = I_G·γ̈ − ½·e × m_r·a_G − M_P − M_S,
  e = P − S the rod's vector, γ its angle, M_P = −μ·r·|F_P|·sgn(γ̇ − ω_planet)
  and M_S = −μ·r·|(X, Y)|·sgn γ̇ the pins' friction torques on the rod
  (ω_planet = −(i − 1)·ω, the planet's spin; the slider does not turn).

The friction terms go with the forces they oppose, so the equations are solved
by fixed-point iteration from the frictionless forces (each step linear in X),
to a relative change of 1e-13; a pose that does not converge in 200 steps (the
friction grows as fast as the forces causing it: self-locking) is NaN.

The crank's torque follows from the power balance: the carrier and the planet
keep a constant kinetic energy and the gears are lossless, so
M = M_frictionless + P_f/ω with P_f = μ_g·|H|·|v_s| + μ·r·|F_S|·|γ̇| +
μ·r·|F_P|·|γ̇ − ω_planet|.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _keyrules, _toml
from .._arrays import finite_number, float_array, positive
from .._errors import InputError

if TYPE_CHECKING:
    from ._drive import GearLeverPress
    from ._torque import DeformationForce

Array = npt.NDArray[np.float64]

#: The keys of a press's ``friction`` table.
PRESS_FRICTION_KEYS = frozenset({"guide_mu", "pin_radius_m", "pin_mu"})
#: The fixed point's tolerance (relative change of the forces) and step limit.
TOL, STEPS = 1e-13, 200


@dataclass(frozen=True)
class PressFriction:
    """The Coulomb friction of a press drive's slider guide and rod pins.

    Each parameter is kept as the attribute of the same name (as a float).

    Parameters
    ----------
    guide_mu : float, default 0.0
        The slider guide's Coulomb coefficient μ_g (≥ 0).
    pin_radius : float, default 0.0
        The radius r of the rod's two pins [m] (≥ 0).
    pin_mu : float, default 0.0
        Their Coulomb coefficient μ (≥ 0).

    Raises
    ------
    InputError
        If a value is not a finite number ≥ 0.

    Examples
    --------
    >>> PressFriction(guide_mu=0.1).pin_mu
    0.0
    """

    guide_mu: float = 0.0
    pin_radius: float = 0.0
    pin_mu: float = 0.0

    def __post_init__(self) -> None:
        for name in ("guide_mu", "pin_radius", "pin_mu"):
            unit = "[m]" if name == "pin_radius" else ""
            v = finite_number(f"PressFriction: {name}", getattr(self, name), unit, low=0.0)
            object.__setattr__(self, name, v)


@dataclass(frozen=True)
class PressFrictionForces:
    """A press drive's forces with friction at one steady crank speed.

    Built by :func:`press_friction`; each parameter is kept as the attribute of the
    same name. N crank angles α (from BDC against the motion).

    Parameters
    ----------
    alpha : ndarray of float, shape (N,)
        The crank angles α [rad].
    omega : float
        The crank speed ω [rad/s].
    slider_force : ndarray of float, shape (N, 2)
        The rod's force on the slider (X, Y) [N] (the bottom pin's force).
    pin_force : ndarray of float, shape (N, 2)
        The planet's force on the rod at the top pin [N].
    guide_force : ndarray of float, shape (N,)
        The guide's normal force H on the slider [N].
    rod_spin : ndarray of float, shape (N,)
        The rod's angular velocity γ̇ [rad/s] (counter-clockwise).
    planet_spin : float
        The planet's angular velocity [rad/s].
    torque : ndarray of float, shape (N,)
        The crank's driving torque with friction [N·m].
    torque_without : ndarray of float, shape (N,)
        Without friction [N·m].
    losses : ndarray of float, shape (N, 3)
        The power lost [W] at the guide, the slider's pin and the planet's pin.
    elements : tuple of str
        The names of ``losses``' columns.
    self_locking : ndarray of bool, shape (N,)
        Where the fixed point does not converge (the forces are NaN).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
    >>> f = press_friction(p, np.radians([90.0]), 4.0, PressFriction(guide_mu=0.1),
    ...                    slider_mass=10.0, k_Sp=0.1)
    >>> f.elements
    ('guide', 'slider pin', 'planet pin')
    """

    alpha: Array
    omega: float
    slider_force: Array
    pin_force: Array
    guide_force: Array
    rod_spin: Array
    planet_spin: float
    torque: Array
    torque_without: Array
    losses: Array
    elements: tuple[str, ...]
    self_locking: npt.NDArray[np.bool_]

    @property
    def friction_power(self) -> Array:
        """The power lost to friction at each angle [W].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> f = press_friction(p, np.radians([90.0]), 4.0, PressFriction(guide_mu=0.1),
        ...                    slider_mass=10.0, k_Sp=0.1)
        >>> bool(f.friction_power[0] >= 0)
        True
        """
        out: Array = self.losses.sum(axis=1)
        return out

    @property
    def input_power(self) -> Array:
        """The power the crank puts in at each angle, M·ω [W].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> f = press_friction(p, np.radians([0.0]), 4.0, PressFriction(guide_mu=0.1), k_Sp=0.1)
        >>> f.input_power.tolist()
        [0.0]
        """
        out: Array = self.torque * self.omega
        return out


def _cross(a: Array, b: Array) -> Array:
    out: Array = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def press_friction(
    press: GearLeverPress,
    alpha: Any,
    omega: float,
    friction: PressFriction,
    *,
    force: DeformationForce | None = None,
    slider_mass: float = 0.0,
    rod_mass: float = 0.0,
    k_Sp: float | None = None,
    working_stroke: float | None = None,
) -> PressFrictionForces:
    """The drive's forces, losses and crank torque with friction at a steady speed.

    The Newton–Euler equations of the slider and the rod with Coulomb friction at
    the guide and the rod's pins, by fixed-point iteration (module docs). The
    load's keywords are :meth:`GearLeverPress.crank_torque`'s.

    Parameters
    ----------
    press : GearLeverPress
        The drive.
    alpha : array_like of float, shape (N,)
        The crank angles α [rad] from BDC against the motion.
    omega : float
        The crank speed ω [rad/s] (> 0).
    friction : PressFriction
        The friction coefficients and the pins' radius.
    force : DeformationForce, optional
        The deformation-force diagram; default None.
    slider_mass, rod_mass : float, default 0.0
        The slider's and the uniform rod's masses [kg] (≥ 0).
    k_Sp, working_stroke : float, optional
        The working stroke, as for :meth:`GearLeverPress.crank_torque`.

    Returns
    -------
    PressFrictionForces
        The forces [N], losses [W] and torque [N·m] at ``alpha``.

    Raises
    ------
    InputError
        If ``friction`` is not a :class:`PressFriction`, ``omega`` is not > 0, or
        as :meth:`GearLeverPress.crank_torque`.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
    >>> f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
    >>> t = press_friction(p, np.radians([30.0]), 4.0, PressFriction(guide_mu=0.1),
    ...                    force=f, k_Sp=0.1)
    >>> bool(t.torque[0] > t.torque_without[0])      # friction costs torque
    True
    """
    if not isinstance(friction, PressFriction):
        raise InputError(f"friction must be a cyclomech.press.PressFriction; got {friction!r}")
    w = positive("omega", omega, "[rad/s]")
    a = float_array("alpha", alpha)
    t0 = press.crank_torque(
        a,
        force=force,
        slider_mass=slider_mass,
        rod_mass=rod_mass,
        k_Sp=k_Sp,
        working_stroke=working_stroke,
    )
    k = press.solve(a)
    # The blank's force, up, on the approach to BDC only (as crank_torque's).
    on = np.mod(a, 2.0 * math.pi) <= t0.alpha_p
    f_b = np.zeros_like(a) if force is None else np.where(on, force.at(k.s), 0.0)
    mo = _motion(press, k, w)
    fs, fp, locked = _forces(mo, f_b, float(slider_mass), float(rod_mass), friction, press.L)
    mr = friction.pin_mu * friction.pin_radius
    h = -fs[:, 0]
    losses = np.stack(
        [
            friction.guide_mu * np.abs(h) * np.abs(mo.v_s),
            mr * np.hypot(fs[:, 0], fs[:, 1]) * np.abs(mo.spin),
            mr * np.hypot(fp[:, 0], fp[:, 1]) * np.abs(mo.spin - mo.planet),
        ],
        axis=1,
    )
    without = t0.torque_nm(w)
    return PressFrictionForces(
        alpha=a,
        omega=w,
        slider_force=fs,
        pin_force=fp,
        guide_force=h,
        rod_spin=mo.spin,
        planet_spin=mo.planet,
        torque=without + losses.sum(axis=1) / w,
        torque_without=without,
        losses=losses,
        elements=("guide", "slider pin", "planet pin"),
        self_locking=locked,
    )


@dataclass(frozen=True)
class _Motion:
    """The rod's and the slider's motion at a steady speed (module docs): the rod's
    vector e = P − S (N, 2), its centre's acceleration a_G (N, 2) [m/s²], its spin
    γ̇ [rad/s] and γ̈ [rad/s²], the slider's velocity and acceleration (up) [m/s,
    m/s²], the planet's spin [rad/s] and the speed ω [rad/s]."""

    e: Array
    a_g: Array
    spin: Array
    spin_dot: Array
    v_s: Array
    a_s: Array
    planet: float
    omega: float


def _motion(press: GearLeverPress, k: Any, w: float) -> _Motion:
    """The motion of the drive's kinematics ``k`` at the speed ``w``: P_α =
    −i(C − k·q), P_αα = −(C + k²·q) (crank_torque's _rod_term), S_α = i·Π',
    ẋ = −ω·x_α, ẍ = ω²·x_αα."""
    kk = press.ratio - 1.0
    c = k.centre[:, 0] + 1j * k.centre[:, 1]
    q = (k.pin[:, 0] + 1j * k.pin[:, 1]) - c
    p1, p2 = -1j * (c - kk * q), -(c + kk * kk * q)
    s1, s2 = 1j * k.ds, 1j * k.dds

    def vec(z: Any) -> Array:
        return np.stack([np.real(z), np.imag(z)], axis=-1)

    e = k.pin - k.slider
    length2 = press.L**2
    return _Motion(
        e=e,
        a_g=vec(0.5 * w * w * (p2 + s2)),
        spin=_cross(e, vec(-w * (p1 - s1))) / length2,
        spin_dot=_cross(e, vec(w * w * (p2 - s2))) / length2,
        v_s=-w * k.ds,
        a_s=w * w * k.dds,
        planet=-kk * w,
        omega=w,
    )


def _forces(
    mo: _Motion, f_b: Array, m_s: float, m_r: float, friction: PressFriction, length: float
) -> tuple[Array, Array, npt.NDArray[np.bool_]]:
    """The rod's force on the slider (X, Y) and the planet's on the rod, (N, 2)
    each [N], and where the fixed point does not converge (module docs)."""
    i_g = m_r * length * length / 12.0
    mu_g, mr = friction.guide_mu, friction.pin_mu * friction.pin_radius
    base = i_g * mo.spin_dot - 0.5 * m_r * _cross(mo.e, mo.a_g)
    # Zero relative velocity (a dead centre, to round-off) costs no friction: the
    # sign there is 0, the linkage's rule (forces/friction.rs).
    tiny = 1e-12 * mo.omega

    def sign(v: Array, unit: float) -> Array:
        out: Array = np.where(np.abs(v) > tiny * unit, np.sign(v), 0.0)
        return out

    sg_s, sg_sp = sign(mo.v_s, length), sign(mo.spin, 1.0)
    sg_pp = sign(mo.spin - mo.planet, 1.0)
    ex, ey = mo.e[:, 0], mo.e[:, 1]
    x, f_s_abs, f_p_abs = (np.zeros_like(f_b) for _ in range(3))
    done = np.zeros(f_b.size, dtype=bool)
    # The fixed point, from the frictionless forces: each step linear in X.
    for _ in range(STEPS):
        y = m_s * mo.a_s - f_b + mu_g * np.abs(x) * sg_s
        m_fric = -mr * f_p_abs * sg_pp - mr * f_s_abs * sg_sp  # M_P + M_S on the rod
        x_new = (ex * y - (base - m_fric)) / ey
        y_new = m_s * mo.a_s - f_b + mu_g * np.abs(x_new) * sg_s
        fs_abs = np.hypot(x_new, y_new)
        fp_abs = np.hypot(x_new + m_r * mo.a_g[:, 0], y_new + m_r * mo.a_g[:, 1])
        scale = np.maximum(np.maximum(fs_abs, fp_abs), 1e-300)
        done = np.maximum(np.abs(x_new - x), np.abs(fs_abs - f_s_abs)) / scale <= TOL
        x, f_s_abs, f_p_abs = x_new, fs_abs, fp_abs
        if done.all():
            break
    fs = np.stack([x, m_s * mo.a_s - f_b + mu_g * np.abs(x) * sg_s], axis=1)
    fp = fs + m_r * mo.a_g
    fs[~done] = np.nan
    fp[~done] = np.nan
    return fs, fp, ~done


def friction_from_table(table: Mapping[str, Any], at: str) -> PressFriction | None:
    """The :class:`PressFriction` of a press table's ``friction`` table, None without one.

    ``guide_mu`` (the slider's guide), ``pin_radius_m`` [m] with ``pin_mu`` (both
    of the rod's pins): each a finite number ≥ 0; a coefficient above 0.5 warns.

    Parameters
    ----------
    table : mapping of str to object
        The press's table.
    at : str
        The file and table, for the messages.

    Returns
    -------
    PressFriction or None
        The friction; None without a ``friction`` table.

    Raises
    ------
    InputError
        If a key is unknown, a value is not a finite number ≥ 0, or ``pin_mu`` comes
        without ``pin_radius_m`` (or the reverse); naming the key and the value.

    Warns
    -----
    CyclomechWarning
        For a friction coefficient above 0.5 (a percentage?).

    Examples
    --------
    >>> friction_from_table({"friction": {"guide_mu": 0.08}}, "[mechanism.drive]")
    PressFriction(guide_mu=0.08, pin_radius=0.0, pin_mu=0.0)
    """
    if "friction" not in table:
        return None
    where = f"{at.rstrip(']')}.friction]"
    spec = table["friction"]
    if not isinstance(spec, Mapping):
        raise InputError(f"{where}: friction = {spec!r} must be a table of friction keys")
    _toml.check_keys(spec, PRESS_FRICTION_KEYS, None, where)
    v = {
        key: _keyrules.friction_number(spec, key, where, "[m]" if key.endswith("_m") else "")
        for key in sorted(spec)
    }
    if ("pin_radius_m" in spec) != ("pin_mu" in spec):
        have, need = (
            ("pin_radius_m", "pin_mu") if "pin_radius_m" in spec else ("pin_mu", "pin_radius_m")
        )
        raise InputError(f"{where}: {have} is given without {need}; give both or neither")
    _keyrules.check(spec, (), where)
    return PressFriction(
        guide_mu=v.get("guide_mu", 0.0),
        pin_radius=v.get("pin_radius_m", 0.0),
        pin_mu=v.get("pin_mu", 0.0),
    )
