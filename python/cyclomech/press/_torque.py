"""The press drive's crank torque: a deformation-force diagram F(S) over the
working stroke and the inertia of the slider and the rod (seed 003's torque
criterion, in N·m; issue 19).

Sign and angle conventions (:mod:`cyclomech.press`): the carrier turns
counterclockwise at ω, α is counted from BDC *against* the motion (θ = θ_B − α,
so dα/dt = −ω) and S = Π(α) ≥ 0 is the slider's height above BDC. The torque M
is the one the drive must put into the crank in its direction of rotation
(positive: the motor gives power; negative: the crank is driven).

Power balance at constant ω, M·ω = dT/dt − P_ext:

* the blank pushes the slider up with F ≥ 0 while the slider comes down; the
  slider's velocity is v = dS/dt = −ω·Π', so the force's power is F·v = −F·Π'·ω
  and the force part of the torque is **M_F = F(Π(α))·Π'(α)** (Π' > 0 on the
  approach to BDC: the drive works against the blank);
* a body point X(α) moves at v = −ω·X_α with acceleration a = ω²·X_αα, so
  m·a·v = −m·ω³·X_α·X_αα and its part is **M_m = −ω²·m·X_α·X_αα**: the slider
  (X_α = (0, Π'), X_αα = (0, Π'')) gives −m_s·ω²·Π'·Π''; a uniform rod of mass
  m_r (centre of mass G at mid-length, moment of inertia m_r·L²/12 about it, at
  angle φ to the guide) gives −m_r·ω²·(G_α·G_αα + L²/12·φ_α·φ_αα).

The carrier and the planet turn about axes that move at constant speed (the
planet's centre on a circle at ω, its spin at −k·ω), so their kinetic energy is
constant: they add nothing at constant ω. Gravity is not included (its work over
a turn is zero; it would only reshape the torque's ripple).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, flag, float_array, positive, real_array
from .._errors import InputError

if TYPE_CHECKING:
    from ._drive import GearLeverPress

__all__ = ["DeformationForce", "PressTorque"]

Array = npt.NDArray[np.float64]

#: Slack allowed beyond the working stroke [0, S_p] for a table's positions, as a
#: fraction of S_p (the rounding of a hand-written S_p).
STROKE_TOL = 1e-9


def check_table(
    s: Any, force: Any, s_key: str, force_key: str, *, counted: bool = False
) -> tuple[Array, Array]:
    """The positions [m] and forces [N] of a force diagram as float64 arrays, or
    :class:`InputError` naming the offending key: 1-D, the same length ≥ 2, finite,
    positions ≥ 0 and strictly increasing, forces ≥ 0. An entry is named as a
    Python subscript (``s[0]``), or ``counted`` from 1 as a file's (``s_m #1``)."""

    def at(key: str, j: Any) -> str:
        return f"{key} #{int(j) + 1}" if counted else f"{key}[{int(j)}]"

    a = float_array(s_key, s)
    f = float_array(force_key, force)
    if a.size < 2 or a.size != f.size:
        raise InputError(
            f"{s_key} and {force_key} must have the same length, at least 2 points; got "
            f"{a.size} and {f.size}"
        )
    for key, v in ((s_key, a), (force_key, f)):
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise InputError(f"{at(key, bad[0])} = {float(v[bad[0]])!r} is not finite")
    bad = np.flatnonzero(np.diff(a) <= 0)
    if bad.size:
        j = int(bad[0])
        raise InputError(
            f"{s_key} must increase strictly (heights above BDC [m]); {at(s_key, j + 1)} = "
            f"{float(a[j + 1])!r} does not exceed {at(s_key, j)} = {float(a[j])!r}"
        )
    if a[0] < 0:
        raise InputError(f"{at(s_key, 0)} = {float(a[0])!r} must be ≥ 0 [m] (a height above BDC)")
    bad = np.flatnonzero(f < 0)
    if bad.size:
        j = int(bad[0])
        raise InputError(
            f"{at(force_key, j)} = {float(f[j])!r} must be ≥ 0 [N] (the blank pushes the slider up)"
        )
    return a, f


