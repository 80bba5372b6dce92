"""The whole machine: `_model` part of :mod:`cyclomech.machine` (its door)."""

from __future__ import annotations

import copy
import difflib
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from .. import _toml
from .._arrays import (
    SPEED_CAP_RPM,
    count,
    finite_number,
    flag,
    instance,
    instances,
    speed_rtol,
    speeds_rpm,
    threads_arg,
)
from .._errors import InfeasibleError, InputError
from .._keydoc import KeyTable
from .._kind import Array, Bound, BoundLaw, Mechanism, TableContext
from ..cyclogram import (
    Cyclogram,
    Optimum,
    SpeedLimit,
    SpeedNetwork,
)
from ..dynamics import DRIVE_KEY_DOCS, BalanceRequest, Drive
from ._keys import KEY_DOCS
from ._kinds import KINDS
from ._many import SpeedSweep, _bounded, _bounds_at, _laws, speed_limits, speed_sweeps

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
    "unmodelled",
}


#: The main shaft's coefficient of speed fluctuation δ when the file gives none
#: (``[machine] speed_fluctuation``): 1/20, a common value for machines with a
#: flywheel on the main shaft.
SPEED_FLUCTUATION = 0.05


def _balance_rows(rows: Any, source: str) -> list[BalanceRequest]:
    """The ``[[balance]]`` rows, each checked."""
    if not isinstance(rows, list):
        raise InputError(f"{source}: balance must be [[balance]] rows (an array of tables)")
    return [BalanceRequest.from_row(row, source, i) for i, row in enumerate(rows)]


