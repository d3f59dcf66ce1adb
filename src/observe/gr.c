/* Radial distribution functions g_ab(r) of disks / spheres per unordered species pair,
 * and their contact values g_ab(sigma_ab+) extrapolated from a fine histogram of the
 * surface gaps r - sigma_ij in [0, contact_fit): a least-squares quadratic in the gap,
 * evaluated at zero gap. Each pair enters the gap histogram with weight sigma_ij, so the
 * extrapolated value is exact for the virial route even when sizes vary within a species
 * (polydispersity): Z = 1 + sum_ab C_ab g_ab (hsbd_gr_contact_weight), and g_ab is the
 * mean of the pairs' contact values weighted by sigma_ij^d. Errors from block averages
 * (time blocks); the extrapolation is linear in the counts, so it is applied to every
 * block's histogram and the blocks' scatter gives its error. Pairs are found with a cell
 * grid of width >= r_max.
 *
 * Between walls (one walls axis z, the others periodic: a slab) the density varies along z
 * and the ideal-gas reference follows it: the particles of each species are counted in
 * thin bins along z (the sampled profile, over the whole run), and the expected number of
 * pairs in an r bin is the sum over pairs of bins (k, k + dk) of <n_a(k)> <n_b(k + dk)>
 * (times (N_a - 1) / N_a for a = b, the canonical count of distinct pairs) times the chance
 * that two independent particles, uniform in their bins and over the periodic area A, are
 * that far apart: W(dk, r bin) / A, W the area of the transverse annulus averaged over the
 * triangular law of the z difference. This is the exact pair count of independent
 * particles with that profile (up to the density's variation inside a z bin, second order
 * in its width): g = 1 for ideal particles between walls in any field, and for a fluid
 * g(r1, r2) = rho2 / (rho(z1) rho(z2)) averaged over the pairs. (The pairs of each sample's
 * own z coordinates would not do: hard spheres close in z are rarely close across, and that
 * reference is then short by O(sigma^2 / A), 3 % in a 6 x 6 slit. Nor would each block's
 * own profile: a particle that stays in one well of a field for a block makes the product
 * of the block's profiles count its own time average, and the same-species reference was
 * 0.3-0.7 % high with N_a = 150.) The error bars come from the scatter of the blocks'
 * ratios of pairs to their own profile's reference, which cancels the profile's slow
 * fluctuations that the pair counts share. Optionally only pairs with both centres in a
 * window along z count (hsbd_gr_set_window), e.g. the middle of a slit. The same reference
 * serves a periodic axis along which a field modulates the density
 * (hsbd_gr_alloc_profile): z differences are then minimum images, and the number of z
 * bins is odd so that every pair of bins has one nearest distance below half the length
 * (exact for r below half the length minus a z bin). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/cellgrid.h"
#include "core/periodic.h"
#include "hsbd/observe.h"
#include "observe/checkpoint.h"

enum { GR_FIT_BINS = 10, GR_Z_BINS_PER_R_BIN = 2 };
static const double HSBD_PI = 3.14159265358979323846;

struct hsbd_gr {
    size_t n, nspecies, npairs, bins;
    int dim;
    double box[3], volume, r_max, width, fit_width;
    double *expected; /* npairs x (bins + GR_FIT_BINS): ideal-gas counts per sample */
    double *weight;   /* npairs: C_ab of Z = 1 + sum_ab C_ab g_ab */
    hsbd_blocks *blocks;
    size_t nblocks;
    hsbd_cells cells;
    double *acc;       /* counts of the current sample */
    double *results;   /* 2 nv: the blocks' means and errors (results allocate nothing) */
    double *per_block; /* nblocks x nv: each block's means */
    /* a slab (zaxis >= 0): the counts per species and z bin follow the pair counts in the
     * blocks; shift_weight (npairs x nshift x row) turns the products of two profiles at
     * z-bin distance dk into the reference of each bin */
    int zaxis, zperiodic;
    double wrap[3]; /* minimum images over these lengths (infinite along a walls axis) */
    size_t nz, nshift, zlo, zhi, nv;
    double hz, area;
    int contact_ok;       /* one size per species: the gap bins' reference is exact */
    double members[64];   /* N_a */
    double *shift_weight; /* npairs x nshift x row */
    double *products;     /* nshift: one block's profile products per z-bin distance */
    double *reference;    /* row: one block's reference (results allocate nothing) */
};

