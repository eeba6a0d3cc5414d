/* test_weightfile.c: the flat weight file reader (weightfile.h) on a valid
 * file and on every kind of bad one, each refused with its exact message;
 * f16 widening checked bit-exactly over every finite half value. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "nn/base/bytes.h"
#include "check.h"
#include "test_util.h"
#include "nn/weightfile.h"

/* The file layout of weights/README.md, as offsets into a file. */
enum { HEADER = 40, ENTRY = 120, E_NAME = 0, E_DTYPE = 64, E_NDIM = 68, E_SHAPE = 72, E_OFFSET = 104,
       E_NBYTES = 112 };

typedef struct {
    const char *name;
    int dtype, ndim;
    uint64_t shape[4];
    const void *data; /* little-endian f32 or f16 values */
} spec;

static const char *dir;
static char path[256];

static uint64_t numel_of(const spec *s) {
    uint64_t n = 1;
    for (int d = 0; d < s->ndim; d++) n *= s->shape[d];
    return n;
}

/* A well-formed file: header, table, 64-byte aligned data, crc32. */
static void build(ws_bytes_writer *w, const uint32_t arch[6], const spec *specs, int count) {
    memset(w, 0, sizeof *w);
    ws_put(w, "WSKCLIP", 8);
    ws_put_u32(w, 1);
    for (int i = 0; i < 6; i++) ws_put_u32(w, arch[i]);
    ws_put_u32(w, (uint32_t)count);
    uint64_t offset = HEADER + (uint64_t)count * ENTRY;
    for (int i = 0; i < count; i++) {
        char name[64] = {0};
        strncpy(name, specs[i].name, 63);
        ws_put(w, name, 64);
        ws_put_u32(w, (uint32_t)specs[i].dtype);
        ws_put_u32(w, (uint32_t)specs[i].ndim);
        for (int d = 0; d < 4; d++) ws_put_u64(w, d < specs[i].ndim ? specs[i].shape[d] : 0);
        uint64_t nbytes = numel_of(&specs[i]) * (specs[i].dtype == WF_F32 ? 4 : 2);
        offset = (offset + 63) / 64 * 64;
        ws_put_u64(w, offset);
        ws_put_u64(w, nbytes);
        offset += nbytes;
    }
    for (int i = 0; i < count; i++) {
        static const char zeros[64];
        ws_put(w, zeros, (64 - w->len % 64) % 64);
        ws_put(w, specs[i].data, numel_of(&specs[i]) * (specs[i].dtype == WF_F32 ? 4 : 2));
    }
    ws_put_u32(w, (uint32_t)crc32(0, w->data, (uInt)w->len));
}

static void put_u32_at(ws_bytes_writer *w, size_t at, uint32_t v) {
    for (int i = 0; i < 4; i++) w->data[at + i] = (unsigned char)(v >> (8 * i));
}

static void put_u64_at(ws_bytes_writer *w, size_t at, uint64_t v) {
    for (int i = 0; i < 8; i++) w->data[at + i] = (unsigned char)(v >> (8 * i));
}

static uint64_t get_u64_at(const ws_bytes_writer *w, size_t at) {
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= (uint64_t)w->data[at + i] << (8 * i);
    return v;
}

/* After an edit: a correct checksum again, so the check under test is the one that fires. */
static void fix_crc(ws_bytes_writer *w) {
    put_u32_at(w, w->len - 4, (uint32_t)crc32(0, w->data, (uInt)(w->len - 4)));
}

static void save(const unsigned char *data, size_t len) {
    FILE *f = fopen(path, "wb");
    CHECK(f && fwrite(data, 1, len, f) == len && fclose(f) == 0, "cannot write %s", path);
}

/* Opens `len` bytes of `w` (saved to a file) and expects the message `want`. */
static void expect_refused(const ws_bytes_writer *w, size_t len, const char *want, const char *what) {
    save(w->data, len);
    wf_file *f = (wf_file *)1;
    ws_status st;
    ws_status_clear(&st);
    int rc = wf_open(&f, path, &st);
    CHECK(rc == WS_EINPUT && st.code == WS_EINPUT && f == NULL, "%s: rc %d", what, rc);
    CHECK(strcmp(st.msg, want) == 0, "%s:\n  got  '%s'\n  want '%s'", what, st.msg, want);
    if (rc == WS_OK) wf_close(f);
}

