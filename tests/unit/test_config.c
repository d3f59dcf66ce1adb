/* The configuration room's own checks. Where each key got its value (src/config/origin.c),
 * text for text: a file's lines, --set, derived defaults, two origins in one message, a copy
 * by value, texts of the longest length, many distinct origins, and the size of the
 * configuration. The table of models: one row per system.model choice, in its order. */
#include <stdio.h>
#include <string.h>

#include "../test_util.h"
#include "config/schema.h"

/* the configuration's bound: 18 KiB of text fields (the lists of [species] and [active] among
 * them) and numbers, under 9 KiB of origins */
enum { CONFIG_BOUND = 27 * 1024, ORIGINS_BOUND = 9 * 1024 };

#define CHECK_TEXT(got, want) CHECK(!strcmp((got), (want)), "'%s', want '%s'", (got), (want))

static int load(hsbd_config *cfg, const char *name, const char *text, hsbd_error *err) {
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    if (!f) return hsbd_error_set(err, HSBD_EIO, "fmemopen");
    const int rc = hsbd_config_load_stream(cfg, f, name, err);
    fclose(f);
    return rc;
}

static void file_and_set_origins(void) {
    static hsbd_config cfg;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    CHECK_TEXT(hsbd_config_origin(&cfg, "run", "dt"), "default");
    CHECK_TEXT(config_origin_of(&cfg, "run", "dt"), "default"); /* no file yet */
    CHECK(load(&cfg, "runs/a.ini", "[run]\ndt = 0.001\n\nt_total = 2\n[system]\nN = 10\n", &err) ==
              HSBD_OK,
          "%s", err.message);
    CHECK_TEXT(hsbd_config_origin(&cfg, "run", "dt"), "runs/a.ini:2");
    CHECK_TEXT(hsbd_config_origin(&cfg, "run", "t_total"), "runs/a.ini:4");
    CHECK_TEXT(hsbd_config_origin(&cfg, "system", "N"), "runs/a.ini:6");
    CHECK_TEXT(hsbd_config_origin(&cfg, "system", "L"), "default");
    CHECK_TEXT(config_origin_of(&cfg, "system", "L"), "runs/a.ini"); /* a default names the file */
    CHECK_TEXT(hsbd_config_origin(&cfg, "system", "nonsense"), "");
    CHECK(hsbd_config_set(&cfg, "system.N=20", "command line (--set)", &err) == HSBD_OK, "%s",
          err.message);
    CHECK(hsbd_config_set(&cfg, "run.t_equil = 1", "hsbd resume --set", &err) == HSBD_OK, "%s",
          err.message);
    CHECK_TEXT(hsbd_config_origin(&cfg, "system", "N"), "command line (--set) system.N");
    CHECK_TEXT(config_origin_of(&cfg, "run", "t_equil"), "hsbd resume --set run.t_equil");
    CHECK(!config_is_default(&cfg, "system", "N") && config_is_default(&cfg, "system", "L"),
          "set and default keys");
    /* a file whose name starts with "default" still names its lines */
    static hsbd_config named;
    hsbd_config_defaults(&named);
    CHECK(load(&named, "defaults.ini", "[run]\ndt = 0.002\n", &err) == HSBD_OK, "%s", err.message);
    CHECK_TEXT(config_origin_of(&named, "run", "dt"), "defaults.ini:2");
    CHECK(!config_is_default(&named, "run", "dt"), "run.dt is set by defaults.ini");
}

