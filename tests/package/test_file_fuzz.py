"""Every file reader checks the types of what it reads (issue 31, item 8).

A linkage file with ``ground = [["A", "D"]]`` ended in ``TypeError: unhashable
type: 'list'`` with a traceback. The rule: whatever a TOML file holds at any
key, table or array entry, reading it either succeeds or raises a
:class:`cyclomech.CyclomechError` naming what is wrong, never another exception.

The test replaces, one at a time, every value of every example file (tables,
arrays and their entries included, down to the cam's segments) by each of a
set of values of the wrong type or range, and reads the result with the reader
the command would use (about 11 000 files).
"""

from __future__ import annotations

import copy
import tomllib
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import cyclomech as cm
import pytest
from cyclomech import _toml
from cyclomech.cam import CamDesign
from cyclomech.cli import main
from cyclomech.transfer.cli import read_transfer_file

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: Values of the wrong type (or range) for some key of every file.
BAD: list[Any] = [
    1, 1.5, -1.0, float("nan"), float("inf"), True, "x", "", [], [1], [["A", "D"]],
    {"a": 1}, [{"a": 1}], [1.0, "x"],
]  # fmt: skip


def _through_load(read: Callable[[str], Any], data: dict[str, Any]) -> Any:
    """``read("f.toml")`` with the file's parsed content ``data`` (the readers that
    take a path load it through ``_toml.load``)."""
    load = _toml.load
    _toml.load = lambda path: (data, "f.toml")
    try:
        return read("f.toml")
    finally:
        _toml.load = load


def _reader(data: dict[str, Any]) -> Callable[[dict[str, Any]], Any]:
    """The reader of the command that takes a file of this layout."""
    if "machine" in data:
        # (as if read from the examples' folder: a servo's catalogue is beside it)
        return lambda d: cm.Machine.from_dict(d, str(EXAMPLES / "f.toml"))
    if "linkage" in data:
        return lambda d: _through_load(cm.Linkage.from_toml, d)
    if "stop" in data:
        return lambda d: _through_load(cm.impact.ImpactStudy.from_toml, d)
    if "press" in data:
        return lambda d: _through_load(cm.press.PressStudy.from_toml, d)
    if "cyclogram" in data:
        return lambda d: cm.Cyclogram.from_dict(d, "f.toml")
    if "transfer" in data:
        return lambda d: _through_load(read_transfer_file, d)
    assert "cam" in data
    return lambda d: _through_load(CamDesign.from_toml, d)


def _paths(node: Any, prefix: tuple[Any, ...] = ()) -> Iterator[tuple[Any, ...]]:
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, value in items:
        yield (*prefix, key)
        if isinstance(value, dict | list):
            yield from _paths(value, (*prefix, key))


def _light(data: dict[str, Any]) -> dict[str, Any]:
    """The file with each knife drive's synthesis made light: two generations of five
    candidates and wide tolerances, which the scheme's preset meets (a six-bar dwell
    linkage's: five generations, its residual limit wide). Every value a
    wrong one replaces that still reads runs a synthesis (each of the three schemes
    with ``compare``): at the file's budget the test took 115 s, here a few. What is
    checked, the reading of every key, is the same."""
    for table in data.get("mechanism", {}).values():
        syn = table.get("synthesize") if isinstance(table, dict) else None
        if isinstance(syn, dict) and syn.get("scheme") in ("br125", "br136", "brp4"):
            syn.update(popsize=5, maxiter=2, stroke_tol_m=0.1, cut_tol_deg=60.0)
        elif isinstance(syn, dict) and syn.get("scheme") == "dwell_sixbar":
            # (at this budget the rocker moves a few degrees over the dwell: the
            # limit widened so that the file reads)
            syn.update(popsize=5, maxiter=5, max_residual_deg=10.0)
    return data


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_any_wrong_value_is_a_cyclomech_error(path: Path) -> None:
    data = _light(tomllib.loads(path.read_text(encoding="utf-8")))
    read = _reader(data)
    read(copy.deepcopy(data))  # the file itself reads
    others: list[str] = []
    calls = 0
    for where in _paths(data):
        for bad in BAD:
            changed = copy.deepcopy(data)
            node = changed
            for key in where[:-1]:
                node = node[key]
            node[where[-1]] = bad
            calls += 1
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # a warning has a valid reading
                    read(changed)
            except cm.CyclomechError:
                pass
            except Exception as e:
                others.append(f"{'.'.join(map(str, where))} = {bad!r}: {type(e).__name__}: {e}")
    assert calls == len(BAD) * len(list(_paths(data))) > 100  # the transfer file: 140
    assert not others, f"{len(others)} of {calls}:\n" + "\n".join(others[:20])


def test_the_issues_linkage_file_is_exit_2(tmp_path, capsys) -> None:
    text = (EXAMPLES / "crank_rocker.toml").read_text(encoding="utf-8")
    start = text.index("ground = ")
    end = text.index("\n", start)
    bad = tmp_path / "bad.toml"
    bad.write_text(text[:start] + 'ground = [["A", "D"]]' + text[end:], encoding="utf-8")
    assert main(["linkage", str(bad), "--out", str(tmp_path / "o"), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "ground #1 = ['A', 'D'] must be a joint name (a string)" in err
    assert "Traceback" not in err
