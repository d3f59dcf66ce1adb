/* hsbd_sim's accessors for callers (the Python module):
 * - hsbd_sim_alloc_from: a simulation started from the initial state of another (its
 *   positions, species, diameters) runs bit for bit as that one does (rods of a mixture
 *   between walls, polydisperse disks in a periodic box, spheres between walls); on a ring
 *   the rods are put in line order from the wrapped positions; positions that overlap,
 *   leave the walls, change a mixture's composition or give a diameter of 0 are refused
 *   with HSBD_EINPUT and a message that says so, and nothing else is built.
 * - the density profiles of spheres between walls (parts.slab): one along the walls axis
 *   only, holding every particle (the profile integrates to N over the slab's volume).
 * - hsbd_sim_summary: the text of summary.json so far, with "completed" once done and
 *   the observers' lines (walls, Z_virial, D_long). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/hsbd.h"

static hsbd_config config(const char *const *sets) {
    hsbd_config cfg;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    for (; *sets; ++sets)
        CHECK(hsbd_config_set(&cfg, *sets, "test", &err) == HSBD_OK, "%s: %s", *sets, err.message);
    CHECK(hsbd_config_finalize(&cfg, &err) == HSBD_OK, "%s", err.message);
    return cfg;
}

/* the positions (N x 3), species and diameters of a simulation, copied */
typedef struct state {
    size_t n;
    double *x, *sigma;
    int *species;
} state;

static state state_of(hsbd_sim *s) {
    const hsbd_sim_parts p = hsbd_sim_get_parts(s);
    const size_t n = (size_t)hsbd_sim_config(s)->system.n;
    state st = {n, calloc(3 * n, sizeof(double)), calloc(n, sizeof(double)),
                calloc(n, sizeof(int))};
    if (p.rods) {
        const hsbd_rods_view v = hsbd_rods_get_view(p.rods);
        for (size_t i = 0; i < n; ++i) {
            st.x[3 * i] = v.z[i] + v.offset[i] + v.unwrap;
            st.species[i] = v.species ? v.species[i] : 0;
            st.sigma[i] = v.species ? v.species_sigma[v.species[i]] : v.sigma;
        }
    } else {
        const hsbd_spheres_view v = hsbd_spheres_get_view(p.spheres);
        memcpy(st.x, v.x, 3 * n * sizeof *st.x);
        memcpy(st.sigma, v.sigma, n * sizeof *st.sigma);
        memcpy(st.species, v.species, n * sizeof *st.species);
    }
    return st;
}

static void state_free(state *st) {
    free(st->x), free(st->sigma), free(st->species);
}

static int same_state(const state *a, const state *b) {
    return a->n == b->n && !memcmp(a->x, b->x, 3 * a->n * sizeof *a->x) &&
           !memcmp(a->sigma, b->sigma, a->n * sizeof *a->sigma) &&
           !memcmp(a->species, b->species, a->n * sizeof *a->species);
}

/* A simulation and one started from its initial state: the same after `steps` steps. */
static void same_trajectory(const char *what, const char *const *sets, uint64_t steps) {
    const hsbd_config cfg = config(sets);
    hsbd_error err;
    hsbd_sim *a = hsbd_sim_alloc(&cfg, &err);
    CHECK(a, "%s: %s", what, err.message);
    if (!a) return;
    state start = state_of(a);
    hsbd_sim *b = hsbd_sim_alloc_from(&cfg, start.x, start.species, start.sigma, &err);
    CHECK(b, "%s: alloc_from: %s", what, err.message);
    if (b) {
        state b0 = state_of(b);
        CHECK(same_state(&start, &b0), "%s: the given initial state is the state (x0 %.17g %.17g)",
              what, start.x[0], b0.x[0]);
        state_free(&b0);
        CHECK(hsbd_sim_advance(a, steps, &err) == HSBD_OK, "%s", err.message);
        CHECK(hsbd_sim_advance(b, steps, &err) == HSBD_OK, "%s", err.message);
        state ea = state_of(a), eb = state_of(b);
        CHECK(same_state(&ea, &eb) && memcmp(ea.x, start.x, 3 * ea.n * sizeof *ea.x),
              "%s: %llu steps from the given state = from the configured one", what,
              (unsigned long long)steps);
        state_free(&ea), state_free(&eb);
    }
    hsbd_sim_free(a), hsbd_sim_free(b);
    state_free(&start);
}

static void refused(const char *what, const hsbd_config *cfg, const double *x, const int *species,
                    const double *sigma, const char *words) {
    hsbd_error err;
    hsbd_sim *s = hsbd_sim_alloc_from(cfg, x, species, sigma, &err);
    CHECK(!s && err.status == HSBD_EINPUT && strstr(err.message, words),
          "%s: refused with '%s' (got status %d, '%s')", what, words, err.status, err.message);
    hsbd_sim_free(s);
}

