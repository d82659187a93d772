#!/usr/bin/env bash
# Record the current ABI on purpose: rewrite tests/abi/symbols.txt (the
# exported names) and tests/abi/brdffit.abi (the abidiff baseline) from a
# build of the shared library.
#
# usage: bash scripts/update-abi.sh [BUILD_DIR]      (default: build)
#
# Use a plain gcc build (no sanitizers) configured from this tree; the
# script builds it first. Review `git diff tests/abi` afterwards: removed or
# changed entries mean an ABI break, which needs a new major version.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build}

if ! command -v abidw > /dev/null || ! command -v abidiff > /dev/null; then
    echo "update-abi.sh: abidw/abidiff not found (Debian: apt-get install abigail-tools)" >&2
    exit 1
fi
if [ ! -f "$build/CMakeCache.txt" ]; then
    cmake -S . -B "$build"
fi
targets=(brdffit)
if grep -q '^BRDFFIT_BUILD_STATIC:BOOL=ON' "$build/CMakeCache.txt"; then
    targets+=(brdffit_static)
fi
cmake --build "$build" -j2 --target "${targets[@]}"

# The ABI tests rewrite their baselines when BRDFFIT_ABI_UPDATE=1, so the
# recorded files come from exactly the commands that later check them.
(cd "$build" && BRDFFIT_ABI_UPDATE=1 ctest -R '^abi_(symbols|abidiff)$' --no-tests=error --output-on-failure)

(cd "$build" && ctest -R '^abi_' --output-on-failure)
echo "update-abi.sh: tests/abi/symbols.txt and tests/abi/brdffit.abi updated; review with git diff tests/abi"
