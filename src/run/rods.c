/* The rods model of the run lifecycle: builds the BCD system (fields, pair forces, sticky
 * contacts, mixtures, walls, the initial state) and its observers (density and contact
 * profiles, MSD per species, contact densities per species pair, clusters, the current,
 * trajectories) and registers them with the lifecycle. */
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
#include "run/run.h"

typedef struct rods_model {
    hsbd_rods *rods;
    hsbd_table *pair_table;         /* pair.type = table */
    hsbd_table *field_table;        /* field.type with table */
    double sticky_ratio;            /* mu max|f| dt / epsilon, Eq. (33) (NaN without stickiness) */
    double field_error, pair_error; /* Euler's distortion, dt k / 4 (NaN: no such force) */
    char warnings[3][HSBD_WARNING_LEN]; /* the time step's, printed at the start */
    int nwarnings;
    hsbd_profile *profile;
    hsbd_msd *msd;
    hsbd_msd *msd_species[HSBD_MAX_SPECIES]; /* mixtures: one MSD per species */
    hsbd_contacts *contacts;                 /* contacts per species pair, at walls */
    int *species;                            /* mixtures: species of each rod, line order */
    hsbd_clusters *clusters;
    hsbd_drift *drift; /* mean velocity, D_eff of tagged rods and of the centre of mass */
    double *drift_x;   /* its scratch: N unwrapped positions */
    hsbd_profile **phase_profile; /* sample.phases: one density profile per phase bin */
    hsbd_blocks *trap; /* field.type with harmonic: X - c(t) and its square at the samples */
    double *trap_rows; /* its block means, for the summary (2 per block) */
    hsbd_rods_step_stats stats; /* of the last step, when it is sampled */
    run_stream *trajectory, *current;
    double sum_x_start, sum_x_last_current; /* for the particle current */
    double displacement_before;             /* sum of displacements of earlier replicas */
    double *x_start;                        /* init.positions in line order (replicas) */
    uint64_t last_current_step;
} rods_model;

static rods_model *model_of(const run *r) {
    return r->m;
}

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
    };
    return p;
}

