/* colmap.c: COLMAP sparse models, text and binary (see colmap.h).
 *
 * Each file is read whole (bounded) and parsed from memory: text line by
 * line (a line's number goes into its messages), binary through the
 * bounds-checked reader of nn/base/bytes.h, every count from the file
 * checked against the bytes left before anything that size is allocated,
 * so a cut or hostile file is refused in one line, never read past. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "io/colmap.h"
#include "base/outfile.h"
#include "base/paths.h"
#include "nn/base/bytes.h"

/* The largest model files read: a million-point cloud with its tracks is
 * some 200 MB; cameras and images are far smaller. */
#define MAX_MODEL_BYTES ((size_t)1 << 30)
/* The smallest records of the binary files, to bound counts by the file's
 * size: a camera (id, model, width, height, 3 parameters), an image (id,
 * pose, camera, 1-byte name and its NUL, no 2D points), a point (id, xyz,
 * rgb, error, empty track). */
/* The largest split list read (SCENE/SPLIT_list.txt) */
#define MAX_LIST_BYTES ((size_t)64 << 20)
#define MIN_CAMERA_BYTES (4 + 4 + 8 + 8 + 3 * 8)
#define MIN_IMAGE_BYTES (4 + 7 * 8 + 4 + 2 + 8)
#define MIN_POINT_BYTES (8 + 3 * 8 + 3 + 8 + 8)

/* COLMAP's models beyond the seven lens.h has, by id from 7, so that a
 * binary file's id is named in the message. */
static const char *const other_models[] = {"FOV", "SIMPLE_RADIAL_FISHEYE", "RADIAL_FISHEYE",
                                           "THIN_PRISM_FISHEYE", "RAD_TAN_THIN_PRISM_FISHEYE"};

int ws_colmap_find(const char *dir, char *found, size_t size) {
    static const char *const folders[] = {"%s/sparse/0", "%s/sparse", "%s"};
    for (int k = 0; k < 3; k++) {
        char path[WS_PATH_MAX];
        int n = snprintf(found, size, folders[k], dir);
        if (n < 0 || (size_t)n >= size) return -1;
        snprintf(path, sizeof path, "%s/cameras.txt", found);
        if (access(path, F_OK) == 0) return 0;
        snprintf(path, sizeof path, "%s/cameras.bin", found);
        if (access(path, F_OK) == 0) return 0;
    }
    return -1;
}

void ws_colmap_free(ws_colmap_model *m) {
    free(m->cameras);
    free(m->images);
    free(m->points);
    memset(m, 0, sizeof *m);
}

const ws_colmap_camera *ws_colmap_camera_of(const ws_colmap_model *m, const ws_colmap_image *im) {
    for (int k = 0; k < m->ncameras; k++)
        if (m->cameras[k].id == im->camera_id) return &m->cameras[k];
    return NULL;
}

/* ---------------------------------------------------------------- poses */

void ws_colmap_to_c2w(const double q[4], const double t[3], double c2w[4][4]) {
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    /* world = R^T (c_cv - t), and c_cv = F c_gl: column j of the rotation
     * is R^T's column j times F's sign */
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) c2w[i][j] = R[j][i] * (j == 0 ? 1 : -1);
        c2w[i][3] = -(R[0][i] * t[0] + R[1][i] * t[1] + R[2][i] * t[2]);
        c2w[3][i] = 0;
    }
    c2w[3][3] = 1;
}

