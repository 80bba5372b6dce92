"""Which key of the machine file buys how many rpm of speed limit: the sensitivity
of :meth:`Machine.speed_limit` to every numeric key of the mechanisms' tables and of
the cyclogram's operations.

**Method.** Each key k of value v (a number ≠ 0 at the top of a ``[mechanism.X]``
table; a number ≠ 0 in one of its sub-tables and lists that its kind lets vary —
:func:`_nested` —; or an ``[[operation]]``'s ``min_angle_deg``, ``max_angle_deg``
or ``min_duration_s``, named ``operation.<k>.<key>`` with k from 1) is varied by
±h·v (h = :data:`STEP`, 0.1 %) with :meth:`Machine.with_values`, and the speed
limits of all 2K variants come from one :func:`~cyclomech.machine.speed_limits`
call (the variants of a mechanism's keys share the cyclogram's network: one
shortest-path call per step of the search for all of them; an operation's
variant has a cyclogram of its own). A key of an operation names it in its note.
With L₊, L₀, L₋ the limits [rpm] at v(1 + h), v, v(1 − h):

* the sensitivity dL/dk = (L₊ − L₋) / (2 h v) [rpm per the key's unit], and the
  rpm a +1 % raise buys, 0.01·v·dL/dk;
* **does not bind**: |L₊ − L₋| and both one-sided changes within
  :data:`FLAT` · L₀ (the limit search's own tolerance is far below it) — the key
  does not set the speed limit here; 0 rpm;
* **kink**: the one-sided slopes (L₊ − L₀)/(h v) and (L₀ − L₋)/(h v) differ by
  more than :data:`KINK` of the larger: the limit changes which bound sets it at
  this value (a maximum of two bounds, or a peak of the limit over the key). No
  slope holds on both sides: ``rpm_per_unit`` is the raise's one-sided slope,
  ``rpm_per_percent`` NaN, and the note gives the limit's change at ±0.1 %;
* **exact**: where the cyclogram sets the limit on its operations' own bounds alone
  (no mechanism's bound or constraint priced at the limit), a binding operation
  key's rate is taken from the LP's shadow prices at the limit instead
  (:func:`_exact`); its note says so. Elsewhere (a mechanism's key: its bound's
  derivative is not at hand) the central difference stands;
* **cannot vary**: a variant is invalid (the key is at the edge of what is
  valid, or is a count): the message says why; no number;
* **not varied**: a key in a sub-table or a list past the first
  :data:`MAX_NESTED`, or a mechanism's or an operation's key where a dynamic error
  sets the limit (below): no number.

**Keys in sub-tables and lists** (a linkage's ``points``, ``lengths``, ``mass``
and ``load``; a cam's or a servo axis's ``segment`` tables; a press's
``deformation_force``; ``friction`` and ``phase`` tables: each kind's
``varied_tables``) are named by their path, a sub-table's key or a list's position
from 1: ``knife.lengths.3.length``, ``"lifter cam".segment.2.stroke_deg``. A list of
at most three numbers is a vector (a point, gravity): each number is a key of its
own (``knife.points.B.1`` is B's x). A longer list of numbers, or a list of such
vectors, is a curve or a table (a force over the crank angle): it is one key,
**scaled as a whole** (its value is the scale, 1; the note says so). At most
:data:`MAX_NESTED` such keys are varied, in the file's order; the rest are listed
as ``"not varied"``, since each costs two analyses. A ``synthesize`` table is not
varied: each variant would run the synthesis again.

Keys that are whole numbers (counts), booleans and strings are not varied; nor
are the catalogue tables of a kind (a servo's motors and gear ratios).

The speed limit is the one :meth:`Machine.speed_limit` gives — the
cyclogram's and each mechanism's own. **The elastic main shaft's dynamic errors**
(``[drive.shaft]``, ``[drive.link.<name>]``) can lower it further: the report folds
in the speed at which a working member's error reaches its bound
(:func:`~cyclomech.dynamics.error_limits`). :func:`drive_sensitivities` adds the
drive's keys (``drive.shaft.stiffness_nm_per_rad.1``,
``drive.link.knife.max_error_m``, …) to the table, each varied by ±0.1 % with the
analysed machine's motions kept (only the shaft and the links change), the limit
being min(L, the dynamic errors' limits): where no dynamic error's limit lies
within :data:`NEAR` above L, none of them can bind at ±0.1 % and they are listed
as not binding without a run. Where a dynamic error sets the machine's limit, the
mechanisms' and the operations' keys are **not varied** for it (their effect on the
errors would need the whole analysis per variant); each note keeps the key's rate
of the limit beneath.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

from .._arrays import instance
from .._errors import CyclomechError, CyclomechWarning

if TYPE_CHECKING:
    from ._model import Machine

__all__ = [
    "EXACT",
    "FLAT",
    "KINK",
    "MAX_NESTED",
    "NEAR",
    "STEP",
    "Sensitivity",
    "drive_sensitivities",
    "sensitivities",
]

#: The relative step of the central difference.
STEP = 1e-3
#: A change of the limit within this fraction of it is no change.
FLAT = 1e-9
#: One-sided slopes differing by more than this fraction of the larger: a kink.
KINK = 0.1
#: At most this many keys in sub-tables and lists are varied (two analyses each).
MAX_NESTED = 200
#: A dynamic error's limit further than this fraction above the speed limit cannot
#: bind at ±0.1 % of a drive key: its keys are not run (:func:`drive_sensitivities`).
NEAR = 0.02
#: The note of a curve or a table varied as a whole.
SCALED = "its {n} numbers scaled together (value: the scale)"


@dataclass(frozen=True)
class Sensitivity:
    """How the speed limit moves with one key of the machine file.

    Built by :func:`sensitivities`; each parameter is kept as the attribute of the
    same name.

    Parameters
    ----------
    key : str
        ``<mechanism>.<key>`` (or a path into a sub-table or a list, positions from
        1: ``knife.lengths.3.length``), as ``--set`` and :meth:`Machine.with_values`
        name it; ``operation.<k>.<key>`` for the k-th ``[[operation]]``.
    value : float
        The key's value in the file, in its own unit (1, the scale, for a curve or
        a table varied as a whole).
    rpm_per_unit : float
        dL/dk [rpm per the key's unit] (NaN where it cannot vary).
    rpm_per_percent : float
        The speed limit a +1 % raise of the key buys [rpm] (negative: lowering the
        key buys speed; 0 where it does not bind, NaN at a kink or where it cannot
        vary).
    status : str
        ``"binds"``, ``"does not bind"``, ``"kink"``, ``"cannot vary"`` or
        ``"not varied"``.
    note : str, default ""
        For a kink, the one-sided changes; for a key that cannot vary, why.
    limit_rpm : float, default nan
        The speed limit at the file's values [rpm] (:meth:`Machine.speed_limit`,
        the one the sensitivities are of).

    Examples
    --------
    >>> import cyclomech as cm
    >>> s = {x.key: x for x in cm.machine.sensitivities(cm.Machine.example())}["lifter.b_m"]
    >>> s.status, s.rpm_per_percent < 0      # lowering b buys speed
    ('binds', True)
    """

    key: str
    value: float
    rpm_per_unit: float
    rpm_per_percent: float
    status: str
    note: str = ""
    limit_rpm: float = math.nan

    def json(self) -> dict[str, Any]:
        """Its entry in ``results.json`` (no NaN: ``null``).

        Returns
        -------
        dict of str to object
            ``key``, ``value``, ``rpm_per_unit``, ``rpm_per_percent``, ``status``,
            ``note``.

        Examples
        --------
        >>> Sensitivity("a.b_m", 0.1, 2.0, 0.002, "binds").json()["rpm_per_percent"]
        0.002
        """

        def num(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {
            "key": self.key,
            "value": self.value,
            "rpm_per_unit": num(self.rpm_per_unit),
            "rpm_per_percent": num(self.rpm_per_percent),
            "status": self.status,
            "note": self.note,
        }


def _keys(machine: Machine) -> list[tuple[str, Any, str]]:
    """The varied keys: (path, value, what it is) of every float ≠ 0 at the top of a
    mechanism's table, then of the numbers in its kind's ``varied_tables``
    (:func:`_nested`: a curve's value is its list, varied as a whole), then every
    number ≠ 0 of an ``[[operation]]`` (its angles and duration: whole numbers there
    are angles, not counts), in the file's order."""
    from ._model import OPERATION_NUMBERS, _varied_tables

    data = machine.data or {}
    out: list[tuple[str, Any, str]] = []
    for name, table in data.get("mechanism", {}).items():
        for k, v in table.items():
            if isinstance(v, float) and math.isfinite(v) and v != 0.0:
                out.append((f"{name}.{k}", v, ""))
        # The tables in the file's order: the kind's set of them has an order of
        # its own in each process (string hashes), which decided the ranking's
        # order among ties and which keys fall past MAX_NESTED.
        varied = _varied_tables(machine.mechanisms[name])
        for k in [k for k in table if k in varied]:
            out += [
                (p, v, SCALED.format(n=sum(1 for _ in _flat(v))) if isinstance(v, list) else "")
                for p, v in _nested(f"{name}.{k}", table[k])
            ]
    for i, op in enumerate(data.get("operation", []), start=1):
        title = op.get("name") or f"{op.get('from')} → {op.get('to')}"
        for k, v in op.items():
            number = isinstance(v, int | float) and not isinstance(v, bool)
            if k in OPERATION_NUMBERS and number and math.isfinite(v) and v != 0:
                out.append((f"operation.{i}.{k}", float(v), f"[[operation]] #{i}: {title}"))
    return out


def _is_number(x: Any) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x)


