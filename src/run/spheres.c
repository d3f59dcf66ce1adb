/* The spheres model of the run lifecycle: builds the EDBD system of hard disks or spheres
 * (species, polydispersity, initial state) and its observers (g(r) and contact values,
 * MSD and F_s(k, t) per species, the collisional virial, trajectories) and registers them
 * with the lifecycle. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/io.h"
#include "hsbd/observe.h"
#include "hsbd/spheres.h"
#include "hsbd/table.h"
#include "hsbd/theory.h"
#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/run.h"
#include "run/walls.h"
#include "spheres/checkpoint.h"

typedef struct spheres_model {
    hsbd_spheres *sys;
    int *species;
    size_t ns;         /* species (1 for one species) */
    double *unwrapped; /* d N unwrapped coordinates for the MSD */
    hsbd_gr *gr;
    char no_gr[HSBD_WARNING_LEN]; /* why gr.tsv is not written ("" when it is) */
    hsbd_msd *msd;
    hsbd_msd *msd_species[HSBD_MAX_SPECIES];
    hsbd_blocks *virial; /* collisional virial per sampled interval */
    double virial_last;
    run_stream *trajectory;
    hsbd_field field;        /* field.type along field.axis (the engine reads it) */
    hsbd_table *field_table; /* a tabulated term's table */
    double *coupling;        /* per particle: the field's factor */
    walls_observers walls;   /* profiles and wall contacts (walls or a field) */
} spheres_model;

static spheres_model *model_of(const run *r) {
    return r->m;
}

static const char *species_name(const run *r, size_t k) {
    return r->cfg->species.n ? r->cfg->species.name[k] : "S";
}

/* ---- set-up ---- */

/* The initial state: init.positions, or init.method (random, lattice, compression). */
static int place_particles(const run *r, spheres_model *m, double *x, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    char why[sizeof err->message];
    int rc;
    if (x) {
        rc = hsbd_spheres_set_positions(m->sys, x, err);
        if (rc != HSBD_OK) {
            snprintf(why, sizeof why, "%s", err->message);
            hsbd_error_set(err, rc, "init.positions '%s': %s", cfg->init.positions, why);
        }
        return rc;
    }
    static const char *const method[] = {"auto", "random", "lattice", "compress"};
    rc = cfg->init.method == HSBD_INIT_LATTICE    ? hsbd_spheres_init_lattice(m->sys, err)
         : cfg->init.method == HSBD_INIT_COMPRESS ? hsbd_spheres_init_compress(m->sys, err)
                                                  : hsbd_spheres_init_random(m->sys, err);
    if (rc == HSBD_EINPUT) {
        snprintf(why, sizeof why, "%s", err->message);
        hsbd_error_set(err, rc, "%s: init.method = %s: %s",
                       hsbd_config_origin(cfg, "init", "method"), method[cfg->init.method], why);
    }
    return rc;
}

/* Particles of an XYZ input must lie between the walls: the file's line of the first
 * that does not (line i + 3 of particle i). */
static int check_positions_walls(const hsbd_config *cfg, const double *x, const double *sigma,
                                 hsbd_error *err) {
    for (size_t i = 0; i < (size_t)cfg->system.n; ++i)
        for (int a = 0; a < (int)cfg->system.dimension; ++a) {
            const double half = 0.5 * sigma[i], top = cfg->system.box[a] - half, tol = 1e-9;
            if (!cfg->system.walls[a] || (x[3 * i + a] >= half * (1 - tol) &&
                                          x[3 * i + a] <= top + tol * cfg->system.box[a]))
                continue;
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%zu: particle %zu at %c = %.9g is outside the walls "
                                  "(system.boundary); allowed: sigma/2 = %.9g <= %c <= box - "
                                  "sigma/2 = %.9g",
                                  cfg->init.positions, i + 3, i + 1, "xyz"[a], x[3 * i + a], half,
                                  "xyz"[a], top);
        }
    return HSBD_OK;
}

/* The field along field.axis and each particle's coupling: species.coupling, or
 * (sigma_i / system.sigma)^d with coupling_law = volume. */
