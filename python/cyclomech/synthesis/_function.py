"""Function generation: a four-bar whose output angle — or an
offset slider-crank whose slider position — follows a wanted function of the
crank angle, by Freudenstein's equation (exact through three precision points,
least squares through more), with the structural error over the whole range.
The solve and the checks are in the Rust core (``synthesis/function.rs``, whose
module docs derive the equations and the sign convention).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _core
from .._arrays import count, finite_number, float_array, positive, real_array
from .._errors import InputError
from ..linkage import Linkage
from ._fourbar import (
    Margins,
    four_bar_linkage,
    four_bar_margins,
    slider_crank_linkage,
    slider_crank_margins,
)

__all__ = ["FunctionCandidate", "chebyshev_points", "function_generation"]

_MECHANISMS = ("four-bar", "slider-crank")
_SPACINGS = ("chebyshev", "uniform")


def chebyshev_points(lo: float, hi: float, n: int) -> np.ndarray:
    """``n`` Chebyshev points over [lo, hi], ascending.

    x_j = (lo + hi)/2 − (hi − lo)/2·cos((2j − 1)π/(2n)), j = 1…n: the spacing of
    precision points that minimises the polynomial factor of the largest
    interpolation error (Freudenstein's and Hartenberg & Denavit's choice).
    Units are the caller's (degrees for angles).

    Examples
    --------
    >>> import cyclomech as cm
    >>> [round(float(x), 4) for x in cm.synthesis.chebyshev_points(0, 90, 3)]
    [6.0289, 45.0, 83.9711]
    """
    lo_f = finite_number("lo", lo, "")
    hi_f = finite_number("hi", hi, "", low=lo_f, strict=True)
    return np.array(_core.chebyshev_points(lo_f, hi_f, count("n", n, what="points")))


@dataclass(frozen=True)
class FunctionCandidate:
    """One linkage from :func:`function_generation`, with its margins.

    Attributes
    ----------
    mechanism : str
        ``"four-bar"`` or ``"slider-crank"``.
    lengths : dict of str to float
        Four-bar: ``crank``, ``coupler``, ``rocker``, ``ground`` [m]; slider-crank:
        ``crank``, ``rod`` [m] and ``offset`` [m] (signed, the slide's line at
        y = offset).
    k : (float, float, float)
        (K1, K2, K3) of the linear equation solved (``function_generation``).
    crank_flipped, output_flipped : bool
        A K gave a negative crank (or rocker) length: the link is drawn at
        φ + 180° (ψ + 180°); its length is the magnitude.
    mode : int
        The assembly branch (+1/−1, see :func:`four_bar_linkage`) the linkage is
        drawn on: the first precision point's.
    precision : tuple of (float, float)
        The precision points (φ [deg], ψ [deg] or s [m]) after ``offset``.
    branches : tuple of int
        The branch each precision point is reached on (nearest of the two).
    branch_defect : bool
        Some precision point is reached only on the other branch.
    structural_error : float
        max |generated − wanted| over the input range [deg] (four-bar) or [m]
        (slider-crank): on a grid of ``n_grid`` angles if a ``function`` was
        given, else at the precision points only. ``inf`` where the linkage
        cannot be assembled somewhere in the range.
    structural_error_at_deg : float
        The input angle φ [deg] where it is largest.
    margins : Margins
        Grashof type, transmission angle over the range, branch, link ratio.
    offset : (float, float)
        The (Δφ [deg], Δψ [deg] or Δs [m]) this candidate was made with.

    Examples
    --------
    >>> import cyclomech as cm
    >>> c = cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)], ground_m=0.2)[0]
    >>> c.mechanism, c.branch_defect, sorted(c.lengths)
    ('four-bar', False, ['coupler', 'crank', 'ground', 'rocker'])
    """

    mechanism: str
    lengths: dict[str, float]
    k: tuple[float, float, float]
    crank_flipped: bool
    output_flipped: bool
    mode: int
    precision: tuple[tuple[float, float], ...]
    branches: tuple[int, ...]
    branch_defect: bool
    structural_error: float
    structural_error_at_deg: float
    margins: Margins
    offset: tuple[float, float] = field(default=(0.0, 0.0))

    @property
    def clean(self) -> bool:
        """No branch defect, and the range is held on one branch (with the crank
        turning fully where the range is a full turn): the ranking's first key.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)])[0].clean
        True
        """
        return not self.branch_defect and self.margins.branch_ok

    def _dims(self) -> tuple[float, float, float, float]:
        ln = self.lengths
        if self.mechanism == "four-bar":
            return (ln["crank"], ln["coupler"], ln["rocker"], ln["ground"])
        return (ln["crank"], ln["rod"], ln["offset"], 0.0)

    def generated(self, input_deg: Any) -> np.ndarray:
        """The generated output at the input angles φ [deg]: ψ [deg] (four-bar,
        near the first precision point's) or s [m] (slider-crank); NaN where it
        does not assemble.

        Examples
        --------
        >>> import cyclomech as cm
        >>> c = cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)])[0]
        >>> [round(float(v), 9) for v in c.generated([30, 60, 90])]
        [80.0, 90.0, 100.0]
        """
        x = np.radians(real_array("input_deg", input_deg, "[deg]", ndims=(0, 1)))
        four = self.mechanism == "four-bar"
        near = math.radians(self.precision[0][1]) if four else 0.0
        out = np.array(
            _core.function_generated(
                self.mechanism,
                self._dims(),
                self.crank_flipped,
                self.output_flipped,
                float(self.mode),
                [float(v) for v in np.atleast_1d(x)],
                near,
            )
        )
        out = np.degrees(out) if four else out
        return out.reshape(x.shape)

    def crank_angle_deg(self, input_deg: float) -> float:
        """The linkage's crank angle [deg] (what :meth:`cyclomech.Linkage.solve` takes, in
        radians) for the function's input angle φ [deg]: φ, or φ + 180° where the
        crank is flipped.

        Examples
        --------
        >>> import cyclomech as cm
        >>> c = cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)])[0]
        >>> c.crank_angle_deg(30) in (30.0, 210.0)    # 210: this crank is flipped
        True
        """
        phi = finite_number("input_deg", input_deg, "[deg]")
        return phi + (180.0 if self.crank_flipped else 0.0)

    def linkage(self, input_deg: float | None = None, *, name: str | None = None) -> Linkage:
        """The :class:`cyclomech.Linkage` of this candidate, drawn at the input
        angle φ [deg] (default: the first precision point) on its branch.

        Four-bar: points A (crank pivot, origin), B, C, D (output pivot on +x);
        the output angle ψ is the angle of D → C, minus 180° where
        ``output_flipped``. Slider-crank: A, B, C (slider pin on y = offset, the
        slide along +x).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> c = cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)])[0]
        >>> sol = c.linkage().solve(np.radians([c.crank_angle_deg(60)]))
        >>> d = sol["C"][0] - sol["D"][0]
        >>> psi = np.degrees(np.arctan2(d[1], d[0])) - 180 * c.output_flipped
        >>> round(float(psi % 360), 9)
        90.0
        """
        phi = self.precision[0][0] if input_deg is None else input_deg
        crank_deg = self.crank_angle_deg(phi)
        ln = self.lengths
        if self.mechanism == "four-bar":
            return four_bar_linkage(
                ln["crank"],
                ln["coupler"],
                ln["rocker"],
                ln["ground"],
                crank_deg=crank_deg,
                mode=self.mode,
                name=name,
            )
        return slider_crank_linkage(
            ln["crank"], ln["rod"], ln["offset"], crank_deg=crank_deg, mode=self.mode, name=name
        )


def _pairs(name: str, value: Any, mechanism: str) -> np.ndarray:
    a = float_array(name, value, (2,))
    if a.shape[1] != 2:
        unit = "ψ [deg]" if mechanism == "four-bar" else "s [m]"
        raise InputError(f"{name} must be (φ [deg], {unit}) pairs; got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if bad.size:
        raise InputError(f"{name}[{bad[0]}] = {tuple(a[bad[0]])} is not finite")
    return a


def _tabulated(table: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    order = np.argsort(table[:, 0], kind="stable")
    x, y = table[order, 0], table[order, 1]
    if np.any(np.diff(x) <= 0):
        i = int(np.flatnonzero(np.diff(x) <= 0)[0])
        raise InputError(
            f"function: the table repeats the input angle {x[i]:g} deg; give each φ once"
        )
    return lambda q: np.interp(q, x, y)


def _call(function: Callable[..., Any], x: np.ndarray, mechanism: str) -> np.ndarray:
    """The wanted outputs at x [deg], from a callable (vectorised or not)."""
    try:
        y = np.array([float(function(float(v))) for v in x])
    except (TypeError, ValueError) as e:
        raise InputError(f"function must map an input angle [deg] to a number; {e}") from None
    bad = np.flatnonzero(~np.isfinite(y))
    if bad.size:
        unit = "deg" if mechanism == "four-bar" else "m"
        raise InputError(
            f"function({x[bad[0]]:g}) = {y[bad[0]]} [{unit}] is not finite; the function "
            "must be defined over all of x_range_deg"
        )
    return y


def _coincident(x_deg: np.ndarray, name: str) -> None:
    for i in range(len(x_deg)):
        for j in range(i + 1, len(x_deg)):
            if abs((x_deg[i] - x_deg[j] + 180.0) % 360.0 - 180.0) <= 1e-7:
                raise InputError(
                    f"{name}[{i}] and {name}[{j}] are coincident precision points: the same "
                    f"input angle {x_deg[i]:g} deg (mod 360); give distinct input angles"
                )


def function_generation(
    pairs_deg: Any = None,
    *,
    function: Callable[[float], float] | Sequence[Sequence[float]] | None = None,
    x_range_deg: Sequence[float] | None = None,
    n: int = 3,
    spacing: str = "chebyshev",
    mechanism: str = "four-bar",
    ground_m: float | None = None,
    offsets: Sequence[Sequence[float]] | None = None,
    n_grid: int = 721,
) -> list[FunctionCandidate]:
    """Four-bars (or slider-cranks) whose output follows a wanted function of the
    crank angle: candidates with their margins, best first.

    Four-bar: Freudenstein's equation in Norton's convention (angles φ of the
    crank and ψ of the output, both counter-clockwise from the ground line
    A → D), K1·cos ψ − K2·cos φ + K3 = cos(φ − ψ) with K1 = d/a, K2 = d/c,
    K3 = (a² − b² + c² + d²)/(2ac); Freudenstein's own form K1·cos φ − K2·cos ψ
    + K3 = cos(φ − ψ) is the same with angles measured from D → A. Slider-crank:
    the slider's position s [m] along the slide from the crank pivot,
    (s − r·cos φ)² + (e − r·sin φ)² = l², linear in (2r, 2re, r² + e² − l²).
    Exact through three precision points (a 3 × 3 solve), least squares through
    more.

    Parameters
    ----------
    pairs_deg : sequence of (φ [deg], ψ [deg] or s [m]), optional
        The precision points. Without them, ``n`` points are placed over
        ``x_range_deg`` by ``spacing`` and read off ``function``.
    function : callable or sequence of pairs, optional
        The wanted relation φ [deg] → ψ [deg] (four-bar) or s [m]
        (slider-crank): a callable, or a table of (φ, y) pairs interpolated
        linearly. With it the structural error is measured on a grid of
        ``n_grid`` angles over the range; without it, only at the precision
        points.
    x_range_deg : (lo, hi), optional
        The input range [deg]; default the table's range, else the precision
        points'. A range of 360° or more asks for a crank that turns fully.
    n : int
        Precision points placed when ``pairs_deg`` is not given (≥ 3; 3 is exact,
        more least squares).
    spacing : {"chebyshev", "uniform"}
        Their spacing over the range (uniform includes the ends).
    mechanism : {"four-bar", "slider-crank"}
        What generates the function.
    ground_m : float, optional
        The four-bar's ground length d [m] (the equation fixes only ratios);
        default 1. Not taken by the slider-crank, whose positions fix its size.
    offsets : sequence of (Δφ [deg], Δψ [deg] or Δs [m]), optional
        Free choices of where the input and output scales start: each pair adds
        Δφ to every input angle and Δψ (Δs) to every output and gives one
        candidate. Default: one candidate, ``[(0, 0)]``. A candidate that has no
        real linkage (b² ≤ 0, a singular system) is left out.
    n_grid : int
        Angles of the structural error's grid (≥ 2).

    Returns
    -------
    list of FunctionCandidate
        Best first: clean candidates (no branch defect, the range held on one
        branch without a fold, the crank turning fully where the range is a full
        turn) before the others; then by smaller structural error; then by larger
        worst transmission angle.

    Raises
    ------
    InputError
        Fewer than three precision points, coincident precision points (named),
        a singular system, precision points no real linkage meets (b² ≤ 0), a
        bad argument — or, with ``offsets``, no candidate left.

    Examples
    --------
    y = x² on 0 ≤ x ≤ 1 by a crank turning from 30° to 90° and an output turning
    from 80° to 100° (Chebyshev spacing, three points, exact):

    >>> import math, cyclomech as cm
    >>> f = lambda phi: 80 + 20 * ((phi - 30) / 60) ** 2
    >>> best = cm.synthesis.function_generation(function=f, x_range_deg=(30, 90), ground_m=0.1)[0]
    >>> [round(float(v), 9) for v in best.generated([p for p, _ in best.precision])] == [
    ...     round(y, 9) for _, y in best.precision]
    True
    >>> round(best.structural_error, 3), best.structural_error_at_deg, best.margins.grashof
    (0.566, 30.0, 'crank-rocker')
    """
    if mechanism not in _MECHANISMS:
        raise InputError(f"mechanism must be one of {_MECHANISMS}; got {mechanism!r}")
    four = mechanism == "four-bar"
    if ground_m is not None and not four:
        raise InputError(
            "ground_m scales a four-bar; a slider-crank's positions [m] fix its size, "
            f"so leave ground_m out; got {ground_m!r}"
        )
    d = 1.0 if ground_m is None else positive("ground_m", ground_m, "[m]")
    if spacing not in _SPACINGS:
        raise InputError(f"spacing must be one of {_SPACINGS}; got {spacing!r}")
    n_grid = count("n_grid", n_grid, low=2, what="grid angles")
    # Checked even where pairs_deg makes it unused: a bad n is a mistake either way.
    n = count("n", n, low=3, what="precision points")

    wanted, table_range = _wanted(function, mechanism)
    given = None if pairs_deg is None else _given_points(pairs_deg, mechanism)
    if given is None and wanted is None:
        raise InputError(
            "give the precision points (pairs_deg=) or the wanted relation (function=, "
            "with x_range_deg= for a callable)"
        )
    lo, hi = _input_range(x_range_deg, table_range, given)
    if given is None:
        assert wanted is not None
        x = chebyshev_points(lo, hi, n) if spacing == "chebyshev" else np.linspace(lo, hi, n)
        _coincident(x % 360.0, "precision points")
        pts = np.column_stack([x, wanted(x)])
    else:
        pts = given

    grid = np.linspace(lo, hi, n_grid) if wanted is not None else pts[:, 0].copy()
    grid_want = wanted(grid) if wanted is not None else pts[:, 1].copy()

    return _ranked(mechanism, pts, grid, grid_want, (lo, hi), d, offsets)


def _wanted(
    function: Any, mechanism: str
) -> tuple[Callable[[np.ndarray], np.ndarray] | None, tuple[float, float] | None]:
    """The wanted relation as a vectorised callable, and a table's input range."""
    if function is None:
        return None, None
    if callable(function):
        fn = function
        return (lambda x: _call(fn, x, mechanism)), None
    table = _pairs("function", function, mechanism)
    if len(table) < 2:
        raise InputError(f"function as a table needs at least 2 (φ, y) pairs; got {len(table)}")
    return _tabulated(table), (float(table[:, 0].min()), float(table[:, 0].max()))


