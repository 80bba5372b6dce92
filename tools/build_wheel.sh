#!/usr/bin/env bash
# Build the one wheel cyclomech ships: abi3 (CPython >= 3.11), manylinux2014
# (glibc >= 2.17), release profile. Usage: bash tools/build_wheel.sh [OUT_DIR]
#
# Why zig: linked on this Debian 12 host (glibc 2.36) the extension picks up
# symbol versions up to GLIBC_2.35 (hypot, pthread_*, stat64) and maturin could
# only tag it manylinux_2_35, which excludes RHEL 8/9 and Ubuntu 20.04. `--zig`
# links against glibc 2.17's symbols instead (ziglang from PyPI, no system
# packages), and maturin's compliance check then passes for manylinux2014.
# The build tools go into their own virtual environment, not the caller's.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
out="$(realpath -m "${1:-$repo/dist}")"
tools="${CYCLOMECH_WHEEL_TOOLS:-${TMPDIR:-/tmp}/cyclomech-wheel-tools}"
if ! { [ -x "$tools/bin/maturin" ] && "$tools/bin/python" -c "import ziglang" 2>/dev/null; }; then
    python3 -m venv "$tools"
    "$tools/bin/pip" install -q "maturin>=1.9.4,<2" "ziglang>=0.13"
fi
mkdir -p "$out"
rm -f "$out"/cyclomech-*.whl
cd "$repo"
# Its own target directory: the zig linker changes every artefact's fingerprint,
# and sharing target/ with `pip install -e .` would rebuild both each time.
CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target/wheel}" PATH="$tools/bin:$PATH" \
    maturin build --release --locked --zig --compatibility manylinux2014 --out "$out"
ls "$out"/cyclomech-*.whl