static int build_field_couplings(const hsbd_config *cfg, spheres_model *m, const double *sigma,
                                 hsbd_error *err) {
    if (!cfg->field.type) return HSBD_OK;
    const int axis = cfg->field.axis, dim = (int)cfg->system.dimension;
    if (run_build_field(cfg, cfg->system.box[axis], !cfg->system.walls[axis],
                        "the box length along field.axis", &m->field_table, &m->field,
                        err) != HSBD_OK)
        return err->status;
    const size_t n = (size_t)cfg->system.n;
    if (!(m->coupling = malloc(n * sizeof *m->coupling)))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; ++i)
        m->coupling[i] = cfg->species.coupling_law == HSBD_COUPLING_VOLUME
                             ? pow(sigma[i] / cfg->system.sigma, dim)
                             : cfg->species.coupling[m->species[i]];
    return HSBD_OK;
}

static int build_system(const run *r, spheres_model *m, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const size_t n = (size_t)cfg->system.n;
    m->ns = cfg->species.n ? cfg->species.n : 1;
    m->species = calloc(n, sizeof *m->species);
    double *x = NULL, *sigma = malloc(2 * n * sizeof *sigma), *diffusion = sigma + n;
    if (!m->species || !sigma)
        return free(sigma), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    /* species in blocks (initial states place particles randomly), sizes and D */
    if (hsbd_config_particles(cfg, m->species, sigma, diffusion, err) != HSBD_OK)
        return free(sigma), err->status;
    if (cfg->init.positions[0]) { /* resuming too: the file gives the sizes and species */
        x = malloc(3 * n * sizeof *x);
        if (!x) return free(sigma), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        if (hsbd_xyz_read_positions(cfg, x, m->species, sigma, err) != HSBD_OK)
            return free(x), free(sigma), err->status;
        for (size_t i = 0; i < n; ++i) { /* the file's species (and diameters) */
            const size_t k = (size_t)m->species[i];
            const double sk = cfg->species.n ? cfg->species.sigma[k] : cfg->system.sigma;
            if (!(cfg->species.polydispersity > 0)) sigma[i] = sk;
            diffusion[i] = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
            if (cfg->species.d_law == HSBD_D_STOKES_EINSTEIN) diffusion[i] *= sk / sigma[i];
        }
        if (check_positions_walls(cfg, x, sigma, err) != HSBD_OK)
            return free(x), free(sigma), err->status;
    }
    if (build_field_couplings(cfg, m, sigma, err) != HSBD_OK)
        return free(x), free(sigma), err->status;
    hsbd_spheres_params p = {.n = n,
                             .dimension = (int)cfg->system.dimension,
                             .sigma = cfg->system.sigma,
                             .diffusion = cfg->system.diffusion,
                             .kT = cfg->system.kT,
                             .dt = cfg->run.dt,
                             .seed = run_noise_seed(cfg),
                             .hard_core = cfg->system.hard_core,
                             .shell = cfg->system.shell,
                             .nspecies = cfg->species.n,
                             .species = m->species,
                             .species_sigma = cfg->species.sigma,
                             .species_diffusion = cfg->species.diffusion,
                             .particle_sigma = sigma,
                             .particle_diffusion = diffusion,
                             .field = cfg->field.type ? &m->field : NULL,
                             .field_axis = cfg->field.axis,
                             .particle_coupling = m->coupling,
                             .event_order = (hsbd_spheres_event_order)cfg->run.events,
                             .threads = run_threads(cfg)};
    for (int a = 0; a < 3; ++a)
        p.box[a] = cfg->system.box[a], p.drift[a] = cfg->system.drift[a],
        p.walls[a] = cfg->system.walls[a];
    m->sys = hsbd_spheres_alloc(&p, err);
    free(sigma);
    if (!m->sys) {
        free(x);
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message); /* name the keys behind the message */
        return hsbd_error_set(
            err, err->status, "%s: %s (system.shell: %s)",
            hsbd_config_origin(cfg, "system", cfg->system.box_text[0] ? "box" : "packing_fraction"),
            why, hsbd_config_origin(cfg, "system", "shell"));
    }
    const int rc = r->resuming ? HSBD_OK : place_particles(r, m, x, err);
    free(x);
    return rc;
}