static double sum_unwrapped(const hsbd_rods *rods) {
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
static int check_sticky_step(const run *r, rods_model *m, const hsbd_rods_params *par,
                             hsbd_error *err) {
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
        snprintf(m->warnings[m->nwarnings++], HSBD_WARNING_LEN,
                 "sticky step ratio mu max|f| dt / epsilon = %.3g > 0.1 (Antonov Eq. 33); dt < "
                 "%.3g keeps it below 0.1",
                 m->sticky_ratio, 0.1 * dt_limit);
    else if (r->opt->progress)
        fprintf(stderr, "hsbd: sticky step ratio mu max|f| dt / epsilon = %.3g (Eq. 33)\n",
                m->sticky_ratio);
    return HSBD_OK;
}

/* The Euler step of the field and of the continuous pair force (the sticky term apart:
 * Eq. 33 above) against their time scales, 1 / (mu max|U''|) and 1 / (2 mu max|V''|) (the
 * gap of two rods diffuses with both mobilities): estimates in the summary, warnings
 * beyond 1 %. */
static void check_field_step(const hsbd_config *cfg, rods_model *m, const hsbd_rods_params *par) {
    const double mu = mobility_max(cfg), dt = cfg->run.dt;
    m->field_error = m->pair_error = NAN;
    if (par->field.nterms) {
        const double k = mu * hsbd_field_max_curvature(&par->field);
        m->field_error = run_euler_density_error(k, dt);
        m->nwarnings +=
            run_euler_warning(k, dt, "field", "stationary density", "dt mu max|U''| / 4",
                              m->warnings[m->nwarnings], HSBD_WARNING_LEN);
    }
    hsbd_pair smooth = {0}; /* the continuous terms */
    for (size_t t = cfg->contact.gamma > 0 ? 1 : 0; t < par->pair.nterms; ++t)
        hsbd_pair_add(&smooth, par->pair.term[t]);
    if (smooth.nterms) {
        const double k = 2 * mu *
                         hsbd_pair_max_curvature(&smooth, cfg->system.sigma,
                                                 fmax(hsbd_pair_range(&smooth), cfg->system.sigma));
        m->pair_error = run_euler_density_error(k, dt);
        m->nwarnings +=
            run_euler_warning(k, dt, "pair force", "pair distribution", "dt 2 mu max|V''| / 4",
                              m->warnings[m->nwarnings], HSBD_WARNING_LEN);
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

/* init.positions: positions (and a mixture's species, which must match the counts). */
static int read_initial_positions(const hsbd_config *cfg, rods_model *m, double *x,
                                  hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    int rc = hsbd_read_positions(cfg, x, m->species, err);
    for (size_t k = 0; k < cfg->species.n && rc == HSBD_OK; ++k) {
        int64_t c = 0;
        for (size_t i = 0; i < n; ++i)
            c += m->species[i] == (int)k;
        if (c != cfg->species.count[k])
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s (init.positions): %lld rods of species %s, but species.count "
                                "says %lld",
                                cfg->init.positions, (long long)c, cfg->species.name[k],
                                (long long)cfg->species.count[k]);
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
    check_field_step(cfg, m, &par);
    double *x = NULL;
    if (cfg->init.positions[0]) { /* before the rods copy the species */
        x = malloc(par.n * sizeof *x);
        if (!x) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        rc = read_initial_positions(cfg, m, x, err);
    }
    if (rc == HSBD_OK) m->rods = hsbd_rods_alloc(&par, err);
    if (rc == HSBD_OK && !m->rods) rc = err->status;
    if (rc == HSBD_OK && x) rc = hsbd_rods_set_positions(m->rods, x, err);
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

/* ---- observers and their operations ----------------------------------------------------- */

/* The centre of mass minus the harmonic trap's centre at the state's time (each rod's
 * nearest image on a ring, as in the trap's force), and its square. */
static void sample_trap(rods_model *m, const hsbd_rods_view *v) {
    const hsbd_field *base = &hsbd_rods_get_params(m->rods)->field;
    hsbd_field now;
    const hsbd_field *field = hsbd_field_at(base, v->time, &now);
    double center = NAN, e = 0;
    for (size_t k = 0; k < field->nterms; ++k)
        if (!strcmp(field->term[k].ops->name, "harmonic"))
            center = field->term[k].p[field->term[k].ops->position - 1];
    for (size_t i = 0; i < v->n; ++i) { /* each rod's nearest image, as the trap's force */
        const double d = v->z[i] + v->offset[i] + v->unwrap - center;
        e += v->periodic ? d - v->length * floor(d / v->length + 0.5) : d;
    }
    e /= (double)v->n;
    double *acc = hsbd_blocks_acc(m->trap);
    acc[0] += e, acc[1] += e * e;
    hsbd_blocks_end_sample(m->trap);
}

/* sample.phases: the bin of t mod drive.period, K bins of the period (stroboscopic) */
static size_t phase_bin(const hsbd_config *cfg, double t) {
    const double period = cfg->drive.period, phase = t / period - floor(t / period);
    const size_t k = (size_t)(phase * (double)cfg->sample.phases);
    return k < (size_t)cfg->sample.phases ? k : (size_t)cfg->sample.phases - 1;
}

static int sample_profiles(run *r, void *ctx, hsbd_error *err) {
    rods_model *m = ctx;
    const hsbd_config *cfg = r->cfg;
    const hsbd_rods_view v = hsbd_rods_get_view(m->rods);
    if (hsbd_profile_sample(m->profile, &v) != HSBD_OK)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory sampling the profiles");
    hsbd_msd_sample(m->msd, &v);
    if (m->trap) sample_trap(m, &v);
    if (hsbd_drift_sample(m->drift, &v, m->drift_x) != HSBD_OK)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory sampling the drift");
    for (size_t q = 0; q < cfg->species.n; ++q)
        hsbd_msd_sample(m->msd_species[q], &v);
    if (cfg->system.hard_core) {
        hsbd_contacts_sample(m->contacts, &v);
        hsbd_clusters_sample(m->clusters, m->rods, &m->stats);
    }
    if (m->phase_profile && hsbd_profile_sample(m->phase_profile[phase_bin(cfg, v.time)], &v))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory sampling the phase profiles");
    if (hsbd_profile_nonfinite(m->profile))
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "non-finite position after step %llu (time %g); check the "
                              "field parameters and dt. Results up to here are written.",
                              (unsigned long long)v.step, v.time);
    return HSBD_OK;
}

static int write_frame(run *r, void *ctx, hsbd_error *err) {
    rods_model *m = ctx;
    const hsbd_rods_view v = hsbd_rods_get_view(m->rods);
    const char(*names)[HSBD_SPECIES_NAME] = r->cfg->species.n ? r->cfg->species.name : NULL;
    if (m->trajectory->is_gsd) return hsbd_gsd_write_rods(&m->trajectory->gsd, &v, names, err);
    hsbd_xyz_write_rods(m->trajectory->file.f, &v, names);
    return run_stream_check(m->trajectory, err);
}

static int write_current(run *r, void *ctx, hsbd_error *err) {
    rods_model *m = ctx;
    const hsbd_config *cfg = r->cfg;
    const double sx = sum_unwrapped(m->rods);
    const double span = (double)(r->steps_done - m->last_current_step) * cfg->run.dt;
    FILE *f = m->current->file.f;
    fprintf(f, "%.10g\t%.10g\n", (double)r->steps_done * cfg->run.dt,
            (sx - m->sum_x_last_current) / (cfg->system.length * span));
    m->sum_x_last_current = sx;
    m->last_current_step = r->steps_done;
    return run_stream_check(m->current, err);
}

static void current_header(const run *r, FILE *f) {
    hsbd_write_table_header(f, r->cfg,
                            "particle current J = sum of displacements / (L interval), per "
                            "interval ending at t",
                            "t\tJ");
}

/* Mixtures: one MSD observer per species (rods of that species, line order is fixed). */
static int build_species_msd(const hsbd_config *cfg, rods_model *m, uint64_t samples,
                             hsbd_error *err) {
    const hsbd_rods_view v = hsbd_rods_get_view(m->rods);
    size_t *members = malloc(v.n * sizeof *members);
    if (!members) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < cfg->species.n && rc == HSBD_OK; ++k) {
        size_t count = 0;
        for (size_t i = 0; i < v.n; ++i)
            if ((size_t)v.species[i] == k) members[count++] = i;
        m->msd_species[k] = hsbd_msd_alloc(
            v.n, cfg->run.dt * (double)cfg->sample.every, samples, cfg->sample.msd_max_lag,
            (int)cfg->sample.msd_points_per_decade, (size_t)cfg->sample.blocks, err);
        rc = m->msd_species[k] ? hsbd_msd_set_members(m->msd_species[k], count, members, err)
                               : err->status;
    }
    free(members);
    return rc;
}

static int build_observers(const hsbd_config *cfg, rods_model *m, hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    const size_t blocks = (size_t)cfg->sample.blocks;
    m->profile = cfg->sample.blocking == HSBD_BLOCKS_SPACE
                     ? hsbd_profile_alloc_spatial(cfg->sample.period, cfg->sample.bin_width,
                                                  cfg->sample.contact_width, blocks, err)
                     : hsbd_profile_alloc(cfg->sample.period, cfg->sample.bin_width,
                                          cfg->sample.contact_width, blocks, samples, err);
    if (!m->profile) return err->status;
    m->msd =
        hsbd_msd_alloc(n, cfg->run.dt * (double)cfg->sample.every, samples, cfg->sample.msd_max_lag,
                       (int)cfg->sample.msd_points_per_decade, blocks, err);
    if (!m->msd) return err->status;
    if (cfg->sample.blocking == HSBD_BLOCKS_SPACE &&
        hsbd_msd_set_segments(m->msd, blocks < n ? blocks : n, err) != HSBD_OK)
        return err->status;
    m->clusters = hsbd_clusters_alloc(n, blocks, samples);
    if (!m->clusters) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    m->drift = hsbd_drift_alloc(n, blocks, samples, err);
    if (!m->drift) return err->status;
    m->drift_x = malloc(n * sizeof *m->drift_x);
    if (!m->drift_x) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    if ((cfg->field.type & HSBD_FIELD_HARMONIC) &&
        (!(m->trap = hsbd_blocks_alloc(2, blocks, samples)) ||
         !(m->trap_rows = malloc(2 * blocks * sizeof *m->trap_rows))))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const size_t phases = (size_t)cfg->sample.phases;
    if (phases > 0) {
        m->phase_profile = calloc(phases, sizeof *m->phase_profile);
        if (!m->phase_profile) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        for (size_t k = 0; k < phases; ++k) {
            m->phase_profile[k] =
                hsbd_profile_alloc(cfg->sample.period, cfg->sample.bin_width,
                                   cfg->sample.contact_width, blocks, samples / phases + 1, err);
            if (!m->phase_profile[k]) return err->status;
        }
    }
    if (cfg->system.hard_core) {
        m->contacts = hsbd_contacts_alloc(n, cfg->species.n, blocks, samples, err);
        if (!m->contacts) return err->status;
    }
    if (cfg->species.n > 0) return build_species_msd(cfg, m, samples, err);
    return HSBD_OK;
}

/* ---- the model's part of the lifecycle ------------------------------------------------ */

static int rods_step(run *r, hsbd_error *err) {
    rods_model *m = model_of(r);
    /* the cluster statistics of the steps the sampling follows */
    const int stats = r->stage == RUN_PRODUCING && r->cfg->system.hard_core &&
                      (r->steps_done + 1) % (uint64_t)r->cfg->sample.every == 0;
    return hsbd_rods_step(m->rods, stats ? &m->stats : NULL) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENUMERIC, "rods: the step failed");
}

static void rods_equilibration_dt(run *r, int on) {
    hsbd_rods_set_dt(model_of(r)->rods, on ? hsbd_config_dt_equil(r->cfg) : r->cfg->run.dt);
}

static int rods_check(run *r, int strict, hsbd_error *err) {
    rods_model *m = model_of(r);
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

static void rods_start_production(run *r) {
    rods_model *m = model_of(r);
    m->sum_x_start = m->sum_x_last_current = sum_unwrapped(m->rods);
}

/* sample.blocking = replicas: a fresh initial state (its own draw of the exact field-free
 * sample, or init.positions again) before the lifecycle equilibrates it; the noise goes on
 * with the step counter, so every replica is independent. Lags of the MSD do not cross
 * replicas. */
static int rods_start_replica(run *r, size_t k, hsbd_error *err) {
    rods_model *m = model_of(r);
    m->displacement_before += sum_unwrapped(m->rods) - m->sum_x_start;
    const hsbd_rods_view end = hsbd_rods_get_view(m->rods); /* the last replica's end */
    int rc = hsbd_drift_close(m->drift, &end, m->drift_x) == HSBD_OK
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory closing a drift block");
    if (rc == HSBD_OK && m->x_start)
        rc = hsbd_rods_set_positions(m->rods, m->x_start, err);
    else if (rc == HSBD_OK)
        hsbd_rods_init_equilibrium_draw(m->rods, k);
    hsbd_msd_restart(m->msd);
    for (size_t q = 0; q < r->cfg->species.n; ++q)
        hsbd_msd_restart(m->msd_species[q]);
    m->sum_x_start = m->sum_x_last_current = sum_unwrapped(m->rods);
    return rc;
}

/* after its equilibration the replica's reference sums are those of its first
 * production step's start: the equilibration moved the rods */
static void rods_replica_reference(run *r) {
    rods_model *m = model_of(r);
    m->sum_x_start = m->sum_x_last_current = sum_unwrapped(m->rods);
}

/* ---- results ----------------------------------------------------------------------------- */

typedef void (*profile_getter)(const hsbd_profile *p, double *x, double *val, double *err);

/* Binned profiles as one table: x, then value and error of each getter. */
static int write_profile_table(const run *r, const rods_model *m, const char *name,
                               const char *what, const char *columns, const profile_getter *get,
                               size_t nget, hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(m->profile);
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * nget * nb * sizeof *val);
    int rc =
        x && val ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    for (size_t g = 0; g < nget && rc == HSBD_OK; ++g)
        get[g](m->profile, x, val + 2 * g * nb, val + (2 * g + 1) * nb);
    if (rc == HSBD_OK)
        rc = hsbd_write_columns_table(r->cfg->output.dir, name, r->cfg, what, columns, nb, x, nget,
                                      val, err);
    free(x), free(val);
    return rc;
}

static int write_profiles(const run *r, const rods_model *m, hsbd_error *err) {
    const profile_getter density[] = {hsbd_profile_density};
    /* the default rho2 is the estimator that is unbiased under the chosen contact rule
     * (docs/validation.md sections 8-11): the extrapolated gap density with reflect, the
     * contact theorem with sticky (whose O(sqrt dt) layer at contact spoils any gap count) */
    const int reflect = r->cfg->system.contact_rule == HSBD_CONTACT_REFLECT;
    const profile_getter contact[] = {
        reflect ? hsbd_profile_contact_extrapolated : hsbd_profile_contact, hsbd_profile_contact,
        hsbd_profile_contact_window, hsbd_profile_contact_extrapolated};
    int rc = write_profile_table(r, m, "density.tsv",
                                 "density profile folded into one period, Antonov Eq. 25, "
                                 "normalised to mean N/L; errors from block averages",
                                 "x\trho\trho_err", density, 1, err);
    char what[640];
    snprintf(what, sizeof what,
             "two-particle density at contact rho2(x, x+sigma), x = left rod. rho2: the default "
             "estimator, here %s (contact_rule = %s); rho2_theorem: contact theorem (mean "
             "contact impulse per time / kT); rho2_window: pairs with gaps in [0, contact_width], "
             "Antonov Eq. 26 (biased, docs/observables.md); rho2_extrap: the windowed gap density "
             "extrapolated linearly to zero gap from four sub-windows",
             reflect ? "rho2_extrap" : "rho2_theorem", reflect ? "reflect" : "sticky");
    if (rc == HSBD_OK && r->cfg->system.hard_core)
        rc = write_profile_table(r, m, "contact.tsv", what,
                                 "x\trho2\trho2_err\trho2_theorem\trho2_theorem_err\trho2_window\t"
                                 "rho2_window_err\trho2_extrap\trho2_extrap_err",
                                 contact, 4, err);
    return rc;
}

typedef void (*blocks_getter)(const hsbd_profile *p, double *out);

static int write_blocks(const run *r, const rods_model *m, const char *name, const char *what,
                        blocks_getter get, hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(m->profile), nblk = hsbd_profile_blocks(m->profile);
    double *val = malloc(nb * nblk * sizeof *val);
    if (!val) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    get(m->profile, val);
    const int rc = hsbd_write_blocks_table(r->cfg->output.dir, name, r->cfg, what, nb, nblk,
                                           r->cfg->sample.period / (double)nb, val, err);
    free(val);
    return rc;
}

static int write_profile_blocks(const run *r, const rods_model *m, hsbd_error *err) {
    const int reflect = r->cfg->system.contact_rule == HSBD_CONTACT_REFLECT;
    const int blocking = r->cfg->sample.blocking;
    const char *unit = blocking == HSBD_BLOCKS_SPACE      ? "segment of the line"
                       : blocking == HSBD_BLOCKS_REPLICAS ? "independent replica"
                                                          : "block of time";
    char what[256];
    snprintf(what, sizeof what,
             "density profile of each %s (the estimates behind rho_err; their covariance "
             "gives correlated errors)",
             unit);
    int rc = write_blocks(r, m, "density_blocks.tsv", what, hsbd_profile_density_blocks, err);
    snprintf(what, sizeof what, "default contact density estimator (%s) of each %s",
             reflect ? "rho2_extrap" : "rho2_theorem", unit);
    if (rc == HSBD_OK && r->cfg->system.hard_core)
        rc = write_blocks(
            r, m, "contact_blocks.tsv", what,
            reflect ? hsbd_profile_contact_extrapolated_blocks : hsbd_profile_contact_blocks, err);
    return rc;
}

static int write_msd(const run *r, const rods_model *m, hsbd_error *err) {
    const size_t ns = r->cfg->species.n, nl = hsbd_msd_lags(m->msd), pairs = 1 + ns;
    char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)] = "t\tmsd\tmsd_err\torigins";
    for (size_t q = 0; q < ns; ++q) {
        const char *name = r->cfg->species.name[q];
        snprintf(columns + strlen(columns), sizeof columns - strlen(columns),
                 "\tmsd_%s\tmsd_%s_err", name, name);
    }
    double *t = malloc(nl * sizeof *t), *val = malloc(2 * pairs * nl * sizeof *val);
    size_t *origins = malloc(nl * sizeof *origins);
    int rc = t && val && origins
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing msd.tsv");
    for (size_t k = 0; k < nl && rc == HSBD_OK; ++k) {
        hsbd_msd_result(m->msd, k, &t[k], &val[k], &val[nl + k], &origins[k]);
        for (size_t q = 0; q < ns; ++q) {
            double tq;
            size_t oq;
            hsbd_msd_result(m->msd_species[q], k, &tq, &val[2 * (q + 1) * nl + k],
                            &val[(2 * (q + 1) + 1) * nl + k], &oq);
        }
    }
    if (rc == HSBD_OK)
        rc =
            hsbd_write_lag_table(r->cfg->output.dir, "msd.tsv", r->cfg,
                                 "tagged-particle mean-squared displacement (unwrapped positions), "
                                 "all rods and, for mixtures, per species; errors from block "
                                 "averages over time origins",
                                 columns, nl, t, origins, pairs, val, err);
    free(t), free(val), free(origins);
    return rc;
}

