#include "io/report.h"

#include <math.h>

#include "hsbd_version.h"

void hsbd_write_table_header(FILE *f, const hsbd_config *cfg, const char *what,
                             const char *columns) {
    fprintf(f, "# hsbd %s (git %s): %s\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT, what);
    hsbd_config_write_header(cfg, f, "# ");
    fprintf(f, "%s\n", columns);
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
