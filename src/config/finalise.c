/* Checks across keys and derived defaults, once all input is read: what every model shares
 * (the species lists, the boundary, the run's step counts, sampling and output keys) and
 * the dispatch to each model's own rules (finalise_rods.c, finalise_spheres.c) through the
 * table of models. */
#include "config/schema.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int config_divides(double b, double a) {
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

size_t config_split_list(char *text, char **words, size_t max) {
    size_t count = 0;
    for (char *w = strtok(text, " \t,"); w; w = strtok(NULL, " \t,")) {
        if (count == max) return max + 1;
        words[count++] = w;
    }
    return count;
}

int config_parse_species_numbers(hsbd_config *cfg, const char *key, const char *text, double min,
                                 int open, int whole, double *out, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t ns = cfg->species.n, got = config_split_list(buf, words, HSBD_MAX_SPECIES);
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
    const int rc = config_parse_species_numbers(cfg, "fraction", cfg->species.fraction_text, 0, 1,
                                                0, frac, err);
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

/* Does the configuration's model read the key? */
static int model_reads(const hsbd_config *cfg, const char *section, const char *key) {
    return config_key_read(cfg, config_find_key(section, key));
}

/* Without species.names, no other list of [species] may be set. */
static int refuse_lists_without_names(const hsbd_config *cfg, hsbd_error *err) {
    static const char *const lists[] = {"count", "sigma", "D", "fraction"};
    for (int k = 0; k < 4; ++k)
        if (!config_is_default(cfg, "species", lists[k]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.%s is set but species.names is empty; name the "
                                  "species first",
                                  config_origin_of(cfg, "species", lists[k]), lists[k]);
    return HSBD_OK;
}

/* species.names: 1 to HSBD_MAX_SPECIES unique names of letters, digits and '_'. */
static int parse_species_names(hsbd_config *cfg, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", cfg->species.names_text);
    const size_t ns = config_split_list(buf, words, HSBD_MAX_SPECIES);
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
    return HSBD_OK;
}

/* species.D: its list (> 0, or >= 0 for a model with immobile species), or with
 * species.D_law = stokes-einstein D_k = D_0 sigma_0 / sigma_k, when the list is not set. */
static int species_diffusion(hsbd_config *cfg, int stokes, hsbd_error *err) {
    if (!stokes)
        return config_parse_species_numbers(cfg, "D", cfg->species.d_text, 0,
                                            !config_model(cfg)->immobile_species, 0,
                                            cfg->species.diffusion, err);
    if (cfg->species.d_text[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.D is set, but species.D_law = stokes-einstein (%s) "
                              "derives D from system.D and system.sigma; remove one of them",
                              config_origin_of(cfg, "species", "D"),
                              config_origin_of(cfg, "species", "D_law"));
    for (size_t k = 0; k < cfg->species.n; ++k)
        cfg->species.diffusion[k] =
            cfg->system.diffusion * cfg->system.sigma / cfg->species.sigma[k];
    return HSBD_OK;
}

/* The counts (from species.count, or species.fraction where the model reads it), the
 * lengths or diameters (> 0 unless the model has point particles) and D of every species. */
static int parse_species_lists(hsbd_config *cfg, int stokes, double *count, hsbd_error *err) {
    const int fractions = model_reads(cfg, "species", "fraction") && cfg->species.fraction_text[0];
    int rc = fractions ? species_counts_from_fractions(cfg, count, err)
                       : config_parse_species_numbers(cfg, "count", cfg->species.count_text, 1, 0,
                                                      1, count, err);
    if (rc == HSBD_OK)
        rc = config_parse_species_numbers(cfg, "sigma", cfg->species.sigma_text, 0,
                                          !config_model(cfg)->point_particles, 0,
                                          cfg->species.sigma, err);
    return rc == HSBD_OK ? species_diffusion(cfg, stokes, err) : rc;
}

int config_parse_species(hsbd_config *cfg, hsbd_error *err) {
    cfg->species.n = 0;
    if (!cfg->species.names_text[0]) return refuse_lists_without_names(cfg, err);
    if (parse_species_names(cfg, err) != HSBD_OK) return err->status;
    const int stokes =
        model_reads(cfg, "species", "D_law") && cfg->species.d_law == HSBD_D_STOKES_EINSTEIN;
    double count[HSBD_MAX_SPECIES], total = 0;
    if (parse_species_lists(cfg, stokes, count, err) != HSBD_OK) return err->status;
    for (size_t k = 0; k < cfg->species.n; ++k)
        cfg->species.count[k] = (int64_t)count[k], total += count[k];
    if (total != (double)cfg->system.n)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.count sums to %.0f rods but system.N = %lld (%s); "
                              "allowed: counts summing to system.N",
                              config_origin_of(cfg, "species", "count"), total,
                              (long long)cfg->system.n, config_origin_of(cfg, "system", "N"));
    static const char *const single[] = {"sigma", "D"};
    /* Stokes-Einstein: the reference D_0, sigma_0; the species of an init.positions file:
     * one value for every species */
    for (int k = 0; k < 2 && !stokes && !config_from_input(cfg, "species", "names"); ++k)
        if (!config_is_default(cfg, "system", single[k]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: system.%s is set, but with species.names the species.%s "
                                  "list gives it; remove one of them",
                                  config_origin_of(cfg, "system", single[k]), single[k], single[k]);
    cfg->system.sigma = cfg->species.sigma[0];
    cfg->system.diffusion = cfg->species.diffusion[0];
    return HSBD_OK;
}

/* The name of the model that reads a key. */
static const char *model_reading(const key_spec *k) {
    for (size_t m = 0; m < config_nmodels; ++m)
        if (k->models & config_models[m].keys) return config_models[m].name;
    return "none";
}

/* A key that the model does not read, set by the user, is an error, not a silent no-op. */
static int refuse_keys_of_other_model(const hsbd_config *cfg, hsbd_error *err) {
    for (size_t i = 0; i < config_nkeys; ++i) {
        const key_spec *k = &config_schema[i];
        if (!config_key_read(cfg, k) && !config_is_default(cfg, k->section, k->key))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s applies to system.model = %s only, but the model "
                                  "is %s (%s); remove the key",
                                  config_origin_of(cfg, k->section, k->key), k->section, k->key,
                                  model_reading(k), config_model(cfg)->name,
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

int config_check_run_keys(hsbd_config *cfg, hsbd_error *err) {
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
    if (isnan(cfg->output.log_every)) { /* derived like trajectory_every: never refuses */
        cfg->output.log_every = fmax(cfg->run.t_total / 1000, cfg->run.dt);
        config_origin_derived(cfg, "output", "log_every", "default (run.t_total/1000)");
    }
    if (cfg->output.log_every > 0 && cfg->output.log_every < cfg->run.dt)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: output.log_every = %g is shorter than run.dt = %g; allowed: 0 "
                              "(no log.tsv) or log_every >= dt",
                              config_origin_of(cfg, "output", "log_every"), cfg->output.log_every,
                              cfg->run.dt);
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

int config_parse_boundary(hsbd_config *cfg, int dim, int *walls, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[4];
    snprintf(buf, sizeof buf, "%s", cfg->system.boundary_text);
    const size_t got = config_split_list(buf, words, 3);
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

int hsbd_config_finalize(hsbd_config *cfg, hsbd_error *err) {
    hsbd_error_clear(err);
    const model_spec *model = config_model(cfg);
    if (!model) {
        char allowed[160];
        config_format_range(config_find_key("system", "model"), allowed, sizeof allowed);
        return hsbd_error_set(err, HSBD_EINPUT, "%s: system.model = %d is not known; allowed: %s",
                              config_origin_of(cfg, "system", "model"), cfg->system.model, allowed);
    }
    config_input in; /* what init.positions fixes: N first */
    if (config_input_take(cfg, &in, err) != HSBD_OK) return err->status;
    if (config_check_memory(cfg, 1, err) != HSBD_OK) return err->status; /* before N-sized arrays */
    if (refuse_keys_of_other_model(cfg, err) != HSBD_OK) return err->status;
    if (model->finalise(cfg, err) != HSBD_OK) return err->status;
    return config_input_check(cfg, &in, err);
}
