"""The machine report's files as a unit: what an interrupted write leaves."""

from __future__ import annotations

import cyclomech as cm
import pytest


def test_an_interrupted_report_leaves_no_file_that_looks_done(tmp_path, monkeypatch) -> None:
    """A new user's Ctrl-C 2.5 s into `cyclomech run` left results.json and the CSVs
    (no report.html): a folder that looked finished. results.json and report.html
    are written last and an earlier run's are removed first."""
    from cyclomech.machine import _report, analyze, write_report

    r = analyze(cm.Machine.example(), progress=False)
    write_report(r, tmp_path, figures=False)  # an earlier, complete run
    assert (tmp_path / "results.json").exists() and (tmp_path / "report.html").exists()

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(_report, "_figures", interrupted)
    pytest.importorskip("matplotlib")
    with pytest.raises(KeyboardInterrupt):
        write_report(r, tmp_path, figures=True)
    assert not (tmp_path / "results.json").exists()
    assert not (tmp_path / "report.html").exists()
