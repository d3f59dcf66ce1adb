/* Exact references for hard rods: Percus' density functional (hard and Baxter-sticky)
 * in a periodic external potential, and closed forms for the homogeneous fluid. */
#ifndef HSBD_THEORY_H
#define HSBD_THEORY_H

#include "hsbd/export.h"
#include <stddef.h>

#include "hsbd/error.h"
#include "hsbd/field.h"
#include "hsbd/pair.h"

/* ---- Percus functional on one period (Antonov Eqs. 20-23, sticky: Eqs. 34a-c) ---- */
typedef struct hsbd_percus_params {
    double sigma;      /* rod length */
    double rho_mean;   /* mean density over a period (canonical normalisation, Eq. 22) */
    double amplitude;  /* U0 of U(x) = (U0/2) cos(2 pi x / wavelength), in kT */
    double wavelength; /* period */
    double gamma;      /* Baxter stickiness (0: hard rods) */
    size_t points;     /* grid points per period */
    double tol;        /* convergence: max |G(rho) - rho| (default 1e-10 if 0) */
    int max_iter;      /* default 20000 if 0 */
} hsbd_percus_params;

typedef struct hsbd_percus_result {
    size_t m;
    double *x;       /* grid x_j = j h */
    double *rho;     /* equilibrium density */
    double *rho2;    /* two-particle density at contact rho2(x, x+sigma) (hard rods, Eq. 23);
                        for gamma > 0 the continuous part at contact, see docs/theory.md */
    double beta_mu;  /* chemical potential (kT units, thermal wavelength 1) */
    double residual; /* max |G(rho) - rho| at the end */
    int iterations;
} hsbd_percus_result;

/* Solve; HSBD_EINPUT for parameters out of range, HSBD_ENUMERIC when it does not converge
 * (nothing is returned then). */
HSBD_API int hsbd_percus_solve(const hsbd_percus_params *p, hsbd_percus_result *out,
                               hsbd_error *err);
HSBD_API void hsbd_percus_result_free(hsbd_percus_result *r);

/* Linear interpolation of a periodic grid function (period m h) at any x. */
HSBD_API double hsbd_periodic_interp(const double *f, size_t m, double h, double x);
/* Its average over [x - width/2, x + width/2] (64-point midpoint rule): what a histogram
 * bin centred at x with that width measures. */
HSBD_API double hsbd_periodic_bin_average(const double *f, size_t m, double h, double x,
                                          double width);

/* ---- rods with a nearest-neighbour pair potential (range <= 2 sigma), exact ---- */
/* The theory works in units of kT: pair and field terms given to it are read as U / kT
 * (build them with kT = 1, e.g. hsbd_pair_sticky(..., 1.0)). */

/* Homogeneous fluid (isobaric gap law, Takahashi): beta P and the pair density at
 * contact rho2(sigma+) = rho p(0+), p(h) the nearest-neighbour gap density. err may be NULL. */
HSBD_API int hsbd_nn_homogeneous_solve(const hsbd_pair *pair, double sigma, double rho,
                                       double *beta_p, double *contact, hsbd_error *err);
/* In the cosine field of p (p->gamma is ignored: stickiness comes as a pair term): the
 * exact profile from the transfer operator between successive rods, on p->points grid
 * points per period (second order when sigma is a multiple of the spacing); rho2 is the
 * pair density at contact rho2(x, x + sigma+); beta_mu is not computed (NaN). */
HSBD_API int hsbd_nn_transfer_solve(const hsbd_percus_params *p, const hsbd_pair *pair,
                                    hsbd_percus_result *out, hsbd_error *err);

/* ---- N hard rods between hard walls in any external field, exact and canonical ---- */
typedef struct hsbd_box_params {
    size_t n;                /* number of rods */
    double length, sigma;    /* box [0, L], rod length; N sigma < L */
    const hsbd_field *field; /* may be NULL (no field) */
    size_t points;           /* grid intervals on the free length L - N sigma */
} hsbd_box_params;

typedef struct hsbd_box_result {
    size_t nbins;
    double bin_width;
    double *rho;  /* density averaged over bin k = [k w, (k+1) w) of the box */
    double *rho2; /* pair density at contact rho2(x, x + sigma+), x the left rod, bin averages */
    double wall_left, wall_right; /* density at contact with each wall, rho(sigma/2) and
                                     rho(L - sigma/2): the wall's force over kT */
} hsbd_box_result;

/* The configuration integral in contact-offset coordinates 0 <= z_0 <= ... <= z_{N-1} <=
 * L - N sigma is a chain of nested integrals: forward and backward cumulative integrals
 * give every rod's marginal density and every neighbour pair's density at contact
 * (trapezoid rule, second order in the spacing; docs/theory.md). No finite-size
 * correction is needed: this is the canonical ensemble of the simulation. */
HSBD_API int hsbd_box_solve(const hsbd_box_params *p, double bin_width, hsbd_box_result *out,
                            hsbd_error *err);
HSBD_API void hsbd_box_result_free(hsbd_box_result *r);

