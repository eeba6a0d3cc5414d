/* loss.c: the loss of one view and its gradient (see loss.h).
 *
 * Data flow of one training view (A augmentations, items a = 0..A):
 *   alpha --(a > 0: augment)--> S_a --(x3 channels)--> CLIP --> h_l(S_a), e(S_a)
 *   photo --(same transforms)--> T_a --> CLIP without tape --> h_l(T_a), e(T_a)
 * and back: dL/dh, dL/de --> CLIP backward --> dL/dS_a (summed over the 3
 * channels) --(augment backward)--> dL/dalpha, summed over items.
 * With an augmentation bank the photo's side comes from the bank's cache. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render/augment.h"
#include "nn/clip.h"
#include "render/edges.h"
#include "objective/loss.h"
#include "objective/loss_l2.h"
#include "objective/view_cache.h"
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
    int res, tokens, width, out_dim;
    int last_block;       /* the last block any term reads */
    int need_embedding;
    int nlayers;          /* layers the geometric term reads */
    int layer[WS_LOSS_MAX_LAYERS];
    size_t feature_size;  /* floats of one image's cached features */
    clip_run *train_run;  /* 1 + A stroke images, with tape */
    clip_run *single_run; /* item 0 alone, with tape (evaluation, grad, cache) */
    clip_run *photo_run;  /* A augmented photos, no tape */
    ws_view_cache photo_cache; /* per view: features of the unaugmented photo */
    int bank;             /* N banked transforms per training view (0: none) */
    ws_view_cache bank_cache; /* per training view: N x feature_size, the photo under each transform */
    float *strokes;       /* (1 + A) x 3 x R x R */
    float *photos;        /* A x 3 x R x R (zeroed: a bank's last batch may not fill it) */
    float *targets;       /* A x feature_size: features of the augmented photos */
    float *d_images;      /* (1 + A) x 3 x R x R */
    float *d_hidden_buf;  /* nlayers x (1 + A) x tokens x width */
    const float *d_hidden[WS_LOSS_MAX_LAYERS]; /* per block, NULL if unread */
    float *d_embedding;   /* (1 + A) x out_dim */
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
    loss_item items[1 + WS_LOSS_MAX_AUG]; /* this step's items, 0 the identity */
    int banked_step;                 /* items 1..A come from the view's bank */
    int *bank_order;                 /* N: scratch for drawing distinct indices */
    ws_aug_workspace *aug_ws;
    ws_step_timing *timing;          /* NULL: no clock is read */
    float *alpha_f, *stroke_aug;     /* H x W */
    float *d_stroke;                 /* H x W */
    double *edge_dalpha;             /* H x W */
};

static int clip_part_create(clip_part *c, const ws_loss_options *opt, const ws_scene *scene,
                            int A, ws_status *st) {
    if (opt->model) {
        c->model = (clip_model *)opt->model;
    } else {
        if (clip_model_load(&c->model, opt->weights_path, st)) return st->code;
        c->owns_model = 1;
    }
    const wf_arch *arch = clip_model_arch(c->model);
    c->res = arch->resolution;
    c->width = arch->width;
    c->out_dim = arch->output_dim;
    c->tokens = 1 + (arch->resolution / arch->patch) * (arch->resolution / arch->patch);
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
    c->feature_size = (size_t)c->nlayers * c->tokens * c->width + (c->need_embedding ? c->out_dim : 0);

    clip_run_options ro = {1 + A, c->last_block, c->need_embedding, 1};
    if (clip_run_create(&c->train_run, c->model, &ro, st)) return st->code;
    ro.batch = 1;
    if (clip_run_create(&c->single_run, c->model, &ro, st)) return st->code;
    if (A > 0) {
        ro.batch = A;
        ro.need_grad = 0;
        if (clip_run_create(&c->photo_run, c->model, &ro, st)) return st->code;
    }
    size_t image = (size_t)3 * c->res * c->res;
    c->bank = A > 0 ? opt->aug_bank : 0;
    if (ws_view_cache_init(&c->photo_cache, scene, c->feature_size, "photo features", st) ||
        ws_view_cache_init(&c->bank_cache, scene, (size_t)c->bank * c->feature_size,
                           "augmentation bank features", st))
        return st->code;
    size_t hidden = (size_t)(1 + A) * c->tokens * c->width;
    if (!(c->strokes = ws_malloc((1 + A) * image * sizeof(float), "stroke images", st)) ||
        !(c->photos = ws_calloc((A ? A : 1) * image, sizeof(float), "photo images", st)) ||
        !(c->targets = ws_malloc((A ? A : 1) * c->feature_size * sizeof(float), "photo features", st)) ||
        !(c->d_images = ws_malloc((1 + A) * image * sizeof(float), "image gradients", st)) ||
        !(c->d_hidden_buf = ws_malloc((c->nlayers ? c->nlayers : 1) * hidden * sizeof(float),
                                      "feature gradients", st)) ||
        !(c->d_embedding = ws_malloc((size_t)(1 + A) * c->out_dim * sizeof(float),
                                     "embedding gradients", st)))
        return st->code;
    return WS_OK;
}

