"""A knife drive synthesised from a machine file's ``[mechanism.<name>.synthesize]``
table: the synthesizer this module registers with
:mod:`cyclomech.linkage` for the schemes ``br125``, ``br136`` and ``brp4``, and
the record it returns (the linkage and its part of the report)."""

from __future__ import annotations

import csv
import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import _keyrules, _toml
from .._arrays import finite_number, flag, positive
from .._errors import InputError
from ..linkage import Linkage, register_synthesizer
from ._knife import SCHEMES, KnifeDrive, KnifeRequirement, knife_drive
from ._knife_compare import KnifeComparison, compare_knife_drives

__all__ = ["SYNTHESIZE_KEYS", "KnifeSynthesis", "from_table"]

#: The requirement's keys (:class:`KnifeRequirement`'s fields, ``envelope`` as
#: ``envelope_m``) and the comparison's.
_REQ_KEYS = {
    "stroke_m": "stroke_m",
    "cut_deg": "cut_deg",
    "knife_m": "knife_m",
    "envelope_m": "envelope",
    "min_transmission_deg": "min_transmission_deg",
    "max_length_ratio": "max_length_ratio",
    "stroke_tol_m": "stroke_tol_m",
    "cut_tol_deg": "cut_tol_deg",
    "seed": "seed",
    "popsize": "popsize",
    "maxiter": "maxiter",
}
_COMPARE_KEYS = {
    "compare_rpm": "rpm",
    "compare_max_acceleration_m_per_s2": "max_acceleration_m_s2",
    "holder_kg": "holder_kg",
    "link_kg_per_m": "link_kg_per_m",
    "cut_force_n": "cut_force_n",
}
#: Every key of a knife drive's ``synthesize`` table.
SYNTHESIZE_KEYS = frozenset({"scheme", "compare", *_REQ_KEYS, *_COMPARE_KEYS})
_P = {"br125": 1, "br136": 2, "brp4": 3}


@functools.lru_cache(maxsize=32)
def _drive(scheme: str, req: KnifeRequirement) -> KnifeDrive:
    # A machine file is parsed again by sweeps and checks: synthesise once.
    return knife_drive(scheme, requirement=req)


@functools.lru_cache(maxsize=8)
def _compare(req: KnifeRequirement, kw: tuple[tuple[str, Any], ...]) -> KnifeComparison:
    return compare_knife_drives(req, **dict(kw))


