/* Local processing of a step's events (internal to src/spheres): the pairs predicted to
 * touch at the start of a step join the particles into groups, and each group runs its
 * events in time order on its own, one group after another in memory order, so that the
 * data a group touches stays in cache. Exact: a new path segment is tested against every
 * neighbour outside the group, including the logged earlier segments of particles whose
 * groups already ran; a hit joins the two groups (re-run from the step's start when the
 * other one already moved). See docs/spheres.md, "Events group by group". */
#ifndef HSBD_SPHERES_GROUPS_H
#define HSBD_SPHERES_GROUPS_H

#include <stddef.h>
#include <stdint.h>

#include "core/cellgrid.h"

/* One logged straight segment of a particle: from time t at position x with velocity v.
 * The first segment of a particle in a step also keeps its shell centre c at the start. */
typedef struct sph_segment {
    double t, x[3], v[3], c[3];
    int32_t prev;      /* earlier segment of the same particle, -1 for the first */
    int32_t next_head; /* first segments only: the next particle's in the same group, -1 */
    int32_t particle;
} sph_segment;

typedef struct sph_groups {
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
    double *first_time, *virial;
    uint64_t *collisions;
    /* the segment log of the step */
    sph_segment *seg;
    size_t seg_cap, nseg;
    /* shells added inside the step: a second grid of centres, entries -> particles */
    hsbd_cells extra;
    int32_t *extra_particle;
    double *extra_sigma;
    size_t extra_cap, nextra;
    int32_t *moved_list;
    size_t nmoved;
    uint64_t replayed; /* events of the step in runs that ended in a join */
    uint64_t played;   /* all events of the step */
    unsigned pause;    /* AUTO: steps left on the global calendar after costly re-runs */
} sph_groups;

void sph_groups_free(sph_groups *g);

#endif
