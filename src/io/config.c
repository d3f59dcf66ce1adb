#include "hsbd/config.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/input.h"
#include "hsbd/spheres.h"

typedef enum { K_INT, K_UINT64, K_DOUBLE, K_STRING, K_ENUM, K_BOOL, K_TERMS } key_type;

enum { OPEN_MIN = 1, OPEN_MAX = 2 };

typedef struct key_spec {
    const char *section, *key;
    key_type type;
    size_t offset;
    double min, max;
    unsigned flags;
    const char *def;     /* default, parsed like user input */
    const char *choices; /* K_ENUM: "a|b|c" (value = position); K_TERMS: "none|a|b|c", the
                            value a '+'-joined set of them (bit k-1 for choice k) */
    const char *doc;
} key_spec;

#define OFF(member) offsetof(hsbd_config, member)
#define INF         HUGE_VAL

/* The one schema table. Ranges are closed unless flagged open. */
static const key_spec schema[] = {
    {"system", "model", K_ENUM, OFF(system.model), 0, 0, 0, "rods", "rods|spheres",
     "particle model (rods: hard rods on a line, Brownian cluster dynamics; spheres: hard "
     "disks or spheres in a periodic box, event-driven Brownian dynamics)"},
    {"system", "dimension", K_INT, OFF(system.dimension), 2, 3, 0, "3", 0,
     "spheres: 2 (disks) or 3 (spheres)"},
    {"system", "box", K_STRING, OFF(system.box_text), 0, 0, 0, "", 0,
     "spheres: periodic box lengths, one value (square / cube) or one per dimension; or set "
     "system.packing_fraction instead"},
    {"system", "packing_fraction", K_DOUBLE, OFF(system.packing_fraction), 0, 1,
     OPEN_MIN | OPEN_MAX, "", 0,
     "spheres: packing fraction phi (volume of the particles over the box); gives a square / "
     "cubic box"},
    {"system", "drift", K_STRING, OFF(system.drift_text), 0, 0, 0, "", 0,
     "spheres: common drift velocity (one value per dimension, length/time), the same for "
     "every particle (Scala Sec. IV); empty: none"},
    {"system", "shell", K_DOUBLE, OFF(system.shell), 0, INF, OPEN_MAX, "0", 0,
     "spheres: neighbour shell radius (half the skin); 0: chosen from D and dt (docs/spheres.md)"},
    {"system", "N", K_INT, OFF(system.n), 1, 2147483647.0, 0, "50", 0, "number of rods"},
    {"system", "L", K_DOUBLE, OFF(system.length), 0, INF, OPEN_MIN | OPEN_MAX, "100", 0,
     "ring length (periodic line); N*sigma must be < L"},
    {"system", "sigma", K_DOUBLE, OFF(system.sigma), 0, INF, OPEN_MAX, "0.5", 0,
     "rod length / particle diameter (rods default 0.5; spheres default 1, and > 0)"},
    {"system", "D", K_DOUBLE, OFF(system.diffusion), 0, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "diffusion coefficient (length^2/time); mobility mu = D/kT"},
    {"system", "kT", K_DOUBLE, OFF(system.kT), 0, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "thermal energy, in the units of every energy of the configuration (field.amplitude, "
     "field.force x length, field.stiffness x length^2, pair.strength, tabulated potentials "
     "and forces): only energy / kT matters, and mobility mu = D/kT; the authors' dialect uses "
     "kT = D (their mu = 1)"},
    {"system", "seed", K_UINT64, OFF(system.seed), 0, 18446744073709551615.0, 0, "1", 0,
     "random seed (64-bit); same seed and binary give byte-identical tables"},
    {"system", "hard_core", K_BOOL, OFF(system.hard_core), 0, 1, 0, "on", 0,
     "on: hard rods; off: free particles (benchmark bound, tests)"},
    {"system", "contact_rule", K_ENUM, OFF(system.contact_rule), 0, 0, 0, "reflect",
     "reflect|sticky",
     "reflect: each gap's Brownian-bridge minimum is drawn first and a crossing reflects it "
     "(no O(sqrt(dt)) contact layer; validated, docs/validation.md); sticky: the paper's BCD "
     "as printed (inelastic mergers), needs ~100x smaller dt in dense systems"},
    {"system", "boundary", K_ENUM, OFF(system.boundary), 0, 0, 0, "periodic", "periodic|walls",
     "periodic: a ring of length L; walls: hard walls at 0 and L (rod centres in [sigma/2, "
     "L - sigma/2])"},
    {"contact", "gamma", K_DOUBLE, OFF(contact.gamma), 0, INF, OPEN_MAX, "0", 0,
     "Baxter stickiness gamma (Antonov Eqs. 29-30); 0: pure hard core"},
    {"contact", "order", K_DOUBLE, OFF(contact.order), 1, INF, OPEN_MIN | OPEN_MAX, "3", 0,
     "exponent p of the power-law delta_eps (Eq. 31); p > 1 keeps the force continuous"},
    {"contact", "epsilon", K_DOUBLE, OFF(contact.epsilon), 0, INF, OPEN_MIN | OPEN_MAX, "0.05", 0,
     "width of delta_eps (Eq. 31): the sticky force acts for gaps in [0, epsilon); the run "
     "checks mu max|f| dt / epsilon (Eq. 33): warns above 0.1, refuses above 1 (--force)"},
    {"pair", "type", K_ENUM, OFF(pair.type), 0, 0, 0, "none", "none|yukawa|lj|table",
     "continuous pair force between rods (Eq. 28): yukawa: V = strength sigma "
     "exp(-kappa (r - sigma))/r; lj: V = strength ((sigma/r)^12 - 2 (sigma/r)^6), a well of "
     "depth strength at contact; table: force f(r) from pair.table. Analytic forms are "
     "force-shifted to vanish continuously at pair.cutoff"},
    {"pair", "strength", K_DOUBLE, OFF(pair.strength), -INF, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "yukawa: V at contact (energy, units of system.kT; > 0 repulsive); lj: well depth (energy)"},
    {"pair", "kappa", K_DOUBLE, OFF(pair.kappa), 0, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "yukawa inverse screening length (1/length)"},
    {"pair", "cutoff", K_DOUBLE, OFF(pair.cutoff), 0, INF, OPEN_MAX, "0", 0,
     "centre distance where yukawa/lj end, > sigma and <= L/2 (0: yukawa sigma + 5/kappa, "
     "lj 2.5 sigma); a table ends at its last r"},
    {"pair", "table", K_STRING, OFF(pair.table), 0, 0, 0, "", 0,
     "pair.type = table: file with lines 'r f(r)' (force on the right rod, energy/length), r "
     "strictly increasing from <= sigma, f = 0 at the last r; natural cubic spline"},
    {"field", "type", K_TERMS, OFF(field.type), 0, 0, 0, "cosine",
     "none|cosine|tilt|harmonic|table",
     "external field, a sum of terms joined by '+' (e.g. cosine+tilt): cosine U = (amplitude/2) "
     "cos(2 pi x/wavelength); tilt: constant force (linear potential U = -force x, gravity); "
     "harmonic: U = (stiffness/2)(x - center)^2 (nearest image on a ring); table: U(x) or f(x) "
     "from field.table"},
    {"field", "amplitude", K_DOUBLE, OFF(field.amplitude), -INF, INF, OPEN_MIN | OPEN_MAX, "6", 0,
     "cosine amplitude U0 (energy, units of system.kT), Antonov Eq. 21"},
    {"field", "wavelength", K_DOUBLE, OFF(field.wavelength), 0, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "cosine wavelength lambda; must divide L"},
    {"field", "force", K_DOUBLE, OFF(field.force), -INF, INF, OPEN_MIN | OPEN_MAX, "0", 0,
     "constant force f (energy/length) of the tilt term; f < 0 pushes rods towards x = 0"},
    {"field", "stiffness", K_DOUBLE, OFF(field.stiffness), 0, INF, OPEN_MAX, "1", 0,
     "harmonic trap stiffness k (energy/length^2)"},
    {"field", "center", K_DOUBLE, OFF(field.center), -INF, INF, OPEN_MIN | OPEN_MAX, "", 0,
     "harmonic trap centre (default: L/2)"},
    {"field", "table", K_STRING, OFF(field.table), 0, 0, 0, "", 0,
     "field.type with table: file with lines 'x value', x strictly increasing; on a ring x runs "
     "from 0 to L exactly, the values at 0 and L agree and the spline is periodic (the force is "
     "continuous across x = 0 = L); between walls x covers [0, L] and the spline is natural"},
    {"field", "table_kind", K_ENUM, OFF(field.table_kind), 0, 0, 0, "potential", "potential|force",
     "what field.table holds: potential U(x) (energy; force -U') or force f(x) (energy/length)"},
    {"species", "names", K_STRING, OFF(species.names_text), 0, 0, 0, "", 0,
     "a mixture: species names (letters, digits, '_'), separated by spaces or commas; empty: "
     "one species with system.sigma and system.D"},
    {"species", "count", K_STRING, OFF(species.count_text), 0, 0, 0, "", 0,
     "particles of each species (whole numbers >= 1), summing to system.N; rods: the order "
     "along the line is a uniformly random arrangement unless init.positions gives it"},
    {"species", "fraction", K_STRING, OFF(species.fraction_text), 0, 0, 0, "", 0,
     "spheres: number fraction of each species (> 0, summing to 1), instead of species.count; "
     "counts are rounded to sum to system.N"},
    {"species", "sigma", K_STRING, OFF(species.sigma_text), 0, 0, 0, "", 0,
     "rod length of each species (>= 0); contact distance (sigma_a + sigma_b)/2"},
    {"species", "D", K_STRING, OFF(species.d_text), 0, 0, 0, "", 0,
     "diffusion coefficient of each species (> 0; spheres also 0: immobile obstacles); "
     "mobility D/kT"},
    {"species", "polydispersity", K_DOUBLE, OFF(species.polydispersity), 0, 0.3, 0, "0", 0,
     "spheres: continuous polydispersity, the relative standard deviation of the diameters "
     "about each species' sigma (or system.sigma); 0: monodisperse species"},
    {"species", "distribution", K_ENUM, OFF(species.distribution), 0, 0, 0, "gaussian",
     "gaussian|uniform",
     "spheres: distribution of the diameters with species.polydispersity (gaussian: truncated "
     "beyond 3.04 widths, variance kept; uniform: a flat band of that standard deviation)"},
    {"species", "D_law", K_ENUM, OFF(species.d_law), 0, 0, 0, "given", "given|stokes-einstein",
     "spheres: given: D of the species (or system.D) for every particle; stokes-einstein: "
     "D_i = D_0 sigma_0 / sigma_i with D_0 = system.D at sigma_0 = system.sigma (then no "
     "species.D)"},
    {"run", "dt", K_DOUBLE, OFF(run.dt), 0, INF, OPEN_MIN | OPEN_MAX, "1e-4", 0, "time step"},
    {"run", "t_equil", K_DOUBLE, OFF(run.t_equil), 0, INF, OPEN_MAX, "10", 0,
     "unsampled dynamics after the initial state"},
    {"run", "t_total", K_DOUBLE, OFF(run.t_total), 0, INF, OPEN_MIN | OPEN_MAX, "100", 0,
     "sampled (production) time"},
    {"run", "dt_equil", K_DOUBLE, OFF(run.dt_equil), 0, INF, OPEN_MAX, "0", 0,
     "time step during equilibration (0: run.dt); a coarser step relaxes slow modes (barrier "
     "hopping) cheaply, the Euler distortion of dt then relaxes within a short time"},
    {"sample", "bin_width", K_DOUBLE, OFF(sample.bin_width), 0, INF, OPEN_MIN | OPEN_MAX, "1e-2", 0,
     "density bin width Delta_x (Eq. 24); must divide sample.period"},
    {"sample", "contact_width", K_DOUBLE, OFF(sample.contact_width), 0, INF, OPEN_MAX, "0", 0,
     "contact window Delta' (Eq. 26): gaps in [0, Delta'] count as contact (0: max(0.01, three "
     "rms relative steps 3 sqrt(4 D dt)), largest D; narrower windows bias rho2_extrap low, "
     "docs/observables.md)"},
    {"sample", "period", K_DOUBLE, OFF(sample.period), 0, INF, OPEN_MIN | OPEN_MAX, "", 0,
     "profiles are folded into one period (default: field.wavelength); must divide L"},
    {"sample", "blocking", K_ENUM, OFF(sample.blocking), 0, 0, 0, "time", "time|space|replicas",
     "error bars of profiles and the MSD from blocks of time, or of space (segments of the "
     "ring, for long rings whose slow modes outlast time blocks; blocks must divide L/period), "
     "or from independent replicas (rods: each block restarts from its own initial state, "
     "the exact field-free sample or init.positions, and equilibrates run.t_equil; errors "
     "then include modes slower than any run)"},
    {"sample", "every", K_INT, OFF(sample.every), 1, 1e15, 0, "1", 0,
     "sample every this many steps (spheres: the MSD and F_s; default 10 there)"},
    {"sample", "blocks", K_INT, OFF(sample.blocks), 2, 10000, 0, "20", 0,
     "number of blocks for block-average error bars"},
    {"sample", "msd_max_lag", K_DOUBLE, OFF(sample.msd_max_lag), 0, INF, OPEN_MAX, "0", 0,
     "largest MSD lag time (0: t_total/10)"},
    {"sample", "msd_points_per_decade", K_INT, OFF(sample.msd_points_per_decade), 1, 1000, 0, "10",
     0, "log-spaced MSD lags per decade"},
    {"sample", "current_every", K_DOUBLE, OFF(sample.current_every), 0, INF, OPEN_MAX, "0", 0,
     "write the particle current every this much time to current.tsv (0: off)"},
    {"sample", "gr_every", K_INT, OFF(sample.gr_every), 0, 1e15, 0, "0", 0,
     "spheres: sample g(r) every this many steps (a pair search up to sample.gr_max, costly); "
     "0: every 0.05 time units (sigma^2/D), samples closer in time are strongly correlated"},
    {"sample", "gr_max", K_DOUBLE, OFF(sample.gr_max), 0, INF, OPEN_MAX, "0", 0,
     "spheres: largest distance of g(r) (0: 3 sigma_max, at most half the box)"},
    {"sample", "gr_bin", K_DOUBLE, OFF(sample.gr_bin), 0, INF, OPEN_MIN | OPEN_MAX, "0.02", 0,
     "spheres: g(r) bin width"},
    {"sample", "contact_fit", K_DOUBLE, OFF(sample.contact_fit), 0, INF, OPEN_MIN | OPEN_MAX, "0.1",
     0,
     "spheres: contact values g_ab(sigma_ab+) by a quadratic fit of g over gaps in [0, "
     "contact_fit)"},
    {"sample", "fs_k", K_DOUBLE, OFF(sample.fs_k), 0, INF, OPEN_MAX, "0", 0,
     "spheres: wavenumber of F_s(k, t) (0: 2 pi / sigma of species 0)"},
    {"output", "dir", K_STRING, OFF(output.dir), 0, 0, 0, "", 0,
     "run directory (default: runs/<config name>); --out overrides"},
    {"output", "trajectory", K_ENUM, OFF(output.trajectory), 0, 0, 0, "none", "none|xyz|gsd",
     "trajectory format (xyz: extended XYZ, read by OVITO/ASE/VMD; gsd: GSD, HOOMD schema)"},
    {"output", "trajectory_every", K_DOUBLE, OFF(output.trajectory_every), 0, INF, OPEN_MAX, "0", 0,
     "time between trajectory frames (0: t_total/100, at least run.dt)"},
    {"output", "checkpoints", K_BOOL, OFF(output.checkpoints), 0, 1, 0, "on", 0,
     "write checkpoints into the run directory (checkpoint.hsbd, the one before it kept as "
     "checkpoint.prev.hsbd), so that 'hsbd resume DIR' continues an interrupted run bit for "
     "bit; taking one never changes the results"},
    {"output", "checkpoint_every", K_DOUBLE, OFF(output.checkpoint_every), 0, INF, OPEN_MAX, "0",
     0,
     "simulated time between checkpoints (0: one every 10 minutes of wall time, so that an "
     "interruption loses at most that much); a stopped or finished run always writes one"},
    {"init", "positions", K_STRING, OFF(init.positions), 0, 0, 0, "", 0,
     "file with initial positions; rods: one per line ('#' comments), default an exact "
     "equilibrium sample of the field-free ring; spheres: extended XYZ (species name and x y "
     "[z] per particle, as hsbd writes it)"},
    {"init", "method", K_ENUM, OFF(init.method), 0, 0, 0, "auto", "auto|random|lattice|compress",
     "spheres without init.positions: random sequential insertion (up to phi 0.30 in 3D, 0.45 "
     "in 2D); compress: insertion at smaller diameters, then Brownian steps with growth into "
     "the gaps (a fluid up to phi 0.58 in 3D, 0.72 in 2D); or a lattice (fcc / centred "
     "rectangular, up to close packing of the largest diameter) melted during run.t_equil; "
     "auto: random, else compress, else lattice"},
};
enum { NKEYS = sizeof schema / sizeof schema[0] };
_Static_assert((int)NKEYS <= (int)HSBD_CONFIG_MAX_KEYS, "raise HSBD_CONFIG_MAX_KEYS");

