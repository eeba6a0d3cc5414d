/* line_metrics.c: accuracy, completeness, Chamfer and F-scores over the
 * largest side (see line_metrics.h). Sums run serially in index order, so
 * the result does not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include "base/json_number.h"
#include "metrics/line_metrics.h"
#include "metrics/metrics.h"

const double WS_LINE_TAU[WS_LINE_NTAU] = {0.01, 0.02};

int ws_line_metrics_compute(const ws_curves *result, const ws_curves *gt, ws_line_metrics *m,
                            ws_status *st) {
    if (result->n < 1) return ws_fail(st, WS_EINPUT, "line metrics: the result has no curves");
    if (gt->n < 1) return ws_fail(st, WS_EINPUT, "line metrics: the ground truth has no curves");
    double lo[3], hi[3];
    ws_curves_bbox(gt, lo, hi);
    /* a point spreads its samples by rounding: an extent at rounding level
     * of the coordinates is none */
    double S = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2])), scale = 0;
    for (int i = 0; i < gt->n * 12; i++) scale = fmax(scale, fabs(gt->P[i]));
    if (!(S > 1e-12 * scale && isfinite(S)))
        return ws_fail(st, WS_EINPUT, "line metrics: the ground-truth curves' bounding box has no extent");
    m->side = S;
    double tau[WS_LINE_NTAU];
    for (int k = 0; k < WS_LINE_NTAU; k++) tau[k] = WS_LINE_TAU[k] * S;
    ws_gaussians rs = {0}, gs = {0};
    int rc = ws_curves_sample_dense(result, WS_LINE_SPACING * S, &rs, st) ||
             ws_curves_sample_dense(gt, WS_LINE_SPACING * S, &gs, st) ||
             ws_directed_distance(rs.mu, rs.n, gs.mu, gs.n, WS_LINE_NTAU, tau, &m->accuracy, m->precision, st) ||
             ws_directed_distance(gs.mu, gs.n, rs.mu, rs.n, WS_LINE_NTAU, tau, &m->completeness, m->recall, st);
    if (!rc) {
        m->accuracy /= S;
        m->completeness /= S;
        m->n_result = rs.n;
        m->n_gt = gs.n;
        m->chamfer = m->accuracy + m->completeness;
        for (int k = 0; k < WS_LINE_NTAU; k++) {
            double pr = m->precision[k] + m->recall[k];
            m->fscore[k] = pr > 0 ? 2 * m->precision[k] * m->recall[k] / pr : 0;
        }
    }
    ws_gaussians_free(&rs);
    ws_gaussians_free(&gs);
    return rc ? st->code : WS_OK;
}

void ws_line_metrics_json(FILE *fp, const ws_line_metrics *m) {
    const char *const names[4] = {"side", "accuracy", "completeness", "chamfer"};
    const double values[4] = {m->side, m->accuracy, m->completeness, m->chamfer};
    fputs("\"lines\": {", fp);
    for (int k = 0; k < 4; k++) {
        fputs(k ? ", " : "", fp);
        ws_json_number(fp, names[k], values[k], 9);
    }
    for (int k = 0; k < WS_LINE_NTAU; k++) {
        int pc = (int)lround(100 * WS_LINE_TAU[k]);
        char key[3][32];
        snprintf(key[0], sizeof key[0], "precision_%d", pc);
        snprintf(key[1], sizeof key[1], "recall_%d", pc);
        snprintf(key[2], sizeof key[2], "fscore_%d", pc);
        const double v[3] = {m->precision[k], m->recall[k], m->fscore[k]};
        for (int j = 0; j < 3; j++) {
            fputs(", ", fp);
            ws_json_number(fp, key[j], v[j], 9);
        }
    }
    fputc('}', fp);
}
