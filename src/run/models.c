/* The models of a run and their observers, registered here once: a new observable is a
 * file under src/run/observers/ and a line in its model's list. */
#include "run/run.h"

#include "run/observers.h"

static const run_observer_ops *const rods_observers[] = {&run_observe_profile,
                                                         &run_observe_phases,
                                                         &run_observe_msd,
                                                         &run_observe_clusters,
                                                         &run_observe_contacts,
                                                         &run_observe_drift,
                                                         &run_observe_trap,
                                                         &run_observe_current,
                                                         &run_observe_trajectory,
                                                         &run_observe_log,
                                                         NULL};

static const run_observer_ops *const spheres_observers[] = {&run_observe_gr,
                                                            &run_observe_virial,
                                                            &run_observe_walls,
                                                            &run_observe_msd,
                                                            &run_observe_trajectory,
                                                            &run_observe_sk,
                                                            &run_observe_log,
                                                            &run_observe_orientation,
                                                            &run_observe_active,
                                                            &run_observe_local_density,
                                                            NULL};

typedef struct run_model_spec {
    const char *name;
    int (*build)(run *r, hsbd_error *err); /* the system, its state and r->model */
    const run_observer_ops *const *observers;
} run_model_spec;

static const run_model_spec models[] = {
    [HSBD_MODEL_RODS] = {"rods", run_rods_build, rods_observers},
    [HSBD_MODEL_SPHERES] = {"spheres", run_spheres_build, spheres_observers},
};

const char *run_model_name(const hsbd_config *cfg) {
    return models[cfg->system.model].name;
}

int run_build(run *r, hsbd_error *err) {
    const run_model_spec *m = &models[r->cfg->system.model];
    const int rc = m->build(r, err);
    return rc == HSBD_OK ? run_observers_build(r, m->observers, err) : rc;
}
