"""Output paths of the public writers (issue 31, item 9).

``write_report(result, out="")`` wrote the report into the current folder. A path
that cannot be meant (empty, blank, not a path, a folder where a file is wanted,
a file where a folder is wanted, a folder that does not exist) is an InputError
naming the argument, raised before anything is written.
"""

from __future__ import annotations

import os
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.machine import analyze, write_report


@pytest.fixture(scope="module")
def result() -> cm.machine.MachineResult:
    return analyze(cm.Machine.example(), progress=False)


@pytest.mark.parametrize(
    ("out", "error", "match"),
    [
        ("", cm.InputError, r"out must be a path \(a non-empty str or Path\); got ''"),
        ("   ", cm.InputError, r"out must be a path"),
        # A wrong object is a TypeError naming the argument (the library's rule).
        (None, TypeError, r"out must be a str or PathLike; got NoneType"),
        (3, TypeError, r"out must be a str or PathLike; got int"),
        (b"out", TypeError, r"out must be a str or PathLike; got bytes"),
    ],
)
def test_write_report_refuses_a_path_that_cannot_be_meant(
    result, tmp_path, monkeypatch, out, error, match
) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(error, match=match):
        write_report(result, out, figures=False)
    assert list(tmp_path.iterdir()) == []  # nothing written in the current folder


def test_write_report_refuses_a_file_as_its_folder(result, tmp_path) -> None:
    f = tmp_path / "report"
    f.write_text("mine")
    with pytest.raises(cm.InputError, match="is a file, not a folder"):
        write_report(result, f, figures=False)
    assert f.read_text() == "mine"


def test_write_report_refuses_what_is_not_a_result(tmp_path) -> None:
    with pytest.raises(TypeError, match="result must be a MachineResult; got dict"):
        write_report({"speed_limit": 1}, tmp_path, figures=False)  # type: ignore[arg-type]


def test_write_report_takes_a_path_object_and_a_str(result, tmp_path) -> None:
    a = write_report(result, tmp_path / "a", figures=False)
    b = write_report(result, os.fspath(tmp_path / "b"), figures=False)
    assert [p.name for p in a] == [p.name for p in b]
    assert (tmp_path / "a" / "report.html").is_file()


@pytest.mark.parametrize(
    ("bad", "match"),
    [
        ("", "path must be a path"),
        ("folder", "is a folder; give a file name"),
        ("no/such/s.npz", "does not exist; make it first"),
    ],
)
def test_file_writers_refuse_a_path_that_cannot_be_meant(tmp_path, bad, match) -> None:
    (tmp_path / "folder").mkdir()
    target = "" if bad == "" else tmp_path / bad
    sweep = cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0]})
    with pytest.raises(cm.InputError, match=match):
        sweep.write(target)
    cyclogram = cm.Machine.example().cyclogram
    with pytest.raises(cm.InputError, match=match):
        cyclogram.to_toml(target if bad else "")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder"]


def test_to_toml_without_a_path_only_returns_the_text(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    text = cm.Machine.example().cyclogram.to_toml()
    assert text.startswith("[cyclogram]") and list(Path(".").iterdir()) == []
