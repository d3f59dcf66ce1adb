/* log.tsv: a time series of the production's quantities, a line every output.log_every of
 * simulated time (the production's time first). Rods: the particle current over the
 * interval, the mean cluster size at its end (hard core) and, between walls, each wall's
 * contact density (its force / kT) averaged over the interval's samples; disks and
 * spheres: collisions per particle-step and, in a homogeneous periodic box, the virial
 * pressure over the interval (Scala's collisional virial, as Z_virial), between walls each
 * wall's pressure (kT times its contact density, from the wall impulses). Only the
 * simulation's state enters, so the file follows the seed byte for byte and a resumed run
 * continues it as if never stopped; wall-clock rates are the progress lines'. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/tables.h"
#include "run/observers.h"
#include "run/rods_model.h"
#include "run/spheres_model.h"

typedef struct log_state {
    run_stream *stream;
    uint64_t steps;     /* production steps between lines */
    uint64_t last_step; /* of the last line */
    int rods, walls;    /* rods: walls sampled every sample.every; spheres: walls columns */
    int virial;         /* spheres: the virial column */
    /* rods: the sum of unwrapped positions at the last line (or a replica's start), the
     * displacement of the interval's earlier replicas, the walls' sums over its samples */
    double sum_last, moved, wall_sum[2];
    uint64_t wall_samples;
    /* spheres: the engine's sums at the last line (6 wall impulses per species, summed) */
    uint64_t collisions_last;
    double virial_last, impulse_last[6], *scratch;
} log_state;

static int spheres_walls(const hsbd_config *cfg) {
    return cfg->system.walls[0] || cfg->system.walls[1] || cfg->system.walls[2];
}

/* the columns, as the observer was built for the run */
static void header(const run *r, FILE *f) {
    const hsbd_config *cfg = r->cfg;
    char columns[256] = "t";
    if (cfg->system.model == HSBD_MODEL_RODS) {
        strcat(columns, "\tJ");
        if (cfg->system.hard_core) strcat(columns, "\tmean_cluster_size");
        if (cfg->system.hard_core && cfg->system.boundary == HSBD_BOUNDARY_WALLS)
            strcat(columns, "\twall_left\twall_right");
    } else {
        strcat(columns, "\tcollisions_per_particle_step");
        if (cfg->system.hard_core && !cfg->field.type && !spheres_walls(cfg))
            strcat(columns, "\tP_virial");
        for (int a = 0; a < (int)cfg->system.dimension; ++a)
            if (cfg->system.walls[a])
                snprintf(columns + strlen(columns), sizeof columns - strlen(columns),
                         "\tP_wall_%c_low\tP_wall_%c_high", "xyz"[a], "xyz"[a]);
    }
    hsbd_write_table_header(
        f, cfg,
        cfg->system.model == HSBD_MODEL_RODS
            ? "time series of the production, a line every output.log_every: t, the particle "
              "current J over the interval (sum of displacements / (L interval)), the mean "
              "cluster size N / clusters at t, between walls each wall's contact density "
              "(force / kT) averaged over the interval's samples"
            : "time series of the production, a line every output.log_every: t, collisions "
              "per particle-step over the interval, the virial pressure P = (N/V) kT (1 + "
              "virial / (d N interval)) over the interval (periodic box without a field), "
              "each wall's pressure kT x impulse / (kT interval area) over the interval",
        columns);
}

static void release(void *state) {
    log_state *l = state;
    if (l) free(l->scratch);
    free(l);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (!(cfg->output.log_every > 0)) return HSBD_OK;
    log_state *l = calloc(1, sizeof *l);
    if (!l) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = l;
    l->steps = run_every(cfg, cfg->output.log_every);
    l->rods = cfg->system.model == HSBD_MODEL_RODS;
    if (l->rods) {
        l->walls = cfg->system.hard_core && cfg->system.boundary == HSBD_BOUNDARY_WALLS;
    } else {
        l->walls = spheres_walls(cfg);
        l->virial = cfg->system.hard_core && !cfg->field.type && !l->walls;
        const size_t ns = cfg->species.n ? cfg->species.n : 1;
        if (l->walls && !(l->scratch = malloc(6 * ns * sizeof *l->scratch)))
            return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    }
    if (!(l->stream = run_add_stream(r, "log.tsv", err))) return err->status;
    l->stream->header = header;
    return HSBD_OK;
}

/* rods between walls sample the walls every sample.every steps; else a call per line */
static uint64_t every(const run *r) {
    const hsbd_config *cfg = r->cfg;
    const int rod_walls = cfg->system.model == HSBD_MODEL_RODS && cfg->system.hard_core &&
                          cfg->system.boundary == HSBD_BOUNDARY_WALLS;
    const uint64_t line = run_every(cfg, cfg->output.log_every);
    const uint64_t sample = (uint64_t)cfg->sample.every;
    return !rod_walls ? line : line % sample == 0 ? sample : 1;
}

/* the spheres' wall impulses now, summed over the species, per wall (6) */
static void wall_impulses(const run *r, const log_state *l, double out[6]) {
    const size_t ns = r->cfg->species.n ? r->cfg->species.n : 1;
    hsbd_spheres_wall_impulses(spheres_model_of(r)->sys, l->scratch);
    for (int q = 0; q < 6; ++q) {
        out[q] = 0;
        for (size_t k = 0; k < ns; ++k)
            out[q] += l->scratch[6 * k + q];
    }
}

