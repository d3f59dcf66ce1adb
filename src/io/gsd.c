/* GSD trajectories: the GSD 2.0 file layer (a 256-byte header, an index of 32-byte
 * entries, a name list, data chunks) with the chunks of the HOOMD schema 1.4, written
 * from the published specification. Layout of a new file: header at 0, an index of 128
 * entries at 256, a name list of 1024 bytes, then the frames' data chunks. A frame appends
 * its chunks, then writes its index entries in place (sorted by frame, then by name id);
 * a full index moves, twice as large, to the end of the file and the header is rewritten.
 * A reader sees only frames whose index entries are written, so a file cut short by
 * kill -9 holds every complete frame. Everything is little-endian. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/io.h"
#include "hsbd_version.h"
#include "io/orientation.h"

enum {
    GSD_HEADER_BYTES = 256,
    GSD_ENTRY_BYTES = 32,
    GSD_INITIAL_ENTRIES = 128,
    GSD_NAMELIST_ENTRIES = 16, /* of 64 bytes */
    GSD_NAME_BYTES = 64,
};
#define GSD_MAGIC            0x65DF65DF65DF65DFull
#define GSD_VERSION          ((2u << 16) | 0u)
#define HOOMD_SCHEMA_VERSION ((1u << 16) | 4u)

/* GSD element types */
enum {
    GSD_UINT8 = 1,
    GSD_UINT32 = 3,
    GSD_UINT64 = 4,
    GSD_INT8 = 5,
    GSD_INT32 = 7,
    GSD_FLOAT = 9,
    GSD_DOUBLE = 10
};

/* The name list: a chunk's id is its position here, and a frame writes its chunks in
 * this order. */
enum {
    ID_STEP,
    ID_DIMENSIONS,
    ID_BOX,
    ID_N,
    ID_TYPES,
    ID_TYPEID,
    ID_DIAMETER,
    ID_POSITION,
    ID_IMAGE,
    ID_TIME,
    ID_POSITION_DOUBLE,
    ID_ORIENTATION,
    ID_COUNT
};
static const char *const chunk_name[ID_COUNT] = {
    "configuration/step", "configuration/dimensions", "configuration/box",
    "particles/N",        "particles/types",          "particles/typeid",
    "particles/diameter", "particles/position",       "particles/image",
    "log/hsbd/time",      "log/hsbd/position",        "particles/orientation"};

/* One frame in the writer's terms: positions centred at the origin. */
typedef struct gsd_frame {
    uint64_t step;
    double time;
    int dimension;
    double box[3]; /* Lx Ly Lz (Lz = 0 in 2D) */
    size_t n, ntypes;
    const char (*types)[HSBD_SPECIES_NAME];
    const char *one_type;      /* ntypes == 0: every particle has this type */
    const double *x;           /* 3 n, centred */
    const int32_t *image;      /* 3 n */
    const int *typeid;         /* n, or NULL (all 0) */
    const double *diameter;    /* n */
    const double *orientation; /* 3 n unit vectors (active particles), or NULL */
} gsd_frame;

static void put_le(unsigned char *p, uint64_t v, int bytes) {
    for (int k = 0; k < bytes; ++k)
        p[k] = (unsigned char)(v >> (8 * k));
}

