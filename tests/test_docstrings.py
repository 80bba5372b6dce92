"""Every runnable example in the public docstrings runs and shows what it says."""

import doctest
import importlib

import pytest

MODULES = [
    "cyclomech._arrays",
    "cyclomech._json",
    "cyclomech._units",
    "cyclomech.schedule",
    "cyclomech.cyclogram",
    "cyclomech.impact",
    "cyclomech.linkage",
    "cyclomech.linkage.presets",
    "cyclomech.machine",
    "cyclomech.motion",
    "cyclomech.plot",
    "cyclomech.press",
    "cyclomech.report",
    "cyclomech.scale",
    "cyclomech.transfer",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    if name in ("cyclomech.plot", "cyclomech.report"):
        pytest.importorskip("matplotlib")
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0, f"{name} has no examples"
    assert result.failed == 0


def test_every_public_function_has_an_example() -> None:
    """Every public function, and every public method of a public class."""
    import inspect

    import cyclomech as cm
    import cyclomech.impact
    import cyclomech.machine
    import cyclomech.motion
    import cyclomech.press
    import cyclomech.report
    import cyclomech.scale
    import cyclomech.transfer

    missing = []
    public = [(name, getattr(cm, name)) for name in cm.__all__]
    for mod in (
        cyclomech.impact,
        cyclomech.machine,
        cyclomech.motion,
        cyclomech.press,
        cyclomech.report,
        cyclomech.scale,
        cyclomech.transfer,
    ):
        public += [(f"{mod.__name__}.{n}", getattr(mod, n)) for n in mod.__all__]
    for name, obj in public:
        if inspect.ismodule(obj):
            continue
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
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
