/* weightfile.c: the flat CLIP weight file (see weightfile.h; the format is
 * documented byte by byte in weights/README.md).
 *
 * The file is mapped read-only and checked completely before anything is
 * handed out: header, every table entry (name, dtype, shape, size, offset,
 * alignment, bounds), overlaps, the checksum and finally the values
 * themselves (a NaN or Inf weight would poison every activation silently).
 * Every count and size read from the file is bounded by the file's own size
 * before it is multiplied, so a hostile file cannot overflow a computation. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "base/bytes.h"
#include "base/fileopen.h"
#include "weightfile.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "weightfile.c hands out f32 data straight from the little-endian file"
#endif

#define WF_MAGIC "WSKCLIP\0"
enum {
    WF_VERSION = 1,
    WF_HEADER_BYTES = 40, /* magic 8, version 4, architecture 6 x 4, count 4 */
    WF_ENTRY_BYTES = 120, /* name 64, dtype 4, ndim 4, shape 4 x 8, offset 8, nbytes 8 */
    WF_ALIGN = 64,
    WF_CRC_BYTES = 4,
    WF_MAX_DIMS = 4
};

/* Bounds on the architecture: generous for any ViT, small enough that the
 * model's own size computations (tokens x width x batch) stay far from
 * overflow. */
enum { WF_MAX_WIDTH = 65536, WF_MAX_LAYERS = 4096, WF_MAX_RESOLUTION = 16384 };
/* What a CLIP vision tower holds: 12 tensors per residual block (ln_1, attn
 * in_proj and out_proj, ln_2, mlp c_fc and c_proj, a weight and a bias
 * each) and 8 outside them (conv1, class and positional embeddings, ln_pre,
 * ln_post, proj). A table longer than its header's layers allow is refused
 * before anything is allocated for it; with names unique and every tower
 * tensor looked up by clip.c, the table then holds exactly the tower. */
enum { WF_TENSORS_PER_LAYER = 12, WF_TENSORS_OUTSIDE_LAYERS = 8 };
/* The largest weight file mapped: ViT-B/32's tower in f32 is 350 MB,
 * ViT-L/14's 1.2 GB. The bound also bounds the work of refusing a hostile
 * file (its checksum reads every byte; f16 is widened to twice its size). */
#define WF_MAX_FILE_BYTES ((uint64_t)4 << 30)

struct wf_file {
    char *path;
    wf_arch arch;
    int count;
    wf_tensor *tensors;
    const wf_tensor **by_name; /* the table sorted by name: duplicates and lookups in O(log n) */
    void *map;
    size_t map_bytes;
    float *widened; /* a file with f16 tensors: every tensor as f32, one block */
};

