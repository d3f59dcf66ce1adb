#!/usr/bin/env bash
# Every kind of run gets its figure (hsbd.plot, `python3 -m hsbd.plot`): short runs of
# rods (a ring with a cosine field and Percus, a mixture, walls with a tilt and a trap, a
# flashing ratchet's phases, a tilted ring's current) and of spheres (a slit between
# walls, a mixture sedimenting between walls in a field, a 3D mixture with immobile
# obstacles, polydisperse disks, active spheres) each give a PNG; the tools (tools/plot_rods.py,
# tools/plot_spheres.py) draw the same through the package and refuse a run of the other
# model. Usage: test_plots.sh path/to/hsbd path/to/build/python
set -eu
HSBD=${1:?usage: test_plots.sh path/to/hsbd path/to/build/python}
export PYTHONPATH=${2:?usage: test_plots.sh path/to/hsbd path/to/build/python}
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
"$HSBD" run "$SRC/examples/rods-flashing.ini" $short --set run.t_total=2 --out "$T/flashing"
"$HSBD" run "$SRC/examples/rods-tilt.ini" $short --set run.t_total=1 --out "$T/tilt"
"$HSBD" run "$SRC/examples/spheres-slit.ini" $short --set run.t_total=0.3 --set system.N=300 --out "$T/slit"
"$HSBD" run "$SRC/examples/spheres-sedimentation.ini" $short --set run.t_total=0.3 --set system.N=300 --out "$T/sediment"
"$HSBD" run "$SRC/examples/spheres-obstacles.ini" $short --set run.t_total=0.3 --set system.N=300 --set sample.gr_every=5 --out "$T/obst"
"$HSBD" run "$SRC/examples/disks.ini" $short --set run.t_total=0.3 --set system.N=300 \
    --set species.polydispersity=0.1 --set sample.gr_every=5 --out "$T/disks"
"$HSBD" run "$SRC/examples/active-spheres.ini" $short --set run.t_total=0.3 --set system.N=300 --out "$T/active"
}
/usr/bin/python3 "$SRC/tools/plot_rods.py" "$T/cosine" --theory "$T/cosine/percus.tsv" --out "$T/cosine/tool.png"
/usr/bin/python3 "$SRC/tools/plot_spheres.py" "$T/slit" --out "$T/slit/tool.png"
/usr/bin/python3 -m hsbd.plot "$T"/{cosine,mix,walls,flashing,tilt,slit,sediment,obst,disks,active}
for d in cosine mix walls flashing tilt slit sediment obst disks active; do
    [ -s "$T/$d/plot.png" ] || { echo "FAIL: no $d/plot.png"; exit 1; }
done
[ -s "$T/cosine/tool.png" ] && [ -s "$T/slit/tool.png" ] || { echo "FAIL: the tools drew nothing"; exit 1; }
# a rods run is not a spheres run: refused with a message
if /usr/bin/python3 "$SRC/tools/plot_spheres.py" "$T/mix" 2>"$T/err"; then echo "FAIL: rods accepted"; exit 1; fi
grep -q "not spheres" "$T/err"
# not a run directory: exit status 2 and a message
if /usr/bin/python3 -m hsbd.plot "$T/cosine/percus.tsv" 2>"$T/err"; then echo "FAIL: a file plotted"; exit 1; fi
grep -q "run directory" "$T/err"
echo "test_plots: 10 runs plotted, 2 by the tools"
