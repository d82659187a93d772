#!/usr/bin/env bash
# Build the benchmarks and run them (docs/benchmarks.md).
#
#   bash scripts/bench.sh [program options]
#
# 1. installs cmake, gcc, g++, GSL, cminpack and Ceres with apt-get when
#    missing (the peers of bench_peers and bench_certified);
# 2. configures a Release build in build-bench/ with -DBRDFFIT_BUILD_BENCH=ON
#    (static library only; no tests, tools or examples) and builds it;
# 3. runs bench_core, bench_fit, bench_peers, bench_certified, bench_scale and
#    bench_many; the tables go
#    to stdout and to build-bench/bench.txt, one JSON object per measurement
#    to build-bench/bench.jsonl (both files are rewritten).
# Options are handed to every program, e.g. --repeats=3 for a quick look.
# The exit status is non-zero when the build or a program's own checks fail;
# a missed performance target is reported, not treated as a failure.
set -uo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
. scripts/common.sh

packages=(
    cmake
    make
    gcc
    g++
    libc6-dev
    libgsl-dev
    libcminpack-dev
    libceres-dev
)
build=build-bench
programs=(bench_core bench_fit bench_peers bench_certified bench_scale bench_many)
jobs=2

if ! install_packages bench.sh "${packages[@]}"; then
    echo "bench.sh: FAILED: could not install the required packages"
    exit 1
fi

log "configure ($build, Release)"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DBRDFFIT_BUILD_BENCH=ON \
    -DBRDFFIT_BUILD_SHARED=OFF -DBRDFFIT_BUILD_STATIC=ON -DBRDFFIT_BUILD_TESTS=OFF \
    -DBRDFFIT_BUILD_TOOLS=OFF -DBRDFFIT_BUILD_EXAMPLES=OFF || exit 1
log "build"
cmake --build "$build" -j"$jobs" --target "${programs[@]}" || exit 1

load=$(cut -d' ' -f1 /proc/loadavg 2> /dev/null || echo '?')
log "run (load average $load; other work on the machine skews the figures)"
: > "$build/bench.jsonl"
: > "$build/bench.txt"
failed=()
start=$(date +%s)
for p in "${programs[@]}"; do
    echo
    "$build/bench/$p" --json="$build/bench.jsonl" "$@" | tee -a "$build/bench.txt"
    [ "${PIPESTATUS[0]}" -eq 0 ] || failed+=("$p")
    echo >> "$build/bench.txt"
done

echo
echo "bench.sh: tables in $build/bench.txt, JSON lines in $build/bench.jsonl" \
    "($(wc -l < "$build/bench.jsonl") records, $(($(date +%s) - start)) s)"
if [ ${#failed[@]} -ne 0 ]; then
    echo "bench.sh: FAILED checks in: ${failed[*]}"
    exit 1
fi
echo "bench.sh: done; see the 'target:' lines above for the goals met and missed"
