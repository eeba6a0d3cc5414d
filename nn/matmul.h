/* matmul.h: a linear layer over frozen weights (cblas_sgemm, or the bf16
 * kernel of gemm_bf16.h where the weight was packed for it).
 *
 * Rows are independent samples (M = batch * tokens, so every image of a
 * batch goes through one GEMM). Only the input gradient exists: the
 * weights are frozen, so no weight-gradient GEMM is ever run. */
#ifndef NN_MATMUL_H
#define NN_MATMUL_H
#include "gemm_bf16.h"
#include "tape.h"

/* out [M,N] = in [M,K] @ W^T + bias + res, W [N,K] (PyTorch Linear
 * layout); with w_kn, W is [K,N] and out = in @ W. bias [N] and res [M,N]
 * (a residual connection) may each be NULL. */
void nn_matmul_forward(float *out, const float *in, const float *w, const float *bias,
                       const float *res, int M, int K, int N, int w_kn);
/* d_in [M,K] = d_out [M,N] @ W (w_kn: @ W^T); added to d_in when acc.
 * (res's gradient is d_out itself.) */
void nn_matmul_backward(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                        int w_kn, int acc);

/* x [..., K] -> [..., N]. w_bf16: W packed for the bf16 kernel
 * (gemm_bf16.h), which then runs both products, or NULL for fp32. */
nn_tensor *nn_matmul(nn_tape *t, nn_tensor *x, const float *w, const nn_bf16_linear *w_bf16,
                     const float *bias, int N, int w_kn);
/* res + matmul(x): a residual connection folded into the GEMM, which adds
 * its product onto rows holding res + bias: no pass of its own forward,
 * and backward the GEMM reads the output's gradient directly. res has the
 * output's shape [..., N]. */
nn_tensor *nn_matmul_residual(nn_tape *t, nn_tensor *x, const float *w, const nn_bf16_linear *w_bf16,
                              const float *bias, int N, int w_kn, nn_tensor *res);

/* One matrix product, row-major and dense: c [m,n] = a [m,k] @ b + beta c,
 * b [k,n], or b [n,k] read transposed when trans_b; when bias [n] or res
 * [m,n] is given (either may be NULL), c = bias + res + a @ b instead. Every
 * GEMM of nn/ runs through nn_gemm_run, on fixed blocks of columns shared
 * out over the OpenMP team: the same bits on any thread count (matmul.c). */
typedef struct {
    int m, n, k, trans_b;
    const float *a, *b;
    float *c;
    const float *bias, *res;
} nn_gemm;

void nn_gemm_run(const nn_gemm *g, float beta);
/* Columns [j0, j0 + n) of the same product in one cblas_sgemm call, on
 * OpenBLAS's own threads if it has any (nn_gemm_run's blocks; the whole
 * product as OpenBLAS alone runs it, for the benchmarks). */
void nn_gemm_columns(const nn_gemm *g, float beta, int j0, int n);

/* The GEMM an op of the tape runs, for tools that walk a tape (the GEMM
 * floor of the benchmarks): the forward's product (without its bias), or
 * the backward's input-gradient product, in fp32 also where the op runs
 * it in bf16 (the floor stays fp32's). Returns 0 and leaves g alone when
 * the op runs none: not a matmul, or no gradient flows to its input. Valid
 * once the tape is planned (the buffers exist). */
int nn_op_gemm(const nn_op *op, int backward, nn_gemm *g);

#endif
