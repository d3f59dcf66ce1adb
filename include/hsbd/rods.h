/* Brownian cluster dynamics (BCD) of hard rods on a periodic line or between hard walls
 * (Antonov et al. 2022), one species or a mixture.
 *
 * State: contact-offset coordinates z_i = x_i - offset_i with offset_i the sum of
 * (sigma_k + sigma_{k+1})/2 over k < i (plus sigma_0/2 between walls), kept in order
 * (z_0 <= ... <= z_{N-1} <= z_0 + L - sum sigma on a ring, 0 <= z_0, z_{N-1} <= L - sum
 * sigma between walls); touching rods have equal z. A step draws the free end points
 * y_i = z_i + mu_i F_i dt (F_i: field and pair forces plus the Brownian force, Eq. 11)
 * and replaces z by the isotonic regression of y with weights 1/mu_i (frictions), on the
 * ring or on the line clamped to the walls: exactly the fragmentation (Eqs. 4-5) followed
 * by all time-ordered perfectly inelastic, friction-weighted mergers (Eqs. 13-19), a wall
 * acting as a cluster of infinite friction. See docs/algorithms.md. */
#ifndef HSBD_RODS_H
#define HSBD_RODS_H

#include "hsbd/export.h"
#include <stddef.h>
#include <stdint.h>

#include "hsbd/error.h"
#include "hsbd/field.h"
#include "hsbd/pair.h"

/* How pairs that reach contact within a step are treated. The default (0) is the rule
 * the CLI uses too. */
enum hsbd_contact_rule {
    HSBD_CONTACT_REFLECT = 0, /* first each gap's Brownian bridge minimum is drawn and a
                                 crossing reflects the gap (exact for an isolated pair,
                                 any dt and constant force, docs/theory.md); then the
                                 same regression resolves what still overlaps */
    HSBD_CONTACT_STICKY = 1   /* the paper's BCD: overlapping free end points merge
                                 (perfectly inelastic); contacts crossed and left within
                                 the step are missed: an O(sqrt(dt)) layer at contact */
};

enum hsbd_rods_boundary {
    HSBD_RODS_PERIODIC = 0, /* a ring of length L */
    HSBD_RODS_WALLS = 1     /* hard walls at 0 and L: centres in [sigma_i/2, L - sigma_i/2] */
};

typedef struct hsbd_rods_params {
    size_t n;         /* number of rods N */
    double length;    /* ring length L */
    double sigma;     /* rod length */
    double diffusion; /* D (length^2 / time) */
    double kT;        /* thermal energy; mobility mu = D / kT */
    double dt;        /* time step */
    uint64_t seed;
    int hard_core;    /* 1: hard rods (BCD); 0: free particles (the free-particle bound) */
    int contact_rule; /* enum hsbd_contact_rule */
    hsbd_field field;
    hsbd_pair pair; /* pair forces between rods within range (Eq. 28); needs the hard core */
    int boundary;   /* enum hsbd_rods_boundary */
    /* Mixtures (nspecies >= 1 with the arrays set; nspecies = 0: every rod has sigma and
     * diffusion): species[i] < nspecies of rod i, in the order of the positions given to
     * hsbd_rods_set_positions, or the order along the line for hsbd_rods_init_equilibrium;
     * species_sigma (>= 0) and species_diffusion (> 0) per species. Copied at alloc. */
    size_t nspecies;
    const int *species;
    const double *species_sigma, *species_diffusion;
    /* threads for the step (noise, field, pair forces, contact pushes, the isotonic
     * regression, the fragmentation statistics); <= 1: one. The results do not depend on it
     * (docs/scaling.md) */
    int threads;
    /* enum hsbd_field_step: how the field's force enters the free end points (0: Euler;
     * Heun: the field at the start and at a free predictor's end point, averaged; the pair
     * forces stay at the step's start either way) */
    int field_step;
} hsbd_rods_params;

