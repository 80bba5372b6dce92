"""The whole machine: `_model` part of :mod:`cyclomech.machine` (its door)."""

from __future__ import annotations

import copy
import difflib
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from .. import _toml
from .._arrays import SPEED_CAP_RPM, count, finite_number, real, speeds_rpm, threads_arg
from .._errors import CyclomechWarning, InfeasibleError, InputError
from .._kind import Array, Bound, BoundLaw, Mechanism, Proportional, TableContext
from .._units import DEG_PER_S_PER_RPM
from ..cyclogram import (
    SPEED_FLOOR_RPM,
    BoundsAt,
    Cyclogram,
    Optimum,
    SpeedLimit,
    SpeedNetwork,
)
from ._kinds import KINDS

__all__ = [
    "SCHEMA",
    "Machine",
    "SpeedSweep",
    "check_parameter",
    "speed_limits",
    "speed_sweeps",
]

#: Version of the layout of ``results.json`` and of sweep files.
SCHEMA = "cyclomech.machine/1"

_MACHINE_KEYS = {
    "name",
    "speed_rpm",
    "speed_points",
    "nominal_rpm",
    "angle_points",
    "speed_fluctuation",
    "flatten_torque",
}


#: The main shaft's coefficient of speed fluctuation δ when the file gives none
#: (``[machine] speed_fluctuation``): 1/20, a common value for machines with a
#: flywheel on the main shaft.
SPEED_FLUCTUATION = 0.05


# --------------------------------------------------------------------- results
@dataclass(frozen=True)
class SpeedSweep:
    """The machine's key figures at each speed ``rpm`` (arrays of that shape).

    With ``linear=True`` (:meth:`Machine.speed_sweep`), the bounds are the seed's
    linearised forms. Built by :meth:`Machine.speed_sweep` and
    :func:`speed_sweeps`; each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    rpm : ndarray of float, shape (S,)
        The speeds [rpm].
    fits : ndarray of bool, shape (S,)
        The cyclogram fits in the cycle with every mechanism's bound.
    limiting_deg : ndarray of float, shape (S,)
        The limiting operation's optimal angle [deg] (NaN where it does not fit).
    limiting_s : ndarray of float, shape (S,)
        The time it gets [s].
    productivity : ndarray of float, shape (S,)
        Machine cycles per minute where it fits, else 0 [1/min].
    binding : ndarray of object, shape (S,)
        The bounds and constraints on the chain that sets the optimum
        (joined by ``"; "``).
    min_phase_deg : dict of str to ndarray
        Each bound's smallest angle [deg], by the bound's name (a stop's is its
        mechanism's name).
    columns : dict of str to ndarray, optional
        What the mechanism kinds add
        (the kinds' ``sweep_columns``; ``max_rebound_m``, the
        largest first rebound of the stops [m] with each stop's arc at its angle in
        the optimum, NaN without stops); default an empty dict.

    Examples
    --------
    >>> import cyclomech as cm
    >>> s = cm.Machine.example().speed_sweep([300.0, 900.0])
    >>> s.productivity.tolist(), {k: v.round(2).tolist() for k, v in s.min_phase_deg.items()}
    ([300.0, 0.0], {'lifter': [30.03, 90.09]})
    """

    rpm: Array
    fits: npt.NDArray[np.bool_]
    limiting_deg: Array
    limiting_s: Array
    productivity: Array
    binding: npt.NDArray[np.object_]
    min_phase_deg: dict[str, Array]
    columns: dict[str, Array] = field(default_factory=dict)

    @property
    def max_rebound_m(self) -> Array:
        """The stops' column ``max_rebound_m`` [m] (NaN without stops).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.Machine.example().speed_sweep([300.0, 900.0]).max_rebound_m
        >>> (r * 1e6).round(6).tolist()   # [µm]: the bound a_max = 100 µm binds at 300 rpm
        [100.0, nan]
        """
        return self.columns["max_rebound_m"]


