/* objective.h: the loss of a sketch and its gradient with respect to the
 * control points (METHOD.md sections 2, 3, 6), the one place that wires
 * sample -> splat -> loss -> backward: the curves are sampled into
 * Gaussians, splatted into each view, compared with the photo (loss.h),
 * and dL/dalpha is carried back through the splatting and the Bernstein
 * weights; with lo->hidden_lines hull, each view draws only the Gaussians
 * the visual hull does not hide (hidden_lines.h). `fit` (a training batch,
 * the validation and test losses), `grad`, `eval`, `rank` (ranking.h) and
 * the benchmarks all call it. */
#ifndef WS_OBJECTIVE_H
#define WS_OBJECTIVE_H
#include <stddef.h>
#include "base/timing.h"
#include "io/scene.h"
#include "nn/base/rng.h"
#include "nn/base/status.h"
#include "objective/loss.h"
#include "render/curves.h"
#include "render/splat.h"

typedef struct ws_objective ws_objective;

/* An objective for sketches of at most n_curves curves on the scene's
 * views (the scene must outlive it). */
int ws_objective_create(ws_objective **obj, const ws_scene *scene, const ws_loss_options *lo,
                        const ws_splat_options *so, int n_curves, ws_status *st);
void ws_objective_free(ws_objective *obj);

/* The loss of view `view` of `split` for the curves c; augment as in
 * ws_loss_view (0: item 0 only, rng unused). With grad (curves x WS_CURVE_FLOATS),
 * scale x dL/dP is added to it; NULL: the loss alone. */
int ws_objective_view(ws_objective *obj, const ws_curves *c, int split, int view, int augment,
                      ws_rng *rng, double scale, double *loss, double *grad, ws_status *st);

/* The training batch: the mean loss of training views views[0..nviews)
 * with augmentation drawn from rng, plus the silhouette term over the
 * part of training views that views[0] falls in (silhouette_loss.h) times
 * its weight when that is not 0,
 * and its gradient (grad: curves x WS_CURVE_FLOATS, overwritten). On WS_ENUMERIC (a non-finite value) loss and grad are
 * partial; the caller decides. */
int ws_objective_batch(ws_objective *obj, const ws_curves *c, const int *views, int nviews, ws_rng *rng,
                       double *loss, double *grad, ws_status *st);

/* The mean loss over the views of `split`, item 0 only, no augmentation
 * (METHOD.md section 8 "test loss"; NaN for an empty split). per_view (n, or
 * NULL) receives each view's loss. */
int ws_objective_split_mean(ws_objective *obj, const ws_curves *c, int split, double *per_view,
                            double *mean, ws_status *st);

/* Do the curves c sample into Gaussians (WS_ENUMERIC when they are too
 * long or not finite)? They become the objective's last sampling. */
int ws_objective_sample(ws_objective *obj, const ws_curves *c, ws_status *st);

/* The Gaussians of the last sampling. */
const ws_gaussians *ws_objective_gaussians(const ws_objective *obj);
/* The loss it takes (for its statistics, e.g. ws_loss_bank_bytes). */
const ws_loss *ws_objective_loss(const ws_objective *obj);

/* From now on add the time of each part to t (NULL: stop). */
void ws_objective_set_timing(ws_objective *obj, ws_step_timing *t);
/* The fit's progress in [0, 1] (ws_loss_set_progress). */
void ws_objective_set_progress(ws_objective *obj, double progress);
/* Splat with this cut-off from now on (the benchmarks compare them). */
void ws_objective_set_cutoff(ws_objective *obj, double cutoff);

#endif
