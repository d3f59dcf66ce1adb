/* The rods model of the run lifecycle: builds the BCD system (fields, pair forces, sticky
 * contacts, mixtures, walls, the initial state), steps it, makes its replicas and frames,
 * and saves its state; its observers are under src/run/observers/ (src/run/models.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vmath.h"
#include "hsbd/io.h"
#include "hsbd/observe.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"
#include "hsbd/table.h"
#include "io/tables.h"
#include "observe/checkpoint.h"
#include "rods1d/checkpoint.h"
#include "run/rods_model.h"

/* ---- the system ---------------------------------------------------------------------- */

/* Pair terms from the configuration; the table (if any) is loaded and checked here. */
static int build_pair(const hsbd_config *cfg, hsbd_table **table, hsbd_pair *pair,
                      hsbd_error *err) {
    const double sigma = cfg->system.sigma;
    if (cfg->contact.gamma > 0)
        hsbd_pair_add(pair, hsbd_pair_sticky(sigma, cfg->contact.gamma, cfg->contact.order,
                                             cfg->contact.epsilon, cfg->system.kT));
    switch (cfg->pair.type) {
    case HSBD_PAIR_YUKAWA:
        hsbd_pair_add(
            pair, hsbd_pair_yukawa(sigma, cfg->pair.strength, cfg->pair.kappa, cfg->pair.cutoff));
        break;
    case HSBD_PAIR_LJ:
        hsbd_pair_add(pair, hsbd_pair_lj(sigma, cfg->pair.strength, cfg->pair.cutoff));
        break;
    case HSBD_PAIR_TABLE: {
        *table = hsbd_table_load(cfg->pair.table, err);
        if (!*table) return err->status;
        const hsbd_table *t = *table;
        const double r0 = hsbd_table_x_min(t), r1 = hsbd_table_x_max(t);
        double fbig = 0;
        for (size_t k = 0; k <= 1000; ++k)
            fbig = fmax(fbig, fabs(hsbd_table_value(t, r0 + (r1 - r0) * (double)k / 1000)));
        if (r0 > sigma || r1 <= sigma || r1 > 0.5 * cfg->system.length)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s (pair.table): r runs from %g to %g; allowed: first r <= "
                                  "system.sigma = %g < last r <= L/2 = %g",
                                  cfg->pair.table, r0, r1, sigma, 0.5 * cfg->system.length);
        if (fabs(hsbd_table_last_value(t)) > 1e-9 * fbig)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s (pair.table): the force at the last r = %g is %g, not 0; "
                                  "the force must vanish at the end of the table (continuous "
                                  "forces, Antonov Sec. IV)",
                                  cfg->pair.table, r1, hsbd_table_last_value(t));
        hsbd_pair_add(pair, hsbd_pair_table(t));
        break;
    }
    default:
        break;
    }
    return HSBD_OK;
}

static hsbd_rods_params rods_params_from(const hsbd_config *cfg) {
    hsbd_rods_params p = {
        .n = (size_t)cfg->system.n,
        .length = cfg->system.length,
        .sigma = cfg->system.sigma,
        .diffusion = cfg->system.diffusion,
        .kT = cfg->system.kT,
        .dt = cfg->run.dt,
        .seed = run_noise_seed(cfg),
        .hard_core = cfg->system.hard_core,
        .contact_rule = cfg->system.contact_rule,
        .boundary =
            cfg->system.boundary == HSBD_BOUNDARY_WALLS ? HSBD_RODS_WALLS : HSBD_RODS_PERIODIC,
        .threads = run_threads(cfg),
        .field_step = cfg->run.field_step,
    };
    return p;
}

double rods_sum_unwrapped(const hsbd_rods *rods) {
    const hsbd_rods_view v = hsbd_rods_get_view(rods);
    double s = 0;
    for (size_t i = 0; i < v.n; ++i)
        s += v.z[i] + v.offset[i] + v.unwrap;
    return s;
}

/* The largest mobility D / kT of the rods (of their species). */
static double mobility_max(const hsbd_config *cfg) {
    double d = cfg->system.diffusion;
    for (size_t k = 0; k < cfg->species.n; ++k)
        d = fmax(d, cfg->species.diffusion[k]);
    return d / cfg->system.kT;
}

