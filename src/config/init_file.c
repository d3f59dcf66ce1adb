/* What an init.positions file fixes (docs/trajectories.md). A GSD frame gives N, the
 * dimension and box, the species (its types that have particles, in the file's order) with
 * their counts and diameters; an extended-XYZ frame of spheres its N and, with a Lattice,
 * its box. A key the configuration leaves unset takes the file's value, its origin naming
 * the file; a key it sets must agree with the file, else the message names both values
 * and where each came from. */
#include "config/schema.h"

#include <stdlib.h>
#include <string.h>

#include "core/input.h"
#include "hsbd/io.h"

/* the relative difference within which a restated length agrees with the file's (GSD keeps
 * float32: 6e-8; an XYZ Lattice is text) */
static double agreement(const config_input *in) {
    return in->kind == 2 ? 1e-6 : 1e-9;
}

static int agree(double a, double b, double tol) {
    return fabs(a - b) <= tol * fabs(b);
}

/* Sets a key the configuration left unset to the file's value (parsed as if given). */
static int take(hsbd_config *cfg, const config_input *in, const char *section, const char *key,
                const char *text, hsbd_error *err) {
    const key_spec *k = config_find_key(section, key);
    if (config_parse_value(cfg, k, text, in->what, err) != HSBD_OK) return err->status;
    config_origin_from_input(cfg, k, in->what);
    return HSBD_OK;
}

static int disagree(const hsbd_config *cfg, const config_input *in, const char *section,
                    const char *key, const char *restated, const char *file, hsbd_error *err) {
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: %s.%s = %s disagrees with %s, which has %s; allowed: the file's "
                          "value, or leave %s.%s out (the file gives it)",
                          config_origin_of(cfg, section, key), section, key, restated, in->what,
                          file, section, key);
}

/* ---- reading the file ------------------------------------------------------------------- */

/* The GSD frame's summary: the types that have particles, their counts and diameters. */
static int summarise_gsd(const hsbd_config *cfg, config_input *in, hsbd_error *err) {
    hsbd_gsd_snapshot s;
    if (hsbd_gsd_read(cfg->init.positions, cfg->init.frame, &s, err) != HSBD_OK) return err->status;
    snprintf(in->what, sizeof in->what, "init.positions '%s' (frame %llu of %llu)",
             cfg->init.positions, (unsigned long long)s.frame, (unsigned long long)s.frames);
    in->kind = 2, in->n = s.n, in->dimension = s.dimension, in->has_box = 1;
    memcpy(in->box, s.box, sizeof in->box);
    int64_t *count = calloc(s.ntypes, sizeof *count);
    double *lo = malloc(2 * s.ntypes * sizeof *lo), *hi = lo + s.ntypes;
    int rc = count && lo ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t i = 0; rc == HSBD_OK && i < s.n; ++i) {
        const uint32_t t = s.typeid[i];
        const double d = s.diameter[i];
        lo[t] = count[t] ? fmin(lo[t], d) : d, hi[t] = count[t] ? fmax(hi[t], d) : d;
        count[t] += 1;
    }
    double *sum = malloc(s.ntypes * sizeof *sum);
    if (rc == HSBD_OK && !sum) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t t = 0; rc == HSBD_OK && t < s.ntypes; ++t)
        sum[t] = 0;
    for (size_t i = 0; rc == HSBD_OK && i < s.n; ++i)
        sum[s.typeid[i]] += s.diameter[i];
    for (size_t t = 0; rc == HSBD_OK && t < s.ntypes; ++t) {
        if (!count[t]) continue; /* a type without particles is no species */
        if (in->ntypes == HSBD_MAX_SPECIES) {
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s: more than %d types have particles; allowed: at most %d "
                                "species",
                                in->what, HSBD_MAX_SPECIES, HSBD_MAX_SPECIES);
            break;
        }
        const size_t k = in->ntypes++;
        snprintf(in->names[k], HSBD_SPECIES_NAME, "%s", s.types[t]);
        in->count[k] = count[t];
        in->varies[k] = lo[t] != hi[t];
        in->sigma[k] = in->varies[k] ? sum[t] / (double)count[t] : lo[t];
    }
    free(count), free(lo), free(sum);
    hsbd_gsd_snapshot_free(&s);
    return rc;
}

static int summarise_xyz(const hsbd_config *cfg, config_input *in, hsbd_error *err) {
    FILE *f = hsbd_input_open(cfg->init.positions, "init.positions file", err);
    if (!f) return err->status;
    const int rc = hsbd_xyz_read_head(f, cfg->init.positions, &in->n, in->box, &in->has_box, err);
    fclose(f);
    snprintf(in->what, sizeof in->what, "init.positions '%s'", cfg->init.positions);
    in->kind = 1;
    return rc;
}

