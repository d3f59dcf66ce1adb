/* Disks and spheres: the distribution of the local packing fraction (local_density.tsv,
 * sample.local_density_every > 0), the usual signature of motility-induced phase
 * separation: one peak in a homogeneous fluid, a dilute and a dense one when it separates.
 * The box is cut into cells of side about sample.local_density_cell (each box length
 * divided into a whole number of them); a cell's packing fraction is the volume of the
 * particles whose centres it holds over its own. The histogram's bins are one mean particle
 * volume over a cell's wide, centred on the fractions 0, 1, 2, ... particles give, so that a
 * monodisperse system's counts fall one to a bin. P is a probability density in phi
 * (sum P dphi = 1); errors from time blocks. */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"

typedef struct local_density {
    int dimension;
    size_t cells[3], ncells, nbins;
    double side[3], cell_volume, bin; /* bin: the fraction of one mean particle */
    double *fill;                     /* per cell: the particles' volume of one sample */
    hsbd_blocks *blocks;              /* per bin: the fraction of cells in it */
} local_density;

static void release(void *state) {
    local_density *l = state;
    if (!l) return;
    free(l->fill);
    hsbd_blocks_free(l->blocks);
    free(l);
}

static double particle_volume(int dimension, double sigma) {
    const double pi = 3.14159265358979323846;
    return dimension == 3 ? pi * sigma * sigma * sigma / 6 : pi * sigma * sigma / 4;
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (cfg->sample.local_density_every <= 0) return HSBD_OK;
    const hsbd_frame *f = run_frame(r);
    local_density *l = calloc(1, sizeof *l);
    if (!l) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = l;
    l->dimension = f->dimension;
    const double want =
        cfg->sample.local_density_cell > 0 ? cfg->sample.local_density_cell : 5 * cfg->system.sigma;
    l->ncells = 1, l->cell_volume = 1;
    for (int a = 0; a < 3; ++a) {
        l->cells[a] = a < f->dimension ? (size_t)fmax(1.0, round(f->box[a] / want)) : 1;
        l->side[a] = a < f->dimension ? f->box[a] / (double)l->cells[a] : 1;
        l->ncells *= l->cells[a];
        if (a < f->dimension) l->cell_volume *= l->side[a];
    }
    double mean = 0;
    for (size_t i = 0; i < f->n; ++i)
        mean += particle_volume(f->dimension, f->diameter[i]) / (double)f->n;
    l->bin = mean / l->cell_volume;
    /* up to close packing and beyond: a cell may hold a few centres more than it can hold */
    l->nbins = (size_t)ceil(1.0 / l->bin) + 2;
    if (l->ncells > 100000000 || l->nbins > 100000)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.local_density_cell = %g gives %zu cells of %zu bins; "
                              "allowed: at most 1e8 cells and 1e5 bins",
                              hsbd_config_origin(cfg, "sample", "local_density_cell"), want,
                              l->ncells, l->nbins);
    l->fill = malloc(l->ncells * sizeof *l->fill);
    l->blocks =
        hsbd_blocks_alloc(l->nbins, (size_t)cfg->sample.blocks,
                          hsbd_config_steps(cfg) / (uint64_t)cfg->sample.local_density_every);
    return l->fill && l->blocks ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
}

static uint64_t every(const run *r) {
    return (uint64_t)r->cfg->sample.local_density_every;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    local_density *l = state;
    const hsbd_frame *f = run_frame(r);
    for (size_t c = 0; c < l->ncells; ++c)
        l->fill[c] = 0;
    for (size_t i = 0; i < f->n; ++i) {
        size_t c = 0;
        for (int a = f->dimension - 1; a >= 0; --a) {
            size_t k = (size_t)(f->x[3 * i + a] / l->side[a]); /* x in [0, box] */
            if (k >= l->cells[a]) k = l->cells[a] - 1;
            c = c * l->cells[a] + k;
        }
        l->fill[c] += particle_volume(f->dimension, f->diameter[i]);
    }
    double *acc = hsbd_blocks_acc(l->blocks);
    for (size_t c = 0; c < l->ncells; ++c) {
        size_t b = (size_t)floor(l->fill[c] / l->cell_volume / l->bin + 0.5);
        if (b >= l->nbins) b = l->nbins - 1;
        acc[b] += 1.0 / (double)l->ncells;
    }
    hsbd_blocks_end_sample(l->blocks);
    return HSBD_OK;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const local_density *l = state;
    double *phi = malloc(l->nbins * sizeof *phi), *val = malloc(2 * l->nbins * sizeof *val);
    if (!phi || !val)
        return free(phi), free(val), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    hsbd_blocks_result(l->blocks, val, val + l->nbins);
    for (size_t b = 0; b < l->nbins; ++b)
        phi[b] = (double)b * l->bin, val[b] /= l->bin, val[l->nbins + b] /= l->bin;
    char what[400], size[96];
    if (l->dimension == 3)
        snprintf(size, sizeof size, "%.6g x %.6g x %.6g", l->side[0], l->side[1], l->side[2]);
    else
        snprintf(size, sizeof size, "%.6g x %.6g", l->side[0], l->side[1]);
    snprintf(what, sizeof what,
             "distribution P(phi) of the local packing fraction over %zu cells of %s (the "
             "particles' volume whose centres a cell holds over its own; bins of one mean "
             "particle, %.6g, centred on its multiples); errors from time blocks",
             l->ncells, size, l->bin);
    const int rc = hsbd_write_columns_table(r->cfg->output.dir, "local_density.tsv", r->cfg, what,
                                            "phi\tP\tP_err", l->nbins, phi, 1, val, err);
    free(phi), free(val);
    return rc;
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_blocks_save(((const local_density *)state)->blocks, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_blocks_load(((local_density *)state)->blocks, rd);
}

const run_observer_ops run_observe_local_density = {.name = "local density",
                                                    .build = build,
                                                    .every = every,
                                                    .sample = sample,
                                                    .save = save,
                                                    .load = load,
                                                    .write_tables = write_tables,
                                                    .free = release};
