/* Both models: the run's frames every output.trajectory_every into trajectory.xyz
 * (extended XYZ) or trajectory.gsd (GSD, HOOMD schema), docs/trajectories.md. */
#include "hsbd/io.h"
#include "run/observers.h"

static int build(run *r, void **state, hsbd_error *err) {
    const int format = r->cfg->output.trajectory;
    if (format == HSBD_TRAJ_NONE) return HSBD_OK;
    run_stream *s =
        run_add_stream(r, format == HSBD_TRAJ_GSD ? "trajectory.gsd" : "trajectory.xyz", err);
    if (!s) return err->status;
    s->is_gsd = format == HSBD_TRAJ_GSD;
    *state = s;
    return HSBD_OK;
}

static uint64_t every(const run *r) {
    return run_every(r->cfg, r->cfg->output.trajectory_every);
}

static int sample(run *r, void *state, hsbd_error *err) {
    run_stream *s = state;
    const hsbd_frame *f = run_frame(r);
    if (s->is_gsd) return hsbd_gsd_write(&s->gsd, f, err);
    hsbd_xyz_write(s->file.f, f);
    return run_stream_check(s, err);
}

const run_observer_ops run_observe_trajectory = {
    .name = "trajectory", .build = build, .every = every, .sample = sample};
