"""The machine-file format reference (cyclomech._keydocs, issue 21) cannot drift
from the parsers: it documents exactly the keys each table takes, its defaults are
the parsed values, a sample of its ranges is what the parsers refuse, and its page
is valid reStructuredText."""

from __future__ import annotations

import copy
import io
import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cyclomech as cm
import pytest
from cyclomech import _keydocs
from cyclomech._keydoc import KeyDoc
from cyclomech._kind import Phase
from cyclomech.cam._design import CAM_KEYS, SEGMENT_KEYS
from cyclomech.cam._friction import CAM_FRICTION_KEYS
from cyclomech.cam._synthesize import SYNTHESIZE_KEYS
from cyclomech.cyclogram._file import _CG_KEYS, _CON_KEYS, _OP_KEYS, _TERM_KEYS
from cyclomech.dynamics._drive import DRIVE_KEYS
from cyclomech.dynamics._frame import BALANCE_KEYS
from cyclomech.forces._file import _GUIDE_KEYS, _LOAD_KEYS, _MASS_KEYS, _PIN_KEYS, FRICTION_KEYS
from cyclomech.machine import KINDS, check_parameter
from cyclomech.machine._model import _MACHINE_KEYS
from cyclomech.press._friction import PRESS_FRICTION_KEYS
from cyclomech.press._kind import FORCE_KEYS
from cyclomech.servo._kind import MOTOR_KEYS

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: Every table of the reference by name: its keys' records (from their owners).
TABLES = {name: t.keys for name, t in _keydocs.tables().items()}
#: An example machine of each kind, and the name of its mechanism of that kind.
KIND_EXAMPLES = {
    "cam": ("stb_loom", "lifter cam"),
    "cam_stop": ("stb_loom", "lifter"),
    "linkage": ("knife_cutter", "knife"),
    "press": ("extrusion_press_line", "drive"),
    "servo": ("flow_wrapper", "film feed"),
    "transfer": ("rotor_line", "line"),
}
#: A cam with a translating follower (the examples' cam is oscillating).
TRANSLATING_CAM = {
    "kind": "cam",
    "follower": "translating",
    "base_radius_m": 0.05,
    "roller_radius_m": 0.01,
    "mass_kg": 0.5,
    "width_m": 0.01,
    "natural_frequency_hz": 300.0,
    "max_vibration_m": 1e-4,
    "segment": [
        {"kind": "rise", "angle_deg": 90.0, "stroke_m": 0.02, "arc": ["1", "3"]},
        {"kind": "dwell", "angle_deg": 90.0},
        {"kind": "return", "angle_deg": 180.0, "stroke_m": 0.02},
    ],
}
#: A slider-crank linkage (the examples' linkage has no slider).
SLIDER_CRANK = {
    "kind": "linkage",
    "points": {"A": [0.0, 0.0], "B": [0.1, 0.0], "C": [0.45, 0.0]},
    "links": [["A", "B"], ["B", "C"]],
    "ground": ["A"],
    "driver": ["A", "B"],
    "sliders": {"C": {"ground": [1.0, 0.0]}},
}


def data(source: str) -> dict[str, Any]:
    """A machine's parsed layout to edit: an example file's, ``"example"``
    (:meth:`Machine.example`), or ``"cam"`` / ``"slider"``: the example with a
    translating cam ``c`` / a slider-crank ``s`` added."""
    if source in ("example", "cam", "slider"):
        d = copy.deepcopy(dict(cm.Machine.example().data or {}))
        if source == "cam":
            d["mechanism"]["c"] = copy.deepcopy(TRANSLATING_CAM)
        if source == "slider":
            d["mechanism"]["s"] = copy.deepcopy(SLIDER_CRANK)
        return d
    d = copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLES / f"{source}.toml").data or {}))
    for table in d.get("mechanism", {}).values():
        # A catalogue's path is relative to the machine file, which build() does not
        # read from: give it whole.
        if "catalogue" in table:
            table["catalogue"] = str(EXAMPLES / table["catalogue"])
    return d


def at(d: Any, path: tuple[Any, ...]) -> Any:
    """The table at ``path`` (keys and row indices) inside ``d``."""
    for p in path:
        d = d[p]
    return d


def build(d: dict[str, Any]) -> cm.Machine:
    return cm.Machine.from_dict(d, "dir/some_machine.toml")


def refused(d: dict[str, Any]) -> str:
    """The message of the error that parsing ``d`` raises."""
    with pytest.raises(cm.CyclomechError) as e:
        build(d)
    return str(e.value)


def valid_keys(d: dict[str, Any]) -> set[str]:
    """The keys a table takes, as the parser lists them when refusing another."""
    m = re.search(r"valid keys are (.*)$", refused(d))
    assert m, "the parser did not list its valid keys"
    return set(m.group(1).split(", "))


def documented(table: str) -> set[str]:
    return {k.name for k in TABLES[table]}


