/* Time-dependent field terms (drives): the parameters at time t, the waveforms, the refused
 * drives, a static field left alone (same pointer, same bits), and the BCD step with a
 * driven field equal to the literal oracle fed with the field evaluated at each step's
 * start time (travelling cosine, square-wave rocking tilt, sticky contact rule); the
 * field's largest curvature.
 * Deterministic: exact values or 1e-12. */
#include <math.h>
#include <string.h>

#include "../test_util.h"
#include "bcd_oracle.h"
#include "hsbd/field.h"
#include "hsbd/rods.h"
#include "hsbd/table.h"

static const double PI = 3.141592653589793;

static void test_parameters_at_time(void) {
    hsbd_field field = {0};
    hsbd_field_term tilt = hsbd_field_tilt(0.5);
    CHECK(hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, 2.0, 3.0, 0.25,
                                0.0) == 0,
          "rocking tilt accepted");
    hsbd_field_term wave = hsbd_field_cosine(4.0, 0.5);
    CHECK(hsbd_field_term_drive(&wave, HSBD_DRIVE_POSITION, HSBD_WAVE_NONE, 0, 0, 0, 0.7) == 0,
          "travelling cosine accepted");
    hsbd_field_add(&field, tilt);
    hsbd_field_add(&field, wave);
    CHECK(hsbd_field_is_driven(&field), "driven");
    hsbd_field now;
    const double t = 1.3;
    const hsbd_field *at = hsbd_field_at(&field, t, &now);
    CHECK(at == &now, "a driven field is evaluated into `now`");
    CHECK_CLOSE(at->term[0].p[0], 0.5 + 2.0 * cos(3.0 * t + 0.25), 1e-15);
    /* force of the travelling cosine at x: (pi U0/lambda) sin(2 pi (x - v t)/lambda) */
    const double x = 0.37, f_expect = 0.5 + 2.0 * cos(3.0 * t + 0.25) +
                                      PI * 4.0 / 0.5 * sin(2 * PI * (x - 0.7 * t) / 0.5);
    double f;
    hsbd_field_force(at, 1, &x, &f);
    CHECK_CLOSE(f, f_expect, 1e-12);
    CHECK_CLOSE(hsbd_field_potential(at, x),
                -at->term[0].p[0] * x + 2.0 * cos(2 * PI * (x - 0.7 * t) / 0.5), 1e-12);
    /* the base field is untouched */
    CHECK(field.term[0].p[0] == 0.5 && field.term[1].p[2] == 0.0, "base field unchanged");

    /* square wave: sign(cos), +1 at cos = 0 */
    hsbd_drive sq = {.wave = HSBD_WAVE_SQUARE, .amplitude = 1, .omega = 2 * PI, .phase = 0};
    CHECK(hsbd_drive_wave(&sq, 0.1) == 1.0 && hsbd_drive_wave(&sq, 0.3) == -1.0 &&
              hsbd_drive_wave(&sq, 0.8) == 1.0,
          "square wave");
    /* dragged trap: centre c0 + v t; oscillating: c0 + A cos(omega t) */
    hsbd_field trap = {0};
    hsbd_field_term h = hsbd_field_harmonic(2.0, 5.0, 0.0);
    CHECK(hsbd_field_term_drive(&h, HSBD_DRIVE_POSITION, HSBD_WAVE_NONE, 0, 0, 0, -0.25) == 0,
          "dragged trap");
    hsbd_field_add(&trap, h);
    const double y = 4.0;
    hsbd_field_force(hsbd_field_at(&trap, 2.0, &now), 1, &y, &f);
    CHECK_CLOSE(f, -2.0 * (4.0 - (5.0 - 0.5)), 1e-15);
}

