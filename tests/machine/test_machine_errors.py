"""A malformed machine file, one mistake at a time: every mistake is an
``InputError`` (a ``CyclomechError`` and a ``ValueError``) whose message names the
file, the table and the key, and what would be valid; a mistyped key is an error,
not ignored. Each case starts from the text of an example file and makes one
mistake in it. The same for the API that edits a machine (``with_values``,
``sweep``) and for the command line.

A case marked ``xfail(strict=True, reason="BUG: …")`` is a message that misses
one of these; it passes once the parser is fixed, and the mark must then go."""

from __future__ import annotations

import re
import tomllib
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _toml
from cyclomech.cli import main
from cyclomech.machine import dask_client, parse_range

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
# The loom before its lifter cam (issue 18): its cam stop gives law and stroke itself,
# so the stop's key errors are tested on it; test_machine_cams.py tests the cam's.
LOOM = ROOT / "tests" / "machine" / "data" / "stb_loom_stop_only.toml"


def example_path(name: str) -> Path:
    """The file a case starts from: an example, the loom as LOOM."""
    return LOOM if name == "stb_loom" else EXAMPLES / f"{name}.toml"


Edit = Callable[[str, Path], None]
Hint = str | tuple[str, ...]
DELETE = object()


# --------------------------------------------------------------------- writing files
def dump(data: Mapping[str, Any]) -> str:
    """The parsed layout as TOML text: tables as ``[a.b]``, arrays of tables as
    ``[[a]]``, everything else as ``key = value``."""
    lines: list[str] = []

    def aot(v: Any) -> bool:
        return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)

    def emit(path: tuple[str, ...], table: Mapping[str, Any], header: str) -> None:
        if path:
            name = ".".join(_toml.key(k) for k in path)
            lines.extend(["", header.format(name)])
        for k, v in table.items():
            if not isinstance(v, Mapping) and not aot(v):
                lines.append(f"{_toml.key(k)} = {_toml.value(v)}")
        for k, v in table.items():
            if isinstance(v, Mapping):
                emit((*path, k), v, "[{}]")
            elif aot(v):
                for item in v:
                    emit((*path, k), item, "[[{}]]")

    emit((), data, "")
    return "\n".join(lines) + "\n"


def replace(old: str, new: str) -> Edit:
    """Replace the one occurrence of ``old`` in the example's text."""

    def edit(text: str, path: Path) -> None:
        assert text.count(old) == 1, f"{old!r} occurs {text.count(old)} times"
        path.write_text(text.replace(old, new), encoding="utf-8")

    return edit


def _walk(data: Any, where: str) -> tuple[Any, Any]:
    """The container and the key or index a dotted path names; a number is the
    1-based index into an array of tables (as ``[[operation]] #3`` counts)."""
    parts = where.split(".")
    node = data
    for p in parts[:-1]:
        node = node[int(p) - 1] if p.isdigit() else node[p]
    last = parts[-1]
    return node, (int(last) - 1 if last.isdigit() else last)


def setting(**changes: Any) -> Edit:
    """Parse the example, set (or with ``DELETE`` remove) keys given as dotted
    paths with ``__`` for the dots, write it back."""

    def edit(text: str, path: Path) -> None:
        data = tomllib.loads(text)
        for where, value in changes.items():
            node, key = _walk(data, where.replace("__", "."))
            if value is DELETE:
                del node[key]
            else:
                node[key] = value
        path.write_text(dump(data), encoding="utf-8")

    return edit


def appending(where: str, item: Any) -> Edit:
    """Parse the example, append ``item`` to the array at ``where`` (made if absent)."""

    def edit(text: str, path: Path) -> None:
        data = tomllib.loads(text)
        node, key = _walk(data, where)
        node.setdefault(key, []).append(item)
        path.write_text(dump(data), encoding="utf-8")

    return edit


def raw(content: bytes) -> Edit:
    def edit(text: str, path: Path) -> None:
        path.write_bytes(content)

    return edit


def not_utf8(text: str, path: Path) -> None:
    path.write_bytes(text.encode().replace(b"ILLUSTRATIVE", b"ILLUSTRATIVE \xff\xfe", 1))


def unchanged(text: str, path: Path) -> None:
    path.write_text(text, encoding="utf-8")


def no_file(text: str, path: Path) -> None:
    pass


def a_directory(text: str, path: Path) -> None:
    path.mkdir()


def with_bom(text: str, path: Path) -> None:
    path.write_bytes(b"\xef\xbb\xbf" + text.encode())


# --------------------------------------------------------------------- checking
def caught(call: Callable[[], Any]) -> BaseException:
    """What ``call`` raises: any exception, a Rust panic too (no ``Exception``)."""
    try:
        call()
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as e:
        return e
    pytest.fail("no error: the mistake was accepted")


def check(
    err: BaseException,
    exc: type[BaseException],
    path: Path | str | None,
    table: str | None,
    key: str | None,
    hints: tuple[Hint, ...],
) -> None:
    """``err`` is an ``exc`` (a CyclomechError, a ValueError) whose message names
    ``path`` once, ``table``, ``key`` (as a word) and each of ``hints`` (a tuple:
    one of its wordings); None: not checked. Table, key and hints are looked for
    outside the file's name."""
    msg = str(err)
    assert isinstance(err, exc), f"{type(err).__name__}: {msg}"
    assert isinstance(err, cm.CyclomechError) and isinstance(err, ValueError)
    rest = msg
    if path is not None:
        # Once as the place; a command to run it with (in backticks) may repeat it.
        bare = re.sub(r"`[^`]*`", "", msg)
        assert bare.count(str(path)) == 1, f"the file {path} not named once in: {msg}"
        rest = msg.replace(str(path), "<file>")
    if table is not None:
        assert table in rest, f"table {table!r} not in: {msg}"
    if key is not None:
        assert re.search(rf"(?<!\w){re.escape(key)}(?!\w)", rest), f"key {key!r} not in: {msg}"
    missing = [h for h in hints if not any(w in rest for w in ((h,) if isinstance(h, str) else h))]
    assert not missing, f"hints {missing} not in: {msg}"


# --------------------------------------------------------------------- the cases
def case(
    id: str,
    example: str,
    edit: Edit,
    table: str | None,
    key: str | None,
    *hints: Hint,
    exc: type[BaseException] = cm.InputError,
    bug: str | None = None,
) -> Any:
    """One mistake in ``example``: the message must name the file, ``table``,
    ``key`` and hold each of ``hints`` (None: not applicable); ``bug`` marks a
    known shortfall (strict xfail)."""
    marks = [pytest.mark.xfail(strict=True, reason=f"BUG: {bug}")] if bug else []
    return pytest.param(example, edit, table, key, hints, exc, id=id, marks=marks)


