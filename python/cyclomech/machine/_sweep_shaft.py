"""The main-shaft columns of a sweep (issue 20): the `_sweep_shaft` part of
:mod:`cyclomech.machine` (its door).

With ``sweep(..., shaft=True)`` (``cyclomech sweep --shaft``) a machine whose
mechanisms load the main shaft (a cam with its follower's loads, a linkage with
masses or loads, a press with its load: what ``cyclomech run`` reports as "the
main shaft") gets, at every point of a sweep, the statistics of its main-shaft
torque: :data:`SHAFT_COLUMNS`. They are the ``cyclomech run``
report's: each design is analysed as ``run`` does (:func:`analyze`: its speed
limit, its optimum at its nominal speed, each mechanism's results there, the
phased sum of their torques, moved within the slack with ``flatten_torque``) and
the torque's statistics taken at each of the sweep's speeds in one Rust call
(:meth:`cyclomech.shaft.ShaftTorque.stats`: the ω² part scales with the speed, the
layout stays that of the nominal optimum, as the report's ``over_speed``). That
costs one analysis per design (~0.7 s for the loom with its cam), which is why
it is asked for, not automatic. A machine without such a mechanism, an invalid
design and a design whose cyclogram has no optimum at its nominal speed get NaN.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from .._errors import CyclomechError
from ._model import Machine

__all__ = ["SHAFT_COLUMNS", "has_shaft", "shaft_columns"]

#: The main-shaft columns of a sweep, and the :class:`~cyclomech.shaft.ShaftStats`
#: field each holds: mean torque [N·m], peak |torque| [N·m], RMS torque [N·m],
#: motor power (mean torque × ω) [W], flywheel for the machine's δ [kg·m²].
SHAFT_COLUMNS = {
    "shaft_mean_torque_nm": "mean_torque_nm",
    "shaft_peak_torque_nm": "peak_torque_nm",
    "shaft_rms_torque_nm": "rms_torque_nm",
    "shaft_power_w": "power_w",
    "shaft_flywheel_kg_m2": "flywheel_kg_m2",
}


def has_shaft(machine: Machine) -> bool:
    """Whether ``machine`` (the file's own values) loads its main shaft, as
    ``cyclomech run`` finds it; False when it cannot be analysed.

    >>> import cyclomech as cm
    >>> from cyclomech.machine._sweep_shaft import has_shaft
    >>> has_shaft(cm.Machine.example()), has_shaft(cm.Machine.from_toml("examples/stb_loom.toml"))
    (False, True)
    """
    from ._report import analyze

    try:
        return analyze(machine, progress=False).shaft is not None
    except CyclomechError:
        return False


def shaft_columns(
    base: Machine,
    names: Sequence[str],
    axes: Sequence[npt.NDArray[Any]],
    designs: npt.NDArray[np.intp],
    speeds: npt.NDArray[np.float64],
    problems: npt.NDArray[np.object_],
) -> dict[str, npt.NDArray[np.float64]]:
    """The :data:`SHAFT_COLUMNS` (D, S) of the designs (k, P) (indices into
    ``axes``) at ``speeds`` [rpm]: one analysis per valid design (``problems[d]``
    empty), NaN where there is no main shaft."""
    from ._report import analyze

    D, S = len(designs), speeds.size
    out = {c: np.full((D, S), np.nan) for c in SHAFT_COLUMNS}
    for d, row in enumerate(designs):
        if problems[d]:
            continue
        values = {k: axes[j][i].item() for j, (k, i) in enumerate(zip(names, row, strict=True))}
        m = base.with_values(values) if names else base
        try:
            shaft = analyze(m, progress=False).shaft
        except CyclomechError:
            continue  # no analysis, no shaft: NaN (the figures say why)
        if shaft is None:
            continue
        st = shaft.torque.stats(speeds, m.speed_fluctuation)
        for c, f in SHAFT_COLUMNS.items():
            out[c][d] = getattr(st, f)
    return out
