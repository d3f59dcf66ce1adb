/* Events group by group (groups.h; docs/spheres.md). Why it is exact: a group runs its
 * own events in time order, and every straight segment a group creates is tested, when
 * it is created, against all neighbours outside the group on the paths they really take:
 * a particle whose group has not run yet is still on its start-of-step line, one whose
 * group ran is on its logged segments. Two segments of different groups are therefore
 * tested against each other once, when the later-made one appears (start-of-step lines
 * against each other in the half scan). A hit joins the two groups: at once when the
 * other group is still on its start lines at the present time (it has not run, and its
 * first event is not earlier), else by re-running the joined group from the step's
 * start; the particles it puts back on their start lines are first tested against the
 * groups that ran, which saw only their earlier paths. Shells moved inside a step only
 * add pairs (the old shell stays registered until the step ends), so groups running out
 * of time order never miss a pair. */
#include "spheres/groups.h"

#include <stdlib.h>
#include <string.h>

#include "spheres/events.h"
#include "spheres/neighbours.h"
#include "spheres/scan.h"
#include "spheres/slab_queue.h"

/* One logged straight segment of a particle: from time t at position x with velocity v.
 * The first segment of a particle in a step also keeps its shell centre c at the start. */
typedef struct sph_segment {
    double t, x[3], v[3], c[3];
    int32_t prev;      /* earlier segment of the same particle, -1 for the first */
    int32_t next_head; /* first segments only: the next particle's in the same group, -1 */
    int32_t particle;
} sph_segment;

/* A write to an int32 of the shared state that an undone first-pass run takes back. */
typedef struct sph_undo {
    int32_t *at, old;
} sph_undo;

/* Where a particle of a group that ran stood before a first-pass run rewound the group:
 * its position, velocity and local time (a collision found separating by round-off moves
 * the pair to its time without a new segment, so these need not be its last segment's),
 * its last segment and its history flag. */
typedef struct sph_ran_path {
    double x[3], v[3], t_local;
    int32_t particle, last;
    uint8_t history;
} sph_ran_path;

/* What a thread of the first pass needs of its own (the rest of the state is shared). */
typedef struct sph_worker {
    sph_calendar calendar;
    int32_t *scan_j;
    double *scan_t;
    size_t scan_cap;
    int32_t *lone; /* the particles a run joined that had met nobody: undone with it */
    size_t lone_len, lone_cap;
    int32_t *joined; /* the pending groups of its slab a run joined: undone with it */
    size_t joined_len, joined_cap;
    sph_undo *undo; /* the writes of a run's re-runs (joins), taken back if it is undone */
    size_t undo_len, undo_cap;
    sph_ran_path *ran; /* the paths of the groups that ran that a run rewound */
    size_t ran_len, ran_cap;
    int32_t *rewound; /* its list of rewound particles (room for every particle) */
    size_t rewound_cap;
} sph_worker;

struct sph_groups {
    size_t n;
    /* union-find over particles: >= 0 parent; roots hold -1 (no group) or -2 - group */
    int32_t *parent;
    int32_t *last_segment; /* per particle, -1 while it is on its start-of-step path */
    uint8_t *moved;        /* per particle: re-centred inside the step (extra shells) */
    uint8_t *history;      /* per particle: its group ran and it has several segments */
    /* the start-of-step hits (j = SPH_EVENT_SHELL for a shell exit), then by group */
    size_t hit_cap, nhits;
    int32_t *hit_i, *hit_j, *hit_group;
    double *hit_t;
    int32_t *by_i, *by_j;
    double *by_t;
    /* groups: their hits by_*[start, start + count), state, constituents, rollback data */
    size_t group_cap, ngroups;
    int32_t *start, *count, *state, *root, *next_part, *first_segment;
    double *first_time;
    sph_exact_sum *virial;
    uint64_t *collisions, *shell_updates;
    /* the segment log of the step */
    sph_segment *seg;
    size_t seg_cap, nseg;
    /* shells added inside the step: a second grid of centres, entries -> particles, each
     * particle's entries chained (extra_head, extra_next) with their centres (a re-run
     * moving a shell to a centre it had already taken adds nothing) */
    hsbd_cells extra;
    int32_t *extra_particle, *extra_next, *extra_head;
    double *extra_sigma, *extra_centre;
    size_t extra_cap, nextra;
    int32_t *moved_list;
    size_t nmoved;
    /* particles put back on their start lines by a rewind, not yet tested against the
     * groups that ran (queued: in the list) */
    int32_t *rewound;
    uint8_t *queued;
    size_t nrewound;
    uint64_t replayed; /* events of the step in runs that ended in a join */
    uint64_t played;   /* all events of the step */
    unsigned pause;    /* AUTO: steps left on the global calendar after costly re-runs */
    /* the first pass, on threads: slabs along one periodic axis (see run_slabs) */
    int nslabs, slab_axis; /* nslabs 0: no first pass */
    double slab_scale;     /* slabs per unit length */
    double slab_shift;     /* 0, or 0.5 in the second round: the slabs moved half a width */
    int32_t *group_slab;   /* per group: the slab holding all its particles, or -1 */
    int32_t *slab_groups;  /* the groups of slab k in order, from slab_first[k]; then
                            * the groups left for the serial pass */
    size_t slab_first[SPH_MAX_SLABS + 1];
    size_t slab_seg[SPH_MAX_SLABS + 1]; /* slab k logs in [slab_seg[k], slab_seg[k + 1]) */
    sph_worker *workers;
    size_t nworkers;
    /* set in a worker's copy of this struct: the slab it runs; a run that would reach
     * outside it stops and waits for the next round or the serial pass */
    int speculative;
    int slab;
    int log_full; /* the slab's share of the log filled up (not out of memory) */
    sph_worker *worker;
};

enum { GROUP_PENDING, GROUP_ACTIVE, GROUP_DONE, GROUP_JOINED };

/* AUTO: a step whose largest group holds more than 1 / LARGEST_GROUP_SHARE of the hits
 * runs on the global calendar (dense or long steps: the groups percolate, nothing to
 * gain); after a step that re-ran more than 1 / REPLAY_SHARE of its events, the next
 * PAUSE_STEPS steps do. Both depend on the state only: runs stay reproducible. */
enum { LARGEST_GROUP_SHARE = 4, REPLAY_SHARE = 4, PAUSE_STEPS = 64 };

/* AUTO's size threshold: lower when the groups' first pass has slabs (threads can share
 * it). Never the thread count itself: the two orders may differ in the last bits (shells
 * far below the default: docs/spheres.md), so one run must take the same order on any
 * number of threads. */
static size_t groups_min_n(const hsbd_spheres *s) {
    int axis;
    if (s->par.groups_min_n) return s->par.groups_min_n;
    return sph_slabs(s, &axis) ? HSBD_SPHERES_GROUPS_MIN_N_THREADS : HSBD_SPHERES_GROUPS_MIN_N;
}

