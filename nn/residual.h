/* residual.h: the residual connection out = a + b. */
#ifndef NN_RESIDUAL_H
#define NN_RESIDUAL_H
#include <stddef.h>
#include "tape.h"

void nn_residual_forward(float *out, const float *a, const float *b, size_t n);
/* da (+)= dout, db (+)= dout: the gradient passes to both unchanged. */
void nn_residual_backward(float *d_in, const float *dout, size_t n, int acc);

/* a, b of the same shape. */
nn_tensor *nn_residual(nn_tape *t, nn_tensor *a, nn_tensor *b);

#endif
