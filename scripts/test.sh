#!/usr/bin/env bash
# Build libbrdffit and run every test, from a fresh Debian machine.
#
#   bash scripts/test.sh
#
# 1. installs the build and test tools with apt-get (skipped when they are
#    all installed already);
# 2. build/        gcc, warnings as errors, all tests;
# 3. build-asan/   gcc, Debug, AddressSanitizer + UndefinedBehaviorSanitizer,
#                  all tests in their quick form (BRDFFIT_TEST_QUICK=1: every
#                  case, fewer repetitions of the slowest sweeps; the gcc and
#                  clang stages run the full form), but the browser renderings (ctest label browser:
#                  the browser's work is not the library's, and the command's
#                  export writers they run are tested here by the other
#                  export cases);
# 4. build-clang/  clang, warnings as errors, all tests but the browser ones;
# 5. build-fuzz/   clang libFuzzer harnesses (tests/fuzz) with AddressSanitizer
#                  and UndefinedBehaviorSanitizer, each fuzzed for
#                  BRDFFIT_FUZZ_SECONDS (default 30) from a scratch copy of its
#                  stored corpus (tests/fuzz/run_fuzzers.sh);
# 6. build-valgrind/ gcc, every test program once more under valgrind
#                  memcheck (ctest label valgrind, tests/valgrind);
# 7. build-tsan/   gcc, ThreadSanitizer, the programs that use threads
#                  (ctest label tsan, tests/tsan).
# The gcc stage also builds bench/ and runs each benchmark once in smoke mode
# (nothing timed).
# Every stage runs even if an earlier one failed; the last line sums up, and
# the exit status is non-zero if anything failed. docs/hardening-tests.md
# describes stages 5 and 6.
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
    valgrind         # the memcheck stage
    libtsan2         # ThreadSanitizer runtime for gcc
    libgsl-dev       # reference solvers of the benchmarks (bench/)
    libcminpack-dev
    libcmocka-dev
    pkg-config
    abigail-tools    # abidw/abidiff for the ABI check
    doxygen
    libcairo2-dev    # the brdffit command draws and writes its PNG previews with cairo (tools/)
    fonts-dejavu-core # the font of the preview's text
    python3          # the Python binding's tests (tests/python)
    python3-numpy
    python3-cffi
    python3-venv     # python_pip_install: pip install into a venv, offline
    python3-pip
    python3-dask     # brdffit.dask and its cluster tests (tests/python)
    python3-distributed
    chromium         # headless browser of the three.js render test (tests/export)
)

jobs=2

# run_stage NAME BUILD_DIR [cmake options...]; the compiler comes from CC/CXX,
# ctest leaves out the label in SKIP_LABEL when it is set.
run_stage()
{
    local name=$1 dir=$2
    shift 2
    log "$name: configure ($dir)"
    cmake -S . -B "$dir" "$@" || return 1
    log "$name: build"
    cmake --build "$dir" -j"$jobs" || return 1
    log "$name: test"
    (cd "$dir" && ctest --output-on-failure -j"$jobs" ${SKIP_LABEL:+-LE "$SKIP_LABEL"})
}

# fuzz_stage: the libFuzzer harnesses, when clang can link them.
fuzz_stage()
{
    local probe
    probe=$(mktemp -d) || return 1
    printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n)\n{ (void)d; (void)n; return 0; }\n' \
        > "$probe/probe.c"
    if ! command -v clang > /dev/null ||
        ! clang -fsanitize=fuzzer,address,undefined "$probe/probe.c" -o "$probe/probe" 2> /dev/null; then
        rm -rf "$probe"
        echo "fuzz: SKIPPED: clang with the libFuzzer runtime (libclang-rt-14-dev) is not available"
        return 0
    fi
    rm -rf "$probe"
    log "fuzz: configure (build-fuzz)"
    CC=clang cmake -S . -B build-fuzz -DBRDFFIT_WERROR=ON -DCMAKE_C_COMPILER=clang \
        -DBRDFFIT_FUZZ=ON -DBRDFFIT_BUILD_TOOLS=OFF -DBRDFFIT_BUILD_EXAMPLES=OFF || return 1
    log "fuzz: build"
    cmake --build build-fuzz -j"$jobs" --target fuzz || return 1
    log "fuzz: run each harness for ${BRDFFIT_FUZZ_SECONDS:-30} s"
    bash tests/fuzz/run_fuzzers.sh build-fuzz "${BRDFFIT_FUZZ_SECONDS:-30}"
}

