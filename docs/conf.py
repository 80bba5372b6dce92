"""Sphinx configuration of cyclomech's documentation site.

Build: ``pip install ".[docs]" && sphinx-build -W --keep-going -b html docs docs/_build/html``
(warnings are errors: a broken reference or a gallery example that fails stops
the build).
"""

from __future__ import annotations

import re
import sys
import types
from pathlib import Path

import cyclomech
from cyclomech._keydocs import doc_comment, roles_as_literals

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

project = "cyclomech"
author = "the cyclomech developers"
copyright = "2026, the cyclomech developers"
release = cyclomech.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax served from the site itself, not a CDN
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "keys_reference",  # docs/_ext: the machine-file format from cyclomech._keydocs
    "machine_run",  # docs/_ext: the machine guide's transcripts of cyclomech run / sweep
]

exclude_patterns = [
    "_build",
    "gallery/README.rst",
    "reference/_generated",
    "api/_generated",
    "guide/_generated",
]
templates_path: list[str] = []
html_static_path = ["_static"]
html_css_files = ["cyclomech.css"]

# The API reference: numpydoc renders the docstrings' sections; members come
# from each domain package's ``__all__`` (its door).
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"  # numpydoc sections carry the types and units
autosummary_generate = False
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,  # an example that fails fails the build
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "within_subsection_order": "FileNameSortKey",
    # No computation-times page: it loads DataTables from a CDN (the site is offline).
    "write_computation_times": False,
}

html_theme = "pydata_sphinx_theme"
html_title = f"cyclomech {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    # The format reference's wide tables get the whole width.
    "secondary_sidebar_items": {"**": ["page-toc"], "reference/machine_format": []},
}
html_show_sourcelink = False

# Every cross-reference must resolve (with -W a broken one fails the build). The
# types named in prose that are not cyclomech's own are not linked anywhere.
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|matplotlib|scipy|pandas|pyarrow|dask|pathlib|collections|typing)\..*"),
]


# The docstrings are written to read well in a terminal (``help()``) as much as
# here: |x| is a magnitude, not a reStructuredText substitution. Escape the bars
# outside code (doctest lines and literal blocks are left as they are).
def _bars_are_magnitudes(app, what, name, obj, options, lines: list[str]) -> None:
    literal_indent: int | None = None
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if literal_indent is not None:
            if stripped and indent <= literal_indent:
                literal_indent = None
            else:
                continue
        if stripped.startswith((">>>", "...")):
            continue
        if "|" in line and "``" not in line:
            lines[i] = line.replace("|", r"\|")
        elif "|" in line:
            # Only outside inline literals.
            parts = line.split("``")
            lines[i] = "``".join(p if k % 2 else p.replace("|", r"\|") for k, p in enumerate(parts))
        if stripped.endswith("::"):
            literal_indent = indent


def _top_level_names(app) -> None:
    """Write api/_generated/top_names.rst: each name ``cyclomech`` exports at its top
    level, linked to where its domain's page documents it (from ``__all__``, so the
    list cannot drift)."""
    import importlib
    import inspect

    rows = []
    for name in cyclomech.__all__:
        obj = getattr(cyclomech, name)
        if inspect.ismodule(obj) or name.startswith("_"):
            continue
        home = "cyclomech"
        for domain in _domains():
            mod = importlib.import_module(f"cyclomech.{domain}")
            if getattr(mod, name, None) is obj and name in getattr(mod, "__all__", ()):
                home = mod.__name__
                break
        errors = isinstance(obj, type) and issubclass(obj, Exception)
        role = "func" if inspect.isfunction(obj) else "exc" if errors else "class"
        summary = " ".join((inspect.getdoc(obj) or "").split("\n\n", 1)[0].split())
        # Cross-references in a summary resolve in its own module, not here: keep
        # their text as literals (the row's name links to the full entry).
        summary = roles_as_literals(summary)
        rows.append(f"   * - :{role}:`cm.{name} <{home}.{name}>`\n     - {summary}")
    out = Path(app.srcdir) / "api" / "_generated" / "top_names.rst"
    out.parent.mkdir(parents=True, exist_ok=True)
    text = (
        ".. list-table::\n   :header-rows: 1\n   :widths: 30 70\n\n"
        "   * - name\n     - what it is\n" + "\n".join(rows) + "\n"
    )
    if not out.exists() or out.read_text(encoding="utf-8") != text:
        out.write_text(text, encoding="utf-8")


