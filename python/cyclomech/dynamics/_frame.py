"""What the whole machine puts on its frame at the nominal speed (issue 34 item 6,
the shaking's part): :func:`machine_shaking` sums each mechanism's shaking force
and moment at its phase in the optimised cyclogram (:func:`~cyclomech.dynamics.shaking`)
and :class:`MachineShaking` gives the report, ``results.json`` and the CLI what
they show: peak and RMS force and moment, each mechanism's share, what was left
out, and the force's hodograph.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from .. import _toml
from .._arrays import count, finite_number, instances, positive
from .._errors import InputError
from ..press import GearLeverPress
from ._balance import OBJECTIVES, PRESS_CARRIER, Balance, _press_balance, balance
from ._shaking import Shaking, shaking

__all__ = [
    "BALANCE_KEYS",
    "BalanceRequest",
    "MachineShaking",
    "machine_balances",
    "machine_shaking",
]


@dataclass(frozen=True)
class MachineShaking:
    """The machine's shaking force and moment on its frame at one speed.

    Built by :func:`machine_shaking`; each parameter is kept as the attribute of
    the same name.

    Parameters
    ----------
    shaking : Shaking
        The machine's (its ``parts`` each mechanism's, at its phase).
    rpm : float
        The main shaft's speed of the statistics [rpm].
    balances : dict of str to Balance, default {}
        The linkages balanced by the file's ``[[balance]]`` rows, by mechanism.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> s = r.shaking.stats()
    >>> round(s["peak_force_n"], 1), round(s["rms_force_n"], 1)
    (264.9, 176.1)
    """

    shaking: Shaking
    rpm: float
    balances: dict[str, Balance] = field(default_factory=dict)

    def stats(self) -> dict[str, float]:
        """Peak and RMS of the force [N] and moment [N·m] at ``rpm``
        (:meth:`Shaking.stats`).

        Returns
        -------
        dict of str to float

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> sorted(r.shaking.stats())[:2]
        ['peak_force_deg', 'peak_force_n']
        """
        return self.shaking.stats(self.rpm)

    def json(self) -> dict[str, Any]:
        """Its ``results.json`` group ``shaking`` (SI; angles in degrees).

        Returns
        -------
        dict of str to Any
            The speed, the statistics, each mechanism's statistics, what was left out
            and why, what was assumed (``assumed``, only when anything was), and the
            force (x, y) and moment over the cycle (every 10th angle).

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> g = r.shaking.json()
        >>> g["rpm"], list(g["mechanisms"]), g["left_out"]
        (45.0, ['knife'], {})
        """
        s, n = self.shaking, self.rpm
        f = s.force(n)
        # What was assumed, when anything was (an oscillating follower's centre of mass).
        notes = {"assumed": dict(s.notes)} if s.notes else {}
        return {
            "rpm": n,
            "about_m": list(s.about_m),
            **self.stats(),
            "mechanisms": {k: p.stats(n) for k, p in s.parts.items()},
            "left_out": dict(s.skipped),
            **notes,
            "theta_deg": s.angles_deg[::10],
            "force_x_n": f[::10, 0],
            "force_y_n": f[::10, 1],
            "moment_nm": s.moment(n)[::10],
            "balance": {k: _balance_json(b) for k, b in self.balances.items()},
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Its report table.

        Returns
        -------
        header : list of str
            ``["quantity", "value"]``.
        rows : list of list
            The force's and moment's peak and RMS, each mechanism's RMS force, what
            was assumed, what was left out.

        Examples
        --------
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> r.shaking.table()[1][0][0]
        'shaking force at 45 rpm, peak [N] (at the cycle angle [deg])'
        """
        st, n = self.stats(), self.rpm
        # No force at all (a lever shaking by a couple only) has no angle of its peak.
        peak = (
            f"{st['peak_force_n']:.4g} (at {st['peak_force_deg']:.1f}°)"
            if st["peak_force_n"] > 0.0
            else "0: no shaking force (see what was assumed and left out below)"
        )
        rows: list[list[Any]] = [
            [f"shaking force at {n:g} rpm, peak [N] (at the cycle angle [deg])", peak],
            ["shaking force, RMS over the cycle [N]", st["rms_force_n"]],
            [
                f"shaking moment about {self.shaking.about_m}, peak / RMS [N·m]",
                f"{st['peak_moment_nm']:.4g} / {st['rms_moment_nm']:.4g}",
            ],
        ]
        rows += [
            [f"RMS shaking force of {k} [N]", p.stats(n)["rms_force_n"]]
            for k, p in self.shaking.parts.items()
        ]
        rows += [[f"assumed for {k}", why] for k, why in self.shaking.notes.items()]
        rows += [[f"left out: {k}", why] for k, why in self.shaking.skipped.items()]
        return ["quantity", "value"], rows

    def figure(self) -> Any:
        """The force's hodograph and the moment over the cycle
        (:func:`cyclomech.plot.plot_shaking`).

        Returns
        -------
        matplotlib.figure.Figure

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> len(r.shaking.figure().axes)
        2
        """
        from .plot import plot_shaking

        return plot_shaking(
            self.shaking, self.rpm, title=f"the machine's shaking force at {self.rpm:g} rpm"
        )

    def balance_figures(self) -> list[tuple[str, Any]]:
        """Each balanced linkage's hodograph and moment before and after, with its
        mechanism's name.

        Returns
        -------
        list of tuple of (str, matplotlib.figure.Figure)

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import cyclomech as cm
        >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
        ...                        progress=False)
        >>> [k for k, _ in r.shaking.balance_figures()]
        ['knife']
        """
        from .plot import plot_shaking

        return [
            (
                k,
                plot_shaking(
                    b,
                    self.rpm,
                    title=f"{k}: before and after balancing",
                    angle_name=f"crank angle of {k}",
                ),
            )
            for k, b in self.balances.items()
        ]