static const uint32_t arch[6] = {8, 1, 2, 4, 8, 4}; /* width layers heads patch resolution output */
static float a_values[40], c_values[5];
static uint16_t b_values[4] = {0x3c00, 0xc000, 0x0001, 0x7bff}; /* 1, -2, 2^-24, 65504 */
static spec base[3] = {{"a", WF_F32, 2, {4, 10}, a_values},
                       {"b", WF_F16, 1, {4}, b_values},
                       {"c", WF_F32, 1, {5}, c_values}};

static void test_valid(const ws_bytes_writer *w) {
    save(w->data, w->len);
    wf_file *f;
    ws_status st;
    ws_status_clear(&st);
    CHECK(wf_open(&f, path, &st) == WS_OK, "valid file refused: %s", st.msg);
    if (st.code) return;
    const wf_arch *a = wf_architecture(f);
    CHECK(a->width == 8 && a->layers == 1 && a->heads == 2 && a->patch == 4 && a->resolution == 8 &&
              a->output_dim == 4,
          "architecture %d %d %d %d %d %d", a->width, a->layers, a->heads, a->patch, a->resolution,
          a->output_dim);
    CHECK(strcmp(wf_path(f), path) == 0, "path %s", wf_path(f));
    CHECK(wf_count(f) == 3, "count %d", wf_count(f));
    const wf_tensor *b = wf_tensor_at(f, 1);
    CHECK(strcmp(b->name, "b") == 0 && b->dtype == WF_F16 && b->ndim == 1 && b->shape[0] == 4 && b->numel == 4,
          "entry 1: %s dtype %d ndim %d numel %lld", b->name, b->dtype, b->ndim, (long long)b->numel);
    const float want_b[4] = {1.0f, -2.0f, 0x1p-24f, 65504.0f};
    CHECK(memcmp(b->data, want_b, sizeof want_b) == 0, "f16 values %g %g %g %g", b->data[0], b->data[1],
          b->data[2], b->data[3]);
    const float *data;
    CHECK(wf_get(f, "a", 2, (const int64_t[]){4, 10}, &data, &st) == WS_OK &&
              memcmp(data, a_values, sizeof a_values) == 0,
          "wf_get a: %s", st.msg);
    CHECK(((uintptr_t)data % 64) == 0, "f32 data not 64-byte aligned");
    CHECK(wf_get(f, "c", 1, (const int64_t[]){5}, &data, &st) == WS_OK &&
              memcmp(data, c_values, sizeof c_values) == 0,
          "wf_get c: %s", st.msg);

    char want[512];
    snprintf(want, sizeof want, "%s: tensor zz missing", path);
    CHECK(wf_get(f, "zz", 1, (const int64_t[]){5}, &data, &st) == WS_EINPUT && strcmp(st.msg, want) == 0,
          "missing tensor: '%s'", st.msg);
    snprintf(want, sizeof want, "%s: tensor a has shape [4, 10], expected [10, 4]", path);
    CHECK(wf_get(f, "a", 2, (const int64_t[]){10, 4}, &data, &st) == WS_EINPUT && strcmp(st.msg, want) == 0,
          "mis-shaped tensor: '%s'", st.msg);
    snprintf(want, sizeof want, "%s: tensor c has shape [5], expected [5, 1]", path);
    CHECK(wf_get(f, "c", 2, (const int64_t[]){5, 1}, &data, &st) == WS_EINPUT && strcmp(st.msg, want) == 0,
          "wrong ndim: '%s'", st.msg);
    wf_close(f);
}