@dataclass(frozen=True, init=False, repr=False, eq=False)
class KnifeSynthesis:
    """The knife drive a ``synthesize`` table asked for, with the comparison of
    the three schemes when ``compare = true``.

    Parameters
    ----------
    drive : KnifeDrive
        The synthesis of the table's scheme.
    comparison : KnifeComparison, optional
        The schemes side by side; None (default) for none.

    Attributes
    ----------
    drive : KnifeDrive
        The synthesis of the table's scheme.
    comparison : KnifeComparison or None
        The three schemes side by side (``compare = true``), None otherwise. A
        machine file's comparison is computed when first read (the report's rows,
        ``results.json``, figures and files read it): reading the file, checking
        it or sweeping it synthesises only the table's scheme. Either way it is
        :func:`~cyclomech.synthesis.compare_knife_drives` of the table's
        requirement, and its drive of the table's scheme is :attr:`drive`.

    Examples
    --------
    >>> from cyclomech.synthesis import KnifeRequirement, KnifeSynthesis, knife_drive
    >>> req = KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
    >>> s = KnifeSynthesis(knife_drive("br125", requirement=req))
    >>> s.comparison is None, s.linkage.output
    (True, 'E')
    """

    drive: KnifeDrive
    _comparison: KnifeComparison | None
    # (requirement, comparison keywords) of a comparison not computed yet, else None.
    _later: tuple[KnifeRequirement, tuple[tuple[str, Any], ...]] | None

    def __init__(self, drive: KnifeDrive, comparison: KnifeComparison | None = None) -> None:
        object.__setattr__(self, "drive", drive)
        object.__setattr__(self, "_comparison", comparison)
        object.__setattr__(self, "_later", None)

    @classmethod
    def _compared_later(
        cls, drive: KnifeDrive, req: KnifeRequirement, kw: tuple[tuple[str, Any], ...]
    ) -> KnifeSynthesis:
        """``drive`` with the comparison ``_compare(req, kw)`` computed when first read."""
        s = cls(drive)
        object.__setattr__(s, "_later", (req, kw))
        return s

    @property
    def comparison(self) -> KnifeComparison | None:
        """The schemes side by side (``compare = true``), None otherwise."""
        if self._later is not None:
            # The file's checks ran when it was read, so this cannot fail on them;
            # the table's own scheme is the cached drive (``_synthesise``'s cache).
            object.__setattr__(self, "_comparison", _compare(*self._later))
            object.__setattr__(self, "_later", None)
        return self._comparison

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, KnifeSynthesis):
            return NotImplemented
        return self.drive == other.drive and self.comparison == other.comparison

    __hash__ = None  # type: ignore[assignment]  # its drive holds dicts and arrays

    def __repr__(self) -> str:
        c = "(computed when first read)" if self._later is not None else repr(self._comparison)
        return f"KnifeSynthesis(drive={self.drive!r}, comparison={c})"

    @property
    def linkage(self) -> Linkage:
        """The synthesised linkage."""
        return self.drive.linkage

    def rows(self) -> list[list[Any]]:
        """The report table's rows: the scheme, why it was chosen, its lengths and
        margins, and each compared scheme's line.

        Examples
        --------
        >>> req = KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
        >>> s = KnifeSynthesis(_drive("br125", req))
        >>> s.rows()[0]
        ['synthesised scheme', 'br125 (seed 001, p = 1)']
        """
        d = self.drive
        lengths = ", ".join(
            f"{a}{b} {v:.4f}"
            for (a, b), v in zip(d.linkage.dimensions, d.linkage.dimension_values, strict=True)
        )
        margins = ", ".join(f"{k} {v:.3g}" for k, v in d.margins.items() if math.isfinite(v))
        rows: list[list[Any]] = [
            ["synthesised scheme", f"{d.scheme} (seed 001, p = {_P[d.scheme]})"],
            ["synthesis: what it chose and why", d.why()],
            ["synthesised lengths [m]", lengths],
            ["synthesis margins (≥ 0 holds)", margins],
        ]
        c = self.comparison
        if c is not None:
            for r in c.rows:
                rows.append(
                    [
                        f"scheme {r['scheme']} at {c.rpm:g} rpm",
                        f"min μ {r['min_transmission_deg']:.1f}°, peak |a| "
                        f"{r['peak_acceleration_m_s2']:.3g} m/s², peak |j| "
                        f"{r['peak_jerk_m_s3']:.3g} m/s³, peak torque {r['peak_torque_nm']:.4g} "
                        f"N·m, most loaded {r['most_loaded_joint']} "
                        f"{r['peak_joint_load_n']:.4g} N, speed limit "
                        f"{r['speed_limit_rpm']:.4g} rpm",
                    ]
                )
            for s, why in c.failed.items():
                rows.append([f"scheme {s}", f"not synthesised: {why}"])
        return rows

    def json(self) -> dict[str, Any]:
        """Its ``synthesis`` entry in ``results.json``.

        Examples
        --------
        >>> req = KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
        >>> s = KnifeSynthesis(_drive("br125", req))
        >>> s.json()["scheme"]
        'br125'
        """
        d = self.drive
        out: dict[str, Any] = {
            "scheme": d.scheme,
            "stroke_m": d.stroke_m,
            "cut_deg": d.cut_deg,
            "top_deg": d.top_deg,
            "lengths_m": {
                f"{a}{b}": float(v)
                for (a, b), v in zip(d.linkage.dimensions, d.linkage.dimension_values, strict=True)
            },
            "min_transmission_deg": d.min_transmission_deg,
            "margins": {k: (v if math.isfinite(v) else None) for k, v in d.margins.items()},
            "why": d.why(),
        }
        if self.comparison is not None:
            out["comparison"] = self.comparison.rows
            out["comparison_failed"] = self.comparison.failed
        return out

    def figures(self, save: Any, name: str) -> None:
        """The compared schemes' knife motion and driving torque (with ``compare``),
        each given to ``save(figure, stem, caption)``.

        Examples
        --------
        Without the comparison there is nothing to draw:

        >>> req = KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
        >>> s = KnifeSynthesis(_drive("br125", req))
        >>> s.figures(print, "knife") is None
        True
        """
        if self.comparison is None:
            return
        from .plot import plot_knife_motion, plot_knife_torque

        c = self.comparison
        save(
            plot_knife_motion(c, title=f"{name}: the knife-drive schemes' knife motion"),
            f"{name}_schemes_motion",
            "The knife's displacement and acceleration over the crank angle from its top, "
            f"each seed-001 scheme synthesised for the same requirement, at {c.rpm:g} rpm.",
        )
        save(
            plot_knife_torque(c, title=f"{name}: the knife-drive schemes' driving torque"),
            f"{name}_schemes_torque",
            "The driving torque of each synthesised scheme (the comparison's mass model) "
            f"over the crank angle from its top, at {c.rpm:g} rpm.",
        )

    def files(self, folder: Path, name: str) -> list[Path]:
        """``<name>_schemes.csv``: the comparison's rows (with ``compare``).

        Examples
        --------
        Without the comparison no file is written:

        >>> import tempfile
        >>> req = KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30)
        >>> s = KnifeSynthesis(_drive("br125", req))
        >>> s.files(tempfile.gettempdir(), "knife")
        []
        """
        if self.comparison is None:
            return []
        cols = [k for k, _, _ in KnifeComparison.COLUMNS]
        path = Path(folder) / f"{'_'.join(name.split())}_schemes.csv"
        with path.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(cols)
            for r in self.comparison.rows:
                w.writerow([r[k] for k in cols])
        return [path]