static uint32_t float_bits(double v) {
    const float f = (float)v;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static uint64_t double_bits(double v) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

static int write_at(hsbd_gsd *g, uint64_t at, const void *p, size_t n) {
    if (fseeko(g->f, (off_t)at, SEEK_SET) != 0) return -1;
    return n && fwrite(p, 1, n, g->f) != n ? -1 : 0;
}

static int write_header(hsbd_gsd *g) {
    unsigned char h[GSD_HEADER_BYTES] = {0};
    put_le(h, GSD_MAGIC, 8);
    put_le(h + 8, g->index_location, 8);
    put_le(h + 16, g->index_capacity, 8);
    put_le(h + 24, GSD_HEADER_BYTES + GSD_INITIAL_ENTRIES * GSD_ENTRY_BYTES, 8);
    put_le(h + 32, GSD_NAMELIST_ENTRIES, 8);
    put_le(h + 40, HOOMD_SCHEMA_VERSION, 4);
    put_le(h + 44, GSD_VERSION, 4);
    snprintf((char *)h + 48, 64, "hsbd %s", HSBD_VERSION_STRING);
    memcpy(h + 112, "hoomd", 5);
    return write_at(g, 0, h, sizeof h);
}

static size_t max_size(size_t a, size_t b) {
    return a > b ? a : b;
}

static int reserve(hsbd_gsd *g, size_t bytes) {
    if (bytes <= g->buf_size) return 0;
    unsigned char *b = realloc(g->buf, bytes);
    if (!b) return -1;
    g->buf = b;
    g->buf_size = bytes;
    return 0;
}

static int fail(const hsbd_gsd *g, hsbd_error *err, const char *what) {
    return hsbd_error_set(err, HSBD_EIO, "%s failed in '%s': %s", what, g->name, strerror(errno));
}

int hsbd_gsd_start(hsbd_gsd *g, FILE *f, const char *name, hsbd_error *err) {
    *g = (hsbd_gsd){.f = f,
                    .name = name,
                    .index_location = GSD_HEADER_BYTES,
                    .index_capacity = GSD_INITIAL_ENTRIES};
    const size_t names = GSD_NAMELIST_ENTRIES * GSD_NAME_BYTES;
    const size_t index = GSD_INITIAL_ENTRIES * GSD_ENTRY_BYTES;
    if (reserve(g, index + names) != 0)
        return hsbd_error_set(err, HSBD_ENOMEM, "GSD trajectory: out of memory");
    memset(g->buf, 0, index + names);
    for (size_t k = 0, at = index; k < ID_COUNT; ++k) {
        memcpy(g->buf + at, chunk_name[k], strlen(chunk_name[k]));
        at += strlen(chunk_name[k]) + 1;
    }
    if (write_header(g) != 0 || write_at(g, GSD_HEADER_BYTES, g->buf, index + names) != 0)
        return fail(g, err, "writing the header");
    g->end = GSD_HEADER_BYTES + index + names;
    return HSBD_OK;
}

int hsbd_gsd_continue(hsbd_gsd *g, FILE *f, const char *name, int64_t length, hsbd_error *err) {
    g->f = f;
    g->name = name;
    g->end = (uint64_t)length;
    const uint64_t block_end = g->index_location + g->index_capacity * GSD_ENTRY_BYTES;
    if (g->entries > g->index_capacity || block_end > g->end || g->end < GSD_HEADER_BYTES)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': its index lies beyond the %lld bytes the "
                              "checkpoint counts",
                              name, (long long)length);
    /* what was written after the checkpoint in place: the header (a moved index) and the
     * entries after the checkpoint's */
    const size_t unused = (size_t)(g->index_capacity - g->entries) * GSD_ENTRY_BYTES;
    if (reserve(g, unused) != 0)
        return hsbd_error_set(err, HSBD_ENOMEM, "GSD trajectory: out of memory");
    if (unused) memset(g->buf, 0, unused); /* none when the index was full (buf may be NULL) */
    if (write_header(g) != 0 ||
        write_at(g, g->index_location + g->entries * GSD_ENTRY_BYTES, g->buf, unused) != 0 ||
        fseeko(f, 0, SEEK_END) != 0)
        return fail(g, err, "restoring the index");
    return HSBD_OK;
}

void hsbd_gsd_free(hsbd_gsd *g) {
    free(g->buf);
    g->buf = NULL;
    g->buf_size = 0;
}

/* ---- frames ---- */

typedef struct chunk_list {
    unsigned char entries[ID_COUNT * GSD_ENTRY_BYTES];
    size_t count;
} chunk_list;

