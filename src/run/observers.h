/* The observers the models register (src/run/models.c), one file each under
 * src/run/observers/. */
#ifndef HSBD_RUN_OBSERVERS_H
#define HSBD_RUN_OBSERVERS_H

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

#endif
