"""cyclomech: design of cyclic machines with a Rust core.

Linkages, stops, press drives, rotor transfer, the machine's cyclogram, and the
whole machine from one machine file (:class:`~cyclomech.machine.Machine`,
:func:`~cyclomech.machine.sweep`). SI units inside; arguments in degrees or rpm say
so in their names (``_deg``, ``rpm``).
"""

from __future__ import annotations

import sys as _sys

from _cyclomech_entry._interrupt import CtrlC as _CtrlC
from _cyclomech_entry._interrupt import report as _report

try:  # every domain, numpy and the Rust core: ~0.6 s
    with _CtrlC() as _watch:  # a Ctrl-C CPython swallows in a callback is not lost
        from . import (
            cam,
            cyclogram,
            dynamics,
            forces,
            impact,
            linkage,
            machine,
            motion,
            press,
            servo,
            shaft,
            synthesis,
            transfer,
        )
except BaseException as _error:
    if not _watch.explains(_error):  # a Ctrl-C, or an import it broke (its rule)
        raise
    # ``python -m cyclomech`` imports this package before its __main__ can catch a
    # Ctrl-C: end as the command does (one line, status 130; _cyclomech_entry does
    # the same for the console script). While -m locates its module, sys.argv[0] is
    # "-m"; orig_argv says which module. Any other import re-raises.
    _argv = _sys.orig_argv
    _ours = "-mcyclomech" in _argv or any(
        _argv[i : i + 2] == ["-m", "cyclomech"] for i in range(len(_argv))
    )
    if _sys.argv[:1] == ["-m"] and _ours:
        _status = _report()
        # Not SystemExit: under -m, CPython 3.11-3.12 die by SIGINT at exit when the
        # interrupt was raised inside a string exec (a dataclass's generated code,
        # say), even though it was caught. Nothing is open yet to close.
        import os as _os

        _os._exit(_status)
    raise
from ._core import __version__ as _core_version
from ._errors import (
    CycleError,
    CyclomechError,
    CyclomechWarning,
    InfeasibleError,
    InputError,
    InternalError,
    SolverError,
)
from .cyclogram import (
    Constraint,
    Cyclogram,
    EventGraph,
    GraphAnalysis,
    Operation,
    Optimum,
    Schedule,
    SpeedLimit,
    longest_path,
    max_cycle_ratio,
    max_difference,
)
from .linkage import Linkage, LinkageSolution
from .machine import Machine, SweepResult, sweep

#: The installed package's version (a string such as ``"0.1.0"``), read from the Rust
#: core: written in one place, Cargo.toml's ``[workspace.package]``.
__version__: str = _core_version

__all__ = [
    "Constraint",
    "CycleError",
    "Cyclogram",
    "CyclomechError",
    "CyclomechWarning",
    "EventGraph",
    "GraphAnalysis",
    "InfeasibleError",
    "InputError",
    "InternalError",
    "Linkage",
    "LinkageSolution",
    "Machine",
    "Operation",
    "Optimum",
    "Schedule",
    "SolverError",
    "SpeedLimit",
    "SweepResult",
    "__version__",
    "cam",
    "cyclogram",
    "dynamics",
    "forces",
    "impact",
    "linkage",
    "longest_path",
    "machine",
    "max_cycle_ratio",
    "max_difference",
    "motion",
    "press",
    "servo",
    "shaft",
    "sweep",
    "synthesis",
    "transfer",
]
