/* objective.c: the loss of a sketch and its gradient (see objective.h).
 *
 * A batch, and the mean over a split, are spread over the ranks of an MPI
 * job by a unit plan (unit_plan.h): each rank computes its units, the owner
 * of a view sums the view's items (those of other ranks' passes reach it in
 * one exchange), adds the weight-free terms and carries dL/dalpha back to
 * the control points; then every rank receives every view's loss and
 * gradient and sums them in view order. Every rank draws every view's
 * transforms, in view order, from the same generator, so the bits are
 * those of one process for any number of ranks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "base/distributed.h"
#include "objective/hidden_lines.h"
#include "objective/objective.h"
#include "objective/silhouette_loss.h"
#include "objective/unit_plan.h"
#include "objective/view_targets.h"

struct ws_objective {
    const ws_scene *scene;
    ws_loss *loss;
    ws_silhouette_loss *silhouettes; /* the training views' term; NULL when its weight is 0 */
    ws_hidden_lines *hidden;  /* hidden-line removal; NULL: none */
    double silhouette_weight;
    ws_splat *splat;
    ws_splat_options splat_opt;
    ws_gaussians gaussians;   /* of the last sampling */
    double *alpha, *dalpha;   /* H x W */
    double *dmu;              /* gaussians x 3, grown with them */
    int dmu_cap;
    double *dP;               /* curves x WS_CURVE_FLOATS */
    int n_curves;
    int items;                /* a training view's CLIP items (loss.h) */
    double *item_loss;        /* 2 x items: the first view a rank touches, then the others */
    float *item_grad;         /* 2 x items x H x W, likewise */
    double *records;          /* views x (1 + curves x WS_CURVE_FLOATS): each view's loss and dL/dP */
    ws_unit_plan plan;        /* this rank's part of the batch or split at hand */
    size_t *xfer;             /* 8 x ranks: counts and offsets of an exchange */
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
    o->silhouette_weight = lo->silhouette_weight;
    const ws_silhouette *sil;
    if (o->silhouette_weight != 0 &&
        (ws_view_targets_silhouettes(ws_loss_targets(o->loss), WS_TRAIN, &sil, st) ||
         ws_silhouette_loss_create(&o->silhouettes, &scene->split[WS_TRAIN], sil, st)))
        return st->code;
    if (lo->hidden_lines == WS_HIDDEN_HULL && ws_hidden_lines_create(&o->hidden, scene, lo->hull, ws_loss_targets(o->loss), st))
        return st->code;
    if (!(o->alpha = ws_malloc(pixels * sizeof(double), "stroke image", st)) ||
        !(o->dalpha = ws_malloc(pixels * sizeof(double), "stroke gradient", st)) ||
        !(o->dP = ws_calloc((size_t)n_curves * WS_CURVE_FLOATS, sizeof(double), "control point gradient", st)))
        return st->code;
    int views = 1;
    for (int s = 0; s < WS_NSPLITS; s++) views = scene->split[s].n > views ? scene->split[s].n : views;
    o->items = ws_loss_items(o->loss, 1);
    size_t items = o->items ? (size_t)o->items : 1;
    if (!(o->item_loss = ws_malloc(2 * items * sizeof(double), "item losses", st)) ||
        !(o->item_grad = ws_malloc(2 * items * pixels * sizeof(float), "item gradients", st)) ||
        !(o->records = ws_malloc((size_t)views * (1 + (size_t)n_curves * WS_CURVE_FLOATS) * sizeof(double), "view gradients",
                                 st)) ||
        !(o->xfer = ws_malloc(8 * (size_t)ws_dist_size() * sizeof(size_t), "exchange counts", st)))
        return st->code;
    return ws_unit_plan_init(&o->plan, ws_dist_size(), ws_dist_rank(), st);
}

void ws_objective_free(ws_objective *o) {
    if (!o) return;
    ws_loss_free(o->loss);
    ws_silhouette_loss_free(o->silhouettes);
    ws_hidden_lines_free(o->hidden);
    ws_splat_free(o->splat);
    ws_gaussians_free(&o->gaussians);
    free(o->alpha);
    free(o->dalpha);
    free(o->dmu);
    free(o->dP);
    free(o->item_loss);
    free(o->item_grad);
    free(o->records);
    ws_unit_plan_free(&o->plan);
    free(o->xfer);
    free(o);
}

