/* Run driver for hard rods: builds the system from a finalized configuration, runs
 * equilibration and production, feeds the observers and writes the results. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/progress.h"
#include "core/vmath.h"
#include "hsbd/io.h"
#include "hsbd/observe.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"
#include "hsbd/run.h"
#include "hsbd/table.h"
#include "hsbd_version.h"
#include "io/report.h"

typedef struct run_state {
    const hsbd_config *cfg;
    const hsbd_run_options *opt;
    hsbd_rods *rods;
    hsbd_table *pair_table;  /* pair.type = table */
    hsbd_table *field_table; /* field.type with table */
    double sticky_ratio;     /* mu max|f| dt / epsilon, Eq. (33) (NaN without stickiness) */
    hsbd_profile *profile;
    hsbd_msd *msd;
    hsbd_msd *msd_species[HSBD_MAX_SPECIES]; /* mixtures: one MSD per species */
    hsbd_contacts *contacts;                 /* contacts per species pair, at walls */
    int *species;                            /* mixtures: species of each rod, line order */
    hsbd_clusters *clusters;
    hsbd_outfile trajectory, current;
    uint64_t steps_done, equil_done;
    double wall_equil, wall_prod;
    double sum_x_start, sum_x_last_current; /* for the particle current */
    double displacement_before;             /* sum of displacements of earlier replicas */
    double *x_start;                        /* init.positions in line order (replicas) */
    size_t replicas_started;                /* sample.blocking = replicas: blocks begun */
    uint64_t last_current_step;
    int completed;
    double min_gap_checked;
} run_state;

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
        .seed = cfg->system.seed,
        .hard_core = cfg->system.hard_core,
        .contact_rule = cfg->system.contact_rule,
        .boundary =
            cfg->system.boundary == HSBD_BOUNDARY_WALLS ? HSBD_RODS_WALLS : HSBD_RODS_PERIODIC,
    };
    return p;
}

/* Field terms from the configuration (field.type is a sum). A table is loaded; between
 * walls it must cover the box [0, L] (natural spline); on a ring it must span exactly one
 * period [0, L] with equal end values, and its spline is made periodic so that the force
 * stays continuous across x = 0 = L (BCD needs continuous forces). */
