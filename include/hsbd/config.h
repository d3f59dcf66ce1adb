/* Run configuration: one schema table gives every key its type, range, default and doc;
 * it drives parsing (INI files, --set overrides), validation, `hsbd run
 * --help` and docs/config.md. Errors name the file, line, key and allowed range. */
#ifndef HSBD_CONFIG_H
#define HSBD_CONFIG_H

#include "hsbd/export.h"
#include <stdint.h>
#include <stdio.h>

#include "hsbd/error.h"

enum hsbd_model { HSBD_MODEL_RODS = 0, HSBD_MODEL_SPHERES };
enum hsbd_init_method {
    HSBD_INIT_AUTO = 0,
    HSBD_INIT_RANDOM,
    HSBD_INIT_LATTICE,
    HSBD_INIT_COMPRESS
};
enum hsbd_d_law { HSBD_D_GIVEN = 0, HSBD_D_STOKES_EINSTEIN };
/* field.type is a sum of terms, e.g. "cosine+tilt": one bit per term */
enum hsbd_field_terms {
    HSBD_FIELD_NONE = 0,
    HSBD_FIELD_COSINE = 1,
    HSBD_FIELD_TILT = 2,
    HSBD_FIELD_HARMONIC = 4,
    HSBD_FIELD_TABLE = 8
};
/* drive.parameter: the field parameter a drive changes in time (the term it belongs to) */
enum hsbd_drive_parameter {
    HSBD_DRIVE_NONE = 0,
    HSBD_DRIVE_FORCE,     /* tilt */
    HSBD_DRIVE_AMPLITUDE, /* cosine: U0 */
    HSBD_DRIVE_SHIFT,     /* cosine: its position (a travelling wave) */
    HSBD_DRIVE_STIFFNESS, /* harmonic */
    HSBD_DRIVE_CENTER     /* harmonic: its centre (dragged or oscillating trap) */
};
enum hsbd_boundary { HSBD_BOUNDARY_PERIODIC = 0, HSBD_BOUNDARY_WALLS };
enum hsbd_coupling_law { HSBD_COUPLING_GIVEN = 0, HSBD_COUPLING_VOLUME = 1 };
enum hsbd_pair_type { HSBD_PAIR_NONE = 0, HSBD_PAIR_YUKAWA, HSBD_PAIR_LJ, HSBD_PAIR_TABLE };
enum hsbd_trajectory { HSBD_TRAJ_NONE = 0, HSBD_TRAJ_XYZ, HSBD_TRAJ_GSD };
enum hsbd_blocking { HSBD_BLOCKS_TIME = 0, HSBD_BLOCKS_SPACE, HSBD_BLOCKS_REPLICAS };
enum {
    HSBD_PATH_MAX = 1024,
    HSBD_ORIGIN_MAX = 1100, /* an origin's text, with its NUL (longer ones are cut) */
    HSBD_CONFIG_MAX_KEYS = 128,
    HSBD_ORIGIN_TEXTS = 2048, /* the distinct texts the origins of one configuration name */
    HSBD_ORIGIN_RING = 4,     /* origins whose texts are valid at once */
    HSBD_MAX_SPECIES = 16,
    HSBD_SPECIES_NAME = 32
};

/* Where one key got its value: its kind (default, a file's line, --set, a derived default;
 * src/config/origin.c), the file's line, and where its text (the file's name, the origin
 * given to hsbd_config_set, the derived default's note) starts in hsbd_origins.texts. */
typedef struct hsbd_key_origin {
    long line;
    uint16_t text;
    uint8_t kind;
} hsbd_key_origin;

/* Every key's origin and the texts they name, each held once. Without pointers: a copy of
 * the configuration by value keeps its origins. hsbd_config_origin() formats into `ring`,
 * so the last HSBD_ORIGIN_RING texts it returned for a configuration are valid at once (one
 * configuration is not asked for origins by two threads at once). */
typedef struct hsbd_origins {
    hsbd_key_origin key[HSBD_CONFIG_MAX_KEYS];
    char texts[HSBD_ORIGIN_TEXTS];
    uint16_t texts_used, ring_next;
    char ring[HSBD_ORIGIN_RING][HSBD_ORIGIN_MAX];
} hsbd_origins;

