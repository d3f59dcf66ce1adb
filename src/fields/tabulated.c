/* Tabulated external potential or force (natural cubic spline of a file's points). */
#include <math.h>

#include "hsbd/field.h"
#include "hsbd/table.h"

enum { TAB_KIND, TAB_PERIOD };

static double reduce(const hsbd_field_term *t, double x) {
    const double period = t->p[TAB_PERIOD];
    return period > 0 ? x - period * floor(x / period) : x;
}

/* potential table: f = -U'(x); force table: f(x) (kT/length) */
static void table_add_force(const hsbd_field_term *t, size_t n, const double *restrict x,
                            double *restrict f) {
    const int force_table = t->p[TAB_KIND] == HSBD_TABLE_FORCE;
    for (size_t i = 0; i < n; ++i) {
        const double xr = reduce(t, x[i]);
        f[i] += force_table ? hsbd_table_value(t->table, xr) : -hsbd_table_derivative(t->table, xr);
    }
}

static double table_potential(const hsbd_field_term *t, double x) {
    const double xr = reduce(t, x);
    return t->p[TAB_KIND] == HSBD_TABLE_FORCE ? -hsbd_table_integral(t->table, xr)
                                              : hsbd_table_value(t->table, xr);
}

/* |f'| sampled at 16 points per interval of the table (central differences) */
static double table_max_curvature(const hsbd_field_term *t) {
    const double x0 = hsbd_table_x_min(t->table), x1 = hsbd_table_x_max(t->table);
    const size_t m = 16 * hsbd_table_size(t->table);
    const double h = (x1 - x0) / (double)m;
    double best = 0.0, f_prev = 0.0;
    for (size_t k = 0; k <= m; ++k) {
        double x = x0 + h * (double)k, f = 0.0;
        table_add_force(t, 1, &x, &f);
        if (k > 0) best = fmax(best, fabs(f - f_prev) / h);
        f_prev = f;
    }
    return best;
}

static const hsbd_field_ops table_ops = {.name = "table",
                                         .strength = 0,
                                         .position = 0,
                                         .add_force = table_add_force,
                                         .potential = table_potential,
                                         .max_curvature = table_max_curvature};

hsbd_field_term hsbd_field_table(const hsbd_table *table, int kind, double period) {
    hsbd_field_term t = {.ops = &table_ops, .table = table};
    t.p[TAB_KIND] = kind;
    t.p[TAB_PERIOD] = period;
    return t;
}
