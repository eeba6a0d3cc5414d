/* metrics.h: the geometric evaluation metrics of METHOD.md section 8.
 *
 * Surface distance: for every Gaussian centre mu_k (ws_curves_sample), the
 * distance d_k to the nearest ground-truth point; reported are
 *   mean = (sum_k d_k / M) / D   and   p90 = d_(r) / D,
 * where d_(1) <= ... <= d_(M) are the sorted distances, r = ceil(0.9 M) (the
 * nearest-rank percentile: the smallest d that at least 90% of the centres
 * do not exceed) and D the diagonal of the ground truth's bounding box.
 *
 * Curve Chamfer and F-score between a result and a ground-truth curve set:
 * - D is the diagonal of the bounding box of the ground-truth curves each
 *   evaluated at the WS_ARC_SAMPLES (300) uniform parameter values of its
 *   arc-length table.
 * - Both sets are sampled densely at uniform arc length with spacing
 *   h = D / WS_METRIC_SAMPLES_PER_DIAGONAL, by ws_curves_sample itself
 *   (thickness h / 2, overlap 0): a curve of arc length L gets
 *   max(1, ceil(L / h)) points including both ends (one point, the
 *   midpoint, when L <= h; a curve is capped at
 *   WS_MAX_GAUSSIANS_PER_CURVE points, i.e. sampled more coarsely, with a
 *   warning, when L exceeds about 4 D).
 * - With d(x, S) the distance from sample x to the nearest sample of set S,
 *   R and G the result and ground-truth samples:
 *     chamfer   = (mean_{x in R} d(x, G) + mean_{y in G} d(y, R)) / (2 D)
 *     precision = fraction of x in R with d(x, G) <= tau, tau = 0.01 D
 *     recall    = fraction of y in G with d(y, R) <= tau
 *     fscore    = 2 P R / (P + R), 0 when P = R = 0.
 * Everything is deterministic and independent of the thread count. */
#ifndef WS_METRICS_H
#define WS_METRICS_H
#include "render/curves.h"
#include "metrics/nearest.h"
#include "io/pointcloud.h"
#include "nn/base/status.h"

#define WS_METRIC_SAMPLES_PER_DIAGONAL 1000
#define WS_METRIC_FSCORE_THRESHOLD 0.01 /* of the diagonal */

/* The ground-truth surface, prepared once for many evaluations. */
typedef struct {
    ws_nearest tree; /* over the ground-truth points */
    double diagonal; /* D: of their bounding box */
} ws_surface_gt;

/* Fails with WS_EINPUT when the bounding box has a zero diagonal. */
int ws_surface_gt_init(ws_surface_gt *gt, const ws_pointcloud *pc, ws_status *st);
void ws_surface_gt_free(ws_surface_gt *gt);

typedef struct {
    int n;       /* Gaussian centres measured */
    double mean; /* mean distance to the ground truth / D */
    double p90;  /* nearest-rank 90th percentile of the distance / D */
} ws_surface_metrics;

/* Needs g->n >= 1 finite centres. */
int ws_surface_distance(const ws_surface_gt *gt, const ws_gaussians *g, ws_surface_metrics *m,
                        ws_status *st);

/* Where the surface distance comes from, curve by curve (eval --per-curve). */
typedef struct {
    int n;          /* Gaussians of the curve */
    double mean;    /* their mean distance / D (0 for a curve without any) */
    double adds;    /* their distances' sum / (all Gaussians x D): what the
                       curve adds to ws_surface_metrics.mean (they sum to it) */
    int beyond_p90; /* how many lie farther than ws_surface_metrics.p90 */
} ws_surface_curve;

/* out (n_curves): per curve of g (g->curve in [0, n_curves)); the same
 * distances as ws_surface_distance, and its failures. */
int ws_surface_distance_by_curve(const ws_surface_gt *gt, const ws_gaussians *g, int n_curves,
                                 ws_surface_curve *out, ws_status *st);

typedef struct {
    double diagonal;    /* D (world units) */
    double spacing;     /* h = D / 1000: the dense sampling step */
    double threshold;   /* tau = 0.01 D: the F-score threshold */
    int n_result, n_gt; /* dense samples of each set */
    double chamfer;     /* symmetric mean nearest-sample distance / D */
    double precision, recall, fscore;
} ws_curve_metrics;

/* The bounding box of curves c evaluated at the WS_ARC_SAMPLES uniform
 * parameter values of their arc-length tables. */
void ws_curves_bbox(const ws_curves *c, double lo[3], double hi[3]);

/* Samples c at uniform arc-length spacing h, by ws_curves_sample itself
 * (thickness h / 2, overlap 0): max(1, ceil(L / h)) points per curve. */
int ws_curves_sample_dense(const ws_curves *c, double h, ws_gaussians *g, ws_status *st);

/* Distances from each of the nfrom points to the nearest of the nto points,
 * summarised as their mean and, for each of the ntau thresholds tau[k], the
 * fraction within it (within[k]). */
int ws_directed_distance(const double *from, int nfrom, const double *to, int nto, int ntau,
                         const double *tau, double *mean, double *within, ws_status *st);

/* Needs at least one curve in each set. */
int ws_curve_metrics_compute(const ws_curves *result, const ws_curves *gt, ws_curve_metrics *m,
                             ws_status *st);

#endif
