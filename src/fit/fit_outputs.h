/* fit_outputs.h: what `wiresketch fit` leaves in its output directory:
 * curves.json/.obj/.ply, log.csv, test/ (each test view's sketch render and
 * its photo), turntable.gif, evolution.gif, metrics.json and report.html.
 * Every file is written to a temporary name and renamed. */
#ifndef WS_FIT_OUTPUTS_H
#define WS_FIT_OUTPUTS_H
#include "fit/fit_options.h"
#include "fit/fit_state.h"
#include "io/scene.h"
#include "objective/view_targets.h"

/* The outputs show the fit's curves less those marked in retire (s->curves.n;
 * fit/respawn.h), unless that would leave none; metrics.json and the
 * report say how many were retired, and how much of the training views'
 * lines they explain (fit_explained.h; targets: the fit's, NULL for a
 * stopped fit, which is not measured), with a warning in the report and,
 * once every output is written, on stderr when that is little. test_losses: one per test view of the
 * fit's curves (NULL: not evaluated, e.g. after an interruption);
 * test_loss: their mean (NaN: not evaluated). */
int ws_fit_write_outputs(const ws_fit_options *opt, const ws_scene *scene, ws_view_targets *targets,
                         const ws_fit_state *s, const int *retire, const double *test_losses, double test_loss,
                         ws_status *st);

/* Refuses, before the fit, an output of the files above that would replace
 * one of the fit's inputs (base/outfile.h: `--init OUT/curves.json`), so
 * that a fit never ends refused halfway through writing them. */
int ws_fit_outputs_check(const char *out_dir, ws_status *st);

#endif
