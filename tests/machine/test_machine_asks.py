"""The machine package asks, it does not reach in (issue 32, "the house, round 3").

* The machine knows its mechanism kinds through the registry alone
  (``machine/_kinds.py``): no other module of ``cyclomech.machine`` imports a kind's
  class or a kind's private module, or tests a mechanism with ``isinstance`` against
  a kind's class. A kind's batch path for sweeps is the kind's optional hook
  ``batch_designs``, which the sweep asks the mechanism's class for.
* A class's private attributes (``self._x`` and its ``_x`` methods) are its
  module's own: no other module of the package reads them (the sweeps go through
  :class:`~cyclomech.Machine`'s public methods and properties).
"""

from __future__ import annotations

import ast
import importlib.util
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
from cyclomech.machine import KINDS, _batch

#: The repository's root, wherever this file stands under tests/.
ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").is_file())
PKG = ROOT / "python" / "cyclomech"
MACHINE = PKG / "machine"
#: The registry: the one module of the machine that names the kinds' classes.
REGISTRY = MACHINE / "_kinds.py"


def _modules(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*.py") if "__pycache__" not in p.parts)


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _absolute(node: ast.ImportFrom, me: str, is_package: bool) -> str:
    """The absolute module an ``from … import`` names, in the module ``me``."""
    if not node.level:
        return node.module or ""
    base = me.split(".") if is_package else me.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join([*base, node.module] if node.module else base)


def kind_reaches(path: Path, me: str, kinds: dict[str, str]) -> list[str]:
    """Where the module ``me`` at ``path`` reaches into a mechanism kind: an import
    of a kind's class (``kinds``: class name → its module) or of a kind's private
    module (its class's module, or a private module of that domain's package), and
    an ``isinstance``/``issubclass`` against a kind's class."""
    domains = {".".join(m.split(".")[:2]) for m in kinds.values()}
    bad = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        mods: list[tuple[str, list[str]]] = []
        if isinstance(node, ast.ImportFrom):
            mod = _absolute(node, me, path.name == "__init__.py")
            mods.append((mod, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            mods += [(a.name, []) for a in node.names]
        for mod, names in mods:
            for n in names:
                if n in kinds:
                    bad.append(f"{me}:{node.lineno}: imports the kind class {n} from {mod}")
                elif n.startswith("_") and mod in domains:
                    bad.append(f"{me}:{node.lineno}: imports the kind's private module {mod}.{n}")
            inside = [mod[len(d) + 1 :].split(".") for d in domains if mod.startswith(d + ".")]
            if mod in kinds.values() or any(p.startswith("_") for parts in inside for p in parts):
                bad.append(f"{me}:{node.lineno}: imports the kind's private module {mod}")
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("isinstance", "issubclass")
            and len(node.args) == 2
        ):
            for sub in ast.walk(node.args[1]):
                name = sub.id if isinstance(sub, ast.Name) else getattr(sub, "attr", None)
                if name in kinds:
                    bad.append(f"{me}:{node.lineno}: {node.func.id}(…, {name})")
    return bad


def _kinds() -> dict[str, str]:
    return {cls.__name__: cls.__module__ for cls in KINDS.values()}


def test_the_machine_knows_no_kind_but_through_its_registry():
    found = [
        b
        for p in _modules(MACHINE)
        if p != REGISTRY
        for b in kind_reaches(p, _module_name(p), _kinds())
    ]
    assert found == []


def test_the_kind_rule_catches_a_reach(tmp_path):
    # The checker itself, on modules written for it.
    bad = tmp_path / "bad.py"
    bad.write_text(
        "from ..impact import CamStop\n"
        "from ..impact._kind import _from_cam\n"
        "from ..press import _press\n"
        "def f(m):\n"
        "    return isinstance(m, (CamStop, int)) or isinstance(m, impact.CamStop)\n"
    )
    good = tmp_path / "good.py"
    good.write_text(
        "from ..impact import propped_lever_stiffness\n"
        "from .._kind import Proportional\n"
        "def f(m):\n"
        "    return isinstance(m, Proportional)\n"
    )
    found = kind_reaches(bad, "cyclomech.machine._bad", _kinds())
    assert kind_reaches(good, "cyclomech.machine._good", _kinds()) == []
    assert len(found) == 5, found
    assert "imports the kind class CamStop" in found[0]
    assert "cyclomech.impact._kind" in found[1]
    assert "cyclomech.press._press" in found[2]
    assert "isinstance(…, CamStop)" in found[3] and "isinstance(…, CamStop)" in found[4]


# --------------------------------------------------------------------- private attributes
def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def class_privates(tree: ast.Module) -> dict[str, set[str]]:
    """Each class of a module → its private attributes: ``self._x`` assignments in
    its methods and its ``_x`` methods and class attributes (dunders not counted)."""
    out: dict[str, set[str]] = {}
    for cls in (n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)):
        names: set[str] = set()
        for item in cls.body:
            if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef) and _private(item.name):
                names.add(item.name)
            targets = item.targets if isinstance(item, ast.Assign) else []
            if isinstance(item, ast.AnnAssign):
                targets = [item.target]
            names |= {t.id for t in targets if isinstance(t, ast.Name) and _private(t.id)}
        for node in ast.walk(cls):
            targets = []
            if isinstance(node, ast.Assign):
                targets = node.targets
            elif isinstance(node, ast.AnnAssign | ast.AugAssign):
                targets = [node.target]
            for t in (e for target in targets for e in ast.walk(target)):
                if (
                    isinstance(t, ast.Attribute)
                    and isinstance(t.value, ast.Name)
                    and t.value.id == "self"
                    and _private(t.attr)
                ):
                    names.add(t.attr)
        out[cls.name] = names
    return out


