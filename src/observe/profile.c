/* Density profile (Antonov Eqs. 24-25) and two-particle density at contact (Eq. 26),
 * folded into one period and block-averaged. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/observe.h"
#include "observe/checkpoint.h"

struct hsbd_profile {
    double period, bin_width, contact_width;
    size_t nbins;
    double periods;   /* L / period, set from the samples */
    size_t nsegments; /* > 0: spatial error blocks (segments of the ring) */
    size_t nblocks;   /* error blocks (time or space) */
    double min_gap;
    uint64_t nonfinite;   /* positions that were NaN or infinite (never binned) */
    hsbd_blocks *density; /* counts per bin per sample */
    hsbd_blocks *contact; /* contact pairs per bin (left rod) per sample */
    hsbd_blocks *impulse; /* contact impulses / (kT dt) per bin (left rod) per sample */
    hsbd_blocks *extrap;  /* gap density extrapolated to zero gap, per bin per sample */
    double *scratch;      /* N + 1 contact impulses of a sample */
    size_t scratch_n;
};

static hsbd_profile *profile_alloc(double period, double bin_width, double contact_width,
                                   size_t nblocks, uint64_t nsamples_total, int spatial,
                                   hsbd_error *err) {
    const double bins = round(period / bin_width);
    if (!(bins >= 1) || bins > 1e8) {
        hsbd_error_set(err, HSBD_EINPUT, "profile: period/bin_width = %g bins is out of range",
                       period / bin_width);
        return NULL;
    }
    hsbd_profile *p = calloc(1, sizeof *p);
    if (!p) return hsbd_error_set(err, HSBD_ENOMEM, "profile: out of memory"), NULL;
    p->period = period;
    p->nbins = (size_t)bins;
    p->bin_width = period / bins;
    p->contact_width = contact_width;
    p->min_gap = DBL_MAX;
    p->nsegments = spatial ? nblocks : 0;
    p->nblocks = nblocks;
    hsbd_blocks **acc[] = {&p->density, &p->contact, &p->impulse, &p->extrap};
    for (int k = 0; k < 4; ++k)
        *acc[k] = spatial ? hsbd_blocks_alloc_spatial(p->nbins, nblocks)
                          : hsbd_blocks_alloc(p->nbins, nblocks, nsamples_total);
    if (!p->density || !p->contact || !p->impulse || !p->extrap) {
        hsbd_profile_free(p);
        hsbd_error_set(err, HSBD_ENOMEM, "profile: out of memory");
        return NULL;
    }
    return p;
}

hsbd_profile *hsbd_profile_alloc(double period, double bin_width, double contact_width,
                                 size_t nblocks, uint64_t nsamples_total, hsbd_error *err) {
    return profile_alloc(period, bin_width, contact_width, nblocks, nsamples_total, 0, err);
}

hsbd_profile *hsbd_profile_alloc_spatial(double period, double bin_width, double contact_width,
                                         size_t nsegments, hsbd_error *err) {
    return profile_alloc(period, bin_width, contact_width, nsegments, 1, 1, err);
}

void hsbd_profile_free(hsbd_profile *p) {
    if (!p) return;
    hsbd_blocks_free(p->density);
    hsbd_blocks_free(p->contact);
    hsbd_blocks_free(p->impulse);
    hsbd_blocks_free(p->extrap);
    free(p->scratch);
    free(p);
}

static size_t bin_of(const hsbd_profile *p, double x) {
    const double b = floor((x - p->period * floor(x / p->period)) / p->bin_width);
    return b < (double)p->nbins ? (size_t)b : p->nbins - 1; /* x finite: b >= 0 */
}

/* The accumulators of this sample: for time blocks the current sample's, for spatial
 * blocks the first segment's (segment k is k * nbins further on). Fetched once per
 * sample, so the per-rod work is an index computation. */
typedef struct acc_set {
    double *density, *contact, *impulse, *extrap;
} acc_set;

