/* The inner loops of EDBD (internal to src/spheres): the contact time of two spheres on
 * straight paths, a kernel that tests one particle against a row of neighbours, and one
 * that finds the points of a few cells within reach of a position. Each kernel has a
 * scalar and an AVX2 version (kernels_avx2.c, chosen at run time); both evaluate the same
 * IEEE operations in the same order without FMA, so they return the same hits and
 * bit-identical times (tests/unit/test_spheres.c checks it). */
#ifndef HSBD_SPHERES_KERNELS_H
#define HSBD_SPHERES_KERNELS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "core/cellgrid.h"
#include "core/periodic.h"

/* The hit test of sph_contact_time: |r + v t|^2 - s^2 = g + 2 b t + vv t^2 has a root in
 * [0, T] iff the pair approaches (b < 0) and either the value at T is <= 0 or the minimum
 * lies inside [0, T] with a non-negative discriminant. */
static inline int sph_contact_hit(double b, double g, double vv, double tmax) {
    const double f_end = g + tmax * (2 * b + vv * tmax), disc = b * b - vv * g;
    return (b < 0) & ((f_end <= 0) | ((-b < vv * tmax) & (disc >= 0)));
}

/* First time in [0, tmax] at which |r + v t| = s, or -1. The tests run without branches
 * (about half the neighbour pairs approach: a branch on b alone mispredicts); the root
 * only for hits. */
static inline double sph_contact_time(const double r[3], const double v[3], double s, double tmax) {
    const double b = hsbd_dot3(r, v), g = hsbd_dot3(r, r) - s * s, vv = hsbd_dot3(v, v);
    if (__builtin_expect(!sph_contact_hit(b, g, vv, tmax), 1)) return -1;
    if (g <= 0) return 0; /* touching (round-off) and approaching */
    const double disc = b * b - vv * g;
    const double t = g / (-b + sqrt(disc > 0 ? disc : 0));
    return t <= tmax ? t : tmax; /* a root exists in [0, tmax]: round-off only */
}

/* One particle i, on the segment x_i + v_i (t - t_i), against a row of neighbours j on
 * theirs, x_j + v_j (t - t_j). A pair's contact time is computed from the later start,
 * t0 = max(t_i, t_j) (the earlier segment moved to it, the later one as it is): r =
 * minimum image of x_j(t0) - x_i(t0), relative velocity v_j - v_i, contact distance
 * (sigma_i + sigma_j) / 2, window [t0, dt]. The result depends on the two segments alone,
 * not on when or from which side the pair is tested. */
typedef struct sph_row_query {
    const double *x, *v;   /* 3 per particle: each segment's start and velocity */
    const double *t_local; /* per particle: each segment's start time */
    const double *sigma;   /* per particle */
    double box[3];
    double xi[3], vi[3], sigma_i, ti; /* i's segment */
    double dt;                        /* the step's end */
} sph_row_query;

/* Writes the j of row[0..m) that reach contact before dt, in row order, to hit_j and
 * their contact times (within the step) to hit_t; returns their number. */
typedef uint32_t (*sph_predict_row_fn)(const sph_row_query *q, const int32_t *row, uint32_t m,
                                       int32_t *hit_j, double *hit_t);

uint32_t sph_predict_row_scalar(const sph_row_query *q, const int32_t *row, uint32_t m,
                                int32_t *hit_j, double *hit_t);
uint32_t sph_predict_row_avx2(const sph_row_query *q, const int32_t *row, uint32_t m,
                              int32_t *hit_j, double *hit_t);
/* The fastest version this CPU runs. */
sph_predict_row_fn sph_predict_row_select(void);

/* The half scan at the start of a step, every particle at its position x (t = 0): the
 * pairs (i, j) with j among the first nb_upper[i] entries of row i, for i in [i0, i1),
 * r = minimum image of x_j - x_i; the pairs of many rows fill the vectors. Hits in i and row order
 * to hit_i, hit_j, hit_t (room for every pair); returns their number. Rows have room for at
 * least 16 entries (the AVX2 version copies 16 at a time). */
typedef struct sph_scan_query {
    const double *x, *v, *sigma; /* x, v: 3 per particle */
    const int32_t *nb;           /* rows of nb_cap entries */
    const uint32_t *nb_upper;
    uint32_t nb_cap;
    double box[3], tmax;
} sph_scan_query;

/* The contact time of the half scan's pair (i, j): sph_contact_time of the minimum image
 * of x_j - x_i and of v_j - v_i, or -1. */
static inline double sph_scan_pair_time(const sph_scan_query *q, size_t i, int32_t j) {
    const double *xi = q->x + 3 * i, *vi = q->v + 3 * i;
    const double *xj = q->x + 3 * (size_t)j, *vj = q->v + 3 * (size_t)j;
    double r[3], v[3];
    for (int a = 0; a < 3; ++a) {
        r[a] = hsbd_wrap_delta(xj[a] - xi[a], q->box[a]);
        v[a] = vj[a] - vi[a];
    }
    return sph_contact_time(r, v, 0.5 * (q->sigma[i] + q->sigma[j]), q->tmax);
}

typedef uint32_t (*sph_half_scan_fn)(const sph_scan_query *q, size_t i0, size_t i1, int32_t *hit_i,
                                     int32_t *hit_j, double *hit_t);
uint32_t sph_half_scan_scalar(const sph_scan_query *q, size_t i0, size_t i1, int32_t *hit_i,
                              int32_t *hit_j, double *hit_t);
uint32_t sph_half_scan_avx2(const sph_scan_query *q, size_t i0, size_t i1, int32_t *hit_i,
                            int32_t *hit_j, double *hit_t);
sph_half_scan_fn sph_half_scan_select(void);

/* The points p of cells list[0..nlist) with |minimum image of p - c|^2 < (reach_base +
 * sigma[id] / 2)^2, in list and slot order, to out (room for the cells' total count plus
 * SPH_NEAR_PAD); returns their number. sigma NULL: all points have one diameter, whose half
 * the caller has added to reach_base (the same sum: no diameters to read). */
enum { SPH_NEAR_PAD = 4 };
typedef uint32_t (*sph_cells_near_fn)(const hsbd_cells *cells, const int32_t *list, int nlist,
                                      const double c[3], const double box[3], const double *sigma,
                                      double reach_base, int32_t *out);

uint32_t sph_cells_near_scalar(const hsbd_cells *cells, const int32_t *list, int nlist,
                               const double c[3], const double box[3], const double *sigma,
                               double reach_base, int32_t *out);
uint32_t sph_cells_near_avx2(const hsbd_cells *cells, const int32_t *list, int nlist,
                             const double c[3], const double box[3], const double *sigma,
                             double reach_base, int32_t *out);
sph_cells_near_fn sph_cells_near_select(void);

#endif
