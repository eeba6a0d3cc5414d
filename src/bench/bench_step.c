/* bench_step.c: where the time of a default training step goes, against
 * the GEMM floor of its CLIP work (bench.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fit/adam.h"
#include "bench/bench.h"
#include "bench/clip_bench.h"
#include "base/runtime.h"

/* The CLIP runs of a default step, for the floor: the 1 + A stroke images
 * with tape and the A augmented photos without. */
typedef struct {
    clip_run *strokes, *photos;
    float *images, *d_images;
} floor_runs;

static void floor_runs_free(floor_runs *f) {
    clip_run_free(f->strokes);
    clip_run_free(f->photos);
    free(f->images);
    free(f->d_images);
}

/* The runs, with one real forward and backward so that the floor's GEMMs
 * read the values a step's GEMMs read (not fresh pages of zeros). */
static int floor_runs_create(floor_runs *f, const clip_model *m, int A, ws_status *st) {
    memset(f, 0, sizeof *f);
    const wf_arch *a = clip_model_arch(m);
    size_t image = (size_t)3 * a->resolution * a->resolution;
    clip_run_options ro = {1 + A, a->layers - 1, 1, 1, 0};
    if (clip_run_create(&f->strokes, m, &ro, st)) return st->code;
    ro.batch = A;
    ro.need_grad = 0;
    if (clip_run_create(&f->photos, m, &ro, st)) return st->code;
    if (!(f->images = ws_malloc((1 + A) * image * sizeof(float), "benchmark images", st)) ||
        !(f->d_images = ws_malloc((1 + A) * image * sizeof(float), "benchmark images", st)))
        return st->code;
    for (size_t i = 0; i < (1 + A) * image; i++) f->images[i] = (float)((i * 2654435761u) % 1000) / 1000.0f;
    float *d_embedding = ws_calloc((size_t)(1 + A) * a->output_dim, sizeof(float), "benchmark seeds", st);
    if (!d_embedding) return st->code;
    for (int i = 0; i < (1 + A) * a->output_dim; i++) d_embedding[i] = 1e-3f * (float)(i % 7);
    int rc = clip_forward(f->strokes, f->images, st) || clip_forward(f->photos, f->images, st) ||
             clip_backward(f->strokes, NULL, NULL, d_embedding, f->d_images, st);
    free(d_embedding);
    return rc ? st->code : WS_OK;
}

int ws_bench_step(const ws_scene *scene, const clip_model *m, const ws_curves *c, int rounds,
                  ws_bench_step_result *res, ws_status *st) {
    memset(res, 0, sizeof *res);
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    lo.model = m;
    ws_splat_options so;
    ws_splat_options_default(&so);
    ws_objective *obj = NULL;
    ws_curves cur = {0};
    ws_adam adam = {0};
    floor_runs fr;
    memset(&fr, 0, sizeof fr);
    double *grad = NULL;
    int rc = ws_objective_create(&obj, scene, &lo, &so, c->n, st);
    if (!rc) rc = ws_bench_scaled(c, 1.0, scene->center, &cur, st);
    if (!rc) rc = ws_adam_init(&adam, c->n * WS_CURVE_FLOATS, 0.005, st);
    if (!rc) rc = floor_runs_create(&fr, m, lo.num_aug, st);
    if (!rc && !(grad = ws_calloc((size_t)c->n * WS_CURVE_FLOATS, sizeof(double), "gradient", st)))
        rc = st->code;
    if (rc) goto done;
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    ws_step_timing t;
    ws_objective_set_timing(obj, &t);
    res->best.seconds[WS_TIME_TOTAL] = INFINITY;
    res->floor_forward = res->floor_backward = res->floor_photo = INFINITY;
    const int view = 0;
    /* round -1 is not measured: it caches the view's photo features (once
     * per view in a fit) and pays the page faults of the buffers */
    for (int r = -1; r < rounds; r++) {
        memset(&t, 0, sizeof t);
        double loss, t0 = ws_seconds();
        if (ws_objective_batch(obj, &cur, &view, 1, &rng, &loss, grad, st)) goto fail;
        double t1 = ws_seconds();
        ws_adam_update(&adam, cur.P, grad);
        double t2 = ws_seconds();
        t.seconds[WS_TIME_OPTIMISER] = t2 - t1;
        t.seconds[WS_TIME_TOTAL] = t2 - t0;
        ws_clip_gemm_floor(fr.strokes, 0);
        double t3 = ws_seconds();
        ws_clip_gemm_floor(fr.strokes, 1);
        double t4 = ws_seconds();
        ws_clip_gemm_floor(fr.photos, 0);
        double t5 = ws_seconds();
        if (r < 0) continue;
        if (t.seconds[WS_TIME_TOTAL] < res->best.seconds[WS_TIME_TOTAL]) res->best = t;
        res->floor_forward = fmin(res->floor_forward, t3 - t2);
        res->floor_backward = fmin(res->floor_backward, t4 - t3);
        res->floor_photo = fmin(res->floor_photo, t5 - t4);
    }
    res->floor = res->floor_forward + res->floor_backward + res->floor_photo;
    res->gaussians = ws_objective_gaussians(obj)->n;
    res->curves = c->n;
    res->views = 1;
    res->num_aug = lo.num_aug;
    res->threads = ws_runtime_threads();
    goto done;
fail:
    rc = st->code;
done:
    free(grad);
    floor_runs_free(&fr);
    ws_adam_free(&adam);
    ws_curves_free(&cur);
    ws_objective_free(obj);
    return rc;
}
