/* attention.h: multi-head self-attention without masking (the ViT's).
 *
 * qkv is the in-projection's output [B,T,3C]: columns [0,C) the queries,
 * [C,2C) the keys, [2C,3C) the values; head h owns columns h*D..h*D+D-1
 * of each (D = C / H). Logits are scaled by D^-1/2; the softmax subtracts
 * the row maximum, so logits of 1e4 stay finite. */
#ifndef NN_ATTENTION_H
#define NN_ATTENTION_H
#include <stddef.h>
#include "tape.h"

/* Floats of scratch the forward / backward need (`work`). */
size_t nn_attention_forward_work(int B, int T, int C, int H);
size_t nn_attention_backward_work(int B, int T, int C, int H);

/* out [B,T,C] (heads side by side), probs [B,H,T,T] kept for backward. */
void nn_attention_forward(float *out, float *probs, float *work, const float *qkv, int B, int T,
                          int C, int H);
/* dqkv [B,T,3C] from dout = dL/dout [B,T,C] and dprobs = the gradient
 * arriving on probs itself [B,H,T,T], either NULL when none arrived (dprobs
 * is added to what comes from the output, before the softmax backward);
 * added to dqkv when acc. */
void nn_attention_backward(float *dqkv, const float *dout, const float *dprobs, const float *qkv,
                           const float *probs, float *work, int B, int T, int C, int H, int acc);

/* qkv [B,T,3C] -> [B,T,C]. */
nn_tensor *nn_attention(nn_tape *t, nn_tensor *qkv, int heads);
/* The probabilities P [B,H,T,T] of the attention op whose output is out,
 * readable after every forward. dprobs (or NULL): a slot that, when it
 * holds a pointer during backward, hands in dL/dP; the op's backward then
 * runs even when no gradient reaches its output. */
nn_tensor *nn_attention_probs(nn_tape *t, nn_tensor *out, const float *const *dprobs);

#endif