static int build_field(const hsbd_config *cfg, hsbd_table **table, hsbd_field *field,
                       hsbd_error *err) {
    const int t = cfg->field.type;
    const double L = cfg->system.length;
    const double period = cfg->system.boundary == HSBD_BOUNDARY_PERIODIC ? L : 0.0;
    if (t & HSBD_FIELD_COSINE)
        hsbd_field_add(field, hsbd_field_cosine(cfg->field.amplitude, cfg->field.wavelength));
    if (t & HSBD_FIELD_TILT) hsbd_field_add(field, hsbd_field_tilt(cfg->field.force));
    if (t & HSBD_FIELD_HARMONIC)
        hsbd_field_add(field, hsbd_field_harmonic(cfg->field.stiffness, cfg->field.center, period));
    if (t & HSBD_FIELD_TABLE) {
        *table = hsbd_table_load(cfg->field.table, err);
        if (!*table) return err->status;
        const double x0 = hsbd_table_x_min(*table), x1 = hsbd_table_x_max(*table);
        if (period == 0 && (x0 > 0 || x1 < L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s (field.table): x runs from %g to %g and does not cover the "
                                  "box; allowed: first x <= 0 and last x >= system.L = %g",
                                  cfg->field.table, x0, x1, L);
        if (period > 0 && (fabs(x0) > 1e-9 * L || fabs(x1 - L) > 1e-9 * L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s (field.table): x runs from %.17g to %.17g; on a ring "
                                  "(system.boundary = periodic) the table spans one period: "
                                  "allowed: first x = 0 and last x = system.L = %g",
                                  cfg->field.table, x0, x1, L);
        char what[HSBD_PATH_MAX + 64];
        snprintf(what, sizeof what, "%s (field.table on a ring)", cfg->field.table);
        if (period > 0 && hsbd_table_make_periodic(*table, what, err) != HSBD_OK)
            return err->status;
        hsbd_field_add(field, hsbd_field_table(*table, cfg->field.table_kind, period));
    }
    return HSBD_OK;
}

static double sum_unwrapped(const hsbd_rods *rods) {
    const hsbd_rods_view v = hsbd_rods_get_view(rods);
    double s = 0;
    for (size_t i = 0; i < v.n; ++i)
        s += v.z[i] + v.offset[i] + v.unwrap;
    return s;
}

/* ---- result tables ------------------------------------------------------------------ */

typedef void (*profile_getter)(const hsbd_profile *p, double *x, double *val, double *err);

/* Binned profiles as one table: x, then value and error of each getter. */
static int write_profile_table(run_state *s, const char *name, const char *what,
                               const char *columns, const profile_getter *get, size_t nget,
                               hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(s->profile);
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * nget * nb * sizeof *val);
    hsbd_outfile o;
    int rc = x && val ? hsbd_outfile_open(&o, s->cfg->output.dir, name, err)
                      : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    if (rc == HSBD_OK) {
        hsbd_write_table_header(o.f, s->cfg, what, columns);
        for (size_t g = 0; g < nget; ++g)
            get[g](s->profile, x, val + 2 * g * nb, val + (2 * g + 1) * nb);
        hsbd_write_value_columns(o.f, nb, x, nget, val);
        rc = hsbd_outfile_commit(&o, err);
    }
    free(x), free(val);
    return rc;
}

static int write_profiles(run_state *s, hsbd_error *err) {
    const profile_getter density[] = {hsbd_profile_density};
    /* the default rho2 is the estimator that is unbiased under the chosen contact rule
     * (docs/validation.md sections 8-11): the extrapolated gap density with reflect, the
     * contact theorem with sticky (whose O(sqrt dt) layer at contact spoils any gap count) */
    const int reflect = s->cfg->system.contact_rule == HSBD_CONTACT_REFLECT;
    const profile_getter contact[] = {
        reflect ? hsbd_profile_contact_extrapolated : hsbd_profile_contact, hsbd_profile_contact,
        hsbd_profile_contact_window, hsbd_profile_contact_extrapolated};
    int rc = write_profile_table(s, "density.tsv",
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
    if (rc == HSBD_OK && s->cfg->system.hard_core)
        rc = write_profile_table(s, "contact.tsv", what,
                                 "x\trho2\trho2_err\trho2_theorem\trho2_theorem_err\trho2_window\t"
                                 "rho2_window_err\trho2_extrap\trho2_extrap_err",
                                 contact, 4, err);
    return rc;
}

typedef void (*blocks_getter)(const hsbd_profile *p, double *out);

/* One profile per error block (the independent estimates behind the error bars), as
 * columns: x, block_1 .. block_n. */
static int write_blocks_table(run_state *s, const char *name, const char *what, blocks_getter get,
                              hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(s->profile), nblk = hsbd_profile_blocks(s->profile);
    double *val = malloc(nb * nblk * sizeof *val);
    if (!val) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    hsbd_outfile o;
    int rc = hsbd_outfile_open(&o, s->cfg->output.dir, name, err);
    if (rc == HSBD_OK) {
        fprintf(o.f, "# hsbd %s (git %s): %s\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT, what);
        hsbd_config_write_header(s->cfg, o.f, "# ");
        fprintf(o.f, "x");
        for (size_t b = 0; b < nblk; ++b)
            fprintf(o.f, "\tblock_%zu", b + 1);
        fputc('\n', o.f);
        get(s->profile, val);
        const double w = s->cfg->sample.period / (double)nb;
        for (size_t k = 0; k < nb; ++k) {
            fprintf(o.f, "%.10g", ((double)k + 0.5) * w);
            for (size_t b = 0; b < nblk; ++b)
                fprintf(o.f, "\t%.8g", val[b * nb + k]);
            fputc('\n', o.f);
        }
        rc = hsbd_outfile_commit(&o, err);
    }
    free(val);
    return rc;
}

static int write_profile_blocks(run_state *s, hsbd_error *err) {
    const int reflect = s->cfg->system.contact_rule == HSBD_CONTACT_REFLECT;
    const int blocking = s->cfg->sample.blocking;
    const char *unit = blocking == HSBD_BLOCKS_SPACE      ? "segment of the line"
                       : blocking == HSBD_BLOCKS_REPLICAS ? "independent replica"
                                                          : "block of time";
    char what[256];
    snprintf(what, sizeof what,
             "density profile of each %s (the estimates behind rho_err; their covariance "
             "gives correlated errors)",
             unit);
    int rc = write_blocks_table(s, "density_blocks.tsv", what, hsbd_profile_density_blocks, err);
    snprintf(what, sizeof what, "default contact density estimator (%s) of each %s",
             reflect ? "rho2_extrap" : "rho2_theorem", unit);
    if (rc == HSBD_OK && s->cfg->system.hard_core)
        rc = write_blocks_table(
            s, "contact_blocks.tsv", what,
            reflect ? hsbd_profile_contact_extrapolated_blocks : hsbd_profile_contact_blocks, err);
    return rc;
}

static int write_msd(run_state *s, hsbd_error *err) {
    hsbd_outfile o;
    int rc = hsbd_outfile_open(&o, s->cfg->output.dir, "msd.tsv", err);
    if (rc != HSBD_OK) return rc;
    char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)] = "t\tmsd\tmsd_err\torigins";
    const size_t ns = s->cfg->species.n;
    for (size_t q = 0; q < ns; ++q) {
        const char *name = s->cfg->species.name[q];
        snprintf(columns + strlen(columns), sizeof columns - strlen(columns),
                 "\tmsd_%s\tmsd_%s_err", name, name);
    }
    hsbd_write_table_header(
        o.f, s->cfg,
        "tagged-particle mean-squared displacement (unwrapped positions), all rods "
        "and, for mixtures, per species; errors from block averages over time "
        "origins",
        columns);
    for (size_t k = 0; k < hsbd_msd_lags(s->msd); ++k) {
        double t, m, e;
        size_t origins;
        hsbd_msd_result(s->msd, k, &t, &m, &e, &origins);
        if (!origins) continue;
        fprintf(o.f, "%.10g\t%.10g\t%.4g\t%zu", t, m, e, origins);
        for (size_t q = 0; q < ns; ++q) {
            hsbd_msd_result(s->msd_species[q], k, &t, &m, &e, &origins);
            fprintf(o.f, "\t%.10g\t%.4g", m, e);
        }
        fputc('\n', o.f);
    }
    return hsbd_outfile_commit(&o, err);
}

static int write_clusters(run_state *s, hsbd_error *err) {
    hsbd_outfile o;
    int rc = hsbd_outfile_open(&o, s->cfg->output.dir, "clusters.tsv", err);
    if (rc != HSBD_OK) return rc;
    hsbd_write_table_header(o.f, s->cfg, "sizes of clusters of touching rods at sampled step ends",
                            "size\tfraction");
    const size_t maxs = hsbd_clusters_max_size(s->clusters);
    for (size_t k = 1; k <= maxs; ++k)
        fprintf(o.f, "%zu\t%.10g\n", k, hsbd_clusters_size_fraction(s->clusters, k));
    return hsbd_outfile_commit(&o, err);
}

/* "contacts": contact densities per ordered species pair (contact theorem) and, between
 * walls, the densities at wall contact (wall force / kT), with block-average errors */
static void write_contacts_json(const run_state *s, FILE *f) {
    const hsbd_config *cfg = s->cfg;
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    fprintf(f, "  \"contacts\": {\n    \"pairs\": [");
    for (size_t a = 0; a < ns; ++a)
        for (size_t b = 0; b < ns; ++b) {
            double val, err;
            hsbd_contacts_pair(s->contacts, a, b, &val, &err);
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
            hsbd_contacts_wall(s->contacts, right, &val, &err);
            fprintf(f, ",\n    \"wall_%s\": %.10g,\n    \"wall_%s_err\": %.4g",
                    right ? "right" : "left", val, right ? "right" : "left",
                    isfinite(err) ? err : 0);
        }
    fprintf(f, "\n  },\n");
}

static int write_summary(run_state *s, const char *stop_reason, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    hsbd_outfile o;
    int rc = hsbd_outfile_open(&o, cfg->output.dir, "summary.json", err);
    if (rc != HSBD_OK) return rc;
    FILE *f = o.f;
    const double n = (double)cfg->system.n;
    const hsbd_rods_view v = hsbd_rods_get_view(s->rods);
    double mean_size = NAN, mean_size_err = NAN, merges = NAN, merges_err = NAN;
    if (cfg->system.hard_core)
        hsbd_clusters_means(s->clusters, &mean_size, &mean_size_err, &merges, &merges_err);
    const double t_prod = (double)s->steps_done * cfg->run.dt;
    const double displaced = s->displacement_before + sum_unwrapped(s->rods) - s->sum_x_start;
    const double current = t_prod > 0 ? displaced / (cfg->system.length * t_prod) : NAN;
    fprintf(f, "{\n  \"program\": \"hsbd\",\n  \"version\": \"%s\",\n  \"git\": \"%s\",\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    fprintf(f, "  \"model\": \"rods\",\n  \"seed\": %llu,\n", (unsigned long long)cfg->system.seed);
    fprintf(f, "  \"completed\": %s,\n", s->completed ? "true" : "false");
    fprintf(f, "  \"stop_reason\": \"%s\",\n", stop_reason);
    fprintf(f, "  \"steps\": %llu,\n  \"steps_planned\": %llu,\n  \"equilibration_steps\": %llu,\n",
            (unsigned long long)s->steps_done, (unsigned long long)hsbd_config_steps(cfg),
            (unsigned long long)s->equil_done);
    fprintf(f, "  \"samples\": %llu,\n",
            (unsigned long long)(s->steps_done / (uint64_t)cfg->sample.every));
    fprintf(f, "  \"replicas\": %zu,\n", s->replicas_started ? s->replicas_started : 1);
    hsbd_json_number(f, "time_simulated", t_prod, 1);
    hsbd_json_number(f, "wall_seconds", s->wall_prod + s->wall_equil, 1);
    hsbd_json_number(f, "wall_seconds_production", s->wall_prod, 1);
    hsbd_json_number(f, "particle_steps_per_second",
                     s->wall_prod > 0 ? n * (double)s->steps_done / s->wall_prod : NAN, 1);
    fprintf(f, "  \"vectorised_math\": %s,\n", hsbd_vmath_vectorised() ? "true" : "false");
    hsbd_json_number(f, "merge_events_per_step", merges, 1);
    hsbd_json_number(f, "merge_events_per_step_err", merges_err, 1);
    hsbd_json_number(f, "mean_cluster_size", mean_size, 1);
    hsbd_json_number(f, "mean_cluster_size_err", mean_size_err, 1);
    hsbd_json_number(f, "sticky_step_ratio", s->sticky_ratio, 1);
    hsbd_json_number(f, "min_gap", cfg->system.hard_core ? hsbd_profile_min_gap(s->profile) : NAN,
                     1);
    hsbd_json_number(f, "particle_current", current, 1);
    if (s->contacts && s->steps_done >= (uint64_t)cfg->sample.every) write_contacts_json(s, f);
    hsbd_json_number(f, "final_time", v.time, 1);
    fprintf(f, "  \"parameters\": ");
    hsbd_config_write_json(cfg, f, 2);
    fprintf(f, "\n}\n");
    return hsbd_outfile_commit(&o, err);
}

/* ---- the run ------------------------------------------------------------------------ */

/* Antonov Eq. (33): the sticky force must move a rod much less than epsilon per step. The
 * largest step of the run (equilibration may be coarser) is the one that counts. */
static int check_sticky_step(run_state *s, const hsbd_rods_params *par, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    s->sticky_ratio = NAN;
    if (!(cfg->contact.gamma > 0)) return HSBD_OK;
    hsbd_pair sticky = {0};
    hsbd_pair_add(&sticky, par->pair.term[0]);
    const double fbig =
        hsbd_pair_max_force(&sticky, cfg->system.sigma, cfg->system.sigma + cfg->contact.epsilon);
    const double mu = cfg->system.diffusion / cfg->system.kT;
    const double dt = fmax(cfg->run.dt, hsbd_config_dt_equil(cfg));
    s->sticky_ratio = mu * fbig * dt / cfg->contact.epsilon;
    const double dt_limit = cfg->contact.epsilon / (mu * fbig);
    if (s->sticky_ratio > 1.0 && !s->opt->force)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.dt = %g: the sticky force moves a rod by mu max|f| dt = "
                              "%.3g epsilon per step (Antonov Eq. 33 needs << 1); allowed: dt "
                              "(and run.dt_equil) < %.3g for contact.gamma = %g, epsilon = %g, "
                              "order = %g, or --force",
                              hsbd_config_origin(cfg, "run", "dt"), dt, s->sticky_ratio, dt_limit,
                              cfg->contact.gamma, cfg->contact.epsilon, cfg->contact.order);
    if (s->sticky_ratio > 0.1)
        fprintf(stderr,
                "hsbd: warning: sticky step ratio mu max|f| dt / epsilon = %.3g > 0.1 "
                "(Antonov Eq. 33); dt < %.3g keeps it below 0.1\n",
                s->sticky_ratio, 0.1 * dt_limit);
    else if (s->opt->progress)
        fprintf(stderr, "hsbd: sticky step ratio mu max|f| dt / epsilon = %.3g (Eq. 33)\n",
                s->sticky_ratio);
    return HSBD_OK;
}

