#!/usr/bin/env bash
# Spheres between walls through `hsbd run` (fixed seeds):
# - The exact wall-and-drift step: 20000 free disks start 1 from contact with the wall at
#   x = 0 (D = 1, kT = 1, field.force = -1: drift c = -1 towards it) and run to t = 1 in
#   steps dt = 1, 0.1 and 0.01 (the first trajectory frame); the end gaps' mean and mean square must lie within 4 of
#   their standard errors of the corrected Scala Eq. 9 (docs/theory.md): 0.850398 and
#   1.299204, the quadrature of hsbd_reflected_drift_density (its moments are checked in
#   test_spheres_walls). The naive mirror rule would give a mean of 1.13 (about 100 error
#   bars off).
# - species.coupling_law = volume with polydisperse diameters: the wall theorem with the
#   drawn sizes (4 error bars).
# - The sedimentation and slit examples run (shortened) and report density.tsv per species,
#   the walls and g(sigma+) in summary.json and gr.tsv; the trajectory marks the walls axes
#   non-periodic.
# - Ideal particles (hard_core = off, two species, couplings 1 / 2) in gravity between
#   walls, and in a cosine field (U0 1, wavelength 3) along z of a periodic box: every bin
#   of gr.tsv (profile-weighted reference) is 1 within 4.5 error bars.
set -u
HSBD=${1:?usage: test_walls_cli.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

awk 'BEGIN { n = 20000; print n; print "Lattice=\"60 0 0 0 2000 0 0 0 1\" Properties=species:S:1:pos:R:3";
             for (i = 0; i < n; i++) printf "S 1.5 %.3f 0\n", 0.05 + 0.1 * i }' >start.xyz
cat >eq9.ini <<'INI'
[system]
model = spheres
dimension = 2
N = 20000
box = 60 2000
boundary = walls periodic
hard_core = off
[field]
type = tilt
force = -1
axis = x
[init]
positions = start.xyz
[run]
t_equil = 0
t_total = 2
[sample]
every = 1
blocks = 2
[output]
trajectory = xyz
trajectory_every = 1
INI
for dt in 1 0.1 0.01; do
    "$HSBD" run eq9.ini --set run.dt=$dt --set system.seed=7 --out "eq9-$dt" --quiet 2>/dev/null ||
        { bad "eq9 dt $dt: run failed"; continue; }
    line=$(sed -n 3,20002p "eq9-$dt/trajectory.xyz" | awk -v m1=0.850398 -v m2=1.299204 '
        { g = $2 - 0.5; s1 += g; s2 += g * g; s4 += g * g * g * g; n++ }
        END { a = s1 / n; b = s2 / n; ea = sqrt((b - a * a) / n); eb = sqrt((s4 / n - b * b) / n);
              printf "%.5f %.5f %.5f %.5f %.2f %.2f\n", a, ea, b, eb, (a - m1) / ea, (b - m2) / eb }')
    read -r mean mean_err msq msq_err dev1 dev2 <<<"$line"
    echo "eq9 dt $dt: mean gap $mean +- $mean_err ($dev1 error bars), mean square $msq +- $msq_err ($dev2)"
    if awk -v a="$dev1" -v b="$dev2" 'BEGIN { exit !(a * a < 16 && b * b < 16) }'; then ok; else bad "eq9 dt $dt: $line"; fi
done
head -2 "eq9-1/trajectory.xyz" | grep -q 'pbc="F T F"' && ok || bad "trajectory: pbc of walls axis"

"$HSBD" run "$SRC/examples/spheres-sedimentation.ini" --set run.t_equil=0.2 --set run.t_total=0.4 \
    --out sed --quiet 2>/dev/null || bad "sedimentation example"
grep -q '"side": "low"' sed/summary.json && grep -q '"side": "high"' sed/summary.json && ok ||
    bad "sedimentation: walls in summary.json"
grep -q 'rho_A_err' sed/density.tsv && ok || bad "sedimentation: density.tsv per species"
"$HSBD" run "$SRC/examples/spheres-slit.ini" --set run.t_equil=0.2 --set run.t_total=0.4 \
    --out slit --quiet 2>/dev/null || bad "slit example"
grep -q '"contact_density"' slit/summary.json && ok || bad "slit: contact densities"
[ -s slit/gr.tsv ] && grep -q '"g_contact"' slit/summary.json && ok || bad "slit: g(r) between walls"
# walls on one axis: its profile is density.tsv, written once (no density_z.tsv beside it)
[ -s slit/density.tsv ] && [ ! -e slit/density_z.tsv ] && ok || bad "slit: $(ls slit | grep density)"

cat >ideal.ini <<'INI'
[system]
model = spheres
N = 300
box = 4 4 6
boundary = periodic periodic walls
hard_core = off
seed = 11
[species]
names = A B
fraction = 0.5 0.5
sigma = 0.1 0.14
D = 1 1
coupling = 1 2
[field]
type = tilt
force = -1
[run]
dt = 0.05
t_equil = 10
t_total = 300
[sample]
gr_every = 10
gr_max = 2
gr_bin = 0.1
INI
# every bin of DIR/gr.tsv within 4.5 error bars of 1 (more than 30 bins)
gr_is_one() {
    local line bins chi2 worst
    line=$(grep -v '^#' "$1/gr.tsv" | awk '{ for (c = 2; c < NF; c += 2) if ($(c + 1) > 0) {
            d = ($c - 1) / $(c + 1); chi += d * d; n++; if (d * d > w) w = d * d } }
        END { printf "%d %.1f %.2f\n", n, chi, sqrt(w) }')
    read -r bins chi2 worst <<<"$line"
    echo "$2: g(r) = 1 over $bins bins, chi^2 $chi2, largest deviation $worst error bars"
    awk -v n="$bins" -v w="$worst" 'BEGIN { exit !(n > 30 && w < 4.5) }' && ok || bad "$2: g(r) $line"
}
if "$HSBD" run ideal.ini --out ideal --quiet 2>/dev/null; then
    gr_is_one ideal "ideal particles in gravity between walls"
