"""Balancing a linkage by counterweights on its links pivoted to the frame
(:func:`balance`, :class:`Balance`, :class:`Counterweight`; issue 34, item 4).

**The counterweight.** On a link pivoted to the frame at P, a counterweight is
the vector w = (m r cos α, m r sin α) [kg·m] in the link's frame: origin at P, u
from P towards the link's first other joint (in the linkage's point order), v
to its left, α counter-clockwise from u. It is a point mass m = |w|/r at the
radius r the designer puts it at (``radius_m``; default the link's length from
P to that joint, e.g. the crank's radius). With the link's angle θ(φ) and its
analogs θ′, θ″ (per crank radian) and E(θ) the rotation to the plane's frame:

* shaking force, −m c̈ = ω²·(θ′² E − θ″ J E) w + ε·(−θ′ J E) w: **linear** in w
  (J the +90° turn); the counterweight's weight g|w|/r is static;
* shaking moment about Q, −dH/dt = (P − Q) × (force) − θ̈·r|w|: its own inertia
  about P, J_P = m r² = |w|·r, enters through the length |w|;
* driving torque, from the power it takes: θ′·(|w|·r·θ̈ − g·(J E w)), θ̈ = θ″ω² + θ′ε.

So the RMS of the shaking force at constant speed is a linear least-squares
problem in the counterweights' vectors (exact, one ``lstsq``; it does not depend
on the speed, the force scaling as ω²); the peak force (min-max, an epigraph
solved by SLSQP) and SAM's criterion RMS force + weight × RMS driving torque
(the torque's J_P term is not linear) go through scipy's optimisers, their
designs evaluated by the Rust batch (:meth:`Balance.evaluate`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import finite_number, float_array, positive, threads_arg
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ..forces import Kinetostatics
from ..linkage import Linkage
from ._shaking import Shaking, _cross, shaking

__all__ = ["OBJECTIVES", "Balance", "Counterweight", "balance"]

Array = npt.NDArray[np.float64]

#: The objectives :func:`balance` minimises.
OBJECTIVES = ("rms_force", "peak_force", "rms_force+torque")

#: The columns of :meth:`Balance.evaluate`, from the Rust kernel.
STATS = tuple(_core.SHAKING_STATS)


@dataclass(frozen=True)
class Counterweight:
    """One counterweight of a :class:`Balance`: where it is and how heavy.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    link : str
        The link, its joints joined by "-" (as ``Kinetostatics.pairs`` names it).
    pivot : str
        Its ground joint, the origin of the link's frame.
    towards : str
        The joint the link frame's u axis points to.
    radius_m : float
        The radius of the counterweight's mass from the pivot [m].
    vector_kg_m : tuple of (float, float)
        (m r cos α, m r sin α) in the link's frame [kg·m].

    Raises
    ------
    InputError
        If a name is not a str, ``radius_m`` is not a finite number > 0 or
        ``vector_kg_m`` not two finite numbers.

    Examples
    --------
    >>> c = Counterweight("O-A", "O", "A", 0.1, (-0.6, 0.0))
    >>> c.mass_radius_kg_m, c.angle_deg, round(c.mass_kg, 9)
    (0.6, 180.0, 6.0)
    """

    link: str
    pivot: str
    towards: str
    radius_m: float
    vector_kg_m: tuple[float, float]

    def __post_init__(self) -> None:
        for name in ("link", "pivot", "towards"):
            if not isinstance(getattr(self, name), str):
                raise InputError(f"{name} = {getattr(self, name)!r} must be a name (str)")
        object.__setattr__(self, "radius_m", positive("radius_m", self.radius_m, "[m]"))
        v = self.vector_kg_m
        if isinstance(v, str) or not hasattr(v, "__len__") or len(v) != 2:
            raise InputError(f"vector_kg_m = {v!r} must be (m r cos α, m r sin α) [kg·m]")
        vec = (
            finite_number("vector_kg_m[0]", v[0], "[kg·m]"),
            finite_number("vector_kg_m[1]", v[1], "[kg·m]"),
        )
        object.__setattr__(self, "vector_kg_m", vec)

    @property
    def mass_radius_kg_m(self) -> float:
        """m·r [kg·m], the vector's length.

        Examples
        --------
        >>> Counterweight("O-A", "O", "A", 0.1, (0.3, 0.4)).mass_radius_kg_m
        0.5
        """
        return float(math.hypot(*self.vector_kg_m))

    @property
    def angle_deg(self) -> float:
        """α [deg] in (−180, 180] in the link's frame, counter-clockwise from the
        pivot→``towards`` axis.

        Examples
        --------
        >>> Counterweight("O-A", "O", "A", 0.1, (0.0, 1.0)).angle_deg
        90.0
        """
        deg = math.degrees(math.atan2(self.vector_kg_m[1], self.vector_kg_m[0]))
        return float(deg + 360.0 if deg <= -180.0 else deg)  # −0.0 below the axis: 180°

    @property
    def mass_kg(self) -> float:
        """m = m·r / r [kg] at ``radius_m``.

        Examples
        --------
        >>> Counterweight("O-A", "O", "A", 0.5, (1.0, 0.0)).mass_kg
        2.0
        """
        return self.mass_radius_kg_m / self.radius_m


@dataclass(frozen=True)
class _Site:
    """A counterweight's place: the link, its pivot P (index), the u joint, the
    radius and the link's angle analogs over the angles."""

    link: str
    pivot: int
    towards: int
    radius: float
    e: Array  # (N, 2, 2): E(θ), the link frame's axes as columns
    d1: Array  # θ′ (N,)
    d2: Array  # θ″ (N,)


