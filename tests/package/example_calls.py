"""The first call each public callable's docstring examples make, recorded once.

``test_fuzz_public.py`` calls every public callable with one bad argument and the
others as its docstring examples gave them: a profiler records the arguments of
the first call of each while the examples run. ``test_docstrings.py`` runs every
example anyway, so while the fuzz is in the session it records as it runs
(:data:`DOCSTRINGS`), and the fuzz reads that recording once every module's
examples have run under it; the two files share a worker for that
(``tests/conftest.py``, ``SAME_WORKER``). Run without the docstring test (alone,
or with ``-k``), the fuzz runs the examples itself (:meth:`FirstCalls.run_examples`),
as it always did: the examples had cost it 15 CPU-s on top of what the docstring
test paid for the same examples.

Either way a recorded call is a real call an example made, its arguments copied
when the call began (before the callable could change them). The docstring test
runs each module's examples (``doctest.testmod``), the fuzz's own run each target's
examples in the targets' order: the first call of a callable that several examples
make can differ between the two, each a valid call of the documented API.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import doctest
import importlib
import inspect
import sys
import types
import warnings
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass, field
from typing import Any

PACKAGES = [
    "cyclomech",
    "cyclomech.cam",
    "cyclomech.cyclogram",
    "cyclomech.dynamics",
    "cyclomech.forces",
    "cyclomech.impact",
    "cyclomech.linkage",
    "cyclomech.machine",
    "cyclomech.motion",
    "cyclomech.press",
    "cyclomech.servo",
    "cyclomech.shaft",
    "cyclomech.synthesis",
    "cyclomech.transfer",
]

#: Docstring examples to skip when recording valid calls: they open plots that
#: the plot modules' own examples already call, or they spawn worker processes.
SKIP_DOCSTRINGS = {"dask_client", "dask_workers"}

Call = tuple[list[Any], dict[str, Any]]

_FACTORY = dataclasses._HAS_DEFAULT_FACTORY  # type: ignore[attr-defined]


def package_modules() -> list[str]:
    """Every module of the package, doors and private modules alike (a re-exported
    object is doctested in the module that defines it), sorted."""
    import pkgutil

    import cyclomech

    names = [
        m.name
        for m in pkgutil.walk_packages(cyclomech.__path__, "cyclomech.")
        if m.name not in ("cyclomech._core", "cyclomech.__main__")
    ]
    return sorted(names)


def public_objects() -> list[tuple[str, Any]]:
    """(qualified name, object) of every entry of every package's ``__all__`` and
    of its ``plot`` module's, modules and exceptions left out."""
    out: dict[int, tuple[str, Any]] = {}
    for pkg in PACKAGES:
        names = [pkg]
        try:
            importlib.import_module(pkg + ".plot")
            names.append(pkg + ".plot")
        except ModuleNotFoundError:
            pass
        for modname in names:
            mod = importlib.import_module(modname)
            for n in mod.__all__:
                obj = getattr(mod, n)
                if inspect.ismodule(obj) or isinstance(obj, types.GenericAlias):
                    continue
                if inspect.isclass(obj) and issubclass(obj, BaseException):
                    continue
                if not callable(obj) or n in SKIP_DOCSTRINGS:
                    continue
                out.setdefault(id(obj), (f"{modname}.{n}", obj))
    return sorted(out.values(), key=lambda t: t[0])


@dataclass
class Target:
    """One public callable: how to call it and which code its examples run."""

    name: str
    func: Callable[..., Any]  # what the fuzz calls (the class for a constructor)
    code: types.CodeType  # what the profiler watches
    docs: list[Any]  # objects whose docstring examples call it
    bound_self: bool = False  # a method: the recorded first argument is the instance


def _code(f: Any) -> types.CodeType | None:
    f = inspect.unwrap(f)
    return getattr(f, "__code__", None)


def targets(result_classes: Collection[str]) -> list[Target]:
    """Every public function, constructor and public method; the constructors of
    ``result_classes`` (built by the library, not inputs) left out."""
    out: list[Target] = []
    for name, obj in public_objects():
        if inspect.isclass(obj):
            if getattr(obj, "_is_protocol", False):
                continue
            init = obj.__dict__.get("__init__")
            code = _code(init) if init is not None else None
            if code is None:
                # a dataclass's generated __init__ is in __dict__; else a parent's
                for base in obj.__mro__[1:]:
                    if base.__module__.startswith("cyclomech") and "__init__" in base.__dict__:
                        code = _code(base.__dict__["__init__"])
                        break
            if code is not None and name not in result_classes:
                out.append(Target(name, obj, code, [obj, init]))
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                static = isinstance(member, staticmethod)
                if isinstance(member, classmethod | staticmethod):
                    member = member.__func__
                if not inspect.isfunction(member):
                    continue
                code = _code(member)
                if code is None:
                    continue
                if static:
                    out.append(Target(f"{name}.{attr}", getattr(obj, attr), code, [member]))
                else:
                    out.append(Target(f"{name}.{attr}", member, code, [member], True))
        elif inspect.isfunction(obj) or hasattr(obj, "__wrapped__"):
            code = _code(obj)
            if code is not None:
                out.append(Target(name, obj, code, [obj]))
    return out