static int build_observers(const hsbd_config *cfg, spheres_model *m, hsbd_error *err) {
    const uint64_t steps = hsbd_config_steps(cfg), every = (uint64_t)cfg->sample.every;
    const size_t blocks = (size_t)cfg->sample.blocks, n = (size_t)cfg->system.n;
    const size_t d = (size_t)cfg->system.dimension;
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    /* g(r) with a profile-weighted reference along the walls axis or the field's axis (ideal
     * particles too, whose g = 1 checks it), the homogeneous one in a periodic box without a
     * field; none between walls on more axes or with a field across the walls axis (the
     * reference would need the density over a plane) */
    int walls = 0, axis = cfg->field.type ? cfg->field.axis : -1;
    for (int a = 0; a < 3; ++a)
        if (cfg->system.walls[a]) walls++, axis = axis < 0 || axis == a ? a : 3;
    if (axis < 3 && walls <= 1 && (cfg->system.hard_core || axis >= 0)) {
        m->gr = hsbd_gr_alloc_profile(&v, axis, cfg->sample.gr_max, cfg->sample.gr_bin,
                                      cfg->sample.contact_fit, blocks,
                                      steps / (uint64_t)cfg->sample.gr_every, err);
        if (!m->gr) return err->status;
    } else {
        snprintf(m->no_gr, sizeof m->no_gr,
                 "gr.tsv is not written (nor contact values or "
                 "Z_virial): %s",
                 axis < 3 && walls <= 1
                     ? "ideal particles (system.hard_core = off) in a periodic box without a "
                       "field have g(r) = 1"
                     : "its reference density would be a profile over a plane (walls on "
                       "two or more axes, or a field across the walls' axis); the density "
                       "profiles along each walls' axis are written");
    }
    if (walls_observers_build(cfg, &v, &m->walls, err) != HSBD_OK) return err->status;
    m->virial = hsbd_blocks_alloc(1, blocks, steps / every);
    m->unwrapped = malloc(d * n * sizeof *m->unwrapped);
    if (!m->virial || !m->unwrapped) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const double dt_sample = cfg->run.dt * (double)every;
    m->msd = hsbd_msd_alloc(d * n, dt_sample, steps / every, cfg->sample.msd_max_lag,
                            (int)cfg->sample.msd_points_per_decade, blocks, err);
    if (!m->msd || hsbd_msd_set_wavenumber(m->msd, cfg->sample.fs_k, err) != HSBD_OK)
        return err->status;
    if (cfg->species.n < 2) return HSBD_OK;
    size_t *idx = malloc(d * n * sizeof *idx);
    if (!idx) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t k = 0; k < cfg->species.n; ++k) {
        size_t c = 0;
        for (size_t i = 0; i < n; ++i)
            if ((size_t)m->species[i] == k)
                for (size_t a = 0; a < d; ++a)
                    idx[c++] = d * i + a;
        m->msd_species[k] = hsbd_msd_alloc(d * n, dt_sample, steps / every, cfg->sample.msd_max_lag,
                                           (int)cfg->sample.msd_points_per_decade, blocks, err);
        if (!m->msd_species[k] || hsbd_msd_set_members(m->msd_species[k], c, idx, err) ||
            hsbd_msd_set_wavenumber(m->msd_species[k], cfg->sample.fs_k, err)) {
            free(idx);
            return err->status;
        }
    }
    free(idx);
    return HSBD_OK;
}

/* The scheme's assumptions (Scala Eqs. 3 and 6, collisions per particle-step) from the
 * particles' own sizes and D; warnings on stderr (collisions: once measured), unless the
 * run keeps them to its summary.json. */
static void warn_scheme(const run *r, const spheres_model *m, double collisions_per_particle_step) {
    if (r->opt->quiet_warnings) return;
    if (m->no_gr[0] && isnan(collisions_per_particle_step))
        fprintf(stderr, "hsbd: warning: %s\n", m->no_gr);
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    hsbd_scheme_check c;
    hsbd_scheme_check_compute(&v, collisions_per_particle_step, &c);
    char msg[3][HSBD_WARNING_LEN];
    const int n = hsbd_scheme_check_warnings(&c, msg, 3);
    for (int k = 0; k < n; ++k) {
        const int measured = strstr(msg[k], "collisions per particle") != NULL;
        if (measured == !isnan(collisions_per_particle_step))
            fprintf(stderr, "hsbd: warning: %s\n", msg[k]);
    }
}