def _main_shaft_keys(head: Mapping[str, Any], source: str) -> tuple[float, bool]:
    """``[machine]``'s keys for the main shaft: its target coefficient of speed
    fluctuation δ and whether to flatten its torque, checked."""
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
    return float(delta), flatten


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
    drive : cyclomech.dynamics.Drive, optional
        The main shaft's motor and flywheel (``[drive]``); default None (the shaft
        turns at constant speed: no real speed, no simulated flywheel).
    balance : sequence of cyclomech.dynamics.BalanceRequest, default ()
        Linkages to balance by counterweights (``[[balance]]``), each naming one of
        ``mechanisms``.
    source : str, default "<machine>"
        The file's name, in messages.
    data : Mapping of str to Any, optional
        The parsed file (needed by :meth:`with_values` and sweeps); default None.

    Raises
    ------
    InputError
        If ``cyclogram`` is not a :class:`~cyclomech.cyclogram.Cyclogram`, the speed range,
        ``nominal_rpm``, a count or ``speed_fluctuation`` is out of range,
        ``flatten_torque`` is not a bool or ``drive`` not a
        :class:`~cyclomech.dynamics.Drive`.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.example()
    >>> sorted(m.mechanisms), m.speed_range_rpm
    (['lifter'], (200.0, 500.0))
    """

    # Its tables' keys, for the machine-file format reference (cyclomech._keydocs).
    key_docs: ClassVar[tuple[KeyTable, ...]] = KEY_DOCS + DRIVE_KEY_DOCS

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
        drive: Drive | None = None,
        balance: Sequence[BalanceRequest] = (),
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
        self.mechanisms = dict(instance("mechanisms", mechanisms, Mapping))
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
        if drive is not None and not isinstance(drive, Drive):
            raise InputError(f"drive must be a cyclomech.dynamics.Drive or None; got {drive!r}")
        self.drive = drive
        for name in () if drive is None or drive.elastic is None else drive.elastic.take_off:
            if name not in self.mechanisms:
                near = difflib.get_close_matches(name, self.mechanisms, 1)
                hint = f" (did you mean {near[0]!r}?)" if near else ""
                raise InputError(
                    f"{source}: [drive.shaft]: take_off names {name!r}, not a mechanism of the "
                    f"machine{hint}; its mechanisms: {', '.join(self.mechanisms)}"
                )
        self.balance = tuple(instances("balance", balance, BalanceRequest))
        for b in self.balance:
            if b.mechanism not in self.mechanisms:
                near = difflib.get_close_matches(b.mechanism, self.mechanisms, 1)
                hint = f" (did you mean {near[0]!r}?)" if near else ""
                raise InputError(
                    f"{source}: [[balance]]: mechanism = {b.mechanism!r} is not a mechanism "
                    f"of the machine{hint}; its mechanisms: {', '.join(self.mechanisms)}"
                )
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
        instance("source", source, (str, os.PathLike))
        if isinstance(data, Mapping) and "machine" not in data:
            other = _other_command(data)
            if other:
                raise InputError(
                    f"{source}: a machine file needs a [machine] table; this looks like "
                    f"{other[0]}: run it with `cyclomech {other[1]} {source}`"
                )
        _toml.check_keys(
            data,
            {"machine", "mechanism", "cyclogram", "operation", "constraint", "drive", "balance"},
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
        delta, flatten = _main_shaft_keys(head, source)
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
        _check_mechanism_names(cg, mechs, head.get("unmodelled", []), source)
        return cls(
            name,
            cg,
            mechs,
            speed_range_rpm=(float(rng[0]), float(rng[1])),
            speed_points=speed_points,
            nominal_rpm=None if nominal is None else float(nominal),
            angle_points=angle_points,
            speed_fluctuation=delta,
            flatten_torque=flatten,
            drive=None if "drive" not in data else Drive.from_table(data["drive"], source),
            balance=_balance_rows(data.get("balance", []), source),
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
            "stroke_m": 9.4e-3,
            "preload_m": 0.25e-3,
            "lever_length_m": 0.1,
            "J_A_kg_m2": 7.4e-5,
            "a_m": 0.05,
            "b_m": 0.1,
            "E_pa": 2.1e11,
            "J_x_m4": 6.14e-11,
            "restitution": 5.0 / 9.0,
            "zeta": 0.05,
            "arc": ["3", "7"],
            "a_max_m": 1e-4,
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
            The new values by ``<mechanism>.<key>`` (``{"lifter.preload_m": 2e-4}``),
            ``<mechanism>.<table>.<key>…`` (a number in a sub-table or a list of
            the mechanism's table: a sub-table's key, or a list's position from 1,
            as ``knife.lengths.3.length`` or ``knife.points.B.1``),
            ``machine.<key>``, ``operation.<k>.<key>`` (a number of the k-th
            ``[[operation]]``, from 1: ``min_angle_deg``, ``max_angle_deg``,
            ``min_duration_s``) or ``drive.shaft.<key>…`` / ``drive.link.<name>.<key>``
            (a number of the ``[drive]`` table's elastic shaft and links:
            ``drive.link.knife.max_error_m``), in the file's units.

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
        >>> m = cm.Machine.example().with_values({"lifter.preload_m": 3e-4})
        >>> m.mechanisms["lifter"].stop.preload
        0.0003
        """
        if self.data is None:
            raise InputError("with_values needs a machine read from a file or a dict")
        # A copy of the tables that change; the others are shared with this machine.
        data = dict(self.data)
        data["mechanism"] = dict(data.get("mechanism", {}))
        touched: set[str] = set()
        for path, value in instance("values", values, Mapping).items():
            head = _head(path, data)
            if head not in touched:
                if head in ("machine", "operation"):
                    data[head] = copy.deepcopy(data.get(head, {} if head == "machine" else []))
                elif head == DRIVE:
                    data["drive"] = copy.deepcopy(data["drive"])
                elif head in data["mechanism"]:
                    data["mechanism"][head] = copy.deepcopy(data["mechanism"][head])
            table, key = _split_key(path, data)
            table[key] = value.item() if isinstance(value, np.generic) else value
            touched.add(head)
        if touched & {"machine", "operation", DRIVE}:
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

    def _with_mechanisms(self, mechanisms: Mapping[str, Mechanism]) -> Machine:
        """A copy with some mechanisms replaced by re-dimensioned ones whose bounds stay
        on the same operations under the same labels (the sizing loop,
        ``_resize.py``): the cyclogram and its network shared, the bound laws anew."""
        mechs = dict(self.mechanisms)
        mechs.update(mechanisms)
        bounded = _bounded(mechs)
        if [b for m in bounded for b in m.bounds()] != self.bounds():
            raise InputError(
                f"{self.source}: a resized mechanism ({', '.join(mechanisms)}) changed its "
                "bounds' operations"
            )
        other = copy.copy(self)
        other.mechanisms, other._bounded, other._laws = mechs, bounded, {}
        return other

    # ----------------------------------------------------------------- its parts
    @property
    def bounded_mechanisms(self) -> list[Mechanism]:
        """The mechanisms that bound cyclogram operations, in the machine's order.

        Their bounds, in this order, are :meth:`bounds` and the columns of
        :meth:`bound_laws`; the sweeps over many machines go through them kind by
        kind. Read-only: a new list each time (the machine keeps its own).

        Returns
        -------
        list of Mechanism
            The mechanisms with at least one bound (a stop; not a press, say).

        Examples
        --------
        >>> import cyclomech as cm
        >>> [m.name for m in cm.Machine.example().bounded_mechanisms]
        ['lifter']
        """
        return list(self._bounded)

    @property
    def speed_network(self) -> SpeedNetwork:
        """The cyclogram's LP with the mechanisms' bounds, solved at many speeds at once.

        Built once with the machine; the variants of :meth:`with_values` that keep
        the bounds on the same operations share it (the sweeps group machines by
        it and solve each group in one shortest-path call). The bounds' values are
        given at each speed [rpm] to its ``solve`` and ``speed_limits``.

        Returns
        -------
        SpeedNetwork
            The network: the operations' minimum angles [deg] and durations [s],
            the constraints and one extra lower bound per entry of :meth:`bounds`.

        Examples
        --------
        >>> import cyclomech as cm
        >>> m = cm.Machine.example()
        >>> other = m.with_values({"lifter.a_max_m": 2e-4})
        >>> len(m.speed_network.bound_op), other.speed_network is m.speed_network
        (1, True)
        """
        return self._network

    @property
    def search_start_rpm(self) -> float:
        """The first speed [rpm] the speed-limit search tries.

        The top of the speed range (at least 1 rpm): the search goes up from there
        while the cyclogram fits and down while it does not.

        Returns
        -------
        float
            The speed [rpm].

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.Machine.example().search_start_rpm
        500.0
        """
        return max(self.speed_range_rpm[1], 1.0)

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
        # Checked before the cache is asked: 1 == True would find the linear laws.
        linear = flag("linear", linear)
        threads = threads_arg(n_threads)
        if linear not in self._laws:
            self._laws[linear] = _laws([self], linear, threads)[0]
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
            By the bound's name (:class:`~cyclomech.machine.Bound`), the smallest angle
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
        rtol = speed_rtol(rtol)
        threads = threads_arg(n_threads)
        at = _bounds_at([self.bound_laws(n_threads=threads)])
        return float(self._network.speed_limits(at, 1, self.search_start_rpm, threads, rtol)[0])

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
            The copy, its ``speed_rpm`` set, each bound a constraint named by its label.

        Raises
        ------
        InfeasibleError
            If a bound cannot be met by any angle at ``rpm`` (it exceeds a turn).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cg = cm.Machine.example().cyclogram_at(300.0)
        >>> [c.name for c in cg.constraints]
        ['rebound[lifter]']
        """
        if np.ndim(rpm) != 0:
            raise InputError(f"rpm must be one speed [rpm]; got {rpm!r}")
        rpm = float(speeds_rpm("rpm", rpm)[0])  # the machine's rule: (0, 1e6] rpm
        cg = copy.deepcopy(self.cyclogram)
        cg.speed_rpm = rpm
        for m in self._bounded:
            for c in m.constraints(rpm, linear=linear):
                if not math.isfinite(c.rhs):  # no angle meets it: the design fails there
                    why = f"{c.name} cannot be met by any angle at {rpm:g} rpm"
                    raise InfeasibleError(f"{why} (its bound exceeds a full turn)", (c.name,))
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


# --------------------------------------------------------------------- parsing
def _check_mechanism_names(
    cg: Cyclogram, mechs: Mapping[str, Mechanism], unmodelled: Any, source: str
) -> None:
    """Every operation's ``mechanism`` is a ``[mechanism.<name>]`` table of the
    machine or is listed in ``[machine] unmodelled``; else :class:`InputError`.

    The rule is strict because a misspelt name is a silent change of design: the
    operation gets a Gantt row of its own and the file's author believes a
    mechanism's bounds and loads are on it when they are not (renaming
    ``[mechanism.lifter]`` to ``[mechanism.lifterx]`` in the loom once passed with a
    warning). A mechanism the file does not model (a clamp, a back gauge) is
    declared by name in ``[machine] unmodelled``; a name listed there must be used
    by an operation and must not also be a mechanism table. The message names the
    operation, the name, the nearest mechanism (difflib) and both ways out.
    """
    at = f"{source}: [machine]: unmodelled"
    if not (isinstance(unmodelled, list) and all(isinstance(u, str) and u for u in unmodelled)):
        raise InputError(
            f"{at} = {unmodelled!r} must be a list of mechanism names (non-empty strings): "
            'the mechanisms the operations name that the file does not model, e.g. ["clamp"]'
        )
    extra = set(unmodelled)
    both = sorted(extra & set(mechs))
    if both:
        raise InputError(
            f"{at} lists {both[0]!r}, which is also a [mechanism.{both[0]}] table: a "
            "mechanism is either modelled (its table) or listed as unmodelled, not both"
        )
    used = {op.mechanism for op in cg.operations if op.mechanism is not None}
    for u in unmodelled:
        if u not in used:
            near = difflib.get_close_matches(u, sorted(used - extra), n=1, cutoff=0.6)
            hint = f"; did you mean {near[0]!r}?" if near else ""
            raise InputError(
                f"{at} lists {u!r}, which no operation names as its mechanism{hint} "
                "(remove it, or correct the spelling)"
            )
    known = set(mechs) | extra
    for op in cg.operations:
        name = op.mechanism
        if name is None or name in known:
            continue
        near = difflib.get_close_matches(name, sorted(mechs), n=1, cutoff=0.6)
        hint = (
            f" Did you mean {near[0]!r}? (Or is the heading [mechanism.{near[0]}] misspelt?)"
            if near
            else ""
        )
        tables = ", ".join(repr(k) for k in mechs) or "none"
        raise InputError(
            f"{source}: operation {op.title!r}: mechanism = {name!r} is not a mechanism of "
            f"the machine (its [mechanism.<name>] tables: {tables}).{hint} A mechanism the "
            f"file does not model is listed in [machine] unmodelled = [{name!r}, …]."
        )


def _other_command(data: Mapping[str, Any]) -> tuple[str, str] | None:
    """What another command's file looks like, and that command: by its tables."""
    if "stop" in data:
        return "an impact file ([stop])", "impact"
    if "cam" in data:
        return "a cam file ([cam])", "cam"
    if "transfer" in data:
        return "a rotor transfer file ([transfer])", "transfer"
    if "linkage" in data:
        return "a linkage file ([linkage])", "linkage"
    if "press" in data:
        return "a press file ([press])", "press"
    if "mechanism" not in data and ("cyclogram" in data or "operation" in data):
        return "a cyclogram file ([cyclogram], [[operation]])", "cyclogram"
    return None


