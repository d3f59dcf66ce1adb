/* The production BCD step (one ring isotonic regression) against the literal
 * event-by-event oracle, and the fragmentation against brute force over all 2^(n-1)
 * compositions (Antonov Eqs. 4-5). */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "../test_util.h"
#include "bcd_oracle.h"
#include "hsbd/config.h"
#include "hsbd/isotonic.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"
#include "core/serial.h"
#include "core/vmath.h"
#include "rods1d/checkpoint.h"
#include "rods1d/gaps.h"

enum { NMAX = 12 };

/* Deterministic test randomness from the library's counter-based streams. */
typedef struct {
    uint64_t seed, draw;
} test_rng;
static double uniform(test_rng *r) {
    double u;
    hsbd_rng_uniforms(r->seed, 99, r->draw++, 0, 1, &u);
    return u;
}
static double normal(test_rng *r) {
    double g;
    hsbd_rng_normals(r->seed, 98, r->draw++, 0, 1, &g);
    return g;
}

/* Eqs. (4)-(5) for the composition encoded by `cuts` (bit c: cut between c and c+1). */
static int composition_is_valid(size_t n, const double *v, const double *fric, unsigned cuts) {
    size_t a = 0;
    double prev_mean = -INFINITY;
    for (size_t c = 0; c < n; ++c) {
        if (c + 1 < n && !(cuts >> c & 1u)) continue;
        const size_t b = c + 1; /* subcluster [a, b) */
        double num = 0, den = 0;
        for (size_t k = a; k < b; ++k)
            num += fric[k] * v[k], den += fric[k];
        const double mean = num / den;
        if (!(prev_mean < mean)) return 0;   /* Eq. (4) */
        for (size_t i = a + 1; i < b; ++i) { /* Eq. (5): prefix mean >= rest mean */
            double n1 = 0, d1 = 0, n2 = 0, d2 = 0;
            for (size_t k = a; k < i; ++k)
                n1 += fric[k] * v[k], d1 += fric[k];
            for (size_t k = i; k < b; ++k)
                n2 += fric[k] * v[k], d2 += fric[k];
            if (!(n1 / d1 >= n2 / d2)) return 0;
        }
        prev_mean = mean;
        a = b;
    }
    return 1;
}

static void test_fragmentation_brute_force(void) {
    test_rng rng = {11, 0};
    hsbd_pava *p = hsbd_pava_alloc(NMAX);
    int mismatches = 0, not_unique = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const size_t n = 1 + (size_t)(uniform(&rng) * NMAX);
        double force[NMAX], mob[NMAX], v[NMAX], fric[NMAX], fit[NMAX];
        const int equal_mob = trial % 2 == 0;
        for (size_t i = 0; i < n; ++i) {
            force[i] = normal(&rng);
            mob[i] = equal_mob ? 1.0 : 0.5 + 1.5 * uniform(&rng);
            v[i] = mob[i] * force[i];
            fric[i] = 1.0 / mob[i];
        }
        unsigned found = 0, count = 0;
        for (unsigned cuts = 0; cuts < (1u << (n - 1)); ++cuts)
            if (composition_is_valid(n, v, fric, cuts)) found = cuts, ++count;
        not_unique += count != 1;
        /* PAVA blocks -> cut mask */
        const size_t nb = hsbd_pava_line(p, n, v, fric, fit);
        unsigned pava_cuts = 0;
        size_t pos = 0;
        for (size_t b = 0; b + 1 < nb; ++b)
            pos += hsbd_pava_block_size(p, b), pava_cuts |= 1u << (pos - 1);
        /* recursive largest-jump rule of the paper */
        size_t sizes[NMAX];
        const size_t parts = oracle_fragment(n, force, mob, sizes);
        unsigned oracle_cuts = 0;
        pos = 0;
        for (size_t b = 0; b + 1 < parts; ++b)
            pos += sizes[b], oracle_cuts |= 1u << (pos - 1);
        mismatches += pava_cuts != found || oracle_cuts != found;
    }
    CHECK(not_unique == 0, "%d force sets had no or several valid compositions", not_unique);
    CHECK(mismatches == 0, "%d force sets: PAVA or recursive split differ from brute force",
          mismatches);
    hsbd_pava_free(p);
}

