#!/usr/bin/env bash
# A corpus of bad inputs. Every case must exit with status 2, print exactly one message line
# that contains the given texts (what is wrong) and names where: a file and line
# ("name.ini:12:"), a file as a whole ("name.ini: ...", "file 'name'"), or the flag or
# argument ("--set", "command line", "argument 3"); and leave nothing behind: no run
# directory, no result file, no new file anywhere in the working directory. The inputs are
# generated here (deterministic bytes, no randomness).
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

# what a message names: a file (and line), or the flag or argument
WHERE="[A-Za-z0-9_-]+\.(ini|xyz|txt|tab|gsd)(:[0-9]+)?[: ']|(file|table|path|directory) '[^']+'|--[a-z]|command line|argument ([0-9]+|'[^']+')|unknown theory '"
# bad_case NAME 'text' ['text'...] -- hsbd-arguments...
# `run` cases without their own --out get --out DIR --quiet appended; DIR must not exist
# afterwards.
bad_case() {
    local name=$1; shift
    local texts=()
    while [ "$1" != "--" ]; do texts+=("$1"); shift; done
    shift
    local out="$T/out-$name" extra=()
    [ "$1" = run ] && extra=(--out "$out" --quiet)
    case " $* " in *" --out "*) extra=() ;; esac # the case's own --out
    local before after
    before=$(ls -A)
    "$HSBD" "$@" "${extra[@]}" >"$T/log/stdout" 2>"$T/log/stderr" </dev/null
    local rc=$?
    after=$(ls -A)
    local msg
    msg=$(head -c 600 "$T/log/stderr")
    if [ $rc -ne 2 ]; then bad "$name: exit $rc, expected 2 ($msg)"; return; fi
    if [ "$(wc -l <"$T/log/stderr")" -ne 1 ]; then bad "$name: expected one message line, got: $msg"; return; fi
    if ! grep -qE -- "$WHERE" "$T/log/stderr"; then bad "$name: the message names no file, line or flag: $msg"; return; fi
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
sph xyz-count-mismatch "count-more.xyz:1:" "the count line says 21, the file has 20 particle lines" -- run sph.ini --set init.positions=count-more.xyz
head -n -1 frame.xyz >count-short.xyz
sph xyz-count-short "count-short.xyz:1:" "the count line says 20, the file has 19 particle lines" -- run sph.ini --set init.positions=count-short.xyz
sph xyz-count-not-n "command line (--set) system.N" "system.N = 21 disagrees with init.positions 'frame.xyz', which has N = 20 particles" -- run sph.ini --set system.N=21 --set init.positions=frame.xyz
{ echo "99999999999999999999999"; tail -n +2 frame.xyz; } >count-huge.xyz
sph xyz-count-huge "count-huge.xyz:1:" -- run sph.ini --set init.positions=count-huge.xyz
head -n 1 frame.xyz >count-only.xyz
sph xyz-count-only "count-only.xyz:1:" "ends after the count" -- run sph.ini --set init.positions=count-only.xyz
head -n 12 frame.xyz >short.xyz
sph xyz-short "short.xyz:1:" "the count line says 20, the file has 10 particle lines" -- run sph.ini --set init.positions=short.xyz
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
sph xyz-lattice-box "sph.ini:" "system.packing_fraction = " "disagrees with init.positions 'lattice.xyz', which has the box 99 x " -- run sph.ini --set init.positions=lattice.xyz
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

# ---- init.positions in GSD: the file's bad cases, and a restated value that disagrees ----
"$HSBD" run sph.ini --out "$T/gsdrun" --quiet --set output.trajectory=gsd || bad "spheres run for a GSD file"
cp "$T/gsdrun/trajectory.gsd" frames.gsd
cp frame.xyz frame.gsd
sph gsd-not-gsd "frame.gsd: the file does not begin with GSD's magic number" -- run sph.ini --set init.positions=frame.gsd
head -c 100 frames.gsd >header-cut.gsd
sph gsd-header-cut "header-cut.gsd: the file ends inside its 256-byte header" -- run sph.ini --set init.positions=header-cut.gsd
head -c 6000 frames.gsd >cut.gsd
sph gsd-cut "cut.gsd: " "beyond the file's end (cut short?)" -- run sph.ini --set init.positions=cut.gsd
sph gsd-frame "frames.gsd: init.frame = 100 is not a frame of the file; allowed: 0 .. 99" -- run sph.ini --set init.positions=frames.gsd --set init.frame=100
sph gsd-frame-xyz "init.frame chooses a frame of a GSD file" -- run sph.ini --set init.positions=frame.xyz --set init.frame=0
sph gsd-count "command line (--set) system.N: system.N = 30 disagrees with init.positions 'frames.gsd' (frame 99 of 100), which has N = 20 particles" -- run sph.ini --set init.positions=frames.gsd --set system.N=30

