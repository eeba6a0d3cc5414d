/* bench_approx.c: error against run time of every approximation that buys
 * speed (bench.h, METHOD.md section 7).
 *
 * A row compares two settings of the same step on the same inputs: the
 * same sketch, training view 0, the same augmentation transforms (the rng
 * restored before each run). Both settings run in alternation, `rounds`
 * times after one unmeasured run each (which also fills the caches a fit
 * fills once per view); times are the fastest run's. Errors are relative:
 * |L - L_exact| / |L_exact| and |g - g_exact| / |g_exact| over all control
 * points' gradient components (2-norms). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "bench/bench.h"
#include "base/runtime.h"

/* One setting: an objective, the cut-off its splatting uses, a thread
 * count (0: leave as it is) and the training view. */
typedef struct {
    ws_objective *objective;
    const ws_curves *curves;
    double cutoff;
    int threads;
    int view;
    uint64_t seed;  /* the step's generator (augmentations); 0: the row's common one */
} setting;

/* What a setting's fastest run measured. */
typedef struct {
    double loss;
    double *grad;          /* curves x WS_CURVE_FLOATS */
    ws_step_timing best;
} outcome;

/* Parts of the step, as bits of ws_step_timing slots. */
enum {
    PART_SPLAT = 1 << WS_TIME_SPLAT,
    PART_CLIP = 1 << WS_TIME_CLIP_FORWARD | 1 << WS_TIME_CLIP_PHOTO | 1 << WS_TIME_CLIP_BACKWARD,
    PART_PHOTO = 1 << WS_TIME_AUGMENT | 1 << WS_TIME_CLIP_PHOTO,
    PART_STEP = 1 << WS_TIME_TOTAL
};

static double part_seconds(const ws_step_timing *t, int part) {
    double s = 0;
    for (int k = 0; k < WS_TIME_PARTS; k++)
        if (part & 1 << k) s += t->seconds[k];
    return s;
}

static int run(const setting *s, const ws_rng *rng0, outcome *o, int measured, ws_status *st) {
    ws_objective_set_cutoff(s->objective, s->cutoff);
    if (s->threads && ws_runtime_init(s->threads, st)) return st->code;
    ws_rng rng = *rng0;
    ws_step_timing t;
    memset(&t, 0, sizeof t);
    ws_objective_set_timing(s->objective, &t);
    double t0 = ws_seconds();
    int rc = ws_objective_batch(s->objective, s->curves, &s->view, 1, &rng, &o->loss, o->grad, st);
    t.seconds[WS_TIME_TOTAL] = ws_seconds() - t0;
    ws_objective_set_timing(s->objective, NULL);
    if (rc) return rc;
    if (measured && t.seconds[WS_TIME_TOTAL] < o->best.seconds[WS_TIME_TOTAL]) o->best = t;
    return WS_OK;
}

static double relative(double a, double b) { return fabs(a - b) / fmax(fabs(b), 1e-300); }

static double relative_norm(const double *a, const double *b, int n) {
    double diff = 0, ref = 0;
    for (int i = 0; i < n; i++) {
        diff += (a[i] - b[i]) * (a[i] - b[i]);
        ref += b[i] * b[i];
    }
    return sqrt(diff) / fmax(sqrt(ref), 1e-300);
}

enum { MAX_SETTINGS = 8, COMMON_SEED = 21 };

/* Runs settings s[0..n) in alternation, s[0] the exact one, and fills
 * rows[k - 1] for each s[k], k >= 1: errors (unless compare is 0) and the
 * times of `part` and of the whole step. */