def _in(mechanism: str) -> Callable[..., Edit]:
    def edit(**changes: Any) -> Edit:
        return setting(**{f"mechanism__{mechanism}__{k}": v for k, v in changes.items()})

    return edit


lifter, drive, line, knife = _in("lifter"), _in("drive"), _in("line"), _in("knife")
LIFTER, DRIVE, LINE, KNIFE = (f"[mechanism.{k}]" for k in ("lifter", "drive", "line", "knife"))
#: The kinds a refused ``kind`` lists: the registry, in its order (found, not typed).
KINDS = ", ".join(cm.machine.KINDS)
VALID = "valid keys are"
SPEED_RANGE = "0 < from < to"
STRING_NUMBER = "a string where a number belongs is taken as the number (float(value))"


def constraint(**changes: Any) -> Edit:
    """The loom with one [[constraint]] t(3, 7) ≥ 30, changed by ``changes``."""
    con: dict[str, Any] = {
        "terms": [{"from": "3", "to": "7", "coeff": 1.0}],
        "sense": ">=",
        "rhs": 30.0,
    }
    for k, v in changes.items():
        if v is DELETE:
            del con[k]
        else:
            con[k] = v
    return appending("constraint", con)


FOUR_BAR_NOT_A_CRANK = {
    "kind": "linkage",
    "links": [["A", "B"], ["B", "C"], ["C", "D"]],
    "ground": ["A", "D"],
    "driver": ["A", "B"],
    "output": "C",
    # crank 0.3, coupler 0.3, rocker 0.32, frame 0.4: s + l > p + q (not Grashof),
    # so the crank cannot turn a whole revolution.
    "points": {"A": [0.0, 0.0], "B": [0.0, 0.3], "C": [0.3, 0.3], "D": [0.4, 0.0]},
}
KNIFE_LINKS = [["A", "B"], ["D", "C"], ["B", "C", "E"], ["E", "F"], ["O", "F"]]

FILE_CASES = [
    case("not TOML", "stb_loom", replace("[machine]\n", "[machine\n"), None, None,
         "not valid TOML", "line 20"),
    case("not UTF-8", "stb_loom", not_utf8, None, None, "UTF-8"),
    case("missing file", "stb_loom", no_file, None, None, "no such file"),
    case("a directory", "stb_loom", a_directory, None, None, "directory"),
    case("empty file", "stb_loom", raw(b""), "[machine]", None, "speed_rpm"),
    case("an impact file", "stb_lifter", unchanged, None, None, "[machine]", "cyclomech impact"),
    case("a linkage file", "burg_trimmer", unchanged, None, None, "cyclomech linkage"),
    case("a cyclogram file", "stb_group1", unchanged, None, None, "cyclomech cyclogram"),
    case("a press file", "extrusion_press", unchanged, None, None, "cyclomech press"),
    case("a key twice", "rotor_line", replace("gap_m = 0.01", "gap_m = 0.01\ngap_m = 0.02"), None,
         None, "not valid TOML", "line 31"),
]  # fmt: skip

TOP_CASES = [
    case("unknown top-level table", "stb_loom",
         replace("[mechanism.lifter]", "[mechanisms.lifter]"), "top level", "mechanisms",
         VALID, "balance, constraint, cyclogram, drive, machine, mechanism, operation"),
    case("top-level key", "rotor_line", replace("[machine]", "speed = 3\n[machine]"),
         "top level", "speed", VALID),
    case("missing [machine]", "stb_loom", setting(machine=DELETE), "[machine]", None,
         "speed_rpm"),
    case("[machine] not a table", "stb_loom", setting(machine=5), "[machine]", None,
         "must be a table"),
    case("speed_rmp", "stb_loom", replace("speed_rpm =", "speed_rmp ="), "[machine]",
         "speed_rmp", VALID, "speed_rpm"),
    case("nominal_rmp", "knife_cutter", replace("nominal_rpm =", "nominal_rmp ="),
         "[machine]", "nominal_rmp", VALID, "nominal_rpm"),
    case("speed_rpm missing", "stb_loom", setting(machine__speed_rpm=DELETE), "[machine]",
         "speed_rpm", SPEED_RANGE),
    case("speed_rpm one number", "stb_loom", setting(machine__speed_rpm=300.0), "[machine]",
         "speed_rpm", SPEED_RANGE),
    case("speed_rpm three numbers", "stb_loom",
         setting(machine__speed_rpm=[200.0, 300.0, 500.0]), "[machine]", "speed_rpm",
         SPEED_RANGE),
    case("speed_rpm reversed", "stb_loom", setting(machine__speed_rpm=[500.0, 200.0]),
         "[machine]", "speed_rpm", SPEED_RANGE),
    case("speed_rpm negative", "stb_loom", setting(machine__speed_rpm=[-100.0, 200.0]),
         "[machine]", "speed_rpm", SPEED_RANGE),
    case("speed_rpm above the cap", "rotor_line", setting(machine__speed_rpm=[1.0, 1e7]),
         "[machine]", "speed_rpm", "1e+06"),
    case("speed_rpm nan", "stb_loom", replace("[200.0, 500.0]", "[nan, 500.0]"), "[machine]",
         "speed_rpm", SPEED_RANGE),
    case("speed_rpm inf", "stb_loom", replace("[200.0, 500.0]", "[200.0, inf]"), "[machine]",
         "speed_rpm", SPEED_RANGE),
    case("speed_rpm strings", "stb_loom", replace("[200.0, 500.0]", '["200", "500"]'),
         "[machine]", "speed_rpm", SPEED_RANGE),
    case("speed_points 1", "stb_loom", setting(machine__speed_points=1), "[machine]",
         "speed_points", "from 2 to 1000000"),
    case("speed_points 0", "stb_loom", setting(machine__speed_points=0), "[machine]",
         "speed_points", "from 2 to 1000000"),
    case("speed_points 2.5", "stb_loom", setting(machine__speed_points=2.5), "[machine]",
         "speed_points", "whole number"),
    case("speed_points true", "stb_loom", setting(machine__speed_points=True), "[machine]",
         "speed_points", "whole number"),
    case("angle_points 4", "stb_loom", setting(machine__angle_points=4), "[machine]",
         "angle_points", "from 9 to 1000000"),
    case("angle_points a string", "rotor_line", setting(machine__angle_points="361"),
         "[machine]", "angle_points", "whole number"),
    case("nominal_rpm negative", "stb_loom", setting(machine__nominal_rpm=-300.0),
         "[machine]", "nominal_rpm", "0 < nominal_rpm"),
    case("nominal_rpm inf", "stb_loom", replace("nominal_rpm = 300.0", "nominal_rpm = inf"),
         "[machine]", "nominal_rpm", "0 < nominal_rpm"),
    case("nominal_rpm a string", "stb_loom", setting(machine__nominal_rpm="300"),
         "[machine]", "nominal_rpm", "0 < nominal_rpm"),
    case("name a number", "stb_loom", setting(machine__name=5), "[machine]", "name",
         "string"),
    case("[mechanism] not a table", "rotor_line", setting(mechanism=5), "[mechanism]", None,
         "[mechanism.<name>]"),
]  # fmt: skip

