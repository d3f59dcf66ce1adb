/* Checks across keys and derived defaults, once all input is read: the species lists and
 * the run's step counts for every model, then each model's own rules. */
#include "config/schema.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/field.h"
#include "hsbd/spheres.h"

#define INF HUGE_VAL

/* a / b is a whole number (relative tolerance 1e-9) */
static int divides(double b, double a) {
    const double q = a / b;
    return q >= 1.0 - 1e-9 && fabs(q - round(q)) <= 1e-9 * q;
}

uint64_t hsbd_config_steps(const hsbd_config *cfg) {
    return (uint64_t)llround(cfg->run.t_total / cfg->run.dt);
}

double hsbd_config_dt_equil(const hsbd_config *cfg) {
    return cfg->run.dt_equil > 0 ? cfg->run.dt_equil : cfg->run.dt;
}

uint64_t hsbd_config_equil_steps(const hsbd_config *cfg) {
    return (uint64_t)llround(cfg->run.t_equil / hsbd_config_dt_equil(cfg));
}

/* Split a list on spaces and commas into at most `max` words; returns the count, or
 * max + 1 when there are more. */
static size_t split_list(char *text, char **words, size_t max) {
    size_t count = 0;
    for (char *w = strtok(text, " \t,"); w; w = strtok(NULL, " \t,")) {
        if (count == max) return max + 1;
        words[count++] = w;
    }
    return count;
}

/* One numeric species list (count, sigma or D): as many finite entries as names, each in
 * [min, inf) (open at min when `open`), whole numbers when `whole`. */
static int parse_species_numbers(hsbd_config *cfg, const char *key, const char *text, double min,
                                 int open, int whole, double *out, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t ns = cfg->species.n, got = split_list(buf, words, HSBD_MAX_SPECIES);
    if (got != ns)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.%s has %zu entries for %zu species.names; allowed: one "
                              "per species",
                              config_origin_of(cfg, "species", key), key, got, ns);
    for (size_t k = 0; k < ns; ++k) {
        double v;
        const char *why;
        if (config_parse_number(words[k], &v, &why) != 0 || (open ? !(v > min) : !(v >= min)) ||
            (whole && v != floor(v)))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.%s entry %zu ('%.40s', species %s) is out of range; "
                                  "allowed: decimal %s %s %g",
                                  config_origin_of(cfg, "species", key), key, k + 1, words[k],
                                  cfg->species.name[k], whole ? "whole numbers" : key,
                                  open ? ">" : ">=", min);
        out[k] = v;
    }
    return HSBD_OK;
}

/* Spheres: species.fraction (each > 0, summing to 1) into counts summing to system.N
 * (largest remainders). Setting both fraction and count is an error. */
static int species_counts_from_fractions(hsbd_config *cfg, double *count, hsbd_error *err) {
    if (cfg->species.count_text[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.count and species.fraction (%s) are both set; allowed: "
                              "one of them",
                              config_origin_of(cfg, "species", "count"),
                              config_origin_of(cfg, "species", "fraction"));
    double frac[HSBD_MAX_SPECIES], total = 0;
    const int rc =
        parse_species_numbers(cfg, "fraction", cfg->species.fraction_text, 0, 1, 0, frac, err);
    if (rc != HSBD_OK) return rc;
    const size_t ns = cfg->species.n;
    for (size_t k = 0; k < ns; ++k)
        total += frac[k];
    if (fabs(total - 1.0) > 1e-6)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.fraction sums to %.9g; allowed: fractions summing to 1",
                              config_origin_of(cfg, "species", "fraction"), total);
    const double n = (double)cfg->system.n;
    double assigned = 0;
    for (size_t k = 0; k < ns; ++k)
        count[k] = floor(frac[k] * n), assigned += count[k];
    while (assigned < n) { /* largest remainder first */
        size_t best = 0;
        double rem = -1;
        for (size_t k = 0; k < ns; ++k)
            if (frac[k] * n - count[k] > rem) rem = frac[k] * n - count[k], best = k;
        count[best] += 1, assigned += 1;
    }
    for (size_t k = 0; k < ns; ++k)
        if (count[k] < 1)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.fraction %g of species %s gives no particle of "
                                  "system.N = %lld; allowed: fraction >= 1/N",
                                  config_origin_of(cfg, "species", "fraction"), frac[k],
                                  cfg->species.name[k], (long long)cfg->system.n);
    return HSBD_OK;
}