else
    bad "ideal particles between walls run"
fi
sed -e 's/^boundary = .*/boundary = periodic/' -e 's/^type = tilt/type = cosine/' \
    -e 's/^force = -1/amplitude = 1\nwavelength = 3/' ideal.ini >cosine.ini
if "$HSBD" run cosine.ini --out cosine --quiet 2>/dev/null; then
    gr_is_one cosine "ideal particles in a cosine field, periodic box"
else
    bad "ideal particles in a cosine field run"
fi

# species.coupling_law = volume with polydisperse sizes: the wall theorem with the drawn
# diameters, kT (rho_low - rho_high) = sum_i (sigma_i / sigma)^3 |F| / A (the radii from
# the trajectory), within 4 error bars of the difference (the two walls' errors added)
cat >vol.ini <<'INI'
[system]
model = spheres
N = 150
box = 5 5 12
boundary = periodic periodic walls
seed = 3
[species]
polydispersity = 0.15
coupling_law = volume
[field]
type = tilt
force = -0.4
[run]
dt = 2e-3
t_equil = 20
t_total = 60
[output]
trajectory = xyz
trajectory_every = 60
INI
if "$HSBD" run vol.ini --out vol --quiet 2>/dev/null; then
    weight=$(tail -n 150 vol/trajectory.xyz | awk '{ w += (2 * $5)^3 } END { printf "%.6f", w * 0.4 / 25 }')
    line=$(grep -o '"contact_density": [-0-9.e+]*, "contact_density_err": [0-9.e+-]*' vol/summary.json |
        awk -v w="$weight" 'NR == 1 { lo = $2; le = $4 } NR == 3 { hi = $2; he = $4 }
            END { gsub(",", "", lo); gsub(",", "", hi); d = lo - hi; e = sqrt(le * le + he * he);
                  printf "%.4f %.4f %.4f %.2f\n", d, e, w, (d - w) / e }')
    read -r diff diff_err wt dev <<<"$line"
    echo "coupling_law = volume: rho_low - rho_high $diff +- $diff_err, weight per area $wt ($dev error bars)"
    awk -v d="$dev" 'BEGIN { exit !(d * d < 16) }' && ok || bad "coupling_law volume: wall theorem $line"
else
    bad "coupling_law volume run"
fi

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