static void rods_line(run *r, log_state *l, double span) {
    const hsbd_config *cfg = r->cfg;
    const hsbd_rods *rods = rods_model_of(r)->rods;
    FILE *f = l->stream->file.f;
    const double sum = rods_sum_unwrapped(rods);
    fprintf(f, "\t%.10g", (l->moved + sum - l->sum_last) / (cfg->system.length * span));
    l->sum_last = sum, l->moved = 0;
    if (cfg->system.hard_core)
        fprintf(f, "\t%.10g", (double)cfg->system.n / (double)hsbd_rods_cluster_count(rods));
    for (int w = 0; w < 2 && l->walls; ++w)
        fprintf(f, "\t%.10g", l->wall_sum[w] / (double)l->wall_samples);
    l->wall_sum[0] = l->wall_sum[1] = 0, l->wall_samples = 0;
}

static void spheres_line(run *r, log_state *l, double span, uint64_t steps) {
    const hsbd_config *cfg = r->cfg;
    const hsbd_spheres_stats st = hsbd_spheres_get_stats(spheres_model_of(r)->sys);
    FILE *f = l->stream->file.f;
    const double n = (double)cfg->system.n, dim = (double)cfg->system.dimension;
    fprintf(f, "\t%.10g", (double)(st.collisions - l->collisions_last) / (n * (double)steps));
    double volume = 1;
    for (int a = 0; a < (int)dim; ++a)
        volume *= cfg->system.box[a];
    if (l->virial) /* P = rho kT Z, Z = 1 + virial / (d N t) (as Z_virial) */
        fprintf(f, "\t%.10g",
                n / volume * cfg->system.kT *
                    (1 + (st.virial - l->virial_last) / (dim * n * span)));
    l->collisions_last = st.collisions, l->virial_last = st.virial;
    if (!l->walls) return;
    double now[6];
    wall_impulses(r, l, now);
    for (int a = 0; a < (int)dim; ++a)
        for (int side = 0; side < 2 && cfg->system.walls[a]; ++side) {
            const int q = 2 * a + side;
            const double area = volume / cfg->system.box[a];
            fprintf(f, "\t%.10g", cfg->system.kT * (now[q] - l->impulse_last[q]) / (span * area));
        }
    memcpy(l->impulse_last, now, sizeof now);
}

static int sample(run *r, void *state, hsbd_error *err) {
    log_state *l = state;
    if (l->rods && l->walls) { /* every sample: the walls' contact densities */
        double w[2];
        const hsbd_rods_view v = hsbd_rods_get_view(rods_model_of(r)->rods);
        hsbd_wall_impulses(&v, w);
        l->wall_sum[0] += w[0], l->wall_sum[1] += w[1], l->wall_samples += 1;
    }
    if (r->steps_done % l->steps) return HSBD_OK;
    const uint64_t steps = r->steps_done - l->last_step;
    const double span = (double)steps * r->cfg->run.dt;
    fprintf(l->stream->file.f, "%.10g", (double)r->steps_done * r->cfg->run.dt);
    if (l->rods)
        rods_line(r, l, span);
    else
        spheres_line(r, l, span, steps);
    fputc('\n', l->stream->file.f);
    l->last_step = r->steps_done;
    return run_stream_check(l->stream, err);
}

/* production begins (the spheres' sums were reset) */
static void start_production(run *r, void *state) {
    log_state *l = state;
    l->last_step = r->steps_done;
    if (l->rods) {
        l->sum_last = rods_sum_unwrapped(rods_model_of(r)->rods);
        return;
    }
    l->collisions_last = 0, l->virial_last = 0;
    memset(l->impulse_last, 0, sizeof l->impulse_last);
}

/* rods' replicas: the displacement of the one that ends stays in the interval's current */
static int end_replica(run *r, void *state, hsbd_error *err) {
    (void)err;
    log_state *l = state;
    if (l->rods) l->moved += rods_sum_unwrapped(rods_model_of(r)->rods) - l->sum_last;
    return HSBD_OK;
}

static void replica_ready(run *r, void *state) {
    log_state *l = state;
    if (l->rods) l->sum_last = rods_sum_unwrapped(rods_model_of(r)->rods);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    const log_state *l = state;
    const double sums[5] = {l->sum_last, l->moved, l->wall_sum[0], l->wall_sum[1], l->virial_last};
    hsbd_put_f64s(w, sums, 5);
    hsbd_put_f64s(w, l->impulse_last, 6);
    const uint64_t counts[3] = {l->last_step, l->wall_samples, l->collisions_last};
    for (int k = 0; k < 3; ++k)
        hsbd_put_u64(w, counts[k]);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    log_state *l = state;
    double sums[5];
    if (hsbd_get_f64s(rd, sums, 5) || hsbd_get_f64s(rd, l->impulse_last, 6) ||
        hsbd_get_u64(rd, &l->last_step) || hsbd_get_u64(rd, &l->wall_samples) ||
        hsbd_get_u64(rd, &l->collisions_last))
        return -1;
    l->sum_last = sums[0], l->moved = sums[1], l->wall_sum[0] = sums[2];
    l->wall_sum[1] = sums[3], l->virial_last = sums[4];
    return 0;
}

const run_observer_ops run_observe_log = {.name = "log",
                                          .build = build,
                                          .every = every,
                                          .sample = sample,
                                          .start_production = start_production,
                                          .end_replica = end_replica,
                                          .replica_ready = replica_ready,
                                          .save = save,
                                          .load = load,
                                          .free = release};