static void spheres_warn_start(const run *r) {
    warn_scheme(r, model_of(r), NAN);
}

/* ---- operations ---- */

static int sample_virial_msd(run *r, void *ctx, hsbd_error *err) {
    (void)err;
    spheres_model *m = ctx;
    const double vir = hsbd_spheres_get_stats(m->sys).virial;
    hsbd_blocks_acc(m->virial)[0] += vir - m->virial_last;
    hsbd_blocks_end_sample(m->virial);
    m->virial_last = vir;
    walls_observers_sample(&m->walls, m->sys);
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    const size_t d = (size_t)v.dimension;
    for (size_t i = 0; i < v.n; ++i)
        for (size_t a = 0; a < d; ++a)
            m->unwrapped[d * i + a] = v.x[3 * i + a] + (double)v.image[3 * i + a] * v.box[a];
    hsbd_msd_sample_values(m->msd, m->unwrapped);
    for (size_t k = 0; k < r->cfg->species.n && m->msd_species[k]; ++k)
        hsbd_msd_sample_values(m->msd_species[k], m->unwrapped);
    return HSBD_OK;
}

static int sample_gr(run *r, void *ctx, hsbd_error *err) {
    (void)r;
    spheres_model *m = ctx;
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    return hsbd_gr_sample(m->gr, &v) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "g(r): out of memory for its cells");
}

static int write_frame(run *r, void *ctx, hsbd_error *err) {
    spheres_model *m = ctx;
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    const char(*names)[HSBD_SPECIES_NAME] = r->cfg->species.n ? r->cfg->species.name : NULL;
    if (m->trajectory->is_gsd) return hsbd_gsd_write_spheres(&m->trajectory->gsd, &v, names, err);
    hsbd_xyz_write_spheres(m->trajectory->file.f, &v, names);
    return run_stream_check(m->trajectory, err);
}

/* ---- the model's part of the lifecycle ---- */

static int spheres_step(run *r, hsbd_error *err) {
    const spheres_model *m = model_of(r);
    const int rc = hsbd_spheres_step(m->sys);
    return rc == HSBD_OK ? HSBD_OK
                         : hsbd_error_set(err, rc, "spheres: out of memory in step %llu",
                                          (unsigned long long)hsbd_spheres_get_view(m->sys).step);
}

static int spheres_check(run *r, int strict, hsbd_error *err) {
    const spheres_model *m = model_of(r);
    int finite;
    const double g = hsbd_spheres_min_gap(m->sys, &finite);
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    if (!finite)
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "non-finite position after step %llu (time %g); results up to "
                              "here are written",
                              (unsigned long long)v.step, v.time);
    if (strict && g < -1e-9)
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "--check: overlap %.3g (relative) after step %llu", g,
                              (unsigned long long)v.step);
    return HSBD_OK;
}

/* The equilibration's collision rate is warned about; production counts from zero. */
static void spheres_start_production(run *r) {
    spheres_model *m = model_of(r);
    if (r->equil_done > 0)
        warn_scheme(r, m,
                    (double)hsbd_spheres_get_stats(m->sys).collisions /
                        ((double)r->cfg->system.n * (double)r->equil_done));
    hsbd_spheres_reset_stats(m->sys);
    m->virial_last = 0;
    walls_observers_restart(&m->walls);
}

/* ---- results ---- */

static int write_gr(const run *r, const spheres_model *m, hsbd_error *err) {
    const size_t nb = hsbd_gr_bins(m->gr), np = hsbd_gr_pairs(m->gr);
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * np * nb * sizeof *val);
    if (!x || !val) {
        free(x), free(val);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing gr.tsv");
    }
    char columns[64 + HSBD_MAX_SPECIES * HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)] = "r";
    for (size_t p = 0; p < np; ++p) {
        size_t a, b;
        hsbd_gr_pair_species(m->gr, p, &a, &b);
        const size_t len = strlen(columns);
        snprintf(columns + len, sizeof columns - len, "\tg_%s_%s\tg_%s_%s_err", species_name(r, a),
                 species_name(r, b), species_name(r, a), species_name(r, b));
        hsbd_gr_result(m->gr, p, x, val + 2 * p * nb, val + (2 * p + 1) * nb);
    }
    const int rc = hsbd_write_columns_table(r->cfg->output.dir, "gr.tsv", r->cfg,
                                            hsbd_gr_profile_axis(m->gr) >= 0
                                                ? "radial distribution function per species "
                                                  "pair (bin centres) over the pairs of "
                                                  "independent particles with the density "
                                                  "profile sampled along the walls or field "
                                                  "axis; errors from time blocks"
                                                : "radial distribution function per species pair "
                                                  "(bin centres); errors from time blocks",
                                            columns, nb, x, np, val, err);
    free(x), free(val);
    return rc;
}

