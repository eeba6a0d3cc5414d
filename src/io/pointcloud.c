/* pointcloud.c: PLY point cloud reader (see pointcloud.h).
 *
 * The whole file is read into memory; the header is parsed into elements
 * and properties; the data is then walked with a bounds-checked cursor that
 * decodes one value at a time, so every type, byte order and skipped
 * property goes through the same few lines. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/outfile.h"
#include "nn/base/bytes.h"
#include "io/pointcloud.h"

#define PLY_MAX_BYTES ((size_t)1 << 34) /* 16 GiB: far beyond any real scan */
#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPERTIES 256
#define PLY_NAME 64
#define PLY_LINE 512

enum { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE };
enum { T_INT8, T_UINT8, T_INT16, T_UINT16, T_INT32, T_UINT32, T_FLOAT32, T_FLOAT64 };

static const struct {
    const char *name, *alias;
    int size;
} ply_types[] = {{"char", "int8", 1},   {"uchar", "uint8", 1},    {"short", "int16", 2},
                 {"ushort", "uint16", 2}, {"int", "int32", 4},    {"uint", "uint32", 4},
                 {"float", "float32", 4}, {"double", "float64", 8}};

typedef struct {
    char name[PLY_NAME];
    int type;       /* of the value, or of each item of a list */
    int count_type; /* of a list's length; -1 for a scalar property */
} ply_property;

typedef struct {
    char name[PLY_NAME];
    long long count;
    int nprop;
    ply_property prop[PLY_MAX_PROPERTIES];
} ply_element;

typedef struct {
    int format;
    int nelem;
    ply_element elem[PLY_MAX_ELEMENTS];
    size_t data_start; /* offset of the first byte after "end_header\n" */
} ply_header;

static int type_of(const char *word) {
    for (int i = 0; i < (int)(sizeof ply_types / sizeof ply_types[0]); i++)
        if (!strcmp(word, ply_types[i].name) || !strcmp(word, ply_types[i].alias)) return i;
    return -1;
}

static int copy_name(char dst[PLY_NAME], const char *src) {
    if (strlen(src) >= PLY_NAME) return -1;
    strcpy(dst, src);
    return 0;
}

static int split_words(char *line, char **word, int max) {
    int n = 0;
    char *save;
    for (char *p = strtok_r(line, " \t", &save); p; p = strtok_r(NULL, " \t", &save)) {
        if (n == max) return max + 1;
        word[n++] = p;
    }
    return n;
}

