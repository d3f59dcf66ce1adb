#!/usr/bin/env bash
# Motility-induced phase separation of active Brownian hard disks (docs/validation.md
# section 21, docs/active.md): examples/active-disks-mips.ini (N 2000, phi 0.6, D_r =
# 3 D / sigma^2) at Pe = v0 sigma / D = 100 and at Pe = 10, each run to the end and
# plotted by tools/plot_active.py (OUT/pe100/plot.png, OUT/pe10/plot.png).
# Judged on the local packing fraction's distribution (local_density.tsv, cells of 5
# sigma), its peaks after smoothing over 0.02:
#   Pe 100: two peaks, a dilute one below 0.4 and a dense one above 0.8 (the coexisting
#           densities of hard ABP disks at this Pe: docs/validation.md section 21);
#   Pe 10:  one peak, within 0.05 of the mean packing fraction 0.6 (no separation).
# Prints the peaks and the pressures; exit status 1 when a criterion fails.
# usage: tools/validate_mips.sh build/hsbd [OUT]   (about 12 minutes of CPU)
set -u
HSBD=${1:?usage: validate_mips.sh path/to/hsbd [OUT]}
OUT=${2:-runs/validate/mips}
SRC=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$OUT"
status=0
for pe in 100 10; do
    v0=$pe # sigma = D = 1
    dir="$OUT/pe$pe"
    if ! "$HSBD" run "$SRC/examples/active-disks-mips.ini" --set active.v0=$v0 --out "$dir" --force --quiet; then
        echo "mips Pe $pe: the run failed"
        status=1
        continue
    fi
    peaks=$(/usr/bin/python3 "$SRC/tools/plot_active.py" "$dir" | sed -n 's/^local density peaks at phi = //p')
    p=$(grep -o '"pressure": [-0-9.e+]*' "$dir/summary.json" | awk '{ print $2 }')
    pe_=$(grep -o '"pressure_err": [-0-9.e+]*' "$dir/summary.json" | awk '{ print $2 }')
    r=$(grep -o '"swim_speed_ratio": [-0-9.e+]*' "$dir/summary.json" | awk '{ print $2 }')
    echo "$peaks" | awk -v pe=$pe -v p="$p" -v pe_="$pe_" -v r="$r" -F', *' '{
        n = NF; lo = $1; hi = $NF
        if (pe == 100) ok = n == 2 && lo < 0.4 && hi > 0.8
        else ok = n == 1 && lo > 0.55 && lo < 0.65
        printf "mips Pe %s: local density peaks at phi = %s (%s); pressure %s +- %s, swim speed ratio %s\n",
               pe, $0, ok ? "as expected" : "NOT as expected", p, pe_, r
        exit !ok }' || status=1
done
exit $status