void ws_objective_set_timing(ws_objective *o, ws_step_timing *t) {
    o->timing = t;
    ws_loss_set_timing(o->loss, t);
}

void ws_objective_set_cutoff(ws_objective *o, double cutoff) { o->splat_opt.cutoff = cutoff; }

void ws_objective_set_progress(ws_objective *o, double progress) { ws_loss_set_progress(o->loss, progress); }

const ws_gaussians *ws_objective_gaussians(const ws_objective *o) { return &o->gaussians; }

const ws_loss *ws_objective_loss(const ws_objective *o) { return o->loss; }

int ws_objective_sample(ws_objective *o, const ws_curves *c, ws_status *st) {
    if (c->n > o->n_curves)
        return ws_fail(st, WS_EINTERNAL, "objective: %d curves in one made for at most %d", c->n, o->n_curves);
    return ws_curves_sample(c, &o->gaussians, st);
}

/* The capacity only once the buffer is there: after a failed allocation the
 * next call tries again instead of writing through NULL. */
static int grow_dmu(ws_objective *o, ws_status *st) {
    if (o->gaussians.n <= o->dmu_cap) return WS_OK;
    free(o->dmu);
    o->dmu_cap = 0;
    o->dmu = ws_malloc((size_t)o->gaussians.n * 2 * 3 * sizeof(double), "Gaussian gradients", st);
    if (!o->dmu) return st->code;
    o->dmu_cap = o->gaussians.n * 2;
    return WS_OK;
}

static int splat_view(ws_objective *o, const ws_curves *c, int split, int view, ws_status *st) {
    double t0 = ws_time_start(o->timing);
    if (o->hidden && ws_hidden_lines_far(o->hidden, split, view, &o->splat_opt.far, st)) return st->code;
    if (ws_splat_forward(o->splat, &o->scene->split[split].views[view].cam, o->gaussians.mu, o->gaussians.n,
                         c->thickness, &o->splat_opt, o->alpha, st))
        return st->code;
    ws_time_add(o->timing, WS_TIME_SPLAT, t0);
    return WS_OK;
}

/* dL/dP (into o->dP) for dL/dalpha in o->dalpha, through the splatting of
 * the view splatted last. */
static int backward(ws_objective *o, const ws_curves *c, ws_status *st) {
    double t0 = ws_time_start(o->timing);
    if (grow_dmu(o, st) || ws_splat_backward(o->splat, o->dalpha, o->dmu, st)) return st->code;
    ws_time_add(o->timing, WS_TIME_SPLAT, t0);
    ws_curves_backward(c, &o->gaussians, o->dmu, o->dP);
    return WS_OK;
}

/* ws_objective_view for the Gaussians of the last sampling of c. */
static int sampled_view(ws_objective *o, const ws_curves *c, int split, int view, int augment, ws_rng *rng,
                        double scale, double *loss, double *grad, ws_status *st) {
    if (splat_view(o, c, split, view, st) ||
        ws_loss_view(o->loss, split, view, o->alpha, augment, rng, loss, grad ? o->dalpha : NULL, st) ||
        (grad && backward(o, c, st)))
        return st->code;
    for (int i = 0; grad && i < c->n * WS_CURVE_FLOATS; i++) grad[i] += scale * o->dP[i];
    return WS_OK;
}

int ws_objective_view(ws_objective *o, const ws_curves *c, int split, int view, int augment, ws_rng *rng,
                      double scale, double *loss, double *grad, ws_status *st) {
    if (ws_objective_sample(o, c, st)) return st->code;
    return sampled_view(o, c, split, view, augment, rng, scale, loss, grad, st);
}

/* Combines the items of a training view that this rank owns and has
 * splatted last into its record: the loss, then dL/dP (NaN loss and a zero
 * gradient when the loss is not finite). */
static int finish_view(ws_objective *o, const ws_curves *c, int view, const double *item_loss,
                       const float *item_grad, double *record, ws_status *st) {
    int np = c->n * WS_CURVE_FLOATS;
    int rc = ws_loss_combine(o->loss, WS_TRAIN, view, o->alpha, 1, item_loss, item_grad, &record[0], o->dalpha,
                             st);
    if (rc == WS_ENUMERIC) {
        ws_status_clear(st);
        record[0] = NAN;
        memset(record + 1, 0, np * sizeof(double));
        return WS_OK;
    }
    if (rc || backward(o, c, st)) return st->code;
    memcpy(record + 1, o->dP, np * sizeof(double));
    return WS_OK;
}

