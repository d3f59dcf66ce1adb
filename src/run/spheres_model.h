/* The spheres model's state as its observers see it (src/run/spheres.c builds it; the
 * observers under src/run/observers/ that measure disks and spheres read it). */
#ifndef HSBD_RUN_SPHERES_MODEL_H
#define HSBD_RUN_SPHERES_MODEL_H

#include "hsbd/spheres.h"
#include "hsbd/table.h"
#include "run/run.h"

typedef struct spheres_model {
    hsbd_spheres *sys;
    int *species;
    size_t ns;               /* species (1 for one species) */
    hsbd_field field;        /* field.type along field.axis (the engine reads it) */
    hsbd_table *field_table; /* a tabulated term's table */
    double *coupling;        /* per particle: the field's factor */
    double *frame_unwrapped; /* the frame's memory: d N unwrapped coordinates */
} spheres_model;

static inline spheres_model *spheres_model_of(const run *r) {
    return r->m;
}

/* The species' names as the tables and summary give them ("S" for one species). */
static inline const char *spheres_species_name(const run *r, size_t k) {
    return r->cfg->species.n ? r->cfg->species.name[k] : "S";
}

#endif
