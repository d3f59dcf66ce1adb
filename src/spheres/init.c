/* Initial states of the EDBD system: random sequential insertion, lattices, given
 * positions (checked for overlaps). All use the seed's initial-state stream. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/internal.h"

enum { INIT_COUNTER_RSI = 0, INIT_COUNTER_SHUFFLE = 1 };

/* Overlap of point x (diameter sg) with any inserted point of grid c (diameters sigma). */
static int overlaps_any(const hsbd_spheres *s, const sph_cells *c, const double *pos,
                        const double x[3], double sg, int32_t self, int32_t *with) {
    int32_t around[27];
    const int nc = sph_cells_around(c, x, around);
    for (int q = 0; q < nc; ++q)
        for (int32_t j = c->head[around[q]]; j >= 0; j = c->next[j]) {
            if (j == self) continue;
            double r2 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d =
                    sph_wrap_delta(pos[3 * (size_t)j + a] - x[a], s->box[a], s->inv_box[a]);
                r2 += d * d;
            }
            const double sij = 0.5 * (sg + s->sigma[j]);
            if (r2 < sij * sij * (1 - 2e-9)) {
                if (with) *with = j;
                return 1;
            }
        }
    return 0;
}

static void reset_dynamics(hsbd_spheres *s) {
    memset(s->image, 0, 3 * s->n * sizeof *s->image);
    memset(s->t_local, 0, s->n * sizeof *s->t_local);
    s->step = 0;
    s->time = 0;
}

int hsbd_spheres_init_random(hsbd_spheres *s, hsbd_error *err) {
    const size_t n = s->n;
    sph_cells grid;
    if (sph_cells_init(&grid, s->dim, s->box, s->sigma_max, n))
        return sph_cells_free(&grid), hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
    /* larger particles first: they are the hardest to place */
    size_t *order = malloc(n * sizeof *order);
    if (!order) return sph_cells_free(&grid), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; ++i)
        order[i] = i;
    for (size_t i = 1; i < n; ++i) { /* insertion sort by diameter, stable: few species */
        const size_t k = order[i];
        size_t j = i;
        while (j > 0 && s->sigma[order[j - 1]] < s->sigma[k])
            order[j] = order[j - 1], --j;
        order[j] = k;
    }
    const uint64_t max_trials = 2000;
    double u[3];
    uint64_t draw = 0;
    int rc = HSBD_OK;
    for (size_t q = 0; q < n && rc == HSBD_OK; ++q) {
        const size_t i = order[q];
        uint64_t trial = 0;
        for (;; ++trial) {
            if (trial == max_trials) {
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "spheres: random sequential insertion stalled after placing "
                                    "%zu of %zu particles (%llu trials for the next); the packing "
                                    "is too dense for init.method = random; allowed: "
                                    "init.method = lattice, or a lower packing fraction",
                                    q, n, (unsigned long long)max_trials);
                break;
            }
            hsbd_rng_uniforms(s->par.seed, HSBD_STREAM_INIT, INIT_COUNTER_RSI, 3 * draw, 3, u);
            ++draw;
            double x[3] = {u[0] * s->box[0], u[1] * s->box[1], s->dim == 3 ? u[2] * s->box[2] : 0};
            if (!overlaps_any(s, &grid, s->x, x, s->sigma[i], -1, NULL)) {
                memcpy(s->x + 3 * i, x, sizeof x);
                sph_cells_insert(&grid, (int32_t)i, x);
                break;
            }
        }
    }
    free(order);
    sph_cells_free(&grid);
    if (rc != HSBD_OK) return rc;
    reset_dynamics(s);
    return sph_rebuild_neighbours(s) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory (neighbour lists)");
}

/* Sites of a face-centred cubic (3D) or centred rectangular (2D) lattice with m[a] cells
 * per axis: the nearest-neighbour distance of that lattice in this box. */
static double lattice_spacing(const hsbd_spheres *s, const int m[3]) {
    double c[3], best = INFINITY;
    for (int a = 0; a < s->dim; ++a)
        c[a] = s->box[a] / m[a];
    for (int a = 0; a < s->dim; ++a) {
        if (c[a] < best) best = c[a];
        for (int b = a + 1; b < s->dim; ++b) {
            const double h = 0.5 * sqrt(c[a] * c[a] + c[b] * c[b]);
            if (h < best) best = h;
        }
    }
    return best;
}

