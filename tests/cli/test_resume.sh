#!/usr/bin/env bash
# A run stopped any number of times at any moment (kill -9 included) and continued with
# `hsbd resume` ends with the same bytes as a run never stopped: every table, the
# trajectory, the currents and log.tsv, for both models with every observer on (profiles and
# contacts, MSD per species, clusters, replicas, spatial blocks, g(r), F_s, virial), and
# GSD trajectories, whose index is also written in place and moves as it grows (the
# gsd cases write enough frames for it to move several times).
# The kill moments are random (bash's RANDOM, seeded, over the run's wall time); each
# case is killed several times, once with SIGTERM (a graceful stop) and otherwise with
# SIGKILL, which may hit a checkpoint being written or a frame half-written.
# Also: a damaged newest checkpoint falls back to the previous one (and is never rotated
# over it), damaged or foreign checkpoints are refused with exit 2, a completed run is
# refused unless extended; an extension stopped before its first checkpoint or before its
# results, or by a signal on the way (the finished run's results stay), and a resume
# refused for a damaged stream, lose nothing; a run started with
# --force past the sticky step check resumes; --force replaces every output of a run; a
# directory another process writes is refused to a resume (also before the run's first
# checkpoint, named as in use) and to run --force; the first checkpoint comes after a
# tenth of output.checkpoint_wall (a run killed with -9 after it resumes), and a run killed
# before it is named as such; --threads may change on a resume; a shorter run.t_total and one that
# adds no step are refused, naming the least extension; a resume
# racing a starting run (its window opened by strace, which CI installs) takes the newest
# checkpoint or none.
set -u
HSBD=${1:?usage: test_resume.sh path/to/hsbd [model]}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
ONLY=${2:-}
# interruptions per case (HSBD_RESUME_KILLS; the sanitizer build sets 2)
KILLS=${HSBD_RESUME_KILLS:-5}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
RANDOM=2026

cat >rods.ini <<'INI'
[system]
N = 60
L = 60
sigma = 0.5
seed = 21
[field]
type = cosine+tilt
amplitude = 4
force = 0.3
[run]
dt = 1e-4
t_equil = 0.3
t_total = 6
[sample]
bin_width = 0.05
blocks = 6
every = 5
current_every = 0.25
[output]
trajectory = xyz
trajectory_every = 0.1
checkpoint_every = 0.05
INI
grep -v '^sigma' rods.ini >rodsmix.ini
cat >spheres.ini <<'INI'
[system]
model = spheres
N = 500
packing_fraction = 0.3
seed = 8
[species]
names = A B
fraction = 0.5 0.5
sigma = 1 1.3
D = 1 0.7
[run]
dt = 1e-3
t_equil = 0.2
t_total = 3
[sample]
gr_every = 10
blocks = 5
[output]
trajectory = xyz
trajectory_every = 0.1
checkpoint_every = 0.05
INI

# name|config|extra settings
cases=(
  "rods|rods.ini|"
  "rods-sticky-space|rods.ini|--set contact.gamma=1 --set run.dt=2e-5 --set run.t_total=1.5 --set sample.blocking=space --set sample.blocks=4 --set system.contact_rule=sticky"
  "rods-walls-mixture|rodsmix.ini|--set system.boundary=walls --set field.type=cosine+harmonic --set field.stiffness=0.01 --set species.names=A,B --set species.count=40,20 --set species.sigma=0.4,0.7 --set species.D=1,0.6 --set sample.period=60"
  "rods-replicas|rods.ini|--set sample.blocking=replicas --set run.t_equil=0.5 --set run.dt_equil=2e-4"
  "spheres|spheres.ini|"
  "spheres-2d-drift|spheres.ini|--set system.dimension=2 --set system.drift=0.3,-0.2 --set system.packing_fraction=0.4"
  "rods-gsd|rodsmix.ini|--set output.trajectory=gsd --set output.trajectory_every=0.01 --set species.names=A,B --set species.count=40,20 --set species.sigma=0.4,0.7 --set species.D=1,0.6"
  "spheres-gsd|spheres.ini|--set output.trajectory=gsd --set output.trajectory_every=0.01"
  "spheres-walls-gravity|spheres.ini|--set system.boundary=walls,periodic,walls --set field.type=tilt --set field.force=-0.5 --set species.coupling=1,2"
  "spheres-active-3d|spheres.ini|--set active.v0=4,1 --set active.rotational_D=2 --set run.t_total=1.5"
  "spheres-active-2d-gsd|spheres.ini|--set system.dimension=2 --set system.packing_fraction=0.5 --set active.v0=8 --set sample.local_density_every=20 --set output.trajectory=gsd --set output.trajectory_every=0.01 --set run.t_total=1.5"
)