/* The authors' section-less keys (Antonov et al., basep.cfg) and where they go. */
typedef struct {
    const char *name, *section, *key;
} authors_key;
static const authors_key authors_keys[] = {
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
enum { NAUTHORS = sizeof authors_keys / sizeof authors_keys[0] };

static void *slot(hsbd_config *cfg, const key_spec *k) {
    return (char *)cfg + k->offset;
}
static const void *cslot(const hsbd_config *cfg, const key_spec *k) {
    return (const char *)cfg + k->offset;
}

static const key_spec *find_key(const char *section, const char *key) {
    for (size_t i = 0; i < NKEYS; ++i)
        if (!strcmp(schema[i].section, section) && !strcmp(schema[i].key, key)) return &schema[i];
    return NULL;
}

static size_t key_index(const key_spec *k) {
    return (size_t)(k - schema);
}

/* ---- messages ------------------------------------------------------------------------ */

static size_t edit_distance(const char *a, const char *b) {
    size_t la = strlen(a), lb = strlen(b), prev[128], cur[128];
    if (la > 120 || lb > 120) return 1000;
    for (size_t j = 0; j <= lb; ++j)
        prev[j] = j;
    for (size_t i = 1; i <= la; ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= lb; ++j) {
            size_t best = prev[j - 1] + ((a[i - 1] | 32) != (b[j - 1] | 32));
            if (prev[j] + 1 < best) best = prev[j] + 1;
            if (cur[j - 1] + 1 < best) best = cur[j - 1] + 1;
            cur[j] = best;
        }
        memcpy(prev, cur, (lb + 1) * sizeof *prev);
    }
    return prev[lb];
}

/* Nearest known "section.key" to a misspelt one. */
static const char *suggest(const char *section, const char *key, char *buf, size_t len) {
    char want[256], cand[256];
    snprintf(want, sizeof want, "%s.%s", section, key);
    size_t best = 1000;
    buf[0] = '\0';
    for (size_t i = 0; i < NKEYS; ++i) {
        snprintf(cand, sizeof cand, "%s.%s", schema[i].section, schema[i].key);
        size_t d = edit_distance(want, cand);
        const size_t dk = edit_distance(key, schema[i].key) + 1; /* right key, wrong section */
        if (dk < d) d = dk;
        if (d < best) best = d, snprintf(buf, len, "%s", cand);
    }
    return best <= 3 || best * 3 <= strlen(want) ? buf : NULL;
}

static void format_range(const key_spec *k, char *buf, size_t len) {
    char lo[64], hi[64];
    switch (k->type) {
    case K_ENUM:
        snprintf(buf, len, "one of %s", k->choices);
        return;
    case K_TERMS:
        snprintf(buf, len, "none, or terms from %s joined by '+'", strchr(k->choices, '|') + 1);
        return;
    case K_BOOL:
        snprintf(buf, len, "on/off (also true/false, yes/no, 1/0)");
        return;
    case K_STRING:
        snprintf(buf, len, "a text of at most %d characters", HSBD_PATH_MAX - 1);
        return;
    default:
        break;
    }
    if (k->type == K_UINT64) {
        snprintf(buf, len, "0 <= %s <= 18446744073709551615 (integer)", k->key);
        return;
    }
    snprintf(lo, sizeof lo, "%.15g", k->min);
    snprintf(hi, sizeof hi, "%.15g", k->max);
    snprintf(buf, len, "%s %s %s %s %s%s", isinf(k->min) ? "-inf" : lo,
             (k->flags & OPEN_MIN) ? "<" : "<=", k->key,
             (k->flags & OPEN_MAX) ? "<" : "<=", isinf(k->max) ? "inf" : hi,
             k->type == K_INT ? " (integer)" : "");
}

