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
/* "replica-<digits>": the name of an ensemble's replica directory */
int run_is_replica_name(const char *name);
/* Claims run directory dir for this process until run_dir_release: with create, dir made
 * if missing (without the checks of hsbd_run_dir_prepare, which come after the claim); an
 * exclusive advisory lock (flock) on it, which the system drops when the process ends,
 * however it ends. *fd gets the lock's descriptor, or -1 where no lock can be had (dir
 * not a directory, or a file system without locks): the caller's own checks then speak.
 * HSBD_EINPUT when another process holds the lock (a run or resume writing there). */
int run_dir_claim(const char *dir, int create, int *fd, hsbd_error *err);
void run_dir_release(int fd);

#endif