static int write_clusters(const run *r, const rods_model *m, hsbd_error *err) {
    const size_t maxs = hsbd_clusters_max_size(m->clusters);
    double *fraction = malloc((maxs ? maxs : 1) * sizeof *fraction);
    if (!fraction) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing clusters.tsv");
    for (size_t k = 1; k <= maxs; ++k)
        fraction[k - 1] = hsbd_clusters_size_fraction(m->clusters, k);
    const int rc = hsbd_write_sizes_table(r->cfg->output.dir, "clusters.tsv", r->cfg,
                                          "sizes of clusters of touching rods at sampled step ends",
                                          maxs, fraction, err);
    free(fraction);
    return rc;
}

/* sample.phases: the density in each phase bin of the drive, one value/error pair each */
static int write_phase_profiles(const run *r, const rods_model *m, hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(m->profile), phases = (size_t)r->cfg->sample.phases;
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * phases * nb * sizeof *val);
    char *columns = malloc(phases * 48 + 8);
    int rc = x && val && columns
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing density_phases.tsv");
    if (rc == HSBD_OK) {
        strcpy(columns, "x");
        for (size_t k = 0; k < phases; ++k) {
            hsbd_profile_density(m->phase_profile[k], x, val + 2 * k * nb, val + (2 * k + 1) * nb);
            sprintf(columns + strlen(columns), "\trho_%zu\trho_%zu_err", k, k);
        }
        char what[320];
        snprintf(what, sizeof what,
                 "density profile resolved by the drive's phase (stroboscopic): column rho_k "
                 "holds the samples with t mod drive.period in [k, k+1) drive.period / %zu, "
                 "folded into one sample.period and normalised to mean N/L; block errors",
                 phases);
        rc = hsbd_write_columns_table(r->cfg->output.dir, "density_phases.tsv", r->cfg, what,
                                      columns, nb, x, phases, val, err);
    }
    free(x), free(val), free(columns);
    return rc;
}

