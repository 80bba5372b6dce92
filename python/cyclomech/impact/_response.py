"""The exact response of a damped oscillator to a piecewise-linear force, in Rust:
:func:`duhamel`, :func:`duhamel_batch` and the first rebound without histories
(:func:`first_rebound`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import flag, float_array, out_array, real, threads_arg
from .._errors import InputError
from ._checks import Array

__all__ = ["Rebound", "duhamel", "duhamel_batch", "first_rebound"]


_F64 = np.dtype(np.float64)


def _grid(name: str, value: Any) -> Array:
    # The common case first, in a few attribute reads: a non-empty 1-D
    # C-contiguous float64 array is taken as it is (issue 20: the checks below
    # cost a few µs, a tenth of a 10 000-step call).
    if (
        type(value) is np.ndarray
        and value.dtype is _F64
        and value.ndim == 1
        and value.size
        and value.flags.c_contiguous
    ):
        return value
    a = float_array(name, value, ndims=(1,))
    if a.size < 1:
        raise InputError(f"{name} must hold at least one time [s]")
    return a


def _cases(b: int, **fields: Any) -> list[Array]:
    """Each per-case field as a contiguous (b,) array (scalars broadcast)."""
    out = []
    for name, value in fields.items():
        a = float_array(name, value, ndims=(0, 1))
        if a.size == 1:
            a = np.full(b, float(a.reshape(-1)[0]))
        elif a.size != b:
            raise InputError(
                f"{name} must be a scalar or hold one value per case ({b}); got {a.size}"
            )
        out.append(np.ascontiguousarray(a))
    return out


def duhamel(
    t: npt.ArrayLike,
    force: npt.ArrayLike,
    *,
    omega_n: float,
    zeta: float,
    mass: float,
    q0: float = 0.0,
    v0: float = 0.0,
    velocity: bool = False,
) -> Any:
    """Exact response q(t) [m] of m·q̈ + 2ζω·m·q̇ + ω²·m·q = F(t) to a piecewise-linear force.

    The force F [N] is linear between the samples of ``t`` (first-order hold; the
    Duhamel integral in closed form from step to step, Nigam–Jennings), from
    q(t[0]) = ``q0``, q̇(t[0]) = ``v0``; over- and critically damped exactly too.

    ``t`` never decreases; a repeated time is a jump of the force there, so a force
    that starts at full value at t[0] (an impact) is exact, and so is a rectangular
    pulse.

    A uniform grid (steps equal to within 2⁻²⁷, as ``np.linspace`` or
    ``h * np.arange`` give) of at least 1025 samples runs as a chunked scan: eight
    blocks in vector lanes, stitched by the unforced motion's transition in closed
    form. Its values differ from the step-by-step recurrence (which other grids
    take) by rounding only: within 1e-12 of the state's peak (max |q| + max |q̇|/ω)
    — up to about 2e-12 over tens of thousands of undamped steps of ωh near 2, where
    the recurrence's own rounding error is larger — and as close to the exact
    solution.

    Parameters
    ----------
    t : array_like of float, shape (N,)
        The time grid [s], non-decreasing (a repeated time is a jump of the force).
    force : array_like of float, shape (N,)
        The force F at each time [N].
    omega_n : float
        The natural angular frequency ω [rad/s] (> 0). Keyword-only, as are the
        parameters below.
    zeta : float
        The damping ratio ζ (≥ 0).
    mass : float
        The mass m [kg] (> 0).
    q0 : float, default 0.0
        The displacement at t[0] [m].
    v0 : float, default 0.0
        The velocity at t[0] [m/s].
    velocity : bool, default False
        Return the velocity q̇ too.

    Returns
    -------
    q : ndarray of float, shape (N,)
        The displacement at each time [m].
    v : ndarray of float, shape (N,)
        The velocity q̇ at each time [m/s]; only with ``velocity=True`` (then the
        result is the tuple ``(q, v)``).

    Raises
    ------
    InputError
        If ``t`` or ``force`` is not a non-empty 1-D array of numbers, their sizes
        differ, ``t`` decreases, or a parameter is not a real number in its range.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> t = np.linspace(0.0, 1.0, 11)                    # a step force, undamped
    >>> q = cm.impact.duhamel(t, np.ones(11), omega_n=2.0, zeta=0.0, mass=1.0)
    >>> bool(np.allclose(q, (1 - np.cos(2 * t)) / 4, rtol=0, atol=1e-15))
    True
    """
    if (
        type(t) is np.ndarray
        and type(force) is np.ndarray
        and t.dtype is _F64
        and force.dtype is _F64
        and t.ndim == 1
        and force.ndim == 1
        and t.size
        and force.size
        and t.flags.c_contiguous
        and force.flags.c_contiguous
        and type(omega_n) is float
        and type(zeta) is float
        and type(mass) is float
        and type(q0) is float
        and type(v0) is float
        and velocity is False
    ):
        # The common call in a few attribute reads, each check once (issue 20:
        # the wrapper's function calls cost a tenth of a 10 000-step call).
        # The kernel checks the ranges and that the sizes agree.
        return _core.duhamel(t, force, omega_n, zeta, mass, q0, v0)
    ta, fa = _grid("t", t), _grid("force", force)
    # Real numbers only (a string, bytes, a bool or a complex is refused, not
    # read as a number); the kernel checks their ranges and names them.
    return _core.duhamel(
        ta,
        fa,
        _real("omega_n", omega_n, "[rad/s]"),
        _real("zeta", zeta, "(damping ratio)"),
        _real("mass", mass, "[kg]"),
        _real("q0", q0, "[m]"),
        _real("v0", v0, "[m/s]"),
        with_velocity=velocity if velocity is False else flag("velocity", velocity),
    )


def _real(name: str, value: Any, unit: str) -> float:
    """``value`` as a float if it is a real number (NaN and inf included: the
    kernels name those), else :class:`InputError`."""
    if type(value) is float:
        return value
    try:
        return real(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a real number {unit}; got {value!r}") from None


def duhamel_batch(
    t: npt.ArrayLike,
    forces: npt.ArrayLike,
    omega_n: npt.ArrayLike,
    zeta: npt.ArrayLike,
    mass: npt.ArrayLike,
    q0: npt.ArrayLike = 0.0,
    v0: npt.ArrayLike = 0.0,
    *,
    n_threads: int | None = None,
    out: Array | None = None,
) -> Any:
    """:func:`duhamel` for B cases on one time grid, computed in parallel in Rust.

    Parameters
    ----------
    t : array_like of float, shape (N,)
        The time grid [s], non-decreasing (a repeated time is a jump of the force).
    forces : array_like of float, shape (B, N)
        The force of each case at each time [N].
    omega_n : float or array_like of float, shape (B,)
        The natural angular frequency of each case [rad/s] (> 0).
    zeta : float or array_like of float, shape (B,)
        The damping ratio of each case (≥ 0).
    mass : float or array_like of float, shape (B,)
        The mass of each case [kg] (> 0).
    q0 : float or array_like of float, shape (B,), default 0.0
        The displacement at t[0] [m].
    v0 : float or array_like of float, shape (B,), default 0.0
        The velocity at t[0] [m/s].
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).
    out : ndarray of float, shape (B, N), optional
        A caller-owned array to write q into and return instead of a new one — a
        writeable, C-contiguous float64 ndarray that shares no memory with an
        input. A caller who runs batch after batch saves the new array's page faults
        and zeroing (about a third of the time of a large batch). Its old content is
        never read; the results are bit for bit those without ``out``. If the call
        raises, ``out`` may be partly written. Default None.

    Returns
    -------
    ndarray of float, shape (B, N)
        The displacement q of each case at each time [m] (``out`` if given).

    Raises
    ------
    InputError
        If an array has the wrong shape, a per-case value is neither a scalar nor
        one per case, a value is out of its range, or ``out`` is not a suitable
        buffer.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> t = np.linspace(0.0, 0.01, 101)
    >>> q = cm.impact.duhamel_batch(t, np.ones((3, 101)), 2 * np.pi * 297, [0.0, 0.05, 1.0], 0.01)
    >>> q.shape
    (3, 101)
    >>> buf = np.empty((3, 101))                         # reused from call to call
    >>> r = cm.impact.duhamel_batch(t, np.ones((3, 101)), 2 * np.pi * 297, [0.0, 0.05, 1.0], 0.01,
    ...                             out=buf)
    >>> r is buf, bool(np.array_equal(r, q))
    (True, True)
    """
    ta = _grid("t", t)
    fa = float_array("forces", forces, ndims=(2,))
    b = fa.shape[0]
    cases = _cases(b, omega_n=omega_n, zeta=zeta, mass=mass, q0=q0, v0=v0)
    if out is not None:
        given = [t, forces, omega_n, zeta, mass, q0, v0]
        out_array(out, (b, ta.size), [ta, fa, *cases, *given], "the responses q [m]")
    return _core.duhamel_batch(ta, fa, *cases, n_threads=threads_arg(n_threads), out=out)


@dataclass(frozen=True)
class Rebound:
    """First rebounds of a batch (see :func:`first_rebound`).

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    time : ndarray of float, shape (B,)
        The time of each case's first turn [s] (+inf where q never turns).
    q : ndarray of float, shape (B,)
        The displacement there [m].

    See Also
    --------
    first_rebound : Builds it.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.impact.first_rebound([0.0], [0.0], 1.0, 0.0, 1.0, v0=1.0)
    >>> r.time.round(6).tolist(), r.q.round(6).tolist()
    ([1.570796], [1.0])
    """

    time: Array
    q: Array


def first_rebound(
    t: npt.ArrayLike,
    forces: npt.ArrayLike,
    omega_n: npt.ArrayLike,
    zeta: npt.ArrayLike,
    mass: npt.ArrayLike,
    q0: npt.ArrayLike = 0.0,
    v0: npt.ArrayLike = 0.0,
    *,
    maximum: bool = False,
    n_threads: int | None = None,
) -> Rebound:
    """The first turn of q(t) after t[0] for each case, without histories.

    The first extremum (``maximum=True``: the first local maximum), found exactly by
    stepping from breakpoint to breakpoint of the pulse table and solving for q̇ = 0
    in closed form between them — O(breakpoints), not O(time steps). The force is
    held at its last value after the table. Where q never turns, ``time`` is inf and
    ``q`` the static deflection of the last force.

    Parameters
    ----------
    t : array_like of float, shape (N,)
        The pulse table's times [s], non-decreasing.
    forces : array_like of float, shape (B, N) or (N,)
        The force of each case at each time [N] (1-D for one case).
    omega_n : float or array_like of float, shape (B,)
        The natural angular frequency of each case [rad/s] (> 0).
    zeta : float or array_like of float, shape (B,)
        The damping ratio of each case (≥ 0).
    mass : float or array_like of float, shape (B,)
        The mass of each case [kg] (> 0).
    q0 : float or array_like of float, shape (B,), default 0.0
        The displacement at t[0] [m].
    v0 : float or array_like of float, shape (B,), default 0.0
        The velocity at t[0] [m/s].
    maximum : bool, default False
        Find the first local maximum instead of the first extremum.
    n_threads : int, optional
        Threads for the Rust kernel; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    Rebound
        Each case's first turn: ``time`` [s] and ``q`` [m], each (B,).

    Raises
    ------
    InputError
        As :func:`duhamel_batch`: an array of the wrong shape or a value out of its
        range.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> w = 2 * np.pi * 297
    >>> r = cm.impact.first_rebound([0.0], [0.0], w, 0.0, 1.0, v0=1.0)  # free vibration
    >>> bool(np.isclose(r.q[0], 1 / w, rtol=1e-14)), bool(np.isclose(r.time[0], np.pi / 2 / w))
    (True, True)
    """
    ta = _grid("t", t)
    fa = float_array("forces", forces, ndims=(1, 2))
    if fa.ndim == 1:
        fa = fa.reshape(1, -1)
    b = fa.shape[0]
    cases = _cases(b, omega_n=omega_n, zeta=zeta, mass=mass, q0=q0, v0=v0)
    time, q = _core.first_rebound_batch(
        ta, fa, *cases, maximum=flag("maximum", maximum), n_threads=threads_arg(n_threads)
    )
    return Rebound(time, q)
