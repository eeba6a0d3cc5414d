/* objective.c: the loss of a sketch and its gradient (see objective.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "objective/objective.h"

struct ws_objective {
    const ws_scene *scene;
    ws_loss *loss;
    ws_splat *splat;
    ws_splat_options splat_opt;
    ws_gaussians gaussians;   /* of the last sampling */
    double *alpha, *dalpha;   /* H x W */
    double *dmu;              /* gaussians x 3, grown with them */
    int dmu_cap;
    double *dP;               /* curves x WS_CURVE_FLOATS */
    int n_curves;
    ws_step_timing *timing;   /* NULL: no clock is read */
};

int ws_objective_create(ws_objective **obj, const ws_scene *scene, const ws_loss_options *lo,
                        const ws_splat_options *so, int n_curves, ws_status *st) {
    ws_objective *o = *obj = ws_calloc(1, sizeof *o, "objective", st);
    if (!o) return st->code;
    o->scene = scene;
    o->splat_opt = *so;
    o->n_curves = n_curves;
    size_t pixels = (size_t)scene->width * scene->height;
    if (ws_loss_create(&o->loss, lo, scene, st) ||
        ws_splat_create(&o->splat, scene->width, scene->height, st))
        return st->code;
    if (!(o->alpha = ws_malloc(pixels * sizeof(double), "stroke image", st)) ||
        !(o->dalpha = ws_malloc(pixels * sizeof(double), "stroke gradient", st)) ||
        !(o->dP = ws_calloc((size_t)n_curves * WS_CURVE_FLOATS, sizeof(double), "control point gradient", st)))
        return st->code;
    return WS_OK;
}

void ws_objective_free(ws_objective *o) {
    if (!o) return;
    ws_loss_free(o->loss);
    ws_splat_free(o->splat);
    ws_gaussians_free(&o->gaussians);
    free(o->alpha);
    free(o->dalpha);
    free(o->dmu);
    free(o->dP);
    free(o);
}

void ws_objective_set_timing(ws_objective *o, ws_step_timing *t) {
    o->timing = t;
    ws_loss_set_timing(o->loss, t);
}

void ws_objective_set_cutoff(ws_objective *o, double cutoff) { o->splat_opt.cutoff = cutoff; }

const ws_gaussians *ws_objective_gaussians(const ws_objective *o) { return &o->gaussians; }

const ws_loss *ws_objective_loss(const ws_objective *o) { return o->loss; }

int ws_objective_sample(ws_objective *o, const ws_curves *c, ws_status *st) {
    if (c->n != o->n_curves)
        return ws_fail(st, WS_EINTERNAL, "objective: %d curves in one made for %d", c->n, o->n_curves);
    return ws_curves_sample(c, &o->gaussians, st);
}

static int grow_dmu(ws_objective *o, ws_status *st) {
    if (o->gaussians.n <= o->dmu_cap) return WS_OK;
    free(o->dmu);
    o->dmu_cap = o->gaussians.n * 2;
    o->dmu = ws_malloc((size_t)o->dmu_cap * 3 * sizeof(double), "Gaussian gradients", st);
    return o->dmu ? WS_OK : st->code;
}

/* ws_objective_view for the Gaussians of the last sampling of c. */
static int sampled_view(ws_objective *o, const ws_curves *c, int split, int view, int augment, ws_rng *rng,
                        double scale, double *loss, double *grad, ws_status *st) {
    const ws_view *v = &o->scene->split[split].views[view];
    double t0 = ws_time_start(o->timing);
    if (ws_splat_forward(o->splat, &v->cam, o->gaussians.mu, o->gaussians.n, c->thickness, &o->splat_opt,
                         o->alpha, st))
        return st->code;
    ws_time_add(o->timing, WS_TIME_SPLAT, t0);
    if (ws_loss_view(o->loss, split, view, o->alpha, augment, rng, loss, grad ? o->dalpha : NULL, st))
        return st->code;
    if (!grad) return WS_OK;
    t0 = ws_time_start(o->timing);
    if (grow_dmu(o, st) || ws_splat_backward(o->splat, o->dalpha, o->dmu, st)) return st->code;
    ws_time_add(o->timing, WS_TIME_SPLAT, t0);
    ws_curves_backward(c, &o->gaussians, o->dmu, o->dP);
    for (int i = 0; i < c->n * WS_CURVE_FLOATS; i++) grad[i] += scale * o->dP[i];
    return WS_OK;
}

int ws_objective_view(ws_objective *o, const ws_curves *c, int split, int view, int augment, ws_rng *rng,
                      double scale, double *loss, double *grad, ws_status *st) {
    if (ws_objective_sample(o, c, st)) return st->code;
    return sampled_view(o, c, split, view, augment, rng, scale, loss, grad, st);
}

int ws_objective_batch(ws_objective *o, const ws_curves *c, const int *views, int nviews, ws_rng *rng,
                       double *loss, double *grad, ws_status *st) {
    memset(grad, 0, (size_t)c->n * WS_CURVE_FLOATS * sizeof(double));
    *loss = 0;
    int rc = ws_objective_sample(o, c, st);
    for (int k = 0; k < nviews && !rc; k++) {
        double l = NAN;
        rc = sampled_view(o, c, WS_TRAIN, views[k], 1, rng, 1.0 / nviews, &l, grad, st);
        *loss += l / nviews;
    }
    return rc;
}

int ws_objective_split_mean(ws_objective *o, const ws_curves *c, int split, double *per_view, double *mean,
                            ws_status *st) {
    const ws_split *sp = &o->scene->split[split];
    *mean = NAN;
    if (ws_objective_sample(o, c, st)) return st->code;
    if (sp->n == 0) return WS_OK;
    double sum = 0;
    for (int v = 0; v < sp->n; v++) {
        double l;
        if (sampled_view(o, c, split, v, 0, NULL, 0, &l, NULL, st)) return st->code;
        if (per_view) per_view[v] = l;
        sum += l;
    }
    *mean = sum / sp->n;
    return WS_OK;
}