def doc(table: str, key: str) -> KeyDoc:
    (k,) = [k for k in TABLES[table] if k.name == key]
    return k


# ---------------------------------------------------------------- the key sets
def test_every_kind_is_documented() -> None:
    assert set(KINDS) <= set(TABLES)
    assert set(KIND_EXAMPLES) == set(KINDS)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_kind_keys(kind: str) -> None:
    assert documented(kind) == set(KINDS[kind].keys)


@pytest.mark.parametrize(
    ("table", "keys"),
    [
        ("machine", _MACHINE_KEYS),
        ("cyclogram", _CG_KEYS),
        ("operation", _OP_KEYS),
        ("constraint", _CON_KEYS),
        ("constraint.terms", _TERM_KEYS),
        ("phase", Phase.KEYS),
        ("cam", CAM_KEYS | {"kind", "friction", "synthesize"}),
        ("cam.friction", CAM_FRICTION_KEYS),
        ("cam.synthesize", SYNTHESIZE_KEYS),
        ("cam.segment", SEGMENT_KEYS | {"arc"}),
        ("linkage.mass", _MASS_KEYS),
        ("linkage.load", _LOAD_KEYS),
        ("linkage.friction", FRICTION_KEYS),
        ("linkage.friction.pins", _PIN_KEYS),
        ("linkage.friction.guides", _GUIDE_KEYS),
        ("press.deformation_force", set(FORCE_KEYS)),
        ("press.friction", PRESS_FRICTION_KEYS),
        ("servo.motor", MOTOR_KEYS),
        ("servo.segment", SEGMENT_KEYS - {"load_n", "load_nm"} | {"arc"}),
        ("drive", DRIVE_KEYS),
        ("balance", BALANCE_KEYS),
    ],
)
def test_constant_key_sets(table: str, keys: Any) -> None:
    assert documented(table) == set(keys)


def test_key_sets_the_parsers_list() -> None:
    """Tables whose keys are no constant: the keys the parser lists when it
    refuses an unknown one."""
    d = data("example")
    d["bogus"] = 1
    assert valid_keys(d) == documented("file")
    d = data("knife_cutter")
    d["mechanism"]["knife"]["lengths"][0]["bogus"] = 1
    assert valid_keys(d) == documented("linkage.lengths")
    # The parsers that list keys list these too.
    d = data("example")
    d["operation"][0]["bogus"] = 1
    assert valid_keys(d) == documented("operation")
    d = data("stb_loom")
    d["mechanism"]["lifter cam"]["segment"][0]["bogus"] = 1
    # (The loom's lifter cam is oscillating: the translating follower's keys are
    # the other follower's, refused there.)
    translating = {"stroke_m", "load_n", "points_m"}
    translating |= {"start_velocity_m_per_rad", "end_velocity_m_per_rad"}
    assert valid_keys(d) | translating == documented("cam.segment")


def test_slider_guide_keys() -> None:
    """A guide is a table with one key, ground or link: each documented key is
    taken (a slider-crank, an inverted slider-crank), another is refused."""
    assert documented("linkage.sliders") == {"ground", "link"}
    build(data("slider"))
    d = data("slider")
    d["mechanism"]["s"] = {
        "kind": "linkage",
        "points": {
            "A": [0.0, 0.0],
            "B": [0.05403023058681398, 0.08414709848078966],
            "C": [0.5, 0.0],
            "D": [-0.0895965444755632, 0.11124708869213232],
        },
        "links": [["A", "B"], ["C", "D"]],
        "ground": ["A", "C"],
        "driver": ["A", "B"],
        "sliders": {"B": {"link": ["C", "D"]}},
    }
    build(d)
    d = data("slider")
    d["mechanism"]["s"]["sliders"] = {"C": {"rail": [1.0, 0.0]}}
    message = refused(d)
    assert "{ground = [dx, dy]}" in message and "{link = [b, c]}" in message


def test_no_key_twice_and_every_table_titled() -> None:
    for table, keys in TABLES.items():
        names = [k.name for k in keys]
        assert len(names) == len(set(names)), table
    titles = [t.title for t in _keydocs.tables().values()]
    assert all(titles) and len(titles) == len(set(titles))
    # A kind's own table takes its paragraph from the kind's docstring; every other
    # table has its own.
    own = {name for name, t in _keydocs.tables().items() if t.intro is None}
    assert own == set(KINDS)


def test_records_are_complete() -> None:
    types = {"number", "integer", "text", "bool", "array", "table", "array of tables"}
    for table, keys in TABLES.items():
        for k in keys:
            assert k.meaning.endswith(".") and k.unit and k.default and k.valid, (table, k)
            assert set(k.type.split(" or ")) <= types, (table, k)