static int parse_header(const char *path, const unsigned char *buf, size_t len, ply_header *h,
                        ws_status *st) {
    size_t pos = 0;
    int have_format = 0;
    h->nelem = 0;
    for (int lineno = 1;; lineno++) {
        if (pos >= len && lineno == 1)
            return ws_fail(st, WS_EINPUT, "%s: not a PLY file (the first line is not 'ply')", path);
        if (pos >= len) return ws_fail(st, WS_EINPUT, "%s: the header has no end_header line", path);
        const unsigned char *nl = memchr(buf + pos, '\n', len - pos);
        size_t n = (nl ? (size_t)(nl - buf) : len) - pos;
        const char *start = (const char *)buf + pos;
        pos += n + 1;
        if (n > 0 && start[n - 1] == '\r') n--;
        if (lineno == 1) {
            if (n != 3 || memcmp(start, "ply", 3))
                return ws_fail(st, WS_EINPUT, "%s: not a PLY file (the first line is not 'ply')", path);
            continue;
        }
        /* Comments may be of any length and content: skip them unread. */
        if ((n >= 7 && !memcmp(start, "comment", 7)) || (n >= 8 && !memcmp(start, "obj_info", 8)))
            continue;
        if (n >= PLY_LINE)
            return ws_fail(st, WS_EINPUT, "%s: header line %d is too long", path, lineno);
        char line[PLY_LINE], *w[6];
        memcpy(line, start, n);
        line[n] = '\0';
        int nw = split_words(line, w, 5);
        if (nw == 0) continue;
        if (!strcmp(w[0], "format")) {
            if (nw != 3)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: expected 'format TYPE VERSION'", path, lineno);
            if (!strcmp(w[1], "ascii")) h->format = PLY_ASCII;
            else if (!strcmp(w[1], "binary_little_endian")) h->format = PLY_BINARY_LE;
            else if (!strcmp(w[1], "binary_big_endian")) h->format = PLY_BINARY_BE;
            else return ws_fail(st, WS_EINPUT, "%s: unsupported PLY format '%s'", path, w[1]);
            have_format = 1;
        } else if (!strcmp(w[0], "element")) {
            if (nw != 3)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: expected 'element NAME COUNT'", path, lineno);
            if (h->nelem == PLY_MAX_ELEMENTS)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: more than %d elements", path, lineno, PLY_MAX_ELEMENTS);
            ply_element *e = &h->elem[h->nelem++];
            char *end;
            errno = 0;
            e->count = strtoll(w[2], &end, 10);
            if (errno || *end || end == w[2] || e->count < 0)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: element count '%s' is not a valid count", path, lineno, w[2]);
            if (copy_name(e->name, w[1]))
                return ws_fail(st, WS_EINPUT, "%s: header line %d: name too long", path, lineno);
            e->nprop = 0;
        } else if (!strcmp(w[0], "property")) {
            if (h->nelem == 0)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: property before any element", path, lineno);
            ply_element *e = &h->elem[h->nelem - 1];
            if (e->nprop == PLY_MAX_PROPERTIES)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: more than %d properties", path, lineno, PLY_MAX_PROPERTIES);
            ply_property *p = &e->prop[e->nprop++];
            int is_list = nw >= 2 && !strcmp(w[1], "list");
            if (nw != (is_list ? 5 : 3))
                return ws_fail(st, WS_EINPUT, "%s: header line %d: expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'", path, lineno);
            p->count_type = is_list ? type_of(w[2]) : -1;
            p->type = type_of(w[is_list ? 3 : 1]);
            const char *bad = p->type < 0 ? w[is_list ? 3 : 1] : is_list && p->count_type < 0 ? w[2] : NULL;
            if (bad)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: unknown property type '%s'", path, lineno, bad);
            if (is_list && p->count_type >= T_FLOAT32)
                return ws_fail(st, WS_EINPUT, "%s: header line %d: list length type '%s' is not an integer type", path, lineno, w[2]);
            if (copy_name(p->name, w[is_list ? 4 : 2]))
                return ws_fail(st, WS_EINPUT, "%s: header line %d: name too long", path, lineno);
        } else if (!strcmp(w[0], "end_header")) {
            if (!have_format) return ws_fail(st, WS_EINPUT, "%s: the header has no format line", path);
            h->data_start = pos > len ? len : pos;
            return WS_OK;
        } else {
            return ws_fail(st, WS_EINPUT, "%s: header line %d: unknown keyword '%.32s'", path, lineno, w[0]);
        }
    }
}

/* A bounds-checked reading position in the data section. */
typedef struct {
    const unsigned char *p, *end;
    int format;
    char token[64]; /* the last ascii token, for error messages */
} ply_cursor;

enum { READ_OK = 0, READ_END = -1, READ_NOT_A_NUMBER = -2, READ_BAD_LENGTH = -3 };

static int read_ascii(ply_cursor *c, double *v) {
    while (c->p < c->end && isspace(*c->p)) c->p++;
    if (c->p == c->end) return READ_END;
    size_t n = 0;
    for (; c->p < c->end && !isspace(*c->p); c->p++, n++)
        if (n < sizeof c->token - 1) c->token[n] = (char)*c->p;
    c->token[n < sizeof c->token ? n : sizeof c->token - 1] = '\0';
    char *end;
    *v = strtod(c->token, &end);
    return n >= sizeof c->token || *end || end == c->token ? READ_NOT_A_NUMBER : READ_OK;
}

