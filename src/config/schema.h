/* The configuration room's private interface: the schema table (one row per key: section,
 * name, the models that read it, type, range, default, doc), the table of models, and the
 * helpers its files share. schema.c holds the tables, origin.c where each key got its
 * value, parse.c reads values, INI lines and --set, dialect.c the authors' section-less
 * files, finalise.c the checks every model shares and finalise_<model>.c each model's own,
 * memory.c the run's memory estimate, emit.c --help, docs/config.md and the tables'
 * headers. */
#ifndef HSBD_CONFIG_SCHEMA_H
#define HSBD_CONFIG_SCHEMA_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "hsbd/config.h"

typedef enum { K_INT, K_UINT64, K_DOUBLE, K_STRING, K_ENUM, K_BOOL, K_TERMS } key_type;

/* flags of a key: open ends of its range; NO_HEADER: not a parameter of the results (where
 * and how often a run is saved), left out of the tables' headers so they stay identical */
enum { OPEN_MIN = 1, OPEN_MAX = 2, NO_HEADER = 4 };

/* the models that read a key (bit 1 << enum hsbd_model); setting a key that the chosen
 * model does not read is an error, and the tables' headers leave it out */
enum {
    RODS = 1 << HSBD_MODEL_RODS,
    SPHERES = 1 << HSBD_MODEL_SPHERES,
    ALL_MODELS = RODS | SPHERES
};

typedef struct key_spec {
    const char *section, *key;
    unsigned models; /* RODS, SPHERES or ALL_MODELS */
    key_type type;
    size_t offset;
    double min, max;
    unsigned flags;
    const char *def;     /* default, parsed like user input */
    const char *choices; /* K_ENUM: "a|b|c" (value = position); K_TERMS: "none|a|b|c", the
                            value a '+'-joined set of them (bit k-1 for choice k) */
    const char *doc;
} key_spec;

/* ---- schema.c: the table and look-ups ------------------------------------------------ */

extern const key_spec config_schema[];
extern const size_t config_nkeys;

const key_spec *config_find_key(const char *section, const char *key);
size_t config_key_index(const key_spec *k);
void *config_slot(hsbd_config *cfg, const key_spec *k);
const void *config_cslot(const hsbd_config *cfg, const key_spec *k);
/* is `name` a section of the table? */
int config_section_known(const char *name);
/* "[system], [contact], ...": the table's sections in its order */
void config_section_list(char *buf, size_t len);
/* the section of the table nearest to a misspelt one, and its edit distance */
const char *config_nearest_section(const char *name, size_t *distance);
/* Nearest known "section.key" to a misspelt one, in buf; NULL when none is near. */
const char *config_suggest(const char *section, const char *key, char *buf, size_t len);
/* The allowed values of a key as text ("0 < dt < inf", "one of a|b"). */
void config_format_range(const key_spec *k, char *buf, size_t len);
/* Does the configuration's model read this key? */
int config_key_read(const hsbd_config *cfg, const key_spec *k);

/* ---- origin.c: where each key got its value ------------------------------------------ */

/* Is a key at its default, or at one derived from other keys (set by no file or --set)? */
int config_is_default(const hsbd_config *cfg, const char *section, const char *key);
/* Where a key got its value, for messages: for a key at its default, the configuration
 * file (when there is one), so that every message names the file. */
const char *config_origin_of(const hsbd_config *cfg, const char *section, const char *key);
/* A key's origin as hsbd_config_origin() gives it. */
const char *config_origin_text(const hsbd_config *cfg, const key_spec *k);
/* Records a key read from line `line` of the file `path`. */
void config_origin_from_file(hsbd_config *cfg, const key_spec *k, const char *path, long line);
/* Records a key set by hsbd_config_set with its origin ("command line (--set)"). */
void config_origin_from_set(hsbd_config *cfg, const key_spec *k, const char *origin);
/* Records where a derived value came from ("default (L/2)"). */
void config_origin_derived(hsbd_config *cfg, const char *section, const char *key,
                           const char *note);
/* Records a value taken from the init.positions file (`what` names it): set, not a default. */
void config_origin_from_input(hsbd_config *cfg, const key_spec *k, const char *what);
/* Did the key take its value from the init.positions file? */
int config_from_input(const hsbd_config *cfg, const char *section, const char *key);

/* ---- parse.c: values ---------------------------------------------------------------- */

/* Strips blanks (and line ends) at both ends, in place. */
char *config_trim(char *s);
/* A decimal number that fills the whole text (no hexadecimal, octal-looking leading zeros,
 * inf or nan): 0, or -1 with what is wrong in *why (NULL: not a number at all). */
int config_parse_number(const char *v, double *d, const char **why);
/* Parse `text` into the key's slot; on failure a message naming the key and range. */
int config_parse_value(hsbd_config *cfg, const key_spec *k, const char *text, const char *where,
                       hsbd_error *err);
/* The key's value as text that reads back the same. */
void config_format_value(const hsbd_config *cfg, const key_spec *k, char *buf, size_t len);

/* The file being read: where we are, what it has set, whether it uses the authors'
 * section-less keys or hsbd's sections (never both). */
typedef struct {
    hsbd_config *cfg;
    const char *path;
    long line;
    const char *section;               /* the open [section] (a schema section name), or NULL */
    long first_section, first_authors; /* lines of the first [section] / section-less key */
    size_t keys;                       /* keys the file set */
    hsbd_error *err;
    char set_at[HSBD_CONFIG_MAX_KEYS]; /* key already set in this file */
} ini_state;

