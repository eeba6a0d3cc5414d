/* transforms.c: the transforms JSON, read and written (see transforms.h). */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/limits.h"
#include "base/outfile.h"
#include "base/paths.h"
#include "render/camera.h"
#include "io/transforms.h"
#include "nn/base/bytes.h"

/* The largest transforms file read: 64 MiB holds some 100 000 frames, and
 * cJSON needs several times the text's size in memory. */
#define TRANSFORMS_MAX_BYTES ((size_t)64 << 20)

const char *const ws_transforms_split_files[WS_NSPLITS] = {"transforms_train.json", "transforms_val.json",
                                                          "transforms_test.json"};

static const char *const list_keys[WS_NSPLITS] = {"train_filenames", "val_filenames", "test_filenames"};

struct ws_transforms {
    int kind;
    cJSON *root;
    cJSON **frame; /* frames[] as an array: frame k at once, not after k list steps */
    int n;
    char path[WS_PATH_MAX];
};

/* ---------------------------------------------------------------- reading */

/* 1-based line of a position in a text. */
static int line_of(const char *text, const char *at) {
    int line = 1;
    for (const char *c = text; c < at && *c; c++) line += *c == '\n';
    return line;
}

/* Reads a transforms file (bounded size) and parses it; its top level must
 * be an object. */
static int read_json(const char *path, cJSON **root_out, ws_status *st) {
    *root_out = NULL;
    unsigned char *bytes = NULL;
    size_t length = 0;
    if (ws_read_file(path, TRANSFORMS_MAX_BYTES, &bytes, &length, st)) return st->code;
    const char *text = (const char *)bytes;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, length, &end, 0);
    /* where parsing stopped: at the error, or after the value, where only
     * white space may follow (cJSON stops quietly after the first value) */
    const char *stop = end ? end : text + length;
    while (root && stop < text + length && *stop && strchr(" \t\r\n", *stop)) stop++;
    int rc = WS_OK;
    if (!root || stop < text + length)
        rc = ws_fail(st, WS_EINPUT, "%s: JSON syntax error near line %d", path, line_of(text, stop));
    else if (!cJSON_IsObject(root))
        rc = ws_fail(st, WS_EINPUT, "%s: not a JSON object", path);
    free(bytes);
    if (rc)
        cJSON_Delete(root);
    else
        *root_out = root;
    return rc;
}

/* root's "frames": a non-empty array. */
static int get_frames(const cJSON *root, const char *path, const cJSON **frames, ws_status *st) {
    *frames = cJSON_GetObjectItemCaseSensitive(root, "frames");
    if (!*frames) return ws_fail(st, WS_EINPUT, "%s: missing frames", path);
    if (!cJSON_IsArray(*frames)) return ws_fail(st, WS_EINPUT, "%s: frames is not an array", path);
    if (cJSON_GetArraySize(*frames) == 0) return ws_fail(st, WS_EINPUT, "%s: no frames", path);
    if (cJSON_GetArraySize(*frames) > WS_MAX_VIEWS) /* each view holds its paths: 14.5 KB before pixels */
        return ws_fail(st, WS_EINPUT, "%s: %d frames, more than the %d a scene file may have", path,
                       cJSON_GetArraySize(*frames), WS_MAX_VIEWS);
    return WS_OK;
}

/* A split file's camera_angle_x: present, a number, a valid angle. */
static int check_angle(const cJSON *root, const char *path, ws_status *st) {
    const cJSON *angle = cJSON_GetObjectItemCaseSensitive(root, "camera_angle_x");
    if (!angle) return ws_fail(st, WS_EINPUT, "%s: missing camera_angle_x", path);
    if (!cJSON_IsNumber(angle)) return ws_fail(st, WS_EINPUT, "%s: camera_angle_x is not a number", path);
    return ws_camera_check_angle(angle->valuedouble, path, st);
}

