/* Observers: they only read the state (hsbd_rods_view) and accumulate; error bars come
 * from block averages (the production run cut into equal consecutive blocks). */
#ifndef HSBD_OBSERVE_H
#define HSBD_OBSERVE_H

#include "hsbd/export.h"
#include <stddef.h>
#include <stdint.h>

#include "hsbd/error.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"

/* ---- block averages of a vector of per-sample quantities ---- */
typedef struct hsbd_blocks hsbd_blocks;
HSBD_API hsbd_blocks *hsbd_blocks_alloc(size_t nvalues, size_t nblocks, uint64_t nsamples_total);
HSBD_API void hsbd_blocks_free(hsbd_blocks *b);
/* Spatial blocks: each block is a part of the system (e.g. a segment of the ring) and
 * sees every sample; add values with hsbd_blocks_acc_block, close samples as usual. */
HSBD_API hsbd_blocks *hsbd_blocks_alloc_spatial(size_t nvalues, size_t nblocks);
HSBD_API double *hsbd_blocks_acc_block(hsbd_blocks *b, size_t k);
/* The accumulator of the current sample: add this sample's values into it. */
HSBD_API double *hsbd_blocks_acc(hsbd_blocks *b);
/* Close the current sample. */
HSBD_API void hsbd_blocks_end_sample(hsbd_blocks *b);
/* Mean per sample (over all samples) and its standard error from the blocks that received
 * samples: sqrt(sum_k (m_k - mean)^2 / (B (B - 1))) with m_k block k's mean, B the blocks
 * used; for blocks of equal size the standard deviation of the block means over sqrt(B).
 * A block still being filled counts with its samples so far. Returns blocks used. */
HSBD_API size_t hsbd_blocks_result(const hsbd_blocks *b, double *mean, double *err);
/* the number of blocks (sample.blocks, more after a run was extended) */
HSBD_API size_t hsbd_blocks_count(const hsbd_blocks *b);
HSBD_API uint64_t hsbd_blocks_samples(const hsbd_blocks *b);
/* The time block the next sample goes to (0 for spatial blocks). */
HSBD_API size_t hsbd_blocks_current(const hsbd_blocks *b);
/* The time block that sample number `sample` (from 0) of nsamples_total falls in. */
HSBD_API size_t hsbd_blocks_block_of(uint64_t sample, size_t nblocks, uint64_t nsamples_total);
/* As hsbd_blocks_result, but the error is that of the shape: each block's values are
 * rescaled to the common total first (for quantities whose total is fixed, like the
 * density of a fixed number of rods observed in segments of the ring), their deviations
 * taken from the overall mean (conservative: the rescaled rows' own mean would give a
 * smaller error). */
HSBD_API size_t hsbd_blocks_result_shape(const hsbd_blocks *b, double *mean, double *err);

/* Each block's mean per sample (nblocks x nvalues, row k = block k; NaN rows for blocks
 * without samples). shape: each row rescaled to the common total, as in
 * hsbd_blocks_result_shape. The rows are the independent estimates behind the errors, for
 * users who want the covariance between values. Returns nblocks. */
HSBD_API size_t hsbd_blocks_block_means(const hsbd_blocks *b, int shape, double *out);

/* ---- density profile (Eqs. 24-25) and two-particle density at contact (Eq. 26) ---- */
typedef struct hsbd_profile hsbd_profile;
/* spatial_blocks = 0: error bars from time blocks; else from that many equal segments
 * of the ring (each a whole number of periods; set up by the caller). */
HSBD_API hsbd_profile *hsbd_profile_alloc(double period, double bin_width, double contact_width,
                                          size_t nblocks, uint64_t nsamples_total, hsbd_error *err);
HSBD_API hsbd_profile *hsbd_profile_alloc_spatial(double period, double bin_width,
                                                  double contact_width, size_t nsegments,
                                                  hsbd_error *err);
HSBD_API void hsbd_profile_free(hsbd_profile *p);
/* HSBD_OK, or HSBD_ENOMEM (the sample is then not taken) */
HSBD_API int hsbd_profile_sample(hsbd_profile *p, const hsbd_rods_view *v);
HSBD_API size_t hsbd_profile_bins(const hsbd_profile *p);
/* rho(x) normalised so that its mean over a period is N/L; x = bin centre. */
HSBD_API void hsbd_profile_density(const hsbd_profile *p, double *x, double *rho, double *err);
/* rho2(x, x+sigma), x the left rod of the pair, from the contact theorem: the mean
 * contact impulse per time over kT (docs/observables.md). The default estimator. */