def _given_points(pairs_deg: Any, mechanism: str) -> np.ndarray:
    pts = _pairs("pairs_deg", pairs_deg, mechanism)
    if len(pts) < 3:
        raise InputError(
            f"pairs_deg has {len(pts)} precision point(s); {mechanism} function generation "
            "needs at least 3 (3 exact, more least squares)"
        )
    _coincident(pts[:, 0], "pairs_deg")
    return pts


def _input_range(
    x_range_deg: Any, table_range: tuple[float, float] | None, given: np.ndarray | None
) -> tuple[float, float]:
    """The input range [deg]: given, else the table's, else the precision points'."""
    if x_range_deg is not None:
        try:
            lo_v, hi_v = x_range_deg
        except (TypeError, ValueError):
            raise InputError(
                f"x_range_deg must be (lo, hi) input angles [deg]; got {x_range_deg!r}"
            ) from None
        lo = finite_number("x_range_deg[0]", lo_v, "[deg]")
        return lo, finite_number("x_range_deg[1]", hi_v, "[deg]", low=lo, strict=True)
    if table_range is not None:
        return table_range
    if given is not None:
        return float(given[:, 0].min()), float(given[:, 0].max())
    raise InputError("x_range_deg = (lo, hi) [deg] is needed with a callable function")