def _nested(path: str, node: Any) -> Iterator[tuple[str, Any]]:
    """(path, value) of every key varied under ``node`` (positions from 1): a float
    ≠ 0; each number ≠ 0 of a vector (a list of at most three numbers); a curve or
    a table (a longer list of numbers, or a list of vectors) as a whole, its value
    the list, if it holds a number ≠ 0.

    >>> list(_nested("k.points", {"A": [0.0, 0.0], "B": [0.3, 0.4]}))
    [('k.points.B.1', 0.3), ('k.points.B.2', 0.4)]
    >>> list(_nested("k.load", [{"angle_deg": [0.0, 90.0, 180.0, 270.0], "point": "E"}]))
    [('k.load.1.angle_deg', [0.0, 90.0, 180.0, 270.0])]
    """
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _nested(f"{path}.{k}", v)
    elif isinstance(node, list) and node and all(_is_number(x) for x in node) and len(node) <= 3:
        for i, x in enumerate(node, start=1):
            if x != 0:
                yield f"{path}.{i}", float(x)
    elif (
        isinstance(node, list)
        and node
        and all(
            _is_number(x) or (isinstance(x, list) and all(_is_number(y) for y in x)) for x in node
        )
    ):
        if any(x != 0 for x in _flat(node)):
            yield path, node
    elif isinstance(node, list):
        for i, v in enumerate(node, start=1):
            yield from _nested(f"{path}.{i}", v)
    elif isinstance(node, float) and math.isfinite(node) and node != 0.0:
        yield path, node