void ws_colmap_from_c2w(const double c2w[4][4], double q[4], double t[3]) {
    double R[3][3]; /* world-to-camera, OpenCV axes: F c2w_rot^T */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) R[i][j] = c2w[j][i] * (i == 0 ? 1 : -1);
    for (int i = 0; i < 3; i++)
        t[i] = -(R[i][0] * c2w[0][3] + R[i][1] * c2w[1][3] + R[i][2] * c2w[2][3]);
    /* Shepperd: from the largest of the four squares, so that no division
     * is by a small number */
    const double tr = R[0][0] + R[1][1] + R[2][2];
    if (tr >= R[0][0] && tr >= R[1][1] && tr >= R[2][2]) {
        const double s = 2 * sqrt(1 + tr);
        q[0] = s / 4, q[1] = (R[2][1] - R[1][2]) / s, q[2] = (R[0][2] - R[2][0]) / s,
        q[3] = (R[1][0] - R[0][1]) / s;
    } else if (R[0][0] >= R[1][1] && R[0][0] >= R[2][2]) {
        const double s = 2 * sqrt(1 + 2 * R[0][0] - tr);
        q[0] = (R[2][1] - R[1][2]) / s, q[1] = s / 4, q[2] = (R[0][1] + R[1][0]) / s,
        q[3] = (R[0][2] + R[2][0]) / s;
    } else if (R[1][1] >= R[2][2]) {
        const double s = 2 * sqrt(1 + 2 * R[1][1] - tr);
        q[0] = (R[0][2] - R[2][0]) / s, q[1] = (R[0][1] + R[1][0]) / s, q[2] = s / 4,
        q[3] = (R[1][2] + R[2][1]) / s;
    } else {
        const double s = 2 * sqrt(1 + 2 * R[2][2] - tr);
        q[0] = (R[1][0] - R[0][1]) / s, q[1] = (R[0][2] + R[2][0]) / s,
        q[2] = (R[1][2] + R[2][1]) / s, q[3] = s / 4;
    }
    if (q[0] < 0)
        for (int i = 0; i < 4; i++) q[i] = -q[i];
}

/* ---------------------------------------------------------------- reading */

/* Grows *array (of `size`-byte items, *cap of them) to hold n + 1. */
static int grow(void **array, int *cap, int n, size_t size, const char *what, ws_status *st) {
    if (n < *cap) return WS_OK;
    int next = *cap ? 2 * *cap : 16;
    void *p = realloc(*array, (size_t)next * size);
    if (!p) return ws_fail(st, WS_ENOMEM, "%s: out of memory", what);
    *array = p;
    *cap = next;
    return WS_OK;
}

/* The next line of a text (NUL-terminated in place), its number in *line;
 * NULL at the end. */
static char *next_line(char **cursor, int *line) {
    char *s = *cursor;
    if (!*s) return NULL;
    char *end = strchr(s, '\n');
    if (end) {
        *end = '\0';
        *cursor = end + 1;
    } else {
        *cursor = s + strlen(s);
    }
    (*line)++;
    return s;
}

/* A line with content: not blank, not a '#' comment. */
static int is_record(const char *s) {
    s += strspn(s, " \t\r");
    return *s && *s != '#';
}

static int parse_doubles(char **save, double *v, int n) {
    for (int k = 0; k < n; k++) {
        char *tok = strtok_r(NULL, " \t\r", save), *end;
        if (!tok) return k;
        v[k] = strtod(tok, &end);
        if (*end) return -1;
    }
    return n;
}

static int parse_int(const char *tok, int *v) {
    char *end;
    long x = tok ? strtol(tok, &end, 10) : 0;
    if (!tok || *end || x < 0 || x > 2147483647L) return -1;
    *v = (int)x;
    return 0;
}

/* One camera from its model name and parameters. */
static int add_camera(ws_colmap_model *m, int *cap, int id, const char *model, const double *params,
                      int nparams, long width, long height, const char *what, ws_status *st) {
    if (width < 1 || width > 65536 || height < 1 || height > 65536)
        return ws_fail(st, WS_EINPUT, "%s: size %ld x %ld is not an image size", what, width, height);
    for (int k = 0; k < m->ncameras; k++)
        if (m->cameras[k].id == id) return ws_fail(st, WS_EINPUT, "%s: camera id repeated", what);
    if (grow((void **)&m->cameras, cap, m->ncameras, sizeof *m->cameras, what, st)) return st->code;
    ws_colmap_camera *c = &m->cameras[m->ncameras];
    c->id = id;
    if (ws_lens_from_colmap(&c->lens, model, params, nparams, (int)width, (int)height, what, st))
        return st->code;
    m->ncameras++;
    return WS_OK;
}

static int check_image(const ws_colmap_model *m, const ws_colmap_image *im, const char *what,
                       const char *cameras_file, ws_status *st) {
    double n2 = 0;
    for (int i = 0; i < 4; i++) n2 += im->q[i] * im->q[i];
    if (!(n2 > 1e-12) || !isfinite(n2) || !isfinite(im->t[0] + im->t[1] + im->t[2]))
        return ws_fail(st, WS_EINPUT, "%s: pose is not finite or its quaternion is zero", what);
    if (!ws_colmap_camera_of(m, im))
        return ws_fail(st, WS_EINPUT, "%s: camera %d is not in %s", what, im->camera_id,
                       cameras_file);
    if (!im->name[0]) return ws_fail(st, WS_EINPUT, "%s: no file name", what);
    return WS_OK;
}

