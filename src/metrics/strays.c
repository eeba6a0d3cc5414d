/* strays.c: Gaussian-level precision and stray curves (see strays.h). */
#include <stdlib.h>
#include "metrics/metrics.h"
#include "metrics/strays.h"

int ws_stray_metrics_compute(const ws_curves *c, const ws_nearest *gt, double diagonal,
                             ws_stray_metrics *m, ws_status *st) {
    ws_gaussians g = {0};
    if (ws_curves_sample(c, &g, st)) return st->code;
    double *d = ws_malloc(sizeof(double) * (g.n ? g.n : 1), "Gaussian distances", st);
    int *far = d ? ws_calloc(c->n ? c->n : 1, sizeof(int), "stray counts", st) : NULL;
    int *count = far ? ws_calloc(c->n ? c->n : 1, sizeof(int), "stray counts", st) : NULL;
    if (!count) {
        free(d);
        free(far);
        ws_gaussians_free(&g);
        return st->code;
    }
    ws_nearest_query(gt, g.mu, g.n, d, NULL);
    int close = 0;
    for (int k = 0; k < g.n; k++) {
        close += d[k] <= WS_METRIC_FSCORE_THRESHOLD * diagonal;
        count[g.curve[k]]++;
        far[g.curve[k]] += d[k] > WS_STRAY_DISTANCE * diagonal;
    }
    *m = (ws_stray_metrics){.n_gaussians = g.n, .n_curves = c->n,
                            .precision = g.n ? (double)close / g.n : 0};
    for (int ci = 0; ci < c->n; ci++) m->stray_curves += 2 * far[ci] > count[ci];
    free(d);
    free(far);
    free(count);
    ws_gaussians_free(&g);
    return WS_OK;
}
