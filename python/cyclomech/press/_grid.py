"""Criteria over a grid of designs (:func:`design_grid`, :class:`PressGrid`), computed in
chunks by the Rust kernel with a progress bar for long grids."""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import check_bytes, count, finite_number, flag, float_array, threads_arg
from .._errors import InputError
from .._progress import progress as progress_bar
from ._drive import (
    _AXES,
    CRITERIA,
    SAMPLES,
    STATUS,
    GearLeverPress,
    PressCriteria,
    _omega,
    _samples,
    _stroke,
)

__all__ = ["PressGrid", "design_grid"]


@dataclass(frozen=True)
class PressGrid:
    """Criteria over a Cartesian grid of designs (from :func:`design_grid`).

    ``ok`` is status 0. ``sw["k_Vp"]`` is ``sw.values["k_Vp"]`` (an unknown name is
    an :class:`~cyclomech.InputError` listing the criteria). Each parameter is kept
    as the attribute of the same name.

    Parameters
    ----------
    axes : dict of str to ndarray of float
        Each swept parameter (in the order R, r, d, L, phi0; those given as arrays)
        to its values [m, rad].
    fixed : dict of str to float
        The other parameters (and ``offset``) [m, rad].
    values : dict of str to ndarray of float
        For every name in :data:`CRITERIA`, an array of the grid's shape (units as
        :class:`PressCriteria`).
    status : ndarray of uint8
        Of the grid's shape: why a design fails (see :data:`STATUS`; 0 if it works).
    omega : float
        The crank speed ω [rad/s].
    k_Sp : float or None
        The working stroke as a fraction of the nominal stroke, if given so.
    working_stroke : float or None
        The working stroke S_p [m], if given so.
    samples : int, default SAMPLES
        Carrier angles per turn.
    elapsed : float, default 0.0
        The computing time [s] (not compared).

    Examples
    --------
    >>> import cyclomech as cm
    >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=0.0, k_Sp=0.1,
    ...                     omega=4.0)
    >>> list(sw.axes), sw.fixed["L"], sw["S_n"].shape
    (['d'], 0.3, (2,))
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
        """Shape of the grid (one entry per swept axis).

        Examples
        --------
        >>> import cyclomech as cm
        >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=[0.0, 0.02], L=[0.3, 0.4, 0.5], phi0=0.0,
        ...                     k_Sp=0.1, omega=4.0)
        >>> sw.shape
        (2, 3)
        """
        return self.status.shape

    @property
    def ok(self) -> npt.NDArray[np.bool_]:
        """True where the design works (status 0), of the grid's shape.

        Examples
        --------
        >>> import cyclomech as cm
        >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=0.0, k_Sp=0.1,
        ...                     omega=4.0)
        >>> sw.ok.tolist()
        [True, True]
        """
        return self.status == 0

    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        try:
            return self.values[name]
        except KeyError:
            raise InputError(f"no criterion {name!r}; criteria are {', '.join(CRITERIA)}") from None

    def _index(self, index: Any) -> tuple[Any, ...]:
        """A grid index as a tuple of per-axis indices: a flat index (a scalar)
        unravelled over the grid's shape, else the index's own entries."""
        size = int(np.prod(self.shape))
        if np.ndim(index) == 0:
            i = count("index", index, low=0, high=size - 1, what="a flat index over the grid")
            return np.unravel_index(i, self.shape)
        idx = tuple(index)
        if len(idx) != len(self.axes):
            raise InputError(f"index {index!r} must have {len(self.axes)} entries")
        return tuple(
            count(f"index[{k}]", v, low=0, high=n - 1)
            for k, (v, n) in enumerate(zip(idx, self.shape, strict=True))
        )

    def design(self, index: tuple[int, ...] | int) -> GearLeverPress:
        """The design at a grid index.

        Parameters
        ----------
        index : int or tuple of int
            A flat index over the grid, or one index per swept axis.

        Returns
        -------
        GearLeverPress
            The design there.

        Raises
        ------
        InputError
            If a tuple index has not one entry per swept axis.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=0.0, k_Sp=0.1,
        ...                     omega=4.0)
        >>> sw.design(1).d
        0.02
        """
        idx = self._index(index)
        if len(idx) != len(self.axes):
            raise InputError(f"index {index!r} must have {len(self.axes)} entries")
        par = dict(self.fixed)
        for (name, vals), i in zip(self.axes.items(), idx, strict=True):
            par[name] = float(vals[i])
        return GearLeverPress(**par)

    def at(self, index: tuple[int, ...] | int) -> PressCriteria:
        """The criteria of the design at a grid index.

        Parameters
        ----------
        index : int or tuple of int
            A flat index over the grid, or one index per swept axis.

        Returns
        -------
        PressCriteria
            The design's criteria, with its status.

        Examples
        --------
        >>> import cyclomech as cm
        >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=0.0, k_Sp=0.1,
        ...                     omega=4.0)
        >>> round(sw.at(0).S_n, 9)
        0.12
        """
        idx = self._index(index)
        vals = {k: float(v[idx]) for k, v in self.values.items()}
        return PressCriteria(**vals, omega=self.omega, status=STATUS[int(self.status[idx])])

    def table(self) -> dict[str, npt.NDArray[Any]]:
        """Flat columns (one row per design), for CSV or a data frame.

        Returns
        -------
        dict of str to ndarray
            The swept parameters, the criteria (k_Vp, k_Vmax, k_J, k_M first) and the
            status code, each a 1-D array of one entry per design.

        Examples
        --------
        >>> import cyclomech as cm
        >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=[0.0, 0.02], L=[0.3, 0.4], phi0=0.0,
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