/* msd.tsv (the per-particle MSD: d times that of the coordinates) or fs.tsv (F_s) */
static int write_time_table(const run *r, const spheres_model *m, const char *name, int fs,
                            hsbd_error *err) {
    const size_t d = (size_t)r->cfg->system.dimension, ns = r->cfg->species.n;
    const size_t per_species = ns > 1 ? ns : 0, pairs = 1 + per_species;
    const char *what = fs ? "fs" : "msd";
    char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)];
    snprintf(columns, sizeof columns, "t\t%s\t%s_err\torigins", what, what);
    for (size_t q = 0; q < per_species; ++q) {
        const size_t len = strlen(columns);
        snprintf(columns + len, sizeof columns - len, "\t%s_%s\t%s_%s_err", what,
                 r->cfg->species.name[q], what, r->cfg->species.name[q]);
    }
    char title[256];
    if (fs)
        snprintf(title, sizeof title,
                 "self-intermediate scattering function F_s(k, t) at k = %g (k along each axis, "
                 "averaged), all particles and per species; errors from blocks of time origins",
                 r->cfg->sample.fs_k);
    else
        snprintf(title, sizeof title,
                 "mean-squared displacement per particle (unwrapped, summed over the %zu "
                 "dimensions), all particles and per species; errors from blocks of time origins",
                 d);
    const double scale = fs ? 1.0 : (double)d;
    const size_t nl = hsbd_msd_lags(m->msd);
    double *t = malloc(nl * sizeof *t), *val = malloc(2 * pairs * nl * sizeof *val);
    size_t *origins = malloc(nl * sizeof *origins);
    int rc = t && val && origins
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    for (size_t k = 0; k < nl && rc == HSBD_OK; ++k)
        for (size_t p = 0; p < pairs; ++p) {
            const hsbd_msd *src = p ? m->msd_species[p - 1] : m->msd;
            double tk, v, e;
            size_t o;
            hsbd_msd_result(src, k, &tk, &v, &e, &o);
            if (fs) hsbd_msd_fs(src, k, &v, &e);
            if (!p) t[k] = tk, origins[k] = o;
            val[2 * p * nl + k] = scale * v, val[(2 * p + 1) * nl + k] = scale * e;
        }
    if (rc == HSBD_OK)
        rc = hsbd_write_lag_table(r->cfg->output.dir, name, r->cfg, title, columns, nl, t, origins,
                                  pairs, val, err);
    free(t), free(val), free(origins);
    return rc;
}

static int spheres_write_tables(run *r, hsbd_error *err) {
    const spheres_model *m = model_of(r);
    int rc = m->gr ? write_gr(r, m, err) : HSBD_OK;
    if (rc == HSBD_OK) rc = write_time_table(r, m, "msd.tsv", 0, err);
    if (rc == HSBD_OK) rc = write_time_table(r, m, "fs.tsv", 1, err);
    if (rc == HSBD_OK) rc = walls_observers_write_tables(r, &m->walls, err);
    return rc;
}

/* "contacts": g_ab(sigma_ab+) per pair with the equation of state's value; Z from them by
 * the virial route, Z = 1 + sum_ab C_ab g_ab, beside the equation of state's Z. Between
 * walls or in a field the values over all pairs against the profile-weighted reference, and
 * neither an equation of state nor Z (the density varies). */
