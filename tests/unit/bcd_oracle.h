/* Literal Brownian cluster dynamics (Antonov Sec. III B), the test oracle: recursive
 * largest-jump fragmentation, then time-ordered perfectly inelastic mergers, Eqs.
 * (13)-(19), generalised to per-rod mobilities (friction-weighted velocities). */
#ifndef HSBD_BCD_ORACLE_H
#define HSBD_BCD_ORACLE_H

#include <stddef.h>

struct hsbd_rods_params;

/* Fragmentation of one cluster with velocities v_i = mob_i F_i: writes the subcluster
 * sizes to sizes[] and returns their number. */
size_t oracle_fragment(size_t n, const double *force, const double *mob, size_t *sizes);

/* One step of length dt on a ring of length L: x in ring order (x_{n-1} < x_0 + L),
 * force = total forces F_i (Eq. 11), mob = mobilities. Gaps <= contact_tol count as
 * contact at the start. Returns the number of merge events. */
size_t oracle_step(size_t n, double *x, const double *force, const double *mob, double sigma,
                   double L, double dt, double contact_tol);

/* The same for rods of lengths sig[i] (contact distance (sig_i + sig_j)/2) on a ring, or
 * between hard walls at 0 and L (walls != 0; x_0 >= sig_0/2, x_{n-1} <= L - sig_{n-1}/2):
 * a wall is an immovable cluster of infinite friction; fragments pressed into it at the
 * start stay, and clusters reaching it stop. Returns the number of merge events. */
size_t oracle_step_general(size_t n, double *x, const double *force, const double *mob,
                           const double *sig, double L, int walls, double dt, double contact_tol);

/* The library's rods (par: one species on a ring, sticky rule) against oracle_step fed with
 * the same total forces, Eq. (11) (the noise from the seed, the field at each step's start
 * time, driven or not), over `steps` consecutive steps from the field-free equilibrium
 * sample: the largest deviation of a position (NAN when the rods cannot be allocated). */
double oracle_library_deviation(const struct hsbd_rods_params *par, int steps);

#endif