HSBD_API void hsbd_profile_contact(const hsbd_profile *p, double *x, double *rho2, double *err);
/* rho2(x, x+sigma) as the gap density extrapolated linearly to zero gap from four
 * sub-windows of [0, contact_width]: removes the first-order bias of a pair density
 * that varies across the window (fields); meant for contact_rule = reflect, whose gap
 * density has no layer at contact. */
HSBD_API void hsbd_profile_contact_extrapolated(const hsbd_profile *p, double *x, double *rho2,
                                                double *err);
/* rho2(x, x+sigma) from pairs with gaps in [0, contact_width] (Antonov Eq. 26). */
HSBD_API void hsbd_profile_contact_window(const hsbd_profile *p, double *x, double *rho2,
                                          double *err);
/* Per-block profiles behind the error bars (time blocks, or segments with spatial
 * blocking), normalised like the profiles above: out is nblocks x bins. Returns nblocks. */
HSBD_API size_t hsbd_profile_blocks(const hsbd_profile *p);
HSBD_API void hsbd_profile_density_blocks(const hsbd_profile *p, double *out);
HSBD_API void hsbd_profile_contact_blocks(const hsbd_profile *p, double *out);
HSBD_API void hsbd_profile_contact_extrapolated_blocks(const hsbd_profile *p, double *out);
/* Positions that were not finite in the samples (a run should stop at the first). */
HSBD_API uint64_t hsbd_profile_nonfinite(const hsbd_profile *p);
/* Smallest neighbour gap seen in the samples. */
HSBD_API double hsbd_profile_min_gap(const hsbd_profile *p);

/* ---- contact impulses of a step, and contact densities per species pair and at walls ---- */
/* The impulse each contact passed in the last step over (kT dt) (contact theorem: its
 * mean is the pair density at contact): out[i] for the gap right of rod i (i = N-1: across
 * the ring, or the right wall), out[N] the left wall; 0 for open gaps. N + 1 entries. */
HSBD_API void hsbd_contact_impulses(const hsbd_rods_view *v, double *out);
/* Between walls: the walls' entries of hsbd_contact_impulses (out[0] the left wall, its
 * out[N]; out[1] the right wall, its out[N-1]) from the chains of rods linked to them
 * only, so in time of the order of those chains; 0 on a ring. */
HSBD_API void hsbd_wall_impulses(const hsbd_rods_view *v, double out[2]);

typedef struct hsbd_contacts hsbd_contacts;
/* n rods of nspecies species (1 for a single species), block averages */
HSBD_API hsbd_contacts *hsbd_contacts_alloc(size_t n, size_t nspecies, size_t nblocks,
                                            uint64_t nsamples_total, hsbd_error *err);
HSBD_API void hsbd_contacts_free(hsbd_contacts *c);
HSBD_API void hsbd_contacts_sample(hsbd_contacts *c, const hsbd_rods_view *v);
/* Contact density of ordered pairs (species a on the left, b on the right) per length of
 * line, (1/L) int rho2_ab(x, x + sigma_ab+) dx, from the contact theorem. */
HSBD_API void hsbd_contacts_pair(const hsbd_contacts *c, size_t a, size_t b, double *val,
                                 double *err);
/* Density at contact with the left (right = 0) or right wall: the wall's force over kT. */
HSBD_API void hsbd_contacts_wall(const hsbd_contacts *c, int right, double *val, double *err);

/* ---- tagged-particle mean-squared displacement at log-spaced lags ---- */
typedef struct hsbd_msd hsbd_msd;
/* sample_dt: time between samples; max_lag: largest lag time. */
HSBD_API hsbd_msd *hsbd_msd_alloc(size_t n, double sample_dt, uint64_t nsamples_total,
                                  double max_lag, int points_per_decade, size_t nblocks,
                                  hsbd_error *err);
HSBD_API void hsbd_msd_free(hsbd_msd *m);
/* Errors from nseg contiguous groups of rods instead of time blocks (call before sampling). */
HSBD_API int hsbd_msd_set_segments(hsbd_msd *m, size_t nseg, hsbd_error *err);
/* Only these rods (indices in line order, which never changes) enter the average, e.g.
 * one species of a mixture; call before sampling. */
HSBD_API int hsbd_msd_set_members(hsbd_msd *m, size_t count, const size_t *members,
                                  hsbd_error *err);