# ---------------------------------------------------------------- sweeps
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_sweep_column_is_what_a_sweep_takes(kind: str) -> None:
    source, name = KIND_EXAMPLES[kind]
    m = cm.Machine.from_toml(EXAMPLES / f"{source}.toml")
    # Keys this example's table takes from elsewhere (a stop's law and stroke from
    # its cam) are refused for this table only; the docs say so in their rule.
    refuses = getattr(KINDS[kind], "sweep_refuses", None)
    here = refuses(m.data["mechanism"][name]) if refuses else {}
    for k in TABLES[kind]:
        if k.name in here:
            assert k.sweep and "cam" in k.valid, k
            with pytest.raises(cm.CyclomechError, match="cannot vary"):
                check_parameter(m, f"{name}.{k.name}")
        elif k.sweep:
            check_parameter(m, f"{name}.{k.name}")
        else:
            with pytest.raises(cm.CyclomechError):
                check_parameter(m, f"{name}.{k.name}")


def test_sweep_column_of_the_other_tables() -> None:
    m = cm.Machine.example()
    for k in TABLES["machine"]:
        if k.sweep:
            check_parameter(m, f"machine.{k.name}")
        else:
            with pytest.raises(cm.CyclomechError):
                check_parameter(m, f"machine.{k.name}")
    for table in ("file", "cyclogram", "operation", "constraint"):
        assert all(k.sweep is False for k in TABLES[table]), table
    for table in TABLES:
        if "." in table or table == "phase":
            assert all(k.sweep is None for k in TABLES[table]), table


