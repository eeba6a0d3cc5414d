/* fit_metrics.c: the metrics table and its verdicts (see fit_metrics.h). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include "fit/fit_metrics.h"
#include "metrics/verdict.h"

/* A row: name, value (printf), and the verdict of `key` on v (key NULL:
 * none; scale_text then stands in the scale column, or nothing). */
static void row(ws_fit_metrics *m, const char *name, const char *key, double v, const char *scale_text,
                const char *fmt, ...) {
    if (m->n >= WS_FIT_METRICS_MAX) return;
    int k = m->n++;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m->text[k][0], sizeof m->text[k][0], fmt, ap);
    va_end(ap);
    const ws_metric_scale *scale = key ? ws_metric_scale_of(key) : NULL;
    if (scale) ws_metric_scale_text(scale, m->text[k][1], sizeof m->text[k][1]);
    m->key[k] = scale ? key : NULL;
    m->items[k] = (ws_report_item){.key = name,
                                   .value = m->text[k][0],
                                   .scale = scale ? m->text[k][1] : scale_text ? scale_text : "",
                                   .verdict = scale ? ws_verdict(scale, v) : NULL};
}

void ws_fit_metrics_fill(ws_fit_metrics *m, const ws_fit_state *s, int retired, double test_loss, int lines_loss,
                         const ws_quality *q) {
    m->n = 0;
    row(m, "steps", NULL, NAN, "", "%ld (%ld skipped; %ld respawned, %d retired)", s->global_step, s->skipped_steps,
        s->respawned, retired);
    row(m, "test loss (item 0)", lines_loss ? "test_loss_edges" : NULL, test_loss,
        "lower is better; compares runs of one scene and one loss only", "%.6g", test_loss);
    if (q->have_surface) {
        row(m, "surface distance, mean / diagonal", "surface_mean", q->surface.mean, NULL, "%.5f", q->surface.mean);
        row(m, "surface distance, 90th percentile / diagonal", "surface_p90", q->surface.p90, NULL, "%.5f",
            q->surface.p90);
        row(m, "Gaussians within 1% of the diagonal of the surface", "surface_precision",
            q->surface_strays.precision, NULL, "%.4f (%d stray of %d)", q->surface_strays.precision,
            q->surface_strays.stray_curves, q->surface_strays.n_curves);
    }
    if (q->have_curves) {
        const ws_line_metrics *l = &q->lines;
        row(m, "curve Chamfer / diagonal", "chamfer", q->curves.chamfer, NULL, "%.5f", q->curves.chamfer);
        row(m, "curve F-score at 1% of the diagonal", "fscore", q->curves.fscore, NULL, "%.4f", q->curves.fscore);
        row(m, "precision over Gaussians / recall over arc length, at 1%", "gaussian_precision",
            q->curve_strays.precision, NULL, "%.4f / %.4f", q->curve_strays.precision, q->curves.recall);
        int n = q->curve_strays.n_curves;
        row(m, "stray curves (most Gaussians beyond 5% of the diagonal)", "stray_share",
            n ? (double)q->curve_strays.stray_curves / n : 0, NULL, "%d of %d", q->curve_strays.stray_curves, n);
        row(m, "accuracy / completeness / Chamfer (their sum), over the largest side", "lines_chamfer", l->chamfer,
            NULL, "%.4f / %.4f / %.4f", l->accuracy, l->completeness, l->chamfer);
        row(m, "precision / recall / F-score at 1% of the largest side", "lines_fscore_1", l->fscore[0], NULL,
            "%.3f / %.3f / %.3f", l->precision[0], l->recall[0], l->fscore[0]);
        row(m, "precision / recall / F-score at 2% of the largest side", "lines_fscore_2", l->fscore[1], NULL,
            "%.3f / %.3f / %.3f", l->precision[1], l->recall[1], l->fscore[1]);
    }
}

void ws_fit_metrics_add_explained(ws_fit_metrics *m, double share) {
    if (isfinite(share))
        row(m, "training views' lines within 1% of the diagonal of a stroke", NULL, share,
            "higher is better; below 20% the curves explain little of the photos", "%.1f%%", 100 * share);
}

void ws_fit_metrics_add_drawing(ws_fit_metrics *m, const ws_drawing_score *d) {
    row(m, "drawing: precision / recall / F at 1% of the image diagonal", "drawing_precision_1", d->precision[0], NULL,
        "%.3f / %.3f / %.3f", d->precision[0], d->recall[0], d->fscore[0]);
    row(m, "drawing: contour recall at 1%", "drawing_contour_recall_1", d->contour_recall[0], NULL, "%.3f",
        d->contour_recall[0]);
    row(m, "drawing: interior scribble at 1%; overdraw", "drawing_scribble_1", d->scribble[0], NULL, "%.3f; %.2f",
        d->scribble[0], d->overdraw);
    row(m, "drawing: precision / recall / F at 0.5% of the image diagonal", "drawing_precision_05", d->precision[1],
        NULL, "%.3f / %.3f / %.3f", d->precision[1], d->recall[1], d->fscore[1]);
}

void ws_fit_metrics_verdicts_json(FILE *fp, const ws_fit_metrics *m) {
    fprintf(fp, "\"verdicts\": {");
    int first = 1;
    for (int k = 0; k < m->n; k++)
        if (m->key[k]) {
            fprintf(fp, "%s\"%s\": \"%s\"", first ? "" : ", ", m->key[k], m->items[k].verdict);
            first = 0;
        }
    fprintf(fp, "}");
}
