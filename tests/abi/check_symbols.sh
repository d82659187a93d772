#!/bin/sh
# Compare the dynamic symbols a shared library exports with a checked-in list.
#
# usage: check_symbols.sh NM SHARED_LIB LIST [STATIC_LIB]
#
# Fails when the library exports a name outside brdffit_*, when an internal
# bf_* function of the static library leaks into the shared one, or when the
# exported names differ from LIST (the difference is printed). With
# BRDFFIT_ABI_UPDATE=1 in the environment, LIST is rewritten instead.
set -u

nm_tool=${1:-}
shared=$2
list=$3
static=${4:-}
[ -n "$nm_tool" ] || nm_tool="nm"

if [ ! -f "$shared" ]; then
    echo "abi_symbols: $shared does not exist (build the library first)"
    exit 1
fi

# Defined dynamic symbols, without version suffixes (name@@BRDFFIT_0) and
# without the version node itself (type A).
exported=$(LC_ALL=C "$nm_tool" -D --defined-only "$shared" |
    awk 'NF >= 2 && $(NF-1) != "A" { sub(/@.*/, "", $NF); print $NF }' | LC_ALL=C sort -u) || {
    echo "abi_symbols: '$nm_tool -D --defined-only $shared' failed"
    exit 1
}

if [ -z "$exported" ]; then
    echo "abi_symbols: $shared exports nothing; the version script or the export macro is broken"
    exit 1
fi

status=0

foreign=$(printf '%s\n' "$exported" | grep -v '^brdffit_' || true)
if [ -n "$foreign" ]; then
    echo "abi_symbols: exported names outside the brdffit_ prefix (check lib/brdffit.map):"
    printf '%s\n' "$foreign" | sed 's/^/    /'
    status=1
fi

# The internal helpers exist (in the static library) but must stay hidden.
if [ -n "$static" ] && [ -f "$static" ]; then
    internal=$(LC_ALL=C "$nm_tool" --defined-only "$static" 2>/dev/null |
        awk 'NF >= 2 && $(NF-1) ~ /^[TDBR]$/ && $NF ~ /^bf_/ { print $NF }' | LC_ALL=C sort -u)
    count=$(printf '%s\n' "$internal" | grep -c '^bf_' || true)
    leaked=$(printf '%s\n%s\n' "$internal" "$exported" | grep '^bf_' | LC_ALL=C sort | uniq -d)
    if [ "$count" -eq 0 ]; then
        echo "abi_symbols: no bf_* functions found in $static; the hidden-symbol check proves nothing"
        status=1
    elif [ -n "$leaked" ]; then
        echo "abi_symbols: internal functions exported by the shared library:"
        printf '%s\n' "$leaked" | sed 's/^/    /'
        status=1
    else
        echo "abi_symbols: $count internal bf_* functions in the static library, none exported"
    fi
fi

if [ "${BRDFFIT_ABI_UPDATE:-0}" = 1 ]; then
    if [ "$status" -ne 0 ]; then
        echo "abi_symbols: not updating $list while the export rules are broken"
        exit 1
    fi
    printf '%s\n' "$exported" > "$list"
    echo "abi_symbols: wrote $(printf '%s\n' "$exported" | wc -l | tr -d ' ') names to $list"
    exit 0
fi

if [ ! -f "$list" ]; then
    echo "abi_symbols: $list is missing (create it with scripts/update-abi.sh)"
    exit 1
fi

expected=$(LC_ALL=C sort -u "$list" | grep -v '^$')
if [ "$expected" != "$exported" ]; then
    echo "abi_symbols: exported symbols differ from $list"
    echo "(+ exported but not listed, - listed but not exported):"
    tmp=${TMPDIR:-/tmp}/brdffit-symbols.$$
    printf '%s\n' "$expected" > "$tmp"
    printf '%s\n' "$exported" | LC_ALL=C comm -13 "$tmp" - | sed 's/^/+ /'
    printf '%s\n' "$exported" | LC_ALL=C comm -23 "$tmp" - | sed 's/^/- /'
    rm -f "$tmp"
    echo "A new public function is added on purpose with scripts/update-abi.sh;"
    echo "a removed or renamed one breaks the ABI."
    status=1
fi

if [ "$status" -eq 0 ]; then
    echo "abi_symbols: $(printf '%s\n' "$exported" | wc -l | tr -d ' ') exported symbols match $list"
fi
exit "$status"
