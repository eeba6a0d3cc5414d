/* layernorm.c: LayerNorm forward and input gradient (layernorm.h). */
#include <math.h>
#include "fastmath.h"
#include "layernorm.h"
#include "parallel.h"

/* One row of the forward; a clone per vector width (fastmath.h). */
NN_SIMD_CLONES static void forward_row(float *oi, float *stats, const float *xi, const float *gamma,
                                       const float *beta, int C) {
    float shift = xi[0], sum = 0.0f;
#pragma omp simd reduction(+ : sum)
    for (int j = 0; j < C; j++) sum += xi[j] - shift;
    float mean = sum / (float)C; /* of the shifted row */
    float ss = 0.0f;
#pragma omp simd reduction(+ : ss)
    for (int j = 0; j < C; j++) ss += (xi[j] - shift - mean) * (xi[j] - shift - mean);
    float rstd = 1.0f / sqrtf(ss / (float)C + NN_LAYERNORM_EPS);
#pragma omp simd
    for (int j = 0; j < C; j++) oi[j] = (xi[j] - shift - mean) * rstd * gamma[j] + beta[j];
    stats[0] = mean;
    stats[1] = rstd;
}

void nn_layernorm_forward(float *out, float *stats, const float *x, const float *gamma,
                          const float *beta, int M, int C) {
#pragma omp parallel for schedule(static) if (nn_fork((size_t)M * C))
    for (int i = 0; i < M; i++)
        forward_row(out + (size_t)i * C, stats + 2 * i, x + (size_t)i * C, gamma, beta, C);
}

/* One row of the backward. */
NN_SIMD_CLONES static void backward_row(float *di, const float *gi, const float *xi,
                                        const float *stats, const float *gamma, int C, int acc) {
    float shift = xi[0], mean = stats[0], rstd = stats[1];
    /* dx = rstd * (g - mean(g) - xhat * mean(g * xhat)), g = dout * gamma */
    float sum_g = 0.0f, sum_gx = 0.0f;
#pragma omp simd reduction(+ : sum_g, sum_gx)
    for (int j = 0; j < C; j++) {
        float g = gi[j] * gamma[j];
        sum_g += g;
        sum_gx += g * (xi[j] - shift - mean) * rstd;
    }
    float mg = sum_g / (float)C, mgx = sum_gx / (float)C;
#pragma omp simd
    for (int j = 0; j < C; j++) {
        float g = gi[j] * gamma[j], xhat = (xi[j] - shift - mean) * rstd;
        di[j] = (acc ? di[j] : 0.0f) + rstd * (g - mg - xhat * mgx);
    }
}

void nn_layernorm_backward(float *dx, const float *dout, const float *x, const float *stats,
                           const float *gamma, int M, int C, int acc) {
#pragma omp parallel for schedule(static) if (nn_fork((size_t)M * C))
    for (int i = 0; i < M; i++) {
        size_t o = (size_t)i * C;
        backward_row(dx + o, dout + o, x + o, stats + 2 * i, gamma, C, acc);
    }
}

/* n[0] = M, n[1] = C; w[0] gamma, w[1] beta; saved: stats [M,2]. */
static void forward(const nn_op *op) {
    nn_layernorm_forward(op->out->data, op->saved->data, op->in[0]->data, op->w[0], op->w[1],
                         op->n[0], op->n[1]);
}

static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    nn_layernorm_backward(x->grad, op->out->grad, x->data, op->saved->data, op->w[0], op->n[0],
                          op->n[1], acc);
}

nn_tensor *nn_layernorm(nn_tape *t, nn_tensor *x, const float *gamma, const float *beta) {
    nn_op *op = nn_tape_append(t, NN_OP_LAYERNORM, forward, backward);
    nn_tape_read(t, op, 0, x, 1);
    op->w[0] = gamma;
    op->w[1] = beta;
    op->n[0] = nn_rows(x);
    op->n[1] = nn_dim(x, 0);
    nn_tape_saved(t, op, 2 * (size_t)op->n[0]);
    return nn_tape_output(t, op, x->ndim, x->shape);
}
