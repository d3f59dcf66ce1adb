/* The assumptions of event-driven Brownian dynamics (Scala Sec. II), checked from the
 * particles' own diameters and diffusion coefficients (polydispersity, Stokes-Einstein
 * D, an XYZ input's sizes), see include/hsbd/observe.h. */
#include <math.h>
#include <stdio.h>

#include "hsbd/observe.h"

/* E|N_d| for a d-dimensional standard normal: sqrt(2) Gamma((d+1)/2) / Gamma(d/2) */
static double mean_norm(int dim) {
    return dim == 3 ? 1.5957691216057308 : 1.2533141373155003;
}

void hsbd_scheme_check_compute(const hsbd_spheres_view *v, double collisions_per_particle_step,
                               hsbd_scheme_check *out) {
    const double c = mean_norm(v->dimension);
    double worst_sigma = 0, worst_step = 0, sum_sigma = 0, volume = 1;
    for (size_t i = 0; i < v->n; ++i) {
        const double step = c * sqrt(2.0 * v->diffusion[i] * v->dt); /* <|dr_i|>, Eq. 2 */
        worst_sigma = fmax(worst_sigma, step / v->sigma[i]);
        worst_step = fmax(worst_step, step);
        sum_sigma += v->sigma[i];
    }
    for (int a = 0; a < v->dimension; ++a)
        volume *= v->box[a];
    /* Eq. 3: rho^(-1/d) - sigma, with the particles' mean diameter */
    const double gap = pow(volume / (double)v->n, 1.0 / v->dimension) - sum_sigma / (double)v->n;
    out->step_over_sigma = worst_sigma;
    out->step_over_gap = gap > 0 ? worst_step / gap : INFINITY;
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
                 "the mean step is %.3g of the mean gap rho^(-1/d) - sigma: binary collisions "
                 "need << 1 (Scala Eq. 3; warned above %g; smaller run.dt)",
                 c->step_over_gap, HSBD_SCHEME_STEP_GAP_MAX);
    if (n < max && c->collisions_per_particle_step > HSBD_SCHEME_COLLISIONS_MAX)
        snprintf(msg[n++], HSBD_WARNING_LEN,
                 "%.3g collisions per particle and step: the binary-collision picture needs "
                 "well below one (warned above %g; smaller run.dt)",
                 c->collisions_per_particle_step, HSBD_SCHEME_COLLISIONS_MAX);
    return n;
}
