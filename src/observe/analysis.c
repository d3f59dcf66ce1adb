/* Analysis of the spheres' results (include/hsbd/observe.h): the scheme's assumptions
 * (Scala Sec. II) from the particles' own diameters and D, the long-time diffusion
 * coefficient from the MSD, and the size classes through which the equations of state
 * of mixtures and polydisperse fluids are compared with the simulated contact values. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hsbd/observe.h"
#include "hsbd/theory.h"

/* E|N_d| for a d-dimensional standard normal: sqrt(2) Gamma((d+1)/2) / Gamma(d/2) */
static double mean_norm(int dim) {
    return dim == 3 ? 1.5957691216057308 : 1.2533141373155003;
}

void hsbd_scheme_check_compute(const hsbd_spheres_view *v, double collisions_per_particle_step,
                               hsbd_scheme_check *out) {
    const double c = mean_norm(v->dimension);
    double worst_sigma = 0, worst_step = 0, sum_sigma = 0, volume = 1;
    for (size_t i = 0; i < v->n; ++i) {
        /* <|dr_i|>, Eq. 2, and an active particle's propulsion v0 dt on top */
        const double step =
            c * sqrt(2.0 * v->diffusion[i] * v->dt) + (v->v0 ? v->v0[i] * v->dt : 0);
        worst_sigma = fmax(worst_sigma, step / v->sigma[i]);
        worst_step = fmax(worst_step, step);
        sum_sigma += v->sigma[i];
    }
    for (int a = 0; a < v->dimension; ++a)
        volume *= v->box[a];
    /* Eq. 3's mean gap rho^(-1/d) - sigma turns negative at phi = pi/6 (3D), pi/4 (2D), in
     * fluids that are still far from dense; the nearest-neighbour distance of the densest
     * lattice at the same number density (fcc: rho a^3 = sqrt 2; hexagonal: rho a^2 =
     * 2 / sqrt 3) stays positive up to close packing and equals rho^(-1/d) within 12 % */
    const double per = v->dimension == 3 ? sqrt(2.0) : 2.0 / sqrt(3.0);
    const double gap =
        pow(per * volume / (double)v->n, 1.0 / v->dimension) - sum_sigma / (double)v->n;
    out->step_over_sigma = worst_sigma;
    out->step_over_gap = gap > 0 ? worst_step / gap : NAN; /* none at close packing */
    out->collisions_per_particle_step = collisions_per_particle_step;
}

int hsbd_scheme_check_warnings(const hsbd_scheme_check *c, char (*msg)[HSBD_WARNING_LEN], int max) {
    int n = 0;
    if (n < max && c->step_over_sigma > HSBD_SCHEME_STEP_SIGMA_MAX)
        snprintf(msg[n++], HSBD_WARNING_LEN,
                 "the mean step is %.3g of a particle's diameter: the flat-wall collision rule "
                 "needs << 1 (Scala Eq. 6; warned above %g; smaller run.dt)",
                 c->step_over_sigma, HSBD_SCHEME_STEP_SIGMA_MAX);
    if (n < max && c->step_over_gap > HSBD_SCHEME_STEP_GAP_MAX)
        snprintf(msg[n++], HSBD_WARNING_LEN,
                 "the mean step is %.3g of the mean gap (the lattice spacing at this density "
                 "minus sigma): binary collisions need << 1 (Scala Eq. 3; warned above %g; "
                 "smaller run.dt)",
                 c->step_over_gap, HSBD_SCHEME_STEP_GAP_MAX);
    if (n < max && c->collisions_per_particle_step > HSBD_SCHEME_COLLISIONS_MAX)
        snprintf(msg[n++], HSBD_WARNING_LEN,
                 "%.3g collisions per particle and step: the binary-collision picture needs "
                 "well below one (warned above %g; smaller run.dt)",
                 c->collisions_per_particle_step, HSBD_SCHEME_COLLISIONS_MAX);
    return n;
}

/* The lags of the D_L estimate: the largest with at least two origins (k1) and the first
 * at or beyond a tenth of it (k0); 0 when there are too few lags. */
