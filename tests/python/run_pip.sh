#!/bin/sh
# python_pip_install: `pip install --no-index ./bindings/python` into a fresh
# virtual environment (with the system's numpy), i.e. with build isolation
# and no package index: the in-tree backend must need no download. Then check
# that nothing new appeared in bindings/python (no build/, no *.egg-info) and
# that the installed package imports (the library from BRDFFIT_LIBRARY).
#
# usage: run_pip.sh PYTHON SOURCE_DIR LIBRARY
# Exit status 77 (skipped) when the interpreter has no venv or pip module.
set -u
python=$1 src=$2 library=$3

if ! "$python" -c "import venv, ensurepip" > /dev/null 2>&1; then
    echo "python_pip_install: SKIPPED: $python has no venv/ensurepip (Debian: python3-venv)"
    exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/brdffit-pip.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
before=$(cd "$src" && find . -path ./build_backend/__pycache__ -prune -o -print | sort)
"$python" -m venv --system-site-packages "$work/venv" || exit 1
# The backend's own module may be compiled to build_backend/__pycache__, as
# any imported module is; that is ignored by git and not counted here.
"$work/venv/bin/python" -m pip install --no-index --no-cache-dir --quiet "$src" ||
    { echo "python_pip_install: pip install failed"; exit 1; }
after=$(cd "$src" && find . -path ./build_backend/__pycache__ -prune -o -print | sort)
if [ "$before" != "$after" ]; then
    echo "python_pip_install: pip left files in $src:"
    echo "$after" | grep -vxF "$before"
    exit 1
fi
cd "$work" || exit 1
BRDFFIT_LIBRARY=$library "$work/venv/bin/python" -c '
import os, sys, brdffit
assert os.path.realpath(brdffit.__file__).startswith(os.path.realpath(sys.prefix)), brdffit.__file__
print("pip installed", os.path.dirname(brdffit.__file__), "library", brdffit.library_version())'
