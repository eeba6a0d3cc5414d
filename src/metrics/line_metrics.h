/* line_metrics.h: the curve metrics of the 3D line / edge reconstruction
 * literature, so that results can be set beside published ones.
 *
 * S is the largest side of the ground truth's bounding box (the curves
 * evaluated at their WS_ARC_SAMPLES arc-table parameters, ws_curves_bbox).
 * Result R and ground truth G are sampled at uniform arc length every
 * h = WS_LINE_SPACING S (ws_curves_sample_dense); d(x, Y) is the distance
 * from x to the nearest sample of Y. Then, all divided by S:
 *   accuracy     = mean_{x in R} d(x, G)     (is what was drawn true?)
 *   completeness = mean_{y in G} d(y, R)     (was everything drawn?)
 *   chamfer      = accuracy + completeness
 * and at each threshold tau_k = WS_LINE_TAU[k] S (1% and 2%):
 *   precision_k = fraction of x in R with d(x, G) <= tau_k,
 *   recall_k    = fraction of y in G with d(y, R) <= tau_k,
 *   fscore_k    = 2 P R / (P + R), 0 when P = R = 0.
 * (metrics.h's chamfer is the mean of the two directions over the
 * diagonal; this one is their sum over the largest side, as published.) */
#ifndef WS_LINE_METRICS_H
#define WS_LINE_METRICS_H
#include <stdio.h>
#include "render/curves.h"
#include "nn/base/status.h"

#define WS_LINE_SPACING 0.005
#define WS_LINE_NTAU 2
extern const double WS_LINE_TAU[WS_LINE_NTAU]; /* 0.01, 0.02 */

typedef struct {
    double side;        /* S, world units */
    int n_result, n_gt; /* samples of each set */
    double accuracy, completeness, chamfer;
    double precision[WS_LINE_NTAU], recall[WS_LINE_NTAU], fscore[WS_LINE_NTAU];
} ws_line_metrics;

/* Needs at least one curve in each set, finite control points and S > 0. */
int ws_line_metrics_compute(const ws_curves *result, const ws_curves *gt, ws_line_metrics *m,
                            ws_status *st);

/* Writes `"lines": {"side": ..., "accuracy": ..., ..., "fscore_2": ...}`
 * (suffix k: the threshold in percent of S) for metrics.json and eval. */
void ws_line_metrics_json(FILE *fp, const ws_line_metrics *m);

#endif
