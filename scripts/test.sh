#!/usr/bin/env bash
# Build libbrdffit and run every test, from a fresh Debian machine.
#
#   bash scripts/test.sh
#
# 1. installs the build and test tools with apt-get (skipped when they are
#    all installed already);
# 2. build/        gcc, warnings as errors, all tests;
# 3. build-asan/   gcc, Debug, AddressSanitizer + UndefinedBehaviorSanitizer,
#                  all tests;
# 4. build-clang/  clang, warnings as errors, all tests.
# Every stage runs even if an earlier one failed; the last line sums up, and
# the exit status is non-zero if anything failed.
set -uo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
. scripts/common.sh

# Debian packages the build and the tests need. Add new ones here.
packages=(
    cmake
    make
    gcc
    libc6-dev
    g++              # the C++ compile check of the public headers
    clang
    libclang-rt-14-dev # sanitizer and fuzzer runtimes for clang
    libcmocka-dev
    pkg-config
    abigail-tools    # abidw/abidiff for the ABI check
    doxygen
    libpng-dev       # PNG previews of the brdffit command (tools/)
    python3          # the Python binding's tests (tests/python)
    python3-numpy
    python3-cffi
    # later: libgsl-dev libcminpack-dev (reference solvers for the benchmarks)
)

jobs=2

# run_stage NAME BUILD_DIR [cmake options...]; the compiler comes from CC/CXX.
run_stage()
{
    local name=$1 dir=$2
    shift 2
    log "$name: configure ($dir)"
    cmake -S . -B "$dir" "$@" || return 1
    log "$name: build"
    cmake --build "$dir" -j"$jobs" || return 1
    log "$name: test"
    (cd "$dir" && ctest --output-on-failure -j"$jobs")
}

failed=()

if ! install_packages test.sh "${packages[@]}"; then
    echo "test.sh: FAILED: could not install the required packages"
    exit 1
fi

CC=gcc CXX=g++ run_stage gcc build -DBRDFFIT_WERROR=ON || failed+=(gcc)

UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} \
    CC=gcc CXX=g++ run_stage asan build-asan -DBRDFFIT_WERROR=ON -DBRDFFIT_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=Debug || failed+=(asan)

CC=clang CXX=clang++ run_stage clang build-clang -DBRDFFIT_WERROR=ON -DCMAKE_C_COMPILER=clang \
    || failed+=(clang)

echo
if [ ${#failed[@]} -eq 0 ]; then
    echo "test.sh: PASSED: gcc, asan+ubsan and clang builds are warning-free and all tests pass"
    exit 0
fi
echo "test.sh: FAILED stages: ${failed[*]} (of gcc, asan, clang)"
exit 1