int ws_transforms_open(ws_transforms **out, const char *path, int kind, ws_status *st) {
    *out = NULL;
    ws_transforms *t = ws_calloc(1, sizeof *t, path, st);
    if (!t) return st->code;
    t->kind = kind;
    snprintf(t->path, sizeof t->path, "%s", path);
    const cJSON *frames = NULL;
    int rc = read_json(path, &t->root, st) || (kind == WS_TRANSFORMS_SPLIT && check_angle(t->root, path, st)) ||
             get_frames(t->root, path, &frames, st);
    if (!rc) {
        t->n = cJSON_GetArraySize(frames);
        t->frame = ws_malloc(sizeof *t->frame * t->n, path, st);
        rc = !t->frame;
    }
    if (rc) {
        ws_transforms_close(t);
        return st->code;
    }
    int k = 0;
    for (cJSON *f = frames->child; f; f = f->next) t->frame[k++] = f;
    *out = t;
    return WS_OK;
}

void ws_transforms_close(ws_transforms *t) {
    if (!t) return;
    cJSON_Delete(t->root);
    free(t->frame);
    free(t);
}

int ws_transforms_count(const ws_transforms *t) { return t->n; }

int ws_transforms_kind(const ws_transforms *t) { return t->kind; }

double ws_transforms_angle(const ws_transforms *t) {
    return cJSON_GetObjectItemCaseSensitive(t->root, "camera_angle_x")->valuedouble;
}

const char *ws_transforms_file_path(const ws_transforms *t, int k) {
    const cJSON *fp = cJSON_GetObjectItemCaseSensitive(t->frame[k], "file_path");
    return cJSON_IsString(fp) ? fp->valuestring : "";
}

int ws_transforms_aabb(const ws_transforms *t, double aabb[2][3], int *found, ws_status *st) {
    const cJSON *box = cJSON_GetObjectItemCaseSensitive(t->root, "aabb");
    *found = box != NULL;
    if (!box) return WS_OK;
    int ok = cJSON_IsArray(box) && cJSON_GetArraySize(box) == 2;
    for (int i = 0; i < 2 && ok; i++) {
        const cJSON *corner = cJSON_GetArrayItem(box, i);
        ok = cJSON_IsArray(corner) && cJSON_GetArraySize(corner) == 3;
        for (int a = 0; a < 3 && ok; a++) {
            const cJSON *x = cJSON_GetArrayItem(corner, a);
            ok = cJSON_IsNumber(x) && isfinite(x->valuedouble);
            if (ok) aabb[i][a] = x->valuedouble;
        }
    }
    if (!ok)
        return ws_fail(st, WS_EINPUT, "%s: aabb is not two triples of finite numbers [[x0,y0,z0],[x1,y1,z1]]",
                       t->path);
    for (int a = 0; a < 3; a++)
        if (!(aabb[0][a] < aabb[1][a]))
            return ws_fail(st, WS_EINPUT, "%s: aabb is empty along %c (%g >= %g)", t->path, "xyz"[a], aabb[0][a],
                           aabb[1][a]);
    return WS_OK;
}

int ws_transforms_ply_file(const ws_transforms *t, const char **name, ws_status *st) {
    const cJSON *ply = cJSON_GetObjectItemCaseSensitive(t->root, "ply_file_path");
    *name = NULL;
    if (!ply) return WS_OK;
    if (!cJSON_IsString(ply) || !ply->valuestring[0])
        return ws_fail(st, WS_EINPUT, "%s: ply_file_path is not a file name", t->path);
    *name = ply->valuestring;
    return WS_OK;
}

/* ---------------------------------------------------------------- splits */

#define SPLIT_PERIOD 8
#define VAL_PHASE 4

int ws_transforms_split_rule(int k) {
    return k % SPLIT_PERIOD == 0 ? WS_TEST : k % SPLIT_PERIOD == VAL_PHASE ? WS_VAL : WS_TRAIN;
}

/* The names of the *_filenames lists ("./" prefixes aside), each with its
 * split, sorted by name and then split, so that a frame finds its split by
 * binary search: searching the lists for every frame costs frames x names,
 * which a scene of 100,000 frames cannot afford. */
