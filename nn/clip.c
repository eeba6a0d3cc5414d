/* clip.c: CLIP's image tower on the tape (clip.h, METHOD.md section 4).
 *
 * The model is the weights plus a table naming each tensor the way
 * OpenAI's state dict does (without "visual."); loading and random
 * initialisation walk the same table. A run records the tower's ops once,
 * for one batch size, and replays them. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "activation.h"
#include "attention.h"
#include "clip.h"
#include "embed.h"
#include "gemm_bf16.h"
#include "layernorm.h"
#include "matmul.h"
#include "normalise.h"
#include "parallel.h"
#include "base/rng.h"
#include "tape.h"

/* MAX_TOKENS keeps every size of a run (rows of a batch, T x T attention
 * blocks) far inside int and memory. */
enum { CHANNELS = 3, MAX_TOKENS = 4096 };

/* CLIP's preprocessing statistics (METHOD.md section 4). */
static const float clip_mean[CHANNELS] = {0.48145466f, 0.4578275f, 0.40821073f};
static const float clip_std[CHANNELS] = {0.26862954f, 0.26130258f, 0.27577711f};

typedef struct {
    const float *ln_1_w, *ln_1_b, *in_proj_w, *in_proj_b, *out_proj_w, *out_proj_b;
    const float *ln_2_w, *ln_2_b, *fc_w, *fc_b, *cproj_w, *cproj_b;
} clip_block;

struct clip_model {
    wf_arch arch;
    wf_file *file; /* loaded models: the weights point into it */
    float *owned;  /* random models: one buffer for all weights */
    const float *conv1, *class_embedding, *positional_embedding;
    const float *ln_pre_w, *ln_pre_b, *ln_post_w, *ln_post_b, *proj;
    clip_block *blocks;
    /* bf16: the weights of the linear layers packed for gemm_bf16.h
     * (packed_count entries, packed_index's order); NULL in fp32 */
    nn_bf16_linear *packed;
};

/* ---- the weight table --------------------------------------------------- */

/* How a random model draws a tensor: uniform noise of standard deviation
 * std around `centre` (1 for LayerNorm gains, else 0). The scales follow
 * CLIP's initialisation, so activations and attention logits are O(1). */
typedef struct {
    char name[64];
    int ndim;
    int64_t shape[4];
    const float **dst;
    float centre, std;
} weight_spec;

static void spec(weight_spec *s, const char *name, int ndim, const int64_t *shape,
                 const float **dst, float centre, float std) {
    snprintf(s->name, sizeof s->name, "%s", name);
    s->ndim = ndim;
    memcpy(s->shape, shape, (size_t)ndim * sizeof *shape);
    s->dst = dst;
    s->centre = centre;
    s->std = std;
}

static int64_t spec_numel(const weight_spec *s) {
    int64_t n = 1;
    for (int i = 0; i < s->ndim; i++) n *= s->shape[i];
    return n;
}

/* DIMS(a, b) expands to the arguments `2, (int64_t[]){a, b}` of spec(). */
#define DIMS(...) (sizeof((int64_t[]){__VA_ARGS__}) / sizeof(int64_t)), (int64_t[]){__VA_ARGS__}

static int spec_count(const wf_arch *a) { return 8 + 12 * a->layers; }

