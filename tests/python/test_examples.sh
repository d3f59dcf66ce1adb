#!/usr/bin/env bash
# The Python examples run and write their figures; the rods example runs to its end as
# its comment says (equilibration 1, production 20); the spheres example's contact value
# agrees with Carnahan-Starling within 4 of its error bars (it prints both).
set -eu
PY=${1:?usage: test_examples.sh build/python}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
export PYTHONPATH=$PY
rods=$(/usr/bin/python3 "$SRC/examples/python/percus.py" "$T/percus.png")
echo "$rods"
echo "$rods" | grep -q "^done at t = 21 (10000 + 200000 steps)" || { echo "FAIL: percus.py did not run to its end"; exit 1; }
out=$(/usr/bin/python3 "$SRC/examples/python/spheres_gr.py" "$T/gr.png")
echo "$out"
[ -s "$T/percus.png" ] && [ -s "$T/gr.png" ]
echo "$out" | awk '{ for (i = 1; i <= NF; ++i) { if ($i == "hsbd") { v = $(i+1); e = $(i+3) } if ($i == "Carnahan-Starling") cs = $(i+1) } }
    END { d = v - cs; if (d < 0) d = -d; if (d > 4 * e) { print "contact off by " d " > 4 x " e; exit 1 } }'
