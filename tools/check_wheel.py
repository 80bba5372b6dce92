"""Check a built cyclomech wheel: its tags, its contents and its version.

Usage: ``python tools/check_wheel.py dist/cyclomech-*.whl``. Exits non-zero naming
every problem:

- one abi3 wheel for CPython >= 3.11 with a manylinux2014 (glibc 2.17) tag;
- the package and nothing else: every module of ``python/cyclomech``, the
  compiled ``_core.abi3.so``, its stub ``_core.pyi`` and ``py.typed`` (PEP 561);
  no tests, examples, benches, Rust sources or build artefacts;
- the version in the wheel's name and metadata is the workspace's (Cargo.toml,
  the one place it is written);
- smaller than 10 MB.
"""

from __future__ import annotations

import re
import sys
import tomllib
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
MAX_BYTES = 10_000_000


def problems(wheel: Path) -> list[str]:
    """Every way ``wheel`` falls short of the rules above (empty when it passes)."""
    out = []
    version = tomllib.loads((REPO / "Cargo.toml").read_text())["workspace"]["package"]["version"]
    m = re.fullmatch(r"cyclomech-([^-]+)-cp311-abi3-(.+)\.whl", wheel.name)
    if not m:
        return [f"{wheel.name}: not an abi3 cp311 wheel of cyclomech"]
    if m.group(1) != version:
        out.append(f"wheel version {m.group(1)} != Cargo.toml's workspace version {version}")
    if "manylinux2014_x86_64" not in m.group(2).split("."):
        out.append(f"platform tags {m.group(2)} do not include manylinux2014_x86_64")
    size = wheel.stat().st_size
    if size > MAX_BYTES:
        out.append(f"{size / 1e6:.1f} MB, more than {MAX_BYTES / 1e6:.0f} MB")
    names = set(zipfile.ZipFile(wheel).namelist())
    package = {
        "cyclomech/" + str(p.relative_to(REPO / "python" / "cyclomech"))
        for p in (REPO / "python" / "cyclomech").rglob("*.py")
    }
    needed = package | {"cyclomech/_core.abi3.so", "cyclomech/_core.pyi", "cyclomech/py.typed"}
    # The console script's entry point, outside the package: every module of it.
    needed |= {
        "_cyclomech_entry/" + str(p.relative_to(REPO / "python" / "_cyclomech_entry"))
        for p in (REPO / "python" / "_cyclomech_entry").rglob("*.py")
    }
    out += [f"missing {n}" for n in sorted(needed - names)]
    dist_info = f"cyclomech-{m.group(1)}.dist-info/"
    extra = sorted(n for n in names - needed if not n.startswith(dist_info))
    out += [f"unexpected file {n}" for n in extra]
    if dist_info + "METADATA" not in names:
        return [*out, f"no {dist_info}METADATA"]
    meta = zipfile.ZipFile(wheel).read(dist_info + "METADATA").decode()
    if f"\nVersion: {version}\n" not in meta:
        out.append(f"METADATA does not say Version: {version}")
    if "Requires-Python: >=3.11" not in meta:
        out.append("METADATA does not say Requires-Python: >=3.11")
    return out


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    wheel = Path(argv[0])
    bad = problems(wheel)
    for p in bad:
        print(f"{wheel.name}: {p}", file=sys.stderr)
    if not bad:
        size = wheel.stat().st_size / 1e6
        print(f"{wheel.name}: ok ({size:.2f} MB, {len(zipfile.ZipFile(wheel).namelist())} files)")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
