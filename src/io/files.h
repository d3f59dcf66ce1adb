/* Run directories (internal; the public part is in hsbd/io.h). */
#ifndef HSBD_IO_FILES_H
#define HSBD_IO_FILES_H

#include <dirent.h>

#include "hsbd/error.h"

/* opendir(dir), or NULL with HSBD_EINPUT naming it */
DIR *run_dir_open(const char *dir, hsbd_error *err);

/* dir holds nothing but an earlier run's files (those --force may replace), and, with
 * replica_dirs, directories replica-<digits> of an earlier ensemble (checked by the
 * caller); HSBD_EINPUT naming the first other entry. Nothing is removed. */
int run_dir_check_earlier(const char *dir, int replica_dirs, hsbd_error *err);
/* dir holds no entry (or cannot be read) */
int run_dir_is_empty(const char *dir);
/* Is path b the directory a or inside it (1), a inside b (-1), or neither (0)? Symbolic
 * links, . and .. resolved; a path not there yet through its nearest existing parent. */
int run_path_nesting(const char *a, const char *b);
/* path copied into out (len bytes) without its trailing slashes ("/" stays "/"), which
 * would make a system call follow a final link; returns the length, >= len when cut. */
size_t run_path_bare(const char *path, char *out, size_t len);
/* Does dir hold a regular file of this name? */
int run_dir_holds(const char *dir, const char *name);
/* Does dir hold a checkpoint (checkpoint.hsbd or checkpoint.prev.hsbd)? */
int run_dir_holds_checkpoint(const char *dir);
/* Does dir hold a run's own results: a checkpoint, or a summary.json that is no merge's
 * (a merge's lists "replica_indices")? */
int run_dir_holds_run(const char *dir);
/* "replica-<digits>": the name of an ensemble's replica directory */
int run_is_replica_name(const char *name);
/* Entry name of dir: a replica directory (1), a replica's name on something else, a link
 * or a file (-1), or another name (0). */
int run_replica_entry(const char *dir, const char *name);
/* Does dir hold a replica directory (an ensemble's run directory)? */
int run_dir_holds_replicas(const char *dir);
/* One writer per run directory: hsbd run, hsbd resume and hsbd merge (into OUT) hold an
 * exclusive advisory lock (flock) on the file RUN_LOCK_FILE in it while they write there
 * (a file, not the directory: NFS locks only files opened for writing); merge holds shared
 * locks on its inputs while it reads them. The system drops a lock when its process ends,
 * however it ends; the file stays, a run's file like the others (an empty directory may
 * hold it). */
#define RUN_LOCK_FILE ".hsbd.lock"
typedef enum run_dir_use {
    RUN_DIR_WRITE_NEW, /* a writer of a new or earlier run's directory, made if missing; no
                        * lock file made in a directory of other files (its checks refuse it) */
    RUN_DIR_WRITE,     /* a writer continuing the run in an existing directory (resume) */
    RUN_DIR_READ,      /* a reader: a shared lock, no lock file made */
    RUN_DIR_CHECK      /* nobody writes there (the caller releases the lock at once) */
} run_dir_use;
/* Claims dir for `use` (taken before the directory's own checks, which come after): *fd
 * gets the lock's descriptor, or -1 where no lock is needed or can be had (no directory or
 * no lock file yet, or a file system without locks). HSBD_EINPUT when another process holds
 * a lock that conflicts (a writer's, or for a writer a reader's). */
int run_dir_claim(const char *dir, run_dir_use use, int *fd, hsbd_error *err);
void run_dir_release(int fd);
/* Removes the empty run directory dir with its lock file (rmdir's result); only for a
 * directory whose lock this process holds, or that no other process can know. */
int run_dir_remove(const char *dir);
/* Makes dir and its missing parents; *made counts the levels this call made (0: dir was
 * there). 0, or -1 with errno. */
int run_dir_make(const char *dir, int *made);
/* Takes back what run_dir_make made (`made` levels), as far as they are empty. */
void run_dir_unmake(const char *dir, int made);

#endif