static void write_contacts_json(const run *r, const spheres_model *m, FILE *f) {
    const int slab = hsbd_gr_profile_axis(m->gr) >= 0;
    const hsbd_config *cfg = r->cfg;
    const int dim = (int)cfg->system.dimension;
    double vol = 1;
    for (int a = 0; a < dim; ++a)
        vol *= cfg->system.box[a];
    const double rho = (double)cfg->system.n / vol;
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    hsbd_size_classes classes;
    hsbd_size_classes_build(&v, m->ns, &classes);
    const int mono = m->ns == 1 && !classes.polydisperse;
    double z = 1, var = 0, z_theory = 1;
    const char *eos = dim == 3 ? (mono ? "Carnahan-Starling" : "BMCSL")
                               : (mono ? "virial series B2-B10" : "none");
    fprintf(f, "  \"contacts\": [");
    for (size_t p = 0; p < hsbd_gr_pairs(m->gr); ++p) {
        size_t a, b;
        hsbd_gr_pair_species(m->gr, p, &a, &b);
        double val, err;
        hsbd_gr_contact(m->gr, p, &val, &err);
        if (slab) {
            fprintf(f,
                    "%s\n    {\"a\": \"%s\", \"b\": \"%s\", \"g_contact\": %.10g, "
                    "\"g_contact_err\": %.4g, \"reference\": \"profile\"}",
                    p ? "," : "", species_name(r, a), species_name(r, b), isfinite(val) ? val : 0,
                    isfinite(err) ? err : 0);
            continue;
        }
        const double weight = hsbd_gr_contact_weight(m->gr, p);
        z += weight * val, var += weight * weight * err * err;
        double theory = NAN;
        if (dim == 3)
            theory = mono ? hsbd_hs_contact_cs(cfg->system.packing_fraction)
                          : hsbd_size_classes_bmcsl_contact(&classes, rho, a, b);
        else if (mono)
            theory = hsbd_hd_contact_virial(cfg->system.packing_fraction); /* Henderson: +0.14 % */
        z_theory += weight * theory;
        fprintf(f,
                "%s\n    {\"a\": \"%s\", \"b\": \"%s\", \"g_contact\": %.10g, \"g_contact_err\": "
                "%.4g, \"theory\": %.10g, \"theory_eos\": \"%s\", \"Z_weight\": %.10g}",
                p ? "," : "", species_name(r, a), species_name(r, b), val, isfinite(err) ? err : 0,
                isfinite(theory) ? theory : 0, eos, weight);
    }
    fprintf(f, "\n  ],\n");
    if (slab) return;
    hsbd_json_number(f, "Z_contact", z, 1);
    hsbd_json_number(f, "Z_contact_err", sqrt(var), 1); /* pairs treated as independent */
    hsbd_json_number(f, "Z_theory", z_theory, 1);
    fprintf(f, "  \"Z_theory_eos\": \"%s\",\n", eos);
    if (dim == 3 && mono) { /* CS is 0.26 % low at phi 0.3 */
        hsbd_json_number(f, "Z_theory_klm", hsbd_hs_z_klm(cfg->system.packing_fraction), 1);
        hsbd_json_number(f, "g_contact_theory_klm",
                         hsbd_hs_contact_klm(cfg->system.packing_fraction), 1);
    }
}

/* "sizes": the diameters as simulated (drawn, or read with the positions) */
static void write_sizes_json(const run *r, const spheres_model *m, FILE *f) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    double mean = 0, var = 0, lo = INFINITY, hi = 0;
    for (size_t i = 0; i < v.n; ++i)
        mean += v.sigma[i] / (double)v.n, lo = fmin(lo, v.sigma[i]), hi = fmax(hi, v.sigma[i]);
    for (size_t i = 0; i < v.n; ++i)
        var += (v.sigma[i] - mean) * (v.sigma[i] - mean) / (double)v.n;
    static const char *const dist[] = {"gaussian", "uniform"}, *const law[] = {"given",
                                                                               "stokes-einstein"};
    fprintf(f,
            "  \"sizes\": {\"mean\": %.10g, \"relative_width\": %.6g, \"min\": %.10g, \"max\": "
            "%.10g, \"polydispersity\": %g, \"distribution\": \"%s\", \"D_law\": \"%s\"},\n",
            mean, sqrt(var) / mean, lo, hi, r->cfg->species.polydispersity,
            dist[r->cfg->species.distribution], law[r->cfg->species.d_law]);
}