def _flat(v: list[Any]) -> Iterator[float]:
    for x in v:
        yield from (_flat(x) if isinstance(x, list) else (x,))


def _scaled(v: Any, f: float) -> Any:
    """``v`` times ``f``: a number, or every number of a curve or a table."""
    return [_scaled(x, f) for x in v] if isinstance(v, list) else v * f


def sensitivities(machine: Machine, *, n_threads: int | None = None) -> list[Sensitivity]:
    """The speed limit's sensitivity to every numeric key of the mechanisms' tables
    and the cyclogram's operations (``operation.<k>.min_duration_s``, …), ranked:
    the keys that buy the most rpm per 1 % first (either way), then the kinks, those
    that do not bind and those that cannot vary (see the module's rules).

    Parameters
    ----------
    machine : Machine
        A machine read from a file or a dict (its keys are varied).
    n_threads : int, optional
        Threads for the Rust kernels; default None (``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of Sensitivity
        One per varied key, ranked.

    Raises
    ------
    InputError
        If ``machine`` is not a :class:`Machine` or was not read from a file or a dict.

    Examples
    --------
    >>> import cyclomech as cm
    >>> s = cm.machine.sensitivities(cm.Machine.example())
    >>> [(x.key, round(x.rpm_per_percent, 3)) for x in s[:2]]   # shorter, faster
    [('operation.4.min_duration_s', -3.611), ('lifter.b_m', -0.833)]
    >>> s[0].note
    '[[operation]] #4: weft insertion'
    """
    from ._many import speed_limits
    from ._model import Machine

    m = instance("machine", machine, Machine)
    if m.data is None:
        from .._errors import InputError

        raise InputError("sensitivities needs a machine read from a file or a dict")
    keys = _keys(m)
    variants: list[Machine] = [m]
    where: list[tuple[int, int] | str] = []  # per key: (index of +, index of −) or why not
    # The variants are this function's own ±0.1 %, not the user's values: what their
    # files' rules would warn of (a ζ of 0.9999 raised past 1) is not the user's slip.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CyclomechWarning)
        nested = 0
        for path, v, _ in keys:
            deep = path.count(".") > 1 and not path.startswith("operation.")
            nested += deep
            if deep and nested > MAX_NESTED:
                where.append(f"past the first {MAX_NESTED} keys in sub-tables and lists")
                continue
            try:
                up = m.with_values({path: _scaled(v, 1 + STEP)})
                down = m.with_values({path: _scaled(v, 1 - STEP)})
            except CyclomechError as e:
                where.append(str(e))
                continue
            where.append((len(variants), len(variants) + 1))
            variants += [up, down]
        found = speed_limits(variants, n_threads=n_threads)
    limits = [lim.rpm for lim in found]
    base = limits[0]
    exact = _exact(m, found[0])
    out = []
    for (path, v, what), at in zip(keys, where, strict=True):
        v = 1.0 if isinstance(v, list) else v  # a curve's value: its scale
        if isinstance(at, str):
            status = "not varied" if at.startswith("past the first") else "cannot vary"
            rec = Sensitivity(path, v, math.nan, math.nan, status, at)
        else:
            rec = _rate(path, v, base, limits[at[0]], limits[at[1]])
        if path in exact and rec.status == "binds":
            rate = exact[path]
            rec = replace(rec, rpm_per_unit=rate, rpm_per_percent=0.01 * v * rate, note=EXACT)
        note = "; ".join(x for x in (what, rec.note) if x)
        out.append(replace(rec, limit_rpm=base, note=note))
    return _ranked(out)