/* Decodes one value of `type`. Binary values are assembled byte by byte
 * from the file's byte order, so the host's order never matters. */
static int read_value(ply_cursor *c, int type, double *v) {
    if (c->format == PLY_ASCII) return read_ascii(c, v);
    int size = ply_types[type].size;
    if (c->end - c->p < size) return READ_END;
    uint64_t u = 0;
    for (int i = 0; i < size; i++)
        u = u << 8 | c->p[c->format == PLY_BINARY_LE ? size - 1 - i : i];
    c->p += size;
    switch (type) {
    case T_INT8: *v = (int8_t)u; break;
    case T_UINT8: *v = (uint8_t)u; break;
    case T_INT16: *v = (int16_t)u; break;
    case T_UINT16: *v = (uint16_t)u; break;
    case T_INT32: *v = (int32_t)u; break;
    case T_UINT32: *v = (uint32_t)u; break;
    case T_FLOAT32: {
        uint32_t bits = (uint32_t)u;
        float f;
        memcpy(&f, &bits, 4);
        *v = f;
        break;
    }
    default: memcpy(v, &u, 8); break;
    }
    return READ_OK;
}

/* Reads one property; a list is skipped (its value is of no use here). */
static int read_property(ply_cursor *c, const ply_property *p, double *v) {
    if (p->count_type < 0) return read_value(c, p->type, v);
    double count;
    int r = read_value(c, p->count_type, &count);
    if (r) return r;
    if (!(count >= 0 && count == floor(count))) return READ_BAD_LENGTH;
    *v = NAN;
    if (c->format != PLY_ASCII) {
        size_t size = (size_t)ply_types[p->type].size;
        if (count > (double)((size_t)(c->end - c->p) / size)) return READ_END;
        c->p += (size_t)count * size;
        return READ_OK;
    }
    /* Every ascii item consumes at least one byte, so this ends at the end
     * of the data whatever the count claims. */
    for (double i = 0; i < count; i++)
        if ((r = read_ascii(c, v))) return r;
    *v = NAN;
    return READ_OK;
}

/* Fails unless the rows of element e could fit into the data left: each
 * ascii value takes at least one character, a binary row at least its
 * scalars and list lengths. Guards every count taken from the header. */
static int rows_fit(const char *path, const ply_cursor *c, const ply_element *e, ws_status *st) {
    long long min_row = 0;
    for (int k = 0; k < e->nprop; k++) {
        const ply_property *p = &e->prop[k];
        min_row += c->format == PLY_ASCII ? 1 : ply_types[p->count_type < 0 ? p->type : p->count_type].size;
    }
    long long have = c->end - c->p;
    if (min_row > 0 && e->count > have / min_row)
        return ws_fail(st, WS_EINPUT, "%s: element '%s' claims %lld rows but only %lld bytes of data follow",
                       path, e->name, e->count, have);
    return WS_OK;
}

/* Reads every row of element e; when xyz is not NULL, stores the values of
 * the properties want[0..2] of each row there (row-major, 3 per row). */
static int read_rows(const char *path, ply_cursor *c, const ply_element *e, const int want[3],
                     double *xyz, ws_status *st) {
    /* A row without properties takes no bytes: nothing to walk. */
    if (e->nprop == 0) return WS_OK;
    if (rows_fit(path, c, e, st)) return st->code;
    for (long long row = 0; row < e->count; row++) {
        for (int k = 0; k < e->nprop; k++) {
            double v;
            int r = read_property(c, &e->prop[k], &v);
            if (r == READ_END)
                return ws_fail(st, WS_EINPUT, "%s: truncated: %lld of %lld %s rows present", path, row,
                               e->count, e->name);
            if (r == READ_NOT_A_NUMBER)
                return ws_fail(st, WS_EINPUT, "%s: %s row %lld: '%s' is not a number", path, e->name,
                               row, c->token);
            if (r == READ_BAD_LENGTH)
                return ws_fail(st, WS_EINPUT, "%s: %s row %lld: bad list length", path, e->name, row);
            if (!xyz) continue;
            for (int a = 0; a < 3; a++)
                if (k == want[a]) xyz[row * 3 + a] = v;
        }
        if (xyz && !(isfinite(xyz[row * 3]) && isfinite(xyz[row * 3 + 1]) && isfinite(xyz[row * 3 + 2])))
            return ws_fail(st, WS_EINPUT, "%s: %s row %lld has a non-finite coordinate", path, e->name, row);
    }
    return WS_OK;
}

