/* fit_metrics.h: the rows of report.html's metrics table, each with its
 * unit, scale and verdict (metrics/verdict.h), and the same verdicts as
 * metrics.json's "verdicts". */
#ifndef WS_FIT_METRICS_H
#define WS_FIT_METRICS_H
#include <stdio.h>
#include "fit/fit_state.h"
#include "io/report.h"
#include "metrics/drawing_score.h"
#include "metrics/quality.h"

#define WS_FIT_METRICS_MAX 20

typedef struct {
    int n;
    ws_report_item items[WS_FIT_METRICS_MAX];
    const char *key[WS_FIT_METRICS_MAX]; /* the verdict's metric (verdict.h), NULL: none */
    char text[WS_FIT_METRICS_MAX][2][200];
} ws_fit_metrics;

/* The rows of a fit: steps, the test loss (a verdict only for the line
 * loss alone, lines_loss), and what the ground truth measured (q). */
void ws_fit_metrics_fill(ws_fit_metrics *m, const ws_fit_state *s, int retired, double test_loss, int lines_loss,
                         const ws_quality *q);

/* The share of the training views' lines the curves explain
 * (fit_explained.h); none when it is NaN. */
void ws_fit_metrics_add_explained(ws_fit_metrics *m, double share);

/* The drawing's rows (metrics/drawing_score.h): precision, recall and F at
 * 1% and 0.5% of the image diagonal, contour recall, interior scribble and
 * overdraw. */
void ws_fit_metrics_add_drawing(ws_fit_metrics *m, const ws_drawing_score *d);

/* `"verdicts": {"surface_mean": "good", ...}` (no separator before it). */
void ws_fit_metrics_verdicts_json(FILE *fp, const ws_fit_metrics *m);

#endif
