/* verdict.c: metrics' scales and verdicts (see verdict.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "metrics/verdict.h"

#define DIAGONAL "fraction of the bounding-box diagonal, 0 best"
#define SHARE "share, 1 best"
#define SIDE "fraction of the object's largest side, 0 best"

static const ws_metric_scale scales[] = {
    {"surface_mean", DIAGONAL, 0, 0.015, 0.03},
    {"surface_p90", DIAGONAL, 0, 0.03, 0.06},
    {"surface_precision", SHARE, 1, 0.8, 0.5},
    {"gaussian_precision", SHARE, 1, 0.8, 0.5},
    {"chamfer", DIAGONAL, 0, 0.01, 0.03},
    {"fscore", "F-score at 1% of the diagonal, 1 best", 1, 0.8, 0.5},
    {"lines_chamfer", SIDE, 0, 0.01, 0.03},
    {"lines_fscore_1", "F-score at 1% of the largest side, 1 best", 1, 0.9, 0.6},
    {"lines_fscore_2", "F-score at 2% of the largest side, 1 best", 1, 0.95, 0.7},
    {"stray_share", "share of the curves, 0 best", 0, 0, 0.1},
    {"test_loss_edges", "line loss, 0 perfect, 1 an empty sketch", 0, 0.15, 0.3},
    {"drawing_precision_1", "share of the drawing within 1% of the image diagonal of a reference line, 1 best", 1,
     0.85, 0.6},
    {"drawing_contour_recall_1", "share of the outline and inner contours drawn, at 1%, 1 best", 1, 0.9, 0.7},
    {"drawing_scribble_1", "share of the drawing inside the object and away from its lines, 0 best", 0, 0.1, 0.25},
    {"drawing_precision_05", "share of the drawing within 0.5% of the image diagonal of a reference line, 1 best", 1,
     0.85, 0.6},
};

const ws_metric_scale *ws_metric_scale_of(const char *key) {
    for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++)
        if (!strcmp(scales[k].key, key)) return &scales[k];
    return NULL;
}

const char *ws_verdict(const ws_metric_scale *m, double v) {
    if (!isfinite(v)) return "none";
    int good = m->higher_better ? v >= m->good : v <= m->good;
    int fair = m->higher_better ? v >= m->fair : v <= m->fair;
    return good ? "good" : fair ? "fair" : "poor";
}

void ws_metric_scale_text(const ws_metric_scale *m, char *text, size_t size) {
    const char *op = m->higher_better ? ">=" : "<=";
    snprintf(text, size, "%s; good %s %g, fair %s %g, poor %s", m->unit, op, m->good, op, m->fair,
             m->higher_better ? "below" : "above");
}
