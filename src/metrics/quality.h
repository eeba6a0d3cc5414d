/* quality.h: how close a sketch is to the ground truth (surface points or
 * curves, METHOD.md section 8). Shared by `fit` and `eval`; its loss on a split
 * is the objective's (objective.h). */
#ifndef WS_QUALITY_H
#define WS_QUALITY_H
#include "base/paths.h"
#include "metrics/metrics.h"
#include "metrics/strays.h"
#include "metrics/line_metrics.h"
#include "render/curves.h"

typedef struct {
    int have_surface;            /* a ground-truth point cloud was given */
    ws_surface_metrics surface;
    ws_stray_metrics surface_strays; /* against the point cloud */
    int have_curves;             /* ground-truth curves were given */
    ws_curve_metrics curves;
    ws_stray_metrics curve_strays;   /* against the curves */
    ws_line_metrics lines;           /* with the curves: over the largest side */
} ws_quality;

/* Distances of the sketch c to gt_points (a PLY point cloud) and gt_curves
 * (a curve file); either may be NULL. What is wrong with a ground-truth
 * file (no curves, no extent) is reported naming it; a sketch without
 * curves is refused first (the caller knows its file). */
int ws_quality_measure(const ws_curves *c, const char *gt_points, const char *gt_curves,
                       ws_quality *q, ws_status *st);

/* SCENE/gt_points.ply and SCENE/gt_curves.json where they exist (else "").
 * Buffers of WS_PATH_MAX bytes. */
void ws_scene_ground_truth(const char *scene_dir, char *gt_points, char *gt_curves);

#endif
