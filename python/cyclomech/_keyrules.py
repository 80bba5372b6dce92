"""The keys of cyclomech's files that were renamed to carry their units, and the
plausibility rules of the values every table takes: one place for both.

**Renamed keys.** A key with a physical unit says it in its name (``a_max_m``,
``preload_m``, ``J_A_kg_m2``, ``R_t_m``, …), as a cam's keys always have
(``base_radius_m``, ``mass_kg``, ``max_stress_pa``). :data:`RENAMED` maps each
key's old name to its new one and the unit in words; :func:`cyclomech._toml.check_keys`
consults it, so an old name in any table of any file (a machine's mechanism, an
impact file's ``[stop]``, a press file's ``[press]``) is an error naming the new
key, not an unknown key.

**Plausibility.** A value can be valid and still not what the user meant: a
rebound limit written in millimetres (``a_max_m = 0.1`` on a 9.4 mm stroke) or a
damping ratio in percent (``zeta = 5``). Each kind declares its :class:`Rule`\\ s
beside its keys (``CamStop.rules``, …); :func:`check` applies them and the rules
every key follows by its unit suffix (:data:`SUFFIX_RULES`: a length over 10 m,
an angle under 0.01°, a stress under 1 MPa). A value that cannot be meant is an
:class:`~cyclomech.InputError`; one that is only unusual a
:class:`~cyclomech.CyclomechWarning`; both name the key, the value and the likely
slip.

>>> RENAMED["a_max"]
('a_max_m', 'metres')
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any, TypeGuard

from ._arrays import finite_number
from ._errors import CyclomechWarning, InputError

__all__ = [
    "MU_PLAUSIBLE",
    "RENAMED",
    "SUFFIX_RULES",
    "Rule",
    "check",
    "file_names",
    "friction_number",
    "renamed",
]

# fmt: off
#: Every renamed key of every file table: old name → (new name, its unit in words).
#: A rename applies in a table whose keys include the new name (``stroke`` is
#: ``stroke_m`` in a cam stop's table; a cam segment's stroke keys were always
#: ``stroke_m`` or ``stroke_deg``).
RENAMED: dict[str, tuple[str, str]] = {
    # a stop: a machine's cam_stop table, an impact file's [stop] and [study]
    "a_max": ("a_max_m", "metres"),
    "stroke": ("stroke_m", "metres"),
    "preload": ("preload_m", "metres"),
    "lever_length": ("lever_length_m", "metres"),
    "J_A": ("J_A_kg_m2", "kg·m²"),
    "a": ("a_m", "metres"),
    "b": ("b_m", "metres"),
    "E": ("E_pa", "pascals"),
    "J_x": ("J_x_m4", "m⁴"),
    "mass": ("mass_kg", "kilograms"),
    "contact_stiffness": ("contact_stiffness_n_per_m", "N/m"),
    "contact_time": ("contact_time_s", "seconds"),
    # a press: a machine's press table, a press file's [press], [working] and [sweep]
    "R": ("R_m", "metres"),
    "r": ("r_m", "metres"),
    "d": ("d_m", "metres"),
    "L": ("L_m", "metres"),
    "offset": ("offset_m", "metres"),
    "working_stroke": ("working_stroke_m", "metres"),
    "max_V_np": ("max_V_np_m_per_s", "m/s"),
    # a transfer
    "R_t": ("R_t_m", "metres"),
    "R_p": ("R_p_m", "metres"),
    "gap": ("gap_m", "metres"),
    "x2": ("x2_m", "metres"),
    "max_jerk": ("max_jerk_m_per_s3", "m/s³"),
    # a transfer and a linkage
    "max_acceleration": ("max_acceleration_m_per_s2", "m/s²"),
}
# fmt: on


def renamed(key: str, allowed: Iterable[str]) -> str | None:
    """The message for an old key name where its new one is allowed, else None.

    Parameters
    ----------
    key : str
        A key the table does not take.
    allowed : iterable of str
        The keys the table takes.

    Returns
    -------
    str or None
        ```a_max` is now `a_max_m` (metres)`` and what to do, or None if ``key`` is
        no old name of an allowed key.

    Examples
    --------
    >>> renamed("a_max", {"a_max_m", "arc"})
    '`a_max` is now `a_max_m` (metres): rename the key, the value stays'
    >>> renamed("a_max", {"arc"}) is None
    True
    """
    new = RENAMED.get(key)
    if new is None or new[0] not in set(allowed):
        return None
    return f"`{key}` is now `{new[0]}` ({new[1]}): rename the key, the value stays"


def file_names(message: str, params: Mapping[str, str]) -> str:
    """An error of a Python class with its parameters' names as a file's keys.

    The class (``StopImpact``, ``GearLeverPress``) names its parameters
    (``preload = …``, ``L must be …``); a file reader that passes its keys on
    rewrites them so the message names the key the user wrote. A name is
    replaced where it is followed by ``=`` or ``must``.

    Parameters
    ----------
    message : str
        The class's message.
    params : Mapping of str to str
        File key → the parameter it sets (``{"preload_m": "preload"}``).

    Returns
    -------
    str
        The message naming the file's keys.

    Examples
    --------
    >>> file_names("preload = 0.02 m must be smaller than stroke = 0.01 m",
    ...            {"preload_m": "preload", "stroke_m": "stroke"})
    'preload_m = 0.02 m must be smaller than stroke_m = 0.01 m'
    """
    keys = {p: k for k, p in params.items() if k != p}
    if not keys:
        return message
    names = "|".join(re.escape(p) for p in sorted(keys, key=len, reverse=True))
    pattern = rf"(?<![\w.])({names})\b(?=\s*(?:=|must\b))"
    return re.sub(pattern, lambda m: keys[m.group(1)], message)


@dataclass(frozen=True)
class Rule:
    """A plausibility rule on one key of a table.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    key : str
        The key (a number); a table without it is not checked.
    fails : callable
        ``fails(value, table)``: True when the value is implausible (``table``, the
        whole table, for rules against another key).
    why : callable
        ``why(value, table)``: what is wrong and the likely slip, after
        ``<key> = <value>``.
    error : bool, default False
        The value cannot be meant (an :class:`~cyclomech.InputError`); else it is
        unusual (a :class:`~cyclomech.CyclomechWarning`).

    Examples
    --------
    >>> r = Rule("zeta", lambda v, t: v >= 1,
    ...          lambda v, t: f"is overdamped — did you mean {v / 100:g}?")
    >>> r.message(5, {}, "f.toml: [stop]")
    'f.toml: [stop]: zeta = 5 is overdamped — did you mean 0.05?'
    """

    key: str
    fails: Callable[[float, Mapping[str, Any]], bool]
    why: Callable[[float, Mapping[str, Any]], str]
    error: bool = False

    def message(self, value: float, table: Mapping[str, Any], where: str) -> str:
        """The message naming the place, the key, the value and the slip.

        Parameters
        ----------
        value : float
            The key's value.
        table : Mapping of str to Any
            The whole table.
        where : str
            The file and table (``loom.toml: [mechanism.lifter]``).

        Returns
        -------
        str
            ``<where>: <key> = <value> <why>``.

        Examples
        --------
        >>> Rule("x_m", lambda v, t: v > 10, lambda v, t: "is long").message(20, {}, "f")
        'f: x_m = 20 is long'
        """
        return f"{where}: {self.key} = {value!r} {self.why(value, table)}"


def _number(v: Any) -> TypeGuard[float]:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


#: The largest length [m] a key ending ``_m`` plausibly means: cyclomech's
#: mechanisms are bench-sized; 20 is far more likely 20 mm than 20 m.
LONGEST_M = 10.0
#: The smallest angle [deg] a key ending ``_deg`` plausibly means (besides 0): a
#: hundredth of a degree; smaller is likelier an angle in radians.
SMALLEST_DEG = 1e-2
#: The smallest stress or modulus [Pa] a key ending ``_pa`` plausibly means: 1 MPa;
#: smaller is likelier MPa or GPa.
SMALLEST_PA = 1e6

#: The rules every key follows by its unit suffix: (suffix, rule for a key ``k``).
SUFFIX_RULES: tuple[tuple[str, Callable[[str], Rule]], ...] = (
    ("_m", lambda k: Rule(
        k, lambda v, t: abs(v) > LONGEST_M,
        lambda v, t: f"m is over {LONGEST_M:g} m — did you mean millimetres "
                     f"({k} = {v / 1000:g})?")),
    ("_deg", lambda k: Rule(
        k, lambda v, t: 0 < abs(v) < SMALLEST_DEG,
        lambda v, t: f"° is under {SMALLEST_DEG:g}° — did you give radians "
                     f"({k} = {math.degrees(v):.4g} if so)?")),
    ("_pa", lambda k: Rule(
        k, lambda v, t: 0 < abs(v) < SMALLEST_PA,
        lambda v, t: f"Pa is under {SMALLEST_PA:g} Pa (1 MPa) — did you give MPa "
                     f"({k} = {v * 1e6:g}) or GPa ({k} = {v * 1e9:g})?")),
)  # fmt: skip


def check(table: Mapping[str, Any], rules: Iterable[Rule], where: str) -> None:
    """Apply ``rules`` and :data:`SUFFIX_RULES` to the numbers of ``table``, and
    :func:`radian_table` to its ``_deg`` arrays.

    Run after the table's own checks (a value of the wrong type or range is their
    error); a key a rule names but the table lacks, or whose value is no finite
    number, is skipped.

    Parameters
    ----------
    table : Mapping of str to Any
        The table as read (with what it takes from elsewhere: a cam stop's stroke
        from its cam).
    rules : iterable of Rule
        The table's own rules (its kind's ``rules``).
    where : str
        The file and table, for messages.

    Raises
    ------
    InputError
        On the first rule with ``error`` that fails.

    Warns
    -----
    CyclomechWarning
        For each other rule that fails (at most one per key).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     check({"lever_length_m": 100.0}, (), "f.toml: [stop]")
    >>> print(caught[0].message)  # doctest: +NORMALIZE_WHITESPACE
    f.toml: [stop]: lever_length_m = 100.0 m is over 10 m — did you mean millimetres
    (lever_length_m = 0.1)?
    """
    own = tuple(rules)
    warned: set[str] = set()
    pending: list[str] = []
    # By the unit's last word: ``contact_stiffness_n_per_m`` is no length.
    suffixed = [
        make(k)
        for k in table
        for suffix, make in SUFFIX_RULES
        if k.endswith(suffix) and not k.endswith("_per" + suffix)
    ]
    # Errors first: a value that cannot be meant stops the file before any warning.
    for rule in sorted((*own, *suffixed), key=lambda r: not r.error):
        v = table.get(rule.key)
        if not _number(v) or rule.key in warned or not rule.fails(v, table):
            continue
        if rule.error:
            raise InputError(rule.message(v, table, where))
        warned.add(rule.key)
        pending.append(rule.message(v, table, where))
    pending.extend(
        msg
        for k, v in table.items()
        if k.endswith("_deg") and not k.endswith("_per_deg") and k not in warned
        for msg in [radian_table(k, v, where)]
        if msg
    )
    for msg in pending:
        warnings.warn(msg, CyclomechWarning, stacklevel=3)


#: One turn [rad]: an angle table (a ``_deg`` key's array, or a column of its rows)
#: whose values all lie within ±this and span no more than it is likelier radians.
TURN_RAD = 2.0 * math.pi


def radian_table(key: str, value: Any, where: str) -> str:
    """The warning for a ``_deg`` array that looks like radians, or "".

    An array of numbers (a flat list, or the first column of a list of rows: the
    angle along the cycle or the crank's) with at least two distinct values, all
    within ±2π and spanning at most 2π (:data:`TURN_RAD`), is likelier radians: the
    angle tables cyclomech reads (a load table over the crank angle, a spline's
    points, precision points, a phase grid) span tens of degrees there. A row's
    other columns are values (an arm's or a rotary axis's swing, an output angle),
    which may well span a few degrees, and are not judged. Other values, and
    anything not a list of finite numbers, give "".

    Parameters
    ----------
    key : str
        The key (ending ``_deg``).
    value : Any
        Its value as read.
    where : str
        The file and table (``knife.toml: [mechanism.knife] load #1``).

    Returns
    -------
    str
        The message naming the place, the key and the values, or "".

    Examples
    --------
    >>> radian_table("angle_deg", [2.443, 2.618, 4.363], "f.toml: [m] load #1")[-35:]
    '9.9736, 150.0004, 249.9815] if so)?'
    >>> radian_table("angle_deg", [140.0, 150.0, 250.0], "f")
    ''
    """
    if not isinstance(value, list) or len(value) < 2:
        return ""
    rows = value if all(isinstance(r, list) for r in value) else [[x] for x in value]
    width = {len(r) for r in rows}
    if len(width) != 1 or not all(_number(x) for r in rows for x in r):
        return ""
    for c in range(min(1, width.pop())):
        col = [float(r[c]) for r in rows]
        lo, hi = min(col), max(col)
        if lo < hi and lo >= -TURN_RAD and hi <= TURN_RAD and hi - lo <= TURN_RAD:
            flat = not isinstance(value[0], list)
            which = "" if flat else f" (column {c + 1})"
            deg = [[round(math.degrees(float(x)), 4) for x in r] for r in rows]
            shown = [d[0] for d in deg] if flat else deg
            return (
                f"{where}: {key} = {value!r}{which} spans only {hi - lo:.4g}°, every value "
                f"within ±2π — did you give radians ({key} = {shown} if so)?"
            )
    return ""


#: A friction coefficient above this is taken but warned about: lubricated metal
#: pairs are 0.05–0.2, dry steel on steel up to about 0.5.
MU_PLAUSIBLE = 0.5


def friction_number(spec: Mapping[str, Any], key: str, at: str, unit: str) -> float:
    """The number ``spec[key]`` of a ``friction`` table (a linkage's, a cam's, a
    press's), finite and ≥ 0, the message naming ``at`` and the key; a friction
    coefficient (a key ending in ``mu``) above :data:`MU_PLAUSIBLE` warns, naming the
    likely slip (a percentage, the friction angle's degrees).

    >>> friction_number({"pin_mu": 0.08}, "pin_mu", "[m.friction]", "")
    0.08
    """
    v = spec[key]
    if isinstance(v, bool) or not isinstance(v, int | float):
        raise InputError(f"{at}: {key} = {v!r} must be a number ≥ 0 {unit}".rstrip())
    what = "a friction coefficient (lubricated bronze on steel 0.05–0.1)" if "mu" in key else ""
    try:
        x = finite_number(f"{at}: {key}", v, unit, low=0.0)
    except InputError as e:
        raise InputError(f"{str(e).rstrip()}{'; ' + what if what else ''}") from None
    if key.endswith("mu") and x > MU_PLAUSIBLE:
        warnings.warn(
            f"{at}: {key} = {x:g} is above {MU_PLAUSIBLE:g}: lubricated metal pairs are "
            "0.05–0.2 and dry steel on steel at most about 0.5 — did you give a percentage "
            f"({key} = {x / 100:g}) or the friction angle's degrees?",
            CyclomechWarning,
            stacklevel=4,
        )
    return x