/* ---- values ------------------------------------------------------------------------- */

static int in_range(const key_spec *k, double v) {
    if (k->flags & OPEN_MIN ? !(v > k->min) : !(v >= k->min)) return 0;
    if (k->flags & OPEN_MAX ? !(v < k->max) : !(v <= k->max)) return 0;
    return 1;
}

static char *trim(char *s) {
    while (*s == ' ' || *s == '\t')
        ++s;
    char *e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n'))
        --e;
    *e = '\0';
    return s;
}

/* Position of the word [w, w + len) in "a|b|c", or -1. */
static int choice_index(const char *choices, const char *w, size_t len) {
    const char *c = choices;
    for (int idx = 0; *c; ++idx) {
        const char *bar = strchr(c, '|');
        const size_t l = bar ? (size_t)(bar - c) : strlen(c);
        if (l == len && !strncmp(w, c, len)) return idx;
        c += l + (bar ? 1 : 0);
    }
    return -1;
}

/* "a+b+c" -> bits of the choices (choice k > 0 is bit k-1; "none" alone is 0); -1 when a
 * term is unknown, repeated or "none" is combined. */
static int parse_terms(const char *choices, const char *v) {
    if (!strcmp(v, "none")) return 0;
    int bits = 0;
    for (const char *w = v;;) {
        const char *plus = strchr(w, '+');
        const size_t len = plus ? (size_t)(plus - w) : strlen(w);
        const int idx = choice_index(choices, w, len);
        if (idx <= 0 || (bits & (1 << (idx - 1)))) return -1;
        bits |= 1 << (idx - 1);
        if (!plus) return bits;
        w = plus + 1;
    }
}

/* A decimal number that fills the whole text (no hexadecimal, octal-looking leading zeros,
 * inf or nan): 0, or -1 with what is wrong in *why. */
static int parse_number(const char *v, double *d, const char **why) {
    const char *digits = v + (*v == '+' || *v == '-');
    if (digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X'))
        return *why = "is hexadecimal (only decimal numbers are read)", -1;
    const size_t len = hsbd_scan_decimal(v, d);
    if (len == 0 || v[len] != '\0') return *why = NULL, -1;
    if (digits[0] == '0' && digits[1] >= '0' && digits[1] <= '9')
        return *why = "has a leading zero (octal numbers are not read; leave the zero out)", -1;
    if (!isfinite(*d)) return *why = "is beyond the range of double precision", -1;
    return 0;
}

/* Parse `text` into the key's slot; on failure a message naming the key and range. */
static int parse_value(hsbd_config *cfg, const key_spec *k, const char *text, const char *where,
                       hsbd_error *err) {
    char buf[HSBD_PATH_MAX], range[160];
    const char *start = text;
    while (*start == ' ' || *start == '\t')
        ++start;
    if (strlen(start) >= sizeof buf)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: %s.%s: the value is longer than %d characters; allowed: "
                              "shorter values",
                              where, k->section, k->key, HSBD_PATH_MAX - 1);
    strcpy(buf, start);
    char *v = trim(buf);
    format_range(k, range, sizeof range);
    switch (k->type) {
    case K_INT:
    case K_DOUBLE: {
        double d;
        const char *why;
        if (parse_number(v, &d, &why) != 0) {
            if (why)
                return hsbd_error_set(err, HSBD_EINPUT, "%s: %s.%s = '%.60s' %s; allowed: %s",
                                      where, k->section, k->key, v, why, range);
            return hsbd_error_set(
                err, HSBD_EINPUT, "%s: %s.%s = '%.60s' is not a %s number; allowed: %s", where,
                k->section, k->key, v, k->type == K_INT ? "whole" : "finite", range);
        }
        if (k->type == K_INT && d != floor(d))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s = '%.60s' is not a whole number; allowed: %s", where,
                                  k->section, k->key, v, range);
        if (!in_range(k, d))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s = %.60s is out of range; allowed: %s", where,
                                  k->section, k->key, v, range);
        if (k->type == K_INT)
            *(int64_t *)slot(cfg, k) = (int64_t)d;
        else
            *(double *)slot(cfg, k) = d;
        return HSBD_OK;
    }
    case K_UINT64: {
        const char *digits = v + (*v == '+');
        int ok = *digits != '\0' && strlen(digits) <= 20 && (digits[0] != '0' || !digits[1]);
        for (const char *c = digits; ok && *c; ++c)
            ok = *c >= '0' && *c <= '9';
        errno = 0;
        const unsigned long long u = ok ? strtoull(digits, NULL, 10) : 0;
        if (!ok || errno == ERANGE)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s = '%.60s' is not a valid integer; allowed: %s "
                                  "(decimal digits, no leading zero)",
                                  where, k->section, k->key, v, range);
        *(uint64_t *)slot(cfg, k) = (uint64_t)u;
        return HSBD_OK;
    }
    case K_STRING:
        strcpy((char *)slot(cfg, k), v);
        return HSBD_OK;
    case K_BOOL: {
        static const char *yes[] = {"on", "true", "yes", "1"}, *no[] = {"off", "false", "no", "0"};
        for (int i = 0; i < 4; ++i) {
            if (!strcmp(v, yes[i])) return *(int *)slot(cfg, k) = 1, HSBD_OK;
            if (!strcmp(v, no[i])) return *(int *)slot(cfg, k) = 0, HSBD_OK;
        }
        return hsbd_error_set(err, HSBD_EINPUT, "%s: %s.%s = '%.60s' is not a switch; allowed: %s",
                              where, k->section, k->key, v, range);
    }
    case K_ENUM:
    case K_TERMS: {
        const int value =
            k->type == K_ENUM ? choice_index(k->choices, v, strlen(v)) : parse_terms(k->choices, v);
        if (value >= 0) return *(int *)slot(cfg, k) = value, HSBD_OK;
        return hsbd_error_set(err, HSBD_EINPUT, "%s: %s.%s = '%.60s' is not known; allowed: %s",
                              where, k->section, k->key, v, range);
    }
    }
    return HSBD_OK;
}

static void format_value(const hsbd_config *cfg, const key_spec *k, char *buf, size_t len) {
    const void *p = cslot(cfg, k);
    switch (k->type) {
    case K_INT:
        snprintf(buf, len, "%lld", (long long)*(const int64_t *)p);
        break;
    case K_UINT64:
        snprintf(buf, len, "%llu", (unsigned long long)*(const uint64_t *)p);
        break;
    case K_DOUBLE: { /* shortest text that reads back as the same double */
        const double d = *(const double *)p;
        for (int prec = 6; prec <= 17; ++prec) {
            snprintf(buf, len, "%.*g", prec, d);
            if (strtod(buf, NULL) == d) break;
        }
        break;
    }
    case K_STRING:
        snprintf(buf, len, "%s", (const char *)p);
        break;
    case K_BOOL:
        snprintf(buf, len, "%s", *(const int *)p ? "on" : "off");
        break;
    case K_ENUM: {
        const char *c = k->choices;
        for (int idx = 0; *c; ++idx) {
            const char *bar = strchr(c, '|');
            const int l = bar ? (int)(bar - c) : (int)strlen(c);
            if (idx == *(const int *)p) {
                snprintf(buf, len, "%.*s", l, c);
                return;
            }
            c += l + (bar ? 1 : 0);
        }
        snprintf(buf, len, "?");
        break;
    }
    case K_TERMS: {
        const int bits = *(const int *)p;
        snprintf(buf, len, "none");
        size_t used = 0;
        const char *c = strchr(k->choices, '|') + 1;
        for (int bit = 0; *c; ++bit) {
            const char *bar = strchr(c, '|');
            const int l = bar ? (int)(bar - c) : (int)strlen(c);
            if ((bits & (1 << bit)) && used < len)
                used += (size_t)snprintf(buf + used, len - used, "%s%.*s", used ? "+" : "", l, c);
            c += l + (bar ? 1 : 0);
        }
    }
    }
}

void hsbd_config_defaults(hsbd_config *cfg) {
    memset(cfg, 0, sizeof *cfg);
    for (size_t i = 0; i < NKEYS; ++i) {
        if (schema[i].def[0] || schema[i].type == K_STRING)
            parse_value(cfg, &schema[i], schema[i].def, "default", NULL);
        snprintf(cfg->origin[i], HSBD_ORIGIN_MAX, "default");
    }
    cfg->sample.period = NAN; /* derived in finalize unless set */
    cfg->field.center = NAN;  /* L/2 unless set */
}

/* ---- INI files ---------------------------------------------------------------------- */

/* The file being read: where we are, what it has set, whether it uses the authors'
 * section-less keys or hsbd's sections (never both). */
typedef struct {
    hsbd_config *cfg;
    const char *path;
    long line;
    const char *section;               /* the open [section] (a schema section name), or NULL */
    long first_section, first_authors; /* lines of the first [section] / section-less key */
    size_t keys;                       /* keys the file set */
    hsbd_error *err;
    char set_at[NKEYS]; /* key already set in this file */
} ini_state;

static int assign(ini_state *st, const key_spec *k, const char *value, const char *as) {
    char where[HSBD_ORIGIN_MAX];
    snprintf(where, sizeof where, "%s:%ld", st->path, st->line);
    const size_t idx = key_index(k);
    if (st->set_at[idx])
        return hsbd_error_set(st->err, HSBD_EINPUT, "%s: %s is set twice (first at %s)", where, as,
                              st->cfg->origin[idx]);
    if (parse_value(st->cfg, k, value, where, st->err) != HSBD_OK) return st->err->status;
    st->set_at[idx] = 1;
    st->keys++;
    snprintf(st->cfg->origin[idx], HSBD_ORIGIN_MAX, "%s", where);
    return HSBD_OK;
}

static const authors_key *find_authors_key(const char *name) {
    for (size_t i = 0; i < NAUTHORS; ++i)
        if (!strcmp(authors_keys[i].name, name)) return &authors_keys[i];
    return NULL;
}

