"""Every runnable example in the public docstrings runs and shows what it says."""

import contextlib
import doctest
import importlib

import pytest
from analyzed_once import analyze_each_machine_once
from example_calls import FirstCalls, docstrings_recording, package_modules

MODULES = package_modules()
# Modules with nothing to show by example: the error classes, the TOML reader's
# internals and the argument parser (tested through the CLI), and the domain doors,
# which only re-export (their objects are doctested where they are defined).
NO_EXAMPLES = {
    "cyclomech._errors",
    "cyclomech._toml",
    "cyclomech.cli",
    # the cyclogram's LP class and file format, private: their examples are those of
    # Cyclogram.optimize, from_toml and to_toml
    "cyclomech.cyclogram._lp",
    "cyclomech.cyclogram._file",
}


def _is_door(name: str) -> bool:
    return hasattr(importlib.import_module(name), "__path__")


#: The examples' analyses, shared by every module's test in this worker.
_ANALYSES: dict[str, bytes] = {}


@pytest.fixture(scope="module")
def recording(request: pytest.FixtureRequest) -> FirstCalls | None:
    """The fuzz's valid calls, recorded while the examples run when the fuzz is in
    this session (it runs after this file in the same worker and reads them:
    example_calls.py), else None: the profiler slows the examples by about a third."""
    fuzz = any(item.path.name == "test_fuzz_public.py" for item in request.session.items)
    return docstrings_recording() if fuzz else None


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(recording: FirstCalls | None, name: str) -> None:
    if "plot" in name or "report" in name:
        pytest.importorskip("matplotlib")
    module = importlib.import_module(name)
    # The same machine file's analysis is computed once per worker, not once per
    # example that opens with it (analyzed_once.py says why that is the same).
    with (
        analyze_each_machine_once(_ANALYSES),
        recording.recording() if recording is not None else contextlib.nullcontext(),
    ):
        result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    if name not in NO_EXAMPLES and not _is_door(name):
        assert result.attempted > 0, f"{name} has no examples"
    assert result.failed == 0
    if recording is not None:
        recording.ran(name)


def test_every_public_function_has_an_example() -> None:
    """Every public function, and every public method of a public class."""
    import inspect
    import types

    import cyclomech as cm
    import cyclomech.cyclogram
    import cyclomech.impact
    import cyclomech.linkage
    import cyclomech.machine
    import cyclomech.motion
    import cyclomech.press
    import cyclomech.transfer

    missing = []
    public = [(name, getattr(cm, name)) for name in cm.__all__]
    for mod in (
        cyclomech.cyclogram,
        cyclomech.impact,
        cyclomech.linkage,
        cyclomech.machine,
        cyclomech.motion,
        cyclomech.press,
        cyclomech.transfer,
    ):
        public += [(f"{mod.__name__}.{n}", getattr(mod, n)) for n in mod.__all__]
    for name, obj in public:
        if inspect.ismodule(obj) or isinstance(obj, types.GenericAlias):
            continue  # a sub-package, or a type alias such as cyclogram.Arc
        if inspect.isclass(obj):
            if issubclass(obj, BaseException) or getattr(obj, "_is_protocol", False):
                continue  # errors; interfaces (typing.Protocol), whose methods are abstract
            if name.rsplit(".", 1)[-1] in {"Cyclogram", "EventGraph"} and ">>>" not in (
                obj.__doc__ or ""
            ):
                missing.append(name)
            for attr, member in vars(obj).items():
                if isinstance(member, classmethod | staticmethod):
                    member = member.__func__
                is_method = inspect.isfunction(member) and not attr.startswith("_")
                if is_method and ">>>" not in (member.__doc__ or ""):
                    missing.append(f"{name}.{attr}")
        elif callable(obj) and ">>>" not in (obj.__doc__ or ""):
            missing.append(name)
    assert not missing, f"public callables without a runnable example: {missing}"


def test_a_repeated_analysis_is_a_copy_of_a_real_one() -> None:
    """The examples' cache (analyzed_once.py) against the real ``analyze``: a
    repeated call is an equal, separate result; a changed machine is a new analysis."""
    import cyclomech as cm
    import numpy as np

    real = cm.machine.analyze(cm.Machine.example(), progress=False)
    with analyze_each_machine_once():
        first = cm.machine.analyze(cm.Machine.example(), progress=False)
        again = cm.machine.analyze(cm.Machine.example(), progress=False)
        changed = cm.machine.analyze(
            cm.Machine.example().with_values({"lifter.preload_m": 3e-4}), progress=False
        )
    assert cm.machine.analyze.__module__ == "cyclomech.machine._report"  # restored
    assert again is not first and again.sweep is not first.sweep
    for r in (first, again):
        assert r.limit.rpm == real.limit.rpm
        assert r.optimum.objective == real.optimum.objective
        np.testing.assert_array_equal(r.sweep.limiting_deg, real.sweep.limiting_deg)
    assert changed.limit.rpm != real.limit.rpm