/* Random ring: gaps exactly 0 with probability 0.4, else exponential, summing to L - n sigma. */
static void random_ring(test_rng *rng, size_t n, double sigma, double L, double *x) {
    double gaps[NMAX], sum = 0;
    for (size_t i = 0; i < n; ++i) {
        gaps[i] = uniform(rng) < 0.4 ? 0.0 : -log(uniform(rng));
        sum += gaps[i];
    }
    if (sum == 0) gaps[n - 1] = sum = 1.0;
    const double free_len = L - (double)n * sigma;
    x[0] = L * uniform(rng);
    for (size_t i = 1; i < n; ++i)
        x[i] = x[i - 1] + sigma + gaps[i - 1] * free_len / sum;
}

static void test_ring_step_vs_oracle(void) {
    test_rng rng = {7, 0};
    hsbd_pava *p = hsbd_pava_alloc(NMAX);
    const double dts[] = {1e-4, 1e-2, 1.0};
    const double sigmas[] = {0.0, 0.3, 1.0};
    double worst = 0;
    size_t total_merges = 0, whole_ring = 0, wrapped = 0;
    for (int trial = 0; trial < 6000; ++trial) {
        const size_t n = 1 + (size_t)(uniform(&rng) * NMAX);
        const double sigma = sigmas[trial % 3], dt = dts[(trial / 3) % 3];
        const double L = (double)n * sigma + 1.0 + 5.0 * uniform(&rng);
        const double free_len = L - (double)n * sigma;
        double x[NMAX], xo[NMAX], force[NMAX], mob[NMAX], fric[NMAX], y[NMAX], z[NMAX];
        random_ring(&rng, n, sigma, L, x);
        const double scale = free_len / (double)n / dt * (trial % 4 == 0 ? 20.0 : 1.0);
        const double bias = trial % 5 == 0 ? scale * normal(&rng) : 0.0; /* common drift */
        for (size_t i = 0; i < n; ++i) {
            mob[i] = trial % 2 ? 1.0 : 0.5 + 1.5 * uniform(&rng);
            fric[i] = 1.0 / mob[i];
            force[i] = bias + scale * normal(&rng);
            xo[i] = x[i];
            z[i] = x[i] - (double)i * sigma;      /* contact-offset coordinate */
            y[i] = z[i] + mob[i] * force[i] * dt; /* free end point */
        }
        total_merges += oracle_step(n, xo, force, mob, sigma, L, dt, 1e-12);
        const size_t nb = hsbd_pava_ring(p, n, y, fric, free_len, z);
        whole_ring += nb == 1 && n > 1;
        wrapped += n > 1 && nb > 1 && z[0] + free_len - z[n - 1] < 1e-12;
        for (size_t i = 0; i < n; ++i) {
            const double d = fabs(z[i] + (double)i * sigma - xo[i]);
            if (d > worst) worst = d;
        }
    }
    CHECK(worst <= 1e-12, "max |PAVA - oracle| = %.3g", worst);
    CHECK(total_merges > 1000, "only %zu merge events exercised", total_merges);
    CHECK(whole_ring > 10, "only %zu steps pooled the whole ring", whole_ring);
    CHECK(wrapped > 10, "only %zu steps had a cluster across the wrap", wrapped);
    printf("ring step vs oracle: max deviation %.3g over 6000 steps, %zu merges, "
           "%zu whole-ring and %zu wrapping clusters\n",
           worst, total_merges, whole_ring, wrapped);
    hsbd_pava_free(p);
}

/* The library step (noise from the seed, cosine + tilt field) equals the oracle fed
 * with the same total forces, Eq. (11), over many consecutive steps. */