/* Fills specs (spec_count entries) for model m, whose arch is set. */
static void weight_table(clip_model *m, weight_spec *specs) {
    const wf_arch *a = &m->arch;
    int64_t W = a->width, G = a->resolution / a->patch, P = (int64_t)CHANNELS * a->patch * a->patch;
    float sw = 1.0f / sqrtf((float)W), sproj = sw / sqrtf(2.0f * a->layers);
    float sfc = 1.0f / sqrtf(2.0f * W), sbias = 0.02f, sln = 0.1f;
    weight_spec *s = specs;
    spec(s++, "conv1.weight", DIMS(W, CHANNELS, a->patch, a->patch), &m->conv1, 0, 1.0f / sqrtf((float)P));
    spec(s++, "class_embedding", DIMS(W), &m->class_embedding, 0, sw);
    spec(s++, "positional_embedding", DIMS(G * G + 1, W), &m->positional_embedding, 0, sw);
    spec(s++, "ln_pre.weight", DIMS(W), &m->ln_pre_w, 1, sln);
    spec(s++, "ln_pre.bias", DIMS(W), &m->ln_pre_b, 0, sln);
    for (int l = 0; l < a->layers; l++) {
        clip_block *b = &m->blocks[l];
        char n[64];
#define BLOCK(suffix, dims, field, centre, std)                                    \
    snprintf(n, sizeof n, "transformer.resblocks.%d." suffix, l);                  \
    spec(s++, n, dims, &b->field, centre, std)
        BLOCK("ln_1.weight", DIMS(W), ln_1_w, 1, sln);
        BLOCK("ln_1.bias", DIMS(W), ln_1_b, 0, sln);
        BLOCK("attn.in_proj_weight", DIMS(3 * W, W), in_proj_w, 0, sw);
        BLOCK("attn.in_proj_bias", DIMS(3 * W), in_proj_b, 0, sbias);
        BLOCK("attn.out_proj.weight", DIMS(W, W), out_proj_w, 0, sproj);
        BLOCK("attn.out_proj.bias", DIMS(W), out_proj_b, 0, sbias);
        BLOCK("ln_2.weight", DIMS(W), ln_2_w, 1, sln);
        BLOCK("ln_2.bias", DIMS(W), ln_2_b, 0, sln);
        BLOCK("mlp.c_fc.weight", DIMS(4 * W, W), fc_w, 0, sfc);
        BLOCK("mlp.c_fc.bias", DIMS(4 * W), fc_b, 0, sbias);
        BLOCK("mlp.c_proj.weight", DIMS(W, 4 * W), cproj_w, 0, sproj);
        BLOCK("mlp.c_proj.bias", DIMS(W), cproj_b, 0, sbias);
#undef BLOCK
    }
    spec(s++, "ln_post.weight", DIMS(W), &m->ln_post_w, 1, sln);
    spec(s++, "ln_post.bias", DIMS(W), &m->ln_post_b, 0, sln);
    spec(s++, "proj", DIMS(W, a->output_dim), &m->proj, 0, sw);
}

/* The sizes every part of the tower relies on. */
static int check_arch(const wf_arch *a, const char *what, ws_status *st) {
    if (a->width < 1 || a->width > 16384 || a->layers < 1 || a->layers > 256 || a->heads < 1 ||
        a->patch < 1 || a->resolution < 1 || a->resolution > 8192 || a->output_dim < 1 ||
        a->output_dim > 65536)
        return ws_fail(st, WS_EINPUT,
                       "%s: implausible architecture (width %d, layers %d, heads %d, patch %d, "
                       "resolution %d, output %d)",
                       what, a->width, a->layers, a->heads, a->patch, a->resolution, a->output_dim);
    if (a->width % a->heads)
        return ws_fail(st, WS_EINPUT, "%s: width %d is not a multiple of the %d heads", what,
                       a->width, a->heads);
    if (a->resolution % a->patch)
        return ws_fail(st, WS_EINPUT, "%s: resolution %d is not a multiple of the patch size %d",
                       what, a->resolution, a->patch);
    int G = a->resolution / a->patch;
    if ((int64_t)G * G + 1 > MAX_TOKENS)
        return ws_fail(st, WS_EINPUT, "%s: %d tokens per image, at most %d supported", what,
                       G * G + 1, MAX_TOKENS);
    return WS_OK;
}

/* A model with arch set, blocks and the table allocated. */
static int model_new(clip_model **out, const wf_arch *arch, const char *what, weight_spec **specs,
                     ws_status *st) {
    *out = NULL;
    *specs = NULL;
    if (check_arch(arch, what, st)) return st->code;
    clip_model *m = ws_calloc(1, sizeof *m, "clip model", st);
    if (!m) return st->code;
    m->arch = *arch;
    m->blocks = ws_calloc((size_t)arch->layers, sizeof *m->blocks, "clip blocks", st);
    *specs = ws_malloc((size_t)spec_count(arch) * sizeof **specs, "clip weight table", st);
    if (!m->blocks || !*specs) {
        free(*specs);
        *specs = NULL;
        clip_model_free(m);
        return st->code;
    }
    weight_table(m, *specs);
    *out = m;
    return WS_OK;
}

int clip_model_load(clip_model **out, const char *path, ws_status *st) {
    *out = NULL;
    wf_file *f;
    if (wf_open(&f, path, st)) return st->code;
    clip_model *m;
    weight_spec *specs;
    if (model_new(&m, wf_architecture(f), path, &specs, st)) {
        wf_close(f);
        return st->code;
    }
    m->file = f;
    for (int i = 0; i < spec_count(&m->arch); i++)
        if (wf_get(f, specs[i].name, specs[i].ndim, specs[i].shape, specs[i].dst, st)) {
            free(specs);
            clip_model_free(m);
            return st->code;
        }
    free(specs);
    *out = m;
    return WS_OK;
}