def _varied_tables(mechanism: Any) -> frozenset[str]:
    """The sub-tables and lists of a mechanism's table whose numbers a sweep or a
    sensitivity may vary by a path (``lengths.3.length``, ``points.B.1``): its
    kind's optional ``varied_tables`` (none by default).

    >>> import cyclomech as cm
    >>> cam = cm.Machine.from_toml("examples/stb_loom.toml").mechanisms["lifter cam"]
    >>> sorted(_varied_tables(cam))
    ['friction', 'segment']
    """
    return frozenset(getattr(type(mechanism), "varied_tables", frozenset()))


#: The keys of a ``[[operation]]`` a sweep or a sensitivity may vary (its numbers).
OPERATION_NUMBERS = frozenset({"min_angle_deg", "max_angle_deg", "min_duration_s"})


#: What :func:`_head` calls the ``[drive]`` table's elastic sub-tables.
DRIVE = "[drive]"


def _head(path: str, data: Mapping[str, Any]) -> str:
    """The table a parameter's path starts in: :data:`DRIVE` for
    ``drive.shaft.…`` and ``drive.link.…`` where the ``[drive]`` table has that
    sub-table (a mechanism may be named ``drive`` too: its keys are never ``shaft``
    or ``link``), else the path's first name (``machine``, ``operation`` or a
    mechanism).

    >>> _head("drive.link.knife.max_error_m", {"drive": {"link": {}}})
    '[drive]'
    >>> _head("drive.R_m", {"drive": {"link": {}}, "mechanism": {"drive": {}}})
    'drive'
    """
    parts = path.split(".")
    drive = data.get("drive")
    elastic = len(parts) > 2 and parts[1] in ("shaft", "link")
    if parts[0] == "drive" and elastic and isinstance(drive, dict) and parts[1] in drive:
        return DRIVE
    return parts[0]


