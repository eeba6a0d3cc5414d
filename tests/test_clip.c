/* slow test */
/* test_clip.c: CLIP's image tower (clip.h) on seeded random weights.
 *
 * A small model (width 64, 2 blocks, 4 heads, patch 16, 64 x 64, output
 * 32): the input gradient of scalar losses of h_l and e against central
 * differences on pixels, seeds on a subset of outputs, truncation, batch
 * independence, determinism, blank images and every error message. Then
 * the full-size ViT-B/32 (width 768, 12 blocks, 12 heads, patch 32, 224 x
 * 224, output 512): forward + backward, finite differences on pixels,
 * identical bits on a second run, truncation, and identical bits for 1 and
 * 2 threads with the Haswell and the SkylakeX kernels. (Agreement with PyTorch on
 * trained-model weight files: test_clip_fixture.c.) */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "base/runtime.h"
#include "check.h"
#include "test_util.h"
#include "nn/clip.h"
#include "nn/gemm_bf16.h"
#include "nn/base/rng.h"

enum { MAX_BLOCKS = 12 };

typedef struct {
    const clip_model *m;
    clip_run *run;
    int batch, blocks, tokens;
    size_t pixels, hidden, embedding; /* floats per batch */
    /* the loss: L = sum_l sum(w_hidden[l] * h_l) + sum(w_embedding * e) */
    float *w_hidden[MAX_BLOCKS], *w_embedding;
} setup;

static ws_rng rng;

static float *randoms(size_t n, double lo, double hi) {
    float *x = malloc(n * sizeof *x);
    for (size_t i = 0; i < n; i++) x[i] = (float)(lo + (hi - lo) * ws_rng_uniform(&rng));
    return x;
}

static int make_run(setup *s, const clip_model *m, int batch, int last_block, int need_embedding,
                    int need_grad) {
    ws_status st;
    ws_status_clear(&st);
    const wf_arch *a = clip_model_arch(m);
    memset(s, 0, sizeof *s);
    s->m = m;
    s->batch = batch;
    s->blocks = need_embedding ? a->layers : last_block + 1;
    s->tokens = 1 + (a->resolution / a->patch) * (a->resolution / a->patch);
    s->pixels = (size_t)batch * 3 * a->resolution * a->resolution;
    s->hidden = (size_t)batch * s->tokens * a->width;
    s->embedding = (size_t)batch * a->output_dim;
    clip_run_options opt = {batch, last_block, need_embedding, need_grad, 0};
    int rc = clip_run_create(&s->run, m, &opt, &st);
    CHECK(rc == WS_OK, "clip_run_create: %s", st.msg);
    return rc;
}

static void free_run(setup *s) {
    clip_run_free(s->run);
    for (int l = 0; l < MAX_BLOCKS; l++) free(s->w_hidden[l]);
    free(s->w_embedding);
}

/* The loss at images (forward only), in double. */
static double loss(setup *s, const float *images) {
    ws_status st;
    ws_status_clear(&st);
    if (clip_forward(s->run, images, &st)) {
        CHECK(0, "clip_forward: %s", st.msg);
        return NAN;
    }
    double L = 0;
    for (int l = 0; l < s->blocks; l++)
        if (s->w_hidden[l])
            for (size_t i = 0; i < s->hidden; i++) L += (double)s->w_hidden[l][i] * clip_hidden(s->run, l)[i];
    if (s->w_embedding)
        for (size_t i = 0; i < s->embedding; i++) L += (double)s->w_embedding[i] * clip_embedding(s->run)[i];
    return L;
}

/* dL/dimages by the backward pass. */
static int gradient(setup *s, const float *images, float *d_images) {
    ws_status st;
    ws_status_clear(&st);
    loss(s, images);
    int rc = clip_backward(s->run, (const float *const *)s->w_hidden, NULL, s->w_embedding, d_images, &st);
    CHECK(rc == WS_OK, "clip_backward: %s", st.msg);
    return rc;
}

/* Index of the largest |g[i]| below bound. */
static size_t largest_below(const float *g, size_t n, double bound) {
    size_t at = 0;
    double best = -1;
    for (size_t i = 0; i < n; i++)
        if (fabs(g[i]) < bound && fabs(g[i]) > best) best = fabs(g[at = i]);
    return at;
}

/* Central differences at the `count` pixels of largest |gradient| (where
 * the float noise of the loss matters least) and `count` spread ones;
 * returns max |fd - grad| / max |grad|. */