static void clip_part_free(clip_part *c) {
    clip_run_free(c->train_run);
    clip_run_free(c->single_run);
    clip_run_free(c->photo_run);
    if (c->owns_model) clip_model_free(c->model);
    ws_view_cache_free(&c->photo_cache);
    ws_view_cache_free(&c->bank_cache);
    free(c->strokes);
    free(c->photos);
    free(c->targets);
    free(c->d_images);
    free(c->d_hidden_buf);
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
    /* a negative weight would make its term a reward for looking unlike the photo */
    int negative = opt->conv_weight < 0 || opt->fc_weight < 0 || opt->global_weight < 0 ||
                   opt->edges_weight < 0 || opt->l2_weight < 0;
    for (int l = 0; l < opt->n_layer_weights; l++) negative |= opt->layer_weights[l] < 0;
    if (negative)
        return ws_fail(st, WS_EUSAGE, "loss weights (--clip-weight, --clip-conv-loss, "
                                      "--clip-fc-loss-weight, --clip-conv-layer-weights, "
                                      "--edges-weight) must be >= 0");
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
    L->items[0].identity = 1;
    if (!(L->bank_order = ws_calloc(opt->aug_bank ? opt->aug_bank : 1, sizeof *L->bank_order,
                                    "augmentation bank", st)) ||
        !(L->alpha_f = ws_malloc(pixels * sizeof(float), "stroke image", st)) ||
        !(L->stroke_aug = ws_malloc(pixels * sizeof(float), "stroke image", st)) ||
        !(L->d_stroke = ws_malloc(pixels * sizeof(float), "stroke gradient", st)) ||
        !(L->edge_dalpha = ws_malloc(pixels * sizeof(double), "stroke gradient", st)))
        return st->code;
    return ws_aug_workspace_create(&L->aug_ws, L->W, L->H, 3, st);
}

void ws_loss_free(ws_loss *L) {
    if (!L) return;
    if (L->use_clip) clip_part_free(&L->clip);
    ws_view_cache_free(&L->edge_cache);
    ws_edges_workspace_free(L->edges_ws);
    ws_aug_workspace_free(L->aug_ws);
    free(L->bank_order);
    free(L->alpha_f);
    free(L->stroke_aug);
    free(L->d_stroke);
    free(L->edge_dalpha);
    free(L);
}

void ws_loss_set_timing(ws_loss *L, ws_step_timing *t) { L->timing = t; }

size_t ws_loss_bank_bytes(const ws_loss *L) {
    return L->use_clip ? ws_view_cache_full_bytes(&L->clip.bank_cache, WS_TRAIN) : 0;
}

/* Copies image `item`'s features out of a run into dst (feature_size floats). */
static void gather_features(const clip_part *c, const clip_run *run, int item, float *dst) {
    size_t hidden = (size_t)c->tokens * c->width;
    for (int k = 0; k < c->nlayers; k++)
        memcpy(dst + k * hidden, clip_hidden(run, c->layer[k]) + item * hidden, hidden * sizeof(float));
    if (c->need_embedding)
        memcpy(dst + c->nlayers * hidden, clip_embedding(run) + (size_t)item * c->out_dim,
               c->out_dim * sizeof(float));
}

