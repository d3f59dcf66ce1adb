/* GSD input: one frame of a GSD file (HOOMD schema), as hsbd, HOOMD-blue or python3-gsd
 * write it, read back as an initial state; from the published file-layer specification
 * (src/io/gsd.c writes it): a 256-byte header, a name list (GSD 2: the names one after
 * the other; GSD 1: 64 bytes each), an index of 32-byte entries (an entry at location 0
 * is unused) and the chunks. A chunk that the frame lacks is frame 0's, else the schema's
 * default. Every count and location is checked against the file's length before
 * anything is allocated or read, so a cut or damaged file is refused with its reason. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/io.h"
#include "io/orientation.h"

#define GSD_MAGIC 0x65DF65DF65DF65DFull
enum { HEADER_BYTES = 256, ENTRY_BYTES = 32, NAME_BYTES = 64, INDEX_BLOCK = 4096 };

/* the chunks read */
enum {
    C_DIMENSIONS,
    C_BOX,
    C_N,
    C_TYPES,
    C_TYPEID,
    C_DIAMETER,
    C_POSITION,
    C_ORIENTATION,
    C_POSITION_DOUBLE,
    C_COUNT
};
static const char *const chunk_name[C_COUNT] = {
    "configuration/dimensions", "configuration/box",     "particles/N",
    "particles/types",          "particles/typeid",      "particles/diameter",
    "particles/position",       "particles/orientation", "log/hsbd/position"};

typedef struct entry {
    uint64_t frame, n, location;
    uint32_t m;
    int chunk; /* C_... */
    int type;
} entry;

typedef struct reader {
    FILE *f;
    const char *name;
    uint64_t size;          /* the file's length */
    int64_t id_of[C_COUNT]; /* the file's name id of each chunk read, or -1 */
    entry *kept;            /* entries of frame 0 and of the frame read */
    size_t nkept, cap;
    hsbd_error *err;
} reader;

static uint64_t get_le(const unsigned char *p, int bytes) {
    uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; --k)
        v = (v << 8) | p[k];
    return v;
}

/* bytes of one element of a GSD type (1 uint8 ... 10 double, 11 character), 0: unknown */
static size_t type_size(int type) {
    static const size_t size[] = {0, 1, 2, 4, 8, 1, 2, 4, 8, 4, 8, 1};
    return type >= 1 && type <= 11 ? size[type] : 0;
}

static int damaged(reader *r, const char *why) {
    return hsbd_error_set(r->err, HSBD_EINPUT, "%s: %s; allowed: a GSD file (HOOMD schema)",
                          r->name, why);
}

static int read_at(reader *r, uint64_t at, void *p, size_t bytes) {
    if (at > r->size || bytes > r->size - at)
        return damaged(r, "its index or name list lies beyond the file's end (cut short?)");
    if (fseeko(r->f, (off_t)at, SEEK_SET) != 0 || fread(p, 1, bytes, r->f) != bytes)
        return hsbd_error_set(r->err, HSBD_EIO, "%s: read error: %s", r->name, strerror(errno));
    return HSBD_OK;
}

/* The name list: which of the file's name ids are chunks read here. */
static int read_names(reader *r, uint64_t location, uint64_t entries, int packed) {
    for (int c = 0; c < C_COUNT; ++c)
        r->id_of[c] = -1;
    if (entries > r->size / NAME_BYTES)
        return damaged(r, "its name list lies beyond the file's end (cut short?)");
    const size_t bytes = (size_t)entries * NAME_BYTES;
    char *names = malloc(bytes + 1);
    if (!names) return hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
    int rc = read_at(r, location, names, bytes);
    names[bytes] = '\0';
    const size_t ids = packed ? bytes : (size_t)entries; /* GSD 1: 64 bytes a name */
    for (size_t id = 0, at = 0; rc == HSBD_OK && at < bytes && id < ids && id < (1 << 16); ++id) {
        const char *s = names + at;
        if (!*s) break;                   /* the end of the list */
        for (int c = 0; c < C_COUNT; ++c) /* the name and its NUL */
            if (r->id_of[c] < 0 && !strncmp(s, chunk_name[c], strlen(chunk_name[c]) + 1))
                r->id_of[c] = (int64_t)id;
        at += packed ? strnlen(s, bytes - at) + 1 : NAME_BYTES;
    }
    free(names);
    return rc;
}

