#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then a user's program (use_hsbd.c) compiled
# with the installed headers and linked with the installed libhsbd.so through the
# installed pkg-config file, and run. Also: the library exports exactly the functions the
# public headers mark HSBD_API (nothing internal, none missing).
# Usage: test_install.sh BUILD_DIR [extra compiler flags, e.g. sanitizers]
set -u
BUILD=${1:?usage: test_install.sh BUILD_DIR [CFLAGS...]}
shift
HERE=$(cd "$(dirname "$0")" && pwd)
SRC=$(cd "$HERE/../.." && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

cmake --install "$BUILD" --prefix "$T/prefix" >"$T/install.log" 2>&1 || { cat "$T/install.log"; exit 1; }
lib=$(ls "$T"/prefix/lib*/libhsbd.so 2>/dev/null | head -1)
[ -n "$lib" ] || { echo "FAIL: no libhsbd.so installed" >&2; exit 1; }
[ -x "$T/prefix/bin/hsbd" ] || bad "the CLI is not installed"
[ -f "$T/prefix/include/hsbd/hsbd.h" ] || bad "the headers are not installed"
pcdir=$(dirname "$lib")/pkgconfig
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs hsbd) || bad "pkg-config does not know hsbd"
# shellcheck disable=SC2086
cc -std=c17 -Wall -Wextra -Werror "$@" -o "$T/use_hsbd" "$HERE/use_hsbd.c" $flags \
    -Wl,-rpath,"$(dirname "$lib")" -lm || bad "use_hsbd.c does not build against the installed library"
if [ -x "$T/use_hsbd" ]; then
    ldd "$T/use_hsbd" | grep -q "$T/prefix" || bad "use_hsbd is not linked with the installed libhsbd.so"
    if "$T/use_hsbd" "$T/run" >"$T/out" 2>&1 && grep -q "^hsbd 0" "$T/out" &&
        [ -s "$T/run/density.tsv" ] && grep -q '"completed": true' "$T/run/summary.json"; then
        echo "  $(tr '\n' ' ' <"$T/out")"
    else
        bad "use_hsbd: $(cat "$T/out")"
    fi
fi
# exported symbols = the HSBD_API declarations of the installed headers
nm -D --defined-only "$lib" | awk '$2 == "T" { print $3 }' | sort >"$T/exported"
grep -ho 'HSBD_API[^(]*(' "$T"/prefix/include/hsbd/*.h | grep -o 'hsbd_[a-z0-9_]*($' | tr -d '(' |
    sort -u >"$T/declared"
if cmp -s "$T/exported" "$T/declared"; then
    echo "  libhsbd.so exports the $(wc -l <"$T/exported") public functions and nothing else"
else
    bad "exported vs declared: $(diff "$T/declared" "$T/exported" | head -10 | tr '\n' ' ')"
fi
nm -D --defined-only "$lib" | grep -q ' hsbd_put_u64$' && bad "an internal function is exported"
# every function the public headers declare is marked HSBD_API (else it is not exported)
unmarked=$(grep -nE '^[A-Za-z_][A-Za-z0-9_ *]*[ *]hsbd_[a-z0-9_]+\(' "$T"/prefix/include/hsbd/*.h |
    grep -v 'HSBD_API' | grep -v ':typedef')
[ -z "$unmarked" ] || bad "declared without HSBD_API: $unmarked"
echo "test_install: $fail failures"
[ $fail -eq 0 ]