typedef struct hsbd_config {
    struct {
        int model;
        int64_t n;
        double length, sigma, diffusion, kT;
        uint64_t seed;
        int hard_core;
        int contact_rule;
        int boundary; /* rods: enum hsbd_boundary, parsed from boundary_text */
        char boundary_text[HSBD_PATH_MAX];
        /* spheres */
        int walls[3]; /* per axis: 1 hard walls, 0 periodic (from boundary_text) */
        int64_t dimension;
        char box_text[HSBD_PATH_MAX], drift_text[HSBD_PATH_MAX];
        double packing_fraction, shell;
        double box[3], drift[3]; /* parsed by hsbd_config_finalize */
    } system;
    struct {
        double gamma, order, epsilon;
    } contact;
    struct {
        int type;
        double strength, kappa, cutoff;
        char table[HSBD_PATH_MAX];
    } pair;
    struct {
        int type; /* bits of enum hsbd_field_terms */
        double amplitude, wavelength, force, stiffness, center;
        char table[HSBD_PATH_MAX];
        int table_kind; /* HSBD_TABLE_POTENTIAL or HSBD_TABLE_FORCE */
        int axis;       /* spheres: the coordinate the field acts on (0 x, 1 y, 2 z) */
    } field;
    struct {
        int parameter; /* enum hsbd_drive_parameter */
        int wave;      /* enum hsbd_wave of hsbd/field.h */
        double amplitude, period, phase, velocity;
    } drive;
    struct {
        /* the keys' texts: whitespace- or comma-separated lists */
        char names_text[HSBD_PATH_MAX], count_text[HSBD_PATH_MAX], sigma_text[HSBD_PATH_MAX],
            d_text[HSBD_PATH_MAX], fraction_text[HSBD_PATH_MAX];
        /* parsed by hsbd_config_finalize; n = 0: one species (system.sigma, system.D) */
        size_t n;
        char name[HSBD_MAX_SPECIES][HSBD_SPECIES_NAME];
        int64_t count[HSBD_MAX_SPECIES];
        double sigma[HSBD_MAX_SPECIES], diffusion[HSBD_MAX_SPECIES];
        /* spheres: relative width of the diameters about each species' sigma, its
         * distribution (enum hsbd_size_distribution), and the law for D (enum hsbd_d_law) */
        double polydispersity;
        int distribution, d_law;
        /* spheres: the field's factor per species (species.coupling, or 1), and its law
         * (enum hsbd_coupling_law: volume scales it with (sigma_i / system.sigma)^d) */
        char coupling_text[HSBD_PATH_MAX];
        double coupling[HSBD_MAX_SPECIES];
        int coupling_law;
    } species;
    struct {
        /* spheres: active Brownian particles (docs/active.md); the keys' texts, one value or
         * one per species, parsed by hsbd_config_finalize into per-species values (on = 0:
         * none active; rotational_default: D_r = 3 D_i / sigma_i^2 of each particle) */
        char v0_text[HSBD_PATH_MAX], rotational_text[HSBD_PATH_MAX];
        int on, rotational_default;
        double v0[HSBD_MAX_SPECIES], rotational[HSBD_MAX_SPECIES];
    } active;
    struct {
        double dt, t_equil, t_total, dt_equil;
        /* ensembles: replicas in all (0: one per MPI rank), and this run's replica index
         * (-1: not one replica of an ensemble) */
        int64_t replicas, replica;
        /* threads of one run (0: the cores the process may use) */
        int64_t threads;
        int events;     /* spheres: hsbd_spheres_event_order */
        int field_step; /* enum hsbd_field_step of hsbd/field.h */
        int pair_rule;  /* spheres: enum hsbd_pair_rule of hsbd/spheres.h */
    } run;
    struct {
        double bin_width, contact_width, period;
        int64_t every, blocks, msd_points_per_decade;
        double msd_max_lag, current_every;
        int blocking;
        int64_t gr_every;
        double gr_max, gr_bin, contact_fit, fs_k;
        int64_t sk_every;            /* S(k) every this many steps (0: off) */
        double sk_max;               /* its largest |k| (0: 20 / system.sigma) */
        int64_t local_density_every; /* the local packing fraction's histogram (0: off) */
        double local_density_cell;   /* its cells' side (0: 5 system.sigma) */
        int64_t phases; /* profiles resolved by the drive's phase: bins of its period */
    } sample;
    struct {
        char dir[HSBD_PATH_MAX];
        int trajectory;
        double trajectory_every;
        double log_every;        /* log.tsv: time between its lines (0: none) */
        int checkpoints;         /* write checkpoints (resumable runs) */
        double checkpoint_every; /* simulated time between them (0: by wall time) */
        double checkpoint_wall;  /* wall-clock seconds between them (the first: a tenth) */
    } output;
    struct {
        char positions[HSBD_PATH_MAX];
        int method;    /* enum hsbd_init_method */
        int64_t frame; /* of a GSD file (-1: the last) */
        int gsd;       /* init.positions is a GSD file (set by hsbd_config_finalize) */
    } init;
    hsbd_origins origins;     /* where each schema key got its value */
    char file[HSBD_PATH_MAX]; /* the configuration file read, if any */
    int authors_dialect;      /* the file used the authors' section-less keys */
} hsbd_config;