# --------------------------------------------------------------------- the machine
class Machine:
    """A machine: its mechanisms and its cyclogram, over a speed range.

    Read one with :meth:`from_toml` (the layout is in :mod:`cyclomech.machine`);
    :meth:`speed_sweep` gives the key figures at many speeds in one pass,
    :meth:`speed_limit` the highest speed at which it works, :meth:`optimize` the
    LP optimum of its cyclogram with the mechanisms' bounds at one speed. The
    mechanisms are instances of the kinds in :data:`KINDS`. Each parameter is kept
    as the attribute of the same name (validated: the speed range as a tuple of
    floats, the mechanisms as a dict).

    Parameters
    ----------
    name : str
        The machine's name.
    cyclogram : Cyclogram
        Its cyclogram.
    mechanisms : Mapping of str to Mechanism
        Its mechanisms by name.
    speed_range_rpm : tuple of (float, float)
        The speed range of the study (from, to) [rpm], 0 < from < to ≤ 1e6.
    speed_points : int, default 61
        Speeds in the report's sweep (≥ 2).
    nominal_rpm : float, optional
        The speed of the optimised cyclogram [rpm]; default None (the top of the
        range, or the speed limit if that is lower).
    angle_points : int, default 361
        Crank angles per turn for mechanisms (≥ 9).
    speed_fluctuation : float, default 0.05
        The main shaft's coefficient of speed fluctuation δ = (ω_max − ω_min)/ω,
        0 < δ < 1, for its flywheel.
    flatten_torque : bool, default False
        Move the main shaft's parts within the cyclogram's slack to its lowest peak
        torque.
    source : str, default "<machine>"
        The file's name, in messages.
    data : Mapping of str to Any, optional
        The parsed file (needed by :meth:`with_values` and sweeps); default None.

    Raises
    ------
    InputError
        If ``cyclogram`` is not a :class:`~cyclomech.cyclogram.Cyclogram`, the speed range,
        ``nominal_rpm``, a count or ``speed_fluctuation`` is out of range, or
        ``flatten_torque`` is not a bool.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> sorted(m.mechanisms), m.speed_range_rpm
    (['lifter'], (200.0, 500.0))
    """

    def __init__(
        self,
        name: str,
        cyclogram: Cyclogram,
        mechanisms: Mapping[str, Mechanism],
        *,
        speed_range_rpm: tuple[float, float],
        speed_points: int = 61,
        nominal_rpm: float | None = None,
        angle_points: int = 361,
        speed_fluctuation: float = SPEED_FLUCTUATION,
        flatten_torque: bool = False,
        source: str = "<machine>",
        data: Mapping[str, Any] | None = None,
    ) -> None:
        if not isinstance(cyclogram, Cyclogram):
            raise InputError(f"cyclogram must be a cyclomech.Cyclogram; got {cyclogram!r}")
        rng = speeds_rpm("speed_range_rpm", speed_range_rpm)
        if rng.size != 2 or not rng[0] < rng[1]:
            raise InputError(
                f"speed_range_rpm = {speed_range_rpm!r} must be (from, to) in rpm with "
                f"0 < from < to ≤ {SPEED_CAP_RPM:g}"
            )
        if nominal_rpm is not None:
            nominal_rpm = float(speeds_rpm("nominal_rpm", nominal_rpm)[0])
        self.name = str(name)
        self.cyclogram = cyclogram
        self.mechanisms = dict(mechanisms)
        self.speed_range_rpm = (float(rng[0]), float(rng[1]))
        self.speed_points = count("speed_points", speed_points, low=2, high=1_000_000)
        self.nominal_rpm = nominal_rpm
        self.angle_points = count("angle_points", angle_points, low=9, high=1_000_000)
        delta = finite_number("speed_fluctuation", speed_fluctuation, "(δ)", low=0.0)
        if not 0.0 < delta < 1.0:
            raise InputError(f"speed_fluctuation = {delta!r} must be the main shaft's δ, 0 < δ < 1")
        self.speed_fluctuation = delta
        if not isinstance(flatten_torque, bool | np.bool_):
            raise InputError(
                f"flatten_torque = {flatten_torque!r} must be True or False (move the main "
                "shaft's parts within the cyclogram's slack to its lowest peak torque)"
            )
        self.flatten_torque = bool(flatten_torque)
        self.source = source
        self.data = data
        self._bounded = _bounded(self.mechanisms)
        self._network = SpeedNetwork(cyclogram, [(b.arc, b.label) for b in self.bounds()])
        self._laws: dict[bool, list[BoundLaw]] = {}

    def __repr__(self) -> str:
        kinds = ", ".join(f"{k}: {type(v).__name__}" for k, v in self.mechanisms.items())
        return f"Machine({self.name!r}, {{{kinds}}}, speed {self.speed_range_rpm} rpm)"

    # ----------------------------------------------------------------- reading
    @classmethod
    def from_toml(cls, path: str | Path) -> Machine:
        """Read a machine file; every error names the file, the table and the key.

        Parameters
        ----------
        path : str or Path
            The machine file (TOML, the layout of :mod:`cyclomech.machine`).

        Returns
        -------
        Machine
            The machine.

        Raises
        ------
        InputError
            If the file cannot be read or a table or key is missing or invalid.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.from_toml("examples/stb_loom.toml").name
        'STB loom, group 1 (illustrative)'
        """
        data, source = _toml.load(path)
        return cls.from_dict(data, source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], source: str = "<dict>") -> Machine:
        """A machine from the parsed layout of :meth:`from_toml`.

        Parameters
        ----------
        data : Mapping of str to Any
            The parsed file: ``machine``, ``mechanism``, ``cyclogram``, ``operation``
            and ``constraint``.
        source : str, default "<dict>"
            Its name in messages.

        Returns
        -------
        Machine
            The machine (holding a deep copy of ``data``).

        Raises
        ------
        InputError
            If a table or key is missing or invalid (or the layout is another
            command's file).

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.example()
        >>> cm.Machine.from_dict(m.data).speed_points
        61
        """
        if isinstance(data, Mapping) and "machine" not in data:
            other = _other_command(data)
            if other:
                raise InputError(
                    f"{source}: a machine file needs a [machine] table; this looks like "
                    f"{other[0]}: run it with `cyclomech {other[1]}`"
                )
        _toml.check_keys(
            data,
            {"machine", "mechanism", "cyclogram", "operation", "constraint"},
            source,
            "top level",
        )
        if "machine" not in data:
            raise InputError(f"{source}: missing table [machine] (its name and speed_rpm)")
        head = data["machine"]
        _toml.check_keys(head, _MACHINE_KEYS, source, "[machine]")
        name = head.get("name", Path(source).stem)
        if not isinstance(name, str):
            raise InputError(f"{source}: [machine]: name = {name!r} must be a string")
        rng = head.get("speed_rpm")
        if not (
            isinstance(rng, list)
            and len(rng) == 2
            and all(_toml.is_number(v) and math.isfinite(v) for v in rng)
            and 0 < rng[0] < rng[1] <= SPEED_CAP_RPM
        ):
            raise InputError(
                f"{source}: [machine]: speed_rpm = {rng!r} must be [from, to] in rpm with "
                f"0 < from < to ≤ {SPEED_CAP_RPM:g}"
            )
        speed_points = _toml.whole(head, "speed_points", 61, 2, f"{source}: [machine]")
        angle_points = _toml.whole(head, "angle_points", 361, 9, f"{source}: [machine]")
        nominal = head.get("nominal_rpm")
        if nominal is not None and not (_toml.is_number(nominal) and 0 < nominal <= SPEED_CAP_RPM):
            raise InputError(
                f"{source}: [machine]: nominal_rpm = {nominal!r} must be a speed in rpm, "
                f"0 < nominal_rpm ≤ {SPEED_CAP_RPM:g}"
            )
        delta = head.get("speed_fluctuation", SPEED_FLUCTUATION)
        if not (_toml.is_number(delta) and 0 < delta < 1):
            raise InputError(
                f"{source}: [machine]: speed_fluctuation = {delta!r} must be the coefficient "
                "of speed fluctuation δ = (ω_max − ω_min)/ω of the main shaft, 0 < δ < 1"
            )
        flatten = head.get("flatten_torque", False)
        if not isinstance(flatten, bool):
            raise InputError(
                f"{source}: [machine]: flatten_torque = {flatten!r} must be true or false "
                "(a TOML boolean, unquoted): whether to move the main shaft's parts within "
                "the cyclogram's slack to its lowest peak torque"
            )
        if "cyclogram" not in data or "operation" not in data:
            raise InputError(
                f"{source}: a machine needs its cyclogram: a [cyclogram] table and "
                "[[operation]] tables (see cyclomech.Cyclogram.from_toml)"
            )
        if isinstance(data["cyclogram"], Mapping) and "speed_rpm" in data["cyclogram"]:
            raise InputError(
                f"{source}: [cyclogram]: speed_rpm is set by the machine; give the speed "
                "range in [machine] speed_rpm and the report's speed in [machine] nominal_rpm"
            )
        if isinstance(data["cyclogram"], Mapping) and "limiting" not in data["cyclogram"]:
            raise InputError(
                f"{source}: [cyclogram]: missing key 'limiting': the operation that gets what "
                'the others leave of the cycle, e.g. limiting = ["10.1", "10.2"]'
            )
        cg = Cyclogram.from_dict(
            {k: data[k] for k in ("cyclogram", "operation", "constraint") if k in data}, source
        )
        mechs: dict[str, Mechanism] = {}
        table = data.get("mechanism", {})
        if not isinstance(table, Mapping):
            raise InputError(f"{source}: [mechanism] must be a table of [mechanism.<name>] tables")
        ctx = TableContext(cg, source, angle_points, table)
        for key, spec in table.items():
            mechs[key] = _mechanism(key, spec, ctx)
        _near_misses(cg, mechs, source)
        return cls(
            name,
            cg,
            mechs,
            speed_range_rpm=(float(rng[0]), float(rng[1])),
            speed_points=speed_points,
            nominal_rpm=None if nominal is None else float(nominal),
            angle_points=angle_points,
            speed_fluctuation=float(delta),
            flatten_torque=flatten,
            source=source,
            data=copy.deepcopy(dict(data)),
        )

    @classmethod
    def example(cls) -> Machine:
        """A small machine for examples.

        The STB lifter's stop on the arc (3, 7) of a four-operation group with a
        time-bound weft insertion.

        Returns
        -------
        Machine
            The machine ``"example"``, speed range 200–500 rpm.

        Examples
        --------
        >>> import cyclomech as cm
        >>> len(cm.Machine.example().cyclogram.operations)
        4
        """
        lifter = {
            "kind": "cam_stop",
            "law": "modified_sine",
            "stroke": 9.4e-3,
            "preload": 0.25e-3,
            "lever_length": 0.1,
            "J_A": 7.4e-5,
            "a": 0.05,
            "b": 0.1,
            "E": 2.1e11,
            "J_x": 6.14e-11,
            "restitution": 5.0 / 9.0,
            "zeta": 0.05,
            "arc": ["3", "7"],
            "a_max": 1e-4,
        }
        ops = [
            {"from": "1", "to": "3", "min_angle_deg": 45.0, "mechanism": "lifter"},
            {"from": "3", "to": "7", "min_angle_deg": 20.0, "mechanism": "lifter"},
            {"from": "7", "to": "10.1", "min_angle_deg": 20.0, "mechanism": "lifter"},
            {
                "from": "10.1",
                "to": "10.2",
                "min_angle_deg": 120.0,
                "min_duration_s": 0.1,
                "name": "weft insertion",
            },
        ]
        return cls.from_dict(
            {
                "machine": {"name": "example", "speed_rpm": [200.0, 500.0]},
                "mechanism": {"lifter": lifter},
                "cyclogram": {"name": "example", "limiting": ["10.1", "10.2"]},
                "operation": ops,
            },
            "<example>",
        )

    def with_values(self, values: Mapping[str, Any]) -> Machine:
        """A copy with mechanism or machine keys replaced.

        The result is validated like a file.

        Parameters
        ----------
        values : Mapping of str to Any
            The new values by ``<mechanism>.<key>`` (``{"lifter.preload": 2e-4}``) or
            ``machine.<key>``, in the file's units.

        Returns
        -------
        Machine
            The copy (sharing the cyclogram and its network where only mechanism
            tables changed and the bounds stay on the same operations).

        Raises
        ------
        InputError
            If the machine was not read from a file or a dict, a path names no table,
            or a new value is invalid.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.example().with_values({"lifter.preload": 3e-4})
        >>> m.mechanisms["lifter"].stop.preload
        0.0003
        """
        if self.data is None:
            raise InputError("with_values needs a machine read from a file or a dict")
        # A copy of the tables that change; the others are shared with this machine.
        data = dict(self.data)
        data["mechanism"] = dict(data.get("mechanism", {}))
        touched: set[str] = set()
        for path, value in values.items():
            head = path.split(".", 1)[0]
            if head not in touched:
                if head == "machine":
                    data["machine"] = copy.deepcopy(data.get("machine", {}))
                elif head in data["mechanism"]:
                    data["mechanism"][head] = copy.deepcopy(data["mechanism"][head])
            table, key = _split_key(path, data)
            table[key] = value.item() if isinstance(value, np.generic) else value
            touched.add(head)
        if "machine" in touched:
            return Machine.from_dict(data, self.source)
        # Only the named mechanisms' tables changed: validate and build those (as
        # from_dict would), and share the cyclogram and its network with this one.
        mechs = dict(self.mechanisms)
        ctx = TableContext(self.cyclogram, self.source, self.angle_points, data["mechanism"])
        for name in touched:
            mechs[name] = _mechanism(name, data["mechanism"][name], ctx)
        bounded = _bounded(mechs)
        if [b for m in bounded for b in m.bounds()] != self.bounds():
            return Machine.from_dict(data, self.source)  # the bounds are on other operations
        other = copy.copy(self)
        other.mechanisms, other.data, other._bounded, other._laws = mechs, data, bounded, {}
        return other

    # ----------------------------------------------------------------- results
    def speed_grid(self) -> Array:
        """The report's speeds [rpm]: ``speed_points`` over ``speed_rpm``.

        Returns
        -------
        ndarray of float, shape (speed_points,)
            The speeds [rpm], evenly spaced over the speed range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().speed_grid()[[0, -1]].tolist()
        [200.0, 500.0]
        """
        return np.linspace(*self.speed_range_rpm, self.speed_points)

    def bounds(self) -> list[Bound]:
        """The lower bounds the mechanisms put on cyclogram operations.

        Returns
        -------
        list of Bound
            The bounds, in the order of the mechanisms.

        Examples
        --------
        >>> import cyclomech as cm
        >>> [b.label for b in cm.Machine.example().bounds()]
        ['rebound[lifter]']
        """
        return [b for m in self._bounded for b in m.bounds()]

    def bound_laws(self, *, linear: bool = False, n_threads: int | None = None) -> list[BoundLaw]:
        """The law of each of :meth:`bounds`: its smallest angle [deg] at any speed.

        Worked out once per machine (and once for all the machines of a sweep,
        :func:`speed_sweeps`).

        Parameters
        ----------
        linear : bool, default False
            The seed's linearised forms.
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        list of BoundLaw
            One law per bound: the smallest angles [deg] at an array of speeds [rpm].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> [law] = cm.Machine.example().bound_laws()
        >>> np.round(law(np.array([300.0])), 2).tolist()
        [30.03]
        """
        if linear not in self._laws:
            self._laws[linear] = _laws([self], linear, threads_arg(n_threads))[0]
        return self._laws[linear]

    def bound_angles(
        self, rpm: npt.ArrayLike, *, linear: bool = False, n_threads: int | None = None
    ) -> dict[str, Array]:
        """Each bound's smallest angle [deg] at each speed, by the bound's name.

        Exact, or the seed's linearised form with ``linear=True``.

        Parameters
        ----------
        rpm : array_like of float
            The speeds [rpm].
        linear : bool, default False
            The seed's linearised forms.
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        dict of str to ndarray
            By the bound's name (:class:`~cyclomech._kind.Bound`), the smallest angle
            [deg] at each speed.

        Raises
        ------
        InputError
            If a speed is not in (0, 1e6].

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> t = cm.Machine.example().bound_angles([300.0])
        >>> {k: np.round(v, 2).tolist() for k, v in t.items()}
        {'lifter': [30.03]}
        """
        n = speeds_rpm("rpm", rpm)
        laws = self.bound_laws(linear=linear, n_threads=n_threads)
        return {b.name: law(n) for b, law in zip(self.bounds(), laws, strict=True)}

    def speed_sweep(
        self,
        rpm: npt.ArrayLike | None = None,
        *,
        linear: bool = False,
        n_threads: int | None = None,
    ) -> SpeedSweep:
        """The key figures at each speed.

        One search per stop for all speeds and one shortest-path call for all speeds
        (:func:`speed_sweeps` for one machine).

        Parameters
        ----------
        rpm : array_like of float, optional
            The speeds [rpm]; default None (:meth:`speed_grid`).
        linear : bool, default False
            The bounds in the seed's linearised forms.
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        SpeedSweep
            Whether it fits, the limiting operation's angle [deg] and time [s], the
            productivity [1/min], the binding chain and the bounds [deg] at each speed.

        Raises
        ------
        InputError
            If a speed is not in (0, 1e6].

        Examples
        --------
        >>> import cyclomech as cm
        >>> s = cm.Machine.example().speed_sweep([300.0, 900.0])
        >>> s.fits.tolist(), round(float(s.limiting_deg[0]), 3)
        ([True, False], 264.971)
        """
        n = self.speed_grid() if rpm is None else speeds_rpm("rpm", rpm)
        return speed_sweeps([self], n, linear=linear, n_threads=n_threads)[0]

    def fits(self, rpm: npt.ArrayLike, *, n_threads: int | None = None) -> npt.NDArray[np.bool_]:
        """Whether the cyclogram with the mechanisms' bounds fits at each speed.

        Parameters
        ----------
        rpm : array_like of float
            The speeds [rpm].
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        ndarray of bool
            One flag per speed.

        Raises
        ------
        InputError
            If a speed is not in (0, 1e6].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().fits([300.0, 900.0]).tolist()
        [True, False]
        """
        n = speeds_rpm("rpm", rpm)
        threads = threads_arg(n_threads)
        at = _bounds_at([self.bound_laws(n_threads=threads)])
        return self._network.fits(at, n[None, :], threads)[0]

    def cyclogram_speed_limit(self, *, n_threads: int | None = None, rtol: float = 1e-10) -> float:
        """The highest speed [rpm] at which the cyclogram with the mechanisms' bounds fits.

        Found to ``rtol`` by :func:`speed_limits`' search.

        Parameters
        ----------
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).
        rtol : float, default 1e-10
            The search's relative tolerance, in [1e-14, 0.5].

        Returns
        -------
        float
            The speed [rpm]: inf if it fits up to 1e6 rpm; 0 if it fits at no speed
            from 1e-6 rpm up.

        Raises
        ------
        InputError
            If ``rtol`` is not in [1e-14, 0.5].

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.Machine.example().cyclogram_speed_limit(), 3)
        421.37
        """
        rtol = _rtol(rtol)
        threads = threads_arg(n_threads)
        at = _bounds_at([self.bound_laws(n_threads=threads)])
        return float(self._network.speed_limits(at, 1, self._search_start(), threads, rtol)[0])

    def speed_limit(self, *, n_threads: int | None = None) -> SpeedLimit:
        """The machine's speed limit: the cyclogram's and every mechanism's.

        :func:`speed_limits` for one machine.

        Parameters
        ----------
        n_threads : int, optional
            Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

        Returns
        -------
        SpeedLimit
            The limit [rpm], what sets it (``by``: "cyclogram" or a mechanism's name)
            and why.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lim = cm.Machine.example().speed_limit()
        >>> round(lim.rpm, 3), lim.by
        (421.37, 'cyclogram')
        """
        return speed_limits([self], n_threads=n_threads)[0]

    def _search_start(self) -> float:
        """The first speed [rpm] the speed-limit search tries."""
        return max(self.speed_range_rpm[1], 1.0)

    def nominal_speed(self, limit: SpeedLimit | None = None) -> float:
        """The speed [rpm] of the report's optimised cyclogram.

        Parameters
        ----------
        limit : SpeedLimit, optional
            The machine's speed limit, if already known; default None (computed).

        Returns
        -------
        float
            ``nominal_rpm``, or the top of the speed range capped at the speed limit
            (the bottom of the range if it fits at no speed) [rpm].

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.Machine.example().nominal_speed(), 3)
        421.37
        """
        if self.nominal_rpm is not None:
            return self.nominal_rpm
        lim = self.speed_limit() if limit is None else limit
        return min(self.speed_range_rpm[1], lim.rpm) if lim.rpm > 0 else self.speed_range_rpm[0]

    def cyclogram_at(self, rpm: float, *, linear: bool = False) -> Cyclogram:
        """A copy of the cyclogram at ``rpm`` with each bound added as a constraint.

        Parameters
        ----------
        rpm : float
            The speed [rpm].
        linear : bool, default False
            The seed's linearised forms, where the mechanism has one (else exact).

        Returns
        -------
        Cyclogram
            The copy, its ``speed_rpm`` set, the bounds as constraints named by their
            labels.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Machine.example().cyclogram_at(300.0)
        >>> [c.name for c in cg.constraints]
        ['rebound[lifter]']
        """
        cg = copy.deepcopy(self.cyclogram)
        cg.speed_rpm = float(rpm)
        for m in self._bounded:
            for c in m.constraints(float(rpm), linear=linear):
                cg.add_constraint(dict(c.coeffs), c.sense, c.rhs, name=c.name)
        return cg

    def optimize(self, rpm: float) -> Optimum:
        """The LP optimum (HiGHS) of the cyclogram with the stops' exact bounds at ``rpm``.

        Parameters
        ----------
        rpm : float
            The speed [rpm].

        Returns
        -------
        Optimum
            The angles [deg], shadow prices and binding bounds.

        Raises
        ------
        InfeasibleError
            If the cyclogram with the bounds does not fit at ``rpm`` (naming the
            machine and the speed).

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.Machine.example().optimize(300.0).objective, 3)
        264.971
        """
        try:
            return self.cyclogram_at(rpm).optimize()
        except InfeasibleError as e:
            raise InfeasibleError(
                f"machine {self.name!r} at {rpm:g} rpm: {e}", e.conflict
            ) from None


