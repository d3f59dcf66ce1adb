/* Checkpoint files (see checkpoint.h). */
#include "run/checkpoint.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hsbd_version.h"

static const char magic[8] = {'H', 'S', 'B', 'D', 'C', 'K', 'P', 'T'};
enum { CHECKPOINT_FORMAT = 1 };

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
        hsbd_put_string(w, r->streams[k].name);
        hsbd_put_i64(w, r->streams[k].committed);
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

static int write_file(const char *path, const void *data, size_t n, hsbd_error *err) {
    FILE *f = fopen(path, "wb");
    if (!f) return hsbd_error_set(err, HSBD_EIO, "cannot write '%s': %s", path, strerror(errno));
    int bad = fwrite(data, 1, n, f) != n || fflush(f) != 0 || fsync(fileno(f)) != 0;
    const int saved = errno;
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
    save_run(r, &w);
    r->model.save(r, &w);
    hsbd_put_tag(&w, "end");
    hsbd_writer file;
    hsbd_writer_init(&file);
    hsbd_put_bytes(&file, magic, sizeof magic);
    hsbd_put_u64(&file, CHECKPOINT_FORMAT);
    hsbd_put_u64(&file, w.len);
    hsbd_put_bytes(&file, w.data, w.len);
    hsbd_put_u64(&file, hsbd_crc64(0, w.data, w.len));
    const char *dir = r->cfg->output.dir;
    char path[HSBD_PATH_MAX + 32], part[HSBD_PATH_MAX + 40], prev[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, HSBD_CHECKPOINT_FILE);
    snprintf(part, sizeof part, "%s.part", path);
    snprintf(prev, sizeof prev, "%s/%s", dir, HSBD_CHECKPOINT_PREV);
    if (w.oom || file.oom)
        rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the checkpoint '%s'", path);
    if (rc == HSBD_OK) rc = write_file(part, file.data, file.len, err);
    hsbd_writer_free(&w);
    hsbd_writer_free(&file);
    if (rc != HSBD_OK) return rc;
    /* the previous checkpoint stays until the new one is complete */
    if (access(path, F_OK) == 0 && rename(path, prev) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", path, prev,
                              strerror(errno));
    if (rename(part, path) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", part, path,
                              strerror(errno));
    sync_dir(dir);
    return HSBD_OK;
}