int sph_groups_wanted(hsbd_spheres *s) {
    switch (s->par.event_order) {
    case HSBD_EVENTS_GLOBAL:
        return 0;
    case HSBD_EVENTS_GROUPS:
        return 1;
    default:
        if (s->n < groups_min_n(s)) return 0;
        if (s->groups && s->groups->pause) return s->groups->pause--, 0;
        return 1;
    }
}

void sph_groups_free(sph_groups *g) {
    if (!g) return;
    free(g->parent);
    free(g->last_segment);
    free(g->moved);
    free(g->history);
    free(g->hit_i);
    free(g->hit_j);
    free(g->hit_group);
    free(g->hit_t);
    free(g->by_i);
    free(g->by_j);
    free(g->by_t);
    free(g->start);
    free(g->count);
    free(g->state);
    free(g->root);
    free(g->next_part);
    free(g->first_segment);
    free(g->first_time);
    free(g->virial);
    free(g->collisions);
    free(g->shell_updates);
    free(g->seg);
    hsbd_cells_free(&g->extra);
    free(g->extra_particle);
    free(g->extra_next);
    free(g->extra_head);
    free(g->extra_sigma);
    free(g->extra_centre);
    free(g->moved_list);
    free(g->rewound);
    free(g->queued);
    free(g->group_slab);
    free(g->slab_groups);
    for (size_t w = 0; w < g->nworkers; ++w) {
        sph_calendar_free(&g->workers[w].calendar);
        free(g->workers[w].scan_j);
        free(g->workers[w].scan_t);
        free(g->workers[w].lone);
        free(g->workers[w].joined);
        free(g->workers[w].undo);
        free(g->workers[w].ran);
        free(g->workers[w].rewound);
    }
    free(g->workers);
    free(g);
}

/* realloc of an array of `cap` elements of `size` bytes; the old one stays on failure */
static int grow_array(void *p, size_t cap, size_t size) {
    void *q = realloc(*(void **)p, cap * size);
    if (!q) return -1;
    *(void **)p = q;
    return 0;
}

static int alloc_particles(hsbd_spheres *s) {
    if (s->groups) return 0;
    const size_t n = s->n;
    sph_groups *g = calloc(1, sizeof *g);
    if (!g) return -1;
    g->parent = malloc(n * sizeof *g->parent);
    g->last_segment = malloc(n * sizeof *g->last_segment);
    g->moved = calloc(n, sizeof *g->moved);
    g->history = malloc(n * sizeof *g->history);
    g->moved_list = malloc(n * sizeof *g->moved_list);
    g->rewound = malloc(n * sizeof *g->rewound);
    g->queued = calloc(n, sizeof *g->queued);
    g->extra_cap = 256; /* the kernels read sigma[0] for empty slots: never empty arrays */
    g->extra_particle = malloc(g->extra_cap * sizeof *g->extra_particle);
    g->extra_next = malloc(g->extra_cap * sizeof *g->extra_next);
    g->extra_head = malloc(n * sizeof *g->extra_head);
    g->extra_sigma = calloc(g->extra_cap, sizeof *g->extra_sigma);
    g->extra_centre = malloc(3 * g->extra_cap * sizeof *g->extra_centre);
    if (g->extra_head)
        for (size_t i = 0; i < n; ++i)
            g->extra_head[i] = -1;
    if (!g->parent || !g->last_segment || !g->moved || !g->history || !g->moved_list ||
        !g->rewound || !g->queued || !g->extra_particle || !g->extra_next || !g->extra_head ||
        !g->extra_sigma || !g->extra_centre ||
        hsbd_cells_init(&g->extra, s->dim, s->box, s->sigma_max + sph_shell_reach(s),
                        g->extra_cap)) {
        sph_groups_free(g);
        return -1;
    }
    g->n = n;
    s->groups = g;
    return 0;
}

int sph_groups_begin(hsbd_spheres *s) {
    if (alloc_particles(s)) return -1;
    sph_groups *g = s->groups;
    memset(g->parent, 0xff, s->n * sizeof *g->parent); /* -1: a root without a group */
    memset(g->last_segment, 0xff, s->n * sizeof *g->last_segment);
    memset(g->history, 0, s->n * sizeof *g->history);
    g->nhits = g->ngroups = g->nseg = 0;
    g->replayed = g->played = 0;
    return 0;
}

static int32_t find_root(sph_groups *g, int32_t i) {
    while (g->parent[i] >= 0) {
        const int32_t p = g->parent[i];
        /* path halving, not on threads: the chain may pass through other slabs */
        if (!g->speculative && g->parent[p] >= 0) g->parent[i] = g->parent[p];
        i = p;
    }
    return i;
}

static void unite(sph_groups *g, int32_t i, int32_t j) {
    i = find_root(g, i);
    j = find_root(g, j);
    if (i == j) return;
    if (i < j)
        g->parent[j] = i;
    else
        g->parent[i] = j;
}

static int grow_hits(sph_groups *g) {
    const size_t cap = g->hit_cap ? 2 * g->hit_cap : 4096;
    if (grow_array(&g->hit_i, cap, sizeof *g->hit_i) ||
        grow_array(&g->hit_j, cap, sizeof *g->hit_j) ||
        grow_array(&g->hit_group, cap, sizeof *g->hit_group) ||
        grow_array(&g->hit_t, cap, sizeof *g->hit_t) ||
        grow_array(&g->by_i, cap, sizeof *g->by_i) || grow_array(&g->by_j, cap, sizeof *g->by_j) ||
        grow_array(&g->by_t, cap, sizeof *g->by_t))
        return -1;
    g->hit_cap = cap;
    return 0;
}

int sph_groups_add_hit(hsbd_spheres *s, double t, int32_t i, int32_t j) {
    sph_groups *g = s->groups;
    if (g->nhits == g->hit_cap && grow_hits(g)) return -1;
    g->hit_i[g->nhits] = i;
    g->hit_j[g->nhits] = j;
    g->hit_t[g->nhits++] = t;
    if (j >= 0) unite(g, i, j);
    return 0;
}

static int grow_groups(sph_groups *g) {
    const size_t cap = g->group_cap ? 2 * g->group_cap : 1024;
    if (grow_array(&g->start, cap, sizeof *g->start) ||
        grow_array(&g->count, cap, sizeof *g->count) ||
        grow_array(&g->state, cap, sizeof *g->state) ||
        grow_array(&g->root, cap, sizeof *g->root) ||
        grow_array(&g->next_part, cap, sizeof *g->next_part) ||
        grow_array(&g->first_segment, cap, sizeof *g->first_segment) ||
        grow_array(&g->first_time, cap, sizeof *g->first_time) ||
        grow_array(&g->virial, cap, sizeof *g->virial) ||
        grow_array(&g->collisions, cap, sizeof *g->collisions) ||
        grow_array(&g->shell_updates, cap, sizeof *g->shell_updates) ||
        grow_array(&g->group_slab, cap, sizeof *g->group_slab) ||
        grow_array(&g->slab_groups, cap, sizeof *g->slab_groups))
        return -1;
    g->group_cap = cap;
    return 0;
}

