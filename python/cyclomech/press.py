"""The planetary gear-lever press drive of seed 003: kinematics, working-stroke
criteria, design sweeps and the non-dominated designs.

The drive: a crank (carrier) turns about the centre O of a fixed internal guide
gear of pitch radius R; a planet gear of radius r rolls inside it (i = R/r, a
whole number; the seed uses 3), so the planet centre is C = (R − r)·e^{iθ} and
the planet turns at −(R − r)/r times the carrier; the rod (length L) hangs on the
planet at eccentricity d, its pin tracing a hypotrochoid; the slider runs on the
vertical guide x = ``offset`` below O. ``phi0`` is the setting angle of the guide
gear: the angle it is turned from the setting in which the pin lies on the
carrier line, outwards, when the carrier points straight down (turning the guide
gear by φ0 turns the planet by i·φ0 relative to the carrier). Designs repeat with
period 2π/i in φ0. With d = 0 the drive is a plain crank-slider of radius R − r,
the baseline every design is compared with.

Angles follow the seed: the carrier turns counterclockwise, and α is the crank
angle counted from the slider's bottom dead centre (BDC) *against* the motion,
so S = Π(α) ≥ 0 is the slider's height above BDC and the working stroke is the
approach to BDC, α from α_p down to 0, where α_p is the first contact with the
blank coming down from TDC (see :class:`PressCriteria` for a slider that leaves
the blank and meets it again). Π' = dS/dα [m/rad], Π'' [m/rad²]; at a
constant crank speed ω the slider speed is |Π'|·ω and its acceleration Π''·ω².

Criteria (:class:`PressCriteria`, all from the Rust kernel): the nominal stroke
S_n, the working stroke S_p = k_Sp·S_n and its crank angle α_p, the slider speed
at its start V_np, its mean V_cp = S_p·ω/α_p and maximum V_pmax over it, the
largest acceleration J_max over the turn, the torque arm (max Π' over the
working stroke: the crank torque per newton of a constant deformation force)
and the dimensionless k_Sp, k_Vp = V_np/V_cp (→ 0), k_Vmax = V_pmax/V_cp
(→ 1), k_M = torque/(S_n/2) and k_J = J_max/(ω²·S_n/2) (→ min; both 1 + λ-ish
for a crank-slider).
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from . import _core
from ._arrays import check_bytes, finite_number, float_array, threads_arg
from ._errors import InfeasibleError, InputError
from ._units import RAD_PER_S_PER_RPM

__all__ = [
    "CRITERIA",
    "OBJECTIVES",
    "SAMPLES",
    "STATUS",
    "GearLeverPress",
    "PressCriteria",
    "PressKinematics",
    "PressOptimum",
    "PressStudy",
    "PressSweep",
    "optimize",
    "pareto_mask",
    "sweep",
]

#: Names of the criteria, in the kernel's column order.
CRITERIA: tuple[str, ...] = tuple(_core.press_criteria_names())
#: Meaning of the status codes of a design.
STATUS = dict(enumerate(_core.PRESS_STATUS))
#: Carrier angles sampled per turn when criteria are computed.
SAMPLES = 360
_AXES = ("R", "r", "d", "L", "phi0")


@dataclass(frozen=True)
class PressKinematics:
    """The drive over a grid of α [rad] (from BDC against the motion).

    ``s`` = Π(α) [m], ``ds`` = Π' [m/rad], ``dds`` = Π'' [m/rad²], shape (N,);
    ``centre`` (planet centre), ``pin`` (rod pin) and ``slider`` (N, 2) [m] in
    the frame of the guide gear's centre; ``ok`` is False where the rod cannot
    reach the guide (NaN there; centre and pin are still given).
    """

    alpha: npt.NDArray[np.float64]
    s: npt.NDArray[np.float64]
    ds: npt.NDArray[np.float64]
    dds: npt.NDArray[np.float64]
    centre: npt.NDArray[np.float64]
    pin: npt.NDArray[np.float64]
    slider: npt.NDArray[np.float64]
    ok: npt.NDArray[np.bool_]


@dataclass(frozen=True)
class PressCriteria:
    """Working-stroke criteria of one design at crank speed ``omega`` [rad/s].

    Lengths [m], speeds [m/s], accelerations [m/s²], angles [rad]; ``torque`` is
    the largest Π' over the working stroke [m] (crank torque per newton of
    constant deformation force); ``theta_bdc`` the carrier angle of BDC. ``status``
    says why a design fails (``ok`` False: its criteria are NaN, except for a
    slider that moves back up during the working stroke, which keeps them).

    The working stroke starts at the *first contact*: coming down from TDC, the first
    α where S = S_p is ``alpha_p`` (``V_np`` the speed there). A slider that then backs
    off above S_p (by more than 1e-9 of the stroke) and comes down on the blank again
    before BDC *re-contacts* (status 4, :data:`STATUS`); one that moves back up without
    leaving the blank has status 2. Both keep their criteria (from the first contact)
    and fail (``ok`` False): sweeps mark them and :func:`optimize` drops them. S_p is
    watched from TDC down to BDC only, the blank taken to be in place from TDC: a
    slider that also dips below S_p on its way up (two strokes a turn; about 1 % of
    i = 3 designs, near φ0 = 60°) is not flagged for it.

    >>> import math, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.028, L=0.46, phi0=math.radians(56))
    >>> c = p.criteria(k_Sp=0.1, omega=2 * math.pi * 40 / 60)
    >>> c.status[:11], round(math.degrees(c.alpha_p), 1), round(c.V_np * 1e3, 1)
    ('re-contacts', 126.2, 57.7)

    Mirror-symmetric designs (no offset, e.g. i = 3 with φ0 = π/3) have two equally
    low BDCs or two equally high TDCs. Dead centres within 1e-12 of the stroke tie;
    of tied BDCs the one at the smallest carrier angle in [0, 2π) is taken, of tied
    TDCs the first reached going back from that BDC, so every way of writing φ0
    gives the same criteria (and :meth:`GearLeverPress.solve` counts α from the same
    BDC).
    """

    S_n: float
    S_p: float
    alpha_p: float
    V_np: float
    V_cp: float
    V_pmax: float
    J_max: float
    torque: float
    k_Sp: float
    k_Vp: float
    k_Vmax: float
    k_M: float
    k_J: float
    theta_bdc: float
    omega: float
    status: str

    @property
    def ok(self) -> bool:
        """True when the design works over the whole turn and the working stroke."""
        return self.status == STATUS[0]

    def as_dict(self) -> dict[str, float | str]:
        """The criteria by name (for tables and JSON).

        >>> import cyclomech as cm
        >>> c = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> sorted(c.criteria(k_Sp=0.1, omega=4.0).as_dict())[:3]
        ['J_max', 'S_n', 'S_p']
        """
        return {k: getattr(self, k) for k in (*CRITERIA, "omega", "status")}


def _stroke(k_Sp: Any, working_stroke: Any) -> tuple[float | None, float | None]:
    if (k_Sp is None) == (working_stroke is None):
        raise InputError(
            "give exactly one of k_Sp (working stroke as a fraction of the nominal stroke) "
            "and working_stroke (S_p [m])"
        )
    if k_Sp is not None:
        k = finite_number("k_Sp", k_Sp, "(a fraction of the nominal stroke)")
        if not 0 < k <= 1:
            raise InputError(f"k_Sp = {k_Sp!r} must lie in (0, 1] (S_p/S_n)")
        return k, None
    s = finite_number("working_stroke", working_stroke, "[m]")
    if s <= 0:
        raise InputError(f"working_stroke = {working_stroke!r} must be > 0 [m]")
    return None, s


def _omega(omega: Any) -> float:
    w = finite_number("omega", omega, "[rad/s]")
    if w <= 0:
        raise InputError(f"omega = {omega!r} must be a positive crank speed [rad/s]")
    return w


def _samples(samples: Any) -> int:
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer):
        raise InputError(f"samples must be an integer; got {samples!r}")
    if not 8 <= samples <= 1_000_000:
        raise InputError(f"samples = {samples} must be between 8 and 1000000 angles per turn")
    return int(samples)


@dataclass(frozen=True)
class GearLeverPress:
    """A planetary gear-lever press drive (see the module docs for the geometry).

    ``R``, ``r`` pitch radii of the guide and planet gears [m] (R/r a whole number
    ≥ 2), ``d`` the pin's eccentricity on the planet [m] (0: crank-slider), ``L``
    the rod [m], ``phi0`` the guide gear's setting angle [rad], ``offset`` of the
    slider's guide from the centre [m].

    >>> import numpy as np, cyclomech as cm
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.025, L=0.3, phi0=0.3)
    >>> k = p.solve(np.radians([0.0, 90.0, 180.0]))
    >>> k.s.round(4).tolist(), k.pin.shape
    ([0.0, 0.0948, 0.1146], (3, 2))
    """

    R: float
    r: float
    d: float
    L: float
    phi0: float
    offset: float = 0.0

    def __post_init__(self) -> None:
        for name, unit in (
            ("R", "[m]"),
            ("r", "[m]"),
            ("d", "[m]"),
            ("L", "[m]"),
            ("phi0", "[rad]"),
            ("offset", "[m]"),
        ):
            object.__setattr__(self, name, finite_number(name, getattr(self, name), unit))
        # The kernel checks the geometry (R > r > 0, R/r whole, d ≥ 0, L > 0).
        _core.press_check(self.R, self.r, self.d, self.L, self.phi0, self.offset)

    def _row(self) -> npt.NDArray[np.float64]:
        return np.array([[self.R, self.r, self.d, self.L, self.phi0, self.offset]])

    @property
    def ratio(self) -> int:
        """The gear ratio i = R/r.

        >>> import cyclomech as cm
        >>> cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.0).ratio
        3
        """
        return round(self.R / self.r)

    def solve(self, alpha: npt.ArrayLike, *, n_threads: int | None = None) -> PressKinematics:
        """Positions and exact transfer functions over α [rad], shape (N,).

        >>> import numpy as np, cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> k = p.solve(np.array([np.pi]))      # crank-slider: TDC at α = π
        >>> round(float(k.s[0]), 12), bool(k.ok[0])
        (0.12, True)
        """
        a = float_array("alpha", alpha)
        s, ds, dds, centre, pin, slider, ok = _core.press_solve(
            self._row(), a, n_threads=threads_arg(n_threads)
        )
        return PressKinematics(a, s[0], ds[0], dds[0], centre[0], pin[0], slider[0], ok[0])

    def criteria(
        self,
        *,
        omega: float,
        k_Sp: float | None = None,
        working_stroke: float | None = None,
        samples: int = SAMPLES,
    ) -> PressCriteria:
        """Working-stroke criteria at crank speed ``omega`` [rad/s], for a working
        stroke of ``k_Sp``·S_n or ``working_stroke`` [m] (one of them).

        ``samples`` carrier angles per turn bracket every extreme, which is then
        found exactly (a root of the next derivative).

        >>> import cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
        >>> c = p.criteria(k_Sp=0.1, omega=4.0)
        >>> round(c.S_n, 9), round(c.k_Vp, 3), c.ok
        (0.12, 1.915, True)
        """
        sw = sweep(
            R=self.R,
            r=self.r,
            d=self.d,
            L=self.L,
            phi0=self.phi0,
            offset=self.offset,
            k_Sp=k_Sp,
            working_stroke=working_stroke,
            omega=omega,
            samples=samples,
            progress=False,
        )
        return sw.at(())

    def baseline(self) -> GearLeverPress:
        """The plain crank-slider of this drive: the same gears, rod and guide with
        the pin on the planet's centre (d = 0).

        >>> import cyclomech as cm
        >>> cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.4).baseline().d
        0.0
        """
        return replace(self, d=0.0, phi0=0.0)

    def to_dict(self) -> dict[str, float]:
        """The design as a plain dict [m, rad].

        >>> import cyclomech as cm
        >>> cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.4).to_dict()["L"]
        0.3
        """
        return {k: getattr(self, k) for k in (*_AXES, "offset")}


@dataclass(frozen=True)
class PressSweep:
    """Criteria over a Cartesian grid of designs (from :func:`sweep`).

    ``axes`` maps each swept parameter (in the order R, r, d, L, phi0; those given
    as arrays) to its values; ``fixed`` holds the others. ``values[name]`` is an
    array of the grid's shape for every name in :data:`CRITERIA`; ``status`` (same
    shape, uint8) says why a design fails (see :data:`STATUS`); ``ok`` is status
    0. ``sw["k_Vp"]`` is ``sw.values["k_Vp"]``.
    """

    axes: dict[str, npt.NDArray[np.float64]]
    fixed: dict[str, float]
    values: dict[str, npt.NDArray[np.float64]]
    status: npt.NDArray[np.uint8]
    omega: float
    k_Sp: float | None
    working_stroke: float | None
    samples: int = SAMPLES
    elapsed: float = field(default=0.0, compare=False)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the grid (one entry per swept axis)."""
        return self.status.shape

    @property
    def ok(self) -> npt.NDArray[np.bool_]:
        """True where the design works (status 0)."""
        return self.status == 0

    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        try:
            return self.values[name]
        except KeyError:
            raise InputError(f"no criterion {name!r}; criteria are {', '.join(CRITERIA)}") from None

    def design(self, index: tuple[int, ...] | int) -> GearLeverPress:
        """The design at a grid index.

        >>> import numpy as np, cyclomech as cm
        >>> sw = cm.press.sweep(R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=0.0, k_Sp=0.1,
        ...                     omega=4.0)
        >>> sw.design(1).d
        0.02
        """
        idx = np.unravel_index(index, self.shape) if np.ndim(index) == 0 else index
        if len(idx) != len(self.axes):
            raise InputError(f"index {index!r} must have {len(self.axes)} entries")
        par = dict(self.fixed)
        for (name, vals), i in zip(self.axes.items(), idx, strict=True):
            par[name] = float(vals[i])
        return GearLeverPress(**par)

    def at(self, index: tuple[int, ...] | int) -> PressCriteria:
        """The criteria of the design at a grid index.

        >>> import cyclomech as cm
        >>> sw = cm.press.sweep(R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=0.0, k_Sp=0.1,
        ...                     omega=4.0)
        >>> round(sw.at(0).S_n, 9)
        0.12
        """
        idx = np.unravel_index(index, self.shape) if np.ndim(index) == 0 else tuple(index)
        vals = {k: float(v[idx]) for k, v in self.values.items()}
        return PressCriteria(**vals, omega=self.omega, status=STATUS[int(self.status[idx])])

    def table(self) -> dict[str, npt.NDArray[Any]]:
        """Flat columns (one row per design): the swept parameters, the criteria and
        the status code, for CSV or a data frame.

        >>> import cyclomech as cm
        >>> sw = cm.press.sweep(R=0.09, r=0.03, d=[0.0, 0.02], L=[0.3, 0.4], phi0=0.0,
        ...                     k_Sp=0.1, omega=4.0)
        >>> t = sw.table(); list(t)[:3], len(t["k_Vp"])
        (['d', 'L', 'k_Vp'], 4)
        """
        grids = np.meshgrid(*self.axes.values(), indexing="ij")
        out: dict[str, npt.NDArray[Any]] = {
            name: g.ravel() for name, g in zip(self.axes, grids, strict=True)
        }
        order = ("k_Vp", "k_Vmax", "k_J", "k_M")
        for name in (*order, *(c for c in CRITERIA if c not in order)):
            out[name] = self.values[name].ravel()
        out["status"] = self.status.ravel()
        return out


