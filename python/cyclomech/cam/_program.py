"""The cam program and its solution: `_program` part of :mod:`cyclomech.cam`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number, float_array, instances, positive, threads_arg
from .._errors import InputError
from .._notebook import data_frame, figure_of, html_card, pandas
from ..motion import NAMES, Program
from . import _loads
from ._followers import FlatFaced, OscillatingRoller, TranslatingRoller
from ._loads import CamLoads, Contact, FollowerLoads, MinPhaseAngles

if TYPE_CHECKING:
    from ..shaft import ShaftTorque

__all__ = ["KINDS", "Cam", "CamKinematics", "Segment"]

#: The kinds of segment.
KINDS = ("rise", "dwell", "return")
_CLOSURES = ("spring", "groove")
#: Tolerance on the segments' angles summing to 360° [deg] (relative 1e-9).
_ANGLE_TOL = 360e-9
#: Relative tolerance on the displacement returning to its start.
_CLOSE_TOL = 1e-12


@dataclass(frozen=True)
class Segment:
    """One segment of a cam program: a rise, dwell or return over a cam angle.

    Each parameter is kept as the attribute of the same name (``angle_deg`` and
    ``stroke`` as floats).

    Parameters
    ----------
    kind : {"rise", "dwell", "return"}
        The segment's kind.
    angle_deg : float
        The cam rotation over which it lasts [deg] (> 0).
    stroke : float, default 0.0
        Its stroke [m] (or [rad] for an oscillating follower; 0 for a dwell).
    law : str, default "cycloidal"
        The motion law, a name of ``cyclomech.motion.NAMES``, taken in its full
        rise form.
    operation : str, optional
        The cyclogram operation the segment is bound to (stored only, for now);
        default None.

    Raises
    ------
    InputError
        If ``kind`` is not one of ``cyclomech.cam.KINDS``, ``angle_deg`` is not > 0,
        ``stroke`` is negative or not finite, ``law`` is not a string or
        ``operation`` is neither None nor a string.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.cam.Segment("rise", 90, 0.01, law="modified_sine").law
    'modified_sine'
    >>> cm.cam.Segment("lift", 90, 0.01)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: kind must be one of ('rise', 'dwell', 'return'); got 'lift'
    """

    kind: str
    angle_deg: float
    stroke: float = 0.0
    law: str = "cycloidal"
    operation: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError(f"kind must be one of {KINDS}; got {self.kind!r}")
        angle = positive("angle_deg", self.angle_deg, "[deg]")
        stroke = finite_number("stroke", self.stroke, "[m or rad]", low=0.0)
        if not isinstance(self.law, str):
            raise InputError(f"law must be a name of cyclomech.motion.NAMES; got {self.law!r}")
        if self.operation is not None and not isinstance(self.operation, str):
            raise InputError(f"operation must be None or a name; got {self.operation!r}")
        object.__setattr__(self, "angle_deg", angle)
        object.__setattr__(self, "stroke", stroke)


@dataclass(frozen=True)
class CamKinematics:
    """The exact kinematics and geometry of a cam at cam angles ``theta``.

    Every array has the shape of ``theta``, points one more axis of 2; the arrays
    are views into one block the kernel filled. Built by :meth:`Cam.solve`; each
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    theta : ndarray of float
        The cam angles [rad].
    s : ndarray of float
        The follower displacement [m, or rad for an oscillating follower].
    ds : ndarray of float
        Its 1st derivative per radian of cam, s′ [m/rad, or rad/rad].
    dds : ndarray of float
        Its 2nd derivative per radian of cam, s″ [m/rad², or rad/rad²].
    ddds : ndarray of float
        Its 3rd derivative per radian of cam, s‴ [m/rad³, or rad/rad³].
    pitch : ndarray of float, shape (..., 2)
        The roller centre (flat face: the face's point on the follower's axis) [m]
        in the cam frame.
    profile : ndarray of float, shape (..., 2)
        The contact point on the cam [m].
    profile_outer : ndarray of float, shape (..., 2) or None
        The groove's outer flank [m] (None for spring closure).
    pressure_angle : ndarray of float
        From the follower's direction of motion to the contact normal [rad], signed
        (translating roller: tan φ = (s′ − e)/(s + √(R_p² − e²))).
    pitch_radius_of_curvature : ndarray of float
        The pitch curve's radius of curvature [m]: signed, + convex, − concave,
        ``inf`` where straight.
    profile_radius_of_curvature : ndarray of float
        The profile's (the inner flank's) radius of curvature [m], signed as the
        pitch curve's.
    undercut : ndarray of bool
        Where the profile cusps (a convex pitch curve tighter than the roller, or
        for a groove's outer flank a concave one; flat face: R_b + s + s″ < 0).

    Examples
    --------
    >>> import cyclomech as cm
    >>> cam = cm.cam.Cam([cm.cam.Segment("rise", 180, 0.01), cm.cam.Segment("return", 180, 0.01)],
    ...                  cm.cam.FlatFaced(0.04))
    >>> float(cam.solve(0.0).pressure_angle)
    0.0
    """

    theta: npt.NDArray[np.float64]
    s: npt.NDArray[np.float64]
    ds: npt.NDArray[np.float64]
    dds: npt.NDArray[np.float64]
    ddds: npt.NDArray[np.float64]
    pitch: npt.NDArray[np.float64]
    profile: npt.NDArray[np.float64]
    profile_outer: npt.NDArray[np.float64] | None
    pressure_angle: npt.NDArray[np.float64]
    pitch_radius_of_curvature: npt.NDArray[np.float64]
    profile_radius_of_curvature: npt.NDArray[np.float64]
    undercut: npt.NDArray[np.bool_]


class Cam:
    """A disc cam: its segments, its follower and its closure.

    Invalid input raises :class:`cyclomech.InputError` naming the segment (index and
    kind), the value and what is valid. Each parameter is kept as the attribute of
    the same name (``segments`` as a tuple).

    Parameters
    ----------
    segments : sequence of Segment, or cyclomech.motion.Program
        The program: segments (:class:`Segment`) whose angles sum to 360°, the displacement
        returning to its start; or (here or as ``program=``) any motion program
        (:class:`cyclomech.motion.Program`,
        moving ends, polynomials, splines) that starts at s = 0 and returns to it
        (``advance`` 0), each moving segment with a net stroke. Its segments are then
        summarised as :class:`Segment` s in ``segments`` (kind by the stroke's sign,
        ``law`` the motion law's name) and the program kept as ``program``.
    follower : TranslatingRoller or FlatFaced or OscillatingRoller
        The follower.
    closure : {"spring", "groove"}, default "spring"
        "spring" (force closure, one flank) or "groove" (form closure, both flanks;
        roller followers only).
    program : cyclomech.motion.Program, optional
        The motion program by keyword (``Cam(program=prog, follower=…)``) instead of
        ``segments``; default None.

    Raises
    ------
    InputError
        If there is no segment, an item is not a :class:`Segment`, the follower or
        the closure is not one of the above, a groove has a flat-faced follower, a
        dwell has a stroke or a rise or return none, a law is unknown, the angles do
        not sum to 360° or the displacement does not return to its start.

    Examples
    --------
    A velocity–velocity program: a constant-velocity stretch between two transitions.

    >>> import cyclomech as cm
    >>> M = cm.motion.Segment
    >>> prog = cm.motion.Program([M("cycloidal", 90, end=(0.01, 0.01)),
    ...                           M("constant_velocity", 90),
    ...                           M("cycloidal", 60, end=0.032), M("poly5", 120, end=0.0)])
    >>> cam = cm.cam.Cam(program=prog, follower=cm.cam.TranslatingRoller(0.05, 0.01))
    >>> [g.kind for g in cam.segments], round(float(cam.solve(math.pi / 2 + 0.3).ds), 12)
    (['rise', 'rise', 'rise', 'return'], 0.01)

    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
    >>> round(float(cam.solve(math.radians(150)).pitch_radius_of_curvature), 12)
    0.08
    >>> cm.cam.Cam([S("rise", 180, 0.02), S("return", 170, 0.02)],
    ...            cm.cam.FlatFaced(0.05))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: the segments' angles sum to 350.0°, not 360° ...
    """

    __slots__ = ("_kernel", "closure", "follower", "program", "segments")

    def __init__(
        self,
        segments: Any = None,
        follower: TranslatingRoller | FlatFaced | OscillatingRoller | None = None,
        closure: str = "spring",
        *,
        program: Program | None = None,
    ) -> None:
        if program is not None:
            if segments is not None:
                raise InputError("give the cam's segments or its program=, not both")
            if not isinstance(program, Program):
                raise InputError(f"program must be a cyclomech.motion.Program; got {program!r}")
            segments = program
        if segments is None or follower is None:
            raise InputError("a Cam needs its segments (or program=) and its follower")
        program = segments if isinstance(segments, Program) else None
        if program is not None:
            segs = _summary(program)
        else:
            segs = tuple(instances("segments", segments, object))  # each a Segment, below
            if not segs:
                raise InputError("segments must hold at least one Segment")
            for i, g in enumerate(segs):
                if not isinstance(g, Segment):
                    raise InputError(f"segment {i + 1} must be a cyclomech.cam.Segment; got {g!r}")
        if not isinstance(follower, TranslatingRoller | FlatFaced | OscillatingRoller):
            raise InputError(
                "follower must be a TranslatingRoller, FlatFaced or OscillatingRoller; "
                f"got {follower!r}"
            )
        if closure not in _CLOSURES:
            raise InputError(f"closure must be one of {_CLOSURES}; got {closure!r}")
        if closure == "groove" and isinstance(follower, FlatFaced):
            raise InputError("closure 'groove' needs a roller follower, not FlatFaced")
        if program is None:
            _check_program(segs)
        kind, params = follower._kernel_args()
        self._kernel = _core.CamKernel(
            [g.kind for g in segs],
            [math.radians(g.angle_deg) for g in segs],
            [g.stroke for g in segs],
            [g.law for g in segs],
            kind,
            params,
            closure == "groove",
            None if program is None else program.kernel,
        )
        self.program = program
        self.segments = segs
        self.follower = follower
        self.closure = closure

    def __reduce__(self) -> tuple[Any, ...]:
        # Rebuilt from its parts (the kernel is not picklable): Dask ships machines.
        program = self.segments if self.program is None else self.program
        return (Cam, (program, self.follower, self.closure))

    def solve(
        self, theta: Any, *, n_threads: int | None = None, out: CamKinematics | None = None
    ) -> CamKinematics:
        """The exact kinematics and geometry at cam angles ``theta``.

        One Rust call with the GIL released.

        Parameters
        ----------
        theta : array_like of float
            The cam angles [rad] (any shape; taken modulo 2π).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
        out : CamKinematics, optional
            A previous result of this method for as many angles, whose arrays are
            overwritten and returned in the new result (a repeated solve then skips
            the first touch of 112 bytes of fresh memory an angle, which costs about
            as much as the arithmetic); bit for bit a fresh solve. Default None
            (new arrays).

        Returns
        -------
        CamKinematics
            The displacement and its derivatives, the pitch curve and profile [m],
            pressure angle [rad], radii of curvature [m] and undercut flags, each of the
            shape of ``theta``.

        Raises
        ------
        InputError
            If ``theta`` is not an array of numbers, or ``out`` is not a result of
            :meth:`solve` for as many angles.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
        ...                  cm.cam.TranslatingRoller(0.05, 0.01))
        >>> k = cam.solve(np.linspace(0, 2 * np.pi, 7).reshape(7, 1))
        >>> k.s.shape, k.profile.shape, round(float(k.s[3, 0]), 12)
        ((7, 1), (7, 1, 2), 0.02)
        >>> again = cam.solve(np.linspace(0, np.pi, 7).reshape(7, 1), out=k)
        >>> np.shares_memory(again.s, k.s), round(float(again.s[6, 0]), 12)
        (True, 0.02)
        """
        # (A bool or a string is not an angle; any number of dimensions.)
        t = float_array("theta", theta, ndims=tuple(range(33)))
        shape = np.shape(theta)  # (float_array makes a 0-d input 1-d)
        if out is not None:
            return self._solve_into(t, shape, out, n_threads)
        # The undercut flags come from the kernel's pass (a pass here over the
        # block's column would read all of it again).
        undercut = np.empty(t.size, dtype=bool)
        rows = self._kernel.solve(
            t.reshape(-1), n_threads=threads_arg(n_threads), undercut=undercut
        )
        # (a copy of the angles: not a view of the caller's array)
        return self._kinematics(rows, shape, t.reshape(shape).copy(), undercut)

    def _kinematics(
        self, block: npt.NDArray[np.float64], shape: tuple[int, ...], theta: Any, undercut: Any
    ) -> CamKinematics:
        """The result as views into the kernel's one (N, 14) block (no copies), with the
        angles and undercut flags given."""

        def col(i: int) -> npt.NDArray[np.float64]:
            return block[:, i].reshape(shape)

        def pts(i: int) -> npt.NDArray[np.float64]:
            return block[:, i : i + 2].reshape(*shape, 2)

        return CamKinematics(
            theta=theta,
            s=col(0),
            ds=col(1),
            dds=col(2),
            ddds=col(3),
            pitch=pts(4),
            profile=pts(6),
            profile_outer=pts(8) if self.closure == "groove" else None,
            pressure_angle=col(10),
            pitch_radius_of_curvature=col(11),
            profile_radius_of_curvature=col(12),
            undercut=np.reshape(undercut, shape),
        )

    def _solve_into(
        self, t: npt.NDArray[np.float64], shape: tuple[int, ...], out: Any, n_threads: int | None
    ) -> CamKinematics:
        """:meth:`solve` into the arrays of ``out``, a previous result."""
        block = getattr(getattr(out, "s", None), "base", None)
        n = t.size
        if not (
            isinstance(out, CamKinematics)
            and isinstance(block, np.ndarray)
            and block.shape == (n, 14)
            and block.dtype == np.float64
            and block.flags.c_contiguous
            and block.flags.writeable
            and out.theta.size == n
            and out.undercut.size == n
            and (out.profile_outer is None) == (self.closure != "groove")
        ):
            got = (
                f"a result for {out.theta.size} angles"
                if isinstance(out, CamKinematics)
                else type(out).__name__
            )
            raise InputError(
                f"out must be a CamKinematics that Cam.solve returned for {n} angles "
                f"(of a cam of the same closure, its arrays writeable); got {got}"
            )
        flags = out.undercut.reshape(-1)
        if not (flags.flags.c_contiguous and flags.flags.writeable and flags.dtype == bool):
            raise InputError(
                "out must be a CamKinematics that Cam.solve returned (its undercut flags "
                "a writeable bool array)"
            )
        if any(np.shares_memory(a, t) for a in (block, out.theta, flags)):
            t = t.copy()  # (solving into the angles' own memory)
        # The kernel copies the angles into out.theta in its pass (θ is then in
        # registers) where that array is one it can write (as Cam.solve made it).
        theta_out = out.theta
        direct = (
            isinstance(theta_out, np.ndarray)
            and theta_out.dtype == np.float64
            and theta_out.flags.c_contiguous
            and theta_out.flags.writeable
        )
        self._kernel.solve(
            t.reshape(-1),
            n_threads=threads_arg(n_threads),
            out=block,
            undercut=flags,
            theta_copy=theta_out.reshape(-1) if direct else None,
        )
        if not direct:
            np.copyto(out.theta.reshape(-1), t.reshape(-1))
        return self._kinematics(block, shape, out.theta.reshape(shape), out.undercut)

    @property
    def initial_arm_angle_deg(self) -> float | None:
        """The initial arm angle ψ0 of an oscillating follower [deg] (None for a translating one).

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.2), S("return", 180, 0.2)],
        ...                  cm.cam.OscillatingRoller(0.1, 0.1, 0.04, 0.0))
        >>> round(cam.initial_arm_angle_deg, 6)
        23.073918
        """
        psi0 = self._kernel.initial_arm_angle
        return None if psi0 is None else math.degrees(psi0)

    def loads(
        self,
        theta: Any,
        rpm: float,
        loads: FollowerLoads,
        contact: Contact | None = None,
        *,
        n_threads: int | None = None,
    ) -> CamLoads:
        """The follower's loads along the cycle at one speed.

        The generalised force, normal force, Hertz stress on the loaded flank (with a
        :class:`Contact`), shaft torque and separation; see :class:`CamLoads` and
        :mod:`cyclomech.cam`. One Rust call, GIL released.

        Parameters
        ----------
        theta : array_like of float
            The cam angles [rad] (any shape).
        rpm : float
            The cam speed [rpm] (one speed).
        loads : FollowerLoads
            The follower's mass, spring and loads.
        contact : Contact, optional
            The Hertz contact; default None (no stress: NaN).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        CamLoads
            The force Q [N, or N·m], normal force [N], Hertz stress [Pa], shaft torque
            [N·m] and separation at ``theta``.

        Raises
        ------
        InputError
            If ``loads`` is not a :class:`FollowerLoads`, ``contact`` not a
            :class:`Contact`, ``rpm`` not one speed > 0 or ``segment_loads`` does not
            hold one load per segment.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
        ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
        >>> ld = cam.loads(np.radians([0.0, 150.0]), 300.0,
        ...                cm.cam.FollowerLoads(1.0, 2000.0, 50.0), cm.cam.Contact(0.01))
        >>> ld.force.tolist(), [round(float(x) / 1e6, 3) for x in ld.contact_stress]
        ([50.0, 90.0], [148.448, 194.364])
        """
        return _loads.solve_loads(self, theta, rpm, loads, contact, n_threads=n_threads)

    def shaft_torque(self, loads: FollowerLoads, samples: int = 3600) -> ShaftTorque:
        """The torque the cam's shaft must supply over one turn [N·m].

        T = Q s′ by the power balance (friction neglected), so
        T = ω²·m s″ s′ + (k s + F0 + F_L) s′ — its ω² part and its static part.

        Parameters
        ----------
        loads : FollowerLoads
            The follower's mass, spring and loads.
        samples : int, default 3600
            The number of cam angles over the turn (≥ 3; cam angle 0 at 0°).

        Returns
        -------
        cyclomech.shaft.ShaftTorque
            The torque on ``samples`` cam angles, its ω² part [N·m·s²] and its static
            part [N·m].

        Raises
        ------
        InputError
            If ``loads`` is not a :class:`FollowerLoads` or ``samples`` is not an
            integer ≥ 3.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
        ...                  cm.cam.TranslatingRoller(0.05, 0.01))
        >>> t = cam.shaft_torque(cm.cam.FollowerLoads(1.0, 2000.0, 50.0))
        >>> s = t.stats(300.0, 0.02)          # a conservative follower: no mean torque
        >>> abs(float(s.mean_torque_nm)) < 1e-9, round(float(s.peak_torque_nm), 3)
        (True, 0.891)
        """
        from ..shaft import ShaftTorque

        if not isinstance(loads, FollowerLoads):
            raise InputError(f"loads must be a cyclomech.cam.FollowerLoads; got {loads!r}")
        n = count("samples", samples, low=3)
        theta = np.arange(n, dtype=np.float64) * (2.0 * math.pi / n)
        kin = self.solve(theta)
        static = self._kernel.loads(theta, 0.0, loads._kernel_args(len(self.segments)))[:, 3]
        inertial = loads.mass * kin.dds * kin.ds
        return ShaftTorque.from_curves(inertial[None, :], static[None, :])

    def jump_rpm(self, loads: FollowerLoads) -> tuple[float, float]:
        """The speed at which a spring-closed follower first leaves the cam, and where.

        The smallest over the cycle of √((k s + F0 + F_L)/(m·(−s″))), each segment's
        minimum found by a bracketed search.

        Parameters
        ----------
        loads : FollowerLoads
            The follower's mass, spring and loads.

        Returns
        -------
        rpm : float
            The jump speed [rpm]: inf for a groove or a massless follower, 0 where the
            spring and loads do not hold the follower even at rest.
        angle_deg : float
            The cam angle where [deg] (nan with an infinite speed).

        Raises
        ------
        InputError
            If ``loads`` is not a :class:`FollowerLoads`.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
        ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
        >>> [round(v, 3) for v in cam.jump_rpm(cm.cam.FollowerLoads(1.0, 2000.0, 50.0))]
        [523.548, 211.526]
        """
        return _loads.solve_jump(self, loads)

    def min_phase_angles(
        self,
        rpm: Any,
        *,
        loads: FollowerLoads | None = None,
        contact: Contact | None = None,
        max_stress: float | None = None,
        max_pressure_angle_deg: float | None = None,
        segments: Any = None,
        vibration: tuple[float, float, float] | None = None,
        n_threads: int | None = None,
    ) -> MinPhaseAngles:
        """The smallest phase angle of each rise and return at each speed, per criterion.

        For each criterion of ``cyclomech.cam.CRITERIA``: the pressure angle ≤
        ``max_pressure_angle_deg``, no undercut, no jump (spring closure, with
        ``loads``), σ_H ≤ ``max_stress`` (with ``loads`` and ``contact``) and, with
        ``vibration``, the follower's residual vibration after the segment ≤ the limit
        (β ≥ τ*·ω/ω_n, :func:`min_vibration_tau`). Each is exact (a bracketed root on
        the segment's worst value, itself refined by Brent's maximiser), the segment's
        start displacement, stroke, law and load kept; all speeds in one Rust call
        (rayon over speeds and segments). See :class:`MinPhaseAngles` for the rule, NaN
        and 0.

        Parameters
        ----------
        rpm : float or array_like of float
            The cam speeds [rpm].
        loads : FollowerLoads, optional
            The follower's mass, spring and loads (for the jump and the stress);
            default None.
        contact : Contact, optional
            The Hertz contact (for the stress); default None.
        max_stress : float, optional
            The largest Hertz stress σ_H [Pa] (needs ``loads`` and ``contact``);
            default None (not a criterion).
        max_pressure_angle_deg : float, optional
            The largest pressure angle [deg], in (0, 90); default None (30°
            translating, 45° oscillating).
        segments : int or sequence of int, optional
            The indices of the rises and returns to bound; default None (all of them).
        vibration : tuple of (float, float, float), optional
            (natural frequency [Hz], damping ratio, amplitude limit [m or rad]);
            default None (not a criterion).
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        MinPhaseAngles
            The angles [deg], shape (speeds, segments, criteria).

        Raises
        ------
        InputError
            If a speed is not > 0, ``loads`` or ``contact`` is of the wrong type,
            ``max_stress`` lacks ``loads`` or ``contact``, ``max_pressure_angle_deg`` is
            not in (0, 90), an index of ``segments`` is not a rise or return, or
            ``vibration`` is malformed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
        ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
        >>> m = cam.min_phase_angles([100.0, 600.0], loads=cm.cam.FollowerLoads(1.0, 2000.0, 50.0),
        ...                          contact=cm.cam.Contact(0.01), max_stress=6e8)
        >>> m.binding[:, 0].tolist(), np.round(m.bound_deg[:, 0], 3).tolist()
        (['pressure_angle', 'jump'], [57.184, 137.523])
        """
        return _loads.solve_min_angles(
            self,
            rpm,
            follower_loads=loads,
            contact=contact,
            max_stress=max_stress,
            max_pressure_angle_deg=max_pressure_angle_deg,
            segments=segments,
            vibration=vibration,
            n_threads=n_threads,
        )

    def undercut_angles_deg(self, samples: int = 7200) -> list[tuple[float, float]]:
        """Runs of cam angles where the profile is undercut [deg].

        Parameters
        ----------
        samples : int, default 7200
            The number of grid points over one turn (≥ 2).

        Returns
        -------
        list of tuple of (float, float)
            Each run's (first, last) sampled angle [deg]; an empty list when the profile
            is sound.

        Raises
        ------
        InputError
            If ``samples`` is not an integer ≥ 2.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 30, 0.05), S("return", 330, 0.05)],
        ...                  cm.cam.TranslatingRoller(0.02, 0.015))
        >>> runs = cam.undercut_angles_deg(3600)
        >>> len(runs) > 0 and 0 <= runs[0][0] < runs[0][1] < 30
        True
        """
        n = count("samples", samples, low=2)
        deg = np.arange(n) * (360.0 / n)
        return _runs(deg, self.solve(np.radians(deg)).undercut)

    def to_pandas(self, samples: int = 3600) -> Any:
        """The cam's exact geometry at ``samples`` cam angles over one turn as a
        pandas DataFrame indexed by ``theta_deg``: the columns of
        :func:`cyclomech.cam.profile_table` (the profile CSV's), lengths in m
        (pandas needed).

        Parameters
        ----------
        samples : int, default 3600
            The number of cam angles over the turn (≥ 3).

        Returns
        -------
        pandas.DataFrame
            One row per cam angle [deg].

        Raises
        ------
        InputError
            If ``samples`` is not an integer ≥ 3.
        ImportError
            If pandas is not installed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
        ...                  cm.cam.TranslatingRoller(0.05, 0.01))
        >>> df = cam.to_pandas(720)
        >>> df.index.name, len(df), round(float(df["s_m"].max()), 12)
        ('theta_deg', 720, 0.02)
        """
        from ._export import profile_table  # here: _export imports this module

        pandas()  # before the work: no table computed for nothing
        return data_frame(profile_table(self, samples), index="theta_deg")

    def _repr_html_(self) -> str:
        """The notebook's view: the follower, the segments, the largest pressure
        angle, the smallest radius of curvature, any undercut, and the drawing."""
        from ._export import profile_table  # here: _export imports this module

        t = profile_table(self, 3600)
        rows: list[tuple[str, Any]] = [
            ("follower", repr(self.follower)),
            ("closure", self.closure),
            ("segments", ", ".join(f"{g.kind} {g.angle_deg:g}°" for g in self.segments)),
            ("largest |pressure angle| [deg]", float(np.max(np.abs(t["pressure_angle_deg"])))),
            (
                "smallest |profile radius of curvature| [m]",
                float(np.nanmin(np.abs(t["profile_curvature_radius_m"]))),
            ),
        ]
        runs = _runs(t["theta_deg"], t["undercut"])  # the table's samples: no second solve
        rows.append(("undercut", ", ".join(f"{a:g}–{b:g}°" for a, b in runs) or "none"))
        return html_card("Cam", rows, figure_of(self))


def _runs(
    deg: npt.NDArray[np.floating[Any]], flags: npt.NDArray[np.bool_]
) -> list[tuple[float, float]]:
    """The (first, last) sampled angle [deg] of each run of ``flags``, from where
    they change.

    >>> _runs(np.arange(6.0), np.array([0, 1, 1, 0, 1, 0], dtype=bool))
    [(1.0, 2.0), (4.0, 4.0)]
    """
    edges = np.diff(np.r_[0, flags.astype(np.int8), 0])
    first, last = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(float(deg[a]), float(deg[b])) for a, b in zip(first, last, strict=True)]


def _summary(program: Program) -> tuple[Segment, ...]:
    """A cam's segments from a motion program (see :class:`Cam`), checked for a cam.

    >>> import cyclomech as cm
    >>> M = cm.motion.Segment
    >>> p = cm.motion.Program([M("poly5", 180, end=0.02), M("dwell", 60), M("poly5", 120, end=0)])
    >>> [(g.kind, g.stroke) for g in _summary(p)]
    [('rise', 0.02), ('dwell', 0.0), ('return', 0.02)]
    """
    if program.advance != 0.0:
        raise InputError(
            f"a cam's program must return to its start: advance = {program.advance!r} "
            "[m or rad] must be 0"
        )
    out = []
    for i, (g, (_, _, s0, s1)) in enumerate(zip(program.segments, program.boundaries, strict=True)):
        if i == 0 and s0[0] != 0.0:
            raise InputError(
                f"a cam's program must start at s = 0 (the displacement from the base "
                f"circle at cam angle 0); segment 1 ({g.law}) starts at s = {s0[0]!r}"
            )
        h = s1[0] - s0[0]
        if g.law == "dwell":
            out.append(Segment("dwell", g.angle_deg, operation=g.operation))
            continue
        if h == 0.0:
            raise InputError(
                f"segment {i + 1} ({g.law}) moves but ends where it starts; a cam's moving "
                "segment needs a net stroke: split it in two"
            )
        kind = "rise" if h > 0 else "return"
        out.append(Segment(kind, g.angle_deg, abs(h), law=g.law, operation=g.operation))
    return tuple(out)


def _check_program(segs: tuple[Segment, ...]) -> None:
    """Each error names the segment (index and kind), the value and what is valid."""
    net, scale, total = 0.0, 0.0, 0.0
    for i, g in enumerate(segs):
        where = f"segment {i + 1} ({g.kind})"
        if g.kind == "dwell":
            if g.stroke != 0.0:
                raise InputError(f"{where}: stroke = {g.stroke!r} must be 0 for a dwell")
            continue
        if g.stroke == 0.0:
            raise InputError(f"{where}: stroke = 0 must be > 0 [m or rad] for a {g.kind}")
        if g.law not in NAMES:
            raise InputError(f"{where}: unknown law {g.law!r}; known laws: {', '.join(NAMES)}")
        net += g.stroke if g.kind == "rise" else -g.stroke
        scale = max(scale, g.stroke)
    total = math.fsum(g.angle_deg for g in segs)
    if abs(total - 360.0) > _ANGLE_TOL:
        raise InputError(
            f"the segments' angles sum to {total!r}°, not 360° "
            f"(angle_deg of segments {[g.angle_deg for g in segs]})"
        )
    if abs(net) > _CLOSE_TOL * scale:
        raise InputError(
            f"the displacement does not return to its start: rises − returns = {net!r} "
            "[m or rad]; it must be 0"
        )