static acc_set accumulators(hsbd_profile *p) {
    if (!p->nsegments)
        return (acc_set){hsbd_blocks_acc(p->density), hsbd_blocks_acc(p->contact),
                         hsbd_blocks_acc(p->impulse), hsbd_blocks_acc(p->extrap)};
    return (acc_set){hsbd_blocks_acc_block(p->density, 0), hsbd_blocks_acc_block(p->contact, 0),
                     hsbd_blocks_acc_block(p->impulse, 0), hsbd_blocks_acc_block(p->extrap, 0)};
}

/* index of the bin of a rod at x (ring frame) in the accumulators of acc_set */
static size_t acc_index(const hsbd_profile *p, const hsbd_rods_view *v, double x) {
    const size_t b = bin_of(p, x);
    if (!p->nsegments) return b;
    const double L = v->length;
    const size_t k = (size_t)((x - L * floor(x / L)) / L * (double)p->nsegments);
    return (k < p->nsegments ? k : p->nsegments - 1) * p->nbins + b;
}

/* gap between rod i and the next in ring order; between walls the last rod has none */
static double ring_gap(const hsbd_rods_view *v, size_t i) {
    if (i + 1 < v->n) return v->z[i + 1] - v->z[i];
    return v->periodic ? v->z[0] + v->free_length - v->z[i] : HUGE_VAL;
}

static double view_mobility(const hsbd_rods_view *v, size_t i) {
    return v->species ? v->species_mobility[v->species[i]] : v->mobility;
}

/* Between walls: the impulse the left wall passed to the chain of rods linked to it
 * (closed or pushed gaps): minus the sum of (y_i - z_i)/mu_i over that chain, since no
 * impulse crosses the chain's open end. */
static double left_wall_impulse(const hsbd_rods_view *v, double tol) {
    const size_t n = v->n;
    const int linked = (v->push && v->push[n] > 0) || v->z[0] <= tol;
    if (!linked) return 0.0;
    double j = 0.0;
    for (size_t i = 0; i < n; ++i) {
        j -= (v->y[i] - v->z[i]) / view_mobility(v, i);
        const int pushed = v->push && v->push[i] > 0;
        if (!pushed && ring_gap(v, i) > tol) break;
    }
    return j;
}

/* Contact theorem estimator: the impulse the step passed across contact (i, i+1) is
 * J_i = sum over the cluster's rods k <= i of (y_k - z_k) / mu_k (Antonov Eq. 8
 * integrated over the step, friction-weighted); kT rho2(x, x+sigma) is the mean contact
 * force, so each contact contributes J_i / (kT dt). */
void hsbd_contact_impulses(const hsbd_rods_view *v, double *out) {
    const size_t n = v->n;
    const double tol = 1e-12 * v->length;
    memset(out, 0, (n + 1) * sizeof *out);
    if (!v->hard_core || !v->y) return;
    /* anchor: a rod whose left gap is open and was not pushed (no impulse across it);
     * between walls rod 0, starting from the left wall's impulse */
    size_t start = 0;
    double widest = -1.0;
    for (size_t i = 0; i < n && v->periodic; ++i) {
        const size_t left = (i + n - 1) % n;
        const double g = ring_gap(v, left);
        const int pushed = v->push && v->push[left] > 0;
        if (!pushed && g > widest) widest = g, start = i;
        if (!pushed && g > tol) break;
    }
    const double scale = 1.0 / (v->kT * v->dt);
    double j = v->periodic ? 0.0 : left_wall_impulse(v, tol); /* across the gap right of i */
    out[n] = j * scale;
    for (size_t k = 0; k < n; ++k) {
        const size_t i = (start + k) % n;
        j += (v->y[i] - v->z[i]) / view_mobility(v, i);
        const int pushed = v->push && v->push[i] > 0;
        const int open = !pushed && (!v->periodic && i + 1 == n ? v->free_length - v->z[i]
                                                                : ring_gap(v, i)) > tol;
        if (open) {
            j = 0.0; /* open gap, no impulse: the running sum closes here */
            continue;
        }
        out[i] = j * scale;
    }
}