/* Mixtures: the species of each rod along the line, a uniformly random arrangement of
 * the counts (Fisher-Yates with the seed's initial-state stream), which with the uniform
 * gaps of hsbd_rods_init_equilibrium samples the field-free equilibrium exactly. */
static int arrange_species(run_state *s, hsbd_rods_params *par, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    const size_t n = (size_t)cfg->system.n;
    s->species = malloc(n * sizeof *s->species);
    double *u = malloc(n * sizeof *u);
    if (!s->species || !u) {
        free(u);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu species", n);
    }
    size_t i = 0;
    for (size_t k = 0; k < cfg->species.n; ++k)
        for (int64_t c = 0; c < cfg->species.count[k]; ++c)
            s->species[i++] = (int)k;
    hsbd_rng_uniforms(cfg->system.seed, HSBD_STREAM_INIT, 3, 0, n, u);
    for (size_t k = n; k-- > 1;) {
        size_t j = (size_t)(u[k] * (double)(k + 1));
        if (j > k) j = k;
        const int t = s->species[k];
        s->species[k] = s->species[j];
        s->species[j] = t;
    }
    free(u);
    par->nspecies = cfg->species.n;
    par->species = s->species;
    par->species_sigma = cfg->species.sigma;
    par->species_diffusion = cfg->species.diffusion;
    return HSBD_OK;
}