static int authors_assign(ini_state *st, const char *name, const char *value) {
    const authors_key *a = find_authors_key(name);
    if (!a) {
        char known[1024] = "";
        for (size_t i = 0; i < NAUTHORS; ++i) {
            strcat(known, i ? ", " : "");
            strcat(known, authors_keys[i].name);
        }
        return hsbd_error_set(
            st->err, HSBD_EINPUT,
            "%s:%ld: unknown key '%.60s' outside any [section]; hsbd keys live in sections "
            "([system], [species], [contact], [pair], [field], [run], [sample], [output], "
            "[init]) and the authors' section-less keys are: %s",
            st->path, st->line, name, known);
    }
    char as[128];
    snprintf(as, sizeof as, "%s (%s.%s)", name, a->section, a->key);
    if (assign(st, find_key(a->section, a->key), value, as) != HSBD_OK) return st->err->status;
    if (!strcmp(name, "tTrajectory")) st->cfg->output.trajectory = HSBD_TRAJ_XYZ;
    return HSBD_OK;
}

static int section_known(const char *name) {
    for (size_t i = 0; i < NKEYS; ++i)
        if (!strcmp(schema[i].section, name)) return 1;
    return 0;
}

/* "[name]" (text after ']' only a comment): opens a schema section */
static int open_section(ini_state *st, char *s) {
    char *close = strchr(s, ']');
    const char *rest = close ? trim(close + 1) : "";
    if (!close || (*rest && *rest != ';' && *rest != '#'))
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: malformed section line; allowed: '[section]', optionally "
                              "followed by a comment",
                              st->path, st->line);
    *close = '\0';
    const char *name = trim(s + 1);
    if (st->first_authors)
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: [%.60s] after the authors' section-less keys (from line "
                              "%ld); allowed: either the authors' keys without sections or hsbd's "
                              "sections, not both in one file",
                              st->path, st->line, name, st->first_authors);
    if (!section_known(name)) {
        size_t best = 1000;
        const char *near = NULL;
        for (size_t i = 0; i < NKEYS; ++i) {
            const size_t d = edit_distance(name, schema[i].section);
            if (d < best) best = d, near = schema[i].section;
        }
        return hsbd_error_set(st->err, HSBD_EINPUT, "%s:%ld: unknown section [%.60s]%s%s%s",
                              st->path, st->line, name,
                              best <= 2 ? "; did you mean [" : "; allowed: ", best <= 2 ? near : "",
                              best <= 2 ? "]?"
                                        : "[system], [species], [contact], [pair], [field], "
                                          "[run], [sample], [output], [init]");
    }
    for (size_t i = 0; i < NKEYS; ++i) /* the table's own string, alive after the line */
        if (!strcmp(schema[i].section, name)) st->section = schema[i].section;
    if (!st->first_section) st->first_section = st->line;
    return HSBD_OK;
}

/* "key = value" in the open section, or an authors' key before any section */
static int assign_line(ini_state *st, char *s) {
    char *eq = strchr(s, '=');
    if (!eq)
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: malformed line; allowed: 'key = value', '[section]', or a "
                              "comment starting with '#' or ';'",
                              st->path, st->line);
    *eq = '\0';
    char *key = trim(s), *value = trim(eq + 1);
    for (char *c = value; *c; ++c) /* inline comments: " ; ..." or " # ..." */
        if ((*c == ';' || *c == '#') && c > value && (c[-1] == ' ' || c[-1] == '\t')) {
            *c = '\0';
            value = trim(value);
            break;
        }
    if (!*key)
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: a value without a key; allowed: "
                              "'key = value'",
                              st->path, st->line);
    if (!st->section) {
        if (!st->first_authors) st->first_authors = st->line;
        return authors_assign(st, key, value);
    }
    const key_spec *k = find_key(st->section, key);
    if (!k) {
        char near[256];
        const char *s2 = suggest(st->section, key, near, sizeof near);
        const authors_key *a = find_authors_key(key);
        char hint[160] = "";
        if (a)
            snprintf(hint, sizeof hint,
                     " ('%s' is the authors' name of %s.%s, read only in "
                     "files without sections)",
                     key, a->section, a->key);
        return hsbd_error_set(
            st->err, HSBD_EINPUT, "%s:%ld: unknown key '%.60s' in section [%s]%s%s%s%s", st->path,
            st->line, key, st->section, s2 ? "; did you mean '" : "", s2 ? s2 : "",
            s2 ? "'?" : (a ? "" : " (hsbd run --help lists all keys)"), hint);
    }
    char as[128];
    snprintf(as, sizeof as, "%s.%s", st->section, key);
    return assign(st, k, value, as);
}

/* One line: blank, a comment (the whole line, whatever it holds), a section or a key. */
static int parse_line(ini_state *st, char *text) {
    if (st->line == 1 && !strncmp(text, "\xEF\xBB\xBF", 3)) text += 3; /* UTF-8 mark */
    char *s = trim(text);
    if (!*s || *s == ';' || *s == '#') return HSBD_OK;
    for (const char *c = s; *c; ++c)
        if (((unsigned char)*c < 0x20 && *c != '\t') || *c == 0x7f)
            return hsbd_error_set(st->err, HSBD_EINPUT,
                                  "%s:%ld: control character 0x%02x in the line (a binary "
                                  "file?); allowed: text",
                                  st->path, st->line, (unsigned)(unsigned char)*c);
    return *s == '[' ? open_section(st, s) : assign_line(st, s);
}

int hsbd_config_load_stream(hsbd_config *cfg, FILE *f, const char *name, hsbd_error *err) {
    hsbd_error_clear(err);
    ini_state st = {.cfg = cfg, .path = name, .err = err};
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    int got, rc = HSBD_OK;
    while (rc == HSBD_OK && (got = hsbd_lines_next(&in, err)) > 0) {
        st.line = in.number;
        rc = parse_line(&st, in.text);
    }
    if (rc == HSBD_OK && got < 0) rc = err->status;
    hsbd_lines_free(&in);
    if (rc != HSBD_OK) return rc;
    if (st.keys == 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: the configuration sets no key (the file is empty, or holds "
                              "only comments and sections); 'hsbd run --defaults' runs the "
                              "defaults without a file",
                              name);
    snprintf(cfg->file, sizeof cfg->file, "%s", name);
    if (st.first_authors) {
        cfg->authors_dialect = 1;
        /* the authors' program: U = (AmpU/2) cos(2 pi x) + tilt, lambda = 1, mu = 1 */
        cfg->field.type = HSBD_FIELD_COSINE | HSBD_FIELD_TILT;
        cfg->field.wavelength = 1.0;
        cfg->system.kT = cfg->system.diffusion;
    }
    return HSBD_OK;
}

int hsbd_config_load_file(hsbd_config *cfg, const char *path, hsbd_error *err) {
    hsbd_error_clear(err);
    FILE *f = hsbd_input_open(path, "configuration file", err);
    if (!f) return err->status;
    const int rc = hsbd_config_load_stream(cfg, f, path, err);
    fclose(f);
    return rc;
}

int hsbd_config_set(hsbd_config *cfg, const char *assignment, const char *origin, hsbd_error *err) {
    hsbd_error_clear(err);
    char buf[HSBD_PATH_MAX + 128];
    if (strlen(assignment) >= sizeof buf)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: '%.40s...' is longer than %zu characters; allowed: "
                              "section.key=value with a value of at most %d characters",
                              origin, assignment, sizeof buf - 1, HSBD_PATH_MAX - 1);
    for (const char *c = assignment; *c; ++c)
        if (((unsigned char)*c < 0x20 && *c != '\t') || *c == 0x7f)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: control character 0x%02x at position %d of the "
                                  "assignment; allowed: text",
                                  origin, (unsigned)(unsigned char)*c, (int)(c - assignment) + 1);
    strcpy(buf, assignment);
    char *eq = strchr(buf, '='), *dot = strchr(buf, '.');
    if (!eq || !dot || dot > eq)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s '%.60s': expected section.key=value (e.g. run.t_total=200)",
                              origin, assignment);
    *eq = '\0', *dot = '\0';
    const char *section = trim(buf), *key = trim(dot + 1), *value = eq + 1;
    const key_spec *k = find_key(section, key);
    if (!k) {
        char near[256];
        const char *s = suggest(section, key, near, sizeof near);
        return hsbd_error_set(err, HSBD_EINPUT, "%s: unknown key '%.60s.%.60s'%s%s%s", origin,
                              section, key, s ? "; did you mean '" : "", s ? s : "",
                              s ? "'?" : " (hsbd run --help lists all keys)");
    }
    char where[HSBD_ORIGIN_MAX];
    snprintf(where, sizeof where, "%s %s.%s", origin, section, key);
    const int rc = parse_value(cfg, k, value, origin, err);
    if (rc == HSBD_OK) snprintf(cfg->origin[key_index(k)], HSBD_ORIGIN_MAX, "%s", where);
    return rc;
}

/* ---- checks across keys ------------------------------------------------------------- */

/* Where a key got its value, for messages: for a key at its default, the configuration
 * file (when there is one), so that every message names the file. */
static const char *origin_of(const hsbd_config *cfg, const char *section, const char *key) {
    const char *o = cfg->origin[key_index(find_key(section, key))];
    return !strncmp(o, "default", 7) && cfg->file[0] ? cfg->file : o;
}

const char *hsbd_config_origin(const hsbd_config *cfg, const char *section, const char *key) {
    const key_spec *k = find_key(section, key);
    return k ? cfg->origin[key_index(k)] : "";
}

/* a / b is a whole number (relative tolerance 1e-9) */
static int divides(double b, double a) {
    const double q = a / b;
    return q >= 1.0 - 1e-9 && fabs(q - round(q)) <= 1e-9 * q;
}

uint64_t hsbd_config_steps(const hsbd_config *cfg) {
    return (uint64_t)llround(cfg->run.t_total / cfg->run.dt);
}

double hsbd_config_dt_equil(const hsbd_config *cfg) {
    return cfg->run.dt_equil > 0 ? cfg->run.dt_equil : cfg->run.dt;
}

uint64_t hsbd_config_equil_steps(const hsbd_config *cfg) {
    return (uint64_t)llround(cfg->run.t_equil / hsbd_config_dt_equil(cfg));
}

/* Split a list on spaces and commas into at most `max` words; returns the count, or
 * max + 1 when there are more. */
