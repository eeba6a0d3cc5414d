/* fit_state.h: everything a fit carries from step to step and a
 * checkpoint stores (control points, Adam moments, rng, position in the
 * schedule, the training log and the evolution snapshots), below the loop
 * (fit.h), the checkpoint and the outputs that all read it. */
#ifndef WS_FIT_STATE_H
#define WS_FIT_STATE_H
#include "fit/adam.h"
#include "nn/base/rng.h"
#include "nn/base/status.h"
#include "render/curves.h"

typedef struct {
    int batch;       /* global batch index */
    long step;       /* global step index */
    double seconds;  /* wall time of fitting when the row was logged */
    double train_loss, val_loss; /* val_loss NaN where not evaluated */
} ws_log_row;

/* Everything a resumed run needs to continue exactly where it stopped. */
typedef struct {
    int epoch, batch_in_epoch, step_in_batch; /* where the next step starts */
    long global_step;
    int global_batch;
    double elapsed;             /* seconds of fitting before this process */
    long skipped_steps;         /* steps refused for a non-finite loss/gradient */
    long respawned;             /* idle curves moved (fit/respawn.h) */
    ws_rng rng;
    int n_train;
    int *order;                 /* this epoch's view order, n_train */
    ws_curves curves;
    ws_adam adam;
    int nlog, caplog;
    ws_log_row *log;
    int nsnap, capsnap;
    double *snapshots;          /* nsnap x (curves.n x WS_CURVE_FLOATS) control points */
} ws_fit_state;

void ws_fit_state_free(ws_fit_state *s);

/* Appends a row to the training log. */
int ws_fit_state_log(ws_fit_state *s, const ws_log_row *row, ws_status *st);
/* Keeps the control points for a frame of evolution.gif. */
int ws_fit_state_snapshot(ws_fit_state *s, ws_status *st);
/* Seconds of fitting: those before this process and those since `start`
 * (ws_seconds() when this process began fitting). */
double ws_fit_state_elapsed(const ws_fit_state *s, double start);

#endif
