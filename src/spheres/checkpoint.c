/* EDBD checkpoints (see checkpoint.h). Per-particle values are written in the user's
 * order with the label that gives the internal one; a load puts them into the fresh
 * engine (user order), then permutes it into the saved order as a spatial sort would. */
#include "spheres/checkpoint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "spheres/groups.h"
#include "spheres/neighbours.h"
#include "spheres/order.h"
#include "spheres/state.h"

/* a per-particle array of `width` doubles in user order */
static void put_user_doubles(hsbd_writer *w, const hsbd_spheres *s, const double *v, size_t width,
                             double *tmp) {
    for (size_t i = 0; i < s->n; ++i)
        memcpy(tmp + width * (size_t)s->label[i], v + width * i, width * sizeof *v);
    hsbd_put_f64s(w, tmp, width * s->n);
}

void hsbd_spheres_save(const hsbd_spheres *s, hsbd_writer *w) {
    const size_t n = s->n;
    hsbd_put_tag(w, "spheres");
    const uint64_t shape[3] = {n, (uint64_t)s->dim, (uint64_t)s->par.hard_core};
    hsbd_put_u64s(w, shape, 3);
    double *tmp = malloc(3 * n * sizeof *tmp);
    int64_t *itmp = malloc(3 * n * sizeof *itmp);
    int *label = malloc(n * sizeof *label);
    if (!tmp || !itmp || !label) {
        free(tmp), free(itmp), free(label);
        w->oom = 1;
        return;
    }
    put_user_doubles(w, s, s->x, 3, tmp);
    put_user_doubles(w, s, s->centre, 3, tmp);
    put_user_doubles(w, s, s->sigma, 1, tmp);
    put_user_doubles(w, s, s->diffusion, 1, tmp);
    for (size_t i = 0; i < n; ++i)
        memcpy(itmp + 3 * (size_t)s->label[i], s->image + 3 * i, 3 * sizeof *itmp);
    hsbd_put_i64s(w, itmp, 3 * n);
    for (size_t i = 0; i < n; ++i)
        label[i] = s->label[i];
    hsbd_put_ints(w, label, n);
    hsbd_put_u64(w, s->step);
    const double clock[5] = {s->time, s->dt, s->sort_clock, s->shell, s->stats.virial};
    hsbd_put_f64s(w, clock, 5);
    const uint64_t stats[6] = {s->stats.steps,        s->stats.collisions,   s->stats.shell_updates,
                               s->stats.stale_events, s->stats.group_reruns, sph_groups_pause(s)};
    hsbd_put_u64s(w, stats, 6);
    if (s->any_walls) { /* only then: the periodic checkpoints keep their bytes */
        hsbd_put_f64s(w, s->wall_sum, 6 * s->nspecies);
        const uint64_t walls[2] = {s->stats.wall_collisions, s->stats.wall_pushes};
        hsbd_put_u64s(w, walls, 2);
    }
    if (s->pair_exact) hsbd_put_u64(w, s->stats.pair_corrections); /* only then, as the walls */
    if (s->active) { /* only then, too: the orientations (user order) and the swim sum */
        hsbd_put_f64s(w, s->orient, 3 * n);
        hsbd_put_f64(w, s->stats.swim_collisional);
    }
    free(tmp), free(itmp), free(label);
}

/* a per-particle array in user order into the engine's (still user-order) array */
static int get_doubles(hsbd_reader *r, double *v, size_t count) {
    if (hsbd_get_f64s(r, v, count)) return -1;
    for (size_t k = 0; k < count; ++k)
        if (!isfinite(v[k])) return hsbd_reader_fail(r, "spheres: a value is not finite");
    return 0;
}

static int check_positions(const hsbd_spheres *s, const double *x, hsbd_reader *r) {
    for (size_t i = 0; i < s->n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double box = s->box[a], tol = 1e-9 * box; /* wrapping rounds to box */
            if (a < s->dim ? !(x[3 * i + a] >= -tol && x[3 * i + a] <= box + tol)
                           : x[3 * i + a] != 0)
                return hsbd_reader_fail(r, "spheres: a position outside the box");
        }
    return 0;
}

