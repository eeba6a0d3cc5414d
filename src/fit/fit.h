/* fit.h: `wiresketch fit`, the optimisation of METHOD.md sections 5-7.
 *
 * ws_fit runs the schedule (epochs of randomly ordered training batches,
 * inner_steps Adam steps each, validation every eval_every batches, test at
 * the end), writes the outputs into out_dir, and checkpoints so that an
 * interrupted run resumes bit-identically. */
#ifndef WS_FIT_H
#define WS_FIT_H
#include <signal.h>
#include <stdint.h>
#include "fit/adam.h"
#include "render/curves.h"
#include "objective/loss.h"
#include "nn/base/rng.h"
#include "nn/base/status.h"

typedef struct {
    const char *scene_dir;
    const char *out_dir;
    const char *init_curves;   /* NULL: the random initialisation of METHOD.md section 2 */
    ws_loss_options loss;
    int size;                  /* working resolution (the model's with CLIP) */
    int batch_size, epochs, inner_steps, n_curves, eval_every, threads;
    double learning_rate, thickness, radius, length, overlap, cutoff;
    uint64_t seed;
    int max_steps;             /* stop after this many steps in all (0: no limit) */
    double checkpoint_minutes; /* checkpoint at least this often */
    int snapshot_every;        /* steps between frames of evolution.gif */
    int quiet;                 /* no progress line */
} ws_fit_options;

void ws_fit_options_default(ws_fit_options *opt);
/* Every option in its range (WS_EUSAGE naming the option otherwise); the
 * command line and a checkpoint's stored arguments both pass here. */
int ws_fit_options_check(const ws_fit_options *opt, ws_status *st);

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
    ws_rng rng;
    int n_train;
    int *order;                 /* this epoch's view order, n_train */
    ws_curves curves;
    ws_adam adam;
    int nlog, caplog;
    ws_log_row *log;
    int nsnap, capsnap;
    double *snapshots;          /* nsnap x (curves.n x 12) control points */
} ws_fit_state;

void ws_fit_state_free(ws_fit_state *s);

/* Set from a signal handler: the fit finishes its current step, checkpoints,
 * writes every output, and returns WS_OK with *interrupted = 1. */
extern volatile sig_atomic_t ws_fit_stop_requested;

/* resume: continue from out_dir/checkpoint.bin (opt must be the options the
 * run was started with: the checkpoint stores them and the command line
 * restores them). */
int ws_fit(const ws_fit_options *opt, const char *const *argv, int argc, int resume,
           int *interrupted, ws_status *st);

#endif
