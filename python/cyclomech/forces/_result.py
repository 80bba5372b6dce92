"""The forces of a linkage over its crank angles (:class:`Kinetostatics`): the
three parts of every result (per ω², per ε, static) and their sum at a speed."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import float_array, instance, instances
from .._errors import InputError
from .._notebook import data_frame, figure_of, html_card
from .._units import at_speed

if TYPE_CHECKING:
    from ..linkage import LinkageSolution
    from ..shaft import ShaftTorque

__all__ = ["NEAR_DEAD_CENTRE", "Kinetostatics"]

#: Below this ``conditioning`` [rad] an angle is near a dead centre: the crank is
#: within about 0.02 rad (1.15°) of a pose where the analogs, and with them the
#: torque and the forces, grow without bound. Near a fold (a four-bar's coupler
#: and rocker lining up, a slider-crank's rod across its guide) the inertia torque
#: grows as 1/δ² with the crank angle δ to it: where the flag turns on it is about
#: (0.1/0.02)² = 25 times its size 0.1 rad (5.7°) away, and under 50 times the
#: largest torque 0.1 rad or more from the fold (36 and 40 times at the two
#: toggles of the four-bar of the forces guide). Well-built linkages stay far
#: above it: a slider-crank of rod 3 cranks at 0.375 rad (its top dead centre),
#: the presets above 0.29 rad, Grashof crank-rockers whose transmission angle
#: falls to 5° above 0.04 rad.
NEAR_DEAD_CENTRE = 0.02

# Below this ``conditioning`` [rad] an angle is at the dead centre (singular, its
# forces NaN). Double precision places a fold only to ~1e-15 rad (a dyad's h² =
# r² − x² carries a few ulps of r², and h² ~ δ r²): within 1e-12 rad the
# analogs are mostly that round-off magnified (at the exact toggle of a four-bar
# they came out 1e22 times the crank's, its torque 1e30 N·m), never a value to
# show. The linkage solver's own test (the dyad's determinant under 1e-9 of its
# sides' product) misses such a pose: at a fold h is √(round-off), ~1e-8.
_AT_DEAD_CENTRE = 1e-12

Array = npt.NDArray[np.float64]


def _conditioning(solution: LinkageSolution, kernel: Array, analogs: Array | None = None) -> Array:
    """The crank angle [rad] from each pose to a dead centre, from the analogs.

    Near a fold, where a dyad's two links line up and the crank can go no
    further (δ the crank angle to it), a point moves as x* + c·√δ: its analogs
    grow as x' ~ δ^-½ and x'' ~ δ^-3/2, and |x'| / (2|x''|) → δ. Taking the
    largest analogs over the points makes the ratio scale-free (lengths cancel,
    the crank speed does not enter) and bounded away from 0 elsewhere: the crank
    pin alone has |x'| = |x''| = r, so a pose far from any dead centre gives
    O(1) rad (1 / (2 (1 + r/l)) at the top dead centre of a slider-crank of crank
    r and rod l). The force block's pivots, the kernel's own measure, only fall
    as δ^½ (and with the links' size), while the torque grows as δ^-2: they flag
    a fold far too late.
    0 where the kernel or the kinematics are singular or the analogs put the
    crank within ``_AT_DEAD_CENTRE`` of a dead centre, NaN where not assembled.
    ``analogs``: the ratio |x'| / (2|x''|) as the kernel took it while reading the
    analogs (``ForceModel.solve``'s third output; NaN where an input is not
    finite), else it is computed here.
    """
    assert solution.vel is not None and solution.acc is not None
    if analogs is None:
        v = np.hypot(solution.vel[..., 0], solution.vel[..., 1]).max(axis=1, initial=0.0)
        a = np.hypot(solution.acc[..., 0], solution.acc[..., 1]).max(axis=1, initial=0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            out: Array = np.where(a > 0.0, v / (2.0 * a), np.inf)
        out = np.where(np.isnan(kernel) | np.isnan(v) | np.isnan(a), np.nan, out)
    else:
        out = np.where(np.isnan(kernel), np.nan, analogs)
    dead = (kernel == 0.0) | (solution.singular & solution.ok) | (out < _AT_DEAD_CENTRE)
    return np.where(dead, 0.0, out)


def _check_kernel_values(solution: LinkageSolution, values: Array, conditioning: Array) -> None:
    """The kernel's contract, for values given by hand: ``conditioning`` is ≥ 0
    (NaN only where the solution's positions or analogs are not), the values
    finite where the solution is finite and ``conditioning`` > 0."""
    assert solution.vel is not None and solution.acc is not None
    given = np.ones(values.shape[1], dtype=bool)
    for a in (solution.xy, solution.vel, solution.acc):
        given &= np.isfinite(a).all(axis=tuple(range(1, a.ndim)))
    bad = given & ~(conditioning >= 0.0)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(
            f"conditioning[{i}] = {float(conditioning[i])!r} must be ≥ 0 where the solution "
            "is finite (NaN marks an angle whose positions or analogs are not) [rad]"
        )
    bad = ~np.isfinite(values) & (given & (conditioning > 0.0))[None, :, None]
    if bad.any():
        i, j, k = (int(x) for x in np.unravel_index(int(np.argmax(bad)), values.shape))
        raise InputError(
            f"values[{i}, {j}, {k}] = {float(values[i, j, k])!r} must be finite where the "
            "solution is finite and conditioning > 0 (the kernel's NaN marks a singular or "
            "not finite angle)"
        )


@dataclass(frozen=True)
class Kinetostatics:
    """A linkage's forces at the crank angles of its ``solution``.

    Every result is ω²·(part 0) + ε·(part 1) + (part 2) for the crank speed ω
    [rad/s] and angular acceleration ε [rad/s²]. ``singular`` is True where a group
    is at a dead centre (the forces unbounded; NaN there); ``ok`` where the linkage
    is assembled and not singular. Built by :func:`kinetostatics`; each parameter
    is kept as the attribute of the same name.

    Parameters
    ----------
    solution : LinkageSolution
        The solved linkage: positions and analogs at the crank angles
        ``angles`` [rad] (N,).
    pairs : tuple of tuple of (str, str)
        The (point, link) of each joint force: the link named by its joints
        joined by "-", ``"frame"`` for the frame's bearing; empty when solved with
        ``reactions=False``.
    guides : tuple of str
        The guides' names (G), e.g. ``"C on the frame"``.
    torque_parts : ndarray of float, shape (3, N)
        The driving torque on the crank [N·m] (positive in the direction of
        increasing crank angle: the torque the motor supplies).
    guide_parts : ndarray of float, shape (3, N, G)
        The normal force of each guide [N] along its normal (the guide's direction
        turned +90°).
    reaction_parts : ndarray of float, shape (3, N, K, 2)
        The force [N] each joint exerts on each part it joins, in the order of
        ``pairs``.
    conditioning : ndarray of float, shape (N,)
        How far each angle is from a dead centre, as a crank angle [rad]:
        max|x'| / (2 max|x''|) over the points' velocity and acceleration analogs,
        0 at a dead centre, NaN where the linkage is not assembled (see
        :attr:`near_dead_centre`).

    See Also
    --------
    kinetostatics : Builds it.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
    >>> k.pairs
    (('O', 'frame'), ('O', 'O-A'), ('A', 'O-A'))
    >>> k.reaction("O", "frame", rpm=60.0).round(4).tolist()   # m ω² r, outwards
    [[23.6871, 0.0]]
    """

    solution: LinkageSolution
    pairs: tuple[tuple[str, str], ...]
    guides: tuple[str, ...]
    torque_parts: Array
    guide_parts: Array
    reaction_parts: Array
    conditioning: Array

    @classmethod
    def from_values(
        cls,
        solution: LinkageSolution,
        values: Array,
        conditioning: Array,
        *,
        pairs: tuple[tuple[str, str], ...],
        guides: tuple[str, ...],
    ) -> Kinetostatics:
        """The forces from their parts as arrays, as :func:`kinetostatics` computes
        them (a result rebuilt from saved arrays, say): views, no copies.

        Parameters
        ----------
        solution : LinkageSolution
            The solved linkage at the N crank angles.
        values : ndarray of float, shape (3, N, 1 + G [+ 2K])
            The parts (ω², ε and constant) of the torque [N·m], the G guide
            forces [N] and, when reactions were asked for, the K joint forces
            (x, y) [N].
        conditioning : ndarray of float, shape (N,)
            The conditioning at each angle: 0 where a block of the force
            system is singular, NaN where an input is not finite. Only those two
            are kept; elsewhere the attribute ``conditioning`` is the scale-free
            crank angle to a dead centre that the solution's analogs give (0 where
            the linkage's kinematics are singular).
        pairs : tuple of tuple of (str, str)
            The (point, link) of each joint force.
        guides : tuple of str
            The guides' names.

        Returns
        -------
        Kinetostatics
            The forces; no reactions (shape (3, N, 0, 2)) when they were not asked for.
            NaN at every dead centre: where only the analogs show one (the given
            values finite), the values are copied with NaN there.

        Raises
        ------
        InputError
            If ``values`` is not of shape (3, N, 1 + G) or (3, N, 1 + G + 2K) (G
            guides, K pairs) or ``conditioning`` of shape (N,), either holds other
            than real numbers, ``conditioning`` is negative or NaN where the
            solution is finite, a value is not finite where the solution is finite
            and ``conditioning`` > 0 (NaN marks only those angles), or
            ``solution`` has no analogs.
        TypeError
            If ``solution`` is not a :class:`~cyclomech.LinkageSolution`, ``guides``
            not a sequence of str or ``pairs`` not a sequence of tuples.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> sol = crank.solve([0.0])
        >>> k = Kinetostatics.from_values(sol, np.zeros((3, 1, 1)), np.ones(1), pairs=(), guides=())
        >>> k.reaction_parts.shape
        (3, 1, 0, 2)
        """
        from ..linkage import LinkageSolution  # here: the linkage package imports this one

        sol = instance("solution", solution, LinkageSolution)
        if sol.vel is None or sol.acc is None or sol.xy.ndim != 3:
            raise InputError(
                "solution must be a linkage's solution with analogs, of one geometry "
                "(linkage.solve(angles))"
            )
        guides = tuple(instances("guides", guides, str))
        for i, pair in enumerate(instances("pairs", pairs, tuple)):
            if len(pair) != 2 or not all(isinstance(p, str) for p in pair):
                raise InputError(f"pairs[{i}] = {pair!r} must be a (point, link) of names")
        n, g = sol.angles.size, len(guides)
        v = float_array("values", values, ndims=(3,))
        widths = sorted({1 + g, 1 + g + 2 * len(pairs)})
        if v.shape[:2] != (3, n) or v.shape[2] not in widths:
            want = " or ".join(f"(3, {n}, {w})" for w in widths)
            raise InputError(f"values must be of shape {want}; got {v.shape}")
        c = float_array("conditioning", conditioning)
        if c.shape != (n,):
            raise InputError(f"conditioning must be of shape ({n},); got {c.shape}")
        _check_kernel_values(sol, v, c)
        return cls._from_kernel(sol, v, c, pairs=pairs, guides=guides)

    @classmethod
    def _from_kernel(
        cls,
        solution: LinkageSolution,
        values: Array,
        conditioning: Array,
        *,
        pairs: tuple[tuple[str, str], ...],
        guides: tuple[str, ...],
        analogs: Array | None = None,
        own: bool = False,
    ) -> Kinetostatics:
        """:meth:`from_values` of the kernel's own output, unchecked (``analogs``:
        see :func:`_conditioning`). ``own``: ``values`` is the result's to keep (the
        kernel's new block, or ``out``'s), so a dead centre's rows are set to NaN in
        it, not in a copy."""
        n, g = values.shape[1], len(guides)
        k = (values.shape[2] - 1 - g) // 2
        cond = _conditioning(solution, conditioning, analogs)
        dead = (cond == 0.0) & ~np.isnan(values[0, :, 0])
        if dead.any():
            if own:
                values[:, dead, :] = np.nan
            else:
                values = np.where(dead[None, :, None], np.nan, values)
        return cls(
            solution=solution,
            pairs=pairs if k else (),
            guides=guides,
            torque_parts=values[:, :, 0],
            guide_parts=values[:, :, 1 : 1 + g],
            reaction_parts=values[:, :, 1 + g :].reshape(3, n, k, 2),
            conditioning=cond,
        )

    def __repr__(self) -> str:
        n, bad = self.angles.size, int(self.near_dead_centre.sum())
        return (
            f"Kinetostatics({n} crank angles, {len(self.pairs)} joint forces, "
            f"{len(self.guides)} guides, {int((~self.ok).sum())} not ok, {bad} near a dead centre)"
        )

    @property
    def angles(self) -> Array:
        """The crank angles (N,) [rad].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics(crank, [0.0, 1.0]).angles.tolist()
        [0.0, 1.0]
        """
        return self.solution.angles

    @property
    def singular(self) -> npt.NDArray[np.bool_]:
        """True at a dead centre (N,), where the forces are unbounded (NaN).

        A group's kinematics or its forces are singular there, or the analogs put
        the crank within 1e-12 rad of a dead centre (``conditioning`` 0): closer
        than that, double precision cannot tell the pose from the dead centre
        itself, and its analogs (and forces) are round-off magnified.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics(crank, [0.0]).singular.tolist()
        [False]
        """
        out: npt.NDArray[np.bool_] = self.conditioning == 0.0
        return out

    @property
    def ok(self) -> npt.NDArray[np.bool_]:
        """True where the forces are finite (N,): assembled and not at a dead centre.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics(crank, [0.0]).ok.tolist()
        [True]
        """
        return self.solution.ok & ~self.singular

    @property
    def near_dead_centre(self) -> npt.NDArray[np.bool_]:
        """True where the linkage is assembled and at or near a dead centre (N,).

        That is, ``conditioning`` below :data:`NEAR_DEAD_CENTRE` (0.02 rad): the
        velocity and acceleration analogs say the crank is within about 0.02 rad of
        a pose where they grow without bound (x' ~ δ^-½, x'' ~ δ^-3/2 at a crank
        angle δ from a fold), and the torque and the forces with them (~ δ^-2): they
        are large and change fast with the angle. The rule reads the kinematics
        only, so it is the same at every speed, mass and load, and for a linkage of
        any size (the ratio of two analogs has no unit of length). Singular angles
        are near a dead centre too.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics(crank, [0.0]).near_dead_centre.tolist()
        [False]
        """
        out: npt.NDArray[np.bool_] = ~(self.conditioning >= NEAR_DEAD_CENTRE)
        return out & self.solution.ok

    def _at(self, parts: Array, rpm: Any, crank_acceleration: Any) -> Array:
        return at_speed(parts, rpm, crank_acceleration)

    def torque(self, rpm: Any, crank_acceleration: float = 0.0) -> Array:
        """The driving torque on the crank [N·m] at a crank speed and acceleration.

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N,)
            The torque the motor supplies at each crank angle [N·m].

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
        >>> k.torque(100.0, crank_acceleration=10.0).round(9).tolist()   # m r² ε
        [1.8]
        """
        return self._at(self.torque_parts, rpm, crank_acceleration)

    def guide_forces(self, rpm: Any, crank_acceleration: float = 0.0) -> Array:
        """The guides' normal forces [N] at a crank speed and acceleration.

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N, G)
            Each guide's normal force at each crank angle [N], in the order of
            ``guides``.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> sc = cm.Linkage({"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
        ...                 [("A", "B"), ("B", "C")], ["A"], ("A", "B"),
        ...                 sliders={"C": ("ground", (1, 0))})
        >>> k = cm.forces.kinetostatics(sc, np.radians([0.0]), point_masses={"C": 1.0},
        ...                             gravity=(0, -9.81))
        >>> k.guides, k.guide_forces(0.0).round(6).tolist()      # the guide carries m g
        (('C on the frame',), [[9.81]])
        """
        return self._at(self.guide_parts, rpm, crank_acceleration)

    def reactions(self, rpm: Any, crank_acceleration: float = 0.0) -> Array:
        """Every joint's force on every part it joins [N], at a crank speed and acceleration.

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N, K, 2)
            The forces (x, y) at each crank angle [N], in the order of ``pairs``.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
        >>> k.reactions(60.0).shape
        (1, 3, 2)
        """
        return self._at(self.reaction_parts, rpm, crank_acceleration)

    def _need_reactions(self) -> None:
        if not self.pairs:
            raise InputError(
                "the joints' forces were not computed (kinetostatics(..., reactions=False)); "
                "solve with reactions=True"
            )

    def reaction(
        self, point: str, link: str | None = None, *, rpm: Any, crank_acceleration: float = 0.0
    ) -> Array:
        """The force [N] one joint exerts on one link, at a crank speed and acceleration.

        Parameters
        ----------
        point : str
            The joint's name.
        link : str, optional
            The link, its joints joined by "-", or ``"frame"``; default None (the
            joint's only or first part).
        rpm : float
            The crank speed [rpm] (keyword-only).
        crank_acceleration : float, default 0.0
            The crank's angular acceleration ε [rad/s²].

        Returns
        -------
        ndarray of float, shape (N, 2)
            The force (x, y) at each crank angle [N].

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number, the joint
            forces were not computed (``reactions=False``) or there is no such joint
            on ``link``.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
        >>> k.reaction("A", rpm=60.0).round(4).tolist()   # the mass at A pulls O-A outwards
        [[23.6871, 0.0]]
        """
        self._need_reactions()
        for k, (p, ln) in enumerate(self.pairs):
            if p == point and (link is None or ln == link):
                return self.reactions(rpm, crank_acceleration)[:, k]
        known = ", ".join(f"{p} on {ln}" for p, ln in self.pairs)
        on = f" on {link!r}" if link is not None else ""
        raise InputError(f"no joint {point!r}{on}; the joints are {known}")

    def joint_loads(self, rpm: Any, crank_acceleration: float = 0.0) -> dict[str, Array]:
        """Each joint's load [N]: the largest force it exerts on any part it joins.

        Angle by angle.

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration ε [rad/s²].

        Returns
        -------
        dict of str to ndarray of float, shape (N,)
            Each joint's load at each crank angle [N].

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number or the joint
            forces were not computed (``reactions=False``).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0}, gravity=(0, -9.81))
        >>> k.joint_loads(0.0)["O"].round(6).tolist()
        [19.62]
        """
        self._need_reactions()
        mag = np.hypot(*np.moveaxis(self.reactions(rpm, crank_acceleration), -1, 0))
        out: dict[str, Array] = {}
        for k, (p, _) in enumerate(self.pairs):
            out[p] = mag[:, k] if p not in out else np.fmax(out[p], mag[:, k])
        return out

    def most_loaded(self, rpm: Any, crank_acceleration: float = 0.0) -> tuple[str, float, float]:
        """The joint with the largest load, over the angles where the forces are finite.

        Ties go to the joint first in ``pairs`` (the linkage's point order) and, for
        one joint, to the first angle.

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration ε [rad/s²].

        Returns
        -------
        joint : str
            The most loaded joint (``""`` where no angle has finite forces).
        peak : float
            Its peak load [N] (NaN where none is finite).
        angle : float
            The crank angle of the peak [deg] (NaN where none is finite).

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number or the joint
            forces were not computed (``reactions=False``).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0, 1.0], point_masses={"A": 2.0})
        >>> k.most_loaded(60.0)[0]
        'O'
        """
        best: tuple[str, float, float] = ("", math.nan, math.nan)
        for p, load in self.joint_loads(rpm, crank_acceleration).items():
            if not np.isfinite(load).any():
                continue
            i = int(np.nanargmax(load))
            if not load[i] <= best[1]:
                best = (p, float(load[i]), float(np.degrees(self.angles[i])))
        return best

    def table(self, rpm: Any, crank_acceleration: float = 0.0) -> tuple[list[str], list[Array]]:
        """The forces at a speed as columns (header, columns), one row per crank
        angle: ``crank_deg``, ``torque_nm``, ``guide_n[<guide>]`` for each guide
        and ``fx_n[<point> on <link>]``, ``fy_n[…]`` for each joint force (the
        columns of a machine's ``<mechanism>_forces.csv``).

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration [rad/s²].

        Returns
        -------
        header : list of str
            The columns' names, units in them.
        columns : list of ndarray of float, each shape (N,)
            The columns.

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.

        Examples
        --------
        >>> import cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0], point_masses={"A": 2.0})
        >>> header, cols = k.table(60.0)
        >>> header[:3], round(float(cols[2][0]), 4)
        (['crank_deg', 'torque_nm', 'fx_n[O on frame]'], 23.6871)
        """
        header = ["crank_deg", "torque_nm"]
        cols: list[Array] = [np.degrees(self.angles), self.torque(rpm, crank_acceleration)]
        guides = self.guide_forces(rpm, crank_acceleration)
        for j, g in enumerate(self.guides):
            header.append(f"guide_n[{g}]")
            cols.append(guides[:, j])
        react = self.reactions(rpm, crank_acceleration)
        for i, (pt, part) in enumerate(self.pairs):
            header += [f"fx_n[{pt} on {part}]", f"fy_n[{pt} on {part}]"]
            cols += [react[:, i, 0], react[:, i, 1]]
        return header, cols

    def to_pandas(self, rpm: Any, crank_acceleration: float = 0.0) -> Any:
        """:meth:`table` as a pandas DataFrame indexed by ``crank_deg`` (pandas
        needed).

        Parameters
        ----------
        rpm : float
            The crank speed [rpm].
        crank_acceleration : float, default 0.0
            The crank's angular acceleration [rad/s²].

        Returns
        -------
        pandas.DataFrame
            One row per crank angle [deg].

        Raises
        ------
        InputError
            If ``rpm`` or ``crank_acceleration`` is not a finite number.
        ImportError
            If pandas is not installed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, [0.0, 1.0], point_masses={"A": 2.0})
        >>> k.to_pandas(60.0)["fx_n[O on frame]"].round(4).tolist()
        [23.6871, 12.7982]
        """
        header, cols = self.table(rpm, crank_acceleration)
        return data_frame(dict(zip(header, cols, strict=True)), index="crank_deg")

    def _repr_html_(self) -> str:
        """The notebook's view: what was solved and the driving torque's parts
        (ω², ε and static), with the linkage at its first angle."""
        torque = np.abs(self.torque_parts)
        with np.errstate(invalid="ignore"):
            peak = [float(np.nanmax(t)) if np.isfinite(t).any() else math.nan for t in torque]
        rows: list[tuple[str, Any]] = [
            ("crank angles", self.angles.size),
            ("joint forces", len(self.pairs)),
            ("guides", ", ".join(self.guides) or "none"),
            ("not assembled or at a dead centre", int((~self.ok).sum())),
            ("near a dead centre", int(self.near_dead_centre.sum())),
            ("peak |torque| per (rad/s)² of crank speed [N·m·s²]", peak[0]),
            ("peak |torque| per rad/s² of crank acceleration [N·m·s²]", peak[1]),
            ("peak |static torque| (gravity, loads) [N·m]", peak[2]),
        ]
        return html_card("Kinetostatics", rows, figure_of(self))

    def shaft_torque(self) -> ShaftTorque:
        """The driving torque as a :class:`~cyclomech.shaft.ShaftTorque`.

        Its ω² and static parts, θ = 0 at the first angle: for the flywheel, the motor
        and the machine's main shaft. The angles must be N uniform steps over one
        turn, the last one step short of the first plus 360°, all forces finite.

        Returns
        -------
        ShaftTorque
            The driving torque T(θ) = ω²·a(θ) + b(θ) [N·m] over the turn.

        Raises
        ------
        InputError
            If the angles are not N ≥ 3 uniform steps over one turn or the forces are
            not finite at every angle.

        Warns
        -----
        CyclomechWarning
            If the linkage is near a dead centre at some angle (its torque there is
            large and depends on the grid).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 1.0)),
        ...                             point_masses={"A": 2.0}, gravity=(0, -9.81))
        >>> s = k.shaft_torque().stats(60.0, speed_fluctuation=0.1)
        >>> abs(float(s.mean_torque_nm)) < 1e-12, round(float(s.energy_fluctuation_j), 3)  # 2·m g r
        (True, 11.772)
        """
        from ..shaft import ShaftTorque

        a = self.angles
        n = a.size
        step = 2.0 * math.pi / n if n else math.nan
        if n < 3 or not np.allclose(np.diff(a), step, rtol=0.0, atol=1e-9 * step):
            raise InputError(
                "shaft_torque needs the forces on N >= 3 uniform crank angles over one turn "
                "(a + 2πk/N, k = 0 … N−1); solve them on such a grid"
            )
        if not self.ok.all():
            bad = np.degrees(a[~self.ok])[:6]
            raise InputError(
                f"the forces are not finite at crank angles {', '.join(f'{v:.1f}' for v in bad)} "
                "degrees (not assembled or a dead centre): no shaft torque over the turn"
            )
        if self.near_dead_centre.any():
            import warnings

            from .._errors import CyclomechWarning

            bad = np.degrees(a[self.near_dead_centre])[:6]
            warnings.warn(
                f"the linkage is near a dead centre at crank angles "
                f"{', '.join(f'{v:.2f}' for v in bad)} degrees (its analogs put the crank "
                f"{float(np.nanmin(self.conditioning)):.2g} rad from one, under "
                f"{NEAR_DEAD_CENTRE:g} rad): its torque there is large and depends on the grid",
                CyclomechWarning,
                stacklevel=2,
            )
        return ShaftTorque(
            np.degrees(a - a[0]),
            np.ascontiguousarray(self.torque_parts[0]),
            np.ascontiguousarray(self.torque_parts[2]),
        )
