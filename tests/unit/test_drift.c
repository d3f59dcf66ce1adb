/* The drift observer's estimator (src/observe/drift.c) on hand-made displacements: two
 * particles, samples at t = 0..5 in three time blocks of two samples, so the blocks are
 * [0, 2], [2, 4] and [4, 5] (the last closed at the end); every value worked out by hand
 * from the formulas in the file's header. Deterministic: 1e-12. */
#include <math.h>

#include "../test_util.h"
#include "hsbd/observe.h"

int main(void) {
    hsbd_error err;
    hsbd_drift *d = hsbd_drift_alloc(2, 3, 6, &err);
    CHECK(d != NULL, "alloc");
    /* positions of the two particles at t = 0..5 */
    const double x[6][2] = {{0, 10}, {1, 10}, {2, 12}, {2, 13}, {5, 14}, {6, 14}};
    for (int s = 0; s < 6; ++s)
        CHECK(hsbd_drift_sample_values(d, (double)s, x[s]) == HSBD_OK, "sample");
    hsbd_drift_result r, open;
    hsbd_drift_get(d, 5.0, x[5], &open); /* the last block counted while still open */
    CHECK(hsbd_drift_close_values(d, 5.0, x[5]) == HSBD_OK, "close");
    hsbd_drift_get(d, 0, NULL, &r);
    CHECK(r.blocks == 3 && open.blocks == 3, "three blocks: %zu, %zu", r.blocks, open.blocks);
    /* block displacements: [2, 2] over T 2, [3, 2] over T 2, [1, 0] over T 1 */
    const double v_b[3] = {1.0, 1.25, 0.5}, t_b[3] = {2, 2, 1};
    const double d1[3][2] = {{2, 2}, {3, 2}, {1, 0}};
    const double v = (v_b[0] + v_b[1] + v_b[2]) / 3;
    double sv = 0, cm[3], tag[3], mcm = 0, mtag = 0;
    for (int k = 0; k < 3; ++k) {
        sv += (v_b[k] - v) * (v_b[k] - v);
        const double m = (d1[k][0] + d1[k][1]) / 2, vt = v * t_b[k];
        cm[k] = 1.5 * (m - vt) * (m - vt) / (2 * t_b[k]);
        tag[k] = ((d1[k][0] - vt) * (d1[k][0] - vt) + (d1[k][1] - vt) * (d1[k][1] - vt)) / 2 /
                 (2 * t_b[k]);
        mcm += cm[k] / 3, mtag += tag[k] / 3;
    }
    double scm = 0, stag = 0;
    for (int k = 0; k < 3; ++k)
        scm += (cm[k] - mcm) * (cm[k] - mcm), stag += (tag[k] - mtag) * (tag[k] - mtag);
    CHECK_CLOSE(r.velocity, v, 1e-12);
    CHECK_CLOSE(r.velocity_err, sqrt(sv / 2 / 3), 1e-12);
    CHECK_CLOSE(r.d_cm, mcm, 1e-12);
    CHECK_CLOSE(r.d_cm_err, sqrt(scm / 2 / 3), 1e-12);
    CHECK_CLOSE(r.d_tagged, mtag + mcm / 3, 1e-12);
    CHECK_CLOSE(r.d_tagged_err, sqrt(stag / 2 / 3), 1e-12);
    CHECK_CLOSE(r.block_time, 5.0 / 3, 1e-12);
    CHECK(open.velocity == r.velocity && open.d_tagged == r.d_tagged && open.d_cm == r.d_cm,
          "the open block counts as the closed one");
    hsbd_drift_free(d);
    return test_finish("test_drift");
}
