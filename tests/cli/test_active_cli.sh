#!/usr/bin/env bash
# Active particles through the command line: the outputs an [active] run writes and their
# exact properties.
#   - Ideal ABPs (hard_core = off) in a periodic box: summary.json's swim pressure is its
#     ideal value rho v0^2 / (d (d-1) mu D_r) exactly (no collisions: swim_speed_ratio 1,
#     pressure_collisional 0), D_r defaults to 3 D / sigma^2, orientation.tsv starts at 1
#     and decays, local_density.tsv integrates to 1.
#   - Orientations from init.positions: a frame written by hsbd (XYZ and GSD) and read back
#     gives the same orientations (straight swimmers that do not turn: D_r = 0, v0 = 0).
#   - A passive run writes no orientation.tsv and no orientation columns.
#   - The two examples run (shortened) and tools/plot_active.py plots them (with the
#     build's Python package as the second argument), and a GSD run;
#     it refuses a passive run.
set -u
HSBD=${1:?usage: test_active_cli.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
SRC=$(cd "$(dirname "$0")/../.." && pwd)
# the package of this build for tools/plot_active.py (none in a sanitized build: the
# examples then run without their plots)
PACKAGE=${2:-}
export PYTHONPATH="$PACKAGE"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
num() { grep "\"$1\":" "$2/summary.json" | head -1 | sed 's/.*: *//; s/,$//'; }

cat >abp.ini <<'INI'
[system]
model = spheres
dimension = 2
N = 300
box = 40
sigma = 1
D = 1
seed = 4
hard_core = off
[active]
v0 = 6
[run]
dt = 1e-3
t_equil = 0.1
t_total = 2
[sample]
local_density_every = 50
blocks = 10
INI
"$HSBD" run abp.ini --quiet --out ideal 2>err || bad "ideal run: $(cat err)"
# rho v0^2 / (2 mu D_r) with D_r = 3 D / sigma^2 = 3: 300 / 1600 * 36 / 6 = 1.125
if awk -v p="$(num pressure_swim_ideal ideal)" -v s="$(num pressure_swim ideal)" \
    -v c="$(num pressure_collisional ideal)" -v r="$(num swim_speed_ratio ideal)" \
    'BEGIN { exit !(p == 1.125 && s == 1.125 && c == 0 && r == 1) }'; then ok
else bad "ideal ABPs: pressure_swim_ideal $(num pressure_swim_ideal ideal), pressure_swim $(num pressure_swim ideal), collisional $(num pressure_collisional ideal), swim_speed_ratio $(num swim_speed_ratio ideal)"; fi
if grep -q '"active": {"v0": \[6\], "rotational_D": \[3\], "Pe": \[6\], "persistence_length": \[2\]}' ideal/summary.json
then ok; else bad "active parameters: $(grep '"active": {"v0"' ideal/summary.json)"; fi
# C(t): 1 - O(dt) at the first lag, decaying as exp(-t D_r) within 5 error bars
if awk '!/^#/ && $1 != "t" { n++; if ($1 == 0.01) first = $2
        if ($3 > 0 && ($2 - exp(-3 * $1)) ^ 2 > 25 * $3 * $3) bad = 1 }
        END { exit bad || n < 10 || !(first > 0.96 && first < 0.98) }' ideal/orientation.tsv
then ok; else bad "orientation.tsv: $(grep -v '^#' ideal/orientation.tsv | head -12 | tr '\n' ' ')"; fi
if awk '!/^#/ && $1 != "phi" { if (NR > 1 && prev != "") w = $1 - prev; prev = $1; s += $2 }
        END { exit !(s * w > 0.999999 && s * w < 1.000001) }' ideal/local_density.tsv
then ok; else bad "local_density.tsv does not integrate to 1"; fi

# orientations read back from init.positions (turning off: D_r = 0, no propulsion)
"$HSBD" run abp.ini --quiet --out first --set output.trajectory=xyz --set output.trajectory_every=0.5 2>err ||
    bad "trajectory run: $(cat err)"
