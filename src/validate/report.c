/* Validation tables (see report.h). */
#include "validate/report.h"

/* Each column: its TSV name, its Markdown header, and the cell text of a row. */
typedef struct column {
    const char *tsv, *md;
    void (*cell)(const validation_row *r, int markdown, char *buf, size_t len);
} column;

static void cell_case(const validation_row *r, int md, char *b, size_t n) {
    (void)md;
    snprintf(b, n, "%s", r->case_name);
}
static void cell_dt(const validation_row *r, int md, char *b, size_t n) {
    (void)md;
    snprintf(b, n, "%g", r->dt);
}
static void cell_t(const validation_row *r, int md, char *b, size_t n) {
    (void)md;
    snprintf(b, n, "%g", r->t_total);
}
static void cell_observable(const validation_row *r, int md, char *b, size_t n) {
    (void)md;
    snprintf(b, n, "%s", r->observable);
}
static void cell_points(const validation_row *r, int md, char *b, size_t n) {
    (void)md;
    snprintf(b, n, "%zu", r->points);
}
static void cell_eff(const validation_row *r, int md, char *b, size_t n) {
    snprintf(b, n, md ? "%.0f" : "%.4g", r->eff_dof);
}
static void cell_chi2(const validation_row *r, int md, char *b, size_t n) {
    snprintf(b, n, md ? "%.3f" : "%.4g", r->chi2_dof);
}
static void cell_max(const validation_row *r, int md, char *b, size_t n) {
    snprintf(b, n, md ? "%.2f" : "%.4g", r->max_dev);
}
static void cell_rel(const validation_row *r, int md, char *b, size_t n) {
    if (md)
        snprintf(b, n, "%.2f %%", 100 * r->mean_rel);
    else
        snprintf(b, n, "%.4g", r->mean_rel);
}
static void cell_p(const validation_row *r, int md, char *b, size_t n) {
    snprintf(b, n, md ? "%.2g" : "%.4g", r->p_value);
}
static void cell_result(const validation_row *r, int md, char *b, size_t n) {
    (void)md;
    snprintf(b, n, "%s", r->result);
}

static const column columns[] = {
    {"case", "case", cell_case},
    {"dt", "dt", cell_dt},
    {"t_total", "t", cell_t},
    {"observable", "observable", cell_observable},
    {"points", "points", cell_points},
    {"eff_points", "effective points", cell_eff},
    {"chi2_dof", "chi^2/dof", cell_chi2},
    {"max_dev_sigma", "max dev / error", cell_max},
    {"mean_rel_dev", "mean rel. dev", cell_rel},
    {"hotelling_p", "Hotelling p", cell_p},
    {"result", "result", cell_result},
};
enum { NCOLUMNS = sizeof columns / sizeof columns[0] };

size_t validation_columns(void) {
    return NCOLUMNS;
}

void validation_write_header(FILE *tsv, FILE *md) {
    for (size_t k = 0; k < NCOLUMNS; ++k) {
        fprintf(tsv, "%s%s", k ? "\t" : "# ", columns[k].tsv);
        fprintf(md, "| %s ", columns[k].md);
    }
    fprintf(tsv, "\n");
    fprintf(md, "|\n");
    for (size_t k = 0; k < NCOLUMNS; ++k)
        fprintf(md, "|---");
    fprintf(md, "|\n");
}

void validation_write_row(FILE *tsv, FILE *md, const validation_row *r) {
    char buf[256];
    for (size_t k = 0; k < NCOLUMNS; ++k) {
        columns[k].cell(r, 0, buf, sizeof buf);
        fprintf(tsv, "%s%s", k ? "\t" : "", buf);
        columns[k].cell(r, 1, buf, sizeof buf);
        fprintf(md, "| %s ", buf);
    }
    fprintf(tsv, "\n");
    fprintf(md, "|\n");
}
