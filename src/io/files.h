/* Run directories (internal; the public part is in hsbd/io.h). */
#ifndef HSBD_IO_FILES_H
#define HSBD_IO_FILES_H

#include "hsbd/error.h"

/* dir holds nothing but an earlier run's files (those --force may replace), and, with
 * replica_dirs, directories replica-<digits> of an earlier ensemble (checked by the
 * caller); HSBD_EINPUT naming the first other entry. Nothing is removed. */
int run_dir_check_earlier(const char *dir, int replica_dirs, hsbd_error *err);

#endif