# --------------------------------------------------------------------- many machines
def _bounded(mechanisms: Mapping[str, Mechanism]) -> list[Mechanism]:
    """The mechanisms that bound cyclogram operations, in order."""
    return [m for m in mechanisms.values() if m.bounds()]


def _networks(machines: Sequence[Machine]) -> dict[int, list[int]]:
    """Indices of the machines that share each cyclogram network (the variants of
    one file made by :meth:`Machine.with_values`), in order."""
    groups: dict[int, list[int]] = {}
    for i, m in enumerate(machines):
        groups.setdefault(id(m._network), []).append(i)
    return groups


def _laws(machines: Sequence[Machine], linear: bool, n_threads: int | None) -> list[list[BoundLaw]]:
    """Each machine's bound laws, (D, K): the machines share a network, so their
    bounded mechanisms match one to one; each kind works out the laws of all the
    designs' mechanisms in one batch (one search for all the stops)."""
    if not machines:
        return []
    out: list[list[BoundLaw]] = [[] for _ in machines]
    for j, first in enumerate(machines[0]._bounded):
        same = [m._bounded[j] for m in machines]
        for d, laws in enumerate(type(first).bound_laws(same, linear=linear, n_threads=n_threads)):
            out[d].extend(laws)
    return out


def _group_laws(
    machines: Sequence[Machine], linear: bool, n_threads: int | None
) -> list[list[BoundLaw]]:
    """The bound laws of machines that share a network: one machine's are kept on
    it (worked out once per machine); many are worked out in one batch."""
    if len(machines) == 1:
        return [machines[0].bound_laws(linear=linear, n_threads=n_threads)]
    return _laws(machines, linear, n_threads)


