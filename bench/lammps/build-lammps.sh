#!/bin/sh
# Build LAMMPS with fix brownian (package BROWNIAN) and pair mie/cut (EXTRA-PAIR) from
# Debian's own source package, at Debian's optimisation (-O2 and the hardening flags of
# dpkg-buildflags), into DIR (outside the repository). Debian's lammps binary lacks the
# BROWNIAN package, hence the rebuild; the same source keeps the comparison with the
# distribution's code. Serial build (no MPI, no OpenMP): the comparison runs one thread.
#
# Usage: bench/lammps/build-lammps.sh DIR [JOBS]
#   then DIR/build/lmp is the binary (bench/lammps/compare.py --lammps DIR/build/lmp).
# Needs: build-essential, cmake, dpkg-dev (all in scripts/install-deps but dpkg-dev, which
# build-essential pulls in) and a deb-src line for Debian's main archive, e.g. on bookworm
# a file /etc/apt/sources.list.d/debian-src.sources holding
#   Types: deb-src
#   URIs: http://deb.debian.org/debian
#   Suites: bookworm bookworm-updates
#   Components: main
#   Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
# followed by apt-get update. The build takes about an hour of CPU on one core; on a
# shared machine run it with nice (nice -n 10 bench/lammps/build-lammps.sh DIR 2).
set -eu
DIR=${1:?usage: build-lammps.sh DIR [JOBS]}
JOBS=${2:-2}
mkdir -p "$DIR"
DIR=$(cd "$DIR" && pwd)
case "$DIR" in
"$(cd "$(dirname "$0")/../.." && pwd)"*)
    echo "build-lammps.sh: $DIR is inside the repository; pick a directory outside it" >&2
    exit 2
    ;;
esac
for tool in apt-get dpkg-source dpkg-buildflags cmake g++; do
    command -v "$tool" >/dev/null 2>&1 || {
        echo "build-lammps.sh: $tool is missing (apt-get install build-essential cmake dpkg-dev)" >&2
        exit 1
    }
done
cd "$DIR"
src=$(find . -maxdepth 1 -type d -name 'lammps-*' | head -n 1)
if [ -z "$src" ]; then
    if ! apt-get source --download-only lammps >/dev/null 2>apt.err; then
        echo "build-lammps.sh: apt-get source lammps failed (no deb-src line? see this" \
            "script's header):" >&2
        cat apt.err >&2
        exit 1
    fi
    dpkg-source -x lammps_*.dsc >/dev/null
    src=$(find . -maxdepth 1 -type d -name 'lammps-*' | head -n 1)
fi
echo "build-lammps.sh: source $src ($(cd "$src" && dpkg-parsechangelog -S Version 2>/dev/null || echo ?))"
# Debian's flags, as its debhelper build passes them (CMAKE_BUILD_TYPE None: no -O3 of
# CMake's Release on top)
CFLAGS=$(dpkg-buildflags --get CFLAGS)
CXXFLAGS=$(dpkg-buildflags --get CXXFLAGS)
CPPFLAGS=$(dpkg-buildflags --get CPPFLAGS)
LDFLAGS=$(dpkg-buildflags --get LDFLAGS)
cmake -S "$src/cmake" -B build -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_C_FLAGS="$CFLAGS $CPPFLAGS" -DCMAKE_CXX_FLAGS="$CXXFLAGS $CPPFLAGS" \
    -DCMAKE_EXE_LINKER_FLAGS="$LDFLAGS" -DCMAKE_SHARED_LINKER_FLAGS="$LDFLAGS" \
    -DBUILD_MPI=OFF -DBUILD_OMP=OFF -DBUILD_SHARED_LIBS=OFF \
    -DPKG_BROWNIAN=ON -DPKG_EXTRA-PAIR=ON >cmake.log
cmake --build build -j "$JOBS" >build.log
"$DIR/build/lmp" -h | grep -q "brownian" || {
    echo "build-lammps.sh: the binary has no fix brownian (see $DIR/build.log)" >&2
    exit 1
}
echo "build-lammps.sh: $DIR/build/lmp"