/* Mixtures: one MSD observer per species (rods of that species, line order is fixed). */
static int setup_species_msd(run_state *s, const hsbd_rods_params *par, uint64_t samples,
                             hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    const hsbd_rods_view v = hsbd_rods_get_view(s->rods);
    size_t *members = malloc(par->n * sizeof *members);
    if (!members) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < cfg->species.n && rc == HSBD_OK; ++k) {
        size_t count = 0;
        for (size_t i = 0; i < par->n; ++i)
            if ((size_t)v.species[i] == k) members[count++] = i;
        s->msd_species[k] = hsbd_msd_alloc(
            par->n, cfg->run.dt * (double)cfg->sample.every, samples, cfg->sample.msd_max_lag,
            (int)cfg->sample.msd_points_per_decade, (size_t)cfg->sample.blocks, err);
        rc = s->msd_species[k] ? hsbd_msd_set_members(s->msd_species[k], count, members, err)
                               : err->status;
    }
    free(members);
    return rc;
}

/* init.positions: positions (and a mixture's species, which must match the counts). */
static int read_initial_positions(run_state *s, double *x, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    const size_t n = (size_t)cfg->system.n;
    int rc = hsbd_read_positions(cfg, x, s->species, err);
    for (size_t k = 0; k < cfg->species.n && rc == HSBD_OK; ++k) {
        int64_t c = 0;
        for (size_t i = 0; i < n; ++i)
            c += s->species[i] == (int)k;
        if (c != cfg->species.count[k])
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s (init.positions): %lld rods of species %s, but species.count "
                                "says %lld",
                                cfg->init.positions, (long long)c, cfg->species.name[k],
                                (long long)cfg->species.count[k]);
    }
    return rc;
}

