/* test_nn_ops.c: every op of the autograd engine (nn/) against a double
 * precision reference written here from the definition: the float forward
 * must match the reference, and the float backward must match central
 * finite differences of the reference's scalar loss L = sum_k w_k out_k
 * (w random). Stiff cases: LayerNorm of a constant row (a blank image),
 * attention logits of 1e4, quick_gelu at +-100. Also the accumulate mode of
 * every backward, the vectorised exp/sigmoid, the loss's similarity
 * functions and the tape (memory planning, seeds, skipped ops). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "nn/activation.h"
#include "nn/attention.h"
#include "check.h"
#include "nn/embed.h"
#include "nn/fastmath.h"
#include "nn/layernorm.h"
#include "nn/matmul.h"
#include "nn/normalise.h"
#include "nn/base/rng.h"
#include "nn/similarity.h"
#include "nn/tape.h"

static ws_rng rng;

static float *randoms(size_t n, double lo, double hi) {
    float *x = malloc(n * sizeof *x);
    for (size_t i = 0; i < n; i++) x[i] = (float)(lo + (hi - lo) * ws_rng_uniform(&rng));
    return x;
}

/* ---- the harness ---------------------------------------------------------- */

/* The double reference of an op: out = f(in), sizes fixed by ctx. */
typedef void (*reference)(double *out, const double *in, const void *ctx);

typedef struct {
    const char *name;
    reference ref;
    const void *ctx;
    size_t n_in, n_out;
} op_case;

static double weighted(const op_case *c, const double *in, const float *w, double *out) {
    c->ref(out, in, c->ctx);
    double s = 0;
    for (size_t k = 0; k < c->n_out; k++) s += w[k] * out[k];
    return s;
}

/* max |a - b| / max(max |b|, floor) */
static double scaled_error(const float *a, const double *b, size_t n, double floor_) {
    double err = 0, scale = floor_;
    for (size_t i = 0; i < n; i++) {
        double e = fabs(a[i] - b[i]);
        err = isfinite(e) ? fmax(err, e) : INFINITY;
        scale = fmax(scale, fabs(b[i]));
    }
    return err / scale;
}

/* Checks the float forward `out` and gradient `dx` (of L = w . out) of an
 * op at input x against the reference; the gradient at up to max_checks
 * inputs spread over x, by central differences of step h. */
static void check_op(const op_case *c, const float *x, const float *out, const float *w,
                     const float *dx, double h, double tol, size_t max_checks) {
    double *xd = malloc(c->n_in * sizeof *xd), *od = malloc(c->n_out * sizeof *od);
    for (size_t i = 0; i < c->n_in; i++) xd[i] = x[i];
    c->ref(od, xd, c->ctx);
    double ferr = scaled_error(out, od, c->n_out, 1e-3);
    CHECK(ferr < tol, "%s: forward differs from the reference by %.2e (scaled)", c->name, ferr);

    size_t step = c->n_in > max_checks ? c->n_in / max_checks : 1, count = 0;
    float *got = malloc(c->n_in * sizeof *got);
    double *fd = malloc(c->n_in * sizeof *fd);
    for (size_t i = 0; i < c->n_in; i += step, count++) {
        double keep = xd[i];
        xd[i] = keep + h;
        double lp = weighted(c, xd, w, od);
        xd[i] = keep - h;
        double lm = weighted(c, xd, w, od);
        xd[i] = keep;
        fd[count] = (lp - lm) / (2 * h);
        got[count] = dx[i];
    }
    double gerr = scaled_error(got, fd, count, 1e-6);
    CHECK(gerr < tol, "%s: gradient differs from finite differences by %.2e (scaled, %zu inputs)",
          c->name, gerr, count);
    free(xd);
    free(od);
    free(got);
    free(fd);
}

/* A backward with acc = 1 must add what acc = 0 writes. Where the gradient
 * is a sum (a GEMM), the kernel may fold `before` into its partial sums in
 * another order, so the rounding is relative to the sum of the absolute
 * terms, `terms` (NULL: the gradient itself), not to the sum's value. */
static void check_accumulates_sum(const char *name, const float *overwritten, const float *added,
                                  const float *before, const double *terms, size_t n) {
    double err = 0;
    for (size_t i = 0; i < n; i++)
        err = fmax(err, fabs((double)added[i] - ((double)before[i] + overwritten[i])) /
                            (1e-6 + fabs(before[i]) + (terms ? terms[i] : fabs(overwritten[i]))));
    CHECK(err < 1e-6, "%s: accumulating backward is not old + gradient (error %.2e)", name, err);
}

static void check_accumulates(const char *name, const float *overwritten, const float *added,
                              const float *before, size_t n) {
    check_accumulates_sum(name, overwritten, added, before, NULL, n);
}

/* ---- matmul --------------------------------------------------------------- */

