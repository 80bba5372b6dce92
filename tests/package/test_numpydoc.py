"""The public docstrings of the converted domains keep numpydoc's sections (issue 21).

A domain in ``CONVERTED`` has every public object, what its door exports in
``__all__`` and the public methods and properties of the exported classes, pass
numpydoc's validation for the checks below: a summary, every parameter
documented (and none that does not exist), a Returns section, an Examples
section. Converting a domain is adding it here; a docstring that loses a section
fails the test naming the object and the checks.

Module constants (tuples, frozensets, floats) cannot carry a docstring of their
own in Python (``__doc__`` is their type's), so numpydoc would read the built-in
type's: they are documented with a ``#:`` comment above the assignment in the
module that defines them (where Sphinx's autodoc reads a constant's
documentation), and that comment is what is checked for them.
"""

from __future__ import annotations

import importlib
import inspect
import types

import pytest
from cyclomech._keydocs import doc_comment
from numpydoc.validate import validate

CONVERTED = [
    "cyclomech.forces",
    "cyclomech.shaft",
    "cyclomech.dynamics",
    "cyclomech.servo",
    "cyclomech.motion",
    "cyclomech.impact",
    "cyclomech.press",
    "cyclomech.transfer",
    "cyclomech.cam",
    "cyclomech.linkage",
    "cyclomech.plot",
    "cyclomech.cyclogram",
    "cyclomech.machine",
    "cyclomech",
]

# PR01 parameter not documented, PR02 unknown parameter, RT01 no Returns section,
# EX01 no Examples section, GL08 no docstring, SS01 no summary.
CHECKS = ("PR01", "PR02", "RT01", "EX01", "GL08", "SS01")


def _public(domain: str) -> tuple[list[str], list[str]]:
    """(documented objects, module constants) of ``domain`` by qualified name."""
    module = importlib.import_module(domain)
    objects: list[str] = []
    constants: list[str] = []
    for name in module.__all__:
        obj = getattr(module, name)
        if inspect.ismodule(obj):
            continue
        qual = f"{domain}.{name}"
        # A type alias (``Arc = tuple[str, str]``) is callable but is a constant: it
        # cannot carry a docstring of its own.
        alias = isinstance(obj, types.GenericAlias | types.UnionType)
        if alias or not (inspect.isclass(obj) or callable(obj)):
            constants.append(qual)
            continue
        objects.append(qual)
        if inspect.isclass(obj):
            for key, value in vars(obj).items():
                if key.startswith("_"):
                    continue
                if inspect.isfunction(value) or isinstance(
                    value, property | classmethod | staticmethod
                ):
                    objects.append(f"{qual}.{key}")
    return objects, constants


OBJECTS = [q for d in CONVERTED for q in _public(d)[0]]
CONSTANTS = [q for d in CONVERTED for q in _public(d)[1]]


@pytest.mark.parametrize("name", OBJECTS)
def test_numpydoc_sections(name: str) -> None:
    errors = [(code, msg) for code, msg in validate(name)["errors"] if code in CHECKS]
    assert not errors, f"{name} fails numpydoc " + "; ".join(f"{c}: {m}" for c, m in errors)


@pytest.mark.parametrize("name", CONSTANTS)
def test_constants_have_doc_comments(name: str) -> None:
    domain, _, short = name.rpartition(".")
    assert doc_comment(domain, short), (
        f"{name}: a module constant is documented by a '#:' comment above its assignment"
    )


def test_every_converted_domain_has_objects() -> None:
    for domain in CONVERTED:
        assert _public(domain)[0], f"{domain} exports nothing to check"