def _split_key(path: str, data: dict[str, Any]) -> tuple[Any, Any]:
    """The container and key a parameter names in the parsed file: a table and a
    key for ``<mechanism>.<key>``, ``machine.<key>`` or ``operation.<k>.<key>`` (the
    k-th ``[[operation]]``, from 1); for a deeper ``<mechanism>.<key>.<sub>…`` the
    sub-table or list holding the number (:func:`_step`: a sub-table's key, or a
    list's position from 1, as ``lengths.3.length`` or ``points.B.1``)."""
    parts = path.split(".")
    mechs = data.get("mechanism", {})
    ops = data.get("operation", [])
    if len(parts) == 2 and parts[0] == "machine":
        table = data.setdefault("machine", {})
    elif len(parts) >= 2 and (parts[0] in mechs or _head(path, data) == DRIVE):
        node: Any = data["drive"] if _head(path, data) == DRIVE else mechs[parts[0]]
        key: Any = parts[1]
        for i, sub in enumerate(parts[2:], start=2):
            node, key = _step(path, ".".join(parts[:i]), node, key, sub)
        return node, key
    elif len(parts) == 3 and parts[0] == "operation":
        k = int(parts[1]) if parts[1].isdigit() else 0
        if not 1 <= k <= len(ops):
            raise InputError(
                f"parameter {path!r}: operation {parts[1]!r} must be the number of an "
                f"[[operation]] of the file, 1 to {len(ops)}"
            )
        return ops[k - 1], parts[2]
    else:
        raise InputError(
            f"parameter {path!r} must be <mechanism>.<key>, <mechanism>.<table>.<key> "
            "(a sub-table's key, or a list's position from 1), machine.<key> or "
            "operation.<number>.<key>; the mechanisms "
            f"are {', '.join(sorted(mechs)) or '(none)'}"
        )
    return table, parts[1]


