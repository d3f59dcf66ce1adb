/* The spheres model of the run lifecycle: builds the EDBD system of hard disks or spheres
 * (species, polydispersity, walls, fields, the initial state), steps it, makes its frames
 * and saves its state, and checks the scheme's assumptions; its observers are under
 * src/run/observers/ (src/run/models.c). */
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
#include "run/spheres_model.h"
#include "spheres/checkpoint.h"

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
            if (r->start_x)
                hsbd_error_set(err, rc, "the positions given: %s", why);
            else
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

/* Particles of an XYZ input (or the caller's positions: given = 1) must lie between the
 * walls: the file's line of the first that does not (line i + 3 of particle i). */
static int check_positions_walls(const hsbd_config *cfg, int given, const double *x,
                                 const double *sigma, hsbd_error *err) {
    for (size_t i = 0; i < (size_t)cfg->system.n; ++i)
        for (int a = 0; a < (int)cfg->system.dimension; ++a) {
            const double half = 0.5 * sigma[i], top = cfg->system.box[a] - half, tol = 1e-9;
            if (!cfg->system.walls[a] || (x[3 * i + a] >= half * (1 - tol) &&
                                          x[3 * i + a] <= top + tol * cfg->system.box[a]))
                continue;
            if (given)
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "the positions given: particle %zu at %c = %.9g is outside "
                                      "the walls (system.boundary); allowed: sigma/2 = %.9g <= %c "
                                      "<= box - sigma/2 = %.9g",
                                      i, "xyz"[a], x[3 * i + a], half, "xyz"[a], top);
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

/* the same number of particles of each species (0 .. ns - 1) in a as in b */
static int same_composition(const int *a, const int *b, size_t n, size_t ns) {
    int64_t count[HSBD_MAX_SPECIES] = {0};
    for (size_t i = 0; i < n; ++i) {
        if (b[i] < 0 || (size_t)b[i] >= ns) return 0;
        ++count[a[i]], --count[b[i]];
    }
    for (size_t k = 0; k < ns; ++k)
        if (count[k]) return 0;
    return 1;
}

/* Active particles: the orientations of init.positions, when it has them (else they stay
 * random). */
static int read_orientations(const hsbd_config *cfg, spheres_model *m, hsbd_error *err) {
    double *e = malloc(3 * (size_t)cfg->system.n * sizeof *e);
    if (!e) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int found = 0;
    int rc = cfg->init.gsd ? hsbd_gsd_read_orientations(cfg, e, &found, err)
                           : hsbd_xyz_read_orientations(cfg, e, &found, err);
    if (rc == HSBD_OK && found) rc = hsbd_spheres_set_orientations(m->sys, e, err);
    free(e);
    return rc;
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
    if (r->start_x || cfg->init.positions[0]) { /* resuming too: the file gives the sizes
                                                 * and species */
        x = malloc(3 * n * sizeof *x);
        if (!x) return free(sigma), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        if (r->start_x) { /* the caller's, else as configured */
            memcpy(x, r->start_x, 3 * n * sizeof *x);
            if (r->start_species && !same_composition(m->species, r->start_species, n, m->ns))
                return free(x), free(sigma),
                       hsbd_error_set(err, HSBD_EINPUT,
                                      "the positions given: the species' counts differ from "
                                      "the configuration's (species.fraction)");
            if (r->start_species) memcpy(m->species, r->start_species, n * sizeof *m->species);
            if (r->start_sigma) memcpy(sigma, r->start_sigma, n * sizeof *sigma);
            for (size_t i = 0; i < n; ++i)
                if (m->species[i] < 0 || (size_t)m->species[i] >= m->ns || !(sigma[i] > 0)) {
                    hsbd_error_set(err, HSBD_EINPUT,
                                   "the positions given: particle %zu has species %d (allowed "
                                   "0 .. %zu) and diameter %g (allowed > 0)",
                                   i, m->species[i], m->ns - 1, sigma[i]);
                    return free(x), free(sigma), err->status;
                }
        } else if (cfg->init.gsd) { /* species, sizes and D came with hsbd_config_particles */
            if (hsbd_gsd_read_positions(cfg, x, NULL, err) != HSBD_OK)
                return free(x), free(sigma), err->status;
        } else if (hsbd_xyz_read_positions(cfg, x, m->species, sigma, err) != HSBD_OK) {
            return free(x), free(sigma), err->status;
        }
        for (size_t i = 0; i < n && !cfg->init.gsd; ++i) { /* the file's species (sizes) */
            const size_t k = (size_t)m->species[i];
            const double sk = cfg->species.n ? cfg->species.sigma[k] : cfg->system.sigma;
            if (!(cfg->species.polydispersity > 0)) sigma[i] = sk;
            diffusion[i] = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
            if (cfg->species.d_law == HSBD_D_STOKES_EINSTEIN) diffusion[i] *= sk / sigma[i];
        }
        if (check_positions_walls(cfg, r->start_x != NULL, x, sigma, err) != HSBD_OK)
            return free(x), free(sigma), err->status;
    }
    if (build_field_couplings(cfg, m, sigma, err) != HSBD_OK)
        return free(x), free(sigma), err->status;
    double *v0 = NULL, *rotational = NULL; /* [active]: per particle */
    if (cfg->active.on) {
        if (!(v0 = malloc(2 * n * sizeof *v0)))
            return free(x), free(sigma), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        rotational = v0 + n;
        hsbd_config_active(cfg, m->species, sigma, diffusion, v0, rotational);
    }
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
                             .field_step = cfg->run.field_step,
                             .pair_rule = cfg->run.pair_rule,
                             .threads = run_threads(cfg),
                             .particle_v0 = v0,
                             .particle_rotational_diffusion = rotational};
    for (int a = 0; a < 3; ++a)
        p.box[a] = cfg->system.box[a], p.drift[a] = cfg->system.drift[a],
        p.walls[a] = cfg->system.walls[a];
    m->sys = hsbd_spheres_alloc(&p, err);
    free(sigma);
    free(v0);
    if (!m->sys) {
        free(x);
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message); /* name the keys behind the message */
        return hsbd_error_set(
            err, err->status, "%s: %s (system.shell: %s)",
            hsbd_config_origin(cfg, "system", cfg->system.box_text[0] ? "box" : "packing_fraction"),
            why, hsbd_config_origin(cfg, "system", "shell"));
    }
    int rc = r->resuming ? HSBD_OK : place_particles(r, m, x, err);
    free(x);
    if (rc == HSBD_OK && !r->resuming && cfg->active.on && cfg->init.positions[0])
        rc = read_orientations(cfg, m, err);
    return rc;
}