def _door_constant(name: str) -> tuple[str, str] | None:
    """(door, short name) when ``name`` is a constant a door exports."""
    import importlib
    import inspect

    door, _, short = name.rpartition(".")
    try:
        module = importlib.import_module(door)
    except ImportError:
        return None
    obj = getattr(module, short, None)
    if short not in getattr(module, "__all__", ()) or obj is None:
        return None
    if inspect.ismodule(obj) or inspect.isclass(obj) or inspect.isroutine(obj):
        return None
    return door, short


def _domains() -> list[str]:
    """The domain packages of cyclomech (its subpackages), found, not listed: a new
    domain's door is searched with no edit here."""
    import pkgutil

    return sorted(m.name for m in pkgutil.iter_modules(cyclomech.__path__) if m.ispkg)


def _constant_pages(srcdir: str | Path) -> list[str]:
    """The API pages that list a door's members with automodule (the others list
    theirs by hand) and so include a generated "Constants" section: autodoc does not
    document constants a door imports, their ``#:`` comments being where they are
    defined. Read from the pages themselves (each includes
    ``_generated/constants_<page>.rst``), so a new page needs no edit here."""
    pattern = re.compile(r"^\.\. include:: _generated/constants_(\w+)\.rst$", re.MULTILINE)
    return sorted(
        m.group(1)
        for page in sorted((Path(srcdir) / "api").glob("*.rst"))
        for m in pattern.finditer(page.read_text(encoding="utf-8"))
    )


def _door_constants(app) -> None:
    """Write api/_generated/constants_<page>.rst: an ``autodata`` for each constant
    (or type alias) the page's door exports, from its ``__all__``."""
    import importlib
    import inspect

    for page in _constant_pages(app.srcdir):
        door = importlib.import_module(f"cyclomech.{page}")
        names = [
            n
            for n in door.__all__
            if not any(
                f(getattr(door, n)) for f in (inspect.ismodule, inspect.isclass, inspect.isroutine)
            )
        ]
        text = ""
        if names:
            text = "Constants\n---------\n\n"
            for n in names:
                value = getattr(door, n)
                if isinstance(value, types.GenericAlias | types.UnionType) or callable(value):
                    # A type alias: autodoc cannot format it; its comment by hand.
                    alias = str(value).replace("typing.", "")
                    text += f".. py:data:: cyclomech.{page}.{n}\n"
                    text += f"   :value: {alias}\n\n" if len(alias) <= 60 else "\n"
                    text += "".join(f"   {ln}\n" for ln in doc_comment(f"cyclomech.{page}", n))
                    text += "\n"
                    continue
                text += f".. autodata:: cyclomech.{page}.{n}\n"
                text += "   :no-value:\n\n" if len(repr(value)) > 160 else "\n"
        out = Path(app.srcdir) / "api" / "_generated" / f"constants_{page}.rst"
        out.parent.mkdir(parents=True, exist_ok=True)
        if not out.exists() or out.read_text(encoding="utf-8") != text:
            out.write_text(text, encoding="utf-8")


def _constant_comment(app, what, name, obj, options, lines: list[str]) -> None:
    """A door constant's documentation: the ``#:`` comment above its assignment in
    the door's modules (what tests/test_numpydoc.py checks is there)."""
    if what != "data":
        return
    found = _door_constant(name)
    if found is None:
        return
    comment = doc_comment(*found)
    if comment:
        lines[:] = comment


def _top_level_targets(app, env, node, contnode):
    """``cyclomech.X`` (a top-level export) links to where its domain documents it."""
    target = node.get("reftarget", "")
    if node.get("refdomain") != "py" or not target.startswith("cyclomech."):
        return None
    head, _, rest = target[len("cyclomech.") :].partition(".")
    obj = getattr(cyclomech, head, None)
    home = getattr(obj, "__module__", "")
    if obj is None or not home.startswith("cyclomech."):
        return None
    door = ".".join(home.split(".")[:2])
    new = f"{door}.{head}" + (f".{rest}" if rest else "")
    if new == target:
        return None
    py = env.get_domain("py")
    return py.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], new, node, contnode)


def setup(app):
    app.connect("autodoc-process-docstring", _bars_are_magnitudes)
    app.connect("builder-inited", _top_level_names)
    app.connect("builder-inited", _door_constants)
    app.connect("autodoc-process-docstring", _constant_comment)
    app.connect("missing-reference", _top_level_targets)