int clip_model_random(clip_model **out, const wf_arch *arch, uint64_t seed, ws_status *st) {
    clip_model *m;
    weight_spec *specs;
    if (model_new(&m, arch, "random model", &specs, st)) return st->code;
    int n = spec_count(arch);
    size_t total = 0;
    for (int i = 0; i < n; i++) total += (size_t)spec_numel(&specs[i]);
    float *w = m->owned = ws_malloc(total * sizeof *w, "random clip weights", st);
    if (!w) {
        free(specs);
        clip_model_free(m);
        return st->code;
    }
    ws_rng rng;
    ws_rng_seed(&rng, seed);
    for (int i = 0; i < n; i++) {
        /* uniform on [-sqrt(3), sqrt(3)) has unit variance */
        double half = sqrt(3.0) * specs[i].std;
        int64_t k = spec_numel(&specs[i]);
        for (int64_t j = 0; j < k; j++)
            w[j] = specs[i].centre + (float)(half * (2.0 * ws_rng_uniform(&rng) - 1.0));
        *specs[i].dst = w;
        w += k;
    }
    free(specs);
    *out = m;
    return WS_OK;
}

void clip_model_free(clip_model *m) {
    if (!m) return;
    clip_model_set_precision(m, CLIP_FP32, NULL);
    if (m->file) wf_close(m->file);
    free(m->owned);
    free(m->blocks);
    free(m);
}

const wf_arch *clip_model_arch(const clip_model *m) { return &m->arch; }

/* ---- precision: the linear layers' weights in bf16 ----------------------- */

/* The packed weights: the patch embedding, the projection, then four per
 * block (in_proj, out_proj, c_fc, c_proj). */
enum { PACK_CONV1, PACK_PROJ, PACK_BLOCKS, PACK_PER_BLOCK = 4 };
enum { PACK_IN_PROJ, PACK_OUT_PROJ, PACK_FC, PACK_CPROJ };

static int packed_count(const wf_arch *a) { return PACK_BLOCKS + PACK_PER_BLOCK * a->layers; }

/* The weight of packed slot i as matmul.h takes it: W, N, K, w_kn. */
static const float *packed_source(const clip_model *m, int i, int *N, int *K, int *w_kn) {
    const wf_arch *a = &m->arch;
    int W = a->width;
    *w_kn = 0;
    if (i == PACK_CONV1) {
        *N = W, *K = CHANNELS * a->patch * a->patch;
        return m->conv1;
    }
    if (i == PACK_PROJ) {
        *N = a->output_dim, *K = W, *w_kn = 1;
        return m->proj;
    }
    const clip_block *b = &m->blocks[(i - PACK_BLOCKS) / PACK_PER_BLOCK];
    switch ((i - PACK_BLOCKS) % PACK_PER_BLOCK) {
    case PACK_IN_PROJ: *N = 3 * W, *K = W; return b->in_proj_w;
    case PACK_OUT_PROJ: *N = W, *K = W; return b->out_proj_w;
    case PACK_FC: *N = 4 * W, *K = W; return b->fc_w;
    default: *N = W, *K = 4 * W; return b->cproj_w;
    }
}

/* Slot i's packing, or NULL in fp32 (what nn_matmul takes). */
static const nn_bf16_linear *packed(const clip_model *m, int i) { return m->packed ? &m->packed[i] : NULL; }

static const nn_bf16_linear *packed_block(const clip_model *m, int layer, int which) {
    return packed(m, PACK_BLOCKS + PACK_PER_BLOCK * layer + which);
}

int clip_model_set_precision(clip_model *m, clip_precision p, ws_status *st) {
    int n = packed_count(&m->arch);
    if (p == CLIP_FP32) {
        for (int i = 0; m->packed && i < n; i++) nn_bf16_linear_free(&m->packed[i]);
        free(m->packed);
        m->packed = NULL;
        return WS_OK;
    }
    if (m->packed) return WS_OK;
    if (!nn_bf16_available())
        return ws_fail(st, WS_EUSAGE, "clip: bf16 needs a CPU with AVX512_BF16, and this one has none (use fp32)");
    if (!(m->packed = ws_calloc((size_t)n, sizeof *m->packed, "bf16 weights", st))) return st->code;
    for (int i = 0; i < n; i++) {
        int N, K, w_kn;
        const float *w = packed_source(m, i, &N, &K, &w_kn);
        if (nn_bf16_linear_pack(&m->packed[i], w, N, K, w_kn, st)) {
            clip_model_set_precision(m, CLIP_FP32, NULL);
            return st->code;
        }
    }
    return WS_OK;
}

clip_precision clip_model_precision(const clip_model *m) { return m->packed ? CLIP_BF16 : CLIP_FP32; }