/* The [species] lists: names, counts summing to system.N, lengths and D. */
static int parse_species(hsbd_config *cfg, hsbd_error *err) {
    cfg->species.n = 0;
    if (!cfg->species.names_text[0]) {
        static const char *const lists[] = {"count", "sigma", "D", "fraction"};
        for (int k = 0; k < 4; ++k)
            if (!config_is_default(cfg, "species", lists[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "%s: species.%s is set but species.names is empty; name the "
                                      "species first",
                                      config_origin_of(cfg, "species", lists[k]), lists[k]);
        return HSBD_OK;
    }
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", cfg->species.names_text);
    const size_t ns = split_list(buf, words, HSBD_MAX_SPECIES);
    if (ns < 1 || ns > HSBD_MAX_SPECIES)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: species.names: allowed: 1 to %d names",
                              config_origin_of(cfg, "species", "names"), HSBD_MAX_SPECIES);
    for (size_t k = 0; k < ns; ++k) {
        const size_t len = strlen(words[k]);
        int ok = len < HSBD_SPECIES_NAME;
        for (size_t c = 0; c < len; ++c)
            ok &= (words[k][c] >= 'a' && words[k][c] <= 'z') ||
                  (words[k][c] >= 'A' && words[k][c] <= 'Z') ||
                  (words[k][c] >= '0' && words[k][c] <= '9') || words[k][c] == '_';
        for (size_t q = 0; q < k; ++q)
            ok &= strcmp(words[q], words[k]) != 0;
        if (!ok)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.names entry '%s' is not allowed: names are unique, "
                                  "at most %d letters, digits or '_'",
                                  config_origin_of(cfg, "species", "names"), words[k],
                                  HSBD_SPECIES_NAME - 1);
        snprintf(cfg->species.name[k], HSBD_SPECIES_NAME, "%s", words[k]);
    }
    cfg->species.n = ns;
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    double count[HSBD_MAX_SPECIES];
    int rc = HSBD_OK;
    if (spheres && cfg->species.fraction_text[0])
        rc = species_counts_from_fractions(cfg, count, err);
    else
        rc = parse_species_numbers(cfg, "count", cfg->species.count_text, 1, 0, 1, count, err);
    if (rc == HSBD_OK)
        rc = parse_species_numbers(cfg, "sigma", cfg->species.sigma_text, 0, spheres, 0,
                                   cfg->species.sigma, err);
    const int stokes = spheres && cfg->species.d_law == HSBD_D_STOKES_EINSTEIN;
    if (rc == HSBD_OK && stokes && cfg->species.d_text[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.D is set, but species.D_law = stokes-einstein (%s) "
                              "derives D from system.D and system.sigma; remove one of them",
                              config_origin_of(cfg, "species", "D"),
                              config_origin_of(cfg, "species", "D_law"));
    if (rc == HSBD_OK && stokes)
        for (size_t k = 0; k < ns; ++k) /* D_k = D_0 sigma_0 / sigma_k (Stokes-Einstein) */
            cfg->species.diffusion[k] =
                cfg->system.diffusion * cfg->system.sigma / cfg->species.sigma[k];
    else if (rc == HSBD_OK)
        rc = parse_species_numbers(cfg, "D", cfg->species.d_text, 0, !spheres, 0,
                                   cfg->species.diffusion, err);
    if (rc != HSBD_OK) return rc;
    double total = 0;
    for (size_t k = 0; k < ns; ++k)
        cfg->species.count[k] = (int64_t)count[k], total += count[k];
    if (total != (double)cfg->system.n)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.count sums to %.0f rods but system.N = %lld (%s); "
                              "allowed: counts summing to system.N",
                              config_origin_of(cfg, "species", "count"), total,
                              (long long)cfg->system.n, config_origin_of(cfg, "system", "N"));
    static const char *const single[] = {"sigma", "D"};
    for (int k = 0; k < 2 && !stokes; ++k) /* Stokes-Einstein: the reference D_0, sigma_0 */
        if (!config_is_default(cfg, "system", single[k]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: system.%s is set, but with species.names the species.%s "
                                  "list gives it; remove one of them",
                                  config_origin_of(cfg, "system", single[k]), single[k], single[k]);
    if (!spheres && (cfg->pair.type != HSBD_PAIR_NONE || cfg->contact.gamma > 0))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair forces and sticky contacts need one species (mixtures with "
                              "pair forces are not supported yet)",
                              config_origin_of(cfg, cfg->contact.gamma > 0 ? "contact" : "pair",
                                               cfg->contact.gamma > 0 ? "gamma" : "type"));
    cfg->system.sigma = cfg->species.sigma[0];
    cfg->system.diffusion = cfg->species.diffusion[0];
    return HSBD_OK;
}

/* total length of the rods */
static double rods_length(const hsbd_config *cfg) {
    if (!cfg->species.n) return (double)cfg->system.n * cfg->system.sigma;
    double total = 0;
    for (size_t k = 0; k < cfg->species.n; ++k)
        total += (double)cfg->species.count[k] * cfg->species.sigma[k];
    return total;
}

/* A list of `dim` finite numbers (or, when one_for_all, 1 repeated) in (min, inf) or any
 * (min = -inf). */
static int parse_vector(const hsbd_config *cfg, const char *key, const char *text, int dim,
                        int one_for_all, double min, double *out, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[4];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t got = split_list(buf, words, 3);
    if ((got != 1 || !one_for_all) && got != (size_t)dim)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: system.%s has %zu value%s; allowed: %s%d (system.dimension)",
                              config_origin_of(cfg, "system", key), key, got, got == 1 ? "" : "s",
                              one_for_all ? "1 or " : "", dim);
    for (int a = 0; a < dim; ++a) {
        const char *w = words[got == 1 ? 0 : a], *why;
        double v;
        if (config_parse_number(w, &v, &why) != 0 || !(v > min))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: system.%s value '%.40s' is out of range; allowed: finite "
                                  "decimal numbers%s",
                                  config_origin_of(cfg, "system", key), key, w,
                                  isinf(min) ? "" : " > 0");
        out[a] = v;
    }
    for (int a = dim; a < 3; ++a)
        out[a] = 0;
    return HSBD_OK;
}