/* Numbers the groups in the order of their first hit (memory order, so space order) and
 * sorts the hits by group. Returns the largest group's hit count, or -1 (out of memory). */
static long number_groups(hsbd_spheres *s) {
    sph_groups *g = s->groups;
    for (size_t k = 0; k < g->nhits; ++k) {
        const int32_t r = find_root(g, g->hit_i[k]);
        if (g->parent[r] == -1) {
            if (g->ngroups == g->group_cap && grow_groups(g)) return -1;
            const size_t a = g->ngroups++;
            g->count[a] = 0;
            g->state[a] = GROUP_PENDING;
            g->root[a] = r;
            g->next_part[a] = g->first_segment[a] = -1;
            g->first_time[a] = s->dt;
            g->virial[a] = 0;
            g->collisions[a] = g->shell_updates[a] = 0;
            g->parent[r] = -2 - (int32_t)a;
        }
        const int32_t a = -2 - g->parent[r];
        g->hit_group[k] = a;
        g->count[a]++;
        if (g->hit_t[k] < g->first_time[a]) g->first_time[a] = g->hit_t[k];
    }
    long largest = 0, sum = 0;
    for (size_t a = 0; a < g->ngroups; ++a) {
        g->start[a] = (int32_t)sum;
        sum += g->count[a];
        if (g->count[a] > largest) largest = g->count[a];
        g->count[a] = 0;
    }
    for (size_t k = 0; k < g->nhits; ++k) {
        const int32_t a = g->hit_group[k], o = g->start[a] + g->count[a]++;
        g->by_i[o] = g->hit_i[k];
        g->by_j[o] = g->hit_j[k];
        g->by_t[o] = g->hit_t[k];
    }
    return largest;
}

/* ---- the segment log ---- */

static int32_t new_segment(hsbd_spheres *s, int32_t p, double t) {
    sph_groups *g = s->groups;
    if (g->nseg == g->seg_cap) {
        if (g->speculative) return g->log_full = 1, -1; /* the slab's share is used up */
        const size_t cap = g->seg_cap ? 2 * g->seg_cap : 1024;
        if (grow_array(&g->seg, cap, sizeof *g->seg)) return -1;
        g->seg_cap = cap;
    }
    sph_segment *e = &g->seg[g->nseg];
    e->t = t;
    memcpy(e->x, s->x + 3 * (size_t)p, sizeof e->x);
    memcpy(e->v, s->v + 3 * (size_t)p, sizeof e->v);
    e->prev = g->last_segment[p];
    e->next_head = -1;
    e->particle = p;
    g->last_segment[p] = (int32_t)g->nseg;
    return (int32_t)g->nseg++;
}

/* Before a particle of group a first moves in the step: log its start (for a re-run).
 * Returns 0, or -1 when out of memory. */
static int log_start(hsbd_spheres *s, int32_t a, int32_t p) {
    sph_groups *g = s->groups;
    if (g->last_segment[p] >= 0) return 0;
    const int32_t k = new_segment(s, p, 0.0);
    if (k < 0) return -1;
    memcpy(g->seg[k].c, s->centre + 3 * (size_t)p, sizeof g->seg[k].c);
    g->seg[k].next_head = g->first_segment[a];
    g->first_segment[a] = k;
    return 0;
}

/* The wall events group a ran leave the step's log. */
static void drop_wall_hits(hsbd_spheres *s, int32_t a) {
    size_t kept = 0;
    for (size_t k = 0; k < s->wall_log_len; ++k)
        if (s->wall_log[k].group != a) s->wall_log[kept++] = s->wall_log[k];
    s->wall_log_len = kept;
}

/* Puts every particle group a moved back on its start-of-step line. */
static void rewind_group(hsbd_spheres *s, int32_t a) {
    sph_groups *g = s->groups;
    for (int32_t k = g->first_segment[a]; k >= 0; k = g->seg[k].next_head) {
        const sph_segment *e = &g->seg[k];
        const int32_t p = e->particle;
        memcpy(s->x + 3 * (size_t)p, e->x, sizeof e->x);
        memcpy(s->v + 3 * (size_t)p, e->v, sizeof e->v);
        memcpy(s->centre + 3 * (size_t)p, e->c, sizeof e->c);
        s->t_local[p] = 0;
        g->last_segment[p] = -1;
        g->history[p] = 0;
        if (!g->queued[p]) g->queued[p] = 1, g->rewound[g->nrewound++] = p;
    }
    g->first_segment[a] = -1;
    if (!g->speculative) drop_wall_hits(s, a);
}

static void forget_rewound(sph_groups *g) {
    while (g->nrewound)
        g->queued[g->rewound[--g->nrewound]] = 0;
}

/* Appends x to a worker's list (len, cap) of `size`-byte items. Returns 0, or -1 when out
 * of memory. */
static int note_item(void *list, size_t *len, size_t *cap, const void *x, size_t size) {
    if (*len == *cap) {
        const size_t more = *cap ? 2 * *cap : 64;
        if (grow_array(list, more, size)) return -1;
        *cap = more;
    }
    memcpy(*(unsigned char **)list + *len * size, x, size);
    (*len)++;
    return 0;
}

static int note(int32_t **list, size_t *len, size_t *cap, int32_t x) {
    return note_item(list, len, cap, &x, sizeof x);
}

/* *at = value; in a first-pass run noted first, so that undoing the run takes it back.
 * Returns 0, or -1 when out of memory (nothing written). */
static int set_undoable(sph_groups *g, int32_t *at, int32_t value) {
    if (g->speculative) {
        const sph_undo u = {at, *at};
        if (note_item(&g->worker->undo, &g->worker->undo_len, &g->worker->undo_cap, &u, sizeof u))
            return -1;
    }
    *at = value;
    return 0;
}

/* Before a first-pass run rewinds group b, which ran: where b's particles stood, so that
 * undoing the run can put them back. Returns 0, or -1 when out of memory. */
static int keep_ran_paths(const hsbd_spheres *s, int32_t b) {
    sph_groups *g = s->groups;
    sph_worker *w = g->worker;
    for (int32_t k = g->first_segment[b]; k >= 0; k = g->seg[k].next_head) {
        const int32_t p = g->seg[k].particle;
        sph_ran_path r = {.t_local = s->t_local[p],
                          .particle = p,
                          .last = g->last_segment[p],
                          .history = g->history[p]};
        memcpy(r.x, s->x + 3 * (size_t)p, sizeof r.x);
        memcpy(r.v, s->v + 3 * (size_t)p, sizeof r.v);
        if (note_item(&w->ran, &w->ran_len, &w->ran_cap, &r, sizeof r)) return -1;
    }
    const sph_undo u = {&g->first_segment[b], g->first_segment[b]};
    return note_item(&w->undo, &w->undo_len, &w->undo_cap, &u, sizeof u);
}

/* Group b joins the running group a, whose events then start again from the step's
 * start (b's results, if it ran, are undone). Returns 0, or -1 when out of memory. */