# tsan_stage: the threaded test programs under ThreadSanitizer.
tsan_stage()
{
    log "tsan: configure (build-tsan)"
    CC=gcc CXX=g++ cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRDFFIT_WERROR=ON \
        -DBRDFFIT_SANITIZE=OFF -DCMAKE_C_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
        -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=thread \
        || return 1
    log "tsan: build"
    cmake --build build-tsan -j"$jobs" --target tsan_tests || return 1
    log "tsan: test"
    (cd build-tsan && ctest -L tsan --output-on-failure -j"$jobs")
}

# valgrind_stage: every test program under memcheck.
valgrind_stage()
{
    if ! command -v valgrind > /dev/null; then
        echo "valgrind: SKIPPED: valgrind is not installed"
        return 0
    fi
    log "valgrind: configure (build-valgrind)"
    CC=gcc cmake -S . -B build-valgrind -DBRDFFIT_WERROR=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DBRDFFIT_VALGRIND=ON -DBRDFFIT_BUILD_TOOLS=OFF || return 1
    log "valgrind: build"
    cmake --build build-valgrind -j"$jobs" || return 1
    log "valgrind: every test program under memcheck"
    (cd build-valgrind && ctest -L valgrind --output-on-failure -j"$jobs")
}

failed=()
stages=(gcc asan clang fuzz valgrind tsan)

if ! install_packages test.sh "${packages[@]}"; then
    echo "test.sh: FAILED: could not install the required packages"
    exit 1
fi

# The export tests (tests/export) run the Khronos glTF Validator and
# MaterialX, which they install with npm; Debian's npm package brings node and npm. It is
# installed only when npm is missing: builds of nodejs from elsewhere ship
# their own npm and conflict with Debian's.
if ! command -v npm > /dev/null && ! install_packages test.sh npm; then
    echo "test.sh: npm could not be installed: the export validation tests will be skipped"
fi

stage_start=$SECONDS
CC=gcc CXX=g++ run_stage gcc build -DBRDFFIT_WERROR=ON -DBRDFFIT_BUILD_BENCH=ON || failed+=(gcc)
echo "gcc: stage took $((SECONDS - stage_start)) s"

# The sanitized Debug build runs the tests 10 to 30 times slower: their
# quick form keeps it inside the machine's time (an auto fit of every
# model under the default objective in test_fit alone took 25 minutes).
stage_start=$SECONDS
BRDFFIT_TEST_QUICK=1 UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} \
    SKIP_LABEL=browser CC=gcc CXX=g++ run_stage asan build-asan -DBRDFFIT_WERROR=ON -DBRDFFIT_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=Debug || failed+=(asan)
echo "asan: stage took $((SECONDS - stage_start)) s"

stage_start=$SECONDS
SKIP_LABEL=browser CC=clang CXX=clang++ run_stage clang build-clang -DBRDFFIT_WERROR=ON -DCMAKE_C_COMPILER=clang \
    || failed+=(clang)
echo "clang: stage took $((SECONDS - stage_start)) s"

stage_start=$SECONDS
fuzz_stage || failed+=(fuzz)
echo "fuzz: stage took $((SECONDS - stage_start)) s"

stage_start=$SECONDS
valgrind_stage || failed+=(valgrind)
echo "valgrind: stage took $((SECONDS - stage_start)) s"

stage_start=$SECONDS
tsan_stage || failed+=(tsan)
echo "tsan: stage took $((SECONDS - stage_start)) s"

echo
echo "stages: $((${#stages[@]} - ${#failed[@]})) passed, ${#failed[@]} failed"
if [ ${#failed[@]} -eq 0 ]; then
    echo "test.sh: PASSED: gcc, asan+ubsan and clang builds are warning-free and all tests pass;" \
        "fuzzing, valgrind memcheck and ThreadSanitizer found nothing"
    exit 0
fi
echo "test.sh: FAILED stages: ${failed[*]} (of ${stages[*]})"
exit 1