/* Antonov Eq. (33): the sticky force must move a rod much less than epsilon per step. The
 * largest step of the run (equilibration may be coarser) is the one that counts. */
static int check_sticky_step(run *r, rods_model *m, const hsbd_rods_params *par, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    m->sticky_ratio = NAN;
    if (!(cfg->contact.gamma > 0)) return HSBD_OK;
    hsbd_pair sticky = {0};
    hsbd_pair_add(&sticky, par->pair.term[0]);
    const double fbig =
        hsbd_pair_max_force(&sticky, cfg->system.sigma, cfg->system.sigma + cfg->contact.epsilon);
    const double mu = mobility_max(cfg);
    const double dt = fmax(cfg->run.dt, hsbd_config_dt_equil(cfg));
    m->sticky_ratio = mu * fbig * dt / cfg->contact.epsilon;
    const double dt_limit = cfg->contact.epsilon / (mu * fbig);
    if (m->sticky_ratio > 1.0 && !r->opt->force && !r->resuming) /* accepted at the start */
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.dt = %g: the sticky force moves a rod by mu max|f| dt = "
                              "%.3g epsilon per step (Antonov Eq. 33 needs << 1); allowed: dt "
                              "(and run.dt_equil) < %.3g for contact.gamma = %g, epsilon = %g, "
                              "order = %g, or --force",
                              hsbd_config_origin(cfg, "run", "dt"), dt, m->sticky_ratio, dt_limit,
                              cfg->contact.gamma, cfg->contact.epsilon, cfg->contact.order);
    if (m->sticky_ratio > 0.1)
        run_warn(r,
                 "sticky step ratio mu max|f| dt / epsilon = %.3g > 0.1 (Antonov Eq. 33); dt < "
                 "%.3g keeps it below 0.1",
                 m->sticky_ratio, 0.1 * dt_limit);
    else if (r->opt->progress)
        fprintf(stderr, "hsbd: sticky step ratio mu max|f| dt / epsilon = %.3g (Eq. 33)\n",
                m->sticky_ratio);
    return HSBD_OK;
}

/* The step of the field (run.field_step) and the Euler step of the continuous pair force
 * (the sticky term apart: Eq. 33 above) against their time scales, 1 / (mu max|U''|) and
 * 1 / (2 mu max|V''|) (the gap of two rods diffuses with both mobilities): estimates in the
 * summary, warnings beyond 1 %. */
static void check_field_step(run *r, rods_model *m, const hsbd_rods_params *par) {
    const hsbd_config *cfg = r->cfg;
    const double mu = mobility_max(cfg), dt = cfg->run.dt;
    const int heun = cfg->run.field_step == HSBD_FIELD_STEP_HEUN;
    char msg[HSBD_WARNING_LEN];
    m->field_error = m->pair_error = NAN;
    if (par->field.nterms) {
        const double k = mu * hsbd_field_max_curvature(&par->field);
        m->field_error = run_step_density_error(heun, k, dt);
        if (run_step_warning(heun, k, dt, "field", "stationary density", "mu max|U''|", msg,
                             sizeof msg))
            run_warn(r, "%s", msg);
    }
    hsbd_pair smooth = {0}; /* the continuous terms */
    for (size_t t = cfg->contact.gamma > 0 ? 1 : 0; t < par->pair.nterms; ++t)
        hsbd_pair_add(&smooth, par->pair.term[t]);
    if (smooth.nterms) {
        const double k = 2 * mu *
                         hsbd_pair_max_curvature(&smooth, cfg->system.sigma,
                                                 fmax(hsbd_pair_range(&smooth), cfg->system.sigma));
        m->pair_error = run_step_density_error(0, k, dt);
        if (run_step_warning(0, k, dt, "pair force", "pair distribution", "2 mu max|V''|", msg,
                             sizeof msg))
            run_warn(r, "%s", msg);
    }
}

/* Mixtures: the species of each rod along the line, a uniformly random arrangement of
 * the counts (Fisher-Yates with the seed's initial-state stream), which with the uniform
 * gaps of hsbd_rods_init_equilibrium samples the field-free equilibrium exactly. */
