/* fit.h: `wiresketch fit`, the optimisation of METHOD.md sections 5-7.
 *
 * ws_fit runs the schedule (epochs of randomly ordered training batches,
 * inner_steps Adam steps each, validation every eval_every batches, test at
 * the end), writes the outputs into out_dir, and checkpoints so that an
 * interrupted run resumes bit-identically. */
#ifndef WS_FIT_H
#define WS_FIT_H
#include <signal.h>
#include "fit/fit_options.h"
#include "nn/base/status.h"

/* Set from a signal handler: the fit finishes its current step, checkpoints,
 * writes every output, and returns WS_OK with *interrupted = 1. */
extern volatile sig_atomic_t ws_fit_stop_requested;

/* resume: continue from out_dir/checkpoint.bin (opt must be the options the
 * run was started with: the checkpoint stores them and the command line
 * restores them). */
int ws_fit(const ws_fit_options *opt, const char *const *argv, int argc, int resume,
           int *interrupted, ws_status *st);

#endif
