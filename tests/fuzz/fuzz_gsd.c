/* Fuzz target: a GSD file read back as an initial state (init.positions). The first byte
 * of the input picks the frame (0: the last, k: frame k - 1); the rest is the file. A
 * frame read must hold what the reader promises: N >= 1 particles, typeids below the
 * number of types, finite positions, diameters >= 0, a box of lengths > 0. (The numbers of
 * any type are read as doubles: a value beyond an integer's range is refused, not cast.) */
#include "fuzz.h"

#include <math.h>

#include "hsbd/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size == 0) return 0;
    FILE *in = fuzz_stream(data + 1, size - 1);
    if (!in) abort();
    hsbd_gsd_snapshot s;
    hsbd_error err;
    if (hsbd_gsd_read_stream(in, "fuzz.gsd", (int64_t)data[0] - 1, &s, &err) != HSBD_OK) {
        fuzz_expect_refusal(&err, "fuzz.gsd");
    } else {
        int ok = s.n >= 1 && s.ntypes >= 1 && s.frame < s.frames && s.box[0] > 0 && s.box[1] > 0 &&
                 (s.dimension == 2 || (s.dimension == 3 && s.box[2] > 0));
        for (size_t i = 0; ok && i < s.n; ++i)
            ok = s.typeid[i] < s.ntypes && s.diameter[i] >= 0 &&
                 isfinite(s.x[3 * i] + s.x[3 * i + 1] + s.x[3 * i + 2]);
        if (!ok) {
            fprintf(stderr, "fuzz: a frame read breaks the reader's promises\n");
            abort();
        }
        hsbd_gsd_snapshot_free(&s);
    }
    fclose(in);
    return 0;
}
