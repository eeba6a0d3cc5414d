/* similarity.h: the feature comparisons of the loss (METHOD.md section 6), on
 * float vectors with double accumulation. Only the first argument gets a
 * gradient: the second is a photo's feature, a constant. */
#ifndef NN_SIMILARITY_H
#define NN_SIMILARITY_H
#include <stddef.h>

/* mean over i of (a_i - b_i)^2. a, b: n */
double nn_mse_forward(const float *a, const float *b, size_t n);
/* da = scale * d(mean (a - b)^2)/da, overwritten. a, b, da: n */
void nn_mse_backward(const float *a, const float *b, size_t n, float scale, float *da);

/* cos(a, b) = a.b / (max(|a|, eps) max(|b|, eps)), eps = 1e-8 as in
 * torch.nn.functional.cosine_similarity: a zero vector gives 0, not NaN. */
double nn_cosine_forward(const float *a, const float *b, size_t n);
/* da += scale * dcos(a, b)/da. a, b, da: n */
void nn_cosine_backward(const float *a, const float *b, size_t n, float scale, float *da);

#endif