# ---------------------------------------------------------------- defaults
Get = Callable[[cm.Machine], Any]
# (table, key, documented default, machine, path of the key's table, parsed value, value)
DEFAULTS: list[tuple[str, str, str, str, tuple[Any, ...], Get, Any]] = [
    ("machine", "name", "the file's name without its extension", "example", ("machine",),
     lambda m: m.name, "some_machine"),
    ("machine", "speed_points", "61", "knife_cutter", ("machine",),
     lambda m: m.speed_points, 61),
    ("machine", "angle_points", "361", "example", ("machine",), lambda m: m.angle_points, 361),
    ("machine", "speed_fluctuation", "0.05", "example", ("machine",),
     lambda m: m.speed_fluctuation, 0.05),
    ("machine", "flatten_torque", "false", "example", ("machine",),
     lambda m: m.flatten_torque, False),
    ("machine", "nominal_rpm", "none (the top of speed_rpm, capped at the speed limit)",
     "knife_cutter", ("machine",),
     lambda m: m.nominal_rpm is None
     and m.nominal_speed() == min(m.speed_range_rpm[1], m.speed_limit().rpm), True),
    ("cyclogram", "name", "the file's name without its extension", "example",
     ("cyclogram",), lambda m: m.cyclogram.name, "some_machine"),
    ("cyclogram", "cycle_deg", "360", "stb_loom", ("cyclogram",),
     lambda m: m.cyclogram.cycle_deg, 360.0),
    ("cyclogram", "events", "the events in the order the operations name them", "example",
     ("cyclogram",), lambda m: m.cyclogram.events, ("1", "3", "7", "10.1", "10.2")),
    ("operation", "min_angle_deg", "0", "example", ("operation", 0),
     lambda m: m.cyclogram.operations[0].min_angle_deg, 0.0),
    ("operation", "max_angle_deg", "none (no upper bound)", "example", ("operation", 0),
     lambda m: m.cyclogram.operations[0].max_angle_deg, None),
    ("operation", "min_duration_s", "0", "example", ("operation", 3),
     lambda m: m.cyclogram.operations[3].min_duration_s, 0.0),
    ("operation", "height", "0", "example", ("operation", 0),
     lambda m: m.cyclogram.operations[0].height, 0),
    ("operation", "name", "none (shown as from→to)", "example", ("operation", 3),
     lambda m: m.cyclogram.operations[3].title, "10.1→10.2"),
    ("operation", "mechanism", "none", "example", ("operation", 0),
     lambda m: m.cyclogram.operations[0].mechanism, None),
    ("phase", "crank_deg", "0", "knife_cutter", ("mechanism", "knife", "phase"),
     lambda m: m.mechanisms["knife"].phase.crank_deg, 0.0),
    ("phase", "event", "none (crank_deg at cycle angle 0)", "knife_cutter",
     ("mechanism", "knife", "phase"), lambda m: m.mechanisms["knife"].phase.event, None),
    ("cam", "closure", "spring", "stb_loom", ("mechanism", "lifter cam"),
     lambda m: m.mechanisms["lifter cam"].design.cam.closure, "spring"),
    ("cam", "max_pressure_angle_deg", "45 for an oscillating follower, 30 otherwise",
     "stb_loom", ("mechanism", "lifter cam"),
     lambda m: m.mechanisms["lifter cam"].design.max_pressure_angle_deg, 45.0),
    ("cam", "max_pressure_angle_deg", "45 for an oscillating follower, 30 otherwise", "cam",
     ("mechanism", "c"), lambda m: m.mechanisms["c"].design.max_pressure_angle_deg, 30.0),
    ("cam", "offset_m", "0 (translating only; other followers refuse it)", "cam",
     ("mechanism", "c"), lambda m: m.mechanisms["c"].design.cam.follower.offset, 0.0),
    ("cam", "damping_ratio", "0", "stb_loom", ("mechanism", "lifter cam"),
     lambda m: m.mechanisms["lifter cam"].design.vibration[1], 0.0),
    ("cam", "spring_rate_n_per_m", "0", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.loads.spring_rate, 0.0),
    ("cam", "preload_n", "0", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.loads.preload, 0.0),
    ("cam", "spring_rate_nm_per_rad", "0", "stb_loom",
     ("mechanism", "lifter cam"),
     lambda m: m.mechanisms["lifter cam"].design.loads.spring_rate, 0.0),
    ("cam", "preload_nm", "0", "stb_loom",
     ("mechanism", "lifter cam"), lambda m: m.mechanisms["lifter cam"].design.loads.preload,
     0.0),
    ("cam", "follower_modulus_pa", "2.1e11", "cam",
     ("mechanism", "c"), lambda m: m.mechanisms["c"].design.contact.follower_modulus, 2.1e11),
    ("cam", "cam_modulus_pa", "2.1e11", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.contact.cam_modulus, 2.1e11),
    ("cam", "follower_poisson", "0.3", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.contact.follower_poisson, 0.3),
    ("cam", "cam_poisson", "0.3", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.contact.cam_poisson, 0.3),
    ("cam", "mass_kg", "none (no loads: no σ_H, jump or vibration from loads)", "cam",
     ("mechanism", "c"), lambda m: m.mechanisms["c"].design.loads, None),
    ("cam", "width_m", "none (no contact stress)", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.contact, None),
    ("cam", "max_stress_pa", "none (σ_H not bounded)", "cam", ("mechanism", "c"),
     lambda m: m.mechanisms["c"].design.max_stress, None),
    ("cam.segment", "law", "cycloidal", "cam", ("mechanism", "c", "segment", 0),
     lambda m: m.mechanisms["c"].design.cam.segments[0].law, "cycloidal"),
    ("cam.segment", "stroke_m", "0", "cam", ("mechanism", "c", "segment", 1),
     lambda m: m.mechanisms["c"].design.cam.segments[1].stroke, 0.0),
    ("cam.segment", "load_nm", "0", "stb_loom",
     ("mechanism", "lifter cam", "segment", 0),
     lambda m: m.mechanisms["lifter cam"].design.loads.segment_loads[0], 0.0),
    ("cam.segment", "arc", "none (the segment bounds no operation)", "cam",
     ("mechanism", "c", "segment", 0), lambda m: m.mechanisms["c"].design.arcs[0], None),
    ("cam_stop", "law", "modified_sine (from the cam with cam)", "example",
     ("mechanism", "lifter"), lambda m: m.mechanisms["lifter"].stop.law.name, "modified_sine"),
    ("cam_stop", "restitution", "5/9", "example", ("mechanism", "lifter"),
     lambda m: m.mechanisms["lifter"].stop.restitution, 5.0 / 9.0),
    ("cam_stop", "zeta", "0.05", "example", ("mechanism", "lifter"),
     lambda m: m.mechanisms["lifter"].stop.zeta, 0.05),
    ("cam_stop", "pulse", "decaying", "example", ("mechanism", "lifter"),
     lambda m: m.mechanisms["lifter"].stop.pulse, "decaying"),
    ("cam_stop", "model", "pulse", "example", ("mechanism", "lifter"),
     lambda m: m.mechanisms["lifter"].stop.model, "pulse"),
    ("cam_stop", "mass_kg", "J_A_kg_m2 / lever_length_m²", "example", ("mechanism", "lifter"),
     lambda m: m.mechanisms["lifter"].stop.mass, 7.4e-5 / 0.1**2),
    ("cam_stop", "phase_deg", "[20, 60, 5]", "stb_loom", ("mechanism", "lifter"),
     lambda m: m.mechanisms["lifter"].phase_deg.tolist(), [20.0, 30.0, 40.0, 50.0, 60.0]),
    ("linkage", "output", "the last point of points", "knife_cutter",
     ("mechanism", "knife"), lambda m: m.mechanisms["knife"].output, "F"),
    ("linkage", "max_acceleration_m_per_s2", "none (no speed limit)", "knife_cutter",
     ("mechanism", "knife"), lambda m: m.mechanisms["knife"].speed_limit_rpm(), math.inf),
    ("linkage", "name", "none", "knife_cutter", ("mechanism", "knife"),
     lambda m: m.mechanisms["knife"].linkage.name, None),
    ("linkage.mass", "inertia_kg_m2", "0", "knife_cutter", ("mechanism", "knife", "mass", 0),
     lambda m: m.mechanisms["knife"].dynamics["masses"][("B", "C", "E")].inertia_kg_m2, 0.0),
    ("linkage", "gravity_m_per_s2", "none (no gravity)", "knife_cutter",
     ("mechanism", "knife"), lambda m: m.mechanisms["knife"].dynamics["gravity"], None),
    ("linkage", "friction", "none (frictionless)", "knife_cutter",
     ("mechanism", "knife"), lambda m: m.mechanisms["knife"].friction, None),
    ("linkage.friction", "pin_viscous_nm_s_per_rad", "0", "knife_cutter",
     ("mechanism", "knife", "friction"),
     lambda m: m.mechanisms["knife"].friction.pins["A"].viscous, 0.0),
    ("press", "offset_m", "0", "extrusion_press_line", ("mechanism", "drive"),
     lambda m: m.mechanisms["drive"].press.offset, 0.0),
    ("press", "slider_mass_kg", "0", "extrusion_press_line", ("mechanism", "drive"),
     lambda m: m.mechanisms["drive"].slider_mass, 0.0),
    ("press", "rod_mass_kg", "0", "extrusion_press_line", ("mechanism", "drive"),
     lambda m: m.mechanisms["drive"].rod_mass, 0.0),
    ("press", "max_V_np_m_per_s", "none (no speed limit)", "extrusion_press_line",
     ("mechanism", "drive"), lambda m: m.mechanisms["drive"].speed_limit_rpm(), math.inf),
    ("press", "deformation_force", "none (no force)", "extrusion_press_line",
     ("mechanism", "drive"), lambda m: m.mechanisms["drive"].force, None),
    ("servo", "force_n", "0", "flow_wrapper", ("mechanism", "film feed"),
     lambda m: m.mechanisms["film feed"].axis.load.force_n, 0.0),
    ("servo", "drive_efficiency", "1", "flow_wrapper", ("mechanism", "film feed"),
     lambda m: m.mechanisms["film feed"].axis.load.efficiency, 1.0),
    ("servo", "torque_nm", "0", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].axis.load.torque_nm, 0.0),
    ("servo", "gear_ratio", "1 (a direct drive)", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].axis.gearbox.ratio, 1.0),
    ("servo", "gear_efficiency", "1", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].axis.gearbox.efficiency, 1.0),
    ("servo", "gear_inertia_kg_m2", "0", "flow_wrapper", ("mechanism", "film feed"),
     lambda m: m.mechanisms["film feed"].axis.gearbox.inertia_kg_m2, 0.0),
    ("servo", "gear_ratios", "[gear_ratio]", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].ratios == (m.mechanisms["jaw"].axis.gearbox.ratio,), True),
    ("servo", "inertia_ratio_limit", "10", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].axis.inertia_ratio_limit, 10.0),
    ("servo", "continuity", "velocity", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].axis.program.continuity, "velocity"),
    ("servo", "torque_reserve", "0 (the motor's full torques)", "flow_wrapper",
     ("mechanism", "jaw"), lambda m: m.mechanisms["jaw"].torque_reserve, 0.0),
    ("servo", "table_points", "3600", "flow_wrapper", ("mechanism", "jaw"),
     lambda m: m.mechanisms["jaw"].table_points, 3600),
    ("servo", "phase", "the first bound segment at its operation's start, else cycle angle 0",
     "flow_wrapper", ("mechanism", "jaw"), lambda m: m.mechanisms["jaw"].phase, None),
    ("servo", "motor", "none (with catalogue: sized only, no bound on the cyclogram)",
     "flow_wrapper", ("mechanism", "film feed"),
     lambda m: (m.mechanisms["film feed"].axis.motor, m.mechanisms["film feed"].bounds()),
     (None, ())),
    ("servo.segment", "law", "cycloidal", "flow_wrapper",
     ("mechanism", "film feed", "segment", 0),
     lambda m: m.mechanisms["film feed"].axis.program.segments[0].law, "cycloidal"),
    ("servo.segment", "arc", "none (the segment bounds no operation)", "flow_wrapper",
     ("mechanism", "film feed", "segment", 0),
     lambda m: m.mechanisms["film feed"].arcs[0], None),
    ("transfer", "max_jerk_m_per_s3", "none (no limit)", "rotor_line", ("mechanism", "line"),
     lambda m: m.mechanisms["line"].max_jerk, None),
    ("transfer", "max_acceleration_m_per_s2", "none (no limit)", "rotor_line",
     ("mechanism", "line"),
     lambda m: m.mechanisms["line"].max_acceleration, None),
    ("drive", "gear_ratio", "1 (a direct drive)", "knife_cutter", ("drive",),
     lambda m: m.drive.motor.ratio, 1.0),
    ("drive", "gear_efficiency", "1", "knife_cutter", ("drive",),
     lambda m: m.drive.motor.efficiency, 1.0),
    ("drive", "rotor_inertia_kg_m2", "0", "knife_cutter", ("drive",),
     lambda m: m.drive.motor.rotor_kg_m2, 0.0),
    ("drive", "flywheel_kg_m2", "none: sized by simulation for [machine] speed_fluctuation",
     "knife_cutter", ("drive",), lambda m: m.drive.flywheel_kg_m2, None),
    ("balance", "objective", "rms_force", "knife_cutter", ("balance", 0),
     lambda m: m.balance[0].objective, "rms_force"),
    ("balance", "torque_weight", "1", "knife_cutter", ("balance", 0),
     lambda m: m.balance[0].torque_weight, 1.0),
    ("balance", "max_mass_radius_kg_m", "none (no bound)", "knife_cutter", ("balance", 0),
     lambda m: m.balance[0].max_mass_radius_kg_m, None),
]  # fmt: skip


