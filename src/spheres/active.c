/* Active Brownian particles (docs/active.md, docs/theory.md "Active Brownian particles").
 *
 * The orientation's step is exact at any dt:
 * - 2D: e = (cos theta, sin theta), theta += sqrt(2 D_r dt) xi, a rotation of e by a
 *   Gaussian angle (the angle's diffusion is free).
 * - 3D: the orientation of an isotropic rotor diffuses on SO(3), and a body vector e = R e0
 *   then performs Brownian motion on the sphere with <P_l(e(0).e(t))> = exp(-l(l+1) D_r t).
 *   The rotation R(t) is a rotation by an angle omega about a uniformly random axis, and
 *   omega's density follows from the heat kernel on SO(3) (its characters' series, summed by
 *   Poisson's formula): with y = omega / 2 and tau = D_r dt,
 *       p(y) ~ sum_k g(y - pi k),   g(y) = y sin y exp(-y^2 / tau)          (docs/theory.md).
 *   For y in [0, pi] the k = 0 term is all but e^(-pi^2 / tau) of it (< 1e-20 for
 *   tau <= 0.2; longer steps are drawn as substeps of at most 0.2). We draw it by
 *   rejection: the Gaussian rotation vector phi = sqrt(2 tau) zeta (zeta standard normal in
 *   3D, the naive small-angle step) has y = |phi| / 2 of density ~ y^2 exp(-y^2 / tau) and
 *   a uniform axis phi / |phi|; accepting it with probability sin(y) / y leaves exactly
 *   p(y) (acceptance 1 - tau / 4 + O(tau^2)). Beyond tau = 20 the orientation is uniform
 *   on the sphere to far below a double's resolution and is drawn so. No normalisation after a
 * kick: the rotation is exact and the renormalisation afterwards removes round-off only. Draws: the
 * first proposal of every particle comes from one bulk draw per step (normals of
 * HSBD_STREAM_ROTATION, 3 per particle in 3D, 1 in 2D, and uniforms of
 * HSBD_STREAM_ROTATION_ACCEPT, both by the user's index at counter = step); proposal q >= 1
 * of a particle (a rejection, or the next substep) uses counter step + q 2^44. So a
 * particle's orientation depends on (seed, step, index) alone. */
#include "spheres/active.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/scan.h"

static const double PI = 3.14159265358979323846;

int sph_active_check(const hsbd_spheres_params *p, const double *diffusion, hsbd_error *err) {
    if (!p->particle_v0 && !p->particle_rotational_diffusion) return HSBD_OK;
    if (!p->particle_v0 || !p->particle_rotational_diffusion)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "spheres: active particles need both particle_v0 and "
                              "particle_rotational_diffusion");
    for (size_t i = 0; i < p->n; ++i) {
        const double v0 = p->particle_v0[i], dr = p->particle_rotational_diffusion[i];
        if (!(v0 >= 0) || !isfinite(v0) || !(dr >= 0) || !isfinite(dr))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: particle %zu has v0 = %g, D_r = %g; allowed: both "
                                  "finite and >= 0",
                                  i, v0, dr);
        if (v0 > 0 && diffusion[i] == 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: particle %zu has D = 0 (immobile) and v0 = %g; "
                                  "allowed: v0 = 0 for immobile particles",
                                  i, v0);
    }
    return HSBD_OK;
}

void sph_active_free(hsbd_spheres *s) {
    free(s->orient), free(s->v0), free(s->rot_d), free(s->swim_weight);
    free(s->rot_normals), free(s->rot_uniforms), free(s->v_free);
}

void sph_random_orientations(hsbd_spheres *s) {
    const size_t n = s->n;
    for (size_t i = 0; i < n; ++i) {
        double *e = s->orient + 3 * i;
        if (s->dim == 2) {
            double u;
            hsbd_rng_uniforms(s->par.seed, HSBD_STREAM_ORIENTATION_INIT, 0, i, 1, &u);
            e[0] = cos(2 * PI * u), e[1] = sin(2 * PI * u), e[2] = 0;
            continue;
        }
        for (uint64_t attempt = 0;; ++attempt) { /* a normal vector's direction is uniform */
            hsbd_rng_normals(s->par.seed, HSBD_STREAM_ORIENTATION_INIT, attempt << 44, 3 * i, 3, e);
            const double norm = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
            if (norm > 1e-100) {
                for (int a = 0; a < 3; ++a)
                    e[a] /= norm;
                break;
            }
        }
    }
}

