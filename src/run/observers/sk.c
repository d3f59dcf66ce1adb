/* The static structure factor S(k) = <|sum_j exp(i k . r_j)|^2> / N of particles in a
 * periodic box (sample.sk_every > 0; sk.tsv): wavevectors of the box's lattice, k_a = 2 pi
 * n_a / L_a, along the axes and the diagonals of that lattice up to sample.sk_max, binned
 * by |k| (bins of 2 pi / L, the largest L), errors from time blocks. Along these directions
 * exp(i k . r) is a product of the particles' exp(i 2 pi n x_a / L_a), made for n = 1, 2,
 * ... by recurrence: per sample O(N x vectors) multiplications, no sine in the inner loop. */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"

enum { SK_DIRECTIONS = 13 };

typedef struct sk {
    int dimension;
    size_t nvec, nbins, mmax; /* wavevectors, |k| bins, the largest multiple of a direction */
    int (*dir)[3];            /* per vector: its direction (components -1, 0, 1) */
    size_t *mult, *bin;       /* per vector: n = mult dir, and its bin */
    double *k_mean;           /* per bin: the mean |k| of its vectors */
    size_t *count;            /* per bin: its vectors */
    double *re, *im;          /* per vector: sums of one sample */
    double *e;                /* per axis, n = 0 .. mmax: exp(i 2 pi n x / L) of a particle */
    hsbd_blocks *blocks;      /* per bin: S averaged over its vectors, per sample */
} sk;

static void release(void *state) {
    sk *s = state;
    if (!s) return;
    free(s->dir), free(s->mult), free(s->bin), free(s->k_mean), free(s->count);
    free(s->re), free(s->im), free(s->e);
    hsbd_blocks_free(s->blocks);
    free(s);
}

/* the directions of the lattice's axes and diagonals, one of each +- pair: 13 in 3D, 4 in
 * 2D, 1 on a line */
static size_t directions(int dimension, int out[SK_DIRECTIONS][3]) {
    size_t n = 0;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) {
                const int d[3] = {x, y, z};
                int first = 0; /* the first non-zero component is positive: one of +-d */
                for (int a = 2; a >= 0; --a)
                    if (d[a]) first = d[a];
                if (first <= 0 || (dimension < 3 && z) || (dimension < 2 && y)) continue;
                out[n][0] = x, out[n][1] = y, out[n][2] = z, ++n;
            }
    return n;
}

static double k_of(const hsbd_frame *f, const int d[3], size_t m) {
    double k2 = 0;
    for (int a = 0; a < f->dimension; ++a) {
        const double ka = 2 * 3.141592653589793 * (double)m * d[a] / f->box[a];
        k2 += ka * ka;
    }
    return sqrt(k2);
}

/* the wavevectors up to kmax and their bins */
static int make_vectors(sk *s, const hsbd_frame *f, double kmax, hsbd_error *err) {
    int d[SK_DIRECTIONS][3];
    const size_t nd = directions(f->dimension, d);
    double lmax = 0;
    for (int a = 0; a < f->dimension; ++a)
        lmax = fmax(lmax, f->box[a]);
    const double dk = 2 * 3.141592653589793 / lmax;
    s->mmax = (size_t)(kmax * lmax / (2 * 3.141592653589793)); /* of the longest axis */
    s->nbins = (size_t)(kmax / dk) + 1;
    const size_t cap = nd * (s->mmax + 1);
    s->dir = malloc(cap * sizeof *s->dir);
    s->mult = malloc(cap * sizeof *s->mult), s->bin = malloc(cap * sizeof *s->bin);
    s->k_mean = calloc(s->nbins, sizeof *s->k_mean), s->count = calloc(s->nbins, sizeof *s->count);
    s->re = malloc(cap * sizeof *s->re), s->im = malloc(cap * sizeof *s->im);
    s->e = malloc(3 * 2 * (s->mmax + 1) * sizeof *s->e);
    if (!s->dir || !s->mult || !s->bin || !s->k_mean || !s->count || !s->re || !s->im || !s->e)
        return hsbd_error_set(err, HSBD_ENOMEM, "S(k): out of memory");
    for (size_t q = 0; q < nd; ++q)
        for (size_t m = 1; m <= s->mmax; ++m) {
            const double k = k_of(f, d[q], m);
            if (k > kmax) break;
            const size_t b = (size_t)(k / dk + 0.5);
            s->dir[s->nvec][0] = d[q][0], s->dir[s->nvec][1] = d[q][1],
            s->dir[s->nvec][2] = d[q][2];
            s->mult[s->nvec] = m, s->bin[s->nvec] = b;
            s->k_mean[b] += k, s->count[b] += 1, ++s->nvec;
        }
    for (size_t b = 0; b < s->nbins; ++b)
        if (s->count[b]) s->k_mean[b] /= (double)s->count[b];
    if (!s->nvec)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "sample.sk_max = %g is below the smallest wavevector of the box, "
                              "2 pi / L = %g; allowed: sk_max >= %g",
                              kmax, dk, dk);
    return HSBD_OK;
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (cfg->sample.sk_every <= 0) return HSBD_OK;
    const hsbd_frame *f = run_frame(r);
    for (int a = 0; a < f->dimension; ++a)
        if (!f->periodic[a]) {
            run_warn(r, "sk.tsv is not written: S(k) needs a periodic box (walls along %c)",
                     "xyz"[a]);
            return HSBD_OK;
        }
    sk *s = calloc(1, sizeof *s);
    if (!s) return hsbd_error_set(err, HSBD_ENOMEM, "S(k): out of memory");
    *state = s;
    s->dimension = f->dimension;
    const double kmax = cfg->sample.sk_max > 0 ? cfg->sample.sk_max : 20 / cfg->system.sigma;
    const int rc = make_vectors(s, f, kmax, err);
    if (rc != HSBD_OK) return rc;
    s->blocks = hsbd_blocks_alloc(s->nbins, (size_t)cfg->sample.blocks,
                                  hsbd_config_steps(cfg) / (uint64_t)cfg->sample.sk_every);
    return s->blocks ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "S(k): out of memory");
}

