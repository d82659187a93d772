#!/bin/sh
# python_install: install the build into a fresh temporary prefix with
# `cmake --install`, then import the installed binding with a clean
# environment (no BRDFFIT_LIBRARY, no LD_LIBRARY_PATH, PYTHONPATH only the
# installed package directory), from a directory outside the source tree, and
# run install_check.py there.
#
# usage: run_install.sh CMAKE BUILD_DIR PYTHON PYTHON_INSTALL_DIR CHECK_SCRIPT
# LD_PRELOAD and ASAN_OPTIONS pass through (the sanitized build needs them).
set -u
cmake=$1 build=$2 python=$3 pydir=$4 check=$5

prefix=$(mktemp -d "${TMPDIR:-/tmp}/brdffit-install.XXXXXX") || exit 1
trap 'rm -rf "$prefix"' EXIT
"$cmake" --install "$build" --prefix "$prefix" > "$prefix.log" 2>&1 ||
    { cat "$prefix.log"; rm -f "$prefix.log"; echo "python_install: cmake --install failed"; exit 1; }
rm -f "$prefix.log"
case $pydir in
/*) ;;
*) pydir=$prefix/$pydir ;;
esac
[ -f "$pydir/brdffit/_install.py" ] || { echo "python_install: $pydir/brdffit/_install.py missing"; exit 1; }
cp "$check" "$prefix/check.py" || exit 1
cd "$prefix" || exit 1
env -i PATH=/usr/bin:/bin HOME="$prefix" PYTHONPATH="$pydir" PYTHONDONTWRITEBYTECODE=1 \
    ${LD_PRELOAD:+LD_PRELOAD="$LD_PRELOAD"} ${ASAN_OPTIONS:+ASAN_OPTIONS="$ASAN_OPTIONS"} \
    "$python" check.py "$prefix"
