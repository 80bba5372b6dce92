"""What the machine's report shows, computed once: :class:`MachineResult`, the
`_result` part of :mod:`cyclomech.machine` (its door).

:func:`~cyclomech.machine.analyze` (``_report``) fills it; the page
(``_page``), ``results.json``, the CSVs (``_report``) and the CLI only read it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._errors import InputError
from .._kind import MechanismResult
from .._notebook import figure_of, html_card, pandas, table_frame
from ..cyclogram import Optimum, SpeedLimit
from ._model import Machine, SpeedSweep
from ._resize import Resizing
from ._sensitivity import Sensitivity

if TYPE_CHECKING:
    from ..dynamics import MachineDynamics, MachineShaking, MachineTorsion
    from ..shaft import MainShaft

__all__ = ["MachineResult"]


@dataclass
class MachineResult:
    """Everything the report shows, computed once by :func:`analyze`.

    Speeds [rpm], angles [deg], SI otherwise: the report, ``results.json``, the
    CSVs and the CLI's summary only read it. Each parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    machine : Machine
        The machine.
    limit : SpeedLimit
        The speed limit.
    nominal_rpm : float
        The speed of ``optimum`` [rpm].
    optimum : Optimum or None
        The LP optimum with the mechanisms' exact bounds (None if it does not fit
        there, and ``problem`` says why).
    problem : str
        Why there is no optimum ("" when there is).
    sweep : SpeedSweep
        The key figures against speed with the exact bounds.
    sweep_linear : SpeedSweep
        The same with the seed's linearised bounds.
    minimums : ndarray of float, optional
        Each operation's smallest angle at the nominal speed [deg]: its own
        minimum angle or duration, or a mechanism's bound on it, whichever is
        larger; default None.
    minimum_by : list of str, optional
        The name of what sets each of ``minimums`` (``min[op]``, ``duration[op]``
        or the bound's label, as in the optimum's ``binding``); default an empty
        list.
    mechanisms : dict of str to MechanismResult, optional
        Each mechanism's results (:meth:`~cyclomech.machine.Mechanism.analyze`);
        default an empty dict.
    seconds : dict of str to float, optional
        The time of each step [s]; default an empty dict.
    shaft : MainShaft, optional
        The main shaft's torque and statistics, when a mechanism loads it; default
        None.
    dynamics : cyclomech.dynamics.MachineDynamics, optional
        The main shaft's real speed under the file's ``[drive]``, when it has one and
        a mechanism loads the shaft; default None.
    shaking : cyclomech.dynamics.MachineShaking, optional
        The shaking force and moment the moving parts put on the frame at the
        nominal speed, when a mechanism gives inertia forces at a phase; default
        None.
    torsion : cyclomech.dynamics.MachineTorsion, optional
        The working members' dynamic errors on the elastic main shaft and links of
        the file's ``[drive.shaft]``, when it has one; default None.
    resizing : Resizing, optional
        How the mechanisms that size themselves (a cam's ``synthesize`` table) were
        sized at the optimised timing, to a fixed point; default None (none does).
    sensitivities : list of Sensitivity, optional
        The speed limit's sensitivity to each numeric key of the mechanisms'
        tables, ranked (:func:`~cyclomech.machine.sensitivities`); default None
        (not asked for: ``analyze(..., sensitivities=True)``, ``cyclomech run``).

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
    >>> r.problem, r.minimums.round(3).tolist(), r.shaft is None
    ('', [45.0, 42.178, 20.0, 252.822], True)
    >>> r.minimum_by[1]      # the lifter's rebound bound exceeds (3, 7)'s own 20°
    'rebound[lifter]'
    """

    machine: Machine
    limit: SpeedLimit
    nominal_rpm: float
    optimum: Optimum | None
    problem: str
    sweep: SpeedSweep
    sweep_linear: SpeedSweep
    minimums: np.ndarray | None = None
    minimum_by: list[str] = field(default_factory=list)
    mechanisms: dict[str, MechanismResult] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)
    shaft: MainShaft | None = None
    dynamics: MachineDynamics | None = None
    shaking: MachineShaking | None = None
    torsion: MachineTorsion | None = None
    resizing: Resizing | None = None
    sensitivities: list[Sensitivity] | None = None

    @property
    def failures(self) -> list[str]:
        """What fails at the nominal speed in a mechanism's own checks, by mechanism,
        and in the main shaft's drive.

        A kind whose results have ``failures()`` (a servo axis whose motor fails
        a check on the optimised timing) and the drive
        (:meth:`cyclomech.dynamics.MachineDynamics.failures`: a motor that cannot
        drive the machine, a real δ above the target) say what must not ship:
        ``cyclomech run`` exits 3 and the report shows it. Empty when nothing fails.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.machine.analyze(cm.Machine.example(), progress=False).failures
        []
        """
        out = []
        for k, res in self.mechanisms.items():
            own = getattr(res, "failures", None)
            out += [f"{k}: {text}" for text in (own() if own is not None else [])]
        if self.dynamics is not None:
            out += self.dynamics.failures()
        if self.torsion is not None:
            out += self.torsion.failures()
        if self.resizing is not None:
            out += self.resizing.failures()
        return out

    @property
    def fails(self) -> list[str]:
        """Everything that makes the design fail as it stands, one text each: the
        machine works at no speed; the cyclogram does not fit at the nominal speed;
        the nominal speed is above a mechanism's own limit
        (:attr:`above_speed_limit`); a mechanism's or the drive's own check fails
        there (:attr:`failures`). ``cyclomech run`` exits 3 exactly when it is not
        empty, and ``results.json`` carries it as ``fails``. Empty when the design
        works.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
        >>> r.fails
        []
        >>> data = cm.Machine.example().data
        >>> data["machine"]["nominal_rpm"] = 500.0
        >>> fast = cm.machine.analyze(cm.Machine.from_dict(data), progress=False)
        >>> fast.fails
        ['the cyclogram does not fit at the nominal 500 rpm (speed limit 421.37 rpm)']
        """
        if self.limit.rpm == 0:
            return [f"the machine works at no speed: {self.limit.reason}"]
        out = []
        if self.optimum is None:
            out.append(
                f"the cyclogram does not fit at the nominal {self.nominal_rpm:g} rpm "
                f"(speed limit {self.limit.rpm:.2f} rpm)"
            )
        if self.above_speed_limit:
            out.append(self.above_speed_limit)
        return out + [f"at {self.nominal_rpm:g} rpm {text}" for text in self.failures]

    @property
    def above_speed_limit(self) -> str:
        """Why the nominal speed is above a mechanism's own speed limit ("" if it is
        not). The cyclogram may still fit there (its optimum is then computed), but
        that mechanism does not work: :func:`analyze` warns, ``cyclomech run`` exits 3.
        (Above the cyclogram's own limit there is no optimum: see ``problem``.)

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.machine.analyze(cm.Machine.example(), progress=False).above_speed_limit
        ''
        """
        over = {k: v for k, v in self.limit.mechanisms_rpm.items() if self.nominal_rpm > v}
        if not over:
            return ""
        k = min(over, key=over.__getitem__)
        return (
            f"the nominal speed {self.nominal_rpm:g} rpm is above the speed limit of "
            f"mechanism {k!r}, {over[k]:.2f} rpm ({self.limit.mechanisms_reason.get(k, '')})"
        )

    def scenes(self, frames: int = 120) -> tuple[Any, dict[str, Any]]:
        """Every mechanism that can be drawn, moving over one cycle: the data of the
        report's animation and of :func:`~cyclomech.plot.animate_machine`.

        Frame k of ``frames`` is at the main shaft's angle k·cycle/``frames``; each
        mechanism is at its own phase there (a linkage's crank, a cam's angle, a
        press's carrier, a servo axis's master angle, from the optimum's timing),
        every point where its solver puts it. A kind draws itself by a ``scene``
        method on its result; a cam stop's lever is drawn over the operation that
        brings it to its stop (its model covers that approach only), and a
        mechanism timed by the optimum is left out when the machine has none.

        Parameters
        ----------
        frames : int, default 120
            Frames over the cycle (≥ 2).

        Returns
        -------
        cycle_deg : ndarray of float
            The main shaft's angle at each frame [deg].
        scenes : dict of str to Scene
            Each drawable mechanism's :class:`~cyclomech.machine.Scene` by name
            (lengths in m).

        Raises
        ------
        InputError
            If ``frames`` is not an integer ≥ 2.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> theta, scenes = r.scenes(frames=8)
        >>> theta.tolist(), list(scenes)
        ([0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0], ['knife'])
        """
        from ._animation import machine_scenes  # here: it reads this module's results

        return machine_scenes(self, frames)

    def to_pandas(self, table: str = "operations.csv") -> Any:
        """One of the report's CSV tables as a pandas DataFrame (pandas needed).

        The same header and rows as the file :func:`~cyclomech.machine.write_report`
        writes: ``"operations.csv"`` (each operation at the optimum, indexed by its
        title), ``"speed_sweep.csv"`` (the key figures at each speed [rpm], indexed
        by speed), and the tables over the cycle at the nominal speed the machine
        has (``"main_shaft.csv"``, ``"main_shaft_speed.csv"``,
        ``"<mechanism>_forces.csv"``: indexed by the angle [deg]).

        Parameters
        ----------
        table : str, default "operations.csv"
            The table's file name.

        Returns
        -------
        pandas.DataFrame
            The table's rows, indexed by its first column (an operation's title,
            a speed [rpm], an angle [deg]).

        Raises
        ------
        InputError
            If the machine has no such table (the message lists those it has).
        ImportError
            If pandas is not installed.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
        >>> r.to_pandas()["angle_deg"].round(3).tolist()
        [45.0, 42.178, 20.0, 252.822]
        >>> r.to_pandas("speed_sweep.csv").index.name
        'speed_rpm'
        """
        from ._report import tables  # here: _report imports this module

        pandas()  # before the work: no table computed for nothing
        have = tables(self)
        if not isinstance(table, str) or table not in have:
            raise InputError(f"table = {table!r} is not one of this machine's: {', '.join(have)}")
        header, rows = have[table]
        index = {"operations.csv": "operation", "speed_sweep.csv": "speed_rpm"}.get(
            table, header[0]
        )
        return table_frame(header, rows, index=index)

    def _repr_html_(self) -> str:
        """The notebook's view: the speed limit, the optimum's key numbers, what
        fails, the operations at the optimum, and the cyclogram at the optimum."""
        from ._report import _operations_table  # here: _report imports this module

        lim = self.limit
        rows: list[tuple[str, Any]] = [
            ("speed limit [rpm]", lim.rpm),
            ("set by", lim.by + (f" ({lim.reason})" if lim.reason else "")),
            ("nominal speed [rpm]", self.nominal_rpm),
        ]
        o = self.optimum
        if o is not None:
            rows.append(("limiting operation's angle at the optimum [deg]", o.objective))
        else:
            rows.append(("optimum", f"none: {self.problem}"))
        if self.above_speed_limit:
            rows.append(("above a speed limit", self.above_speed_limit))
        rows.append(("fails", "; ".join(self.failures) or "nothing"))
        header, ops = _operations_table(self)  # only this table: not the sweep's too
        keep = [header.index(h) for h in ("operation", "minimum_deg", "angle_deg", "start_deg")]
        figure = None if o is None else figure_of(self)
        return html_card(
            self.machine.name,
            rows,
            figure,
            tables=[
                (
                    "Operations at the optimum",
                    [header[i] for i in keep],
                    [[r[i] for i in keep] for r in ops],
                )
            ],
        )