static size_t split_list(char *text, char **words, size_t max) {
    size_t count = 0;
    for (char *w = strtok(text, " \t,"); w; w = strtok(NULL, " \t,")) {
        if (count == max) return max + 1;
        words[count++] = w;
    }
    return count;
}

static int is_default(const hsbd_config *cfg, const char *section, const char *key) {
    return !strncmp(cfg->origin[key_index(find_key(section, key))], "default", 7);
}

/* One numeric species list (count, sigma or D): as many finite entries as names, each in
 * [min, inf) (open at min when `open`), whole numbers when `whole`. */
static int parse_species_numbers(hsbd_config *cfg, const char *key, const char *text, double min,
                                 int open, int whole, double *out, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t ns = cfg->species.n, got = split_list(buf, words, HSBD_MAX_SPECIES);
    if (got != ns)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.%s has %zu entries for %zu species.names; allowed: one "
                              "per species",
                              origin_of(cfg, "species", key), key, got, ns);
    for (size_t k = 0; k < ns; ++k) {
        double v;
        const char *why;
        if (parse_number(words[k], &v, &why) != 0 || (open ? !(v > min) : !(v >= min)) ||
            (whole && v != floor(v)))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.%s entry %zu ('%.40s', species %s) is out of range; "
                                  "allowed: decimal %s %s %g",
                                  origin_of(cfg, "species", key), key, k + 1, words[k],
                                  cfg->species.name[k], whole ? "whole numbers" : key,
                                  open ? ">" : ">=", min);
        out[k] = v;
    }
    return HSBD_OK;
}

/* Spheres: species.fraction (each > 0, summing to 1) into counts summing to system.N
 * (largest remainders). Setting both fraction and count is an error. */
static int species_counts_from_fractions(hsbd_config *cfg, double *count, hsbd_error *err) {
    if (cfg->species.count_text[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.count and species.fraction (%s) are both set; allowed: "
                              "one of them",
                              origin_of(cfg, "species", "count"),
                              origin_of(cfg, "species", "fraction"));
    double frac[HSBD_MAX_SPECIES], total = 0;
    const int rc =
        parse_species_numbers(cfg, "fraction", cfg->species.fraction_text, 0, 1, 0, frac, err);
    if (rc != HSBD_OK) return rc;
    const size_t ns = cfg->species.n;
    for (size_t k = 0; k < ns; ++k)
        total += frac[k];
    if (fabs(total - 1.0) > 1e-6)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.fraction sums to %.9g; allowed: fractions summing to 1",
                              origin_of(cfg, "species", "fraction"), total);
    const double n = (double)cfg->system.n;
    double assigned = 0;
    for (size_t k = 0; k < ns; ++k)
        count[k] = floor(frac[k] * n), assigned += count[k];
    while (assigned < n) { /* largest remainder first */
        size_t best = 0;
        double rem = -1;
        for (size_t k = 0; k < ns; ++k)
            if (frac[k] * n - count[k] > rem) rem = frac[k] * n - count[k], best = k;
        count[best] += 1, assigned += 1;
    }
    for (size_t k = 0; k < ns; ++k)
        if (count[k] < 1)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.fraction %g of species %s gives no particle of "
                                  "system.N = %lld; allowed: fraction >= 1/N",
                                  origin_of(cfg, "species", "fraction"), frac[k],
                                  cfg->species.name[k], (long long)cfg->system.n);
    return HSBD_OK;
}

/* The [species] lists: names, counts summing to system.N, lengths and D. */
static int parse_species(hsbd_config *cfg, hsbd_error *err) {
    cfg->species.n = 0;
    if (!cfg->species.names_text[0]) {
        static const char *const lists[] = {"count", "sigma", "D", "fraction"};
        for (int k = 0; k < 4; ++k)
            if (!is_default(cfg, "species", lists[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "%s: species.%s is set but species.names is empty; name the "
                                      "species first",
                                      origin_of(cfg, "species", lists[k]), lists[k]);
        return HSBD_OK;
    }
    char buf[HSBD_PATH_MAX], *words[HSBD_MAX_SPECIES + 1];
    snprintf(buf, sizeof buf, "%s", cfg->species.names_text);
    const size_t ns = split_list(buf, words, HSBD_MAX_SPECIES);
    if (ns < 1 || ns > HSBD_MAX_SPECIES)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: species.names: allowed: 1 to %d names",
                              origin_of(cfg, "species", "names"), HSBD_MAX_SPECIES);
    for (size_t k = 0; k < ns; ++k) {
        const size_t len = strlen(words[k]);
        int ok = len < HSBD_SPECIES_NAME;
        for (size_t c = 0; c < len; ++c)
            ok &= (words[k][c] >= 'a' && words[k][c] <= 'z') ||
                  (words[k][c] >= 'A' && words[k][c] <= 'Z') ||
                  (words[k][c] >= '0' && words[k][c] <= '9') || words[k][c] == '_';
        for (size_t q = 0; q < k; ++q)
            ok &= strcmp(words[q], words[k]) != 0;
        if (!ok)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: species.names entry '%s' is not allowed: names are unique, "
                                  "at most %d letters, digits or '_'",
                                  origin_of(cfg, "species", "names"), words[k],
                                  HSBD_SPECIES_NAME - 1);
        snprintf(cfg->species.name[k], HSBD_SPECIES_NAME, "%s", words[k]);
    }
    cfg->species.n = ns;
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    double count[HSBD_MAX_SPECIES];
    int rc = HSBD_OK;
    if (spheres && cfg->species.fraction_text[0])
        rc = species_counts_from_fractions(cfg, count, err);
    else
        rc = parse_species_numbers(cfg, "count", cfg->species.count_text, 1, 0, 1, count, err);
    if (rc == HSBD_OK)
        rc = parse_species_numbers(cfg, "sigma", cfg->species.sigma_text, 0, spheres, 0,
                                   cfg->species.sigma, err);
    const int stokes = spheres && cfg->species.d_law == HSBD_D_STOKES_EINSTEIN;
    if (rc == HSBD_OK && stokes && cfg->species.d_text[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.D is set, but species.D_law = stokes-einstein (%s) "
                              "derives D from system.D and system.sigma; remove one of them",
                              origin_of(cfg, "species", "D"), origin_of(cfg, "species", "D_law"));
    if (rc == HSBD_OK && stokes)
        for (size_t k = 0; k < ns; ++k) /* D_k = D_0 sigma_0 / sigma_k (Stokes-Einstein) */
            cfg->species.diffusion[k] =
                cfg->system.diffusion * cfg->system.sigma / cfg->species.sigma[k];
    else if (rc == HSBD_OK)
        rc = parse_species_numbers(cfg, "D", cfg->species.d_text, 0, !spheres, 0,
                                   cfg->species.diffusion, err);
    if (rc != HSBD_OK) return rc;
    double total = 0;
    for (size_t k = 0; k < ns; ++k)
        cfg->species.count[k] = (int64_t)count[k], total += count[k];
    if (total != (double)cfg->system.n)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: species.count sums to %.0f rods but system.N = %lld (%s); "
                              "allowed: counts summing to system.N",
                              origin_of(cfg, "species", "count"), total, (long long)cfg->system.n,
                              origin_of(cfg, "system", "N"));
    static const char *const single[] = {"sigma", "D"};
    for (int k = 0; k < 2 && !stokes; ++k) /* Stokes-Einstein: the reference D_0, sigma_0 */
        if (!is_default(cfg, "system", single[k]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: system.%s is set, but with species.names the species.%s "
                                  "list gives it; remove one of them",
                                  origin_of(cfg, "system", single[k]), single[k], single[k]);
    if (!spheres && (cfg->pair.type != HSBD_PAIR_NONE || cfg->contact.gamma > 0))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair forces and sticky contacts need one species (mixtures with "
                              "pair forces are not supported yet)",
                              origin_of(cfg, cfg->contact.gamma > 0 ? "contact" : "pair",
                                        cfg->contact.gamma > 0 ? "gamma" : "type"));
    cfg->system.sigma = cfg->species.sigma[0];
    cfg->system.diffusion = cfg->species.diffusion[0];
    return HSBD_OK;
}

/* total length of the rods */
static double rods_length(const hsbd_config *cfg) {
    if (!cfg->species.n) return (double)cfg->system.n * cfg->system.sigma;
    double total = 0;
    for (size_t k = 0; k < cfg->species.n; ++k)
        total += (double)cfg->species.count[k] * cfg->species.sigma[k];
    return total;
}

static int check_run_keys(hsbd_config *cfg, hsbd_error *err);
static int check_memory(const hsbd_config *cfg, int particles_only, hsbd_error *err);

/* Keys that only one model reads: setting one for the other model is an error, not a
 * silent no-op. */
static const char *const rods_only[][2] = {
    {"system", "L"},         {"system", "contact_rule"}, {"system", "boundary"},
    {"contact", "gamma"},    {"contact", "order"},       {"contact", "epsilon"},
    {"pair", "type"},        {"pair", "strength"},       {"pair", "kappa"},
    {"pair", "cutoff"},      {"pair", "table"},          {"field", "type"},
    {"field", "amplitude"},  {"field", "wavelength"},    {"field", "force"},
    {"field", "stiffness"},  {"field", "center"},        {"field", "table"},
    {"field", "table_kind"}, {"sample", "bin_width"},    {"sample", "contact_width"},
    {"sample", "period"},    {"sample", "blocking"},     {"sample", "current_every"},
    {"run", "dt_equil"}};
static const char *const spheres_only[][2] = {
    {"system", "dimension"},       {"system", "box"},           {"system", "packing_fraction"},
    {"system", "drift"},           {"system", "shell"},         {"species", "fraction"},
    {"sample", "gr_every"},        {"sample", "gr_max"},        {"sample", "gr_bin"},
    {"sample", "contact_fit"},     {"sample", "fs_k"},          {"init", "method"},
    {"species", "polydispersity"}, {"species", "distribution"}, {"species", "D_law"}};

/* Is section.key read only by the model this configuration does not use? */
static int key_of_other_model(const hsbd_config *cfg, const char *section, const char *key) {
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    const size_t count = spheres ? sizeof rods_only / sizeof rods_only[0]
                                 : sizeof spheres_only / sizeof spheres_only[0];
    for (size_t k = 0; k < count; ++k) {
        const char *const *other = spheres ? rods_only[k] : spheres_only[k];
        if (!strcmp(other[0], section) && !strcmp(other[1], key)) return 1;
    }
    return 0;
}

static int refuse_keys_of_other_model(const hsbd_config *cfg, hsbd_error *err) {
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    const size_t count = spheres ? sizeof rods_only / sizeof rods_only[0]
                                 : sizeof spheres_only / sizeof spheres_only[0];
    for (size_t k = 0; k < count; ++k) {
        const char *const *key = spheres ? rods_only[k] : spheres_only[k];
        if (!is_default(cfg, key[0], key[1]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s applies to system.model = %s only, but the model "
                                  "is %s (%s); remove the key",
                                  origin_of(cfg, key[0], key[1]), key[0], key[1],
                                  spheres ? "rods" : "spheres", spheres ? "spheres" : "rods",
                                  origin_of(cfg, "system", "model"));
    }
    return HSBD_OK;
}

/* A list of `dim` finite numbers (or, when one_for_all, 1 repeated) in (min, inf) or any
 * (min = -inf). */
static int parse_vector(const hsbd_config *cfg, const char *key, const char *text, int dim,
                        int one_for_all, double min, double *out, hsbd_error *err) {
    char buf[HSBD_PATH_MAX], *words[4];
    snprintf(buf, sizeof buf, "%s", text);
    const size_t got = split_list(buf, words, 3);
    if ((got != 1 || !one_for_all) && got != (size_t)dim)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: system.%s has %zu value%s; allowed: %s%d (system.dimension)",
                              origin_of(cfg, "system", key), key, got, got == 1 ? "" : "s",
                              one_for_all ? "1 or " : "", dim);
    for (int a = 0; a < dim; ++a) {
        const char *w = words[got == 1 ? 0 : a], *why;
        double v;
        if (parse_number(w, &v, &why) != 0 || !(v > min))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: system.%s value '%.40s' is out of range; allowed: finite "
                                  "decimal numbers%s",
                                  origin_of(cfg, "system", key), key, w, isinf(min) ? "" : " > 0");
        out[a] = v;
    }
    for (int a = dim; a < 3; ++a)
        out[a] = 0;
    return HSBD_OK;
}

