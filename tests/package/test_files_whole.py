"""Output files are written whole or not at all (cyclomech._files.whole): a Ctrl-C
while ``cyclomech run`` drew its figures left a 124-byte PNG (a new user's trial).
"""

from __future__ import annotations

from pathlib import Path

import cyclomech as cm
import matplotlib.figure
import pytest
from cyclomech._files import whole
from cyclomech.machine import analyze, write_report

ROOT = Path(__file__).resolve().parents[2]


def test_an_interrupted_block_leaves_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "x.csv"
    p.write_text("old\n")
    with pytest.raises(KeyboardInterrupt), whole(p) as tmp:
        tmp.write_text("half")
        raise KeyboardInterrupt
    assert p.read_text() == "old\n" and sorted(tmp_path.iterdir()) == [p]
    with whole(p) as tmp:
        assert tmp.suffix == ".csv" and tmp.parent == p.parent
        tmp.write_text("new\n")
    assert p.read_text() == "new\n" and sorted(tmp_path.iterdir()) == [p]


def test_a_report_interrupted_in_a_figure_leaves_no_broken_figure(tmp_path, monkeypatch):
    r = analyze(cm.Machine.from_toml(ROOT / "examples" / "stb_loom.toml"), progress=False)
    real = matplotlib.figure.Figure.savefig
    calls = []

    def cut(self, fname, *args, **kwargs):  # the third figure: 124 bytes, then Ctrl-C
        calls.append(fname)
        if len(calls) == 3:
            Path(fname).write_bytes(b"\x89PNG" + b"\0" * 120)
            raise KeyboardInterrupt
        return real(self, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", cut)
    with pytest.raises(KeyboardInterrupt):
        write_report(r, tmp_path / "out", figures=True)
    figures = sorted((tmp_path / "out" / "figures").iterdir())
    assert len(figures) == 2 and all(f.stat().st_size > 1000 for f in figures), figures
    assert not any(f.name.startswith(".") for f in (tmp_path / "out").rglob("*"))
    assert not (tmp_path / "out" / "report.html").exists()