CYCLOGRAM_CASES = [
    case("missing [cyclogram]", "stb_loom", setting(cyclogram=DELETE), "[cyclogram]", None,
         "[[operation]]"),
    case("missing [[operation]]", "rotor_line", setting(operation=DELETE), "[[operation]]",
         None, "[cyclogram]"),
    case("operation not an array", "rotor_line", setting(operation=5), "[[operation]]",
         "operation"),
    case("operation not a table", "rotor_line", setting(operation=[5]), "[[operation]] #1",
         None, "must be a table"),
    case("speed_rpm in [cyclogram]", "stb_loom", setting(cyclogram__speed_rpm=300.0),
         "[cyclogram]", "speed_rpm", "[machine]"),
    case("limiting missing", "stb_loom", setting(cyclogram__limiting=DELETE), "[cyclogram]",
         "limiting", "limiting = ["),
    case("limiting not an operation", "stb_loom", setting(cyclogram__limiting=["1", "10.2"]),
         "[cyclogram]", "limiting", ("10.1", "weft insertion")),
    case("limiting one event", "rotor_line", setting(cyclogram__limiting="clamped"),
         "[cyclogram]", "limiting", "'process'"),
    case("cycle_deg 0", "rotor_line", setting(cyclogram__cycle_deg=0.0), "[cyclogram]",
         "cycle_deg", "positive"),
    case("cycle_deg a string", "rotor_line", setting(cyclogram__cycle_deg="360"),
         "[cyclogram]", "cycle_deg"),
    case("limitting", "rotor_line", setting(cyclogram__limitting=["a", "b"]),
         "[cyclogram]", "limitting", VALID, "limiting"),
    case("events not an array", "stb_loom", setting(cyclogram__events="1,2"),
         "[cyclogram]", "events", "array"),
    case("min_angel_deg", "stb_loom", setting(operation__2__min_angel_deg=20.0),
         "[[operation]] #2", "min_angel_deg", VALID, "min_angle_deg"),
    case("min_angle_deg nan", "rotor_line",
         replace("min_angle_deg = 30.0", "min_angle_deg = nan"), "[[operation]] #3",
         "min_angle_deg", "finite"),
    case("min_angle_deg a string", "rotor_line", setting(operation__3__min_angle_deg="30"),
         "[[operation]] #3", "min_angle_deg"),
    case("max_angle_deg below min", "stb_loom", setting(operation__6__max_angle_deg=50.0),
         "[[operation]] #6", "max_angle_deg", "min_angle_deg"),
    case("min_duration_s negative", "rotor_line", setting(operation__2__min_duration_s=-0.1),
         "[[operation]] #2", "min_duration_s", ">= 0"),
    case("min_duration_s a string", "stb_loom", setting(operation__11__min_duration_s="0.1"),
         "[[operation]] #11", "min_duration_s"),
    case("missing to", "stb_loom", setting(operation__3__to=DELETE), "[[operation]] #3",
         "to", "missing"),
    case("from not an event", "stb_loom", setting(operation__1__from="0"),
         "[[operation]] #1", "from", "'10.2'"),
    case("from a number", "rotor_line", setting(operation__1__from=3.5), "[[operation]] #1",
         "from", "string"),
    case("from = to", "rotor_line", setting(operation__1__to="arrive"), "[[operation]] #1",
         "arrive", "two different events"),
    case("height 1.5", "extrusion_press_line", setting(operation__5__height=1.5),
         "[[operation]] #5", "height", "non-negative integer"),
    case("height -1", "extrusion_press_line", setting(operation__5__height=-1),
         "[[operation]] #5", "height", "non-negative integer"),
    case("operation twice", "rotor_line",
         appending("operation", {"from": "arrive", "to": "clamped", "min_angle_deg": 10.0}),
         "[[operation]] #5", "arrive", "already exists"),
    case("constraint sense =>", "stb_loom", constraint(sense="=>"), "[[constraint]] #1",
         "sense", "'<='", "'>='", "'=='"),
    case("constraint term not an operation", "stb_loom",
         constraint(terms=[{"from": "3", "to": "8", "coeff": 1.0}]), "[[constraint]] #1",
         "3→8", "10.1→10.2"),
    case("constraint rsh", "stb_loom", constraint(rhs=DELETE, rsh=30.0), "[[constraint]] #1",
         "rsh", VALID, "rhs"),
    case("constraint cof", "stb_loom", constraint(terms=[{"from": "3", "to": "7", "cof": 1}]),
         "[[constraint]] #1", "cof", VALID, "coeff"),
    case("constraint without sense", "stb_loom", constraint(sense=DELETE),
         "[[constraint]] #1", "sense", "missing"),
    case("constraint terms not an array", "stb_loom", constraint(terms=5),
         "[[constraint]] #1", "terms", "{from, to, coeff}"),
    case("constraint rhs nan", "stb_loom", constraint(rhs=float("nan")), "[[constraint]] #1",
         "rhs", "finite"),
    case("constraint rhs a string", "stb_loom", constraint(rhs="30"), "[[constraint]] #1",
         "rhs"),
    case("constraint coeff a string", "stb_loom",
         constraint(terms=[{"from": "3", "to": "7", "coeff": "1"}]), "[[constraint]] #1",
         "coeff"),
]  # fmt: skip

