/* loss.c: the loss of one view and its gradient (see loss.h).
 *
 * Data flow of one training view (A augmentations, items a = 0..A):
 *   alpha --(a > 0: augment)--> S_a --(x3 channels)--> CLIP --> h_l(S_a) or P_l(S_a), e(S_a)
 *   photo --(same transforms)--> T_a --> CLIP without tape --> h_l(T_a) or P_l(T_a), e(T_a)
 * and back: dL/dh (or dL/dP), dL/de --> CLIP backward --> dL/dS_a (summed over the 3
 * channels) --(augment backward)--> dL/dalpha, summed over items.
 * With an augmentation bank the photo's side comes from the bank's cache. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render/augment.h"
#include "nn/clip.h"
#include "render/edges.h"
#include "objective/lines.h"
#include "objective/loss.h"
#include "objective/loss_l2.h"
#include "objective/view_cache.h"
#include "objective/view_targets.h"
#include "nn/similarity.h"

void ws_loss_options_default(ws_loss_options *opt) {
    memset(opt, 0, sizeof *opt);
    opt->weights_path = "weights/clip-vit-b32.bin";
    opt->conv_weight = 1.0;
    opt->n_layer_weights = 5;
    opt->layer_weights[2] = 1.0;
    opt->layer_weights[3] = 1.0;
    opt->fc_weight = 0.1;
    opt->global_weight = 1.0;
    opt->num_aug = 4;
}

static int uses_layers(const ws_loss_options *opt) {
    if (opt->conv_weight == 0) return 0;
    for (int l = 0; l < opt->n_layer_weights; l++)
        if (opt->layer_weights[l] != 0) return 1;
    return 0;
}

int ws_loss_uses_clip(const ws_loss_options *opt) {
    return uses_layers(opt) || opt->fc_weight != 0 || opt->global_weight != 0;
}

/* The CLIP part: the runs, the cached photo features and the buffers. */
typedef struct {
    clip_model *model;
    int owns_model;       /* loaded here (else borrowed from the options) */
    int res, tokens, width, heads, out_dim;
    int last_block;       /* the last block any term reads */
    int need_embedding;
    int nlayers;          /* layers the geometric term reads */
    int layer[WS_LOSS_MAX_LAYERS];
    int attention;        /* it reads P_l (heads x tokens x tokens), else h_l (tokens x width) */
    size_t geo_size;      /* floats of one image's features of one such layer */
    size_t feature_size;  /* floats of one image's cached features */
    int pass_items;       /* G: stroke images per CLIP pass */
    /* By batch size b (NULL where no pass needs it): runs of b stroke images
     * with tape (b = 1 also serves the unaugmented photo) and of b
     * augmented photos without. A pass always has the same items, so its
     * bits do not depend on which rank runs it. */
    clip_run *stroke_run[2 + WS_LOSS_MAX_AUG];
    clip_run *photo_run[2 + WS_LOSS_MAX_AUG];
    ws_view_cache photo_cache; /* per view: features of the unaugmented photo */
    int bank;             /* N banked transforms per training view (0: none) */
    ws_view_cache bank_cache; /* per training view: N x feature_size, the photo under each transform */
    float *strokes;       /* G x 3 x R x R */
    float *photos;        /* max(A, G) x 3 x R x R (zeroed: a bank's last batch may not fill it) */
    float *targets;       /* G x feature_size: features of the augmented photos */
    float *d_images;      /* G x 3 x R x R */
    float *d_geo_buf;     /* nlayers x G x geo_size */
    const float *d_geo[WS_LOSS_MAX_LAYERS]; /* dL/dh_l or dL/dP_l per block, NULL if unread */
    float *d_embedding;   /* G x out_dim */
} clip_part;

/* Item a of a view's step: a = 0 is the image itself, a = 1..A its
 * augmentations (the same transform for the strokes and the photo). */
typedef struct {
    int identity;          /* item 0: no transform */
    ws_aug_params params;  /* the transform (not identity) */
    int bank_index;        /* its index in the view's bank; -1: drawn fresh */
} loss_item;