/* ---- taking what the file fixes --------------------------------------------------------- */

static int take_count(hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    char text[64];
    snprintf(text, sizeof text, "%zu", in->n);
    if (config_is_default(cfg, "system", "N")) return take(cfg, in, "system", "N", text, err);
    if ((size_t)cfg->system.n == in->n) return HSBD_OK;
    char restated[32], file[64];
    snprintf(restated, sizeof restated, "%lld", (long long)cfg->system.n);
    snprintf(file, sizeof file, "N = %zu particles", in->n);
    return disagree(cfg, in, "system", "N", restated, file, err);
}

/* spheres: the dimension (GSD) and the box, unless system.box or packing_fraction is set */
static int take_box(hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    char text[96];
    if (in->dimension && config_is_default(cfg, "system", "dimension")) {
        snprintf(text, sizeof text, "%d", in->dimension);
        if (take(cfg, in, "system", "dimension", text, err) != HSBD_OK) return err->status;
    } else if (in->dimension && cfg->system.dimension != in->dimension) {
        snprintf(text, sizeof text, "%lld", (long long)cfg->system.dimension);
        return disagree(cfg, in, "system", "dimension", text,
                        in->dimension == 2 ? "2 dimensions" : "3 dimensions", err);
    }
    if (!in->has_box || cfg->system.box_text[0] ||
        !config_is_default(cfg, "system", "packing_fraction"))
        return HSBD_OK; /* a restated box is compared once it is parsed */
    const int dim = (int)cfg->system.dimension;
    snprintf(text, sizeof text, "%.17g %.17g", in->box[0], in->box[1]);
    if (dim == 3) snprintf(text + strlen(text), sizeof text - strlen(text), " %.17g", in->box[2]);
    return take(cfg, in, "system", "box", text, err);
}

/* the names of species.names as the configuration gives them, space-separated */
static size_t config_names(const hsbd_config *cfg, char *list, size_t len) {
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", cfg->species.names_text);
    const size_t n = config_split_list(buf, words, HSBD_MAX_SPECIES);
    list[0] = '\0';
    for (size_t k = 0; k < n && k <= HSBD_MAX_SPECIES; ++k)
        snprintf(list + strlen(list), len - strlen(list), "%s%s", k ? " " : "", words[k]);
    return n;
}

/* a species list of the file's (names, counts or diameters), space-separated */
static void file_list(const config_input *in, int what, char *list, size_t len) {
    list[0] = '\0';
    for (size_t k = 0; k < in->ntypes; ++k) {
        const size_t at = strlen(list);
        const char *sep = k ? " " : "";
        if (what == 0) snprintf(list + at, len - at, "%s%s", sep, in->names[k]);
        if (what == 1) snprintf(list + at, len - at, "%s%lld", sep, (long long)in->count[k]);
        if (what == 2) snprintf(list + at, len - at, "%s%.17g", sep, in->sigma[k]);
    }
}

/* One type and no species.names: one species, system.sigma its diameter (or their mean). */
static int take_one_species(hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    char text[64];
    snprintf(text, sizeof text, "%.17g", in->sigma[0]);
    return config_is_default(cfg, "system", "sigma") ? take(cfg, in, "system", "sigma", text, err)
                                                     : HSBD_OK;
}

/* The file's types as the species: species.names must list them (in the file's order)
 * when set; counts and diameters are taken when unset, D is system.D for every species
 * when species.D is unset and the names are the file's. */