static int arrange_species(const hsbd_config *cfg, rods_model *m, hsbd_rods_params *par,
                           hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    m->species = malloc(n * sizeof *m->species);
    double *u = malloc(n * sizeof *u);
    if (!m->species || !u) {
        free(u);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu species", n);
    }
    size_t i = 0;
    for (size_t k = 0; k < cfg->species.n; ++k)
        for (int64_t c = 0; c < cfg->species.count[k]; ++c)
            m->species[i++] = (int)k;
    hsbd_rng_uniforms(run_noise_seed(cfg), HSBD_STREAM_INIT, 3, 0, n, u);
    for (size_t k = n; k-- > 1;) {
        size_t j = (size_t)(u[k] * (double)(k + 1));
        if (j > k) j = k;
        const int t = m->species[k];
        m->species[k] = m->species[j];
        m->species[j] = t;
    }
    free(u);
    par->nspecies = cfg->species.n;
    par->species = m->species;
    par->species_sigma = cfg->species.sigma;
    par->species_diffusion = cfg->species.diffusion;
    return HSBD_OK;
}

/* init.positions, or the caller's initial state (hsbd_sim_alloc_from): positions and a
 * mixture's species, which must match the counts. */
static int initial_positions(const run *r, rods_model *m, double *x, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const size_t n = (size_t)cfg->system.n;
    int rc = HSBD_OK;
    if (r->start_x) {
        for (size_t i = 0; i < n; ++i)
            x[i] = r->start_x[3 * i];
        if (r->start_species && m->species)
            memcpy(m->species, r->start_species, n * sizeof *m->species);
    } else {
        rc = cfg->init.gsd ? hsbd_gsd_read_positions(cfg, x, m->species, err)
                           : hsbd_read_positions(cfg, x, m->species, err);
    }
    const char *source = r->start_x ? "the positions given" : cfg->init.positions;
    for (size_t k = 0; k < cfg->species.n && rc == HSBD_OK; ++k) {
        int64_t c = 0;
        for (size_t i = 0; i < n; ++i)
            c += m->species[i] == (int)k;
        if (c != cfg->species.count[k])
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s%s: %lld rods of species %s, but species.count says %lld",
                                source, r->start_x ? "" : " (init.positions)", (long long)c,
                                cfg->species.name[k], (long long)cfg->species.count[k]);
    }
    return rc;
}

/* The engine with its initial state: init.positions, or the exact field-free sample. */
static int build_system(run *r, rods_model *m, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    hsbd_rods_params par = rods_params_from(cfg);
    if (cfg->species.n > 0 && arrange_species(cfg, m, &par, err) != HSBD_OK) return err->status;
    int rc =
        run_build_field(cfg, cfg->system.length, cfg->system.boundary == HSBD_BOUNDARY_PERIODIC,
                        "system.L", &m->field_table, &par.field, err);
    if (rc == HSBD_OK) rc = build_pair(cfg, &m->pair_table, &par.pair, err);
    if (rc == HSBD_OK) rc = check_sticky_step(r, m, &par, err);
    if (rc != HSBD_OK) return rc;
    check_field_step(r, m, &par);
    double *x = NULL;
    if (r->start_x || cfg->init.positions[0]) { /* before the rods copy the species */
        x = malloc(par.n * sizeof *x);
        if (!x) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        rc = initial_positions(r, m, x, err);
    }
    if (rc == HSBD_OK) m->rods = hsbd_rods_alloc(&par, err);
    if (rc == HSBD_OK && !m->rods) rc = err->status;
    if (rc == HSBD_OK && x) rc = hsbd_rods_set_positions(m->rods, x, err);
    if (rc == HSBD_EINPUT && x && cfg->init.gsd) { /* a text file was checked as it was read */
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message);
        hsbd_error_set(err, rc, "init.positions '%s': %s", cfg->init.positions, why);
    }
    if (rc == HSBD_OK && !x) hsbd_rods_init_equilibrium(m->rods);
    if (rc == HSBD_OK && x && cfg->sample.blocking == HSBD_BLOCKS_REPLICAS) {
        /* line order, so that setting them again keeps a mixture's species in place */
        const hsbd_rods_view v = hsbd_rods_get_view(m->rods);
        for (size_t i = 0; i < par.n; ++i)
            x[i] = v.z[i] + v.offset[i];
        m->x_start = x, x = NULL;
    }
    free(x);
    return rc;
}

