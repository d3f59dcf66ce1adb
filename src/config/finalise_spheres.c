/* The spheres' rules across keys: the box or the packing fraction, the walls and the field,
 * the couplings per species, the initial state, g(r), and derived defaults. */
#include "config/schema.h"

#include <stdint.h>
#include <stdlib.h>

#include "hsbd/spheres.h"

/* A list of `dim` finite numbers (or, when one_for_all, 1 repeated) in (min, inf) or any
 * (min = -inf). */
static int parse_vector(const hsbd_config *cfg, const char *key, const char *text, int dim,
                        int one_for_all, double min, double *out, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[4];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t got = config_split_list(buf, words, 3);
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

/* The particles' volume (phi in a unit box) and largest diameter, from the diameters drawn
 * with the seed when polydisperse. */
static int particles_volume(const hsbd_config *cfg, double *volume, double *sigma_max,
                            hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    double *sigma = malloc(n * sizeof *sigma);
    if (!sigma) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    if (hsbd_config_particles(cfg, NULL, sigma, NULL, err) != HSBD_OK)
        return free(sigma), err->status;
    const double unit[3] = {1, 1, 1};
    *volume = hsbd_spheres_packing_fraction((int)cfg->system.dimension, unit, n, sigma);
    *sigma_max = 0;
    for (size_t i = 0; i < n; ++i)
        *sigma_max = fmax(*sigma_max, sigma[i]);
    free(sigma);
    return HSBD_OK;
}

/* The box, from system.box or from system.packing_fraction (exactly one of them), below
 * close packing; its packing fraction in *phi. */
static int parse_box(hsbd_config *cfg, double volume, double *phi, hsbd_error *err) {
    const int dim = (int)cfg->system.dimension;
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
        const double side = pow(volume / cfg->system.packing_fraction, 1.0 / dim);
        for (int a = 0; a < 3; ++a)
            cfg->system.box[a] = a < dim ? side : 0;
    }
    double box_volume = 1;
    for (int a = 0; a < dim; ++a)
        box_volume *= cfg->system.box[a];
    *phi = volume / box_volume;
    if (!has_phi) cfg->system.packing_fraction = *phi;
    if (*phi >= (dim == 3 ? 0.74 : 0.9069))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: packing fraction %g exceeds close packing (%g); allowed: a "
                              "larger box",
                              config_origin_of(cfg, "system", has_box ? "box" : "packing_fraction"),
                              *phi, dim == 3 ? 0.7405 : 0.9069);
    return HSBD_OK;
}

/* The walls per axis, each pair at least sigma_max apart. */
static int check_walls(hsbd_config *cfg, double sigma_max, hsbd_error *err) {
    const int dim = (int)cfg->system.dimension;
    if (config_parse_boundary(cfg, dim, cfg->system.walls, err) != HSBD_OK) return err->status;
    for (int a = 0; a < dim; ++a)
        if (cfg->system.walls[a] && !(cfg->system.box[a] >= sigma_max))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: the box length %g along axis %c between walls is shorter "
                                  "than the largest diameter %g; allowed: >= sigma_max",
                                  config_origin_of(cfg, "system", "boundary"), cfg->system.box[a],
                                  "xyz"[a], sigma_max);
    return HSBD_OK;
}

/* The field: none unless set, along the last axis unless set (within the dimension), its
 * wavelength dividing a periodic box, a table term with its file, centred in the box
 * unless set. */
static int check_field(hsbd_config *cfg, hsbd_error *err) {
    const int dim = (int)cfg->system.dimension;
    if (config_is_default(cfg, "field", "type")) cfg->field.type = 0; /* spheres: none */
    if (config_is_default(cfg, "field", "axis")) cfg->field.axis = dim - 1;
    const int axis = cfg->field.axis;
    if (axis >= dim)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.axis = %c is beyond system.dimension = %d; allowed: %s",
                              config_origin_of(cfg, "field", "axis"), "xyz"[axis], dim,
                              dim == 2 ? "x or y" : "x, y or z");
    const double length = cfg->system.box[axis];
    if ((cfg->field.type & HSBD_FIELD_COSINE) && !cfg->system.walls[axis] &&
        !config_divides(cfg->field.wavelength, length))
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
    return HSBD_OK;
}

/* The field's factor per species: 1, or species.coupling (with species.names, and not with
 * species.coupling_law = volume). */