def _bounds_at(laws: Sequence[Sequence[BoundLaw]]) -> BoundsAt:
    """``bounds_at(designs, rpm)`` over the laws (D, K) of
    :meth:`SpeedNetwork.speed_limits`: bound k of design ``designs[i]`` at the
    speeds ``rpm[i]``; the speed-proportional laws of all the designs in one
    vectorised step."""
    K = len(laws[0]) if laws else 0
    prop = [all(isinstance(row[k], Proportional) for row in laws) for k in range(K)]
    slopes = [
        np.array([cast(Proportional, row[k]).per_rpm if prop[k] else 0.0 for row in laws])
        for k in range(K)
    ]

    def at(designs: npt.NDArray[np.int64], rpm: Array) -> list[Array]:
        m = rpm.shape[1]
        rows = rpm.reshape(-1)
        out = []
        for k in range(K):
            if prop[k]:
                out.append(Proportional.evaluate(rows, np.repeat(slopes[k][designs], m)))
            else:
                # Designs that share a law (a mechanism the variants did not change)
                # are one call over all their speeds.
                vals = np.empty(rows.size)
                groups: dict[int, list[int]] = {}
                for i, d in enumerate(designs):
                    groups.setdefault(id(laws[d][k]), []).append(i)
                for idx in groups.values():
                    law = laws[designs[idx[0]]][k]
                    got = np.asarray(law(rpm[idx].reshape(-1)), dtype=np.float64)
                    for j, i in enumerate(idx):
                        vals[i * m : (i + 1) * m] = got[j * m : (j + 1) * m]
                out.append(vals)
        return out

    return at


