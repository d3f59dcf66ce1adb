/* Initial states of the EDBD system: random sequential insertion, lattices, compression
 * by Brownian growth, given positions (checked for overlaps), and polydisperse diameters.
 * All use the seed's initial-state stream (the compression's steps their own). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/neighbours.h"
#include "spheres/order.h"
#include "spheres/state.h"

enum { INIT_COUNTER_RSI = 0, INIT_COUNTER_SHUFFLE = 1, INIT_COUNTER_SIZES = 2 };

/* Overlap of point x (diameter sg) with any inserted point of grid c (diameters sigma). */
static int overlaps_any(const hsbd_spheres *s, const hsbd_cells *c, const double *pos,
                        const double x[3], double sg, int32_t self, int32_t *with) {
    int32_t around[27];
    const int nc = hsbd_cells_around(c, x, around);
    for (int q = 0; q < nc; ++q)
        for (uint32_t u = 0; u < hsbd_cells_count(c, around[q]); ++u) {
            const int32_t j = hsbd_cells_id(c, around[q], u);
            if (j == self) continue;
            double r2 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d = hsbd_wrap_delta(pos[3 * (size_t)j + a] - x[a], s->box[a]);
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
    s->sort_clock = INFINITY; /* new positions: sorted before the next step */
}

/* Every init writes per-particle values by the user's index. */
static int restore_user_order(hsbd_spheres *s, hsbd_error *err) {
    return sph_restore_user_order(s) ? hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory")
                                     : HSBD_OK;
}

int hsbd_spheres_init_random(hsbd_spheres *s, hsbd_error *err) {
    if (restore_user_order(s, err) != HSBD_OK) return HSBD_ENOMEM;
    const size_t n = s->n;
    hsbd_cells grid;
    if (hsbd_cells_init(&grid, s->dim, s->box, s->sigma_max, n))
        return hsbd_cells_free(&grid), hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
    /* larger particles first: they are the hardest to place */
    size_t *order = malloc(n * sizeof *order);
    if (!order) return hsbd_cells_free(&grid), hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
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
            double x[3] = {0, 0, 0};
            for (int a = 0; a < s->dim; ++a) /* between walls: centres in [sigma/2, L - sigma/2] */
                x[a] = s->walls[a] ? 0.5 * s->sigma[i] + u[a] * (s->length[a] - s->sigma[i])
                                   : u[a] * s->box[a];
            if (!overlaps_any(s, &grid, s->x, x, s->sigma[i], -1, NULL)) {
                memcpy(s->x + 3 * i, x, sizeof x);
                if (hsbd_cells_insert(&grid, (int32_t)i, x))
                    rc = hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
                break;
            }
        }
    }
    free(order);
    hsbd_cells_free(&grid);
    if (rc != HSBD_OK) return rc;
    reset_dynamics(s);
    return sph_rebuild_neighbours(s) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory (neighbour lists)");
}

/* The length a lattice fills along axis a: the box, or between walls the room of the
 * centres of the largest particles (the sites start at sigma_max / 2 there). */
static double lattice_span(const hsbd_spheres *s, int a) {
    return s->walls[a] ? s->length[a] - s->sigma_max : s->box[a];
}

/* Sites of a face-centred cubic (3D) or centred rectangular (2D) lattice with m[a] cells
 * per axis: the nearest-neighbour distance of that lattice in this box. */
