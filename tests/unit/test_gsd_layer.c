/* The GSD writer's resume: a file cut back to its length at some moment and continued
 * with the layout it had then (what hsbd resume does with a checkpoint) must hold exactly
 * the bytes it had at that moment, also when the index moved (and the header changed)
 * after it, and continuing must then give the bytes of a file never cut; the moment is
 * taken with room for two frames in the index and with the index exactly full. Also: the
 * layout of a new file (header fields, index at 256 holding 128 entries, the name list),
 * entries sorted by frame, and the index moving twice as large when full. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../test_util.h"
#include "hsbd/io.h"

enum { N = 5 };

static void frame(hsbd_gsd *g, uint64_t k) {
    double x[3 * N], sigma[N] = {1, 1, 1.2, 1.2, 1};
    int64_t image[3 * N] = {0};
    int species[N] = {0, 0, 1, 1, 0};
    for (int i = 0; i < 3 * N; ++i)
        x[i] = 0.37 * (double)((i * 7 + (int)k * 3) % 20);
    image[0] = (int64_t)k;
    const char names[2][HSBD_SPECIES_NAME] = {"A", "B"};
    const hsbd_frame fr = {.n = N,
                           .dimension = 3,
                           .box = {8, 8, 8},
                           .periodic = {1, 1, 1},
                           .x = x,
                           .image = image,
                           .diameter = sigma,
                           .species = species,
                           .nspecies = 2,
                           .names = names,
                           .one_name = "S",
                           .time = 0.01 * (double)k,
                           .step = 10 * k};
    hsbd_error err;
    CHECK(hsbd_gsd_write(g, &fr, &err) == HSBD_OK, "%s", err.message);
}

static unsigned char *contents(FILE *f, long *len) {
    fflush(f);
    fseek(f, 0, SEEK_END);
    *len = ftell(f);
    unsigned char *b = malloc((size_t)*len);
    fseek(f, 0, SEEK_SET);
    if (b && fread(b, 1, (size_t)*len, f) != (size_t)*len) *len = -1;
    fseek(f, 0, SEEK_END);
    return b;
}

static uint64_t le(const unsigned char *p, int bytes) {
    uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; --k)
        v = v << 8 | p[k];
    return v;
}

/* Writes frames to a file never cut and to one cut back to the moment its index had room
 * for `room` more entries, and continued from there; both must end with the same bytes. */
static void cut_and_continue(uint64_t room) {
    hsbd_error err;
    FILE *ref = tmpfile(), *cut = tmpfile();
    hsbd_gsd gr, gc;
    CHECK(ref && cut, "tmpfile");
    if (!ref || !cut) {
        if (ref) fclose(ref);
        if (cut) fclose(cut);
        return;
    }
    CHECK(hsbd_gsd_start(&gr, ref, "ref", &err) == HSBD_OK, "%s", err.message);
    CHECK(hsbd_gsd_start(&gc, cut, "cut", &err) == HSBD_OK, "%s", err.message);
    /* frames until the index has room for exactly `room` more entries: the moment of the
     * "checkpoint" (the first frame writes 11 entries, later ones 7: the index of 128
     * entries has room for 19 after 15 frames and is never full, the moved one of 256 is
     * full after 36) */
    uint64_t k = 0;
    while (gc.entries + room != gc.index_capacity && k < 100)
        frame(&gr, k), frame(&gc, k), ++k;
    CHECK(gc.entries + room == gc.index_capacity, "%llu entries at the checkpoint",
          (unsigned long long)gc.entries);
    const hsbd_gsd saved = gc;
    long len_saved;
    unsigned char *at_checkpoint = contents(cut, &len_saved);
    /* then frames whose entries fill the index in place, and more that move it (the header
     * rewritten) */
    const uint64_t moved_at = k;
    while (gc.index_capacity == saved.index_capacity || k < moved_at + 3)
        frame(&gc, k), ++k;
    CHECK(gc.index_capacity == 2 * saved.index_capacity && gc.index_location > 256,
          "the index moved: %llu entries at %llu", (unsigned long long)gc.index_capacity,
          (unsigned long long)gc.index_location);
    /* cut back and continue with the layout of the checkpoint */
    CHECK(ftruncate(fileno(cut), len_saved) == 0, "ftruncate");
    hsbd_gsd_free(&gc);
    gc = saved;
    gc.buf = NULL, gc.buf_size = 0;
    CHECK(hsbd_gsd_continue(&gc, cut, "cut", len_saved, &err) == HSBD_OK, "%s", err.message);
    long len_back;
    unsigned char *back = contents(cut, &len_back);
    CHECK(len_back == len_saved && !memcmp(back, at_checkpoint, (size_t)len_saved),
          "the cut file holds the bytes of the checkpoint's moment");
    free(back);
    free(at_checkpoint);
    /* continued to the end: the bytes of the file never cut */
    for (uint64_t j = moved_at; j < moved_at + 40; ++j)
        frame(&gr, j), frame(&gc, j);
    long lr, lc;
    unsigned char *br = contents(ref, &lr), *bc = contents(cut, &lc);
    CHECK(lr == lc && lr > 0 && !memcmp(br, bc, (size_t)lr), "continued = never cut (%ld, %ld)", lr,
          lc);
    /* every entry sorted by frame, the last frame's number = frames - 1 */
    const uint64_t at = le(br + 8, 8), cap = le(br + 16, 8);
    uint64_t last = 0, used = 0;
    for (uint64_t e = 0; e < cap && le(br + at + 32 * e + 16, 8) != 0; ++e, ++used) {
        const uint64_t fr = le(br + at + 32 * e, 8);
        CHECK(fr >= last, "entry %llu out of order", (unsigned long long)e);
        last = fr;
    }
    CHECK(used == gr.entries && last + 1 == gr.frames, "%llu entries, last frame %llu",
          (unsigned long long)used, (unsigned long long)last);
    free(br);
    free(bc);
    hsbd_gsd_free(&gr);
    hsbd_gsd_free(&gc);
    fclose(ref);
    fclose(cut);
}

int main(void) {
    hsbd_error err;
    FILE *f = tmpfile();
    hsbd_gsd g;
    CHECK(f != NULL, "tmpfile");
    if (!f) return test_finish("test_gsd_layer");
    CHECK(hsbd_gsd_start(&g, f, "new", &err) == HSBD_OK, "%s", err.message);
    long len0;
    unsigned char *empty = contents(f, &len0);
    CHECK(len0 == 256 + 128 * 32 + 16 * 64, "a new file has %ld bytes", len0);
    CHECK(le(empty, 8) == 0x65DF65DF65DF65DFull && le(empty + 8, 8) == 256 &&
              le(empty + 16, 8) == 128 && le(empty + 24, 8) == 256 + 128 * 32 &&
              le(empty + 32, 8) == 16 && le(empty + 40, 4) == (1u << 16 | 4u) &&
              le(empty + 44, 4) == 2u << 16 && !memcmp(empty + 112, "hoomd", 6),
          "header fields");
    CHECK(!memcmp(empty + 256 + 128 * 32, "configuration/step", 19), "the name list");
    free(empty);
    hsbd_gsd_free(&g);
    fclose(f);
    /* in the first index (128 entries: 11 + 7 k never fill it), and in the moved one with
     * room for two frames and with none */
    cut_and_continue(19);
    cut_and_continue(14);
    cut_and_continue(0);
    return test_finish("test_gsd_layer");
}