static int join_and_rewind(hsbd_spheres *s, int32_t a, int32_t b) {
    sph_groups *g = s->groups;
    if (g->state[b] == GROUP_DONE) {
        if (g->speculative && keep_ran_paths(s, b)) return -1;
        rewind_group(s, b);
    }
    rewind_group(s, a);
    int32_t last = a;
    while (g->next_part[last] >= 0)
        last = g->next_part[last];
    if (set_undoable(g, &g->parent[g->root[b]], g->root[a]) ||
        set_undoable(g, &g->state[b], GROUP_JOINED) || set_undoable(g, &g->next_part[last], b))
        return -1;
    s->stats.group_reruns++;
    return 0;
}

/* The start-of-step events of group b into the calendar. Returns 0, or -1 when out of
 * memory (so do the functions below that return int). */
static int push_group_hits(hsbd_spheres *s, int32_t b) {
    const sph_groups *g = s->groups;
    for (int32_t k = g->start[b]; k < g->start[b] + g->count[b]; ++k)
        if (sph_push_event(s, g->by_t[k], g->by_i[k], g->by_j[k])) return -1;
    return 0;
}

/* Group b, still on its start lines up to the present, joins the running group a. */
static int join_pending(hsbd_spheres *s, int32_t a, int32_t b) {
    sph_groups *g = s->groups;
    g->parent[g->root[b]] = g->root[a];
    g->state[b] = GROUP_JOINED;
    g->next_part[b] = g->next_part[a]; /* b has no parts of its own yet */
    g->next_part[a] = b;
    return push_group_hits(s, b);
}

/* ---- shells moved inside a step ---- */

static int in_row(const hsbd_spheres *s, int32_t i, int32_t j) {
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    for (uint32_t k = 0; k < s->nb_count[i]; ++k)
        if (row[k] == j) return 1;
    return 0;
}

static int add_pair_once(hsbd_spheres *s, int32_t i, int32_t j) {
    if (j == i || in_row(s, i, j)) return 0;
    return sph_nb_add(s, i, j) || sph_nb_add(s, j, i) ? -1 : 0;
}

/* Registers i's new shell centre in the second grid, unless i had that centre already in
 * this step (a re-run replays its shell moves bit for bit: without this check a group
 * re-run many times filled the grid's cells with copies). */
static int add_extra_shell(hsbd_spheres *s, int32_t i) {
    sph_groups *g = s->groups;
    const double *c = s->centre + 3 * (size_t)i;
    for (int32_t e = g->extra_head[i]; e >= 0; e = g->extra_next[e])
        if (!memcmp(g->extra_centre + 3 * (size_t)e, c, 3 * sizeof *c)) return 0;
    if (g->nextra == g->extra_cap) {
        const size_t cap = 2 * g->extra_cap;
        if (grow_array(&g->extra_particle, cap, sizeof *g->extra_particle) ||
            grow_array(&g->extra_next, cap, sizeof *g->extra_next) ||
            grow_array(&g->extra_sigma, cap, sizeof *g->extra_sigma) ||
            grow_array(&g->extra_centre, 3 * cap, sizeof *g->extra_centre) ||
            hsbd_cells_reserve_points(&g->extra, cap))
            return -1;
        g->extra_cap = cap;
    }
    const int32_t e = (int32_t)g->nextra;
    if (hsbd_cells_insert(&g->extra, e, c)) return -1;
    g->extra_particle[e] = i;
    g->extra_sigma[e] = s->sigma[i];
    memcpy(g->extra_centre + 3 * (size_t)e, c, 3 * sizeof *c);
    g->extra_next[e] = g->extra_head[i];
    g->extra_head[i] = e;
    g->nextra++;
    return 0;
}

/* Re-centres i's shell at its position at time t, keeping the old one registered: pairs
 * with every shell (old or new) that overlaps the new one are added, none removed. */
static int recentre_adding(hsbd_spheres *s, int32_t i, double t) {
    sph_groups *g = s->groups;
    if (!g->moved[i]) {
        g->moved[i] = 1;
        g->moved_list[g->nmoved++] = i;
    }
    double x[3];
    sph_position_at(s, i, t, x);
    sph_set_centre(s, i, x);
    uint32_t found;
    if (sph_shells_near(s, &s->cells, s->sigma, i, &s->near, &found)) return -1;
    for (uint32_t k = 0; k < found; ++k)
        if (add_pair_once(s, i, s->near.id[k])) return -1;
    if (sph_shells_near(s, &g->extra, g->extra_sigma, i, &s->near, &found)) return -1;
    for (uint32_t k = 0; k < found; ++k)
        if (add_pair_once(s, i, g->extra_particle[s->near.id[k]])) return -1;
    return add_extra_shell(s, i);
}

/* The shells added inside the step leave the second grid. */
static void drop_extra_shells(sph_groups *g) {
    for (size_t e = 0; e < g->nextra; ++e) {
        hsbd_cells_remove(&g->extra, (int32_t)e);
        g->extra_head[g->extra_particle[e]] = -1;
    }
    g->nextra = 0;
}

/* At the end of a step: the moved shells go to the main grid at their last centres, the
 * pairs no longer in reach leave the rows, the extra shells are dropped. */
static int settle_moved_shells(hsbd_spheres *s) {
    sph_groups *g = s->groups;
    for (size_t k = 0; k < g->nmoved; ++k) {
        const int32_t p = g->moved_list[k];
        hsbd_cells_remove(&s->cells, p);
        if (hsbd_cells_insert(&s->cells, p, s->centre + 3 * (size_t)p)) return -1;
    }
    for (size_t k = 0; k < g->nmoved; ++k) {
        const int32_t p = g->moved_list[k];
        const double *cp = s->centre + 3 * (size_t)p;
        const int32_t *row = s->nb + (size_t)p * s->nb_cap;
        for (uint32_t q = 0; q < s->nb_count[p];) {
            const int32_t m = row[q];
            double d[3];
            sph_min_image(s, s->centre + 3 * (size_t)m, cp, d);
            const double reach = 0.5 * (s->sigma[p] + s->sigma[m]) + sph_shell_reach(s);
            if (hsbd_dot3(d, d) < reach * reach) {
                ++q;
                continue;
            }
            sph_nb_remove(s, p, m); /* moves another entry to q */
            sph_nb_remove(s, m, p);
        }
        g->moved[p] = 0;
    }
    g->nmoved = 0;
    drop_extra_shells(g);
    return 0;
}

/* ---- running a group ---- */

/* The group of a neighbour whose group ran, that i's new segment (from time t) meets on
 * one of its earlier segments (the kernel tested the current one), or -1. */