MECHANISM_CASES = [
    # its kind
    case("no kind", "stb_loom", lifter(kind=DELETE), LIFTER, "kind", KINDS),
    case("unknown kind", "stb_loom", lifter(kind="camshaft"), LIFTER, "kind", KINDS),
    case("kind capitalised", "extrusion_press_line", drive(kind="Press"), DRIVE, "kind",
         KINDS),
    case("mechanism not a table", "stb_loom", setting(mechanism__lifter=5), LIFTER, None,
         "must be a table"),
    # a mistyped key, for each kind
    case("cam_stop prelod", "stb_loom", replace("preload_m =", "prelod_m ="), LIFTER,
         "prelod_m", VALID, "preload_m"),
    case("press phi0", "extrusion_press_line", replace("phi0_deg =", "phi0 ="), DRIVE,
         "phi0", VALID, "phi0_deg"),
    case("transfer pocket_t", "rotor_line", replace("pockets_t =", "pocket_t ="), LINE,
         "pocket_t", VALID, "pockets_t"),
    case("linkage grund", "knife_cutter", replace("ground =", "grund ="), KNIFE, "grund",
         VALID, "ground"),
    case("linkage max_acceleraton", "knife_cutter",
         replace("max_acceleration_m_per_s2 =", "max_acceleraton_m_per_s2 ="), KNIFE,
         "max_acceleraton_m_per_s2", VALID,
         "max_acceleration"),
    case("linkage lengths lenght", "knife_cutter",
         setting(mechanism__knife__lengths__1__lenght=0.4,
                 mechanism__knife__lengths__1__length=DELETE),
         KNIFE, "lenght", VALID, "length"),
    # a missing key, for each kind
    case("cam_stop no stroke", "stb_loom", lifter(stroke_m=DELETE), LIFTER, "stroke_m",
         "missing"),
    case("cam_stop no arc", "stb_loom", lifter(arc=DELETE), LIFTER, "arc", "missing"),
    case("cam_stop no a_max", "stb_loom", lifter(a_max_m=DELETE), LIFTER, "a_max_m", "missing"),
    case("press no L", "extrusion_press_line", drive(L_m=DELETE), DRIVE, "L_m", "missing"),
    case("press no phi0_deg", "extrusion_press_line", drive(phi0_deg=DELETE), DRIVE,
         "phi0_deg", "missing"),
    case("transfer no gap", "rotor_line", line(gap_m=DELETE), LINE, "gap_m", "missing"),
    case("transfer no pockets_p", "rotor_line", line(pockets_p=DELETE), LINE, "pockets_p",
         "missing"),
    case("linkage no driver", "knife_cutter", knife(driver=DELETE), KNIFE, "driver",
         "missing"),
    case("linkage no points", "knife_cutter", knife(points=DELETE), KNIFE, "points",
         "missing"),
    case("linkage lengths without length", "knife_cutter",
         setting(mechanism__knife__lengths__1__length=DELETE), KNIFE, "lengths",
         "must be a length"),
    # not a number: strings, booleans
    case("cam_stop stroke a string", "stb_loom", lifter(stroke_m="0.0094"), LIFTER, "stroke_m",
         "number"),
    case("cam_stop E true", "stb_loom", lifter(E_pa=True), LIFTER, "E_pa", "number"),
    case("cam_stop law a number", "stb_loom", lifter(law=5), LIFTER, "law", "string"),
    case("cam_stop unknown law", "stb_loom", lifter(law="modified_sinus"), LIFTER, "law",
         "modified_sine", "cycloidal"),
    case("cam_stop unknown pulse", "stb_loom", lifter(pulse="square"), LIFTER, "pulse",
         "rectangular"),
    case("cam_stop unknown model", "stb_loom", lifter(model="fem"), LIFTER, "model",
         "'contact'"),
    case("press R a string", "extrusion_press_line", drive(R_m="0.09"), DRIVE, "R_m", "number"),
    case("press k_Sp true", "extrusion_press_line", drive(k_Sp=True), DRIVE, "k_Sp",
         "number"),
    case("press offset a string", "extrusion_press_line", drive(offset_m="x"), DRIVE,
         "offset_m", "number"),
    case("transfer R_t true", "rotor_line", line(R_t_m=True), LINE, "R_t_m", "number"),
    case("transfer pockets 8.5", "rotor_line", line(pockets_t=8.5), LINE, "pockets_t",
         "whole number"),
    case("transfer pockets true", "rotor_line", line(pockets_t=True), LINE, "pockets_t",
         "whole number"),
    case("transfer x2 a string", "rotor_line", line(x2_m="a"), LINE, "x2_m", "number"),
    case("linkage limit a string", "knife_cutter", knife(max_acceleration_m_per_s2="8"), KNIFE,
         "max_acceleration_m_per_s2", "number"),
    case("linkage point a word", "knife_cutter", knife(points__A=["zero", 0.0]), KNIFE,
         "points", "'A'", "(x, y)"),
    case("linkage point one coordinate", "knife_cutter", knife(points__A=[0.0]), KNIFE,
         "points", "'A'", "(x, y)"),
    case("linkage point a string", "knife_cutter", knife(points__A=["0", 0.0]), KNIFE,
         "points", "'A'", "(x, y)"),
    case("linkage length a string", "knife_cutter", knife(lengths__1__length="0.425"), KNIFE,
         "lengths"),
    case("linkage lengths not an array", "knife_cutter", knife(lengths=5), KNIFE, "lengths"),
    case("linkage sliders not a table", "knife_cutter", knife(sliders=5), KNIFE, "sliders"),
    case("linkage name a number", "knife_cutter", knife(name=5), KNIFE, "name", "string"),
    # NaN and inf
    case("cam_stop stroke nan", "stb_loom", replace("stroke_m = 0.0094", "stroke_m = nan"),
         LIFTER, "stroke_m", "finite"),
    case("cam_stop J_x inf", "stb_loom", replace("J_x_m4 = 6.14e-11", "J_x_m4 = inf"), LIFTER,
         "J_x_m4", "finite"),
    case("cam_stop a_max inf", "stb_loom", replace("a_max_m = 1e-4", "a_max_m = inf"), LIFTER,
         "a_max_m", "finite"),
    case("cam_stop contact_stiffness nan", "stb_loom",
         lifter(contact_stiffness_n_per_m=float("nan")), LIFTER, "contact_stiffness_n_per_m",
         "finite"),
    case("press d nan", "extrusion_press_line", replace("d_m = 0.029", "d_m = nan"), DRIVE, "d_m",
         "finite"),
    case("press phi0_deg nan", "extrusion_press_line", drive(phi0_deg=float("nan")), DRIVE,
         "phi0_deg", "finite"),
    case("transfer gap inf", "rotor_line", replace("gap_m = 0.01", "gap_m = inf"), LINE, "gap_m",
         "finite"),
    case("transfer R_t nan", "rotor_line", line(R_t_m=float("nan")), LINE, "R_t_m", "finite"),
    case("linkage limit nan", "knife_cutter",
         replace("max_acceleration_m_per_s2 = 8.0", "max_acceleration_m_per_s2 = nan"), KNIFE,
         "max_acceleration_m_per_s2", "finite"),
    case("linkage point nan", "knife_cutter", replace("F = [-0.082,", "F = [nan,"), KNIFE,
         "'F'", "finite"),
    case("linkage length nan", "knife_cutter", knife(lengths__1__length=float("nan")),
         KNIFE, "lengths", "positive length"),
    # zero or negative where it must be positive
    case("cam_stop stroke 0", "stb_loom", lifter(stroke_m=0.0), LIFTER, "stroke_m", "> 0"),
    case("cam_stop stroke negative", "stb_loom", lifter(stroke_m=-0.0094), LIFTER, "stroke_m",
         "> 0"),
    case("cam_stop E 0", "stb_loom", lifter(E_pa=0.0), LIFTER, "E_pa", "> 0"),
    case("cam_stop lever_length negative", "stb_loom", lifter(lever_length_m=-0.1), LIFTER,
         "lever_length_m", "> 0"),
    case("cam_stop mass 0", "stb_loom", lifter(mass_kg=0.0), LIFTER, "mass_kg", "> 0"),
    case("cam_stop preload negative", "stb_loom", lifter(preload_m=-1e-4), LIFTER, "preload_m",
         "≥ 0"),
    case("cam_stop a_max 0", "stb_loom", lifter(a_max_m=0.0), LIFTER, "a_max_m", "positive"),
    case("cam_stop a_max negative", "stb_loom", lifter(a_max_m=-1e-4), LIFTER, "a_max_m",
         "positive"),
    case("cam_stop zeta negative", "stb_loom", lifter(zeta=-0.1), LIFTER, "zeta", "≥ 0"),
    case("cam_stop restitution 1.5", "stb_loom", lifter(restitution=1.5), LIFTER,
         "restitution", "[0, 1]"),
    case("press R 0", "extrusion_press_line", drive(R_m=0.0), DRIVE, "R_m", "exceed r"),
    case("press R negative", "extrusion_press_line", drive(R_m=-0.09), DRIVE, "R_m", "exceed r"),
    case("press r above R", "extrusion_press_line", drive(r_m=0.2), DRIVE, "r_m", "exceed r"),
    case("press r 0", "extrusion_press_line", drive(r_m=0.0), DRIVE, "r_m", "positive"),
    case("press d negative", "extrusion_press_line", drive(d_m=-0.028), DRIVE, "d_m", "≥ 0"),
    case("press L 0", "extrusion_press_line", drive(L_m=0.0), DRIVE, "L_m", "positive"),
    case("press max_V_np 0", "extrusion_press_line", drive(max_V_np_m_per_s=0.0), DRIVE,
         "max_V_np_m_per_s", "positive"),
    case("press working_stroke 0", "extrusion_press_line",
         drive(k_Sp=DELETE, working_stroke_m=0.0), DRIVE, "working_stroke_m", "must be positive"),
    case("press k_Sp 0", "extrusion_press_line", drive(k_Sp=0.0), DRIVE, "k_Sp", "(0, 1]"),
    case("press k_Sp 1.5", "extrusion_press_line", drive(k_Sp=1.5), DRIVE, "k_Sp",
         "(0, 1]"),
    case("transfer R_p negative", "rotor_line", line(R_p_m=-0.25), LINE, "R_p_m", "> 0"),
    case("transfer gap 0 (touching)", "rotor_line", line(gap_m=0.0), LINE, "gap_m", "positive"),
    case("transfer gap negative", "rotor_line", line(gap_m=-0.01), LINE, "gap_m", "positive"),
    case("transfer pockets 0", "rotor_line", line(pockets_p=0), LINE, "pockets_p", "≥ 1"),
    case("transfer x2 0", "rotor_line", line(x2_m=0.0), LINE, "x2_m", "> 0"),
    case("transfer max_jerk negative", "rotor_line", line(max_jerk_m_per_s3=-10.0), LINE,
         "max_jerk_m_per_s3",
         "positive"),
    case("linkage limit 0", "knife_cutter", knife(max_acceleration_m_per_s2=0.0), KNIFE,
         "max_acceleration_m_per_s2", "positive"),
    case("linkage length 0", "knife_cutter", knife(lengths__2__length=0.0), KNIFE,
         "lengths", "positive length"),
    # a cam stop's preload, arc and phase angles
    case("preload = stroke", "stb_loom", lifter(preload_m=0.0094), LIFTER, "preload_m",
         "smaller than stroke"),
    case("preload > stroke", "stb_loom", lifter(preload_m=0.02), LIFTER, "preload_m",
         "smaller than stroke"),
    case("arc not an operation", "stb_loom", lifter(arc=["3", "8"]), LIFTER, "arc",
         "['1', '3'], ['3', '7']"),
    case("arc one event", "stb_loom", lifter(arc="3"), LIFTER, "arc", "[from, to]"),
    case("arc numbers", "stb_loom", lifter(arc=[3, 7]), LIFTER, "arc", "[from, to]"),
    case("phase_deg two numbers", "stb_loom", lifter(phase_deg=[25.0, 55.0]), LIFTER,
         "phase_deg", "[from, to, count]"),
    case("phase_deg count 2.5", "stb_loom", lifter(phase_deg=[25.0, 55.0, 2.5]), LIFTER,
         "phase_deg", "whole count from 1 to 50"),
    case("phase_deg count 0", "stb_loom", lifter(phase_deg=[25.0, 55.0, 0]), LIFTER,
         "phase_deg", "whole count from 1 to 50"),
    case("phase_deg 400", "stb_loom", lifter(phase_deg=[25.0, 400.0, 4]), LIFTER,
         "phase_deg", "(0, 360]"),
    case("phase_deg a string", "stb_loom", lifter(phase_deg="25:55"), LIFTER, "phase_deg",
         "[from, to, count]"),
    # a press that cannot work
    case("press k_Sp and working_stroke", "extrusion_press_line",
         drive(working_stroke_m=0.01), DRIVE, "working_stroke_m", "k_Sp", "one of"),
    case("press neither k_Sp nor working_stroke", "extrusion_press_line", drive(k_Sp=DELETE),
         DRIVE, "working_stroke_m", "k_Sp", "one of"),
    case("press rod too short", "extrusion_press_line", drive(L_m=0.05), DRIVE, "L_m"),
    case("press offset too large", "extrusion_press_line", drive(offset_m=1.0), DRIVE,
         "offset_m"),
    case("press working_stroke above the stroke", "extrusion_press_line",
         drive(k_Sp=DELETE, working_stroke_m=1.0), DRIVE, "working_stroke_m", "nominal stroke"),
    # a transfer that cannot work
    case("transfer x2 too long for the gap", "rotor_line", line(x2_m=1.0), LINE, "x2_m",
         "too long"),
    # a linkage that cannot work
    case("linkage not a crank", "knife_cutter", setting(mechanism__knife=FOUR_BAR_NOT_A_CRANK),
         KNIFE, None, "cannot be assembled", "degrees"),
    case("linkage unknown point in links", "knife_cutter",
         knife(links=[*KNIFE_LINKS[:1], ["D", "X"], *KNIFE_LINKS[2:]]), KNIFE, "links",
         "'X'", "known points are A, D, O, B, C, E, F"),
    case("linkage links a string", "knife_cutter", knife(links="AB"), KNIFE, "links", "'AB'"),
    case("linkage a link short", "knife_cutter",
         knife(links=KNIFE_LINKS[:3] + KNIFE_LINKS[4:], lengths__6=DELETE), KNIFE, "links",
         "mobility", "add a link"),
    case("linkage unknown output", "knife_cutter", knife(output="Z"), KNIFE, "output",
         "'Z'", "A, D, O, B, C, E, F"),
    case("linkage unknown ground point", "knife_cutter", knife(ground=["A", "D", "Q"]),
         KNIFE, "ground", "'Q'", "A, D, O, B, C, E, F"),
    case("linkage ground a string", "knife_cutter", knife(ground="A"), KNIFE, "ground",
         "'A'"),
    case("linkage driver one point", "knife_cutter", knife(driver=["O"]), KNIFE, "driver",
         "(pivot, tip)"),
    case("linkage driver not a link", "knife_cutter", knife(driver=["O", "E"]), KNIFE,
         "driver", "F"),
    case("linkage lengths on no point", "knife_cutter", knife(lengths__1__joints=["A", "Q"]),
         KNIFE, "lengths", "no point 'Q'"),
    case("linkage lengths on no link", "knife_cutter", knife(lengths__1__joints=["A", "E"]),
         KNIFE, "lengths", "not joints of one link"),
    case("linkage slider guide mistyped", "knife_cutter",
         knife(sliders={"E": {"grund": [1.0, 0.0]}}), KNIFE, "sliders", "{ground = [dx, dy]}"),
]  # fmt: skip