static int setup(run_state *s, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    hsbd_rods_params par = rods_params_from(cfg);
    if (cfg->species.n > 0 && arrange_species(s, &par, err) != HSBD_OK) return err->status;
    int rc0 = build_field(cfg, &s->field_table, &par.field, err);
    if (rc0 == HSBD_OK) rc0 = build_pair(cfg, &s->pair_table, &par.pair, err);
    if (rc0 == HSBD_OK) rc0 = check_sticky_step(s, &par, err);
    if (rc0 != HSBD_OK) return rc0;
    double *x = NULL;
    if (cfg->init.positions[0]) { /* before the rods copy the species */
        x = malloc(par.n * sizeof *x);
        if (!x) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        rc0 = read_initial_positions(s, x, err);
    }
    if (rc0 == HSBD_OK) s->rods = hsbd_rods_alloc(&par, err);
    if (rc0 == HSBD_OK && !s->rods) rc0 = err->status;
    if (rc0 == HSBD_OK && x) rc0 = hsbd_rods_set_positions(s->rods, x, err);
    if (rc0 == HSBD_OK && !x) hsbd_rods_init_equilibrium(s->rods);
    if (rc0 == HSBD_OK && x && cfg->sample.blocking == HSBD_BLOCKS_REPLICAS) {
        /* line order, so that setting them again keeps a mixture's species in place */
        const hsbd_rods_view v = hsbd_rods_get_view(s->rods);
        for (size_t i = 0; i < par.n; ++i)
            x[i] = v.z[i] + v.offset[i];
        s->x_start = x, x = NULL;
    }
    free(x);
    if (rc0 != HSBD_OK) return rc0;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    const size_t blocks = (size_t)cfg->sample.blocks;
    s->profile = cfg->sample.blocking == HSBD_BLOCKS_SPACE
                     ? hsbd_profile_alloc_spatial(cfg->sample.period, cfg->sample.bin_width,
                                                  cfg->sample.contact_width, blocks, err)
                     : hsbd_profile_alloc(cfg->sample.period, cfg->sample.bin_width,
                                          cfg->sample.contact_width, blocks, samples, err);
    if (!s->profile) return err->status;
    s->msd = hsbd_msd_alloc(par.n, cfg->run.dt * (double)cfg->sample.every, samples,
                            cfg->sample.msd_max_lag, (int)cfg->sample.msd_points_per_decade, blocks,
                            err);
    if (!s->msd) return err->status;
    if (cfg->sample.blocking == HSBD_BLOCKS_SPACE &&
        hsbd_msd_set_segments(s->msd, blocks < par.n ? blocks : par.n, err) != HSBD_OK)
        return err->status;
    s->clusters = hsbd_clusters_alloc(par.n, blocks, samples);
    if (!s->clusters) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    if (cfg->system.hard_core) {
        s->contacts = hsbd_contacts_alloc(par.n, cfg->species.n, blocks, samples, err);
        if (!s->contacts) return err->status;
    }
    if (cfg->species.n > 0) return setup_species_msd(s, &par, samples, err);
    return HSBD_OK;
}