static int read_points(const char *path, const unsigned char *buf, size_t len, ply_header *h,
                       ws_pointcloud *pc, ws_status *st) {
    if (parse_header(path, buf, len, h, st)) return st->code;
    int v = 0;
    while (v < h->nelem && strcmp(h->elem[v].name, "vertex")) v++;
    if (v == h->nelem) return ws_fail(st, WS_EINPUT, "%s: no vertex element", path);
    const ply_element *ve = &h->elem[v];
    int want[3] = {-1, -1, -1};
    static const char *axis[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; a++) {
        for (int k = 0; k < ve->nprop && want[a] < 0; k++)
            if (!strcmp(ve->prop[k].name, axis[a])) want[a] = k;
        if (want[a] < 0)
            return ws_fail(st, WS_EINPUT, "%s: vertex element has no property '%s'", path, axis[a]);
        if (ve->prop[want[a]].count_type >= 0)
            return ws_fail(st, WS_EINPUT, "%s: vertex property '%s' is a list", path, axis[a]);
    }
    if (ve->count == 0) return ws_fail(st, WS_EINPUT, "%s: no vertices", path);
    ply_cursor c = {.p = buf + h->data_start, .end = buf + len, .format = h->format};
    for (int e = 0; e < v; e++)
        if (read_rows(path, &c, &h->elem[e], NULL, NULL, st)) return st->code;
    if (rows_fit(path, &c, ve, st)) return st->code;
    if (ve->count > WS_MAX_POINTS)
        return ws_fail(st, WS_EINPUT, "%s: %lld vertices exceed the limit of %d", path, ve->count, WS_MAX_POINTS);
    pc->xyz = ws_malloc((size_t)ve->count * 3 * sizeof(double), "point cloud", st);
    if (!pc->xyz) return st->code;
    pc->n = (int)ve->count;
    return read_rows(path, &c, ve, want, pc->xyz, st);
}

int ws_pointcloud_load_ply(const char *path, ws_pointcloud *pc, ws_status *st) {
    pc->n = 0;
    pc->xyz = NULL;
    unsigned char *buf;
    size_t len;
    if (ws_read_file(path, PLY_MAX_BYTES, &buf, &len, st)) return st->code;
    ply_header *h = ws_malloc(sizeof *h, "PLY header", st);
    int rc = h ? read_points(path, buf, len, h, pc, st) : st->code;
    free(h);
    free(buf);
    if (rc) ws_pointcloud_free(pc);
    return rc;
}

void ws_pointcloud_free(ws_pointcloud *pc) {
    free(pc->xyz);
    pc->xyz = NULL;
    pc->n = 0;
}

int ws_pointcloud_save_ply(const char *path, const double *xyz, int n, ws_status *st) {
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                  "property double z\nend_header\n", n);
    for (int k = 0; k < n; k++) fprintf(f.fp, "%.17g %.17g %.17g\n", xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
    return ws_outfile_commit(&f, st);
}

void ws_points_bbox(const double *xyz, int n, double lo[3], double hi[3]) {
    for (int a = 0; a < 3; a++) lo[a] = hi[a] = n > 0 ? xyz[a] : 0;
    for (int i = 1; i < n; i++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], xyz[i * 3 + a]);
            hi[a] = fmax(hi[a], xyz[i * 3 + a]);
        }
}

double ws_points_diagonal(const double *xyz, int n) {
    double lo[3], hi[3];
    ws_points_bbox(xyz, n, lo, hi);
    return hypot(hypot(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
}