/* A key that the model does not read, set by the user, is an error, not a silent no-op. */
static int refuse_keys_of_other_model(const hsbd_config *cfg, hsbd_error *err) {
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    for (size_t i = 0; i < config_nkeys; ++i) {
        const key_spec *k = &config_schema[i];
        if (!config_key_read(cfg, k) && !config_is_default(cfg, k->section, k->key))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s applies to system.model = %s only, but the model "
                                  "is %s (%s); remove the key",
                                  config_origin_of(cfg, k->section, k->key), k->section, k->key,
                                  spheres ? "rods" : "spheres", spheres ? "spheres" : "rods",
                                  config_origin_of(cfg, "system", "model"));
    }
    return HSBD_OK;
}

/* ---- every model: run, sampling and output keys -------------------------------------- */

/* Of a time (run.t_total or run.t_equil) and its step, which one a message about their
 * ratio blames: the one the user set, or of two set ones the one further from its default
 * in the direction that made the ratio bad (too_many: the time long, the step short). */
static const char *blame_time_or_step(const hsbd_config *cfg, const char *time_key,
                                      const char *step_key, int too_many) {
    const int time_set = !config_is_default(cfg, "run", time_key);
    const int step_set = !config_is_default(cfg, "run", step_key);
    if (time_set != step_set) return time_set ? time_key : step_key;
    const double t = *(const double *)config_cslot(cfg, config_find_key("run", time_key));
    const double dt = *(const double *)config_cslot(cfg, config_find_key("run", step_key));
    const double t0 = strtod(config_find_key("run", time_key)->def, NULL);
    const double dt0 = strtod(config_find_key("run", "dt")->def, NULL);
    const double time_off = too_many ? t / t0 : t0 / t, step_off = too_many ? dt0 / dt : dt / dt0;
    return time_off >= step_off ? time_key : step_key;
}

/* Between 1 and 9e15 steps in each phase (exact in double precision). */
static int check_step_counts(const hsbd_config *cfg, hsbd_error *err) {
    static const char *const times[2] = {"t_total", "t_equil"};
    const double t[2] = {cfg->run.t_total, cfg->run.t_equil};
    const double dt[2] = {cfg->run.dt, hsbd_config_dt_equil(cfg)};
    const char *const dts[2] = {"dt", cfg->run.dt_equil > 0 ? "dt_equil" : "dt"};
    for (int p = 0; p < 2; ++p) {
        if (!(t[p] / dt[p] > 9.0e15)) continue;
        const char *blamed = blame_time_or_step(cfg, times[p], dts[p], 1);
        const int time = blamed == times[p];
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.%s = %g over run.%s = %g gives %.3g steps; allowed: at most "
                              "9e15 steps (run.%s %s %g)",
                              config_origin_of(cfg, "run", blamed), times[p], t[p], dts[p], dt[p],
                              t[p] / dt[p], blamed,
                              time ? "<=" : ">=", time ? 9.0e15 * dt[p] : t[p] / 9.0e15);
    }
    if (cfg->run.t_total < cfg->run.dt * (1 - 1e-9)) {
        const char *blamed = blame_time_or_step(cfg, "t_total", "dt", 0);
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.t_total = %g is shorter than run.dt = %g; allowed: "
                              "t_total >= dt",
                              config_origin_of(cfg, "run", blamed), cfg->run.t_total, cfg->run.dt);
    }
    const uint64_t steps = hsbd_config_steps(cfg);
    const uint64_t samples = steps / (uint64_t)cfg->sample.every;
    const uint64_t blocks = (uint64_t)cfg->sample.blocks, most_every = steps / blocks;
    if (samples >= blocks) return HSBD_OK;
    if (!config_is_default(cfg, "sample", "every") && most_every >= 1)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.every = %lld leaves %llu samples in the %llu steps of "
                              "run.t_total/run.dt, fewer than sample.blocks = %llu; allowed: 1 "
                              "<= every <= %llu",
                              config_origin_of(cfg, "sample", "every"),
                              (long long)cfg->sample.every, (unsigned long long)samples,
                              (unsigned long long)steps, (unsigned long long)blocks,
                              (unsigned long long)most_every);
    if (!config_is_default(cfg, "sample", "blocks") && samples >= 2)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.blocks = %llu needs at least as many samples, but "
                              "t_total/(dt*every) = %llu; allowed: 2 <= blocks <= %llu",
                              config_origin_of(cfg, "sample", "blocks"), (unsigned long long)blocks,
                              (unsigned long long)samples, (unsigned long long)samples);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: run.t_total = %g gives %llu steps and %llu samples (sample.every = "
                          "%lld), fewer than sample.blocks = %llu; allowed: t_total >= %g",
                          config_origin_of(cfg, "run", "t_total"), cfg->run.t_total,
                          (unsigned long long)steps, (unsigned long long)samples,
                          (long long)cfg->sample.every, (unsigned long long)blocks,
                          (double)blocks * (double)cfg->sample.every * cfg->run.dt);
}

/* Ensembles (docs/scaling.md): a replica's index lies below their number when that is
 * given, and an ensemble's replicas are not also the error blocks of one run. */
static int check_ensemble_keys(const hsbd_config *cfg, hsbd_error *err) {
    if (cfg->run.replicas > 0 && cfg->run.replica >= cfg->run.replicas)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.replica = %lld is not a replica of run.replicas = %lld; "
                              "allowed: 0 <= replica < replicas",
                              config_origin_of(cfg, "run", "replica"), (long long)cfg->run.replica,
                              (long long)cfg->run.replicas);
    if ((cfg->run.replicas > 1 || cfg->run.replica >= 0) &&
        cfg->sample.blocking == HSBD_BLOCKS_REPLICAS)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.blocking = replicas with an ensemble (run.replicas or "
                              "run.replica): the ensemble's replicas already give the errors; "
                              "allowed: blocking = time or space",
                              config_origin_of(cfg, "sample", "blocking"));
    return HSBD_OK;
}