@pytest.mark.parametrize(
    ("table", "key", "default", "source", "path", "get", "value"),
    DEFAULTS,
    ids=[f"{c[0]}.{c[1]}-{c[3]}" for c in DEFAULTS],
)
def test_documented_default_is_the_parsed_value(
    table: str, key: str, default: str, source: str, path: tuple[Any, ...], get: Get, value: Any
) -> None:
    assert doc(table, key).default == default
    d = data(source)
    at(d, path).pop(key, None)
    got = get(build(d))
    if isinstance(value, float) and not math.isinf(value):
        assert got == pytest.approx(value, rel=1e-12)
    else:
        assert got == value


def test_constraint_name_default() -> None:
    assert doc("constraint", "name").default.startswith("constraint <n>")
    d = data("example")
    d["constraint"] = [
        {"terms": [{"from": "1", "to": "3", "coeff": 1.0}], "sense": ">=", "rhs": 50.0}
    ]
    assert build(d).cyclogram.constraints[0].name == "constraint 1"


def test_required_keys_are_required() -> None:
    """Each key documented as "required" (without "unless" or "for"): its table
    without it is refused, naming it."""
    cases = {
        "machine": ("example", ("machine",)),
        "cam_stop": ("example", ("mechanism", "lifter")),
        "cam": ("cam", ("mechanism", "c")),
        "cam.segment": ("cam", ("mechanism", "c", "segment", 0)),
        "linkage": ("knife_cutter", ("mechanism", "knife")),
        "linkage.mass": ("knife_cutter", ("mechanism", "knife", "mass", 0)),
        "press": ("extrusion_press_line", ("mechanism", "drive")),
        "press.deformation_force": (
            "extrusion_press_line",
            ("mechanism", "drive", "deformation_force"),
        ),
        "transfer": ("rotor_line", ("mechanism", "line")),
        "servo": ("flow_wrapper", ("mechanism", "film feed")),
        "servo.segment": ("flow_wrapper", ("mechanism", "film feed", "segment", 0)),
        "operation": ("example", ("operation", 0)),
        "constraint": ("example", ("constraint", 0)),
        "constraint.terms": ("example", ("constraint", 0, "terms", 0)),
        "linkage.lengths": ("knife_cutter", ("mechanism", "knife", "lengths", 0)),
        "drive": ("knife_cutter", ("drive",)),
        "balance": ("knife_cutter", ("balance", 0)),
    }
    seen = 0
    for table, (source, path) in cases.items():
        for k in TABLES[table]:
            if k.default != "required" or k.name == "kind":
                continue
            d = data(source)
            if source == "example":
                d["constraint"] = [
                    {"terms": [{"from": "1", "to": "3", "coeff": 1.0}], "sense": ">=", "rhs": 5.0}
                ]
            if (table, k.name) == ("cam_stop", "stroke_m"):
                continue  # required unless cam: the example's lifter gives law and stroke
            at(d, path).pop(k.name)
            assert k.name in refused(d), (table, k.name)
            seen += 1
    assert seen > 40