int main(void) {
    static const char *const rods[] = {"system.N=40",
                                       "system.L=60",
                                       "system.boundary=walls",
                                       "species.names=A,B",
                                       "species.count=25,15",
                                       "species.sigma=0.5,1",
                                       "species.D=1,0.5",
                                       "field.type=cosine",
                                       "field.amplitude=2",
                                       "run.dt=1e-3",
                                       "run.t_equil=0.1",
                                       "run.t_total=0.4",
                                       NULL};
    same_trajectory("rods mixture", rods, 300);
    static const char *const disks[] = {"system.model=spheres",
                                        "system.dimension=2",
                                        "system.N=150",
                                        "system.packing_fraction=0.4",
                                        "species.polydispersity=0.1",
                                        "run.dt=1e-3",
                                        "run.t_equil=0.05",
                                        "run.t_total=0.2",
                                        NULL};
    same_trajectory("polydisperse disks", disks, 150);
    static const char *const slit[] = {"system.model=spheres",
                                       "system.N=200",
                                       "system.box=8 8 9",
                                       "system.boundary=periodic periodic walls",
                                       "species.names=A,B",
                                       "species.fraction=0.5,0.5",
                                       "species.sigma=1,1.2",
                                       "species.D=1,0.8",
                                       "run.dt=1e-3",
                                       "run.t_equil=0.05",
                                       "run.t_total=0.3",
                                       "sample.blocks=4",
                                       NULL};
    same_trajectory("spheres between walls", slit, 150);

    /* a ring: the positions given, wrapped and in line order, species following */
    static const char *const ring[] = {"system.N=4",
                                       "system.L=10",
                                       "species.names=A,B",
                                       "species.count=3,1",
                                       "species.sigma=1,2",
                                       "species.D=1,1",
                                       NULL};
    const hsbd_config ringc = config(ring);
    const double xr[12] = {9.5, 0, 0, 3, 0, 0, -3, 0, 0, 10.8, 0, 0};
    const int sr[4] = {0, 1, 0, 0};
    hsbd_error err;
    hsbd_sim *r = hsbd_sim_alloc_from(&ringc, xr, sr, NULL, &err);
    CHECK(r, "%s", err.message);
    if (r) {
        state st = state_of(r);
        const double want[4] = {0.8, 3, 7, 9.5}; /* 9.5, 3, -3, 10.8 wrapped, sorted */
        const int want_species[4] = {0, 1, 0, 0};
        for (int i = 0; i < 4; ++i) {
            CHECK_CLOSE(st.x[3 * i] - 10 * floor(st.x[3 * i] / 10), want[i], 1e-12);
            CHECK(st.species[i] == want_species[i], "rod %d: species %d", i, st.species[i]);
        }
        state_free(&st);
        hsbd_sim_free(r);
    }

    /* refusals */
    const hsbd_config rc = config(rods), sc = config(slit);
    double x[3 * 200] = {0};
    int species[200] = {0};
    for (size_t i = 0; i < 40; ++i)
        x[3 * i] = 1.5 * (double)i, species[i] = i < 25 ? 0 : 1;
    for (size_t i = 0; i < 40; ++i)
        x[3 * i] += 1;
    x[3] = x[0] + 0.2;
    refused("rods overlap", &rc, x, species, NULL, "overlap");
    x[3] = 2.5;
    species[0] = 1;
    refused("rods: a species' count changed", &rc, x, species, NULL, "species.count");
    hsbd_sim *s = hsbd_sim_alloc(&sc, &err);
    CHECK(s, "%s", err.message);
    if (s) {
        state st = state_of(s);
        st.x[3 * 7 + 2] = 0.3; /* below sigma/2 from the wall at z = 0 */
        refused("spheres outside the walls", &sc, st.x, st.species, NULL, "outside the walls");
        st.x[3 * 7 + 2] = 4.5, st.species[0] = 1 - st.species[0];
        refused("spheres: a species' count changed", &sc, st.x, st.species, NULL, "counts");
        st.species[0] = 1 - st.species[0], st.sigma[3] = 0;
        refused("spheres: a diameter of 0", &sc, st.x, st.species, st.sigma, "diameter 0");
        state_free(&st);

        /* profiles along the walls axis only, every particle in them; the summary */
        CHECK(hsbd_sim_advance(s, 1000000, &err) == HSBD_OK, "%s", err.message);
        const hsbd_sim_parts p = hsbd_sim_get_parts(s);
        CHECK(!p.slab[0] && !p.slab[1] && p.slab[2], "a profile along z only");
        if (p.slab[2]) {
            const size_t nb = hsbd_slab_bins(p.slab[2]);
            double *z = malloc(3 * nb * sizeof *z), *rho = z + nb, *e = rho + nb, total = 0;
            hsbd_slab_density(p.slab[2], -1, z, rho, e);
            for (size_t k = 0; k < nb; ++k)
                total += rho[k] * 9.0 / (double)nb * 64.0;
            CHECK_CLOSE(total, 200, 1e-9);
            free(z);
        }
        char *json = NULL;
        CHECK(hsbd_sim_summary(s, &json, &err) == HSBD_OK && json, "%s", err.message);
        if (json) {
            CHECK(strstr(json, "\"completed\": true") && strstr(json, "\"walls\": [") &&
                      strstr(json, "\"D_long\"") && strstr(json, "\"parameters\""),
                  "summary: %.300s", json);
            CHECK(!strstr(json, "Z_virial"), "no virial pressure between walls");
        }
        free(json);
        hsbd_sim_free(s);
    }
    return test_finish("test_sim");
}
