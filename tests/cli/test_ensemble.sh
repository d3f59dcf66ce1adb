#!/usr/bin/env bash
# Ensembles of replicas (docs/scaling.md): the merged result of R replicas has the same
# bytes whether the replicas ran in one process (run.replicas = R), on 2 MPI ranks
# (mpirun --oversubscribe -n 2, R = 2 by default and R = 3 spread unevenly) or one by one
# (hsbd run --replica K) and were joined with hsbd merge, for rods (fields, currents,
# clusters, MSD) and spheres (through the run layer). Each replica's own tables equal
# those of the replica run alone. hsbd merge refuses runs of another configuration, the
# same replica twice, a run that is no replica and a single directory (exit 2, nothing
# written). The mpirun cases are skipped with a message when hsbd has no MPI or mpirun
# is missing; CI installs both (scripts/install-deps).
set -u
HSBD=${1:?usage: test_ensemble.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

cat >rods.ini <<'INI'
[system]
N = 60
L = 60
seed = 5
[field]
type = cosine+tilt
amplitude = 4
force = 0.3
[run]
dt = 1e-3
t_equil = 0.2
t_total = 2
[sample]
bin_width = 0.05
blocks = 5
current_every = 0.1
INI
cat >spheres.ini <<'INI'
[system]
model = spheres
N = 200
packing_fraction = 0.3
seed = 8
[run]
dt = 1e-3
t_equil = 0.05
t_total = 0.5
[sample]
blocks = 5
INI

# the merged files of two ensemble directories agree byte for byte (summary.json apart
# from the line naming its own directory)
same_merged() { # same_merged WHAT DIR1 DIR2
    local what=$1 a=$2 b=$3 f n=0
    for f in "$a"/*.tsv; do
        n=$((n + 1))
        cmp -s "$f" "$b/$(basename "$f")" || { bad "$what: $(basename "$f") differs"; return; }
    done
    [ "$n" -ge 2 ] || { bad "$what: only $n tables in $a"; return; }
    if diff <(grep -v '"dir":' "$a/summary.json") <(grep -v '"dir":' "$b/summary.json") >/dev/null
    then ok; else bad "$what: summary.json differs"; fi
}

MPIRUN=()
if command -v mpirun >/dev/null && "$HSBD" version >/dev/null &&
    grep -q "mpirun -n P" <("$HSBD" run --help); then
    # OpenMPI's own allocations live until exit: LeakSanitizer (make asan) would report
    # them; hsbd's own leaks are checked by every case without mpirun (same code paths)
    MPIRUN=(env "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
        mpirun --oversubscribe -n 2)
    [ "$(id -u)" -eq 0 ] && MPIRUN+=(--allow-run-as-root)
fi

for model in rods spheres; do
    cfg=$model.ini
    # one process, R = 3 and R = 2
    "$HSBD" run "$cfg" --quiet --set run.replicas=3 --out $model-one3 || bad "$model: one process R=3"
    "$HSBD" run "$cfg" --quiet --set run.replicas=2 --out $model-one2 || bad "$model: one process R=2"
    # one by one, merged in another order than the replicas'
    for k in 2 0 1; do
        "$HSBD" run "$cfg" --quiet --replica $k --out $model-r$k || bad "$model: --replica $k"
    done
    "$HSBD" merge $model-merged3 $model-r2 $model-r0 $model-r1 || bad "$model: merge of 3"
    "$HSBD" merge $model-merged2 $model-r1 $model-r0 || bad "$model: merge of 2"
    same_merged "$model: one process vs hsbd merge (R=3)" $model-one3 $model-merged3
    same_merged "$model: one process vs hsbd merge (R=2)" $model-one2 $model-merged2
    # each replica's own tables are those of the replica run alone (headers apart from
    # run.replicas, the ensemble's size)
    for k in 0 1 2; do
        if diff <(grep -v '^# run.replicas' $model-one3/replica-$k/msd.tsv) \
            <(grep -v '^# run.replicas' $model-r$k/msd.tsv) >/dev/null; then ok
        else bad "$model: replica $k of the ensemble differs from --replica $k"; fi
    done
    # the replicas differ from each other (independent noise)
    if cmp -s $model-r0/msd.tsv $model-r1/msd.tsv; then bad "$model: replicas 0 and 1 equal"
    else ok; fi
    if [ ${#MPIRUN[@]} -gt 0 ]; then
        "${MPIRUN[@]}" "$HSBD" run "$cfg" --quiet --out $model-mpi2 >mpi.log 2>&1 ||
            { bad "$model: mpirun -n 2"; cat mpi.log >&2; }
        "${MPIRUN[@]}" "$HSBD" run "$cfg" --quiet --set run.replicas=3 --out $model-mpi3 \
            >mpi.log 2>&1 || { bad "$model: mpirun -n 2, R=3"; cat mpi.log >&2; }
        same_merged "$model: 2 ranks (R=2 by default) vs one process" $model-mpi2 $model-one2
        same_merged "$model: 2 ranks (R=3) vs one process" $model-mpi3 $model-one3
    fi
done
[ ${#MPIRUN[@]} -gt 0 ] || echo "test_ensemble: no MPI in this hsbd or no mpirun: the 2-rank cases are skipped" >&2

# an ensemble directory with a bad input leaves nothing behind
"$HSBD" run rods.ini --quiet --set run.replicas=2 --set init.positions=missing.txt \
    --out nothing 2>/dev/null
rc=$?
if [ $rc -eq 2 ] && [ ! -e nothing ]; then ok; else bad "bad input of an ensemble: exit $rc"; fi

# refusals of hsbd merge: exit 2, a message, nothing written
refused() { # refused WHAT PATTERN ARGS...
    local what=$1 pattern=$2
    shift 2
    "$HSBD" merge out-refused "$@" >/dev/null 2>err.txt
    local rc=$?
    if [ $rc -eq 2 ] && grep -q -- "$pattern" err.txt && [ ! -e out-refused ]; then ok
    else bad "merge refusal ($what): exit $rc, $(cat err.txt)"; fi
}
"$HSBD" run rods.ini --quiet --replica 1 --set system.N=61 --out rods-otherN || bad "other N"
"$HSBD" run rods.ini --quiet --replica 1 --seed 6 --out rods-otherseed || bad "other seed"
"$HSBD" run rods.ini --quiet --out rods-plain || bad "plain run"
refused "another N" 'system.N = 60 in the first, 61 in the second' rods-r0 rods-otherN
refused "another seed" 'system.seed = 5 in the first, 6 in the second' rods-r0 rods-otherseed
refused "another model" 'not replicas of one configuration' rods-r0 spheres-r1
refused "the same replica twice" 'both replica 1' rods-r1 rods-r0 rods-one3/replica-1
refused "no replica" 'no replica of an ensemble' rods-r0 rods-plain
refused "one directory" 'at least two' rods-r0
refused "no run directory" 'no readable summary.json' rods-r0 .

echo "test_ensemble: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