HSBD_API void hsbd_msd_sample(hsbd_msd *m, const hsbd_rods_view *v);
/* Sample from an array of unwrapped coordinates (one per item; members index into it):
 * for d-dimensional particles allocate n = d N items, one per coordinate; the MSD per
 * particle is then d times the result. */
HSBD_API void hsbd_msd_sample_values(hsbd_msd *m, const double *values);
/* Forget every time origin: no lag spans the samples before and after this call (a new
 * independent replica starts). */
HSBD_API void hsbd_msd_restart(hsbd_msd *m);
/* Also accumulate the self-intermediate scattering function: the mean of cos(k dx) per
 * item (for coordinates: F_s(k, t) with k along the axes, averaged over them). */
HSBD_API int hsbd_msd_set_wavenumber(hsbd_msd *m, double k, hsbd_error *err);
HSBD_API void hsbd_msd_fs(const hsbd_msd *m, size_t k, double *fs, double *err);
HSBD_API size_t hsbd_msd_lags(const hsbd_msd *m);
/* lag time, MSD, its error (time blocks or rod segments) and number of origins */
HSBD_API void hsbd_msd_result(const hsbd_msd *m, size_t k, double *t, double *msd, double *err,
                              size_t *origins);

/* ---- drift: mean velocity and effective diffusion (tagged, centre of mass) ----
 * From the displacements over blocks of time (src/observe/drift.c has the estimator):
 * D_eff = lim var x(t) / 2t estimated at t = the block length, with the blocks' errors. */
typedef struct hsbd_drift hsbd_drift;
typedef struct hsbd_drift_result {
    double velocity, velocity_err; /* mean velocity of a particle */
    double d_tagged, d_tagged_err; /* var of a tagged particle's displacement / 2T */
    double d_cm, d_cm_err;         /* var of the centre of mass's displacement / 2T */
    double block_time;             /* mean block length T */
    size_t blocks;                 /* closed blocks (NaN results below 2) */
} hsbd_drift_result;
/* n tagged coordinates, nsamples_total samples cut into nblocks time blocks (as
 * hsbd_blocks_alloc; blocks of an extended run and replicas' blocks fit as there) */
HSBD_API hsbd_drift *hsbd_drift_alloc(size_t n, size_t nblocks, uint64_t nsamples_total,
                                      hsbd_error *err);
HSBD_API void hsbd_drift_free(hsbd_drift *d);
/* A sample at time t of the unwrapped positions x (n values): the first sample of a time
 * block closes the open block here and starts the next. HSBD_OK or HSBD_ENOMEM. */
HSBD_API int hsbd_drift_sample_values(hsbd_drift *d, double t, const double *x);
/* Close the open block at time t with positions x (the run's end, a replica's end). */
HSBD_API int hsbd_drift_close_values(hsbd_drift *d, double t, const double *x);
/* The same from a rods view (unwrapped positions); scratch holds n doubles. */
HSBD_API int hsbd_drift_sample(hsbd_drift *d, const hsbd_rods_view *v, double *scratch);
HSBD_API int hsbd_drift_close(hsbd_drift *d, const hsbd_rods_view *v, double *scratch);
/* The estimates; x != NULL: the open block counted as if closed at time t with positions x
 * (the run's current state; d is not changed). Allocates nothing; returns HSBD_OK. */
HSBD_API int hsbd_drift_get(const hsbd_drift *d, double t, const double *x, hsbd_drift_result *out);

/* ---- disks / spheres: radial distribution per species pair, contact values ---- */
typedef struct hsbd_gr hsbd_gr;
/* Bins of width `width` up to r_max (<= half the shortest periodic box length); contact
 * values by a quadratic fit of g over gaps in [0, fit_width). A periodic box, or walls on
 * one axis (a slab): the ideal-gas reference then follows the density sampled along that
 * axis (src/observe/gr.c), so ideal particles give g = 1 in any field; contact values need
 * one size per species there (NaN otherwise). HSBD_EINPUT with walls on more axes. */
HSBD_API hsbd_gr *hsbd_gr_alloc(const hsbd_spheres_view *v, double r_max, double width,
                                double fit_width, size_t nblocks, uint64_t nsamples_total,
                                hsbd_error *err);
/* The same with the ideal-gas reference following the density sampled along `axis` (-1:
 * none, a homogeneous periodic box): a walls axis (the only one) or a periodic axis along
 * which a field modulates the density (minimum images; the reference is exact for r below
 * half the box length minus width / 2). hsbd_gr_alloc takes the walls axis, if any. */