/* Checks of the run, sampling and output keys shared by every model. */
static int check_run_keys(hsbd_config *cfg, hsbd_error *err) {
    if (check_step_counts(cfg, err) != HSBD_OK) return err->status;
    if (check_ensemble_keys(cfg, err) != HSBD_OK) return err->status;
    const int replicas = cfg->sample.blocking == HSBD_BLOCKS_REPLICAS;
    const double lag_limit = replicas ? cfg->run.t_total / (double)cfg->sample.blocks
                                      : cfg->run.t_total; /* a replica's production time */
    if (cfg->sample.msd_max_lag == 0)
        cfg->sample.msd_max_lag = fmin(cfg->run.t_total / 10, lag_limit);
    if (cfg->sample.msd_max_lag > lag_limit * (1 + 1e-12))
        return hsbd_error_set(
            err, HSBD_EINPUT, "%s: sample.msd_max_lag = %g exceeds %s = %g",
            config_origin_of(cfg, "sample", "msd_max_lag"), cfg->sample.msd_max_lag,
            replicas ? "a replica's time run.t_total/sample.blocks" : "run.t_total", lag_limit);
    if (cfg->output.trajectory_every == 0) /* the default never refuses a short run */
        cfg->output.trajectory_every = fmax(cfg->run.t_total / 100, cfg->run.dt);
    if (cfg->output.trajectory_every < cfg->run.dt)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: output.trajectory_every = %g is shorter than run.dt = %g",
                              config_origin_of(cfg, "output", "trajectory_every"),
                              cfg->output.trajectory_every, cfg->run.dt);
    if (cfg->sample.current_every > 0 && cfg->sample.current_every < cfg->run.dt)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.current_every = %g is shorter than run.dt = %g",
                              config_origin_of(cfg, "sample", "current_every"),
                              cfg->sample.current_every, cfg->run.dt);
    return HSBD_OK;
}

/* system.boundary: one word (rods: dim 1) or one per axis, each periodic or walls, into
 * walls[a]. */
static int parse_boundary(hsbd_config *cfg, int dim, int *walls, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[4];
    snprintf(buf, sizeof buf, "%s", cfg->system.boundary_text);
    const size_t got = split_list(buf, words, 3);
    if (got != 1 && got != (size_t)dim)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: system.boundary has %zu values; allowed: %s",
                              config_origin_of(cfg, "system", "boundary"), got,
                              dim == 1 ? "one (rods)" : "1 or one per axis (system.dimension)");
    for (int a = 0; a < dim; ++a) {
        const char *w = words[got == 1 ? 0 : a];
        if (strcmp(w, "periodic") && strcmp(w, "walls"))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: system.boundary = '%.40s' is not known; allowed: periodic "
                                  "or walls",
                                  config_origin_of(cfg, "system", "boundary"), w);
        walls[a] = !strcmp(w, "walls");
    }
    return HSBD_OK;
}

/* ---- rods ---------------------------------------------------------------------------- */

/* ---- drives --------------------------------------------------------------------------- */

/* A drive must change a parameter of a term in field.type, with a wave of a period of at
 * least one step (and one amplitude) or a velocity; sample.phases needs the wave. */
