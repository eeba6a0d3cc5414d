/* layernorm.h: LayerNorm over the last dimension, eps 1e-5 (as PyTorch). */
#ifndef NN_LAYERNORM_H
#define NN_LAYERNORM_H
#include "tape.h"

#define NN_LAYERNORM_EPS 1e-5f

/* out [M,C] = (x - mean) * rstd * gamma + beta, row by row. The sums run
 * on the row minus its first element (shifted data: no cancellation when
 * the mean is large against the spread), and stats [M,2] keeps (mean of
 * the shifted row, rstd) for the backward. A constant row (a blank image)
 * is exactly 0 after the shift: variance 0, rstd = eps^-1/2, out = beta
 * exactly, and nothing divides by zero. */
void nn_layernorm_forward(float *out, float *stats, const float *x, const float *gamma,
                          const float *beta, int M, int C);
/* dx [M,C] from dout [M,C]; added to dx when acc. */
void nn_layernorm_backward(float *dx, const float *dout, const float *x, const float *stats,
                           const float *gamma, int M, int C, int acc);

nn_tensor *nn_layernorm(nn_tape *t, nn_tensor *x, const float *gamma, const float *beta);

#endif