typedef struct {
    const char *name;
    int split;
} listed_name;

static int compare_listed(const void *a, const void *b) {
    const listed_name *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : x->split - y->split;
}

static int listed_names(const cJSON *root, const char *path, listed_name **out, int *n, ws_status *st) {
    size_t total = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        total += (size_t)cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, list_keys[s]));
    *n = 0;
    if (!(*out = ws_malloc((total ? total : 1) * sizeof **out, path, st))) return st->code;
    for (int s = 0; s < WS_NSPLITS; s++) {
        const cJSON *item;
        cJSON_ArrayForEach(item, cJSON_GetObjectItemCaseSensitive(root, list_keys[s])) {
            const char *name = cJSON_IsString(item) ? item->valuestring : "";
            (*out)[(*n)++] = (listed_name){strncmp(name, "./", 2) ? name : name + 2, s};
        }
    }
    qsort(*out, (size_t)*n, sizeof **out, compare_listed);
    return WS_OK;
}

/* The first split (train, val, test) whose list holds file_path, or -1. */
static int split_by_list(const listed_name *names, int n, const char *file_path) {
    if (!strncmp(file_path, "./", 2)) file_path += 2;
    int lo = 0, hi = n; /* the first entry not below file_path */
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (strcmp(names[mid].name, file_path) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && !strcmp(names[lo].name, file_path) ? names[lo].split : -1;
}

int ws_transforms_splits(const ws_transforms *t, int *split_of, ws_status *st) {
    int lists = 0;
    for (int s = 0; s < WS_NSPLITS; s++) lists |= cJSON_HasObjectItem(t->root, list_keys[s]);
    listed_name *listed = NULL;
    int nlisted = 0;
    if (lists && listed_names(t->root, t->path, &listed, &nlisted, st)) return st->code;
    for (int k = 0; k < t->n; k++) {
        const cJSON *fp = cJSON_GetObjectItemCaseSensitive(t->frame[k], "file_path");
        split_of[k] = !lists ? ws_transforms_split_rule(k)
                      : cJSON_IsString(fp) ? split_by_list(listed, nlisted, fp->valuestring)
                                           : WS_TRAIN; /* reported as it is read */
    }
    free(listed);
    return WS_OK;
}

/* ---------------------------------------------------------------- frames */

static int read_matrix(const cJSON *m, const char *what, double c2w[4][4], ws_status *st) {
    if (!cJSON_IsArray(m) || cJSON_GetArraySize(m) != 4)
        return ws_fail(st, WS_EINPUT, "%s: transform_matrix is not 4x4", what);
    for (int i = 0; i < 4; i++) {
        const cJSON *row = cJSON_GetArrayItem(m, i);
        if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != 4)
            return ws_fail(st, WS_EINPUT, "%s: transform_matrix is not 4x4", what);
        for (int j = 0; j < 4; j++) {
            const cJSON *x = cJSON_GetArrayItem(row, j);
            if (!cJSON_IsNumber(x))
                return ws_fail(st, WS_EINPUT, "%s: transform_matrix[%d][%d] is not a number", what,
                               i, j);
            c2w[i][j] = x->valuedouble;
        }
    }
    return WS_OK;
}

/* An optional path key: NULL when absent, else a string. */
static int optional_path(const cJSON *frame, const char *key, const char *what, const char **value,
                         ws_status *st) {
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(frame, key);
    *value = x && cJSON_IsString(x) ? x->valuestring : NULL;
    return x && !cJSON_IsString(x) ? ws_fail(st, WS_EINPUT, "%s: %s is not a string", what, key) : WS_OK;
}