/* ---- the model's part of the lifecycle ------------------------------------------------ */

static int rods_step(run *r, hsbd_error *err) {
    rods_model *m = rods_model_of(r);
    /* the cluster statistics of the steps the sampling follows */
    const int stats = r->stage == RUN_PRODUCING && r->cfg->system.hard_core &&
                      (r->steps_done + 1) % (uint64_t)r->cfg->sample.every == 0;
    return hsbd_rods_step(m->rods, stats ? &m->stats : NULL) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENUMERIC, "rods: the step failed");
}

static void rods_equilibration_dt(run *r, int on) {
    hsbd_rods_set_dt(rods_model_of(r)->rods, on ? hsbd_config_dt_equil(r->cfg) : r->cfg->run.dt);
}

static int rods_check(run *r, int strict, hsbd_error *err) {
    rods_model *m = rods_model_of(r);
    int finite;
    const double g = hsbd_rods_min_gap(m->rods, &finite);
    const double sigma = r->cfg->system.sigma;
    if (!finite)
        return hsbd_error_set(err, HSBD_ENUMERIC, "non-finite position after step %llu",
                              (unsigned long long)hsbd_rods_get_view(m->rods).step);
    if ((strict || r->stage == RUN_EQUILIBRATING) && r->cfg->system.hard_core &&
        g < -1e-9 * (sigma > 0 ? sigma : 1.0))
        return hsbd_error_set(err, HSBD_ENUMERIC, "--check: overlap %.3g after step %llu", g,
                              (unsigned long long)hsbd_rods_get_view(m->rods).step);
    return HSBD_OK;
}

/* sample.blocking = replicas: a fresh initial state (its own draw of the exact field-free
 * sample, or init.positions again) before the lifecycle equilibrates it; the noise goes on
 * with the step counter, so every replica is independent. */
static int rods_start_replica(run *r, size_t k, hsbd_error *err) {
    rods_model *m = rods_model_of(r);
    if (m->x_start) return hsbd_rods_set_positions(m->rods, m->x_start, err);
    hsbd_rods_init_equilibrium_draw(m->rods, k);
    return HSBD_OK;
}

/* The rods on x of a line of length L: wrapped positions and images on a ring, and the
 * exact unwrapped positions; diameters per species. */
static void rods_frame(const run *r, hsbd_frame *f) {
    const rods_model *m = rods_model_of(r);
    const hsbd_rods_view v = hsbd_rods_get_view(m->rods);
    const double L = v.length;
    for (size_t i = 0; i < v.n; ++i) {
        const double xu = v.z[i] + v.offset[i] + v.unwrap;
        const double wraps = v.periodic ? floor(xu / L) : 0.0;
        m->frame_unwrapped[i] = xu;
        m->frame_x[3 * i] = xu - L * wraps;
        m->frame_image[3 * i] = (int64_t)wraps;
    }
    const hsbd_config *cfg = r->cfg;
    *f = (hsbd_frame){.step = v.step,
                      .time = v.time,
                      .dimension = 1,
                      .n = v.n,
                      .box = {L, 0, 0},
                      .periodic = {v.periodic, 0, 0},
                      .x = m->frame_x,
                      .image = m->frame_image,
                      .unwrapped = m->frame_unwrapped,
                      .diameter = m->frame_diameter,
                      .species = m->species,
                      .nspecies = cfg->species.n,
                      .names = cfg->species.n ? cfg->species.name : NULL,
                      .one_name = "R"};
}

