#!/usr/bin/env bash
# The command line and the configuration reader on good input: spheres in a box given by
# system.box (2D and 3D, one length or one per dimension), --defaults, comments of any
# length (never read as keys), inline comments, a UTF-8 byte-order mark, --help of every
# subcommand, bench --list, theory output to a file or standard output, GNU-style
# --name=value options.
set -u
HSBD=${1:?usage: test_cli_options.sh path/to/hsbd}
HSBD=$(cd "$(dirname "$HSBD")" && pwd)/$(basename "$HSBD")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# spheres from system.box: the box as given, phi = N v / V (v: pi/4 or pi/6 for sigma = 1)
sph_box() {
    printf '[system]\nmodel = spheres\ndimension = %s\nN = 50\nbox = %s\n' "$1" "$2"
    printf '[run]\ndt = 1e-3\nt_equil = 0.01\nt_total = 0.1\n[sample]\nblocks = 4\n'
}
for spec in "2|12|12 12 0" "2|12, 10|12 10 0" "3|8|8 8 8" "3|8 9 10|8 9 10"; do
    IFS='|' read -r dim box want <<<"$spec"
    sph_box "$dim" "$box" >box.ini
    name="box-$dim-${box// /_}"
    if "$HSBD" run box.ini --out "$name" --quiet 2>"$T/stderr" &&
        python3 -c "
import json, math, sys
d = json.load(open('$name/summary.json'))
want = [float(w) for w in '$want'.split()]
assert d['box'] == want, d['box']
v = math.pi / 4 if $dim == 2 else math.pi / 6
V = want[0] * want[1] * (want[2] if $dim == 3 else 1)
assert abs(d['parameters']['system']['packing_fraction'] - 50 * v / V) < 1e-9
" && grep -q "^# system.box = $box\$" "$name/gr.tsv"; then ok; else bad "spheres with system.box = $box in ${dim}D: $(cat "$T/stderr")"; fi
done
# a drift with one value per dimension
sph_box 3 8 >drift.ini
"$HSBD" run drift.ini --set "system.drift=0.5 0 0" --out drift --quiet && ok || bad "system.drift with 3 values"

# GNU-style options: --name=value is --name value (--set=key=value too), same results
"$HSBD" run drift.ini --quiet --threads 1 --seed 5 --set run.t_total=0.05 --out gnu-apart &&
    "$HSBD" run drift.ini --quiet --threads=1 --seed=5 --set=run.t_total=0.05 --out=gnu-joined &&
    cmp -s gnu-apart/msd.tsv gnu-joined/msd.tsv && grep -q '"seed": 5,' gnu-joined/summary.json &&
    ok || bad "GNU-style --name=value options"

# hsbd validate --quick: its help says how many cases it runs, as many as it lists; a
# line on stderr as each case's simulation ends
said=$("$HSBD" validate --help | grep -o -E '[0-9]+ short cases' | cut -d' ' -f1)
listed=$("$HSBD" validate --quick --list | wc -l)
[ -n "$said" ] && [ "$said" = "$listed" ] && ok || bad "validate --quick: help says '$said' cases, it lists $listed"
if "$HSBD" validate --quick --case tonks --out vq >/dev/null 2>vq.err &&
    grep -q -E '^hsbd validate: \[1/1\] tonks-s0.5-rho0.5: simulated in [0-9]+ s$' vq.err; then ok
else bad "validate: a line per case: $(cat vq.err)"; fi

# --defaults: no file, every key at its default, into runs/defaults
if "$HSBD" run --defaults --set run.t_total=0.01 --set run.t_equil=0 --set run.dt=1e-3 \
    --set sample.blocks=2 --quiet && grep -q '"completed": true' runs/defaults/summary.json &&
    grep -q '^# system.N = 50$' runs/defaults/density.tsv; then ok; else bad "--defaults"; fi

base() {
    printf '[system]\nN = 20\nL = 40\n[run]\ndt = 1e-3\nt_equil = 0.1\nt_total = 0.5\n'
    printf '[sample]\nbin_width = 0.05\nblocks = 4\n'
}
# a comment line longer than any buffer, whose tail reads like a key, stays a comment
{ base; printf '; '; head -c 197 /dev/zero | tr '\0' x; printf 'kT = 5\n# '; head -c 5000 /dev/zero | tr '\0' y; printf ' N = 7\n'; } >long.ini
if "$HSBD" run long.ini --out long --quiet && grep -q '^# system.kT = 1$' long/density.tsv &&
    grep -q '^# system.N = 20$' long/density.tsv; then ok; else bad "the tail of a long comment was read"; fi
# inline comments after a blank, a byte-order mark, CRLF line ends, indented keys
{ printf '\xef\xbb\xbf'; base | sed 's/^N = 20$/N = 20 ; twenty/; s/^L = 40$/  L = 40 # forty/'; } | sed 's/$/\r/' >marks.ini
if "$HSBD" run marks.ini --out marks --quiet && grep -q '^# system.L = 40$' marks/density.tsv; then ok; else bad "inline comments, BOM, CRLF"; fi
# a table whose comment line is longer than 4096 characters
base >tab.ini
{ printf '0 1\n# '; head -c 5000 /dev/zero | tr '\0' c; printf ' 20 7\n40 1\n'; } >tab.txt
if "$HSBD" run tab.ini --set field.type=table --set field.table=tab.txt --out tab --quiet; then ok; else bad "a long comment in a table"; fi

# every subcommand takes --help (usage on standard output, exit 0)
for cmd in "run" "bench" "theory" "theory percus" "theory tonks" "theory box" "theory washboard" "validate" "config-doc"; do
    # shellcheck disable=SC2086
    if "$HSBD" $cmd --help >help.txt 2>"$T/stderr" && grep -q '^usage: ' help.txt && [ ! -s "$T/stderr" ]; then ok
    else bad "hsbd $cmd --help"; fi
done
"$HSBD" --help | grep -q "Every subcommand takes --help" && ok || bad "hsbd --help"
# bench --list names the cases of both tables, one per line
if "$HSBD" bench --list >cases.txt && grep -qx 's0.5-rho0.5' cases.txt &&
    grep -qx 'spheres-N4000-phi0.3-dt1e-3' cases.txt && [ "$(sort -u cases.txt | wc -l)" -ge 10 ]; then ok
else bad "bench --list"; fi

# theory into a file (atomically: no .part left) and to standard output
if "$HSBD" theory percus --sigma 0.5 --rho 0.5 --amplitude 2 --points 64 --out sub/../p.tsv 2>/dev/null; then
    bad "theory wrote into a missing directory"
else ok; fi
mkdir sub
if "$HSBD" theory percus --sigma 0.5 --rho 0.5 --amplitude 2 --points 64 --out sub/p.tsv &&
    [ -s sub/p.tsv ] && [ ! -e sub/p.tsv.part ] &&
    "$HSBD" theory percus --sigma 0.5 --rho 0.5 --amplitude 2 --points 64 --out - | cmp -s - sub/p.tsv; then ok
else bad "theory percus --out"; fi

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