static size_t pair_index(size_t ns, size_t a, size_t b) {
    if (a > b) {
        const size_t t = a;
        a = b, b = t;
    }
    return a * ns - a * (a - 1) / 2 + (b - a); /* row a of the upper triangle */
}

void hsbd_gr_pair_species(const hsbd_gr *g, size_t pair, size_t *a, size_t *b) {
    for (size_t p = 0; p < g->nspecies; ++p)
        for (size_t q = p; q < g->nspecies; ++q)
            if (pair_index(g->nspecies, p, q) == pair) {
                *a = p, *b = q;
                return;
            }
}

/* volume (3D) or area (2D) of the shell r0 < r < r1 */
static double shell_volume(int dim, double r0, double r1) {
    if (dim == 3) return 4.0 / 3.0 * HSBD_PI * (r1 * r1 * r1 - r0 * r0 * r0);
    return HSBD_PI * (r1 * r1 - r0 * r0);
}

void hsbd_gr_free(hsbd_gr *g) {
    if (!g) return;
    free(g->products);
    free(g->shift_weight);
    free(g->reference);
    free(g->weight);
    free(g->expected);
    free(g->acc);
    free(g->results);
    free(g->per_block);
    hsbd_blocks_free(g->blocks);
    hsbd_cells_free(&g->cells);
    free(g);
}

/* Sum of s_ij^m over the pairs of species a and b, s_ij = (sigma_i + sigma_j)/2, from the
 * species' power sums pa[k] = sum sigma^k: binomial expansion over ordered pairs, halved
 * without the self pairs when a = b. */
static double pair_power_sum(int m, const double *pa, const double *pb, int same) {
    static const double binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    double ordered = 0;
    for (int k = 0; k <= m; ++k)
        ordered += binom[m][k] * pa[k] * pb[m - k];
    ordered /= (double)(1 << m);
    return same ? 0.5 * (ordered - pa[m]) : ordered;
}

/* Ideal-gas counts of pair (a, b) per sample: r bins, and the sigma_ij-weighted gap bins
 * (shell of gaps [lo, hi) at contact distance s: 3D (4 pi/3)(3 s^2 D1 + 3 s D2 + D3),
 * 2D pi (2 s D1 + D2), D_m = hi^m - lo^m); the Z weight C_ab = S_d sum s^d / (V d N). */
static void expect_pairs(hsbd_gr *g, size_t a, size_t b, const double *pa, const double *pb) {
    const size_t row = g->bins + GR_FIT_BINS;
    double *e = g->expected + pair_index(g->nspecies, a, b) * row;
    const int same = a == b;
    const double pairs = pair_power_sum(0, pa, pb, same) / g->volume;
    for (size_t k = 0; k < g->bins; ++k)
        e[k] = pairs * shell_volume(g->dim, (double)k * g->width, (double)(k + 1) * g->width);
    double sm[4];
    for (int m = 0; m < 4; ++m)
        sm[m] = pair_power_sum(m, pa, pb, same) / g->volume;
    const double h = g->fit_width / GR_FIT_BINS;
    for (size_t k = 0; k < GR_FIT_BINS; ++k) {
        const double lo = (double)k * h, hi = lo + h, d1 = hi - lo, d2 = hi * hi - lo * lo,
                     d3 = hi * hi * hi - lo * lo * lo;
        e[g->bins + k] = g->dim == 3
                             ? 4.0 / 3.0 * HSBD_PI * (3 * sm[3] * d1 + 3 * sm[2] * d2 + sm[1] * d3)
                             : HSBD_PI * (2 * sm[2] * d1 + sm[1] * d2);
    }
    const double surface = g->dim == 3 ? 4 * HSBD_PI : 2 * HSBD_PI;
    g->weight[pair_index(g->nspecies, a, b)] =
        surface * sm[g->dim] / ((double)g->dim * (double)g->n);
}

