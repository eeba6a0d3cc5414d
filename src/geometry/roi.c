/* roi.c: the region of interest of a capture (see roi.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "base/sort.h"
#include "geometry/roi.h"
#include "io/pointcloud.h"

void ws_roi_centre(const ws_roi *roi, double centre[3]) {
    for (int a = 0; a < 3; a++) centre[a] = 0.5 * (roi->lo[a] + roi->hi[a]);
}

int ws_roi_parse_bbox(const char *text, double box[6], ws_status *st) {
    const char *s = text;
    for (int k = 0; k < 6; k++) {
        char *end;
        box[k] = strtod(s, &end);
        if (end == s || !isfinite(box[k]) || *end != (k < 5 ? ',' : '\0'))
            return ws_fail(st, WS_EUSAGE, "--bbox %s: not six numbers x0,y0,z0,x1,y1,z1", text);
        s = end + 1;
    }
    for (int a = 0; a < 3; a++)
        if (!(box[a] < box[3 + a]))
            return ws_fail(st, WS_EUSAGE, "--bbox %s: the box is empty along %c (%g >= %g)", text, "xyz"[a], box[a],
                           box[3 + a]);
    return WS_OK;
}

/* Whether world point p projects in front of cam and into its frame. */
static int sees(const ws_camera *cam, const double p[3]) {
    double c[3], u, v;
    ws_camera_to_cam(cam, p, c);
    if (!(ws_camera_project(cam, c, &u, &v) > 0)) return 0;
    return u >= 0 && u < cam->width && v >= 0 && v < cam->height;
}

static void box_line(ws_roi *roi, const char *from) {
    snprintf(roi->line, sizeof roi->line, "region of interest [%.3g, %.3g] x [%.3g, %.3g] x [%.3g, %.3g] from %s",
             roi->lo[0], roi->hi[0], roi->lo[1], roi->hi[1], roi->lo[2], roi->hi[2], from);
}

int ws_roi_from_points(const ws_scene *scene, const double *points, int n, ws_roi *roi, int *found,
                       ws_status *st) {
    *found = 0;
    const ws_split *train = &scene->split[WS_TRAIN];
    const int stride = n > WS_ROI_MAX_SAMPLE ? (n + WS_ROI_MAX_SAMPLE - 1) / WS_ROI_MAX_SAMPLE : 1;
    int m = 0;
    double *p = ws_malloc(sizeof *p * 3 * (size_t)(n / stride + 1), "region of interest", st);
    if (!p) return st->code;
    /* the points in the train views' common view */
    for (int k = 0; k < n; k += stride) {
        int seen = 0;
        for (int v = 0; v < train->n; v++) seen += sees(&train->views[v].cam, points + 3 * (size_t)k);
        if (2 * seen >= train->n) memcpy(p + 3 * m++, points + 3 * (size_t)k, sizeof *p * 3);
    }
    double *kth = m > WS_ROI_NEIGHBOURS ? ws_malloc(sizeof *kth * 2 * m, "region of interest", st) : NULL;
    double *near = kth ? ws_malloc(sizeof *near * (size_t)m, "region of interest", st) : NULL;
    if (m > WS_ROI_NEIGHBOURS && !near) {
        free(p);
        free(kth);
        return st->code;
    }
    int kept = 0;
    if (near) {
        /* kth[i]: the squared distance to point i's K-th nearest neighbour */
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < m; j++) {
                double d = 0;
                for (int a = 0; a < 3; a++) d += (p[3 * i + a] - p[3 * j + a]) * (p[3 * i + a] - p[3 * j + a]);
                near[j] = d;
            }
            ws_sort_doubles(near, (size_t)m);
            kth[i] = kth[m + i] = near[WS_ROI_NEIGHBOURS]; /* near[0] is the point itself */
        }
        ws_sort_doubles(kth + m, (size_t)m);
        const double limit = WS_ROI_DENSITY * WS_ROI_DENSITY * kth[m + m / 2];
        for (int i = 0; i < m; i++) /* the crowded points to the front of p */
            if (kth[i] <= limit) memmove(p + 3 * kept++, p + 3 * i, sizeof *p * 3);
        double lo[3], hi[3];
        ws_points_bbox(p, kept, lo, hi);
        if (kept >= WS_ROI_MIN_POINTS) {
            double side = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
            for (int a = 0; a < 3; a++) {
                roi->lo[a] = lo[a] - WS_ROI_MARGIN * side;
                roi->hi[a] = hi[a] + WS_ROI_MARGIN * side;
            }
            roi->source = WS_ROI_POINTS;
            char from[200];
            snprintf(from, sizeof from, "the sparse points (%d of the %d%s the train views share; %d of them crowded, "
                     "the rest outliers)", m, (n + stride - 1) / stride, stride > 1 ? " looked at" : "", kept);
            box_line(roi, from);
            *found = 1;
        }
    }
    free(p);
    free(kth);
    free(near);
    return WS_OK;
}

