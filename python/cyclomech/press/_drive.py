"""The press drive (:class:`GearLeverPress`): its kinematics and working-stroke
criteria for one design, from the Rust kernel, and the names of the criteria and
status codes."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, float_array, threads_arg
from .._errors import InputError

if TYPE_CHECKING:
    from ._torque import DeformationForce, PressTorque

__all__ = ["CRITERIA", "SAMPLES", "STATUS", "GearLeverPress", "PressCriteria", "PressKinematics"]


#: Names of the criteria, in the kernel's column order.
CRITERIA: tuple[str, ...] = tuple(_core.press_criteria_names())


#: Meaning of the status codes of a design.
STATUS = dict(enumerate(_core.PRESS_STATUS))


#: Carrier angles sampled per turn when criteria are computed.
SAMPLES = 360


_AXES = ("R", "r", "d", "L", "phi0")


@dataclass(frozen=True)
class PressKinematics:
    """The drive over a grid of α [rad] (from BDC against the motion).

    Built by :meth:`GearLeverPress.solve`; each parameter is kept as the attribute
    of the same name.

    Parameters
    ----------
    alpha : ndarray of float, shape (N,)
        The crank angles α [rad].
    s : ndarray of float, shape (N,)
        Π(α), the slider's height above BDC [m].
    ds : ndarray of float, shape (N,)
        Π' [m/rad].
    dds : ndarray of float, shape (N,)
        Π'' [m/rad²].
    centre : ndarray of float, shape (N, 2)
        The planet's centre [m] in the frame of the guide gear's centre.
    pin : ndarray of float, shape (N, 2)
        The rod's pin [m], same frame.
    slider : ndarray of float, shape (N, 2)
        The slider [m], same frame.
    ok : ndarray of bool, shape (N,)
        False where the rod cannot reach the guide (NaN there; centre and pin are
        still given).

    See Also
    --------
    GearLeverPress.solve : Builds it.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
    >>> k = p.solve(np.radians([0.0, 90.0]))
    >>> k.ok.tolist(), k.ds.round(4).tolist(), k.slider.round(4).tolist()
    ([True, True], [0.0, 0.06], [[0.0, -0.36], [0.0, -0.2939]])
    """

    alpha: npt.NDArray[np.float64]
    s: npt.NDArray[np.float64]
    ds: npt.NDArray[np.float64]
    dds: npt.NDArray[np.float64]
    centre: npt.NDArray[np.float64]
    pin: npt.NDArray[np.float64]
    slider: npt.NDArray[np.float64]
    ok: npt.NDArray[np.bool_]


@dataclass(frozen=True)
class PressCriteria:
    """Working-stroke criteria of one design at a crank speed.

    Built by :meth:`GearLeverPress.criteria` (and :meth:`PressGrid.at`); each
    parameter is kept as the attribute of the same name. ``status`` says why a
    design fails (``ok`` False: its criteria are NaN, except for a slider that moves
    back up during the working stroke, which keeps them).

    The working stroke starts at the *first contact*: coming down from TDC, the
    first α where S = S_p is ``alpha_p`` (``V_np`` the speed there). A slider that
    then backs off above S_p (by more than 1e-9 of the stroke) and comes down on the
    blank again before BDC *re-contacts* (status 4, :data:`STATUS`); one that moves
    back up without leaving the blank (rising faster than 1e-12 of the stroke per
    radian anywhere in the working stroke, also between samples: near a cusp,
    d ≈ r, the rise can be a few nanometres over a fraction of a sample step) has
    status 2. Both keep their criteria (from the first contact) and fail (``ok``
    False): design grids mark them and :func:`optimize` drops them. S_p is watched
    from TDC down to BDC only, the blank taken to be in place from TDC: a slider
    that also dips below S_p on its way up (two strokes a turn; about 1 % of i = 3
    designs, near φ0 = 60°) is not flagged for it.

    Mirror-symmetric designs (no offset, e.g. i = 3 with φ0 = π/3) have two equally
    low BDCs or two equally high TDCs. Dead centres within 1e-12 of the stroke tie;
    of tied BDCs the one at the smallest carrier angle in [0, 2π) is taken, of tied
    TDCs the first reached going back from that BDC, so every way of writing φ0
    gives the same criteria (and :meth:`GearLeverPress.solve` counts α from the same
    BDC).

    A *flat* BDC (y″ = 0 there, as in the symmetric R = 0.18, r = 0.03, d = 0.01,
    L = 0.4 m, φ0 = π/6, where y − y_B grows as the fourth power of the angle) is
    ill-conditioned: θ_B is the root of a y′ that is cubic there, and the ~1e-17
    rounding of y′ moves it by ~(6·1e-17/y⁗)^(1/3), about 3e-6 to 1e-5 rad, differently
    for each way of writing φ0 and for each ``samples``. ``theta_bdc`` and the
    criteria counted from it, ``alpha_p``, ``V_cp``, ``k_Vp`` and ``k_Vmax``, are then
    known to ~2e-5 (relative); the others, and the carrier angle of the first contact
    ``theta_bdc - alpha_p``, to rounding. :meth:`GearLeverPress.solve` takes its α = 0
    from the BDC these criteria find with the default ``samples``, so that
    S(``alpha_p``) = ``S_p`` to rounding also there.

    Parameters
    ----------
    S_n : float
        The nominal stroke [m].
    S_p : float
        The working stroke [m], k_Sp·S_n.
    alpha_p : float
        The crank angle of the working stroke's start, the first contact [rad].
    V_np : float
        The slider's speed at the first contact [m/s].
    V_cp : float
        Its mean speed over the working stroke, S_p·ω/α_p [m/s].
    V_pmax : float
        Its largest speed over the working stroke [m/s].
    J_max : float
        Its largest acceleration over the turn [m/s²].
    torque_arm : float
        The largest Π' over the working stroke [m]: the crank torque per newton of
        constant deformation force, a lever arm, not a torque (the crank torque
        [N·m] of a deformation-force diagram is :meth:`GearLeverPress.crank_torque`).
    k_Sp : float
        S_p/S_n.
    k_Vp : float
        V_np/V_cp (→ 0).
    k_Vmax : float
        V_pmax/V_cp (→ 1).
    k_M : float
        torque_arm/(S_n/2) (→ min).
    k_J : float
        J_max/(ω²·S_n/2) (→ min).
    theta_bdc : float
        The carrier angle of BDC [rad].
    omega : float
        The crank speed ω [rad/s].
    status : str
        The design's status, a value of :data:`STATUS` (``"ok"`` if it works).

    Examples
    --------
    >>> import math, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.028, L=0.46, phi0=math.radians(56))
    >>> c = p.criteria(k_Sp=0.1, omega=2 * math.pi * 40 / 60)
    >>> c.status[:11], round(math.degrees(c.alpha_p), 1), round(c.V_np * 1e3, 1)
    ('re-contacts', 126.2, 57.7)
    """

    S_n: float
    S_p: float
    alpha_p: float
    V_np: float
    V_cp: float
    V_pmax: float
    J_max: float
    torque_arm: float
    k_Sp: float
    k_Vp: float
    k_Vmax: float
    k_M: float
    k_J: float
    theta_bdc: float
    omega: float
    status: str

    @property
    def ok(self) -> bool:
        """True when the design works over the whole turn and the working stroke.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> p.criteria(k_Sp=0.1, omega=4.0).ok
        True
        """
        return self.status == STATUS[0]

    def as_dict(self) -> dict[str, float | str]:
        """The criteria by name (for tables and JSON).

        Returns
        -------
        dict of str to float or str
            Each criterion of :data:`CRITERIA`, ``omega`` and ``status``, by name.

        Examples
        --------
        >>> import cyclomech as cm
        >>> c = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> sorted(c.criteria(k_Sp=0.1, omega=4.0).as_dict())[:3]
        ['J_max', 'S_n', 'S_p']
        """
        return {k: getattr(self, k) for k in (*CRITERIA, "omega", "status")}


def _stroke(k_Sp: Any, working_stroke: Any) -> tuple[float | None, float | None]:
    if (k_Sp is None) == (working_stroke is None):
        raise InputError(
            "give exactly one of k_Sp (working stroke as a fraction of the nominal stroke) "
            "and working_stroke (S_p [m])"
        )
    if k_Sp is not None:
        k = finite_number("k_Sp", k_Sp, "(a fraction of the nominal stroke)")
        if not 0 < k <= 1:
            raise InputError(f"k_Sp = {k_Sp!r} must lie in (0, 1] (S_p/S_n)")
        return k, None
    s = finite_number("working_stroke", working_stroke, "[m]")
    if s <= 0:
        raise InputError(f"working_stroke = {working_stroke!r} must be > 0 [m]")
    return None, s


def _omega(omega: Any) -> float:
    w = finite_number("omega", omega, "[rad/s]")
    if w <= 0:
        raise InputError(f"omega = {omega!r} must be a positive crank speed [rad/s]")
    return w


def _samples(samples: Any) -> int:
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer):
        raise InputError(f"samples must be an integer; got {samples!r}")
    if not 8 <= samples <= 1_000_000:
        raise InputError(f"samples = {samples} must be between 8 and 1000000 angles per turn")
    return int(samples)


@dataclass(frozen=True)
class GearLeverPress:
    """A planetary gear-lever press drive (see :mod:`cyclomech.press` for the geometry).

    Each parameter is kept as the attribute of the same name (as a float).

    Parameters
    ----------
    R : float
        The guide gear's pitch radius [m].
    r : float
        The planet gear's pitch radius [m] (R/r a whole number from 2 to 64).
    d : float
        The pin's eccentricity on the planet [m] (0: crank-slider).
    L : float
        The rod's length [m].
    phi0 : float
        The guide gear's setting angle [rad].
    offset : float, default 0.0
        The slider's guide's offset from the centre [m].

    Raises
    ------
    InputError
        If a value is not finite or the geometry is impossible (R > r > 0, R/r
        whole, d ≥ 0, L > 0).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.025, L=0.3, phi0=0.3)
    >>> k = p.solve(np.radians([0.0, 90.0, 180.0]))
    >>> k.s.round(4).tolist(), k.pin.shape
    ([0.0, 0.0948, 0.1146], (3, 2))
    """

    R: float
    r: float
    d: float
    L: float
    phi0: float
    offset: float = 0.0

    def __post_init__(self) -> None:
        for name, unit in (
            ("R", "[m]"),
            ("r", "[m]"),
            ("d", "[m]"),
            ("L", "[m]"),
            ("phi0", "[rad]"),
            ("offset", "[m]"),
        ):
            object.__setattr__(self, name, finite_number(name, getattr(self, name), unit))
        # The kernel checks the geometry (R > r > 0, R/r whole, d ≥ 0, L > 0).
        _core.press_check(self.R, self.r, self.d, self.L, self.phi0, self.offset)

    def _row(self) -> npt.NDArray[np.float64]:
        return np.array([[self.R, self.r, self.d, self.L, self.phi0, self.offset]])

    @property
    def ratio(self) -> int:
        """The gear ratio i = R/r (dimensionless, whole).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.0).ratio
        3
        """
        return round(self.R / self.r)

    def solve(self, alpha: npt.ArrayLike, *, n_threads: int | None = None) -> PressKinematics:
        """Positions and exact transfer functions over a grid of crank angles.

        Parameters
        ----------
        alpha : array_like of float, shape (N,)
            The crank angles α [rad], from BDC against the motion: the BDC of
            :meth:`criteria` at the default ``samples`` (``theta_bdc``, the same
            numbers bit for bit, so that S(α_p) = S_p to rounding, see
            :class:`PressCriteria`); for a rod that cannot reach the guide over the
            whole turn (no criteria), the lowest point of the turn's assembled part.
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        PressKinematics
            Π, Π', Π'' and the positions at each angle.

        Raises
        ------
        InputError
            If ``alpha`` is not a 1-D array of numbers.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> k = p.solve(np.array([np.pi]))      # crank-slider: TDC at α = π
        >>> round(float(k.s[0]), 12), bool(k.ok[0])
        (0.12, True)
        """
        a = float_array("alpha", alpha)
        s, ds, dds, centre, pin, slider, ok = _core.press_solve(
            self._row(), a, n_threads=threads_arg(n_threads)
        )
        return PressKinematics(a, s[0], ds[0], dds[0], centre[0], pin[0], slider[0], ok[0])

    def criteria(
        self,
        *,
        omega: float,
        k_Sp: float | None = None,
        working_stroke: float | None = None,
        samples: int = SAMPLES,
    ) -> PressCriteria:
        """Working-stroke criteria at a crank speed ``omega`` [rad/s].

        For a working stroke of ``k_Sp``·S_n or ``working_stroke`` [m] (one of them).
        ``samples`` carrier angles per turn bracket every extreme, which is then found
        exactly (a root of the next derivative).

        Parameters
        ----------
        omega : float
            The crank speed ω [rad/s] (> 0). Keyword-only, as are the parameters below.
        k_Sp : float, optional
            The working stroke as a fraction of the nominal stroke, in (0, 1]; give it
            or ``working_stroke``.
        working_stroke : float, optional
            The working stroke S_p [m] (> 0).
        samples : int, default SAMPLES
            Carrier angles per turn (8 to 10⁶; :data:`SAMPLES` = 360).

        Returns
        -------
        PressCriteria
            The criteria (NaN and a failing ``status`` where the design does not work).

        Raises
        ------
        InputError
            If not exactly one of ``k_Sp`` and ``working_stroke`` is given, or a value
            is out of range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> c = p.criteria(k_Sp=0.1, omega=4.0)
        >>> round(c.S_n, 9), round(c.k_Vp, 3), c.ok
        (0.12, 1.915, True)
        """
        from ._grid import design_grid  # the grid module builds on this one

        sw = design_grid(
            R=self.R,
            r=self.r,
            d=self.d,
            L=self.L,
            phi0=self.phi0,
            offset=self.offset,
            k_Sp=k_Sp,
            working_stroke=working_stroke,
            omega=omega,
            samples=samples,
            progress=False,
        )
        return sw.at(())

    def crank_torque(
        self,
        alpha: npt.ArrayLike,
        *,
        force: DeformationForce | None = None,
        slider_mass: float = 0.0,
        rod_mass: float = 0.0,
        k_Sp: float | None = None,
        working_stroke: float | None = None,
        n_threads: int | None = None,
    ) -> PressTorque:
        """The crank torque [N·m] over α for a deformation-force diagram and the moving masses.

        For a working stroke of ``k_Sp``·S_n or ``working_stroke`` (one of them)::

            M(α) = F(Π(α))·Π'(α) [on the working stroke, 0 ≤ α ≤ α_p]
                   − ω²·(m_s·Π'·Π'' + m_r·(G_α·G_αα + L²/12·φ_α·φ_αα))

        [N·m], the torque the drive puts into the crank in its turning direction, from
        the power balance M·ω = dT/dt − F·v with v = dS/dt = −ω·Π' (α runs against the
        motion); G is the rod's centre, φ its angle. The ω² part and the force part come apart
        (:class:`PressTorque`). On the working stroke a height Π above S_p by no more
        than rounding (1e-12 of the nominal stroke, as at α = α_p, where Π = S_p to
        rounding) is read from the diagram at S_p, so that the force does not drop to
        zero at the stroke's start by the last bit of Π.

        Parameters
        ----------
        alpha : array_like of float, shape (N,)
            The crank angles α [rad], from BDC against the motion.
        force : DeformationForce, optional
            The deformation-force diagram, heights above BDC inside the working stroke
            [0, S_p]; default None (no force). Keyword-only, as are the parameters
            below.
        slider_mass : float, default 0.0
            The slider's mass m_s [kg] (≥ 0).
        rod_mass : float, default 0.0
            A uniform rod's mass m_r [kg] (≥ 0).
        k_Sp : float, optional
            The working stroke as a fraction of the nominal stroke, in (0, 1].
        working_stroke : float, optional
            The working stroke S_p [m] (> 0).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        PressTorque
            The torque's ω² part and its force part over α, with S_p, α_p and the
            energy per stroke.

        Raises
        ------
        InputError
            If not exactly one of ``k_Sp`` and ``working_stroke`` is given, a mass is
            negative, the force diagram leaves the working stroke, the design does not
            work at some angle, or a value is out of range.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
        >>> t = p.crank_torque(np.radians([30.0]), force=f, slider_mass=20.0, k_Sp=0.1)
        >>> t.torque_nm(4.0).round(2).tolist()
        [3521.58]
        """
        from ._torque import crank_torque

        return crank_torque(
            self,
            alpha,
            force=force,
            slider_mass=slider_mass,
            rod_mass=rod_mass,
            k_Sp=k_Sp,
            working_stroke=working_stroke,
            n_threads=n_threads,
        )

    def baseline(self) -> GearLeverPress:
        """The plain crank-slider of this drive.

        The same gears, rod and guide with the pin on the planet's centre (d = 0, and
        φ0 = 0).

        Returns
        -------
        GearLeverPress
            The baseline design.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.4).baseline().d
        0.0
        """
        return replace(self, d=0.0, phi0=0.0)

    def to_dict(self) -> dict[str, float]:
        """The design as a plain dict [m, rad].

        Returns
        -------
        dict of str to float
            ``R``, ``r``, ``d``, ``L`` [m], ``phi0`` [rad] and ``offset`` [m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.4).to_dict()["L"]
        0.3
        """
        return {k: getattr(self, k) for k in (*_AXES, "offset")}