# ---- rods: configuration files ----
rods_ini() { # a quick rods configuration; extra lines (given as arguments) go to its end
    printf '[system]\nN = 20\nL = 40\nsigma = 0.5\n[field]\ntype = cosine\namplitude = 6\n'
    printf '[run]\ndt = 1e-3\nt_equil = 0.1\nt_total = 0.5\n[sample]\nbin_width = 0.05\nblocks = 4\n'
    for line in "$@"; do printf '%s\n' "$line"; done
}
rods_ini >good.ini
in_system() { # a configuration with LINE as line 2 (first in [system])
    { echo '[system]'; printf '%s\n' "$1"; rods_ini | tail -n +2; }
}
: >empty.ini
bad_case empty-file "empty.ini: the configuration sets no key" "--defaults" -- run empty.ini
printf '# only\n; comments\n\n' >comments.ini
bad_case comments-only "comments.ini: the configuration sets no key" -- run comments.ini
printf '[system]\n[run]\n' >sections.ini
bad_case sections-only "sections.ini: the configuration sets no key" -- run sections.ini
mkdir cfgdir
bad_case config-directory "cannot read configuration file 'cfgdir': Is a directory" -- run cfgdir
bad_case config-missing "cannot read configuration file 'nosuch.ini': No such file" -- run nosuch.ini
bad_case no-config "no configuration file given; --defaults" -- run
bad_case defaults-and-file "--defaults runs without a configuration file" -- run good.ini --defaults
# drives that make no sense: the file, line and key named
rods_ini '[drive]' 'parameter = force' 'wave = cosine' 'amplitude = 2' 'period = 1' >drive-absent.ini
bad_case drive-absent-term "drive-absent.ini:16: drive.parameter" "the tilt term, which field.type does not have" -- run drive-absent.ini
rods_ini '[drive]' 'parameter = amplitude' 'wave = square' 'amplitude = 2' 'period = 1e-4' >drive-period.ini
bad_case drive-short-period "drive-period.ini:19: drive.period" "allowed: drive.period >= the time step 0.001" -- run drive-period.ini
bad_case drive-dt-equil "drive.period = 0.002" "time step 0.01 (run.dt, run.dt_equil)" -- run drive-period.ini --set drive.period=2e-3 --set run.dt_equil=1e-2
bad_case drive-nothing "drive.velocity is set, but drive.parameter = none drives nothing" -- run good.ini --set drive.velocity=1
bad_case drive-no-change "neither drive.wave nor drive.velocity changes it" -- run good.ini --set drive.parameter=shift
bad_case drive-period-without-wave "drive.period is set, but drive.wave = none" -- run good.ini --set drive.parameter=shift --set drive.velocity=1 --set drive.period=2
bad_case drive-zero-amplitude "drive.amplitude = 0 with drive.wave set changes nothing" -- run good.ini --set drive.parameter=amplitude --set drive.wave=cosine --set drive.period=2
bad_case drive-wave-name "drive.wave" "one of none|cosine|square" -- run good.ini --set drive.wave=sawtooth
bad_case phases-without-drive "sample.phases = 4 needs a periodic drive" -- run good.ini --set sample.phases=4
bad_case phases-range "sample.phases" "0 <= phases <= 100" -- run good.ini --set sample.phases=101
in_system "$(printf 'N = 2\001 0')" >ctrl.ini
bad_case control-character "ctrl.ini:2:" "control character 0x01" -- run ctrl.ini
{ echo '[system]'; printf 'N = 2\0 0\n'; rods_ini | tail -n +2; } >nul.ini
bad_case nul-byte "nul.ini:2:" "NUL byte" -- run nul.ini
head -c 4000 /dev/zero | tr '\0' '\001' >binary.ini
bad_case binary-file "binary.ini:1:" "control character" -- run binary.ini
printf '\x7fELF\x02\x01\x01\x00\x00\x00\x00\x00\x00\x00\x00\x00\x02\x00\x3e\x00' >elf.ini
bad_case elf-file "elf.ini:1:" -- run elf.ini
{ printf '[system]\nN = '; head -c 1100000 /dev/zero | tr '\0' '9'; echo; } >longline.ini
bad_case over-long-line "longline.ini:2:" "line longer than" -- run longline.ini
{ echo '[system]'; head -c 100000 /dev/zero | tr '\0' 'k'; echo ' = 5'; } >longkey.ini
bad_case long-key "longkey.ini:2:" "unknown key 'kkkk" -- run longkey.ini
in_system 'N = 0x14' >hex.ini
bad_case hex-integer "hex.ini:2:" "system.N = '0x14' is hexadecimal" -- run hex.ini
in_system 'N = 010' >octal.ini
bad_case octal-integer "octal.ini:2:" "system.N = '010' has a leading zero" -- run octal.ini
in_system 'seed = 010' >octseed.ini
bad_case octal-seed "octseed.ini:2:" "system.seed = '010' is not a valid integer" -- run octseed.ini
in_system 'seed = 0x10' >hexseed.ini
bad_case hex-seed "hexseed.ini:2:" "system.seed = '0x10'" -- run hexseed.ini
in_system 'seed = 18446744073709551616' >bigseed.ini
bad_case seed-overflow "bigseed.ini:2:" "system.seed = '18446744073709551616'" -- run bigseed.ini
in_system 'seed = -1' >negseed.ini
bad_case negative-seed "negseed.ini:2:" "system.seed = '-1'" -- run negseed.ini
in_system 'L = 0x1p6' >hexfloat.ini
bad_case hex-float "hexfloat.ini:2:" "system.L = '0x1p6' is hexadecimal" -- run hexfloat.ini
in_system 'L = inf' >inf.ini
bad_case infinite "inf.ini:2:" "system.L = 'inf' is not a finite number" -- run inf.ini
in_system 'L = nan' >nan.ini
bad_case nan "nan.ini:2:" "system.L = 'nan' is not a finite number" -- run nan.ini
in_system 'L = 1e999' >huge.ini
bad_case beyond-double "huge.ini:2:" "system.L = '1e999' is beyond the range" -- run huge.ini
in_system 'N = 1e300' >hugen.ini
bad_case huge-count "hugen.ini:2:" "system.N = 1e300 is out of range" -- run hugen.ini
in_system 'N = -5' >negn.ini
bad_case negative-count "negn.ini:2:" "system.N = -5 is out of range" -- run negn.ini
in_system 'N = 20.5' >fracn.ini
bad_case fractional-count "fracn.ini:2:" "'20.5' is not a whole number" -- run fracn.ini
in_system 'N =' >emptyval.ini
bad_case empty-value "emptyval.ini:2:" "system.N = '' is not a whole number" -- run emptyval.ini
in_system 'N = 20 30' >twovals.ini
bad_case two-values "twovals.ini:2:" "system.N = '20 30'" -- run twovals.ini
in_system 'N = 1,5' >comma.ini
bad_case decimal-comma "comma.ini:2:" "system.N = '1,5'" -- run comma.ini
in_system 'hard_core = maybe' >switch.ini
bad_case switch "switch.ini:2:" "system.hard_core = 'maybe' is not a switch" -- run switch.ini
in_system 'model = cubes' >model.ini
bad_case unknown-model "model.ini:2:" "system.model = 'cubes' is not known" -- run model.ini
in_system 'N: 20' >colon.ini
bad_case colon-separator "colon.ini:2:" "malformed line" -- run colon.ini
in_system '= 20' >nokey.ini
bad_case value-without-key "nokey.ini:2:" "a value without a key" -- run nokey.ini
in_system 'N = 20' >dup.ini
bad_case duplicate-key "dup.ini:3:" "system.N is set twice (first at dup.ini:2)" -- run dup.ini
{ rods_ini; echo '[system]'; echo 'N = 30'; } >dupsec.ini
bad_case duplicate-across-sections "dupsec.ini:16:" "system.N is set twice" -- run dupsec.ini
{ echo '[sytem]'; rods_ini | tail -n +2; } >sytem.ini
bad_case unknown-section "sytem.ini:1:" "unknown section [sytem]; did you mean [system]?" -- run sytem.ini
{ rods_ini; echo '[physics]'; echo 'g = 9.81'; } >physics.ini
bad_case unknown-section-far "physics.ini:15:" "unknown section [physics]; allowed:" -- run physics.ini
{ echo '[system] extra'; rods_ini | tail -n +2; } >secjunk.ini
bad_case section-junk "secjunk.ini:1:" "malformed section line" -- run secjunk.ini
{ echo '[system'; rods_ini | tail -n +2; } >secopen.ini
bad_case section-unclosed "secopen.ini:1:" "malformed section line" -- run secopen.ini
{ echo '[]'; rods_ini | tail -n +2; } >secempty.ini
bad_case section-empty "secempty.ini:1:" "unknown section []" -- run secempty.ini
in_system 'particles = 20' >authkey.ini
bad_case authors-key-in-section "authkey.ini:2:" "'particles' is the authors' name of system.N" -- run authkey.ini
{ printf 'particles = 20\nlength = 40\n'; echo '[run]'; echo 'dt = 1e-3'; } >authmix.ini
bad_case authors-then-section "authmix.ini:3:" "[run] after the authors' section-less keys (from line 1)" -- run authmix.ini
printf 'particles = 20\nlength = 40\nparticles = 30\n' >authdup.ini
bad_case authors-duplicate "authdup.ini:3:" "particles (system.N) is set twice" -- run authdup.ini
printf 'particles = 20\nlength = 40\ndiameter = 0x1\n' >authhex.ini
bad_case authors-hex "authhex.ini:3:" "system.sigma = '0x1' is hexadecimal" -- run authhex.ini
printf 'particles = 20\nlength = 40\nN = 20\n' >authn.ini
bad_case authors-hsbd-key "authn.ini:3:" "unknown key 'N' outside any [section]" -- run authn.ini
rods_ini 'every = 1e15' >every.ini
bad_case every-huge "every.ini:15:" "sample.every = 1000000000000000 leaves 0 samples" "1 <= every <= 125" -- run every.ini
rods_ini 'blocks = 1000' | sed '/^blocks = 4$/d' >blocks.ini
bad_case blocks-many "blocks.ini:14:" "sample.blocks = 1000 needs at least as many samples" "2 <= blocks <= 500" -- run blocks.ini
rods_ini 'blocks = 1' | sed '/^blocks = 4$/d' >blocks1.ini
bad_case blocks-one "blocks1.ini:14:" "sample.blocks = 1 is out of range" -- run blocks1.ini
sed 's/^t_total = 0.5$/t_total = 1e300/' good.ini >ttotal.ini
bad_case t-total-huge "ttotal.ini:11:" "run.t_total = 1e+300 over run.dt = 0.001" "run.t_total <= 9e+12" -- run ttotal.ini
sed 's/^t_equil = 0.1$/t_equil = 1e300/' good.ini >tequil.ini
bad_case t-equil-huge "tequil.ini:10:" "run.t_equil = 1e+300" -- run tequil.ini
sed 's/^dt = 1e-3$/dt = 1e-300/' good.ini >dttiny.ini
bad_case dt-tiny "dttiny.ini:9:" "run.dt = 1e-300 gives" "run.dt >= " -- run dttiny.ini
sed 's/^dt = 1e-3$/dt = 1/' good.ini >dtlong.ini
bad_case dt-longer-than-run "dtlong.ini:" "run.t_total = 0.5 is shorter than run.dt = 1" -- run dtlong.ini
sed 's/^N = 20$/N = 2000000000/; s/^L = 40$/L = 1e10/' good.ini >memrods.ini
bad_case memory-rods "memrods.ini:2:" "system.N = 2000000000: the run needs an estimated" "GiB for the particles" -- run memrods.ini
rods_ini 'msd_max_lag = 1e7' | sed 's/^t_total = 0.5$/t_total = 1e8/' >memlag.ini
bad_case memory-msd-lags "memlag.ini:15:" "sample.msd_max_lag = 1e+07" "the MSD's lag table" -- run memlag.ini
rods_ini 'bin_width = 1e-9' | sed '/^bin_width = 0.05$/d' >memprof.ini
bad_case memory-profile "memprof.ini:" "sample.bin_width" "GiB" -- run memprof.ini
mix() { rods_ini '[species]' "$@" | sed '/^sigma = 0.5$/d'; } # species lines from line 15
mix 'names = A A' 'count = 10 10' 'sigma = 0.5 0.5' 'D = 1 1' >spdup.ini
bad_case species-duplicate-names "spdup.ini:15:" "species.names entry 'A' is not allowed" -- run spdup.ini
mix 'names = A-1 B' 'count = 10 10' 'sigma = 0.5 0.5' 'D = 1 1' >spchar.ini
bad_case species-bad-name "spchar.ini:15:" "species.names entry 'A-1'" -- run spchar.ini
mix "names = $(echo {a..q})" 'count = 20' >spmany.ini
bad_case species-too-many "spmany.ini:15:" "1 to 16 names" -- run spmany.ini
mix 'names = A B' 'count = -1 21' 'sigma = 0.5 0.5' 'D = 1 1' >spneg.ini
bad_case species-negative-count "spneg.ini:16:" "species.count entry 1 ('-1'" -- run spneg.ini
mix 'names = A B' 'count = 10 0x0a' 'sigma = 0.5 0.5' 'D = 1 1' >sphex.ini
bad_case species-hex-count "sphex.ini:16:" "species.count entry 2 ('0x0a'" -- run sphex.ini
mix 'names = A B' 'count = 10 10 0' 'sigma = 0.5 0.5' 'D = 1 1' >spthree.ini
bad_case species-count-entries "spthree.ini:16:" "species.count has 3 entries for 2 species.names" -- run spthree.ini
mix 'names = A B' 'count = 10 10' 'sigma = 0.5 inf' 'D = 1 1' >spinf.ini
bad_case species-infinite-sigma "spinf.ini:17:" "species.sigma entry 2 ('inf'" -- run spinf.ini
mix 'names = A B' 'count = 10 10' 'sigma = 0.5 0.5' 'D = 1' >spd.ini
bad_case species-d-entries "spd.ini:18:" "species.D has 1 entries for 2 species.names" -- run spd.ini
mix 'names = A B' 'count = 10 10' 'sigma = 0.5 0.5' >spnod.ini
bad_case species-d-missing "spnod.ini:" "species.D has 0 entries for 2 species.names" -- run spnod.ini
mix 'count = 10 10' >spnonames.ini
bad_case species-no-names "spnonames.ini:15:" "species.count is set but species.names is empty" -- run spnonames.ini
mix 'fraction = 0.5 0.5' 'names = A B' 'sigma = 0.5 0.5' 'D = 1 1' >spfrac.ini
bad_case species-fraction-rods "spfrac.ini:15:" "species.fraction applies to system.model = spheres only" -- run spfrac.ini
bad_case spheres-key-for-rods "system.dimension applies to system.model = spheres only" -- run good.ini --set system.dimension=2
bad_case pair-rule-for-rods "run.pair_rule applies to system.model = spheres only" -- run good.ini --set run.pair_rule=mirror
sph pair-rule-name "run.pair_rule" "one of exact|mirror" -- run sph.ini --set run.pair_rule=bounce

