/* The validation report's two tables have as many cells in every row as in their header
 * (a 9-column header once stood over 8-column rows in validation.tsv and over 10-cell rows
 * in validation.md), and the cells carry the row's values. */
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "validate/report.h"

/* cells of each line: tab-separated (TSV) or between '|' (Markdown) */
static void check_cells(const char *what, char *text, char sep, size_t want, size_t lines) {
    size_t seen = 0;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n"), ++seen) {
        size_t cells = sep == '\t' ? 1 : 0;
        for (const char *p = line; *p; ++p)
            cells += *p == sep;
        if (sep == '|') cells -= 1; /* n cells have n + 1 bars */
        CHECK(cells == want, "%s line %zu has %zu cells, want %zu: %s", what, seen + 1, cells, want,
              line);
    }
    CHECK(seen == lines, "%s: %zu lines, want %zu", what, seen, lines);
}

int main(void) {
    char *tsv_text = NULL, *md_text = NULL;
    size_t tsv_len = 0, md_len = 0;
    FILE *tsv = open_memstream(&tsv_text, &tsv_len), *md = open_memstream(&md_text, &md_len);
    validation_write_header(tsv, md);
    const validation_row rows[2] = {
        {"percus-s0.5-rho0.5", "density", "FAIL", 2.5e-5, 20, 34, 9, 2.606, 4.63, 0.0039, 0.071},
        {"tonks-s0.5-rho0.5", "contact (theorem)", "pass", 1e-4, 200, 1, 1, 0.001, 0.03, 1e-4,
         NAN}};
    for (int k = 0; k < 2; ++k)
        validation_write_row(tsv, md, &rows[k]);
    fclose(tsv);
    fclose(md);
    const size_t ncol = validation_columns();
    CHECK(ncol == 11, "%zu columns", ncol);
    CHECK(strstr(tsv_text, "percus-s0.5-rho0.5\t2.5e-05\t20\tdensity\t34\t9\t2.606\t4.63\t0.0039"
                           "\t0.071\tFAIL\n") != NULL,
          "TSV row: %s", tsv_text);
    CHECK(strstr(md_text, "| percus-s0.5-rho0.5 | 2.5e-05 | 20 | density | 34 | 9 | 2.606 | "
                          "4.63 | 0.39 % | 0.071 | FAIL |\n") != NULL,
          "Markdown row: %s", md_text);
    check_cells("validation.tsv", tsv_text, '\t', ncol, 3);
    check_cells("validation.md", md_text, '|', ncol, 4);
    free(tsv_text);
    free(md_text);
    return test_finish("test_validate_report");
}
