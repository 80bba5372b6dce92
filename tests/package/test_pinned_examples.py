"""The example machines' outputs, pinned before the house is rebuilt (issue 17).

`results.json`, the CSV files and the `cyclomech run` summary of every example
machine are compared with the copies in ``tests/package/pinned/<example>/``, written by this
test at commit time (``CYCLOMECH_PIN=1 python -m pytest tests/package/test_pinned_examples.py``
rewrites them). A restructuring must leave them as they are: text exactly, numbers to
1e-9 relative (the kernels agree bit for bit across instruction sets, but the pin
must not depend on the processor CI happens to run on). What is not a result is left
out: the wall times (``seconds``) and the file's path as given (``source``).
"""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path
from typing import Any

import cyclomech as cm
import pytest
from cyclomech.machine import analyze, write_report

ROOT = Path(__file__).resolve().parents[2]
PINNED = Path(__file__).resolve().parent / "pinned"
EXAMPLES = (
    "stb_loom",
    "knife_cutter",
    "extrusion_press_line",
    "rotor_line",
    "knife_cutter_synthesized",
    "lifter_cam_sized",
    "transfer_arm_synthesized",
)
WRITE = os.environ.get("CYCLOMECH_PIN", "") not in ("", "0")
RTOL = 1e-9
#: Not results: wall times and the path the file was given by.
VOLATILE = ("seconds", "source")


def _same(got: Any, want: Any, where: str) -> None:
    """Recursive comparison: text and structure exactly, numbers to RTOL."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and sorted(got) == sorted(want), where
        for k in want:
            _same(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), where
        for i, (g, w) in enumerate(zip(got, want, strict=True)):
            _same(g, w, f"{where}[{i}]")
    elif isinstance(want, bool) or want is None or isinstance(want, str):
        assert got == want, f"{where}: {got!r} != {want!r}"
    elif isinstance(want, int | float):
        assert isinstance(got, int | float) and not isinstance(got, bool), where
        if math.isnan(want):
            assert math.isnan(got), f"{where}: {got} != nan"
            return
        assert math.isclose(got, want, rel_tol=RTOL, abs_tol=1e-12), f"{where}: {got} != {want}"
    else:  # pragma: no cover - JSON holds nothing else
        raise AssertionError(f"{where}: unexpected {want!r}")


def _cell(text: str) -> Any:
    try:
        return float(text)
    except ValueError:
        return text


#: Tables over the cycle (main_shaft.csv, <mechanism>_forces.csv: 3600 rows)
#: are pinned at every 40th row, the header kept.
EVERY = 40


def _table(path: Path) -> list[list[Any]]:
    with path.open(newline="", encoding="utf-8") as f:
        rows = [[_cell(c) for c in row] for row in csv.reader(f)]
    return rows if len(rows) <= 1000 else [rows[0], *rows[1::EVERY]]


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_outputs_are_pinned(example: str, tmp_path: Path, cli_run) -> None:
    m = cm.Machine.from_toml(ROOT / "examples" / f"{example}.toml")
    write_report(analyze(m, progress=False), tmp_path, figures=False)
    results = json.loads((tmp_path / "results.json").read_text("utf-8"))
    for k in VOLATILE:
        results.pop(k)
    tables = {p.name: _table(p) for p in sorted(tmp_path.glob("*.csv"))}
    run = cli_run(ROOT / "examples" / f"{example}.toml", "--no-plot", "--quiet")
    out = run.out
    assert run.code == 0
    summary = run.stdout.replace(str(out), "<out>").replace(str(ROOT), "<root>")
    # The report animates every mechanism of every example (the machine moving).
    page = (out / "report.html").read_text("utf-8")
    data = json.loads(page.split("id='cm-anim-data'>", 1)[1].split("</script>", 1)[0])
    assert [s["name"] for s in data["scenes"]] == list(m.mechanisms)
    here = PINNED / example
    if WRITE:
        here.mkdir(parents=True, exist_ok=True)
        (here / "results.json").write_text(
            json.dumps(results, indent=1, ensure_ascii=False) + "\n", encoding="utf-8"
        )
        (here / "tables.json").write_text(
            json.dumps(tables, indent=1, ensure_ascii=False) + "\n", encoding="utf-8"
        )
        (here / "summary.txt").write_text(summary, encoding="utf-8")
    _same(results, json.loads((here / "results.json").read_text("utf-8")), "results.json")
    _same(tables, json.loads((here / "tables.json").read_text("utf-8")), "csv")
    assert summary == (here / "summary.txt").read_text("utf-8")