# ---- rods: init.positions ----
pos() { bad_case "$@"; } # pos NAME texts -- run good.ini --set init.positions=FILE
seq 0 2 38 >pos.txt
"$HSBD" run good.ini --set init.positions=pos.txt --out "$T/posok" --quiet || bad "good positions are refused"
sed '5s/.*/9/' pos.txt >overlap.txt
pos positions-overlap "overlap.txt:5:" "the rod at x = 9" "line 6 (x = 10)" "contact distance 1.5" -- run good.ini --set system.sigma=1.5 --set init.positions=overlap.txt
sed '1s/.*/0.5/; 20s/.*/39.5/' pos.txt >wrapoverlap.txt
pos positions-overlap-across-0 "wrapoverlap.txt:20:" "line 1 (x = 0.5)" -- run good.ini --set system.sigma=1.2 --set init.positions=wrapoverlap.txt
sed '3s/.*/41/' pos.txt >beyond.txt
pos positions-beyond-L "beyond.txt:3:" "x = 41 is outside the ring" "0 <= x <= L = 40" -- run good.ini --set init.positions=beyond.txt
sed '4s/.*/-1/' pos.txt >negpos.txt
pos positions-negative "negpos.txt:4:" "x = -1 is outside the ring" -- run good.ini --set init.positions=negpos.txt
sed '1s/.*/0.1/' pos.txt >wallpos.txt
pos positions-walls "wallpos.txt:1:" "outside the walls" -- run good.ini --set system.boundary=walls --set init.positions=wallpos.txt
sed '2s/.*/0x2/' pos.txt >hexpos.txt
pos positions-hex "hexpos.txt:2:" "expected one finite number per line" -- run good.ini --set init.positions=hexpos.txt
sed '2s/.*/2 junk/' pos.txt >junkpos.txt
pos positions-junk "junkpos.txt:2:" "got '2 junk'" -- run good.ini --set init.positions=junkpos.txt
sed '7s/.*/nan/' pos.txt >nanpos.txt
pos positions-nan "nanpos.txt:7:" "one finite number" -- run good.ini --set init.positions=nanpos.txt
{ head -n 3 pos.txt; printf '6\0\n'; tail -n +5 pos.txt; } >nulpos.txt
pos positions-nul "nulpos.txt:4:" "NUL byte" -- run good.ini --set init.positions=nulpos.txt
{ seq 0 2 38; echo 39; } >morepos.txt
pos positions-more "morepos.txt:21:" "more positions than system.N = 20" -- run good.ini --set init.positions=morepos.txt
: >emptypos.txt
pos positions-empty "emptypos.txt: 0 positions for system.N = 20" -- run good.ini --set init.positions=emptypos.txt
mkdir posdir
pos positions-directory "cannot read init.positions file 'posdir': Is a directory" -- run good.ini --set init.positions=posdir
pos positions-missing "cannot read init.positions file 'nosuch.txt'" -- run good.ini --set init.positions=nosuch.txt
head -c 2000 /dev/zero | tr '\0' '\377' >junk.txt
pos positions-binary "junk.txt:1:" -- run good.ini --set init.positions=junk.txt