int ws_transforms_frame_read(const ws_transforms *t, int k, const char *what, ws_transforms_frame *f,
                             ws_status *st) {
    const cJSON *frame = t->frame[k];
    memset(f, 0, sizeof *f);
    f->split = -1;
    if (!cJSON_IsObject(frame)) return ws_fail(st, WS_EINPUT, "%s: not a JSON object", what);
    const cJSON *fp = cJSON_GetObjectItemCaseSensitive(frame, "file_path");
    if (!fp) return ws_fail(st, WS_EINPUT, "%s: missing file_path", what);
    if (!cJSON_IsString(fp)) return ws_fail(st, WS_EINPUT, "%s: file_path is not a string", what);
    f->file_path = fp->valuestring;
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(frame, "transform_matrix");
    if (!m) return ws_fail(st, WS_EINPUT, "%s: missing transform_matrix", what);
    if (read_matrix(m, what, f->c2w, st) || optional_path(frame, "mask_path", what, &f->mask_path, st) ||
        optional_path(frame, "edge_path", what, &f->edge_path, st))
        return st->code;
    return WS_OK;
}

/* Intrinsic `key` of a frame: its own value, else the file's; *found = 0
 * when neither has one. */
static int intrinsic(const cJSON *frame, const cJSON *root, const char *key, const char *what,
                     double *value, int *found, ws_status *st) {
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(frame, key);
    if (!x) x = cJSON_GetObjectItemCaseSensitive(root, key);
    *found = x != NULL;
    if (!x) return WS_OK;
    if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble))
        return ws_fail(st, WS_EINPUT, "%s: %s is not a finite number", what, key);
    *value = x->valuedouble;
    return WS_OK;
}

static const char *const lens_keys[6] = {"k1", "k2", "k3", "k4", "p1", "p2"};

/* The lens of a frame, nerfstudio / instant-ngp keys: camera_model
 * PINHOLE, SIMPLE_PINHOLE, OPENCV or OPENCV_FISHEYE (none: OPENCV, or
 * instant-ngp's is_fisheye), k1..k4 (a fisheye lens' angle terms, else the
 * radial polynomial), p1, p2 (perspective only). */
static int frame_lens(const cJSON *frame, const cJSON *root, const char *what, ws_transforms_camera *in,
                      ws_status *st) {
    double v[6] = {0};
    int found;
    for (int k = 0; k < 6; k++)
        if (intrinsic(frame, root, lens_keys[k], what, &v[k], &found, st)) return st->code;
    const cJSON *model = cJSON_GetObjectItemCaseSensitive(frame, "camera_model");
    if (!model) model = cJSON_GetObjectItemCaseSensitive(root, "camera_model");
    const cJSON *fisheye = cJSON_GetObjectItemCaseSensitive(frame, "is_fisheye");
    if (!fisheye) fisheye = cJSON_GetObjectItemCaseSensitive(root, "is_fisheye");
    const char *name = cJSON_IsString(model) ? model->valuestring : model ? "" : "OPENCV";
    const int pinhole = !strcmp(name, "PINHOLE") || !strcmp(name, "SIMPLE_PINHOLE");
    if (!pinhole && strcmp(name, "OPENCV") && strcmp(name, "OPENCV_FISHEYE"))
        return ws_fail(st, WS_EINPUT,
                       "%s: camera_model is not PINHOLE, SIMPLE_PINHOLE, OPENCV or OPENCV_FISHEYE",
                       what);
    ws_lens *l = &in->lens;
    memset(l, 0, sizeof *l);
    l->fisheye = !strcmp(name, "OPENCV_FISHEYE") || cJSON_IsTrue(fisheye);
    for (int k = 0; k < 6; k++) {
        if (v[k] != 0 && pinhole)
            return ws_fail(st, WS_EINPUT, "%s: distortion %s = %g with camera_model %s (a lens "
                           "with distortion is OPENCV or OPENCV_FISHEYE)", what, lens_keys[k], v[k], name);
        if (v[k] != 0 && k >= 4 && l->fisheye)
            return ws_fail(st, WS_EINPUT, "%s: distortion %s = %g with a fisheye lens (it has "
                           "k1..k4 only)", what, lens_keys[k], v[k]);
    }
    memcpy(l->k, v, sizeof l->k);
    memcpy(l->p, v + 4, sizeof l->p);
    l->fx = in->fx, l->fy = in->fy, l->cx = in->cx, l->cy = in->cy;
    l->width = in->w, l->height = in->h;
    return ws_lens_check(l, what, st);
}