static int take_species(hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    char list[HSBD_PATH_MAX], names[HSBD_PATH_MAX];
    file_list(in, 0, list, sizeof list);
    if (cfg->species.names_text[0]) {
        config_names(cfg, names, sizeof names);
        if (strcmp(names, list)) {
            char file[HSBD_PATH_MAX + 40];
            snprintf(file, sizeof file, "the types '%s'", list);
            snprintf(names, sizeof names, "'%.1000s'", cfg->species.names_text);
            return disagree(cfg, in, "species", "names", names, file, err);
        }
    } else if (take(cfg, in, "species", "names", list, err) != HSBD_OK) {
        return err->status;
    } else if (!config_is_default(cfg, "system", "sigma")) {
        for (size_t k = 0; k < in->ntypes; ++k)
            if (!in->varies[k] && !agree(cfg->system.sigma, in->sigma[k], agreement(in))) {
                snprintf(names, sizeof names, "%.17g", cfg->system.sigma);
                snprintf(list, sizeof list, "the diameter %.9g for type %s", in->sigma[k],
                         in->names[k]);
                return disagree(cfg, in, "system", "sigma", names, list, err);
            }
    }
    const int fractions = config_key_read(cfg, config_find_key("species", "fraction")) &&
                          cfg->species.fraction_text[0];
    file_list(in, 1, list, sizeof list);
    if (!cfg->species.count_text[0] && !fractions &&
        take(cfg, in, "species", "count", list, err) != HSBD_OK)
        return err->status;
    file_list(in, 2, list, sizeof list);
    if (!cfg->species.sigma_text[0] && take(cfg, in, "species", "sigma", list, err) != HSBD_OK)
        return err->status;
    if (cfg->species.d_text[0] || !config_from_input(cfg, "species", "names")) return HSBD_OK;
    list[0] = '\0';
    for (size_t k = 0; k < in->ntypes; ++k)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%.17g", k ? " " : "",
                 cfg->system.diffusion);
    return take(cfg, in, "species", "D", list, err);
}

/* Diameters come from a GSD file: not drawn (spheres), one per type (rods). */
static int check_diameters(const hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    if (config_key_read(cfg, config_find_key("species", "polydispersity")) &&
        !config_is_default(cfg, "species", "polydispersity"))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.polydispersity draws the diameters, but %s gives "
                              "each particle's; remove species.polydispersity",
                              config_origin_of(cfg, "species", "polydispersity"), in->what);
    for (size_t k = 0; k < in->ntypes && cfg->system.model == HSBD_MODEL_RODS; ++k)
        if (in->varies[k])
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: the rods of type %s have different diameters; allowed: "
                                  "one length per type (species)",
                                  in->what, in->names[k]);
    return HSBD_OK;
}

int config_input_take(hsbd_config *cfg, config_input *in, hsbd_error *err) {
    *in = (config_input){0};
    const char *path = cfg->init.positions;
    cfg->init.gsd = path[0] && hsbd_gsd_file(path);
    if (!cfg->init.gsd && !config_is_default(cfg, "init", "frame"))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: init.frame chooses a frame of a GSD file, but init.positions "
                              "%s%s%s; remove init.frame",
                              config_origin_of(cfg, "init", "frame"), path[0] ? "'" : "",
                              path[0] ? path : "is not set", path[0] ? "' is not one" : "");
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    int rc = !path[0]        ? HSBD_OK
             : cfg->init.gsd ? summarise_gsd(cfg, in, err)
             : spheres       ? summarise_xyz(cfg, in, err)
                             : HSBD_OK; /* the rods' text files fix nothing */
    if (rc != HSBD_OK || !in->kind) return rc;
    if (take_count(cfg, in, err) != HSBD_OK) return err->status;
    char text[64];
    if (spheres && take_box(cfg, in, err) != HSBD_OK) return err->status;
    snprintf(text, sizeof text, "%.17g", in->box[0]);
    if (!spheres && config_is_default(cfg, "system", "L") &&
        take(cfg, in, "system", "L", text, err) != HSBD_OK)
        return err->status;
    if (in->kind != 2) return HSBD_OK;
    if (check_diameters(cfg, in, err) != HSBD_OK) return err->status;
    return in->ntypes == 1 && !cfg->species.names_text[0] ? take_one_species(cfg, in, err)
                                                          : take_species(cfg, in, err);
}

/* ---- after the model's checks: what the configuration restates agrees ------------------- */

static int check_box(const hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    const int dim = spheres ? (int)cfg->system.dimension : 1;
    const double *box = spheres ? cfg->system.box : &cfg->system.length;
    int same = 1;
    for (int a = 0; a < dim; ++a)
        same &= agree(box[a], in->box[a], agreement(in));
    if (same) return HSBD_OK;
    char restated[HSBD_PATH_MAX + 64], file[160];
    const char *key = !spheres ? "L" : cfg->system.box_text[0] ? "box" : "packing_fraction";
    if (key[0] == 'L') snprintf(restated, sizeof restated, "%.17g", box[0]);
    if (key[0] == 'b') snprintf(restated, sizeof restated, "'%.1000s'", cfg->system.box_text);
    if (key[0] == 'p')
        snprintf(restated, sizeof restated, "%.9g (a box of side %.9g)",
                 cfg->system.packing_fraction, box[0]);
    snprintf(file, sizeof file, "the box %.9g", in->box[0]);
    for (int a = 1; a < dim; ++a)
        snprintf(file + strlen(file), sizeof file - strlen(file), " x %.9g", in->box[a]);
    return disagree(cfg, in, "system", key, restated, file, err);
}