void hsbd_wall_impulses(const hsbd_rods_view *v, double out[2]) {
    const size_t n = v->n;
    const double tol = 1e-12 * v->length;
    out[0] = out[1] = 0.0;
    if (!v->hard_core || !v->y || v->periodic || n == 0) return;
    const double scale = 1.0 / (v->kT * v->dt), left = left_wall_impulse(v, tol);
    out[0] = left * scale;
    const int linked = (v->push && v->push[n - 1] > 0) || v->free_length - v->z[n - 1] <= tol;
    if (!linked) return;
    size_t start = n - 1; /* the chain's first rod: after its last open gap (as above) */
    while (start > 0 && ((v->push && v->push[start - 1] > 0) || ring_gap(v, start - 1) <= tol))
        --start;
    double j = start == 0 ? left : 0.0;
    for (size_t i = start; i < n; ++i)
        j += (v->y[i] - v->z[i]) / view_mobility(v, i);
    out[1] = j * scale;
}

static void sample_impulses(hsbd_profile *p, const hsbd_rods_view *v, double *impulse) {
    const size_t n = v->n;
    double *j = p->scratch;
    hsbd_contact_impulses(v, j);
    for (size_t i = 0; i < n; ++i) {
        if (!v->periodic && i + 1 == n) break; /* the right wall: no rod pair */
        if (j[i] != 0.0) impulse[acc_index(p, v, v->z[i] + v->offset[i])] += j[i];
    }
}

int hsbd_profile_sample(hsbd_profile *p, const hsbd_rods_view *v) {
    const size_t n = v->n;
    if (v->hard_core && v->y && n > 1 && p->scratch_n != n + 1) { /* the impulses' room */
        free(p->scratch);
        p->scratch = malloc((n + 1) * sizeof *p->scratch);
        p->scratch_n = p->scratch ? n + 1 : 0;
        if (!p->scratch) return HSBD_ENOMEM; /* the sample is not taken */
    }
    const acc_set acc = accumulators(p);
    p->periods = v->length / p->period;
    double min_gap = p->min_gap;
    const double closed_tol = 1e-12 * v->length; /* as in hsbd_contact_impulses */
    for (size_t i = 0; i < n; ++i) {
        const double x = v->z[i] + v->offset[i];
        if (!isfinite(x)) {
            p->nonfinite += 1;
            continue;
        }
        const size_t b = acc_index(p, v, x);
        acc.density[b] += 1.0;
        if (!v->hard_core || n < 2) continue;
        const double gap = ring_gap(v, i);
        if (gap < min_gap) min_gap = gap;
        if (gap <= p->contact_width) {
            acc.contact[b] += 1.0; /* left rod */
            /* straight line through the gap densities of 4 sub-windows, value at gap 0:
             * fixed least-squares weights for sub-window centres (k + 1/2) h. Gaps closed
             * exactly by a merge of the step's regression are an atom, not a density, and
             * are left out (under reflect an O(dt) artefact of pushes into a third rod;
             * docs/validation.md section 14) */
            static const double w[4] = {0.85, 0.45, 0.05, -0.35};
            const double h = 0.25 * p->contact_width;
            int k = (int)(gap / h);
            k = k < 0 ? 0 : k > 3 ? 3 : k;
            if (gap > closed_tol) acc.extrap[b] += w[k] / h;
        }
    }
    p->min_gap = min_gap;
    if (v->hard_core && v->y && n > 1) sample_impulses(p, v, acc.impulse);
    hsbd_blocks_end_sample(p->density);
    hsbd_blocks_end_sample(p->contact);
    hsbd_blocks_end_sample(p->impulse);
    hsbd_blocks_end_sample(p->extrap);
    return HSBD_OK;
}

size_t hsbd_profile_bins(const hsbd_profile *p) {
    return p->nbins;
}

