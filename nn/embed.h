/* embed.h: from pixels to tokens and back to the class token (ViT).
 *
 * patchify: the im2col of a stride-p p x p convolution, so that the patch
 * embedding is one GEMM (matmul.h) over all patches of all images;
 * tokens: class token prepended and positional embedding added;
 * class_token: token 0 of every image (what ln_post and proj read). */
#ifndef NN_EMBED_H
#define NN_EMBED_H
#include "tape.h"

/* img [B,C,R,R] -> patches [B,G*G,C*p*p], G = R/p (R a multiple of p);
 * patch gy*G+gx, feature (c*p+ky)*p+kx: the conv weight [W,C,p,p] order. */
void nn_patchify_forward(float *patches, const float *img, int B, int C, int R, int p);
/* Patches do not overlap: the backward is the inverse permutation. */
void nn_patchify_backward(float *d_img, const float *d_patches, int B, int C, int R, int p,
                          int acc);

/* x [B,T,W]: x[b,0] = cls + pos[0], x[b,1+i] = emb[b,i] + pos[1+i];
 * emb [B,T-1,W], cls [W], pos [T,W]. */
void nn_tokens_forward(float *x, const float *emb, const float *cls, const float *pos, int B, int T,
                       int W);
void nn_tokens_backward(float *d_emb, const float *dx, int B, int T, int W, int acc);

/* out [B,W] = x[b,0,:] of x [B,T,W]; the backward writes zeros to the
 * other tokens when it does not accumulate. */
void nn_class_token_forward(float *out, const float *x, int B, int T, int W);
void nn_class_token_backward(float *dx, const float *dout, int B, int T, int W, int acc);

/* img [B,C,R,R] -> [B,(R/p)^2,C*p*p]. */
nn_tensor *nn_patchify(nn_tape *t, nn_tensor *img, int patch);
/* emb [B,T-1,W] -> [B,T,W]. */
nn_tensor *nn_tokens(nn_tape *t, nn_tensor *emb, const float *cls, const float *pos);
/* x [B,T,W] -> [B,W]. */
nn_tensor *nn_class_token(nn_tape *t, nn_tensor *x);

#endif