# ---------------------------------------------------------------- ranges
# (machine, path of the table, key, a value just outside the range, one just inside)
RANGES: list[tuple[str, tuple[Any, ...], str, Any, Any]] = [
    ("example", ("machine",), "speed_points", 1, 2),
    ("example", ("machine",), "angle_points", 8, 9),
    ("example", ("machine",), "speed_fluctuation", 1.0, 0.999),
    ("example", ("machine",), "nominal_rpm", 0.0, 1e6),
    ("example", ("machine",), "speed_rpm", [0.0, 500.0], [1e-9, 1e6]),
    ("example", ("machine",), "flatten_torque", 1, True),
    ("example", ("cyclogram",), "cycle_deg", 0.0, 400.0),
    ("example", ("operation", 0), "min_angle_deg", -1e-9, 0.0),
    ("example", ("operation", 0), "height", -1, 0),
    ("example", ("operation", 0), "min_duration_s", 1e-13, 1e-12),
    ("cam", ("mechanism", "c"), "max_pressure_angle_deg", 90.0, 89.9),
    ("cam", ("mechanism", "c"), "damping_ratio", 1.0, 0.99),
    ("cam", ("mechanism", "c"), "follower_poisson", 0.5, 0.49),
    ("cam", ("mechanism", "c"), "closure", "belt", "groove"),
    ("cam", ("mechanism", "c"), "follower", "disc", "translating"),
    ("cam", ("mechanism", "c", "segment", 0), "angle_deg", 0.0, 90.0),
    ("cam", ("mechanism", "c", "segment", 0), "law", "linear", "harmonic"),
    ("example", ("mechanism", "lifter"), "restitution", 1.01, 1.0),
    ("example", ("mechanism", "lifter"), "zeta", -1e-9, 0.0),
    ("example", ("mechanism", "lifter"), "preload_m", 9.4e-3, 0.0),
    ("example", ("mechanism", "lifter"), "a_max_m", 0.0, 1e-9),
    ("example", ("mechanism", "lifter"), "pulse", "square", "half_sine"),
    ("example", ("mechanism", "lifter"), "model", "spring", "contact"),
    ("example", ("mechanism", "lifter"), "phase_deg", [20.0, 60.0, 51], [20.0, 360.0, 50]),
    ("knife_cutter", ("mechanism", "knife"), "max_acceleration_m_per_s2", 0.0, 1e-9),
    ("knife_cutter", ("mechanism", "knife", "mass", 0), "mass_kg", -1e-9, 0.0),
    ("knife_cutter", ("mechanism", "knife", "lengths", 0), "length", 0.0, 0.425),
    ("knife_cutter", ("mechanism", "knife", "friction"), "pin_mu", -1e-9, 0.0),
    ("knife_cutter", ("mechanism", "knife", "friction"), "pin_radius_m", -1e-9, 0.0),
    ("extrusion_press_line", ("mechanism", "drive"), "k_Sp", 1.01, 0.1),
    ("extrusion_press_line", ("mechanism", "drive"), "slider_mass_kg", -1e-9, 0.0),
    ("extrusion_press_line", ("mechanism", "drive"), "rod_mass_kg", -1.0, 0.0),
    ("extrusion_press_line", ("mechanism", "drive"), "max_V_np_m_per_s", 0.0, 0.005),
    ("rotor_line", ("mechanism", "line"), "pockets_t", 0, 1),
    ("rotor_line", ("mechanism", "line"), "pockets_p", 10_001, 10_000),
    ("rotor_line", ("mechanism", "line"), "gap_m", 0.0, 0.01),
    ("rotor_line", ("mechanism", "line"), "max_jerk_m_per_s3", 0.0, 1e-9),
    ("flow_wrapper", ("mechanism", "film feed"), "gear_ratio", 0.0, 0.5),
    ("flow_wrapper", ("mechanism", "film feed"), "drive_efficiency", 1.01, 1.0),
    ("flow_wrapper", ("mechanism", "film feed"), "lead_m", 0.0, 0.3),
    ("flow_wrapper", ("mechanism", "jaw"), "gear_efficiency", 0.0, 0.5),
    ("flow_wrapper", ("mechanism", "jaw"), "gear_inertia_kg_m2", -1e-9, 0.0),
    ("flow_wrapper", ("mechanism", "jaw"), "inertia_ratio_limit", 0.0, 1.0),
    ("flow_wrapper", ("mechanism", "jaw"), "table_points", 1, 2),
    ("flow_wrapper", ("mechanism", "jaw"), "torque_reserve", 1.0, 0.5),
    ("flow_wrapper", ("mechanism", "jaw"), "gear_ratios", [0.0, 1.0], [1.0]),
    ("knife_cutter", ("drive",), "gear_ratio", 0.0, 1e-3),
    ("knife_cutter", ("drive",), "gear_efficiency", 1.01, 1.0),
    ("knife_cutter", ("drive",), "rotor_inertia_kg_m2", -1e-9, 0.0),
    ("knife_cutter", ("drive",), "flywheel_kg_m2", -1e-9, 0.0),
    ("knife_cutter", ("drive",), "breakdown_ratio", 1.0, 1.01),
    ("knife_cutter", ("drive",), "rated_rpm", 1500.0, 1499.0),
    ("knife_cutter", ("drive",), "motor", "diesel", "induction"),
    ("knife_cutter", ("balance", 0), "objective", "min", "peak_force"),
    ("knife_cutter", ("balance", 0), "torque_weight", -1e-9, 0.0),
    ("knife_cutter", ("balance", 0), "max_mass_radius_kg_m", 0.0, 1e-9),
]