# analytic pair forces are written in units of sigma: point rods are refused
bad_case pair-yukawa-point-rods "pair.type = yukawa needs system.sigma > 0" -- run good.ini --set system.sigma=0 --set pair.type=yukawa --set pair.strength=1 --set pair.kappa=2
bad_case pair-lj-point-rods "pair.type = lj needs system.sigma > 0" -- run good.ini --set system.sigma=0 --set pair.type=lj --set pair.strength=1

# ---- rods: field.table and pair.table ----
ftab() { bad_case "$@"; }
printf '0 1\n20 0\n40 1\n' >ftab.txt
"$HSBD" run good.ini --set field.type=table --set field.table=ftab.txt --out "$T/ftabok" --quiet || bad "a good field table is refused"
: >ftab-empty.txt
ftab field-table-empty "ftab-empty.txt: a table needs at least 2 points, got 0" -- run good.ini --set field.type=table --set field.table=ftab-empty.txt
printf '0 1\n' >ftab-one.txt
ftab field-table-one-point "ftab-one.txt: a table needs at least 2 points, got 1" -- run good.ini --set field.type=table --set field.table=ftab-one.txt
mkdir tabdir
ftab field-table-directory "cannot read table 'tabdir': Is a directory" -- run good.ini --set field.type=table --set field.table=tabdir
ftab field-table-missing-file "cannot read table 'nosuch.tab'" -- run good.ini --set field.type=table --set field.table=nosuch.tab
printf '0 1\n0x14 0\n40 1\n' >ftab-hex.txt
ftab field-table-hex "ftab-hex.txt:2:" "two finite numbers" -- run good.ini --set field.type=table --set field.table=ftab-hex.txt
printf '0 1\n20 0abc\n40 1\n' >ftab-junk.txt
ftab field-table-junk "ftab-junk.txt:2:" "two finite numbers" -- run good.ini --set field.type=table --set field.table=ftab-junk.txt
printf '0 1\n20\n40 1\n' >ftab-col.txt
ftab field-table-one-column "ftab-col.txt:2:" "two finite numbers" -- run good.ini --set field.type=table --set field.table=ftab-col.txt
printf '0 1\n20 inf\n40 1\n' >ftab-inf.txt
ftab field-table-inf "ftab-inf.txt:2:" "two finite numbers" -- run good.ini --set field.type=table --set field.table=ftab-inf.txt
printf '0 1\n20 0\n20 0.5\n40 1\n' >ftab-dup.txt
ftab field-table-repeated-x "ftab-dup.txt:3:" "does not increase" -- run good.ini --set field.type=table --set field.table=ftab-dup.txt
printf '0 1\n20 0\n40 1e999\n' >ftab-big.txt
ftab field-table-overflow "ftab-big.txt:3:" "two finite numbers" -- run good.ini --set field.type=table --set field.table=ftab-big.txt
{ printf '0 1\n# '; head -c 1100000 /dev/zero | tr '\0' c; printf '\n20 0\n40 1\n'; } >ftab-long.txt
ftab field-table-long-line "ftab-long.txt:2:" "line longer than" -- run good.ini --set field.type=table --set field.table=ftab-long.txt
printf '0 1\n20\0 0\n40 1\n' >ftab-nul.txt
ftab field-table-nul "ftab-nul.txt:2:" "NUL byte" -- run good.ini --set field.type=table --set field.table=ftab-nul.txt
head -c 3000 /dev/zero | tr '\0' '\001' >ftab-bin.txt
ftab field-table-binary "ftab-bin.txt:1:" -- run good.ini --set field.type=table --set field.table=ftab-bin.txt
ftab field-table-kind "field.table_kind = 'energy' is not known" -- run good.ini --set field.type=table --set field.table=ftab.txt --set field.table_kind=energy
printf '0.5 1\n0.8 0.5\n1.0 0\n' >ptab.txt
"$HSBD" run good.ini --set pair.type=table --set pair.table=ptab.txt --out "$T/ptabok" --quiet || bad "a good pair table is refused"
ftab pair-table-directory "cannot read table 'tabdir': Is a directory" -- run good.ini --set pair.type=table --set pair.table=tabdir
ftab pair-table-empty "ftab-empty.txt: a table needs at least 2 points, got 0" -- run good.ini --set pair.type=table --set pair.table=ftab-empty.txt
printf '0.5 1\n0.8 0.5\n1.0 0.1\n' >ptab-end.txt
ftab pair-table-end "ptab-end.txt" "not 0" -- run good.ini --set pair.type=table --set pair.table=ptab-end.txt
printf '0.5 1\n0.8 0.5\n30 0\n' >ptab-far.txt
ftab pair-table-beyond-half "ptab-far.txt" -- run good.ini --set pair.type=table --set pair.table=ptab-far.txt
printf '0.5 1\n0.8 0x1\n1.0 0\n' >ptab-hex.txt
ftab pair-table-hex "ptab-hex.txt:2:" "two finite numbers" -- run good.ini --set pair.type=table --set pair.table=ptab-hex.txt
ftab pair-table-for-spheres "pair.type applies to system.model = rods only" -- run sph.ini --set pair.type=table --set pair.table=ptab.txt

