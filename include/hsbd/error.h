/* Explicit error returns: every fallible call takes an hsbd_error and returns a status. */
#ifndef HSBD_ERROR_H
#define HSBD_ERROR_H

#include "hsbd/export.h"

enum hsbd_status {
    HSBD_OK = 0,
    HSBD_EINPUT = 2,    /* bad user input: configuration, flags, initial state (exit 2) */
    HSBD_EIO = 3,       /* file system */
    HSBD_ENOMEM = 4,    /* allocation failed */
    HSBD_ENUMERIC = 5,  /* NaN/Inf or broken invariant during a run */
    HSBD_EINTERRUPT = 6 /* stopped by a signal; results so far were written */
};

typedef struct hsbd_error {
    int status;
    char message[1024];
} hsbd_error;

/* Record status and a printf-style message (when err is not NULL); returns status. */
HSBD_API int hsbd_error_set(hsbd_error *err, int status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
HSBD_API void hsbd_error_clear(hsbd_error *err);

#endif
