#!/usr/bin/env bash
# Ensembles of replicas (docs/scaling.md): the merged result of R replicas has the same
# bytes whether the replicas ran in one process (run.replicas = R), on 2 MPI ranks
# (mpirun --oversubscribe -n 2, R = 2 by default and R = 3 spread unevenly) or one by one
# (hsbd run --replica K) and were joined with hsbd merge, for rods (fields, currents,
# clusters, MSD) and spheres (through the run layer). Each replica's own tables equal
# those of the replica run alone. hsbd merge refuses runs of another configuration or of
# another content of an input file, the same replica twice, a run that is no replica, a
# single directory, an unfinished replica, a table that one replica lacks, a cell that is
# no number, a table cut short, an OUT too long (exit 2, nothing written), and an OUT
# holding a run, a replica, an ensemble or (with --force) a run's directory, even with
# --force (OUT forgotten: the message shows the line with a new OUT; --force replaces an
# earlier merge's result only); a table of more than 64 columns merges whole; a summary
# edited by hand merges into valid JSON. An ensemble replaces no earlier results, with or
# without --force (an earlier ensemble or a single run stays as it was); an ensemble's own
# merge that fails leaves no merged file. Under mpirun rank 0 reads and checks the input
# and shares it (another command line on rank 1 is never read; a configuration on the
# standard input runs): a bad input or a directory rank 0 refuses is one message and exit
# 2 on every rank, with nothing written; a replica refused on rank 1 only is one message
# naming the rank, exit 2 and no merge; --help is printed once; a single run, hsbd resume
# and hsbd merge run on rank 0 only; by default the working ranks of a node share its CPUs
# out. A directory another process writes is refused to an ensemble and to merge (reading
# or writing it), as is a lock file that is a link or a FIFO; a directory of other files
# gets no lock file. Merge refuses replicas of different builds, a replica index or a cell
# that is no number as hsbd writes them (nan merges), and a file that is no regular file.
# A merge that meets a full disk leaves nothing. The time step's warnings are printed once
# per ensemble (one process or two ranks) and listed, each once, in the merged summary.
# The mpirun cases are skipped with a message when hsbd has no MPI or mpirun is missing;
# CI installs both (scripts/install-deps).
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
if command -v mpirun >/dev/null && "$HSBD" version | grep -q "built with: mpi"; then
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