static float half_to_float(uint16_t h) {
    uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
    uint32_t exponent = (h >> 10) & 0x1fu;
    uint32_t mantissa = h & 0x3ffu;
    if (exponent == 0) { /* zero or subnormal: mantissa x 2^-24, exact in f32 */
        float v = ldexpf((float)mantissa, -24);
        return sign ? -v : v;
    }
    uint32_t bits = exponent == 31 ? sign | 0x7f800000u | mantissa << 13
                                   : sign | (exponent + 112) << 23 | mantissa << 13;
    float v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

static int map_file(wf_file *f, ws_status *st) {
    int fd;
    uint64_t bytes;
    if (ws_open_regular(f->path, WF_MAX_FILE_BYTES, &fd, &bytes, st)) return st->code;
    if (bytes < WF_HEADER_BYTES + WF_CRC_BYTES) {
        close(fd);
        return ws_fail(st, WS_EINPUT, "%s: truncated (%llu bytes; a weight file has at least %d)",
                       f->path, (unsigned long long)bytes, WF_HEADER_BYTES + WF_CRC_BYTES);
    }
    f->map_bytes = (size_t)bytes;
    void *map = mmap(NULL, f->map_bytes, PROT_READ, MAP_PRIVATE, fd, 0);
    int err = errno;
    close(fd);
    if (map == MAP_FAILED) return ws_fail(st, WS_EIO, "%s: cannot map: %s", f->path, strerror(err));
    f->map = map;
    return WS_OK;
}

static int read_header(wf_file *f, ws_bytes_reader *r, uint32_t *count, ws_status *st) {
    if (memcmp(f->map, WF_MAGIC, 8) != 0)
        return ws_fail(st, WS_EINPUT,
                       "%s: not a wiresketch weight file (bad magic); convert weights with "
                       "tools/convert_weights.py",
                       f->path);
    r->pos = 8;
    uint32_t version = ws_get_u32(r);
    if (version != WF_VERSION)
        return ws_fail(st, WS_EINPUT, "%s: unsupported weight file version %u (this build reads version %d)",
                       f->path, version, WF_VERSION);
    uint32_t a[6];
    for (int i = 0; i < 6; i++) a[i] = ws_get_u32(r);
    *count = ws_get_u32(r);
    /* width, layers, heads, patch, resolution, output_dim */
    int ok = a[0] >= 1 && a[0] <= WF_MAX_WIDTH && a[1] >= 1 && a[1] <= WF_MAX_LAYERS && a[2] >= 1 &&
             a[2] <= a[0] && a[0] % a[2] == 0 && a[3] >= 1 && a[4] <= WF_MAX_RESOLUTION &&
             a[3] <= a[4] && a[4] % a[3] == 0 && a[5] >= 1 && a[5] <= WF_MAX_WIDTH;
    if (!ok)
        return ws_fail(st, WS_EINPUT,
                       "%s: bad architecture (width %u, layers %u, heads %u, patch %u, resolution %u, "
                       "output_dim %u)",
                       f->path, a[0], a[1], a[2], a[3], a[4], a[5]);
    f->arch = (wf_arch){(int)a[0], (int)a[1], (int)a[2], (int)a[3], (int)a[4], (int)a[5]};
    uint64_t most = (uint64_t)a[1] * WF_TENSORS_PER_LAYER + WF_TENSORS_OUTSIDE_LAYERS;
    if (*count > most)
        return ws_fail(st, WS_EINPUT, "%s: %u tensors in the table, a %u-layer CLIP tower has %llu",
                       f->path, *count, a[1], (unsigned long long)most);
    uint64_t data_end = f->map_bytes - WF_CRC_BYTES;
    if (*count == 0 || *count > (data_end - WF_HEADER_BYTES) / WF_ENTRY_BYTES)
        return ws_fail(st, WS_EINPUT, "%s: truncated or malformed (a table of %u tensors does not fit in %zu bytes)",
                       f->path, *count, f->map_bytes);
    return WS_OK;
}

static void format_shape(char *buf, size_t cap, int ndim, const uint64_t *shape) {
    size_t n = (size_t)snprintf(buf, cap, "[");
    for (int d = 0; d < ndim && n < cap; d++)
        n += (size_t)snprintf(buf + n, cap - n, "%s%llu", d ? ", " : "", (unsigned long long)shape[d]);
    if (n < cap) snprintf(buf + n, cap - n, "]");
}

/* One table entry, checked on its own: name, dtype, shape, size, bounds. */
static int read_entry(wf_file *f, ws_bytes_reader *r, int index, uint64_t table_end, wf_tensor *t,
                      uint64_t *offset, uint64_t *nbytes, ws_status *st) {
    const unsigned char *name = r->data + r->pos;
    r->pos += 64;
    size_t len = strnlen((const char *)name, 64);
    int padded = len > 0 && len < 64;
    for (size_t i = len; padded && i < 64; i++) padded = name[i] == 0;
    /* printable ASCII only: the name goes into one-line messages */
    for (size_t i = 0; padded && i < len; i++) padded = name[i] > 0x20 && name[i] < 0x7f;
    if (!padded)
        return ws_fail(st, WS_EINPUT, "%s: tensor table entry %d has a malformed name", f->path, index);
    memcpy(t->name, name, len + 1);
    uint32_t dtype = ws_get_u32(r);
    uint32_t ndim = ws_get_u32(r);
    uint64_t shape[WF_MAX_DIMS];
    for (int d = 0; d < WF_MAX_DIMS; d++) shape[d] = ws_get_u64(r);
    *offset = ws_get_u64(r);
    *nbytes = ws_get_u64(r);
    if (dtype != WF_F32 && dtype != WF_F16)
        return ws_fail(st, WS_EINPUT, "%s: tensor %s has unknown dtype %u", f->path, t->name, dtype);
    if (ndim < 1 || ndim > WF_MAX_DIMS)
        return ws_fail(st, WS_EINPUT, "%s: tensor %s has %u dimensions (1 to 4 allowed)", f->path, t->name,
                       ndim);
    /* numel stays <= the file size at every step, so nothing overflows */
    uint64_t numel = 1;
    int zero_dim = 0, unused_set = 0;
    for (int d = 0; d < WF_MAX_DIMS; d++) {
        if (d >= (int)ndim) {
            unused_set |= shape[d] != 0;
            continue;
        }
        if (shape[d] == 0) {
            zero_dim = 1;
            continue;
        }
        if (numel > f->map_bytes / shape[d]) {
            char s[160];
            format_shape(s, sizeof s, (int)ndim, shape);
            return ws_fail(st, WS_EINPUT, "%s: tensor %s has shape %s, larger than the file", f->path,
                           t->name, s);
        }
        numel *= shape[d];
    }
    if (zero_dim || unused_set)
        return ws_fail(st, WS_EINPUT, "%s: tensor %s has a malformed shape (a zero dimension, or a "
                       "non-zero entry past ndim)", f->path, t->name);
    uint64_t element = dtype == WF_F32 ? 4 : 2;
    if (*nbytes != numel * element)
        return ws_fail(st, WS_EINPUT, "%s: tensor %s has %llu data bytes, its shape needs %llu", f->path,
                       t->name, (unsigned long long)*nbytes, (unsigned long long)(numel * element));
    if (*offset % WF_ALIGN != 0)
        return ws_fail(st, WS_EINPUT, "%s: tensor %s: data offset %llu is not %d-byte aligned", f->path,
                       t->name, (unsigned long long)*offset, WF_ALIGN);
    if (*offset < table_end)
        return ws_fail(st, WS_EINPUT, "%s: tensor %s: data offset %llu lies inside the header or table",
                       f->path, t->name, (unsigned long long)*offset);
    uint64_t data_end = f->map_bytes - WF_CRC_BYTES;
    if (*offset > data_end || *nbytes > data_end - *offset)
        return ws_fail(st, WS_EINPUT,
                       "%s: tensor %s lies outside the file (bytes %llu + %llu, data ends at %llu; "
                       "truncated?)",
                       f->path, t->name, (unsigned long long)*offset, (unsigned long long)*nbytes,
                       (unsigned long long)data_end);
    t->dtype = (int)dtype;
    t->ndim = (int)ndim;
    for (int d = 0; d < WF_MAX_DIMS; d++) t->shape[d] = (int64_t)shape[d];
    t->numel = (int64_t)numel;
    return WS_OK;
}

typedef struct {
    uint64_t offset, nbytes;
    int index;
} wf_span;

static int by_offset(const void *a, const void *b) {
    const wf_span *x = a, *y = b;
    return x->offset < y->offset ? -1 : x->offset > y->offset;
}

static int by_tensor_name(const void *a, const void *b) {
    return strcmp((*(const wf_tensor *const *)a)->name, (*(const wf_tensor *const *)b)->name);
}

static int check_overlaps_and_names(wf_file *f, wf_span *spans, ws_status *st) {
    f->by_name = ws_malloc((size_t)f->count * sizeof *f->by_name, "weight file table", st);
    if (!f->by_name) return st->code;
    for (int i = 0; i < f->count; i++) f->by_name[i] = &f->tensors[i];
    qsort(f->by_name, (size_t)f->count, sizeof *f->by_name, by_tensor_name);
    for (int i = 1; i < f->count; i++)
        if (strcmp(f->by_name[i - 1]->name, f->by_name[i]->name) == 0)
            return ws_fail(st, WS_EINPUT, "%s: tensor %s appears twice", f->path, f->by_name[i]->name);
    qsort(spans, (size_t)f->count, sizeof *spans, by_offset);
    for (int i = 1; i < f->count; i++)
        if (spans[i - 1].offset + spans[i - 1].nbytes > spans[i].offset)
            return ws_fail(st, WS_EINPUT, "%s: tensors %s and %s overlap", f->path,
                           f->tensors[spans[i - 1].index].name, f->tensors[spans[i].index].name);
    return WS_OK;
}

static int check_crc(wf_file *f, ws_status *st) {
    const unsigned char *p = f->map;
    size_t left = f->map_bytes - WF_CRC_BYTES;
    uLong crc = crc32(0L, Z_NULL, 0);
    while (left > 0) { /* zlib takes uInt lengths */
        uInt chunk = left > (1u << 30) ? (1u << 30) : (uInt)left;
        crc = crc32(crc, p, chunk);
        p += chunk;
        left -= chunk;
    }
    ws_bytes_reader r = {f->map, f->map_bytes, f->map_bytes - WF_CRC_BYTES, 0};
    uint32_t stored = ws_get_u32(&r);
    if (stored != (uint32_t)crc)
        return ws_fail(st, WS_EINPUT, "%s: checksum mismatch (stored %08x, computed %08x): the file is corrupt",
                       f->path, stored, (unsigned)crc);
    return WS_OK;
}

/* Points every tensor at its f32 values and refuses NaN or Inf anywhere.
 * An all-f32 file is used in place (in its mapping); a file with f16
 * tensors is widened whole into one block, f32 tensors copied beside them,
 * so that the mapping can be dropped and the f16 file costs no more memory
 * than its f32 values. */
static int load_values(wf_file *f, const uint64_t *offsets, ws_status *st) {
    uint64_t total_numel = 0; /* each tensor rounded up to 16 floats: 64-byte aligned starts */
    int any_f16 = 0;
    for (int i = 0; i < f->count; i++) {
        total_numel += ((uint64_t)f->tensors[i].numel + 15) / 16 * 16;
        any_f16 |= f->tensors[i].dtype == WF_F16;
    }
    if (any_f16) {
        if (total_numel > SIZE_MAX / sizeof(float))
            return ws_fail(st, WS_EINPUT, "%s: too large to widen on this machine", f->path);
        void *block = NULL;
        if (posix_memalign(&block, 64, (size_t)total_numel * sizeof(float)) != 0)
            return ws_fail(st, WS_ENOMEM, "out of memory widening the f16 weights of %s", f->path);
        f->widened = block;
    }
    float *next = f->widened;
    for (int i = 0; i < f->count; i++) {
        wf_tensor *t = &f->tensors[i];
        const unsigned char *src = (const unsigned char *)f->map + offsets[i];
        if (t->dtype == WF_F16) {
            for (int64_t k = 0; k < t->numel; k++)
                next[k] = half_to_float((uint16_t)(src[2 * k] | src[2 * k + 1] << 8));
        } else if (any_f16) {
            memcpy(next, src, (size_t)t->numel * sizeof(float));
        }
        /* f32 in place: 64-byte aligned in a page-aligned mapping */
        t->data = any_f16 ? next : (const float *)src;
        if (any_f16) next += (t->numel + 15) / 16 * 16;
        for (int64_t k = 0; k < t->numel; k++)
            if (!isfinite(t->data[k]))
                return ws_fail(st, WS_EINPUT, "%s: tensor %s has a non-finite value at index %lld", f->path,
                               t->name, (long long)k);
    }
    if (any_f16) {
        munmap(f->map, f->map_bytes);
        f->map = NULL;
    }
    return WS_OK;
}

static int parse(wf_file *f, ws_status *st) {
    ws_bytes_reader r = {f->map, f->map_bytes, 0, 0};
    uint32_t count = 0;
    if (read_header(f, &r, &count, st)) return st->code;
    f->count = (int)count;
    uint64_t table_end = WF_HEADER_BYTES + (uint64_t)count * WF_ENTRY_BYTES;
    f->tensors = ws_calloc(count, sizeof *f->tensors, "weight file table", st);
    wf_span *spans = ws_calloc(count, sizeof *spans, "weight file table", st);
    uint64_t *offsets = ws_calloc(count, sizeof *offsets, "weight file table", st);
    int rc = f->tensors && spans && offsets ? WS_OK : WS_ENOMEM;
    for (int i = 0; rc == WS_OK && i < f->count; i++) {
        rc = read_entry(f, &r, i, table_end, &f->tensors[i], &offsets[i], &spans[i].nbytes, st);
        spans[i].offset = offsets[i];
        spans[i].index = i;
    }
    if (rc == WS_OK) rc = check_overlaps_and_names(f, spans, st);
    if (rc == WS_OK) rc = check_crc(f, st);
    if (rc == WS_OK) rc = load_values(f, offsets, st);
    free(spans);
    free(offsets);
    return rc;
}

int wf_open(wf_file **out, const char *path, ws_status *st) {
    *out = NULL;
    wf_file *f = ws_calloc(1, sizeof *f, "weight file", st);
    if (!f) return st->code;
    f->path = ws_malloc(strlen(path) + 1, "weight file path", st);
    if (!f->path) {
        free(f);
        return st->code;
    }
    strcpy(f->path, path);
    if (map_file(f, st) || parse(f, st)) {
        int rc = st->code;
        wf_close(f);
        return rc;
    }
    *out = f;
    return WS_OK;
}

void wf_close(wf_file *f) {
    if (!f) return;
    if (f->map) munmap(f->map, f->map_bytes);
    free(f->widened);
    free(f->tensors);
    free(f->by_name);
    free(f->path);
    free(f);
}

const wf_arch *wf_architecture(const wf_file *f) { return &f->arch; }
const char *wf_path(const wf_file *f) { return f->path; }
int wf_count(const wf_file *f) { return f->count; }
const wf_tensor *wf_tensor_at(const wf_file *f, int i) { return &f->tensors[i]; }

int wf_get(const wf_file *f, const char *name, int ndim, const int64_t *shape, const float **data,
           ws_status *st) {
    if (ndim < 1 || ndim > WF_MAX_DIMS)
        return ws_fail(st, WS_EINTERNAL, "wf_get: %d dimensions asked for %s", ndim, name);
    int lo = 0, hi = f->count; /* binary search in by_name */
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2, c = strcmp(f->by_name[mid]->name, name);
        if (c < 0) {
            lo = mid + 1;
            continue;
        }
        if (c > 0) {
            hi = mid;
            continue;
        }
        const wf_tensor *t = f->by_name[mid];
        int same = t->ndim == ndim;
        for (int d = 0; same && d < ndim; d++) same = t->shape[d] == shape[d];
        if (!same) {
            uint64_t have[WF_MAX_DIMS], want[WF_MAX_DIMS];
            for (int d = 0; d < WF_MAX_DIMS; d++) {
                have[d] = (uint64_t)t->shape[d];
                want[d] = d < ndim ? (uint64_t)shape[d] : 0;
            }
            char hs[160], ws[160];
            format_shape(hs, sizeof hs, t->ndim, have);
            format_shape(ws, sizeof ws, ndim, want);
            return ws_fail(st, WS_EINPUT, "%s: tensor %s has shape %s, expected %s", f->path, name, hs, ws);
        }
        *data = t->data;
        return WS_OK;
    }
    return ws_fail(st, WS_EINPUT, "%s: tensor %s missing", f->path, name);
}
