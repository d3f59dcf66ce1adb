#include "hsbd/field.h"

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

int hsbd_field_add(hsbd_field *field, hsbd_field_term term) {
    if (field->nterms >= HSBD_MAX_FIELD_TERMS) return -1;
    field->term[field->nterms++] = term;
    return 0;
}
