"""Event names in files are strings (new-user review): ``from = 1`` was read as the
event "1" (and ``events = [1, ...]``, a term's ``from = 3``) without a word. Every
reader of an event name (the cyclogram's tables, a cam segment's and a cam_stop's
``arc``, a mechanism's ``phase.event``, an impact study's ``arc``) now refuses a
number through one check, ``cyclomech._toml.event`` / ``events``, naming the file,
the table, the key, the value and what is valid."""

from __future__ import annotations

import re
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech import _toml

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: The one check's words, in every message.
WORDS = "must be an event name, a string that is not blank (event names are strings"

# (file, the text to replace once, its replacement, fragments of the message)
CASES = {
    "operation from": (
        "stb_loom.toml",
        'from = "1"\nto = "3"',
        'from = 1\nto = "3"',
        ["[[operation]] #1", "from = 1 ", 'write from = "1"'],
    ),
    "operation to": (
        "stb_loom.toml",
        'from = "1"\nto = "3"',
        'from = "1"\nto = 3',
        ["[[operation]] #1", "to = 3 ", 'write to = "3"'],
    ),
    "events": (
        "stb_loom.toml",
        'events = ["1", "2",',
        'events = [1, "2",',
        [
            "[cyclogram]",
            "events = [1, '2'",
            "an array of event names: 1 must",
            'write events = ["1",',
        ],
    ),
    "limiting": (
        "stb_loom.toml",
        'limiting = ["10.1", "10.2"]',
        'limiting = [10.1, "10.2"]',
        ["[cyclogram]", "limiting = [10.1, '10.2']", 'write limiting = ["10.1", "10.2"]'],
    ),
    "cam_stop arc": (
        "stb_loom.toml",
        'arc = ["3", "7"]               #',
        "arc = [3, 7]               #",
        ["[mechanism.lifter]", "arc = [3, 7] must be [from, to], two", 'write arc = ["3", "7"]'],
    ),
    "cam segment arc": (
        "stb_loom.toml",
        'arc = ["1", "3"]',
        'arc = ["1", 3]',
        ["[mechanism.lifter cam]", "segment 1", "arc = ['1', 3]", 'write arc = ["1", "3"]'],
    ),
    "phase event": (
        "knife_cutter.toml",
        'event = "clamped"',
        "event = 2",
        ["[mechanism.knife] phase", "event = 2 ", 'write event = "2"'],
    ),
    "a blank name": (
        "stb_loom.toml",
        'from = "1"\nto = "3"',
        'from = " "\nto = "3"',
        ["[[operation]] #1", "from = ' '"],
    ),
}


def _write(tmp_path: Path, name: str, old: str, new: str) -> Path:
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    assert text.count(old) >= 1, old
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


@pytest.mark.parametrize(("name", "old", "new", "fragments"), CASES.values(), ids=CASES.keys())
def test_a_number_for_an_event_name_is_refused_in_a_machine_file(
    tmp_path: Path, name: str, old: str, new: str, fragments: list[str]
) -> None:
    path = _write(tmp_path, name, old, new)
    with pytest.raises(cm.InputError) as err:
        cm.Machine.from_toml(path)
    assert isinstance(err.value, ValueError)
    msg = str(err.value)
    assert msg.startswith(f"{path}: "), msg
    assert WORDS in msg
    for fragment in fragments:
        assert fragment in msg, (fragment, msg)


def test_a_number_in_a_constraint_term_is_refused_in_a_cyclogram_file(tmp_path: Path) -> None:
    old = 'terms = [{ from = "3", to = "7", coeff = -0.003 }]'
    path = _write(tmp_path, "stb_group1.toml", old, old.replace('to = "7"', "to = 7"))
    with pytest.raises(cm.InputError, match=re.escape(WORDS)) as err:
        cm.Cyclogram.from_toml(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}: [[constraint]] #1: terms #1: to = 7 "), msg
    assert 'write to = "7"' in msg


def test_a_number_in_an_impact_study_arc_is_refused(tmp_path: Path) -> None:
    path = _write(tmp_path, "stb_lifter.toml", 'arc = ["3", "7"]', 'arc = ["3", 7]')
    with pytest.raises(cm.InputError, match=re.escape(WORDS)) as err:
        cm.impact.ImpactStudy.from_toml(path)
    assert str(err.value).startswith(f"{path}: [study]: arc = ['3', 7] must be [from, to]"), (
        err.value
    )


def test_the_same_files_with_strings_still_read() -> None:
    """The examples, with their names in quotes, read as before (the control)."""
    for name in ("stb_loom.toml", "knife_cutter.toml"):
        cm.Machine.from_toml(EXAMPLES / name)
    cm.Cyclogram.from_toml(EXAMPLES / "stb_group1.toml")
    cm.impact.ImpactStudy.from_toml(EXAMPLES / "stb_lifter.toml")


@pytest.mark.parametrize("bad", [1, 1.5, True, None, "", "  ", ["a"], {"a": 1}])
def test_the_one_check(bad: object) -> None:
    with pytest.raises(cm.InputError, match=re.escape(WORDS)):
        _toml.event({"from": bad}, "from", "f.toml: [x]")
    with pytest.raises(cm.InputError, match=r"^f\.toml: \[x\]: arc = "):
        _toml.events({"arc": ["a", bad]}, "arc", "f.toml: [x]", arc=True)
    assert _toml.event({"from": "1"}, "from", "w") == "1"
    assert _toml.events({"arc": ["1", "b"]}, "arc", "w", arc=True) == ["1", "b"]
    with pytest.raises(cm.InputError, match=re.escape("arc = ['a'] must be [from, to]")):
        _toml.events({"arc": ["a"]}, "arc", "w", arc=True)


def test_an_event_listed_twice_is_refused(tmp_path) -> None:
    """A new user's typo, events = ["1", "2", "3", "3", …], ran with exit 0: a
    repeated event is a mistake the file's reader names (exit 2 from the CLI)."""
    text = (EXAMPLES / "stb_loom.toml").read_text("utf-8")
    head = 'events = ["1", "2", "3",'
    assert head in text
    bad = tmp_path / "twice.toml"
    bad.write_text(text.replace(head, 'events = ["1", "2", "3", "3",', 1), "utf-8")
    with pytest.raises(cm.InputError, match=r"\[cyclogram\].*events = .*names the event '3' twice"):
        cm.Machine.from_toml(bad)
