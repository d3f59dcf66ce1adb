/* A run held in memory and advanced by the caller (the Python module's Simulation): the
 * model, initial state and observers that `hsbd run` builds from a configuration, the
 * same lifecycle (equilibration, then production with sampling on its schedule), and
 * access to the state and the observers between steps. Writes no files: trajectories,
 * currents and checkpoints are off; hsbd_run writes a run directory. */
#ifndef HSBD_SIM_H
#define HSBD_SIM_H

#include <stdint.h>

#include "hsbd/config.h"
#include "hsbd/error.h"
#include "hsbd/export.h"
#include "hsbd/observe.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"

typedef struct hsbd_sim hsbd_sim;

/* The state and observers of a simulation (NULL where the model has none), owned by it
 * and valid until hsbd_sim_free; what they point to changes with every step. */
typedef struct hsbd_sim_parts {
    hsbd_rods *rods;             /* system.model = rods */
    hsbd_spheres *spheres;       /* system.model = spheres */
    const int *species;          /* rods: the species of each rod (mixtures), else NULL */
    const hsbd_profile *profile; /* rods: density and contact profiles */
    const hsbd_msd *msd;         /* every particle */
    const hsbd_msd *msd_species[HSBD_MAX_SPECIES]; /* mixtures: per species */
    const hsbd_gr *gr; /* spheres: g(r) per pair (NULL when sample.gr_every = 0) */
    /* spheres: the density profile along each axis with walls or the field (else NULL) */
    const hsbd_slab *slab[3];
} hsbd_sim_parts;

enum hsbd_sim_stage { HSBD_SIM_EQUILIBRATING = 0, HSBD_SIM_PRODUCING = 1, HSBD_SIM_DONE = 2 };

/* A simulation of a finalized configuration (copied); HSBD_EINPUT with the message of
 * `hsbd run` for what the model refuses (e.g. an initial state that cannot be made). */
HSBD_API hsbd_sim *hsbd_sim_alloc(const hsbd_config *cfg, hsbd_error *err);
/* The same from the caller's initial state instead of init.positions or init.method:
 * positions x (N x 3, rods x[3 i]; checked as init.positions is: overlaps, walls), and
 * each particle's species (N, or NULL: as configured) and diameter (spheres with
 * polydispersity, N, or NULL: as drawn). Rods are kept in line order (particle i is the
 * i-th from the left, its species follows its position). */
HSBD_API hsbd_sim *hsbd_sim_alloc_from(const hsbd_config *cfg, const double *x, const int *species,
                                       const double *sigma, hsbd_error *err);
HSBD_API void hsbd_sim_free(hsbd_sim *s);
/* At most `steps` more steps of the run (fewer when it ends). */
HSBD_API int hsbd_sim_advance(hsbd_sim *s, uint64_t steps, hsbd_error *err);
HSBD_API int hsbd_sim_stage(const hsbd_sim *s);
/* production steps done, equilibration steps done */
HSBD_API uint64_t hsbd_sim_production_steps(const hsbd_sim *s);
HSBD_API uint64_t hsbd_sim_equilibration_steps(const hsbd_sim *s);
HSBD_API hsbd_sim_parts hsbd_sim_get_parts(const hsbd_sim *s);
HSBD_API const hsbd_config *hsbd_sim_config(const hsbd_sim *s);
/* The results so far as the text of summary.json (what `hsbd run` writes at the end: the
 * model's and every observer's lines, e.g. Z_virial, D_long, walls, clusters, drift; the
 * parameters), into *json (malloc'ed, the caller frees it). HSBD_OK or HSBD_ENOMEM. */
HSBD_API int hsbd_sim_summary(hsbd_sim *s, char **json, hsbd_error *err);

#endif
