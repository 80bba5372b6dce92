"""The example machine files read well where the docs show them (new-user review):
their comment lines scrolled sideways in the article column. Every line that holds a
comment is at most 88 characters, the width the docs' code blocks show whole in a
1300 px window (docs/_static/cyclomech.css). Lines of values alone are the file's
data and are not re-wrapped (an inline table cannot span lines in TOML)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: Characters a comment line may take.
WIDTH = 88
#: TOML strings, removed before looking for a comment's ``#``.
STRINGS = re.compile(r'"(?:[^"\\]|\\.)*"|\'[^\']*\'')


def comment_lines_too_long(text: str) -> list[tuple[int, int]]:
    """(line number, length) of each line with a comment longer than :data:`WIDTH`."""
    return [
        (n, len(line))
        for n, line in enumerate(text.splitlines(), 1)
        if "#" in STRINGS.sub("", line) and len(line) > WIDTH
    ]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_example_comment_lines_fit_the_docs_column(path: Path) -> None:
    assert comment_lines_too_long(path.read_text(encoding="utf-8")) == []


def test_the_check_finds_comments_not_hashes_in_strings() -> None:
    long = "x" * WIDTH
    text = f'a = "{long}#"\nb = 1  # {long}\n# {long}\nc = 1  # short\n'
    assert comment_lines_too_long(text) == [(2, WIDTH + 9), (3, WIDTH + 2)]
