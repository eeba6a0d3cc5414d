/* scene.c: loading scenes in their three layouts (see scene.h, METHOD.md section 1); the camera
 * files are read by their owners, io/transforms.h and io/colmap.h.
 *
 * Loading runs in two passes: first every transforms file is parsed and
 * every image path resolved (cheap, serial, so the first malformed frame is
 * the one reported), then the PNGs are decoded in parallel, each frame into
 * its own status, and the failure of the lowest frame wins. Frames are
 * numbered from 0 in messages, as they are indexed in frames[]. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>
#include "base/paths.h"
#include "io/colmap.h"
#include "io/pointcloud.h"
#include "io/scene.h"
#include "io/transforms.h"
#include "io/undistort.h"
#include "base/limits.h"
#include "io/view_crop.h"
#include "nn/base/bytes.h"

/* A message's prefix: a path and the item in it ("PATH: frame 12"). */
#define WHAT_MAX (WS_PATH_MAX + 64)

const char *ws_scene_file(const ws_scene *scene, int s) {
    return scene->layout == WS_LAYOUT_NERFSTUDIO ? WS_TRANSFORMS_FILE
           : scene->layout == WS_LAYOUT_COLMAP   ? scene->model_file
                                                 : ws_transforms_split_files[s];
}

int ws_split_index(const char *name) {
    for (int s = 0; s < WS_NSPLITS; s++)
        if (!strcmp(name, ws_split_names[s])) return s;
    return -1;
}

void ws_scene_options_default(ws_scene_options *opt) {
    opt->width = opt->height = 224;
    opt->background[0] = opt->background[1] = opt->background[2] = 0.0f;
    opt->background_auto = 0;
    opt->load_images = 1;
    opt->defer_images = 0;
    opt->edge_maps_dir = NULL;
    opt->images_dir = NULL;
    opt->masks_dir = NULL;
    opt->progress = NULL;
}

void ws_scene_free(ws_scene *scene) {
    for (int s = 0; s < WS_NSPLITS; s++) {
        for (int k = 0; k < scene->split[s].n; k++) {
            ws_image_free(&scene->split[s].views[k].photo);
            ws_image_free(&scene->split[s].views[k].mask);
            ws_image_free(&scene->split[s].views[k].edges);
        }
        free(scene->split[s].views);
        scene->split[s].views = NULL;
        scene->split[s].n = 0;
    }
    free(scene->points);
    scene->points = NULL;
    scene->npoints = 0;
}

const double *ws_scene_points(const ws_scene *scene, int *n) {
    *n = scene->npoints;
    return scene->points;
}

static int file_exists(const char *path) { return access(path, F_OK) == 0; }

/* The length of name's image extension (".png", ".jpg", ".jpeg", any
 * case), 0 when it has none. */
static size_t image_extension(const char *name) {
    static const char *const extensions[] = {".png", ".jpg", ".jpeg"};
    size_t n = strlen(name);
    for (size_t k = 0; k < sizeof extensions / sizeof extensions[0]; k++) {
        size_t m = strlen(extensions[k]);
        if (n > m && !strcasecmp(name + n - m, extensions[k])) return m;
    }
    return 0;
}

/* Finds the image of `file_path`: SCENE/P or SCENE/rgb/P when P ends in
 * an image extension (the name used as written), else SCENE/P.png or
 * SCENE/rgb/P.png (NeRF-synthetic names have none). Which format a file
 * holds, its content says (image.h). */