static int read_text(ws_colmap_model *m, const char *folder, ws_status *st) {
    char path[3][WS_PATH_MAX];
    const char *const names[3] = {"cameras.txt", "images.txt", "points3D.txt"};
    for (int f = 0; f < 3; f++) snprintf(path[f], sizeof path[f], "%s/%s", folder, names[f]);
    int rc = WS_OK, cap[3] = {0, 0, 0};
    for (int f = 0; f < 3 && !rc; f++) {
        unsigned char *bytes = NULL;
        size_t length;
        if (ws_read_file(path[f], MAX_MODEL_BYTES, &bytes, &length, st)) return st->code;
        char *cursor = (char *)bytes, *s, *save;
        int line = 0;
        while (!rc && (s = next_line(&cursor, &line))) {
            if (!is_record(s)) continue;
            char what[sizeof path + 200];
            snprintf(what, sizeof what, "%s: line %d", path[f], line);
            const char *first = strtok_r(s, " \t\r", &save);
            int id;
            if (parse_int(first, &id)) {
                rc = ws_fail(st, WS_EINPUT, "%s: '%s' is not an id", what, first);
                break;
            }
            if (f == 0) {
                snprintf(what + strlen(what), sizeof what - strlen(what), ": camera %d", id);
                const char *model = strtok_r(NULL, " \t\r", &save);
                double size[2], params[16];
                int np = parse_doubles(&save, size, 2), nq = np == 2 ? parse_doubles(&save, params, 16) : 0;
                if (np != 2 || nq < 0 || size[0] != floor(size[0]) || size[1] != floor(size[1]))
                    rc = ws_fail(st, WS_EINPUT, "%s: expected MODEL WIDTH HEIGHT PARAMS...", what);
                else
                    rc = add_camera(m, &cap[0], id, model ? model : "", params, nq, (long)size[0],
                                    (long)size[1], what, st);
            } else if (f == 1) {
                ws_colmap_image im = {0};
                im.id = id;
                double pose[7];
                const char *camera = NULL, *name = NULL;
                if (parse_doubles(&save, pose, 7) != 7 ||
                    parse_int(camera = strtok_r(NULL, " \t\r", &save), &im.camera_id) ||
                    !(name = strtok_r(NULL, " \t\r", &save))) {
                    rc = ws_fail(st, WS_EINPUT, "%s: image %d: expected QW QX QY QZ TX TY TZ CAMERA_ID NAME", what, id);
                    break;
                }
                memcpy(im.q, pose, sizeof im.q);
                memcpy(im.t, pose + 4, sizeof im.t);
                snprintf(what + strlen(what), sizeof what - strlen(what), ": image %d", id);
                if (strlen(name) >= sizeof im.name) {
                    rc = ws_fail(st, WS_EINPUT, "%s: file name too long", what);
                    break;
                }
                strcpy(im.name, name);
                if (!(rc = check_image(m, &im, what, names[0], st)) &&
                    !(rc = grow((void **)&m->images, &cap[1], m->nimages, sizeof im, what, st)))
                    m->images[m->nimages++] = im;
                next_line(&cursor, &line); /* its 2D points, unused */
            } else {
                double xyz[3];
                if (parse_doubles(&save, xyz, 3) != 3)
                    rc = ws_fail(st, WS_EINPUT, "%s: point %d: expected X Y Z R G B ERROR TRACK...", what, id);
                else if (!isfinite(xyz[0]) || !isfinite(xyz[1]) || !isfinite(xyz[2]))
                    rc = ws_fail(st, WS_EINPUT, "%s: point %d: coordinate is not finite", what, id);
                else if (!(rc = grow((void **)&m->points, &cap[2], m->npoints, 3 * sizeof(double), what, st)))
                    memcpy(m->points + 3 * (size_t)m->npoints++, xyz, sizeof xyz);
            }
        }
        free(bytes);
    }
    return rc;
}

/* The binary files: little-endian, as COLMAP writes them on every machine
 * it runs on. */