class _Progress:
    """A text progress bar on stderr, for sweeps that take more than a moment."""

    def __init__(self, total: int, label: str, enabled: bool) -> None:
        self.total, self.label, self.enabled = total, label, enabled
        self.done, self.t0 = 0, time.perf_counter()

    def update(self, n: int) -> None:
        self.done += n
        if self.enabled:
            frac = self.done / max(self.total, 1)
            bar = "#" * int(30 * frac)
            dt = time.perf_counter() - self.t0
            sys.stderr.write(
                f"\r{self.label} [{bar:<30}] {100 * frac:5.1f}% {self.done}/{self.total} {dt:.1f} s"
            )
            sys.stderr.flush()

    def close(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")
            sys.stderr.flush()


#: Designs per kernel call of a large sweep (about half a second on one core).
_CHUNK = 250_000


def sweep(
    *,
    d: npt.ArrayLike,
    L: npt.ArrayLike,
    phi0: npt.ArrayLike,
    R: npt.ArrayLike,
    r: npt.ArrayLike,
    omega: float,
    offset: float = 0.0,
    k_Sp: float | None = None,
    working_stroke: float | None = None,
    samples: int = SAMPLES,
    n_threads: int | None = None,
    progress: bool | None = None,
) -> PressSweep:
    """Criteria over the full Cartesian grid of designs, in parallel in Rust.

    Each of ``R``, ``r``, ``d``, ``L`` [m] and ``phi0`` [rad] is a scalar (fixed)
    or a 1-D array (an axis of the grid, in that order). ``omega`` [rad/s] and the
    working stroke (``k_Sp`` or ``working_stroke`` [m]) as in
    :meth:`GearLeverPress.criteria`. A large grid runs in chunks of 250 000
    designs, one Rust call each, with a progress bar on stderr (``progress=None``:
    when stderr is a terminal and the grid is large); Ctrl-C stops between chunks.

    >>> import numpy as np, cyclomech as cm
    >>> sw = cm.press.sweep(R=0.09, r=0.03, d=np.linspace(0, 0.04, 5), L=[0.3, 0.4],
    ...                     phi0=np.radians(np.arange(0, 120, 10)), k_Sp=0.1, omega=4.0)
    >>> sw.shape, sw["k_Vp"].shape, bool(sw.ok.all())
    ((5, 2, 12), (5, 2, 12), True)
    """
    k, s = _stroke(k_Sp, working_stroke)
    w = _omega(omega)
    m = _samples(samples)
    off = finite_number("offset", offset, "[m]")
    axes: dict[str, npt.NDArray[np.float64]] = {}
    fixed: dict[str, float] = {"offset": off}
    flat: list[npt.NDArray[np.float64]] = []
    for name, value in zip(_AXES, (R, r, d, L, phi0), strict=True):
        scalar = np.ndim(value) == 0
        a = float_array(name, value, ndims=(0, 1))
        bad = ~np.isfinite(a)
        if bad.any():
            i = int(np.argmax(bad.ravel()))
            raise InputError(f"{name}[{i}] = {a.ravel()[i]!r} must be finite")
        if not scalar:
            if a.size == 0:
                raise InputError(f"{name} must hold at least one value")
            axes[name] = a
        else:
            fixed[name] = float(a[0])
        flat.append(np.ascontiguousarray(a.reshape(-1)))
    shape = tuple(len(v) for v in axes.values())
    n = math.prod(len(f) for f in flat)
    # Chunk along the outermost axis longer than one value.
    lead = next((i for i, f in enumerate(flat) if len(f) > 1), 0)
    inner = n // len(flat[lead])
    step = max(1, _CHUNK // max(inner, 1))
    bar = _Progress(
        n,
        "press.sweep",
        (n > 2 * _CHUNK and sys.stderr.isatty()) if progress is None else bool(progress),
    )
    threads = threads_arg(n_threads)
    check_bytes(f"press.sweep's {n:,} designs", n * (8 * len(CRITERIA) + 1), "sweep a coarser grid")
    table = np.empty((n, len(CRITERIA)))
    status = np.empty(n, dtype=np.uint8)
    t0 = time.perf_counter()
    try:
        for start in range(0, len(flat[lead]), step):
            part = list(flat)
            part[lead] = flat[lead][start : start + step]
            lo, hi = start * inner, min(start + step, len(flat[lead])) * inner
            _core.press_sweep(
                *part,
                table[lo:hi],
                status[lo:hi],
                offset=off,
                k_sp=k,
                working_stroke=s,
                omega=w,
                samples=m,
                n_threads=threads,
            )
            bar.update(hi - lo)
    finally:
        bar.close()
    values = {c: table[:, j].reshape(shape) for j, c in enumerate(CRITERIA)}
    st = status.reshape(shape)
    return PressSweep(axes, fixed, values, st, w, k, s, m, elapsed=time.perf_counter() - t0)


#: The objectives of :func:`optimize`: name → how a design's value is scored (lower
#: is better).
OBJECTIVES = {
    "k_Vp": lambda v: v["k_Vp"],
    "k_Vmax": lambda v: np.abs(v["k_Vmax"] - 1.0),
    "k_J": lambda v: v["k_J"],
    "k_M": lambda v: v["k_M"],
}


@dataclass(frozen=True)
class PressOptimum:
    """The non-dominated designs of :func:`optimize`.

    ``designs`` lists them as :class:`GearLeverPress`, ``criteria`` their
    :class:`PressCriteria`, ``refined`` whether scipy moved each off the grid,
    ``scores`` their weighted score (lower is better; 1 per objective is the
    baseline's level; sorted, so ``best`` = 0 is the lowest). ``baseline`` are
    the criteria of ``baseline_press``, the crank-slider (d = 0) of the same gears
    with the grid's median rod, which every objective is divided by; ``grid`` the
    sweep it started from. ``edges`` says, one sentence each, where the best design
    lies on a bound of the grid (a swept axis's first or last value, to within half
    a grid step; not d = 0, nor φ0 on an axis spanning a whole period 2π/i, which
    wraps): a better design may lie beyond it, outside the grid. Empty when the best
    design is inside.
    """

    designs: tuple[GearLeverPress, ...]
    criteria: tuple[PressCriteria, ...]
    refined: tuple[bool, ...]
    scores: npt.NDArray[np.float64]
    best: int
    baseline: PressCriteria
    baseline_press: GearLeverPress
    grid: PressSweep
    objectives: tuple[str, ...]
    edges: tuple[str, ...] = ()


def _objective_matrix(values: Mapping[str, Any], objectives: Sequence[str]) -> Any:
    return np.stack([np.asarray(OBJECTIVES[o](values), dtype=np.float64) for o in objectives], -1)


def pareto_mask(points: npt.ArrayLike) -> npt.NDArray[np.bool_]:
    """True for the rows of ``points`` (n, m) that no other row dominates (every
    objective lower or equal, one strictly lower); lower is better. Equal rows
    are all kept. In Rust: rows in order of their sum, each compared with the
    front found so far.

    >>> import numpy as np, cyclomech as cm
    >>> cm.press.pareto_mask(np.array([[1, 2], [2, 1], [2, 2], [1, 2]])).tolist()
    [True, True, False, True]
    """
    p = float_array("points", points, ndims=(2,))
    return _core.pareto_mask(p)


def optimize(
    *,
    d: npt.ArrayLike,
    L: npt.ArrayLike,
    phi0: npt.ArrayLike,
    R: float,
    r: float,
    omega: float,
    offset: float = 0.0,
    k_Sp: float | None = None,
    working_stroke: float | None = None,
    limits: Mapping[str, float] | None = None,
    objectives: Sequence[str] = ("k_Vp", "k_Vmax", "k_J", "k_M"),
    weights: Sequence[float] | None = None,
    refine: int = 5,
    samples: int = SAMPLES,
    n_threads: int | None = None,
    progress: bool | None = None,
) -> PressOptimum:
    """The non-dominated designs over a grid of (d, L, φ0), then refined off it.

    Objectives (lower is better): ``k_Vp`` (→ 0), ``|k_Vmax − 1|``, ``k_J`` and
    ``k_M`` (the dimensionless peak acceleration and torque arm), or a subset.
    ``limits`` bounds any criterion from above, e.g. ``{"V_np": 0.05}`` for a
    start of the working stroke at most 50 mm/s at ``omega``. Designs that fail
    (see :data:`STATUS`: a rod that cannot reach, a slider that moves back up or
    re-contacts the blank) or break a limit are dropped. The score of a design is
    the weighted sum of its objectives, each divided by the baseline crank-slider's.

    The refinement (``refine`` > 0) is multi-start, with the limits inside it. A
    coarse grid is swept once more, finer (at most 100 000 designs, one Rust call),
    because the designs that meet a tight limit on V_np lie in a narrow band of φ0
    that a coarse grid steps over. From that sweep start the ``refine`` best
    designs that meet the limits and the ``refine`` best working designs by score
    plus a penalty of 1000 per unit of relative excess over a limit, the starts
    spread (none within a grid step of another). Each start is refined by a zoom
    (boxes of 9³ designs, ± one step around the best so far, a quarter the size
    each time, 8 times; one Rust call each) and polished by scipy's Nelder–Mead on
    the penalised score, within the grid's bounds; of every design met, the best
    that meets the limits is kept. So a limit that no grid design meets can still
    be met by a design between the grid's points; with ``refine = 0``, or when no
    design is found, :class:`~cyclomech.InfeasibleError` names the limits. The
    returned front is recomputed over the grid's front and the refined designs;
    :attr:`PressOptimum.edges` says when the best design lies on the grid's bound.

    >>> import numpy as np, cyclomech as cm
    >>> opt = cm.press.optimize(R=0.09, r=0.03, d=np.linspace(0, 0.04, 9),
    ...                         L=[0.3, 0.4], phi0=np.radians(np.arange(0, 120, 10)),
    ...                         k_Sp=0.1, omega=4.0, refine=1)
    >>> c = opt.criteria[opt.best]
    >>> c.k_Vp < opt.baseline.k_Vp, len(opt.designs) >= 1
    (True, True)
    """
    from scipy.optimize import minimize

    objectives = tuple(objectives)
    for o in objectives:
        if o not in OBJECTIVES:
            raise InputError(f"objective {o!r} is not known; choose from {', '.join(OBJECTIVES)}")
    if not objectives:
        raise InputError("objectives must name at least one objective")
    wts = np.ones(len(objectives)) if weights is None else float_array("weights", weights)
    if wts.shape != (len(objectives),) or not (np.isfinite(wts).all() and (wts >= 0).all()):
        raise InputError(
            f"weights must be {len(objectives)} finite non-negative numbers, one per objective"
        )
    lim: dict[str, float] = {}
    for name, v in dict(limits or {}).items():
        if name not in CRITERIA:
            raise InputError(f"limits: no criterion {name!r}; criteria are {', '.join(CRITERIA)}")
        lim[name] = finite_number(f"limits[{name!r}]", v, "")
    if isinstance(refine, bool) or not isinstance(refine, int) or refine < 0:
        raise InputError(f"refine must be a non-negative integer; got {refine!r}")
    for name, value in (("R", R), ("r", r)):
        if np.ndim(value) != 0:
            raise InputError(f"{name} must be a scalar for optimize; sweep it with cm.press.sweep")
    # What every sweep of this optimisation shares: gears, stroke, speed, sampling.
    common: dict[str, Any] = {
        "R": R,
        "r": r,
        "offset": offset,
        "k_Sp": k_Sp,
        "working_stroke": working_stroke,
        "omega": omega,
        "samples": samples,
        "n_threads": n_threads,
    }
    grid = sweep(d=d, L=L, phi0=phi0, progress=progress, **common)
    flat = {k: v.ravel() for k, v in grid.values.items()}
    ok = grid.ok.ravel()
    # How far each grid design breaks the limits (relative; 0: meets them all).
    excess = np.zeros(ok.size)
    for name, v in lim.items():
        excess += np.maximum(flat[name] - v, 0.0) / _limit_scale(v)
    usable = ok & (excess == 0.0)
    if not ok.any() or (not usable.any() and refine == 0):
        why = f" within the limits {lim}" if lim else ""
        raise InfeasibleError(
            f"no design of the grid works{why}: widen or refine the grid, or relax the limits",
            tuple(lim),
        )
    # Score relative to one baseline: the crank-slider (d = 0) of the same gears
    # with the grid's median rod.
    base_press = GearLeverPress(
        R=float(R),
        r=float(r),
        d=0.0,
        L=float(np.median(np.atleast_1d(L))),
        phi0=0.0,
        offset=offset,
    )
    base = base_press.criteria(
        k_Sp=k_Sp, working_stroke=working_stroke, omega=omega, samples=samples
    )
    bvals = _objective_matrix(base.as_dict(), objectives)
    norm = np.where(np.abs(bvals) > 1e-12, np.abs(bvals), 1.0)
    obj = _objective_matrix(flat, objectives) / norm
    cand = np.flatnonzero(usable)
    front = cand[pareto_mask(obj[cand])] if cand.size else cand
    score = obj @ wts
    ranked = front[np.argsort(score[front], kind="stable")]

    designs: list[GearLeverPress] = [grid.design(int(i)) for i in ranked]
    crits: list[PressCriteria] = [grid.at(int(i)) for i in ranked]
    refined = [False] * len(designs)
    # Refine along the swept axes that span a range.
    names = [n_ for n_ in ("d", "L", "phi0") if n_ in grid.axes and np.ptp(grid.axes[n_]) > 0]
    bounds = [(float(grid.axes[n_].min()), float(grid.axes[n_].max())) for n_ in names]
    # Where the refinement starts: a coarse grid is swept again first, finer
    # (each refined axis `factor` times denser, at most _DENSE designs, one Rust
    # call), so that a narrow feasible region between the grid's points has
    # designs in it.
    dense, factor = grid, 1
    if names and refine:
        factor = int((_DENSE / grid.status.size) ** (1 / len(names)) + 1e-9)
        if factor >= 2:
            kw: dict[str, Any] = {}
            for n_ in ("d", "L", "phi0"):
                if n_ in names:
                    ax = grid.axes[n_]
                    kw[n_] = np.linspace(ax.min(), ax.max(), (len(ax) - 1) * factor + 1)
                else:
                    kw[n_] = grid.axes[n_] if n_ in grid.axes else grid.fixed[n_]
            dense = sweep(progress=False, **common, **kw)
        else:
            factor = 1
    steps = np.array([np.ptp(dense.axes[n_]) / max(len(dense.axes[n_]) - 1, 1) for n_ in names])

    def evaluate(p: GearLeverPress) -> PressCriteria:
        return p.criteria(k_Sp=k_Sp, working_stroke=working_stroke, omega=omega, samples=samples)

    lo_b = np.array([b_[0] for b_ in bounds])
    hi_b = np.array([b_[1] for b_ in bounds])

    def penalised(values: Mapping[str, Any], status: Any, mu: float = _PENALTY) -> tuple[Any, Any]:
        """(score, score + mu·the limits' excess); inf where a design fails."""
        sc = (_objective_matrix(values, objectives) / norm) @ wts
        over = np.zeros(np.shape(sc))
        for k_, v in lim.items():
            over = over + np.maximum(np.asarray(values[k_]) - v, 0.0) / _limit_scale(v)
        bad = np.asarray(status) != 0
        return np.where(bad | (over > 0), np.inf, sc), np.where(bad, np.inf, sc + mu * over)

    def zoom(p0: GearLeverPress, best: list[Any]) -> npt.NDArray[np.float64]:
        """A box of _ZOOM points per axis, ± one grid step around the start, swept
        in one Rust call; its best design (by penalised score) the centre of the
        next box, a quarter the size, _LEVELS times. Every design of every box
        counts: the best one that meets the limits is kept in ``best``. A box
        search, not a descent: a feasible sliver thinner than the grid's step, or
        bordered by designs that fail, is found as long as a box point lands in it,
        and the penalty leads the boxes towards it otherwise."""
        x = np.array([float(getattr(p0, n_)) for n_ in names])
        c0 = evaluate(p0)
        half = steps.copy()
        for level in range(_LEVELS):
            mu = _PENALTY ** ((level + 1) / _LEVELS)
            x_pen = penalised(c0.as_dict(), 0 if c0.ok else 1, mu)[1]
            axes = [
                np.linspace(max(lo, c - h), min(hi, c + h), _ZOOM)
                for lo, hi, c, h in zip(lo_b, hi_b, x, half, strict=True)
            ]
            kw = {n_: getattr(p0, n_) for n_ in ("d", "L", "phi0")}
            kw.update(zip(names, axes, strict=True))
            box = sweep(progress=False, **common, **kw)  # p0 shares R, r, offset
            feas, pen = penalised(box.values, box.status, mu)
            i = int(np.argmin(feas))
            if feas.flat[i] < best[0]:
                q = box.design(i)
                best[:] = [float(feas.flat[i]), np.array([getattr(q, n_) for n_ in names]), None]
            j = int(np.argmin(pen))
            if pen.flat[j] < x_pen:
                q = box.design(j)
                c0 = box.at(j)
                x = np.array([float(getattr(q, n_)) for n_ in names])
            half = half / (_ZOOM - 1) * 2
        return x

    starts: list[int] = []
    if names and refine:
        d_feas, d_pen = penalised(dense.values, dense.status)
        d_feas, d_pen = d_feas.ravel(), d_pen.ravel()
        d_usable = np.flatnonzero(np.isfinite(d_feas))
        d_ranked = d_usable[np.argsort(d_feas[d_usable], kind="stable")]
        starts = _starts(dense, d_ranked, d_pen, refine, reach=factor)
        found: list[tuple[float, npt.NDArray[np.float64], PressCriteria]] = []
        for start in starts:
            p0 = dense.design(int(start))
            best: list[Any] = [math.inf, None, None]
            x0 = zoom(p0, best)

            def f(
                x: npt.NDArray[np.float64], best: list[Any] = best, p0: GearLeverPress = p0
            ) -> float:
                # The limits inside the refinement: an exact penalty on their
                # excess, so that a start that breaks them moves towards them
                # and one that meets them is not walled in; the best design met
                # that meets them is kept whatever the simplex ends on.
                x = np.clip(x, lo_b, hi_b)
                try:
                    c = evaluate(replace(p0, **dict(zip(names, x.tolist(), strict=True))))
                except InputError:
                    return math.inf
                feas, pen = penalised(c.as_dict(), 0 if c.ok else 1)
                if feas < best[0]:
                    best[:] = [float(feas), x.copy(), c]
                return float(pen)

            # Nelder–Mead polishes the boxes' best, its first simplex a last box
            # step on each axis.
            h = steps * (2 / (_ZOOM - 1)) ** _LEVELS
            simplex = np.vstack(
                [x0]
                + [
                    x0
                    + np.where(np.arange(len(names)) == j, hj, 0.0)
                    * (1.0 if x0[j] + hj <= hi_b[j] else -1.0)
                    for j, hj in enumerate(h)
                ]
            )
            minimize(
                f,
                x0,
                method="Nelder-Mead",
                bounds=bounds,
                options={
                    "xatol": 1e-9,
                    "fatol": 1e-10,
                    "maxfev": 200,
                    "initial_simplex": simplex,
                },
            )
            if best[1] is None:
                continue
            # On the user's grid, keep a move only when it is a real improvement
            # on a start that met the limits, not rounding (off it, every design
            # is new).
            s0 = float(d_feas[start])
            if dense is grid and math.isfinite(s0) and best[0] >= s0 - 1e-6 * max(abs(s0), 1.0):
                continue
            # Starts that converge to one design keep it once.
            span = np.array([hi - lo for lo, hi in bounds]) + 1e-300
            if any(np.all(np.abs(best[1] - x) <= 1e-6 * span) for _, x, _ in found):
                continue
            q = replace(p0, **dict(zip(names, best[1].tolist(), strict=True)))
            c = best[2] if best[2] is not None else evaluate(q)
            found.append((best[0], best[1], c))
            designs.append(q)
            crits.append(c)
            refined.append(True)
    if not designs:
        raise InfeasibleError(
            f"no design of the grid works within the limits {lim}, nor any refined from its "
            f"{len(starts)} designs nearest to them: widen or refine the grid, or relax the "
            "limits",
            tuple(lim),
        )
    allobj = np.array([_objective_matrix(c.as_dict(), objectives) / norm for c in crits])
    keep = pareto_mask(allobj)
    sel = np.flatnonzero(keep)
    scores = allobj[sel] @ wts
    order = sel[np.argsort(scores, kind="stable")]
    out_designs = tuple(designs[i] for i in order)
    return PressOptimum(
        designs=out_designs,
        criteria=tuple(crits[i] for i in order),
        refined=tuple(refined[i] for i in order),
        scores=np.sort(scores),
        best=0,
        baseline=base,
        baseline_press=base_press,
        grid=grid,
        objectives=objectives,
        edges=_edges(grid, out_designs[0], ratio=base_press.ratio),
    )


#: Weight of the limits' relative excess in the refinement's score (the score is
#: about 1 per objective): large enough that no gain in score pays for breaking a
#: limit.
_PENALTY = 1e3
#: Points per axis of each box of the refinement's zoom, and the number of boxes
#: (each a quarter the size of the one before: 8 boxes narrow one grid step
#: 65 536-fold).
_ZOOM = 9
_LEVELS = 8
#: Designs of the finer sweep a coarse grid's refinement starts from.
_DENSE = 100_000


def _limit_scale(v: float) -> float:
    """The unit a limit's excess is measured in: the limit itself (1 if it is 0)."""
    return abs(v) if v != 0 else 1.0


def _starts(
    grid: PressSweep,
    ranked: npt.NDArray[np.intp],
    penalised: npt.NDArray[np.float64],
    refine: int,
    reach: int = 1,
) -> list[int]:
    """The refinement's starts: the ``refine`` best grid designs that meet the
    limits (``ranked``), then the ``refine`` best working grid designs by penalised
    score (a limit broken counts against it), each at least ``reach`` + 1 steps
    away on some axis from every start taken before, so that the starts spread
    over the grid's basins instead of one."""
    taken: list[npt.NDArray[np.intp]] = []

    def far(i: int) -> bool:
        at = np.array(np.unravel_index(i, grid.shape))
        return all(np.any(np.abs(at - t) > reach) for t in taken)

    out: list[int] = []
    for pool in (ranked, np.argsort(penalised, kind="stable")):
        n = 0
        for i in pool:
            if n == refine or not np.isfinite(penalised[i]):
                break
            if far(int(i)):
                taken.append(np.array(np.unravel_index(int(i), grid.shape)))
                out.append(int(i))
                n += 1
    return out


def _edges(grid: PressSweep, p: GearLeverPress, *, ratio: int) -> tuple[str, ...]:
    """Where design ``p`` lies on a bound of the grid: a swept axis's lowest or
    highest value, to within half a grid step (the grid cannot tell a better design
    beyond it). Not an edge: d = 0 (no lower eccentricity exists) and φ0 on an
    axis that spans a whole period 2π/i (designs repeat: the axis wraps)."""
    out = []
    units = {"d": ("mm", 1e3), "L": ("mm", 1e3), "phi0": ("°", 180 / math.pi)}
    for name in ("d", "L", "phi0"):
        if name not in grid.axes or len(grid.axes[name]) < 2:
            continue
        ax = grid.axes[name]
        lo, hi = float(ax.min()), float(ax.max())
        half = 0.5 * (hi - lo) / (len(ax) - 1)
        if name == "phi0" and hi - lo + 2 * half >= 2 * math.pi / ratio * (1 - 1e-9):
            continue
        v = float(getattr(p, name))
        u, f = units[name]
        for bound, side in ((lo, "lower"), (hi, "upper")):
            if abs(v - bound) < half and not (name == "d" and side == "lower" and bound <= 0):
                out.append(
                    f"{name} = {v * f:.4g} {u} is at the {side} bound {bound * f:.4g} {u} of the "
                    f"grid: a better design may lie beyond it"
                )
    return tuple(out)


@dataclass(frozen=True)
class PressStudy:
    """A press file: one design, its working stroke and speed, and optionally a
    design grid with limits for :func:`optimize` (read with :meth:`from_toml`).

    The file::

        [press]
        name = "extrusion press"     # optional
        R = 0.09                     # guide gear pitch radius [m]
        r = 0.03                     # planet pitch radius [m] (R/r whole)
        d = 0.025                    # pin eccentricity [m]
        L = 0.30                     # rod [m]
        phi0_deg = 17.0              # guide gear setting angle [°]
        offset = 0.0                 # optional, guide offset [m]

        [working]
        k_Sp = 0.1                   # or working_stroke = 0.012 [m]
        rpm = 40.0                   # crank speed [rpm]

        [sweep]                      # optional: a grid of (d, L, φ0), [from, to, count]
        d = [0.0, 0.04, 41]
        L = [0.25, 0.5, 26]
        phi0_deg = [0.0, 118.0, 60]

        [limits]                     # optional upper bounds on criteria (SI units)
        V_np = 0.05
    """

    press: GearLeverPress
    rpm: float
    k_Sp: float | None = None
    working_stroke: float | None = None
    grid: dict[str, npt.NDArray[np.float64]] | None = None
    limits: dict[str, float] = field(default_factory=dict)
    name: str = ""

    @property
    def omega(self) -> float:
        """Crank speed [rad/s].

        >>> import cyclomech as cm
        >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.02, L=0.3, phi0=0.0)
        >>> round(cm.press.PressStudy(p, rpm=60.0, k_Sp=0.1).omega, 6)
        6.283185
        """
        return self.rpm * RAD_PER_S_PER_RPM

    @classmethod
    def from_toml(cls, path: str | Any) -> PressStudy:
        """Read a press file; errors name the file, the table and the key.

        >>> import cyclomech as cm, pathlib, tempfile
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "p.toml"
        >>> _ = f.write_text('[press]\\nR = 0.09\\nr = 0.03\\nd = 0.02\\nL = 0.3\\n'
        ...                  'phi0_deg = 15\\n[working]\\nk_Sp = 0.1\\nrpm = 40\\n')
        >>> st = cm.press.PressStudy.from_toml(f)
        >>> round(st.press.phi0, 6), st.grid is None
        (0.261799, True)
        """
        from . import _toml

        data, src = _toml.load(path)
        _toml.check_keys(data, {"press", "working", "sweep", "limits"}, src, "the file")
        for t in ("press", "working"):
            if t not in data:
                raise InputError(f"{src}: missing table [{t}]")
        pt, wt = data["press"], data["working"]
        _toml.check_keys(pt, {"name", "R", "r", "d", "L", "phi0_deg", "offset"}, src, "[press]")
        _toml.check_keys(wt, {"k_Sp", "working_stroke", "rpm"}, src, "[working]")

        def num(table: Mapping[str, Any], where: str, key: str, default: Any = None) -> float:
            if key not in table:
                if default is not None:
                    return float(default)
                raise InputError(f"{src}: {where}: missing key {key!r}")
            v = table[key]
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                raise InputError(f"{src}: {where}: {key} = {v!r} must be a finite number")
            return float(v)

        try:
            press = GearLeverPress(
                R=num(pt, "[press]", "R"),
                r=num(pt, "[press]", "r"),
                d=num(pt, "[press]", "d"),
                L=num(pt, "[press]", "L"),
                phi0=math.radians(num(pt, "[press]", "phi0_deg")),
                offset=num(pt, "[press]", "offset", 0.0),
            )
        except InputError as e:
            raise InputError(f"{src}: [press]: {e}") from None
        rpm = num(wt, "[working]", "rpm")
        if rpm <= 0:
            raise InputError(f"{src}: [working]: rpm = {rpm!r} must be > 0")
        k = num(wt, "[working]", "k_Sp") if "k_Sp" in wt else None
        s = num(wt, "[working]", "working_stroke") if "working_stroke" in wt else None
        try:
            _stroke(k, s)
        except InputError as e:
            raise InputError(f"{src}: [working]: {e}") from None
        grid = None
        if "sweep" in data:
            st = data["sweep"]
            _toml.check_keys(st, {"d", "L", "phi0_deg"}, src, "[sweep]")
            grid = {}
            for key, name, scale in (("d", "d", 1.0), ("L", "L", 1.0), ("phi0_deg", "phi0", None)):
                if key not in st:
                    grid[name] = np.array([getattr(press, name)])
                    continue
                v = st[key]
                ok = (
                    isinstance(v, list)
                    and len(v) == 3
                    and all(isinstance(x, int | float) and not isinstance(x, bool) for x in v)
                    and isinstance(v[2], int)
                    and v[2] >= 1
                    and all(math.isfinite(x) for x in v)
                )
                if not ok:
                    raise InputError(
                        f"{src}: [sweep]: {key} = {v!r} must be [from, to, count] "
                        "(two numbers and a whole count ≥ 1)"
                    )
                vals = np.linspace(float(v[0]), float(v[1]), int(v[2]))
                grid[name] = vals if scale else np.radians(vals)
        limits: dict[str, float] = {}
        if "limits" in data:
            _toml.check_keys(data["limits"], set(CRITERIA), src, "[limits]")
            limits = {k_: num(data["limits"], "[limits]", k_) for k_ in data["limits"]}
        name = pt.get("name", "")
        if not isinstance(name, str):
            raise InputError(f"{src}: [press]: name = {name!r} must be a string")
        return cls(press, rpm, k, s, grid, limits, name)
