"""Sweeps in one Rust call per chunk (issue 20): the `_batch` part of
:mod:`cyclomech.machine` (its door). The machine asks, it does not reach in: a
kind that can solve many designs of one of its mechanisms at once offers the
optional hook ``batch_designs`` (documented with
:class:`~cyclomech._kind.Mechanism`; the ``cam_stop`` kind has one, in
:mod:`cyclomech.impact._batch`), and this module combines the designs it solves
with the machine's other mechanisms, its cyclogram and its own limits.

A sweep whose parameters all belong to mechanisms whose kinds take them in a
batch does not build a :class:`~cyclomech.Machine` per design: each kind
builds its designs' table (``designs``) and solves them (``solve``: its bounds'
phase angles per rpm, for every design), the cyclogram's shortest paths and
speed-limit search take every design at once as before, and each kind gives its
sweep columns at the optimum. The results are bit for bit those of one machine
per design (``sweep(..., batch=False)``, the reference the tests compare with).

What stays on the per-design path (:func:`plan` returns None, or a design is
left out of the batch):

* a parameter of ``[machine]`` (it may change the speed range or the cyclogram);
* a parameter of a mechanism whose kind has no batch path (cams, linkages,
  presses, transfers), or whose kind's hook refuses it (returns None);
* a design a kind's checks refuse (``ok`` False): the per-design path builds it,
  so that its ``problem`` text is the file reader's own.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._kind import BatchDesigns, BatchSolution, Proportional
from .._units import DEG_PER_S_PER_RPM
from ._many import _bounds_at, _own_limits
from ._model import Machine

__all__ = ["Plan", "batch_designs", "batch_figures", "plan"]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Plan:
    """A sweep the batch can take: each swept mechanism's batch (by name, in the
    machine's order: what its kind's ``batch_designs`` hook returned) and, per
    parameter, its mechanism and key."""

    batches: dict[str, BatchDesigns]
    keys: dict[str, tuple[str, str]]

    @property
    def mechanisms(self) -> tuple[str, ...]:
        """The swept mechanisms' names, in the machine's order.

        >>> import cyclomech as cm
        >>> plan(cm.Machine.example(), ["lifter.preload_m"]).mechanisms
        ('lifter',)
        """
        return tuple(self.batches)


def plan(machine: Machine, names: Sequence[str]) -> Plan | None:
    """The batch plan of a sweep of ``names`` (``<mechanism>.<key>``) over
    ``machine``, or None when a parameter needs the per-design path (see the
    module's docstring): each swept mechanism's kind is asked through its
    optional hook ``batch_designs``.

    >>> import cyclomech as cm
    >>> plan(cm.Machine.example(), ["lifter.preload_m"]).mechanisms
    ('lifter',)
    >>> plan(cm.Machine.example(), ["machine.speed_points"]) is None
    True
    """
    if not names or machine.data is None:
        return None
    keys: dict[str, tuple[str, str]] = {}
    for path in names:
        head, _, key = path.partition(".")
        if head == "machine" or head not in machine.mechanisms:
            return None
        keys[path] = (head, key)
    tables = machine.data.get("mechanism", {})
    batches: dict[str, BatchDesigns] = {}
    heads = {h for h, _ in keys.values()}
    for name in (k for k in machine.mechanisms if k in heads):
        mech = machine.mechanisms[name]
        hook = getattr(type(mech), "batch_designs", None)
        own = [key for h, key in keys.values() if h == name]
        batch = None if hook is None else hook(mech, tables.get(name, {}), own)
        if batch is None:
            return None
        batches[name] = batch
    return Plan(batches, keys)


def batch_designs(
    machine: Machine, pl: Plan, values: Mapping[str, Array]
) -> tuple[dict[str, Array], npt.NDArray[np.bool_]]:
    """Each swept mechanism's design table (its kind's, designs along the last
    axis) and the designs every one of their checks passed (the others go to the
    per-design path).

    >>> import numpy as np, cyclomech as cm
    >>> m = cm.Machine.example()
    >>> pl = plan(m, ["lifter.preload_m"])
    >>> tables, ok = batch_designs(m, pl, {"lifter.preload_m": np.array([1e-4, 2e-2])})
    >>> tables["lifter"].shape, ok.tolist()
    ((8, 2), [True, False])
    """
    out: dict[str, Array] = {}
    ok: npt.NDArray[np.bool_] | None = None
    for name, batch in pl.batches.items():
        own = {key: values[path] for path, (h, key) in pl.keys.items() if h == name}
        out[name], passed = batch.designs(own)
        ok = passed if ok is None else ok & passed
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
    for bit, with the swept mechanisms solved by their kinds' batches.

    >>> import numpy as np, cyclomech as cm
    >>> m = cm.Machine.example()
    >>> pl = plan(m, ["lifter.a_max_m"])
    >>> tables, _ = batch_designs(m, pl, {"lifter.a_max_m": np.array([1e-4, 2e-4])})
    >>> cols = batch_figures(m, pl, tables, np.array([300.0]), 1)
    >>> cols["limiting_deg"].round(3).tolist()
    [[264.971], [275.0]]
    """
    # C order (a boolean column selection of the caller's is Fortran-ordered).
    tables = {k: np.ascontiguousarray(t, dtype=np.float64) for k, t in tables.items()}
    D = next(iter(tables.values())).shape[1]
    S = speeds.size
    net = machine.speed_network
    bounded = machine.bounded_mechanisms
    base_laws = machine.bound_laws(n_threads=n_threads)
    solved = {name: pl.batches[name].solve(table, n_threads) for name, table in tables.items()}
    # Each design's bound laws: the swept mechanisms' own (speed-proportional, from
    # their batches), every other mechanism's shared.
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
            got = solved[m.name].sweep_values(grid, angles, fits)
        else:
            got = type(m).sweep_values([m] * D, grid, angles, fits, n_threads=n_threads)
        for c, v in got.items():
            prev = extra.get(c)
            extra[c] = np.fmax(np.full(rows.shape, np.nan) if prev is None else prev, v)
        k += nb
    own = _own_limits(machine)  # shared by the designs
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
    # each mechanism's own limit (shared by the designs).
    if slopes is not None:
        cg = net.speed_limits_proportional(slopes, machine.search_start_rpm, n_threads, 1e-10)
    else:
        cg = net.speed_limits(at, D, machine.search_start_rpm, n_threads, 1e-10)
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
    solved: Mapping[str, BatchSolution],
    D: int,
) -> list[list[Any]]:
    """Each design's bound laws (D, K): the swept mechanisms' own (proportional,
    from their batches), every other mechanism's shared."""
    per_mech: list[list[Any]] = []
    k = 0
    for m in bounded:
        nb = len(m.bounds())
        if m.name in solved:
            rows = solved[m.name].per_rpm.tolist()
            per_mech.append([[Proportional(float(x)) for x in row] for row in rows])
        else:
            per_mech.append([base_laws[k : k + nb]] * D)
        k += nb
    return [[law for col in per_mech for law in col[d]] for d in range(D)]


def _slopes(
    bounded: Sequence[Any],
    base_laws: Sequence[Any],
    solved: Mapping[str, BatchSolution],
    D: int,
) -> Array | None:
    """The bound laws of :func:`_laws` as slopes (D, K) [deg/rpm] when every one
    is proportional, else None."""
    cols: list[Array] = []
    k = 0
    for m in bounded:
        nb = len(m.bounds())
        if m.name in solved:
            cols.extend(solved[m.name].per_rpm.T)
        else:
            for law in base_laws[k : k + nb]:
                if not isinstance(law, Proportional):
                    return None
                cols.append(np.full(D, law.per_rpm))
        k += nb
    if not cols:
        return np.empty((D, 0))
    return np.ascontiguousarray(np.stack(cols, axis=1), dtype=np.float64)