static int check_hard_core(run_state *s, hsbd_error *err) {
    int finite;
    const double g = hsbd_rods_min_gap(s->rods, &finite);
    if (g < s->min_gap_checked) s->min_gap_checked = g;
    const double sigma = s->cfg->system.sigma;
    if (!finite)
        return hsbd_error_set(err, HSBD_ENUMERIC, "non-finite position after step %llu",
                              (unsigned long long)hsbd_rods_get_view(s->rods).step);
    if (s->cfg->system.hard_core && g < -1e-9 * (sigma > 0 ? sigma : 1.0))
        return hsbd_error_set(err, HSBD_ENUMERIC, "--check: overlap %.3g after step %llu", g,
                              (unsigned long long)hsbd_rods_get_view(s->rods).step);
    return HSBD_OK;
}

static int stop_requested(const run_state *s) {
    return s->opt->stop && *s->opt->stop;
}

static int equilibrate(run_state *s, hsbd_error *err) {
    const uint64_t n = hsbd_config_equil_steps(s->cfg);
    hsbd_rods_set_dt(s->rods, hsbd_config_dt_equil(s->cfg));
    hsbd_progress pr;
    hsbd_progress_start(&pr, s->opt->progress, "equilibrating", (double)s->cfg->system.n);
    const double t0 = hsbd_wall_seconds();
    int rc = HSBD_OK;
    for (uint64_t k = 0; k < n; ++k) {
        hsbd_rods_step(s->rods, NULL);
        s->equil_done += 1; /* over all replicas */
        if (s->opt->check && (rc = check_hard_core(s, err)) != HSBD_OK) break;
        if ((k & 255) == 0) {
            hsbd_progress_update(&pr, k, n);
            if (stop_requested(s)) break;
            if ((rc = check_hard_core(s, err)) != HSBD_OK) break; /* O(N): NaN, overlap */
        }
    }
    s->wall_equil += hsbd_wall_seconds() - t0;
    hsbd_rods_set_dt(s->rods, s->cfg->run.dt);
    hsbd_progress_end(&pr);
    return rc;
}

