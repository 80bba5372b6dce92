"""Ctrl-C while the ``cyclomech`` console script starts (the package and the Rust core
take ~0.6 s to load) exits 130 with one line, no traceback, like Ctrl-C later.

The console script's entry point is ``_cyclomech_entry:main``, a module outside the
package that catches the KeyboardInterrupt of ``import cyclomech``. No timing is
asserted: SIGINT is sent at several delays after the process exists; any of them may
land before, during or after the import, and every one must end the command quietly.
A SIGINT before the interpreter has installed its handler (the first milliseconds)
ends the process by the signal itself: status -2 here, which a shell reports as 130
(128 + SIGINT) like the command's own 130; no Python code runs then, so no traceback.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LOOM = ROOT / "examples" / "stb_loom.toml"
SCRIPT = Path(sys.executable).with_name("cyclomech")
ENTRY = "import sys, _cyclomech_entry; sys.exit(_cyclomech_entry.main())"


QUIET = (130, -signal.SIGINT)


def _interrupt(cmd: list[str], delay: float, tmp_path: Path) -> tuple[int, str]:
    # A sweep long enough that the signal lands before the command could finish.
    args = [str(LOOM), "--out", str(tmp_path / "o"), "--quiet"]
    args += ["--set", "lifter.preload=0.0001:0.0005:2000", "--speed", "200:500:301"]
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen(
        [*cmd, "sweep", *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env
    )
    while proc.pid is None:  # pragma: no cover - Popen returns with the pid set
        time.sleep(0.001)
    time.sleep(delay)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    return proc.returncode, err.decode()


@pytest.mark.slow
@pytest.mark.parametrize("delay", [0.0, 0.05, 0.15, 0.3, 0.6, 1.5])
def test_ctrl_c_at_start_up_exits_130_without_a_traceback(tmp_path, delay):
    # The entry point as the console script calls it (the script itself too, below).
    status, err = _interrupt([sys.executable, "-c", ENTRY], delay, tmp_path)
    assert "Traceback" not in err, err
    assert status in QUIET, err
    assert status == -signal.SIGINT or err == "cyclomech: interrupted\n"


@pytest.mark.slow
@pytest.mark.skipif(
    not SCRIPT.is_file() or shutil.which("cyclomech") is None,
    reason="the cyclomech console script is not installed beside this Python",
)
@pytest.mark.parametrize("delay", [0.0, 0.1, 0.4])
def test_the_installed_console_script_does_the_same(tmp_path, delay):
    status, err = _interrupt([str(SCRIPT)], delay, tmp_path)
    assert "Traceback" not in err, err
    assert status in QUIET, err


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
