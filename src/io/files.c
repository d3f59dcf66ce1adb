/* Atomic output files and the rods' initial positions (see hsbd/io.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/input.h"
#include "hsbd/io.h"

int hsbd_outfile_open(hsbd_outfile *o, const char *dir, const char *name, hsbd_error *err) {
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    snprintf(o->tmp, sizeof o->tmp, "%s.part", o->path);
    o->f = fopen(o->tmp, "w+"); /* read too: the GSD index moves */
    if (!o->f)
        return hsbd_error_set(err, HSBD_EIO, "cannot write '%s': %s", o->tmp, strerror(errno));
    return HSBD_OK;
}

int hsbd_outfile_commit(hsbd_outfile *o, hsbd_error *err) {
    if (!o->f) return HSBD_OK;
    int bad = fflush(o->f) != 0 || ferror(o->f);
    if (!bad) fsync(fileno(o->f));
    bad |= fclose(o->f) != 0;
    o->f = NULL;
    if (bad) {
        remove(o->tmp);
        return hsbd_error_set(err, HSBD_EIO, "writing '%s' failed: %s", o->path, strerror(errno));
    }
    if (rename(o->tmp, o->path) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", o->tmp, o->path,
                              strerror(errno));
    return HSBD_OK;
}

int hsbd_outfile_can_reopen(const char *dir, const char *name, int64_t length, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 64], tmp[HSBD_PATH_MAX + 72];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(tmp, sizeof tmp, "%s.part", path);
    struct stat st;
    const char *found = stat(tmp, &st) == 0 ? tmp : stat(path, &st) == 0 ? path : NULL;
    if (!found)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': neither it nor '%s' can be opened (%s)", path,
                              tmp, strerror(errno));
    if (!S_ISREG(st.st_mode) || access(found, R_OK | W_OK) != 0)
        return hsbd_error_set(err, HSBD_EINPUT, "cannot continue '%s': not a writable file", found);
    if (st.st_size < length)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': it has %lld bytes, the checkpoint counts %lld",
                              found, (long long)st.st_size, (long long)length);
    return HSBD_OK;
}

int hsbd_outfile_reopen(hsbd_outfile *o, const char *dir, const char *name, int64_t length,
                        hsbd_error *err) {
    if (hsbd_outfile_can_reopen(dir, name, length, err) != HSBD_OK) return err->status;
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    snprintf(o->tmp, sizeof o->tmp, "%s.part", o->path);
    struct stat st;
    if (stat(o->tmp, &st) != 0 && rename(o->path, o->tmp) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", o->path, o->tmp,
                              strerror(errno));
    o->f = fopen(o->tmp, "r+");
    if (!o->f)
        return hsbd_error_set(err, HSBD_EIO, "cannot open '%s': %s", o->tmp, strerror(errno));
    if (ftruncate(fileno(o->f), (off_t)length) != 0 || fseeko(o->f, length, SEEK_SET) != 0) {
        fclose(o->f), o->f = NULL;
        return hsbd_error_set(err, HSBD_EIO, "cannot cut '%s' back to %lld bytes: %s", o->tmp,
                              (long long)length, strerror(errno));
    }
    return HSBD_OK;
}

void hsbd_outfile_discard(hsbd_outfile *o) {
    if (!o->f) return;
    fclose(o->f);
    o->f = NULL;
    remove(o->tmp);
}

/* species name -> index, or -1 */
static int species_index(const char *word, size_t nspecies,
                         const char (*names)[HSBD_SPECIES_NAME]) {
    for (size_t k = 0; k < nspecies; ++k)
        if (!strcmp(word, names[k])) return (int)k;
    return -1;
}

/* one rod as read: its position (0 for L on a ring), length and line */
typedef struct read_rod {
    double x, sigma;
    long line;
} read_rod;

static int compare_rods(const void *a, const void *b) {
    const double xa = ((const read_rod *)a)->x, xb = ((const read_rod *)b)->x;
    return (xa > xb) - (xa < xb);
}