CASES = FILE_CASES + TOP_CASES + CYCLOGRAM_CASES + MECHANISM_CASES


@pytest.mark.parametrize(("example", "edit", "table", "key", "hints", "exc"), CASES)
def test_a_mistake_in_a_machine_file_is_named(tmp_path, example, edit, table, key, hints, exc):
    path = tmp_path / "bad.toml"
    edit(example_path(example).read_text(encoding="utf-8"), path)
    err = caught(lambda: cm.Machine.from_toml(path))
    check(err, exc, path, table, key, hints)


def loom_with_a_cycle(path: Path) -> Path:
    """The loom with 10.2 → 1 in the same machine cycle: 1 → 3 → 7 → 10.1 → 10.2 → 1
    is then a cycle of height 0, which no schedule can satisfy."""
    appending("operation", {"from": "10.2", "to": "1", "min_angle_deg": 10.0})(
        LOOM.read_text(encoding="utf-8"), path
    )
    return path


def test_operations_in_a_cycle_within_one_machine_cycle_are_a_cycle_error(tmp_path):
    path = loom_with_a_cycle(tmp_path / "bad.toml")
    err = caught(lambda: cm.Machine.from_toml(path))
    check(err, cm.CycleError, path, "[[operation]]", None, ("form a cycle", "height"))
    assert isinstance(err, cm.CycleError)
    assert set(err.events) == {"1", "3", "7", "10.1", "10.2"}