struct ws_loss {
    ws_loss_options opt;
    const ws_scene *scene;
    int W, H, A;
    int use_clip;
    clip_part clip;
    ws_view_cache edge_cache;        /* per view: the photo's edge map */
    ws_edges_workspace *edges_ws;
    ws_view_targets *view_targets;   /* per view: the line target (and silhouette) */
    int owns_view_targets;           /* made here (else borrowed from the options) */
    ws_lines_workspace *lines_ws;
    double progress;                 /* of the fit, for the line loss's levels */
    loss_item items[1 + WS_LOSS_MAX_AUG]; /* this step's items, 0 the identity */
    int banked_step;                 /* items 1..A come from the view's bank */
    int *bank_order;                 /* N: scratch for drawing distinct indices */
    ws_aug_workspace *aug_ws;
    ws_step_timing *timing;          /* NULL: no clock is read */
    float *alpha_f, *stroke_aug;     /* H x W */
    float *d_stroke;                 /* H x W */
    double *edge_dalpha;             /* H x W */
    double *item_loss;               /* 1 + A: ws_loss_view's items */
    float *item_grad;                /* (1 + A) x H x W */
};

/* Items [first, first + count) of a view of n items, pass `pass` of
 * passes of G items. */
static void pass_range(int n, int G, int pass, int *first, int *count) {
    *first = pass * G;
    *count = n - *first < G ? n - *first : G;
}

/* Makes the runs of the batch sizes that the passes over n items take:
 * stroke runs of each pass's size, photo runs of its augmented items. */
static int create_pass_runs(clip_part *c, int n, const clip_run_options *with_tape, ws_status *st) {
    for (int pass = 0; pass * c->pass_items < n; pass++) {
        int first, count;
        pass_range(n, c->pass_items, pass, &first, &count);
        clip_run_options ro = *with_tape;
        ro.batch = count;
        if (!c->stroke_run[count] && clip_run_create(&c->stroke_run[count], c->model, &ro, st)) return st->code;
        ro.batch = first == 0 ? count - 1 : count;
        ro.need_grad = 0;
        if (ro.batch > 0 && !c->photo_run[ro.batch] && clip_run_create(&c->photo_run[ro.batch], c->model, &ro, st))
            return st->code;
    }
    return WS_OK;
}

static int clip_part_create(clip_part *c, const ws_loss_options *opt, const ws_scene *scene,
                            int A, ws_status *st) {
    if (opt->model) {
        c->model = (clip_model *)opt->model;
    } else {
        if (clip_model_load(&c->model, opt->weights_path, st)) return st->code;
        c->owns_model = 1;
        if (clip_model_set_precision(c->model, (clip_precision)opt->precision, st)) return st->code;
    }
    const wf_arch *arch = clip_model_arch(c->model);
    c->res = arch->resolution;
    c->width = arch->width;
    c->out_dim = arch->output_dim;
    c->tokens = 1 + (arch->resolution / arch->patch) * (arch->resolution / arch->patch);
    c->heads = arch->heads;
    c->attention = opt->geometric == WS_GEOMETRIC_ATTENTION;
    c->geo_size = c->attention ? (size_t)c->heads * c->tokens * c->tokens : (size_t)c->tokens * c->width;
    if (scene->width != c->res || scene->height != c->res)
        return ws_fail(st, WS_EUSAGE,
                       "%s: the model takes %d x %d images but the scene is loaded at %d x %d",
                       opt->weights_path, c->res, c->res, scene->width, scene->height);
    if (opt->n_layer_weights > arch->layers)
        return ws_fail(st, WS_EUSAGE, "clip_conv_layer_weights: %d weights for a model of %d blocks",
                       opt->n_layer_weights, arch->layers);
    c->nlayers = 0;
    c->last_block = -1;
    if (uses_layers(opt))
        for (int l = 0; l < opt->n_layer_weights; l++)
            if (opt->layer_weights[l] != 0) {
                c->layer[c->nlayers++] = l;
                c->last_block = l;
            }
    c->need_embedding = opt->fc_weight != 0 || opt->global_weight != 0;
    if (c->need_embedding) c->last_block = arch->layers - 1;
    c->feature_size = (size_t)c->nlayers * c->geo_size + (c->need_embedding ? c->out_dim : 0);

    c->pass_items = opt->pass_items ? opt->pass_items : 1 + A;
    clip_run_options ro = {1, c->last_block, c->need_embedding, 1, c->attention && c->nlayers};
    if (create_pass_runs(c, 1, &ro, st) || create_pass_runs(c, 1 + A, &ro, st)) return st->code;
    ro.batch = A;
    ro.need_grad = 0;
    if (A > 0 && !c->photo_run[A] && clip_run_create(&c->photo_run[A], c->model, &ro, st)) return st->code;
    size_t image = (size_t)3 * c->res * c->res;
    c->bank = A > 0 ? opt->aug_bank : 0;
    if (ws_view_cache_init(&c->photo_cache, scene, c->feature_size, "photo features", st) ||
        ws_view_cache_init(&c->bank_cache, scene, (size_t)c->bank * c->feature_size,
                           "augmentation bank features", st))
        return st->code;
    size_t G = (size_t)c->pass_items, geo = G * c->geo_size;
    size_t photos = A > (int)G ? (size_t)A : G;
    if (!(c->strokes = ws_malloc(G * image * sizeof(float), "stroke images", st)) ||
        !(c->photos = ws_calloc(photos * image, sizeof(float), "photo images", st)) ||
        !(c->targets = ws_malloc(G * c->feature_size * sizeof(float), "photo features", st)) ||
        !(c->d_images = ws_malloc(G * image * sizeof(float), "image gradients", st)) ||
        !(c->d_geo_buf = ws_malloc((c->nlayers ? c->nlayers : 1) * geo * sizeof(float),
                                   "feature gradients", st)) ||
        !(c->d_embedding = ws_malloc(G * c->out_dim * sizeof(float), "embedding gradients", st)))
        return st->code;
    return WS_OK;
}

