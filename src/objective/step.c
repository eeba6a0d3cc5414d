/* step.c: the loss and gradient of a set of curves (see step.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "objective/step.h"

int ws_step_init(ws_step *s, const ws_scene *scene, const ws_loss_options *lo,
                 const ws_splat_options *so, int n_curves, ws_status *st) {
    memset(s, 0, sizeof *s);
    s->scene = scene;
    s->splat_opt = *so;
    s->n_curves = n_curves;
    size_t pixels = (size_t)scene->width * scene->height;
    if (ws_loss_create(&s->loss, lo, scene, st) ||
        ws_splat_create(&s->splat, scene->width, scene->height, st))
        return st->code;
    if (!(s->alpha = ws_malloc(pixels * sizeof(double), "stroke image", st)) ||
        !(s->dalpha = ws_malloc(pixels * sizeof(double), "stroke gradient", st)) ||
        !(s->dP = ws_malloc((size_t)n_curves * 12 * sizeof(double), "control point gradient", st)))
        return st->code;
    return WS_OK;
}

void ws_step_free(ws_step *s) {
    ws_loss_free(s->loss);
    ws_splat_free(s->splat);
    ws_gaussians_free(&s->gaussians);
    free(s->alpha);
    free(s->dalpha);
    free(s->dmu);
    free(s->dP);
    memset(s, 0, sizeof *s);
}

void ws_step_set_timing(ws_step *s, ws_step_timing *t) {
    s->timing = t;
    ws_loss_set_timing(s->loss, t);
}

static int grow_dmu(ws_step *s, ws_status *st) {
    if (s->gaussians.n <= s->dmu_cap) return WS_OK;
    free(s->dmu);
    s->dmu_cap = s->gaussians.n * 2;
    s->dmu = ws_malloc((size_t)s->dmu_cap * 3 * sizeof(double), "Gaussian gradients", st);
    return s->dmu ? WS_OK : st->code;
}

int ws_step_view(ws_step *s, const ws_curves *c, int split, int view, int augment, ws_rng *rng,
                 double scale, double *loss, double *grad, ws_status *st) {
    if (c->n != s->n_curves)
        return ws_fail(st, WS_EINTERNAL, "step: %d curves in a workspace for %d", c->n, s->n_curves);
    const ws_view *v = &s->scene->split[split].views[view];
    double t0 = ws_time_start(s->timing);
    if (ws_splat_forward(s->splat, &v->cam, s->gaussians.mu, s->gaussians.n, c->thickness,
                         &s->splat_opt, s->alpha, st))
        return st->code;
    ws_time_add(s->timing, WS_TIME_SPLAT, t0);
    if (ws_loss_view(s->loss, split, view, s->alpha, augment, rng, loss, grad ? s->dalpha : NULL, st))
        return st->code;
    if (!grad) return WS_OK;
    t0 = ws_time_start(s->timing);
    if (grow_dmu(s, st) || ws_splat_backward(s->splat, s->dalpha, s->dmu, st)) return st->code;
    ws_time_add(s->timing, WS_TIME_SPLAT, t0);
    ws_curves_backward(c, &s->gaussians, s->dmu, s->dP);
    for (int i = 0; i < c->n * 12; i++) grad[i] += scale * s->dP[i];
    return WS_OK;
}

int ws_step_batch(ws_step *s, const ws_curves *c, const int *views, int nviews, ws_rng *rng,
                  double *loss, double *grad, ws_status *st) {
    memset(grad, 0, (size_t)c->n * 12 * sizeof(double));
    *loss = 0;
    int rc = ws_curves_sample(c, &s->gaussians, st);
    for (int k = 0; k < nviews && !rc; k++) {
        double l = NAN;
        rc = ws_step_view(s, c, WS_TRAIN, views[k], 1, rng, 1.0 / nviews, &l, grad, st);
        *loss += l / nviews;
    }
    return rc;
}
