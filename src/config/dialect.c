/* The authors' configuration files (Antonov et al., basep.cfg): keys without sections,
 * each mapped onto a key of the schema, and what their program fixes that the files do not
 * say. A file uses either these keys or hsbd's sections (parse.c refuses a mix). */
#include "config/schema.h"

#include <string.h>

const authors_key config_authors_keys[] = {
    {"particles", "system", "N"},
    {"length", "system", "L"},
    {"diameter", "system", "sigma"},
    {"DiffusionConstant", "system", "D"},
    {"force", "field", "force"},
    {"AmpU", "field", "amplitude"},
    {"totaltime", "run", "t_total"},
    {"timestep", "run", "dt"},
    {"eqtime", "run", "t_equil"},
    {"delta", "sample", "bin_width"},
    {"deltaPrime", "sample", "contact_width"},
    {"prefix", "output", "dir"},
    {"tTrajectory", "output", "trajectory_every"},
    {"tCurrent", "sample", "current_every"},
    {"gamma", "contact", "gamma"},
    {"order", "contact", "order"},
    {"epsilon", "contact", "epsilon"},
};
const size_t config_nauthors = sizeof config_authors_keys / sizeof config_authors_keys[0];

const authors_key *config_find_authors_key(const char *name) {
    for (size_t i = 0; i < config_nauthors; ++i)
        if (!strcmp(config_authors_keys[i].name, name)) return &config_authors_keys[i];
    return NULL;
}

int config_authors_assign(ini_state *st, const char *name, const char *value) {
    const authors_key *a = config_find_authors_key(name);
    if (!a) {
        char known[1024] = "";
        for (size_t i = 0; i < config_nauthors; ++i) {
            strcat(known, i ? ", " : "");
            strcat(known, config_authors_keys[i].name);
        }
        char sections[256];
        config_section_list(sections, sizeof sections);
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: unknown key '%.60s' outside any [section]; hsbd keys live "
                              "in sections (%s) and the authors' section-less keys are: %s",
                              st->path, st->line, name, sections, known);
    }
    char as[128];
    snprintf(as, sizeof as, "%s (%s.%s)", name, a->section, a->key);
    if (config_assign(st, config_find_key(a->section, a->key), value, as) != HSBD_OK)
        return st->err->status;
    if (!strcmp(name, "tTrajectory")) st->cfg->output.trajectory = HSBD_TRAJ_XYZ;
    return HSBD_OK;
}

void config_authors_finish(hsbd_config *cfg) {
    cfg->authors_dialect = 1;
    /* the authors' program: U = (AmpU/2) cos(2 pi x) + tilt, lambda = 1, mu = 1 */
    cfg->field.type = HSBD_FIELD_COSINE | HSBD_FIELD_TILT;
    cfg->field.wavelength = 1.0;
    cfg->system.kT = cfg->system.diffusion;
}
