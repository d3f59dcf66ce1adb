/* Fuzz target: init.positions of rods (one position per line, 'x name' for a mixture),
 * read against a small ring or box. The first byte of the input picks the system: bit 0
 * walls instead of a ring, bit 1 a mixture of two species, bit 2 no hard core; the rest is
 * the file. */
#include "fuzz.h"

#include "hsbd/io.h"

enum { VARIANTS = 8, RODS_N = 5 };

static const hsbd_config *variant(unsigned v) {
    static hsbd_config cfgs[VARIANTS];
    static int made[VARIANTS];
    if (!made[v]) {
        const char *sets[16];
        size_t n = 0;
        sets[n++] = "system.N=5";
        sets[n++] = "system.L=10";
        sets[n++] = "field.type=none";
        sets[n++] = "run.t_total=1";
        sets[n++] = "run.t_equil=0";
        sets[n++] = "run.dt=1e-2";
        sets[n++] = "sample.blocks=2";
        sets[n++] = "sample.bin_width=0.5";
        if (v & 1) sets[n++] = "system.boundary=walls";
        if (v & 2) {
            sets[n++] = "species.names=A B";
            sets[n++] = "species.count=3 2";
            sets[n++] = "species.sigma=0.5 1.5";
            sets[n++] = "species.D=1 2";
        } else {
            sets[n++] = "system.sigma=1.5";
        }
        if (v & 4) sets[n++] = "system.hard_core=off";
        fuzz_configure(&cfgs[v], sets, n);
        made[v] = 1;
    }
    return &cfgs[v];
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size == 0) return 0;
    const hsbd_config *cfg = variant(data[0] % VARIANTS);
    FILE *in = fuzz_stream(data + 1, size - 1);
    if (!in) abort();
    double x[RODS_N];
    int species[RODS_N];
    hsbd_error err;
    if (hsbd_read_positions_stream(in, "fuzz.pos", cfg, x, species, &err) != HSBD_OK)
        fuzz_expect_refusal(&err, "fuzz.pos");
    fclose(in);
    return 0;
}
