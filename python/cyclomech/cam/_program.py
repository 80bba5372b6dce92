"""The cam program and its solution: `_program` part of :mod:`cyclomech.cam`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, float_array, positive, threads_arg
from .._errors import InputError
from ..motion import NAMES
from ._followers import FlatFaced, OscillatingRoller, TranslatingRoller

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
    """One segment of a cam program: ``kind`` "rise", "dwell" or "return" over
    ``angle_deg`` [deg] of cam rotation, with ``stroke`` [m] (or [rad] for an
    oscillating follower; 0 for a dwell) following ``law`` (a name of
    :data:`cyclomech.motion.NAMES`, taken in its full rise form). ``operation``
    optionally names the cyclogram operation the segment is bound to (stored
    only, for now).

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
    """The exact kinematics and geometry of a cam at cam angles ``theta`` [rad]
    (every array has the shape of ``theta``, points one more axis of 2; the
    arrays are views into one block the kernel filled):

    * ``s``, ``ds``, ``dds``, ``ddds``: follower displacement [m, or rad for an
      oscillating follower] and its 1st–3rd derivatives per radian of cam;
    * ``pitch``: roller centre (flat face: the face's point on the follower's
      axis) [m] in the cam frame; ``profile``: the contact point on the cam [m];
      ``profile_outer``: the groove's outer flank [m] (``None`` for spring closure);
    * ``pressure_angle`` [rad]: from the follower's direction of motion to the
      contact normal, signed (translating roller: tan φ = (s′ − e)/(s + √(R_p² − e²)));
    * ``pitch_radius_of_curvature``, ``profile_radius_of_curvature`` [m]: signed,
      + convex, − concave, ``inf`` where straight (the profile's is the inner flank);
    * ``undercut``: where the profile cusps (a convex pitch curve tighter than
      the roller, or for a groove's outer flank a concave one; flat face:
      R_b + s + s″ < 0).

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
    """A disc cam: ``segments`` (:class:`Segment` s summing to 360°, the
    displacement returning to its start), a ``follower``
    (:class:`TranslatingRoller`, :class:`FlatFaced` or :class:`OscillatingRoller`)
    and its ``closure``: "spring" (force closure, one flank) or "groove" (form
    closure, both flanks; roller followers only). Invalid input raises
    :class:`cyclomech.InputError` naming the segment (index and kind), the value
    and what is valid.

    >>> import cyclomech as cm
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

    __slots__ = ("_kernel", "closure", "follower", "segments")

    def __init__(
        self,
        segments: Any,
        follower: TranslatingRoller | FlatFaced | OscillatingRoller,
        closure: str = "spring",
    ) -> None:
        segs = tuple(segments)
        if not segs:
            raise InputError("segments must hold at least one Segment")
        for i, g in enumerate(segs):
            if not isinstance(g, Segment):
                raise InputError(f"segment {i} must be a cyclomech.cam.Segment; got {g!r}")
        if not isinstance(follower, TranslatingRoller | FlatFaced | OscillatingRoller):
            raise InputError(
                "follower must be a TranslatingRoller, FlatFaced or OscillatingRoller; "
                f"got {follower!r}"
            )
        if closure not in _CLOSURES:
            raise InputError(f"closure must be one of {_CLOSURES}; got {closure!r}")
        if closure == "groove" and isinstance(follower, FlatFaced):
            raise InputError("closure 'groove' needs a roller follower, not FlatFaced")
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
        )
        self.segments = segs
        self.follower = follower
        self.closure = closure

    def solve(self, theta: Any, *, n_threads: int | None = None) -> CamKinematics:
        """The exact kinematics and geometry at cam angles ``theta`` [rad] (any
        shape; taken modulo 2π) in one Rust call with the GIL released: see
        :class:`CamKinematics`.

        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
        ...                  cm.cam.TranslatingRoller(0.05, 0.01))
        >>> k = cam.solve(np.linspace(0, 2 * np.pi, 7).reshape(7, 1))
        >>> k.s.shape, k.profile.shape, round(float(k.s[3, 0]), 12)
        ((7, 1), (7, 1, 2), 0.02)
        """
        # (A bool or a string is not an angle; any number of dimensions.)
        t = float_array("theta", theta, ndims=tuple(range(33)))
        shape = np.shape(theta)  # (float_array makes a 0-d input 1-d)
        rows = self._kernel.solve(t.reshape(-1), n_threads=threads_arg(n_threads))

        # Views into the kernel's one (N, 14) block: no copies.
        def col(i: int) -> npt.NDArray[np.float64]:
            return rows[:, i].reshape(shape)

        def pts(i: int) -> npt.NDArray[np.float64]:
            return rows[:, i : i + 2].reshape(*shape, 2)

        return CamKinematics(
            theta=t.reshape(shape).copy(),  # (not a view of the caller's array)
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
            undercut=col(13) != 0.0,
        )

    @property
    def initial_arm_angle_deg(self) -> float | None:
        """ψ0 [deg] of an oscillating follower (None for a translating one).

        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 180, 0.2), S("return", 180, 0.2)],
        ...                  cm.cam.OscillatingRoller(0.1, 0.1, 0.04, 0.0))
        >>> round(cam.initial_arm_angle_deg, 6)
        23.073918
        """
        psi0 = self._kernel.initial_arm_angle
        return None if psi0 is None else math.degrees(psi0)

    def undercut_angles_deg(self, samples: int = 7200) -> list[tuple[float, float]]:
        """Runs of cam angles [deg] where the profile is undercut, as (first,
        last) sampled angles on a grid of ``samples`` points over one turn; an
        empty list when the profile is sound.

        >>> import cyclomech as cm
        >>> S = cm.cam.Segment
        >>> cam = cm.cam.Cam([S("rise", 30, 0.05), S("return", 330, 0.05)],
        ...                  cm.cam.TranslatingRoller(0.02, 0.015))
        >>> runs = cam.undercut_angles_deg(3600)
        >>> len(runs) > 0 and 0 <= runs[0][0] < runs[0][1] < 30
        True
        """
        if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 2:
            raise InputError(f"samples must be an integer >= 2; got {samples!r}")
        deg = np.arange(int(samples)) * (360.0 / samples)
        flags = self.solve(np.radians(deg)).undercut
        runs: list[tuple[float, float]] = []
        start = None
        for i, f in enumerate(flags):
            if f and start is None:
                start = i
            if not f and start is not None:
                runs.append((float(deg[start]), float(deg[i - 1])))
                start = None
        if start is not None:
            runs.append((float(deg[start]), float(deg[-1])))
        return runs


def _check_program(segs: tuple[Segment, ...]) -> None:
    """Each error names the segment (index and kind), the value and what is valid."""
    net, scale, total = 0.0, 0.0, 0.0
    for i, g in enumerate(segs):
        where = f"segment {i} ({g.kind})"
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
