/* The external field of a run from its configuration, shared by the models (run.h). */
#include <math.h>

#include "hsbd/table.h"
#include "run/run.h"

/* The configuration's drive on `term` when drive.parameter is one of its parameters
 * (strength_key or position_key), else the term unchanged. */
static hsbd_field_term driven(const hsbd_config *cfg, hsbd_field_term term, int strength_key,
                              int position_key) {
    const int p = cfg->drive.parameter;
    if (p == HSBD_DRIVE_NONE || (p != strength_key && p != position_key)) return term;
    const double omega = cfg->drive.period > 0 ? 2 * 3.141592653589793 / cfg->drive.period : 0;
    hsbd_field_term_drive(&term, p == strength_key ? HSBD_DRIVE_STRENGTH : HSBD_DRIVE_POSITION,
                          cfg->drive.wave, cfg->drive.amplitude, omega, cfg->drive.phase,
                          cfg->drive.velocity);
    return term;
}

double run_step_density_error(int heun, double k, double dt) {
    return heun ? 0.125 * (k * dt) * (k * dt) : 0.25 * k * dt;
}

/* the dt at which the estimate is `error` */
static double step_dt_for(int heun, double k, double error) {
    return heun ? sqrt(8 * error) / k : 4 * error / k;
}

int run_step_warning(int heun, double k, double dt, const char *what, const char *where,
                     const char *curvature, char *msg, size_t len) {
    const double e = run_step_density_error(heun, k, dt);
    if (!(e > RUN_STEP_ERROR_MAX)) return 0;
    snprintf(msg, len,
             "run.dt = %g: the %s's %s step distorts the %s by about %.2g %% (%s %s = %.3g, "
             "a harmonic estimate; warned above %g %%); run.dt <= %.2g gives about 1 %%, <= "
             "%.2g about 0.1 %%",
             dt, what, heun ? "Heun" : "Euler", where, 100 * e,
             heun ? "(dt k)^2 / 8 with k =" : "dt k / 4 with k =", curvature, k,
             100 * RUN_STEP_ERROR_MAX, step_dt_for(heun, k, 0.01), step_dt_for(heun, k, 0.001));
    return 1;
}

/* Field terms from the configuration (field.type is a sum) along a line of length L,
 * periodic or between walls (run.h). A table is loaded; between
 * walls it must cover the box [0, L] (natural spline); on a ring it must span exactly one
 * period [0, L] with equal end values, and its spline is made periodic so that the force
 * stays continuous across x = 0 = L (BCD needs continuous forces). */
int run_build_field(const hsbd_config *cfg, double L, int periodic, const char *length_key,
                    hsbd_table **table, hsbd_field *field, hsbd_error *err) {
    const int t = cfg->field.type;
    const double period = periodic ? L : 0.0;
    if (t & HSBD_FIELD_COSINE)
        hsbd_field_add(field,
                       driven(cfg, hsbd_field_cosine(cfg->field.amplitude, cfg->field.wavelength),
                              HSBD_DRIVE_AMPLITUDE, HSBD_DRIVE_SHIFT));
    if (t & HSBD_FIELD_TILT)
        hsbd_field_add(field, driven(cfg, hsbd_field_tilt(cfg->field.force), HSBD_DRIVE_FORCE, -1));
    if (t & HSBD_FIELD_HARMONIC)
        hsbd_field_add(
            field, driven(cfg, hsbd_field_harmonic(cfg->field.stiffness, cfg->field.center, period),
                          HSBD_DRIVE_STIFFNESS, HSBD_DRIVE_CENTER));
    if (t & HSBD_FIELD_TABLE) {
        *table = hsbd_table_load(cfg->field.table, err);
        if (!*table) return err->status;
        const double x0 = hsbd_table_x_min(*table), x1 = hsbd_table_x_max(*table);
        if (period == 0 && (x0 > 0 || x1 < L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s (field.table): x runs from %g to %g and does not cover the "
                                  "box; allowed: first x <= 0 and last x >= %s = %g",
                                  cfg->field.table, x0, x1, length_key, L);
        if (period > 0 && (fabs(x0) > 1e-9 * L || fabs(x1 - L) > 1e-9 * L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s (field.table): x runs from %.17g to %.17g; on a ring "
                                  "(system.boundary = periodic) the table spans one period: "
                                  "allowed: first x = 0 and last x = %s = %g",
                                  cfg->field.table, x0, x1, length_key, L);
        char what[HSBD_PATH_MAX + 64];
        snprintf(what, sizeof what, "%s (field.table on a ring)", cfg->field.table);
        if (period > 0 && hsbd_table_make_periodic(*table, what, err) != HSBD_OK)
            return err->status;
        hsbd_field_add(field, hsbd_field_table(*table, cfg->field.table_kind, period));
    }
    return HSBD_OK;
}