static void test_refused_drives(void) {
    hsbd_field_term tilt = hsbd_field_tilt(1.0);
    CHECK(hsbd_field_term_drive(&tilt, HSBD_DRIVE_POSITION, HSBD_WAVE_COSINE, 1, 1, 0, 0) == -1,
          "a tilt has no position");
    CHECK(hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, 7, 1, 1, 0, 0) == -1, "unknown wave");
    CHECK(hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, 1, -1, 0, 0) == -1,
          "omega < 0");
    CHECK(hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, NAN, 1, 0, 0) == -1,
          "NaN amplitude");
    CHECK(!memcmp(&tilt.drive, &(hsbd_drive){0}, sizeof tilt.drive), "a refused drive leaves none");
    hsbd_field_term table = hsbd_field_table(NULL, HSBD_TABLE_POTENTIAL, 0.0);
    CHECK(hsbd_field_term_drive(&table, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, 1, 1, 0, 0) == -1,
          "a table has no drivable parameter");
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_cosine(6.0, 1.0));
    hsbd_field now;
    CHECK(!hsbd_field_is_driven(&field) && hsbd_field_at(&field, 3.0, &now) == &field,
          "a static field is used as it is");
}

/* The library's steps with a driven field equal the oracle fed with the forces of the
 * field at each step's start time t_n = n dt. */
static void test_driven_step_vs_oracle(void) {
    enum { N = 10 };
    hsbd_rods_params par = {.n = N,
                            .length = 6.0,
                            .sigma = 0.5,
                            .diffusion = 1.3,
                            .kT = 0.7,
                            .dt = 1e-2,
                            .seed = 77,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY};
    hsbd_field_term wave = hsbd_field_cosine(6.0, 1.0), tilt = hsbd_field_tilt(0.8);
    hsbd_field_term_drive(&wave, HSBD_DRIVE_POSITION, HSBD_WAVE_NONE, 0, 0, 0, 0.4);
    hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, HSBD_WAVE_SQUARE, 1.5, 2 * PI / 0.37, 0.1, 0);
    hsbd_field_add(&par.field, wave);
    hsbd_field_add(&par.field, tilt);
    const double worst = oracle_library_deviation(&par, 400);
    CHECK(worst <= 1e-12, "driven step vs oracle: max deviation %.3g", worst);
}

/* The field's largest curvature, which sets the Euler warning: exact for the cosine
 * (2 pi^2 U0 / lambda^2) and the trap (k), zero for a tilt, a driven strength at its largest
 * |p(0)| + |amplitude|, a sum bounded by the sum of its terms, and a tabulated cosine within
 * its spline's accuracy. */
static void test_max_curvature(void) {
    hsbd_field f = {0};
    hsbd_field_add(&f, hsbd_field_cosine(6.0, 0.5));
    CHECK_CLOSE(hsbd_field_max_curvature(&f), 2 * PI * PI * 6.0 / 0.25, 1e-12);
    hsbd_field_add(&f, hsbd_field_tilt(-3.0));
    hsbd_field_add(&f, hsbd_field_harmonic(-0.7, 1.0, 0.0));
    CHECK_CLOSE(hsbd_field_max_curvature(&f), 2 * PI * PI * 6.0 / 0.25 + 0.7, 1e-12);
    hsbd_field g = {0};
    hsbd_field_term c = hsbd_field_cosine(2.0, 1.0);
    hsbd_field_term_drive(&c, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, -3.0, 1.0, 0, 0);
    hsbd_field_add(&g, c);
    CHECK_CLOSE(hsbd_field_max_curvature(&g), 2 * PI * PI * 5.0, 1e-12);
    enum { M = 201 };
    double x[M], y[M];
    for (int k = 0; k < M; ++k)
        x[k] = -0.25 + 1.5 * k / (double)(M - 1), y[k] = 3.0 * cos(2 * PI * x[k]);
    hsbd_error err;
    hsbd_table *t = hsbd_table_alloc(M, x, y, "cosine table", &err);
    CHECK(t != NULL, "table");
    if (!t) return;
    hsbd_field h = {0};
    hsbd_field_add(&h, hsbd_field_table(t, HSBD_TABLE_POTENTIAL, 0.0));
    CHECK_CLOSE(hsbd_field_max_curvature(&h), 3.0 * 4 * PI * PI, 0.01 * 3.0 * 4 * PI * PI);
    hsbd_table_free(t);
}

int main(void) {
    test_max_curvature();
    test_parameters_at_time();
    test_refused_drives();
    test_driven_step_vs_oracle();
    return test_finish("test_field_drive");
}
