/* The observers of a run (run.h): built from a model's list, called at every stage. */
#include "run/run.h"

static int observer_sample(run *r, void *ctx, hsbd_error *err) {
    const run_observer *o = ctx;
    return o->ops->sample(r, o->state, err);
}

int run_observers_build(run *r, const run_observer_ops *const *list, hsbd_error *err) {
    for (; *list; ++list) {
        void *state = NULL;
        int rc = (*list)->build(r, &state, err);
        if (rc != HSBD_OK || !state) {
            if (state && (*list)->free) (*list)->free(state);
            if (rc != HSBD_OK) return rc;
            continue;
        }
        if (r->nobservers == RUN_MAX_OBSERVERS) {
            if ((*list)->free) (*list)->free(state);
            return hsbd_error_set(err, HSBD_ENOMEM, "run: too many observers (%s)", (*list)->name);
        }
        run_observer *o = &r->observers[r->nobservers++];
        *o = (run_observer){*list, state};
        const uint64_t every = o->ops->every ? o->ops->every(r) : (uint64_t)r->cfg->sample.every;
        if (o->ops->sample && every > 0)
            rc = run_add_op(r, o->ops->name, every, observer_sample, o, err);
        if (rc != HSBD_OK) return rc;
    }
    return HSBD_OK;
}

void run_observers_start_production(run *r) {
    for (size_t k = 0; k < r->nobservers; ++k)
        if (r->observers[k].ops->start_production)
            r->observers[k].ops->start_production(r, r->observers[k].state);
}

int run_observers_end_replica(run *r, hsbd_error *err) {
    for (size_t k = 0; k < r->nobservers; ++k) {
        const run_observer *o = &r->observers[k];
        const int rc = o->ops->end_replica ? o->ops->end_replica(r, o->state, err) : HSBD_OK;
        if (rc != HSBD_OK) return rc;
    }
    return HSBD_OK;
}

void run_observers_start_replica(run *r) {
    for (size_t k = 0; k < r->nobservers; ++k)
        if (r->observers[k].ops->start_replica)
            r->observers[k].ops->start_replica(r, r->observers[k].state);
}

void run_observers_replica_ready(run *r) {
    for (size_t k = 0; k < r->nobservers; ++k)
        if (r->observers[k].ops->replica_ready)
            r->observers[k].ops->replica_ready(r, r->observers[k].state);
}

void run_observers_save(const run *r, hsbd_writer *w) {
    for (size_t k = 0; k < r->nobservers; ++k) {
        const run_observer *o = &r->observers[k];
        hsbd_put_tag(w, o->ops->name);
        if (o->ops->save) o->ops->save(r, o->state, w);
    }
}

int run_observers_load(run *r, hsbd_reader *rd) {
    for (size_t k = 0; k < r->nobservers; ++k) {
        const run_observer *o = &r->observers[k];
        if (hsbd_get_tag(rd, o->ops->name) || (o->ops->load && o->ops->load(r, o->state, rd)))
            return -1;
    }
    return 0;
}

int run_observers_write_tables(const run *r, hsbd_error *err) {
    for (size_t k = 0; k < r->nobservers; ++k) {
        const run_observer *o = &r->observers[k];
        const int rc = o->ops->write_tables ? o->ops->write_tables(r, o->state, err) : HSBD_OK;
        if (rc != HSBD_OK) return rc;
    }
    return HSBD_OK;
}

void run_observers_write_summary(const run *r, FILE *f) {
    for (size_t k = 0; k < r->nobservers; ++k)
        if (r->observers[k].ops->write_summary)
            r->observers[k].ops->write_summary(r, r->observers[k].state, f);
}

void run_observers_expose(const run *r, hsbd_sim_parts *parts) {
    for (size_t k = 0; k < r->nobservers; ++k)
        if (r->observers[k].ops->expose)
            r->observers[k].ops->expose(r, r->observers[k].state, parts);
}

void run_observers_free(run *r) {
    for (size_t k = 0; k < r->nobservers; ++k)
        if (r->observers[k].ops->free) r->observers[k].ops->free(r->observers[k].state);
    r->nobservers = 0;
}
