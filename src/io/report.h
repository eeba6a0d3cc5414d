/* report.h: report.html, the one-page summary of a fit.
 *
 * The page is self-contained and needs no network: CSS, the loss plot
 * (inline SVG), the curves (a JSON array of polylines, 64 points per curve
 * or fewer when there are very many curves) and the 3D viewer (plain
 * JavaScript on a canvas: drag to rotate, scroll to zoom, double-click to
 * reset) are all inside the file. Images (test renders, photos,
 * animations) are referenced by paths relative to the report, so they must
 * be files in the output directory: the page shows whatever is there.
 * Every string is escaped for HTML, every path percent-encoded, so any
 * text (a scene path with '<' or '&', say) is shown as it is. */
#ifndef WS_REPORT_H
#define WS_REPORT_H
#include "render/curves.h"
#include "nn/base/status.h"

typedef struct ws_report_item {
    const char *key, *value;
    const char *scale;   /* a metric's unit, scale and thresholds; NULL: none (settings) */
    const char *verdict; /* "good", "fair", "poor"; NULL: none */
} ws_report_item;

typedef struct {
    const char *name;        /* "r_0" */
    const char *render_path; /* the stroke render, relative to the report */
    const char *photo_path;  /* the photo, relative to the report; NULL: none */
    double loss;             /* the view's test loss; NaN: not shown */
    int width;               /* the images' side in pixels (square) */
    int crop[3];             /* x, y and side of the square both are shown cropped to; side 0: whole */
} ws_report_view;

typedef struct {
    const char *caption;
    const char *path;        /* relative to the report: "turntable.gif" */
} ws_report_image;

typedef struct {
    const char *title;       /* NULL: "wiresketch fit" */
    const char *scene_path;  /* NULL: not shown */
    const ws_report_item *settings;
    int n_settings;
    const ws_report_item *metrics;  /* with a scale and a verdict each, where they have one */
    int n_metrics;
    const char *warning;     /* shown above the metrics (what they do not measure); NULL: none */
    /* Loss curves: train loss at every step, val loss at the eval points.
     * Non-finite values leave gaps. The y axis is logarithmic when the
     * positive values span more than a factor 10. */
    const long *train_step;
    const double *train_loss;
    int n_train;
    const long *val_step;
    const double *val_loss;
    int n_val;
    /* Phases of the schedule marked on the plot: phase k starts at step
     * phase_step[k] and is labelled phase_label[k]; phase_note says why
     * they matter (NULL: no phases). */
    const long *phase_step;
    const char *const *phase_label;
    int n_phases;
    const char *phase_note;
    const ws_report_view *tests;
    int n_tests;
    const ws_report_image *images; /* animations and other pictures */
    int n_images;
    double wall_seconds;     /* NaN: not shown */
    const ws_curves *curves; /* NULL: no 3D view; curves with a non-finite
                                point are left out */
    const double *cameras;   /* 6 per camera shown in the 3D view: its centre and viewing direction */
    int n_cameras;
} ws_report;

int ws_report_write(const char *path, const ws_report *r, ws_status *st);

#endif
