"""A kind's documentation and lists come from the kind (issue 32, "the house, round
3"): the format reference gathers each registered kind's own ``key_docs``, and the
README's lists of kinds are held to the registry. A toy kind, a package written
into a temporary folder and registered with one line, is on the reference page with
no other edit, and a README that does not name it fails the README check."""

from __future__ import annotations

import importlib
import importlib.util
import re
import sys
import textwrap
from pathlib import Path

import pytest
from cyclomech import _keydocs
from cyclomech.machine import KINDS, register

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def readme_table_kinds(text: str) -> set[str]:
    """The kinds the README's architecture table names (its last column)."""
    lines = text.splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("| domain |"))
    assert lines[start].rstrip("|").rsplit("|", 1)[-1].strip() == "machine-file kind"
    kinds: set[str] = set()
    for ln in lines[start + 2 :]:
        if not ln.startswith("|"):
            break
        cell = ln.strip().strip("|").rsplit("|", 1)[-1]
        if "(keys of" not in cell:  # forces: keys of another kind's table
            kinds |= set(re.findall(r"`([a-z_]+)`", cell))
    return kinds


def readme_diagram_kinds(text: str) -> dict[str, str]:
    """The README's data-flow diagram's registry: kind → ``<door>.<class>``."""
    block = re.search(r"^KINDS \{(.*?)\}", text, re.MULTILINE | re.DOTALL)
    assert block, "the README's data-flow diagram has no KINDS {…}"
    return dict(re.findall(r'"([a-z_]+)": ([\w.]+)', block.group(1)))


def registry_as_the_readme_names_it() -> dict[str, str]:
    """The registry, each class by its door: ``{"cam": "cam.CamMechanism", …}``."""
    return {kind: f"{cls.__module__.split('.')[1]}.{cls.__name__}" for kind, cls in KINDS.items()}


def readme_problems(text: str) -> list[str]:
    """What the README says about the kinds that the registry does not."""
    problems = []
    table = readme_table_kinds(text)
    for kind in sorted(set(KINDS) - table):
        problems.append(f"the architecture table does not name the kind {kind!r}")
    for kind in sorted(table - set(KINDS)):
        problems.append(f"the architecture table names {kind!r}, which is not a kind")
    if readme_diagram_kinds(text) != registry_as_the_readme_names_it():
        problems.append(
            f"the data-flow diagram's KINDS {readme_diagram_kinds(text)} is not the "
            f"registry {registry_as_the_readme_names_it()}"
        )
    return problems


def test_the_readme_names_the_registered_kinds() -> None:
    assert readme_problems(README.read_text(encoding="utf-8")) == []


# ---------------------------------------------------------------- a toy kind
TOY_INIT = '''
"""A toy domain: a kind defined outside cyclomech."""
from ._kind import Rest

__all__ = ["Rest"]
'''
TOY_KIND = '''
"""The toy kind."""
from typing import ClassVar

from cyclomech.machine import KeyDoc, KeyTable, Unbounded


class Rest(Unbounded):
    """A toy kind that rests the tool between two strokes.

    Only what the format reference reads is here.
    """

    kind: ClassVar[str] = "rest"
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "rest_s", "pad"})
    key_docs: ClassVar[tuple[KeyTable, ...]] = (
        KeyTable("rest", "kind = rest", (
            KeyDoc("kind", "The mechanism's kind.", "—", "text", "required", "rest", False),
            KeyDoc("rest_s", "How long the tool rests.", "s", "number", "required",
                   "finite, > 0", True),
            KeyDoc("pad", "The pad under the tool.", "—", "table", "none (no pad)",
                   "a table {thickness_m}", True),
        )),
        KeyTable("rest.pad", "pad of a rest", (
            KeyDoc("thickness_m", "The pad's thickness.", "m", "number", "required",
                   "finite, > 0", None),
        ), intro="The pad under a resting tool."),
    )
'''


@pytest.fixture
def toy_kind(tmp_path, monkeypatch):
    """The toy package written into ``tmp_path``, imported and registered (one line)."""
    package = tmp_path / "toy_rest"
    package.mkdir()
    (package / "__init__.py").write_text(textwrap.dedent(TOY_INIT), encoding="utf-8")
    (package / "_kind.py").write_text(textwrap.dedent(TOY_KIND), encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    cls = importlib.import_module("toy_rest").Rest
    register(cls)  # the one line
    try:
        yield cls
    finally:
        del KINDS["rest"]
        for name in ("toy_rest", "toy_rest._kind"):
            sys.modules.pop(name, None)


def _extension():
    spec = importlib.util.spec_from_file_location(
        "keys_reference", ROOT / "docs" / "_ext" / "keys_reference.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_registered_kind_is_on_the_format_page_with_no_other_edit(toy_kind, tmp_path):
    tables = _keydocs.tables()
    # After every stock kind, in the registry's order, its own table first.
    assert list(tables)[-2:] == ["rest", "rest.pad"]
    assert [k.name for k in tables["rest"].keys] == ["kind", "rest_s", "pad"]
    page = _extension().write(tmp_path / "docs").read_text(encoding="utf-8")
    assert page == _keydocs.render_page()
    section = page.split("kind = rest\n-----------\n", 1)[1].split("pad of a rest\n", 1)[0]
    # Its paragraph is its docstring's first; its rows its records.
    assert section.startswith("\nA toy kind that rests the tool between two strokes.\n")
    assert "   * - ``rest_s``\n     - How long the tool rests.\n     - s\n" in section
    assert "The pad under a resting tool." in page and "``thickness_m``" in page


def test_the_lists_the_tests_derive_take_a_registered_kind(toy_kind):
    # The reference's own checks read the registry: the toy's table is the one
    # whose paragraph comes from its class, beside the stock kinds'.
    own = {name for name, t in _keydocs.tables().items() if t.intro is None}
    assert own == set(KINDS) and "rest" in own
    # The README check reads the registry too: the README does not name the toy.
    problems = readme_problems(README.read_text(encoding="utf-8"))
    assert "the architecture table does not name the kind 'rest'" in problems
    assert any("data-flow diagram" in p for p in problems)


def test_a_kind_without_key_docs_is_refused_by_the_page(monkeypatch):
    class Bare:
        """A kind that documents nothing."""

        kind = "bare"

    monkeypatch.setitem(KINDS, "bare", Bare)
    with pytest.raises(ValueError, match=r"the kind 'bare' \(.*Bare\) documents no keys"):
        _keydocs.render_page()
