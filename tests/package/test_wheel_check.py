"""tools/check_wheel.py (run by CI on the built wheel) finds what it must: a
wrong tag or version, a missing stub or module, a file that does not belong.
Checked on synthetic wheels written here, so no build is needed."""

from __future__ import annotations

import importlib.util
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("check_wheel", ROOT / "tools" / "check_wheel.py")
assert _spec and _spec.loader
check_wheel = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check_wheel)

VERSION = tomllib.loads((ROOT / "Cargo.toml").read_text())["workspace"]["package"]["version"]
TAG = "manylinux2014_x86_64.manylinux_2_17_x86_64"


def _members(version: str = VERSION) -> dict[str, str]:
    pkg = ROOT / "python" / "cyclomech"
    files = {f"cyclomech/{p.relative_to(pkg)}": "" for p in pkg.rglob("*.py")}
    files |= {"cyclomech/_core.abi3.so": "", "cyclomech/_core.pyi": "", "cyclomech/py.typed": ""}
    entry = ROOT / "python" / "_cyclomech_entry"  # the console script's entry point
    files |= {f"_cyclomech_entry/{p.relative_to(entry)}": "" for p in entry.rglob("*.py")}
    meta = f"Metadata-Version: 2.4\nName: cyclomech\nVersion: {version}\nRequires-Python: >=3.11\n"
    files[f"cyclomech-{version}.dist-info/METADATA"] = meta
    return files


def _wheel(tmp: Path, files: dict[str, str], version: str = VERSION, tag: str = TAG) -> Path:
    path = tmp / f"cyclomech-{version}-cp311-abi3-{tag}.whl"
    with zipfile.ZipFile(path, "w") as z:
        for name, text in files.items():
            z.writestr(name, text)
    return path


def test_a_complete_wheel_passes(tmp_path):
    assert check_wheel.problems(_wheel(tmp_path, _members())) == []


@pytest.mark.parametrize(
    ("change", "problem"),
    [
        (lambda f: f.pop("cyclomech/_core.pyi"), "missing cyclomech/_core.pyi"),
        (lambda f: f.pop("cyclomech/py.typed"), "missing cyclomech/py.typed"),
        (lambda f: f.pop("cyclomech/machine/_sweep.py"), "missing cyclomech/machine/_sweep.py"),
        (
            lambda f: f.pop("_cyclomech_entry/_interrupt.py"),
            "missing _cyclomech_entry/_interrupt.py",
        ),
        (lambda f: f.update({"tests/test_x.py": ""}), "unexpected file tests/test_x.py"),
        (lambda f: f.update({"cyclomech/data.csv": ""}), "unexpected file cyclomech/data.csv"),
    ],
    ids=["no stub", "no py.typed", "no module", "no entry module", "tests", "data"],
)
def test_each_content_problem_is_named(tmp_path, change, problem):
    files = _members()
    change(files)
    assert problem in check_wheel.problems(_wheel(tmp_path, files))


def test_a_wrong_version_or_tag_is_named(tmp_path):
    bad = check_wheel.problems(_wheel(tmp_path, _members("9.9.9"), version="9.9.9"))
    assert f"wheel version 9.9.9 != Cargo.toml's workspace version {VERSION}" in bad
    bad = check_wheel.problems(_wheel(tmp_path, _members(), tag="manylinux_2_35_x86_64"))
    assert bad == ["platform tags manylinux_2_35_x86_64 do not include manylinux2014_x86_64"]
    other = tmp_path / f"cyclomech-{VERSION}-cp312-cp312-{TAG}.whl"
    other.write_bytes(b"")
    assert check_wheel.problems(other) == [f"{other.name}: not an abi3 cp311 wheel of cyclomech"]


def test_the_version_is_written_once():
    """pyproject.toml takes the version from Cargo.toml (maturin's dynamic version),
    and the installed package reports the same."""
    import cyclomech

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert "version" not in project and "version" in project["dynamic"]
    assert cyclomech.__version__ == VERSION