/* Every finite f16 bit pattern widens to exactly sign x mantissa x 2^exp. */
static void test_f16_widening(void) {
    enum { N = 63488 }; /* 65536 minus the 2048 Inf/NaN patterns */
    uint16_t *half = malloc(N * sizeof *half);
    int n = 0;
    for (uint32_t h = 0; h < 65536; h++)
        if (((h >> 10) & 0x1f) != 0x1f) half[n++] = (uint16_t)h;
    spec s[1] = {{"h", WF_F16, 1, {N}, half}};
    ws_bytes_writer w;
    build(&w, arch, s, 1);
    save(w.data, w.len);
    ws_bytes_writer_free(&w);
    wf_file *f;
    ws_status st;
    ws_status_clear(&st);
    CHECK(wf_open(&f, path, &st) == WS_OK, "f16 file refused: %s", st.msg);
    if (st.code == WS_OK) {
        const float *v = wf_tensor_at(f, 0)->data;
        int wrong = 0, first = -1;
        for (int i = 0; i < N; i++) {
            int e = (half[i] >> 10) & 0x1f, m = half[i] & 0x3ff;
            double want = e ? ldexp(1024 + m, e - 25) : ldexp(m, -24);
            if (half[i] & 0x8000) want = -want;
            int same = (double)v[i] == want && !signbit(v[i]) == !signbit(want);
            if (!same && first < 0) first = i;
            wrong += !same;
        }
        CHECK(wrong == 0, "%d of %d f16 values widened wrongly (first pattern %04x -> %.9g)", wrong, N,
              first >= 0 ? half[first] : 0, first >= 0 ? v[first] : 0.0);
        wf_close(f);
    }
    free(half);
}

