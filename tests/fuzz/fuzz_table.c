/* Fuzz target: a table file (field.table, pair.table: 'x value' lines), read, its spline
 * evaluated across and beyond its range, then made periodic (as a field table on a ring)
 * and evaluated again. */
#include "fuzz.h"

#include <math.h>

#include "hsbd/field.h"
#include "hsbd/pair.h"
#include "hsbd/table.h"

/* The spline, a field of it (potential and force; `period` 0: walls) and a pair force. */
static void evaluate(const hsbd_table *t, double period) {
    const double lo = hsbd_table_x_min(t), hi = hsbd_table_x_max(t);
    hsbd_field field = {0};
    hsbd_pair pair = {0};
    hsbd_field_add(&field, hsbd_field_table(t, HSBD_TABLE_POTENTIAL, period));
    hsbd_field_add(&field, hsbd_field_table(t, HSBD_TABLE_FORCE, period));
    hsbd_pair_add(&pair, hsbd_pair_table(t));
    double x[21], f[21];
    volatile double sum = hsbd_table_last_value(t) + hsbd_pair_range(&pair);
    for (int k = -2; k <= 18; ++k) {
        x[k + 2] = lo + (hi - lo) * k / 16.0;
        sum += hsbd_table_value(t, x[k + 2]) + hsbd_table_derivative(t, x[k + 2]) +
               hsbd_table_integral(t, x[k + 2]) + hsbd_field_potential(&field, x[k + 2]) +
               hsbd_pair_force(&pair, x[k + 2]) + hsbd_pair_potential(&pair, x[k + 2]);
    }
    hsbd_field_force(&field, 21, x, f);
    sum += f[0] + hsbd_pair_max_force(&pair, lo, hi);
    (void)sum;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    FILE *in = fuzz_stream(data, size);
    if (!in) abort();
    hsbd_error err;
    hsbd_table *t = hsbd_table_read(in, "fuzz.tab", &err);
    fclose(in);
    if (!t) {
        fuzz_expect_refusal(&err, "fuzz.tab");
        return 0;
    }
    evaluate(t, 0);
    if (hsbd_table_make_periodic(t, "field.table", &err) == HSBD_OK)
        evaluate(t, hsbd_table_x_max(t) - hsbd_table_x_min(t));
    else
        fuzz_expect_refusal(&err, "field.table");
    hsbd_table_free(t);
    return 0;
}
