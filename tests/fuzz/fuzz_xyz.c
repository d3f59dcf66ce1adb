/* Fuzz target: one extended-XYZ frame of spheres (init.positions), read against a small
 * box. The first byte of the input picks what the frame must match: bit 0 3D instead of
 * 2D, bit 1 two species with their counts, bit 2 a radius column; the rest is the file. */
#include "fuzz.h"

#include "hsbd/io.h"

enum { XYZ_N = 4 };

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size == 0) return 0;
    static const double box[3] = {5, 6, 7};
    static const char names[2][HSBD_SPECIES_NAME] = {"A", "B"};
    static const int64_t count[2] = {3, 1};
    const unsigned v = data[0];
    const hsbd_xyz_expect e = {.n = XYZ_N,
                               .dimension = v & 1 ? 3 : 2,
                               .box = box,
                               .nspecies = v & 2 ? 2 : 0,
                               .names = v & 2 ? names : NULL,
                               .count = v & 2 ? count : NULL,
                               .radius_reason = v & 4 ? "polydisperse" : NULL};
    FILE *in = fuzz_stream(data + 1, size - 1);
    if (!in) abort();
    double x[3 * XYZ_N], radius[XYZ_N];
    int species[XYZ_N];
    hsbd_error err;
    if (hsbd_xyz_read_spheres(in, "fuzz.xyz", &e, x, species, radius, &err) != HSBD_OK)
        fuzz_expect_refusal(&err, "fuzz.xyz");
    fclose(in);
    return 0;
}