/* particle volume (3D) or area (2D) of diameter s */
static int finalize_spheres(hsbd_config *cfg, hsbd_error *err) {
    if (refuse_keys_of_other_model(cfg, err) != HSBD_OK) return err->status;
    const int dim = (int)cfg->system.dimension;
    if (is_default(cfg, "system", "sigma")) {
        cfg->system.sigma = 1.0;
        snprintf(cfg->origin[key_index(find_key("system", "sigma"))], HSBD_ORIGIN_MAX,
                 "default (spheres)");
    }
    if (!(cfg->system.sigma > 0))
        return hsbd_error_set(err, HSBD_EINPUT, "%s: system.sigma = %g; allowed: sigma > 0",
                              origin_of(cfg, "system", "sigma"), cfg->system.sigma);
    if (parse_species(cfg, err) != HSBD_OK) return err->status;
    /* the particles' volume, from the diameters drawn with the seed when polydisperse */
    double sigma_max = 0;
    const size_t n = (size_t)cfg->system.n;
    double *sigma = malloc(n * sizeof *sigma);
    if (!sigma) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    if (hsbd_config_particles(cfg, NULL, sigma, NULL, err) != HSBD_OK)
        return free(sigma), err->status;
    const double unit[3] = {1, 1, 1}; /* phi in a unit box: the particles' volume */
    const double vp = hsbd_spheres_packing_fraction(dim, unit, n, sigma);
    for (size_t i = 0; i < n; ++i)
        sigma_max = fmax(sigma_max, sigma[i]);
    free(sigma);
    /* packing_fraction has no default: unset is its origin, not its value */
    const int has_box = cfg->system.box_text[0] != 0,
              has_phi = !is_default(cfg, "system", "packing_fraction");
    if (has_box == has_phi)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: spheres need exactly one of system.box and "
                              "system.packing_fraction (%s)",
                              origin_of(cfg, "system", has_box ? "box" : "model"),
                              has_box ? "both are set" : "neither is set");
    if (has_box) {
        if (parse_vector(cfg, "box", cfg->system.box_text, dim, 1, 0, cfg->system.box, err))
            return err->status;
    } else {
        const double side = pow(vp / cfg->system.packing_fraction, 1.0 / dim);
        for (int a = 0; a < 3; ++a)
            cfg->system.box[a] = a < dim ? side : 0;
    }
    double volume = 1;
    for (int a = 0; a < dim; ++a)
        volume *= cfg->system.box[a];
    const double phi = vp / volume;
    if (!has_phi) cfg->system.packing_fraction = phi;
    if (phi >= (dim == 3 ? 0.74 : 0.9069))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: packing fraction %g exceeds close packing (%g); allowed: a "
                              "larger box",
                              origin_of(cfg, "system", has_box ? "box" : "packing_fraction"), phi,
                              dim == 3 ? 0.7405 : 0.9069);
    if (cfg->system.drift_text[0] &&
        parse_vector(cfg, "drift", cfg->system.drift_text, dim, 0, -INF, cfg->system.drift, err))
        return err->status;
    /* what each initial state reaches: RSI stalls near 0.38 / 0.547; the compression
     * was measured to reach 0.60 / 0.72 at N = 4000 (docs/spheres.md) */
    const double phi_random = dim == 3 ? 0.30 : 0.45, phi_compress = dim == 3 ? 0.58 : 0.72;
    const double reach = cfg->init.method == HSBD_INIT_RANDOM     ? phi_random
                         : cfg->init.method == HSBD_INIT_COMPRESS ? phi_compress
                                                                  : 1;
    if (phi > reach && !cfg->init.positions[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: init.method = %s reaches packing fractions up to %g, but "
                              "phi = %g; allowed: init.method = %s, or init.positions",
                              origin_of(cfg, "init", "method"),
                              cfg->init.method == HSBD_INIT_RANDOM ? "random" : "compress", reach,
                              phi, phi > phi_compress ? "lattice" : "compress or auto");
    if (cfg->init.method == HSBD_INIT_AUTO)
        cfg->init.method = phi <= phi_random     ? HSBD_INIT_RANDOM
                           : phi <= phi_compress ? HSBD_INIT_COMPRESS
                                                 : HSBD_INIT_LATTICE;
    double half = INF;
    for (int a = 0; a < dim; ++a)
        half = fmin(half, 0.5 * cfg->system.box[a]);
    if (cfg->sample.gr_max == 0) cfg->sample.gr_max = fmin(3.0 * sigma_max, half);
    if (cfg->sample.gr_max > half)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.gr_max = %g; allowed: at most half the shortest box "
                              "length, %g",
                              origin_of(cfg, "sample", "gr_max"), cfg->sample.gr_max, half);
    if (cfg->sample.gr_bin > cfg->sample.gr_max)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: sample.gr_bin = %g exceeds sample.gr_max = %g",
                              origin_of(cfg, "sample", "gr_bin"), cfg->sample.gr_bin,
                              cfg->sample.gr_max);
    if (is_default(cfg, "sample", "every")) { /* an MSD sample costs d N: every 10 steps */
        cfg->sample.every = 10;
        snprintf(cfg->origin[key_index(find_key("sample", "every"))], HSBD_ORIGIN_MAX,
                 "default (spheres)");
    }
    if (cfg->sample.fs_k == 0)
        cfg->sample.fs_k = 2 * 3.14159265358979323846 /
                           (cfg->species.n ? cfg->species.sigma[0] : cfg->system.sigma);
    const int rc = check_run_keys(cfg, err);
    if (rc != HSBD_OK) return rc;
    if (cfg->sample.gr_every == 0) {
        const double steps = hsbd_config_steps(cfg);
        cfg->sample.gr_every = (int64_t)fmax(1.0, round(0.05 / cfg->run.dt));
        /* short runs: still at least 10 samples per error block */
        const double most = floor(steps / (10.0 * (double)cfg->sample.blocks));
        if ((double)cfg->sample.gr_every > most) cfg->sample.gr_every = (int64_t)fmax(1.0, most);
        snprintf(cfg->origin[key_index(find_key("sample", "gr_every"))], HSBD_ORIGIN_MAX,
                 "default (0.05 time units)");
    }
    const uint64_t gr_samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.gr_every;
    if (gr_samples < (uint64_t)cfg->sample.blocks)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.gr_every = %lld leaves %llu g(r) samples for "
                              "sample.blocks = %lld; allowed: at least one per block",
                              origin_of(cfg, "sample", "gr_every"), (long long)cfg->sample.gr_every,
                              (unsigned long long)gr_samples, (long long)cfg->sample.blocks);
    return check_memory(cfg, 0, err);
}

/* ---- memory ------------------------------------------------------------------------- */

/* Bytes per particle of the engines with their run drivers, measured as the slope of the
 * peak resident size over N (/usr/bin/time -v, hsbd run with t_total = 4 steps, e504a92):
 * rods 80 B (N 1e6 .. 8e6: 104 B minus the MSD's three snapshots of 8 B); spheres 3D
 * 700-850 B at phi 0.3 (N 2.5e5 .. 1e6), 2D 620-650 B, more at higher phi as the
 * neighbour lists fill (docs/config.md). The constants round those up. */
enum { RODS_BYTES = 96, SPHERES_BYTES_2D = 900, SPHERES_BYTES_3D = 1300 };
/* the share of the machine's physical memory a run may plan to use */
#define MEMORY_SHARE 0.8

/* One part of the estimate and the key that makes it large. */
typedef struct memory_part {
    double bytes;
    const char *section, *key, *what;
} memory_part;

/* The MSD observer of `items` coordinates (hsbd_msd_alloc): its snapshots, its lag table
 * (one entry per sample up to the largest lag) and its values per lag and origin (twice
 * with F_s); parts[0..2] += those. */
static void msd_memory(const hsbd_config *cfg, double items, int fs, double copies,
                       memory_part *parts) {
    const double samples = floor((double)hsbd_config_steps(cfg) / (double)cfg->sample.every);
    const double sample_dt = cfg->run.dt * (double)cfg->sample.every;
    double lmax = fmin(floor(cfg->sample.msd_max_lag / sample_dt + 1e-9), fmax(samples - 1, 0));
    lmax = fmax(lmax, 1);
    double slots = floor((128.0 * 1024 * 1024) / (8 * fmax(items, 1)));
    slots = fmin(fmax(slots, 4), 64);
    double every = fmax(floor((lmax + slots - 2) / (slots - 1)), 1);
    every = fmax(every, floor(samples / 4000));
    const double alive = floor(lmax / every) + 2, origins = floor(samples / every) + 1;
    const double lags = (double)cfg->sample.msd_points_per_decade * (log10(lmax) + 1) + 2;
    parts[0].bytes += copies * alive * items * 8;
    parts[1].bytes += copies * (lmax + 1) * 8;
    parts[2].bytes += copies * lags * origins * 8 * (fs ? 2 : 1);
}

