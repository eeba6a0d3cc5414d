/* fit_time.h: what a fit's schedule will take, told before the first step
 * and as the time left on every progress line.
 *
 * A step's cost depends on where it is in the schedule: the line loss
 * (objective/lines.h) adds its finer levels as the fit progresses, so its
 * coarse-to-fine phases cost up to 2-4 times the first one's steps per
 * step. The schedule is cut into phases of equal work (the levels in use;
 * one phase without the line loss). Before the first step each phase's
 * step is timed once or more (the training batch's loss and gradient at a
 * progress within the phase, on the first batches' views, with the sketch
 * grown to the length it will have there; CPU time, which the machine's
 * load leaves alone) and the phases are modelled as costing in that
 * proportion. While the fit runs, the time left is
 *   left = sum over the remaining steps of (a m(phase of the step) + b),
 * m the modelled CPU seconds of a step's batch, a the median of the last
 * WS_FIT_TIME_WINDOW steps' batch wall seconds over their m (it carries
 * the load and the threads; the median leaves out the one-time costs of a
 * view's first batch, such as its hidden-line map), b the mean wall
 * seconds a step costs besides its batch (Adam, validation, respawn,
 * snapshots, checkpoints) over all steps so far. Every phase's modelled
 * and measured costs end the fit's output, so that the model can be
 * checked against the run. */
#ifndef WS_FIT_TIME_H
#define WS_FIT_TIME_H
#include "nn/base/rng.h"
#include "nn/base/status.h"
#include "fit/fit_options.h"
#include "objective/objective.h"

#define WS_FIT_TIME_PHASES 8
#define WS_FIT_TIME_WINDOW 64

typedef struct {
    int n;                              /* phases */
    long first[WS_FIT_TIME_PHASES + 1]; /* phase k: steps first[k] .. first[k + 1] - 1 */
    long total;                         /* steps planned (first[n]) */
    long schedule;                      /* the epochs' steps: progress = step / schedule */
    double model[WS_FIT_TIME_PHASES];   /* CPU seconds per step, timed before the first step */
    double wall_per_cpu;                /* of the timing: the estimate before the first step */
    /* measured in this process, per phase: wall and CPU seconds of the
     * batches' losses and gradients, of the whole steps, and steps */
    double batch_wall[WS_FIT_TIME_PHASES], batch_cpu[WS_FIT_TIME_PHASES];
    double wall[WS_FIT_TIME_PHASES], cpu[WS_FIT_TIME_PHASES];
    long steps[WS_FIT_TIME_PHASES];
    double ratio[WS_FIT_TIME_WINDOW];   /* the last steps' batch wall seconds over m */
    long seen;                          /* steps measured */
    float *batch_steps;                 /* each step's batch CPU seconds (total), for the medians */
} ws_fit_time;

/* The phases of steps 0 .. total - 1 of a schedule of `schedule` steps,
 * with the line loss's levels (lines) or without. */
int ws_fit_time_phases(ws_fit_time *t, long total, long schedule, int lines, ws_status *st);
/* The same phases alone: their first steps (first[n] = total) and the
 * line loss's levels in use in each (all of them without it); returns n. */
int ws_fit_time_boundaries(long total, long schedule, int lines, long first[WS_FIT_TIME_PHASES + 1],
                           int levels[WS_FIT_TIME_PHASES]);
void ws_fit_time_free(ws_fit_time *t);

/* Times each phase's training step of the curves c, each stretched about
 * its middle (its point at t = 1/2) so that together they are as long as
 * a fit's sketch is at the phase's middle, start_length (the length at
 * step 0) times 1 + (WS_FIT_TIME_GROWTH - 1) x the progress there, when
 * they are shorter: a step's cost grows with its Gaussians. On the first
 * WS_FIT_TIME_BATCHES batches of order[0..n_train) (batch_size views
 * each), each called once untimed first (a view's first call pays for what
 * is kept, such as its hidden-line map), then in turn until
 * WS_FIT_TIME_CALIBRATION CPU seconds per phase (at most WS_FIT_TIME_CALLS
 * calls; on several MPI ranks, where each call is collective, one batch
 * and one call, whatever each rank measures); the phase's model is the
 * median call. The rng is copied, grad a scratch buffer: nothing of the
 * fit's state changes, and each step sets the objective's progress again. */
#define WS_FIT_TIME_CALIBRATION 0.15
#define WS_FIT_TIME_CALLS 50
#define WS_FIT_TIME_BATCHES 4
int ws_fit_time_calibrate(ws_fit_time *t, ws_objective *obj, const ws_curves *c, double start_length,
                          const int *order, int n_train, int batch_size, const ws_rng *rng, double *grad,
                          ws_status *st);

/* How a fit's sketch grows: about linearly over the schedule, from its
 * start to WS_FIT_TIME_GROWTH times as long (a line-loss fit's 25 strokes
 * of 0.15 end 2.6 - 4.3 times as long on the capture test bed:
 * docs/RESULTS.md, "The time a fit announces"). A CLIP step's cost hardly
 * depends on it. */
#define WS_FIT_TIME_GROWTH 3.2

/* Process CPU seconds. */
double ws_cpu_seconds(void);

/* Step `step` took batch (wall, CPU seconds) for its batch's loss and
 * gradient and all in all. */
void ws_fit_time_add(ws_fit_time *t, long step, const double batch[2], const double all[2]);

/* Wall seconds predicted for steps from .. total - 1 (before any step is
 * measured: the timing's, scaled by its wall per CPU second). */
double ws_fit_time_left(const ws_fit_time *t, long from);

/* Before the first step: "fit: N steps, about 40 s" on out, and past an
 * hour a warning that names the settings that make the fit faster. */
void ws_fit_time_announce(const ws_fit_time *t, long from, const ws_fit_options *opt, FILE *out);

/* For the fit's last words: the wall per CPU second of the timing and of
 * the steps, then one line per phase: "fit: phase K: steps A-B,
 * modelled X ms, measured Y ms CPU per step in the batch (median M) + Z ms
 * besides (W ms wall in all)". */
void ws_fit_time_print(const ws_fit_time *t, FILE *out);

#endif
