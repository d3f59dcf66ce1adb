/* The rods' rules across keys: the ring or the walls, room for the rods, pair forces and
 * sticky contacts, the field and the profiles' period, the drives, and derived defaults. */
#include "config/schema.h"

#include "hsbd/field.h"

/* total length of the rods */
static double rods_length(const hsbd_config *cfg) {
    if (!cfg->species.n) return (double)cfg->system.n * cfg->system.sigma;
    double total = 0;
    for (size_t k = 0; k < cfg->species.n; ++k)
        total += (double)cfg->species.count[k] * cfg->species.sigma[k];
    return total;
}

/* ---- drives --------------------------------------------------------------------------- */

/* A drive must change a parameter of a term in field.type, with a wave of a period of at
 * least one step (and one amplitude) or a velocity; sample.phases needs the wave. */
static int check_drive(const hsbd_config *cfg, hsbd_error *err) {
    static const char *const keys[] = {"wave", "amplitude", "period", "phase", "velocity"};
    static const int term_of[] = {0,
                                  HSBD_FIELD_TILT,
                                  HSBD_FIELD_COSINE,
                                  HSBD_FIELD_COSINE,
                                  HSBD_FIELD_HARMONIC,
                                  HSBD_FIELD_HARMONIC};
    static const char *const term_name[] = {"", "tilt", "cosine", "cosine", "harmonic", "harmonic"};
    const int p = cfg->drive.parameter, wave = cfg->drive.wave != HSBD_WAVE_NONE;
    if (p == HSBD_DRIVE_NONE) {
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
            if (!config_is_default(cfg, "drive", keys[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "%s: drive.%s is set, but drive.parameter = none drives "
                                      "nothing; allowed: drive.parameter = "
                                      "force|amplitude|shift|stiffness|center",
                                      config_origin_of(cfg, "drive", keys[k]), keys[k]);
    } else if (!(cfg->field.type & term_of[p])) {
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: drive.parameter drives the %s term, which field.type does not "
                              "have; allowed: a parameter of a term in field.type",
                              config_origin_of(cfg, "drive", "parameter"), term_name[p]);
    } else if (wave) {
        const double dt = fmax(cfg->run.dt, hsbd_config_dt_equil(cfg));
        if (!(cfg->drive.period >= dt))
            return hsbd_error_set(
                err, HSBD_EINPUT,
                "%s: drive.period = %g with drive.wave set; allowed: drive.period "
                ">= the time step %g (run.dt, run.dt_equil)",
                config_origin_of(cfg, "drive", "period"), cfg->drive.period, dt);
        if (cfg->drive.amplitude == 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: drive.amplitude = 0 with drive.wave set changes nothing; "
                                  "allowed: drive.amplitude != 0",
                                  config_origin_of(cfg, "drive", "amplitude"));
    } else {
        for (size_t k = 1; k < 4; ++k)
            if (!config_is_default(cfg, "drive", keys[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "%s: drive.%s is set, but drive.wave = none; allowed: "
                                      "drive.wave = cosine|square, or leave drive.%s out",
                                      config_origin_of(cfg, "drive", keys[k]), keys[k], keys[k]);
        if (cfg->drive.velocity == 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: drive.parameter is set, but neither drive.wave nor "
                                  "drive.velocity changes it; allowed: drive.wave = cosine|square "
                                  "or drive.velocity != 0",
                                  config_origin_of(cfg, "drive", "parameter"));
    }
    if (cfg->sample.phases > 0 && !(p != HSBD_DRIVE_NONE && wave))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.phases = %lld needs a periodic drive; allowed: "
                              "sample.phases = 0, or drive.wave = cosine|square",
                              config_origin_of(cfg, "sample", "phases"),
                              (long long)cfg->sample.phases);
    return HSBD_OK;
}

/* The rods fit in the ring or between the walls. */
static int check_room(const hsbd_config *cfg, hsbd_error *err) {
    const double L = cfg->system.length, sigma = cfg->system.sigma;
    const double occupied = rods_length(cfg);
    if (occupied < L) return HSBD_OK;
    char allowed[96];
    if (cfg->species.n)
        snprintf(allowed, sizeof allowed, "sum of species.count x species.sigma < L");
    else
        snprintf(allowed, sizeof allowed, "N < %g", sigma > 0 ? L / sigma : INFINITY);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: system.N = %lld rods of total length %g do not fit in system.L "
                          "= %g (no room); allowed: %s",
                          config_origin_of(cfg, "system", "N"), (long long)cfg->system.n, occupied,
                          L, allowed);
}

/* sample.contact_width, unless set: 3 sqrt(4 D dt) of the fastest rod, at least 0.01 */
static void derive_contact_width(hsbd_config *cfg) {
    if (cfg->sample.contact_width != 0) return;
    double d = cfg->system.diffusion;
    for (size_t k = 0; k < cfg->species.n; ++k)
        d = fmax(d, cfg->species.diffusion[k]);
    cfg->sample.contact_width = fmax(1e-2, 3 * sqrt(4 * d * cfg->run.dt));
    config_origin_derived(cfg, "sample", "contact_width", "default (derived from run.dt)");
}

/* Pair forces and sticky contacts: the hard core they need, sigma > 0 for the potentials
 * written in units of it, the cutoff (derived from pair.type unless set) and epsilon
 * within half the ring, a table file. */
static int check_pair_and_contact(hsbd_config *cfg, hsbd_error *err) {
    const double L = cfg->system.length, sigma = cfg->system.sigma;
    if (cfg->pair.type != HSBD_PAIR_NONE && !cfg->system.hard_core)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type needs system.hard_core = on (pair forces act between "
                              "neighbours in ring order)",
                              config_origin_of(cfg, "pair", "type"));
    if (cfg->contact.gamma > 0 && !cfg->system.hard_core)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: contact.gamma > 0 needs system.hard_core = on",
                              config_origin_of(cfg, "contact", "gamma"));
    if ((cfg->pair.type == HSBD_PAIR_YUKAWA || cfg->pair.type == HSBD_PAIR_LJ) && !(sigma > 0))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type = %s needs system.sigma > 0 (the potential is written "
                              "in units of sigma: point rods, which may coincide, give 0/0); "
                              "allowed: sigma > 0, or pair.type = table",
                              config_origin_of(cfg, "pair", "type"),
                              cfg->pair.type == HSBD_PAIR_LJ ? "lj" : "yukawa");
    if (cfg->pair.type == HSBD_PAIR_YUKAWA || cfg->pair.type == HSBD_PAIR_LJ) {
        if (cfg->pair.cutoff == 0) {
            cfg->pair.cutoff =
                cfg->pair.type == HSBD_PAIR_YUKAWA ? sigma + 5.0 / cfg->pair.kappa : 2.5 * sigma;
            config_origin_derived(cfg, "pair", "cutoff", "default (derived from pair.type)");
        }
        if (!(cfg->pair.cutoff > sigma) || !(cfg->pair.cutoff <= 0.5 * L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: pair.cutoff = %g out of range; allowed: system.sigma = %g "
                                  "< cutoff <= L/2 = %g",
                                  config_origin_of(cfg, "pair", "cutoff"), cfg->pair.cutoff, sigma,
                                  0.5 * L);
    }
    if (cfg->pair.type == HSBD_PAIR_TABLE && !cfg->pair.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type = table needs pair.table = <file with 'r f(r)' lines>",
                              config_origin_of(cfg, "pair", "type"));
    if (cfg->contact.gamma > 0 && !(sigma + cfg->contact.epsilon <= 0.5 * L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: contact.epsilon = %g out of range; allowed: sigma + epsilon <= "
                              "L/2 = %g",
                              config_origin_of(cfg, "contact", "epsilon"), cfg->contact.epsilon,
                              0.5 * L);
    return HSBD_OK;
}

/* The field's wavelength divides a ring, a table term has its file; field.center is L/2
 * unless set. */
static int check_field(hsbd_config *cfg, hsbd_error *err) {
    const double L = cfg->system.length;
    const int walls = cfg->system.boundary == HSBD_BOUNDARY_WALLS;
    const int has_cosine = (cfg->field.type & HSBD_FIELD_COSINE) != 0;
    if (has_cosine && !walls && !config_divides(cfg->field.wavelength, L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.wavelength = %g must divide system.L = %g (the ring is "
                              "periodic)",
                              config_origin_of(cfg, "field", "wavelength"), cfg->field.wavelength,
                              L);
    if ((cfg->field.type & HSBD_FIELD_TABLE) && !cfg->field.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.type with table needs field.table = <file with 'x value' "
                              "lines covering [0, L]>",
                              config_origin_of(cfg, "field", "type"));
    if (isnan(cfg->field.center)) {
        cfg->field.center = 0.5 * L;
        config_origin_derived(cfg, "field", "center", "default (L/2)");
    }
    return HSBD_OK;
}

/* The profiles: sample.period (derived unless set) divides the ring or is the box between
 * walls, whole bins of sample.bin_width in it, their accumulators within 4 GiB, whole
 * periods per block of space. */
static int check_profiles(hsbd_config *cfg, hsbd_error *err) {
    const double L = cfg->system.length;
    const int walls = cfg->system.boundary == HSBD_BOUNDARY_WALLS;
    const int has_cosine = (cfg->field.type & HSBD_FIELD_COSINE) != 0;
    if (isnan(cfg->sample.period)) {
        cfg->sample.period = has_cosine && !walls ? cfg->field.wavelength : L;
        if (!config_divides(cfg->sample.period, L)) cfg->sample.period = L;
        config_origin_derived(cfg, "sample", "period",
                              walls ? "default (L: walls)" : "default (field.wavelength or L)");
    }
    if (walls && cfg->sample.period != L)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.period = %g, but with system.boundary = walls the "
                              "profile covers the whole box; allowed: sample.period = L = %g",
                              config_origin_of(cfg, "sample", "period"), cfg->sample.period, L);
    if (!config_divides(cfg->sample.period, L))
        return hsbd_error_set(err, HSBD_EINPUT, "%s: sample.period = %g must divide system.L = %g",
                              config_origin_of(cfg, "sample", "period"), cfg->sample.period, L);
    if (!config_divides(cfg->sample.bin_width, cfg->sample.period))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.bin_width = %g must divide sample.period = %g into a "
                              "whole number of bins",
                              config_origin_of(cfg, "sample", "bin_width"), cfg->sample.bin_width,
                              cfg->sample.period);
    /* the profile keeps four accumulators per bin and error block */
    const double profile_bytes =
        cfg->sample.period / cfg->sample.bin_width * ((double)cfg->sample.blocks + 1) * 4 * 8;
    if (profile_bytes > 4.0 * 1024 * 1024 * 1024)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.bin_width = %g gives %.3g bins over sample.period = %g, "
                              "%.1f GiB of profile accumulators with %lld blocks; allowed: at most "
                              "4 GiB (a wider bin, or fewer blocks)",
                              config_origin_of(cfg, "sample", "bin_width"), cfg->sample.bin_width,
                              cfg->sample.period / cfg->sample.bin_width, cfg->sample.period,
                              profile_bytes / (1024.0 * 1024 * 1024),
                              (long long)cfg->sample.blocks);
    if (cfg->sample.blocking == HSBD_BLOCKS_SPACE &&
        !config_divides((double)cfg->sample.blocks * cfg->sample.period, L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.blocks = %lld must divide the number of periods "
                              "L/period = %g when sample.blocking = space",
                              config_origin_of(cfg, "sample", "blocks"),
                              (long long)cfg->sample.blocks, L / cfg->sample.period);
    return HSBD_OK;
}

/* Pair forces and sticky contacts act between the rods of one species only. */
static int check_one_species_forces(const hsbd_config *cfg, hsbd_error *err) {
    if (!cfg->species.n || (cfg->pair.type == HSBD_PAIR_NONE && !(cfg->contact.gamma > 0)))
        return HSBD_OK;
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: pair forces and sticky contacts need one species (mixtures with "
                          "pair forces are not supported yet)",
                          config_origin_of(cfg, cfg->contact.gamma > 0 ? "contact" : "pair",
                                           cfg->contact.gamma > 0 ? "gamma" : "type"));
}

int config_finalise_rods(hsbd_config *cfg, hsbd_error *err) {
    int walls = 0;
    if (config_parse_boundary(cfg, 1, &walls, err) != HSBD_OK) return err->status;
    cfg->system.boundary = walls ? HSBD_BOUNDARY_WALLS : HSBD_BOUNDARY_PERIODIC;
    if (config_parse_species(cfg, err) != HSBD_OK) return err->status;
    if (check_one_species_forces(cfg, err) != HSBD_OK) return err->status;
    if (check_room(cfg, err) != HSBD_OK) return err->status;
    derive_contact_width(cfg);
    if (check_pair_and_contact(cfg, err) != HSBD_OK) return err->status;
    if (check_field(cfg, err) != HSBD_OK) return err->status;
    if (check_profiles(cfg, err) != HSBD_OK) return err->status;
    if (config_check_run_keys(cfg, err) != HSBD_OK) return err->status;
    if (check_drive(cfg, err) != HSBD_OK) return err->status;
    return config_check_memory(cfg, 0, err);
}
