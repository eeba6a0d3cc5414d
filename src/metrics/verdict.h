/* verdict.h: what a fit's numbers mean: each metric's unit and scale, and
 * a one-word verdict, good, fair or poor, against thresholds stated here
 * and shown with it (report.html, metrics.json's "verdicts").
 *
 * The thresholds come from what the fits measured (docs/RESULTS.md):
 *   surface_mean  mean distance of the sketch to the ground-truth surface
 *                 over the bounding-box diagonal: good <= 0.015 (issue
 *                 10's target for the rose), fair <= 0.03;
 *   surface_p90   its 90th percentile: good <= 0.03 (the same target),
 *                 fair <= 0.06;
 *   surface_precision, gaussian_precision  the share of the sketch's
 *                 Gaussians within 1% of the diagonal of the truth:
 *                 good >= 0.8, fair >= 0.5;
 *   chamfer       curve Chamfer distance over the diagonal: good <= 0.01,
 *                 fair <= 0.03;
 *   fscore        curve F-score at 1% of the diagonal: good >= 0.8,
 *                 fair >= 0.5;
 *   lines_chamfer accuracy + completeness over the largest side: good
 *                 <= 0.01 (the cube demo 0.005), fair <= 0.03;
 *   lines_fscore_1, lines_fscore_2  F-score at 1% and 2% of the largest
 *                 side: good >= 0.9 and 0.95 (the demo 0.99 and 1.00),
 *                 fair >= 0.6 and 0.7;
 *   stray_share   curves whose Gaussians lie mostly beyond 5% of the
 *                 diagonal, over all curves: good 0, fair <= 0.1;
 *   test_loss_edges  the line loss of the test views (1 - the cosine of
 *                 blurred strokes and edges: 0 perfect, 1 an empty
 *                 sketch): good <= 0.15 (the ground truth scores 0.035 to
 *                 0.16 at stroke thicknesses 0.005 to 0.04; a sketch
 *                 shifted by 5% 0.22 to 0.29), fair <= 0.3 (the truth
 *                 shrunk to dots 0.35 to 0.46).
 *   drawing_precision_1, drawing_precision_05  the share of the drawing's
 *                 pixels within 1% (0.5%) of the image diagonal of a
 *                 reference line (metrics/drawing_score.h): good >= 0.85
 *                 (issue 23's targets), fair >= 0.6;
 *   drawing_contour_recall_1  the share of the outline and inner contours
 *                 drawn: good >= 0.9, fair >= 0.7;
 *   drawing_scribble_1  the share of the drawing inside the object and
 *                 away from its lines: good <= 0.1, fair <= 0.25.
 * Other losses compare runs of one scene and loss only: no verdict. */
#ifndef WS_VERDICT_H
#define WS_VERDICT_H
#include <stddef.h>

typedef struct {
    const char *key;   /* "surface_mean" */
    const char *unit;  /* "fraction of the bounding-box diagonal, 0 best" */
    int higher_better;
    double good, fair; /* good when at least as good as `good`, fair as `fair`, else poor */
} ws_metric_scale;

/* The scale of metric `key`, or NULL for one without a verdict. */
const ws_metric_scale *ws_metric_scale_of(const char *key);

/* "good", "fair", "poor", or "none" for a non-finite value. */
const char *ws_verdict(const ws_metric_scale *m, double value);

/* "fraction of the bounding-box diagonal, 0 best; good <= 0.015, fair <=
 * 0.03, poor above". */
void ws_metric_scale_text(const ws_metric_scale *m, char *text, size_t size);

#endif