/* sample.blocking = replicas: before the first step of each block after the first, a
 * fresh initial state (its own draw of the exact field-free sample, or init.positions
 * again) and its own equilibration; the noise goes on with the step counter, so every
 * replica is independent. Lags of the MSD do not cross replicas. */
static int start_replica(run_state *s, hsbd_error *err) {
    s->displacement_before += sum_unwrapped(s->rods) - s->sum_x_start;
    int rc = HSBD_OK;
    if (s->x_start)
        rc = hsbd_rods_set_positions(s->rods, s->x_start, err);
    else
        hsbd_rods_init_equilibrium_draw(s->rods, s->replicas_started);
    s->replicas_started += 1;
    if (rc == HSBD_OK) rc = equilibrate(s, err);
    hsbd_msd_restart(s->msd);
    for (size_t q = 0; q < s->cfg->species.n; ++q)
        hsbd_msd_restart(s->msd_species[q]);
    s->sum_x_start = s->sum_x_last_current = sum_unwrapped(s->rods);
    return rc;
}

/* Does a new replica begin before production step k? */
static int replica_due(const run_state *s, uint64_t k) {
    const hsbd_config *cfg = s->cfg;
    const uint64_t every = (uint64_t)cfg->sample.every;
    if (cfg->sample.blocking != HSBD_BLOCKS_REPLICAS || k == 0 || k % every != 0) return 0;
    const uint64_t total = hsbd_config_steps(cfg) / every, done = k / every;
    const size_t nb = (size_t)cfg->sample.blocks;
    return done < total &&
           hsbd_blocks_block_of(done, nb, total) != hsbd_blocks_block_of(done - 1, nb, total);
}

static int produce(run_state *s, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    const uint64_t n = hsbd_config_steps(cfg), every = (uint64_t)cfg->sample.every;
    const uint64_t traj_every =
        cfg->output.trajectory == HSBD_TRAJ_XYZ
            ? (uint64_t)fmax(1.0, round(cfg->output.trajectory_every / cfg->run.dt))
            : 0;
    const uint64_t cur_every =
        cfg->sample.current_every > 0
            ? (uint64_t)fmax(1.0, round(cfg->sample.current_every / cfg->run.dt))
            : 0;
    const int hard = cfg->system.hard_core;
    hsbd_progress pr;
    hsbd_progress_start(&pr, s->opt->progress, "running", (double)cfg->system.n);
    s->sum_x_start = s->sum_x_last_current = sum_unwrapped(s->rods);
    const double t0 = hsbd_wall_seconds(), equil0 = s->wall_equil;
    int rc = HSBD_OK;
    if (cfg->sample.blocking == HSBD_BLOCKS_REPLICAS) s->replicas_started = 1;
    for (uint64_t k = 0; k < n; ++k) {
        if (replica_due(s, k) && (rc = start_replica(s, err)) != HSBD_OK) break;
        const int sample = (k + 1) % every == 0;
        hsbd_rods_step_stats st;
        hsbd_rods_step(s->rods, sample && hard ? &st : NULL);
        s->steps_done = k + 1;
        if (s->opt->check && (rc = check_hard_core(s, err)) != HSBD_OK) break;
        if (sample) {
            const hsbd_rods_view v = hsbd_rods_get_view(s->rods);
            hsbd_profile_sample(s->profile, &v);
            hsbd_msd_sample(s->msd, &v);
            for (size_t q = 0; q < cfg->species.n; ++q)
                hsbd_msd_sample(s->msd_species[q], &v);
            if (hard) hsbd_contacts_sample(s->contacts, &v);
            if (hard) hsbd_clusters_sample(s->clusters, s->rods, &st);
            if (hsbd_profile_nonfinite(s->profile)) {
                rc = hsbd_error_set(err, HSBD_ENUMERIC,
                                    "non-finite position after step %llu (time %g); check the "
                                    "field parameters and dt. Results up to here are written.",
                                    (unsigned long long)v.step, v.time);
                break;
            }
        }
        if (traj_every && (k + 1) % traj_every == 0) {
            const hsbd_rods_view v = hsbd_rods_get_view(s->rods);
            hsbd_xyz_write_rods(s->trajectory.f, &v, cfg->species.n ? cfg->species.name : NULL);
        }
        if (cur_every && (k + 1) % cur_every == 0) {
            const double sx = sum_unwrapped(s->rods);
            const double span = (double)(k + 1 - s->last_current_step) * cfg->run.dt;
            fprintf(s->current.f, "%.10g\t%.10g\n", (double)(k + 1) * cfg->run.dt,
                    (sx - s->sum_x_last_current) / (cfg->system.length * span));
            s->sum_x_last_current = sx;
            s->last_current_step = k + 1;
        }
        if ((k & 255) == 0) {
            hsbd_progress_update(&pr, k, n);
            if (stop_requested(s)) break;
        }
    }
    s->wall_prod = hsbd_wall_seconds() - t0 - (s->wall_equil - equil0); /* replicas' own */
    hsbd_progress_end(&pr);
    s->completed = rc == HSBD_OK && s->steps_done == n;
    return rc;
}