typedef struct {
    const float *w, *bias;
    int M, K, N, w_kn, with_res;
} matmul_ctx;

/* The input is x [M,K], followed by res [M,N] when with_res. */
static void matmul_ref(double *out, const double *in, const void *vctx) {
    const matmul_ctx *c = vctx;
    const double *res = in + c->M * c->K;
    for (int i = 0; i < c->M; i++)
        for (int j = 0; j < c->N; j++) {
            double s = (c->bias ? c->bias[j] : 0) + (c->with_res ? res[i * c->N + j] : 0);
            for (int k = 0; k < c->K; k++)
                s += in[i * c->K + k] * (c->w_kn ? c->w[k * c->N + j] : c->w[j * c->K + k]);
            out[i * c->N + j] = s;
        }
}

/* out = x W (+ bias) (+ res); the gradient of res is the output's. N
 * above 192 spans several of nn_gemm_run's column blocks, the last one
 * partial (each with its own bias and residual columns). */
static void test_matmul(int w_kn, int with_bias, int with_res, int K, int N) {
    enum { M = 5 };
    matmul_ctx c = {NULL, NULL, M, K, N, w_kn, with_res};
    size_t n_in = M * K + (with_res ? M * N : 0);
    float *x = randoms(n_in, -1, 1), *w = randoms(K * N, -1, 1), *bias = randoms(N, -1, 1);
    float *g = randoms(M * N, -1, 1), *out = malloc(M * N * sizeof *out);
    float *dx = malloc(n_in * sizeof *dx), *dx2 = randoms(M * K, -1, 1), *before = malloc(M * K * sizeof *before);
    memcpy(before, dx2, M * K * sizeof *before);
    c.w = w;
    c.bias = with_bias ? bias : NULL;
    nn_matmul_forward(out, x, w, c.bias, with_res ? x + M * K : NULL, M, K, N, w_kn);
    nn_matmul_backward(dx, g, w, M, K, N, w_kn, 0);
    if (with_res) memcpy(dx + M * K, g, M * N * sizeof *dx);
    nn_matmul_backward(dx2, g, w, M, K, N, w_kn, 1);
    char name[64];
    snprintf(name, sizeof name, "matmul (W %s%s%s, N %d)", w_kn ? "[K,N]" : "[N,K]", with_bias ? ", bias" : "",
             with_res ? ", residual" : "", N);
    op_case oc = {name, matmul_ref, &c, n_in, M * N};
    check_op(&oc, x, out, g, dx, 1e-3, 1e-5, 1000);
    /* dx[i,k] = sum_j g[i,j] W[k,j]: N terms, whose absolute sum bounds the rounding. */
    double *terms = calloc((size_t)M * K, sizeof *terms);
    for (int i = 0; i < M; i++)
        for (int k = 0; k < K; k++)
            for (int j = 0; j < N; j++)
                terms[i * K + k] += fabs((double)g[i * N + j] * (w_kn ? w[k * N + j] : w[j * K + k]));
    check_accumulates_sum(name, dx, dx2, before, terms, M * K);
    free(terms);
    free(x), free(w), free(bias), free(g), free(out), free(dx), free(dx2), free(before);
}

/* ---- layernorm ------------------------------------------------------------ */

typedef struct {
    const float *gamma, *beta;
    int M, C;
} layernorm_ctx;

static void layernorm_ref(double *out, const double *in, const void *vctx) {
    const layernorm_ctx *c = vctx;
    for (int i = 0; i < c->M; i++) {
        const double *x = in + i * c->C;
        double mean = 0, var = 0;
        for (int j = 0; j < c->C; j++) mean += x[j] / c->C;
        for (int j = 0; j < c->C; j++) var += (x[j] - mean) * (x[j] - mean) / c->C;
        for (int j = 0; j < c->C; j++)
            out[i * c->C + j] = (x[j] - mean) / sqrt(var + 1e-5) * c->gamma[j] + c->beta[j];
    }
}

/* blank: row 1 is constant, what a blank image gives (variance 0); its
 * gradient (rstd = eps^-1/2) dwarfs the others, hence a separate case. */