def test_a_machine_that_fits_at_no_speed_has_speed_limit_0(tmp_path):
    path = tmp_path / "bad.toml"
    setting(operation__2__min_angle_deg=400.0)(
        (EXAMPLES / "rotor_line.toml").read_text(encoding="utf-8"), path
    )
    m = cm.Machine.from_toml(path)  # a cyclogram that fits nowhere is a result, not a mistake
    assert not m.fits([30.0, 240.0]).any()
    assert m.cyclogram_speed_limit() == 0.0
    assert m.speed_limit().rpm == 0.0


def test_a_byte_order_mark_is_skipped(tmp_path):
    """Some Windows editors start UTF-8 files with a byte order mark, which tomllib
    refuses: the file reads as it would without it."""
    path = tmp_path / "bom.toml"
    with_bom((EXAMPLES / "rotor_line.toml").read_text(encoding="utf-8"), path)
    m = cm.Machine.from_toml(path)
    assert m.data == cm.Machine.from_toml(EXAMPLES / "rotor_line.toml").data


def test_item9_negative_min_angle_in_a_machine_is_refused(tmp_path):
    """Issue 16 item 9: the loom's cam rise 1→3 at min_angle_deg = −45 used to read,
    and its optimum gave the rise 0° while the weft insertion gained 20° (285° vs
    264.97° at 300 rpm): a lead cannot be honoured when every event lies in one
    cycle from 0. The file is refused, naming it, the operation and the value."""
    path = tmp_path / "lead.toml"
    setting(operation__0__min_angle_deg=-45.0)(LOOM.read_text(encoding="utf-8"), path)
    with pytest.raises(cm.InputError, match=r"lead\.toml.*min_angle_deg = -45.*≥ 0"):
        cm.Machine.from_toml(path)


def _pin_x_range(R: float, r: float, d: float, phi0_deg: float) -> tuple[float, float]:
    """min and max of the press pin's x over a turn, from the geometry alone: the
    pin is P = (R − r)·e^{iθ} + d·e^{iβ}, β = −((R − r)/r)·θ + (R/r)·(φ0 − π/2)
    (see tests/press/test_press.py); a dense grid, each end polished by scipy."""
    from scipy.optimize import minimize_scalar

    def x(th: Any) -> Any:
        beta = -((R - r) / r) * th + (R / r) * (np.radians(phi0_deg) - np.pi / 2)
        return ((R - r) * np.exp(1j * th) + d * np.exp(1j * beta)).real

    th = np.linspace(0.0, 2 * np.pi, 20_001)
    ends = []
    for sign in (1.0, -1.0):
        k = int(np.argmin(sign * x(th)))
        res = minimize_scalar(lambda t, s=sign: s * x(t), bracket=(th[k - 1], th[k], th[k + 1]))
        ends.append(float(x(res.x)))
    return ends[0], ends[1]


def _press_reads(tmp_path: Path, **drive_keys: Any) -> str | None:
    """None if the press line reads with these drive keys, else the message."""
    path = tmp_path / "press.toml"
    drive(**drive_keys)((EXAMPLES / "extrusion_press_line.toml").read_text("utf-8"), path)
    try:
        cm.Machine.from_toml(path)
    except cm.InputError as e:
        return str(e)
    return None


def _numbers(msg: str, before: str) -> list[float]:
    """The numbers in ``msg`` after the text ``before``."""
    tail = msg.split(before, 1)[1]
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?(?:e-?\d+)?", tail)]


def test_a_rod_too_short_names_the_shortest_rod_and_the_offsets(tmp_path):
    """The message's bounds are the pin's reach from the geometry (to its 4
    figures), and they are the edges: just inside reads, just outside does not."""
    x_lo, x_hi = _pin_x_range(0.09, 0.03, 0.029, 55.95)
    msg = _press_reads(tmp_path, L_m=0.05)
    assert msg is not None
    (reach,) = _numbers(msg, "must exceed")[:1]
    assert reach == pytest.approx(max(x_hi, -x_lo), rel=5e-4)
    assert _press_reads(tmp_path, L_m=max(x_hi, -x_lo) * 1.001) is None
    assert _press_reads(tmp_path, L_m=max(x_hi, -x_lo) * 0.999) is not None
    msg = _press_reads(tmp_path, offset_m=1.0)
    assert msg is not None
    lo, hi = _numbers(msg, "offset_m must lie in")[:2]
    assert (lo, hi) == (pytest.approx(x_hi - 0.25, rel=5e-4), pytest.approx(x_lo + 0.25, rel=5e-4))
    for offset, fine in (((x_hi - 0.25) * 0.999, True), ((x_lo + 0.25) * 1.001, False)):
        assert (_press_reads(tmp_path, offset_m=offset) is None) == fine, offset


