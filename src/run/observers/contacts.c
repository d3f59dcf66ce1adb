/* Rods: the contact density per ordered species pair (contact theorem) and, between walls,
 * at each wall's contact (summary "contacts"). */
#include <math.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/rods_model.h"

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (!cfg->system.hard_core) return HSBD_OK;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    *state = hsbd_contacts_alloc((size_t)cfg->system.n, cfg->species.n, (size_t)cfg->sample.blocks,
                                 samples, err);
    return *state ? HSBD_OK : err->status;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    const hsbd_rods_view v = hsbd_rods_get_view(rods_model_of(r)->rods);
    hsbd_contacts_sample(state, &v);
    return HSBD_OK;
}

/* contact densities per ordered species pair and at the walls, with block-average errors */
static void write_summary(const run *r, const void *state, FILE *f) {
    const hsbd_config *cfg = r->cfg;
    if (r->steps_done < (uint64_t)cfg->sample.every) return; /* no sample yet */
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    fprintf(f, "  \"contacts\": {\n    \"pairs\": [");
    for (size_t a = 0; a < ns; ++a)
        for (size_t b = 0; b < ns; ++b) {
            double val, err;
            hsbd_contacts_pair(state, a, b, &val, &err);
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
            hsbd_contacts_wall(state, right, &val, &err);
            fprintf(f, ",\n    \"wall_%s\": %.10g,\n    \"wall_%s_err\": %.4g",
                    right ? "right" : "left", val, right ? "right" : "left",
                    isfinite(err) ? err : 0);
        }
    fprintf(f, "\n  },\n");
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_contacts_save(state, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_contacts_load(state, rd);
}

static void release(void *state) {
    hsbd_contacts_free(state);
}

const run_observer_ops run_observe_contacts = {.name = "contacts",
                                               .build = build,
                                               .sample = sample,
                                               .save = save,
                                               .load = load,
                                               .write_summary = write_summary,
                                               .free = release};