/* Sets a key from the current line of the file (`as`: the name the file gave it). */
int config_assign(ini_state *st, const key_spec *k, const char *value, const char *as);

/* ---- dialect.c: the authors' section-less keys ---------------------------------------- */

typedef struct {
    const char *name, *section, *key;
} authors_key;

extern const authors_key config_authors_keys[];
extern const size_t config_nauthors;

const authors_key *config_find_authors_key(const char *name);
/* A section-less "name = value" line of the authors' files. */
int config_authors_assign(ini_state *st, const char *name, const char *value);
/* What the authors' program fixes that their files do not say (field, kT). */
void config_authors_finish(hsbd_config *cfg);

/* ---- finalise.c: what the models' checks share ------------------------------------- */

/* a / b is a whole number (relative tolerance 1e-9) */
int config_divides(double b, double a);
/* Split a list on spaces and commas into at most `max` words; returns the count, or
 * max + 1 when there are more. */
size_t config_split_list(char *text, char **words, size_t max);
/* One numeric species list (count, sigma, D or coupling): as many finite entries as names,
 * each in [min, inf) (open at min when `open`), whole numbers when `whole`. */
int config_parse_species_numbers(hsbd_config *cfg, const char *key, const char *text, double min,
                                 int open, int whole, double *out, hsbd_error *err);
/* The [species] lists: names, counts summing to system.N, lengths and D. */
int config_parse_species(hsbd_config *cfg, hsbd_error *err);
/* system.boundary: one word (rods: dim 1) or one per axis, each periodic or walls, into
 * walls[a]. */
int config_parse_boundary(hsbd_config *cfg, int dim, int *walls, hsbd_error *err);
/* Checks of the run, sampling and output keys shared by every model (and their derived
 * defaults). */
int config_check_run_keys(hsbd_config *cfg, hsbd_error *err);

/* ---- init_file.c: what an init.positions file fixes ----------------------------------- */

/* What the file fixes: N; a GSD frame also its dimension, box, the types that have
 * particles (in the file's order: the species) with their counts and diameters; an
 * extended-XYZ frame its box when it gives a Lattice. */
typedef struct config_input {
    int kind;                      /* 0: no such file (or rods' text); 1: XYZ; 2: GSD */
    char what[HSBD_PATH_MAX + 64]; /* "init.positions 'x.gsd' (frame 3)", for messages */
    size_t n;
    int dimension, has_box; /* dimension 0: not given */
    double box[3];
    size_t ntypes;
    char names[HSBD_MAX_SPECIES][HSBD_SPECIES_NAME];
    int64_t count[HSBD_MAX_SPECIES];
    double sigma[HSBD_MAX_SPECIES]; /* each type's diameter, or their mean when they vary */
    int varies[HSBD_MAX_SPECIES];
} config_input;

/* Reads the file and fills the keys the configuration leaves unset with its values (their
 * origin names the file); refuses a restated N, dimension or species.names that disagree
 * (before the model's checks). */
int config_input_take(hsbd_config *cfg, config_input *in, hsbd_error *err);
/* After the model's checks: the box, counts and diameters the configuration restates
 * agree with the file's (relative 1e-6, the precision of GSD's float32). */
int config_input_check(const hsbd_config *cfg, const config_input *in, hsbd_error *err);
/* hsbd_config_particles of spheres from a GSD file: each particle's species (its type's),
 * diameter (its species' sigma, or the file's own where a type's diameters vary) and D. */
int config_input_particles(const hsbd_config *cfg, int *species, double *sigma, double *diffusion,
                           hsbd_error *err);

/* ---- the models: what differs between them ------------------------------------------ */

/* One part of a run's memory estimate and the key that makes it large. */
typedef struct memory_part {
    double bytes;
    const char *section, *key, *what;
} memory_part;

typedef struct model_spec {
    const char *name;     /* system.model's value */
    unsigned keys;        /* RODS or SPHERES: the keys of the schema the model reads */
    int point_particles;  /* species.sigma may be 0 (rods); else > 0 */
    int immobile_species; /* species.D may be 0 (spheres); else > 0 */
    /* its checks across keys and derived defaults (finalise_<model>.c) */
    int (*finalise)(hsbd_config *cfg, hsbd_error *err);
    /* its run's estimated memory (memory.c) in at most 8 parts, their count returned; the
     * particles' part first, and only it when `particles_only` */
    size_t (*memory)(const hsbd_config *cfg, int particles_only, memory_part *parts);
} model_spec;

/* schema.c: one row per enum hsbd_model */
extern const model_spec config_models[];
extern const size_t config_nmodels;
/* The configuration's model; NULL when system.model is none of enum hsbd_model. */
const model_spec *config_model(const hsbd_config *cfg);

int config_finalise_rods(hsbd_config *cfg, hsbd_error *err);
int config_finalise_spheres(hsbd_config *cfg, hsbd_error *err);
size_t config_memory_rods(const hsbd_config *cfg, int particles_only, memory_part *parts);
size_t config_memory_spheres(const hsbd_config *cfg, int particles_only, memory_part *parts);

/* ---- memory.c ---------------------------------------------------------------------- */

/* Refuses a run whose estimated memory exceeds a share of the machine's, naming the key
 * behind its largest part. `particles_only`: only the particles' part (before anything of
 * size N is allocated while finalising). */
int config_check_memory(const hsbd_config *cfg, int particles_only, hsbd_error *err);

#endif
