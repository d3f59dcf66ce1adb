/* What the schema prints: the tables' headers (the run's keys), the JSON of a run, and
 * the reference of every key (hsbd run --help, docs/config.md). */
#include "config/schema.h"

#include <string.h>

void hsbd_config_write_header(const hsbd_config *cfg, FILE *out, const char *prefix) {
    char v[HSBD_PATH_MAX + 64];
    for (size_t i = 0; i < config_nkeys; ++i) {
        const key_spec *k = &config_schema[i];
        if ((k->flags & NO_HEADER) || !config_key_read(cfg, k)) continue;
        config_format_value(cfg, k, v, sizeof v);
        fprintf(out, "%s%s.%s = %s\n", prefix, k->section, k->key, v);
    }
}

static void json_string(FILE *out, const char *s) {
    fputc('"', out);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\')
            fprintf(out, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(out, "\\u%04x", *s);
        else
            fputc(*s, out);
    }
    fputc('"', out);
}

void hsbd_config_write_json(const hsbd_config *cfg, FILE *out, int indent) {
    char v[HSBD_PATH_MAX + 64];
    fputc('{', out);
    for (size_t i = 0; i < config_nkeys; ++i) {
        const key_spec *k = &config_schema[i];
        const int first_in_section = i == 0 || strcmp(config_schema[i - 1].section, k->section);
        const int last_in_section =
            i + 1 == config_nkeys || strcmp(config_schema[i + 1].section, k->section);
        if (first_in_section) fprintf(out, "\n%*s\"%s\": {", indent + 2, "", k->section);
        config_format_value(cfg, k, v, sizeof v);
        fprintf(out, "\n%*s\"%s\": ", indent + 4, "", k->key);
        if (k->type == K_STRING || k->type == K_ENUM || k->type == K_BOOL || k->type == K_TERMS)
            json_string(out, v);
        else if (k->type == K_DOUBLE && !isfinite(*(const double *)config_cslot(cfg, k)))
            fputs("null", out); /* unset (a key of the other model) */
        else
            fputs(v, out);
        if (!last_in_section)
            fputc(',', out);
        else
            fprintf(out, "\n%*s}%s", indent + 2, "", i + 1 == config_nkeys ? "" : ",");
    }
    fprintf(out, "\n%*s}", indent, "");
}

void hsbd_config_write_reference(FILE *out, int markdown) {
    char range[160];
    if (markdown) {
        fprintf(out,
                "# Configuration reference\n\n"
                "Generated from the schema table in `src/config/schema.c` by `hsbd config-doc`;\n"
                "`hsbd run --help` prints the same. Any key can be overridden on the command\n"
                "line with `--set section.key=value`; `hsbd run --defaults` runs without a\n"
                "file, every key at its default.\n\n"
                "The file: `[section]` lines and `key = value` lines, of any length up to\n"
                "1 MiB. A line whose first non-blank character is `#` or `;` is a comment,\n"
                "whatever follows; an inline comment starts at ` #` or ` ;` (after a blank).\n"
                "Numbers are decimal (no hexadecimal, no leading zeros, no inf or nan). A file\n"
                "that sets no key, unknown sections or keys, a key set twice, NUL bytes or\n"
                "control characters are refused. Errors name the file, line, key and the\n"
                "allowed range, and exit with status 2.\n\n"
                "Memory: before anything is allocated, the run's memory is estimated (the\n"
                "particles at bytes per particle measured for each model, the MSD's snapshots,\n"
                "lag table and values, the profiles' or g(r)'s bins times blocks); a run that\n"
                "needs more than 80%% of the machine's physical memory is refused, naming the\n"
                "key behind the largest part.\n");
    }
    const char *open = NULL;
    for (size_t i = 0; i < config_nkeys; ++i) {
        const key_spec *k = &config_schema[i];
        config_format_range(k, range, sizeof range);
        const char *def = k->def[0] ? k->def : "(derived)";
        if (!open || strcmp(open, k->section)) {
            open = k->section;
            if (markdown)
                fprintf(out,
                        "\n## [%s]\n\n| key | default | allowed | meaning |\n|---|---|---|---|\n",
                        open);
            else
                fprintf(out, "\n[%s]\n", open);
        }
        if (markdown)
            fprintf(out, "| `%s` | `%s` | %s | %s |\n", k->key, def, range, k->doc);
        else
            fprintf(out, "  %-22s default %-8s %s\n  %-22s allowed: %s\n", k->key, def, k->doc, "",
                    range);
    }
    if (markdown) {
        fprintf(out, "\n## The authors' configuration files\n\n"
                     "Files without sections are read in the dialect of the authors' BCD program\n"
                     "(Antonov et al. 2022). Their keys map as follows. The field is their\n"
                     "`U = (AmpU/2) cos(2 pi x) - force x` with wavelength 1, and kT = D (their\n"
                     "mobility is 1).\n\n| authors' key | hsbd key |\n|---|---|\n");
        for (size_t i = 0; i < config_nauthors; ++i)
            fprintf(out, "| `%s` | `%s.%s` |\n", config_authors_keys[i].name,
                    config_authors_keys[i].section, config_authors_keys[i].key);
    }
}
