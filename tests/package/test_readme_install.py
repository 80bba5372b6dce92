"""The README's install advice (a user's trial: "about a minute" of compiling took
7 minutes on one busy core, with no sign of progress, and packaging details came
before any usage). The reference is the text CI runs and the script that builds the
wheel: the README's first two commands stay first and verbatim (``.ci/run`` greps
for them), usage comes before the install details, the compile's cost is stated in
minutes with the way to watch it, and a user without Rust is told where the wheel
comes from (``tools/build_wheel.sh``'s output folder) and how to install it."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
CI = (ROOT / ".ci" / "run").read_text(encoding="utf-8")


def test_the_first_two_commands_are_the_ones_ci_runs():
    commands = re.findall(r"^    (pip install .*)$", README, flags=re.M)
    assert (
        commands[0]
        == 'pip install ".[plot]" && cyclomech run examples/stb_loom.toml --out out/stb_loom'
    )
    assert commands[1] == 'pip install ".[test]" && python -m pytest -n auto'
    for var in ("TEST_CMD", "DOCS_CMD"):
        cmd = re.search(rf"^{var}='(.*)'$", CI, flags=re.M).group(1)
        assert cmd in README


def test_usage_comes_before_packaging():
    sections = re.findall(r"^## (.*)$", README, flags=re.M)
    assert sections.index("Install") > sections.index("The whole machine")
    assert sections[0] == "The cyclogram in Python"


def test_the_compile_is_priced_and_its_progress_shown():
    head = README[: README.index("## The cyclogram in Python")]
    assert "about a minute" not in README
    assert re.search(r"\d+ min", head) and 'pip install -v ".[plot]"' in head


def test_a_user_without_rust_gets_the_wheel():
    script = (ROOT / "tools" / "build_wheel.sh").read_text(encoding="utf-8")
    assert 'out="$(realpath -m "${1:-$repo/dist}")"' in script  # where it lands
    install = README[README.index("## Install") :]
    assert "bash tools/build_wheel.sh" in install and "dist/" in install
    assert re.search(r'pip install "cyclomech-[^"]+\.whl\[plot\]"', install)
