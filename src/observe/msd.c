/* Tagged-particle MSD from unwrapped positions at log-spaced lag times. Time origins are
 * spaced so that at most `slots` snapshots of N positions are alive (memory bounded at
 * large N); each (origin, lag) pair gives one particle-averaged value, and the error of
 * a lag is the block average over its origins in time order, or, with segments, the
 * scatter between contiguous groups of rods (label order is space order on a line):
 * time blocks shorter than the lag overlap and understate the error at long lags. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/observe.h"
#include "observe/checkpoint.h"

struct hsbd_msd {
    size_t n, nlags, slots, nblocks;
    double sample_dt;
    uint64_t origin_every, max_origins, sample;
    uint64_t *lag;     /* lag k in samples */
    long *lag_index;   /* samples -> k, or -1 (size max lag + 1) */
    uint64_t max_lag;  /* in samples */
    double *snap;      /* slots x n unwrapped positions */
    uint64_t *snap_at; /* sample index of each slot's origin */
    double *value;     /* nlags x max_origins */
    size_t *count;     /* values per lag */
    size_t *members;   /* the rods averaged over (NULL: all n) */
    size_t nseg;       /* rod segments for the error (0: time blocks) */
    double *seg_sum;   /* nlags x nseg sums of squared displacements */
    double wavenumber; /* > 0: also the self-intermediate scattering function */
    double *fs_value;  /* nlags x max_origins means of cos(k displacement) */
};

void hsbd_msd_free(hsbd_msd *m) {
    if (!m) return;
    free(m->lag);
    free(m->lag_index);
    free(m->snap);
    free(m->snap_at);
    free(m->value);
    free(m->count);
    free(m->seg_sum);
    free(m->members);
    free(m->fs_value);
    free(m);
}

hsbd_msd *hsbd_msd_alloc(size_t n, double sample_dt, uint64_t nsamples_total, double max_lag,
                         int points_per_decade, size_t nblocks, hsbd_error *err) {
    hsbd_msd *m = calloc(1, sizeof *m);
    if (!m) return hsbd_error_set(err, HSBD_ENOMEM, "msd: out of memory"), NULL;
    m->n = n;
    m->sample_dt = sample_dt;
    m->nblocks = nblocks;
    uint64_t lmax = (uint64_t)floor(max_lag / sample_dt + 1e-9);
    if (lmax >= nsamples_total) lmax = nsamples_total ? nsamples_total - 1 : 0;
    if (lmax < 1) lmax = 1;
    m->max_lag = lmax;
    /* log-spaced lags 1 .. lmax, duplicates removed */
    const size_t cap = (size_t)(points_per_decade * (log10((double)lmax) + 1) + 2);
    m->lag = malloc(cap * sizeof *m->lag);
    m->lag_index = malloc((lmax + 1) * sizeof *m->lag_index);
    if (!m->lag || !m->lag_index) goto oom;
    for (uint64_t l = 0; l <= lmax; ++l)
        m->lag_index[l] = -1;
    for (int j = 0;; ++j) {
        uint64_t l = (uint64_t)llround(pow(10.0, (double)j / points_per_decade));
        if (l > lmax) l = lmax;
        if (m->lag_index[l] < 0 && m->nlags < cap) {
            m->lag_index[l] = (long)m->nlags;
            m->lag[m->nlags++] = l;
        }
        if (l == lmax) break;
    }
    /* snapshots alive: at most ~128 MiB worth, between 4 and 64 */
    size_t slots = (size_t)((128u << 20) / (8 * (n ? n : 1)));
    slots = slots < 4 ? 4 : slots > 64 ? 64 : slots;
    m->origin_every = (lmax + slots - 2) / (slots - 1);
    if (m->origin_every < 1) m->origin_every = 1;
    const uint64_t min_every = nsamples_total / 4000; /* at most ~4000 origins */
    if (m->origin_every < min_every) m->origin_every = min_every;
    m->slots = (size_t)(lmax / m->origin_every + 2);
    m->max_origins = nsamples_total / m->origin_every + 1;
    m->snap = malloc(m->slots * n * sizeof *m->snap);
    m->snap_at = calloc(m->slots, sizeof *m->snap_at);
    m->value = malloc(m->nlags * m->max_origins * sizeof *m->value);
    m->count = calloc(m->nlags, sizeof *m->count);
    if (!m->snap || !m->snap_at || !m->value || !m->count) goto oom;
    for (size_t s = 0; s < m->slots; ++s)
        m->snap_at[s] = UINT64_MAX;
    return m;
oom:
    hsbd_msd_free(m);
    hsbd_error_set(err, HSBD_ENOMEM, "msd: out of memory for N = %zu", n);
    return NULL;
}