static int measure(const setting *s, int n, int rounds, int part, int compare,
                   ws_bench_approx_row *const *rows, ws_status *st) {
    int np = s[0].curves->n * WS_CURVE_FLOATS, rc = WS_OK;
    outcome o[MAX_SETTINGS];
    memset(o, 0, sizeof o);
    for (int k = 0; k < n && !rc; k++) {
        o[k].best.seconds[WS_TIME_TOTAL] = INFINITY;
        if (!(o[k].grad = ws_malloc((size_t)np * sizeof(double), "gradient", st))) rc = st->code;
    }
    ws_rng rng[MAX_SETTINGS];
    for (int k = 0; k < n; k++) ws_rng_seed(&rng[k], s[k].seed ? s[k].seed : COMMON_SEED);
    for (int r = -1; r < rounds && !rc; r++)
        for (int k = 0; k < n && !rc; k++) rc = run(&s[k], &rng[k], &o[k], r >= 0, st);
    for (int k = 1; k < n && !rc; k++) {
        ws_bench_approx_row *row = rows[k - 1];
        row->loss_error = compare ? relative(o[k].loss, o[0].loss) : NAN;
        row->grad_error = compare ? relative_norm(o[k].grad, o[0].grad, np) : NAN;
        row->part_exact = part_seconds(&o[0].best, part);
        row->part_approx = part_seconds(&o[k].best, part);
        row->step_exact = o[0].best.seconds[WS_TIME_TOTAL];
        row->step_approx = o[k].best.seconds[WS_TIME_TOTAL];
    }
    for (int k = 0; k < n; k++) free(o[k].grad);
    return rc;
}

/* A row with its labels; the measurement fills the numbers. */
static ws_bench_approx_row *new_row(ws_bench_approx_row *rows, int max, int *n, const char *name,
                                    const char *exact, const char *part, ws_status *st) {
    if (*n >= max) {
        ws_fail(st, WS_EINTERNAL, "bench: more than %d approximation rows", max);
        return NULL;
    }
    ws_bench_approx_row *r = &rows[(*n)++];
    memset(r, 0, sizeof *r);
    snprintf(r->name, sizeof r->name, "%s", name);
    snprintf(r->exact, sizeof r->exact, "%s", exact);
    snprintf(r->part, sizeof r->part, "%s", part);
    return r;
}

/* The default loss with model m and the given changes. */
static ws_loss_options loss_options(const clip_model *m, int num_aug, int aug_bank, int clip_embedding) {
    ws_loss_options lo;
    ws_loss_options_default(&lo);
    lo.model = m;
    lo.num_aug = num_aug;
    lo.aug_bank = aug_bank;
    lo.aug_seed = 5;
    if (!clip_embedding) lo.fc_weight = lo.global_weight = 0;
    return lo;
}

static int step_for(ws_objective **s, const ws_bench_approx_input *in, const ws_loss_options *lo,
                    ws_status *st) {
    ws_splat_options so;
    ws_splat_options_default(&so);
    return ws_objective_create(s, in->scene, lo, &so, in->sketch->n, st);
}

/* The view's camera shifted sideways (along its x axis) by `share` of the
 * view's half width at the scene centre: moves a sketch partly out of view. */
static void sideways(const ws_scene *scene, double share, double shift[3]) {
    const ws_camera *cam = &scene->split[WS_TRAIN].views[0].cam;
    double c[3];
    ws_camera_to_cam(cam, scene->center, c);
    double half_width = -c[2] * 0.5 * cam->width / cam->focal;
    for (int x = 0; x < 3; x++) shift[x] = share * half_width * cam->R[0][x];
}

/* Rows: the splatting cut-off at 2..5 sigma against the exact sum; and
 * culling: a sketch three times larger, moved half out of the view, at 4
 * sigma against the exact sum (every Gaussian outside costs nothing). */
static int cutoff_rows(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                       ws_status *st) {
    ws_objective *s = NULL;
    ws_loss_options lo = loss_options(in->model, 4, 0, 1);
    ws_curves big = {0};
    int rc = step_for(&s, in, &lo, st);
    if (!rc) rc = ws_bench_scaled(in->sketch, 3.0, in->scene->center, &big, st);
    setting set[WS_BENCH_CUTOFFS];
    ws_bench_approx_row *row[WS_BENCH_CUTOFFS];
    set[0] = (setting){s, in->sketch, INFINITY, 0, 0, 0};
    for (int k = 1; k < WS_BENCH_CUTOFFS && !rc; k++) {
        set[k] = set[0];
        set[k].cutoff = ws_bench_cutoffs[k - 1];
        if (!(row[k - 1] = new_row(rows, max, n, "cutoff", "exact sum", "splat", st))) rc = st->code;
        else snprintf(row[k - 1]->setting, sizeof row[k - 1]->setting, "%g sigma", set[k].cutoff);
    }
    if (!rc) rc = measure(set, WS_BENCH_CUTOFFS, in->rounds, PART_SPLAT, 1, row, st);
    if (!rc && !(row[0] = new_row(rows, max, n, "culling", "exact sum", "splat", st))) rc = st->code;
    if (!rc) {
        double shift[3];
        sideways(in->scene, 1.0, shift);
        for (int i = 0; i < big.n * WS_CURVE_FLOATS; i++) big.P[i] += shift[i % 3];
        set[0].curves = set[1].curves = &big;
        set[1].cutoff = 4;
        rc = measure(set, 2, in->rounds, PART_SPLAT, 1, row, st);
    }
    if (!rc) {
        int drawn;
        const ws_gaussians *g = ws_objective_gaussians(s);
        ws_bench_pixel_visits(&in->scene->split[WS_TRAIN].views[0].cam, g->mu, g->n, big.thickness, 4,
                              &drawn);
        snprintf(row[0]->setting, sizeof row[0]->setting, "4 sigma, half out of view");
        snprintf(row[0]->note, sizeof row[0]->note,
                 "a sketch 3x larger, moved sideways: %d of its %d Gaussians are outside the view",
                 g->n - drawn, g->n);
    }
    ws_curves_free(&big);
    ws_objective_free(s);
    return rc;
}

