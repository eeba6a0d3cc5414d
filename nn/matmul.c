/* matmul.c: the linear layer (matmul.h). GEMMs are called from the main
 * thread only: OpenBLAS runs its own threads, never nested in OpenMP. */
#include <cblas.h>
#include <string.h>
#include "matmul.h"

void nn_gemm_run(const nn_gemm *g, float beta) {
    cblas_sgemm(CblasRowMajor, CblasNoTrans, g->trans_b ? CblasTrans : CblasNoTrans, g->m, g->n,
                g->k, 1.0f, g->a, g->k, g->b, g->trans_b ? g->k : g->n, beta, g->c, g->n);
}

/* The forward product without bias: out = in @ W^T (w_kn: @ W). */
static nn_gemm forward_gemm(float *out, const float *in, const float *w, int M, int K, int N,
                            int w_kn) {
    return (nn_gemm){M, N, K, !w_kn, in, w, out};
}

/* The input gradient: d_in = d_out @ W (w_kn: @ W^T). */
static nn_gemm backward_gemm(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                             int w_kn) {
    return (nn_gemm){M, K, N, w_kn, d_out, w, d_in};
}

/* Rows of out [M,N] = bias + res, either may be NULL (not both). */
static void init_rows(float *out, const float *bias, const float *res, int M, int N) {
    for (int i = 0; i < M; i++) {
        float *o = out + (size_t)i * N;
        const float *r = res ? res + (size_t)i * N : NULL;
        if (!r) {
            memcpy(o, bias, (size_t)N * sizeof *o);
        } else if (!bias) {
            memcpy(o, r, (size_t)N * sizeof *o);
        } else {
#pragma omp simd
            for (int j = 0; j < N; j++) o[j] = r[j] + bias[j];
        }
    }
}

void nn_matmul_forward(float *out, const float *in, const float *w, const float *bias,
                       const float *res, int M, int K, int N, int w_kn) {
    float beta = 0.0f;
    if (bias || res) {
        /* The GEMM adds onto bias + res: no separate pass over out. */
        init_rows(out, bias, res, M, N);
        beta = 1.0f;
    }
    nn_gemm g = forward_gemm(out, in, w, M, K, N, w_kn);
    nn_gemm_run(&g, beta);
}

void nn_matmul_backward(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                        int w_kn, int acc) {
    nn_gemm g = backward_gemm(d_in, d_out, w, M, K, N, w_kn);
    nn_gemm_run(&g, acc ? 1.0f : 0.0f);
}

/* n[0] = M, n[1] = K, n[2] = N, n[3] = w_kn; w[0] weight, w[1] bias;
 * in[1] the residual or NULL. */
static void forward(const nn_op *op) {
    const nn_tensor *res = op->in[1];
    nn_matmul_forward(op->out->data, op->in[0]->data, op->w[0], op->w[1], res ? res->data : NULL,
                      op->n[0], op->n[1], op->n[2], op->n[3]);
}

static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0], *res = op->in[1];
    if (res && res->grad) nn_grad_add(res, op->out->grad);
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    nn_matmul_backward(x->grad, op->out->grad, op->w[0], op->n[0], op->n[1], op->n[2], op->n[3],
                       acc);
}

nn_tensor *nn_matmul_residual(nn_tape *t, nn_tensor *x, const float *w, const float *bias, int N,
                              int w_kn, nn_tensor *res) {
    nn_op *op = nn_tape_append(t, NN_OP_MATMUL, forward, backward);
    nn_tape_read(t, op, 0, x, 0);
    if (res) nn_tape_read(t, op, 1, res, 0);
    op->w[0] = w;
    op->w[1] = bias;
    op->n[0] = nn_rows(x);
    op->n[1] = nn_dim(x, 0);
    op->n[2] = N;
    op->n[3] = w_kn;
    int shape[NN_MAX_DIMS];
    memcpy(shape, x->shape, sizeof shape);
    shape[x->ndim - 1] = N;
    return nn_tape_output(t, op, x->ndim, shape);
}

nn_tensor *nn_matmul(nn_tape *t, nn_tensor *x, const float *w, const float *bias, int N, int w_kn) {
    return nn_matmul_residual(t, x, w, bias, N, w_kn, NULL);
}

int nn_op_gemm(const nn_op *op, int backward, nn_gemm *g) {
    if (op->kind != NN_OP_MATMUL) return 0;
    if (!backward) {
        *g = forward_gemm(op->out->data, op->in[0]->data, op->w[0], op->n[0], op->n[1], op->n[2],
                          op->n[3]);
        return 1;
    }
    if (!op->in[0]->grad) return 0;
    *g = backward_gemm(op->in[0]->grad, op->out->grad, op->w[0], op->n[0], op->n[1], op->n[2],
                       op->n[3]);
    return 1;
}
