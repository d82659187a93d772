#!/bin/sh
# Build and run programs against an installed libbrdffit, as users would.
#
# usage: run_consumer.sh install|pkgconfig|pkgconfig-static|cmake|cmake-version
#
# Settings come from the environment (tests/consumer/CMakeLists.txt sets them):
#   BRDFFIT_BUILD_DIR  the build tree to install from
#   BRDFFIT_PREFIX     the install prefix (under the build tree)
#   BRDFFIT_LIBDIR     CMAKE_INSTALL_LIBDIR (relative to the prefix)
#   BRDFFIT_CMAKE      the cmake executable
#   BRDFFIT_CC         the C compiler
#   BRDFFIT_FLAGS      extra compile and link flags (the sanitizer flags)
#   BRDFFIT_VERSION    the expected version string
#   BRDFFIT_SHARED, BRDFFIT_STATIC   1 when that library is built
#   BRDFFIT_PKG_CONFIG the pkg-config executable (empty: skip those cases)
#   BRDFFIT_OBJDUMP    objdump, to check how a program is linked (optional)
# Exit status 77 means "skipped".
set -u

mode=$1
here=$(cd "$(dirname "$0")" && pwd)
work=$PWD/$mode
prefix=$BRDFFIT_PREFIX
libdir=$prefix/$BRDFFIT_LIBDIR
cflags_common="-std=c11 -Wall -Wextra -Wpedantic -Werror"

fail()
{
    echo "consumer $mode: FAILED: $*"
    exit 1
}

# Run a consumer program and check that it reports the expected version.
run_program()
{
    out=$("$@" 2>&1) || fail "$1 exited with status $?: $out"
    echo "$out"
    case "$out" in
    "libbrdffit $BRDFFIT_VERSION (headers $BRDFFIT_VERSION)"*) ;;
    *) fail "$1 did not report version $BRDFFIT_VERSION" ;;
    esac
}

# Fail if a program needs libbrdffit.so at run time.
check_static()
{
    [ -n "${BRDFFIT_OBJDUMP:-}" ] || return 0
    if "$BRDFFIT_OBJDUMP" -p "$1" | grep -q 'NEEDED.*libbrdffit'; then
        fail "$1 was linked against the shared library"
    fi
    echo "$1: libbrdffit linked statically"
}

need_pkg_config()
{
    if [ -z "${BRDFFIT_PKG_CONFIG:-}" ]; then
        echo "consumer $mode: SKIPPED: pkg-config not found"
        exit 77
    fi
    PKG_CONFIG_PATH=$libdir/pkgconfig
    PKG_CONFIG_LIBDIR=$libdir/pkgconfig
    export PKG_CONFIG_PATH PKG_CONFIG_LIBDIR
    version=$("$BRDFFIT_PKG_CONFIG" --modversion brdffit) || fail "pkg-config cannot find brdffit.pc"
    [ "$version" = "$BRDFFIT_VERSION" ] || fail "pkg-config reports version $version"
}

rm -rf "$work"
mkdir -p "$work" || exit 1
cd "$work" || exit 1

case $mode in
install)
    rm -rf "$prefix"
    "$BRDFFIT_CMAKE" --install "$BRDFFIT_BUILD_DIR" --prefix "$prefix" || fail "cmake --install"
    for f in include/brdffit/brdffit.h include/brdffit/version.h \
             "$BRDFFIT_LIBDIR/pkgconfig/brdffit.pc" \
             "$BRDFFIT_LIBDIR/cmake/brdffit/brdffitConfig.cmake" \
             "$BRDFFIT_LIBDIR/cmake/brdffit/brdffitConfigVersion.cmake"; do
        [ -f "$prefix/$f" ] || fail "$f was not installed"
    done
    if [ "$BRDFFIT_SHARED" = 1 ]; then
        [ -f "$libdir/libbrdffit.so" ] || fail "libbrdffit.so was not installed"
    fi
    if [ "$BRDFFIT_STATIC" = 1 ]; then
        [ -f "$libdir/libbrdffit.a" ] || fail "libbrdffit.a was not installed"
    fi
    echo "installed into $prefix"
    ;;