/* The scheme's assumptions (Scala Eqs. 3 and 6, collisions per particle-step) from the
 * particles' own sizes and D; warnings on stderr (collisions: once measured), unless the
 * run keeps them to its summary.json. */
static void warn_scheme(const run *r, double collisions_per_particle_step) {
    if (r->opt->quiet_warnings) return;
    const hsbd_spheres_view v = hsbd_spheres_get_view(spheres_model_of(r)->sys);
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
    warn_scheme(r, NAN);
}

/* ---- D_L and the time step ---- */

/* The step's deficit of the long-time self-diffusion of one-size hard spheres (3D) and
 * disks (2D): 1 - D_L(dt) / D_L(0) = c(phi) x, x = D dt / sigma^2, c(phi) = a phi^p fitted
 * to D_L at phi 0.1-0.5, dt 3e-4 to 1e-2 (spheres: a = 35.3 +- 5.9, p = 1.60 +- 0.18, c
 * within 4-25 %) and at phi 0.4 and 0.6 (disks: a = 94, p = 5.75, c(0.6) = 5.0 +- 0.9,
 * c(0.4) = 0.5 +- 0.8); scripts/validation/dl_step_scan.py, docs/spheres.md "D_L and the
 * time step". Z and g(r) have no such error. */
static double dl_step_slope(int dim, double phi) {
    return dim == 3 ? 35.3 * pow(phi, 1.60) : 94.0 * pow(phi, 5.75);
}

/* A run whose step leaves D_L more than 1 % low is warned, with the dt that keeps it
 * within 1 %. The reduced step is the mobile particles' mean D times dt over the square of
 * the mean diameter (mixtures and size spreads: an estimate from the one-size fits); ideal
 * particles (hard core off) have no such error. */
static void warn_dl_step(run *r) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(spheres_model_of(r)->sys);
    if (!v.hard_core) return;
    double sum_d = 0, sum_sigma = 0;
    size_t mobile = 0;
    for (size_t i = 0; i < v.n; ++i) {
        sum_sigma += v.sigma[i];
        if (v.diffusion[i] > 0) sum_d += v.diffusion[i], ++mobile;
    }
    if (!mobile) return;
    const double sigma = sum_sigma / (double)v.n;
    const double rate = sum_d / (double)mobile / (sigma * sigma), x = rate * v.dt;
    const double phi = hsbd_spheres_packing_fraction(v.dimension, v.box, v.n, v.sigma);
    const double deficit = dl_step_slope(v.dimension, phi) * x, level = 0.01;
    if (!(deficit > level)) return;
    run_warn(r,
             "run.dt = %g: D_L (D_long, the MSD's long-time slope) is about %.1f %% low at phi "
             "%.3g from the step alone (Z and g(r) are exact at any dt; docs/spheres.md); "
             "run.dt <= %.2g keeps it within 1 %%",
             v.dt, 100 * deficit, phi, v.dt * level / deficit);
}