int ws_transforms_camera_read(const ws_transforms *t, int k, const char *what, ws_transforms_camera *in,
                              ws_status *st) {
    const cJSON *frame = t->frame[k], *root = t->root;
    double w = 0, h = 0;
    int has_w, has_h, has_fx, has_fy, has_cx, has_cy;
    if (intrinsic(frame, root, "w", what, &w, &has_w, st) ||
        intrinsic(frame, root, "h", what, &h, &has_h, st))
        return st->code;
    if (!has_w || !has_h) return ws_fail(st, WS_EINPUT, "%s: missing %s", what, has_w ? "h" : "w");
    if (!(w >= 1 && w <= 65536 && h >= 1 && h <= 65536 && w == floor(w) && h == floor(h)))
        return ws_fail(st, WS_EINPUT, "%s: w x h = %g x %g is not a size in pixels", what, w, h);
    in->w = (int)w;
    in->h = (int)h;
    if (intrinsic(frame, root, "fl_x", what, &in->fx, &has_fx, st)) return st->code;
    if (!has_fx) {
        double angle = 0;
        if (intrinsic(frame, root, "camera_angle_x", what, &angle, &has_fx, st)) return st->code;
        if (!has_fx) return ws_fail(st, WS_EINPUT, "%s: missing fl_x (or camera_angle_x)", what);
        if (ws_camera_check_angle(angle, what, st)) return st->code;
        in->fx = 0.5 * w / tan(0.5 * angle);
    }
    if (intrinsic(frame, root, "fl_y", what, &in->fy, &has_fy, st) ||
        intrinsic(frame, root, "cx", what, &in->cx, &has_cx, st) ||
        intrinsic(frame, root, "cy", what, &in->cy, &has_cy, st))
        return st->code;
    if (!has_fy) in->fy = in->fx;
    if (!has_cx) in->cx = 0.5 * w;
    if (!has_cy) in->cy = 0.5 * h;
    if (!(in->fx > 0) || !(in->fy > 0))
        return ws_fail(st, WS_EINPUT, "%s: fl_x %g and fl_y %g must be positive", what, in->fx, in->fy);
    return frame_lens(frame, root, what, in, st);
}

/* ---------------------------------------------------------------- writing */

/* Writes root as path; `newline` ends the text with one (a rewritten
 * file; the files of a written scene end at their closing brace). */
static int write_root(const char *path, const cJSON *root, int newline, ws_status *st) {
    char *text = cJSON_Print(root);
    if (!text) return ws_fail(st, WS_ENOMEM, "%s: out of memory building the JSON", path);
    ws_outfile f;
    int rc = ws_outfile_open(&f, path, st);
    if (!rc) {
        fputs(text, f.fp);
        if (newline) fputc('\n', f.fp);
        rc = ws_outfile_commit(&f, st);
    }
    cJSON_free(text);
    return rc;
}

/* train/val/test_filenames naming the file_path of every frame kept
 * (drop NULL or drop[k] == 0) in its split (split_of[k]; -1: in none), in
 * frame order; a list the root has is replaced where it stands. Returns 0
 * when out of memory. Each item goes to its parent as soon as it is made
 * (adding fails only for a NULL item), so a failure leaks nothing. */
static int set_split_lists(cJSON *root, const char *const *file_path, const int *split_of, const char *drop,
                           int n) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        cJSON *list = cJSON_CreateArray();
        int ok = list != NULL;
        for (int k = 0; k < n && ok; k++)
            if (!(drop && drop[k]) && split_of[k] == s) ok = cJSON_AddItemToArray(list, cJSON_CreateString(file_path[k]));
        if (ok)
            ok = cJSON_HasObjectItem(root, list_keys[s]) ? cJSON_ReplaceItemInObjectCaseSensitive(root, list_keys[s], list)
                                                         : cJSON_AddItemToObject(root, list_keys[s], list);
        if (!ok) {
            cJSON_Delete(list);
            return 0;
        }
    }
    return 1;
}

