/* hsbd_sim: the run lifecycle advanced by the caller (include/hsbd/sim.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run/run.h"

struct hsbd_sim {
    hsbd_config cfg; /* the caller's, with the file outputs off */
    hsbd_run_options opt;
    run r;
};

static hsbd_sim *sim_build(const hsbd_config *cfg, const double *x, const int *species,
                           const double *sigma, hsbd_error *err) {
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
    s->r = (run){.cfg = &s->cfg,
                 .opt = &s->opt,
                 .start_x = x,
                 .start_species = species,
                 .start_sigma = sigma};
    const int rc = run_build(&s->r, err);
    s->r.start_x = s->r.start_sigma = NULL, s->r.start_species = NULL; /* the caller's */
    if (rc != HSBD_OK) {
        hsbd_sim_free(s);
        return NULL;
    }
    run_warn_start(&s->r);
    run_begin(&s->r);
    return s;
}

hsbd_sim *hsbd_sim_alloc(const hsbd_config *cfg, hsbd_error *err) {
    return sim_build(cfg, NULL, NULL, NULL, err);
}

hsbd_sim *hsbd_sim_alloc_from(const hsbd_config *cfg, const double *x, const int *species,
                              const double *sigma, hsbd_error *err) {
    if (!x) {
        hsbd_error_set(err, HSBD_EINPUT, "hsbd_sim_alloc_from: no positions");
        return NULL;
    }
    return sim_build(cfg, x, species, sigma, err);
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

int hsbd_sim_summary(hsbd_sim *s, char **json, hsbd_error *err) {
    hsbd_error_clear(err);
    size_t len = 0;
    *json = NULL;
    FILE *f = open_memstream(json, &len);
    if (!f) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the summary");
    run_write_summary(&s->r, f, s->r.completed ? "completed" : "running");
    if (fclose(f) != 0 || !*json) {
        free(*json);
        *json = NULL;
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the summary");
    }
    return HSBD_OK;
}
