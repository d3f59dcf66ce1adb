#!/usr/bin/env bash
# Faults are caught at once and nothing complete is deleted: an output directory that
# cannot be written is refused before any dynamics (exit 2, naming it); a disk that fills
# during the run stops it with the name of the file that failed, and the last checkpoint
# stays (resumed elsewhere it completes the run exactly); SIGHUP, SIGINT and SIGTERM write
# a checkpoint and the results so far (exit 129, 130, 143); --force into an earlier run's
# directory removes that run's files first and refuses a directory with other files.
# The full disk and the read-only directory use small tmpfs mounts, which need root (as
# in CI); without root those cases are skipped with a message.
set -u
HSBD=${1:?usage: test_faults.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
T=$(mktemp -d)
MOUNTS=()
cleanup() {
    for m in "${MOUNTS[@]}"; do umount "$m" 2>/dev/null; done
    rm -rf "$T"
}
trap cleanup EXIT
cd "$T"
pass=0 fail=0 skipped=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
skip() { skipped=$((skipped + 1)); echo "skipped: $*"; }

cat >r.ini <<'INI'
[system]
N = 50
L = 100
sigma = 0.5
seed = 5
[run]
dt = 1e-4
t_equil = 0.2
t_total = 20
[sample]
bin_width = 0.05
blocks = 4
current_every = 0.5
[output]
trajectory = xyz
trajectory_every = 0.05
checkpoint_every = 0.5
INI
ref=(--set run.t_total=4 --set output.trajectory_every=0.005)

mounted=0
if [ "$(id -u)" = 0 ] && mkdir -p mnt && mount -t tmpfs -o size=16k tmpfs mnt 2>/dev/null; then
    umount mnt && mounted=1
fi

# a directory that cannot be written: refused at once, before the dynamics
if [ $mounted = 1 ]; then
    mkdir -p ro && mount -t tmpfs -o ro,size=64k tmpfs ro && MOUNTS+=("$T/ro")
    start=$(date +%s%N)
    "$HSBD" run r.ini --quiet --out ro/run >out 2>err
    rc=$?
    took=$((($(date +%s%N) - start) / 1000000))
    if [ $rc = 2 ] && grep -q "ro/run" err && [ $took -lt 2000 ]; then ok; else
        bad "read-only directory: exit $rc after $took ms: $(cat err)"; fi
else
    mkdir ro && chmod 555 ro
    "$HSBD" run r.ini --quiet --out ro/run >out 2>err
    rc=$?
    if [ "$(id -u)" != 0 ] && [ $rc = 2 ] && grep -q "ro/run" err; then ok; else
        skip "read-only directory (root without tmpfs mounts bypasses permissions)"; fi
fi
printf 'x' >afile
"$HSBD" run r.ini --quiet --out afile/run >out 2>err
if [ $? = 2 ] && grep -q "afile" err; then ok; else bad "a file as a parent directory: $(cat err)"; fi

# a disk that fills: the run stops with the file that failed; the last checkpoint stays
if [ $mounted = 1 ]; then
    "$HSBD" run r.ini --quiet "${ref[@]}" --out reference 2>/dev/null || bad "reference run failed"
    mkdir -p small && mount -t tmpfs -o size=1200k tmpfs small && MOUNTS+=("$T/small")
    "$HSBD" run r.ini --quiet "${ref[@]}" --out small/run >out 2>err
    rc=$?
    if [ $rc = 1 ] && grep -q "No space left on device" err && grep -q "small/run/" err &&
        [ -s small/run/checkpoint.hsbd ]; then ok; else
        bad "full disk: exit $rc, $(cat err); $(ls small/run 2>&1 | tr '\n' ' ')"; fi
    # the checkpoint is good: continued where there is room, the results are exact
    cp -r small/run moved && umount small && MOUNTS=("${MOUNTS[@]/$T\/small/}")
    if "$HSBD" resume moved --quiet 2>err; then
        same=1
        for f in reference/*.tsv reference/trajectory.xyz; do
            cmp -s "$f" "moved/$(basename "$f")" || { same=0; echo "differs: $(basename "$f")" >&2; }
        done
        if [ $same = 1 ]; then ok; else bad "full disk: the resumed run differs"; fi
    else bad "full disk: resume failed: $(cat err)"; fi
else
    skip "full disk (needs root for a small tmpfs)"
fi

# stop signals: a checkpoint and the results so far, exit 128 + the signal
for sig in HUP INT TERM; do
    "$HSBD" run r.ini --quiet --out "sig$sig" 2>/dev/null &
    pid=$!
    for _ in $(seq 50); do [ -s "sig$sig/checkpoint.hsbd" ] && break; sleep 0.1; done
    kill -s "$sig" $pid
    wait $pid
    rc=$?
    want=$((128 + $(kill -l "$sig")))
    if [ $rc = $want ] && grep -q '"completed": false' "sig$sig/summary.json" &&
        [ -s "sig$sig/density.tsv" ] && [ -s "sig$sig/checkpoint.hsbd" ] &&
        [ -s "sig$sig/trajectory.xyz" ]; then ok; else
        bad "SIG$sig: exit $rc (want $want); $(ls "sig$sig" | tr '\n' ' ')"; fi
done

# --force into an earlier run's directory: its files go first; foreign files refuse
"$HSBD" run r.ini --quiet --set run.t_total=1 --out stale 2>/dev/null
"$HSBD" run r.ini --quiet --set run.t_total=1 --set output.trajectory=none \
    --set sample.current_every=0 --force --out stale 2>err
if [ $? = 0 ] && [ ! -e stale/trajectory.xyz ] && [ ! -e stale/current.tsv ] &&
    [ -s stale/density.tsv ]; then ok; else bad "--force left the earlier run's files: $(ls stale | tr '\n' ' ')"; fi
printf 'mine\n' >stale/notes.txt
"$HSBD" run r.ini --quiet --set run.t_total=1 --force --out stale >out 2>err
if [ $? = 2 ] && grep -q "notes.txt" err && [ -e stale/notes.txt ] && [ -s stale/density.tsv ]; then ok; else
    bad "--force with a foreign file: $(cat err)"; fi
"$HSBD" run r.ini --quiet --set run.t_total=1 --out stale >out 2>err
if [ $? = 2 ] && grep -q "hsbd resume" err; then ok; else bad "existing directory: $(cat err)"; fi

echo "test_faults: $pass passed, $fail failed, $skipped skipped"
[ $fail -eq 0 ]
