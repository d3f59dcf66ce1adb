/* Event-driven Brownian dynamics step (Scala 2012 Secs. II-III): fictive velocities from
 * Gaussian displacements, elastic collisions with masses 1/D_i inside [0, dt), per-
 * particle neighbour shells (re-centred locally, never a global rebuild). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/active.h"
#include "spheres/reflect.h"
#include "spheres/events.h"
#include "spheres/global.h"
#include "spheres/groups.h"
#include "spheres/neighbours.h"
#include "spheres/order.h"
#include "spheres/scan.h"
#include "spheres/state.h"

/* ---- parameters and allocation ---- */

static double species_value(const hsbd_spheres_params *p, const double *per_particle,
                            const double *per_species, double one, size_t i) {
    if (per_particle) return per_particle[i];
    return p->nspecies ? per_species[p->species[i]] : one;
}

static int check_params(const hsbd_spheres_params *p, hsbd_error *err) {
    if (p->n < 1)
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: N = %zu; allowed: N >= 1", p->n);
    if (p->n > 2147483647u)
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: N = %zu; allowed: N < 2^31", p->n);
    if (p->dimension != 2 && p->dimension != 3)
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: dimension = %d; allowed: 2 or 3",
                              p->dimension);
    if (!(p->kT > 0) || !(p->dt > 0) || !isfinite(p->dt))
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: kT = %g, dt = %g; allowed: both > 0",
                              p->kT, p->dt);
    for (int a = 0; a < p->dimension; ++a)
        if (!(p->box[a] > 0) || !isfinite(p->box[a]))
            return hsbd_error_set(err, HSBD_EINPUT, "spheres: box[%d] = %g; allowed: > 0", a,
                                  p->box[a]);
    if (p->nspecies) {
        if (!p->species || !p->species_sigma || !p->species_diffusion)
            return hsbd_error_set(err, HSBD_EINPUT, "spheres: nspecies > 0 needs the arrays");
        for (size_t i = 0; i < p->n; ++i)
            if (p->species[i] < 0 || (size_t)p->species[i] >= p->nspecies)
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "spheres: species[%zu] = %d; allowed: 0 <= species < %zu", i,
                                      p->species[i], p->nspecies);
    }
    double dmax = 0;
    const size_t ns = p->nspecies ? p->nspecies : 1;
    for (size_t k = 0; k < ns; ++k) {
        const double sg = p->nspecies ? p->species_sigma[k] : p->sigma;
        const double d = p->nspecies ? p->species_diffusion[k] : p->diffusion;
        if (!p->particle_sigma && (!(sg > 0) || !isfinite(sg)))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: sigma = %g (species %zu); allowed: > 0", sg, k);
        if (!p->particle_diffusion && (!(d >= 0) || !isfinite(d)))
            return hsbd_error_set(err, HSBD_EINPUT, "spheres: D = %g (species %zu); allowed: >= 0",
                                  d, k);
        if (d > dmax) dmax = d;
    }
    if (p->particle_diffusion) dmax = 0; /* they replace the species' values */
    for (size_t i = 0; i < p->n && (p->particle_sigma || p->particle_diffusion); ++i) {
        const double sg = p->particle_sigma ? p->particle_sigma[i] : 1.0;
        const double d = p->particle_diffusion ? p->particle_diffusion[i] : 0.0;
        if (!(sg > 0) || !isfinite(sg) || !(d >= 0) || !isfinite(d))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: particle %zu has sigma = %g, D = %g; allowed: sigma > "
                                  "0, D >= 0",
                                  i, sg, d);
        if (p->particle_diffusion && d > dmax) dmax = d;
    }
    if (!(dmax > 0))
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: every D is 0; allowed: some D > 0");
    const int drift = p->drift[0] != 0 || p->drift[1] != 0 || p->drift[2] != 0;
    for (size_t i = 0; drift && p->particle_diffusion && i < p->n; ++i)
        if (p->particle_diffusion[i] == 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: a drift with immobile particles (D = 0, particle %zu) "
                                  "is not a common drift; allowed: drift 0",
                                  i);
    if (drift && p->nspecies)
        for (size_t k = 0; k < p->nspecies; ++k)
            if (p->species_diffusion[k] == 0)
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "spheres: a drift with immobile particles (D = 0, species "
                                      "%zu) is not a common drift; allowed: drift 0",
                                      k);
    for (int a = 0; a < 3; ++a)
        if (p->walls[a] != 0 && p->walls[a] != 1)
            return hsbd_error_set(err, HSBD_EINPUT, "spheres: walls[%d] = %d; allowed: 0 or 1", a,
                                  p->walls[a]);
    if (p->field_step != HSBD_FIELD_STEP_EULER && p->field_step != HSBD_FIELD_STEP_HEUN)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "spheres: field_step = %d; allowed: 0 (Euler), 1 "
                              "(Heun)",
                              p->field_step);
    if (p->pair_rule != HSBD_PAIR_EXACT && p->pair_rule != HSBD_PAIR_MIRROR)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "spheres: pair_rule = %d; allowed: 0 (exact), 1 (mirror)",
                              p->pair_rule);
    if (p->field && (p->field_axis < 0 || p->field_axis >= p->dimension))
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: field axis %d; allowed: 0 .. %d",
                              p->field_axis, p->dimension - 1);
    for (size_t k = 0; p->field && p->species_coupling && k < (p->nspecies ? p->nspecies : 1); ++k)
        if (!isfinite(p->species_coupling[k]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: coupling of species %zu is not finite", k);
    for (size_t i = 0; p->field && p->particle_coupling && i < p->n; ++i)
        if (!isfinite(p->particle_coupling[i]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: coupling of particle %zu is not finite", i);
    if (!(p->shell >= 0) || !isfinite(p->shell))
        return hsbd_error_set(err, HSBD_EINPUT, "spheres: shell = %g; allowed: >= 0", p->shell);
    if (p->event_order < HSBD_EVENTS_AUTO || p->event_order > HSBD_EVENTS_GROUPS)
        return hsbd_error_set(
            err, HSBD_EINPUT,
            "spheres: event_order = %d; allowed: 0 (auto), 1 (global), 2 (groups)",
            (int)p->event_order);
    return HSBD_OK;
}

/* Shell radius: re-centring costs ~ (2 d D dt)/shell^2 per particle and step, the pair
 * predictions grow with (sigma + 2 shell)^d; their balance gives shell ~ (D dt)^(1/3)
 * (bench/RESULTS.md has the scan behind the factor). */
static double default_shell(const hsbd_spheres *s, double dmax, double sigma_mean) {
    const double shell = 1.65 * cbrt(2.0 * s->dim * dmax * s->dt * sigma_mean);
    const double lo = 0.02 * sigma_mean, hi = 0.5 * s->sigma_max;
    return shell < lo ? lo : shell > hi ? hi : shell;
}

static void free_hit_parts(sph_hits *parts, size_t count) {
    for (size_t k = 0; k < count; ++k) {
        free(parts[k].i);
        free(parts[k].j);
        free(parts[k].t);
    }
    free(parts);
}

void hsbd_spheres_free(hsbd_spheres *s) {
    if (!s) return;
    free(s->x);
    free(s->x_start);
    free(s->v);
    free(s->t_local);
    free(s->centre);
    free(s->image);
    free(s->counter);
    free(s->sigma);
    free(s->diffusion);
    free(s->noise_amp);
    free(s->species);
    free(s->sp_sigma);
    free(s->sp_diffusion);
    free(s->nb_count);
    free(s->nb_upper);
    free(s->nb);
    free(s->near.id);
    for (size_t k = 0; k < s->near_nparts; ++k)
        free(s->near_parts[k].id);
    free(s->near_parts);
    free(s->leaving);
    free(s->scan_j);
    free(s->scan_t);
    free(s->start_flag);
    free_hit_parts(s->hit_parts, s->hit_nparts);
    free_hit_parts(s->exit_parts, s->exit_nparts);
    for (size_t k = 0; k < s->push_nparts; ++k)
        free(s->push_parts[k].p), free(s->push_parts[k].near);
    free(s->push_parts);
    free(s->drift);
    free(s->push_sum);
    free(s->normals);
    free(s->label);
    free(s->cell_rank);
    free(s->user_x);
    free(s->user_image);
    free(s->user_sigma);
    free(s->user_diffusion);
    free(s->user_species);
    free(s->wall_step);
    free(s->wall_sum);
    free(s->wall_log);
    free(s->drift_mu);
    free(s->field_x);
    free(s->field_f);
    free(s->field_fp);
    sph_active_free(s);
    hsbd_cells_free(&s->cells);
    sph_calendar_free(&s->calendar);
    sph_groups_free(s->groups);
    free(s);
}

/* The cached per-particle quantities that follow from dt and D: the noise amplitudes. */
static void set_noise_amplitudes(hsbd_spheres *s) {
    for (size_t i = 0; i < s->n; ++i)
        s->noise_amp[i] = sqrt(2.0 * s->diffusion[i] / s->dt); /* v = dr/dt, <dr^2> = 2 D dt */
}

/* The walls' impulse sums and log, the field's drift factors D_i coupling_i / kT and its
 * buffers. Returns 0, or -1 when out of memory. */
static int alloc_walls_and_field(hsbd_spheres *s) {
    const hsbd_spheres_params *p = &s->par;
    const size_t n = s->n;
    if (s->any_walls) {
        s->wall_step = calloc(6 * s->nspecies, sizeof *s->wall_step);
        s->wall_sum = calloc(6 * s->nspecies, sizeof *s->wall_sum);
        if (!s->wall_step || !s->wall_sum) return -1;
    }
    if (!p->field) return 0;
    s->drift_mu = malloc(n * sizeof *s->drift_mu);
    s->field_x = malloc(n * sizeof *s->field_x);
    s->field_f = malloc(n * sizeof *s->field_f);
    if (p->field_step == HSBD_FIELD_STEP_HEUN) s->field_fp = malloc(n * sizeof *s->field_fp);
    if (!s->drift_mu || !s->field_x || !s->field_f ||
        (p->field_step == HSBD_FIELD_STEP_HEUN && !s->field_fp))
        return -1;
    for (size_t i = 0; i < n; ++i) {
        const double c = p->particle_coupling  ? p->particle_coupling[i]
                         : p->species_coupling ? p->species_coupling[s->species[i]]
                                               : 1.0;
        s->drift_mu[i] = s->diffusion[i] / p->kT * c; /* mu_i = D_i / kT */
    }
    s->par.species_coupling = s->par.particle_coupling = NULL; /* drift_mu holds them */
    return 0;
}

/* Whether two particles' drifts can differ in a step, so that the exact pair rule has work
 * (docs/spheres.md, "Pair collisions under a relative drift"): active particles that swim
 * (each along its own orientation), a field whose force varies in space (a term of non-zero
 * or unknown curvature), or drift factors D_i coupling_i that differ between particles
 * (immobile ones included: their factor is 0). The common drift moves every mobile particle
 * alike and is refused with immobile ones. */
static int relative_drifts(const hsbd_spheres *s, const hsbd_spheres_params *p) {
    if (s->v0_max > 0) return 1; /* sph_active_alloc ran before */
    if (!p->field) return 0;
    for (size_t k = 0; k < p->field->nterms; ++k)
        if (!p->field->term[k].ops->max_curvature) return 1;
    if (hsbd_field_max_curvature(p->field) != 0) return 1;
    double first = 0;
    for (size_t i = 0; i < s->n; ++i) {
        const double c = p->particle_coupling  ? p->particle_coupling[i]
                         : p->species_coupling ? p->species_coupling[s->species[i]]
                                               : 1.0;
        const double factor = s->diffusion[i] * c;
        if (i == 0) first = factor;
        if (factor != first) return 1;
    }
    return 0;
}

hsbd_spheres *hsbd_spheres_alloc(const hsbd_spheres_params *params, hsbd_error *err) {
    hsbd_error_clear(err);
    if (check_params(params, err) != HSBD_OK) return NULL;
    hsbd_spheres *s = calloc(1, sizeof *s);
    if (!s) return hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory"), NULL;
    s->par = *params;
    s->dim = params->dimension;
    s->n = params->n;
    s->threads = params->threads > 1 ? params->threads : 1;
    s->dt = params->dt;
    s->noise_stream = HSBD_STREAM_NOISE;
    s->bridge_stream = HSBD_STREAM_CONTACT;
    const size_t n = s->n;
    for (int a = 0; a < 3; ++a) {
        s->box[a] = a < s->dim ? params->box[a] : 1.0;
        s->length[a] = s->box[a];
        s->walls[a] = a < s->dim && params->walls[a];
        s->any_walls |= s->walls[a];
        s->par.walls[a] = s->walls[a];
        s->par.box[a] = s->box[a];
        if (a >= s->dim) s->par.drift[a] = 0;
    }
    s->x = calloc(3 * n + 1, sizeof *s->x); /* + 1: the AVX2 row kernel reads 4 at a time */
    s->v = calloc(3 * n + 1, sizeof *s->v);
    s->t_local = calloc(n, sizeof *s->t_local);
    s->centre = calloc(3 * n, sizeof *s->centre);
    s->image = calloc(3 * n, sizeof *s->image);
    s->counter = calloc(n, sizeof *s->counter);
    s->sigma = malloc(n * sizeof *s->sigma);
    s->diffusion = malloc(n * sizeof *s->diffusion);
    s->noise_amp = malloc(n * sizeof *s->noise_amp);
    s->species = calloc(n, sizeof *s->species);
    s->normals = malloc((size_t)s->dim * n * sizeof *s->normals);
    s->nspecies = params->nspecies ? params->nspecies : 1;
    s->sp_sigma = malloc(s->nspecies * sizeof *s->sp_sigma);
    s->sp_diffusion = malloc(s->nspecies * sizeof *s->sp_diffusion);
    s->label = malloc(n * sizeof *s->label);
    if (!s->x || !s->v || !s->t_local || !s->centre || !s->image || !s->counter || !s->sigma ||
        !s->diffusion || !s->noise_amp || !s->species || !s->normals || !s->sp_sigma ||
        !s->sp_diffusion || !s->label)
        goto oom;
    for (size_t i = 0; i < n; ++i)
        s->label[i] = (int32_t)i;
    double dmax = 0, sigma_sum = 0;
    for (size_t k = 0; k < s->nspecies; ++k) {
        s->sp_sigma[k] = params->nspecies ? params->species_sigma[k] : params->sigma;
        s->sp_diffusion[k] = params->nspecies ? params->species_diffusion[k] : params->diffusion;
    }
    for (size_t i = 0; i < n; ++i) {
        s->species[i] = params->nspecies ? params->species[i] : 0;
        s->sigma[i] =
            species_value(params, params->particle_sigma, params->species_sigma, params->sigma, i);
        s->diffusion[i] = species_value(params, params->particle_diffusion,
                                        params->species_diffusion, params->diffusion, i);
        if (s->sigma[i] > s->sigma_max) s->sigma_max = s->sigma[i];
        if (s->diffusion[i] > dmax) dmax = s->diffusion[i];
        sigma_sum += s->sigma[i];
    }
    s->one_sigma = 1;
    for (size_t i = 0; i < n; ++i)
        s->one_sigma &= s->sigma[i] == s->sigma_max;
    s->par.species = s->species; /* the copies */
    s->par.species_sigma = s->sp_sigma;
    s->par.species_diffusion = s->sp_diffusion;
    s->par.particle_sigma = s->par.particle_diffusion = NULL; /* s->sigma, s->diffusion hold them */
    set_noise_amplitudes(s);
    s->diffusion_max = dmax;
    s->virial_scale = sph_exact_scale_for(s->sigma_max * s->sigma_max / dmax); /* a time */
    s->wall_scale = sph_exact_scale_for(s->sigma_max / dmax);
    s->swim_scale = sph_exact_scale_for(params->kT * s->sigma_max * s->sigma_max / dmax);
    if (sph_active_check(params, s->diffusion, err) != HSBD_OK) {
        hsbd_spheres_free(s);
        return NULL;
    }
    if (sph_active_alloc(s)) goto oom;
    s->shell = params->shell > 0 ? params->shell : default_shell(s, dmax, sigma_sum / (double)n);
    s->pair_exact =
        params->hard_core && params->pair_rule == HSBD_PAIR_EXACT && relative_drifts(s, params);
    s->pair_skin = sph_pair_skin(s, s->dt);
    const double reach = s->sigma_max + sph_shell_reach(s);
    for (int a = 0; a < s->dim; ++a) {
        if (s->walls[a] && !(s->length[a] >= s->sigma_max)) {
            hsbd_error_set(err, HSBD_EINPUT,
                           "spheres: box[%d] = %g between walls is shorter than the largest "
                           "diameter %g; allowed: >= sigma_max",
                           a, s->length[a], s->sigma_max);
            hsbd_spheres_free(s);
            return NULL;
        }
        if (s->walls[a]) s->box[a] = 2 * s->length[a] + 3 * reach; /* never wraps: state.h */
        s->inv_box[a] = 1.0 / s->box[a];
    }
    if (alloc_walls_and_field(s)) goto oom;
    if (s->pair_exact && !(s->drift = malloc(3 * n * sizeof *s->drift))) goto oom;
    for (int a = 0; a < s->dim; ++a)
        if (params->hard_core && !s->walls[a] && !(s->box[a] >= 2 * reach)) {
            hsbd_error_set(err, HSBD_EINPUT,
                           "spheres: box[%d] = %g is shorter than twice the interaction range "
                           "plus skin, 2 (sigma_max + 2 shell) = %g (sigma_max %g, shell %g); "
                           "allowed: a larger box or more particles",
                           a, s->box[a], 2 * reach, s->sigma_max, s->shell);
            hsbd_spheres_free(s);
            return NULL;
        }
    s->par.shell = s->shell;
    if (params->hard_core) {
        if (hsbd_cells_init(&s->cells, s->dim, s->box, reach, n)) goto oom;
        s->nb_cap = 16;
        s->nb_count = calloc(n, sizeof *s->nb_count);
        s->nb_upper = calloc(n, sizeof *s->nb_upper);
        s->nb = sph_rows_alloc(n, s->nb_cap);
        if (!s->nb_count || !s->nb_upper || !s->nb) goto oom;
        s->predict_row = sph_predict_row_select();
        s->cells_near = sph_cells_near_select();
        s->half_scan = sph_half_scan_select();
        s->scan_cap = 4096;
        s->scan_j = malloc(s->scan_cap * sizeof *s->scan_j);
        s->scan_t = malloc(s->scan_cap * sizeof *s->scan_t);
        s->x_start = malloc(3 * n * sizeof *s->x_start);
        s->start_flag = malloc(n * sizeof *s->start_flag);
        s->leaving = malloc(n * sizeof *s->leaving);
        if (!s->scan_j || !s->scan_t || !s->x_start || !s->start_flag || !s->leaving) goto oom;
        if (!params->keep_order) { /* the view's user-order copies */
            s->sort_enabled = 1;
            s->sort_clock = INFINITY; /* sort before the first step */
            s->user_x = malloc(3 * n * sizeof *s->user_x);
            s->user_image = malloc(3 * n * sizeof *s->user_image);
            s->user_sigma = malloc(n * sizeof *s->user_sigma);
            s->user_diffusion = malloc(n * sizeof *s->user_diffusion);
            s->user_species = malloc(n * sizeof *s->user_species);
            if (!s->user_x || !s->user_image || !s->user_sigma || !s->user_diffusion ||
                !s->user_species)
                goto oom;
        }
    }
    return s;
oom:
    hsbd_spheres_free(s);
    hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory for N = %zu", n);
    return NULL;
}

void hsbd_spheres_set_dt(hsbd_spheres *s, double dt) {
    s->dt = dt;
    s->par.dt = dt;
    set_noise_amplitudes(s);
}

void hsbd_spheres_set_threads(hsbd_spheres *s, int threads) {
    s->threads = threads > 1 ? threads : 1;
    s->par.threads = s->threads;
}

/* ---- the step ---- */

/* Heun's field force along the axis (docs/algorithms.md, "The time step in a field"):
 * the free predictor x_p = x + (v_i + mu_i F(x)) dt, v_i the step's noise and drift
 * velocity, then F <- (F(x) + F(x_p)) / 2 in field_f (energy / length). Walls and other
 * particles do not stop the predictor; a force equal at both ends gives back F(x) to the
 * bit, so a constant field (gravity) steps as with Euler. */
static void heun_field_force(hsbd_spheres *s) {
    const size_t n = s->n, a = (size_t)s->par.field_axis;
    const double dt = s->dt;
    for (size_t i = 0; i < n; ++i)
        s->field_x[i] += (s->v[3 * i + a] + s->drift_mu[i] * s->field_f[i]) * dt;
    hsbd_field_force(s->par.field, n, s->field_x, s->field_fp);
    for (size_t i = 0; i < n; ++i)
        s->field_f[i] = 0.5 * (s->field_f[i] + s->field_fp[i]); /* trapezoid, Heun */
}

/* The field's drift along its axis, v_i += (D_i coupling_i / kT) F with F the force at the
 * start-of-step position (Euler: exact for a constant force, else weak order 1, the
 * stationary profile off by O(dt) where F changes over a step's displacement) or Heun's
 * mean of the start and a predictor's end point (stationary profile off by O(dt^2)). */
static void add_field_drift(hsbd_spheres *s) {
    const size_t n = s->n, a = (size_t)s->par.field_axis;
    for (size_t i = 0; i < n; ++i)
        s->field_x[i] = s->x[3 * i + a];
    hsbd_field_force(s->par.field, n, s->field_x, s->field_f);
    if (s->field_fp) heun_field_force(s);
    for (size_t i = 0; i < n; ++i)
        s->v[3 * i + a] += s->drift_mu[i] * s->field_f[i];
}

/* Each particle's drift velocity in this step: the common drift, the field's and the
 * propulsion (the exact pair rule compares them between partners: reflect.c). */
static void record_drifts(hsbd_spheres *s) {
    const double *g = s->par.drift;
    for (size_t i = 0; i < s->n; ++i)
        for (int a = 0; a < 3; ++a)
            s->drift[3 * i + a] = s->noise_amp[i] > 0 ? g[a] : 0.0;
    if (s->par.field) {
        const size_t axis = (size_t)s->par.field_axis;
        for (size_t i = 0; i < s->n; ++i)
            s->drift[3 * i + axis] += s->drift_mu[i] * s->field_f[i];
    }
    if (!s->active) return;
    for (size_t i = 0; i < s->n; ++i) { /* each particle's own drift, its propulsion */
        double own[3];
        sph_propulsion(s, (int32_t)i, own);
        for (int a = 0; a < 3; ++a)
            s->drift[3 * i + a] += own[a];
    }
}

/* The walls' Skorokhod pushes, added to the fictive velocities before any event: a
 * particle alone at a wall then ends where the reflected Brownian motion with its drift
 * ends, and its straight path stays off the wall. Each wall's bridge is drawn from the
 * free path (user index, axis, side), so in a slit narrower than a few sqrt(2 D dt) the
 * two pushes are an approximation and the wall events fold what still crosses. The
 * pushes' impulses go to this step's wall sums. */
static void add_wall_pushes(hsbd_spheres *s) {
    const double dt = s->dt;
    for (int a = 0; a < s->dim; ++a) {
        if (!s->walls[a]) continue;
        for (size_t i = 0; i < s->n; ++i) {
            const double d = s->diffusion[i], half = 0.5 * s->sigma[i];
            double *x = s->x + 3 * i + a, *v = s->v + 3 * i + a;
            const double dx = *v * dt, low = *x - half, high = s->length[a] - half - *x;
            if (!(d > 0) || (low * (low + dx) >= SPH_BRIDGE_REACH * d * dt &&
                             high * (high - dx) >= SPH_BRIDGE_REACH * d * dt))
                continue; /* the common case: neither bridge can reach its wall */
            const uint64_t index = 2 * (3 * (uint64_t)s->label[i] + (uint64_t)a);
            const double up = sph_bridge_push(s, low, low + dx, d * dt, index);
            const double down = sph_bridge_push(s, high, high - dx, d * dt, index + 1);
            if (up == 0 && down == 0) continue;
            *v += (up - down) / dt;
            sph_exact_sum *sum = s->wall_step + 6 * (size_t)s->species[i] + 2 * a;
            sum[0] += sph_exact_term(s->wall_scale, up / d); /* impulse / kT: displacement / D */
            sum[1] += sph_exact_term(s->wall_scale, down / d);
            s->stats.wall_pushes++;
        }
    }
}

/* The normals of the user's particles in range k of `parts` (each draw is its own Philox
 * counter: the split changes no bit). */
static void normals_range(hsbd_spheres *s, int parts, int k) {
    const size_t d = (size_t)s->dim, first = sph_range_start(s->n, parts, k);
    const size_t count = sph_range_start(s->n, parts, k + 1) - first;
    hsbd_rng_normals(s->par.seed, s->noise_stream, s->step, d * first, d * count,
                     s->normals + d * first);
}

/* The velocities loop reads each particle's normals by the user's index, in random order
 * once the engine sorts in space: beyond the caches (SPH_PREFETCH_MIN_N) it asks for the
 * normals VELOCITY_PREFETCH particles ahead (N 2 x 10^5: the loop's share of a step
 * 4.2 % -> 1.6 %). */
enum { VELOCITY_PREFETCH = 16 };

static void draw_velocities(hsbd_spheres *s) {
    const size_t d = (size_t)s->dim;
    const int threads = sph_threads(s);
    const long n = (long)s->n, ahead = n >= SPH_PREFETCH_MIN_N ? VELOCITY_PREFETCH : n;
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
#pragma omp for schedule(static, 1)
        for (int k = 0; k < threads; ++k)
            normals_range(s, threads, k);
        const double *g = s->par.drift;
#pragma omp for schedule(static)
        for (long i = 0; i < n; ++i) {
            if (i + ahead < n) __builtin_prefetch(s->normals + d * (size_t)s->label[i + ahead]);
            double *v = s->v + 3 * i;
            const double amp = s->noise_amp[i];
            const double *z = s->normals + d * (size_t)s->label[i]; /* the user's particle's */
            for (size_t a = 0; a < d; ++a)
                v[a] = amp * z[a] + (amp > 0 ? g[a] : 0.0);
        }
    }
    if (s->par.field) add_field_drift(s);
    if (s->active) sph_add_propulsion(s);
    if (s->pair_exact) record_drifts(s);
    if (s->any_walls) add_wall_pushes(s);
}

/* A start-of-step event: into the calendar, or into the groups' hit list. Returns 0, or
 * -1 when out of memory. */
static int start_event(hsbd_spheres *s, int grouped, double t, int32_t i, int32_t j) {
    return grouped ? sph_groups_add_hit(s, t, i, j) : sph_push_event(s, t, i, j);
}

/* The hits of parts[0 .. threads) in order (particle or row order, whatever the threads)
 * as start-of-step events. Returns 0, or -1 when out of memory. */
static int hand_over_hits(hsbd_spheres *s, int grouped, const sph_hits *parts, int threads) {
    for (int p = 0; p < threads; ++p)
        for (size_t k = 0; k < parts[p].len; ++k)
            if (start_event(s, grouped, parts[p].t[k], parts[p].i[k], parts[p].j[k])) return -1;
    return 0;
}

/* Re-centre the shells of particles whose straight end point would leave them, then
 * predict every neighbour pair once (half scan) and the rare shell exits. Returns 0, or
 * -1 when out of memory. */
static int start_step_events(hsbd_spheres *s, int grouped) {
    const int threads = sph_threads(s);
    if (!grouped && sph_calendar_start(&s->calendar, s->dt)) return -1;
    /* the start positions, velocities and shells; the shell exits and wall contacts */
    if (sph_scan_leaving(s, threads) || sph_move_leaving_shells(s, threads) ||
        hand_over_hits(s, grouped, s->exit_parts, threads) || sph_scan_pairs(s, threads))
        return -1;
    return hand_over_hits(s, grouped, s->hit_parts, threads);
}

/* Every event of the step, group by group or through the global calendar. Returns 0, or
 * -1 when out of memory (the step is then cut short). */
static int run_events(hsbd_spheres *s) {
    s->step_virial = 0;
    const int grouped = sph_groups_wanted(s);
    if ((grouped && sph_groups_begin(s)) || start_step_events(s, grouped)) return -1;
    const int rc = grouped ? sph_groups_run(s) : 1;
    return rc < 0 ? -1 : rc == 1 ? sph_global_run(s) : 0;
}

static void forget_wall_step(hsbd_spheres *s) {
    if (s->wall_step) memset(s->wall_step, 0, 6 * s->nspecies * sizeof *s->wall_step);
    s->wall_log_len = 0;
}

/* The step's wall events join its pushes in the sums since the last reset. */
static void commit_wall_step(hsbd_spheres *s) {
    for (size_t k = 0; k < s->wall_log_len; ++k) {
        const sph_wall_hit *h = &s->wall_log[k];
        s->wall_step[6 * (size_t)s->species[h->particle] + (size_t)h->wall] +=
            sph_exact_term(s->wall_scale, h->impulse);
    }
    s->stats.wall_collisions += s->wall_log_len;
    for (size_t k = 0; k < 6 * s->nspecies; ++k)
        s->wall_sum[k] += sph_exact_value(s->wall_scale, s->wall_step[k]);
    forget_wall_step(s);
}

/* A free particle's end point along a walls axis folded back between the planes: the
 * specular reflections of its straight path, as the calendar's wall events give a
 * particle that meets no other (hard_core = 0); the impulses go to the step's sums. */
static void fold_between_walls(hsbd_spheres *s, size_t i, int a) {
    double *x = s->x + 3 * i;
    const double lo = 0.5 * s->sigma[i], hi = s->length[a] - lo, d = s->diffusion[i];
    sph_exact_sum *sum = s->wall_step + 6 * (size_t)s->species[i] + 2 * a;
    if (!(hi > lo)) { /* a slit as wide as the particle holds it */
        x[a] = lo;
        return;
    }
    while (x[a] < lo || x[a] > hi) {
        const int side = x[a] > hi;
        const double plane = side ? hi : lo;
        sum[side] += sph_exact_term(s->wall_scale, 2.0 * fabs(x[a] - plane) / d); /* impulse / kT */
        x[a] = 2 * plane - x[a];
        s->stats.wall_collisions++;
    }
}

/* Along the walls axes: free particles fold, hard ones (whose wall events kept them
 * inside) lose the round-off of their last move. */
static void keep_between_walls(hsbd_spheres *s) {
    for (int a = 0; a < s->dim; ++a) {
        if (!s->walls[a]) continue;
        for (size_t i = 0; i < s->n; ++i) {
            if (!s->par.hard_core) {
                fold_between_walls(s, i, a);
                continue;
            }
            double *x = s->x + 3 * i + a;
            const double lo = 0.5 * s->sigma[i], hi = s->length[a] - lo;
            *x = *x < lo ? lo : *x > hi ? hi : *x;
        }
    }
}

/* After an allocation failed inside a step: back to the state at its start (positions,
 * local times, statistics), the shells moved in it forgotten, and the neighbour lists
 * rebuilt from the start positions (at the next step if that fails too). */
static int fail_step(hsbd_spheres *s, const hsbd_spheres_stats *stats_at_start) {
    memcpy(s->x, s->x_start, 3 * s->n * sizeof *s->x);
    memset(s->t_local, 0, s->n * sizeof *s->t_local);
    s->stats = *stats_at_start;
    forget_wall_step(s);
    sph_groups_abandon(s);
    sph_rebuild_neighbours(s); /* when it fails, nb_stale stays set */
    return HSBD_ENOMEM;
}

/* Every particle to t = dt, wrapped into the box with image counters. */
static void finish_step(hsbd_spheres *s) {
    const double dt = s->dt;
    const int threads = sph_threads(s);
    const long n = (long)s->n;
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (long i = 0; i < n; ++i) {
        double *x = s->x + 3 * i;
        const double *v = s->v + 3 * i;
        const double h = dt - s->t_local[i];
        s->t_local[i] = 0;
        for (int a = 0; a < s->dim; ++a) {
            x[a] += v[a] * h;
            /* the common case: no floor(); between walls free particles may end outside
             * (folded back afterwards, never wrapped) */
            if ((x[a] >= 0 && x[a] < s->box[a]) || s->walls[a]) continue;
            const double w = floor(x[a] * s->inv_box[a]);
            if (w != 0) {
                x[a] -= w * s->box[a];
                if (x[a] >= s->box[a]) x[a] -= s->box[a], s->image[3 * i + a]++; /* round-off */
                if (x[a] < 0) x[a] += s->box[a], s->image[3 * i + a]--;
                s->image[3 * i + a] += (int64_t)w;
            }
        }
    }
}

/* x_start = x, range by range on threads. */
static void keep_start_positions(hsbd_spheres *s) {
    const int threads = sph_threads(s);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)
    for (int k = 0; k < threads; ++k) {
        const size_t first = 3 * sph_range_start(s->n, threads, k);
        const size_t end = 3 * sph_range_start(s->n, threads, k + 1);
        memcpy(s->x_start + first, s->x + first, (end - first) * sizeof *s->x);
    }
}

/* Sorted again once the fastest particle could have moved about half a cell (rms
 * displacement sqrt(0.6) sigma_max): often enough to keep neighbours near in memory,
 * rarely enough that the renumbering costs little (N 10^6: 0.1 s, a third of a step, per
 * 100 steps; docs/spheres.md). The clock advances after each step that succeeded.
 * Returns 0, or -1 when out of memory (then nothing changed). */
static int keep_spatial_order(hsbd_spheres *s) {
    if (!s->sort_enabled || s->sort_clock < 0.1 * s->sigma_max * s->sigma_max) return 0;
    if (sph_sort_spatially(s)) return -1;
    s->sort_clock = 0;
    return 0;
}

int hsbd_spheres_step(hsbd_spheres *s) {
    if (s->par.hard_core) {
        if (s->nb_stale && sph_rebuild_neighbours(s) != HSBD_OK) return HSBD_ENOMEM;
        if (keep_spatial_order(s)) return HSBD_ENOMEM;
    }
    const hsbd_spheres_stats stats_at_start = s->stats; /* before the walls' pushes count */
    draw_velocities(s);
    if (s->par.hard_core) {
        keep_start_positions(s);
        if (s->active) sph_keep_free_velocities(s); /* before the pair rule: the swim sum */
        s->push_virial = 0;
        if ((s->pair_exact && sph_pair_corrections(s)) || run_events(s))
            return fail_step(s, &stats_at_start);
        s->stats.virial += sph_exact_value(s->virial_scale, s->step_virial + s->push_virial);
        if (s->active) sph_add_swim_collisional(s);
    }
    if (s->sort_enabled) s->sort_clock += s->diffusion_max * s->dt;
    finish_step(s);
    if (s->any_walls) {
        keep_between_walls(s);
        commit_wall_step(s);
    }
    if (s->active) sph_rotate(s); /* the orientations of the step's end (its counter) */
    s->step++;
    s->stats.steps++;
    s->time += s->dt;
    return HSBD_OK;
}

/* ---- views and diagnostics ---- */

hsbd_spheres_view hsbd_spheres_get_view(const hsbd_spheres *s) {
    if (s->reordered) sph_fill_user_view(s);
    hsbd_spheres_view v = {.n = s->n,
                           .walls = {s->walls[0], s->walls[1], s->walls[2]},
                           .dimension = s->dim,
                           .x = s->reordered ? s->user_x : s->x,
                           .image = s->reordered ? s->user_image : s->image,
                           .sigma = s->reordered ? s->user_sigma : s->sigma,
                           .diffusion = s->reordered ? s->user_diffusion : s->diffusion,
                           .species = s->reordered ? s->user_species : s->species,
                           .nspecies = s->nspecies,
                           .kT = s->par.kT,
                           .dt = s->dt,
                           .time = s->time,
                           .step = s->step,
                           .hard_core = s->par.hard_core,
                           .orientation = s->orient,
                           .v0 = s->v0,
                           .rotational_diffusion = s->rot_d};
    for (int a = 0; a < 3; ++a)
        v.box[a] = s->length[a];
    return v;
}

const hsbd_spheres_params *hsbd_spheres_get_params(const hsbd_spheres *s) {
    return &s->par;
}

hsbd_spheres_stats hsbd_spheres_get_stats(const hsbd_spheres *s) {
    return s->stats;
}

void hsbd_spheres_reset_stats(hsbd_spheres *s) {
    memset(&s->stats, 0, sizeof s->stats);
    if (s->wall_sum) memset(s->wall_sum, 0, 6 * s->nspecies * sizeof *s->wall_sum);
}

void hsbd_spheres_wall_impulses(const hsbd_spheres *s, double *out) {
    for (size_t k = 0; k < 6 * s->nspecies; ++k)
        out[k] = s->wall_sum ? s->wall_sum[k] : 0.0;
}

double hsbd_spheres_shell(const hsbd_spheres *s) {
    return s->shell;
}

double hsbd_spheres_min_gap(const hsbd_spheres *s, int *all_finite) {
    int finite = 1;
    for (size_t k = 0; k < 3 * s->n; ++k)
        finite &= isfinite(s->x[k]) != 0;
    if (all_finite) *all_finite = finite;
    double worst = INFINITY;
    for (size_t i = 0; i < s->n && finite && s->any_walls; ++i)
        for (int a = 0; a < s->dim; ++a) {
            if (!s->walls[a]) continue;
            const double x = s->x[3 * i + a], half = 0.5 * s->sigma[i];
            const double gap = fmin(x - half, s->length[a] - half - x) / s->sigma[i];
            if (gap < worst) worst = gap;
        }
    if (!s->par.hard_core || !finite) return worst;
    for (size_t i = 0; i < s->n; ++i) {
        const int32_t *row = s->nb + i * s->nb_cap;
        for (uint32_t k = 0; k < s->nb_upper[i]; ++k) {
            const int32_t j = row[k];
            double r[3];
            sph_min_image(s, s->x + 3 * (size_t)j, s->x + 3 * i, r);
            const double sij = sph_contact_distance(s, (int32_t)i, j);
            const double gap = (sqrt(hsbd_dot3(r, r)) - sij) / sij;
            if (gap < worst) worst = gap;
        }
    }
    return worst;
}
