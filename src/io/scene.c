/* scene.c: loading NeRF-synthetic scenes (see scene.h, METHOD.md section 1).
 *
 * Loading runs in two passes: first every transforms file is parsed and
 * every image path resolved (cheap, serial, so the first malformed frame is
 * the one reported), then the PNGs are decoded in parallel, each frame into
 * its own status, and the failure of the lowest frame wins. Frames are
 * numbered from 0 in messages, as they are indexed in frames[]. */
#include <cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/paths.h"
#include "io/scene.h"
#include "nn/base/bytes.h"

/* The largest transforms file read: 64 MiB holds some 100 000 frames, and
 * cJSON needs several times the text's size in memory. */
#define TRANSFORMS_MAX_BYTES ((size_t)64 << 20)

const char *const ws_split_names[WS_NSPLITS] = {"train", "val", "test"};

int ws_split_index(const char *name) {
    for (int s = 0; s < WS_NSPLITS; s++)
        if (!strcmp(name, ws_split_names[s])) return s;
    return -1;
}

void ws_scene_options_default(ws_scene_options *opt) {
    opt->width = opt->height = 224;
    opt->background[0] = opt->background[1] = opt->background[2] = 0.0f;
    opt->load_images = 1;
}

void ws_scene_free(ws_scene *scene) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        for (int k = 0; k < scene->split[s].n; k++) {
            ws_image_free(&scene->split[s].views[k].photo);
            ws_image_free(&scene->split[s].views[k].mask);
        }
        free(scene->split[s].views);
        scene->split[s].views = NULL;
        scene->split[s].n = 0;
    }
}

static int file_exists(const char *path) { return access(path, F_OK) == 0; }

static int ends_with(const char *s, const char *suffix) {
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && !strcmp(s + n - m, suffix);
}

/* Finds the PNG of `file_path`: SCENE/P.png, SCENE/rgb/P.png, and first
 * SCENE/P and SCENE/rgb/P when P already names a .png. */
static int resolve_image(const char *dir, const char *file_path, const char *what, char *found,
                         size_t size, ws_status *st) {
    const char *const patterns[4] = {"%s/%s", "%s/rgb/%s", "%s/%s.png", "%s/rgb/%s.png"};
    char tried[4][4096];
    int ntried = 0;
    for (int k = ends_with(file_path, ".png") ? 0 : 2; k < 4; k++) {
        int len = snprintf(tried[ntried], sizeof tried[0], patterns[k], dir, file_path);
        if (len < 0 || (size_t)len >= sizeof tried[0] || (size_t)len >= size)
            return ws_fail(st, WS_EINPUT, "%s: image path too long", what);
        if (file_exists(tried[ntried])) {
            strcpy(found, tried[ntried]);
            return WS_OK;
        }
        ntried++;
    }
    char list[3 * 4096 + 16] = "";
    for (int k = 0; k < ntried; k++) {
        if (k) strcat(list, ", ");
        strcat(list, tried[k]);
    }
    return ws_fail(st, WS_EINPUT, "%s: image not found (tried %s)", what, list);
}

/* Does file_path climb out of the scene directory (a ".." component)? A
 * scene is one self-contained directory: its transforms may name only
 * files inside it, so a scene from elsewhere cannot make wiresketch read
 * (and echo the names of) files beside or above it. */
static int leaves_scene(const char *file_path) {
    for (const char *c = file_path; *c; c = strchr(c, '/') ? strchr(c, '/') + 1 : c + strlen(c))
        if (c[0] == '.' && c[1] == '.' && (c[2] == '/' || c[2] == '\0')) return 1;
    return 0;
}

/* A path a frame names (file_path, mask_path): echoed in messages, which
 * are one line each, so no control character; and inside the scene. */