def speed_sweeps(
    machines: Sequence[Machine],
    rpm: npt.ArrayLike,
    *,
    linear: bool = False,
    n_threads: int | None = None,
) -> list[SpeedSweep]:
    """:meth:`Machine.speed_sweep` of many machines at the same speeds.

    Variants of one file (:meth:`Machine.with_values`) share their cyclogram: their
    bounds are worked out together and every design at every speed goes into one
    shortest-path call; each kind's sweep columns are one call for all the designs.

    Parameters
    ----------
    machines : sequence of Machine
        The machines.
    rpm : array_like of float
        The speeds [rpm].
    linear : bool, default False
        The bounds in the seed's linearised forms.
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of SpeedSweep
        One per machine, in order.

    Raises
    ------
    InputError
        If a speed is not in (0, 1e6].

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> a, b = cm.machine.speed_sweeps([m, m.with_values({"lifter.a_max": 2e-4})], [300.0])
    >>> round(float(a.limiting_deg[0]), 3), round(float(b.limiting_deg[0]), 3)
    (264.971, 275.0)
    """
    n = speeds_rpm("rpm", rpm)
    threads = threads_arg(n_threads)
    out: list[SpeedSweep | None] = [None] * len(machines)
    S = n.size
    columns = sorted({c for cls in KINDS.values() for c in cls.sweep_columns})
    for idx in _networks(machines).values():
        ms = [machines[i] for i in idx]
        net, D = ms[0]._network, len(ms)
        laws = _group_laws(ms, linear, threads)
        grid = np.tile(n, (D, 1))
        t_bound = _bounds_at(laws)(np.arange(D), grid)
        rows = grid.reshape(-1)
        value, fits, binding, mins = net.solve(rows, t_bound, threads)
        extra = {c: np.full(rows.shape, np.nan) for c in columns}
        k = 0
        for j, first in enumerate(ms[0]._bounded):
            nb = len(first.bounds())
            angles = [mins[:, net.bound_op[k + i]] for i in range(nb)]
            same = [m._bounded[j] for m in ms]
            got = type(first).sweep_values(same, grid, angles, fits, n_threads=threads)
            for c, v in got.items():
                extra[c] = np.fmax(extra.get(c, np.full(rows.shape, np.nan)), v)
            k += nb
        names = [b.name for b in ms[0].bounds()]
        for j, i in enumerate(idx):
            r = slice(j * S, (j + 1) * S)
            out[i] = SpeedSweep(
                rpm=n,
                fits=fits[r],
                limiting_deg=value[r],
                limiting_s=value[r] / (DEG_PER_S_PER_RPM * n),
                productivity=np.where(fits[r], n, 0.0),
                binding=binding[r],
                min_phase_deg={name: t[r] for name, t in zip(names, t_bound, strict=True)},
                columns={c: v[r] for c, v in extra.items()},
            )
    return out  # type: ignore[return-value]