static void test_layernorm(int blank) {
    layernorm_ctx c = {NULL, NULL, 4, 9};
    size_t n = (size_t)c.M * c.C;
    float *x = randoms(n, -2, 3), *gamma = randoms((size_t)c.C, 0.5, 1.5);
    float *beta = randoms((size_t)c.C, -0.5, 0.5), *g = randoms(n, -1, 1);
    if (blank)
        for (int j = 0; j < c.C; j++) x[c.C + j] = 0.3f;
    float *out = malloc(n * sizeof *out), *stats = malloc(2 * (size_t)c.M * sizeof *stats);
    float *dx = malloc(n * sizeof *dx), *dx2 = randoms(n, -1, 1), *before = malloc(n * sizeof *before);
    memcpy(before, dx2, n * sizeof *before);
    c.gamma = gamma;
    c.beta = beta;
    nn_layernorm_forward(out, stats, x, gamma, beta, c.M, c.C);
    nn_layernorm_backward(dx, g, x, stats, gamma, c.M, c.C, 0);
    nn_layernorm_backward(dx2, g, x, stats, gamma, c.M, c.C, 1);
    int finite = 1;
    double off_beta = 0;
    for (size_t i = 0; i < n; i++) finite &= isfinite(out[i]) && isfinite(dx[i]);
    for (int j = 0; j < c.C; j++) off_beta = fmax(off_beta, fabs(out[c.C + j] - beta[j]));
    CHECK(finite, "layernorm: non-finite output or gradient");
    if (blank) CHECK(off_beta == 0, "layernorm: a constant row must give exactly beta (off by %.2e)", off_beta);
    op_case oc = {blank ? "layernorm (constant row)" : "layernorm", layernorm_ref, &c, n, n};
    /* On the constant row the variance grows as h^2 and changes rstd by
     * h^2 / (2 C eps): h = 1e-6 keeps that third-order term at 1e-8. */
    check_op(&oc, x, out, g, dx, 1e-6, 1e-5, 1000);
    check_accumulates("layernorm", dx, dx2, before, n);
    free(x), free(gamma), free(beta), free(g), free(out), free(stats), free(dx), free(dx2), free(before);
}

/* ---- attention ------------------------------------------------------------ */

typedef struct {
    int B, T, C, H;
    int probs; /* the output is followed by the probabilities */
} attention_ctx;

/* out [B,T,C], then (c->probs) P [B,H,T,T]. */
static void attention_ref(double *out, const double *qkv, const void *vctx) {
    const attention_ctx *c = vctx;
    int D = c->C / c->H, row = 3 * c->C;
    double *s = malloc((size_t)c->T * sizeof *s);
    for (int b = 0; b < c->B; b++)
        for (int h = 0; h < c->H; h++)
            for (int i = 0; i < c->T; i++) {
                const double *q = qkv + ((size_t)b * c->T + i) * row + h * D;
                double mx = -INFINITY, sum = 0;
                for (int j = 0; j < c->T; j++) {
                    const double *k = qkv + ((size_t)b * c->T + j) * row + c->C + h * D;
                    s[j] = 0;
                    for (int d = 0; d < D; d++) s[j] += q[d] * k[d] / sqrt(D);
                    mx = fmax(mx, s[j]);
                }
                for (int j = 0; j < c->T; j++) sum += s[j] = exp(s[j] - mx);
                double *p = out + (size_t)c->B * c->T * c->C + (((size_t)b * c->H + h) * c->T + i) * c->T;
                for (int j = 0; c->probs && j < c->T; j++) p[j] = s[j] / sum;
                for (int d = 0; d < D; d++) {
                    double o = 0;
                    for (int j = 0; j < c->T; j++)
                        o += s[j] / sum * qkv[((size_t)b * c->T + j) * row + 2 * c->C + h * D + d];
                    out[((size_t)b * c->T + i) * c->C + h * D + d] = o;
                }
            }
    free(s);
}

/* What reaches the attention's backward: the output's gradient, that and
 * one on the probabilities (dL/dP, the geometric loss's attention
 * variant), or the latter alone (no gradient on the output). */
typedef enum { FROM_OUT, FROM_OUT_AND_PROBS, FROM_PROBS } attention_seeds;

/* scale multiplies q and k: 1 gives O(1) logits; large values give logits
 * of order 1e4 (a saturated softmax), which must stay finite and exact.
 * The probabilities' gradient is checked as part of L = w . (out, P). */
