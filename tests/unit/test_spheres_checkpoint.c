/* An EDBD engine saved after k steps and loaded into a fresh engine of the same
 * parameters continues bit for bit: after the remaining steps its positions, image
 * counters and statistics (the virial's bytes included) equal those of the engine that
 * was never stopped. Cases: spheres at phi 0.3 and 0.5 with the global calendar and group
 * by group (the groups' automatic pause included), a binary mixture with D = 0 obstacles,
 * 2D disks, polydisperse spheres with Stokes-Einstein D and a drift, a mixture in a cosine
 * field with per-species couplings (the exact pair rule's pushes); each saved once in
 * the middle (after spatial sorts, so the saved internal order is not the user's). Also:
 * every truncation of a saved state is refused without a crash, and a state of another
 * system (other sizes) is refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "core/serial.h"
#include "hsbd/spheres.h"
#include "spheres/checkpoint.h"

typedef struct ck_case {
    const char *name;
    hsbd_spheres_params par;
    int steps;
} ck_case;

static int same_state(const hsbd_spheres *a, const hsbd_spheres *b) {
    const hsbd_spheres_view va = hsbd_spheres_get_view(a), vb = hsbd_spheres_get_view(b);
    const hsbd_spheres_stats sa = hsbd_spheres_get_stats(a), sb = hsbd_spheres_get_stats(b);
    return va.step == vb.step && va.time == vb.time &&
           !memcmp(va.x, vb.x, 3 * va.n * sizeof *va.x) &&
           !memcmp(va.image, vb.image, 3 * va.n * sizeof *va.image) &&
           sa.collisions == sb.collisions && sa.shell_updates == sb.shell_updates &&
           sa.pair_corrections == sb.pair_corrections &&
           !memcmp(&sa.virial, &sb.virial, sizeof sa.virial);
}

static void run_case(const ck_case *c) {
    hsbd_error err;
    hsbd_spheres *a = hsbd_spheres_alloc(&c->par, &err), *b = hsbd_spheres_alloc(&c->par, &err);
    CHECK(a && b, "%s: alloc: %s", c->name, err.message);
    if (!a || !b) return;
    CHECK(hsbd_spheres_init_lattice(a, &err) == HSBD_OK, "%s: init: %s", c->name, err.message);
    hsbd_spheres_init_lattice(b, &err);
    const int half = c->steps / 2;
    for (int k = 0; k < c->steps; ++k)
        hsbd_spheres_step(a);
    for (int k = 0; k < half; ++k)
        hsbd_spheres_step(b);
    hsbd_writer w;
    hsbd_writer_init(&w);
    hsbd_spheres_save(b, &w);
    CHECK(!w.oom, "%s: save", c->name);
    hsbd_spheres_free(b);
    hsbd_spheres *resumed = hsbd_spheres_alloc(&c->par, &err);
    hsbd_reader r;
    hsbd_reader_init(&r, w.data, w.len);
    CHECK(hsbd_spheres_load(resumed, &r) == 0 && r.pos == w.len, "%s: load: %s", c->name, r.why);
    for (int k = half; k < c->steps; ++k)
        CHECK(hsbd_spheres_step(resumed) == HSBD_OK, "%s: step", c->name);
    CHECK(same_state(a, resumed), "%s: the resumed engine differs from the uninterrupted one",
          c->name);
    /* truncated states are refused, never read beyond their end */
    int refused = 1;
    for (size_t cut = 0; cut < w.len; cut += 1 + w.len / 97) {
        hsbd_spheres *t = hsbd_spheres_alloc(&c->par, &err);
        hsbd_reader_init(&r, w.data, cut);
        refused &= hsbd_spheres_load(t, &r) != 0;
        hsbd_spheres_free(t);
    }
    CHECK(refused, "%s: a truncated state was accepted", c->name);
    const uint64_t pushes = hsbd_spheres_get_stats(a).pair_corrections;
    CHECK(c->par.field ? pushes > 0 : pushes == 0, "%s: %llu pair pushes", c->name,
          (unsigned long long)pushes);
    printf("  %s: %d + %d steps, %zu bytes, %llu pair pushes: identical\n", c->name, half,
           c->steps - half, w.len, (unsigned long long)pushes);
    hsbd_writer_free(&w);
    hsbd_spheres_free(a);
    hsbd_spheres_free(resumed);
}