def _sites(k: Kinetostatics, counterweights: Any) -> list[_Site]:
    """The counterweights' sites, every name checked."""
    names = list(k.solution.names)
    ground = {p for p, ln in k.pairs if ln == "frame"}
    joints: dict[str, list[str]] = {}
    for p, ln in k.pairs:
        if ln != "frame":
            joints.setdefault(ln, []).append(p)
    pivoted = [ln for ln, js in joints.items() if len(set(js) & ground) == 1]
    valid = ", ".join(pivoted) or "none"
    if isinstance(counterweights, Mapping):
        items = list(counterweights.items())
    elif isinstance(counterweights, str) or not isinstance(counterweights, Sequence):
        raise InputError(
            f"counterweights = {counterweights!r} must be a list of links (their joints, "
            f"e.g. ('O', 'A')) or a mapping of links to radii [m]; the links pivoted to "
            f"the frame are {valid}"
        )
    else:
        items = [(c, None) for c in counterweights]
    if not items:
        raise InputError(f"counterweights: none given; the links pivoted to the frame are {valid}")
    xy, vel, acc = k.solution.xy, k.solution.vel, k.solution.acc
    assert vel is not None and acc is not None
    out: list[_Site] = []
    for key, radius in items:
        want = set(key.split("-")) if isinstance(key, str) else key
        if not isinstance(want, set | tuple | list) or not all(isinstance(p, str) for p in want):
            raise InputError(
                f"counterweights: {key!r} must be a link's joints, e.g. ('O', 'A'); the "
                f"links pivoted to the frame are {valid}"
            )
        link = next((ln for ln, js in joints.items() if set(js) == set(want)), None)
        if link is None:
            raise InputError(
                f"counterweights: no moving link has the joints {'-'.join(want)}; the "
                f"links pivoted to the frame are {valid}"
            )
        if link not in pivoted:
            raise InputError(
                f"counterweights: the link {link} is not pivoted to the frame (it turns "
                f"about no fixed point: a counterweight there is no vector m·r); the links "
                f"pivoted to the frame are {valid}"
            )
        if any(s.link == link for s in out):
            raise InputError(f"counterweights: the link {link} is given twice; give it once")
        js = joints[link]
        piv = names.index(next(j for j in js if j in ground))
        tip = names.index(next(j for j in js if j not in ground))
        d = xy[:, tip] - xy[:, piv]
        length = float(np.hypot(*d[0]))
        r = length if radius is None else positive(f"counterweights[{link!r}]", radius, "[m]")
        dd = np.einsum("ni,ni->n", d, d)
        ex = d / np.sqrt(dd)[:, None]
        e = np.stack([np.stack([ex[:, 0], -ex[:, 1]], -1), np.stack([ex[:, 1], ex[:, 0]], -1)], 1)
        # θ′ = d × d′ / |d|², θ″ = d × d″ / |d|² (|d| constant on a rigid link).
        th1, th2 = _cross(d, vel[:, tip]) / dd, _cross(d, acc[:, tip]) / dd
        out.append(_Site(link, piv, tip, r, e, th1, th2))
    return out


def _turn(e: Array) -> Array:
    """J·E: the +90° turn of E's columns (N, 2, 2)."""
    return np.stack([-e[:, 1], e[:, 0]], axis=1)


@dataclass(frozen=True)
class _Form:
    """The linear form of the four channels at a speed (see the Rust kernel)."""

    base: Array  # (4, N)
    lin: Array  # (4, J, N, 2)
    nrm: Array  # (4, J, N)