/* counts per sample -> density: the L/period periods are folded onto one, Eq. (25) */
static void finish(const hsbd_profile *p, hsbd_blocks *b, double width, double *x, double *val,
                   double *err, int fixed_total) {
    if (fixed_total && p->nsegments)
        hsbd_blocks_result_shape(b, val, err);
    else
        hsbd_blocks_result(b, val, err);
    /* spatial blocks average over segments of periods/nsegments periods each */
    const double periods = p->nsegments ? p->periods / (double)p->nsegments : p->periods;
    const double norm = 1.0 / (width * periods);
    for (size_t k = 0; k < p->nbins; ++k) {
        x[k] = ((double)k + 0.5) * p->bin_width;
        val[k] *= norm;
        err[k] *= norm;
    }
}

void hsbd_profile_density(const hsbd_profile *p, double *x, double *rho, double *err) {
    /* N is fixed: in spatial blocks only the shape scatters (segments trade rods) */
    finish(p, p->density, p->bin_width, x, rho, err, 1);
}

void hsbd_profile_contact_window(const hsbd_profile *p, double *x, double *rho2, double *err) {
    finish(p, p->contact, p->bin_width * p->contact_width, x, rho2, err, 0);
}

void hsbd_profile_contact_extrapolated(const hsbd_profile *p, double *x, double *rho2,
                                       double *err) {
    finish(p, p->extrap, p->bin_width, x, rho2, err, 0);
}

void hsbd_profile_contact(const hsbd_profile *p, double *x, double *rho2, double *err) {
    finish(p, p->impulse, p->bin_width, x, rho2, err, 0);
}

size_t hsbd_profile_blocks(const hsbd_profile *p) {
    return p->nblocks;
}

/* per-block counts per sample -> densities, normalised as in finish() */
static void finish_blocks(const hsbd_profile *p, const hsbd_blocks *b, double width, int shape,
                          double *out) {
    hsbd_blocks_block_means(b, shape, out);
    const double periods = p->nsegments ? p->periods / (double)p->nsegments : p->periods;
    const double norm = 1.0 / (width * periods);
    for (size_t j = 0; j < p->nblocks * p->nbins; ++j)
        out[j] *= norm;
}

void hsbd_profile_density_blocks(const hsbd_profile *p, double *out) {
    finish_blocks(p, p->density, p->bin_width, p->nsegments > 0, out);
}

void hsbd_profile_contact_blocks(const hsbd_profile *p, double *out) {
    finish_blocks(p, p->impulse, p->bin_width, 0, out);
}

void hsbd_profile_contact_extrapolated_blocks(const hsbd_profile *p, double *out) {
    finish_blocks(p, p->extrap, p->bin_width, 0, out);
}

uint64_t hsbd_profile_nonfinite(const hsbd_profile *p) {
    return p->nonfinite;
}

double hsbd_profile_min_gap(const hsbd_profile *p) {
    return p->min_gap;
}

/* ---- checkpoints ---- */
void hsbd_profile_save(const hsbd_profile *p, hsbd_writer *w) {
    hsbd_put_tag(w, "profile");
    hsbd_put_u64(w, p->nbins);
    hsbd_put_f64(w, p->periods);
    hsbd_put_f64(w, p->min_gap);
    hsbd_put_u64(w, p->nonfinite);
    const hsbd_blocks *acc[] = {p->density, p->contact, p->impulse, p->extrap};
    for (int k = 0; k < 4; ++k)
        hsbd_blocks_save(acc[k], w);
}

int hsbd_profile_load(hsbd_profile *p, hsbd_reader *r) {
    if (hsbd_get_tag(r, "profile") || hsbd_get_count(r, p->nbins, "profile bins") ||
        hsbd_get_f64(r, &p->periods) || hsbd_get_f64(r, &p->min_gap) ||
        hsbd_get_u64(r, &p->nonfinite))
        return -1;
    hsbd_blocks *acc[] = {p->density, p->contact, p->impulse, p->extrap};
    for (int k = 0; k < 4; ++k)
        if (hsbd_blocks_load(acc[k], r)) return -1;
    p->nblocks = hsbd_blocks_count(p->density); /* more after an extension */
    return 0;
}