static int32_t logged_neighbour_hit(hsbd_spheres *s, int32_t i, double t) {
    sph_groups *g = s->groups;
    const double *vi = s->v + 3 * (size_t)i;
    double xi[3];
    sph_position_at(s, i, t, xi);
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    const uint32_t count = s->nb_count[i];
    unsigned any = 0; /* usually none: one pass without a branch per entry */
    for (uint32_t q = 0; q < count; ++q)
        any |= g->history[row[q]];
    if (!any) return -1;
    for (uint32_t q = 0; q < count; ++q) {
        const int32_t m = row[q];
        if (!g->history[m]) continue;
        const int32_t last = g->last_segment[m];
        const double s_im = sph_contact_distance(s, i, m);
        double end = g->seg[last].t; /* the segments before the current one */
        for (int32_t k = g->seg[last].prev; k >= 0 && end > t; k = g->seg[k].prev) {
            const sph_segment *e = &g->seg[k];
            const double from = e->t > t ? e->t : t;
            double xm[3], xi_from[3], r_im[3], v_im[3];
            for (int a = 0; a < 3; ++a) {
                xm[a] = e->x[a] + e->v[a] * (from - e->t);
                xi_from[a] = xi[a] + vi[a] * (from - t);
                v_im[a] = e->v[a] - vi[a];
            }
            sph_min_image(s, xm, xi_from, r_im);
            if (sph_contact_time(r_im, v_im, s_im, end - from) >= 0)
                return -2 - g->parent[find_root(g, m)];
            end = e->t;
        }
    }
    return -1;
}

/* The group of a neighbour whose group ran, that i's start-of-step line (i back on it
 * after a rewind, t_local 0) meets on one of its segments after its own start line, or
 * -1. The groups that ran tested their segments against i's path of the earlier run,
 * which may have left the start line sooner than it will now; start lines against start
 * lines are the half scan's. A hit beyond i's next event only costs a needless join. */
static int32_t start_line_hit(hsbd_spheres *s, int32_t root_a, int32_t i) {
    sph_groups *g = s->groups;
    const double *xi = s->x + 3 * (size_t)i, *vi = s->v + 3 * (size_t)i;
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    for (uint32_t q = 0; q < s->nb_count[i]; ++q) {
        const int32_t m = row[q];
        if (!g->history[m]) continue;
        const int32_t r = find_root(g, m);
        if (r == root_a) continue;
        const double s_im = sph_contact_distance(s, i, m);
        double end = s->dt; /* every segment but the first, the current one included */
        for (int32_t k = g->last_segment[m]; k >= 0 && g->seg[k].prev >= 0; k = g->seg[k].prev) {
            const sph_segment *e = &g->seg[k];
            double xi_at[3], r_im[3], v_im[3];
            for (int a = 0; a < 3; ++a) {
                xi_at[a] = xi[a] + vi[a] * e->t;
                v_im[a] = e->v[a] - vi[a];
            }
            sph_min_image(s, e->x, xi_at, r_im);
            if (sph_contact_time(r_im, v_im, s_im, end - e->t) >= 0) return -2 - g->parent[r];
            end = e->t;
        }
    }
    return -1;
}

/* The first group that a particle rewound since the last call meets on its start line
 * (start_line_hit), or -1 when none does; the particles tested leave the list. */
static int32_t rewound_hit(hsbd_spheres *s, int32_t a) {
    sph_groups *g = s->groups;
    while (g->nrewound) {
        const int32_t p = g->rewound[--g->nrewound];
        g->queued[p] = 0;
        const int32_t b = start_line_hit(s, g->root[a], p);
        if (b >= 0) return b;
    }
    return -1;
}

/* What predict_in_group, play_group and run_group return besides a group to join; DEFER:
 * a first-pass run would reach outside its slab; GIVE_UP: see run_group */
enum { NO_JOIN = -1, OUT_OF_MEMORY = -2, DEFER = -3, GIVE_UP = -4 };

/* The joins with a re-run that one first-pass run may make before it waits for the serial
 * pass (which has the bound on re-runs over the whole step) */
enum { SPECULATIVE_RERUNS = 4 };

/* The slab of particle p's start position (p has not moved in the step). */
static int slab_of(const hsbd_spheres *s, const sph_groups *g, int32_t p) {
    const double x = s->x[3 * (size_t)p + g->slab_axis];
    long k = (long)floor(x * g->slab_scale + g->slab_shift) % g->nslabs;
    return (int)(k < 0 ? k + g->nslabs : k);
}

/* Whether a first-pass run may join group b with a re-run: b is a group of its slab, of
 * this round, that ran (its paths are rewound, and put back if the run is undone) or is
 * still pending. */
static int joinable_here(const sph_groups *g, int32_t b) {
    return g->group_slab[b] == g->slab &&
           (g->state[b] == GROUP_DONE || g->state[b] == GROUP_PENDING);
}

/* A first-pass run of group a meets particle j of its slab: j joins if it met nobody, its
 * group if that is a pending group of the slab still on its start lines at time t (both
 * noted, so that an undone run can take them back). Returns NO_JOIN, DEFER when j is
 * elsewhere (another slab, a group that spans slabs or ran in another), the group of the
 * slab to join with a re-run (it ran, or moved before t), or OUT_OF_MEMORY. */
static int32_t join_speculative(hsbd_spheres *s, int32_t a, int32_t j, int32_t r, double t) {
    sph_groups *g = s->groups;
    sph_worker *w = g->worker;
    if (g->parent[r] == -1) { /* checked first: no other slab's group is read */
        if (slab_of(s, g, j) != g->slab) return DEFER;
        if (note(&w->lone, &w->lone_len, &w->lone_cap, j)) return OUT_OF_MEMORY;
        g->parent[j] = g->root[a];
        return NO_JOIN;
    }
    const int32_t b = -2 - g->parent[r];
    if (!joinable_here(g, b)) return DEFER;
    if (g->state[b] == GROUP_DONE || g->first_time[b] < t) return b;
    if (note(&w->joined, &w->joined_len, &w->joined_cap, b)) return OUT_OF_MEMORY;
    return join_pending(s, a, b) ? OUT_OF_MEMORY : NO_JOIN;
}

/* Takes back what an undone first-pass run of group a did: its paths, the groups that ran
 * and that it rewound, and what it joined. */
static void undo_speculative(hsbd_spheres *s, int32_t a) {
    sph_groups *g = s->groups;
    sph_worker *w = g->worker;
    rewind_group(s, a);
    forget_rewound(g);   /* nothing else has met the paths it puts back */
    while (w->ran_len) { /* where the rewound groups' particles stood, latest first */
        const sph_ran_path *r = &w->ran[--w->ran_len];
        memcpy(s->x + 3 * (size_t)r->particle, r->x, sizeof r->x);
        memcpy(s->v + 3 * (size_t)r->particle, r->v, sizeof r->v);
        s->t_local[r->particle] = r->t_local;
        g->last_segment[r->particle] = r->last;
        g->history[r->particle] = r->history;
    }
    while (w->undo_len) {
        const sph_undo *u = &w->undo[--w->undo_len];
        *u->at = u->old;
    }
    for (size_t l = 0; l < w->lone_len; ++l)
        g->parent[w->lone[l]] = -1;
    for (size_t l = 0; l < w->joined_len; ++l) {
        const int32_t b = w->joined[l];
        g->parent[g->root[b]] = -2 - b;
        g->state[b] = GROUP_PENDING;
        g->next_part[b] = -1;
    }
    g->next_part[a] = -1;
    g->state[a] = GROUP_PENDING;
}

