"""Shared test settings: headless matplotlib, reproducible hypothesis runs in CI,
the repository's root as the working directory of every test, and one
``cyclomech run`` per test session of each file that several tests only read
(:func:`cli_run`)."""

import contextlib
import gc
import hashlib
import io
import json
import os
import shutil
from collections.abc import Callable, Iterator, MutableMapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

try:
    import fcntl
except ImportError:  # not POSIX: each worker runs its own cli_run commands
    fcntl = None  # type: ignore[assignment]

os.environ.setdefault("MPLBACKEND", "Agg")

import pytest
from hypothesis import HealthCheck, settings

# CI machines are slow and shared: no per-example deadline, and a fixed seed so a
# failure reproduces. Locally, hypothesis explores fresh examples each run.
settings.register_profile(
    "ci", derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

ROOT = Path(__file__).resolve().parents[1]


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config: pytest.Config) -> None:
    """``-n N`` sends whole files to the workers (``--dist loadfile``) unless a
    ``--dist`` is given: many files build a module-scoped fixture (the docstring
    examples' recorded calls, the full-disk reference outputs, a synthesised drive,
    the million-event graphs) that ``--dist load`` builds again on every worker
    that gets one of the file's tests. Set here, not in pyproject's addopts:
    pytest-benchmark turns timing off whenever ``--dist`` is set, also without
    ``-n``. Runs before xdist's own hook, which makes ``-n`` mean ``--dist load``."""
    if getattr(config.option, "numprocesses", None) and config.option.dist == "no":
        config.option.dist = "loadfile"


#: Files that ``--dist loadfile`` sends to one worker as one unit, in collection order
#: (the first named runs first), because the later one reads what the earlier one
#: computed in that process, and on another worker would compute it again:
#: ``test_docstrings`` records the first call of each public callable its examples
#: make (``example_calls.py``), the fuzz's valid calls (its examples had cost the
#: fuzz 15 CPU-s more); the knife drive the synthesised knife file's report compares
#: (about 7 CPU-s a process) is computed once for both files that report it.
SAME_WORKER = (
    ("package/test_docstrings.py", "package/test_fuzz_public.py"),
    ("machine/test_knife_synthesized.py", "package/test_pinned_examples.py"),
)


#: Files of one long test (mypy and stubtest on the whole package, 18 and 8 CPU-s in
#: a subprocess) that ``--dist loadfile`` sends first: xdist sends the files with the
#: most tests first, so these came last, and one worker ran mypy alone while the
#: other had run out of files.
FIRST = ("package/test_types.py", "package/test_stubs.py")


def pytest_collection_finish(session: pytest.Session) -> None:
    """What collection built (every test module, the ~5400 items, the libraries they
    import: ~0.4 million objects) lives as long as the session: moved out of the
    cyclic garbage collector's reach once, after one last collection
    (``gc.freeze``), so that each full collection stops walking all of it again (in
    one process with the whole suite collected and 461 of its tests run, the full
    collections took 6.0 CPU-s, 4.9 with the freeze). The tests see no difference:
    what is frozen was reachable, and stays so.

    Then the youngest generation's threshold goes from 700 to 7000 allocations: the
    tests make many short-lived containers, and each 100th young collection is a full
    one over all that the tests keep. One process running tests/machine,
    tests/dynamics and the docstring examples (956 tests; both settings at once, so
    under the same load): full collections 58 -> 19, the collector's CPU time 7.9 ->
    4.4 s of ~285. A cycle of garbage waits a little longer to be freed."""
    gc.collect()
    gc.freeze()
    gc.set_threshold(7000, 10, 10)


def _short(path: str) -> str:
    return "/".join(path.split("/")[-2:])


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """``--dist loadfile`` with the files of each :data:`SAME_WORKER` group in one
    scope and the :data:`FIRST` files sent first (xdist's own scheduler otherwise:
    None lets its hook choose)."""
    if config.option.dist != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    group = {f: " + ".join(g) for g in SAME_WORKER for f in g}

    class SameWorkerScheduling(LoadFileScheduling):
        ordered = False

        def _split_scope(self, nodeid: str) -> str:
            path = nodeid.split("::", 1)[0]
            return group.get(_short(path), path)

        def _assign_work_unit(self, node: Any) -> None:
            if not self.ordered:  # the first assignment: the queue is whole
                self.ordered = True
                for scope in reversed([s for s in self.workqueue if _short(s) in FIRST]):
                    self.workqueue.move_to_end(scope, last=False)
            super()._assign_work_unit(node)

    return SameWorkerScheduling(config, log)