def speed_limits(machines: Sequence[Machine], *, n_threads: int | None = None) -> list[SpeedLimit]:
    """:meth:`Machine.speed_limit` of many machines.

    The cyclogram limits of the variants of one file are searched together (one
    shortest-path call per step for all of them); a mechanism shared by variants is
    evaluated once.

    Parameters
    ----------
    machines : sequence of Machine
        The machines.
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of SpeedLimit
        One per machine, in order: the limit [rpm], what sets it and why.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> both = cm.machine.speed_limits([m, m.with_values({"lifter.a_max": 2e-4})])
    >>> [round(x.rpm, 2) for x in both]
    [421.37, 453.81]
    """
    threads = threads_arg(n_threads)
    out: list[SpeedLimit | None] = [None] * len(machines)
    own: dict[int, float] = {}  # a mechanism's own limit, by object
    for idx in _networks(machines).values():
        ms = [machines[i] for i in idx]
        net = ms[0]._network
        laws = _group_laws(ms, False, threads)
        at = _bounds_at(laws)
        cg = net.speed_limits(at, len(ms), ms[0]._search_start(), threads, 1e-10)
        ok = np.flatnonzero((cg > 0.0) & np.isfinite(cg))
        binding = np.full(len(ms), "", dtype=object)
        if ok.size:
            binding[ok] = net.solve(cg[ok], at(ok, cg[ok, None]), threads)[2]
        for j, (i, m) in enumerate(zip(idx, ms, strict=True)):
            mech, why = {}, {}
            for k, x in m.mechanisms.items():
                if id(x) not in own:
                    own[id(x)] = float(x.speed_limit_rpm())
                if math.isfinite(own[id(x)]):
                    mech[k] = own[id(x)]
                    why[k] = x.limit_reason()
            by, rpm = "cyclogram", float(cg[j])
            for k, v in mech.items():
                if v < rpm:
                    by, rpm = k, v
            chain = tuple(b for b in str(binding[j]).split("; ") if b)
            reason = why[by] if by != "cyclogram" else _cyclogram_reason(m, rpm, chain)
            out[i] = SpeedLimit(
                rpm,
                binding=chain,
                reason=reason,
                by=by,
                cyclogram_rpm=float(cg[j]),
                mechanisms_rpm=mech,
                mechanisms_reason=why,
            )
    return out  # type: ignore[return-value]