static size_t rod_of(const hsbd_msd *m, size_t k) {
    return m->members ? m->members[k] : k;
}

/* Unwrapped coordinate of item i: from a value array, or from the rods' view. */
typedef struct msd_source {
    const double *values;
    const hsbd_rods_view *rods;
} msd_source;

static inline double coordinate(const msd_source *src, size_t i) {
    if (src->values) return src->values[i];
    return src->rods->z[i] + src->rods->offset[i] + src->rods->unwrap;
}

/* sum of squared displacements of averaged items [lo, hi) from the origin snapshot x0 */
static double squared_displacements(const hsbd_msd *m, const msd_source *src, const double *x0,
                                    size_t lo, size_t hi) {
    double sum = 0;
    for (size_t k = lo; k < hi; ++k) {
        const double d = coordinate(src, rod_of(m, k)) - x0[k];
        sum += d * d;
    }
    return sum;
}

static double mean_cosine(const hsbd_msd *m, const msd_source *src, const double *x0) {
    double sum = 0;
    for (size_t k = 0; k < m->n; ++k)
        sum += cos(m->wavenumber * (coordinate(src, rod_of(m, k)) - x0[k]));
    return sum / (double)m->n;
}

int hsbd_msd_set_wavenumber(hsbd_msd *m, double k, hsbd_error *err) {
    if (!(k > 0) || !isfinite(k) || m->sample > 0)
        return hsbd_error_set(err, HSBD_EINPUT, "msd: wavenumber %g (need > 0, before sampling)",
                              k);
    free(m->fs_value);
    m->fs_value = malloc(m->nlags * m->max_origins * sizeof *m->fs_value);
    if (!m->fs_value) return hsbd_error_set(err, HSBD_ENOMEM, "msd: out of memory");
    m->wavenumber = k;
    return HSBD_OK;
}

int hsbd_msd_set_members(hsbd_msd *m, size_t count, const size_t *members, hsbd_error *err) {
    if (count < 1 || count > m->n || m->sample > 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "msd: %zu members of %zu rods (need 1..N, before "
                              "sampling)",
                              count, m->n);
    free(m->members);
    m->members = malloc(count * sizeof *m->members);
    if (!m->members) return hsbd_error_set(err, HSBD_ENOMEM, "msd: out of memory");
    for (size_t k = 0; k < count; ++k)
        m->members[k] = members[k];
    m->n = count;
    return HSBD_OK;
}

static void msd_sample(hsbd_msd *m, const msd_source *v) {
    const uint64_t k = m->sample++;
    const size_t n = m->n;
    /* displacements from every live origin whose lag is on the grid */
    for (size_t s = 0; s < m->slots; ++s) {
        const uint64_t o = m->snap_at[s];
        if (o == UINT64_MAX || k <= o || k - o > m->max_lag) continue;
        const long j = m->lag_index[k - o];
        if (j < 0) continue;
        const double *x0 = m->snap + s * n;
        double sum = 0;
        if (m->nseg) {
            for (size_t g = 0; g < m->nseg; ++g) {
                const double part =
                    squared_displacements(m, v, x0, g * n / m->nseg, (g + 1) * n / m->nseg);
                m->seg_sum[(size_t)j * m->nseg + g] += part;
                sum += part;
            }
        } else {
            sum = squared_displacements(m, v, x0, 0, n);
        }
        const size_t c = m->count[j];
        if (c < m->max_origins) {
            m->value[(size_t)j * m->max_origins + c] = sum / (double)n;
            if (m->fs_value) m->fs_value[(size_t)j * m->max_origins + c] = mean_cosine(m, v, x0);
            m->count[j] = c + 1;
        }
    }
    if (k % m->origin_every == 0) {
        const size_t s = (size_t)((k / m->origin_every) % m->slots);
        double *x0 = m->snap + s * n;
        for (size_t q = 0; q < n; ++q)
            x0[q] = coordinate(v, rod_of(m, q));
        m->snap_at[s] = k;
    }
}