static int rods_write_tables(run *r, hsbd_error *err) {
    const rods_model *m = model_of(r);
    int rc = write_profiles(r, m, err);
    if (rc == HSBD_OK && m->phase_profile) rc = write_phase_profiles(r, m, err);
    if (rc == HSBD_OK) rc = write_profile_blocks(r, m, err);
    if (rc == HSBD_OK) rc = write_msd(r, m, err);
    if (rc == HSBD_OK && r->cfg->system.hard_core) rc = write_clusters(r, m, err);
    return rc;
}

/* "contacts": contact densities per ordered species pair (contact theorem) and, between
 * walls, the densities at wall contact (wall force / kT), with block-average errors */
static void write_contacts_json(const run *r, const rods_model *m, FILE *f) {
    const hsbd_config *cfg = r->cfg;
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    fprintf(f, "  \"contacts\": {\n    \"pairs\": [");
    for (size_t a = 0; a < ns; ++a)
        for (size_t b = 0; b < ns; ++b) {
            double val, err;
            hsbd_contacts_pair(m->contacts, a, b, &val, &err);
            fprintf(f,
                    "%s\n      {\"left\": \"%s\", \"right\": \"%s\", \"rho2\": %.10g, "
                    "\"rho2_err\": %.4g}",
                    a + b ? "," : "", cfg->species.n ? cfg->species.name[a] : "rods",
                    cfg->species.n ? cfg->species.name[b] : "rods", val, isfinite(err) ? err : 0);
        }
    fprintf(f, "\n    ]");
    if (cfg->system.boundary == HSBD_BOUNDARY_WALLS)
        for (int right = 0; right < 2; ++right) {
            double val, err;
            hsbd_contacts_wall(m->contacts, right, &val, &err);
            fprintf(f, ",\n    \"wall_%s\": %.10g,\n    \"wall_%s_err\": %.4g",
                    right ? "right" : "left", val, right ? "right" : "left",
                    isfinite(err) ? err : 0);
        }
    fprintf(f, "\n  },\n");
}