int hsbd_spheres_load(hsbd_spheres *s, hsbd_reader *r) {
    const size_t n = s->n;
    uint64_t shape[3];
    if (hsbd_get_tag(r, "spheres") || hsbd_get_u64s(r, shape, 3)) return -1;
    if (shape[0] != n || shape[1] != (uint64_t)s->dim || shape[2] != (uint64_t)s->par.hard_core)
        return hsbd_reader_fail(r, "spheres: another system");
    if (s->reordered && sph_restore_user_order(s))
        return hsbd_reader_oom(r, "the particles' order");
    double *sig = malloc(2 * n * sizeof *sig);
    int *label = malloc(n * sizeof *label);
    int32_t *order = malloc(n * sizeof *order);
    unsigned char *seen = calloc(n, 1);
    int rc = sig && label && order && seen ? 0 : hsbd_reader_oom(r, "the particles");
    if (!rc)
        rc = get_doubles(r, s->x, 3 * n) || check_positions(s, s->x, r) ||
             get_doubles(r, s->centre, 3 * n) || check_positions(s, s->centre, r) ||
             get_doubles(r, sig, n) || get_doubles(r, sig + n, n) ||
             hsbd_get_i64s(r, s->image, 3 * n) || hsbd_get_ints(r, label, n);
    /* the sizes and D are those of the configuration (read again from its inputs) */
    for (size_t i = 0; !rc && i < n; ++i)
        if (sig[i] != s->sigma[i] || sig[n + i] != s->diffusion[i])
            rc = hsbd_reader_fail(r, "spheres: particles of other sizes or D");
    for (size_t i = 0; !rc && i < n; ++i) {
        if (label[i] < 0 || (size_t)label[i] >= n || seen[label[i]])
            rc = hsbd_reader_fail(r, "spheres: the order is not a permutation");
        else
            seen[label[i]] = 1, order[i] = label[i];
    }
    uint64_t step = 0, stats[6];
    double clock[5];
    if (!rc)
        rc = hsbd_get_u64(r, &step) || hsbd_get_f64s(r, clock, 5) || hsbd_get_u64s(r, stats, 6);
    if (!rc && (clock[1] != s->dt || !isfinite(clock[0]) || clock[3] != s->shell))
        rc = hsbd_reader_fail(r, "spheres: another time step or shell");
    free(sig), free(label), free(seen);
    if (rc) return free(order), -1;
    memset(s->t_local, 0, n * sizeof *s->t_local);
    memset(s->counter, 0, n * sizeof *s->counter);
    int moved = 0;
    for (size_t i = 0; i < n && !moved; ++i)
        moved = order[i] != (int32_t)i;
    if (moved && sph_set_order(s, order)) rc = hsbd_reader_oom(r, "the particles' order");
    free(order);
    if (rc) return -1;
    s->step = step;
    s->time = clock[0];
    s->dt = clock[1];
    s->sort_clock = s->sort_enabled ? clock[2] : s->sort_clock;
    s->stats = (hsbd_spheres_stats){.steps = stats[0],
                                    .collisions = stats[1],
                                    .shell_updates = stats[2],
                                    .stale_events = stats[3],
                                    .group_reruns = stats[4],
                                    .virial = clock[4]};
    uint64_t walls[2] = {0, 0};
    if (s->any_walls &&
        (get_doubles(r, s->wall_sum, 6 * s->nspecies) || hsbd_get_u64s(r, walls, 2)))
        return -1;
    s->stats.wall_collisions = walls[0];
    s->stats.wall_pushes = walls[1];
    if (s->pair_exact && hsbd_get_u64(r, &s->stats.pair_corrections)) return -1;
    if (s->active) {
        if (get_doubles(r, s->orient, 3 * n) || hsbd_get_f64(r, &s->stats.swim_collisional))
            return -1;
        for (size_t i = 0; i < n; ++i) {
            const double *e = s->orient + 3 * i;
            if (fabs(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] - 1) > 1e-9 ||
                (s->dim == 2 && e[2] != 0))
                return hsbd_reader_fail(r, "spheres: an orientation is not a unit vector");
        }
    }
    if (stats[5] > 1000) return hsbd_reader_fail(r, "spheres: an unknown event-order state");
    if (sph_groups_set_pause(s, (unsigned)stats[5])) return hsbd_reader_oom(r, "the event groups");
    if (sph_rebuild_rows(s) != HSBD_OK) return hsbd_reader_oom(r, "the neighbour lists");
    return 0;
}