def drive_sensitivities(result: Any, table: list[Sensitivity]) -> list[Sensitivity]:
    """The table of :func:`sensitivities` with the drive's elastic keys added, of the
    limit the report gives: min(L, each working member's dynamic-error limit) (see
    the module's rules).

    Parameters
    ----------
    result : MachineResult
        :func:`analyze`'s result, whose ``torsion`` holds the dynamic errors (the
        table is returned as it is without them).
    table : list of Sensitivity
        :func:`sensitivities` of its machine.

    Returns
    -------
    list of Sensitivity
        The table with one row per number of ``[drive.shaft]`` and of each
        ``[drive.link.<name>]``, ranked with the others.

    Raises
    ------
    InputError
        If ``result`` is not a :class:`MachineResult` or ``table`` not a list of
        :class:`Sensitivity`.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.Machine.from_toml("examples/knife_cutter.toml")
    >>> r = cm.machine.analyze(m, progress=False, sensitivities=True)
    >>> s = {x.key: x for x in r.sensitivities}["drive.link.knife.max_error_m"]
    >>> s.status, s.note[:44]
    ('does not bind', 'no dynamic error limits the speed within 2 %')
    """
    from ..dynamics import error_limits
    from ._result import MachineResult

    result = instance("result", result, MachineResult)
    table = list(instance("table", table, list))
    if not all(isinstance(x, Sensitivity) for x in table):
        from .._errors import InputError

        raise InputError("table must be a list of Sensitivity (cyclomech.machine.sensitivities)")
    m = result.machine
    if result.torsion is None or m.data is None or "drive" not in m.data:
        return table
    base = table[0].limit_rpm if table else m.speed_limit().rpm
    drive = m.data["drive"]
    keys = list(_nested("drive.shaft", drive.get("shaft", {})))
    for name, link in drive.get("link", {}).items():
        keys += _nested(f"drive.link.{name}", link)
    own = {k: v for k, v in result.torsion.limits_rpm.items() if math.isfinite(v)}
    lowest = min(own.values(), default=math.inf)
    out = list(table)
    if lowest > base * (1.0 + NEAR):
        quiet = (
            f"no dynamic error limits the speed within {100 * NEAR:g} % of {base:.4g} rpm "
            f"(lowest: {lowest:.4g} rpm)"
        )
        out += [Sensitivity(p, v, 0.0, 0.0, "does not bind", quiet, base) for p, v in keys]
        return _ranked(out)
    folded = min(base, lowest)

    def limit(path: str, value: Any) -> float:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CyclomechWarning)
            other = m.with_values({path: value})
        return min([base, *error_limits(result, other.drive.elastic, below_rpm=base).values()])

    for path, v in keys:
        try:
            up, down = limit(path, v * (1 + STEP)), limit(path, v * (1 - STEP))
        except CyclomechError as e:
            out.append(Sensitivity(path, v, math.nan, math.nan, "cannot vary", str(e), folded))
            continue
        out.append(replace(_rate(path, v, folded, up, down), limit_rpm=folded))
    if lowest < base:
        out = [x if x.key.startswith("drive.") else _beneath(x, folded) for x in out]
    return _ranked(out)