def _cyclogram_reason(m: Machine, rpm: float, chain: tuple[str, ...]) -> str:
    """Why the cyclogram limits machine ``m`` at ``rpm``, in words."""
    if math.isinf(rpm):
        return f"nothing limits the speed up to {SPEED_CAP_RPM:g} rpm"
    if rpm > 0:
        bounded = f"; bounded by {', '.join(chain)}" if chain else ""
        return "the cyclogram fills the cycle" + bounded
    # Fits at no speed: the operations' durations and the bounds vanish as the
    # speed falls, so what is left is the minimum angles and the constraints.
    try:
        m.cyclogram.max_speed_rpm()
    except InfeasibleError as e:
        text = str(e).replace(" at 0 rpm", "")
        return (
            "the minimum angles alone do not fit in the cycle at any speed (they do not "
            f"depend on the speed): {text}"
        )
    try:
        m.cyclogram_at(SPEED_FLOOR_RPM).optimize()
    except InfeasibleError as e:
        return f"the cyclogram's bounds and constraints conflict at any speed: {e}"
    return f"the cyclogram does not fit even at {SPEED_FLOOR_RPM:g} rpm"


# --------------------------------------------------------------------- parsing
def _near_misses(cg: Cyclogram, mechs: Mapping[str, Mechanism], source: str) -> None:
    """Warn when an operation's ``mechanism`` is not one of the machine's but nearly
    is (``"liftr"`` for ``"lifter"``: difflib ratio ≥ 0.75): probably a typo that
    would draw a Gantt row of its own. A name far from every mechanism is a
    mechanism the file does not model (a clamp, a back gauge), and stays quiet."""
    seen: set[str] = set()
    for op in cg.operations:
        name = op.mechanism
        if name is None or name in mechs or name in seen:
            continue
        seen.add(name)
        near = difflib.get_close_matches(name, list(mechs), n=1, cutoff=0.75)
        if near:
            warnings.warn(
                f"{source}: operation {op.title!r}: mechanism = {name!r} is not a mechanism "
                f"of the machine; did you mean {near[0]!r}? (it gets a Gantt row of its own)",
                CyclomechWarning,
                stacklevel=4,
            )