# a time step the scheme warns about: each warning printed once for the whole ensemble
# (in one process and on 2 ranks), and the merged summary.json lists the replicas'
# warnings, each distinct text once, as hsbd merge of the same replicas does
coarse=(--quiet --set run.dt=0.02 --set run.t_equil=0.1 --set run.t_total=1 --set run.replicas=3)
warned_once() { # warned_once WHAT LOG DIR
    local what=$1 log=$2 dir=$3 n
    n=$(grep -c "warning: the mean step is .* of a particle's diameter" "$log")
    # Scala Eqs. 6 and 3, the collision rate, D_L's time-step error: four in all
    if [ "$n" -eq 1 ] && [ "$(grep -c 'warning:' "$log")" -eq 4 ] &&
        python3 -c "import json, sys
w = json.load(open('$dir/summary.json'))['warnings']
r = [x for k in range(3) for x in json.load(open('$dir/replica-%d/summary.json' % k))['warnings']]
s = json.load(open('$dir/summary.json'))
sys.exit(not (w == list(dict.fromkeys(r)) and len(w) >= 4 and len(s['box']) == 3))"
    then ok; else bad "$what: warnings $n times, $(cat "$log")"; fi
}
"$HSBD" run spheres.ini "${coarse[@]}" --out warned 2>warn.log || bad "coarse ensemble"
warned_once "one process" warn.log warned
if [ ${#MPIRUN[@]} -gt 0 ]; then
    "${MPIRUN[@]}" "$HSBD" run spheres.ini "${coarse[@]}" --out warned-mpi >/dev/null 2>warn.log ||
        bad "coarse ensemble, mpirun"
    warned_once "mpirun -n 2" warn.log warned-mpi
fi
# a replica's summary.json whose warnings line is cut inside a string and whose box is no
# JSON (edited by hand): its warnings are left out, and the box (which all share otherwise);
# the merged summary.json is still JSON, with the others' warnings
cp -r warned/replica-1 warned-hand
sed -i 's/^  "warnings": .*/  "warnings": ["kept", "cut \\/' warned-hand/summary.json
sed -i 's/^  "box": .*/  "box": [1, {"x": 2],/' warned-hand/summary.json
"$HSBD" merge warned-merged warned/replica-0 warned-hand warned/replica-2 2>err.txt
if [ $? -eq 0 ] && python3 -c "import json, sys
s = json.load(open('warned-merged/summary.json'))
sys.exit('kept' in s['warnings'] or len(s['warnings']) < 3 or 'box' in s)"; then ok
else bad "merge of a hand-written warnings line: $(cat err.txt)"; fi

# an ensemble directory with a bad input leaves nothing behind
"$HSBD" run rods.ini --quiet --set run.replicas=2 --set init.positions=missing.txt \
    --out nothing 2>/dev/null
rc=$?
if [ $rc -eq 2 ] && [ ! -e nothing ]; then ok; else bad "bad input of an ensemble: exit $rc"; fi
"$HSBD" run rods.ini --quiet --set run.replicas=2 --set init.positions=missing.txt \
    --out nothing2/sub 2>/dev/null
rc=$?
if [ $rc -eq 2 ] && [ ! -e nothing2 ]; then ok; else bad "bad input of a nested ensemble: exit $rc"; fi

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
"$HSBD" run rods.ini --quiet --replica 1 --set system.N=61 --seed 6 --out rods-othertwo ||
    bad "other N and seed"
"$HSBD" run rods.ini --quiet --out rods-plain || bad "plain run"
# damaged or unfinished replicas
cp -r rods-r1 rods-stopped && rm rods-stopped/summary.json
cp -r rods-r0 rods-nomsd && rm rods-nomsd/msd.tsv
cp -r rods-r0 rods-part && mv rods-part/current.tsv rods-part/current.tsv.part
cp -r rods-r1 rods-garbage && awk -F'\t' -v OFS='\t' '!/^#/ && ++n == 3 {$2 = "garbage"} 1' \
    rods-r1/msd.tsv >rods-garbage/msd.tsv
cp -r rods-r1 rods-cut && head -c -2 rods-r1/msd.tsv >rods-cut/msd.tsv
# the same configuration reading two contents of one field table
table() { awk -v a="$1" 'BEGIN { for (i = 0; i <= 600; i++) printf "%.1f %.10g\n", i / 10, a / 2 * cos(2 * 3.14159265358979 * i / 10) }'; }
table 4 >pot.txt
"$HSBD" run rods.ini --quiet --replica 0 --set field.type=table --set field.table=pot.txt \
    --out rods-t0 || bad "table field, replica 0"
table 8 >pot.txt
"$HSBD" run rods.ini --quiet --replica 1 --set field.type=table --set field.table=pot.txt \
    --out rods-t1 || bad "table field, replica 1"
refused "another N" 'system.N = 60 in the first, 61 in the second' rods-r0 rods-otherN
refused "another seed" 'system.seed = 5 in the first, 6 in the second' rods-r0 rods-otherseed
refused "two others" 'system.N = 60 in the first, 61 in the second;' rods-r0 \
    rods-othertwo
refused "another model" 'not replicas of one configuration' rods-r0 spheres-r1
refused "the same replica twice" 'both replica 1' rods-r1 rods-r0 rods-one3/replica-1

# an ensemble completed in its own directory (hsbd merge DIR): one whose replica 2 never
# began and whose merge never ran is refused until that replica is run alone, then merges
# into the same bytes as the ensemble run whole; merging DIR's replicas into DIR by name is
# refused with the hint, and hsbd resume DIR names the replicas
mkdir rods-stopped3 && cp -r rods-one3/replica-0 rods-one3/replica-1 rods-stopped3/
"$HSBD" merge rods-stopped3 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "lacks replica 2 of its 3 (it never began); run it alone first: hsbd run CONFIG --replica 2 --set run.replicas=3 --out rods-stopped3/replica-2" err.txt &&
    [ ! -e rods-stopped3/summary.json ]
then ok; else bad "merge DIR, replica 2 missing: exit $rc, $(cat err.txt)"; fi
"$HSBD" resume rods-stopped3 2>err.txt
if [ $? -eq 2 ] && grep -q "is an ensemble's directory, whose replicas hold the checkpoints" err.txt
then ok; else bad "resume of an ensemble's directory: $(cat err.txt)"; fi
"$HSBD" run rods.ini --quiet --replica 2 --set run.replicas=3 --out rods-stopped3/replica-2 ||
    bad "the missing replica run alone"
"$HSBD" merge rods-stopped3 rods-stopped3/replica-0 rods-stopped3/replica-1 2>err.txt
if [ $? -eq 2 ] && grep -q "or merge its replicas into it: hsbd merge rods-stopped3$" err.txt
then ok; else bad "merge DIR DIR/replica-K: $(cat err.txt)"; fi
if "$HSBD" merge rods-stopped3; then
    same_merged "an ensemble completed with hsbd merge DIR" rods-stopped3 rods-one3
else bad "merge DIR of a whole ensemble"; fi
# hsbd merge DIR refuses: a DIR that holds a run of its own beside replica directories, a
# replica that is a link, a single replica, and a gap in the replicas of an ensemble whose
# size is not recorded (run.replicas = 0: the ranks of mpirun); a finished ensemble merges
# again into the same bytes
merge_dir_refused() { # merge_dir_refused WHAT PATTERN DIR
    "$HSBD" merge "$3" 2>err.txt
    local rc=$?
    if [ $rc -eq 2 ] && grep -q -- "$2" err.txt; then ok
    else bad "merge DIR ($1): exit $rc, $(cat err.txt)"; fi
}
cp -r rods-plain own-run && cp -r rods-one3/replica-0 rods-one3/replica-1 own-run/
merge_dir_refused "a run of its own" "holds the results of a run of its own" own-run
mkdir linked && cp -r rods-one3/replica-1 linked/ && ln -s "$PWD/rods-one3/replica-0" linked/replica-0
merge_dir_refused "a replica that is a link (none)" "holds 1 replica-K directories" linked
mkdir single && cp -r rods-r0 single/replica-0
merge_dir_refused "one replica" "holds 1 replica-K directories" single
mkdir gap && cp -r rods-r0 gap/replica-0 && cp -r rods-r2 gap/replica-2
merge_dir_refused "a gap" "lacks replica 1 of its 3" gap
cp -r rods-one3 again
if "$HSBD" merge again; then same_merged "a finished ensemble merged again" again rods-one3
else bad "merge DIR of a finished ensemble"; fi
# the merged blocks tables name each column by its replica
"$HSBD" merge rods-merged20 rods-r2 rods-r0 || bad "merge of replicas 2 and 0"
if grep -q "^# x	replica_0	replica_2$" rods-merged20/density_blocks.tsv; then ok
else bad "blocks columns: $(grep "^# x" rods-merged20/density_blocks.tsv)"; fi
mkdir no-replicas && "$HSBD" merge no-replicas 2>err.txt
if [ $? -eq 2 ] && grep -q "holds 0 replica-K directories" err.txt; then ok
else bad "merge DIR without replicas: $(cat err.txt)"; fi
refused "no replica" 'no replica of an ensemble' rods-r0 rods-plain
refused "one directory" 'at least two' rods-r0
refused "no run directory" 'no readable summary.json' rods-r0 .

refused "an unfinished replica" 'did not finish' rods-r0 rods-stopped
refused "a table replica 0 lacks" 'holds msd.tsv but' rods-nomsd rods-r1
refused "an output still being written" "current.tsv.part', an output" rods-part rods-r1
refused "a cell that is no number" "column msd: 'garbage' is not a number" rods-r0 rods-garbage
refused "a table cut short" 'ends inside line' rods-r0 rods-cut
refused "another input file content" 'differ in input_checksums' rods-t0 rods-t1
cp -r rods-r1 rods-otherbuild && sed -i 's/^  "git": .*/  "git": "0000000",/' rods-otherbuild/summary.json
refused "another build" 'differ in git (' rods-r0 rods-otherbuild
cp -r rods-r1 rods-badindex && sed -i 's/^      "replica": 1,/      "replica": abc,/' rods-badindex/summary.json
refused "a replica index that is no number" 'gives no run.replica as a whole number' rods-r0 rods-badindex
for cell in ' 0x1p3' '1e400' '2 '; do
    cp -r rods-r1 rods-cell && awk -F'\t' -v OFS='\t' -v c="$cell" '!/^#/ && ++n == 3 {$2 = c} 1' \
        rods-r1/msd.tsv >rods-cell/msd.tsv
    refused "the cell '$cell'" "column msd: '$cell' is not a number" rods-r0 rods-cell
    rm -r rods-cell
done
cp -r rods-r1 rods-fifo && rm rods-fifo/msd.tsv && mkfifo rods-fifo/msd.tsv
refused "a table that is a FIFO (it would block)" "msd.tsv': not a regular file" rods-r0 rods-fifo
# a cell as printf writes an estimate without data merges (to nan)
cp -r rods-r1 rods-nan && awk -F'\t' -v OFS='\t' '!/^#/ && ++n == 3 {$2 = "-nan"} 1' \
    rods-r1/msd.tsv >rods-nan/msd.tsv
if "$HSBD" merge rods-mergednan rods-r0 rods-nan 2>err.txt &&
    [ "$(grep -v '^#' rods-mergednan/msd.tsv | sed -n 3p | cut -f2)" = nan ]; then ok
else bad "merge of a nan cell: $(cat err.txt)"; fi
long=$(printf 'd%.0s' $(seq 1 1100))
"$HSBD" merge "$long" rods-r0 rods-r1 >/dev/null 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "too long" err.txt; then ok; else bad "merge into a too long OUT: exit $rc"; fi
# OUT may not be, or hold, one of the runs merged, even with --force (a run or an ensemble:
# never replaced; a directory holding a run's directory: not an earlier merge's result)
cp -r rods-r0 rods-c0
"$HSBD" merge --force rods-c0 rods-c0 rods-r1 >/dev/null 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "which merge never replaces" err.txt && cmp -s rods-c0/summary.json rods-r0/summary.json
then ok; else bad "merge --force into one of its inputs: exit $rc, $(cat err.txt)"; fi
"$HSBD" merge --force rods-one3 rods-one3/replica-0 rods-r1 >/dev/null 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "holds an ensemble's replicas" err.txt && [ -e rods-one3/replica-0/summary.json ]
then ok; else bad "merge --force into a directory holding an input: exit $rc"; fi
mkdir holder && cp -r rods-r0 holder/r0
"$HSBD" merge --force holder holder/r0 rods-r1 >/dev/null 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "holds 'r0', which is not a file of an hsbd run" err.txt &&
    diff -r holder/r0 rods-r0 >/dev/null; then ok
else bad "merge --force into a directory around an input: exit $rc, $(cat err.txt)"; fi
# OUT forgotten (hsbd merge rep0 rep1 rep2): a run, a replica or an ensemble is never
# replaced, with or without --force, and the message shows the line with a new OUT; an
# earlier merge's result is replaced with --force only
cp -r rods-r0 rods-k0 && cp -r rods-r1 rods-k1 && cp -r rods-r2 rods-k2
for force in "" --force; do
    "$HSBD" merge $force rods-k0 rods-k1 rods-k2 >/dev/null 2>err.txt
    rc=$?
    if [ $rc -eq 2 ] && grep -q "holds a run" err.txt &&
        grep -q "hsbd merge MERGED rods-k0 rods-k1 rods-k2" err.txt &&
        diff -r rods-k0 rods-r0 >/dev/null; then ok
    else bad "merge $force over a replica (OUT forgotten): exit $rc, $(cat err.txt)"; fi
done
"$HSBD" merge --force rods-one2 rods-k1 rods-k2 >/dev/null 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "holds an ensemble's replicas" err.txt &&
    [ -e rods-one2/replica-0/checkpoint.hsbd ]; then ok
else bad "merge --force over an ensemble: exit $rc, $(cat err.txt)"; fi
"$HSBD" merge rods-k-merged rods-k0 rods-k1 || bad "merge of k0 k1"
"$HSBD" merge --force rods-k-merged rods-k1 rods-k2 2>err.txt && grep -q '"replica_indices": \[1, 2\]' \
    rods-k-merged/summary.json && ok || bad "merge --force over an earlier merge: $(cat err.txt)"
# an ensemble's --force never replaces a single run
"$HSBD" run rods.ini --quiet --force --set run.replicas=2 --out rods-k0 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "holds a single run" err.txt && diff -r rods-k0 rods-r0 >/dev/null
then ok; else bad "ensemble --force over a run: exit $rc, $(cat err.txt)"; fi

# a table of more than 64 columns (40 phases of a drive: 81) merges whole
"$HSBD" run rods.ini --quiet --set field.type=cosine --set drive.parameter=amplitude \
    --set drive.wave=square --set drive.amplitude=3 --set drive.period=0.5 \
    --set sample.phases=40 --set sample.bin_width=0.2 --set run.replicas=2 --out rods-phases ||
    bad "drive with 40 phases"
cols() { grep -v '^#' "$1" | head -1 | awk -F'\t' '{print NF}'; }
if [ "$(cols rods-phases/density_phases.tsv)" = "$(cols rods-phases/replica-0/density_phases.tsv)" ] &&
    [ "$(cols rods-phases/density_phases.tsv)" -gt 64 ]; then ok
else bad "wide table: $(cols rods-phases/density_phases.tsv) columns merged"; fi

# an ensemble replaces no earlier results, with or without --force: an earlier ensemble,
# a run's directory (above) and a directory of other files stay as they were (exit 2)
"$HSBD" run rods.ini --quiet --set run.replicas=2 --out rods-ens || bad "ensemble"
before=$(ls -AR rods-ens; cat rods-ens/*.tsv rods-ens/replica-*/*.tsv | sha256sum)
for force in "" --force; do
    "$HSBD" run rods.ini --quiet $force --set run.replicas=2 --set system.seed=9 --out rods-ens 2>err.txt
    rc=$?
    if [ $rc -eq 2 ] && grep -q "an ensemble replaces no earlier results (with or without --force)" err.txt &&
        [ "$(ls -AR rods-ens; cat rods-ens/*.tsv rods-ens/replica-*/*.tsv | sha256sum)" = "$before" ]
    then ok; else bad "ensemble $force over an earlier ensemble: exit $rc, $(cat err.txt)"; fi
done
# -h as the value of a flag is that value, not a request for help
"$HSBD" run rods.ini --quiet --set run.t_total=0.5 --out -h >out.txt 2>&1
rc=$?
if [ $rc -eq 0 ] && [ -f ./-h/summary.json ] && ! grep -q usage out.txt; then ok
else bad "--out -h: exit $rc, $(cat out.txt)"; fi
# a link to nowhere as DIR is named as such, and nothing is made
ln -s nowhere/x dangling
"$HSBD" run rods.ini --quiet --set run.replicas=2 --out dangling 2>err.txt
rc=$?
"$HSBD" run rods.ini --quiet --out dangling/ 2>>err.txt # a trailing slash too
rc2=$?
if [ $rc -eq 2 ] && [ $rc2 -eq 2 ] &&
    [ "$(grep -c "leads to no directory (a dangling symbolic link?)" err.txt)" = 2 ] &&
    [ ! -e nowhere ]
then ok; else bad "a dangling link as --out: exit $rc and $rc2, $(cat err.txt)"; fi
# under mpirun rank 0 reads and checks the input and shares it with the other ranks: a
# refusal is one message and exit 2 on every rank (none hangs, nothing is written); replica
# k runs on rank k mod P and rank 0 merges once all are done (exit status: the worst over
# the ranks, each distinct message printed once); a single run, hsbd resume and hsbd merge
# run on rank 0 only
if [ ${#MPIRUN[@]} -gt 0 ]; then
    mpi() { timeout 300 "${MPIRUN[@]}" "$@" >err.txt 2>&1; }
    echo junk >a-file
    mpi "$HSBD" run rods.ini --quiet --out a-file
    rc=$?
    if [ $rc -eq 2 ] && [ "$(grep -c "exists and is not a directory" err.txt)" = 1 ]
    then ok; else bad "mpirun, output refused on rank 0: exit $rc (124: hung), $(cat err.txt)"; fi
    (cat rods.ini; printf '[run]\nbogus = 3\n') >bogus.ini
    mpi "$HSBD" run bogus.ini --quiet --out bogus-out
    rc=$?
    if [ $rc -eq 2 ] && [ "$(grep -c "unknown key 'bogus'" err.txt)" = 1 ] && [ ! -e bogus-out ]
    then ok; else bad "mpirun, a bad input: exit $rc, $(cat err.txt)"; fi
    mpi "$HSBD" run rods.ini --quiet --out help-out --help
    rc=$?
    if [ $rc -eq 0 ] && [ "$(grep -c '^usage: hsbd run' err.txt)" = 1 ] && [ ! -e help-out ]
    then ok; else bad "mpirun, --help: exit $rc, $(cat err.txt)"; fi
    # rank 0's input is every rank's: rank 1's command line names a file it cannot parse and
    # another seed, and is never read; a configuration on the standard input, which mpirun
    # gives to rank 0 only, runs too: both ensembles are that of rods.ini
    mpi sh -c 'c=rods.ini; [ "${OMPI_COMM_WORLD_RANK:-$PMI_RANK}" = 1 ] && c="bogus.ini --seed 6"
        exec "$0" run $c --quiet --out shared' "$HSBD"
    rc=$?
    if [ $rc -eq 0 ]; then same_merged "mpirun, rank 0's input shared" shared rods-mpi2
    else bad "mpirun, rank 0's input shared: exit $rc, $(cat err.txt)"; fi
    mpi "$HSBD" run /dev/stdin --quiet --out stdin-out <rods.ini
    rc=$?
    if [ $rc -eq 0 ]; then same_merged "mpirun, configuration on the standard input" stdin-out rods-mpi2
    else bad "mpirun, configuration on the standard input: exit $rc, $(cat err.txt)"; fi
    # a replica that fails on rank 1 only (random insertion stalls for replica 7 of this seed,
    # not for 0-6): exit 2 on every rank, its message once, naming rank 1, and no merge
    printf '[system]\nmodel = spheres\nN = 60\npacking_fraction = 0.30\nseed = 8\n[init]\nmethod = random\n[run]\ndt = 1e-3\nt_equil = 0.01\nt_total = 0.05\n[sample]\nblocks = 2\n' >rsi.ini
    mpi "$HSBD" run rsi.ini --quiet --set run.replicas=8 --out rsi-mpi
    rc=$?
    if [ $rc -eq 2 ] && [ "$(grep -c "rank 1 of mpirun: .*stalled" err.txt)" = 1 ] &&
        [ -f rsi-mpi/replica-6/summary.json ] && [ ! -e rsi-mpi/summary.json ]
    then ok; else bad "mpirun, a replica refused on rank 1: exit $rc, $(cat err.txt)"; fi
    # the command line: an unknown command is reported once; the commands that do not use
    # MPI run on every rank
    mpi "$HSBD" rnu rods.ini
    rc=$?
    if [ $rc -eq 2 ] && [ "$(grep -c "unknown command 'rnu'" err.txt)" = 1 ] &&
        [ "$(grep -c '^usage:' err.txt)" = 1 ]
    then ok; else bad "mpirun, an unknown command: exit $rc, $(cat err.txt)"; fi
    if mpi "$HSBD" version && [ "$(grep -c '^hsbd ' err.txt)" = 2 ]; then ok
    else bad "mpirun, version on both ranks: $(cat err.txt)"; fi
    mpi "$HSBD" run rods.ini --quiet --set init.positions=missing.txt --out missing-out
    rc=$?
    if [ $rc -eq 2 ] && [ "$(grep -c "cannot read init.positions" err.txt)" = 1 ] && [ ! -e missing-out ]
    then ok; else bad "mpirun, a missing input of every replica: exit $rc, $(cat err.txt)"; fi
    # a single run runs once, on rank 0 (rank 1's --out is never read)
    mpi sh -c 'exec "$0" run rods.ini --quiet --replica 0 --out single-${OMPI_COMM_WORLD_RANK:-$PMI_RANK}' "$HSBD" ||
        bad "mpirun, a single run: $(cat err.txt)"
    if [ ! -e single-1 ] && diff -r -x summary.json -x "checkpoint*" single-0 rods-r0 >/dev/null
    then ok; else bad "mpirun, a single run: $(ls -d single-*)"; fi
    mpi "$HSBD" merge
    rc=$?
    mv err.txt err1.txt
    mpi "$HSBD" resume
    rc2=$?
    if [ $rc -eq 2 ] && [ $rc2 -eq 2 ] && [ "$(grep -c "no output directory given" err1.txt)" = 1 ] &&
        [ "$(grep -c "no run directory given" err.txt)" = 1 ]
    then ok; else bad "mpirun, merge and resume without a directory: exit $rc, $rc2, $(cat err1.txt err.txt)"; fi
    # hsbd merge under mpirun: rank 0 merges, once
    if mpi "$HSBD" merge mpi-merged rods-r1 rods-r0; then
        same_merged "mpirun hsbd merge" mpi-merged rods-merged2
    else bad "mpirun hsbd merge: $(cat err.txt)"; fi
    # the ranks share the node's CPUs out by default (no oversubscription: each replica
    # of 2 ranks takes at most half the CPUs); run.threads set is kept
    env -u OMP_NUM_THREADS "${MPIRUN[@]}" "$HSBD" run rods.ini --quiet --out rods-share \
        >err.txt 2>&1 || bad "mpirun, threads by default: $(cat err.txt)"
    half=$(( $(nproc) / 2 > 1 ? $(nproc) / 2 : 1 ))
    for k in 0 1; do
        t=$(sed -n 's/^  "threads_used": \([0-9]*\),$/\1/p' rods-share/replica-$k/summary.json)
        if [ -n "$t" ] && [ "$t" -ge 1 ] && [ "$t" -le "$half" ]; then ok
        else bad "mpirun -n 2: replica $k took '$t' threads of $(nproc) CPUs"; fi
    done
    "${MPIRUN[@]}" "$HSBD" run rods.ini --quiet --threads 3 --out rods-three >err.txt 2>&1 ||
        bad "mpirun, --threads 3: $(cat err.txt)"
    if grep -q '^  "threads_used": 3,$' rods-three/replica-1/summary.json; then ok
    else bad "mpirun: --threads 3 not kept"; fi
    # hsbd resume under mpirun: rank 0 resumes, the others do nothing
    "$HSBD" run rods.ini --quiet --replica 0 --set run.t_total=1 --out rods-ext1 || bad "t_total 1"
    cp -r rods-ext1 rods-ext2
    mpi "$HSBD" resume rods-ext1 --quiet --set run.t_total=2
    rc=$?
    "$HSBD" resume rods-ext2 --quiet --set run.t_total=2 || bad "resume to t_total 2"
    if [ $rc -eq 0 ] && diff -r -x summary.json -x "checkpoint*" rods-ext1 rods-ext2 >/dev/null; then ok
    else bad "mpirun -n 2 hsbd resume: exit $rc, $(cat err.txt)"; fi
    # ... with all the CPUs rank 0 may use (ranks not bound: every CPU)
    "$HSBD" run rods.ini --quiet --replica 0 --set run.t_total=1 --out rods-ext3 || bad "t_total 1"
    env -u OMP_NUM_THREADS timeout 300 "${MPIRUN[@]}" --bind-to none "$HSBD" resume rods-ext3 \
        --quiet --set run.t_total=2 >err.txt 2>&1 || bad "mpirun --bind-to none resume: $(cat err.txt)"
    t=$(sed -n 's/^  "threads_used": \([0-9]*\),$/\1/p' rods-ext3/summary.json)
    if [ "$t" = "$(nproc)" ]; then ok
    else bad "mpirun -n 2 hsbd resume: rank 0 took '$t' threads of $(nproc) CPUs"; fi
    mpi "$HSBD" run rods.ini --quiet --out rods-ens
    rc=$?
    if [ $rc -eq 2 ] && [ "$(grep -c "already exists and is not empty" err.txt)" = 1 ]
    then ok; else bad "mpirun, an existing ensemble: exit $rc (124: hung), $(cat err.txt)"; fi
fi
# a directory another process writes (its lock held, here by flock(1)) is refused to an
# ensemble (its claim comes first), to hsbd merge reading it, and to hsbd merge --force
# writing into it; nothing is touched
hold() { # hold DIR: the lock of DIR held until release
    flock -o "$1/.hsbd.lock" sleep 120 &
    holder=$!
    while flock -n "$1/.hsbd.lock" true; do sleep 0.05; done
}
release() { pkill -P $holder sleep; wait $holder 2>/dev/null; }
in_use() { # in_use WHAT DIR CMD...: exit 2, "is in use", DIR unchanged
    local what=$1 dir=$2 before rc
    shift 2
    before=$(ls -AR "$dir"; cat "$dir"/* 2>/dev/null | sha256sum)
    "$@" >/dev/null 2>err.txt
    rc=$?
    if [ $rc -eq 2 ] && grep -q "is in use" err.txt &&
        [ "$(ls -AR "$dir"; cat "$dir"/* 2>/dev/null | sha256sum)" = "$before" ]; then ok
    else bad "$what while it is written: exit $rc, $(cat err.txt)"; fi
}
cp -r rods-one2 busy-ens
hold busy-ens
in_use "ensemble --force over an ensemble" busy-ens "$HSBD" run rods.ini --quiet --force \
    --set run.replicas=2 --out busy-ens
release
"$HSBD" merge busy-merge rods-r0 rods-r1 || bad "busy-merge"
hold busy-merge
in_use "merge --force into an earlier merge" busy-merge "$HSBD" merge --force busy-merge rods-r0 \
    rods-r1
release
hold rods-one3/replica-1
in_use "merge of a replica" rods-r0 "$HSBD" merge busy-merged rods-r0 rods-one3/replica-1
release
[ ! -e busy-merged ] || bad "merge of a replica in use wrote busy-merged"
# a .hsbd.lock that is no lock file (a link, a FIFO) is refused, not followed or waited on;
# a directory of other files gets no lock file from a refused run or merge
cp -r rods-r1 rods-fifolock && rm rods-fifolock/.hsbd.lock && mkfifo rods-fifolock/.hsbd.lock
refused "a lock file that is a FIFO" "is not the lock file of a run directory" rods-r0 rods-fifolock
"$HSBD" run rods.ini --quiet --out planted || bad "planted"
rm planted/.hsbd.lock && ln -s ../rods-r0/summary.json planted/.hsbd.lock
"$HSBD" run rods.ini --quiet --force --out planted 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "is not the lock file" err.txt && [ -L planted/.hsbd.lock ] &&
    [ -s planted/summary.json ]; then ok
else bad "a lock file that is a link: exit $rc, $(cat err.txt)"; fi
mkdir foreign && echo notes >foreign/notes.txt
"$HSBD" run rods.ini --quiet --force --out foreign 2>/dev/null
"$HSBD" merge --force foreign rods-r0 rods-r1 2>/dev/null
if [ ! -e foreign/.hsbd.lock ] && [ "$(ls -A foreign)" = notes.txt ]; then ok
else bad "a directory of other files got: $(ls -A foreign | tr '\n' ' ')"; fi
# the ensemble's own merge meeting a full file-size limit leaves no merged file (the
# replicas' blocks tables, one column per replica, exceed 4 KiB; the replicas' own not)
(trap '' XFSZ; ulimit -f 4; "$HSBD" run rods.ini --quiet --set run.replicas=24 \
    --set sample.blocks=2 --set output.checkpoints=off --out rods-big 2>err.txt)
rc=$?
if [ $rc -ne 0 ] && grep -q "too large" err.txt && [ -z "$(ls rods-big | grep -v '^replica-')" ]
then ok; else bad "ensemble merge over the size limit: exit $rc, left $(ls rods-big | grep -v '^replica-' | tr '\n' ' ')"; fi
# an existing ensemble without --force: the message names the way on
"$HSBD" run rods.ini --quiet --set run.replicas=2 --out rods-ens 2>err.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "replica by replica" err.txt; then ok
else bad "existing ensemble directory: exit $rc, $(cat err.txt)"; fi

# a merge that meets a full disk leaves nothing behind (a 12 KiB tmpfs: needs root, as in CI)
if [ "$(id -u)" = 0 ] && mkdir -p small && mount -t tmpfs -o size=12k tmpfs small 2>/dev/null; then
    "$HSBD" merge small/m rods-r0 rods-r1 rods-r2 >/dev/null 2>err.txt
    rc=$?
    if [ $rc -ne 0 ] && [ ! -e small/m ] && grep -q "space" err.txt; then ok
    else bad "merge onto a full disk: exit $rc, left: $(ls -R small 2>&1 | tr '\n' ' ')"; fi
    umount small
else
    echo "test_ensemble: no tmpfs mount (needs root): the full-disk merge is skipped" >&2
fi

echo "test_ensemble: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