static int chunk_of_id(const reader *r, uint64_t id) {
    for (int c = 0; c < C_COUNT; ++c)
        if (r->id_of[c] == (int64_t)id) return c;
    return -1;
}

/* Each used index entry in turn (those at location 0 are unused), in blocks. */
static int scan_index(reader *r, uint64_t location, uint64_t entries, uint64_t *frames,
                      uint64_t want) {
    if (entries > r->size / ENTRY_BYTES)
        return damaged(r, "its index lies beyond the file's end (cut short?)");
    unsigned char *block = malloc(INDEX_BLOCK * ENTRY_BYTES);
    if (!block) return hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
    int rc = HSBD_OK;
    for (uint64_t at = 0; rc == HSBD_OK && at < entries; at += INDEX_BLOCK) {
        const size_t count = entries - at < INDEX_BLOCK ? (size_t)(entries - at) : INDEX_BLOCK;
        rc = read_at(r, location + at * ENTRY_BYTES, block, count * ENTRY_BYTES);
        for (size_t k = 0; rc == HSBD_OK && k < count; ++k) {
            const unsigned char *p = block + k * ENTRY_BYTES;
            const entry e = {.frame = get_le(p, 8),
                             .n = get_le(p + 8, 8),
                             .location = get_le(p + 16, 8),
                             .m = (uint32_t)get_le(p + 24, 4),
                             .chunk = chunk_of_id(r, get_le(p + 28, 2)),
                             .type = p[30]};
            if (!e.location) continue;
            if (e.frame >= *frames) *frames = e.frame + 1;
            if (e.chunk < 0 || (e.frame != 0 && e.frame != want)) continue;
            if (r->nkept == r->cap) {
                r->cap = r->cap ? 2 * r->cap : 32;
                entry *grown = realloc(r->kept, r->cap * sizeof *grown);
                if (!grown) {
                    rc = hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
                    break;
                }
                r->kept = grown;
            }
            r->kept[r->nkept++] = e;
        }
    }
    free(block);
    return rc;
}

/* The frame's chunk, else frame 0's, else NULL (the schema's default). */
static const entry *chunk_of(const reader *r, int chunk, uint64_t frame) {
    const entry *first = NULL;
    for (size_t k = 0; k < r->nkept; ++k)
        if (r->kept[k].chunk == chunk) {
            if (r->kept[k].frame == frame) return &r->kept[k];
            if (r->kept[k].frame == 0) first = &r->kept[k];
        }
    return first;
}

/* A chunk's n x m elements as doubles into out (allocated), after checking its shape
 * (rows: 0 for any), its type and that it lies inside the file. */