static int resolve_image(const char *dir, const char *file_path, const char *what, char *found,
                         size_t size, ws_status *st) {
    const char *const patterns[4] = {"%s/%s", "%s/rgb/%s", "%s/%s.png", "%s/rgb/%s.png"};
    char tried[2][WS_PATH_MAX];
    int ntried = 0;
    const int first = image_extension(file_path) ? 0 : 2;
    for (int k = first; k < first + 2; k++) {
        int len = snprintf(tried[ntried], sizeof tried[0], patterns[k], dir, file_path);
        if (len < 0 || (size_t)len >= sizeof tried[0] || (size_t)len >= size)
            return ws_fail(st, WS_EINPUT, "%s: image path too long", what);
        if (file_exists(tried[ntried])) {
            strcpy(found, tried[ntried]);
            return WS_OK;
        }
        ntried++;
    }
    char list[2 * WS_PATH_MAX + 16] = "";
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

/* The view's name: the last component of file_path without its image
 * extension. */
static int view_name(const char *file_path, const char *what, char *name, size_t size,
                     ws_status *st) {
    const char *slash = strrchr(file_path, '/');
    const char *base = slash ? slash + 1 : file_path;
    size_t n = strlen(base) - image_extension(base);
    if (n == 0)
        return ws_fail(st, WS_EINPUT, "%s: file_path '%s' has no file name", what, file_path);
    if (n >= size) return ws_fail(st, WS_EINPUT, "%s: file_path name too long", what);
    memcpy(name, base, n);
    name[n] = '\0';
    return WS_OK;
}

/* The view's image name (scene.h): file_path without "./", and without
 * its first folder where `in_folder` (a nerfstudio file names its images
 * "images/NAME"). */
static int set_image_name(ws_view *v, const char *file_path, int in_folder, const char *what, ws_status *st) {
    while (!strncmp(file_path, "./", 2)) file_path += 2;
    const char *slash = in_folder ? strchr(file_path, '/') : NULL;
    if (slash) file_path = slash + 1;
    if (strlen(file_path) >= sizeof v->image_name)
        return ws_fail(st, WS_EINPUT, "%s: file_path name too long", what);
    strcpy(v->image_name, file_path);
    return WS_OK;
}

/* ---------------------------------------------------------------- unique names
 *
 * A view's name names its outputs (a fit's test/NAME.png, render's
 * OUT/NAME.png) and its row of a report, so the views of a split must not
 * share one: views whose file names repeat ("a/r_0" and "b/r_0") are
 * named after their whole file_path instead ("a_r_0", "b_r_0"), and
 * names that still repeat get their frame index ("a_r_0_f7"). */
typedef struct {
    const char *name;
    int k;
} named_view;

static int by_name(const void *a, const void *b) {
    const named_view *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : x->k - y->k;
}

/* Marks in shared[k] the views whose name another view of the split has;
 * returns whether any has. */
static int mark_shared(const ws_split *split, named_view *order, char *shared) {
    for (int k = 0; k < split->n; k++) {
        order[k] = (named_view){split->views[k].name, k};
        shared[k] = 0;
    }
    qsort(order, split->n, sizeof *order, by_name);
    int any = 0;
    for (int i = 1; i < split->n; i++)
        if (!strcmp(order[i - 1].name, order[i].name)) any = shared[order[i - 1].k] = shared[order[i].k] = 1;
    return any;
}

static int unique_view_names(ws_split *split, const ws_transforms *t, const char *path, ws_status *st) {
    if (split->n < 2) return WS_OK;
    named_view *order = ws_malloc(sizeof *order * split->n, path, st);
    char *shared = order ? ws_malloc(split->n, path, st) : NULL;
    int rc = shared ? WS_OK : st->code;
    if (!rc && mark_shared(split, order, shared)) {
        for (int k = 0; k < split->n && !rc; k++) {
            ws_view *v = &split->views[k];
            const char *p = ws_transforms_file_path(t, v->frame);
            while (!strncmp(p, "./", 2)) p += 2;
            size_t n = strlen(p) - image_extension(p);
            if (!shared[k]) continue;
            if (n >= sizeof v->name) {
                rc = ws_fail(st, WS_EINPUT, "%s: frame %d: file_path name too long", path, v->frame);
                break;
            }
            for (size_t i = 0; i < n; i++) v->name[i] = p[i] == '/' ? '_' : p[i];
            v->name[n] = '\0';
        }
        int again = !rc && mark_shared(split, order, shared);
        for (int k = 0; k < split->n && again && !rc; k++) {
            ws_view *v = &split->views[k];
            size_t n = strlen(v->name);
            if (shared[k] && snprintf(v->name + n, sizeof v->name - n, "_f%d", v->frame) >= (int)(sizeof v->name - n))
                rc = ws_fail(st, WS_EINPUT, "%s: frame %d: file_path name too long", path, v->frame);
        }
        if (again && !rc && mark_shared(split, order, shared))
            for (int k = 0; k < split->n && !rc; k++)
                if (shared[k]) rc = ws_fail(st, WS_EINPUT, "%s: two views are named %s", path, split->views[k].name);
    }
    free(order);
    free(shared);
    return rc;
}

/* One frame, all but its camera: file_path (the view's name and, when
 * images are wanted, its image), mask_path, edge_path, and
 * transform_matrix into c2w. Messages start with `what`
 * ("SCENE/transforms_train.json: frame 3"). */
static int parse_frame(const ws_transforms *t, int index, const char *what, const char *dir,
                       const ws_scene_options *opt, ws_view *v, double c2w[4][4], ws_status *st) {
    ws_transforms_frame f;
    if (ws_transforms_frame_read(t, index, what, &f, st) || check_scene_path(f.file_path, "file_path", what, st) ||
        view_name(f.file_path, what, v->name, sizeof v->name, st) ||
        set_image_name(v, f.file_path, ws_transforms_kind(t) == WS_TRANSFORMS_NERFSTUDIO, what, st))
        return st->code;
    memcpy(c2w, f.c2w, sizeof f.c2w);
    if (!opt->load_images) return WS_OK;
    char field_what[WHAT_MAX + 16];
    if (resolve_image(dir, f.file_path, what, v->image_path, sizeof v->image_path, st)) return st->code;
    if (f.mask_path) {
        if (check_scene_path(f.mask_path, "mask_path", what, st)) return st->code;
        snprintf(field_what, sizeof field_what, "%s: mask_path", what);
        if (resolve_image(dir, f.mask_path, field_what, v->mask_path, sizeof v->mask_path, st)) return st->code;
    }
    if (opt->edge_maps_dir) {
        snprintf(field_what, sizeof field_what, "%s: --edge-maps", what);
        if (resolve_image(opt->edge_maps_dir, f.file_path, field_what, v->edge_path, sizeof v->edge_path, st))
            return st->code;
    } else if (f.edge_path) {
        if (check_scene_path(f.edge_path, "edge_path", what, st)) return st->code;
        snprintf(field_what, sizeof field_what, "%s: edge_path", what);
        if (resolve_image(dir, f.edge_path, field_what, v->edge_path, sizeof v->edge_path, st)) return st->code;
    }
    return WS_OK;
}

/* Parses SCENE/transforms_SPLIT.json into `split` (cameras, names, image
 * paths; no pixels yet). A missing file leaves the split empty. */
static int parse_split(ws_scene *scene, const char *dir, int s, const ws_scene_options *opt, ws_split *split,
                       double *angle_out, ws_status *st) {
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, ws_transforms_split_files[s]);
    split->n = 0;
    split->views = NULL;
    struct stat sb;
    if (stat(path, &sb) != 0 && errno == ENOENT) {
        if (s == WS_TRAIN)
            return ws_fail(st, WS_EINPUT,
                           "%s: missing (a scene needs a train split, a transforms.json or a "
                           "COLMAP model in sparse/0, sparse or the folder)",
                           path);
        return WS_OK;
    }
    ws_transforms *t;
    if (ws_transforms_open(&t, path, WS_TRANSFORMS_SPLIT, st)) return st->code;
    const double angle = ws_transforms_angle(t);
    const int n = ws_transforms_count(t);
    *angle_out = angle;
    split->views = ws_calloc(n, sizeof *split->views, path, st);
    int rc = split->views ? WS_OK : st->code;
    if (!rc) split->n = n;
    for (int index = 0; index < n && !rc; index++) {
        char what[WHAT_MAX];
        double c2w[4][4];
        ws_view *v = &split->views[index];
        v->frame = index;
        snprintf(what, sizeof what, "%s: frame %d", path, index);
        if (!(rc = parse_frame(t, index, what, dir, opt, v, c2w, st)))
            rc = ws_camera_init(&v->cam, c2w, angle, opt->width, opt->height, what, st);
    }
    if (!rc) rc = unique_view_names(split, t, path, st);
    if (!rc && s == WS_TRAIN) rc = ws_transforms_aabb(t, scene->aabb, &scene->has_aabb, st);
    ws_transforms_close(t);
    return rc;
}