/* Row: the CLIP forward stops after the last block the loss reads (blocks
 * 2 and 3 when the fc and global weights are 0) instead of running all 12.
 * Compared at CLIP level (the loss cannot be asked to run blocks it does
 * not read): the stroke images forward and backward and the photos
 * forward; the step's times are the stopped step as measured and that step
 * plus the blocks it leaves out. */
static int clip_stop_row(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                         ws_status *st) {
    const wf_arch *a = clip_model_arch(in->model);
    const int A = 4, blocks[2] = {2, 3};
    if (a->layers <= blocks[1] + 1) return WS_OK; /* nothing to leave out */
    ws_bench_approx_row *row = new_row(rows, max, n, "clip_stop", "all blocks", "clip", st);
    if (!row) return st->code;
    snprintf(row->setting, sizeof row->setting, "stop after block %d", blocks[1]);
    int tokens = 1 + (a->resolution / a->patch) * (a->resolution / a->patch);
    size_t image = (size_t)3 * a->resolution * a->resolution, hidden = (size_t)(1 + A) * tokens * a->width;
    clip_run *strokes[2] = {NULL, NULL}, *photos[2] = {NULL, NULL};
    float *images = NULL, *d_images = NULL, *seeds = NULL;
    const float **d_hidden = ws_calloc((size_t)a->layers, sizeof *d_hidden, "benchmark seeds", st);
    int rc = d_hidden ? WS_OK : st->code;
    for (int k = 0; k < 2 && !rc; k++) {
        int last = k ? blocks[1] : a->layers - 1;
        clip_run_options ro = {1 + A, last, 0, 1, 0};
        rc = clip_run_create(&strokes[k], in->model, &ro, st);
        ro.batch = A;
        ro.need_grad = 0;
        if (!rc) rc = clip_run_create(&photos[k], in->model, &ro, st);
    }
    if (!rc && (!(images = ws_malloc((1 + A) * image * sizeof(float), "benchmark images", st)) ||
                !(d_images = ws_malloc(2 * (1 + A) * image * sizeof(float), "benchmark images", st)) ||
                !(seeds = ws_malloc(2 * hidden * sizeof(float), "benchmark seeds", st))))
        rc = st->code;
    if (!rc) {
        ws_rng rng;
        ws_rng_seed(&rng, 4);
        for (size_t i = 0; i < (1 + A) * image; i++) images[i] = (float)ws_rng_uniform(&rng);
        for (size_t i = 0; i < 2 * hidden; i++) seeds[i] = (float)(1e-3 * (2 * ws_rng_uniform(&rng) - 1));
        d_hidden[blocks[0]] = seeds;
        d_hidden[blocks[1]] = seeds + hidden;
        double best[2] = {INFINITY, INFINITY};
        for (int r = -1; r < in->rounds && !rc; r++)
            for (int k = 0; k < 2 && !rc; k++) {
                double t0 = ws_seconds();
                if (clip_forward(strokes[k], images, st) || clip_forward(photos[k], images, st) ||
                    clip_backward(strokes[k], d_hidden, NULL, NULL, d_images + k * (1 + A) * image, st)) {
                    rc = st->code;
                    break;
                }
                if (r >= 0) best[k] = fmin(best[k], ws_seconds() - t0);
            }
        if (!rc) {
            double fdiff = 0, fref = 0, gdiff = 0, gref = 0;
            for (int b = 0; b < 2; b++) {
                const float *h0 = clip_hidden(strokes[0], blocks[b]), *h1 = clip_hidden(strokes[1], blocks[b]);
                for (size_t i = 0; i < hidden; i++) {
                    fdiff += ((double)h1[i] - h0[i]) * ((double)h1[i] - h0[i]);
                    fref += (double)h0[i] * h0[i];
                }
            }
            for (size_t i = 0; i < (1 + A) * image; i++) {
                double g0 = d_images[i], g1 = d_images[(1 + A) * image + i];
                gdiff += (g1 - g0) * (g1 - g0);
                gref += g0 * g0;
            }
            row->loss_error = sqrt(fdiff / fmax(fref, 1e-300));
            row->grad_error = sqrt(gdiff / fmax(gref, 1e-300));
            row->part_exact = best[0];
            row->part_approx = best[1];
            snprintf(row->note, sizeof row->note,
                     "errors: of the block outputs the loss reads and of the image gradient");
        }
    }
    /* the stopped step as the loss runs it (fc and global weights 0) */
    if (!rc) {
        ws_objective *s = NULL;
        ws_loss_options lo = loss_options(in->model, A, 0, 0);
        rc = step_for(&s, in, &lo, st);
        ws_bench_approx_row timing, *timed = &timing;
        setting stopped[2] = {{s, in->sketch, 4, 0, 0, 0}, {s, in->sketch, 4, 0, 0, 0}};
        if (!rc) rc = measure(stopped, 2, in->rounds, PART_STEP, 0, &timed, st);
        ws_objective_free(s);
        row->step_approx = timing.step_approx;
        /* Stopping early never adds work: on a loaded machine the two
         * CLIP timings can cross, and a negative saving is noise. */
        row->step_exact = timing.step_approx + fmax(0.0, row->part_exact - row->part_approx);
    }
    for (int k = 0; k < 2; k++) {
        clip_run_free(strokes[k]);
        clip_run_free(photos[k]);
    }
    free(d_hidden);
    free(images);
    free(d_images);
    free(seeds);
    return rc;
}

