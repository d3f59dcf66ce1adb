/* The library's version. */
#ifndef HSBD_VERSION_API_H
#define HSBD_VERSION_API_H

#include "hsbd/export.h"

/* "MAJOR.MINOR.PATCH (git COMMIT)" of the library actually linked. */
HSBD_API const char *hsbd_version(void);

#endif
