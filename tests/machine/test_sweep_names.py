"""One name for each key figure wherever a user reads it (new-user review): the
sweep's columns (``cm.sweep``, ``cyclomech sweep``'s Parquet file), the speed
sweep's attributes and the run report's CSV and JSON. The productivity was
``productivity`` in the sweep and ``productivity_per_min`` in the report; it is
``productivity_per_min`` (its unit in the name, like ``limiting_deg``) in each, and
a sweep file written under the old name still reads."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main

ROOT = Path(__file__).resolve().parents[2]
# The loom's stop alone (no cam): quick, and it has a stop, so max_rebound_m too.
LOOM = str(ROOT / "tests" / "machine" / "data" / "stb_loom_stop_only.toml")
#: The figures the sweep and the report share, by the one name each has.
SHARED = ("fits", "limiting_deg", "limiting_s", "productivity_per_min", "max_rebound_m")
SPEEDS = [200.0, 300.0, 900.0]


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("names") / "out"
    assert main(["run", LOOM, "--out", str(out), "--quiet", "--no-plot"]) == 0
    return out


def test_the_report_and_the_sweep_use_the_same_names(report: Path, tmp_path: Path) -> None:
    js = json.loads((report / "results.json").read_text(encoding="utf-8"))["speed_sweep"]
    with (report / "speed_sweep.csv").open(newline="", encoding="utf-8") as f:
        header = next(csv.reader(f))
    m = cm.Machine.from_toml(LOOM)
    kept = cm.sweep(m, {"speed_rpm": SPEEDS}, progress=False)
    per_design = cm.sweep(m, {"speed_rpm": SPEEDS}, progress=False, batch=False)
    s = m.speed_sweep(SPEEDS)
    for name in SHARED:
        assert name in js and name in header, name
        assert name in kept.columns and name in per_design.columns, name
        assert hasattr(s, name), name
    for names in (js, header, kept.columns, per_design.columns):
        assert "productivity" not in names
    assert not hasattr(s, "productivity")
    # The same figure under the name: machine cycles a minute where it fits, else 0.
    want = np.where(s.fits, SPEEDS, 0.0)
    np.testing.assert_array_equal(s.productivity_per_min, want)
    np.testing.assert_array_equal(kept.columns["productivity_per_min"], want)
    np.testing.assert_array_equal(per_design.columns["productivity_per_min"], want)


def test_the_sweep_command_writes_the_name(tmp_path: Path) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "sweep"
    argv = ["sweep", LOOM, "--set", "lifter.preload_m=1e-4:2e-4:2", "--speed", "300:400:2"]
    assert main([*argv, "--out", str(out), "--quiet"]) == 0
    names = pq.read_schema(out / "sweep.parquet").names
    assert set(SHARED) <= set(names) and "productivity" not in names
    streamed = cm.sweep(
        cm.Machine.from_toml(LOOM),
        {"speed_rpm": [300.0]},
        progress=False,
        out=tmp_path / "s.parquet",
    )
    assert "productivity_per_min" in pq.read_schema(streamed.path).names


@pytest.mark.parametrize("suffix", [".npz", ".parquet"])
def test_a_file_with_the_old_name_still_reads(tmp_path: Path, suffix: str) -> None:
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    r = cm.sweep(cm.Machine.from_toml(LOOM), {"speed_rpm": SPEEDS}, progress=False)
    # As written before the rename: the same columns, in the same order, one renamed.
    old_cols = {
        ("productivity" if k == "productivity_per_min" else k): v for k, v in r.columns.items()
    }
    old = cm.SweepResult(old_cols, r.parameters).write(tmp_path / f"old{suffix}")
    back = cm.SweepResult.read(old)
    assert list(back.columns) == list(r.columns)
    assert back.parameters == ()
    np.testing.assert_array_equal(
        back.columns["productivity_per_min"], r.columns["productivity_per_min"]
    )


def test_write_refuses_a_suffix_it_would_change(tmp_path) -> None:
    """A new user's r.write("loom_sweep.csv") wrote loom_sweep.npz over an existing
    file: a suffix other than .parquet or .npz is an InputError, nothing written."""
    r = cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0]}, progress=False)
    (tmp_path / "x.npz").write_bytes(b"keep")
    with pytest.raises(cm.InputError, match=r"x\.csv: SweepResult.write writes .parquet or .npz"):
        r.write(tmp_path / "x.csv")
    assert (tmp_path / "x.npz").read_bytes() == b"keep"
    assert r.write(tmp_path / "y.npz").suffix == ".npz"