def _ranked(
    mechanism: str,
    pts: np.ndarray,
    grid: np.ndarray,
    grid_want: np.ndarray,
    span: tuple[float, float],
    d: float,
    offsets: Any,
) -> list[FunctionCandidate]:
    """One candidate per offset (those with no real linkage left out, unless
    there is only the one), clean first, then by structural error, then by the
    larger worst transmission angle."""
    shifts = (
        [(0.0, 0.0)]
        if offsets is None
        else [tuple(o) for o in _pairs("offsets", offsets, mechanism)]
    )
    made: list[FunctionCandidate] = []
    first_error: InputError | None = None
    for dx, dy in shifts:
        try:
            made.append(_candidate(mechanism, pts, grid, grid_want, span, d, (dx, dy)))
        except InputError as e:
            if offsets is None:
                raise
            first_error = first_error or e
    if not made:
        assert first_error is not None
        raise InputError(f"no offset gives a real {mechanism}; the first says: {first_error}")
    made.sort(
        key=lambda c: (
            not c.clean,
            c.structural_error,
            -np.nan_to_num(c.margins.worst_transmission_deg, nan=-1.0),
        )
    )
    return made


def _candidate(
    mechanism: str,
    pts: np.ndarray,
    grid: np.ndarray,
    grid_want: np.ndarray,
    span: tuple[float, float],
    d: float,
    shift: tuple[float, float],
) -> FunctionCandidate:
    """One fit with the scales shifted by ``shift`` = (Δφ [deg], Δy)."""
    four = mechanism == "four-bar"
    dx, dy = shift
    to_out = math.radians if four else float
    x = [math.radians(v + dx) for v in pts[:, 0]]
    y = [to_out(v + dy) for v in pts[:, 1]]
    k, dims, flip_in, flip_out = _core.function_fit(mechanism, x, y, d)
    sig = _core.function_branches(mechanism, dims, flip_in, flip_out, x, y)
    branches = tuple(int(s) for s in sig)
    mode = branches[0] if branches[0] != 0 else 1
    gx = [math.radians(v + dx) for v in grid]
    gy = [to_out(v + dy) for v in grid_want]
    err, at = _core.function_error(mechanism, dims, flip_in, flip_out, float(mode), gx, gy)
    lo, hi = span[0] + dx, span[1] + dx
    full_turn = hi - lo >= 360.0
    defect = any(b != mode for b in branches)
    flip = 180.0 if flip_in else 0.0
    rng = (lo + flip, hi + flip)
    if four:
        a, b, c, _ = dims
        lengths = {"crank": a, "coupler": b, "rocker": c, "ground": d}
        m = four_bar_margins(a, b, c, d, range_deg=rng, branch_ok=not defect)
    else:
        r, ln, e, _ = dims
        lengths = {"crank": r, "rod": ln, "offset": e}
        m = slider_crank_margins(r, ln, e, range_deg=rng, branch_ok=not defect)
    if full_turn and not m.crank_turns:
        # A full-turn range asks for a crank: a rocker cannot hold it on one branch.
        m = Margins(
            m.grashof,
            m.crank_turns,
            m.transmission_min_deg,
            m.transmission_max_deg,
            False,
            m.length_ratio,
        )
    return FunctionCandidate(
        mechanism=mechanism,
        lengths=lengths,
        k=(k[0], k[1], k[2]),
        crank_flipped=flip_in,
        output_flipped=flip_out,
        mode=mode,
        precision=tuple((float(p + dx), float(q + dy)) for p, q in pts),
        branches=branches,
        branch_defect=defect,
        structural_error=math.degrees(err) if four and math.isfinite(err) else err,
        structural_error_at_deg=float(grid[at] + dx),
        margins=m,
        offset=(float(dx), float(dy)),
    )
