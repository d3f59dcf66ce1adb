/* PAVA on small hand-checked cases, weights, and ring versus line. */
#include "../test_util.h"
#include "hsbd/isotonic.h"

static void test_known_cases(void) {
    hsbd_pava *p = hsbd_pava_alloc(8);
    double fit[8];
    const double y1[] = {1, 3, 2, 4};
    CHECK(hsbd_pava_line(p, 4, y1, NULL, fit) == 3, "blocks");
    CHECK(fit[0] == 1 && fit[1] == 2.5 && fit[2] == 2.5 && fit[3] == 4, "fit %g %g %g %g", fit[0],
          fit[1], fit[2], fit[3]);
    const double y2[] = {5, 4, 3, 2, 1};
    CHECK(hsbd_pava_line(p, 5, y2, NULL, fit) == 1 && fit[0] == 3 && fit[4] == 3, "all pooled");
    const double y3[] = {0, 3}, w3[] = {3, 1};
    CHECK(hsbd_pava_line(p, 2, y3, w3, fit) == 2 && fit[1] == 3, "ordered input untouched");
    const double y4[] = {3, 0};
    CHECK(hsbd_pava_line(p, 2, y4, w3, fit) == 1, "one block");
    CHECK_CLOSE(fit[0], 9.0 / 4.0, 1e-15); /* weighted mean (3*3 + 1*0)/4 */
    CHECK(hsbd_pava_block_size(p, 0) == 2, "block size");
    hsbd_pava_free(p);
}

static void test_ring(void) {
    hsbd_pava *p = hsbd_pava_alloc(8);
    double fit[8];
    /* far from the wrap, the ring is the line */
    const double y[] = {0.1, 0.5, 0.3, 0.9};
    CHECK(hsbd_pava_ring(p, 4, y, NULL, 10.0, fit) == 3, "ring = line");
    CHECK(fit[1] == 0.4 && fit[2] == 0.4, "pooled pair");
    /* last element's image violates the first: they pool across the wrap */
    const double yw[] = {0.0, 0.5, 1.2}; /* shift 1: image of y0 sits at 1.0 < 1.2 */
    const size_t nb = hsbd_pava_ring(p, 3, yw, NULL, 1.0, fit);
    CHECK(nb == 2, "wrapping block: %zu blocks", nb);
    CHECK_CLOSE(fit[2], 1.1, 1e-15);
    CHECK_CLOSE(fit[0], 0.1, 1e-15); /* = block mean - shift */
    CHECK(fit[0] <= fit[1] && fit[1] <= fit[2] && fit[2] <= fit[0] + 1.0, "ring order");
    /* a single element never pools with its own image */
    const double y1[] = {0.7};
    CHECK(hsbd_pava_ring(p, 1, y1, NULL, 0.5, fit) == 1 && fit[0] == 0.7, "n = 1");
    hsbd_pava_free(p);
}

int main(void) {
    test_known_cases();
    test_ring();
    return test_finish("test_isotonic");
}