int ws_roi_from_cameras(const ws_scene *scene, ws_roi *roi, ws_status *st) {
    const ws_split *train = &scene->split[WS_TRAIN];
    double radius = HUGE_VAL;
    if (train->n == 0)
        return ws_fail(st, WS_EINPUT, "%s: no train views, so the cameras give no region of interest", scene->dir);
    for (int v = 0; v < train->n; v++) {
        const ws_camera *cam = &train->views[v].cam;
        double c[3], u, w;
        ws_camera_to_cam(cam, scene->center, c);
        double d = ws_camera_project(cam, c, &u, &w);
        double margin = fmin(fmin(u, cam->width - u), fmin(w, cam->height - w));
        if (!(d > 0) || !(margin > 0))
            return ws_fail(st, WS_EINPUT,
                           "%s/%s: train view %d does not see the point the cameras look at, so the cameras give "
                           "no region of interest (give one with --bbox)",
                           scene->dir, ws_scene_file(scene, WS_TRAIN), v);
        /* the smallest angle between the ray to the centre and a ray to
         * the frame's border (straight across to each side) */
        const double to[4][2] = {{0, w}, {cam->width, w}, {u, 0}, {u, cam->height}};
        double angle = HUGE_VAL, a[3], b[3];
        ws_camera_ray(cam, u, w, a);
        for (int k = 0; k < 4; k++) {
            ws_camera_ray(cam, to[k][0], to[k][1], b);
            double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            double nb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
            angle = fmin(angle, acos(fmin(1, dot / (na * nb))));
        }
        double dist = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        radius = fmin(radius, dist * sin(angle));
    }
    for (int a = 0; a < 3; a++) roi->lo[a] = scene->center[a] - radius, roi->hi[a] = scene->center[a] + radius;
    roi->source = WS_ROI_CAMERAS;
    char from[WS_ROI_LINE - 100];
    int used = snprintf(from, sizeof from, "where the cameras look (the ball of radius %.3g around (%.3g, %.3g, "
                        "%.3g) that every train view sees whole)", radius, scene->center[0], scene->center[1],
                        scene->center[2]);
    if (scene->points_missing[0] && used > 0 && (size_t)used < sizeof from)
        snprintf(from + used, sizeof from - used, "; the sparse points %.200s (ply_file_path) are not there",
                 scene->points_missing);
    box_line(roi, from);
    return WS_OK;
}

int ws_roi_find(const ws_scene *scene, const double *user, ws_roi *roi, ws_status *st) {
    memset(roi, 0, sizeof *roi);
    if (user) {
        memcpy(roi->lo, user, sizeof roi->lo);
        memcpy(roi->hi, user + 3, sizeof roi->hi);
        roi->source = WS_ROI_USER;
        box_line(roi, "--bbox");
        return WS_OK;
    }
    if (scene->has_aabb) {
        memcpy(roi->lo, scene->aabb[0], sizeof roi->lo);
        memcpy(roi->hi, scene->aabb[1], sizeof roi->hi);
        roi->source = WS_ROI_AABB;
        char from[80]; /* the file is transforms.json or transforms_train.json */
        snprintf(from, sizeof from, "the aabb of %.60s", ws_scene_file(scene, WS_TRAIN));
        box_line(roi, from);
        return WS_OK;
    }
    int n, found = 0;
    const double *points = ws_scene_points(scene, &n);
    if (n > 0 && ws_roi_from_points(scene, points, n, roi, &found, st)) return st->code;
    return found ? WS_OK : ws_roi_from_cameras(scene, roi, st);
}

int ws_roi_load_scene(ws_scene *scene, const char *dir, const ws_scene_options *opt, const double *user,
                      ws_roi *roi, ws_status *roi_st, ws_status *st) {
    ws_scene_options first = *opt;
    first.defer_images = 1;
    if (ws_scene_load(scene, dir, &first, st)) return st->code;
    ws_roi found;
    ws_status why;
    ws_status_clear(&why);
    const int have = ws_roi_find(scene, user, &found, &why) == WS_OK;
    if (roi) *roi = found;
    if (roi_st) *roi_st = why;
    if (!have && why.code != WS_EINPUT) { /* out of memory, not a scene without a region */
        ws_scene_free(scene);
        *st = why;
        return st->code;
    }
    const double box[6] = {found.lo[0], found.lo[1], found.lo[2], found.hi[0], found.hi[1], found.hi[2]};
    /* where the cameras look is a guess, not the object's place: no zoom */
    return ws_scene_zoom(scene, have && found.source != WS_ROI_CAMERAS ? box : NULL, opt, st);
}