static int is_blank_char(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* One line "x" or "x name" into *x and *sp; HSBD_EINPUT naming the line otherwise. */
static int parse_position_line(const hsbd_lines *in, const hsbd_config *cfg, double *x, int *sp,
                               hsbd_error *err) {
    const size_t ns = cfg->species.n;
    const char *s = in->text;
    while (is_blank_char(*s))
        ++s;
    const size_t len = hsbd_scan_decimal(s, x);
    const char *e = s + len;
    char word[HSBD_SPECIES_NAME + 1] = "";
    size_t wl = 0;
    if (len > 0 && ns > 0 && is_blank_char(*e)) {
        while (is_blank_char(*e))
            ++e;
        while (*e && !is_blank_char(*e) && wl < HSBD_SPECIES_NAME)
            word[wl++] = *e++;
        word[wl] = '\0';
    }
    while (is_blank_char(*e))
        ++e;
    if (len == 0 || *e != '\0' || !isfinite(*x) || (ns > 0 && !wl))
        return hsbd_error_set(err, HSBD_EINPUT, "%s:%ld: expected %s per line, got '%.40s'",
                              in->name, in->number,
                              ns ? "a finite position and a species name" : "one finite number", s);
    *sp = 0;
    if (ns > 0 && (*sp = species_index(word, ns, cfg->species.name)) < 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: unknown species '%.40s'; allowed: the species.names",
                              in->name, in->number, word);
    return HSBD_OK;
}

/* the rod inside the ring [0, L] (L is 0 again) or between the walls */
static int check_position(const hsbd_lines *in, const hsbd_config *cfg, double x, double sigma,
                          hsbd_error *err) {
    const double L = cfg->system.length, half = 0.5 * sigma;
    if (cfg->system.boundary == HSBD_BOUNDARY_WALLS) {
        if (x < half * (1 - 1e-12) || x > L - half * (1 - 1e-12))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: x = %.17g is outside the walls: allowed sigma/2 = %g "
                                  "<= x <= L - sigma/2 = %g",
                                  in->name, in->number, x, half, L - half);
    } else if (!(x >= 0 && x <= L)) {
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: x = %.17g is outside the ring; allowed: 0 <= x <= L = %g "
                              "(positions are not wrapped)",
                              in->name, in->number, x, L);
    }
    return HSBD_OK;
}

/* No two rods closer than their contact distance (on a ring also across x = 0 = L). */
static int check_overlaps(const char *name, const hsbd_config *cfg, read_rod *r, size_t n,
                          hsbd_error *err) {
    const double L = cfg->system.length;
    const int ring = cfg->system.boundary != HSBD_BOUNDARY_WALLS;
    const double tol = 1e-12 * (cfg->system.sigma > 0 ? cfg->system.sigma : 1.0);
    qsort(r, n, sizeof *r, compare_rods);
    for (size_t i = 0; n > 1 && i < (ring ? n : n - 1); ++i) {
        const size_t j = i + 1 < n ? i + 1 : 0;
        const double next = i + 1 < n ? r[j].x : r[0].x + L;
        const double contact = 0.5 * (r[i].sigma + r[j].sigma);
        if (next - r[i].x - contact < -tol)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: the rod at x = %.17g and the one at line %ld (x = "
                                  "%.17g) overlap: distance %.17g < contact distance %g; allowed: "
                                  "no overlaps",
                                  name, r[i].line, r[i].x, r[j].line, r[j].x, next - r[i].x,
                                  contact);
    }
    return HSBD_OK;
}

int hsbd_read_positions_stream(FILE *f, const char *name, const hsbd_config *cfg, double *x,
                               int *species, hsbd_error *err) {
    hsbd_error_clear(err);
    const size_t n = (size_t)cfg->system.n;
    read_rod *rods = malloc((n ? n : 1) * sizeof *rods);
    if (!rods) return hsbd_error_set(err, HSBD_ENOMEM, "%s: out of memory for N = %zu", name, n);
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    size_t count = 0;
    int got, rc = HSBD_OK;
    while (rc == HSBD_OK && (got = hsbd_lines_next(&in, err)) > 0) {
        const char *s = in.text;
        while (is_blank_char(*s))
            ++s;
        if (*s == '#' || *s == '\0') continue;
        if (count == n) {
            rc = hsbd_error_set(err, HSBD_EINPUT, "%s:%ld: more positions than system.N = %zu",
                                name, in.number, n);
            break;
        }
        double v;
        int sp = 0;
        if ((rc = parse_position_line(&in, cfg, &v, &sp, err)) != HSBD_OK) break;
        const double sigma = cfg->species.n ? cfg->species.sigma[sp] : cfg->system.sigma;
        if ((rc = check_position(&in, cfg, v, sigma, err)) != HSBD_OK) break;
        if (species) species[count] = sp;
        x[count] = v;
        const int ring = cfg->system.boundary != HSBD_BOUNDARY_WALLS;
        rods[count++] = (read_rod){ring && v == cfg->system.length ? 0 : v, sigma, in.number};
    }
    if (rc == HSBD_OK && got < 0) rc = err->status;
    hsbd_lines_free(&in);
    if (rc == HSBD_OK && count != n)
        rc = hsbd_error_set(err, HSBD_EINPUT, "%s: %zu positions for system.N = %zu", name, count,
                            n);
    if (rc == HSBD_OK && cfg->system.hard_core) rc = check_overlaps(name, cfg, rods, n, err);
    free(rods);
    return rc;
}

int hsbd_read_positions(const hsbd_config *cfg, double *x, int *species, hsbd_error *err) {
    const char *path = cfg->init.positions;
    FILE *f = hsbd_input_open(path, "init.positions file", err);
    if (!f) return err->status;
    const int rc = hsbd_read_positions_stream(f, path, cfg, x, species, err);
    fclose(f);
    return rc;
}