/* Row: the unaugmented photo's features computed once per view instead of
 * every step: the first step on a view (cold) against the next (warm). */
static int photo_cache_row(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                           ws_status *st) {
    ws_bench_approx_row *row = new_row(rows, max, n, "photo_cache", "computed every step", "clip_photo", st);
    if (!row) return st->code;
    snprintf(row->setting, sizeof row->setting, "once per view");
    ws_objective *s = NULL;
    ws_loss_options lo = loss_options(in->model, 4, 0, 1);
    int rc = step_for(&s, in, &lo, st), np = in->sketch->n * WS_CURVE_FLOATS;
    outcome o[2];
    memset(o, 0, sizeof o);
    for (int k = 0; k < 2 && !rc; k++) {
        o[k].best.seconds[WS_TIME_TOTAL] = INFINITY;
        if (!(o[k].grad = ws_malloc((size_t)np * sizeof(double), "gradient", st))) rc = st->code;
    }
    ws_rng rng0;
    ws_rng_seed(&rng0, 21);
    double worst_loss = 0, worst_grad = 0;
    /* a fresh view every round: its first step computes the features */
    for (int r = 0; r < in->rounds && r + 1 < in->scene->split[WS_TRAIN].n && !rc; r++) {
        setting v = {s, in->sketch, 4, 0, r + 1, 0};
        rc = run(&v, &rng0, &o[0], 1, st) || run(&v, &rng0, &o[1], 1, st) ? st->code : WS_OK;
        worst_loss = fmax(worst_loss, relative(o[1].loss, o[0].loss));
        worst_grad = fmax(worst_grad, relative_norm(o[1].grad, o[0].grad, np));
    }
    if (!rc) {
        row->loss_error = worst_loss;
        row->grad_error = worst_grad;
        row->part_exact = o[0].best.seconds[WS_TIME_CLIP_PHOTO];
        row->part_approx = o[1].best.seconds[WS_TIME_CLIP_PHOTO];
        row->step_exact = o[0].best.seconds[WS_TIME_TOTAL];
        row->step_approx = o[1].best.seconds[WS_TIME_TOTAL];
    }
    free(o[0].grad);
    free(o[1].grad);
    ws_objective_free(s);
    return rc;
}

