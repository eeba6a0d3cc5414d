/* quality.c: distance of a sketch to the ground truth (see quality.h). */
#include <math.h>
#include <stdio.h>
#include <unistd.h>
#include "base/paths.h"
#include "metrics/quality.h"
#include "io/pointcloud.h"

/* A failure of measuring against the ground truth at path (rc), prefixed
 * with that path: what is wrong with a file the user gave names it (the
 * loaders' own messages name it already, so only failures after them). */
static int against(const char *path, int rc, ws_status *st) {
    if (!rc) return WS_OK;
    char why[sizeof st->msg];
    snprintf(why, sizeof why, "%s", st->msg);
    return ws_fail(st, rc, "%s: %s", path, why);
}

static int surface(const ws_curves *c, const char *path, ws_surface_metrics *m,
                   ws_stray_metrics *strays, ws_status *st) {
    ws_pointcloud pc = {0};
    ws_surface_gt gt = {0};
    ws_gaussians g = {0};
    int rc = ws_pointcloud_load_ply(path, &pc, st);
    if (!rc) {
        rc = ws_surface_gt_init(&gt, &pc, st);
        if (!rc) rc = ws_curves_sample(c, &g, st);
        if (!rc) rc = ws_surface_distance(&gt, &g, m, st);
        if (!rc) rc = ws_stray_metrics_compute(c, &gt.tree, gt.diagonal, strays, st);
        rc = against(path, rc, st);
    }
    ws_gaussians_free(&g);
    ws_surface_gt_free(&gt);
    ws_pointcloud_free(&pc);
    return rc;
}

static int curve_distance(const ws_curves *c, const char *path, ws_curve_metrics *m,
                          ws_stray_metrics *strays, ws_line_metrics *lines, ws_status *st) {
    ws_curves gt = {0};
    ws_gaussians dense = {0};
    ws_nearest tree = {0};
    int rc = ws_curves_load(path, &gt, st);
    if (!rc) {
        rc = ws_curve_metrics_compute(c, &gt, m, st);
        if (!rc) rc = ws_curves_sample_dense(&gt, m->spacing, &dense, st);
        if (!rc) rc = ws_nearest_build(&tree, dense.mu, dense.n, st);
        if (!rc) rc = ws_stray_metrics_compute(c, &tree, m->diagonal, strays, st);
        if (!rc) rc = ws_line_metrics_compute(c, &gt, lines, st);
        rc = against(path, rc, st);
    }
    ws_nearest_free(&tree);
    ws_gaussians_free(&dense);
    ws_curves_free(&gt);
    return rc;
}

int ws_quality_measure(const ws_curves *c, const char *gt_points, const char *gt_curves,
                       ws_quality *q, ws_status *st) {
    q->have_surface = gt_points && *gt_points;
    q->have_curves = gt_curves && *gt_curves;
    /* before the measures, whose failures name the ground-truth file */
    if ((q->have_surface || q->have_curves) && c->n < 1)
        return ws_fail(st, WS_EINPUT, "the sketch has no curves to measure against the ground truth");
    if (q->have_surface && surface(c, gt_points, &q->surface, &q->surface_strays, st)) return st->code;
    if (q->have_curves && curve_distance(c, gt_curves, &q->curves, &q->curve_strays, &q->lines, st)) return st->code;
    return WS_OK;
}

void ws_scene_ground_truth(const char *scene_dir, char *gt_points, char *gt_curves) {
    snprintf(gt_points, WS_PATH_MAX, "%s/gt_points.ply", scene_dir);
    if (access(gt_points, R_OK) != 0) gt_points[0] = '\0';
    snprintf(gt_curves, WS_PATH_MAX, "%s/gt_curves.json", scene_dir);
    if (access(gt_curves, R_OK) != 0) gt_curves[0] = '\0';
}
