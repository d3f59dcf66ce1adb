#include "io/tables.h"

#include <math.h>
#include <string.h>

#include "hsbd/io.h"

#include "hsbd_version.h"

void hsbd_write_table_header(FILE *f, const hsbd_config *cfg, const char *what,
                             const char *columns) {
    fprintf(f, "# hsbd %s (git %s): %s\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT, what);
    hsbd_config_write_header(cfg, f, "# ");
    fprintf(f, "# %s\n", columns); /* numpy.loadtxt skips it */
}

void hsbd_write_value_columns(FILE *f, size_t rows, const double *x, size_t pairs,
                              const double *val) {
    for (size_t k = 0; k < rows; ++k) {
        fprintf(f, "%.10g", x[k]);
        for (size_t p = 0; p < pairs; ++p)
            fprintf(f, "\t%.10g\t%.4g", val[2 * p * rows + k], val[(2 * p + 1) * rows + k]);
        fputc('\n', f);
    }
}

void hsbd_json_string(FILE *f, const char *s) {
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\')
            fprintf(f, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(f, "\\u%04x", *s);
        else
            fputc(*s, f);
    }
    fputc('"', f);
}

void hsbd_json_number(FILE *f, const char *key, double v, int comma) {
    if (isfinite(v))
        fprintf(f, "  \"%s\": %.10g%s\n", key, v, comma ? "," : "");
    else
        fprintf(f, "  \"%s\": null%s\n", key, comma ? "," : "");
}

int hsbd_run_outcome(const hsbd_config *cfg, int write_rc, const hsbd_error *werr, int completed,
                     uint64_t steps_done, hsbd_error *err) {
    if (write_rc != HSBD_OK) return hsbd_error_set(err, write_rc, "%s", werr->message);
    if (!completed)
        return hsbd_error_set(err, HSBD_EINTERRUPT,
                              "stopped after %llu of %llu steps; results so far are in '%s' "
                              "(summary.json says \"completed\": false)",
                              (unsigned long long)steps_done,
                              (unsigned long long)hsbd_config_steps(cfg), cfg->output.dir);
    return HSBD_OK;
}

int hsbd_write_columns_table(const char *dir, const char *name, const hsbd_config *cfg,
                             const char *what, const char *columns, size_t rows, const double *x,
                             size_t pairs, const double *val, hsbd_error *err) {
    hsbd_outfile o;
    if (hsbd_outfile_open(&o, dir, name, err) != HSBD_OK) return err->status;
    hsbd_write_table_header(o.f, cfg, what, columns);
    hsbd_write_value_columns(o.f, rows, x, pairs, val);
    return hsbd_outfile_commit(&o, err);
}

int hsbd_write_blocks_table(const char *dir, const char *name, const hsbd_config *cfg,
                            const char *what, size_t rows, size_t nblocks, double width,
                            const double *val, hsbd_error *err) {
    hsbd_outfile o;
    if (hsbd_outfile_open(&o, dir, name, err) != HSBD_OK) return err->status;
    fprintf(o.f, "# hsbd %s (git %s): %s\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT, what);
    hsbd_config_write_header(cfg, o.f, "# ");
    fprintf(o.f, "# x");
    for (size_t b = 0; b < nblocks; ++b)
        fprintf(o.f, "\tblock_%zu", b + 1);
    fputc('\n', o.f);
    for (size_t k = 0; k < rows; ++k) {
        fprintf(o.f, "%.10g", ((double)k + 0.5) * width);
        for (size_t b = 0; b < nblocks; ++b)
            fprintf(o.f, "\t%.8g", val[b * rows + k]);
        fputc('\n', o.f);
    }
    return hsbd_outfile_commit(&o, err);
}

int hsbd_write_lag_table(const char *dir, const char *name, const hsbd_config *cfg,
                         const char *what, const char *columns, size_t rows, const double *t,
                         const size_t *origins, size_t pairs, const double *val, hsbd_error *err) {
    hsbd_outfile o;
    if (hsbd_outfile_open(&o, dir, name, err) != HSBD_OK) return err->status;
    hsbd_write_table_header(o.f, cfg, what, columns);
    for (size_t k = 0; k < rows; ++k) {
        if (!origins[k]) continue;
        fprintf(o.f, "%.10g\t%.10g\t%.4g\t%zu", t[k], val[k], val[rows + k], origins[k]);
        for (size_t p = 1; p < pairs; ++p)
            fprintf(o.f, "\t%.10g\t%.4g", val[2 * p * rows + k], val[(2 * p + 1) * rows + k]);
        fputc('\n', o.f);
    }
    return hsbd_outfile_commit(&o, err);
}

int hsbd_write_sizes_table(const char *dir, const char *name, const hsbd_config *cfg,
                           const char *what, size_t max, const double *fraction, hsbd_error *err) {
    hsbd_outfile o;
    if (hsbd_outfile_open(&o, dir, name, err) != HSBD_OK) return err->status;
    hsbd_write_table_header(o.f, cfg, what, "size\tfraction");
    for (size_t k = 1; k <= max; ++k)
        fprintf(o.f, "%zu\t%.10g\n", k, fraction[k - 1]);
    return hsbd_outfile_commit(&o, err);
}