/* Row: an augmentation bank of N transforms per view, the photo's features
 * under them computed once, against fresh transforms every step. */
static int aug_bank_row(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                        ws_status *st) {
    ws_bench_approx_row *row = new_row(rows, max, n, "aug_bank", "fresh transforms", "photo", st);
    if (!row) return st->code;
    snprintf(row->setting, sizeof row->setting, "%d per view", in->aug_bank);
    ws_objective *fresh = NULL, *banked = NULL;
    ws_loss_options lo = loss_options(in->model, 4, 0, 1), lb = loss_options(in->model, 4, in->aug_bank, 1);
    int rc = step_for(&fresh, in, &lo, st);
    if (!rc) rc = step_for(&banked, in, &lb, st);
    setting set[2] = {{fresh, in->sketch, 4, 0, 0, 0}, {banked, in->sketch, 4, 0, 0, 0}};
    /* the first, unmeasured run of `measure` fills the view's bank */
    if (!rc) rc = measure(set, 2, in->rounds, PART_PHOTO, 0, &row, st);
    if (!rc) {
        row->bytes = (double)ws_loss_bank_bytes(ws_objective_loss(banked));
        snprintf(row->note, sizeof row->note,
                 "other transforms, so no error is defined: a view sees %d transforms, not fresh ones; "
                 "filling a view's bank costs %d photo forwards of %d images, once",
                 in->aug_bank, (in->aug_bank + 3) / 4, 4);
    }
    ws_objective_free(banked);
    ws_objective_free(fresh);
    return rc;
}

/* Row: weights stored as f16 (widened to f32 when loaded) against the same
 * weights as f32. */
static int f16_row(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                   ws_status *st) {
    ws_bench_approx_row *row = new_row(rows, max, n, "f16_weights", "f32 weights", "clip", st);
    if (!row) return st->code;
    snprintf(row->setting, sizeof row->setting, "f16 weight file");
    clip_model *m[2] = {NULL, NULL};
    ws_objective *s[2] = {NULL, NULL};
    int rc = clip_model_load(&m[0], in->weights_f32, st);
    if (!rc) rc = clip_model_load(&m[1], in->weights_f16, st);
    for (int k = 0; k < 2 && !rc; k++) {
        ws_loss_options lo = loss_options(m[k], 4, 0, 1);
        rc = step_for(&s[k], in, &lo, st);
    }
    setting set[2] = {{s[0], in->sketch, 4, 0, 0, 0}, {s[1], in->sketch, 4, 0, 0, 0}};
    if (!rc) rc = measure(set, 2, in->rounds, PART_CLIP, 1, &row, st);
    if (!rc) {
        struct stat sb[2];
        double size[2] = {0, 0};
        for (int k = 0; k < 2; k++)
            if (stat(k ? in->weights_f16 : in->weights_f32, &sb[k]) == 0) size[k] = (double)sb[k].st_size;
        snprintf(row->note, sizeof row->note,
                 "file %.0f MB instead of %.0f MB; widened to f32 when loaded, so the GEMMs read as many bytes",
                 size[1] / 1e6, size[0] / 1e6);
    }
    for (int k = 0; k < 2; k++) {
        ws_objective_free(s[k]);
        clip_model_free(m[k]);
    }
    return rc;
}

/* Rows: CLIP's weight GEMMs in bf16 against fp32 on the same step, and
 * the yardstick of its error: the same fp32 step with other augmentations
 * (another seed of the step's generator), what the augmentations' own
 * randomness moves the loss and the gradient by from one step to the
 * next. bf16 is the default of fit where its error stays below that. */