/* the frame's memory: positions on x (y = z = 0), images, diameters (fixed) */
static int frame_alloc(const hsbd_config *cfg, rods_model *m, hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    m->frame_x = calloc(3 * n, sizeof *m->frame_x);
    m->frame_image = calloc(3 * n, sizeof *m->frame_image);
    m->frame_unwrapped = malloc(n * sizeof *m->frame_unwrapped);
    m->frame_diameter = malloc(n * sizeof *m->frame_diameter);
    if (!m->frame_x || !m->frame_image || !m->frame_unwrapped || !m->frame_diameter)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    for (size_t i = 0; i < n; ++i)
        m->frame_diameter[i] = m->species ? cfg->species.sigma[m->species[i]] : cfg->system.sigma;
    return HSBD_OK;
}

/* ---- results ----------------------------------------------------------------------------- */

static void rods_write_summary(run *r, FILE *f) {
    const rods_model *m = rods_model_of(r);
    const hsbd_config *cfg = r->cfg;
    const double n = (double)cfg->system.n;
    fprintf(f, "  \"samples\": %llu,\n",
            (unsigned long long)(r->steps_done / (uint64_t)cfg->sample.every));
    fprintf(f, "  \"replicas\": %zu,\n", r->replicas_started ? r->replicas_started : 1);
    hsbd_json_number(f, "time_simulated", (double)r->steps_done * cfg->run.dt, 1);
    hsbd_json_number(f, "wall_seconds", r->wall_prod + r->wall_equil, 1);
    hsbd_json_number(f, "wall_seconds_production", r->wall_prod, 1);
    hsbd_json_number(f, "particle_steps_per_second",
                     r->wall_prod > 0 ? n * (double)r->steps_done / r->wall_prod : NAN, 1);
    fprintf(f, "  \"vectorised_math\": %s,\n", hsbd_vmath_vectorised() ? "true" : "false");
    hsbd_json_number(f, "sticky_step_ratio", m->sticky_ratio, 1);
    hsbd_json_number(f, "field_step_error", m->field_error, 1);
    hsbd_json_number(f, "pair_step_error", m->pair_error, 1);
    run_write_warnings(r, f, NULL, 0);
    hsbd_json_number(f, "final_time", hsbd_rods_get_view(m->rods).time, 1);
}

/* ---- checkpoints ------------------------------------------------------------------------ */

static void rods_save(const run *r, hsbd_writer *w) {
    const rods_model *m = rods_model_of(r);
    hsbd_rods_save(m->rods, w);
    hsbd_put_tag(w, "rods run");
    if (m->x_start) hsbd_put_f64s(w, m->x_start, (size_t)r->cfg->system.n);
}

static int rods_load(run *r, hsbd_reader *rd) {
    rods_model *m = rods_model_of(r);
    if (hsbd_rods_load(m->rods, rd) || hsbd_get_tag(rd, "rods run")) return -1;
    if (m->x_start && hsbd_get_f64s(rd, m->x_start, (size_t)r->cfg->system.n)) return -1;
    return 0;
}

static void rods_expose(const run *r, hsbd_sim_parts *p) {
    const rods_model *m = rods_model_of(r);
    p->rods = m->rods;
    p->species = m->species;
}

static void rods_release(run *r) {
    rods_model *m = rods_model_of(r);
    if (!m) return;
    hsbd_rods_free(m->rods);
    hsbd_table_free(m->pair_table);
    hsbd_table_free(m->field_table);
    free(m->species);
    free(m->x_start);
    free(m->frame_x);
    free(m->frame_image);
    free(m->frame_unwrapped);
    free(m->frame_diameter);
    free(m);
    r->m = NULL;
}

int run_rods_build(run *r, hsbd_error *err) {
    rods_model *m = calloc(1, sizeof *m);
    if (!m) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    r->m = m;
    r->model = (run_model){.name = "rods",
                           .particles = (double)r->cfg->system.n,
                           .step = rods_step,
                           .equilibration_dt = rods_equilibration_dt,
                           .check = rods_check,
                           .start_replica = rods_start_replica,
                           .save = rods_save,
                           .load = rods_load,
                           .write_summary = rods_write_summary,
                           .expose = rods_expose,
                           .frame = rods_frame,
                           .release = rods_release};
    const int rc = build_system(r, m, err);
    return rc == HSBD_OK ? frame_alloc(r->cfg, m, err) : rc;
}
