"""Sweeps of a cam stop's parameters in one Rust call per chunk (issue 20): the
`_batch` part of :mod:`cyclomech.machine` (its door).

A sweep that varies only numeric keys of pulse-model ``cam_stop`` mechanisms
(:data:`BATCH_KEYS`: the stop's preload, stroke, lever, stiffness, damping,
restitution, contact time, rebound limit …) does not build a
:class:`~cyclomech.Machine` and a :class:`~cyclomech.impact.StopImpact` per design:
the designs' parameters go to Rust as arrays (``_core.stop_design_batch``: each
design's contact point, rebound per unit impact speed g, largest admissible impact
speed, phase angle per rpm and smallest phase angle at every speed, rayon over
designs, the GIL released), the cyclogram's shortest paths and speed-limit search
take every design at once as before, and the rebounds at the optimum are g times
the impact speed there (the pulse model is linear in it, and
:func:`~cyclomech.impact.rebounds` takes it so too). The results are bit for bit
those of one machine per design (``sweep(..., batch=False)``, the reference the tests compare with).

What stays on the per-design path (:func:`plan` returns None, or a design is
left out of the batch):

* a parameter of ``[machine]`` (it may change the speed range or the cyclogram)
  or of any other kind of mechanism (cams, linkages, presses, transfers);
* a stop in the contact model (its search is a different kernel) or with the
  ``half_sine`` pulse (sampled with numpy's sine);
* ``stroke_m`` or ``lever_length_m`` of a stop that takes its law and stroke from
  a cam (``cam = "…"``);
* a design the batch's checks refuse (a preload at or beyond the stroke, a
  negative stiffness …): the per-design path builds it, so that its ``problem``
  text is the file reader's own.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._kind import Proportional
from .._units import DEG_PER_S_PER_RPM
from ..impact import CamStop, propped_lever_stiffness
from ._many import _own_limits
from ._model import Machine, _bounds_at

__all__ = ["BATCH_KEYS", "Plan", "batch_figures", "plan"]

#: The keys of a ``cam_stop`` table a batched sweep may vary: every key a sweep may
#: set (``CamStop.keys`` less its fixed keys) but the text ones and ``phase_deg``.
BATCH_KEYS = CamStop.keys - CamStop.fixed_keys - {"law", "pulse", "model", "phase_deg"}

#: The pulse shapes of the batch kernel, by their code.
_PULSE_CODE = {"decaying": 0, "rectangular": 1, "triangular": 2}

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Plan:
    """A sweep the batch can take: the swept stops (mechanism names, in the
    machine's order) and, per parameter, its stop and key."""

    stops: tuple[str, ...]
    keys: dict[str, tuple[str, str]]


def plan(machine: Machine, names: Sequence[str]) -> Plan | None:
    """The batch plan of a sweep of ``names`` (``<mechanism>.<key>``) over
    ``machine``, or None when a parameter needs the per-design path (see the
    module's docstring).

    >>> import cyclomech as cm
    >>> from cyclomech.machine._batch import plan
    >>> plan(cm.Machine.example(), ["lifter.preload_m"]).stops
    ('lifter',)
    >>> plan(cm.Machine.example(), ["machine.speed_points"]) is None
    True
    """
    if not names or machine.data is None:
        return None
    keys: dict[str, tuple[str, str]] = {}
    tables = machine.data.get("mechanism", {})
    for path in names:
        head, _, key = path.partition(".")
        mech = machine.mechanisms.get(head)
        if head == "machine" or not isinstance(mech, CamStop) or key not in BATCH_KEYS:
            return None
        stop = mech.stop
        if stop.model != "pulse" or stop.pulse not in _PULSE_CODE:
            return None
        if "cam" in tables.get(head, {}) and key in ("stroke_m", "lever_length_m"):
            return None
        keys[path] = (head, key)
    heads = {h for h, _ in keys.values()}
    return Plan(tuple(k for k in machine.mechanisms if k in heads), keys)


@dataclass(frozen=True)
class _Designs:
    """One swept stop's designs: the (8, D) table of the kernels (stroke,
    preload, mass, stiffness, contact time, restitution, ζ, a_max) and which
    designs passed the checks."""

    table: Array
    ok: npt.NDArray[np.bool_]


#: An empty speed grid for ``_core.stop_design_batch``.
_NO_SPEEDS = np.empty(0)


@functools.lru_cache(maxsize=4096)
def _propped_ratio(a: float, b: float) -> float:
    """StopImpact's contact-stiffness ratio of a lever of arms ``a``, ``b`` [m]
    (E·J_x cancels, so at E = J_x = 1), NaN out of range; remembered, since a
    sweep's chunks mostly share their levers."""
    try:
        free, propped = propped_lever_stiffness(1.0, 1.0, a, b)
    except ValueError:  # an InputError: out of range
        return float("nan")
    return float(propped / free)


def _stop_designs(mech: CamStop, table: Mapping[str, Any], values: Mapping[str, Array]) -> _Designs:
    """The designs of one stop with ``values`` (key → (D,)) replacing its table's:
    every quantity as :class:`~cyclomech.impact.StopImpact` computes it, in the
    same order (so, bit for bit), and the checks it makes; a design that fails
    one is left to the per-design path."""
    st = mech.stop
    D = next(iter(values.values())).size
    base = {
        "stroke": st.stroke,
        "preload": st.preload,
        "lever_length": st.lever_length,
        "J_A": st.J_A,
        "a": st.a,
        "b": st.b,
        "E": st.E,
        "J_x": st.J_x,
        "mass": st.mass,
        "restitution": st.restitution,
        "zeta": st.zeta,
        "contact_stiffness": st.contact_stiffness,
        "contact_time": st.contact_time,
        "a_max": mech.a_max,
    }
    p = {
        k: np.asarray(values[k], dtype=np.float64) if k in values else np.full(D, v)
        for k, v in base.items()
    }
    ok = np.ones(D, dtype=bool)
    with np.errstate(all="ignore"):
        for k in ("stroke", "lever_length", "J_A", "a", "b", "E", "J_x", "a_max"):
            ok &= np.isfinite(p[k]) & (p[k] > 0.0)
        ok &= (p["preload"] >= 0.0) & (p["preload"] < p["stroke"])
        # A rebound limit not below the stroke is the reader's error (CamStop.rules).
        ok &= p["a_max"] < p["stroke"]
        ok &= (p["restitution"] >= 0.0) & (p["restitution"] <= 1.0)
        ok &= p["zeta"] >= 0.0
        E, J, a, b = p["E"], p["J_x"], p["a"], p["b"]
        stiffness = 3.0 * E * J / ((a + b) * b * b)  # lever_stiffness
        ok &= np.isfinite(stiffness) & (stiffness > 0.0)
        # Given, or derived as StopImpact derives it when the table gives none.
        derived = ("mass", "contact_stiffness", "contact_time")
        file_key = {p: k for k, p in CamStop.params.items()}
        given = {k: k in values or file_key[k] in table for k in derived}
        if given["mass"]:
            mass = p["mass"]
        else:
            # J_A/l**2 as Python floats do it (a float power, not numpy's square).
            pairs_jl = zip(p["J_A"].tolist(), p["lever_length"].tolist(), strict=True)
            mass = np.array([j / ln**2 for j, ln in pairs_jl])
        ok &= np.isfinite(mass) & (mass > 0.0)
        if given["contact_stiffness"]:
            contact = p["contact_stiffness"]
            ok &= np.isfinite(contact) & (contact > stiffness)
        else:
            # One ratio per distinct lever (a sweep's designs mostly share one).
            ratio = np.full(D, np.nan)
            levers, which = np.unique(np.stack([a[ok], b[ok]]), axis=1, return_inverse=True)
            per_lever = [_propped_ratio(float(x), float(y)) for x, y in levers.T.tolist()]
            ratio[ok] = np.asarray(per_lever, dtype=np.float64)[which.reshape(-1)]
            contact = stiffness * ratio
        ok &= np.isfinite(contact) & (contact > 0.0)
        # contact_time(c, m) when not given: π·√(m/c).
        tau = p["contact_time"] if given["contact_time"] else np.pi * np.sqrt(mass / contact)
        ok &= np.isfinite(tau) & (tau > 0.0)
    rows = [p["stroke"], p["preload"], mass, stiffness, tau]
    rows += [p["restitution"], p["zeta"], p["a_max"]]
    return _Designs(np.ascontiguousarray(np.stack(rows)), ok)


def batch_designs(
    machine: Machine, pl: Plan, values: Mapping[str, Array]
) -> tuple[dict[str, Array], npt.NDArray[np.bool_]]:
    """Each swept stop's (8, D) design table and the designs every stop's checks
    passed (the others go to the per-design path)."""
    assert machine.data is not None
    tables = machine.data.get("mechanism", {})
    out: dict[str, Array] = {}
    ok: npt.NDArray[np.bool_] | None = None
    for name in pl.stops:
        # By StopImpact's parameter names (the file's keys carry their units).
        own = {CamStop.params[key]: values[path] for path, (h, key) in pl.keys.items() if h == name}
        mech = machine.mechanisms[name]
        assert isinstance(mech, CamStop)
        d = _stop_designs(mech, tables.get(name, {}), own)
        out[name] = d.table
        ok = d.ok if ok is None else ok & d.ok
    assert ok is not None
    return out, ok


def batch_figures(
    machine: Machine,
    pl: Plan,
    tables: Mapping[str, Array],
    speeds: Array,
    n_threads: int | None,
) -> dict[str, npt.NDArray[Any]]:
    """The sweep's figures (D, S) of the designs ``tables`` (from
    :func:`batch_designs`, only designs that passed) at ``speeds`` [rpm]: what
    :func:`~cyclomech.machine.speed_sweeps` and
    :func:`~cyclomech.machine.speed_limits` give for one machine per design, bit
    for bit, with the swept stops solved by the batch kernels."""
    # C order (a boolean column selection of the caller's is Fortran-ordered).
    tables = {k: np.ascontiguousarray(t, dtype=np.float64) for k, t in tables.items()}
    D = next(iter(tables.values())).shape[1]
    S = speeds.size
    net = machine._network
    bounded = machine._bounded
    base_laws = machine.bound_laws(n_threads=n_threads)
    solved: dict[str, tuple[Array, Array, Array]] = {}
    for name, table in tables.items():
        mech = machine.mechanisms[name]
        assert isinstance(mech, CamStop)
        law = mech.stop.law
        coeffs = None if law.coeffs is None else np.asarray(law.coeffs, dtype=np.float64)
        # No speeds: the smallest phase angles per speed are not needed here (the
        # shortest paths take the slopes).
        _, _, _, unit, per, _, g = _core.stop_design_batch(
            law.name,
            law.form == "rise",
            coeffs,
            _PULSE_CODE[mech.stop.pulse],
            table,
            _NO_SPEEDS,
            n_threads=n_threads,
        )
        solved[name] = (unit, per, g)
    # Each design's bound laws: the swept stops' own, every other mechanism's shared.
    # All proportional (the usual case: stops only): their slopes (D, K), the
    # solve at every speed and the speed-limit search each one Rust call; else
    # the laws, SpeedNetwork.solve and the Python search.
    grid = np.tile(speeds, (D, 1))
    rows = grid.reshape(-1)
    slopes = _slopes(bounded, base_laws, solved, D)
    at: Any = None
    if slopes is not None:
        value, fits, binding, bound_mins = net.solve_proportional(slopes, speeds, n_threads)
    else:
        at = _bounds_at(_laws(bounded, base_laws, solved, D))
        value, fits, binding, mins = net.solve(rows, at(np.arange(D), grid), n_threads)
        bound_mins = mins[:, net.bound_op].reshape(rows.size, len(net.bound_op))
    extra: dict[str, Array] = {}  # the mechanisms' own columns, largest of each
    k = 0
    for m in bounded:
        nb = len(m.bounds())
        angles = [bound_mins[:, k + i] for i in range(nb)]
        if m.name in solved:
            unit, g = solved[m.name][0], solved[m.name][2]
            t = angles[0].reshape(D, S)
            # The impact speed at the optimum's angle t: n·unit/t; its rebound g·v0
            # (rebounds' arithmetic; NaN where the machine does not fit).
            ok = fits.reshape(D, S)
            v0 = grid * unit[:, None] / np.where(ok, t, 1.0)
            a = (g[:, None] * v0).reshape(-1)
            got = {"max_rebound_m": np.where(fits, a, np.nan)}
        else:
            got = type(m).sweep_values([m] * D, grid, angles, fits, n_threads=n_threads)
        for c, v in got.items():
            prev = extra.get(c)
            extra[c] = np.fmax(np.full(rows.shape, np.nan) if prev is None else prev, v)
        k += nb
    own = _own_limits(machine)  # shared by the designs (a stop has none)
    lowest = min(own.values(), default=np.inf)
    cols: dict[str, npt.NDArray[Any]] = {
        "fits": fits,
        "limiting_deg": value,
        "limiting_s": value / (DEG_PER_S_PER_RPM * rows),
        "productivity_per_min": np.where(fits & (rows <= lowest), rows, 0.0),
        "max_rebound_m": extra.get("max_rebound_m", np.full(rows.shape, np.nan)),
        "binding": binding,
    }
    cols = {c: v.reshape(D, S) for c, v in cols.items()}
    # The speed limit: the cyclogram's search over every design at once, then
    # each mechanism's own limit (shared by the designs: a stop has none).
    if slopes is not None:
        cg = net.speed_limits_proportional(slopes, machine._search_start(), n_threads, 1e-10)
    else:
        cg = net.speed_limits(at, D, machine._search_start(), n_threads, 1e-10)
    rpm = np.asarray(cg, dtype=np.float64).copy()
    by = np.full(D, "cyclogram", dtype=object)
    for name, limit in own.items():
        lower = limit < rpm  # never for inf
        by[lower], rpm[lower] = name, limit
    cols["speed_limit_rpm"] = np.repeat(rpm[:, None], S, axis=1)
    cols["speed_limit_by"] = np.repeat(by[:, None], S, axis=1)
    return cols


def _laws(
    bounded: Sequence[Any],
    base_laws: Sequence[Any],
    solved: Mapping[str, tuple[Array, Array, Array]],
    D: int,
) -> list[list[Any]]:
    """Each design's bound laws (D, K): the swept stops' own (proportional, from
    the batch kernel), every other mechanism's shared."""
    per_mech: list[list[Any]] = []
    k = 0
    for m in bounded:
        nb = len(m.bounds())
        if m.name in solved:
            per_mech.append([[Proportional(float(x))] for x in solved[m.name][1].tolist()])
        else:
            per_mech.append([base_laws[k : k + nb]] * D)
        k += nb
    return [[law for col in per_mech for law in col[d]] for d in range(D)]


def _slopes(
    bounded: Sequence[Any],
    base_laws: Sequence[Any],
    solved: Mapping[str, tuple[Array, Array, Array]],
    D: int,
) -> Array | None:
    """The bound laws of :func:`_laws` as slopes (D, K) [deg/rpm] when every one
    is proportional, else None."""
    cols: list[Array] = []
    k = 0
    for m in bounded:
        nb = len(m.bounds())
        if m.name in solved:
            cols.append(solved[m.name][1])
        else:
            for law in base_laws[k : k + nb]:
                if not isinstance(law, Proportional):
                    return None
                cols.append(np.full(D, law.per_rpm))
        k += nb
    if not cols:
        return np.empty((D, 0))
    return np.ascontiguousarray(np.stack(cols, axis=1), dtype=np.float64)