static void test_attention(const char *name, attention_ctx c, attention_seeds seeds, double scale, double h,
                           double tol, size_t checks) {
    c.probs = seeds != FROM_OUT;
    size_t nq = (size_t)c.B * c.T * 3 * c.C, no = (size_t)c.B * c.T * c.C;
    size_t np = c.probs ? (size_t)c.B * c.H * c.T * c.T : 0;
    /* Inputs of their own, whatever the other tests drew: at logits of
     * 1e4 a draw where two logits tie within float rounding (5e-4) gives
     * a softmax gradient that no float computation matches to 1e-5. */
    ws_rng_seed(&rng, 7);
    float *qkv = randoms(nq, -1, 1), *g = randoms(no + np, -1, 1);
    for (size_t r = 0; r < (size_t)c.B * c.T; r++)
        for (int j = 0; j < 2 * c.C; j++) qkv[r * 3 * c.C + j] *= (float)scale;
    if (seeds == FROM_PROBS) memset(g, 0, no * sizeof *g);
    const float *dout = seeds == FROM_PROBS ? NULL : g, *dprobs = c.probs ? g + no : NULL;
    /* out, then the probabilities (for the comparison with the reference) */
    float *out = malloc((no + (size_t)c.B * c.H * c.T * c.T) * sizeof *out), *probs = out + no;
    float *work = malloc(nn_attention_backward_work(c.B, c.T, c.C, c.H) * sizeof *work);
    float *fwork = malloc(nn_attention_forward_work(c.B, c.T, c.C, c.H) * sizeof *fwork);
    float *dx = malloc(nq * sizeof *dx), *dx2 = randoms(nq, -1, 1), *before = malloc(nq * sizeof *before);
    memcpy(before, dx2, nq * sizeof *before);
    nn_attention_forward(out, probs, fwork, qkv, c.B, c.T, c.C, c.H);
    nn_attention_backward(dx, dout, dprobs, qkv, probs, work, c.B, c.T, c.C, c.H, 0);
    nn_attention_backward(dx2, dout, dprobs, qkv, probs, work, c.B, c.T, c.C, c.H, 1);
    int finite = 1;
    for (size_t i = 0; i < nq; i++) finite &= isfinite(dx[i]);
    for (size_t i = 0; i < no + np; i++) finite &= isfinite(out[i]);
    CHECK(finite, "%s: non-finite output or gradient", name);
    op_case oc = {name, attention_ref, &c, nq, no + np};
    check_op(&oc, qkv, out, g, dx, h, tol, checks);
    check_accumulates(name, dx, dx2, before, nq);
    if (seeds == FROM_PROBS) { /* no output gradient: v gets none */
        double dv = 0;
        for (size_t r = 0; r < (size_t)c.B * c.T; r++)
            for (int j = 2 * c.C; j < 3 * c.C; j++) dv = fmax(dv, fabs(dx[r * 3 * c.C + j]));
        CHECK(dv == 0, "%s: dL/dv is %.2e, not 0, without an output gradient", name, dv);
    }
    free(qkv), free(g), free(out), free(work), free(fwork), free(dx), free(dx2), free(before);
}

/* ---- quick_gelu ----------------------------------------------------------- */

static size_t gelu_n;

static void gelu_ref(double *out, const double *z, const void *ctx) {
    for (size_t i = 0; i < gelu_n; i++) out[i] = z[i] / (1 + exp(-1.702 * z[i]));
}

static void test_quick_gelu(void) {
    static const float stiff[] = {100, -100, 30, -30, 0, 1e-3f, -1e-3f};
    size_t ns = sizeof stiff / sizeof *stiff, n = 50 + ns;
    float *z = randoms(n, -6, 6), *g = randoms(n, -1, 1);
    memcpy(z + 50, stiff, sizeof stiff);
    float *out = malloc(n * sizeof *out), *dz = malloc(n * sizeof *dz), *dz2 = randoms(n, -1, 1);
    float *before = malloc(n * sizeof *before);
    memcpy(before, dz2, n * sizeof *before);
    gelu_n = n;
    nn_quick_gelu_forward(out, z, n);
    nn_quick_gelu_backward(dz, g, z, n, 0);
    nn_quick_gelu_backward(dz2, g, z, n, 1);
    CHECK(out[50] == 100.0f && out[51] == 0.0f && dz[50] == g[50] && dz[51] == 0.0f,
          "quick_gelu(+-100) = %g, %g with slopes %g, %g: want 100, 0, 1, 0", out[50], out[51],
          dz[50] / g[50], dz[51] / g[51]);
    op_case oc = {"quick_gelu", gelu_ref, NULL, n, n};
    check_op(&oc, z, out, g, dz, 1e-4, 1e-5, 1000);
    check_accumulates("quick_gelu", dz, dz2, before, n);
    free(z), free(g), free(out), free(dz), free(dz2), free(before);
}

/* ---- normalise, patchify, tokens, class token ------------------------------ */

typedef struct {
    int B, C, R, p;
    const float *mean, *std;
} image_ctx;

static void normalise_ref(double *out, const double *in, const void *vctx) {
    const image_ctx *c = vctx;
    size_t hw = (size_t)c->R * c->R;
    for (int b = 0; b < c->B; b++)
        for (int ch = 0; ch < c->C; ch++)
            for (size_t i = 0; i < hw; i++) {
                size_t o = ((size_t)b * c->C + ch) * hw + i;
                out[o] = (in[o] - c->mean[ch]) / c->std[ch];
            }
}

/* patch (gy, gx) of image b, feature (ch, ky, kx): the layout of a
 * convolution weight [W, C, p, p] flattened, written from the definition. */
