/* strays.h: the sketch as a viewer sees it. Every Gaussian is drawn in
 * every view, a floating dot (one Gaussian, no length) as much as a point
 * of a long stroke, so these measures count Gaussians rather than arc
 * length:
 * - precision: the fraction of Gaussian centres (ws_curves_sample at the
 *   sketch's own thickness and overlap) within WS_METRIC_FSCORE_THRESHOLD
 *   (1%) of the diagonal D from the ground truth;
 * - stray curves: curves more than half of whose Gaussians lie farther than
 *   WS_STRAY_DISTANCE (5%) of D from the ground truth.
 * The ground truth is a nearest-point tree over its points (a surface
 * cloud, or ground-truth curves sampled densely as in metrics.h). */
#ifndef WS_STRAYS_H
#define WS_STRAYS_H
#include "metrics/nearest.h"
#include "render/curves.h"

#define WS_STRAY_DISTANCE 0.05 /* of the diagonal */

typedef struct {
    int n_gaussians, n_curves;
    double precision;  /* of the Gaussian centres, at 1% of D */
    int stray_curves;
} ws_stray_metrics;

int ws_stray_metrics_compute(const ws_curves *c, const ws_nearest *gt, double diagonal,
                             ws_stray_metrics *m, ws_status *st);

#endif