static void test_refusals(ws_bytes_writer *w) {
    const size_t e0 = HEADER, e1 = HEADER + ENTRY, e2 = HEADER + 2 * ENTRY;
    const uint64_t data_end = w->len - 4;
    char want[1024];
    unsigned char *pristine = malloc(w->len);
    memcpy(pristine, w->data, w->len);
#define RESET() memcpy(w->data, pristine, w->len)

    snprintf(want, sizeof want, "%s: cannot open: No such file or directory", path);
    unlink(path);
    {
        wf_file *f;
        ws_status st;
        CHECK(wf_open(&f, path, &st) == WS_EINPUT && strcmp(st.msg, want) == 0, "missing file: '%s'", st.msg);
        CHECK(wf_open(&f, dir, &st) == WS_EINPUT && strstr(st.msg, ": not a regular file"),
              "directory: '%s'", st.msg);
    }

    snprintf(want, sizeof want, "%s: truncated (20 bytes; a weight file has at least 44)", path);
    expect_refused(w, 20, want, "truncated header");
    snprintf(want, sizeof want, "%s: truncated (0 bytes; a weight file has at least 44)", path);
    expect_refused(w, 0, want, "empty file");

    uint64_t c_offset = get_u64_at(w, e2 + E_OFFSET);
    snprintf(want, sizeof want,
             "%s: tensor c lies outside the file (bytes %llu + 20, data ends at %llu; truncated?)", path,
             (unsigned long long)c_offset, (unsigned long long)(data_end - 10));
    expect_refused(w, w->len - 10, want, "truncated data");
    snprintf(want, sizeof want,
             "%s: truncated or malformed (a table of 3 tensors does not fit in 300 bytes)", path);
    expect_refused(w, 300, want, "truncated table");

    w->data[0] = 'X';
    snprintf(want, sizeof want,
             "%s: not a wiresketch weight file (bad magic); convert weights with tools/convert_weights.py",
             path);
    expect_refused(w, w->len, want, "bad magic");
    RESET();

    put_u32_at(w, 8, 2);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: unsupported weight file version 2 (this build reads version 1)", path);
    expect_refused(w, w->len, want, "unknown version");
    RESET();

    put_u32_at(w, 12 + 2 * 4, 3); /* 3 heads do not divide width 8 */
    fix_crc(w);
    snprintf(want, sizeof want,
             "%s: bad architecture (width 8, layers 1, heads 3, patch 4, resolution 8, output_dim 4)", path);
    expect_refused(w, w->len, want, "bad architecture");
    RESET();

    put_u32_at(w, 36, 1000000000);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: 1000000000 tensors in the table, a 1-layer CLIP tower has 20", path);
    expect_refused(w, w->len, want, "huge tensor count");
    RESET();

    put_u32_at(w, 36, 20);
    fix_crc(w);
    snprintf(want, sizeof want,
             "%s: truncated or malformed (a table of 20 tensors does not fit in %zu bytes)", path,
             w->len);
    expect_refused(w, w->len, want, "tensor count past the file");
    RESET();

    w->data[w->len - 8] ^= 0x40; /* a bit of c's data */
    uint32_t computed = (uint32_t)crc32(0, w->data, (uInt)(w->len - 4));
    uint32_t stored = (uint32_t)crc32(0, pristine, (uInt)(w->len - 4));
    snprintf(want, sizeof want, "%s: checksum mismatch (stored %08x, computed %08x): the file is corrupt",
             path, stored, computed);
    expect_refused(w, w->len, want, "bad checksum");
    RESET();

    memset(w->data + e0 + E_NAME, 'n', 64); /* no NUL */
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor table entry 0 has a malformed name", path);
    expect_refused(w, w->len, want, "unterminated name");
    RESET();

    w->data[e0 + E_NAME + 10] = 'x'; /* garbage after the NUL */
    fix_crc(w);
    expect_refused(w, w->len, want, "name not NUL-padded");
    RESET();

    put_u32_at(w, e0 + E_DTYPE, 7);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a has unknown dtype 7", path);
    expect_refused(w, w->len, want, "unknown dtype");
    RESET();

    put_u32_at(w, e0 + E_NDIM, 5);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a has 5 dimensions (1 to 4 allowed)", path);
    expect_refused(w, w->len, want, "too many dimensions");
    RESET();

    put_u64_at(w, e0 + E_SHAPE, 0);
    fix_crc(w);
    snprintf(want, sizeof want,
             "%s: tensor a has a malformed shape (a zero dimension, or a non-zero entry past ndim)", path);
    expect_refused(w, w->len, want, "zero dimension");
    RESET();

    put_u64_at(w, e0 + E_SHAPE, 1ull << 62);
    put_u64_at(w, e0 + E_SHAPE + 8, 1ull << 62);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a has shape [%llu, %llu], larger than the file", path,
             1ull << 62, 1ull << 62);
    expect_refused(w, w->len, want, "huge dimensions");
    RESET();

    put_u32_at(w, e0 + E_NDIM, 4); /* product 2^64 wraps to 0 in naive arithmetic */
    for (int d = 0; d < 4; d++) put_u64_at(w, e0 + E_SHAPE + 8 * d, 1ull << 16);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a has shape [65536, 65536, 65536, 65536], larger than the file",
             path);
    expect_refused(w, w->len, want, "dimensions overflowing 64 bits");
    RESET();

    put_u64_at(w, e0 + E_NBYTES, 156);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a has 156 data bytes, its shape needs 160", path);
    expect_refused(w, w->len, want, "size mismatch");
    RESET();

    uint64_t a_offset = get_u64_at(w, e0 + E_OFFSET);
    put_u64_at(w, e0 + E_OFFSET, a_offset + 4);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a: data offset %llu is not 64-byte aligned", path,
             (unsigned long long)a_offset + 4);
    expect_refused(w, w->len, want, "unaligned offset");
    RESET();

    put_u64_at(w, e0 + E_OFFSET, 0);
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a: data offset 0 lies inside the header or table", path);
    expect_refused(w, w->len, want, "offset inside the table");
    RESET();

    put_u64_at(w, e1 + E_OFFSET, 1ull << 40);
    fix_crc(w);
    snprintf(want, sizeof want,
             "%s: tensor b lies outside the file (bytes %llu + 8, data ends at %llu; truncated?)", path,
             1ull << 40, (unsigned long long)data_end);
    expect_refused(w, w->len, want, "offset past the end");
    RESET();

    put_u64_at(w, e1 + E_OFFSET, UINT64_MAX - 63); /* offset + nbytes wraps */
    fix_crc(w);
    snprintf(want, sizeof want,
             "%s: tensor b lies outside the file (bytes %llu + 8, data ends at %llu; truncated?)", path,
             (unsigned long long)(UINT64_MAX - 63), (unsigned long long)data_end);
    expect_refused(w, w->len, want, "offset wrapping around");
    RESET();

    put_u64_at(w, e1 + E_OFFSET, a_offset + 64); /* inside a's 160 bytes */
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensors a and b overlap", path);
    expect_refused(w, w->len, want, "overlapping tensors");
    RESET();

    w->data[e2 + E_NAME] = 'a';
    fix_crc(w);
    snprintf(want, sizeof want, "%s: tensor a appears twice", path);
    expect_refused(w, w->len, want, "duplicate name");
    RESET();

    free(pristine);