static int parse_couplings(hsbd_config *cfg, hsbd_error *err) {
    for (size_t k = 0; k < (cfg->species.n ? cfg->species.n : 1); ++k)
        cfg->species.coupling[k] = 1.0;
    if (!cfg->species.coupling_text[0]) return HSBD_OK;
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
    return config_parse_species_numbers(cfg, "coupling", cfg->species.coupling_text, -INFINITY, 1,
                                        0, cfg->species.coupling, err);
}

/* Particles with D = 0 cannot move: no field acts on them, no drift. */
static int refuse_moving_immobile(const hsbd_config *cfg, hsbd_error *err) {
    for (size_t k = 0; k < (cfg->species.n ? cfg->species.n : 1); ++k) {
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
    return HSBD_OK;
}

/* One [active] list: one value for every species or one per species, each finite and
 * >= 0, into out[species]. */
static int parse_active_list(hsbd_config *cfg, const char *key, const char *text, double *out,
                             hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    const size_t got = config_split_list(buf, words, HSBD_MAX_SPECIES);
    if (got != 1 && got != ns)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: active.%s has %zu values for %zu species; allowed: one value, "
                              "or one per species (species.names)",
                              config_origin_of(cfg, "active", key), key, got, ns);
    for (size_t k = 0; k < ns; ++k) {
        const char *w = words[got == 1 ? 0 : k], *why;
        double v;
        if (config_parse_number(w, &v, &why) != 0 || !(v >= 0))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: active.%s value '%.40s'%s%s is out of range; allowed: "
                                  "finite decimal numbers 0 <= %s < inf",
                                  config_origin_of(cfg, "active", key), key, w,
                                  got > 1 ? " of species " : "",
                                  got > 1 ? cfg->species.name[k] : "", key);
        out[k] = v;
    }
    return HSBD_OK;
}

/* [active]: v0 per species (none active when empty), D_r per species or 3 D_i / sigma_i^2;
 * a species with D = 0 cannot be active. */
static int parse_active(hsbd_config *cfg, hsbd_error *err) {
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    cfg->active.on = cfg->active.v0_text[0] != 0;
    cfg->active.rotational_default = !cfg->active.rotational_text[0];
    for (size_t k = 0; k < ns; ++k)
        cfg->active.v0[k] = cfg->active.rotational[k] = 0;
    if (!cfg->active.on) {
        if (cfg->active.rotational_text[0])
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: active.rotational_D is set but active.v0 is empty; allowed: "
                                  "active.v0 (0 for passive rotors) with it, or neither",
                                  config_origin_of(cfg, "active", "rotational_D"));
        return HSBD_OK;
    }
    if (parse_active_list(cfg, "v0", cfg->active.v0_text, cfg->active.v0, err) != HSBD_OK ||
        (!cfg->active.rotational_default &&
         parse_active_list(cfg, "rotational_D", cfg->active.rotational_text, cfg->active.rotational,
                           err) != HSBD_OK))
        return err->status;
    for (size_t k = 0; k < ns; ++k) {
        const double d = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
        if (d == 0 && cfg->active.v0[k] > 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: active.v0 = %g for species %s, whose D = 0 cannot move; "
                                  "allowed: v0 = 0 for it (one value per species)",
                                  config_origin_of(cfg, "active", "v0"), cfg->active.v0[k],
                                  cfg->species.n ? cfg->species.name[k] : "(one)");
    }
    return HSBD_OK;
}

void hsbd_config_active(const hsbd_config *cfg, const int *species, const double *sigma,
                        const double *diffusion, double *v0, double *rotational) {
    for (size_t i = 0; i < (size_t)cfg->system.n; ++i) {
        const size_t k = species ? (size_t)species[i] : 0;
        v0[i] = cfg->active.on ? cfg->active.v0[k] : 0.0;
        rotational[i] = !cfg->active.on                  ? 0.0
                        : cfg->active.rotational_default ? 3 * diffusion[i] / (sigma[i] * sigma[i])
                                                         : cfg->active.rotational[k];
    }
}

/* The profiles along field.axis: bins of sigma/20 unless set, over sample.period (the
 * field's wavelength or the box unless set) dividing a periodic box, the box between walls. */
static int check_profiles(hsbd_config *cfg, hsbd_error *err) {
    const double length = cfg->system.box[cfg->field.axis];
    const int periodic = !cfg->system.walls[cfg->field.axis];
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
    if (!config_divides(cfg->sample.period, length) || (!periodic && cfg->sample.period != length))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.period = %g; allowed: a divisor of the periodic box "
                              "length %g along field.axis (the box length between walls)",
                              config_origin_of(cfg, "sample", "period"), cfg->sample.period,
                              length);
    return HSBD_OK;
}