int sph_active_alloc(hsbd_spheres *s) {
    const hsbd_spheres_params *p = &s->par;
    if (!p->particle_v0) return 0;
    const size_t n = s->n;
    s->active = 1;
    s->propel = 1;
    s->orient = calloc(3 * n, sizeof *s->orient);
    s->v0 = malloc(n * sizeof *s->v0);
    s->rot_d = malloc(n * sizeof *s->rot_d);
    s->swim_weight = malloc(n * sizeof *s->swim_weight);
    s->rot_normals = malloc((size_t)s->dim * n * sizeof *s->rot_normals);
    s->rot_uniforms = malloc(n * sizeof *s->rot_uniforms);
    if (p->hard_core) s->v_free = malloc(3 * n * sizeof *s->v_free);
    if (!s->orient || !s->v0 || !s->rot_d || !s->swim_weight || !s->rot_normals ||
        !s->rot_uniforms || (p->hard_core && !s->v_free))
        return -1;
    memcpy(s->v0, p->particle_v0, n * sizeof *s->v0);
    memcpy(s->rot_d, p->particle_rotational_diffusion, n * sizeof *s->rot_d);
    for (size_t i = 0; i < n; ++i) { /* the user's order: the engine has not sorted yet */
        const double d = s->diffusion[i], k = (s->dim - 1) * s->rot_d[i];
        if (s->v0[i] > s->v0_max) s->v0_max = s->v0[i];
        s->swim_weight[i] = k > 0 && d > 0 ? s->v0[i] * p->kT / (k * d) : 0.0; /* v0 / (mu k) */
    }
    s->par.particle_v0 = s->v0; /* the copies */
    s->par.particle_rotational_diffusion = s->rot_d;
    sph_random_orientations(s);
    return 0;
}

void sph_add_propulsion(hsbd_spheres *s) {
    if (!s->propel) return;
    const long n = (long)s->n;
    const int threads = sph_threads(s);
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (long i = 0; i < n; ++i) {
        const size_t u = (size_t)s->label[i];
        const double v0 = s->v0[u];
        if (v0 == 0) continue;
        double *v = s->v + 3 * i;
        for (int a = 0; a < s->dim; ++a)
            v[a] += v0 * s->orient[3 * u + a];
    }
}

void sph_keep_free_velocities(hsbd_spheres *s) {
    if (s->v_free && s->propel) memcpy(s->v_free, s->v, 3 * s->n * sizeof *s->v);
}

/* sum_i w_i e_i . dr_i over [first, end) of the internal order, dr_i = (x - x_start) +
 * (v (dt - t_local) - v_free dt): exactly 0 for a particle no event touched */
static sph_exact_sum swim_range(const hsbd_spheres *s, size_t first, size_t end) {
    sph_exact_sum sum = 0;
    for (size_t i = first; i < end; ++i) {
        const size_t u = (size_t)s->label[i];
        const double w = s->swim_weight[u];
        if (w == 0) continue;
        const double *x = s->x + 3 * i, *x0 = s->x_start + 3 * i, *v = s->v + 3 * i;
        const double *vf = s->v_free + 3 * i, *e = s->orient + 3 * u, h = s->dt - s->t_local[i];
        double along = 0;
        for (int a = 0; a < s->dim; ++a)
            along += e[a] * ((x[a] - x0[a]) + (v[a] * h - vf[a] * s->dt));
        sum += sph_exact_term(s->swim_scale, w * along);
    }
    return sum;
}

void sph_add_swim_collisional(hsbd_spheres *s) {
    if (!s->v_free || !s->propel) return;
    const int threads = sph_threads(s);
    sph_exact_sum part[64] = {0};
    const int parts = threads < 64 ? threads : 64;
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
    for (int k = 0; k < parts; ++k)
        part[k] =
            swim_range(s, sph_range_start(s->n, parts, k), sph_range_start(s->n, parts, k + 1));
    sph_exact_sum sum = 0;
    for (int k = 0; k < parts; ++k)
        sum += part[k]; /* integers: the order does not matter */
    s->stats.swim_collisional += sph_exact_value(s->swim_scale, sum);
}

/* e rotated by the angle omega about the unit axis n (Rodrigues), renormalised */
static void rotate_about(double *e, const double n[3], double omega) {
    const double c = cos(omega), sn = sin(omega), along = n[0] * e[0] + n[1] * e[1] + n[2] * e[2];
    const double cross[3] = {n[1] * e[2] - n[2] * e[1], n[2] * e[0] - n[0] * e[2],
                             n[0] * e[1] - n[1] * e[0]};
    double r[3], norm = 0;
    for (int a = 0; a < 3; ++a)
        r[a] = e[a] * c + cross[a] * sn + n[a] * along * (1 - c), norm += r[a] * r[a];
    norm = sqrt(norm);
    for (int a = 0; a < 3; ++a)
        e[a] = r[a] / norm;
}

/* Proposal q of user particle i: three normals and a uniform (q = 0: the bulk draw). */
static void proposal(const hsbd_spheres *s, size_t i, uint64_t q, double zeta[3], double *u) {
    if (q == 0) {
        memcpy(zeta, s->rot_normals + 3 * i, 3 * sizeof *zeta);
        *u = s->rot_uniforms[i];
        return;
    }
    const uint64_t counter = s->step + (q << 44);
    hsbd_rng_normals(s->par.seed, HSBD_STREAM_ROTATION, counter, 3 * i, 3, zeta);
    hsbd_rng_uniforms(s->par.seed, HSBD_STREAM_ROTATION_ACCEPT, counter, i, 1, u);
}