static int long_time_lags(const hsbd_msd *m, size_t *k0, size_t *k1) {
    const size_t nl = hsbd_msd_lags(m);
    double t1, m1, e1;
    size_t o1, last = nl;
    for (size_t k = nl; k-- > 0;) {
        hsbd_msd_result(m, k, &t1, &m1, &e1, &o1);
        if (o1 >= 2) {
            last = k;
            break;
        }
    }
    if (last == nl) return 0;
    for (size_t k = 0; k < last; ++k) {
        double t0, m0, e0;
        size_t o0;
        hsbd_msd_result(m, k, &t0, &m0, &e0, &o0);
        if (t0 >= 0.1 * t1) {
            *k0 = k, *k1 = last;
            return 1;
        }
    }
    return 0;
}

/* D_L from the MSD: slope between the largest lag with two origins and the first lag of at
 * least a tenth of it, over 2 d (the MSD of coordinates times d); the two errors combined
 * in quadrature (they are positively correlated: conservative). */
void hsbd_msd_long_time_diffusion(const hsbd_msd *m, int dimension, double *dl, double *err) {
    *dl = *err = NAN;
    size_t k0, k1, o;
    if (!long_time_lags(m, &k0, &k1)) return;
    const double d = (double)dimension;
    double t0, m0, e0, t1, m1, e1;
    hsbd_msd_result(m, k0, &t0, &m0, &e0, &o);
    hsbd_msd_result(m, k1, &t1, &m1, &e1, &o);
    *dl = d * (m1 - m0) / (2 * d * (t1 - t0));
    *err = d * sqrt(e1 * e1 + e0 * e0) / (2 * d * (t1 - t0));
}

void hsbd_msd_long_time_lags(const hsbd_msd *m, double *t0, double *t1) {
    *t0 = *t1 = NAN;
    size_t k0, k1, o;
    double v, e;
    if (!long_time_lags(m, &k0, &k1)) return;
    hsbd_msd_result(m, k0, t0, &v, &e, &o);
    hsbd_msd_result(m, k1, t1, &v, &e, &o);
}

void hsbd_size_classes_build(const hsbd_spheres_view *v, size_t nspecies, hsbd_size_classes *c) {
    double lo[HSBD_SIZE_CLASS_SPECIES], hi[HSBD_SIZE_CLASS_SPECIES];
    for (size_t k = 0; k < nspecies; ++k)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    for (size_t i = 0; i < v->n; ++i)
        lo[v->species[i]] = fmin(lo[v->species[i]], v->sigma[i]),
        hi[v->species[i]] = fmax(hi[v->species[i]], v->sigma[i]);
    memset(c, 0, sizeof *c);
    double sum[HSBD_SIZE_CLASS_SPECIES * HSBD_SIZE_CLASSES] = {0};
    for (size_t k = 0; k < nspecies; ++k) {
        c->first[k] = k * HSBD_SIZE_CLASSES;
        if (hi[k] > lo[k]) c->polydisperse = 1;
    }
    for (size_t i = 0; i < v->n; ++i) {
        const size_t k = (size_t)v->species[i];
        const double w = hi[k] > lo[k] ? (v->sigma[i] - lo[k]) / (hi[k] - lo[k]) : 0;
        const size_t b = k * HSBD_SIZE_CLASSES +
                         (size_t)fmin(HSBD_SIZE_CLASSES - 1, floor(w * HSBD_SIZE_CLASSES));
        c->x[b] += 1.0 / (double)v->n, sum[b] += v->sigma[i];
    }
    for (size_t b = 0; b < nspecies * HSBD_SIZE_CLASSES; ++b)
        c->sigma[b] = c->x[b] > 0 ? sum[b] / (c->x[b] * (double)v->n) : 1.0;
    c->first[nspecies] = c->n = nspecies * HSBD_SIZE_CLASSES;
}

/* The 3D BMCSL contact value of species a, b over their size classes, weighted by
 * x x' sigma_cc'^3 as the simulation's contact value is (hsbd_gr_contact). */
double hsbd_size_classes_bmcsl_contact(const hsbd_size_classes *c, double rho, size_t a, size_t b) {
    double num = 0, den = 0;
    for (size_t p = c->first[a]; p < c->first[a + 1]; ++p)
        for (size_t q = c->first[b]; q < c->first[b + 1]; ++q) {
            if (c->x[p] == 0 || c->x[q] == 0) continue;
            const double sij = 0.5 * (c->sigma[p] + c->sigma[q]);
            const double w = c->x[p] * c->x[q] * sij * sij * sij;
            num += w * hsbd_hs_contact_bmcsl(c->n, c->x, c->sigma, rho, p, q), den += w;
        }
    return num / den;
}
