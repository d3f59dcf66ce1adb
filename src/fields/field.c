#include "hsbd/field.h"

#include <math.h>
#include <string.h>

void hsbd_field_force(const hsbd_field *field, size_t n, const double *restrict x,
                      double *restrict f) {
    memset(f, 0, n * sizeof *f);
    for (size_t k = 0; k < field->nterms; ++k)
        field->term[k].ops->add_force(&field->term[k], n, x, f);
}

double hsbd_field_potential(const hsbd_field *field, double x) {
    double u = 0.0;
    for (size_t k = 0; k < field->nterms; ++k)
        u += field->term[k].ops->potential(&field->term[k], x);
    return u;
}

double hsbd_field_max_curvature(const hsbd_field *field) {
    double sum = 0.0;
    for (size_t k = 0; k < field->nterms; ++k) {
        hsbd_field_term t = field->term[k];
        const hsbd_drive *d = &t.drive;
        if (d->wave != HSBD_WAVE_NONE && d->param == t.ops->strength - 1)
            t.p[d->param] = fabs(t.p[d->param]) + fabs(d->amplitude);
        sum += t.ops->max_curvature ? t.ops->max_curvature(&t) : 0.0; /* a user's term */
    }
    return sum;
}

int hsbd_field_add(hsbd_field *field, hsbd_field_term term) {
    if (field->nterms >= HSBD_MAX_FIELD_TERMS) return -1;
    field->term[field->nterms++] = term;
    return 0;
}

/* ---- drives ---- */

int hsbd_field_term_drive(hsbd_field_term *term, int target, int wave, double amplitude,
                          double omega, double phase, double velocity) {
    const int param = target == HSBD_DRIVE_STRENGTH   ? term->ops->strength
                      : target == HSBD_DRIVE_POSITION ? term->ops->position
                                                      : 0;
    if (param <= 0 || param > HSBD_FIELD_PARAMS) return -1;
    if (wave != HSBD_WAVE_NONE && wave != HSBD_WAVE_COSINE && wave != HSBD_WAVE_SQUARE) return -1;
    if (!isfinite(amplitude) || !isfinite(omega) || !(omega >= 0) || !isfinite(phase) ||
        !isfinite(velocity))
        return -1;
    term->drive = (hsbd_drive){.param = param - 1,
                               .wave = wave,
                               .amplitude = amplitude,
                               .omega = omega,
                               .phase = phase,
                               .velocity = velocity};
    return 0;
}

static int term_is_driven(const hsbd_field_term *t) {
    return t->drive.wave != HSBD_WAVE_NONE || t->drive.velocity != 0;
}

int hsbd_field_is_driven(const hsbd_field *field) {
    for (size_t k = 0; k < field->nterms; ++k)
        if (term_is_driven(&field->term[k])) return 1;
    return 0;
}

double hsbd_drive_wave(const hsbd_drive *d, double t) {
    if (d->wave == HSBD_WAVE_NONE) return 1.0;
    const double c = cos(d->omega * t + d->phase);
    return d->wave == HSBD_WAVE_SQUARE ? (c >= 0 ? 1.0 : -1.0) : c;
}

/* p(t) = p(0) + velocity t + amplitude w(omega t + phase) */
const hsbd_field *hsbd_field_at(const hsbd_field *field, double t, hsbd_field *now) {
    if (!hsbd_field_is_driven(field)) return field;
    *now = *field;
    for (size_t k = 0; k < now->nterms; ++k) {
        hsbd_field_term *term = &now->term[k];
        const hsbd_drive *d = &term->drive;
        if (!term_is_driven(term)) continue;
        const double wave = d->wave == HSBD_WAVE_NONE ? 0.0 : d->amplitude * hsbd_drive_wave(d, t);
        term->p[d->param] += d->velocity * t + wave;
    }
    return now;
}
