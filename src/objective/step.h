/* step.h: the loss of a set of curves and its gradient with respect to the
 * control points, the work of one training step (METHOD.md sections 2, 3, 6):
 * sample the curves into Gaussians, splat them into each view, take the
 * loss (loss.h), and carry dL/dalpha back through the splatting and the
 * Bernstein weights. `fit` runs it every step; the benchmarks time it. */
#ifndef WS_STEP_H
#define WS_STEP_H
#include "render/curves.h"
#include "objective/loss.h"
#include "io/scene.h"
#include "render/splat.h"
#include "base/timing.h"

typedef struct {
    const ws_scene *scene;
    ws_loss *loss;
    ws_splat *splat;
    ws_splat_options splat_opt;
    ws_gaussians gaussians;   /* of the last sampling */
    double *alpha, *dalpha;   /* H x W */
    double *dmu;              /* gaussians x 3, grown with them */
    int dmu_cap;
    double *dP;               /* curves x 12 */
    int n_curves;
    ws_step_timing *timing;   /* NULL: no clock is read */
} ws_step;

/* A workspace for n_curves curves on the scene's views (the scene must
 * outlive it). */
int ws_step_init(ws_step *s, const ws_scene *scene, const ws_loss_options *lo,
                 const ws_splat_options *so, int n_curves, ws_status *st);
void ws_step_free(ws_step *s);

/* From now on add the time of each part to t (NULL: stop). */
void ws_step_set_timing(ws_step *s, ws_step_timing *t);

/* The loss of view `view` of `split` for the Gaussians of the last
 * ws_curves_sample(c, &s->gaussians); augment as in ws_loss_view. With grad
 * (curves x 12), scale x dL/dP is added to it. */
int ws_step_view(ws_step *s, const ws_curves *c, int split, int view, int augment, ws_rng *rng,
                 double scale, double *loss, double *grad, ws_status *st);

/* The mean loss of training views views[0..nviews) with augmentation drawn
 * from rng, and its gradient (grad: curves x 12, overwritten). Samples the
 * curves first. On WS_ENUMERIC (a non-finite value) loss and grad are
 * partial; the caller decides. */
int ws_step_batch(ws_step *s, const ws_curves *c, const int *views, int nviews, ws_rng *rng,
                  double *loss, double *grad, ws_status *st);

#endif
