"""Every name a domain's door exports is documented once on its API page: the pages
that list their members by hand (for a reading order) cannot drop a new export."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

API = Path(__file__).resolve().parents[2] / "docs" / "api"
PAGES = sorted(p for p in API.glob("*.rst") if p.stem not in ("index", "top"))


@pytest.mark.parametrize("page", PAGES, ids=[p.stem for p in PAGES])
def test_page_documents_every_export_once(page: Path) -> None:
    text = page.read_text(encoding="utf-8")
    (module,) = re.findall(r"^\.\. automodule:: (\S+)", text, re.MULTILINE)
    if ":no-members:" not in text:
        return  # automodule lists the door's __all__ itself
    door = importlib.import_module(module)
    named = re.findall(rf"^\.\. auto\w+:: {re.escape(module)}\.(\w+)", text, re.MULTILINE)
    wrong = sorted(n for n in set(named) if named.count(n) > 1 or n not in door.__all__)
    assert sorted(named) == sorted(door.__all__), (
        f"{page.name}: missing {sorted(set(door.__all__) - set(named))}, extra or repeated {wrong}"
    )
