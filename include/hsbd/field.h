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
    /* largest |U''(x)| of the term as its parameters stand (energy / length^2); NULL:
     * unknown (left out of hsbd_field_max_curvature) */
    double (*max_curvature)(const hsbd_field_term *term);
    /* 1 + the index into p[] of the parameter a drive may change, 0: none (so terms of
     * older code have no drivable parameter): the strength (tilt force, cosine amplitude
     * U0, harmonic stiffness) and the position (cosine shift, harmonic centre) */
    int strength, position;
} hsbd_field_ops;

/* A drive changes one parameter of a term in time:
 *   p(t) = p(0) + velocity t + amplitude w(omega t + phase),
 * w(s) = cos s (HSBD_WAVE_COSINE) or the square wave sign(cos s), +1 where cos s = 0
 * (HSBD_WAVE_SQUARE); wave = HSBD_WAVE_NONE with velocity 0: a static term. */
enum hsbd_wave { HSBD_WAVE_NONE = 0, HSBD_WAVE_COSINE = 1, HSBD_WAVE_SQUARE = 2 };
typedef struct hsbd_drive {
    int param; /* index into p[] (ops->strength - 1 or ops->position - 1) */
    int wave;  /* enum hsbd_wave */
    double amplitude, omega, phase, velocity;
} hsbd_drive;
struct hsbd_field_term {
    const hsbd_field_ops *ops;
    double p[HSBD_FIELD_PARAMS]; /* meaning set by the constructor */
    const hsbd_table *table;     /* tabulated terms: owned by the caller, must outlive use */
    hsbd_drive drive;            /* zero: static */
};

typedef struct hsbd_field {
    size_t nterms;
    hsbd_field_term term[HSBD_MAX_FIELD_TERMS];
} hsbd_field;

/* How an integrator takes the field's force into a step (the parameter field_step of
 * hsbd_rods_params and hsbd_spheres_params). Zero, Euler, is the step of programs written
 * before the choice existed; the CLI's default is run.field_step (docs/config.md).
 * Heun's stationary density is right to O(dt^2) where Euler's is off by O(dt)
 * (docs/algorithms.md, "The time step in a field"). */
enum hsbd_field_step {
    HSBD_FIELD_STEP_EULER = 0, /* the force at the step's start, F(x) dt (Antonov Eq. 10) */
    HSBD_FIELD_STEP_HEUN = 1   /* the mean of F(x) at the start (time t) and F(x_p) at the
                                  end point x_p of a free Euler predictor with the step's own
                                  noise (time t + dt): one force evaluation more per step */
};

/* U(x) = (U0/2) cos(2 pi (x - s) / lambda), Antonov Eq. (21) shifted by s (0 from the
 * constructor; a travelling wave moves it); force (pi U0/lambda) sin(2 pi (x - s)/lambda). */
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
/* the potential of the terms as constructed (a drive's time dependence left out) */
HSBD_API double hsbd_field_potential(const hsbd_field *field, double x);
/* An upper bound of max |U''| (energy / length^2): the sum over the terms of each one's
 * largest curvature, a driven strength at its largest magnitude |p(0)| + |amplitude| (a
 * drive's steady velocity left out). It sets the field's time scale 1 / (mu max|U''|). */
HSBD_API double hsbd_field_max_curvature(const hsbd_field *field);

/* ---- drives (time-dependent terms) ---- */
enum hsbd_drive_target { HSBD_DRIVE_STRENGTH = 0, HSBD_DRIVE_POSITION = 1 };
/* Give the term a drive of its strength or position (p(0) is the constructor's value):
 * rocking tilt F(t) = F0 + F1 cos(omega t) (strength, cosine wave), its square wave, a
 * flashing or modulated amplitude U0(t) (strength), a travelling cosine (position,
 * velocity v), a dragged (velocity) or oscillating (cosine wave) trap centre. Returns 0,
 * or -1 when the term has no such parameter (a tilt has no position, a table neither), the
 * wave is unknown or a number is not finite or omega < 0. */
HSBD_API int hsbd_field_term_drive(hsbd_field_term *term, int target, int wave, double amplitude,
                                   double omega, double phase, double velocity);
/* Whether any term is driven. */
HSBD_API int hsbd_field_is_driven(const hsbd_field *field);
/* The field at time t: `field` itself when nothing is driven, else `now` filled with every
 * driven parameter evaluated at t (static terms copied). The integrators call it once per
 * step with the time at the step's start, so the field is frozen over the step
 * (docs/theory.md: the error this makes). */
HSBD_API const hsbd_field *hsbd_field_at(const hsbd_field *field, double t, hsbd_field *now);
/* The waveform w(omega t + phase) of a drive (1 for HSBD_WAVE_NONE). */
HSBD_API double hsbd_drive_wave(const hsbd_drive *drive, double t);

#endif