def _step(path: str, where: str, node: Any, key: Any, sub: str) -> tuple[Any, Any]:
    """One step down a parameter's path: from ``node[key]`` (which must exist) to
    its entry ``sub`` — a sub-table's key, or a list's position from 1."""
    inner = node.get(key) if isinstance(node, dict) else node[key]
    if isinstance(inner, dict):
        if sub not in inner:
            raise InputError(
                f"parameter {path!r}: {where} has no key {sub!r}; its keys are "
                f"{', '.join(map(str, inner)) or '(none)'}"
            )
        return inner, sub
    if isinstance(inner, list):
        k = int(sub) if sub.isdigit() else 0
        if not 1 <= k <= len(inner):
            raise InputError(
                f"parameter {path!r}: {where} is a list of {len(inner)}: {sub!r} must be a "
                f"position in it, 1 to {len(inner)}"
            )
        return inner, k - 1
    what = (
        "not in the file" if inner is None else f"a {type(inner).__name__}, not a table or a list"
    )
    raise InputError(f"parameter {path!r}: {where} is {what}: nothing to step into")


def check_parameter(machine: Machine, path: str) -> None:
    """Check that a sweep parameter names a key its table can take.

    What a sweep checks before it starts, whatever the values (a value that makes a
    design invalid is that design's problem, not the sweep's).

    Parameters
    ----------
    machine : Machine
        The machine (read from a file or a dict).
    path : str
        The parameter: ``<mechanism>.<key>``, ``machine.<key>`` or
        ``operation.<k>.<key>`` (a number of the k-th ``[[operation]]``, from 1).

    Raises
    ------
    InputError
        Unless ``path`` names a key its table can take (not a fixed key, nor one
        this table refuses), or if the machine has no parsed file.

    Examples
    --------
    >>> import cyclomech as cm
    >>> from cyclomech.machine import check_parameter
    >>> check_parameter(cm.Machine.example(), "lifter.preload_m")
    >>> check_parameter(cm.Machine.example(), "lifter.preloud_m")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: <example>: parameter 'lifter.preloud_m': [mechanism.lifter] ...
    """
    instance("machine", machine, Machine)
    instance("path", path, str)
    if machine.data is None:
        raise InputError("a sweep needs a machine read from a file or a dict")
    parts = path.split(".")
    head = parts[0]
    if _head(path, machine.data) == DRIVE:
        raise InputError(
            f"{machine.source}: parameter {path!r}: a sweep does not vary the drive's keys "
            "(its speed limit is the cyclogram's and the mechanisms'); cyclomech run's "
            "sensitivities rank them"
        )
    table, key = _split_key(path, dict(machine.data))  # a copy: it may add a [machine] table
    if head not in ("machine", "operation") and len(parts) > 2:
        tables = _varied_tables(machine.mechanisms[head])
        if parts[1] not in tables:
            raise InputError(
                f"{machine.source}: parameter {path!r}: [mechanism.{head}] {parts[1]!r} is "
                "not a table whose numbers a sweep can set; those of this kind are "
                f"{', '.join(sorted(tables)) or '(none)'}"
            )
    value = table.get(key) if isinstance(table, dict) else table[key]
    if len(parts) > 2 and head != "operation":
        if isinstance(value, bool) or not isinstance(value, int | float | dict | list):
            raise InputError(f"{machine.source}: parameter {path!r} names {value!r}, not a number")
        _a_number(machine, path, value)
        return
    if head == "machine":
        allowed, where = _MACHINE_KEYS - {"name", "speed_rpm", "unmodelled"}, "[machine]"
    elif head == "operation":
        allowed, where = set(OPERATION_NUMBERS), f"[[operation]] #{path.split('.')[1]}"
    else:
        kind = type(machine.mechanisms[head])
        allowed, where = set(kind.keys - kind.fixed_keys), f"[mechanism.{head}]"
        if key in _varied_tables(machine.mechanisms[head]):
            _a_number(machine, path, value)  # a table whose numbers a path names
    if key not in allowed:
        raise InputError(
            f"{machine.source}: parameter {path!r}: {where} has no key {key!r} a sweep can "
            f"set{_toml.renamed_hint(key, allowed)}; valid keys are "
            f"{', '.join(sorted(allowed))}"
        )
    if head not in ("machine", "operation"):
        # A key the kind takes in general that this table refuses (a stop's stroke
        # when it names its cam): refused before the sweep, not design by design.
        refuses = getattr(type(machine.mechanisms[head]), "sweep_refuses", None)
        why = refuses(machine.data["mechanism"][head]).get(key) if refuses else None
        if why:
            raise InputError(
                f"{machine.source}: parameter {path!r}: {where} cannot vary {key}: {why}"
            )
    _a_number(machine, path, value)