static void patchify_ref(double *out, const double *in, const void *vctx) {
    const image_ctx *c = vctx;
    int G = c->R / c->p;
    size_t f = 0;
    for (int b = 0; b < c->B; b++)
        for (int gy = 0; gy < G; gy++)
            for (int gx = 0; gx < G; gx++)
                for (int ch = 0; ch < c->C; ch++)
                    for (int ky = 0; ky < c->p; ky++)
                        for (int kx = 0; kx < c->p; kx++)
                            out[f++] = in[(((size_t)b * c->C + ch) * c->R + gy * c->p + ky) * c->R +
                                          gx * c->p + kx];
}

static void test_image_ops(void) {
    static const float mean[3] = {0.48145466f, 0.4578275f, 0.40821073f};
    static const float std[3] = {0.26862954f, 0.26130258f, 0.27577711f};
    image_ctx c = {2, 3, 8, 4, mean, std};
    size_t n = (size_t)c.B * c.C * c.R * c.R;
    float *x = randoms(n, 0, 1), *g = randoms(n, -1, 1), *out = malloc(n * sizeof *out);
    float *dx = malloc(n * sizeof *dx), *dx2 = randoms(n, -1, 1), *before = malloc(n * sizeof *before);

    memcpy(before, dx2, n * sizeof *before);
    nn_normalise_forward(out, x, mean, std, c.B, c.C, c.R * c.R);
    nn_normalise_backward(dx, g, std, c.B, c.C, c.R * c.R, 0);
    nn_normalise_backward(dx2, g, std, c.B, c.C, c.R * c.R, 1);
    op_case on = {"normalise", normalise_ref, &c, n, n};
    check_op(&on, x, out, g, dx, 1e-3, 1e-5, 1000);
    check_accumulates("normalise", dx, dx2, before, n);

    memcpy(before, dx2, n * sizeof *before);
    nn_patchify_forward(out, x, c.B, c.C, c.R, c.p);
    nn_patchify_backward(dx, g, c.B, c.C, c.R, c.p, 0);
    nn_patchify_backward(dx2, g, c.B, c.C, c.R, c.p, 1);
    op_case op = {"patchify", patchify_ref, &c, n, n};
    check_op(&op, x, out, g, dx, 1e-3, 1e-5, 1000);
    check_accumulates("patchify", dx, dx2, before, n);
    free(x), free(g), free(out), free(dx), free(dx2), free(before);
}

typedef struct {
    int B, T, W;
    const float *cls, *pos;
} token_ctx;

static void tokens_ref(double *out, const double *emb, const void *vctx) {
    const token_ctx *c = vctx;
    for (int b = 0; b < c->B; b++)
        for (int t = 0; t < c->T; t++)
            for (int j = 0; j < c->W; j++)
                out[((size_t)b * c->T + t) * c->W + j] =
                    c->pos[t * c->W + j] +
                    (t == 0 ? c->cls[j] : emb[((size_t)b * (c->T - 1) + t - 1) * c->W + j]);
}

static void class_token_ref(double *out, const double *x, const void *vctx) {
    const token_ctx *c = vctx;
    for (int b = 0; b < c->B; b++)
        for (int j = 0; j < c->W; j++) out[b * c->W + j] = x[(size_t)b * c->T * c->W + j];
}

static void test_token_ops(void) {
    token_ctx c = {2, 5, 6, NULL, NULL};
    size_t ne = (size_t)c.B * (c.T - 1) * c.W, nx = (size_t)c.B * c.T * c.W, nc = (size_t)c.B * c.W;
    float *cls = randoms((size_t)c.W, -1, 1), *pos = randoms((size_t)c.T * c.W, -1, 1);
    float *emb = randoms(ne, -1, 1), *gx = randoms(nx, -1, 1), *gc = randoms(nc, -1, 1);
    float *x = malloc(nx * sizeof *x), *cout = malloc(nc * sizeof *cout);
    float *de = malloc(ne * sizeof *de), *de2 = randoms(ne, -1, 1), *before = malloc(nx * sizeof *before);
    float *dx = malloc(nx * sizeof *dx), *dx2 = randoms(nx, -1, 1);
    c.cls = cls;
    c.pos = pos;

    memcpy(before, de2, ne * sizeof *before);
    nn_tokens_forward(x, emb, cls, pos, c.B, c.T, c.W);
    nn_tokens_backward(de, gx, c.B, c.T, c.W, 0);
    nn_tokens_backward(de2, gx, c.B, c.T, c.W, 1);
    op_case ot = {"tokens", tokens_ref, &c, ne, nx};
    check_op(&ot, emb, x, gx, de, 1e-3, 1e-5, 1000);
    check_accumulates("tokens", de, de2, before, ne);

    memcpy(before, dx2, nx * sizeof *before);
    nn_class_token_forward(cout, x, c.B, c.T, c.W);
    nn_class_token_backward(dx, gc, c.B, c.T, c.W, 0);
    nn_class_token_backward(dx2, gc, c.B, c.T, c.W, 1);
    op_case oc = {"class_token", class_token_ref, &c, nx, nc};
    check_op(&oc, x, cout, gc, dx, 1e-3, 1e-5, 1000);
    check_accumulates("class_token", dx, dx2, before, nx);
    free(cls), free(pos), free(emb), free(gx), free(gc), free(x), free(cout), free(de), free(de2);
    free(before), free(dx), free(dx2);
}

