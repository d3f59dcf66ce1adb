/* HSBD_API marks the functions of the public API: the only symbols libhsbd.so exports
 * (the library is built with -fvisibility=hidden). */
#ifndef HSBD_EXPORT_H
#define HSBD_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define HSBD_API __attribute__((visibility("default")))
#else
#define HSBD_API
#endif

#endif