static int truncated(const char *path, const char *item, uint64_t k, uint64_t n, ws_status *st) {
    return ws_fail(st, WS_EINPUT, "%s: truncated (ends inside %s %llu of %llu)", path, item,
                   (unsigned long long)k + 1, (unsigned long long)n);
}

/* Skips n bytes, or marks the reader failed when fewer are left. */
static void skip(ws_bytes_reader *r, uint64_t n) {
    if (r->failed || n > r->len - r->pos) r->failed = 1;
    else r->pos += n;
}

static int read_binary(ws_colmap_model *m, const char *folder, ws_status *st) {
    char path[3][WS_PATH_MAX];
    const char *const names[3] = {"cameras.bin", "images.bin", "points3D.bin"};
    const char *const items[3] = {"camera", "image", "point"};
    const size_t min_bytes[3] = {MIN_CAMERA_BYTES, MIN_IMAGE_BYTES, MIN_POINT_BYTES};
    for (int f = 0; f < 3; f++) snprintf(path[f], sizeof path[f], "%s/%s", folder, names[f]);
    int rc = WS_OK;
    for (int f = 0; f < 3 && !rc; f++) {
        unsigned char *bytes = NULL;
        size_t length;
        if (ws_read_file(path[f], MAX_MODEL_BYTES, &bytes, &length, st)) return st->code;
        ws_bytes_reader r = {bytes, length, 0, 0};
        const uint64_t n = ws_get_u64(&r);
        if (r.failed || !ws_bytes_have(&r, n, min_bytes[f])) {
            rc = r.failed ? ws_fail(st, WS_EINPUT, "%s: truncated (no count)", path[f])
                          : ws_fail(st, WS_EINPUT, "%s: truncated (%llu %ss do not fit in its %zu bytes)",
                                    path[f], (unsigned long long)n, items[f], length);
            free(bytes);
            break;
        }
        int cap = (int)n;
        void **array = f == 0 ? (void **)&m->cameras : f == 1 ? (void **)&m->images : (void **)&m->points;
        const size_t item = f == 0 ? sizeof *m->cameras : f == 1 ? sizeof *m->images : 3 * sizeof(double);
        *array = n ? ws_calloc(n, item, path[f], st) : NULL;
        if (n && !*array) rc = st->code;
        for (uint64_t k = 0; k < n && !rc; k++) {
            char what[sizeof path + 200];
            snprintf(what, sizeof what, "%s: %s %llu", path[f], items[f], (unsigned long long)k + 1);
            if (f == 0) {
                const int id = (int)ws_get_u32(&r), model = (int)ws_get_u32(&r);
                const uint64_t w = ws_get_u64(&r), h = ws_get_u64(&r);
                const char *name = model >= 0 && model < ws_lens_model_count ? ws_lens_model_names[model]
                                   : model >= 7 && model < 12              ? other_models[model - 7]
                                                                           : "(unknown id)";
                double params[12];
                const int np = model >= 0 && model < ws_lens_model_count ? ws_lens_model_params[model] : 0;
                ws_get_f64s(&r, params, np);
                if (r.failed) rc = truncated(path[f], items[f], k, n, st);
                else /* cap: allocated above, so add_camera's grow never reallocates */
                    rc = add_camera(m, &cap, id, name, params, np, w > 65536 ? 0 : (long)w,
                                    h > 65536 ? 0 : (long)h, what, st);
            } else if (f == 1) {
                ws_colmap_image *im = &m->images[k];
                im->id = (int)ws_get_u32(&r);
                ws_get_f64s(&r, im->q, 4);
                ws_get_f64s(&r, im->t, 3);
                im->camera_id = (int)ws_get_u32(&r);
                size_t len = 0;
                while (r.pos + len < r.len && r.data[r.pos + len]) len++;
                if (r.pos + len >= r.len) {
                    rc = truncated(path[f], items[f], k, n, st);
                    break;
                }
                if (len >= sizeof im->name) {
                    rc = ws_fail(st, WS_EINPUT, "%s: file name too long", what);
                    break;
                }
                memcpy(im->name, r.data + r.pos, len);
                r.pos += len + 1;
                const uint64_t npoints2d = ws_get_u64(&r);
                if (r.failed || !ws_bytes_have(&r, npoints2d, 24)) {
                    rc = truncated(path[f], items[f], k, n, st);
                    break;
                }
                skip(&r, npoints2d * 24); /* x, y, point3D id: unused */
                snprintf(what, sizeof what, "%s: image %d", path[f], im->id);
                if (!(rc = check_image(m, im, what, names[0], st))) m->nimages++;
            } else {
                ws_get_u64(&r);
                double *xyz = m->points + 3 * k;
                ws_get_f64s(&r, xyz, 3);
                skip(&r, 3); /* rgb */
                ws_get_f64(&r);
                const uint64_t track = ws_get_u64(&r);
                if (r.failed || !ws_bytes_have(&r, track, 8)) {
                    rc = truncated(path[f], items[f], k, n, st);
                    break;
                }
                skip(&r, track * 8);
                if (!isfinite(xyz[0]) || !isfinite(xyz[1]) || !isfinite(xyz[2]))
                    rc = ws_fail(st, WS_EINPUT, "%s: coordinate is not finite", what);
                else
                    m->npoints++;
            }
        }
        free(bytes);
    }
    return rc;
}

