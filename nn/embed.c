/* embed.c: patchify, tokens and class token (embed.h). */
#include <string.h>
#include "embed.h"

/* The image and the patches are both made of row segments of p floats;
 * segment s = (((b*G + gy)*G + gx)*C + c)*p + ky sits at *patch_off in
 * the patches and at the returned offset in the image. */
static size_t segment(size_t s, int C, int R, int p, size_t *patch_off) {
    int G = R / p;
    *patch_off = s * (size_t)p;
    int ky = (int)(s % (size_t)p);
    s /= (size_t)p;
    int c = (int)(s % (size_t)C);
    s /= (size_t)C;
    int gx = (int)(s % (size_t)G);
    s /= (size_t)G;
    int gy = (int)(s % (size_t)G);
    size_t b = s / (size_t)G;
    return ((b * C + c) * R + (size_t)gy * p + ky) * R + (size_t)gx * p;
}

void nn_patchify_forward(float *patches, const float *img, int B, int C, int R, int p) {
    long n = (long)B * (R / p) * (R / p) * C * p;
    for (long s = 0; s < n; s++) {
        size_t po, io = segment((size_t)s, C, R, p, &po);
        memcpy(patches + po, img + io, (size_t)p * sizeof *patches);
    }
}

void nn_patchify_backward(float *d_img, const float *d_patches, int B, int C, int R, int p,
                          int acc) {
    long n = (long)B * (R / p) * (R / p) * C * p;
    for (long s = 0; s < n; s++) {
        size_t po, io = segment((size_t)s, C, R, p, &po);
        for (int k = 0; k < p; k++) d_img[io + k] = (acc ? d_img[io + k] : 0.0f) + d_patches[po + k];
    }
}

void nn_tokens_forward(float *x, const float *emb, const float *cls, const float *pos, int B, int T,
                       int W) {
    for (int b = 0; b < B; b++)
        for (int t = 0; t < T; t++) {
            float *xt = x + ((size_t)b * T + t) * W;
            const float *src = t == 0 ? cls : emb + ((size_t)b * (T - 1) + t - 1) * W;
            const float *pt = pos + (size_t)t * W;
#pragma omp simd
            for (int j = 0; j < W; j++) xt[j] = src[j] + pt[j];
        }
}

void nn_tokens_backward(float *d_emb, const float *dx, int B, int T, int W, int acc) {
    for (int b = 0; b < B; b++)
        for (int t = 1; t < T; t++) {
            float *d = d_emb + ((size_t)b * (T - 1) + t - 1) * W;
            const float *g = dx + ((size_t)b * T + t) * W;
#pragma omp simd
            for (int j = 0; j < W; j++) d[j] = (acc ? d[j] : 0.0f) + g[j];
        }
}

void nn_class_token_forward(float *out, const float *x, int B, int T, int W) {
    for (int b = 0; b < B; b++) memcpy(out + (size_t)b * W, x + (size_t)b * T * W, (size_t)W * sizeof *out);
}

void nn_class_token_backward(float *dx, const float *dout, int B, int T, int W, int acc) {
    for (int b = 0; b < B; b++) {
        float *d = dx + (size_t)b * T * W;
        const float *g = dout + (size_t)b * W;
        if (acc) {
            for (int j = 0; j < W; j++) d[j] += g[j];
        } else {
            memcpy(d, g, (size_t)W * sizeof *d);
            memset(d + W, 0, (size_t)(T - 1) * W * sizeof *d);
        }
    }
}

/* patchify: n[0] = B, n[1] = C, n[2] = R, n[3] = p. */
static void patchify_fwd(const nn_op *op) {
    nn_patchify_forward(op->out->data, op->in[0]->data, op->n[0], op->n[1], op->n[2], op->n[3]);
}

static void patchify_bwd(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    nn_patchify_backward(x->grad, op->out->grad, op->n[0], op->n[1], op->n[2], op->n[3], acc);
}

nn_tensor *nn_patchify(nn_tape *t, nn_tensor *img, int patch) {
    nn_op *op = nn_tape_append(t, NN_OP_PATCHIFY, patchify_fwd, patchify_bwd);
    nn_tape_read(t, op, 0, img, 0);
    op->n[0] = img->shape[0];
    op->n[1] = img->shape[1];
    op->n[2] = img->shape[2];
    op->n[3] = patch;
    int G = op->n[2] / patch;
    int shape[3] = {op->n[0], G * G, op->n[1] * patch * patch};
    return nn_tape_output(t, op, 3, shape);
}

/* tokens: n[0] = B, n[1] = T, n[2] = W; w[0] cls, w[1] pos. */
static void tokens_fwd(const nn_op *op) {
    nn_tokens_forward(op->out->data, op->in[0]->data, op->w[0], op->w[1], op->n[0], op->n[1],
                      op->n[2]);
}

static void tokens_bwd(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    nn_tokens_backward(x->grad, op->out->grad, op->n[0], op->n[1], op->n[2], acc);
}

nn_tensor *nn_tokens(nn_tape *t, nn_tensor *emb, const float *cls, const float *pos) {
    nn_op *op = nn_tape_append(t, NN_OP_TOKENS, tokens_fwd, tokens_bwd);
    nn_tape_read(t, op, 0, emb, 0);
    op->w[0] = cls;
    op->w[1] = pos;
    op->n[0] = emb->shape[0];
    op->n[1] = emb->shape[1] + 1;
    op->n[2] = emb->shape[2];
    return nn_tape_output(t, op, 3, op->n);
}

/* class_token: n[0] = B, n[1] = T, n[2] = W. */
static void class_token_fwd(const nn_op *op) {
    nn_class_token_forward(op->out->data, op->in[0]->data, op->n[0], op->n[1], op->n[2]);
}

static void class_token_bwd(const nn_op *op) {
    nn_tensor *x = op->in[0];
    if (!x->grad) return;
    int acc = nn_grad_begin(x);
    nn_class_token_backward(x->grad, op->out->grad, op->n[0], op->n[1], op->n[2], acc);
}

nn_tensor *nn_class_token(nn_tape *t, nn_tensor *x) {
    nn_op *op = nn_tape_append(t, NN_OP_CLASS_TOKEN, class_token_fwd, class_token_bwd);
    nn_tape_read(t, op, 0, x, 0);
    op->n[0] = x->shape[0];
    op->n[1] = x->shape[1];
    op->n[2] = x->shape[2];
    int shape[2] = {op->n[0], op->n[2]};
    return nn_tape_output(t, op, 2, shape);
}