/* Transverse measure (3D: area, 2D: length) of the points at distance in [lo, hi) from a
 * point at height difference u: the annulus between the circles of radius
 * sqrt(lo^2 - u^2) and sqrt(hi^2 - u^2) */
static double transverse_measure(int dim, double u, double lo, double hi) {
    const double a = fmax(0.0, hi * hi - u * u), b = fmax(0.0, lo * lo - u * u);
    return dim == 3 ? HSBD_PI * (a - b) : 2 * (sqrt(a) - sqrt(b));
}

/* The transverse measure averaged over the z difference of two points uniform in bins dk
 * apart (width h): a triangle of half-width h about dk h. Gauss-Legendre (8 nodes) between
 * the kinks (the triangle's ends and peak, +-lo, +-hi): exact for the 3D polynomials. */
static double shift_average(int dim, size_t dk, double h, double lo, double hi) {
    static const double x8[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                 0.9602898564975363};
    static const double w8[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                 0.1012285362903763};
    const double c = (double)dk * h;
    double cut[7] = {c - h, c, c + h, lo, hi, -lo, -hi};
    int n = 0;
    double pts[7];
    for (int k = 0; k < 7; ++k)
        if (cut[k] >= c - h && cut[k] <= c + h) pts[n++] = cut[k];
    for (int i = 1; i < n; ++i) /* insertion sort of at most 7 points */
        for (int j = i; j > 0 && pts[j - 1] > pts[j]; --j) {
            const double t = pts[j];
            pts[j] = pts[j - 1], pts[j - 1] = t;
        }
    double sum = 0;
    for (int p = 0; p + 1 < n; ++p) {
        const double m = 0.5 * (pts[p] + pts[p + 1]), half = 0.5 * (pts[p + 1] - pts[p]);
        for (int q = 0; q < 8; ++q) {
            const double u = m + (q < 4 ? -1 : 1) * half * x8[q % 4];
            const double tri = (1 - fabs(u - c) / h) / h;
            sum += half * w8[q % 4] * tri * transverse_measure(dim, u, lo, hi);
        }
    }
    return sum;
}

/* The slab's weights: shift_weight[pair][dk][k] = W(dk, bin k) / A, the gap bins of pair
 * (a, b) at their contact distance sigma_ab and weighted by it as the counts are. */
static int slab_setup(hsbd_gr *g, const hsbd_spheres_view *v, int zaxis) {
    const size_t row = g->bins + GR_FIT_BINS;
    g->zaxis = zaxis;
    g->zperiodic = !v->walls[zaxis];
    g->nz = (size_t)ceil(GR_Z_BINS_PER_R_BIN * v->box[zaxis] / g->width - 1e-9);
    if (g->zperiodic && g->nz % 2 == 0) g->nz++;
    g->hz = v->box[zaxis] / (double)g->nz;
    g->zlo = 0, g->zhi = g->nz;
    g->area = 1;
    for (int a = 0; a < g->dim; ++a)
        if (a != zaxis) g->area *= v->box[a];
    g->wrap[zaxis] = g->zperiodic ? v->box[zaxis] : INFINITY;
    double smax = 0, sig[64];
    g->contact_ok = 1;
    for (size_t k = 0; k < g->nspecies; ++k)
        sig[k] = NAN;
    for (size_t i = 0; i < v->n; ++i) {
        const size_t k = (size_t)v->species[i];
        g->members[k] += 1;
        if (isnan(sig[k])) sig[k] = v->sigma[i];
        g->contact_ok &= sig[k] == v->sigma[i];
        smax = fmax(smax, v->sigma[i]);
    }
    const double reach = fmax(g->r_max, smax + g->fit_width);
    g->nshift = (size_t)ceil(reach / g->hz) + 2;
    if (g->nshift > g->nz) g->nshift = g->nz;
    if (g->zperiodic && g->nshift > (g->nz + 1) / 2) g->nshift = (g->nz + 1) / 2;
    g->products = malloc(g->nshift * sizeof *g->products);
    g->shift_weight = calloc(g->npairs * g->nshift * row, sizeof *g->shift_weight);
    g->reference = malloc(row * sizeof *g->reference);
    if (!g->products || !g->shift_weight || !g->reference) return -1;
    const double h = g->fit_width / GR_FIT_BINS;
    for (size_t a = 0; a < g->nspecies; ++a)
        for (size_t b = a; b < g->nspecies; ++b) {
            double *w = g->shift_weight + pair_index(g->nspecies, a, b) * g->nshift * row;
            const double sab = 0.5 * (sig[a] + sig[b]);
            for (size_t dk = 0; dk < g->nshift; ++dk) {
                for (size_t k = 0; k < g->bins; ++k)
                    w[dk * row + k] = shift_average(g->dim, dk, g->hz, (double)k * g->width,
                                                    (double)(k + 1) * g->width) /
                                      g->area;
                for (size_t k = 0; k < GR_FIT_BINS && isfinite(sab); ++k)
                    w[dk * row + g->bins + k] =
                        sab *
                        shift_average(g->dim, dk, g->hz, sab + (double)k * h,
                                      sab + (double)(k + 1) * h) /
                        g->area;
            }
        }
    return 0;
}

