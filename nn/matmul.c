/* matmul.c: the linear layer (matmul.h). GEMMs are called from the main
 * thread only: OpenBLAS runs its own threads, never nested in OpenMP. */
#include <cblas.h>
#include <string.h>
#include "matmul.h"

void matmul_forward(float *out, const float *in, const float *w, const float *bias, int M, int K,
                    int N, int w_kn) {
    float beta = 0.0f;
    if (bias) {
        /* The GEMM adds onto the bias rows: no separate pass over out. */
        for (int i = 0; i < M; i++) memcpy(out + (size_t)i * N, bias, (size_t)N * sizeof *out);
        beta = 1.0f;
    }
    cblas_sgemm(CblasRowMajor, CblasNoTrans, w_kn ? CblasNoTrans : CblasTrans, M, N, K, 1.0f, in,
                K, w, w_kn ? N : K, beta, out, N);
}

void matmul_backward(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                     int w_kn, int acc) {
    cblas_sgemm(CblasRowMajor, CblasNoTrans, w_kn ? CblasTrans : CblasNoTrans, M, K, N, 1.0f,
                d_out, N, w, w_kn ? N : K, acc ? 1.0f : 0.0f, d_in, K);
}

/* n[0] = M, n[1] = K, n[2] = N, n[3] = w_kn; w[0] weight, w[1] bias. */
static void forward(const nn_op *op) {
    matmul_forward(op->out->data, op->in[0]->data, op->w[0], op->w[1], op->n[0], op->n[1],
                   op->n[2], op->n[3]);
}

static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    matmul_backward(x->grad, op->out->grad, op->w[0], op->n[0], op->n[1], op->n[2], op->n[3], acc);
}

nn_tensor *nn_matmul(nn_tape *t, nn_tensor *x, const float *w, const float *bias, int N, int w_kn) {
    nn_op *op = nn_tape_append(t, "matmul", forward, backward);
    nn_tape_read(t, op, 0, x, 0);
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

int nn_matmul_gemm_only(const nn_op *op, int backward) {
    if (op->forward != forward) return 0;
    if (!backward)
        matmul_forward(op->out->data, op->in[0]->data, op->w[0], NULL, op->n[0], op->n[1],
                       op->n[2], op->n[3]);
    else if (op->in[0]->grad)
        matmul_backward(op->in[0]->grad, op->out->grad, op->w[0], op->n[0], op->n[1], op->n[2],
                        op->n[3], 0);
    return 1;
}