#undef RESET
}

static void test_non_finite(void) {
    char want[512];
    float c_nan[5] = {1, 2, NAN, 4, 5};
    spec s[3] = {base[0], base[1], {"c", WF_F32, 1, {5}, c_nan}};
    ws_bytes_writer w;
    build(&w, arch, s, 3);
    snprintf(want, sizeof want, "%s: tensor c has a non-finite value at index 2", path);
    expect_refused(&w, w.len, want, "NaN in f32");
    ws_bytes_writer_free(&w);

    uint16_t b_inf[4] = {0x3c00, 0xfc00, 0, 0}; /* -Inf */
    spec t[3] = {base[0], {"b", WF_F16, 1, {4}, b_inf}, base[2]};
    build(&w, arch, t, 3);
    snprintf(want, sizeof want, "%s: tensor b has a non-finite value at index 1", path);
    expect_refused(&w, w.len, want, "Inf in f16");
    ws_bytes_writer_free(&w);
}

/* The longest table a header allows (4096 layers: 12 x 4096 + 8 tensors),
 * each tensor one element: names are checked and looked up through a sorted
 * index, so this loads at once (every pair compared took minutes at 200 000
 * tensors), finds its last name, and a duplicate at the very end is caught. */
static void test_long_table(void) {
    enum { N = 12 * 4096 + 8 };
    static char names[N][8];
    static spec s[N];
    static float one = 1.0f;
    for (int i = 0; i < N; i++) {
        snprintf(names[i], sizeof names[i], "t%05d", N - 1 - i); /* stored in reverse order */
        s[i] = (spec){names[i], WF_F32, 1, {1}, &one};
    }
    const uint32_t deep[6] = {8, 4096, 2, 4, 8, 4};
    ws_bytes_writer w;
    build(&w, deep, s, N);
    save(w.data, w.len);
    wf_file *f;
    ws_status st = {0};
    const float *data = NULL;
    CHECK(wf_open(&f, path, &st) == WS_OK, "long table refused: %s", st.msg);
    if (!st.code) {
        CHECK(wf_get(f, "t00000", 1, (const int64_t[]){1}, &data, &st) == WS_OK && data && *data == 1.0f,
              "wf_get in a long table: %s", st.msg);
        wf_close(f);
    }
    ws_bytes_writer_free(&w);
    char want[512];
    snprintf(names[N - 1], sizeof names[N - 1], "t%05d", N - 1);
    build(&w, deep, s, N);
    snprintf(want, sizeof want, "%s: tensor t%05d appears twice", path, N - 1);
    expect_refused(&w, w.len, want, "duplicate at the end of a long table");
    ws_bytes_writer_free(&w);
}

int main(void) {
    dir = test_tmpdir("weightfile");
    snprintf(path, sizeof path, "%s/w.bin", dir);
    for (int i = 0; i < 40; i++) a_values[i] = (float)(i - 17) * 0.37f;
    for (int i = 0; i < 5; i++) c_values[i] = 1e-3f * (float)(i + 1);

    ws_bytes_writer w;
    build(&w, arch, base, 3);
    CHECK(!w.failed, "building the test file failed");
    test_valid(&w);
    test_refusals(&w);
    ws_bytes_writer_free(&w);
    test_non_finite();
    test_f16_widening();
    test_long_table();
    return check_summary();
}