/* New predictions for i (on a new segment from time t, or a new shell: then its wall
 * event stands, new_path 0) in group a. Returns NO_JOIN, the group that i's segment
 * reaches and that must join a with a re-run, or OUT_OF_MEMORY. */
static int32_t predict_in_group(hsbd_spheres *s, int32_t a, int32_t i, double t, int new_path) {
    sph_groups *g = s->groups;
    const int32_t root_a = g->root[a];
    const uint32_t hits = sph_row_hits(s, i, t);
    for (uint32_t k = 0; k < hits; ++k) {
        const int32_t j = s->scan_j[k], r = find_root(g, j);
        if (r != root_a) {
            if (g->speculative) {
                const int32_t rc = join_speculative(s, a, j, r, t);
                if (rc != NO_JOIN) return rc;
            } else if (g->parent[r] == -1) { /* j never met anyone: it joins as it is */
                g->parent[r] = root_a;
            } else {
                const int32_t b = -2 - g->parent[r];
                /* a hit lies on j's current segment (sph_row_hits starts at the later
                 * segment's start); j's earlier segments are the log test's */
                if (g->state[b] == GROUP_DONE) return b;
                if (g->first_time[b] < t) return b; /* it moved before now: re-run */
                if (join_pending(s, a, b)) return OUT_OF_MEMORY;
            }
        }
        if (sph_push_event(s, s->scan_t[k], i, j)) return OUT_OF_MEMORY;
    }
    const int32_t b = logged_neighbour_hit(s, i, t);
    if (b >= 0) return b;
    const double exit = sph_shell_exit_time(s, i, t);
    if (exit >= 0 && sph_push_event(s, exit, i, SPH_EVENT_SHELL)) return OUT_OF_MEMORY;
    int wall = 0;
    const double contact = new_path && s->any_walls ? sph_wall_time(s, i, t, &wall) : -1;
    if (contact >= 0 && sph_push_event(s, contact, i, sph_wall_event(wall))) return OUT_OF_MEMORY;
    return NO_JOIN;
}

/* Runs group a (and the groups joined to it) from the step's start in time order.
 * Returns NO_JOIN when done, a group that must join a before it runs again, or
 * OUT_OF_MEMORY. */
static int32_t play_group(hsbd_spheres *s, int32_t a) {
    sph_groups *g = s->groups;
    size_t hits = 0;
    for (int32_t b = a; b >= 0; b = g->next_part[b])
        hits += (size_t)g->count[b];
    if (sph_calendar_start_for(&s->calendar, s->dt, 2 * hits, 8)) return OUT_OF_MEMORY;
    for (int32_t b = a; b >= 0; b = g->next_part[b])
        if (push_group_hits(s, b)) return OUT_OF_MEMORY;
    g->collisions[a] = g->shell_updates[a] = 0; /* a re-run counts afresh */
    g->virial[a] = 0;
    sph_event e;
    uint64_t played = 0;
    while (sph_calendar_pop(&s->calendar, &e)) {
        if (sph_event_stale(s, &e)) continue;
        played++;
        if (log_start(s, a, e.i)) return OUT_OF_MEMORY;
        int32_t joined;
        if (e.j == SPH_EVENT_SHELL && g->speculative) {
            joined = DEFER; /* re-centring edits rows and cells outside the slab */
        } else if (e.j == SPH_EVENT_SHELL) {
            if (recentre_adding(s, e.i, e.t)) return OUT_OF_MEMORY;
            g->shell_updates[a]++;
            joined = predict_in_group(s, a, e.i, e.t, 0);
        } else if (e.j <= SPH_EVENT_WALL) {
            const int rc = sph_collide_wall(s, &e, a);
            if (rc < 0) return OUT_OF_MEMORY;
            if (!rc) continue;
            if (new_segment(s, e.i, e.t) < 0) return OUT_OF_MEMORY;
            joined = predict_in_group(s, a, e.i, e.t, 1);
        } else {
            if (log_start(s, a, e.j)) return OUT_OF_MEMORY;
            double virial;
            if (!sph_collide_pair(s, &e, &virial)) continue;
            g->collisions[a]++;
            g->virial[a] += sph_exact_term(s->virial_scale, virial);
            if (new_segment(s, e.i, e.t) < 0 || new_segment(s, e.j, e.t) < 0) return OUT_OF_MEMORY;
            joined = predict_in_group(s, a, e.i, e.t, 1);
            if (joined == NO_JOIN) joined = predict_in_group(s, a, e.j, e.t, 1);
        }
        if (joined == OUT_OF_MEMORY) return OUT_OF_MEMORY;
        if (joined != NO_JOIN) { /* the re-run starts a new calendar */
            g->played += played;
            g->replayed += played;
            return joined;
        }
    }
    g->played += played;
    return NO_JOIN;
}

/* Group a ran to the end of the step. */
static void finish_group(sph_groups *g, int32_t a) {
    g->state[a] = GROUP_DONE;
    for (int32_t k = g->first_segment[a]; k >= 0; k = g->seg[k].next_head) {
        const int32_t p = g->seg[k].particle; /* several segments: the log test needed */
        g->history[p] = g->seg[g->last_segment[p]].prev >= 0;
    }
}

/* Runs group a to the end of the step. Returns NO_JOIN when done; GIVE_UP when the groups
 * give up for this step (re-runs cost more than the step's predicted pairs: the groups
 * percolate as they run; AUTO and GROUPS alike, else a percolating step costs without
 * bound), group a then back on its start lines; in a first-pass run DEFER when it would
 * join a group it may not (undo_speculative then takes the run back); or OUT_OF_MEMORY. */
static int32_t run_group(hsbd_spheres *s, int32_t a) {
    sph_groups *g = s->groups;
    g->state[a] = GROUP_ACTIVE;
    int32_t b;
    int reruns = 0;
    while ((b = play_group(s, a)) >= 0) {
        do { /* b joins; then the groups that the rewound start lines meet */
            if (g->speculative && (!joinable_here(g, b) || ++reruns > SPECULATIVE_RERUNS))
                return DEFER;
            if (join_and_rewind(s, a, b)) return OUT_OF_MEMORY;
            if (!g->speculative && g->replayed > g->nhits) {
                g->state[a] = GROUP_PENDING;
                return GIVE_UP;
            }
        } while ((b = rewound_hit(s, a)) >= 0);
    }
    if (b == NO_JOIN) finish_group(g, a);
    return b;
}

/* Every start-of-step event into the global calendar (which then runs the step). */
static int hand_to_global_calendar(hsbd_spheres *s) {
    sph_groups *g = s->groups;
    if (sph_calendar_start_for(&s->calendar, s->dt, 2 * g->nhits, 64)) return -1;
    for (size_t k = 0; k < g->nhits; ++k)
        if (sph_push_event(s, g->hit_t[k], g->hit_i[k], g->hit_j[k])) return -1;
    return 0;
}

