/* Extended XYZ: trajectory frames of rods and spheres, and one frame of spheres read back as
 * the initial state (init.positions). The reader accepts what the writers write and refuses,
 * with the file and line, whatever does not fit the configuration: another count, a box
 * that disagrees, a coordinate outside the box, an unknown species. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/input.h"
#include "hsbd/io.h"
#include "io/orientation.h"

/* rods: positions on x, their radius, the exact unwrapped position; disks and spheres:
 * positions, radius, image counters (OVITO and ASE read both); active ones also their
 * orientation, as OVITO's Orientation quaternion (x y z w: the rotation of the body's x
 * axis onto e) and as the unit vector e in OVITO's dipole column (drawn as arrows) */
void hsbd_xyz_write(FILE *f, const hsbd_frame *fr) {
    const int rods = fr->dimension == 1, three = fr->dimension == 3;
    const char *active = fr->orientation ? ":orientation:R:4:dipoles:R:3" : "";
    fprintf(f, "%zu\n", fr->n);
    if (rods)
        fprintf(f,
                "Lattice=\"%.17g 0 0 0 1 0 0 0 1\" pbc=\"%s F F\" Time=%.17g Step=%llu "
                "Properties=species:S:1:pos:R:3:radius:R:1:x_unwrapped:R:1:id:I:1\n",
                fr->box[0], fr->periodic[0] ? "T" : "F", fr->time, (unsigned long long)fr->step);
    else
        fprintf(f,
                "Lattice=\"%.17g 0 0 0 %.17g 0 0 0 %.17g\" pbc=\"%c %c %c\" Time=%.17g Step=%llu "
                "Properties=species:S:1:pos:R:3:radius:R:1:image:I:3:id:I:1%s\n",
                fr->box[0], fr->box[1], three ? fr->box[2] : 1.0, fr->periodic[0] ? 'T' : 'F',
                fr->periodic[1] ? 'T' : 'F', three && fr->periodic[2] ? 'T' : 'F', fr->time,
                (unsigned long long)fr->step, active);
    for (size_t i = 0; i < fr->n; ++i) {
        const char *name = fr->names && fr->species ? fr->names[fr->species[i]] : fr->one_name;
        const double *x = fr->x + 3 * i;
        if (rods)
            fprintf(f, "%s %.10g 0 0 %.10g %.15g %zu\n", name, x[0], 0.5 * fr->diameter[i],
                    fr->unwrapped[i], i + 1);
        else
            fprintf(f, "%s %.10g %.10g %.10g %.10g %lld %lld %lld %zu", name, x[0], x[1], x[2],
                    0.5 * fr->diameter[i], (long long)fr->image[3 * i],
                    (long long)fr->image[3 * i + 1], (long long)fr->image[3 * i + 2], i + 1);
        if (fr->orientation && !rods) {
            const double *e = fr->orientation + 3 * i;
            double q[4];
            hsbd_orientation_quaternion(e, q);
            fprintf(f, " %.10g %.10g %.10g %.10g %.10g %.10g %.10g", q[1], q[2], q[3], q[0], e[0],
                    e[1], e[2]);
        }
        if (!rods) fputc('\n', f);
    }
}

/* ---- reading ---------------------------------------------------------------------------- */

static int is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* Splits s in place into at most max whitespace-separated words; returns the count. */
static size_t split_words(char *s, char **words, size_t max) {
    size_t n = 0;
    while (n < max) {
        while (is_space(*s))
            ++s;
        if (!*s) break;
        words[n++] = s;
        while (*s && !is_space(*s))
            ++s;
        if (*s) *s++ = '\0';
    }
    return n;
}

/* the whole word is one finite decimal number */
static int word_number(const char *w, double *v) {
    const size_t len = hsbd_scan_decimal(w, v);
    return len > 0 && w[len] == '\0' && isfinite(*v);
}

static int blank(const char *s) {
    while (is_space(*s))
        ++s;
    return *s == '\0';
}

