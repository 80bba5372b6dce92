"""The user guide's Python blocks run as written (from a folder holding the
repository's examples), and its generated transcripts are what the commands print."""

from __future__ import annotations

import doctest
import importlib.util
import re
import shutil
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide"
BLOCK = re.compile(r"^\.\. code-block:: python\n\n((?:(?:   .*)?\n)+)", re.MULTILINE)


def _blocks() -> list[tuple[str, str]]:
    found = []
    for page in sorted(GUIDE.glob("*.rst")):
        for k, m in enumerate(BLOCK.finditer(page.read_text(encoding="utf-8"))):
            code = "\n".join(line[3:] for line in m.group(1).splitlines())
            found.append((f"{page.stem}[{k}]", code))
    return found


BLOCKS = _blocks()


def test_the_guide_has_python_blocks() -> None:
    assert any(name.startswith("machine") for name, _ in BLOCKS)


@pytest.mark.parametrize("name,code", BLOCKS, ids=[n for n, _ in BLOCKS])
def test_python_block_runs(
    name: str, code: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("matplotlib")
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"docs/guide/{name}", "exec"), {})
    if "write_report" in code:
        assert (tmp_path / "out" / "stb_loom" / "report.html").is_file()


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    """The extension's transcripts as a docs build writes them: each command run once
    for the two tests that read them."""
    return _machine_run().write(tmp_path_factory.mktemp("docs"))


def test_transcripts_are_the_commands_output(written: list[Path]) -> None:
    text = written[1].read_text(encoding="utf-8")
    assert written[1].name == "loom_sweep.txt"
    assert text.startswith("$ cyclomech sweep examples/stb_loom.toml")
    assert "4 designs × 31 speeds = 124 points" in text
    assert "speed limit over the designs:" in text
    assert "/tmp" not in text and "Wrote out/stb_loom_sweep/sweep.parquet" in text


def _machine_run() -> Any:
    path = ROOT / "docs" / "_ext" / "machine_run.py"
    spec = importlib.util.spec_from_file_location("machine_run", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_extension_writes_both_transcripts_and_its_examples_run(written: list[Path]) -> None:
    ext = _machine_run()
    paths = written
    assert [p.name for p in paths] == ["loom_run.txt", "loom_sweep.txt"]
    run = paths[0].read_text(encoding="utf-8")
    assert "Speed limit: " in run and "Report: out/stb_loom/report.html" in run
    assert doctest.testmod(ext).failed == 0


def test_a_failing_command_fails_the_build() -> None:
    ext = _machine_run()
    with pytest.raises(RuntimeError, match="exited with status 2"):
        ext.transcript(["run", "examples/no_such_file.toml", "--out", "out/x"], ROOT)
