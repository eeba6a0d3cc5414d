/* evaluate.h: how good a sketch is: its loss on a split (item 0, no
 * augmentation, METHOD.md section 8 "test loss") and its distance to the ground
 * truth (surface points or curves). Shared by `fit` and `eval`. */
#ifndef WS_EVALUATE_H
#define WS_EVALUATE_H
#include "render/curves.h"
#include "objective/loss.h"
#include "metrics/metrics.h"
#include "io/scene.h"
#include "render/splat.h"

/* The mean loss over the views of `split` for the Gaussians g of radius r
 * (NaN for an empty split). alpha: a H x W buffer; per_view (n, or NULL)
 * receives each view's loss. */
int ws_split_loss(ws_loss *loss, ws_splat *splat, const ws_splat_options *so, const ws_scene *scene,
                  int split, const ws_gaussians *g, double radius, double *alpha, double *per_view,
                  double *mean, ws_status *st);

typedef struct {
    int have_surface;            /* a ground-truth point cloud was given */
    ws_surface_metrics surface;
    int have_curves;             /* ground-truth curves were given */
    ws_curve_metrics curves;
} ws_quality;

/* Distances of the sketch c to gt_points (a PLY point cloud) and gt_curves
 * (a curve file); either may be NULL. */
int ws_quality_measure(const ws_curves *c, const char *gt_points, const char *gt_curves,
                       ws_quality *q, ws_status *st);

/* SCENE/gt_points.ply and SCENE/gt_curves.json where they exist (else "").
 * Buffers of 4200 bytes. */
void ws_scene_ground_truth(const char *scene_dir, char *gt_points, char *gt_curves);

#endif