static void messages_with_origins(void) {
    static hsbd_config cfg;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    CHECK(load(&cfg, "x.ini", "[run]\ndt = 0.001\n# again\ndt = 0.002\n", &err) == HSBD_EINPUT,
          "a key set twice");
    CHECK_TEXT(err.message, "x.ini:4: run.dt is set twice (first at x.ini:2)");
    /* two origins in one message: from a file's lines, then from two --set origins */
    hsbd_config_defaults(&cfg);
    CHECK(load(&cfg, "mix.ini",
               "[system]\nmodel = spheres\nN = 10\npacking_fraction = 0.1\n[species]\n"
               "names = a b\ncount = 5 5\nfraction = 0.5 0.5\n",
               &err) == HSBD_OK,
          "%s", err.message);
    CHECK(hsbd_config_finalize(&cfg, &err) == HSBD_EINPUT, "count and fraction");
    CHECK_TEXT(err.message, "mix.ini:7: species.count and species.fraction (mix.ini:8) are both "
                            "set; allowed: one of them");
    hsbd_config_defaults(&cfg);
    const char *sets[] = {"system.model=spheres",        "system.N=10",
                          "system.packing_fraction=0.1", "species.names=a b",
                          "species.count=5 5",           "species.sigma=1 2"};
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; ++k)
        CHECK(hsbd_config_set(&cfg, sets[k], "validate", &err) == HSBD_OK, "%s", err.message);
    CHECK(hsbd_config_set(&cfg, "species.D=1 1", "command line (--set)", &err) == HSBD_OK, "%s",
          err.message);
    CHECK(hsbd_config_set(&cfg, "species.D_law=stokes-einstein", "hsbd resume --set", &err) ==
              HSBD_OK,
          "%s", err.message);
    CHECK(hsbd_config_finalize(&cfg, &err) == HSBD_EINPUT, "D and D_law");
    CHECK_TEXT(err.message,
               "command line (--set) species.D: species.D is set, but species.D_law = "
               "stokes-einstein (hsbd resume --set species.D_law) derives D from system.D and "
               "system.sigma; remove one of them");
    char both[256];
    snprintf(both, sizeof both, "%s | %s", config_origin_of(&cfg, "species", "count"),
             config_origin_of(&cfg, "species", "D"));
    CHECK_TEXT(both, "validate species.count | command line (--set) species.D");
}

static void derived_origins_and_copies(void) {
    static hsbd_config cfg, copy, later;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    CHECK(hsbd_config_finalize(&cfg, &err) == HSBD_OK, "%s", err.message);
    CHECK_TEXT(hsbd_config_origin(&cfg, "field", "center"), "default (L/2)");
    CHECK_TEXT(config_origin_of(&cfg, "sample", "period"), "default (field.wavelength or L)");
    CHECK(config_is_default(&cfg, "field", "center"), "a derived default is a default");
    hsbd_config_defaults(&later);
    CHECK(load(&later, "rods.ini", "[system]\nN = 10\n", &err) == HSBD_OK, "%s", err.message);
    CHECK(hsbd_config_set(&later, "run.dt=0.002", "Python (keyword arguments)", &err) == HSBD_OK,
          "%s", err.message);
    CHECK(hsbd_config_finalize(&later, &err) == HSBD_OK, "%s", err.message);
    CHECK_TEXT(hsbd_config_origin(&later, "sample", "contact_width"),
               "default (derived from run.dt)");
    CHECK_TEXT(config_origin_of(&later, "sample", "contact_width"), "rods.ini");
    copy = later; /* by value, as src/run/sim.c does */
    hsbd_config_defaults(&later);
    CHECK(load(&later, "other.ini", "[system]\n\nN = 12\n", &err) == HSBD_OK, "%s", err.message);
    CHECK_TEXT(hsbd_config_origin(&copy, "system", "N"), "rods.ini:2");
    CHECK_TEXT(hsbd_config_origin(&copy, "run", "dt"), "Python (keyword arguments) run.dt");
    CHECK_TEXT(hsbd_config_origin(&copy, "field", "center"), "default (L/2)");
    CHECK_TEXT(hsbd_config_origin(&later, "system", "N"), "other.ini:3");
    const char *text = hsbd_config_origin(&copy, "system", "N");
    CHECK(text >= (const char *)&copy && text < (const char *)(&copy + 1),
          "a copy's origins are its own");
    /* HSBD_ORIGIN_RING texts are valid at once */
    const char *ring[HSBD_ORIGIN_RING] = {
        hsbd_config_origin(&copy, "system", "N"), hsbd_config_origin(&copy, "run", "dt"),
        config_origin_of(&copy, "system", "N"), hsbd_config_origin(&copy, "run", "dt")};
    CHECK_TEXT(ring[0], "rods.ini:2");
    CHECK_TEXT(ring[1], "Python (keyword arguments) run.dt");
    CHECK_TEXT(ring[2], "rods.ini:2");
    CHECK_TEXT(ring[3], "Python (keyword arguments) run.dt");
}