/* init.method reaches phi (unless init.positions gives the state); auto chooses the first
 * that does. What each reaches: RSI stalls near 0.38 / 0.547; the compression was measured
 * to reach 0.60 / 0.72 at N = 4000 (docs/spheres.md). */
static int choose_init_method(hsbd_config *cfg, double phi, hsbd_error *err) {
    const int dim = (int)cfg->system.dimension;
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
    return HSBD_OK;
}

/* g(r)'s range: 3 sigma_max unless set, at most half the shortest periodic box length
 * (pairs are minimum images along the periodic axes only), and wider than a bin. */
static int check_gr_range(hsbd_config *cfg, double sigma_max, hsbd_error *err) {
    double half = INFINITY;
    for (int a = 0; a < (int)cfg->system.dimension; ++a)
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
    return HSBD_OK;
}

/* Samples every 10 steps unless set (an MSD sample costs d N); F_s at k = 2 pi / sigma
 * unless set. */
static void derive_sampling(hsbd_config *cfg) {
    if (config_is_default(cfg, "sample", "every")) {
        cfg->sample.every = 10;
        config_origin_derived(cfg, "sample", "every", "default (spheres)");
    }
    if (cfg->sample.fs_k == 0)
        cfg->sample.fs_k = 2 * 3.14159265358979323846 /
                           (cfg->species.n ? cfg->species.sigma[0] : cfg->system.sigma);
}

/* g(r) every 0.05 time units unless set (short runs: at least 10 samples per error block),
 * at least one sample per block. */
static int check_gr_every(hsbd_config *cfg, hsbd_error *err) {
    if (cfg->sample.gr_every == 0) {
        const double steps = hsbd_config_steps(cfg);
        cfg->sample.gr_every = (int64_t)fmax(1.0, round(0.05 / cfg->run.dt));
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
    return HSBD_OK;
}

/* system.sigma: 1 unless set, and > 0. */
static int check_sigma(hsbd_config *cfg, hsbd_error *err) {
    if (config_is_default(cfg, "system", "sigma")) {
        cfg->system.sigma = 1.0;
        config_origin_derived(cfg, "system", "sigma", "default (spheres)");
    }
    if (!(cfg->system.sigma > 0))
        return hsbd_error_set(err, HSBD_EINPUT, "%s: system.sigma = %g; allowed: sigma > 0",
                              config_origin_of(cfg, "system", "sigma"), cfg->system.sigma);
    return HSBD_OK;
}

int config_finalise_spheres(hsbd_config *cfg, hsbd_error *err) {
    double volume = 0, sigma_max = 0, phi = 0;
    if (check_sigma(cfg, err) != HSBD_OK) return err->status;
    if (config_parse_species(cfg, err) != HSBD_OK) return err->status;
    if (particles_volume(cfg, &volume, &sigma_max, err) != HSBD_OK) return err->status;
    if (parse_box(cfg, volume, &phi, err) != HSBD_OK) return err->status;
    if (cfg->system.drift_text[0] &&
        parse_vector(cfg, "drift", cfg->system.drift_text, (int)cfg->system.dimension, 0, -INFINITY,
                     cfg->system.drift, err))
        return err->status;
    if (check_walls(cfg, sigma_max, err) != HSBD_OK) return err->status;
    if (check_field(cfg, err) != HSBD_OK) return err->status;
    if (parse_couplings(cfg, err) != HSBD_OK) return err->status;
    if (refuse_moving_immobile(cfg, err) != HSBD_OK) return err->status;
    if (parse_active(cfg, err) != HSBD_OK) return err->status;
    if (check_profiles(cfg, err) != HSBD_OK) return err->status;
    if (choose_init_method(cfg, phi, err) != HSBD_OK) return err->status;
    if (check_gr_range(cfg, sigma_max, err) != HSBD_OK) return err->status;
    derive_sampling(cfg);
    if (config_check_run_keys(cfg, err) != HSBD_OK) return err->status;
    if (check_gr_every(cfg, err) != HSBD_OK) return err->status;
    return config_check_memory(cfg, 0, err);
}

int hsbd_config_particles(const hsbd_config *cfg, int *species, double *sigma, double *diffusion,
                          hsbd_error *err) {
    if (cfg->init.gsd) return config_input_particles(cfg, species, sigma, diffusion, err);
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