/* the mean velocity and D_eff (tagged, centre of mass) of the time blocks, the open block
 * counted up to now; the current's error is the velocity's times N/L */
static void write_drift_json(const rods_model *m, const hsbd_rods_view *v, FILE *f) {
    for (size_t i = 0; i < v->n; ++i)
        m->drift_x[i] = v->z[i] + v->offset[i] + v->unwrap;
    hsbd_drift_result d;
    hsbd_drift_get(m->drift, v->time, m->drift_x, &d);
    hsbd_json_number(f, "particle_current_err", d.velocity_err * (double)v->n / v->length, 1);
    hsbd_json_number(f, "mean_velocity", d.velocity, 1);
    hsbd_json_number(f, "mean_velocity_err", d.velocity_err, 1);
    hsbd_json_number(f, "d_eff_tagged", d.d_tagged, 1);
    hsbd_json_number(f, "d_eff_tagged_err", d.d_tagged_err, 1);
    hsbd_json_number(f, "d_eff_cm", d.d_cm, 1);
    hsbd_json_number(f, "d_eff_cm_err", d.d_cm_err, 1);
    hsbd_json_number(f, "drift_block_time", d.block_time, 1);
}

/* trap_offset: <X - c> of the centre of mass X and the trap centre c(t); trap_variance: the
 * variance of X - c, per block about the overall mean (errors from the blocks' scatter) */