pkgconfig)
    [ "$BRDFFIT_SHARED" = 1 ] || { echo "consumer $mode: SKIPPED: no shared library"; exit 77; }
    need_pkg_config
    flags=$("$BRDFFIT_PKG_CONFIG" --cflags --libs brdffit) || fail "pkg-config --cflags --libs"
    pc_libdir=$("$BRDFFIT_PKG_CONFIG" --variable=libdir brdffit)
    echo "pkg-config --cflags --libs brdffit: $flags"
    # shellcheck disable=SC2086
    "$BRDFFIT_CC" $cflags_common ${BRDFFIT_FLAGS:-} -o consumer "$here/consumer.c" $flags \
        "-Wl,-rpath,$pc_libdir" || fail "compiling with pkg-config flags"
    run_program ./consumer
    ;;
pkgconfig-static)
    [ "$BRDFFIT_STATIC" = 1 ] || { echo "consumer $mode: SKIPPED: no static library"; exit 77; }
    need_pkg_config
    cflags=$("$BRDFFIT_PKG_CONFIG" --static --cflags brdffit) || fail "pkg-config --static --cflags"
    libs=$("$BRDFFIT_PKG_CONFIG" --static --libs brdffit) || fail "pkg-config --static --libs"
    echo "pkg-config --static --cflags --libs brdffit: $cflags $libs"
    case " $libs " in
    *" -lm "*) ;;
    *) fail "pkg-config --static --libs lacks -lm" ;;
    esac
    # Pick the archive even where the shared library sits next to it.
    libs=$(echo "$libs" | sed 's/-lbrdffit/-Wl,-Bstatic -lbrdffit -Wl,-Bdynamic/')
    # shellcheck disable=SC2086
    "$BRDFFIT_CC" $cflags_common ${BRDFFIT_FLAGS:-} -o consumer_static "$here/consumer.c" \
        $cflags $libs || fail "compiling with pkg-config --static flags"
    check_static ./consumer_static
    run_program ./consumer_static
    ;;
cmake)
    # shellcheck disable=SC2086
    "$BRDFFIT_CMAKE" -S "$here/cmake_project" -B build \
        "-DCMAKE_C_COMPILER=$BRDFFIT_CC" "-DCMAKE_PREFIX_PATH=$prefix" \
        "-DBRDFFIT_EXPECTED_DIR=$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
        "-DCMAKE_C_FLAGS=${BRDFFIT_FLAGS:-}" "-DCMAKE_EXE_LINKER_FLAGS=${BRDFFIT_FLAGS:-}" \
        -DCMAKE_BUILD_TYPE=Release || fail "configuring the consumer project"
    "$BRDFFIT_CMAKE" --build build || fail "building the consumer project"
    if [ "$BRDFFIT_SHARED" = 1 ]; then
        run_program ./build/consumer
    fi
    if [ "$BRDFFIT_STATIC" = 1 ]; then
        [ -x build/consumer_static ] || fail "brdffit::brdffit_static is not in the package"
        check_static ./build/consumer_static
        run_program ./build/consumer_static
        case "$out" in
        *"BRDFFIT_STATIC defined"*) ;;
        *) fail "brdffit::brdffit_static does not define BRDFFIT_STATIC for its users" ;;
        esac
    fi
    ;;
cmake-version)
    # The package promises SameMajorVersion: a request for 1.0 must fail.
    major=${BRDFFIT_VERSION%%.*}
    next=$((major + 1)).0
    if "$BRDFFIT_CMAKE" -S "$here/cmake_project" -B build \
        "-DCMAKE_C_COMPILER=$BRDFFIT_CC" "-DCMAKE_PREFIX_PATH=$prefix" \
        -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "-DBRDFFIT_REQUEST=$next" > configure.log 2>&1; then
        cat configure.log
        fail "find_package(brdffit $next) succeeded against version $BRDFFIT_VERSION"
    fi
    grep -q "compatible with requested version \"$next\"" configure.log ||
        { cat configure.log; fail "find_package(brdffit $next) failed for another reason"; }
    echo "find_package(brdffit $next) fails against $BRDFFIT_VERSION, as it should:"
    grep -E 'compatible with requested|, version: ' configure.log
    ;;
*)
    fail "unknown mode"
    ;;
esac
echo "consumer $mode: passed"
