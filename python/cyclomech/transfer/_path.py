"""The composed transfer path in the machine frame (:class:`TransferPath`): circle,
smooth transition, straight segment, smooth transition, circle; sampled, and the
workpiece's acceleration and jerk along it for a speed law."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import (
    available_bytes,
    check_bytes,
    count,
    finite_number,
    flag,
    instance,
    one_block,
    out_array,
    threads_arg,
)
from .._errors import InfeasibleError, InputError
from ._checks import _LENGTH_RANGE, Array, _finite_array, _point, _radius, _speeds
from ._quintic import smooth_k_b, smooth_transition

__all__ = ["PathAcceleration", "PathSample", "TransferPath"]


#: Bytes a point budgeted by :meth:`TransferPath.sample`'s size check. The Rust
#: kernel writes straight into its outputs (49 bytes a point kept, nothing else);
#: the budget stays at the numpy code's peak, 112, which is also about what
#: :meth:`TransferPath.acceleration` holds (the sample and 64 bytes of kinematics
#: rows, whose allocation the bindings check too). tests/package/test_size_limits.py
#: pins the message.
_SAMPLE_PEAK_BYTES = 112

#: An overlap of the transitions up to this times the centre distance is rounding:
#: the straight counts as 0 m (the Rust candidate scan, ``STRAIGHT_RTOL`` in
#: rust/core/src/transfer/design.rs, takes the same rule; a test holds them equal).
_STRAIGHT_RTOL = 1e-12

#: Pieces of a sampled path, in travel order.
PIECES = ("arc_t", "transition_t", "straight", "transition_p", "arc_p")


@dataclass(frozen=True)
class PathSample:
    """A sampled :class:`TransferPath`, in travel order.

    Built by :meth:`TransferPath.sample`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    points : ndarray of float, shape (n, 2)
        The points (x, y) in the machine frame [m].
    s : ndarray of float, shape (n,)
        The arc length from the start [m].
    heading : ndarray of float, shape (n,)
        The tangent's angle [rad], unwrapped.
    curvature : ndarray of float, shape (n,)
        The signed curvature [1/m] (left turns positive).
    curvature_rate : ndarray of float, shape (n,)
        dκ/ds [1/m²].
    piece : ndarray of int8, shape (n,)
        The index into ``PIECES`` (arc_t, transition_t, straight, transition_p,
        arc_p) of each point.

    See Also
    --------
    TransferPath.sample : Builds it.

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
    >>> s = p.sample(11)
    >>> s.points.shape, s.piece.tolist()
    ((11, 2), [0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4])
    """

    points: Array
    s: Array
    heading: Array
    curvature: Array
    curvature_rate: Array
    piece: npt.NDArray[np.int8]


@dataclass(frozen=True)
class PathAcceleration:
    """The workpiece's motion along a sampled path for a speed law.

    Built by :meth:`TransferPath.acceleration`; each parameter is kept as the
    attribute of the same name. All arrays are of the sample's shape (n,).

    Parameters
    ----------
    s : ndarray of float
        The arc length from the start [m].
    time : ndarray of float
        The time from the start [s].
    speed : ndarray of float
        The speed v [m/s].
    normal : ndarray of float
        The normal acceleration v²·κ [m/s²].
    tangential : ndarray of float
        The tangential acceleration v·dv/ds [m/s²].
    total : ndarray of float
        |a| [m/s²].
    normal_rate : ndarray of float
        d(v²κ)/dt [m/s³].
    tangential_rate : ndarray of float
        The tangential acceleration's rate [m/s³].
    jerk : ndarray of float
        |da/dt| [m/s³] (the acceleration vector's rate, turning of the frame
        included).
    piece : ndarray of int8
        The index into ``PIECES`` of each point.

    See Also
    --------
    TransferPath.acceleration : Builds it.

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
    >>> a = p.acceleration(0.2)
    >>> round(float(a.speed[0]), 12), round(float(a.tangential.max()), 12)
    (0.2, 0.0)
    """

    s: Array
    time: Array
    speed: Array
    normal: Array
    tangential: Array
    total: Array
    normal_rate: Array
    tangential_rate: Array
    jerk: Array
    piece: npt.NDArray[np.int8]

    @property
    def max_jerk(self) -> float:
        """Peak |da/dt| [m/s³].

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> round(p.acceleration(0.2).max_jerk, 3)
        1.584
        """
        return float(self.jerk.max())

    @property
    def max_acceleration(self) -> float:
        """Peak |a| [m/s²].

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> round(p.acceleration(0.2).max_acceleration, 6)        # V²/R_t
        0.266667
        """
        return float(self.total.max())


def _rot(v: Array, angle: Any) -> Array:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _left(v: Array) -> Array:
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


@dataclass(frozen=True)
class _Geometry:
    """The path's construction for arrays of transition lengths (broadcast), in the
    frame where the transport rotor turns counter-clockwise."""

    k: Array  # (…, 2): per side
    b: Array
    shift: Array  # line's distance from each centre minus the radius
    feasible: npt.NDArray[np.bool_]  # the shifted circles leave room for the line
    u: Array  # (…, 2): direction of travel on the straight
    ends: Array  # (…, 2 sides, 2): B_t and B_p
    t_a: Array  # (…, 2 sides, 2): local x axes at A (transport) and C (process)
    origin: Array  # (…, 2 sides, 2): A and C
    straight: Array  # length of the straight segment


def _geometry(r: Array, c_t: Array, c_p: Array, x2: Array) -> _Geometry:
    """Both transitions and the line for transition lengths ``x2`` (…, 2) [m] on
    the circles r = (R_t, R_p) with centres c_t, c_p (counter-clockwise transport)."""
    k, b = smooth_k_b(r, x2)
    dist = (r - b) / np.sqrt(1.0 + k * k)  # the line's distance from each centre
    d_vec = c_p - c_t
    d = float(np.hypot(*d_vec))
    e = d_vec / d
    span = dist.sum(axis=-1)
    feasible = span <= d
    psi = np.arcsin(np.minimum(span / d, 1.0))
    # Direction of travel on the line: from near the transport rotor towards the
    # process one, the transport centre on its left.
    u = _rot(np.broadcast_to(e, (*psi.shape, 2)), psi)
    theta = np.arctan(k)  # each transition's turn, from its start frame to the line
    t_a = np.stack([_rot(u, -theta[..., 0]), _rot(-u, -theta[..., 1])], axis=-2)
    centres = np.stack([c_t, c_p])
    origin = centres - r[..., None] * _left(t_a)
    y_end = k * x2 + b
    ends = origin + x2[..., None] * t_a + y_end[..., None] * _left(t_a)
    straight = np.einsum("...i,...i->...", ends[..., 1, :] - ends[..., 0, :], u)
    return _Geometry(
        k=k,
        b=b,
        shift=dist - r,
        feasible=feasible,
        u=u,
        ends=ends,
        t_a=t_a,
        origin=origin,
        straight=np.where(feasible, straight, -np.inf),
    )


class TransferPath:
    """The guide of a workpiece from a transport rotor to a process rotor.

    The transport pitch circle (a lead-in arc of ``lead_deg``), a smooth quintic
    transition (:func:`smooth_transition`, length ``x2_t`` along its tangent), the
    straight segment, the mirror transition onto the process pitch circle (length
    ``x2_p``) and a lead-out arc. The straight line is the internal common tangent
    of the two circles each widened by its transition's shift (≈ x2²/(40R)), so the
    curvature runs continuously +1/R_t → 0 → −1/R_p, its rate too.

    Parameters
    ----------
    R_t : float
        The transport rotor's pitch radius [m] (> 0).
    R_p : float
        The process rotor's pitch radius [m] (> 0).
    centre_t : array_like of float, shape (2,)
        The transport rotor's centre (x, y) in the machine frame [m].
    centre_p : array_like of float, shape (2,)
        The process rotor's centre (x, y) [m], apart from ``centre_t`` by more than
        R_t + R_p (the transitions leave each pitch circle outwards, so they need a
        gap).
    x2 : float or tuple of (float, float), optional
        One transition length for both [m], or a pair (x2_t, x2_p); default None:
        the longest equal transitions the gap allows (the straight segment shrinks
        to a point: the guide is transition → transition, the seed's transfer with
        no common tangent segment).
    ccw : bool, default True
        The transport rotor turns counter-clockwise (the process rotor, meshing,
        clockwise); False mirrors the path. Keyword-only.
    lead_deg : float, default 30.0
        The lead-in and lead-out arcs [deg of pitch circle], in [0, 180].
        Keyword-only.

    Attributes
    ----------
    x2_t, x2_p : float
        The transition lengths [m] (given or the longest).
    k, b, shift : tuple of (float, float)
        Per side (transport, process): the line's slope and intercept [m] in the
        transition's frame, and the line's distance from the centre minus the
        radius [m].
    gap : float
        The gap between the pitch circles [m].
    A, C : ndarray of float, shape (2,)
        Where the path leaves the transport circle and joins the process one
        (machine frame) [m].
    B_t, B_p : ndarray of float, shape (2,)
        The ends of the straight segment (machine frame) [m].
    straight_length : float
        The straight segment's length [m].
    transitions : tuple of (QuinticTransition, QuinticTransition)
        The two transitions.
    frames : tuple of (tuple of (float, float, float), tuple of (float, float, float))
        The seed's (α [rad], x0 [m], y0 [m]) of each transition's frame, so that
        ``to_machine(x, q.y(x), *frames[i])`` places transition i (``q``) in the
        machine frame — with ``ccw=False`` the path is a mirror image and the seed's
        rotation cannot mirror, so there ``to_machine(x, -q.y(x), *frames[i])``.
    length : float
        The length of the whole path [m].

    Raises
    ------
    InputError
        If a radius, a centre, ``x2`` or ``lead_deg`` is malformed or out of range,
        or the pitch circles touch or overlap.
    InfeasibleError
        If the transitions are too long for the gap (they would overlap).

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.transfer.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.05)
    >>> round(p.straight_length, 4), [round(s * 1e3, 3) for s in p.shift]   # m, mm
    (0.0361, [0.425, 0.252])
    >>> smp = p.sample(2001)
    >>> round(float(smp.curvature[0]), 6), round(float(smp.curvature[-1]), 6)
    (6.666667, -4.0)
    """

    def __init__(
        self,
        R_t: float,
        R_p: float,
        centre_t: Any,
        centre_p: Any,
        x2: Any = None,
        *,
        ccw: bool = True,
        lead_deg: float = 30.0,
    ) -> None:
        self.R_t = _radius("R_t", R_t)
        self.R_p = _radius("R_p", R_p)
        self.centre_t = _point("centre_t", centre_t)
        self.centre_p = _point("centre_p", centre_p)
        self.ccw = flag("ccw", ccw)
        self.lead_deg = finite_number(
            "lead_deg", lead_deg, "degrees of pitch circle before and after", low=0.0
        )
        if self.lead_deg > 180.0:
            raise InputError(f"lead_deg = {lead_deg!r} must be ≤ 180 degrees")
        d = float(np.hypot(*(self.centre_p - self.centre_t)))
        self.gap = d - self.R_t - self.R_p
        if self.gap <= 0.0:
            raise InputError(
                f"the pitch circles touch or overlap: centre distance {d:.6g} m ≤ "
                f"R_t + R_p = {self.R_t + self.R_p:.6g} m (gap {self.gap:.3g} m). The "
                "transitions leave each pitch circle outwards, so the centres must be "
                "farther apart than R_t + R_p"
            )
        r = np.array([self.R_t, self.R_p])
        if x2 is None:
            x2v = _longest(r, *self._canonical_centres(), ratio=np.ones(2))
        else:
            x2a = _finite_array("x2", x2, "[m]")
            if x2a.shape not in ((), (1,), (2,)):
                raise InputError(
                    f"x2 must be one length or a pair (x2_t, x2_p) [m]; got shape {x2a.shape}"
                )
            x2v = np.broadcast_to(x2a, (2,)).astype(np.float64)
            lo, hi = _LENGTH_RANGE
            if not ((x2v >= lo) & (x2v <= hi)).all():
                raise InputError(
                    f"x2 must be > 0 m, in [{lo:g}, {hi:g}] m (transition lengths); got {x2!r}"
                )
        self.x2_t, self.x2_p = float(x2v[0]), float(x2v[1])
        g = _geometry(r, *self._canonical_centres(), x2v)
        if not g.feasible or g.straight < -_STRAIGHT_RTOL * d:
            longest = _longest(r, *self._canonical_centres(), ratio=x2v / x2v.max())
            raise InfeasibleError(
                f"x2 = ({self.x2_t:.6g}, {self.x2_p:.6g}) m is too long for a gap of "
                f"{self.gap:.6g} m: the transitions overlap (straight segment "
                f"{float(g.straight):.3g} m). In these proportions the longest is "
                f"({longest[0]:.6g}, {longest[1]:.6g}) m; x2=None takes it"
            )
        self._g = g
        self.k = (float(g.k[0]), float(g.k[1]))
        self.b = (float(g.b[0]), float(g.b[1]))
        self.shift = (float(g.shift[0]), float(g.shift[1]))
        self.straight_length = max(float(g.straight), 0.0)
        self.transitions = (
            smooth_transition(self.R_t, self.x2_t),
            smooth_transition(self.R_p, self.x2_p),
        )
        t_a, origin = g.t_a * self._mirror, g.origin * self._mirror
        self.frames = tuple(
            (math.atan2(-t[1], t[0]), -float(o[0]), -float(o[1]))
            for t, o in zip(t_a, origin, strict=True)
        )
        self.A, self.C = origin
        self.B_t, self.B_p = g.ends * self._mirror
        lead = math.radians(self.lead_deg)
        self._lengths = np.array(
            [
                self.R_t * lead,
                self.transitions[0].length,
                self.straight_length,
                self.transitions[1].length,
                self.R_p * lead,
            ]
        )
        self.length = float(self._lengths.sum())

    # Frames: everything is built with a counter-clockwise transport rotor; a
    # clockwise one is its mirror image in the x axis (its own inverse).
    @property
    def _mirror(self) -> Array:
        return np.array([1.0, 1.0 if self.ccw else -1.0])

    def _canonical_centres(self) -> tuple[Array, Array]:
        return self.centre_t * self._mirror, self.centre_p * self._mirror

    @property
    def transfer_length(self) -> float:
        """Arc length from A (leaving the transport circle) to C [m].

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> round(p.transfer_length, 6)
        0.136641
        """
        return float(self._lengths[1:4].sum())

    @property
    def start_of_transfer(self) -> float:
        """Arc length at A [m] (the lead-in arc's length).

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> round(p.start_of_transfer, 6)                  # 0.15 m · 30°
        0.07854
        """
        return float(self._lengths[0])

    def sample(
        self, n: int = 10_001, *, n_threads: int | None = None, out: PathSample | None = None
    ) -> PathSample:
        """Points along the whole path with arc length, heading, signed curvature and its rate.

        Each piece is sampled evenly in its own parameter, in proportion to its length;
        every piece gets ≥ 2. One Rust call with the GIL released, blocks of points on
        ``n_threads`` threads; the result does not depend on the thread count. Arc
        length on the transitions: 4-point Gauss–Legendre per interval, restarted from a
        16-point quadrature every 4096 points (exact to rounding).

        Parameters
        ----------
        n : int, default 10001
            The number of points (≥ 10).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
        out : PathSample, optional
            A previous sample of ``n`` points whose arrays are written in place (bit
            for bit a new sample; no new memory to first-touch). Default None: new
            arrays, carved from one block started on a huge-page boundary (they share
            its memory).

        Returns
        -------
        PathSample
            The sample, in travel order (with ``out``: a new PathSample of its arrays).

        Raises
        ------
        InputError
            If ``n`` is not a count ≥ 10, the sample would not fit in memory, or
            ``out`` is not a PathSample of ``n`` writeable C-contiguous arrays that
            share no memory with one another.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> s = p.sample(10_001)
        >>> bool(abs(s.s[-1] - p.length) < 1e-12), bool(abs(s.curvature).max() <= 1 / 0.15)
        (True, True)
        >>> again = p.sample(10_001, out=s)                # into s's arrays
        >>> again.s is s.s
        True
        """
        n = count("n", n, low=10, what="points along the path")
        threads = threads_arg(n_threads)
        if out is None:
            # Sized before anything is allocated: a size that cannot fit is an
            # InputError, not a MemoryError or the OOM killer.
            check_bytes(
                f"TransferPath.sample({n})",
                float(n) * _SAMPLE_PEAK_BYTES,
                f"sample fewer points (≤ {int(available_bytes() // _SAMPLE_PEAK_BYTES):,} fit)",
            )
            arrays = one_block(
                ((n, 2), np.float64),
                *[((n,), np.float64)] * 4,
                ((n,), np.int8),
                what=f"TransferPath.sample({n})",
                hint="sample fewer points",
            )
        else:
            arrays = _sample_out(out, n)
        counts = np.array(_allocate(n, self._lengths), dtype=np.int64)
        points, s, heading, curv, rate, piece = _core.transfer_sample(
            self._spec, counts, self.ccw, n_threads=threads, out=tuple(arrays)
        )
        return PathSample(points, s, heading, curv, rate, piece)

    @property
    def _spec(self) -> Array:
        """The path for the Rust sampler (cyclomech_core::transfer::N_SPEC numbers),
        in the counter-clockwise frame. Headings are carried on from piece to
        piece (each the last one's end angle), so they come out continuous."""
        g = self._g
        c_t, c_p = self._canonical_centres()
        phi_a = math.atan2(*(g.origin[0] - c_t)[::-1])  # A's angle about c_t
        base_t = phi_a + 0.5 * math.pi  # the heading at A
        head = base_t + math.atan(g.k[0])  # the straight's
        # The process transition is travelled backwards in C's frame: its
        # heading at B_p, atan(k_p) + base_p + π, is the straight's.
        base_p = head - math.atan(g.k[1]) - math.pi
        phi_c = base_p + 1.5 * math.pi  # C's angle about c_p: heading at C + π/2
        return np.concatenate(
            [
                c_t,
                c_p,
                [self.R_t, self.R_p, math.radians(self.lead_deg)],
                self.transitions[0].coeffs,
                self.transitions[1].coeffs,
                [self.x2_t, self.x2_p],
                g.origin.ravel(),
                g.t_a.ravel(),
                g.ends[0],
                g.u,
                [self.straight_length],
                self._lengths,
                [phi_a, base_t, head, base_p, phi_c],
            ]
        ).astype(np.float64)

    def speed_law(self, speed: Any) -> Any:
        """The speed law ``speed`` as a function s ↦ (v, dv/ds, d²v/ds²).

        See :meth:`acceleration`; v is V_t before A and V_p after C.

        Parameters
        ----------
        speed : float or tuple of (float, float)
            A constant speed V [m/s] or a pair (V_t, V_p) [m/s].

        Returns
        -------
        callable
            Arc lengths s [m] (array_like) to the tuple (v [m/s], dv/ds [1/s],
            d²v/ds² [1/(m·s)]) of arrays of their shape.

        Raises
        ------
        InputError
            If ``speed`` is not a finite number or pair.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> v, dv, ddv = p.speed_law((0.15, 0.25))([0.0, p.length])
        >>> v.round(12).tolist(), dv.tolist()
        ([0.15, 0.25], [0.0, 0.0])
        """
        return _speed_law(speed, self.start_of_transfer, self.transfer_length)

    def acceleration(
        self, speed: Any, n: int = 20_001, *, n_threads: int | None = None
    ) -> PathAcceleration:
        """The workpiece's acceleration and jerk along the path for a speed law.

        The speed law is a number V (constant, equal peripheral speeds), or a pair
        (V_t, V_p) — the speed changes from V_t to V_p between A and C by a quintic
        smoothstep in arc length (its first two derivatives zero at both ends), as when
        rotors of different pitch turn at one workpiece rate. Normal acceleration v²κ,
        tangential v·dv/ds, and their rates d/dt = v·d/ds; the time by the trapezoid
        rule in 1/v. Two Rust calls (the sample, then the kinematics), the GIL
        released, on ``n_threads``.

        Parameters
        ----------
        speed : float or tuple of (float, float)
            The speed V [m/s] or the pair (V_t, V_p) [m/s].
        n : int, default 20001
            The number of points the path is sampled at (≥ 10).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        PathAcceleration
            The speed, accelerations [m/s²] and their rates [m/s³] at each point.

        Raises
        ------
        InputError
            If ``speed`` is not a finite number or pair, or ``n`` is out of range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> a = p.acceleration(0.2)
        >>> round(float(a.normal[0]), 6), round(float(a.normal[-1]), 6)  # V²/R_t, −V²/R_p
        (0.266667, -0.16)
        """
        v_t, v_p = _speeds(speed)
        smp = self.sample(n, n_threads=n_threads)
        law = (v_t, v_p, self.start_of_transfer, self.transfer_length)
        rows = _core.transfer_kinematics(
            smp.s, smp.curvature, smp.curvature_rate, law, n_threads=threads_arg(n_threads)
        )
        time, v, a_n, a_t, total, an_rate, at_rate, jerk = rows
        return PathAcceleration(
            s=smp.s,
            time=time,
            speed=v,
            normal=a_n,
            tangential=a_t,
            total=total,
            normal_rate=an_rate,
            tangential_rate=at_rate,
            jerk=jerk,
            piece=smp.piece,
        )

    def max_jerk(self, speed: Any, n: int = 20_001, *, n_threads: int | None = None) -> float:
        """Peak |da/dt| [m/s³] along the path for a speed law (see :meth:`acceleration`).

        Parameters
        ----------
        speed : float or tuple of (float, float)
            The speed V [m/s] or the pair (V_t, V_p) [m/s].
        n : int, default 20001
            The number of points the path is sampled at (≥ 10).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        float
            The peak jerk [m/s³].

        Raises
        ------
        InputError
            If ``speed`` is not a finite number or pair, or ``n`` is out of range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
        >>> round(p.max_jerk(0.2), 3)                    # m/s³
        1.584
        """
        return self.acceleration(speed, n, n_threads=n_threads).max_jerk

    def __repr__(self) -> str:
        return (
            f"TransferPath(R_t={self.R_t!r}, R_p={self.R_p!r}, centre_t={self.centre_t.tolist()}, "
            f"centre_p={self.centre_p.tolist()}, x2=({self.x2_t:.6g}, {self.x2_p:.6g}), "
            f"ccw={self.ccw})"
        )


def _sample_out(out: Any, n: int) -> list[Any]:
    """The arrays of ``out`` (a :class:`PathSample`) for a sample of ``n`` points
    written in place, checked by the rule of every ``out=`` (``out_array``): each
    writeable, C-contiguous, of the sample's shape and type, sharing no memory
    with another; anything else is an :class:`InputError` naming the field."""
    out = instance("out", out, PathSample)
    fields = ("points", "s", "heading", "curvature", "curvature_rate", "piece")
    arrays = [getattr(out, f) for f in fields]
    for f, a in zip(fields, arrays, strict=True):
        if f == "piece":
            ok = isinstance(a, np.ndarray) and a.dtype == np.int8 and a.shape == (n,)
            if not (ok and a.flags.c_contiguous and a.flags.writeable):
                raise InputError(
                    f"out.piece must be a writeable C-contiguous int8 array of shape ({n},); "
                    f"got {type(a).__name__} {getattr(a, 'dtype', '')} {getattr(a, 'shape', '')}"
                )
            continue
        try:
            out_array(a, (n, 2) if f == "points" else (n,), [], f"the sample's {f}")
        except InputError as e:
            raise InputError(f"out.{f}: {e}") from None
    for i, a in enumerate(arrays):
        for j in range(i):
            if np.shares_memory(a, arrays[j]):
                raise InputError(
                    f"out.{fields[i]} shares memory with out.{fields[j]}: each array of "
                    "the sample must be its own"
                )
    return arrays


def _allocate(n: int, lengths: Array) -> list[int]:
    """Points per piece: ≥ 2 each (an empty piece gets 2 at one place), the rest
    in proportion to length; the last piece takes the end point too."""
    free = n - 2 * len(lengths)
    share = free * lengths / lengths.sum()
    extra = np.floor(share).astype(int)
    rest = free - int(extra.sum())
    extra[np.argsort(share - extra)[::-1][:rest]] += 1
    return [2 + int(e) for e in extra]


def _speed_law(speed: Any, start: float, span: float) -> Any:
    """s ↦ (v, dv/ds, d²v/ds²) for a constant speed or a (V_t, V_p) pair."""
    v_t, v_p = _speeds(speed)

    def law(s: Any) -> tuple[Array, Array, Array]:
        s = np.asarray(s, dtype=np.float64)
        u = np.clip((s - start) / span, 0.0, 1.0)
        inside = (s > start) & (s < start + span)
        h = u**3 * (10.0 - 15.0 * u + 6.0 * u * u)
        dh = np.where(inside, 30.0 * u * u * (1.0 - u) ** 2 / span, 0.0)
        ddh = np.where(inside, 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / span**2, 0.0)
        dv = v_p - v_t
        return v_t + dv * h, dv * dh, dv * ddh

    return law


def _longest(r: Array, c_t: Array, c_p: Array, ratio: Array) -> Array:
    """The longest transitions in proportions ``ratio`` (x2 = λ·ratio) whose
    straight segment is not negative: λ on 257 geometric points, then eight
    refinements on 65 even points of the last bracket (the straight length falls
    as λ grows), in Rust."""
    d = float(np.hypot(*(c_p - c_t)))
    radii = (float(r[0]), float(r[1]))
    got = _core.transfer_longest(radii, d, (float(ratio[0]), float(ratio[1])))
    if got is None:
        raise InfeasibleError("no transition fits between these rotors")
    return np.array(got)