def _a_number(machine: Machine, path: str, value: Any) -> None:
    """Refuse a parameter that names a table or a list: a sweep sets numbers."""
    if isinstance(value, dict | list):
        sub = next(iter(value), None) if isinstance(value, dict) else 1
        raise InputError(
            f"{machine.source}: parameter {path!r} names a "
            f"{'table' if isinstance(value, dict) else 'list'}, not a number: name one of "
            f"its numbers ({path}.{sub}…)"
        )


def _mechanism(key: str, spec: Any, ctx: TableContext) -> Mechanism:
    """The mechanism of the table ``[mechanism.<key>]``, by its kind's parser."""
    where = ctx.where(key)
    if not isinstance(spec, Mapping):
        raise InputError(f"{where} must be a table; got {spec!r}")
    kind = spec.get("kind")
    if not isinstance(kind, str) or kind not in KINDS:
        said = "the key kind is missing; it" if kind is None else f"kind = {kind!r}"
        raise InputError(f"{where}: {said} must be one of {', '.join(KINDS)}")
    try:
        return KINDS[kind].from_table(key, spec, ctx)
    except (InputError, InfeasibleError) as e:
        # A mechanism that cannot work (a transition too long for its gap, say) is a
        # mistake in the file: an InputError naming the file and the table.
        msg = str(e)
        raise InputError(msg if msg.startswith(ctx.source) else f"{where}: {msg}") from None


def with_mechanisms(machine: Machine, mechanisms: Mapping[str, Mechanism]) -> Machine:
    """``machine`` with some mechanisms replaced by re-dimensioned ones (the sizing
    loop of ``_resize.py``; Machine's privates stay in this module)."""
    return machine._with_mechanisms(mechanisms)
