"""Electronic cam tables: `_export` part of :mod:`cyclomech.motion` (its door).

A drive rebuilds a program from a table of master angle → slave position,
velocity and acceleration at a chosen resolution, or exactly from each piece's
closed form. Both are CSV with a documented header: one line of column names with
their units, numbers in ``%.17g`` (every float64 written exactly).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._arrays import count, instance
from .._errors import InputError
from .._files import file_target, savetxt
from ._program import Program

__all__ = ["COEFFICIENT_COLUMNS", "TABLE_COLUMNS", "write_cam_coefficients", "write_cam_table"]

#: The columns of :func:`write_cam_table` (position in m, or rad for a rotary axis).
TABLE_COLUMNS = ("master_deg", "s", "v_per_rad", "a_per_rad2", "j_per_rad3")
#: Polynomial coefficients per piece in :func:`write_cam_coefficients`.
_DEGREES = 8
#: The columns of :func:`write_cam_coefficients`.
COEFFICIENT_COLUMNS = (
    "segment",
    "master_start_deg",
    "master_end_deg",
    *(f"c{k}" for k in range(_DEGREES)),
    "sine_amplitude",
    "sine_omega_per_rad",
    "sine_phase_rad",
)


def write_cam_table(program: Program, path: Any, *, points: int = 3600) -> Any:
    """Write ``program`` as a cam table: master angle → s, v, a, j at ``points`` steps.

    Rows at master angles 0, 360/points, …, 360° (both ends: the last row is the
    next cycle's start, s + ``advance``); columns :data:`TABLE_COLUMNS`: the master
    angle [deg], the slave position s [m, or rad for a rotary axis] and its
    derivatives per radian of master (at ω [rad/s]: v·ω, a·ω², j·ω³). One Rust call.

    Parameters
    ----------
    program : Program
        The motion program.
    path : str or os.PathLike
        The CSV file to write (its folder must exist).
    points : int, default 3600
        Steps over the cycle, at least 2.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        If ``program`` is not a :class:`Program`, ``points`` is not an integer ≥ 2,
        or ``path`` is not a writable file path.

    Examples
    --------
    >>> import tempfile, pathlib, cyclomech as cm
    >>> S = cm.motion.Segment
    >>> p = cm.motion.Program([S("cycloidal", 180, end=0.1), S("cycloidal", 180, end=0.0)])
    >>> f = cm.motion.write_cam_table(p, pathlib.Path(tempfile.mkdtemp()) / "t.csv", points=4)
    >>> f.read_text().splitlines()[0]
    'master_deg,s,v_per_rad,a_per_rad2,j_per_rad3'
    >>> len(f.read_text().splitlines())
    6
    """
    instance("program", program, Program)
    n = count("points", points, low=2)
    target = file_target("path", path)
    deg = np.linspace(0.0, 360.0, n + 1)
    m = program.evaluate(np.radians(deg))
    table = np.column_stack([deg, m.s, m.v, m.a, m.j])
    return _write(target, table, TABLE_COLUMNS)


def write_cam_coefficients(program: Program, path: Any) -> Any:
    """Write ``program``'s pieces in closed form, so that a drive rebuilds it exactly.

    One row per piece (a segment has one or several); columns
    :data:`COEFFICIENT_COLUMNS`: its segment's index, its master start and end
    angles [deg], and s = Σ c_k t^k + A·sin(ω t + φ) with t [rad] the master angle
    from the piece's start, c_k [m or rad per rad^k] (c0 … c7, zeros beyond the
    piece's degree), A [m or rad], ω [per rad] and φ [rad] (A = 0 for a polynomial
    piece). A polynomial segment is one piece: its c_k are its polynomial in t from
    the segment's start (VDI 2143's s = s₀ + h·Σ C_k z^k with z = t/β has
    C_k = c_k β^k / h).

    Parameters
    ----------
    program : Program
        The motion program.
    path : str or os.PathLike
        The CSV file to write (its folder must exist).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        If ``program`` is not a :class:`Program` or ``path`` is not a writable file path.

    Examples
    --------
    >>> import tempfile, pathlib, cyclomech as cm
    >>> S = cm.motion.Segment
    >>> p = cm.motion.Program([S("poly5", 180, end=0.1), S("poly5", 180, end=0.0)])
    >>> f = cm.motion.write_cam_coefficients(p, pathlib.Path(tempfile.mkdtemp()) / "c.csv")
    >>> rows = f.read_text().splitlines()
    >>> rows[0].split(",")[:5], len(rows)
    (['segment', 'master_start_deg', 'master_end_deg', 'c0', 'c1'], 3)
    """
    instance("program", program, Program)
    target = file_target("path", path)
    rows = []
    for seg, x0, x1, poly, amp, omega, phase in program._kernel.pieces:
        # A named law's pieces come integrated from its acceleration, one
        # coefficient longer than its degree (polynomial_4567: 9, the last 0).
        coeffs = np.asarray(poly, dtype=float)
        nonzero = np.flatnonzero(coeffs)
        kept = coeffs[: nonzero[-1] + 1 if nonzero.size else 0]
        if len(kept) > _DEGREES:
            raise InputError(
                f"program: segment {seg} has a piece of degree {len(kept) - 1}; the "
                f"coefficient file holds degree 7 at most (c0 … c7): write it with "
                f"write_cam_table"
            )
        c = np.zeros(_DEGREES)
        c[: len(kept)] = kept
        rows.append([seg, np.degrees(x0), np.degrees(x1), *c, amp, omega, phase])
    return _write(target, np.array(rows, dtype=float), COEFFICIENT_COLUMNS, first="%d")


def _write(target: Any, table: Any, columns: tuple[str, ...], first: str = "%.17g") -> Any:
    """A CSV with one header line of ``columns``, numbers in ``%.17g`` (exact), the
    first column in ``first``."""
    fmt = [first, *(["%.17g"] * (len(columns) - 1))]
    return savetxt(target, table, delimiter=",", header=",".join(columns), comments="", fmt=fmt)