/* Adds the frames array; 0 when out of memory. */
static int add_frames(cJSON *root, const ws_transforms_frame *frames, int n) {
    cJSON *array = cJSON_AddArrayToObject(root, "frames");
    int ok = array != NULL;
    for (int k = 0; k < n && ok; k++) {
        const ws_transforms_frame *f = &frames[k];
        cJSON *frame = cJSON_CreateObject(), *m = NULL;
        ok = cJSON_AddItemToArray(array, frame) && cJSON_AddStringToObject(frame, "file_path", f->file_path) &&
             (!f->mask_path || cJSON_AddStringToObject(frame, "mask_path", f->mask_path)) &&
             (!f->edge_path || cJSON_AddStringToObject(frame, "edge_path", f->edge_path)) &&
             (m = cJSON_AddArrayToObject(frame, "transform_matrix"));
        for (int i = 0; i < 4 && ok; i++) ok = cJSON_AddItemToArray(m, cJSON_CreateDoubleArray(f->c2w[i], 4));
    }
    return ok;
}

int ws_transforms_write_split(const char *path, double camera_angle_x, const double object_position[3],
                              const ws_transforms_frame *frames, int n, ws_status *st) {
    cJSON *root = cJSON_CreateObject();
    int ok = root && cJSON_AddNumberToObject(root, "camera_angle_x", camera_angle_x) &&
             cJSON_AddItemToObject(root, "object_position", cJSON_CreateDoubleArray(object_position, 3)) &&
             add_frames(root, frames, n);
    int rc = ok ? write_root(path, root, 0, st) : ws_fail(st, WS_ENOMEM, "%s: out of memory building the JSON", path);
    cJSON_Delete(root);
    return rc;
}

int ws_transforms_write_nerfstudio(const char *path, const ws_transforms_camera *cam, const char *ply_file_path,
                                   const ws_transforms_frame *frames, int n, ws_status *st) {
    const ws_lens *l = &cam->lens;
    const double values[6] = {l->k[0], l->k[1], l->k[2], l->k[3], l->p[0], l->p[1]};
    /* OPENCV: k1, k2, p1, p2 always (nerfstudio's keys), k3 and k4 where set */
    static const int opencv[6] = {0, 1, 4, 5, 2, 3}, fisheye[4] = {0, 1, 2, 3};
    const int *order = l->fisheye ? fisheye : opencv, nkeys = l->fisheye ? 4 : 6;
    const char **names = ws_calloc(n ? n : 1, sizeof *names, path, st);
    int *split_of = names ? ws_malloc(sizeof *split_of * (n ? n : 1), path, st) : NULL;
    if (!split_of) {
        free(names);
        return st->code;
    }
    for (int k = 0; k < n; k++) names[k] = frames[k].file_path, split_of[k] = frames[k].split;
    cJSON *root = cJSON_CreateObject();
    int ok = root && cJSON_AddStringToObject(root, "camera_model", l->fisheye ? "OPENCV_FISHEYE" : "OPENCV") &&
             cJSON_AddNumberToObject(root, "fl_x", cam->fx) && cJSON_AddNumberToObject(root, "fl_y", cam->fy) &&
             cJSON_AddNumberToObject(root, "cx", cam->cx) && cJSON_AddNumberToObject(root, "cy", cam->cy) &&
             cJSON_AddNumberToObject(root, "w", cam->w) && cJSON_AddNumberToObject(root, "h", cam->h);
    for (int k = 0; k < nkeys && ok; k++)
        if (k < 4 || values[order[k]] != 0) ok = cJSON_AddNumberToObject(root, lens_keys[order[k]], values[order[k]]) != NULL;
    if (ok && ply_file_path) ok = cJSON_AddStringToObject(root, "ply_file_path", ply_file_path) != NULL;
    ok = ok && set_split_lists(root, names, split_of, NULL, n) && add_frames(root, frames, n);
    int rc = ok ? write_root(path, root, 0, st) : ws_fail(st, WS_ENOMEM, "%s: out of memory building the JSON", path);
    cJSON_Delete(root);
    free(names);
    free(split_of);
    return rc;
}