/* Beyond this D_r dt the orientation forgets where it was: <P_l> = e^(-l(l+1) tau) <
 * e^-40, far below a double's resolution, so it is drawn uniformly on the sphere. */
#define ROTATION_TAU_UNIFORM 20.0

/* Brownian motion of e on the unit sphere over tau = D_r dt, exactly (file comment). */
static void rotate_3d(const hsbd_spheres *s, size_t i, double tau) {
    if (tau > ROTATION_TAU_UNIFORM) { /* the first proposal's direction: uniform */
        double *e = s->orient + 3 * i;
        for (uint64_t q = 0;; ++q) {
            double zeta[3], u;
            proposal(s, i, q, zeta, &u);
            const double norm = sqrt(zeta[0] * zeta[0] + zeta[1] * zeta[1] + zeta[2] * zeta[2]);
            if (!(norm > 1e-100)) continue;
            for (int a = 0; a < 3; ++a)
                e[a] = zeta[a] / norm;
            return;
        }
    }
    const int substeps = tau > SPH_ROTATION_TAU_MAX ? (int)ceil(tau / SPH_ROTATION_TAU_MAX) : 1;
    const double amp = sqrt(2 * tau / substeps); /* the rotation vector's rms per axis */
    uint64_t q = 0;
    for (int sub = 0; sub < substeps;) {
        double zeta[3], u;
        proposal(s, i, q++, zeta, &u);
        const double omega = amp * sqrt(zeta[0] * zeta[0] + zeta[1] * zeta[1] + zeta[2] * zeta[2]);
        const double y = 0.5 * omega;
        if (!(y < PI) || (y > 0 && u * y >= sin(y))) continue; /* rejected: p = sin(y) / y */
        if (omega > 0) {
            const double n[3] = {amp * zeta[0] / omega, amp * zeta[1] / omega,
                                 amp * zeta[2] / omega};
            rotate_about(s->orient + 3 * i, n, omega);
        }
        ++sub;
    }
}

/* the particles [first, end) of the user's order */
static void rotate_range(hsbd_spheres *s, size_t first, size_t end) {
    const size_t d = (size_t)s->dim;
    hsbd_rng_normals(s->par.seed, HSBD_STREAM_ROTATION, s->step, d * first, d * (end - first),
                     s->rot_normals + d * first);
    if (s->dim == 3)
        hsbd_rng_uniforms(s->par.seed, HSBD_STREAM_ROTATION_ACCEPT, s->step, first, end - first,
                          s->rot_uniforms + first);
    for (size_t i = first; i < end; ++i) {
        const double tau = s->rot_d[i] * s->dt;
        if (tau == 0) continue;
        if (s->dim == 3) {
            rotate_3d(s, i, tau);
            continue;
        }
        const double dtheta = sqrt(2 * tau) * s->rot_normals[i]; /* exact: a free angle */
        double *e = s->orient + 3 * i;
        const double c = cos(dtheta), sn = sin(dtheta);
        const double ex = c * e[0] - sn * e[1], ey = sn * e[0] + c * e[1];
        const double norm = sqrt(ex * ex + ey * ey);
        e[0] = ex / norm, e[1] = ey / norm;
    }
}

void sph_rotate(hsbd_spheres *s) {
    if (!s->propel) return;
    const int threads = sph_threads(s);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)
    for (int k = 0; k < threads; ++k)
        rotate_range(s, sph_range_start(s->n, threads, k), sph_range_start(s->n, threads, k + 1));
}

/* |e| over the first dim components */
static double norm_of(const double *e, int dim) {
    double sum = 0;
    for (int a = 0; a < dim; ++a)
        sum += e[a] * e[a];
    return sqrt(sum);
}

int hsbd_spheres_set_orientations(hsbd_spheres *s, const double *e, hsbd_error *err) {
    hsbd_error_clear(err);
    if (!s->active)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "spheres: orientations given to a system without active particles");
    for (size_t i = 0; i < s->n; ++i) {
        const double norm = norm_of(e + 3 * i, s->dim);
        if (!isfinite(norm) || !(norm > 0))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "spheres: the orientation of particle %zu is not a finite "
                                  "non-zero vector; allowed: any direction",
                                  i + 1);
    }
    for (size_t i = 0; i < s->n; ++i) {
        const double norm = norm_of(e + 3 * i, s->dim);
        for (int a = 0; a < 3; ++a)
            s->orient[3 * i + a] = a < s->dim ? e[3 * i + a] / norm : 0.0;
    }
    return HSBD_OK;
}