/* ---------------------------------------------------------------- nerfstudio
 *
 * Scenes in the nerfstudio / instant-ngp layout, one SCENE/transforms.json
 * with pinhole intrinsics (see scene.h). The working view is a crop
 * around the object (io/view_crop.h). */

/* The working view's crop and camera (io/view_crop.h), first around the
 * frame's centre: crop_around_object moves it once every camera is known. */
static int frame_camera(const ws_lens *lens, const double c2w[4][4], const ws_scene_options *opt,
                        const char *what, ws_view *v, ws_status *st) {
    v->file_width = lens->width;
    v->file_height = lens->height;
    v->lens = *lens;
    return ws_view_crop(lens->fx, lens->fy, lens->cx, lens->cy, lens->width, lens->height, c2w, NULL, NULL,
                        opt->width, opt->height, what, v->crop, &v->cam, st);
}

/* Each cropped view's crop moved around the object's projection: the
 * centre the cameras look at (scene->center), or zoomed onto the object's
 * box when box is not NULL (a nerfstudio or COLMAP scene; the pinhole
 * intrinsics the view's images are undistorted to are v->lens's). */
static int crop_around_object(ws_scene *scene, const double box[6], const ws_scene_options *opt, ws_status *st) {
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            ws_view *v = &scene->split[s].views[k];
            const ws_lens *l = &v->lens;
            char what[WHAT_MAX];
            double c2w[4][4];
            memcpy(c2w, v->cam.c2w, sizeof c2w);
            snprintf(what, sizeof what, "%s/%s: frame %d", scene->dir, ws_scene_file(scene, s), v->frame);
            const int largest = v->crop[2]; /* before the zoom, the crop is the largest */
            if (ws_view_crop(l->fx, l->fy, l->cx, l->cy, l->width, l->height, c2w, scene->center, box, opt->width,
                             opt->height, what, v->crop, &v->cam, st))
                return st->code;
            scene->zoomed += box && v->crop[2] < largest;
        }
    return WS_OK;
}