int ws_colmap_read(ws_colmap_model *m, const char *folder, ws_status *st) {
    memset(m, 0, sizeof *m);
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/cameras.txt", folder);
    int rc = access(path, F_OK) == 0 ? read_text(m, folder, st) : read_binary(m, folder, st);
    if (!rc && m->nimages == 0)
        rc = ws_fail(st, WS_EINPUT, "%s: the model has no images", folder);
    if (rc) ws_colmap_free(m);
    return rc;
}

/* ---------------------------------------------------------------- writing */

static int write_bytes(const char *path, const ws_bytes_writer *w, ws_status *st) {
    if (w->failed) return ws_fail(st, WS_ENOMEM, "%s: out of memory", path);
    ws_outfile f;
    if (ws_outfile_open(&f, path, st)) return st->code;
    fwrite(w->data, 1, w->len, f.fp);
    return ws_outfile_commit(&f, st);
}

/* The model's camera parameters as COLMAP states them. */
static int camera_params(const ws_colmap_camera *c, double *params, const char *path, ws_status *st) {
    const int model = ws_lens_to_colmap(&c->lens, params);
    if (model < 0)
        return ws_fail(st, WS_EINTERNAL, "%s: camera %d: its lens has no COLMAP model", path, c->id);
    return model;
}

static int write_text(const ws_colmap_model *m, const char *folder, ws_status *st) {
    char path[WS_PATH_MAX];
    ws_outfile f;
    snprintf(path, sizeof path, "%s/cameras.txt", folder);
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "# Camera list with one line of data per camera:\n"
                  "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n");
    for (int k = 0; k < m->ncameras; k++) {
        double q[12];
        const int model = camera_params(&m->cameras[k], q, path, st);
        if (model < 0) {
            ws_outfile_abort(&f);
            return st->code;
        }
        fprintf(f.fp, "%d %s %d %d", m->cameras[k].id, ws_lens_model_names[model],
                m->cameras[k].lens.width, m->cameras[k].lens.height);
        for (int i = 0; i < ws_lens_model_params[model]; i++) fprintf(f.fp, " %.17g", q[i]);
        fputc('\n', f.fp);
    }
    if (ws_outfile_commit(&f, st)) return st->code;
    snprintf(path, sizeof path, "%s/images.txt", folder);
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "# Image list with two lines of data per image:\n"
                  "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
                  "#   POINTS2D[] as (X, Y, POINT3D_ID)\n");
    for (int k = 0; k < m->nimages; k++) {
        const ws_colmap_image *im = &m->images[k];
        fprintf(f.fp, "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %d %s\n\n", im->id, im->q[0],
                im->q[1], im->q[2], im->q[3], im->t[0], im->t[1], im->t[2], im->camera_id, im->name);
    }
    if (ws_outfile_commit(&f, st)) return st->code;
    snprintf(path, sizeof path, "%s/points3D.txt", folder);
    if (ws_outfile_open(&f, path, st)) return st->code;
    fprintf(f.fp, "# 3D point list with one line of data per point:\n"
                  "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n");
    for (int k = 0; k < m->npoints; k++)
        fprintf(f.fp, "%d %.17g %.17g %.17g 128 128 128 1\n", k + 1, m->points[3 * k],
                m->points[3 * k + 1], m->points[3 * k + 2]);
    return ws_outfile_commit(&f, st);
}