def _domain(module: str) -> str:
    """The package a module belongs to: ``cyclomech.<domain>``, or the module
    itself for one outside every domain (``cyclomech._kind``)."""
    parts = module.split(".")
    return ".".join(parts[:2]) if len(parts) > 2 or (PKG / parts[-1]).is_dir() else module


def private_reaches(
    modules: list[tuple[Path, str]], home: Callable[[str], str] = lambda me: me
) -> list[str]:
    """Every attribute access, in ``modules`` (path, module name), to a private
    name that a class of these modules defines, where no class at home with the
    accessing module defines that name: a reach into another home's object. The
    home of a module is ``home(module name)``: the module itself (the default) or
    its domain (:func:`_domain`)."""
    trees = {me: ast.parse(p.read_text(encoding="utf-8")) for p, me in modules}
    owners: dict[str, set[str]] = {}  # private name → modules whose classes define it
    classes: dict[str, set[str]] = {}  # private name → "module.Class"
    for me, tree in trees.items():
        for cls, names in class_privates(tree).items():
            for n in names:
                owners.setdefault(n, set()).add(me)
                classes.setdefault(n, set()).add(f"{me}.{cls}")
    bad = []
    for me, tree in trees.items():
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and _private(node.attr)
                and node.attr in owners
                and home(me) not in {home(o) for o in owners[node.attr]}
            ):
                who = ", ".join(sorted(classes[node.attr]))
                bad.append(f"{me}:{node.lineno}: .{node.attr} of {who}")
    return bad


def _package() -> list[tuple[Path, str]]:
    return [(p, _module_name(p)) for p in _modules(PKG)]


def test_no_domain_reads_another_domains_private_attributes():
    # Within a domain, its modules share their classes' insides (the cyclogram's
    # LP and speed search read Cyclogram's tables); across domains, never.
    assert private_reaches(_package(), _domain) == []


def test_the_machines_privates_stay_in_their_modules():
    # Stricter for the machine's classes: a private of Machine (``_bounded``,
    # ``_network``, its laws …) is read by _model.py alone; the sweeps in _many.py
    # and _batch.py use Machine's public properties (issue 32).
    tree = ast.parse((MACHINE / "_model.py").read_text(encoding="utf-8"))
    assert {"_bounded", "_network", "_laws"} <= class_privates(tree)["Machine"]
    found = [b for b in private_reaches(_package()) if " of cyclomech.machine." in b]
    assert found == []


