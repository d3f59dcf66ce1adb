/* Checkpoint files (see checkpoint.h). */
#include "run/checkpoint.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hsbd_version.h"

static const char magic[8] = {'H', 'S', 'B', 'D', 'C', 'K', 'P', 'T'};
enum { CHECKPOINT_FORMAT = 3 }; /* 3: the log observer's section */

/* Where the configuration came from, and the input files it read. */
static void save_source(const run *r, hsbd_writer *w) {
    const hsbd_run_source *src = r->source;
    hsbd_put_tag(w, "config");
    hsbd_put_u64(w, src != NULL);
    if (src) {
        hsbd_put_u64(w, src->name != NULL);
        hsbd_put_string(w, src->name ? src->name : "");
        hsbd_put_u64(w, src->text_len);
        hsbd_put_bytes(w, src->text, src->text_len);
        hsbd_put_u64(w, src->nsets);
        for (size_t k = 0; k < src->nsets; ++k)
            hsbd_put_string(w, src->sets[k]);
    }
    hsbd_put_string(w, r->cwd);
    hsbd_put_u64(w, r->ninputs);
    for (size_t k = 0; k < r->ninputs; ++k) {
        hsbd_put_string(w, r->inputs[k].path);
        hsbd_put_u64(w, r->inputs[k].crc);
    }
}

/* The lifecycle's own counters. */
static void save_run(const run *r, hsbd_writer *w) {
    hsbd_put_tag(w, "run");
    hsbd_put_u64(w, (uint64_t)r->stage);
    hsbd_put_u64(w, r->stage_steps);
    hsbd_put_u64(w, r->steps_done);
    hsbd_put_u64(w, r->equil_done);
    hsbd_put_u64(w, r->replicas_started);
    hsbd_put_u64(w, r->resumes);
    const double times[4] = {r->wall_equil, r->wall_prod, r->cpu_equil, r->cpu_prod};
    hsbd_put_f64s(w, times, 4);
    hsbd_put_tag(w, "streams");
    hsbd_put_u64(w, r->nstreams);
    for (size_t k = 0; k < r->nstreams; ++k) {
        const run_stream *s = &r->streams[k];
        hsbd_put_string(w, s->name);
        hsbd_put_i64(w, s->committed);
        if (!s->is_gsd) continue;
        const uint64_t layout[4] = {s->gsd.index_location, s->gsd.index_capacity, s->gsd.entries,
                                    s->gsd.frames};
        hsbd_put_u64s(w, layout, 4);
    }
}

/* Every stream's bytes so far reach the disk; their lengths go into the checkpoint. */
static int sync_streams(run *r, hsbd_error *err) {
    for (size_t k = 0; k < r->nstreams; ++k) {
        run_stream *s = &r->streams[k];
        if (!s->file.f) continue;
        if (fflush(s->file.f) != 0 || fsync(fileno(s->file.f)) != 0)
            return hsbd_error_set(err, HSBD_EIO, "writing '%s' failed: %s", s->file.tmp,
                                  strerror(errno));
        s->committed = (int64_t)ftello(s->file.f);
    }
    return HSBD_OK;
}

int run_checkpoint_write_file(const char *path, const hsbd_writer *payload, hsbd_error *err) {
    FILE *f = fopen(path, "wb");
    if (!f) return hsbd_error_set(err, HSBD_EIO, "cannot write '%s': %s", path, strerror(errno));
    hsbd_writer head, tail;
    hsbd_writer_init(&head), hsbd_writer_init(&tail);
    hsbd_put_bytes(&head, magic, sizeof magic);
    hsbd_put_u64(&head, CHECKPOINT_FORMAT);
    hsbd_put_u64(&head, payload->len);
    hsbd_put_u64(&tail, hsbd_crc64(0, payload->data, payload->len));
    if (head.oom || tail.oom) {
        hsbd_writer_free(&head), hsbd_writer_free(&tail);
        fclose(f);
        remove(path);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing '%s'", path);
    }
    int bad = fwrite(head.data, 1, head.len, f) != head.len ||
              fwrite(payload->data, 1, payload->len, f) != payload->len ||
              fwrite(tail.data, 1, tail.len, f) != tail.len || fflush(f) != 0 ||
              fsync(fileno(f)) != 0;
    const int saved = errno;
    hsbd_writer_free(&head), hsbd_writer_free(&tail);
    bad |= fclose(f) != 0;
    if (bad) {
        remove(path);
        return hsbd_error_set(err, HSBD_EIO, "writing '%s' failed: %s", path,
                              strerror(saved ? saved : errno));
    }
    return HSBD_OK;
}

static void sync_dir(const char *dir) {
    const int fd = open(dir, O_RDONLY);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
}