HSBD_API hsbd_gr *hsbd_gr_alloc_profile(const hsbd_spheres_view *v, int axis, double r_max,
                                        double width, double fit_width, size_t nblocks,
                                        uint64_t nsamples_total, hsbd_error *err);
HSBD_API void hsbd_gr_free(hsbd_gr *g);
/* Between walls only, before the first sample: count only pairs with both centres in [lo, hi)
 * along the walls axis (rounded to the reference's z bins), e.g. the middle of a slit. */
HSBD_API int hsbd_gr_set_window(hsbd_gr *g, double lo, double hi, hsbd_error *err);
/* Returns HSBD_OK, or HSBD_ENOMEM (the sample is then not taken). */
HSBD_API int hsbd_gr_sample(hsbd_gr *g, const hsbd_spheres_view *v);
HSBD_API size_t hsbd_gr_bins(const hsbd_gr *g);
/* the axis of the profile-weighted reference, or -1 (a homogeneous periodic box) */
HSBD_API int hsbd_gr_profile_axis(const hsbd_gr *g);
/* unordered species pairs a <= b: nspecies (nspecies + 1) / 2 */
HSBD_API size_t hsbd_gr_pairs(const hsbd_gr *g);
HSBD_API void hsbd_gr_pair_species(const hsbd_gr *g, size_t pair, size_t *a, size_t *b);
/* bin centres, g(r) and its block error (arrays of hsbd_gr_bins) */
HSBD_API void hsbd_gr_result(const hsbd_gr *g, size_t pair, double *r, double *gr, double *err);
/* g_ab(sigma_ab+) extrapolated to contact, with the blocks' scatter as error; with sizes
 * that vary within a species, the mean of the pairs' contact values weighted by
 * sigma_ij^d (exact for the pressure) */
HSBD_API void hsbd_gr_contact(const hsbd_gr *g, size_t pair, double *value, double *err);
/* C_ab of the virial route Z = 1 + sum over pairs C_ab g_ab(sigma_ab+): the sum over the
 * pairs of species a, b of S_d sigma_ij^d / (V d N), S_d = 4 pi (3D) or 2 pi (2D); NaN
 * along a profile axis (no homogeneous pressure) */
HSBD_API double hsbd_gr_contact_weight(const hsbd_gr *g, size_t pair);

/* ---- disks / spheres between walls or in a field: profiles along one axis, wall contacts ---- */
typedef struct hsbd_slab hsbd_slab;
/* The number density along `axis` per species in bins of about bin_width (rounded so that
 * they fill the period), folded into `period` (a divisor of the box length; the length
 * between walls), and, when the axis has walls, the density of the gaps x - sigma_i/2 (and
 * L - sigma_i/2 - x) in four sub-windows of [0, contact_window) for the contact density. */
HSBD_API hsbd_slab *hsbd_slab_alloc(const hsbd_spheres_view *v, int axis, double period,
                                    double bin_width, double contact_window, size_t nblocks,
                                    uint64_t nsamples_total, hsbd_error *err);
HSBD_API void hsbd_slab_free(hsbd_slab *p);
HSBD_API void hsbd_slab_sample(hsbd_slab *p, const hsbd_spheres_view *v);
HSBD_API size_t hsbd_slab_bins(const hsbd_slab *p);
/* Bin centres, number density (per volume) of one species (or all: species < 0) and its
 * block error. */
HSBD_API void hsbd_slab_density(const hsbd_slab *p, int species, double *x, double *rho,
                                double *err);
/* Density of centres at contact with the wall at 0 (side 0) or at the box length (side
 * 1): the gap density extrapolated linearly to zero gap from the four sub-windows, block
 * by block; error from the blocks' scatter. NaN without walls on the axis. */
HSBD_API void hsbd_slab_wall_contact(const hsbd_slab *p, int side, int species, double *value,
                                     double *err);
/* the accumulators (checkpoints) */
HSBD_API hsbd_blocks *hsbd_slab_blocks(hsbd_slab *p);

/* ---- clusters: size histogram, mean size, merge events per step ---- */
typedef struct hsbd_clusters hsbd_clusters;
HSBD_API hsbd_clusters *hsbd_clusters_alloc(size_t n, size_t nblocks, uint64_t nsamples_total);
HSBD_API void hsbd_clusters_free(hsbd_clusters *c);
HSBD_API void hsbd_clusters_sample(hsbd_clusters *c, const hsbd_rods *rods,
                                   const hsbd_rods_step_stats *st);
