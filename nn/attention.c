/* attention.c: multi-head self-attention (attention.h).
 *
 * Each (image, head) pair is an independent task for OpenMP; within one,
 * T x T x D tight loops whose innermost dimension is the head's D
 * contiguous floats, so they vectorise. Every task writes only its own
 * columns of out/dqkv: no reductions across threads, same bits every run. */
#include <math.h>
#include <string.h>
#include "attention.h"
#include "fastmath.h"

static inline float dot(const float *a, const float *b, int n) {
    float s = 0.0f;
#pragma omp simd reduction(+ : s)
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

/* y += a * x */
static inline void axpy(float *y, float a, const float *x, int n) {
#pragma omp simd
    for (int i = 0; i < n; i++) y[i] += a * x[i];
}

/* One row of logits -> probabilities, in place. */
static void softmax_row(float *p, int n) {
    float mx = p[0];
    for (int j = 1; j < n; j++) mx = p[j] > mx ? p[j] : mx;
    float sum = 0.0f;
#pragma omp simd reduction(+ : sum)
    for (int j = 0; j < n; j++) {
        p[j] = nn_exp_nonpos(p[j] - mx);
        sum += p[j];
    }
    float inv = 1.0f / sum; /* sum >= 1: the maximum contributes exp(0) */
#pragma omp simd
    for (int j = 0; j < n; j++) p[j] *= inv;
}

void attention_forward(float *out, float *probs, const float *qkv, int B, int T, int C, int H) {
    int D = C / H;
    size_t row = 3 * (size_t)C;
    float scale = 1.0f / sqrtf((float)D);
#pragma omp parallel for collapse(2) schedule(static)
    for (int b = 0; b < B; b++)
        for (int h = 0; h < H; h++) {
            const float *q = qkv + (size_t)b * T * row + (size_t)h * D, *k = q + C, *v = q + 2 * C;
            float *pbh = probs + ((size_t)b * H + h) * T * T;
            for (int i = 0; i < T; i++) {
                float *p = pbh + (size_t)i * T;
                for (int j = 0; j < T; j++) p[j] = scale * dot(q + i * row, k + j * row, D);
                softmax_row(p, T);
                float *o = out + ((size_t)b * T + i) * C + (size_t)h * D;
                memset(o, 0, (size_t)D * sizeof *o);
                for (int j = 0; j < T; j++) axpy(o, p[j], v + j * row, D);
            }
        }
}

void attention_backward(float *dqkv, const float *dout, const float *qkv, const float *probs,
                        int B, int T, int C, int H, int acc) {
    int D = C / H;
    size_t row = 3 * (size_t)C;
    float scale = 1.0f / sqrtf((float)D);
#pragma omp parallel for collapse(2) schedule(static)
    for (int b = 0; b < B; b++)
        for (int h = 0; h < H; h++) {
            size_t base = (size_t)b * T * row + (size_t)h * D;
            const float *q = qkv + base, *k = q + C, *v = q + 2 * C;
            float *dq = dqkv + base, *dk = dq + C, *dv = dq + 2 * C;
            const float *pbh = probs + ((size_t)b * H + h) * T * T;
            if (!acc)
                for (int i = 0; i < T; i++)
                    for (int part = 0; part < 3; part++)
                        memset(dq + i * row + (size_t)part * C, 0, (size_t)D * sizeof *dq);
            float dp[T];
            for (int i = 0; i < T; i++) {
                const float *p = pbh + (size_t)i * T;
                const float *g = dout + ((size_t)b * T + i) * C + (size_t)h * D;
                /* out_i = sum_j p_ij v_j */
                for (int j = 0; j < T; j++) {
                    dp[j] = dot(g, v + j * row, D);
                    axpy(dv + j * row, p[j], g, D);
                }
                /* softmax: ds_j = p_j (dp_j - sum_k p_k dp_k); s_ij = scale q_i.k_j */
                float pdp = dot(p, dp, T);
                for (int j = 0; j < T; j++) {
                    float ds = scale * p[j] * (dp[j] - pdp);
                    axpy(dq + i * row, ds, k + j * row, D);
                    axpy(dk + j * row, ds, q + i * row, D);
                }
            }
        }
}

/* n[0] = B, n[1] = T, n[2] = C, n[3] = H; saved: probs [B,H,T,T]. */
static void forward(const nn_op *op) {
    attention_forward(op->out->data, op->saved->data, op->in[0]->data, op->n[0], op->n[1],
                      op->n[2], op->n[3]);
}

static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    attention_backward(x->grad, op->out->grad, x->data, op->saved->data, op->n[0], op->n[1],
                       op->n[2], op->n[3], acc);
}

nn_tensor *nn_attention(nn_tape *t, nn_tensor *qkv, int heads) {
    nn_op *op = nn_tape_append(t, "attention", forward, backward);
    nn_tape_read(t, op, 0, qkv, 1);
    int T = nn_dim(qkv, 1), C = nn_dim(qkv, 0) / 3, B = nn_rows(qkv) / T;
    op->n[0] = B;
    op->n[1] = T;
    op->n[2] = C;
    op->n[3] = heads;
    nn_tape_saved(t, op, (size_t)B * heads * T * T);
    int shape[3] = {B, T, C};
    return nn_tape_output(t, op, 3, shape);
}