static int check_drive(const hsbd_config *cfg, hsbd_error *err) {
    static const char *const keys[] = {"wave", "amplitude", "period", "phase", "velocity"};
    static const int term_of[] = {0,
                                  HSBD_FIELD_TILT,
                                  HSBD_FIELD_COSINE,
                                  HSBD_FIELD_COSINE,
                                  HSBD_FIELD_HARMONIC,
                                  HSBD_FIELD_HARMONIC};
    static const char *const term_name[] = {"", "tilt", "cosine", "cosine", "harmonic", "harmonic"};
    const int p = cfg->drive.parameter, wave = cfg->drive.wave != HSBD_WAVE_NONE;
    if (p == HSBD_DRIVE_NONE) {
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
            if (!config_is_default(cfg, "drive", keys[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "%s: drive.%s is set, but drive.parameter = none drives "
                                      "nothing; allowed: drive.parameter = "
                                      "force|amplitude|shift|stiffness|center",
                                      config_origin_of(cfg, "drive", keys[k]), keys[k]);
    } else if (!(cfg->field.type & term_of[p])) {
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: drive.parameter drives the %s term, which field.type does not "
                              "have; allowed: a parameter of a term in field.type",
                              config_origin_of(cfg, "drive", "parameter"), term_name[p]);
    } else if (wave) {
        const double dt = fmax(cfg->run.dt, hsbd_config_dt_equil(cfg));
        if (!(cfg->drive.period >= dt))
            return hsbd_error_set(
                err, HSBD_EINPUT,
                "%s: drive.period = %g with drive.wave set; allowed: drive.period "
                ">= the time step %g (run.dt, run.dt_equil)",
                config_origin_of(cfg, "drive", "period"), cfg->drive.period, dt);
        if (cfg->drive.amplitude == 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: drive.amplitude = 0 with drive.wave set changes nothing; "
                                  "allowed: drive.amplitude != 0",
                                  config_origin_of(cfg, "drive", "amplitude"));
    } else {
        for (size_t k = 1; k < 4; ++k)
            if (!config_is_default(cfg, "drive", keys[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "%s: drive.%s is set, but drive.wave = none; allowed: "
                                      "drive.wave = cosine|square, or leave drive.%s out",
                                      config_origin_of(cfg, "drive", keys[k]), keys[k], keys[k]);
        if (cfg->drive.velocity == 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: drive.parameter is set, but neither drive.wave nor "
                                  "drive.velocity changes it; allowed: drive.wave = cosine|square "
                                  "or drive.velocity != 0",
                                  config_origin_of(cfg, "drive", "parameter"));
    }
    if (cfg->sample.phases > 0 && !(p != HSBD_DRIVE_NONE && wave))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.phases = %lld needs a periodic drive; allowed: "
                              "sample.phases = 0, or drive.wave = cosine|square",
                              config_origin_of(cfg, "sample", "phases"),
                              (long long)cfg->sample.phases);
    return HSBD_OK;
}

static int finalise_rods(hsbd_config *cfg, hsbd_error *err) {
    int walls_rods = 0;
    if (parse_boundary(cfg, 1, &walls_rods, err) != HSBD_OK) return err->status;
    cfg->system.boundary = walls_rods ? HSBD_BOUNDARY_WALLS : HSBD_BOUNDARY_PERIODIC;
    if (parse_species(cfg, err) != HSBD_OK) return err->status;
    const double L = cfg->system.length, sigma = cfg->system.sigma;
    const double occupied = rods_length(cfg);
    if (!(occupied < L)) {
        char allowed[96];
        if (cfg->species.n)
            snprintf(allowed, sizeof allowed, "sum of species.count x species.sigma < L");
        else
            snprintf(allowed, sizeof allowed, "N < %g", sigma > 0 ? L / sigma : INF);
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: system.N = %lld rods of total length %g do not fit in system.L "
                              "= %g (no room); allowed: %s",
                              config_origin_of(cfg, "system", "N"), (long long)cfg->system.n,
                              occupied, L, allowed);
    }
    if (cfg->sample.contact_width == 0) {
        double d = cfg->system.diffusion;
        for (size_t k = 0; k < cfg->species.n; ++k)
            d = fmax(d, cfg->species.diffusion[k]);
        cfg->sample.contact_width = fmax(1e-2, 3 * sqrt(4 * d * cfg->run.dt));
        config_origin_derived(cfg, "sample", "contact_width", "default (derived from run.dt)");
    }
    if (cfg->pair.type != HSBD_PAIR_NONE && !cfg->system.hard_core)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type needs system.hard_core = on (pair forces act between "
                              "neighbours in ring order)",
                              config_origin_of(cfg, "pair", "type"));
    if (cfg->contact.gamma > 0 && !cfg->system.hard_core)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: contact.gamma > 0 needs system.hard_core = on",
                              config_origin_of(cfg, "contact", "gamma"));
    if ((cfg->pair.type == HSBD_PAIR_YUKAWA || cfg->pair.type == HSBD_PAIR_LJ) && !(sigma > 0))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type = %s needs system.sigma > 0 (the potential is written "
                              "in units of sigma: point rods, which may coincide, give 0/0); "
                              "allowed: sigma > 0, or pair.type = table",
                              config_origin_of(cfg, "pair", "type"),
                              cfg->pair.type == HSBD_PAIR_LJ ? "lj" : "yukawa");
    if (cfg->pair.type == HSBD_PAIR_YUKAWA || cfg->pair.type == HSBD_PAIR_LJ) {
        if (cfg->pair.cutoff == 0) {
            cfg->pair.cutoff =
                cfg->pair.type == HSBD_PAIR_YUKAWA ? sigma + 5.0 / cfg->pair.kappa : 2.5 * sigma;
            config_origin_derived(cfg, "pair", "cutoff", "default (derived from pair.type)");
        }
        if (!(cfg->pair.cutoff > sigma) || !(cfg->pair.cutoff <= 0.5 * L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: pair.cutoff = %g out of range; allowed: system.sigma = %g "
                                  "< cutoff <= L/2 = %g",
                                  config_origin_of(cfg, "pair", "cutoff"), cfg->pair.cutoff, sigma,
                                  0.5 * L);
    }
    if (cfg->pair.type == HSBD_PAIR_TABLE && !cfg->pair.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type = table needs pair.table = <file with 'r f(r)' lines>",
                              config_origin_of(cfg, "pair", "type"));
    if (cfg->contact.gamma > 0 && !(sigma + cfg->contact.epsilon <= 0.5 * L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: contact.epsilon = %g out of range; allowed: sigma + epsilon <= "
                              "L/2 = %g",
                              config_origin_of(cfg, "contact", "epsilon"), cfg->contact.epsilon,
                              0.5 * L);
    const int walls = cfg->system.boundary == HSBD_BOUNDARY_WALLS;
    const int has_cosine = (cfg->field.type & HSBD_FIELD_COSINE) != 0;
    if (has_cosine && !walls && !divides(cfg->field.wavelength, L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.wavelength = %g must divide system.L = %g (the ring is "
                              "periodic)",
                              config_origin_of(cfg, "field", "wavelength"), cfg->field.wavelength,
                              L);
    if ((cfg->field.type & HSBD_FIELD_TABLE) && !cfg->field.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.type with table needs field.table = <file with 'x value' "
                              "lines covering [0, L]>",
                              config_origin_of(cfg, "field", "type"));
    if (isnan(cfg->field.center)) {
        cfg->field.center = 0.5 * L;
        config_origin_derived(cfg, "field", "center", "default (L/2)");
    }
    if (isnan(cfg->sample.period)) {
        cfg->sample.period = has_cosine && !walls ? cfg->field.wavelength : L;
        if (!divides(cfg->sample.period, L)) cfg->sample.period = L;
        config_origin_derived(cfg, "sample", "period",
                              walls ? "default (L: walls)" : "default (field.wavelength or L)");
    }
    if (walls && cfg->sample.period != L)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.period = %g, but with system.boundary = walls the "
                              "profile covers the whole box; allowed: sample.period = L = %g",
                              config_origin_of(cfg, "sample", "period"), cfg->sample.period, L);
    if (!divides(cfg->sample.period, L))
        return hsbd_error_set(err, HSBD_EINPUT, "%s: sample.period = %g must divide system.L = %g",
                              config_origin_of(cfg, "sample", "period"), cfg->sample.period, L);
    if (!divides(cfg->sample.bin_width, cfg->sample.period))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.bin_width = %g must divide sample.period = %g into a "
                              "whole number of bins",
                              config_origin_of(cfg, "sample", "bin_width"), cfg->sample.bin_width,
                              cfg->sample.period);
    /* the profile keeps four accumulators per bin and error block */
    const double profile_bytes =
        cfg->sample.period / cfg->sample.bin_width * ((double)cfg->sample.blocks + 1) * 4 * 8;
    if (profile_bytes > 4.0 * 1024 * 1024 * 1024)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.bin_width = %g gives %.3g bins over sample.period = %g, "
                              "%.1f GiB of profile accumulators with %lld blocks; allowed: at most "
                              "4 GiB (a wider bin, or fewer blocks)",
                              config_origin_of(cfg, "sample", "bin_width"), cfg->sample.bin_width,
                              cfg->sample.period / cfg->sample.bin_width, cfg->sample.period,
                              profile_bytes / (1024.0 * 1024 * 1024),
                              (long long)cfg->sample.blocks);
    if (cfg->sample.blocking == HSBD_BLOCKS_SPACE &&
        !divides((double)cfg->sample.blocks * cfg->sample.period, L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.blocks = %lld must divide the number of periods "
                              "L/period = %g when sample.blocking = space",
                              config_origin_of(cfg, "sample", "blocks"),
                              (long long)cfg->sample.blocks, L / cfg->sample.period);
    if (check_run_keys(cfg, err) != HSBD_OK) return err->status;
    if (check_drive(cfg, err) != HSBD_OK) return err->status;
    return config_check_memory(cfg, 0, err);
}

/* ---- spheres ------------------------------------------------------------------------- */

/* Spheres between walls and in fields: the walls per axis (each at least sigma_max long),
 * the field's axis, terms and defaults, the couplings per species, and what cannot move
 * (no force, no drift on particles with D = 0). */
static int finalise_spheres_walls_field(hsbd_config *cfg, double sigma_max, hsbd_error *err) {
    const int dim = (int)cfg->system.dimension;
    if (parse_boundary(cfg, dim, cfg->system.walls, err) != HSBD_OK) return err->status;
    for (int a = 0; a < dim; ++a)
        if (cfg->system.walls[a] && !(cfg->system.box[a] >= sigma_max))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: the box length %g along axis %c between walls is shorter "
                                  "than the largest diameter %g; allowed: >= sigma_max",
                                  config_origin_of(cfg, "system", "boundary"), cfg->system.box[a],
                                  "xyz"[a], sigma_max);
    if (config_is_default(cfg, "field", "type")) cfg->field.type = 0; /* spheres: none */
    if (config_is_default(cfg, "field", "axis")) cfg->field.axis = dim - 1;
    const int axis = cfg->field.axis;
    if (axis >= dim)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.axis = %c is beyond system.dimension = %d; allowed: %s",
                              config_origin_of(cfg, "field", "axis"), "xyz"[axis], dim,
                              dim == 2 ? "x or y" : "x, y or z");
    const double length = cfg->system.box[axis];
    const int periodic = !cfg->system.walls[axis];
    if ((cfg->field.type & HSBD_FIELD_COSINE) && periodic &&
        !divides(cfg->field.wavelength, length))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.wavelength = %g must divide the periodic box length %g "
                              "along field.axis = %c",
                              config_origin_of(cfg, "field", "wavelength"), cfg->field.wavelength,
                              length, "xyz"[axis]);
    if ((cfg->field.type & HSBD_FIELD_TABLE) && !cfg->field.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.type with table needs field.table = <file with 'x value' "
                              "lines>",
                              config_origin_of(cfg, "field", "type"));
    if (isnan(cfg->field.center)) {
        cfg->field.center = 0.5 * length;
        config_origin_derived(cfg, "field", "center", "default (half the box along field.axis)");
    }
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    for (size_t k = 0; k < ns; ++k)
        cfg->species.coupling[k] = 1.0;
    if (cfg->species.coupling_text[0]) {
        if (!cfg->species.n)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.coupling is set but species.names is empty; name "
                                  "the species first",
                                  config_origin_of(cfg, "species", "coupling"));
        if (cfg->species.coupling_law == HSBD_COUPLING_VOLUME)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.coupling is set with species.coupling_law = volume "
                                  "(which gives the couplings); allowed: one of them",
                                  config_origin_of(cfg, "species", "coupling"));
        if (parse_species_numbers(cfg, "coupling", cfg->species.coupling_text, -INFINITY, 1, 0,
                                  cfg->species.coupling, err) != HSBD_OK)
            return err->status;
    }
    for (size_t k = 0; k < ns; ++k) {
        const double d = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
        if (d != 0) continue;
        const int law = cfg->species.coupling_law == HSBD_COUPLING_VOLUME;
        if (cfg->field.type && (law || cfg->species.coupling[k] != 0))
            return hsbd_error_set(
                err, HSBD_EINPUT,
                "%s: a field acts on species %s, whose D = 0 cannot move%s; "
                "allowed: species.coupling = 0 for it",
                config_origin_of(cfg, "species", law ? "coupling_law" : "coupling"),
                cfg->species.n ? cfg->species.name[k] : "(one)",
                !law && config_is_default(cfg, "species", "coupling")
                    ? " (species.coupling is not set: 1 for every species)"
                    : "");
        if (cfg->system.drift_text[0])
            return hsbd_error_set(
                err, HSBD_EINPUT,
                "%s: system.drift with species %s, whose D = 0 cannot move (not a "
                "common drift); allowed: no drift",
                config_origin_of(cfg, "system", "drift"),
                cfg->species.n ? cfg->species.name[k] : "(one)");
    }
    if (config_is_default(cfg, "sample", "bin_width")) {
        cfg->sample.bin_width = 0.05 * cfg->system.sigma;
        config_origin_derived(cfg, "sample", "bin_width", "default (spheres: sigma/20)");
    }
    const int folds = (cfg->field.type & HSBD_FIELD_COSINE) && periodic;
    if (isnan(cfg->sample.period)) {
        cfg->sample.period = folds ? cfg->field.wavelength : length;
        config_origin_derived(cfg, "sample", "period",
                              "default (spheres: field.wavelength or the box)");
    }
    if (!divides(cfg->sample.period, length) || (!periodic && cfg->sample.period != length))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.period = %g; allowed: a divisor of the periodic box "
                              "length %g along field.axis (the box length between walls)",
                              config_origin_of(cfg, "sample", "period"), cfg->sample.period,
                              length);
    return HSBD_OK;
}