run_killed() { # run_killed NAME CONFIG SETTINGS... : stopped at random moments, resumed to the end
    local name=$1 cfg=$2 wall=$3
    shift 3
    "$HSBD" run "$cfg" "$@" --quiet --out "$name" 2>/dev/null &
    local pid=$! kills=0 k term=$((KILLS < 3 ? KILLS : 3))
    for k in $(seq "$KILLS"); do
        # a moment in the first ~60 % of the run's wall time
        local ms=$((RANDOM % (wall * 6 / 10 + 1) + 30))
        sleep "$(awk -v ms="$ms" 'BEGIN { print ms / 1000 }')"
        if kill -0 $pid 2>/dev/null; then
            kill -s "$([ "$k" = "$term" ] && echo TERM || echo KILL)" $pid 2>/dev/null && kills=$((kills + 1))
        fi
        wait $pid 2>/dev/null
        [ -e "$name/checkpoint.hsbd" ] || [ -e "$name/checkpoint.prev.hsbd" ] || {
            "$HSBD" run "$cfg" "$@" --quiet --force --out "$name" 2>/dev/null & pid=$!; continue; }
        "$HSBD" resume "$name" --quiet 2>/dev/null &
        pid=$!
    done
    wait $pid 2>/dev/null
    # whatever is left: resumed to the end
    if ! grep -q '"completed": true' "$name/summary.json" 2>/dev/null; then
        "$HSBD" resume "$name" --quiet 2>"$name.err" || echo "resume: $(cat "$name.err")" >&2
    fi
    echo "$kills"
}