/* ---- the first pass, on threads ----
 * The box is cut into an even number of slabs along a periodic axis, each at least as
 * wide as the reach of a neighbour pair at the start of a step (sigma_max + 4 shell + skin). A
 * group whose particles all start in slab k reads only particles in slabs k - 1 to
 * k + 1, so the groups of the even slabs can run at the same time, and then those of the
 * odd ones. A run takes in what it meets in its slab that has not run: particles that met
 * nobody, and groups still on their start lines at the present time. It re-runs itself, as
 * the serial pass would, with a group of its slab and round that it meets after that group
 * ran or moved (only the runs of its own slab, on its own thread, have met the paths of a
 * group that ran there). A run that would touch anything else (a particle of another slab,
 * a group that spans slabs or ran elsewhere, a shell to move, its share of the segment log
 * full, more than SPECULATIVE_RERUNS re-runs) is undone at once, with what it took in and
 * the groups it rewound put back, and its group waits. Then a second round does the same
 * on the slabs moved by half a width, for the groups left that lie wholly in one of those
 * (most of those that span two slabs of the first round), and the serial pass runs the
 * rest as before. Which group runs where depends on the state only, never on the number
 * of threads, so neither do the results: the positions are those of the global calendar
 * (docs/spheres.md, "Threads"), and the sums are taken in group order at the end. */

static void choose_slabs(hsbd_spheres *s, sph_groups *g) {
    g->nslabs = sph_slabs(s, &g->slab_axis);
    if (g->nslabs) g->slab_scale = g->nslabs / s->box[g->slab_axis];
}

/* Group a's slab: -1 when it is not pending or not all its particles start in one. */
static int slab_of_group(const hsbd_spheres *s, const sph_groups *g, size_t a) {
    const int32_t first = g->start[a], end = first + g->count[a];
    int k = g->state[a] == GROUP_PENDING ? slab_of(s, g, g->by_i[first]) : -1;
    for (int32_t h = first; h < end && k >= 0; ++h) {
        const int32_t j = g->by_j[h]; /* a shell to move would stop the run */
        if (slab_of(s, g, g->by_i[h]) != k || j == SPH_EVENT_SHELL ||
            (j >= 0 && slab_of(s, g, j) != k))
            k = -1;
    }
    return k;
}

/* Each group's slab, the slabs' lists of groups and their shares of the segment log.
 * Returns 0, or -1 when out of memory. */
static int plan_slabs(hsbd_spheres *s, int threads) {
    sph_groups *g = s->groups;
    size_t groups[SPH_MAX_SLABS] = {0}, segments[SPH_MAX_SLABS] = {0};
    const long ngroups = (long)g->ngroups;
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (long a = 0; a < ngroups; ++a)
        g->group_slab[a] = slab_of_group(s, g, (size_t)a);
    for (size_t a = 0; a < g->ngroups; ++a) {
        const int k = g->group_slab[a];
        if (k < 0) continue;
        groups[k]++;
        /* at most count + 1 particles start a segment, two per collision: most runs */
        segments[k] += 3 * (size_t)g->count[a] + 5;
    }
    g->slab_first[0] = 0;
    g->slab_seg[0] = g->nseg;
    for (int k = 0; k < g->nslabs; ++k) {
        g->slab_first[k + 1] = g->slab_first[k] + groups[k];
        g->slab_seg[k + 1] = g->slab_seg[k] + segments[k];
        groups[k] = g->slab_first[k];
    }
    for (size_t a = 0; a < g->ngroups; ++a)
        if (g->group_slab[a] >= 0) g->slab_groups[groups[g->group_slab[a]]++] = (int32_t)a;
    const size_t need = g->slab_seg[g->nslabs];
    if (need > g->seg_cap) {
        if (grow_array(&g->seg, need, sizeof *g->seg)) return -1;
        g->seg_cap = need;
    }
    return 0;
}

/* The neighbours of group a's particles, which its run's row predictions read, and their
 * shells. Always inlined: gcc takes a function of prefetches alone for one without effects
 * and drops its calls. */
static inline __attribute__((always_inline)) void prefetch_group_neighbours(const hsbd_spheres *s,
                                                                            int32_t a) {
    const sph_groups *g = s->groups;
    for (int32_t o = g->start[a]; o < g->start[a] + g->count[a]; ++o) {
        const int32_t ends[2] = {g->by_i[o], g->by_j[o]};
        for (int e = 0; e < 1 + (ends[1] >= 0); ++e) { /* not a shell exit or a wall */
            sph_prefetch_neighbours(s, ends[e]);
            __builtin_prefetch(s->centre + 3 * (size_t)ends[e]); /* its shell-exit test */
        }
    }
}

/* The rows (their first 16 entries) and row counts of group a's particles, which
 * prefetch_group_neighbours reads a few groups later, and their own bookkeeping: asked for
 * first, so that those reads do not wait. Always inlined, as above. */
static inline __attribute__((always_inline)) void prefetch_group_rows(const hsbd_spheres *s,
                                                                      int32_t a) {
    const sph_groups *g = s->groups;
    for (int32_t o = g->start[a]; o < g->start[a] + g->count[a]; ++o) {
        const int32_t ends[2] = {g->by_i[o], g->by_j[o]};
        for (int e = 0; e < 1 + (ends[1] >= 0); ++e) {
            sph_prefetch_row(s, ends[e]);
            __builtin_prefetch(s->nb_count + ends[e]);
            __builtin_prefetch(g->last_segment + ends[e]); /* its run's own bookkeeping */
            __builtin_prefetch(g->parent + ends[e]);
            __builtin_prefetch(s->counter + ends[e]);
        }
    }
}

enum { ROWS_AHEAD = 8, NEIGHBOURS_AHEAD = 3 }; /* groups ahead in a list */

/* Before the q-th of the groups list[0 .. len) runs (beyond the caches): the rows of the
 * group ROWS_AHEAD places on, and the neighbours of the one NEIGHBOURS_AHEAD on. */
static inline __attribute__((always_inline)) void
prefetch_groups_ahead(const hsbd_spheres *s, const int32_t *list, size_t q, size_t len) {
    if (q + ROWS_AHEAD < len) prefetch_group_rows(s, list[q + ROWS_AHEAD]);
    if (q + NEIGHBOURS_AHEAD < len) prefetch_group_neighbours(s, list[q + NEIGHBOURS_AHEAD]);
}

/* The groups of slab k, in order, in a worker's copies of the state (the rows of the
 * group eight ahead and the neighbours of the group three ahead asked for in advance).
 * Returns 0, or -1 when out of memory. */
