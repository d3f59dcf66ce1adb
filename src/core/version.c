#include "hsbd/version.h"

#include "hsbd_version.h"

const char *hsbd_version(void) {
    return HSBD_VERSION_STRING " (git " HSBD_GIT_COMMIT ")";
}