/* The items of passes r of a view, as byte counts and offsets of its item
 * losses and gradients. */
static void item_bytes(const ws_objective *o, ws_pass_range r, size_t *loss_bytes, size_t *loss_off,
                       size_t *grad_bytes, size_t *grad_off) {
    size_t pixels = (size_t)o->scene->width * o->scene->height;
    int first, count, last_first, last_count;
    ws_loss_pass_items(o->loss, 1, r.begin, &first, &count);
    ws_loss_pass_items(o->loss, 1, r.end - 1, &last_first, &last_count);
    size_t items = (size_t)(last_first + last_count - first);
    *loss_bytes = items * sizeof(double);
    *loss_off = (size_t)first * sizeof(double);
    *grad_bytes = items * pixels * sizeof(float);
    *grad_off = (size_t)first * pixels * sizeof(float);
}

/* Sends the items this rank computed of the plan's send_view to its owner
 * and receives those of its recv_view from the ranks that computed them,
 * each in its item slot (unit_plan.h). */
static void exchange_items(ws_objective *o) {
    const ws_unit_plan *p = &o->plan;
    int N = p->ranks, n = o->items;
    size_t pixels = (size_t)o->scene->width * o->scene->height;
    size_t *sb = o->xfer, *so = sb + N, *rb = so + N, *ro = rb + N;
    size_t *gsb = ro + N, *gso = gsb + N, *grb = gso + N, *gro = grb + N;
    memset(o->xfer, 0, 8 * (size_t)N * sizeof(size_t));
    double none_loss;
    float none_grad;
    double *loss_base[2] = {&none_loss, &none_loss};
    float *grad_base[2] = {&none_grad, &none_grad};
    int view[2] = {p->send_view, p->recv_view};
    for (int side = 0; side < 2; side++) {
        if (view[side] < 0) continue;
        int slot = ws_unit_plan_slot(p, view[side]);
        loss_base[side] = o->item_loss + (size_t)slot * n;
        grad_base[side] = o->item_grad + (size_t)slot * n * pixels;
    }
    if (p->send_view >= 0) item_bytes(o, p->send, &sb[p->send_to], &so[p->send_to], &gsb[p->send_to], &gso[p->send_to]);
    for (int r = 0; p->recv_view >= 0 && r < N; r++)
        if (p->recv[r].begin < p->recv[r].end) item_bytes(o, p->recv[r], &rb[r], &ro[r], &grb[r], &gro[r]);
    ws_dist_exchange(loss_base[0], sb, so, loss_base[1], rb, ro);
    ws_dist_exchange(grad_base[0], gsb, gso, grad_base[1], grb, gro);
}

/* Every rank's records of the views it owns under the plan, in view order,
 * to every rank. */
static void share_records(ws_objective *o, size_t record) {
    const ws_unit_plan *p = &o->plan;
    if (p->ranks == 1) return;
    size_t *bytes = o->xfer;
    memset(bytes, 0, (size_t)p->ranks * sizeof(size_t));
    for (int k = 0; k < p->views; k++) bytes[ws_unit_plan_owner(p, k)] += record * sizeof(double);
    ws_dist_allgather(o->records, bytes);
}

/* Adds the silhouette term (silhouette_loss.h) of the last sampling over
 * the part of the batch's first view, its weight times, to a batch's loss
 * and gradient. Every rank computes it whole (it is cheap beside a view's
 * loss), with the same bits. */
static int add_silhouette_term(ws_objective *o, const ws_curves *c, int part, double *loss, double *grad,
                               ws_status *st) {
    const ws_gaussians *g = &o->gaussians;
    double term;
    if (ws_silhouette_loss_forward(o->silhouettes, g->mu, g->n, part, &term, st) || grow_dmu(o, st))
        return ws_dist_fail_alone(st);
    *loss += o->silhouette_weight * term;
    ws_silhouette_loss_backward(o->silhouettes, o->silhouette_weight, o->dmu);
    ws_curves_backward(c, g, o->dmu, o->dP);
    for (int i = 0; i < c->n * WS_CURVE_FLOATS; i++) grad[i] += o->dP[i];
    return WS_OK;
}

/* Splats training view `view` and computes its passes r into item slot
 * `slot`. */