def _beneath(x: Sensitivity, folded: float) -> Sensitivity:
    """A mechanism's or an operation's row where a dynamic error sets the limit: not
    varied for it (each variant would need the whole analysis), its rate of the
    rigid limit beneath kept in the note."""
    was = (
        f"on the limit beneath ({x.limit_rpm:.4g} rpm) +1 % gives {x.rpm_per_percent:+.4g} rpm"
        if x.status == "binds"
        else f"on the limit beneath ({x.limit_rpm:.4g} rpm): {x.status}"
    )
    why = "a dynamic error sets the limit; this key's effect on it is not computed"
    note = "; ".join(y for y in (x.note, why, was) if y)
    return replace(
        x,
        rpm_per_unit=math.nan,
        rpm_per_percent=math.nan,
        status="not varied",
        note=note,
        limit_rpm=folded,
    )


def _ranked(table: list[Sensitivity]) -> list[Sensitivity]:
    """The keys that buy the most rpm per 1 % first (either way), then the kinks,
    those that do not bind, that cannot vary and that were not varied."""
    order = {"binds": 0, "kink": 1, "does not bind": 2, "cannot vary": 3, "not varied": 4}
    return sorted(
        table,
        key=lambda s: (order[s.status], -abs(s.rpm_per_percent if s.status == "binds" else 0)),
    )


#: The note of a rate from the LP's duals (:func:`_exact`).
EXACT = "exact: the LP's shadow prices at the limit"


def _labels(ops: list[Any]) -> list[str]:
    """Each operation's label in the LP's rows: its title, with its arc where
    several operations share the title (the cyclogram's rule)."""
    titles = [op.title for op in ops]
    return [
        t if titles.count(t) == 1 else f"{t} ({op.src}→{op.dst})"
        for t, op in zip(titles, ops, strict=True)
    ]