static void write_trap_json(const rods_model *m, FILE *f) {
    const size_t nb = hsbd_blocks_count(m->trap);
    double mean[2], err[2], *rows = m->trap_rows;
    hsbd_blocks_result(m->trap, mean, err);
    hsbd_blocks_block_means(m->trap, 0, rows);
    double var = NAN, var_err = NAN, s = 0, ss = 0;
    size_t used = 0;
    for (size_t k = 0; k < nb; ++k) {
        const double vb = rows[2 * k + 1] - 2 * mean[0] * rows[2 * k] + mean[0] * mean[0];
        if (isfinite(vb)) s += vb, ss += vb * vb, ++used;
    }
    if (used > 1) {
        var = s / (double)used;
        var_err = sqrt(fmax(ss / (double)used - var * var, 0) / (double)(used - 1));
    }
    hsbd_json_number(f, "trap_offset", mean[0], 1);
    hsbd_json_number(f, "trap_offset_err", err[0], 1);
    hsbd_json_number(f, "trap_variance", var, 1);
    hsbd_json_number(f, "trap_variance_err", var_err, 1);
}

static void rods_write_summary(run *r, FILE *f) {
    const rods_model *m = model_of(r);
    const hsbd_config *cfg = r->cfg;
    const double n = (double)cfg->system.n;
    const hsbd_rods_view v = hsbd_rods_get_view(m->rods);
    double mean_size = NAN, mean_size_err = NAN, merges = NAN, merges_err = NAN;
    if (cfg->system.hard_core)
        hsbd_clusters_means(m->clusters, &mean_size, &mean_size_err, &merges, &merges_err);
    const double t_prod = (double)r->steps_done * cfg->run.dt;
    const double displaced =
        r->steps_done ? m->displacement_before + sum_unwrapped(m->rods) - m->sum_x_start : 0;
    const double current = t_prod > 0 ? displaced / (cfg->system.length * t_prod) : NAN;
    fprintf(f, "  \"samples\": %llu,\n",
            (unsigned long long)(r->steps_done / (uint64_t)cfg->sample.every));
    fprintf(f, "  \"replicas\": %zu,\n", r->replicas_started ? r->replicas_started : 1);
    hsbd_json_number(f, "time_simulated", t_prod, 1);
    hsbd_json_number(f, "wall_seconds", r->wall_prod + r->wall_equil, 1);
    hsbd_json_number(f, "wall_seconds_production", r->wall_prod, 1);
    hsbd_json_number(f, "particle_steps_per_second",
                     r->wall_prod > 0 ? n * (double)r->steps_done / r->wall_prod : NAN, 1);
    fprintf(f, "  \"vectorised_math\": %s,\n", hsbd_vmath_vectorised() ? "true" : "false");
    hsbd_json_number(f, "merge_events_per_step", merges, 1);
    hsbd_json_number(f, "merge_events_per_step_err", merges_err, 1);
    hsbd_json_number(f, "mean_cluster_size", mean_size, 1);
    hsbd_json_number(f, "mean_cluster_size_err", mean_size_err, 1);
    hsbd_json_number(f, "sticky_step_ratio", m->sticky_ratio, 1);
    hsbd_json_number(f, "euler_field_error", m->field_error, 1);
    hsbd_json_number(f, "euler_pair_error", m->pair_error, 1);
    fprintf(f, "  \"warnings\": [");
    for (int k = 0; k < m->nwarnings; ++k) {
        fputs(k ? ", " : "", f);
        hsbd_json_string(f, m->warnings[k]);
    }
    fprintf(f, "],\n");
    hsbd_json_number(f, "min_gap", cfg->system.hard_core ? hsbd_profile_min_gap(m->profile) : NAN,
                     1);
    hsbd_json_number(f, "particle_current", current, 1);
    write_drift_json(m, &v, f);
    if (m->trap) write_trap_json(m, f);
    if (m->contacts && r->steps_done >= (uint64_t)cfg->sample.every) write_contacts_json(r, m, f);
    hsbd_json_number(f, "final_time", v.time, 1);
}