hsbd_gr *hsbd_gr_alloc(const hsbd_spheres_view *v, double r_max, double width, double fit_width,
                       size_t nblocks, uint64_t nsamples_total, hsbd_error *err) {
    int zaxis = -1;
    for (int a = 0; a < v->dimension; ++a)
        if (v->walls[a] && zaxis < 0) zaxis = a;
    return hsbd_gr_alloc_profile(v, zaxis, r_max, width, fit_width, nblocks, nsamples_total, err);
}

hsbd_gr *hsbd_gr_alloc_profile(const hsbd_spheres_view *v, int zaxis, double r_max, double width,
                               double fit_width, size_t nblocks, uint64_t nsamples_total,
                               hsbd_error *err) {
    double half_box = INFINITY;
    int nwalls = 0;
    for (int a = 0; a < v->dimension; ++a) {
        nwalls += v->walls[a] != 0;
        if (!v->walls[a]) half_box = fmin(half_box, 0.5 * v->box[a]);
    }
    if (zaxis >= v->dimension || nwalls > 1 || (nwalls && (zaxis < 0 || !v->walls[zaxis])))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "g(r): walls on %d axes, profile axis %d; allowed: a periodic box "
                              "(any profile axis) or walls on one axis (the profile axis)",
                              nwalls, zaxis),
               NULL;
    if (!(r_max > 0) || r_max > half_box || !(width > 0) || width > r_max || !(fit_width > 0))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "g(r): r_max = %g, bin %g, contact fit %g; allowed: 0 < bin <= "
                              "r_max <= half the shortest periodic box length (%g), fit > 0",
                              r_max, width, fit_width, half_box),
               NULL;
    hsbd_gr *g = calloc(1, sizeof *g);
    if (!g) return hsbd_error_set(err, HSBD_ENOMEM, "g(r): out of memory"), NULL;
    g->n = v->n;
    g->dim = v->dimension;
    g->nspecies = v->nspecies;
    g->npairs = g->nspecies * (g->nspecies + 1) / 2;
    g->bins = (size_t)ceil(r_max / width - 1e-9);
    g->width = width;
    g->r_max = (double)g->bins * width;
    if (g->r_max > half_box) g->bins--, g->r_max -= width;
    g->fit_width = fit_width;
    g->volume = 1;
    g->zaxis = -1;
    for (int a = 0; a < 3; ++a)
        g->box[a] = g->wrap[a] = v->box[a], g->volume *= a < g->dim ? v->box[a] : 1.0;
    const size_t row = g->bins + GR_FIT_BINS;
    if (g->nspecies > 64) {
        hsbd_gr_free(g);
        return hsbd_error_set(err, HSBD_EINPUT, "g(r): at most 64 species"), NULL;
    }
    if (zaxis >= 0 && slab_setup(g, v, zaxis)) {
        hsbd_gr_free(g);
        return hsbd_error_set(err, HSBD_ENOMEM, "g(r): out of memory"), NULL;
    }
    g->nv = g->npairs * row + (zaxis >= 0 ? g->nspecies * g->nz : 0);
    g->weight = calloc(g->npairs, sizeof *g->weight);
    g->expected = calloc(g->npairs * row, sizeof *g->expected);
    g->acc = calloc(g->nv, sizeof *g->acc);
    g->results = malloc(2 * g->nv * sizeof *g->results);
    g->per_block = malloc(nblocks * g->nv * sizeof *g->per_block);
    g->blocks = hsbd_blocks_alloc(g->nv, nblocks, nsamples_total);
    g->nblocks = nblocks;
    if (!g->weight || !g->expected || !g->acc || !g->results || !g->per_block || !g->blocks ||
        hsbd_cells_init(&g->cells, g->dim, g->box, g->r_max, g->n)) {
        hsbd_gr_free(g);
        return hsbd_error_set(err, HSBD_ENOMEM, "g(r): out of memory"), NULL;
    }
    double power[64][4] = {{0}}; /* sum over the members of sigma^m, m = 0..3 */
    for (size_t i = 0; i < v->n; ++i)
        for (int m = 0, sp = v->species[i]; m < 4; ++m)
            power[sp][m] += pow(v->sigma[i], m);
    for (size_t a = 0; a < g->nspecies; ++a)
        for (size_t b = a; b < g->nspecies; ++b)
            expect_pairs(g, a, b, power[a], power[b]);
    return g;
}