/* nerfstudio's sparse points (ply_file_path, relative to the scene's
 * folder), kept as a COLMAP scene keeps its points3D. A file that is not
 * there leaves the scene without points (scene.h: points_missing): they
 * only place the region of interest, which the cameras place too, and a
 * transforms.json copied away from its capture without them should still
 * load; a file that is there must be a point cloud. */
static int sparse_points(ws_scene *scene, const ws_transforms *t, const char *dir, ws_status *st) {
    const char *name;
    char what[WS_PATH_MAX + 32], path[WS_PATH_MAX];
    snprintf(what, sizeof what, "%s/" WS_TRANSFORMS_FILE, dir);
    if (ws_transforms_ply_file(t, &name, st)) return st->code;
    if (!name) return WS_OK;
    if (check_scene_path(name, "ply_file_path", what, st)) return st->code;
    if (snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path)
        return ws_fail(st, WS_EINPUT, "%s: ply_file_path is too long", what);
    if (access(path, F_OK) != 0 && errno == ENOENT) {
        snprintf(scene->points_missing, sizeof scene->points_missing, "%s", path);
        return WS_OK;
    }
    ws_pointcloud pc;
    if (ws_pointcloud_load_ply(path, &pc, st)) return st->code;
    scene->points = pc.xyz; /* the scene keeps them */
    scene->npoints = pc.n;
    return WS_OK;
}

static int parse_nerfstudio(ws_scene *scene, const char *dir, const ws_scene_options *opt,
                            ws_status *st) {
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/" WS_TRANSFORMS_FILE, dir);
    ws_transforms *t;
    if (ws_transforms_open(&t, path, WS_TRANSFORMS_NERFSTUDIO, st)) return st->code;
    const int n = ws_transforms_count(t);
    int *split_of = ws_malloc(sizeof *split_of * n, path, st), rc = split_of ? WS_OK : st->code;
    int count[WS_NSPLITS] = {0};
    if (!rc) rc = ws_transforms_splits(t, split_of, st);
    for (int index = 0; index < n && !rc; index++)
        if (split_of[index] >= 0) count[split_of[index]]++;
    if (!rc && count[WS_TRAIN] == 0)
        rc = ws_fail(st, WS_EINPUT, "%s: no train frames (of %d frames)", path, n);
    for (int s = 0; s < WS_NSPLITS && !rc; s++) {
        scene->split[s].views = count[s] ? ws_calloc(count[s], sizeof(ws_view), path, st) : NULL;
        if (count[s] && !scene->split[s].views) rc = st->code;
    }
    for (int index = 0; index < n && !rc; index++) {
        int s = split_of[index];
        if (s < 0) continue;
        char what[WHAT_MAX];
        double c2w[4][4];
        ws_transforms_camera in;
        ws_view *v = &scene->split[s].views[scene->split[s].n++];
        v->frame = index;
        snprintf(what, sizeof what, "%s: frame %d", path, index);
        if (!(rc = parse_frame(t, index, what, dir, opt, v, c2w, st)) &&
            !(rc = ws_transforms_camera_read(t, index, what, &in, st)))
            rc = frame_camera(&in.lens, c2w, opt, what, v, st);
    }
    for (int s = 0; s < WS_NSPLITS && !rc; s++) rc = unique_view_names(&scene->split[s], t, path, st);
    if (!rc) rc = ws_transforms_aabb(t, scene->aabb, &scene->has_aabb, st);
    if (!rc) rc = sparse_points(scene, t, dir, st);
    if (!rc) {
        const ws_camera *first = &scene->split[WS_TRAIN].views[0].cam;
        scene->camera_angle_x = 2 * atan(0.5 * first->width / first->focal);
    }
    free(split_of);
    ws_transforms_close(t);
    return rc;
}

/* ---------------------------------------------------------------- COLMAP */

static int compare_image_names(const void *a, const void *b) {
    return strcmp((*(const ws_colmap_image *const *)a)->name, (*(const ws_colmap_image *const *)b)->name);
}

