/* The observers of spheres between walls and in fields (walls.c): density profiles along
 * every walls or field axis per species (density.tsv, density_<axis>.tsv) and the wall
 * contact densities from the walls' impulses (contact theorem) and from the profiles
 * (summary.json "walls"). Internal to src/run. */
#ifndef HSBD_RUN_WALLS_H
#define HSBD_RUN_WALLS_H

#include "hsbd/observe.h"
#include "run/run.h"

typedef struct walls_observers {
    hsbd_slab *slab[3];   /* per axis: walls or the field act along it; else NULL */
    hsbd_blocks *impulse; /* per sample: wall impulse increments, 6 (ns + 1) (the last: all) */
    double *impulse_last; /* 6 ns sums at the previous sample */
    double *scratch;      /* 6 ns */
    size_t ns;
} walls_observers;

/* Nothing is allocated when no axis has walls or a field. */
int walls_observers_build(const hsbd_config *cfg, const hsbd_spheres_view *v, walls_observers *w,
                          hsbd_error *err);
void walls_observers_free(walls_observers *w);
/* A sample of the profiles and the impulses since the last (sys: the engine's sums). */
void walls_observers_sample(walls_observers *w, const hsbd_spheres *sys);
/* Production begins: the engine's sums were reset. */
void walls_observers_restart(walls_observers *w);
int walls_observers_write_tables(const run *r, const walls_observers *w, hsbd_error *err);
void walls_observers_write_summary(const run *r, const walls_observers *w, FILE *f);
void walls_observers_save(const walls_observers *w, hsbd_writer *wr);
int walls_observers_load(walls_observers *w, hsbd_reader *rd);

#endif
