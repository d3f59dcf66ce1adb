#!/usr/bin/env bash
# The flagship example (examples/rods-cosine.ini) at the settings it ships with agrees with
# Percus' exact profile, as its comments say: the density over 50 bins has chi^2/dof <= 2
# and no bin beyond 4.5 error bars, the contact density (the default estimator) chi^2/dof
# <= 2, each against the theory averaged over the bin. Fixed seed (the example's, 1:
# chi^2/dof 1.08 with the default Heun step, largest bin 2.4; 1.30 with Euler's). The
# bound: over seeds 1-6 the density's chi^2/dof is 0.31-1.34 with Heun's step (0.60-1.60
# with Euler's); for 50 independent bins the 99.9 % point of chi^2/dof is 1.73, and the bars
# (20 segments: Student's t with 19 degrees of freedom) fatten its tail, so 2 is a failure
# of the physics, not of luck. About 15 s (optimised build only).
set -u
HSBD=${1:?usage: test_flagship.sh path/to/hsbd}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$HSBD" run "$SRC/examples/rods-cosine.ini" --quiet --out "$T/run" || { echo "FAIL: the example did not run"; exit 1; }
"$HSBD" theory percus --sigma 0.5 --rho 0.5 --amplitude 6 --out "$T/percus.tsv" >/dev/null ||
    { echo "FAIL: theory"; exit 1; }
/usr/bin/python3 - "$SRC/tools" "$T/run" "$T/percus.tsv" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
from hsbd_tools import read_table

theory = read_table(sys.argv[3]).data
fine = np.linspace(0, 1, 20001)[:-1]
fail = 0
for table, column, theory_col, max_z in (("density", "rho", 1, 4.5), ("contact", "rho2", 2, None)):
    t = read_table(f"{sys.argv[2]}/{table}.tsv")
    x = t.data[:, 0]
    k = t.names.index(column)
    sim, err = t.data[:, k], t.data[:, k + 1]
    width = x[1] - x[0]
    ref = np.interp(fine, theory[:, 0], theory[:, theory_col], period=1.0)
    mean = np.array([ref[((fine - (xi - width / 2)) % 1.0) < width].mean() for xi in x])
    z = (sim - mean) / err
    chi2 = float(np.mean(z ** 2))
    ok = chi2 <= 2.0 and (max_z is None or np.max(np.abs(z)) <= max_z)
    print(f"{table}: chi2/dof {chi2:.2f} over {len(z)} bins, largest |dev| {np.max(np.abs(z)):.2f} error bars: {'pass' if ok else 'FAIL'}")
    fail += not ok
sys.exit(1 if fail else 0)
PY