/* Origins of HSBD_ORIGIN_MAX - 1 characters at most, cut as snprintf cuts; many distinct
 * origins fill the pool of texts without overrunning it. */
static void long_and_many_origins(void) {
    static hsbd_config cfg;
    static char origin[1500], want[HSBD_ORIGIN_MAX];
    hsbd_error err;
    const size_t lengths[] = {1090, 1095, 1499};
    for (size_t t = 0; t < 3; ++t) {
        hsbd_config_defaults(&cfg);
        memset(origin, 'o', lengths[t]);
        origin[lengths[t]] = '\0';
        CHECK(hsbd_config_set(&cfg, "run.dt=0.001", origin, &err) == HSBD_OK, "%s", err.message);
        const size_t cut = lengths[t] < sizeof want - 1 ? lengths[t] : sizeof want - 1;
        memcpy(want, origin, cut); /* what snprintf(want, HSBD_ORIGIN_MAX, "%s run.dt") keeps */
        snprintf(want + cut, sizeof want - cut, " run.dt");
        CHECK_TEXT(hsbd_config_origin(&cfg, "run", "dt"), want);
    }
    hsbd_config_defaults(&cfg);
    CHECK(hsbd_config_set(&cfg, "system.N=7", "first", &err) == HSBD_OK, "%s", err.message);
    for (int k = 0; k < 40; ++k) {
        snprintf(origin, sizeof origin, "%080d", k);
        CHECK(hsbd_config_set(&cfg, "run.dt=0.001", origin, &err) == HSBD_OK, "%s", err.message);
    }
    CHECK(cfg.origins.texts_used < HSBD_ORIGIN_TEXTS, "%u", (unsigned)cfg.origins.texts_used);
    CHECK_TEXT(hsbd_config_origin(&cfg, "system", "N"), "first system.N");
}

static void models(void) {
    static hsbd_config cfg;
    hsbd_error err;
    const char *names[] = {"rods", "spheres"};
    CHECK(config_nmodels == 2, "%zu models", config_nmodels);
    for (size_t m = 0; m < 2; ++m) {
        char set[64];
        snprintf(set, sizeof set, "system.model=%s", names[m]);
        hsbd_config_defaults(&cfg);
        CHECK(hsbd_config_set(&cfg, set, "test", &err) == HSBD_OK, "%s", err.message);
        CHECK(config_model(&cfg) == &config_models[m], "%s", names[m]);
        CHECK_TEXT(config_models[m].name, names[m]);
        CHECK(config_models[m].keys == 1u << m, "%s reads its keys", names[m]);
    }
    hsbd_config_defaults(&cfg);
    cfg.system.model = 7; /* written past the schema */
    CHECK(config_model(&cfg) == NULL, "no model 7");
    CHECK(hsbd_config_finalize(&cfg, &err) == HSBD_EINPUT, "model 7 finalised");
    CHECK_TEXT(err.message, "default: system.model = 7 is not known; allowed: one of rods|spheres");
}

int main(void) {
    models();
    file_and_set_origins();
    messages_with_origins();
    derived_origins_and_copies();
    long_and_many_origins();
    CHECK(sizeof(hsbd_origins) < ORIGINS_BOUND, "sizeof(hsbd_origins) = %zu", sizeof(hsbd_origins));
    CHECK(sizeof(hsbd_config) < CONFIG_BOUND, "sizeof(hsbd_config) = %zu", sizeof(hsbd_config));
    printf("sizeof(hsbd_config) = %zu, of its origins %zu\n", sizeof(hsbd_config),
           sizeof(hsbd_origins));
    return test_finish("test_config");
}