def _form(s: Shaking, torque: Array, sites: list[_Site], xy: Array, w2: float, g: Array) -> _Form:
    """base, lin, nrm of [F_x, F_y, M, T] at ω² = ``w2`` (constant speed);
    ``torque`` the driving torque's parts (3, N)."""
    n, j = s.angles_deg.size, len(sites)
    base = np.stack(
        [
            w2 * s.force_parts[0, :, 0],
            w2 * s.force_parts[0, :, 1],
            w2 * s.moment_parts[0],
            w2 * torque[0] + torque[2],
        ]
    )
    lin = np.zeros((4, j, n, 2))
    nrm = np.zeros((4, j, n))
    q = np.array(s.about_m)
    for i, st in enumerate(sites):
        a2 = st.d1[:, None, None] ** 2 * st.e - st.d2[:, None, None] * _turn(st.e)
        lin[0, i], lin[1, i] = w2 * a2[:, 0], w2 * a2[:, 1]
        a = xy[:, st.pivot] - q  # (P − Q) × (A w) = [−a_y, a_x] · A w
        lin[2, i] = w2 * np.einsum("ni,nij->nj", np.stack([-a[:, 1], a[:, 0]], -1), a2)
        nrm[2, i] = -w2 * st.d2 * st.radius
        lin[3, i] = -st.d1[:, None] * np.einsum("i,nij->nj", g, _turn(st.e))
        nrm[3, i] = w2 * st.d1 * st.d2 * st.radius
    return _Form(base, lin, nrm)


def _after(s: Shaking, sites: list[_Site], xy: Array, w: Array, g: Array) -> Shaking:
    """``s`` with the counterweights ``w`` (J, 2) added, every part."""
    f, m = s.force_parts.copy(), s.moment_parts.copy()
    q = np.array(s.about_m)
    for st, wj in zip(sites, w, strict=True):
        length = float(np.hypot(*wj))
        ew, jew = st.e @ wj, _turn(st.e) @ wj
        a = xy[:, st.pivot] - q
        parts = (st.d1[:, None] ** 2 * ew - st.d2[:, None] * jew, -st.d1[:, None] * jew)
        for i, fi in enumerate(parts):
            f[i] += fi
            m[i] += _cross(a, fi) - (st.d2, st.d1)[i] * st.radius * length
        weight = g * length / st.radius
        f[2] += weight
        m[2] += _cross(a, weight[None]) + _cross(ew, g[None])
    return replace(s, force_parts=f, moment_parts=m)


def _torque_after(torque: Array, sites: list[_Site], w: Array, g: Array) -> Array:
    """The driving torque's parts (3, N) with the counterweights ``w`` added."""
    t = torque.copy()
    for st, wj in zip(sites, w, strict=True):
        rl = st.radius * float(np.hypot(*wj))
        t[0] += st.d1 * st.d2 * rl
        t[1] += st.d1**2 * rl
        t[2] -= st.d1 * np.einsum("i,ni->n", g, _turn(st.e) @ wj)
    return t