def _run_examples(objs: list[Any], globs: dict[str, Any]) -> None:
    finder = doctest.DocTestFinder(recurse=False)
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    for o in objs:
        if o is None or not (getattr(o, "__doc__", None) or "").count(">>>"):
            continue
        mod = inspect.getmodule(o)
        g = dict(vars(mod)) if mod is not None else dict(globs)
        for test in finder.find(o, globs=g):
            runner.run(test, out=lambda s: None)


@dataclass
class FirstCalls:
    """The (args, kwargs) of the first call of each watched code object made while
    :meth:`recording` is on, and the package modules whose examples all ran under it
    (:meth:`ran`)."""

    watched: frozenset[types.CodeType]
    seen: dict[types.CodeType, Call] = field(default_factory=dict)
    modules: set[str] = field(default_factory=set)

    def _profile(self, frame: types.FrameType, event: str, arg: Any) -> None:
        if event != "call" or frame.f_code not in self.watched or frame.f_code in self.seen:
            return
        code = frame.f_code
        loc = frame.f_locals
        n = code.co_argcount
        k = code.co_kwonlyargcount
        names = code.co_varnames[: n + k]
        args = [loc[v] for v in names[:n]]
        kwargs = {v: loc[v] for v in names[n:]}
        i = n + k
        if code.co_flags & inspect.CO_VARARGS:
            args += list(loc[code.co_varnames[i]])
            i += 1
        if code.co_flags & inspect.CO_VARKEYWORDS:
            kwargs.update(loc[code.co_varnames[i]])
        try:
            # A dataclass's generated __init__ takes a default_factory field's default
            # as a marker it tests by identity: a copy of it would be a value.
            rec = copy.deepcopy((args, kwargs), {id(_FACTORY): _FACTORY})
        except Exception:
            rec = (args, kwargs)
        self.seen[code] = rec

    @contextlib.contextmanager
    def recording(self) -> Iterator[None]:
        """Record while the block runs (the profiler there before is put back)."""
        before = sys.getprofile()
        sys.setprofile(self._profile)
        try:
            yield
        finally:
            sys.setprofile(before)

    def ran(self, module: str) -> None:
        """Every example of ``module`` ran under :meth:`recording`, and passed."""
        self.modules.add(module)

    def run_examples(self, of: list[Target]) -> None:
        """Run the examples of each target's docs under :meth:`recording` (warnings
        ignored, figures closed): the fuzz's own recording."""
        import matplotlib.pyplot as plt
        from analyzed_once import analyze_each_machine_once

        docs: dict[int, Any] = {}
        for t in of:
            for d in t.docs:
                docs.setdefault(id(d), d)
        # A repeated analysis of one machine is a copy of the first (analyzed_once.py):
        # the first call of every callable inside it is recorded by the first one.
        with (
            self.recording(),
            warnings.catch_warnings(),
            analyze_each_machine_once(),
        ):
            warnings.simplefilter("ignore")
            for d in docs.values():
                _run_examples([d], {})
                plt.close("all")

    def calls(self, of: list[Target]) -> dict[str, Call]:
        """name -> (args, kwargs) of the first call of each target recorded."""
        return {t.name: self.seen[t.code] for t in of if t.code in self.seen}


#: The docstring test's recording in this process (:func:`docstrings_recording`).
DOCSTRINGS: list[FirstCalls] = []


def docstrings_recording() -> FirstCalls:
    """This process's recording of the docstring test's examples, watching every
    public callable (result classes' constructors too: a superset of the fuzz's)."""
    if not DOCSTRINGS:
        DOCSTRINGS.append(FirstCalls(frozenset(t.code for t in targets(()))))
    return DOCSTRINGS[0]


def docstrings_calls(of: list[Target]) -> dict[str, Call] | None:
    """The first calls of ``of`` that the docstring test recorded in this process,
    or None unless every package module's examples ran (and passed) under it."""
    if not DOCSTRINGS or not set(package_modules()) <= DOCSTRINGS[0].modules:
        return None
    return DOCSTRINGS[0].calls(of)
