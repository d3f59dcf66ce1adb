#!/usr/bin/env bash
# End-to-end tests of the hsbd command line: bad input gets exit status 2 and one message
# naming file, line, key and allowed range, and leaves no output behind; examples and
# the authors' dialect run; outputs are reproducible and atomic; interrupts keep results.
set -u
HSBD=${1:?usage: test_cli.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0

ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# quick settings so every run takes well under a second
QUICK=(--set run.t_total=0.5 --set run.t_equil=0.1 --set run.dt=1e-3 --set sample.blocks=4 --quiet)

base_ini() {
    cat <<'INI'
[system]
N = 20
L = 40
sigma = 0.5
[field]
type = cosine
amplitude = 6
[run]
dt = 1e-3
t_equil = 0.1
t_total = 0.5
[sample]
bin_width = 0.05
blocks = 4
INI
}

# expect_fail NAME 'substring' ['substring'...] -- hsbd-args...
expect_fail() {
    local name=$1; shift
    local subs=()
    while [ "$1" != "--" ]; do subs+=("$1"); shift; done
    shift
    local out="$T/out-$name"
    "$HSBD" "$@" --out "$out" --quiet >"$T/stdout" 2>"$T/stderr"
    local rc=$?
    if [ $rc -ne 2 ]; then bad "$name: exit $rc, expected 2 ($(cat "$T/stderr"))"; return; fi
    if [ "$(wc -l <"$T/stderr")" -ne 1 ]; then bad "$name: expected one message line, got: $(cat "$T/stderr")"; return; fi
    for s in "${subs[@]}"; do
        if ! grep -qF -- "$s" "$T/stderr"; then bad "$name: message lacks '$s': $(cat "$T/stderr")"; return; fi
    done
    if [ -e "$out" ]; then bad "$name: output directory was created"; return; fi
    ok
}

with_line() { # with_line SECTION 'key = value' -> config with that line appended to SECTION
    base_ini | awk -v sec="[$1]" -v line="$2" '{print} $0==sec{print line; done=1}
        END{if (!done) {print sec; print line}}'
}

with_line system 'N = 0' >n0.ini
expect_fail n-zero "n0.ini:2:" "system.N = 0" "allowed: 1 <= N" -- run n0.ini
with_line system 'sigma = -0.1' >sneg.ini
expect_fail sigma-negative "sneg.ini:" "system.sigma = -0.1" "0 <= sigma" -- run sneg.ini
with_line system 'N = 5x' >nfmt.ini
expect_fail malformed-number "nfmt.ini:2:" "'5x' is not a whole number" -- run nfmt.ini
with_line run 'dt = 0' >dt0.ini
expect_fail dt-zero "dt0.ini:" "run.dt = 0" "0 < dt" -- run dt0.ini
with_line run 't_total = -1' >tt.ini
expect_fail t-total "tt.ini:" "run.t_total = -1" "0 < t_total" -- run tt.ini
base_ini | sed 's/^N = 20/N = 80/' >room.ini
expect_fail no-room "room.ini:2:" "system.N = 80" "no room" "N < 80" -- run room.ini
with_line sample 'bin_widht = 0.01' >typo.ini
expect_fail unknown-key "typo.ini:" "unknown key 'bin_widht'" "did you mean 'sample.bin_width'" -- run typo.ini
with_line sample 'period = 0.3' >per.ini
expect_fail period "per.ini:" "sample.period = 0.3 must divide system.L" -- run per.ini
base_ini | sed 's/^bin_width = 0.05/bin_width = 0.3/' >bw.ini
expect_fail bin-width "bw.ini:" "sample.bin_width = 0.3 must divide sample.period" -- run bw.ini
with_line system 'contact_rule = bounce' >ft.ini
expect_fail enum "ft.ini:" "system.contact_rule = 'bounce' is not known" "one of reflect|sticky" -- run ft.ini
for terms in cosinus cosine+cosine none+tilt 'cosine+'; do
    with_line field "type = $terms" >ft.ini
    expect_fail "field terms $terms" "ft.ini:" "field.type = '$terms' is not known" \
        "none, or terms from cosine|tilt|harmonic|table joined by '+'" -- run ft.ini
done
with_line system 'N = 30' >dup.ini
expect_fail duplicate "dup.ini:" "system.N is set twice" -- run dup.ini
printf '[system]\nthis line has no equals sign\n' >mal.ini
expect_fail malformed-line "mal.ini:2:" "malformed line" -- run mal.ini
expect_fail unreadable "cannot read configuration file 'missing.ini'" -- run missing.ini
base_ini >good.ini
expect_fail set-unknown "unknown key 'run.t_totl'" "did you mean 'run.t_total'" -- run good.ini --set run.t_totl=5
expect_fail set-range "command line (--set)" "run.dt = -3 is out of range" -- run good.ini --set run.dt=-3
expect_fail bad-flag "unknown option '--frobnicate'" -- run good.ini --frobnicate
# sticky contacts: the step condition of Antonov Eq. (33) refuses a step that is too long
printf 'particles = 10\nlength = 20\ndiameter = 0.5\ngamma = 1.0\ntimestep = 0.001\n' >sticky.cfg
expect_fail authors-sticky-dt "sticky.cfg:5" "run.dt = 0.001" "Eq. 33" "allowed: dt" "--force" -- run sticky.cfg
with_line contact 'order = 1' >ord.ini
expect_fail sticky-order "ord.ini:" "contact.order = 1" "1 < order" -- run ord.ini
with_line contact 'epsilon = 0' >eps.ini
expect_fail sticky-epsilon "eps.ini:" "contact.epsilon = 0" "0 < epsilon" -- run eps.ini
with_line contact 'gamma = -1' >gneg.ini
expect_fail sticky-gamma "gneg.ini:" "contact.gamma = -1" "0 <= gamma" -- run gneg.ini
# pair forces: unknown names, bad tables
with_line pair 'type = coulomb' >ptype.ini
expect_fail pair-type "ptype.ini:" "pair.type = 'coulomb'" "yukawa" -- run ptype.ini
with_line pair 'type = table' >pnotab.ini
expect_fail pair-no-table "pnotab.ini:" "pair.table" -- run pnotab.ini
printf '# r f\n0.5 1\n0.7 nan\n0.9 0\n' >tnan.txt
expect_fail pair-table-nan "tnan.txt:3" "two finite numbers" -- run good.ini --set pair.type=table --set pair.table=tnan.txt
printf '0.5 1\n0.8 0.5\n0.7 0\n' >tsort.txt
expect_fail pair-table-unsorted "tsort.txt:3" "strictly increasing" -- run good.ini --set pair.type=table --set pair.table=tsort.txt
printf '0.5 1\n0.8 0.5\n' >tend.txt
expect_fail pair-table-end "tend.txt" "not 0" -- run good.ini --set pair.type=table --set pair.table=tend.txt
printf '0.6 1\n0.8 0\n' >tstart.txt
expect_fail pair-table-start "tstart.txt" "first r <= system.sigma" -- run good.ini --set pair.type=table --set pair.table=tstart.txt
expect_fail pair-cutoff "pair.cutoff = 0.4" "sigma = 0.5 < cutoff" -- run good.ini --set pair.type=yukawa --set pair.cutoff=0.4
printf 'particles = 10\nlenght = 20\n' >authtypo.cfg
expect_fail authors-unknown "authtypo.cfg:2:" "unknown key 'lenght' outside any [section]" -- run authtypo.cfg
printf '1.0\n1.2\n5\n' >pos.txt
expect_fail positions-count "pos.txt" "3 positions for system.N = 20" -- run good.ini --set init.positions=pos.txt

# fields: tables that do not span the ring or the box, or are not increasing, ends that
# disagree on a ring (the periodic spline needs them equal), a table without a file
printf '0 1\n20 0\n40 1\n' >ftab.txt
"$HSBD" run good.ini --set field.type=cosine+table --set field.table=ftab.txt --out "$T/ftab" "${QUICK[@]}" \
    && ok || bad "field table spanning the ring did not run"
printf '0 1\n20 0\n41 1\n' >flong.txt
expect_fail field-table-ring-span "flong.txt" "on a ring" "last x = system.L = 40" -- run good.ini --set field.type=table --set field.table=flong.txt
printf '0 1\n20 0\n40 1.5\n' >fends.txt
expect_fail field-table-ring-ends "fends.txt" "equal values at its ends" "1.5" -- run good.ini --set field.type=table --set field.table=fends.txt
"$HSBD" run good.ini --set system.boundary=walls --set field.type=table --set field.table=flong.txt --out "$T/fwall" "${QUICK[@]}" \
    && ok || bad "field table covering the walls' box did not run"
printf '0 1\n20 0\n30 1\n' >fshort.txt
expect_fail field-table-cover "fshort.txt" "on a ring" "first x = 0" -- run good.ini --set field.type=table --set field.table=fshort.txt
expect_fail field-table-cover-walls "fshort.txt" "does not cover the box" "last x >= system.L = 40" -- run good.ini --set system.boundary=walls --set field.type=table --set field.table=fshort.txt
printf '0 1\n20 0\n10 1\n50 0\n' >fsort.txt
expect_fail field-table-unsorted "fsort.txt:3" "strictly increasing" -- run good.ini --set field.type=table --set field.table=fsort.txt
printf '0 1\n20 nan\n50 0\n' >fnan.txt
expect_fail field-table-nan "fnan.txt:2" "two finite numbers" -- run good.ini --set field.type=table --set field.table=fnan.txt
expect_fail field-table-missing "field.table" -- run good.ini --set field.type=harmonic+table
expect_fail field-stiffness "field.stiffness = -1" "0 <= stiffness" -- run good.ini --set field.type=harmonic --set field.stiffness=-1
# walls: profile over the box only; positions inside the walls
expect_fail walls-period "sample.period = 1" "allowed: sample.period = L = 40" -- run good.ini --set system.boundary=walls --set sample.period=1
printf '0.1\n' >wpos.txt; for k in $(seq 1 19); do echo "$((2 * k))" >>wpos.txt; done
expect_fail walls-positions "outside the walls" "sigma/2 = 0.25 <= x" -- run good.ini --set system.boundary=walls --set init.positions=wpos.txt
"$HSBD" run good.ini --set system.boundary=walls --set field.type=harmonic+tilt --set field.force=-0.5 --out "$T/walls" "${QUICK[@]}" \
    && grep -q '"wall_left"' "$T/walls/summary.json" && ok || bad "walls run without wall contact densities"
# independent replicas: each block restarts (its own draw, or init.positions) and
# equilibrates; the MSD's lags stay inside a replica
"$HSBD" run good.ini --set sample.blocking=replicas --out "$T/rep" "${QUICK[@]}" &&
    grep -q '"replicas": 4,' "$T/rep/summary.json" && grep -q '"equilibration_steps": 400,' "$T/rep/summary.json" &&
    grep -q "independent replica" "$T/rep/density_blocks.tsv" && ok || bad "replicas run"
for k in $(seq 0 19); do echo "$((2 * k + 1))" >>rpos.txt; done
"$HSBD" run good.ini --set sample.blocking=replicas --set init.positions=rpos.txt --out "$T/rep2" "${QUICK[@]}" &&
    grep -q '"replicas": 4,' "$T/rep2/summary.json" && ok || bad "replicas run from init.positions"
expect_fail replicas-lag "sample.msd_max_lag = 0.3" "run.t_total/sample.blocks = 0.125" -- run good.ini --set sample.blocking=replicas --set sample.msd_max_lag=0.3
# statistical (fixed seed 31): Tonks ring N = 1000, L = 2000, sigma = 0.5, 20 replicas of 2
# time units at dt = 1e-3; the contact theorem against the exact canonical value
# (N/L)(N-1)/(L - N sigma) = 0.333 within 4 error bars (replica errors match the scatter of
# independent runs: docs/validation.md section 14)
printf '[system]\nN = 1000\nL = 2000\nsigma = 0.5\nseed = 31\n[field]\ntype = none\n[run]\ndt = 1e-3\nt_equil = 0.5\nt_total = 40\n[sample]\nbin_width = 1\nperiod = 1\nblocking = replicas\n' >tonksrep.ini
if "$HSBD" run tonksrep.ini --out "$T/tonksrep" --quiet &&
    awk '!/^#/ && $1 != "x" { d = $4 - 0.333; e = $5; exit !(e > 0 && e < 0.01 && d * d < 16 * e * e) }' "$T/tonksrep/contact.tsv"; then ok
else bad "Tonks ring with replicas: contact theorem off the exact value ($(grep -v '^#' "$T/tonksrep/contact.tsv" | tail -1))"; fi
expect_fail profile-memory "sample.bin_width = 0.0001" "GiB of profile accumulators" "at most 4 GiB" -- run good.ini --set system.boundary=walls --set system.L=1000 --set sample.bin_width=1e-4 --set sample.blocks=20 --set sample.every=1
# exact theory between walls: the walls carry the column's weight (N |force| = 15)
"$HSBD" theory box --N 30 --L 50 --sigma 1 --force -0.5 --bin 0.5 --out box.tsv \
    && awk '/^# wall_left/{l=$4} /^# wall_right/{r=$4} END{d=l-r-15; exit !(d < 1e-3 && d > -1e-3)}' box.tsv \
    && ok || bad "theory box: walls do not balance the weight"
# one particle in a tilted cosine: no potential gives <v> = mu F and D_eff = D exactly; at
# U0 = 2, F = 2 the values of the unit tests (tests/unit/test_washboard.c)
"$HSBD" theory washboard --amplitude 1e-300 --force 3 --D 2 --kT 0.5 --out wb0.tsv \
    && awk '!/^#/ && $1 != "force" { exit !($2 > 11.999999 && $2 < 12.000001 && $3 > 1.999999 && $3 < 2.000001) }' wb0.tsv \
    && ok || bad "theory washboard: free particle"
"$HSBD" theory box --N 30 --L 20 --sigma 1 --out - >/dev/null 2>"$T/stderr"
[ $? -eq 2 ] && grep -q "N sigma < L" "$T/stderr" && ok || bad "theory box: no room not refused"
# mixtures: counts must sum to N, one entry per species, sane values
mix_ini() {
    printf '[system]\nN = 20\nL = 40\n[species]\nnames = A B\ncount = %s\nsigma = %s\nD = %s\n' "$1" "$2" "$3"
    printf '[field]\ntype = none\n[run]\ndt = 1e-3\nt_equil = 0.1\nt_total = 0.5\n[sample]\nblocks = 4\n'
}
mix_ini "12 8" "1 0.5" "1 2" >mix.ini
"$HSBD" run mix.ini --out "$T/mix" --quiet && grep -q 'msd_A' "$T/mix/msd.tsv" \
    && grep -q '"left": "B", "right": "A"' "$T/mix/summary.json" && ok || bad "mixture run lacks per-species outputs"
mix_ini "12 9" "1 0.5" "1 2" >mixn.ini
expect_fail species-sum "mixn.ini:6" "species.count sums to 21 rods but system.N = 20" -- run mixn.ini
mix_ini "12 8" "1" "1 2" >mixl.ini
expect_fail species-entries "mixl.ini:7" "species.sigma has 1 entries for 2 species.names" -- run mixl.ini
mix_ini "12 8" "1 0.5" "1 0" >mixd.ini
expect_fail species-d "mixd.ini:8" "species.D entry 2" "D > 0" -- run mixd.ini
mix_ini "12 8" "1 -0.5" "1 2" >mixs.ini
expect_fail species-sigma "mixs.ini:7" "species.sigma entry 2" "sigma >= 0" -- run mixs.ini
mix_ini "12 8.5" "1 0.5" "1 2" >mixc.ini
expect_fail species-count "mixc.ini:6" "species.count entry 2" "whole numbers" -- run mixc.ini
expect_fail species-system-sigma "system.sigma is set" -- run mix.ini --set system.sigma=0.5
expect_fail species-pair "one species" -- run mix.ini --set pair.type=yukawa
expect_fail species-no-names "species.count is set but species.names is empty" -- run good.ini --set species.count=20
printf '1 A\n3 C\n' >mpos.txt
expect_fail species-positions-name "mpos.txt:2" "unknown species 'C'" -- run mix.ini --set init.positions=mpos.txt
: >mpos2.txt; for k in $(seq 0 19); do echo "$((2 * k + 1)) A" >>mpos2.txt; done
expect_fail species-positions-count "20 rods of species A, but species.count says 12" -- run mix.ini --set init.positions=mpos2.txt

# an existing, non-empty run directory is refused without --force; with --force it is
# refused too when it holds files that no hsbd run wrote (they are never deleted), and an
# earlier run's files are replaced (tests/cli/test_faults.sh)
mkdir -p existing && echo keep >existing/note
"$HSBD" run good.ini --out existing --quiet 2>"$T/stderr"
if [ $? -eq 2 ] && grep -q "already exists" "$T/stderr" && [ ! -e existing/density.tsv ]; then ok; else bad "existing dir not refused"; fi
"$HSBD" run good.ini --out existing --force --quiet 2>"$T/stderr"
if [ $? -eq 2 ] && grep -q "'note'" "$T/stderr" && [ -e existing/note ] && [ ! -e existing/density.tsv ]; then ok; else bad "--force over a foreign file"; fi

# every example runs (shortened)
for ini in "$SRC"/examples/*.ini; do
    name=$(basename "$ini" .ini)
    extra=()  # sticky examples need the small step of Antonov Eq. (33)
    if grep -q '^gamma' "$ini"; then extra=(--set run.dt=1e-5 --set run.t_total=0.02 --set run.t_equil=0.01); fi
    if "$HSBD" run "$ini" "${QUICK[@]}" "${extra[@]}" --out "ex-$name" && [ -s "ex-$name/summary.json" ]; then ok; else bad "example $name"; fi
done

# profiles by the drive's phase: rods in a trap whose centre oscillates, c = 50 + 5 cos(pi t / 2),
# k = 2, mu = 1. The centre of mass is a driven Ornstein-Uhlenbeck process (docs/theory.md),
# X = 50 + R cos(theta - phi) with R = 5 / sqrt(1 + (omega/(mu k))^2), phi = atan(omega/(mu k)); its
# mean over phase bin 0 minus bin 2 (of 4) is 2 R (cos phi + sin phi) / (pi/2) = 7.0298. The
# density-weighted mean x of rho_0 and rho_2 must show it: each bin's mean has the error
# sqrt(kT/(N k) / n_eff) = 0.05 (n_eff = 10 correlation times 1/(mu k) of samples per bin over
# t = 40), the difference 0.07; tolerance 4 of them, 0.28. Fixed seed (the example's).
if "$HSBD" run "$SRC/examples/rods-oscillating-trap.ini" --set run.t_total=40 --set sample.blocks=10 \
    --set sample.phases=4 --quiet --out phases &&
    awk '!/^#/ && $1 != "x" { for (k = 0; k < 4; ++k) { w[k] += $(2 + 2 * k); m[k] += $1 * $(2 + 2 * k) } }
         END { d = m[0] / w[0] - m[2] / w[2] - 7.0298; exit !(NF == 9 && d < 0.28 && d > -0.28) }' phases/density_phases.tsv
then ok; else bad "density_phases.tsv: the oscillating trap's phase bins"; fi

# the authors' example file runs (shortened); so does their dialect written here
if "$HSBD" run "$SRC/examples/authors-basep.cfg" "${QUICK[@]}" --out ex-authors && [ -s ex-authors/current.tsv ]; then ok; else bad "examples/authors-basep.cfg"; fi

# --check verifies the hard core after every step, here on a dense ring (rho sigma = 0.9)
if "$HSBD" run good.ini --check --set system.N=72 --set system.L=40 --out dense --quiet &&
    grep -q '"min_gap": ' dense/summary.json; then ok; else bad "--check on a dense ring"; fi

# both contact rules run with the hard core verified after every step; reflect is the default
if "$HSBD" run good.ini --check --set system.N=72 --set system.L=40 \
    --out reflect --quiet && grep -q '"contact_rule": "reflect"' reflect/summary.json; then ok; else bad "contact_rule = reflect"; fi
if "$HSBD" run good.ini --check --set system.contact_rule=sticky --set system.N=72 --set system.L=40 \
    --out sticky --quiet && grep -q '"contact_rule": "sticky"' sticky/summary.json &&
    awk '!/^#/ && !/^x/ { if ($2 != $4 || $3 != $5) bad = 1 } END { exit bad }' sticky/contact.tsv; then ok; else bad "contact_rule = sticky"; fi

# the authors' dialect (their key names, no sections) runs unchanged
cat >authors.cfg <<'CFG'
particles = 20
length = 40
diameter = 0.5
force = 1.0
AmpU = 6.0
DiffusionConstant = 1.0
totaltime = 0.5
timestep = 0.001
tCurrent = 0.1
tTrajectory = 0.25
eqtime = 0.1
order = 3
epsilon = 0.05
delta = 0.01
deltaPrime = 0.01
gamma = 0.0
prefix = authors-out
CFG
if "$HSBD" run authors.cfg --quiet --set sample.blocks=4 && [ -s authors-out/current.tsv ] &&
    [ "$(grep -c '^20$' authors-out/trajectory.xyz)" -eq 2 ] &&
    grep -q '"type": "cosine+tilt"' authors-out/summary.json; then ok; else bad "authors' dialect"; fi

# initial positions from a file
seq 0 2 38 >pos20.txt
if "$HSBD" run good.ini --set init.positions=pos20.txt --out posrun --quiet && [ -s posrun/density.tsv ]; then ok; else bad "init.positions"; fi
printf '0\n0.3\n' >overlap.txt
expect_fail positions-overlap "overlap" -- run good.ini --set system.N=2 --set init.positions=overlap.txt

# same seed -> byte-identical tables; another seed -> different
"$HSBD" run good.ini --seed 7 --out r1 --quiet && "$HSBD" run good.ini --seed 7 --out r2 --quiet &&
    "$HSBD" run good.ini --seed 8 --out r3 --quiet
same=1
for f in density.tsv contact.tsv msd.tsv clusters.tsv; do cmp -s "r1/$f" "r2/$f" || same=0; done
if [ $same -eq 1 ]; then ok; else bad "same seed gave different tables"; fi
if ! cmp -s r1/density.tsv r3/density.tsv; then ok; else bad "seed has no effect"; fi
if grep -q '^# system.seed = 7$' r1/density.tsv && grep -q '^# x	rho	rho_err$' r1/density.tsv &&
    grep -q '^# x	rho2	rho2_err	rho2_theorem	rho2_theorem_err	rho2_window	rho2_window_err	rho2_extrap	rho2_extrap_err$' r1/contact.tsv; then ok; else bad "table header"; fi
# the default rho2 column is the extrapolated estimator under reflect (the default rule)
if awk '!/^#/ && !/^x/ { if ($2 != $8 || $3 != $9) bad = 1 } END { exit bad }' r1/contact.tsv; then ok; else bad "rho2 is not rho2_extrap under reflect"; fi
if ls r1/*.part >/dev/null 2>&1; then bad "temporary files left"; else ok; fi

# SIGINT: results so far are written, marked incomplete, exit 130
"$HSBD" run good.ini --set run.t_total=1e4 --set output.trajectory=xyz --out intr --quiet &
pid=$!
for _ in $(seq 1500); do [ -e intr/trajectory.xyz.part ] && break; sleep 0.02; done
sleep 0.2 # a few samples in
kill -INT $pid
wait $pid
rc=$?
if [ $rc -eq 130 ] && grep -q '"completed": false' intr/summary.json && [ -s intr/density.tsv ] &&
    ! ls intr/*.part >/dev/null 2>&1; then ok; else bad "interrupt: rc=$rc"; fi

# a run that produces non-finite positions stops with a message; what was sampled stays valid
"$HSBD" run good.ini --set field.amplitude=1e308 --out nan --quiet 2>"$T/stderr"
rc=$?
if [ $rc -eq 1 ] && grep -q "non-finite position" "$T/stderr" && grep -q '"completed": false' nan/summary.json &&
    ! ls nan/*.part >/dev/null 2>&1; then ok; else bad "non-finite run: rc=$rc $(cat "$T/stderr")"; fi

# ---- spheres (EDBD) ----
sph_ini() {
    cat <<'INI'
[system]
model = spheres
N = 200
packing_fraction = 0.2
[run]
dt = 1e-3
t_equil = 0.05
t_total = 0.4
[sample]
blocks = 4
INI
}
sph_ini >sph.ini
if "$HSBD" run sph.ini --out sph --quiet && grep -q '"model": "spheres"' sph/summary.json &&
    grep -q '"Z_virial":' sph/summary.json && [ -s sph/gr.tsv ] && [ -s sph/msd.tsv ] && [ -s sph/fs.tsv ] &&
    python3 -c "import json,sys; json.load(open('sph/summary.json'))" 2>/dev/null; then ok; else bad "spheres run"; fi
# same seed, same tables
"$HSBD" run sph.ini --out sph2 --quiet
if cmp -s sph/gr.tsv sph2/gr.tsv && cmp -s sph/msd.tsv sph2/msd.tsv; then ok; else bad "spheres: not reproducible"; fi
# a 2D binary mixture by number fractions, lattice start, XYZ trajectory read back as input
sph_ini | sed 's/packing_fraction = 0.2/packing_fraction = 0.4\ndimension = 2/' >disk.ini
printf '[species]\nnames = A B\nfraction = 0.5 0.5\nsigma = 1 1.4\nD = 1 0.7\n[output]\ntrajectory = xyz\n' >>disk.ini
if "$HSBD" run disk.ini --out disk --quiet && grep -q '"g_contact"' disk/summary.json &&
    grep -q 'msd_A' disk/msd.tsv && head -2 disk/trajectory.xyz | grep -q 'Lattice='; then ok; else bad "2D mixture run"; fi
tail -n 202 disk/trajectory.xyz >frame.xyz
if "$HSBD" run disk.ini --set init.positions=frame.xyz --set output.trajectory=none --out disk2 --quiet; then ok; else bad "XYZ input"; fi
# bad input
awk 'NR==3{$2 = $2; $3 = $3} {print}' frame.xyz | awk 'NR==4{split(prev, a, " "); $2 = a[2]; $3 = a[3]} {prev = $0; print}' >overlap.xyz
expect_fail sph-overlap "overlap.xyz" "overlap" -- run disk.ini --set init.positions=overlap.xyz --set output.trajectory=none
sed 's/^A /Q /' frame.xyz >unknown.xyz
expect_fail sph-unknown-species "unknown.xyz:3:" "unknown species name 'Q'" -- run disk.ini --set init.positions=unknown.xyz --set output.trajectory=none
expect_fail sph-phi "system.packing_fraction" "exceeds close packing" -- run sph.ini --set system.packing_fraction=0.8
expect_fail sph-random "init.method = random reaches" -- run sph.ini --set system.packing_fraction=0.4 --set init.method=random
expect_fail sph-sigma "system.sigma = 0" "sigma > 0" -- run sph.ini --set system.sigma=0
expect_fail sph-dneg "species.D entry 2" -- run disk.ini --set "species.D=1 -1"
expect_fail sph-box "twice the interaction range" "system.packing_fraction" -- run sph.ini --set system.packing_fraction=0.2 --set system.N=4
expect_fail sph-rods-key "contact.gamma applies to system.model = rods only" -- run sph.ini --set contact.gamma=0.5
expect_fail sph-both "exactly one of system.box and system.packing_fraction" -- run sph.ini --set system.box=20
expect_fail sph-lattice-dense "init.method = lattice" "spacing" -- run disk.ini --set system.packing_fraction=0.85 --set init.method=lattice
# continuous polydispersity with Stokes-Einstein D, compressed to a dense fluid; its frame
# (with radii) read back; the diameters' moments come out in summary.json
sph_ini | sed 's/packing_fraction = 0.2/packing_fraction = 0.5/' >poly.ini
printf '[species]\npolydispersity = 0.1\nD_law = stokes-einstein\n[output]\ntrajectory = xyz\n' >>poly.ini
if "$HSBD" run poly.ini --out poly --quiet && grep -q '"method": "compress"' poly/summary.json &&
    grep -q '"Z_theory_eos": "BMCSL"' poly/summary.json &&
    python3 -c "
import json; d = json.load(open('poly/summary.json'))
assert d['min_gap'] >= 0 and d['contacts'][0]['g_contact'] > 1
assert abs(d['sizes']['relative_width'] - 0.1) < 0.02" 2>/dev/null; then ok; else bad "polydisperse run"; fi
tail -n 202 poly/trajectory.xyz >pframe.xyz
if "$HSBD" run poly.ini --set init.positions=pframe.xyz --set output.trajectory=none --out poly2 --quiet; then ok; else bad "polydisperse XYZ input"; fi
awk '{print $1, $2, $3, $4}' pframe.xyz >noradius.xyz
expect_fail sph-poly-radius "noradius.xyz:" "radius" -- run poly.ini --set init.positions=noradius.xyz --set output.trajectory=none
expect_fail sph-poly-width "species.polydispersity = 0.5" "0 <= polydispersity <= 0.3" -- run poly.ini --set species.polydispersity=0.5
expect_fail sph-se-d "species.D is set, but species.D_law = stokes-einstein" -- run disk.ini --set species.D_law=stokes-einstein
expect_fail sph-compress-dense "init.method = compress reaches" "init.method = lattice" -- run sph.ini --set system.packing_fraction=0.62 --set init.method=compress
# the scheme's checks use the particles' own sizes and D: uniform polydispersity 0.2 with
# Stokes-Einstein D gives particles of 0.654 sigma with D 1.53; at dt 1.25e-3 the nominal
# step is 0.080 sigma (no warning) but theirs is 0.151 of their diameter (Scala Eq. 6),
# warned on stderr at the start and listed in summary.json
sph_ini | sed 's/dt = 1e-3/dt = 1.25e-3/' >se.ini
printf '[species]\npolydispersity = 0.2\ndistribution = uniform\nD_law = stokes-einstein\n' >>se.ini
if "$HSBD" run se.ini --out se --quiet 2>se.err && grep -q "warning: the mean step is 0.1[45]" se.err &&
    grep -q "Scala Eq. 6" se.err && python3 -c "
import json; d = json.load(open('se/summary.json'))
assert 0.14 < d['mean_step_over_sigma'] < 0.16, d['mean_step_over_sigma']
assert any('Eq. 6' in w for w in d['warnings'])" 2>/dev/null; then ok; else bad "spheres scheme check: $(cat se.err)"; fi
# the mean gap at phi 0.45: a step of 0.7 of it is warned (Scala Eq. 3)
if "$HSBD" run sph.ini --set system.packing_fraction=0.45 --set init.method=compress --set run.dt=2e-3 \
       --out eq3 --quiet 2>eq3.err && grep -q "Scala Eq. 3" eq3.err; then ok; else bad "Eq. 3 warning: $(cat eq3.err)"; fi

# D_L's time-step error (docs/spheres.md, "D_L and the time step"): at phi 0.3 a step of
# 1e-2 leaves D_L several percent low, warned on stderr and in summary.json with the dt that
# keeps it within 1 %; 1e-3 is below that level, and ideal particles (hard core off) have
# no such error
dl_step() { # dl_step NAME DT [ARGS...]: the warning build of a phi 0.3 run
    local name=$1 dt=$2
    shift 2
    "$HSBD" run sph.ini --set system.packing_fraction=0.3 --set run.dt="$dt" --set run.t_equil=0 \
        --set run.t_total=0.1 --set sample.every=1 --set sample.blocks=2 "$@" --out "$name" \
        --quiet 2>"$name.err"
}
if dl_step dlc 1e-2 && grep -q "warning: run.dt = 0.01: D_L (D_long, the MSD's long-time slope) is about [3-6]\.[0-9] % low at phi 0.3 .*; run.dt <= 0.00[12][0-9]* keeps it within 1 %" dlc.err &&
    python3 -c "
import json; w = json.load(open('dlc/summary.json'))['warnings']
assert sum('D_L (D_long' in x for x in w) == 1, w" 2>/dev/null; then ok
else bad "D_L time-step warning at dt 1e-2: $(cat dlc.err)"; fi
if dl_step dlf 1e-3 && ! grep -q "D_L" dlf.err && python3 -c "
import json; w = json.load(open('dlf/summary.json'))['warnings']
assert not any('D_L' in x for x in w), w" 2>/dev/null; then ok
else bad "D_L warned at dt 1e-3: $(cat dlf.err)"; fi
if dl_step dli 1e-2 --set system.hard_core=off && ! grep -q "D_L" dli.err; then ok
else bad "D_L warned for ideal particles: $(cat dli.err)"; fi

# above phi = pi/6 Scala's mean gap rho^(-1/3) - sigma is negative: the lattice spacing's
# gap stays finite (phi 0.55, dt 2e-4: a step of 0.31 of it, no warning, no inf or nan)
if "$HSBD" run sph.ini --set system.packing_fraction=0.55 --set init.method=compress \
       --set run.dt=2e-4 --set run.t_equil=0 --set run.t_total=0.02 --out dense55 2>dense55.err &&
    ! grep -q -i -E "inf|nan|mean gap" dense55.err && python3 -c "
import json; d = json.load(open('dense55/summary.json'))
assert abs(d['mean_step_over_mean_gap'] - 0.306) < 0.005, d['mean_step_over_mean_gap']" 2>/dev/null
then ok; else bad "spheres at phi 0.55: $(cat dense55.err)"; fi

# g(r) between walls on two axes, or with a field across the walls' axis, is not
# written: said on stderr and in summary.json's warnings, not dropped in silence
for case in "walls2|--set system.boundary=walls,walls,periodic" \
    "across|--set system.boundary=walls,periodic,periodic --set field.type=tilt --set field.force=-1 --set field.axis=y"; do
    name=${case%%|*}
    "$HSBD" run sph.ini ${case#*|} --set run.t_total=0.05 --out nogr-$name 2>nogr-$name.err
    if [ ! -e nogr-$name/gr.tsv ] && grep -q "warning: gr.tsv is not written" nogr-$name.err &&
        grep -q '"warnings": \[.*gr.tsv is not written' nogr-$name/summary.json; then ok
    else bad "g(r) not written ($name) without a word: $(cat nogr-$name.err)"; fi
done

# S(k) (sample.sk_every): particles frozen (D = 1e-9) on a simple cubic lattice of spacing 2
# in a box of 8 give exactly N = 64 at the reciprocal vector 2 pi / 2 (three axis vectors,
# alone in their bin below sk_max = 3.3) and 0 elsewhere; ideal particles give S = 1 in every
# bin within 4 error bars (fixed seed: 9 bins, chi^2/dof 0.50)
awk 'BEGIN { print 64; print "Lattice=\"8 0 0 0 8 0 0 0 8\""
    for (i = 0; i < 4; i++) for (j = 0; j < 4; j++) for (k = 0; k < 4; k++)
        printf "S %g %g %g\n", 2 * i + 1, 2 * j + 1, 2 * k + 1 }' >lattice.xyz
printf '[system]\nmodel = spheres\nN = 64\nbox = 8\nD = 1e-9\n[run]\ndt = 1e-3\nt_equil = 0\nt_total = 0.04\n[sample]\nblocks = 4\nsk_every = 1\nsk_max = 3.3\n[init]\npositions = lattice.xyz\n' >lattice.ini
if "$HSBD" run lattice.ini --out sk-lattice --quiet && awk '!/^#/ && NR > 1 && $1 + 0 > 0 {
        bragg = ($1 - 3.14159265 < 1e-6 && 3.14159265 - $1 < 1e-6)
        if (bragg && ($2 < 64 - 1e-6 || $2 > 64 + 1e-6 || $4 != 3)) bad = 1
        if (!bragg && $2 > 1e-6) bad = 1; n++ } END { exit bad || n != 4 }' sk-lattice/sk.tsv
then ok; else bad "S(k) of a lattice: $(grep -v '^#' sk-lattice/sk.tsv 2>&1 | tr '\n' ' ')"; fi
printf '[system]\nmodel = spheres\nN = 500\nbox = 10\nhard_core = off\nseed = 4\n[run]\ndt = 1e-2\nt_equil = 1\nt_total = 20\n[sample]\nsk_every = 10\nsk_max = 6\n' >ideal.ini
if "$HSBD" run ideal.ini --out sk-ideal --quiet 2>/dev/null && awk '!/^#/ && $1 + 0 > 0 {
        z = ($2 - 1) / $3; s += z * z; n++; if (z * z > 16) bad = 1 }
        END { exit bad || n != 9 || s / n > 3 }' sk-ideal/sk.tsv; then ok
else bad "S(k) of ideal particles: $(grep -v '^#' sk-ideal/sk.tsv 2>&1 | tr '\n' ' ')"; fi

# rods' time step against the field's and the pair force's time scales: the cosine of
# U0 = 6 (k = mu max|U''| = 118.4) at dt 0.01 distorts the density by ~30 % with Euler's
# step (dt k / 4 = 0.296) and ~18 % with Heun's ((dt k)^2 / 8 = 0.175), warned on stderr
# with a suggested dt and listed in summary.json; none at dt 1e-5 (Euler) or 1e-4 (Heun,
# the default); a stiff pair force (LJ well at contact, always an Euler step) is warned too
rods_dt() { # rods_dt DIR DT [--set ...]: a short cosine run at DT
    local dir=$1 dt=$2
    shift 2
    "$HSBD" run "$SRC/examples/rods-cosine.ini" --quiet --set run.dt="$dt" --set run.t_equil=0 \
        --set run.t_total="$(awk -v d="$dt" 'BEGIN { print 200 * d }')" --set sample.every=1 \
        --set sample.blocks=4 "$@" --out "$dir" 2>"$dir.err"
}
step_warned() { # step_warned DIR STEP ESTIMATE: one warning naming STEP, the estimate in the summary
    python3 -c "
import json; d = json.load(open('$1/summary.json'))
assert abs(d['field_step_error'] - $3) < 1e-3, d['field_step_error']
assert len(d['warnings']) == 1 and '$2' in d['warnings'][0]" 2>/dev/null
}
if rods_dt coarse 0.01 --set run.field_step=euler && grep -q "warning: run.dt = 0.01: the field's Euler step distorts the stationary density by about 30 %.*run.dt <= 0.00034 gives about 1 %" coarse.err &&
    step_warned coarse Euler 0.296; then ok
else bad "rods Euler time-step warning at dt 0.01: $(cat coarse.err)"; fi
if rods_dt coarseh 0.01 && grep -q "warning: run.dt = 0.01: the field's Heun step distorts the stationary density by about 18 %.*run.dt <= 0.0024 gives about 1 %, <= 0.00076 about 0.1 %" coarseh.err &&
    step_warned coarseh Heun 0.175; then ok
else bad "rods Heun time-step warning at dt 0.01: $(cat coarseh.err)"; fi
for case in "fine 1e-5 euler" "fineh 1e-4 heun"; do
    read -r dir dt step <<<"$case"
    if rods_dt "$dir" "$dt" --set run.field_step="$step" && [ ! -s "$dir.err" ] && python3 -c "
import json; d = json.load(open('$dir/summary.json')); assert d['warnings'] == []" 2>/dev/null; then ok
    else bad "rods at dt $dt ($step) warned: $(cat "$dir.err")"; fi
done
if rods_dt ljpair 1e-3 --set pair.type=lj --set pair.strength=2 --set pair.cutoff=1 &&
    ! grep -q "the field's" ljpair.err && grep -q "the pair force's Euler step distorts the pair distribution by about 29 %" ljpair.err
then ok; else bad "rods pair-force time-step warning: $(cat ljpair.err)"; fi

# the configuration reference in docs/ is the one the schema generates
if "$HSBD" config-doc | diff -q - "$SRC/docs/config.md" >/dev/null; then ok; else bad "docs/config.md is stale: run 'build/hsbd config-doc > docs/config.md'"; fi

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
