"""Ctrl-C while the ``cyclomech`` console script or ``python -m cyclomech`` starts (the
package and the Rust core take ~0.6 s to load) exits 130 with one line, no traceback,
like Ctrl-C later.

The console script's entry point is ``_cyclomech_entry:main``, a module outside the
package that catches the KeyboardInterrupt of ``import cyclomech``; under ``python -m
cyclomech`` the package's ``__init__`` catches it itself (and only then). No timing is
asserted: SIGINT is sent at several delays after the entry point has started; any of
them may land during or after the import, and every one must end the command quietly.

The rule, decided: the promise starts when the entry point runs. Before it, the
interpreter itself is starting (``site``, the console script's own two lines); a
SIGINT there is CPython's to handle (it may print "Fatal Python error:
init_import_site" and its traceback) and no code of ours can run. So the delays are
counted from a point past that window: a byte the child writes once the entry module
is imported (``python -c``), or numpy's core library mapped into the process (the
installed script and ``python -m``: only ``import cyclomech`` imports numpy).
A CI run sent SIGINT 50 ms after the process started, while ``site`` was still
importing, and got CPython's fatal error: that window is what this rule leaves out.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"
SCRIPT = Path(sys.executable).with_name("cyclomech")
# The console script's two lines, with one byte written on fd {fd} once the entry
# point's watch is on (CtrlC.__enter__): the promise starts when the entry point
# runs. A byte written by the script before it calls main() left a window (a CI run
# under load sent SIGINT there, into the script's own line, and got its traceback).
ENTRY = (
    "import os, sys, _cyclomech_entry, _cyclomech_entry._interrupt as i; on = i.CtrlC.__enter__\n"
    "def enter(self):\n"
    "    r = on(self); os.write({fd}, b'.'); os.close({fd}); i.CtrlC.__enter__ = on; return r\n"
    "i.CtrlC.__enter__ = enter\n"
    "sys.exit(_cyclomech_entry.main())"
)


ARGS = ["--set", "lifter.preload_m=0.0001:0.0005:2000", "--speed", "200:500:301", "--quiet"]


def _start(cmd: list[str], tmp_path: Path, fds: tuple[int, ...] = ()) -> subprocess.Popen[bytes]:
    """Start a sweep long enough that a signal lands before it could finish."""
    args = ["sweep", str(LOOM), "--out", str(tmp_path / "o"), *ARGS]
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    return subprocess.Popen(
        [*cmd, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, pass_fds=fds
    )


def _interrupt(proc: subprocess.Popen[bytes], delay: float) -> tuple[int, str]:
    """SIGINT ``delay`` s from now, and again every 5 s while the command runs: a
    signal landing inside C code that clears errors (scipy's import calls some) is
    lost before any code of ours sees it, and a user then presses Ctrl-C again."""
    time.sleep(delay)
    for _ in range(24):
        proc.send_signal(signal.SIGINT)
        try:
            _, err = proc.communicate(timeout=5)
            break
        except subprocess.TimeoutExpired:
            continue
    else:
        proc.kill()
        _, err = proc.communicate()
    return proc.returncode, err.decode()


@pytest.mark.slow
@pytest.mark.parametrize("delay", [0.01, 0.03, 0.08, 0.15, 0.3, 0.6, 1.5])
def test_ctrl_c_at_start_up_exits_130_without_a_traceback(tmp_path, delay):
    # The entry point as the console script calls it (the script itself too, below).
    read, write = os.pipe()
    try:
        proc = _start([sys.executable, "-c", ENTRY.format(fd=write)], tmp_path, (write,))
        os.close(write)
        assert os.read(read, 1) == b".", "the entry module never loaded"
    finally:
        os.close(read)
    status, err = _interrupt(proc, delay)
    assert "Traceback" not in err, err
    assert (status, err) == (130, "cyclomech: interrupted\n")


def _numpy_mapped(pid: int) -> bool:
    return "_multiarray_umath" in Path(f"/proc/{pid}/maps").read_text()


def _interrupt_in_import(cmd: list[str], delay: float, tmp_path: Path) -> tuple[int, str]:
    proc = _start(cmd, tmp_path)
    deadline = time.monotonic() + 60.0
    while not _numpy_mapped(proc.pid):  # inside the import of cyclomech
        assert proc.poll() is None and time.monotonic() < deadline, "numpy never loaded"
        time.sleep(0.001)
    return _interrupt(proc, delay)


needs_proc = pytest.mark.skipif(not Path("/proc/self/maps").is_file(), reason="needs Linux's /proc")


@pytest.mark.slow
@pytest.mark.skipif(
    not SCRIPT.is_file() or shutil.which("cyclomech") is None,
    reason="the cyclomech console script is not installed beside this Python",
)
@needs_proc
@pytest.mark.parametrize("delay", [0.0, 0.1, 0.4])
def test_the_installed_console_script_does_the_same(tmp_path, delay):
    status, err = _interrupt_in_import([str(SCRIPT)], delay, tmp_path)
    assert "Traceback" not in err, err
    assert (status, err) == (130, "cyclomech: interrupted\n")


@pytest.mark.slow
@needs_proc
@pytest.mark.parametrize("form", [["-m", "cyclomech"], ["-mcyclomech"]])
@pytest.mark.parametrize("delay", [0.0, 0.1, 0.4])
def test_python_dash_m_does_the_same(tmp_path, delay, form):
    # The package's own __init__ catches it (python -m imports the package first).
    status, err = _interrupt_in_import([sys.executable, *form], delay, tmp_path)
    assert "Traceback" not in err, err
    assert (status, err) == (130, "cyclomech: interrupted\n")


# How a Ctrl-C reaches an import: as itself, or (when it lands inside an extension
# module's initialisation, as CI saw in scipy's HiGHS module) as the ImportError
# CPython raises from it.
RAISES = {
    "interrupt": "raise KeyboardInterrupt",
    "broken init": "raise ImportError('initialization failed') from KeyboardInterrupt()",
    # In a weakref callback or __del__ (CI saw it in an import's module lock), where
    # CPython prints "Exception ignored in ..." and goes on: the Ctrl-C was lost.
    "swallowed": "Dropped()",
    # A Cython module's init turns it into an ImportError of its own, unchained.
    "unchained": "unchained()",
}
FAKE_IMPORT = (
    "import builtins, sys\n"
    "import os, signal, time\n"
    "def unchained():\n"
    "    try:\n"
    "        os.kill(os.getpid(), signal.SIGINT)\n"
    "        time.sleep(5)\n"
    "    except KeyboardInterrupt:\n"
    "        pass\n"
    "    raise ImportError('numpy.core.multiarray failed to import')\n"
    "class Dropped:\n"
    "    def __del__(self):\n"
    "        raise KeyboardInterrupt\n"
    "real = builtins.__import__\n"
    "def fake(name, *a, **k):\n"
    "    if name == {name!r}:\n"
    "        {raise_}\n"
    "    return real(name, *a, **k)\n"
    "builtins.__import__ = fake\n"
)


@pytest.mark.parametrize("how", RAISES)
@pytest.mark.parametrize(
    ("argv0", "orig", "quiet"),
    [
        ("-m", ["-m", "cyclomech", "sweep"], True),  # python -m cyclomech, locating
        ("-m", ["-mcyclomech"], True),
        ("-m", ["-m", "other"], False),  # another module's import of cyclomech
        ("-c", ["-c", "import cyclomech"], False),
        ("script.py", ["script.py", "-m", "cyclomech"], False),  # "-m" as a script's argument
    ],
)
def test_only_python_dash_m_cyclomech_ends_quietly(argv0, orig, quiet, how):
    # The interrupt raised from inside the import at once (no timing): numpy's
    # import raises it; sys.argv / orig_argv as that command line would set them.
    code = FAKE_IMPORT.format(name="numpy", raise_=RAISES[how]) + (
        f"sys.argv[0] = {argv0!r}\n"
        f"sys.orig_argv = [sys.executable, *{orig!r}]\n"
        "try:\n"
        "    import cyclomech\n"
        "except (KeyboardInterrupt, ImportError):\n"
        "    print('raised')\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    if quiet:
        assert (proc.returncode, proc.stdout, proc.stderr) == (130, "", "cyclomech: interrupted\n")
    else:
        assert (proc.returncode, proc.stdout) == (0, "raised\n"), proc.stderr


@pytest.mark.parametrize("how", RAISES)
# numpy first, the Rust core (``from ._core import …``) and the command line last:
# scipy, the largest import before, is no longer imported at start.
@pytest.mark.parametrize("module", ["numpy", "_core", "cyclomech.cli"])
def test_the_entry_point_ends_quietly_however_the_interrupt_arrives(module, how):
    code = FAKE_IMPORT.format(name=module, raise_=RAISES[how]) + (
        "import _cyclomech_entry\nsys.exit(_cyclomech_entry.main())\n"
    )
    proc = subprocess.run([sys.executable, "-c", code, "--version"], capture_output=True, text=True)
    assert (proc.returncode, proc.stderr) == (130, "cyclomech: interrupted\n")


def test_an_import_error_of_another_cause_is_not_an_interrupt():
    # The rule is the chain, not the class: a missing module still shows its error.
    code = FAKE_IMPORT.format(name="_core", raise_="raise ImportError('no core')") + (
        "import _cyclomech_entry\nsys.exit(_cyclomech_entry.main())\n"
    )
    proc = subprocess.run([sys.executable, "-c", code, "--version"], capture_output=True, text=True)
    assert proc.returncode == 1
    assert "ImportError: no core" in proc.stderr


def test_the_entry_point_runs_the_command(capsys):
    import _cyclomech_entry

    argv = sys.argv
    sys.argv = ["cyclomech", "--version"]
    try:
        with pytest.raises(SystemExit) as e:
            _cyclomech_entry.main()
    finally:
        sys.argv = argv
    assert e.value.code == 0
    assert capsys.readouterr().out.startswith("cyclomech ")


def test_ctrl_c_while_the_command_line_is_parsed(monkeypatch, capsys):
    # Found by the SIGINT tests above: a Ctrl-C while the sub-commands' parsers were
    # being built escaped with a traceback. The whole of main is covered now.
    from cyclomech import cli

    def interrupted(sub: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(cli.COMMANDS[0], "add_commands", interrupted)
    assert cli.main(["run", str(LOOM)]) == 130
    assert capsys.readouterr().err == "cyclomech: interrupted\n"


def test_an_import_a_ctrl_c_broke_inside_the_command_is_an_interrupt(monkeypatch, capsys):
    # A lazy import inside a command (ezdxf, matplotlib) can be broken the same way.
    from cyclomech import cli

    def broken(sub: object) -> None:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as e:
            raise ImportError("initialization failed") from e

    monkeypatch.setattr(cli.COMMANDS[0], "add_commands", broken)
    assert cli.main(["run", str(LOOM)]) == 130
    assert capsys.readouterr().err == "cyclomech: interrupted\n"


def test_a_ctrl_c_swallowed_inside_the_command_still_stops_it():
    # CPython prints "Exception ignored in ..." for a KeyboardInterrupt in a __del__
    # and goes on; the command ends 130 with one line. (In a child: the Ctrl-C sent
    # again lands anywhere, an open file's ResourceWarning included, which pytest's
    # own hook would report.)
    code = (
        "import sys\n"
        "from cyclomech import cli\n"
        "import os, signal, time\n"
        "def unchained():\n"
        "    try:\n"
        "        os.kill(os.getpid(), signal.SIGINT)\n"
        "        time.sleep(5)\n"
        "    except KeyboardInterrupt:\n"
        "        pass\n"
        "    raise ImportError('numpy.core.multiarray failed to import')\n"
        "class Dropped:\n"
        "    def __del__(self):\n"
        "        raise KeyboardInterrupt\n"
        "real = cli.COMMANDS[0].add_commands\n"
        "def dropping(sub):\n"
        "    Dropped()\n"
        "    real(sub)\n"
        "cli.COMMANDS[0].add_commands = dropping\n"
        f"sys.exit(cli.main(['run', {str(LOOM)!r}, '--out', sys.argv[1]]))\n"
    )
    with tempfile.TemporaryDirectory() as out:
        proc = subprocess.run([sys.executable, "-c", code, out], capture_output=True, text=True)
    assert (proc.returncode, proc.stderr) == (130, "cyclomech: interrupted\n")
