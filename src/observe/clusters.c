/* Cluster diagnostics: size histogram of touching clusters at the end of sampled steps,
 * number-mean cluster size, and merge events per step (fragments - final clusters). */
#include <stdlib.h>

#include "hsbd/observe.h"
#include "observe/checkpoint.h"

struct hsbd_clusters {
    size_t n;
    double *hist; /* clusters of each size, summed over samples */
    double total;
    hsbd_blocks *means; /* [mean cluster size, merges in the step] */
};

hsbd_clusters *hsbd_clusters_alloc(size_t n, size_t nblocks, uint64_t nsamples_total) {
    hsbd_clusters *c = calloc(1, sizeof *c);
    if (!c) return NULL;
    c->n = n;
    c->hist = calloc(n + 1, sizeof *c->hist);
    c->means = hsbd_blocks_alloc(2, nblocks, nsamples_total);
    if (!c->hist || !c->means) {
        hsbd_clusters_free(c);
        return NULL;
    }
    return c;
}

void hsbd_clusters_free(hsbd_clusters *c) {
    if (!c) return;
    free(c->hist);
    hsbd_blocks_free(c->means);
    free(c);
}

void hsbd_clusters_sample(hsbd_clusters *c, const hsbd_rods *rods, const hsbd_rods_step_stats *st) {
    const size_t nc = hsbd_rods_cluster_count(rods);
    for (size_t k = 0; k < nc; ++k)
        c->hist[hsbd_rods_cluster_size(rods, k)] += 1.0;
    c->total += (double)nc;
    double *acc = hsbd_blocks_acc(c->means);
    acc[0] += nc ? (double)c->n / (double)nc : 0.0;
    acc[1] += (double)st->fragments - (double)st->clusters_end;
    hsbd_blocks_end_sample(c->means);
}

double hsbd_clusters_size_fraction(const hsbd_clusters *c, size_t s) {
    return c->total > 0 ? c->hist[s] / c->total : 0.0;
}

size_t hsbd_clusters_max_size(const hsbd_clusters *c) {
    size_t m = 0;
    for (size_t s = 1; s <= c->n; ++s)
        if (c->hist[s] > 0) m = s;
    return m;
}

void hsbd_clusters_means(const hsbd_clusters *c, double *mean_size, double *mean_size_err,
                         double *merges_per_step, double *merges_err) {
    double mean[2], err[2];
    hsbd_blocks_result(c->means, mean, err);
    *mean_size = mean[0], *mean_size_err = err[0];
    *merges_per_step = mean[1], *merges_err = err[1];
}

/* ---- checkpoints ---- */
void hsbd_clusters_save(const hsbd_clusters *c, hsbd_writer *w) {
    hsbd_put_tag(w, "clusters");
    hsbd_put_f64s(w, c->hist, c->n + 1);
    hsbd_put_f64(w, c->total);
    hsbd_blocks_save(c->means, w);
}

int hsbd_clusters_load(hsbd_clusters *c, hsbd_reader *r) {
    if (hsbd_get_tag(r, "clusters") || hsbd_get_f64s(r, c->hist, c->n + 1) ||
        hsbd_get_f64(r, &c->total))
        return -1;
    return hsbd_blocks_load(c->means, r);
}