static void spheres_write_summary(run *r, FILE *f) {
    const spheres_model *m = model_of(r);
    const hsbd_config *cfg = r->cfg;
    const double n = (double)cfg->system.n, steps = (double)r->steps_done;
    const int dim = (int)cfg->system.dimension;
    /* statistics since production began (the equilibration's if it never did) */
    const hsbd_spheres_stats st = hsbd_spheres_get_stats(m->sys);
    const double t_prod = steps * cfg->run.dt;
    fprintf(f, "  \"dimension\": %d,\n", dim);
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys); /* an XYZ input's own sizes */
    hsbd_json_number(f, "packing_fraction", hsbd_spheres_packing_fraction(dim, v.box, v.n, v.sigma),
                     1);
    fprintf(f, "  \"box\": [%.17g, %.17g, %.17g],\n", cfg->system.box[0], cfg->system.box[1],
            cfg->system.box[2]);
    write_sizes_json(r, m, f);
    hsbd_json_number(f, "shell", hsbd_spheres_shell(m->sys), 1);
    hsbd_json_number(f, "time_simulated", t_prod, 1);
    hsbd_json_number(f, "cpu_seconds", r->cpu_prod + r->cpu_equil, 1);
    hsbd_json_number(f, "cpu_seconds_production", r->cpu_prod, 1);
    hsbd_json_number(f, "wall_seconds_production", r->wall_prod, 1);
    hsbd_json_number(f, "particle_steps_per_second",
                     r->cpu_prod > 0 ? n * steps / r->cpu_prod : NAN, 1);
    hsbd_json_number(f, "collisions_per_second",
                     r->cpu_prod > 0 ? (double)st.collisions / r->cpu_prod : NAN, 1);
    hsbd_json_number(f, "time_per_cpu_second", r->cpu_prod > 0 ? t_prod / r->cpu_prod : NAN, 1);
    /* diagnostics: the scheme's assumptions (Scala Eqs. 3 and 6), the particles' own values */
    const double cpp = steps > 0 ? (double)st.collisions / (n * steps) : NAN;
    hsbd_scheme_check check;
    hsbd_scheme_check_compute(&v, cpp, &check);
    hsbd_json_number(f, "collisions_per_particle_step", cpp, 1);
    hsbd_json_number(f, "mean_step_over_sigma", check.step_over_sigma, 1);
    hsbd_json_number(f, "mean_step_over_mean_gap", check.step_over_gap, 1);
    char warnings[3][HSBD_WARNING_LEN];
    const int nw = hsbd_scheme_check_warnings(&check, warnings, 3);
    fprintf(f, "  \"warnings\": [");
    for (int k = 0; k < nw; ++k) {
        fputs(k ? ", " : "", f);
        hsbd_json_string(f, warnings[k]);
    }
    if (m->no_gr[0]) {
        fputs(nw ? ", " : "", f);
        hsbd_json_string(f, m->no_gr);
    }
    fprintf(f, "],\n");
    hsbd_json_number(f, "shell_updates_per_particle_step",
                     steps > 0 ? (double)st.shell_updates / (n * steps) : NAN, 1);
    /* the collisional virial: Z = 1 + <sum sigma_ij n . F_j> / (d N kT) */
    double vm = NAN, ve = NAN;
    hsbd_blocks_result(m->virial, &vm, &ve);
    const double per = cfg->run.dt * (double)cfg->sample.every * (double)dim * n;
    if (m->gr && hsbd_gr_profile_axis(m->gr) < 0) { /* a homogeneous periodic box */
        hsbd_json_number(f, "Z_virial", 1 + vm / per, 1);
        hsbd_json_number(f, "Z_virial_err", ve / per, 1);
    }
    if (m->gr && cfg->system.hard_core) write_contacts_json(r, m, f);
    walls_observers_write_summary(r, &m->walls, f);
    double dl, dle;
    hsbd_msd_long_time_diffusion(m->msd, dim, &dl, &dle);
    hsbd_json_number(f, "D_long", dl, 1);
    hsbd_json_number(f, "D_long_err", dle, 1);
    if (cfg->species.n > 1) {
        fprintf(f, "  \"D_long_species\": {");
        for (size_t k = 0; k < cfg->species.n; ++k) {
            hsbd_msd_long_time_diffusion(m->msd_species[k], dim, &dl, &dle);
            fprintf(f, "%s\"%s\": [%.10g, %.4g]", k ? ", " : "", cfg->species.name[k],
                    isfinite(dl) ? dl : 0, isfinite(dle) ? dle : 0);
        }
        fprintf(f, "},\n");
    }
    int finite;
    hsbd_json_number(f, "min_gap", hsbd_spheres_min_gap(m->sys, &finite), 1);
}