/* ---- a run: the recorded tower ------------------------------------------ */

struct clip_run {
    clip_run_options opt;
    const char *model_name;    /* the weight file, named in messages */
    int blocks;                /* blocks recorded: last_block + 1, or all for the embedding */
    nn_tape tape;
    nn_tensor *images;         /* graph input [B,3,R,R] */
    nn_tensor **hidden;        /* [blocks] */
    nn_tensor **probs;         /* [blocks] attention probabilities, with need_attention */
    nn_tensor *embedding;      /* [B,output_dim] or NULL */
    const float **seed_hidden; /* [last_block + 1] slots the seed ops read */
    const float **seed_probs;  /* [last_block + 1] slots the attention ops read */
    const float *seed_embedding;
    int forward_done;
};

/* x = x + attn(ln_1(x)); x = x + c_proj(quick_gelu(c_fc(ln_2(x)))); the
 * residual additions ride on the output projections' GEMMs. *attn: the
 * attention's output (nn_attention_probs finds its probabilities). */
static nn_tensor *record_block(nn_tape *t, const clip_model *m, int l, nn_tensor *x, nn_tensor **attn) {
    const clip_block *b = &m->blocks[l];
    int W = m->arch.width;
    nn_tensor *qkv = nn_matmul(t, nn_layernorm(t, x, b->ln_1_w, b->ln_1_b), b->in_proj_w,
                               packed_block(m, l, PACK_IN_PROJ), b->in_proj_b, 3 * W, 0);
    *attn = nn_attention(t, qkv, m->arch.heads);
    nn_tensor *mid = nn_matmul_residual(t, *attn, b->out_proj_w, packed_block(m, l, PACK_OUT_PROJ),
                                        b->out_proj_b, W, 0, x);
    nn_tensor *z = nn_matmul(t, nn_layernorm(t, mid, b->ln_2_w, b->ln_2_b), b->fc_w,
                             packed_block(m, l, PACK_FC), b->fc_b, 4 * W, 0);
    return nn_matmul_residual(t, nn_quick_gelu(t, z), b->cproj_w, packed_block(m, l, PACK_CPROJ),
                              b->cproj_b, W, 0, mid);
}

int clip_run_create(clip_run **out, const clip_model *m, const clip_run_options *opt, ws_status *st) {
    *out = NULL;
    const wf_arch *a = &m->arch;
    if (opt->batch < 1 || opt->batch > 65536)
        return ws_fail(st, WS_EUSAGE, "clip: batch %d out of range", opt->batch);
    if (opt->last_block < 0 || opt->last_block >= a->layers)
        return ws_fail(st, WS_EUSAGE, "clip: last block %d out of range (the model has %d blocks)",
                       opt->last_block, a->layers);
    clip_run *r = ws_calloc(1, sizeof *r, "clip run", st);
    if (!r) return st->code;
    r->opt = *opt;
    r->model_name = m->file ? wf_path(m->file) : "clip (random weights)";
    r->blocks = opt->need_embedding ? a->layers : opt->last_block + 1;
    r->hidden = ws_calloc((size_t)r->blocks, sizeof *r->hidden, "clip run", st);
    r->probs = ws_calloc((size_t)r->blocks, sizeof *r->probs, "clip run", st);
    r->seed_hidden = ws_calloc((size_t)opt->last_block + 1, sizeof *r->seed_hidden, "clip run", st);
    r->seed_probs = ws_calloc((size_t)opt->last_block + 1, sizeof *r->seed_probs, "clip run", st);
    if (!r->hidden || !r->probs || !r->seed_hidden || !r->seed_probs ||
        nn_tape_init(&r->tape, 16 + 12 * r->blocks, opt->need_grad, st)) {
        clip_run_free(r);
        return st->code;
    }
    nn_tape *t = &r->tape;
    int R = a->resolution, W = a->width;
    int shape[4] = {opt->batch, CHANNELS, R, R};
    r->images = nn_tape_input(t, 4, shape);
    nn_tensor *x = nn_normalise(t, r->images, clip_mean, clip_std);
    x = nn_matmul(t, nn_patchify(t, x, a->patch), m->conv1, packed(m, PACK_CONV1), NULL, W, 0);
    x = nn_tokens(t, x, m->class_embedding, m->positional_embedding);
    x = nn_layernorm(t, x, m->ln_pre_w, m->ln_pre_b);
    for (int l = 0; l < r->blocks; l++) {
        nn_tensor *attn;
        x = r->hidden[l] = record_block(t, m, l, x, &attn);
        nn_tape_keep(t, x);
        int seeded = opt->need_grad && l <= opt->last_block;
        if (seeded) nn_tape_seed(t, x, &r->seed_hidden[l]);
        /* with need_grad the probabilities are kept for the backward anyway */
        if (seeded || opt->need_attention)
            r->probs[l] = nn_attention_probs(t, attn, seeded ? &r->seed_probs[l] : NULL);
    }
    if (opt->need_embedding) {
        x = nn_layernorm(t, nn_class_token(t, x), m->ln_post_w, m->ln_post_b);
        x = r->embedding = nn_matmul(t, x, m->proj, packed(m, PACK_PROJ), NULL, a->output_dim, 1);
        nn_tape_keep(t, x);
        if (opt->need_grad) nn_tape_seed(t, x, &r->seed_embedding);
    }
    if (nn_tape_plan(t, st)) {
        clip_run_free(r);
        return st->code;
    }
    *out = r;
    return WS_OK;
}

