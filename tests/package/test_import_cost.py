"""What ``import cyclomech`` costs: every command (``cyclomech --version`` too)
and every worker pays it. The package, its domains and its command line import
neither scipy (~0.3 s: the LP, the root finders and differential evolution import
it where they run) nor matplotlib nor a plot module (the plot modules import
matplotlib when they draw)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import cyclomech as cm

DOMAINS = sorted(p.parent.name for p in Path(cm.__file__).parent.glob("*/__init__.py"))


def test_import_cyclomech_its_domains_and_its_cli_imports_no_scipy_nor_plotting() -> None:
    code = (
        "import sys, cyclomech, cyclomech.cli\n"
        f"for d in {DOMAINS!r}:\n"
        "    __import__(f'cyclomech.{d}')\n"
        "heavy = ('scipy', 'matplotlib')\n"
        "print(sorted(m for m in sys.modules if m.endswith('plot') or m.startswith(heavy)))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert run.returncode == 0 and run.stdout == "[]\n", run.stdout + run.stderr
    assert len(DOMAINS) >= 10  # the glob found the domains


def test_what_needs_scipy_imports_it_when_it_runs() -> None:
    # A cyclogram's optimum, an LP of scipy's HiGHS, in a fresh process.
    code = (
        "import sys, cyclomech as cm\n"
        "m = cm.Machine.example()\n"
        "assert 'scipy' not in sys.modules\n"
        "print(round(m.optimize(300.0).objective, 3), 'scipy.optimize' in sys.modules)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert run.returncode == 0, run.stderr
    objective, imported = run.stdout.split()
    assert float(objective) > 0.0 and imported == "True"