static double fd_error(setup *s, float *images, const float *grad, int count, float h) {
    double gmax = fabs(grad[largest_below(grad, s->pixels, INFINITY)]), err = 0, bound = INFINITY;
    for (int k = 0; k < 2 * count; k++) {
        size_t at;
        if (k < count)
            bound = fabs(grad[at = largest_below(grad, s->pixels, bound)]);
        else
            at = (size_t)(k - count) * (s->pixels / count) + s->pixels / (2 * count);
        float keep = images[at], up = keep + h, down = keep - h;
        images[at] = up;
        double lp = loss(s, images);
        images[at] = down;
        double lm = loss(s, images);
        images[at] = keep;
        err = fmax(err, fabs((lp - lm) / ((double)up - down) - grad[at]));
    }
    return err / gmax;
}

static int same_bits(const float *a, const float *b, size_t n) { return !memcmp(a, b, n * sizeof *a); }

static void test_small_gradients(const clip_model *m) {
    setup s;
    if (make_run(&s, m, 2, 1, 1, 1)) return;
    float *images = randoms(s.pixels, 0, 1), *grad = malloc(s.pixels * sizeof *grad);
    s.w_hidden[0] = randoms(s.hidden, -1, 1);
    s.w_hidden[1] = randoms(s.hidden, -1, 1);
    s.w_embedding = randoms(s.embedding, -1, 1);
    if (!gradient(&s, images, grad)) {
        double e = fd_error(&s, images, grad, 6, 1e-2f);
        CHECK(e < 2e-3, "small model, loss of h_0, h_1 and e: gradient off finite differences by %.2e", e);
    }
    /* only h_0 seeded: block 1 and the head are skipped */
    free(s.w_hidden[1]);
    free(s.w_embedding);
    s.w_hidden[1] = NULL;
    s.w_embedding = NULL;
    if (!gradient(&s, images, grad)) {
        double e = fd_error(&s, images, grad, 6, 1e-2f);
        CHECK(e < 2e-3, "small model, loss of h_0 alone: gradient off finite differences by %.2e", e);
    }
    /* nothing seeded: a zero gradient */
    free(s.w_hidden[0]);
    s.w_hidden[0] = NULL;
    ws_status st;
    ws_status_clear(&st);
    int zero = clip_backward(s.run, NULL, NULL, NULL, grad, &st) == WS_OK;
    for (size_t i = 0; i < s.pixels; i++) zero &= grad[i] == 0.0f;
    CHECK(zero, "no seed must give a zero image gradient");
    free_run(&s);
    free(images);
    free(grad);
}

/* A run that stops at block 0 gives block 0's bits and block 0's gradient;
 * a run without tape the same forward bits; the same run twice the same
 * bits; an image's outputs do not depend on its batch mates. */
static void test_small_runs(const clip_model *m) {
    setup full, cut, plain, single;
    if (make_run(&full, m, 2, 1, 1, 1) || make_run(&cut, m, 2, 0, 0, 1) ||
        make_run(&plain, m, 2, 1, 1, 0) || make_run(&single, m, 1, 1, 1, 0))
        return;
    float *images = randoms(full.pixels, 0, 1);
    float *g1 = malloc(full.pixels * sizeof *g1), *g2 = malloc(full.pixels * sizeof *g2);
    full.w_hidden[0] = randoms(full.hidden, -1, 1);
    cut.w_hidden[0] = malloc(cut.hidden * sizeof(float));
    memcpy(cut.w_hidden[0], full.w_hidden[0], cut.hidden * sizeof(float));
    gradient(&full, images, g1);
    gradient(&cut, images, g2);
    CHECK(same_bits(clip_hidden(full.run, 0), clip_hidden(cut.run, 0), full.hidden),
          "truncated run: h_0 differs from the full run's");
    CHECK(clip_hidden(cut.run, 1) == NULL && clip_embedding(cut.run) == NULL,
          "truncated run: blocks past last_block and the embedding must be NULL");
    CHECK(same_bits(g1, g2, full.pixels), "truncated run: the gradient of h_0 differs");

    loss(&plain, images);
    CHECK(same_bits(clip_hidden(full.run, 1), clip_hidden(plain.run, 1), full.hidden) &&
              same_bits(clip_embedding(full.run), clip_embedding(plain.run), full.embedding),
          "a run without tape computes other bits than one with");
    ws_status st;
    ws_status_clear(&st);
    CHECK(clip_backward(plain.run, NULL, NULL, NULL, g2, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "clip: backward on a run made without need_grad"),
          "backward without tape: got '%s'", st.msg);

    gradient(&full, images, g2);
    CHECK(same_bits(g1, g2, full.pixels), "the same run twice gives other gradient bits");

    loss(&single, images + full.pixels / 2); /* image 1 alone */
    double diff = 0;
    const float *e2 = clip_embedding(plain.run) + full.embedding / 2, *e1 = clip_embedding(single.run);
    for (size_t i = 0; i < full.embedding / 2; i++) diff = fmax(diff, fabs(e2[i] - e1[i]));
    CHECK(diff < 1e-5, "image 1's embedding depends on its batch mate (off by %.2e)", diff);
    free_run(&full);
    free_run(&cut);
    free_run(&plain);
    free_run(&single);
    free(images);
    free(g1);
    free(g2);
}

