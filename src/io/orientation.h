/* The orientation of an active particle, a unit vector e, as the quaternion of the
 * trajectory formats: the rotation that takes the body axis x = (1, 0, 0) to e (HOOMD's
 * active force acts along the body's x), the half-way rotation
 * q = (1 + e_x, x cross e) / |...| = (w, 0, -e_z, e_y) / |...|, about z by pi when e = -x. In
 * 2D (e_z = 0) it is the rotation by the angle theta of e about z, (cos theta/2, 0, 0,
 * sin theta/2). And back: e = q x q*. */
#ifndef HSBD_IO_ORIENTATION_H
#define HSBD_IO_ORIENTATION_H

#include <math.h>

/* q = (w, x, y, z) */
static inline void hsbd_orientation_quaternion(const double e[3], double q[4]) {
    const double w = 1 + e[0];
    if (!(w > 1e-12)) { /* e = -x (to round-off): a half turn about z */
        q[0] = q[1] = q[2] = 0, q[3] = 1;
        return;
    }
    const double norm = sqrt(w * w + e[2] * e[2] + e[1] * e[1]);
    q[0] = w / norm, q[1] = 0, q[2] = 0.0 - e[2] / norm, q[3] = e[1] / norm; /* no -0 */
}

/* e = q (1, 0, 0) q*, q = (w, x, y, z) of any length (normalised here); 0 when q = 0 */
static inline int hsbd_orientation_of_quaternion(const double q[4], double e[3]) {
    const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (!(n2 > 0) || !isfinite(n2)) return 0;
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    e[0] = (w * w + x * x - y * y - z * z) / n2;
    e[1] = 2 * (x * y + w * z) / n2;
    e[2] = 2 * (x * z - w * y) / n2;
    return 1;
}

#endif
