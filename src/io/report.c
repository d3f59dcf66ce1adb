#include "io/report.h"

#include <math.h>

#include "hsbd_version.h"

void hsbd_write_table_header(FILE *f, const hsbd_config *cfg, const char *what,
                             const char *columns) {
    fprintf(f, "# hsbd %s (git %s): %s\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT, what);
    hsbd_config_write_header(cfg, f, "# ");
    fprintf(f, "%s\n", columns);
}

void hsbd_json_number(FILE *f, const char *key, double v, int comma) {
    if (isfinite(v))
        fprintf(f, "  \"%s\": %.10g%s\n", key, v, comma ? "," : "");
    else
        fprintf(f, "  \"%s\": null%s\n", key, comma ? "," : "");
}
