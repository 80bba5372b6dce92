"""Names in a machine file: every operation's mechanism is a mechanism of the
machine or declared unmodelled, and a name is a string (issue 31, item 3).

Renaming ``[mechanism.lifter]`` to ``[mechanism.lifterx]`` in the loom passed with a
warning and exit 0; a number where a name belongs was read as text.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LOOM = EXAMPLES / "stb_loom.toml"


def _run(tmp_path: Path, text: str, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    code = main(["run", str(path), "--out", str(tmp_path / "out"), "--no-plot", "--quiet"])
    return code, capsys.readouterr().err


def test_a_misspelt_mechanism_table_is_an_error(tmp_path, capsys) -> None:
    text = LOOM.read_text(encoding="utf-8").replace("[mechanism.lifter]", "[mechanism.lifterx]")
    code, err = _run(tmp_path, text, capsys)
    assert code == 2
    # Both names, the nearest match and the way to declare an unmodelled one.
    assert "mechanism = 'lifter' is not a mechanism of the machine" in err
    assert "Did you mean 'lifterx'?" in err and "[machine] unmodelled" in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_an_operation_naming_no_mechanism_far_from_all_is_an_error() -> None:
    data = tomllib.loads(LOOM.read_text(encoding="utf-8"))
    data["machine"]["unmodelled"].remove("weft insertion")
    with pytest.raises(cm.InputError, match=r"mechanism = 'weft insertion' is not") as e:
        cm.Machine.from_dict(data, "loom.toml")
    assert "Did you mean" not in str(e.value)  # nothing near: no guess offered
    assert "'lifter', 'lifter cam'" in str(e.value)  # the machine's tables


@pytest.mark.parametrize(
    ("where", "value", "match"),
    [
        ("operation", 1.0, r"mechanism must be a name \(a string\); got 1.0"),
        ("operation name", 1.0, r"name must be a name \(a string\); got 1.0"),
        ("cyclogram", 1.0, r"\[cyclogram\]: name must be the cyclogram's name .*got 1.0"),
        ("constraint", 2, r"constraint's name must be a string; got 2"),
    ],
)
def test_a_number_where_a_name_belongs(tmp_path, capsys, where, value, match) -> None:
    data = tomllib.loads(LOOM.read_text(encoding="utf-8"))
    if where == "operation":
        data["operation"][0]["mechanism"] = value
    elif where == "operation name":
        data["operation"][0]["name"] = value
    elif where == "cyclogram":
        data["cyclogram"]["name"] = value
    else:
        data["constraint"] = [
            {"name": value, "terms": [{"from": "1", "to": "3", "coeff": 1.0}], "sense": "<=",
             "rhs": 100.0}
        ]  # fmt: skip
    with pytest.raises(cm.InputError, match=match):
        cm.Machine.from_dict(data, "loom.toml")


def test_the_cli_gives_exit_2_for_a_number_as_mechanism(tmp_path, capsys) -> None:
    text = LOOM.read_text(encoding="utf-8").replace('mechanism = "lifter"', "mechanism = 1.0", 1)
    code, err = _run(tmp_path, text, capsys)
    assert code == 2 and "mechanism must be a name" in err and "got 1.0" in err


@pytest.mark.parametrize(
    ("unmodelled", "match"),
    [
        ('"clamp"', r"unmodelled = 'clamp' must be a list of mechanism names"),
        ('["weft insertion", 3]', r"must be a list of mechanism names"),
        ('["weft insertion", "lifter"]', r"lists 'lifter', which is also a \[mechanism.lifter\]"),
        ('["weft insertion", "weft insertoin"]',
         r"lists 'weft insertoin', which no operation names"),
    ],
)  # fmt: skip
def test_the_unmodelled_list_is_checked(unmodelled, match) -> None:
    text = LOOM.read_text(encoding="utf-8")
    start = text.index("unmodelled = [")
    end = text.index("]", start) + 1
    data = tomllib.loads(text[:start] + f"unmodelled = {unmodelled}" + text[end:])
    with pytest.raises(cm.InputError, match=match):
        cm.Machine.from_dict(data, "loom.toml")


def test_every_example_declares_its_unmodelled_mechanisms() -> None:
    """The examples read without an error or a warning (warnings are errors here),
    and each operation's mechanism is a table or declared unmodelled."""
    for path in sorted(EXAMPLES.glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        if "machine" not in data:
            continue
        m = cm.Machine.from_toml(path)
        declared = set(data["machine"].get("unmodelled", []))
        for op in m.cyclogram.operations:
            assert (
                op.mechanism is None or op.mechanism in m.mechanisms or (op.mechanism in declared)
            ), (path.name, op.mechanism)


def test_the_python_api_refuses_a_number_as_a_name() -> None:
    with pytest.raises(cm.InputError, match="mechanism must be a name"):
        cm.Operation("a", "b", mechanism=1.0)  # type: ignore[arg-type]
    with pytest.raises(cm.InputError, match="name must be the cyclogram's name"):
        cm.Cyclogram(1.0)  # type: ignore[arg-type]
    assert cm.Operation("a", "b", name="feed", mechanism="feeder").mechanism == "feeder"