/* Fills a slot of the photo cache: the unaugmented photo's features. */
static int fill_photo_features(void *ctx, int split, int view, float *slot, ws_status *st) {
    ws_loss *L = ctx;
    clip_part *c = &L->clip;
    double t0 = ws_time_start(L->timing);
    if (clip_forward(c->single_run, L->scene->split[split].views[view].photo.data, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_PHOTO, t0);
    gather_features(c, c->single_run, 0, slot);
    return WS_OK;
}

/* The three CLIP terms for items 0..n-1 of `run` (strokes) against targets
 * (n feature vectors, item 0's first) and the global term's T_0; fills the
 * gradients with respect to the stroke features. Returns the loss. */
static double clip_terms(clip_part *c, const ws_loss_options *opt, const clip_run *run, int n,
                         const float *const *targets) {
    size_t hidden = (size_t)c->tokens * c->width;
    double loss = 0;
    for (int l = 0; l < WS_LOSS_MAX_LAYERS; l++) c->d_hidden[l] = NULL;
    for (int k = 0; k < c->nlayers; k++) {
        int l = c->layer[k];
        double w = opt->conv_weight * opt->layer_weights[l];
        float *d = c->d_hidden_buf + (size_t)k * n * hidden;
        const float *h = clip_hidden(run, l);
        /* the mean over items, tokens and channels is the mean of the
         * per-item means: every item has the same size */
        for (int a = 0; a < n; a++) {
            loss += w / n * nn_mse_forward(h + a * hidden, targets[a] + k * hidden, hidden);
            nn_mse_backward(h + a * hidden, targets[a] + k * hidden, hidden, (float)(w / n), d + a * hidden);
        }
        c->d_hidden[l] = d;
    }
    if (c->need_embedding) {
        const float *e = clip_embedding(run);
        int D = c->out_dim;
        size_t off = (size_t)c->nlayers * hidden;
        for (int a = 0; a < n; a++) {
            float *de = c->d_embedding + (size_t)a * D;
            memset(de, 0, D * sizeof(float));
            double fc = opt->fc_weight / n;
            loss += fc * (1.0 - nn_cosine_forward(e + a * D, targets[a] + off, D));
            nn_cosine_backward(e + a * D, targets[a] + off, D, (float)-fc, de);
            if (a > 0) {
                double g = opt->global_weight;
                loss += g * (1.0 - nn_cosine_forward(e + a * D, targets[0] + off, D));
                nn_cosine_backward(e + a * D, targets[0] + off, D, (float)-g, de);
            }
        }
    }
    return loss;
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
        if (clip_forward(c->photo_run, c->photos, st)) return st->code;
        ws_time_add(L->timing, WS_TIME_CLIP_PHOTO, t0);
        for (int a = 0; a < m; a++)
            gather_features(c, c->photo_run, a, out + (size_t)(k0 + a) * c->feature_size);
    }
    return WS_OK;
}

/* targets[a], a = 1..A: the photo's features under item a: from the
 * view's bank, or computed now (one CLIP forward without tape). */
