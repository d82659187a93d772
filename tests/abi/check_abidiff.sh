#!/bin/sh
# Compare the ABI of the built shared library with the committed baseline.
#
# usage: check_abidiff.sh ABIDW ABIDIFF SHARED_LIB BASELINE SUPPRESSIONS HEADER_DIR...
#
# abidw describes the library (only types declared in HEADER_DIRs count),
# abidiff compares that with BASELINE. Exit status of abidiff is a bit set:
# 1 error, 2 usage error, 4 ABI change, 8 incompatible ABI change.
#   - bit 8, or any removed or changed function or variable: FAIL;
#   - bit 4 with additions only: pass (scripts/update-abi.sh records them);
#   - abidw/abidiff not installed: skipped (exit 77).
# With BRDFFIT_ABI_UPDATE=1 in the environment, BASELINE is rewritten instead.
set -u

abidw=$1
abidiff=$2
shared=$3
baseline=$4
suppressions=$5
shift 5

case "$abidw$abidiff" in
*NOTFOUND*) abidw= ;;
esac
if [ -z "$abidw" ] || [ -z "$abidiff" ]; then
    echo "abi_abidiff: SKIPPED: abidw/abidiff not found (Debian: apt-get install abigail-tools)"
    exit 77
fi
if [ ! -f "$shared" ]; then
    echo "abi_abidiff: $shared does not exist (build the library first)"
    exit 1
fi

# Turn the header directories into "--headers-dir DIR" pairs.
count=$#
for dir in "$@"; do
    set -- "$@" --headers-dir "$dir"
done
shift "$count"

current=${PWD}/brdffit.current.abi
# Only exported functions and the public types they reach are described;
# paths and source locations are left out, so the baseline neither depends
# on where the tree was built nor changes when code merely moves.
if ! "$abidw" --exported-interfaces-only --drop-private-types --no-corpus-path \
        --no-comp-dir-path --no-show-locs --short-locs --type-id-style hash "$@" \
        --out-file "$current" "$shared"; then
    echo "abi_abidiff: abidw failed on $shared"
    exit 1
fi

if [ "${BRDFFIT_ABI_UPDATE:-0}" = 1 ]; then
    cp "$current" "$baseline" || exit 1
    echo "abi_abidiff: wrote $baseline"
    exit 0
fi
if [ ! -f "$baseline" ]; then
    echo "abi_abidiff: $baseline is missing (create it with scripts/update-abi.sh)"
    exit 1
fi

report=${PWD}/abidiff.report
"$abidiff" --no-default-suppression --suppressions "$suppressions" \
    "$baseline" "$current" > "$report" 2>&1
status=$?
cat "$report"

if [ $((status & 3)) -ne 0 ]; then
    echo "abi_abidiff: abidiff failed (exit status $status)"
    exit 1
fi
if [ $((status & 8)) -ne 0 ]; then
    echo "abi_abidiff: FAILED: incompatible ABI change against $baseline (exit status $status)"
    exit 1
fi
if [ $((status & 4)) -ne 0 ]; then
    # Only additions are compatible: a changed or removed function or
    # variable counts as a break even where abidiff does not call it one.
    broken=$(grep -E 'changes summary: ' "$report" |
        grep -E '(^|[^0-9])[1-9][0-9]* (Removed|Changed)' || true)
    if [ -n "$broken" ]; then
        echo "abi_abidiff: FAILED: existing interfaces changed or removed against $baseline"
        echo "(if the break is intended, bump the major version and run scripts/update-abi.sh)"
        exit 1
    fi
    echo "abi_abidiff: compatible additions only; record them with scripts/update-abi.sh"
    exit 0
fi
echo "abi_abidiff: ABI matches $baseline"
exit 0
