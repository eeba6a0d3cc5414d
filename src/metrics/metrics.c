/* metrics.c: surface distance, curve Chamfer and F-score (see metrics.h).
 *
 * Evaluation runs a few times per fit, so scratch buffers are allocated per
 * call; sums run serially in index order so the result never depends on the
 * thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "metrics/metrics.h"
#include "base/sort.h"

int ws_surface_gt_init(ws_surface_gt *gt, const ws_pointcloud *pc, ws_status *st) {
    gt->diagonal = ws_points_diagonal(pc->xyz, pc->n);
    if (ws_nearest_build(&gt->tree, pc->xyz, pc->n, st)) return st->code;
    if (!(gt->diagonal > 0)) {
        ws_nearest_free(&gt->tree);
        return ws_fail(st, WS_EINPUT, "ground-truth points: the bounding box has a zero diagonal");
    }
    return WS_OK;
}

void ws_surface_gt_free(ws_surface_gt *gt) { ws_nearest_free(&gt->tree); }

/* Fails unless n >= 1 and all n points are finite; `what` names the set. */
static int check_points(const double *xyz, int n, const char *what, ws_status *st) {
    if (n < 1) return ws_fail(st, WS_EINPUT, "%s: no points to measure", what);
    for (int i = 0; i < n * 3; i++)
        if (!isfinite(xyz[i])) return ws_fail(st, WS_ENUMERIC, "%s: point %d is not finite", what, i / 3);
    return WS_OK;
}

static double mean_of(const double *v, int n) {
    double sum = 0;
    for (int i = 0; i < n; i++) sum += v[i];
    return sum / n;
}

/* *d (g->n, allocated): each centre's distance to the nearest ground-truth point. */
static int surface_distances(const ws_surface_gt *gt, const ws_gaussians *g, double **d, ws_status *st) {
    if (check_points(g->mu, g->n, "surface distance: Gaussian centres", st)) return st->code;
    if (!(*d = ws_malloc((size_t)g->n * sizeof(double), "surface distances", st))) return st->code;
    ws_nearest_query(&gt->tree, g->mu, g->n, *d, NULL);
    return WS_OK;
}

/* The nearest-rank 90th percentile of the n distances d, sorted in place. */
static double p90_of(double *d, int n) {
    ws_sort_doubles(d, (size_t)n);
    long long rank = (9LL * n + 9) / 10; /* ceil(0.9 n), 1-based */
    return d[rank - 1];
}

int ws_surface_distance(const ws_surface_gt *gt, const ws_gaussians *g, ws_surface_metrics *m,
                        ws_status *st) {
    double *d;
    if (surface_distances(gt, g, &d, st)) return st->code;
    m->n = g->n;
    m->mean = mean_of(d, g->n) / gt->diagonal;
    m->p90 = p90_of(d, g->n) / gt->diagonal;
    free(d);
    return WS_OK;
}

int ws_surface_distance_by_curve(const ws_surface_gt *gt, const ws_gaussians *g, int n_curves,
                                 ws_surface_curve *out, ws_status *st) {
    for (int k = 0; k < g->n; k++)
        if (g->curve[k] < 0 || g->curve[k] >= n_curves)
            return ws_fail(st, WS_EINTERNAL, "surface distance: Gaussian %d belongs to curve %d of %d", k,
                           g->curve[k], n_curves);
    double *d, *sorted = NULL;
    if (surface_distances(gt, g, &d, st)) return st->code;
    if (!(sorted = ws_malloc((size_t)g->n * sizeof(double), "surface distances", st))) {
        free(d);
        return st->code;
    }
    memcpy(sorted, d, (size_t)g->n * sizeof(double));
    double p90 = p90_of(sorted, g->n);
    memset(out, 0, (size_t)n_curves * sizeof *out);
    for (int k = 0; k < g->n; k++) {
        ws_surface_curve *c = &out[g->curve[k]];
        c->n++;
        c->adds += d[k];
        c->beyond_p90 += d[k] > p90;
    }
    for (int ci = 0; ci < n_curves; ci++) {
        out[ci].mean = out[ci].n ? out[ci].adds / (out[ci].n * gt->diagonal) : 0;
        out[ci].adds /= g->n * gt->diagonal;
    }
    free(sorted);
    free(d);
    return WS_OK;
}