int hsbd_gr_set_window(hsbd_gr *g, double lo, double hi, hsbd_error *err) {
    if (g->zaxis < 0 || g->zperiodic || hsbd_blocks_samples(g->blocks) > 0 || !(lo >= 0) ||
        !(hi <= (double)g->nz * g->hz) || !(hi - lo >= g->hz))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "g(r) window [%g, %g]: allowed between walls, before sampling, "
                              "0 <= lo < hi <= %g",
                              lo, hi, (double)g->nz * g->hz);
    g->zlo = (size_t)llround(lo / g->hz);
    g->zhi = (size_t)llround(hi / g->hz);
    return HSBD_OK;
}

/* the z bin of a centre, or nz when outside the window */
static size_t z_bin(const hsbd_gr *g, double z) {
    const long k = (long)floor(z / g->hz);
    return k >= (long)g->zlo && k < (long)g->zhi ? (size_t)k : g->nz;
}

int hsbd_gr_sample(hsbd_gr *g, const hsbd_spheres_view *v) {
    const size_t row = g->bins + GR_FIT_BINS;
    memset(g->acc, 0, g->nv * sizeof *g->acc);
    hsbd_cells_clear(&g->cells);
    for (size_t i = 0; i < g->n; ++i)
        if ((g->zaxis < 0 || z_bin(g, v->x[3 * i + g->zaxis]) < g->nz) &&
            hsbd_cells_insert(&g->cells, (int32_t)i, v->x + 3 * i))
            return HSBD_ENOMEM;
    const double rmax2 = g->r_max * g->r_max, inv_w = 1.0 / g->width;
    const double h_inv = GR_FIT_BINS / g->fit_width;
    /* cell by cell: the cells around are the same for all of a cell's points, and the
     * positions are read from the cells' own contiguous slots, not by particle index
     * (which at large N is a cache miss per pair) */
    const hsbd_cells *cells = &g->cells;
    for (size_t c = 0; c < cells->ncells; ++c) {
        const uint32_t nin = hsbd_cells_count(cells, (int32_t)c);
        if (!nin) continue;
        int32_t around[27];
        const int nc = hsbd_cells_around(cells, hsbd_cells_position(cells, (int32_t)c, 0), around);
        for (uint32_t p = 0; p < nin; ++p) {
            const int32_t i = hsbd_cells_id(cells, (int32_t)c, p);
            const double *xi = hsbd_cells_position(cells, (int32_t)c, p);
            const size_t si = (size_t)v->species[i];
            for (int q = 0; q < nc; ++q) {
                const uint32_t cnt = hsbd_cells_count(cells, around[q]);
                for (uint32_t u = 0; u < cnt; ++u) {
                    const int32_t j = hsbd_cells_id(cells, around[q], u);
                    if (j <= i) continue;
                    const double *xj = hsbd_cells_position(cells, around[q], u);
                    double r2 = 0;
                    for (int a = 0; a < g->dim; ++a) {
                        const double d = hsbd_wrap_delta(xj[a] - xi[a], g->wrap[a]);
                        r2 += d * d;
                    }
                    if (r2 >= rmax2) continue;
                    const double r = sqrt(r2);
                    double *acc = g->acc + pair_index(g->nspecies, si, (size_t)v->species[j]) * row;
                    const size_t k = (size_t)(r * inv_w);
                    if (k < g->bins) acc[k] += 1;
                    const double sij = 0.5 * (v->sigma[i] + v->sigma[j]), gap = r - sij;
                    if (gap >= 0 && gap < g->fit_width) {
                        const size_t f = (size_t)(gap * h_inv);
                        acc[g->bins + (f < GR_FIT_BINS ? f : GR_FIT_BINS - 1)] += sij;
                    }
                }
            }
        }
    }
    for (size_t i = 0; i < g->n && g->zaxis >= 0; ++i) { /* the profile of each species */
        const size_t k = z_bin(g, v->x[3 * i + g->zaxis]);
        if (k < g->nz) g->acc[g->npairs * row + (size_t)v->species[i] * g->nz + k] += 1;
    }
    double *b = hsbd_blocks_acc(g->blocks);
    for (size_t k = 0; k < g->nv; ++k)
        b[k] += g->acc[k];
    hsbd_blocks_end_sample(g->blocks);
    return HSBD_OK;
}

