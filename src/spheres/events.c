/* The pieces of event processing that both schedulers use (internal to src/spheres): the
 * collision rule and the contact time, pushing a predicted event, a particle against its
 * row of neighbours, the time it leaves its shell, and a collision of a pair. */
#include "spheres/events.h"

#include <math.h>
#include <stdlib.h>

/* ---- collision rule and contact time (exposed for tests) ---- */

void hsbd_spheres_collide(double di, double dj, const double n[3], double vi[3], double vj[3]) {
    const double u = (vj[0] - vi[0]) * n[0] + (vj[1] - vi[1]) * n[1] + (vj[2] - vi[2]) * n[2];
    const double dsum = di + dj;
    if (!(u < 0) || !(dsum > 0)) return;
    const double ai = 2.0 * di / dsum * u, aj = 2.0 * dj / dsum * u; /* masses 1/D: Sec. III */
    for (int k = 0; k < 3; ++k) {
        vi[k] += ai * n[k];
        vj[k] -= aj * n[k];
    }
}

double hsbd_spheres_contact_time(const double r[3], const double v[3], double s, double tmax) {
    return sph_contact_time(r, v, s, tmax);
}

/* ---- predictions ---- */

int sph_push_event(hsbd_spheres *s, double t, int32_t i, int32_t j) {
    const sph_event e = {t, i, j, s->counter[i], j >= 0 ? s->counter[j] : 0};
    return sph_calendar_push(&s->calendar, e);
}

uint32_t sph_row_hits(hsbd_spheres *s, int32_t i, double t) {
    sph_row_query q = {.x = s->x,
                       .v = s->v,
                       .t_local = s->t_local,
                       .sigma = s->sigma,
                       .sigma_i = s->sigma[i],
                       .ti = s->t_local[i],
                       .dt = s->dt};
    for (int a = 0; a < 3; ++a) {
        q.box[a] = s->box[a];
        q.xi[a] = s->x[3 * (size_t)i + a];
        q.vi[a] = s->v[3 * (size_t)i + a];
    }
    const uint32_t hits =
        s->predict_row(&q, s->nb + (size_t)i * s->nb_cap, s->nb_count[i], s->scan_j, s->scan_t);
    for (uint32_t k = 0; k < hits; ++k)
        if (s->scan_t[k] < t) s->scan_t[k] = t;
    return hits;
}

double sph_shell_exit_time(const hsbd_spheres *s, int32_t i, double t) {
    return sph_shell_exit_from(s, i, t, s->centre + 3 * (size_t)i);
}

double sph_shell_exit_from(const hsbd_spheres *s, int32_t i, double t, const double c[3]) {
    double p[3], d[3];
    sph_position_at(s, i, t, p);
    sph_min_image(s, p, c, d);
    const double *v = s->v + 3 * (size_t)i;
    const double T = s->dt - t, r2 = s->shell * s->shell;
    double e[3] = {d[0] + v[0] * T, d[1] + v[1] * T, d[2] + v[2] * T};
    if (hsbd_dot3(e, e) <= r2) return -1; /* the straight path stays inside (convex ball) */
    const double vv = hsbd_dot3(v, v), b = hsbd_dot3(d, v), q = hsbd_dot3(d, d) - r2;
    double h = (-b + sqrt(b * b - vv * q)) / vv; /* q < 0: one positive root */
    if (!(h >= 0)) h = 0;
    return t + h;
}

/* ---- a collision ---- */

int sph_collide_pair(hsbd_spheres *s, const sph_event *e, double *virial) {
    const int32_t i = e->i, j = e->j;
    sph_advance(s, i, e->t);
    sph_advance(s, j, e->t);
    double r[3];
    sph_min_image(s, s->x + 3 * (size_t)j, s->x + 3 * (size_t)i, r);
    const double dist = sqrt(hsbd_dot3(r, r));
    const double nrm[3] = {r[0] / dist, r[1] / dist, r[2] / dist};
    double *vi = s->v + 3 * (size_t)i, *vj = s->v + 3 * (size_t)j;
    const double u = (vj[0] - vi[0]) * nrm[0] + (vj[1] - vi[1]) * nrm[1] + (vj[2] - vi[2]) * nrm[2];
    if (!(u < 0)) return 0; /* separating already (round-off): nothing to do */
    const double di = s->diffusion[i], dj = s->diffusion[j];
    hsbd_spheres_collide(di, dj, nrm, vi, vj);
    /* sigma_ij times the displacement change of j along n over D_j: impulse / kT */
    *virial = sph_contact_distance(s, i, j) * (-2.0 * u / (di + dj)) * (s->dt - e->t);
    s->counter[i]++;
    s->counter[j]++;
    return 1;
}

/* ---- walls ---- */

double sph_wall_time(const hsbd_spheres *s, int32_t i, double t, int *wall) {
    double p[3], best = -1;
    sph_position_at(s, i, t, p);
    const double *v = s->v + 3 * (size_t)i, half = 0.5 * s->sigma[i];
    for (int a = 0; a < s->dim; ++a) {
        if (!s->walls[a] || v[a] == 0) continue;
        const int side = v[a] > 0;
        const double plane = side ? s->length[a] - half : half;
        double h = (plane - p[a]) / v[a];
        if (!(h >= 0)) h = 0; /* past the plane by round-off, moving outwards: now */
        if (t + h < s->dt && (best < 0 || t + h < best)) {
            best = t + h;
            *wall = 2 * a + side;
        }
    }
    return best;
}

int sph_log_wall_hit(hsbd_spheres *s, sph_wall_hit hit) {
    if (s->wall_log_len == s->wall_log_cap) {
        const size_t cap = s->wall_log_cap ? 2 * s->wall_log_cap : 256;
        sph_wall_hit *log = realloc(s->wall_log, cap * sizeof *log);
        if (!log) return -1;
        s->wall_log = log;
        s->wall_log_cap = cap;
    }
    s->wall_log[s->wall_log_len++] = hit;
    return 0;
}

int sph_collide_wall(hsbd_spheres *s, const sph_event *e, int32_t group) {
    const int32_t i = e->i;
    const int w = sph_event_wall(e->j), a = w / 2, side = w % 2;
    sph_advance(s, i, e->t);
    double *x = s->x + 3 * (size_t)i, *v = s->v + 3 * (size_t)i;
    if (side ? !(v[a] > 0) : !(v[a] < 0)) return 0;
    const double half = 0.5 * s->sigma[i];
    x[a] = side ? s->length[a] - half : half; /* on the plane, round-off removed */
    /* the wall's impulse over kT: the displacement it causes, 2 |v| (dt - t), over D_i */
    const double impulse = 2.0 * fabs(v[a]) * (s->dt - e->t) / s->diffusion[i];
    v[a] = -v[a];
    s->counter[i]++;
    return sph_log_wall_hit(s, (sph_wall_hit){i, w, group, impulse}) ? -1 : 1;
}