/* A black and a white image: constant patches, finite everything. */
static void test_blank_images(const clip_model *m) {
    setup s;
    if (make_run(&s, m, 2, 1, 1, 1)) return;
    float *images = calloc(s.pixels, sizeof *images), *grad = malloc(s.pixels * sizeof *grad);
    for (size_t i = s.pixels / 2; i < s.pixels; i++) images[i] = 1.0f;
    s.w_hidden[1] = randoms(s.hidden, -1, 1);
    s.w_embedding = randoms(s.embedding, -1, 1);
    int ok = !gradient(&s, images, grad);
    for (size_t i = 0; ok && i < s.pixels; i++) ok = isfinite(grad[i]);
    CHECK(ok, "blank images: the gradient must be finite");
    free_run(&s);
    free(images);
    free(grad);
}

static void test_errors(const clip_model *m) {
    ws_status st;
    ws_status_clear(&st);
    clip_run *r = NULL;
    clip_run_options opt = {1, 2, 0, 1, 0};
    CHECK(clip_run_create(&r, m, &opt, &st) == WS_EUSAGE &&
              !strcmp(st.msg, "clip: last block 2 out of range (the model has 2 blocks)"),
          "last block: got '%s'", st.msg);
    opt = (clip_run_options){0, 1, 0, 1, 0};
    CHECK(clip_run_create(&r, m, &opt, &st) == WS_EUSAGE && !strcmp(st.msg, "clip: batch 0 out of range"),
          "batch: got '%s'", st.msg);
    clip_model *bad = NULL;
    wf_arch a = {66, 2, 4, 16, 64, 32};
    CHECK(clip_model_random(&bad, &a, 1, &st) == WS_EINPUT &&
              !strcmp(st.msg, "random model: width 66 is not a multiple of the 4 heads"),
          "width/heads: got '%s'", st.msg);
    a = (wf_arch){64, 2, 4, 16, 72, 32};
    CHECK(clip_model_random(&bad, &a, 1, &st) == WS_EINPUT &&
              !strcmp(st.msg, "random model: resolution 72 is not a multiple of the patch size 16"),
          "resolution/patch: got '%s'", st.msg);
    CHECK(clip_model_load(&bad, "tests/no_such_weights.bin", &st) != WS_OK &&
              strstr(st.msg, "tests/no_such_weights.bin") && bad == NULL,
          "missing weight file: got '%s'", st.msg);

    setup s;
    if (make_run(&s, m, 1, 0, 0, 1)) return;
    float *images = randoms(s.pixels, 0, 1), *grad = malloc(s.pixels * sizeof *grad);
    CHECK(clip_backward(s.run, NULL, NULL, NULL, grad, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "clip: backward without a successful forward"),
          "backward first: got '%s'", st.msg);
    images[5] = NAN;
    CHECK(clip_forward(s.run, images, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "clip: input image value 5 is not finite"),
          "NaN pixel: got '%s'", st.msg);
    images[5] = 0.5f;
    CHECK(clip_forward(s.run, images, &st) == WS_OK, "%s", st.msg);
    CHECK(clip_backward(s.run, NULL, NULL, images, grad, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "clip: embedding gradient on a run without the embedding"),
          "embedding seed: got '%s'", st.msg);
    free_run(&s);
    free(images);
    free(grad);
}