int hsbd_gr_profile_axis(const hsbd_gr *g) {
    return g->zaxis;
}

size_t hsbd_gr_bins(const hsbd_gr *g) {
    return g->bins;
}

size_t hsbd_gr_pairs(const hsbd_gr *g) {
    return g->npairs;
}

/* g(r) of a pair and the contact value by the quadratic fit, from a per-sample count row */
static double fit_contact(const hsbd_gr *g, const double *counts, const double *expected) {
    /* least squares of y_k = g at gap centre x_k by c0 + c1 x + c2 x^2; returns c0 */
    double m[3][4] = {{0}};
    const double h = g->fit_width / GR_FIT_BINS;
    for (size_t k = 0; k < GR_FIT_BINS; ++k) {
        const double x = ((double)k + 0.5) * h, y = counts[k] / expected[k];
        const double p[3] = {1, x, x * x};
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c)
                m[r][c] += p[r] * p[c];
            m[r][3] += p[r] * y;
        }
    }
    for (int c = 0; c < 3; ++c) /* Gauss-Jordan, well conditioned for 10 points */
        for (int r = 0; r < 3; ++r) {
            if (r == c) continue;
            const double f = m[r][c] / m[c][c];
            for (int q = 0; q < 4; ++q)
                m[r][q] -= f * m[c][q];
        }
    return m[0][3] / m[0][0];
}

/* One block's reference row of a pair along a profile axis: the products of its mean profiles at
 * each z-bin distance (each pair of bins once; distinct pairs for a = b) times the weights */