static int finalise_spheres(hsbd_config *cfg, hsbd_error *err) {
    const int dim = (int)cfg->system.dimension;
    if (config_is_default(cfg, "system", "sigma")) {
        cfg->system.sigma = 1.0;
        config_origin_derived(cfg, "system", "sigma", "default (spheres)");
    }
    if (!(cfg->system.sigma > 0))
        return hsbd_error_set(err, HSBD_EINPUT, "%s: system.sigma = %g; allowed: sigma > 0",
                              config_origin_of(cfg, "system", "sigma"), cfg->system.sigma);
    if (parse_species(cfg, err) != HSBD_OK) return err->status;
    /* the particles' volume, from the diameters drawn with the seed when polydisperse */
    double sigma_max = 0;
    const size_t n = (size_t)cfg->system.n;
    double *sigma = malloc(n * sizeof *sigma);
    if (!sigma) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    if (hsbd_config_particles(cfg, NULL, sigma, NULL, err) != HSBD_OK)
        return free(sigma), err->status;
    const double unit[3] = {1, 1, 1}; /* phi in a unit box: the particles' volume */
    const double vp = hsbd_spheres_packing_fraction(dim, unit, n, sigma);
    for (size_t i = 0; i < n; ++i)
        sigma_max = fmax(sigma_max, sigma[i]);
    free(sigma);
    /* packing_fraction has no default: unset is its origin, not its value */
    const int has_box = cfg->system.box_text[0] != 0,
              has_phi = !config_is_default(cfg, "system", "packing_fraction");
    if (has_box == has_phi)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: spheres need exactly one of system.box and "
                              "system.packing_fraction (%s)",
                              config_origin_of(cfg, "system", has_box ? "box" : "model"),
                              has_box ? "both are set" : "neither is set");
    if (has_box) {
        if (parse_vector(cfg, "box", cfg->system.box_text, dim, 1, 0, cfg->system.box, err))
            return err->status;
    } else {
        const double side = pow(vp / cfg->system.packing_fraction, 1.0 / dim);
        for (int a = 0; a < 3; ++a)
            cfg->system.box[a] = a < dim ? side : 0;
    }
    double volume = 1;
    for (int a = 0; a < dim; ++a)
        volume *= cfg->system.box[a];
    const double phi = vp / volume;
    if (!has_phi) cfg->system.packing_fraction = phi;
    if (phi >= (dim == 3 ? 0.74 : 0.9069))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: packing fraction %g exceeds close packing (%g); allowed: a "
                              "larger box",
                              config_origin_of(cfg, "system", has_box ? "box" : "packing_fraction"),
                              phi, dim == 3 ? 0.7405 : 0.9069);
    if (cfg->system.drift_text[0] &&
        parse_vector(cfg, "drift", cfg->system.drift_text, dim, 0, -INF, cfg->system.drift, err))
        return err->status;
    if (finalise_spheres_walls_field(cfg, sigma_max, err) != HSBD_OK) return err->status;
    /* what each initial state reaches: RSI stalls near 0.38 / 0.547; the compression
     * was measured to reach 0.60 / 0.72 at N = 4000 (docs/spheres.md) */
    const double phi_random = dim == 3 ? 0.30 : 0.45, phi_compress = dim == 3 ? 0.58 : 0.72;
    const double reach = cfg->init.method == HSBD_INIT_RANDOM     ? phi_random
                         : cfg->init.method == HSBD_INIT_COMPRESS ? phi_compress
                                                                  : 1;
    if (phi > reach && !cfg->init.positions[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: init.method = %s reaches packing fractions up to %g, but "
                              "phi = %g; allowed: init.method = %s, or init.positions",
                              config_origin_of(cfg, "init", "method"),
                              cfg->init.method == HSBD_INIT_RANDOM ? "random" : "compress", reach,
                              phi, phi > phi_compress ? "lattice" : "compress or auto");
    if (cfg->init.method == HSBD_INIT_AUTO)
        cfg->init.method = phi <= phi_random     ? HSBD_INIT_RANDOM
                           : phi <= phi_compress ? HSBD_INIT_COMPRESS
                                                 : HSBD_INIT_LATTICE;
    double half = INF; /* pairs are minimum images along the periodic axes only */
    for (int a = 0; a < dim; ++a)
        if (!cfg->system.walls[a]) half = fmin(half, 0.5 * cfg->system.box[a]);
    if (cfg->sample.gr_max == 0) cfg->sample.gr_max = fmin(3.0 * sigma_max, half);
    if (cfg->sample.gr_max > half)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.gr_max = %g; allowed: at most half the shortest "
                              "periodic box length, %g",
                              config_origin_of(cfg, "sample", "gr_max"), cfg->sample.gr_max, half);
    if (cfg->sample.gr_bin > cfg->sample.gr_max)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: sample.gr_bin = %g exceeds sample.gr_max = %g",
                              config_origin_of(cfg, "sample", "gr_bin"), cfg->sample.gr_bin,
                              cfg->sample.gr_max);
    if (config_is_default(cfg, "sample", "every")) { /* an MSD sample costs d N: every 10 steps */
        cfg->sample.every = 10;
        config_origin_derived(cfg, "sample", "every", "default (spheres)");
    }
    if (cfg->sample.fs_k == 0)
        cfg->sample.fs_k = 2 * 3.14159265358979323846 /
                           (cfg->species.n ? cfg->species.sigma[0] : cfg->system.sigma);
    const int rc = check_run_keys(cfg, err);
    if (rc != HSBD_OK) return rc;
    if (cfg->sample.gr_every == 0) {
        const double steps = hsbd_config_steps(cfg);
        cfg->sample.gr_every = (int64_t)fmax(1.0, round(0.05 / cfg->run.dt));
        /* short runs: still at least 10 samples per error block */
        const double most = floor(steps / (10.0 * (double)cfg->sample.blocks));
        if ((double)cfg->sample.gr_every > most) cfg->sample.gr_every = (int64_t)fmax(1.0, most);
        config_origin_derived(cfg, "sample", "gr_every", "default (0.05 time units)");
    }
    const uint64_t gr_samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.gr_every;
    if (gr_samples < (uint64_t)cfg->sample.blocks)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.gr_every = %lld leaves %llu g(r) samples for "
                              "sample.blocks = %lld; allowed: at least one per block",
                              config_origin_of(cfg, "sample", "gr_every"),
                              (long long)cfg->sample.gr_every, (unsigned long long)gr_samples,
                              (long long)cfg->sample.blocks);
    return config_check_memory(cfg, 0, err);
}