/* Fill every key with its default. */
HSBD_API void hsbd_config_defaults(hsbd_config *cfg);
/* Read an INI file (hsbd sections, or the authors' section-less keys; docs/config.md).
 * Lines of any length up to 1 MiB; a whole-line comment starts with '#' or ';', an inline
 * one with " #" or " ;". A file that sets no key, a directory, NUL bytes or control
 * characters, unknown sections or keys, keys set twice, and the authors' keys mixed with
 * sections are HSBD_EINPUT with the file and line. */
HSBD_API int hsbd_config_load_file(hsbd_config *cfg, const char *path, hsbd_error *err);
/* The same from an open stream; `name` stands for the file in messages and origins. */
HSBD_API int hsbd_config_load_stream(hsbd_config *cfg, FILE *f, const char *name, hsbd_error *err);
/* Apply "section.key=value" (from --set). */
HSBD_API int hsbd_config_set(hsbd_config *cfg, const char *assignment, const char *origin,
                             hsbd_error *err);
/* Derived defaults and checks that involve several keys; call once after all input. */
HSBD_API int hsbd_config_finalize(hsbd_config *cfg, hsbd_error *err);

/* Where a key got its value ("file:line", "<origin> section.key" for hsbd_config_set,
 * "default", or "default (<how it was derived>)"); "" for unknown keys. The text is valid
 * until the configuration changes or is asked for HSBD_ORIGIN_RING more origins. */
HSBD_API const char *hsbd_config_origin(const hsbd_config *cfg, const char *section,
                                        const char *key);

/* Spheres: each particle's propulsion speed v0 and rotational diffusion coefficient D_r
 * from [active] (0 for every particle when it is not set), given the particles' species,
 * diameters and D (as hsbd_config_particles gives them). */
HSBD_API void hsbd_config_active(const hsbd_config *cfg, const int *species, const double *sigma,
                                 const double *diffusion, double *v0, double *rotational);

/* Number of production / equilibration steps. */
HSBD_API uint64_t hsbd_config_steps(const hsbd_config *cfg);

/* Spheres: every particle's species (in blocks of species.count), diameter (drawn with
 * species.polydispersity from the seed) and D (species.D, or Stokes-Einstein from the
 * nominal values: D_i = D_k sigma_k / sigma_i), for a finalized configuration. Any of the
 * arrays (N values) may be NULL. */
HSBD_API int hsbd_config_particles(const hsbd_config *cfg, int *species, double *sigma,
                                   double *diffusion, hsbd_error *err);
HSBD_API uint64_t hsbd_config_equil_steps(const hsbd_config *cfg);
/* Time step of the equilibration (run.dt_equil, or run.dt when that is 0). */
HSBD_API double hsbd_config_dt_equil(const hsbd_config *cfg);

/* Every key as "prefix section.key = value" lines (TSV headers). */
HSBD_API void hsbd_config_write_header(const hsbd_config *cfg, FILE *out, const char *prefix);
/* Every key as a JSON object {"section": {"key": value, ...}, ...} at the given indent. */
HSBD_API void hsbd_config_write_json(const hsbd_config *cfg, FILE *out, int indent);
/* The schema as a Markdown reference (docs/config.md) or plain text (--help). */
HSBD_API void hsbd_config_write_reference(FILE *out, int markdown);

#endif