def _balance_json(b: Balance) -> dict[str, Any]:
    """A balance's ``results.json`` entry (the torque weight and the bound on m·r
    only when the row used them)."""
    used: dict[str, Any] = {}
    if b.torque_weight is not None:
        used["torque_weight"] = b.torque_weight
    if b.max_mass_radius_kg_m is not None:
        used["max_mass_radius_kg_m"] = b.max_mass_radius_kg_m
        used["at_bound"] = list(b.at_bound)
    return {
        "objective": b.objective,
        **used,
        "before": b.before,
        "after": b.after,
        "counterweights": [
            {
                "link": c.link,
                "radius_m": c.radius_m,
                "mass_radius_kg_m": c.mass_radius_kg_m,
                "angle_deg": c.angle_deg,
                "mass_kg": c.mass_kg,
            }
            for c in b.counterweights
        ],
    }


def machine_shaking(
    result: Any, rpm: Any = None, requests: Sequence[BalanceRequest] = ()
) -> MachineShaking | None:
    """The machine's shaking force and moment on its frame, or None when no
    mechanism gives one (no linkage with masses, cam follower with its mass or
    inertia, or loaded press at a phase in the cyclogram).

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result.
    rpm : float, optional
        The speed of the statistics [rpm]; default the result's nominal speed.
    requests : sequence of BalanceRequest, default ()
        Linkages to balance (:func:`machine_balances`, at the nominal speed).

    Returns
    -------
    MachineShaking or None

    Raises
    ------
    InputError
        If ``rpm`` is not a speed > 0.
    TypeError
        If ``result`` is not a machine's result.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.example(), progress=False)
    >>> machine_shaking(r) is None       # a stop only: no inertia forces at a phase
    True
    """
    _a_result(result)
    n = float(result.nominal_rpm) if rpm is None else positive("rpm", rpm, "[rpm]")
    # The balances first: a request the machine cannot meet is an error even where
    # nothing else shakes the frame.
    balances = machine_balances(result, requests)
    try:
        s = shaking(result)
    except InputError:
        return None
    return MachineShaking(s, n, balances)


#: The keys of a ``[[balance]]`` row.
BALANCE_KEYS: frozenset[str] = frozenset(
    {"mechanism", "links", "objective", "torque_weight", "max_mass_radius_kg_m"}
)