@dataclass(frozen=True)
class Balance:
    """A linkage balanced by counterweights: where they go, before and after.

    ``before`` and ``after`` hold the statistics at ``rpm`` (``STATS`` with
    units: ``rms_force_n``, ``peak_force_n``, ``rms_moment_nm``, ``peak_moment_nm``,
    ``rms_torque_nm``, ``peak_torque_nm``; the force and moment are the shaking
    ones, inertia only, the torque the driving torque with the static loads).
    Built by :func:`balance`; each parameter is kept as the attribute of the same
    name.

    Parameters
    ----------
    objective : str
        The objective minimised (one of :data:`OBJECTIVES`).
    rpm : float
        The crank speed of the statistics [rpm].
    counterweights : tuple of Counterweight
        The counterweights found.
    before : dict of str to float
        The statistics without counterweights.
    after : dict of str to float
        The statistics with them.
    shaking_before : Shaking
        The shaking without counterweights.
    shaking_after : Shaking
        The shaking with them (their weight in the static part).
    torque_parts_after : ndarray of float, shape (3, N)
        The driving torque's parts (per ω², per ε, static) with them [N·m·s², N·m].
    form : object
        The linear form at ``rpm`` that :meth:`evaluate` reads.
    torque_weight : float or None, default None
        The RMS torque's weight [1/m] when the objective is ``"rms_force+torque"``.
    max_mass_radius_kg_m : float or None, default None
        The bound on each counterweight's m·r [kg·m], if one was given.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 10.0)),
    ...                             point_masses={"A": 2.0})
    >>> b = cm.dynamics.balance(k, counterweights=[("O", "A")], rpm=600.0)
    >>> c = b.counterweights[0]
    >>> round(c.mass_radius_kg_m, 9), round(c.angle_deg, 6), round(b.after["rms_force_n"], 6)
    (0.2, 180.0, 0.0)
    """

    objective: str
    rpm: float
    counterweights: tuple[Counterweight, ...]
    before: dict[str, float]
    after: dict[str, float]
    shaking_before: Shaking
    shaking_after: Shaking
    torque_parts_after: Array
    form: Any
    torque_weight: float | None = None
    max_mass_radius_kg_m: float | None = None

    @property
    def at_bound(self) -> tuple[str, ...]:
        """The links whose counterweight sits at ``max_mass_radius_kg_m`` (to 1e-6):
        the optimum wants a heavier one there, the bound decided it.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 10.0)),
        ...                             point_masses={"A": 2.0})
        >>> cm.dynamics.balance(k, counterweights=[("O", "A")], rpm=600.0,
        ...                     max_mass_radius_kg_m=0.15).at_bound   # 0.2 kg·m wanted
        ('O-A',)
        """
        b = self.max_mass_radius_kg_m
        if b is None:
            return ()
        return tuple(c.link for c in self.counterweights if c.mass_radius_kg_m >= b * (1 - 1e-6))

    def evaluate(self, designs: Any, *, n_threads: int | None = None) -> dict[str, Array]:
        """The statistics of many counterweight designs at ``rpm``, in one Rust call.

        Designs in parallel, the GIL released; only the statistics are kept (10 000
        designs × 3600 angles never hold the curves).

        Parameters
        ----------
        designs : array_like of float, shape (D, J, 2)
            D designs of the J counterweights' vectors (m r cos α, m r sin α) [kg·m],
            in the order of ``counterweights``, at their radii.
        n_threads : int, optional
            Threads; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        dict of str to ndarray of float, shape (D,)
            ``rms_force_n``, ``peak_force_n``, ``rms_moment_nm``, ``peak_moment_nm``,
            ``rms_torque_nm``, ``peak_torque_nm`` of each design.

        Raises
        ------
        InputError
            If ``designs`` is not of shape (D, J, 2) or not finite, or ``n_threads``
            is not a positive count.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 10.0)),
        ...                             point_masses={"A": 2.0})
        >>> b = cm.dynamics.balance(k, counterweights=[("O", "A")], rpm=600.0)
        >>> b.evaluate([[[0.0, 0.0]], [[-0.1, 0.0]]])["rms_force_n"].round(3).tolist()
        [789.568, 394.784]
        """
        return _evaluate(self.form, designs, n_threads)

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table: each statistic before and after, and each counterweight.

        Returns
        -------
        header : list of str
            ``["quantity", "before", "after"]``.
        rows : list of list
            The statistics, then one row per counterweight (m·r [kg·m], α [deg]
            and m [kg] at its radius).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
        >>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 10.0)),
        ...                             point_masses={"A": 2.0})
        >>> cm.dynamics.balance(k, counterweights=[("O", "A")], rpm=600.0).table()[1][0][0]
        'RMS shaking force [N]'
        """
        labels = {
            "rms_force_n": "RMS shaking force [N]",
            "peak_force_n": "peak shaking force [N]",
            "rms_moment_nm": "RMS shaking moment [N·m]",
            "peak_moment_nm": "peak shaking moment [N·m]",
            "rms_torque_nm": "RMS driving torque [N·m]",
            "peak_torque_nm": "peak driving torque [N·m]",
        }
        rows: list[list[Any]] = [[v, self.before[k], self.after[k]] for k, v in labels.items()]
        bound = self.at_bound
        for c in self.counterweights:
            rows.append(
                [
                    f"counterweight on {c.link} at r = {c.radius_m:g} m: "
                    "m·r [kg·m], α [deg], m [kg]",
                    "",
                    f"{c.mass_radius_kg_m:.4g}, {c.angle_deg:.2f}, {c.mass_kg:.4g}"
                    + (
                        f" (at the bound max_mass_radius_kg_m = {self.max_mass_radius_kg_m:g}: "
                        "the optimum wants more)"
                        if c.link in bound
                        else ""
                    ),
                ]
            )
        return ["quantity", "before", "after"], rows


_UNITS = (
    "rms_force_n",
    "peak_force_n",
    "rms_moment_nm",
    "peak_moment_nm",
    "rms_torque_nm",
    "peak_torque_nm",
)


def _evaluate(form: _Form, designs: Any, n_threads: int | None) -> dict[str, Array]:
    j = form.lin.shape[1]
    d = float_array("designs", designs, ndims=(3,))
    if d.shape[1:] != (j, 2):
        raise InputError(f"designs must be of shape (D, {j}, 2) [kg·m]; got {d.shape}")
    out = _core.shaking_batch(form.base, form.lin, form.nrm, d, n_threads=threads_arg(n_threads))
    return {k: out[:, i] for i, k in enumerate(_UNITS)}


def _stats(form: _Form, w: Array) -> dict[str, float]:
    return {k: float(v[0]) for k, v in _evaluate(form, w[None], None).items()}


def _within(w: Array, bound: float | None) -> Array:
    """``w`` (J, 2) with each counterweight's m·r shrunk to ``bound`` where above."""
    if bound is None:
        return w
    size = np.hypot(w[:, 0], w[:, 1])
    out: Array = w * np.minimum(1.0, bound / np.maximum(size, 1e-300))[:, None]
    return out


