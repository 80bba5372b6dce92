"""The forces of a linkage over its crank angles (:class:`Kinetostatics`): the
three parts of every result (per ω², per ε, static) and their sum at a speed."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM

if TYPE_CHECKING:
    from ..linkage import LinkageSolution
    from ..shaft import ShaftTorque

__all__ = ["NEAR_DEAD_CENTRE", "Kinetostatics"]

#: Below this ``conditioning`` (the smallest pivot of the system's blocks over
#: the block's largest entry) an angle is near a dead centre: its forces are
#: large and change fast with the angle. Well-built linkages stay above 1e-2.
NEAR_DEAD_CENTRE = 1e-3

Array = npt.NDArray[np.float64]


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
        How far each angle is from a dead centre (0 at one; the forces grow as its
        inverse; see :attr:`near_dead_centre`).

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
        """The forces from the Rust kernel's values: views, no copies.

        Parameters
        ----------
        solution : LinkageSolution
            The solved linkage at the N crank angles.
        values : ndarray of float, shape (3, N, 1 + G [+ 2K])
            The kernel's parts: the torque [N·m], the G guide forces [N] and, when
            reactions were asked for, the K joint forces (x, y) [N].
        conditioning : ndarray of float, shape (N,)
            The kernel's conditioning at each angle (set to 0 where the linkage's
            kinematics are singular).
        pairs : tuple of tuple of (str, str)
            The (point, link) of each joint force.
        guides : tuple of str
            The guides' names.

        Returns
        -------
        Kinetostatics
            The forces; no reactions (shape (3, N, 0, 2)) when they were not asked for.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> sol = crank.solve([0.0])
        >>> k = Kinetostatics.from_values(sol, np.zeros((3, 1, 1)), np.ones(1), pairs=(), guides=())
        >>> k.reaction_parts.shape
        (3, 1, 0, 2)
        """
        n, g = values.shape[1], len(guides)
        k = (values.shape[2] - 1 - g) // 2
        return cls(
            solution=solution,
            pairs=pairs if k else (),
            guides=guides,
            torque_parts=values[:, :, 0],
            guide_parts=values[:, :, 1 : 1 + g],
            reaction_parts=values[:, :, 1 + g :].reshape(3, n, k, 2),
            conditioning=np.where(solution.singular & solution.ok, 0.0, conditioning),
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

        A group's kinematics or its forces are singular there.

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
        """True where the forces are ill-conditioned (N,), or singular.

        That is, ``conditioning`` below :data:`NEAR_DEAD_CENTRE`: a group within a hair
        of a dead centre, its forces large and sensitive to the angle.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> cm.forces.kinetostatics(crank, [0.0]).near_dead_centre.tolist()
        [False]
        """
        out: npt.NDArray[np.bool_] = ~(self.conditioning >= NEAR_DEAD_CENTRE)
        return out & self.solution.ok

    @staticmethod
    def _weights(rpm: Any, crank_acceleration: Any) -> tuple[float, float]:
        n = finite_number("rpm", rpm, "[rpm]")
        eps = finite_number("crank_acceleration", crank_acceleration, "[rad/s²]")
        return (n * RAD_PER_S_PER_RPM) ** 2, eps

    def _at(self, parts: Array, rpm: Any, crank_acceleration: Any) -> Array:
        w2, eps = self._weights(rpm, crank_acceleration)
        out: Array = w2 * parts[0] + eps * parts[1] + parts[2]
        return out

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
                f"{', '.join(f'{v:.2f}' for v in bad)} degrees (conditioning "
                f"{float(np.nanmin(self.conditioning)):.2g} < {NEAR_DEAD_CENTRE:g}): its torque "
                "there is large and depends on the grid",
                CyclomechWarning,
                stacklevel=2,
            )
        return ShaftTorque(
            np.degrees(a - a[0]),
            np.ascontiguousarray(self.torque_parts[0]),
            np.ascontiguousarray(self.torque_parts[2]),
        )