static void clip_part_free(clip_part *c) {
    for (int b = 0; b < 2 + WS_LOSS_MAX_AUG; b++) {
        clip_run_free(c->stroke_run[b]);
        clip_run_free(c->photo_run[b]);
    }
    if (c->owns_model) clip_model_free(c->model);
    ws_view_cache_free(&c->photo_cache);
    ws_view_cache_free(&c->bank_cache);
    free(c->strokes);
    free(c->photos);
    free(c->targets);
    free(c->d_images);
    free(c->d_geo_buf);
    free(c->d_embedding);
}

int ws_loss_options_check(const ws_loss_options *opt, ws_status *st) {
    if (opt->num_aug < 0 || opt->num_aug > WS_LOSS_MAX_AUG)
        return ws_fail(st, WS_EUSAGE, "--num-aug: %d is not in 0..%d", opt->num_aug, WS_LOSS_MAX_AUG);
    if (opt->aug_bank < 0 || opt->aug_bank > 4096 || (opt->aug_bank > 0 && opt->aug_bank < opt->num_aug))
        return ws_fail(st, WS_EUSAGE,
                       "--aug-bank: %d is not 0 or in %d..4096 (a step uses --num-aug %d distinct "
                       "transforms of the bank)",
                       opt->aug_bank, opt->num_aug, opt->num_aug);
    if (opt->pass_items < 0 || opt->pass_items > 1 + opt->num_aug)
        return ws_fail(st, WS_EUSAGE, "--clip-batch: %d is not in 0..%d (1 + --num-aug)", opt->pass_items,
                       1 + opt->num_aug);
    /* a negative weight would make its term a reward for looking unlike the photo */
    int negative = opt->conv_weight < 0 || opt->fc_weight < 0 || opt->global_weight < 0 ||
                   opt->edges_weight < 0 || opt->l2_weight < 0 || opt->lines_weight < 0;
    if (opt->hidden_lines != WS_HIDDEN_NONE && opt->hidden_lines != WS_HIDDEN_HULL)
        return ws_fail(st, WS_EUSAGE, "--hidden-lines: mode %d is not none (%d) or hull (%d)",
                       (int)opt->hidden_lines, WS_HIDDEN_NONE, WS_HIDDEN_HULL);
    if (opt->geometric != WS_GEOMETRIC_BLOCKS && opt->geometric != WS_GEOMETRIC_ATTENTION)
        return ws_fail(st, WS_EUSAGE, "--clip-geometric: variant %d is not blocks (%d) or attention (%d)",
                       (int)opt->geometric, WS_GEOMETRIC_BLOCKS, WS_GEOMETRIC_ATTENTION);
    for (int l = 0; l < opt->n_layer_weights; l++) negative |= opt->layer_weights[l] < 0;
    if (negative)
        return ws_fail(st, WS_EUSAGE, "loss weights (--clip-weight, --clip-conv-loss, "
                                      "--clip-fc-loss-weight, --clip-conv-layer-weights, "
                                      "--edges-weight) must be >= 0");
    /* not finite or negative: a reward for leaving the silhouettes */
    if (!(opt->silhouette_weight >= 0 && opt->silhouette_weight < INFINITY))
        return ws_fail(st, WS_EUSAGE, "--silhouette-weight: %g is not a finite number >= 0",
                       opt->silhouette_weight);
    const struct {
        const char *option;
        double value;
    } weights[] = {{"--clip-weight", opt->global_weight},   {"--clip-conv-loss", opt->conv_weight},
                   {"--clip-fc-loss-weight", opt->fc_weight}, {"--edges-weight", opt->edges_weight},
                   {"--edges-weight", opt->lines_weight},   {"--silhouette-weight", opt->silhouette_weight}};
    for (size_t k = 0; k < sizeof weights / sizeof weights[0]; k++)
        if (!(weights[k].value <= WS_LOSS_MAX_WEIGHT))
            return ws_fail(st, WS_EUSAGE, "%s: %g is not in [0, %g]", weights[k].option, weights[k].value,
                           WS_LOSS_MAX_WEIGHT);
    for (int l = 0; l < opt->n_layer_weights; l++)
        if (!(opt->layer_weights[l] <= WS_LOSS_MAX_WEIGHT))
            return ws_fail(st, WS_EUSAGE, "--clip-conv-layer-weights: %g is not in [0, %g]", opt->layer_weights[l],
                           WS_LOSS_MAX_WEIGHT);
    return WS_OK;
}