@pytest.fixture(autouse=True)
def _in_the_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    """Docstring examples and tests name files as a user at the repository's root
    does (``examples/stb_loom.toml``), also when pytest runs elsewhere: against an
    installed wheel, tools/test_wheel.sh runs it from an empty directory so that
    ``python/`` cannot be imported, and the package is imported before this runs."""
    monkeypatch.chdir(ROOT)


@dataclass(frozen=True)
class RunOutput:
    """What ``cyclomech run <file> --out <folder> <flags>`` gave: its exit status, its
    output folder and what it printed on stdout."""

    code: int
    out: Path
    stdout: str


def _session_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder every worker of this test session sees: under xdist the parent of
    the workers' base temps (``…/pytest-N``, one a session), else the base temp (and
    where files cannot be locked, each worker's own)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if fcntl is not None and os.environ.get("PYTEST_XDIST_WORKER") else base


@contextlib.contextmanager
def _exclusive(lock: Path) -> Iterator[None]:
    """Hold the file ``lock`` against the session's other workers while the block
    runs (a plain block where files cannot be locked: the folder is the worker's)."""
    if fcntl is None:
        yield
        return
    with lock.open("w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)  # released when the file is closed
        yield


class _Pickles(MutableMapping[str, bytes]):
    """``analyze_each_machine_once``'s cache (digest -> pickled result) as a folder,
    one file a result, so the session's workers share it. A result is written under
    a name of the writer's own and renamed into place, so a reader finds it whole or
    not at all; two workers that analyse the same machine at once both compute it."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder

    def __contains__(self, key: str) -> bool:
        return (self.folder / key).is_file()

    def __getitem__(self, key: str) -> bytes:
        return (self.folder / key).read_bytes()

    def __setitem__(self, key: str, blob: bytes) -> None:
        part = self.folder / f"{key}.{os.getpid()}"
        part.write_bytes(blob)
        os.replace(part, self.folder / key)

    def __delitem__(self, key: str) -> None:
        (self.folder / key).unlink()

    def __iter__(self) -> Iterator[str]:
        return (p.name for p in self.folder.iterdir() if "." not in p.name)

    def __len__(self) -> int:
        return sum(1 for _ in self)


@pytest.fixture(scope="session")
def cli_run(tmp_path_factory: pytest.TempPathFactory) -> Callable[..., RunOutput]:
    """``cli_run(file, *flags)``: ``cyclomech run file --out <folder> *flags``, run
    once per test session for each (file, flags) and answered from then on by the
    same :class:`RunOutput`. A run of the loom costs seconds (its sensitivities: two
    speed-limit searches per key), and a dozen files read the same run's
    ``results.json``, report and tables: each test still reads what the command
    wrote for that file with those flags. Tests only read the folder (a test that
    writes must run its own command); stdout is kept, stderr is not (ask
    ``--quiet``, or run it yourself where stderr matters).

    Under xdist the workers share the runs: the first worker that asks for one runs
    it (in its process, ``cyclomech.cli.main``) into the session's folder
    (:func:`_session_folder`) while it holds that run's lock, and writes the exit
    status and stdout beside it; a worker that asks later, or waited on the lock,
    reads them. The loom's run is read by nine files, and both workers ran it. In a
    process, runs of one machine file with flags that leave its analysis as it is
    (the loom's report with figures and with ``--no-plot``) analyse it once in the
    session (``analyzed_once.py``: a later run, on either worker, gets a copy of the
    first one's result, :class:`_Pickles`)."""
    from analyzed_once import analyze_each_machine_once
    from cyclomech.cli import main

    runs = _session_folder(tmp_path_factory) / "cli_runs"
    (runs / "analyses").mkdir(parents=True, exist_ok=True)
    done: dict[tuple[str, ...], RunOutput] = {}
    analyses = _Pickles(runs / "analyses")

    def run(file: str | Path, *flags: str) -> RunOutput:
        key = (str(Path(file).resolve()), *flags)
        if key not in done:
            digest = hashlib.sha256("\0".join(key).encode()).hexdigest()[:16]
            folder = runs / f"{Path(file).stem}-{digest}"
            record = folder / "run.json"
            with _exclusive(runs / f"{folder.name}.lock"):
                if not record.is_file():  # not run yet, or a run that failed half-way
                    shutil.rmtree(folder, ignore_errors=True)
                    printed = io.StringIO()
                    with contextlib.redirect_stdout(printed), analyze_each_machine_once(analyses):
                        code = main(["run", key[0], "--out", str(folder / "out"), *flags])
                    said = {"code": code, "stdout": printed.getvalue()}
                    record.write_text(json.dumps(said), encoding="utf-8")
                said = json.loads(record.read_text(encoding="utf-8"))
            done[key] = RunOutput(said["code"], folder / "out", said["stdout"])
        return done[key]

    return run