@dataclass(frozen=True)
class BalanceRequest:
    """A machine file's ``[[balance]]`` row: counterweights to find for one linkage.

    Parameters
    ----------
    mechanism : str
        The linkage's name in the machine.
    links : tuple of tuple of (str, str)
        The links to counterweight, each by two of its joints, one pivoted to the
        frame.
    objective : str, default "rms_force"
        One of :data:`~cyclomech.dynamics.OBJECTIVES`.
    torque_weight : float, default 1.0
        The RMS torque's weight in ``"rms_force+torque"`` [1/m].
    max_mass_radius_kg_m : float, optional
        The largest m·r of each counterweight [kg·m]; default None (no bound).

    Raises
    ------
    InputError
        If a field is not of its kind: a name, (joint, joint) pairs, an objective of
        :data:`~cyclomech.dynamics.OBJECTIVES`, a finite weight ≥ 0, a bound > 0.

    Examples
    --------
    >>> BalanceRequest.from_row({"mechanism": "knife", "links": [["O", "F"]]}, "m.toml", 0).links
    (('O', 'F'),)
    """

    mechanism: str
    links: tuple[tuple[str, str], ...]
    objective: str = "rms_force"
    torque_weight: float = 1.0
    max_mass_radius_kg_m: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.mechanism, str):
            raise InputError(f"mechanism = {self.mechanism!r} must name a linkage")
        links = self.links
        if not (
            isinstance(links, tuple | list)
            and links
            and all(
                isinstance(p, tuple | list) and len(p) == 2 and all(isinstance(j, str) for j in p)
                for p in links
            )
        ):
            raise InputError(f"links = {links!r} must be one or more (joint, joint) pairs")
        object.__setattr__(self, "links", tuple((p[0], p[1]) for p in links))
        if not isinstance(self.objective, str) or self.objective not in OBJECTIVES:
            raise InputError(
                f"objective = {self.objective!r} must be one of {', '.join(OBJECTIVES)}"
            )
        w = finite_number("torque_weight", self.torque_weight, "[1/m]", low=0.0)
        object.__setattr__(self, "torque_weight", w)
        if self.max_mass_radius_kg_m is not None:
            b = positive("max_mass_radius_kg_m", self.max_mass_radius_kg_m, "[kg·m]")
            object.__setattr__(self, "max_mass_radius_kg_m", b)

    @classmethod
    def from_row(cls, row: Any, source: str, index: int) -> BalanceRequest:
        """The request of one ``[[balance]]`` row.

        Parameters
        ----------
        row : Mapping
            The row as read.
        source : str
            The file's name, for messages.
        index : int
            The row's place among the ``[[balance]]`` rows (from 0).

        Returns
        -------
        BalanceRequest

        Raises
        ------
        InputError
            Naming the file, the row and the key: an unknown key, a missing mechanism
            or links, links that are not pairs of joint names, an unknown objective,
            a negative torque weight or one with an objective that has no torque
            (it would be ignored), a bound on m·r that is not > 0.

        Examples
        --------
        >>> r = BalanceRequest.from_row({"mechanism": "knife", "links": [["O", "F"]],
        ...                              "objective": "peak_force"}, "m.toml", 0)
        >>> r.objective
        'peak_force'
        """
        index = count("index", index, low=0)
        where = f"{source}: [[balance]] #{index + 1}"
        _toml.must_be_table(row, source, f"[[balance]] #{index + 1}")
        _toml.check_keys(row, BALANCE_KEYS, source, f"[[balance]] #{index + 1}")
        name = row.get("mechanism")
        if not isinstance(name, str):
            raise InputError(f"{where}: mechanism = {name!r} must name a linkage of the machine")
        links = row.get("links")
        if not (
            isinstance(links, list)
            and links
            and all(
                isinstance(p, list) and len(p) == 2 and all(isinstance(j, str) for j in p)
                for p in links
            )
        ):
            raise InputError(
                f"{where}: links = {links!r} must be a non-empty array of links, each two "
                'joint names, one pivoted to the frame (e.g. [["O", "F"], ["A", "B"]])'
            )
        objective = row.get("objective", "rms_force")
        if objective not in OBJECTIVES:
            raise InputError(
                f"{where}: objective = {objective!r} must be one of {', '.join(OBJECTIVES)}"
            )
        weight = row.get("torque_weight", 1.0)
        if not (_toml.is_number(weight) and math.isfinite(weight) and weight >= 0):
            raise InputError(f"{where}: torque_weight = {weight!r} must be finite and ≥ 0 [1/m]")
        if "torque_weight" in row and objective != "rms_force+torque":
            raise InputError(
                f"{where}: torque_weight = {weight!r} only applies to objective = "
                f'"rms_force+torque" (this row\'s objective is {objective!r}, which has no '
                "torque term): remove it or set that objective"
            )
        bound = row.get("max_mass_radius_kg_m")
        if bound is not None and not (
            _toml.is_number(bound) and math.isfinite(bound) and bound > 0
        ):
            raise InputError(
                f"{where}: max_mass_radius_kg_m = {bound!r} must be finite and > 0 [kg·m]"
            )
        return cls(
            name,
            tuple((p[0], p[1]) for p in links),
            objective,
            float(weight),
            None if bound is None else float(bound),
        )