def test_the_examples_themselves_read():
    """The cases start from these files: each must read as it is, and this
    file's TOML writer must give back what it was given."""
    for name in ("stb_loom", "knife_cutter", "extrusion_press_line", "rotor_line"):
        text = (EXAMPLES / f"{name}.toml").read_text(encoding="utf-8")
        assert tomllib.loads(dump(tomllib.loads(text))) == tomllib.loads(text)
        cm.Machine.from_toml(EXAMPLES / f"{name}.toml")


# --------------------------------------------------------------------- the API
@pytest.fixture(scope="module")
def loom() -> cm.Machine:
    return cm.Machine.from_toml(LOOM)


def api(
    id: str,
    call: Callable[[cm.Machine], Any],
    file: bool,
    table: str | None,
    key: str | None,
    *hints: Hint,
    bug: str | None = None,
) -> Any:
    """A call on the loom machine; ``file``: the message must name the loom's file."""
    marks = [pytest.mark.xfail(strict=True, reason=f"BUG: {bug}")] if bug else []
    return pytest.param(call, file, table, key, hints, id=id, marks=marks)


API_CASES = [
    api("with_values unknown key", lambda m: m.with_values({"lifter.nosuchkey": 1}), True,
        LIFTER, "nosuchkey", VALID, "preload"),
    api("with_values unknown mechanism", lambda m: m.with_values({"nosuchmech.preload": 1}),
        False, None, "nosuchmech.preload", "<mechanism>.<key>", "lifter"),
    api("with_values no mechanism", lambda m: m.with_values({"preload": 1}), False, None,
        "preload", "<mechanism>.<key>", "lifter"),
    api("with_values a cyclogram key", lambda m: m.with_values({"cyclogram.cycle_deg": 300}),
        False, None, "cyclogram.cycle_deg", "machine.<key>"),
    api("with_values preload -1", lambda m: m.with_values({"lifter.preload_m": -1}), True,
        LIFTER, "preload_m", "≥ 0"),
    api("with_values preload above the stroke",
        lambda m: m.with_values({"lifter.preload_m": 0.02}), True, LIFTER, "preload_m",
        "smaller than stroke"),
    api("with_values speed_rmp", lambda m: m.with_values({"machine.speed_rmp": [1.0, 2.0]}),
        True, "[machine]", "speed_rmp", VALID, "speed_rpm"),
    api("with_values speed_rpm reversed",
        lambda m: m.with_values({"machine.speed_rpm": [500.0, 200.0]}), True, "[machine]",
        "speed_rpm", SPEED_RANGE),
    api("sweep nan", lambda m: cm.sweep(m, {"lifter.preload_m": [float("nan")]}), False, None,
        "lifter.preload_m", "finite"),
    api("sweep no values", lambda m: cm.sweep(m, {"lifter.preload_m": []}), False, None,
        "lifter.preload_m", "finite"),
    api("sweep a string", lambda m: cm.sweep(m, {"lifter.preload_m": ["a"]}), False, None,
        "lifter.preload_m", ("finite", "number")),
    api("sweep speed -1", lambda m: cm.sweep(m, {"speed_rpm": [-1.0]}), False, None,
        "speed_rpm", "positive"),
    api("sweep speed above the cap", lambda m: cm.sweep(m, {"speed_rpm": [2e6]}), False,
        None, "speed_rpm", "1e+06"),
    api("sweep unknown key", lambda m: cm.sweep(m, {"lifter.nosuchkey": [1.0]}), True,
        LIFTER, "nosuchkey", VALID),
    api("sweep unknown mechanism", lambda m: cm.sweep(m, {"nosuch.key": [1.0]}), False,
        None, "nosuch.key", "lifter"),
    api("sweep chunk 0", lambda m: cm.sweep(m, {"lifter.preload_m": [1e-4]}, chunk=0), False,
        None, "chunk", "≥ 1"),
    api("sweep executor 5", lambda m: cm.sweep(m, {"lifter.preload_m": [1e-4]}, executor=5),
        False, None, "executor", "concurrent.futures.Executor"),
    api("parse_range 1:2", lambda m: parse_range("1:2", "--speed"), False, None, "--speed",
        "'1:2'", "from:to:count"),
    api("parse_range count 0", lambda m: parse_range("1:2:0", "--speed"), False, None,
        "--speed", "whole count ≥ 1"),
    api("parse_range words", lambda m: parse_range("a:b:3", "--speed"), False, None,
        "--speed", "from:to:count"),
    api("parse_range nan", lambda m: parse_range("nan", "--speed"), False, None, "--speed",
        "finite"),
    api("dask udp", lambda m: dask_client("udp://x"), False, None, "--dask", "'udp://x'",
        "local:N", "tcp://HOST:PORT"),
    api("dask local:0", lambda m: dask_client("local:0"), False, None, "--dask", "N ≥ 1"),
]  # fmt: skip


@pytest.mark.parametrize(("call", "file", "table", "key", "hints"), API_CASES)
def test_a_mistake_in_a_call_is_named(loom, call, file, table, key, hints):
    err = caught(lambda: call(loom))
    check(err, cm.InputError, str(LOOM) if file else None, table, key, hints)


# --------------------------------------------------------------------- the CLI
def cli(id: str, make: Callable[[Path], list[str]], *parts: str, bug: str | None = None) -> Any:
    """``make(tmp_path)`` gives the arguments; ``parts`` (with ``{file}`` for the
    machine file's name) must be in the one line on stderr."""
    marks = [pytest.mark.xfail(strict=True, reason=f"BUG: {bug}")] if bug else []
    return pytest.param(make, parts, id=id, marks=marks)


def bad_file(edit: Edit, example: str = "stb_loom") -> Callable[[Path], Path]:
    def make(tmp: Path) -> Path:
        path = tmp / "bad.toml"
        edit(example_path(example).read_text(encoding="utf-8"), path)
        return path

    return make


def _a_file(path: Path) -> Path:
    path.write_text("not a folder\n")
    return path


def run(make: Callable[[Path], Path]) -> Callable[[Path], list[str]]:
    return lambda tmp: ["run", str(make(tmp)), "--out", str(tmp / "out"), "--no-plot"]


def sweep(*args: str) -> Callable[[Path], list[str]]:
    return lambda tmp: ["sweep", str(LOOM), *args, "--out", str(tmp / "out"), "--quiet"]