static int compute_passes(ws_objective *o, const ws_curves *c, int view, ws_pass_range r, int slot,
                          ws_status *st) {
    size_t pixels = (size_t)o->scene->width * o->scene->height;
    double *il = o->item_loss + (size_t)slot * o->items;
    float *ig = o->item_grad + (size_t)slot * o->items * pixels;
    if (splat_view(o, c, WS_TRAIN, view, st)) return st->code;
    for (int pass = r.begin; pass < r.end; pass++) {
        int first, count;
        ws_loss_pass_items(o->loss, 1, pass, &first, &count);
        if (ws_loss_pass(o->loss, WS_TRAIN, view, o->alpha, 1, pass, il + first, ig + first * pixels, st))
            return st->code;
    }
    return WS_OK;
}

/* finish_view of batch view k from its item slot, into its record. */
static int finish_slot(ws_objective *o, const ws_curves *c, const int *views, int k, ws_status *st) {
    size_t pixels = (size_t)o->scene->width * o->scene->height, record = 1 + (size_t)c->n * WS_CURVE_FLOATS;
    int slot = ws_unit_plan_slot(&o->plan, k);
    return finish_view(o, c, views[k], o->item_loss + (size_t)slot * o->items,
                       o->item_grad + (size_t)slot * o->items * pixels, o->records + k * record, st);
}

int ws_objective_batch(ws_objective *o, const ws_curves *c, const int *views, int nviews, ws_rng *rng,
                       double *loss, double *grad, ws_status *st) {
    const ws_unit_plan *p = &o->plan;
    int np = c->n * WS_CURVE_FLOATS;
    size_t record = 1 + (size_t)np;
    memset(grad, 0, (size_t)np * sizeof(double));
    *loss = 0;
    if (ws_objective_sample(o, c, st)) return st->code;
    ws_unit_plan_make(&o->plan, nviews, ws_loss_passes(o->loss, 1));
    for (int k = 0; k < nviews; k++) {
        if (ws_loss_draw(o->loss, WS_TRAIN, views[k], rng, st)) return ws_dist_fail_alone(st);
        ws_pass_range r = ws_unit_plan_computes(p, k);
        if (r.begin >= r.end) continue;
        if (compute_passes(o, c, views[k], r, ws_unit_plan_slot(p, k), st) ||
            (k != p->send_view && k != p->recv_view && finish_slot(o, c, views, k, st)))
            return ws_dist_fail_alone(st);
    }
    if (p->ranks > 1) exchange_items(o);
    if (p->recv_view >= 0 && finish_slot(o, c, views, p->recv_view, st)) return ws_dist_fail_alone(st);
    share_records(o, record);
    for (int k = 0; k < nviews; k++) {
        const double *r = o->records + k * record;
        if (!isfinite(r[0]))
            return ws_fail(st, WS_ENUMERIC, "loss of %s view %s is not finite", ws_split_names[WS_TRAIN],
                           o->scene->split[WS_TRAIN].views[views[k]].name);
        *loss += r[0] / nviews;
        for (int i = 0; i < np; i++) grad[i] += (1.0 / nviews) * r[1 + i];
    }
    return o->silhouettes && nviews > 0 ? add_silhouette_term(o, c, views[0], loss, grad, st) : WS_OK;
}

int ws_objective_split_mean(ws_objective *o, const ws_curves *c, int split, double *per_view, double *mean,
                            ws_status *st) {
    const ws_split *sp = &o->scene->split[split];
    *mean = NAN;
    if (ws_objective_sample(o, c, st)) return st->code;
    if (sp->n == 0) return WS_OK;
    ws_unit_plan_make(&o->plan, sp->n, 1);
    for (long v = o->plan.lo; v < o->plan.hi; v++) {
        int rc = sampled_view(o, c, split, (int)v, 0, NULL, 0, &o->records[v], NULL, st);
        if (rc == WS_ENUMERIC) {
            ws_status_clear(st);
            o->records[v] = NAN;
        } else if (rc) {
            return ws_dist_fail_alone(st);
        }
    }
    share_records(o, 1);
    double sum = 0;
    for (int v = 0; v < sp->n; v++) {
        if (!isfinite(o->records[v]))
            return ws_fail(st, WS_ENUMERIC, "loss of %s view %s is not finite", ws_split_names[split],
                           sp->views[v].name);
        if (per_view) per_view[v] = o->records[v];
        sum += o->records[v];
    }
    *mean = sum / sp->n;
    return WS_OK;
}
