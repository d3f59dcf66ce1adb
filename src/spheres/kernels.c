#include "spheres/kernels.h"

#include "core/vmath.h"

/* The pair's later segment start t0 (returned), separation at t0 and relative velocity,
 * as both kernels compute them. */
static inline double pair_geometry(const sph_row_query *q, int32_t j, double r[3], double v[3]) {
    const double *xj = q->x + 3 * (size_t)j, *vj = q->v + 3 * (size_t)j;
    const double tj = q->t_local[j], t0 = q->ti > tj ? q->ti : tj;
    const double hj = t0 - tj, hi = t0 - q->ti;
    for (int a = 0; a < 3; ++a) {
        const double pj = xj[a] + vj[a] * hj, pi = q->xi[a] + q->vi[a] * hi;
        r[a] = hsbd_wrap_delta(pj - pi, q->box[a]);
        v[a] = vj[a] - q->vi[a];
    }
    return t0;
}

uint32_t sph_predict_row_scalar(const sph_row_query *q, const int32_t *row, uint32_t m,
                                int32_t *hit_j, double *hit_t) {
    uint32_t hits = 0;
    for (uint32_t k = 0; k < m; ++k) {
        const int32_t j = row[k];
        double r[3], v[3];
        const double t0 = pair_geometry(q, j, r, v);
        const double tc = sph_contact_time(r, v, 0.5 * (q->sigma_i + q->sigma[j]), q->dt - t0);
        if (tc >= 0) {
            hit_j[hits] = j;
            hit_t[hits++] = t0 + tc;
        }
    }
    return hits;
}

uint32_t sph_half_scan_scalar(const sph_scan_query *q, size_t i0, size_t i1, int32_t *hit_i,
                              int32_t *hit_j, double *hit_t) {
    uint32_t hits = 0;
    for (size_t i = i0; i < i1; ++i) {
        const int32_t *row = q->nb + i * q->nb_cap;
        for (uint32_t k = 0; k < q->nb_upper[i]; ++k) {
            const int32_t j = row[k];
            const double tc = sph_scan_pair_time(q, i, j);
            if (tc >= 0) {
                hit_i[hits] = (int32_t)i;
                hit_j[hits] = j;
                hit_t[hits++] = tc;
            }
        }
    }
    return hits;
}

uint32_t sph_cells_near_scalar(const hsbd_cells *cells, const int32_t *list, int nlist,
                               const double c[3], const double box[3], const double *sigma,
                               double reach_base, int32_t *out) {
    uint32_t found = 0;
    for (int q = 0; q < nlist; ++q) {
        const uint32_t m = hsbd_cells_count(cells, list[q]);
        for (uint32_t u = 0; u < m; ++u) {
            const double *p = hsbd_cells_position(cells, list[q], u);
            const int32_t j = hsbd_cells_id(cells, list[q], u);
            double r[3];
            for (int a = 0; a < 3; ++a)
                r[a] = hsbd_wrap_delta(p[a] - c[a], box[a]);
            const double reach = sigma ? reach_base + 0.5 * sigma[j] : reach_base;
            out[found] = j;
            found += hsbd_dot3(r, r) < reach * reach;
        }
    }
    return found;
}

#if defined(__x86_64__) || defined(_M_X64)
sph_predict_row_fn sph_predict_row_select(void) {
    return hsbd_cpu_has_avx2() ? sph_predict_row_avx2 : sph_predict_row_scalar;
}
sph_cells_near_fn sph_cells_near_select(void) {
    return hsbd_cpu_has_avx2() ? sph_cells_near_avx2 : sph_cells_near_scalar;
}
sph_half_scan_fn sph_half_scan_select(void) {
    return hsbd_cpu_has_avx2() ? sph_half_scan_avx2 : sph_half_scan_scalar;
}
#else
uint32_t sph_predict_row_avx2(const sph_row_query *q, const int32_t *row, uint32_t m,
                              int32_t *hit_j, double *hit_t) {
    return sph_predict_row_scalar(q, row, m, hit_j, hit_t);
}
sph_predict_row_fn sph_predict_row_select(void) {
    return sph_predict_row_scalar;
}
uint32_t sph_cells_near_avx2(const hsbd_cells *cells, const int32_t *list, int nlist,
                             const double c[3], const double box[3], const double *sigma,
                             double reach_base, int32_t *out) {
    return sph_cells_near_scalar(cells, list, nlist, c, box, sigma, reach_base, out);
}
sph_cells_near_fn sph_cells_near_select(void) {
    return sph_cells_near_scalar;
}
uint32_t sph_half_scan_avx2(const sph_scan_query *q, size_t i0, size_t i1, int32_t *hit_i,
                            int32_t *hit_j, double *hit_t) {
    return sph_half_scan_scalar(q, i0, i1, hit_i, hit_j, hit_t);
}
sph_half_scan_fn sph_half_scan_select(void) {
    return sph_half_scan_scalar;
}
#endif