static void rods_warn_start(const run *r) {
    const rods_model *m = model_of(r);
    for (int k = 0; k < m->nwarnings; ++k)
        fprintf(stderr, "hsbd: warning: %s\n", m->warnings[k]);
}

/* ---- checkpoints ------------------------------------------------------------------------ */

static void rods_save(const run *r, hsbd_writer *w) {
    const rods_model *m = model_of(r);
    hsbd_rods_save(m->rods, w);
    hsbd_put_tag(w, "rods run");
    const double sums[3] = {m->sum_x_start, m->sum_x_last_current, m->displacement_before};
    hsbd_put_f64s(w, sums, 3);
    hsbd_put_u64(w, m->last_current_step);
    hsbd_profile_save(m->profile, w);
    hsbd_msd_save(m->msd, w);
    for (size_t q = 0; q < r->cfg->species.n; ++q)
        hsbd_msd_save(m->msd_species[q], w);
    hsbd_clusters_save(m->clusters, w);
    hsbd_drift_save(m->drift, w);
    if (m->trap) hsbd_blocks_save(m->trap, w);
    for (size_t k = 0; m->phase_profile && k < (size_t)r->cfg->sample.phases; ++k)
        hsbd_profile_save(m->phase_profile[k], w);
    if (m->contacts) hsbd_contacts_save(m->contacts, w);
    if (m->x_start) hsbd_put_f64s(w, m->x_start, (size_t)r->cfg->system.n);
}