def _bound_constraint(j: int, bound: float, extra: int) -> dict[str, Any]:
    """SLSQP's inequality B² − |w_j|² ≥ 0 for each counterweight, on x = (w, ``extra``
    more variables), scaled by B²."""

    def fun(x: Array) -> Array:
        w = x[: 2 * j].reshape(j, 2)
        out: Array = 1.0 - np.einsum("ji,ji->j", w, w) / bound**2
        return out

    def jac(x: Array) -> Array:
        w = x[: 2 * j].reshape(j, 2)
        out = np.zeros((j, 2 * j + extra))
        for i in range(j):
            out[i, 2 * i : 2 * i + 2] = -2.0 * w[i] / bound**2
        return out

    return {"type": "ineq", "fun": fun, "jac": jac}


def _rms_bounded(form: _Form, w0: Array, bound: float) -> Array:
    """The design of least RMS force with each |w_j| ≤ ``bound``: the least squares
    of the force at ``rpm`` (linear in w) under the bounds, by SLSQP from the
    unbounded design shrunk to them (a convex problem: its optimum is the one)."""
    from scipy.optimize import minimize

    j = form.lin.shape[1]
    base = form.base[:2].T.ravel()  # (N·2)
    a = np.moveaxis(form.lin[:2], 0, 2)  # (J, N, 2 [channel], 2)
    mat = np.moveaxis(a, 0, 2).reshape(-1, 2 * j)  # rows (n, channel)
    scale = float(np.abs(base).max(initial=0.0)) or 1.0
    mat_s, base_s = mat / scale, base / scale

    def f(x: Array) -> float:
        r = mat_s @ x + base_s
        return float(r @ r)

    def g(x: Array) -> Array:
        out: Array = 2.0 * mat_s.T @ (mat_s @ x + base_s)
        return out

    res = minimize(
        f,
        _within(w0, bound).ravel(),
        jac=g,
        constraints=[_bound_constraint(j, bound, 0)],
        method="SLSQP",
        options={"maxiter": 500, "ftol": 1e-15},
    )
    out: Array = _within(res.x.reshape(j, 2), bound)
    return out


def _peak(form: _Form, w0: Array, bound: float | None = None) -> Array:
    """The design of least peak force: min t s.t. t² ≥ |F_n(w)|² at every angle
    (and each |w_j| ≤ ``bound``), by SLSQP from ``w0`` (the least-squares design)."""
    from scipy.optimize import minimize

    j = form.lin.shape[1]
    base = form.base[:2].T  # (N, 2)
    a = np.moveaxis(form.lin[:2], 0, 2)  # (J, N, 2 [channel], 2)
    scale = float(np.abs(form.base[:2]).max(initial=0.0)) or 1.0

    def force(x: Array) -> Array:
        out: Array = base + np.einsum("jncb,jb->nc", a, x[:-1].reshape(j, 2))
        return out / scale

    def cons(x: Array) -> Array:
        f = force(x)
        out: Array = x[-1] ** 2 - np.einsum("nc,nc->n", f, f)
        return out

    def jac(x: Array) -> Array:
        f = force(x)
        dw = -2.0 * np.einsum("nc,jncb->njb", f, a).reshape(f.shape[0], -1) / scale
        return np.concatenate([dw, 2.0 * x[-1] * np.ones((f.shape[0], 1))], axis=1)

    w0 = _within(w0, bound)
    x0 = np.concatenate([w0.ravel(), [float(np.sqrt((force(np.append(w0, 0)) ** 2).sum(1).max()))]])
    constraints = [{"type": "ineq", "fun": cons, "jac": jac}]
    if bound is not None:
        constraints.append(_bound_constraint(j, bound, 1))
    res = minimize(
        lambda x: x[-1],
        x0,
        jac=lambda x: np.eye(x.size)[-1],
        constraints=constraints,
        method="SLSQP",
        options={"maxiter": 500, "ftol": 1e-12},
    )
    best: Array = _within(res.x[:-1].reshape(j, 2), bound)
    return best


