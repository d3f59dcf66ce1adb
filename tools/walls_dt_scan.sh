#!/usr/bin/env bash
# Time-step scans of spheres between walls and in fields (docs/validation.md, "Spheres
# between walls"): prints one row per case and dt.
#   wall   hard spheres (N 200, box 5 x 5 x 14, gravity -0.5): kT (rho_low - rho_high) from
#          the walls' impulses vs the weight per area 4, and the floor's contact density
#          from the impulses and from the profile
#   slit   hard spheres (N 206, box 6 x 6 x 12, no field): the contact density (mean of the
#          two walls) vs beta P(rho_mid) of Kolafa-Labik-Malijevsky, rho_mid from the
#          middle 4 sigma of density.tsv
#   cosine ideal particles (N 2000, sigma 0.1) in U = 2 cos(pi x) on a periodic axis: the
#          profile folded into one period vs Boltzmann, the largest relative deviation and
#          chi^2 per bin (the Euler error of the start-of-step force)
# The wall and slit rows fail (exit status 1) beyond 4 error bars; the cosine rows
# measure the Euler error and are not judged.
# usage: tools/walls_dt_scan.sh build/hsbd [case ...]   (about 15 minutes on one core)
set -u
HSBD=${1:?usage: walls_dt_scan.sh path/to/hsbd [wall|slit|cosine ...]}
shift
CASES=${*:-wall slit cosine}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
status=0
field() { grep -o "\"$2\": [-0-9.e+]*" "$1" | head -n "${3:-1}" | tail -n 1 | awk '{print $2}'; }
for c in $CASES; do
case $c in
wall)
    printf '[system]\nmodel = spheres\nN = 200\nbox = 5 5 14\nboundary = periodic periodic walls\nseed = 1\n[field]\ntype = tilt\nforce = -0.5\n[run]\nt_equil = 20\nt_total = 100\n[output]\ntrajectory = none\n' >"$T/wall.ini"
    for dt in 4e-3 2e-3 1e-3 5e-4; do
        "$HSBD" run "$T/wall.ini" --set run.dt=$dt --out "$T/w$dt" --quiet 2>/dev/null || { echo "wall dt $dt failed"; continue; }
        s="$T/w$dt/summary.json"
        lo=$(field "$s" contact_density 1); loe=$(field "$s" contact_density_err 1)
        lop=$(field "$s" contact_density_profile 1); lope=$(field "$s" contact_density_profile_err 1)
        hi=$(field "$s" contact_density 3); hie=$(field "$s" contact_density_err 3)
        awk -v dt=$dt -v lo=$lo -v loe=$loe -v hi=$hi -v hie=$hie -v lop=$lop -v lope=$lope 'BEGIN {
            d = lo - hi; e = sqrt(loe * loe + hie * hie);
            printf "wall dt %s: rho_low - rho_high %.4f +- %.4f (weight/area 4, %+.2f error bars); floor contact: impulses %.4f +- %.4f, profile %.4f +- %.4f\n",
                   dt, d, e, (d - 4) / e, lo, loe, lop, lope; exit ((d - 4)^2 > 16 * e^2) }' || status=1
    done ;;
slit)
    printf '[system]\nmodel = spheres\nN = 206\nbox = 6 6 12\nboundary = periodic periodic walls\nseed = 1\n[run]\nt_equil = 5\nt_total = 200\n[sample]\nbin_width = 0.1\n[output]\ntrajectory = none\n' >"$T/slit.ini"
    for dt in 4e-3 2e-3 1e-3 5e-4; do
        "$HSBD" run "$T/slit.ini" --set run.dt=$dt --out "$T/s$dt" --quiet 2>/dev/null || { echo "slit dt $dt failed"; continue; }
        s="$T/s$dt/summary.json"
        lo=$(field "$s" contact_density 1); loe=$(field "$s" contact_density_err 1)
        hi=$(field "$s" contact_density 3); hie=$(field "$s" contact_density_err 3)
        grep -v '^#' "$T/s$dt/density.tsv" | awk -v dt=$dt -v lo=$lo -v loe=$loe -v hi=$hi -v hie=$hie '
            $1 > 4 && $1 < 8 { r += $2; v += $3 * $3; n++ }
            END { rho = r / n; re = sqrt(v) / n; pi = 3.14159265358979;
                  # Kolafa-Labik-Malijevsky Z (src/theory/hardspheres.c)
                  phi = rho * pi / 6; q = 1 - phi; z = (1 + phi + phi^2 - 2 / 3 * (phi^3 + phi^4)) / q^3;
                  p2 = (rho + 1e-4) * pi / 6; q2 = 1 - p2; z2 = (1 + p2 + p2^2 - 2 / 3 * (p2^3 + p2^4)) / q2^3;
                  bp = rho * z; bpe = ((rho + 1e-4) * z2 - bp) / 1e-4 * re;
                  c = (lo + hi) / 2; ce = sqrt(loe * loe + hie * hie) / 2;
                  dev = (c - bp) / sqrt(ce * ce + bpe * bpe)
                  printf "slit dt %s: contact %.4f +- %.4f (walls %.4f, %.4f); rho_mid %.4f +- %.4f, KLM beta P %.4f +- %.4f; %+.2f combined error bars\n",
                         dt, c, ce, lo, hi, rho, re, bp, bpe, dev; exit (dev^2 > 16) }' || status=1
    done ;;
cosine)
    printf '[system]\nmodel = spheres\nN = 2000\nsigma = 0.1\nbox = 4 4 4\nhard_core = off\nseed = 1\n[field]\ntype = cosine\namplitude = 4\nwavelength = 2\naxis = x\n[run]\nt_equil = 2\nt_total = 50\n[sample]\nbin_width = 0.05\n[output]\ntrajectory = none\n' >"$T/cos.ini"
    for dt in 1e-2 3e-3 1e-3 3e-4; do
        "$HSBD" run "$T/cos.ini" --set run.dt=$dt --out "$T/c$dt" --quiet 2>/dev/null || { echo "cosine dt $dt failed"; continue; }
        grep -v '^#' "$T/c$dt/density.tsv" | awk -v dt=$dt 'BEGIN { n = 0 } { x[n] = $1; r[n] = $2; e[n] = $3; n++ }
            END { pi = 3.14159265358979; w = 0.05; m = 2000 / 64;
                  # Boltzmann: m exp(-2 cos(pi x)) / I0(2), averaged over each bin (Simpson)
                  i0 = 2.2795853023360673;
                  for (k = 0; k < n; k++) {
                      s = 0; for (j = 0; j <= 20; j++) { xx = x[k] - w / 2 + w * j / 20; f = exp(-2 * cos(pi * xx));
                          s += (j == 0 || j == 20 ? 1 : (j % 2 ? 4 : 2)) * f }
                      th = m * s * (w / 20) / 3 / w / i0;
                      d = (r[k] - th) / th; if (d * d > worst * worst) worst = d;
                      chi += (r[k] - th)^2 / e[k]^2 }
                  printf "cosine dt %s: largest relative deviation from Boltzmann %+.4f, chi^2 per bin %.2f (%d bins)\n", dt, worst, chi / n, n }'
    done ;;
*) echo "unknown case $c" ;;
esac
done
exit $status
