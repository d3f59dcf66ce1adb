#include "hsbd/error.h"

#include <stdarg.h>
#include <stdio.h>

int hsbd_error_set(hsbd_error *err, int status, const char *fmt, ...) {
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->status = status;
    }
    return status;
}

void hsbd_error_clear(hsbd_error *err) {
    if (err) {
        err->status = HSBD_OK;
        err->message[0] = '\0';
    }
}