static int read_numbers(reader *r, const entry *e, uint64_t rows, uint32_t m, double **out) {
    const size_t size = type_size(e->type);
    char why[160];
    if (!size || (rows && e->n != rows) || e->m != m || e->n == 0 || m == 0) {
        snprintf(why, sizeof why,
                 "%s of frame %llu has %llu x %u values of type %d; expected %llu x %u numbers",
                 chunk_name[e->chunk], (unsigned long long)e->frame, (unsigned long long)e->n, e->m,
                 e->type, (unsigned long long)(rows ? rows : e->n), m);
        return damaged(r, why);
    }
    if (e->n > r->size / size / m || e->location > r->size - e->n * m * size) {
        snprintf(why, sizeof why, "%s of frame %llu lies beyond the file's end (cut short?)",
                 chunk_name[e->chunk], (unsigned long long)e->frame);
        return damaged(r, why);
    }
    const size_t count = (size_t)e->n * m;
    unsigned char *raw = malloc(count * size);
    *out = malloc(count * sizeof **out);
    int rc = raw && *out ? read_at(r, e->location, raw, count * size)
                         : hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
    for (size_t k = 0; rc == HSBD_OK && k < count; ++k) {
        const uint64_t u = get_le(raw + k * size, (int)size);
        double v;
        if (e->type == 9) {
            const uint32_t bits = (uint32_t)u;
            float f;
            memcpy(&f, &bits, sizeof f);
            v = f;
        } else if (e->type == 10) {
            memcpy(&v, &u, sizeof v);
        } else if (e->type >= 5 && e->type <= 8) { /* signed: sign-extend */
            const int shift = 64 - 8 * (int)size;
            v = (double)((int64_t)(u << shift) >> shift);
        } else {
            v = (double)u;
        }
        (*out)[k] = v;
    }
    free(raw);
    return rc;
}

/* particles/types: rows of characters, each a name padded with NULs */
static int read_types(reader *r, const entry *e, hsbd_gsd_snapshot *s) {
    double *c = NULL;
    if (e->type != 1 && e->type != 5 && e->type != 11)
        return damaged(r, "particles/types is not of characters (int8, uint8 or character)");
    int rc = read_numbers(r, e, 0, e->m, &c);
    if (rc == HSBD_OK && !(s->types = calloc((size_t)e->n, sizeof *s->types)))
        rc = hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
    for (size_t t = 0; rc == HSBD_OK && t < e->n; ++t) {
        size_t len = 0;
        while (len < e->m && c[t * e->m + len] != 0)
            ++len;
        if (len == 0 || len >= HSBD_SPECIES_NAME) {
            char why[96];
            snprintf(why, sizeof why, "particles/types: type %zu has a name of %zu characters", t,
                     len);
            rc = damaged(r, why);
        }
        for (size_t k = 0; k < len; ++k)
            s->types[t][k] = (char)(unsigned char)(int)c[t * e->m + k];
    }
    if (rc == HSBD_OK) s->ntypes = (size_t)e->n;
    free(c);
    return rc;
}

/* One number of a chunk (dimensions, N), or `fallback` without one. */
static int read_scalar(reader *r, int chunk, uint64_t frame, double fallback, double *v) {
    const entry *e = chunk_of(r, chunk, frame);
    double *p = NULL;
    *v = fallback;
    if (!e) return HSBD_OK;
    const int rc = read_numbers(r, e, 1, 1, &p);
    if (rc == HSBD_OK) *v = p[0];
    free(p);
    return rc;
}

/* The configuration: dimensions, box (no tilt), N. */
static int read_configuration(reader *r, uint64_t frame, hsbd_gsd_snapshot *s) {
    double dim = 3, n = 0, *box = NULL;
    int rc = read_scalar(r, C_DIMENSIONS, frame, 3, &dim);
    if (rc == HSBD_OK) rc = read_scalar(r, C_N, frame, 0, &n);
    const entry *e = chunk_of(r, C_BOX, frame);
    if (rc == HSBD_OK && e) rc = read_numbers(r, e, 6, 1, &box);
    if (rc != HSBD_OK) return free(box), rc;
    char why[200];
    s->dimension = dim == 2 || dim == 3 ? (int)dim : 0;
    s->n = n >= 1 && n <= 2147483647.0 ? (size_t)n : 0; /* system.N's range */
    for (int a = 0; a < 3; ++a)
        s->box[a] = box ? box[a] : 1.0;
    const int tilted = box && (box[3] != 0 || box[4] != 0 || box[5] != 0);
    free(box);
    if (s->dimension == 0)
        snprintf(why, sizeof why, "configuration/dimensions = %g; allowed: 2 or 3", dim);
    else if (tilted)
        snprintf(why, sizeof why,
                 "frame %llu has a tilted (triclinic) box; allowed: a "
                 "rectangular box (tilt factors 0)",
                 (unsigned long long)frame);
    else if (!(s->box[0] > 0 && s->box[1] > 0 && (s->dimension == 2 || s->box[2] > 0)) ||
             !isfinite(s->box[0] + s->box[1] + s->box[2]))
        snprintf(why, sizeof why,
                 "frame %llu has the box %g x %g x %g; allowed: finite lengths > 0",
                 (unsigned long long)frame, s->box[0], s->box[1], s->box[2]);
    else if (s->n == 0)
        snprintf(why, sizeof why, "frame %llu has particles/N = %g; allowed: 1 .. 2147483647",
                 (unsigned long long)frame, n);
    else
        return HSBD_OK;
    return damaged(r, why);
}