/* The COLMAP model in `folder` (ws_colmap_find) of scene `dir`. */
static int parse_colmap(ws_scene *scene, const char *dir, const char *folder,
                        const ws_scene_options *opt, ws_status *st) {
    ws_colmap_model model;
    if (ws_colmap_read(&model, folder, st)) return st->code;
    char images_file[WS_PATH_MAX + 16];
    snprintf(images_file, sizeof images_file, "%s/images.txt", folder);
    if (access(images_file, F_OK) != 0) snprintf(images_file, sizeof images_file, "%s/images.bin", folder);
    snprintf(scene->model_file, sizeof scene->model_file, "%s", images_file + strlen(dir) + 1);
    const int n = model.nimages;
    const ws_colmap_image **order = ws_malloc(sizeof *order * n, images_file, st);
    int rc = order ? WS_OK : st->code;
    ws_colmap_lists lists;
    if (!rc) rc = ws_colmap_lists_read(dir, &lists, st);
    int count[WS_NSPLITS] = {0}, *split_of = rc ? NULL : ws_malloc(sizeof *split_of * n, images_file, st);
    if (!rc && !split_of) rc = st->code;
    if (!rc) { /* frames in name order, as nerfstudio numbers them */
        for (int k = 0; k < n; k++) order[k] = &model.images[k];
        qsort(order, n, sizeof *order, compare_image_names);
        for (int k = 0; k < n; k++) {
            split_of[k] = lists.any ? ws_colmap_lists_split(&lists, order[k]->name) : ws_transforms_split_rule(k);
            if (split_of[k] >= 0) count[split_of[k]]++;
        }
        if (count[WS_TRAIN] == 0)
            rc = ws_fail(st, WS_EINPUT, "%s: no train images (of %d images)", images_file, n);
    }
    for (int s = 0; s < WS_NSPLITS && !rc; s++) {
        scene->split[s].views = count[s] ? ws_calloc(count[s], sizeof(ws_view), images_file, st) : NULL;
        if (count[s] && !scene->split[s].views) rc = st->code;
    }
    for (int k = 0; k < n && !rc; k++) {
        if (split_of[k] < 0) continue;
        const ws_colmap_image *im = order[k];
        const ws_lens *lens = &ws_colmap_camera_of(&model, im)->lens;
        ws_view *v = &scene->split[split_of[k]].views[scene->split[split_of[k]].n++];
        char what[WHAT_MAX];
        snprintf(what, sizeof what, "%s: image %d", images_file, im->id);
        v->frame = k;
        if ((rc = check_scene_path(im->name, "name", what, st)) ||
            (rc = view_name(im->name, what, v->name, sizeof v->name, st)) ||
            (rc = set_image_name(v, im->name, 0, what, st)))
            break;
        int len = opt->images_dir ? snprintf(v->image_path, sizeof v->image_path, "%s/%s", opt->images_dir, im->name)
                                  : snprintf(v->image_path, sizeof v->image_path, "%s/images/%s", dir, im->name);
        if (len < 0 || (size_t)len >= sizeof v->image_path) {
            rc = ws_fail(st, WS_EINPUT, "%s: image path too long", what);
            break;
        }
        if (opt->load_images && !file_exists(v->image_path)) {
            rc = ws_fail(st, WS_EINPUT, "%s: no file %s", what, v->image_path);
            break;
        }
        double c2w[4][4];
        ws_colmap_to_c2w(im->q, im->t, c2w);
        rc = frame_camera(lens, c2w, opt, what, v, st);
    }
    if (!rc) {
        const ws_camera *first = &scene->split[WS_TRAIN].views[0].cam;
        scene->camera_angle_x = 2 * atan(0.5 * first->width / first->focal);
        scene->points = model.points; /* the scene keeps them */
        scene->npoints = model.npoints;
        model.points = NULL;
    }
    if (order) ws_colmap_lists_free(&lists);
    free(split_of);
    free(order);
    ws_colmap_free(&model);
    return rc;
}

/* A mask from a 1-channel alpha or the first channel of a mask image:
 * 1 where the value is at least 1/2. */
static void threshold_mask(ws_image *m) {
    for (size_t p = 0; p < (size_t)m->width * m->height; p++) m->data[p] = m->data[p] >= 0.5f;
}

/* The first plane (red, or gray) of a planar image; the rest is let go
 * (kept allocated should the shrinking realloc fail). */
static ws_image first_plane(ws_image img) {
    float *first = realloc(img.data, (size_t)img.width * img.height * sizeof *first);
    return (ws_image){img.width, img.height, 1, first ? first : img.data};
}

/* img (the image file at 1 / reduced of its size a side) becomes the
 * view's part of its pinhole frame: undistorted through the view's lens,
 * where it has one, and cropped to v->crop (none: the whole frame), at
 * 1 / reduced of the frame's scale. Only the crop's pixels are made: a
 * capture's crop is a small part of a phone photo. fill: what
 * undistortion puts where the photo has nothing. */
