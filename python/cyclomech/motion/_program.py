"""Motion programs (VDI 2143): `_program` part of :mod:`cyclomech.motion` (its door)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number, float_array, instances, positive, threads_arg
from .._errors import CyclomechWarning, InputError

__all__ = [
    "CONTINUITY",
    "SEGMENT_LAWS",
    "Characteristics",
    "MotionValues",
    "Program",
    "Segment",
]

#: The laws a :class:`Segment` takes.
SEGMENT_LAWS = tuple(_core.SEGMENT_LAWS)
#: The orders a :class:`Program` can ask its joins to be continuous to.
CONTINUITY = ("position", "velocity", "acceleration", "jerk")

_Ends = tuple[float | None, float | None, float | None, float | None]


def _ends(name: str, value: Any) -> _Ends:
    """None, a position, or up to four values (s, v, a, j), each a number or None."""
    if value is None:
        return (None, None, None, None)
    if isinstance(value, int | float) and not isinstance(value, bool):
        value = (value,)
    if isinstance(value, str) or not isinstance(value, Sequence) or not 1 <= len(value) <= 4:
        raise InputError(
            f"{name} must be None, a position or a tuple (s, v, a, j) of 1 to 4 numbers "
            f"or None (v, a, j per rad of master); got {value!r}"
        )
    out = [
        None if v is None else finite_number(f"{name}[{k}]", v, "[m or rad per rad^k]")
        for k, v in enumerate(value)
    ]
    return (*out, *([None] * (4 - len(out))))  # type: ignore[return-value]


@dataclass(frozen=True)
class Segment:
    """One segment of a motion program: a law over a master angle between end values.

    End values are position s [m, or rad for a rotary axis], velocity v = ds/dθ,
    acceleration a = d²s/dθ² and jerk j = d³s/dθ³, per radian of master (the main
    shaft), so that a program does not depend on the machine's speed. A value left
    ``None`` is free and resolved by one rule: a free start value is the previous
    segment's end value (0 for the first segment); a free end value is what the next
    segment (the first, after the last) fixes at its start (a value given there, a
    dwell's rest, a constant velocity's speed), else 0. A value given that the law
    cannot meet is an error naming the segment and the value. Each parameter is kept
    as the attribute of the same name (``start`` and ``end`` as 4-tuples, ``points``
    as a tuple of pairs).

    The laws (:data:`SEGMENT_LAWS`; the math is in the guide, *Motion programs*):

    - ``"dwell"``; ``"constant_velocity"`` (its velocity: ``start`` or ``end`` v, or
      from the end position, else the velocity it starts with);
    - ``"cycloidal"``, ``"harmonic"``, ``"modified_sine"``, ``"modified_trapezoid"``:
      rest to rest, or with moving ends (the velocity change carried by the law's
      shape); ``"polynomial_345"``, ``"polynomial_4567"``: rest to rest only;
    - ``"poly5"`` / ``"poly7"``: through s, v, a (and j) at both ends;
    - ``"polynomial"``: through exactly the values given (degree = their count − 1);
    - ``"spline"``: through ``points`` (C2 cubic, or C4 quintic with ``degree=5``);
      ends given or natural, or periodic for one segment over the whole cycle with
      free ends (about the line from its first to its last value: the advance).

    Parameters
    ----------
    law : str
        One of :data:`SEGMENT_LAWS`.
    angle_deg : float
        The master angle the segment lasts [deg] (> 0).
    start, end : float or tuple, optional
        Its values at each end: a position, or (s, v, a, j) with any entry None
        (free); default None (all free). A motion law needs its end position.
    points : sequence of (float, float), optional
        A spline's table: (angle from the segment's start [deg], s), the first at 0,
        the last at ``angle_deg``; default None.
    degree : {3, 5}, default 3
        A spline's degree.
    operation : str, optional
        The cyclogram operation the segment is bound to; default None.

    Raises
    ------
    InputError
        If ``law`` is unknown, ``angle_deg`` is not > 0, an end value is not a
        number or None, or ``points`` is not a table of pairs.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.motion.Segment("constant_velocity", 60, start=(0.0, 0.02)).start
    (0.0, 0.02, None, None)
    >>> cm.motion.Segment("cycloid", 60, end=0.01)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: law must be one of ('dwell', ...); got 'cycloid'
    """

    law: str
    angle_deg: float
    start: Any = None
    end: Any = None
    points: Any = None
    degree: int = 3
    operation: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.law, str) or self.law not in SEGMENT_LAWS:
            raise InputError(f"law must be one of {SEGMENT_LAWS}; got {self.law!r}")
        object.__setattr__(self, "angle_deg", positive("angle_deg", self.angle_deg, "[deg]"))
        object.__setattr__(self, "start", _ends("start", self.start))
        object.__setattr__(self, "end", _ends("end", self.end))
        object.__setattr__(self, "degree", count("degree", self.degree, low=3, high=5))
        if self.points is not None:
            table = float_array("points", self.points, ndims=(2,))
            if table.shape[1] != 2 or len(table) < 2:
                raise InputError(
                    "points must be a table of at least 2 pairs (angle from the segment's "
                    f"start [deg], s); got shape {table.shape}"
                )
            object.__setattr__(self, "points", tuple(map(tuple, table.tolist())))
        if self.operation is not None and not isinstance(self.operation, str):
            raise InputError(f"operation must be None or a name; got {self.operation!r}")


def _shifted(segments: Any, continuity: str, advance: float, shift: float) -> Program:
    """A program s + shift·s″ rebuilt from its parts (unpickling)."""
    return Program(segments, continuity="position", advance=advance).plus_second_derivative(
        shift, continuity
    )


@dataclass(frozen=True)
class MotionValues:
    """A program evaluated: position and derivatives per radian of master.

    Built by :meth:`Program.evaluate`; each parameter is kept as the attribute of the
    same name, every array of the shape of ``theta``.

    Parameters
    ----------
    theta : ndarray of float
        Master angles [rad].
    s : ndarray of float
        Position [m, or rad for a rotary axis].
    v, a, j : ndarray of float
        ds/dθ, d²s/dθ², d³s/dθ³ [per rad, rad², rad³ of master]; at ω [rad/s] the
        slave's velocity is v·ω, its acceleration a·ω², its jerk j·ω³.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.motion.Segment
    >>> p = cm.motion.Program([S("cycloidal", 180, end=0.1), S("cycloidal", 180, end=0.0)])
    >>> round(float(p.evaluate(np.pi / 2).s), 12)
    0.05
    """

    theta: npt.NDArray[np.float64]
    s: npt.NDArray[np.float64]
    v: npt.NDArray[np.float64]
    a: npt.NDArray[np.float64]
    j: npt.NDArray[np.float64]


@dataclass(frozen=True)
class Characteristics:
    """A segment's peaks and characteristic values (VDI 2143).

    With h its stroke and β its angle [rad]: C_v = max ``|v|``·β/``|h|``, C_a = max
    ``|a|``·β²/``|h|``, C_j = max ``|j|``·β³/``|h|``, C_m = max ``|v·a|``·β³/h² (NaN where
    h = 0). Each parameter is
    kept as the attribute of the same name.

    Parameters
    ----------
    stroke : float
        h = end − start position [m or rad].
    v_max, a_max, j_max : float
        max |v|, |a|, |j| over the segment [per rad^k of master].
    cv, ca, cj, cm : float
        The dimensionless characteristic values.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.motion.Segment
    >>> p = cm.motion.Program([S("modified_sine", 90, end=1.0), S("modified_sine", 270, end=0.0)])
    >>> c = p.characteristics[0]
    >>> round(c.cv, 3), round(c.ca, 3)
    (1.76, 5.528)
    """

    stroke: float
    v_max: float
    a_max: float
    j_max: float
    cv: float
    ca: float
    cj: float
    cm: float


class Program:
    """A motion program: segments over one master cycle (360°), joins checked.

    Free end values are resolved (see :class:`Segment`), values given are checked
    against each law, the angles must sum to 360° and every join — the last segment
    back to the first across ``advance`` — must be continuous up to ``continuity``;
    a join that is not raises naming both segments, the angle and the jump.
    Evaluation is exact (closed form per piece) and in one Rust call. Each parameter
    is kept as the attribute of the same name (``segments`` as a tuple).

    Parameters
    ----------
    segments : sequence of Segment
        The segments in order from master angle 0.
    continuity : {"position", "velocity", "acceleration", "jerk"}, default "velocity"
        The highest derivative every join must keep continuous.
    advance : float, default 0.0
        Position gained per cycle [m or rad]: 0 for a cam or a reciprocating axis,
        the feed length of a film feed, 2π for a rotating knife.

    Attributes
    ----------
    shift : float
        c [rad²]: this program is the motion s + c·s″ of its segments (a polydyne
        cam's, see :func:`cyclomech.cam.polydyne`); 0 for a plain program.

    Raises
    ------
    InputError
        If a segment is not a :class:`Segment`, a law cannot meet a value given, the
        angles do not sum to 360° or a join jumps.

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.motion.Segment
    >>> p = cm.motion.Program([S("constant_velocity", 120, start=(0, 0.05)),
    ...                        S("cycloidal", 240, end=(0.05 * 2 * np.pi, 0.05))],
    ...                       advance=0.05 * 2 * np.pi)
    >>> round(float(p.evaluate(1.0).v), 12)
    0.05
    >>> cm.motion.Program([S("harmonic", 90, end=0.1), S("dwell", 90), S("harmonic", 180, end=0.0)],
    ...                   continuity="acceleration")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: segment 1 (harmonic) → segment 2 (dwell) at 90°: the ...
    """

    __slots__ = ("_kernel", "advance", "continuity", "segments", "shift")

    def __init__(self, segments: Any, continuity: str = "velocity", advance: float = 0.0) -> None:
        segs = tuple(instances("segments", segments, Segment))
        if continuity not in CONTINUITY:
            raise InputError(f"continuity must be one of {CONTINUITY}; got {continuity!r}")
        adv = finite_number("advance", advance, "[m or rad]")
        nan = float("nan")
        ends = np.array(
            [[nan if v is None else v for v in (*g.start, *g.end)] for g in segs], dtype=float
        ).reshape(len(segs), 8)
        self._kernel = _core.ProgramKernel(
            [g.law for g in segs],
            np.radians([g.angle_deg for g in segs]),
            np.ascontiguousarray(ends[:, :4]),
            np.ascontiguousarray(ends[:, 4:]),
            [[(math.radians(x), y) for x, y in (g.points or ())] for g in segs],
            [g.degree for g in segs],
            CONTINUITY.index(continuity),
            adv,
        )
        self.segments = segs
        self.continuity = continuity
        self.advance = adv
        self.shift = 0.0
        for i, row in enumerate(self._kernel.spans):
            if row[5] is not None:
                at, v = row[5]
                warnings.warn(
                    f"segment {i + 1} ({segs[i].law}) runs backwards: v = {v:.4g} per rad at "
                    f"{math.degrees(at):.4g}°, against its stroke; its stroke is short for "
                    "its end velocities (lengthen it, or shorten the angle)",
                    CyclomechWarning,
                    stacklevel=2,
                )

    def __reduce__(self) -> tuple[Any, ...]:
        # Rebuilt from its parts (the kernel is not picklable): Dask ships programs.
        if self.shift:
            return (_shifted, (self.segments, self.continuity, self.advance, self.shift))
        return (Program, (self.segments, self.continuity, self.advance))

    def plus_second_derivative(self, c: float, continuity: str = "velocity") -> Program:
        """The program s + c·s″ (c [rad²]): a polydyne cam's motion, joins checked.

        Each piece stays a polynomial plus a sine (closed form). The new program is
        continuous to ``continuity`` only where this one is two orders higher; a
        join that jumps raises, naming it. :func:`cyclomech.cam.polydyne` calls it
        with c = m·ω²/k.

        Parameters
        ----------
        c : float
            The factor of s″ [rad²].
        continuity : {"position", "velocity", "acceleration", "jerk"}, default "velocity"
            The order every join of the new program must keep continuous.

        Returns
        -------
        Program
            The new program, its ``shift`` = ``c``.

        Raises
        ------
        InputError
            If this program is already shifted, ``c`` is not finite, ``continuity``
            is not a name of :data:`CONTINUITY` or a join jumps.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> p = cm.motion.Program([S("poly7", 180, end=0.1), S("poly7", 180, end=0.0)])
        >>> q = p.plus_second_derivative(0.01, "velocity")
        >>> m, n = p.evaluate(1.0), q.evaluate(1.0)
        >>> bool(abs(n.s - (m.s + 0.01 * m.a)) < 1e-15), q.shift
        (True, 0.01)
        """
        if continuity not in CONTINUITY:
            raise InputError(f"continuity must be one of {CONTINUITY}; got {continuity!r}")
        if self.shift:
            raise InputError("this program is already a polydyne motion (shift ≠ 0)")
        shift = finite_number("c", c, "[rad²]")
        kernel = self._kernel.plus_second_derivative(shift, CONTINUITY.index(continuity))
        out = object.__new__(Program)
        out._kernel = kernel
        out.segments = self.segments
        out.continuity = continuity
        out.advance = self.advance
        out.shift = shift
        return out

    def __repr__(self) -> str:
        laws = ", ".join(f"{g.law} {g.angle_deg:g}°" for g in self.segments)
        return f"Program([{laws}], continuity={self.continuity!r}, advance={self.advance!r})"

    def evaluate(self, theta: Any, *, n_threads: int | None = None) -> MotionValues:
        """Position and its derivatives at master angles ``theta``, in one Rust call.

        Parameters
        ----------
        theta : array_like of float
            Master angles [rad], any shape; an angle outside [0, 2π) is the cycle's
            angle plus ``advance`` per whole cycle.
        n_threads : int, optional
            Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        MotionValues
            ``s`` [m or rad] and ``v``, ``a``, ``j`` per rad^k of master.

        Raises
        ------
        InputError
            If ``theta`` is not an array of finite numbers.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> p = cm.motion.Program([S("poly5", 180, end=(1.0, 0.0, 0.0)),
        ...                        S("poly5", 180, end=0.0)])
        >>> m = p.evaluate(np.linspace(0, np.pi, 3))
        >>> m.s.round(12).tolist()
        [0.0, 0.5, 1.0]
        """
        t = float_array("theta", theta, ndims=tuple(range(33)))
        shape = np.shape(theta)
        # The kernel copies θ as it reads it: cheaper than a copy here, which
        # would read the angles a second time.
        copy, rows = self._kernel.eval_with_theta(t.reshape(-1), n_threads=threads_arg(n_threads))
        s, v, a, j = (rows[k].reshape(shape) for k in range(4))
        return MotionValues(theta=copy.reshape(shape), s=s, v=v, a=a, j=j)

    @property
    def characteristics(self) -> tuple[Characteristics, ...]:
        """Each segment's peaks and characteristic values (see :class:`Characteristics`).

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> p = cm.motion.Program([S("cycloidal", 180, end=0.1), S("cycloidal", 180, end=0.0)])
        >>> round(p.characteristics[1].cv, 12)
        2.0
        """
        return tuple(
            Characteristics(*self._kernel.characteristics(i)) for i in range(len(self.segments))
        )

    @property
    def kernel(self) -> Any:
        """The compiled program, as the Rust kernels of other domains take it.

        A cam (:class:`cyclomech.cam.Cam`) and a servo axis hand it to their own
        kernels, which read each segment's law there instead of rebuilding it.

        Examples
        --------
        >>> import cyclomech as cm
        >>> p = cm.motion.Program([cm.motion.Segment("dwell", 360)])
        >>> type(p.kernel).__name__
        'ProgramKernel'
        """
        return self._kernel

    @property
    def scalable(self) -> tuple[bool, ...]:
        """Per segment: does its shape stay the same when its angle changes?

        True for a rest-to-rest segment of a named law or a polynomial (the same law
        stretched: what a cam's minimum phase angle assumes) and a dwell; False for
        moving ends, a constant velocity and a spline (its table is in angles).

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> cm.motion.Program([S("poly5", 180, end=0.1), S("cycloidal", 90, end=(0.02, -0.02)),
        ...                    S("poly5", 90, end=0.0)]).scalable
        (True, False, False)
        """
        return tuple(bool(row[4]) for row in self._kernel.spans)

    @property
    def boundaries(self) -> tuple[tuple[float, float, tuple[float, ...], tuple[float, ...]], ...]:
        """Each segment as built: (start [deg], angle [deg], (s, v, a, j) at its start, at its end).

        Free values resolved; v, a, j per rad^k of master.

        Examples
        --------
        >>> import cyclomech as cm
        >>> S = cm.motion.Segment
        >>> p = cm.motion.Program([S("constant_velocity", 90, start=(0, 0.1)),
        ...                        S("poly5", 270, end=(0.0, 0.1))])
        >>> round(p.boundaries[1][2][1], 12)  # v at the poly5's start: the previous one's
        0.1
        """
        return tuple(
            (math.degrees(b), math.degrees(w), tuple(s0), tuple(s1))
            for b, w, s0, s1, *_ in self._kernel.spans
        )
