#!/usr/bin/env bash
# `pip install .` into a fresh virtual environment, offline (--no-build-isolation: Debian's
# setuptools; --system-site-packages: Debian's numpy and matplotlib), then, from another
# directory, `import hsbd` is the installed package (not the source or build tree), its
# __version__ is the CLI's and the installed metadata's, its extension needs no library of
# the build tree, a Simulation runs and `python -m hsbd.plot` draws a run of the CLI.
# Cheap: the compiled extension is reused (HSBD_BUILD_DIR points setup.py at this build
# tree, where the extension's target is already up to date; a cold build compiles the
# library, minutes), pip gets a copy of the files setup.py packs, and the environment is
# made without its own pip (ensurepip takes 5-20 s): Debian's pip installs into it with
# --python, as the environment's own pip would.
# Usage: test_pip_install.sh SOURCE_DIR BUILD_DIR path/to/hsbd
set -u
SRC=${1:?usage: test_pip_install.sh SOURCE_DIR BUILD_DIR HSBD}
BUILD=$(cd "${2:?}" && pwd)
HSBD=$(cd "$(dirname "${3:?}")" && pwd)/$(basename "$3")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail=0
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

mkdir "$T/src"
cp -r "$SRC/pyproject.toml" "$SRC/setup.py" "$SRC/README.md" "$SRC/CMakeLists.txt" "$SRC/python" "$T/src/"
rm -rf "$T/src/python/hsbd/__pycache__"
/usr/bin/python3 -m venv --system-site-packages --without-pip "$T/venv" ||
    { echo "FAIL: no venv (python3-venv)"; exit 1; }
if ! HSBD_BUILD_DIR=$BUILD /usr/bin/python3 -m pip --python "$T/venv/bin/python" install \
    --no-build-isolation --no-deps --no-index \
    --quiet "$T/src" >"$T/pip.log" 2>&1; then
    cat "$T/pip.log"
    echo "FAIL: pip install"
    exit 1
fi
rm -rf "$T/src"
"$HSBD" run --defaults --quiet --set system.N=20 --set run.t_equil=0.1 --set run.t_total=1 --out "$T/run" ||
    bad "hsbd run"
cd "$T" || exit 1
out=$(HSBD_CLI=$HSBD "$T/venv/bin/python" - <<'PY' 2>&1
import importlib.metadata, os, subprocess, sys
import hsbd
site = os.path.join(sys.prefix, "lib")
assert hsbd.__file__.startswith(site), f"hsbd from {hsbd.__file__}, not the venv"
cli = subprocess.run([os.environ["HSBD_CLI"], "--version"], capture_output=True, text=True).stdout
meta = importlib.metadata.version("hsbd")
assert hsbd.__version__ == meta and f"hsbd {meta} " in cli, (hsbd.__version__, meta, cli)
s = hsbd.Simulation(system={"N": 10}, run={"t_equil": 0.1, "t_total": 0.5})
s.run()
assert s.stage == "done" and s.density()[1].mean() > 0
print(f"installed {hsbd.__version__} in {os.path.dirname(hsbd.__file__)}")
PY
) && echo "  $out" || bad "the installed package: $out"
ext=$(ls "$T"/venv/lib/python3*/site-packages/hsbd/_hsbd*.so 2>/dev/null | head -1)
[ -n "$ext" ] || bad "no extension installed"
[ -n "$ext" ] && ldd "$ext" | grep -q "$BUILD" && bad "the extension links into the build tree"
"$T/venv/bin/python" -m hsbd.plot "$T/run" >/dev/null 2>"$T/plot.err" && [ -s "$T/run/plot.png" ] ||
    bad "python -m hsbd.plot: $(cat "$T/plot.err")"
echo "test_pip_install: $fail failures"
[ $fail -eq 0 ]
