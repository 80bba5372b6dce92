#!/usr/bin/env bash
# Prove a built wheel: install it into a fresh virtual environment with no Rust
# toolchain on PATH, then run the test suite against the installed package.
# Usage: bash tools/test_wheel.sh WHEEL [PYTEST ARGS...]
#
# pytest runs from an empty directory, so `import cyclomech` can only find the
# installed wheel (the check below fails loudly otherwise); the tests themselves
# are read from the repository.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
wheel="$(realpath "$1")"
shift
work="$(mktemp -d "${TMPDIR:-/tmp}/cyclomech-wheel-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
python3 "$repo/tools/check_wheel.py" "$wheel"
python3 -m venv "$work/venv"
# PATH without any directory that holds cargo, rustc or rustup.
clean_path=""
IFS=: read -ra dirs <<< "$PATH"
for d in "${dirs[@]}"; do
    if [ -n "$d" ] && [ ! -e "$d/cargo" ] && [ ! -e "$d/rustc" ] && [ ! -e "$d/rustup" ]; then
        clean_path="${clean_path:+$clean_path:}$d"
    fi
done
export PATH="$work/venv/bin:$clean_path"
unset CARGO_HOME RUSTUP_HOME CARGO_TARGET_DIR VIRTUAL_ENV
if command -v cargo >/dev/null || command -v rustc >/dev/null; then
    echo "test_wheel.sh: a Rust toolchain is still on PATH: $(command -v cargo rustc)" >&2
    exit 1
fi
# --only-binary: pip may not fall back to building cyclomech from a source tree.
pip install -q --only-binary cyclomech "$wheel[test]"
cd "$work"
where="$(python -c 'import cyclomech, sys; print(cyclomech.__file__)')"
case "$where" in
    "$work/venv/"*) echo "== testing the installed wheel at $where" ;;
    *) echo "test_wheel.sh: cyclomech imported from $where, not from the wheel" >&2; exit 1 ;;
esac
# Left out here, having run on the source install already (CI's budget is 25
# minutes, and this second run is its largest part): the tests of the source tree
# itself (its layout, import layers, types, docstring sections, API pages), which say
# nothing of the wheel (~30 s); the slow tests (Ctrl-C at start-up and in kernels,
# ~40 s), which time Python's signal handling, not the build; and the full-disk
# tests (~30 s), which test the Python writers against a tmpfs. Every kernel, every
# docstring example and the entry point's import still run against the wheel. The -m
# replaces pyproject's (-m "not exhaustive"), so it says both.
python -m pytest "$repo/tests" -p no:cacheprovider -q -n auto -m "not slow and not exhaustive" \
    --ignore="$repo/tests/package/test_full_disk.py" \
    --ignore="$repo/tests/package/test_architecture.py" \
    --ignore="$repo/tests/package/test_layers.py" \
    --ignore="$repo/tests/package/test_types.py" \
    --ignore="$repo/tests/package/test_numpydoc.py" \
    --ignore="$repo/tests/package/test_docs_api.py" \
    "$@"
