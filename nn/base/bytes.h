/* bytes.h: little-endian byte buffers for the binary files wiresketch writes
 * itself (checkpoints): a growable writer and a bounds-checked reader, so
 * that a truncated or hostile file is refused, never read past its end.
 *
 * nn/base holds the project's base types, shared by both layers (nn/ and
 * src/), so its names keep the project's ws_ prefix; the rest of nn/ uses
 * nn_ (and clip_, wf_ for the CLIP tower and its weight file). */
#ifndef NN_BASE_BYTES_H
#define NN_BASE_BYTES_H
#include <stddef.h>
#include <stdint.h>
#include "status.h"

typedef struct {
    unsigned char *data;
    size_t len, cap;
    int failed; /* an allocation failed: every later put is ignored */
} ws_bytes_writer;

void ws_put(ws_bytes_writer *w, const void *p, size_t n);
void ws_put_u32(ws_bytes_writer *w, uint32_t v);
void ws_put_u64(ws_bytes_writer *w, uint64_t v);
void ws_put_f64(ws_bytes_writer *w, double v);
void ws_put_f64s(ws_bytes_writer *w, const double *v, size_t n);
void ws_put_str(ws_bytes_writer *w, const char *s);
void ws_bytes_writer_free(ws_bytes_writer *w);

typedef struct {
    const unsigned char *data;
    size_t len, pos;
    int failed; /* a read went past the end: every later get returns 0 */
} ws_bytes_reader;

uint32_t ws_get_u32(ws_bytes_reader *r);
uint64_t ws_get_u64(ws_bytes_reader *r);
double ws_get_f64(ws_bytes_reader *r);
void ws_get_f64s(ws_bytes_reader *r, double *v, size_t n);
/* A string stored by ws_put_str, NUL-terminated in a new allocation; NULL
 * on failure (r->failed set). */
char *ws_get_str(ws_bytes_reader *r);
/* Can `count` items of `size` bytes still be read? Guards allocations sized
 * by counts from the file. */
int ws_bytes_have(const ws_bytes_reader *r, uint64_t count, size_t size);

/* Reads a whole regular file into memory (at most max_bytes; opened with
 * ws_fopen_regular, so a FIFO or device is refused), followed by a NUL byte
 * that *len does not count, so that text parsers may rely on it. */
int ws_read_file(const char *path, size_t max_bytes, unsigned char **data, size_t *len,
                 ws_status *st);

#endif