/* ---- homogeneous hard rods (Tonks gas) ---- */
HSBD_API double hsbd_tonks_pressure(double rho, double sigma); /* beta P = rho / (1 - rho sigma) */
HSBD_API double hsbd_tonks_beta_mu(double rho,
                                   double sigma); /* ln(rho/(1-rho s)) + rho s/(1-rho s) */
HSBD_API double hsbd_tonks_contact(double rho,
                                   double sigma); /* rho2(x, x+sigma) = rho^2/(1-rho s) */
/* pair correlation g(r) of the infinite Tonks gas (sum over neighbour orders) */
HSBD_API double hsbd_tonks_g(double r, double rho, double sigma);
/* exact ring of N rods: contact density (N/L)(N-1)/(L - N sigma) */
HSBD_API double hsbd_tonks_ring_contact(double n, double length, double sigma);

/* ---- homogeneous sticky (Baxter) rods ---- */
HSBD_API double hsbd_sticky_pressure(double rho, double sigma, double gamma);
HSBD_API double hsbd_sticky_beta_mu(double rho, double sigma, double gamma);

/* ---- single-file diffusion: long-time tagged MSD -> ((1 - rho s)/rho) sqrt(4 D t / pi) ---- */
HSBD_API double hsbd_single_file_msd(double t, double rho, double sigma, double diffusion);
/* the exact tagged MSD at any t for the infinite system started in equilibrium (the
 * Harris / Roedenbeck-Kaerger-Hahn construction; derivation in src/theory/closed.c):
 * 2 D t at short times, the law above at long times */
HSBD_API double hsbd_single_file_msd_exact(double t, double rho, double sigma, double diffusion);
/* short-time MSD with the first collision correction (docs/validation.md section 3) */
HSBD_API double hsbd_short_time_msd(double t, double rho_gap, double diffusion);

/* Density at x >= 0 after time t of a Brownian particle (diffusion D) with constant drift
 * velocity c, started at x0 >= 0, reflected at a wall at 0: Scala Eq. 9 as corrected in
 * docs/theory.md, G(x - x0 - c t) + e^(-c x0 / D) G(x + x0 - c t)
 * - (c / 2D) e^(c x / D) erfc((x + x0 + c t) / sqrt(4 D t)), G the free Gaussian of
 * variance 2 D t. Its stationary limit for c < 0 is the barometric (|c| / D) e^(c x / D). */
HSBD_API double hsbd_reflected_drift_density(double x, double x0, double c, double diffusion,
                                             double t);
/* Its moments <x^k>, k = 0, 1, 2 (by quadrature; 0 gives the normalisation). */
HSBD_API double hsbd_reflected_drift_moment(int k, double x0, double c, double diffusion, double t);

/* ---- hard disks and spheres ---- */
/* Carnahan-Starling: contact value g(sigma+) and Z = P/(rho kT) at packing fraction phi */
HSBD_API double hsbd_hs_contact_cs(double phi);
HSBD_API double hsbd_hs_z_cs(double phi);
/* Kolafa-Labik-Malijevsky: the more accurate fluid equation of state (3D, one size) */
HSBD_API double hsbd_hs_z_klm(double phi);
HSBD_API double hsbd_hs_contact_klm(double phi);
/* Henderson's hard-disk equation of state (2D) */
HSBD_API double hsbd_hd_contact_henderson(double phi);
HSBD_API double hsbd_hd_z_henderson(double phi);
/* Hard disks from the virial series to B10 with a geometric remainder: the more accurate
 * fluid reference (Henderson is 0.14 % high at phi = 0.4); phi <= 0.45 */
HSBD_API double hsbd_hd_z_virial(double phi);
HSBD_API double hsbd_hd_contact_virial(double phi);
/* BMCSL contact value g_ab of a 3D mixture: ns species with number fractions x and
 * diameters sigma at number density rho */
HSBD_API double hsbd_hs_contact_bmcsl(size_t ns, const double *x, const double *sigma, double rho,
                                      size_t a, size_t b);
/* Z from contact values (virial route): contact is ns x ns, g_ab(sigma_ab+) */
HSBD_API double hsbd_hs_z_from_contacts(int dim, size_t ns, const double *x, const double *sigma,
                                        double rho, const double *contact);

/* ---- dynamics of Brownian hard disks / spheres without hydrodynamic interactions ----
 * A mixture at given number densities; a collision of a and b is elastic with masses 1/D
 * (Scala Sec. III): it shares the change of their normal relative displacement in the
 * proportion D_a / (D_a + D_b). Derivations in docs/theory.md. */
typedef struct hsbd_hs_mixture {
    int dimension; /* 2 (disks) or 3 (spheres) */
    size_t nspecies;
    const double *density;   /* number density of each species */
    const double *sigma;     /* diameters */
    const double *diffusion; /* D of each species (>= 0; 0: immobile obstacles) */
    const double *contact;   /* nspecies x nspecies contact values g_ab(sigma_ab+) (NULL: 1) */
} hsbd_hs_mixture;
/* Short times: MSD_a(t) = 2 d D_a t - c_a t^(3/2) + O(t^2); returns c_a (length^2 /
 * time^(3/2)), exact at any density from the contact densities rho_b g_ab(sigma_ab+).
 * share < 0: the collision rule of masses 1/D; share in [0, 1]: a rule that gives a the
 * fixed share `share` of every change of the relative displacement (0.5: equal masses),
 * the alternative the data must exclude. */