# ---- spheres: configuration ----
sph_box() { # a quick spheres configuration with system.box = $1 in dimension $2
    printf '[system]\nmodel = spheres\ndimension = %s\nN = 20\nbox = %s\n' "$2" "$1"
    printf '[run]\ndt = 1e-3\nt_equil = 0.01\nt_total = 0.1\n[sample]\nblocks = 4\n'
}
sph_box '12 12' 3 >box2in3.ini
bad_case box-entries "box2in3.ini:5:" "system.box has 2 values; allowed: 1 or 3" -- run box2in3.ini
sph_box '12 -12' 2 >boxneg.ini
bad_case box-negative "boxneg.ini:5:" "system.box value '-12' is out of range" -- run boxneg.ini
sph_box '0x10' 2 >boxhex.ini
bad_case box-hex "boxhex.ini:5:" "system.box value '0x10'" -- run boxhex.ini
sph_box '12' 3 >box3.ini
bad_case box-and-fraction "box3.ini:5:" "exactly one of system.box and system.packing_fraction (both are set)" -- run box3.ini --set system.packing_fraction=0.1
sed '/^box/d' box3.ini >nobox.ini
bad_case box-neither "nobox.ini:2:" "(neither is set)" -- run nobox.ini
sph_box '2' 3 >boxfull.ini
bad_case box-too-small "boxfull.ini:5:" "exceeds close packing" -- run boxfull.ini
bad_case drift-one-value "system.drift has 1 value; allowed: 3 (system.dimension)" -- run box3.ini --set system.drift=1
bad_case drift-two-values "system.drift has 2 values; allowed: 3" -- run box3.ini --set "system.drift=1 1"
bad_case drift-nan "system.drift value 'nan'" -- run box3.ini --set "system.drift=1 nan 0"
bad_case dimension-4 "system.dimension = 4 is out of range" -- run box3.ini --set system.dimension=4
bad_case memory-spheres "system.N = 2147483647: the run needs an estimated" "GiB for the particles" -- run sph.ini --set system.N=2147483647 --set output.trajectory=none
bad_case memory-gr "sample.gr_bin = 1e-09" "g(r)'s bins" -- run box3.ini --set sample.gr_bin=1e-9
bad_case spheres-fraction-sum "species.fraction sums to 0.9" -- run box3.ini --set "species.names=A B" --set "species.fraction=0.5 0.4" --set "species.sigma=1 1" --set "species.D=1 1"
bad_case spheres-fraction-and-count "species.count and species.fraction" -- run box3.ini --set "species.names=A B" --set "species.fraction=0.5 0.5" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 1"
bad_case spheres-rods-key "contact.gamma applies to system.model = rods only" -- run box3.ini --set contact.gamma=0.5
# walls and fields of spheres
printf '[system]\nmodel = spheres\ndimension = 2\nN = 2\nbox = 12 0.8\nboundary = periodic walls\n[run]\ndt = 1e-3\nt_equil = 0.01\nt_total = 0.1\n[sample]\nblocks = 4\n' >slitthin.ini
bad_case walls-narrow "slitthin.ini:6:" "between walls is shorter than the largest diameter 1" -- run slitthin.ini
bad_case boundary-word "command line (--set) system.boundary" "system.boundary = 'wall' is not known; allowed: periodic or walls" -- run box3.ini --set system.boundary=wall
bad_case boundary-count "system.boundary has 2 values; allowed: 1 or one per axis" -- run box3.ini --set "system.boundary=walls walls"
bad_case field-axis-2d "field.axis = z is beyond system.dimension = 2" -- run sph.ini --set field.type=tilt --set field.axis=z
bad_case field-cosine-period "field.wavelength = 5 must divide the periodic box length 12 along field.axis = z" -- run box3.ini --set field.type=cosine --set field.wavelength=5
bad_case coupling-count "species.coupling has 1 entries for 2 species.names" -- run box3.ini --set "species.names=A B" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 1" --set species.coupling=1 --set field.type=tilt
bad_case coupling-and-law "species.coupling is set with species.coupling_law = volume" -- run box3.ini --set "species.names=A B" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 1" --set "species.coupling=1 2" --set species.coupling_law=volume --set field.type=tilt
bad_case coupling-no-species "species.coupling is set but species.names is empty" -- run box3.ini --set species.coupling=2 --set field.type=tilt
bad_case force-immobile "a field acts on species B, whose D = 0 cannot move" -- run box3.ini --set "species.names=A B" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 0" --set field.type=tilt
bad_case drift-immobile "system.drift with species B, whose D = 0 cannot move" -- run box3.ini --set "species.names=A B" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 0" --set "system.drift=1 0 0"
# active particles
bad_case active-v0-negative "command line (--set) active.v0" "active.v0 value '-1' is out of range; allowed: finite decimal numbers 0 <= v0 < inf" -- run box3.ini --set active.v0=-1
bad_case active-dr-negative "active.rotational_D value '-0.5' is out of range; allowed: finite decimal numbers 0 <= rotational_D < inf" -- run box3.ini --set active.v0=1 --set active.rotational_D=-0.5
bad_case active-v0-count "active.v0 has 3 values for 2 species; allowed: one value, or one per species" -- run box3.ini --set "species.names=A B" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 1" --set "active.v0=1 2 3"
bad_case active-immobile "active.v0 = 2 for species B, whose D = 0 cannot move; allowed: v0 = 0 for it" -- run box3.ini --set "species.names=A B" --set "species.count=10 10" --set "species.sigma=1 1" --set "species.D=1 0" --set active.v0=2
bad_case active-rotational-alone "active.rotational_D is set but active.v0 is empty" -- run box3.ini --set active.rotational_D=1
bad_case active-rods "active.v0 applies to system.model = spheres only, but the model is rods" -- run --defaults --set active.v0=1
printf '2\nLattice="12 0 0 0 12 0 0 0 12" Properties=species:S:1:pos:R:3:radius:R:1:orientation:R:4\nS 1 1 1 0.5 0 0 0 1\nS 5 5 5 0.5 0 0 0 0\n' >zeroquat.xyz
bad_case active-zero-quaternion "zeroquat.xyz:4: the orientation (columns 6-9, quaternion x y z w) is not four finite numbers of a rotation" -- run box3.ini --set system.N=2 --set active.v0=1 --set init.positions=zeroquat.xyz
printf '[system]\nmodel = rods\n[active]\nv0 = 3\n' >rodsactive.ini
bad_case active-rods-file "rodsactive.ini:4:" "active.v0 applies to system.model = spheres only" -- run rodsactive.ini
printf '2\nLattice="12 0 0 0 12 0 0 0 12" Properties=species:S:1:pos:R:3\nS 1 1 1\nS 5 5 0.2\n' >wallpos.xyz
bad_case memory-profiles "sample.bin_width = 1e-09" "the density profiles' bins" -- run box3.ini --set system.boundary=walls --set sample.bin_width=1e-9
bad_case xyz-outside-walls "wallpos.xyz:4: particle 2 at z = 0.2 is outside the walls" "allowed: sigma/2 = 0.5 <= z" -- run box3.ini --set system.N=2 --set system.boundary=walls --set init.positions=wallpos.xyz