#: Keys that a table takes only beside another key's value: that value is set
#: before the key's range is tried.
ALONGSIDE: dict[str, dict[str, Any]] = {"torque_weight": {"objective": "rms_force+torque"}}


@pytest.mark.parametrize(
    ("source", "path", "key", "outside", "inside"),
    RANGES,
    ids=[f"{c[0]}-{c[2]}" for c in RANGES],
)
def test_documented_range_is_enforced(
    source: str, path: tuple[Any, ...], key: str, outside: Any, inside: Any
) -> None:
    table = {
        ("machine",): "machine",
        ("cyclogram",): "cyclogram",
        ("operation",): "operation",
        ("drive",): "drive",
        ("balance",): "balance",
    }.get(path[:1])
    if table is None:
        kind = at(data(source), path[:2]).get("kind")
        sub = {
            "segment": "cam.segment",
            "mass": "linkage.mass",
            "lengths": "linkage.lengths",
            "friction": "linkage.friction",
        }
        table = f"{kind}.{path[2]}" if kind == "servo" and len(path) > 2 else None
        table = table or (sub[path[2]] if len(path) > 2 else kind)
    assert key in documented(table)
    d = data(source)
    at(d, path).update(ALONGSIDE.get(key, {}))
    at(d, path)[key] = outside
    assert key in refused(d)
    d = data(source)
    at(d, path).update(ALONGSIDE.get(key, {}))
    at(d, path)[key] = inside
    build(d)