static double lattice_spacing(const hsbd_spheres *s, const int m[3]) {
    double c[3], best = INFINITY;
    for (int a = 0; a < s->dim; ++a)
        c[a] = lattice_span(s, a) / m[a];
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
    if (restore_user_order(s, err) != HSBD_OK) return HSBD_ENOMEM;
    const size_t n = s->n;
    const int basis = s->dim == 3 ? 4 : 2;
    /* cells per axis: start from the cell volume that holds N sites, add cells along the
     * axis with the widest cells until there are enough sites */
    double vol = 1;
    for (int a = 0; a < s->dim; ++a)
        vol *= lattice_span(s, a);
    const double side = pow(vol * basis / (double)n, 1.0 / s->dim);
    int m[3] = {1, 1, 1};
    for (int a = 0; a < s->dim; ++a)
        m[a] = (int)fmax(1.0, floor(lattice_span(s, a) / side));
    for (;;) {
        size_t sites = (size_t)basis;
        for (int a = 0; a < s->dim; ++a)
            sites *= (size_t)m[a];
        if (sites >= n) break;
        int widest = 0;
        for (int a = 1; a < s->dim; ++a)
            if (lattice_span(s, a) / m[a] > lattice_span(s, widest) / m[widest]) widest = a;
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
                x = ((double)cell + off[a] + 0.25) * lattice_span(s, a) / m[a] +
                    (s->walls[a] ? 0.5 * s->sigma_max : 0.0);
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
    if (restore_user_order(s, err) != HSBD_OK) return HSBD_ENOMEM;
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
            const double half = 0.5 * s->sigma[i], tol = 1e-9 * s->sigma[i];
            if (a < s->dim && s->walls[a] && !(v >= half - tol && v <= s->length[a] - half + tol)) {
                free(pos);
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "spheres: particle %zu at %.9g on axis %d is outside the "
                                      "walls; allowed: %.9g <= x <= %.9g (sigma/2 from 0 and "
                                      "from the box length)",
                                      i + 1, v, a, half, s->length[a] - half);
            }
            if (a < s->dim && s->walls[a])
                pos[3 * i + a] = fmin(fmax(v, half), s->length[a] - half);
        }
    int rc = HSBD_OK;
    if (s->par.hard_core) {
        hsbd_cells grid;
        if (hsbd_cells_init(&grid, s->dim, s->box, s->sigma_max, n)) {
            hsbd_cells_free(&grid);
            free(pos);
            return hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
        }
        for (size_t i = 0; i < n && rc == HSBD_OK; ++i) {
            int32_t j = -1;
            if (overlaps_any(s, &grid, pos, pos + 3 * i, s->sigma[i], (int32_t)i, &j)) {
                double r2 = 0;
                for (int a = 0; a < 3; ++a) {
                    const double d =
                        hsbd_wrap_delta(pos[3 * (size_t)j + a] - pos[3 * i + a], s->box[a]);
                    r2 += d * d;
                }
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "spheres: particles %d and %zu overlap: distance %.9g < "
                                    "contact distance %.9g; allowed: no overlaps",
                                    j + 1, i + 1, sqrt(r2), 0.5 * (s->sigma[i] + s->sigma[j]));
            }
            if (rc == HSBD_OK && hsbd_cells_insert(&grid, (int32_t)i, pos + 3 * i))
                rc = hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
        }
        hsbd_cells_free(&grid);
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

/* ---- compression by Brownian growth ---- */

/* Every particle grows by `fraction` of its smallest surface gap, so two neighbours that
 * both grow use at most that fraction of the gap between them. Just after a rebuild the
 * shells sit on the particles, so a non-neighbour is at least 2 shell away: that bounds
 * the growth too. No particle passes its final diameter. Returns how many are below it. */
static size_t grow_into_gaps(hsbd_spheres *s, const double *final, double fraction,
                             double *growth) {
    size_t below = 0;
    for (size_t i = 0; i < s->n; ++i) {
        double room = 2 * s->shell;
        const int32_t *row = s->nb + i * s->nb_cap;
        for (uint32_t k = 0; k < s->nb_count[i]; ++k) {
            const int32_t j = row[k];
            double r2 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d =
                    hsbd_wrap_delta(s->x[3 * (size_t)j + a] - s->x[3 * i + a], s->box[a]);
                r2 += d * d;
            }
            const double gap = sqrt(r2) - 0.5 * (s->sigma[i] + s->sigma[j]);
            if (gap < room) room = gap;
        }
        for (int a = 0; a < s->dim; ++a) /* a wall does not grow: twice its gap */
            if (s->walls[a]) {
                const double x = s->x[3 * i + a], half = 0.5 * s->sigma[i];
                room = fmin(room, 2 * fmin(x - half, s->length[a] - half - x));
            }
        growth[i] = fmax(0.0, fraction * room);
    }
    for (size_t i = 0; i < s->n; ++i) {
        s->sigma[i] = fmin(final[i], s->sigma[i] + growth[i]);
        below += s->sigma[i] < final[i];
    }
    return below;
}

double hsbd_spheres_packing_fraction(int dimension, const double box[3], size_t n,
                                     const double *sigma) {
    const double pi = 3.14159265358979323846;
    double vp = 0, vol = 1;
    for (size_t i = 0; i < n; ++i)
        vp +=
            dimension == 3 ? pi / 6 * sigma[i] * sigma[i] * sigma[i] : pi / 4 * sigma[i] * sigma[i];
    for (int a = 0; a < dimension; ++a)
        vol *= box[a];
    return vp / vol;
}

static double packing_fraction(const hsbd_spheres *s, const double *sigma) {
    return hsbd_spheres_packing_fraction(s->dim, s->length, s->n, sigma);
}

/* Brownian steps with growth until every diameter is final, or a stall (below). The
 * diameters start scaled to a packing that random insertion reaches. */