def _other_command(data: Mapping[str, Any]) -> tuple[str, str] | None:
    """What another command's file looks like, and that command: by its tables."""
    if "stop" in data:
        return "an impact file ([stop])", "impact"
    if "linkage" in data:
        return "a linkage file ([linkage])", "linkage"
    if "press" in data:
        return "a press file ([press])", "press"
    if "mechanism" not in data and ("cyclogram" in data or "operation" in data):
        return "a cyclogram file ([cyclogram], [[operation]])", "cyclogram"
    return None


def _rtol(value: Any) -> float:
    """A relative tolerance of a speed search: finite, in [1e-14, 0.5] (below, the
    64-speed refinement cannot shrink its bracket in float64; at 1 and above it
    would stop at once, at the search's floor)."""
    try:
        v = real(value)
    except (TypeError, ValueError):
        v = math.nan
    if not 1e-14 <= v <= 0.5:
        raise InputError(f"rtol = {value!r} must be a relative tolerance in [1e-14, 0.5]")
    return v


def _split_key(path: str, data: dict[str, Any]) -> tuple[dict[str, Any], str]:
    """The table and key a sweep parameter ``<mechanism>.<key>`` or
    ``machine.<key>`` names in the parsed file."""
    parts = path.split(".")
    mechs = data.get("mechanism", {})
    if len(parts) == 2 and parts[0] == "machine":
        table = data.setdefault("machine", {})
    elif len(parts) == 2 and parts[0] in mechs:
        table = mechs[parts[0]]
    else:
        raise InputError(
            f"parameter {path!r} must be <mechanism>.<key> or machine.<key>; the mechanisms "
            f"are {', '.join(sorted(mechs)) or '(none)'}"
        )
    return table, parts[1]


def check_parameter(machine: Machine, path: str) -> None:
    """Check that a sweep parameter names a key its table can take.

    What a sweep checks before it starts, whatever the values (a value that makes a
    design invalid is that design's problem, not the sweep's).

    Parameters
    ----------
    machine : Machine
        The machine (read from a file or a dict).
    path : str
        The parameter: ``<mechanism>.<key>`` or ``machine.<key>``.

    Raises
    ------
    InputError
        Unless ``path`` names a key its table can take (not a fixed key, nor one
        this table refuses), or if the machine has no parsed file.

    Examples
    --------
    >>> import cyclomech as cm
    >>> from cyclomech.machine import check_parameter
    >>> check_parameter(cm.Machine.example(), "lifter.preload")
    >>> check_parameter(cm.Machine.example(), "lifter.preloud")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: <example>: parameter 'lifter.preloud': [mechanism.lifter] has ...
    """
    if machine.data is None:
        raise InputError("a sweep needs a machine read from a file or a dict")
    _, key = _split_key(path, dict(machine.data))  # a copy: it may add a [machine] table
    head = path.split(".", 1)[0]
    if head == "machine":
        allowed, where = _MACHINE_KEYS - {"name", "speed_rpm"}, "[machine]"
    else:
        kind = type(machine.mechanisms[head])
        allowed, where = set(kind.keys - kind.fixed_keys), f"[mechanism.{head}]"
    if key not in allowed:
        raise InputError(
            f"{machine.source}: parameter {path!r}: {where} has no key {key!r} a sweep can "
            "set; valid keys are "
            f"{', '.join(sorted(allowed))}"
        )
    if head != "machine":
        # A key the kind takes in general that this table refuses (a stop's stroke
        # when it names its cam): refused before the sweep, not design by design.
        refuses = getattr(type(machine.mechanisms[head]), "sweep_refuses", None)
        why = refuses(machine.data["mechanism"][head]).get(key) if refuses else None
        if why:
            raise InputError(
                f"{machine.source}: parameter {path!r}: {where} cannot vary {key}: {why}"
            )


def _mechanism(key: str, spec: Any, ctx: TableContext) -> Mechanism:
    """The mechanism of the table ``[mechanism.<key>]``, by its kind's parser."""
    where = ctx.where(key)
    if not isinstance(spec, Mapping):
        raise InputError(f"{where} must be a table; got {spec!r}")
    kind = spec.get("kind")
    if kind not in KINDS:
        raise InputError(f"{where}: kind = {kind!r} must be one of {', '.join(KINDS)}")
    try:
        return KINDS[kind].from_table(key, spec, ctx)
    except (InputError, InfeasibleError) as e:
        # A mechanism that cannot work (a transition too long for its gap, say) is a
        # mistake in the file: an InputError naming the file and the table.
        msg = str(e)
        raise InputError(msg if msg.startswith(ctx.source) else f"{where}: {msg}") from None
