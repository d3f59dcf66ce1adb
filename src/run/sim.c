/* hsbd_sim: the run lifecycle advanced by the caller (include/hsbd/sim.h). */
#include <stdlib.h>
#include <string.h>

#include "run/run.h"

struct hsbd_sim {
    hsbd_config cfg; /* the caller's, with the file outputs off */
    hsbd_run_options opt;
    run r;
};

hsbd_sim *hsbd_sim_alloc(const hsbd_config *cfg, hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_sim *s = calloc(1, sizeof *s);
    if (!s) {
        hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        return NULL;
    }
    s->cfg = *cfg;
    s->cfg.output.trajectory = HSBD_TRAJ_NONE;
    s->cfg.output.checkpoints = 0;
    s->cfg.sample.current_every = 0;
    s->cfg.output.log_every = 0; /* no files: no stream */
    s->r = (run){.cfg = &s->cfg, .opt = &s->opt};
    const int rc = run_build(&s->r, err);
    if (rc != HSBD_OK) {
        hsbd_sim_free(s);
        return NULL;
    }
    run_warn_start(&s->r);
    run_begin(&s->r);
    return s;
}

void hsbd_sim_free(hsbd_sim *s) {
    if (!s) return;
    run_observers_free(&s->r);
    if (s->r.model.release) s->r.model.release(&s->r);
    free(s);
}

int hsbd_sim_advance(hsbd_sim *s, uint64_t steps, hsbd_error *err) {
    hsbd_error_clear(err);
    return run_advance(&s->r, steps, err);
}

int hsbd_sim_stage(const hsbd_sim *s) {
    return s->r.stage;
}

uint64_t hsbd_sim_production_steps(const hsbd_sim *s) {
    return s->r.steps_done;
}

uint64_t hsbd_sim_equilibration_steps(const hsbd_sim *s) {
    return s->r.equil_done;
}

hsbd_sim_parts hsbd_sim_get_parts(const hsbd_sim *s) {
    hsbd_sim_parts p;
    memset(&p, 0, sizeof p);
    s->r.model.expose(&s->r, &p);
    run_observers_expose(&s->r, &p);
    return p;
}

const hsbd_config *hsbd_sim_config(const hsbd_sim *s) {
    return &s->cfg;
}