HSBD_API double hsbd_hs_msd_deficit(const hsbd_hs_mixture *m, size_t a, double share);
/* Long times, first order in the densities: D_L,a / D_a = 1 - sum_b rho_b v_d sigma_ab^d
 * D_a / ((d - 1)(D_a + D_b)), v_d the volume of the unit ball (equal D and sizes in 3D:
 * 1 - 2 phi; D_b = 0: Maxwell's dilute obstacles, 1 - phi_excluded / (d - 1)). The
 * contact values are not used (they enter at second order). NaN for D_a = 0. */
HSBD_API double hsbd_hs_long_time_ratio(const hsbd_hs_mixture *m, size_t a);
/* All times, 3D, first order in the densities: what the MSD slope between lags t0 < t1,
 * (MSD_a(t1) - MSD_a(t0)) / (2 d D_a (t1 - t0)), measures (the two-body problem solved at
 * every time, Hanna, Hess and Klein 1982); -> hsbd_hs_long_time_ratio as t0 -> infinity.
 * NaN in 2D, for D_a = 0 or t1 <= t0. */
HSBD_API double hsbd_hs_msd_slope_ratio(const hsbd_hs_mixture *m, size_t a, double t0, double t1);
/* Gamma(tau) of that solution (docs/theory.md): (4/3) tau^(3/2) / sqrt(pi) at short times,
 * tau/2 - 1/4 + O(tau^(-1/2)) at long ones */
HSBD_API double hsbd_hs_excluded_sphere_gamma(double tau);

/* ---- one overdamped Brownian particle in a tilted periodic potential (washboard) ----
 * dx = mu F(x) dt + sqrt(2 D dt) N, mu = D / kT, F = -V', V(x) = U(x) - f x with U periodic
 * (period lambda). Exact stationary results from nested integrals over one period
 * (docs/theory.md): the mean velocity (Stratonovich), the effective diffusion coefficient
 * D_eff = lim var x(t) / 2t (Reimann et al., PRL 87, 010602 (2001)) and the stationary
 * density. */
typedef struct hsbd_washboard_params {
    double diffusion;        /* D (length^2 / time) */
    double kT;               /* thermal energy, in the units of the field's energies */
    double period;           /* lambda: every term of field must have this period */
    double force;            /* the tilt f (energy / length), any sign */
    const hsbd_field *field; /* the periodic part U(x); NULL: U = 0 */
    double tol;              /* target relative error, >= 1e-14 (default 1e-10 if 0) */
    size_t points;     /* 0: automatic (grids of 64, 128, ... points until the estimate is below
                          tol); otherwise this one grid (even, >= 16), tol unused */
    size_t max_points; /* automatic grids stop here (default 2^20 if 0) */
} hsbd_washboard_params;

typedef struct hsbd_washboard_result {
    double velocity;      /* <v> = lim <x(t)> / t */
    double diffusion_eff; /* D_eff = lim var x(t) / (2 t) */
    double error;         /* estimated relative error of velocity, diffusion_eff and density: the
                             largest relative change from the grid with half the points (the error of
                             the returned grid is smaller still) */
    size_t m;             /* grid points over one period */
    double *x;            /* x_j = j lambda / m, j < m */
    double *density;      /* stationary p(x_j), int_0^lambda p dx = 1 */
} hsbd_washboard_result;

/* HSBD_EINPUT for parameters out of range or a field that is not periodic with the period
 * (a tilt term belongs in `force`), HSBD_ENUMERIC when max_points is reached before tol or
 * the integrals overflow (barriers of several hundred kT), HSBD_ENOMEM. Nothing is returned
 * on error. err may be NULL. */
HSBD_API int hsbd_washboard_solve(const hsbd_washboard_params *p, hsbd_washboard_result *out,
                                  hsbd_error *err);
HSBD_API void hsbd_washboard_result_free(hsbd_washboard_result *r);

typedef struct hsbd_washboard_rocking_result {
    double velocity; /* (1/pi) int_0^pi <v>(f0 + f1 cos theta) d theta */
    double error;    /* estimated relative error (phase quadrature and every static solve),
                        relative to the larger of |velocity| and the phase average of |<v>| */
    size_t phases;   /* phase intervals on [0, pi] */
} hsbd_washboard_rocking_result;

/* The adiabatically rocked particle: tilt F(t) = f0 + f1 cos(omega t) in the limit
 * omega -> 0, where the density follows the static one at every instant; the drift is the
 * time average of the static <v>(F(t)) over a drive period (trapezoid rule in the phase,
 * doubled until the change is below p->tol). p->force is ignored; p->points and
 * p->max_points apply to every static solve. Errors as hsbd_washboard_solve. */
HSBD_API int hsbd_washboard_rocking(const hsbd_washboard_params *p, double f0, double f1,
                                    hsbd_washboard_rocking_result *out, hsbd_error *err);

#endif