CLI_CASES = [
    cli("run: prelod", run(bad_file(replace("preload_m =", "prelod_m ="))), LIFTER, "prelod",
        VALID),
    cli("run: no such file", run(lambda tmp: tmp / "bad.toml"), "no such file"),
    cli("run: not TOML", run(bad_file(replace("[machine]\n", "[machine\n"))),
        "not valid TOML"),
    cli("run: speed_points 1", run(bad_file(setting(machine__speed_points=1))), "[machine]",
        "speed_points", "from 2"),
    cli("run: phi0", run(bad_file(replace("phi0_deg =", "phi0 ="), "extrusion_press_line")),
        DRIVE, "phi0", VALID),
    cli("run: linkage not a crank",
        run(bad_file(setting(mechanism__knife=FOUR_BAR_NOT_A_CRANK), "knife_cutter")), KNIFE,
        "cannot be assembled"),
    cli("run: a cycle", run(lambda tmp: loom_with_a_cycle(tmp / "bad.toml")), "form a cycle"),
    cli("sweep: --set without =", sweep("--set", "lifter.preload_m"), "lifter.preload_m",
        "<mechanism>.<key>=from:to:count"),
    cli("sweep: --set unknown mechanism", sweep("--set", "nosuch.key=1:2:3"), "nosuch.key",
        "the mechanisms are lifter"),
    cli("sweep: --set unknown key", sweep("--set", "lifter.nosuchkey=1:2:3"), LIFTER,
        "nosuchkey", VALID),
    cli("sweep: --set words", sweep("--set", "lifter.preload_m=a:b:3"), "lifter.preload_m",
        "from:to:count"),
    cli("sweep: --speed 1:2", sweep("--speed", "1:2"), "--speed", "'1:2'", "from:to:count"),
    cli("sweep: --speed from 0", sweep("--speed", "0:200:3"), "--speed", "positive", "got 0"),
    cli("sweep: --dask udp", sweep("--set", "lifter.preload_m=1e-4:2e-4:2", "--dask", "udp://x"),
        "--dask", "tcp://HOST:PORT"),
    cli("sweep: --out a file",
        lambda tmp: ["sweep", str(LOOM), "--set", "lifter.preload_m=1e-4:2e-4:2", "--out",
                     str(_a_file(tmp / "afile")), "--quiet"],
        "--out", "is a file, not a folder"),
    cli("run: --out under a file",
        lambda tmp: ["run", str(LOOM), "--out", str(_a_file(tmp / "afile") / "x"), "--no-plot"],
        "--out", "is a file, not a folder"),
    cli("sweep: a bad file",
        lambda tmp: ["sweep", str(bad_file(replace("preload_m =", "prelod_m ="))(tmp)), "--set",
                     "lifter.a_max_m=1e-4:2e-4:2", "--out", str(tmp / "out"), "--quiet"],
        LIFTER, "prelod"),
]  # fmt: skip


@pytest.mark.parametrize(("make", "parts"), CLI_CASES)
def test_a_mistake_on_the_command_line_is_one_line_on_stderr(tmp_path, capsys, make, parts):
    argv = make(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("cyclomech: error: ") and err.count("\n") == 1, err
    assert argv[1] in err, f"the file {argv[1]} not in: {err}"
    missing = [p for p in parts if p not in err]
    assert not missing, f"{missing} not in: {err}"
    assert not (tmp_path / "out").exists(), "an output folder for a run that failed"


@pytest.mark.parametrize("rpm", [-300.0, 0.0, float("nan"), 2e6])
def test_optimize_takes_the_machines_speeds_and_says_so(rpm):
    # Found by a new user's trial: -300 read "speed_rpm must be >= 0", then 0 was
    # refused with "> 0". One rule, one message, for every bad speed.
    with pytest.raises(cm.InputError, match=r"rpm must hold positive speeds in rpm, each in \(0, "):
        cm.Machine.example().optimize(rpm)


@pytest.mark.parametrize(
    ("key", "bad"), [("linear", 1), ("linear", 0), ("n_threads", "2"), ("n_threads", True)]
)
def test_a_bad_flag_or_thread_count_is_refused_also_when_the_laws_are_kept(key, bad):
    """Found by the fuzz: ``bound_angles(linear=1)`` returned the linear laws a
    ``linear=True`` call had kept on the machine (1 == True as a dict key), where a
    fresh machine refuses 1. Both are refused, whichever laws the machine keeps."""
    machine = cm.Machine.example()
    machine.bound_angles([300.0], linear=True)
    machine.bound_angles([300.0], linear=False)
    with pytest.raises(cm.InputError, match=key):
        machine.bound_angles([300.0], **{key: bad})
    with pytest.raises(cm.InputError, match=key):
        machine.bound_laws(**{key: bad})


def test_a_mechanism_without_its_kind_says_the_key_is_missing(tmp_path):
    text = (EXAMPLES / "stb_loom.toml").read_text("utf-8").replace('kind = "cam_stop"\n', "", 1)
    path = tmp_path / "m.toml"
    path.write_text(text, "utf-8")
    with pytest.raises(
        cm.InputError, match=r"\[mechanism.lifter\]: the key kind is missing; it must"
    ):
        cm.Machine.from_toml(path)


@pytest.mark.parametrize(("omega", "text"), [(1e-200, "got 1e-200"), (1e200, "got 1e200")])
def test_numbers_in_rust_messages_are_short(omega, text):
    # Found by a new user's trial: Rust printed 1e-200 as "0." and 199 zeros.
    with pytest.raises(cm.InputError) as e:
        cm.impact.first_rebound([0.0], [0.0], omega, 0.0, 1.0, v0=1.0)
    assert str(e.value).endswith(text)


def test_a_bound_no_angle_meets_makes_the_machine_work_at_no_speed(tmp_path, capsys):
    # Found by a new user's trial: natural_frequency_hz = 1e-9 made the cam's
    # vibration bound exceed any turn, and the run failed with "constraint
    # 'vibration[…]': rhs must be finite; got nan" (exit 2, no key named). It is a
    # design that fits at no speed: exit 3, the bound named.
    text = (EXAMPLES / "stb_loom.toml").read_text("utf-8")
    text = text.replace("natural_frequency_hz = 400.0", "natural_frequency_hz = 1e-9", 1)
    path = tmp_path / "m.toml"
    path.write_text(text, "utf-8")
    m = cm.Machine.from_toml(path)
    lim = m.speed_limit()
    assert (
        lim.rpm == 0 and "vibration[lifter cam rise 1→3] cannot be met by any angle" in lim.reason
    )
    with pytest.raises(cm.InfeasibleError) as e:
        m.optimize(300.0)
    assert e.value.conflict == ("vibration[lifter cam rise 1→3]",)
    out = tmp_path / "o"
    argv = ["run", str(path), "--out", str(out), "--no-plot", "--quiet", "--no-sensitivities"]
    assert main(argv) == 3
    assert "works at no speed" in capsys.readouterr().err
