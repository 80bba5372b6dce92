"""cm.sweep on a real Dask cluster: two worker processes, bit for bit the in-process sweep.

One ``LocalCluster`` (2 processes, 1 thread each) serves the whole module; the CLI test
starts and closes its own through ``--dask local:2``, as a user's command would.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import socket
import warnings
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from cyclomech.cli import main
from cyclomech.machine._sweep import FIGURES, SPEED, _run_chunk, dask_client

distributed = pytest.importorskip("dask.distributed")
pytest.importorskip("pyarrow")

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"
#: 3 × 2 designs × 25 speeds = 150 points; the speeds straddle the loom's speed limit
#: (421.4 rpm), so NaNs, non-fitting points and several binding chains all appear.
GRID: dict[str, npt.NDArray[np.float64]] = {
    "lifter.preload_m": np.array([2e-4, 2.5e-4, 3e-4]),
    "lifter.a_max_m": np.array([1e-4, 1.2e-4]),
    SPEED: np.linspace(200.0, 500.0, 25),
}
COLUMNS = ("lifter.preload_m", "lifter.a_max_m", SPEED, *FIGURES)
TEXT = ("speed_limit_by", "binding")


def assert_bitwise_equal(got: dict[str, npt.NDArray[Any]], want: dict[str, npt.NDArray[Any]]):
    """Same columns in the same order; floats bit for bit (NaN where NaN), text by ==."""
    assert list(got) == list(want)
    for k in want:
        a, b = got[k], want[k]
        assert a.shape == b.shape, k
        if k in TEXT:
            assert a.dtype == object and b.dtype == object, k
            assert (a == b).all(), k
        elif b.dtype.kind == "f":
            assert a.dtype == b.dtype, k
            assert np.array_equal(a, b, equal_nan=True), k
            assert a.tobytes() == b.tobytes(), k  # not even a -0.0 for a 0.0
        else:
            assert a.dtype == b.dtype, k
            assert np.array_equal(a, b), k


@pytest.fixture(scope="module")
def cluster():
    # dashboard_address=None still binds the scheduler's HTTP server to port 8787
    # (see test_dask_client_local_does_not_need_port_8787); ":0" takes a free port, so
    # this module neither depends on 8787 being free nor takes it from the CLI test.
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=":0"
    ) as c:
        yield c


@pytest.fixture(scope="module")
def client(cluster):
    with distributed.Client(cluster) as c:
        yield c


@pytest.fixture(scope="module")
def loom() -> cm.Machine:
    return cm.Machine.from_toml(LOOM)


@pytest.fixture(scope="module")
def local(loom: cm.Machine) -> cm.SweepResult:
    r = cm.sweep(loom, GRID, progress=False)
    assert tuple(r.columns) == COLUMNS
    assert r.n_points == 150
    fits = r.columns["fits"]
    assert fits.any() and not fits.all()  # both sides of the speed limit
    assert np.isnan(r.columns["limiting_deg"][~fits]).all()
    assert len(set(r.columns["binding"][fits])) > 1
    return r


def test_client_equals_in_process(loom, client, local) -> None:
    r = cm.sweep(loom, GRID, client, progress=False)
    assert r.parameters == local.parameters
    assert_bitwise_equal(r.columns, local.columns)


def test_client_executor_equals_in_process(loom, client, local) -> None:
    r = cm.sweep(loom, GRID, client.get_executor(), progress=False)
    assert_bitwise_equal(r.columns, local.columns)


def test_chunk_size_does_not_change_the_result(loom, client, local) -> None:
    r = cm.sweep(loom, GRID, client, chunk=4, progress=False)  # chunks of 4 and 2 designs
    assert_bitwise_equal(r.columns, local.columns)


def test_chunks_run_in_the_worker_processes(loom, client, local) -> None:
    pids = client.run(os.getpid)
    assert len(pids) == 2
    assert len(set(pids.values())) == 2 and os.getpid() not in pids.values()
    with distributed.get_task_stream(client) as stream:
        r = cm.sweep(loom, GRID, client, chunk=1, progress=False)
    assert_bitwise_equal(r.columns, local.columns)
    chunks = [t for t in stream.data if t["key"].startswith("_run_chunk")]
    assert len(chunks) == 6  # one task per design
    assert {t["worker"] for t in chunks} <= set(pids)


class _Recording(cf.Executor):
    """Forwards to a Dask executor and keeps what each task was called with."""

    def __init__(self, inner: cf.Executor) -> None:
        self.inner = inner
        self.calls: list[tuple[Any, tuple[Any, ...]]] = []

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[override]
        self.calls.append((fn, args))
        return self.inner.submit(fn, *args, **kwargs)


def test_tasks_run_the_kernels_on_one_thread(loom, client, local) -> None:
    # sweep() hands every task n_threads=1 (the last argument of _run_chunk),
    # whatever n_threads it was given for in-process runs.
    ex = _Recording(client.get_executor())
    r = cm.sweep(loom, GRID, ex, n_threads=2, progress=False)
    assert_bitwise_equal(r.columns, local.columns)
    assert ex.calls and all(fn is _run_chunk for fn, _ in ex.calls)
    assert {args[-1] for _, args in ex.calls} == {1}


@pytest.mark.parametrize("n_threads", [None, 2])
def test_run_chunk_one_thread_equals_all_threads(loom, n_threads) -> None:
    # The designs (2e-4, 1e-4) and (3e-4, 1.2e-4): indices into the axes.
    axes = [np.array([2e-4, 3e-4]), np.array([1e-4, 1.2e-4])]
    designs = np.array([[0, 0], [1, 1]])
    speeds = np.linspace(200.0, 500.0, 401)  # big enough for the kernels to go parallel
    names = ["lifter.preload_m", "lifter.a_max_m"]
    args = (loom.data, loom.source, names, axes, designs, speeds)
    one = _run_chunk(*args, 1)
    many = _run_chunk(*args, n_threads)
    assert tuple(one) == FIGURES
    assert one["fits"].any() and not one["fits"].all()
    assert_bitwise_equal(many, one)


def test_tcp_address(loom, cluster, local) -> None:
    c = dask_client(cluster.scheduler_address)
    try:
        assert cluster.scheduler_address.startswith("tcp://")
        assert c.scheduler.address == cluster.scheduler_address
        r = cm.sweep(loom, GRID, c, progress=False)
    finally:
        c.close()
    assert_bitwise_equal(r.columns, local.columns)


# dask_client("local:2") starts the scheduler's HTTP server on port 8787 and warns if
# another cluster on this machine holds it; that bug has its own test below.
@pytest.mark.filterwarnings("ignore:Port 8787 is already in use:UserWarning")
def test_cli_sweep_on_dask(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    argv = [
        "sweep",
        "examples/stb_loom.toml",
        "--set",
        "lifter.preload_m=0.0002:0.0003:3",
        "--speed",
        "250:450:9",
        "--quiet",
    ]
    assert main([*argv, "--out", str(tmp_path / "local")]) == 0
    assert main([*argv, "--out", str(tmp_path / "dask"), "--dask", "local:2"]) == 0
    out = capsys.readouterr().out
    assert "3 designs × 9 speeds = 27 points on Dask (local:2)" in out
    want = cm.SweepResult.read(tmp_path / "local" / "sweep.parquet")
    got = cm.SweepResult.read(tmp_path / "dask" / "sweep.parquet")
    assert got.parameters == want.parameters == ("lifter.preload_m",)
    assert got.n_points == 27
    assert_bitwise_equal(got.columns, want.columns)
    # and the file holds what the API computes in this process
    m = cm.Machine.from_toml(LOOM)
    grid = {"lifter.preload_m": np.linspace(2e-4, 3e-4, 3), SPEED: np.linspace(250, 450, 9)}
    assert_bitwise_equal(got.columns, cm.sweep(m, grid, progress=False).columns)


def test_dask_client_local_does_not_need_port_8787() -> None:
    held = socket.socket()
    try:
        try:
            held.bind(("127.0.0.1", 8787))
            held.listen()
        except OSError:
            pass  # another process holds it already: the same situation
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            c = dask_client("local:1")
            try:
                assert c.submit(os.getpid).result() != os.getpid()
            finally:
                c.close()
                c.cluster.close()
    finally:
        held.close()
    assert not [w for w in caught if "8787" in str(w.message)]


def test_cli_unreachable_scheduler_is_an_error_message(tmp_path: Path, capsys) -> None:
    with socket.socket() as s:  # a port with nothing listening
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    import dask

    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        code = main(
            [
                "sweep",
                str(LOOM),
                "--speed",
                "250:450:3",
                "--out",
                str(tmp_path),
                "--quiet",
                "--dask",
                f"tcp://127.0.0.1:{port}",
            ]
        )
    assert code == 2
    assert "cyclomech: error:" in capsys.readouterr().err
