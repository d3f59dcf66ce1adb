/* External force fields as small function tables shared by all integrators.
 *
 * A field adds its force (energy / length) at n positions to an output array; the
 * integrators only see `add_force`, so new fields never touch them. Forces add up, so a
 * sum of fields is a list of terms. Energies are absolute, in the units of the thermal
 * energy kT the integrator is given (mobility D / kT): only U / kT matters. */
#ifndef HSBD_FIELD_H
#define HSBD_FIELD_H

#include "hsbd/export.h"
#include <stddef.h>

enum { HSBD_MAX_FIELD_TERMS = 6, HSBD_FIELD_PARAMS = 4 };

typedef struct hsbd_field_term hsbd_field_term;
typedef struct hsbd_table hsbd_table;

typedef struct hsbd_field_ops {
    const char *name;
    /* f[i] += force at x[i], for i < n */
    void (*add_force)(const hsbd_field_term *term, size_t n, const double *restrict x,
                      double *restrict f);
    /* potential energy at x (energy); the force is its negative derivative */
    double (*potential)(const hsbd_field_term *term, double x);
} hsbd_field_ops;

struct hsbd_field_term {
    const hsbd_field_ops *ops;
    double p[HSBD_FIELD_PARAMS]; /* meaning set by the constructor */
    const hsbd_table *table;     /* tabulated terms: owned by the caller, must outlive use */
};

typedef struct hsbd_field {
    size_t nterms;
    hsbd_field_term term[HSBD_MAX_FIELD_TERMS];
} hsbd_field;

/* U(x) = (U0/2) cos(2 pi x / lambda), Antonov Eq. (21); force (pi U0/lambda) sin(2 pi x/lambda). */
HSBD_API hsbd_field_term hsbd_field_cosine(double amplitude_u0, double wavelength);
/* constant force f: the linear potential U(x) = -f x (gravity: f = -m_b g, pointing to x = 0) */
HSBD_API hsbd_field_term hsbd_field_tilt(double force);
/* harmonic trap U(x) = (k/2) d^2 with d = x - center; period > 0 (a ring of that length):
 * d is the nearest image, in [-period/2, period/2); period = 0: no images (walls). */
HSBD_API hsbd_field_term hsbd_field_harmonic(double stiffness, double center, double period);
/* Tabulated potential U(x) (kind 0) or force f(x) (kind 1): the table's cubic spline; a
 * force table's potential is minus its integral from the table's first x. period > 0: x
 * is taken modulo period; the table must then span [0, period] and should be made
 * periodic (hsbd_table_make_periodic), else the force jumps at x = 0 = period. */
enum { HSBD_TABLE_POTENTIAL = 0, HSBD_TABLE_FORCE = 1 };
HSBD_API hsbd_field_term hsbd_field_table(const hsbd_table *table, int kind, double period);

/* Append a term; returns 0, or -1 when the field already has HSBD_MAX_FIELD_TERMS. */
HSBD_API int hsbd_field_add(hsbd_field *field, hsbd_field_term term);

/* f[i] = total force at x[i] (overwrites f). */
HSBD_API void hsbd_field_force(const hsbd_field *field, size_t n, const double *restrict x,
                               double *restrict f);
HSBD_API double hsbd_field_potential(const hsbd_field *field, double x);

#endif