void clip_run_free(clip_run *r) {
    if (!r) return;
    nn_tape_free(&r->tape);
    free(r->hidden);
    free(r->probs);
    free(r->seed_hidden);
    free(r->seed_probs);
    free(r);
}

/* Index of the first non-finite value of x[0..n), or -1. The check of
 * every pass's input and output (1.5 M floats a forward+backward of 5
 * images): one pass that vectorises and forks (an exponent of all ones is
 * Inf or NaN), the search for the index only on a hit. */
static long first_nonfinite(const float *x, size_t n) {
    int any = 0;
#pragma omp parallel for simd reduction(| : any) schedule(static) if (nn_fork(n))
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &x[i], sizeof u);
        any |= (u & 0x7f800000u) == 0x7f800000u;
    }
    for (size_t i = 0; any && i < n; i++)
        if (!isfinite(x[i])) return (long)i;
    return -1;
}

int clip_forward(clip_run *r, const float *images, ws_status *st) {
    r->forward_done = 0;
    long bad = first_nonfinite(images, r->images->numel);
    if (bad >= 0)
        return ws_fail(st, WS_ENUMERIC, "clip: input image value %ld is not finite", bad);
    r->images->data = (float *)images; /* the tape never writes its inputs */
    nn_tape_forward(&r->tape);
    const nn_tensor *last = r->embedding ? r->embedding : r->hidden[r->blocks - 1];
    if (first_nonfinite(last->data, last->numel) >= 0)
        return ws_fail(st, WS_ENUMERIC, "%s: the forward pass produced a non-finite value",
                       r->model_name);
    r->forward_done = 1;
    return WS_OK;
}

const float *clip_hidden(const clip_run *r, int layer) {
    return layer >= 0 && layer < r->blocks ? r->hidden[layer]->data : NULL;
}

const float *clip_attention(const clip_run *r, int layer) {
    return r->opt.need_attention && layer >= 0 && layer < r->blocks ? r->probs[layer]->data : NULL;
}

const float *clip_embedding(const clip_run *r) { return r->embedding ? r->embedding->data : NULL; }

int clip_backward(clip_run *r, const float *const *d_hidden, const float *const *d_attention,
                  const float *d_embedding, float *d_images, ws_status *st) {
    if (!r->opt.need_grad)
        return ws_fail(st, WS_EINTERNAL, "clip: backward on a run made without need_grad");
    if (!r->forward_done)
        return ws_fail(st, WS_EINTERNAL, "clip: backward without a successful forward");
    if (d_embedding && !r->embedding)
        return ws_fail(st, WS_EINTERNAL, "clip: embedding gradient on a run without the embedding");
    for (int l = 0; l <= r->opt.last_block; l++) {
        r->seed_hidden[l] = d_hidden ? d_hidden[l] : NULL;
        r->seed_probs[l] = d_attention ? d_attention[l] : NULL;
    }
    r->seed_embedding = d_embedding;
    r->images->grad = d_images;
    nn_tape_backward(&r->tape);
    if (!r->images->grad_ready) memset(d_images, 0, r->images->numel * sizeof *d_images);
    for (int l = 0; l <= r->opt.last_block; l++) r->seed_hidden[l] = r->seed_probs[l] = NULL;
    r->seed_embedding = NULL;
    if (first_nonfinite(d_images, r->images->numel) >= 0)
        return ws_fail(st, WS_ENUMERIC, "clip: the backward pass produced a non-finite gradient");
    return WS_OK;
}

size_t clip_run_bytes(const clip_run *r) { return nn_tape_bytes(&r->tape); }

nn_tape *clip_run_tape(clip_run *r) { return &r->tape; }
