"""The house's layers (issue 32, round 3), read from the code's own imports with
``ast``: the cyclogram's LP is solved in one package (scipy's ``linprog`` is named
only inside ``cyclogram/``); the modules of the cyclogram and of the main shaft
import each other one way (no circle, imports under ``TYPE_CHECKING`` and inside
functions counted too); and the cyclogram stands on the shared ground alone (no
mechanism kind, no machine, no other domain above it)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[2] / "python" / "cyclomech"

#: The shared modules every domain may stand on (errors, number checks, the Rust
#: core, units, files, TOML, the key documentation, plotting, notebook and CLI helpers,
#: the animation's scenes).
GROUND = {
    "cyclomech._arrays",
    "cyclomech._cli",
    "cyclomech._core",
    "cyclomech._errors",
    "cyclomech._files",
    "cyclomech._json",
    "cyclomech._keydoc",
    "cyclomech._notebook",
    "cyclomech._plotting",
    "cyclomech._scene",
    "cyclomech._toml",
    "cyclomech._units",
}


def _module(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_module(name: str, root: Path) -> bool:
    base = root.joinpath(*name.split("."))
    return any(base.with_suffix(s).is_file() for s in (".py", ".pyi")) or base.is_dir()


def imports(path: Path, root: Path = PKG.parent) -> set[str]:
    """The cyclomech modules ``path`` (a file under ``root``) imports, anywhere in
    it (under ``TYPE_CHECKING`` and inside functions too); ``from . import x``
    names the module x where x is one, else the package."""
    me = _module(path, root)
    package = me if path.name == "__init__.py" else me.rsplit(".", 1)[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join([*base, node.module] if node.module else base)
            else:
                mod = node.module or ""
            subs = {f"{mod}.{a.name}" for a in node.names if _is_module(f"{mod}.{a.name}", root)}
            out |= subs
            if len(subs) < len(node.names):  # a name from the package itself
                out.add(mod)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
    return {m for m in out if m.split(".")[0] == "cyclomech"}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (or a module
    importing itself): Tarjan's algorithm."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in graph.get(v, ()):
                found.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def package_graph(folder: Path) -> dict[str, set[str]]:
    """Each module of the package ``folder`` and the modules of it that it imports."""
    paths = sorted(folder.glob("*.py"))
    known = {_module(p, PKG.parent) for p in paths}
    return {_module(p, PKG.parent): imports(p) & known for p in paths}


def test_circles_finds_a_circle_and_only_one():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"e"}}
    assert circles(graph) == [["a", "b", "c"], ["e"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def test_imports_reads_type_checking_and_function_imports(tmp_path):
    pkg = tmp_path / "cyclomech" / "cyclogram"
    pkg.mkdir(parents=True)
    src = pkg / "_x.py"
    (pkg / "_file.py").write_text("")
    src.write_text(
        "from typing import TYPE_CHECKING\n"
        "from . import _file, Arc\n"
        "if TYPE_CHECKING:\n    from ._model import Cyclogram\n"
        "def f():\n    from .._kind import Bound\n"
    )
    assert imports(src, tmp_path) == {
        "cyclomech.cyclogram",
        "cyclomech.cyclogram._file",
        "cyclomech.cyclogram._model",
        "cyclomech._kind",
    }
    assert imports(pkg / "_file.py", tmp_path) == set()


@pytest.mark.parametrize("package", ["cyclogram", "shaft"])
def test_no_import_circle_inside_the_package(package):
    assert circles(package_graph(PKG / package)) == []


def test_linprog_is_named_only_inside_the_cyclogram():
    # The cyclogram's LP is built and solved in one package: another domain asks
    # it (Cyclogram.feasible_set) instead of calling the solver on its rows.
    outside = []
    for path in sorted(PKG.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        named = any(
            (isinstance(n, ast.Name) and n.id == "linprog")
            or (isinstance(n, ast.Attribute) and n.attr == "linprog")
            or (isinstance(n, ast.alias) and n.name.split(".")[-1] == "linprog")
            for n in ast.walk(tree)
        )
        if named and path.relative_to(PKG).parts[0] != "cyclogram":
            outside.append(str(path.relative_to(PKG)))
    assert outside == []


def test_the_cyclogram_stands_on_the_ground_alone():
    # Bound laws belong to the cyclogram (issue 32): it imports no mechanism-kind
    # contract (_kind), no machine, no other domain.
    above = {}
    for path in sorted((PKG / "cyclogram").glob("*.py")):
        bad = {
            m for m in imports(path) if not m.startswith("cyclomech.cyclogram") and m not in GROUND
        }
        if bad:
            above[path.name] = sorted(bad)
    assert above == {}