/* ||x - y|| / ||y||. */
static double relative_error(const float *x, const float *y, size_t n) {
    double d = 0, r = 0;
    for (size_t i = 0; i < n; i++) d += ((double)x[i] - y[i]) * ((double)x[i] - y[i]), r += (double)y[i] * y[i];
    return sqrt(d / r);
}

/* The linear layers in bf16 (nn/gemm_bf16.h): embedding and gradient near
 * fp32's (each GEMM's inputs rounded to 8 bits: a relative error of about
 * 2^-8 / sqrt(K) a product, never above 2^-7), the same bits on 1 and 2
 * threads, and fp32's exact bits again once the model is back in fp32.
 * Without AVX512_BF16 the model refuses bf16 with its message. */
static void test_bf16(clip_model *m) {
    ws_status st;
    ws_status_clear(&st);
    if (!nn_bf16_available()) {
        CHECK(clip_model_set_precision(m, CLIP_BF16, &st) == WS_EUSAGE &&
                  !strcmp(st.msg, "clip: bf16 needs a CPU with AVX512_BF16, and this one has none (use fp32)"),
              "bf16 without AVX512_BF16: got '%s'", st.msg);
        return;
    }
    setup s[3];
    /* OpenBLAS held at one thread, as in the program: its own threads give other fp32 bits */
    CHECK(ws_runtime_init(1, &st) == WS_OK, "%s", st.msg);
    if (make_run(&s[0], m, 2, 1, 1, 1)) return;
    float *images = randoms(s[0].pixels, 0, 1), *g[4];
    for (int k = 0; k < 4; k++) g[k] = malloc(s[0].pixels * sizeof *g[k]);
    float *e32 = malloc(s[0].embedding * sizeof *e32);
    s[0].w_hidden[1] = randoms(s[0].hidden, -1, 1);
    s[0].w_embedding = randoms(s[0].embedding, -1, 1);
    gradient(&s[0], images, g[0]);
    memcpy(e32, clip_embedding(s[0].run), s[0].embedding * sizeof *e32);
    CHECK(clip_model_set_precision(m, CLIP_BF16, &st) == WS_OK && clip_model_precision(m) == CLIP_BF16, "%s",
          st.msg);
    if (make_run(&s[1], m, 2, 1, 1, 1)) return;
    s[1].w_hidden[1] = s[0].w_hidden[1];
    s[1].w_embedding = s[0].w_embedding;
    gradient(&s[1], images, g[1]);
    double ee = relative_error(clip_embedding(s[1].run), e32, s[0].embedding);
    double eg = relative_error(g[1], g[0], s[0].pixels);
    CHECK(ee > 1e-5 && ee < 2e-2, "bf16: embedding off fp32's by %.2e (none at all: not bf16)", ee);
    CHECK(eg > 1e-5 && eg < 2e-2, "bf16: gradient off fp32's by %.2e (none at all: not bf16)", eg);
    CHECK(ws_runtime_init(2, &st) == WS_OK, "%s", st.msg);
    gradient(&s[1], images, g[2]);
    CHECK(same_bits(g[1], g[2], s[0].pixels), "bf16: 1 and 2 threads give other gradient bits");
    CHECK(clip_model_set_precision(m, CLIP_FP32, &st) == WS_OK && clip_model_precision(m) == CLIP_FP32, "%s", st.msg);
    clip_run_free(s[1].run);
    if (make_run(&s[2], m, 2, 1, 1, 1)) return;
    s[2].w_hidden[1] = s[0].w_hidden[1];
    s[2].w_embedding = s[0].w_embedding;
    gradient(&s[2], images, g[3]);
    CHECK(same_bits(g[0], g[3], s[0].pixels), "bf16 and back to fp32: other gradient bits than fp32's");
    clip_run_free(s[2].run);
    free_run(&s[0]);
    free(images);
    free(e32);
    for (int k = 0; k < 4; k++) free(g[k]);
}