tail -n 302 first/trajectory.xyz >last.xyz
"$HSBD" run abp.ini --quiet --out again --set init.positions=last.xyz --set active.v0=0 \
    --set active.rotational_D=0 --set run.t_equil=0 --set run.t_total=0.05 --set sample.blocks=2 \
    --set output.trajectory=xyz --set output.trajectory_every=0.05 2>err || bad "read back: $(cat err)"
if paste <(tail -n 300 last.xyz) <(tail -n 300 again/trajectory.xyz) |
    awk '{ for (k = 10; k <= 16; ++k) if ((($k) - ($(k + 16))) ^ 2 > 1e-18) bad = 1 } END { exit bad || NR != 300 }'
then ok; else bad "orientations read from init.positions differ from the file's (beyond its 10 digits)"; fi
# the same from a GSD frame (float32 quaternions: equal within their rounding)
"$HSBD" run abp.ini --quiet --out gfirst --set output.trajectory=gsd --set output.trajectory_every=0.5 \
    --set run.t_total=1 --set sample.blocks=2 2>err || bad "GSD trajectory run: $(cat err)"
"$HSBD" run abp.ini --quiet --out gagain --set init.positions=gfirst/trajectory.gsd --set active.v0=0 \
    --set active.rotational_D=0 --set run.t_equil=0 --set run.t_total=0.05 --set sample.blocks=2 \
    --set output.trajectory=gsd --set output.trajectory_every=0.05 2>err || bad "GSD read back: $(cat err)"
if /usr/bin/python3 -c "
import sys, gsd.hoomd, numpy as np
a = gsd.hoomd.open('gfirst/trajectory.gsd', 'rb')[-1].particles.orientation
b = gsd.hoomd.open('gagain/trajectory.gsd', 'rb')[-1].particles.orientation
sys.exit(not (a is not None and b is not None and np.max(np.abs(a - b)) < 1e-6))"; then ok
else bad "orientations read from a GSD init.positions differ from the file's"; fi
# a file without orientations: random ones, the run goes on
grep -o '^S [^ ]* [^ ]* [^ ]*' last.xyz >plain.body
{ echo 300; echo 'Lattice="40 0 0 0 40 0 0 0 1"'; cat plain.body; } >plain.xyz
if "$HSBD" run abp.ini --quiet --out plain --set init.positions=plain.xyz --set run.t_total=0.05 \
    --set sample.blocks=2 2>err; then ok; else bad "positions without orientations: $(cat err)"; fi

# passive runs: nothing of the above
"$HSBD" run abp.ini --quiet --out passive --set active.v0= --set output.trajectory=xyz 2>err ||
    bad "passive run: $(cat err)"
if [ ! -e passive/orientation.tsv ] && ! grep -q orientation passive/trajectory.xyz &&
    ! grep -q pressure_swim passive/summary.json; then ok
else bad "a passive run writes orientations or the swim pressure"; fi

# the examples run (shortened) and tools/plot_active.py draws them
for ex in active-disks-mips active-spheres; do
    if "$HSBD" run "$SRC/examples/$ex.ini" --quiet --out "$ex" --set system.N=300 --set run.t_equil=0.01 \
        --set run.t_total=0.1 --set sample.blocks=4 --set sample.local_density_every=50 \
        --set sample.gr_every=50 --set output.trajectory_every=0.05 2>err &&
        { [ -z "$PACKAGE" ] || { /usr/bin/python3 "$SRC/tools/plot_active.py" "$ex" >out 2>err &&
            [ -s "$ex/plot.png" ] && grep -q "local density peaks at phi" out; }; }; then ok
    else bad "$ex: $(cat err out 2>/dev/null | head -3)"; fi
done
# GSD trajectories are read too; a passive run is refused
"$HSBD" run abp.ini --quiet --out gsdrun --set output.trajectory=gsd --set run.t_total=0.2 --set sample.blocks=2 2>err
if [ -n "$PACKAGE" ]; then
    if /usr/bin/python3 "$SRC/tools/plot_active.py" gsdrun >out 2>err && [ -s gsdrun/plot.png ]; then ok
    else bad "plot of a GSD run: $(cat err)"; fi
    if ! /usr/bin/python3 "$SRC/tools/plot_active.py" passive 2>err && grep -q "not a run of active" err; then ok
    else bad "plot_active accepted a passive run"; fi
fi

echo "test_active_cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
