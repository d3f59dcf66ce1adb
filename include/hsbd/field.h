/* External force fields as small function tables shared by all integrators.
 *
 * A field adds its force (units kT / length) at n positions to an output array; the
 * integrators only see `add_force`, so new fields never touch them. Forces add up, so a
 * sum of fields is a list of terms. */
#ifndef HSBD_FIELD_H
#define HSBD_FIELD_H

#include <stddef.h>

enum { HSBD_MAX_FIELD_TERMS = 4, HSBD_FIELD_PARAMS = 4 };

typedef struct hsbd_field_term hsbd_field_term;

typedef struct hsbd_field_ops {
    const char *name;
    /* f[i] += force at x[i], for i < n */
    void (*add_force)(const hsbd_field_term *term, size_t n, const double *restrict x,
                      double *restrict f);
    /* potential energy at x (kT); the force is its negative derivative */
    double (*potential)(const hsbd_field_term *term, double x);
} hsbd_field_ops;

struct hsbd_field_term {
    const hsbd_field_ops *ops;
    double p[HSBD_FIELD_PARAMS]; /* meaning set by the constructor */
};

typedef struct hsbd_field {
    size_t nterms;
    hsbd_field_term term[HSBD_MAX_FIELD_TERMS];
} hsbd_field;

/* U(x) = (U0/2) cos(2 pi x / lambda), Antonov Eq. (21); force (pi U0/lambda) sin(2 pi x/lambda). */
hsbd_field_term hsbd_field_cosine(double amplitude_u0, double wavelength);
/* constant force f (a tilt of the potential: U(x) = -f x) */
hsbd_field_term hsbd_field_tilt(double force);

/* Append a term; returns 0, or -1 when the field already has HSBD_MAX_FIELD_TERMS. */
int hsbd_field_add(hsbd_field *field, hsbd_field_term term);

/* f[i] = total force at x[i] (overwrites f). */
void hsbd_field_force(const hsbd_field *field, size_t n, const double *restrict x,
                      double *restrict f);
double hsbd_field_potential(const hsbd_field *field, double x);

#endif