/* ---------------------------------------------------------------- rewriting */

/* The focal lengths of one object (the file's root or a frame) scaled:
 * fl_x and fl_y times `scale`, camera_angle_x to the angle of that focal. */
static void scale_focal(cJSON *object, double scale) {
    static const char *const lengths[2] = {"fl_x", "fl_y"};
    for (int k = 0; k < 2; k++) {
        cJSON *fl = cJSON_GetObjectItemCaseSensitive(object, lengths[k]);
        if (cJSON_IsNumber(fl)) cJSON_SetNumberValue(fl, fl->valuedouble * scale);
    }
    cJSON *angle = cJSON_GetObjectItemCaseSensitive(object, "camera_angle_x");
    if (cJSON_IsNumber(angle)) cJSON_SetNumberValue(angle, 2 * atan(tan(0.5 * angle->valuedouble) / scale));
}

/* The OpenCV flip of a matrix: its y and z columns negated. */
static void flip_axes(cJSON *m) {
    for (int i = 0; i < 3; i++)
        for (int j = 1; j <= 2; j++) {
            cJSON *e = cJSON_GetArrayItem(cJSON_GetArrayItem(m, i), j);
            cJSON_SetNumberValue(e, -e->valuedouble);
        }
}

int ws_transforms_rewrite(const ws_transforms *t, const ws_transforms_edit *e, const char *out_path,
                          ws_status *st) {
    const int n = t->n;
    cJSON *root = cJSON_Duplicate(t->root, 1), *frames = cJSON_GetObjectItemCaseSensitive(root, "frames");
    const char **names = root ? ws_calloc(n, sizeof *names, out_path, st) : NULL;
    int rc = !root ? ws_fail(st, WS_ENOMEM, "%s: out of memory copying the JSON", out_path) : names ? WS_OK : st->code;
    int k = 0, dropped = 0;
    for (cJSON *f = frames ? frames->child : NULL; f && !rc; f = f->next, k++) {
        if (e->camera[k] != k) { /* from the file as it was read, before any move */
            cJSON *moved = cJSON_Duplicate(cJSON_GetObjectItemCaseSensitive(t->frame[e->camera[k]], "transform_matrix"), 1);
            if (!moved || !cJSON_ReplaceItemInObjectCaseSensitive(f, "transform_matrix", moved)) {
                cJSON_Delete(moved);
                rc = ws_fail(st, WS_ENOMEM, "%s: out of memory copying the JSON", out_path);
            }
        }
        if (!rc && e->flip[k]) flip_axes(cJSON_GetObjectItemCaseSensitive(f, "transform_matrix"));
        if (e->focal_scale != 1) scale_focal(f, e->focal_scale);
        names[k] = ws_transforms_file_path(t, k);
        dropped += e->drop[k];
    }
    if (!rc && e->focal_scale != 1) scale_focal(root, e->focal_scale);
    if (!rc && t->kind == WS_TRANSFORMS_NERFSTUDIO && dropped && !set_split_lists(root, names, e->split_of, e->drop, n))
        rc = ws_fail(st, WS_ENOMEM, "out of memory for the split lists");
    for (k = n - 1; k >= 0 && !rc; k--)
        if (e->drop[k]) cJSON_DeleteItemFromArray(frames, k);
    if (!rc) rc = write_root(out_path, root, 1, st);
    cJSON_Delete(root);
    free(names);
    return rc;
}

int ws_transforms_is_file(const char *name, int nerfstudio) {
    return !strncmp(name, "transforms_", 11) || (nerfstudio && !strcmp(name, WS_TRANSFORMS_FILE));
}