/* The non-blank lines left after the comment line (the frame's particle lines), or -1 */
static long particle_lines_left(hsbd_lines *in, hsbd_error *err) {
    long lines = 0;
    int got = hsbd_lines_next(in, err); /* the comment line */
    while (got > 0 && (got = hsbd_lines_next(in, err)) > 0)
        lines += !blank(in->text);
    return got < 0 ? -1 : lines;
}

/* line 1: the particle count, a whole number alone on its line */
static int parse_count(hsbd_lines *in, size_t *count, hsbd_error *err) {
    const int got = hsbd_lines_next(in, err);
    if (got < 0) return err->status;
    if (got == 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: the file is empty; expected an XYZ frame (the number of "
                              "particles on line 1)",
                              in->name);
    char *w[2];
    const size_t nw = split_words(in->text, w, 2);
    *count = 0;
    int ok = nw == 1 && w[0][0] >= '0' && w[0][0] <= '9' && strlen(w[0]) <= 18;
    for (const char *c = ok ? w[0] : ""; ok && *c; ++c) {
        ok = *c >= '0' && *c <= '9';
        *count = 10 * *count + (size_t)(*c - '0');
    }
    if (!ok)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:1: expected the number of particles (a whole number alone on "
                              "the line) at the start of an XYZ frame",
                              in->name);
    return HSBD_OK;
}

/* line 1: the count, equal to system.N (when not: the particle lines counted, to say which
 * of the two is off) */
static int read_count(hsbd_lines *in, const hsbd_xyz_expect *e, hsbd_error *err) {
    size_t count;
    if (parse_count(in, &count, err) != HSBD_OK) return err->status;
    if (count == e->n) return HSBD_OK;
    const long lines = particle_lines_left(in, err);
    if (lines < 0) return err->status;
    if ((size_t)lines != count)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:1: the count line says %zu, the file has %ld particle lines "
                              "(and system.N = %zu)",
                              in->name, count, lines, e->n);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "%s:1: the XYZ file has %zu particles; allowed: system.N = %zu", in->name,
                          count, e->n);
}

/* Lattice="a1 a2 a3 b1 b2 b3 c1 c2 c3" on the comment line: *has (0 without one) and its
 * nine numbers */
static int parse_lattice(const hsbd_lines *in, double m[9], int *has, hsbd_error *err) {
    const char *p = strstr(in->text, "Lattice=\"");
    *has = p != NULL;
    if (!p) return HSBD_OK;
    p += strlen("Lattice=\"");
    for (int k = 0; k < 9; ++k) {
        while (is_space(*p))
            ++p;
        const size_t len = hsbd_scan_decimal(p, &m[k]);
        if (len == 0 || !isfinite(m[k]) || !(is_space(p[len]) || p[len] == '"'))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:2: Lattice=\"...\" needs 9 finite numbers (three box "
                                  "vectors)",
                                  in->name);
        p += len;
    }
    while (is_space(*p))
        ++p;
    if (*p != '"')
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:2: Lattice=\"...\" needs 9 finite numbers and a closing '\"'",
                              in->name);
    return HSBD_OK;
}

/* the Lattice, when present: a diagonal box equal to the configuration's (the third vector
 * of a 2D frame is not a length) */
static int check_lattice(const hsbd_lines *in, const hsbd_xyz_expect *e, hsbd_error *err) {
    double m[9];
    int has;
    if (parse_lattice(in, m, &has, err) != HSBD_OK || !has) return err->status;
    int same = 1;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            const double v = m[3 * a + b];
            if (a != b)
                same &= v == 0;
            else if (a < e->dimension)
                same &= fabs(v - e->box[a]) <= 1e-9 * e->box[a];
        }
    if (!same)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:2: the frame's Lattice (%.10g x %.10g%s%.10g) is not the box "
                              "of the configuration (%.10g x %.10g%s%.10g); allowed: the same "
                              "box, axis-aligned",
                              in->name, m[0], m[4], e->dimension == 3 ? " x " : "",
                              e->dimension == 3 ? m[8] : NAN, e->box[0], e->box[1],
                              e->dimension == 3 ? " x " : "", e->dimension == 3 ? e->box[2] : NAN);
    return HSBD_OK;
}