def _weighted(form: _Form, w0: Array, weight: float, bound: float | None = None) -> Array:
    """The design of least RMS force + weight × RMS torque, by Nelder–Mead from
    the least-squares design and from none (the better of the two). With a
    ``bound`` on each |w_j|, a design beyond it is read at the bound plus a
    penalty on the excess (Nelder–Mead takes no constraints), so the search
    ends inside or on it."""
    from scipy.optimize import minimize

    j = form.lin.shape[1]
    w0 = _within(w0, bound)
    # The penalty's scale: the objective's size at no counterweight, per kg·m.
    s0 = _evaluate(form, np.zeros((1, j, 2)), None)
    unit = float(s0["rms_force_n"][0] + weight * s0["rms_torque_nm"][0]) / (bound or 1.0)

    def f(x: Array) -> float:
        w = x.reshape(j, 2)
        at = _within(w, bound)
        s = _evaluate(form, at[None], None)
        excess = float(np.abs(w - at).sum()) * (unit or 1.0)
        return float(s["rms_force_n"][0] + weight * s["rms_torque_nm"][0]) + excess

    scale = max(float(np.abs(w0).max(initial=0.0)), 1e-6)
    results = []
    for start in (w0.ravel(), np.zeros(2 * j)):
        simplex = np.vstack([start, start + scale * 0.2 * np.eye(2 * j)])
        results.append(
            minimize(
                f,
                start,
                method="Nelder-Mead",
                options={
                    "initial_simplex": simplex,
                    "xatol": 1e-10 * scale,
                    "fatol": 1e-12,
                    "maxiter": 4000 * j,
                },
            )
        )
    best = min(results, key=lambda r: float(r.fun))
    out: Array = _within(best.x.reshape(j, 2), bound)
    if bound is not None:
        # Nelder–Mead creeps along a bound (the penalty's kink): polish by SLSQP
        # under the bounds from where it stopped, kept if better and inside them.
        def clean(x: Array) -> float:
            st = _evaluate(form, x.reshape(1, j, 2), None)
            return float(st["rms_force_n"][0] + weight * st["rms_torque_nm"][0])

        res = minimize(
            clean,
            out.ravel(),
            constraints=[_bound_constraint(j, bound, 0)],
            method="SLSQP",
            options={"maxiter": 200, "ftol": 1e-12},
        )
        polished = _within(res.x.reshape(j, 2), bound)
        if clean(polished.ravel()) < clean(out.ravel()):
            out = polished
    return out


def _arguments(
    objective: Any, rpm: Any, torque_weight: Any, max_mass_radius_kg_m: Any
) -> tuple[float, float, float | None]:
    """The balance's arguments checked: (rpm, torque weight, bound on m·r or None)."""
    if objective not in OBJECTIVES:
        raise InputError(f"objective = {objective!r} must be one of {', '.join(OBJECTIVES)}")
    n = positive("rpm", rpm, "[rpm]")
    weight = finite_number("torque_weight", torque_weight, "[1/m]", low=0.0)
    bound = (
        None
        if max_mass_radius_kg_m is None
        else positive("max_mass_radius_kg_m", max_mass_radius_kg_m, "[kg·m]")
    )
    return n, weight, bound


