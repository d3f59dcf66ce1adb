/* Disks and spheres between walls or in a field: the density profile along one axis per
 * species (folded into a period), and at each wall of that axis the density of the
 * particles' gaps to it near contact, extrapolated to zero gap (docs/observables.md). Block
 * averages over time give the errors. */
#include <math.h>
#include <stdlib.h>

#include "hsbd/observe.h"

enum { GAP_BINS = 4 }; /* sub-windows of the contact window, as for rods (Eq. 26) */

struct hsbd_slab {
    int axis, walls;
    size_t ns, bins;
    double period, width, window, cross_area, folds;
    hsbd_blocks *blocks; /* per sample: bins x ns counts, then 2 sides x ns x GAP_BINS */
};

hsbd_slab *hsbd_slab_alloc(const hsbd_spheres_view *v, int axis, double period, double bin_width,
                           double contact_window, size_t nblocks, uint64_t nsamples_total,
                           hsbd_error *err) {
    const double length = v->box[axis];
    if (axis < 0 || axis >= v->dimension || !(period > 0) || !(period <= length) ||
        !(bin_width > 0) || !(contact_window > 0)) {
        hsbd_error_set(err, HSBD_EINPUT, "slab profile: axis %d, period %g, bin width %g", axis,
                       period, bin_width);
        return NULL;
    }
    hsbd_slab *p = calloc(1, sizeof *p);
    if (!p) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory"), NULL;
    p->axis = axis;
    p->walls = v->walls[axis];
    p->ns = v->nspecies ? v->nspecies : 1;
    p->period = period;
    p->bins = (size_t)ceil(period / bin_width - 1e-9); /* the bins fill the period */
    p->width = period / (double)p->bins;
    p->window = contact_window;
    p->folds = length / period;
    p->cross_area = 1;
    for (int a = 0; a < v->dimension; ++a)
        if (a != axis) p->cross_area *= v->box[a];
    p->blocks = hsbd_blocks_alloc(p->bins * p->ns + 2 * GAP_BINS * p->ns, nblocks, nsamples_total);
    if (!p->blocks) {
        free(p);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the density profile"), NULL;
    }
    return p;
}

void hsbd_slab_free(hsbd_slab *p) {
    if (!p) return;
    hsbd_blocks_free(p->blocks);
    free(p);
}

size_t hsbd_slab_bins(const hsbd_slab *p) {
    return p->bins;
}

hsbd_blocks *hsbd_slab_blocks(hsbd_slab *p) {
    return p->blocks;
}

void hsbd_slab_sample(hsbd_slab *p, const hsbd_spheres_view *v) {
    double *acc = hsbd_blocks_acc(p->blocks), *gaps = acc + p->bins * p->ns;
    const double gap_width = p->window / GAP_BINS;
    for (size_t i = 0; i < v->n; ++i) {
        const size_t k = (size_t)v->species[i];
        const double x = v->x[3 * i + (size_t)p->axis];
        double folded = x - p->period * floor(x / p->period);
        size_t b = (size_t)(folded / p->width);
        acc[(b < p->bins ? b : p->bins - 1) * p->ns + k] += 1;
        if (!p->walls) continue;
        const double half = 0.5 * v->sigma[i];
        const double gap[2] = {x - half, v->box[p->axis] - half - x};
        for (int side = 0; side < 2; ++side)
            if (gap[side] < p->window) {
                const size_t g = (size_t)fmax(0.0, floor(gap[side] / gap_width));
                gaps[((size_t)side * p->ns + k) * GAP_BINS + (g < GAP_BINS ? g : GAP_BINS - 1)] +=
                    1;
            }
    }
    hsbd_blocks_end_sample(p->blocks);
}

/* number density per count and sample in a bin of this width */
static double density_per_count(const hsbd_slab *p, double width) {
    return 1.0 / (width * p->cross_area * p->folds);
}

void hsbd_slab_density(const hsbd_slab *p, int species, double *x, double *rho, double *err) {
    const size_t nv = p->bins * p->ns + 2 * GAP_BINS * p->ns;
    double *mean = malloc(2 * nv * sizeof *mean), *e = mean ? mean + nv : NULL;
    for (size_t b = 0; b < p->bins; ++b)
        x[b] = ((double)b + 0.5) * p->width, rho[b] = err[b] = NAN;
    if (!mean) return;
    const size_t used = hsbd_blocks_result(p->blocks, mean, e);
    (void)used;
    const double c = density_per_count(p, p->width);
    for (size_t b = 0; b < p->bins; ++b) {
        double r = 0, v = 0;
        for (size_t k = 0; k < p->ns; ++k)
            if (species < 0 || (size_t)species == k)
                r += mean[b * p->ns + k], v += e[b * p->ns + k] * e[b * p->ns + k];
        rho[b] = c * r;
        err[b] = c * sqrt(v); /* species counted as independent in a sum */
    }
    free(mean);
}

/* intercept at zero gap of the least-squares line through the sub-windows' densities */
static double extrapolate_to_contact(const double *count, double gap_width, double per_count) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int g = 0; g < GAP_BINS; ++g) {
        const double xg = (g + 0.5) * gap_width, y = count[g] * per_count;
        sx += xg, sy += y, sxx += xg * xg, sxy += xg * y;
    }
    const double n = GAP_BINS, slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    return (sy - slope * sx) / n;
}

void hsbd_slab_wall_contact(const hsbd_slab *p, int side, int species, double *value, double *err) {
    *value = *err = NAN;
    if (!p->walls) return;
    const size_t nv = p->bins * p->ns + 2 * GAP_BINS * p->ns, nb = hsbd_blocks_count(p->blocks);
    double *rows = malloc(nb * nv * sizeof *rows);
    if (!rows) return;
    hsbd_blocks_block_means(p->blocks, 0, rows);
    const double gap_width = p->window / GAP_BINS;
    const double per_count = 1.0 / (gap_width * p->cross_area);
    double sum = 0, sum2 = 0;
    size_t used = 0;
    for (size_t blk = 0; blk < nb; ++blk) {
        const double *gaps = rows + blk * nv + p->bins * p->ns;
        if (isnan(gaps[0])) continue;
        double c[GAP_BINS] = {0};
        for (size_t k = 0; k < p->ns; ++k)
            if (species < 0 || (size_t)species == k)
                for (int g = 0; g < GAP_BINS; ++g)
                    c[g] += gaps[((size_t)side * p->ns + k) * GAP_BINS + (size_t)g];
        const double v = extrapolate_to_contact(c, gap_width, per_count);
        sum += v, sum2 += v * v, used++;
    }
    free(rows);
    if (used < 2) return;
    *value = sum / (double)used;
    *err = sqrt(fmax(0.0, sum2 / (double)used - *value * *value) / (double)(used - 1));
}