def _compare_value(key: str, value: Any) -> float:
    """A comparison key's number, checked before it keys the cache."""
    if key == "cut_force_n":
        return finite_number(key, value, "[N]", low=0.0)
    units = {
        "compare_rpm": "[rpm]",
        "compare_max_acceleration_m_per_s2": "[m/s²]",
        "holder_kg": "[kg]",
        "link_kg_per_m": "[kg/m]",
    }
    return positive(key, value, units[key])


def from_table(table: Mapping[str, Any], where: str) -> KnifeSynthesis:
    """The knife drive of a ``synthesize`` table (the synthesizer registered for
    the schemes of :data:`~cyclomech.synthesis.SCHEMES`).

    Parameters
    ----------
    table : mapping
        The table: ``scheme``, ``stroke_m``, ``cut_deg`` and the optional keys of
        :data:`SYNTHESIZE_KEYS`.
    where : str
        The place messages name.

    Returns
    -------
    KnifeSynthesis
        The drive and, with ``compare = true``, the comparison.

    Raises
    ------
    InputError
        For an unknown key, a malformed value or a requirement no candidate meets
        (naming ``where``).

    Examples
    --------
    >>> from cyclomech.synthesis._knife_file import from_table
    >>> rec = from_table({"scheme": "br125", "stroke_m": 0.15, "cut_deg": 175.0,
    ...                   "popsize": 8, "maxiter": 30}, "<doc>")
    >>> rec.linkage.output
    'E'
    """
    _toml.check_keys(table, set(SYNTHESIZE_KEYS), None, where)
    _toml.require(table, ("scheme", "stroke_m", "cut_deg"), where)
    try:
        scheme = table["scheme"]
        if scheme not in SCHEMES:
            raise InputError(f"scheme = {scheme!r}; the schemes are {', '.join(SCHEMES)}")
        kw = {f: table[k] for k, f in _REQ_KEYS.items() if k in table}
        if "envelope" in kw and isinstance(kw["envelope"], list):
            kw["envelope"] = tuple(kw["envelope"])
        req = KnifeRequirement(**kw)
        _keyrules.check(table, (), where)  # a stroke in mm given as m, …
        compare = flag("compare", table.get("compare", False))
        ckw = tuple(
            sorted((f, _compare_value(k, table[k])) for k, f in _COMPARE_KEYS.items() if k in table)
        )
        if ckw and not compare:
            raise InputError(
                f"{', '.join(k for k in _COMPARE_KEYS if k in table)} set the comparison's "
                "speed and masses: they need compare = true"
            )
        if not compare:
            return KnifeSynthesis(_drive(scheme, req))
        try:
            # The comparison's drive of this scheme is this one (knife_drive's cache):
            # the other schemes are synthesised when the comparison is first read.
            drive = _drive(scheme, req)
        except InputError:
            # The comparison's messages, as when it ran first: its own when no
            # scheme meets the requirement, else this scheme's.
            c = _compare(req, ckw)
            raise InputError(c.failed[scheme]) from None
        return KnifeSynthesis._compared_later(drive, req, ckw)
    except InputError as e:
        raise InputError(f"{where}: {e}") from None


for _scheme in SCHEMES:
    register_synthesizer(_scheme, from_table)