static int write_binary(const ws_colmap_model *m, const char *folder, ws_status *st) {
    char path[WS_PATH_MAX];
    ws_bytes_writer w = {0};
    snprintf(path, sizeof path, "%s/cameras.bin", folder);
    ws_put_u64(&w, (uint64_t)m->ncameras);
    for (int k = 0; k < m->ncameras; k++) {
        double q[12];
        const int model = camera_params(&m->cameras[k], q, path, st);
        if (model < 0) {
            ws_bytes_writer_free(&w);
            return st->code;
        }
        ws_put_u32(&w, (uint32_t)m->cameras[k].id);
        ws_put_u32(&w, (uint32_t)model);
        ws_put_u64(&w, (uint64_t)m->cameras[k].lens.width);
        ws_put_u64(&w, (uint64_t)m->cameras[k].lens.height);
        ws_put_f64s(&w, q, ws_lens_model_params[model]);
    }
    int rc = write_bytes(path, &w, st);
    ws_bytes_writer_free(&w);
    if (rc) return rc;
    snprintf(path, sizeof path, "%s/images.bin", folder);
    ws_put_u64(&w, (uint64_t)m->nimages);
    for (int k = 0; k < m->nimages; k++) {
        const ws_colmap_image *im = &m->images[k];
        ws_put_u32(&w, (uint32_t)im->id);
        ws_put_f64s(&w, im->q, 4);
        ws_put_f64s(&w, im->t, 3);
        ws_put_u32(&w, (uint32_t)im->camera_id);
        ws_put(&w, im->name, strlen(im->name) + 1);
        ws_put_u64(&w, 0); /* no 2D points */
    }
    rc = write_bytes(path, &w, st);
    ws_bytes_writer_free(&w);
    if (rc) return rc;
    snprintf(path, sizeof path, "%s/points3D.bin", folder);
    ws_put_u64(&w, (uint64_t)m->npoints);
    for (int k = 0; k < m->npoints; k++) {
        static const unsigned char grey[3] = {128, 128, 128};
        ws_put_u64(&w, (uint64_t)k + 1);
        ws_put_f64s(&w, m->points + 3 * (size_t)k, 3);
        ws_put(&w, grey, 3);
        ws_put_f64(&w, 1.0);
        ws_put_u64(&w, 0); /* empty track */
    }
    rc = write_bytes(path, &w, st);
    ws_bytes_writer_free(&w);
    return rc;
}

int ws_colmap_write(const ws_colmap_model *m, const char *folder, int binary, ws_status *st) {
    return binary ? write_binary(m, folder, st) : write_text(m, folder, st);
}

/* ---------------------------------------------------------------- split lists */

int ws_colmap_lists_read(const char *dir, ws_colmap_lists *l, ws_status *st) {
    memset(l, 0, sizeof *l);
    for (int s = 0; s < WS_NSPLITS; s++) {
        char path[WS_PATH_MAX];
        size_t length;
        snprintf(path, sizeof path, "%s/%s_list.txt", dir, ws_split_names[s]);
        if (access(path, F_OK) != 0) continue;
        l->any = 1;
        if (ws_read_file(path, MAX_LIST_BYTES, (unsigned char **)&l->text[s], &length, st)) {
            ws_colmap_lists_free(l);
            return st->code;
        }
    }
    return WS_OK;
}

void ws_colmap_lists_free(ws_colmap_lists *l) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        free(l->text[s]);
        l->text[s] = NULL;
    }
}

int ws_colmap_lists_split(const ws_colmap_lists *l, const char *name) {
    const size_t n = strlen(name);
    for (int s = 0; s < WS_NSPLITS; s++)
        for (const char *line = l->text[s]; line && *line; line += strcspn(line, "\n"), line += *line == '\n') {
            size_t len = strcspn(line, "\r\n");
            if (len == n && !strncmp(line, name, n)) return s;
        }
    return -1;
}

int ws_colmap_lists_write(const char *dir, const char *const *names, const int *split_of, int n, ws_status *st) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        char path[WS_PATH_MAX];
        ws_outfile list;
        snprintf(path, sizeof path, "%s/%s_list.txt", dir, ws_split_names[s]);
        if (ws_outfile_open(&list, path, st)) return st->code;
        for (int k = 0; k < n; k++)
            if (split_of[k] == s) fprintf(list.fp, "%s\n", names[k]);
        if (ws_outfile_commit(&list, st)) return st->code;
    }
    return WS_OK;
}