void hsbd_msd_sample(hsbd_msd *m, const hsbd_rods_view *v) {
    const msd_source src = {NULL, v};
    msd_sample(m, &src);
}

void hsbd_msd_sample_values(hsbd_msd *m, const double *values) {
    const msd_source src = {values, NULL};
    msd_sample(m, &src);
}

void hsbd_msd_restart(hsbd_msd *m) {
    for (size_t s = 0; s < m->slots; ++s)
        m->snap_at[s] = UINT64_MAX;
}

int hsbd_msd_set_segments(hsbd_msd *m, size_t nseg, hsbd_error *err) {
    if (nseg < 2 || nseg > m->n)
        return hsbd_error_set(err, HSBD_EINPUT, "msd: %zu segments for %zu rods (need 2..N)", nseg,
                              m->n);
    free(m->seg_sum);
    m->seg_sum = calloc(m->nlags * nseg, sizeof *m->seg_sum);
    if (!m->seg_sum) return hsbd_error_set(err, HSBD_ENOMEM, "msd: out of memory");
    m->nseg = nseg;
    return HSBD_OK;
}

size_t hsbd_msd_lags(const hsbd_msd *m) {
    return m->nlags;
}

/* mean of c per-origin values and its block-average error over origins in time order */
static void origin_blocks(const double *val, size_t c, size_t nblocks, double *mean, double *err) {
    double sum = 0;
    for (size_t i = 0; i < c; ++i)
        sum += val[i];
    *mean = c ? sum / (double)c : NAN;
    const size_t nb = c < nblocks ? c : nblocks;
    if (nb < 2) {
        *err = NAN;
        return;
    }
    double var = 0;
    for (size_t b = 0; b < nb; ++b) {
        const size_t lo = b * c / nb, hi = (b + 1) * c / nb;
        double s = 0;
        for (size_t i = lo; i < hi; ++i)
            s += val[i];
        const double d = s / (double)(hi - lo) - *mean;
        var += d * d;
    }
    *err = sqrt(var / ((double)nb * (double)(nb - 1)));
}

void hsbd_msd_fs(const hsbd_msd *m, size_t k, double *fs, double *err) {
    if (!m->fs_value) {
        *fs = *err = NAN;
        return;
    }
    origin_blocks(m->fs_value + k * m->max_origins, m->count[k], m->nblocks, fs, err);
}

void hsbd_msd_result(const hsbd_msd *m, size_t k, double *t, double *msd, double *err,
                     size_t *origins) {
    const size_t c = m->count[k];
    const double *val = m->value + k * m->max_origins;
    *t = (double)m->lag[k] * m->sample_dt;
    *origins = c;
    double sum = 0;
    for (size_t i = 0; i < c; ++i)
        sum += val[i];
    *msd = c ? sum / (double)c : NAN;
    if (m->nseg) { /* scatter of the segments' means (each over all origins) */
        double var = 0;
        for (size_t g = 0; g < m->nseg; ++g) {
            const double rods = (double)((g + 1) * m->n / m->nseg - g * m->n / m->nseg);
            const double d = m->seg_sum[k * m->nseg + g] / (rods * (double)c) - *msd;
            var += d * d;
        }
        *err = c ? sqrt(var / ((double)m->nseg * (double)(m->nseg - 1))) : NAN;
        return;
    }
    origin_blocks(val, c, m->nblocks, msd, err);
}