/* ---- checkpoints ---- */

static void spheres_save(const run *r, hsbd_writer *w) {
    const spheres_model *m = model_of(r);
    hsbd_spheres_save(m->sys, w);
    hsbd_put_tag(w, "spheres run");
    hsbd_put_f64(w, m->virial_last);
    hsbd_blocks_save(m->virial, w);
    hsbd_msd_save(m->msd, w);
    for (size_t k = 0; k < r->cfg->species.n && m->msd_species[k]; ++k)
        hsbd_msd_save(m->msd_species[k], w);
    if (m->gr) hsbd_gr_save(m->gr, w);
    walls_observers_save(&m->walls, w);
}

static int spheres_load(run *r, hsbd_reader *rd) {
    spheres_model *m = model_of(r);
    if (hsbd_spheres_load(m->sys, rd) || hsbd_get_tag(rd, "spheres run") ||
        hsbd_get_f64(rd, &m->virial_last) || hsbd_blocks_load(m->virial, rd) ||
        hsbd_msd_load(m->msd, rd))
        return -1;
    for (size_t k = 0; k < r->cfg->species.n && m->msd_species[k]; ++k)
        if (hsbd_msd_load(m->msd_species[k], rd)) return -1;
    if (m->gr && hsbd_gr_load(m->gr, rd)) return -1;
    return walls_observers_load(&m->walls, rd);
}

static void spheres_release(run *r) {
    spheres_model *m = model_of(r);
    if (!m) return;
    hsbd_spheres_free(m->sys);
    hsbd_table_free(m->field_table);
    free(m->coupling);
    hsbd_gr_free(m->gr);
    walls_observers_free(&m->walls);
    hsbd_msd_free(m->msd);
    for (size_t k = 0; k < HSBD_MAX_SPECIES; ++k)
        hsbd_msd_free(m->msd_species[k]);
    hsbd_blocks_free(m->virial);
    free(m->unwrapped);
    free(m->species);
    free(m);
    r->m = NULL;
}

static void spheres_expose(const run *r, hsbd_sim_parts *p) {
    const spheres_model *m = model_of(r);
    p->spheres = m->sys;
    p->msd = m->msd;
    for (size_t q = 0; q < r->cfg->species.n; ++q)
        p->msd_species[q] = m->msd_species[q];
    p->gr = m->gr;
}

static int register_ops(run *r, spheres_model *m, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    int rc = run_add_op(r, "sample", (uint64_t)cfg->sample.every, sample_virial_msd, m, err);
    if (rc == HSBD_OK && m->gr)
        rc = run_add_op(r, "g(r)", (uint64_t)cfg->sample.gr_every, sample_gr, m, err);
    if (rc == HSBD_OK) rc = run_add_trajectory(r, write_frame, m, &m->trajectory, err);
    return rc;
}

int run_spheres_build(run *r, hsbd_error *err) {
    spheres_model *m = calloc(1, sizeof *m);
    if (!m) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    r->m = m;
    r->model = (run_model){.name = "spheres",
                           .particles = (double)r->cfg->system.n,
                           .step = spheres_step,
                           .check = spheres_check,
                           .start_production = spheres_start_production,
                           .save = spheres_save,
                           .load = spheres_load,
                           .write_tables = spheres_write_tables,
                           .write_summary = spheres_write_summary,
                           .expose = spheres_expose,
                           .warn_start = spheres_warn_start,
                           .release = spheres_release};
    int rc = build_system(r, m, err);
    if (rc == HSBD_OK) rc = build_observers(r->cfg, m, err);
    if (rc == HSBD_OK) rc = register_ops(r, m, err);
    return rc;
}
