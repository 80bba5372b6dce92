"""Seed 001's three knife-drive schemes synthesised for one requirement and
compared side by side: transmission angles, the knife's peak
acceleration and jerk, driving torque and joint loads by the kinetostatics, and
the speed limit.

**Jerk.** The knife's acceleration analog d²xy/dφ² of a linkage turning at
constant speed is a smooth 2π-periodic function of the crank angle, so its
derivative is taken spectrally: the FFT of the analog on a uniform grid of
``JERK_POINTS`` angles, times i·k, back. For an analytic periodic function
the error falls exponentially with the grid (the test checks it against a
central difference of the solver's own acceleration analog). Jerk = ω³ · that
third derivative; acceleration = ω² · the second (ω the crank speed [rad/s]).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import count, finite_number, positive
from .._errors import InputError
from .._units import RAD_PER_S_PER_RPM
from ..forces import Kinetostatics, LinkMass, PointLoad, kinetostatics
from ..linkage import Linkage, LinkageSolution
from ._knife import SCHEMES, KnifeDrive, KnifeRequirement, knife_drive, transmission_angles

__all__ = ["JERK_POINTS", "KnifeComparison", "compare_knife_drives", "knife_forces"]

Array = npt.NDArray[np.float64]

#: Crank angles of the comparison's uniform grid (0.25°): the spectral jerk and
#: the peaks are read on it.
JERK_POINTS = 1440


def spectral_derivative(values: Array, axis: int = 0) -> Array:
    """d/dφ of samples of a 2π-periodic function on a uniform grid of one turn
    (no repeated end), by FFT; the Nyquist mode of an even grid is dropped."""
    n = values.shape[axis]
    k = np.fft.fftfreq(n, 1.0 / n)
    if n % 2 == 0:
        k[n // 2] = 0.0
    shape = [1] * values.ndim
    shape[axis] = n
    spec = np.fft.fft(values, axis=axis) * (1j * k).reshape(shape)
    return np.real(np.fft.ifft(spec, axis=axis))


def knife_forces(
    drive: KnifeDrive | Linkage,
    angles: Array,
    *,
    holder_kg: float = 80.0,
    link_kg_per_m: float = 10.0,
    cut_force_n: float = 0.0,
    cut: tuple[float, float] | None = None,
) -> Kinetostatics:
    """The kinetostatics of a knife drive with the comparison's mass model.

    The knife holder B–C–E has ``holder_kg`` at its joints' centroid with the
    inertia of a slender bar of length BC (m·BC²/12); every other moving link
    ``link_kg_per_m`` times its length (a ternary link: the sum of its sides),
    at its joints' centroid, inertia m·L²/12 of its longest side; gravity −9.81
    m/s² along y; the pile resists the knife with ``cut_force_n`` upwards on E
    over the cut (a table from the top to the bottom, ramps of 5° or a quarter
    of the cut).

    Parameters
    ----------
    drive : KnifeDrive or Linkage
        The knife drive (its ``cut`` taken from the drive when not given).
    angles : ndarray
        Absolute crank angles [rad].
    holder_kg, link_kg_per_m, cut_force_n : float
        The mass model [kg, kg/m] and the cutting force [N] (≥ 0).
    cut : (float, float), optional
        (top, bottom) crank angles [deg] of the cut; default the drive's.

    Returns
    -------
    Kinetostatics
        :func:`cyclomech.forces.kinetostatics` of the linkage.

    Examples
    --------
    >>> import numpy as np
    >>> from cyclomech.linkage import presets
    >>> from cyclomech.synthesis import knife_forces
    >>> k = knife_forces(presets.br125(), np.radians(np.arange(0, 360, 10.0)))
    >>> k.torque(60.0).shape
    (36,)
    """
    lk = drive.linkage if isinstance(drive, KnifeDrive) else drive
    if not isinstance(lk, Linkage):
        raise InputError(f"drive must be a KnifeDrive or a Linkage; got {type(drive).__name__}")
    m_h = positive("holder_kg", holder_kg, "[kg]")
    rho = positive("link_kg_per_m", link_kg_per_m, "[kg/m]")
    f_cut = finite_number("cut_force_n", cut_force_n, "[N]", low=0.0)
    ground = set(lk.to_dict()["ground"])
    masses: dict[Sequence[str], LinkMass] = {}
    for link in lk.to_dict()["links"]:
        if all(p in ground for p in link):
            continue
        sides = [lk.length(a, b) for i, a in enumerate(link) for b in link[i + 1 :]]
        if set(link) == {"B", "C", "E"}:
            bc = lk.length("B", "C")
            masses[tuple(link)] = LinkMass(m_h, inertia_kg_m2=m_h * bc * bc / 12.0)
        else:
            m = rho * sum(sides)
            masses[tuple(link)] = LinkMass(m, inertia_kg_m2=m * max(sides) ** 2 / 12.0)
    loads: list[Any] = []
    if f_cut > 0.0:
        if cut is None:
            if not isinstance(drive, KnifeDrive):
                raise InputError("cut_force_n needs the cut's angles: give cut=(top, bottom)")
            top = drive.top_deg
            cut = (top, top + drive.cut_deg)
        t0, t1 = float(cut[0]), float(cut[1])
        if t1 <= t0:
            t1 += 360.0
        ramp = min(5.0, (t1 - t0) / 4.0)
        loads.append(
            PointLoad(
                "E",
                [[0.0, 0.0], [0.0, f_cut], [0.0, f_cut], [0.0, 0.0]],
                angle_deg=[t0, t0 + ramp, t1 - ramp, t1],
            )
        )
    return kinetostatics(lk, angles, masses=masses, loads=loads, gravity=(0.0, -9.81))


@dataclass(frozen=True)
class KnifeComparison:
    """The schemes synthesised for one requirement, side by side.

    Attributes
    ----------
    requirement : KnifeRequirement
        What each was synthesised for.
    rpm : float
        The crank speed of the dynamic columns [rpm].
    drives : dict of str to KnifeDrive
        Each scheme's synthesis (schemes that could not meet the requirement are
        left out and named in ``failed``).
    rows : list of dict
        One row per scheme (see :meth:`table` for the columns).
    curves : dict of str to dict of str to ndarray
        Per scheme over ``angles`` (crank angle from each drive's top [deg]):
        ``s`` the knife's displacement [m], ``acc`` its acceleration along −y
        [m/s²], ``jerk`` [m/s³] along −y, ``torque`` [N·m].
    failed : dict of str to str
        The schemes that failed, with why.
    """

    requirement: KnifeRequirement
    rpm: float
    drives: dict[str, KnifeDrive]
    rows: list[dict[str, Any]]
    curves: dict[str, dict[str, Array]] = field(repr=False)
    angles: Array = field(repr=False)
    failed: dict[str, str] = field(default_factory=dict)

    #: (key, heading, format) of the table's columns.
    COLUMNS = (
        ("scheme", "scheme", "{}"),
        ("stroke_mm", "stroke [mm]", "{:.2f}"),
        ("cut_deg", "cut [deg]", "{:.2f}"),
        ("min_transmission_deg", "min μ [deg]", "{:.1f}"),
        ("peak_acceleration_m_s2", "peak |a| [m/s²]", "{:.3g}"),
        ("peak_jerk_m_s3", "peak |j| [m/s³]", "{:.3g}"),
        ("peak_torque_nm", "peak torque [N·m]", "{:.4g}"),
        ("rms_torque_nm", "rms torque [N·m]", "{:.4g}"),
        ("most_loaded_joint", "most loaded joint", "{}"),
        ("peak_joint_load_n", "its peak load [N]", "{:.4g}"),
        ("speed_limit_rpm", "speed limit [rpm]", "{:.4g}"),
    )

    def table(self) -> str:
        """The comparison as fixed-width text, one line per scheme.

        Examples
        --------
        >>> import cyclomech as cm
        >>> req = cm.synthesis.KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
        >>> c = cm.synthesis.compare_knife_drives(req, schemes=("br125",))
        >>> c.table().splitlines()[0].split()[0]
        'scheme'
        """
        head = [h for _, h, _ in self.COLUMNS]
        body = [[f.format(r[k]) for k, _, f in self.COLUMNS] for r in self.rows]
        widths = [max(len(x) for x in col) for col in zip(head, *body, strict=True)]
        lines = [
            "  ".join(x.rjust(w) for x, w in zip(row, widths, strict=True)) for row in [head, *body]
        ]
        lines += [f"{s}: {why}" for s, why in self.failed.items()]
        return "\n".join(lines)


def _row_and_curves(
    drive: KnifeDrive, rpm: float, max_acc: float, force_kw: dict[str, Any]
) -> tuple[dict[str, Any], dict[str, Array], LinkageSolution, Kinetostatics]:
    lk = drive.linkage
    top = math.radians(drive.top_deg)
    angles: Array = top + np.arange(JERK_POINTS, dtype=np.float64) * (2.0 * math.pi / JERK_POINTS)
    sol = lk.solve(angles)
    assert sol.vel is not None and sol.acc is not None
    k = sol.index("E")
    acc_an = sol.acc[:, k, :]
    jerk_an = spectral_derivative(acc_an, axis=0)
    w = rpm * RAD_PER_S_PER_RPM
    _, checks = SCHEMES[drive.scheme]
    mu = transmission_angles(sol, checks).min(axis=0)
    kin = knife_forces(drive, angles, **force_kw)
    torque = kin.torque(rpm)
    joint, peak_load, _ = kin.most_loaded(rpm)
    peak_acc_an = float(np.max(np.hypot(*acc_an.T)))
    row = {
        "scheme": drive.scheme,
        "stroke_mm": drive.stroke_m * 1e3,
        "cut_deg": drive.cut_deg,
        "min_transmission_deg": float(mu.min()),
        "transmission_deg": {c[1]: float(v) for c, v in zip(checks, mu, strict=True)},
        "peak_acceleration_m_s2": w * w * peak_acc_an,
        "peak_jerk_m_s3": w**3 * float(np.max(np.hypot(*jerk_an.T))),
        "peak_torque_nm": float(np.max(np.abs(torque))),
        "rms_torque_nm": float(np.sqrt(np.mean(torque**2))),
        "most_loaded_joint": joint,
        "peak_joint_load_n": float(peak_load),
        "speed_limit_rpm": (
            math.sqrt(max_acc / peak_acc_an) / RAD_PER_S_PER_RPM if max_acc > 0 else math.inf
        ),
    }
    curves = {
        "s": -sol.xy[:, k, 1] + sol.xy[0, k, 1],
        "acc": -w * w * acc_an[:, 1],
        "jerk": -(w**3) * jerk_an[:, 1],
        "torque": torque,
    }
    return row, curves, sol, kin


def compare_knife_drives(
    requirement: KnifeRequirement,
    schemes: Sequence[str] = ("br125", "br136", "brp4"),
    *,
    rpm: float = 45.0,
    max_acceleration_m_s2: float = 8.0,
    holder_kg: float = 80.0,
    link_kg_per_m: float = 10.0,
    cut_force_n: float = 0.0,
) -> KnifeComparison:
    """Synthesise each scheme for ``requirement`` and compare them side by side.

    Each scheme is synthesised by :func:`knife_drive` and then solved by its own
    :meth:`~cyclomech.Linkage.solve` on ``JERK_POINTS`` angles from its top:
    the least transmission angle at each checked joint, the knife's peak
    acceleration (ω²·max|d²E/dφ²|) and jerk (ω³·max|d³E/dφ³|, spectral; see the
    module), the driving torque and the most loaded joint by
    :func:`cyclomech.forces.kinetostatics` with :func:`knife_forces`'s mass
    model, and the speed at which the peak acceleration reaches
    ``max_acceleration_m_s2``.

    Parameters
    ----------
    requirement : KnifeRequirement
        The knife motion and constraints.
    schemes : sequence of str, default all three
        The schemes to compare.
    rpm : float, default 45
        The crank speed of the dynamic columns [rpm].
    max_acceleration_m_s2 : float, default 8
        The knife's allowed acceleration [m/s²] for the speed limit.
    holder_kg, link_kg_per_m, cut_force_n : float
        The mass model and cutting force of :func:`knife_forces`.

    Returns
    -------
    KnifeComparison
        The rows, the curves for the figures and the drives.

    Raises
    ------
    InputError
        For an unknown scheme, a malformed argument, or when no scheme meets the
        requirement (each one's reason named).

    Examples
    --------
    >>> import cyclomech as cm
    >>> req = cm.synthesis.KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
    >>> c = cm.synthesis.compare_knife_drives(req, schemes=("br125",), rpm=45.0)
    >>> c.rows[0]["scheme"], c.rows[0]["min_transmission_deg"] >= 30.0
    ('br125', True)
    """
    if not isinstance(requirement, KnifeRequirement):
        raise InputError(
            f"requirement must be a KnifeRequirement; got {type(requirement).__name__}"
        )
    if isinstance(schemes, str) or not isinstance(schemes, Sequence) or not schemes:
        raise InputError(f"schemes must be a non-empty list of scheme names; got {schemes!r}")
    for s in schemes:
        if s not in SCHEMES:
            raise InputError(
                f"schemes: no knife-drive scheme {s!r}; the schemes are {', '.join(SCHEMES)}"
            )
    n = positive("rpm", rpm, "[rpm]")
    amax = positive("max_acceleration_m_s2", max_acceleration_m_s2, "[m/s²]")
    force_kw = {"holder_kg": holder_kg, "link_kg_per_m": link_kg_per_m, "cut_force_n": cut_force_n}
    count("schemes", len(schemes), low=1, what="schemes")
    drives, rows, curves, failed = {}, [], {}, {}
    for s in dict.fromkeys(schemes):
        try:
            d = knife_drive(s, requirement=requirement)
        except InputError as e:
            failed[s] = str(e)
            continue
        row, cv, _, _ = _row_and_curves(d, n, amax, force_kw)
        drives[s], curves[s] = d, cv
        rows.append(row)
    if not drives:
        raise InputError(
            "no knife-drive scheme meets the requirement: "
            + "; ".join(f"{s}: {why}" for s, why in failed.items())
        )
    grid: Array = np.arange(JERK_POINTS, dtype=np.float64) * (360.0 / JERK_POINTS)
    return KnifeComparison(requirement, n, drives, rows, curves, grid, failed)