static int check_scene_path(const char *value, const char *field, const char *what, ws_status *st) {
    for (const char *c = value; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            return ws_fail(st, WS_EINPUT, "%s: %s contains a control character", what, field);
    if (leaves_scene(value))
        return ws_fail(st, WS_EINPUT, "%s: %s '%s' leaves the scene directory ('..')", what, field,
                       value);
    return WS_OK;
}

/* The view's name: the last component of file_path without ".png". */
static int view_name(const char *file_path, const char *what, char *name, size_t size,
                     ws_status *st) {
    const char *slash = strrchr(file_path, '/');
    const char *base = slash ? slash + 1 : file_path;
    size_t n = strlen(base);
    if (ends_with(base, ".png")) n -= 4;
    if (n == 0)
        return ws_fail(st, WS_EINPUT, "%s: file_path '%s' has no file name", what, file_path);
    if (n >= size) return ws_fail(st, WS_EINPUT, "%s: file_path name too long", what);
    memcpy(name, base, n);
    name[n] = '\0';
    return WS_OK;
}

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

/* One frame: its camera, name and (when images are wanted) image path. */
static int parse_frame(const cJSON *frame, const char *path, int index, double angle,
                       const char *dir, const ws_scene_options *opt, ws_view *v, ws_status *st) {
    char what[4300];
    snprintf(what, sizeof what, "%s: frame %d", path, index);
    if (!cJSON_IsObject(frame)) return ws_fail(st, WS_EINPUT, "%s: not a JSON object", what);
    const cJSON *fp = cJSON_GetObjectItemCaseSensitive(frame, "file_path");
    if (!fp) return ws_fail(st, WS_EINPUT, "%s: missing file_path", what);
    if (!cJSON_IsString(fp)) return ws_fail(st, WS_EINPUT, "%s: file_path is not a string", what);
    if (check_scene_path(fp->valuestring, "file_path", what, st)) return st->code;
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(frame, "transform_matrix");
    if (!m) return ws_fail(st, WS_EINPUT, "%s: missing transform_matrix", what);
    double c2w[4][4];
    if (read_matrix(m, what, c2w, st)) return st->code;
    if (ws_camera_init(&v->cam, c2w, angle, opt->width, opt->height, what, st)) return st->code;
    if (view_name(fp->valuestring, what, v->name, sizeof v->name, st)) return st->code;
    if (opt->load_images &&
        resolve_image(dir, fp->valuestring, what, v->image_path, sizeof v->image_path, st))
        return st->code;
    const cJSON *mp = cJSON_GetObjectItemCaseSensitive(frame, "mask_path");
    if (mp && !cJSON_IsString(mp))
        return ws_fail(st, WS_EINPUT, "%s: mask_path is not a string", what);
    if (mp && opt->load_images) {
        if (check_scene_path(mp->valuestring, "mask_path", what, st)) return st->code;
        char mask_what[4400];
        snprintf(mask_what, sizeof mask_what, "%s: mask_path", what);
        if (resolve_image(dir, mp->valuestring, mask_what, v->mask_path, sizeof v->mask_path, st))
            return st->code;
    }
    return WS_OK;
}

/* 1-based line of a position in a text. */
static int line_of(const char *text, const char *at) {
    int line = 1;
    for (const char *c = text; c < at && *c; c++) line += *c == '\n';
    return line;
}

/* Parses SCENE/transforms_SPLIT.json into `split` (cameras, names, image
 * paths; no pixels yet). A missing file leaves the split empty. */
static int parse_split(const char *dir, int s, const ws_scene_options *opt, ws_split *split,
                       double *angle_out, ws_status *st) {
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/transforms_%s.json", dir, ws_split_names[s]);
    split->n = 0;
    split->views = NULL;
    struct stat sb;
    if (stat(path, &sb) != 0 && errno == ENOENT) {
        if (s == WS_TRAIN)
            return ws_fail(st, WS_EINPUT, "%s: missing (a scene needs a train split)", path);
        return WS_OK;
    }
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
    if (!root || stop < text + length) {
        rc =
            ws_fail(st, WS_EINPUT, "%s: JSON syntax error near line %d", path, line_of(text, stop));
        goto done;
    }
    if (!cJSON_IsObject(root)) {
        rc = ws_fail(st, WS_EINPUT, "%s: not a JSON object", path);
        goto done;
    }
    const cJSON *angle = cJSON_GetObjectItemCaseSensitive(root, "camera_angle_x");
    const cJSON *frames = cJSON_GetObjectItemCaseSensitive(root, "frames");
    if (!angle)
        rc = ws_fail(st, WS_EINPUT, "%s: missing camera_angle_x", path);
    else if (!cJSON_IsNumber(angle))
        rc = ws_fail(st, WS_EINPUT, "%s: camera_angle_x is not a number", path);
    else if (ws_camera_check_angle(angle->valuedouble, path, st))
        rc = st->code;
    else if (!frames)
        rc = ws_fail(st, WS_EINPUT, "%s: missing frames", path);
    else if (!cJSON_IsArray(frames))
        rc = ws_fail(st, WS_EINPUT, "%s: frames is not an array", path);
    else if (cJSON_GetArraySize(frames) == 0)
        rc = ws_fail(st, WS_EINPUT, "%s: no frames", path);
    if (rc) goto done;
    *angle_out = angle->valuedouble;
    int n = cJSON_GetArraySize(frames);
    split->views = ws_calloc(n, sizeof *split->views, path, st);
    if (!split->views) {
        rc = st->code;
        goto done;
    }
    split->n = n;
    int index = 0;
    for (const cJSON *frame = frames->child; frame; frame = frame->next, index++)
        if ((rc = parse_frame(frame, path, index, angle->valuedouble, dir, opt,
                              &split->views[index], st)))
            break;
done:
    cJSON_Delete(root);
    free(bytes);
    return rc;
}

/* A mask from a 1-channel alpha or the first channel of a mask image:
 * 1 where the value is at least 1/2. */
static void threshold_mask(ws_image *m) {
    for (size_t p = 0; p < (size_t)m->width * m->height; p++) m->data[p] = m->data[p] >= 0.5f;
}

/* One view's photo and mask: the mask_path image when the frame names one,
 * else the photo's alpha. */
static int load_view(ws_view *v, const ws_scene_options *opt, ws_status *st) {
    int from_file = v->mask_path[0] != '\0';
    if (ws_png_read_alpha(v->image_path, opt->width, opt->height, opt->background, &v->photo,
                          from_file ? NULL : &v->mask, st))
        return st->code;
    if (from_file) {
        static const float black[3] = {0, 0, 0};
        ws_image rgb;
        if (ws_png_read(v->mask_path, opt->width, opt->height, black, &rgb, st)) return st->code;
        /* the first plane (red, or gray) is the mask; the rest is let go */
        size_t plane = (size_t)rgb.width * rgb.height;
        float *first = realloc(rgb.data, plane * sizeof *first);
        v->mask = (ws_image){rgb.width, rgb.height, 1, first ? first : rgb.data};
    }
    if (v->mask.data) threshold_mask(&v->mask);
    return WS_OK;
}

/* Decodes every view's PNG, in parallel; the failure of the lowest view (in
 * split, then frame order) is reported, whatever the schedule. */
static int load_photos(ws_scene *scene, const ws_scene_options *opt, ws_status *st) {
    int total = 0;
    for (int s = 0; s < WS_NSPLITS; s++) total += scene->split[s].n;
    ws_view **views = ws_malloc(sizeof *views * total, "the view list", st);
    ws_status *status = views ? ws_malloc(sizeof *status * total, "the view list", st) : NULL;
    if (!status) {
        free(views);
        return st->code;
    }
    for (int s = 0, k = 0; s < WS_NSPLITS; s++)
        for (int i = 0; i < scene->split[s].n; i++) views[k++] = &scene->split[s].views[i];
#pragma omp parallel for schedule(dynamic)
    for (int k = 0; k < total; k++) {
        ws_status_clear(&status[k]);
        load_view(views[k], opt, &status[k]);
    }
    int rc = WS_OK;
    for (int k = 0; k < total && !rc; k++)
        if (status[k].code) {
            *st = status[k];
            rc = st->code;
        }
    free(status);
    free(views);
    return rc;
}

/* The point nearest to every optical axis in the least-squares sense: with
 * unit directions d_k and positions p_k, minimise sum_k |(I - d_k d_k^T)(x - p_k)|^2,
 * i.e. solve sum (I - d d^T) x = sum (I - d d^T) p. */
static void axes_center(const ws_scene *scene, double center[3]) {
    double A[3][3] = {{0}}, b[3] = {0}, mean[3] = {0};
    int n = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            const ws_camera *cam = &scene->split[s].views[k].cam;
            double p[3], d[3];
            ws_camera_position(cam, p);
            /* The camera looks down its -z: the third column of c2w, negated.
             * Its length is not zero: the camera's matrix is not singular. */
            double len = sqrt(cam->c2w[0][2] * cam->c2w[0][2] + cam->c2w[1][2] * cam->c2w[1][2] +
                              cam->c2w[2][2] * cam->c2w[2][2]);
            for (int i = 0; i < 3; i++) d[i] = -cam->c2w[i][2] / len;
            for (int i = 0; i < 3; i++) {
                for (int j = 0; j < 3; j++) {
                    double m = (i == j) - d[i] * d[j];
                    A[i][j] += m;
                    b[i] += m * p[j];
                }
                mean[i] += p[i];
            }
            n++;
        }
    for (int i = 0; i < 3; i++) mean[i] /= n;
    double cof[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            cof[i][j] = A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1];
        }
    double det = A[0][0] * cof[0][0] + A[0][1] * cof[0][1] + A[0][2] * cof[0][2];
    /* A is symmetric positive semi-definite; det / (trace / 3)^3 is the
     * product of its eigenvalues over the cube of their mean, a scale-free
     * measure that is 0 when all axes are parallel (A has a null direction
     * along them) and 1 for axes spread evenly in all directions. */
    double mean_eig = (A[0][0] + A[1][1] + A[2][2]) / 3;
    if (det > 1e-9 * mean_eig * mean_eig * mean_eig) {
        for (int i = 0; i < 3; i++)
            center[i] = (cof[0][i] * b[0] + cof[1][i] * b[1] + cof[2][i] * b[2]) / det;
        return;
    }
    /* All axes (nearly) parallel, or a single camera: every point on a line
     * along them fits equally well, so the system cannot choose. Take, on
     * each axis, the point nearest the mean camera position, and average:
     * that stays on the bundle of axes and at the cameras' mean depth along
     * them, rather than at an arbitrary (possibly infinitely far) point. For
     * exactly parallel axes it is the mean camera position itself: where
     * along the axes the object lies, no intersection can tell. */
    for (int i = 0; i < 3; i++) center[i] = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            const ws_camera *cam = &scene->split[s].views[k].cam;
            double p[3], d[3], dot = 0, len2 = 0;
            ws_camera_position(cam, p);
            for (int i = 0; i < 3; i++) {
                d[i] = -cam->c2w[i][2];
                dot += d[i] * (mean[i] - p[i]);
                len2 += d[i] * d[i];
            }
            for (int i = 0; i < 3; i++) center[i] += (p[i] + dot / len2 * d[i]) / n;
        }
}