def _exact(m: Machine, lim: Any) -> dict[str, float]:
    """dL/dk [rpm per unit] of the operations' angles and durations, exact, where
    the cyclogram sets the limit L on its operations' own bounds alone.

    At L the optimum's limiting angle F(n) meets its own minimum m_0(n); F moves
    with each priced bound j by its shadow price y_j (F_k = Σ y_j ∂m_j/∂k, and
    likewise in n), so dL/dk = −(F_k − ∂m_0/∂k)/(F_n − ∂m_0/∂n), with
    m_j = a_j (angle row ``min[…]``) or 6·n·t_j [deg] (duration row ``duration[…]``).
    Empty where a mechanism's bound or a constraint is priced (their derivative in
    n is not at hand: the finite differences stand), at a tie of the limiting
    operation's angle and duration, or where the optimum cannot be taken.
    """
    from .._errors import InfeasibleError

    cg, limit = m.cyclogram, lim.rpm  # lim: the machine's SpeedLimit, already found
    if lim.by != "cyclogram" or not (0.0 < limit < math.inf) or cg.limiting is None:
        return {}
    n = limit * (1.0 - 1e-9)  # the limit is searched to ~1e-11: just inside it
    try:
        o = m.optimize(n)
    except (InfeasibleError, CyclomechError):
        return {}
    ops = list(cg.operations)
    labels = _labels(ops)
    rows = {}
    for i, lab in enumerate(labels):
        rows[f"min[{lab}]"], rows[f"duration[{lab}]"] = (i, "angle"), (i, "duration")
    priced = {k: y for k, y in o.duals.items() if abs(y) > 1e-12 and k != "cycle"}
    if any(k not in rows for k in priced):
        return {}
    head = [op.arc for op in ops].index(cg.limiting)
    lead = ops[head]
    a0, d0 = lead.min_angle_deg, 6.0 * n * lead.min_duration_s
    if math.isclose(a0, d0) or not math.isclose(max(a0, d0), o.objective, rel_tol=1e-6):
        return {}
    f_n = sum(y * 6.0 * ops[rows[k][0]].min_duration_s for k, y in priced.items() if k[0] == "d")
    m0_n = 6.0 * lead.min_duration_s if d0 > a0 else 0.0
    if abs(f_n - m0_n) < 1e-15:
        return {}
    out = {}
    for i, label in enumerate(labels):
        for key, row, per in (
            ("min_angle_deg", f"min[{label}]", 1.0),
            ("min_duration_s", f"duration[{label}]", 6.0 * n),
        ):
            f_k = priced.get(row, 0.0) * per
            own = i == head and ((key == "min_angle_deg") == (a0 > d0))
            out[f"operation.{i + 1}.{key}"] = -(f_k - (per if own else 0.0)) / (f_n - m0_n)
    return out


def _rate(path: str, v: float, base: float, up: float, down: float) -> Sensitivity:
    """One key's sensitivity from the limits at v(1 ± h) and v (the module's rules).

    >>> _rate("a.k", 2.0, 100.0, 100.2, 99.8).rpm_per_percent
    2.0000000000000284
    >>> _rate("a.k", 2.0, 100.0, 100.0, 100.0).status
    'does not bind'
    >>> _rate("a.k", 2.0, 100.0, 100.0, 99.8).status
    'kink'
    """
    if not all(math.isfinite(x) for x in (base, up, down)):
        return Sensitivity(path, v, math.nan, math.nan, "cannot vary", "no finite speed limit")
    tol = FLAT * max(abs(base), 1.0)
    if abs(up - base) <= tol and abs(base - down) <= tol:
        return Sensitivity(path, v, 0.0, 0.0, "does not bind")
    s_up, s_down = (up - base) / (STEP * v), (base - down) / (STEP * v)
    if abs(s_up - s_down) > KINK * max(abs(s_up), abs(s_down)):
        note = (
            f"+0.1 % changes the limit by {up - base:+.4g} rpm, −0.1 % by {down - base:+.4g} rpm: "
            "another bound takes over here"
        )
        return Sensitivity(path, v, s_up, math.nan, "kink", note)
    rate = (up - down) / (2.0 * STEP * v)
    return Sensitivity(path, v, rate, rate * 0.01 * v, "binds")
