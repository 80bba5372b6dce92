"""The API pages and the documentation speak of the product, not of its history.

A new user read "(issue 19)", "the code lives in private modules beside this door"
and private module names on the API pages. Every docstring the API pages show — each
door's module docstring and those of the names in its ``__all__`` with their public
methods and properties — and every ``.rst`` page of ``docs/`` is checked here for an
issue number, the private-module paragraph and dotted private names
(``cyclomech.x._y``; a doctest's traceback shows the errors' module, as Python
prints it). Comments in the code may keep their issue references.

``ALLOWED`` lists the files other work is editing today; they are to be cleaned and
the list emptied (``test_the_allow_list_is_needed`` fails for an entry no longer
needed).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import cyclomech
import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "python" / "cyclomech"
#: What a page of the product does not say.
HISTORY = re.compile(
    r"\b[Ii]ssues? \d+|private modules? beside|beside this door|"
    r"\bcyclomech(?:\.[a-z]\w*)*\._(?!errors\.)[a-z]\w*"
)
#: Files whose text is being edited elsewhere: to be cleaned, then this emptied.
ALLOWED: set[str] = set()


def _allowed(path: str) -> bool:
    return any(path == a or (a.endswith("/") and path.startswith(a)) for a in ALLOWED)


def _doors() -> list[str]:
    return ["cyclomech"] + [
        f"cyclomech.{m.name}"
        for m in pkgutil.iter_modules(cyclomech.__path__)
        if not m.name.startswith("_") and m.name not in ("cli",)
    ]


def _source(obj: object) -> str:
    try:
        return Path(inspect.getsourcefile(obj) or "").resolve().relative_to(ROOT).as_posix()
    except (TypeError, ValueError):
        return ""


def _public_docstrings() -> list[tuple[str, str, str]]:
    """(name, source file, docstring) of everything the API pages show."""
    out, seen = [], set()
    for door in _doors():
        mod = importlib.import_module(door)
        items = [(door, mod)] + [(f"{door}.{n}", getattr(mod, n)) for n in mod.__all__]
        for name, obj in items:
            members = [(name, obj)]
            if inspect.isclass(obj):
                for k, v in vars(obj).items():
                    if k.startswith("_") and k != "__init__":
                        continue
                    v = v.__func__ if isinstance(v, classmethod | staticmethod) else v
                    v = v.fget if isinstance(v, property) else v
                    members.append((f"{name}.{k}", v))
            for n, o in members:
                if not (inspect.isroutine(o) or inspect.isclass(o) or inspect.ismodule(o)):
                    continue
                if id(o) in seen or not o.__doc__:
                    continue
                seen.add(id(o))
                src = _source(o) or _source(inspect.getmodule(o))
                out.append((n, src, o.__doc__))
    return out


DOCSTRINGS = _public_docstrings()
#: The pages as written (not those a build generates: the machine-file format page
#: is checked from its records below).
PAGES = sorted(
    p
    for p in (ROOT / "docs").rglob("*.rst")
    if not {"_build", "_generated", "auto_gallery"} & set(p.relative_to(ROOT).parts)
)


def _hits(text: str) -> list[str]:
    return [m.group(0) for m in HISTORY.finditer(text)]


def test_public_docstrings_speak_of_the_product():
    assert len(DOCSTRINGS) > 300  # the doors, their names and their methods
    bad = [
        f"{name} ({src}): {', '.join(_hits(doc))}"
        for name, src, doc in DOCSTRINGS
        if _hits(doc) and not _allowed(src)
    ]
    assert bad == [], "\n".join(bad)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_docs_pages_speak_of_the_product(page):
    rel = page.relative_to(ROOT).as_posix()
    if _allowed(rel):
        pytest.skip("allowed for now")
    assert _hits(page.read_text(encoding="utf-8")) == []


def test_the_check_finds_what_the_trial_found():
    assert _hits("Forces in planar linkages: kinetostatics (issue 19).") == ["issue 19"]
    assert _hits("The code lives in private modules beside this door: ``_model``")
    assert _hits("see ``cyclomech.cam._export`` and") == ["cyclomech.cam._export"]
    assert _hits("units ``_deg`` at the edges; cyclomech.cam.profile_table") == []


def test_the_allow_list_is_needed():
    """Each allowed path exists (an entry for a moved file would hide nothing)."""
    assert all((ROOT / a).exists() for a in ALLOWED)


def test_the_page_toc_wraps_long_names():
    """The page's table of contents cut long API names at the sidebar's edge: the
    site's stylesheet lets its entries, and the code in them, wrap anywhere."""
    css = (ROOT / "docs" / "_static" / "cyclomech.css").read_text(encoding="utf-8")
    rules = dict(re.findall(r"([^{}]+)\{([^}]*)\}", re.sub(r"/\*.*?\*/", "", css, flags=re.S)))
    toc = [body for sel, body in rules.items() if ".toc-entry a.nav-link code" in sel]
    assert toc, "no rule for the page's table of contents"
    decl = dict(d.split(":", 1) for d in toc[0].replace(" ", "").split(";") if d)
    assert decl.get("white-space") == "normal" and decl.get("overflow-wrap") == "anywhere"
    conf = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    assert '"cyclomech.css"' in conf and "pydata_sphinx_theme" in conf


def test_the_machine_file_reference_and_the_readme_speak_of_the_product():
    """The machine-file format page, generated from the key records, and the README."""
    from cyclomech._keydocs import render_page

    assert _hits(render_page()) == []
    assert _hits((ROOT / "README.md").read_text(encoding="utf-8")) == []
