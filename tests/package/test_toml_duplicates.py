"""A key or table given twice names itself, its table, the file and the line.

tomllib says only "Cannot overwrite a value (at line 42, column 28)". The reference
here is the construction: a copy of each example with one of its key lines (or a
table header) repeated right below it, so the duplicate's line, key and table are
known without the parser.
"""

from __future__ import annotations

import re
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech import _toml
from cyclomech.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
KEY_LINE = re.compile(r"^\s*([A-Za-z0-9_]+)\s*=")
HEADER = re.compile(r"^\s*(\[\[?[^\]]+\]\]?)")


def _duplicated(text: str, every: int = 7) -> list[tuple[str, int, str, str]]:
    """Copies of ``text`` with a key line repeated below it (every ``every``-th key
    line, and the first): (text, the duplicate's line, its key, its table)."""
    lines = text.splitlines(keepends=True)
    out = []
    table = "the top level"
    seen = 0
    multiline = False
    for i, line in enumerate(lines):
        if h := HEADER.match(line):
            table = f"table {h.group(1)}"
        m = KEY_LINE.match(line)
        if m and not multiline:
            if seen % every == 0 and line.rstrip().endswith(tuple("0123456789\"]'e")):
                dup = [
                    *lines[: i + 1],
                    line if line.endswith("\n") else line + "\n",
                    *lines[i + 1 :],
                ]
                out.append(("".join(dup), i + 2, m.group(1), table))
            seen += 1
        # a value spanning lines (an array): its continuation lines are no keys
        multiline = line.count("[") > line.count("]") if m or multiline else False
    return out


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_a_key_given_twice_names_the_key_its_table_and_the_line(path, tmp_path):
    cases = _duplicated(path.read_text(encoding="utf-8"))
    assert cases
    for text, line, key, table in cases:
        f = tmp_path / path.name
        f.write_text(text, encoding="utf-8")
        with pytest.raises(cm.InputError) as e:
            _toml.load(f)
        msg = str(e.value)
        assert msg.startswith(f"{f}: not valid TOML: line {line}: key {key!r} of {table} "), msg
        assert "is given twice" in msg


def test_a_table_declared_twice_names_it_and_the_command_says_so(tmp_path, capsys):
    text = (EXAMPLES / "stb_loom.toml").read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    n = next(i for i, ln in enumerate(lines) if ln.startswith("[machine]"))
    f = tmp_path / "loom.toml"
    f.write_text("".join([*lines, "\n", lines[n], "name = 'again'\n"]), encoding="utf-8")
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert f"{f}: not valid TOML: line {len(lines) + 2}: table [machine] is declared twice" in err


def test_a_table_over_a_value_and_a_dotted_key_say_what_they_are(tmp_path):
    for text, expected in [
        ("x = 1\n[x]\n", "line 2: table [x] names a key that already holds a value"),
        ("a = 1\na.b = 2\n", "line 2: key 'a.b' of the top level is given twice, or a part"),
        ('[t]\n"q k" = 1\n"q k" = 2\n', 'line 3: key "q k" of table [t] is given twice'),
    ]:
        f = tmp_path / "f.toml"
        f.write_text(text, encoding="utf-8")
        with pytest.raises(cm.InputError, match=re.escape(expected)):
            _toml.load(f)


def test_other_syntax_errors_are_tomllibs_own(tmp_path):
    f = tmp_path / "f.toml"
    f.write_text("[t\nx = 1\n", encoding="utf-8")
    with pytest.raises(cm.InputError) as e:
        _toml.load(f)
    assert "not valid TOML" in str(e.value) and "twice" not in str(e.value)