static void test_library_step_vs_oracle(void) {
    const size_t n = 10;
    hsbd_rods_params par = {.n = n,
                            .length = 6.0,
                            .sigma = 0.5,
                            .diffusion = 1.3,
                            .kT = 0.7,
                            .dt = 1e-2,
                            .seed = 2024,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY};
    hsbd_field_add(&par.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_field_add(&par.field, hsbd_field_tilt(0.8));
    const double worst = oracle_library_deviation(&par, 400);
    CHECK(worst <= 1e-12, "library step vs oracle: max deviation %.3g", worst);
}

/* Fragments of the clusters touching at the start on a ring (gaps <= 1e-12 L close), each
 * split by the oracle's friction-weighted velocities: what the step statistics count. */
static size_t ring_fragments(size_t n, const double *x, const double *force, const double *mob,
                             const double *sig, double L) {
    double f[64], m[64];
    size_t sizes[64], first = 0, total = 0;
    const double tol = 1e-12 * L;
    for (size_t i = 0; i < n; ++i) { /* a rod whose left gap is open */
        const size_t l = (i + n - 1) % n;
        const double left = (x[i] - x[l] + (i == 0 ? L : 0.0)) - 0.5 * (sig[i] + sig[l]);
        if (left > tol) {
            first = i;
            break;
        }
    }
    for (size_t k = 0; k < n;) {
        size_t len = 0, i = (first + k) % n;
        for (;;) {
            f[len] = force[i], m[len++] = mob[i], ++k;
            const size_t r = (i + 1) % n;
            const double gap = (x[r] - x[i] + (r == 0 ? L : 0.0)) - 0.5 * (sig[i] + sig[r]);
            if (k == n || gap > tol) break;
            i = r;
        }
        total += oracle_fragment(len, f, m, sizes);
    }
    return total;
}

/* A binary mixture (lengths 0.3 and 0.7, D 1 and 2.5) on a ring and between walls: the
 * library step (friction-weighted regression, clamped to the walls) equals the literal
 * oracle with per-rod lengths and mobilities, walls as immovable clusters; on the ring the
 * fragmentation diagnostic counts the oracle's fragments (friction-weighted: unweighted it
 * missed some, found in 2026-12). */
static void test_mixture_step_vs_oracle(int boundary) {
    enum { N = 12 };
    const int species[N] = {0, 1, 1, 0, 0, 1, 0, 1, 1, 1, 0, 0};
    const double sp_sigma[2] = {0.3, 0.7}, sp_d[2] = {1.0, 2.5};
    hsbd_rods_params par = {.n = N,
                            .length = 7.0,
                            .sigma = 0.3,
                            .diffusion = 1.0,
                            .kT = 0.8,
                            .dt = 1e-2,
                            .seed = 77,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY,
                            .boundary = boundary,
                            .nspecies = 2,
                            .species = species,
                            .species_sigma = sp_sigma,
                            .species_diffusion = sp_d};
    hsbd_field_add(&par.field, hsbd_field_cosine(4.0, 1.0));
    hsbd_field_add(&par.field, hsbd_field_tilt(boundary == HSBD_RODS_WALLS ? -3.0 : 0.8));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    CHECK(rods != NULL, "alloc: %s", err.message);
    if (!rods) return;
    hsbd_rods_init_equilibrium(rods);
    double worst = 0, min_gap = 1;
    size_t merges = 0, wall_contacts = 0, fragment_mismatches = 0;
    for (int s = 0; s < 400; ++s) {
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        double x[N], force[N], g[N], mob[N], sig[N];
        hsbd_rng_normals(par.seed, HSBD_STREAM_NOISE, v.step, 0, N, g);
        for (size_t i = 0; i < N; ++i) {
            x[i] = v.z[i] + v.offset[i];
            mob[i] = v.species_mobility[v.species[i]];
            sig[i] = v.species_sigma[v.species[i]];
        }
        hsbd_field_force(&par.field, N, x, force);
        for (size_t i = 0; i < N; ++i)
            force[i] += sqrt(2 * mob[i] * par.kT / par.dt) / mob[i] * g[i];
        const double shift = v.unwrap;
        const size_t expected =
            boundary == HSBD_RODS_PERIODIC ? ring_fragments(N, x, force, mob, sig, par.length) : 0;
        merges += oracle_step_general(N, x, force, mob, sig, par.length, boundary, par.dt, 1e-12);
        hsbd_rods_step_stats st;
        CHECK(hsbd_rods_step(rods, &st) == HSBD_OK, "step");
        if (boundary == HSBD_RODS_PERIODIC) fragment_mismatches += st.fragments != expected;
        const hsbd_rods_view w = hsbd_rods_get_view(rods);
        for (size_t i = 0; i < N; ++i) {
            const double d = fabs((w.z[i] + w.offset[i] + w.unwrap) - (x[i] + shift));
            if (d > worst) worst = d;
        }
        wall_contacts += boundary == HSBD_RODS_WALLS && w.z[0] == 0.0;
        const double gmin = hsbd_rods_min_gap(rods, NULL);
        if (gmin < min_gap) min_gap = gmin;
    }
    CHECK(worst <= 1e-12, "mixture (boundary %d) vs oracle: max deviation %.3g", boundary, worst);
    CHECK(merges > 100, "only %zu merges exercised", merges);
    CHECK(fragment_mismatches == 0, "fragmentation diagnostic differs from the oracle in %zu steps",
          fragment_mismatches);
    CHECK(min_gap >= -1e-12, "overlap: min gap %.3g", min_gap);
    if (boundary == HSBD_RODS_WALLS)
        CHECK(wall_contacts > 50, "only %zu steps ended at the left wall", wall_contacts);
    printf("mixture step vs oracle (boundary %d): max deviation %.3g, %zu merges, %zu steps at "
           "the wall\n",
           boundary, worst, merges, wall_contacts);
    hsbd_rods_free(rods);
}

/* The fragmentation diagnostic counts what the oracle does; with the reflect rule the
 * fragments are those of the pushed end points, so merges stay >= 0 (a regression of
 * 2026-11: counted before the pushes, they went negative and wrapped around). */
static void test_step_stats(int contact_rule) {
    hsbd_rods_params par = {.n = 40,
                            .length = 25.0,
                            .sigma = 0.5,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = 1e-2,
                            .seed = 5,
                            .hard_core = 1,
                            .contact_rule = contact_rule};
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_rods_init_equilibrium(rods);
    size_t merges = 0, frag = 0, start = 0;
    for (int s = 0; s < 200; ++s) {
        hsbd_rods_step_stats st;
        CHECK(hsbd_rods_step(rods, &st) == HSBD_OK, "step");
        CHECK(st.fragments >= st.clusters_start && st.fragments >= st.clusters_end,
              "step %d: %zu clusters, %zu fragments, %zu at end", s, st.clusters_start,
              st.fragments, st.clusters_end);
        size_t total = 0;
        for (size_t k = 0; k < hsbd_rods_cluster_count(rods); ++k)
            total += hsbd_rods_cluster_size(rods, k);
        CHECK(total == par.n, "cluster sizes add to %zu", total);
        merges += st.fragments - st.clusters_end, frag += st.fragments, start += st.clusters_start;
    }
    CHECK(merges > 0 && frag > start, "no merges (%zu) or fragmentations (%zu vs %zu)", merges,
          frag, start);
    hsbd_rods_free(rods);
}

/* Threads change no bit of a step or of its statistics, also when clusters are longer than
 * the part of the ring each thread counts fragments in (a jammed system, packing 0.999, in
 * one deep cosine well that presses it into clusters of thousands of rods: the regression
 * in chunks joined at the seams). */
static void test_stats_on_threads(int contact_rule, int boundary) {
    hsbd_rods_params par = {.n = 20000,
                            .length = 20020.0,
                            .sigma = 1.0,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = 1e-2,
                            .seed = 11,
                            .hard_core = 1,
                            .boundary = boundary,
                            .contact_rule = contact_rule};
    hsbd_field_add(&par.field, hsbd_field_cosine(1e7, par.length));
    hsbd_error err;
    hsbd_rods *one = hsbd_rods_alloc(&par, &err);
    par.threads = 3;
    hsbd_rods *three = hsbd_rods_alloc(&par, &err);
    if (!one || !three) {
        CHECK(0, "alloc");
        return;
    }
    hsbd_rods_init_equilibrium(one);
    hsbd_rods_init_equilibrium(three);
    size_t longest = 0, same = 1;
    for (int s = 0; s < 20; ++s) {
        hsbd_rods_step_stats a, b;
        hsbd_rods_step(one, &a);
        hsbd_rods_step(three, &b);
        same &= a.clusters_start == b.clusters_start && a.fragments == b.fragments &&
                a.clusters_end == b.clusters_end;
        const hsbd_rods_view va = hsbd_rods_get_view(one), vb = hsbd_rods_get_view(three);
        same &= memcmp(va.z, vb.z, par.n * sizeof *va.z) == 0 && va.unwrap == vb.unwrap;
        same &= hsbd_rods_cluster_count(one) == hsbd_rods_cluster_count(three);
        for (size_t k = 0; k < hsbd_rods_cluster_count(one); ++k) {
            const size_t size = hsbd_rods_cluster_size(one, k);
            same &= size == hsbd_rods_cluster_size(three, k);
            if (size > longest) longest = size;
        }
    }
    CHECK(same, "rule %d boundary %d: 3 threads differ from 1", contact_rule, boundary);
    CHECK(longest > par.n / 3, "rule %d boundary %d: the longest cluster, %zu rods, fits a part",
          contact_rule, boundary, longest);
    hsbd_rods_free(one);
    hsbd_rods_free(three);
}

/* The reflect rule writes the pushed end points into z and runs the regression in place
 * when no fragment count is asked for (one species), and into an array of its own when
 * one is: both must give the same bits. A dense system (many pushes) of three batches of
 * gaps and a tail, on a ring and between walls, the in-place one on one and on three
 * threads (batches side by side), stepped against one that counts fragments every step:
 * positions, free end points, pushes and unwrap compared at every step. */
static void test_reflect_in_place(int boundary, int threads) {
    hsbd_rods_params par = {.n = 3100,
                            .length = 3100.0,
                            .sigma = 0.9,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = 1e-3,
                            .seed = 21,
                            .hard_core = 1,
                            .boundary = boundary,
                            .contact_rule = HSBD_CONTACT_REFLECT};
    hsbd_field_add(&par.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_error err;
    hsbd_rods *counted = hsbd_rods_alloc(&par, &err);
    par.threads = threads;
    hsbd_rods *in_place = hsbd_rods_alloc(&par, &err);
    if (!counted || !in_place) {
        CHECK(0, "alloc");
        return;
    }
    hsbd_rods_init_equilibrium(counted);
    hsbd_rods_init_equilibrium(in_place);
    int same = 1, first_diff = -1;
    size_t pushed = 0;
    for (int s = 0; s < 300 && same; ++s) {
        hsbd_rods_step_stats st;
        hsbd_rods_step(counted, &st);
        hsbd_rods_step(in_place, NULL);
        const hsbd_rods_view a = hsbd_rods_get_view(counted), b = hsbd_rods_get_view(in_place);
        same = memcmp(a.z, b.z, par.n * sizeof *a.z) == 0 &&
               memcmp(a.y, b.y, par.n * sizeof *a.y) == 0 &&
               memcmp(a.push, b.push, (par.n + 1) * sizeof *a.push) == 0 && a.unwrap == b.unwrap;
        if (!same) first_diff = s;
        for (size_t i = 0; i <= par.n; ++i)
            pushed += a.push[i] > 0;
    }
    CHECK(same, "boundary %d, %d threads: in place differs from counted at step %d", boundary,
          threads, first_diff);
    CHECK(pushed > 1000, "boundary %d: only %zu pushes in 300 steps", boundary, pushed);
    hsbd_rods_free(counted);
    hsbd_rods_free(in_place);
}

/* A short batch of gaps that listed gaps in its last step draws its random bytes and first
 * low digits before its tests, in one call (push_gap_batch); a fresh system, which has no
 * last step, draws them after: both must give the same bits. A dense ring of 100 rods (one
 * short batch, gaps listed every step) is stepped on; before each step its state is loaded
 * into a fresh system, stepped once beside it, and positions, free end points and pushes
 * compared. */
static void test_reflect_early_draws(void) {
    hsbd_rods_params par = {.n = 100,
                            .length = 100.0,
                            .sigma = 0.9,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = 1e-3,
                            .seed = 23,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_REFLECT};
    hsbd_field_add(&par.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_error err;
    hsbd_rods *on = hsbd_rods_alloc(&par, &err);
    if (!on) {
        CHECK(0, "alloc");
        return;
    }
    hsbd_rods_init_equilibrium(on);
    int same = 1, first_diff = -1;
    size_t pushed = 0;
    for (int s = 0; s < 200 && same; ++s) {
        hsbd_writer w;
        hsbd_writer_init(&w);
        hsbd_rods_save(on, &w);
        hsbd_reader rd;
        hsbd_reader_init(&rd, w.data, w.len);
        hsbd_rods *fresh = hsbd_rods_alloc(&par, &err);
        CHECK(fresh && hsbd_rods_load(fresh, &rd) == 0, "load at step %d", s);
        hsbd_writer_free(&w);
        if (!fresh) break;
        hsbd_rods_step(on, NULL);
        hsbd_rods_step(fresh, NULL);
        const hsbd_rods_view a = hsbd_rods_get_view(on), b = hsbd_rods_get_view(fresh);
        same = memcmp(a.z, b.z, par.n * sizeof *a.z) == 0 &&
               memcmp(a.y, b.y, par.n * sizeof *a.y) == 0 &&
               memcmp(a.push, b.push, (par.n + 1) * sizeof *a.push) == 0;
        if (!same) first_diff = s;
        for (size_t i = 0; i <= par.n; ++i)
            pushed += a.push[i] > 0;
        hsbd_rods_free(fresh);
    }
    CHECK(same, "early draws differ from late ones at step %d", first_diff);
    CHECK(pushed > 1000, "only %zu pushes in 200 steps", pushed);
    hsbd_rods_free(on);
}

/* The library's default contact rule (a zero-initialised parameter struct) is the one the
 * CLI's configuration defaults to: a benchmark or a library user then times and runs what
 * `hsbd run` runs (the library once defaulted to the paper's sticky rule). */
static void test_default_contact_rule(void) {
    const hsbd_rods_params p = {0};
    hsbd_config cfg;
    hsbd_config_defaults(&cfg);
    CHECK(p.contact_rule == cfg.system.contact_rule,
          "library default contact rule %d, configuration default %d", p.contact_rule,
          cfg.system.contact_rule);
    CHECK(cfg.system.contact_rule == HSBD_CONTACT_REFLECT, "default rule %d is not reflect",
          cfg.system.contact_rule);
}

/* The reflect rule's passes over a batch (gaps.h): the scalar and the AVX2 versions give what
 * a plain loop over bridge_may_cross and bridge_byte_candidate gives (the blocks that hold a
 * gap that may cross, their masks, every gap's product g0 g1, the candidates in order, also
 * from both tests in one pass),
 * and the same bits for the pushes and the halves they give the rods (all rods', or only
 * those next to a push), for every batch length (whole blocks and
 * short last ones), one diffusion for all or one per gap, gaps at the edges of the tests
 * (closed or overlapping at the end, -0, NaN, infinite, products on the listing's bound)
 * and bytes at the edges of theirs (0, 255, the last byte that can cross and the next). */
static void test_gap_passes(void) {
    enum { M = 203, BLOCKS = (M + GAP_BLOCK - 1) / GAP_BLOCK };
    test_rng rng = {.seed = 31, .draw = 0};
    double z[M + 1], y[M + 1], d[M], want_g0g1[M];
    uint8_t bytes[GAP_BLOCK * BLOCKS];
    int bad_blocks = 0, bad_candidates = 0, bad_pushes = 0, listed = 0, candidates = 0, total = 0;
    for (int trial = 0; trial < 40; ++trial) {
        const double d_one = 1e-4 * (1 + trial % 3);
        z[0] = y[0] = 0;
        for (size_t j = 0; j < M; ++j) {
            const double u = uniform(&rng), g0 = 0.05 * uniform(&rng);
            double g1 = g0 + 0.02 * normal(&rng);
            if (u < 0.03)
                g1 = 0.0;
            else if (u < 0.06)
                g1 = -0.0;
            else if (u < 0.08)
                g1 = NAN;
            else if (u < 0.10)
                g1 = INFINITY;
            else if (u < 0.15)
                g1 = 20.0 * d_one / g0; /* the product at the listing's bound */
            z[j + 1] = z[j] + g0;
            y[j + 1] = y[j] + g1; /* y's differences give g1 back up to rounding */
            d[j] = d_one * (0.5 + uniform(&rng));
            const double p = exp(-(z[j + 1] - z[j]) * (y[j + 1] - y[j]) / d_one);
            const double v = uniform(&rng);
            const double last = floor(256 * p); /* the byte below p's, or just at it */
            bytes[j] = (uint8_t)(v < 0.1                 ? 0
                                 : v < 0.2               ? 255
                                 : v < 0.5 && last < 256 ? last
                                 : v < 0.6 && last < 255 ? last + 1
                                                         : 256 * uniform(&rng));
        }
        for (size_t m = (size_t)trial; m <= M; m += 41) {
            for (int per_gap = 0; per_gap <= 1; ++per_gap) {
                const double *dd = per_gap ? d : NULL;
                uint16_t want_mask[BLOCKS] = {0}, mask[BLOCKS];
                unsigned want_blocks[BLOCKS], blocks[BLOCKS], want[M + GAP_BLOCK];
                unsigned got[M + GAP_BLOCK];
                double g0g1[M];
                size_t nblocks = 0, count = 0;
                for (size_t j = 0; j < m; ++j) {
                    const double g0 = z[j + 1] - z[j], g1 = y[j + 1] - y[j];
                    const double dj = dd ? dd[j] : d_one;
                    want_g0g1[j] = g0 * g1;
                    if (!bridge_may_cross(g0, g1, dj)) continue;
                    want_mask[j / GAP_BLOCK] |= (uint16_t)(1u << (j % GAP_BLOCK));
                    if (bridge_byte_candidate(g0 * g1, dj, bytes[j])) want[count++] = (unsigned)j;
                    ++listed;
                }
                for (unsigned b = 0; GAP_BLOCK * b < m; ++b)
                    if (want_mask[b]) want_blocks[nblocks++] = b;
                total += (int)m, candidates += (int)count;
                for (int avx2 = 0; avx2 <= hsbd_cpu_has_avx2(); ++avx2) {
                    const size_t nb =
                        (avx2 ? gap_blocks_may_cross_avx2 : gap_blocks_may_cross_scalar)(
                            z, y, dd, d_one, m, mask, blocks, g0g1);
                    int same = nb == nblocks && !memcmp(blocks, want_blocks, nb * sizeof *blocks) &&
                               !memcmp(g0g1, want_g0g1, m * sizeof *g0g1);
                    for (size_t b = 0; GAP_BLOCK * b < m; ++b)
                        same &= mask[b] == want_mask[b];
                    bad_blocks += !same;
                    const size_t n = (avx2 ? gap_candidates_avx2 : gap_candidates_scalar)(
                        g0g1, dd, d_one, m, mask, blocks, nb, bytes, got);
                    bad_candidates += n != count || memcmp(got, want, count * sizeof *got) != 0;
                    size_t listed_blocks;
                    const size_t n_all =
                        (avx2 ? gap_candidates_all_avx2 : gap_candidates_all_scalar)(
                            z, y, dd, d_one, m, bytes, got, &listed_blocks);
                    bad_candidates += n_all != count || listed_blocks != nblocks ||
                                      memcmp(got, want, count * sizeof *got) != 0;
                }
            }
        }
        /* the pushes of the first gaps, as if all were candidates, and their halves */
        if (hsbd_cpu_has_avx2()) {
            double sum[M], sq[M], lu[2][M];
            for (size_t k = 0; k < M; ++k) {
                const double g0 = z[k + 1] - z[k], g1 = y[k + 1] - y[k];
                sum[k] = g0 + g1, sq[k] = (g1 - g0) * (g1 - g0);
                lu[0][k] = lu[1][k] = log(uniform(&rng));
            }
            const size_t count = (size_t)(M - trial);
            gap_pushes_scalar(count, sum, sq, trial % 2 ? d : NULL, d_one, lu[0]);
            gap_pushes_avx2(count, sum, sq, trial % 2 ? d : NULL, d_one, lu[1]);
            bad_pushes += memcmp(lu[0], lu[1], sizeof lu[0]) != 0;
            /* the halves of sparse pushes (every seventh gap) three ways */
            double push[M], half[3][M];
            unsigned at[M];
            size_t count_at = 0;
            for (size_t k = 0; k < M; ++k) {
                push[k] = k % 7 == (size_t)trial % 7 ? lu[0][k] : 0.0;
                if (push[k] != 0) at[count_at++] = (unsigned)k;
            }
            gap_half_pushes_scalar(M - 1, y + 1, push + 1, half[0] + 1);
            gap_half_pushes_avx2(M - 1, y + 1, push + 1, half[1] + 1);
            gap_half_pushes_at(M, y, push, at, count_at, half[2]);
            bad_pushes += memcmp(half[0] + 1, half[1] + 1, (M - 1) * sizeof half[0][0]) != 0 ||
                          memcmp(half[0] + 1, half[2] + 1, (M - 1) * sizeof half[0][0]) != 0;
        }
    }
    CHECK(bad_blocks == 0, "blocks, masks or products wrong in %d batches", bad_blocks);
    CHECK(bad_candidates == 0, "candidates wrong in %d batches", bad_candidates);
    CHECK(bad_pushes == 0, "pushes or halves differ between the versions in %d trials", bad_pushes);
    CHECK(listed > total / 10 && listed < total && candidates > listed / 10 && candidates < listed,
          "%d of %d gaps listed, %d candidates: the test is not mixed", listed, total, candidates);
}

/* bridge_byte_candidate never turns down a gap that can cross: with the byte b, the uniform
 * U = (b + V) / 256 can be below the crossing probability p = exp(-x), x = g0 g1 / D_rel dt,
 * exactly when b < 256 p; every such (x, b) must be a candidate, over x in [0, 25] on a fine
 * grid and at the points where 256 p is a whole number (the edges), for several D_rel dt.
 * And it lets through few others: at most 6.2 % more bytes than can cross, plus one. */
static void test_byte_candidate_bound(void) {
    int missed = 0, loose = 0, tested = 0;
    const double ds[3] = {1e-7, 3e-4, 2.5};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i <= 50000 + 255; ++i) {
            /* a grid in x, then the x at which 256 p = b + 1 for each b, nudged down */
            const double x =
                i <= 50000 ? 25.0 * i / 50000 : -log((i - 50000 + 1) / 256.0) * (1 - 1e-15);
            const long double p = expl(-(long double)x);
            const double g0g1 = x * ds[k]; /* g0 g1 / D_rel dt = x up to rounding */
            const long double p_eff = expl(-(long double)g0g1 / ds[k]);
            int count = 0, can = 0;
            for (unsigned b = 0; b < 256; ++b) {
                const int c = bridge_byte_candidate(g0g1, ds[k], b);
                const int crosses = (long double)b < 256.0L * p_eff;
                missed += crosses && !c;
                count += c, can += crosses;
            }
            loose += count > 1.062 * 256.0 * (double)p + 1.0 && count > can;
            ++tested;
        }
    CHECK(missed == 0, "%d bytes that can cross were turned down (of %d x)", missed, tested);
    CHECK(loose == 0, "%d x let through more than 6.2 %% extra bytes", loose);
}

int main(void) {
    test_gap_passes();
    test_byte_candidate_bound();
    test_default_contact_rule();
    test_reflect_early_draws();
    test_fragmentation_brute_force();
    test_ring_step_vs_oracle();
    test_library_step_vs_oracle();
    test_mixture_step_vs_oracle(HSBD_RODS_PERIODIC);
    test_mixture_step_vs_oracle(HSBD_RODS_WALLS);
    test_step_stats(HSBD_CONTACT_STICKY);
    test_step_stats(HSBD_CONTACT_REFLECT);
    for (int threads = 1; threads <= 3; threads += 2) {
        test_reflect_in_place(HSBD_RODS_PERIODIC, threads);
        test_reflect_in_place(HSBD_RODS_WALLS, threads);
    }
    for (int rule = 0; rule <= 1; ++rule) {
        test_stats_on_threads(rule ? HSBD_CONTACT_STICKY : HSBD_CONTACT_REFLECT,
                              HSBD_RODS_PERIODIC);
        test_stats_on_threads(rule ? HSBD_CONTACT_STICKY : HSBD_CONTACT_REFLECT, HSBD_RODS_WALLS);
    }
    return test_finish("test_bcd_step");
}