/* What happened inside one step (filled only when asked for: it costs a pass). */
typedef struct hsbd_rods_step_stats {
    size_t clusters_start; /* clusters of touching rods at the start of the step */
    size_t fragments;      /* moving clusters after fragmentation, Eqs. (4)-(5) */
    size_t clusters_end;   /* clusters at the end; merge events = fragments - clusters_end */
} hsbd_rods_step_stats;

/* Read-only view of the state for observers. Unwrapped position of rod i:
 * z[i] + offset[i] + unwrap; position on the ring: that value modulo length. */
typedef struct hsbd_rods_view {
    size_t n;
    double length, sigma, free_length; /* sigma: of species 0 in mixtures */
    int periodic;                      /* 0: hard walls at 0 and L */
    const double *z, *offset;
    /* mixtures (else NULL / 0): species of each rod in line order, and per species */
    size_t nspecies;
    const int *species;
    const double *species_sigma, *species_mobility;
    /* free end points of the last step in the frame of z (hard core only; else NULL):
     * y_i - z_i = mu (J_{i-1,i} - J_{i,i+1}) with J the contact impulses of the step */
    const double *y;
    /* reflection push given to each gap in the last step, as a change of the gap: push[i]
     * for the gap right of rod i (i = N-1: to rod 0 across the ring, or to the right
     * wall), push[N] for the gap between the left wall and rod 0; NULL for the sticky rule */
    const double *push;
    double unwrap;
    double mobility, kT, dt;
    uint64_t step;
    double time;
    int hard_core;
} hsbd_rods_view;

typedef struct hsbd_rods hsbd_rods;

/* Checks the parameters (N >= 1, sum sigma < L, D > 0, kT > 0, dt > 0, pair range <= L/2
 * and pair forces only with the hard core and one species); NULL on error. */
HSBD_API hsbd_rods *hsbd_rods_alloc(const hsbd_rods_params *params, hsbd_error *err);
HSBD_API void hsbd_rods_free(hsbd_rods *rods);

/* Exact equilibrium sample of field-free hard rods in their order (uniform on
 * configuration space): N sorted uniform points in the free length shifted by the
 * offsets; on a ring the whole ring is rotated by a uniform offset. Uses the seed's
 * initial-state stream. */
HSBD_API void hsbd_rods_init_equilibrium(hsbd_rods *rods);

/* The same with an independent draw number: draw 0 is hsbd_rods_init_equilibrium; other
 * draws give independent samples of the same seed (e.g. for independent replicas). */
HSBD_API void hsbd_rods_init_equilibrium_draw(hsbd_rods *rods, uint64_t draw);

/* Positions (ring: in [0, L) or unwrapped; walls: in [sigma_i/2, L - sigma_i/2]), any
 * order; sorted along the line, a mixture's species following their rods. Refuses
 * overlaps (gap < -1e-12 sigma) and non-finite values with HSBD_EINPUT. */
HSBD_API int hsbd_rods_set_positions(hsbd_rods *rods, const double *x, hsbd_error *err);

/* Change the time step (e.g. after a coarse equilibration); dt > 0. */
HSBD_API void hsbd_rods_set_dt(hsbd_rods *rods, double dt);

/* One BCD step of length dt; stats may be NULL. Returns HSBD_OK: the step allocates
 * nothing and cannot fail (an int like hsbd_spheres_step, whose steps can). */
HSBD_API int hsbd_rods_step(hsbd_rods *rods, hsbd_rods_step_stats *stats);

/* Clusters of touching rods after the last step: count and sizes (first cluster is the
 * one containing or following rod 0). Valid for hard-core runs after a step. */
HSBD_API size_t hsbd_rods_cluster_count(const hsbd_rods *rods);
HSBD_API size_t hsbd_rods_cluster_size(const hsbd_rods *rods, size_t k);

HSBD_API hsbd_rods_view hsbd_rods_get_view(const hsbd_rods *rods);
HSBD_API const hsbd_rods_params *hsbd_rods_get_params(const hsbd_rods *rods);

/* Smallest gap between neighbours, walls included (negative: overlap), and whether all
 * coordinates are finite. Hard-core runs only. */
HSBD_API double hsbd_rods_min_gap(const hsbd_rods *rods, int *all_finite);

#endif