static int to_view_crop(const ws_view *v, const float *fill, int reduced, ws_image *img, ws_status *st) {
    const int *k = v->crop[2] ? v->crop : NULL;
    ws_image part = {0};
    int rc;
    if (reduced > 1 || !ws_lens_is_pinhole(&v->lens)) { /* the lens' frame is the file's */
        const double rect[4] = {k ? k[0] : 0, k ? k[1] : 0, k ? k[2] : v->lens.width, k ? k[3] : v->lens.height};
        const int w = (int)fmax(1, round(rect[2] / reduced)), h = (int)fmax(1, round(rect[3] / reduced));
        rc = ws_image_undistort(img, 1.0 / reduced, &v->lens, fill, rect, w, h, &part, st);
    } else if (k) {
        rc = ws_image_crop(img, k[0], k[1], k[2], k[3], &part, st);
    } else {
        return WS_OK;
    }
    ws_image_free(img);
    *img = part;
    return rc;
}

/* How many times the working size a side a crop keeps when its photo is
 * decoded smaller. The crop is sampled bilinearly at the decoded scale,
 * which blurs by about a decoded pixel; averaged down by 4 or more, that
 * is a quarter of a working pixel, as from the whole photo, while by 2
 * the thin edges move and the fits with them (docs/RESULTS.md, "Loading
 * large photos"). */
#define WS_DECODED_CROP_OVER_WORKING 4

/* The factor a view's photo, and its mask, are decoded smaller by
 * (image.h): the largest of 2, 4 and 8 that leaves its crop
 * WS_DECODED_CROP_OVER_WORKING times the working size a side or more; 1
 * where none does, where the frame's size is not known (a NeRF-synthetic
 * scene) or where an edge map must meet the photo at the file's size (its
 * 1-pixel lines would fade in the blocks' means). */
static int photo_reduction(const ws_view *v, const ws_scene_options *opt) {
    if (!v->file_width || v->edge_path[0]) return 1;
    const int w = v->crop[2] ? v->crop[2] : v->file_width, h = v->crop[2] ? v->crop[3] : v->file_height;
    const int kw = WS_DECODED_CROP_OVER_WORKING * opt->width, kh = WS_DECODED_CROP_OVER_WORKING * opt->height;
    int reduce = 1;
    while (reduce < 8 && w / (2 * reduce) >= kw && h / (2 * reduce) >= kh) reduce *= 2;
    return reduce;
}

/* The view's edge map read like its photo: resampled to the image file's
 * size w x h, its first channel kept, cropped, resampled to the working size. */
static int load_edge_map(ws_view *v, int w, int h, const ws_scene_options *opt, ws_status *st) {
    static const float black[3] = {0, 0, 0}, none = 0;
    ws_image rgb = {0};
    int rc = ws_image_read(v->edge_path, w, h, black, &rgb, st);
    if (rc) return rc;
    ws_image gray = first_plane(rgb);
    rc = to_view_crop(v, &none, 1, &gray, st);
    if (!rc) rc = ws_image_resample(&gray, opt->width, opt->height, &v->edges, st);
    ws_image_free(&gray);
    return rc;
}

/* One view's photo and mask, at the working size: the image decoded at
 * 1 / photo_reduction of its size (alpha composited), its mask (the
 * mask_path image decoded at the same scale, else the alpha), the
 * background where a mask_path says so, then the crop (nerfstudio) and the
 * resampling to the working size. */