/* Appends one chunk of n x m elements of `type` (its bytes in g->buf) and notes its entry. */
static int append_chunk(hsbd_gsd *g, chunk_list *c, int id, uint64_t n, uint32_t m, int type,
                        size_t elem) {
    const size_t bytes = (size_t)n * m * elem;
    if (write_at(g, g->end, g->buf, bytes) != 0) return -1;
    unsigned char *e = c->entries + c->count++ * GSD_ENTRY_BYTES;
    put_le(e, g->frames, 8);
    put_le(e + 8, n, 8);
    put_le(e + 16, g->end, 8);
    put_le(e + 24, m, 4);
    put_le(e + 28, (uint64_t)id, 2);
    e[30] = (unsigned char)type;
    e[31] = 0;
    g->end += bytes;
    return 0;
}

/* The index has room for `more` entries: else it moves, doubled, to the end of the file. */
static int index_room(hsbd_gsd *g, size_t more) {
    if (g->entries + more <= g->index_capacity) return 0;
    uint64_t capacity = g->index_capacity;
    while (g->entries + more > capacity)
        capacity *= 2;
    const size_t old = (size_t)g->entries * GSD_ENTRY_BYTES;
    const size_t bytes = (size_t)capacity * GSD_ENTRY_BYTES;
    if (reserve(g, bytes) != 0) return -2;
    if (fseeko(g->f, (off_t)g->index_location, SEEK_SET) != 0 ||
        (old && fread(g->buf, 1, old, g->f) != old))
        return -1;
    memset(g->buf + old, 0, bytes - old);
    if (write_at(g, g->end, g->buf, bytes) != 0) return -1;
    g->index_location = g->end;
    g->index_capacity = capacity;
    g->end += bytes;
    return write_header(g);
}

static int frame_chunks(hsbd_gsd *g, const gsd_frame *fr, chunk_list *c) {
    const size_t n = fr->n;
    const int first = g->frames == 0;
    put_le(g->buf, fr->step, 8);
    if (append_chunk(g, c, ID_STEP, 1, 1, GSD_UINT64, 8)) return -1;
    if (first) {
        g->buf[0] = (unsigned char)fr->dimension;
        if (append_chunk(g, c, ID_DIMENSIONS, 1, 1, GSD_UINT8, 1)) return -1;
    }
    for (int k = 0; k < 6; ++k)
        put_le(g->buf + 4 * k, float_bits(k < 3 ? fr->box[k] : 0.0), 4);
    if (append_chunk(g, c, ID_BOX, 6, 1, GSD_FLOAT, 4)) return -1;
    put_le(g->buf, n, 4);
    if (append_chunk(g, c, ID_N, 1, 1, GSD_UINT32, 4)) return -1;
    if (first) {
        const size_t nt = fr->ntypes ? fr->ntypes : 1;
        size_t width = 1;
        for (size_t t = 0; t < nt; ++t)
            width = max_size(width, strlen(fr->ntypes ? fr->types[t] : fr->one_type) + 1);
        memset(g->buf, 0, nt * width);
        for (size_t t = 0; t < nt; ++t) {
            const char *name = fr->ntypes ? fr->types[t] : fr->one_type;
            memcpy(g->buf + t * width, name, strlen(name));
        }
        if (append_chunk(g, c, ID_TYPES, nt, (uint32_t)width, GSD_INT8, 1)) return -1;
        for (size_t i = 0; i < n; ++i)
            put_le(g->buf + 4 * i, fr->typeid ? (uint64_t)fr->typeid[i] : 0, 4);
        if (append_chunk(g, c, ID_TYPEID, n, 1, GSD_UINT32, 4)) return -1;
        for (size_t i = 0; i < n; ++i)
            put_le(g->buf + 4 * i, float_bits(fr->diameter[i]), 4);
        if (append_chunk(g, c, ID_DIAMETER, n, 1, GSD_FLOAT, 4)) return -1;
    }
    for (size_t i = 0; i < 3 * n; ++i)
        put_le(g->buf + 4 * i, float_bits(fr->x[i]), 4);
    if (append_chunk(g, c, ID_POSITION, n, 3, GSD_FLOAT, 4)) return -1;
    for (size_t i = 0; i < 3 * n; ++i)
        put_le(g->buf + 4 * i, (uint32_t)fr->image[i], 4);
    if (append_chunk(g, c, ID_IMAGE, n, 3, GSD_INT32, 4)) return -1;
    put_le(g->buf, double_bits(fr->time), 8);
    if (append_chunk(g, c, ID_TIME, 1, 1, GSD_DOUBLE, 8)) return -1;
    for (size_t i = 0; i < 3 * n; ++i)
        put_le(g->buf + 8 * i, double_bits(fr->x[i]), 8);
    if (append_chunk(g, c, ID_POSITION_DOUBLE, n, 3, GSD_DOUBLE, 8)) return -1;
    if (!fr->orientation) return 0;
    for (size_t i = 0; i < n; ++i) { /* quaternions (w, x, y, z) taking the body's x to e */
        double q[4];
        hsbd_orientation_quaternion(fr->orientation + 3 * i, q);
        for (int k = 0; k < 4; ++k)
            put_le(g->buf + 16 * i + 4 * k, float_bits(q[k]), 4);
    }
    return append_chunk(g, c, ID_ORIENTATION, n, 4, GSD_FLOAT, 4);
}