/* The particles: types, typeid, diameter, positions (hsbd's float64 ones when present),
 * orientations when present. */
static int read_particles(reader *r, uint64_t frame, hsbd_gsd_snapshot *s) {
    const size_t n = s->n;
    char why[160];
    const entry *e = chunk_of(r, C_TYPES, frame);
    int rc = e ? read_types(r, e, s) : HSBD_OK;
    if (rc == HSBD_OK && !e) { /* the default: one type, A */
        if (!(s->types = calloc(1, sizeof *s->types)))
            return hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
        s->types[0][0] = 'A', s->ntypes = 1;
    }
    double *typeid = NULL;
    if (rc == HSBD_OK && (e = chunk_of(r, C_TYPEID, frame))) rc = read_numbers(r, e, n, 1, &typeid);
    if (rc == HSBD_OK && (e = chunk_of(r, C_DIAMETER, frame)))
        rc = read_numbers(r, e, n, 1, &s->diameter);
    const entry *exact = chunk_of(r, C_POSITION_DOUBLE, frame);
    if (exact && exact->frame != frame) exact = NULL; /* frame 0's would be stale */
    if (rc == HSBD_OK && (e = exact ? exact : chunk_of(r, C_POSITION, frame)))
        rc = read_numbers(r, e, n, 3, &s->x);
    else if (rc == HSBD_OK)
        rc = damaged(r, "the frame has no particles/position");
    s->exact = exact != NULL;
    if (rc == HSBD_OK && (e = chunk_of(r, C_ORIENTATION, frame)))
        rc = read_numbers(r, e, n, 4, &s->orientation);
    if (rc == HSBD_OK && !(s->typeid = calloc(n, sizeof *s->typeid)))
        rc = hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
    if (rc == HSBD_OK && !s->diameter && (s->diameter = malloc(n * sizeof *s->diameter)))
        for (size_t i = 0; i < n; ++i)
            s->diameter[i] = 1.0;
    if (rc == HSBD_OK && !s->diameter)
        rc = hsbd_error_set(r->err, HSBD_ENOMEM, "%s: out of memory", r->name);
    for (size_t i = 0; rc == HSBD_OK && i < n; ++i) {
        const double t = typeid ? typeid[i] : 0;
        if (!(t >= 0 && t < (double)s->ntypes)) {
            snprintf(why, sizeof why,
                     "particle %zu has typeid %g; allowed: 0 .. %zu (particles/types)", i, t,
                     s->ntypes - 1);
            rc = damaged(r, why);
        } else if (!(isfinite(s->diameter[i]) && s->diameter[i] >= 0)) {
            snprintf(why, sizeof why, "particle %zu has the diameter %g; allowed: >= 0", i,
                     s->diameter[i]);
            rc = damaged(r, why);
        } else if (!isfinite(s->x[3 * i] + s->x[3 * i + 1] + s->x[3 * i + 2])) {
            snprintf(why, sizeof why, "particle %zu has a position that is not finite", i);
            rc = damaged(r, why);
        }
        if (rc == HSBD_OK) s->typeid[i] = (uint32_t)t;
    }
    free(typeid);
    return rc;
}