def balance(
    mechanism: Any,
    *,
    counterweights: Any,
    rpm: Any,
    objective: str = "rms_force",
    torque_weight: Any = 1.0,
    gravity: Any = None,
    linkage: Linkage | None = None,
    about_m: Any = (0.0, 0.0),
    max_mass_radius_kg_m: Any = None,
) -> Balance:
    """Counterweights on links pivoted to the frame that minimise the shaking.

    ``objective``: ``"rms_force"`` the RMS of the shaking force over the cycle (an
    exact linear least-squares solve: the force is linear in the counterweights'
    vectors, see :mod:`cyclomech.dynamics`; the optimum does not depend on the
    speed), ``"peak_force"`` its peak (SLSQP on the epigraph, from the
    least-squares design), ``"rms_force+torque"`` RMS force + ``torque_weight`` ×
    RMS driving torque at ``rpm`` (SAM's criterion; Nelder–Mead, the counterweight's
    own inertia m r² = |m r|·r about its pivot being non-linear). Constant speed.

    Parameters
    ----------
    mechanism : Kinetostatics or LinkageResult
        The linkage's forces over the cycle (uniform angles over one turn for the
        cycle's RMS), with reactions; or a machine's linkage result.
    counterweights : sequence of tuple of str, or mapping of tuple of str to float
        The links to counterweight (their joints, in any order, or their names
        ``"O-A"``), each pivoted to the frame; a mapping gives each one's radius [m]
        (default the link's length from its pivot to its first other joint).
    rpm : float
        The crank speed of the statistics and of the torque objective [rpm].
    objective : str, default "rms_force"
        One of :data:`OBJECTIVES`.
    torque_weight : float, default 1.0
        The weight of the RMS torque in ``"rms_force+torque"`` [N per N·m = 1/m] (≥ 0).
    gravity : tuple of (float, float), optional
        The gravity the kinetostatics was solved with (gx, gy) [m/s²], for the
        counterweights' own weight in the torque; default None (none).
    linkage : Linkage, optional
        The linkage of a ``Kinetostatics`` with guides (see :func:`shaking`).
    about_m : tuple of (float, float), default (0.0, 0.0)
        The point of the shaking moment (x, y) [m].
    max_mass_radius_kg_m : float, optional
        The largest m·r of each counterweight [kg·m] (> 0); default None (no
        bound). With it every objective goes through SLSQP or Nelder–Mead under
        the bound (the least squares too, when its optimum exceeds it), and
        :attr:`Balance.at_bound` names the counterweights it stopped.

    Returns
    -------
    Balance
        The counterweights and the statistics before and after.

    Raises
    ------
    InputError
        If a link is unknown, not pivoted to the frame or given twice, a radius is
        not > 0, ``objective`` is unknown, ``rpm`` or ``torque_weight`` is not a
        finite number (``torque_weight`` ≥ 0), ``gravity`` is not (gx, gy), or the
        forces are not finite at every angle.
    TypeError
        If ``mechanism`` is neither a Kinetostatics nor a linkage result.

    Examples
    --------
    A slider-crank's crank counterweight balances the rotating mass and half the
    reciprocating one at the least RMS force (m_A + m_C/2 at the crank's radius):

    >>> import numpy as np, cyclomech as cm
    >>> sc = cm.Linkage({"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
    ...                 [("A", "B"), ("B", "C")], ["A"], ("A", "B"),
    ...                 sliders={"C": ("ground", (1, 0))})
    >>> k = cm.forces.kinetostatics(sc, np.radians(np.arange(0.0, 360.0, 1.0)),
    ...                             point_masses={"B": 1.0, "C": 3.0})
    >>> b = cm.dynamics.balance(k, counterweights=[("A", "B")], rpm=300.0, linkage=sc)
    >>> c = b.counterweights[0]
    >>> round(c.mass_kg, 6), round(c.angle_deg, 3)
    (2.5, 180.0)
    """
    n, weight, bound = _arguments(objective, rpm, torque_weight, max_mass_radius_kg_m)
    g = np.zeros(2) if gravity is None else float_array("gravity", gravity)
    if g.shape != (2,) or not np.isfinite(g).all():
        raise InputError(f"gravity = {gravity!r} must be (gx, gy) [m/s²], finite")
    if isinstance(mechanism, Kinetostatics):
        k = mechanism
        s = shaking(k, linkage=linkage, about_m=about_m)
    elif isinstance(getattr(mechanism, "kinetostatics", None), Kinetostatics):
        k = mechanism.kinetostatics
        s = shaking(mechanism, about_m=about_m)
    else:
        raise TypeError(
            "mechanism must be a Kinetostatics or a machine's linkage result with forces; "
            f"got {type(mechanism).__name__}"
        )
    if not k.ok.all():
        bad = np.degrees(k.angles[~k.ok])[:6]
        raise InputError(
            f"mechanism: the forces are not finite at crank angles "
            f"{', '.join(f'{v:.1f}' for v in bad)} degrees (not assembled or a dead centre)"
        )
    sites = _sites(k, counterweights)
    return _solve(
        s, k.torque_parts, sites, k.solution.xy, k.solution.names, n, g, objective, weight, bound
    )


def _solve(
    s: Shaking,
    torque: Array,
    sites: list[_Site],
    xy: Array,
    names: Sequence[str],
    n: float,
    g: Array,
    objective: str,
    weight: float,
    bound: float | None,
) -> Balance:
    """The counterweights at ``sites`` for ``objective`` and their balance: ``s`` the
    shaking without them, ``torque`` the driving torque's parts (3, N), ``xy`` the
    points (N, P, 2) the sites' indices name (``names``), at ``n`` rpm."""
    form = _form(s, torque, sites, xy, (n * RAD_PER_S_PER_RPM) ** 2, g)
    # Least squares on the per-ω² force: the same optimum at every speed.
    a = np.moveaxis(_form(s, torque, sites, xy, 1.0, g).lin[:2], 0, 2)  # (J, N, 2, 2)
    mat = np.moveaxis(a, 0, 2).reshape(-1, 2 * len(sites))  # rows (n, channel)
    w, *_ = np.linalg.lstsq(mat, -s.force_parts[0].ravel(), rcond=None)
    w = w.reshape(len(sites), 2)
    if objective == "peak_force":
        w = _peak(form, w, bound)
    elif objective == "rms_force+torque":
        w = _weighted(form, w, weight, bound)
    elif bound is not None and np.hypot(w[:, 0], w[:, 1]).max() > bound:
        w = _rms_bounded(form, w, bound)
    cws = tuple(
        Counterweight(
            st.link,
            names[st.pivot],
            names[st.towards],
            st.radius,
            (float(wj[0]), float(wj[1])),
        )
        for st, wj in zip(sites, w, strict=True)
    )
    return Balance(
        objective=objective,
        rpm=n,
        counterweights=cws,
        before=_stats(form, np.zeros_like(w)),
        after=_stats(form, w),
        shaking_before=s,
        shaking_after=_after(s, sites, xy, w, g),
        torque_parts_after=_torque_after(torque, sites, w, g),
        form=form,
        torque_weight=weight if objective == "rms_force+torque" else None,
        max_mass_radius_kg_m=bound,
    )


