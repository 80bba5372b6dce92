"""The cam's profile for a machinist: `_export` part of :mod:`cyclomech.cam` (its door).

:func:`profile_table` samples the exact profile (:meth:`Cam.solve`) at evenly spaced
cam angles; :func:`write_profile_csv` writes that table, lengths in **metres** (the
house's SI units, the column names carry them); :func:`write_profile_dxf` writes the
drawing a CAM program reads, lengths in **millimetres** ($INSUNITS = 4), with
`ezdxf <https://ezdxf.mozman.at>`_ (an optional dependency:
``pip install 'cyclomech[dxf]'``).

The DXF profile is a closed LWPOLYLINE through the sampled points, not a fit-point
SPLINE: its vertices are the exact profile points and what lies between them is a
chord, whose distance from the true curve (the chordal error h²/(8ρ) for a chord h
on a radius of curvature ρ) the table bounds and a warning reports; a fit-point
spline's curve between the points depends on how the reading program computes its
end tangents and knots, which the file does not pin down. Polylines are what CNC
post-processors cut from; more samples make the error as small as needed.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import count, finite_number, instance
from .._errors import CyclomechError, CyclomechWarning, InputError
from .._files import file_target, whole
from ._followers import FlatFaced, OscillatingRoller

if TYPE_CHECKING:
    from ._program import Cam

__all__ = [
    "CHORDAL_TOLERANCE_MM",
    "DxfUnavailableError",
    "cutter_path",
    "profile_table",
    "write_profile_csv",
    "write_profile_dxf",
]

#: The chordal error [mm] above which :func:`profile_table` warns.
CHORDAL_TOLERANCE_MM = 1e-3
#: The DXF's layers: what lies on each.
LAYERS = {
    "PROFILE": "the cam profile (the inner flank of a groove)",
    "GROOVE_OUTER": "the outer flank of a groove",
    "PITCH": "the pitch curve (the roller centre's path)",
    "BASE": "the base circle",
    "CENTRE": "the cam centre (a POINT)",
    "CUTTER": "the centre path of a cutter of the given radius along the profile",
    "CUTTER_OUTER": "the cutter's centre path along a groove's outer flank",
}
_MM = 1000.0


class DxfUnavailableError(CyclomechError, ImportError):
    """The DXF writer needs ezdxf, which is not installed.

    A :class:`cyclomech.CyclomechError`, so a ``ValueError``, and an
    ``ImportError``.

    Examples
    --------
    >>> issubclass(DxfUnavailableError, ValueError), issubclass(DxfUnavailableError, ImportError)
    (True, True)
    """


def _samples(samples: Any) -> int:
    return count("samples", samples, low=3, what="cam angles over one turn")


def profile_table(
    cam: Cam, samples: int = 3600, tool_radius: float | None = None
) -> dict[str, npt.NDArray[Any]]:
    """The cam's exact geometry at evenly spaced cam angles over one turn.

    θ = 0, 360°/samples, … (the last is not 360°: the curves are closed), one Rust
    call. If the chordal error exceeds ``CHORDAL_TOLERANCE_MM`` (1e-3 mm)
    anywhere away from an undercut, a :class:`cyclomech.CyclomechWarning` says where
    and how many samples would do.

    Parameters
    ----------
    cam : Cam
        The cam.
    samples : int, default 3600
        The number of cam angles over the turn (≥ 3).
    tool_radius : float, optional
        A cutter's radius [m]: adds the centre path of a cutter of that radius
        that cuts the profile (:func:`cutter_path`); default None (none).

    Returns
    -------
    dict of str to ndarray, each shape (samples,)
        The columns, lengths in **m** (the names carry the units):

        * ``theta_deg`` [deg]; ``s_m`` (``s_rad`` for an oscillating follower) the
          follower displacement;
        * ``pitch_x_m``, ``pitch_y_m``: the pitch curve; ``profile_x_m``,
          ``profile_y_m``: the profile (a groove's inner flank); ``outer_x_m``,
          ``outer_y_m``: a groove's outer flank (groove closure only);
        * ``pressure_angle_deg`` [deg], signed;
        * ``pitch_curvature_radius_m``, ``profile_curvature_radius_m``: the signed
          radii of curvature (+ convex, − concave, inf straight), the profile's of
          the inner flank;
        * ``chordal_error_m``: the distance from the chord to the next point to the
          curve, h²/(8ρ) with ρ the smaller |radius| at its ends (the largest of the
          flanks; 0 where straight, NaN at an undercut point);
        * ``undercut``: bool;
        * with ``tool_radius``: ``cutter_x_m``, ``cutter_y_m`` (and a groove's
          ``outer_cutter_x_m``, ``outer_cutter_y_m``): the cutter's centre path.

    Raises
    ------
    InputError
        If ``samples`` is not an integer ≥ 3, or ``tool_radius`` is not > 0 or the
        follower is a knife edge (:func:`cutter_path`).

    Examples
    --------
    >>> import cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> t = cm.cam.profile_table(cam, 720)
    >>> t["theta_deg"][:3].tolist(), round(float(t["profile_y_m"][0]), 12)
    ([0.0, 0.5, 1.0], 0.05)
    """
    from ._program import Cam  # at call time, as the type-only import above

    instance("cam", cam, Cam)
    n = _samples(samples)
    deg = np.arange(n) * (360.0 / n)
    k = cam.solve(np.radians(deg))
    angular = isinstance(cam.follower, OscillatingRoller)
    table: dict[str, npt.NDArray[Any]] = {
        "theta_deg": deg,
        "s_rad" if angular else "s_m": k.s.copy(),
        "pitch_x_m": k.pitch[:, 0].copy(),
        "pitch_y_m": k.pitch[:, 1].copy(),
        "profile_x_m": k.profile[:, 0].copy(),
        "profile_y_m": k.profile[:, 1].copy(),
    }
    if k.profile_outer is not None:
        table["outer_x_m"] = k.profile_outer[:, 0].copy()
        table["outer_y_m"] = k.profile_outer[:, 1].copy()
    table["pressure_angle_deg"] = np.degrees(k.pressure_angle)
    table["pitch_curvature_radius_m"] = k.pitch_radius_of_curvature.copy()
    table["profile_curvature_radius_m"] = k.profile_radius_of_curvature.copy()
    table["chordal_error_m"] = _chordal_error(cam, k)
    table["undercut"] = k.undercut.copy()
    if tool_radius is not None:
        paths = _cutter(cam, k, tool_radius)
        table["cutter_x_m"], table["cutter_y_m"] = paths[0][:, 0], paths[0][:, 1]
        if len(paths) == 2:
            table["outer_cutter_x_m"], table["outer_cutter_y_m"] = paths[1][:, 0], paths[1][:, 1]
        _warn_gouge(table, tool_radius)
    _warn_chordal(table, n)
    return table


def _tool_radius(tool_radius: Any, cam: Cam) -> float:
    r = finite_number("tool_radius", tool_radius, "[m]", low=0.0)
    if r <= 0.0:
        raise InputError(f"tool_radius = {r!r} [m] must be > 0")
    if not isinstance(cam.follower, FlatFaced) and cam.follower.roller_radius == 0.0:
        raise InputError(
            "tool_radius: a knife-edge follower's profile is its pitch curve, with no "
            "roller to take the normal from; cut it from profile_x_m, profile_y_m"
        )
    r_r = getattr(cam.follower, "roller_radius", None)
    if cam.closure == "groove" and r_r is not None and r > r_r:
        # The outer flank is cut from inside the groove (2·r_r wide): a wider
        # cutter's centre falls on the far side of the pitch curve and its disc
        # cuts 2·(r_t − r_r) into the opposite flank.
        raise InputError(
            f"tool_radius = {r!r} [m] is larger than the roller radius {r_r!r} [m]: a "
            f"groove is 2·r_r wide and both its flanks are cut from inside it, so a "
            f"wider cutter cuts {2 * (r - r_r):.3g} m into the opposite flank; use a "
            f"tool_radius of at most {r_r!r} m"
        )
    return r


def _cutter(cam: Cam, k: Any, tool_radius: Any) -> list[npt.NDArray[np.float64]]:
    """The cutter's centre paths (the profile's, then a groove's outer flank's)."""
    r_t = _tool_radius(tool_radius, cam)
    if isinstance(cam.follower, FlatFaced):
        # The face's normal is the follower's axis, through the cam centre: the
        # pitch point (the face's point on the axis) gives its direction.
        n = k.pitch / np.hypot(k.pitch[:, 0], k.pitch[:, 1])[:, None]
        return [k.profile + r_t * n]
    r_r = float(cam.follower.roller_radius)
    n = (k.pitch - k.profile) / r_r  # the profile's outward normal, exactly
    out = [k.pitch - (r_r - r_t) * n]
    if k.profile_outer is not None:
        out.append(k.pitch + (r_r - r_t) * n)
    return out


def cutter_path(cam: Cam, tool_radius: float, samples: int = 3600) -> npt.NDArray[np.float64]:
    """The centre path of a cutter (a milling or grinding tool) of radius
    ``tool_radius`` that cuts the cam's profile, at ``samples`` cam angles [m].

    The profile's outward normal n at the contact: for a roller follower
    (pitch − profile)/r_r, exactly; for a flat face the follower's axis. The
    cutter's centre is the profile point moved out by ``tool_radius`` along n: for a
    roller, pitch − (r_r − r_t)·n (the pitch curve itself for a cutter of the
    roller's size); a groove's outer flank is cut from inside the groove, at
    pitch + (r_r − r_t)·n (:func:`profile_table`'s ``outer_cutter_*``). Where the
    profile is concave with a radius of curvature smaller than the cutter's, the
    cutter would gouge it: :func:`profile_table` warns. A groove's cutter must fit
    in the groove (``tool_radius`` ≤ r_r): a wider one is refused.

    Parameters
    ----------
    cam : Cam
        The cam (a roller or flat-faced follower).
    tool_radius : float
        The cutter's radius [m], > 0.
    samples : int, default 3600
        The number of cam angles over the turn (≥ 3), as :func:`profile_table`'s.

    Returns
    -------
    ndarray of float, shape (samples, 2)
        The cutter's centre along the profile (a groove's inner flank) [m].

    Raises
    ------
    InputError
        If ``tool_radius`` is not > 0, the follower is a knife edge or ``samples``
        is not an integer ≥ 3.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> c = cm.cam.cutter_path(cam, 0.01, 360)           # the roller's size: the pitch curve
    >>> bool(np.allclose(c, cam.solve(np.radians(np.arange(360.0))).pitch, atol=1e-15))
    True
    """
    from ._program import Cam  # at call time, as the type-only import above

    instance("cam", cam, Cam)
    n = _samples(samples)
    k = cam.solve(np.radians(np.arange(n) * (360.0 / n)))
    return _cutter(cam, k, tool_radius)[0]


def _warn_gouge(table: dict[str, npt.NDArray[Any]], tool_radius: float) -> None:
    """Warn where the profile is concave tighter than the cutter (it would gouge)."""
    rho = table["profile_curvature_radius_m"]
    bad = (rho < 0) & (-rho < tool_radius)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        warnings.warn(
            f"a cutter of radius {tool_radius * _MM:g} mm gouges the profile where it is "
            f"concave tighter than that: from θ = {table['theta_deg'][i]:.4g}° "
            f"(radius of curvature {-rho[i] * _MM:.4g} mm; {int(bad.sum())} of "
            f"{rho.size} samples); take a smaller cutter",
            CyclomechWarning,
            stacklevel=3,
        )


def _chordal_error(cam: Cam, k: Any) -> npt.NDArray[np.float64]:
    """Per chord (point i to i+1, the last back to the first): h²/(8ρ) on each
    flank, the larger; ρ the smaller |radius| at the chord's ends. A groove's
    outer flank is the pitch curve offset outward by the roller radius: its
    radius of curvature is ρ_pitch + r_r."""
    flanks = [(k.profile, np.abs(k.profile_radius_of_curvature))]
    if k.profile_outer is not None:
        rr = float(getattr(cam.follower, "roller_radius", 0.0))
        flanks.append((k.profile_outer, np.abs(k.pitch_radius_of_curvature + rr)))
    err = np.zeros(len(k.s))
    for pts, rho in flanks:
        h = np.hypot(*(np.roll(pts, -1, axis=0) - pts).T)
        r = np.minimum(rho, np.roll(rho, -1))
        with np.errstate(divide="ignore", invalid="ignore"):
            e = np.where(np.isinf(r), 0.0, h * h / (8.0 * r))
        err = np.maximum(err, e)
    bad = k.undercut | np.roll(k.undercut, -1)
    return np.where(bad, np.nan, err)


def _warn_chordal(table: dict[str, npt.NDArray[Any]], n: int) -> None:
    err = table["chordal_error_m"] * _MM
    if not np.isfinite(err).any():
        return
    i = int(np.nanargmax(err))
    worst = float(err[i])
    if worst <= CHORDAL_TOLERANCE_MM:
        return
    # The error falls as 1/samples²: this many would do (with a margin of 5 %).
    need = math.ceil(n * math.sqrt(worst / CHORDAL_TOLERANCE_MM) * 1.05)
    warnings.warn(
        f"samples = {n} leaves a chordal error of {worst:.3g} mm (> {CHORDAL_TOLERANCE_MM:g} mm) "
        f"at θ = {table['theta_deg'][i]:.4g}°; samples ≥ {need} would keep it within",
        CyclomechWarning,
        stacklevel=3,
    )


def write_profile_csv(
    cam: Cam, path: str | Path, samples: int = 3600, tool_radius: float | None = None
) -> Path:
    """Write :func:`profile_table` to ``path`` as CSV.

    One header line of the column names with their units (lengths in m, angles in
    deg, ``undercut`` 0 or 1), one row per cam angle, 17 significant digits (a
    float64 round trips).

    Parameters
    ----------
    cam : Cam
        The cam.
    path : str or Path
        The CSV file to write.
    samples : int, default 3600
        The number of cam angles over the turn (≥ 3).
    tool_radius : float, optional
        A cutter's radius [m]: the columns of its centre path too
        (:func:`cutter_path`); default None.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    InputError
        If ``samples`` is not an integer ≥ 3 or ``tool_radius`` is invalid.
    OSError
        If the file cannot be written (a full disk, no permission), naming the
        file; no half-written file is left.

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np, cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> p = cm.cam.write_profile_csv(cam, pathlib.Path(tempfile.mkdtemp()) / "p.csv", 720)
    >>> p.read_text().splitlines()[0][:42]
    'theta_deg,s_m,pitch_x_m,pitch_y_m,profile_'
    """
    table = profile_table(cam, samples, tool_radius)
    p = file_target("path", path)
    cols = [v.astype(np.float64) for v in table.values()]
    fmt = ["%.17g"] * (len(cols) - 1) + ["%d"]
    with whole(p) as tmp:  # a full disk or a Ctrl-C leaves no half-written profile
        np.savetxt(
            tmp,
            np.column_stack(cols),
            delimiter=",",
            comments="",
            header=",".join(table),
            fmt=fmt,
        )
    return p


def write_profile_dxf(
    cam: Cam, path: str | Path, samples: int = 3600, tool_radius: float | None = None
) -> Path:
    """Write the cam as a DXF drawing (R2013), lengths in **mm**.

    $INSUNITS = 4, $MEASUREMENT metric, the cam centre at the origin in the cam
    frame of :mod:`cyclomech.cam`: the profile as a closed LWPOLYLINE of
    ``samples`` vertices on layer PROFILE (a groove's inner flank), a groove's
    outer flank on GROOVE_OUTER, the pitch curve on PITCH, the base circle (a
    CIRCLE) on BASE and the centre (a POINT) on CENTRE. A polyline, not a spline:
    its vertices are the exact profile points, and the chordal error between them
    is :func:`profile_table`'s ``chordal_error_m`` (a warning when ``samples`` leaves
    more than 1 µm). Needs ezdxf (``pip install 'cyclomech[dxf]'``).

    Parameters
    ----------
    cam : Cam
        The cam.
    path : str or Path
        The DXF file to write.
    samples : int, default 3600
        The number of profile vertices over the turn (≥ 3).
    tool_radius : float, optional
        A cutter's radius [m]: its centre path on layer CUTTER (a groove's outer
        flank's on CUTTER_OUTER), :func:`cutter_path`; default None.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    DxfUnavailableError
        If ezdxf is not installed (before the file is touched).
    InputError
        If ``samples`` is not an integer ≥ 3 or ``tool_radius`` is invalid.
    OSError
        If the file cannot be written (a full disk, no permission), naming the
        file; no half-written file is left.

    Examples
    --------
    >>> import tempfile, pathlib, cyclomech as cm
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> p = cm.cam.write_profile_dxf(cam, pathlib.Path(tempfile.mkdtemp()) / "cam.dxf", 720)
    >>> import ezdxf
    >>> doc = ezdxf.readfile(p)
    >>> doc.header["$INSUNITS"], len(doc.modelspace().query("LWPOLYLINE[layer=='PROFILE']")[0])
    (4, 720)
    """
    try:
        import ezdxf
    except ImportError:
        raise DxfUnavailableError(
            "write_profile_dxf needs ezdxf, which is not installed: "
            "pip install 'cyclomech[dxf]' (or pip install ezdxf)"
        ) from None
    table = profile_table(cam, samples, tool_radius)
    doc = ezdxf.new("R2013", setup=False)
    doc.header["$INSUNITS"] = 4  # millimetres
    doc.header["$MEASUREMENT"] = 1  # metric
    for name, what in LAYERS.items():
        doc.layers.add(name).description = what
    msp = doc.modelspace()

    def polyline(x: str, y: str, layer: str) -> None:
        pts = np.column_stack([table[x], table[y]]) * _MM
        msp.add_lwpolyline(pts.tolist(), format="xy", close=True, dxfattribs={"layer": layer})

    polyline("profile_x_m", "profile_y_m", "PROFILE")
    if "outer_x_m" in table:
        polyline("outer_x_m", "outer_y_m", "GROOVE_OUTER")
    polyline("pitch_x_m", "pitch_y_m", "PITCH")
    if "cutter_x_m" in table:
        polyline("cutter_x_m", "cutter_y_m", "CUTTER")
    if "outer_cutter_x_m" in table:
        polyline("outer_cutter_x_m", "outer_cutter_y_m", "CUTTER_OUTER")
    msp.add_circle((0.0, 0.0), cam.follower.base_radius * _MM, dxfattribs={"layer": "BASE"})
    msp.add_point((0.0, 0.0), dxfattribs={"layer": "CENTRE"})
    p = file_target("path", path)
    with whole(p) as tmp:  # a full disk or a Ctrl-C leaves no half-written drawing
        doc.saveas(tmp)
    return p