static int compress_from_rsi(hsbd_spheres *s, const double *final, double *growth,
                             hsbd_error *err) {
    const double phi = packing_fraction(s, final), phi_start = s->dim == 3 ? 0.25 : 0.40;
    const double scale = phi > phi_start ? pow(phi_start / phi, 1.0 / s->dim) : 1.0;
    for (size_t i = 0; i < s->n; ++i)
        s->sigma[i] = scale * final[i];
    int rc = hsbd_spheres_init_random(s, err);
    if (rc != HSBD_OK) return rc;
    double dmax = 0, sigma_mean = 0;
    for (size_t i = 0; i < s->n; ++i)
        dmax = fmax(dmax, s->diffusion[i]), sigma_mean += final[i] / (double)s->n;
    const double step_rms = 0.03 * sigma_mean; /* per axis, of the fastest particle */
    const double dt_max = step_rms * step_rms / (2 * dmax);
    double dt = dt_max;
    /* a stall: less than 0.1 % gain of phi in a window, no end after max_steps, or more
     * than max_collisions per particle or steps shrunk a billion-fold, the signs of a
     * jamming packing (the targets the configuration allows took 90 to 280 steps and 300
     * to 600 collisions per particle at N = 400 to 4000) */
    const uint64_t window = 1000, max_steps = 10000, max_collisions = 5000;
    double checked = 0;
    for (uint64_t k = 0;; ++k) {
        if ((rc = sph_rebuild_neighbours(s)) != HSBD_OK) break;
        const size_t below = grow_into_gaps(s, final, 0.5, growth);
        if (!below) break;
        if ((rc = sph_rebuild_neighbours(s)) != HSBD_OK) break;
        const double now = packing_fraction(s, s->sigma);
        if ((k % window == 0 && k > 0 && now < checked * (1 + 1e-3)) || k == max_steps ||
            s->stats.collisions > max_collisions * s->n || dt < 1e-9 * dt_max) {
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "spheres: compression stalled at packing fraction %.4f of %.4f "
                                "(%zu particles below their diameter after %llu steps); allowed: "
                                "a lower packing fraction, or init.positions",
                                now, phi, below, (unsigned long long)k);
            break;
        }
        if (k % window == 0) checked = now;
        /* a few collisions per particle and step: shorter steps as the gaps close */
        const uint64_t before = s->stats.collisions;
        hsbd_spheres_set_dt(s, dt);
        if ((rc = hsbd_spheres_step(s)) != HSBD_OK) break;
        const double per_particle = (double)(s->stats.collisions - before) / (double)s->n;
        if (per_particle > 10) dt *= 0.5;
        if (per_particle < 2) dt = fmin(dt_max, 1.25 * dt);
    }
    return rc == HSBD_ENOMEM ? hsbd_error_set(err, rc, "spheres: out of memory (compression)") : rc;
}

int hsbd_spheres_init_compress(hsbd_spheres *s, hsbd_error *err) {
    if (restore_user_order(s, err) != HSBD_OK) return HSBD_ENOMEM;
    double *final = malloc(2 * s->n * sizeof *final), *growth = final + s->n;
    if (!final) return hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory");
    memcpy(final, s->sigma, s->n * sizeof *final);
    const double dt = s->dt;
    s->noise_stream = HSBD_STREAM_COMPRESS;
    s->bridge_stream = HSBD_STREAM_COMPRESS_CONTACT;
    const int sort_enabled = s->sort_enabled; /* final[] and growth[] use the user's order */
    const int propel = s->propel;             /* passive growth: no propulsion, no turns */
    s->sort_enabled = 0;
    s->propel = 0;
    int rc = s->par.hard_core ? compress_from_rsi(s, final, growth, err)
                              : hsbd_spheres_init_random(s, err);
    memcpy(s->sigma, final, s->n * sizeof *final);
    free(final);
    s->noise_stream = HSBD_STREAM_NOISE;
    s->bridge_stream = HSBD_STREAM_CONTACT;
    s->sort_enabled = sort_enabled;
    s->propel = propel;
    hsbd_spheres_set_dt(s, dt);
    reset_dynamics(s);
    hsbd_spheres_reset_stats(s);
    if (rc == HSBD_OK && sph_rebuild_neighbours(s) != HSBD_OK)
        rc = hsbd_error_set(err, HSBD_ENOMEM, "spheres: out of memory (neighbour lists)");
    return rc;
}

/* ---- polydisperse diameters ---- */

int hsbd_spheres_draw_diameters(uint64_t seed, size_t n, const double *mean, double width,
                                hsbd_size_distribution dist, double *sigma, hsbd_error *err) {
    if (!(width >= 0 && width <= 0.3) ||
        (dist != HSBD_SIZES_GAUSSIAN && dist != HSBD_SIZES_UNIFORM))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "spheres: polydispersity %g; allowed: 0 <= width <= 0.3, "
                              "distribution gaussian or uniform",
                              width);
    /* the normal truncated at |z| <= 3 has variance 0.973337: rescale to unit variance */
    const double unit = 1.0 / sqrt(0.9733369246625415);
    for (size_t i = 0; i < n; ++i) {
        double xi;
        if (dist == HSBD_SIZES_UNIFORM) {
            hsbd_rng_uniforms(seed, HSBD_STREAM_INIT, INIT_COUNTER_SIZES, i, 1, &xi);
            xi = sqrt(3.0) * (2 * xi - 1);
        } else {
            for (uint64_t attempt = 0;; ++attempt) { /* a fresh counter per redraw */
                hsbd_rng_normals(seed, HSBD_STREAM_INIT, INIT_COUNTER_SIZES + (attempt << 32), i, 1,
                                 &xi);
                if (fabs(xi) <= 3.0) break;
            }
            xi *= unit;
        }
        sigma[i] = mean[i] * (1 + width * xi);
    }
    return HSBD_OK;
}