/* ---- the model's part of the lifecycle ---- */

static int spheres_step(run *r, hsbd_error *err) {
    const spheres_model *m = spheres_model_of(r);
    const int rc = hsbd_spheres_step(m->sys);
    return rc == HSBD_OK ? HSBD_OK
                         : hsbd_error_set(err, rc, "spheres: out of memory in step %llu",
                                          (unsigned long long)hsbd_spheres_get_view(m->sys).step);
}

static int spheres_check(run *r, int strict, hsbd_error *err) {
    const spheres_model *m = spheres_model_of(r);
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
    spheres_model *m = spheres_model_of(r);
    if (r->equil_done > 0)
        warn_scheme(r, (double)hsbd_spheres_get_stats(m->sys).collisions /
                           ((double)r->cfg->system.n * (double)r->equil_done));
    hsbd_spheres_reset_stats(m->sys);
}

/* The particles as they are, their unwrapped coordinates x + image box (d per particle). */
static void spheres_frame(const run *r, hsbd_frame *f) {
    const spheres_model *m = spheres_model_of(r);
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    const size_t d = (size_t)v.dimension;
    for (size_t i = 0; i < v.n; ++i)
        for (size_t a = 0; a < d; ++a)
            m->frame_unwrapped[d * i + a] = v.x[3 * i + a] + (double)v.image[3 * i + a] * v.box[a];
    const hsbd_config *cfg = r->cfg;
    *f = (hsbd_frame){.step = v.step,
                      .time = v.time,
                      .dimension = v.dimension,
                      .n = v.n,
                      .box = {v.box[0], v.box[1], v.box[2]},
                      .periodic = {!v.walls[0], !v.walls[1], v.dimension == 3 && !v.walls[2]},
                      .x = v.x,
                      .image = v.image,
                      .unwrapped = m->frame_unwrapped,
                      .diameter = v.sigma,
                      .species = v.species,
                      .nspecies = cfg->species.n,
                      .names = cfg->species.n ? cfg->species.name : NULL,
                      .one_name = HSBD_XYZ_ONE_SPECIES,
                      .orientation = v.orientation};
}

/* ---- results ---- */

/* "sizes": the diameters as simulated (drawn, or read with the positions) */
static void write_sizes_json(const run *r, FILE *f) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(spheres_model_of(r)->sys);
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
    const spheres_model *m = spheres_model_of(r);
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
    write_sizes_json(r, f);
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
    run_write_warnings(r, f, (const char(*)[HSBD_WARNING_LEN])warnings,
                       hsbd_scheme_check_warnings(&check, warnings, 3));
    hsbd_json_number(f, "shell_updates_per_particle_step",
                     steps > 0 ? (double)st.shell_updates / (n * steps) : NAN, 1);
    /* pairs whose end gap the exact pair rule changed (run.pair_rule) */
    hsbd_json_number(f, "pair_corrections_per_particle_step",
                     steps > 0 ? (double)st.pair_corrections / (n * steps) : NAN, 1);
    int finite;
    hsbd_json_number(f, "min_gap", hsbd_spheres_min_gap(m->sys, &finite), 1);
}

/* ---- checkpoints ---- */

static void spheres_save(const run *r, hsbd_writer *w) {
    hsbd_spheres_save(spheres_model_of(r)->sys, w);
    hsbd_put_tag(w, "spheres run");
}

static int spheres_load(run *r, hsbd_reader *rd) {
    return hsbd_spheres_load(spheres_model_of(r)->sys, rd) || hsbd_get_tag(rd, "spheres run") ? -1
                                                                                              : 0;
}

static void spheres_release(run *r) {
    spheres_model *m = spheres_model_of(r);
    if (!m) return;
    hsbd_spheres_free(m->sys);
    hsbd_table_free(m->field_table);
    free(m->coupling);
    free(m->frame_unwrapped);
    free(m->species);
    free(m);
    r->m = NULL;
}

static void spheres_expose(const run *r, hsbd_sim_parts *p) {
    p->spheres = spheres_model_of(r)->sys;
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
                           .write_summary = spheres_write_summary,
                           .expose = spheres_expose,
                           .frame = spheres_frame,
                           .warn_start = spheres_warn_start,
                           .release = spheres_release};
    int rc = build_system(r, m, err);
    if (rc == HSBD_OK) warn_dl_step(r);
    const size_t dn = (size_t)(r->cfg->system.dimension * r->cfg->system.n);
    if (rc == HSBD_OK && !(m->frame_unwrapped = malloc(dn * sizeof *m->frame_unwrapped)))
        rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    return rc;
}
