#!/usr/bin/env bash
# A corpus of bad inputs. Every case must exit with status 2, print exactly one message line
# that contains the given texts (the file and line, or the flag, and what is wrong), and
# leave nothing behind: no run directory, no result file, no new file anywhere in the
# working directory. The inputs are generated here (deterministic bytes, no randomness).
set -u
HSBD=${1:?usage: test_bad_inputs.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir "$T/in" "$T/log"
cd "$T/in"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# bad_case NAME 'text' ['text'...] -- hsbd-arguments...
# `run` cases get --out DIR --quiet appended; DIR must not exist afterwards.
bad_case() {
    local name=$1; shift
    local texts=()
    while [ "$1" != "--" ]; do texts+=("$1"); shift; done
    shift
    local out="$T/out-$name" extra=()
    [ "$1" = run ] && extra=(--out "$out" --quiet)
    local before after
    before=$(ls -A)
    "$HSBD" "$@" "${extra[@]}" >"$T/log/stdout" 2>"$T/log/stderr" </dev/null
    local rc=$?
    after=$(ls -A)
    local msg
    msg=$(head -c 600 "$T/log/stderr")
    if [ $rc -ne 2 ]; then bad "$name: exit $rc, expected 2 ($msg)"; return; fi
    if [ "$(wc -l <"$T/log/stderr")" -ne 1 ]; then bad "$name: expected one message line, got: $msg"; return; fi
    for s in "${texts[@]}"; do
        if ! grep -qF -- "$s" "$T/log/stderr"; then bad "$name: message lacks '$s': $msg"; return; fi
    done
    if [ -e "$out" ]; then bad "$name: the run directory was created"; return; fi
    if [ "$before" != "$after" ]; then bad "$name: files appeared: $(diff <(echo "$before") <(echo "$after") | grep '^>' | head -3)"; return; fi
    ok
}

# ---- spheres: init.positions in extended XYZ ----
cat >sph.ini <<'INI'
[system]
model = spheres
dimension = 2
N = 20
packing_fraction = 0.2
[run]
dt = 1e-3
t_equil = 0.01
t_total = 0.1
[sample]
blocks = 4
[output]
trajectory = xyz
INI
"$HSBD" run sph.ini --out "$T/frame" --quiet || bad "spheres run for a frame"
tail -n 22 "$T/frame/trajectory.xyz" >frame.xyz
cat >mix.ini <<'INI'
[system]
model = spheres
dimension = 2
N = 20
packing_fraction = 0.2
[species]
names = A B
count = 10 10
sigma = 1 1
D = 1 1
[run]
dt = 1e-3
t_equil = 0.01
t_total = 0.1
[sample]
blocks = 4
INI
sed '3,12s/^S /A /; 13,22s/^S /B /' frame.xyz >mixframe.xyz
"$HSBD" run mix.ini --set init.positions=mixframe.xyz --out "$T/mixok" --quiet || bad "a good mixture frame is refused"
sph() { bad_case "$@" --set output.trajectory=none; } # sph NAME texts -- run sph.ini --set init.positions=F

: >empty.xyz
sph xyz-empty "empty.xyz: the file is empty" -- run sph.ini --set init.positions=empty.xyz
{ echo "twenty"; tail -n +2 frame.xyz; } >count-word.xyz
sph xyz-count-word "count-word.xyz:1:" "number of particles" -- run sph.ini --set init.positions=count-word.xyz
{ echo "-20"; tail -n +2 frame.xyz; } >count-neg.xyz
sph xyz-count-negative "count-neg.xyz:1:" "number of particles" -- run sph.ini --set init.positions=count-neg.xyz
{ echo "0x14"; tail -n +2 frame.xyz; } >count-hex.xyz
sph xyz-count-hex "count-hex.xyz:1:" "number of particles" -- run sph.ini --set init.positions=count-hex.xyz
{ echo "21"; tail -n +2 frame.xyz; } >count-more.xyz
sph xyz-count-mismatch "count-more.xyz:1:" "has 21 particles; allowed: system.N = 20" -- run sph.ini --set init.positions=count-more.xyz
{ echo "99999999999999999999999"; tail -n +2 frame.xyz; } >count-huge.xyz
sph xyz-count-huge "count-huge.xyz:1:" -- run sph.ini --set init.positions=count-huge.xyz
head -n 1 frame.xyz >count-only.xyz
sph xyz-count-only "count-only.xyz:1:" "ends after the count" -- run sph.ini --set init.positions=count-only.xyz
head -n 12 frame.xyz >short.xyz
sph xyz-short "short.xyz:12:" "ends after 10 of 20 particles" -- run sph.ini --set init.positions=short.xyz
awk 'NR == 5 { $2 = 1e6 } { print }' frame.xyz >outside.xyz
sph xyz-outside-box "outside.xyz:5:" "outside the box" -- run sph.ini --set init.positions=outside.xyz
awk 'NR == 6 { $3 = -0.5 } { print }' frame.xyz >negative.xyz
sph xyz-negative "negative.xyz:6:" "y = -0.5 is outside the box" -- run sph.ini --set init.positions=negative.xyz
awk 'NR == 7 { $2 = "nan" } { print }' frame.xyz >nan.xyz
sph xyz-nan "nan.xyz:7:" "x = 'nan' is not a finite number" -- run sph.ini --set init.positions=nan.xyz
awk 'NR == 7 { $3 = "0x1p2" } { print }' frame.xyz >hexcoord.xyz
sph xyz-hex-coordinate "hexcoord.xyz:7:" "y = '0x1p2'" -- run sph.ini --set init.positions=hexcoord.xyz
awk 'NR == 8 { $4 = 0.5 } { print }' frame.xyz >z2d.xyz
sph xyz-z-in-2d "z2d.xyz:8:" "z = 0.5 in a 2D frame" -- run sph.ini --set init.positions=z2d.xyz
sed '3s/^S /Q /' frame.xyz >species.xyz
sph xyz-unknown-species "species.xyz:3:" "unknown species name 'Q'" "allowed: S" -- run sph.ini --set init.positions=species.xyz
sed '4s/^A /C /' mixframe.xyz >mixspecies.xyz
bad_case xyz-unknown-species-mixture "mixspecies.xyz:4:" "unknown species name 'C'" "allowed: A, B" -- run mix.ini --set init.positions=mixspecies.xyz
sed '13s/^B /A /' mixframe.xyz >mixcount.xyz
bad_case xyz-species-count "mixcount.xyz" "11 particles of species A" -- run mix.ini --set init.positions=mixcount.xyz
sed '2s/Lattice="[0-9.e+-]*/Lattice="99/' frame.xyz >lattice.xyz
sph xyz-lattice-box "lattice.xyz:2:" "Lattice" "is not the box" -- run sph.ini --set init.positions=lattice.xyz
sed '2s/Lattice="\([^ ]*\) 0 0/Lattice="\1 0.5 0/' frame.xyz >lattice-skew.xyz
sph xyz-lattice-skew "lattice-skew.xyz:2:" "axis-aligned" -- run sph.ini --set init.positions=lattice-skew.xyz
sed '2s/Lattice="[^"]*"/Lattice="1 2 3"/' frame.xyz >lattice-short.xyz
sph xyz-lattice-malformed "lattice-short.xyz:2:" "9 finite numbers" -- run sph.ini --set init.positions=lattice-short.xyz
sed '2s/Properties=species:S:1:pos:R:3/Properties=pos:R:3:species:S:1/' frame.xyz >props.xyz
sph xyz-properties "props.xyz:2:" "Properties= must begin with species:S:1:pos:R:3" -- run sph.ini --set init.positions=props.xyz
{ head -n 9 frame.xyz; printf 'S 1\0 2 0\n'; tail -n +11 frame.xyz; } >nul.xyz
sph xyz-nul-byte "nul.xyz:10:" "NUL byte" -- run sph.ini --set init.positions=nul.xyz
cat frame.xyz frame.xyz >two.xyz
sph xyz-two-frames "two.xyz:23:" "one frame" -- run sph.ini --set init.positions=two.xyz
{ head -n 4 frame.xyz; head -c 1100000 /dev/zero | tr '\0' '1'; echo; tail -n +6 frame.xyz; } >long.xyz
sph xyz-long-line "long.xyz:5:" "line longer than" -- run sph.ini --set init.positions=long.xyz
mkdir xyzdir
sph xyz-directory "cannot read init.positions file 'xyzdir'" "Is a directory" -- run sph.ini --set init.positions=xyzdir
sph xyz-missing "cannot read init.positions file 'nosuch.xyz'" "No such file" -- run sph.ini --set init.positions=nosuch.xyz
head -c 3000 /dev/zero | tr '\0' '\377' >junk.xyz
sph xyz-binary "junk.xyz:1:" -- run sph.ini --set init.positions=junk.xyz

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