/* ViT-B/32 at full size: one image, loss of h_3 and e. */
static void test_full_size(void) {
    ws_status st;
    ws_status_clear(&st);
    wf_arch a = {768, 12, 12, 32, 224, 512};
    clip_model *m;
    CHECK(clip_model_random(&m, &a, 1234, &st) == WS_OK, "%s", st.msg);
    if (st.code) return;
    setup s, cut;
    if (make_run(&s, m, 1, 3, 1, 1) || make_run(&cut, m, 1, 3, 0, 0)) return;
    float *images = randoms(s.pixels, 0, 1);
    float *g1 = malloc(s.pixels * sizeof *g1), *g2 = malloc(s.pixels * sizeof *g2);
    s.w_hidden[3] = randoms(s.hidden, -1, 1);
    s.w_embedding = randoms(s.embedding, -1, 1);
    if (!gradient(&s, images, g1)) {
        double e = fd_error(&s, images, g1, 2, 1e-2f);
        CHECK(e < 5e-3, "ViT-B/32: gradient off finite differences by %.2e", e);
    }
    gradient(&s, images, g2);
    CHECK(same_bits(g1, g2, s.pixels), "ViT-B/32: a second run gives other gradient bits");
    loss(&cut, images);
    CHECK(same_bits(clip_hidden(s.run, 3), clip_hidden(cut.run, 3), s.hidden),
          "ViT-B/32: the run that stops after block 3 gives another h_3");
    double norm = 0;
    for (size_t i = 0; i < s.embedding; i++) norm += (double)clip_embedding(s.run)[i] * clip_embedding(s.run)[i];
    CHECK(norm > 1e-3 && isfinite(norm), "ViT-B/32: embedding norm^2 %g", norm);
    free_run(&s);
    free_run(&cut);
    clip_model_free(m);
    free(images);
    free(g1);
    free(g2);
}

/* Child of test_threads (OPENBLAS_CORETYPE set): the full-size gradient of
 * 2 images through ws_runtime_init with 1 and then 2 threads. Exit 0 when
 * the bits agree. */
static int threads_child(void) {
    ws_status st;
    ws_status_clear(&st);
    wf_arch a = {768, 12, 12, 32, 224, 512};
    clip_model *m;
    setup s;
    if (ws_runtime_init(1, &st) || clip_model_random(&m, &a, 1234, &st)) {
        CHECK(0, "%s", st.msg);
        return 1;
    }
    if (make_run(&s, m, 2, 3, 1, 1)) return 1;
    float *images = randoms(s.pixels, 0, 1);
    float *g[2] = {malloc(s.pixels * sizeof(float)), malloc(s.pixels * sizeof(float))};
    s.w_hidden[3] = randoms(s.hidden, -1, 1);
    s.w_embedding = randoms(s.embedding, -1, 1);
    for (int k = 0; k < 2; k++) {
        CHECK(ws_runtime_init(k + 1, &st) == WS_OK, "%s", st.msg);
        gradient(&s, images, g[k]);
    }
    CHECK(same_bits(g[0], g[1], s.pixels), "kernels %s: 1 and 2 threads give other gradient bits",
          openblas_get_corename());
    free_run(&s);
    clip_model_free(m);
    free(images);
    free(g[0]);
    free(g[1]);
    return check_failed ? 1 : 0;
}

/* The same bits on 1 and 2 threads with each kernel set the CPU runs:
 * OpenBLAS's own threads would give other bits with Haswell's (nn/matmul.c).
 * A child per set, as OpenBLAS reads OPENBLAS_CORETYPE when it loads. */
static void test_threads(const char *self) {
    __builtin_cpu_init();
    const char *kernels[2] = {
        __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? "Haswell" : NULL,
        __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl")
            ? "SkylakeX"
            : NULL};
    for (int k = 0; k < 2; k++) {
        if (!kernels[k]) continue;
        char out[4096];
        int rc = run_cmd(out, sizeof out, "WS_TEST_CLIP_THREADS=1 OPENBLAS_CORETYPE=%s %s", kernels[k], self);
        CHECK(rc == 0, "kernels %s, 1 and 2 threads (exit %d): %s", kernels[k], rc, out);
    }
}

int main(int argc, char **argv) {
    (void)argc;
    if (getenv("WS_TEST_CLIP_THREADS")) return threads_child();
    ws_rng_seed(&rng, 7);
    ws_status st;
    ws_status_clear(&st);
    wf_arch small = {64, 2, 4, 16, 64, 32};
    clip_model *m;
    CHECK(clip_model_random(&m, &small, 99, &st) == WS_OK, "%s", st.msg);
    if (st.code) return check_summary();
    test_small_gradients(m);
    test_small_runs(m);
    test_blank_images(m);
    test_errors(m);
    test_bf16(m);
    clip_model_free(m);
    test_full_size();
    test_threads(argv[0]);
    return check_summary();
}
