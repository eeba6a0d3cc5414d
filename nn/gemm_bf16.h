/* gemm_bf16.h: products with frozen weights in bf16 on CPUs with
 * AVX512_BF16 (METHOD.md, "bf16 GEMMs").
 *
 * c [m,n] = init + a [m,k] @ B [k,n]: B is a frozen weight matrix packed
 * once, rounded to bf16 (round to nearest even), in the layout the kernel
 * reads; a is fp32 and rounded to bf16 on every product; the products of
 * pairs of bf16 values are summed in fp32 by `vdpbf16ps`, over all of k in
 * one fixed order. The threads share out blocks of columns only, so every
 * element is the same sum on any thread count: the same bits. Only CPUs
 * that have the instruction run it (nn_bf16_available); the file compiles
 * for any x86-64 (the kernel is built for its target alone) and elsewhere
 * nn_bf16_available is 0. */
#ifndef NN_GEMM_BF16_H
#define NN_GEMM_BF16_H
#include <stddef.h>
#include <stdint.h>
#include "base/status.h"

/* 1 when this CPU (and its operating system) runs AVX512_BF16 code. */
int nn_bf16_available(void);

/* B [k,n] in bf16, in panels of 64 columns (4 vectors of 16), each panel
 * the pairs of rows (2i, 2i+1) interleaved column by column: one vector
 * of 16 columns x 2 rows per `vdpbf16ps`. k and n are padded with zeros
 * to an even k and whole vectors. */
typedef struct {
    uint16_t *data;
    int k, n;
} nn_bf16_matrix;

/* Packs B [k,n] given as b[i*n + j] or, with trans_b, b[j*k + i]. */
int nn_bf16_matrix_pack(nn_bf16_matrix *p, const float *b, int k, int n, int trans_b, ws_status *st);
void nn_bf16_matrix_free(nn_bf16_matrix *p);

/* A linear layer's weight W packed for both its products: the forward's
 * out = in @ W^T (w_kn: @ W) and the backward's d_in = d_out @ W (w_kn:
 * @ W^T). W is [N,K] (w_kn: [K,N]), as in matmul.h. */
typedef struct nn_bf16_linear {
    nn_bf16_matrix forward, backward;
} nn_bf16_linear;

int nn_bf16_linear_pack(nn_bf16_linear *l, const float *w, int N, int K, int w_kn, ws_status *st);
void nn_bf16_linear_free(nn_bf16_linear *l);

/* Floats of scratch (`work`) a product with m rows of a needs: a in bf16. */
size_t nn_bf16_gemm_work(int m, int k);

/* c [m, b->n] = init + a [m, b->k] @ B, where init is bias [n] + res [m,n]
 * when either is given (the other may be NULL), else beta * c (beta 0 or
 * 1). work: nn_bf16_gemm_work(m, b->k) floats. Only where
 * nn_bf16_available(). */
void nn_bf16_gemm(float *c, const float *a, const nn_bf16_matrix *b, int m, const float *bias,
                  const float *res, float beta, float *work);

/* x rounded to bf16 (to nearest, ties to even; NaN stays NaN) and widened
 * back: the value the kernel multiplies. */
float nn_bf16_round(float x);

#endif