@dataclass(frozen=True)
class DeformationForce:
    """A deformation-force diagram: the force the blank puts on the slider over its height.

    Linearly interpolated, and zero outside the table: the slider is off the blank
    there. It acts only on the working stroke, the approach to BDC (α from α_p down
    to 0); the table must lie inside [0, S_p] (see :meth:`check_stroke`). Each
    parameter is kept as the attribute of the same name (as a float array).

    Parameters
    ----------
    s : array_like of float, shape (M,)
        The slider's heights above BDC [m] (the press's S = Π(α)), M ≥ 2, ≥ 0 and
        strictly increasing.
    force : array_like of float, shape (M,)
        The force at each height [N] (≥ 0: the blank pushes the slider up).

    Raises
    ------
    InputError
        If the arrays are not of one length ≥ 2, not finite, the heights are
        negative or do not increase strictly, or a force is negative.

    Examples
    --------
    >>> f = DeformationForce([0.0, 0.004, 0.01], [2e5, 2e5, 0.0])
    >>> f.at([0.002, 0.007, 0.02]).tolist(), f.energy_j
    ([200000.0, 100000.0, 0.0], 1400.0)
    """

    s: Array
    force: Array

    def __post_init__(self) -> None:
        s, f = check_table(self.s, self.force, "s", "force")
        object.__setattr__(self, "s", s)
        object.__setattr__(self, "force", f)

    def at(self, s: npt.ArrayLike) -> Array:
        """The force [N] at given heights above BDC (0 outside the table).

        Parameters
        ----------
        s : float or array_like of float
            The slider's heights above BDC [m].

        Returns
        -------
        ndarray of float
            The force at each height [N], of the shape of ``s``.

        Examples
        --------
        >>> DeformationForce([0.001, 0.002], [10.0, 20.0]).at([0.0, 0.0015]).tolist()
        [0.0, 15.0]
        """
        x = real_array("s", s, "[m]")
        return np.interp(x, self.s, self.force, left=0.0, right=0.0)

    @property
    def energy_j(self) -> float:
        """The energy per stroke ∫ F dS [J] (exact for the linear interpolation).

        Examples
        --------
        >>> DeformationForce([0.0, 0.01], [1e5, 1e5]).energy_j
        1000.0
        """
        return float(np.sum(0.5 * (self.force[1:] + self.force[:-1]) * np.diff(self.s)))

    def check_stroke(self, S_p: float, s_key: str = "s", *, counted: bool = False) -> None:
        """Check that the table lies inside the working stroke [0, ``S_p``] [m].

        To ``STROKE_TOL`` (1e-9)·S_p.

        Parameters
        ----------
        S_p : float
            The working stroke [m].
        s_key : str, default "s"
            The key the error names (the table's key in the file).
        counted : bool, default False
            Name the entry counted from 1, as a file's (``s_m #2``), not as a
            Python subscript (``s[1]``).

        Raises
        ------
        InputError
            Naming ``s_key``, if a height lies above the working stroke.

        Examples
        --------
        >>> DeformationForce([0.0, 0.02], [1.0, 1.0]).check_stroke(0.0128)
        Traceback (most recent call last):
        cyclomech._errors.InputError: s[1] = 0.02 m lies above the working stroke: the force
        diagram's heights above BDC must lie in [0, 0.0128] m (S_p = 0.0128 m)
        """
        S_p = positive("S_p", S_p, "[m]")
        counted = flag("counted", counted)
        top = S_p * (1.0 + STROKE_TOL)
        bad = np.flatnonzero(self.s > top)
        if bad.size:
            j = int(bad[0])
            at = f"{s_key} #{j + 1}" if counted else f"{s_key}[{j}]"
            raise InputError(
                f"{at} = {float(self.s[j])!r} m lies above the working stroke: the force "
                f"diagram's heights above BDC must lie in [0, {S_p:.6g}] m (S_p = {S_p:.6g} m)"
            )


