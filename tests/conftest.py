"""Shared test settings: headless matplotlib, reproducible hypothesis runs in CI,
the repository's root as the working directory of every test, and one
``cyclomech run`` per worker of each file that several tests only read
(:func:`cli_run`)."""

import contextlib
import io
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

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


@pytest.fixture(scope="session")
def cli_run(tmp_path_factory: pytest.TempPathFactory) -> Callable[..., RunOutput]:
    """``cli_run(file, *flags)``: ``cyclomech run file --out <folder> *flags`` in this
    process, run once per worker for each (file, flags) and answered from then on
    by the same :class:`RunOutput`. A run of the loom costs seconds (its
    sensitivities: two speed-limit searches per key), and a dozen files read the
    same run's ``results.json``, report and tables: each test still reads what the
    command wrote for that file with those flags. Tests only read the folder (a test
    that writes must run its own command); stdout is kept, stderr is not (ask
    ``--quiet``, or run it yourself where stderr matters)."""
    from cyclomech.cli import main

    done: dict[tuple[str, ...], RunOutput] = {}

    def run(file: str | Path, *flags: str) -> RunOutput:
        key = (str(Path(file).resolve()), *flags)
        if key not in done:
            out = tmp_path_factory.mktemp(Path(file).stem) / "out"
            printed = io.StringIO()
            with contextlib.redirect_stdout(printed):
                code = main(["run", key[0], "--out", str(out), *flags])
            done[key] = RunOutput(code, out, printed.getvalue())
        return done[key]

    return run
