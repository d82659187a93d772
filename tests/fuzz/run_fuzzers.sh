#!/usr/bin/env bash
# Run every libFuzzer harness of a -DBRDFFIT_FUZZ=ON build for a fixed time.
#
#   bash tests/fuzz/run_fuzzers.sh BUILD_DIR [SECONDS]
#
# SECONDS per harness defaults to $BRDFFIT_FUZZ_SECONDS, else 60. Each
# harness starts from a scratch copy of its stored corpus
# (tests/fuzz/corpus/<name>), so the tree is never modified. A harness
# fails when libFuzzer reports a crash, a leak, undefined behaviour, a
# timeout or running out of memory; its inputs are then kept in
# BUILD_DIR/fuzz-findings/<name>/ and printed in hex. Once fixed, a
# finding is minimised (fuzz_<name> -minimize_crash=1 -runs=10000 FILE)
# and added to tests/fuzz/corpus/<name>/, where the ordinary ctest case
# fuzz_<name>_corpus runs it from then on.
#
# Prints one line per harness with its executions; exits non-zero if any
# harness failed.
set -uo pipefail

if [ $# -lt 1 ]; then
    echo "usage: $0 BUILD_DIR [SECONDS]" >&2
    exit 2
fi
build=$(cd "$1" && pwd) || exit 2
seconds=${2:-${BRDFFIT_FUZZ_SECONDS:-60}}
src=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
harnesses=(csv merl astm rgl fit eval)

work=$(mktemp -d "${TMPDIR:-/tmp}/brdffit-fuzz-XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT

# Undefined behaviour aborts (the build also compiles it as non-recoverable).
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}

failed=()
summary=()
for h in "${harnesses[@]}"; do
    bin=$build/tests/fuzz/fuzz_$h
    if [ ! -x "$bin" ]; then
        echo "fuzz_$h: not built in $build (configure with CC=clang -DBRDFFIT_FUZZ=ON)"
        failed+=("$h")
        continue
    fi
    # A harness with an open entry in known_defects.txt would only find that
    # defect again: it is not fuzzed until the entry is gone (its stored
    # inputs still run as ctest cases).
    if grep -q "^$h/" "$src/known_defects.txt"; then
        echo "fuzz_$h: NOT FUZZED: open known defect, see tests/fuzz/known_defects.txt"
        summary+=("fuzz_$h: not fuzzed (open known defect)")
        continue
    fi
    mkdir -p "$work/$h/corpus" "$work/$h/artifacts"
    cp "$src/corpus/$h/"* "$work/$h/corpus/"
    # inputs of defects not fixed yet would stop the run at once
    sed -n "s|^$h/\([^ ]*\).*|\1|p" "$src/known_defects.txt" | while read -r known; do
        rm -f "$work/$h/corpus/$known"
    done
    echo "fuzz_$h: fuzzing for $seconds s from $(ls "$work/$h/corpus" | wc -l) stored inputs"
    start=$SECONDS
    "$bin" -max_total_time="$seconds" -print_final_stats=1 -timeout=60 -rss_limit_mb=4096 \
        -artifact_prefix="$work/$h/artifacts/" "$work/$h/corpus" > "$work/$h/log" 2>&1
    rc=$?
    took=$((SECONDS - start))
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/$h/log" | tail -n 1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$work/$h/log" | tail -n 1)
    corpus=$(ls "$work/$h/corpus" | wc -l)
    line="fuzz_$h: ${execs:-?} executions in $took s (${rate:-?}/s), corpus $corpus inputs"
    findings=$(ls "$work/$h/artifacts" | wc -l)
    if [ "$rc" -ne 0 ] || [ "$findings" -ne 0 ] || [ -z "$execs" ]; then
        line="$line: FAILED (exit $rc, $findings findings)"
        failed+=("$h")
        echo "---- last lines of the fuzz_$h log"
        tail -n 60 "$work/$h/log"
        if [ "$findings" -ne 0 ]; then
            mkdir -p "$build/fuzz-findings/$h"
            cp "$work/$h/artifacts/"* "$build/fuzz-findings/$h/"
            for f in "$work/$h/artifacts/"*; do
                echo "---- finding $(basename "$f") (kept in $build/fuzz-findings/$h/):"
                od -An -tx1 -v "$f" | head -n 64
            done
        fi
    fi
    echo "$line"
    summary+=("$line")
done

echo
printf '%s\n' "${summary[@]}"
if [ ${#failed[@]} -ne 0 ]; then
    echo "fuzzing: FAILED: ${failed[*]}"
    exit 1
fi
echo "fuzzing: no crash, leak or undefined behaviour in ${harnesses[*]}"
