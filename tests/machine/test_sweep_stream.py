"""Streamed sweeps (issue 20): ``sweep(..., out=path.parquet)`` writes each task's
rows as they finish, in order, and keeps none; the file reads back to the
in-memory result, bit for bit, whatever the tasks and where they ran."""

from __future__ import annotations

import concurrent.futures as cf
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.machine import _sweep

pytest.importorskip("pyarrow")

LOOM = Path(__file__).parent / "data" / "stb_loom_stop_only.toml"


@pytest.fixture(scope="module")
def loom() -> cm.Machine:
    return cm.Machine.from_toml(LOOM)


def grid(designs: int = 13, speeds: int = 11) -> dict[str, np.ndarray]:
    return {
        "lifter.preload_m": np.linspace(1e-4, 5e-4, designs),
        "speed_rpm": np.linspace(200.0, 500.0, speeds),
    }


def same(a: cm.SweepResult, b: cm.SweepResult) -> None:
    assert list(a.columns) == list(b.columns)
    for k, v in b.columns.items():
        w = a.columns[k]
        if v.dtype == object:
            assert (w == v).all(), k
        else:
            assert np.array_equal(w, v, equal_nan=v.dtype.kind == "f"), k


def test_streamed_rows_read_back_bit_for_bit(loom, tmp_path) -> None:
    want = cm.sweep(loom, grid(), progress=False)
    r = cm.sweep(loom, grid(), progress=False, chunk=4, out=tmp_path / "a" / "s.parquet")
    assert r.columns == {} and r.path == tmp_path / "a" / "s.parquet"
    assert r.n_points == want.n_points == 143
    assert r.summary["fits"] == int(want.columns["fits"].sum())
    assert r.n_invalid == 0
    back = cm.SweepResult.read(r.path)
    same(back, want)
    assert back.parameters == ("lifter.preload_m",)
    assert not list((tmp_path / "a").glob(".*partial*"))


def test_an_executor_streams_in_order(loom, tmp_path) -> None:
    want = cm.sweep(loom, grid(), progress=False)
    with cf.ThreadPoolExecutor(3) as ex:
        r = cm.sweep(loom, grid(), ex, progress=False, chunk=2, out=tmp_path / "s.parquet")
    same(cm.SweepResult.read(r.path), want)


def test_one_design_of_many_speeds_is_cut_into_speed_blocks(loom, tmp_path, monkeypatch) -> None:
    want = cm.sweep(loom, grid(3, 50), progress=False)
    monkeypatch.setattr(_sweep, "_TASK_POINTS", 16)
    first = [(slice(0, 1), slice(0, 16)), (slice(0, 1), slice(16, 32))]
    assert _sweep._tasks(3, 50, 1)[:2] == first
    same(cm.sweep(loom, grid(3, 50), progress=False), want)
    r = cm.sweep(loom, grid(3, 50), progress=False, out=tmp_path / "s.parquet")
    same(cm.SweepResult.read(r.path), want)


def test_invalid_designs_are_counted(loom, tmp_path) -> None:
    g = {"lifter.preload_m": [1e-4, 2e-2], "speed_rpm": [300.0, 400.0]}
    r = cm.sweep(loom, g, progress=False, out=tmp_path / "s.parquet")
    assert r.n_invalid == 2 and "must be smaller than stroke" in r.summary["problem"]


class _Boom(cf.ThreadPoolExecutor):
    """An executor whose third task is interrupted (as Ctrl-C would)."""

    def __init__(self) -> None:
        super().__init__(1)
        self.n = 0

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[override]
        self.n += 1
        if self.n == 3:
            raise KeyboardInterrupt
        return super().submit(fn, *args, **kwargs)


def test_an_interrupted_stream_leaves_nothing(loom, tmp_path) -> None:
    target = tmp_path / "new" / "deeper" / "s.parquet"
    with _Boom() as ex, pytest.raises(KeyboardInterrupt):
        cm.sweep(loom, grid(), ex, progress=False, chunk=1, out=target)
    assert not (tmp_path / "new").exists()


def test_bad_out_and_sizes(loom, tmp_path, monkeypatch) -> None:
    with pytest.raises(cm.InputError, match=r"must name a \.parquet file"):
        cm.sweep(loom, grid(), progress=False, out=tmp_path / "s.npz")
    # 10^9 points do not fit in memory, but stream (refused only for its tasks).
    big = {
        "lifter.preload_m": np.linspace(1e-4, 5e-4, 10_000),
        "speed_rpm": np.linspace(1, 2, 100_000),
    }
    monkeypatch.setattr(_sweep, "check_bytes", _raise_over(2e9))
    with pytest.raises(cm.InputError, match="the sweep's result"):
        cm.sweep(loom, big, progress=False)
    _sweep._check_size(10_000, 100_000, 1, streamed=True)  # 16 tasks × 2^17 points: fits


def _raise_over(limit: float):
    def check(what: str, need: float, hint: str) -> None:
        if need > limit:
            raise cm.InputError(f"{what} needs {need:g} bytes; {hint}")

    return check


def test_writing_parquet_without_pyarrow_says_so(loom, tmp_path, monkeypatch) -> None:
    # Found by a new user's trial: write("x.parquet") wrote x.npz in silence.
    import sys

    r = cm.sweep(loom, {"speed_rpm": [300.0, 400.0]})
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow: ImportError
    with pytest.warns(cm.CyclomechWarning, match=r"pyarrow is not installed, so s\.npz"):
        path = r.write(tmp_path / "s.parquet")
    assert path == tmp_path / "s.npz" and not (tmp_path / "s.parquet").exists()
    back = cm.SweepResult.read(path)
    assert np.array_equal(back.columns["limiting_deg"], r.columns["limiting_deg"])
