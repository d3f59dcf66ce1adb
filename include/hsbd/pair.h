/* Continuous pair forces between rods (Antonov Eqs. 27-28) and Baxter's sticky contact in
 * its power-law representation (Eqs. 29-32), as small function tables like the fields.
 *
 * A term gives the force f(r) (energy / length) that the left rod of a pair exerts on
 * the right one at centre distance r >= sigma (positive: repulsive; the left rod feels
 * -f), and the pair potential V(r) (energy) with f = -dV/dr. Energies are absolute, in
 * the units of the thermal energy kT the integrator is given (its mobility is D / kT), so
 * only V / kT matters. Beyond `range` both vanish, and every term is continuous there
 * (the BCD step needs continuous forces, Sec. IV). */
#ifndef HSBD_PAIR_H
#define HSBD_PAIR_H

#include "hsbd/export.h"
#include <stddef.h>

#include "hsbd/error.h"

enum { HSBD_MAX_PAIR_TERMS = 4, HSBD_PAIR_PARAMS = 6 };

typedef struct hsbd_pair_term hsbd_pair_term;
typedef struct hsbd_table hsbd_table;

typedef struct hsbd_pair_ops {
    const char *name;
    double (*force)(const hsbd_pair_term *term, double r);
    double (*potential)(const hsbd_pair_term *term, double r);
} hsbd_pair_ops;

struct hsbd_pair_term {
    const hsbd_pair_ops *ops;
    double range;               /* centre distance beyond which f = V = 0 */
    double p[HSBD_PAIR_PARAMS]; /* meaning set by the constructor */
    const hsbd_table *table;    /* tabulated terms: owned by the caller, must outlive use */
};

typedef struct hsbd_pair {
    size_t nterms;
    hsbd_pair_term term[HSBD_MAX_PAIR_TERMS];
} hsbd_pair;

/* Baxter's sticky contact of strength gamma represented by delta_eps of order p > 1 and
 * width epsilon > 0 (Eq. 31): V = -kT ln(1 + gamma delta_eps(r - sigma)), force Eq. (32)
 * times kT. Baxter's model is defined by its Boltzmann factor 1 + gamma delta_eps, which
 * does not depend on temperature: the term needs the kT of the system it acts in. */
HSBD_API hsbd_pair_term hsbd_pair_sticky(double sigma, double gamma, double order, double epsilon,
                                         double kT);
/* Screened Coulomb: V(r) = A sigma exp(-kappa (r - sigma)) / r (A: value at contact),
 * force-shifted to vanish continuously at the cutoff: f(r) - f(rc), V(r) - V(rc) + (r - rc) f(rc).
 */
HSBD_API hsbd_pair_term hsbd_pair_yukawa(double sigma, double contact_value, double kappa,
                                         double cutoff);
/* Lennard-Jones well (depth: energy) with its minimum at contact, attractive outside the hard core:
 * V(r) = depth ((sigma/r)^12 - 2 (sigma/r)^6), force-shifted at the cutoff like Yukawa. */
HSBD_API hsbd_pair_term hsbd_pair_lj(double sigma, double depth, double cutoff);
/* Tabulated force f(r) (natural cubic spline through the table's points; zero beyond its
 * last r, where the table must reach zero force); V(r) = integral of f from r to the end. */
HSBD_API hsbd_pair_term hsbd_pair_table(const hsbd_table *force_table);

/* Append a term; returns 0, or -1 when the list is full. */
HSBD_API int hsbd_pair_add(hsbd_pair *pair, hsbd_pair_term term);
/* Largest range of the terms (0 without terms). */
HSBD_API double hsbd_pair_range(const hsbd_pair *pair);
HSBD_API double hsbd_pair_force(const hsbd_pair *pair, double r);
HSBD_API double hsbd_pair_potential(const hsbd_pair *pair, double r);
/* max |f(r)| over [r_lo, r_hi] (dense sampling plus golden-section refinement). */
HSBD_API double hsbd_pair_max_force(const hsbd_pair *pair, double r_lo, double r_hi);
/* max |V''(r)| = max |f'(r)| over [r_lo, r_hi] (central differences of dense samples). */
HSBD_API double hsbd_pair_max_curvature(const hsbd_pair *pair, double r_lo, double r_hi);

#endif
