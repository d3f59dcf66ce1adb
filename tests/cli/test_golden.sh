#!/usr/bin/env bash
# Results of fixed seeds stay the same: short runs of both models with every observer on
# (profiles, contacts, MSD, clusters, currents, trajectories, replicas, spatial blocks,
# g(r), F_s, mixtures, walls, sticky contacts, pair forces, drifts, XYZ input, active
# particles) are hashed (data lines of every table, trajectory frames, the physical results
# of summary.json) and compared with tests/golden/tables.sha256, recorded on this code's
# own output:
#   tests/cli/test_golden.sh build/hsbd --record
# A change of the numbers must be deliberate (a physics change, documented), never a side
# effect of restructuring. The noise and the field's sin use vectorised elementary
# functions when the CPU has AVX2 and FMA, so the hashes are recorded with the CPU
# features that matter; on a CPU without them the test says so and is skipped.
set -u
HSBD=${1:?usage: test_golden.sh path/to/hsbd [--record]}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
SRC=$(cd "$(dirname "$0")/../.." && pwd)
GOLD=$SRC/tests/golden/tables.sha256
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"

features=$(grep -o -w -E 'avx2|fma' /proc/cpuinfo 2>/dev/null | sort -u | tr '\n' ' ')
features=${features% }

R=(--quiet --set run.t_equil=0.05 --set sample.blocks=4)
# the flagship example as it was when the hashes were first recorded (the example's own
# settings may change; these runs must not)
cat >rc.ini <<'INI'
[system]
model = rods
N = 50
L = 100
sigma = 0.5
D = 1
kT = 1
seed = 1
[field]
type = cosine
amplitude = 6
wavelength = 1
[run]
dt = 1e-4
t_equil = 10
t_total = 400
[sample]
bin_width = 0.02
contact_width = 0.02
every = 10
blocks = 20
INI
cat >walls.ini <<'INI'
[system]
N = 30
L = 20
boundary = walls
seed = 9
[species]
names = A B
count = 20 10
sigma = 0.4 0.7
D = 1 0.5
[field]
type = cosine+tilt+harmonic
amplitude = 2
force = -0.4
stiffness = 0.01
[run]
dt = 1e-3
t_total = 2
[sample]
bin_width = 0.1
every = 5
current_every = 0.5
INI
awk 'BEGIN { for (i = 0; i < 40; ++i) printf "%.6f\n", 2.5 * i + 0.3 }' >pos.txt
printf 'particles = 40\nlength = 100\ndiameter = 0.5\nDiffusionConstant = 1.5\nAmpU = 4\nforce = 0.5\ntotaltime = 1\ntimestep = 1e-4\neqtime = 0.1\ndelta = 0.02\ndeltaPrime = 0.05\ntTrajectory = 0.5\ntCurrent = 0.25\ngamma = 0.5\n' >authors.cfg
cat >sph.ini <<'INI'
[system]
model = spheres
N = 300
packing_fraction = 0.3
seed = 4
[run]
dt = 1e-3
t_total = 0.6
[sample]
gr_every = 20
[output]
trajectory = xyz
trajectory_every = 0.2
INI
cat >disks.ini <<'INI'
[system]
model = spheres
dimension = 2
N = 400
packing_fraction = 0.4
seed = 6
[species]
names = big small wall
fraction = 0.45 0.45 0.1
sigma = 1.2 1 1
D = 0.8 1 0
[run]
dt = 1e-3
t_total = 0.5
[sample]
gr_every = 25
INI

# name, then hsbd arguments
cases=(
  "rods-cosine|run rc.ini --set run.t_total=2 --set output.trajectory=xyz --set output.trajectory_every=0.5 --set sample.current_every=0.5"
  "rods-sticky|run rc.ini --set run.t_total=1 --set system.contact_rule=sticky --set contact.gamma=1 --set run.dt=1e-5 --set sample.blocking=space --set sample.blocks=5 --set sample.every=20"
  "rods-walls-mixture|run walls.ini"
  "rods-replicas|run rc.ini --set system.N=40 --set run.t_total=2 --set sample.blocking=replicas --set init.positions=pos.txt --set run.dt=1e-3"
  "rods-yukawa|run rc.ini --set run.t_total=1 --set pair.type=yukawa --set pair.strength=2 --set pair.kappa=3"
  "rods-free|run rc.ini --set run.t_total=1 --set system.hard_core=off"
  "rods-authors|run authors.cfg"
  "spheres-3d|run sph.ini --set sample.fs_k=5"
  "spheres-disks-mixture|run disks.ini"
  "spheres-poly|run sph.ini --set system.packing_fraction=0.45 --set species.polydispersity=0.1 --set species.D_law=stokes-einstein --set init.method=compress --set output.trajectory=none"
  "spheres-drift|run sph.ini --set system.drift=0.5,0,-1 --set output.trajectory=none"
  "spheres-active-disks|run disks.ini --set active.v0=4,2,0 --set sample.local_density_every=10 --set output.trajectory=xyz --set output.trajectory_every=0.1"
  "spheres-active-3d|run sph.ini --set active.v0=3 --set active.rotational_D=0.5"
)

fingerprint() { # every result file of a run directory: one hash per file
    local dir=$1
    for f in "$dir"/*.tsv "$dir"/*.xyz; do
        [ -e "$f" ] || continue
        printf '%s %s\n' "$(grep -v '^#' "$f" | sha256sum | cut -c1-16)" "$(basename "$f")"
    done
    # summary.json: its lines without timings and the input files' checksums, as a set (the
    # order of the fields is free)
    printf '%s summary.json\n' "$(grep -v -E 'second|"git"|"version"|"dir"|checkpoint|resumes|threads_used|input_checksums' "$dir/summary.json" |
        sed 's/,$//' | sort | sha256sum | cut -c1-16)"
}

out=$T/got.sha256
echo "# cpu: $features" >"$out"
for c in "${cases[@]}"; do
    name=${c%%|*}
    args=${c#*|}
    # shellcheck disable=SC2086
    if ! "$HSBD" $args "${R[@]}" --out "$T/$name" 2>"$T/$name.err"; then
        echo "FAIL: $name did not run: $(cat "$T/$name.err")" >&2
        exit 1
    fi
    fingerprint "$T/$name" | sed "s/^/$name /" >>"$out"
done

if [ "${2:-}" = "--record" ]; then
    mkdir -p "$(dirname "$GOLD")"
    cp "$out" "$GOLD"
    echo "recorded $(grep -vc '^#' "$GOLD") hashes in $GOLD"
    exit 0
fi
if [ "$(head -1 "$GOLD")" != "# cpu: $features" ]; then
    echo "test_golden: skipped: hashes recorded on a CPU with '$(head -1 "$GOLD" | cut -c8-)', this one has '$features'"
    exit 0
fi
if diff "$GOLD" "$out" >"$T/diff"; then
    echo "test_golden: $(grep -vc '^#' "$GOLD") result files identical to the recorded ones"
else
    echo "FAIL: results differ from tests/golden/tables.sha256 (a deliberate change is recorded with --record):" >&2
    cat "$T/diff" >&2
    exit 1
fi
