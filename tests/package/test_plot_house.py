"""The house of the plots: each domain's plot module, the facade that re-exports
them, doors that never import matplotlib."""

from __future__ import annotations

import doctest
import importlib
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import cyclomech as cm
import cyclomech.plot as cplot
import matplotlib.pyplot as plt
import pytest


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


#: Every domain with its own plots (a ``<domain>/plot.py``), found, not listed.
DOMAINS = tuple(sorted(p.parent.name for p in Path(cm.__file__).parent.glob("*/plot.py")))


@pytest.mark.parametrize("module", ["cyclomech.plot", *(f"cyclomech.{d}.plot" for d in DOMAINS)])
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0
    assert result.failed == 0


def test_the_facade_re_exports_each_domains_plots_under_their_old_names():
    assert cplot.__all__ == [
        "animate_linkage",
        "animate_machine",
        "plot_along_cycle",
        "plot_analogs",
        "plot_burmester",
        "plot_cam",
        "plot_crank_torque",
        "plot_cyclogram",
        "plot_cyclogram_pair",
        "plot_duty",
        "plot_forces",
        "plot_knife_motion",
        "plot_knife_torque",
        "plot_law",
        "plot_linkage",
        "plot_machine_frame",
        "plot_min_phase",
        "plot_min_phase_angles",
        "plot_press",
        "plot_press_criteria",
        "plot_rebound_vs_speed",
        "plot_response",
        "plot_shaking",
        "plot_size_tradeoff",
        "plot_speed_sweep",
        "plot_svaj",
        "plot_torsion",
        "plot_transfer",
    ]
    homes = set()
    for name in cplot.__all__:
        f = getattr(cplot, name)
        # Defined in its domain (its plot module, or a private module beside it)
        # and exported by the domain's plot module.
        domain = f.__module__.split(".")[1]
        assert domain in DOMAINS, name
        home = importlib.import_module(f"cyclomech.{domain}.plot")
        assert name in home.__all__ and getattr(home, name) is f
        homes.add(home.__name__)
    assert homes == {f"cyclomech.{d}.plot" for d in DOMAINS}
    # Every domain plot module's public functions are in the facade.
    assert {n for d in DOMAINS for n in importlib.import_module(f"cyclomech.{d}.plot").__all__} == (
        set(cplot.__all__)
    )
    # The colours stay where they were.
    assert cplot.MECHANISM_COLORS[0] == "#9ecae1" and cplot.WORK_COLOR == "#f28e2b"
    assert cplot.CRITICAL_COLOR == "#d62728" and cplot.XY_COLORS == ("#1f77b4", "#d62728")


def test_import_cyclomech_and_its_plot_modules_needs_no_matplotlib():
    """The plot modules import matplotlib only when they draw (that no door imports
    a plot module, matplotlib or scipy: ``test_import_cost.py``)."""
    code = (
        "import sys\n"
        "sys.modules['matplotlib'] = None\n"
        "import cyclomech, cyclomech.plot\n"
        f"for d in {DOMAINS!r}:\n"
        "    __import__(f'cyclomech.{d}.plot')\n"
        "print('ok')\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert run.returncode == 0 and run.stdout == "ok\n", run.stderr