def test_the_private_rule_catches_a_reach(tmp_path):
    owner, user = tmp_path / "owner.py", tmp_path / "user.py"
    owner.write_text(
        "class A:\n"
        "    _table = {}\n"
        "    def __init__(self):\n"
        "        self._n = 1\n"
        "        self.__dict__\n"
        "    def _start(self):\n"
        "        return self._n\n"
        "    def same_module(self, other):\n"
        "        return other._n\n"
    )
    user.write_text("def f(a):\n    return a._n, a._start(), a._table, a.__class__, a._elsewhere\n")
    found = private_reaches([(owner, "cyclomech.x._owner"), (user, "cyclomech.y._user")])
    assert sorted(f.split(": ", 1)[1] for f in found) == [
        f".{n} of cyclomech.x._owner.A" for n in ("_n", "_start", "_table")
    ]
    assert all(f.startswith("cyclomech.y._user:2") for f in found)
    # By domain: a module of the owner's domain may read them, another may not.
    both = [(owner, "cyclomech.x._owner"), (user, "cyclomech.x._user")]
    assert private_reaches(both, _domain) == []
    assert len(private_reaches(both)) == 3


# --------------------------------------------------------------------- the batch hook
def test_the_sweep_takes_a_kinds_batch_through_its_hook(monkeypatch):
    """The fast path is the kind's: the sweep asks the mechanism's class for
    ``batch_designs``, and without the hook the same sweep takes the per-design
    path, to the same numbers."""
    m = cm.Machine.example()
    cls = type(m.mechanisms["lifter"])
    asked = []
    real = cls.batch_designs.__func__

    def spy(kind, mechanism, table, keys):
        asked.append((kind, mechanism.name, tuple(keys)))
        return real(kind, mechanism, table, keys)

    monkeypatch.setattr(cls, "batch_designs", classmethod(spy))
    grid = {"lifter.preload_m": np.linspace(1e-4, 4e-4, 7), "speed_rpm": [250.0, 400.0]}
    fast = cm.sweep(m, grid, progress=False, n_threads=1)
    assert asked and all(a == (cls, "lifter", ("preload_m",)) for a in asked)
    pl = _batch.plan(m, ["lifter.preload_m"])
    assert pl is not None and pl.mechanisms == ("lifter",)
    # A kind without the hook: no batch plan, the per-design path, the same results.
    monkeypatch.delattr(cls, "batch_designs")
    assert _batch.plan(m, ["lifter.preload_m"]) is None
    slow = cm.sweep(m, grid, progress=False, n_threads=1)
    for k, v in slow.columns.items():
        w = fast.columns[k]
        assert (w == v).all() if v.dtype == object else np.array_equal(w, v, equal_nan=True), k


def test_a_hook_that_refuses_sends_the_sweep_the_per_design_way(monkeypatch):
    m = cm.Machine.example()
    cls = type(m.mechanisms["lifter"])
    monkeypatch.setattr(cls, "batch_designs", classmethod(lambda kind, mech, table, keys: None))
    assert _batch.plan(m, ["lifter.preload_m"]) is None


# --------------------------------------------------------------------- cut by subject
#: Lines of code a module of the machine may hold (issue 32: the report was 619).
MACHINE_LIMIT = 600
#: Lines of code of one function of the report's page and figures (the page was
#: one function of 168, the speed-sweep figure one of 145).
FUNCTION_LIMIT = 110


def _architecture() -> Any:
    """tests' test_architecture module (its ``code_lines``, the one way the house
    counts lines of code), loaded from wherever it stands under tests/."""
    path = next((ROOT / "tests").rglob("test_architecture.py"))
    spec = importlib.util.spec_from_file_location("_architecture_rules", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_machines_modules_are_cut_by_subject():
    code_lines = _architecture().code_lines
    sizes = {p.name: code_lines(p.read_text(encoding="utf-8")) for p in _modules(MACHINE)}
    assert {k: v for k, v in sizes.items() if v > MACHINE_LIMIT} == {}
    # The page is laid out apart from the files it is written with.
    report = ast.parse((MACHINE / "_report.py").read_text(encoding="utf-8"))
    imported = {a.name for n in ast.walk(report) if isinstance(n, ast.Import) for a in n.names}
    assert "html" not in imported
    long = []
    for name in ("_report.py", "_page.py", "plot.py"):
        text = (MACHINE / name).read_text(encoding="utf-8")
        lines = text.splitlines()
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.FunctionDef):
                body = "\n".join(lines[node.lineno - 1 : node.end_lineno])
                n = code_lines(textwrap.dedent(body))
                if n > FUNCTION_LIMIT:
                    long.append(f"{name}:{node.name}: {n}")
    assert long == []