/* Properties=..., when present: species first, then the three coordinates (and the radius
 * when it is read), as hsbd writes them */
static int check_properties(const hsbd_lines *in, const hsbd_xyz_expect *e, hsbd_error *err) {
    const char *p = strstr(in->text, "Properties=");
    if (!p) return HSBD_OK;
    p += strlen("Properties=");
    const char *want = e->radius_reason ? "species:S:1:pos:R:3:radius:R:1" : "species:S:1:pos:R:3";
    if (strncmp(p, want, strlen(want)) != 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:2: Properties= must begin with %s (the columns hsbd reads)",
                              in->name, want);
    return HSBD_OK;
}

static int species_of(const char *word, const hsbd_xyz_expect *e) {
    if (e->nspecies == 0) return strcmp(word, HSBD_XYZ_ONE_SPECIES) ? -1 : 0;
    for (size_t k = 0; k < e->nspecies; ++k)
        if (!strcmp(word, e->names[k])) return (int)k;
    return -1;
}

/* One particle line: "name x y z [radius ...]" (z may be left out in 2D unless the radius
 * is read; it is then 0). */
static int read_particle(hsbd_lines *in, const hsbd_xyz_expect *e, size_t i, double *x,
                         int *species, double *radius, hsbd_error *err) {
    char *w[6];
    const size_t nw = split_words(in->text, w, 6);
    const int dim = e->dimension;
    const size_t need = e->radius_reason ? 5 : (size_t)(1 + dim);
    if (nw < need) {
        if (e->radius_reason)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: expected 'name x y z radius' with radius > 0, as hsbd "
                                  "writes trajectories (%s)",
                                  in->name, in->number, e->radius_reason);
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: expected 'name x y%s' (particle %zu of %zu)", in->name,
                              in->number, dim == 3 ? " z" : "", i + 1, e->n);
    }
    const int sp = species_of(w[0], e);
    if (sp < 0) {
        char names[HSBD_MAX_SPECIES * (HSBD_SPECIES_NAME + 2)] = "";
        for (size_t k = 0; k < e->nspecies; ++k)
            strcat(strcat(names, k ? ", " : ""), e->names[k]);
        return hsbd_error_set(err, HSBD_EINPUT, "%s:%ld: unknown species name '%.40s'; allowed: %s",
                              in->name, in->number, w[0],
                              e->nspecies ? names
                                          : HSBD_XYZ_ONE_SPECIES " (one species; a mixture "
                                                                 "names its species in "
                                                                 "species.names)");
    }
    static const char axis[] = "xyz";
    const size_t coords = nw >= 4 ? 3 : 2;
    double c[3] = {0, 0, 0};
    for (size_t a = 0; a < coords; ++a)
        if (!word_number(w[1 + a], &c[a]))
            return hsbd_error_set(err, HSBD_EINPUT, "%s:%ld: %c = '%.40s' is not a finite number",
                                  in->name, in->number, axis[a], w[1 + a]);
    for (int a = 0; a < dim; ++a)
        if (!(c[a] >= 0 && c[a] <= e->box[a] * (1 + 1e-9))) /* %.10g rounds */
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: %c = %.10g is outside the box; allowed: 0 <= %c <= "
                                  "%.10g (the box of system.box / system.packing_fraction)",
                                  in->name, in->number, axis[a], c[a], axis[a], e->box[a]);
    if (dim == 2 && c[2] != 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: z = %.10g in a 2D frame; allowed: z = 0 (system.dimension "
                              "= 2)",
                              in->name, in->number, c[2]);
    if (e->radius_reason) {
        double r;
        if (!word_number(w[4], &r) || !(r > 0))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: radius = '%.40s'; expected 'name x y z radius' with "
                                  "radius > 0, as hsbd writes trajectories (%s)",
                                  in->name, in->number, w[4], e->radius_reason);
        radius[i] = r;
    }
    species[i] = sp;
    memcpy(x + 3 * i, c, sizeof c);
    return HSBD_OK;
}

