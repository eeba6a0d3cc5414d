/* clip.h: CLIP's image tower (ViT, METHOD.md section 4), forward and backward.
 *
 * The weights are frozen: only the gradient with respect to the input image
 * is ever computed. A clip_run holds every activation of one batch size and
 * stops the forward after the last block anything reads. */
#ifndef NN_CLIP_H
#define NN_CLIP_H
#include <stddef.h>
#include <stdint.h>
#include "base/status.h"
#include "tape.h"
#include "weightfile.h"

typedef struct clip_model clip_model;

/* Loads a weight file (weightfile.h); the architecture comes from the file. */
int clip_model_load(clip_model **m, const char *path, ws_status *st);
/* A model of the given architecture with seeded random weights (tests and
 * benchmarks), scaled like a trained model so activations stay O(1). */
int clip_model_random(clip_model **m, const wf_arch *arch, uint64_t seed, ws_status *st);
void clip_model_free(clip_model *m);
const wf_arch *clip_model_arch(const clip_model *m);

/* The arithmetic of the linear layers' products (patch embedding, the
 * blocks' four, projection; attention's own products stay fp32): fp32,
 * the default, or bf16 on CPUs with AVX512_BF16 (nn/gemm_bf16.h: inputs
 * rounded to bf16, sums in fp32; METHOD.md, "bf16 GEMMs"). */
typedef enum { CLIP_FP32, CLIP_BF16 } clip_precision;

/* The precision of the runs created from now on (free the model's runs
 * before changing it). bf16 packs the weights once, 4 bytes a weight (both
 * products' layouts); on a CPU without AVX512_BF16 it fails: WS_EUSAGE,
 * "clip: bf16 needs a CPU with AVX512_BF16, and this one has none (use
 * fp32)". fp32 frees the packing and cannot fail (st may be NULL). */
int clip_model_set_precision(clip_model *m, clip_precision p, ws_status *st);
clip_precision clip_model_precision(const clip_model *m);

typedef struct {
    int batch;          /* images per forward pass */
    int last_block;     /* the forward stops after this block (0-based) */
    int need_embedding; /* run ln_post and the projection (needs all blocks) */
    int need_grad;      /* keep what the backward pass needs */
    int need_attention; /* keep every block's attention probabilities (clip_attention) */
} clip_run_options;

typedef struct clip_run clip_run;

int clip_run_create(clip_run **r, const clip_model *m, const clip_run_options *opt, ws_status *st);
void clip_run_free(clip_run *r);

/* images: batch x 3 x R x R, RGB in [0, 1] (CLIP's per-channel
 * normalisation is applied inside). */
int clip_forward(clip_run *r, const float *images, ws_status *st);
/* h_l, block l's output: batch x tokens x width (tokens = 1 + (R/patch)^2);
 * NULL for a block the run does not compute. Valid until the next forward. */
const float *clip_hidden(const clip_run *r, int layer);
/* P_l, block l's attention probabilities (softmax of q.k / sqrt(D)):
 * batch x heads x tokens (query) x tokens (key); NULL without
 * need_attention or for a block the run does not compute. Valid until the
 * next forward. */
const float *clip_attention(const clip_run *r, int layer);
/* e: batch x output_dim (NULL without need_embedding). */
const float *clip_embedding(const clip_run *r);

/* d_hidden[l]: dL/dh_l (batch x tokens x width) and d_attention[l]: dL/dP_l
 * (batch x heads x tokens x tokens), each NULL for blocks the loss does
 * not read (arrays of last_block + 1 entries, or NULL for none);
 * d_embedding: dL/de or NULL. d_images: batch x 3 x R x R, overwritten.
 * Only the blocks below the deepest seed are replayed. Needs a forward
 * first; may run again after the same forward (e.g. other seeds). */
int clip_backward(clip_run *r, const float *const *d_hidden, const float *const *d_attention,
                  const float *d_embedding, float *d_images, ws_status *st);

/* Bytes of the run's activation arena (values, saved state, gradients). */
size_t clip_run_bytes(const clip_run *r);
/* The run's op tape, for tools that walk it (the benchmarks' GEMM floor,
 * matmul.h's nn_op_gemm) or profile it (nn_tape_profile). */
nn_tape *clip_run_tape(clip_run *r);

#endif