/* ---- the loss's comparisons (similarity.h) --------------------------------- */

typedef struct {
    const float *b;
    size_t n;
    int cosine;
} similarity_ctx;

static void similarity_ref(double *out, const double *a, const void *vctx) {
    const similarity_ctx *c = vctx;
    double ab = 0, aa = 0, bb = 0, sq = 0;
    for (size_t i = 0; i < c->n; i++) {
        ab += a[i] * c->b[i];
        aa += a[i] * a[i];
        bb += (double)c->b[i] * c->b[i];
        sq += (a[i] - c->b[i]) * (a[i] - c->b[i]);
    }
    out[0] = c->cosine ? ab / (fmax(sqrt(aa), 1e-8) * fmax(sqrt(bb), 1e-8)) : sq / c->n;
}

static void test_similarity(void) {
    size_t n = 40;
    float *a = randoms(n, -1, 1), *b = randoms(n, -1, 1), w = 0.7f, out;
    float *da = malloc(n * sizeof *da);
    for (int cosine = 0; cosine < 2; cosine++) {
        similarity_ctx c = {b, n, cosine};
        if (cosine) {
            memset(da, 0, n * sizeof *da);
            out = (float)nn_cosine_forward(a, b, n);
            nn_cosine_backward(a, b, n, w, da);
        } else {
            out = (float)nn_mse_forward(a, b, n);
            nn_mse_backward(a, b, n, w, da);
        }
        op_case oc = {cosine ? "cosine similarity" : "mean squared difference", similarity_ref, &c, n, 1};
        check_op(&oc, a, &out, &w, da, 1e-4, 1e-5, 1000);
    }
    float *zero = calloc(n, sizeof *zero);
    double cz = nn_cosine_forward(zero, b, n);
    memset(da, 0, n * sizeof *da);
    nn_cosine_backward(zero, b, n, 1.0f, da);
    int finite = 1;
    for (size_t i = 0; i < n; i++) finite &= isfinite(da[i]);
    CHECK(cz == 0 && finite, "cosine with a zero vector: %g (want 0) and a finite gradient", cz);
    free(a), free(b), free(da), free(zero);
}

/* ---- fastmath --------------------------------------------------------------- */

static void test_fastmath(void) {
    double worst = 0;
    for (int i = 0; i <= 870000; i++) {
        float x = (float)(-87.0 * i / 870000);
        worst = fmax(worst, fabs(nn_exp_nonpos(x) - exp((double)x)) / exp((double)x));
    }
    CHECK(worst < 4e-7, "nn_exp_nonpos: relative error %.2e on [-87, 0] (want a few ulp)", worst);
    CHECK(nn_exp_nonpos(0.0f) == 1.0f && nn_exp_nonpos(-0.0f) == 1.0f, "exp(0) must be 1");
    CHECK(nn_exp_nonpos(-90.0f) == 0.0f && nn_exp_nonpos(-1e30f) == 0.0f && nn_exp_nonpos(-INFINITY) == 0.0f,
          "exp below -87 must flush to 0");
    float s, sc, worst_s = 0;
    for (int i = -1600; i <= 1600; i++) { /* |x| <= 80: 1 - s stays a normal float */
        float x = 0.05f * (float)i;
        nn_sigmoid2(x, &s, &sc);
        double ref = 1 / (1 + exp(-(double)x)), ref_c = 1 / (1 + exp((double)x));
        worst_s = fmaxf(worst_s, (float)fmax(fabs(s - ref) / ref, fabs(sc - ref_c) / ref_c));
    }
    CHECK(worst_s < 5e-7, "nn_sigmoid2: relative error %.2e of s or 1 - s on [-80, 80]", worst_s);
    nn_sigmoid2(1e4f, &s, &sc);
    CHECK(s == 1.0f && sc == 0.0f, "sigmoid(1e4) = %g, 1 - it = %g", s, sc);
    nn_sigmoid2(-1e4f, &s, &sc);
    CHECK(s == 0.0f && sc == 1.0f, "sigmoid(-1e4) = %g, 1 - it = %g", s, sc);
}

/* ---- the tape ------------------------------------------------------------- */

/* x -> layernorm -> matmul -> quick_gelu -> matmul + x: a residual
 * block on the tape against the same kernels called by hand, with the
 * seed on the output; the planner must let buffers share memory without
 * changing a bit. */
