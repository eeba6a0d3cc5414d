/* bytes.c: little-endian byte buffers (see bytes.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bytes.h"
#include "fileopen.h"

void ws_put(ws_bytes_writer *w, const void *p, size_t n) {
    if (w->failed) return;
    if (w->len + n > w->cap) {
        size_t cap = w->cap ? w->cap : 4096;
        while (cap < w->len + n) cap *= 2;
        unsigned char *grown = realloc(w->data, cap);
        if (!grown) {
            w->failed = 1;
            return;
        }
        w->data = grown;
        w->cap = cap;
    }
    memcpy(w->data + w->len, p, n);
    w->len += n;
}

void ws_put_u32(ws_bytes_writer *w, uint32_t v) {
    unsigned char b[4];
    for (int i = 0; i < 4; i++) b[i] = (unsigned char)(v >> (8 * i));
    ws_put(w, b, 4);
}

void ws_put_u64(ws_bytes_writer *w, uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; i++) b[i] = (unsigned char)(v >> (8 * i));
    ws_put(w, b, 8);
}

void ws_put_f64(ws_bytes_writer *w, double v) {
    uint64_t bits;
    memcpy(&bits, &v, 8);
    ws_put_u64(w, bits);
}

void ws_put_f64s(ws_bytes_writer *w, const double *v, size_t n) {
    for (size_t i = 0; i < n; i++) ws_put_f64(w, v[i]);
}

void ws_put_str(ws_bytes_writer *w, const char *s) {
    size_t n = strlen(s);
    ws_put_u32(w, (uint32_t)n);
    ws_put(w, s, n);
}

void ws_bytes_writer_free(ws_bytes_writer *w) {
    free(w->data);
    w->data = NULL;
    w->len = w->cap = 0;
}

static const unsigned char *take(ws_bytes_reader *r, size_t n) {
    if (r->failed || n > r->len - r->pos) {
        r->failed = 1;
        return NULL;
    }
    const unsigned char *p = r->data + r->pos;
    r->pos += n;
    return p;
}

uint32_t ws_get_u32(ws_bytes_reader *r) {
    const unsigned char *b = take(r, 4);
    if (!b) return 0;
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v |= (uint32_t)b[i] << (8 * i);
    return v;
}

uint64_t ws_get_u64(ws_bytes_reader *r) {
    const unsigned char *b = take(r, 8);
    if (!b) return 0;
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= (uint64_t)b[i] << (8 * i);
    return v;
}

double ws_get_f64(ws_bytes_reader *r) {
    uint64_t bits = ws_get_u64(r);
    double v;
    memcpy(&v, &bits, 8);
    return v;
}

void ws_get_f64s(ws_bytes_reader *r, double *v, size_t n) {
    for (size_t i = 0; i < n; i++) v[i] = ws_get_f64(r);
}

char *ws_get_str(ws_bytes_reader *r) {
    uint32_t n = ws_get_u32(r);
    const unsigned char *p = take(r, n);
    if (!p) return NULL;
    char *s = malloc((size_t)n + 1);
    if (!s) {
        r->failed = 1;
        return NULL;
    }
    memcpy(s, p, n);
    s[n] = '\0';
    return s;
}

int ws_bytes_have(const ws_bytes_reader *r, uint64_t count, size_t size) {
    return !r->failed && size != 0 && count <= (r->len - r->pos) / size;
}

int ws_read_file(const char *path, size_t max_bytes, unsigned char **data, size_t *len,
                 ws_status *st) {
    *data = NULL;
    *len = 0;
    FILE *f;
    if (ws_fopen_regular(path, max_bytes, &f, st)) return st->code;
    size_t cap = 1 << 16, n = 0;
    unsigned char *buf = NULL;
    for (;;) {
        if (n == cap || !buf) {
            if (buf) cap *= 2;
            unsigned char *grown = realloc(buf, cap);
            if (!grown) {
                free(buf);
                fclose(f);
                return ws_fail(st, WS_ENOMEM, "%s: out of memory reading the file", path);
            }
            buf = grown;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n > max_bytes) {
            free(buf);
            fclose(f);
            return ws_fail(st, WS_EINPUT, "%s: larger than %llu bytes", path,
                           (unsigned long long)max_bytes);
        }
        if (got == 0) break;
    }
    int err = ferror(f);
    fclose(f);
    if (err) {
        free(buf);
        return ws_fail(st, WS_EINPUT, "%s: read error", path);
    }
    buf[n] = '\0'; /* n < cap: the last read returned nothing */
    *data = buf;
    *len = n;
    return WS_OK;
}