/* the engine and its run driver: bytes per particle times N */
static memory_part particles_memory(const hsbd_config *cfg) {
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    const double per = !spheres                     ? RODS_BYTES
                       : cfg->system.dimension == 3 ? SPHERES_BYTES_3D
                                                    : SPHERES_BYTES_2D;
    return (memory_part){(double)cfg->system.n * per, "system", "N", "the particles"};
}

/* Estimated bytes of a finalized configuration's run, in parts (returns their count). */
static size_t memory_estimate(const hsbd_config *cfg, memory_part *parts) {
    const int spheres = cfg->system.model == HSBD_MODEL_SPHERES;
    const double n = (double)cfg->system.n, d = (double)cfg->system.dimension;
    const double blocks = (double)cfg->sample.blocks;
    size_t np = 0;
    parts[np++] = particles_memory(cfg);
    parts[np++] = (memory_part){0, "system", "N", "the MSD's snapshots"};
    parts[np++] = (memory_part){0, "sample", "msd_max_lag", "the MSD's lag table"};
    parts[np++] = (memory_part){0, "sample", "msd_points_per_decade", "the MSD's values"};
    /* mixtures: one more MSD per species (spheres: from two species on) */
    const double per_species = (double)cfg->species.n >= (spheres ? 2 : 1) ? cfg->species.n : 0;
    msd_memory(cfg, spheres ? d * n : n, spheres, 1 + (double)per_species, parts + 1);
    if (spheres) {
        const double pairs = cfg->species.n ? cfg->species.n * (cfg->species.n + 1) / 2.0 : 1;
        const double bins = ceil(cfg->sample.gr_max / cfg->sample.gr_bin) + 10;
        parts[np++] =
            (memory_part){pairs * bins * 8 * (3 + blocks), "sample", "gr_bin", "g(r)'s bins"};
    } else {
        const double bins = round(cfg->sample.period / cfg->sample.bin_width);
        parts[np++] =
            (memory_part){4 * bins * 8 * (1 + blocks), "sample", "bin_width", "the profiles' bins"};
    }
    return np;
}

/* The machine's physical memory in bytes (0 when unknown: nothing is refused). */
static double physical_memory(void) {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    return pages > 0 && size > 0 ? (double)pages * (double)size : 0;
}

/* Refuses a run whose estimated memory exceeds MEMORY_SHARE of the machine's, naming
 * the key behind its largest part. `particles_only`: only the particles' part (before
 * anything of size N is allocated while finalizing). */
static int check_memory(const hsbd_config *cfg, int particles_only, hsbd_error *err) {
    memory_part parts[8];
    const size_t np = particles_only ? 1 : memory_estimate(cfg, parts);
    if (particles_only) parts[0] = particles_memory(cfg);
    double total = 0;
    size_t big = 0;
    for (size_t k = 0; k < np; ++k) {
        total += parts[k].bytes;
        if (parts[k].bytes > parts[big].bytes) big = k;
    }
    const double have = physical_memory(), gib = 1024.0 * 1024 * 1024;
    if (have == 0 || total <= MEMORY_SHARE * have) return HSBD_OK;
    char value[HSBD_PATH_MAX + 64];
    const key_spec *k = find_key(parts[big].section, parts[big].key);
    format_value(cfg, k, value, sizeof value);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: %s.%s = %s: the run needs an estimated %.3g GiB of memory (%.3g "
                          "GiB for %s), more than %.0f%% of this machine's %.3g GiB; allowed: "
                          "a smaller run (docs/config.md, memory)",
                          origin_of(cfg, parts[big].section, parts[big].key), parts[big].section,
                          parts[big].key, value, total / gib, parts[big].bytes / gib,
                          parts[big].what, 100 * MEMORY_SHARE, have / gib);
}

/* Of a time (run.t_total or run.t_equil) and its step, which one a message about their
 * ratio blames: the one the user set, or of two set ones the one further from its default
 * in the direction that made the ratio bad (too_many: the time long, the step short). */
static const char *blame_time_or_step(const hsbd_config *cfg, const char *time_key,
                                      const char *step_key, int too_many) {
    const int time_set = !is_default(cfg, "run", time_key);
    const int step_set = !is_default(cfg, "run", step_key);
    if (time_set != step_set) return time_set ? time_key : step_key;
    const double t = *(const double *)cslot(cfg, find_key("run", time_key));
    const double dt = *(const double *)cslot(cfg, find_key("run", step_key));
    const double t0 = strtod(find_key("run", time_key)->def, NULL);
    const double dt0 = strtod(find_key("run", "dt")->def, NULL);
    const double time_off = too_many ? t / t0 : t0 / t, step_off = too_many ? dt0 / dt : dt / dt0;
    return time_off >= step_off ? time_key : step_key;
}

/* Between 1 and 9e15 steps in each phase (exact in double precision). */
static int check_step_counts(const hsbd_config *cfg, hsbd_error *err) {
    static const char *const times[2] = {"t_total", "t_equil"};
    const double t[2] = {cfg->run.t_total, cfg->run.t_equil};
    const double dt[2] = {cfg->run.dt, hsbd_config_dt_equil(cfg)};
    const char *const dts[2] = {"dt", cfg->run.dt_equil > 0 ? "dt_equil" : "dt"};
    for (int p = 0; p < 2; ++p) {
        if (!(t[p] / dt[p] > 9.0e15)) continue;
        const char *blamed = blame_time_or_step(cfg, times[p], dts[p], 1);
        const int time = blamed == times[p];
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.%s = %g over run.%s = %g gives %.3g steps; allowed: at most "
                              "9e15 steps (run.%s %s %g)",
                              origin_of(cfg, "run", blamed), times[p], t[p], dts[p], dt[p],
                              t[p] / dt[p], blamed,
                              time ? "<=" : ">=", time ? 9.0e15 * dt[p] : t[p] / 9.0e15);
    }
    if (cfg->run.t_total < cfg->run.dt * (1 - 1e-9)) {
        const char *blamed = blame_time_or_step(cfg, "t_total", "dt", 0);
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: run.t_total = %g is shorter than run.dt = %g; allowed: "
                              "t_total >= dt",
                              origin_of(cfg, "run", blamed), cfg->run.t_total, cfg->run.dt);
    }
    const uint64_t steps = hsbd_config_steps(cfg);
    const uint64_t samples = steps / (uint64_t)cfg->sample.every;
    const uint64_t blocks = (uint64_t)cfg->sample.blocks, most_every = steps / blocks;
    if (samples >= blocks) return HSBD_OK;
    if (!is_default(cfg, "sample", "every") && most_every >= 1)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.every = %lld leaves %llu samples in the %llu steps of "
                              "run.t_total/run.dt, fewer than sample.blocks = %llu; allowed: 1 "
                              "<= every <= %llu",
                              origin_of(cfg, "sample", "every"), (long long)cfg->sample.every,
                              (unsigned long long)samples, (unsigned long long)steps,
                              (unsigned long long)blocks, (unsigned long long)most_every);
    if (!is_default(cfg, "sample", "blocks") && samples >= 2)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.blocks = %llu needs at least as many samples, but "
                              "t_total/(dt*every) = %llu; allowed: 2 <= blocks <= %llu",
                              origin_of(cfg, "sample", "blocks"), (unsigned long long)blocks,
                              (unsigned long long)samples, (unsigned long long)samples);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s: run.t_total = %g gives %llu steps and %llu samples (sample.every = "
                          "%lld), fewer than sample.blocks = %llu; allowed: t_total >= %g",
                          origin_of(cfg, "run", "t_total"), cfg->run.t_total,
                          (unsigned long long)steps, (unsigned long long)samples,
                          (long long)cfg->sample.every, (unsigned long long)blocks,
                          (double)blocks * (double)cfg->sample.every * cfg->run.dt);
}

/* Checks of the run, sampling and output keys shared by every model. */
static int check_run_keys(hsbd_config *cfg, hsbd_error *err) {
    if (check_step_counts(cfg, err) != HSBD_OK) return err->status;
    const int replicas = cfg->sample.blocking == HSBD_BLOCKS_REPLICAS;
    const double lag_limit = replicas ? cfg->run.t_total / (double)cfg->sample.blocks
                                      : cfg->run.t_total; /* a replica's production time */
    if (cfg->sample.msd_max_lag == 0)
        cfg->sample.msd_max_lag = fmin(cfg->run.t_total / 10, lag_limit);
    if (cfg->sample.msd_max_lag > lag_limit * (1 + 1e-12))
        return hsbd_error_set(
            err, HSBD_EINPUT, "%s: sample.msd_max_lag = %g exceeds %s = %g",
            origin_of(cfg, "sample", "msd_max_lag"), cfg->sample.msd_max_lag,
            replicas ? "a replica's time run.t_total/sample.blocks" : "run.t_total", lag_limit);
    if (cfg->output.trajectory_every == 0) /* the default never refuses a short run */
        cfg->output.trajectory_every = fmax(cfg->run.t_total / 100, cfg->run.dt);
    if (cfg->output.trajectory_every < cfg->run.dt)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: output.trajectory_every = %g is shorter than run.dt = %g",
                              origin_of(cfg, "output", "trajectory_every"),
                              cfg->output.trajectory_every, cfg->run.dt);
    if (cfg->sample.current_every > 0 && cfg->sample.current_every < cfg->run.dt)
        return hsbd_error_set(
            err, HSBD_EINPUT, "%s: sample.current_every = %g is shorter than run.dt = %g",
            origin_of(cfg, "sample", "current_every"), cfg->sample.current_every, cfg->run.dt);
    return HSBD_OK;
}