static int load_view(ws_view *v, const ws_scene_options *opt, ws_status *st) {
    static const float black[3] = {0, 0, 0};
    const int from_file = v->mask_path[0] != '\0';
    ws_image full = {0}, alpha = {0};
    int reduced, file_size[2];
    int rc = ws_image_read_reduced(v->image_path, photo_reduction(v, opt),
                                   opt->background_auto ? black : opt->background, &full, &alpha, &reduced,
                                   file_size, st);
    v->reduced = rc ? 0 : reduced;
    if (!rc && v->file_width && (file_size[0] != v->file_width || file_size[1] != v->file_height))
        rc = ws_fail(st, WS_EINPUT, "%s: image is %d x %d but the scene file says w x h = %d x %d",
                     v->image_path, file_size[0], file_size[1], v->file_width, v->file_height);
    const size_t plane = (size_t)full.width * full.height;
    float bg[3] = {opt->background[0], opt->background[1], opt->background[2]};
    if (!rc && opt->background_auto) {
        float *scratch = ws_malloc(sizeof *scratch * 2 * (full.width + full.height), "border", st);
        if (!scratch) rc = st->code;
        if (!rc) ws_image_border_median(&full, bg, scratch);
        free(scratch);
        for (size_t p = 0; !rc && alpha.data && p < plane; p++) /* now onto bg, not black */
            for (int c = 0; c < 3; c++) full.data[c * plane + p] += (1 - alpha.data[p]) * bg[c];
    }
    if (!rc && from_file) { /* at the photo's scale */
        ws_image_free(&alpha);
        ws_image rgb;
        int mask_reduced, mask_size[2];
        rc = ws_image_read_reduced(v->mask_path, reduced, black, &rgb, NULL, &mask_reduced, mask_size, st);
        if (!rc && (mask_size[0] != file_size[0] || mask_size[1] != file_size[1])) {
            rc = ws_fail(st, WS_EINPUT, "%s: mask is %d x %d but its image %s is %d x %d", v->mask_path, mask_size[0],
                         mask_size[1], v->image_path, file_size[0], file_size[1]);
            ws_image_free(&rgb);
        }
        if (!rc) { /* the first plane is the mask */
            alpha = first_plane(rgb);
            for (size_t p = 0; p < plane; p++)
                if (alpha.data[p] < 0.5f)
                    for (int c = 0; c < 3; c++) full.data[c * plane + p] = bg[c];
        }
    }
    if (!rc && v->edge_path[0]) rc = load_edge_map(v, full.width, full.height, opt, st);
    static const float transparent = 0; /* to the pinhole camera; outside: background */
    if (!rc) rc = to_view_crop(v, bg, reduced, &full, st);
    if (!rc && alpha.data) rc = to_view_crop(v, &transparent, reduced, &alpha, st);
    if (!rc && (full.width != opt->width || full.height != opt->height)) {
        rc = ws_image_resample(&full, opt->width, opt->height, &v->photo, st);
        if (!rc && alpha.data) rc = ws_image_resample(&alpha, opt->width, opt->height, &v->mask, st);
    } else if (!rc) {
        v->photo = full;
        v->mask = alpha;
        full = alpha = (ws_image){0};
    }
    ws_image_free(&full);
    ws_image_free(&alpha);
    if (!rc && v->mask.data) threshold_mask(&v->mask);
    return rc;
}

/* ---------------------------------------------------------------- masks folder */

static int is_folder(const char *path) {
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

/* The mask of image `name` in folder `dir`: DIR/NAME with its image
 * extension replaced by .png, or with .png added; tried[2] get both. */
static int find_mask(const char *dir, const char *name, char tried[2][WS_PATH_MAX], char *found, size_t size) {
    const size_t stem = strlen(name) - image_extension(name);
    snprintf(tried[0], WS_PATH_MAX, "%s/%.*s.png", dir, (int)stem, name);
    snprintf(tried[1], WS_PATH_MAX, "%s/%s.png", dir, name);
    for (int k = 0; k < 2; k++)
        if (file_exists(tried[k]) && strlen(tried[k]) < size) {
            strcpy(found, tried[k]);
            return 1;
        }
    return 0;
}

/* Every view without a mask_path takes its mask from the masks folder
 * (scene.h): opt->masks_dir, which must exist, or SCENE/masks of a
 * nerfstudio or COLMAP scene. A folder that has masks for some views must
 * have every one's: a view left without is refused, not fitted on its
 * background. */
static int find_masks(ws_scene *scene, const ws_scene_options *opt, ws_status *st) {
    char dir[WS_PATH_MAX], tried[2][WS_PATH_MAX], first_tried[2][WS_PATH_MAX];
    snprintf(dir, sizeof dir, "%s/masks", scene->dir);
    if (opt->masks_dir && !is_folder(opt->masks_dir))
        return ws_fail(st, WS_EUSAGE, "--masks %s: no such folder", opt->masks_dir);
    if (opt->masks_dir)
        snprintf(dir, sizeof dir, "%s", opt->masks_dir);
    else if (scene->layout == WS_LAYOUT_NERF_SYNTHETIC || !is_folder(dir))
        dir[0] = '\0';
    const ws_view *missing = NULL;
    int nmissing = 0;
    for (int s = 0; s < WS_NSPLITS; s++)
        for (int k = 0; k < scene->split[s].n; k++) {
            ws_view *v = &scene->split[s].views[k];
            if (v->mask_path[0]) {
                scene->masks_from_paths++;
            } else if (dir[0] && find_mask(dir, v->image_name, tried, v->mask_path, sizeof v->mask_path)) {
                scene->masks_from_dir++;
            } else if (dir[0] && nmissing++ == 0) {
                missing = v;
                memcpy(first_tried, tried, sizeof tried);
            }
        }
    if (!nmissing) {
        if (scene->masks_from_dir) snprintf(scene->masks_dir, sizeof scene->masks_dir, "%s", dir);
        return WS_OK;
    }
    if (!scene->masks_from_dir)
        return ws_fail(st, WS_EINPUT, "%s: no mask for any image (tried %s and %s for %s)", dir,
                       first_tried[0], first_tried[1], missing->image_name);
    return ws_fail(st, WS_EINPUT, "%s: no mask for %s (tried %s and %s), though the folder has the masks "
                   "of %d other views", dir, missing->image_name, first_tried[0], first_tried[1], scene->masks_from_dir);
}

void ws_scene_mask_line(const ws_scene *scene, char *line, size_t size) {
    int n = 0;
    for (int s = 0; s < WS_NSPLITS; s++) n += scene->split[s].n;
    line[0] = '\0';
    if (scene->masks_from_paths && scene->masks_from_dir)
        snprintf(line, size, "%.300s: masks for %d of %d views, %d from the frames' mask_path, %d from %.300s",
                 scene->dir, scene->masks_from_paths + scene->masks_from_dir, n, scene->masks_from_paths,
                 scene->masks_from_dir, scene->masks_dir);
    else if (scene->masks_from_paths || scene->masks_from_dir)
        snprintf(line, size, "%.300s: masks for %d of %d views from %.300s", scene->dir,
                 scene->masks_from_paths + scene->masks_from_dir, n,
                 scene->masks_from_dir ? scene->masks_dir : "the frames' mask_path");
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
    ws_progress_begin(opt->progress, "loading the photos", "views", total);
#pragma omp parallel for schedule(dynamic)
    for (int k = 0; k < total; k++) {
        ws_status_clear(&status[k]);
        load_view(views[k], opt, &status[k]);
        ws_progress_advance(opt->progress, 1);
    }
    ws_progress_end(opt->progress);
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
                        "%s/%s: frame %d: camera too far out (its distance to the scene centre "
                        "overflows)",
                        scene->dir, ws_scene_file(scene, s), scene->split[s].views[k].frame);
                ws_scene_free(scene);
                return st->code;
            }
        }
    return WS_OK;
}