int hsbd_gsd_read_stream(FILE *f, const char *name, int64_t frame, hsbd_gsd_snapshot *s,
                         hsbd_error *err) {
    *s = (hsbd_gsd_snapshot){0};
    hsbd_error_clear(err);
    reader *r = calloc(1, sizeof *r);
    if (!r) return hsbd_error_set(err, HSBD_ENOMEM, "%s: out of memory", name);
    *r = (reader){.f = f, .name = name, .err = err};
    unsigned char h[HEADER_BYTES] = {0};
    int rc = fseeko(f, 0, SEEK_END) == 0 && ftello(f) >= 0
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_EIO, "%s: cannot read: %s", name, strerror(errno));
    r->size = rc == HSBD_OK ? (uint64_t)ftello(f) : 0;
    if (rc == HSBD_OK && r->size >= 8)
        rc = read_at(r, 0, h, r->size < HEADER_BYTES ? 8 : HEADER_BYTES);
    if (rc == HSBD_OK && get_le(h, 8) != GSD_MAGIC)
        rc = damaged(r, "the file does not begin with GSD's magic number: not a GSD file");
    else if (rc == HSBD_OK && r->size < HEADER_BYTES)
        rc = damaged(r, "the file ends inside its 256-byte header (cut short?)");
    const uint32_t version = rc == HSBD_OK ? (uint32_t)get_le(h + 44, 4) : 0;
    if (rc == HSBD_OK && (version >> 16 < 1 || version >> 16 > 2)) {
        char why[96];
        snprintf(why, sizeof why, "GSD version %u.%u; allowed: 1.x or 2.x", version >> 16,
                 version & 0xffff);
        rc = damaged(r, why);
    }
    if (rc == HSBD_OK) rc = read_names(r, get_le(h + 24, 8), get_le(h + 32, 8), version >> 16 >= 2);
    uint64_t frames = 0;
    const uint64_t want = frame < 0 ? UINT64_MAX : (uint64_t)frame;
    if (rc == HSBD_OK) rc = scan_index(r, get_le(h + 8, 8), get_le(h + 16, 8), &frames, want);
    if (rc == HSBD_OK && frame < 0 && frames > 0) { /* the last frame: once more for it */
        r->nkept = 0;
        uint64_t again = 0;
        rc = scan_index(r, get_le(h + 8, 8), get_le(h + 16, 8), &again, frames - 1);
    }
    if (rc == HSBD_OK && frames == 0) rc = damaged(r, "the file holds no frame");
    if (rc == HSBD_OK && frame >= 0 && (uint64_t)frame >= frames)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "%s: init.frame = %lld is not a frame of the file; allowed: 0 .. "
                            "%llu, or -1 (the last)",
                            name, (long long)frame, (unsigned long long)(frames - 1));
    s->frames = frames;
    s->frame = frame < 0 ? frames - 1 : (uint64_t)frame;
    if (rc == HSBD_OK) rc = read_configuration(r, s->frame, s);
    if (rc == HSBD_OK) rc = read_particles(r, s->frame, s);
    free(r->kept);
    free(r);
    if (rc != HSBD_OK) hsbd_gsd_snapshot_free(s);
    return rc;
}

int hsbd_gsd_read(const char *path, int64_t frame, hsbd_gsd_snapshot *s, hsbd_error *err) {
    FILE *f = fopen(path, "rb");
    if (!f) {
        *s = (hsbd_gsd_snapshot){0};
        return hsbd_error_set(err, HSBD_EINPUT, "cannot read init.positions file '%s': %s", path,
                              strerror(errno));
    }
    const int rc = hsbd_gsd_read_stream(f, path, frame, s, err);
    fclose(f);
    return rc;
}

void hsbd_gsd_snapshot_free(hsbd_gsd_snapshot *s) {
    free(s->types), free(s->typeid), free(s->diameter), free(s->x), free(s->orientation);
    *s = (hsbd_gsd_snapshot){0};
}