#: Designs per kernel call of a large design grid (about half a second on one core).
_CHUNK = 250_000


def design_grid(
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
) -> PressGrid:
    """Criteria over the full Cartesian grid of designs, in parallel in Rust.

    A large grid runs in chunks of 250 000 designs, one Rust call each, with a
    progress bar on stderr; Ctrl-C stops between chunks. All parameters are
    keyword-only.

    Parameters
    ----------
    d : float or array_like of float
        The pin's eccentricity [m]: a scalar (fixed) or a 1-D array (an axis of the
        grid; the axes in the order R, r, d, L, phi0).
    L : float or array_like of float
        The rod's length [m], fixed or an axis.
    phi0 : float or array_like of float
        The guide gear's setting angle [rad], fixed or an axis.
    R : float or array_like of float
        The guide gear's pitch radius [m], fixed or an axis.
    r : float or array_like of float
        The planet gear's pitch radius [m], fixed or an axis.
    omega : float
        The crank speed ω [rad/s] (> 0).
    offset : float, default 0.0
        The slider's guide's offset from the centre [m].
    k_Sp : float, optional
        The working stroke as a fraction of the nominal stroke, in (0, 1]; give it
        or ``working_stroke`` (as in :meth:`GearLeverPress.criteria`).
    working_stroke : float, optional
        The working stroke S_p [m] (> 0).
    samples : int, default SAMPLES
        Carrier angles per turn (8 to 10⁶).
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
    progress : bool, optional
        Show a progress bar; default None (when stderr is a terminal and the grid is
        large).

    Returns
    -------
    PressGrid
        The criteria and status of every design, arrays of the grid's shape.

    Raises
    ------
    InputError
        If a value is not finite, an axis is empty, not exactly one of ``k_Sp`` and
        ``working_stroke`` is given, a value is out of range, or the grid would not
        fit in memory.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=np.linspace(0, 0.04, 5), L=[0.3, 0.4],
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
    # By default a bar only for a grid of several calls, on a terminal.
    show = (
        (n > 2 * _CHUNK and sys.stderr.isatty()) if progress is None else flag("progress", progress)
    )
    bar = progress_bar(n, "press.design_grid", show)
    threads = threads_arg(n_threads)
    check_bytes(
        f"press.design_grid's {n:,} designs", n * (8 * len(CRITERIA) + 1), "use a coarser grid"
    )
    table = np.empty((n, len(CRITERIA)))
    status = np.empty(n, dtype=np.uint8)
    t0 = time.perf_counter()
    try:
        for start in range(0, len(flat[lead]), step):
            part = list(flat)
            part[lead] = flat[lead][start : start + step]
            lo, hi = start * inner, min(start + step, len(flat[lead])) * inner
            # The chunk of each axis, in _AXES order (R, r, d, L, phi0).
            R_part, r_part, d_part, L_part, phi0_part = part
            _core.press_sweep(
                R_part,
                r_part,
                d_part,
                L_part,
                phi0_part,
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
    return PressGrid(axes, fixed, values, st, w, k, s, m, elapsed=time.perf_counter() - t0)
