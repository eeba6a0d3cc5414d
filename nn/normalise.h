/* normalise.h: per-channel normalisation of planar images (CLIP's
 * preprocessing: (x - mean_c) / std_c). */
#ifndef NN_NORMALISE_H
#define NN_NORMALISE_H
#include "tape.h"

/* img, out [B,C,HW]; mean, std [C]. */
void nn_normalise_forward(float *out, const float *img, const float *mean, const float *std, int B,
                          int C, int HW);
/* d_img = d_out / std_c; added when acc. */
void nn_normalise_backward(float *d_img, const float *d_out, const float *std, int B, int C, int HW,
                           int acc);

/* img [B,C,H,W] -> same shape. mean and std must outlive the tape. */
nn_tensor *nn_normalise(nn_tape *t, nn_tensor *img, const float *mean, const float *std);

#endif
