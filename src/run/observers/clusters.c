/* Rods: clusters of touching rods at the sampled step ends (clusters.tsv: their sizes;
 * summary: the mean cluster size and the merge events per step of the sampled steps). */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/rods_model.h"

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    *state = hsbd_clusters_alloc((size_t)cfg->system.n, (size_t)cfg->sample.blocks, samples);
    return *state ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    const rods_model *m = rods_model_of(r);
    if (r->cfg->system.hard_core) hsbd_clusters_sample(state, m->rods, &m->stats);
    return HSBD_OK;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    if (!r->cfg->system.hard_core) return HSBD_OK;
    const size_t maxs = hsbd_clusters_max_size(state);
    double *fraction = malloc((maxs ? maxs : 1) * sizeof *fraction);
    if (!fraction) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing clusters.tsv");
    for (size_t k = 1; k <= maxs; ++k)
        fraction[k - 1] = hsbd_clusters_size_fraction(state, k);
    const int rc = hsbd_write_sizes_table(r->cfg->output.dir, "clusters.tsv", r->cfg,
                                          "sizes of clusters of touching rods at sampled step ends",
                                          maxs, fraction, err);
    free(fraction);
    return rc;
}

static void write_summary(const run *r, const void *state, FILE *f) {
    double mean_size = NAN, mean_size_err = NAN, merges = NAN, merges_err = NAN;
    if (r->cfg->system.hard_core)
        hsbd_clusters_means(state, &mean_size, &mean_size_err, &merges, &merges_err);
    hsbd_json_number(f, "merge_events_per_step", merges, 1);
    hsbd_json_number(f, "merge_events_per_step_err", merges_err, 1);
    hsbd_json_number(f, "mean_cluster_size", mean_size, 1);
    hsbd_json_number(f, "mean_cluster_size_err", mean_size_err, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_clusters_save(state, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_clusters_load(state, rd);
}

static void release(void *state) {
    hsbd_clusters_free(state);
}

const run_observer_ops run_observe_clusters = {.name = "clusters",
                                               .build = build,
                                               .sample = sample,
                                               .save = save,
                                               .load = load,
                                               .write_tables = write_tables,
                                               .write_summary = write_summary,
                                               .free = release};