static void test_tape(void) {
    enum { M = 6, C = 8, F = 16 };
    ws_status st;
    ws_status_clear(&st);
    float *gamma = randoms(C, 0.5, 1.5), *beta = randoms(C, -0.5, 0.5);
    float *w1 = randoms(F * C, -0.5, 0.5), *w2 = randoms(C * F, -0.5, 0.5), *b1 = randoms(F, -0.1, 0.1);
    float *x = randoms(M * C, -1, 1), *seed = randoms(M * C, -1, 1), *dx = malloc(M * C * sizeof *dx);
    nn_tape t;
    CHECK(nn_tape_init(&t, 8, 1, &st) == WS_OK, "%s", st.msg);
    int shape[2] = {M, C};
    nn_tensor *in = nn_tape_input(&t, 2, shape);
    nn_tensor *z = nn_matmul(&t, nn_layernorm(&t, in, gamma, beta), w1, NULL, b1, F, 0);
    nn_tensor *y = nn_matmul_residual(&t, nn_quick_gelu(&t, z), w2, NULL, NULL, C, 0, in);
    const float *slot = seed;
    nn_tape_keep(&t, y);
    nn_tape_seed(&t, y, &slot);
    CHECK(nn_tape_plan(&t, &st) == WS_OK, "%s", st.msg);
    in->data = x;
    in->grad = dx;
    nn_tape_forward(&t);
    nn_tape_backward(&t);

    /* by hand */
    float a[M * C], stats[2 * M], zz[M * F], gz[M * F], yy[M * C];
    float dgz[M * F], dz[M * F], da[M * C], ref_dx[M * C];
    nn_layernorm_forward(a, stats, x, gamma, beta, M, C);
    nn_matmul_forward(zz, a, w1, b1, NULL, M, C, F, 0);
    nn_quick_gelu_forward(gz, zz, M * F);
    nn_matmul_forward(yy, gz, w2, NULL, x, M, F, C, 0);
    nn_matmul_backward(dgz, seed, w2, M, F, C, 0, 0);
    nn_quick_gelu_backward(dz, dgz, zz, M * F, 0);
    nn_matmul_backward(da, dz, w1, M, C, F, 0, 0);
    memcpy(ref_dx, seed, sizeof ref_dx);
    nn_layernorm_backward(ref_dx, da, x, stats, gamma, M, C, 1);
    CHECK(!memcmp(y->data, yy, sizeof yy), "tape forward differs from the kernels called by hand");
    CHECK(!memcmp(dx, ref_dx, sizeof ref_dx), "tape backward differs from the kernels called by hand");
    CHECK(in->grad_ready, "the input's gradient must be marked ready");
    size_t unshared = 2 * (M * C + 2 * M + M * C + M * F + M * F + M * C + M * C) * sizeof(float);
    CHECK(nn_tape_bytes(&t) < unshared, "planner shares nothing: %zu bytes for %zu", nn_tape_bytes(&t), unshared);

    /* no seed: every op is skipped and the input gets no gradient */
    slot = NULL;
    nn_tape_backward(&t);
    CHECK(!in->grad_ready, "without a seed no gradient may arrive");
    nn_tape_free(&t);

    /* recording more ops than reserved is a bug, reported at planning */
    CHECK(nn_tape_init(&t, 2, 0, &st) == WS_OK, "%s", st.msg);
    in = nn_tape_input(&t, 2, shape);
    nn_quick_gelu(&t, nn_quick_gelu(&t, nn_quick_gelu(&t, in)));
    CHECK(nn_tape_plan(&t, &st) == WS_EINTERNAL && !strcmp(st.msg, "tape: more than 2 ops recorded"),
          "overflow: got '%s'", st.msg);
    nn_tape_free(&t);
    free(gamma), free(beta), free(w1), free(w2), free(b1), free(x), free(seed), free(dx);
}

/* Tools walk a tape through op kinds, nn_op_gemm and nn_tape_profile:
 * x -> matmul (bias) -> quick_gelu -> matmul, seeded on the output. */
