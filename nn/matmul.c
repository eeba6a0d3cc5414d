/* matmul.c: the linear layer (matmul.h). */
#include <cblas.h>
#include <string.h>
#include "matmul.h"
#include "parallel.h"

/* Columns of c per cblas_sgemm call. Every product runs as the same calls
 * on the same blocks of columns whatever the thread count: OpenBLAS's own
 * threaded driver cuts a product at other places than its single-threaded
 * one, and some kernels (Haswell's, AVX2) sum K in another order in some
 * tiles than in others, so its threads change the bits. The threads share
 * out the blocks; each block is one single-threaded OpenBLAS call on all M
 * rows, so each element's sum runs the same way on 1 or N threads. 192
 * columns: a multiple of every kernel's tile (8, 16, 32 columns), 4, 12
 * and 16 blocks for CLIP's products (768, 2304, 3072 columns: even shares
 * on 2 and 4 threads), and few enough that repacking A (M x K) for each
 * call costs 2-5% (docs/RESULTS.md, "Speed and accuracy"). */
enum { NN_GEMM_COLUMNS = 192 };

/* Columns [j0, j0 + n) of rows of c = bias + res (either may be NULL, not
 * both): what the block's GEMM then adds onto, while the block is in cache. */
static void init_block(const nn_gemm *g, int j0, int n) {
    for (int i = 0; i < g->m; i++) {
        float *o = g->c + (size_t)i * g->n + j0;
        const float *r = g->res ? g->res + (size_t)i * g->n + j0 : NULL, *bias = g->bias ? g->bias + j0 : NULL;
        if (!r) {
            memcpy(o, bias, (size_t)n * sizeof *o);
        } else if (!bias) {
            memcpy(o, r, (size_t)n * sizeof *o);
        } else {
#pragma omp simd
            for (int j = 0; j < n; j++) o[j] = r[j] + bias[j];
        }
    }
}

void nn_gemm_columns(const nn_gemm *g, float beta, int j0, int n) {
    if (g->bias || g->res) {
        init_block(g, j0, n);
        beta = 1.0f;
    }
    const float *b = g->trans_b ? g->b + (size_t)j0 * g->k : g->b + j0;
    cblas_sgemm(CblasRowMajor, CblasNoTrans, g->trans_b ? CblasTrans : CblasNoTrans, g->m, n, g->k,
                1.0f, g->a, g->k, b, g->trans_b ? g->k : g->n, beta, g->c + j0, g->n);
}

static void gemm_block(const nn_gemm *g, float beta, int j0) {
    nn_gemm_columns(g, beta, j0, g->n - j0 < NN_GEMM_COLUMNS ? g->n - j0 : NN_GEMM_COLUMNS);
}

void nn_gemm_run(const nn_gemm *g, float beta) {
    int blocks = (g->n + NN_GEMM_COLUMNS - 1) / NN_GEMM_COLUMNS;
    /* OpenBLAS itself threaded (a program that gave it threads): no team
     * around its calls, whose threads would then nest inside ours */
    int fork = blocks > 1 && openblas_get_num_threads() == 1 &&
               nn_fork((size_t)g->m * g->n * g->k);
#pragma omp parallel for schedule(static) if (fork)
    for (int j = 0; j < blocks; j++) gemm_block(g, beta, j * NN_GEMM_COLUMNS);
}

/* The forward product without bias: out = in @ W^T (w_kn: @ W). */
static nn_gemm forward_gemm(float *out, const float *in, const float *w, int M, int K, int N,
                            int w_kn) {
    return (nn_gemm){M, N, K, !w_kn, in, w, out, NULL, NULL};
}

/* The input gradient: d_in = d_out @ W (w_kn: @ W^T). */
static nn_gemm backward_gemm(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                             int w_kn) {
    return (nn_gemm){M, K, N, w_kn, d_out, w, d_in, NULL, NULL};
}

void nn_matmul_forward(float *out, const float *in, const float *w, const float *bias,
                       const float *res, int M, int K, int N, int w_kn) {
    nn_gemm g = forward_gemm(out, in, w, M, K, N, w_kn);
    g.bias = bias;
    g.res = res;
    nn_gemm_run(&g, 0.0f);
}

void nn_matmul_backward(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                        int w_kn, int acc) {
    nn_gemm g = backward_gemm(d_in, d_out, w, M, K, N, w_kn);
    nn_gemm_run(&g, acc ? 1.0f : 0.0f);
}

/* n[0] = M, n[1] = K, n[2] = N, n[3] = w_kn; w[0] weight, w[1] bias;
 * in[1] the residual or NULL; with w_bf16, work[0] and work[1] hold the
 * forward's input and the backward's output gradient rounded to bf16. */
static void forward(const nn_op *op) {
    const nn_tensor *res = op->in[1];
    if (op->w_bf16)
        nn_bf16_gemm(op->out->data, op->in[0]->data, &op->w_bf16->forward, op->n[0], op->w[1],
                     res ? res->data : NULL, 0.0f, op->work[0]->data);
    else
        nn_matmul_forward(op->out->data, op->in[0]->data, op->w[0], op->w[1], res ? res->data : NULL,
                          op->n[0], op->n[1], op->n[2], op->n[3]);
}

static void backward(const nn_op *op) {
    nn_tensor *x = op->in[0], *res = op->in[1];
    if (res && res->grad) nn_grad_add(res, op->out->grad);
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    if (op->w_bf16)
        nn_bf16_gemm(x->grad, op->out->grad, &op->w_bf16->backward, op->n[0], NULL, NULL,
                     acc ? 1.0f : 0.0f, op->work[1]->data);
    else
        nn_matmul_backward(x->grad, op->out->grad, op->w[0], op->n[0], op->n[1], op->n[2],
                           op->n[3], acc);
}

nn_tensor *nn_matmul_residual(nn_tape *t, nn_tensor *x, const float *w, const nn_bf16_linear *w_bf16,
                              const float *bias, int N, int w_kn, nn_tensor *res) {
    nn_op *op = nn_tape_append(t, NN_OP_MATMUL, forward, backward);
    nn_tape_read(t, op, 0, x, 0);
    if (res) nn_tape_read(t, op, 1, res, 0);
    op->w[0] = w;
    op->w[1] = bias;
    op->w_bf16 = w_bf16;
    if (w_bf16) {
        nn_tape_workspace(t, op, nn_bf16_gemm_work(nn_rows(x), nn_dim(x, 0)), 0);
        if (t->with_grad && x->needs_grad) nn_tape_workspace(t, op, nn_bf16_gemm_work(nn_rows(x), N), 1);
    }
    op->n[0] = nn_rows(x);
    op->n[1] = nn_dim(x, 0);
    op->n[2] = N;
    op->n[3] = w_kn;
    int shape[NN_MAX_DIMS];
    memcpy(shape, x->shape, sizeof shape);
    shape[x->ndim - 1] = N;
    return nn_tape_output(t, op, x->ndim, shape);
}

nn_tensor *nn_matmul(nn_tape *t, nn_tensor *x, const float *w, const nn_bf16_linear *w_bf16,
                     const float *bias, int N, int w_kn) {
    return nn_matmul_residual(t, x, w, w_bf16, bias, N, w_kn, NULL);
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
