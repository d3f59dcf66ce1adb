/* The rods model's state as its observers see it (src/run/rods.c builds it; the observers
 * under src/run/observers/ that measure rods read it). */
#ifndef HSBD_RUN_RODS_MODEL_H
#define HSBD_RUN_RODS_MODEL_H

#include "hsbd/observe.h"
#include "hsbd/rods.h"
#include "run/run.h"

typedef struct rods_model {
    hsbd_rods *rods;
    hsbd_table *pair_table;         /* pair.type = table */
    hsbd_table *field_table;        /* field.type with table */
    double sticky_ratio;            /* mu max|f| dt / epsilon, Eq. (33) (NaN without stickiness) */
    double field_error, pair_error; /* the steps' distortion estimates (NaN: no such force) */
    int *species;                   /* mixtures: species of each rod, line order */
    hsbd_rods_step_stats stats;     /* of the last step, when it is sampled */
    double *x_start;                /* init.positions in line order (replicas) */
    /* the frame's memory (run_frame) */
    double *frame_x, *frame_unwrapped, *frame_diameter;
    int64_t *frame_image;
} rods_model;

static inline rods_model *rods_model_of(const run *r) {
    return r->m;
}

/* The sum of the rods' unwrapped positions (the particle current's numerator). */
double rods_sum_unwrapped(const hsbd_rods *rods);

#endif
