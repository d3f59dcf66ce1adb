#!/usr/bin/env bash
# Energies enter the physics only through U / kT. Energies in a configuration are absolute
# (in the units of system.kT), so doubling kT and every energy (field.amplitude,
# field.force, field.stiffness, pair.strength, tabulated potentials and forces) at fixed
# D must leave every result unchanged; Baxter's stickiness gamma is a pure number and
# stays. A factor 2 is exact in floating point (mu = D/kT halves, every force doubles, and
# mu F dt keeps its bits), so the tables must agree byte for byte, not only within errors:
# one test per model piece (each field term, each pair force, sticky contacts, walls,
# a mixture), and the other rule of contact too.
set -u
HSBD=${1:?usage: test_kt_scaling.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

QUICK=(--set run.t_total=0.3 --set run.t_equil=0.05 --set run.dt=1e-4 --set sample.blocks=4
       --set sample.every=10 --set sample.current_every=0.05 --quiet)

# a potential table on [0, L = 20]: U(x) = A cos(2 pi x / 2) + A/2 sin(2 pi x / 5) (periodic)
awk 'BEGIN { pi = atan2(0, -1); for (i = 0; i <= 400; ++i) { x = i * 0.05;
     printf "%.17g %.17g\n", x, 3 * cos(pi * x) + 1.5 * sin(2 * pi * x / 5) } }' >u1.tsv
# a force table between walls: f(x) = -0.4 + 0.3 sin(x)
awk 'BEGIN { for (i = 0; i <= 400; ++i) { x = i * 0.05;
     printf "%.17g %.17g\n", x, -0.4 + 0.3 * sin(x) } }' >f1.tsv
# a pair force table: repulsive, vanishing at r = 1.5
awk 'BEGIN { for (i = 0; i <= 100; ++i) { r = 0.5 + i * 0.01; d = 1.5 - r;
     printf "%.17g %.17g\n", r, 2 * d * d } }' >p1.tsv
for f in u1 f1 p1; do awk '{ printf "%.17g %.17g\n", $1, 2 * $2 }' $f.tsv >${f}x2.tsv; done

cat >base.ini <<'INI'
[system]
N = 12
L = 20
seed = 7
[field]
type = none
[sample]
bin_width = 0.1
INI

# data lines of every table, and the physical results of summary.json
fingerprint() {
    local dir=$1
    for f in "$dir"/*.tsv; do echo "== $(basename "$f")"; grep -v '^#' "$f"; done
    grep -E '"(particle_current|min_gap|mean_cluster_size|merge_events_per_step|rho2|wall_left|wall_right)' \
        "$dir/summary.json" | grep -v '_err'
    sed -n '/"contacts"/,/^  }/p' "$dir/summary.json"
}

# case NAME "settings at kT = 1" "the same at kT = 2 with every energy doubled"
case_kt() {
    local name=$1 one=$2 two=$3
    # shellcheck disable=SC2086
    "$HSBD" run base.ini "${QUICK[@]}" $one --out "$T/$name-1" 2>"$T/$name-1.err" ||
        { bad "$name: kT = 1 run failed: $(cat "$T/$name-1.err")"; return; }
    # shellcheck disable=SC2086
    "$HSBD" run base.ini "${QUICK[@]}" $two --set system.kT=2 --out "$T/$name-2" 2>"$T/$name-2.err" ||
        { bad "$name: kT = 2 run failed: $(cat "$T/$name-2.err")"; return; }
    fingerprint "$T/$name-1" >"$T/$name-1.fp"
    fingerprint "$T/$name-2" >"$T/$name-2.fp"
    if [ "$(grep -c . "$T/$name-1.fp")" -lt 20 ]; then bad "$name: too few result lines"; return; fi
    if cmp -s "$T/$name-1.fp" "$T/$name-2.fp"; then ok; else
        bad "$name: results differ between kT = 1 and kT = 2 (energies doubled):"
        diff "$T/$name-1.fp" "$T/$name-2.fp" | head -6 >&2
    fi
}

S=--set
ONE="$S system.D=1.3" # one species; the mixture gives its own D
case_kt cosine "$ONE $S field.type=cosine $S field.amplitude=6" \
               "$ONE $S field.type=cosine $S field.amplitude=12"
case_kt cosine-tilt "$ONE $S field.type=cosine+tilt $S field.amplitude=4 $S field.force=0.8" \
                    "$ONE $S field.type=cosine+tilt $S field.amplitude=8 $S field.force=1.6"
case_kt harmonic "$ONE $S field.type=harmonic $S field.stiffness=0.3" \
                 "$ONE $S field.type=harmonic $S field.stiffness=0.6"
case_kt table-potential-ring "$ONE $S field.type=table $S field.table=u1.tsv" \
                             "$ONE $S field.type=table $S field.table=u1x2.tsv"
case_kt table-force-walls "$ONE $S system.boundary=walls $S field.type=table $S field.table=f1.tsv $S field.table_kind=force" \
                          "$ONE $S system.boundary=walls $S field.type=table $S field.table=f1x2.tsv $S field.table_kind=force"
case_kt walls-sediment "$ONE $S system.boundary=walls $S field.type=tilt+harmonic $S field.force=-0.5 $S field.stiffness=0.02" \
                       "$ONE $S system.boundary=walls $S field.type=tilt+harmonic $S field.force=-1 $S field.stiffness=0.04"
case_kt yukawa "$ONE $S pair.type=yukawa $S pair.strength=1.5 $S pair.kappa=2" \
               "$ONE $S pair.type=yukawa $S pair.strength=3 $S pair.kappa=2"
case_kt lj "$ONE $S pair.type=lj $S pair.strength=0.7 $S field.type=cosine $S field.amplitude=2" \
           "$ONE $S pair.type=lj $S pair.strength=1.4 $S field.type=cosine $S field.amplitude=4"
case_kt pair-table "$ONE $S pair.type=table $S pair.table=p1.tsv" \
                   "$ONE $S pair.type=table $S pair.table=p1x2.tsv"
# Baxter's gamma is dimensionless: only kT changes
case_kt sticky "$ONE $S contact.gamma=1 $S contact.epsilon=0.05 $S field.type=cosine $S field.amplitude=3" \
               "$ONE $S contact.gamma=1 $S contact.epsilon=0.05 $S field.type=cosine $S field.amplitude=6"
case_kt sticky-rule-sticky "$ONE $S system.contact_rule=sticky $S contact.gamma=2 $S field.type=cosine $S field.amplitude=3" \
                           "$ONE $S system.contact_rule=sticky $S contact.gamma=2 $S field.type=cosine $S field.amplitude=6"
MIX="$S species.names=A,B $S species.count=8,4 $S species.sigma=0.4,0.9 $S species.D=1,0.5"
case_kt mixture-walls "$MIX $S system.boundary=walls $S field.type=cosine+tilt $S field.amplitude=2 $S field.force=-0.3" \
                      "$MIX $S system.boundary=walls $S field.type=cosine+tilt $S field.amplitude=4 $S field.force=-0.6"

echo "test_kt_scaling: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