int hsbd_spheres_init_lattice(hsbd_spheres *s, hsbd_error *err) {
    const size_t n = s->n;
    const int basis = s->dim == 3 ? 4 : 2;
    /* cells per axis: start from the cell volume that holds N sites, add cells along the
     * axis with the widest cells until there are enough sites */
    double vol = 1;
    for (int a = 0; a < s->dim; ++a)
        vol *= s->box[a];
    const double side = pow(vol * basis / (double)n, 1.0 / s->dim);
    int m[3] = {1, 1, 1};
    for (int a = 0; a < s->dim; ++a)
        m[a] = (int)fmax(1.0, floor(s->box[a] / side));
    for (;;) {
        size_t sites = (size_t)basis;
        for (int a = 0; a < s->dim; ++a)
            sites *= (size_t)m[a];
        if (sites >= n) break;
        int widest = 0;
        for (int a = 1; a < s->dim; ++a)
            if (s->box[a] / m[a] > s->box[widest] / m[widest]) widest = a;
        m[widest]++;
    }
    const double spacing = lattice_spacing(s, m);
    if (spacing < s->sigma_max * (1 + 1e-9))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "spheres: a lattice of %d x %d x %d cells (%s) in this box has "
                              "spacing %g < the largest diameter %g; allowed: a lower packing "
                              "fraction, or init.positions",
                              m[0], m[1], m[2], s->dim == 3 ? "fcc" : "centred rectangular",
                              spacing, s->sigma_max);
    size_t sites = (size_t)basis;
    for (int a = 0; a < s->dim; ++a)
        sites *= (size_t)m[a];
    /* a uniformly random choice of N sites, in random order (vacancies and species spread) */
    size_t *site = malloc(sites * sizeof *site);
    double *u = malloc(sites * sizeof *u);
    if (!site || !u) {
        free(site);
        free(u);
        return hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
    }
    hsbd_rng_uniforms(s->par.seed, HSBD_STREAM_INIT, INIT_COUNTER_SHUFFLE, 0, sites, u);
    for (size_t k = 0; k < sites; ++k)
        site[k] = k;
    for (size_t k = sites - 1; k > 0; --k) { /* Fisher-Yates */
        const size_t r = (size_t)(u[k] * (double)(k + 1));
        const size_t t = site[k];
        site[k] = site[r < k ? r : k];
        site[r < k ? r : k] = t;
    }
    static const double fcc[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    static const double crect[2][3] = {{0, 0, 0}, {0.5, 0.5, 0}};
    for (size_t i = 0; i < n; ++i) {
        size_t k = site[i];
        const int b = (int)(k % (size_t)basis);
        k /= (size_t)basis;
        const double *off = s->dim == 3 ? fcc[b] : crect[b];
        for (int a = 0; a < 3; ++a) {
            double x = 0;
            if (a < s->dim) {
                const size_t cell = k % (size_t)m[a];
                k /= (size_t)m[a];
                x = ((double)cell + off[a] + 0.25) * s->box[a] / m[a];
            }
            s->x[3 * i + a] = x - s->box[a] * floor(x * s->inv_box[a]);
        }
    }
    free(site);
    free(u);
    reset_dynamics(s);
    return sph_rebuild_neighbours(s) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory (neighbour lists)");
}

int hsbd_spheres_set_positions(hsbd_spheres *s, const double *x, hsbd_error *err) {
    const size_t n = s->n;
    double *pos = malloc(3 * n * sizeof *pos);
    if (!pos) return hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double v = a < s->dim ? x[3 * i + a] : 0.0;
            if (!isfinite(v)) {
                free(pos);
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "spheres: position of particle %zu is not finite", i + 1);
            }
            pos[3 * i + a] = v - s->box[a] * floor(v * s->inv_box[a]);
        }
    int rc = HSBD_OK;
    if (s->par.hard_core) {
        sph_cells grid;
        if (sph_cells_init(&grid, s->dim, s->box, s->sigma_max, n)) {
            sph_cells_free(&grid);
            free(pos);
            return hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
        }
        for (size_t i = 0; i < n && rc == HSBD_OK; ++i) {
            int32_t j = -1;
            if (overlaps_any(s, &grid, pos, pos + 3 * i, s->sigma[i], (int32_t)i, &j)) {
                double r2 = 0;
                for (int a = 0; a < 3; ++a) {
                    const double d = sph_wrap_delta(pos[3 * (size_t)j + a] - pos[3 * i + a],
                                                    s->box[a], s->inv_box[a]);
                    r2 += d * d;
                }
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "spheres: particles %d and %zu overlap: distance %.9g < "
                                    "contact distance %.9g; allowed: no overlaps",
                                    j + 1, i + 1, sqrt(r2), 0.5 * (s->sigma[i] + s->sigma[j]));
            }
            sph_cells_insert(&grid, (int32_t)i, pos + 3 * i);
        }
        sph_cells_free(&grid);
    }
    if (rc == HSBD_OK) {
        memcpy(s->x, pos, 3 * n * sizeof *pos);
        reset_dynamics(s);
        if (sph_rebuild_neighbours(s) != HSBD_OK)
            rc = hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory (neighbour lists)");
    }
    free(pos);
    return rc;
}