static void test_tape_walk(void) {
    enum { M = 3, C = 4, F = 5 };
    ws_status st;
    ws_status_clear(&st);
    float *w1 = randoms(F * C, -0.5, 0.5), *b1 = randoms(F, -0.1, 0.1), *w2 = randoms(F * C, -0.5, 0.5);
    float *x = randoms(M * C, -1, 1), *seed = randoms(M * C, -1, 1), dx[M * C];
    nn_tape t;
    CHECK(nn_tape_init(&t, 4, 1, &st) == WS_OK, "%s", st.msg);
    int shape[2] = {M, C};
    nn_tensor *in = nn_tape_input(&t, 2, shape);
    nn_tensor *y = nn_matmul(&t, nn_quick_gelu(&t, nn_matmul(&t, in, w1, NULL, b1, F, 0)), w2, NULL, NULL, C, 1);
    const float *slot = seed;
    nn_tape_seed(&t, y, &slot);
    CHECK(nn_tape_plan(&t, &st) == WS_OK, "%s", st.msg);
    static const nn_op_kind kinds[] = {NN_OP_MATMUL, NN_OP_QUICK_GELU, NN_OP_MATMUL, NN_OP_SEED};
    CHECK(t.nops == 4, "%d ops recorded", t.nops);
    for (int i = 0; i < 4 && i < t.nops; i++)
        CHECK(t.ops[i].kind == kinds[i], "op %d is a %s", i, nn_op_kind_name(t.ops[i].kind));
    CHECK(!strcmp(nn_op_kind_name(NN_OP_QUICK_GELU), "quick_gelu"), "kind name");

    double seconds[8];
    nn_tape_profile(&t, seconds);
    in->data = x;
    in->grad = dx;
    nn_tape_forward(&t);
    nn_tape_backward(&t);
    nn_tape_profile(&t, NULL);
    for (int i = 0; i < 8; i++)
        CHECK(seconds[i] >= 0 && seconds[i] < 10, "op time %d: %g s", i, seconds[i]);

    /* the GEMMs as described: the first matmul's without its bias, the
     * second's with w [K,N]; backward: the input gradients */
    nn_gemm g;
    CHECK(!nn_op_gemm(&t.ops[1], 0, &g) && !nn_op_gemm(&t.ops[3], 1, &g), "only matmuls have GEMMs");
    CHECK(nn_op_gemm(&t.ops[0], 0, &g) && g.m == M && g.n == F && g.k == C && g.trans_b == 1 &&
              g.a == x && g.b == w1 && g.c == t.ops[0].out->data,
          "first forward GEMM: %d x %d x %d, trans %d", g.m, g.n, g.k, g.trans_b);
    float z[M * F];
    memcpy(z, g.c, sizeof z);
    nn_gemm_run(&g, 0.0f);
    for (int i = 0; i < M * F; i++)
        CHECK(fabsf(z[i] - b1[i % F] - g.c[i]) < 1e-5f, "GEMM without bias: %g vs %g", g.c[i], z[i] - b1[i % F]);
    CHECK(nn_op_gemm(&t.ops[2], 0, &g) && g.m == M && g.n == C && g.k == F && g.trans_b == 0 && g.b == w2,
          "second forward GEMM");
    CHECK(nn_op_gemm(&t.ops[2], 1, &g) && g.m == M && g.n == F && g.k == C && g.trans_b == 1 &&
              g.a == y->grad && g.c == t.ops[2].in[0]->grad,
          "second backward GEMM");
    CHECK(nn_op_gemm(&t.ops[0], 1, &g) && g.c == dx && g.m == M && g.n == C && g.k == F, "first backward GEMM");
    nn_tape_free(&t);
    free(w1), free(b1), free(w2), free(x), free(seed);
}

int main(void) {
    ws_rng_seed(&rng, 42);
    for (int w_kn = 0; w_kn < 2; w_kn++)
        for (int bias = 0; bias < 2; bias++)
            for (int res = 0; res < 2; res++) {
                test_matmul(w_kn, bias, res, 7, 6);
                test_matmul(w_kn, bias, res, 20, 2 * 192 + 5);
            }
    test_layernorm(0);
    test_layernorm(1);
    test_attention("attention", (attention_ctx){2, 5, 8, 2, 0}, FROM_OUT, 1.0, 1e-4, 1e-5, 1000);
    /* T and D beyond one vector block (64) */
    test_attention("attention (T 67, D 72)", (attention_ctx){1, 67, 144, 2, 0}, FROM_OUT, 1.0, 1e-4, 1e-5, 300);
    /* |q| |k| ~ 100 in D = 4: logits ~1e4, a saturated softmax */
    test_attention("attention (logits 1e4)", (attention_ctx){2, 5, 8, 2, 0}, FROM_OUT, 100.0, 1e-6, 1e-5, 1000);
    /* a gradient on the probabilities, with the output's and alone */
    test_attention("attention (dL/dout and dL/dP)", (attention_ctx){2, 5, 8, 2, 0}, FROM_OUT_AND_PROBS, 1.0, 1e-4,
                   1e-5, 1000);
    test_attention("attention (dL/dP alone)", (attention_ctx){2, 5, 8, 2, 0}, FROM_PROBS, 1.0, 1e-4, 1e-5, 1000);
    test_attention("attention (dL/dP, T 67, D 72)", (attention_ctx){1, 67, 144, 2, 0}, FROM_PROBS, 1.0, 1e-4,
                   1e-5, 300);
    test_quick_gelu();
    test_image_ops();
    test_token_ops();
    test_similarity();
    test_fastmath();
    test_tape();
    test_tape_walk();
    return check_summary();
}