@dataclass(frozen=True)
class PressTorque:
    """The crank torque of a press drive over α: M(α) = ω²·``per_omega2`` + ``static`` [N·m].

    The torque the drive puts into the crank in its direction of rotation (see the
    module's derivation), α from BDC against the motion. Built by
    :meth:`GearLeverPress.crank_torque`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    alpha : ndarray of float, shape (N,)
        The crank angles α [rad], from BDC against the motion.
    per_omega2 : ndarray of float, shape (N,)
        The inertia of the slider and the rod, the torque per ω² [N·m·s²].
    static : ndarray of float, shape (N,)
        F(Π)·Π' on the working stroke (0 ≤ α mod 2π ≤ α_p), 0 elsewhere [N·m].
    S_p : float
        The working stroke [m].
    alpha_p : float
        The crank angle of the working stroke [rad].
    energy_per_stroke_j : float
        ∫ F dS over the working stroke [J] (0 without a force diagram).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
    >>> f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
    >>> t = p.crank_torque(np.radians([0.0, 30.0, 90.0]), force=f, k_Sp=0.1)
    >>> t.static.round(1).tolist(), round(t.energy_per_stroke_j, 3)
    ([0.0, 3522.2, 0.0], 1200.0)
    """

    alpha: Array
    per_omega2: Array
    static: Array
    S_p: float
    alpha_p: float
    energy_per_stroke_j: float

    def torque_nm(self, omega: float) -> Array:
        """M(α) [N·m] at a crank speed.

        Parameters
        ----------
        omega : float
            The crank speed ω [rad/s].

        Returns
        -------
        ndarray of float, shape (N,)
            The torque at each angle of ``alpha`` [N·m].

        Raises
        ------
        InputError
            If ``omega`` is not finite.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> t = p.crank_torque(np.radians([90.0]), slider_mass=10.0, k_Sp=0.1)
        >>> t.torque_nm(2.0).round(4).tolist()      # −m·ω²·Π'·Π'' at α = 90°
        [0.0294]
        """
        w = finite_number("omega", omega, "[rad/s]")
        return w * w * self.per_omega2 + self.static

    def peak_torque_nm(self, omega: float) -> float:
        """The largest M over the grid [N·m] at a crank speed.

        It is the grid's: where the diagram starts with a force at S_p, the peak may sit
        at the first contact α_p, which the grid then must hold to see.

        Parameters
        ----------
        omega : float
            The crank speed ω [rad/s].

        Returns
        -------
        float
            The peak torque over the grid [N·m].

        Raises
        ------
        InputError
            If ``omega`` is not finite.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
        >>> t = p.crank_torque(np.radians(np.arange(3600) / 10), force=f, k_Sp=0.1)
        >>> round(t.peak_torque_nm(4.0), 1)
        3886.4
        """
        return float(np.max(self.torque_nm(omega)))


def _mass(name: str, value: Any) -> float:
    return finite_number(name, value, "[kg]", low=0.0)


def crank_torque(
    press: GearLeverPress,
    alpha: npt.ArrayLike,
    *,
    force: DeformationForce | None = None,
    slider_mass: float = 0.0,
    rod_mass: float = 0.0,
    k_Sp: float | None = None,
    working_stroke: float | None = None,
    n_threads: int | None = None,
) -> PressTorque:
    """:meth:`GearLeverPress.crank_torque` (see there)."""
    m_s, m_r = _mass("slider_mass", slider_mass), _mass("rod_mass", rod_mass)
    c = press.criteria(omega=1.0, k_Sp=k_Sp, working_stroke=working_stroke)
    if not (math.isfinite(c.S_p) and math.isfinite(c.alpha_p)):
        raise InputError(f"the press design has no working stroke: {c.status}")
    if force is not None and not isinstance(force, DeformationForce):
        raise InputError(
            f"force = {force!r} must be a cyclomech.press.DeformationForce (the force diagram "
            "over the slider's height above BDC), or None"
        )
    if force is not None:
        force.check_stroke(c.S_p)
    a = float_array("alpha", alpha)
    k = press.solve(a, n_threads=n_threads)
    if not k.ok.all():
        bad = int((~k.ok).sum())
        raise InputError(
            f"the press design does not work: the rod cannot reach the guide at {bad} of the angles"
        )
    # The force acts on the approach to BDC only, α mod 2π in [0, α_p].
    on = np.mod(a, 2.0 * math.pi) <= c.alpha_p
    static = np.zeros_like(a)
    if force is not None:
        # Π = S_p at α_p only to rounding (the criteria and the kinematics compute
        # it apart): heights above S_p by at most 1e-12 of the stroke read the
        # diagram at S_p, not past its end (where the force is zero).
        s = np.where((k.s > c.S_p) & (k.s <= c.S_p + 1e-12 * c.S_n), c.S_p, k.s)
        static = np.where(on, force.at(s) * k.ds, 0.0)
    per_omega2 = -m_s * k.ds * k.dds
    if m_r > 0:
        per_omega2 = per_omega2 - m_r * _rod_term(press, k)
    energy = 0.0 if force is None else force.energy_j
    return PressTorque(a, per_omega2, static, c.S_p, c.alpha_p, energy)


