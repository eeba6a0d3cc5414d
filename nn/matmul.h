/* matmul.h: a linear layer over frozen weights (cblas_sgemm).
 *
 * Rows are independent samples (M = batch * tokens, so every image of a
 * batch goes through one GEMM). Only the input gradient exists: the
 * weights are frozen, so no weight-gradient GEMM is ever run. */
#ifndef NN_MATMUL_H
#define NN_MATMUL_H
#include "tape.h"

/* out [M,N] = in [M,K] @ W^T + bias, W [N,K] (PyTorch Linear layout);
 * with w_kn, W is [K,N] and out = in @ W. bias [N] or NULL. */
void matmul_forward(float *out, const float *in, const float *w, const float *bias, int M, int K,
                    int N, int w_kn);
/* d_in [M,K] = d_out [M,N] @ W (w_kn: @ W^T); added to d_in when acc. */
void matmul_backward(float *d_in, const float *d_out, const float *w, int M, int K, int N,
                     int w_kn, int acc);

/* x [..., K] -> [..., N]. */
nn_tensor *nn_matmul(nn_tape *t, nn_tensor *x, const float *w, const float *bias, int N, int w_kn);

/* The GEMM floor of a benchmark: runs op's bare GEMM alone on its own
 * buffers (forward: no bias; backward: the input-gradient GEMM, only when
 * the input has a gradient). Returns 0 when op is not a matmul. */
int nn_matmul_gemm_only(const nn_op *op, int backward);

#endif