#: The press's carrier, as a [[balance]] row names it: from the guide gear's centre
#: (the main shaft's axis, fixed) to the planet's centre.
PRESS_CARRIER = ("O", "planet")


def _press_balance(
    mechanism: Any,
    *,
    rpm: Any,
    objective: str = "rms_force",
    torque_weight: Any = 1.0,
    max_mass_radius_kg_m: Any = None,
    radius_m: Any = None,
) -> Balance:
    """A counterweight on a gear-lever press's carrier (its crank, turning with the
    main shaft about the guide gear's centre O) against the slider's and the rod's
    shaking (:func:`~cyclomech.dynamics.shaking`'s press part).

    The carrier is the link O → planet (its centre); the counterweight is the
    vector (m r cos α, m r sin α) in its frame, as on a linkage's crank
    (:func:`balance`, the same objectives and solvers). The carrier turns rigidly
    with the shaft, so its counterweight's force ω²·m·r turns with it: it takes
    out the force's part that turns with the crank, not the slider's higher
    harmonics. Constant speed; the carrier's and planet's own masses are not in
    the press's model; no gravity.

    Parameters
    ----------
    mechanism : PressResult
        A machine's press result (``result.mechanisms[name]``) with its masses and
        load (its shaft torque).
    rpm : float
        The crank speed of the statistics and of the torque objective [rpm].
    objective : str, default "rms_force"
        One of :data:`OBJECTIVES`.
    torque_weight : float, default 1.0
        The RMS torque's weight in ``"rms_force+torque"`` [1/m].
    max_mass_radius_kg_m : float, optional
        The largest m·r [kg·m]; default None (no bound).
    radius_m : float, optional
        The counterweight's radius [m]; default the carrier's length R − r.

    Returns
    -------
    Balance
        Its one counterweight, on the link ``"O-planet"``, and the statistics
        before and after on the press's own carrier angles ψ past BDC.

    Raises
    ------
    InputError
        If the press has no shaft torque (no load or optimum) or an argument is out
        of its range.
    TypeError
        If ``mechanism`` is not a press result.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/extrusion_press_line.toml"),
    ...                        progress=False)
    >>> b = _press_balance(r.mechanisms["drive"], rpm=40.0)
    >>> b.counterweights[0].link, b.after["rms_force_n"] < b.before["rms_force_n"]
    ('O-planet', True)
    """
    from ..press import GearLeverPress
    from ._shaking import _of_press

    m: Any = getattr(mechanism, "mech", None)
    press = getattr(m, "press", None)
    if not isinstance(press, GearLeverPress) or not hasattr(mechanism, "shaft_torque"):
        raise TypeError(
            f"mechanism must be a machine's press result; got {type(mechanism).__name__}"
        )
    n, weight, bound = _arguments(objective, rpm, torque_weight, max_mass_radius_kg_m)
    curve, inertia = mechanism.shaft_torque(), mechanism.shaft_inertia()
    if curve is None or inertia is None:
        raise InputError(
            "mechanism: the press has no torque on the main shaft (a deformation_force "
            "and an optimum are needed): nothing to balance"
        )
    size = curve[0].size
    s = _of_press(press, m.slider_mass, m.rod_mass, (0.0, 0.0), size)
    torque = np.stack([curve[0], inertia[0], curve[1]])
    psi = np.arange(size, dtype=np.float64) * (2.0 * math.pi / size)
    centre = press.solve(np.mod(-psi, 2.0 * math.pi)).centre  # (N, 2), O at the origin
    length = float(np.hypot(*centre[0]))
    r = length if radius_m is None else positive("radius_m", radius_m, "[m]")
    ex = centre / np.hypot(centre[:, 0], centre[:, 1])[:, None]
    e = np.stack([np.stack([ex[:, 0], -ex[:, 1]], -1), np.stack([ex[:, 1], ex[:, 0]], -1)], 1)
    # The carrier turns with the shaft, θ = θ0 ± ψ: its sign from two samples.
    turn = float(_cross(ex[0], ex[1])) / (psi[1] - psi[0])
    sign = 1.0 if turn > 0 else -1.0
    site = _Site("-".join(PRESS_CARRIER), 0, 1, r, e, np.full(size, sign), np.zeros(size))
    xy = np.stack([np.zeros_like(centre), centre], axis=1)
    return _solve(s, torque, [site], xy, PRESS_CARRIER, n, np.zeros(2), objective, weight, bound)