static int open_streams(run_state *s, hsbd_error *err) {
    const hsbd_config *cfg = s->cfg;
    int rc = HSBD_OK;
    if (cfg->output.trajectory == HSBD_TRAJ_XYZ)
        rc = hsbd_outfile_open(&s->trajectory, cfg->output.dir, "trajectory.xyz", err);
    if (rc == HSBD_OK && cfg->sample.current_every > 0) {
        rc = hsbd_outfile_open(&s->current, cfg->output.dir, "current.tsv", err);
        if (rc == HSBD_OK)
            hsbd_write_table_header(s->current.f, cfg,
                                    "particle current J = sum of displacements / (L interval), per "
                                    "interval ending at t",
                                    "t\tJ");
    }
    return rc;
}

static int finish(run_state *s, int run_rc, hsbd_error *err) {
    const char *reason = run_rc == HSBD_OK ? (s->completed ? "completed" : "interrupted") : "error";
    hsbd_error werr;
    hsbd_error_clear(&werr);
    int rc = write_profiles(s, &werr);
    if (rc == HSBD_OK) rc = write_profile_blocks(s, &werr);
    if (rc == HSBD_OK) rc = write_msd(s, &werr);
    if (rc == HSBD_OK && s->cfg->system.hard_core) rc = write_clusters(s, &werr);
    if (rc == HSBD_OK) rc = hsbd_outfile_commit(&s->trajectory, &werr);
    if (rc == HSBD_OK) rc = hsbd_outfile_commit(&s->current, &werr);
    if (rc == HSBD_OK) rc = write_summary(s, reason, &werr);
    if (run_rc != HSBD_OK) return run_rc; /* the run's own error message stays in err */
    return hsbd_run_outcome(s->cfg, rc, &werr, s->completed, s->steps_done, err);
}

static void release(run_state *s) {
    hsbd_outfile_discard(&s->trajectory);
    hsbd_outfile_discard(&s->current);
    hsbd_rods_free(s->rods);
    hsbd_table_free(s->pair_table);
    hsbd_table_free(s->field_table);
    hsbd_profile_free(s->profile);
    hsbd_msd_free(s->msd);
    for (size_t q = 0; q < HSBD_MAX_SPECIES; ++q)
        hsbd_msd_free(s->msd_species[q]);
    hsbd_contacts_free(s->contacts);
    free(s->species);
    hsbd_clusters_free(s->clusters);
    free(s->x_start);
}

int hsbd_run_rods(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    hsbd_error_clear(err);
    run_state s = {.cfg = cfg, .opt = opt, .min_gap_checked = HUGE_VAL};
    /* everything that can reject the input happens before the directory is touched */
    int rc = setup(&s, err);
    if (rc == HSBD_OK) rc = hsbd_run_dir_prepare(cfg->output.dir, opt->force, err);
    if (rc == HSBD_OK) rc = open_streams(&s, err);
    if (rc != HSBD_OK) {
        release(&s);
        return rc;
    }
    rc = equilibrate(&s, err);
    if (rc == HSBD_OK && !stop_requested(&s)) rc = produce(&s, err);
    rc = finish(&s, rc, err);
    release(&s);
    return rc;
}
