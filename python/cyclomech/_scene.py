"""A mechanism drawn over a cycle: the data of the machine's animation.

A mechanism kind's result that can be drawn moving has a method
``scene(cycle_deg)`` returning a :class:`Scene`: where every named point of the
mechanism is at each of the main shaft's angles ``cycle_deg`` (put there by the
kind's own solver, at the mechanism's own angle for that cycle angle), which
points the bars and plates join, which are fixed to the frame, and the rigid
outlines (a cam's profile, a roller, a slider's block, a stop) with their pose at
each angle. The machine's report animates these (a canvas and a small script),
:func:`cyclomech.plot.animate_machine` writes them as a GIF, and
:func:`cyclomech.plot.plot_machine_frame` draws one frame. Nothing here
solves: a scene only carries what the solvers gave.

Units: lengths in m, angles in rad (the cycle angles in degrees, as named).

>>> import numpy as np
>>> s = Scene("crank", {"A": np.zeros((2, 2)), "B": np.array([[1.0, 0.0], [0.0, 1.0]])},
...           links=(("A", "B"),), ground=("A",))
>>> s.frames, s.box()
(2, (-0.075, 1.075, -0.075, 1.075))
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ._arrays import count, flag, float_array, instance, real_array
from ._errors import InputError

__all__ = ["Body", "Scene", "block", "circle", "cycle_angles", "rotate"]

Array = npt.NDArray[np.float64]


def cycle_angles(cycle_deg: object) -> Array:
    """The main shaft's angles [deg] a ``scene`` hook is asked for: a non-empty 1-D
    array of finite numbers, or :class:`InputError`.

    Parameters
    ----------
    cycle_deg : array_like of float
        The angles [deg].

    Returns
    -------
    ndarray of float, shape (N,)
        The angles [deg].

    Examples
    --------
    >>> cycle_angles([0, 90]).tolist()
    [0.0, 90.0]
    """
    a = real_array("cycle_deg", cycle_deg, "[deg]", ndims=(1,))
    if not a.size:
        raise InputError("cycle_deg must hold at least one angle [deg]; got an empty array")
    return a


def _xy(name: str, value: object, cols: int, *, nan: bool) -> Array:
    """``value`` as an (n, ``cols``) float array: no ±inf, NaN only where ``nan``."""
    a = float_array(name, value, ndims=(2,))
    if a.shape[1] != cols or not a.shape[0]:
        raise InputError(f"{name} must have shape (n ≥ 1, {cols}); got {a.shape}")
    bad = np.isinf(a) | (np.isnan(a) if not nan else False)
    if bad.any():
        i = tuple(int(k) for k in np.argwhere(bad)[0])
        allowed = "finite or NaN (a break)" if nan else "finite"
        raise InputError(f"{name}{list(i)} = {a[i]!r} must be {allowed}")
    return a


def rotate(xy: Array, angle: Array) -> Array:
    """Points ``xy`` (..., 2) turned counter-clockwise by ``angle`` [rad] about the origin.

    Parameters
    ----------
    xy : ndarray of float, shape (..., 2)
        The points [m].
    angle : ndarray of float
        The angle [rad], broadcast against ``xy[..., 0]``.

    Returns
    -------
    ndarray of float, shape (..., 2)
        R(angle)·xy [m].

    Examples
    --------
    >>> rotate(np.array([1.0, 0.0]), np.array(np.pi / 2)).round(12) + 0.0
    array([0., 1.])
    """
    c, s = np.cos(angle), np.sin(angle)
    x, y = xy[..., 0], xy[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def circle(radius: float, n: int = 48) -> Array:
    """A closed circle's outline about the origin: ``n`` points [m].

    Parameters
    ----------
    radius : float
        Its radius [m].
    n : int, default 48
        The number of points.

    Returns
    -------
    ndarray of float, shape (n, 2)
        The points [m].

    Examples
    --------
    >>> circle(2.0, 4).round(12) + 0.0
    array([[ 2.,  0.],
           [ 0.,  2.],
           [-2.,  0.],
           [ 0., -2.]])
    """
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.stack([radius * np.cos(t), radius * np.sin(t)], axis=1)


def block(length: float, width: float) -> Array:
    """A rectangle about the origin, ``length`` along x and ``width`` along y [m].

    Parameters
    ----------
    length, width : float
        Its sides [m].

    Returns
    -------
    ndarray of float, shape (4, 2)
        Its corners [m], counter-clockwise.

    Examples
    --------
    >>> block(2.0, 1.0)
    array([[-1. , -0.5],
           [ 1. , -0.5],
           [ 1. ,  0.5],
           [-1. ,  0.5]])
    """
    a, b = 0.5 * length, 0.5 * width
    return np.array([[-a, -b], [a, -b], [a, b], [-a, b]])


@dataclass(frozen=True)
class Body:
    """A rigid outline moved over the frames.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    outline : ndarray of float, shape (P, 2)
        The outline in the body's own frame [m] (NaN rows break it into pieces).
    pose : ndarray of float, shape (F, 3)
        At each frame, where the body's origin is (x, y) [m] and how far it has
        turned [rad] counter-clockwise.
    closed : bool, default True
        The outline closes (a disc, a block) or not (a guide, a face).
    fill : bool, default True
        Filled (a part) or drawn as a line only.

    Examples
    --------
    >>> b = Body(block(2.0, 1.0), np.array([[0.0, 0.0, 0.0], [1.0, 0.0, np.pi / 2]]))
    >>> b.at(1).round(12) + 0.0
    array([[ 1.5, -1. ],
           [ 1.5,  1. ],
           [ 0.5,  1. ],
           [ 0.5, -1. ]])
    """

    outline: Array
    pose: Array
    closed: bool = True
    fill: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "outline", _xy("outline", self.outline, 2, nan=True))
        object.__setattr__(self, "pose", _xy("pose", self.pose, 3, nan=False))
        object.__setattr__(self, "closed", flag("closed", self.closed))
        object.__setattr__(self, "fill", flag("fill", self.fill))

    def at(self, frame: int) -> Array:
        """The outline where the body is at frame ``frame`` [m].

        Parameters
        ----------
        frame : int
            The frame's index (from 0).

        Returns
        -------
        ndarray of float, shape (P, 2)
            The outline turned and moved to the frame's pose [m].

        Examples
        --------
        >>> Body(circle(1.0, 4), np.array([[2.0, 0.0, 0.0]])).at(0).round(12) + 0.0
        array([[ 3.,  0.],
               [ 2.,  1.],
               [ 1.,  0.],
               [ 2., -1.]])
        """
        i = count("frame", frame, low=0, high=self.pose.shape[0] - 1)
        x, y, a = self.pose[i]
        out: Array = rotate(self.outline, np.array(a)) + np.array([x, y])
        return out


def _fixed(pose: Array, frames: int) -> Array:
    return np.broadcast_to(np.asarray(pose, dtype=np.float64), (frames, 3)).copy()


@dataclass(frozen=True)
class Scene:
    """One mechanism over the animation's frames: its points, bars, pivots and bodies.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    name : str
        The mechanism's name.
    points : Mapping of str to ndarray of float, shape (F, 2)
        Each named point at each frame [m], where the mechanism's solver puts it
        (NaN where it cannot be assembled).
    links : tuple of tuple of str, optional
        The bars (two points) and plates (three or more, drawn as a closed outline)
        joining the points; default none.
    ground : tuple of str, optional
        The points fixed to the frame (drawn with a ground mark); default none.
    bodies : Mapping of str to Body, optional
        Rigid outlines (a cam's profile, a roller, a block, a guide, a stop) by name;
        default none.
    traces : tuple of str, optional
        Points whose whole path over the frames is drawn; default none.

    Raises
    ------
    InputError
        If the points or the bodies' poses do not all have the same number of
        frames, or a link, ground point or trace names an unknown point.

    Examples
    --------
    >>> s = Scene("slider", {"P": np.array([[0.0, 0.0], [0.5, 0.0]])},
    ...           bodies={"block": Body(block(0.2, 0.1), np.zeros((2, 3)))}, traces=("P",))
    >>> s.frames, sorted(s.bodies)
    (2, ['block'])
    """

    name: str
    points: Mapping[str, Array]
    links: tuple[tuple[str, ...], ...] = ()
    ground: tuple[str, ...] = ()
    bodies: Mapping[str, Body] = field(default_factory=dict)
    traces: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        instance("name", self.name, str)
        points = {
            instance("points' names", k, str): _xy(f"points[{k!r}]", v, 2, nan=True)
            for k, v in instance("points", self.points, Mapping).items()
        }
        object.__setattr__(self, "points", points)
        for what in ("links", "ground", "traces"):
            value = getattr(self, what)
            if isinstance(value, str) or not isinstance(value, tuple | list):
                raise InputError(f"{what} must be a tuple of point names; got {value!r}")
        links = tuple(tuple(ln) if isinstance(ln, tuple | list) else ln for ln in self.links)
        if not all(isinstance(ln, tuple) and len(ln) >= 2 for ln in links):
            raise InputError(f"links must be tuples of two or more point names; got {self.links!r}")
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "ground", tuple(self.ground))
        object.__setattr__(self, "traces", tuple(self.traces))
        for k, b in instance("bodies", self.bodies, Mapping).items():
            instance(f"bodies[{k!r}]", b, Body)
        if not points and not self.bodies:
            raise InputError(f"scene {self.name!r} has neither points nor bodies")
        sizes = {np.shape(v)[0] for v in self.points.values()}
        sizes |= {b.pose.shape[0] for b in self.bodies.values()}
        if len(sizes) != 1:
            raise InputError(f"scene {self.name!r}: points and bodies disagree on the frames")
        named = [p for ln in self.links for p in ln] + list(self.ground) + list(self.traces)
        unknown = sorted({p for p in named if p not in self.points})
        if unknown:
            raise InputError(f"scene {self.name!r}: unknown points {unknown}")

    @property
    def frames(self) -> int:
        """The number of frames.

        Examples
        --------
        >>> Scene("p", {"A": np.zeros((3, 2))}).frames
        3
        """
        first = next(iter(self.points.values()), None)
        if first is not None:
            return int(np.shape(first)[0])
        return int(next(iter(self.bodies.values())).pose.shape[0])

    def box(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) [m] of everything over every frame, padded 7.5 %.

        Returns
        -------
        tuple of float
            The extent [m].

        Examples
        --------
        >>> Scene("p", {"A": np.array([[0.0, 0.0], [2.0, 1.0]])}).box()
        (-0.15, 2.15, -0.15, 1.15)
        """
        pts = [np.asarray(v, dtype=np.float64).reshape(-1, 2) for v in self.points.values()]
        # every body at every frame at once: (F, P, 2)
        pts += [
            (rotate(b.outline[None], b.pose[:, 2:3]) + b.pose[:, None, :2]).reshape(-1, 2)
            for b in self.bodies.values()
        ]
        allp = np.concatenate(pts) if pts else np.zeros((1, 2))
        allp = allp[np.isfinite(allp).all(axis=1)]
        if not allp.size:
            allp = np.zeros((1, 2))
        (x0, y0), (x1, y1) = allp.min(axis=0), allp.max(axis=0)
        pad = 0.075 * max(x1 - x0, y1 - y0) or 0.05
        return (float(x0 - pad), float(x1 + pad), float(y0 - pad), float(y1 + pad))

    @staticmethod
    def fixed(pose: tuple[float, float, float], frames: int) -> Array:
        """A pose held over ``frames`` frames: shape (frames, 3).

        Parameters
        ----------
        pose : tuple of float
            (x [m], y [m], angle [rad]).
        frames : int
            The number of frames.

        Returns
        -------
        ndarray of float, shape (frames, 3)
            The pose at every frame.

        Examples
        --------
        >>> Scene.fixed((1.0, 2.0, 0.0), 2)
        array([[1., 2., 0.],
               [1., 2., 0.]])
        """
        p = real_array("pose", pose, "[m, m, rad]", ndims=(1,))
        if p.shape != (3,):
            raise InputError(f"pose must be (x [m], y [m], angle [rad]); got shape {p.shape}")
        return _fixed(p, count("frames", frames, low=1))