int hsbd_config_finalize(hsbd_config *cfg, hsbd_error *err) {
    hsbd_error_clear(err);
    if (check_memory(cfg, 1, err) != HSBD_OK) return err->status; /* before N-sized arrays */
    if (cfg->system.model == HSBD_MODEL_SPHERES) return finalize_spheres(cfg, err);
    if (refuse_keys_of_other_model(cfg, err) != HSBD_OK) return err->status;
    if (parse_species(cfg, err) != HSBD_OK) return err->status;
    const double L = cfg->system.length, sigma = cfg->system.sigma;
    const double occupied = rods_length(cfg);
    if (!(occupied < L)) {
        char allowed[96];
        if (cfg->species.n)
            snprintf(allowed, sizeof allowed, "sum of species.count x species.sigma < L");
        else
            snprintf(allowed, sizeof allowed, "N < %g", sigma > 0 ? L / sigma : INF);
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: system.N = %lld rods of total length %g do not fit in system.L "
                              "= %g (no room); allowed: %s",
                              origin_of(cfg, "system", "N"), (long long)cfg->system.n, occupied, L,
                              allowed);
    }
    if (cfg->sample.contact_width == 0) {
        double d = cfg->system.diffusion;
        for (size_t k = 0; k < cfg->species.n; ++k)
            d = fmax(d, cfg->species.diffusion[k]);
        cfg->sample.contact_width = fmax(1e-2, 3 * sqrt(4 * d * cfg->run.dt));
        snprintf(cfg->origin[key_index(find_key("sample", "contact_width"))], HSBD_ORIGIN_MAX,
                 "default (derived from run.dt)");
    }
    if (cfg->pair.type != HSBD_PAIR_NONE && !cfg->system.hard_core)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type needs system.hard_core = on (pair forces act between "
                              "neighbours in ring order)",
                              origin_of(cfg, "pair", "type"));
    if (cfg->contact.gamma > 0 && !cfg->system.hard_core)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: contact.gamma > 0 needs system.hard_core = on",
                              origin_of(cfg, "contact", "gamma"));
    if (cfg->pair.type == HSBD_PAIR_YUKAWA || cfg->pair.type == HSBD_PAIR_LJ) {
        if (cfg->pair.cutoff == 0) {
            cfg->pair.cutoff =
                cfg->pair.type == HSBD_PAIR_YUKAWA ? sigma + 5.0 / cfg->pair.kappa : 2.5 * sigma;
            snprintf(cfg->origin[key_index(find_key("pair", "cutoff"))], HSBD_ORIGIN_MAX,
                     "default (derived from pair.type)");
        }
        if (!(cfg->pair.cutoff > sigma) || !(cfg->pair.cutoff <= 0.5 * L))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: pair.cutoff = %g out of range; allowed: system.sigma = %g "
                                  "< cutoff <= L/2 = %g",
                                  origin_of(cfg, "pair", "cutoff"), cfg->pair.cutoff, sigma,
                                  0.5 * L);
    }
    if (cfg->pair.type == HSBD_PAIR_TABLE && !cfg->pair.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: pair.type = table needs pair.table = <file with 'r f(r)' lines>",
                              origin_of(cfg, "pair", "type"));
    if (cfg->contact.gamma > 0 && !(sigma + cfg->contact.epsilon <= 0.5 * L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: contact.epsilon = %g out of range; allowed: sigma + epsilon <= "
                              "L/2 = %g",
                              origin_of(cfg, "contact", "epsilon"), cfg->contact.epsilon, 0.5 * L);
    const int walls = cfg->system.boundary == HSBD_BOUNDARY_WALLS;
    const int has_cosine = (cfg->field.type & HSBD_FIELD_COSINE) != 0;
    if (has_cosine && !walls && !divides(cfg->field.wavelength, L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.wavelength = %g must divide system.L = %g (the ring is "
                              "periodic)",
                              origin_of(cfg, "field", "wavelength"), cfg->field.wavelength, L);
    if ((cfg->field.type & HSBD_FIELD_TABLE) && !cfg->field.table[0])
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: field.type with table needs field.table = <file with 'x value' "
                              "lines covering [0, L]>",
                              origin_of(cfg, "field", "type"));
    if (isnan(cfg->field.center)) {
        cfg->field.center = 0.5 * L;
        snprintf(cfg->origin[key_index(find_key("field", "center"))], HSBD_ORIGIN_MAX,
                 "default (L/2)");
    }
    if (isnan(cfg->sample.period)) {
        cfg->sample.period = has_cosine && !walls ? cfg->field.wavelength : L;
        if (!divides(cfg->sample.period, L)) cfg->sample.period = L;
        snprintf(cfg->origin[key_index(find_key("sample", "period"))], HSBD_ORIGIN_MAX,
                 walls ? "default (L: walls)" : "default (field.wavelength or L)");
    }
    if (walls && cfg->sample.period != L)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.period = %g, but with system.boundary = walls the "
                              "profile covers the whole box; allowed: sample.period = L = %g",
                              origin_of(cfg, "sample", "period"), cfg->sample.period, L);
    if (!divides(cfg->sample.period, L))
        return hsbd_error_set(err, HSBD_EINPUT, "%s: sample.period = %g must divide system.L = %g",
                              origin_of(cfg, "sample", "period"), cfg->sample.period, L);
    if (!divides(cfg->sample.bin_width, cfg->sample.period))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.bin_width = %g must divide sample.period = %g into a "
                              "whole number of bins",
                              origin_of(cfg, "sample", "bin_width"), cfg->sample.bin_width,
                              cfg->sample.period);
    /* the profile keeps four accumulators per bin and error block */
    const double profile_bytes =
        cfg->sample.period / cfg->sample.bin_width * ((double)cfg->sample.blocks + 1) * 4 * 8;
    if (profile_bytes > 4.0 * 1024 * 1024 * 1024)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.bin_width = %g gives %.3g bins over sample.period = %g, "
                              "%.1f GiB of profile accumulators with %lld blocks; allowed: at most "
                              "4 GiB (a wider bin, or fewer blocks)",
                              origin_of(cfg, "sample", "bin_width"), cfg->sample.bin_width,
                              cfg->sample.period / cfg->sample.bin_width, cfg->sample.period,
                              profile_bytes / (1024.0 * 1024 * 1024),
                              (long long)cfg->sample.blocks);
    if (cfg->sample.blocking == HSBD_BLOCKS_SPACE &&
        !divides((double)cfg->sample.blocks * cfg->sample.period, L))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: sample.blocks = %lld must divide the number of periods "
                              "L/period = %g when sample.blocking = space",
                              origin_of(cfg, "sample", "blocks"), (long long)cfg->sample.blocks,
                              L / cfg->sample.period);
    if (check_run_keys(cfg, err) != HSBD_OK) return err->status;
    return check_memory(cfg, 0, err);
}

/* ---- writers ------------------------------------------------------------------------ */

void hsbd_config_write_header(const hsbd_config *cfg, FILE *out, const char *prefix) {
    char v[HSBD_PATH_MAX + 64];
    for (size_t i = 0; i < NKEYS; ++i) {
        /* where the run was written, and how often it was checkpointed, are not
         * parameters of the results: tables stay byte-identical */
        if (!strcmp(schema[i].section, "output") &&
            (!strcmp(schema[i].key, "dir") || !strncmp(schema[i].key, "checkpoint", 10)))
            continue;
        if (key_of_other_model(cfg, schema[i].section, schema[i].key)) continue; /* not read */
        format_value(cfg, &schema[i], v, sizeof v);
        fprintf(out, "%s%s.%s = %s\n", prefix, schema[i].section, schema[i].key, v);
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
    for (size_t i = 0; i < NKEYS; ++i) {
        const key_spec *k = &schema[i];
        const int first_in_section = i == 0 || strcmp(schema[i - 1].section, k->section);
        const int last_in_section = i + 1 == NKEYS || strcmp(schema[i + 1].section, k->section);
        if (first_in_section) fprintf(out, "\n%*s\"%s\": {", indent + 2, "", k->section);
        format_value(cfg, k, v, sizeof v);
        fprintf(out, "\n%*s\"%s\": ", indent + 4, "", k->key);
        if (k->type == K_STRING || k->type == K_ENUM || k->type == K_BOOL || k->type == K_TERMS)
            json_string(out, v);
        else if (k->type == K_DOUBLE && !isfinite(*(const double *)cslot(cfg, k)))
            fputs("null", out); /* unset (a key of the other model) */
        else
            fputs(v, out);
        if (!last_in_section)
            fputc(',', out);
        else
            fprintf(out, "\n%*s}%s", indent + 2, "", i + 1 == NKEYS ? "" : ",");
    }
    fprintf(out, "\n%*s}", indent, "");
}

void hsbd_config_write_reference(FILE *out, int markdown) {
    char range[160];
    if (markdown) {
        fprintf(out,
                "# Configuration reference\n\n"
                "Generated from the schema table in `src/io/config.c` by `hsbd config-doc`;\n"
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
    for (size_t i = 0; i < NKEYS; ++i) {
        const key_spec *k = &schema[i];
        format_range(k, range, sizeof range);
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
        for (size_t i = 0; i < NAUTHORS; ++i)
            fprintf(out, "| `%s` | `%s.%s` |\n", authors_keys[i].name, authors_keys[i].section,
                    authors_keys[i].key);
    }
}

int hsbd_config_particles(const hsbd_config *cfg, int *species, double *sigma, double *diffusion,
                          hsbd_error *err) {
    const size_t n = (size_t)cfg->system.n;
    double *mean = malloc(n * sizeof *mean);
    if (!mean) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    size_t i = 0;
    for (size_t k = 0; k < (cfg->species.n ? cfg->species.n : 1); ++k) {
        const size_t count = cfg->species.n ? (size_t)cfg->species.count[k] : n;
        for (size_t c = 0; c < count && i < n; ++c, ++i) {
            mean[i] = cfg->species.n ? cfg->species.sigma[k] : cfg->system.sigma;
            if (species) species[i] = (int)k;
            if (diffusion)
                diffusion[i] = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
        }
    }
    double *out = sigma ? sigma : malloc(n * sizeof *out);
    int rc = out ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory for N = %zu", n);
    if (rc == HSBD_OK)
        rc = hsbd_spheres_draw_diameters(cfg->system.seed, n, mean, cfg->species.polydispersity,
                                         (hsbd_size_distribution)cfg->species.distribution, out,
                                         err);
    for (size_t q = 0; rc == HSBD_OK && diffusion && q < n; ++q)
        if (cfg->species.d_law == HSBD_D_STOKES_EINSTEIN) diffusion[q] *= mean[q] / out[q];
    if (!sigma) free(out);
    free(mean);
    return rc;
}