/* Everything downstream (initialisation radius, turntable, culling)
 * squares distances between the cameras and the centre: a camera so far
 * out that they overflow is refused here, naming its frame. */
static int check_distances(ws_scene *scene, ws_status *st) {
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            double p[3], d2 = 0;
            ws_camera_position(&scene->split[s].views[k].cam, p);
            for (int i = 0; i < 3; i++) d2 += (p[i] - scene->center[i]) * (p[i] - scene->center[i]);
            if (!isfinite(d2)) {
                ws_fail(st, WS_EINPUT,
                        "%s/transforms_%s.json: frame %d: camera too far out (its distance to the "
                        "scene centre overflows)",
                        scene->dir, ws_split_names[s], k);
                ws_scene_free(scene);
                return st->code;
            }
        }
    return WS_OK;
}

int ws_scene_load(ws_scene *scene, const char *dir, const ws_scene_options *opt, ws_status *st) {
    memset(scene, 0, sizeof *scene);
    if (opt->width <= 0 || opt->height <= 0)
        return ws_fail(st, WS_EUSAGE, "%s: working size %d x %d is not positive", dir, opt->width,
                       opt->height);
    if (strlen(dir) >= sizeof scene->dir) return ws_fail(st, WS_EUSAGE, "%s: path too long", dir);
    struct stat sb;
    if (stat(dir, &sb) != 0)
        return ws_fail(st, WS_EINPUT, "%s: cannot open scene directory: %s", dir, strerror(errno));
    if (!S_ISDIR(sb.st_mode)) return ws_fail(st, WS_EINPUT, "%s: not a directory", dir);
    strcpy(scene->dir, dir);
    scene->width = opt->width;
    scene->height = opt->height;
    for (int s = 0; s < WS_NSPLITS; s++) {
        double angle = 0;
        if (parse_split(dir, s, opt, &scene->split[s], &angle, st)) {
            ws_scene_free(scene);
            return st->code;
        }
        if (s == WS_TRAIN) scene->camera_angle_x = angle;
    }
    if (opt->load_images && load_photos(scene, opt, st)) {
        ws_scene_free(scene);
        return st->code;
    }
    axes_center(scene, scene->center);
    return check_distances(scene, st);
}
