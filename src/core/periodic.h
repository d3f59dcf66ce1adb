/* Small vector helpers for periodic rectangular boxes (internal): 3-component dot
 * products and the minimum-image difference along one axis. */
#ifndef HSBD_CORE_PERIODIC_H
#define HSBD_CORE_PERIODIC_H

static inline double hsbd_dot3(const double *a, const double *b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Minimum-image difference along one axis, for |d| < 1.5 box (positions wrapped into the
 * box differ by less than one box length); branch-free selects. */
static inline double hsbd_wrap_delta(double d, double box) {
    const double half = 0.5 * box;
    d = d > half ? d - box : d;
    return d < -half ? d + box : d;
}

#endif