int run_checkpoint_write(run *r, hsbd_error *err) {
    int rc = sync_streams(r, err);
    if (rc != HSBD_OK) return rc;
    hsbd_writer w;
    hsbd_writer_init(&w);
    hsbd_put_tag(&w, "header");
    hsbd_put_string(&w, HSBD_VERSION_STRING);
    hsbd_put_string(&w, HSBD_GIT_COMMIT);
    hsbd_put_string(&w, r->model.name);
    save_source(r, &w);
    save_run(r, &w);
    r->model.save(r, &w);
    run_observers_save(r, &w);
    hsbd_put_tag(&w, "end");
    const char *dir = r->cfg->output.dir;
    char path[HSBD_PATH_MAX + 32], part[HSBD_PATH_MAX + 40], prev[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, HSBD_CHECKPOINT_FILE);
    snprintf(part, sizeof part, "%s.part", path);
    snprintf(prev, sizeof prev, "%s/%s", dir, HSBD_CHECKPOINT_PREV);
    if (w.oom) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the checkpoint '%s'", path);
    if (rc == HSBD_OK) rc = run_checkpoint_write_file(part, &w, err);
    hsbd_writer_free(&w);
    if (rc != HSBD_OK) return rc;
    /* the previous checkpoint stays until the new one is complete */
    if (r->newest_unusable) { /* never rotate an unusable file over the good previous one */
        if (remove(path) != 0 && errno != ENOENT)
            return hsbd_error_set(err, HSBD_EIO, "cannot remove '%s': %s", path, strerror(errno));
        r->newest_unusable = 0;
    } else if (access(path, F_OK) == 0 && rename(path, prev) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", path, prev,
                              strerror(errno));
    if (rename(part, path) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", part, path,
                              strerror(errno));
    sync_dir(dir);
    return HSBD_OK;
}

/* ---- reading ---- */

/* The payload of one checkpoint file, or a message saying what is wrong with it. */
static int read_one(const char *path, run_checkpoint_data *ck, char *why, size_t len) {
    FILE *f = fopen(path, "rb");
    if (!f) return snprintf(why, len, "%s", strerror(errno)), -1;
    unsigned char head[24];
    if (fread(head, 1, sizeof head, f) != sizeof head || memcmp(head, magic, sizeof magic)) {
        fclose(f);
        return snprintf(why, len, "not an hsbd checkpoint (or truncated)"), -1;
    }
    hsbd_reader hr;
    hsbd_reader_init(&hr, head + 8, 16);
    uint64_t format, payload;
    hsbd_get_u64(&hr, &format);
    hsbd_get_u64(&hr, &payload);
    if (format != CHECKPOINT_FORMAT) {
        fclose(f);
        return snprintf(why, len,
                        "checkpoint format %llu, this hsbd reads format %d (written by an "
                        "incompatible version)",
                        (unsigned long long)format, CHECKPOINT_FORMAT),
               -1;
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || st.st_size < 0 ||
        (uint64_t)st.st_size != sizeof head + payload + 8) {
        fclose(f);
        return snprintf(why, len, "truncated (%lld bytes, the header announces %llu)",
                        (long long)st.st_size, (unsigned long long)(sizeof head + payload + 8)),
               -1;
    }
    unsigned char *data = malloc(payload + 8);
    if (!data) {
        fclose(f);
        return snprintf(why, len, "out of memory for its %llu bytes", (unsigned long long)payload),
               -2;
    }
    if (fread(data, 1, payload + 8, f) != payload + 8) {
        free(data);
        fclose(f);
        return snprintf(why, len, "cannot read it (short read)"), -1;
    }
    fclose(f);
    hsbd_reader_init(&hr, data + payload, 8);
    uint64_t crc;
    hsbd_get_u64(&hr, &crc);
    if (crc != hsbd_crc64(0, data, payload)) {
        free(data);
        return snprintf(why, len, "damaged (its CRC-64 does not match)"), -1;
    }
    ck->data = data;
    ck->len = payload;
    snprintf(ck->path, sizeof ck->path, "%s", path);
    return 0;
}

int run_checkpoint_read(const char *dir, run_checkpoint_data *ck, hsbd_error *err) {
    memset(ck, 0, sizeof *ck);
    char newest[HSBD_PATH_MAX + 32], prev[HSBD_PATH_MAX + 32], why1[256], why2[256];
    snprintf(newest, sizeof newest, "%s/%s", dir, HSBD_CHECKPOINT_FILE);
    snprintf(prev, sizeof prev, "%s/%s", dir, HSBD_CHECKPOINT_PREV);
    const int got = read_one(newest, ck, why1, sizeof why1);
    if (got == 0) return HSBD_OK;
    if (got == -2) return hsbd_error_set(err, HSBD_ENOMEM, "'%s': %s", newest, why1);
    const int got_prev = read_one(prev, ck, why2, sizeof why2);
    if (got_prev == -2) return hsbd_error_set(err, HSBD_ENOMEM, "'%s': %s", prev, why2);
    if (got_prev == 0) {
        ck->fell_back = 1;
        fprintf(stderr, "hsbd: warning: '%s' is not usable (%s); continuing from '%s'\n", newest,
                why1, prev);
        return HSBD_OK;
    }
    return hsbd_error_set(err, HSBD_EINPUT, "no usable checkpoint in '%s': '%s': %s; '%s': %s", dir,
                          newest, why1, prev, why2);
}

void run_checkpoint_data_free(run_checkpoint_data *ck) {
    free(ck->data);
    ck->data = NULL;
}

