/* status.c: failure reporting (see status.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include "status.h"

int ws_fail(ws_status *st, int code, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(st->msg, sizeof st->msg, fmt, ap);
    va_end(ap);
    st->code = code;
    return code;
}

void ws_status_clear(ws_status *st) {
    st->code = WS_OK;
    st->msg[0] = '\0';
}

int ws_exit_code(const ws_status *st) {
    if (st->code == WS_OK) return 0;
    return st->code == WS_EUSAGE ? 2 : 1;
}

void *ws_malloc(size_t bytes, const char *what, ws_status *st) {
    void *p = malloc(bytes ? bytes : 1);
    if (!p) ws_fail(st, WS_ENOMEM, "out of memory allocating %zu bytes for %s", bytes, what);
    return p;
}

void *ws_calloc(size_t count, size_t size, const char *what, ws_status *st) {
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p) ws_fail(st, WS_ENOMEM, "out of memory allocating %zu x %zu bytes for %s", count, size, what);
    return p;
}
