/* activation.h: quick_gelu(z) = z * sigmoid(1.702 z), CLIP's MLP activation. */
#ifndef NN_ACTIVATION_H
#define NN_ACTIVATION_H
#include <stddef.h>
#include "tape.h"

void nn_quick_gelu_forward(float *out, const float *z, size_t n);
/* dz = dout * (s + 1.702 z s (1 - s)), s = sigmoid(1.702 z); added when acc. */
void nn_quick_gelu_backward(float *dz, const float *dout, const float *z, size_t n, int acc);

nn_tensor *nn_quick_gelu(nn_tape *t, nn_tensor *z);

#endif