for c in "${cases[@]}"; do
    IFS='|' read -r name cfg extra <<<"$c"
    case "$name" in "$ONLY"*) ;; *) continue ;; esac
    # shellcheck disable=SC2086
    start=$(date +%s%N)
    "$HSBD" run "$cfg" $extra --quiet --out "$name-ref" 2>/dev/null || { bad "$name: reference run"; continue; }
    wall=$((($(date +%s%N) - start) / 1000000))
    # shellcheck disable=SC2086
    kills=$(run_killed "$name" "$cfg" "$wall" $extra)
    same=1
    for f in "$name-ref"/*.tsv "$name-ref"/*.xyz "$name-ref"/*.gsd; do
        [ -e "$f" ] || continue
        if ! cmp -s "$f" "$name/$(basename "$f")"; then
            same=0
            echo "$name: $(basename "$f") differs" >&2
        fi
    done
    if [ $same = 1 ] && grep -q '"completed": true' "$name/summary.json"; then
        ok
        echo "  $name: identical after $kills interruptions ($wall ms run)"
    else bad "$name: the resumed results differ ($kills interruptions)"; fi
done

if [ -z "$ONLY" ] || [ "$ONLY" = rods ]; then
    # a completed run: refused, unless extended
    "$HSBD" resume rods-ref --quiet 2>err
    if [ $? = 2 ] && grep -q "is complete" err; then ok; else bad "completed run: $(cat err)"; fi
    # a run.t_total that rounds to the same number of steps is no extension: the message
    # names the least T that is one, and that T extends the run by one step
    "$HSBD" resume rods-ref --set run.t_total=6.00004 --quiet 2>err
    if [ $? = 2 ] && grep -q "is complete (60000 of 60000 steps); to extend it: --set run.t_total=T with T >= 6.0001" err
    then ok; else bad "an extension by less than a step: $(cat err)"; fi
    cp -r rods-ref plus1
    if "$HSBD" resume plus1 --set run.t_total=6.0001 --quiet 2>err && grep -q '"steps": 60001' plus1/summary.json
    then ok; else bad "an extension by one step: $(cat err)"; fi
    # a shorter run.t_total cuts nothing: refused, naming the run's own
    "$HSBD" resume rods-ref --set run.t_total=3 --quiet 2>err
    if [ $? = 2 ] && grep -q "run.t_total=3 is shorter than the run's own 6; allowed: run.t_total >= 6" err
    then ok; else bad "a shorter run.t_total: $(cat err)"; fi
    # a run stopped after its final checkpoint but before its results were all written
    # (kill -9 in that window): resuming writes them, the same bytes
    cp -r rods-ref late
    rm late/summary.json late/density.tsv && mv late/trajectory.xyz late/trajectory.xyz.part
    if "$HSBD" resume late --quiet 2>err && cmp -s late/density.tsv rods-ref/density.tsv &&
        cmp -s late/trajectory.xyz rods-ref/trajectory.xyz && grep -q '"completed": true' late/summary.json
    then ok; else bad "results after the final checkpoint: $(cat err)"; fi
    # a damaged newest checkpoint: the previous one is used (with a warning)
    "$HSBD" run rods.ini --quiet --set run.t_total=2 --out dmg 2>/dev/null &
    pid=$!
    for _ in $(seq 100); do [ -s dmg/checkpoint.prev.hsbd ] && break; sleep 0.05; done
    kill -9 $pid; wait $pid 2>/dev/null
    printf 'XXXX' | dd of=dmg/checkpoint.hsbd bs=1 seek=200 conv=notrunc 2>/dev/null
    if "$HSBD" resume dmg --quiet 2>err && grep -q "checkpoint.prev.hsbd" err &&
        grep -q '"completed": true' dmg/summary.json; then ok; else bad "damaged newest: $(cat err)"; fi
    # both damaged, truncated, foreign, empty: exit 2 with a message, never a crash
    for what in truncate garbage empty; do
        rm -rf hostile && cp -r dmg hostile
        case $what in
            truncate) truncate -s 1000 hostile/checkpoint.hsbd; cp hostile/checkpoint.hsbd hostile/checkpoint.prev.hsbd ;;
            garbage) head -c 5000 /dev/urandom >hostile/checkpoint.hsbd; cp hostile/checkpoint.hsbd hostile/checkpoint.prev.hsbd ;;
            empty) : >hostile/checkpoint.hsbd; rm -f hostile/checkpoint.prev.hsbd ;;
        esac
        "$HSBD" resume hostile --quiet 2>err
        rc=$?
        if [ $rc = 2 ] && grep -q "no usable checkpoint" err; then ok; else bad "$what checkpoint: exit $rc $(cat err)"; fi
    done
    "$HSBD" resume nowhere --quiet 2>err
    if [ $? = 2 ] && grep -q "nowhere" err; then ok; else bad "missing directory: $(cat err)"; fi
    # taking checkpoints never changes the results, not even the tables' bytes
    "$HSBD" run rods.ini --quiet --set run.t_total=1 --set output.checkpoints=off --out ck-off 2>/dev/null
    "$HSBD" run rods.ini --quiet --set run.t_total=1 --set output.checkpoint_every=1e-4 --out ck-all 2>/dev/null
    "$HSBD" run spheres.ini --quiet --set run.t_total=0.5 --set output.checkpoint_every=1e-3 --out cks-all \
        --set output.trajectory=gsd --set output.trajectory_every=1e-3 2>/dev/null
    "$HSBD" run spheres.ini --quiet --set run.t_total=0.5 --set output.checkpoints=off --out cks-off \
        --set output.trajectory=gsd --set output.trajectory_every=1e-3 2>/dev/null
    same=1
    for f in ck-off/*.tsv ck-off/*.xyz cks-off/*.tsv cks-off/*.gsd; do
        g=${f/ck-off/ck-all}; g=${g/cks-off/cks-all}
        cmp -s "$f" "$g" || { same=0; echo "checkpoints changed $f" >&2; }
    done
    if [ $same = 1 ] && [ -s ck-all/checkpoint.prev.hsbd ] && [ ! -e ck-off/checkpoint.hsbd ]; then ok; else
        bad "checkpoints every step changed the results"; fi
    # an extension: the run goes on to the longer time; the trajectory, currents, log and
    # MSD are those of a run planned that long (with the lag grid and the frame and log
    # intervals the first run derived from its own length), the means too; the error
    # blocks keep their length, so there are twice as many
    "$HSBD" run rods.ini --quiet --set run.t_total=1 --out ext 2>/dev/null
    cp -r ext ext-1
    "$HSBD" run rods.ini --quiet --set run.t_total=2 --set sample.msd_max_lag=0.1 \
        --set output.trajectory_every=0.1 --set output.log_every=1e-3 --out ext-ref 2>/dev/null
    if "$HSBD" resume ext --set "run.t_total = 2" --quiet 2>err && cmp -s ext/trajectory.xyz ext-ref/trajectory.xyz &&
        cmp -s ext/msd.tsv ext-ref/msd.tsv &&
        diff -q <(grep -v '^#' ext/current.tsv) <(grep -v '^#' ext-ref/current.tsv) >/dev/null &&
        diff -q <(grep -v '^#' ext/log.tsv) <(grep -v '^#' ext-ref/log.tsv) >/dev/null &&
        diff -q <(grep -v '^#' ext/density.tsv | cut -f1,2) <(grep -v '^#' ext-ref/density.tsv | cut -f1,2) >/dev/null &&
        [ "$(grep -v '^#' ext/density_blocks.tsv | head -1 | wc -w)" = 13 ] &&
        grep -q '"steps": 20000' ext/summary.json; then ok; else bad "extension: $(cat err)"; fi
    # the same for a GSD trajectory: its index moves as the extension grows it, as in a run
    # planned that long
    "$HSBD" run rods.ini --quiet --set run.t_total=1 --set output.trajectory=gsd \
        --set output.trajectory_every=2e-3 --out extg 2>/dev/null
    "$HSBD" run rods.ini --quiet --set run.t_total=2 --set sample.msd_max_lag=0.1 --set output.trajectory=gsd \
        --set output.trajectory_every=2e-3 --out extg-ref 2>/dev/null
    if "$HSBD" resume extg --set run.t_total=2 --quiet 2>err && [ -s extg-ref/trajectory.gsd ] &&
        cmp -s extg/trajectory.gsd extg-ref/trajectory.gsd; then ok; else bad "GSD extension: $(cat err)"; fi
    "$HSBD" run rods.ini --quiet --set run.t_total=1 --set sample.blocking=replicas --out extrep 2>/dev/null
    "$HSBD" resume extrep --set run.t_total=2 --quiet 2>err
    if [ $? = 2 ] && grep -q "replicas" err; then ok; else bad "extending replicas: $(cat err)"; fi
    # threads are no extension: such a run resumes with other threads (here: it is complete)
    "$HSBD" resume extrep --threads 1 --quiet 2>err
    if [ $? = 2 ] && grep -q "is complete" err; then ok; else bad "replicas, --threads: $(cat err)"; fi
    "$HSBD" resume dmg --set system.N=10 --quiet 2>err
    if [ $? = 2 ] && grep -q "run.t_total" err; then ok; else bad "resume --set other key: $(cat err)"; fi
    # the two keys an extension keeps for itself are not the user's to set
    cp -r ext-1 kept && "$HSBD" resume kept --set run.t_total=2 --set output.trajectory_every=0.5 --quiet 2>err
    if [ $? = 2 ] && grep -q "output.trajectory_every" err; then ok; else bad "resume --set kept key: $(cat err)"; fi
    # an extension stopped after its final checkpoint but before its results (the summary
    # still the first run's): resuming writes the extension's results
    cp -r ext late-ext && cp ext-1/summary.json late-ext/ && rm late-ext/density.tsv &&
        mv late-ext/trajectory.xyz late-ext/trajectory.xyz.part
    if "$HSBD" resume late-ext --quiet 2>err && cmp -s late-ext/trajectory.xyz ext/trajectory.xyz &&
        cmp -s late-ext/density.tsv ext/density.tsv && grep -q '"steps": 20000' late-ext/summary.json
    then ok; else bad "extension's results after its final checkpoint: $(cat err)"; fi
    # an extension stopped by a signal on the way leaves the finished run's results as they
    # were (its streams under their temporary names); resumed, it ends with the bytes of the
    # extension never stopped
    cp -r ext-1 ext-whole && cp -r ext-1 ext-stop
    "$HSBD" resume ext-whole --set run.t_total=12 --quiet 2>/dev/null || bad "extension to 12"
    "$HSBD" resume ext-stop --set run.t_total=12 --quiet 2>err &
    ext_pid=$!
    for _ in $(seq 1500); do ls ext-stop/*.part >/dev/null 2>&1 && break; sleep 0.02; done
    kill -TERM $ext_pid # once the extension writes (its streams' temporary names)
    wait $ext_pid
    rc=$?
    kept=1
    for f in ext-1/*; do
        [ -e "ext-stop/${f#ext-1/}" ] || [ -e "ext-stop/${f#ext-1/}.part" ] || kept=0
        [ ! -e "ext-stop/${f#ext-1/}" ] || cmp -s "$f" "ext-stop/${f#ext-1/}" ||
            case $f in */checkpoint*) ;; *) kept=0 ;; esac
    done
    if [ $rc = 143 ] && [ $kept = 1 ] && grep -q "finished run's results in '.*ext-stop' stay as they were" err
    then ok; else bad "an extension stopped by SIGTERM: exit $rc, kept $kept, $(cat err)"; fi
    same=1
    "$HSBD" resume ext-stop --quiet 2>err || same=0
    for f in ext-whole/*.tsv ext-whole/trajectory.xyz; do
        cmp -s "$f" "ext-stop/${f#ext-whole/}" || same=0
    done
    if [ $same = 1 ]; then ok; else bad "an extension stopped, then resumed: $(cat err)"; fi
    # an extension stopped before its first checkpoint: the completed run is refused again,
    # with its streams back under their names and at their lengths
    cp -r ext-1 early-ext && mv early-ext/trajectory.xyz early-ext/trajectory.xyz.part &&
        mv early-ext/current.tsv early-ext/current.tsv.part &&
        head -c 5000 ext/trajectory.xyz >>early-ext/trajectory.xyz.part && echo "1.5 0 0" >>early-ext/current.tsv.part
    "$HSBD" resume early-ext --quiet 2>err
    if [ $? = 2 ] && grep -q "is complete" err && cmp -s early-ext/trajectory.xyz ext-1/trajectory.xyz &&
        cmp -s early-ext/current.tsv ext-1/current.tsv && ! ls early-ext/*.part >/dev/null 2>&1
    then ok; else bad "extension stopped before its first checkpoint: $(cat err)"; fi
    # a resume refused because a stream file is missing touches no file: every stream is
    # checked before any is renamed or cut back (an extension, and a finished run's restore)
    "$HSBD" run rods.ini --quiet --set run.t_total=0.5 --set output.trajectory=gsd --out refused 2>/dev/null
    mv refused/current.tsv refused-current.tsv
    cp refused/trajectory.gsd refused-trajectory.gsd
    "$HSBD" resume refused --set run.t_total=1 --quiet 2>err
    rc=$?
    "$HSBD" resume refused --quiet 2>>err
    rc2=$?
    if [ $rc = 2 ] && [ $rc2 = 2 ] && grep -q "current.tsv" err && cmp -s refused/trajectory.gsd refused-trajectory.gsd &&
        [ ! -e refused/trajectory.gsd.part ]; then ok; else bad "refused resume: $(cat err); $(ls refused)"; fi
    # after falling back to checkpoint.prev.hsbd the damaged newest is never rotated over it
    "$HSBD" run rods.ini --quiet --set run.t_total=1 --set output.checkpoint_every=0.5 --out fb 2>/dev/null
    printf 'XXXX' | dd of=fb/checkpoint.hsbd bs=1 seek=200 conv=notrunc 2>/dev/null
    cp fb/checkpoint.hsbd fb-damaged.hsbd
    if "$HSBD" resume fb --quiet 2>err && ! cmp -s fb/checkpoint.prev.hsbd fb-damaged.hsbd &&
        "$HSBD" resume fb --set run.t_total=1.5 --quiet 2>err; then ok; else bad "fall-back rotation: $(cat err)"; fi
    # a run started with --force past the sticky step check resumes (and extends)
    "$HSBD" run rods.ini --quiet --force --set contact.gamma=1 --set run.dt=1e-3 --set run.t_total=0.5 \
        --set run.t_equil=0.1 --out sticky-force 2>/dev/null
    if "$HSBD" resume sticky-force --set run.t_total=1 --quiet 2>err; then ok; else bad "resume after --force: $(cat err)"; fi
fi

if [ -z "$ONLY" ] || [ "$ONLY" = spheres ]; then
    # --force replaces every file a run wrote, the density profiles between walls included
    walls="--set system.boundary=walls,periodic,walls --set field.type=tilt --set field.force=-0.5 --set species.coupling=1,2 --set run.t_total=0.1 --set run.t_equil=0"
    "$HSBD" run spheres.ini --quiet $walls --out sw 2>/dev/null
    if "$HSBD" run spheres.ini --quiet $walls --out sw --force 2>err; then ok; else bad "--force over walls outputs: $(cat err)"; fi
fi

# one process writes a run directory at a time: while another holds it (the lock a run or
# a resume takes, here held by flock(1)), hsbd resume and hsbd run --force are refused
# with exit 2 and change nothing; once it is free the run extends as before
if [ -z "$ONLY" ] || [ "$ONLY" = rods ]; then
    "$HSBD" run rods.ini --quiet --set run.t_total=0.5 --out locked || bad "run to lock"
    before=$(ls -A locked; cat locked/* | sha256sum)
    flock -o locked/.hsbd.lock sleep 60 & # -o: the lock stays with flock, not with sleep
    holder=$!
    while flock -n locked/.hsbd.lock true; do sleep 0.05; done
    "$HSBD" resume locked --quiet --set run.t_total=1 2>err
    rc=$?
    "$HSBD" run rods.ini --quiet --force --out locked 2>err2
    rc2=$?
    if [ $rc -eq 2 ] && [ $rc2 -eq 2 ] && grep -q "is in use" err && grep -q "is in use" err2 &&
        [ "$(ls -A locked; cat locked/* | sha256sum)" = "$before" ]; then ok
    else bad "a directory in use: exit $rc and $rc2, $(cat err err2)"; fi
    # a run that has not reached its first checkpoint: "in use", not "no checkpoint"
    mkdir starting && : >starting/.hsbd.lock
    flock -o starting/.hsbd.lock sleep 60 &
    starter=$!
    while flock -n starting/.hsbd.lock true; do sleep 0.05; done
    "$HSBD" resume starting --quiet 2>err
    if [ $? -eq 2 ] && grep -q "is in use.*(it has no checkpoint yet)" err; then ok
    else bad "resume of a run before its first checkpoint: $(cat err)"; fi
    pkill -P $starter sleep
    wait $starter 2>/dev/null
    # the first checkpoint comes after a tenth of output.checkpoint_wall (here 1 s of 10),
    # not a whole interval: a run killed with -9 after it resumes (here stopped by SIGTERM
    # once the resumed run has written its own first checkpoint, whatever the machine's
    # load: the summary then records the resume); killed before it, the message says why
    "$HSBD" run rods.ini --quiet --set run.t_total=1e4 --set output.checkpoint_every=0 \
        --set output.checkpoint_wall=10 --out early 2>/dev/null &
    early=$!
    for _ in $(seq 150); do [ -e early/checkpoint.hsbd ] && break; sleep 0.1; done
    kill -9 $early 2>/dev/null
    wait $early 2>/dev/null
    if [ -e early/checkpoint.hsbd ]; then
        touch early.killed
        "$HSBD" resume early --quiet 2>/dev/null &
        resumed=$!
        for _ in $(seq 300); do [ early/checkpoint.hsbd -nt early.killed ] && break; sleep 0.1; done
        kill -TERM $resumed
        wait $resumed 2>/dev/null
        if grep -q '^  "resumes": 1,$' early/summary.json; then ok
        else bad "resume after kill -9 past the first checkpoint: $(cat early/summary.json 2>&1)"; fi
    else bad "no checkpoint within 15 s with output.checkpoint_wall = 10"; fi
    "$HSBD" run rods.ini --quiet --set run.t_total=1e4 --set output.checkpoint_every=0 \
        --out killed0 2>/dev/null &
    killed=$!
    while [ ! -e killed0/.hsbd.lock ]; do sleep 0.02; done
    kill -9 $killed
    wait $killed 2>/dev/null
    "$HSBD" resume killed0 --quiet 2>err
    if [ $? -eq 2 ] && grep -q "stopped before its first one.*run it again" err; then ok
    else bad "resume of a run killed before its first checkpoint: $(cat err)"; fi
    pkill -P $holder sleep
    wait $holder 2>/dev/null
    if "$HSBD" resume locked --quiet --set run.t_total=1 2>err; then ok
    else bad "resume once the directory is free: $(cat err)"; fi
    # a run directory that lost its lock file and holds a file of the user's gets one again
    rm locked/.hsbd.lock && echo notes >locked/notes.txt
    "$HSBD" resume locked --quiet --set run.t_total=1.5 2>err || bad "resume beside notes: $(cat err)"
    [ -f locked/.hsbd.lock ] && ok || bad "resume beside a user's file took no lock"
    # threads may change on a resume (they change no result); a bad count is refused
    if "$HSBD" resume locked --quiet --threads 1 --set run.t_total=2 2>err &&
        grep -q '"threads_used": 1,' locked/summary.json; then ok
    else bad "resume --threads 1: $(cat err)"; fi
    "$HSBD" resume locked --quiet --threads 2000 --set run.t_total=2.5 2>err
    if [ $? -eq 2 ] && grep -q "allowed: 0 <= threads <= 1024" err; then ok
    else bad "resume --threads 2000: $(cat err)"; fi
fi

# a resume that finds no checkpoint at first and the run's first one by the time it loads
# (strace(1) delays its test and its claim, while a run starts and ends in the directory):
# it claims the directory after the load and reads the newest checkpoint again, so it
# finds the run complete instead of resuming an older checkpoint of it
if { [ -z "$ONLY" ] || [ "$ONLY" = rods ]; } && command -v strace >/dev/null &&
    strace -o /dev/null true 2>/dev/null; then
    race_run() { # $1 directory, $2 t_total: checkpoints from its start on
        "$HSBD" run rods.ini --quiet --set run.t_total="$2" \
            --set output.checkpoint_every="$(awk -v t="$2" 'BEGIN { print t / 30 }')" \
            --out "$1" || bad "run into $1"
    }
    seconds_of() { # $1 t_total: the wall seconds of such a run in this build
        start=$(date +%s.%N)
        race_run race-probe-"$1" "$1"
        awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { print e - s }'
    }
    # a run of about 1.8 s in this build (its start-up and its rate measured): going when
    # the resume loads (1 s after the resume's start, 0.7 s after the run's), over when it
    # claims (1.5 s after the run's end)
    short=$(seconds_of 2)
    long=$(seconds_of 8)
    t_total=$(awk -v a="$short" -v b="$long" 'BEGIN {
        r = (b - a) / 6; s = a - 2 * r; t = r > 0 ? (1.8 - s) / r : 8; print t < 8 ? 8 : t }')
    claim_delay=$(awk -v a="$short" -v b="$long" -v t="$t_total" 'BEGIN {
        r = (b - a) / 6; print int(1e6 * (a + (t - 2) * r + 1.5)) }')
    mkdir race
    # LeakSanitizer cannot work under ptrace: off for the traced resume (make asan)
    env "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
        strace -o /dev/null -f -P race/checkpoint.prev.hsbd -P race/.hsbd.lock \
        -e inject=newfstatat:delay_exit=1000000 -e inject=openat:delay_exit="$claim_delay" \
        "$HSBD" resume race --quiet 2>err &
    resume=$!
    sleep 0.3 # the resume has found no checkpoint and waits in its second test
    race_run race "$t_total"
    wait $resume
    rc=$?
    if [ $rc -eq 2 ] && grep -q "is complete" err && grep -q '^  "resumes": 0,$' race/summary.json
    then ok; else bad "a resume racing a run's first checkpoint: exit $rc, $(cat err)"; fi
else
    echo "test_resume: strace missing or not allowed here: the race of a resume with a starting run is not tested"
fi

echo "test_resume: $pass passed, $fail failed"
[ $fail -eq 0 ]