static int rods_load(run *r, hsbd_reader *rd) {
    rods_model *m = model_of(r);
    double sums[3];
    if (hsbd_rods_load(m->rods, rd) || hsbd_get_tag(rd, "rods run") || hsbd_get_f64s(rd, sums, 3) ||
        hsbd_get_u64(rd, &m->last_current_step) || hsbd_profile_load(m->profile, rd) ||
        hsbd_msd_load(m->msd, rd))
        return -1;
    m->sum_x_start = sums[0], m->sum_x_last_current = sums[1], m->displacement_before = sums[2];
    for (size_t q = 0; q < r->cfg->species.n; ++q)
        if (hsbd_msd_load(m->msd_species[q], rd)) return -1;
    if (hsbd_clusters_load(m->clusters, rd) || hsbd_drift_load(m->drift, rd)) return -1;
    if (m->trap && hsbd_blocks_load(m->trap, rd)) return -1;
    if (m->trap) { /* an extended run has more blocks */
        double *rows = realloc(m->trap_rows, 2 * hsbd_blocks_count(m->trap) * sizeof *rows);
        if (!rows) return hsbd_reader_oom(rd, "the trap's block means");
        m->trap_rows = rows;
    }
    for (size_t k = 0; m->phase_profile && k < (size_t)r->cfg->sample.phases; ++k)
        if (hsbd_profile_load(m->phase_profile[k], rd)) return -1;
    if (m->contacts && hsbd_contacts_load(m->contacts, rd)) return -1;
    if (m->x_start && hsbd_get_f64s(rd, m->x_start, (size_t)r->cfg->system.n)) return -1;
    return 0;
}

static void rods_expose(const run *r, hsbd_sim_parts *p) {
    const rods_model *m = model_of(r);
    p->rods = m->rods;
    p->species = m->species;
    p->profile = m->profile;
    p->msd = m->msd;
    for (size_t q = 0; q < r->cfg->species.n; ++q)
        p->msd_species[q] = m->msd_species[q];
}

static void rods_release(run *r) {
    rods_model *m = model_of(r);
    if (!m) return;
    hsbd_rods_free(m->rods);
    hsbd_table_free(m->pair_table);
    hsbd_table_free(m->field_table);
    hsbd_profile_free(m->profile);
    hsbd_msd_free(m->msd);
    for (size_t q = 0; q < HSBD_MAX_SPECIES; ++q)
        hsbd_msd_free(m->msd_species[q]);
    hsbd_contacts_free(m->contacts);
    free(m->species);
    hsbd_clusters_free(m->clusters);
    hsbd_drift_free(m->drift);
    hsbd_blocks_free(m->trap);
    free(m->trap_rows);
    free(m->drift_x);
    for (size_t k = 0; m->phase_profile && k < (size_t)r->cfg->sample.phases; ++k)
        hsbd_profile_free(m->phase_profile[k]);
    free(m->phase_profile);
    free(m->x_start);
    free(m);
    r->m = NULL;
}

/* ---- registration ----------------------------------------------------------------------- */

static int register_ops(run *r, rods_model *m, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    int rc = run_add_op(r, "sample", (uint64_t)cfg->sample.every, sample_profiles, m, err);
    if (rc == HSBD_OK) rc = run_add_trajectory(r, write_frame, m, &m->trajectory, err);
    if (rc == HSBD_OK && cfg->sample.current_every > 0) {
        m->current = run_add_stream(r, "current.tsv", err);
        if (m->current) m->current->header = current_header;
        rc = m->current ? run_add_op(r, "current", run_every(cfg, cfg->sample.current_every),
                                     write_current, m, err)
                        : err->status;
    }
    return rc;
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
                           .replica_ready = rods_replica_reference,
                           .start_production = rods_start_production,
                           .save = rods_save,
                           .load = rods_load,
                           .write_tables = rods_write_tables,
                           .write_summary = rods_write_summary,
                           .expose = rods_expose,
                           .warn_start = rods_warn_start,
                           .release = rods_release};
    int rc = build_system(r, m, err);
    if (rc == HSBD_OK) rc = build_observers(r->cfg, m, err);
    if (rc == HSBD_OK) rc = register_ops(r, m, err);
    return rc;
}