static uint64_t every(const run *r) {
    return (uint64_t)r->cfg->sample.sk_every;
}

/* exp(i 2 pi n x / L) for n = 0 .. mmax of one coordinate, as (re, im) pairs */
static void phases(double x, double length, size_t mmax, double *e) {
    const double t = 2 * 3.141592653589793 * x / length, c = cos(t), s = sin(t);
    e[0] = 1, e[1] = 0;
    for (size_t n = 1; n <= mmax; ++n) {
        e[2 * n] = e[2 * n - 2] * c - e[2 * n - 1] * s;
        e[2 * n + 1] = e[2 * n - 2] * s + e[2 * n - 1] * c;
    }
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    sk *s = state;
    const hsbd_frame *f = run_frame(r);
    const size_t stride = 2 * (s->mmax + 1);
    for (size_t v = 0; v < s->nvec; ++v)
        s->re[v] = s->im[v] = 0;
    for (size_t i = 0; i < f->n; ++i) {
        for (int a = 0; a < s->dimension; ++a)
            phases(f->x[3 * i + a], f->box[a], s->mmax, s->e + a * stride);
        for (size_t v = 0; v < s->nvec; ++v) { /* prod_a exp(i 2 pi m d_a x_a / L_a) */
            double re = 1, im = 0;
            for (int a = 0; a < s->dimension; ++a) {
                if (!s->dir[v][a]) continue;
                const double *e = s->e + a * stride + 2 * s->mult[v];
                const double er = e[0], ei = s->dir[v][a] > 0 ? e[1] : -e[1];
                const double nr = re * er - im * ei;
                im = re * ei + im * er, re = nr;
            }
            s->re[v] += re, s->im[v] += im;
        }
    }
    double *acc = hsbd_blocks_acc(s->blocks);
    for (size_t v = 0; v < s->nvec; ++v)
        acc[s->bin[v]] += (s->re[v] * s->re[v] + s->im[v] * s->im[v]) / (double)f->n /
                          (double)s->count[s->bin[v]];
    hsbd_blocks_end_sample(s->blocks);
    return HSBD_OK;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const sk *s = state;
    double *val = malloc(3 * s->nbins * sizeof *val);
    if (!val) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing sk.tsv");
    hsbd_blocks_result(s->blocks, val + 2 * s->nbins, val + s->nbins);
    for (size_t b = 0; b < s->nbins; ++b)
        val[b] = val[2 * s->nbins + b];
    const int rc = hsbd_write_lag_table(
        r->cfg->output.dir, "sk.tsv", r->cfg,
        "static structure factor S(k) = <|sum_j exp(i k.r_j)|^2> / N over the wavevectors of "
        "the box's lattice along its axes and diagonals, binned by |k| (k: the mean |k| of the "
        "bin's vectors); errors from time blocks",
        "k\tS\tS_err\tvectors", s->nbins, s->k_mean, s->count, 1, val, err);
    free(val);
    return rc;
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_blocks_save(((const sk *)state)->blocks, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_blocks_load(((sk *)state)->blocks, rd);
}

const run_observer_ops run_observe_sk = {.name = "S(k)",
                                         .build = build,
                                         .every = every,
                                         .sample = sample,
                                         .save = save,
                                         .load = load,
                                         .write_tables = write_tables,
                                         .free = release};
