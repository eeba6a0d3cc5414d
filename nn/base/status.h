/* status.h: how every failure in wiresketch is reported.
 *
 * Every function that can fail returns an int code (WS_OK = 0) and, on
 * failure, fills a ws_status with a one-line message that names the file and
 * what is wrong. Callers check every call and pass the status up unchanged:
 *
 *     if (ws_scene_load(&scene, dir, &opt, st)) return st->code;
 *
 * The command line prints st->msg on stderr and exits with ws_exit_code().
 *
 * nn/base holds the project's base types, shared by both layers (nn/ and
 * src/), so its names keep the project's ws_ prefix; the rest of nn/ uses
 * nn_ (and clip_, wf_ for the CLIP tower and its weight file). */
#ifndef NN_BASE_STATUS_H
#define NN_BASE_STATUS_H
#include <stddef.h>

enum {
    WS_OK = 0,
    WS_EINPUT = 1,   /* a file the user brought is missing or malformed */
    WS_EUSAGE = 2,   /* bad command line: unknown option, bad value */
    WS_ENOMEM = 3,   /* an allocation failed */
    WS_EIO = 4,      /* reading or writing failed (disk full, permissions) */
    WS_ENUMERIC = 5, /* NaN or Inf where a finite value is required */
    WS_EINTERNAL = 6 /* a broken invariant: a bug in wiresketch */
};

typedef struct {
    int code;
    char msg[1024];
} ws_status;

/* Sets st->code and st->msg (printf-style) and returns code, so that a
 * failure is one line: return ws_fail(st, WS_EINPUT, "%s: not a PNG", path); */
int ws_fail(ws_status *st, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Resets st to WS_OK with an empty message. */
void ws_status_clear(ws_status *st);

/* Process exit code for a status: 0 ok, 2 bad usage, 1 everything else. */
int ws_exit_code(const ws_status *st);

/* malloc/calloc that report failure through st (message names what). */
void *ws_malloc(size_t bytes, const char *what, ws_status *st);
void *ws_calloc(size_t count, size_t size, const char *what, ws_status *st);

#endif