def _rod_term(press: GearLeverPress, k: Any) -> Array:
    """G_α·G_αα + L²/12·φ_α·φ_αα of a uniform rod per unit mass [m²] (α-derivatives,
    θ = θ_B − α): the pin P = C + q with C = (R − r)·e^{iθ}, q = d·e^{iβ},
    β = β0 − kθ, so P_θ = i(C − k·q), P_θθ = −(C + k²·q); P_α = −P_θ, P_αα = P_θθ."""
    g1, g2, phi1, phi2 = _rod_analogs(press, k)
    out: Array = (g1.real * g2.real + g1.imag * g2.imag) + press.L**2 / 12.0 * phi1 * phi2
    return out


def crank_inertia(
    press: GearLeverPress,
    alpha: npt.ArrayLike,
    *,
    slider_mass: float = 0.0,
    rod_mass: float = 0.0,
    n_threads: int | None = None,
) -> Array:
    """The reduced moment of inertia about the crank of the slider and the rod [kg·m²].

    The kinetic energy ½·J(α)·ω² of the parts whose speed varies over the turn:
    J = m_s·Π′² + m_r·(|G_α|² + L²/12·φ_α²) (the carrier and the planet add a
    constant, left out as :func:`crank_torque` leaves it out). Half its
    α-derivative is minus the ω² part of :func:`crank_torque` (dα/dt = −ω).

    Parameters
    ----------
    press : GearLeverPress
        The drive.
    alpha : array_like of float, shape (N,)
        The crank angles α [rad] from BDC against the motion.
    slider_mass, rod_mass : float, default 0.0
        The slider's and the uniform rod's masses [kg] (≥ 0).
    n_threads : int, optional
        Threads for the kinematics; default None.

    Returns
    -------
    ndarray of float, shape (N,)
        J at each angle [kg·m²].

    Raises
    ------
    InputError
        If a mass is negative or the rod cannot reach the guide at some angle.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.press._torque import crank_inertia
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
    >>> bool(crank_inertia(p, np.radians([0.0, 90.0]), slider_mass=10.0)[0] < 1e-12)
    True
    """
    m_s, m_r = _mass("slider_mass", slider_mass), _mass("rod_mass", rod_mass)
    a = float_array("alpha", alpha)
    k = press.solve(a, n_threads=n_threads)
    if not k.ok.all():
        bad = int((~k.ok).sum())
        raise InputError(
            f"the press design does not work: the rod cannot reach the guide at {bad} of the angles"
        )
    out: Array = m_s * k.ds * k.ds
    if m_r > 0:
        g1, _g2, phi1, _phi2 = _rod_analogs(press, k)
        out = out + m_r * (np.abs(g1) ** 2 + press.L**2 / 12.0 * phi1 * phi1)
    return out


def _rod_analogs(press: GearLeverPress, k: Any) -> tuple[Any, Any, Array, Array]:
    """The rod's centre of mass G_α, G_αα (complex) and its angle's φ_α, φ_αα
    (α-derivatives; see :func:`_rod_term`)."""
    kk = press.ratio - 1.0
    c = k.centre[:, 0] + 1j * k.centre[:, 1]
    q = (k.pin[:, 0] + 1j * k.pin[:, 1]) - c
    p1 = -1j * (c - kk * q)
    p2 = -(c + kk * kk * q)
    g1 = 0.5 * (p1 + 1j * k.ds)
    g2 = 0.5 * (p2 + 1j * k.dds)
    u = k.pin[:, 0] - press.offset
    w = k.pin[:, 1] - k.slider[:, 1]
    u1, u2 = p1.real, p2.real
    phi1 = u1 / w
    phi2 = u2 / w + u * u1 * u1 / w**3
    return g1, g2, phi1, phi2