static void slab_reference(const hsbd_gr *g, const double *block, size_t pair, double *ref) {
    const size_t row = g->bins + GR_FIT_BINS;
    size_t a = 0, b = 0;
    hsbd_gr_pair_species(g, pair, &a, &b);
    const double *na = block + g->npairs * row + a * g->nz,
                 *nb = block + g->npairs * row + b * g->nz;
    const double same = a == b ? (g->members[a] - 1) / g->members[a] : 0;
    double *c = g->products;
    for (size_t dk = 0; dk < g->nshift; ++dk)
        c[dk] = 0;
    for (size_t k = g->zlo; k < g->zhi; ++k) {
        if (na[k] == 0 && nb[k] == 0) continue;
        c[0] += a == b ? 0.5 * same * na[k] * na[k] : na[k] * nb[k];
        for (size_t dk = 1; dk < g->nshift && (g->zperiodic || k + dk < g->zhi); ++dk) {
            const size_t l = (k + dk) % g->nz; /* a periodic axis: its nearest image */
            c[dk] += a == b ? same * na[k] * na[l] : na[k] * nb[l] + nb[k] * na[l];
        }
    }
    const double *w = g->shift_weight + pair * g->nshift * row;
    for (size_t k = 0; k < row; ++k)
        ref[k] = 0;
    for (size_t dk = 0; dk < g->nshift; ++dk)
        for (size_t k = 0; k < row && c[dk] != 0; ++k)
            ref[k] += c[dk] * w[dk * row + k];
}

/* The mean of the blocks' rows (the profile over the whole run) into g->results, and the
 * reference of a pair from it into g->reference; returns the blocks used. */
static size_t profile_reference(const hsbd_gr *g, size_t pair) {
    double *mean = g->results, *all = g->per_block;
    hsbd_blocks_block_means(g->blocks, 0, all);
    size_t used = 0;
    for (size_t j = 0; j < g->nv; ++j)
        mean[j] = 0;
    for (size_t b = 0; b < g->nblocks; ++b) {
        if (isnan(all[b * g->nv])) continue;
        for (size_t j = 0; j < g->nv; ++j)
            mean[j] += all[b * g->nv + j];
        ++used;
    }
    for (size_t j = 0; j < g->nv && used; ++j)
        mean[j] /= (double)used;
    slab_reference(g, mean, pair, g->reference);
    return used;
}

/* Along a profile axis: g = the pairs over the reference of the run's mean profile; the
 * error from the scatter of the blocks' ratios of pairs to their own profile's reference
 * (the ratio cancels the profile's slow fluctuations, which the pairs share) */
static void slab_result(const hsbd_gr *g, size_t pair, double *gr, double *err) {
    const size_t row = g->bins + GR_FIT_BINS, used = profile_reference(g, pair);
    for (size_t k = 0; k < g->bins; ++k) {
        const double *ref = g->reference, *mean = g->results + pair * row;
        gr[k] = ref[k] > 0 && used ? mean[k] / ref[k] : NAN;
        err[k] = 0;
    }
    double *sum = g->results; /* the blocks' ratios (the mean row is used up) */
    for (size_t k = 0; k < g->bins; ++k)
        sum[k] = 0;
    for (size_t b = 0; b < g->nblocks; ++b) {
        const double *block = g->per_block + b * g->nv, *c = block + pair * row;
        if (isnan(c[0])) continue;
        slab_reference(g, block, pair, g->reference);
        for (size_t k = 0; k < g->bins; ++k) {
            const double ratio = g->reference[k] > 0 ? c[k] / g->reference[k] : 0;
            sum[k] += ratio, err[k] += ratio * ratio;
        }
    }
    for (size_t k = 0; k < g->bins; ++k) {
        const double m = sum[k] / (double)used;
        err[k] = used >= 2 && isfinite(gr[k])
                     ? sqrt(fmax(0.0, (err[k] / (double)used - m * m) / (double)(used - 1)))
                     : NAN;
    }
}

void hsbd_gr_result(const hsbd_gr *g, size_t pair, double *r, double *gr, double *err) {
    const size_t row = g->bins + GR_FIT_BINS, nv = g->nv;
    for (size_t k = 0; k < g->bins; ++k)
        r[k] = ((double)k + 0.5) * g->width;
    if (g->zaxis >= 0) {
        slab_result(g, pair, gr, err);
        return;
    }
    double *mean = g->results, *e = g->results + nv;
    hsbd_blocks_result(g->blocks, mean, e);
    const double *ex = g->expected + pair * row;
    for (size_t k = 0; k < g->bins; ++k) {
        gr[k] = ex[k] > 0 ? mean[pair * row + k] / ex[k] : NAN;
        err[k] = ex[k] > 0 ? e[pair * row + k] / ex[k] : NAN;
    }
}