static int run_slab(hsbd_spheres *s, int k) {
    sph_groups *g = s->groups;
    g->slab = k;
    g->nseg = g->slab_seg[k];
    g->seg_cap = g->slab_seg[k + 1];
    const int ahead = s->n >= SPH_PREFETCH_MIN_N;
    for (size_t q = g->slab_first[k]; q < g->slab_first[k + 1]; ++q) {
        const int32_t a = g->slab_groups[q];
        if (ahead) prefetch_groups_ahead(s, g->slab_groups, q, g->slab_first[k + 1]);
        if (g->state[a] != GROUP_PENDING) continue; /* joined by an earlier run */
        sph_worker *w = g->worker;
        w->lone_len = w->joined_len = w->undo_len = w->ran_len = 0;
        g->log_full = 0;
        const size_t nseg = g->nseg; /* an undone run gives its segments back */
        const uint64_t reruns = s->stats.group_reruns;
        const int32_t rc = run_group(s, a);
        if (rc == NO_JOIN) continue;
        if (rc == OUT_OF_MEMORY && !g->log_full) {
            forget_rewound(g); /* the list is the worker's: the step is abandoned */
            return -1;
        }
        undo_speculative(s, a); /* as if it had not run */
        g->nseg = nseg;
        s->stats.group_reruns = reruns;
    }
    return 0;
}

/* A calendar, a row's hit buffers and a list of rewound particles for each of `threads`
 * workers. Returns 0 or -1. */
static int reserve_workers(hsbd_spheres *s, int threads) {
    sph_groups *g = s->groups;
    if ((size_t)threads > g->nworkers) {
        sph_worker *workers =
            sph_grow_zeroed(g->workers, g->nworkers, (size_t)threads, sizeof *workers);
        if (!workers) return -1;
        g->workers = workers;
        g->nworkers = (size_t)threads;
    }
    for (size_t w = 0; w < (size_t)threads; ++w) {
        sph_worker *k = &g->workers[w];
        if (!k->rewound_cap) {
            if (grow_array(&k->rewound, s->n, sizeof *k->rewound)) return -1;
            k->rewound_cap = s->n;
        }
        if (k->scan_cap >= s->scan_cap) continue;
        if (grow_array(&k->scan_j, s->scan_cap, sizeof *k->scan_j) ||
            grow_array(&k->scan_t, s->scan_cap, sizeof *k->scan_t))
            return -1;
        k->scan_cap = s->scan_cap;
    }
    return 0;
}

_Static_assert((int)SPH_MAX_SLABS <= (int)SPH_SLAB_QUEUE_MAX,
               "a slab queue holds the first pass's slabs");

/* A round of the first pass: the slabs on the threads, even ones first, each odd one once
 * its neighbours are done (slab_queue.h). Returns 0 or -1. */
static int run_slabs(hsbd_spheres *s) {
    sph_groups *g = s->groups;
    const int threads = sph_threads(s);
    if (plan_slabs(s, threads) || reserve_workers(s, threads)) return -1;
    uint64_t played = 0, replayed = 0, stale = 0, reruns = 0;
    sph_slab_queue queue;
    sph_slab_queue_start(&queue, g->nslabs);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(+ : played, replayed, stale, reruns)
    for (int w = 0; w < threads; ++w) {
        sph_worker *worker = &g->workers[w];
        hsbd_spheres local = *s; /* shares every array; its own calendar and buffers */
        sph_groups local_groups = *g;
        local.groups = &local_groups;
        local.calendar = worker->calendar;
        local.scan_j = worker->scan_j;
        local.scan_t = worker->scan_t;
        local_groups.speculative = 1;
        local_groups.worker = worker;
        local_groups.rewound = worker->rewound;
        local_groups.nrewound = 0;
        local_groups.played = local_groups.replayed = 0;
        for (int k; (k = sph_slab_queue_take(&queue)) >= 0;)
            sph_slab_queue_finish(&queue, k, run_slab(&local, k) != 0);
        worker->calendar = local.calendar;
        played += local_groups.played;
        replayed += local_groups.replayed;
        stale += local.stats.stale_events - s->stats.stale_events;
        reruns += local.stats.group_reruns - s->stats.group_reruns;
    }
    g->played += played;
    g->replayed += replayed;
    s->stats.stale_events += stale;
    s->stats.group_reruns += reruns;
    g->nseg = g->slab_seg[g->nslabs];
    return atomic_load(&queue.failed) ? -1 : 0;
}

int sph_groups_run(hsbd_spheres *s) {
    sph_groups *g = s->groups;
    forget_rewound(g); /* what a given-up or failed step left */
    const long largest = number_groups(s);
    const int automatic = s->par.event_order == HSBD_EVENTS_AUTO;
    if (largest < 0) return -1;
    if (automatic && largest * LARGEST_GROUP_SHARE > (long)g->nhits)
        return hand_to_global_calendar(s) ? -1 : 1;
    choose_slabs(s, g);
    for (int round = 0; round < 2 && g->nslabs; ++round) { /* then the slabs moved by half */
        g->slab_shift = 0.5 * round;
        if (run_slabs(s)) return -1;
    }
    /* the groups left, in order, into slab_groups (the first pass is done with it), so
     * that their data can be asked for ahead */
    size_t pending = 0;
    for (size_t a = 0; a < g->ngroups; ++a)
        if (g->state[a] == GROUP_PENDING) g->slab_groups[pending++] = (int32_t)a;
    const int ahead = s->n >= SPH_PREFETCH_MIN_N;
    for (size_t q = 0; q < pending; ++q) {
        const int32_t a = g->slab_groups[q];
        if (ahead) prefetch_groups_ahead(s, g->slab_groups, q, pending);
        if (g->state[a] != GROUP_PENDING) continue; /* joined by an earlier run */
        const int32_t rc = run_group(s, a);
        if (rc == OUT_OF_MEMORY) return -1;
        if (rc == NO_JOIN) continue;
        for (size_t b = 0; b < g->ngroups; ++b) /* give up: the whole step back to its start */
            if (g->state[b] == GROUP_DONE) rewind_group(s, (int32_t)b);
        g->pause = PAUSE_STEPS;
        return settle_moved_shells(s) || hand_to_global_calendar(s) ? -1 : 1;
    }
    if (settle_moved_shells(s)) return -1;
    for (size_t a = 0; a < g->ngroups; ++a) /* exact sums: the order does not matter */
        if (g->state[a] == GROUP_DONE) {
            s->stats.collisions += g->collisions[a];
            s->stats.shell_updates += g->shell_updates[a];
            s->step_virial += g->virial[a];
        }
    if (automatic && g->replayed * REPLAY_SHARE > g->played) g->pause = PAUSE_STEPS;
    return 0;
}

unsigned sph_groups_pause(const hsbd_spheres *s) {
    return s->groups ? s->groups->pause : 0;
}

int sph_groups_set_pause(hsbd_spheres *s, unsigned pause) {
    if (!pause) return 0;
    if (!s->groups && sph_groups_begin(s)) return -1;
    s->groups->pause = pause;
    return 0;
}

void sph_groups_abandon(hsbd_spheres *s) {
    sph_groups *g = s->groups;
    if (!g) return;
    for (size_t k = 0; k < g->nmoved; ++k)
        g->moved[g->moved_list[k]] = 0;
    g->nmoved = 0;
    drop_extra_shells(g);
}