int ws_directed_distance(const double *from, int nfrom, const double *to, int nto, int ntau,
                         const double *tau, double *mean, double *within, ws_status *st) {
    ws_nearest tree;
    if (ws_nearest_build(&tree, to, nto, st)) return st->code;
    double *d = ws_malloc((size_t)nfrom * sizeof(double), "curve distances", st);
    if (!d) {
        ws_nearest_free(&tree);
        return st->code;
    }
    ws_nearest_query(&tree, from, nfrom, d, NULL);
    for (int k = 0; k < ntau; k++) {
        int close = 0;
        for (int i = 0; i < nfrom; i++) close += d[i] <= tau[k];
        within[k] = (double)close / nfrom;
    }
    *mean = mean_of(d, nfrom);
    free(d);
    ws_nearest_free(&tree);
    return WS_OK;
}

/* ws_curves_sample spaces its Gaussians 2 * thickness * (1 - overlap) apart. */
int ws_curves_sample_dense(const ws_curves *c, double h, ws_gaussians *g, ws_status *st) {
    ws_curves dense = *c;
    dense.thickness = h / 2;
    dense.overlap = 0;
    return ws_curves_sample(&dense, g, st);
}

void ws_curves_bbox(const ws_curves *c, double lo[3], double hi[3]) {
    for (int a = 0; a < 3; a++) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (int ci = 0; ci < c->n; ci++)
        for (int k = 0; k < WS_ARC_SAMPLES; k++) {
            double p[3];
            ws_curve_point(c, ci, (double)k / (WS_ARC_SAMPLES - 1), p);
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], p[a]);
                hi[a] = fmax(hi[a], p[a]);
            }
        }
}

/* D: the diagonal of that box. */
static double curves_diagonal(const ws_curves *c) {
    double lo[3], hi[3];
    ws_curves_bbox(c, lo, hi);
    return hypot(hypot(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
}

int ws_curve_metrics_compute(const ws_curves *result, const ws_curves *gt, ws_curve_metrics *m,
                             ws_status *st) {
    if (result->n < 1) return ws_fail(st, WS_EINPUT, "curve metrics: the result has no curves");
    if (gt->n < 1) return ws_fail(st, WS_EINPUT, "curve metrics: the ground truth has no curves");
    /* Finite control points give finite samples. */
    if (check_points(result->P, result->n * 4, "curve metrics: result control points", st) ||
        check_points(gt->P, gt->n * 4, "curve metrics: ground-truth control points", st))
        return st->code;
    /* A curve whose control points coincide still spreads its samples by
     * rounding: a diagonal at rounding level of the coordinates is zero. */
    double D = curves_diagonal(gt), scale = 0;
    for (int i = 0; i < gt->n * WS_CURVE_FLOATS; i++) scale = fmax(scale, fabs(gt->P[i]));
    if (!(D > 1e-12 * scale))
        return ws_fail(st, WS_EINPUT, "curve metrics: the ground-truth curves have a zero-diagonal bounding box");
    m->diagonal = D;
    m->spacing = D / WS_METRIC_SAMPLES_PER_DIAGONAL;
    m->threshold = WS_METRIC_FSCORE_THRESHOLD * D;
    ws_gaussians rs = {0}, gs = {0};
    double mean_r, mean_g;
    int rc = ws_curves_sample_dense(result, m->spacing, &rs, st) ||
             ws_curves_sample_dense(gt, m->spacing, &gs, st) ||
             ws_directed_distance(rs.mu, rs.n, gs.mu, gs.n, 1, &m->threshold, &mean_r, &m->precision, st) ||
             ws_directed_distance(gs.mu, gs.n, rs.mu, rs.n, 1, &m->threshold, &mean_g, &m->recall, st);
    if (!rc) {
        m->n_result = rs.n;
        m->n_gt = gs.n;
        m->chamfer = (mean_r + mean_g) / (2 * D);
        double pr = m->precision + m->recall;
        m->fscore = pr > 0 ? 2 * m->precision * m->recall / pr : 0;
    }
    ws_gaussians_free(&rs);
    ws_gaussians_free(&gs);
    return rc ? st->code : WS_OK;
}