void hsbd_gr_contact(const hsbd_gr *g, size_t pair, double *value, double *err) {
    *value = *err = NAN;
    const size_t row = g->bins + GR_FIT_BINS, nv = g->nv;
    if (g->zaxis >= 0 ? !g->contact_ok : g->expected[pair * row + g->bins] <= 0) return;
    double *all = g->per_block;
    hsbd_blocks_block_means(g->blocks, 0, all);
    /* the value from all samples (block means weighted by their samples: equal blocks),
     * the error from the scatter of the blocks' extrapolations */
    const double *ex = g->expected + pair * row + g->bins;
    double global = NAN; /* along a profile axis: the fit to the run's mean pairs and profile */
    if (g->zaxis >= 0) {
        profile_reference(g, pair);
        if (!(g->reference[g->bins] > 0)) return;
        global = fit_contact(g, g->results + pair * row + g->bins, g->reference + g->bins);
        ex = g->reference + g->bins;
    }
    double sum = 0, sum2 = 0;
    size_t used = 0;
    for (size_t b = 0; b < g->nblocks; ++b) {
        const double *c = all + b * nv + pair * row + g->bins;
        if (isnan(c[0])) continue;
        if (g->zaxis >= 0) { /* the scatter: each block against its own profile */
            slab_reference(g, all + b * nv, pair, g->reference);
            if (!(ex[0] > 0)) continue;
        }
        const double val = fit_contact(g, c, ex);
        sum += val, sum2 += val * val, ++used;
    }
    if (!used) return;
    const double m = sum / (double)used;
    *value = g->zaxis >= 0 ? global : m;
    if (used >= 2) *err = sqrt(fmax(0.0, (sum2 / (double)used - m * m) / (double)(used - 1)));
}

double hsbd_gr_contact_weight(const hsbd_gr *g, size_t pair) {
    return g->zaxis >= 0 ? NAN : g->weight[pair]; /* Z needs a homogeneous box */
}

/* ---- checkpoints: the blocks, and the ideal-gas references of the sizes simulated ---- */
void hsbd_gr_save(const hsbd_gr *g, hsbd_writer *w) {
    const size_t row = g->bins + GR_FIT_BINS;
    hsbd_put_tag(w, "gr");
    const uint64_t shape[3] = {g->npairs, g->bins, g->nblocks};
    hsbd_put_u64s(w, shape, 3);
    hsbd_put_f64s(w, g->expected, g->npairs * row);
    hsbd_put_f64s(w, g->weight, g->npairs);
    hsbd_blocks_save(g->blocks, w);
}

int hsbd_gr_load(hsbd_gr *g, hsbd_reader *r) {
    const size_t row = g->bins + GR_FIT_BINS;
    uint64_t shape[3];
    if (hsbd_get_tag(r, "gr") || hsbd_get_u64s(r, shape, 3)) return -1;
    if (shape[0] != g->npairs || shape[1] != g->bins || shape[2] < g->nblocks)
        return hsbd_reader_fail(r, "g(r) of another shape");
    if (hsbd_get_f64s(r, g->expected, g->npairs * row) || hsbd_get_f64s(r, g->weight, g->npairs) ||
        hsbd_blocks_load(g->blocks, r))
        return -1;
    const size_t nblocks = hsbd_blocks_count(g->blocks); /* more after an extension */
    if (nblocks > g->nblocks) {
        double *pb = realloc(g->per_block, nblocks * g->nv * sizeof *pb);
        if (!pb) return hsbd_reader_oom(r, "g(r) blocks");
        g->per_block = pb;
    }
    g->nblocks = nblocks;
    return 0;
}
