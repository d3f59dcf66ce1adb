/* The memory a run will need, estimated from its configuration before anything is
 * allocated, and refused beyond a share of the machine's physical memory. */
#include "config/schema.h"

#include <unistd.h>

/* Bytes per particle of the engines with their run drivers, measured as the slope of the
 * peak resident size over N (/usr/bin/time -v, hsbd run with t_total = 4 steps, e504a92):
 * rods 80 B (N 1e6 .. 8e6: 104 B minus the MSD's three snapshots of 8 B); spheres 3D
 * 700-850 B at phi 0.3 (N 2.5e5 .. 1e6), 2D 620-650 B, more at higher phi as the
 * neighbour lists fill (docs/config.md). The constants round those up. */
enum { RODS_BYTES = 96, SPHERES_BYTES_2D = 900, SPHERES_BYTES_3D = 1300 };
/* active particles add their orientation, v0, D_r, swim weight, the rotation's draws and
 * the free velocities (src/spheres/active.c): 14 doubles */
enum { ACTIVE_BYTES = 14 * 8 };
/* the share of the machine's physical memory a run may plan to use */
#define MEMORY_SHARE 0.8

/* The MSD observer of `items` coordinates (hsbd_msd_alloc): its snapshots, its lag table
 * (one entry per sample up to the largest lag) and its values per lag and origin (twice
 * with F_s); parts[0..2] += those. */
static void msd_memory(const hsbd_config *cfg, double items, int fs, double copies,
                       memory_part *parts) {
    const double samples = floor((double)hsbd_config_steps(cfg) / (double)cfg->sample.every);
    const double sample_dt = cfg->run.dt * (double)cfg->sample.every;
    double lmax = fmin(floor(cfg->sample.msd_max_lag / sample_dt + 1e-9), fmax(samples - 1, 0));
    lmax = fmax(lmax, 1);
    double slots = floor((128.0 * 1024 * 1024) / (8 * fmax(items, 1)));
    slots = fmin(fmax(slots, 4), 64);
    double every = fmax(floor((lmax + slots - 2) / (slots - 1)), 1);
    every = fmax(every, floor(samples / 4000));
    const double alive = floor(lmax / every) + 2, origins = floor(samples / every) + 1;
    const double lags = (double)cfg->sample.msd_points_per_decade * (log10(lmax) + 1) + 2;
    parts[0].bytes += copies * alive * items * 8;
    parts[1].bytes += copies * (lmax + 1) * 8;
    parts[2].bytes += copies * lags * origins * 8 * (fs ? 2 : 1);
}

/* the particles' part: bytes per particle times N */
static memory_part particles_part(const hsbd_config *cfg, double bytes_per_particle) {
    return (memory_part){(double)cfg->system.n * bytes_per_particle, "system", "N",
                         "the particles"};
}

/* the MSD's three parts (parts[0..2]) for `items` coordinates, with one more MSD per
 * species when there are at least `own_from` species */
static size_t msd_parts(const hsbd_config *cfg, double items, int fs, size_t own_from,
                        memory_part *parts) {
    parts[0] = (memory_part){0, "system", "N", "the MSD's snapshots"};
    parts[1] = (memory_part){0, "sample", "msd_max_lag", "the MSD's lag table"};
    parts[2] = (memory_part){0, "sample", "msd_points_per_decade", "the MSD's values"};
    const double per_species = cfg->species.n >= own_from ? (double)cfg->species.n : 0;
    msd_memory(cfg, items, fs, 1 + per_species, parts);
    return 3;
}

/* rods: the ring, the MSD of N positions (one per species with species), the profiles */
size_t config_memory_rods(const hsbd_config *cfg, int particles_only, memory_part *parts) {
    parts[0] = particles_part(cfg, RODS_BYTES);
    if (particles_only) return 1;
    size_t np = 1 + msd_parts(cfg, (double)cfg->system.n, 0, 1, parts + 1);
    const double bins = round(cfg->sample.period / cfg->sample.bin_width);
    parts[np++] = (memory_part){4 * bins * 8 * (1 + (double)cfg->sample.blocks), "sample",
                                "bin_width", "the profiles' bins"};
    return np;
}