int hsbd_gsd_file(const char *path) {
    FILE *f = fopen(path, "rb");
    unsigned char magic[8];
    const int is = f && fread(magic, 1, 8, f) == 8 && get_le(magic, 8) == GSD_MAGIC;
    if (f) fclose(f);
    const size_t len = strlen(path);
    return is || (len > 4 && !strcmp(path + len - 4, ".gsd"));
}

/* ---- init.positions ---------------------------------------------------------------------- */

int hsbd_gsd_read_positions(const hsbd_config *cfg, double *x, int *species, hsbd_error *err) {
    hsbd_gsd_snapshot s;
    const char *path = cfg->init.positions;
    if (hsbd_gsd_read(path, cfg->init.frame, &s, err) != HSBD_OK) return err->status;
    const int rods = cfg->system.model == HSBD_MODEL_RODS;
    const int dim = rods ? 1 : (int)cfg->system.dimension;
    const double *box = rods ? &cfg->system.length : cfg->system.box;
    int rc = s.n == (size_t)cfg->system.n
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: frame %llu has %zu particles, system.N = "
                                  "%lld (the file changed?)",
                                  path, (unsigned long long)s.frame, s.n, (long long)cfg->system.n);
    for (size_t i = 0; rc == HSBD_OK && i < s.n; ++i) {
        for (int a = 0; a < 3; ++a) { /* from the centred box into [0, L) */
            const double v = s.x[3 * i + a];
            if (a >= dim && v != 0) {
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "%s: frame %llu: particle %zu has %c = %.9g; allowed: %c = 0 "
                                    "(%s)",
                                    path, (unsigned long long)s.frame, i, "xyz"[a], v, "xyz"[a],
                                    rods ? "rods lie on the x axis" : "a 2D frame");
                break;
            }
            const int periodic = rods ? cfg->system.boundary != HSBD_BOUNDARY_WALLS
                                      : a < dim && !cfg->system.walls[a];
            double u = a < dim ? v + 0.5 * box[a] : 0.0;
            if (periodic) u -= box[a] * floor(u / box[a]);
            if (rods && a == 0) x[i] = u;
            if (!rods) x[3 * i + a] = u;
        }
        int k = 0; /* the species: the type's place in species.names */
        for (size_t q = 0; q < cfg->species.n; ++q)
            if (!strcmp(cfg->species.name[q], s.types[s.typeid[i]])) k = (int)q;
        if (species) species[i] = k;
    }
    hsbd_gsd_snapshot_free(&s); /* its orientations: hsbd_gsd_read_orientations */
    return rc;
}

int hsbd_gsd_read_orientations(const hsbd_config *cfg, double *e, int *found, hsbd_error *err) {
    hsbd_gsd_snapshot s;
    const char *path = cfg->init.positions;
    *found = 0;
    if (hsbd_gsd_read(path, cfg->init.frame, &s, err) != HSBD_OK) return err->status;
    int rc = HSBD_OK;
    for (size_t i = 0; s.orientation && i < s.n && i < (size_t)cfg->system.n; ++i) {
        double *ei = e + 3 * i; /* e = q (1, 0, 0) q*, q = (w, x, y, z) as HOOMD stores it */
        int ok = hsbd_orientation_of_quaternion(s.orientation + 4 * i, ei);
        if (ok && cfg->system.dimension == 2) { /* disks turn in the plane */
            const double norm = hypot(ei[0], ei[1]);
            ok = norm > 1e-6;
            if (ok) ei[0] /= norm, ei[1] /= norm, ei[2] = 0;
        }
        if (!ok) {
            rc =
                hsbd_error_set(err, HSBD_EINPUT,
                               "%s: frame %llu: particle %zu's particles/orientation is not a "
                               "rotation%s",
                               path, (unsigned long long)s.frame, i,
                               cfg->system.dimension == 2 ? " about z (system.dimension = 2)" : "");
            break;
        }
    }
    *found = rc == HSBD_OK && s.orientation != NULL;
    hsbd_gsd_snapshot_free(&s);
    return rc;
}
