#!/usr/bin/env bash
# Threads change no result: rods runs on 1, 2 and 4 threads (oversubscribed on a small
# machine, which is fine) write byte-identical tables (every file, headers included) and
# the same physical results in summary.json, for a ring with a field (the default reflect
# rule), the sticky rule, walls with a tilt, a mixture (ring and walls), and pair forces
# (ring and walls; on threads each rod gathers its pair forces in the serial order). N is
# large enough that every threaded loop is split (more than four chunks of rods and gaps).
# The isotonic regression splits sequences longer than 4096 rods into chunks joined at the
# seams: the dense cases (12000 rods, three chunks; a ring, the sticky rule, walls, a
# mixture on a ring and between walls) pool blocks across the seams once or twice a step.
set -u
HSBD=${1:?usage: test_threads.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
# idle threads sleep instead of spinning: on a loaded machine spinning only wastes time
export OMP_WAIT_POLICY=passive
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

cat >ring.ini <<'INI'
[system]
N = 5000
L = 10000
sigma = 0.9
seed = 3
[field]
type = cosine
amplitude = 4
[run]
dt = 1e-4
t_equil = 0.002
t_total = 0.01
[sample]
blocks = 4
every = 5
current_every = 0.0025
INI
cat >mixture.ini <<'INI'
[system]
N = 5000
L = 8000
seed = 9
[species]
names = long short
count = 2500 2500
sigma = 1 0.5
D = 1 2
[field]
type = cosine
amplitude = 2
wavelength = 2
[run]
dt = 1e-4
t_equil = 0.002
t_total = 0.01
[sample]
blocks = 4
every = 5
bin_width = 0.02
INI

# the dense systems: 12000 rods, steps of 1e-3 (ten times the time of the runs above)
densify() { sed -e 's/^N = 5000/N = 12000/' -e 's/^dt = 1e-4/dt = 1e-3/' -e 's/^t_equil = 0.002/t_equil = 0.01/' \
                -e 's/^t_total = 0.01/t_total = 0.05/' -e 's/^current_every = 0.0025/current_every = 0.0125/' "$@"; }
densify -e 's/^L = 10000/L = 11000/' ring.ini >dense.ini
densify -e 's/^L = 8000/L = 9400/' -e 's/^count = 2500 2500/count = 6000 6000/' mixture.ini >dense-mixture.ini

# walls start from evenly spaced rods (the exact sampler of a bounded system with a field
# costs more than these short runs), with coarse bins (the profile spans the whole box)
awk 'BEGIN { for (i = 0; i < 5000; ++i) printf "%.6f\n", (i + 0.5) * 2 }' >even.txt
awk 'BEGIN { for (i = 0; i < 5000; ++i) printf "%.6f %s\n", (i + 0.5) * 2, i % 2 ? "short" : "long" }' >even-mix.txt
awk 'BEGIN { for (i = 0; i < 12000; ++i) printf "%.6f\n", (i + 0.5) * 11000 / 12000 }' >even-dense.txt
awk 'BEGIN { for (i = 0; i < 12000; ++i) printf "%.6f %s\n", 0.5 + i * 9399 / 12000, i % 2 ? "short" : "long" }' >even-dense-mix.txt

cases=(
  "ring|ring.ini|"
  "sticky|ring.ini|--set system.contact_rule=sticky"
  "walls|ring.ini|--set system.boundary=walls --set field.type=cosine+tilt --set field.force=0.5 --set init.positions=even.txt --set sample.bin_width=2"
  "mixture|mixture.ini|"
  "mixture-walls|mixture.ini|--set system.boundary=walls --set system.L=10000 --set init.positions=even-mix.txt --set sample.bin_width=2"
  "yukawa|ring.ini|--set pair.type=yukawa --set pair.strength=1 --set pair.kappa=1 --set pair.cutoff=4"
  "yukawa-walls|ring.ini|--set pair.type=yukawa --set pair.strength=1 --set pair.kappa=1 --set pair.cutoff=4 --set system.boundary=walls --set init.positions=even.txt --set sample.bin_width=2"
  "dense|dense.ini|"
  "dense-sticky|dense.ini|--set system.contact_rule=sticky"
  "dense-walls|dense.ini|--set system.boundary=walls --set field.type=cosine+tilt --set field.force=0.5 --set init.positions=even-dense.txt --set sample.bin_width=2"
  "dense-mixture|dense-mixture.ini|"
  "dense-mixture-walls|dense-mixture.ini|--set system.boundary=walls --set init.positions=even-dense-mix.txt --set sample.bin_width=2"
)
# runs config $2 (extra arguments after it) as case $1 on 1, 2 and 4 threads and compares
# every table and the physical results in summary.json
same_on_threads() {
    local name=$1 cfg=$2 t f same
    shift 2
    for t in 1 2 4; do
        "$HSBD" run "$cfg" "$@" --threads $t --quiet --out "$name-$t" || bad "$name: --threads $t failed"
    done
    for t in 2 4; do
        same=1
        for f in "$name-1"/*.tsv; do
            cmp -s "$f" "$name-$t/$(basename "$f")" || { same=0; bad "$name: $(basename "$f") differs on $t threads"; }
        done
        diff <(grep -v -E 'second|"threads(_used)?"|"dir"' "$name-1/summary.json") \
            <(grep -v -E 'second|"threads(_used)?"|"dir"' "$name-$t/summary.json") >/dev/null ||
            { same=0; bad "$name: summary.json differs on $t threads"; }
        [ $same -eq 1 ] && ok
    done
}

for c in "${cases[@]}"; do
    IFS='|' read -r name cfg extra <<<"$c"
    # shellcheck disable=SC2086
    same_on_threads "$name" "$cfg" $extra
done
# Spheres: 1, 2 and 4 threads give byte-identical tables (g(r), MSD, F_s, profiles) and
# summary.json: a fluid (its events through the global calendar, and group by group,
# whose first pass runs on threads; also with shells of 0.05 sigma), a mixture between
# walls with gravity, and active spheres; the two event orders give the same results. N 4000 is
# above the engine's threshold for threads (2048 particles).
cat >spheres.ini <<'INI'
[system]
model = spheres
dimension = 3
N = 4000
packing_fraction = 0.3
seed = 4
[run]
dt = 1e-3
t_equil = 0.02
t_total = 0.1
[sample]
gr_every = 10
blocks = 4
INI
cat >spheres-walls.ini <<'INI'
[system]
model = spheres
dimension = 3
N = 4000
box = 20 20 40
boundary = periodic periodic walls
seed = 5
[field]
type = tilt
axis = z
force = -0.5
[species]
names = A B
fraction = 0.5 0.5
sigma = 1 1.4
D = 1 0.714
coupling = 1 2.744
[run]
dt = 1e-3
t_equil = 0.02
t_total = 0.1
[sample]
blocks = 4
bin_width = 0.5
INI
# the groups give the global calendar's trajectories and statistics (contact times depend
# on the two paths alone, the virial is an exact sum): the same tables and summary.json
# of runs $1 and $2 but for the lines that name run.events
same_event_orders() {
    local f same=1
    for f in "$1"/*.tsv; do
        cmp -s <(grep -v 'run.events' "$f") <(grep -v 'run.events' "$2/$(basename "$f")") ||
            { same=0; bad "$1: $(basename "$f") differs between run.events = auto and groups"; }
    done
    diff <(grep -v -E 'second|"threads(_used)?"|"dir"|events' "$1/summary.json") \
        <(grep -v -E 'second|"threads(_used)?"|"dir"|events' "$2/summary.json") >/dev/null ||
        { same=0; bad "$1: summary.json differs between run.events = auto and groups"; }
    [ $same -eq 1 ] && ok
}
same_on_threads spheres spheres.ini
same_on_threads spheres-groups spheres.ini --set run.events=groups
same_event_orders spheres-1 spheres-groups-1
# shells far below the default (about 0.3 here): several shell moves per particle and
# step, pairs predicted at other moments in the two orders (their last bits differed
# before contact times came from the paths alone)
same_on_threads spheres-shell spheres.ini --set system.shell=0.05
same_on_threads spheres-shell-groups spheres.ini --set system.shell=0.05 --set run.events=groups
same_event_orders spheres-shell-1 spheres-shell-groups-1
same_on_threads spheres-walls spheres-walls.ini
# active particles: the propulsion, the exact rotation (3D, with rejections and, at
# D_r dt = 0.5, substeps) and the swim sum on threads; the event orders agree too
same_on_threads spheres-active spheres.ini --set active.v0=5 --set active.rotational_D=500
same_on_threads spheres-active-groups spheres.ini --set active.v0=5 --set active.rotational_D=500 --set run.events=groups
same_event_orders spheres-active-1 spheres-active-groups-1

echo "test_threads: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
