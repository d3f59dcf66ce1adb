#!/usr/bin/env bash
# The plotting tools read short runs of every kind and write their PNGs: rods (a ring
# with a cosine field and Percus, a mixture, walls with a tilt and a trap) and spheres (a
# 3D mixture with obstacles, polydisperse disks).
set -eu
HSBD=${1:?usage: test_plots.sh path/to/hsbd}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
short="--quiet --set run.t_equil=0.1"
# shellcheck disable=SC2086
{
"$HSBD" run "$SRC/examples/rods-cosine.ini" $short --set run.t_total=2 --out "$T/cosine"
"$HSBD" theory percus --sigma 0.5 --rho 0.5 --amplitude 6 --out "$T/cosine/percus.tsv"
"$HSBD" run "$SRC/examples/rods-mixture.ini" $short --set run.t_total=1 --out "$T/mix"
"$HSBD" run "$SRC/examples/rods-sediment.ini" $short --set run.t_total=2 --out "$T/walls"
"$HSBD" run "$SRC/examples/spheres-obstacles.ini" $short --set run.t_total=0.3 --set system.N=300 --set sample.gr_every=5 --out "$T/obst"
"$HSBD" run "$SRC/examples/disks.ini" $short --set run.t_total=0.3 --set system.N=300 \
    --set species.polydispersity=0.1 --set sample.gr_every=5 --out "$T/disks"
}
/usr/bin/python3 "$SRC/tools/plot_rods.py" "$T/cosine" --theory "$T/cosine/percus.tsv"
for d in mix walls; do /usr/bin/python3 "$SRC/tools/plot_rods.py" "$T/$d"; done
for d in obst disks; do /usr/bin/python3 "$SRC/tools/plot_spheres.py" "$T/$d"; done
for d in cosine mix walls obst disks; do [ -s "$T/$d/plot.png" ] || { echo "FAIL: no $d/plot.png"; exit 1; }; done
# a rods run is not a spheres run: refused with a message
if /usr/bin/python3 "$SRC/tools/plot_spheres.py" "$T/mix" 2>"$T/err"; then echo "FAIL: rods accepted"; exit 1; fi
grep -q "not spheres" "$T/err"
echo "test_plots: 5 plots written"