/* fraction of clusters of size s (1 <= s <= N) over all samples */
HSBD_API double hsbd_clusters_size_fraction(const hsbd_clusters *c, size_t s);
HSBD_API size_t hsbd_clusters_max_size(const hsbd_clusters *c);
HSBD_API void hsbd_clusters_means(const hsbd_clusters *c, double *mean_size, double *mean_size_err,
                                  double *merges_per_step, double *merges_err);

/* ---- disks / spheres: the EDBD scheme's assumptions (Scala Sec. II) ---- */
/* Warned above these: Eq. 6 (mean step << diameter, the flat-wall collision), Eq. 3 (mean
 * step << mean gap, binary collisions), and collisions per particle and step. The
 * thresholds follow the measured time-step convergence (docs/spheres.md): at phi 0.3 a
 * step of 0.14 sigma (0.7 of the mean gap) still gives the exact equation of state, while
 * D_L is 0.6 % low once the step reaches half the mean gap. */
#define HSBD_SCHEME_STEP_SIGMA_MAX 0.1
#define HSBD_SCHEME_STEP_GAP_MAX   0.5
#define HSBD_SCHEME_COLLISIONS_MAX 0.5
enum { HSBD_WARNING_LEN = 256 };
typedef struct hsbd_scheme_check {
    double step_over_sigma; /* largest <|dr_i|> / sigma_i over the particles, Eq. 6 */
    double step_over_gap;   /* largest <|dr_i|> over the mean gap (Eq. 3): the nearest-neighbour
                             * distance of the densest lattice at the number density (fcc,
                             * hexagonal) minus <sigma>; NaN at or beyond close packing */
    double collisions_per_particle_step; /* as measured (NaN: not yet) */
} hsbd_scheme_check;
/* From the view's diameters and D (<|dr_i|> = E|N_d| sqrt(2 D_i dt), plus v0_i dt for an
 * active particle) and a measured collision rate (NaN when not yet measured). */
HSBD_API void hsbd_scheme_check_compute(const hsbd_spheres_view *v,
                                        double collisions_per_particle_step,
                                        hsbd_scheme_check *out);
/* Up to max messages for the criteria beyond their thresholds; returns their number. */
HSBD_API int hsbd_scheme_check_warnings(const hsbd_scheme_check *c, char (*msg)[HSBD_WARNING_LEN],
                                        int max);

/* The long-time diffusion coefficient D_L from an MSD of d-dimensional coordinates: the
 * slope between its largest lag (with at least two origins) and a tenth of it, over 2 d;
 * NaN when there are too few lags. */
HSBD_API void hsbd_msd_long_time_diffusion(const hsbd_msd *m, int dimension, double *dl,
                                           double *err);
/* the two lags t0 < t1 of that slope (NaN when there are too few lags): the first order in
 * density of what it measures at finite lags is hsbd_hs_msd_slope_ratio */
HSBD_API void hsbd_msd_long_time_lags(const hsbd_msd *m, double *t0, double *t1);

/* Size classes: per species HSBD_SIZE_CLASSES bins of its diameters (one class when
 * monodisperse), each with its members' mean diameter and number fraction of all
 * particles; the equations of state of mixtures are evaluated over them. */
enum { HSBD_SIZE_CLASSES = 64, HSBD_SIZE_CLASS_SPECIES = 16 };
typedef struct hsbd_size_classes {
    size_t n, first[HSBD_SIZE_CLASS_SPECIES + 1]; /* species k: first[k] .. first[k+1] */
    double x[HSBD_SIZE_CLASS_SPECIES * HSBD_SIZE_CLASSES];
    double sigma[HSBD_SIZE_CLASS_SPECIES * HSBD_SIZE_CLASSES];
    int polydisperse;
} hsbd_size_classes;
HSBD_API void hsbd_size_classes_build(const hsbd_spheres_view *v, size_t nspecies,
                                      hsbd_size_classes *c);
/* BMCSL's g_ab(sigma_ab+) (3D) over the classes of species a and b at number density rho,
 * weighted by x x' sigma^3 as the simulated contact value is */
HSBD_API double hsbd_size_classes_bmcsl_contact(const hsbd_size_classes *c, double rho, size_t a,
                                                size_t b);

#endif
