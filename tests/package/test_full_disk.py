"""Output files on a full disk (issue 31, item 7).

A full disk gave a Python traceback and exit 1 (``OSError: [Errno 28]``). The
rule: one line naming the file that could not be written and the system's
reason, exit status 4 (``EXIT_WRITE``, in the README's table), and no
half-written file (each file is written whole or not at all).

Two real write failures, no mocking: a tiny ``tmpfs`` (ENOSPC; needs root, as on
this project's machines and CI, else skipped) and a file-size limit
(``RLIMIT_FSIZE``, EFBIG; any user on Linux).

The file-size limit runs the command as a user does, ``python -m cyclomech`` in a
process of its own (its exit status, its stderr, no traceback at exit). The roomy
and tiny disks call the same entry point in this process (``cyclomech.cli.main``,
what ``python -m cyclomech`` runs and returns as the exit status): what they test
is the Python writers against a real ENOSPC, and each process would only import
the package again (1.5 CPU-s of the 2-14 s a command takes, 18 runs). They also
share the loom's analysis (``analyzed_once.py``: the roomy disk's run analyses it,
the tiny disks' runs get a copy of that result, which is what they would compute):
the writes come after the analysis. The file-size limit's process analyses it for
real. The loom runs with ``--no-sensitivities``: its sensitivities were 12 of the
14 s its run took, in the roomy run and again in the file-size limit's process,
and they write no file of their own (a section of ``results.json`` and the page,
written by the same writers); ``test_pinned_examples.py`` and
``test_machine.py``'s runs write them.
"""

from __future__ import annotations

import contextlib
import io
import os
import resource
import signal
import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from analyzed_once import analyze_each_machine_once
from cyclomech._cli import EXIT_WRITE
from cyclomech.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: (command, example file, extra arguments): every command that writes files.
COMMANDS = [
    ("run", "stb_loom.toml", ["--no-sensitivities"]),
    ("cam", "lifter_cam.toml", []),
    ("linkage", "crank_rocker.toml", []),
    ("impact", "stb_lifter.toml", []),
    ("cyclogram", "stb_group1.toml", []),
    ("press", "extrusion_press.toml", []),
]


def _command(name: str, example: str, extra: list[str], out: Path) -> list[str]:
    return [
        sys.executable, "-m", "cyclomech", name, str(EXAMPLES / example), "--out", str(out),
        *extra,
    ]  # fmt: skip


#: The analyses of this file's in-process runs (``analyze_each_machine_once``'s cache).
ANALYSED: dict[str, bytes] = {}


def _in_process(name: str, example: str, extra: list[str], out: Path) -> tuple[int, str]:
    """(exit status, stderr) of the command run by ``cyclomech.cli.main`` here: an
    exception it lets through fails the test, as a traceback would. A machine this
    file's runs analysed already is answered by a copy of that analysis."""
    err = io.StringIO()
    with (
        contextlib.redirect_stdout(io.StringIO()),
        contextlib.redirect_stderr(err),
        analyze_each_machine_once(ANALYSED),
    ):
        code = main(_command(name, example, extra, out)[3:])
    return code, err.getvalue()


#: What the reference leaves out: the figures (and the cam's DXF), written after the
#: tables, so no run on a small disk or under the file-size limit gets to write one
#: (they write CSV and JSON files, then fail), and the tables do not depend on them
#: (byte for byte the same with and without): the reference took 12.3 CPU-s with
#: them, 2.3 without. A run that does write one fails :func:`_check_whole` by name.
REFERENCE_SKIPS = ["--no-plot"]
REFERENCE_SKIPS_CAM = ["--no-plot", "--no-dxf"]


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Each command's output on a roomy disk: what a whole table holds."""
    out = {}
    for name, example, extra in COMMANDS:
        folder = tmp_path_factory.mktemp(f"ref-{name}")
        skips = REFERENCE_SKIPS_CAM if name == "cam" else REFERENCE_SKIPS
        code, err = _in_process(name, example, [*extra, *skips], folder)
        assert code in (0, 3), err  # 3: a design that fails, files written
        out[name] = folder
    return out


def _check_whole(folder: Path, reference: Path) -> None:
    """No temporary file is left, and every file written is byte for byte the one a
    roomy disk gets (a CSV cut short, a PNG of 124 bytes would differ)."""
    for f in folder.rglob("*"):
        if f.is_dir():
            continue
        assert ".partial" not in f.name, f
        ref = reference / f.relative_to(folder)
        if f.suffix in (".csv", ".toml", ".png", ".dxf"):
            assert ref.exists(), f"{f.name} was written: the reference skips it (REFERENCE_SKIPS)"
            assert f.read_bytes() == ref.read_bytes(), f


def _check_one_line(returncode: int, stderr: str, reason: str) -> Path:
    assert returncode == EXIT_WRITE, (returncode, stderr)
    assert "Traceback" not in stderr, stderr
    errors = [ln for ln in stderr.splitlines() if ln.startswith("cyclomech: error: ")]
    assert len(errors) == 1, stderr
    line = errors[0]
    assert reason in line and "cannot write " in line, line
    named = Path(line.split("cannot write ", 1)[1].split(": ", 1)[0])
    assert not named.exists() and ".partial" not in named.name  # the user's file, unwritten
    return named


@pytest.fixture
def tiny_disk(tmp_path: Path):
    """A tmpfs of a few kB mounted on a fresh folder (root only), unmounted after."""
    if sys.platform != "linux" or os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root on Linux")
    where = tmp_path / f"disk-{uuid.uuid4().hex[:6]}"
    where.mkdir()

    def mount(size: str) -> Path:
        r = subprocess.run(
            ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)],
            capture_output=True,
            text=True,
        )
        if r.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here: {r.stderr.strip()}")
        return where

    yield mount
    subprocess.run(["umount", str(where)], capture_output=True)


@pytest.mark.parametrize(("name", "example", "extra"), COMMANDS)
@pytest.mark.parametrize("size", ["8k", "120k"])
def test_a_full_disk_is_one_line_and_exit_4(tiny_disk, reference, name, example, extra, size):
    """8 kB: the first file fails; 120 kB: some files are written, a later one
    fails (for the commands whose output exceeds it)."""
    disk = tiny_disk(size)
    out = disk / "out"
    code, err = _in_process(name, example, extra, out)
    if code in (0, 3):  # everything fitted: nothing to test at this size
        assert size == "120k", err
        _check_whole(out, reference[name])
        return
    _check_one_line(code, err, "No space left on device")
    _check_whole(out, reference[name])


def _limit_file_size(limit: int) -> None:
    # SIGXFSZ would kill the process; ignored, a write past the limit fails EFBIG.
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_FSIZE as on Linux")
@pytest.mark.parametrize(("name", "example", "extra"), COMMANDS[:3])
def test_a_file_too_large_is_one_line_and_exit_4(tmp_path, reference, name, example, extra):
    """The same rule for another write failure any user can cause: a file-size
    limit of 4 kB (each command writes a larger file)."""
    out = tmp_path / "out"
    r = subprocess.run(
        _command(name, example, extra, out),
        capture_output=True,
        text=True,
        preexec_fn=lambda: _limit_file_size(4096),
    )
    _check_one_line(r.returncode, r.stderr, "File too large")
    _check_whole(out, reference[name])


def test_the_readme_lists_exit_status_4() -> None:
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    assert "4 when an output file could not be written" in readme