static int bf16_rows(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                     ws_status *st) {
    ws_bench_approx_row *row[2] = {new_row(rows, max, n, "bf16", "fp32 GEMMs", "clip", st), NULL};
    if (!row[0] || !(row[1] = new_row(rows, max, n, "aug_seed", "the same step", "clip", st))) return st->code;
    snprintf(row[0]->setting, sizeof row[0]->setting, "bf16 GEMMs");
    snprintf(row[1]->setting, sizeof row[1]->setting, "other augmentations");
    ws_objective *s[2] = {NULL, NULL};
    int rc = WS_OK;
    for (int k = 0; k < 2 && !rc; k++) {
        ws_loss_options lo = loss_options(k ? in->model_bf16 : in->model, 4, 0, 1);
        rc = step_for(&s[k], in, &lo, st);
    }
    setting set[3] = {{s[0], in->sketch, 4, 0, 0, 0}, {s[1], in->sketch, 4, 0, 0, 0},
                      {s[0], in->sketch, 4, 0, 0, COMMON_SEED + 1}};
    if (!rc) rc = measure(set, 3, in->rounds, PART_CLIP, 1, row, st);
    if (!rc) {
        snprintf(row[0]->note, sizeof row[0]->note,
                 "gradient error %.2g of the augmentations' own (aug_seed row); weights packed once, 4 bytes each",
                 row[0]->grad_error / row[1]->grad_error);
        snprintf(row[1]->note, sizeof row[1]->note,
                 "fp32, another seed of the augmentations: the noise of one step's gradient");
    }
    for (int k = 0; k < 2; k++) ws_objective_free(s[k]);
    return rc;
}

/* Row: all cores against one thread. */
static int threads_row(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                       ws_status *st) {
    int threads = ws_runtime_threads();
    ws_bench_approx_row *row = new_row(rows, max, n, "threads", "1 thread", "step", st);
    if (!row) return st->code;
    snprintf(row->setting, sizeof row->setting, "%d threads", threads);
    ws_objective *s = NULL;
    ws_loss_options lo = loss_options(in->model, 4, 0, 1);
    int rc = step_for(&s, in, &lo, st);
    setting set[2] = {{s, in->sketch, 4, 1, 0, 0}, {s, in->sketch, 4, threads, 0, 0}};
    if (!rc) rc = measure(set, 2, in->rounds, PART_STEP, 1, &row, st);
    if (!rc) rc = ws_runtime_init(threads, st);
    snprintf(row->note, sizeof row->note, "%s",
             row->grad_error == 0 && row->loss_error == 0
                 ? "bit-identical: every sum is split the same way whatever the thread count"
                 : "the error is rounding: sums split across threads add up in another order");
    ws_objective_free(s);
    return rc;
}

/* Rows: 2, 1 and 0 augmentations against 4. */
static int num_aug_rows(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *n,
                        ws_status *st) {
    static const int counts[] = {4, 2, 1, 0};
    enum { NCOUNTS = sizeof counts / sizeof counts[0] };
    ws_objective *s[NCOUNTS];
    setting set[NCOUNTS];
    ws_bench_approx_row *row[NCOUNTS];
    memset(s, 0, sizeof s);
    int rc = WS_OK;
    for (int k = 0; k < NCOUNTS && !rc; k++) {
        ws_loss_options lo = loss_options(in->model, counts[k], 0, 1);
        rc = step_for(&s[k], in, &lo, st);
        set[k] = (setting){s[k], in->sketch, 4, 0, 0, 0};
        if (!rc && k > 0) {
            if (!(row[k - 1] = new_row(rows, max, n, "num_aug", "A = 4", "step", st))) {
                rc = st->code;
                break;
            }
            snprintf(row[k - 1]->setting, sizeof row[k - 1]->setting, "A = %d", counts[k]);
            snprintf(row[k - 1]->note, sizeof row[k - 1]->note,
                     "another loss (the global term sums over the augmentations): no error is defined");
        }
    }
    if (!rc) rc = measure(set, NCOUNTS, in->rounds, PART_STEP, 0, row, st);
    for (int k = 0; k < NCOUNTS; k++) ws_objective_free(s[k]);
    return rc;
}

int ws_bench_approx(const ws_bench_approx_input *in, ws_bench_approx_row *rows, int max, int *nrows,
                    ws_status *st) {
    *nrows = 0;
    if (cutoff_rows(in, rows, max, nrows, st) || clip_stop_row(in, rows, max, nrows, st) ||
        photo_cache_row(in, rows, max, nrows, st) || aug_bank_row(in, rows, max, nrows, st))
        return st->code;
    if (in->weights_f32 && in->weights_f16 && f16_row(in, rows, max, nrows, st)) return st->code;
    if (in->model_bf16 && bf16_rows(in, rows, max, nrows, st)) return st->code;
    return threads_row(in, rows, max, nrows, st) || num_aug_rows(in, rows, max, nrows, st) ? st->code
                                                                                           : WS_OK;
}