static int write_frame(hsbd_gsd *g, const gsd_frame *fr, hsbd_error *err) {
    const size_t width = HSBD_SPECIES_NAME * (fr->ntypes ? fr->ntypes : 1);
    if (reserve(g, max_size(24 * fr->n, width)) != 0)
        return hsbd_error_set(err, HSBD_ENOMEM, "GSD trajectory: out of memory for N = %zu", fr->n);
    chunk_list c = {.count = 0};
    if (frame_chunks(g, fr, &c) != 0) return fail(g, err, "writing a frame");
    const int room = index_room(g, c.count);
    if (room == -2) return hsbd_error_set(err, HSBD_ENOMEM, "GSD trajectory: out of memory");
    if (room != 0 ||
        write_at(g, g->index_location + g->entries * GSD_ENTRY_BYTES, c.entries,
                 c.count * GSD_ENTRY_BYTES) != 0 ||
        fseeko(g->f, 0, SEEK_END) != 0)
        return fail(g, err, "writing the index");
    g->entries += c.count;
    g->frames += 1;
    return HSBD_OK;
}

/* ---- frames ---- */

int hsbd_gsd_write(hsbd_gsd *g, const hsbd_frame *f, hsbd_error *err) {
    double *x = malloc(3 * f->n * sizeof *x);
    int32_t *image = malloc(3 * f->n * sizeof *image);
    if (!x || !image) {
        free(x), free(image);
        return hsbd_error_set(err, HSBD_ENOMEM, "GSD trajectory: out of memory for N = %zu", f->n);
    }
    const int rods = f->dimension == 1;
    for (size_t i = 0; i < f->n; ++i)
        for (int a = 0; a < 3; ++a) { /* centred at the origin */
            const int used = a < f->dimension;
            x[3 * i + a] = used ? f->x[3 * i + a] - 0.5 * f->box[a] : 0.0;
            image[3 * i + a] = used ? (int32_t)f->image[3 * i + a] : 0;
        }
    const gsd_frame fr = {.step = f->step,
                          .time = f->time,
                          .dimension = rods ? 2 : f->dimension,
                          .box = {f->box[0], rods ? HSBD_GSD_RODS_HEIGHT : f->box[1],
                                  f->dimension == 3 ? f->box[2] : 0.0},
                          .n = f->n,
                          .ntypes = f->names && f->species ? f->nspecies : 0,
                          .types = f->names,
                          .one_type = f->one_name,
                          .x = x,
                          .image = image,
                          .typeid = f->species,
                          .diameter = f->diameter,
                          .orientation = rods ? NULL : f->orientation};
    const int rc = write_frame(g, &fr, err);
    free(x), free(image);
    return rc;
}