def test_every_kind_has_a_range_checked() -> None:
    kinds = set()
    for source, path, *_ in RANGES:
        if path[0] == "mechanism":
            kinds.add(at(data(source), path[:2])["kind"])
    assert kinds == set(KINDS)


# ---------------------------------------------------------------- rendering
def test_page_is_valid_restructuredtext() -> None:
    docutils_core = pytest.importorskip("docutils.core")
    page = _keydocs.render_page()
    warnings = io.StringIO()
    tree = docutils_core.publish_doctree(
        page,
        settings_overrides={"report_level": 2, "halt_level": 2, "warning_stream": warnings},
    )
    assert warnings.getvalue() == ""
    text = tree.astext()
    for table, keys in TABLES.items():
        assert _keydocs.tables()[table].title in text
        for k in keys:
            assert k.name in text
    for kind, cls in KINDS.items():
        first = " ".join((cls.__doc__ or "").split()[:3])
        assert first in text, kind


@pytest.mark.parametrize("table", sorted(TABLES))
def test_each_table_renders_one_row_per_key(table: str) -> None:
    text = _keydocs.render_table(table)
    assert text.count("   * - ") == len(TABLES[table]) + 1


def _extension() -> Any:
    import importlib.util

    path = Path(__file__).resolve().parents[2] / "docs" / "_ext" / "keys_reference.py"
    spec = importlib.util.spec_from_file_location("keys_reference", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_extension_writes_the_page(tmp_path: Path) -> None:
    ext = _extension()
    page = ext.write(tmp_path)
    assert page == tmp_path / "reference" / "_generated" / "machine_format.rst"
    assert page.read_text(encoding="utf-8") == _keydocs.render_page()
    stamp = page.stat().st_mtime_ns
    ext.write(tmp_path)
    assert page.stat().st_mtime_ns == stamp  # unchanged: not rewritten


@pytest.mark.slow
def test_extension_in_a_sphinx_build_without_warnings(tmp_path: Path) -> None:
    sphinx_build = pytest.importorskip("sphinx.cmd.build")
    src = tmp_path / "src"
    src.mkdir()
    ext_dir = Path(__file__).resolve().parents[2] / "docs" / "_ext"
    (src / "conf.py").write_text(
        f"import sys\nsys.path.insert(0, {str(ext_dir)!r})\nproject = 'cyclomech'\n"
        "extensions = ['keys_reference']\n",
        encoding="utf-8",
    )
    (src / "index.rst").write_text(
        "cyclomech\n=========\n\n.. toctree::\n\n   reference/_generated/machine_format\n",
        encoding="utf-8",
    )
    status = sphinx_build.build_main(["-W", "-q", "-b", "html", str(src), str(tmp_path / "out")])
    assert status == 0
    html = (tmp_path / "out" / "reference" / "_generated" / "machine_format.html").read_text(
        encoding="utf-8"
    )
    assert "speed_fluctuation" in html and "kind = transfer" in html


@pytest.mark.parametrize(
    ("source", "path", "key", "value"),
    [
        ("cam", ("mechanism", "c"), "inertia_kg_m2", 0.01),
        ("cam", ("mechanism", "c"), "max_vibration_deg", 0.05),
        ("cam", ("mechanism", "c", "segment", 0), "stroke_deg", 5.0),
        ("stb_loom", ("mechanism", "lifter cam"), "mass_kg", 0.5),
        ("stb_loom", ("mechanism", "lifter cam", "segment", 0), "load_n", 1.0),
    ],
)
def test_keys_of_the_other_follower_are_refused(
    source: str, path: tuple[Any, ...], key: str, value: Any
) -> None:
    """What "refused with an oscillating (a translating or flat) follower" says."""
    table = "cam.segment" if "segment" in path else "cam"
    assert "refused with" in doc(table, key).valid
    d = data(source)
    at(d, path)[key] = value
    assert key in refused(d)