/* spheres: the particles, the MSD of d N coordinates with F_s (one per species from two
 * species on), g(r)'s bins and the density profiles across walls or along the field */
size_t config_memory_spheres(const hsbd_config *cfg, int particles_only, memory_part *parts) {
    const double n = (double)cfg->system.n, d = (double)cfg->system.dimension;
    parts[0] = particles_part(cfg, (d == 3 ? SPHERES_BYTES_3D : SPHERES_BYTES_2D) +
                                       (cfg->active.on ? ACTIVE_BYTES : 0));
    if (particles_only) return 1;
    size_t np = 1 + msd_parts(cfg, d * n, 1, 2, parts + 1);
    if (cfg->active.on) /* orientation.tsv: the MSD accumulators of the unit vectors */
        msd_memory(cfg, d * n, 0, 1 + (cfg->species.n >= 2 ? (double)cfg->species.n : 0),
                   parts + 1);
    const double blocks = (double)cfg->sample.blocks;
    const double pairs = cfg->species.n ? cfg->species.n * (cfg->species.n + 1) / 2.0 : 1;
    const double bins = ceil(cfg->sample.gr_max / cfg->sample.gr_bin) + 10;
    const double ns = cfg->species.n ? (double)cfg->species.n : 1;
    double gr_bytes = pairs * bins * 8 * (3 + blocks), profiles = 0;
    for (int a = 0; a < (int)d; ++a) {
        if (!cfg->system.walls[a] && !(cfg->field.type && cfg->field.axis == a)) continue;
        profiles += /* src/run/walls.c */
            (ceil(cfg->system.box[a] / cfg->sample.bin_width) + 8) * ns * 8 * (3 + blocks);
        /* g(r)'s own profile in z bins of half its r bins, and its reference weights
         * (src/observe/gr.c; an upper bound when g(r) is not measured there) */
        const double nz = ceil(2 * cfg->system.box[a] / cfg->sample.gr_bin) + 1;
        gr_bytes += (ns * nz * (3 + blocks) + pairs * fmin(nz, 2 * bins) * bins) * 8;
    }
    parts[np++] = (memory_part){gr_bytes, "sample", "gr_bin", "g(r)'s bins"};
    parts[np++] = (memory_part){profiles, "sample", "bin_width", "the density profiles' bins"};
    return np;
}

/* The machine's physical memory in bytes (0 when unknown: nothing is refused). */
static double physical_memory(void) {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    return pages > 0 && size > 0 ? (double)pages * (double)size : 0;
}

/* MEMORY_SHARE of the machine's memory at most */
int config_check_memory(const hsbd_config *cfg, int particles_only, hsbd_error *err) {
    memory_part parts[8];
    const size_t np = config_model(cfg)->memory(cfg, particles_only, parts);
    double total = 0;
    size_t big = 0;
    for (size_t k = 0; k < np; ++k) {
        total += parts[k].bytes;
        if (parts[k].bytes > parts[big].bytes) big = k;
    }
    const double have = physical_memory(), gib = 1024.0 * 1024 * 1024;
    if (have == 0 || total <= MEMORY_SHARE * have) return HSBD_OK;
    char value[HSBD_PATH_MAX + 64];
    const key_spec *k = config_find_key(parts[big].section, parts[big].key);
    config_format_value(cfg, k, value, sizeof value);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: %s.%s = %s: the run needs an estimated %.3g GiB of memory (%.3g "
                          "GiB for %s), more than %.0f%% of this machine's %.3g GiB; allowed: "
                          "a smaller run (docs/config.md, memory)",
                          config_origin_of(cfg, parts[big].section, parts[big].key),
                          parts[big].section, parts[big].key, value, total / gib,
                          parts[big].bytes / gib, parts[big].what, 100 * MEMORY_SHARE, have / gib);
}
