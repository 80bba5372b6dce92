"""What loads a linkage (:class:`LinkMass`, :class:`PointLoad`, :class:`LinkTorque`)
and :func:`kinetostatics`, which builds the Rust force model from a linkage's
topology and solves it at every crank angle."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, flag, float_array, instance, real_array, threads_arg
from .._errors import InputError
from ._result import Kinetostatics

if TYPE_CHECKING:
    from ..linkage import Linkage, LinkageSolution

__all__ = ["LinkMass", "LinkTorque", "PointLoad", "check_dynamics", "kinetostatics"]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LinkMass:
    """The inertia of one link: its mass, centre of mass and moment of inertia.

    The centre of mass is given one way at most: ``com_m`` in the drawn pose,
    ``com_point`` a joint of the link, or ``com_offset_m`` in the link's frame;
    none: the centroid of the link's joints. Each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    mass_kg : float
        The link's mass [kg] (≥ 0).
    com_m : tuple of (float, float), optional
        The centre of mass (x, y) [m] in the drawn pose; default None.
    inertia_kg_m2 : float, default 0.0
        The moment of inertia about the centre of mass [kg·m²] (0: the mass is a
        point).
    com_point : str, optional
        A joint of the link at the centre of mass; default None.
    com_offset_m : tuple of (float, float), optional
        The centre of mass (u, v) [m] in the link's frame (origin at its first
        joint, u towards its second, v to the left); default None.

    See Also
    --------
    kinetostatics : Takes a mapping of links to their ``LinkMass``.

    Raises
    ------
    InputError
        If ``mass_kg`` or ``inertia_kg_m2`` is not a finite number ≥ 0 (a string,
        a bool, None, NaN, ±inf or a negative number).

    Notes
    -----
    The centre of mass is checked when the linkage's forces are built
    (:func:`kinetostatics`, :func:`check_dynamics`), which raise
    :class:`~cyclomech.InputError` for a centre of mass given more than one way or
    a ``com_point`` not on the link.

    Examples
    --------
    >>> LinkMass(2.0, inertia_kg_m2=0.01).mass_kg
    2.0
    """

    mass_kg: float
    com_m: tuple[float, float] | None = None
    inertia_kg_m2: float = 0.0
    com_point: str | None = None
    com_offset_m: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        # Each number once, here: the mass of every link the forces are built from.
        for name, unit in (("mass_kg", "[kg]"), ("inertia_kg_m2", "[kg·m²]")):
            v = finite_number(name, getattr(self, name), unit, low=0.0)
            object.__setattr__(self, name, v)


def _table(what: str, angle_deg: Any, values: Any, width: int) -> tuple[Array | None, Array]:
    """A constant (``angle_deg`` None) or a table over the crank angle: the
    angles strictly increasing over at most one turn, one row of values each."""
    if angle_deg is None:
        v = float_array(what, values, ndims=(0, 1)).reshape(-1)
        if v.size != width or not np.isfinite(v).all():
            raise InputError(f"{what} = {values!r} must be {width} finite number(s)")
        return None, v
    a = float_array(f"{what}: angle_deg", angle_deg)
    v2 = float_array(what, values, ndims=(1, 2))
    if a.size < 2 or v2.size != a.size * width:
        raise InputError(
            f"{what}: a table needs >= 2 crank angles and one value of {width} number(s) "
            f"each; got {a.size} angles and values of shape {np.shape(values)}"
        )
    v2 = v2.reshape(a.size, width)
    if not (np.isfinite(a).all() and np.isfinite(v2).all()):
        raise InputError(f"{what}: angle_deg and the values must be finite")
    if not (np.diff(a) > 0).all() or a[-1] - a[0] > 360.0:
        raise InputError(
            f"{what}: angle_deg = {a.tolist()} must increase strictly over at most one turn (360°)"
        )
    return a, v2


def _evaluate(table: Array | None, values: Array, phi_deg: Array) -> Array:
    """The load at crank angles ``phi_deg`` (N,): constant, or the table's linear
    interpolation where the angle (moved by whole turns to the table's start) is
    inside it, and zero outside."""
    if table is None:
        return np.broadcast_to(values, (phi_deg.size, values.size))
    x = table[0] + np.mod(phi_deg - table[0], 360.0)
    inside = x <= table[-1]
    cols = [
        np.where(inside, np.interp(x, table, values[:, c]), 0.0) for c in range(values.shape[1])
    ]
    return np.stack(cols, axis=1)


@dataclass(frozen=True, init=False)
class PointLoad:
    """An external force [N] on a point, constant or a table over the crank angle.

    A table is linear between its rows and **zero outside the table** (a cutting
    force acts only during the cut; an angle is first moved by whole turns to the
    table's start). Each parameter is kept as the attribute of the same name
    (``force_n`` as a float array, ``angle_deg`` as a float array or None).

    Parameters
    ----------
    point : str
        The name of the (moving) point the force acts on.
    force_n : array_like of float, shape (2,) or (M, 2)
        The force (fx, fy) [N]: constant, or one row per angle of ``angle_deg``.
    angle_deg : array_like of float, shape (M,), optional
        The absolute crank angles of the table's rows [deg], M ≥ 2, strictly
        increasing over at most one turn; default None (a constant force).

    Raises
    ------
    InputError
        If ``point`` is not a name, or the force or the table is malformed (not
        finite, wrong shape, angles not strictly increasing over at most 360°).

    Examples
    --------
    >>> p = PointLoad("E", [[0, -500], [0, -500]], angle_deg=[200, 300])
    >>> p.at(np.radians([250.0, 100.0])).tolist()
    [[0.0, -500.0], [0.0, 0.0]]
    """

    point: str
    angle_deg: Array | None
    force_n: Array

    def __init__(self, point: str, force_n: Any, angle_deg: Any = None) -> None:
        if not isinstance(point, str):
            raise InputError(f"PointLoad: point must be a point's name; got {point!r}")
        a, v = _table(f"load on {point!r}: force_n", angle_deg, force_n, 2)
        object.__setattr__(self, "point", point)
        object.__setattr__(self, "angle_deg", a)
        object.__setattr__(self, "force_n", v)

    def at(self, angles: Any) -> Array:
        """The force at the crank angles ``angles`` [N].

        Parameters
        ----------
        angles : array_like of float, shape (N,)
            The absolute crank angles [rad].

        Returns
        -------
        ndarray of float, shape (N, 2)
            The force (fx, fy) at each angle [N] (zero outside a table).

        Raises
        ------
        InputError
            If ``angles`` is not a 1-D array of finite real numbers.

        Examples
        --------
        >>> PointLoad("C", (-1000.0, 0.0)).at(np.radians([0.0, 90.0])).tolist()
        [[-1000.0, 0.0], [-1000.0, 0.0]]
        """
        deg = np.degrees(real_array("angles", angles, "[rad]", ndims=(1,)))
        return _evaluate(self.angle_deg, self.force_n, deg)


@dataclass(frozen=True, init=False)
class LinkTorque:
    """An external torque [N·m] on a link, constant or a table over the crank angle.

    Counter-clockwise positive; a table works as :class:`PointLoad`'s (linear
    between its rows, zero outside it). Each parameter is kept as the attribute of
    the same name (``link`` as a tuple, ``torque_nm`` as a float array).

    Parameters
    ----------
    link : sequence of str
        The link, by its joints' names (in any order).
    torque_nm : float or array_like of float, shape (M,)
        The torque [N·m]: constant, or one value per angle of ``angle_deg``.
    angle_deg : array_like of float, shape (M,), optional
        The absolute crank angles of the table's rows [deg], M ≥ 2, strictly
        increasing over at most one turn; default None (a constant torque).

    Raises
    ------
    InputError
        If ``link`` is not a sequence of joint names, or the torque or the table is
        malformed.

    Examples
    --------
    >>> LinkTorque(("B", "C"), 5.0).at(np.zeros(2)).tolist()
    [5.0, 5.0]
    """

    link: tuple[str, ...]
    angle_deg: Array | None
    torque_nm: Array

    def __init__(self, link: Sequence[str], torque_nm: Any, angle_deg: Any = None) -> None:
        # A number or None is no sequence of names either: an InputError, which a
        # machine file's reader prefixes with the file, table and key.
        names = () if isinstance(link, str) or not hasattr(link, "__iter__") else tuple(link)
        if not names or not all(isinstance(p, str) for p in names):
            raise InputError(f"LinkTorque: link must be its joints' names; got {link!r}")
        link = names
        a, v = _table(f"torque on {'-'.join(link)}: torque_nm", angle_deg, torque_nm, 1)
        object.__setattr__(self, "link", tuple(link))
        object.__setattr__(self, "angle_deg", a)
        object.__setattr__(self, "torque_nm", v)

    def at(self, angles: Any) -> Array:
        """The torque at the crank angles ``angles`` [N·m].

        Parameters
        ----------
        angles : array_like of float, shape (N,)
            The absolute crank angles [rad].

        Returns
        -------
        ndarray of float, shape (N,)
            The torque at each angle [N·m] (zero outside a table).

        Raises
        ------
        InputError
            If ``angles`` is not a 1-D array of finite real numbers.

        Examples
        --------
        >>> t = LinkTorque(("B", "C"), [2.0, 4.0], angle_deg=[0.0, 90.0])
        >>> t.at(np.radians([45.0, 180.0])).tolist()
        [3.0, 0.0]
        """
        deg = np.degrees(real_array("angles", angles, "[rad]", ndims=(1,)))
        return _evaluate(self.angle_deg, self.torque_nm, deg)[:, 0]


def _link_index(links: list[list[str]], moving: list[int], joints: Sequence[str], what: str) -> int:
    want = set(joints)
    for b, k in enumerate(moving):
        if set(links[k]) == want:
            return b
    names = ", ".join("-".join(links[k]) for k in moving)
    raise InputError(
        f"{what}: no moving link has the joints {'-'.join(joints)}; the moving links are {names}"
    )


def _com_in_frame(
    lm: LinkMass, ln: list[str], pts: Mapping[str, tuple[float, float]]
) -> tuple[float, float]:
    """The centre of mass as (u, v) with c = x₀ + u·d + v·d⊥, d = x₁ − x₀ (the
    kernel's frame), from whichever way ``lm`` gives it."""
    name = "-".join(ln)
    given = [k for k in ("com_m", "com_point", "com_offset_m") if getattr(lm, k) is not None]
    if len(given) > 1:
        raise InputError(f"link {name}: give its centre of mass one way, not {' and '.join(given)}")
    x0, x1 = np.array(pts[ln[0]]), np.array(pts[ln[1]])
    d = x1 - x0
    dd = float(d @ d)
    if lm.com_offset_m is not None:
        off = lm.com_offset_m
        if isinstance(off, str) or not isinstance(off, Sequence) or len(off) != 2:
            raise InputError(f"link {name}: com_offset_m = {off!r} must be (u, v) [m]")
        u = finite_number(f"com_offset_m of link {name}", lm.com_offset_m[0], "[m]")
        v = finite_number(f"com_offset_m of link {name}", lm.com_offset_m[1], "[m]")
        return u / math.sqrt(dd), v / math.sqrt(dd)
    if lm.com_point is not None:
        if lm.com_point not in ln:
            raise InputError(
                f"link {name}: com_point = {lm.com_point!r} is not one of its joints "
                f"({', '.join(ln)})"
            )
        c: Any = pts[lm.com_point]
    elif lm.com_m is not None:
        c = lm.com_m
        if isinstance(c, str) or not isinstance(c, Sequence) or len(c) != 2:
            raise InputError(f"link {name}: com_m = {c!r} must be (x, y) [m]")
    else:
        c = tuple(np.mean([pts[p] for p in ln], axis=0))
    cx = finite_number(f"com_m of link {name}", c[0], "[m]")
    cy = finite_number(f"com_m of link {name}", c[1], "[m]")
    r = np.array([cx, cy]) - x0
    return float(r @ d) / dd, float(r @ np.array([-d[1], d[0]])) / dd


def _build(
    linkage: Linkage,
    masses: Mapping[Sequence[str], LinkMass] | None,
    point_masses: Mapping[str, float] | None,
    loads: Sequence[PointLoad | LinkTorque],
    gravity: Sequence[float] | None,
) -> tuple[Any, list[str], list[str], list[str], list[list[str]], list[int]]:
    """The Rust force model of ``linkage`` with its masses and gravity, every
    name checked (loads included); (model, point names, link names, guide
    names, links, moving link indices)."""
    from ..linkage import Linkage  # here: the linkage package imports this one

    table = instance("linkage", linkage, Linkage).to_dict()
    names = list(linkage.names)
    idx = {n: i for i, n in enumerate(names)}
    pts = {n: (float(x), float(y)) for n, (x, y) in table["points"].items()}
    ground = set(table["ground"])
    links = [list(ln) for ln in table["links"]]
    moving = [k for k, ln in enumerate(links) if not set(ln) <= ground]
    pivot, tip = table["driver"]
    driver = next(b for b, k in enumerate(moving) if pivot in links[k] and tip in links[k])

    body_mass = np.zeros(len(moving))
    body_inertia = np.zeros(len(moving))
    com = np.zeros((len(moving), 2))
    given: dict[int, LinkMass] = {}
    if masses is not None and not isinstance(masses, Mapping):
        raise InputError(f"masses = {masses!r} must map links (their joints) to LinkMass")
    for joints, lm in (masses or {}).items():
        if isinstance(joints, str):
            raise InputError(f"masses: key {joints!r} must be a link's joints, e.g. ('B', 'C')")
        what = f"masses[{'-'.join(joints)}]"
        if not isinstance(lm, LinkMass):
            raise InputError(f"{what} = {lm!r} must be a LinkMass")
        b = _link_index(links, moving, joints, what)
        if b in given:
            raise InputError(
                f"{what}: the link {'-'.join(links[moving[b]])} has a mass already (given "
                "twice, in another order of its joints); give each link once"
            )
        given[b] = lm
    for b, k in enumerate(moving):
        ln = links[k]
        lm = given.get(b, LinkMass(0.0))
        body_mass[b], body_inertia[b] = lm.mass_kg, lm.inertia_kg_m2  # checked by LinkMass
        com[b] = _com_in_frame(lm, ln, pts)

    pmass = np.zeros(len(names))
    if point_masses is not None and not isinstance(point_masses, Mapping):
        raise InputError(f"point_masses = {point_masses!r} must map points to masses [kg]")
    for p, m in (point_masses or {}).items():
        if p not in idx:
            raise InputError(f"point_masses: no point {p!r}; the points are {', '.join(names)}")
        pmass[idx[p]] = finite_number(f"point_masses[{p!r}]", m, "[kg]", low=0.0)
        if p in ground and pmass[idx[p]] > 0:
            raise InputError(
                f"point_masses[{p!r}]: {p!r} is a ground joint, which does not move: a mass "
                "there loads only the frame; put it on a moving point"
            )

    guide_idx, guide_dir, guide_names = [], [], []
    for p, guides in (table.get("sliders") or {}).items():
        for g in guides:
            ((kind, arg),) = g.items()
            if kind == "ground":
                guide_idx.append([idx[p], -1, -1, -1])
                guide_dir.append([float(arg[0]), float(arg[1])])
                guide_names.append(f"{p} on the frame")
            else:
                b_, c_ = arg
                body = next(
                    (b for b, k in enumerate(moving) if b_ in links[k] and c_ in links[k]), None
                )
                if body is None:  # a guide on a link of the frame is a guide of the frame
                    (bx, by), (cx_, cy_) = pts[b_], pts[c_]
                    guide_idx.append([idx[p], -1, -1, -1])
                    guide_dir.append([cx_ - bx, cy_ - by])
                else:
                    guide_idx.append([idx[p], idx[b_], idx[c_], body])
                    guide_dir.append([0.0, 0.0])
                guide_names.append(f"{p} on {b_}–{c_}")

    g = (0.0, 0.0) if gravity is None else tuple(float_array("gravity", gravity).tolist())
    if len(g) != 2 or not all(math.isfinite(v) for v in g):
        raise InputError(f"gravity = {gravity!r} must be (gx, gy) [m/s²], finite")

    ptr = np.concatenate([[0], np.cumsum([len(links[k]) for k in moving])]).astype(np.int64)
    model = _core.ForceModel(
        len(names),
        ptr,
        np.array([idx[p] for k in moving for p in links[k]], dtype=np.int64),
        body_mass,
        com,
        body_inertia,
        np.array([idx[p] for p in sorted(ground)], dtype=np.int64),
        pmass,
        np.array(guide_idx, dtype=np.int64).reshape(-1, 4),
        np.array(guide_dir, dtype=np.float64).reshape(-1, 2),
        driver,
        np.array(g, dtype=np.float64),
    )

    if isinstance(loads, PointLoad | LinkTorque) or not isinstance(loads, Sequence):
        raise InputError(f"loads = {loads!r} must be a list of PointLoad and LinkTorque")
    for load in loads:
        if isinstance(load, PointLoad):
            if load.point not in idx:
                raise InputError(
                    f"loads: a force on {load.point!r}, which is not a point; the points are "
                    f"{', '.join(names)}"
                )
            if load.point in ground:
                raise InputError(
                    f"loads: a force on {load.point!r}, a ground joint: it goes straight into "
                    "the frame and loads no link; put it on a moving point"
                )
        elif isinstance(load, LinkTorque):
            _link_index(links, moving, load.link, "loads: a torque")
        else:
            raise InputError(f"loads: {load!r} is neither a PointLoad nor a LinkTorque")
    body_names = ["-".join(links[k]) for k in moving]
    return model, names, body_names, guide_names, links, moving


def kinetostatics(
    linkage: Linkage,
    angles: Any,
    *,
    masses: Mapping[Sequence[str], LinkMass] | None = None,
    point_masses: Mapping[str, float] | None = None,
    loads: Sequence[PointLoad | LinkTorque] = (),
    gravity: Sequence[float] | None = None,
    reactions: bool = True,
    n_threads: int | None = None,
    out: Kinetostatics | None = None,
) -> Kinetostatics:
    """Joint reactions, guide forces and the crank's driving torque of a linkage.

    At the absolute crank angles ``angles``, for any crank speed and angular
    acceleration (:class:`Kinetostatics`). The positions and analogs come from
    :meth:`~cyclomech.linkage.Linkage.solve`; each angle is one linear solve in Rust (see
    :mod:`cyclomech.forces`), three right-hand sides (ω², ε, static), angles in
    parallel, the GIL released.

    Parameters
    ----------
    linkage : Linkage
        The linkage.
    angles : array_like of float, shape (N,), or LinkageSolution
        The absolute crank angles [rad]; or a :class:`~cyclomech.LinkageSolution`
        of ``linkage`` already solved (every point, with analogs), which is then
        not solved again.
    masses : mapping of tuple of str to LinkMass, optional
        Maps a moving link (its joints, in any order) to its :class:`LinkMass`;
        default None (massless links).
    point_masses : mapping of str to float, optional
        Maps a moving point to a lumped mass [kg] (a slider block, a knife);
        default None.
    loads : sequence of PointLoad and LinkTorque, default ()
        The external forces [N] and torques [N·m].
    gravity : tuple of (float, float), optional
        The acceleration of gravity (gx, gy) [m/s²]; default None (no gravity).
    reactions : bool, default True
        False computes the driving torque and the guide forces only (the joints'
        forces are most of the output: 2 numbers per joint and part per angle).
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all
        cores).
    out : Kinetostatics, optional
        A previous result of this function for as many angles and the same outputs
        (the same guides and joint forces, ``reactions`` alike), whose force arrays
        are overwritten and returned in the new result: a repeated solve (other
        masses, loads, or angles) then skips the first touch of fresh memory, 3·(1 +
        G + 2K) numbers an angle. Bit for bit a fresh solve. Default None (new
        arrays).

    Returns
    -------
    Kinetostatics
        The forces' three parts (per ω², per ε, static) at every angle.

    Raises
    ------
    InputError
        If a link or point named does not exist, a mass is negative, ``masses`` or
        ``point_masses`` is not a mapping, a load is on a ground joint, ``gravity``
        is not (gx, gy), the linkage's forces are not statically determinate,
        ``angles`` is a solution of another linkage or without analogs, or ``out``
        is not a result of this function for as many angles and the same outputs.
    TypeError
        If ``linkage`` is not a :class:`~cyclomech.Linkage`.

    See Also
    --------
    check_dynamics : The same checks without solving.

    Examples
    --------
    A crank O–A of 0.3 m with 2 kg at A held against gravity needs m·g·r·cos φ:

    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> k = cm.forces.kinetostatics(crank, np.radians([0.0, 60.0]), point_masses={"A": 2.0},
    ...                             gravity=(0, -9.81))
    >>> k.torque(rpm=0.0).round(6).tolist()           # 2·9.81·0.3·cos φ
    [5.886, 2.943]

    Again with 3 kg, into the first result's arrays:

    >>> again = cm.forces.kinetostatics(crank, np.radians([0.0, 60.0]), point_masses={"A": 3.0},
    ...                                 gravity=(0, -9.81), out=k)
    >>> again.torque(rpm=0.0).round(6).tolist()
    [8.829, 4.4145]
    >>> np.shares_memory(again.torque_parts, k.torque_parts)
    True
    """
    model, names, body_names, guide_names, links, moving = _build(
        linkage, masses, point_masses, loads, gravity
    )
    sol = _solution(linkage, angles, n_threads)
    reactions = flag("reactions", reactions)
    block = None if out is None else _out_block(out, (3, sol.angles.size, model.width(reactions)))
    force, torque = _load_arrays(loads, sol.angles, names, links, moving)
    values, conditioning, analogs = model.solve(
        np.ascontiguousarray(sol.xy),
        np.ascontiguousarray(sol.vel),
        np.ascontiguousarray(sol.acc),
        force,
        torque,
        reactions=reactions,
        n_threads=threads_arg(n_threads),
        out=block,
    )
    pairs = tuple((names[p], "frame" if b < 0 else body_names[b]) for p, b in model.pairs())
    return Kinetostatics._from_kernel(  # the kernel's output: checked by its tests, not per call
        sol,
        values,
        conditioning,
        pairs=pairs,
        guides=tuple(guide_names),
        analogs=analogs,
        own=True,
    )


def _out_block(out: Any, shape: tuple[int, int, int]) -> Array:
    """The (3, N, W) block of ``out``, a result of :func:`kinetostatics` (its force
    arrays are views of it), checked to take a solve of ``shape``."""
    block = getattr(getattr(out, "torque_parts", None), "base", None)
    if not (
        isinstance(out, Kinetostatics)
        and isinstance(block, np.ndarray)
        and block.shape == shape
        and block.dtype == np.float64
        and block.flags.c_contiguous
        and block.flags.writeable
    ):
        if isinstance(out, Kinetostatics):
            w = block.shape[2] if isinstance(block, np.ndarray) and block.ndim == 3 else "?"
            got = f"a result for {out.angles.size} angles with {w} values an angle and part"
            if isinstance(block, np.ndarray) and not block.flags.writeable:
                got += ", read-only"
        else:
            got = type(out).__name__
        raise InputError(
            f"out must be a Kinetostatics that kinetostatics returned for {shape[1]} angles "
            f"with {shape[2]} values an angle and part (the same guides and joint forces, "
            f"reactions alike), its arrays writeable; got {got}"
        )
    return block


def _load_arrays(
    loads: Sequence[PointLoad | LinkTorque],
    angles: Array,
    names: list[str],
    links: list[list[str]],
    moving: list[int],
) -> tuple[Array | None, Array | None]:
    """The loads (checked by :func:`_build`) at the crank angles ``angles``: the
    point forces (N, P, 2) [N] and the link torques (N, B) [N·m], None for none."""
    n = angles.size
    force = torque = None
    idx = {p: i for i, p in enumerate(names)}
    for load in loads:
        if isinstance(load, PointLoad):
            if force is None:
                force = np.zeros((n, len(names), 2))
            force[:, idx[load.point]] += load.at(angles)
        else:
            b = _link_index(links, moving, load.link, "loads: a torque")
            if torque is None:
                torque = np.zeros((n, len(moving)))
            torque[:, b] += load.at(angles)
    return force, torque


def _solution(linkage: Linkage, angles: Any, n_threads: int | None) -> LinkageSolution:
    """``angles`` solved, or ``angles`` itself when it is a solution of every
    point of ``linkage`` with analogs."""
    if hasattr(angles, "names") and hasattr(angles, "xy"):
        sol = angles
        if tuple(sol.names) != tuple(linkage.names) or sol.vel is None or sol.xy.ndim != 3:
            raise InputError(
                "kinetostatics needs a solution of every point of the linkage, with analogs, "
                f"of one geometry: solve it with linkage.solve(angles); got points {sol.names}"
                f"{'' if sol.vel is not None else ' without analogs'}"
            )
        return sol
    sol = linkage.solve(angles, n_threads)
    assert sol.vel is not None and sol.acc is not None
    return sol


def check_dynamics(
    linkage: Linkage,
    *,
    masses: Mapping[Sequence[str], LinkMass] | None = None,
    point_masses: Mapping[str, float] | None = None,
    loads: Sequence[PointLoad | LinkTorque] = (),
    gravity: Sequence[float] | None = None,
) -> None:
    """Check :func:`kinetostatics`'s keywords against a linkage without solving it.

    Every link and point named exists, masses are ≥ 0, gravity is (gx, gy), and
    the linkage's forces are statically determinate.

    Parameters
    ----------
    linkage : Linkage
        The linkage.
    masses : mapping of tuple of str to LinkMass, optional
        As :func:`kinetostatics`'s: moving links to their :class:`LinkMass`.
    point_masses : mapping of str to float, optional
        As :func:`kinetostatics`'s: moving points to lumped masses [kg].
    loads : sequence of PointLoad and LinkTorque, default ()
        As :func:`kinetostatics`'s: the external forces [N] and torques [N·m].
    gravity : tuple of (float, float), optional
        As :func:`kinetostatics`'s: (gx, gy) [m/s²].

    Raises
    ------
    InputError
        The error :func:`kinetostatics` would raise.
    TypeError
        If ``linkage`` is not a :class:`~cyclomech.Linkage`.

    Examples
    --------
    >>> import cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.3, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> check_dynamics(crank, point_masses={"B": 1.0})
    Traceback (most recent call last):
      ...
    cyclomech._errors.InputError: point_masses: no point 'B'; the points are O, A
    """
    _build(linkage, masses, point_masses, loads, gravity)