/* ---- checkpoints ---- */
void hsbd_msd_save(const hsbd_msd *m, hsbd_writer *w) {
    hsbd_put_tag(w, "msd");
    const uint64_t shape[7] = {
        m->n, m->nlags, m->slots, m->max_origins, m->nseg, m->fs_value != NULL, m->origin_every};
    hsbd_put_u64s(w, shape, 7);
    hsbd_put_u64(w, m->sample);
    hsbd_put_f64s(w, m->snap, m->slots * m->n);
    hsbd_put_u64s(w, m->snap_at, m->slots);
    hsbd_put_f64s(w, m->value, m->nlags * m->max_origins);
    hsbd_put_u64(w, m->nlags);
    for (size_t k = 0; k < m->nlags; ++k)
        hsbd_put_u64(w, m->count[k]);
    if (m->nseg) hsbd_put_f64s(w, m->seg_sum, m->nlags * m->nseg);
    if (m->fs_value) hsbd_put_f64s(w, m->fs_value, m->nlags * m->max_origins);
}

/* A per-lag table of `have` origins per lag read into rows of `room` (room >= have). */
static int load_rows(hsbd_reader *r, double *v, size_t nlags, size_t have, size_t room) {
    if (hsbd_get_count(r, nlags * have, "msd values")) return -1;
    for (size_t k = 0; k < nlags; ++k)
        for (size_t c = 0; c < have; ++c)
            if (hsbd_get_f64(r, &v[k * room + c])) return -1;
    return 0;
}

/* Into an MSD of the same configuration. When the run was extended (more samples
 * planned), the stored origin spacing is kept and there is room for the new origins. */
int hsbd_msd_load(hsbd_msd *m, hsbd_reader *r) {
    uint64_t shape[7], sample;
    if (hsbd_get_tag(r, "msd") || hsbd_get_u64s(r, shape, 7) || hsbd_get_u64(r, &sample)) return -1;
    const uint64_t every = shape[6], stored_origins = shape[3];
    if (shape[0] != m->n || shape[1] != m->nlags || shape[4] != m->nseg ||
        shape[5] != (m->fs_value != NULL) || every < 1 || every > m->max_lag + 1 ||
        shape[2] != (size_t)(m->max_lag / every + 2) || stored_origins < 1)
        return hsbd_reader_fail(r, "an MSD of another shape");
    /* the planned samples give the room for origins at the stored spacing */
    const uint64_t planned = (m->max_origins - 1) * m->origin_every;
    const uint64_t room =
        planned / every + 1 > stored_origins ? planned / every + 1 : stored_origins;
    if (stored_origins > planned / every + 2 || sample > planned + every)
        return hsbd_reader_fail(r, "an MSD of a longer run");
    if (every != m->origin_every || (size_t)shape[2] != m->slots || room != m->max_origins) {
        double *snap = realloc(m->snap, (size_t)shape[2] * m->n * sizeof *snap);
        uint64_t *at = snap ? realloc(m->snap_at, (size_t)shape[2] * sizeof *at) : NULL;
        double *val = at ? malloc(m->nlags * (size_t)room * sizeof *val) : NULL;
        double *fs = val && m->fs_value ? malloc(m->nlags * (size_t)room * sizeof *fs) : NULL;
        if (snap) m->snap = snap;
        if (at) m->snap_at = at;
        if (!val || (m->fs_value && !fs)) {
            free(val);
            return hsbd_reader_oom(r, "the MSD");
        }
        free(m->value), m->value = val;
        if (fs) free(m->fs_value), m->fs_value = fs;
        m->origin_every = every, m->slots = (size_t)shape[2], m->max_origins = (size_t)room;
    }
    m->sample = sample;
    if (hsbd_get_f64s(r, m->snap, m->slots * m->n) || hsbd_get_u64s(r, m->snap_at, m->slots) ||
        load_rows(r, m->value, m->nlags, (size_t)stored_origins, m->max_origins) ||
        hsbd_get_count(r, m->nlags, "msd counts"))
        return -1;
    for (size_t k = 0; k < m->nlags; ++k) {
        uint64_t c;
        if (hsbd_get_u64(r, &c)) return -1;
        if (c > stored_origins) return hsbd_reader_fail(r, "msd: more origins than room");
        m->count[k] = (size_t)c;
    }
    if (m->nseg && hsbd_get_f64s(r, m->seg_sum, m->nlags * m->nseg)) return -1;
    if (m->fs_value && load_rows(r, m->fs_value, m->nlags, (size_t)stored_origins, m->max_origins))
        return -1;
    return 0;
}