int ws_loss_create(ws_loss **out, const ws_loss_options *opt, const ws_scene *scene,
                   ws_status *st) {
    *out = NULL;
    if (ws_loss_options_check(opt, st)) return st->code;
    ws_loss *L = ws_calloc(1, sizeof *L, "loss", st);
    if (!L) return st->code;
    *out = L;
    L->opt = *opt;
    L->scene = scene;
    L->W = scene->width;
    L->H = scene->height;
    L->A = opt->num_aug;
    L->use_clip = ws_loss_uses_clip(opt);
    size_t pixels = (size_t)L->W * L->H;
    if (L->use_clip && clip_part_create(&L->clip, opt, scene, L->A, st)) return st->code;
    if (opt->edges_weight != 0 && (ws_edges_workspace_create(&L->edges_ws, L->W, L->H, st) ||
                                   ws_view_cache_init(&L->edge_cache, scene, pixels, "edge maps", st)))
        return st->code;
    if (opt->lines_weight != 0 && ws_lines_workspace_create(&L->lines_ws, L->W, L->H, st)) return st->code;
    L->view_targets = opt->targets;
    L->owns_view_targets = !opt->targets;
    if (L->owns_view_targets && ws_view_targets_create(&L->view_targets, scene, st)) return st->code;
    L->progress = 1;
    L->items[0].identity = 1;
    if (!(L->bank_order = ws_calloc(opt->aug_bank ? opt->aug_bank : 1, sizeof *L->bank_order,
                                    "augmentation bank", st)) ||
        !(L->alpha_f = ws_malloc(pixels * sizeof(float), "stroke image", st)) ||
        !(L->stroke_aug = ws_malloc(pixels * sizeof(float), "stroke image", st)) ||
        !(L->d_stroke = ws_malloc(pixels * sizeof(float), "stroke gradient", st)) ||
        !(L->edge_dalpha = ws_malloc(pixels * sizeof(double), "stroke gradient", st)) ||
        !(L->item_loss = ws_malloc((1 + L->A) * sizeof(double), "item losses", st)) ||
        !(L->item_grad = ws_malloc((1 + L->A) * pixels * sizeof(float), "item gradients", st)))
        return st->code;
    return ws_aug_workspace_create(&L->aug_ws, L->W, L->H, 3, st);
}

void ws_loss_free(ws_loss *L) {
    if (!L) return;
    if (L->use_clip) clip_part_free(&L->clip);
    ws_view_cache_free(&L->edge_cache);
    ws_edges_workspace_free(L->edges_ws);
    if (L->owns_view_targets) ws_view_targets_free(L->view_targets);
    ws_lines_workspace_free(L->lines_ws);
    ws_aug_workspace_free(L->aug_ws);
    free(L->bank_order);
    free(L->alpha_f);
    free(L->stroke_aug);
    free(L->d_stroke);
    free(L->edge_dalpha);
    free(L->item_loss);
    free(L->item_grad);
    free(L);
}