int hsbd_xyz_read_spheres(FILE *f, const char *name, const hsbd_xyz_expect *e, double *x,
                          int *species, double *radius, hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    int rc = read_count(&in, e, err);
    if (rc == HSBD_OK) {
        const int got = hsbd_lines_next(&in, err);
        if (got == 0)
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s:1: the file ends after the count; expected a comment line "
                                "(Lattice=...) and %zu particles",
                                name, e->n);
        else if (got < 0)
            rc = err->status;
    }
    if (rc == HSBD_OK) rc = check_lattice(&in, e, err);
    if (rc == HSBD_OK) rc = check_properties(&in, e, err);
    size_t have[HSBD_MAX_SPECIES] = {0};
    for (size_t i = 0; i < e->n && rc == HSBD_OK; ++i) {
        const int got = hsbd_lines_next(&in, err);
        if (got <= 0) {
            rc = got < 0 ? err->status
                         : hsbd_error_set(err, HSBD_EINPUT,
                                          "%s:1: the count line says %zu, the file has %zu "
                                          "particle lines",
                                          name, e->n, i);
            break;
        }
        rc = read_particle(&in, e, i, x, species, radius, err);
        if (rc == HSBD_OK) ++have[species[i]];
    }
    for (int got = 1; rc == HSBD_OK && got > 0;) { /* one frame, then at most blank lines */
        got = hsbd_lines_next(&in, err);
        if (got < 0) rc = err->status;
        if (got > 0 && !blank(in.text))
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s:%ld: more lines after the %zu particles of the frame; allowed: "
                                "one frame (of a trajectory, take the last %zu + 2 lines)",
                                name, in.number, e->n, e->n);
    }
    for (size_t k = 0; rc == HSBD_OK && e->count && k < e->nspecies; ++k)
        if (have[k] != (size_t)e->count[k])
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s: the file has %zu particles of species %s, species.count / "
                                "fraction asks for %lld",
                                name, have[k], e->names[k], (long long)e->count[k]);
    hsbd_lines_free(&in);
    return rc;
}

int hsbd_xyz_read_head(FILE *f, const char *name, size_t *n, double box[3], int *has_box,
                       hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    double m[9];
    int rc = parse_count(&in, n, err);
    const int got = rc == HSBD_OK ? hsbd_lines_next(&in, err) : 0;
    if (rc == HSBD_OK && got < 0) rc = err->status;
    if (rc == HSBD_OK && got == 0)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "%s:1: the file ends after the count; expected a comment line "
                            "(Lattice=...) and %zu particles",
                            name, *n);
    *has_box = 0;
    if (rc == HSBD_OK && got > 0) rc = parse_lattice(&in, m, has_box, err);
    for (int a = 0; rc == HSBD_OK && *has_box && a < 3; ++a) {
        box[a] = m[4 * a];
        if (!(box[a] > 0) || m[3 * a + (a + 1) % 3] != 0 || m[3 * a + (a + 2) % 3] != 0)
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "%s:2: the frame's Lattice is not an axis-aligned box of lengths "
                                "> 0; allowed: Lattice=\"Lx 0 0 0 Ly 0 0 0 Lz\"",
                                name);
    }
    long lines = 0; /* fewer particle lines than the count: the count is wrong */
    for (int more = got; rc == HSBD_OK && more > 0 && (size_t)lines < *n;) {
        more = hsbd_lines_next(&in, err);
        if (more < 0) rc = err->status;
        lines += more > 0 && !blank(in.text);
    }
    if (rc == HSBD_OK && (size_t)lines < *n)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "%s:1: the count line says %zu, the file has %ld particle lines", name,
                            *n, lines);
    hsbd_lines_free(&in);
    return rc;
}

