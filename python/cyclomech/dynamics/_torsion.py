"""The main shaft's torsion and the working members' dynamic errors: `_torsion`
part of :mod:`cyclomech.dynamics` (its door). The kernel is
``rust/core/src/dynamics/torsion.rs``; the model, the method and its error are
described there and in :func:`torsion`."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import (
    count,
    finite_number,
    float_array,
    instance,
    instances,
    positive,
    threads_arg,
    tolerance,
)
from .._errors import InputError, SolverError
from .._units import RAD_PER_S_PER_RPM
from ._motor import Motor, pack

__all__ = [
    "ShaftNode",
    "Torsion",
    "TorsionSweep",
    "WorkingMember",
    "torsion",
    "torsion_sweep",
]

Array = npt.NDArray[np.float64]

_STATUS: tuple[str, ...] = tuple(_core.TORSION_STATUS)


def _rows(name: str, value: Any, samples: int | None) -> Array:
    """``value`` as a C-contiguous (C, N) float array of finite numbers."""
    a = np.array(float_array(name, value, (1, 2)), ndmin=2, copy=True)
    if a.ndim != 2 or a.shape[0] > 3 or (samples is not None and a.shape[1] != samples):
        want = "N" if samples is None else str(samples)
        raise InputError(
            f"{name} must have shape (N,) or (C, N) with C ≤ 3, N = {want}; got {a.shape}"
        )
    if not np.isfinite(a).all():
        raise InputError(f"{name} must be finite everywhere")
    return np.ascontiguousarray(a)


@dataclass(frozen=True)
class WorkingMember:
    """A mechanism's working member on its elastic link (or transmission).

    Its rigid position Π(φ) over the mechanism's take-off angle φ on the main
    shaft's N uniform angles (one to three coordinates: a slider's travel, a
    point's x and y), with the derivatives Π′ and Π″ in φ; the link's natural
    frequency (the member as one mass on it; infinite: a rigid link) and damping
    ratio; and the dynamic error it may have (None: no bound). Each parameter is
    kept as the attribute of the same name (the arrays as (C, N)).

    Parameters
    ----------
    position, d1, d2 : array_like of float, shape (N,) or (C, N)
        Π [unit], Π′ [unit/rad], Π″ [unit/rad²].
    unit : str, default "m"
        Π's unit ("m" or "rad").
    frequency_hz : float, default inf
        The link's natural frequency [Hz] (> 0; inf: a rigid link).
    damping_ratio : float, default 0.05
        The link's damping ratio ζ (≥ 0).
    max_error : float, optional
        The largest dynamic error allowed [unit] (> 0).

    Raises
    ------
    InputError
        If an array is not finite or the shapes differ, or a number is out of range.

    Examples
    --------
    >>> import numpy as np
    >>> phi = np.linspace(0.0, 2 * np.pi, 8, endpoint=False)
    >>> m = WorkingMember(0.01 * np.sin(phi), 0.01 * np.cos(phi), -0.01 * np.sin(phi),
    ...                   frequency_hz=50.0)
    >>> m.position.shape, m.unit
    ((1, 8), 'm')
    """

    position: Array
    d1: Array
    d2: Array
    unit: str = "m"
    frequency_hz: float = math.inf
    damping_ratio: float = 0.05
    max_error: float | None = None

    def __post_init__(self) -> None:
        p = _rows("WorkingMember: position", self.position, None)
        object.__setattr__(self, "position", p)
        for name in ("d1", "d2"):
            v = _rows(f"WorkingMember: {name}", getattr(self, name), p.shape[1])
            if v.shape != p.shape:
                raise InputError(f"WorkingMember: {name} must have position's shape {p.shape}")
            object.__setattr__(self, name, v)
        if self.unit not in ("m", "rad"):
            raise InputError(f"WorkingMember: unit = {self.unit!r} must be 'm' or 'rad'")
        f = self.frequency_hz
        if not (isinstance(f, (int, float)) and not isinstance(f, bool) and f > 0):
            raise InputError(f"WorkingMember: frequency_hz = {f!r} must be > 0 [Hz] (inf: rigid)")
        object.__setattr__(self, "frequency_hz", float(f))
        z = finite_number("WorkingMember: damping_ratio", self.damping_ratio, "", low=0.0)
        object.__setattr__(self, "damping_ratio", z)
        if self.max_error is not None:
            object.__setattr__(
                self, "max_error", positive("WorkingMember: max_error", self.max_error, self.unit)
            )


@dataclass(frozen=True)
class ShaftNode:
    """A take-off point on the main shaft, in order from the motor's end.

    Its mechanism's reduced inertia J(φ) [kg·m²], J′ = dJ/dφ [kg·m²/rad] and load
    torque Q(φ) [N·m] at the main shaft's N uniform angles (phased by the
    cyclogram, as :func:`reduced` phases them), the constant inertia of its hub
    (the crank, cam disc, gear and shaft section there) [kg·m²], the stiffness
    [N·m/rad] and damping [N·m·s/rad] of the shaft segment between it and the
    node before it (the motor's end for the first), and its working member. Each
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The mechanism's name.
    inertia_kg_m2, d_inertia, load_torque_nm : array_like of float, shape (N,)
        J, J′ and Q.
    hub_inertia_kg_m2 : float
        > 0.
    stiffness_nm_per_rad : float
        > 0.
    damping_nm_s_per_rad : float, default 0.0
        ≥ 0 (the steady state needs some damping somewhere to settle).
    member : WorkingMember, optional
        Its working member (None: only the twist is computed).

    Raises
    ------
    InputError
        If a value is out of range or the arrays differ in length.

    Examples
    --------
    >>> import numpy as np
    >>> n = ShaftNode("knife", np.zeros(8), np.zeros(8), np.full(8, 2.0), 0.01, 1e4)
    >>> n.stiffness_nm_per_rad
    10000.0
    """

    name: str
    inertia_kg_m2: Array
    d_inertia: Array
    load_torque_nm: Array
    hub_inertia_kg_m2: float
    stiffness_nm_per_rad: float
    damping_nm_s_per_rad: float = 0.0
    member: WorkingMember | None = field(default=None)

    def __post_init__(self) -> None:
        instance("ShaftNode: name", self.name, str)
        j = _rows(f"ShaftNode {self.name!r}: inertia_kg_m2", self.inertia_kg_m2, None)
        if j.shape[0] != 1 or j.shape[1] < 4:
            raise InputError(f"ShaftNode {self.name!r}: inertia_kg_m2 must be (N,) with N ≥ 4")
        n = j.shape[1]
        object.__setattr__(self, "inertia_kg_m2", j[0])
        for k in ("d_inertia", "load_torque_nm"):
            object.__setattr__(
                self, k, _rows(f"ShaftNode {self.name!r}: {k}", getattr(self, k), n)[0]
            )
        w = f"ShaftNode {self.name!r}"
        object.__setattr__(
            self,
            "hub_inertia_kg_m2",
            positive(f"{w}: hub_inertia_kg_m2", self.hub_inertia_kg_m2, "[kg·m²]"),
        )
        object.__setattr__(
            self,
            "stiffness_nm_per_rad",
            positive(f"{w}: stiffness_nm_per_rad", self.stiffness_nm_per_rad, "[N·m/rad]"),
        )
        object.__setattr__(
            self,
            "damping_nm_s_per_rad",
            finite_number(
                f"{w}: damping_nm_s_per_rad", self.damping_nm_s_per_rad, "[N·m·s/rad]", low=0.0
            ),
        )
        if self.member is not None:
            instance(f"{w}: member", self.member, WorkingMember)
            if self.member.position.shape[1] != n:
                raise InputError(
                    f"{w}: its member has {self.member.position.shape[1]} angles, not {n}"
                )
        if (j[0] + self.hub_inertia_kg_m2 <= 0).any():
            raise InputError(f"{w}: J + hub_inertia_kg_m2 must be > 0 at every angle")


def _pack(nodes: Sequence[ShaftNode]) -> dict[str, Array]:
    """The kernel's chain arrays (see ``rust/bindings/src/dynamics_torsion.rs``)."""
    nodes = instances("nodes", nodes, ShaftNode)
    if not nodes:
        raise InputError("nodes: the shaft needs at least one take-off point (ShaftNode)")
    n = nodes[0].inertia_kg_m2.size
    if any(x.inertia_kg_m2.size != n for x in nodes):
        raise InputError(f"nodes: every node needs the same number of angles ({n})")
    names = [x.name for x in nodes]
    if len(set(names)) != len(names):
        raise InputError(f"nodes: the names {names} repeat")
    curves = np.vstack(
        [
            [x.inertia_kg_m2 for x in nodes],
            [x.d_inertia for x in nodes],
            [x.load_torque_nm for x in nodes],
        ]
    )
    rows = []
    for x in nodes:
        m = x.member
        rows.append(
            [
                x.hub_inertia_kg_m2,
                x.stiffness_nm_per_rad,
                x.damping_nm_s_per_rad,
                0.0 if m is None else m.position.shape[0],
                math.inf if m is None else 2.0 * math.pi * m.frequency_hz,
                0.0 if m is None else m.damping_ratio,
            ]
        )
    ms = [x.member for x in nodes if x.member is not None]
    members = (
        np.vstack(
            [
                np.vstack([m.position for m in ms]),
                np.vstack([m.d1 for m in ms]),
                np.vstack([m.d2 for m in ms]),
            ]
        )
        if ms
        else np.zeros((0, n))
    )
    return {
        "curves": np.ascontiguousarray(curves),
        "nodes": np.ascontiguousarray(np.asarray(rows, dtype=np.float64)),
        "members": np.ascontiguousarray(members),
    }


def _options(tol: Any, max_cycles: Any, accuracy: Any) -> dict[str, Any]:
    return {
        "tol": tolerance("tol", tol, 1e-14, 0.1),
        "max_cycles": count("max_cycles", max_cycles, low=1, high=1_000_000),
        "accuracy": tolerance("accuracy", accuracy, 1e-4, 0.5),
    }


@dataclass(frozen=True)
class Torsion:
    """The periodic steady state of the main shaft as a chain of torsional springs.

    At the N head (motor-end) angles ``theta_deg``: the head's speed, the time,
    each node's twist behind the head θ_k [rad] and the torque in the segment
    before it [N·m], and each working member's dynamic error e (its position
    minus the rigid machine's at the same head angle) [its unit], with its peak
    (the largest |e| over the samples, the norm over a point's coordinates).
    Built by :func:`torsion`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    names : tuple of str
        The nodes, in order from the head.
    theta_deg, omega, time_s : ndarray of float, shape (N,)
        Head angles [deg], speed [rad/s], time from the first angle [s].
    twist_rad, segment_torque_nm : ndarray of float, shape (n, N)
        θ_k and S_k.
    error : dict of str to ndarray, shape (C, N)
        Each member's error [its unit].
    peak_error : dict of str to float
        Each member's peak |e| [its unit].
    units : dict of str to str
        Each member's unit.
    cycles, steps : int
        Cycles integrated to the steady state, RK4 steps per cycle.
    residual : float
        The last cycle's relative change of the state.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    >>> node = cm.dynamics.ShaftNode("crank", np.zeros(360), np.zeros(360),
    ...                              5.0 + 2.0 * np.sin(phi), 0.02, 2e4, 2.0)
    >>> t = cm.dynamics.torsion([node], rpm=300.0)
    >>> round(float(t.twist_rad.mean()) * 2e4, 3)   # the mean twist: mean load / c
    5.0
    """

    names: tuple[str, ...]
    theta_deg: Array
    omega: Array
    time_s: Array
    twist_rad: Array
    segment_torque_nm: Array
    error: dict[str, Array]
    peak_error: dict[str, float]
    units: dict[str, str]
    cycles: int
    steps: int
    residual: float

    @property
    def mean_rpm(self) -> float:
        """The head's mean speed over the cycle, 2π/T [rpm].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> node = cm.dynamics.ShaftNode("a", np.zeros(8), np.zeros(8), np.ones(8), 0.1, 1e4, 5.0)
        >>> round(cm.dynamics.torsion([node], rpm=120.0).mean_rpm, 9)
        120.0
        """
        n = self.omega.size
        # the period: t at the last sample plus its step (the speed there)
        period = self.time_s[-1] + (2.0 * math.pi / n) / self.omega[-1]
        return float(2.0 * math.pi / period / RAD_PER_S_PER_RPM)

    def lag_deg(self, name: str, at_deg: Any) -> Array:
        """Node ``name``'s twist behind the head at head angles ``at_deg`` [deg], in
        degrees: an event of its mechanism at that angle of the cyclogram happens
        this much later (its working member reaches the event's position late by
        it, its link's vibration aside).

        Parameters
        ----------
        name : str
            A node's name.
        at_deg : float or array_like of float
            Head angles [deg] (any turn).

        Returns
        -------
        ndarray of float
            The lag [deg], linear between the samples.

        Raises
        ------
        InputError
            If ``name`` is not a node.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> node = cm.dynamics.ShaftNode("a", np.zeros(8), np.zeros(8), np.ones(8), 0.1, 1e4, 5.0)
        >>> float(np.round(cm.dynamics.torsion([node], rpm=120.0).lag_deg("a", 90.0), 6))
        0.00573
        """
        if name not in self.names:
            raise InputError(f"lag_deg: {name!r} is not a node; the nodes are {list(self.names)}")
        k = self.names.index(name)
        a = float_array("at_deg", at_deg, (0, 1))
        if not np.isfinite(a).all():
            raise InputError(f"lag_deg: at_deg = {at_deg!r} must be finite angles [deg]")
        x = np.mod(a, 360.0)
        grid = np.append(self.theta_deg, 360.0)
        tw = np.append(self.twist_rad[k], self.twist_rad[k][0])
        # the shape of at_deg (a number gives a 0-d array)
        return np.asarray(np.degrees(np.interp(x, grid, tw))).reshape(np.shape(at_deg))


def torsion(
    nodes: Sequence[ShaftNode],
    *,
    rpm: float | None = None,
    motor: Motor | None = None,
    head_inertia_kg_m2: float | None = None,
    start_rpm: float | None = None,
    tol: float = 1e-9,
    max_cycles: int = 5000,
    accuracy: float = 0.1,
) -> Torsion:
    """The periodic steady state of the main shaft as a chain of torsional springs.

    The head (the motor's end) turns at a constant ``rpm``, or under ``motor`` on
    its constant inertia ``head_inertia_kg_m2`` (flywheel, rotor and gears reduced
    to the shaft; the motor's rotor is *not* added: give it in the inertia).
    Each node carries its mechanism's J(φ) and Q(φ) on its hub and its working
    member on an elastic link; the equations are in the kernel's
    (``rust/core/src/dynamics/torsion.rs``). Integrated in the head's angle by
    fixed-step RK4 whose time step keeps the chain's fastest rate times it at
    ``accuracy``, cycle after cycle from the static twist, until the state at the
    first angle repeats to ``tol`` (relative to each variable's range). The
    working members' reaction on the shaft is what J and Q hold: their
    vibration's is neglected (a light member on a heavy shaft).

    Parameters
    ----------
    nodes : sequence of ShaftNode
        The take-off points in order from the head.
    rpm : float, optional
        The head's constant speed [rpm] (> 0); give this or ``motor``.
    motor : Motor, optional
        The motor at the head.
    head_inertia_kg_m2 : float, optional
        The head's inertia [kg·m²] (> 0), with ``motor``.
    start_rpm : float, optional
        The head's speed at the start [rpm] (> 0), required with ``motor``: the
        rigid machine's steady speed at the first angle
        (:func:`steady_state`) is the best start, the transient from it the
        shortest.
    tol : float, default 1e-9
        The periodicity, in [1e-14, 0.1].
    max_cycles : int, default 5000
        Cycles at most.
    accuracy : float, default 0.1
        The fastest rate times the time step, in [1e-4, 0.5].

    Returns
    -------
    Torsion
        Speeds, twists, segment torques and dynamic errors over the cycle.

    Raises
    ------
    InputError
        Naming the argument or node: a bad value, neither or both of ``rpm`` and
        ``motor``, or a chain too stiff for the speed (too many steps a cycle).
    SolverError
        If the chain does not settle in ``max_cycles`` (too little damping) or the
        head stalls.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    >>> member = cm.dynamics.WorkingMember(0.01 * np.sin(phi), 0.01 * np.cos(phi),
    ...                                    -0.01 * np.sin(phi))
    >>> node = cm.dynamics.ShaftNode("crank", np.zeros(360), np.zeros(360),
    ...                              np.full(360, 20.0), 0.02, 2e4, 2.0, member)
    >>> t = cm.dynamics.torsion([node], rpm=300.0)
    >>> round(t.peak_error["crank"] * 1e6, 2)   # ≈ 0.01 m · 20/2e4 rad [µm]
    10.0
    """
    arrays = _pack(nodes)
    opts = _options(tol, max_cycles, accuracy)
    names = tuple(x.name for x in nodes)
    if (rpm is None) == (motor is None):
        raise InputError(
            "torsion: give either rpm (a constant head speed) or motor, not both or neither"
        )
    if motor is not None:
        instance("motor", motor, Motor)
        if head_inertia_kg_m2 is None:
            raise InputError(
                "torsion: a motor needs head_inertia_kg_m2 (flywheel, rotor, gears) [kg·m²]"
            )
        inertia = positive("head_inertia_kg_m2", head_inertia_kg_m2, "[kg·m²]")
        if start_rpm is None:
            raise InputError(
                "torsion: a motor needs start_rpm, the head's speed at the start [rpm] (the "
                "rigid machine's steady speed at the first angle is the best start)"
            )
        speed, motors = math.nan, pack([motor])
        start = positive("start_rpm", start_rpm, "[rpm]") * RAD_PER_S_PER_RPM
    else:
        speed = positive("rpm", rpm, "[rpm]") * RAD_PER_S_PER_RPM
        motors, inertia, start = pack([]), 1.0, speed
    meta, w, t, tw, tq, err, peak = _core.dynamics_torsion(
        arrays["curves"],
        arrays["nodes"],
        arrays["members"],
        speed,
        **motors,
        head_inertia=inertia,
        omega_start=start,
        **opts,
    )
    status = int(meta[0])
    if status != 0:
        raise SolverError(
            f"torsion: no periodic steady state: {_STATUS[status]} after {int(meta[1])} cycles "
            f"(residual {meta[2]:.3g}); "
            + (
                "the chain needs more damping (damping_nm_s_per_rad, a link's damping_ratio) or "
                "more max_cycles"
                if status == 1
                else "the motor cannot drive the chain (its speed reached 0)"
            )
        )
    errors, peaks, units, row = {}, {}, {}, 0
    for k, x in enumerate(nodes):
        if x.member is not None:
            c = x.member.position.shape[0]
            errors[x.name], peaks[x.name] = err[row : row + c], float(peak[k])
            units[x.name] = x.member.unit
            row += c
    n = w.size
    return Torsion(
        names,
        np.linspace(0.0, 360.0, n, endpoint=False),
        w,
        t,
        tw,
        tq,
        errors,
        peaks,
        units,
        int(meta[1]),
        int(meta[3]),
        float(meta[2]),
    )


@dataclass(frozen=True)
class TorsionSweep:
    """The dynamic errors at many constant head speeds (:func:`torsion_sweep`).

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    names : tuple of str
        The nodes, in order from the head.
    rpm : ndarray of float, shape (S,)
        The head speeds [rpm].
    peak_error : ndarray of float, shape (S, n)
        Each member's peak |e| [its unit] (NaN without a member, or where the
        chain did not settle).
    max_twist_rad : ndarray of float, shape (S, n)
        Each node's largest |θ| [rad].
    settled : ndarray of bool, shape (S,)
        Where the steady state was found.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> node = cm.dynamics.ShaftNode("a", np.zeros(8), np.zeros(8), np.ones(8), 0.1, 1e4, 5.0)
    >>> cm.dynamics.torsion_sweep([node], [60.0, 120.0]).settled.tolist()
    [True, True]
    """

    names: tuple[str, ...]
    rpm: Array
    peak_error: Array
    max_twist_rad: Array
    settled: npt.NDArray[np.bool_]

    def limit_rpm(self, name: str, max_error: float) -> float:
        """The lowest speed of the sweep at which member ``name``'s peak error
        exceeds ``max_error``, linear between the two speeds that bracket it [rpm].

        **The rule** where the error is not monotone in speed (a resonance of the
        link or the shaft between two speeds that pass): the *first* crossing
        from below, from the lowest speed up: a window of speeds above it where
        the error drops again is not offered. inf where no speed of the sweep
        exceeds it; the lowest speed where even that one does (0 would claim a
        limit below the sweep). A speed where the chain did not settle counts as
        exceeding.

        Parameters
        ----------
        name : str
            A node with a working member.
        max_error : float
            The bound [the member's unit] (> 0).

        Returns
        -------
        float
            The speed [rpm].

        Raises
        ------
        InputError
            If ``name`` is not a node or ``max_error`` is not > 0.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> s = TorsionSweep(("a",), np.array([10.0, 20.0, 30.0]), np.array([[1.0], [3.0], [1.0]]),
        ...                  np.zeros((3, 1)), np.ones(3, bool))
        >>> s.limit_rpm("a", 2.0)   # crosses 2 between 10 and 20 rpm; 30 rpm is not offered
        15.0
        """
        i = self.first_over(name, max_error)
        if i is None:
            return math.inf
        e = self.peak_error[:, self.names.index(name)]
        if i == 0 or not self.settled[i]:
            return float(self.rpm[i])
        lo, hi = self.rpm[i - 1], self.rpm[i]
        return float(lo + (hi - lo) * (max_error - e[i - 1]) / (e[i] - e[i - 1]))

    def first_over(self, name: str, max_error: float) -> int | None:
        """The index of the lowest speed of the sweep at which member ``name``'s
        peak error exceeds ``max_error`` or the chain did not settle: the upper end
        of :meth:`limit_rpm`'s bracket.

        Parameters
        ----------
        name : str
            A node with a working member.
        max_error : float
            The bound [the member's unit] (> 0).

        Returns
        -------
        int or None
            The index into ``rpm``; None where no speed of the sweep exceeds it.

        Raises
        ------
        InputError
            If ``name`` is not a node or ``max_error`` is not > 0.

        Examples
        --------
        >>> import numpy as np
        >>> s = TorsionSweep(("a",), np.array([10.0, 20.0, 30.0]), np.array([[1.0], [3.0], [1.0]]),
        ...                  np.zeros((3, 1)), np.ones(3, bool))
        >>> s.first_over("a", 2.0), s.first_over("a", 4.0)
        (1, None)
        """
        if name not in self.names:
            raise InputError(f"limit_rpm: {name!r} is not a node; the nodes are {list(self.names)}")
        bound = positive("max_error", max_error, "")
        over = ~self.settled | ~(self.peak_error[:, self.names.index(name)] <= bound)
        return int(np.argmax(over)) if over.any() else None


def torsion_sweep(
    nodes: Sequence[ShaftNode],
    rpm: Any,
    *,
    tol: float = 1e-9,
    max_cycles: int = 5000,
    accuracy: float = 0.1,
    n_threads: int | None = None,
) -> TorsionSweep:
    """The dynamic errors at each constant head speed of ``rpm``, in parallel.

    As :func:`torsion` with the head at each constant speed (an ideal speed
    control, or a flywheel much larger than the chain's inertias), in Rust, the
    speeds in parallel and the GIL released.

    Parameters
    ----------
    nodes : sequence of ShaftNode
        The take-off points in order from the head.
    rpm : array_like of float, shape (S,)
        The head speeds [rpm], each > 0, increasing.
    tol, max_cycles, accuracy
        As :func:`torsion`'s.
    n_threads : int, optional
        Threads; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    TorsionSweep
        The peak errors and twists at each speed.

    Raises
    ------
    InputError
        Naming the argument: a bad value, or speeds not increasing.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> node = cm.dynamics.ShaftNode("a", np.zeros(8), np.zeros(8), np.ones(8), 0.1, 1e4, 5.0)
    >>> (cm.dynamics.torsion_sweep([node], [60.0, 120.0]).max_twist_rad * 1e4).round(6).tolist()
    [[1.0], [1.0]]
    """
    arrays = _pack(nodes)
    opts = _options(tol, max_cycles, accuracy)
    r = np.array(float_array("rpm", rpm, (0, 1)), ndmin=1)
    if r.ndim != 1 or r.size == 0 or not (np.isfinite(r) & (r > 0)).all():
        raise InputError(
            f"rpm must be a non-empty 1-D array of finite speeds > 0 [rpm]; got {rpm!r}"
        )
    if (np.diff(r) <= 0).any():
        raise InputError("rpm must increase strictly")
    out = _core.dynamics_torsion_sweep(
        arrays["curves"],
        arrays["nodes"],
        arrays["members"],
        r * RAD_PER_S_PER_RPM,
        **opts,
        n_threads=threads_arg(n_threads),
    )
    n = len(nodes)
    return TorsionSweep(
        tuple(x.name for x in nodes), r, out[:, 3 : 3 + n], out[:, 3 + n :], out[:, 0] == 0.0
    )