void ws_loss_set_timing(ws_loss *L, ws_step_timing *t) { L->timing = t; }

ws_view_targets *ws_loss_targets(const ws_loss *L) { return L->view_targets; }

size_t ws_loss_bank_bytes(const ws_loss *L) {
    return L->use_clip ? ws_view_cache_full_bytes(&L->clip.bank_cache, WS_TRAIN) : 0;
}

/* Layer l's features of a run's images (batch x geo_size): h_l or P_l. */
static const float *geo_features(const clip_part *c, const clip_run *run, int l) {
    return c->attention ? clip_attention(run, l) : clip_hidden(run, l);
}

/* Copies image `item`'s features out of a run into dst (feature_size floats). */
static void gather_features(const clip_part *c, const clip_run *run, int item, float *dst) {
    size_t geo = c->geo_size;
    for (int k = 0; k < c->nlayers; k++)
        memcpy(dst + k * geo, geo_features(c, run, c->layer[k]) + item * geo, geo * sizeof(float));
    if (c->need_embedding)
        memcpy(dst + c->nlayers * geo, clip_embedding(run) + (size_t)item * c->out_dim,
               c->out_dim * sizeof(float));
}

/* Fills a slot of the photo cache: the unaugmented photo's features. */
static int fill_photo_features(void *ctx, int split, int view, float *slot, ws_status *st) {
    ws_loss *L = ctx;
    clip_part *c = &L->clip;
    double t0 = ws_time_start(L->timing);
    if (clip_forward(c->stroke_run[1], L->scene->split[split].views[view].photo.data, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_PHOTO, t0);
    gather_features(c, c->stroke_run[1], 0, slot);
    return WS_OK;
}

/* The three CLIP terms of the count items of `run` (strokes; item i is
 * item first + i of the view's n) against targets (count feature vectors)
 * and the unaugmented photo's t0 (the global term); fills the gradients
 * with respect to the stroke features and item_loss[i] with item i's part
 * of the view's loss. */
static void clip_terms(clip_part *c, const ws_loss_options *opt, const clip_run *run, int first, int count,
                       int n, const float *const *targets, const float *t0, double *item_loss) {
    size_t geo = c->geo_size, off = (size_t)c->nlayers * geo;
    int D = c->out_dim;
    for (int l = 0; l < WS_LOSS_MAX_LAYERS; l++) c->d_geo[l] = NULL;
    for (int k = 0; k < c->nlayers; k++) c->d_geo[c->layer[k]] = c->d_geo_buf + (size_t)k * count * geo;
    for (int i = 0; i < count; i++) {
        double loss = 0;
        /* the mean over items and an item's features (tokens and channels,
         * or heads, query and key tokens) is the mean of the per-item
         * means: every item has the same size */
        for (int k = 0; k < c->nlayers; k++) {
            int l = c->layer[k];
            double w = opt->conv_weight * opt->layer_weights[l];
            const float *h = geo_features(c, run, l) + i * geo, *t = targets[i] + k * geo;
            loss += w / n * nn_mse_forward(h, t, geo);
            nn_mse_backward(h, t, geo, (float)(w / n), (float *)c->d_geo[l] + i * geo);
        }
        if (c->need_embedding) {
            const float *e = clip_embedding(run) + (size_t)i * D;
            float *de = c->d_embedding + (size_t)i * D;
            memset(de, 0, D * sizeof(float));
            double fc = opt->fc_weight / n;
            loss += fc * (1.0 - nn_cosine_forward(e, targets[i] + off, D));
            nn_cosine_backward(e, targets[i] + off, D, (float)-fc, de);
            if (first + i > 0) {
                double g = opt->global_weight;
                loss += g * (1.0 - nn_cosine_forward(e, t0 + off, D));
                nn_cosine_backward(e, t0 + off, D, (float)-g, de);
            }
        }
        item_loss[i] = loss;
    }
}

/* Writes the 1-channel image src into the 3 channels of dst (R x R each). */
static void to_rgb(const float *src, size_t pixels, float *dst) {
    for (int ch = 0; ch < 3; ch++) memcpy(dst + ch * pixels, src, pixels * sizeof(float));
}

/* Transform k of training view `view`'s bank: drawn from a generator seeded
 * by (aug_seed, view, k) alone. */
static int bank_transform(const ws_loss *L, int view, int k, ws_aug_params *p, ws_status *st) {
    ws_rng rng;
    ws_rng_seed(&rng, L->opt.aug_seed);
    ws_rng_seed(&rng, ws_rng_next(&rng) ^ (uint64_t)view);
    ws_rng_seed(&rng, ws_rng_next(&rng) ^ (uint64_t)k);
    return ws_aug_sample(p, &rng, L->W, L->H, st);
}

/* Item `it` of an image (C x H x W) into out: a copy for the identity,
 * else its transform. */
static int item_forward(ws_loss *L, const loss_item *it, const float *in, int C, float *out, ws_status *st) {
    if (!it->identity) return ws_aug_forward(&it->params, in, C, L->H, L->W, out, L->aug_ws, st);
    memcpy(out, in, (size_t)C * L->H * L->W * sizeof(float));
    return WS_OK;
}

/* The gradient of item_forward (1 channel): din = item^T dout. */
static int item_backward(ws_loss *L, const loss_item *it, const float *dout, float *din, ws_status *st) {
    if (!it->identity) return ws_aug_backward(&it->params, dout, 1, L->H, L->W, din, L->aug_ws, st);
    memcpy(din, dout, (size_t)L->H * L->W * sizeof(float));
    return WS_OK;
}

/* Fills a slot of the bank cache: the photo's features under each of
 * training view `view`'s N banked transforms, in batches k = 0..A-1,
 * A..2A-1, ... whatever step asks first, so that they are the same bits in
 * a resumed run. A last batch that is not full leaves the other images of
 * the buffer as they are (finite: the buffer starts zeroed; images of a
 * batch do not mix). */
static int fill_bank(void *ctx, int split, int view, float *out, ws_status *st) {
    ws_loss *L = ctx;
    clip_part *c = &L->clip;
    const ws_view *v = &L->scene->split[split].views[view];
    size_t image = (size_t)3 * L->W * L->H;
    for (int k0 = 0; k0 < c->bank; k0 += L->A) {
        int m = c->bank - k0 < L->A ? c->bank - k0 : L->A;
        double t0 = ws_time_start(L->timing);
        for (int a = 0; a < m; a++) {
            loss_item it = {0, {0}, k0 + a};
            if (bank_transform(L, view, k0 + a, &it.params, st) ||
                item_forward(L, &it, v->photo.data, 3, c->photos + a * image, st))
                return st->code;
        }
        ws_time_add(L->timing, WS_TIME_AUGMENT, t0);
        t0 = ws_time_start(L->timing);
        if (clip_forward(c->photo_run[L->A], c->photos, st)) return st->code;
        ws_time_add(L->timing, WS_TIME_CLIP_PHOTO, t0);
        for (int a = 0; a < m; a++)
            gather_features(c, c->photo_run[L->A], a, out + (size_t)(k0 + a) * c->feature_size);
    }
    return WS_OK;
}

/* targets[0..m): the photo's features under items first .. first+m-1
 * (first >= 1): from the view's bank, or computed now (one CLIP forward
 * without tape). */
static int augmented_photo_features(ws_loss *L, const ws_view *v, int view, int first, int m,
                                    const float **targets, ws_status *st) {
    clip_part *c = &L->clip;
    if (L->banked_step) {
        const float *bank;
        if (ws_view_cache_get(&c->bank_cache, WS_TRAIN, view, fill_bank, L, &bank, st)) return st->code;
        for (int i = 0; i < m; i++) targets[i] = bank + (size_t)L->items[first + i].bank_index * c->feature_size;
        return WS_OK;
    }
    size_t image = (size_t)3 * L->W * L->H;
    double t0 = ws_time_start(L->timing);
    for (int i = 0; i < m; i++)
        if (item_forward(L, &L->items[first + i], v->photo.data, 3, c->photos + i * image, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_AUGMENT, t0);
    t0 = ws_time_start(L->timing);
    if (clip_forward(c->photo_run[m], c->photos, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_PHOTO, t0);
    for (int i = 0; i < m; i++) {
        float *slot = c->targets + i * c->feature_size;
        gather_features(c, c->photo_run[m], i, slot);
        targets[i] = slot;
    }
    return WS_OK;
}

/* One CLIP pass: items [first, first + count) of a view of n items, the
 * stroke image alpha_f under each item; item_loss (count) receives each
 * item's loss and, when given, item_grad (count x H x W) its dL/dalpha. */
static int clip_pass(ws_loss *L, const ws_view *v, int split, int view, int first, int count, int n,
                     double *item_loss, float *item_grad, ws_status *st) {
    clip_part *c = &L->clip;
    size_t pixels = (size_t)L->W * L->H, image = 3 * pixels;
    const float *t0 = NULL, *targets[1 + WS_LOSS_MAX_AUG];
    if (ws_view_cache_get(&c->photo_cache, split, view, fill_photo_features, L, &t0, st)) return st->code;
    double t = ws_time_start(L->timing);
    for (int i = 0; i < count; i++) {
        if (item_forward(L, &L->items[first + i], L->alpha_f, 1, L->stroke_aug, st)) return st->code;
        to_rgb(L->stroke_aug, pixels, c->strokes + i * image);
    }
    ws_time_add(L->timing, WS_TIME_AUGMENT, t);
    int skip = first == 0; /* item 0's target is t0 */
    if (skip) targets[0] = t0;
    if (count > skip &&
        augmented_photo_features(L, v, view, first + skip, count - skip, targets + skip, st))
        return st->code;
    clip_run *run = c->stroke_run[count];
    t = ws_time_start(L->timing);
    if (clip_forward(run, c->strokes, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_FORWARD, t);
    clip_terms(c, &L->opt, run, first, count, n, targets, t0, item_loss);
    if (!item_grad) return WS_OK;
    t = ws_time_start(L->timing);
    const float *const *d_geo = c->nlayers ? c->d_geo : NULL;
    if (clip_backward(run, c->attention ? NULL : d_geo, c->attention ? d_geo : NULL,
                      c->need_embedding ? c->d_embedding : NULL, c->d_images, st))
        return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_BACKWARD, t);
    for (int i = 0; i < count; i++) {
        const float *d = c->d_images + i * image;
        for (size_t p = 0; p < pixels; p++) L->d_stroke[p] = d[p] + d[pixels + p] + d[2 * pixels + p];
        t = ws_time_start(L->timing);
        if (item_backward(L, &L->items[first + i], L->d_stroke, item_grad + i * pixels, st)) return st->code;
        ws_time_add(L->timing, WS_TIME_AUGMENT, t);
    }
    return WS_OK;
}

/* Fills a slot of the edge cache: the edge map of the view's photo. */
static int fill_edge_map(void *ctx, int split, int view, float *slot, ws_status *st) {
    ws_loss *L = ctx;
    ws_edges_target(L->scene->split[split].views[view].photo.data, L->W, L->H, slot);
    return WS_OK;
}

void ws_loss_set_progress(ws_loss *L, double progress) { L->progress = progress; }

/* This step's items 1..A: fresh transforms from rng, or (a training view
 * with a bank) A distinct ones of the view's bank, chosen with rng. */
static int draw_transforms(ws_loss *L, int split, int view, ws_rng *rng, ws_status *st) {
    int N = L->opt.aug_bank;
    L->banked_step = split == WS_TRAIN && N > 0;
    if (!L->banked_step) {
        for (int a = 1; a <= L->A; a++) {
            L->items[a].bank_index = -1;
            if (ws_aug_sample(&L->items[a].params, rng, L->W, L->H, st)) return st->code;
        }
        return WS_OK;
    }
    for (int k = 0; k < N; k++) L->bank_order[k] = k;
    for (int a = 0; a < L->A; a++) {
        int j = a + (int)ws_rng_below(rng, (uint64_t)(N - a));
        int k = L->bank_order[j];
        L->bank_order[j] = L->bank_order[a];
        L->bank_order[a] = k;
        L->items[1 + a].bank_index = k;
        if (bank_transform(L, view, k, &L->items[1 + a].params, st)) return st->code;
    }
    return WS_OK;
}

int ws_loss_items(const ws_loss *L, int augment) { return L->use_clip ? (augment ? 1 + L->A : 1) : 0; }

int ws_loss_passes(const ws_loss *L, int augment) {
    int n = ws_loss_items(L, augment), G = L->use_clip ? L->clip.pass_items : 1;
    return n > G ? (n + G - 1) / G : 1;
}

void ws_loss_pass_items(const ws_loss *L, int augment, int pass, int *first, int *count) {
    int n = ws_loss_items(L, augment);
    pass_range(n, n ? L->clip.pass_items : 1, pass, first, count);
}

static int check_view(const ws_loss *L, int split, int view, ws_status *st) {
    if (split < 0 || split >= WS_NSPLITS || view < 0 || view >= L->scene->split[split].n)
        return ws_fail(st, WS_EINTERNAL, "loss: no view %d in split %d", view, split);
    return WS_OK;
}

int ws_loss_draw(ws_loss *L, int split, int view, ws_rng *rng, ws_status *st) {
    return check_view(L, split, view, st) || draw_transforms(L, split, view, rng, st) ? st->code : WS_OK;
}

int ws_loss_pass(ws_loss *L, int split, int view, const double *alpha, int augment, int pass,
                 double *item_loss, float *item_grad, ws_status *st) {
    int first, count;
    ws_loss_pass_items(L, augment, pass, &first, &count);
    if (check_view(L, split, view, st)) return st->code;
    if (count == 0) return WS_OK;
    size_t pixels = (size_t)L->W * L->H;
    for (size_t i = 0; i < pixels; i++) L->alpha_f[i] = (float)alpha[i];
    return clip_pass(L, &L->scene->split[split].views[view], split, view, first, count,
                     ws_loss_items(L, augment), item_loss, item_grad, st);
}

int ws_loss_combine(ws_loss *L, int split, int view, const double *alpha, int augment, const double *item_loss,
                    const float *item_grad, double *value, double *dalpha, ws_status *st) {
    if (check_view(L, split, view, st)) return st->code;
    const ws_view *v = &L->scene->split[split].views[view];
    size_t pixels = (size_t)L->W * L->H;
    if (dalpha) memset(dalpha, 0, pixels * sizeof(double));
    double loss = 0;
    for (int a = 0; a < ws_loss_items(L, augment); a++) {
        loss += item_loss[a];
        for (size_t i = 0; dalpha && i < pixels; i++) dalpha[i] += item_grad[a * pixels + i];
    }
    if (L->opt.edges_weight != 0) {
        double w = L->opt.edges_weight;
        const float *edges;
        if (ws_view_cache_get(&L->edge_cache, split, view, fill_edge_map, L, &edges, st)) return st->code;
        loss += w * ws_edges_loss_forward(alpha, edges, L->W, L->H, L->edges_ws);
        if (dalpha) {
            ws_edges_loss_backward(alpha, edges, L->W, L->H, L->edges_ws, L->edge_dalpha);
            for (size_t i = 0; i < pixels; i++) dalpha[i] += w * L->edge_dalpha[i];
        }
    }
    if (L->opt.lines_weight != 0) {
        double w = L->opt.lines_weight, levels[WS_LINES_LEVELS];
        const float *target;
        if (ws_view_targets_line(L->view_targets, split, view, &target, st)) return st->code;
        ws_lines_weights(augment ? L->progress : 1, levels);
        loss += w * ws_lines_loss(alpha, target, levels, L->lines_ws, dalpha ? L->edge_dalpha : NULL);
        if (dalpha)
            for (size_t i = 0; i < pixels; i++) dalpha[i] += w * L->edge_dalpha[i];
    }
    if (L->opt.l2_weight != 0) {
        double w = L->opt.l2_weight;
        loss += w * ws_loss_l2_forward(alpha, v->photo.data, pixels);
        if (dalpha) ws_loss_l2_backward(alpha, v->photo.data, pixels, w, dalpha);
    }
    if (!isfinite(loss))
        return ws_fail(st, WS_ENUMERIC, "loss of %s view %s is not finite", ws_split_names[split], v->name);
    *value = loss;
    return WS_OK;
}

int ws_loss_view(ws_loss *L, int split, int view, const double *alpha, int augment,
                 ws_rng *rng, double *value, double *dalpha, ws_status *st) {
    if (augment && ws_loss_draw(L, split, view, rng, st)) return st->code;
    size_t pixels = (size_t)L->W * L->H;
    for (int pass = 0; pass < ws_loss_passes(L, augment); pass++) {
        int first, count;
        ws_loss_pass_items(L, augment, pass, &first, &count);
        if (ws_loss_pass(L, split, view, alpha, augment, pass, L->item_loss + first,
                         dalpha ? L->item_grad + first * pixels : NULL, st))
            return st->code;
    }
    return ws_loss_combine(L, split, view, alpha, augment, L->item_loss, dalpha ? L->item_grad : NULL, value,
                           dalpha, st);
}
