/* sweep_page.h: the summary of a sweep (cli/cmd_sweep.c), beside the fit's
 * report (report.h): DIR/contact_sheet.png, row 0 the photos of the first
 * run's test views, then one row per run of its test renders, each row
 * named in a strip above its cells; and DIR/index.html, the same as a
 * table with each run's metrics and time from DIR/RUN/metrics.json and
 * links to its report. Every string is escaped and every path
 * percent-encoded (html.h). */
#ifndef WS_SWEEP_PAGE_H
#define WS_SWEEP_PAGE_H
#include "nn/base/status.h"

typedef struct {
    const char *scene;       /* the scene swept, shown on the page */
    const char *out;         /* DIR */
    int nruns;
    const char *const *runs; /* each run's folder in DIR ("n_curves=10"), in grid order */
    int views, cell;         /* test views shown per run; pixels per contact sheet cell */
} ws_sweep_page;

/* Fails with WS_EUSAGE when the contact sheet of these runs would be
 * larger than a contact sheet may be, so that a sweep says so before its
 * first fit rather than after its last. */
int ws_sweep_page_check(const ws_sweep_page *p, ws_status *st);

/* Writes DIR/index.html and DIR/contact_sheet.png; a run's missing
 * render leaves its cell grey, missing metrics show as a dash. */
int ws_sweep_page_write(const ws_sweep_page *p, ws_status *st);

#endif
