/* The observers the models register (src/run/models.c), one file each under
 * src/run/observers/. */
#ifndef HSBD_RUN_OBSERVERS_H
#define HSBD_RUN_OBSERVERS_H

#include "observe/checkpoint.h"
#include "run/run.h"

/* rods */
extern const run_observer_ops run_observe_profile;  /* density and contact profiles */
extern const run_observer_ops run_observe_phases;   /* profiles per phase of a drive */
extern const run_observer_ops run_observe_clusters; /* clusters of touching rods */
extern const run_observer_ops run_observe_contacts; /* contact densities per species pair */
extern const run_observer_ops run_observe_drift;    /* mean velocity, D_eff */
extern const run_observer_ops run_observe_trap;     /* centre of mass in a harmonic trap */
extern const run_observer_ops run_observe_current;  /* particle current */
/* disks and spheres */
extern const run_observer_ops run_observe_gr;            /* g(r), contact values, Z by contacts */
extern const run_observer_ops run_observe_virial;        /* Z from the collisional virial */
extern const run_observer_ops run_observe_walls;         /* profiles and wall contact densities */
extern const run_observer_ops run_observe_sk;            /* the static structure factor */
extern const run_observer_ops run_observe_orientation;   /* active: <e(0).e(t)> */
extern const run_observer_ops run_observe_active;        /* active: the pressure's parts */
extern const run_observer_ops run_observe_local_density; /* local packing fraction */
/* both models */
extern const run_observer_ops run_observe_msd;        /* MSD, F_s, D_L */
extern const run_observer_ops run_observe_trajectory; /* XYZ or GSD frames */
extern const run_observer_ops run_observe_log;        /* log.tsv, a time series */

/* One lag accumulator over the frame's d N components and, when nspecies > 0, one per
 * species (msd.c: the MSD and F_s; orientation.c: <e(0).e(t)>), with the run's lags,
 * origins and blocks, built, sampled, restarted, saved, loaded and written together. */
typedef struct run_msd_set {
    int dimension;
    size_t nspecies; /* accumulators per species (0: none) */
    hsbd_msd *all, *species[HSBD_MAX_SPECIES];
} run_msd_set;
/* the value and its error of one accumulator at lag k, as its table shows them */
typedef void (*run_msd_value)(const hsbd_msd *m, size_t k, int dimension, double *v, double *e);
/* fs_k > 0: with F_s at that wave number */
int run_msd_set_build(run_msd_set *s, run *r, size_t nspecies, double fs_k, hsbd_error *err);
void run_msd_set_sample(run_msd_set *s, const double *values);
void run_msd_set_restart(run_msd_set *s);
void run_msd_set_save(const run_msd_set *s, hsbd_writer *w);
int run_msd_set_load(run_msd_set *s, hsbd_reader *rd);
void run_msd_set_free(run_msd_set *s);
/* the table `name`: columns t, what, what_err, origins, then per species */
int run_msd_set_write(const run_msd_set *s, const run *r, const char *name, const char *what,
                      const char *title, run_msd_value value, hsbd_error *err);

#endif