def _a_result(result: Any) -> None:
    """Refuse what is not a machine's result (:func:`cyclomech.machine.analyze`)."""
    if not hasattr(result, "mechanisms") or not hasattr(result, "nominal_rpm"):
        raise TypeError(f"result must be a MachineResult; got {type(result).__name__}")


def machine_balances(result: Any, requests: Sequence[BalanceRequest]) -> dict[str, Balance]:
    """Each requested linkage balanced at the machine's nominal speed
    (:func:`~cyclomech.dynamics.balance`, with the linkage's gravity), or a press's
    carrier (a counterweight on the carrier, its links ``[["O", "planet"]]``).

    Parameters
    ----------
    result : MachineResult
        :func:`cyclomech.machine.analyze`'s result.
    requests : sequence of BalanceRequest
        The ``[[balance]]`` rows.

    Returns
    -------
    dict of str to Balance
        By mechanism.

    Raises
    ------
    InputError
        If a request names no linkage with masses of the machine, or a link the
        balance refuses (not pivoted to the frame, unknown), naming the row.
    TypeError
        If ``result`` is not a machine's result or ``requests`` not a sequence of
        :class:`BalanceRequest`.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> b = machine_balances(r, r.machine.balance)["knife"]
    >>> round(b.before["rms_force_n"], 1), round(b.after["rms_force_n"], 6)
    (176.1, 0.0)
    """
    _a_result(result)
    instances("requests", requests, BalanceRequest)
    out: dict[str, Balance] = {}
    for i, req in enumerate(requests):
        res = result.mechanisms.get(req.mechanism)
        where = f"[[balance]] #{i + 1}"
        if isinstance(getattr(getattr(res, "mech", None), "press", None), GearLeverPress):
            out[req.mechanism] = _press(res, req, where, result.nominal_rpm)
            continue
        if getattr(res, "kinetostatics", None) is None:
            raise InputError(
                f"{where}: mechanism = {req.mechanism!r} must be a linkage of the machine "
                "with masses (its kinetostatics gives the shaking force) or a press with "
                "its masses and load"
            )
        gravity = (res.mech.dynamics or {}).get("gravity")
        try:
            out[req.mechanism] = balance(
                res,
                counterweights=list(req.links),
                rpm=result.nominal_rpm,
                objective=req.objective,
                torque_weight=req.torque_weight,
                gravity=gravity,
                max_mass_radius_kg_m=req.max_mass_radius_kg_m,
            )
        except InputError as e:
            raise InputError(f"{where}: {e}") from None
    return out


def _press(res: Any, req: BalanceRequest, where: str, rpm: float) -> Balance:
    """A press's [[balance]] row: the counterweight on its carrier
    (``_balance._press_balance``), the row's links checked."""
    carrier = set(PRESS_CARRIER)
    if len(req.links) != 1 or set(req.links[0]) != carrier:
        raise InputError(
            f"{where}: links = {[list(p) for p in req.links]!r}: a press has one link to "
            f"counterweight, its carrier {list(PRESS_CARRIER)!r} (from the guide gear's "
            "centre O on the main shaft to the planet's centre)"
        )
    try:
        return _press_balance(
            res,
            rpm=rpm,
            objective=req.objective,
            torque_weight=req.torque_weight,
            max_mass_radius_kg_m=req.max_mass_radius_kg_m,
        )
    except InputError as e:
        raise InputError(f"{where}: mechanism = {req.mechanism!r}: {e}") from None