/* The masks and photos of every view, loaded (frees the scene on failure). */
static int load_images(ws_scene *scene, const ws_scene_options *opt, ws_status *st) {
    if (find_masks(scene, opt, st) || load_photos(scene, opt, st)) {
        ws_scene_free(scene);
        return st->code;
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
    scene->progress = opt->progress;
    scene->width = opt->width;
    scene->height = opt->height;
    char path[WS_PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, ws_transforms_split_files[WS_TRAIN]);
    int nerfstudio = access(path, F_OK) != 0;
    snprintf(path, sizeof path, "%s/" WS_TRANSFORMS_FILE, dir);
    nerfstudio &= access(path, F_OK) == 0;
    char folder[WS_PATH_MAX]; /* a COLMAP model's, when there is no transforms file */
    snprintf(path, sizeof path, "%s/%s", dir, ws_transforms_split_files[WS_TRAIN]);
    const int colmap = !nerfstudio && access(path, F_OK) != 0 &&
                       ws_colmap_find(dir, folder, sizeof folder) == 0;
    if (nerfstudio || colmap) {
        scene->layout = nerfstudio ? WS_LAYOUT_NERFSTUDIO : WS_LAYOUT_COLMAP;
        if (nerfstudio ? parse_nerfstudio(scene, dir, opt, st) : parse_colmap(scene, dir, folder, opt, st)) {
            ws_scene_free(scene);
            return st->code;
        }
    }
    for (int s = 0; s < WS_NSPLITS && !nerfstudio && !colmap; s++) {
        double angle = 0;
        if (parse_split(scene, dir, s, opt, &scene->split[s], &angle, st)) {
            ws_scene_free(scene);
            return st->code;
        }
        if (s == WS_TRAIN) scene->camera_angle_x = angle;
    }
    axes_center(scene, scene->center); /* the crops do not move the cameras' axes */
    if ((nerfstudio || colmap) && crop_around_object(scene, NULL, opt, st)) {
        ws_scene_free(scene);
        return st->code;
    }
    if (check_distances(scene, st)) return st->code;
    return opt->load_images && !opt->defer_images ? load_images(scene, opt, st) : WS_OK;
}

int ws_scene_zoom(ws_scene *scene, const double box[6], const ws_scene_options *opt, ws_status *st) {
    if (box && scene->layout != WS_LAYOUT_NERF_SYNTHETIC && crop_around_object(scene, box, opt, st)) {
        ws_scene_free(scene);
        return st->code;
    }
    return opt->load_images ? load_images(scene, opt, st) : WS_OK;
}