# ---- the command line ----
: >plainfile
bad_case run-out-proc "cannot create output directory '/proc/x'" -- run good.ini --quiet --out /proc/x
bad_case run-out-file "output path 'plainfile' exists and is not a directory" -- run good.ini --quiet --out plainfile
bad_case run-out-under-file "cannot create output directory 'plainfile/run'" -- run good.ini --quiet --out plainfile/run
bad_case out-without-value "--out needs a value" -- run good.ini --out
bad_case out-then-flag "--out needs a value, but the next argument '--quiet' is a flag" -- run good.ini --out --quiet
bad_case set-then-flag "--set needs a value, but the next argument '--out' is a flag" -- run good.ini --set --out x
bad_case set-without-equals "--set needs section.key=value, not 'run.dt'" -- run good.ini --set run.dt
bad_case set-value-apart "--set needs section.key=value, not 'run.t_total' (write --set run.t_total=5)" -- run good.ini --set run.t_total 5
bad_case set-without-section "command line (--set) 'dt=1': expected section.key=value" -- run good.ini --set dt=1
bad_case set-unknown-section "unknown key 'sytem.N'; did you mean 'system.N'?" -- run good.ini --set sytem.N=5
bad_case set-control "argument 4 (the value of --set) has a control character (0x0a at position 13)" -- run good.ini --set "$(printf 'output.dir=a\nb')"
bad_case set-long "is longer than" -- run good.ini --set "output.dir=$(head -c 3000 /dev/zero | tr '\0' d)"
bad_case seed-flag "command line (--seed)" "system.seed = 'x'" -- run good.ini --seed x
bad_case seed-without-value "--seed needs a value" -- run good.ini --seed
bad_case two-configs "more than one configuration file ('good.ini', 'other.ini')" -- run good.ini other.ini
bad_case unknown-flag "unknown option '-x'" -- run good.ini -x
bad_case theory-out-missing-dir "--out '/nonexistent/f': cannot write there" -- theory percus --sigma 0.5 --rho 0.5 --amplitude 6 --out /nonexistent/f
bad_case theory-out-proc "--out '/proc/x': cannot write there" -- theory percus --sigma 0.5 --rho 0.5 --amplitude 1 --out /proc/x
bad_case theory-out-proc-box "--out '/proc/x': cannot write there" -- theory box --N 3 --L 10 --sigma 1 --out /proc/x
bad_case theory-out-directory "--out '.': cannot write there: it names a directory" -- theory percus --sigma 0.5 --rho 0.5 --amplitude 6 --out .
bad_case theory-out-no-value "--out needs a value (nothing follows it)" -- theory percus --sigma 0.5 --rho 0.5 --amplitude 6 --out
bad_case theory-no-out "--out FILE (or - for standard output) is required" -- theory percus --sigma 0.5 --rho 0.5 --amplitude 6
bad_case theory-flag-value "--sigma needs a value, but the next argument '--rho' is a flag" -- theory tonks --sigma --rho 0.5
bad_case theory-range "--rho = '-1'; allowed: 0 < rho < inf" -- theory tonks --sigma 0.5 --rho -1
bad_case theory-unknown "unknown option '--frobnicate'" -- theory tonks --sigma 0.5 --rho 0.5 --frobnicate 1
bad_case theory-which "hsbd theory: unknown theory 'maxwell'; allowed: percus, tonks, box, washboard" -- theory maxwell
bad_case theory-washboard-tilt "give --force F, or --force-min A --force-max B --forces K" -- theory washboard --amplitude 2 --out -
bad_case theory-washboard-both "give --force F, or --force-min A" -- theory washboard --amplitude 2 --force 1 --forces 3 --force-min 0 --force-max 1 --out -
bad_case theory-washboard-range "--amplitude = '1e5'; allowed: -10000 <= amplitude <= 10000" -- theory washboard --amplitude 1e5 --force 1 --out -
bad_case theory-box-whole "need whole --N" -- theory box --N 2.5 --L 10 --sigma 1 --out -
bad_case bench-case "--case: no case named 'nope' (hsbd bench --list names them)" -- bench --case nope
bad_case bench-seconds "--seconds needs a value" -- bench --seconds
bad_case bench-seconds-range "--seconds = '0'; allowed: 0 < S < 3600" -- bench --seconds 0
bad_case validate-jobs "--jobs = '0'; allowed: 1 <= jobs <= 64" -- validate --jobs 0
bad_case validate-out "--out needs a value" -- validate --out
bad_case validate-unknown "unknown option '--fast'" -- validate --fast
bad_case config-doc-argument "unexpected argument 'x'" -- config-doc x

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