static double side(int dim, size_t n, double phi, double mean_volume) {
    return pow((double)n * mean_volume / phi, 1.0 / dim);
}

int main(void) {
    const double pi = 3.14159265358979323846, v3 = pi / 6;
    const double s3 = side(3, 1500, 0.3, v3), s5 = side(3, 1500, 0.45, v3);
    static const int species[600] = {0};
    static int mix[800];
    for (int i = 0; i < 800; ++i)
        mix[i] = i % 5 == 0 ? 2 : i % 2;
    const double mix_sigma[3] = {1.0, 1.3, 1.0}, mix_d[3] = {1.0, 0.8, 0.0};
    static double poly_sigma[1000], poly_d[1000];
    for (int i = 0; i < 1000; ++i)
        poly_sigma[i] = 0.85 + 0.3 * ((i * 7919) % 1000) / 1000.0, poly_d[i] = 1.0 / poly_sigma[i];
    (void)species;
    hsbd_field cosine = {0};
    hsbd_field_add(&cosine, hsbd_field_cosine(3, 4));
    const double mix_coupling[3] = {1.0, 2.0, 0.0};
    const ck_case cases[] = {
        {"phi0.3-global",
         {.n = 1500,
          .dimension = 3,
          .box = {s3, s3, s3},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 1e-3,
          .seed = 3,
          .hard_core = 1,
          .event_order = HSBD_EVENTS_GLOBAL},
         400},
        {"phi0.45-groups",
         {.n = 1500,
          .dimension = 3,
          .box = {s5, s5, s5},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 1e-3,
          .seed = 4,
          .hard_core = 1,
          .event_order = HSBD_EVENTS_GROUPS},
         300},
        {"phi0.45-auto-groups",
         {.n = 1500,
          .dimension = 3,
          .box = {s5, s5, s5},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 2e-3,
          .seed = 5,
          .hard_core = 1,
          .event_order = HSBD_EVENTS_AUTO,
          .groups_min_n = 1},
         300},
        {"mixture-obstacles",
         {.n = 800,
          .dimension = 3,
          .box = {12, 12, 12},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 1e-3,
          .seed = 6,
          .hard_core = 1,
          .nspecies = 3,
          .species = mix,
          .species_sigma = mix_sigma,
          .species_diffusion = mix_d},
         300},
        {"disks",
         {.n = 900,
          .dimension = 2,
          .box = {side(2, 900, 0.5, pi / 4), side(2, 900, 0.5, pi / 4)},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 1e-3,
          .seed = 7,
          .hard_core = 1},
         300},
        {"polydisperse-drift",
         {.n = 1000,
          .dimension = 3,
          .box = {15, 15, 15},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 1e-3,
          .seed = 8,
          .hard_core = 1,
          .drift = {0.5, 0, -0.3},
          .particle_sigma = poly_sigma,
          .particle_diffusion = poly_d},
         300},
        {"mixture-field-pair-rule",
         {.n = 800,
          .dimension = 3,
          .box = {12, 12, 12},
          .sigma = 1,
          .diffusion = 1,
          .kT = 1,
          .dt = 1e-3,
          .seed = 9,
          .hard_core = 1,
          .nspecies = 3,
          .species = mix,
          .species_sigma = mix_sigma,
          .species_diffusion = mix_d,
          .field = &cosine,
          .field_axis = 2,
          .species_coupling = mix_coupling},
         300},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k)
        run_case(&cases[k]);
    /* a state of another system: the sizes differ */
    hsbd_error err;
    hsbd_spheres_params p = cases[0].par, q = p;
    q.sigma = 0.9;
    hsbd_spheres *a = hsbd_spheres_alloc(&p, &err), *b = hsbd_spheres_alloc(&q, &err);
    hsbd_spheres_init_lattice(a, &err);
    hsbd_writer w;
    hsbd_writer_init(&w);
    hsbd_spheres_save(a, &w);
    hsbd_reader r;
    hsbd_reader_init(&r, w.data, w.len);
    CHECK(hsbd_spheres_load(b, &r) != 0 && strstr(r.why, "sizes"), "other sizes: %s", r.why);
    hsbd_writer_free(&w);
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
    return test_finish("test_spheres_checkpoint");
}