int hsbd_config_finalize(hsbd_config *cfg, hsbd_error *err) {
    hsbd_error_clear(err);
    if (config_check_memory(cfg, 1, err) != HSBD_OK) return err->status; /* before N-sized arrays */
    if (refuse_keys_of_other_model(cfg, err) != HSBD_OK) return err->status;
    return cfg->system.model == HSBD_MODEL_SPHERES ? finalise_spheres(cfg, err)
                                                   : finalise_rods(cfg, err);
}

int hsbd_config_particles(const hsbd_config *cfg, int *species, double *sigma, double *diffusion,
                          hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    double *mean = malloc(n * sizeof *mean);
    if (!mean) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    size_t i = 0;
    for (size_t k = 0; k < (cfg->species.n ? cfg->species.n : 1); ++k) {
        const size_t count = cfg->species.n ? (size_t)cfg->species.count[k] : n;
        for (size_t c = 0; c < count && i < n; ++c, ++i) {
            mean[i] = cfg->species.n ? cfg->species.sigma[k] : cfg->system.sigma;
            if (species) species[i] = (int)k;
            if (diffusion)
                diffusion[i] = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
        }
    }
    double *out = sigma ? sigma : malloc(n * sizeof *out);
    int rc = out ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    if (rc == HSBD_OK)
        rc = hsbd_spheres_draw_diameters(cfg->system.seed, n, mean, cfg->species.polydispersity,
                                         (hsbd_size_distribution)cfg->species.distribution, out,
                                         err);
    for (size_t q = 0; rc == HSBD_OK && diffusion && q < n; ++q)
        if (cfg->species.d_law == HSBD_D_STOKES_EINSTEIN) diffusion[q] *= mean[q] / out[q];
    if (!sigma) free(out);
    free(mean);
    return rc;
}
