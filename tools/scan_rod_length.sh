#!/usr/bin/env bash
# Particle current of hard rods in a tilted cosine potential against the rod length
# (docs/validation.md, section 17, "Current against rod length"). U(x) = (U0/2)
# cos(2 pi x / lambda) - F x with U0 = 6 kT, lambda = 1, F = 8 (critical tilt
# pi U0 / lambda = 18.85), D = kT = 1, N = 160, L = 400 (density 0.4; N=, L= in the
# environment change them), dt 1e-4, t = 100 after 10 of
# equilibration, 20 time blocks, seed 1. Prints one row per rod length:
#   sigma N L J J_err v v_err J/J_single (v - v_single)/v_err
# where v_single is the exact one-particle drift (hsbd theory washboard). For sigma a
# whole multiple of lambda the last column is exact to compare against (docs/theory.md,
# "Driven rods"); for the others it only measures the interaction effect.
# Extra rows (density 2/3, N 160, L 240) test the exact shift sigma -> sigma - lambda,
# rho -> rho / (1 - rho lambda) against the rows sigma + 1 at density 0.4.
# usage: [N=160 L=400] tools/scan_rod_length.sh build/hsbd [sigma ...]   (about 2 minutes
# on two cores; the extra rows only with the default sigma list)
set -u
HSBD=${1:?usage: scan_rod_length.sh path/to/hsbd [sigma ...]}
shift
N=${N:-160}
L=${L:-400}
SIGMAS=${*:-$(seq 0.1 0.1 2.0)}
EXTRA=$([ $# -eq 0 ] && printf '0.3 160 240\n0.5 160 240\n')
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
run_one() { # sigma N L
    nice -n 10 "$HSBD" run --defaults --set system.N="$2" --set system.L="$3" \
        --set system.sigma="$1" --set system.seed=1 --set field.type=cosine+tilt \
        --set field.amplitude=6 --set field.wavelength=1 --set field.force=8 \
        --set run.dt=1e-4 --set run.t_equil=10 --set run.t_total=100 \
        --set sample.blocks=20 --set sample.every=100 --out "$T/$1-$2-$3" --quiet \
        >/dev/null 2>"$T/$1-$2-$3.err" || echo "run sigma $1 N $2 L $3 failed" >&2
}
export -f run_one
export HSBD T
{
    for s in $SIGMAS; do echo "$s $N $L"; done
    [ -n "$EXTRA" ] && echo "$EXTRA"
} | xargs -P 2 -n 3 bash -c 'run_one "$@"' _
V1=$("$HSBD" theory washboard --amplitude 6 --force 8 --out - | awk '$1 ~ /^[-0-9.]/ {print $2; exit}')
echo "# v_single = $V1"
echo "# sigma N L J J_err v v_err J/J_single (v-v_single)/v_err"
field() { grep -o "\"$2\": [-0-9.e+]*" "$1" | head -n 1 | awk '{print $2}'; }
for d in $(ls "$T" | grep -v '\.err$' | sort -t- -k3,3nr -k1,1g); do
    s="$T/$d/summary.json"
    [ -f "$s" ] || continue
    set -- $(echo "$d" | tr - ' ')
    J=$(field "$s" particle_current); JE=$(field "$s" particle_current_err)
    V=$(field "$s" mean_velocity); VE=$(field "$s" mean_velocity_err)
    awk -v s="$1" -v n="$2" -v l="$3" -v j="$J" -v je="$JE" -v v="$V" -v ve="$VE" -v v1="$V1" \
        'BEGIN { printf "%s %s %s %.5f %.5f %.5f %.5f %.4f %+.2f\n", s, n, l, j, je, v, ve, j / (n / l * v1), (v - v1) / ve }'
done