int config_input_check(const hsbd_config *cfg, const config_input *in, hsbd_error *err) {
    if (!in->kind) return HSBD_OK;
    if (in->has_box && check_box(cfg, in, err) != HSBD_OK) return err->status;
    if (in->kind != 2) return HSBD_OK;
    char restated[64], file[160];
    for (size_t k = 0; k < in->ntypes && cfg->species.n; ++k) {
        if (cfg->species.count[k] != in->count[k]) {
            const char *key = cfg->species.count_text[0] ? "count" : "fraction";
            snprintf(restated, sizeof restated, "'%.40s'",
                     key[0] == 'c' ? cfg->species.count_text : cfg->species.fraction_text);
            snprintf(file, sizeof file, "%lld particles of type %s (species.%s gives %lld)",
                     (long long)in->count[k], in->names[k], key, (long long)cfg->species.count[k]);
            return disagree(cfg, in, "species", key, restated, file, err);
        }
        if (!in->varies[k] && !agree(cfg->species.sigma[k], in->sigma[k], agreement(in))) {
            snprintf(restated, sizeof restated, "'%.40s'", cfg->species.sigma_text);
            snprintf(file, sizeof file, "the diameter %.9g for type %s", in->sigma[k],
                     in->names[k]);
            return disagree(cfg, in, "species", "sigma", restated, file, err);
        }
    }
    if (!cfg->species.n && !in->varies[0] &&
        !agree(cfg->system.sigma, in->sigma[0], agreement(in))) {
        snprintf(restated, sizeof restated, "%.17g", cfg->system.sigma);
        snprintf(file, sizeof file, "the diameter %.9g", in->sigma[0]);
        return disagree(cfg, in, "system", "sigma", restated, file, err);
    }
    return HSBD_OK;
}

/* ---- the particles of a GSD file -------------------------------------------------------- */

int config_input_particles(const hsbd_config *cfg, int *species, double *sigma, double *diffusion,
                           hsbd_error *err) {
    hsbd_gsd_snapshot s;
    if (hsbd_gsd_read(cfg->init.positions, cfg->init.frame, &s, err) != HSBD_OK) return err->status;
    const size_t n = (size_t)cfg->system.n;
    int *of_type = malloc(s.ntypes * sizeof *of_type), varies[HSBD_MAX_SPECIES] = {0};
    int seen[HSBD_MAX_SPECIES] = {0};
    double first[HSBD_MAX_SPECIES] = {0};
    int rc = of_type ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t t = 0; rc == HSBD_OK && t < s.ntypes; ++t) { /* its species, or -1 */
        of_type[t] = cfg->species.n ? -1 : 0;
        for (size_t k = 0; k < cfg->species.n; ++k)
            if (!strcmp(s.types[t], cfg->species.name[k])) of_type[t] = (int)k;
    }
    int *kind = malloc(n * sizeof *kind);
    if (rc == HSBD_OK && !kind) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    if (rc == HSBD_OK && s.n != n)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "init.positions '%s': %zu particles, system.N = %zu "
                            "(the file changed?)",
                            cfg->init.positions, s.n, n);
    for (size_t i = 0; rc == HSBD_OK && i < n; ++i) {
        const int k = of_type[s.typeid[i]];
        if (k < 0) {
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "init.positions '%s': particle %zu has the type "
                                "%s, which is not in species.names (the file changed?)",
                                cfg->init.positions, i, s.types[s.typeid[i]]);
            break;
        }
        kind[i] = k;
        if (!seen[k]) seen[k] = 1, first[k] = s.diameter[i];
        varies[k] |= s.diameter[i] != first[k];
    }
    for (size_t i = 0; rc == HSBD_OK && i < n; ++i) {
        const int k = kind[i];
        const double nominal = cfg->species.n ? cfg->species.sigma[k] : cfg->system.sigma;
        const double d = varies[k] ? s.diameter[i] : nominal; /* a restated sigma: exact */
        if (species) species[i] = k;
        if (sigma) sigma[i] = d;
        if (diffusion)
            diffusion[i] = (cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion) *
                           (cfg->species.d_law == HSBD_D_STOKES_EINSTEIN ? nominal / d : 1.0);
    }
    free(of_type), free(kind);
    hsbd_gsd_snapshot_free(&s);
    return rc;
}
