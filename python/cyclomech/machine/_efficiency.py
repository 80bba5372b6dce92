"""The machine's friction and efficiency at the nominal speed (issue 34 item 5):
each mechanism with a ``friction`` table gives its own over its turn
(``efficiency()`` of its result); the machine's is the useful power over the
input power across the mechanisms on the main shaft, over the cycle."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ._result import MachineResult

__all__ = ["efficiency_line", "efficiency_table", "machine_efficiency"]


def machine_efficiency(r: MachineResult) -> dict[str, Any] | None:
    """The machine's efficiency at the nominal speed, None when no mechanism has friction.

    Over one cycle at steady speed the energy stored returns to its start, so the
    useful work is the input work less the friction work: η = 1 − ΣP̄_f / P̄_in,
    P̄_f each mechanism's mean friction power [W] and P̄_in the main shaft's mean
    power (its mean torque with friction × ω) [W]: the mechanisms without
    friction count as lossless. None for η where a mechanism self-locks, the
    main shaft is not loaded or its mean power is not positive.

    Parameters
    ----------
    r : MachineResult
        The machine's result.

    Returns
    -------
    dict of str to Any or None
        ``machine_efficiency``, ``mean_input_power_w``, ``mean_friction_power_w``,
        ``mean_useful_power_w`` and ``mechanisms`` (each mechanism's
        ``efficiency()``, by name); None without friction.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"),
    ...                        progress=False)
    >>> e = machine_efficiency(r)
    >>> list(e["mechanisms"]), 0.8 < e["machine_efficiency"] < 1.0
    (['knife'], True)
    """
    own = {}
    for k, res in r.mechanisms.items():
        get = getattr(res, "efficiency", None)
        e = None if get is None else get()
        if e is not None:
            own[k] = e
    if not own:
        return None
    on_shaft = r.shaft is not None and all(k in r.shaft.parts for k in own)
    lost = [e["mean_friction_power_w"] for e in own.values()]
    p_f = None if any(v is None for v in lost) else float(sum(lost))
    p_in = float(r.shaft.at_nominal.power_w) if r.shaft is not None and on_shaft else None
    eta = None
    if p_f is not None and p_in is not None and p_in > 0.0:
        eta = 1.0 - p_f / p_in
    return {
        "nominal_rpm": r.nominal_rpm,
        "machine_efficiency": eta,
        "mean_input_power_w": p_in,
        "mean_friction_power_w": p_f,
        "mean_useful_power_w": None if eta is None or p_in is None else p_in * eta,
        "mechanisms": own,
    }


def _f(v: float | None, spec: str) -> str:
    return "—" if v is None or not math.isfinite(v) else format(v, spec)


def efficiency_table(e: dict[str, Any]) -> tuple[list[str], list[list[Any]]]:
    """The report's table of :func:`machine_efficiency`'s ``e``: one row per
    mechanism with friction and one for the machine.

    Examples
    --------
    >>> e = {"nominal_rpm": 45.0, "machine_efficiency": 0.95, "mean_input_power_w": 100.0,
    ...      "mean_friction_power_w": 5.0, "mean_useful_power_w": 95.0, "mechanisms": {}}
    >>> efficiency_table(e)[1][-1][:2]
    ['machine (on the main shaft)', '0.9500']
    """
    header = [
        "mechanism",
        "efficiency over the cycle",
        "mean friction power [W]",
        "mean input power [W]",
        "peak driving torque with / without friction [N·m]",
    ]
    rows: list[list[Any]] = []
    for k, m in e["mechanisms"].items():
        rows.append(
            [
                k,
                _f(m["cycle_efficiency"], ".4f"),
                _f(m["mean_friction_power_w"], ".4g"),
                _f(m["mean_input_power_w"], ".4g"),
                f"{_f(m['peak_torque_nm'], '.4g')} / {_f(m['peak_torque_nm_without'], '.4g')}",
            ]
        )
    rows.append(
        [
            "machine (on the main shaft)",
            _f(e["machine_efficiency"], ".4f"),
            _f(e["mean_friction_power_w"], ".4g"),
            _f(e["mean_input_power_w"], ".4g"),
            "",
        ]
    )
    return header, rows


def efficiency_line(e: dict[str, Any]) -> str:
    """The ``cyclomech run`` summary line of :func:`machine_efficiency`'s ``e``.

    Examples
    --------
    >>> e = {"nominal_rpm": 45.0, "machine_efficiency": 0.95, "mean_input_power_w": 100.0,
    ...      "mean_friction_power_w": 5.0, "mean_useful_power_w": 95.0, "mechanisms": {}}
    >>> efficiency_line(e)
    'Friction at 45 rpm: machine efficiency 0.9500 (5 W of 100 W lost)'
    """
    parts = [
        f"{k} efficiency {_f(m['cycle_efficiency'], '.4f')} "
        f"({_f(m['mean_friction_power_w'], '.4g')} W lost, peak torque "
        f"{_f(m['peak_torque_nm'], '.4g')} N·m with friction)"
        for k, m in e["mechanisms"].items()
    ]
    machine = (
        f"machine efficiency {_f(e['machine_efficiency'], '.4f')} "
        f"({_f(e['mean_friction_power_w'], '.4g')} W of "
        f"{_f(e['mean_input_power_w'], '.4g')} W lost)"
    )
    return f"Friction at {e['nominal_rpm']:g} rpm: " + "; ".join([*parts, machine])