int run_checkpoint_read_source(hsbd_reader *rd, run_source_copy *src) {
    memset(src, 0, sizeof *src);
    uint64_t has, has_file, len, nsets, ninputs;
    if (hsbd_get_tag(rd, "header") || hsbd_get_string(rd, src->version, sizeof src->version) ||
        hsbd_get_string(rd, src->git, sizeof src->git) ||
        hsbd_get_string(rd, src->model, sizeof src->model) || hsbd_get_tag(rd, "config") ||
        hsbd_get_u64(rd, &has))
        return -1;
    if (!has)
        return hsbd_reader_fail(rd, "the run kept no configuration source (not run by the CLI)");
    if (hsbd_get_u64(rd, &has_file) || hsbd_get_string(rd, src->name, sizeof src->name) ||
        hsbd_get_u64(rd, &len))
        return -1;
    if (len > rd->len - rd->pos) return hsbd_reader_fail(rd, "configuration text beyond the end");
    src->has_file = has_file != 0;
    src->text = malloc(len + 1);
    if (!src->text) return hsbd_reader_oom(rd, "the configuration");
    if (hsbd_get_bytes(rd, src->text, (size_t)len)) return -1;
    src->text[len] = '\0';
    src->text_len = (size_t)len;
    if (hsbd_get_u64(rd, &nsets)) return -1;
    if (nsets > 4096) return hsbd_reader_fail(rd, "too many overrides");
    src->sets = calloc(nsets ? nsets : 1, sizeof *src->sets);
    if (!src->sets) return hsbd_reader_oom(rd, "the overrides");
    src->nsets = (size_t)nsets;
    for (size_t k = 0; k < src->nsets; ++k)
        if (hsbd_get_string(rd, src->sets[k], sizeof src->sets[k])) return -1;
    if (hsbd_get_string(rd, src->cwd, sizeof src->cwd) || hsbd_get_u64(rd, &ninputs)) return -1;
    if (ninputs > RUN_MAX_INPUTS) return hsbd_reader_fail(rd, "too many input files");
    src->ninputs = (size_t)ninputs;
    for (size_t k = 0; k < src->ninputs; ++k)
        if (hsbd_get_string(rd, src->inputs[k].path, sizeof src->inputs[k].path) ||
            hsbd_get_u64(rd, &src->inputs[k].crc))
            return -1;
    return 0;
}

void run_source_copy_free(run_source_copy *src) {
    free(src->text);
    free(src->sets);
    src->text = NULL;
    src->sets = NULL;
}

int run_checkpoint_load_run(run *r, hsbd_reader *rd) {
    uint64_t stage, replicas, nstreams;
    double times[4];
    if (hsbd_get_tag(rd, "run") || hsbd_get_u64(rd, &stage) || hsbd_get_u64(rd, &r->stage_steps) ||
        hsbd_get_u64(rd, &r->steps_done) || hsbd_get_u64(rd, &r->equil_done) ||
        hsbd_get_u64(rd, &replicas) || hsbd_get_u64(rd, &r->resumes) ||
        hsbd_get_f64s(rd, times, 4) || hsbd_get_tag(rd, "streams") || hsbd_get_u64(rd, &nstreams))
        return -1;
    if (stage > RUN_DONE) return hsbd_reader_fail(rd, "unknown stage");
    if (r->steps_done > hsbd_config_steps(r->cfg) ||
        r->stage_steps > hsbd_config_equil_steps(r->cfg) ||
        replicas > (uint64_t)r->cfg->sample.blocks)
        return hsbd_reader_fail(rd, "counters beyond the run's length");
    if (nstreams != r->nstreams) return hsbd_reader_fail(rd, "another set of stream files");
    r->stage = (int)stage;
    r->replicas_started = (size_t)replicas;
    r->wall_equil = times[0], r->wall_prod = times[1], r->cpu_equil = times[2];
    r->cpu_prod = times[3];
    for (size_t k = 0; k < r->nstreams; ++k) {
        char name[64];
        if (hsbd_get_string(rd, name, sizeof name) || hsbd_get_i64(rd, &r->streams[k].committed))
            return -1;
        if (strcmp(name, r->streams[k].name) || r->streams[k].committed < 0)
            return hsbd_reader_fail(rd, "another stream file");
        hsbd_gsd *g = &r->streams[k].gsd;
        uint64_t layout[4];
        if (!r->streams[k].is_gsd) continue;
        if (hsbd_get_u64s(rd, layout, 4)) return -1;
        g->index_location = layout[0], g->index_capacity = layout[1];
        g->entries = layout[2], g->frames = layout[3];
    }
    return 0;
}

int run_file_crc(const char *path, uint64_t *crc) {
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    struct stat st; /* a device or pipe (a checkpoint naming /dev/zero) would never end */
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) return fclose(f), -1;
    unsigned char buf[65536];
    uint64_t c = 0;
    for (size_t n; (n = fread(buf, 1, sizeof buf, f)) > 0;)
        c = hsbd_crc64(c, buf, n);
    const int bad = ferror(f);
    fclose(f);
    *crc = c;
    return bad ? -1 : 0;
}