static int augmented_photo_features(ws_loss *L, const ws_view *v, int view, const float **targets,
                                    ws_status *st) {
    clip_part *c = &L->clip;
    if (L->banked_step) {
        const float *bank;
        if (ws_view_cache_get(&c->bank_cache, WS_TRAIN, view, fill_bank, L, &bank, st)) return st->code;
        for (int a = 1; a <= L->A; a++) targets[a] = bank + (size_t)L->items[a].bank_index * c->feature_size;
        return WS_OK;
    }
    size_t image = (size_t)3 * L->W * L->H;
    double t0 = ws_time_start(L->timing);
    for (int a = 1; a <= L->A; a++)
        if (item_forward(L, &L->items[a], v->photo.data, 3, c->photos + (a - 1) * image, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_AUGMENT, t0);
    t0 = ws_time_start(L->timing);
    if (clip_forward(c->photo_run, c->photos, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_PHOTO, t0);
    for (int a = 1; a <= L->A; a++) {
        float *slot = c->targets + (a - 1) * c->feature_size;
        gather_features(c, c->photo_run, a - 1, slot);
        targets[a] = slot;
    }
    return WS_OK;
}

/* The CLIP terms of one view for items 0..n-1 (n = 1 + A when
 * augmenting) and, when dalpha is given, their gradient added to it. */
static int clip_view(ws_loss *L, const ws_view *v, int split, int view, int n, double *loss,
                     double *dalpha, ws_status *st) {
    clip_part *c = &L->clip;
    size_t pixels = (size_t)L->W * L->H, image = 3 * pixels;
    const float *targets[1 + WS_LOSS_MAX_AUG];
    if (ws_view_cache_get(&c->photo_cache, split, view, fill_photo_features, L, &targets[0], st)) return st->code;
    double t0 = ws_time_start(L->timing);
    for (int a = 0; a < n; a++) {
        if (item_forward(L, &L->items[a], L->alpha_f, 1, L->stroke_aug, st)) return st->code;
        to_rgb(L->stroke_aug, pixels, c->strokes + a * image);
    }
    ws_time_add(L->timing, WS_TIME_AUGMENT, t0);
    if (n > 1 && augmented_photo_features(L, v, view, targets, st)) return st->code;
    clip_run *run = n > 1 ? c->train_run : c->single_run;
    t0 = ws_time_start(L->timing);
    if (clip_forward(run, c->strokes, st)) return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_FORWARD, t0);
    *loss += clip_terms(c, &L->opt, run, n, targets);
    if (!dalpha) return WS_OK;
    t0 = ws_time_start(L->timing);
    if (clip_backward(run, c->nlayers ? c->d_hidden : NULL, c->need_embedding ? c->d_embedding : NULL,
                      c->d_images, st))
        return st->code;
    ws_time_add(L->timing, WS_TIME_CLIP_BACKWARD, t0);
    for (int a = 0; a < n; a++) {
        const float *d = c->d_images + a * image;
        for (size_t i = 0; i < pixels; i++) L->d_stroke[i] = d[i] + d[pixels + i] + d[2 * pixels + i];
        t0 = ws_time_start(L->timing);
        if (item_backward(L, &L->items[a], L->d_stroke, L->stroke_aug, st)) return st->code;
        ws_time_add(L->timing, WS_TIME_AUGMENT, t0);
        for (size_t i = 0; i < pixels; i++) dalpha[i] += L->stroke_aug[i];
    }
    return WS_OK;
}

/* Fills a slot of the edge cache: the edge map of the view's photo. */
static int fill_edge_map(void *ctx, int split, int view, float *slot, ws_status *st) {
    ws_loss *L = ctx;
    ws_edges_target(L->scene->split[split].views[view].photo.data, L->W, L->H, slot);
    return WS_OK;
}

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

int ws_loss_view(ws_loss *L, int split, int view, const double *alpha, int augment,
                 ws_rng *rng, double *value, double *dalpha, ws_status *st) {
    if (split < 0 || split >= WS_NSPLITS || view < 0 || view >= L->scene->split[split].n)
        return ws_fail(st, WS_EINTERNAL, "loss: no view %d in split %d", view, split);
    const ws_view *v = &L->scene->split[split].views[view];
    size_t pixels = (size_t)L->W * L->H;
    int n = augment ? 1 + L->A : 1;
    for (size_t i = 0; i < pixels; i++) L->alpha_f[i] = (float)alpha[i];
    if (augment && draw_transforms(L, split, view, rng, st)) return st->code;
    if (dalpha) memset(dalpha, 0, pixels * sizeof(double));
    double loss = 0;
    if (L->use_clip && clip_view(L, v, split, view, n, &loss, dalpha, st)) return st->code;
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
