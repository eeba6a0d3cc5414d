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

/* Set to a signal's number by its handler (or to SIGPIPE when the progress
 * line cannot be written: its reader went away): the fit finishes its
 * current step, checkpoints, writes every output it can, and returns with
 * *interrupted = that number. */
extern volatile sig_atomic_t ws_fit_stop_requested;

/* resume: continue from out_dir/checkpoint.bin (opt must be the options the
 * run was started with: the checkpoint stores them and the command line
 * restores them). *interrupted: 0, or the signal that stopped the run (on
 * several ranks, the largest any rank received); then a failed write of the
 * checkpoint or an output does not stop the others and the first failure
 * is returned. */
int ws_fit(const ws_fit_options *opt, const char *const *argv, int argc, int resume,
           int *interrupted, ws_status *st);

#endif
