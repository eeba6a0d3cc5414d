/* hidden_lines.c: hidden-line removal by the visual hull (see hidden_lines.h). */
#include <math.h>
#include <stdlib.h>
#include "objective/hidden_lines.h"
#include "objective/view_cache.h"

const char *const ws_hidden_mode_names[2] = {"none", "hull"};

struct ws_hidden_lines {
    const ws_scene *scene;
    ws_scene_hull own;         /* carved here when none was lent */
    const ws_scene_hull *hull;
    ws_view_cache far;         /* per view: the far limit, H x W */
    float *z;                  /* H x W scratch: the depth, then the window's row pass */
    int *nearest;              /* H x W scratch: the surface voxel nearest at each pixel */
};

int ws_hidden_lines_create(ws_hidden_lines **out, const ws_scene *scene, const ws_scene_hull *hull,
                           ws_view_targets *targets, ws_status *st) {
    ws_hidden_lines *hl = *out = ws_calloc(1, sizeof *hl, "hidden lines", st);
    if (!hl) return st->code;
    hl->scene = scene;
    size_t hw = (size_t)scene->width * scene->height;
    const ws_silhouette *sil;
    if (!hull && (ws_view_targets_silhouettes(targets, WS_TRAIN, &sil, st) ||
                  ws_scene_hull_make(scene, WS_TRAIN, sil, WS_HULL_INIT_RESOLUTION, &hl->own, st)))
        return st->code;
    hl->hull = hull ? hull : &hl->own;
    if (ws_view_cache_init(&hl->far, scene, hw, "hidden-line far limits", st) ||
        !(hl->z = ws_malloc(hw * sizeof(float), "a hidden-line scratch map", st)) ||
        !(hl->nearest = ws_malloc(hw * sizeof(int), "a hidden-line scratch map", st)))
        return st->code;
    return WS_OK;
}

void ws_hidden_lines_free(ws_hidden_lines *hl) {
    if (!hl) return;
    ws_scene_hull_free(&hl->own);
    ws_view_cache_free(&hl->far);
    free(hl->z);
    free(hl->nearest);
    free(hl);
}

/* The tolerance, in voxels, of a surface voxel with outward normal n whose
 * centre lies at camera-space c: WS_HIDDEN_TOLERANCE_HEAD_ON / |cos| of the
 * angle between n and the ray, at most WS_HIDDEN_TOLERANCE (reached from 55
 * degrees off head-on, and where the normal is zero). */
static double tolerance_voxels(const ws_camera *cam, const double n[3], const double c[3]) {
    double dot = 0, cc = 0;
    for (int i = 0; i < 3; i++) {
        dot += (cam->R[i][0] * n[0] + cam->R[i][1] * n[1] + cam->R[i][2] * n[2]) * c[i];
        cc += c[i] * c[i];
    }
    double cosine = fabs(dot) / sqrt(cc);
    return WS_HIDDEN_TOLERANCE_HEAD_ON < cosine * WS_HIDDEN_TOLERANCE ? WS_HIDDEN_TOLERANCE_HEAD_ON / cosine
                                                                        : WS_HIDDEN_TOLERANCE;
}

/* Z of a view into z (H x W): the surface voxels z-buffered as discs
 * (surface.h; nearest: their indices); and into far, Z plus the tolerance
 * of the voxel nearest there (+inf where none falls). */
static void depth_map(const ws_scene_hull *h, const ws_camera *cam, float *z, int *nearest, float *far) {
    ws_hull_surface_depth(&h->surface, cam, h->hull.voxel * sqrt(3.0) / 2, z, nearest, NULL);
    for (size_t p = 0; p < (size_t)cam->width * cam->height; p++) {
        int k = nearest[p];
        far[p] = INFINITY;
        if (k < 0) continue;
        double c[3];
        ws_camera_to_cam(cam, h->surface.p + 3 * k, c);
        far[p] = (float)(z[p] + tolerance_voxels(cam, h->surface.normal + 3 * k, c) * h->hull.voxel);
    }
}

/* out = the largest of in over the (2 WINDOW + 1) pixels along each row,
 * then (in place, through tmp) along each column. */
static void window_max(const float *in, float *tmp, float *out, int W, int H) {
    const int w = WS_HIDDEN_WINDOW;
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            float m = -INFINITY;
            for (int k = j - w; k <= j + w; k++)
                if (k >= 0 && k < W) m = fmaxf(m, in[(size_t)i * W + k]);
            tmp[(size_t)i * W + j] = m;
        }
    for (int i = 0; i < H; i++)
        for (int j = 0; j < W; j++) {
            float m = -INFINITY;
            for (int k = i - w; k <= i + w; k++)
                if (k >= 0 && k < H) m = fmaxf(m, tmp[(size_t)k * W + j]);
            out[(size_t)i * W + j] = m;
        }
}

/* ws_view_fill of the far limits: Z plus each pixel's tolerance, then its
 * window's largest (the tolerance is added in depth_map only; the window's
 * largest commutes with float rounding, so a constant tolerance gives the
 * bits of Zmax + tolerance). */
static int fill_far(void *ctx, int split, int view, float *slot, ws_status *st) {
    (void)st;
    ws_hidden_lines *hl = ctx;
    const ws_camera *cam = &hl->scene->split[split].views[view].cam;
    depth_map(hl->hull, cam, hl->z, hl->nearest, slot);
    window_max(slot, hl->z, slot, cam->width, cam->height);
    return WS_OK;
}

int ws_hidden_lines_far(ws_hidden_lines *hl, int split, int view, const float **far, ws_status *st) {
    return ws_view_cache_get(&hl->far, split, view, fill_far, hl, far, st);
}