int hsbd_xyz_read_positions(const hsbd_config *cfg, double *x, int *species, double *sigma,
                            hsbd_error *err) {
    const char *path = cfg->init.positions;
    char reason[HSBD_ORIGIN_MAX + 64];
    snprintf(reason, sizeof reason, "species.polydispersity > 0 at %s reads each diameter",
             hsbd_config_origin(cfg, "species", "polydispersity"));
    const int poly = cfg->species.polydispersity > 0; /* the diameters come with the positions */
    const hsbd_xyz_expect e = {.n = (size_t)cfg->system.n,
                               .dimension = (int)cfg->system.dimension,
                               .box = cfg->system.box,
                               .nspecies = cfg->species.n,
                               .names = cfg->species.name,
                               .count = cfg->species.n ? cfg->species.count : NULL,
                               .radius_reason = poly ? reason : NULL};
    FILE *f = hsbd_input_open(path, "init.positions file", err);
    if (!f) return err->status;
    const int rc = hsbd_xyz_read_spheres(f, path, &e, x, species, poly ? sigma : NULL, err);
    fclose(f);
    for (size_t i = 0; rc == HSBD_OK && poly && i < e.n; ++i)
        sigma[i] *= 2; /* the file holds radii */
    return rc;
}

/* ---- orientations (active particles) ---------------------------------------------------- */

/* The first column of `name` with `count` real values in Properties=... of the comment
 * line (columns counted from 0, the species' name being column 0), or -1. */
static long properties_column(const char *comment, const char *name, long count) {
    const char *p = strstr(comment, "Properties=");
    if (!p) return -1;
    p += strlen("Properties=");
    long column = 0;
    while (*p && !is_space(*p)) {
        char field[3][64];
        for (int k = 0; k < 3; ++k) { /* name:type:count */
            size_t len = 0;
            while (*p && *p != ':' && !is_space(*p) && len < sizeof field[k] - 1)
                field[k][len++] = *p++;
            field[k][len] = '\0';
            if (*p == ':') ++p;
        }
        const long n = strtol(field[2], NULL, 10);
        if (n < 1 || n > 64) return -1;
        if (!strcmp(field[0], name) && field[1][0] == 'R' && n == count) return column;
        column += n;
    }
    return -1;
}

int hsbd_xyz_read_orientations(const hsbd_config *cfg, double *e, int *found, hsbd_error *err) {
    hsbd_error_clear(err);
    *found = 0;
    const char *path = cfg->init.positions;
    const size_t n = (size_t)cfg->system.n;
    FILE *f = hsbd_input_open(path, "init.positions file", err);
    if (!f) return err->status;
    hsbd_lines in;
    hsbd_lines_init(&in, f, path);
    int rc = HSBD_OK;
    long column = -1;
    for (int line = 0; line < 2 && rc == HSBD_OK; ++line) /* the count, the comment */
        if (hsbd_lines_next(&in, err) <= 0)
            rc = err->status ? err->status
                             : hsbd_error_set(err, HSBD_EINPUT, "%s: no XYZ frame", path);
    if (rc == HSBD_OK) column = properties_column(in.text, "orientation", 4);
    for (size_t i = 0; rc == HSBD_OK && column > 0 && i < n; ++i) {
        if (hsbd_lines_next(&in, err) <= 0) {
            rc = err->status
                     ? err->status
                     : hsbd_error_set(err, HSBD_EINPUT, "%s: fewer than %zu particles", path, n);
            break;
        }
        char *w[80];
        const size_t nw = split_words(in.text, w, 80);
        double q[4]; /* the file's x y z w (OVITO's order) into w x y z */
        int ok = nw >= (size_t)column + 4;
        for (int k = 0; ok && k < 4; ++k)
            ok = word_number(w[column + k], &q[(k + 1) % 4]);
        double *ei = e + 3 * i;
        ok = ok && hsbd_orientation_of_quaternion(q, ei);
        if (ok && cfg->system.dimension == 2) { /* disks turn in the plane */
            const double norm = hypot(ei[0], ei[1]);
            ok = norm > 1e-6;
            if (ok) ei[0] /= norm, ei[1] /= norm, ei[2] = 0;
        }
        if (!ok)
            rc =
                hsbd_error_set(err, HSBD_EINPUT,
                               "%s:%ld: the orientation (columns %ld-%ld, quaternion x y z w) "
                               "is not four finite numbers of a rotation%s",
                               path, in.number, column + 1, column + 4,
                               cfg->system.dimension == 2 ? " about z (system.dimension = 2)" : "");
    }
    hsbd_lines_free(&in);
    fclose(f);
    *found = rc == HSBD_OK && column > 0;
    return rc;
}
